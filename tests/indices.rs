//! `u32` vertex indices: a mesh with `u32` triangles renders exactly like
//! the same mesh with `u16` ones, and a mesh of more than 65,536 vertices
//! draws the triangles that use the vertices beyond `u16`'s reach.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::{MeshError, Vec3Fx};
use microraster::prelude::*;
use support::Capture;

fn render<const V: usize>(scene: &Scene<'_>, size: Size) -> (Vec<Rgb565>, FrameStats) {
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::new(0, 0, 0)));
    let mut ws: Box<Workspace<V, 8192, 80>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, Rgb565::new(0, 0, 0));
    let s = r.render(&mut ws, scene, &mut cap).expect("renders");
    (cap.pixels, s)
}

#[test]
fn u32_indices_render_like_u16_ones() {
    let assets = DemoAssets::new();
    let knot16 = assets.knot();
    let tris32: Vec<[u32; 3]> = knot16.triangles().iter().collect();
    let knot32 = Mesh::new_u32(&assets.knot_positions, &tris32)
        .unwrap()
        .with_normals(&assets.knot_normals)
        .unwrap();
    let cube = cube();
    let size = Size::new(160, 120);
    let a = draws(&knot16, &cube, 0.9, Shading::Gouraud);
    let b = draws(&knot32, &cube, 0.9, Shading::Gouraud);
    let (pa, sa) = render::<2048>(&Scene::new(camera(160, 120), &a).light(light()), size);
    let (pb, sb) = render::<2048>(&Scene::new(camera(160, 120), &b).light(light()), size);
    assert!(sa.pixels_shaded > 1000);
    assert_eq!(sa, sb);
    assert!(pa == pb, "u32 indices changed the image");
}

#[test]
fn more_vertices_than_u16_reaches() {
    // A few megabytes of workspace: built on a thread with room for it.
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(|| {
            const N: usize = 70_000;
            let fx = |v: f32| I16F16::from_num(v);
            let p = |x: f32, y: f32| -> Vec3Fx { [fx(x), fx(y), fx(0.0)] };
            // Vertices 0..N - 3 are far away and unused; the last three
            // make a triangle in view, reached only through u32 indices.
            let mut positions = vec![p(50.0, 50.0); N];
            positions[N - 3] = p(-0.8, -0.8);
            positions[N - 2] = p(0.8, -0.8);
            positions[N - 1] = p(0.0, 0.8);
            let tris = [[(N - 3) as u32, (N - 2) as u32, (N - 1) as u32]];
            assert_eq!(
                Mesh::new(&positions, &[[0, 1, 2]]).unwrap_err(),
                MeshError::TooManyVertices { count: N }
            );
            let big = Mesh::new_u32(&positions, &tris).unwrap();
            let small_pos = [p(-0.8, -0.8), p(0.8, -0.8), p(0.0, 0.8)];
            let small = Mesh::new(&small_pos, &[[0, 1, 2]]).unwrap();
            let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
            let size = Size::new(64, 64);
            let color = Rgb888::new(200, 120, 40);
            let d_big = [Draw::new(&big).color(color)];
            let d_small = [Draw::new(&small).color(color)];
            let (pb, sb) = render::<N>(&Scene::new(cam, &d_big), size);
            let (ps, ss) = render::<N>(&Scene::new(cam, &d_small), size);
            assert!(sb.pixels_shaded > 500, "{sb:?}");
            assert_eq!(sb.pixels_shaded, ss.pixels_shaded);
            assert!(pb == ps);
            // An index past the end is an error, not a panic later.
            let bad = [[0u32, 1, N as u32]];
            assert_eq!(
                Mesh::new_u32(&positions, &bad).unwrap_err(),
                MeshError::IndexOutOfRange {
                    triangle: 0,
                    index: N as u32,
                    vertex_count: N
                }
            );
        })
        .unwrap()
        .join()
        .unwrap();
}
