//! Which optional paths a renderer links ([`Features`]).

/// Which optional paths a renderer links: chosen by a type, so that a
/// firmware pays in flash only for what it draws.
///
/// Everything a scene or a [`Config`](super::Config) selects at run time
/// (a rasterizer, fragment shaders, lines, blending, culling, sorting) has
/// to be linked into a firmware that might select it. A [`Features`] type
/// says at compile time which of them a [`Renderer`](super::Renderer)
/// supports; the code of the others is never reached, and the optimiser
/// leaves it out. [`All`] (the default) supports everything;
/// [`Triangles`] only flat and Gouraud triangles, [`GouraudTriangles`]
/// only Gouraud ones; a firmware can name its own set.
///
/// A scene that asks for a path its renderer does not link is refused by
/// [`Renderer::begin`](super::Renderer::begin) with
/// [`RenderError::Unsupported`](super::RenderError::Unsupported), except
/// for the two paths that only change the speed, never the picture: the
/// Hilbert rasterizer (the scanline rasterizer draws instead) and frustum
/// culling (nothing is culled).
///
/// ```
/// use microraster::prelude::*;
/// use microraster::render::Features;
/// use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
///
/// /// Triangles and wireframe overlays, culled against the frustum.
/// struct Overlays;
/// impl Features for Overlays {
///     // Every path is in unless left out.
///     const HILBERT: bool = false;
///     const SHADERS: bool = false;
///     const BLEND: bool = false;
///     const SORT: bool = false;
/// }
/// let renderer: Renderer<Rgb565, 32, 32, Overlays> =
///     Renderer::new(Config::new(Size::new(320, 240), Rgb565::BLACK));
/// ```
pub trait Features {
    /// The Hilbert-order rasterizer, for [`Rasterizer::Hilbert`] and
    /// [`Rasterizer::Auto`](crate::Rasterizer::Auto); without it they draw
    /// with the scanline rasterizer (the same image).
    ///
    /// [`Rasterizer::Hilbert`]: crate::Rasterizer::Hilbert
    const HILBERT: bool = true;
    /// Fragment shaders: draws with
    /// [`Shading::Shader`](crate::scene::Shading::Shader).
    const SHADERS: bool = true;
    /// Lines and points: [`Shading::Wireframe`](crate::scene::Shading::Wireframe),
    /// [`Shading::Points`](crate::scene::Shading::Points) and
    /// [`Draw::edges`](crate::scene::Draw::edges).
    const LINES: bool = true;
    /// Transparent draws: a [`Blend`](crate::scene::Blend) other than
    /// `Opaque`.
    const BLEND: bool = true;
    /// Culling draws and mesh clusters against the view frustum
    /// ([`Config::frustum_cull`](super::Config::frustum_cull)); without it
    /// nothing is culled (the same image).
    const CULL: bool = true;
    /// Visiting draws sorted by depth
    /// ([`Config::sort_draws`](super::Config::sort_draws)).
    const SORT: bool = true;
    /// Depth comparisons other than [`DepthTest::LessEqual`] with depth
    /// writes, the default (see
    /// [`Config::depth_test`](super::Config::depth_test)).
    ///
    /// [`DepthTest::LessEqual`]: crate::DepthTest::LessEqual
    const DEPTH_TESTS: bool = true;
    /// The general lighting: [`Scene::lighting`](crate::scene::Scene::lighting)
    /// with more than one light, point lights or fog, and materials other
    /// than white and matte. Without it a draw is lit only by the fast
    /// path: one directional light and ambient (a
    /// [`Scene::light`](crate::scene::Scene::light)) on the default
    /// material.
    const LIGHTING: bool = true;
    /// Flat triangles: [`Shading::Flat`](crate::scene::Shading::Flat)
    /// (their attribute set-up and span loop).
    const FLAT: bool = true;
    /// Gouraud triangles:
    /// [`Shading::Gouraud`](crate::scene::Shading::Gouraud) (their
    /// attribute set-up and span loop, the largest of the triangle paths).
    const GOURAUD: bool = true;
    /// The opaque quasi-perspective span loops: in a frame with
    /// [`Perspective::Quasi8`] or [`Perspective::Quasi16`], opaque draws'
    /// spans (but those of draws of constant `w`, see [`Features::AFFINE`])
    /// go to
    /// [`FragmentShader::shade_quasi_spans`](crate::shader::FragmentShader::shade_quasi_spans),
    /// a second copy of each shader's shading function. Without it they
    /// take the general loop (the same image, more instructions a pixel),
    /// and a firmware that never draws quasi-perspective frames does not
    /// link that copy.
    ///
    /// [`Perspective::Quasi8`]: crate::shader::Perspective::Quasi8
    /// [`Perspective::Quasi16`]: crate::shader::Perspective::Quasi16
    const QUASI: bool = true;
    /// The opaque affine span loops: in a frame with
    /// [`Perspective::Affine`], and in any frame for a draw whose
    /// clip-space `w` is the same at every vertex (an orthographic camera,
    /// see [`Perspective`]), opaque draws' spans go to
    /// [`FragmentShader::shade_affine_spans`](crate::shader::FragmentShader::shade_affine_spans),
    /// a copy of each shader's shading function of its own. Without it
    /// they take the general loop (the same image, more instructions a
    /// pixel), and a firmware does not link that copy.
    ///
    /// [`Perspective`]: crate::shader::Perspective
    /// [`Perspective::Affine`]: crate::shader::Perspective::Affine
    const AFFINE: bool = true;
    /// Meshes with `u32` vertex indices ([`Mesh::new_u32`]); without it
    /// only `u16` meshes are binned, and a draw of a `u32` mesh is refused.
    ///
    /// [`Mesh::new_u32`]: crate::mesh::Mesh::new_u32
    const U32_INDICES: bool = true;
}

/// Every path (the default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct All;

impl Features for All {}

/// Flat and Gouraud triangles only, with the scanline rasterizer, the
/// default depth test, one directional light, `u16` mesh indices and no
/// frustum culling: the smallest firmware. Its parameters say which of the
/// two triangle paths it keeps ([`Features::FLAT`],
/// [`Features::GOURAUD`]); `Triangles` keeps both, [`GouraudTriangles`]
/// Gouraud only.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Triangles<const FLAT: bool = true, const GOURAUD: bool = true>;

impl<const FLAT: bool, const GOURAUD: bool> Features for Triangles<FLAT, GOURAUD> {
    const HILBERT: bool = false;
    const SHADERS: bool = false;
    const LINES: bool = false;
    const BLEND: bool = false;
    const CULL: bool = false;
    const SORT: bool = false;
    const DEPTH_TESTS: bool = false;
    const LIGHTING: bool = false;
    const QUASI: bool = false;
    const AFFINE: bool = false;
    const U32_INDICES: bool = false;
    const FLAT: bool = FLAT;
    const GOURAUD: bool = GOURAUD;
}

/// Gouraud triangles only: [`Triangles`] without flat shading, the
/// smallest set that draws lit meshes (flat triangles' set-up and span
/// loop left out too). A draw with
/// [`Shading::Flat`](crate::scene::Shading::Flat) is refused with
/// [`Path::Flat`].
pub type GouraudTriangles = Triangles<false, true>;

/// A path a [`Features`] type can leave out, named in
/// [`RenderError::Unsupported`](super::RenderError::Unsupported).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Path {
    /// [`Features::SHADERS`].
    Shaders,
    /// [`Features::LINES`].
    Lines,
    /// [`Features::BLEND`].
    Blend,
    /// [`Features::SORT`].
    Sort,
    /// [`Features::DEPTH_TESTS`].
    DepthTests,
    /// [`Features::LIGHTING`].
    Lighting,
    /// [`Features::U32_INDICES`].
    U32Indices,
    /// [`Features::FLAT`].
    Flat,
    /// [`Features::GOURAUD`].
    Gouraud,
}

impl core::fmt::Display for Path {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Path::Shaders => "fragment shaders",
            Path::Lines => "lines and points",
            Path::Blend => "blending",
            Path::Sort => "sorted draws",
            Path::DepthTests => "depth tests other than LessEqual with writes",
            Path::Lighting => "the general lighting",
            Path::U32Indices => "u32 mesh indices",
            Path::Flat => "flat triangles",
            Path::Gouraud => "Gouraud triangles",
        })
    }
}
