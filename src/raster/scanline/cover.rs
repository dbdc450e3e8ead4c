//! Whether a triangle may cover a pixel centre of a clip rectangle: one
//! corner per edge against the edge function (the trivial-reject corner of
//! hierarchical rasterization), so that a tile skips the row walk of a tall
//! triangle whose bounding box merely overlaps it.

use super::long_on_left;
use crate::raster::{PixelRect, SubPoint, HALF_PIXEL, SUBPIXEL};

/// Whether the triangle `v`, of positive twice signed area when
/// `positive` (negative otherwise; zero covers nothing, whatever this
/// says), may cover a pixel centre of `clip`: false only when no centre
/// of `clip` can be covered, as every centre of its part within 2^20
/// pixels of the origin lies strictly outside one of its edges (which no
/// fill-rule tie can change), and the triangle, within the guard band,
/// covers none beyond. A cheap test (one corner per edge) that lets a
/// tile skip the row walk of a triangle whose bounding box merely
/// overlaps it.
///
/// The clip so clamped, the corners' offsets from a vertex fit `i32`
/// (below 2^25 sub-pixels), as do the edge vectors (2^19): each edge's
/// test is two 32 x 32-bit products (the `i64` ones took 400 bytes of
/// the OLED firmware's flash).
#[inline]
pub(super) fn may_cover(v: &[SubPoint; 3], positive: bool, clip: PixelRect) -> bool {
    const L: i32 = 1 << 20;
    let (x0, x1) = (clip.x0.clamp(-L, L), clip.x1.clamp(-L, L));
    let (y0, y1) = (clip.y0.clamp(-L, L), clip.y1.clamp(-L, L));
    if x0 >= x1 || y0 >= y1 {
        return false;
    }
    let (xl, xh) = (x0 * SUBPIXEL + HALF_PIXEL, (x1 - 1) * SUBPIXEL + HALF_PIXEL);
    let (yl, yh) = (y0 * SUBPIXEL + HALF_PIXEL, (y1 - 1) * SUBPIXEL + HALF_PIXEL);
    for k in 0..3 {
        let (p, q) = (v[k], v[(k + 1) % 3]);
        let (mut ex, mut ey) = (q.x - p.x, q.y - p.y);
        // E(c) = ex (c.y - p.y) - ey (c.x - p.x) has the sign of the area on
        // the inner side; flip it so the inner side is positive.
        if !positive {
            (ex, ey) = (-ex, -ey);
        }
        // The corner centre where E is largest.
        let cx = if ey < 0 { xh } else { xl };
        let cy = if ex > 0 { yh } else { yl };
        if crate::math::mul_wide(ex, cy - p.y) < crate::math::mul_wide(ey, cx - p.x) {
            return false;
        }
    }
    true
}

/// Whether the triangle `a, b, c` (sorted by y) misses every pixel centre
/// of `clip` ([`may_cover`]). Out of line, as only a triangle of more
/// than [`CHECK_ROWS`](super::CHECK_ROWS) rows in a tile asks: the walk then computes the
/// orientation only where it needs it, in `i32` for a triangle within
/// its tile's columns (inlined, the 64-bit orientation was computed for
/// every triangle and spilled; the M3's `demo` -26 K instructions).
///
/// A 64-bit host has the registers for it inline (out of line there,
/// x86-64 `demo` measured +3 %, `fill` +3.6 %).
#[cfg_attr(target_pointer_width = "64", inline(always))]
#[cfg_attr(not(target_pointer_width = "64"), inline(never))]
pub(super) fn misses(a: SubPoint, b: SubPoint, c: SubPoint, clip: PixelRect) -> bool {
    !may_cover(&[a, b, c], long_on_left(a, b, c), clip)
}

/// [`misses`] out of line, for [`find_spans_inline`](super::find_spans_inline): on 64-bit hosts in
/// `i64` without the clamps of the clip and its emptiness test
/// ([`may_cover_wide`]: about 15 instructions fewer a call; `fill` 8.84
/// -> 8.81 a pixel, `tri10000` -26 K). The walk that `fill`'s
/// `find_spans` makes (the shader draws' and any other rasterizer's)
/// keeps [`misses`] inline on 64-bit hosts: out of line there, the
/// shader fills took 0.07 instructions a fragment more.
#[inline(never)]
pub(super) fn misses_apart(a: SubPoint, b: SubPoint, c: SubPoint, clip: PixelRect) -> bool {
    if cfg!(target_pointer_width = "64") {
        return !may_cover_wide(&[a, b, c], long_on_left(a, b, c), clip);
    }
    misses(a, b, c, clip)
}

/// [`may_cover`] in `i64` (64-bit hosts): the corners and products of any
/// clip fit, so the clip needs no clamp (the same answer for every clip
/// within 2^20 pixels of the origin, where the clamp changes nothing, and
/// as exact beyond). An empty clip is not tested: whatever the answer,
/// its rows are empty or its spans clamped empty (see [`find_spans`](super::find_spans)),
/// and [`misses_apart`] is asked only of the rows the walk takes.
#[inline(always)]
fn may_cover_wide(v: &[SubPoint; 3], positive: bool, clip: PixelRect) -> bool {
    let c = |c: i32| c as i64 * SUBPIXEL as i64 + HALF_PIXEL as i64;
    let (xl, xh) = (c(clip.x0), c(clip.x1 - 1));
    let (yl, yh) = (c(clip.y0), c(clip.y1 - 1));
    for k in 0..3 {
        let (p, q) = (v[k], v[(k + 1) % 3]);
        let (mut ex, mut ey) = ((q.x - p.x) as i64, (q.y - p.y) as i64);
        if !positive {
            (ex, ey) = (-ex, -ey);
        }
        let cx = if ey < 0 { xh } else { xl };
        let cy = if ex > 0 { yh } else { yl };
        if ex * (cy - p.y as i64) < ey * (cx - p.x as i64) {
            return false;
        }
    }
    true
}
