//! Tiles on demand: a frame begun with `Renderer::begin` and drawn tile by
//! tile into the caller's buffers gives the same tiles, in the same order,
//! with the same statistics, as `Renderer::render`, whatever the passes.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;
use microraster::TileBuffer;
use support::Order;

/// The scene rendered both ways with a workspace of `B` bin entries and
/// `T` tiles per pass; returns the statistics after checking that they,
/// the tiles' order and every pixel agree.
fn both_ways<const B: usize, const T: usize>(
    scene: &Scene<'_>,
    config: Config<Rgb565>,
) -> FrameStats {
    let size = config.size;
    let mut renderer: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, B, T>> = Box::new(Workspace::new());
    let mut reference = Order::new(size, Rgb565::new(31, 0, 31));
    let expected = renderer.render(&mut ws, scene, &mut reference).unwrap();

    // Two buffers in turn, as a caller with one tile on the wire would.
    let mut tiles = [
        TileBuffer::new(Rgb565::new(0, 63, 0)),
        TileBuffer::new(Rgb565::new(0, 0, 31)),
    ];
    let mut got = Order::new(size, Rgb565::new(31, 0, 31));
    let mut frame = renderer.begin(&mut ws, scene).unwrap();
    assert_eq!(frame.tile_count(), reference.0.len());
    let mut k = 0;
    while let Some(area) = frame.render_next(&mut tiles[k % 2]) {
        got.write_tile(&area, &tiles[k % 2].view(&area)).unwrap();
        k += 1;
    }
    // A finished frame stays finished.
    assert_eq!(frame.render_next(&mut tiles[0]), None);
    assert_eq!(frame.stats(), expected);
    assert_eq!(got.0, reference.0, "tiles in the same order");
    got.1.assert_once_and_equal(&reference.1);
    expected
}

#[test]
fn tiles_on_demand_match_render_in_one_pass() {
    let size = Size::new(320, 240);
    with_demo_scene(0.7, size, |scene| {
        let config = Config::new(size, Rgb565::new(2, 4, 6));
        let s = both_ways::<8192, 80>(scene, config);
        assert_eq!((s.bin_passes, s.rescanned_tiles), (1, 0));
        assert!(s.pixels_shaded > 10_000, "{s:?}");
        // Along the Hilbert curve too.
        both_ways::<8192, 80>(scene, config.tile_order(TileOrder::Hilbert));
    });
}

#[test]
fn tiles_on_demand_match_render_over_many_passes_and_rescans() {
    let size = Size::new(317, 233);
    with_demo_scene(1.3, size, |scene| {
        let config = Config::new(size, Rgb565::new(2, 4, 6));
        // Few tiles per pass.
        let s = both_ways::<8192, 7>(scene, config);
        assert!(s.bin_passes >= 12, "{s:?}");
        // A pool so small that passes give up tiles and some tiles alone
        // overflow it.
        let s = both_ways::<64, 80>(scene, config);
        assert!(s.bin_passes > 12 && s.rescanned_tiles > 0, "{s:?}");
        let s = both_ways::<64, 80>(scene, config.tile_order(TileOrder::Hilbert));
        assert!(s.rescanned_tiles > 0, "{s:?}");
    });
}

#[test]
fn begin_finds_every_error_before_a_tile() {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let renderer: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(Size::new(0, 240), Rgb565::new(0, 0, 0)));
    let mut ws: Box<Workspace<2048, 4096, 80>> = Box::new(Workspace::new());
    let scene = Scene::new(camera(320, 240), &d);
    assert!(matches!(
        renderer.begin(&mut ws, &scene),
        Err(RenderError::ZeroViewport)
    ));

    let renderer: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(Size::new(320, 240), Rgb565::new(0, 0, 0)));
    let mut small: Workspace<4, 64, 4> = Workspace::new();
    match renderer.begin(&mut small, &scene) {
        Err(e) => {
            assert_eq!(
                e,
                RenderError::VertexCapacity {
                    needed: cube.vertex_count(),
                    capacity: 4
                }
            );
            // The same error, for any sink.
            let e: RenderError<u8> = e.for_sink();
            assert!(matches!(e, RenderError::VertexCapacity { capacity: 4, .. }));
        }
        Ok(_) => panic!("a workspace of 4 vertices holds no cube"),
    }
}
