//! The nearest-texel loops of opaque affine spans on a repeated
//! power-of-two `Rgb565` texture: on 64-bit hosts a triangle's spans in a
//! tile at once (`per_pair::affine_spans`: what is the same for all of
//! them read once, each span's start from the planes, then its pixels,
//! the texture coordinates' sums stepped), on 32-bit targets each span
//! through `nearest_span`'s affine loop.

use super::light::{Lit, Unlit};
use super::NearestConstants;
#[cfg(not(target_pointer_width = "64"))]
use super::{nearest_span, NearestSpan};
#[cfg(not(target_pointer_width = "64"))]
use crate::shade::perspective::span::AFFINE;
use crate::shade::ColourPlanes;
#[cfg(not(target_pointer_width = "64"))]
use crate::shader::SpanInput;
use crate::shader::TriangleSpans;
use crate::texture::FromTexel;
use fixed::types::I16F16;

/// The longest of `Textured`'s and `TexturedLit`'s opaque affine spans
/// on a repeated power-of-two `Rgb565` texture that take the shader's
/// opaque affine loop (`SpanInput::shade_affine`, inline in the renderer's
/// affine copy of its shading function) rather than their own
/// (`nearest_span`, out of line): the same bits, but a short span's
/// set-up for the call (its constants, sums and steps, the light's start)
/// cost more than the own loop saves on its pixels. On a mesh's spans of
/// 2.3 pixels on average, the textured frame in affine mode
/// (`demo-textured-lit-affine`) took on the Cortex-M3, with spans of at
/// most 4, 8, 16 and 1,000 pixels there, 7,410,927 -> 6,683,051,
/// 6,641,650, 6,637,165 and 6,640,150 instructions, the lit fill (spans of
/// up to 32) 85.64 -> 85.50 a fragment with 16, 88.66 with 1,000. With
/// 16: the Cortex-M4F's frame 7,438,626 -> 6,723,636 (its fill 90.94 ->
/// 90.99); with `Textured` in that frame, 5,215,333 -> 4,721,121 on the
/// M3 and 5,157,631 -> 4,777,409 on the M4F, the nearest fill 36.81 ->
/// 36.94 and 39.15 -> 39.42. None on ARMv6-M, where the frame took
/// 13,332,152 -> 14,000,279 even with spans of at most 2, as the opaque
/// affine loop takes more there a pixel. Not built for 64-bit hosts,
/// which take a triangle's spans at once (`per_pair`): their constants
/// are laid out for that function, not for `nearest_span`.
#[cfg(not(target_pointer_width = "64"))]
pub(crate) const SHORT_SPANS: Option<usize> = if cfg!(microraster_narrow_multiply) {
    None
} else {
    Some(16)
};

impl<C: FromTexel> TriangleSpans<'_, C, [I16F16; 2]> {
    /// `Textured`'s opaque affine spans, the texels as they are: the same
    /// bits as the opaque affine loop with `Textured`'s pixel. `c` from
    /// [`nearest_constants`](Self::nearest_constants) with `affine`.
    #[inline(always)]
    pub(crate) fn run_nearest_affine(self, c: &NearestConstants<'_>) -> u32 {
        #[cfg(target_pointer_width = "64")]
        return per_pair::affine_spans(per_pair::Spans::of(self), c, |_, _| Unlit);
        #[cfg(not(target_pointer_width = "64"))]
        self.each(|s| s.run_nearest_affine(c, None))
    }

    /// [`run_nearest_affine`](Self::run_nearest_affine) for
    /// `TexturedLit`: each texel modulated by the colour of the
    /// triangle's colour `planes` ([`ColourPlanes::start`], as the opaque
    /// affine loop takes it), stepped beside the texture coordinates.
    #[inline(always)]
    pub(crate) fn run_nearest_affine_lit(
        self,
        c: &NearestConstants<'_>,
        planes: &ColourPlanes,
    ) -> u32 {
        // Red and green packed, but for a sliver's planes
        // ([`ColourPlanes::wide`]), as the 64-bit Gouraud loop packs them.
        #[cfg(target_pointer_width = "64")]
        {
            use per_pair::{affine_spans, Spans};
            if !planes.wide() {
                return affine_spans(Spans::of(self), c, |x0, j| {
                    let (col, dc) = planes.start_inline(x0, j);
                    super::light::LitPacked::new(col, dc)
                });
            }
            affine_spans(Spans::of(self), c, |x0, j| {
                let (col, dc) = planes.start_inline(x0, j);
                Lit::<false>::new(col, dc)
            })
        }
        #[cfg(not(target_pointer_width = "64"))]
        self.each(|s| s.run_nearest_affine(c, Some(planes)))
    }
}

#[cfg(not(target_pointer_width = "64"))]
impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// One span of [`TriangleSpans::run_nearest_affine`] (`planes`
    /// `None`) or of [`TriangleSpans::run_nearest_affine_lit`], through
    /// `nearest_span`'s affine loop, on 32-bit targets, whose longer spans
    /// [`SHORT_SPANS`] sends here. The light's start before the span's record: the
    /// other way round, the record was kept across its call (Cortex-M3
    /// `demo-textured-lit-affine` 6,637,163 -> 6,723,603 instructions).
    #[inline(always)]
    pub(crate) fn run_nearest_affine(
        self,
        c: &NearestConstants<'_>,
        planes: Option<&ColourPlanes>,
    ) -> u32 {
        let record = || NearestSpan {
            c,
            sh: 0,
            z: self.z,
            planes: self.planes,
        };
        let Some(planes) = planes else {
            return nearest_span::<C, _, AFFINE>(self.color, self.depth, &record(), Unlit);
        };
        let (col, dc) = planes.start(self.x0, self.y);
        let light = Lit::<false>::new(col, dc);
        nearest_span::<C, _, AFFINE>(self.color, self.depth, &record(), light)
    }
}

/// A triangle's affine spans at once ([`affine_spans`](per_pair::affine_spans)), on 64-bit
/// hosts. 32-bit targets take each span through `nearest_span`: there
/// the pixel loop inlined beside the spans' took more registers than the
/// cores have, and `nearest_span` called from it (a call a span, its
/// constants read through a pointer) cost more a pair than it spared a
/// span. Per textured frame in affine mode (`demo-textured-lit-affine`),
/// with the per-pair function calling `nearest_span`: Cortex-M3 7,533,562
/// -> 7,723,662 instructions, Cortex-M4F 7,524,811 -> 7,771,535, ARMv6-M
/// 13,419,958 -> 13,749,777 (the lit fill 86.09 -> 85.20, 91.25 -> 90.56,
/// 132.30 -> 131.68 a fragment); with the pixel loop inlined, the
/// Cortex-M3's `fill-nearest-affine` 36.84 -> 39.30 a fragment.
#[cfg(target_pointer_width = "64")]
mod per_pair {
    use super::super::light::{Light, SpanLight};
    #[cfg(doc)]
    use super::super::MASKED_INDEX;
    use super::super::{at, masked_index, scaled_sum, NearestConstants};
    use crate::raster::Span;
    use crate::shade::perspective::{depth16, PerspectiveSetup, Z_FRAC};
    use crate::shade::Corners;
    use crate::shader::TriangleSpans;
    use crate::texture::FromTexel;
    use fixed::types::I16F16;

    /// What [`affine_spans`] reads of a [`TriangleSpans`]: its fields, taken
    /// out in the caller (given the whole record, which a call out of line
    /// keeps in memory, the renderer's affine copy of its shading function no
    /// longer knew that its other spans are opaque, and kept the general
    /// loops: 20 KB more of a Cortex-M4F firmware).
    pub(super) struct Spans<'a, C> {
        color: &'a mut [C],
        depth: &'a mut [u16],
        width: usize,
        ox: i32,
        oy: i32,
        found: &'a [Span],
        setup: &'a PerspectiveSetup<[I16F16; 2]>,
        corners: &'a Corners<'a>,
    }

    impl<'a, C> Spans<'a, C> {
        #[inline(always)]
        pub(super) fn of(s: TriangleSpans<'a, C, [I16F16; 2]>) -> Self {
            Self {
                color: s.color,
                depth: s.depth,
                width: s.width,
                ox: s.ox,
                oy: s.oy,
                found: s.found,
                setup: s.setup,
                corners: s.corners,
            }
        }
    }

    /// The spans of `spans` on the texture of `c` (its
    /// [`NearestConstants`], made with `affine`), each texel coloured by the
    /// light `light(x0, j)` gives for the span starting at `(x0, j)`. Out of
    /// line, one call a triangle and tile: a call a span (with its record of
    /// the span, the constants copied, the light's start in a call of its
    /// own) took about 250 x86-64 instructions a span of `knot1k-textured-lit`
    /// in affine mode, more than its pixels.
    ///
    /// Each fraction is the high word of `2^20 T` modulo 2^64
    /// (`PerspectiveSetup::values_affine`'s `T`, whose low 44 bits it keeps),
    /// which changes by the same step at every pixel: the plane values `B1`,
    /// `B2` change by their steps exactly along a span (their sums stay
    /// within `i32`, see `affine_sum`), so the stepped sums are the
    /// products' at every pixel. As [`MASKED_INDEX`] has it, each sum is `2^-20`
    /// of that, its fraction in bits 12 to 43 (the sum's low 20 bits are
    /// zeros: the same bits, modulo 2^44), shifted up by `log2(w)` for `u`
    /// and `log2(w h)` for `v` (at most 20, `MASKED_TEXELS`): bits 44 and up
    /// of `u`'s then hold the column in their low `log2(w)` bits, those of
    /// `v`'s the row times `w` in theirs from `log2(w)` to `log2(w h)`, and
    /// the texel's index is a few shifts and masks.
    #[inline(never)]
    pub(super) fn affine_spans<C: FromTexel, L: Light>(
        spans: Spans<'_, C>,
        c: &NearestConstants<'_>,
        light: impl Fn(i32, i32) -> L,
    ) -> u32 {
        let (color, depth, p) = (spans.color, spans.depth, spans.setup);
        let k = &c.k;
        // The texels cut to the count, a power of two (`nearest_constants`
        // checked that the slice holds them), here, so that the compiler
        // knows the length: an index masked by `m` then needs no bounds
        // check, `at & m <= m < m + 1`.
        let m = k[at::LAST] as usize;
        let Some(texels) = c.texels.get(..=m) else {
            return 0;
        };
        // The sums' shifts (`nearest_constants`): `log2(w)` for `u`,
        // `log2(w h)` for `v`.
        let (lu, lv) = (k[at::SHIFTS] & 63, k[at::SHIFTS + 1] & 63);
        // The sums' steps, the same for every span (`nearest_constants`).
        let step = |at: usize| (k[at + 1] as u64) << 32 | k[at] as u64;
        let (gu, gv, gz) = (step(at::GU), step(at::GV), k[at::DZ]);
        // The column's mask.
        let column = k[at::WIDTH].wrapping_sub(1);
        // `2^0 (d1 b1 + d2 b2) + 2^12 f0` modulo 2^64 (`MASKED_INDEX`'s
        // scale), shifted.
        let sum = |d1: usize, d2: usize, b: (i32, i32), f0: u32, l: u32| {
            scaled_sum::<0>((k[d1] as i32, k[d2] as i32), b, f0) << l
        };
        // The pixels that fail: the common path holds no count.
        let (mut pixels, mut fails) = (0, 0);
        for &Span { j, x0, x1 } in spans.found {
            // The spans lie inside the tile (the walk clips them to it).
            let row = (j - spans.oy) as usize * spans.width;
            let (a, b) = (
                row + (x0 - spans.ox) as usize,
                row + (x1 - spans.ox) as usize,
            );
            let (Some(color), Some(depth)) = (color.get_mut(a..b), depth.get_mut(a..b)) else {
                continue;
            };
            let mut z = (p.depth.z_start(spans.corners, x0, j) as u32) << (16 - Z_FRAC);
            let [_, b1, b2] = p.plane_starts(x0, j);
            let (mut su, mut sv) = (
                sum(at::D1U, at::D2U, (b1, b2), k[at::F0U], lu),
                sum(at::D1V, at::D2V, (b1, b2), k[at::F0V], lv),
            );
            let (mut light, light_steps) = light(x0, j).start();
            pixels += color.len() as u32;
            for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
                let zz = depth16(z);
                if zz <= *d {
                    let at = masked_index(su, sv, 44, column);
                    *c = light.texel(texels[at as usize & m]);
                    *d = zz;
                } else {
                    fails += 1;
                }
                su = su.wrapping_add(gu);
                sv = sv.wrapping_add(gv);
                z = z.wrapping_add(gz);
                light.step(&light_steps);
            }
        }
        pixels - fails
    }
}
