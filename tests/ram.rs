//! The RAM budget: a 320x240 frame of a 4,000-triangle mesh with 32x32 tiles
//! in at most 48 KiB, measured from the types' sizes, and the RAM table in
//! the docs generated from those sizes.

#[path = "../examples/common/mod.rs"]
mod common;
#[path = "../examples/ram_table.rs"]
mod ram_table;

use common::*;
use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;

type BudgetRenderer = Renderer<Rgb565, 32, 32>;
type BudgetWorkspace = Workspace<2048, 4096, 80>;

#[test]
fn budget_configuration_fits_48_kib() {
    let total = core::mem::size_of::<BudgetRenderer>() + core::mem::size_of::<BudgetWorkspace>();
    assert!(total <= 48 * 1024, "{total} bytes");
}

#[test]
fn budget_configuration_renders_the_demo_in_one_pass() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    assert!(knot.triangle_count() >= 4000);
    let mut r = BudgetRenderer::new(Config::new(Size::new(320, 240), Rgb565::new(0, 0, 0)));
    let mut ws: Box<BudgetWorkspace> = Box::new(Workspace::new());
    for f in 0..12 {
        let d = draws(&knot, &cube, f as f32 * 0.55, Shading::Gouraud);
        let scene = Scene::new(camera(320, 240), &d).light(light());
        let s = r.render(&mut ws, &scene, &mut NullSink).unwrap();
        assert_eq!(
            (s.bin_passes, s.rescanned_tiles),
            (1, 0),
            "frame {f}: {s:?}"
        );
        assert_eq!(s.tiles, 80);
    }
}

#[test]
fn docs_carry_the_measured_ram_table() {
    let table = ram_table::table();
    for doc in ["README.md", "ARCHITECTURE.md"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(doc);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains(&table),
            "{doc} does not contain the current RAM table; paste the output of `cargo run --example ram_table`"
        );
    }
}
