//! The demo scene, shared by the demo, the tests and the benchmarks: a lit
//! torus knot of 4,000 triangles next to a spinning cube.
#![allow(dead_code)]

use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shapes::{
    torus_knot, torus_knot_size, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
};

#[path = "../demo_scene/mod.rs"]
mod demo_scene;
// Each example or test that includes this file uses a different subset.
#[allow(unused_imports)]
pub use demo_scene::{
    draws, light, DEMO_CLEAR, KNOT_P, KNOT_Q, KNOT_RADIUS, KNOT_SEGMENTS, KNOT_SIDES, KNOT_TUBE,
};

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
            KNOT_P,
            KNOT_Q,
            KNOT_RADIUS,
            KNOT_TUBE,
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

/// The demo camera for a `width` x `height` frame.
pub fn camera(width: u32, height: u32) -> Camera {
    demo_scene::camera(width, height).expect("the demo camera is valid for a non-empty frame")
}
