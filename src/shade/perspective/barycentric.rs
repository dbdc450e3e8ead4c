//! The weights of a pixel from the perspective planes: `b1 = B1 / Q`,
//! `b2 = B2 / Q` in 0.16 fixed point with one 32-bit reciprocal, and the
//! span-wide shortcut when the whole span allows it.

use super::lerp::NARROW_MULTIPLY;

/// The perspective-correct weights `(B1 / Q, B2 / Q)` in 0.16 fixed
/// point, with one 32-bit division: `Q` is shifted to 16 significant bits
/// (`B1`, `B2` with it), so the reciprocal `2^31 / Q` has 16 as well and
/// each product fits `u32`. Each weight is within 7 units (of 65,536) of
/// the exact quotient when `Q >= 2^15`, which holds unless the triangle's
/// `w` vary by more than 2^13: the truncations of `Q`, of the numerator
/// and of the reciprocal cost at most 2 units each, the final shift 1.
#[inline(always)]
pub(crate) fn weights(q: i32, b1: i32, b2: i32) -> (i32, i32) {
    let q = q.max(1) as u32;
    let sh = if NARROW_MULTIPLY {
        shift16(q)
    } else {
        (32 - q.leading_zeros()).saturating_sub(16)
    };
    let qn = q >> sh;
    let r = reciprocal(qn);
    let n1 = ((b1.max(0) as u32) >> sh).min(qn);
    let n2 = ((b2.max(0) as u32) >> sh).min(qn);
    // n <= qn, so n * r <= 2^31.
    (((n1 * r) >> 15) as i32, ((n2 * r) >> 15) as i32)
}

/// [`weights`] where `Q`'s normalising shift is most likely [`GUESS`]: on
/// ARMv6-M, where [`shift16`] (no `CLZ`) takes four compares and shifts
/// a pixel, the guess is tested instead and `shift16` taken only when it
/// fails. `Q >> sh` in `2^15..2^16` holds exactly when `Q`'s bit length
/// is `sh + 16`, which is when `sh` is `shift16(Q)`: the same bits as
/// `weights`. Elsewhere `weights` itself.
#[inline(always)]
pub(crate) fn weights_guessed(q: i32, b1: i32, b2: i32) -> (i32, i32) {
    weights_guessed_in::<NARROW_MULTIPLY>(q, b1, b2)
}

/// [`weights_guessed`], with `NARROW` its ARMv6-M form (the tests run
/// both).
#[inline(always)]
fn weights_guessed_in<const NARROW: bool>(q: i32, b1: i32, b2: i32) -> (i32, i32) {
    if !NARROW {
        return weights(q, b1, b2);
    }
    let q = q.max(1) as u32;
    let (sh, qn) = if (q >> GUESS) >> 15 == 1 {
        (GUESS, q >> GUESS)
    } else {
        let sh = shift16(q);
        (sh, q >> sh)
    };
    // `weights`' tail written again: shared through one inlined function
    // it changed x86-64's code (`demo-textured-lit` 5,993,431 ->
    // 6,132,014 instructions), though `weights_guessed` runs `weights`
    // itself there.
    let r = reciprocal(qn);
    let n1 = ((b1.max(0) as u32) >> sh).min(qn);
    let n2 = ((b2.max(0) as u32) >> sh).min(qn);
    // n <= qn, so n * r <= 2^31.
    (((n1 * r) >> 15) as i32, ((n2 * r) >> 15) as i32)
}

/// [`weights_guessed`]' shift: that of a `Q` in `2^27..2^28`, as at most
/// pixels of a small triangle, whose vertices' `q` (`2^28 w_min / w`) are
/// all near `2^28`, the nearest vertex's, and mostly just below it.
/// ARMv6-M `demo-textured-lit` (single-scene build) 12,751,909
/// instructions with 13, 12,493,942 with 12.
const GUESS: u32 = 12;

/// [`SpanInput::opaque_shift`](crate::shader::span::SpanInput::opaque_shift) for a span of `len` pixels starting at
/// `planes` (`Q`, `B1`, `B2`) with `steps`.
#[inline(always)]
pub(super) fn span_shift(planes: [i32; 3], steps: [i32; 3], len: usize) -> Option<u32> {
    // The convex test's sums are dead code here, left out when inlined.
    span_shift_convex32(planes, steps, len).map(|(sh, _)| sh)
}

/// [`span_shift`] in `i64`, on a 64-bit host where its products and sums
/// are single instructions: the ends cannot overflow (`|g| < 2^31`, the
/// length below 2^31), so no checked arithmetic, and an end outside `i32`
/// fails the same tests that its overflow failed. `Q`'s bit lengths at
/// both ends are compared as `q ^ qe < q & qe` (two positive numbers have
/// the same highest bit exactly when their `and` is above their `xor`),
/// and `0 <= B <= Q` as one unsigned comparison (`Q` positive): the same
/// shift as `span_shift` (a unit test holds them together). With it,
/// whether `B1 + B2 <= Q` at both ends of the span (then at every pixel: the planes are linear along it). Where it
/// holds, the weights of [`shifted_weights`] (and [`flat_weights`]) sum to
/// at most 2^16: `(B1 >> sh) + (B2 >> sh) <= Q >> sh = qn`, so the two
/// products by `r = 2^31 / qn` sum to at most `qn · r <= 2^31`, and the
/// sum of their quotients by 2^15 to at most 2^16. A colour interpolated
/// with them is then a convex combination of the vertices' (plus the
/// rounding half), each channel within `0..=255` after its shift: no clamp
/// ([`Interpolated`](crate::shader::span::Interpolated)'s `convex`).
///
/// With `CONVEX_ONLY`, `None` for the spans that are not convex too (for
/// a caller that sends them where it sends the others, a shader without
/// varyings): `B1, B2 >= 0` at both ends is then one sign test of their
/// `or`, and `B <= Q` follows from `B1 + B2 <= Q` (`B1 <= B1 + B2` as
/// `B2 >= 0`), so the four upper tests go (x86-64 `fill-gouraud-exact`
/// 47.86 -> 47.76 instructions a fragment). Not for `TexturedLit`, whose
/// loops' registers moved with it (`knot1k-textured-lit` +1.7 %).
#[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
#[inline(always)]
pub(super) fn span_shift_convex<const CONVEX_ONLY: bool>(
    planes: [i32; 3],
    steps: [i32; 3],
    len: usize,
) -> Option<(u32, bool)> {
    let last = i32::try_from(len.saturating_sub(1)).ok()? as i64;
    let [q, b1, b2] = planes.map(i64::from);
    let [gq, g1, g2] = steps.map(i64::from);
    let qe = q + gq * last;
    if q < 1 || qe < 1 || qe > i32::MAX as i64 || (q ^ qe) >= (q & qe) {
        return None;
    }
    let (b1e, b2e) = (b1 + g1 * last, b2 + g2 * last);
    if CONVEX_ONLY {
        return ((b1 | b2 | b1e | b2e) >= 0 && b1 + b2 <= q && b1e + b2e <= qe)
            .then(|| ((32 - (q as u32).leading_zeros()).saturating_sub(16), true));
    }
    let within = |b: i64, q: i64| b as u64 <= q as u64;
    let convex = b1 + b2 <= q && b1e + b2e <= qe;
    (within(b1, q) && within(b2, q) && within(b1e, qe) && within(b2e, qe))
        .then(|| ((32 - (q as u32).leading_zeros()).saturating_sub(16), convex))
}

/// [`span_shift_convex`] in `i32`, checked (a span whose ends overflow
/// takes the other loop), for 32-bit cores: [`span_shift`] is its shift,
/// and cores without a 64-bit product (ARMv6-M), where the byte clamps
/// that convex spans save take a compare and a branch each (no `USAT`),
/// take its test too. The sums of `B1 + B2 <= Q` are taken in `u32`,
/// where two values of `0..2^31` cannot overflow.
#[inline(always)]
pub(super) fn span_shift_convex32(
    planes: [i32; 3],
    steps: [i32; 3],
    len: usize,
) -> Option<(u32, bool)> {
    span_shift_convex32_in::<NARROW_MULTIPLY>(planes, steps, len)
}

/// [`span_shift_convex32`], with `NARROW` the ARMv6-M form (the tests
/// run both): the products' overflow test by [`checked_mul_short`],
/// where `checked_mul` took a 64-bit library product (about 40
/// instructions), and `Q`'s bit lengths compared as
/// [`span_shift_convex`] does and its shift by [`shift16`], where
/// `leading_zeros` is a library call (about 36).
#[inline(always)]
pub(super) fn span_shift_convex32_in<const NARROW: bool>(
    planes: [i32; 3],
    steps: [i32; 3],
    len: usize,
) -> Option<(u32, bool)> {
    let last = i32::try_from(len.saturating_sub(1)).ok()?;
    let end = |a: i32, g: i32| {
        if NARROW {
            checked_mul_short(g, last)
        } else {
            g.checked_mul(last)
        }
        .and_then(|d| a.checked_add(d))
    };
    let [q, b1, b2] = planes;
    let [gq, g1, g2] = steps;
    let qe = end(q, gq)?;
    if q < 1 || qe < 1 {
        return None;
    }
    let same_length = if NARROW {
        (q ^ qe) < (q & qe)
    } else {
        q.leading_zeros() == qe.leading_zeros()
    };
    if !same_length {
        return None;
    }
    let (b1e, b2e) = (end(b1, g1)?, end(b2, g2)?);
    let within = |b: i32, q: i32| 0 <= b && b <= q;
    let sum = |a: i32, b: i32| (a as u32).wrapping_add(b as u32);
    let convex = sum(b1, b2) <= q as u32 && sum(b1e, b2e) <= qe as u32;
    let shift = || {
        if NARROW {
            shift16(q as u32)
        } else {
            (32 - q.leading_zeros()).saturating_sub(16)
        }
    };
    (within(b1, q) && within(b2, q) && within(b1e, qe) && within(b2e, qe))
        .then(|| (shift(), convex))
}

/// `g.checked_mul(last)` for `last >= 0` in 32-bit products, on ARMv6-M
/// (whose `checked_mul` is a 64-bit library product): for `last <
/// 2^16` (a span's length, always), with `g = gh 2^16 + gl` (`0 <= gl <
/// 2^16`), `g last = (gh last + floor(gl last / 2^16)) 2^16 + (gl last
/// mod 2^16)`, where `gl last < 2^32` and the high part `h` stays inside
/// `i32` (`|gh| <= 2^15`); the product fits `i32` exactly when `-2^15 <=
/// h < 2^15`. Longer `last` as `checked_mul`. (Not `mul_wide` and a
/// range test: its closure was left out of line, a call per span end.)
#[inline(always)]
fn checked_mul_short(g: i32, last: i32) -> Option<i32> {
    if last >> 16 != 0 {
        return g.checked_mul(last);
    }
    let (gh, gl) = (g >> 16, (g & 0xFFFF) as u32);
    let lo = gl * last as u32;
    let h = gh * last + (lo >> 16) as i32;
    ((-(1 << 15)..1 << 15).contains(&h)).then_some((h << 16) | (lo & 0xFFFF) as i32)
}

/// [`weights`] where its clamps change nothing and `Q`'s normalising
/// shift `sh` is known: `1 <= Q < 2^31`, `0 <= B1, B2 <= Q`
/// ([`span_shift`]), so `qn > 0` and each product is at most 2^31.
#[inline(always)]
pub(super) fn shifted_weights(q: i32, b1: i32, b2: i32, sh: u32) -> (i32, i32) {
    let qn = (q as u32) >> sh;
    let r = reciprocal(qn);
    let w1 = (((b1 as u32) >> sh) * r) >> 15;
    let w2 = (((b2 as u32) >> sh) * r) >> 15;
    (w1 as i32, w2 as i32)
}

/// `shifted_weights`' reciprocal `2^31 / (Q >> sh)` for a span whose `Q`
/// does not change along it (its step is zero: a face whose `1 / w` does
/// not vary along the screen's rows, as any face parallel to the screen),
/// taken once per span rather than at every pixel. `Q >> sh >= 1` where
/// [`span_shift`] allowed the span; the `max` only keeps this total.
#[inline(always)]
pub(super) fn span_reciprocal(q: i32, sh: u32) -> u32 {
    reciprocal(((q as u32) >> sh).max(1))
}

/// `2^31 / qn`, floored, for `qn >= 1`: a division, or on ARMv6-M
/// [`reciprocal_narrow`].
#[inline(always)]
fn reciprocal(qn: u32) -> u32 {
    if NARROW_MULTIPLY {
        reciprocal_narrow(qn)
    } else {
        (1u32 << 31) / qn
    }
}

/// [`reciprocal`] on ARMv6-M, which has no divider (its library division
/// takes about 150 instructions in the QEMU firmware): for `qn` of 16
/// bits (`2^15 <= qn < 2^16`, every pixel whose `Q` is at least `2^15`),
/// the area set-up's 16-bit reciprocal from below (`recip31`: a table
/// look-up and one Newton step in 32-bit products, at most 3.1 below
/// `2^31 / qn`), then corrected up while the remainder `2^31 - r qn`
/// (at most `4 qn`, no wrap as `r qn <= 2^31`) holds another `qn`: the
/// floored quotient exactly. Other `qn` divide.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn reciprocal_narrow(qn: u32) -> u32 {
    if qn >> 15 != 1 {
        return (1u32 << 31) / qn;
    }
    let mut r = crate::math::recip31(qn);
    let mut rem = (1u32 << 31) - r * qn;
    // At most three steps (`rem < 4 qn`), written out: the loop's form
    // was unrolled with the remainders of one to three more steps
    // computed up front (products and stack slots) at nearly every
    // pixel, where the estimate is mostly one short.
    if rem >= qn {
        r += 1;
        rem -= qn;
        if rem >= qn {
            r += 1;
            rem -= qn;
            if rem >= qn {
                r += 1;
            }
        }
    }
    r
}

/// `(32 - q.leading_zeros()).saturating_sub(16)`, [`weights`]' shift, on
/// ARMv6-M (no `CLZ`: `leading_zeros` is a library call of about 36
/// instructions there): the bit length of `q >> 16` by four compares
/// and shifts (after them `x` is 0 or 1).
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(super) fn shift16(q: u32) -> u32 {
    let (mut x, mut n) = (q >> 16, 0);
    for s in [8, 4, 2, 1] {
        if x >> s != 0 {
            x >>= s;
            n += s;
        }
    }
    n + x
}

/// [`shifted_weights`] with its reciprocal `r` from [`span_reciprocal`]
/// (`Q` the same at every pixel of the span): the same bits, no division.
#[inline(always)]
pub(super) fn flat_weights(b1: i32, b2: i32, sh: u32, r: u32) -> (i32, i32) {
    let w1 = (((b1 as u32) >> sh) * r) >> 15;
    let w2 = (((b2 as u32) >> sh) * r) >> 15;
    (w1 as i32, w2 as i32)
}

/// [`weights`] with the sign of `B1` and `B2` kept (the same for
/// non-negative ones): the quasi-perspective sample one pixel beyond a
/// span's end may lie a little outside the triangle.
#[inline(always)]
pub(crate) fn signed_weights(q: i32, b1: i32, b2: i32) -> (i32, i32) {
    let (w1, w2) = weights(q, b1.saturating_abs(), b2.saturating_abs());
    (if b1 < 0 { -w1 } else { w1 }, if b2 < 0 { -w2 } else { w2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_match_the_quotient() {
        let mut next = crate::testing::rng();
        for _ in 0..200_000 {
            let bits = 1 + next(29);
            let q = 1 + next(1 << bits) as i32;
            let b1 = next(q as u64 + 1) as i32;
            let b2 = next((q - b1) as u64 + 1) as i32;
            let (w1, w2) = weights(q, b1, b2);
            for (w, b) in [(w1, b1), (w2, b2)] {
                let exact = b as f64 / q as f64 * 65_536.0;
                // 7 units for Q >= 2^15 (see `weights`); below, the
                // truncation of the numerator costs up to one unit of Q.
                let tol = if q >= 1 << 15 {
                    7.0
                } else {
                    65_536.0 / q as f64 + 2.0
                };
                assert!(
                    (w as f64 - exact).abs() <= tol,
                    "q {q} b {b}: {w} vs {exact}"
                );
            }
        }
    }

    /// A span's `[Q, B1, B2]` at its first pixel (`Q` small or negative
    /// one time in five, `B1` and `B2` from -1 up to about `Q`), their
    /// steps and its length: spans of the usual sizes and the edges.
    fn random_span(next: &mut impl FnMut(u64) -> u64, n: u32) -> ([i32; 3], [i32; 3], usize) {
        let len = 1 + next(64) as usize;
        let bits = 1 + next(30);
        let q = next(1 << bits) as i32 + if n.is_multiple_of(5) { -2 } else { 1 };
        let b1 = next(q.max(1) as u64 + 2) as i32 - 1;
        let b2 = next((q.max(1) - b1.max(0)) as u64 + 2) as i32 - 1;
        let mut g = || (next(1 << 16) as i32 - (1 << 15)) >> next(12);
        ([q, b1, b2], [g(), g(), g()], len)
    }

    /// Where `span_shift` allows a span, `shifted_weights` gives the bits
    /// of `weights` at each of its pixels; and it allows the usual spans.
    #[test]
    fn shifted_weights_match_where_allowed() {
        let mut next = crate::testing::rng();
        let mut allowed = 0;
        for n in 0..40_000 {
            let ([q, b1, b2], steps, len) = random_span(&mut next, n);
            let Some(sh) = span_shift([q, b1, b2], steps, len) else {
                continue;
            };
            allowed += 1;
            let [mut q, mut b1, mut b2] = [q, b1, b2];
            for _ in 0..len {
                assert_eq!(
                    shifted_weights(q, b1, b2, sh),
                    weights(q, b1, b2),
                    "{q} {b1} {b2}"
                );
                q = q.wrapping_add(steps[0]);
                b1 = b1.wrapping_add(steps[1]);
                b2 = b2.wrapping_add(steps[2]);
            }
        }
        assert!(allowed > 5_000, "{allowed} spans allowed");
    }

    /// Where `span_shift_convex` finds `B1 + B2 <= Q` at a span's ends,
    /// `shifted_weights` sum to at most 2^16 at each of its pixels.
    #[test]
    fn convex_weights_sum_to_one_at_most() {
        let mut next = crate::testing::rng();
        let mut convex = 0;
        for n in 0..40_000 {
            let ([q, b1, b2], steps, len) = random_span(&mut next, n);
            let Some((sh, true)) = span_shift_convex::<false>([q, b1, b2], steps, len) else {
                continue;
            };
            convex += 1;
            let [mut q, mut b1, mut b2] = [q, b1, b2];
            for _ in 0..len {
                let (w1, w2) = shifted_weights(q, b1, b2, sh);
                assert!(w1 >= 0 && w2 >= 0 && w1 + w2 <= 1 << 16, "{q} {b1} {b2}");
                q = q.wrapping_add(steps[0]);
                b1 = b1.wrapping_add(steps[1]);
                b2 = b2.wrapping_add(steps[2]);
            }
        }
        assert!(convex > 2_000, "{convex} convex spans");
    }

    /// `span_shift_convex` (in `i64`; with `CONVEX_ONLY`, its convex
    /// answers) decides as `span_shift_convex32`
    /// (in `i32`, checked; `span_shift` is its shift), ends that overflow
    /// `i32` and every edge of their tests included.
    #[test]
    fn span_shift_in_i64_and_i32_match() {
        let mut next = crate::testing::rng();
        let mut allowed = 0;
        for n in 0..400_000 {
            let len = match n % 4 {
                0 => next(4) as usize,
                _ => 1 + next(64) as usize,
            };
            let v = |next: &mut dyn FnMut(u64) -> u64| match next(4) {
                0 => [i32::MIN, -1, 0, 1, 2, i32::MAX, 1 << 16, (1 << 16) - 1][next(8) as usize],
                1 => next(1 << 32) as u32 as i32,
                _ => (next(1 << 30) as i32) >> next(20),
            };
            let planes = [v(&mut next), v(&mut next), v(&mut next)];
            let g = |next: &mut dyn FnMut(u64) -> u64| match next(3) {
                0 => next(1 << 32) as u32 as i32,
                _ => (next(1 << 20) as i32 - (1 << 19)) >> next(12),
            };
            let steps = [g(&mut next), g(&mut next), g(&mut next)];
            let convex = span_shift_convex::<false>(planes, steps, len);
            assert_eq!(
                span_shift_convex::<true>(planes, steps, len),
                convex.filter(|&(_, c)| c),
                "{planes:?} {steps:?} {len}"
            );
            let convex32 = span_shift_convex32(planes, steps, len);
            assert_eq!(convex32, convex, "{planes:?} {steps:?} {len}");
            let narrow = span_shift_convex32_in::<true>(planes, steps, len);
            assert_eq!(narrow, convex, "{planes:?} {steps:?} {len}");
            allowed += convex.is_some() as u32;
        }
        assert!(allowed > 10_000, "{allowed} spans allowed");
    }

    /// Where `span_shift` allows a span whose `Q` does not change,
    /// `flat_weights` with the span's reciprocal gives `weights`' bits.
    #[test]
    fn flat_weights_match_where_q_is_constant() {
        let mut next = crate::testing::rng();
        let mut allowed = 0;
        for _ in 0..40_000 {
            let len = 1 + next(64) as usize;
            let bits = 1 + next(30);
            let q = next(1 << bits) as i32 + 1;
            let b1 = next(q as u64 + 1) as i32;
            let b2 = next((q - b1) as u64 + 1) as i32;
            let g =
                |next: &mut dyn FnMut(u64) -> u64| (next(1 << 16) as i32 - (1 << 15)) >> next(12);
            let steps = [0, g(&mut next), g(&mut next)];
            let Some(sh) = span_shift([q, b1, b2], steps, len) else {
                continue;
            };
            allowed += 1;
            let r = span_reciprocal(q, sh);
            let [mut b1, mut b2] = [b1, b2];
            for _ in 0..len {
                assert_eq!(
                    flat_weights(b1, b2, sh, r),
                    weights(q, b1, b2),
                    "{q} {b1} {b2}"
                );
                b1 = b1.wrapping_add(steps[1]);
                b2 = b2.wrapping_add(steps[2]);
            }
        }
        assert!(allowed > 5_000, "{allowed} spans allowed");
    }

    /// ARMv6-M's reciprocal is the division for every `qn` of 16 bits
    /// and below.
    #[test]
    fn narrow_reciprocal_is_the_quotient() {
        for qn in 1u32..1 << 16 {
            assert_eq!(reciprocal_narrow(qn), (1u32 << 31) / qn, "{qn}");
        }
    }

    /// `checked_mul_short` is `checked_mul` for every step and length,
    /// the ends of both ranges included.
    #[test]
    fn short_checked_product_matches() {
        let mut next = crate::testing::rng();
        let edges = [
            i32::MIN,
            i32::MIN + 1,
            -65_537,
            -65_536,
            -1,
            0,
            1,
            65_535,
            i32::MAX,
        ];
        for _ in 0..400_000 {
            let g = match next(3) {
                0 => edges[next(edges.len() as u64) as usize],
                1 => next(1 << 32) as u32 as i32,
                _ => (next(1 << 32) as u32 as i32) >> next(32),
            };
            let last = match next(3) {
                0 => [0, 1, 65_535, 65_536, i32::MAX][next(5) as usize],
                1 => next(1 << 16) as i32,
                _ => next(1 << 31) as i32 >> next(31),
            };
            assert_eq!(
                checked_mul_short(g, last),
                g.checked_mul(last),
                "{g} {last}"
            );
        }
    }

    /// `weights_guessed`'s ARMv6-M form gives the bits of `weights`,
    /// around the guessed shift's bounds and anywhere: `Q` of every bit
    /// length, below 1 too, `B1` and `B2` from below 0 to beyond `Q`.
    #[test]
    fn guessed_weights_match() {
        let mut next = crate::testing::rng();
        let mut check = |q: i32| {
            let m = q.max(1) as u64;
            for _ in 0..8 {
                let b1 = (next(2 * m + 4) as i32).wrapping_sub(2);
                let b2 = (next(2 * m + 4) as i32).wrapping_sub(2);
                assert_eq!(
                    weights_guessed_in::<true>(q, b1, b2),
                    weights(q, b1, b2),
                    "{q} {b1} {b2}"
                );
                assert_eq!(weights_guessed_in::<false>(q, b1, b2), weights(q, b1, b2));
            }
        };
        for k in 0..31 {
            for d in -2..=2 {
                check((1i32 << k).wrapping_add(d));
            }
        }
        for q in [i32::MIN, -1, 0, i32::MAX] {
            check(q);
        }
        let mut next = crate::testing::rng();
        for _ in 0..50_000 {
            let q = (next(1 << 31) as i32) >> next(31);
            check(q);
        }
    }

    /// ARMv6-M's shift of `weights` is the one from the leading zeros.
    #[test]
    fn narrow_shift_matches() {
        let mut next = crate::testing::rng();
        let check = |q: u32| {
            assert_eq!(
                shift16(q),
                (32 - q.leading_zeros()).saturating_sub(16),
                "{q}"
            );
        };
        for k in 0..32 {
            for q in [(1u32 << k) - 1, 1 << k, (1 << k) + 1] {
                check(q);
            }
        }
        check(u32::MAX);
        for _ in 0..100_000 {
            check(next(1 << 32) as u32 >> next(32));
        }
    }

    /// The 32-bit form of ARMv6-M gives the bits of the `i64` formula,
    /// extremes included.

    #[test]
    fn signed_weights_keep_the_sign() {
        assert_eq!(
            signed_weights(1 << 20, 1 << 18, 0),
            weights(1 << 20, 1 << 18, 0)
        );
        let (p, _) = weights(1 << 20, 1 << 10, 0);
        assert_eq!(signed_weights(1 << 20, -(1 << 10), 5).0, -p);
    }
}
