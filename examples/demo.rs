//! The host demo: a lit, rotating torus knot and cube, rendered tile by tile
//! into the embedded-graphics simulator.
//!
//! Headless by default: writes PNG frames to `target/demo/` and prints the
//! statistics of every frame. With `--features window` it opens the live
//! simulator window instead (needs SDL2).
//!
//! ```text
//! cargo run --release --example demo [-- --frames N --out DIR --flat]
//!     [--hilbert | --raster scanline|hilbert|auto] [--hilbert-tiles]
//! ```
//!
//! `--hilbert` (or `--raster hilbert`) renders with the Hilbert-order
//! rasterizer, `--hilbert-tiles` visits the tiles along the Hilbert curve;
//! both give the same images as the defaults.

mod common;

use common::*;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics_simulator::{OutputSettingsBuilder, SimulatorDisplay};
use microraster::prelude::*;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

/// The configuration of the RAM budget: 32x32 tiles, room for the whole
/// demo scene and every tile of a 320x240 frame in one binning pass.
type DemoRenderer = Renderer<Rgb565, 32, 32>;
type DemoWorkspace = Workspace<2048, 4096, 80>;

struct Args {
    frames: usize,
    out: std::path::PathBuf,
    shading: Shading,
    raster: Rasterizer,
    tile_order: TileOrder,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        frames: 8,
        out: std::path::PathBuf::from("target/demo"),
        shading: Shading::Gouraud,
        raster: Rasterizer::Scanline,
        tile_order: TileOrder::RowMajor,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--frames" => {
                args.frames = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .ok_or("--frames needs a number")?
            }
            "--out" => args.out = it.next().ok_or("--out needs a directory")?.into(),
            "--flat" => args.shading = Shading::Flat,
            "--hilbert" => args.raster = Rasterizer::Hilbert,
            "--raster" => {
                args.raster = match it.next().as_deref() {
                    Some("scanline") => Rasterizer::Scanline,
                    Some("hilbert") => Rasterizer::Hilbert,
                    Some("auto") => Rasterizer::Auto,
                    _ => return Err("--raster needs scanline, hilbert or auto".into()),
                }
            }
            "--hilbert-tiles" => args.tile_order = TileOrder::Hilbert,
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    Ok(args)
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("demo: {e}");
            std::process::exit(2);
        }
    };
    let assets = DemoAssets::new();
    let knot = assets.knot();
    let cube = cube();
    let mut renderer = DemoRenderer::new(
        Config::new(Size::new(WIDTH, HEIGHT), DEMO_CLEAR)
            .rasterizer(args.raster)
            .tile_order(args.tile_order),
    );
    let mut workspace = Box::new(DemoWorkspace::new());
    let mut display = SimulatorDisplay::<Rgb565>::new(Size::new(WIDTH, HEIGHT));
    println!(
        "renderer RAM: tile buffer + settings {} B, workspace {} B; {:?} rasterizer, {:?} tiles",
        core::mem::size_of::<DemoRenderer>(),
        core::mem::size_of::<DemoWorkspace>(),
        args.raster,
        args.tile_order
    );

    #[cfg(feature = "window")]
    {
        use embedded_graphics_simulator::{SimulatorEvent, Window};
        let _ = &args.out;
        let mut window = Window::new(
            "microraster demo",
            &OutputSettingsBuilder::new().scale(2).build(),
        );
        let mut t = 0.0f32;
        'running: loop {
            let draws = draws(&knot, &cube, t, args.shading);
            let scene = Scene::new(camera(WIDTH, HEIGHT), &draws).light(light());
            renderer
                .render(&mut workspace, &scene, &mut display)
                .expect("demo scene renders");
            window.update(&display);
            if window.events().any(|e| e == SimulatorEvent::Quit) {
                break 'running;
            }
            t += 0.03;
        }
    }

    #[cfg(not(feature = "window"))]
    {
        use embedded_graphics::draw_target::DrawTarget;
        use embedded_graphics::pixelcolor::RgbColor;
        if let Err(e) = std::fs::create_dir_all(&args.out) {
            eprintln!("demo: cannot create {}: {e}", args.out.display());
            std::process::exit(1);
        }
        let settings = OutputSettingsBuilder::new().build();
        println!("frame  tris_in culled rejected clipped drawn  pixels tiles passes");
        for f in 0..args.frames {
            let t = f as f32 * core::f32::consts::TAU / args.frames.max(1) as f32 / 3.0;
            let draws = draws(&knot, &cube, t, args.shading);
            let scene = Scene::new(camera(WIDTH, HEIGHT), &draws).light(light());
            display.clear(Rgb565::BLACK).ok();
            let s = match renderer.render(&mut workspace, &scene, &mut display) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("demo: frame {f}: {e}");
                    std::process::exit(1);
                }
            };
            println!(
                "{f:5} {:8} {:6} {:8} {:7} {:5} {:7} {:5} {:6}",
                s.triangles_in,
                s.culled,
                s.rejected,
                s.clipped,
                s.drawn,
                s.pixels_shaded,
                s.tiles,
                s.bin_passes
            );
            let path = args.out.join(format!("frame_{f:03}.png"));
            if let Err(e) = display.to_rgb_output_image(&settings).save_png(&path) {
                eprintln!("demo: cannot write {}: {e}", path.display());
                std::process::exit(1);
            }
        }
        println!("wrote {} frames to {}", args.frames, args.out.display());
    }
}
