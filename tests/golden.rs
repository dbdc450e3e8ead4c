//! Golden images: several scenes in every supported colour format, compared
//! pixel-exactly with PNGs in `tests/golden/`. `BLESS=1 cargo test --test
//! golden` regenerates them (look at them before committing); a mismatch
//! writes the actual image and a diff to `target/golden-diff/`.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{BinaryColor, Gray4, Gray8, Rgb565, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use support::{check_golden, Capture};

const W: u32 = 160;
const H: u32 = 120;

/// Renders with the scanline rasterizer in row-major tile order, checks
/// that every other rasterizer and tile order gives the same pixels, and
/// returns the first image.
fn render<C>(scene: &Scene<'_>, size: Size, clear: C, cull: CullMode) -> Capture<C>
where
    C: embedded_graphics::pixelcolor::PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
{
    let config = Config::new(size, clear).cull(cull);
    let reference = render_with(scene, config);
    for (raster, order) in [
        (Rasterizer::Hilbert, TileOrder::RowMajor),
        (Rasterizer::Auto, TileOrder::RowMajor),
        (Rasterizer::Scanline, TileOrder::Hilbert),
        (Rasterizer::Hilbert, TileOrder::Hilbert),
    ] {
        let other = render_with(scene, config.rasterizer(raster).tile_order(order));
        assert!(
            other.pixels == reference.pixels,
            "{raster:?} with {order:?} tiles differs from the scanline rasterizer"
        );
    }
    reference
}

fn render_with<C>(scene: &Scene<'_>, config: Config<C>) -> Capture<C>
where
    C: embedded_graphics::pixelcolor::PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
{
    let (size, clear) = (config.size, config.clear_color);
    let mut r: Renderer<C, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, 4096, 80>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, clear);
    let stats = r.render(&mut ws, scene, &mut cap).expect("scene renders");
    assert_eq!(
        stats.tiles,
        size.width.div_ceil(32) * size.height.div_ceil(32)
    );
    assert!(
        cap.writes.iter().all(|&w| w == 1),
        "every pixel is sent exactly once"
    );
    assert_eq!(cap.fills, stats.tiles, "one fill_contiguous per tile");
    cap
}

fn golden<C>(name: &str, scene: &Scene<'_>, size: Size, clear: C, cull: CullMode)
where
    C: embedded_graphics::pixelcolor::PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
{
    let cap = render(scene, size, clear, cull);
    check_golden(name, size, &cap.to_rgb());
}

fn knot_scene<'a>(knot: &'a Mesh<'a>, cube: &'a Mesh<'a>, shading: Shading) -> [Draw<'a>; 2] {
    draws(knot, cube, 0.7, shading)
}

#[test]
fn knot_in_every_colour_format() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = knot_scene(&knot, &cube, Shading::Gouraud);
    let scene = Scene::new(camera(W, H), &d).light(light());
    let size = Size::new(W, H);
    golden(
        "knot_rgb565",
        &scene,
        size,
        Rgb565::new(3, 6, 8),
        CullMode::Back,
    );
    golden(
        "knot_rgb888",
        &scene,
        size,
        Rgb888::new(24, 24, 64),
        CullMode::Back,
    );
    golden("knot_gray8", &scene, size, Gray8::new(20), CullMode::Back);
    golden("knot_gray4", &scene, size, Gray4::new(1), CullMode::Back);
    // One bit per pixel thresholds luma at 50 %: white meshes, so lit
    // surfaces read white and those turned away from the light black.
    let white = d.map(|x| x.color(Rgb888::WHITE));
    let scene = Scene::new(camera(W, H), &white).light(light());
    golden(
        "knot_binary",
        &scene,
        size,
        BinaryColor::Off,
        CullMode::Back,
    );
}

/// The demo's first frame at full size. The README shows the same frame,
/// written by the demo itself (`docs/frame_000.png`); it must match too.
#[test]
fn demo_frame_full_size() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.0, Shading::Gouraud);
    let scene = Scene::new(camera(320, 240), &d).light(light());
    let size = Size::new(320, 240);
    let cap = render(&scene, size, DEMO_CLEAR, CullMode::Back);
    check_golden("demo_320x240_rgb565", size, &cap.to_rgb());
    let readme = support::read_png(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/frame_000.png"),
    )
    .expect(
        "docs/frame_000.png exists: cargo run --release --example demo -- --frames 1 --out-dir docs",
    );
    assert_eq!(readme.0, size);
    assert!(
        readme.1 == cap.to_rgb(),
        "docs/frame_000.png is stale: regenerate it with the demo"
    );
}

#[test]
fn flat_shading() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = knot_scene(&knot, &cube, Shading::Flat);
    let scene = Scene::new(camera(W, H), &d).light(light());
    golden(
        "knot_flat_rgb565",
        &scene,
        Size::new(W, H),
        Rgb565::new(3, 6, 8),
        CullMode::Back,
    );
}

/// A checkerboard floor of separate quads, `n x n`, spanning `[-s, s]` in
/// x and z at height `y`.
struct Floor {
    positions: Vec<Vec3Fx>,
    colors: Vec<Rgb888>,
    triangles: Vec<[u16; 3]>,
}

fn floor(n: usize, s: f32, y: f32) -> Floor {
    let mut f = Floor {
        positions: vec![],
        colors: vec![],
        triangles: vec![],
    };
    let fx = |v: f32| I16F16::from_num(v);
    let step = 2.0 * s / n as f32;
    for i in 0..n {
        for j in 0..n {
            let (x0, z0) = (-s + i as f32 * step, -s + j as f32 * step);
            let b = f.positions.len() as u16;
            for (dx, dz) in [(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)] {
                f.positions
                    .push([fx(x0 + dx * step), fx(y), fx(z0 + dz * step)]);
                let c = if (i + j) % 2 == 0 {
                    Rgb888::new(230, 230, 220)
                } else {
                    Rgb888::new(40, 90, 160)
                };
                f.colors.push(c);
            }
            // Counter-clockwise seen from above (+y).
            f.triangles.push([b, b + 1, b + 2]);
            f.triangles.push([b, b + 2, b + 3]);
        }
    }
    f
}

/// A floor that runs under the camera and through the near plane, with the
/// cube standing on it: exercises near clipping and the guard band.
#[test]
fn floor_through_near_plane() {
    let fl = floor(16, 12.0, -1.0);
    let floor_mesh = Mesh::new(&fl.positions, &fl.triangles)
        .and_then(|m| m.with_colors(&fl.colors))
        .unwrap();
    let cube = cube();
    let d = [
        Draw::new(&floor_mesh),
        Draw::new(&cube)
            .transform(
                Mat4::translation(Vec3::new(0.0, -0.4, -1.0))
                    * Mat4::rotation_y(0.6)
                    * Mat4::scale(Vec3::new(0.6, 0.6, 0.6)),
            )
            .color(Rgb888::new(220, 80, 60)),
    ];
    let cam = Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 0.2, 2.0),
            Vec3::new(0.0, -0.6, -2.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(1.2, W as f32 / H as f32, 0.3, 30.0).unwrap(),
    );
    let scene = Scene::new(cam, &d).light(light());
    let cap = render(
        &scene,
        Size::new(W, H),
        Rgb565::new(10, 20, 28),
        CullMode::Back,
    );
    // The floor's quads reach behind the eye, so some must have been clipped.
    let mut r: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(Size::new(W, H), Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 4096, 80>> = Box::new(Workspace::new());
    let stats = r
        .render(&mut ws, &scene, &mut microraster::NullSink)
        .unwrap();
    assert!(stats.clipped > 0, "{stats:?}");
    check_golden("floor_near_clip_rgb565", Size::new(W, H), &cap.to_rgb());
    golden(
        "floor_near_clip_gray4",
        &scene,
        Size::new(W, H),
        Gray4::new(2),
        CullMode::Back,
    );
}

/// Two interpenetrating quads under an orthographic camera: the depth test
/// must split them along their intersection line.
#[test]
fn interpenetrating_quads_orthographic() {
    let fx = |v: f32| I16F16::from_num(v);
    let positions = [
        // Quad A: tilted in depth along x.
        [fx(-0.8), fx(-0.6), fx(-0.5)],
        [fx(0.8), fx(-0.6), fx(0.5)],
        [fx(0.8), fx(0.6), fx(0.5)],
        [fx(-0.8), fx(0.6), fx(-0.5)],
        // Quad B: tilted the other way.
        [fx(-0.6), fx(-0.8), fx(0.5)],
        [fx(0.6), fx(-0.8), fx(-0.5)],
        [fx(0.6), fx(0.8), fx(-0.5)],
        [fx(-0.6), fx(0.8), fx(0.5)],
    ];
    let colors = [
        Rgb888::new(255, 60, 60),
        Rgb888::new(255, 200, 60),
        Rgb888::new(255, 60, 200),
        Rgb888::new(200, 60, 60),
        Rgb888::new(60, 255, 90),
        Rgb888::new(60, 120, 255),
        Rgb888::new(60, 255, 255),
        Rgb888::new(30, 160, 90),
    ];
    let tris = [[0u16, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let mesh = Mesh::new(&positions, &tris)
        .and_then(|m| m.with_colors(&colors))
        .unwrap();
    let d = [Draw::new(&mesh)];
    let cam = Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::orthographic(-1.2, 1.2, -0.9, 0.9, 1.0, 5.0).unwrap(),
    );
    let scene = Scene::new(cam, &d);
    golden(
        "quads_ortho_rgb888",
        &scene,
        Size::new(W, H),
        Rgb888::BLACK,
        CullMode::None,
    );
    golden(
        "quads_ortho_binary",
        &scene,
        Size::new(W, H),
        BinaryColor::Off,
        CullMode::None,
    );
}
