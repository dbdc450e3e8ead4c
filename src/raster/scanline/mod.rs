//! The scanline (edge-walking) rasterizer.
//!
//! This follows Chris Hecker's *Perspective Texture Mapping* articles (Game
//! Developer, 1995–96): sort the vertices by y, split the triangle at the
//! middle vertex, and walk the long edge and the two short edges one pixel
//! row at a time. Every edge is *pre-stepped* to the first pixel-centre row
//! it covers, and every span starts at the first pixel centre at or right of
//! the left edge, so sub-pixel vertex positions are honoured exactly.
//!
//! Hecker walks x with a 16.16 slope, which accumulates rounding error. Here
//! the slope is split, as in his `FloorDivMod` stepper, into an integer
//! column step and an exact remainder with the edge's own denominator, so
//! the column where each span starts and ends is the exact
//! `ceil((x_edge(y_c) - ½) )` of the rational edge position. That makes the
//! coverage identical to an exact edge-function test with the top-left rule
//! (see [`crate::raster`]):
//!
//! * rows: a centre row `y_c` is inside when `y_top <= y_c < y_bottom`, so a
//!   horizontal top edge is drawn and a horizontal bottom edge is not;
//! * columns: a span is `[ceil(x_left - ½), ceil(x_right - ½))`, so a centre
//!   on a left edge is drawn and one on a right edge is not.
//!
//! Set-up needs one `i32` division per edge, its per-row step. The start
//! column of an edge's own first row follows from that step in `i32`;
//! only a start that a tile's top clips lower needs `i64` products (screen
//! coordinates within the guard band reach ±2^18 sub-pixels) and a second
//! division, in `i32` unless a long edge lies far from the origin. The
//! per-row stepping is `i32` adds and one compare per edge.
//!
//! On a core with a division instruction (all but ARMv6-M's) a
//! triangle within `0..DIRECT_COLS` columns is walked as `Direct`
//! edges instead: the numerator of each edge's column is kept and
//! divided at every row, so an edge's set-up is two multiplies and no
//! division or sign test. It takes fewer instructions (docs/rounds.md,
//! "The round of `289aa7d`"), though a division takes more cycles than
//! the stepper's three: 2 to 12 on the M3, about 10 to 25 on x86-64.
//!
//! The walk records the spans of a triangle's rows in a buffer rather than
//! calling back for each: the renderer walks a triangle's rows in a tile
//! into a buffer of one span per tile row, so the edge loop runs with
//! nothing else in registers, and shades them afterwards. [`spans`] runs
//! the same walk over bands of 32 rows through a small buffer.

use super::{
    first_centre_at_or_after, PixelRect, Span, SubPoint, HALF_PIXEL, SUBPIXEL, SUBPIXEL_BITS,
};
#[cfg(test)]
use cover::may_cover;
use cover::{misses, misses_apart};
use direct::{half_direct, Direct, BOTH, DIRECT_COLS, DIRECT_DY};
#[cfg(target_pointer_width = "64")]
use direct::{LEFT, RIGHT};
use edge::{half, lower_half, EdgeStepper};
use packed::{half_packed, Packed, PACKED_COLS, PACKED_DY};

mod cover;
mod direct;
mod edge;
mod packed;

/// Whether [`find_spans`] walks the triangles within `0..DIRECT_COLS`
/// as [`Direct`] edges, a division a row for each: on cores with a
/// division instruction (not ARMv6-M, whose division is a library call,
/// nor ARMv8-M Baseline), and in the unit tests, which also walk the
/// other way ([`find_spans_with`]).
const DIRECT: bool = cfg!(any(not(microraster_narrow_multiply), test));

/// Row count above which [`find_spans`] first tests whether the triangle misses
/// the clip rectangle altogether.
///
/// 20 rather than 16: the test (out of line on 32-bit cores) costs more
/// than the 17 to 20 rows it could spare a pair in `demo`. The same code
/// but the compare's constant: `demo` M3 3,112,233 -> 3,110,999
/// instructions, M4F 3,076,199 -> 3,074,991, ARMv6-M 6,296,430 ->
/// 6,292,947, x86-64 3,097,082 -> 3,096,242; `rock` and `fill`
/// unchanged on all four (24 to 31 within 5 of 20; 12 +5.2 K on the M3).
const CHECK_ROWS: i32 = 20;

/// Records the non-empty spans of triangle `v` in `clip`, in row order,
/// in `out`, and returns how many: the walk of the rows of `clip` (at most
/// the first `out.len()` of the triangle's rows there), as the renderer
/// asks it for a tile.
///
/// The long edge a -> c (vertices sorted by y) is on the left when the
/// middle vertex b is right of it. The short edge is a -> b for rows whose
/// centre lies above b, then b -> c. Both halves run through the same row
/// loop (a copy for each half, of [`half`] or of [`half_packed`]), and no
/// row tests which edge is on which side.
#[inline(always)]
pub(crate) fn find_spans(v: &[SubPoint; 3], clip: PixelRect, out: &mut [Span]) -> usize {
    find_spans_with::<DIRECT, false>(v, clip, out)
}

/// [`find_spans`] for a caller that inlines the walk (the tile loop's
/// common path on every core with a long multiply): the test of a tall
/// triangle ([`misses`]) out of line ([`misses_apart`]), so that the
/// caller's loop keeps its registers for the small triangles, and the
/// rows' spans written to the slots left
/// ([`SLOTS_LEFT`](edge::SLOTS_LEFT)'s form) on 64-bit hosts too. (The
/// call written in the condition itself: bound
/// to a local first, the clip moved the tile loop's registers, x86-64
/// `demo` +6.9 K, `fill` +4.3 K.)
#[inline(always)]
pub(crate) fn find_spans_inline(v: &[SubPoint; 3], clip: PixelRect, out: &mut [Span]) -> usize {
    find_spans_with::<DIRECT, true>(v, clip, out)
}

/// [`find_spans`], with the triangles within `0..DIRECT_COLS` walked as
/// [`Direct`] edges when `DIRECT` (the same spans).
#[inline(always)]
fn find_spans_with<const DIRECT: bool, const APART: bool>(
    v: &[SubPoint; 3],
    clip: PixelRect,
    out: &mut [Span],
) -> usize {
    // Sort by y: a on top, c at the bottom.
    let (mut a, mut b, mut c) = (v[0], v[1], v[2]);
    if a.y > b.y {
        core::mem::swap(&mut a, &mut b);
    }
    if b.y > c.y {
        core::mem::swap(&mut b, &mut c);
    }
    if a.y > b.y {
        core::mem::swap(&mut a, &mut b);
    }
    // Neither a zero area nor an empty clip is tested: a triangle of zero
    // area has its edges on one line, so each row's left and right
    // columns are equal and every span is empty (and `may_cover` may
    // reject it), and an empty clip's rows are empty and its spans
    // clamped empty (a triangle within its columns then lies within one
    // column, whose spans are empty too).
    // The rows by `first_row` where the walk divides (M4F `demo`
    // 3,158,058 -> 3,149,398 instructions, x86-64 3,605,162 ->
    // 3,595,512, `fill` 9.07 -> 9.03 a pixel); ARMv6-M keeps its code,
    // and so does the Cortex-M3 (`microraster_armv7m`), where it moved the
    // row loop's registers: `demo` -692 but `fill` 14.68 -> 14.73 a pixel.
    let first_row = if DIRECT && !cfg!(microraster_armv7m) {
        first_row
    } else {
        first_centre_at_or_after
    };
    let row_top = first_row(a.y).max(clip.y0);
    let row_mid = first_row(b.y);
    // On ARMv6-M the last row alone by `first_row` (an add and a shift;
    // the local `first_row` is `first_centre_at_or_after` there): `demo`
    // 5,862,997 -> 5,846,622 instructions, `rock` 4,892,285 -> 4,880,063,
    // `fill` 20.06 -> 20.05 a pixel. All three rows by `first_row` took
    // `demo` to 5,858,873 but `fill` to 20.08 (the clamped row loop's
    // registers moved), `rock` +446.
    let mut row_end = if cfg!(microraster_narrow_multiply) {
        self::first_row(c.y)
    } else {
        first_row(c.y)
    }
    .min(clip.y1);
    if row_top >= row_end {
        return 0;
    }
    // Before walking many rows, check that no edge puts every pixel
    // centre of the clipped block strictly outside (a tile that the
    // triangle's bounding box overlaps but the triangle misses).
    if row_end - row_top > CHECK_ROWS {
        // Marked rare on 32-bit cores, where the call of `misses` otherwise
        // keeps the sorted vertices and the rows in stack slots on every
        // pair's path (Cortex-M3 `demo` 4,113,898 -> 4,104,279
        // instructions); a 64-bit host inlines the test, and walks large
        // triangles (x86-64 `fill` 9.71 -> 10.03 per pixel with the mark).
        #[cfg(target_pointer_width = "32")]
        crate::hint::cold();
        if APART && misses_apart(a, b, c, PixelRect::new(clip.x0, row_top, clip.x1, row_end))
            || !APART && misses(a, b, c, PixelRect::new(clip.x0, row_top, clip.x1, row_end))
        {
            return 0;
        }
    }
    if DIRECT {
        let (x0, x1) = (clip.x0, clip.x1);
        let (xmin, xmax) = (a.x.min(b.x).min(c.x), a.x.max(b.x).max(c.x));
        if direct_fits(xmin, xmax, c.y - a.y) {
            // Whether every span lies within the clip's columns (as
            // below): `xmin >= 16 x0 - 7` is `floor((xmin + 7) / 16) >=
            // x0`, and `xmax <= 16 x1 + 8` is `ceil((xmax - 8) / 16) <=
            // x1`, the same floor of `xmax + 7`; compared, no difference
            // can wrap, whatever the clip (the differences' signs took
            // a test of the clip's columns too: M3 `demo` -21.7 K).
            let h = HALF_PIXEL - 1;
            // (Compiled out elsewhere: the dead block had changed the
            // OLED firmware's code, +8 B; one match for every target,
            // the one-side arms guarded by a constant, took the M3's
            // `demo` +2.7 K and the M4F's +30 K.)
            #[cfg(target_pointer_width = "64")]
            if APART {
                // The walk inlined in the tile loop of 64-bit hosts: a
                // triangle across one side column clamps its spans at
                // that side only (two instructions fewer a row): x86-64
                // `demo` 2,855,742 -> 2,845,244 instructions, `rock`
                // 2,370,417 -> 2,363,446, `demo-flat` 2,481,253 ->
                // 2,470,755, `fill` 8.81 -> 8.76 a pixel, `tri4` -27 K,
                // `tri100` -68 K, `tri10000` -67 K.
                let rows = (row_top, row_mid, row_end);
                let (left_in, right_in) = ((xmin + h) >> 4 >= x0, (xmax + h) >> 4 <= x1);
                return match (left_in, right_in) {
                    (true, true) => walk_direct::<false, BOTH, true>(a, b, c, rows, x0, x1, out),
                    (false, true) => walk_direct::<true, LEFT, true>(a, b, c, rows, x0, x1, out),
                    (true, false) => walk_direct::<true, RIGHT, true>(a, b, c, rows, x0, x1, out),
                    (false, false) => walk_direct::<true, BOTH, true>(a, b, c, rows, x0, x1, out),
                };
            }
            let inside = ((xmin + h) >> 4 >= x0) & ((xmax + h) >> 4 <= x1);
            return if inside {
                walk_direct::<false, BOTH, false>(a, b, c, (row_top, row_mid, row_end), x0, x1, out)
            } else {
                walk_direct::<true, BOTH, false>(a, b, c, (row_top, row_mid, row_end), x0, x1, out)
            };
        }
    }
    // At most one span per row of `out`.
    if (row_end - row_top) as usize > out.len() {
        row_end = row_top + out.len() as i32;
    }
    // Whether every span lies within the clip's columns: its columns are
    // those of the edges between the vertices, so the vertices' extent
    // bounds them. A triangle inside its tile's columns (most of a mesh's
    // small ones) then takes a row loop with no clamps, whose two fewer
    // live values spare it loads from the stack on a 32-bit core. On
    // x86-64 that loop without packing measured slower (`demo` +0.8 %,
    // `fill` +3.6 %), packed faster: `demo` 4,701,139 -> 4,641,680
    // instructions, `rock` 3,910,785 -> 3,860,305, `fill` 9.70 -> 9.81
    // per pixel (its quads take the other loop, whose code moved).
    //
    // The loop without clamps also packs each edge's column and error
    // term into one word ([`Packed`]), which needs the columns within
    // `0..PACKED_COLS` and the edges at most `PACKED_DY` sub-pixels tall.
    //
    // A vertex at `x` keeps its edges' columns at or after `x0` when
    // `x >= 16 x0 - 7` and at or before `x1` when `x <= 16 x1 + 8`. Each
    // condition is the sign of a difference, tested at once: within the
    // guard band only a clip far outside it could wrap a difference,
    // and the column bounds then fail first.
    let (lo, hi) = (
        clip.x0.wrapping_mul(SUBPIXEL).wrapping_sub(HALF_PIXEL - 1),
        clip.x1.wrapping_mul(SUBPIXEL).wrapping_add(HALF_PIXEL),
    );
    let outside = clip.x0
        | (PACKED_COLS - 1).wrapping_sub(clip.x1)
        | (PACKED_DY - (c.y - a.y))
        | a.x.wrapping_sub(lo)
        | b.x.wrapping_sub(lo)
        | c.x.wrapping_sub(lo)
        | hi.wrapping_sub(a.x)
        | hi.wrapping_sub(b.x)
        | hi.wrapping_sub(c.x);
    let inside = outside >= 0;
    // Otherwise, whether the edges can still be packed: their columns
    // within `0..PACKED_COLS` (the vertices within `-7..=16 (PACKED_COLS
    // - 1) + 8`, as above), walked with clamps (a triangle across its
    // tile's side columns: 30 % of `demo`'s pairs, whose rows took the
    // clamped loop of `EdgeStepper`s, 36 to 40 instructions a row on the
    // M3). Only a triangle near the frame's left edge or outside it, or
    // one taller than `PACKED_DY`, takes the `EdgeStepper`s.
    let packed = inside
        || cfg!(any(target_pointer_width = "32", test)) && {
            let (lo, hi) = (1 - HALF_PIXEL, (PACKED_COLS - 1) * SUBPIXEL + HALF_PIXEL);
            (PACKED_DY - (c.y - a.y))
                | (a.x - lo)
                | (b.x - lo)
                | (c.x - lo)
                | (hi - a.x)
                | (hi - b.x)
                | (hi - c.x)
                >= 0
        };
    // The short edge of the first row, and where its half ends.
    let ((p, q), stop) = if row_top < row_mid {
        ((a, b), row_mid.min(row_end))
    } else {
        ((b, c), row_end)
    };
    let (x0, x1) = (clip.x0, clip.x1);
    // (Where `DIRECT`, the direct walk took every triangle the packed one
    // could, but for one exactly `PACKED_DY` tall: none is packed, and
    // its code is left out.)
    if packed && !DIRECT {
        // The orientation in `i32`, which holds it here: the vertices lie
        // within `-7..=16 (PACKED_COLS - 1) + 8`, their x differences
        // below 2^14, and their y within `PACKED_DY` (2^15), so each
        // product is below 2^29. (The 64-bit products, computed for every
        // triangle before, were spilled to the stack.)
        let long_on_left = (b.x - a.x) * (c.y - a.y) > (c.x - a.x) * (b.y - a.y);
        // Both edges set up packed straight away: fewer live values than
        // two `EdgeStepper`s packed afterwards.
        let long = Packed::new::<false>(a, c, row_top);
        let short = Packed::new::<false>(p, q, row_top);
        let (mut left, mut right) = sides(long_on_left, long, short);
        let n = if inside {
            half_packed::<false>(out, 0, row_top, stop, &mut left, &mut right, x0, x1)
        } else {
            half_packed::<true>(out, 0, row_top, stop, &mut left, &mut right, x0, x1)
        };
        if stop >= row_end {
            return n;
        }
        // The lower half, from `stop == row_mid`.
        let lower = Packed::new::<true>(b, c, stop);
        replace_short(long_on_left, lower, &mut left, &mut right);
        return if inside {
            half_packed::<false>(out, n, stop, row_end, &mut left, &mut right, x0, x1)
        } else {
            half_packed::<true>(out, n, stop, row_end, &mut left, &mut right, x0, x1)
        };
    }
    let long_on_left = long_on_left(a, b, c);
    let long = EdgeStepper::new::<false>(a, c, row_top);
    let short = EdgeStepper::new::<false>(p, q, row_top);
    let (mut left, mut right) = sides(long_on_left, long, short);
    // A copy of the row loop for each half: the one loop kept the lower
    // half's set-up live across the upper half's rows. (On x86-64 one loop
    // had measured faster before the packed walk took the triangles within
    // their tile's columns; with it, the two copies: `demo` 4,641,680 ->
    // 4,585,091 instructions, `rock` 3,860,305 -> 3,819,141, `fill` 9.81
    // -> 9.71 per pixel, with `SLOTS_LEFT`.)
    let n = half::<APART>(out, 0, row_top, stop, &mut left, &mut right, x0, x1);
    if stop >= row_end {
        return n;
    }
    // The lower half, from `stop == row_mid`.
    lower_half(b, c, stop, long_on_left, &mut left, &mut right);
    half::<APART>(out, n, stop, row_end, &mut left, &mut right, x0, x1)
}

/// [`first_centre_at_or_after`] as `floor((v + 7) / 16)`, the same
/// ceiling of `(v - 8) / 16`: an add and a shift, where its negated
/// shift of `8 - v` took a register holding zero through the walk's
/// set-up. (`v` within the guard band: no overflow.)
#[inline(always)]
const fn first_row(v: i32) -> i32 {
    (v + (HALF_PIXEL - 1)) >> SUBPIXEL_BITS
}

/// Whether a triangle whose vertices' `x` lie within `xmin..=xmax` and
/// whose height is `dy` (sorted by y: `c.y - a.y`) can be walked as
/// [`Direct`] edges: the vertices within `-7..DIRECT_COLS * SUBPIXEL - 8`
/// (`x + 7` within `0..2^14`) and the height below `DIRECT_DY` (its half
/// below 2^14), tested at once.
#[inline(always)]
fn direct_fits(xmin: i32, xmax: i32, dy: i32) -> bool {
    const _: () = assert!(DIRECT_COLS * SUBPIXEL == 1 << 14 && DIRECT_DY == 1 << 15);
    let w = (xmin + (HALF_PIXEL - 1)) | (xmax + (HALF_PIXEL - 1)) | (dy >> 1);
    (w as u32) >> 14 == 0
}

/// The walk of [`find_spans_with`] for a triangle `a, b, c` (sorted by
/// y) within `0..DIRECT_COLS` as [`Direct`] edges: the rows
/// `row_top..row_end`, the short edge `a -> b` above `row_mid`, then `b
/// -> c`. At most `out.len()` spans: a half stops when no slot is left.
/// With `CLAMP`, the spans clamped on the `SIDES` side or sides (see
/// [`half_direct`]); `FRESH` as there (the walk inlined in the
/// tile loop of 64-bit hosts).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn walk_direct<const CLAMP: bool, const SIDES: u8, const FRESH: bool>(
    a: SubPoint,
    b: SubPoint,
    c: SubPoint,
    (row_top, row_mid, row_end): (i32, i32, i32),
    x0: i32,
    x1: i32,
    out: &mut [Span],
) -> usize {
    // The orientation in `i32`: x differences below 2^14, y differences
    // below 2^15.
    let long_on_left = (b.x - a.x) * (c.y - a.y) > (c.x - a.x) * (b.y - a.y);
    let long = Direct::new::<false>(a, c, row_top);
    // The short edge of the first row, and where its half ends.
    let ((p, q), stop) = if row_top < row_mid {
        ((a, b), row_mid.min(row_end))
    } else {
        ((b, c), row_end)
    };
    // `MAX` on this edge alone: see `Direct::new`.
    let short = Direct::new::<true>(p, q, row_top);
    let (mut left, mut right) = sides(long_on_left, long, short);
    let len = out.len();
    let rest =
        half_direct::<CLAMP, SIDES, FRESH>(out, row_top, stop, &mut left, &mut right, x0, x1);
    if stop >= row_end {
        return len - rest.len();
    }
    // The lower half, from `stop == row_mid`.
    replace_short(
        long_on_left,
        Direct::new::<false>(b, c, stop),
        &mut left,
        &mut right,
    );
    let rest =
        half_direct::<CLAMP, SIDES, FRESH>(rest, stop, row_end, &mut left, &mut right, x0, x1);
    len - rest.len()
}

/// Whether the middle vertex `b` (vertices sorted by y) is right of the
/// long edge `a -> c`: twice the signed area, `(b - a) x (c - a)`, is
/// positive. The two products are compared rather than subtracted, and
/// only that one bit stays live. Within the guard band the edge vectors
/// fit `i32`. A zero area gives false (see [`find_spans`]).
#[inline(always)]
pub(super) fn long_on_left(a: SubPoint, b: SubPoint, c: SubPoint) -> bool {
    crate::math::mul_wide(b.x - a.x, c.y - a.y) > crate::math::mul_wide(c.x - a.x, b.y - a.y)
}

/// The left and right edges of the upper half's rows, the long edge (from
/// the top vertex to the bottom one) on the left when `long_on_left`: for
/// the packed edges and the general ones alike.
#[inline(always)]
fn sides<E>(long_on_left: bool, long: E, short: E) -> (E, E) {
    if long_on_left {
        (long, short)
    } else {
        (short, long)
    }
}

/// The lower half's short edge `lower` in place of the upper half's, on
/// the side the long edge leaves free.
#[inline(always)]
pub(super) fn replace_short<E>(long_on_left: bool, lower: E, left: &mut E, right: &mut E) {
    if long_on_left {
        *right = lower;
    } else {
        *left = lower;
    }
}

/// Calls `span(row, x_start, x_end)` for every non-empty run of covered
/// pixels `x_start..x_end` of the triangle `v`, row by row from the top,
/// restricted to `clip`.
///
/// Works for either winding and does nothing for a zero-area triangle.
/// Vertices must lie within the guard band of [`crate::vertex`] (±2^18
/// sub-pixels), which the vertex stage guarantees.
///
/// ```
/// use microraster::raster::{scanline::spans, PixelRect, SubPoint};
/// // A 4x4-pixel right triangle: centres strictly above its hypotenuse are
/// // covered; the three centres exactly on it lie on a right edge and are not.
/// let tri = [SubPoint::new(0, 0), SubPoint::new(64, 0), SubPoint::new(0, 64)];
/// let mut covered = 0;
/// spans(&tri, PixelRect::new(0, 0, 16, 16), |_row, x0, x1| covered += x1 - x0);
/// assert_eq!(covered, 3 + 2 + 1);
/// ```
pub fn spans<F: FnMut(i32, i32, i32)>(v: &[SubPoint; 3], clip: PixelRect, mut span: F) {
    // The walk of the renderer's tiles, over bands of 32 rows of `clip`.
    let mut buf = [Span::default(); 32];
    let mut y0 = clip.y0;
    while y0 < clip.y1 {
        let y1 = y0.saturating_add(buf.len() as i32).min(clip.y1);
        let n = find_spans(v, PixelRect::new(clip.x0, y0, clip.x1, y1), &mut buf);
        for s in &buf[..n] {
            span(s.j, s.x0, s.x1);
        }
        y0 = y1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    // No `std` in the library, not even in its tests (CI checks): spans of
    // at most 40 rows fit a fixed vector.
    type Spans = heapless::Vec<(i32, i32, i32), 64>;

    fn count(v: [SubPoint; 3]) -> i32 {
        let mut n = 0;
        spans(&v, PixelRect::new(-100, -100, 100, 100), |_, a, b| {
            n += b - a
        });
        n
    }

    #[test]
    fn square_split_in_two_covers_each_pixel_once() {
        let p = |x, y| SubPoint::new(x * 16, y * 16);
        let a = count([p(0, 0), p(4, 0), p(4, 4)]);
        let b = count([p(0, 0), p(4, 4), p(0, 4)]);
        assert_eq!(a + b, 16);
    }

    /// Rows of `spans` over `clip`, one row at a time (never long enough
    /// for the early rejection), against one call over all of `clip`.
    #[test]
    fn early_rejection_changes_no_span() {
        let mut rng = crate::testing::rng();
        let mut next = move |m: u64| rng(m) as i32;
        let mut rejected = 0;
        for _ in 0..3_000 {
            let p = |a: i32, b: i32| SubPoint::new(a - 200, b - 200);
            let v = [
                p(next(1200), next(1200)),
                p(next(1200), next(1200)),
                p(next(1200), next(1200)),
            ];
            let (x0, y0) = (next(60) - 10, next(60) - 10);
            let clip = PixelRect::new(x0, y0, x0 + 1 + next(40), y0 + 1 + next(40));
            let mut all = Spans::new();
            spans(&v, clip, |j, a, b| all.push((j, a, b)).unwrap());
            let mut by_row = Spans::new();
            for j in clip.y0..clip.y1 {
                spans(&v, PixelRect::new(clip.x0, j, clip.x1, j + 1), |j, a, b| {
                    by_row.push((j, a, b)).unwrap()
                });
            }
            assert_eq!(all, by_row, "{v:?} {clip:?}");
            let area2 = crate::raster::signed_area2(&v);
            if area2 != 0 && !may_cover(&v, area2 > 0, clip) {
                assert!(by_row.is_empty(), "{v:?} {clip:?}");
                rejected += 1;
            }
        }
        assert!(rejected > 100, "the test should exercise rejection");
    }

    /// The row loop without clamps (a triangle inside the clip's columns)
    /// against the one with them (the same triangle in narrower columns).
    #[test]
    fn spans_without_clamps_match_the_clamped_ones() {
        let mut rng = crate::testing::rng();
        let mut next = move |m: u64| rng(m) as i32;
        for _ in 0..20_000 {
            let p = |a: i32, b: i32| SubPoint::new(a - 100, b - 100);
            let v = [
                p(next(700), next(700)),
                p(next(700), next(700)),
                p(next(700), next(700)),
            ];
            let mut wide = Spans::new();
            spans(&v, PixelRect::new(-10, -10, 40, 40), |j, a, b| {
                wide.push((j, a, b)).unwrap()
            });
            let (x0, x1) = (next(30) - 5, next(30) - 5);
            let clip = PixelRect::new(x0, -10, x1, 40);
            let mut narrow = Spans::new();
            spans(&v, clip, |j, a, b| narrow.push((j, a, b)).unwrap());
            let clipped: Spans = wide
                .iter()
                .map(|&(j, a, b)| (j, a.max(x0), b.min(x1)))
                .filter(|&(_, a, b)| a < b)
                .collect();
            assert_eq!(narrow, clipped, "{v:?} {clip:?}");
        }
    }

    /// The row loop of [`Packed`] edges (a triangle within the columns of
    /// a clip within `0..PACKED_COLS`) against the clamped one (the same
    /// triangle in a clip from column -1, clamped afterwards), at both
    /// ends of the packed columns.
    #[test]
    fn packed_spans_match_the_clamped_ones() {
        let mut rng = crate::testing::rng();
        let mut next = move |m: u64| rng(m) as i32;
        let mut packed = 0;
        for k in 0..40_000 {
            let x0 = if k % 2 == 0 { 0 } else { PACKED_COLS - 41 };
            let x1 = x0 + 1 + next(40);
            let p = |a: i32, b: i32| SubPoint::new(x0 * SUBPIXEL - 24 + a, b - 100);
            let v = [
                p(next(700), next(700)),
                p(next(700), next(700)),
                p(next(700), next(700)),
            ];
            let clip = PixelRect::new(x0, -10, x1, 40);
            let mut got = Spans::new();
            spans(&v, clip, |j, a, b| got.push((j, a, b)).unwrap());
            let mut wide = Spans::new();
            spans(&v, PixelRect::new(-1, -10, x1, 40), |j, a, b| {
                wide.push((j, a, b)).unwrap()
            });
            let clipped: Spans = wide
                .iter()
                .map(|&(j, a, b)| (j, a.max(x0), b))
                .filter(|&(_, a, b)| a < b)
                .collect();
            assert_eq!(got, clipped, "{v:?} {clip:?}");
            let (lo, hi) = (v.iter().map(|p| p.x).min(), v.iter().map(|p| p.x).max());
            if first_centre_at_or_after(lo.unwrap()) >= x0
                && first_centre_at_or_after(hi.unwrap()) <= x1
                && !got.is_empty()
            {
                packed += 1;
            }
        }
        assert!(packed > 1_000, "the test should exercise the packed loop");
    }

    /// The packed walk with clamps (a triangle within the packed columns,
    /// across its clip's sides) against the walk of `EdgeStepper`s: the
    /// same triangle and clip moved whole pixels left, out of the packed
    /// columns (coverage moves with them).
    #[test]
    fn clamped_packed_spans_match_the_stepped_ones() {
        const K: i32 = 1024;
        let mut rng = crate::testing::rng();
        let mut next = move |m: u64| rng(m) as i32;
        let mut clamped = 0;
        for _ in 0..20_000 {
            let p = |a: i32, b: i32| SubPoint::new(a, b - 100);
            let v = [
                p(next(900), next(700)),
                p(next(900), next(700)),
                p(next(900), next(700)),
            ];
            let (x0, x1) = (next(50), next(50));
            let clip = PixelRect::new(x0, -10, x1, 40);
            let mut got = Spans::new();
            spans(&v, clip, |j, a, b| got.push((j, a, b)).unwrap());
            let moved = v.map(|q| SubPoint::new(q.x - K * SUBPIXEL, q.y));
            let mut want = Spans::new();
            spans(
                &moved,
                PixelRect::new(x0 - K, -10, x1 - K, 40),
                |j, a, b| want.push((j, a + K, b + K)).unwrap(),
            );
            assert_eq!(got, want, "{v:?} {clip:?}");
            let across = v
                .iter()
                .any(|q| q.x < x0 * SUBPIXEL - 7 || q.x > x1 * SUBPIXEL + 8);
            if across && !got.is_empty() {
                clamped += 1;
            }
        }
        assert!(clamped > 1_000, "the test should exercise the clamps");
    }

    /// The walk of [`Direct`] edges against the stepped and packed ones
    /// ([`find_spans_with`]): triangles of every size across clips of
    /// every kind, near the direct columns' ends and beyond them.
    #[test]
    fn direct_spans_match_the_stepped_ones() {
        let mut rng = crate::testing::rng();
        let mut next = move |m: u64| rng(m) as i32;
        let mut direct = 0;
        for k in 0..60_000 {
            let (ox, span) = match k % 4 {
                0 => (-40, 400),
                1 => (DIRECT_COLS * SUBPIXEL - 300, 400),
                2 => (next(16_000) - 200, 60 + next(600)),
                _ => (-300, 4_000 + next(30_000)),
            };
            let p = |a: i32, b: i32| SubPoint::new(ox + a, b - 100);
            let h = if k % 4 == 3 { 40_000 } else { span };
            let v = [
                p(next(span as u64), next(h as u64)),
                p(next(span as u64), next(h as u64)),
                p(next(span as u64), next(h as u64)),
            ];
            let cx = ox / SUBPIXEL - 4 + next(12);
            let x0 = if k % 8 < 4 { cx } else { cx - 30 };
            let y0 = next(20) - 12;
            let clip = PixelRect::new(x0, y0, x0 + 1 + next(40), y0 + 1 + next(32));
            let mut a = [Span::default(); 32];
            let mut b = [Span::default(); 32];
            let na = find_spans_with::<true, false>(&v, clip, &mut a);
            let nb = find_spans_with::<false, false>(&v, clip, &mut b);
            assert_eq!(a[..na], b[..nb], "{v:?} {clip:?}");
            // The tile loop's inlined walk (64-bit hosts: its clamps of
            // one side only).
            let mut c = [Span::default(); 32];
            let nc = find_spans_with::<true, true>(&v, clip, &mut c);
            assert_eq!(c[..nc], b[..nb], "{v:?} {clip:?}");
            // Counted only where the direct walk itself found the spans:
            // the triangle passes the dispatcher's range test.
            let (xmin, xmax) = (
                v[0].x.min(v[1].x).min(v[2].x),
                v[0].x.max(v[1].x).max(v[2].x),
            );
            let (ymin, ymax) = (
                v[0].y.min(v[1].y).min(v[2].y),
                v[0].y.max(v[1].y).max(v[2].y),
            );
            direct += (na > 0 && direct_fits(xmin, xmax, ymax - ymin)) as u32;
        }
        assert!(
            direct > 10_000,
            "the direct walk should find spans: {direct}"
        );
    }

    #[test]
    fn degenerate_triangles_cover_nothing() {
        let p = |x, y| SubPoint::new(x, y);
        assert_eq!(count([p(0, 0), p(100, 100), p(200, 200)]), 0);
        assert_eq!(count([p(5, 5), p(5, 5), p(5, 5)]), 0);
        assert_eq!(count([p(0, 8), p(100, 8), p(200, 8)]), 0);
    }
}
