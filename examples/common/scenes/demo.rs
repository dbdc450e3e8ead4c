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

/// The demo frame textured and lit (`demo-textured-lit`): the knot and the
/// cube through `TexturedLit`, with the 32x32 checker texture (nearest,
/// exact perspective) times the Lambert-lit vertex colour of the demo's
/// light; the scene the firmware's `demo-textured-lit` renders too.
pub struct TexturedDemoScene {
    knot: Mesh<'static>,
    cube: Mesh<'static>,
    texture: Texture<'static>,
}

impl Default for TexturedDemoScene {
    fn default() -> Self {
        Self::new()
    }
}

impl TexturedDemoScene {
    /// Generates the knot and its texture coordinates, and the texture.
    pub fn new() -> Self {
        Self::with_knot(common::KNOT_SEGMENTS, common::KNOT_SIDES)
    }

    /// The same frame with a knot of `segments` x `sides` quads: 64 x 8
    /// gives `knot1k-textured-lit`, 1,024 triangles and the cube's 12, the
    /// size of textured model the issue about textured pixels measures
    /// (the demo's knot has 4,000).
    pub fn with_knot(segments: usize, sides: usize) -> Self {
        let assets: &'static common::DemoAssets =
            Box::leak(Box::new(common::DemoAssets::with_knot(segments, sides)));
        let (u, v) = common::KNOT_UV_REPEATS;
        let uvs: &'static [_] =
            Box::leak(common::knot_uvs_of((segments, sides), u, v).into_boxed_slice());
        Self {
            knot: assets
                .knot()
                .with_uvs(uvs)
                .expect("one coordinate per vertex"),
            cube: common::textured_cube(),
            texture: super::checker_texture(),
        }
    }

    /// Renders frame 0 (animation time 0).
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        use microraster::shader::TexturedLit;
        let draws = common::textured_draws(&self.knot, &self.cube, &self.texture, 0.0);
        let scene = Scene::new(common::camera(WIDTH, HEIGHT), &draws)
            .light(common::light())
            .shader(&TexturedLit);
        r.render(ws, &scene, sink)
            .expect("textured demo frame renders")
    }
}
