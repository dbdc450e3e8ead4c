//! Bilinear filtering: four texels blended with 12-bit weights, exactly as
//! the module docs of [`texture`](super) define it.

use super::{Texture, WEIGHT_BITS};

/// One channel of the bilinear blend, exactly `floor((Σ w_ij c_ij + 2^23) /
/// 2^24)` of the module docs, as two linear interpolations.
#[inline(always)]
pub(super) fn blend_channel(c00: u8, c10: u8, c01: u8, c11: u8, fx: u32, fy: u32) -> u8 {
    let lerp_x = |a: u8, b: u8| ((a as i32) << WEIGHT_BITS) + (b as i32 - a as i32) * fx as i32;
    // Both rows are in `0..=255 · 2^12`.
    let (top, bottom) = (lerp_x(c00, c10), lerp_x(c01, c11));
    // The exact value is in `0..=255 · 2^24`, which fits a `u32` but not an
    // `i32`; wrapping arithmetic is exact modulo 2^32, so the `u32` result
    // is that value, even though `bottom - top` may be negative.
    let v = ((top as u32) << WEIGHT_BITS).wrapping_add(((bottom - top) as u32).wrapping_mul(fy));
    // At most 255 · 2^24 + 2^23 < 2^32.
    ((v + (1 << (2 * WEIGHT_BITS - 1))) >> (2 * WEIGHT_BITS)) as u8
}

impl Texture<'_> {
    /// [`sample`](Self::sample) with [`Filter::Bilinear`](super::Filter::Bilinear).
    #[inline(never)]
    pub(super) fn bilinear(&self, u: i32, v: i32) -> [u8; 3] {
        let (x0, x1, fx) = self.u.taps(u);
        let (y0, y1, fy) = self.v.taps(v);
        let (a, b) = (self.fetch_call(x0, y0), self.fetch_call(x1, y0));
        let (c, d) = (self.fetch_call(x0, y1), self.fetch_call(x1, y1));
        let mut out = [0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            *o = blend_channel(a[k], b[k], c[k], d[k], fx, fy);
        }
        out
    }

    /// [`fetch`](Self::fetch) as a call: bilinear filtering reads four
    /// texels, and four inlined copies of the format match would more
    /// than double the code of `sample` for a few cycles each.
    #[inline(never)]
    pub(super) fn fetch_call(&self, x: u32, y: u32) -> [u8; 3] {
        self.fetch(x, y)
    }
}
