//! Reading one texel in its storage format (Rgb565, Gray8, Indexed8,
//! Indexed4) as RGB888.

use super::{rgb565_to_rgb888, Texels, Texture};

impl Texture<'_> {
    /// Texel `(x, y)`, for `x < width` and `y < height`.
    #[inline(always)]
    pub(super) fn fetch(&self, x: u32, y: u32) -> [u8; 3] {
        let row = y as usize * self.stride as usize;
        let i = row + x as usize;
        // `new` checked the lengths and every index, so each `get` below
        // succeeds; the fallbacks (black) only keep the lookups free of
        // panic paths, which `forbid(unsafe_code)` cannot remove otherwise.
        match self.texels {
            Texels::Rgb565(t) => rgb565_to_rgb888(match t.get(i) {
                Some(&c) => c,
                None => 0,
            }),
            Texels::Gray8(t) => {
                let g = match t.get(i) {
                    Some(&g) => g,
                    None => 0,
                };
                [g, g, g]
            }
            Texels::Indexed8 { indices, palette } => {
                let index = match indices.get(i) {
                    Some(&n) => n,
                    None => 0,
                };
                palette_color(palette, index)
            }
            Texels::Indexed4 { indices, palette } => {
                let byte = match indices.get(row + x as usize / 2) {
                    Some(&b) => b,
                    None => 0,
                };
                // The left (even) texel is in the high nibble.
                let index = (byte >> (4 - 4 * (x & 1))) & 0x0F;
                palette_color(palette, index)
            }
        }
    }
}

#[inline(always)]
pub(super) fn palette_color(palette: &[u16], index: u8) -> [u8; 3] {
    rgb565_to_rgb888(match palette.get(index as usize) {
        Some(&c) => c,
        None => 0,
    })
}
