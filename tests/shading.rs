//! Golden images of the classic shading scenes (`examples/gallery_scenes`),
//! each rendered with every rasterizer and tile order, which must agree
//! pixel for pixel, and compared exactly with `tests/golden/`.
//! `BLESS=1 cargo test --test shading` regenerates them (look at them
//! before committing). The README's gallery, `docs/gallery.png`, must be
//! the contact sheet of the same scenes (`cargo run --example gallery`).

#[path = "../examples/common/mod.rs"]
mod common;
#[path = "../examples/gallery_scenes/mod.rs"]
mod gallery_scenes;
mod support;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use gallery_scenes::*;
use microraster::prelude::*;
use support::{check_golden, Capture};

fn render(g: &Gallery, name: &str, config: Config<Rgb565>) -> Capture<Rgb565> {
    let mut cap = Capture::new(config.size, config.clear_color);
    g.render(name, config, &mut cap).expect("the scene exists");
    assert!(
        cap.writes.iter().all(|&w| w == 1),
        "{name}: every pixel sent once"
    );
    cap
}

#[test]
fn every_scene_matches_its_golden_image_with_every_rasterizer() {
    let g = Gallery::new();
    for (name, _) in SCENES {
        let config = scene_config(name);
        let reference = render(&g, name, config);
        for (raster, order) in [
            (Rasterizer::Hilbert, TileOrder::RowMajor),
            (Rasterizer::Auto, TileOrder::RowMajor),
            (Rasterizer::Hilbert, TileOrder::Hilbert),
        ] {
            let other = render(&g, name, config.rasterizer(raster).tile_order(order));
            assert!(
                other.pixels == reference.pixels,
                "{name}: {raster:?} with {order:?} tiles differs from the scanline rasterizer"
            );
        }
        check_golden(name, config.size, &reference.to_rgb());
    }
}

/// The README's gallery is what `examples/gallery.rs` draws from these
/// scenes now.
#[test]
fn readme_gallery_is_current() {
    use embedded_graphics::prelude::Point;
    let g = Gallery::new();
    let size = sheet_size();
    // The simulator's display, as the example draws into (text goes
    // through fill_contiguous in ways the test capture does not accept).
    let mut sheet = embedded_graphics_simulator::SimulatorDisplay::<Rgb565>::new(size);
    draw_sheet(&g, &mut sheet);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/gallery.png");
    let (file_size, pixels) =
        support::read_png(&path).expect("docs/gallery.png exists: cargo run --example gallery");
    assert_eq!(file_size, size);
    let expected: Vec<Rgb888> = (0..size.height as i32)
        .flat_map(|y| (0..size.width as i32).map(move |x| Point::new(x, y)))
        .map(|p| sheet.get_pixel(p).into())
        .collect();
    assert!(
        pixels == expected,
        "docs/gallery.png is stale: regenerate it with cargo run --example gallery"
    );
}
