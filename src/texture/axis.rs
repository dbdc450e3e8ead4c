//! Texture addressing along one axis: a normalised coordinate to a texel
//! index under the wrap mode (repeat, mirrored repeat, clamp), and the two
//! taps and the weight of bilinear filtering. A power-of-two size masks
//! and shifts; any other size divides once per sample.

use super::{Wrap, HALF, WEIGHT_BITS};

/// The addressing of one axis: its size and wrap mode, and whether the size
/// is a power of two (then `log2` is its exponent, and `shift` is
/// `16 - log2`, stored so nearest sampling need not subtract), decided once.
#[derive(Clone, Copy, Debug)]
pub(super) struct Axis {
    pub(super) size: u32,
    pub(super) log2: u8,
    pub(super) shift: u8,
    pub(super) pow2: bool,
    pub(super) wrap: Wrap,
}

impl Axis {
    pub(super) const fn new(size: u32) -> Self {
        Self {
            size,
            log2: size.trailing_zeros() as u8,
            // Only used for powers of two, where `log2 <= 15`.
            shift: 16u32.saturating_sub(size.trailing_zeros()) as u8,
            pow2: size.is_power_of_two(),
            wrap: Wrap::Repeat,
        }
    }

    /// `floor(u · size) mod size`, for `u` with raw 16.16 bits `raw`.
    #[inline(always)]
    pub(super) fn repeat(self, raw: i32) -> u32 {
        if self.pow2 {
            // The arithmetic shift is `floor(u · 2^log2)`.
            (raw >> self.shift) as u32 & (self.size - 1)
        } else {
            // `floor(u · size) = floor(u) · size + floor(frac(u) · size)`,
            // and the second term is already in `0..size`. The product is
            // below 2^16 · 2^15.
            ((raw as u32 & 0xFFFF) * self.size) >> 16
        }
    }

    /// The texel of [`Filter::Nearest`](super::Filter::Nearest): `floor(u · size)` mapped by the
    /// wrap mode.
    #[inline(always)]
    pub(super) fn nearest(self, raw: i32) -> u32 {
        match self.wrap {
            Wrap::Repeat => self.repeat(raw),
            Wrap::MirroredRepeat => {
                let i = self.repeat(raw);
                // Copies with odd `floor(u)` (bit 16) are the mirrored ones.
                if raw & 0x1_0000 != 0 {
                    self.size - 1 - i
                } else {
                    i
                }
            }
            // `u` clamped to `[0, 1)` gives the same texel as `floor(u · size)`
            // clamped: 0xFFFF · size / 2^16 is just below `size`.
            Wrap::ClampToEdge => (raw.clamp(0, 0xFFFF) as u32 * self.size) >> 16,
        }
    }

    /// Mirrored repeat of texel coordinate `c` (taken modulo `2 · size`,
    /// which divides 2^32) for a power-of-two size.
    #[inline(always)]
    pub(super) fn mirror_pow2(self, c: u32) -> u32 {
        let flip = ((c >> self.log2) & 1).wrapping_neg();
        (c ^ flip) & (self.size - 1)
    }

    /// Mirrored repeat of texel coordinate `c` in `0..=2 · size` (any size).
    #[inline(always)]
    pub(super) fn mirror(self, c: u32) -> u32 {
        if c < self.size {
            c
        } else if c < 2 * self.size {
            2 * self.size - 1 - c
        } else {
            // `2 · size` is coordinate 0 of the next period.
            0
        }
    }

    /// The two texels of [`Filter::Bilinear`](super::Filter::Bilinear) and the weight of the second:
    /// `(i0, i1, fx)` with `s = u · size - ½`, `i0 = floor(s)` and
    /// `i1 = i0 + 1` mapped by the wrap mode, and `fx` the fraction of `s`
    /// in [`WEIGHT_BITS`] bits, truncated.
    ///
    /// Below, `j = i1 = floor(u · size + ½)` and `s + 1` is computed as
    /// `(j << 16) + fraction`, so no step needs a negative number.
    #[inline(always)]
    pub(super) fn taps(self, raw: i32) -> (u32, u32, u32) {
        let (i0, i1, frac) = match self.wrap {
            Wrap::Repeat | Wrap::MirroredRepeat if self.pow2 => {
                // Wrapping arithmetic is exact modulo 2^32, and both modes
                // only need `j` modulo `2 · size`, which divides 2^16.
                let s = ((raw as u32) << self.log2).wrapping_add(HALF);
                let j = s >> 16;
                let pair = if self.wrap == Wrap::Repeat {
                    let mask = self.size - 1;
                    (j.wrapping_sub(1) & mask, j & mask)
                } else {
                    (self.mirror_pow2(j.wrapping_sub(1)), self.mirror_pow2(j))
                };
                (pair.0, pair.1, s)
            }
            Wrap::Repeat => {
                // `u mod 1` shifts `s` by a multiple of `size`: the same
                // texels modulo `size`, the same fraction. Below 2^31 + 2^15.
                let s = (raw as u32 & 0xFFFF) * self.size + HALF;
                let j = s >> 16; // 0..=size
                let i0 = if j == 0 { self.size - 1 } else { j - 1 };
                let i1 = if j == self.size { 0 } else { j };
                (i0, i1, s)
            }
            Wrap::MirroredRepeat => {
                // `u mod 2` shifts `s` by a multiple of the period `2 · size`.
                // `t` is below 2^17 · 2^15 = 2^32, but `t + ½` may not be,
                // so the half is added to the fraction alone.
                let t = (raw as u32 & 0x1_FFFF) * self.size;
                let j = (t >> 16) + (((t & 0xFFFF) + HALF) >> 16); // 0..=2·size
                let i0 = if j == 0 { 0 } else { self.mirror(j - 1) };
                (i0, self.mirror(j), t.wrapping_add(HALF))
            }
            Wrap::ClampToEdge => {
                // Beyond `0..=1` both texels clamp to the same edge texel, as
                // they do at `u = 0` or `u = 1`, so clamping `u` first changes
                // nothing. At most 2^31 + 2^15.
                let s = raw.clamp(0, 0x1_0000) as u32 * self.size + HALF;
                let j = s >> 16; // 0..=size
                (j.saturating_sub(1), j.min(self.size - 1), s)
            }
        };
        (i0, i1, (frac & 0xFFFF) >> (16 - WEIGHT_BITS))
    }
}
