//! Draws the README's gallery, `docs/gallery.png`: the classic shading
//! scenes of `examples/common/gallery.rs` (the golden tests' scenes) on one
//! contact sheet, each 160x120 with its caption.
//!
//! ```text
//! cargo run --example gallery [-- OUT.png]
//! ```

mod common;

use common::gallery::{draw_sheet, sheet_size, Gallery};
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics_simulator::{OutputSettingsBuilder, SimulatorDisplay};

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/gallery.png".into());
    let mut display = SimulatorDisplay::<Rgb565>::new(sheet_size());
    draw_sheet(&Gallery::new(), &mut display);
    let image = display.to_rgb_output_image(&OutputSettingsBuilder::new().build());
    if let Err(e) = image.save_png(&out) {
        eprintln!("gallery: cannot write {out}: {e}");
        std::process::exit(1);
    }
    println!("wrote {out}");
}
