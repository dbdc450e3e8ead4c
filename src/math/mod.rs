//! Per-frame set-up math in `f32`, and its hand-over to 16.16 fixed point.
//!
//! Matrices are built once per frame (or per draw) in `f32`, so they cost
//! nothing per vertex. The vertex stage never sees a float:
//! [`Mat4::to_fixed`] converts a matrix to [`FixedMat4`], whose elements are
//! [`I16F16`], and every per-vertex product goes through `i64`.
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
mod recip16;
mod trig;
mod wide;

pub use cast::{f32_to_i32, f32_to_i64, f32_to_u64, f32_to_u8};
pub(crate) use divisor::{shift_in_zeros, Divisor, WDivisor};
pub use fixed_mat4::FixedMat4;
#[cfg(test)]
pub(crate) use recip16::leading_zeros_search;
#[cfg_attr(not(microraster_narrow_multiply), allow(unused_imports))]
pub(crate) use recip16::{leading_zeros, recip31, Recip16};
pub use trig::{sin_cos, sqrt, tan};
pub(crate) use wide::{mul_wide, SPLIT};

use fixed::types::I16F16;

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
        let (s, c) = sin_cos(angle);
        let mut r = Self::IDENTITY;
        r.m[1] = [0.0, c, s, 0.0];
        r.m[2] = [0.0, -s, c, 0.0];
        r
    }

    /// A rotation of `angle` radians about the y axis.
    pub fn rotation_y(angle: f32) -> Self {
        let (s, c) = sin_cos(angle);
        let mut r = Self::IDENTITY;
        r.m[0] = [c, 0.0, -s, 0.0];
        r.m[2] = [s, 0.0, c, 0.0];
        r
    }

    /// A rotation of `angle` radians about the z axis.
    pub fn rotation_z(angle: f32) -> Self {
        let (s, c) = sin_cos(angle);
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
        // cot(fovy / 2) from one sine and cosine (within 3 ulps).
        let (s, c) = sin_cos(fovy * 0.5);
        let f = c / s;
        let nf = 1.0 / (near - far);
        // 2 far near / (near - far) as 2 far (near / (near - far)): the
        // product far near underflows f32 for planes below about 1e-19 (and
        // overflows above 1e19) where the ratio is still exact, so the
        // projection of a scene scaled to any units is the same up to its
        // scale.
        let r = Self {
            m: [
                [f / aspect, 0.0, 0.0, 0.0],
                [0.0, f, 0.0, 0.0],
                [0.0, 0.0, (far + near) * nf, -1.0],
                [0.0, 0.0, 2.0 * far * (near * nf), 0.0],
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
    ///
    /// The 3x3 part is first scaled by a power of two that brings its
    /// largest element into `[1, 2)`, and the result by the same power:
    /// exact, so the result is what the plain computation gives wherever
    /// that neither underflows nor overflows, and a model matrix in any
    /// units (a scale of 1e-20 has a determinant of 1e-60) still inverts.
    pub fn inverse_transform_vector(&self, v: Vec3) -> Option<Vec3> {
        self.inverse3()?.apply(v)
    }

    /// The part of [`inverse_transform_vector`](Self::inverse_transform_vector)
    /// that does not depend on the vector: the scaled 3x3 part's adjugate,
    /// its determinant's reciprocal and the scale; `None` when singular
    /// (or not finite). A draw's light set-up moves the eye and every
    /// light by one (two `M⁻¹` products took the Cortex-M3 about 4,000
    /// instructions each).
    pub(crate) fn inverse3(&self) -> Option<Inverse3> {
        // The largest magnitude by the bits: for finite elements the
        // order of `|x|` is that of `x.to_bits() & 0x7fff_ffff` (the
        // Cortex-M3's `fmaxf` took about 40 instructions an element). A
        // NaN or infinite element gives `None` here; `f32::max` skipped a
        // NaN, but its determinant was NaN, and `None` all the same.
        let big = (0..3)
            .flat_map(|c| self.m[c][..3].iter())
            .fold(0u32, |b, x| b.max(x.to_bits() & 0x7fff_ffff));
        if big >= 0x7f80_0000 || big == 0 {
            return None;
        }
        // big = 1.x 2^e (subnormals counted as 2^-126): scale by 2^-e.
        let e = (((big >> 23) as i32).max(1) - 127).min(126);
        let k = f32::from_bits(((127 - e) as u32) << 23);
        // Rows of the 3x3 part, scaled (only the nine elements it uses).
        let m = &self.m;
        let row = |r: usize| {
            Vec3::new(
                times_pow2(m[0][r], k),
                times_pow2(m[1][r], k),
                times_pow2(m[2][r], k),
            )
        };
        let (r0, r1, r2) = (row(0), row(1), row(2));
        // Columns of the inverse are cross products of rows / det.
        let c = [r1.cross(r2), r2.cross(r0), r0.cross(r1)];
        let det = r0.dot(c[0]);
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        Some(Inverse3 {
            c,
            inv: 1.0 / det,
            k,
        })
    }

    /// The same projective transform with its largest element ±1: the
    /// matrix divided by the magnitude of its largest element.
    ///
    /// A model-view-projection matrix acts on homogeneous coordinates, so
    /// any non-zero multiple of it gives the same picture (x/w, y/w and z/w
    /// do not change). A scene in millimetres or in kilometres, with its
    /// camera and planes in the same units, differs from the scene in metres
    /// by such a factor only; dividing it out before the conversion to
    /// 16.16 ([`to_fixed_normalized`](Self::to_fixed_normalized)) makes the
    /// fixed-point matrix, and so the picture, the same in any units (up to
    /// the rounding of the `f32` set-up). A power of two would keep the
    /// elements' bits but leave a factor in `[1, 2)` that changes with the
    /// units, and with it every rounding of the vertex stage.
    ///
    /// Returns `None` when an element is not finite, or when the largest is
    /// below 2^-100 (zero included): then the elements that matter are
    /// subnormal or nearly so, and have lost precision already.
    ///
    /// ```
    /// use microraster::math::{Mat4, Vec3};
    /// let m = Mat4::translation(Vec3::new(0.5, -4.0, 1.0));
    /// let n = m.normalized().unwrap();
    /// assert_eq!(n.m[3], [0.125, -1.0, 0.25, 0.25]);
    /// // Any multiple of it is the same transform, and normalizes the same.
    /// let times = |k: f32| Mat4 { m: m.m.map(|c| c.map(|v| v * k)) };
    /// assert_eq!(times(1e-3).normalized(), Some(n));
    /// assert_eq!(times(-65_536.0).normalized(), Some(times(-1.0).normalized().unwrap()));
    /// assert_eq!(Mat4 { m: [[0.0; 4]; 4] }.normalized(), None);
    /// ```
    pub fn normalized(&self) -> Option<Self> {
        let big = self.normal_scale()?;
        let mut out = *self;
        if SOFT_FLOAT {
            // Sixteen soft-float divisions (about 100 instructions each on
            // the Cortex-M3) by one divisor: through its integer
            // reciprocal instead, the same bits.
            let d = ScaleDivisor::new(big);
            for v in out.m.iter_mut().flatten() {
                *v = d.div(*v);
            }
        } else {
            for v in out.m.iter_mut().flatten() {
                *v /= big;
            }
        }
        Some(out)
    }

    /// What [`normalized`](Self::normalized) divides by, the largest
    /// element's magnitude; `None` exactly where it returns `None`. The
    /// renderer checks the camera by this alone: its product normalized
    /// was never used, and took 16 `f32` divisions a frame.
    pub(crate) fn normal_scale(&self) -> Option<f32> {
        if !self.is_finite() {
            return None;
        }
        // By the bits, finite as they are: `|x|` orders as `x.to_bits() &
        // 0x7fff_ffff` (the Cortex-M3's `fmaxf` took about 40 instructions
        // an element).
        let big = self
            .m
            .iter()
            .flatten()
            .fold(0u32, |b, v| b.max(v.to_bits() & 0x7fff_ffff));
        // 2^-100: the elements within 2^-17 of it are normal f32s.
        (big >= 27 << 23).then(|| f32::from_bits(big))
    }

    /// [`normalized`](Self::normalized), converted to 16.16: what the vertex
    /// stage transforms with, so that the picture does not depend on the
    /// scene's units.
    ///
    /// Returns `None` where `normalized` does, and when the conversion
    /// would lose a whole row: a row with a non-zero element in `f32` whose
    /// elements all round to zero, relative to the largest element, in
    /// 16.16 (a coordinate of clip space would be lost, and the picture
    /// with it). Such a matrix spans more than 2^17 between its rows: it
    /// cannot be represented in 16.16 in any units.
    ///
    /// ```
    /// use microraster::math::{Mat4, Vec3};
    /// // The identity times 3e-5: the same transform.
    /// let tiny = Mat4 { m: Mat4::IDENTITY.m.map(|c| c.map(|v| v * 3e-5)) };
    /// assert_eq!(tiny.to_fixed().unwrap().m[0][0], 2); // most bits lost
    /// assert_eq!(tiny.to_fixed_normalized(), Mat4::IDENTITY.to_fixed_normalized());
    /// // x spans 2^-20 of w: not representable.
    /// let flat = Mat4::scale(Vec3::new(1e-6, 1.0, 1.0));
    /// assert!(flat.to_fixed_normalized().is_none());
    /// ```
    pub fn to_fixed_normalized(&self) -> Option<FixedMat4> {
        self.normalized()?.fixed_whole()
    }

    /// The conversion of [`to_fixed_normalized`](Self::to_fixed_normalized)
    /// of a matrix already [`normalized`](Self::normalized) (`self`): `None`
    /// when an element is out of range or a row would be lost.
    pub(crate) fn fixed_whole(&self) -> Option<FixedMat4> {
        let n = self;
        let fixed = n.to_fixed()?;
        // `v != 0.0` by the bits (the sign shifted out): without a
        // soft-float compare per element.
        let nonzero = |v: f32| v.to_bits() << 1 != 0;
        let lost = (0..4)
            .any(|r| (0..4).any(|c| nonzero(n.m[c][r])) && (0..4).all(|c| fixed.m[c][r] == 0));
        (!lost).then_some(fixed)
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

/// Whether `f32` arithmetic is in software (ARM cores without an FPU),
/// where the library takes short cuts around it: there [`Mat4`]'s product
/// skips the terms of zeros and ones, whose tests cost more than the
/// products they save where an FPU does them (the Cortex-M4F's `demo`
/// frame took 2,065 instructions more for an affine matrix's last row). Not in builds optimised
/// for size (`microraster_size`: the OLED firmware's flash took 320 B
/// more). The library's own tests take the short cut too, to compare it
/// with the full product.
pub(crate) const SOFT_FLOAT: bool = cfg!(any(
    test,
    all(
        target_arch = "arm",
        not(target_abi = "eabihf"),
        not(microraster_size)
    )
));

impl core::ops::Mul for Mat4 {
    type Output = Mat4;
    /// Out of line: a frame takes a few products (camera, each draw's
    /// model-view-projection), and on a core without an FPU each inlined
    /// copy is 1.3 KB of soft-float calls.
    ///
    /// There (`SOFT_FLOAT`), when `rhs` is affine (its last row
    /// exactly `(0, 0, 0, 1)`: a model or view matrix) and `self` finite,
    /// the last row's products are known: `a * 0.0` is a zero of `a`'s
    /// sign and `a * 1.0` is `a`, so the last term is added without its
    /// product, and in the first three columns not added at all (only a
    /// zero sum's sign can change, fixed by the bits): the same bits as
    /// the full product (NaN payloads aside), 16 multiplications and 12
    /// additions fewer (`demo`'s frame: Cortex-M3 6,961 instructions
    /// fewer, ARMv6-M 10,556). (The short cut in a function of its own,
    /// inlined here, copied both matrices on the stack.)
    ///
    /// Before that, where both matrices are finite, the product is made
    /// term by term (`product_by_terms`, in soft-float builds), the same
    /// bits: a term with a zero or a one for a factor needs no
    /// multiplication, and a known zero no addition (so the affine short cut is left for matrices
    /// with an element not finite). Rotations, translations and scales
    /// are mostly zeros and ones: `demo`'s frame, whose scene builds six
    /// products besides the camera's and the two draws', Cortex-M3
    /// 3,011,495 -> 2,999,356 instructions, ARMv6-M 6,127,299 ->
    /// 6,112,817. A cfg, not the `SOFT_FLOAT` test: with an FPU the code
    /// is not merely the same in effect but the same text (the
    /// Cortex-M4F's binning moved by 8,600 instructions when the crate's
    /// codegen units were partitioned otherwise).
    #[inline(never)]
    fn mul(self, rhs: Mat4) -> Mat4 {
        #[cfg(any(
            test,
            all(target_arch = "arm", not(target_abi = "eabihf"), not(microraster_size))
        ))]
        if let Some(out) = product_by_terms(&self, &rhs) {
            return out;
        }
        let bits = |v: f32| v.to_bits();
        let affine = SOFT_FLOAT
            && (bits(rhs.m[0][3]) | bits(rhs.m[1][3]) | bits(rhs.m[2][3])) == 0
            && bits(rhs.m[3][3]) == bits(1.0)
            && self
                .m
                .iter()
                .flatten()
                .all(|v| bits(*v) & 0x7fff_ffff < 0x7f80_0000);
        let mut out = [[0.0f32; 4]; 4];
        for (c, out_col) in out.iter_mut().enumerate() {
            for (r, o) in out_col.iter_mut().enumerate() {
                let s = self.m[0][r] * rhs.m[c][0]
                    + self.m[1][r] * rhs.m[c][1]
                    + self.m[2][r] * rhs.m[c][2];
                let a = self.m[3][r];
                *o = match (affine, c) {
                    (false, _) => s + a * rhs.m[c][3],
                    (true, 3) => s + a,
                    // `s + (a * 0.0)`: `s`, but for a zero `s`, whose
                    // sum with a zero of `a`'s sign is -0.0 only when
                    // both are (round to nearest). The bits through
                    // `black_box`: LLVM turned the integer test into a
                    // soft-float compare (a library call each).
                    (true, _) => match core::hint::black_box(bits(s)) {
                        z if z << 1 != 0 => s,
                        z => f32::from_bits(z & (bits(a) | 0x7fff_ffff)),
                    },
                };
            }
        }
        Mat4 { m: out }
    }
}

/// `a * b` where `f32` is in software ([`SOFT_FLOAT`]), term by term with
/// the zeros and ones known from the bits; `None` when an element is not
/// finite (then the caller multiplies).
///
/// For finite `x` and `y`: `x * ±0` and `±0 * y` are zeros whose sign is
/// the signs' exclusive or; `x * 1` is `x` (and `1 * y` is `y`); `s +
/// -0` is `s`, and `s + +0` is `s` but for `s = -0`, whose sum is `+0`
/// (rounding to nearest); `±0 + t` is `t` for a non-zero `t`, and the sum
/// of two zeros is `-0` only when both are. A sum is made only where a
/// term is known to be zero (from its factors' bits); otherwise it is
/// added, so a zero that a product or sum rounds to is handled by the
/// library's arithmetic itself. The bits through `black_box`: LLVM turns
/// integer tests of a float's bits into soft-float compares (a library
/// call each).
#[cfg(any(
    test,
    all(target_arch = "arm", not(target_abi = "eabihf"), not(microraster_size))
))]
#[inline(always)]
fn product_by_terms(a: &Mat4, b: &Mat4) -> Option<Mat4> {
    const ONE: u32 = 0x3f80_0000;
    let finite = |m: &Mat4| {
        m.m.iter()
            .flatten()
            .all(|v| v.to_bits() & 0x7fff_ffff < 0x7f80_0000)
    };
    if !(finite(a) && finite(b)) {
        return None;
    }
    // A term: `Err(bits)` for a known zero, `Ok(value)` otherwise. Its
    // factors' bits through `black_box` one pair at a time (both
    // matrices' at once took ARMv6-M's vertex stage 48 B more stack).
    let term = |x: f32, y: f32| -> Result<f32, u32> {
        let (x, y) = core::hint::black_box((x.to_bits(), y.to_bits()));
        if x << 1 == 0 || y << 1 == 0 {
            Err((x ^ y) & 0x8000_0000)
        } else if y == ONE {
            Ok(f32::from_bits(x))
        } else if x == ONE {
            Ok(f32::from_bits(y))
        } else {
            Ok(f32::from_bits(x) * f32::from_bits(y))
        }
    };
    let mut out = [[0.0f32; 4]; 4];
    for (c, out_col) in out.iter_mut().enumerate() {
        for (r, o) in out_col.iter_mut().enumerate() {
            let mut acc = term(a.m[0][r], b.m[c][0]);
            for k in 1..4 {
                acc = match (acc, term(a.m[k][r], b.m[c][k])) {
                    (Ok(s), Ok(t)) => Ok(s + t),
                    (Ok(s), Err(0)) if s.to_bits() == 0x8000_0000 => Ok(0.0),
                    (Ok(s), Err(_)) => Ok(s),
                    (Err(0), Ok(t)) if t.to_bits() == 0x8000_0000 => Ok(0.0),
                    (Err(_), Ok(t)) => Ok(t),
                    (Err(z), Err(w)) => Err(z & w),
                };
            }
            *o = match acc {
                Ok(v) => v,
                Err(z) => f32::from_bits(z),
            };
        }
    }
    Some(Mat4 { m: out })
}

/// `x * k` for `k` a positive normal power of two (an [`Inverse3`]'s
/// scale), the same bits: where `f32` arithmetic is in software
/// ([`SOFT_FLOAT`]), a zero is itself and a normal `x` whose product is
/// normal has `k`'s exponent added to its own (exact), without the
/// soft-float multiply (some 45 instructions on the Cortex-M3, twelve a
/// draw's light set-up); any other `x` is multiplied.
#[inline]
pub(crate) fn times_pow2(x: f32, k: f32) -> f32 {
    if !SOFT_FLOAT {
        return x * k;
    }
    // The bits through `black_box`: LLVM turned the zero test into a
    // soft-float compare (a library call each, as in `Mat4`'s product).
    // (Not where the product is kept: the Cortex-M4F's `demo` took 76
    // instructions more through it.)
    let (b, kb) = (core::hint::black_box(x.to_bits()), k.to_bits());
    let field = (b >> 23) & 0xff;
    let sum = field as i32 + (kb >> 23) as i32 - 127;
    match b << 1 == 0 {
        true => x,
        false if field != 0 && field != 255 && (1..=254).contains(&sum) => {
            f32::from_bits(b.wrapping_add(kb.wrapping_sub(127 << 23)))
        }
        false => x * k,
    }
}

/// Division of `f32`s by one positive normal `f32`, correctly rounded
/// (the same bits as `/`), through an integer reciprocal of the
/// divisor's significand: [`Mat4::normalized`]'s sixteen divisions by its
/// largest element where `f32` arithmetic is in software.
///
/// With `a` and `b` the dividend's and the divisor's significands (24
/// bits, `2^23 <= a, b < 2^24`) and `a' = a` or `2 a` (whichever makes
/// `a' >= b`), the quotient's significand rounded to 24 bits is that of
/// `q = floor(a' 2^24 / b)`, which has 25 bits, rounded by its last: a
/// quotient is never exactly halfway between two 24-bit values (then
/// `a' 2^25 = (2 Q + 1) b` for an integer `Q >= 2^23`, and the odd part
/// of the left side, that of `a`, below 2^24, would be a multiple of
/// `2 Q + 1 > 2^24`), so the bit below the last says which way it
/// rounds. `q` comes from `r = floor((2^64 - 1) / (2^9 b))`, within 2
/// under `2^55 / b` and below 2^32: `floor(a' r / 2^31)` (`a' < 2^25`)
/// falls short of `a' 2^24 / b` by less than 2^-5, so it is `q` or
/// `q - 1`, which the remainder (below `2 b`, exact in wrapping `u32`
/// arithmetic) tells apart.
#[derive(Clone, Copy, Debug)]
struct ScaleDivisor {
    /// The divisor.
    d: f32,
    /// Its significand `b`, the implicit bit included.
    b: u32,
    /// Its exponent field.
    field: i32,
    /// `floor((2^64 - 1) / (2^9 b))`.
    r: u32,
}

impl ScaleDivisor {
    /// The divisor `d`, positive and normal.
    #[inline(always)]
    fn new(d: f32) -> Self {
        let bits = d.to_bits();
        let b = (bits & 0x7f_ffff) | 0x80_0000;
        // `b` is not zero.
        let nz = core::num::NonZeroU64::new(u64::from(b)).unwrap_or(core::num::NonZeroU64::MIN);
        Self {
            d,
            b,
            field: ((bits >> 23) & 0xff) as i32,
            r: (divisor::max_div_long(nz) >> 9) as u32,
        }
    }

    /// `v / d`, the same bits. A zero is itself (`d` is positive); a
    /// subnormal, infinite or NaN `v`, or a quotient outside the normal
    /// range, is divided.
    #[inline(always)]
    fn div(&self, v: f32) -> f32 {
        // The bits through `black_box`: LLVM turned the zero test into a
        // soft-float compare (a library call each, as in `Mat4`'s
        // product).
        let x = core::hint::black_box(v.to_bits());
        if x << 1 == 0 {
            return v;
        }
        let fv = ((x >> 23) & 0xff) as i32;
        let a = (x & 0x7f_ffff) | 0x80_0000;
        let below = u32::from(a < self.b);
        let a = a << below;
        // The quotient's exponent field, before a carry of its rounding.
        let field = fv - self.field + 127 - below as i32;
        if fv == 0 || fv == 255 || !(1..=254).contains(&field) {
            return v / self.d;
        }
        let product = if wide::SPLIT {
            wide::mul_split_u(a, self.r)
        } else {
            u64::from(a) * u64::from(self.r)
        };
        let est = (product >> 31) as u32;
        let rem = (a << 24).wrapping_sub(est.wrapping_mul(self.b));
        let q = est + u32::from(rem >= self.b);
        // The significand rounded, its implicit bit added to the field
        // (and a carry to 2^24 makes the next power of two).
        let sig = (q + 1) >> 1;
        f32::from_bits((x & 0x8000_0000) | ((((field - 1) as u32) << 23) + sig))
    }
}

/// The inverse of a [`Mat4`]'s 3x3 part, made once for several vectors
/// ([`Mat4::inverse3`]); [`apply`](Self::apply) gives
/// [`Mat4::inverse_transform_vector`]'s result, the same bits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Inverse3 {
    /// The columns of the scaled part's adjugate.
    c: [Vec3; 3],
    /// `1 / det` of the scaled part.
    inv: f32,
    /// The power of two the part was scaled by.
    k: f32,
}

impl Inverse3 {
    /// Whether the 3x3 part's largest element (in magnitude) lies within
    /// `[2^-60, 2^62)`: then the sum of its elements' squares is a finite
    /// f32 of at least 2^-120 (the light set-up's model scale need not be
    /// made to be known finite and positive).
    pub(crate) fn moderate(&self) -> bool {
        // `k = 2^-e` for the largest element `1.x 2^e`, `e` in `-60..=61`.
        (self.k.to_bits() >> 23).wrapping_sub(127 - 61) <= 121
    }

    /// Whether `apply(v - t)` is known, from the exponents alone, to be
    /// `Some` with every coordinate at most 2^44 in magnitude (so that
    /// 2^16 times it is at most 2^60: what the light set-up's raw 16.16
    /// takes). `false` says nothing: the caller computes it. A few dozen
    /// integer instructions where the product and its tests were about
    /// 1,600 soft-float ones on the Cortex-M3, per draw, for an eye whose
    /// model-space value the one-light set-up never uses.
    ///
    /// Every finite `x` (zero and subnormals too) is below `2^(f - 126)`,
    /// `f` its exponent field; with `|c| < 2^a` for the adjugate's
    /// elements and `|v|, |t| < 2^(b - 1)`, each rounded step of `apply`
    /// stays within: `|v - t| <= 2^b`, each product `<= 2^(a + b)`, the
    /// sum of three `<= 2^(a + b + 2)`, times `inv < 2^i` `<= 2^(a + b +
    /// 2 + i)`, times `k = 2^kk` (exact, or smaller where it underflows)
    /// `<= 2^(a + b + 2 + i + kk)`. Finite where each bound is at most
    /// 2^127. Where a value is not finite (its field 255: `inv` is
    /// infinite for a determinant below about 2^-128), the bounds do not
    /// hold, and the test fails.
    pub(crate) fn moves_within_2_44(&self, v: Vec3, t: Vec3) -> bool {
        let field = |x: f32| ((x.to_bits() >> 23) & 0xff) as i32;
        let top = |v: Vec3| field(v.x).max(field(v.y)).max(field(v.z));
        let (fc, fv) = (
            top(self.c[0]).max(top(self.c[1])).max(top(self.c[2])),
            top(v).max(top(t)),
        );
        let fi = field(self.inv);
        if fc.max(fv).max(fi) == 255 {
            return false;
        }
        let (a, b, i) = (fc - 126, fv - 125, fi - 126);
        let kk = field(self.k) - 127;
        let sum = a + b + 2;
        sum <= 127 && sum + i <= 127 && sum + i + kk <= 44
    }

    /// `M⁻¹ v`; `None` when a coordinate is not finite.
    pub(crate) fn apply(&self, v: Vec3) -> Option<Vec3> {
        let ([c0, c1, c2], inv, k) = (self.c, self.inv, self.k);
        // The inverse of the scaled matrix is k times the inverse.
        let out = Vec3::new(
            times_pow2((c0.x * v.x + c1.x * v.y + c2.x * v.z) * inv, k),
            times_pow2((c0.y * v.x + c1.y * v.y + c2.y * v.z) * inv, k),
            times_pow2((c0.z * v.x + c1.z * v.y + c2.z * v.z) * inv, k),
        );
        out.is_finite().then_some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::trig::tests::ulps;
    use super::*;

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
