//! `Textured`'s bilinear span loop for opaque affine spans on a repeated
//! power-of-two `Rgb565` texture: the texture coordinates' sums stepped
//! as [`nearest`](super::nearest)'s affine loop steps them, each pixel's
//! sample by [`Pow2Rgb565::bilinear_fine`] from the fractions, the last
//! four texels kept across the span ([`Quad`]).

use super::{depth16, SpanInput};
use crate::math::mul_wide;
use crate::texture::{FromTexel, Pow2Rgb565, Quad};
use fixed::types::I16F16;

impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// The opaque affine loop ([`run_opaque`](Self::run_opaque) with
    /// affine weights) for [`Textured`](crate::shader::Textured) with
    /// bilinear filtering on a repeated power-of-two `Rgb565` texture
    /// `t`: the same bits, in a loop of its own ([`bilinear_span`]).
    #[inline(always)]
    pub(crate) fn run_bilinear_affine(self, t: &Pow2Rgb565<'_>) -> u32 {
        let p = self.setup;
        let [f0u, f0v] = p.fine0.map(|f| f.to_bits() as u32);
        let [[d1u, d1v], [d2u, d2v]] = p.dvar.map(|d| d.map(I16F16::to_bits));
        let [_, b1, b2] = self.planes;
        let [_, g1, g2] = self.steps;
        let s = BilinearSpan {
            sums: [
                affine_fraction((d1u, d2u), (b1, b2), f0u),
                affine_fraction((d1v, d2v), (b1, b2), f0v),
            ],
            steps: [
                affine_fraction((d1u, d2u), (g1, g2), 0),
                affine_fraction((d1v, d2v), (g1, g2), 0),
            ],
            z: self.z,
            gz: self.gz,
        };
        bilinear_span(self.color, self.depth, t, &s)
    }
}

/// `2^20 (d1 b1 + d2 b2) + 2^32 f0` modulo 2^64, of `d = (d1, d2)`, the
/// planes' values `b = (b1, b2)` and the fraction `f0` to 32 bits at the
/// first vertex: the affine loop's sum of a texture coordinate, whose
/// high word is the coordinate's fraction to 32 bits (see
/// `nearest_span`), or with the planes' steps and no `f0`, its step.
#[inline(always)]
fn affine_fraction((d1, d2): (i32, i32), (b1, b2): (i32, i32), f0: u32) -> u64 {
    (((mul_wide(d1, b1) + mul_wide(d2, b2)) as u64) << 20).wrapping_add((f0 as u64) << 32)
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
    let [mut su, mut sv] = s.sums;
    let [gu, gv] = s.steps;
    let (mut z, gz) = (s.z, s.gz);
    let mut quad = Quad::NONE;
    let mut n = 0;
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if zz <= *d {
            let (fu, fv) = ((su >> 32) as u32, (sv >> 32) as u32);
            *c = C::from_rgb888(t.bilinear_fine(fu, fv, &mut quad));
            *d = zz;
            n += 1;
        }
        su = su.wrapping_add(gu);
        sv = sv.wrapping_add(gv);
        z = z.wrapping_add(gz);
    }
    n
}
