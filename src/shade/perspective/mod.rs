//! The perspective set-up of a triangle for a fragment shader, and the
//! span loop behind [`SpanInput`] (the method is in [`crate::shader`]'s
//! docs, the stepping in [`crate::shader::span`]'s).
//!
//! Per triangle and tile: the three `1 / w` are scaled to
//! `q_i = 2^28 w_min / w_i` (all `2^28` for [`Perspective::Affine`]), and
//! three planes are set up over the screen exactly as the colour planes of
//! the Gouraud path ([`Basis`]): `Q` through `(q0, q1, q2)`,
//! `B1` through `(0, q1, 0)`, `B2` through `(0, 0, q2)`. Their gradients are
//! rounded to whole units of `2^-28`, clamped to ±2^40 like every
//! attribute's (only slivers reach that), and each span starts from the
//! planes evaluated in `i64`.
//!
//! At a sample pixel the weights `b1 = B1 / Q`, `b2 = B2 / Q` come from one
//! 32-bit reciprocal ([`weights`]); then each varying is
//! `a0 + (b1 (a1 - a0) + b2 (a2 - a0)) / 2^16` in `i64` (on ARMv6-M, which
//! has no 64-bit product, the same bits in `i32` halves: [`lerp32`](lerp::lerp32)), and
//! each colour channel the same in `i32`. In [`Perspective::Affine`] the
//! planes `B1`, `B2` are the weights, in units of 2^-28, and each varying
//! is `a0 + (B1 (a1 - a0) + B2 (a2 - a0)) / 2^28` rounded once
//! ([`PerspectiveSetup::values_affine`]): linear along a span, so a loop may
//! step its sum; the colour of an opaque draw there is the Gouraud
//! shading's, from colour planes set up beside
//! ([`ColourPlanes`](crate::shade::ColourPlanes)).
//! Between samples (quasi-perspective modes)
//! varyings and colour step linearly in wrapping `i32`, exact modulo 2^32,
//! with steps from a table of reciprocals of the segment length; the next
//! sample starts again from exact values, so nothing drifts past a
//! segment.
//!
//! This file sets the triangle up ([`PerspectiveSetup`]), `plane` its
//! three planes and `lerp` the 32-bit forms of a varying's value;
//! `barycentric` turns the planes into the weights of a pixel; `span` is the
//! loop that walks a span's pixels with them ([`SpanInput`]'s methods and
//! the [`Output`] that says how fragments are tested and written);
//! `nearest` and `bilinear` are the built-in textured shaders' loops of
//! their own (nearest texels in every mode, bilinear ones in affine
//! spans, the texture coordinates' sums stepped there).

use super::{depth16, Basis, Corners, DepthTest, SpanPos, TriangleSetup, Z_FRAC};
use crate::scene::Blend;
use crate::shader::span::{Interpolated, PixelFn, PutPixel, SpanInput};
use crate::shader::{Perspective, Varyings};
use crate::texture::Texture;
use fixed::types::I16F16;

mod barycentric;
mod bilinear;
mod lerp;
mod nearest;
mod plane;
mod quasi;
mod span;
mod values;

use values::{STEPPED, STEP_AFFINE};

pub(crate) use barycentric::{signed_weights, weights};
#[cfg(not(target_pointer_width = "64"))]
pub(crate) use nearest::SHORT_SPANS;
pub(crate) use nearest::{MASKED_INDEX, MASKED_TEXELS};
pub(crate) use span::{
    colour_constants, span_input, Output, AFFINE, AFFINE_SUMS, CLAMPED, COLOUR_LOOP, FLAT_Q,
    LOOPS32, SHIFTED,
};

use lerp::{FIT_PRODUCTS, NARROW_MULTIPLY};
#[cfg(not(microraster_narrow_multiply))]
use plane::small_planes;
use plane::{scale_q, scale_q32, wide_planes_apart, WidePlane};
#[cfg(microraster_narrow_multiply)]
use {crate::math::Recip16, plane::small_planes_split_by};

/// `1 / w` of the nearest vertex, scaled.
const Q_ONE: i64 = 1 << 28;
/// Span starts are clamped to this (the exact values are at most
/// [`Q_ONE`]; the margin holds the gradients' rounding).
const Q_MAX: i64 = 1 << 29;

/// A triangle ready for a fragment shader: its corners, their clip-space
/// `w` and varyings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShaderTriangle<'a, V> {
    /// Index of the triangle's draw in the scene.
    pub draw: usize,
    pub corners: Corners<'a>,
    pub w: [i32; 3],
    pub var: [V; 3],
}

/// A triangle's perspective set-up.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PerspectiveSetup<V> {
    /// Index of the triangle's draw in the scene.
    draw: usize,
    depth: TriangleSetup,
    /// `Q`, `B1`, `B2`.
    planes: [WidePlane; 3],
    var: [V; 3],
    /// The varyings' differences `a1 - a0`, `a2 - a0`, wrapped to 16.16
    /// bits (see [`values_fit`](Self::values_fit)).
    dvar: [V; 2],
    /// Each varying's `a0 · 2^16 + 2^15`, wrapped: the start of its
    /// fraction to 32 bits (see [`values_fit`](Self::values_fit)).
    fine0: V,
    /// Every difference of `dvar` is exact (none wrapped): the opaque span
    /// loops may take them ([`fits`](Self::fits)).
    fits: bool,
    /// The provoking vertex's colour.
    flat: [u8; 3],
    /// No gradient of `planes` was clamped: span starts in `i32`
    /// ([`WidePlane::at32`]). Only on 32-bit targets (see
    /// [`narrow`](Self::narrow)).
    #[cfg(not(target_pointer_width = "64"))]
    narrow: bool,
    /// Per channel: `c0 · 2^16 + 2^15` (the rounding bias), `c1 - c0`,
    /// `c2 - c0`, ready for the span loop.
    pub(super) color: [[i32; 3]; 3],
    /// On a 64-bit host, red and green of `color`'s three rows packed in
    /// one word each (red from bit 40, green from bit 8 without varyings,
    /// else from bit 0): see
    /// [`color_convex`](Self::color_convex).
    #[cfg(target_pointer_width = "64")]
    color_rg: [u64; 3],
    /// On a 64-bit host, blue of `color`'s three rows shifted up by 8
    /// bits, in wrapping `u32`: see [`color_convex`](Self::color_convex).
    #[cfg(target_pointer_width = "64")]
    color_b: [u32; 3],
}

impl<V: Varyings> PerspectiveSetup<V> {
    #[inline(always)]
    pub(crate) fn new(t: &ShaderTriangle<'_, V>, affine: bool) -> Self {
        // Shaders with varyings on 32-bit targets take the small
        // triangles' narrow planes ([`small_planes`]); the others keep the
        // set-up of before, statement for statement: with the small path
        // beside it in one function, `fill-gouraud-exact` took 67.86 ->
        // 73.75 instructions per fragment on the Cortex-M3 (its loop's
        // registers).
        if V::LEN > 0 && cfg!(not(target_pointer_width = "64")) {
            Self::new_small(t, affine)
        } else {
            Self::new_wide(t, affine)
        }
    }

    /// The vertices' perspective weights `q` (all [`Q_ONE`] when affine).
    #[inline(always)]
    fn perspective_q(t: &ShaderTriangle<'_, V>, affine: bool) -> [i64; 3] {
        // The arrays are written out rather than mapped: each `map` was
        // an out-of-line call per triangle and tile.
        if affine {
            [Q_ONE; 3]
        } else if NARROW_MULTIPLY {
            // ARMv6-M: the same weights in 32-bit words. Each `w` of at
            // least 1 is below 2^31 (an `i32`), so that `scale_q` takes
            // `scale_q32` for every vertex: its 64-bit range tests and
            // the 64-bit minimum left out.
            let w = [
                t.w[0].max(1) as u32,
                t.w[1].max(1) as u32,
                t.w[2].max(1) as u32,
            ];
            let wmin = w[0].min(w[1]).min(w[2]);
            [
                scale_q32(wmin, w[0]),
                scale_q32(wmin, w[1]),
                scale_q32(wmin, w[2]),
            ]
        } else {
            // Vertices reaching the shader have w >= W_MIN - 1 > 0 (the
            // clipper's round-off); `max(1)` only keeps this total.
            let w = [
                (t.w[0] as i64).max(1),
                (t.w[1] as i64).max(1),
                (t.w[2] as i64).max(1),
            ];
            let wmin = w[0].min(w[1]).min(w[2]);
            [
                scale_q(wmin, w[0]),
                scale_q(wmin, w[1]),
                scale_q(wmin, w[2]),
            ]
        }
    }

    /// The varyings' differences from vertex 0, vertex 0's values with
    /// 16 more fraction bits and a half added, and whether the differences
    /// fit `i32`.
    #[inline(always)]
    fn differences(t: &ShaderTriangle<'_, V>) -> ([V; 2], V, bool) {
        // Once per triangle, in `i32` when they fit (every mesh's but
        // texture coordinates repeated tens of thousands of times across
        // one triangle).
        let mut dvar = [V::zeroed(); 2];
        let mut fits = true;
        let mut fine0 = V::zeroed();
        for (o, a0) in fine0.as_mut_slice().iter_mut().zip(t.var[0].as_slice()) {
            *o = I16F16::from_bits((a0.to_bits() << 16).wrapping_add(1 << 15));
        }
        for (d, a) in dvar.iter_mut().zip(&t.var[1..]) {
            for ((o, a), a0) in d
                .as_mut_slice()
                .iter_mut()
                .zip(a.as_slice())
                .zip(t.var[0].as_slice())
            {
                let (v, wrapped) = a.to_bits().overflowing_sub(a0.to_bits());
                fits &= !wrapped;
                *o = I16F16::from_bits(v);
            }
        }
        (dvar, fine0, fits)
    }

    /// Vertex 0's colour channels in 16.16 with a half added, and the
    /// other two vertices' differences from it.
    #[inline(always)]
    fn colour_differences(t: &ShaderTriangle<'_, V>) -> [[i32; 3]; 3] {
        let [v0, v1, v2] = t.corners.0;
        let (c0, c1, c2) = (v0.color(), v1.color(), v2.color());
        let d = |a: [u8; 3], k: usize| a[k] as i32 - c0[k] as i32;
        [
            [
                ((c0[0] as i32) << 16) + (1 << 15),
                ((c0[1] as i32) << 16) + (1 << 15),
                ((c0[2] as i32) << 16) + (1 << 15),
            ],
            [d(c1, 0), d(c1, 1), d(c1, 2)],
            [d(c2, 0), d(c2, 1), d(c2, 2)],
        ]
    }

    /// [`new`](Self::new) for shaders with varyings on 32-bit targets.
    #[inline(always)]
    fn new_small(t: &ShaderTriangle<'_, V>, affine: bool) -> Self {
        let f = Basis::new(&t.corners.points());
        let q = Self::perspective_q(t, affine);
        let (dvar, fine0, fits) = Self::differences(t);
        // ARMv6-M: the area's reciprocal made once for the perspective
        // planes and depth's, whose gradients it divides in two digits
        // each (`TriangleSetup::depth_small`) where the general set-up
        // made one of its own and three digits of 64-bit partial
        // quotients: the same planes. `demo-textured-lit` 13,690,964 ->
        // 13,376,636 instructions (all-scenes build), the shader fills
        // within 0.3 a fragment (their loops' registers moved).
        #[cfg(microraster_narrow_multiply)]
        let ((planes, narrow), depth) = match &f.small {
            Some(s) => {
                let r = Recip16::new_small(s.area);
                let planes = match small_planes_split_by(&f, s, &r, q) {
                    Some(planes) => (planes, true),
                    None => wide_planes_apart(&f, q),
                };
                let depth = TriangleSetup::depth_small(&f, s, r, &t.corners)
                    .unwrap_or_else(|| TriangleSetup::with_basis(&f, &t.corners, false));
                (planes, depth)
            }
            None => (
                wide_planes_apart(&f, q),
                TriangleSetup::with_basis(&f, &t.corners, false),
            ),
        };
        // A small triangle's planes when every gradient is below 2^31:
        // none clamped, so the planes are narrow; the others' tested.
        #[cfg(not(microraster_narrow_multiply))]
        #[cfg_attr(target_pointer_width = "64", allow(unused_variables))]
        let (planes, narrow) = match small_planes(&f, q) {
            Some(planes) => (planes, true),
            None => wide_planes_apart(&f, q),
        };
        #[cfg(not(microraster_narrow_multiply))]
        let depth = TriangleSetup::with_basis(&f, &t.corners, false);
        Self {
            draw: t.draw,
            depth,
            planes,
            #[cfg(not(target_pointer_width = "64"))]
            narrow,
            var: t.var,
            dvar,
            fine0,
            fits,
            flat: t.corners.0[0].color(),
            color: Self::colour_differences(t),
            #[cfg(target_pointer_width = "64")]
            color_rg: [0; 3],
            #[cfg(target_pointer_width = "64")]
            color_b: [0; 3],
        }
    }

    /// [`new`](Self::new) for the others: the set-up of before.
    #[inline(always)]
    fn new_wide(t: &ShaderTriangle<'_, V>, affine: bool) -> Self {
        let f = Basis::new(&t.corners.points());
        let q = Self::perspective_q(t, affine);
        // The colours written out here, not by `colour_differences`: with
        // it, x86-64's `demo-textured-lit` took 7,634,978 -> 7,672,415
        // instructions and `fill-lit-exact` 128.21 -> 130.31 a fragment.
        let [v0, v1, v2] = t.corners.0;
        let (c0, c1, c2) = (v0.color(), v1.color(), v2.color());
        let d = |a: [u8; 3], k: usize| a[k] as i32 - c0[k] as i32;
        // The 32-bit gradients of small triangles only for shaders with
        // varyings: with them, `Gouraud`'s long-span loops compiled worse
        // on the Cortex-M3 (BENCHMARKS.md).
        let small = V::LEN > 0;
        let (dvar, fine0, fits) = Self::differences(t);
        #[allow(unused_mut)]
        let mut s = Self {
            draw: t.draw,
            depth: TriangleSetup::with_basis(&f, &t.corners, false),
            planes: [
                WidePlane::new(&f, q, small),
                WidePlane::new(&f, [0, q[1], 0], small),
                WidePlane::new(&f, [0, 0, q[2]], small),
            ],
            #[cfg(not(target_pointer_width = "64"))]
            narrow: false,
            var: t.var,
            dvar,
            fine0,
            fits,
            flat: t.corners.0[0].color(),
            color: [
                [
                    ((c0[0] as i32) << 16) + (1 << 15),
                    ((c0[1] as i32) << 16) + (1 << 15),
                    ((c0[2] as i32) << 16) + (1 << 15),
                ],
                [d(c1, 0), d(c1, 1), d(c1, 2)],
                [d(c2, 0), d(c2, 1), d(c2, 2)],
            ],
            #[cfg(target_pointer_width = "64")]
            color_rg: {
                // Two's complement lanes: the packed sums are exact
                // modulo 2^64 (see `color_convex`).
                // Green from bit 8 for a shader without varyings
                // (`Gouraud`), whose green byte is then the top of the low
                // half; from bit 0 for the others (`TexturedLit`, whose
                // loop takes the form of before: x86-64
                // `knot1k-textured-lit` +11 K with green and blue moved up).
                let g = if V::LEN == 0 { 8 } else { 0 };
                let pack =
                    |hi: i32, lo: i32| ((hi as i64) << 40).wrapping_add((lo as i64) << g) as u64;
                let base = |k: usize| ((c0[k] as i32) << 16) + (1 << 15);
                [
                    pack(base(0), base(1)),
                    pack(d(c1, 0), d(c1, 1)),
                    pack(d(c2, 0), d(c2, 1)),
                ]
            },
            // Only where `color_convex` reads it (no varyings): the
            // textured frames' set-up without it.
            #[cfg(target_pointer_width = "64")]
            color_b: if V::LEN == 0 {
                [
                    (((c0[2] as u32) << 16) + (1 << 15)) << 8,
                    (d(c1, 2) as u32) << 8,
                    (d(c2, 2) as u32) << 8,
                ]
            } else {
                [0; 3]
            },
        };
        #[cfg(not(target_pointer_width = "64"))]
        {
            s.narrow = s.planes.iter().all(WidePlane::exact);
        }
        s
    }

    /// Whether span starts are evaluated in `i32` ([`WidePlane::at32`]):
    /// on 32-bit targets, whose 64-bit products and clamps take several
    /// instructions each, when no gradient was clamped (demo-textured-lit
    /// -1.9 % on the Cortex-M3). Never on a 64-bit host, where they are
    /// single instructions and the test per triangle and the branch per
    /// span cost more than they save (+2.4 % there; +1.4 % with the flag
    /// kept in the record but never set).
    #[inline(always)]
    fn narrow(&self) -> bool {
        #[cfg(not(target_pointer_width = "64"))]
        return self.narrow;
        #[cfg(target_pointer_width = "64")]
        false
    }

    /// Whether the opaque span loops may take the triangle: its varyings'
    /// differences fit `i32` ([`values_fit`](Self::values_fit)). A
    /// triangle whose do not takes the general loop, which computes them
    /// in `i64`.
    #[inline(always)]
    pub(crate) fn fits(&self) -> bool {
        V::LEN == 0 || !FIT_PRODUCTS || self.fits
    }

    /// [`fits`](Self::fits) for the opaque affine loops, which take the
    /// differences of `dvar` on every target
    /// ([`values_affine`](Self::values_affine), `nearest_span`): there
    /// they must all be exact.
    #[inline(always)]
    pub(crate) fn fits_affine(&self) -> bool {
        V::LEN == 0 || self.fits
    }

    /// Index of the triangle's draw in the scene.
    #[inline(always)]
    pub(crate) fn draw(&self) -> usize {
        self.draw
    }

    /// The provoking vertex's colour.
    #[inline(always)]
    pub(crate) fn flat(&self) -> [u8; 3] {
        self.flat
    }
}

#[cfg(test)]
mod tests {
    use super::lerp::{fine_fit, lerp32, lerp_fit};
    use super::plane::*;
    use super::*;
    use crate::shade::small::Small;

    /// The `i64` formula of `values`: `a0 + (d1 b1 + d2 b2 + 2^15) >> 16`
    /// with `d1 = a1 - a0`, `d2 = a2 - a0`.
    fn wide([a0, a1, a2]: [i32; 3], (b1, b2): (i32, i32)) -> i32 {
        let base = a0 as i64;
        let (d1, d2) = (a1 as i64 - base, a2 as i64 - base);
        (base + ((d1 * b1 as i64 + d2 * b2 as i64 + (1 << 15)) >> 16)) as i32
    }

    /// Three vertex values: the ends of the range, small ones, or any.
    fn values(next: &mut impl FnMut(u64) -> u64) -> [i32; 3] {
        let edges = [i32::MIN, i32::MIN + 1, -65_536, -1, 0, 1, 65_535, i32::MAX];
        let mut a = [0i32; 3];
        for v in &mut a {
            *v = match next(4) {
                0 => edges[next(edges.len() as u64) as usize],
                1 => next(1 << 18) as i32 - (1 << 17),
                _ => next(1 << 32) as u32 as i32,
            };
        }
        a
    }

    /// Weights of every mode: exact in `0..=2^16` (summing to `2^16` or
    /// not), affine `B >> 12` of either sign.
    fn weights(next: &mut impl FnMut(u64) -> u64) -> (i32, i32) {
        match next(3) {
            0 => (next(65_537) as i32, next(65_537) as i32),
            1 => {
                let b1 = next(65_537) as i32;
                (b1, 65_536 - b1)
            }
            _ => (
                next(1 << 18) as i32 - (1 << 17),
                next(1 << 18) as i32 - (1 << 17),
            ),
        }
    }

    #[test]
    fn lerp32_matches_the_wide_formula() {
        let mut next = crate::testing::rng();
        for _ in 0..300_000 {
            let a = values(&mut next);
            let b1 = next(65_537) as i32;
            let b2 = match next(3) {
                0 => 65_536 - b1,
                _ => next(65_537) as i32,
            };
            let w = (b1, b2);
            assert_eq!(lerp32(a[0], a[1], a[2], w), wide(a, w), "{a:?} {w:?}");
        }
    }

    /// `lerp_fit` gives the `i64` formula of `values` wherever the
    /// differences fit `i32`, for the weights of every mode (exact in
    /// `0..=2^16`, affine `B >> 12` of either sign).
    #[test]
    fn lerp_fit_matches_the_wide_formula() {
        let mut next = crate::testing::rng();
        let mut checked = 0;
        for _ in 0..300_000 {
            let a = values(&mut next);
            let (Some(d1), Some(d2)) = (a[1].checked_sub(a[0]), a[2].checked_sub(a[0])) else {
                continue;
            };
            let w = weights(&mut next);
            assert_eq!(lerp_fit(a[0], d1, d2, w), wide(a, w), "{a:?} {w:?}");
            checked += 1;
        }
        assert!(checked > 100_000, "{checked}");
    }

    /// `fine_fit`'s bits 16 to 31 are the low 16 bits of the `i64`
    /// formula's value, for any differences (wrapped when they do not fit)
    /// and the weights of every mode.
    #[test]
    fn fine_fit_gives_the_value_s_low_bits() {
        let mut next = crate::testing::rng();
        for _ in 0..300_000 {
            let a = values(&mut next);
            let w = weights(&mut next);
            let f0 = (a[0] << 16).wrapping_add(1 << 15);
            let fine = fine_fit(f0, a[1].wrapping_sub(a[0]), a[2].wrapping_sub(a[0]), w);
            assert_eq!(fine as u32 >> 16, wide(a, w) as u32 & 0xFFFF, "{a:?} {w:?}");
        }
    }

    /// The `i32` span starts of 32-bit targets give the `i64` ones at
    /// every span start of a triangle whose gradients were not clamped,
    /// large triangles and far vertices included.
    #[test]
    fn narrow_span_starts_match() {
        use crate::raster::{scanline::spans, PixelRect, SubPoint};
        let mut next = crate::testing::rng();
        let mut checked = 0u64;
        for n in 0..4_000 {
            let (range, offset) = match n % 3 {
                0 => (4_000, 0),
                1 => (1 << 19, 1 << 18),
                _ => (600, 0),
            };
            let mut p = || SubPoint::new(next(range) as i32 - offset, next(range) as i32 - offset);
            let v = [p(), p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let f = Basis::new(&v);
            let mut q = || 1 + next(Q_ONE as u64) as i64;
            let q = [q(), q(), q()];
            let planes = [
                WidePlane::new(&f, q, false),
                WidePlane::new(&f, [0, q[1], 0], false),
                WidePlane::new(&f, [0, 0, q[2]], false),
            ];
            if !planes.iter().all(WidePlane::exact) {
                continue;
            }
            const M: i32 = Q_MAX as i32;
            spans(&v, PixelRect::new(0, 0, 4096, 4096), |j, x0, _| {
                assert_eq!(planes[0].at32(x0, j, 1, M), planes[0].at(x0, j, 1, Q_MAX));
                assert_eq!(
                    planes[0].at32_unclamped(x0, j).max(1),
                    planes[0].at(x0, j, 1, Q_MAX)
                );
                for p in &planes[1..] {
                    assert_eq!(p.at32(x0, j, -M, M), p.at(x0, j, -Q_MAX, Q_MAX), "{v:?}");
                    assert_eq!(p.at32_unclamped(x0, j), p.at(x0, j, -Q_MAX, Q_MAX));
                }
                checked += 1;
            });
        }
        assert!(checked > 100_000, "{checked} span starts");
    }

    /// Calls `each` for `count` random triangles with edges below 2^10, 64
    /// or 8 sub-pixels anywhere in the guard band, those with a small
    /// basis: their vertices, basis, its small part and perspective values
    /// `q` (all one, one differing, or all random).
    fn each_small_case(
        count: u32,
        mut each: impl FnMut(&[crate::raster::SubPoint; 3], &Basis, &Small, [i64; 3]),
    ) {
        use crate::raster::SubPoint;
        let mut next = crate::testing::rng();
        for n in 0..count {
            let edge = match n % 3 {
                0 => 1 << 10,
                1 => 64,
                _ => 8,
            };
            let o = SubPoint::new(
                next(1 << 19) as i32 - (1 << 18),
                next(1 << 19) as i32 - (1 << 18),
            );
            let mut p = || {
                SubPoint::new(
                    o.x + next(2 * edge) as i32 - edge as i32,
                    o.y + next(2 * edge) as i32 - edge as i32,
                )
            };
            let v = [o, p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let f = Basis::with_small(&v, true);
            let Some(small) = &f.small else {
                continue;
            };
            let q = match next(4) {
                0 => [Q_ONE; 3],
                1 => [Q_ONE, next(Q_ONE as u64 + 1) as i64, Q_ONE],
                _ => {
                    let mut q = || next(Q_ONE as u64 + 1) as i64;
                    [q(), q(), q()]
                }
            };
            each(&v, &f, small, q);
        }
    }

    /// `small_gradient` gives `Basis::gradients`' quotients (those of
    /// `Small::div_round_wide`) for every small triangle's perspective
    /// planes whose gradients are below 2^31, slivers and far vertices
    /// included, and declines the others.
    #[test]
    fn small_gradients_match_the_wide_ones() {
        let mut checked = 0u32;
        each_small_case(200_000, |v, f, small, q| {
            let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
            for values in [q, [0, q[1], 0], [0, 0, q[2]]] {
                let (gx, gy) = f.gradients(values, 0);
                let (d1, d2) = (
                    (values[1] - values[0]) as i32,
                    (values[2] - values[0]) as i32,
                );
                let n = [mul(d1, y2) - mul(d2, y1), mul(d2, x1) - mul(d1, x2)];
                for (g, n) in [(gx, n[0]), (gy, n[1])] {
                    match small_gradient(small, n) {
                        Some(s) => {
                            assert_eq!(s as i64, g, "{v:?} {values:?}");
                            checked += 1;
                        }
                        None => assert!(g.abs() >= 1 << 31, "{v:?} {values:?}"),
                    }
                }
            }
        });
        assert!(checked > 500_000, "{checked} gradients");
    }

    /// ARMv6-M's `small_planes_split` (split products, the area's
    /// reciprocal) gives `small_planes_wide`'s planes, or declines as it
    /// does, for every small triangle, slivers and far vertices included.
    #[test]
    fn split_small_planes_match() {
        let (mut declined, mut checked) = (0u32, 0u32);
        each_small_case(100_000, |v, f, small, q| {
            match (
                small_planes_split(f, small, q),
                small_planes_wide(f, small, q),
            ) {
                (Some(a), Some(b)) => {
                    // The constants' low 32 bits: all that narrow planes read.
                    for (a, b) in a.iter().zip(&b) {
                        let (ak, bk) = (a.k as i32, b.k as i32);
                        assert_eq!((a.gx, a.gy, ak), (b.gx, b.gy, bk), "{v:?} {q:?}");
                    }
                    checked += 1;
                }
                (None, None) => declined += 1,
                (a, b) => panic!("{v:?} {q:?}: {a:?} {b:?}"),
            }
        });
        assert!(declined > 0 && checked > 50_000, "{declined} {checked}");
    }

    /// ARMv6-M's `wide_gradients_split` gives `Basis::gradients`' quotients
    /// for the perspective planes of triangles of any size in the guard
    /// band, slivers included.
    #[test]
    fn split_wide_gradients_match() {
        use crate::raster::SubPoint;
        let mut next = crate::testing::rng();
        let mut checked = 0u32;
        for n in 0..200_000u32 {
            let edge = [1u64 << 18, 1 << 12, 1 << 5][n as usize % 3];
            let o = SubPoint::new(
                next(1 << 19) as i32 - (1 << 18),
                next(1 << 19) as i32 - (1 << 18),
            );
            let mut p = || {
                let c = |a: i32, d: u64| (a + d as i32 - edge as i32).clamp(-(1 << 18), 1 << 18);
                SubPoint::new(c(o.x, next(2 * edge)), c(o.y, next(2 * edge)))
            };
            let v = [o, p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let f = Basis::with_small(&v, false);
            let mut q = || match next(4) {
                0 => Q_ONE,
                1 => 0,
                _ => next(Q_ONE as u64 + 1) as i64,
            };
            let q = [q(), q(), q()];
            for values in [q, [0, q[1], 0], [0, 0, q[2]]] {
                let want = f.gradients(values, 0);
                assert_eq!(wide_gradients_split(&f, values), want, "{v:?} {values:?}");
            }
            checked += 1;
        }
        assert!(checked > 150_000, "{checked}");
    }

    /// ARMv6-M's `small_wide_gradients_digits` gives `Basis::gradients`'
    /// quotients for small triangles' perspective planes, slivers and far
    /// vertices included.
    #[test]
    fn small_wide_gradients_match() {
        let mut checked = 0u32;
        each_small_case(100_000, |v, f, small, q| {
            for values in [q, [0, q[1], 0], [0, 0, q[2]]] {
                let want = f.gradients(values, 0);
                let got = small_wide_gradients_digits(f, small, values);
                assert_eq!(got, want, "{v:?} {values:?}");
            }
            checked += 1;
        });
        assert!(checked > 50_000, "{checked}");
    }

    /// `small_gradient_digits` gives `small_gradient`'s quotient (or
    /// `None`) for numerators across their range, up to the largest, and
    /// areas across theirs.
    #[test]
    fn gradient_digits_match() {
        let mut next = crate::testing::rng();
        let top = (1i64 << 39) - (1 << 29);
        for _ in 0..400_000 {
            let area = match next(3) {
                0 => 1 + next(64) as u32,
                1 => (1 << 21) - 1 - next(64) as u32,
                _ => 1 + next((1 << 21) - 1) as u32,
            };
            let small = Small {
                area: core::num::NonZeroU32::new(area).unwrap(),
                half: area / 2,
            };
            let n = match next(4) {
                0 => top - next(1 << 20) as i64,
                1 => (next(1 << 40) as i64).min(top),
                2 => next(1 << 20) as i64,
                _ => (((area as i64) << 27) - 2 + next(4) as i64).min(top),
            };
            let n = if next(2) == 0 { -n } else { n };
            // `n = h 2^16 + l`, `l` anywhere within 2^27 as `split_mul`'s
            // sums and differences.
            let k = next(1 << 11) as i64 - (1 << 10);
            let (h, l) = (
                (n >> 16) as i32 - k as i32,
                ((n & 0xFFFF) + (k << 16)) as i32,
            );
            let r = crate::math::Recip16::new_small(small.area);
            assert_eq!(
                small_gradient_digits(&r, small.half, (h, l)),
                small_gradient(&small, n),
                "{n} / {area}"
            );
        }
    }

    /// `small_planes_of` gives the planes of `WidePlane::new` (gradients and
    /// constants) for small triangles, slivers and far vertices included,
    /// whenever it gives any, and then none of them was clamped.
    #[test]
    fn small_planes_match_the_wide_ones() {
        let mut checked = 0u32;
        each_small_case(100_000, |v, f, small, q| {
            let Some(planes) = small_planes_of(f, small, q) else {
                return;
            };
            let wide = [
                WidePlane::new(f, q, false),
                WidePlane::new(f, [0, q[1], 0], false),
                WidePlane::new(f, [0, 0, q[2]], false),
            ];
            for (s, w) in planes.iter().zip(&wide) {
                assert!(w.exact(), "{v:?} {q:?}");
                assert_eq!((s.gx, s.gy, s.k), (w.gx, w.gy, w.k), "{v:?} {q:?}");
            }
            checked += 1;
        });
        assert!(checked > 50_000, "{checked} triangles");
    }

    /// The 32-bit long division of `scale_q` gives the 64-bit quotient.
    #[test]
    fn scale_q_matches_the_division() {
        let mut next = crate::testing::rng();
        let edges = [
            1i64,
            2,
            3,
            65_535,
            65_536,
            (1 << 30) - 1,
            1 << 30,
            (1 << 31) - 1,
        ];
        for _ in 0..300_000 {
            let w = match next(3) {
                0 => edges[next(edges.len() as u64) as usize],
                1 => 1 + next(1 << 22) as i64,
                _ => 1 + next((1 << 31) - 1) as i64,
            };
            let wmin = match next(3) {
                0 => w,
                1 => 1 + next(w as u64) as i64,
                _ => (w - next(16) as i64).max(1),
            };
            let expected = (wmin << 28) / w;
            assert_eq!(scale_q32(wmin as u32, w as u32), expected, "{wmin} / {w}");
            assert_eq!(scale_q(wmin, w), expected, "{wmin} / {w}");
            if wmin < w {
                let nz = core::num::NonZeroU32::new(w as u32).unwrap();
                let q = scale_q_digits(wmin as u32, nz) as i64;
                assert_eq!(q, expected, "{wmin} / {w}");
            }
        }
    }
}
