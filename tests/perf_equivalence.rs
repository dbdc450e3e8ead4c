//! The optimised frame loop against itself in every configuration that
//! takes a different path: bin pools around the chunk size and far below
//! what a frame needs (passes that give up tiles, tiles drawn by
//! re-scanning), one tile per pass, small and odd tiles. Every picture and
//! every statistic but the pass counts must equal the single-pass render,
//! and every pixel must be written exactly once.
//!
//! The scenes are the demo (in three poses, so that the knot's triangles
//! fall differently on the tiles) and the demo with a floor through the near
//! plane and a wall beyond the guard band, so that clipped triangles go
//! through every path too.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;
use support::Capture;

type Picture = (Vec<Rgb565>, FrameStats);

fn render<const TW: usize, const TH: usize, const V: usize, const B: usize, const T: usize>(
    scene: &Scene<'_>,
    size: Size,
    cull: CullMode,
) -> Picture {
    let mut r: Renderer<Rgb565, TW, TH> =
        Renderer::new(Config::new(size, common::DEMO_CLEAR).cull(cull));
    let mut ws: Box<Workspace<V, B, T>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
    let stats = r.render(&mut ws, scene, &mut cap).unwrap();
    assert!(
        cap.writes.iter().all(|&n| n == 1),
        "{TW}x{TH}, Workspace<{V}, {B}, {T}>: a pixel not written exactly once"
    );
    (cap.pixels, stats)
}

/// Same pixels and statistics (but the pass counts and, across tile
/// shapes, the tile count).
fn assert_same(name: &str, img: &Picture, reference: &Picture) {
    support::assert_same_frame(name, img, reference, false);
}

/// Renders `scene` with 32x32 tiles and every pool in `pools`, and with a
/// few other tile shapes, against one big single-pass render.
fn check(what: &str, scene: &Scene<'_>, size: Size, cull: CullMode) {
    let reference = render::<32, 32, 2100, 16384, 64>(scene, size, cull);
    assert_eq!(reference.1.bin_passes, 1, "{what}: {:?}", reference.1);
    assert!(
        reference.1.pixels_shaded > 1000,
        "{what}: {:?}",
        reference.1
    );
    macro_rules! pools {
        ($($b:literal),*) => {$(
            let p = render::<32, 32, 2100, $b, 64>(scene, size, cull);
            assert_eq!(p.1.tiles, reference.1.tiles, "{what}, {} entries", $b);
            assert_same(&format!("{what}, {} entries", $b), &p, &reference);
            let p = render::<32, 32, 2100, $b, 3>(scene, size, cull);
            assert_same(&format!("{what}, {} entries, 3 tiles a pass", $b), &p, &reference);
        )*};
    }
    // Below one chunk, one chunk and a slot either side, a few chunks,
    // and a pool a little short of the frame's needs.
    pools!(1, 6, 7, 8, 9, 15, 16, 17, 64, 250, 1000);
    let small = render::<32, 32, 2100, 1000, 64>(scene, size, cull);
    assert!(small.1.bin_passes > 1, "{what}: {:?}", small.1);
    let one = render::<32, 32, 2100, 16384, 1>(scene, size, cull);
    assert_same(&format!("{what}, one tile a pass"), &one, &reference);
    let odd = render::<13, 7, 2100, 700, 50>(scene, size, cull);
    assert_same(&format!("{what}, 13x7 tiles"), &odd, &reference);
    let wide = render::<64, 16, 2100, 16384, 64>(scene, size, cull);
    assert_same(&format!("{what}, 64x16 tiles"), &wide, &reference);
}

#[test]
fn demo_renders_the_same_with_every_pool_and_tile() {
    let assets = common::DemoAssets::new();
    let (knot, cube) = (assets.knot(), common::cube());
    let size = Size::new(150, 110);
    for t in [0.0, 1.3, 2.9] {
        let d = common::draws(&knot, &cube, t, Shading::Gouraud);
        let scene = Scene::new(common::camera(size.width, size.height), &d).light(common::light());
        check(&format!("demo at {t}"), &scene, size, CullMode::Back);
    }
}

#[test]
fn clipped_scene_renders_the_same_with_every_pool_and_tile() {
    common::with_clipped_scene(|scene, size| {
        let reference = render::<32, 32, 2100, 16384, 64>(scene, size, CullMode::None);
        assert!(reference.1.clipped >= 3, "{:?}", reference.1);
        check("clipped scene", scene, size, CullMode::None);
    });
}
