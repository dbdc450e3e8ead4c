//! [`TerrainScene`]: a terrain imported in clusters, seen from on it.

use super::{BenchRenderer, TerrainWorkspace, HEIGHT, WIDTH};
use crate::common;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;

/// Quads per side of [`TerrainScene`]'s terrain.
pub const TERRAIN_QUADS: usize = 96;
/// Most triangles per cluster of [`TerrainScene`]'s terrain.
pub const TERRAIN_CLUSTER: usize = 64;

/// A terrain of 96x96 quads (18,432 triangles) imported in clusters of at
/// most 64 triangles, seen from a point on it looking across: what lies
/// behind and beside the view is culled cluster by cluster.
pub struct TerrainScene {
    clustered: Mesh<'static>,
    whole: Mesh<'static>,
}

impl TerrainScene {
    /// Imports the terrain, in clusters and without, and builds the meshes
    /// once (building one checks every index: set-up, not frame, work).
    pub fn new() -> Self {
        let obj = common::terrain_obj(TERRAIN_QUADS);
        let clustered: &'static common::ImportedModel =
            Box::leak(Box::new(common::ImportedModel::new(&obj, TERRAIN_CLUSTER)));
        let whole: &'static common::ImportedModel =
            Box::leak(Box::new(common::ImportedModel::new(&obj, 0)));
        Self {
            clustered: clustered.clustered(),
            whole: whole.whole(),
        }
    }

    /// The camera: above the terrain's centre, looking along -z.
    pub fn camera() -> Camera {
        let view = Mat4::look_at(
            Vec3::new(0.0, 5.0, 8.0),
            Vec3::new(-6.0, 1.0, -20.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .expect("a valid view");
        let proj = Mat4::perspective(1.0, WIDTH as f32 / HEIGHT as f32, 0.3, 60.0)
            .expect("a valid projection");
        Camera::new(view, proj)
    }

    /// Renders the terrain: imported in clusters, or imported without them
    /// (the file's triangle order, no copied vertices).
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut TerrainWorkspace,
        clustered: bool,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let mesh = if clustered {
            &self.clustered
        } else {
            &self.whole
        };
        let draws = [Draw::new(mesh).color(Rgb888::new(120, 200, 90))];
        let scene = Scene::new(Self::camera(), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("the terrain renders")
    }
}
