//! Prints a hash of each benchmark scene's whole image, independent of
//! the tiles it was rendered in, for a study of the tile size: build it
//! with `MICRORASTER_BENCH_TILE=WxH` (`examples/bench_tile`) and compare
//! with the 32x32 build's hashes, which must be the same.
//!
//! ```text
//! MICRORASTER_BENCH_TILE=64x32 cargo run --release --example tile_image
//! ```
//!
//! (The Cortex-M firmware's image hashes, `examples/icount.rs`, fold the
//! tiles in their order with their rectangles: they compare a board with
//! the host at the same tile size only.)

mod common;

use common::scenes::*;
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::primitives::Rectangle;
use microraster::prelude::*;
use microraster::sink::TileSink;
use microraster::tile::TileView;

/// The whole frame, as `Rgb565`'s raw bits, row by row.
struct Frame(Vec<u16>);

impl TileSink<Rgb565> for Frame {
    type Error = core::convert::Infallible;

    fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, Rgb565>,
    ) -> Result<(), Self::Error> {
        let (x0, y0) = (area.top_left.x as usize, area.top_left.y as usize);
        for (dy, row) in tile.rows().enumerate() {
            let at = (y0 + dy) * WIDTH as usize + x0;
            for (p, &c) in self.0[at..at + row.len()].iter_mut().zip(row) {
                *p = RawU16::from(c).into_inner();
            }
        }
        Ok(())
    }
}

impl Frame {
    fn new() -> Self {
        Self(vec![0; (WIDTH * HEIGHT) as usize])
    }

    /// FNV-1a over the pixels.
    fn hash(&self) -> u32 {
        self.0.iter().fold(0x811c_9dc5, |h: u32, &p| {
            (h ^ p as u32).wrapping_mul(0x0100_0193)
        })
    }
}

fn main() {
    println!("tile {TILE_W}x{TILE_H} ({TILES} tiles)");
    let mut r = renderer();
    let mut image =
        |name: &str, render: &mut dyn FnMut(&mut BenchRenderer, &mut Frame) -> FrameStats| {
            let mut f = Frame::new();
            let s = render(&mut r, &mut f);
            println!(
                "image: {name} {:08x} tile_pairs={} bin_passes={} peak_bin_entries={}",
                f.hash(),
                s.tile_pairs,
                s.bin_passes,
                s.peak_bin_entries
            );
        };
    let mut ws: Box<DemoWorkspace> = Box::default();
    let demo = DemoScene::new();
    image("demo", &mut |r, f| {
        demo.render(r, &mut ws, Shading::Gouraud, f)
    });
    image("demo-flat", &mut |r, f| {
        demo.render(r, &mut ws, Shading::Flat, f)
    });
    let fill = FillScene::new(8);
    image("fill", &mut |r, f| fill.render(r, &mut ws, f));
    let textured = TexturedDemoScene::new();
    image("demo-textured-lit", &mut |r, f| {
        textured.render(r, &mut ws, f)
    });
    let mut rock_ws: Box<RockWorkspace> = Box::default();
    let rock = RockScene::new();
    image("rock", &mut |r, f| rock.render(r, &mut rock_ws, f));
}
