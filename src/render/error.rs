//! Why a frame could not be rendered.

use super::MAX_TRIANGLES;
use crate::light::LightError;
use crate::shader::ShaderError;
use crate::vertex::{VertexError, MAX_VIEWPORT};
use embedded_graphics::prelude::Size;

/// Why a frame could not be rendered. Every error except `Sink` is found
/// before the first tile is sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError<E = core::convert::Infallible> {
    /// The frame has a zero width or height.
    ZeroViewport,
    /// A side is larger than [`MAX_VIEWPORT`].
    ViewportTooLarge {
        /// Requested size.
        size: Size,
    },
    /// The camera's matrices are not finite or not representable.
    BadCamera,
    /// The scene's light or lighting is invalid: a zero or non-finite
    /// direction or position, a bad range or fog, or more than
    /// [`MAX_LIGHTS`](super::MAX_LIGHTS) lights.
    Light(LightError),
    /// A draw's matrices or vertices could not be transformed.
    Draw {
        /// Index of the draw in the scene.
        draw: usize,
        /// What went wrong.
        error: VertexError,
    },
    /// The scene has more vertices than the workspace holds.
    VertexCapacity {
        /// Vertices in the scene.
        needed: usize,
        /// `VERTICES` of the workspace.
        capacity: usize,
    },
    /// The scene has more than [`MAX_TRIANGLES`] triangles.
    TooManyTriangles {
        /// Triangles in the scene.
        count: usize,
    },
    /// A draw uses [`Shading::Shader`](crate::scene::Shading::Shader) with
    /// a shader index ([`Draw::shader`](crate::scene::Draw::shader)) that
    /// the scene's shaders do not have: the scene has none, or fewer.
    MissingShader {
        /// Index of the draw in the scene.
        draw: usize,
        /// The shader it asks for.
        index: usize,
    },
    /// A draw lacks what the scene's shader reads.
    Shader {
        /// Index of the draw in the scene.
        draw: usize,
        /// What is missing.
        error: ShaderError,
    },
    /// The scene or the configuration asks for a path that the renderer's
    /// [`Features`](super::Features) leave out.
    Unsupported {
        /// The draw that asks for it, or `None` for the configuration.
        draw: Option<usize>,
        /// The path.
        path: super::Path,
    },
    /// The sink failed; tiles before it were delivered.
    Sink(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::ZeroViewport => write!(f, "the frame has zero width or height"),
            Self::ViewportTooLarge { size } => write!(
                f,
                "frame {}x{} exceeds the {MAX_VIEWPORT}-pixel limit per side",
                size.width, size.height
            ),
            Self::BadCamera => write!(f, "the camera matrices are not finite, or their product is zero"),
            Self::Light(e) => write!(f, "lighting: {e}"),
            Self::Draw { draw, error } => match error {
                VertexError::BadMatrix => write!(
                    f,
                    "draw {draw}: its transform is not finite, or cannot be represented in 16.16 in any units"
                ),
                VertexError::OutOfRange { vertex } => write!(
                    f,
                    "draw {draw}: vertex {vertex} leaves the 16.16 range of clip space"
                ),
                VertexError::GeneralLighting => write!(
                    f,
                    "draw {draw}: needs the general lighting, which this renderer does not link"
                ),
            },
            Self::VertexCapacity { needed, capacity } => write!(
                f,
                "the scene has {needed} vertices but the workspace holds {capacity}"
            ),
            Self::TooManyTriangles { count } => write!(
                f,
                "the scene has {count} triangles, more than {MAX_TRIANGLES}"
            ),
            Self::MissingShader { draw, index } => write!(
                f,
                "draw {draw} uses shader {index}, which the scene does not have"
            ),
            Self::Shader { draw, error } => write!(f, "draw {draw}: {error}"),
            Self::Unsupported { draw, path } => {
                if let Some(d) = draw {
                    write!(f, "draw {d}: ")?;
                }
                write!(f, "not linked into this renderer (its Features): {path}")
            }
            Self::Sink(e) => write!(f, "the sink failed: {e:?}"),
        }
    }
}

impl RenderError {
    /// The same error as a [`RenderError`] of any sink: what
    /// [`Renderer::begin`](super::Renderer::begin) finds is never a sink's
    /// error.
    pub fn for_sink<E>(self) -> RenderError<E> {
        match self {
            Self::ZeroViewport => RenderError::ZeroViewport,
            Self::ViewportTooLarge { size } => RenderError::ViewportTooLarge { size },
            Self::BadCamera => RenderError::BadCamera,
            Self::Light(e) => RenderError::Light(e),
            Self::Draw { draw, error } => RenderError::Draw { draw, error },
            Self::VertexCapacity { needed, capacity } => {
                RenderError::VertexCapacity { needed, capacity }
            }
            Self::TooManyTriangles { count } => RenderError::TooManyTriangles { count },
            Self::MissingShader { draw, index } => RenderError::MissingShader { draw, index },
            Self::Shader { draw, error } => RenderError::Shader { draw, error },
            Self::Unsupported { draw, path } => RenderError::Unsupported { draw, path },
            Self::Sink(never) => match never {},
        }
    }
}
