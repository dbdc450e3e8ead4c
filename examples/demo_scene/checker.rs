//! The benchmark checker texture, shared by the host scenes
//! (`examples/common`) and the Cortex-M instruction-count firmware
//! (`examples/icount_scenes`), so that both sample the same texels.

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::IntoStorage;

/// Texel `(x, y)` of the `size` x `size` checker, as raw `Rgb565`: 8x8
/// squares of orange and blue shading across the texture, and a light
/// first row and column that show where it repeats.
pub fn checker_texel(x: u32, y: u32, size: u32) -> u16 {
    let [r, g, b] = checker_rgb(x, y, size);
    Rgb565::from(Rgb888::new(r as u8, g as u8, b as u8)).into_storage()
}

/// The `Rgb888` channels of [`checker_texel`] (each below 256), as a
/// `const fn` so that a firmware can also make the texture at compile time.
pub const fn checker_rgb(x: u32, y: u32, size: u32) -> [u32; 3] {
    let size = if size == 0 { 1 } else { size };
    let shade = (x + y) * 96 / (2 * size);
    if x == 0 || y == 0 {
        [250, 240, 200]
    } else if ((x / 8) + (y / 8)).is_multiple_of(2) {
        [150 + shade, 70 + shade / 2, 40]
    } else {
        [30, 90 + shade / 2, 140 + shade]
    }
}
