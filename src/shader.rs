//! Fragment shaders: the per-pixel colour of a draw, as a monomorphized
//! trait, with perspective-correct varyings.
//!
//! A draw with [`Shading::Shader`](crate::scene::Shading::Shader) is
//! coloured by the scene's [`FragmentShader`]. The renderer is generic over
//! the shader's type, so its `fragment` function is inlined into the span
//! loop: there is no `dyn` call per pixel. A shader has two halves:
//!
//! * [`vertex`](FragmentShader::vertex) gives the *varyings* of one mesh
//!   vertex: any number of 16.16 values (`[I16F16; N]`), such as texture
//!   coordinates or a normal. It is evaluated when a triangle is set up in
//!   a tile (the renderer keeps no per-vertex varyings in RAM, so it must be
//!   a pure function of its input);
//! * [`fragment`](FragmentShader::fragment) gets the varyings interpolated
//!   at a pixel centre, with the pixel's position, depth and the
//!   interpolated lit vertex colour, and returns a colour or discards the
//!   fragment (`None`: nothing is written, depth included).
//!
//! # Perspective-correct interpolation
//!
//! Following Hecker (*Perspective Texture Mapping*, Game Developer
//! 1995–96), a varying `a` is not linear in screen space, but `a / w` and
//! `1 / w` are. The renderer interpolates the *perspective-correct
//! barycentric coordinates* rather than each varying: per triangle it
//! scales the three `1 / w` to `q_i = 2^28 w_min / w_i` and sets up three
//! screen-space planes, `Q = Σ λ_i q_i`, `B1 = λ_1 q_1` and `B2 = λ_2 q_2`
//! (with `λ` the screen-space barycentrics), whatever the number of
//! varyings. At a pixel, `b1 = B1 / Q` and `b2 = B2 / Q` are the weights of
//! vertices 1 and 2 in the triangle itself, and every varying is
//! `a0 + b1 (a1 - a0) + b2 (a2 - a0)`, colour included (but for an opaque
//! draw in affine mode, see [`Perspective`]). The division is one
//! 32-bit reciprocal after normalising `Q` to 16 significant bits, so the
//! weights are within 7/65,536 of exact while `Q >= 2^15` (see
//! [`Perspective`]; `Q` is smaller only where the triangle's `w` vary by
//! more than 2^13, and there the weights have as many bits as `Q`).
//! Clipped triangles carry the original triangle's barycentrics through the
//! clipper (interpolated in clip space, where attributes are linear), so
//! the varyings of a clipped vertex are those of the point it lies on.
//!
//! [`Perspective`] selects how often the division happens: at every pixel,
//! every 8 or 16 pixels with linear steps between (the Quake technique),
//! or never (affine, screen-space linear).
//!
//! # Built-in shaders
//!
//! [`Textured`], [`TexturedLit`], [`DepthShade`], [`Normals`],
//! [`Gouraud`] (perspective-correct colour) and [`Flat`]. Flat and screen-space
//! Gouraud colour need no shader: they are [`Shading::Flat`] and
//! [`Shading::Gouraud`], the renderer's fastest paths.
//!
//! [`Shading::Flat`]: crate::scene::Shading::Flat
//! [`Shading::Gouraud`]: crate::scene::Shading::Gouraud

mod builtin;
pub(crate) mod interpolated;
mod set;
pub mod span;
mod triangle_spans;
mod with_planes;

pub(crate) use builtin::modulate;
pub use builtin::{mul255, DepthShade, Flat, Gouraud, Normals, Textured, TexturedLit};
pub(crate) use set::check as check_in_set;
pub use set::{ShaderSet, VisitShader};
pub use span::{Interpolated, PixelFn, SpanInput, TriangleSpans};

use crate::mesh::Mesh;
use crate::scene::Draw;
use crate::texture::Texture;
use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;

/// How varyings are interpolated across a span.
///
/// The weights `b1`, `b2` (see the module docs) are computed exactly, up to
/// 7/65,536, at *sample* pixels; between samples they and every varying
/// step linearly. Between two samples whose `1 / w` are in ratio `r`, the
/// true value runs along a hyperbola and the linear step misses it by at
/// most `|Δa| (√r - 1) / (√r + 1)`, where `Δa` is the varying's change
/// between the samples: nothing for a surface facing the camera (`r = 1`),
/// 3.3 % of `Δa` for `r = 1.14`, 17 % for `r = 2`. The quasi-perspective
/// samples are the screen columns that are multiples of 8 or 16, and each
/// span's ends (the last pixel, or the column just beyond it when that is
/// such a multiple; see [`span`]), so the image is the same with either
/// rasterizer, any tile order and any tile width that is a multiple of 16
/// (a narrower or odd width cuts spans at columns that become samples).
/// `tests/perspective.rs` holds every mode to an
/// `f64` reference with this bound; on its floor at a grazing angle the
/// worst pixel reaches about a third of it. Affine mode is linear over the
/// whole triangle: textures bend and swim on surfaces seen at an angle
/// (the gallery's `affine` picture), which is fine for small or
/// camera-facing triangles.
///
/// Which mode is fastest depends on the spans more than on the
/// divisions. On a mesh of small triangles (spans of two or three pixels)
/// the quasi-perspective modes are the slowest, as each span samples
/// both its ends (x86-64's textured demo frame, BENCHMARKS.md's
/// `demo-textured-lit`: 290 instructions a shaded pixel exact, 308
/// affine, 367 quasi16); affine mode is the fastest there on the
/// Cortex-M3 and M4F (6.63 M and 6.72 M instructions a frame against
/// exact's 6.92 M and 6.90 M), exact on ARMv6-M (12.48 M against 13.33 M).
/// Long spans of a surface seen at an angle are where quasi-perspective
/// pays (x86-64's nearest `-facing` fill: 45.4 instructions a fragment
/// against exact's 55.7).
///
/// A draw whose clip-space `w` is the same at every vertex (its
/// transform's `w` row is `(0, 0, 0, c)`: an orthographic or 2D camera,
/// [`DrawSetup::constant_w`](crate::vertex::DrawSetup::constant_w)) has
/// no perspective to correct: every mode interpolates it as `Affine`
/// does, the varyings rounded once (within about half a unit of 2^-16),
/// which the exact weights, truncated to 16 bits before their sum, are
/// not, and its opaque passes take the affine span loops
/// ([`FragmentShader::shade_affine_spans`]). The image of such a draw is
/// the same in all four modes.
///
/// In affine mode (and so for such a draw) the colour
/// ([`Fragment::color`]) of an opaque draw is
/// [`Shading::Gouraud`](crate::scene::Shading::Gouraud)'s, from the same
/// colour planes, stepped along each span: the [`Gouraud`] shader then
/// draws what that shading draws, in its span loops. A blended draw's
/// (and that of the rare triangle whose varyings' differences do not fit
/// 32 bits) keeps the weights' colour, `c0 + b1 (c1 - c0) + b2 (c2 - c0)`
/// with the weights truncated to 16 bits: within a unit of a channel of
/// the planes'.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Perspective {
    /// Every pixel is a sample: one reciprocal per fragment that passes the
    /// depth test.
    #[default]
    Exact,
    /// The columns `x ≡ 0 (mod 8)` and each span's ends are samples.
    Quasi8,
    /// The columns `x ≡ 0 (mod 16)` and each span's ends are samples.
    Quasi16,
    /// All `1 / w` treated as equal: varyings are linear in screen space
    /// (textures swim on planes seen at an angle), each rounded once from
    /// its exact linear value (within about half a unit of 2^-16), so that
    /// span loops step them by one addition a pixel; an opaque draw's
    /// colour is the Gouraud shading's (see above).
    Affine,
}

impl Perspective {
    /// Pixels between samples (`0` for affine: only the span's ends).
    pub(crate) fn segment(self) -> u32 {
        match self {
            Perspective::Exact => 1,
            Perspective::Quasi8 => 8,
            Perspective::Quasi16 => 16,
            Perspective::Affine => 0,
        }
    }
}

/// The varyings of a shader: `[I16F16; N]` for any `N`.
pub trait Varyings: Copy + core::fmt::Debug + private::Sealed {
    /// How many values.
    const LEN: usize;
    /// All zeros.
    fn zeroed() -> Self;
    /// The values.
    fn as_slice(&self) -> &[I16F16];
    /// The values, mutable.
    fn as_mut_slice(&mut self) -> &mut [I16F16];
}

mod private {
    pub trait Sealed {}
    impl<const N: usize> Sealed for [fixed::types::I16F16; N] {}
}

impl<const N: usize> Varyings for [I16F16; N] {
    const LEN: usize = N;
    #[inline(always)]
    fn zeroed() -> Self {
        [I16F16::ZERO; N]
    }
    #[inline(always)]
    fn as_slice(&self) -> &[I16F16] {
        self
    }
    #[inline(always)]
    fn as_mut_slice(&mut self) -> &mut [I16F16] {
        self
    }
}

/// What [`FragmentShader::vertex`] reads: one vertex of a draw's mesh.
#[derive(Clone, Copy, Debug)]
pub struct VertexInput<'a> {
    /// Index of the draw in the scene.
    pub draw: usize,
    /// Index of the vertex in the draw's mesh (always in range).
    pub index: usize,
    /// The draw's mesh.
    pub mesh: &'a Mesh<'a>,
}

impl VertexInput<'_> {
    /// The vertex's texture coordinates, or zeros when the mesh has none.
    #[inline(always)]
    pub fn uv(&self) -> [I16F16; 2] {
        match self.mesh.uvs() {
            Some(uv) => uv[self.index],
            None => [I16F16::ZERO; 2],
        }
    }

    /// The vertex's model-space normal, or zeros when the mesh has none.
    #[inline(always)]
    pub fn normal(&self) -> [I16F16; 3] {
        match self.mesh.normals() {
            Some(n) => n[self.index],
            None => [I16F16::ZERO; 3],
        }
    }

    /// The vertex's model-space position.
    #[inline(always)]
    pub fn position(&self) -> [I16F16; 3] {
        self.mesh.positions()[self.index]
    }
}

/// One fragment, as [`FragmentShader::fragment`] sees it.
#[derive(Clone, Copy, Debug)]
pub struct Fragment<'t, V> {
    /// Index of the draw in the scene (a shader shared by several draws
    /// can tell them apart).
    pub draw: usize,
    /// Screen column of the pixel.
    pub x: i32,
    /// Screen row of the pixel.
    pub y: i32,
    /// Its depth, 0 (near) to 65535 (far).
    pub depth: u16,
    /// The lit vertex colours interpolated (perspective-correct; in an
    /// opaque draw in [`Perspective::Affine`] as
    /// [`Shading::Gouraud`](crate::scene::Shading::Gouraud) interpolates
    /// them), or the provoking vertex's colour under
    /// [`FragmentShader::INTERPOLATE_COLOR`]` = false`.
    pub color: [u8; 3],
    /// The varyings, interpolated.
    pub varyings: V,
    /// The draw's texture, if it has one.
    pub texture: Option<&'t Texture<'t>>,
}

/// Why a draw cannot use a shader: found before anything is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderError {
    /// The shader samples a texture and the draw has none.
    MissingTexture,
    /// The shader reads texture coordinates and the mesh has none.
    MissingUvs,
    /// The shader reads normals and the mesh has none.
    MissingNormals,
}

impl core::fmt::Display for ShaderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::MissingTexture => "the shader needs a texture and the draw has none",
            Self::MissingUvs => "the shader needs texture coordinates and the mesh has none",
            Self::MissingNormals => "the shader needs normals and the mesh has none",
        })
    }
}

/// A fragment shader, monomorphized into the renderer's span loop.
///
/// ```
/// use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
/// use fixed::types::I16F16;
/// use microraster::shader::{Fragment, FragmentShader, VertexInput};
///
/// /// A checkerboard from the texture coordinates: 8 squares per unit.
/// struct Checker;
/// impl FragmentShader<Rgb565> for Checker {
///     type Varyings = [I16F16; 2];
///     fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 2] {
///         v.uv()
///     }
///     fn fragment(&self, f: &Fragment<'_, [I16F16; 2]>) -> Option<Rgb565> {
///         let [u, v] = f.varyings;
///         let odd = ((u.to_bits() >> 13) ^ (v.to_bits() >> 13)) & 1 == 1;
///         Some(if odd { Rgb565::WHITE } else { Rgb565::BLACK })
///     }
/// }
/// ```
pub trait FragmentShader<C> {
    /// The interpolated values: `[I16F16; N]`.
    type Varyings: Varyings;

    /// Whether [`Fragment::color`] is interpolated (three more multiply-adds
    /// per fragment) or the provoking vertex's colour.
    const INTERPOLATE_COLOR: bool = true;

    /// Checks that `draw` has what the shader reads (a texture, UVs,
    /// normals), once per frame before anything is drawn.
    fn check(&self, _draw: &Draw<'_>) -> Result<(), ShaderError> {
        Ok(())
    }

    /// The varyings of one vertex. Must be a pure function of `v`: it is
    /// evaluated again for every tile the triangle touches.
    fn vertex(&self, v: &VertexInput<'_>) -> Self::Varyings;

    /// The colour of a fragment, or `None` to discard it (nothing written).
    fn fragment(&self, f: &Fragment<'_, Self::Varyings>) -> Option<C>;

    /// Colours one span, returning the number of pixels written. The
    /// default calls [`fragment`](Self::fragment) at each pixel that
    /// passes the depth test ([`SpanInput::fragments`]), inlined into the
    /// renderer's loop. Override it to decide once per span what does not
    /// change along it and hand [`SpanInput::shade`] a per-pixel function
    /// made for that (see [`span`]); it must colour the span as
    /// `fragment` would, pixel for pixel.
    #[inline(always)]
    fn shade_span(&self, span: SpanInput<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        span.fragments(Self::INTERPOLATE_COLOR, |f| self.fragment(f))
    }

    /// Colours the spans of one triangle in one tile, returning the number
    /// of pixels written. The default calls
    /// [`shade_span`](Self::shade_span) for each. Override it to decide
    /// once per triangle and tile, rather than once per span, what does
    /// not change between its spans (the texture's kind, say), then colour
    /// them with [`TriangleSpans::each`]; it must colour them as
    /// `shade_span` would. A shader that overrides neither needs neither.
    #[inline(always)]
    fn shade_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        spans.each(|span| self.shade_span(span))
    }

    /// [`shade_spans`](Self::shade_spans) for the spans of an opaque draw
    /// (no blend, the `LessEqual` depth test, depth written) in a
    /// quasi-perspective frame ([`Perspective::Quasi8`],
    /// [`Perspective::Quasi16`]; [`TriangleSpans::quasi_opaque`]). The
    /// renderer calls it from a function of its own, so that its loops are
    /// compiled apart from those of the other frames. Override it to
    /// colour them with [`TriangleSpans::each_quasi`] and a per-pixel
    /// function, whose loop has the test, write and blend known; it must
    /// colour them as `shade_span` would. The default calls
    /// [`shade_span`](Self::shade_span) for each (not `shade_spans`, whose
    /// loop would then be called from two places, which can leave it out
    /// of line in every frame).
    #[inline(always)]
    fn shade_quasi_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        spans.each(|span| self.shade_span(span))
    }

    /// [`shade_spans`](Self::shade_spans) for the spans of an opaque draw
    /// in an affine frame ([`Perspective::Affine`]), or of an opaque draw
    /// whose clip-space `w` is the same at every vertex in any frame (see
    /// [`Perspective`]; [`TriangleSpans::affine_opaque`]). The renderer calls it from a
    /// function of its own, as it calls
    /// [`shade_quasi_spans`](Self::shade_quasi_spans), and
    /// [`SpanInput::shade_with`] colours these spans in the opaque affine
    /// loop (the test, write and blend known). Override it to decide once
    /// per triangle and tile what does not change between its spans; it
    /// must colour them as `shade_span` would. The default calls
    /// [`shade_span`](Self::shade_span) for each.
    #[inline(always)]
    fn shade_affine_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        spans.each(|span| self.shade_span(span))
    }
}

/// A shader by reference, so that a [`ShaderSet`] tuple can hold
/// shaders it borrows: `(&a, &b)`. Every method forwards, `shade_span`
/// and `shade_spans` included, so a borrowed built-in keeps its own span
/// loops.
impl<C, S: FragmentShader<C> + ?Sized> FragmentShader<C> for &S {
    type Varyings = S::Varyings;
    const INTERPOLATE_COLOR: bool = S::INTERPOLATE_COLOR;
    #[inline(always)]
    fn check(&self, draw: &Draw<'_>) -> Result<(), ShaderError> {
        (**self).check(draw)
    }
    #[inline(always)]
    fn vertex(&self, v: &VertexInput<'_>) -> Self::Varyings {
        (**self).vertex(v)
    }
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, Self::Varyings>) -> Option<C> {
        (**self).fragment(f)
    }
    #[inline(always)]
    fn shade_span(&self, span: SpanInput<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        (**self).shade_span(span)
    }
    #[inline(always)]
    fn shade_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        (**self).shade_spans(spans)
    }
    #[inline(always)]
    fn shade_quasi_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        (**self).shade_quasi_spans(spans)
    }
    #[inline(always)]
    fn shade_affine_spans(&self, spans: TriangleSpans<'_, C, Self::Varyings>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        (**self).shade_affine_spans(spans)
    }
}

// Defined with the scene, whose default shader it is, so that `scene`
// does not depend on this module (which depends on `scene` for `Draw`).
pub use crate::scene::NoShader;

impl<C> FragmentShader<C> for NoShader {
    type Varyings = [I16F16; 0];
    const INTERPOLATE_COLOR: bool = false;
    fn vertex(&self, _: &VertexInput<'_>) -> [I16F16; 0] {
        []
    }
    fn fragment(&self, _: &Fragment<'_, [I16F16; 0]>) -> Option<C> {
        None
    }
}

/// A colour format that ordered dithering quantizes to: the target's
/// levels per channel, and the quantized colour of an 8-bit colour at a
/// pixel.
///
/// Ordered dithering (Bayer 1973, *An optimum method for two-level
/// rendition of continuous-tone pictures*) adds to each channel, before it
/// is cut to the target's levels, a threshold from a 4x4 matrix indexed by
/// the pixel position: `level = floor(c (L - 1) / 255 + (t + ½) / 16)`
/// with `t` in `0..16`. Over any 4x4 block the mean level is then within
/// one sixteenth of a level of the exact `c (L - 1) / 255`, so smooth
/// gradients keep their slope instead of breaking into bands. Integer
/// arithmetic only, the same bits everywhere.
pub trait Dither: Sized {
    /// The colour of `c` at pixel `(x, y)`.
    fn dither(c: [u8; 3], x: i32, y: i32) -> Self;
}

/// The 4x4 Bayer matrix: thresholds `0..16`.
const BAYER4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// `c` (0..=255) cut to `levels` levels with Bayer threshold `t`.
#[inline(always)]
pub fn dither_channel(c: u8, levels: u32, t: u8) -> u32 {
    // floor((c (L - 1) 32 + (2t + 1) 255) / (255 · 32)); below L.
    (c as u32 * (levels - 1) * 32 + (2 * t as u32 + 1) * 255) / (255 * 32)
}

#[inline(always)]
fn threshold(x: i32, y: i32) -> u8 {
    BAYER4[(y & 3) as usize][(x & 3) as usize]
}

impl Dither for embedded_graphics::pixelcolor::Rgb565 {
    #[inline(always)]
    fn dither(c: [u8; 3], x: i32, y: i32) -> Self {
        let t = threshold(x, y);
        Self::new(
            dither_channel(c[0], 32, t) as u8,
            dither_channel(c[1], 64, t) as u8,
            dither_channel(c[2], 32, t) as u8,
        )
    }
}

impl Dither for embedded_graphics::pixelcolor::Gray4 {
    #[inline(always)]
    fn dither(c: [u8; 3], x: i32, y: i32) -> Self {
        use embedded_graphics::pixelcolor::{Gray8, GrayColor};
        // The luma embedded-graphics gives, then 256 levels to 16.
        let luma = Gray8::from(Rgb888::new(c[0], c[1], c[2])).luma();
        Self::new(dither_channel(luma, 16, threshold(x, y)) as u8)
    }
}

/// 8 bits per channel already: no dithering, the plain conversion.
impl Dither for Rgb888 {
    #[inline(always)]
    fn dither(c: [u8; 3], _: i32, _: i32) -> Self {
        Rgb888::new(c[0], c[1], c[2])
    }
}

/// Shader `S`'s colours, ordered-dithered to the target's levels (see
/// [`Dither`]): for `Rgb565` and `Gray4` targets, whose 32, 64 or 16 levels
/// band smooth shading. Wraps any shader that outputs `Rgb888`.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb565;
/// use microraster::shader::{Dithered, FragmentShader, Gouraud};
/// fn takes<S: FragmentShader<Rgb565>>(_: &S) {}
/// takes(&Dithered(Gouraud));
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Dithered<S>(pub S);

impl<C: Dither, S: FragmentShader<Rgb888>> FragmentShader<C> for Dithered<S> {
    type Varyings = S::Varyings;
    const INTERPOLATE_COLOR: bool = S::INTERPOLATE_COLOR;
    fn check(&self, draw: &Draw<'_>) -> Result<(), ShaderError> {
        self.0.check(draw)
    }
    #[inline(always)]
    fn vertex(&self, v: &VertexInput<'_>) -> Self::Varyings {
        self.0.vertex(v)
    }
    #[inline(always)]
    fn fragment(&self, f: &Fragment<'_, Self::Varyings>) -> Option<C> {
        use embedded_graphics::pixelcolor::RgbColor;
        let c = self.0.fragment(f)?;
        Some(C::dither([c.r(), c.g(), c.b()], f.x, f.y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every level of every channel width: the mean over the 16 Bayer
    /// thresholds is within 1/16 level of exact, the extremes are exact,
    /// and no level leaves the range.
    #[test]
    fn dithering_keeps_the_mean() {
        for levels in [16u32, 32, 64] {
            for c in 0..=255u8 {
                let sum: u32 = (0..16).map(|t| dither_channel(c, levels, t)).sum();
                let mean = sum as f64 / 16.0;
                let exact = c as f64 * (levels - 1) as f64 / 255.0;
                assert!(
                    (mean - exact).abs() <= 1.0 / 16.0 + 1e-9,
                    "{levels} {c}: {mean} vs {exact}"
                );
                assert!((0..16).all(|t| dither_channel(c, levels, t) < levels));
            }
            assert!((0..16).all(|t| dither_channel(0, levels, t) == 0));
            assert!((0..16).all(|t| dither_channel(255, levels, t) == levels - 1));
        }
        // Each threshold appears once per 4x4 block.
        let mut seen = [false; 16];
        for row in BAYER4 {
            for t in row {
                seen[t as usize] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
    }
}
