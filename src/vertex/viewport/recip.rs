//! The projection by `w`'s 16-bit reciprocal ([`Recip16`]), for ARMv6-M,
//! which has neither a divide instruction nor a 32 x 32 -> 64-bit multiply:
//! every quotient digits of a long division, two `MULS` and a correction each.

use super::long::depth_of_digits;
use super::{Viewport, W_MIN};
use crate::math::Recip16;
use crate::raster::SubPoint;
use core::num::NonZeroU32;

impl Viewport {
    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`](super::super::MUST_CLIP) bits
    /// and `w <` [`RECIP_W`] by `w`'s 16-bit reciprocal ([`Recip16`]), for
    /// ARMv6-M, which has neither a divide instruction nor a 32 x 32 ->
    /// 64-bit multiply: every quotient is three digits of a long division
    /// ([`Recip16::digit`]: two `MULS` and one correction each), with no
    /// 64-bit product, where `w`'s 32-bit reciprocal and its 64-bit
    /// multiply-highs took about 350 instructions a vertex more. The
    /// quotients are the same.
    ///
    /// x's quotient `floor((|x| hw + e) / w)` (`e = floor(w / 2)`,
    /// `|x| <= 4w`, `hw <= 2^15`) from `|x| = a w + b` (`b < w`) and `hw =
    /// c1 2^7 + c0` (`c1 <= 2^8`, `c0 < 2^7`): with `b c1 = d1 w + r1`,
    /// `|x| hw + e = (a hw + d1 2^7) w + (r1 2^7 + b c0 + e)`, the last
    /// term below `w (2^8 + 1)`; so the quotient is `a hw + d1 2^7 +
    /// floor((r1 2^7 + b c0 + e) / w)`. Likewise y. Depth's `floor((c
    /// 65535 + w) / w)` (`c = z + w` in `0..=2w`) as [`depth_digits`](super::long::depth_digits)'.
    /// The first digit of each pair is left uncorrected
    /// ([`Recip16::estimate`]): the identities hold for any `d1`, `r1`
    /// with `b c1 = d1 w + r1` (or `c 2^8`), and `r1 < 2w` keeps the last
    /// term below `w 2^9` and `w 514`. Every digit's dividend is below `w
    /// 2^12` (within [`Recip16::digit`]'s range) and, with `w <`
    /// [`RECIP_W`], below `2^32`.
    ///
    /// Where both half sides are below `2^12` and `w` is at most `one_w`,
    /// x's and y's `floor((b h + e) / w)` is one digit (its dividend below
    /// `w 2^12` and `2^32`): ARMv6-M `demo` 6,746,451 to 6,663,049
    /// instructions (vertex 1,060,241 to 976,845). For a vertex inside the
    /// view volume (`inside`: `|x|, |y| <= w`, so `a` is 0 or `b = 0`)
    /// the whole `floor((|x| h + e) / w)` is that one digit, without the
    /// first digit's compare and `a h`: `demo` 6,661,509 to 6,630,124
    /// (vertex 927,437 to 896,052).
    #[inline(always)]
    #[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
    pub(crate) fn project_recip(
        &self,
        p: &[i32; 4],
        w: NonZeroU32,
        inside: bool,
    ) -> (SubPoint, u32) {
        debug_assert!(w.get() < RECIP_W && w.get() as i64 >= W_MIN);
        // w < 2^23: its logarithm from a table, not a search.
        let f = Recip16::new_w23(w);
        let wu = w.get();
        let half = wu / 2;
        // floor((|n| h + half) / w) for |n| <= 4w, h <= 2^15. A function
        // inline, not a closure: LLVM kept the closure out of line (two
        // calls a vertex).
        #[inline(always)]
        fn quotient(f: &Recip16, half: u32, n: i32, h: u32, one: bool) -> u32 {
            // The first digit is 0 for nearly every vertex (inside the
            // view volume, `|n| <= w`): a compare rather than a digit's
            // two products and correction.
            let m = n.unsigned_abs();
            let (a, b) = if m < f.d { (0, m) } else { f.digit(m) };
            // One digit where `one_w` allows it (a small viewport and
            // `w`), else two of 8 and 7 bits.
            let rest = match one {
                true => f.digit(b * h + half).0,
                false => {
                    // The first uncorrected: `r1 < 2w` keeps the second's
                    // dividend below `w 2^9` (and 2^32).
                    let (d1, r1) = f.estimate(b * (h >> 7));
                    let (d0, _) = f.digit((r1 << 7) + b * (h & 127) + half);
                    (d1 << 7) + d0
                }
            };
            a * h + rest
        }
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        let one = wu <= self.one_w();
        let (qx, qy) = match inside && one {
            // `|n| <= w` (inside the view volume: nearly every vertex):
            // `|n| h + half < w (h + 1)`, below `w 2^12` and, for `w <=
            // one_w`, `2^32`, so each quotient is one digit, without the
            // first digit's compare and its product `a h`.
            true => {
                let digit = |n: i32, h: u32| f.digit(n.unsigned_abs() * h + half).0;
                (digit(p[0], hw), digit(p[1], hh))
            }
            false => (
                quotient(&f, half, p[0], hw, one),
                quotient(&f, half, p[1], hh, one),
            ),
        };
        // div_round(n h, w) with the sign of n.
        let signed = |n: i32, q: u32| if n < 0 { -(q as i32) } else { q as i32 };
        let x = self.half_w as i32 + signed(p[0], qx);
        let y = self.half_h as i32 - signed(p[1], qy);
        // -w <= z <= w (`depth_recip`).
        (SubPoint::new(x, y), depth_recip(&f, p[2], wu))
    }

    /// [`project_recip`](Self::project_recip) of a vertex inside the view
    /// volume (outcode 0) with `2^15 <= w <= one_w` (nearly every vertex:
    /// `w` from half a unit up), inline in ARMv6-M's vertex loop; `None`
    /// for any other vertex, which the loop sends out of line
    /// (`vertex::setup`'s `lit_rest`, the whole vertex). Its outcode is then the
    /// constant 0 and its `inside` true, where the loop's one inline path
    /// for every vertex carried both (and the outcode) as values from the
    /// outcode's paths to the packing, and `w`'s reciprocal is
    /// [`Recip16::new_w15`], without `new_w23`'s branch below `2^15`. The
    /// test of the view volume is [`outcode`](super::super::outcode)'s for ARMv6-M (the three
    /// `w - |v|` or-ed, one sign test), its `|v|` kept for the digits.
    #[inline(always)]
    #[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
    pub(crate) fn project_recip_fast(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        let wu = p[3] as u32;
        // 2^15 <= w <= one_w (W_MIN <= 2^15, one_w < RECIP_W < 2^23).
        if wu.wrapping_sub(1 << 15) >= self.fast_w() {
            return None;
        }
        let m = [p[0], p[1], p[2]].map(|v| v.unsigned_abs());
        // |v| <= w for each, as `w - |v|` below 2^31 (see `outcode`).
        if (wu.wrapping_sub(m[0]) | wu.wrapping_sub(m[1]) | wu.wrapping_sub(m[2])) >> 31 != 0 {
            return None;
        }
        let f = Recip16::new_w15(wu);
        let half = wu / 2;
        // `|n| h + half < w (h + 1)`, below `w 2^12` and, for `w <=
        // one_w`, `2^32`: one digit (as `project_recip`'s).
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        let qx = f.digit(m[0] * hw + half).0;
        let qy = f.digit(m[1] * hh + half).0;
        let signed = |n: i32, q: u32| if n < 0 { -(q as i32) } else { q as i32 };
        let x = self.half_w as i32 + signed(p[0], qx);
        let y = self.half_h as i32 - signed(p[1], qy);
        Some((SubPoint::new(x, y), depth_recip(&f, p[2], wu)))
    }
}

/// Depth of `z` by `w`'s [`Recip16`] `f` (`-w <= z <= w`, `w <`
/// [`RECIP_W`]), as [`depth_digits`](super::long::depth_digits)' two digits of `c = z + w` in
/// `0..=2w`, the first uncorrected (`estimate`: `r1 < 2w`, `c 2^8 = d1 w +
/// r1` all the same), the second's dividend below `w 514` and so below
/// 2^32 (`RECIP_W`).
#[inline(always)]
fn depth_recip(f: &Recip16, z: i32, w: u32) -> u32 {
    let c = (z + w as i32) as u32;
    let (d1, r1) = f.estimate(c << 8);
    let (d0, _) = f.digit((r1 << 8) + (2 * w - c));
    depth_of_digits(d1, d0)
}

/// [`Viewport::project_recip`] takes `w` below this: below `2^23` (its
/// logarithm's table) and such that `514 w < 2^32`, the bound of depth's
/// second dividend after an uncorrected first digit.
pub(super) const RECIP_W: u32 = u32::MAX / 514;
