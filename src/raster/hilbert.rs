//! Hilbert-order hierarchical edge-equation traversal (after M. McCool,
//! C. Wales and K. Moule, *Incremental and Hierarchical Hilbert Order Edge
//! Equation Polygon Rasterization*, Graphics Hardware 2001).
//!
//! A `2^n x 2^n` region (a tile) is walked along the Hilbert curve, one
//! square block at a time. For every block the three edge equations are
//! known at the block's first pixel centre; because an edge equation is
//! linear, its largest and smallest values over the block's pixel centres
//! lie at two of the block's corners, found with per-level constants. So:
//!
//! * a block that lies outside one edge at all its pixel centres is skipped
//!   whole;
//! * a block inside all three edges at all its pixel centres is covered
//!   whole, with no per-pixel edge test;
//! * any other block is split into its four quadrants, visited in Hilbert
//!   order; a single pixel is decided exactly.
//!
//! # The state machine
//!
//! The curve inside a block is the base pattern under one of four
//! transformations of the block (the Klein four-group): identity `I`,
//! transpose `S` (swap x and y), anti-transpose `A` (reflect across the
//! other diagonal) and the half turn `R = S∘A`. The base pattern visits the
//! quadrants in the order of the standard `d2xy` Hilbert index, and its
//! four sub-curves are transformed by `S, I, I, A`:
//!
//! ```text
//!  the four states, quadrants numbered in visiting order (x →, y ↓):
//!
//!      I            S            A            R
//!    0   3        0───1        2───3        2───1
//!    │   │            │        │            │   │
//!    1───2        3───2        1───0        3   0
//!
//!  the sub-curves of a block in state I:   ┌───┬───┐
//!  (quadrant 0 is transposed, 3 is        │ S │ A │
//!   anti-transposed, 1 and 2 keep I)      ├───┼───┤
//!                                         │ I │ I │
//!                                         └───┴───┘
//! ```
//!
//! A child's state is its parent's state composed with the base
//! sub-curve's transformation, `NEXT[T][k] = T∘C[k]`; since every element of
//! the group is its own inverse, the same table recovers the parent's state
//! on the way up: `T = NEXT[child][k]`. The two tables, [`QUAD`] (which
//! quadrant is visited `k`-th) and [`NEXT`], pack 2 bits per entry into one
//! `u32` each (8 bytes), and a third `u32`, [`MOVE`], holds the direction of
//! each step between consecutive quadrants (12 bytes in all). The walk keeps
//! one 2-bit digit per level (which child it is in) in a single `u32`, so it
//! needs no recursion and no heap, for regions up to `2^15` pixels a side.
//!
//! Edge values are carried incrementally in `i64`: descending into a
//! quadrant adds the quadrant's offset, moving to the next sibling adds one
//! step, ascending subtracts the last offset. Integer additions are exactly
//! reversible, so ascending needs no saved copies and the values are exact
//! at every block (a test walks whole regions and checks that they return to
//! their start).
//!
//! # Coverage
//!
//! The edge equations are exact integer functions of the 1/16-pixel screen
//! positions, with the top-left rule applied as a bias of one on edges that
//! are neither top nor left, so the covered set is exactly the one of
//! [`super::scanline`] and of the reference in the tests. The paper sets its
//! equations up from homogeneous vertices `(x·w, y·w, w)`; for a triangle
//! that has been clipped and projected, those equations are the screen-space
//! ones scaled by `w1·w2 > 0`, which changes neither sign nor zero, so
//! working on the snapped screen positions loses nothing and keeps the two
//! rasterizers bit-identical. The values need more than 16.16 (up to 2^39
//! for screen positions within the guard band), hence `i64`.

use super::{PixelRect, SubPoint, HALF_PIXEL, SUBPIXEL};

/// `QUAD[T][k]`: the quadrant visited `k`-th in state `T`, as `qx | qy << 1`,
/// 2 bits per entry, entry `T * 4 + k`.
pub const QUAD: u32 = pack([
    [0b00, 0b10, 0b11, 0b01], // I: (0,0) (0,1) (1,1) (1,0)
    [0b00, 0b01, 0b11, 0b10], // S: (0,0) (1,0) (1,1) (0,1)
    [0b11, 0b10, 0b00, 0b01], // A: (1,1) (0,1) (0,0) (1,0)
    [0b11, 0b01, 0b00, 0b10], // R: (1,1) (1,0) (0,0) (0,1)
]);

/// State names, as indices into the tables.
const I: u8 = 0;
const S: u8 = 1;
const A: u8 = 2;
const R: u8 = 3;

/// `NEXT[T][k] = T∘C[k]` with `C = [S, I, I, A]`: the state of the `k`-th
/// child of a block in state `T`, and also (the group being its own
/// inverse) the parent's state given the child's.
pub const NEXT: u32 = pack([
    [S, I, I, A], // I∘C
    [I, S, S, R], // S∘C
    [R, A, A, I], // A∘C
    [A, R, R, S], // R∘C
]);

/// `MOVE[T][k]` for `k < 3`: the step from quadrant `k` to quadrant `k + 1`
/// as `0: +x, 1: +y, 2: -x, 3: -y` (entry `k = 3` unused), derived from
/// [`QUAD`] by a test.
pub const MOVE: u32 = pack([[1, 0, 3, 0], [0, 1, 2, 0], [2, 3, 0, 0], [3, 2, 1, 0]]);

const fn pack(t: [[u8; 4]; 4]) -> u32 {
    let mut out = 0u32;
    let mut s = 0;
    while s < 4 {
        let mut k = 0;
        while k < 4 {
            out |= (t[s][k] as u32 & 3) << (2 * (s * 4 + k));
            k += 1;
        }
        s += 1;
    }
    out
}

#[inline(always)]
const fn entry(table: u32, state: u8, k: u32) -> u8 {
    ((table >> (2 * (state as u32 * 4 + k))) & 3) as u8
}

/// The largest region side the walk supports (its digit stack is one `u32`).
pub const MAX_ORDER: u32 = 15;

/// Three edge equations `E(P) = a·Px + b·Py + c` over sub-pixel positions,
/// each biased so that a pixel centre is covered exactly when all three are
/// `>= 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edges {
    a: [i64; 3],
    b: [i64; 3],
    c: [i64; 3],
}

impl Edges {
    /// The edge equations of a triangle, or `None` when it has zero area.
    /// Works for either winding.
    pub fn new(v: &[SubPoint; 3]) -> Option<Self> {
        let area2 = super::signed_area2(v);
        if area2 == 0 {
            return None;
        }
        let sign = if area2 > 0 { 1 } else { -1 };
        let mut e = Self {
            a: [0; 3],
            b: [0; 3],
            c: [0; 3],
        };
        for k in 0..3 {
            let (p, q) = (v[k], v[(k + 1) % 3]);
            let (dx, dy) = (q.x as i64 - p.x as i64, q.y as i64 - p.y as i64);
            // E = dx (Py - py) - dy (Px - px), positive inside when the
            // triangle's area is positive; flipped otherwise.
            let (a, b) = (-dy * sign, dx * sign);
            let c = -(a * p.x as i64 + b * p.y as i64);
            // Top-left rule: a left edge has the inside towards +x (a > 0),
            // a top edge is horizontal with the inside towards +y (b > 0).
            let top_left = a > 0 || (a == 0 && b > 0);
            e.a[k] = a;
            e.b[k] = b;
            e.c[k] = c - if top_left { 0 } else { 1 };
        }
        Some(e)
    }

    /// The three values at the centre of pixel `(i, j)`.
    #[inline]
    pub fn at(&self, i: i32, j: i32) -> [i64; 3] {
        let x = i as i64 * SUBPIXEL as i64 + HALF_PIXEL as i64;
        let y = j as i64 * SUBPIXEL as i64 + HALF_PIXEL as i64;
        [
            self.a[0] * x + self.b[0] * y + self.c[0],
            self.a[1] * x + self.b[1] * y + self.c[1],
            self.a[2] * x + self.b[2] * y + self.c[2],
        ]
    }
}

/// Per-level constants of the walk: for blocks of side `s`, the change of
/// each edge value over one block step in x and y, and over the block's
/// extent to its largest and smallest corner.
#[derive(Clone, Copy, Debug, Default)]
struct Level {
    step_x: [i64; 3],
    step_y: [i64; 3],
    to_max: [i64; 3],
    to_min: [i64; 3],
}

/// What to do with a block, decided by the traversal's visitor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Visit {
    /// Nothing in it: go on to the next block.
    Skip,
    /// Visit its four quadrants.
    Split,
}

/// The state-machine walk shared by the rasterizer and the tests: visits
/// blocks of the `2^order` region at `(x0, y0)` in Hilbert order, starting
/// with the whole region, handing `visit` each block's position, side, edge
/// values at its first pixel centre and per-level constants; `Split` on a
/// single pixel is treated as `Skip`. Returns the edge values at the end,
/// which equal those at the start.
fn traverse<F>(edges: &Edges, x0: i32, y0: i32, order: u32, mut visit: F) -> [i64; 3]
where
    F: FnMut(i32, i32, i32, &[i64; 3], &Level) -> Visit,
{
    let order = order.min(MAX_ORDER);
    let mut levels = [Level::default(); MAX_ORDER as usize + 1];
    for (l, lv) in levels.iter_mut().enumerate().take(order as usize + 1) {
        // Level l has blocks of side 2^(order - l).
        let side = 1i64 << (order as usize - l);
        for k in 0..3 {
            let (a, b) = (edges.a[k] * SUBPIXEL as i64, edges.b[k] * SUBPIXEL as i64);
            lv.step_x[k] = a * side;
            lv.step_y[k] = b * side;
            let (ea, eb) = (a * (side - 1), b * (side - 1));
            lv.to_max[k] = ea.max(0) + eb.max(0);
            lv.to_min[k] = ea.min(0) + eb.min(0);
        }
    }

    let mut e = edges.at(x0, y0);
    let (mut x, mut y) = (x0, y0);
    let mut level = 0u32;
    let mut state = I;
    // Digit `l` (2 bits at 2*l) is which child of its parent the block at
    // level l is.
    let mut digits = 0u32;
    loop {
        let side = 1i32 << (order - level);
        if side > 1 && visit(x, y, side, &e, &levels[level as usize]) == Visit::Split {
            // Into the first child, in this block's state.
            level += 1;
            let child = &levels[level as usize];
            let q = entry(QUAD, state, 0);
            if q & 1 != 0 {
                x += side / 2;
                add(&mut e, &child.step_x);
            }
            if q & 2 != 0 {
                y += side / 2;
                add(&mut e, &child.step_y);
            }
            digits &= !(3 << (2 * level));
            state = entry(NEXT, state, 0);
            continue;
        }
        if side == 1 {
            visit(x, y, 1, &e, &levels[level as usize]);
        }
        // Next sibling, climbing while this was the last child.
        loop {
            if level == 0 {
                return e;
            }
            let k = (digits >> (2 * level)) & 3;
            let parent = entry(NEXT, state, k);
            let lv = &levels[level as usize];
            let side = 1i32 << (order - level);
            if k < 3 {
                match entry(MOVE, parent, k) {
                    0 => {
                        x += side;
                        add(&mut e, &lv.step_x);
                    }
                    1 => {
                        y += side;
                        add(&mut e, &lv.step_y);
                    }
                    2 => {
                        x -= side;
                        sub(&mut e, &lv.step_x);
                    }
                    _ => {
                        y -= side;
                        sub(&mut e, &lv.step_y);
                    }
                }
                digits += 1 << (2 * level);
                state = entry(NEXT, parent, k + 1);
                break;
            }
            // Back to the parent's origin: undo the last quadrant's offset.
            let q = entry(QUAD, parent, 3);
            if q & 1 != 0 {
                x -= side;
                sub(&mut e, &lv.step_x);
            }
            if q & 2 != 0 {
                y -= side;
                sub(&mut e, &lv.step_y);
            }
            state = parent;
            level -= 1;
        }
    }
}

#[inline(always)]
fn add(e: &mut [i64; 3], d: &[i64; 3]) {
    for k in 0..3 {
        e[k] += d[k];
    }
}

#[inline(always)]
fn sub(e: &mut [i64; 3], d: &[i64; 3]) {
    for k in 0..3 {
        e[k] -= d[k];
    }
}

/// Walks the `2^order`-sided region whose top-left pixel is `(x0, y0)` in
/// Hilbert order and calls `covered(x, y, side)` for every `side x side`
/// block of covered pixel centres of the triangle (a single covered pixel
/// has side 1), restricted to `clip`. Returns the number of blocks
/// classified, a cost measure.
///
/// ```
/// use microraster::raster::hilbert::{walk, Edges};
/// use microraster::raster::{PixelRect, SubPoint};
/// // The 4x4 right triangle of the scanline example: 3 + 2 + 1 pixels.
/// let e = Edges::new(&[SubPoint::new(0, 0), SubPoint::new(64, 0), SubPoint::new(0, 64)]).unwrap();
/// let mut covered = 0;
/// walk(&e, 0, 0, 2, PixelRect::new(0, 0, 4, 4), |_, _, side| covered += side * side);
/// assert_eq!(covered, 6);
/// ```
pub fn walk<F: FnMut(i32, i32, i32)>(
    edges: &Edges,
    x0: i32,
    y0: i32,
    order: u32,
    clip: PixelRect,
    mut covered: F,
) -> u32 {
    let mut blocks = 0;
    traverse(edges, x0, y0, order, |x, y, side, e, lv| {
        blocks += 1;
        let block = PixelRect::new(x, y, x + side, y + side);
        let in_clip = block.intersect(&clip);
        if in_clip.is_empty() || (0..3).any(|k| e[k] + lv.to_max[k] < 0) {
            return Visit::Skip;
        }
        if (0..3).all(|k| e[k] + lv.to_min[k] >= 0) && in_clip == block {
            covered(x, y, side);
            return Visit::Skip;
        }
        // A single pixel inside the clip was decided exactly above.
        Visit::Split
    });
    blocks
}

/// The cell `(x, y)` of the `index`-th step along the Hilbert curve of a
/// `2^order` square, from the state machine's tables (the same order the
/// traversal visits pixels in). Used to visit tiles in Hilbert order.
pub const fn index_to_cell(order: u32, index: u32) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    let mut state = I;
    let mut level = order;
    while level > 0 {
        level -= 1;
        let k = (index >> (2 * level)) & 3;
        let q = entry(QUAD, state, k);
        x |= (q as u32 & 1) << level;
        y |= ((q as u32 >> 1) & 1) << level;
        state = entry(NEXT, state, k);
    }
    (x, y)
}

/// The position along the Hilbert curve of a `2^order` square of the cell
/// `(x, y)`: the inverse of [`index_to_cell`].
pub const fn cell_to_index(order: u32, x: u32, y: u32) -> u32 {
    let mut index = 0u32;
    let mut state = I;
    let mut level = order;
    while level > 0 {
        level -= 1;
        let q = (((x >> level) & 1) | (((y >> level) & 1) << 1)) as u8;
        // The step k whose quadrant is q, in this state.
        let mut k = 0;
        while k < 3 && entry(QUAD, state, k) != q {
            k += 1;
        }
        index = (index << 2) | k;
        state = entry(NEXT, state, k);
    }
    index
}

/// The order (`log2` of the side) of the smallest power-of-two square that
/// holds a `w x h` rectangle.
pub const fn order_for(w: u32, h: u32) -> u32 {
    let side = if w > h { w } else { h };
    let mut order = 0;
    while (1u32 << order) < side && order < MAX_ORDER {
        order += 1;
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The standard Hilbert index to coordinates (`d2xy` of the
    /// literature), written from its definition for comparison.
    fn d2xy(order: u32, d: u32) -> (i32, i32) {
        let (mut x, mut y, mut t) = (0u32, 0u32, d);
        let mut s = 1u32;
        while s < (1 << order) {
            let rx = 1 & (t / 2);
            let ry = 1 & (t ^ rx);
            if ry == 0 {
                if rx == 1 {
                    x = s - 1 - x;
                    y = s - 1 - y;
                }
                core::mem::swap(&mut x, &mut y);
            }
            x += s * rx;
            y += s * ry;
            t /= 4;
            s *= 2;
        }
        (x as i32, y as i32)
    }

    fn some_edges() -> Edges {
        Edges::new(&[
            SubPoint::new(-1000, 37),
            SubPoint::new(50_000, -900),
            SubPoint::new(123, 44_444),
        ])
        .unwrap()
    }

    #[test]
    fn move_table_matches_quadrant_table() {
        for s in 0..4u8 {
            for k in 0..3u32 {
                let (a, b) = (entry(QUAD, s, k), entry(QUAD, s, k + 1));
                let d = (
                    (b & 1) as i32 - (a & 1) as i32,
                    (b >> 1) as i32 - (a >> 1) as i32,
                );
                let m = match d {
                    (1, 0) => 0,
                    (0, 1) => 1,
                    (-1, 0) => 2,
                    (0, -1) => 3,
                    _ => panic!("quadrants {a} and {b} of state {s} are not adjacent"),
                };
                assert_eq!(entry(MOVE, s, k), m, "state {s} step {k}");
            }
        }
    }

    #[test]
    fn tables_fit_in_twelve_bytes() {
        let bytes = core::mem::size_of_val(&QUAD)
            + core::mem::size_of_val(&NEXT)
            + core::mem::size_of_val(&MOVE);
        assert_eq!(bytes, 12);
    }

    /// Splitting every block, the single pixels come in the order of the
    /// standard Hilbert index, every cell of orders 1 to 8 exactly once; the
    /// incremental edge values equal direct evaluation at every block and
    /// return to their start value after the whole walk.
    #[test]
    fn walk_visits_every_cell_in_hilbert_order_with_exact_edges() {
        let edges = some_edges();
        for order in 1..=8u32 {
            let (x0, y0) = (-7, 13);
            let mut d = 0u32;
            let end = traverse(&edges, x0, y0, order, |x, y, side, e, _| {
                assert_eq!(
                    *e,
                    edges.at(x, y),
                    "order {order} block ({x}, {y}) side {side}"
                );
                if side == 1 {
                    let (hx, hy) = d2xy(order, d);
                    assert_eq!((x - x0, y - y0), (hx, hy), "order {order}, index {d}");
                    d += 1;
                }
                Visit::Split
            });
            assert_eq!(d, 1 << (2 * order), "order {order}: every cell once");
            assert_eq!(end, edges.at(x0, y0), "order {order}: back to the start");
        }
    }

    #[test]
    fn cell_index_conversions_match_d2xy_and_invert() {
        for order in 0..=8u32 {
            for d in 0..(1u32 << (2 * order)) {
                let (x, y) = index_to_cell(order, d);
                assert_eq!(
                    (x as i32, y as i32),
                    d2xy(order, d),
                    "order {order} index {d}"
                );
                assert_eq!(cell_to_index(order, x, y), d);
            }
        }
    }

    #[test]
    fn order_for_covers_the_rectangle() {
        assert_eq!(order_for(1, 1), 0);
        assert_eq!(order_for(32, 32), 5);
        assert_eq!(order_for(64, 32), 6);
        assert_eq!(order_for(24, 20), 5);
        assert_eq!(order_for(320, 240), 9);
    }
}
