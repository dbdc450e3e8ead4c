//! The span loops of [`Textured`](super::Textured) and
//! [`TexturedLit`](super::TexturedLit): where a texel comes from
//! ([`Texels`], one kind per
//! [`Texture::sampler`](crate::texture::Texture::sampler), decided once
//! per triangle and tile), the pixel that colours it ([`TexelPixel`]), and
//! which loop each kind of span takes in each of the renderer's copies:
//! the general one ([`textured_spans`]), the affine one
//! ([`textured_affine_spans`]) and the quasi-perspective one
//! ([`textured_quasi_spans`]).

use super::modulate;
#[cfg(not(target_pointer_width = "64"))]
use crate::shade::perspective::SHORT_SPANS;
use crate::shade::perspective::{FLAT_Q, LOOPS32, MASKED_INDEX, MASKED_TEXELS, SHIFTED};
use crate::shader::{Interpolated, PixelFn, SpanInput, TriangleSpans};
use crate::texture::{rgb565_to_rgb888, FromTexel, Pow2Rgb565, Quad, Sampler, Texture};
use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;

/// Where a textured shader's texels come from, decided once per span:
/// the colour at raw 16.16 coordinates `(u, v)`, in 8 bits per channel
/// and in the target's format.
trait Texels {
    fn rgb(&mut self, u: i32, v: i32) -> [u8; 3];
    #[inline(always)]
    fn target<C: FromTexel>(&mut self, u: i32, v: i32) -> C {
        C::from_rgb888(self.rgb(u, v))
    }
    /// [`rgb`](Self::rgb) from the coordinates' fractions to 32 bits
    /// ([`Interpolated`]'s `fine`), where the texture is addressed by
    /// them alone (repeated, power-of-two sides); `None` otherwise.
    #[inline(always)]
    fn rgb_fine(&mut self, _fu: u32, _fv: u32) -> Option<[u8; 3]> {
        None
    }
    /// [`target`](Self::target) from the fractions, as
    /// [`rgb_fine`](Self::rgb_fine).
    #[inline(always)]
    fn target_fine<C: FromTexel>(&mut self, fu: u32, fv: u32) -> Option<C> {
        self.rgb_fine(fu, fv).map(C::from_rgb888)
    }
    /// [`rgb`](Self::rgb) modulated by `light` ([`modulate`]), in the
    /// target's format.
    #[inline(always)]
    fn lit<C: FromTexel>(&mut self, u: i32, v: i32, light: [u8; 3]) -> C {
        C::from_rgb888(modulate(self.rgb(u, v), light))
    }
    /// [`lit`](Self::lit) from the fractions, as
    /// [`rgb_fine`](Self::rgb_fine).
    #[inline(always)]
    fn lit_fine<C: FromTexel>(&mut self, fu: u32, fv: u32, light: [u8; 3]) -> Option<C> {
        self.rgb_fine(fu, fv)
            .map(|t| C::from_rgb888(modulate(t, light)))
    }
}

/// [`Sampler::NearestRgb565`]: the texel's bits go to the target as they
/// are where it is `Rgb565` ([`FromTexel`]).
#[derive(Clone, Copy)]
struct Nearest565<'t>(Pow2Rgb565<'t>);

impl Texels for Nearest565<'_> {
    #[inline(always)]
    fn rgb(&mut self, u: i32, v: i32) -> [u8; 3] {
        rgb565_to_rgb888(self.0.nearest(u, v))
    }
    #[inline(always)]
    fn target<C: FromTexel>(&mut self, u: i32, v: i32) -> C {
        C::from_rgb565(self.0.nearest(u, v))
    }
    #[inline(always)]
    fn rgb_fine(&mut self, fu: u32, fv: u32) -> Option<[u8; 3]> {
        Some(rgb565_to_rgb888(self.0.nearest_fine(fu, fv)))
    }
    #[inline(always)]
    fn target_fine<C: FromTexel>(&mut self, fu: u32, fv: u32) -> Option<C> {
        Some(C::from_rgb565(self.0.nearest_fine(fu, fv)))
    }
    #[inline(always)]
    fn lit<C: FromTexel>(&mut self, u: i32, v: i32, light: [u8; 3]) -> C {
        C::from_lit_rgb565(self.0.nearest(u, v), light)
    }
    #[inline(always)]
    fn lit_fine<C: FromTexel>(&mut self, fu: u32, fv: u32, light: [u8; 3]) -> Option<C> {
        Some(C::from_lit_rgb565(self.0.nearest_fine(fu, fv), light))
    }
}

/// [`Sampler::BilinearRgb565`], with the last four texels read (a span's
/// pixels reuse them while they fall between the same four).
#[derive(Clone, Copy)]
struct Bilinear565<'t>(Pow2Rgb565<'t>, Quad);

impl Texels for Bilinear565<'_> {
    #[inline(always)]
    fn rgb(&mut self, u: i32, v: i32) -> [u8; 3] {
        self.0.bilinear_reusing(u, v, &mut self.1)
    }
    #[inline(always)]
    fn rgb_fine(&mut self, fu: u32, fv: u32) -> Option<[u8; 3]> {
        Some(self.0.bilinear_fine(fu, fv, &mut self.1))
    }
}

/// [`Sampler::General`]: [`Texture::sample`].
impl Texels for &Texture<'_> {
    #[inline(always)]
    fn rgb(&mut self, u: i32, v: i32) -> [u8; 3] {
        self.sample(I16F16::from_bits(u), I16F16::from_bits(v))
    }
}

/// The pixel of [`Textured`](super::Textured) (`LIT` false: the texel, in the target's
/// format where it matches) and of [`TexturedLit`](super::TexturedLit) (`LIT`: the texel
/// modulated by the interpolated colour).
#[derive(Clone, Copy)]
struct TexelPixel<T, const LIT: bool>(T);

impl<C: FromTexel, T: Texels, const LIT: bool> PixelFn<[I16F16; 2], C> for TexelPixel<T, LIT> {
    #[inline(always)]
    fn pixel(&mut self, p: &Interpolated<[I16F16; 2]>) -> Option<C> {
        // The fractions where the loop has them and the texture is
        // addressed by them (then the varyings go unused, and their sums
        // are not computed).
        if let Some([fu, fv]) = p.fine {
            let (fu, fv) = (fu.to_bits() as u32, fv.to_bits() as u32);
            let c = if LIT {
                self.0.lit_fine(fu, fv, p.rgb())
            } else {
                self.0.target_fine(fu, fv)
            };
            if c.is_some() {
                return c;
            }
        }
        let [u, v] = p.varyings;
        let (u, v) = (u.to_bits(), v.to_bits());
        Some(if LIT {
            self.0.lit(u, v, p.rgb())
        } else {
            self.0.target(u, v)
        })
    }
}

/// [`Textured`](super::Textured)'s and [`TexturedLit`](super::TexturedLit)'s span: one loop per kind of texture
/// ([`Texture::sampler`](crate::texture::Texture::sampler)), the colour
/// interpolated only when `LIT`.
#[inline(always)]
pub(super) fn textured_span<C, const LIT: bool>(span: SpanInput<'_, C, [I16F16; 2]>) -> u32
where
    C: FromTexel + Copy + Into<Rgb888>,
{
    let Some(texture) = span.texture() else {
        return 0;
    };
    match texture.sampler() {
        Sampler::NearestRgb565(t) => span.shade_plain(LIT, TexelPixel::<_, LIT>(Nearest565(t))),
        Sampler::BilinearRgb565(t) => {
            span.shade_plain(LIT, TexelPixel::<_, LIT>(Bilinear565(t, Quad::NONE)))
        }
        Sampler::General(t) => span.shade_unspecialised(LIT, TexelPixel::<_, LIT>(t)),
    }
}

/// [`textured_span`] for a triangle's spans in a tile, the texture's kind
/// decided once for all of them.
#[inline(always)]
pub(super) fn textured_spans<C, const LIT: bool>(spans: TriangleSpans<'_, C, [I16F16; 2]>) -> u32
where
    C: FromTexel + Copy + Into<Rgb888>,
{
    let Some(texture) = spans.texture() else {
        return 0;
    };
    match texture.sampler() {
        Sampler::NearestRgb565(t) => {
            // `Textured`'s opaque spans take a loop of their own
            // (`run_nearest`), whose constants are gathered once here.
            let near = match t.fine_parts() {
                Some((texels, parts)) if !LIT => spans.nearest_constants(texels, parts, false),
                _ => None,
            };
            match near {
                Some(c) => spans.each(|s| {
                    if let Some(sh) = s.shifted_opaque() {
                        if LOOPS32 && s.flat_q() {
                            return s.run_nearest::<FLAT_Q>(&c, sh);
                        }
                        return s.run_nearest::<SHIFTED>(&c, sh);
                    }
                    s.shade_unshifted(LIT, TexelPixel::<_, LIT>(Nearest565(t)))
                }),
                None => spans.each(|s| s.shade_plain(LIT, TexelPixel::<_, LIT>(Nearest565(t)))),
            }
        }
        Sampler::BilinearRgb565(t) => {
            spans.each(|s| s.shade_plain(LIT, TexelPixel::<_, LIT>(Bilinear565(t, Quad::NONE))))
        }
        Sampler::General(t) => spans.each(|s| s.shade_unspecialised(LIT, TexelPixel::<_, LIT>(t))),
    }
}

/// [`textured_spans`] for an opaque draw's spans in an affine frame
/// ([`FragmentShader::shade_affine_spans`](crate::shader::FragmentShader::shade_affine_spans)): the nearest texels on a
/// repeated power-of-two `Rgb565` texture in a loop of their own, the
/// triangle's spans at once (`run_nearest_affine`, the texture
/// coordinates' sums stepped; `TexturedLit`'s in
/// `run_nearest_affine_lit`, lit by the colour planes' colour, which the
/// renderer's affine copy sets up for every triangle of a shader that
/// reads the colour), the others in the opaque affine loop with the
/// shader's pixel. Its own
/// `match` rather than a call of `textured_spans` for the other samplers:
/// called from two shading functions, that one's span closures went out
/// of line (x86-64 `demo-textured-lit` 5,976,296 -> 7,049,062
/// instructions).
#[inline(always)]
pub(super) fn textured_affine_spans<C, const LIT: bool>(
    spans: TriangleSpans<'_, C, [I16F16; 2]>,
) -> u32
where
    C: FromTexel + Copy + Into<Rgb888>,
{
    let Some(texture) = spans.texture() else {
        return 0;
    };
    match texture.sampler() {
        Sampler::NearestRgb565(t) => {
            // Where `MASKED_INDEX`, textures of `MASKED_TEXELS` at most;
            // `TexturedLit`'s colour from the triangle's colour planes.
            let parts = t.fine_parts().filter(|&(_, [_, _, last])| {
                spans.affine_opaque() && (!MASKED_INDEX || last < MASKED_TEXELS)
            });
            let planes = spans.colour;
            if let Some(c) = parts.and_then(|(texels, p)| spans.nearest_constants(texels, p, true))
            {
                // `TexturedLit`'s texels lit by the colour planes (which
                // the renderer's affine copy sets up for every triangle of
                // a shader that reads the colour).
                let lit = if LIT { planes } else { None };
                if !LIT || lit.is_some() {
                    // On 32-bit targets, the short spans in the opaque
                    // affine loop (`SHORT_SPANS`).
                    #[cfg(not(target_pointer_width = "64"))]
                    if let Some(short) = SHORT_SPANS {
                        return spans.each(|s| {
                            if s.color.len() <= short {
                                return s.shade_affine(LIT, TexelPixel::<_, LIT>(Nearest565(t)));
                            }
                            s.run_nearest_affine(&c, lit)
                        });
                    }
                    return match lit {
                        Some(planes) => spans.run_nearest_affine_lit(&c, planes),
                        None => spans.run_nearest_affine(&c),
                    };
                }
            }
            spans.each(|s| s.shade_affine(LIT, TexelPixel::<_, LIT>(Nearest565(t))))
        }
        // `Textured`'s bilinear texels in a loop of their own too
        // (`run_bilinear_affine`), where [`BILINEAR_LOOP`].
        Sampler::BilinearRgb565(t) if BILINEAR_LOOP && !LIT && spans.affine_opaque() => {
            let steps = spans.bilinear_steps();
            spans.each(|s| s.run_bilinear_affine(&t, steps))
        }
        Sampler::BilinearRgb565(t) => {
            spans.each(|s| s.shade_affine(LIT, TexelPixel::<_, LIT>(Bilinear565(t, Quad::NONE))))
        }
        Sampler::General(t) => spans.each(|s| s.shade_unspecialised(LIT, TexelPixel::<_, LIT>(t))),
    }
}

/// Whether `Textured`'s opaque affine spans on a repeated power-of-two
/// `Rgb565` texture with bilinear filtering take a loop of their own
/// (`run_bilinear_affine`, the texture coordinates' sums stepped) rather
/// than the opaque affine loop with the shader's pixel: per fragment,
/// `fill-bilinear-exact` x86-64 153.68 -> 146.49, Cortex-M4F 147.26 ->
/// 143.36, ARMv6-M 215.12 -> 207.83; not on ARMv7-M (the build script's
/// `microraster_armv7m`), whose Cortex-M3 took 142.93 -> 144.86.
const BILINEAR_LOOP: bool = !cfg!(microraster_armv7m);

/// Whether `TexturedLit`'s opaque quasi-perspective spans on a repeated
/// power-of-two `Rgb565` texture take a loop of their own
/// (`run_nearest_quasi::<true>`, the same bits as the general one): where
/// [`LOOPS32`], as it was measured faster on 32-bit targets
/// (`fill-lit-quasi16` 104.72 -> 97.31 instructions a fragment on the
/// Cortex-M3, 108.16 -> 105.23 on the Cortex-M4F, 200.00 -> 198.41 on
/// ARMv6-M). On x86-64 it spilled more than the general loop: 98.43 ->
/// 104.84.
const LIT_QUASI_LOOP: bool = LOOPS32;

/// [`textured_spans`] for an opaque draw's spans in a quasi-perspective
/// frame ([`FragmentShader::shade_quasi_spans`](crate::shader::FragmentShader::shade_quasi_spans)), the texture's sampler
/// `sampler`: `Textured`'s nearest texels in a loop of their own
/// (`run_nearest_quasi`), the others in the opaque quasi-perspective loop
/// with the shader's pixel.
#[inline(always)]
pub(super) fn textured_quasi_spans<C, const LIT: bool>(
    spans: TriangleSpans<'_, C, [I16F16; 2]>,
    sampler: Sampler<'_>,
) -> u32
where
    C: FromTexel + Copy + Into<Rgb888>,
{
    match sampler {
        Sampler::NearestRgb565(t) => {
            // A loop of their own, the texel lit there if `LIT` where
            // [`LIT_QUASI_LOOP`] says.
            let own = !LIT || LIT_QUASI_LOOP;
            let parts = t.fine_parts().filter(|_| own && spans.quasi_opaque());
            if let Some(c) = parts.and_then(|(texels, p)| spans.nearest_constants(texels, p, false))
            {
                return spans.each(|s| s.run_nearest_quasi::<LIT>(&c));
            }
            spans.each_quasi(LIT, TexelPixel::<_, LIT>(Nearest565(t)))
        }
        Sampler::BilinearRgb565(t) => {
            spans.each_quasi(LIT, TexelPixel::<_, LIT>(Bilinear565(t, Quad::NONE)))
        }
        Sampler::General(t) => spans.each_quasi(LIT, TexelPixel::<_, LIT>(t)),
    }
}
