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
//!   order, down to a leaf (8 x 8 pixels, see below) whose pixels are then
//!   decided exactly, one by one.
//!
//! The walk, [`walk`], reports covered rectangles: whole blocks and the
//! covered run of each row of a leaf.
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
//! [`super::scanline`] and of the reference in the tests.
//!
//! ## Why screen space and `i64`, not normalised 16.16
//!
//! The paper sets its equations up from homogeneous vertices
//! `(x·w, y·w, w)`: the rows of the adjugate of the 3x3 vertex matrix, whose
//! determinant's sign gives the facing. For a triangle that the vertex stage
//! has already clipped (near and far, and to the guard band) and projected,
//! those rows are the screen-space equations below scaled by `w_j·w_k > 0`,
//! which changes neither a sign nor a zero. [`Edges::new`] computes exactly
//! those rows for the matrix `[x_k, y_k, 1]` of the snapped screen
//! positions (`a = y_j - y_k`, `b = x_k - x_j`, `c = x_j·y_k - x_k·y_j`,
//! oriented by the determinant `2·area`). Normalising each edge to 16.16 by
//! its largest exponent, as the paper does for hardware, would round the
//! coefficients, and a centre within that rounding of an edge could then
//! fall on the other side of it than in the scanline rasterizer: the images
//! would differ. Kept exact, the values need up to 2^39 for screen
//! positions within the guard band, hence `i64`, and every decision is the
//! exact one. The attribute equations are not part of this module: both
//! rasterizers hand their spans to the same shading code ([`crate::shade`]).
//!
//! # In the renderer
//!
//! The renderer shades spans, one per covered row of a triangle in a tile.
//! Its Hilbert span finder (also behind [`spans`]) walks the smallest
//! power-of-two square at the top-left of the triangle's bounds in the
//! tile, and each covered block widens the span of each of its rows; since
//! a triangle's covered centres in a row are contiguous, the union is
//! exactly the scanline rasterizer's span.
//! The hierarchy stops at leaves of `8 x 8` pixels ([`LEAF_SHIFT`]): a leaf
//! that straddles an edge is finished by testing its pixels row by row,
//! which measured cheaper than three more levels of classification.
//!
//! The same tables order the tiles of a frame: [`rank_in_grid`] and
//! [`cell_at_rank`] give the Hilbert visiting order of a grid of any size
//! (see [`crate::tile::TileOrder`]).

mod curve;

pub use curve::{cell_at_rank, cell_to_index, index_to_cell, order_for, rank_in_grid};

use super::{PixelRect, Span, SubPoint, HALF_PIXEL, SUBPIXEL};

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

/// The per-pixel constants of the walk, from which those of every level
/// follow by a shift: over a block of side `2^l`, edge `k` changes by
/// `a[k] << l` per block step in x and `b[k] << l` in y, and its largest
/// and smallest value lie `(up[k] << l) - up[k]` and
/// `(down[k] << l) - down[k]` from its value at the block's first pixel
/// centre (the corner where each of `a` and `b` is largest, or smallest,
/// `2^l - 1` pixels away).
#[derive(Clone, Copy, Debug)]
struct Steps {
    a: [i64; 3],
    b: [i64; 3],
    up: [i64; 3],
    down: [i64; 3],
}

impl Steps {
    fn new(edges: &Edges) -> Self {
        let (mut a, mut b, mut up, mut down) = ([0; 3], [0; 3], [0; 3], [0; 3]);
        for k in 0..3 {
            a[k] = edges.a[k] * SUBPIXEL as i64;
            b[k] = edges.b[k] * SUBPIXEL as i64;
            up[k] = a[k].max(0) + b[k].max(0);
            down[k] = a[k].min(0) + b[k].min(0);
        }
        Self { a, b, up, down }
    }

    #[inline(always)]
    fn step_x(&self, shift: u32) -> [i64; 3] {
        self.a.map(|a| a << shift)
    }

    #[inline(always)]
    fn step_y(&self, shift: u32) -> [i64; 3] {
        self.b.map(|b| b << shift)
    }
}

/// How a block of side `2^shift` stands against the edges: with `e` the
/// edge values at its first pixel centre, whether it lies wholly outside
/// one edge, and whether it lies wholly inside all three.
#[inline(always)]
fn classify(steps: &Steps, e: &[i64; 3], shift: u32) -> (bool, bool) {
    let mut outside = false;
    let mut inside = true;
    for ((e, up), down) in e.iter().zip(steps.up).zip(steps.down) {
        outside |= e + (up << shift) - up < 0;
        inside &= e + (down << shift) - down >= 0;
    }
    (outside, inside)
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
/// with the whole region, handing `visit` each block's position, side as a
/// shift (`side = 1 << shift`) and edge values at its first pixel centre;
/// `Split` on a single pixel is treated as `Skip`. `steps` are the edges'
/// [`Steps`], which the caller's visitor needs too and so sets up once.
/// Returns the edge values at the end, which equal those at the start.
fn traverse<F>(edges: &Edges, steps: &Steps, x0: i32, y0: i32, order: u32, mut visit: F) -> [i64; 3]
where
    F: FnMut(i32, i32, u32, &[i64; 3]) -> Visit,
{
    let order = order.min(MAX_ORDER);
    let mut e = edges.at(x0, y0);
    let (mut x, mut y) = (x0, y0);
    // Blocks at `level` have side `1 << (order - level)`.
    let mut level = 0u32;
    let mut state = I;
    // Digit `l` (2 bits at 2*l) is which child of its parent the block at
    // level l is.
    let mut digits = 0u32;
    loop {
        let shift = order - level;
        if visit(x, y, shift, &e) == Visit::Split && shift > 0 {
            // Into the first child, in this block's state.
            level += 1;
            let half = shift - 1;
            let q = entry(QUAD, state, 0);
            if q & 1 != 0 {
                x += 1 << half;
                add(&mut e, &steps.step_x(half));
            }
            if q & 2 != 0 {
                y += 1 << half;
                add(&mut e, &steps.step_y(half));
            }
            digits &= !(3 << (2 * level));
            state = entry(NEXT, state, 0);
            continue;
        }
        // Next sibling, climbing while this was the last child.
        loop {
            if level == 0 {
                return e;
            }
            let k = (digits >> (2 * level)) & 3;
            let parent = entry(NEXT, state, k);
            let shift = order - level;
            let side = 1i32 << shift;
            if k < 3 {
                match entry(MOVE, parent, k) {
                    0 => {
                        x += side;
                        add(&mut e, &steps.step_x(shift));
                    }
                    1 => {
                        y += side;
                        add(&mut e, &steps.step_y(shift));
                    }
                    2 => {
                        x -= side;
                        sub(&mut e, &steps.step_x(shift));
                    }
                    _ => {
                        y -= side;
                        sub(&mut e, &steps.step_y(shift));
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
                sub(&mut e, &steps.step_x(shift));
            }
            if q & 2 != 0 {
                y -= side;
                sub(&mut e, &steps.step_y(shift));
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

/// Blocks of at most `1 << LEAF_SHIFT` pixels a side that straddle an
/// edge are finished pixel by pixel, row by row, rather than split further:
/// the last levels of the hierarchy would cost a classification per block
/// for a handful of pixels each.
pub const LEAF_SHIFT: u32 = 3;

/// Walks the `2^order`-sided region whose top-left pixel is `(x0, y0)` in
/// Hilbert order and calls `covered(x, y, w, h)` for rectangles of covered
/// pixel centres of the triangle, restricted to `clip`: whole blocks inside
/// all three edges (`w == h`, a power of two), and the covered run of each
/// row of a leaf block (at most `1 << LEAF_SHIFT` pixels a side) that
/// straddles an edge (`h == 1`). Every covered pixel is reported exactly
/// once. Returns the number of blocks classified, a cost measure.
///
/// ```
/// use microraster::raster::hilbert::{walk, Edges};
/// use microraster::raster::{PixelRect, SubPoint};
/// // The 4x4 right triangle of the scanline example: 3 + 2 + 1 pixels.
/// let e = Edges::new(&[SubPoint::new(0, 0), SubPoint::new(64, 0), SubPoint::new(0, 64)]).unwrap();
/// let mut covered = 0;
/// walk(&e, 0, 0, 2, PixelRect::new(0, 0, 4, 4), |_, _, w, h| covered += w * h);
/// assert_eq!(covered, 6);
/// ```
pub fn walk<F: FnMut(i32, i32, i32, i32)>(
    edges: &Edges,
    x0: i32,
    y0: i32,
    order: u32,
    clip: PixelRect,
    mut covered: F,
) -> u32 {
    let mut blocks = 0;
    let steps = Steps::new(edges);
    traverse(edges, &steps, x0, y0, order, |x, y, shift, e| {
        blocks += 1;
        let side = 1i32 << shift;
        let (bx1, by1) = (x + side, y + side);
        if x >= clip.x1 || y >= clip.y1 || bx1 <= clip.x0 || by1 <= clip.y0 {
            return Visit::Skip;
        }
        let (outside, inside) = classify(&steps, e, shift);
        if outside {
            return Visit::Skip;
        }
        let in_clip = x >= clip.x0 && y >= clip.y0 && bx1 <= clip.x1 && by1 <= clip.y1;
        if inside && in_clip {
            covered(x, y, side, side);
            return Visit::Skip;
        }
        if shift > LEAF_SHIFT {
            return Visit::Split;
        }
        leaf(&steps, e, x, y, side, &clip, &mut covered);
        Visit::Skip
    });
    blocks
}

/// Finishes a leaf block at `(x, y)` with edge values `e` at its first
/// pixel centre: tests its pixels inside `clip` one by one and reports
/// each row's covered run (the covered centres of a row of a triangle are
/// contiguous).
#[inline(always)]
fn leaf<F: FnMut(i32, i32, i32, i32)>(
    steps: &Steps,
    e: &[i64; 3],
    x: i32,
    y: i32,
    side: i32,
    clip: &PixelRect,
    covered: &mut F,
) {
    let (c0, c1) = (x.max(clip.x0), (x + side).min(clip.x1));
    let (r0, r1) = (y.max(clip.y0), (y + side).min(clip.y1));
    let mut row = [0i64; 3];
    for k in 0..3 {
        row[k] = e[k] + steps.a[k] * (c0 - x) as i64 + steps.b[k] * (r0 - y) as i64;
    }
    for j in r0..r1 {
        let mut p = row;
        let mut first = c1;
        let mut last = c1;
        for i in c0..c1 {
            let inside = p[0] >= 0 && p[1] >= 0 && p[2] >= 0;
            if inside && first == c1 {
                first = i;
            } else if !inside && first != c1 {
                last = i;
                break;
            }
            add(&mut p, &steps.a);
        }
        if first < last {
            covered(first, j, last - first, 1);
        }
        add(&mut row, &steps.b);
    }
}

/// Records the spans of triangle `v` within `clip` in `out`, one per
/// covered row in row order (the same spans as the scanline walker gives),
/// and returns how many. Only the first `out.len()` rows of the triangle's
/// bounds in `clip` are walked.
///
/// The region walked is the smallest `2^n` square at the top-left of the
/// triangle's pixel bounds in `clip`; blocks outside those bounds are
/// skipped by the walk's clip test. Every covered block widens the span of
/// each of its rows; a triangle's covered centres in a row are contiguous,
/// so the union of its blocks there is exactly one span.
#[inline(never)]
pub(crate) fn find_spans(v: &[SubPoint; 3], clip: PixelRect, out: &mut [Span]) -> usize {
    let Some(edges) = Edges::new(v) else {
        return 0;
    };
    let mut bounds = PixelRect::covering(v).intersect(&clip);
    bounds.y1 = bounds.y1.min(bounds.y0.saturating_add(out.len() as i32));
    if bounds.is_empty() {
        return 0;
    }
    let rows = (bounds.y1 - bounds.y0) as usize;
    for (r, s) in out[..rows].iter_mut().enumerate() {
        *s = Span {
            j: bounds.y0 + r as i32,
            x0: i32::MAX,
            x1: i32::MIN,
        };
    }
    let (w, h) = (bounds.x1 - bounds.x0, bounds.y1 - bounds.y0);
    let order = order_for(w as u32, h as u32);
    walk(&edges, bounds.x0, bounds.y0, order, bounds, |x, y, w, h| {
        let first = (y - bounds.y0) as usize;
        for s in &mut out[first..first + h as usize] {
            s.x0 = s.x0.min(x);
            s.x1 = s.x1.max(x + w);
        }
    });
    let mut n = 0;
    for r in 0..rows {
        if out[r].x0 < out[r].x1 {
            out[n] = out[r];
            n += 1;
        }
    }
    n
}

/// Whether triangle `v` covers every pixel centre of `rect` (not empty):
/// the hierarchy's first test, on the rectangle as one block, with the edge
/// values at the corner where each is smallest. [`super::Rasterizer::Auto`]
/// asks it of triangles whose bounds hold a whole tile, which then need no
/// edge walk at all.
pub(crate) fn covers_rect(v: &[SubPoint; 3], rect: &PixelRect) -> bool {
    let Some(edges) = Edges::new(v) else {
        return false;
    };
    let e = edges.at(rect.x0, rect.y0);
    let (w, h) = (
        (rect.x1 - rect.x0 - 1) as i64,
        (rect.y1 - rect.y0 - 1) as i64,
    );
    (0..3).all(|k| {
        let (a, b) = (edges.a[k] * SUBPIXEL as i64, edges.b[k] * SUBPIXEL as i64);
        e[k] + a.min(0) * w + b.min(0) * h >= 0
    })
}

/// Calls `span(row, x0, x1)` for every row of pixel centres triangle `v`
/// covers within `clip`, in row order: the spans of the Hilbert walk, which
/// are those of [`super::scanline::spans`] (the tests prove it).
///
/// ```
/// use microraster::raster::{hilbert, PixelRect, SubPoint};
/// let tri = [SubPoint::new(0, 0), SubPoint::new(64, 0), SubPoint::new(0, 64)];
/// let mut covered = 0;
/// hilbert::spans(&tri, PixelRect::new(0, 0, 16, 16), |_row, x0, x1| covered += x1 - x0);
/// assert_eq!(covered, 3 + 2 + 1);
/// ```
pub fn spans<F: FnMut(i32, i32, i32)>(v: &[SubPoint; 3], clip: PixelRect, mut span: F) {
    let bounds = PixelRect::covering(v).intersect(&clip);
    let mut buf = [Span::default(); 32];
    let mut y0 = bounds.y0;
    while y0 < bounds.y1 {
        let band = PixelRect::new(bounds.x0, y0, bounds.x1, bounds.y1);
        let n = find_spans(v, band, &mut buf);
        for s in &buf[..n] {
            span(s.j, s.x0, s.x1);
        }
        y0 = y0.saturating_add(buf.len() as i32);
    }
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
            let end = traverse(
                &edges,
                &Steps::new(&edges),
                x0,
                y0,
                order,
                |x, y, shift, e| {
                    let side = 1 << shift;
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
                },
            );
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

    /// Grid ranks follow the curve, skip nothing and repeat nothing, for
    /// grids of every shape up to 17 x 17.
    #[test]
    fn grid_ranks_follow_the_curve_over_any_grid() {
        for cols in 1..=17u32 {
            for rows in 1..=17u32 {
                let order = order_for(cols, rows);
                let mut expected = 0;
                for d in 0..(1u32 << (2 * order)) {
                    let (x, y) = index_to_cell(order, d);
                    if x < cols && y < rows {
                        assert_eq!(
                            rank_in_grid(cols, rows, x, y),
                            expected,
                            "{cols}x{rows} ({x}, {y})"
                        );
                        assert_eq!(
                            cell_at_rank(cols, rows, expected),
                            (x, y),
                            "{cols}x{rows} rank {expected}"
                        );
                        expected += 1;
                    }
                }
                assert_eq!(expected, cols * rows);
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
