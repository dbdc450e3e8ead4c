//! [`RockScene`]: a geodesic sphere of small, uneven triangles.

use super::{BenchRenderer, HEIGHT, TILES, WIDTH};
use crate::common::{self, rock_scene};
use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;

/// Subdivision frequency of the rock: `20 n²` triangles, `10 n² + 2`
/// vertices (3,920 and 1,962).
pub const ROCK_FREQUENCY: usize = rock_scene::FREQUENCY;

/// A workspace for the rock: all its vertices, all 80 tiles in one pass
/// (its 6,144 bin entries `MICRORASTER_BENCH_BINS` at build time if set).
pub type RockWorkspace = Workspace<2048, { super::bench_tile::bin_entries(6144) }, TILES>;

/// A small-triangle mesh like a scanned or modelled one: a geodesic sphere
/// of frequency [`ROCK_FREQUENCY`] (3,920 triangles), every vertex pushed
/// in or out by a smooth bulge and a small random bump, so that the
/// triangles differ in size and shape, with per-vertex normals. It fills
/// most of the 320x240 frame at 5 to 20 pixels per visible triangle.
pub struct RockScene {
    mesh: Mesh<'static>,
}

impl RockScene {
    /// Builds the mesh (`examples/rock_scene`: in `f32` with IEEE basic
    /// operations and square roots only, so every machine, and a
    /// firmware's constant evaluation, makes the same one).
    pub fn new() -> Self {
        let data: &'static rock_scene::RockData = Box::leak(Box::new(rock_scene::rock_data()));
        let mesh = Mesh::new(&data.positions, &data.triangles)
            .and_then(|m| m.with_normals(&data.normals))
            .expect("a valid rock");
        Self { mesh }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh<'static> {
        &self.mesh
    }

    /// The camera: the rock seen from its front, slightly above.
    pub fn camera() -> Camera {
        rock_scene::camera(WIDTH, HEIGHT).expect("a valid camera")
    }

    /// Renders the rock, Gouraud-shaded and lit like the demo.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut RockWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = rock_scene::draws(&self.mesh);
        let scene = Scene::new(Self::camera(), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("the rock renders")
    }
}
