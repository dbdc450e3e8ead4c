//! [`Copies`]: many copies of one triangle of a given pixel area, and the
//! sizes the throughput benchmarks use.

use super::{leak, ndc, ndc_camera, BenchRenderer, CopiesWorkspace, HEIGHT, WIDTH};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;

/// `count` copies of one triangle of about `area` pixels, scattered over
/// the frame (an R2 low-discrepancy sequence of sub-pixel offsets), all at
/// the same depth, Gouraud shaded with three vertex colours.
pub struct Copies {
    mesh: Mesh<'static>,
}

impl Copies {
    /// Builds the copies; `3 * count` must fit the vertex buffer of
    /// [`CopiesWorkspace`].
    pub fn new(area: f32, count: usize) -> Self {
        // The shape (0, 0), (0.4 s, s), (s, 0.25 s) has area 0.45 s^2 and
        // is counter-clockwise in NDC (clockwise on the y-down screen).
        let s = (area / 0.45).sqrt();
        let (room_x, room_y) = (WIDTH as f32 - s - 1.0, HEIGHT as f32 - s - 1.0);
        let (mut positions, mut colors, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..count {
            let fx = (0.5 + k as f32 * 0.754_877_7).fract();
            let fy = (0.5 + k as f32 * 0.569_840_3).fract();
            let (x, y) = (0.5 + fx * room_x.max(0.0), 0.5 + fy * room_y.max(0.0));
            let b = positions.len() as u16;
            positions.extend([
                ndc(x, y, 0.0),
                ndc(x + 0.4 * s, y + s, 0.0),
                ndc(x + s, y + 0.25 * s, 0.0),
            ]);
            colors.extend([
                Rgb888::new(250, 40, 40),
                Rgb888::new(40, 250, 40),
                Rgb888::new(40, 40, 250),
            ]);
            triangles.push([b, b + 1, b + 2]);
        }
        let mesh = Mesh::new(leak(positions), leak(triangles))
            .and_then(|m| m.with_colors(leak(colors)))
            .expect("triangle copies are valid");
        Self { mesh }
    }

    /// Number of triangles.
    pub fn count(&self) -> usize {
        self.mesh.triangle_count()
    }

    /// Renders every copy (Gouraud, `LessEqual`: overlapping copies at the
    /// same depth are all drawn).
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut CopiesWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = [Draw::new(&self.mesh)];
        let scene = Scene::new(ndc_camera(), &draws);
        r.render(ws, &scene, sink).expect("triangle copies render")
    }
}

/// The triangle sizes of the throughput benchmarks: (name, target pixel
/// area, copies per frame).
pub const TRIANGLE_SIZES: [(&str, f32, usize); 5] = [
    ("4px", 4.0, 8_000),
    ("32px", 32.0, 4_000),
    ("100px", 100.0, 2_000),
    ("1000px", 1_000.0, 400),
    ("10000px", 10_000.0, 100),
];
