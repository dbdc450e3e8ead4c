//! The projection by 32-bit division, where a division is an instruction
//! (ARMv7-M, ARMv8-M Mainline, RISC-V `rv32im`): x and y one division each,
//! depth two digits of a long division.

use super::{Viewport, W_MIN};
use crate::raster::SubPoint;
use core::num::NonZeroU32;

impl Viewport {
    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`](super::super::MUST_CLIP) bits
    /// and `w` below `short_w` (and `2^23`) by 32-bit division: x's and
    /// y's dividends `|x| h + w / 2 <= 4 w h + w / 2` fit 32 bits, so
    /// each quotient is one division (where the long division below took
    /// two and their shifts); depth's quotient is two divisions
    /// ([`depth_digits`]).
    #[inline(always)]
    pub(crate) fn project_digits(&self, p: &[i32; 4], w: NonZeroU32) -> (SubPoint, u32) {
        debug_assert!(w.get() < self.short_w && w.get() as i64 >= W_MIN);
        let half = w.get() / 2;
        // Half a viewport side in sub-pixels is at most 2^15; |x|, |y| <=
        // 4w.
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        // div_round(n hw, w) with the sign of n.
        let round = |n: i32, h: u32| -> i32 {
            let q = ((n.unsigned_abs() * h + half) / w) as i32;
            if n < 0 {
                -q
            } else {
                q
            }
        };
        let x = self.half_w as i32 + round(p[0], hw);
        let y = self.half_h as i32 - round(p[1], hh);
        // div_round((z + w) 65535, 2w) = floor(((z + w) 65535 + w) / w) / 2,
        // and -w <= z <= w: not negative, at most
        // floor((2w 65535 + w) / w) / 2 = 65535, no clamp. (The 64-bit
        // dividend's two divisions took its shifts and leading-zero count
        // besides: 8 instructions a vertex more on the Cortex-M3.)
        let z = depth_digits((p[2] + w.get() as i32) as u32, w);
        (SubPoint::new(x, y), z)
    }

    /// [`project`](Self::project) of a vertex inside the view volume
    /// (outcode 0: `W_MIN <= w`, `|x|, |y|, |z| <= w`) with `w` below
    /// `short_w`, by 32-bit divisions; `None` for any other vertex. With
    /// `c = v + w` for each coordinate `v` (`0..=2w` inside, and outside
    /// it as an unsigned word, for `w < 2^23`: so the inside test is three
    /// unsigned compares with `2w`):
    ///
    /// * x's `div_round(x hw, w)` (ties away from zero) is `floor((x hw +
    ///   o) / w)` with `o = floor(w / 2)` for `x >= 0` and `floor((w - 1) /
    ///   2)` for `x < 0`; adding `hw w` (`hw` half the width), the screen
    ///   `x = hw + div_round(x hw, w)` is `floor((c hw + o) / w)`, which is
    ///   `floor((2 c hw + w - s) / (2w))` (`s = 1` for `x < 0`, else 0: an
    ///   odd numerator is never a multiple of `2w`), no sign test; the
    ///   numerator is at most `4 w hw + w < 2^32` (`short_w`);
    /// * y likewise, as `2 hh - floor((2 c hh + w - s) / (2w))`;
    /// * depth by two divisions ([`depth_digits`]).
    ///
    /// The same results; about 30 instructions a vertex fewer on the
    /// Cortex-M3 than the outcode and [`project_digits`](Self::project_digits).
    #[inline(always)]
    pub(crate) fn project_fast(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        let w = p[3] as u32;
        // W_MIN <= w < short_w, as one unsigned compare (short_w > W_MIN).
        // The bound masked to 23 bits, which leaves it as it is (`short_w
        // <= 2^23`) but shows the compiler that `w < 2^24`, so that `2w`
        // is not 0 (once per loop: the bound is the loop's; it tested `2w`
        // every vertex).
        let bound = (self.short_w - W_MIN as u32) & ((1 << DIGITS_W_BITS) - 1);
        if w.wrapping_sub(W_MIN as u32) >= bound {
            return None;
        }
        // Not 0 (the compiler sees it through the bound, see above).
        let w2n = NonZeroU32::new(w << 1)?;
        let w2 = w2n.get();
        let c = [p[0], p[1], p[2]].map(|v| (v as u32).wrapping_add(w));
        if c[0] > w2 || c[1] > w2 || c[2] > w2 {
            return None;
        }
        // The width and height in sub-pixels, 2 hw and 2 hh.
        let (tw, th) = ((self.half_w as u32) << 1, (self.half_h as u32) << 1);
        // w - s, for s = 1 where the coordinate is negative.
        let odd = |v: i32| w.wrapping_add((v >> 31) as u32);
        let x = (c[0] * tw + odd(p[0])) / w2n;
        let y = th - (c[1] * th + odd(p[1])) / w2n;
        // 3w - c = 2w - z: one subtraction (from `c`, `3w` took one more).
        let z = depth_by_2w(c[2], w2.wrapping_sub(p[2] as u32), w2n);
        Some((SubPoint::new(x as i32, y as i32), z))
    }
}

/// Depth `floor((c 65535 + w) / w) / 2` (at most 65,535) of `c = z + w`
/// in `0..=2w`, for `w < 2^23`, by two 32-bit divisions: with `c 2^8 = d1
/// w + r1`, `c 65535 + w = c 2^16 - c + w = d1 2^8 w + (r1 2^8 + w - c)`,
/// and `w - c >= -w`, so the quotient is `d1 2^8 + floor((r1 2^8 + 2w - c)
/// / w) - 1`; every dividend is below `2^32` (`c 2^8 <= w 2^9`, `r1 2^8 +
/// 2w < w 2^8 + 2w`). (Three digits of one division each, the first `c /
/// w`, took a multiply and three instructions more.)
#[inline(always)]
pub(super) fn depth_digits(c: u32, w: NonZeroU32) -> u32 {
    debug_assert!(w.get() >> DIGITS_W_BITS == 0 && c <= 2 * w.get());
    let c8 = c << 8;
    let (d1, r1) = (c8 / w, c8 % w);
    let d0 = ((r1 << 8) + (2 * w.get() - c)) / w;
    depth_of_digits(d1, d0)
}

/// Depth `floor((c 65535 + w) / (2w))` (at most 65,535) of `c = z + w`
/// in `0..=2w`, given `e = 3w - c` and `w2 = 2w`, for `w <` [`FAST_W`],
/// by two 32-bit divisions by `2w`
/// ([`Viewport::project_fast`]'s divisor for x and y): with `c 2^8 = d1
/// 2w + r1` (`r1 < 2w`), `c 65535 + w = d1 2^8 2w + (r1 2^8 + w - c)`,
/// and `w - c >= -w`, so the depth is `d1 2^8 + floor((r1 2^8 + 3w - c)
/// / (2w)) - 1`, whose dividend is at least `w` and below `515 w <= 2^32`
/// (`c 2^8 <= w 2^9` too); and not negative (where `r1 2^8 + w < c`,
/// `c > w` and `d1 >= 128`). [`depth_digits`]' quotients by `w` took a
/// halving more: one instruction a vertex on the Cortex-M3 and M4F.
#[inline(always)]
fn depth_by_2w(c: u32, e: u32, w2: NonZeroU32) -> u32 {
    let w = w2.get() / 2;
    debug_assert!(w < FAST_W && w2.get() == 2 * w && c <= 2 * w && e == 3 * w - c);
    let c8 = c << 8;
    let (d1, r1) = (c8 / w2, c8 % w2);
    let d0 = ((r1 << 8) + e) / w2;
    let z = (d1 << 8) + d0 - 1;
    debug_assert!(z <= 65_535);
    z
}

/// The bound of `short_w`: [`depth_by_2w`] takes `w` below it, `515 w <
/// 2^32` (below `2^23`, `DIGITS_W_BITS`).
pub(super) const FAST_W: u32 = u32::MAX / 515;

/// Depth from the two digits of [`depth_digits`] (and of
/// [`Viewport::project_recip`]'s), `d1 2^8 + d0 = floor((c 65535 + w) /
/// w) + 1`: that quotient halved.
#[inline(always)]
pub(super) fn depth_of_digits(d1: u32, d0: u32) -> u32 {
    // Not negative: the quotient is at least 1.
    let z = ((d1 << 8) + d0 - 1) >> 1;
    debug_assert!(z <= 65_535);
    z
}

/// [`Viewport::project_digits`] takes `w` below `2^DIGITS_W_BITS`.
pub(super) const DIGITS_W_BITS: u32 = 23;
