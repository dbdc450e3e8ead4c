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
use crate::texture::FromTexel;
use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;
use textured::{textured_affine_spans, textured_quasi_spans, textured_span, textured_spans};

mod textured;

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
/// with one loop per kind of texture ([`Texture::sampler`](crate::texture::Texture::sampler)), decided once
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
