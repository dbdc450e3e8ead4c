//! What a frame draws: a camera, a light and a list of draws.
//!
//! A [`Scene`] only borrows its draws, and a [`Draw`] only borrows its mesh,
//! so building a scene costs a few words of stack. Everything here is
//! per-frame set-up in `f32`; the renderer converts it to fixed point once.

use crate::math::{Mat4, Vec3};
use crate::mesh::Mesh;
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
}

/// A directional light plus an ambient term, evaluated per vertex in fixed
/// point (Lambert diffuse).
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

    /// Sets the diffuse colour.
    pub const fn color(mut self, color: Rgb888) -> Self {
        self.color = color;
        self
    }

    /// Sets the ambient colour.
    pub const fn ambient(mut self, ambient: Rgb888) -> Self {
        self.ambient = ambient;
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
    /// Flat or Gouraud.
    pub shading: Shading,
}

impl<'a> Draw<'a> {
    /// A white, Gouraud-shaded draw of `mesh` at the origin.
    pub fn new(mesh: &'a Mesh<'a>) -> Self {
        Self {
            mesh,
            transform: Mat4::IDENTITY,
            color: Rgb888::new(255, 255, 255),
            shading: Shading::Gouraud,
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
}

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
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// The camera.
    pub camera: Camera,
    /// The light; without one, vertices keep their unlit colour.
    pub light: Option<Light>,
    /// The draws, rendered in order (later ones win depth ties under
    /// [`crate::DepthTest::LessEqual`]).
    pub draws: &'a [Draw<'a>],
}

impl<'a> Scene<'a> {
    /// An unlit scene.
    pub const fn new(camera: Camera, draws: &'a [Draw<'a>]) -> Self {
        Self {
            camera,
            light: None,
            draws,
        }
    }

    /// Lights the scene.
    pub const fn light(mut self, light: Light) -> Self {
        self.light = Some(light);
        self
    }
}
