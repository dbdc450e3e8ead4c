//! The demo scene, shared by the demo, the tests and the benchmarks: a lit
//! torus knot of 4,000 triangles next to a spinning cube.
#![allow(dead_code)]

use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shapes::{
    torus_knot, torus_knot_size, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
};

/// The demo's background.
pub const DEMO_CLEAR: embedded_graphics::pixelcolor::Rgb565 =
    embedded_graphics::pixelcolor::Rgb565::new(3, 6, 8);

/// Knot resolution: 200 x 10 = 2,000 vertices, 4,000 triangles.
pub const KNOT_SEGMENTS: usize = 200;
pub const KNOT_SIDES: usize = 10;
/// Vertices of the whole demo scene (knot + cube).
pub const SCENE_VERTICES: usize = KNOT_SEGMENTS * KNOT_SIDES + 24;

/// Generated mesh data of the demo.
pub struct DemoAssets {
    pub knot_positions: Vec<Vec3Fx>,
    pub knot_normals: Vec<Vec3Fx>,
    pub knot_triangles: Vec<[u16; 3]>,
}

impl DemoAssets {
    pub fn new() -> Self {
        let (nv, nt) = torus_knot_size(KNOT_SEGMENTS, KNOT_SIDES);
        let mut p = vec![[I16F16::ZERO; 3]; nv];
        let mut n = vec![[I16F16::ZERO; 3]; nv];
        let mut t = vec![[0u16; 3]; nt];
        torus_knot(
            2,
            3,
            1.0,
            0.28,
            KNOT_SEGMENTS,
            KNOT_SIDES,
            &mut p,
            &mut n,
            &mut t,
        )
        .expect("demo knot parameters are valid");
        Self {
            knot_positions: p,
            knot_normals: n,
            knot_triangles: t,
        }
    }

    pub fn knot(&self) -> Mesh<'_> {
        Mesh::new(&self.knot_positions, &self.knot_triangles)
            .and_then(|m| m.with_normals(&self.knot_normals))
            .expect("generated knot is valid")
    }
}

pub fn cube() -> Mesh<'static> {
    Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES)
        .and_then(|m| m.with_normals(&CUBE_NORMALS))
        .expect("cube is valid")
}

pub fn camera(width: u32, height: u32) -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 0.6, 4.2),
            Vec3::new(0.35, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(0.9, width as f32 / height as f32, 0.5, 20.0).unwrap(),
    )
}

pub fn light() -> Light {
    Light::new(Vec3::new(-0.6, 0.8, 0.9)).ambient(Rgb888::new(40, 40, 56))
}

/// The knot and the cube at animation time `t` (radians of knot spin).
pub fn draws<'a>(
    knot: &'a Mesh<'a>,
    cube: &'a Mesh<'a>,
    t: f32,
    shading: Shading,
) -> [Draw<'a>; 2] {
    [
        Draw::new(knot)
            .transform(
                Mat4::translation(Vec3::new(-0.3, 0.0, 0.0))
                    * Mat4::rotation_y(t)
                    * Mat4::rotation_x(0.4),
            )
            .color(Rgb888::new(230, 120, 40))
            .shading(shading),
        Draw::new(cube)
            .transform(
                Mat4::translation(Vec3::new(1.75, 0.1, -0.3))
                    * Mat4::rotation_y(-1.3 * t + 0.5)
                    * Mat4::rotation_x(0.6)
                    * Mat4::scale(Vec3::new(0.42, 0.42, 0.42)),
            )
            .color(Rgb888::new(70, 150, 230))
            .shading(shading),
    ]
}
