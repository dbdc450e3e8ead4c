//! The built-in shaders, each with a span loop of its own
//! ([`FragmentShader::shade_span`]): what does not change along a span
//! (the texture's kind, the colour) is decided before it (the texture's
//! kind once per triangle and tile, [`FragmentShader::shade_spans`]), and
//! the per-pixel work is a [`PixelFn`] whose `pixel` is always inlined.
//! `fragment` stays the definition, and `tests/span_shaders.rs` holds
//! every span loop to it, pixel for pixel.

use super::{
    Fragment, FragmentShader, Interpolated, PixelFn, ShaderError, SpanInput, TriangleSpans,
    VertexInput,
};
use crate::scene::Draw;
use crate::shade::perspective::{AFFINE, FLAT_Q, LOOPS32, MASKED_INDEX, MASKED_TEXELS, SHIFTED};
use crate::texture::{rgb565_to_rgb888, FromTexel, Pow2Rgb565, Quad, Sampler, Texture};
use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;

fn needs_uv_texture(draw: &Draw<'_>) -> Result<(), ShaderError> {
    if draw.texture.is_none() {
        Err(ShaderError::MissingTexture)
    } else if draw.mesh.uvs().is_none() {
        Err(ShaderError::MissingUvs)
    } else {
        Ok(())
    }
}

/// A span method of a built-in shader: `shade_span` (over a
/// [`SpanInput`]) or `shade_spans` (over [`TriangleSpans`]) for `$n`
/// varyings, always inlined (the per-pixel work is inlined into the tile's
/// shading function), with the bound on the colour type the trait gives
/// them. A macro, so that each shader's method is the code written out.
macro_rules! span_method {
    ($(#[$doc:meta])* $name:ident(&$s:ident, $arg:ident: $input:ident<$n:literal>) $body:block) => {
        $(#[$doc])*
        #[inline(always)]
        fn $name(&$s, $arg: $input<'_, C, [I16F16; $n]>) -> u32
        where
            C: Copy + From<Rgb888> + Into<Rgb888>,
        $body
    };
}

/// The varyings of a shader that has none, and its vertex function.
macro_rules! no_varyings {
    () => {
        type Varyings = [I16F16; 0];
        fn vertex(&self, _: &VertexInput<'_>) -> [I16F16; 0] {
            []
        }
    };
}

/// The methods of [`Textured`] (`$lit` false) and [`TexturedLit`] (true)
/// but `fragment`: the texture coordinates as varyings, and span methods
/// with one loop per kind of texture ([`Texture::sampler`]), decided once
/// per triangle and tile; an `Rgb565` texel goes to the target as it is
/// ([`FromTexel`]), and the light's product is taken in 8 bits per channel,
/// as `fragment` takes it: the same colours, whatever the target.
macro_rules! textured_methods {
    ($lit:literal) => {
        type Varyings = [I16F16; 2];
        fn check(&self, draw: &Draw<'_>) -> Result<(), ShaderError> {
            needs_uv_texture(draw)
        }
        #[inline(always)]
        fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 2] {
            v.uv()
        }
        span_method!(shade_span(&self, span: SpanInput<2>) {
            textured_span::<C, $lit>(span)
        });
        span_method!(shade_spans(&self, spans: TriangleSpans<2>) {
            textured_spans::<C, $lit>(spans)
        });
        span_method!(shade_affine_spans(&self, spans: TriangleSpans<2>) {
            textured_affine_spans::<C, $lit>(spans)
        });
        span_method!(shade_quasi_spans(&self, spans: TriangleSpans<2>) {
            match spans.texture() {
                Some(t) => textured_quasi_spans::<C, $lit>(spans, t.sampler()),
                None => 0,
            }
        });
    };
}

/// The draw's texture at the interpolated texture coordinates, unlit.
#[derive(Clone, Copy, Debug, Default)]
pub struct Textured;

impl<C: FromTexel> FragmentShader<C> for Textured {
    const INTERPOLATE_COLOR: bool = false;
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 2]>) -> Option<C> {
        let [r, g, b] = f.texture?.sample(f.varyings[0], f.varyings[1]);
        Some(C::from(Rgb888::new(r, g, b)))
    }
    textured_methods!(false);
}

/// A colour from its bytes.
#[inline(always)]
fn rgb<C: From<Rgb888>>([r, g, b]: [u8; 3]) -> C {
    C::from(Rgb888::new(r, g, b))
}

/// `texel * light / 255` per channel, rounded (see [`mul255`]).
#[inline(always)]
pub(crate) fn modulate(t: [u8; 3], c: [u8; 3]) -> [u8; 3] {
    [mul255(t[0], c[0]), mul255(t[1], c[1]), mul255(t[2], c[2])]
}

/// The draw's texture modulated by the lit vertex colour (interpolated,
/// perspective-correct): `texel * colour / 255` per channel, rounded.
#[derive(Clone, Copy, Debug, Default)]
pub struct TexturedLit;

/// `a * b / 255` rounded to nearest, exact for all bytes.
#[inline(always)]
pub fn mul255(a: u8, b: u8) -> u8 {
    let p = a as u32 * b as u32 + 128;
    ((p + (p >> 8)) >> 8) as u8
}

impl<C: FromTexel> FragmentShader<C> for TexturedLit {
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 2]>) -> Option<C> {
        let t = f.texture?.sample(f.varyings[0], f.varyings[1]);
        Some(rgb(modulate(t, f.color)))
    }
    textured_methods!(true);
}

/// Depth as grey: white at depth `near`, black at `far` and beyond,
/// linear between (in the 16-bit depth, which is `z / w`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthShade {
    near: u16,
    /// `2^24 / (far - near)`, so a pixel needs one multiply.
    scale: u32,
}

impl DepthShade {
    /// Grey from `near` (white) to `far` (black); `far <= near` is
    /// treated as `near + 1`.
    pub const fn new(near: u16, far: u16) -> Self {
        let span = if far > near { far - near } else { 1 } as u32;
        Self {
            near,
            scale: (1 << 24) / span,
        }
    }

    /// The grey of a depth.
    #[inline(always)]
    pub fn grey(&self, depth: u16) -> u8 {
        let d = depth.saturating_sub(self.near) as u32;
        // `(d · scale) >> 16` with `d < 2^16`, `scale <= 2^24`: the product
        // needs 40 bits, so `scale` is split in halves, each product below
        // 2^32 and the low one's fraction dropped as the whole would be.
        let t = d * (self.scale >> 16) + ((d * (self.scale & 0xFFFF)) >> 16);
        255 - t.min(255) as u8
    }
}

impl Default for DepthShade {
    fn default() -> Self {
        Self::new(0, u16::MAX)
    }
}

impl<C: From<Rgb888>> FragmentShader<C> for DepthShade {
    no_varyings!();
    const INTERPOLATE_COLOR: bool = false;
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 0]>) -> Option<C> {
        let g = self.grey(f.depth);
        Some(C::from(Rgb888::new(g, g, g)))
    }
    span_method! {
        /// Depth only: no weights, no varyings.
        shade_span(&self, span: SpanInput<0>) {
            span.shade_with(false, *self)
        }
    }
}

/// The interpolated model-space normal as colour: each component from
/// `-1..1` to `0..255`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Normals;

impl<C: From<Rgb888>> FragmentShader<C> for Normals {
    type Varyings = [I16F16; 3];
    const INTERPOLATE_COLOR: bool = false;
    fn check(&self, draw: &Draw<'_>) -> Result<(), ShaderError> {
        match draw.mesh.normals() {
            Some(_) => Ok(()),
            None => Err(ShaderError::MissingNormals),
        }
    }
    #[inline(always)]
    fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 3] {
        v.normal()
    }
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 3]>) -> Option<C> {
        Some(rgb(f.varyings.map(normal_byte)))
    }
    span_method! {
        /// The three varyings, no colour.
        shade_span(&self, span: SpanInput<3>) {
            span.shade_with(false, Normals)
        }
    }
}

/// A normal's component from `-1..=1` to `0..=255`: `(n + 1) · 255 / 2`,
/// truncated (the clamp makes the sum non-negative, so the division is a
/// shift).
#[inline(always)]
fn normal_byte(n: I16F16) -> u8 {
    ((n.to_bits().clamp(-65_536, 65_536) + 65_536) as u32 * 255 / 131_072) as u8
}

/// The provoking vertex's lit colour: what
/// [`Shading::Flat`](crate::scene::Shading::Flat) draws, through the
/// fragment-shader path (used for transparent flat draws).
#[derive(Clone, Copy, Debug, Default)]
pub struct Flat;

impl<C: From<Rgb888>> FragmentShader<C> for Flat {
    no_varyings!();
    const INTERPOLATE_COLOR: bool = false;
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 0]>) -> Option<C> {
        Some(rgb(f.color))
    }
    span_method! {
        /// One colour, converted once per span.
        shade_span(&self, span: SpanInput<0>) {
            let c = rgb(span.flat_color());
            span.shade_with(false, Constant(c))
        }
    }
}

/// The lit vertex colours interpolated perspective-correct (the
/// [`Shading::Gouraud`](crate::scene::Shading::Gouraud) path interpolates
/// them linearly in screen space, which is faster). For any `'static`
/// colour type (every colour type is): its pixels convert to `Rgb565` by
/// tables, picked by the type's `TypeId` (see
/// [`Renderer`](crate::render::Renderer)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Gouraud;

impl<C: From<Rgb888> + 'static> FragmentShader<C> for Gouraud {
    no_varyings!();
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, [I16F16; 0]>) -> Option<C> {
        Some(rgb(f.color))
    }
    span_method! {
        /// The weights and the colour, no varyings.
        shade_span(&self, span: SpanInput<0>) {
            span.shade_plain(true, Gouraud)
        }
    }
    span_method! {
        /// [`shade_span`](Self::shade_span) for each span, with the colour
        /// loop's constants gathered once for them.
        shade_spans(&self, spans: TriangleSpans<0>) {
            spans.each_colour(Gouraud)
        }
    }
    span_method! {
        /// The opaque quasi-perspective loop with the colour stepped.
        shade_quasi_spans(&self, spans: TriangleSpans<0>) {
            spans.each_quasi(true, Gouraud)
        }
    }
    span_method! {
        /// The built-in Gouraud shading's span loops: an affine
        /// triangle's colour is its colour planes'.
        shade_affine_spans(&self, spans: TriangleSpans<0>) {
            spans.each_gouraud(Gouraud)
        }
    }
}

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

/// The pixel of [`Textured`] (`LIT` false: the texel, in the target's
/// format where it matches) and of [`TexturedLit`] (`LIT`: the texel
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

/// [`Textured`]'s and [`TexturedLit`]'s span: one loop per kind of texture
/// ([`Texture::sampler`]), the colour interpolated only when `LIT`.
#[inline(always)]
fn textured_span<C, const LIT: bool>(span: SpanInput<'_, C, [I16F16; 2]>) -> u32
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
fn textured_spans<C, const LIT: bool>(spans: TriangleSpans<'_, C, [I16F16; 2]>) -> u32
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
/// ([`FragmentShader::shade_affine_spans`]): the nearest texels on a
/// repeated power-of-two `Rgb565` texture in a loop of their own
/// (`run_nearest::<AFFINE>`, the texture coordinates' sums stepped;
/// `TexturedLit`'s in `run_nearest_lit`, lit by the colour planes'
/// colour, which the renderer's affine copy sets up for every triangle
/// of a shader that reads the colour), the others in the opaque affine
/// loop with the shader's pixel. Its own
/// `match` rather than a call of `textured_spans` for the other samplers:
/// called from two shading functions, that one's span closures went out
/// of line (x86-64 `demo-textured-lit` 5,976,296 -> 7,049,062
/// instructions).
#[inline(always)]
fn textured_affine_spans<C, const LIT: bool>(spans: TriangleSpans<'_, C, [I16F16; 2]>) -> u32
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
                match planes {
                    _ if !LIT => return spans.each(|s| s.run_nearest::<AFFINE>(&c, 0)),
                    Some(planes) => return spans.each(|s| s.run_nearest_lit(&c, planes)),
                    None => {}
                }
            }
            spans.each(|s| s.shade_affine(LIT, TexelPixel::<_, LIT>(Nearest565(t))))
        }
        // `Textured`'s bilinear texels in a loop of their own too
        // (`run_bilinear_affine`), where [`BILINEAR_LOOP`].
        Sampler::BilinearRgb565(t) if BILINEAR_LOOP && !LIT && spans.affine_opaque() => {
            spans.each(|s| s.run_bilinear_affine(&t))
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
/// `fill-bilinear-exact` x86-64 153.68 -> 146.45, Cortex-M4F 147.26 ->
/// 143.42, ARMv6-M 215.12 -> 207.78; not on ARMv7-M (the build script's
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
/// frame ([`FragmentShader::shade_quasi_spans`]), the texture's sampler
/// `sampler`: `Textured`'s nearest texels in a loop of their own
/// (`run_nearest_quasi`), the others in the opaque quasi-perspective loop
/// with the shader's pixel.
#[inline(always)]
fn textured_quasi_spans<C, const LIT: bool>(
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

impl<C: From<Rgb888>> PixelFn<[I16F16; 0], C> for DepthShade {
    #[inline(always)]
    fn pixel(&mut self, p: &Interpolated<[I16F16; 0]>) -> Option<C> {
        let g = self.grey(p.depth);
        Some(rgb([g, g, g]))
    }
}

impl<C: From<Rgb888>> PixelFn<[I16F16; 3], C> for Normals {
    #[inline(always)]
    fn pixel(&mut self, p: &Interpolated<[I16F16; 3]>) -> Option<C> {
        Some(rgb(p.varyings.map(normal_byte)))
    }
}

impl<C: From<Rgb888> + 'static> PixelFn<[I16F16; 0], C> for Gouraud {
    #[inline(always)]
    fn pixel(&mut self, p: &Interpolated<[I16F16; 0]>) -> Option<C> {
        let [r, g, b] = p.rgb();
        // Through the conversion's tables on every target: on x86-64
        // they beat embedded-graphics' arithmetic, which an earlier loop
        // had measured faster (`fill-gouraud-exact` 62.97 -> 50.88
        // instructions a fragment).
        Some(crate::shade::rgb(r, g, b))
    }
}

/// [`Flat`]'s pixel: one colour, converted once per span.
struct Constant<C>(C);

impl<C: Copy> PixelFn<[I16F16; 0], C> for Constant<C> {
    #[inline(always)]
    fn pixel(&mut self, _: &Interpolated<[I16F16; 0]>) -> Option<C> {
        Some(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul255_is_exact() {
        for a in 0..=255u32 {
            for b in 0..=255u32 {
                let exact = (a * b * 2 + 255) / 510;
                assert_eq!(mul255(a as u8, b as u8) as u32, exact, "{a} {b}");
            }
        }
    }

    #[test]
    fn depth_shade_runs_white_to_black() {
        let d = DepthShade::new(1000, 3000);
        assert_eq!(d.grey(0), 255);
        assert_eq!(d.grey(1000), 255);
        assert_eq!(d.grey(2000), 128);
        assert_eq!(d.grey(3000), 0);
        assert_eq!(d.grey(u16::MAX), 0);
        let degenerate = DepthShade::new(5, 5);
        assert_eq!(degenerate.grey(5), 255);
        assert_eq!(degenerate.grey(6), 0);
    }
}
