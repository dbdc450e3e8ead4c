//! Per-frame set-up math in `f32`, and its hand-over to 16.16 fixed point.
//!
//! Matrices are built once per frame (or per draw) in `f32`, so they cost
//! nothing per vertex. The vertex stage never sees a float:
//! [`Mat4::to_fixed`] converts a matrix to [`FixedMat4`], whose elements are
//! [`I16F16`](fixed::types::I16F16), and every per-vertex product goes through `i64`.
//!
//! Conventions follow OpenGL: column vectors, right-handed eye space looking
//! down -z, clip-space x, y, z in `[-w, w]`.
//!
//! # Trigonometry
//!
//! [`sin_cos`] and [`tan`] (in `trig`) are within a few ulps at any angle,
//! with range reduction by Payne and Hanek; see that module for the method
//! and its bounds.
//!
//! # The same bits on every target
//!
//! Everything here uses only integer arithmetic and the basic IEEE
//! operations (`+ - * /`), which are correctly rounded on every target,
//! soft float included. Floats become integers through [`f32_to_i32`] and
//! its kin (in `cast`), which read the float's bits, never through a
//! platform's conversion routine (the RP2040's ROM rounds differently); Rust never contracts `a * b + c` into
//! a fused multiply-add, and no function of a platform's maths library is
//! called. So the set-up gives the same bits on the host, a Cortex-M0+
//! without an FPU and a Cortex-M4F with one. [`sqrt`] refines micromath's
//! estimate with Newton steps in basic operations.

mod cast;
mod divisor;
mod fixed_mat4;
mod mat4;
mod recip16;
pub(crate) mod soft_float;
mod trig;
mod wide;

pub use cast::{f32_to_i32, f32_to_i64, f32_to_u64, f32_to_u8};
pub(crate) use divisor::{shift_in_zeros, Divisor, WDivisor};
pub use fixed_mat4::FixedMat4;
pub(crate) use mat4::Inverse3;
pub use mat4::Mat4;
#[cfg(test)]
pub(crate) use recip16::leading_zeros_search;
#[cfg_attr(not(microraster_narrow_multiply), allow(unused_imports))]
pub(crate) use recip16::{leading_zeros, recip31, Recip16};
pub(crate) use soft_float::{times_pow2, SOFT_FLOAT};
pub use trig::{sin_cos, sqrt, tan};
pub(crate) use wide::{mul_wide, mul_wide_by_narrow, SPLIT};

/// A 3-component `f32` vector, used for per-frame set-up (camera, lights).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3 {
    /// x component.
    pub x: f32,
    /// y component.
    pub y: f32,
    /// z component.
    pub z: f32,
}

impl Vec3 {
    /// Creates a vector.
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z }
    }

    /// Dot product.
    pub fn dot(self, o: Self) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length.
    pub fn length(self) -> f32 {
        sqrt(self.dot(self))
    }

    /// The unit vector in the same direction, or `None` for a zero-length or
    /// non-finite vector.
    pub fn normalize(self) -> Option<Self> {
        let sq = self.dot(self);
        if sq.is_finite() && sq >= f32::MIN_POSITIVE {
            let len = sqrt(sq);
            return Some(Self::new(self.x / len, self.y / len, self.z / len));
        }
        // The squared length overflowed (a component above ~1.8e19) or
        // underflowed (all below ~1e-19), although the vector may well be
        // finite and non-zero: scale by the largest component first, which
        // is exact in direction, and normalise the result (length in
        // [1, sqrt(3)]). Vectors that took the path above are unchanged.
        if !self.is_finite() {
            return None;
        }
        let m = self.x.abs().max(self.y.abs()).max(self.z.abs());
        if m == 0.0 {
            return None;
        }
        let s = Self::new(self.x / m, self.y / m, self.z / m);
        let len = sqrt(s.dot(s));
        Some(Self::new(s.x / len, s.y / len, s.z / len))
    }

    /// Whether every component is finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl core::ops::Sub for Vec3 {
    type Output = Vec3;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

#[cfg(test)]
mod tests {
    use super::soft_float::ScaleDivisor;
    use super::trig::tests::ulps;
    use super::*;
    use fixed::types::I16F16;

    /// A random `f32` for the set-up's tests: often `±0`, `±1`, a
    /// subnormal, a huge or non-finite value, otherwise of any size.
    fn odd_f32(next: &mut impl FnMut(u64) -> u64) -> f32 {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            1e-40,
            -3e-39,
            3e38,
            f32::INFINITY,
            f32::NAN,
            0.5,
        ];
        match next(4) {
            0 => special[next(special.len() as u64) as usize],
            1 => f32::from_bits(next(1 << 32) as u32),
            _ => (next(2001) as f32 - 1000.0) / (1 + next(100)) as f32,
        }
    }

    /// The root of a positive finite `f32` is positive and finite (the
    /// light set-up tests the model scale's square so): every subnormal
    /// and the values of every binade, its ends and a stride within.
    #[test]
    fn sqrt_of_positive_finite_is_positive_finite() {
        let ok = |b: u32| {
            let y = sqrt(f32::from_bits(b));
            assert!(y.is_finite() && y > 0.0, "{b:#x} {y}");
        };
        (1..0x80_0000).step_by(7).for_each(ok);
        (1..0x7f80_0000u32).step_by(4099).for_each(ok);
        for e in 0..255u32 {
            for m in [0, 1, 2, 0x40_0000, 0x7f_fffe, 0x7f_ffff] {
                let b = e << 23 | m;
                if b != 0 {
                    ok(b);
                }
            }
        }
    }

    /// Where [`Inverse3::moderate`] holds, the 3x3 part's mean square is
    /// finite and positive: random matrices and the extremes of the range.
    #[test]
    fn moderate_inverse_has_a_finite_positive_square() {
        let square = |m: &Mat4| {
            let axis = |c: usize| Vec3::new(m.m[c][0], m.m[c][1], m.m[c][2]);
            (axis(0).dot(axis(0)) + axis(1).dot(axis(1)) + axis(2).dot(axis(2))) / 3.0
        };
        let mut next = crate::testing::rng();
        let top = f32::from_bits((62 + 127) << 23).next_down();
        let low = f32::from_bits((127 - 60) << 23);
        let mut moderate = 0;
        for i in 0..200_000 {
            let mut m = Mat4 {
                m: [[0.0; 4]; 4].map(|c| c.map(|_| odd_f32(&mut next))),
            };
            match i % 3 {
                0 => m = Mat4::scale(Vec3::new(top, -top, top)),
                1 => m.m[0][0] = [top, low, -top, -low][i % 4],
                _ => {}
            }
            if m.inverse3().is_some_and(|i| i.moderate()) {
                moderate += 1;
                let q = square(&m);
                assert!(q.is_finite() && q > 0.0, "{m:?}");
            }
        }
        assert!(moderate > 10_000, "{moderate}");
        // The ends: a scale of 2^62 is not moderate, one of 2^-61 neither.
        let s = |v: f32| Mat4::scale(Vec3::new(v, v, v)).inverse3().unwrap();
        assert!(s(top).moderate() && s(low).moderate());
        assert!(!s(top.next_up()).moderate() && !s(low.next_down()).moderate());
    }

    /// The product term by term (taken on soft-float cores and in these
    /// tests: [`SOFT_FLOAT`]) gives the full product's bits, zeros'
    /// signs included (NaNs compared as NaNs): matrices with many zeros
    /// and ones, tiny elements whose products round to zero, affine
    /// right-hand sides.
    #[test]
    fn product_by_terms_is_the_full_product() {
        let full = |a: &Mat4, b: &Mat4| {
            let mut out = [[0.0f32; 4]; 4];
            for (c, col) in out.iter_mut().enumerate() {
                for (r, o) in col.iter_mut().enumerate() {
                    *o = a.m[0][r] * b.m[c][0]
                        + a.m[1][r] * b.m[c][1]
                        + a.m[2][r] * b.m[c][2]
                        + a.m[3][r] * b.m[c][3];
                }
            }
            out
        };
        let mut next = crate::testing::rng();
        for i in 0..100_000 {
            let mut f = || match next(5) {
                // Zeros of both signs often, so that sums are zero.
                0 => [0.0, -0.0][next(2) as usize],
                1 => 1.0,
                // Products of two round to a zero of either sign.
                2 => [1e-30, -3e-25, 1e-20][next(3) as usize],
                _ => odd_f32(&mut next),
            };
            let a = Mat4 {
                m: [[0.0; 4]; 4].map(|c| c.map(|_| f())),
            };
            let mut b = Mat4 {
                m: [[0.0; 4]; 4].map(|c| c.map(|_| f())),
            };
            if i % 4 != 0 {
                (0..3).for_each(|c| b.m[c][3] = 0.0);
                b.m[3][3] = 1.0;
            }
            let (got, want) = ((a * b).m, full(&a, &b));
            for (g, w) in got.iter().flatten().zip(want.iter().flatten()) {
                assert!(
                    g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()),
                    "{a:?} {b:?}"
                );
            }
        }
    }

    /// Where [`Inverse3::moves_within_2_44`] holds, `apply(v - t)` is
    /// finite and within 2^44: random matrices, eyes and translations of
    /// any size, and moderate ones (where the bound mostly holds).
    #[test]
    fn bounded_move_is_finite_and_within_2_44() {
        let mut next = crate::testing::rng();
        let mut held = 0;
        for i in 0..300_000 {
            let mut f = || match i % 3 {
                0 => odd_f32(&mut next),
                // Within 2^±20 or so, any sign: the bound's usual case.
                _ => {
                    let e = next(41) as i32 - 20;
                    let m = 1.0 + next(1 << 23) as f32 / (1 << 23) as f32;
                    let v = m * f32::from_bits(((127 + e) as u32) << 23);
                    [v, -v][next(2) as usize]
                }
            };
            let m = Mat4 {
                m: [[0.0; 4]; 4].map(|c| c.map(|_| f())),
            };
            let (v, t) = (Vec3::new(f(), f(), f()), Vec3::new(f(), f(), f()));
            let Some(inverse) = m.inverse3() else {
                continue;
            };
            if inverse.moves_within_2_44(v, t) {
                held += 1;
                let out = inverse.apply(v - t);
                let fits = out.is_some_and(|o| {
                    [o.x, o.y, o.z]
                        .iter()
                        .all(|c| c.abs() <= (1u64 << 44) as f32)
                });
                assert!(fits, "{m:?} {v:?} {t:?}");
            }
        }
        assert!(held > 50_000, "{held}");
    }

    /// [`times_pow2`] is the product, bit for bit (NaNs as NaNs), for
    /// every scale an [`Inverse3`] takes and random or special values.
    #[test]
    fn times_pow2_is_the_product() {
        let mut next = crate::testing::rng();
        for i in 0..400_000u32 {
            let k = f32::from_bits((1 + i % 254) << 23);
            let x = match i % 2 {
                0 => odd_f32(&mut next),
                _ => f32::from_bits(next(1 << 32) as u32),
            };
            let (got, want) = (times_pow2(x, k), x * k);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{x:?} {k:?}"
            );
        }
    }

    /// A vector fails to normalize exactly when it is not finite or is
    /// zero (the light set-up tests a direction so).
    #[test]
    fn normalize_fails_only_on_zero_or_non_finite() {
        let mut next = crate::testing::rng();
        for _ in 0..200_000 {
            let v = Vec3::new(odd_f32(&mut next), odd_f32(&mut next), odd_f32(&mut next));
            let zero = v.x == 0.0 && v.y == 0.0 && v.z == 0.0;
            assert_eq!(v.normalize().is_none(), !v.is_finite() || zero, "{v:?}");
        }
    }

    /// `inverse_transform_vector` as it was before [`Mat4::inverse3`]
    /// (scaling all sixteen elements, `f32::max` over the nine).
    fn inverse_reference(m: &Mat4, v: Vec3) -> Option<Vec3> {
        let big = (0..3)
            .flat_map(|c| m.m[c][..3].iter())
            .fold(0.0f32, |b, x| b.max(x.abs()));
        if !big.is_finite() || big == 0.0 {
            return None;
        }
        let e = (((big.to_bits() >> 23) as i32).max(1) - 127).min(126);
        let k = f32::from_bits(((127 - e) as u32) << 23);
        let m = m.m.map(|c| c.map(|x| x * k));
        let r0 = Vec3::new(m[0][0], m[1][0], m[2][0]);
        let r1 = Vec3::new(m[0][1], m[1][1], m[2][1]);
        let r2 = Vec3::new(m[0][2], m[1][2], m[2][2]);
        let (c0, c1, c2) = (r1.cross(r2), r2.cross(r0), r0.cross(r1));
        let det = r0.dot(c0);
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        let inv = 1.0 / det;
        let out = Vec3::new(
            times_pow2((c0.x * v.x + c1.x * v.y + c2.x * v.z) * inv, k),
            times_pow2((c0.y * v.x + c1.y * v.y + c2.y * v.z) * inv, k),
            times_pow2((c0.z * v.x + c1.z * v.y + c2.z * v.z) * inv, k),
        );
        out.is_finite().then_some(out)
    }

    /// The integer division by a shared divisor gives `/`'s bits: random
    /// divisors and dividends of any bits, quotients near 1 (both
    /// significands close) and the divisors of the extreme significands.
    #[test]
    fn scale_divisor_is_division() {
        let mut next = crate::testing::rng();
        let same = |d: f32, v: f32| {
            let (got, want) = (ScaleDivisor::new(d).div(v), v / d);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{v:e} / {d:e}: {got:e}, not {want:e}"
            );
        };
        for _ in 0..300_000 {
            let d = f32::from_bits(next(0x7f00_0000) as u32 + 0x80_0000);
            same(d, f32::from_bits(next(1 << 32) as u32));
            // The same exponent, nearby significands, either sign.
            let near = (d.to_bits() as i64 + next(64) as i64 - 32) as u32;
            same(d, f32::from_bits(near | (next(2) as u32) << 31));
            same(d, odd_f32(&mut next));
        }
        for d in [
            1.0f32,
            f32::from_bits(0x3fff_ffff),
            1.5,
            f32::from_bits(27 << 23),
        ] {
            for k in 0..100_000u32 {
                same(d, f32::from_bits(0x3f00_0000 + k * 167));
                same(d, f32::from_bits(0x3f80_0000 - k));
            }
        }
    }

    /// The inverse made once gives the reference's bits, and the largest
    /// element by the bits is `f32::max`'s.
    #[test]
    fn inverse3_and_normal_scale_are_the_references() {
        let mut next = crate::testing::rng();
        let bits = |v: Option<Vec3>| v.map(|v| [v.x, v.y, v.z].map(f32::to_bits));
        for _ in 0..200_000 {
            let m = Mat4 {
                m: [[0.0; 4]; 4].map(|c| c.map(|_| odd_f32(&mut next))),
            };
            let v = Vec3::new(odd_f32(&mut next), odd_f32(&mut next), odd_f32(&mut next));
            assert_eq!(
                bits(m.inverse_transform_vector(v)),
                bits(inverse_reference(&m, v)),
                "{m:?} {v:?}"
            );
            let scale = m
                .is_finite()
                .then(|| m.m.iter().flatten().fold(0.0f32, |b, v| b.max(v.abs())));
            let scale = scale.filter(|&b| b >= f32::from_bits(27 << 23));
            assert_eq!(
                m.normal_scale().map(f32::to_bits),
                scale.map(f32::to_bits),
                "{m:?}"
            );
        }
    }

    #[test]
    fn perspective_maps_near_and_far_to_clip_bounds() {
        let p = Mat4::perspective(1.0, 1.0, 1.0, 10.0).unwrap();
        // A point on the near plane: z_eye = -1 -> z_clip = -w.
        let zc = -p.m[2][2] + p.m[3][2];
        let wc = -p.m[2][3];
        assert!((zc + wc).abs() < 1e-6);
        let zc = p.m[2][2] * -10.0 + p.m[3][2];
        let wc = p.m[2][3] * -10.0;
        assert!((zc - wc).abs() < 1e-4);
    }

    #[test]
    fn bad_projection_parameters_are_rejected() {
        assert!(Mat4::perspective(f32::NAN, 1.0, 1.0, 2.0).is_none());
        assert!(Mat4::perspective(1.0, 1.0, 0.0, 2.0).is_none());
        assert!(Mat4::perspective(1.0, 1.0, 2.0, 2.0).is_none());
        assert!(Mat4::perspective(4.0, 1.0, 1.0, 2.0).is_none());
        assert!(Mat4::orthographic(0.0, 0.0, 0.0, 1.0, 0.0, 1.0).is_none());
        assert!(
            Mat4::look_at(Vec3::default(), Vec3::default(), Vec3::new(0.0, 1.0, 0.0)).is_none()
        );
    }

    /// The 3x3 part of a rotation: its columns have unit length and are
    /// orthogonal to `f32` precision, and its elements are the exact sine
    /// and cosine, at any angle; huge angles included (micromath's
    /// `rotation_y(1e7)` had m00 = -0.708 and m02 = -1, and `1e8` gave
    /// zeros).
    #[test]
    fn rotations_are_orthonormal_at_any_angle() {
        let mut next = crate::testing::rng();
        let angles = (0..20_000)
            .map(|_| f32::from_bits(next(0x7f80_0000) as u32))
            .chain([0.7f32, 1e7, 1e8, 3e9, 1e30, f32::MAX])
            .flat_map(|a| [a, -a]);
        for a in angles {
            let (es, ec) = ((a as f64).sin(), (a as f64).cos());
            for (axis, m) in [
                (0, Mat4::rotation_x(a)),
                (1, Mat4::rotation_y(a)),
                (2, Mat4::rotation_z(a)),
            ] {
                let col = |c: usize| [0, 1, 2].map(|r| m.m[c][r] as f64);
                for i in 0..3 {
                    for j in 0..3 {
                        let (ci, cj) = (col(i), col(j));
                        let dot: f64 = (0..3).map(|k| ci[k] * cj[k]).sum();
                        let want = if i == j { 1.0 } else { 0.0 };
                        // Within 2 2^-24: sine and cosine within 1 ulp each.
                        assert!((dot - want).abs() < 1.2e-7, "axis {axis}, {a:e}: {m:?}");
                    }
                }
                // The cosine on the diagonal, the sine off it.
                let (c, s) = match axis {
                    0 => (m.m[1][1], m.m[1][2]),
                    1 => (m.m[0][0], m.m[2][0]),
                    _ => (m.m[0][0], m.m[0][1]),
                };
                assert!(ulps(c, ec) < 1.0 && ulps(s, es) < 1.0, "axis {axis}, {a:e}");
            }
        }
        let m = Mat4::rotation_y(1e8);
        assert!((m.m[0][0] as f64 - 1e8f64.cos()).abs() < 1e-7);
        assert!((m.m[2][0] as f64 - 1e8f64.sin()).abs() < 1e-7);
    }

    /// The focal length `1 / tan(fovy / 2)` of a perspective projection is
    /// within 3 ulps for every field of view (micromath's tangent made the
    /// picture 0.19 % too large at 45°).
    #[test]
    fn perspective_focal_length_is_accurate() {
        let quarter = core::f32::consts::FRAC_PI_4;
        let f = Mat4::perspective(quarter, 1.0, 1.0, 10.0).unwrap().m[1][1];
        // 1 / tan of the f32 nearest π/8 is 2.41421349 (1 + √2 = 2.41421356).
        assert!(ulps(f, 2.414_213_487_753) <= 2.5, "{f}");
        for k in 1..10_000 {
            let fovy = k as f32 * (core::f32::consts::PI / 10_000.0);
            let Some(p) = Mat4::perspective(fovy, 1.5, 0.1, 100.0) else {
                panic!("fovy {fovy}");
            };
            let exact = 1.0 / (fovy as f64 * 0.5).tan();
            assert!(ulps(p.m[1][1], exact) <= 2.5, "fovy {fovy}: {}", p.m[1][1]);
            assert!(
                ulps(p.m[0][0], exact / 1.5) <= 3.0,
                "fovy {fovy}: {}",
                p.m[0][0]
            );
        }
    }

    /// A perspective with its planes scaled by a power of two is the same
    /// matrix up to that scale in its last column, exactly, from 2^-100 to
    /// 2^100 (`far near` underflowed below about 2^-63 and overflowed
    /// above 2^61).
    #[test]
    fn perspective_is_the_same_in_any_units() {
        let base = Mat4::perspective(0.9, 1.3, 0.5, 20.0).unwrap();
        for e in -100..=100 {
            let k = 2f32.powi(e);
            let p = Mat4::perspective(0.9, 1.3, 0.5 * k, 20.0 * k).unwrap();
            assert_eq!(p.m[..3], base.m[..3], "2^{e}");
            assert_eq!(p.m[3][2], base.m[3][2] * k, "2^{e}");
        }
    }

    /// The inverse of a model matrix in any units: exact powers of two of
    /// the unit one (the determinant of a 2^-50 scale underflowed).
    #[test]
    fn inverse_transform_works_in_any_units() {
        let r = Mat4::rotation_y(0.7) * Mat4::rotation_x(-0.3);
        let v = Vec3::new(0.3, -0.5, 0.8);
        let unit = r.inverse_transform_vector(v).unwrap();
        for e in -120..=120 {
            let k = 2f32.powi(e);
            let m = Mat4::scale(Vec3::new(k, k, k)) * r;
            let back = m.inverse_transform_vector(v).unwrap();
            assert_eq!(back, Vec3::new(unit.x / k, unit.y / k, unit.z / k), "2^{e}");
        }
        assert_eq!(
            Mat4::scale(Vec3::new(0.0, 1.0, 1.0)).inverse_transform_vector(v),
            None
        );
    }

    /// The fixed-point matrix of the vertex stage does not depend on the
    /// units: a scene scaled with its camera gives the same 16.16 matrix
    /// (exactly for powers of two; for other factors up to the `f32`
    /// rounding of the set-up, here none), where the plain conversion
    /// lost every bit at 3e-5.
    #[test]
    fn normalized_fixed_matrix_is_the_same_in_any_units() {
        let mvp = |s: f32| {
            let eye = Vec3::new(1.2 * s, 1.0 * s, 2.5 * s);
            let view = Mat4::look_at(eye, Vec3::default(), Vec3::new(0.0, 1.0, 0.0)).unwrap();
            let proj = Mat4::perspective(0.9, 4.0 / 3.0, 0.5 * s, 20.0 * s).unwrap();
            proj * view * Mat4::scale(Vec3::new(s, s, s)) * Mat4::rotation_y(0.6)
        };
        let unit = mvp(1.0).to_fixed_normalized().unwrap();
        for e in -70..=60 {
            let m = mvp(2f32.powi(e));
            assert_eq!(m.to_fixed_normalized(), Some(unit), "2^{e}");
        }
        for s in [3e-5f32, 1e-3, 1e-4, 1e-6, 1e4] {
            let m = mvp(s).to_fixed_normalized().unwrap();
            let most = (0..4)
                .flat_map(|c| (0..4).map(move |r| (c, r)))
                .map(|(c, r)| (m.m[c][r] - unit.m[c][r]).abs())
                .max();
            assert!(most <= Some(1), "{s}: {m:?} against {unit:?}");
        }
        assert_eq!(
            mvp(3e-5).to_fixed().map(|f| f.m[0][0].abs() < 4),
            Some(true)
        );
        // What no units can represent: zero, and a row lost beside the rest.
        assert_eq!(Mat4 { m: [[0.0; 4]; 4] }.to_fixed_normalized(), None);
        assert_eq!(
            Mat4::scale(Vec3::new(1.0, 1e-6, 1.0)).to_fixed_normalized(),
            None
        );
        assert!(Mat4::scale(Vec3::new(1.0, 1e-4, 1.0))
            .to_fixed_normalized()
            .is_some());
        let nan = Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0));
        assert_eq!(nan.to_fixed_normalized(), None);
    }

    #[test]
    fn inverse_transform_undoes_transform() {
        let m =
            Mat4::rotation_y(0.7) * Mat4::rotation_x(-0.3) * Mat4::scale(Vec3::new(2.0, 2.0, 2.0));
        let v = Vec3::new(0.3, -0.5, 0.8);
        let back = m.inverse_transform_vector(m.transform_vector(v)).unwrap();
        assert!(
            (back.x - v.x).abs() < 1e-5
                && (back.y - v.y).abs() < 1e-5
                && (back.z - v.z).abs() < 1e-5
        );
    }

    #[test]
    fn normalize_handles_huge_and_tiny_vectors() {
        let unit = Vec3::new(0.5, -0.25, 1.0).normalize().unwrap();
        for k in [1e30f32, 3e38, 1e-30, 1e-37] {
            let v = Vec3::new(0.5 * k, -0.25 * k, k).normalize();
            assert_eq!(v, Some(unit), "{k}");
        }
        assert_eq!(
            Vec3::new(f32::MAX, 0.0, 0.0).normalize(),
            Some(Vec3::new(1.0, 0.0, 0.0))
        );
        let tiny = f32::from_bits(1); // the smallest subnormal
        assert_eq!(
            Vec3::new(0.0, -tiny, 0.0).normalize(),
            Some(Vec3::new(0.0, -1.0, 0.0))
        );
        assert_eq!(Vec3::new(0.0, 0.0, 0.0).normalize(), None);
        assert_eq!(Vec3::new(f32::NAN, 0.0, 1.0).normalize(), None);
        assert_eq!(Vec3::new(0.0, f32::INFINITY, 0.0).normalize(), None);
    }

    #[test]
    fn fixed_transform_sum_overflow_is_reported() {
        // Three products of about 2^62 each: the exact sum leaves i64.
        let m = FixedMat4 {
            m: [
                [-0x7fff_0000; 4],
                [-0x7fff_0000; 4],
                [-0x7fff_0000; 4],
                [0, 0, 0, 1 << 16],
            ],
        };
        let p = -0x7fff_0000;
        assert_eq!(m.transform_point([p, p, p]), None);
        assert_eq!(m.transform_point([-p, -p, -p]), None);
        assert_eq!(m.transform_point([0, 0, 0]), Some([0, 0, 0, 1 << 16]));
    }

    #[test]
    fn fixed_transform_overflow_is_reported() {
        let m = Mat4::scale(Vec3::new(1000.0, 1.0, 1.0)).to_fixed().unwrap();
        let big = I16F16::from_num(1000).to_bits();
        assert!(m.transform_point([big, 0, 0]).is_none());
        assert!(Mat4::scale(Vec3::new(f32::INFINITY, 1.0, 1.0))
            .to_fixed()
            .is_none());
    }

    /// The narrow transform is the bounded one wherever it is taken:
    /// random matrices with elements within ±2^16 (the translation any),
    /// points within extents up to 2^21, their extremes among them.
    #[test]
    fn narrow_transform_matches_the_bounded_one() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        for _ in 0..20_000 {
            let e = |next: &mut dyn FnMut(u64) -> u64| {
                let bits = next(18);
                (next(2 << bits) as i64 - (1 << bits)).clamp(-(1 << 16), 1 << 16) as i32
            };
            let mut m = FixedMat4 { m: [[0; 4]; 4] };
            for c in 0..3 {
                for r in 0..4 {
                    m.m[c][r] = e(&mut next);
                }
            }
            for r in 0..4 {
                m.m[3][r] = next(1 << 32) as u32 as i32 >> next(32);
            }
            let extent = match next(4) {
                0 => 1 << 21,
                _ => (next(1 << 21) + 1) as u32,
            };
            if !(m.bounded(extent) && m.narrow(extent)) {
                continue;
            }
            taken += 1;
            let x = extent as i64;
            for k in 0..16 {
                let mut c = || match k {
                    0 => x,
                    1 => -x,
                    _ => next(2 * x as u64 + 1) as i64 - x,
                } as i32;
                let p = [c(), c(), c()];
                assert_eq!(
                    m.transform_point_narrow(p),
                    m.transform_point_bounded(p),
                    "{m:?} {p:?}"
                );
            }
        }
        assert!(taken > 1_000, "{taken}");
        let full = FixedMat4 {
            m: [[1 << 16; 4]; 4],
        };
        assert!(full.narrow(1 << 21) && !full.narrow((1 << 21) + 1));
        let mut wide = full;
        wide.m[2][3] = (1 << 16) + 1;
        assert!(!wide.narrow(1));
    }

    #[test]
    fn bounded_transform_matches_the_checked_one() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut bounded = 0;
        for _ in 0..20_000 {
            let mut e =
                || (next() >> (32 + next() % 32)) as i32 * if next() % 2 == 0 { 1 } else { -1 };
            let m = FixedMat4 {
                m: [
                    [e(), e(), e(), e()],
                    [e(), e(), e(), e()],
                    [e(), e(), e(), e()],
                    [e(), e(), e(), e()],
                ],
            };
            let extent = (next() >> (33 + next() % 31)) as u32;
            if !m.bounded(extent) {
                continue;
            }
            bounded += 1;
            for _ in 0..8 {
                let mut c = || (next() % (2 * extent as u64 + 1)) as i64 - extent as i64;
                let p = [c() as i32, c() as i32, c() as i32];
                assert_eq!(
                    Some(m.transform_point_bounded(p)),
                    m.transform_point(p),
                    "{m:?} {p:?}"
                );
            }
        }
        assert!(bounded > 1_000, "{bounded}");
    }
}
