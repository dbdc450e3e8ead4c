//! Which span loop shades a triangle: chosen once per tile from the configuration.

use super::fill::{shade, shade_custom, AFFINE, GENERAL, QUASI};
use super::find::{finder, FindFn};
use super::Config;
use super::Features;
use crate::raster::{PixelRect, Span};
use crate::scene::Blend;
use crate::shade::perspective::{Output, ShaderTriangle};
use crate::shade::{DepthFn, DepthTest};
use crate::shader::{self, FragmentShader, ShaderSet};
use crate::texture::Texture;
use crate::tile::TileBuffer;
use crate::vertex::ScreenVertex;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};

/// The second phase of a triangle's drawing, as monomorphized for the
/// frame's depth writes and for `LessEqual` or any other depth test (see
/// [`DepthFn`]): the only code that depends on them, so the tile loop
/// exists once per colour and tile size.
pub(super) type ShadeFn<C, const TW: usize, const TH: usize> =
    fn(&mut TileBuffer<C, TW, TH>, &PixelRect, &[&ScreenVertex; 3], &[Span], DepthTest) -> u32;

/// The second phase for a fragment shader `G`: one function per shader
/// and colour type (the depth test is decided at run time there).
pub(super) type CustomFn<C, G, const TW: usize, const TH: usize> = fn(
    &mut TileBuffer<C, TW, TH>,
    &PixelRect,
    &ShaderTriangle<'_, <G as FragmentShader<C>>::Varyings>,
    &[Span],
    &G,
    Option<&Texture<'_>>,
    Output,
) -> u32;

/// How a frame draws a triangle: its rasterizer and its shading
/// functions: Gouraud, flat, for transparent draws flat and Gouraud
/// through the fragment-shader path, and the scene's fragment shaders.
pub(super) struct Shaders<'s, C: From<Rgb888> + 'static, F, const TW: usize, const TH: usize> {
    pub(super) find: FindFn,
    pub(super) out: Output,
    /// The flat and the Gouraud [`ShadeFn`], indexed by whether the
    /// triangle is Gouraud shaded: one load a pair, where a select of
    /// two fields took four instructions more.
    pub(super) fill: [ShadeFn<C, TW, TH>; 2],
    pub(super) flat_t: CustomFn<C, shader::Flat, TW, TH>,
    pub(super) gouraud_t: CustomFn<C, shader::Gouraud, TW, TH>,
    pub(super) set: &'s F,
}

impl<'s, C, F, const TW: usize, const TH: usize> Shaders<'s, C, F, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    /// The functions of a frame drawn with depth comparison `D`, depth
    /// writes `WRITE` and the paths `P` links: those of the other paths
    /// are never taken, so that they are not linked.
    pub(super) fn new<D: DepthFn, const WRITE: bool, P: Features>(
        cfg: &Config<C>,
        set: &'s F,
    ) -> Self {
        Self {
            find: finder::<P>(cfg.rasterizer),
            out: Output {
                mode: cfg.perspective,
                blend: Blend::Opaque,
                test: cfg.depth_test,
                write: WRITE,
            },
            fill: [
                // Also for Gouraud triangles of one colour, where
                // `fill::ONE_COLOUR_FLAT`.
                if P::FLAT || P::GOURAUD && super::fill::ONE_COLOUR_FLAT {
                    shade::<C, D, WRITE, false, TW, TH>
                } else {
                    shade_nothing::<C, TW, TH>
                },
                if P::GOURAUD {
                    shade::<C, D, WRITE, true, TW, TH>
                } else {
                    shade_nothing::<C, TW, TH>
                },
            ],
            flat_t: if P::BLEND && P::FLAT {
                shade_custom::<C, shader::Flat, TW, TH, GENERAL>
            } else {
                shade_none::<C, shader::Flat, TW, TH>
            },
            gouraud_t: if P::BLEND && P::GOURAUD {
                shade_custom::<C, shader::Gouraud, TW, TH, GENERAL>
            } else {
                shade_none::<C, shader::Gouraud, TW, TH>
            },
            set,
        }
    }

    /// The functions that shade with the scene's shader `G`: none when the
    /// paths `P` leave shaders out, so that none is linked; for an opaque
    /// pass (`blend`) of a quasi-perspective or affine frame, the copy
    /// with the opaque quasi-perspective or affine loops where `P` has
    /// them ([`Features::QUASI`], [`Features::AFFINE`]), so that a blended
    /// pass is not set up there only to be handed on. The second is for
    /// draws whose clip-space `w` is the same at every vertex, which every
    /// frame interpolates affinely ([`ShaderPass::constant_w`]): the
    /// affine copy for an opaque pass where `P` has it.
    pub(super) fn custom<G: FragmentShader<C>, P: Features>(
        &self,
        blend: Blend,
    ) -> [CustomFn<C, G, TW, TH>; 2] {
        let opaque = blend == Blend::Opaque;
        let affine = if P::SHADERS && P::AFFINE && opaque {
            shade_custom::<C, G, TW, TH, AFFINE>
        } else if P::SHADERS {
            shade_custom::<C, G, TW, TH, GENERAL>
        } else {
            shade_none::<C, G, TW, TH>
        };
        let frame = if P::SHADERS && P::QUASI && opaque && self.out.quasi_opaque() {
            shade_custom::<C, G, TW, TH, QUASI>
        } else if P::SHADERS && P::AFFINE && opaque && self.out.affine_opaque() {
            shade_custom::<C, G, TW, TH, AFFINE>
        } else if P::SHADERS {
            shade_custom::<C, G, TW, TH, GENERAL>
        } else {
            shade_none::<C, G, TW, TH>
        };
        [frame, affine]
    }

    /// A pass through fragment shader `g` with its functions `shade` (see
    /// [`custom`](Self::custom)).
    pub(super) fn pass<'g, G: FragmentShader<C>>(
        &self,
        g: &'g G,
        [shade, affine_shade]: [CustomFn<C, G, TW, TH>; 2],
        blend: Blend,
    ) -> ShaderPass<'g, C, G, TW, TH> {
        let mut out = self.out;
        out.blend = blend;
        ShaderPass {
            shader: g,
            shade,
            affine_shade,
            find: self.find,
            out,
        }
    }
}

/// Everything the fragment-shader path needs to draw a triangle.
pub(super) struct ShaderPass<'g, C, G: FragmentShader<C>, const TW: usize, const TH: usize> {
    pub(super) shader: &'g G,
    pub(super) shade: CustomFn<C, G, TW, TH>,
    /// `shade` for a draw whose clip-space `w` is the same at every vertex
    /// ([`constant_w`](Self::constant_w)).
    pub(super) affine_shade: CustomFn<C, G, TW, TH>,
    pub(super) find: FindFn,
    pub(super) out: Output,
}

// By hand: a derive would ask `C` and `G` to be `Copy`.
impl<C, G: FragmentShader<C>, const TW: usize, const TH: usize> Clone
    for ShaderPass<'_, C, G, TW, TH>
{
    fn clone(&self) -> Self {
        *self
    }
}

impl<C, G: FragmentShader<C>, const TW: usize, const TH: usize> Copy
    for ShaderPass<'_, C, G, TW, TH>
{
}

impl<'g, C, G: FragmentShader<C>, const TW: usize, const TH: usize> ShaderPass<'g, C, G, TW, TH> {
    /// The pass for a draw whose clip-space `w` is the same at every
    /// vertex ([`DrawSetup::constant_w`](crate::vertex::DrawSetup::constant_w)):
    /// interpolated affinely whatever the frame's mode, in the affine copy
    /// where the renderer links it ([`affine_shade`](Self::affine_shade)). There
    /// perspective-correct interpolation is affine, `Q` the constant
    /// `2^28`, and the affine path rounds each varying once after its sum
    /// where the exact weights are truncated first. Per run or triangle,
    /// never per pixel.
    #[inline(always)]
    pub(super) fn constant_w(mut self, constant: bool) -> Self {
        if constant {
            self.shade = self.affine_shade;
            self.out.mode = crate::shader::Perspective::Affine;
        }
        self
    }

    /// The pass with its output changed by `f`.
    pub(super) fn with(mut self, f: impl FnOnce(Output) -> Output) -> Self {
        self.out = f(self.out);
        self
    }
}

/// The [`ShadeFn`] of a triangle path the renderer does not link
/// ([`Features::FLAT`], [`Features::GOURAUD`]): never called, since
/// `begin` refuses a scene with such a draw, and it draws nothing, so the
/// path's set-up and span loop are left out.
fn shade_nothing<C, const TW: usize, const TH: usize>(
    _: &mut TileBuffer<C, TW, TH>,
    _: &PixelRect,
    _: &[&ScreenVertex; 3],
    _: &[Span],
    _: DepthTest,
) -> u32 {
    0
}

/// The fragment-shader function of a path the renderer does not link
/// ([`Features`]): never called, since the scene was refused or the path
/// is not taken, and it draws nothing.
// `fill::shade_custom`'s parameters again: it fills the same function pointer.
#[allow(clippy::too_many_arguments)]
fn shade_none<C, G: FragmentShader<C>, const TW: usize, const TH: usize>(
    _: &mut TileBuffer<C, TW, TH>,
    _: &PixelRect,
    _: &ShaderTriangle<'_, G::Varyings>,
    _: &[Span],
    _: &G,
    _: Option<&Texture<'_>>,
    _: Output,
) -> u32 {
    0
}
