//! One attribute plane of a triangle, `gx i + gy j + k` at pixel
//! `(i, j)`, and the geometry its gradients come from: Cramer's rule over
//! twice the triangle's signed area ([`Basis`]), dividing by the area's
//! reciprocal, or in 32-bit steps for a small triangle (see the [parent
//! module](super) for the method and the fixed-point formats).

use super::small::{Small, SMALL_EDGE, SMALL_SETUP};
use crate::math::{Divisor, SPLIT};
use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use core::num::{NonZeroU32, NonZeroU64};

/// One interpolated attribute, with `frac` fraction bits: its value at the
/// centre of pixel `(i, j)` is `gx i + gy j + k`.
///
/// That is the plane `base + floor((gx dx + gy dy) / SUBPIXEL)` through
/// vertex `o`, with `dx = SUBPIXEL i + HALF_PIXEL - o.x` (likewise `dy`)
/// and `base` the biased value at `o`, regrouped exactly: `gx SUBPIXEL i`
/// is a multiple of `SUBPIXEL`, so it passes through the floor unchanged,
/// and the terms that do not depend on the pixel are summed once into `k`.
///
/// # Why `i32` arithmetic is exact
///
/// The gradients are rounded to the nearest integer, so at a pixel centre
/// `(dx, dy)` sub-pixels from `o` the value is within
/// `(|dx| + |dy|) / 32 + 1` of the exact plane. Span starts are covered
/// centres, which lie in the triangle, where the exact plane is between
/// the smallest and largest vertex value; vertices lie within 2^18
/// sub-pixels of the origin and pixels within 2^16, so the value is within
/// 20,481 of `lo..=hi`, far inside `i32` (`hi < 2^30`). The sum
/// `gx i + gy j + k` may wrap on the way there, but wrapping arithmetic is
/// exact modulo 2^32, so its result is that value exactly, as the `i64`
/// sum would give. This holds unless a gradient had to be clamped to
/// ±2^40 (only for a sliver narrower than about 1/1,000 pixel, see the
/// module docs); then [`TriangleSetup::wide`](super::TriangleSetup::wide) is set and the span starts
/// come from [`wide_start`](super::sliver::wide_start), in `i64`, which never wraps.
///
/// The value is then clamped to `lo..=hi`, as a span starts there and
/// steps from there.
///
/// Along a span the value steps by `gx`. A span of two or more pixels has
/// two covered centres one pixel apart, where the exact values differ by
/// at most the attribute's range, so `|gx| < 2^30` there and the step is
/// exact too.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plane {
    pub(super) gx: i32,
    pub(super) gy: i32,
    pub(super) k: i32,
}

/// The geometry every plane of a triangle shares: the edge vectors from
/// vertex 0, with signs chosen so that the Cramer denominator (twice the
/// absolute area) is positive, that denominator, and the offset of the
/// first pixel centre from vertex 0.
#[derive(Clone, Copy, Debug)]
pub(super) struct Basis {
    pub(super) x1: i64,
    pub(super) y1: i64,
    pub(super) x2: i64,
    pub(super) y2: i64,
    /// Twice the absolute area, by which all eight gradients are divided
    /// (through its reciprocal on 32-bit targets, see [`Divisor`]; not
    /// made for a [`Small`] triangle, whose gradients take 32-bit
    /// divisions instead).
    pub(super) area: Divisor,
    /// Twice the absolute area, for the divisions of a [`Small`] triangle's
    /// gradients that do not fit its 32-bit ones.
    pub(super) area64: NonZeroU64,
    /// Half of twice the absolute area, for rounding.
    pub(super) half: u64,
    /// `HALF_PIXEL - o.x` and `HALF_PIXEL - o.y` of vertex 0.
    pub(super) ox: i64,
    pub(super) oy: i64,
    /// On 32-bit targets, a triangle whose edge vectors are below
    /// [`SMALL_EDGE`] in magnitude.
    pub(super) small: Option<Small>,
}

impl Basis {
    #[inline(always)]
    pub(super) fn new(v: &[SubPoint; 3]) -> Self {
        Self::with_small(v, SMALL_SETUP)
    }

    /// [`Basis::new`], with small triangles set up in 32-bit divisions
    /// when `small_setup` (the tests compare both on the host).
    #[inline(always)]
    pub(super) fn with_small(v: &[SubPoint; 3], small_setup: bool) -> Self {
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        // Twice the signed area, as `crate::raster::signed_area2` (the
        // vertices lie within the guard band). On ARMv6-M, whose 64-bit
        // products are made of four 16-bit ones, a small triangle's in
        // `i32` (edge vectors below 2^10: products below 2^20), as the
        // fragment shaders' set-up takes every triangle-tile pair
        // through here: `demo-textured-lit` 13,143,847 -> 13,030,706
        // instructions, `demo` 6,081,261 -> 6,080,114, `fill` 23.26 ->
        // 23.28 a pixel. (The `i32` area for the fragment shaders' set-up
        // alone measured worse on every scene: 13,080,330, 6,081,032,
        // 23.27.)
        // (Behind `cfg`: the other targets keep the order before, whose
        // code the test ahead of the area had moved, Cortex-M3 `demo`
        // +64; on ARMv6-M the test written twice measured worse,
        // `demo-textured-lit` +54 K.)
        // Whether the edge vectors are small: tested where each target
        // measured it best (see above).
        let edges_small = || small_setup && [x1, y1, x2, y2].iter().all(|c| c.abs() < SMALL_EDGE);
        #[cfg(microraster_narrow_multiply)]
        let small_edges = edges_small();
        #[cfg(microraster_narrow_multiply)]
        let area2 = if small_edges {
            let [a, b, c, d] = [x1 as i32, y1 as i32, x2 as i32, y2 as i32];
            (a * d - c * b) as i64
        } else {
            crate::raster::signed_area2_banded(v)
        };
        #[cfg(not(microraster_narrow_multiply))]
        let area2 = crate::raster::signed_area2_banded(v);
        // Callers never set up a zero-area triangle (it has no spans); the
        // fallback only keeps this total.
        let area = NonZeroU64::new(area2.unsigned_abs()).unwrap_or(NonZeroU64::MIN);
        // n / d with d < 0 is (-n) / (-d); negating the edge vectors negates
        // every numerator exactly, so every division has a positive
        // denominator and the same rounded result.
        let s = if area2 < 0 { -1 } else { 1 };
        #[cfg(not(microraster_narrow_multiply))]
        let small_edges = edges_small();
        let small = match small_edges {
            // Twice the area of a small triangle is below 2^21.
            true => NonZeroU32::new(area.get() as u32).map(|area| Small {
                area,
                half: area.get() / 2,
            }),
            false => None,
        };
        // ARMv6-M has no 64-bit multiply: `s * x1` there is a library call
        // (`__aeabi_lmul`) for each of the four, where a negation is two
        // instructions; the other targets keep their code.
        let [x1, y1, x2, y2] = if !SPLIT {
            [s * x1, s * y1, s * x2, s * y2]
        } else if area2 < 0 {
            [-x1, -y1, -x2, -y2]
        } else {
            [x1, y1, x2, y2]
        };
        Self {
            x1,
            y1,
            x2,
            y2,
            area: match small {
                Some(_) => Divisor::new(NonZeroU64::MIN),
                None => Divisor::new(area),
            },
            area64: area,
            half: area.get() / 2,
            ox: HALF_PIXEL as i64 - v[0].x as i64,
            oy: HALF_PIXEL as i64 - v[0].y as i64,
            small,
        }
    }

    /// `n / area` rounded to nearest, ties away from zero, as
    /// the vertex stage rounds too.
    #[inline(always)]
    pub(super) fn div_round(&self, n: i64) -> i64 {
        if self.small.is_some() {
            // A small triangle's attribute beyond its 32-bit divisions
            // (the perspective weights): a plain division.
            let q = ((n.unsigned_abs() + self.half) / self.area64) as i64;
            return if n >= 0 { q } else { -q };
        }
        // |n| < 2^57 and half < 2^39: within `Reciprocal::div`'s range.
        if n >= 0 {
            self.area.div(n as u64 + self.half) as i64
        } else {
            -(self.area.div(n.unsigned_abs() + self.half) as i64)
        }
    }
}

impl Basis {
    /// The gradients `(gx, gy)` of an attribute with `values` at the three
    /// vertices and `frac` fraction bits, per pixel, rounded to nearest
    /// (Cramer's rule), not yet clamped.
    #[inline(always)]
    pub(super) fn gradients(&self, values: [i64; 3], frac: u32) -> (i64, i64) {
        let d1 = values[1] - values[0];
        let d2 = values[2] - values[0];
        let shift = frac + SUBPIXEL_BITS;
        if let Some(small) = &self.small {
            if d1.abs() < 1 << 16 && d2.abs() < 1 << 16 {
                // |d| < 2^16 and edge vectors below 2^10: the numerators
                // are below 2^27, and the shift at most 20.
                let [x1, y1, x2, y2] = [
                    self.x1 as i32,
                    self.y1 as i32,
                    self.x2 as i32,
                    self.y2 as i32,
                ];
                let (d1, d2) = (d1 as i32, d2 as i32);
                return (
                    small.div_round(d1 * y2 - d2 * y1, shift),
                    small.div_round(d2 * x1 - d1 * x2, shift),
                );
            }
            if frac == 0 && d1.abs() <= 1 << 28 && d2.abs() <= 1 << 28 {
                // The perspective planes (values up to 2^28, no fraction
                // bits): numerators below 2^39 before the shift of 4, so
                // within `div_round_wide`'s 2^43.
                return (
                    small.div_round_wide((d1 * self.y2 - d2 * self.y1) << shift),
                    small.div_round_wide((d2 * self.x1 - d1 * self.x2) << shift),
                );
            }
        }
        (
            self.div_round((d1 * self.y2 - d2 * self.y1) << shift),
            self.div_round((d2 * self.x1 - d1 * self.x2) << shift),
        )
    }

    /// The plane constant `k` of an attribute whose value at vertex 0 is
    /// `value`, in wrapping arithmetic: exact for gradients within
    /// ±[`GRADIENT_LIMIT`](super::GRADIENT_LIMIT), no overflow check beyond.
    /// On ARMv6-M only its low 32 bits ([`Basis::constant_low`]), the part
    /// a 32-bit target uses: the rest is for 64-bit hosts' packed starts.
    #[inline(always)]
    pub(super) fn constant_wrapping(&self, value: i64, frac: u32, (gx, gy): (i64, i64)) -> i64 {
        if SPLIT {
            return self.constant_low(value, frac, (gx, gy)) as i64;
        }
        let base = (value << frac) + (1i64 << (frac - 1));
        let t = gx
            .wrapping_mul(self.ox)
            .wrapping_add(gy.wrapping_mul(self.oy));
        base.wrapping_add(t >> SUBPIXEL_BITS)
    }

    /// The low 32 bits of [`Basis::constant_wrapping`], all that a 32-bit
    /// target keeps of it ([`Plane::k`]), in 32-bit products: ARMv6-M
    /// makes each of the two 64-bit products a library call
    /// ([`offset_low`](Self::offset_low)).
    #[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
    #[inline(always)]
    pub(super) fn constant_low(&self, value: i64, frac: u32, g: (i64, i64)) -> i32 {
        let base = ((value as i32) << frac).wrapping_add(1 << (frac - 1));
        self.offset_low(g, base)
    }

    /// The low 32 bits of `base + ((gx ox + gy oy) >> 4)`, a plane's
    /// constant at the basis's offset, in four 32-bit products (the
    /// 64-bit form takes two 64-bit products, library calls on ARMv6-M):
    /// [`constant_low`](Self::constant_low)'s and the perspective planes'.
    ///
    /// With `gx = 16 q + r` (`q = gx >> 4`, `0 <= r < 16`) and likewise
    /// `gy = 16 qy + ry`, the product `gx ox` is `16 q ox` plus `r ox`, so
    /// `(gx ox + gy oy) >> 4` is `q ox + qy oy + ((r ox + ry oy) >> 4)`
    /// exactly. Modulo 2^32 the first two terms need only the low 32 bits
    /// of `q` and `ox`, and the last is exact in `i32`: `|ox|, |oy| < 2^19`
    /// (vertices within 2^18 sub-pixels of the origin), so
    /// `|r ox + ry oy| < 2^24`.
    #[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
    #[inline(always)]
    pub(crate) fn offset_low(&self, (gx, gy): (i64, i64), base: i32) -> i32 {
        const _: () = assert!(SUBPIXEL_BITS == 4);
        let (ox, oy) = (self.ox as i32, self.oy as i32);
        let (qx, qy) = ((gx >> SUBPIXEL_BITS) as i32, (gy >> SUBPIXEL_BITS) as i32);
        let (rx, ry) = ((gx & 15) as i32, (gy & 15) as i32);
        let low = rx.wrapping_mul(ox).wrapping_add(ry.wrapping_mul(oy)) >> SUBPIXEL_BITS;
        base.wrapping_add(qx.wrapping_mul(ox))
            .wrapping_add(qy.wrapping_mul(oy))
            .wrapping_add(low)
    }
}

impl Plane {
    /// The value at the centre of pixel `(i, j)`, exact (see the type's
    /// docs), not clamped to the attribute's range.
    #[inline(always)]
    pub(super) fn at(&self, i: i32, j: i32) -> i32 {
        // `k + gy j` first: two multiply-accumulates (wrapping, so any
        // order gives the same value).
        self.k
            .wrapping_add(self.gy.wrapping_mul(j))
            .wrapping_add(self.gx.wrapping_mul(i))
    }

    /// The step along a span (exact for every span of two pixels or more,
    /// see the type's docs).
    #[inline(always)]
    pub(super) fn step(&self) -> i32 {
        self.gx
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Basis::constant_low`] is the low 32 bits of the 64-bit constant,
    /// for any gradients (wrapping) and vertices in the guard band.
    #[test]
    fn constant_low_is_the_wrapping_constant() {
        let mut next = crate::testing::rng();
        let v = [SubPoint { x: 0, y: 0 }; 3];
        let mut f = Basis::with_small(&v, false);
        let signed = |n: u64, next: &mut dyn FnMut(u64) -> u64| next(2 * n) as i64 - n as i64;
        for k in 0..1_000_000 {
            f.ox = HALF_PIXEL as i64 - signed(1 << 18, &mut next);
            f.oy = HALF_PIXEL as i64 - signed(1 << 18, &mut next);
            let wide = |next: &mut dyn FnMut(u64) -> u64| {
                (next(1 << 32) << 32 | next(1 << 32)) as i64 >> next(64)
            };
            let (gx, gy) = match k % 3 {
                0 => (wide(&mut next), wide(&mut next)),
                1 => (signed(1 << 40, &mut next), signed(1 << 40, &mut next)),
                _ => (signed(1 << 20, &mut next), signed(1 << 20, &mut next)),
            };
            let value = signed(1 << 24, &mut next);
            for frac in [14, 16] {
                let base = (value << frac) + (1i64 << (frac - 1));
                let t = gx.wrapping_mul(f.ox).wrapping_add(gy.wrapping_mul(f.oy));
                let k = base.wrapping_add(t >> SUBPIXEL_BITS);
                assert_eq!(f.constant_low(value, frac, (gx, gy)), k as i32);
                assert_eq!(f.constant_wrapping(value, frac, (gx, gy)) as i32, k as i32);
            }
        }
    }
}
