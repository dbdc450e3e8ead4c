//! The projection in 64-bit words, where a 64-bit division is an
//! instruction (64-bit hosts).

use super::{Viewport, W_MIN};
use crate::raster::SubPoint;
use core::num::NonZeroU64;

impl Viewport {
    /// [`project_fast`](Self::project_fast) in 64-bit words, for any `w`
    /// from `W_MIN` up, where a 64-bit division is an instruction
    /// ([`WIDE_DIVISION`](super::WIDE_DIVISION)): the same three quotients by `2w` (depth's
    /// `floor(floor((c 65535 + w) / w) / 2)` is `floor((c 65535 + w) /
    /// (2w))`), whose numerators (below `2^50`) cannot overflow; `None`
    /// for a vertex outside the view volume. The general projection's
    /// sign tests, clamp and `w`'s divisor took x86-64 about 20
    /// instructions a vertex more, besides the outcode.
    #[inline(always)]
    pub(crate) fn project_fast_wide(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        self.project_fast_words(&p.map(i64::from))
    }

    /// [`project_fast_wide`](Self::project_fast_wide) of clip coordinates
    /// given as 64-bit words, each within `i32` (x86-64's common vertex
    /// loop, whose transform sums in 64 bits: from 32-bit words it
    /// sign-extended each again).
    #[inline(always)]
    pub(crate) fn project_fast_words(&self, p: &[i64; 4]) -> Option<(SubPoint, u32)> {
        debug_assert!(p.iter().all(|&v| i32::try_from(v).is_ok()));
        let w = p[3];
        if w < W_MIN {
            return None;
        }
        // At least 2 W_MIN: not zero (the compiler does not see it). The
        // `xor` with zero keeps LLVM's 32-bit test off the three
        // divisions (see `hash`).
        let w2n = NonZeroU64::new(((w as u64) << 1) ^ self.hash())?;
        let w2 = w2n.get();
        // `v + w`, in `0..=2w` inside the view volume (a negative one
        // wraps above it).
        let c = [p[0], p[1], p[2]].map(|v| (v + w) as u64);
        if c[0] > w2 || c[1] > w2 || c[2] > w2 {
            return None;
        }
        let (tw, th) = ((self.half_w as u64) << 1, (self.half_h as u64) << 1);
        // w - s, for s = 1 where the coordinate is negative.
        let odd = |v: i64| (w + (v >> 63)) as u64;
        let x = (c[0] * tw + odd(p[0])) / w2n;
        let y = th - (c[1] * th + odd(p[1])) / w2n;
        let z = (c[2] * 65_535 + w as u64) / w2n;
        debug_assert!(z <= 65_535);
        Some((SubPoint::new(x as i32, y as i32), z as u32))
    }
}
