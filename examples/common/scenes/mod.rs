//! Benchmark scenes, shared by `benches/raster.rs`, `examples/count.rs`
//! and `examples/raster_plot.rs` (`common::scenes`; they use the demo
//! scene of `common`).
//!
//! * [`DemoScene`]: the demo frame (torus knot + cube, frame 0 of the demo)
//!   at 320x240, as the demo renders it.
//! * [`FillScene`]: `layers` flat-shaded 320x240 quads, drawn back to front
//!   with the depth test on, so every fragment passes and is written.
//! * [`Copies`]: many copies of one triangle of a given pixel area,
//!   scattered over the frame, for per-triangle costs.
//! * [`EucDemo`]: the demo frame rendered by the `euc` crate, for comparison.
//! * [`TerrainScene`]: a terrain of 18,432 triangles imported in clusters,
//!   seen from on it: most of it lies outside the view.
#![allow(dead_code)]

use crate::common;
use embedded_graphics::pixelcolor::Rgb565;
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;

#[path = "../../bench_tile/mod.rs"]
mod bench_tile;
mod copies;
mod demo;
mod euc_demo;
mod fill;
mod rock;
mod terrain;

// Each example or bench that includes this file uses a different subset.
#[allow(unused_imports)]
pub use copies::{Copies, TRIANGLE_SIZES};
#[allow(unused_imports)]
pub use demo::{DemoScene, TexturedDemoScene};
#[allow(unused_imports)]
pub use euc_demo::EucDemo;
#[allow(unused_imports)]
pub use fill::FillScene;
#[allow(unused_imports)]
pub use rock::{RockScene, RockWorkspace, ROCK_FREQUENCY};
#[allow(unused_imports)]
pub use terrain::{TerrainScene, TERRAIN_CLUSTER, TERRAIN_QUADS};

/// Frame width of every scene.
pub const WIDTH: u32 = 320;
/// Frame height of every scene.
pub const HEIGHT: u32 = 240;

pub use bench_tile::{TILE_H, TILE_W};

/// The tiles of the frame: 80 in 32x32 tiles.
pub const TILES: usize = bench_tile::tiles(WIDTH, HEIGHT);

/// The renderer every benchmark uses: 32x32 tiles of `Rgb565` (or the
/// tiles named at build time in `MICRORASTER_BENCH_TILE=WxH`, for a study
/// of the tile size: `examples/bench_tile`).
pub type BenchRenderer = Renderer<Rgb565, TILE_W, TILE_H>;
/// The demo's workspace: the whole demo scene, all 80 tiles in one pass
/// (its 4,096 bin entries `MICRORASTER_BENCH_BINS` at build time if set).
pub type DemoWorkspace = Workspace<2048, { bench_tile::bin_entries(4096) }, TILES>;
/// A workspace for the triangle-copies scenes (up to 24,000 vertices).
pub type CopiesWorkspace = Workspace<24_000, 32_768, TILES>;

/// A workspace for the terrain scene (every vertex of the clustered
/// terrain, a slot each whether culled or not).
pub type TerrainWorkspace = Workspace<16_384, 16_384, TILES>;

/// A renderer with the demo's settings (back-face culling, `LessEqual`,
/// depth writes) and the scanline rasterizer.
pub fn renderer() -> BenchRenderer {
    renderer_with(Rasterizer::Scanline)
}

/// [`renderer`] with the given rasterizer.
pub fn renderer_with(raster: Rasterizer) -> BenchRenderer {
    BenchRenderer::new(Config::new(Size::new(WIDTH, HEIGHT), common::DEMO_CLEAR).rasterizer(raster))
}

/// The rasterizer named on a command line: `scanline`, `hilbert` or
/// `auto`.
pub fn parse_rasterizer(name: &str) -> Option<Rasterizer> {
    match name {
        "scanline" => Some(Rasterizer::Scanline),
        "hilbert" => Some(Rasterizer::Hilbert),
        "auto" => Some(Rasterizer::Auto),
        _ => None,
    }
}

/// The fill scenes' cameras, shared with the Cortex-M firmware's.
#[path = "../../fill_camera/mod.rs"]
mod fill_camera;
pub use fill_camera::{facing_camera, ndc_camera};

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

/// Pixel position (x right, y down) to a normalised-device-coordinate
/// vertex at depth `z`.
fn ndc(px: f32, py: f32, z: f32) -> Vec3Fx {
    [
        fx(px * 2.0 / WIDTH as f32 - 1.0),
        fx(1.0 - py * 2.0 / HEIGHT as f32),
        fx(z),
    ]
}

/// Leaks `v` so a mesh can borrow it for the rest of the program (scenes
/// are built once per process, and building a [`Mesh`] validates every
/// index, which is not per-frame work).
fn leak<T>(v: Vec<T>) -> &'static [T] {
    Vec::leak(v)
}

/// The benchmarks' 32x32 checker texture (`common::checker_texels`),
/// nearest: what the fill and textured demo scenes sample.
fn checker_texture() -> microraster::texture::Texture<'static> {
    use microraster::texture::{Texels, Texture};
    Texture::new(
        32,
        32,
        Texels::Rgb565(leak(crate::common::checker_texels(32))),
    )
    .expect("the checker texture is valid")
}
