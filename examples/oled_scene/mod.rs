//! The scene the LM3S6965EVB firmware draws on its 128x64 4-bit OLED, shared
//! (no_std, no alloc) by the firmware and by the host test that checks the
//! emulated board's screen pixel for pixel.
#![allow(dead_code)]

use embedded_graphics::pixelcolor::{Gray4, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::render::GouraudTriangles;
use microraster::shapes::{torus_knot, torus_knot_size};

/// Panel size.
pub const WIDTH: u32 = 128;
/// Panel size.
pub const HEIGHT: u32 = 64;

/// Knot resolution: 64 x 8 = 512 vertices, 1,024 triangles.
pub const SEGMENTS: usize = 64;
/// Knot resolution.
pub const SIDES: usize = 8;
/// Vertices of the knot.
pub const VERTICES: usize = torus_knot_size(SEGMENTS, SIDES).0;
/// Triangles of the knot.
pub const TRIANGLES: usize = torus_knot_size(SEGMENTS, SIDES).1;

/// 32x32 tiles: the panel is 4 x 2 tiles, and every tile starts on an even
/// column as the SSD0323's two-pixels-per-byte columns need. The firmware
/// draws Gouraud triangles only, and links nothing else
/// ([`GouraudTriangles`]).
pub type OledRenderer = Renderer<Gray4, 32, 32, GouraudTriangles>;
/// Room for the knot and all 8 tiles in one binning pass.
pub type OledWorkspace = Workspace<VERTICES, 1536, 8>;

/// The knot's mesh data, generated at start-up into caller memory.
pub struct KnotData {
    pub positions: [Vec3Fx; VERTICES],
    pub normals: [Vec3Fx; VERTICES],
    pub triangles: [[u16; 3]; TRIANGLES],
}

impl KnotData {
    /// Zeroed storage (usable in a `static`).
    pub const fn new() -> Self {
        Self {
            positions: [[I16F16::ZERO; 3]; VERTICES],
            normals: [[I16F16::ZERO; 3]; VERTICES],
            triangles: [[0; 3]; TRIANGLES],
        }
    }

    /// Generates the knot; the same bits on every target.
    pub fn generate(&mut self) {
        let r = torus_knot(
            2,
            3,
            1.0,
            0.3,
            SEGMENTS,
            SIDES,
            &mut self.positions,
            &mut self.normals,
            &mut self.triangles,
        );
        assert!(r.is_ok(), "the knot's parameters are valid");
    }

    /// The mesh.
    pub fn mesh(&self) -> Mesh<'_> {
        match Mesh::new(&self.positions, &self.triangles)
            .and_then(|m| m.with_normals(&self.normals))
        {
            Ok(m) => m,
            Err(_) => panic!("the generated knot is a valid mesh"),
        }
    }
}

/// Background grey.
pub const CLEAR: Gray4 = Gray4::new(1);

/// The knot at animation frame `frame`.
pub fn draw<'a>(knot: &'a Mesh<'a>, frame: u32) -> Draw<'a> {
    let t = frame as f32 * 0.12;
    Draw::new(knot)
        .transform(Mat4::rotation_y(t) * Mat4::rotation_x(0.5 + 0.3 * t))
        .color(Rgb888::new(255, 255, 255))
}

/// The camera: the knot fills the panel's height.
pub fn camera() -> Camera {
    let view = Mat4::look_at(
        Vec3::new(0.0, 0.0, 3.2),
        Vec3::default(),
        Vec3::new(0.0, 1.0, 0.0),
    );
    let proj = Mat4::perspective(0.75, WIDTH as f32 / HEIGHT as f32, 0.5, 10.0);
    match (view, proj) {
        (Some(v), Some(p)) => Camera::new(v, p),
        _ => panic!("the camera parameters are valid"),
    }
}

/// One white light from the upper left, with a dim ambient term.
pub fn light() -> Light {
    Light::new(Vec3::new(-0.5, 0.7, 1.0)).ambient(Rgb888::new(36, 36, 36))
}

/// The renderer's settings.
pub fn config() -> Config<Gray4> {
    Config::new(Size::new(WIDTH, HEIGHT), CLEAR)
}

/// The imported model (feature `assets`): `examples/assets/rocket.obj`,
/// converted into `static` arrays in flash by `build.rs` at build time
/// (recentred and scaled to the unit sphere, normals computed), drawn one
/// group per draw in its material's colour.
#[cfg(feature = "assets")]
pub mod rocket {
    use super::*;

    include!(concat!(env!("OUT_DIR"), "/rocket.rs"));

    /// The model's groups (body, nose, nozzle, fins): one draw each.
    pub const GROUPS: usize = ROCKET_GROUPS.len();
    /// Vertices the draws transform: every group's mesh shares all of the
    /// model's vertices.
    pub const DRAW_VERTICES: usize = ROCKET_POSITIONS.len() * GROUPS;
    const _: () = assert!(
        DRAW_VERTICES <= VERTICES,
        "the OLED workspace holds the rocket"
    );

    /// One mesh per group, over the shared vertex arrays.
    pub fn meshes() -> [Mesh<'static>; GROUPS] {
        core::array::from_fn(|g| {
            let (_, first, count) = ROCKET_GROUPS[g];
            match Mesh::new(&ROCKET_POSITIONS, &ROCKET_TRIANGLES[first..first + count])
                .and_then(|m| m.with_normals(&ROCKET_NORMALS))
            {
                Ok(m) => m,
                Err(_) => panic!("the imported rocket is a valid mesh"),
            }
        })
    }

    /// The rocket at animation frame `frame`: lying across the panel,
    /// spinning about its own axis.
    pub fn draws<'a>(meshes: &'a [Mesh<'a>; GROUPS], frame: u32) -> [Draw<'a>; GROUPS] {
        let t = frame as f32 * 0.15;
        let m = Mat4::rotation_z(-1.2) * Mat4::rotation_x(0.3) * Mat4::rotation_y(t);
        core::array::from_fn(|g| {
            Draw::new(&meshes[g])
                .transform(m)
                .color(ROCKET_GROUP_COLORS[g])
        })
    }

    /// The camera: close enough that the rocket, lying across the panel,
    /// spans most of its width.
    pub fn camera() -> Camera {
        let view = Mat4::look_at(
            Vec3::new(0.0, 0.0, 1.45),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let proj = Mat4::perspective(0.8, WIDTH as f32 / HEIGHT as f32, 0.3, 10.0);
        match (view, proj) {
            (Some(v), Some(p)) => Camera::new(v, p),
            _ => panic!("the camera parameters are valid"),
        }
    }
}
