//! Tile invariance: the same scene rendered with different tile sizes, frame
//! sizes that are not multiples of the tile, and different workspace
//! capacities gives identical images.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;
use support::Capture;

fn render<const TW: usize, const TH: usize>(
    scene: &Scene<'_>,
    size: Size,
) -> (Vec<Rgb565>, FrameStats) {
    render_with::<TW, TH>(scene, size, Rasterizer::Scanline)
}

fn render_with<const TW: usize, const TH: usize>(
    scene: &Scene<'_>,
    size: Size,
    raster: Rasterizer,
) -> (Vec<Rgb565>, FrameStats) {
    let mut r: Renderer<Rgb565, TW, TH> =
        Renderer::new(Config::new(size, Rgb565::new(1, 2, 3)).rasterizer(raster));
    let mut ws: Box<Workspace<2048, 8192, 256>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
    let stats = r.render(&mut ws, scene, &mut cap).unwrap();
    assert!(
        cap.writes.iter().all(|&w| w == 1),
        "{TW}x{TH}: every pixel sent once"
    );
    assert_eq!(
        stats.tiles,
        size.width.div_ceil(TW as u32) * size.height.div_ceil(TH as u32)
    );
    (cap.pixels, stats)
}

fn check_all_tile_sizes(scene: &Scene<'_>, size: Size) {
    let (reference, stats) = render::<32, 32>(scene, size);
    assert!(
        stats.pixels_shaded > 1000,
        "the scene draws something: {stats:?}"
    );
    let others = [
        ("16x16", render::<16, 16>(scene, size)),
        ("64x32", render::<64, 32>(scene, size)),
        ("8x8", render::<8, 8>(scene, size)),
        ("24x20", render::<24, 20>(scene, size)),
        ("64x64", render::<64, 64>(scene, size)),
        ("13x7", render::<13, 7>(scene, size)),
        // One tile the size of the frame (larger than the 317x233 one):
        // a frame buffer, for boards whose RAM holds one.
        ("320x240", render::<320, 240>(scene, size)),
        // The frame-sized tile through the other rasterizers, whose
        // coverage is the scanline rasterizer's at any tile.
        (
            "320x240 Hilbert",
            render_with::<320, 240>(scene, size, Rasterizer::Hilbert),
        ),
        (
            "320x240 Auto",
            render_with::<320, 240>(scene, size, Rasterizer::Auto),
        ),
    ];
    for (name, (img, s)) in others {
        let diff = img.iter().zip(&reference).filter(|(a, b)| a != b).count();
        assert_eq!(
            diff, 0,
            "{name} tiles differ from 32x32 in {diff} pixels at {size:?}"
        );
        // Triangle classification does not depend on tiles either.
        assert_eq!(
            (s.culled, s.rejected, s.clipped, s.drawn),
            (stats.culled, stats.rejected, stats.clipped, stats.drawn)
        );
    }
}

#[test]
fn demo_scene_is_tile_invariant() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    for (size, t) in [(Size::new(320, 240), 0.3), (Size::new(317, 233), 1.9)] {
        let d = draws(&knot, &cube, t, Shading::Gouraud);
        let scene = Scene::new(camera(size.width, size.height), &d).light(light());
        check_all_tile_sizes(&scene, size);
    }
}

#[test]
fn clipped_scene_is_tile_invariant() {
    // The cube close enough to cross the near plane and far enough sideways
    // to leave the guard band.
    let cube = cube();
    let d = [
        Draw::new(&cube)
            .transform(Mat4::translation(Vec3::new(0.0, 0.0, 3.4)) * Mat4::rotation_y(0.5))
            .color(Rgb888::new(200, 160, 90)),
        Draw::new(&cube)
            .transform(
                Mat4::translation(Vec3::new(30.0, 0.0, -3.0))
                    * Mat4::scale(Vec3::new(28.0, 1.0, 1.0)),
            )
            .color(Rgb888::new(90, 160, 200)),
    ];
    let size = Size::new(203, 151);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    let (_, stats) = render::<32, 32>(&scene, size);
    assert!(stats.clipped >= 2, "{stats:?}");
    check_all_tile_sizes(&scene, size);
}
