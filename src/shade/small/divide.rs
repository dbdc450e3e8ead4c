//! The divisions of a small triangle's set-up by twice its area (below
//! 2^21): long division in 32-bit steps, each one instruction on a
//! Cortex-M3/M4, by `Recip16` digits on ARMv6-M, or in `i32` when every
//! value fits; the quotients are [`Basis::div_round`](super::super::plane::Basis::div_round)'s.

use crate::math::Recip16;
use core::num::NonZeroU32;

/// What the `i32` set-up of a [`Small`] triangle shares
/// ([`TriangleSetup::small`](super::super::TriangleSetup::small)): the edge vectors `x1, y1, x2, y2` from
/// vertex 0 (not negated as [`Basis`](super::super::plane::Basis)'s: the divisor keeps its sign), the
/// offsets `ox, oy`, twice the signed area (neither 0 nor -1, at most
/// `2 * 1023^2` in magnitude) and half its magnitude.
pub(in crate::shade) struct SmallBasis<D = ShortDivisor> {
    pub(in crate::shade) e: [i32; 4],
    pub(in crate::shade) o: [i32; 2],
    pub(in crate::shade) area2: i32,
    pub(in crate::shade) half: i32,
    /// `|area2|` as the gradients divide by it where through a reciprocal
    /// (ARMv6-M: [`SmallBasis::div_round32`]): [`ShortDivisor`], or the
    /// area's own [`Recip16`] (the perspective set-up's depth plane,
    /// [`TriangleSetup::depth_small`](super::super::TriangleSetup::depth_small));
    /// unused elsewhere, where the optimiser drops it.
    pub(in crate::shade) divisor: D,
}

/// `d = |area2|` as ARMv6-M's gradients divide it
/// ([`SmallBasis::div_round32_short`]): the reciprocal of `d 2^k`, with
/// every dividend scaled by `2^k` (the same quotients, the remainders
/// times `2^k`). One type for each form of divisor, so that each set-up
/// holds only what its own digits read.
pub(in crate::shade) trait AreaDivisor {
    /// The reciprocal of `d 2^k`.
    fn recip(&self) -> &Recip16;
    /// The scale `k`.
    fn k(&self) -> u32;
    /// `floor(d / 2) 2^k`, given `half = floor(d / 2)` (the basis's).
    fn half(&self, half: u32) -> u32;
    /// [`SmallBasis::two_digit_bound`]: `d` below 2^20, else 0.
    fn bound(&self) -> u32;
    /// A digit's estimate ([`Recip16::estimate`]'s) of `x / (d 2^k)`.
    fn estimate(&self, x: u32) -> (u32, u32);
}

/// The divisor by its own reciprocal, unscaled (`k = 0`): the perspective
/// set-up's depth plane
/// ([`TriangleSetup::depth_small`](super::super::TriangleSetup::depth_small)),
/// which shares the area's reciprocal with its perspective planes (scaled
/// there, `demo-textured-lit` measured 12,423,162 -> 12,506,105). Half the
/// area is the basis's and the two-digit bound is made where it is used:
/// no value more live over the textured set-up than the reciprocal
/// (`demo-textured-lit` 12,460,060 -> 12,442,305 against a divisor that
/// held its own). The same machine code as the divisor with a run-time
/// `scaled` flag had, whose flag the optimiser folded here.
impl AreaDivisor for Recip16 {
    #[inline(always)]
    fn recip(&self) -> &Recip16 {
        self
    }

    #[inline(always)]
    fn k(&self) -> u32 {
        0
    }

    #[inline(always)]
    fn half(&self, half: u32) -> u32 {
        half
    }

    #[inline(always)]
    fn bound(&self) -> u32 {
        two_digit_bound_of(self.d)
    }

    #[inline(always)]
    fn estimate(&self, x: u32) -> (u32, u32) {
        Recip16::estimate(self, x)
    }
}

/// `d = |area2|` as ARMv6-M's Gouraud and flat gradients divide by it: the
/// reciprocal of `d 2^k`, scaled into `2^19..2^20`
/// ([`Recip16::new_scaled`]; `k = 0` and `d`'s own from `2^20` up), with
/// half the area scaled alike and the two-digit quotients' bound. The
/// dividends are scaled by `2^k` too (the same quotients, remainders
/// times `2^k`), so that every digit of the two-digit gradients drops a
/// constant 16 bits ([`Recip16::estimate16`]) where each shifted by a
/// variable `s`: a `MOV`, a shift and often a reload fewer a digit, and
/// one register fewer over the set-up.
#[derive(Clone, Copy, Debug, Default)]
pub(in crate::shade) struct ShortDivisor {
    pub(in crate::shade) recip: Recip16,
    /// The scale: `recip.d = d 2^k`.
    pub(in crate::shade) k: u32,
    /// `floor(d / 2) 2^k`.
    pub(in crate::shade) half: u32,
    /// [`SmallBasis::two_digit_bound`]: `d` below 2^20, else 0.
    pub(in crate::shade) bound: u32,
}

/// [`SmallBasis::two_digit_bound`] of the divisor `d`: `d` below 2^20,
/// where two digits of a gradient do not overflow, else 0.
#[inline(always)]
const fn two_digit_bound_of(d: u32) -> u32 {
    if d >> 20 == 0 {
        d
    } else {
        0
    }
}

impl ShortDivisor {
    /// The divisor `d` (below 2^21).
    #[inline(always)]
    pub(in crate::shade) fn new(d: NonZeroU32) -> Self {
        let (recip, k) = Recip16::new_scaled(d);
        let d = d.get();
        Self {
            recip,
            k,
            half: (d / 2) << k,
            bound: two_digit_bound_of(d),
        }
    }
}

impl AreaDivisor for ShortDivisor {
    #[inline(always)]
    fn recip(&self) -> &Recip16 {
        &self.recip
    }

    #[inline(always)]
    fn k(&self) -> u32 {
        self.k
    }

    #[inline(always)]
    fn half(&self, _: u32) -> u32 {
        self.half
    }

    #[inline(always)]
    fn bound(&self) -> u32 {
        self.bound
    }

    /// [`Recip16::estimate16`]: `d 2^k` is in `2^19..2^20` where it
    /// takes two digits.
    #[inline(always)]
    fn estimate(&self, x: u32) -> (u32, u32) {
        self.recip.estimate16(x)
    }
}

/// The divisor of a small triangle's gradients: twice its absolute area,
/// below `2 * SMALL_EDGE^2 = 2^21`.
#[derive(Clone, Copy, Debug)]
pub(in crate::shade) struct Small {
    pub(in crate::shade) area: NonZeroU32,
    pub(in crate::shade) half: u32,
}

impl Small {
    /// `n 2^shift / area` rounded to nearest, ties away from zero, for
    /// `|n| < 2^31` and `area < 2^21`: [`Basis::div_round`](super::super::plane::Basis::div_round)'s quotient, by
    /// long division in 32-bit steps of at most 10 bits. With
    /// `|n| = q area + r`, `|n| 2^10 = (q 2^10 + d) area + r'` for
    /// `d = floor(r 2^10 / area)`, and so on down the shift; every partial
    /// dividend is below `area 2^10 + half < 2^32`. Three divisions for
    /// the shifts of depth and colour (18 and 20), each one instruction on
    /// a Cortex-M3/M4.
    #[inline(always)]
    pub(in crate::shade) fn div_round(&self, n: i32, shift: u32) -> i64 {
        if cfg!(any(microraster_narrow_multiply, test)) {
            return self.div_round_digits(n, shift);
        }
        let d = self.area;
        let a = n.unsigned_abs();
        let mut q = (a / d) as u64;
        let mut r = a % d;
        let mut left = shift;
        while left > 10 {
            let part = r << 10;
            q = (q << 10) | (part / d) as u64;
            r = part % d;
            left -= 10;
        }
        let q = ((q << left) + (((r << left) + self.half) / d) as u64) as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    }
}

impl Small {
    /// [`Small::div_round`] by [`Recip16`] digits where a first digit
    /// `|n| / area` below 2^12 allows (ARMv6-M, whose division is a
    /// library call of about fifty instructions; also in the unit tests,
    /// which compare it with the 64-bit division): the general set-up of
    /// a small triangle that the `i32` one does not take (a sliver, a
    /// steep depth), about 20 a `demo` frame. Every later digit's
    /// dividend, `r 2^10` or `r 2^left + half` with `r < area`, is below
    /// `area (2^10 + 1)` and 2^32 (`area < 2^21`): within
    /// [`Recip16::digit`]'s range. The same quotient.
    #[inline(always)]
    pub(super) fn div_round_digits(&self, n: i32, shift: u32) -> i64 {
        let d = self.area;
        let f = Recip16::new_small(d);
        let a = n.unsigned_abs();
        let (q, mut r) = if a >> 12 < d.get() {
            f.digit(a)
        } else {
            (a / d, a % d)
        };
        let mut q = q as u64;
        let mut left = shift;
        while left > 10 {
            let (digit, rest) = f.digit(r << 10);
            q = (q << 10) | digit as u64;
            r = rest;
            left -= 10;
        }
        let q = ((q << left) + f.digit((r << left) + self.half).0 as u64) as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    }
}

impl<D: AreaDivisor> SmallBasis<D> {
    /// [`Small::div_round`] in `i32` arithmetic, for `-2^21 <= n < 2^21`,
    /// `shift` 18 or 20 (depth and colour) and a first digit
    /// `|n| 2^10 / area` of at most `2^(40 - shift)`, which keeps the
    /// quotient within `2^30 + 2^(shift - 10)` in magnitude (the callers
    /// check both bounds before).
    ///
    /// Two truncating signed divisions by the signed area (the divisor's
    /// sign is the quotient's, as `Basis`'s negated edge vectors make
    /// it): `n 2^10 = q area2 + r` with `r` of `n`'s sign and
    /// `|r| < |area2|`, then the last `shift - 10` bits from
    /// `r 2^(shift - 10)` plus half the area with `n`'s sign, whose
    /// truncated quotient is the rounded one's with the quotient's sign
    /// (ties away from zero). Against the unsigned digits of
    /// [`Small::div_round`] this spares each gradient the magnitude of its
    /// numerator and the quotient's negation, and the set-up the edge
    /// vectors' (a Cortex-M3's signed division is one instruction as the
    /// unsigned one).
    ///
    /// Where the division is a library call (ARMv6-M: no divider), the
    /// digits of the magnitudes by the area's reciprocal instead
    /// ([`SmallBasis::div_round32_short`]); the same quotient.
    #[inline(always)]
    pub(super) fn div_round32(&self, n: i32, shift: u32) -> i32 {
        if cfg!(microraster_narrow_multiply) {
            self.div_round32_short(n, shift)
        } else {
            self.div_round32_with::<true>(n, shift)
        }
    }

    /// [`SmallBasis::div_round32_short`] for `|n| < d 2^(23 - shift)` and
    /// `d < 2^20` ([`SmallBasis::two_digit_bound`]): its two digits (see
    /// there), the first left uncorrected.
    ///
    /// [`Recip16::estimate`]'s first digit `q0'` is `q0` or one less, its
    /// remainder `r0'` in `0..2d`; the second digit's dividend
    /// `r0' 2^11 + half` is then below `d (2^12 + 1)`, within the
    /// estimate's range (and below 2^32, as `d < 2^20`), so
    /// `|n| 2^shift + half = (q0' 2^11 + q1') d + r1'` with `r1'` in
    /// `0..2d`, and `Q = q0' 2^11 + q1' + [r1' >= d]`: one correction a
    /// gradient where there were two.
    #[inline(always)]
    pub(in crate::shade) fn div_round_two_digits(&self, n: i32, shift: u32) -> i32 {
        // By `d 2^k` ([`ShortDivisor`]), the dividends times `2^k`: the
        // first below `d 2^(12 + k) < 2^32`, the second `r0 2^11 + half
        // 2^k` with `r0` (a multiple of `2^k`) below `2 d 2^k` as above.
        let s = &self.divisor;
        let (q0, r0) = s.estimate(n.unsigned_abs() << (shift - 11 + s.k()));
        let (q1, r1) = s.estimate((r0 << 11) + s.half(self.half as u32));
        let q = (q0 << 11) + q1 + (r1 >= s.recip().d) as u32;
        // The quotient's sign: the numerator's times the divisor's.
        if (n ^ self.area2) < 0 {
            (q as i32).wrapping_neg()
        } else {
            q as i32
        }
    }

    /// [`SmallBasis::div_round32`] by [`Recip16`] digits (ARMv6-M: no
    /// library division per gradient): the rounded quotient of the
    /// magnitudes `Q = floor((|n| 2^shift + half) / d)`, `d = |area2|`,
    /// from three digits of the long division, then the sign of
    /// `n area2`. With `|n| = q0 d + r0`, `r0 2^10 = q1 d + r1` and
    /// `r1 2^k + half = q2 d + r2` (`k = shift - 10`, each remainder in
    /// `0..d`), `|n| 2^shift + half = (q0 2^shift + q1 2^k + q2) d + r2`,
    /// so `Q = q0 2^shift + q1 2^k + q2`: the quotient of
    /// [`SmallBasis::div_round32_with`], whose unsigned form takes the
    /// first two digits as one (`floor(|n| 2^10 / d) = q0 2^10 + q1`).
    /// Each digit's dividend is within [`Recip16::digit`]'s range: `|n|
    /// <= d 2^12` (the first digit at most `2^(40 - shift)`, `2^12` for
    /// depth, below `2^10` for colour), `r0 2^10 < d 2^10` and
    /// `r1 2^k + half < d (2^k + 1)`; `q2` may be `2^k` (added, not
    /// or-ed), and `Q` is within `2^30 + 2^k + 1`.
    ///
    /// Nearly every gradient takes two digits instead: where
    /// `|n| < d 2^(23 - shift)` (the quotient below 2^23: a colour
    /// channel's gradient below 128 levels a pixel, depth's below 512
    /// units), `|n| 2^(shift - 11) = q0 d + r0` with `q0 < 2^12` and
    /// `r0 2^11 + half = q1 d + r1`, so `|n| 2^shift + half =
    /// (q0 2^11 + q1) d + r1` and `Q = q0 2^11 + q1`. Both dividends are
    /// below `d 2^12` (`(d - 1) 2^11 + d / 2` for the second), within
    /// [`Recip16::digit`]'s range, and below 2^32: `|n| 2^(shift - 11) <
    /// 2^30`, `d 2^11 < 2^32` (a second digit of 12 bits would overflow
    /// where twice the area exceeds 2^20). A digit is about 20
    /// instructions with its spills, and a Gouraud set-up has eight
    /// gradients: ARMv6-M `demo` 8,303,163 -> 8,189,046 instructions,
    /// `rock` 6,861,253 -> 6,771,913.
    #[inline(always)]
    pub(in crate::shade) fn div_round32_short(&self, n: i32, shift: u32) -> i32 {
        let k = shift - 10;
        let s = &self.divisor;
        let f = s.recip();
        let a = n.unsigned_abs();
        if a >> (23 - shift) < self.two_digit_bound() {
            return self.div_round_two_digits(n, shift);
        }
        // By `d 2^k` ([`ShortDivisor`]): each dividend times `2^k`, the
        // first `|n| 2^k <= d 2^(12 + k) < 2^32` (`d 2^k < 2^20`, or
        // `k = 0`), the remainders times `2^k`; the same digits.
        let (q0, r0) = f.digit(a << s.k());
        let (q1, r1) = f.digit(r0 << 10);
        let (q2, _) = f.digit((r1 << k) + s.half(self.half as u32));
        let q = (q0 << shift) + (q1 << k) + q2;
        // The quotient's sign: the numerator's times the divisor's.
        if (n ^ self.area2) < 0 {
            (q as i32).wrapping_neg()
        } else {
            q as i32
        }
    }

    /// [`SmallBasis::div_round32`] in signed divisions (`SIGNED`) or in
    /// unsigned ones of the magnitudes (one library call for quotient and
    /// remainder where the division is one; the tests' reference for
    /// [`SmallBasis::div_round32_short`]).
    #[inline(always)]
    pub(in crate::shade) fn div_round32_with<const SIGNED: bool>(&self, n: i32, shift: u32) -> i32 {
        let k = shift - 10;
        if !SIGNED {
            let d = self.area2.unsigned_abs();
            // Below 2^31 for |n| <= 2^21.
            let m = n.unsigned_abs() << 10;
            let (q, r) = (m / d, m % d);
            let q = (q << k) + ((r << k) + self.half as u32) / d;
            // The quotient's sign: the numerator's times the divisor's.
            return if (n ^ self.area2) < 0 {
                (q as i32).wrapping_neg()
            } else {
                q as i32
            };
        }
        // Within i32 for -2^21 <= n < 2^21: no bit is lost.
        self.div_round32_of_m(n << 10, shift)
    }
}

impl<D: AreaDivisor> SmallBasis<D> {
    /// [`SmallBasis::div_round32`] in signed divisions of `m = n 2^10`
    /// (the caller's numerator times 2^10, for `-2^21 <= n < 2^21`
    /// within its bounds); [`SmallBasis::div_round32_with`]'s signed
    /// form passes `n` shifted. Given as a product's result, `m` is a register the remainder
    /// `m - q area2` takes in one multiply-subtract, where the shifted
    /// `n` went into a subtract with a shifted operand after a
    /// multiply (see [`SHIFTED_NUMERATORS`](super::SHIFTED_NUMERATORS)).
    #[inline(always)]
    pub(in crate::shade) fn div_round32_of_m(&self, m: i32, shift: u32) -> i32 {
        let k = shift - 10;
        let d = self.area2;
        let q = m / d;
        let r = m - q * d;
        // `n`'s sign, read from `m` (the same bit: the shift loses none).
        // The optimiser takes it as one bit-field extract of `n` and
        // allocates the set-up's registers differently: Cortex-M3 `demo`
        // 3,641,795 -> 3,637,327 instructions, `rock` 2,976,250 ->
        // 2,972,752. (From the remainder's sign instead, which is `n`'s
        // or 0, and a zero remainder gives 0 with either `half`: +33 K.)
        let sign = m >> 31;
        // `half` with n's sign. `|area2| <= 2 * 1023^2` (edge vectors of at
        // most 1023 sub-pixels), so `|r| 2^10 + half <= (|area2| - 1) 2^10
        // + |area2| / 2 < 2^31`: no overflow.
        let half = (self.half ^ sign) - sign;
        let low = ((r << k) + half) / d;
        (q << k) + low
    }
}

impl Small {
    /// `n / area` rounded to nearest, ties away from zero (as
    /// [`Basis::div_round`](super::super::plane::Basis::div_round)), for `|n| < 2^43` and `area < 2^21`: the
    /// perspective planes' numerators, whose values reach 2^28. Long
    /// division in 32-bit steps of 11 bits (every partial dividend is
    /// below `area 2^11 < 2^32`): four divisions, each one instruction on a
    /// Cortex-M3/M4, where a 64-bit division is a library call.
    #[inline(always)]
    pub(in crate::shade) fn div_round_wide(&self, n: i64) -> i64 {
        let d = self.area;
        // Below 2^43 + 2^20 < 2^44: four chunks of 11 bits.
        let a = n.unsigned_abs() + self.half as u64;
        let top = (a >> 33) as u32;
        let mut q = (top / d) as u64;
        let mut r = top % d;
        for shift in [22, 11, 0] {
            let part = (r << 11) | ((a >> shift) as u32 & 0x7FF);
            q = (q << 11) | (part / d) as u64;
            r = part % d;
        }
        let q = q as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    }
}
