//! Golden images of the classic shading scenes (`examples/common/gallery.rs`),
//! each rendered with every rasterizer and tile order, which must agree
//! pixel for pixel, and compared exactly with `tests/golden/`.
//! `BLESS=1 cargo test --test shading` regenerates them (look at them
//! before committing). The README's gallery, `docs/gallery.png`, must be
//! the contact sheet of the same scenes (`cargo run --example gallery`).

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::gallery::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
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

/// A horizontal grey ramp on a 16-level `Gray4` target, plain (banded)
/// and ordered-dithered, and a dark colour ramp on `Rgb565`.
#[test]
fn ordered_dithering() {
    use embedded_graphics::pixelcolor::Gray4;
    use fixed::types::I16F16;
    use microraster::shader::{Dithered, Gouraud};
    let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
    let pos = [p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)];
    let tris = [[0u16, 1, 2], [0, 2, 3]];
    let grey = [
        Rgb888::new(0, 0, 0),
        Rgb888::new(255, 255, 255),
        Rgb888::new(255, 255, 255),
        Rgb888::new(0, 0, 0),
    ];
    let dark = [
        Rgb888::new(0, 10, 30),
        Rgb888::new(60, 40, 90),
        Rgb888::new(60, 40, 90),
        Rgb888::new(0, 10, 30),
    ];
    let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let size = Size::new(W, 40);
    for (name, colors) in [("ramp", &grey), ("dark_ramp", &dark)] {
        let mesh = Mesh::new(&pos, &tris).unwrap().with_colors(colors).unwrap();
        let d = [Draw::new(&mesh).shading(Shading::Shader)];
        let plain = Scene::new(cam, &d).shader(&Gouraud);
        let dithered = Scene::new(cam, &d).shader(&Dithered(Gouraud));
        for raster in [Rasterizer::Scanline, Rasterizer::Hilbert] {
            let mut images = Vec::new();
            for (suffix, dither) in [("", false), ("_dithered", true)] {
                if name == "ramp" {
                    let cfg = Config::new(size, Gray4::new(0)).rasterizer(raster);
                    let mut r: Renderer<Gray4, 32, 32> = Renderer::new(cfg);
                    let mut ws: Workspace<4, 64, 16> = Workspace::new();
                    let mut cap = Capture::new(size, Gray4::new(0));
                    if dither {
                        r.render(&mut ws, &dithered, &mut cap).unwrap();
                    } else {
                        r.render(&mut ws, &plain, &mut cap).unwrap();
                    }
                    images.push((format!("{name}_gray4{suffix}"), cap.to_rgb()));
                } else {
                    let cfg = Config::new(size, Rgb565::new(0, 0, 0)).rasterizer(raster);
                    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
                    let mut ws: Workspace<4, 64, 16> = Workspace::new();
                    let mut cap = Capture::new(size, Rgb565::new(0, 0, 0));
                    if dither {
                        r.render(&mut ws, &dithered, &mut cap).unwrap();
                    } else {
                        r.render(&mut ws, &plain, &mut cap).unwrap();
                    }
                    images.push((format!("{name}_rgb565{suffix}"), cap.to_rgb()));
                }
            }
            // Dithering changes the picture, and keeps each column's mean
            // brightness closer to the exact ramp than banding does.
            assert!(
                images[0].1 != images[1].1,
                "{name}: dithering changed nothing"
            );
            for (golden, px) in &images {
                check_golden(golden, size, px);
            }
            if name == "ramp" {
                let column_mean = |px: &Vec<Rgb888>, x: u32| -> f64 {
                    (0..size.height)
                        .map(|y| px[(y * size.width + x) as usize].r() as f64)
                        .sum::<f64>()
                        / size.height as f64
                };
                let err = |px: &Vec<Rgb888>| -> f64 {
                    (0..size.width)
                        .map(|x| {
                            let exact = 255.0 * (x as f64 + 0.5) / size.width as f64;
                            (column_mean(px, x) - exact).abs()
                        })
                        .sum::<f64>()
                        / size.width as f64
                };
                let (banded, dithered) = (err(&images[0].1), err(&images[1].1));
                assert!(
                    dithered < banded * 0.6,
                    "dithered error {dithered} against banded {banded}"
                );
            }
        }
    }
}
