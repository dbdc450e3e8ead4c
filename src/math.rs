//! Per-frame set-up math in `f32`, and its hand-over to 16.16 fixed point.
//!
//! Matrices are built once per frame (or per draw) in `f32`, with
//! [`micromath`] for the trigonometry, so they cost nothing per vertex. The
//! vertex stage never sees a float: [`Mat4::to_fixed`] converts a matrix to
//! [`FixedMat4`], whose elements are [`I16F16`], and every per-vertex product
//! goes through `i64`.
//!
//! Conventions follow OpenGL: column vectors, right-handed eye space looking
//! down -z, clip-space x, y, z in `[-w, w]`. Only the basic IEEE operations
//! and micromath's pure-`f32` routines are used, so the same inputs give the
//! same bits on every target; all trigonometry is called through
//! [`micromath::F32Ext`] explicitly so a host build never silently picks up
//! `std`'s different implementation.

use core::num::NonZeroU64;
use fixed::types::I16F16;
use micromath::F32Ext;

/// Square root to full `f32` precision: micromath's bit-trick estimate
/// (about 5 % off) refined by three Newton steps. Only basic IEEE
/// operations, so it gives the same bits on every target.
pub fn sqrt(x: f32) -> f32 {
    if x.is_nan() || x < 0.0 {
        return f32::NAN;
    }
    if x == 0.0 || x == f32::INFINITY {
        return x;
    }
    let mut y = F32Ext::sqrt(x);
    for _ in 0..3 {
        y = 0.5 * (y + x / y);
    }
    y
}

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

/// A 4x4 `f32` matrix, column-major (`m[column][row]`), acting on column
/// vectors as in OpenGL.
///
/// ```
/// use microraster::math::{Mat4, Vec3};
/// let view = Mat4::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::default(), Vec3::new(0.0, 1.0, 0.0)).unwrap();
/// let proj = Mat4::perspective(1.0, 4.0 / 3.0, 0.5, 10.0).unwrap();
/// let view_proj = proj * view;
/// assert!(view_proj.is_finite());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat4 {
    /// Columns; `m[c][r]` is row `r` of column `c`.
    pub m: [[f32; 4]; 4],
}

impl Default for Mat4 {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Mat4 {
    /// The identity matrix.
    pub const IDENTITY: Self = Self {
        m: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
    };

    /// A translation.
    pub fn translation(t: Vec3) -> Self {
        let mut r = Self::IDENTITY;
        r.m[3] = [t.x, t.y, t.z, 1.0];
        r
    }

    /// A uniform or non-uniform scale.
    pub fn scale(s: Vec3) -> Self {
        let mut r = Self::IDENTITY;
        r.m[0][0] = s.x;
        r.m[1][1] = s.y;
        r.m[2][2] = s.z;
        r
    }

    /// A rotation of `angle` radians about the x axis.
    pub fn rotation_x(angle: f32) -> Self {
        let (s, c) = (F32Ext::sin(angle), F32Ext::cos(angle));
        let mut r = Self::IDENTITY;
        r.m[1] = [0.0, c, s, 0.0];
        r.m[2] = [0.0, -s, c, 0.0];
        r
    }

    /// A rotation of `angle` radians about the y axis.
    pub fn rotation_y(angle: f32) -> Self {
        let (s, c) = (F32Ext::sin(angle), F32Ext::cos(angle));
        let mut r = Self::IDENTITY;
        r.m[0] = [c, 0.0, -s, 0.0];
        r.m[2] = [s, 0.0, c, 0.0];
        r
    }

    /// A rotation of `angle` radians about the z axis.
    pub fn rotation_z(angle: f32) -> Self {
        let (s, c) = (F32Ext::sin(angle), F32Ext::cos(angle));
        let mut r = Self::IDENTITY;
        r.m[0] = [c, s, 0.0, 0.0];
        r.m[1] = [-s, c, 0.0, 0.0];
        r
    }

    /// An OpenGL perspective projection: vertical field of view `fovy`
    /// (radians), `aspect` = width / height, and positive `near` < `far`.
    ///
    /// Returns `None` for parameters that give no usable matrix (non-finite,
    /// `near <= 0`, `far <= near`, `fovy` outside `(0, π)`, `aspect <= 0`).
    pub fn perspective(fovy: f32, aspect: f32, near: f32, far: f32) -> Option<Self> {
        let ok = [fovy, aspect, near, far].iter().all(|v| v.is_finite())
            && fovy > 0.0
            && fovy < core::f32::consts::PI
            && aspect > 0.0
            && near > 0.0
            && far > near;
        if !ok {
            return None;
        }
        let f = 1.0 / F32Ext::tan(fovy * 0.5);
        let nf = 1.0 / (near - far);
        let r = Self {
            m: [
                [f / aspect, 0.0, 0.0, 0.0],
                [0.0, f, 0.0, 0.0],
                [0.0, 0.0, (far + near) * nf, -1.0],
                [0.0, 0.0, 2.0 * far * near * nf, 0.0],
            ],
        };
        r.is_finite().then_some(r)
    }

    /// An OpenGL orthographic projection of the box `[left, right] x
    /// [bottom, top] x [-near, -far]` in eye space.
    ///
    /// Returns `None` when a pair of bounds is equal or a value is not finite.
    pub fn orthographic(
        left: f32,
        right: f32,
        bottom: f32,
        top: f32,
        near: f32,
        far: f32,
    ) -> Option<Self> {
        if ![left, right, bottom, top, near, far]
            .iter()
            .all(|v| v.is_finite())
            || left == right
            || bottom == top
            || near == far
        {
            return None;
        }
        let (rl, tb, fneg) = (right - left, top - bottom, far - near);
        let r = Self {
            m: [
                [2.0 / rl, 0.0, 0.0, 0.0],
                [0.0, 2.0 / tb, 0.0, 0.0],
                [0.0, 0.0, -2.0 / fneg, 0.0],
                [
                    -(right + left) / rl,
                    -(top + bottom) / tb,
                    -(far + near) / fneg,
                    1.0,
                ],
            ],
        };
        r.is_finite().then_some(r)
    }

    /// A right-handed view matrix looking from `eye` at `target`.
    ///
    /// Returns `None` when `eye == target`, `up` is parallel to the view
    /// direction, or a value is not finite.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Self> {
        let f = (target - eye).normalize()?;
        let s = f.cross(up).normalize()?;
        let u = s.cross(f);
        let r = Self {
            m: [
                [s.x, u.x, -f.x, 0.0],
                [s.y, u.y, -f.y, 0.0],
                [s.z, u.z, -f.z, 0.0],
                [-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0],
            ],
        };
        r.is_finite().then_some(r)
    }

    /// Whether every element is finite.
    pub fn is_finite(&self) -> bool {
        self.m.iter().flatten().all(|v| v.is_finite())
    }

    /// Applies the upper 3x3 part to a direction (no translation).
    pub fn transform_vector(&self, v: Vec3) -> Vec3 {
        let m = &self.m;
        Vec3::new(
            m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
            m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z,
        )
    }

    /// The transpose of the inverse of the upper 3x3 part applied to `v`,
    /// i.e. `M⁻¹ v` computed through the adjugate; `None` when singular.
    ///
    /// Lighting uses it to move a world-space light direction into model
    /// space once per draw, so no per-vertex normal matrix is needed.
    pub fn inverse_transform_vector(&self, v: Vec3) -> Option<Vec3> {
        let m = &self.m;
        // Rows of the 3x3 part.
        let r0 = Vec3::new(m[0][0], m[1][0], m[2][0]);
        let r1 = Vec3::new(m[0][1], m[1][1], m[2][1]);
        let r2 = Vec3::new(m[0][2], m[1][2], m[2][2]);
        // Columns of the inverse are cross products of rows / det.
        let c0 = r1.cross(r2);
        let c1 = r2.cross(r0);
        let c2 = r0.cross(r1);
        let det = r0.dot(c0);
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        let inv = 1.0 / det;
        let out = Vec3::new(
            (c0.x * v.x + c1.x * v.y + c2.x * v.z) * inv,
            (c0.y * v.x + c1.y * v.y + c2.y * v.z) * inv,
            (c0.z * v.x + c1.z * v.y + c2.z * v.z) * inv,
        );
        out.is_finite().then_some(out)
    }

    /// Converts to 16.16 fixed point, rounding to nearest.
    ///
    /// Returns `None` when an element is not finite or lies outside the
    /// `I16F16` range (±32768).
    pub fn to_fixed(&self) -> Option<FixedMat4> {
        let mut out = [[0i32; 4]; 4];
        for (c, col) in self.m.iter().enumerate() {
            for (r, &v) in col.iter().enumerate() {
                out[c][r] = I16F16::checked_from_num(v)?.to_bits();
            }
        }
        Some(FixedMat4 { m: out })
    }
}

impl core::ops::Mul for Mat4 {
    type Output = Mat4;
    fn mul(self, rhs: Mat4) -> Mat4 {
        let mut out = [[0.0f32; 4]; 4];
        for (c, out_col) in out.iter_mut().enumerate() {
            for (r, o) in out_col.iter_mut().enumerate() {
                *o = self.m[0][r] * rhs.m[c][0]
                    + self.m[1][r] * rhs.m[c][1]
                    + self.m[2][r] * rhs.m[c][2]
                    + self.m[3][r] * rhs.m[c][3];
            }
        }
        Mat4 { m: out }
    }
}

/// A 4x4 matrix in 16.16 fixed point (raw `I16F16` bits), column-major.
///
/// Produced by [`Mat4::to_fixed`]; applied per vertex with `i64`
/// accumulation, so a core without an FPU does no soft-float per vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FixedMat4 {
    /// Columns of raw 16.16 values; `m[c][r]`.
    pub m: [[i32; 4]; 4],
}

impl FixedMat4 {
    /// Transforms the point `(p, 1)` (raw 16.16 components) to homogeneous
    /// coordinates, each the exact `i64` sum of products rounded once to
    /// 16.16. Returns `None` if a result leaves the `I16F16` range.
    #[inline]
    pub fn transform_point(&self, p: [i32; 3]) -> Option<[i32; 4]> {
        let m = &self.m;
        let mut out = [0i32; 4];
        for (r, o) in out.iter_mut().enumerate() {
            // Each product is below 2^62 in magnitude, but three of them
            // can leave i64 (all elements and coordinates near +-32768),
            // which panicked in debug builds and wrapped to a wrong vertex
            // in release. A partial sum that overflows is more than 2^61
            // away from zero whatever the remaining terms (each below 2^62,
            // the translation below 2^47), far outside 16.16: `None`.
            let acc = (m[0][r] as i64 * p[0] as i64)
                .checked_add(m[1][r] as i64 * p[1] as i64)?
                .checked_add(m[2][r] as i64 * p[2] as i64)?
                .checked_add((m[3][r] as i64) << 16)?;
            *o = i32::try_from(acc.checked_add(1 << 15)? >> 16).ok()?;
        }
        Some(out)
    }

    /// Whether [`transform_point_bounded`](Self::transform_point_bounded)
    /// is exact for every point whose coordinates are at most `extent` in
    /// magnitude: when every row's sum of products, its translation and the
    /// rounding stay below 2^47, no partial sum can leave `i64` and the
    /// rounded result always fits `i32`, so neither needs checking.
    pub fn bounded(&self, extent: u32) -> bool {
        (0..4).all(|r| {
            let sum: u64 = (0..3)
                .map(|c| self.m[c][r].unsigned_abs() as u64 * extent as u64)
                .sum::<u64>()
                + ((self.m[3][r].unsigned_abs() as u64) << 16)
                + (1 << 15);
            sum < 1 << 47
        })
    }

    /// The `w` row of [`transform_point_bounded`](Self::transform_point_bounded),
    /// in wrapping arithmetic: equal to `transform_point`'s `w` whenever
    /// that succeeded.
    #[inline(always)]
    pub fn transform_w_unchecked(&self, p: [i32; 3]) -> i32 {
        let m = &self.m;
        let acc = (m[0][3] as i64 * p[0] as i64)
            .wrapping_add(m[1][3] as i64 * p[1] as i64)
            .wrapping_add(m[2][3] as i64 * p[2] as i64)
            .wrapping_add((m[3][3] as i64) << 16);
        (acc.wrapping_add(1 << 15) >> 16) as i32
    }

    /// [`transform_point`](Self::transform_point) without its overflow
    /// checks, for a matrix that is [`bounded`](Self::bounded) for the
    /// point's extent; then it gives the same result (the sums are exact,
    /// the result in range).
    #[inline(always)]
    pub fn transform_point_bounded(&self, p: [i32; 3]) -> [i32; 4] {
        let m = &self.m;
        let mut out = [0i32; 4];
        for (r, o) in out.iter_mut().enumerate() {
            // Within the bound nothing wraps; wrapping arithmetic only
            // spares the checks.
            let acc = (m[0][r] as i64 * p[0] as i64)
                .wrapping_add(m[1][r] as i64 * p[1] as i64)
                .wrapping_add(m[2][r] as i64 * p[2] as i64)
                .wrapping_add((m[3][r] as i64) << 16);
            *o = (acc.wrapping_add(1 << 15) >> 16) as i32;
        }
        out
    }
}

/// Exact integer division of many dividends by one divisor, through the
/// divisor's reciprocal: one 64-bit division up front, then per quotient a
/// multiply-high and one correction.
///
/// A 64-bit division is a slow library call on a 32-bit core (and the
/// Cortex-M0+ has no divider at all), while the 64 x 64 -> 128-bit
/// multiply-high is a handful of `umull`s. The quotients are exactly those
/// of the division: `r = floor((2^64 - 1) / d)` undershoots `2^64 / d` by
/// less than 2, so for `m < 2^63` the estimate `floor(m r / 2^64)`
/// undershoots `m / d` by less than 1 and is `floor(m / d)` or one less,
/// which the remainder test corrects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
pub(crate) struct Reciprocal {
    d: u64,
    r: u64,
}

#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
impl Reciprocal {
    /// The reciprocal of `d`.
    #[inline(always)]
    pub(crate) fn new(d: NonZeroU64) -> Self {
        Self {
            d: d.get(),
            r: u64::MAX / d,
        }
    }

    /// `floor(m / d)`, for `m < 2^63`.
    #[inline(always)]
    pub(crate) fn div(&self, m: u64) -> u64 {
        debug_assert!(m < 1 << 63);
        let q = ((m as u128 * self.r as u128) >> 64) as u64;
        // q <= floor(m / d), so q d <= m and the remainder cannot wrap.
        let rem = m - q * self.d;
        q + (rem >= self.d) as u64
    }
}

/// A divisor used for many dividends, divided by as a 64-bit CPU does best:
/// with its division instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
pub(crate) struct Hardware(NonZeroU64);

#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
impl Hardware {
    /// The divisor `d`.
    #[inline(always)]
    pub(crate) fn new(d: NonZeroU64) -> Self {
        Self(d)
    }

    /// `floor(m / d)`.
    #[inline(always)]
    pub(crate) fn div(&self, m: u64) -> u64 {
        m / self.0
    }
}

/// The divisor the attribute set-up uses: [`Reciprocal`] where a 64-bit
/// division is a library call (32-bit targets: every Cortex-M, RISC-V
/// `rv32`), the division instruction on 64-bit targets, where one
/// instruction beats a multiply-high and a correction. Both give the same
/// quotients, so images do not depend on the choice.
#[cfg(not(target_pointer_width = "64"))]
pub(crate) type Divisor = Reciprocal;
/// See the 32-bit definition.
#[cfg(target_pointer_width = "64")]
pub(crate) type Divisor = Hardware;

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn sqrt_is_accurate() {
        for &x in &[1e-6f32, 0.01, 0.5, 1.0, 2.0, 3.0, 10.0, 12345.0, 1e9] {
            let r = sqrt(x);
            assert!((r * r - x).abs() <= x * 1e-6, "{x}: {r}");
        }
        assert_eq!(sqrt(0.0), 0.0);
        assert!(sqrt(-1.0).is_nan());
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

    #[test]
    fn reciprocal_division_is_exact() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let divisors = [
            1u64,
            2,
            3,
            7,
            255,
            65_535,
            1 << 20,
            (1 << 39) - 1,
            1 << 39,
            (1 << 62) + 12_345,
        ];
        for &d in &divisors {
            let r = Reciprocal::new(NonZeroU64::new(d).unwrap());
            for m in [0u64, 1, d - 1, d, d + 1, (1 << 63) - 1, (1 << 63) - d] {
                assert_eq!(r.div(m), m / d, "{m} / {d}");
            }
        }
        for _ in 0..200_000 {
            let d = next() >> (next() % 64);
            let Some(nz) = NonZeroU64::new(d) else {
                continue;
            };
            let (r, h) = (Reciprocal::new(nz), Hardware::new(nz));
            for _ in 0..4 {
                let m = next() >> (1 + next() % 63);
                assert_eq!(r.div(m), m / d, "{m} / {d}");
                assert_eq!(h.div(m), m / d, "{m} / {d}");
            }
        }
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
