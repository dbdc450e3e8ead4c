//! [`FillScene`]: full-frame quads drawn back to front, every fragment
//! written.

use super::{
    facing_camera, fx, leak, ndc, ndc_camera, BenchRenderer, DemoWorkspace, HEIGHT, WIDTH,
};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;

/// `layers` full-frame quads (two triangles each), flat shaded, from the
/// back (z = 0.8) to the front (z = -0.8).
pub struct FillScene {
    mesh: Mesh<'static>,
    /// A 32x32 checker texture (`common::checker_texels`), repeated four
    /// times across each quad by the mesh's texture coordinates.
    pub texture: microraster::texture::Texture<'static>,
}

impl FillScene {
    /// Builds the quads.
    pub fn new(layers: usize) -> Self {
        let mut positions = Vec::new();
        let mut colors = Vec::new();
        let mut triangles = Vec::new();
        let mut uvs = Vec::new();
        for l in 0..layers {
            let z = 0.8 - 1.6 * l as f32 / (layers.max(2) - 1) as f32;
            let b = positions.len() as u16;
            let (w, h) = (WIDTH as f32, HEIGHT as f32);
            // Counter-clockwise in NDC (y up): the front face.
            positions.extend([
                ndc(0.0, h, z),
                ndc(w, h, z),
                ndc(w, 0.0, z),
                ndc(0.0, 0.0, z),
            ]);
            let c = Rgb888::new(
                (40 + (25 * l) % 200) as u8,
                (200 - (20 * l) % 160) as u8,
                90,
            );
            colors.extend([c; 4]);
            uvs.extend([
                [fx(0.0), fx(3.0)],
                [fx(4.0), fx(3.0)],
                [fx(4.0), fx(0.0)],
                [fx(0.0), fx(0.0)],
            ]);
            triangles.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
        }
        let mesh = Mesh::new(leak(positions), leak(triangles))
            .and_then(|m| m.with_colors(leak(colors)))
            .and_then(|m| m.with_uvs(leak(uvs)))
            .expect("fill quads are valid");
        Self {
            mesh,
            texture: super::checker_texture(),
        }
    }

    /// Renders the quads through fragment shader `shader` (every draw
    /// [`Shading::Shader`], sampling `texture`), with the depth test;
    /// through [`facing_camera`] if `facing`, else [`ndc_camera`] (whose
    /// constant `w` every perspective mode interpolates affinely).
    #[allow(clippy::too_many_arguments)]
    pub fn render_shader<S, F>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        shader: &F,
        texture: &microraster::texture::Texture<'_>,
        facing: bool,
        sink: &mut S,
    ) -> FrameStats
    where
        S: TileSink<Rgb565>,
        S::Error: core::fmt::Debug,
        F: FragmentShader<Rgb565>,
    {
        let draws = [Draw::new(&self.mesh)
            .shading(Shading::Shader)
            .texture(texture)];
        let camera = if facing {
            facing_camera()
        } else {
            ndc_camera()
        };
        let scene = Scene::new(camera, &draws).shader(shader);
        r.render(ws, &scene, sink).expect("fill frame renders")
    }

    /// Renders the quads with flat shading and the depth test.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = [Draw::new(&self.mesh).shading(Shading::Flat)];
        let scene = Scene::new(ndc_camera(), &draws);
        r.render(ws, &scene, sink).expect("fill frame renders")
    }
}
