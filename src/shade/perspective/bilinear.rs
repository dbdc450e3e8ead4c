//! `Textured`'s bilinear span loop for opaque affine spans on a repeated
//! power-of-two `Rgb565` texture: the texture coordinates' sums stepped
//! as [`nearest`](super::nearest)'s affine loop steps them, each pixel's
//! sample by [`Pow2Rgb565::bilinear_fine`] from the fractions (on a
//! 64-bit host `bilinear_packed`, red and green blended together), the
//! last four texels kept across the span (`Quad`, `PackedQuad`).

use super::nearest::scaled_sum;
use super::{depth16, SpanInput};
use crate::shader::TriangleSpans;
#[cfg(target_pointer_width = "64")]
use crate::texture::PackedQuad;
#[cfg(not(target_pointer_width = "64"))]
use crate::texture::Quad;
use crate::texture::{FromTexel, Pow2Rgb565};
use fixed::types::I16F16;

impl<C> TriangleSpans<'_, C, [I16F16; 2]> {
    /// The steps of the texture coordinates' sums of
    /// [`SpanInput::run_bilinear_affine`], the same for every span of the
    /// triangle in the tile: taken once for them.
    #[inline(always)]
    pub(crate) fn bilinear_steps(&self) -> [u64; 2] {
        let p = self.setup;
        let [[d1u, d1v], [d2u, d2v]] = p.dvar.map(|d| d.map(I16F16::to_bits));
        let [_, p1, p2] = &p.planes;
        let g = (p1.step(), p2.step());
        [
            scaled_sum::<20>((d1u, d2u), g, 0),
            scaled_sum::<20>((d1v, d2v), g, 0),
        ]
    }
}

impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// The opaque affine loop ([`run_opaque`](Self::run_opaque) with
    /// affine weights) for [`Textured`](crate::shader::Textured) with
    /// bilinear filtering on a repeated power-of-two `Rgb565` texture
    /// `t`, the sums' `steps` from
    /// [`TriangleSpans::bilinear_steps`]: the same bits, in a loop of its
    /// own ([`bilinear_span`]). Each sum is `2^20 (d1 B1 + d2 B2) + 2^32
    /// f0` modulo 2^64, whose high word is the coordinate's fraction to
    /// 32 bits, as `nearest_span`'s affine loop takes it.
    #[inline(always)]
    pub(crate) fn run_bilinear_affine(self, t: &Pow2Rgb565<'_>, steps: [u64; 2]) -> u32 {
        let p = self.setup;
        let [f0u, f0v] = p.fine0.map(|f| f.to_bits() as u32);
        let [[d1u, d1v], [d2u, d2v]] = p.dvar.map(|d| d.map(I16F16::to_bits));
        let [_, b1, b2] = self.planes;
        let s = BilinearSpan {
            sums: [
                scaled_sum::<20>((d1u, d2u), (b1, b2), f0u),
                scaled_sum::<20>((d1v, d2v), (b1, b2), f0v),
            ],
            steps,
            z: self.z,
            gz: self.gz,
        };
        bilinear_span(self.color, self.depth, t, &s)
    }
}

/// What [`bilinear_span`] reads: the texture coordinates' sums at the
/// first pixel and their steps, depth (as `z << 2`) and its step.
struct BilinearSpan {
    sums: [u64; 2],
    steps: [u64; 2],
    z: u32,
    gz: u32,
}

/// The loop of [`SpanInput::run_bilinear_affine`], out of line as
/// `nearest_span` is: inlined beside the shading function's other loops,
/// its values would share their registers.
#[inline(never)]
fn bilinear_span<C: FromTexel>(
    color: &mut [C],
    depth: &mut [u16],
    t: &Pow2Rgb565<'_>,
    s: &BilinearSpan,
) -> u32 {
    // On a 64-bit host, the texels cut to their count (read unchecked)
    // and the blend with red and green packed.
    #[cfg(target_pointer_width = "64")]
    let (Some(t), mut quad) = (&t.cut(), PackedQuad::NONE) else {
        return 0;
    };
    #[cfg(not(target_pointer_width = "64"))]
    let mut quad = Quad::NONE;
    let [mut su, mut sv] = s.sums;
    let [gu, gv] = s.steps;
    let (mut z, gz) = (s.z, s.gz);
    let mut n = 0;
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if zz <= *d {
            let (fu, fv) = ((su >> 32) as u32, (sv >> 32) as u32);
            #[cfg(target_pointer_width = "64")]
            let rgb = t.bilinear_packed(fu, fv, &mut quad);
            #[cfg(not(target_pointer_width = "64"))]
            let rgb = t.bilinear_fine(fu, fv, &mut quad);
            *c = C::from_rgb888(rgb);
            *d = zz;
            n += 1;
        }
        su = su.wrapping_add(gu);
        sv = sv.wrapping_add(gv);
        z = z.wrapping_add(gz);
    }
    n
}
