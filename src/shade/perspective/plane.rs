//! The three perspective planes of a triangle for a fragment shader,
//! `Q`, `B1` and `B2` ([`WidePlane`], see the [parent module](super) for
//! the method): the general set-up in `i64` with clamped gradients, the
//! 32-bit one of small triangles on 32-bit targets, and the vertices'
//! scaled `1 / w` ([`scale_q`]).

use super::lerp::NARROW_MULTIPLY;
use super::{PerspectiveSetup, COLOUR_LOOP, Q_MAX, Q_ONE};
use crate::math::{mul_wide, mul_wide_by_narrow, Recip16};
use crate::raster::SUBPIXEL_BITS;
use crate::shade::small::Small;
use crate::shade::{Basis, GRADIENT_LIMIT};
use crate::shader::Varyings;

/// One plane in `i64`, gradients clamped to ±2^40: the value at the
/// centre of pixel `(i, j)` is `gx i + gy j + k`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct WidePlane {
    pub(super) gx: i64,
    pub(super) gy: i64,
    pub(super) k: i64,
}

impl WidePlane {
    /// The plane through `values` at the vertices of `f` (in `0..=2^28`).
    /// With `small`, on a 32-bit target, a small triangle's gradients in
    /// 32-bit divisions ([`perspective_gradients`]; the same values).
    #[inline(always)]
    pub(super) fn new(f: &Basis, values: [i64; 3], small: bool) -> Self {
        let (gx, gy) = if small {
            perspective_gradients(f, values)
        } else if NARROW_MULTIPLY {
            match &f.small {
                Some(s) => small_wide_gradients_digits(f, s, values),
                None => wide_gradients_split(f, values),
            }
        } else {
            f.gradients(values, 0)
        };
        let (gx, gy) = (
            gx.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT),
            gy.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT),
        );
        // |g| <= 2^40 and |o| < 2^19: no overflow.
        let k = if NARROW_MULTIPLY {
            values[0]
                + ((mul_wide_by_narrow(gx, f.ox as i32) + mul_wide_by_narrow(gy, f.oy as i32))
                    >> SUBPIXEL_BITS)
        } else {
            values[0] + ((gx * f.ox + gy * f.oy) >> SUBPIXEL_BITS)
        };
        Self { gx, gy, k }
    }

    /// [`new`](Self::new) out of line (see [`wide_planes_apart`]).
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(never)]
    pub(super) fn apart(f: &Basis, values: [i64; 3]) -> Self {
        Self::new(f, values, false)
    }

    /// The value at pixel `(i, j)`, clamped to `lo..=hi`. `|i|, |j| < 2^13`,
    /// so the sum stays below 2^60.
    #[inline(always)]
    pub(super) fn at(&self, i: i32, j: i32, lo: i64, hi: i64) -> i32 {
        (self.gx * i as i64 + self.gy * j as i64 + self.k).clamp(lo, hi) as i32
    }

    /// [`at`](Self::at) in wrapping `i32` arithmetic, the same value for a
    /// span start of a triangle none of whose gradients was clamped: the
    /// gradients are then the exact ones rounded, so at a covered pixel
    /// centre the plane is within 2^15 of the exact one, which lies
    /// between the vertex values (`0..=2^28`); that value fits `i32`, and
    /// the wrapping sum is exact modulo 2^32 (as [`Plane`](crate::shade::plane::Plane)'s). Two
    /// 32-bit products and a 32-bit clamp instead of 64-bit ones: a few
    /// instructions per span on a Cortex-M.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(always)]
    pub(super) fn at32(&self, i: i32, j: i32, lo: i32, hi: i32) -> i32 {
        self.at32_unclamped(i, j).clamp(lo, hi)
    }

    /// [`at32`](Self::at32) without its clamp, where the clamp cannot
    /// change the value: at a covered pixel centre the plane lies within
    /// `-2^15..=2^28 + 2^15` (see there), inside `-Q_MAX..=Q_MAX`. So
    /// `B1`'s and `B2`'s span starts take no clamp, and `Q`'s only its
    /// lower bound (`Q` at a pixel may be below 1 where the vertices' `q`
    /// are). Four compares and selects fewer per plane and span on a
    /// Cortex-M.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(always)]
    pub(super) fn at32_unclamped(&self, i: i32, j: i32) -> i32 {
        (self.gx as i32)
            .wrapping_mul(i)
            .wrapping_add((self.gy as i32).wrapping_mul(j))
            .wrapping_add(self.k as i32)
    }

    /// Whether neither gradient was clamped.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(always)]
    pub(super) fn exact(&self) -> bool {
        self.gx.abs() < GRADIENT_LIMIT && self.gy.abs() < GRADIENT_LIMIT
    }

    /// The step along a span, saturated to `i32` (a triangle whose step
    /// saturates is a sliver of one pixel per span, whose step is unused).
    #[inline(always)]
    pub(super) fn step(&self) -> i32 {
        self.gx.clamp(-Q_MAX, Q_MAX) as i32
    }
}

impl<V: Varyings> PerspectiveSetup<V> {
    /// The planes `Q`, `B1` and `B2` at the centre of pixel `(x0, j)`, the
    /// first of a span: in `i64`, clamped to their ranges (`Q` to
    /// `1..=Q_MAX`, the others to `±Q_MAX`), or on a 32-bit target, for a
    /// triangle none of whose gradients was clamped
    /// ([`narrow`](PerspectiveSetup::narrow)), the same values in `i32`.
    #[inline(always)]
    pub(crate) fn plane_starts(&self, x0: i32, j: i32) -> [i32; 3] {
        let [pq, p1, p2] = &self.planes;
        if self.narrow() && (V::LEN > 0 || COLOUR_LOOP) {
            // The clamps that cannot change a value left out
            // (`WidePlane::at32_unclamped`): Cortex-M3 `demo-textured-lit`
            // -1.8 %, `fill-nearest-exact` 58.61 -> 58.04,
            // `fill-nearest-affine` 46.05 -> 45.37, but `fill-bilinear-exact`
            // 161.82 -> 162.80 and `fill-lit-exact` 112.19 -> 112.67 (their
            // loops' registers). For shaders without varyings only on
            // Thumb-2 ([`COLOUR_LOOP`]), where `Gouraud`'s loop for spans
            // of constant `Q` is out of line (`colour_span_flat`): there
            // Cortex-M3 `fill-gouraud-exact` 57.23 -> 56.90 instructions a
            // fragment, Cortex-M4F 67.74 -> 67.12 (when that loop was
            // inlined, the M3's took 67.86 -> 70.23 with it).
            [
                pq.at32_unclamped(x0, j).max(1),
                p1.at32_unclamped(x0, j),
                p2.at32_unclamped(x0, j),
            ]
        } else if self.narrow() {
            const M: i32 = Q_MAX as i32;
            [
                pq.at32(x0, j, 1, M),
                p1.at32(x0, j, -M, M),
                p2.at32(x0, j, -M, M),
            ]
        } else {
            [
                pq.at(x0, j, 1, Q_MAX),
                p1.at(x0, j, -Q_MAX, Q_MAX),
                p2.at(x0, j, -Q_MAX, Q_MAX),
            ]
        }
    }
}

/// The three perspective planes through `q` by [`WidePlane::new`], and
/// whether none of their gradients was clamped, for what [`small_planes`]
/// declines on a 32-bit target
/// (large triangles, whose set-up is paid over many pixels, and slivers),
/// each plane out of line ([`WidePlane::apart`]): inlined beside the
/// small path, the three planes had the LM3S6965's `demo-textured-lit`
/// firmware over its flash.
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
pub(super) fn wide_planes_apart(f: &Basis, q: [i64; 3]) -> ([WidePlane; 3], bool) {
    let planes = [
        WidePlane::apart(f, q),
        WidePlane::apart(f, [0, q[1], 0]),
        WidePlane::apart(f, [0, 0, q[2]]),
    ];
    (planes, planes.iter().all(WidePlane::exact))
}

/// The three perspective planes of a [`Small`] triangle on a 32-bit
/// target when all six gradients are below 2^31 in magnitude
/// ([`small_gradient`]): the planes of [`WidePlane::new`], without its
/// clamps (at most 2^40, they change nothing) and with no `exact` test
/// to follow (every plane is). The numerators are written out for the
/// planes' values `(q0, q1, q2)`, `(0, q1, 0)` and `(0, 0, q2)`: those of
/// `B1` and `B2` one product each.
///
/// The planes through `q`, or `None` (a 64-bit host, no [`Small`], or
/// a gradient of 2^31 or more): then [`WidePlane::new`].
#[inline(always)]
#[cfg_attr(target_pointer_width = "64", allow(unused_variables))]
#[cfg_attr(microraster_narrow_multiply, allow(dead_code))]
pub(super) fn small_planes(f: &Basis, q: [i64; 3]) -> Option<[WidePlane; 3]> {
    #[cfg(not(target_pointer_width = "64"))]
    if let Some(s) = &f.small {
        return small_planes_of(f, s, q);
    }
    None
}

/// [`small_planes`] for a [`Small`] triangle `f` (whose `small` is `s`),
/// on any target (the tests run it on the host).
#[cfg_attr(
    any(target_pointer_width = "64", microraster_narrow_multiply),
    allow(dead_code)
)]
#[inline(always)]
pub(super) fn small_planes_of(f: &Basis, s: &Small, q: [i64; 3]) -> Option<[WidePlane; 3]> {
    if NARROW_MULTIPLY {
        small_planes_split(f, s, q)
    } else {
        small_planes_wide(f, s, q)
    }
}

/// [`small_planes_of`] where the core has a 32x32 to 64-bit multiply and
/// a divider: 64-bit numerators, two 32-bit divisions a gradient
/// ([`small_gradient`]).
#[cfg_attr(
    any(target_pointer_width = "64", microraster_narrow_multiply),
    allow(dead_code)
)]
#[inline(always)]
pub(super) fn small_planes_wide(f: &Basis, s: &Small, q: [i64; 3]) -> Option<[WidePlane; 3]> {
    debug_assert!(q.iter().all(|v| (0..=Q_ONE).contains(v)));
    // The edge vectors through a `black_box`, so that each numerator's
    // products are 32x32 to 64-bit ones (one `SMULL`): the optimiser,
    // knowing from `Small` that the `i64` edge vectors fit `i32`, had
    // dropped their truncation and sign extension and multiplied in 64
    // bits (`UMULL` and two `MLA`s a product, the vectors' high words
    // kept on the stack). Cortex-M3 `demo-textured-lit` 6,979,259 ->
    // 6,923,492 instructions, its affine frame 6,638,486 -> 6,631,957;
    // Cortex-M4F 6,969,821 -> 6,898,851 and 6,723,468 -> 6,719,053 (a
    // build of the two).
    let [x1, y1, x2, y2] =
        core::hint::black_box([f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32]);
    let [q0, q1, q2] = [q[0] as i32, q[1] as i32, q[2] as i32];
    let (d1, d2) = (q1 - q0, q2 - q0);
    let g = |n: i64| small_gradient(s, n);
    let qx = g(mul(d1, y2) - mul(d2, y1))?;
    let qy = g(mul(d2, x1) - mul(d1, x2))?;
    let b1x = g(mul(q1, y2))?;
    let b1y = g(-mul(q1, x2))?;
    let b2x = g(-mul(q2, y1))?;
    let b2y = g(mul(q2, x1))?;
    // |g| < 2^31 and |o| < 2^19: no overflow.
    let plane = |gx: i32, gy: i32, v0: i64| {
        let (gx, gy) = (gx as i64, gy as i64);
        WidePlane {
            gx,
            gy,
            k: v0 + ((gx * f.ox + gy * f.oy) >> SUBPIXEL_BITS),
        }
    };
    Some([plane(qx, qy, q[0]), plane(b1x, b1y, 0), plane(b2x, b2y, 0)])
}

/// [`small_planes_of`] on ARMv6-M, which has neither a 32x32 to 64-bit
/// multiply (each `i64` product is a library call of about 40
/// instructions) nor a divider (each 32-bit division one of about 150
/// in the QEMU firmware): the same planes, with each numerator's
/// products split at bit 16 of the value ([`split_mul`]: 32-bit
/// products by an edge vector below 2^10) and each gradient from three
/// digits of the area's 16-bit reciprocal ([`small_gradient_digits`]),
/// made once for the six. The constants only in their low 32 bits, the
/// part narrow planes read ([`Basis::offset_low`]): the same planes modulo
/// 2^32 in each `k`. Before, `demo-textured-lit` took 12
/// divisions and 16 64-bit products here per triangle and tile.
#[cfg_attr(not(test), allow(dead_code))]
#[inline(always)]
pub(super) fn small_planes_split(f: &Basis, s: &Small, q: [i64; 3]) -> Option<[WidePlane; 3]> {
    small_planes_split_by(f, s, &Recip16::new_small(s.area), q)
}

/// [`small_planes_split`] by `r`, the area's [`Recip16`]
/// (`Recip16::new_small(s.area)`), which ARMv6-M's perspective set-up
/// makes once for these planes and the depth plane
/// ([`TriangleSetup::depth_small`](crate::shade::TriangleSetup)).
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn small_planes_split_by(
    f: &Basis,
    s: &Small,
    r: &Recip16,
    q: [i64; 3],
) -> Option<[WidePlane; 3]> {
    debug_assert!(q.iter().all(|v| (0..=Q_ONE).contains(v)));
    let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
    let [q0, q1, q2] = [q[0] as i32, q[1] as i32, q[2] as i32];
    let (d1, d2) = (q1 - q0, q2 - q0);
    let g = |n: (i32, i32)| small_gradient_digits(r, s.half, n);
    let diff = |a: (i32, i32), b: (i32, i32)| (a.0 - b.0, a.1 - b.1);
    let neg = |a: (i32, i32)| (-a.0, -a.1);
    // The same Cramer's rule as `small_planes_wide`, line for line: one
    // function for both over the products' form (closures for the
    // product, difference, negation and gradient) cost the Cortex-M3's
    // `fill-lit-exact` 106.93 -> 108.75 a fragment (its span loop's
    // registers moved), so each keeps its own.
    let qx = g(diff(split_mul(d1, y2), split_mul(d2, y1)))?;
    let qy = g(diff(split_mul(d2, x1), split_mul(d1, x2)))?;
    let b1x = g(split_mul(q1, y2))?;
    let b1y = g(neg(split_mul(q1, x2)))?;
    let b2x = g(neg(split_mul(q2, y1)))?;
    let b2y = g(split_mul(q2, x1))?;
    // Every plane is narrow (no gradient clamped): the span starts read
    // only the constants' low 32 bits (`WidePlane::at32_unclamped`).
    let plane = |gx: i32, gy: i32, v0: i32| WidePlane {
        gx: gx as i64,
        gy: gy as i64,
        k: f.offset_low((gx as i64, gy as i64), v0) as i64,
    };
    Some([
        plane(qx, qy, q[0] as i32),
        plane(b1x, b1y, 0),
        plane(b2x, b2y, 0),
    ])
}

/// `a e` as `(h, l)` with `a e = h 2^16 + l`, for `|a| <= 2^28` (a
/// perspective value or a difference of two) and an edge vector `|e| <
/// 2^10`: `h = (a >> 16) e` (below 2^23 in magnitude) and `l = (a mod
/// 2^16) e` (below 2^26), two 32-bit products. A sum or difference of
/// two such stays far inside `i32` in each half.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn split_mul(a: i32, e: i32) -> (i32, i32) {
    ((a >> 16) * e, (a & 0xFFFF) * e)
}

/// [`small_gradient`] for the numerator `n = h 2^16 + l` (from
/// [`split_mul`]) by the area's reciprocal `r` ([`Recip16`], `r.d` the
/// area, below 2^21) and `half` (half the area): the same quotient or
/// `None`, by long division without a divider.
///
/// `a = |n| 2^4 + half < 2^43`. Its quotient is below 2^31 exactly when
/// `a`'s bits from 31 up, `t < 2^12`, are below `d`; then three digits of
/// 11, 10 and 10 bits bring the rest down, each by
/// [`Recip16::estimate`] and left uncorrected (the digit exact or one
/// less, its remainder in `0..2d`): the dividends `t 2^11 + a_{20..31}`
/// (below `d 2^11`) and `r' 2^10 + a_{10..20}`, `r' 2^10 + a_{0..10}`
/// (below `2d 2^10 = d 2^11`, and below 2^32 as `d < 2^21`) are within
/// its range `d (2^12 + 1)`. By construction `a = (q1 2^20 + q2 2^10 +
/// q3) d + r3` with `r3` in `0..2d`, so the quotient is that sum plus
/// `[r3 >= d]`.
///
/// `a` is made in 32-bit words, with no 64-bit value (ARMv6-M spent
/// some 25 instructions a gradient on the `i64` numerator's magnitude,
/// shift and sum, and on the digits' fields): `n = H 2^16 + L` with
/// `H = h + (l >> 16)` and `L = l mod 2^16` in `0..2^16`, so `n`'s sign
/// is `H`'s, and with `s` that sign as 0 or -1, `|n| = H' 2^16 + L'`
/// for `H' = H ^ s` (`-H - 1` when negative) and `L' = (L ^ (s mod
/// 2^16)) - s` (`2^16 - L`, at most 2^16: its two's complement). Then
/// `a = H' 2^20 + B` with `B = L' 2^4 + half < 2^21`, so `a >> 20 =
/// H' + (B >> 20)` (below 2^23 for `|n| < 2^39`), which is the first
/// dividend `t 2^11 + a_{20..31}` itself, and `a_{0..20} = B mod 2^20`.
/// `demo-textured-lit` on ARMv6-M 13,376,636 -> 13,143,847 instructions.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn small_gradient_digits(r: &Recip16, half: u32, (h, l): (i32, i32)) -> Option<i32> {
    let big_h = h + (l >> 16);
    let s = big_h >> 31;
    let hm = (big_h ^ s) as u32;
    let lm = ((l as u32 & 0xFFFF) ^ (s as u32 & 0xFFFF)).wrapping_sub(s as u32);
    let b = (lm << SUBPIXEL_BITS) + half;
    // `a >> 20`, and `a`'s low 20 bits.
    let top = hm + (b >> 20);
    let b = b & 0xF_FFFF;
    if top >> 11 >= r.d {
        return None;
    }
    let (q1, r1) = r.estimate(top);
    let (q2, r2) = r.estimate((r1 << 10) | (b >> 10));
    let (q3, r3) = r.estimate((r2 << 10) | (b & 0x3FF));
    let q = ((q1 << 20) + (q2 << 10) + q3 + (r3 >= r.d) as u32) as i32;
    Some(if s < 0 { -q } else { q })
}

/// `f.gradients(values, 0)` for a perspective plane (`Q`, `B1` or `B2`:
/// values in `0..=2^28`). On a 32-bit target a [`Small`] triangle's
/// gradients take two 32-bit divisions each ([`small_gradient`]) where
/// `Basis::gradients` takes four (`Small::div_round_wide`), when they are
/// below 2^31 in magnitude; the same quotients. The edge vectors are then
/// below 2^10 and the differences of the values at most 2^28, so each
/// numerator is a difference of two 32x32 to 64-bit products.
#[inline(always)]
pub(super) fn perspective_gradients(f: &Basis, values: [i64; 3]) -> (i64, i64) {
    #[cfg(not(target_pointer_width = "64"))]
    if let Some(small) = &f.small {
        debug_assert!(values.iter().all(|v| (0..=Q_ONE).contains(v)));
        let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
        let (d1, d2) = (
            (values[1] - values[0]) as i32,
            (values[2] - values[0]) as i32,
        );
        if let (Some(gx), Some(gy)) = (
            small_gradient(small, mul(d1, y2) - mul(d2, y1)),
            small_gradient(small, mul(d2, x1) - mul(d1, x2)),
        ) {
            return (gx as i64, gy as i64);
        }
    }
    f.gradients(values, 0)
}

/// `f.gradients(values, 0)` for a perspective plane of a triangle too large
/// for the [`Small`] set-up, on ARMv6-M, where each `i64` product is a
/// library call (`__aeabi_lmul`, about 40 instructions): the numerators
/// from 32-bit halves ([`mul_wide`]: the values' differences are at most
/// 2^28 and the edge vectors below 2^19, both within `i32`) and the
/// division by the area's reciprocal from them too
/// ([`Divisor::div_split`](crate::math::Divisor)), the same quotients as
/// `Basis::div_round`. For `f.small` `None` (only then is `f.area` the
/// area's reciprocal).
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn wide_gradients_split(f: &Basis, values: [i64; 3]) -> (i64, i64) {
    debug_assert!(f.small.is_none());
    let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
    let (d1, d2) = (
        (values[1] - values[0]) as i32,
        (values[2] - values[0]) as i32,
    );
    // |n| < 2^49 before the shift: within `div_split`'s 2^63 after it.
    let div_round = |n: i64| {
        let q = f
            .area
            .div_split((n.unsigned_abs() << SUBPIXEL_BITS) + f.half) as i64;
        if n >= 0 {
            q
        } else {
            -q
        }
    };
    (
        div_round(mul_wide(d1, y2) - mul_wide(d2, y1)),
        div_round(mul_wide(d2, x1) - mul_wide(d1, x2)),
    )
}

/// `f.gradients(values, 0)` for a perspective plane of a [`Small`]
/// triangle `f` (`s` its `small`) on ARMv6-M, where the small planes
/// declined (a gradient of 2^31 or more): the numerators' products split
/// ([`split_mul`]) and the quotient, rounded to nearest as
/// `Small::div_round_wide`'s, by four 11-bit digits of the area's 16-bit
/// reciprocal ([`Recip16::estimate`], each remainder corrected so the
/// next partial dividend, below `d 2^11 < 2^32`, is within the estimate's
/// range) where that takes four library divisions and their remainders.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn small_wide_gradients_digits(f: &Basis, s: &Small, values: [i64; 3]) -> (i64, i64) {
    debug_assert!(values.iter().all(|v| (0..=Q_ONE).contains(v)));
    let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
    let (d1, d2) = (
        (values[1] - values[0]) as i32,
        (values[2] - values[0]) as i32,
    );
    let r = Recip16::new_small(s.area);
    let div_round = |(h0, l0): (i32, i32), (h1, l1): (i32, i32)| {
        let n = (((h0 - h1) as i64) << 16) + (l0 - l1) as i64;
        // |n| < 2^39: `a` below 2^44, four digits of 11 bits.
        let a = (n.unsigned_abs() << SUBPIXEL_BITS) + s.half as u64;
        let digit = |rest: u32| {
            let (q, rem) = r.estimate(rest);
            if rem >= r.d {
                (q + 1, rem - r.d)
            } else {
                (q, rem)
            }
        };
        let (q, mut rem) = digit((a >> 33) as u32);
        let mut q = q as u64;
        for shift in [22, 11, 0] {
            let (d, next) = digit((rem << 11) | ((a >> shift) as u32 & 0x7FF));
            q = (q << 11) + d as u64;
            rem = next;
        }
        let q = q as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    };
    (
        div_round(split_mul(d1, y2), split_mul(d2, y1)),
        div_round(split_mul(d2, x1), split_mul(d1, x2)),
    )
}

/// `a b` in `i64`: one 32x32 to 64-bit product.
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
pub(super) fn mul(a: i32, b: i32) -> i64 {
    a as i64 * b as i64
}

/// `n 2^4 / area` rounded to nearest, ties away from zero (the quotient of
/// `Small::div_round_wide` and of `Basis::gradients`), for
/// `|n| <= 2 (2^28) (2^10 - 1) = 2^39 - 2^29`, if its magnitude is below
/// 2^31; `None` otherwise. Then `a = |n| 2^4 + half < 2^43`, so `a >> 11`
/// fits `u32`: one 32-bit division for it, and one for its remainder
/// (below `area < 2^21`) shifted by 11 with `a`'s low 11 bits.
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
pub(super) fn small_gradient(small: &Small, n: i64) -> Option<i32> {
    let d = small.area.get();
    let a = (n.unsigned_abs() << SUBPIXEL_BITS) + small.half as u64;
    let hi = (a >> 11) as u32;
    let q1 = hi / d;
    if q1 >= 1 << 20 {
        return None;
    }
    let lo = ((hi - q1 * d) << 11) | (a as u32 & 0x7FF);
    let q = ((q1 << 11) | (lo / d)) as i32;
    Some(if n < 0 { -q } else { q })
}

/// `(wmin << 28) / w` for `1 <= wmin <= w < 2^31`: a vertex's `1 / w`
/// scaled so that the nearest is [`Q_ONE`]. A 64-bit host divides; a
/// 32-bit core, where a 64-bit division is a library call, takes the same
/// quotient by long division in 32-bit steps of `k` bits, `k` the leading
/// zeros of `w` (so every partial dividend `r 2^k < w 2^k` fits `u32`):
/// two or three divisions for the usual `w` of 2^16 to 2^21.
#[inline(always)]
pub(super) fn scale_q(wmin: i64, w: i64) -> i64 {
    if cfg!(target_pointer_width = "64") || !(1..=w).contains(&wmin) || w >= 1 << 31 {
        return (wmin << 28) / w;
    }
    scale_q32(wmin as u32, w as u32)
}

/// [`scale_q`] on a 32-bit core, for `1 <= wmin <= w < 2^31`.
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
pub(super) fn scale_q32(wmin: u32, w: u32) -> i64 {
    if wmin == w {
        return Q_ONE;
    }
    // 1 <= wmin < w < 2^31: the quotient is below 2^28.
    let w = core::num::NonZeroU32::new(w).unwrap_or(core::num::NonZeroU32::MAX);
    if NARROW_MULTIPLY {
        return scale_q_digits(wmin, w) as i64;
    }
    crate::math::shift_in_zeros(0, wmin, w, 28).0 as i64
}

/// [`scale_q32`]'s long division on ARMv6-M, which has no divider: its
/// digits by `w`'s 16-bit reciprocal ([`Recip16::digit`]: two 32-bit
/// products and a correction each, where the library division takes
/// about 150 instructions), of `k = min(leading zeros of w, 12)` bits,
/// so that each partial dividend `r 2^k < w 2^k` is below 2^32 and
/// within the digit's range `2^(t + 13)` (`2^t <= w`): three digits for
/// the usual `w` of 2^16 to 2^21. For `1 <= wmin < w < 2^31`.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn scale_q_digits(wmin: u32, w: core::num::NonZeroU32) -> u32 {
    // Below 2^23 (nearly every `w`) the reciprocal by a table look-up of
    // `w`'s top byte rather than a search of its leading zeros, and below
    // 2^20 the digit's 12 bits without them.
    let v = w.get();
    if v < 1 << 20 {
        // Nearly every `w`: the three digits of 12, 12 and 4 bits written
        // out, where the loop kept its quotient, count and shift in stack
        // slots: ARMv6-M `demo-textured-lit` 13,030,706 -> 12,807,162
        // instructions, `fill-gouraud-exact` 96.71 -> 95.28 a fragment,
        // for 2.8 KB of flash in the all-scenes firmware (a copy in each
        // shader's set-up).
        let f = Recip16::new_w23(w);
        let (d1, r) = f.digit(wmin << 12);
        let (d2, r) = f.digit(r << 12);
        let (d3, _) = f.digit(r << 4);
        return (d1 << 16) | (d2 << 4) | d3;
    }
    let f = if v < 1 << 23 {
        Recip16::new_w23(w)
    } else {
        Recip16::new(w)
    };
    let k = crate::math::leading_zeros(w).min(12);
    let (mut q, mut r, mut left) = (0u32, wmin, 28u32);
    while left > 0 {
        let s = k.min(left);
        let (digit, rest) = f.digit(r << s);
        q = (q << s) | digit;
        r = rest;
        left -= s;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_offset_products_are_exact() {
        let mut next = crate::testing::rng();
        let gs = [
            -(1i64 << 40),
            -(1 << 32) - 1,
            -(1 << 32),
            -1,
            0,
            1,
            u32::MAX as i64,
            1 << 40,
        ];
        let os = [-(1i32 << 19) + 1, -65_536, -1, 0, 1, 65_535, (1 << 19) - 1];
        for &g in &gs {
            for &o in &os {
                assert_eq!(mul_wide_by_narrow(g, o), g * o as i64, "{g} * {o}");
            }
        }
        for _ in 0..100_000 {
            let g = next((1 << 41) + 1) as i64 - (1 << 40);
            let o = next(1 << 20) as i32 - (1 << 19) + 1;
            assert_eq!(mul_wide_by_narrow(g, o), g * o as i64, "{g} * {o}");
        }
    }
}
