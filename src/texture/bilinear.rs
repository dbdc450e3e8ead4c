//! Bilinear filtering: four texels blended with 12-bit weights, exactly as
//! the module docs of [`texture`](super) define it; on a 64-bit host, the
//! same blend with two channels in one word for the own loop of affine
//! spans ([`Pow2Rgb565::bilinear_packed`]).

#[cfg(target_pointer_width = "64")]
use super::{
    sampler::{blend_sum, blend_terms, expand, Taps},
    Pow2Rgb565,
};
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

/// On a 64-bit host, the four texels of a bilinear sample as the blend's
/// terms ([`Pow2Rgb565::bilinear_packed`]), and where they were read (the
/// index of the top left one; see [`Quad`](super::Quad)). Red's and
/// green's in one `u64` each, red's from bit 0 and green's from bit 32:
/// `c00 · 2^24 + 2^23`, `c10 - c00`, `c01 - c00` and `c11 - c10 - c01 +
/// c00`, in wrapping arithmetic; blue's in `u32`.
#[cfg(target_pointer_width = "64")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct PackedQuad {
    at: u32,
    rg: [u64; 4],
    b: [u32; 4],
}

#[cfg(target_pointer_width = "64")]
impl PackedQuad {
    /// No texels yet: an index no texture has.
    pub(crate) const NONE: PackedQuad = PackedQuad {
        at: u32::MAX,
        rg: [0; 4],
        b: [0; 4],
    };
}

/// The blend's rounding half, `2^23`, in both lanes of
/// [`PackedQuad`]'s `rg`.
#[cfg(target_pointer_width = "64")]
const HALF_RG: u64 = (1 << (2 * WEIGHT_BITS - 1)) * (1 + (1 << 32));

#[cfg(target_pointer_width = "64")]
impl Pow2Rgb565<'_> {
    /// [`bilinear_fine`](Self::bilinear_fine) on a 64-bit host, for a loop
    /// of its own (`bilinear_span`): the same blend, expanded as the
    /// general loop's (`2^24 c00 + 2^12 fx (c10 - c00) + 2^12 fy (c01 -
    /// c00) + fx fy (c11 - c10 - c01 + c00) + 2^23`, see
    /// [`bilinear_reusing`](Self::bilinear_reusing)), red and green
    /// together in `u64` lanes of 32 bits. Each of their terms is `t_r +
    /// 2^32 t_g` modulo 2^64 (a negative difference's low lane borrows
    /// from the high one), so the wrapping sum is `S_r + 2^32 S_g` modulo
    /// 2^64, and, each channel's sum being in `0..2^32`, exactly that:
    /// each sum in its lane, three products for two channels (x86-64
    /// `fill-bilinear-exact` 146.94 -> 130.77 instructions a fragment,
    /// with the texels read unchecked after [`cut`](Self::cut)). Kept apart
    /// from the general loop's [`Quad`](super::Quad): with its terms in
    /// this form, the textured frames' nearest loops beside it moved
    /// registers (x86-64 `demo-textured-lit` 290.4 -> 296.7 instructions
    /// a pixel).
    #[inline(always)]
    pub(crate) fn bilinear_packed(&self, fu: u32, fv: u32, quad: &mut PackedQuad) -> [u8; 3] {
        let Taps {
            x,
            y,
            f: [fx, fy],
            at,
        } = self.taps((fu >> 16) as i32, (fv >> 16) as i32);
        if at != quad.at {
            quad.at = at;
            let texel = |x: u32, y: u32| expand(self.at_cut(x, y));
            let [c00, c10, c01, c11] = [
                texel(x[0], y[0]),
                texel(x[1], y[0]),
                texel(x[0], y[1]),
                texel(x[1], y[1]),
            ];
            // Red's and green's terms as `blend_terms` makes blue's, in
            // the lanes of one `u64`.
            let rg = |c: [u8; 3]| (c[1] as u64) << 32 | c[0] as u64;
            let [a, b, c, d] = [rg(c00), rg(c10), rg(c01), rg(c11)];
            quad.rg = [
                (a << (2 * WEIGHT_BITS)) + HALF_RG,
                b.wrapping_sub(a),
                c.wrapping_sub(a),
                d.wrapping_sub(b).wrapping_sub(c).wrapping_add(a),
            ];
            let [a, b, c, d] = [c00[2], c10[2], c01[2], c11[2]].map(u32::from);
            quad.b = blend_terms(a, b, c, d);
        }
        let (wx, wy, wxy) = (fx << WEIGHT_BITS, fy << WEIGHT_BITS, fx * fy);
        let [c, dx, dy, dxy] = quad.rg;
        let rg = c
            .wrapping_add((wx as u64).wrapping_mul(dx))
            .wrapping_add((wy as u64).wrapping_mul(dy))
            .wrapping_add((wxy as u64).wrapping_mul(dxy));
        let b = blend_sum(quad.b, [wx, wy, wxy]);
        [
            (rg >> (2 * WEIGHT_BITS)) as u8,
            (rg >> (32 + 2 * WEIGHT_BITS)) as u8,
            (b >> (2 * WEIGHT_BITS)) as u8,
        ]
    }
}
