//! Exact division of many dividends by one divisor: the attribute set-up's
//! and the vertex stage's divisions, as each kind of core does them best.

use crate::math::Recip16;
use core::num::{NonZeroU32, NonZeroU64};

/// Exact integer division of many dividends by one divisor, through the
/// divisor's reciprocal: one 64-bit division up front, then per quotient a
/// multiply-high and one correction.
///
/// A 64-bit division is a slow library call on a 32-bit core (and the
/// Cortex-M0+ has no divider at all), while the 64 x 64 -> 128-bit
/// multiply-high is a handful of `umull`s. The quotients are exactly those
/// of the division: `r = floor((2^64 - 1) / d)` undershoots `2^64 / d` by
/// less than 2, so for `m < 2^63` the estimate `floor(m r / 2^64)`
/// undershoots `m / d` by less than 1 and is `floor(m / d)` or one less,
/// which the remainder test corrects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
pub(crate) struct Reciprocal {
    d: u64,
    r: u64,
}

#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
impl Reciprocal {
    /// The reciprocal of `d`: the general attribute set-up's, by
    /// [`max_div_long`] (the same as [`new_long`](Self::new_long)), whose
    /// divisors (twice the area of a triangle too large for the small
    /// set-up) are mostly above 2^16, where the reciprocal had been the
    /// 64-bit division's library call (and four 16-bit digits below):
    /// Cortex-M3 `fill`, whose quads all take the general set-up,
    /// 8,989,693 -> 8,854,413 instructions (14.63 -> 14.41 a pixel);
    /// `demo` 3,091,310 -> 3,091,525, `rock` 2,549,064 -> 2,549,075,
    /// `grid4` the same; Cortex-M4F `demo` 3,061,846 -> 3,061,859, `rock`
    /// +1; ARMv6-M (three library divisions below 2^16 where there were
    /// four) `demo` 6,250,433 -> 6,250,375, `rock` -2. The perspective
    /// set-up shares it: the M3's `demo-textured-lit` 7,190,948 ->
    /// 7,178,882, its shader fills 0.15 to 0.23 a fragment fewer. The
    /// OLED firmware +96 B (43,384 B).
    #[inline(always)]
    pub(crate) fn new(d: NonZeroU64) -> Self {
        Self::new_long(d)
    }

    /// The reciprocal of `d`, with the 64-bit division of divisors from
    /// 2^16 up done by long division in 32-bit steps ([`max_div_long`]):
    /// for the vertex stage's `w`, mostly of 2^16 to 2^22, and the
    /// attribute set-up's twice the area ([`new`](Self::new)).
    #[inline(always)]
    pub(crate) fn new_long(d: NonZeroU64) -> Self {
        Self {
            d: d.get(),
            r: max_div_long(d),
        }
    }

    /// `floor(m / d)`, for `m < 2^63`.
    #[inline(always)]
    pub(crate) fn div(&self, m: u64) -> u64 {
        debug_assert!(m < 1 << 63);
        let q = ((m as u128 * self.r as u128) >> 64) as u64;
        // q <= floor(m / d), so q d <= m and the remainder cannot wrap.
        let rem = m - q * self.d;
        q + (rem >= self.d) as u64
    }

    /// [`div`](Self::div) with its products from 32-bit halves on ARMv6-M
    /// (see `math::wide`); the same quotient. For the vertex stage's
    /// projection, where that took about 470,000 instructions off the
    /// `demo` frame on ARMv6-M; the attribute set-up keeps `div`, which
    /// measured faster there (its numerators are often narrower).
    #[inline(always)]
    pub(crate) fn div_split(&self, m: u64) -> u64 {
        debug_assert!(m < 1 << 63);
        let q = super::wide::mul_high_u64(m, self.r);
        // As in `div`: q d <= m, the low 64 bits are the product.
        let rem = m - super::wide::mul_low_u64(q, self.d);
        q + (rem >= self.d) as u64
    }
}

/// `floor((2^64 - 1) / d)` by long division in 32-bit steps where the
/// 64-bit division is a library call (about 190 instructions on a
/// Cortex-M3): the upper
/// word of the quotient is `floor((2^32 - 1) / d)`, the lower one comes
/// from its remainder in digits of `k` bits, `k` the leading zeros of `d`
/// (so every partial dividend `rem 2^k + (2^k - 1)`, with `rem < d`, fits
/// `u32`). That is three divisions below 2^16 (two 16-bit digits), up to
/// four below 2^21, a single instruction each on a Cortex-M3/M4. The
/// quotient is the same. Divisors of 2^28 and more (seven or more digits)
/// keep the 64-bit division, and so does ARMv6-M from 2^16 up: there each
/// 32-bit division is a call of about 110 instructions too, and the
/// `demo` frame's vertex stage measured 54,000 instructions slower.
#[inline(always)]
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
pub(crate) fn max_div_long(d: NonZeroU64) -> u64 {
    let limit = if super::wide::SPLIT { 1 << 16 } else { 1 << 28 };
    match u32::try_from(d.get()) {
        Ok(small) if small < limit => {
            // `small` is d, not zero.
            let d = core::num::NonZeroU32::new(small).unwrap_or(core::num::NonZeroU32::MIN);
            let high = u32::MAX / d;
            let mut rem = u32::MAX - high * d.get();
            // The next digit, of `s` bits (1 <= s < 32): rem < d <
            // 2^(32 - s), so the partial dividend fits u32 and its
            // quotient is below 2^s.
            let mut digit = |s: u32| {
                let part = (rem << s) | (u32::MAX >> (32 - s));
                let digit = part / d;
                rem = part - digit * d.get();
                digit
            };
            let low = if small < 1 << 16 {
                // Two digits, without the loop.
                let top = digit(16);
                top << 16 | digit(16)
            } else {
                // 4..=15 bits a digit.
                let k = small.leading_zeros();
                let (mut low, mut left) = (0u32, 32u32);
                while left > 0 {
                    let s = k.min(left);
                    low = (low << s) | digit(s);
                    left -= s;
                }
                low
            };
            (high as u64) << 32 | low as u64
        }
        _ => u64::MAX / d,
    }
}

/// Long division by `d` carried on over `left` more zero bits of the
/// dividend: with `q` the quotient so far and `r < d` its remainder, the
/// quotient and remainder once `left` zero bits are brought down, in
/// digits of as many bits as `d` has leading zeros (so every partial
/// dividend `r 2^s < d 2^s` fits `u32`). The caller keeps the quotient
/// below 2^32.
#[inline(always)]
pub(crate) fn shift_in_zeros(mut q: u32, mut r: u32, d: NonZeroU32, mut left: u32) -> (u32, u32) {
    let k = d.leading_zeros();
    while left > 0 {
        let s = k.min(left);
        let part = r << s;
        let digit = part / d;
        r = part - digit * d.get();
        q = (q << s) | digit;
        left -= s;
    }
    (q, r)
}

/// The vertex stage's divisor `w` on ARMv6-M: [`Short`]'s 32-bit
/// reciprocal when it applies (`8 <= w < 2^31` and the dividend below
/// `2^(30 + bits of w)`: every vertex inside the guard band), else
/// [`Reciprocal`]'s out of line. Without a 32 x 32 -> 64-bit multiply,
/// `Short`'s three products a quotient cost much less than the seven of
/// [`Reciprocal::div_split`]; on the Cortex-M3, whose `umlal` makes the
/// 64-bit multiply-high cheap, it measured slower (see `Viewport::project`).
/// The quotients are the same.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
pub(crate) struct ShortOrLong {
    d: NonZeroU64,
    short: Option<Short>,
}

#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
impl ShortOrLong {
    /// The divisor `d`.
    #[inline(always)]
    pub(crate) fn new_long(d: NonZeroU64) -> Self {
        Self {
            d,
            short: Short::new(d),
        }
    }

    /// `floor(m / d)`, for `m < 2^63`.
    #[inline(always)]
    pub(crate) fn div_split(&self, m: u64) -> u64 {
        match self.short {
            Some(s) if m >> s.bits == 0 => s.div(m) as u64,
            _ => div_long(self.d, m),
        }
    }
}

/// `floor(m / d)` outside [`Short`]'s range, through [`Reciprocal`].
#[inline(never)]
#[cold]
#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
fn div_long(d: NonZeroU64, m: u64) -> u64 {
    Reciprocal::new_long(d).div_split(m)
}

/// Exact division by `d` (`8 <= d < 2^31`, of `l` bits) of dividends below
/// `2^K`, `K = 30 + l`, through the 32-bit reciprocal `r = floor(2^K / d)
/// <= 2^31`: per quotient two 32 x 32 -> 64-bit products for the estimate
/// `floor(m r / 2^K)` and one for the correction, where [`Reciprocal`]'s
/// 64-bit multiply-high takes four and its remainder three. The estimate
/// undershoots `m / d` by less than `m / 2^K < 1` (as `r > 2^K / d - 1`)
/// and never overshoots it, so it is `floor(m / d)` or one less, which the
/// remainder test corrects. The reciprocal itself is a long division of
/// `2^K` in digits of [`Recip16`] (a table look-up, a Newton step, then
/// per digit two `MULS` and one correction), where ARMv6-M's library
/// division took about a hundred instructions a digit: see [`Short::new`].
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
struct Short {
    d: u32,
    r: u32,
    /// `K`.
    bits: u32,
}

#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
impl Short {
    /// `d`'s reciprocal, if `8 <= d < 2^31`.
    ///
    /// With `t = l - 1` (3..=30), `K = 31 + t`. The long division of
    /// `2^K` by `d` starts from the partial dividend `2^a`, `a = min(31,
    /// t + 12)` (within [`Recip16::digit`]'s range `2^(t + 13)` and
    /// `u32`), then brings down the other `K - a` zero bits in digits of
    /// `min(12, 31 - t)` bits: each partial dividend `rem 2^s < d 2^s <
    /// 2^(t + 1 + s)` fits `u32` and the digit's range. Three digits for
    /// `d` below 2^21, four up to 2^23. The quotient is exactly
    /// `floor(2^K / d)`, as the library's division gave.
    #[inline(always)]
    fn new(d: NonZeroU64) -> Option<Self> {
        let d = u32::try_from(d.get())
            .ok()
            .filter(|d| (8..1 << 31).contains(d))?;
        let nz = core::num::NonZeroU32::new(d)?;
        // k in 1..=28, t in 3..=30.
        let k = crate::math::leading_zeros(nz);
        let t = 31 - k;
        let f = Recip16::new(nz);
        let a = 31.min(t + 12);
        let (mut r, mut rem) = f.digit(1 << a);
        let s = 12.min(k);
        let mut left = 31 + t - a;
        while left > 0 {
            let s = s.min(left);
            let (digit, next) = f.digit(rem << s);
            // r stays below 2^32 (r <= 2^31 at the end).
            r = (r << s) | digit;
            rem = next;
            left -= s;
        }
        Some(Self { d, r, bits: 62 - k })
    }

    /// `floor(m / d)`, for `m < 2^K`.
    #[inline(always)]
    fn div(&self, m: u64) -> u32 {
        // Only ARMv6-M divides here: its products from 16-bit halves.
        use super::wide::mul_split_u as mul_wide_u;
        debug_assert!(m >> self.bits == 0);
        // m r = (mh r + (ml r >> 32)) 2^32 + (ml r mod 2^32); K >= 34, so
        // the low word cannot carry into floor(m r / 2^K). mh < 2^29 and
        // r <= 2^31: t < 2^61.
        let (mh, ml) = ((m >> 32) as u32, m as u32);
        let t = mul_wide_u(mh, self.r) + (mul_wide_u(ml, self.r) >> 32);
        // The estimate is at most m / d < 2^K / 2^(l - 1) = 2^31, so its
        // bits come from t's two words, shifted by 2..=29 and 3..=30.
        let s = self.bits - 32;
        let q = (t as u32 >> s) | ((t >> 32) as u32) << (32 - s);
        // q d <= m: the remainder cannot wrap.
        let rem = m - mul_wide_u(q, self.d);
        q + (rem >= self.d as u64) as u32
    }
}

/// A divisor used for many dividends, divided by as a 64-bit CPU does best:
/// with its division instruction.
///
/// Divided by as `d ^ mask`, with `d` and `mask` such that LLVM cannot
/// fold the `xor` away: LLVM guards a 64-bit division on x86-64 (its
/// `idivq-to-divl` tuning) with a test whether both operands fit 32 bits,
/// taking the shorter `div` then (an `or`, a shift, a branch and a jump a
/// division), but not when an operand is the result of an `xor`, which it
/// takes for a hash, too wide for the test to pay. The divisions of one
/// divisor share the `xor`. [`new`](Self::new) (the attribute set-up's
/// eight divisions) holds `d ^ 2^30` through `black_box` and `2^30`;
/// [`new_long`](Self::new_long) (the vertex stage's three) holds `d` and
/// an atomic zero ([`ZERO`], a plain load), which measured cheaper there
/// and dearer in the set-up (register allocation; again so in the offset
/// set-up: x86-64 `demo` 3,052,140 -> 3,053,796). x86-64 `demo`
/// 4,430,827 -> 4,356,901 instructions (the set-up) and 4,331,822 ->
/// 4,323,714 (the vertex stage). The mask `2^30` rather than `2^63`: an
/// immediate operand, where `2^63` took a 64-bit constant built in a
/// register for the `xor` and for the division's test of a zero divisor
/// (`demo` 3,052,140 -> 3,045,438, `rock` 2,541,971 -> 2,536,724).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
pub(crate) struct Hardware {
    /// The divisor, `xor`-ed with `mask`.
    d: u64,
    /// What `d` is `xor`-ed with.
    mask: u64,
}

/// Equal when the divisors are, however held.
impl PartialEq for Hardware {
    fn eq(&self, other: &Self) -> bool {
        self.d ^ self.mask == other.d ^ other.mask
    }
}

impl Eq for Hardware {}

/// See [`Hardware`]: always zero (a plain load on x86-64).
#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
static ZERO: core::sync::atomic::AtomicUsize = core::sync::atomic::AtomicUsize::new(0);

#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
impl Hardware {
    /// The divisor `d`.
    #[inline(always)]
    pub(crate) fn new(d: NonZeroU64) -> Self {
        const HASH: u64 = 1 << 30;
        Self {
            d: core::hint::black_box(d.get() ^ HASH),
            mask: HASH,
        }
    }

    /// The same as [`new`](Self::new) (see [`Reciprocal::new_long`]).
    #[inline(always)]
    pub(crate) fn new_long(d: NonZeroU64) -> Self {
        Self {
            d: d.get(),
            mask: ZERO.load(core::sync::atomic::Ordering::Relaxed) as u64,
        }
    }

    /// `floor(m / d)`.
    #[inline(always)]
    pub(crate) fn div(&self, m: u64) -> u64 {
        // Never zero: `d` was not, and `mask` is. (A zero would only
        // panic.)
        m / (self.d ^ self.mask)
    }

    /// The same as [`div`](Self::div) (see [`Reciprocal::div_split`]).
    #[inline(always)]
    pub(crate) fn div_split(&self, m: u64) -> u64 {
        self.div(m)
    }
}

/// The divisor the attribute set-up uses: [`Reciprocal`] where a 64-bit
/// division is a library call (32-bit targets: every Cortex-M, RISC-V
/// `rv32`), the division instruction on 64-bit targets, where one
/// instruction beats a multiply-high and a correction. Both give the same
/// quotients, so images do not depend on the choice.
#[cfg(not(target_pointer_width = "64"))]
pub(crate) type Divisor = Reciprocal;
/// See the 32-bit definition.
#[cfg(target_pointer_width = "64")]
pub(crate) type Divisor = Hardware;

/// The vertex stage's divisor `w`: [`ShortOrLong`] on cores without a
/// 32 x 32 -> 64-bit multiply (ARMv6-M, ARMv8-M Baseline:
/// `microraster_narrow_multiply`), else [`Divisor`] (both through
/// `new_long` and `div_split`).
#[cfg(microraster_narrow_multiply)]
pub(crate) type WDivisor = ShortOrLong;
/// See the narrow-multiply definition.
#[cfg(not(microraster_narrow_multiply))]
pub(crate) type WDivisor = Divisor;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_div_long_is_the_64_bit_quotient() {
        for d in (1u64..=70_000).chain([u32::MAX as u64, 1 << 40, u64::MAX]) {
            let nz = NonZeroU64::new(d).unwrap();
            assert_eq!(max_div_long(nz), u64::MAX / d, "{d}");
        }
        // Every digit width, around each power of two, and at random.
        for b in 16..64 {
            for d in (1u64 << b) - 300..=(1u64 << b).saturating_add(300) {
                let nz = NonZeroU64::new(d).unwrap();
                assert_eq!(max_div_long(nz), u64::MAX / d, "{d}");
            }
        }
        let mut next = crate::testing::rng();
        for _ in 0..2_000_000 {
            let d = ((next(1 << 32) << 32 | next(1 << 32)) >> next(64)).max(1);
            let nz = NonZeroU64::new(d).unwrap();
            assert_eq!(max_div_long(nz), u64::MAX / d, "{d}");
        }
    }

    /// The vertex stage's quotients through the 32-bit reciprocal and
    /// through its fallback ([`ShortOrLong`]) against the division: every
    /// divisor below 70,000 and around every power of two, dividends at
    /// and near the limit `2^(30 + l)` and at random.
    #[test]
    fn short_quotients_are_exact() {
        let mut next = crate::testing::rng();
        let check = |d: u64, r: u64, e: u64| {
            let nz = NonZeroU64::new(d).unwrap();
            let l = 64 - d.leading_zeros();
            let limit = 1u64 << (30 + l).min(62);
            let s = ShortOrLong::new_long(nz);
            for m in [
                0,
                1,
                d - 1,
                d,
                d + 1,
                limit - 1,
                limit,
                limit.saturating_sub(d),
                (1 << 62) - 1,
                r % limit,
                r >> (1 + e),
            ] {
                assert_eq!(s.div_split(m), m / d, "{m} / {d}");
            }
        };
        for d in 1..70_000 {
            check(d, next(1 << 32) << 32 | next(1 << 32), next(63));
        }
        for b in 17..63 {
            for d in (1u64 << b) - 200..=(1u64 << b) + 200 {
                check(d, next(1 << 32) << 32 | next(1 << 32), next(63));
            }
        }
        for _ in 0..100_000 {
            let d = (next(1 << 32) << 31 | next(1 << 31)) >> next(62) | 1;
            check(d, next(1 << 32) << 32 | next(1 << 32), next(63));
        }
    }

    /// [`Short`]'s reciprocal from [`Recip16`] digits is the 64-bit
    /// division's `floor(2^K / d)`: every divisor below 2^21 and around
    /// every power of two up to 2^31, and at random.
    #[test]
    fn short_reciprocal_is_the_quotient() {
        let check = |d: u32| {
            let s = Short::new(NonZeroU64::new(d as u64).unwrap()).unwrap();
            let bits = 62 - d.leading_zeros();
            assert_eq!((s.d, s.bits), (d, bits));
            assert_eq!(s.r as u64, (1u64 << bits) / d as u64, "{d}");
        };
        for d in 8..1 << 21 {
            check(d);
        }
        for b in 21..31 {
            for d in (1u32 << b) - 2_000..((1u64 << b) + 2_000).min((1 << 31) - 1) as u32 {
                check(d);
            }
        }
        check((1 << 31) - 1);
        let mut next = crate::testing::rng();
        for _ in 0..1_000_000 {
            check(((next(1 << 31) as u32) >> next(28)).max(8));
        }
    }

    #[test]
    fn reciprocal_division_is_exact() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let divisors = [
            1u64,
            2,
            3,
            7,
            255,
            65_535,
            1 << 20,
            (1 << 39) - 1,
            1 << 39,
            (1 << 62) + 12_345,
        ];
        for &d in &divisors {
            let r = Reciprocal::new(NonZeroU64::new(d).unwrap());
            for m in [0u64, 1, d - 1, d, d + 1, (1 << 63) - 1, (1 << 63) - d] {
                assert_eq!(r.div(m), m / d, "{m} / {d}");
            }
        }
        for _ in 0..200_000 {
            let d = next() >> (next() % 64);
            let Some(nz) = NonZeroU64::new(d) else {
                continue;
            };
            let (r, h) = (Reciprocal::new(nz), Hardware::new(nz));
            assert_eq!(Reciprocal::new_long(nz), r);
            assert_eq!(Hardware::new_long(nz), h);
            for _ in 0..4 {
                let m = next() >> (1 + next() % 63);
                assert_eq!(r.div(m), m / d, "{m} / {d}");
                assert_eq!(r.div_split(m), m / d, "{m} / {d}");
                assert_eq!(h.div(m), m / d, "{m} / {d}");
                assert_eq!(h.div_split(m), m / d, "{m} / {d}");
            }
        }
    }
}
