//! # microraster
//!
//! A `no_std`, allocation-free 3D rasterizer for microcontrollers. Vertices
//! are transformed in 16.16 fixed point ([`fixed::types::I16F16`]),
//! triangles are clipped in homogeneous space, culled, binned to tiles and
//! rasterized one small tile at a time into a [`TileBuffer`] of colour and
//! 16-bit depth; every finished tile is streamed to a [`TileSink`], which
//! any embedded-graphics `DrawTarget` is. No frame buffer is ever held, so
//! a 320x240 display is driven from a few tens of kilobytes of RAM.
//!
//! ## The triangle path
//!
//! [`vertex`] (MVP, lighting, outcodes, viewport) → [`clip`] (near, far and
//! guard band, Sutherland–Hodgman) → [`render`] (culling, binning, the tile
//! loop) → [`raster::scanline`] (coverage) → [`shade`] (depth test and
//! colour) → [`tile`] → [`sink`].
//!
//! ## Conventions
//!
//! * Clip space is OpenGL's: x, y, z in `[-w, w]`; depth z/w maps to
//!   `0..=65535` (0 nearest). The front face is counter-clockwise in
//!   normalised device coordinates (y up).
//! * Screen space has its origin at the top-left, x right, y down; pixel
//!   `(i, j)` has its centre at `(i + ½, j + ½)`. Positions are snapped to
//!   1/16 pixel.
//! * Fill rule: a pixel is drawn when its centre is inside the triangle, or
//!   on a top or left edge (see [`raster`]). Shared edges are drawn once.
//! * Everything per vertex and per pixel is integer arithmetic, so every
//!   target renders bit-identical images. `f32` appears only in per-frame
//!   set-up ([`math`]), using integers and IEEE basic operations only
//!   (trigonometry included).
//!
//! ## Example
//!
//! ```
//! use microraster::prelude::*;
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::BinaryColor};
//! use fixed::types::I16F16;
//!
//! // One triangle, covering the middle of a 16x16 frame.
//! let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
//! let positions = [p(-0.5, -0.5), p(0.5, -0.5), p(0.0, 0.5)];
//! let triangles = [[0u16, 1, 2]];
//! let mesh = Mesh::new(&positions, &triangles).unwrap();
//! let draws = [Draw::new(&mesh)];
//! let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
//!
//! let mut renderer: Renderer<BinaryColor, 16, 16> =
//!     Renderer::new(Config::new(Size::new(16, 16), BinaryColor::Off));
//! let mut workspace: Workspace<16, 64, 1> = Workspace::new();
//! let mut display = MockDisplay::new();
//! let stats = renderer.render(&mut workspace, &scene, &mut display).unwrap();
//! assert_eq!(stats.drawn, 1);
//! assert_eq!(display.get_pixel(Point::new(8, 8)), Some(BinaryColor::On));
//! assert_eq!(display.get_pixel(Point::new(1, 1)), Some(BinaryColor::Off));
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod clip;
pub mod cull;
mod hint;
pub mod light;
pub mod math;
pub mod mesh;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shade;
pub mod shader;
pub mod shapes;
pub mod sink;
pub mod texture;
pub mod tile;
pub mod vertex;

// The versions of the two crates in the library's signatures, so that a
// program names exactly these (`microraster::fixed::types::I16F16`,
// `microraster::embedded_graphics::pixelcolor::Rgb565`) and cannot pick
// another, incompatible version of either.
pub use embedded_graphics;
pub use fixed;

pub use raster::Rasterizer;
pub use render::{Config, Features, FrameStats, Profiler, RenderError, Renderer, Stage, Workspace};
pub use shade::DepthTest;
pub use sink::{
    AsyncTileSink, FrameBuffer, FrameBufferError, NullSink, Rgb565Be, TileQueue, TileSink,
    TileTransfer,
};
pub use tile::{TileBuffer, TileOrder, TileView};

/// The types most programs need: the scene, the renderer, lighting,
/// textures, the fragment-shader interface with the built-in shaders, and
/// what a [`TileSink`], [`TileTransfer`] or [`AsyncTileSink`]
/// implementation names.
pub mod prelude {
    pub use crate::light::{DirectionalLight, Lighting, Material, PointLight};
    pub use crate::math::{Mat4, Vec3};
    pub use crate::mesh::{Mesh, MeshError};
    pub use crate::raster::Rasterizer;
    pub use crate::render::{Config, FrameStats, RenderError, Renderer, Workspace};
    pub use crate::scene::{Blend, Camera, CullMode, Draw, Edges, Light, Scene, Shading};
    pub use crate::shade::DepthTest;
    pub use crate::shader::{
        DepthShade, Dithered, Flat, Fragment, FragmentShader, Gouraud, Interpolated, Normals,
        Perspective, PixelFn, ShaderSet, SpanInput, Textured, TexturedLit, VertexInput,
    };
    pub use crate::sink::{
        AsyncTileSink, FrameBuffer, FrameBufferError, NullSink, Rgb565Be, TileQueue, TileSink,
        TileTransfer,
    };
    pub use crate::texture::{Filter, FromTexel, Texels, Texture};
    pub use crate::tile::{TileBuffer, TileOrder, TileView};
    pub use embedded_graphics::pixelcolor::PixelColor;
    pub use embedded_graphics::prelude::{Point, Size};
    pub use embedded_graphics::primitives::Rectangle;
}

/// Helpers shared by the unit tests.
#[cfg(test)]
pub(crate) mod testing {
    /// A xorshift generator, the same sequence every run: `next(m)` is the
    /// next value modulo `m`.
    pub(crate) fn rng() -> impl FnMut(u64) -> u64 {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        move |m: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % m
        }
    }
}

/// The README's code examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
