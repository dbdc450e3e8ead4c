//! Culling whole draws against the view frustum, before the vertex stage.
//!
//! A scene of many meshes (a room, a level) usually has most of them out of
//! view. Each draw's mesh knows its bounding box ([`Mesh::bounds`](crate::mesh::Mesh::bounds)); per
//! frame and draw, the six frustum planes are taken from the rows of the
//! model-view-projection matrix `P V M` in the mesh's own model space
//! (Gribb and Hartmann, *Fast Extraction of Viewing Frustum Planes from the
//! World-View-Projection Matrix*, 2001): `left = r3 + r0`, `right = r3 -
//! r0`, `bottom = r3 + r1`, `top = r3 - r1`, `near = r3 + r2`, `far = r3 -
//! r2`, where a point `p` is inside plane `(a, b, c, d)` when
//! `a x + b y + c z + d >= 0`. In model space the test is exact for any
//! model matrix, and needs no normalised planes: the box, in centre-extent
//! form, is outside when the centre's signed distance is below
//! `-(|a| e_x + |b| e_y + |c| e_z)`. (Its bounding sphere, outside when the
//! distance is below `-ρ |(a, b, c)|`, is never tighter: it is offered for
//! callers, and the whole-draw test does without it.)
//!
//! A draw outside any plane is culled: none of its vertices is
//! transformed, none of its triangles binned. The renderer would have
//! rejected every one of its triangles anyway (all three vertices outside
//! one half-space), so culling never changes the picture; to keep that
//! true although the planes come from an `f32` matrix and the vertex stage
//! computes in rounded 16.16, a box is culled only when it is outside by a
//! margin that covers both roundings (the property tests render random
//! poses with and without culling and compare).
//!
//! # Clusters
//!
//! A mesh with [clusters](crate::mesh::Cluster) is tested cluster by
//! cluster after the whole draw passes: a culled cluster's vertices are not
//! transformed and its triangles not binned. A scene may hold hundreds of
//! clusters, and the microcontrollers this crate targets have no FPU, so
//! the per-box test runs in integers: per draw, each plane is scaled by a
//! power of two so that its largest coefficient lies just below `2^27` and
//! truncated to integers, and everything the truncation, the `f32` planes
//! and the 16.16 vertex stage can move is folded into one margin per plane
//! (it depends only on the plane and the mesh's largest coordinate). With
//! the box's doubled centre `lo + hi` and doubled extent `hi - lo`, in raw
//! 16.16 (33 bits), a plane then costs six 64-bit multiplies (a 32-bit
//! coefficient by a 33-bit coordinate: a few instructions each on a
//! Cortex-M3, a library call on a Cortex-M0+) and is exact in `i64`. Clusters take the box test only: it is tighter than the sphere
//! around the box and, in integers, barely dearer than it.

use crate::math::times_pow2;
use crate::math::Mat4;
use crate::math::{mul_wide_by_narrow, SPLIT};
use crate::mesh::{Mesh, Vec3Fx};
use crate::scene::Draw;

/// Whether `draw`, seen through `view_proj`, lies wholly outside the view
/// frustum (with the rounding margin of the module docs): its bounding
/// box. A non-finite matrix is never culled here
/// (the vertex stage reports it).
pub fn outside(view_proj: &Mat4, draw: &Draw<'_>) -> bool {
    Frustum::new(view_proj, draw).is_some_and(|f| f.excludes_mesh(draw.mesh))
}

/// One frustum plane in a draw's model space, in integers: a point with
/// raw 16.16 coordinates `2p` (doubled) is inside when
/// `n · 2p + d2 + margin >= 0`.
#[derive(Clone, Copy, Debug)]
struct Plane {
    /// `(a, b, c)` scaled by `2^s`, truncated: `|n[k]| < 2^27`.
    n: [i32; 3],
    /// `d` scaled by `2^(s + 17)` (raw 16.16, doubled): `|d2| < 2^44`.
    d2: i64,
    /// Everything the roundings can move the plane's value, in its units;
    /// at most `2^61` (a plane that coarse never culls).
    margin: i64,
}

/// The six planes of a view frustum in one draw's model space, ready to
/// test boxes in integer arithmetic ([module docs](self)).
///
/// ```
/// use fixed::types::I16F16;
/// use microraster::cull::Frustum;
/// use microraster::math::{Mat4, Vec3};
/// use microraster::mesh::Mesh;
/// use microraster::scene::Draw;
/// let p = [[I16F16::ZERO; 3], [I16F16::ONE; 3]];
/// let tris = [[0u16, 1, 1]];
/// let mesh = Mesh::new(&p, &tris).unwrap();
/// let view = Mat4::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::default(), Vec3::new(0.0, 1.0, 0.0)).unwrap();
/// let vp = Mat4::perspective(1.0, 1.0, 0.5, 20.0).unwrap() * view;
/// let frustum = Frustum::new(&vp, &Draw::new(&mesh)).unwrap();
/// let fx = |v: i32| I16F16::from_num(v);
/// assert!(!frustum.excludes_box(&[[fx(0); 3], [fx(1); 3]]));
/// // Far to the right, and behind the eye.
/// assert!(frustum.excludes_box(&[[fx(40), fx(0), fx(0)], [fx(41), fx(1), fx(1)]]));
/// assert!(frustum.excludes_box(&[[fx(0), fx(0), fx(8)], [fx(1), fx(1), fx(9)]]));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    planes: [Plane; 6],
}

/// `x 2^s`, truncated toward zero, saturated at `±2^62` (and 0 for
/// subnormal `x`), for a finite `x`: the scaling is a shift of the
/// mantissa's bits, where a soft-float core would multiply twice and
/// convert.
fn scaled(x: f32, s: i32) -> i64 {
    let bits = x.to_bits();
    let field = ((bits >> 23) & 0xff) as i32;
    if field == 0 {
        return 0;
    }
    let mant = i64::from((bits & 0x7f_ffff) | 0x80_0000);
    let e = field - 150 + s;
    let v = match e {
        // The mantissa has 24 bits: below 2^62 up to a shift of 38.
        39.. => 1 << 62,
        0..=38 if SPLIT => shift_left_split(mant as u32, e as u32),
        0..=38 => mant << e,
        // A 32-bit shift where a 64-bit one is a library call (ARMv6-M).
        -23..=-1 if SPLIT => i64::from(mant as u32 >> -e),
        -23..=-1 => mant >> -e,
        _ => 0,
    };
    if bits >> 31 == 1 {
        -v
    } else {
        v
    }
}

/// `m 2^e` for a mantissa `m < 2^24` and `e <= 38` ([`scaled`]'s left
/// shift) from 32-bit shifts of its two words: ARMv6-M makes a 64-bit
/// shift by a variable a library call (`__aeabi_llsl`), about 60 a frame.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
fn shift_left_split(m: u32, e: u32) -> i64 {
    let (hi, lo) = match e {
        // Below 2^31: one word.
        0..=7 => (0, m << e),
        8..=31 => (m >> (32 - e), m << e),
        _ => (m << (e - 32), 0),
    };
    ((u64::from(hi) << 32) | u64::from(lo)) as i64
}

impl Frustum {
    /// The frustum of `view_proj` in the model space of `draw` (whose
    /// mesh's largest coordinate sets the margin for the vertex stage's
    /// rounding). `None` if the matrix is not finite or cannot be
    /// normalized ([`Mat4::normalized`]): nothing is culled then, and the
    /// vertex stage reports the error.
    pub fn new(view_proj: &Mat4, draw: &Draw<'_>) -> Option<Self> {
        // Normalized as the vertex stage normalizes it (the planes are
        // homogeneous too, so the test does not change), so that its
        // 16.16 matrix is this one rounded.
        Self::from_normalized(&(*view_proj * draw.transform).normalized()?, draw)
    }

    /// [`new`](Self::new) from `view_proj * draw.transform` already
    /// [`normalized`](Mat4::normalized) (`m`): the vertex stage's product,
    /// which it converts to 16.16 too.
    pub(crate) fn from_normalized(m: &Mat4, draw: &Draw<'_>) -> Option<Self> {
        let m = *m;
        // The vertex stage's 16.16 matrix differs from this one by at most
        // 2^-17 per element, and a transformed coordinate by at most
        // (3 E + 2) 2^-17 with E the largest model coordinate; a plane sums
        // two rows, so twice that.
        let extent = draw.mesh.extent();
        // The powers of two by the exponent where `f32` is in software
        // ([`times_pow2`]; the same bits).
        let e = times_pow2(extent as f32, 1.0 / 65_536.0);
        let fixed = times_pow2(3.0 * e + 2.0, 2.0 / 131_072.0);
        let row = |r: usize| [m.m[0][r], m.m[1][r], m.m[2][r], m.m[3][r]];
        let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
        // Each row's pair of planes shares its rounding bound: a soft-float
        // core computes it (nine `f32` operations) once per pair.
        let [p0, p1] = Plane::pair(r3, r0, fixed, e);
        let [p2, p3] = Plane::pair(r3, r1, fixed, e);
        let [p4, p5] = Plane::pair(r3, r2, fixed, e);
        Some(Self {
            planes: [p0, p1, p2, p3, p4, p5],
        })
    }

    /// Whether the whole `mesh` (the one this frustum was made for) lies
    /// outside: its bounding box, by [`excludes_box`](Self::excludes_box)
    /// alone. The sphere around the box excludes no box the box test keeps
    /// (by Cauchy-Schwarz, `|a| e_x + |b| e_y + |c| e_z <= |(a, b, c)|
    /// |e|`, and both factors are rounded up), so asking it first never
    /// changed the answer; it only cost each plane a square root.
    pub fn excludes_mesh(&self, mesh: &Mesh<'_>) -> bool {
        self.excludes_box(&mesh.bounds())
    }

    /// Whether the box `bounds` (smallest, largest coordinates) lies
    /// outside the frustum, beyond the margin: in centre-extent form,
    /// outside a plane when the centre's distance is below
    /// `-(|a| e_x + |b| e_y + |c| e_z)`.
    #[inline]
    pub fn excludes_box(&self, bounds: &[Vec3Fx; 2]) -> bool {
        if SPLIT {
            return self.excludes_box_split(bounds);
        }
        let (c, e) = centre_extent(bounds);
        self.planes.iter().any(|p| {
            let [a, b, cc] = p.n.map(i64::from);
            let dist = a * c[0] + b * c[1] + cc * c[2] + p.d2;
            let reach = a.abs() * e[0] + b.abs() * e[1] + cc.abs() * e[2];
            // |n| < 2^27 and |c|, e <= 2^32: |dist| < 3 2^59 + 2^44,
            // reach < 3 2^59, margin <= 2^61, so the sum stays below 2^62.
            dist + reach + p.margin < 0
        })
    }

    /// [`excludes_box`](Self::excludes_box) on ARMv6-M, which has no
    /// 32x32 to 64-bit multiply (each `i64` product a library call of
    /// about 40 instructions): the same sums, each product from 32-bit
    /// pieces ([`mul_wide_by_narrow`]: a doubled centre or extent `|v| < 2^33`
    /// by a coefficient `|a| < 2^27`), the same answer. Out of line:
    /// inlined into the draw, its code cost the binning stage 7,223
    /// instructions of `demo` a frame (that function's registers moved).
    /// Elsewhere only inline, so that no other target compiles it.
    #[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
    #[cfg_attr(microraster_narrow_multiply, inline(never))]
    #[cfg_attr(not(microraster_narrow_multiply), inline)]
    fn excludes_box_split(&self, bounds: &[Vec3Fx; 2]) -> bool {
        let (c, e) = centre_extent(bounds);
        self.planes.iter().any(|p| {
            let [a, b, cc] = p.n;
            let dist = mul_wide_by_narrow(c[0], a)
                + mul_wide_by_narrow(c[1], b)
                + mul_wide_by_narrow(c[2], cc)
                + p.d2;
            let reach = mul_wide_by_narrow(e[0], a.abs())
                + mul_wide_by_narrow(e[1], b.abs())
                + mul_wide_by_narrow(e[2], cc.abs());
            // The bounds of `excludes_box`: the sum stays below 2^62.
            dist + reach + p.margin < 0
        })
    }

    /// Whether the sphere around the box `bounds` (its centre, its half
    /// diagonal, rounded up) lies outside the frustum, beyond the margin.
    /// It is never tighter than [`excludes_box`](Self::excludes_box),
    /// and not cheaper in integers (each plane's norm takes a square
    /// root): [`excludes_mesh`](Self::excludes_mesh) does not ask it.
    pub fn excludes_sphere(&self, bounds: &[Vec3Fx; 2]) -> bool {
        let (c, e) = centre_extent(bounds);
        // The doubled radius, rounded up, by a 32-bit root: the extents
        // shifted right until the largest has 15 bits, plus one each.
        let big = e[0].max(e[1]).max(e[2]) as u64;
        let shift = (64 - big.leading_zeros()).saturating_sub(15);
        let [x, y, z] = e.map(|v| ((v as u64 >> shift) as u32) + 1);
        let radius = u64::from((x * x + y * y + z * z).isqrt() + 1) << shift;
        self.planes.iter().any(|p| {
            let [a, b, cc] = p.n.map(i64::from);
            let dist = a * c[0] + b * c[1] + cc * c[2] + p.d2;
            // radius < 2^33.2 and norm < 2^27.8: the product stays below
            // 2^61, the sum below 2^63.
            dist + p.norm() * radius as i64 + p.margin < 0
        })
    }
}

/// The doubled centre `lo + hi` and doubled extent `hi - lo` of a box, raw
/// 16.16 (each below 2^33 in magnitude).
#[inline(always)]
fn centre_extent(bounds: &[Vec3Fx; 2]) -> ([i64; 3], [i64; 3]) {
    let [lo, hi] = bounds.map(|p| p.map(|v| i64::from(v.to_bits())));
    (
        [0, 1, 2].map(|k| lo[k] + hi[k]),
        [0, 1, 2].map(|k| (hi[k] - lo[k]).max(0)),
    )
}

impl Plane {
    /// The planes `r3 + r` and `r3 - r`, in integers, with the margin for
    /// `fixed` (the vertex stage's error of a plane's value, in clip
    /// units) and a mesh whose largest coordinate is `e` (in units): by
    /// `pair_by_bits` where `f32` is in software
    /// (and in the tests), by `pair_by_sums` with an
    /// FPU. Both are compiled in the tests, which compare them.
    fn pair(r3: [f32; 4], r: [f32; 4], fixed: f32, e: f32) -> [Self; 2] {
        #[cfg(any(test, microraster_soft_float))]
        let pair = Self::pair_by_bits;
        #[cfg(not(any(test, microraster_soft_float)))]
        let pair = Self::pair_by_sums;
        pair(r3, r, fixed, e)
    }

    /// [`pair`](Self::pair) with an FPU: each size `|r3[k]| + |r[k]|`
    /// summed as written.
    #[cfg(any(test, not(microraster_soft_float)))]
    #[inline(always)]
    fn pair_by_sums(r3: [f32; 4], r: [f32; 4], fixed: f32, e: f32) -> [Self; 2] {
        // Each sum rounds by at most 2^-24 of its operands' size (more than
        // of its own, when they cancel); at a point within the mesh's
        // extent E that moves the plane's value by at most
        // 2^-24 (E (s0 + s1 + s2) + s3). Taken 32 times over, with f32's
        // own rounding of this bound. The sizes are the same for either
        // sign.
        let size = [0, 1, 2, 3].map(|k| r3[k].abs() + r[k].abs());
        let slack = fixed + (e * (size[0] + size[1] + size[2]) + size[3]) * (1.0 / 524_288.0);
        [
            Self::new([0, 1, 2, 3].map(|k| r3[k] + r[k]), slack),
            Self::new([0, 1, 2, 3].map(|k| r3[k] - r[k]), slack),
        ]
    }

    /// [`pair`](Self::pair) where `f32` is in software ([`SOFT_FLOAT`](crate::math::SOFT_FLOAT)'s
    /// condition, as a cfg: with an FPU the code is
    /// `pair_by_sums`, not merely the same in
    /// effect, since the Cortex-M4F's frame moved by thousands of
    /// instructions elsewhere when it was not), the same bits. Each size `|r3[k]| + |r[k]|` is one of the planes' sums in
    /// magnitude: the sum where the two have the same sign (it is theirs
    /// times `|r3[k]| + |r[k]|`, and rounding to nearest is symmetric),
    /// the difference where they differ (zeros of either sign included):
    /// four library calls a pair fewer. The power of two is an exponent's
    /// sum ([`times_pow2`]).
    #[cfg(any(test, microraster_soft_float))]
    #[inline(always)]
    fn pair_by_bits(r3: [f32; 4], r: [f32; 4], fixed: f32, e: f32) -> [Self; 2] {
        // The sums through `soft_float::add` (the same bits; a
        // projection's rows have many zeros).
        use crate::math::soft_float::{add, sub};
        let sum = [0, 1, 2, 3].map(|k| add(r3[k], r[k]));
        let diff = [0, 1, 2, 3].map(|k| sub(r3[k], r[k]));
        let size = [0, 1, 2, 3].map(|k| {
            let same = (r3[k].to_bits() ^ r[k].to_bits()) >> 31 == 0;
            f32::from_bits(if same { sum[k] } else { diff[k] }.to_bits() & 0x7fff_ffff)
        });
        let slack = add(
            fixed,
            times_pow2(
                add(e * add(add(size[0], size[1]), size[2]), size[3]),
                1.0 / 524_288.0,
            ),
        );
        [Self::new(sum, slack), Self::new(diff, slack)]
    }

    /// The plane `p` in integers, with `slack` the bound of its error (in
    /// its units) that [`pair`](Self::pair) computes.
    fn new(p: [f32; 4], slack: f32) -> Self {
        // The largest magnitude by the bits: for the sums of finite values
        // here (never NaN) `|x|` orders as `x.to_bits() & 0x7fff_ffff`,
        // with infinity above every finite value (the Cortex-M3's `fmaxf`
        // took about 40 instructions a coefficient). A NaN would count as
        // not finite too.
        let big = p.iter().fold(0u32, |m, v| m.max(v.to_bits() & 0x7fff_ffff));
        if big >= 0x7f80_0000 || slack.to_bits() & 0x7fff_ffff >= 0x7f80_0000 {
            // Rows near f32's largest values summed past it: this plane
            // culls nothing (and the vertex stage will not accept such a
            // matrix anyway).
            return Self {
                n: [0; 3],
                d2: 0,
                margin: 1 << 61,
            };
        }
        // The binary exponent of the largest coefficient: scaled by 2^s it
        // lies in [2^26, 2^27). Coarse planes (tiny coefficients) stop at
        // s = 60 and only lose precision, which the margin covers.
        let exp = (big >> 23) as i32 - 127;
        let s = if big == 0 {
            0
        } else {
            (26 - exp).clamp(-101, 60)
        };
        let n = [0, 1, 2].map(|k| scaled(p[k], s) as i32);
        let d2 = scaled(p[3], s) << 17;
        // Truncating n moves each coefficient by less than 1, times a
        // doubled coordinate (below 2^33): the six terms of a box test move
        // less than 2^36; truncating d, less than 2^17; truncating the
        // slack, less than 1.
        let margin = ((1i64 << 36) + (1 << 17) + 1)
            .saturating_add(scaled(slack, s + 17))
            .min(1 << 61);
        Self { n, d2, margin }
    }

    /// `|(a, b, c)|` of the integer plane, rounded up (below 2^28), from
    /// coefficients shifted into u32 squares (a 32-bit root is cheap on a
    /// 32-bit core): ((|n| >> 12) + 1) 2^12 over-estimates each, and their
    /// squares sum below 3 2^30.
    fn norm(&self) -> i64 {
        let [x, y, z] = self.n.map(|v| (v.unsigned_abs() >> 12) + 1);
        i64::from(((x * x + y * y + z * z).isqrt() + 1) << 12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::mesh::Mesh;
    use fixed::types::I16F16;

    fn p(x: f32, y: f32, z: f32) -> [I16F16; 3] {
        [
            I16F16::from_num(x),
            I16F16::from_num(y),
            I16F16::from_num(z),
        ]
    }

    #[test]
    fn boxes_in_front_are_kept_and_behind_or_aside_culled() {
        let pos = [p(-1.0, -1.0, -1.0), p(1.0, 1.0, 1.0)];
        let tris = [[0u16, 1, 1]];
        let mesh = Mesh::new(&pos, &tris).unwrap();
        let view = Mat4::look_at(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        let vp = Mat4::perspective(1.0, 1.0, 0.5, 20.0).unwrap() * view;
        let at = |x: f32, y: f32, z: f32| {
            Draw::new(&mesh).transform(Mat4::translation(Vec3::new(x, y, z)))
        };
        assert!(!outside(&vp, &at(0.0, 0.0, 0.0)));
        // Behind the camera, beyond far, far to the side, above.
        assert!(outside(&vp, &at(0.0, 0.0, 10.0)));
        assert!(outside(&vp, &at(0.0, 0.0, -30.0)));
        assert!(outside(&vp, &at(40.0, 0.0, 0.0)));
        assert!(outside(&vp, &at(0.0, -40.0, 0.0)));
        // Straddling the near plane or an edge: kept.
        assert!(!outside(&vp, &at(0.0, 0.0, 4.0)));
        assert!(!outside(&vp, &at(3.5, 0.0, 0.0)));
        // A non-finite transform is left to the vertex stage.
        let nan = Draw::new(&mesh).transform(Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0)));
        assert!(!outside(&vp, &nan));
    }

    /// A random camera and model pose, and a box in model space.
    fn pose(r: &mut impl FnMut(u64) -> u64) -> (Mat4, Mat4, [[f32; 3]; 2]) {
        let mut f = |lo: f32, hi: f32| lo + (hi - lo) * (r(1 << 20) as f32 / (1 << 20) as f32);
        let eye = Vec3::new(f(-12.0, 12.0), f(-12.0, 12.0), f(-12.0, 12.0));
        let target = Vec3::new(f(-5.0, 5.0), f(-5.0, 5.0), f(-5.0, 5.0));
        let view = Mat4::look_at(eye, target, Vec3::new(0.0, 1.0, 0.0)).unwrap_or(Mat4::IDENTITY);
        let near = f(0.05, 2.0);
        let proj = Mat4::perspective(f(0.3, 2.0), f(0.5, 2.0), near, near + f(1.0, 60.0));
        let model = Mat4::translation(Vec3::new(f(-5.0, 5.0), f(-5.0, 5.0), f(-5.0, 5.0)))
            * Mat4::rotation_y(f(-3.0, 3.0))
            * Mat4::rotation_x(f(-3.0, 3.0))
            * Mat4::scale(Vec3::new(f(0.2, 3.0), f(0.2, 3.0), f(0.2, 3.0)));
        let c = [f(-8.0, 8.0), f(-8.0, 8.0), f(-8.0, 8.0)];
        let e = [f(0.0, 4.0), f(0.0, 4.0), f(0.0, 4.0)];
        let b = [
            [0, 1, 2].map(|k| c[k] - e[k]),
            [0, 1, 2].map(|k| c[k] + e[k]),
        ];
        (proj.unwrap() * view, model, b)
    }

    #[test]
    fn split_shifts_are_exact() {
        for m in [0x80_0000u32, 0x80_0001, 0xab_cdef, 0xff_ffff] {
            for e in 0..=38 {
                assert_eq!(shift_left_split(m, e), i64::from(m) << e, "{m} << {e}");
            }
        }
    }

    #[test]
    fn split_coefficient_products_are_exact() {
        let mut next = crate::testing::rng();
        let vs = [
            -(1i64 << 33) + 2,
            -(1 << 32) - 1,
            -(1 << 32),
            -1,
            0,
            1,
            u32::MAX as i64,
            (1 << 33) - 2,
        ];
        let az = [-(1i32 << 27) + 1, -65_536, -1, 0, 1, 65_535, (1 << 27) - 1];
        for &v in &vs {
            for &a in &az {
                assert_eq!(mul_wide_by_narrow(v, a), v * a as i64, "{v} * {a}");
            }
        }
        for _ in 0..100_000 {
            let v = next(1 << 34) as i64 - (1 << 33) + 1;
            let a = next(1 << 28) as i32 - (1 << 27) + 1;
            assert_eq!(mul_wide_by_narrow(v, a), v * a as i64, "{v} * {a}");
        }
    }

    /// Every box the integer test excludes has all its corners (and its
    /// centre) outside one plane as the renderer's 16.16 vertex stage
    /// computes them, so culling it cannot change the picture; and it
    /// excludes nearly every box that exact arithmetic finds outside.
    #[test]
    fn excluded_boxes_are_outside_in_the_vertex_stage_and_few_are_missed() {
        use crate::vertex::{outcode, DrawSetup, REJECT_MASK};
        let mut r = crate::testing::rng();
        let (mut excluded, mut exactly_outside, mut both) = (0, 0, 0);
        for _ in 0..3000 {
            let (vp, model, [lo, hi]) = pose(&mut r);
            let corner = |i: usize| {
                [0, 1, 2].map(|k| I16F16::from_num(if i >> k & 1 == 0 { lo[k] } else { hi[k] }))
            };
            let mut pos = [[I16F16::ZERO; 3]; 9];
            for (i, p) in pos.iter_mut().enumerate().take(8) {
                *p = corner(i);
            }
            pos[8] = [0, 1, 2].map(|k| (pos[0][k] + pos[7][k]) / 2);
            let tris = [[0u16, 1, 2]];
            let mesh = Mesh::new(&pos, &tris).unwrap();
            let draw = Draw::new(&mesh).transform(model);
            let frustum = Frustum::new(&vp, &draw).unwrap();
            let bounds = [pos[0], pos[7]];
            let out = frustum.excludes_box(&bounds);
            // ARMv6-M's form answers the same.
            assert_eq!(frustum.excludes_box_split(&bounds), out);
            // The whole-draw test: the sphere never excludes what the box
            // keeps.
            assert!(!frustum.excludes_sphere(&bounds) || out);
            assert_eq!(outside(&vp, &draw), out);
            let setup = DrawSetup::new(&draw, &vp, None, Vec3::default()).unwrap();
            let codes = (0..9).fold(0xff, |c, i| {
                c & outcode(&setup.clip_vertex(&mesh, i).unwrap().pos)
            });
            if out {
                excluded += 1;
                assert_ne!(codes & REJECT_MASK & !crate::vertex::OUT_W, 0, "{bounds:?}");
            }
            // Exact (f64) planes of the f32 matrix: outside when every
            // corner is below one plane.
            let m = vp * model;
            let exact = [
                (0, 1.0),
                (0, -1.0),
                (1, 1.0),
                (1, -1.0),
                (2, 1.0),
                (2, -1.0),
            ]
            .iter()
            .any(|&(row, sign)| {
                (0..8).all(|i| {
                    let p = corner(i).map(|v| v.to_num::<f64>());
                    let v = |r: usize| {
                        (0..3).map(|k| m.m[k][r] as f64 * p[k]).sum::<f64>() + m.m[3][r] as f64
                    };
                    v(3) + sign * v(row) < 0.0
                })
            });
            if exact {
                exactly_outside += 1;
                both += out as u32;
            }
        }
        // About half the poses put the box outside.
        assert!(excluded > 1000, "{excluded}");
        assert!(
            both * 100 >= exactly_outside * 99,
            "{both} of {exactly_outside}"
        );
    }

    /// The planes as first written, one at a time with `f32::max`: the
    /// pairs with their shared bound and their maximum by the bits give
    /// the same integers.
    #[test]
    fn plane_pairs_are_the_planes_one_at_a_time() {
        fn reference(r3: [f32; 4], r: [f32; 4], sign: f32, fixed: f32, extent: u32) -> Plane {
            let p = [0, 1, 2, 3].map(|k| r3[k] + sign * r[k]);
            let size = [0, 1, 2, 3].map(|k| r3[k].abs() + r[k].abs());
            let e = extent as f32 * (1.0 / 65_536.0);
            let slack = fixed + (e * (size[0] + size[1] + size[2]) + size[3]) * (1.0 / 524_288.0);
            let big = p.iter().fold(0.0f32, |m, v| m.max(v.abs()));
            if !(big.is_finite() && slack.is_finite()) {
                return Plane {
                    n: [0; 3],
                    d2: 0,
                    margin: 1 << 61,
                };
            }
            // From here the plane depends on the largest magnitude's bits
            // alone: `Plane::new`'s scaling (not a copy of it) once its
            // maximum by the bits is `f32::max`'s.
            let by_bits = p.iter().fold(0u32, |m, v| m.max(v.to_bits() & 0x7fff_ffff));
            assert_eq!(by_bits, big.to_bits(), "{p:?}");
            Plane::new(p, slack)
        }
        let same = |a: Plane, b: Plane| a.n == b.n && a.d2 == b.d2 && a.margin == b.margin;
        let mut r = crate::testing::rng();
        for i in 0..20_000 {
            let mut v = || -> f32 {
                match r(4) {
                    0 => 0.0,
                    1 => f32::from_bits(r(1 << 32) as u32 & 0xff7f_ffff),
                    _ => {
                        (r(1 << 24) as f32 / (1 << 23) as f32 - 1.0) * 2f32.powi(r(40) as i32 - 20)
                    }
                }
            };
            let r3 = [0; 4].map(|_| v());
            let row = [0; 4].map(|_| v());
            if !(r3.iter().chain(&row).all(|x| x.is_finite())) {
                continue;
            }
            let extent = if i % 2 == 0 {
                1 << 16
            } else {
                r(1 << 32) as u32
            };
            let e = extent as f32 * (1.0 / 65_536.0);
            let fixed = (3.0 * e + 2.0) * (2.0 / 131_072.0);
            let [plus, minus] = Plane::pair(r3, row, fixed, e);
            assert!(same(plus, reference(r3, row, 1.0, fixed, extent)));
            assert!(same(minus, reference(r3, row, -1.0, fixed, extent)));
        }
    }

    /// Both forms of [`Plane::pair`], by the bits (soft-float cores, and
    /// the other tests) and by the sums (cores with an FPU), give the same
    /// planes for the rows of random matrices: zeros of either sign, ones,
    /// subnormals, the largest finite values, infinities and NaNs among
    /// moderate elements and random bits, for meshes of every extent.
    #[test]
    fn plane_pairs_by_bits_are_the_pairs_by_sums() {
        let same = |a: &[Plane; 2], b: &[Plane; 2]| {
            a.iter()
                .zip(b)
                .all(|(a, b)| a.n == b.n && a.d2 == b.d2 && a.margin == b.margin)
        };
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::from_bits(1),
            -f32::MIN_POSITIVE,
            1e30,
            -3e-30,
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut r = crate::testing::rng();
        let (mut finite, mut culling) = (0, 0);
        for i in 0..50_000 {
            let mut v = || -> f32 {
                match r(4) {
                    0 => special[r(special.len() as u64) as usize],
                    1 => f32::from_bits(r(1 << 32) as u32),
                    _ => {
                        (r(1 << 24) as f32 / (1 << 23) as f32 - 1.0) * 2f32.powi(r(60) as i32 - 30)
                    }
                }
            };
            let m = Mat4 {
                m: [[0.0f32; 4]; 4].map(|c| c.map(|_| v())),
            };
            let extent = match i % 3 {
                0 => 1 << 16,
                1 => r(1 << 32) as u32,
                _ => 0,
            };
            let e = extent as f32 * (1.0 / 65_536.0);
            let fixed = (3.0 * e + 2.0) * (2.0 / 131_072.0);
            let row = |k: usize| [m.m[0][k], m.m[1][k], m.m[2][k], m.m[3][k]];
            for k in 0..3 {
                let bits = Plane::pair_by_bits(row(3), row(k), fixed, e);
                let sums = Plane::pair_by_sums(row(3), row(k), fixed, e);
                assert!(same(&bits, &sums), "{m:?} {k} {extent}");
                finite += row(3).iter().chain(&row(k)).all(|x| x.is_finite()) as u32;
                culling += bits.iter().filter(|p| p.margin < 1 << 61).count() as u32;
            }
        }
        // Most pairs are of finite rows, and most of their planes can cull.
        assert!(finite > 60_000 && culling > 100_000, "{finite} {culling}");
    }

    /// The bit-shift scaling truncates exactly like `f64` arithmetic.
    #[test]
    fn scaling_by_shifts_truncates_toward_zero() {
        let mut r = crate::testing::rng();
        for _ in 0..20_000 {
            // Any bits, or moderate values that land in every shift range.
            let x = match r(2) {
                0 => f32::from_bits(r(1 << 32) as u32),
                _ => {
                    f32::from_bits((r(1 << 31) as u32 & 0x807f_ffff) | ((100 + r(56) as u32) << 23))
                }
            };
            let s = r(160) as i32 - 100;
            if !x.is_finite() {
                continue;
            }
            let exact = (x as f64 * 2f64.powi(s)).trunc();
            let want = if x.abs() < f32::MIN_POSITIVE {
                0
            } else if exact.abs() >= 2f64.powi(62) {
                (1i64 << 62) * exact.signum() as i64
            } else {
                exact as i64
            };
            assert_eq!(scaled(x, s), want, "{x:e} * 2^{s}");
        }
    }

    /// Planes of any finite scale, and boxes at the ends of the 16.16
    /// range, never overflow the integer test (debug builds would panic).
    #[test]
    fn extreme_planes_and_boxes_do_not_overflow() {
        let mut r = crate::testing::rng();
        let p = [[I16F16::MIN; 3], [I16F16::MAX; 3]];
        let tris = [[0u16, 1, 1]];
        let mesh = Mesh::new(&p, &tris).unwrap();
        let exps = [-126, -60, -30, -1, 0, 1, 30, 60, 100, 127];
        for _ in 0..2000 {
            let mut m = Mat4::IDENTITY;
            for c in 0..4 {
                for row in 0..4 {
                    let e = exps[r(exps.len() as u64) as usize];
                    let sign = if r(2) == 0 { 1.0 } else { -1.0 };
                    let mant = 1.0 + r(1000) as f32 / 1000.0;
                    m.m[c][row] = if r(5) == 0 {
                        0.0
                    } else {
                        sign * mant * 2f32.powi(e).min(f32::MAX / 2.0)
                    };
                }
            }
            let Some(f) = Frustum::new(&m, &Draw::new(&mesh)) else {
                continue;
            };
            let pick = |r: &mut dyn FnMut(u64) -> u64| match r(3) {
                0 => I16F16::MIN,
                1 => I16F16::MAX,
                _ => I16F16::from_bits(r(u32::MAX as u64) as u32 as i32),
            };
            let pairs = [0; 3].map(|_| (pick(&mut r), pick(&mut r)));
            let b = [pairs.map(|(x, y)| x.min(y)), pairs.map(|(x, y)| x.max(y))];
            let _ = f.excludes_box(&b);
            let _ = f.excludes_sphere(&b);
            let _ = f.excludes_box(&p);
            let _ = f.excludes_sphere(&p);
        }
    }
}
