//! A 16-bit reciprocal of a divisor below 2^21 and the long divisions
//! by its digits: ARMv6-M's division, which has no divide instruction and
//! no 32 x 32 -> 64-bit multiply, in 16 x 16 -> 32-bit products. The small
//! triangles' set-up (`shade::small`), the vertex stage's `w`
//! (`math::divisor`'s `Short`) and the scanline walk's small quotients use
//! it.

use core::num::NonZeroU32;

/// A divisor `d` (`1 <= d < 2^21`) and its 16-bit reciprocal, for
/// quotients of at most 12 bits ([`Recip16::digit`]): per triangle a
/// table look-up and one Newton step ([`recip31`]), then per digit of a
/// long division two 16 x 16 -> 32-bit products (`MULS` on ARMv6-M) and
/// one correction, where ARMv6-M's library division
/// (`__aeabi_uidivmod`) takes about a hundred instructions.
///
/// With `2^t <= d < 2^(t + 1)`, `r` approximates `E = 2^(t + 16) / d`
/// (in `(2^15, 2^16]`) from below, `0 <= E - r < 5.1`: for `t <= 15`,
/// `E = 2^31 / D` for `D = d 2^(15 - t)`, which [`recip31`] approximates
/// within 3.1; else `D = d' + 1` for `d`'s upper 16 bits
/// `d' = floor(d / 2^(t - 15))` (`2^16 - 1` for `2^16`, whose reciprocal
/// from below, at most `2^15`, is still below `E`). Then
/// `d' 2^(t - 15) <= d < (d' + 1) 2^(t - 15)` puts `E` between
/// `2^31 / (d' + 1)` and `2^31 / d'`, less than
/// `2^31 / (d' (d' + 1)) < 2` apart (`d' >= 2^15`). For `t < 3`
/// (`d < 8`) `r` is stored times `2^(3 - t)`, so that every digit's
/// product drops the same 19 bits.
///
/// The same holds for any `d < 2^31` (`t <= 30`: `d'` and `r` are as
/// for `t = 16..=20`), with every `x < 2^32` of the range from `t = 19`
/// up: ARMv6-M's vertex stage builds `w`'s 32-bit reciprocal from such
/// digits (`math::divisor`'s `Short`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Recip16 {
    pub(crate) d: u32,
    pub(crate) r: u32,
    /// `s = max(t - 3, 0)`: the dividend's bits dropped before the product.
    s: u32,
}

impl Recip16 {
    /// `d`'s reciprocal, for `d < 2^31`.
    #[inline(always)]
    pub(crate) fn new(d: NonZeroU32) -> Self {
        Self::with_log2(d, 31 - leading_zeros(d))
    }

    /// [`Recip16::new`] for `d < 2^21` (twice a small triangle's area),
    /// its logarithm by [`log2_small`]'s table rather than a search of
    /// five steps: ARMv6-M `demo` 7,632,901 -> 7,614,948 instructions,
    /// `rock` 6,330,524 -> 6,317,065 (the set-up), and 7,610,103,
    /// 6,313,649 with the scanline walk's divisions.
    #[inline(always)]
    pub(crate) fn new_small(d: NonZeroU32) -> Self {
        Self::with_log2(d, log2_small(d))
    }

    /// A reciprocal of `d < 2^23` (the vertex stage's `w` on ARMv6-M)
    /// with [`Recip16::new`]'s bounds, for [`Recip16::digit`]. Below
    /// `2^15`, [`Recip16::new`]'s, its logarithm by [`log2_w23`]'s table
    /// rather than [`leading_zeros`]' search of five steps; from `2^15` up
    /// (nearly every `w`: half a unit), `k = t - 15` is [`LOG2`] of `d`'s
    /// bits 15 to 22 alone and `r` is [`recip31_next`] of `d' = floor(d /
    /// 2^k)`: no search of the byte, no branch on `t <= 15` and no clamp of
    /// `d' + 1`. For `t = 15` that is `d + 1`'s reciprocal rather than
    /// `d`'s, below `E` by less than `2^31 / (d (d + 1)) + 3.1 < 5.1`, the
    /// bound of `t >= 16`. ARMv6-M `demo` 6,630,124 to 6,599,789
    /// instructions (vertex 896,052 to 865,717).
    #[inline(always)]
    pub(crate) fn new_w23(d: NonZeroU32) -> Self {
        let v = d.get();
        debug_assert!(v < 1 << 23);
        if v >> 15 == 0 {
            return Self::with_log2(d, log2_w23(d));
        }
        Self::new_w15(v)
    }

    /// [`Recip16::new_w23`] of `d` from `2^15` up (below `2^23`): its
    /// second branch alone, for ARMv6-M's vertex loop, whose inline path
    /// takes only such a `w` (`Viewport::project_recip_fast`). `d` as a
    /// plain word (it is at least `2^15`): a `NonZeroU32` made from it
    /// cost that loop a test of `w` against 0.
    #[inline(always)]
    pub(crate) fn new_w15(v: u32) -> Self {
        debug_assert!(v >> 15 != 0 && v < 1 << 23);
        // Masked: the optimiser then knows both shifts below 32 (`k <= 7`).
        let k = LOG2[(v >> 15) as usize & 0xff] as u32 & 7;
        Self {
            d: v,
            r: recip31_next(v >> k),
            s: k + 12,
        }
    }

    /// [`Recip16::new`] given `t = floor(log2(d))`.
    #[inline(always)]
    fn with_log2(d: NonZeroU32, t: u32) -> Self {
        Self::of_log2(d.get(), t)
    }

    /// [`Recip16::with_log2`] of a `d` known not to be 0 (`floor(log2(d))
    /// = t`).
    #[inline(always)]
    fn of_log2(d: u32, t: u32) -> Self {
        let r = if t <= 15 {
            recip31(d << (15 - t)) << 3u32.saturating_sub(t)
        } else {
            // (d' + 1 = 2^16 as 2^16 - 1: see `recip31`.)
            recip31(((d >> (t - 15)) + 1).min(0xffff))
        };
        Self {
            d,
            r,
            // Masked (`t < 31`: the same value), so that the optimiser
            // knows the shift below 32 and each digit's shift by it needs
            // no mask of its own (ARMv6-M: two instructions a digit).
            s: t.saturating_sub(3) & 31,
        }
    }

    /// The reciprocal of `d 2^k` for `d < 2^20`, `k = 19 - t`
    /// (`t = floor(log2(d))`), and `k`: the divisor scaled into
    /// `2^19..2^20`, so that every digit drops the same 16 bits of its
    /// dividend ([`Recip16::estimate16`], a constant shift where
    /// [`Recip16::estimate`] shifts by the field `s`, which ARMv6-M holds
    /// in a register or reloads). A quotient by `d` is the same by
    /// `d 2^k` of the dividend times `2^k`. From `2^20` up (`k = 0`),
    /// [`Recip16::new_small`]'s reciprocal of `d` itself, which
    /// `estimate16` does not take.
    #[inline(always)]
    pub(crate) fn new_scaled(d: NonZeroU32) -> (Self, u32) {
        let t = log2_small(d);
        if t >= 20 {
            return (Self::with_log2(d, t), 0);
        }
        let k = 19 - t;
        // In 2^19..2^20 (not 0): `s = 16`.
        (Self::of_log2(d.get() << k, 19), k)
    }

    /// [`Recip16::estimate`] of a divisor in `2^19..2^20`
    /// ([`Recip16::new_scaled`]'s, `s = 16`): the same estimate, its
    /// shift a constant.
    #[inline(always)]
    pub(crate) fn estimate16(&self, x: u32) -> (u32, u32) {
        debug_assert_eq!(self.s, 16);
        let q = ((x >> 16) * self.r) >> 19;
        (q, x - q * self.d)
    }

    /// `(floor(x / d), x mod d)` for `x < 2^(t + 13)`, which every `x`
    /// up to `d 2^12` is.
    ///
    /// For `t >= 3`, the estimate `q' = floor(xh r / 2^19)` of the
    /// dividend's upper bits `xh = floor(x / 2^s)` (below 2^16, so with
    /// `r <= 2^16` the product fits `u32`): with `x = xh 2^s + xl`,
    /// `x / d = xh E / 2^19 + xl / d`, so `x / d - xh r / 2^19 =
    /// xh (E - r) / 2^19 + xl / d`, at least 0 and below
    /// `2^16 5.1 / 2^19 + 2^s / 2^t < 0.64 + 1/8`. For `t < 3`,
    /// `q' = floor(x r / 2^19)` with `r <= E 2^(3 - t) = 2^19 / d` (the
    /// product is below `2^(t + 13) 2^19 / 2^t = 2^32`), and
    /// `x / d - x r / 2^19 = x 2^(3 - t) (E - r / 2^(3 - t)) / 2^19`,
    /// below `2^(t + 13 + 3 - t - 19) 3.1 < 0.39`. The estimate is thus
    /// `floor(x / d)` or one less: its remainder `x - q' d` (no wrap:
    /// `q' d <= x`) is below `2 d`, and one compare corrects both.
    #[inline(always)]
    pub(crate) fn digit(&self, x: u32) -> (u32, u32) {
        let (q, rem) = self.estimate(x);
        if rem >= self.d {
            (q + 1, rem - self.d)
        } else {
            (q, rem)
        }
    }

    /// [`Recip16::digit`] without its correction: `(q', x - q' d)` with
    /// `q'` either `floor(x / d)` or one less, so the remainder is in
    /// `0..2d`, for any `x < d (2^12 + 1)` (a little beyond `digit`'s
    /// range: a dividend made from an uncorrected remainder, `r 2^11 +
    /// d / 2` with `r < 2d`).
    ///
    /// The bounds of `digit`'s proof, for `x < d (2^12 + 1) < 2^(t + 13)
    /// + 2^(t + 1)`: for `t >= 3`, `xh < 2^16 + 2^4`, so the estimate is
    /// below `x / d` by less than `(2^16 + 2^4) 5.1 / 2^19 + 1/8 < 0.77`;
    /// for `t < 3`, by less than `(2^16 + 2^4) 3.1 / 2^19 < 0.39`. The
    /// product stays below 2^32: `xh r <= x 2^19 / d < (2^12 + 1) 2^19`.
    #[inline(always)]
    pub(crate) fn estimate(&self, x: u32) -> (u32, u32) {
        let q = ((x >> self.s) * self.r) >> 19;
        (q, x - q * self.d)
    }
}

/// `d.leading_zeros()`; on ARMv6-M, which has no `CLZ`, by a binary
/// search inline ([`leading_zeros_search`]) rather than the library's
/// `__clzsi2` call: about 73,000 instructions off the `demo` frame.
#[inline(always)]
pub(crate) fn leading_zeros(d: NonZeroU32) -> u32 {
    if cfg!(microraster_narrow_multiply) {
        leading_zeros_search(d)
    } else {
        d.leading_zeros()
    }
}

/// `d.leading_zeros()` by five compares and shifts: with `x = d 2^n`, a
/// step of `s` bits shifts when `x`'s top `s` bits are clear (so `d`'s
/// top bit stays within `x`'s top `s` bits after each step).
#[inline(always)]
pub(crate) fn leading_zeros_search(d: NonZeroU32) -> u32 {
    let (mut x, mut n) = (d.get(), 0);
    for s in [16, 8, 4, 2, 1] {
        if x >> (32 - s) == 0 {
            x <<= s;
            n += s;
        }
    }
    n
}

/// `floor(log2(i))` for `i` in `1..256` (0 for 0).
const LOG2: [u8; 256] = {
    let mut t = [0; 256];
    let mut i = 2;
    while i < 256 {
        t[i] = t[i / 2] + 1;
        i += 1;
    }
    t
};

/// `floor(log2(d))` for `d < 2^21`, from [`LOG2`] by the byte that holds
/// `d`'s top bit (`d`'s bits 13 to 20, 5 to 12 or 0 to 7): two compares
/// and one load, where ARMv6-M's search ([`leading_zeros_search`]) takes
/// five steps.
#[inline(always)]
fn log2_small(d: NonZeroU32) -> u32 {
    let d = d.get();
    debug_assert!(d < 1 << 21);
    // The byte's place alone chosen, then one shift by it: one value
    // out of the branches where there were two.
    let base = if d >> 13 != 0 {
        13
    } else if d >> 5 != 0 {
        5
    } else {
        0
    };
    base + LOG2[(d >> base) as usize & 0xff] as u32
}

/// `floor(log2(d))` for `d < 2^23`, as [`log2_small`] by the byte that
/// holds `d`'s top bit (`d`'s bits 15 to 22, 7 to 14 or 0 to 7).
#[inline(always)]
fn log2_w23(d: NonZeroU32) -> u32 {
    let d = d.get();
    debug_assert!(d < 1 << 23);
    let base = if d >> 15 != 0 {
        15
    } else if d >> 7 != 0 {
        7
    } else {
        0
    };
    base + LOG2[(d >> base) as usize & 0xff] as u32
}

/// `floor(2^31 / (2^15 + (i + 1) 2^7))` for `i` in `0..256`: [`recip31`]'s
/// first estimate, from below, for the 16-bit divisors whose upper 9 bits
/// are `2^8 + i`.
const RECIP_SEED: [u16; 256] = {
    let mut t = [0; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = ((1u32 << 31) / ((1 << 15) + (i as u32 + 1) * 128)) as u16;
        i += 1;
    }
    t
};

/// A reciprocal `r` of `D` (`2^15 <= D < 2^16`) from below:
/// `r <= E0 = 2^31 / D` and `E0 - r < 3.1`, without a division
/// ([`Recip16::new`]: ARMv6-M's is a library call).
///
/// The seed `r0` ([`RECIP_SEED`]) is `2^31 / D'` floored for the end `D'`
/// of `D`'s bucket of 2^7, so `E0 - r0 < 2^31 2^7 / D^2 + 1 <= 257`. One
/// Newton step from below: `e = 2^31 - D r0 = D (E0 - r0)` (below 2^25,
/// and no wrap), `r = r0 + floor(r0 floor(e / 2^9) / 2^22)`; without
/// the truncations `E0 - r = (E0 - r0)^2 / E0 <= 257^2 / 2^15 < 2.02`,
/// and they lower `r` by less than `1 + 2^16 / 2^22`: never above `E0`,
/// below it by less than 3.1 (the tests check every `D`). Every product
/// is of 16-bit factors.
#[inline(always)]
pub(crate) fn recip31(d: u32) -> u32 {
    newton31(seed31(d), d)
}

/// [`RECIP_SEED`]'s seed for `d`'s bucket of 2^7.
#[inline(always)]
fn seed31(d: u32) -> u32 {
    RECIP_SEED[(d >> 7) as usize & 0xff] as u32
}

/// One Newton step from below from the seed `r0` towards `2^31 / D`
/// (see [`recip31`]).
#[inline(always)]
fn newton31(r0: u32, d: u32) -> u32 {
    let e = (1u32 << 31) - d * r0;
    r0 + ((r0 * (e >> 9)) >> 22)
}

/// [`recip31`] of `D = d + 1` for `2^15 <= d < 2^16`, its seed chosen by
/// `d` (`D = 2^16` included): where `D` is the first of its bucket of 2^7,
/// `d`'s seed is `floor(2^31 / D)`, so `e = 2^31 - D r0 < D` and the step
/// adds `floor(r0 floor(e / 2^9) / 2^22) = 0` (`r0 e / 2^9 < 2^22`): `r
/// = floor(2^31 / D)` (for `D = 2^16`, `2^15` exactly; the product `D r0`
/// is `2^31`, no wrap). Otherwise `D` shares `d`'s bucket: `recip31(D)`.
#[inline(always)]
fn recip31_next(d: u32) -> u32 {
    newton31(seed31(d), d + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Recip16::estimate`] is `floor(x / d)` or one less for every
    /// divisor below 2^21 (all below 2^12, powers of two and their
    /// neighbours, random ones) and dividends up to its bound,
    /// `d (2^12 + 1) - 1`: small, at the multiples of `d`, random.
    #[test]
    fn estimates_are_the_quotient_or_one_less() {
        let mut next = crate::testing::rng();
        let mut divisors: heapless::Vec<u32, 4200> = (1..4096).collect();
        for k in 12..21 {
            for d in [(1u32 << k) - 1, 1 << k, (1 << k) + 1] {
                divisors.push(d).unwrap();
            }
        }
        for _ in 0..60 {
            divisors.push(1 + next((1 << 21) - 1) as u32).unwrap();
        }
        divisors.push((1 << 21) - 1).unwrap();
        for &d in &divisors {
            let f = Recip16::new(NonZeroU32::new(d).unwrap());
            let top = d as u64 * 4097 - 1;
            let check = |x: u64| {
                let x = x.min(top) as u32;
                let (q, rem) = f.estimate(x);
                let exact = x / d;
                assert!(q == exact || q + 1 == exact, "{x} / {d}: {q}");
                assert_eq!(q as u64 * d as u64 + rem as u64, x as u64);
                assert!(rem < 2 * d);
            };
            for x in [0, 1, 2, d as u64 - 1, d as u64, top - 1, top] {
                check(x);
            }
            for q in [1u64, 2, 2047, 2048, 4095, 4096, 4097] {
                for e in [0, 1, 2] {
                    check((q * d as u64).saturating_sub(e));
                    check(q * d as u64 + e);
                }
            }
            for _ in 0..200 {
                check(next(top + 1));
            }
        }
    }

    /// [`log2_small`] is `31 - leading_zeros` for every `d < 2^21`, so
    /// [`Recip16::new_small`] is [`Recip16::new`].
    #[test]
    fn small_logarithm_is_the_leading_zeros() {
        for d in 1u32..1 << 21 {
            let nz = NonZeroU32::new(d).unwrap();
            assert_eq!(log2_small(nz), 31 - d.leading_zeros(), "{d}");
        }
    }

    /// [`Recip16::new_w23`] has [`Recip16::new`]'s bounds for every `d <
    /// 2^23`: `s = max(t - 3, 0)`, and `r` at most `E = 2^(t + 16) / d` and
    /// above `E - 5.1` (scaled by `2^(3 - t)` below 8), so
    /// [`Recip16::digit`]'s proof holds.
    #[test]
    fn w23_reciprocal_has_the_bounds() {
        for d in 1u32..1 << 23 {
            let f = Recip16::new_w23(NonZeroU32::new(d).unwrap());
            let t = 31 - d.leading_zeros();
            assert_eq!(f.s, t.saturating_sub(3), "{d}");
            let (r, e) = (f.r as u64, 1u64 << (t.max(3) + 16));
            assert!(r * d as u64 <= e, "{d}: {r}");
            // r > E - 5.1 (times 2^(3 - t) below 8).
            let scale = 1u64 << 3u32.saturating_sub(t);
            assert!(
                10 * r * d as u64 + 51 * scale * d as u64 > 10 * e,
                "{d}: {r}"
            );
        }
    }

    /// [`log2_w23`] is `31 - leading_zeros` for every `d < 2^23`, so
    /// [`Recip16::new_w23`] is [`Recip16::new`].
    #[test]
    fn w23_logarithm_is_the_leading_zeros() {
        for d in 1u32..1 << 23 {
            let nz = NonZeroU32::new(d).unwrap();
            assert_eq!(log2_w23(nz), 31 - d.leading_zeros(), "{d}");
        }
    }
}
