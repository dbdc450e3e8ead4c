//! A tile buffer reused across tiles and frames: `render_next` clears only
//! the rows drawn since the buffer's last clear, so a buffer that held
//! other tiles (of this frame or an earlier one, drawn by triangles,
//! lines, points, transparent or shader draws, or packed for a transfer),
//! or was cleared with another colour or depth, must give every tile the
//! pixels and depths of a fresh buffer.

#[path = "../examples/common/mod.rs"]
mod common;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;
use microraster::render::Frame;

type Tile = TileBuffer<Rgb565, 32, 32>;

/// Not a multiple of the tile: the right column of tiles is 22 pixels
/// wide, the bottom row 14 high.
const SIZE: Size = Size::new(150, 110);

/// A tile as drawn: where it lies, its pixels and its depths, row by row.
type Drawn = (Rectangle, Vec<Rgb565>, Vec<u16>);

/// The tile's pixels and depths (its buffer's top-left `area.size`).
fn read(tile: &Tile, area: Rectangle) -> Drawn {
    let (w, h) = (area.size.width as usize, area.size.height as usize);
    let pixels = tile.view(&area).pixels().collect();
    let depths = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| tile.depth(x, y).unwrap())
        .collect();
    (area, pixels, depths)
}

/// Every tile of a frame of `scene`, each drawn into a fresh buffer.
fn fresh<F: ShaderSet<Rgb565>>(config: Config<Rgb565>, scene: &Scene<'_, F>) -> Vec<Drawn> {
    let mut ws: Box<Workspace<2048, 8192, 32>> = Box::new(Workspace::new());
    let mut frame: Frame<'_, Rgb565, F, 32, 32> = Frame::begin(config, &mut ws, scene).unwrap();
    let mut out = Vec::new();
    loop {
        // Its own colour, unlike any clear colour of the frames.
        let mut tile = Tile::new(Rgb565::new(7, 50, 9));
        let Some(area) = frame.render_next(&mut tile) else {
            return out;
        };
        out.push(read(&tile, area));
    }
}

/// Every tile of a frame of `scene`, drawn into the buffers of `pool` in
/// turn (tile `k` into buffer `k % pool.len()`), each narrow tile then
/// packed for a transfer, as a DMA transfer would. Binned with a pool of
/// `B` entries: a small one makes passes of a few tiles, and tiles whose
/// bin overflows it, rescanned.
fn reused<F: ShaderSet<Rgb565>, const B: usize>(
    config: Config<Rgb565>,
    scene: &Scene<'_, F>,
    pool: &mut [Tile],
) -> Vec<Drawn> {
    let mut ws: Box<Workspace<2048, B, 32>> = Box::new(Workspace::new());
    let mut frame: Frame<'_, Rgb565, F, 32, 32> = Frame::begin(config, &mut ws, scene).unwrap();
    let mut out = Vec::new();
    for k in 0.. {
        let tile = &mut pool[k % pool.len()];
        let Some(area) = frame.render_next(tile) else {
            let s = frame.stats();
            assert!(B > 64 || s.rescanned_tiles > 0, "{s:?}");
            return out;
        };
        out.push(read(tile, area));
        if area.size.width < 32 {
            let packed = tile.pack(&area).to_vec();
            assert_eq!(packed, out[k].1, "tile {k}: packed");
        }
    }
    unreachable!()
}

fn check<F: ShaderSet<Rgb565>>(
    name: &str,
    config: Config<Rgb565>,
    scene: &Scene<'_, F>,
    pool: &mut [Tile],
) {
    let expected = fresh(config, scene);
    let got = reused::<F, 8192>(config, scene, pool);
    assert_eq!(got.len(), expected.len(), "{name}");
    assert!(
        reused::<F, 64>(config, scene, pool) == expected,
        "{name}: rescanned"
    );
    let drawn = expected
        .iter()
        .filter(|t| t.1.iter().any(|&c| c != config.clear_color));
    assert!(drawn.count() >= 4, "{name}: the frame draws something");
    for (k, (g, e)) in got.iter().zip(&expected).enumerate() {
        assert_eq!(g.0, e.0, "{name}: tile {k}: area");
        assert!(g.1 == e.1, "{name}: tile {k} at {:?}: pixels", e.0);
        assert!(g.2 == e.2, "{name}: tile {k} at {:?}: depths", e.0);
    }
}

#[test]
fn a_reused_buffer_draws_as_a_fresh_one() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let camera = camera(SIZE.width, SIZE.height);
    let blue = Rgb565::new(0, 0, 20);
    let grey = Rgb565::new(12, 25, 12);
    let plain = Config::new(SIZE, blue);
    // The buffers outlive the frames: each frame starts with what the
    // last left in them.
    for pool_len in [1, 2, 3] {
        let pool = &mut vec![Tile::new(Rgb565::new(31, 0, 0)); pool_len][..];
        for (i, t) in [0.3, 1.9, 4.1].into_iter().enumerate() {
            let name = |what: &str| format!("{what}, t {t}, {pool_len} buffers");
            // Filled triangles, with edges drawn over them.
            let [k, c] = draws(&knot, &cube, t, Shading::Gouraud);
            let d = [k, c.edges(Edges::new(Rgb888::new(255, 255, 0)))];
            let scene = Scene::new(camera, &d).light(light());
            check(&name("gouraud"), plain, &scene, pool);
            // The same in Hilbert order, then with another clear colour
            // and depth (every other frame), then the first again.
            let hilbert = plain.tile_order(TileOrder::Hilbert);
            check(&name("hilbert"), hilbert, &scene, pool);
            let auto = plain.rasterizer(Rasterizer::Auto);
            check(&name("auto"), auto, &scene, pool);
            let walk = plain.rasterizer(Rasterizer::Hilbert);
            check(&name("hilbert walk"), walk, &scene, pool);
            let other = match i % 2 {
                0 => plain.clear_depth(65_000),
                _ => plain.clear_color(grey),
            };
            check(&name("other clear"), other, &scene, pool);
            check(&name("gouraud again"), plain, &scene, pool);
            // Lines and points alone, a transparent draw, a shader draw.
            let [k, c] = draws(&knot, &cube, t, Shading::Wireframe);
            let d = [k, c.shading(Shading::Points(3))];
            let scene = Scene::new(camera, &d).light(light());
            check(&name("wireframe"), plain, &scene, pool);
            let [k, c] = draws(&knot, &cube, t, Shading::Flat);
            let d = [k.shader(0), c.blend(Blend::Alpha(128))];
            let scene = Scene::new(camera, &d).light(light()).shader(&Gouraud);
            check(&name("shader"), other, &scene, pool);
            check(&name("shader"), plain, &scene, pool);
        }
    }
}

/// A buffer from `TileBuffer::new_nearest` (all zeros, for a static in
/// .bss: the nearest depth and no row recorded as written) draws its
/// first tile as a fresh `TileBuffer::new` one, whether the frame clears
/// to its colour or to another.
#[test]
fn a_nearest_buffer_draws_as_a_fresh_one() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let camera = camera(SIZE.width, SIZE.height);
    let black = Rgb565::new(0, 0, 0);
    let [k, c] = draws(&knot, &cube, 1.9, Shading::Gouraud);
    let d = [k, c];
    let scene = Scene::new(camera, &d).light(light());
    for clear in [black, Rgb565::new(0, 0, 20)] {
        let config = Config::new(SIZE, clear);
        for first in [black, Rgb565::new(31, 0, 0)] {
            let pool = &mut [Tile::new_nearest(first), Tile::new_nearest(first)];
            assert_eq!(pool[0].depth(31, 31), Some(0));
            check(
                &format!("clear {clear:?}, buffers of {first:?}"),
                config,
                &scene,
                pool,
            );
        }
    }
}
