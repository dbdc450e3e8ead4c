//! Sizing a workspace from what a frame reports: the vertex slots, the
//! (triangle, tile) pairs, the bin entries and tiles one pass took.

#[path = "../examples/common/mod.rs"]
mod common;

use common::*;
use embedded_graphics::pixelcolor::{BinaryColor, Rgb565};
use fixed::types::I16F16;
use microraster::prelude::*;
use microraster::render::CHUNK;

fn quad() -> ([[I16F16; 3]; 4], [[u16; 3]; 2]) {
    let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
    // Nearly the whole 64x64 frame: both triangles touch all four tiles.
    let positions = [p(-0.9, -0.9), p(0.9, -0.9), p(0.9, 0.9), p(-0.9, 0.9)];
    (positions, [[0, 1, 2], [0, 2, 3]])
}

fn render<const B: usize, const T: usize>(mesh: &Mesh<'_>) -> FrameStats {
    let draws = [Draw::new(mesh)];
    let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    let mut r: Renderer<BinaryColor, 32, 32> =
        Renderer::new(Config::new(Size::new(64, 64), BinaryColor::Off).cull(CullMode::None));
    let mut ws: Workspace<4, B, T> = Workspace::new();
    r.render(&mut ws, &scene, &mut NullSink).unwrap()
}

#[test]
fn one_pass_needs_the_peak_it_reports() {
    let (positions, triangles) = quad();
    let mesh = Mesh::new(&positions, &triangles).unwrap();
    // Two triangles in each of four tiles: 8 pairs, one chunk per tile.
    let s = render::<64, 4>(&mesh);
    assert_eq!((s.vertex_slots, s.tile_pairs), (4, 8));
    assert_eq!((s.bin_passes, s.peak_tiles_per_pass), (1, 4));
    assert_eq!(s.peak_bin_entries, 4 * CHUNK as u32);
    // Exactly that pool still takes one pass; a chunk less takes more.
    let s = render::<{ 4 * CHUNK }, 4>(&mesh);
    assert_eq!(s.bin_passes, 1);
    let s = render::<{ 3 * CHUNK }, 4>(&mesh);
    assert_eq!((s.bin_passes, s.peak_tiles_per_pass), (2, 3));
    assert_eq!(s.peak_bin_entries, 3 * CHUNK as u32);
    // Fewer tiles per pass: the peak says so.
    let s = render::<64, 2>(&mesh);
    assert_eq!((s.bin_passes, s.peak_tiles_per_pass), (2, 2));
}

#[test]
fn the_demo_reports_what_it_used() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.0, Shading::Gouraud);
    let scene = Scene::new(camera(320, 240), &d).light(light());
    let mut r: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(Size::new(320, 240), Rgb565::new(0, 0, 0)));
    let mut ws: Box<Workspace<2048, 8192, 80>> = Box::new(Workspace::new());
    let s = r.render(&mut ws, &scene, &mut NullSink).unwrap();
    let slots = (knot.vertex_count() + cube.vertex_count()) as u32;
    assert_eq!(s.vertex_slots, slots);
    assert_eq!((s.bin_passes, s.peak_tiles_per_pass), (1, 80));
    // Every drawn triangle is in at least one tile; every pair needs a
    // slot, and chunks add their links and unused slots.
    assert!(s.tile_pairs >= s.drawn, "{s}");
    assert!(s.peak_bin_entries >= s.tile_pairs * CHUNK as u32 / (CHUNK as u32 - 1));
    assert_eq!(s.peak_bin_entries % CHUNK as u32, 0);
    // The reported peak is enough for one pass (rounded to chunks the
    // workspace's 4,096 is), and the Display names the fields.
    assert!(
        s.peak_bin_entries <= 4096,
        "the budget workspace holds it: {s}"
    );
    assert!(s
        .to_string()
        .contains(&format!("peak_bin_entries={}", s.peak_bin_entries)));
}
