//! Prints the RAM the renderer holds per configuration, measured from the
//! types' sizes, as the Markdown table in README.md and ARCHITECTURE.md.
//!
//! ```text
//! cargo run --example ram_table
//! ```

use core::mem::size_of;
use embedded_graphics::pixelcolor::{BinaryColor, Gray4, Gray8, Rgb565, Rgb888};
use microraster::{Renderer, Workspace};

/// One row: a name, the renderer (tile buffer + settings) size and the
/// workspace size.
// A line a row, as the table it prints (rustfmt would give each argument of
// `row!` a line of its own).
#[rustfmt::skip]
pub fn rows() -> Vec<(String, usize, usize)> {
    macro_rules! row {
        ($c:ty, $tw:literal, $th:literal, $v:literal, $b:literal, $t:literal, $what:literal) => {
            (
                format!(
                    "{} | {}x{} | {} | {} | {} | {}",
                    $what,
                    $tw,
                    $th,
                    stringify!($c),
                    $v,
                    $b,
                    $t
                ),
                size_of::<Renderer<$c, $tw, $th>>(),
                size_of::<Workspace<$v, $b, $t>>(),
            )
        };
    }
    vec![
        //   colour       tile    vertices bins tiles/pass frame and scene
        row!(Rgb565,      32, 32, 2048, 4096,  80, "320x240, 4,000-triangle mesh (the budget)"),
        row!(Rgb565,      16, 16, 2048, 4096, 300, "320x240, 4,000-triangle mesh"),
        row!(Rgb565,      64, 32, 2048, 3584,  40, "320x240, 4,000-triangle mesh"),
        row!(Rgb565,     320, 240, 2048, 4096,   1, "320x240, 4,000-triangle mesh, one tile (a frame buffer)"),
        row!(Rgb888,      32, 32, 2048, 4096,  80, "320x240, 4,000-triangle mesh"),
        row!(Gray8,       32, 32, 2048, 4096,  80, "320x240, 4,000-triangle mesh"),
        row!(Rgb565,      32, 32,  512, 1024,  80, "320x240, 1,000-triangle mesh"),
        row!(Rgb565,      16, 16,  256,  512,  16, "240x240, 500 triangles, 16 tiles per pass"),
        row!(Gray4,       32, 32,  512, 1024,   8, "128x64 OLED, 1,000 triangles"),
        row!(BinaryColor, 16, 16,  128,  256,  32, "128x64 mono, 250 triangles"),
    ]
}

/// The table, in Markdown.
pub fn table() -> String {
    let mut s = String::from(
        "| frame and scene | tile | colour | vertices | bin entries | tiles per pass | tile buffer + settings | workspace | total |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, r, w) in rows() {
        s += &format!(
            "| {name} | {r} B | {w} B | **{} B ({:.1} KiB)** |\n",
            r + w,
            (r + w) as f64 / 1024.0
        );
    }
    s
}

#[allow(dead_code)]
fn main() {
    print!("{}", table());
}
