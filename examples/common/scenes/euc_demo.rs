//! [`EucDemo`]: the demo frame rendered by the `euc` crate, for
//! comparison.

use super::{DemoScene, HEIGHT, WIDTH};
use crate::common;
use embedded_graphics::pixelcolor::RgbColor;
use embedded_graphics::prelude::IntoStorage;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;

/// The demo frame rendered by [`euc`] 0.5: the same meshes, transforms,
/// camera, light and size; per-vertex (Lambert) colour interpolated over
/// the triangle, an `f32` depth buffer with a less-or-equal test, back
/// faces culled, `Rgb565` output into a full frame buffer.
///
/// euc has no index buffer with a vertex cache: its vertex shader runs for
/// each corner of each triangle. So that both renderers light and transform
/// each vertex once, a per-frame pass (part of the measured frame) computes
/// every vertex's clip position and colour in `f32`, and euc's vertex
/// shader only looks them up.
pub struct EucDemo {
    /// Model-space positions and normals of the knot then the cube.
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    /// Vertex count of the knot (the cube's vertices follow).
    knot_vertices: usize,
    /// Triangle corners, the cube's indices offset past the knot's.
    indices: Vec<u32>,
    /// Per frame: clip-space positions and colours (0..=255).
    clip: Vec<[f32; 4]>,
    rgb: Vec<(f32, f32, f32)>,
    /// The frame.
    pub color: euc::buffer::Buffer2d<u16>,
    /// The demo's clear colour as raw `Rgb565` bits.
    clear: u16,
    depth: euc::buffer::Buffer2d<f32>,
    demo: DemoScene,
}

struct EucPipe<'a> {
    clip: &'a [[f32; 4]],
    rgb: &'a [(f32, f32, f32)],
}

impl euc::Pipeline for EucPipe<'_> {
    type Vertex = u32;
    type VsOut = (f32, f32, f32);
    type Pixel = u16;

    #[inline(always)]
    fn vert(&self, i: &u32) -> ([f32; 4], Self::VsOut) {
        (self.clip[*i as usize], self.rgb[*i as usize])
    }

    #[inline(always)]
    fn frag(&self, c: &Self::VsOut) -> u16 {
        let (r, g, b) = (c.0 as u16, c.1 as u16, c.2 as u16);
        ((r >> 3) << 11) | ((g >> 2) << 5) | (b >> 3)
    }
}

impl Default for EucDemo {
    fn default() -> Self {
        Self::new()
    }
}

impl EucDemo {
    /// Converts the demo meshes to `f32` and allocates the frame.
    pub fn new() -> Self {
        let demo = DemoScene::new();
        let f = |v: &Vec3Fx| [v[0].to_num(), v[1].to_num(), v[2].to_num()];
        let (knot, cube) = (demo.knot(), demo.cube());
        let mut positions: Vec<[f32; 3]> = knot.positions().iter().map(f).collect();
        let mut normals: Vec<[f32; 3]> = knot.normals().unwrap().iter().map(f).collect();
        let knot_vertices = positions.len();
        positions.extend(cube.positions().iter().map(f));
        normals.extend(cube.normals().unwrap().iter().map(f));
        let mut indices = Vec::new();
        for t in knot.triangles().iter() {
            indices.extend(t);
        }
        for t in cube.triangles().iter() {
            indices.extend(t.map(|i| i + knot_vertices as u32));
        }
        let n = positions.len();
        let clear = common::DEMO_CLEAR.into_storage();
        Self {
            positions,
            normals,
            knot_vertices,
            indices,
            clip: vec![[0.0; 4]; n],
            rgb: vec![(0.0, 0.0, 0.0); n],
            color: euc::buffer::Buffer2d::new([WIDTH as usize, HEIGHT as usize], clear),
            clear,
            depth: euc::buffer::Buffer2d::new([WIDTH as usize, HEIGHT as usize], 1.0),
            demo,
        }
    }

    /// Renders demo frame 0: vertex pass, clear, draw.
    pub fn render(&mut self) {
        use euc::{Pipeline, Target};
        let draws = common::draws(self.demo.knot(), self.demo.cube(), 0.0, Shading::Gouraud);
        let camera = common::camera(WIDTH, HEIGHT);
        let light = common::light();
        let view_proj = camera.projection * camera.view;
        let ldir = light.direction.normalize().expect("demo light is valid");
        let ranges = [
            (0, self.knot_vertices),
            (self.knot_vertices, self.positions.len()),
        ];
        for (draw, (from, to)) in draws.iter().zip(ranges) {
            let m = (view_proj * draw.transform).m;
            let base = [draw.color.r(), draw.color.g(), draw.color.b()].map(|c| c as f32);
            for i in from..to {
                let p = self.positions[i];
                let mut c = [0.0f32; 4];
                for (r, out) in c.iter_mut().enumerate() {
                    *out = m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r];
                }
                self.clip[i] = c;
                let n = self.normals[i];
                let wn = draw.transform.transform_vector(Vec3::new(n[0], n[1], n[2]));
                let ndotl = (wn.dot(ldir) / wn.length()).max(0.0);
                let lit = |k: usize, amb: u8, lc: u8| {
                    (base[k] * (amb as f32 + lc as f32 * ndotl) / 255.0).min(255.0)
                };
                self.rgb[i] = (
                    lit(0, light.ambient.r(), light.color.r()),
                    lit(1, light.ambient.g(), light.color.g()),
                    lit(2, light.ambient.b(), light.color.b()),
                );
            }
        }
        self.color.clear(self.clear);
        self.depth.clear(1.0);
        EucPipe {
            clip: &self.clip,
            rgb: &self.rgb,
        }
        .draw::<euc::rasterizer::Triangles<'_, _, euc::rasterizer::BackfaceCullingEnabled>, _>(
            &self.indices,
            &mut self.color,
            Some(&mut self.depth),
        );
    }

    /// Pixels of the frame that are not the clear colour.
    pub fn covered(&self) -> usize {
        self.color
            .as_ref()
            .iter()
            .filter(|&&p| p != self.clear)
            .count()
    }
}
