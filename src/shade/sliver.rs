//! The span starts of a sliver: a triangle narrow enough (below about
//! 1/1,000 pixel) that a gradient had to be clamped to ±2^40, whose `i32`
//! planes would not be exact. Rare, so small rather than fast.

#[cfg(doc)]
use super::plane::Basis;
use super::setup::{Corners, C_HI, C_LO, Z_HI, Z_LO};
use super::GRADIENT_LIMIT;
use crate::raster::{HALF_PIXEL, SUBPIXEL_BITS};
use core::num::NonZeroU64;

/// The values at the centre of pixel `(i, j)` of a sliver whose gradients
/// had to be clamped to ±[`GRADIENT_LIMIT`]: the planes set up again with
/// the clamped gradients and evaluated in `i64`, which cannot overflow
/// (`|gx i| < 2^52`, `|k| < 2^59`), then clamped to each attribute's range.
/// Rare enough to redo the set-up for every span, and small rather than
/// fast: [`Basis`]'s gradients and constants written out with plain 64-bit
/// divisions (the same quotients as its reciprocal and its 32-bit
/// divisions), one attribute at a time, which saves about a kilobyte of
/// flash on 32-bit targets.
#[cold]
#[inline(never)]
pub(super) fn wide_start(t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
    let v = t.points();
    let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
    let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
    let area2 = x1 * y2 - x2 * y1;
    // As in `Basis`: edge vectors negated for a positive denominator (a
    // wide triangle is never degenerate; the fallback keeps this total).
    let s = if area2 < 0 { -1 } else { 1 };
    let w = Wide {
        basis: [s * x1, s * y1, s * x2, s * y2],
        area: NonZeroU64::new(area2.unsigned_abs()).unwrap_or(NonZeroU64::MIN),
        o: (
            HALF_PIXEL as i64 - v[0].x as i64,
            HALF_PIXEL as i64 - v[0].y as i64,
        ),
        at: (i as i64, j as i64),
    };
    [0, 1, 2, 3].map(|a| wide_value(&w, t, a))
}

/// What [`wide_start`]'s attributes share: the edge vectors `x1, y1, x2,
/// y2` and twice the absolute area, as in [`Basis`], the first pixel
/// centre's offset from vertex 0 and the pixel.
struct Wide {
    basis: [i64; 4],
    area: NonZeroU64,
    o: (i64, i64),
    at: (i64, i64),
}

/// Attribute `a` of [`wide_start`] (as [`Corners::values`] numbers them),
/// clamped to its range.
#[cold]
#[inline(never)]
fn wide_value(w: &Wide, t: &Corners<'_>, a: usize) -> i32 {
    let [x1, y1, x2, y2] = w.basis;
    let ((ox, oy), (i, j), area) = (w.o, w.at, w.area);
    let (values, frac) = t.values(a);
    let (lo, hi) = if a == 0 { (Z_LO, Z_HI) } else { (C_LO, C_HI) };
    let half = area.get() / 2;
    // `Basis::div_round` with a plain division: |n| < 2^57, half < 2^39.
    let div_round = |n: i64| {
        let q = ((n.unsigned_abs() + half) / area) as i64;
        if n >= 0 {
            q
        } else {
            -q
        }
    };
    let (d1, d2) = (values[1] - values[0], values[2] - values[0]);
    let shift = frac + SUBPIXEL_BITS;
    let gx = div_round((d1 * y2 - d2 * y1) << shift).clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
    let gy = div_round((d2 * x1 - d1 * x2) << shift).clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
    // `Basis::constant`.
    let k = (values[0] << frac) + (1i64 << (frac - 1)) + ((gx * ox + gy * oy) >> SUBPIXEL_BITS);
    (gx * i + gy * j + k).clamp(lo as i64, hi as i64) as i32
}
