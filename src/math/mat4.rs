//! [`Mat4`], the `f32` matrix of the per-frame set-up: its constructors
//! (camera, projection, model transforms), its product, its inverse's
//! 3x3 part for the lights ([`Inverse3`]) and its hand-over to
//! [`FixedMat4`].

use super::soft_float::{add, cross, dot, mul, normalize, sub, sub_vec, ScaleDivisor};
use super::{sin_cos, times_pow2, FixedMat4, Vec3, SOFT_FLOAT};
use fixed::types::I16F16;

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
        let nf = 1.0 / sub(near, far);
        // 2 far near / (near - far) as 2 far (near / (near - far)): the
        // product far near underflows f32 for planes below about 1e-19 (and
        // overflows above 1e19) where the ratio is still exact, so the
        // projection of a scene scaled to any units is the same up to its
        // scale.
        let r = Self {
            m: [
                [f / aspect, 0.0, 0.0, 0.0],
                [0.0, f, 0.0, 0.0],
                [0.0, 0.0, add(far, near) * nf, -1.0],
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
        // The products through `mul` (`dot`, `cross`, `normalize`): the
        // same bits, where `f32` is in software without the library's
        // multiply.
        let f = normalize(sub_vec(target, eye))?;
        let s = normalize(cross(f, up))?;
        let u = cross(s, f);
        let r = Self {
            m: [
                [s.x, u.x, -f.x, 0.0],
                [s.y, u.y, -f.y, 0.0],
                [s.z, u.z, -f.z, 0.0],
                [-dot(s, eye), -dot(u, eye), dot(f, eye), 1.0],
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
        // Columns of the inverse are cross products of rows / det (the
        // products through `mul`, as in `look_at`).
        let c = [cross(r1, r2), cross(r2, r0), cross(r0, r1)];
        let det = dot(r0, c[0]);
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

/// The product of two [`Mat4`]s (or references to them), every term
/// multiplied and added in order: written once for `Mul` with an FPU,
/// where it stays in place, and `full_product` in soft-float builds. A
/// macro, not a function: as a function of its own, even inlined, it
/// moved the Cortex-M4F's callers (`demo` +38 instructions, 104 B more
/// stack).
macro_rules! every_term {
    ($a:expr, $b:expr) => {{
        let mut out = [[0.0f32; 4]; 4];
        for (c, out_col) in out.iter_mut().enumerate() {
            for (r, o) in out_col.iter_mut().enumerate() {
                *o = $a.m[0][r] * $b.m[c][0]
                    + $a.m[1][r] * $b.m[c][1]
                    + $a.m[2][r] * $b.m[c][2]
                    + $a.m[3][r] * $b.m[c][3];
            }
        }
        Mat4 { m: out }
    }};
}

impl core::ops::Mul for Mat4 {
    type Output = Mat4;
    /// Out of line: a frame takes a few products (camera, each draw's
    /// model-view-projection), and on a core without an FPU each inlined
    /// copy is 1.3 KB of soft-float calls.
    ///
    /// There, where both matrices are finite, the product is made term by
    /// term (`product_by_terms`, in soft-float builds), the same bits: a
    /// term with a zero or a one for a factor needs no multiplication, and
    /// a known zero no addition. Rotations, translations and scales are
    /// mostly zeros and ones: `demo`'s frame, whose scene builds six
    /// products besides the camera's and the two draws', Cortex-M3
    /// 3,011,495 -> 2,999,356 instructions, ARMv6-M 6,127,299 ->
    /// 6,112,817. A cfg, not the `SOFT_FLOAT` test: with an FPU the code
    /// is not merely the same in effect but the same text (the
    /// Cortex-M4F's binning moved by 8,600 instructions when the crate's
    /// codegen units were partitioned otherwise). A matrix with an element
    /// not finite takes the full product: its result is no matrix the
    /// vertex stage takes, so it has no short cut of its own.
    #[inline(never)]
    fn mul(self, rhs: Mat4) -> Mat4 {
        #[cfg(any(test, microraster_soft_float))]
        let Some(out) = product_by_terms(&self, &rhs) else {
            return full_product(&self, &rhs);
        };
        // With an FPU the full product in place, as it was before the
        // short cuts (see `every_term`).
        #[cfg(not(any(test, microraster_soft_float)))]
        let out = every_term!(self, rhs);
        out
    }
}

/// `a * b`, every term multiplied and added, where `f32` is in software
/// ([`Mat4`]'s product for matrices with an element not finite): cold
/// and out of line, so that the product term by term keeps `mul`'s
/// registers (inlined there, the Cortex-M3's `demo` frame took 456
/// instructions more, ARMv6-M's 130).
#[cfg(any(test, microraster_soft_float))]
#[cold]
#[inline(never)]
fn full_product(a: &Mat4, b: &Mat4) -> Mat4 {
    every_term!(a, b)
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
#[cfg(any(test, microraster_soft_float))]
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
            // Where the core has no 32 x 32 -> 64-bit multiply, in
            // integers (`soft_float::mul`, the same bits).
            Ok(super::soft_float::mul(f32::from_bits(x), f32::from_bits(y)))
        }
    };
    let mut out = [[0.0f32; 4]; 4];
    for (c, out_col) in out.iter_mut().enumerate() {
        for (r, o) in out_col.iter_mut().enumerate() {
            let mut acc = term(a.m[0][r], b.m[c][0]);
            for k in 1..4 {
                acc = match (acc, term(a.m[k][r], b.m[c][k])) {
                    (Ok(s), Ok(t)) => Ok(add(s, t)),
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
        // The inverse of the scaled matrix is k times the inverse (the
        // products through `mul`, as in `look_at`).
        let row = |x: f32, y: f32, z: f32| dot(Vec3::new(x, y, z), v);
        let out = Vec3::new(
            times_pow2(mul(row(c0.x, c1.x, c2.x), inv), k),
            times_pow2(mul(row(c0.y, c1.y, c2.y), inv), k),
            times_pow2(mul(row(c0.z, c1.z, c2.z), inv), k),
        );
        out.is_finite().then_some(out)
    }

    /// [`apply`](Self::apply)'s vector normalized ([`Vec3::normalize`],
    /// the same bits): a light's direction in model space, its products
    /// through the soft-float short cuts where `f32` is in software.
    /// Inline, so that `apply`'s callers are all in the lighting's set-up:
    /// out of line here it left `apply` in two codegen units, two copies
    /// of 438 B on the ESP32-C3.
    #[inline]
    pub(crate) fn apply_unit(&self, v: Vec3) -> Option<Vec3> {
        self.apply(v).and_then(normalize)
    }
}
