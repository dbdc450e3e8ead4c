//! [`DemoScene`]: the demo frame, as the demo renders it.

use super::{BenchRenderer, DemoWorkspace, HEIGHT, WIDTH};
use crate::common;
use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;

/// The demo scene: the knot and the cube, generated and validated once.
pub struct DemoScene {
    knot: Mesh<'static>,
    cube: Mesh<'static>,
}

impl Default for DemoScene {
    fn default() -> Self {
        Self::new()
    }
}

impl DemoScene {
    /// Generates the knot.
    pub fn new() -> Self {
        let assets: &'static common::DemoAssets = Box::leak(Box::new(common::DemoAssets::new()));
        Self {
            knot: assets.knot(),
            cube: common::cube(),
        }
    }

    /// Renders demo frame 0 (animation time 0) with `shading`, exactly as
    /// `examples/demo.rs` builds it.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        shading: Shading,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = common::draws(&self.knot, &self.cube, 0.0, shading);
        let scene = Scene::new(common::camera(WIDTH, HEIGHT), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("demo frame renders")
    }

    /// The knot.
    pub fn knot(&self) -> &Mesh<'static> {
        &self.knot
    }

    /// The cube.
    pub fn cube(&self) -> &Mesh<'static> {
        &self.cube
    }
}
