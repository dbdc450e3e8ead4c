//! What a frame draws: a camera, a light and a list of draws.
//!
//! A [`Scene`] only borrows its draws, and a [`Draw`] only borrows its mesh,
//! so building a scene costs a few words of stack. Everything here is
//! per-frame set-up in `f32`; the renderer converts it to fixed point once.

use crate::light::{Intensity, Lighting, Material};
use crate::math::{Mat4, Vec3};
use crate::mesh::Mesh;
use crate::texture::Texture;
use embedded_graphics::pixelcolor::Rgb888;

/// How colour varies across a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Shading {
    /// One colour per triangle: the colour of its first vertex (the
    /// provoking vertex, as in OpenGL).
    Flat,
    /// Vertex colours interpolated linearly in screen space.
    #[default]
    Gouraud,
    /// Coloured per pixel by one of the scene's fragment shaders
    /// ([`Scene::shader`], [`Scene::shaders`]; the draw picks it with
    /// [`Draw::shader`]), with perspective-correct varyings.
    Shader,
    /// No fill: only the edges of the triangles that survive culling,
    /// as [`Draw::edges`] styles them (by default in the vertex colours).
    Wireframe,
    /// No fill: a square of this many pixels a side at every vertex of
    /// the triangles that survive culling, for vertices between the near
    /// and far planes and inside the guard band.
    Points(u8),
}

/// How a draw's triangle edges are drawn as lines (Bresenham, depth
/// tested): over the filled triangles as an overlay, or alone under
/// [`Shading::Wireframe`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Edges {
    /// One colour for every edge, or `None` for the lit vertex colours
    /// interpolated along each edge.
    pub color: Option<Rgb888>,
    /// Subtracted from the lines' depth (saturating), so that an overlay
    /// wins the depth test against the faces it outlines: their depths
    /// differ by rounding only, so a few units suffice.
    pub depth_bias: u16,
}

impl Edges {
    /// Edges in one colour, with a depth bias of 64.
    pub const fn new(color: Rgb888) -> Self {
        Self {
            color: Some(color),
            depth_bias: 64,
        }
    }

    /// Edges in the vertex colours, with a depth bias of 64.
    pub const fn vertex_colors() -> Self {
        Self {
            color: None,
            depth_bias: 64,
        }
    }

    /// Sets the depth bias.
    pub const fn depth_bias(mut self, bias: u16) -> Self {
        self.depth_bias = bias;
        self
    }
}

impl Default for Edges {
    fn default() -> Self {
        Self::vertex_colors()
    }
}

/// How a draw's fragments combine with what the tile already holds.
///
/// Transparent draws (anything but [`Blend::Opaque`]) are drawn after all
/// opaque triangles of a tile, back to front (farthest vertex depth first,
/// in batches of [`MAX_TRANSPARENT`](crate::render::MAX_TRANSPARENT) per
/// tile), depth tested but without writing depth, so they never hide each
/// other or what is behind them. A draw's edges and points
/// ([`Edges`], [`Shading::Wireframe`], [`Shading::Points`]) are always
/// opaque: blending applies to its filled triangles. Their colour comes through the fragment-shader
/// path: flat and Gouraud colour perspective-correct, as
/// [`shader::Flat`](crate::shader::Flat) and
/// [`shader::Gouraud`](crate::shader::Gouraud) give.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Blend {
    /// The fragment replaces the pixel.
    #[default]
    Opaque,
    /// Source alpha over one minus source alpha: `(src a + dst (255 - a))
    /// / 255` per channel, rounded; `a = 255` is opaque but still drawn
    /// in the transparent pass.
    Alpha(u8),
    /// `src + dst` per channel, saturated.
    Additive,
}

impl Blend {
    /// The colour of a pixel holding `dst` after a fragment `src`.
    #[inline(always)]
    pub fn apply(self, src: [u8; 3], dst: [u8; 3]) -> [u8; 3] {
        match self {
            Blend::Opaque => src,
            Blend::Alpha(a) => {
                let (a, b) = (a as u32, 255 - a as u32);
                [0, 1, 2].map(|k| {
                    // Exact rounding of p / 255 for p <= 65,025.
                    let p = src[k] as u32 * a + dst[k] as u32 * b + 128;
                    ((p + (p >> 8)) >> 8) as u8
                })
            }
            Blend::Additive => [0, 1, 2].map(|k| src[k].saturating_add(dst[k])),
        }
    }
}

/// Which faces are discarded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum CullMode {
    /// Keep every triangle.
    None,
    /// Discard triangles facing away (clockwise in NDC, y up).
    #[default]
    Back,
    /// Discard triangles facing the camera.
    Front,
}

/// The camera: a view matrix and a projection matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// World to eye space.
    pub view: Mat4,
    /// Eye to clip space ([`Mat4::perspective`] or [`Mat4::orthographic`]).
    pub projection: Mat4,
}

impl Camera {
    /// A camera from a view and a projection matrix.
    pub const fn new(view: Mat4, projection: Mat4) -> Self {
        Self { view, projection }
    }

    /// The eye's position in world space, for highlights and fog: `-Rᵀ t`
    /// of a rigid view matrix `[R | t]` (as [`Mat4::look_at`] makes).
    pub fn eye(&self) -> Vec3 {
        let m = &self.view.m;
        let t = Vec3::new(m[3][0], m[3][1], m[3][2]);
        // The dot product through the soft-float short cuts where `f32`
        // is in software (the same bits, in the same order).
        let col = |c: usize| -crate::math::soft_float::dot(Vec3::new(m[c][0], m[c][1], m[c][2]), t);
        Vec3::new(col(0), col(1), col(2))
    }
}

/// A directional light plus an ambient term, evaluated per vertex in fixed
/// point (Lambert diffuse): the simple case of a
/// [`Lighting`] with one
/// [`DirectionalLight`](crate::light::DirectionalLight), which it is turned
/// into (with the same colours, bit for bit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction *towards* the light, in world space (need not be unit).
    pub direction: Vec3,
    /// Diffuse colour of the light.
    pub color: Rgb888,
    /// Ambient colour, added everywhere.
    pub ambient: Rgb888,
}

impl Light {
    /// A white light from `direction` with a dim grey ambient term.
    pub const fn new(direction: Vec3) -> Self {
        Self {
            direction,
            color: Rgb888::new(255, 255, 255),
            ambient: Rgb888::new(48, 48, 48),
        }
    }

    /// Sets the diffuse colour: a colour or a fraction of white
    /// ([`Intensity`]).
    ///
    /// ```
    /// use embedded_graphics::pixelcolor::Rgb888;
    /// use microraster::prelude::*;
    /// let light = Light::new(Vec3::new(1.0, 1.0, 1.0)).color(0.8).ambient(0.1);
    /// assert_eq!(light.color, Rgb888::new(204, 204, 204));
    /// assert_eq!(light.ambient, Rgb888::new(26, 26, 26));
    /// ```
    pub fn color(mut self, color: impl Into<Intensity>) -> Self {
        self.color = color.into().0;
        self
    }

    /// Sets the ambient colour: a colour or a fraction of white
    /// ([`Intensity`]).
    pub fn ambient(mut self, ambient: impl Into<Intensity>) -> Self {
        self.ambient = ambient.into().0;
        self
    }
}

/// One mesh placed in the world, with its colour and shading.
#[derive(Clone, Copy, Debug)]
pub struct Draw<'a> {
    /// The mesh.
    pub mesh: &'a Mesh<'a>,
    /// Model to world transform.
    pub transform: Mat4,
    /// Base colour, used when the mesh has no vertex colours.
    pub color: Rgb888,
    /// Flat, Gouraud or one of the scene's shaders.
    pub shading: Shading,
    /// Which of the scene's shaders colours a [`Shading::Shader`] draw: its
    /// place in the scene's [`ShaderSet`](crate::shader::ShaderSet).
    pub shader: u8,
    /// The texture the scene's shader may sample.
    pub texture: Option<&'a Texture<'a>>,
    /// Opaque or transparent.
    pub blend: Blend,
    /// Edges drawn as lines over the triangles (see [`Edges`]).
    pub edges: Option<Edges>,
    /// How the surface reflects the scene's lights.
    pub material: Material,
}

impl<'a> Draw<'a> {
    /// A white, Gouraud-shaded draw of `mesh` at the origin.
    pub fn new(mesh: &'a Mesh<'a>) -> Self {
        Self {
            mesh,
            transform: Mat4::IDENTITY,
            color: Rgb888::new(255, 255, 255),
            shading: Shading::Gouraud,
            shader: 0,
            texture: None,
            blend: Blend::Opaque,
            edges: None,
            material: Material::new(),
        }
    }

    /// Sets the model to world transform.
    pub fn transform(mut self, transform: Mat4) -> Self {
        self.transform = transform;
        self
    }

    /// Sets the base colour.
    pub fn color(mut self, color: Rgb888) -> Self {
        self.color = color;
        self
    }

    /// Sets the shading.
    pub fn shading(mut self, shading: Shading) -> Self {
        self.shading = shading;
        self
    }

    /// Colours the draw with shader `index` of the scene's
    /// [`ShaderSet`](crate::shader::ShaderSet) (0 for the first, or only,
    /// one): sets the shading to [`Shading::Shader`].
    pub fn shader(mut self, index: u8) -> Self {
        self.shading = Shading::Shader;
        self.shader = index;
        self
    }

    /// Draws the triangles' edges as lines over them (or, under
    /// [`Shading::Wireframe`], alone).
    pub fn edges(mut self, edges: Edges) -> Self {
        self.edges = Some(edges);
        self
    }

    /// Sets the material (the default reflects ambient and diffuse light
    /// white, without highlights).
    pub fn material(mut self, material: Material) -> Self {
        self.material = material;
        self
    }

    /// Makes the draw transparent (see [`Blend`]).
    pub fn blend(mut self, blend: Blend) -> Self {
        self.blend = blend;
        self
    }

    /// Gives the draw a texture, for the scene's shader to sample.
    pub fn texture(mut self, texture: &'a Texture<'a>) -> Self {
        self.texture = Some(texture);
        self
    }
}

/// The shaders of a scene that has none. [`Shading::Shader`] draws are an
/// error without a shader
/// ([`RenderError::MissingShader`](crate::render::RenderError::MissingShader)).
/// It is an empty [`ShaderSet`](crate::shader::ShaderSet), and a
/// [`FragmentShader`](crate::shader::FragmentShader) of every colour that
/// draws nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoShader;

/// Everything one frame draws.
///
/// ```
/// use microraster::prelude::*;
/// let camera = Camera::new(
///     Mat4::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::default(), Vec3::new(0.0, 1.0, 0.0)).unwrap(),
///     Mat4::perspective(1.0, 4.0 / 3.0, 0.5, 20.0).unwrap(),
/// );
/// let scene = Scene::new(camera, &[]).light(Light::new(Vec3::new(1.0, 1.0, 1.0)));
/// assert!(scene.light.is_some());
/// ```
///
/// Draws with [`Shading::Shader`] are coloured by the scene's fragment
/// shaders `S`, a [`ShaderSet`](crate::shader::ShaderSet) that the renderer
/// is monomorphized for: one shader, or several that each draw picks from
/// by index ([`Draw::shader`]):
///
/// ```
/// use microraster::prelude::*;
/// use microraster::shader::{Normals, Textured};
/// # let positions = [[fixed::types::I16F16::ZERO; 3]; 3];
/// # let mesh = Mesh::new(&positions, &[[0, 1, 2]]).unwrap();
/// let camera = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
/// let one = Scene::new(camera, &[]).shader(&Textured);
/// let draws = [
///     Draw::new(&mesh).shader(0), // textured
///     Draw::new(&mesh).shader(1), // its normals as colours
///     Draw::new(&mesh),           // Gouraud, no shader
/// ];
/// let two = Scene::new(camera, &draws).shaders((Textured, Normals));
/// # let _ = (one, two);
/// ```
pub struct Scene<'a, S = NoShader> {
    /// The camera.
    pub camera: Camera,
    /// One directional light and an ambient term: the simple way to light
    /// a scene. Without it (or [`lighting`](Self::lighting)), vertices keep
    /// their unlit colour.
    pub light: Option<Light>,
    /// Any number of directional and point lights, highlights and fog
    /// (up to [`MAX_LIGHTS`](crate::render::MAX_LIGHTS) lights); replaces
    /// [`light`](Self::light) when set.
    pub lighting: Option<&'a Lighting<'a>>,
    /// The draws, rendered in order (later ones win depth ties under
    /// [`crate::DepthTest::LessEqual`]).
    pub draws: &'a [Draw<'a>],
    /// The fragment shaders of [`Shading::Shader`] draws: a
    /// [`ShaderSet`](crate::shader::ShaderSet).
    pub shaders: S,
}

// By hand: derived impls would require `S: Debug`.
impl<S: Clone> Clone for Scene<'_, S> {
    fn clone(&self) -> Self {
        Self {
            camera: self.camera,
            light: self.light,
            lighting: self.lighting,
            draws: self.draws,
            shaders: self.shaders.clone(),
        }
    }
}
impl<S: Copy> Copy for Scene<'_, S> {}
impl<S> core::fmt::Debug for Scene<'_, S> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Scene")
            .field("camera", &self.camera)
            .field("light", &self.light)
            .field("lighting", &self.lighting)
            .field("draws", &self.draws)
            .field("shaders", &core::any::type_name::<S>())
            .finish()
    }
}

impl<'a> Scene<'a> {
    /// An unlit scene without a fragment shader.
    pub const fn new(camera: Camera, draws: &'a [Draw<'a>]) -> Self {
        Self {
            camera,
            light: None,
            lighting: None,
            draws,
            shaders: NoShader,
        }
    }
}

impl<'a, S> Scene<'a, S> {
    /// Lights the scene.
    pub const fn light(mut self, light: Light) -> Self {
        self.light = Some(light);
        self
    }

    /// Lights the scene with any number of lights, highlights and fog.
    pub const fn lighting(mut self, lighting: &'a Lighting<'a>) -> Self {
        self.lighting = Some(lighting);
        self
    }

    /// Sets the fragment shader of [`Shading::Shader`] draws: the scene's
    /// only one, index 0.
    pub fn shader<T>(self, shader: &'a T) -> Scene<'a, &'a T> {
        self.shaders(shader)
    }

    /// Sets the fragment shaders of [`Shading::Shader`] draws: a tuple of
    /// up to eight, which each draw picks from by index
    /// ([`Draw::shader`]), or any other [`ShaderSet`](crate::shader::ShaderSet).
    pub fn shaders<T>(self, shaders: T) -> Scene<'a, T> {
        Scene {
            camera: self.camera,
            light: self.light,
            lighting: self.lighting,
            draws: self.draws,
            shaders,
        }
    }
}
