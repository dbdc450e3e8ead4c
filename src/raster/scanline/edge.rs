//! One edge of the scanline walk: its start column at a pixel row and its
//! per-row step, as an integer column and an exact remainder (Hecker's
//! `FloorDivMod` stepper), and the divisions that set it up.
//!
//! An edge's set-up is one `i32` division, its per-row step. Its own first
//! row's start column follows from that step without a second division
//! ([`EdgeStepper::new`]); a start that a tile's top clips lower is
//! divided out in [`far_start`]. On ARMv6-M, whose division is a library
//! call, small quotients come from compares ([`div_rem_compare`]).

use super::replace_short;
use crate::math::mul_wide;
use crate::math::Recip16;
use crate::raster::{Span, SubPoint, HALF_PIXEL, SUBPIXEL, SUBPIXEL_BITS};
use core::num::NonZeroU32;

/// One edge being walked down the rows: the first covered column at the
/// current row, and the exact remainder of that ceiling, kept as an error
/// term below zero so that a step needs no comparison with a register.
#[derive(Clone, Copy, Debug)]
pub(super) struct EdgeStepper {
    /// `ceil(N / den)` for the current row, with `N` the edge's numerator.
    pub(super) col: i32,
    /// `col * den - N - den`, always in `-den..0`.
    pub(super) err: i32,
    /// Column step per row: `ceil(SUBPIXEL * dx / den)`.
    pub(super) step_col: i32,
    /// Error step per row: `step_col * den - SUBPIXEL * dx`, in `0..den`;
    /// a carry (the error reaching zero) takes one column back.
    pub(super) step_err: i32,
    /// `SUBPIXEL * dy`.
    pub(super) den: i32,
}

impl EdgeStepper {
    /// Starts the edge `p -> q` (`q.y > p.y`) at pixel row `row`, whose
    /// centre is at or below `p` (`row >= first_centre_at_or_after(p.y)`).
    ///
    /// One `i32` division, the per-row step `ceil(dx / dy) = (s, r)`. When
    /// the start row is one of the first sixteen sub-pixel rows below `p`
    /// (every edge's own first row: only a tile's top clips below that),
    /// the start column follows from it with no second division: with
    /// `t = y_c - p.y < 16` and `P = p.x - ½ + t s = 16 Q + R`, the
    /// numerator is `16 dy Q + (dy R - t r)`, and `|dy R - t r| < 16 dy`, so
    /// the ceiling is `Q` or `Q + 1`. Otherwise the start column is divided
    /// out: in `i32` when its numerator fits (a single instruction on a
    /// Cortex-M3/M4 where the 64-bit one is a library call), in `i64` for
    /// long edges far from the origin; all give the same quotient.
    ///
    /// `NEAR` tells that `row` is the edge's own first row (so `t < 16`).
    #[inline(always)]
    pub(super) fn new<const NEAR: bool>(p: SubPoint, q: SubPoint, row: i32) -> Self {
        // Within the guard band coordinates are below 2^18 in magnitude
        // (see `crate::vertex`), so differences fit i32 with room to spare.
        let dx = q.x - p.x;
        let dy = q.y - p.y;
        debug_assert!(dy > 0);
        // dy > 0 (the caller walks edges downwards); the fallback only
        // spares the divisions their checks.
        let dy = NonZeroU32::new(dy as u32).unwrap_or(NonZeroU32::MIN);
        let den = (dy.get() * SUBPIXEL as u32) as i32;
        // ceil(SUBPIXEL dx / (SUBPIXEL dy)) = ceil(dx / dy), with the
        // remainder scaled back by SUBPIXEL.
        let (step_col, r) = ceil_div_rem32(dx, dy);
        let yc = row * SUBPIXEL + HALF_PIXEL;
        let t = yc - p.y;
        debug_assert!(!NEAR || (t as u32) < SUBPIXEL as u32);
        let (col, rem) = if NEAR || (t as u32) < SUBPIXEL as u32 {
            // |t s| <= 15 * 2^19: P fits i32; dy R and t r are below 2^24.
            let big_p = p.x - HALF_PIXEL + t * step_col;
            let n = dy.get() as i32 * (big_p & (SUBPIXEL - 1)) - t * r;
            let up = (n > 0) as i32;
            (
                (big_p >> SUBPIXEL_BITS) + up,
                // den - n when the ceiling rounds up, -n otherwise.
                (den & -up) - n,
            )
        } else {
            far_start_of(p, dx, dy, t, (step_col, r))
        };
        // Within the guard band every quantity here fits i32; see the
        // module docs of `crate::vertex` for the bound.
        Self {
            col,
            err: rem - den,
            step_col,
            step_err: r * SUBPIXEL,
            den,
        }
    }
}

/// [`far_start`], or on ARMv6-M [`far_start_stepped`], which takes the
/// edge's step `(step_col, r)` (`ceil(dx / dy)` and its remainder) in
/// place of `dx`.
#[inline(always)]
pub(super) fn far_start_of(
    p: SubPoint,
    dx: i32,
    dy: NonZeroU32,
    t: i32,
    (step_col, r): (i32, i32),
) -> (i32, i32) {
    if crate::math::SPLIT {
        far_start_stepped(p.x, dy, t, step_col, r)
    } else {
        far_start(p, dx, dy, t)
    }
}

/// [`far_start`] from the edge's step `s = ceil(dx / dy)` and its
/// remainder `r = s dy - dx` (ARMv6-M, whose division is a library call
/// of about a hundred instructions): the near start's formula of
/// [`EdgeStepper::new`] for any `t`. With `P = p.x - ½ + t s = 16 Q + R`
/// (`R` in `0..16`), the numerator `(p.x - ½) dy + t dx` is
/// `dy P - t r = 16 dy Q + M`, `M = dy R - t r`, so the ceiling over
/// `16 dy` is `Q + ceil(M / (16 dy))` and its remainder `M`'s. `M` lies
/// within `-t dy..16 dy`: its quotient is at most `t / 16` (the rows the
/// tile's top clips) in magnitude, four times in five below 4 in `demo`,
/// which [`div_rem_compare`] takes by compares, where `far_start` divided
/// every time: ARMv6-M `demo` 7,759,325 -> 7,704,424 instructions, `rock`
/// 6,421,499 -> 6,386,042. Where `p.x - ½`, `t`, `s` and
/// `dy` lie within `-2^14..2^14` (an edge on a screen below 1,024 pixels
/// a side), `t s`, `t r` (`r < dy`) and `P` are below 2^29 in magnitude:
/// every value is exact in `i32`. Otherwise [`far_start`], with `dx`
/// recomputed (`s dy - r`, below 2^20 within the guard band; `far_start`
/// reads only `p.x`).
#[inline(never)]
pub(super) fn far_start_stepped(px: i32, dy: NonZeroU32, t: i32, s: i32, r: i32) -> (i32, i32) {
    let a = px - HALF_PIXEL;
    let lift = |v: i32| v.wrapping_add(1 << 14) as u32;
    if (lift(a) | lift(t) | lift(s) | lift(dy.get() as i32)) >> 15 == 0 {
        let den = dy.get() * SUBPIXEL as u32;
        let den = NonZeroU32::new(den).unwrap_or(NonZeroU32::MIN);
        let big_p = a + t * s;
        let m = dy.get() as i32 * (big_p & (SUBPIXEL - 1)) - t * r;
        let (k, rem) = ceil_div_rem32(m, den);
        return ((big_p >> SUBPIXEL_BITS) + k, rem);
    }
    let dx = s.wrapping_mul(dy.get() as i32).wrapping_sub(r);
    far_start(SubPoint::new(px, 0), dx, dy, t)
}

/// The start column of the edge from `p`, `dx` across and `dy` down, at
/// `t` sub-pixels below `p`, and the remainder of its ceiling, for a start
/// that a tile's top clips lower than the edge's own first row (see
/// [`EdgeStepper::new`]). Out of line: four edge set-ups share it, for
/// the rare start that a tile's top clips (the OLED firmware's flash).
#[inline(never)]
pub(super) fn far_start(p: SubPoint, dx: i32, dy: NonZeroU32, t: i32) -> (i32, i32) {
    // x_edge(y_c) - ½px, times den, as a sub-pixel numerator:
    // (p.x - ½) * dy + (y_c - p.y) * dx, over SUBPIXEL * dy (< 2^39).
    // (On ARMv6-M each product from 16-bit halves, `mul_wide`, rather than
    // a call of `__aeabi_lmul`: `dy` is below 2^19 within the guard band;
    // ARMv6-M `demo` 7,965,098 -> 7,938,358 instructions, `rock` 6,596,192
    // -> 6,579,357.)
    let (a, b) = (p.x - HALF_PIXEL, dy.get() as i32);
    let den = dy.get() * SUBPIXEL as u32;
    let den = NonZeroU32::new(den).unwrap_or(NonZeroU32::MIN);
    // On ARMv6-M, factors within -2^14..2^14 (an edge on a screen below
    // 1,024 pixels a side) give products of at most 2^28 in magnitude: the sum
    // is exact in `i32`, from two `MULS` (ARMv6-M `demo` 7,925,692 ->
    // 7,885,964 instructions, `rock` 6,566,351 -> 6,541,339).
    let lift = |v: i32| v.wrapping_add(1 << 14) as u32;
    if crate::math::SPLIT && (lift(a) | lift(b) | lift(t) | lift(dx)) >> 15 == 0 {
        return ceil_div_rem32(a * b + t * dx, den);
    }
    let num = mul_wide(a, b) + mul_wide(t, dx);
    match i32::try_from(num) {
        Ok(n) => ceil_div_rem32(n, den),
        Err(_) => {
            let (c, r) = ceil_div_rem(num, den.get() as i64);
            (c as i32, r as i32)
        }
    }
}

/// `(q, r)` with `q = ceil(n / d)` and `r = q * d - n` in `0..d`, for `d > 0`.
#[inline]
pub(super) fn ceil_div_rem(n: i64, d: i64) -> (i64, i64) {
    // One truncating division gives both: truncation is the ceiling when
    // the remainder is not positive.
    let (q, r) = (n / d, n % d);
    if r > 0 {
        (q + 1, d - r)
    } else {
        (q, -r)
    }
}

/// [`ceil_div_rem`] for an `i32` numerator and a divisor below 2^31, as
/// unsigned divisions by a divisor known to be non-zero, which need no
/// checks for division by zero or overflow.
#[inline(always)]
pub(super) fn ceil_div_rem32(n: i32, d: NonZeroU32) -> (i32, i32) {
    if n > 0 {
        // ceil(n / d) = (n - 1) / d + 1, n - 1 >= 0.
        let m = n as u32 - 1;
        let (q, r) = div_rem_u32(m, d);
        ((q + 1) as i32, (d.get() - 1 - r) as i32)
    } else {
        // ceil(n / d) = -floor(-n / d), -n >= 0.
        let m = n.unsigned_abs();
        let (q, r) = div_rem_u32(m, d);
        (-(q as i32), r as i32)
    }
}

/// `(m / d, m % d)`: on ARMv6-M, whose division is a library call of
/// about a hundred instructions, through [`div_rem_compare`].
#[inline(always)]
pub(super) fn div_rem_u32(m: u32, d: NonZeroU32) -> (u32, u32) {
    if cfg!(microraster_narrow_multiply) {
        div_rem_compare(m, d)
    } else {
        (m / d, m % d)
    }
}

/// `(m / d, m % d)`, quotients below 4 (most edges' slopes in a mesh of
/// small triangles) by compares and subtractions, others by
/// [`div_rem_long`].
/// Each subtracted multiple of `d` is at most `m`, so nothing wraps.
/// (Four restoring steps, for quotients below 16, measured 60,000
/// instructions slower on ARMv6-M's `demo` frame than no fast path.)
#[inline(always)]
pub(super) fn div_rem_compare(m: u32, d: NonZeroU32) -> (u32, u32) {
    let dv = d.get();
    if m < dv {
        (0, m)
    } else if m - dv < dv {
        (1, m - dv)
    } else if m >> 2 < dv {
        // 2 <= m / d < 4 (m >= 2d, and m < 4d as floor(m / 4) < d).
        let m = m - 2 * dv;
        if m >= dv {
            (3, m - dv)
        } else {
            (2, m)
        }
    } else {
        div_rem_long(m, d)
    }
}

/// [`div_rem_compare`]'s larger quotients (`m >= 4 d`): those below 8
/// by two restoring steps (ARMv6-M `demo` 7,610,103 -> 7,590,628
/// instructions, `rock` 6,313,649 -> 6,299,985; three steps, for those
/// below 16, gained nothing more), those below 2^12 (where
/// `m < d 2^12`, [`Recip16::digit`]'s range) of divisors below 2^21 (an
/// edge or a far start's `16 dy` on any screen below 8,192 pixels a side,
/// [`Recip16::new_small`]) by one [`Recip16`] digit, about 50
/// instructions with the reciprocal's set-up
/// where ARMv6-M's library division takes about a hundred; others by the
/// division. Out of line: its callers are inlined into the scanline walk,
/// whose registers it would crowd. The edges' steps of more than 3
/// columns a row and the far starts that a tile's top clips by more than
/// 3 rows: ARMv6-M `demo` 7,704,424 -> 7,632,901 instructions, `rock`
/// 6,386,042 -> 6,330,524.
#[inline(never)]
fn div_rem_long(m: u32, d: NonZeroU32) -> (u32, u32) {
    let dv = d.get();
    debug_assert!(m >> 2 >= dv);
    if m >> 3 < dv {
        // 4 <= m / d < 8: two restoring steps (no multiple of `d` here
        // exceeds `m`, so none wraps).
        let (mut q, mut m) = (4, m - 4 * dv);
        if m >= 2 * dv {
            (q, m) = (q + 2, m - 2 * dv);
        }
        if m >= dv {
            (q, m) = (q + 1, m - dv);
        }
        return (q, m);
    }
    if m >> 12 < d.get() && d.get() >> 21 == 0 {
        Recip16::new_small(d).digit(m)
    } else {
        (m / d, m % d)
    }
}

/// Starts the lower half at `row`: the short edge becomes `b -> c`, on
/// the left or the right (`long_on_left`).
#[inline(always)]
pub(super) fn lower_half(
    b: SubPoint,
    c: SubPoint,
    row: i32,
    long_on_left: bool,
    left: &mut EdgeStepper,
    right: &mut EdgeStepper,
) {
    replace_short(
        long_on_left,
        EdgeStepper::new::<true>(b, c, row),
        left,
        right,
    );
}

/// Whether [`half`] writes to the slots left where
/// [`find_spans`](super::find_spans) calls it: on 32-bit cores, and in
/// the unit tests, which thereby walk as those cores do. The tile loop's
/// inline walk ([`find_spans_inline`](super::find_spans_inline), `half`'s
/// `INLINE`) writes so on 64-bit hosts too: there its slots left measured faster
/// (x86-64 `demo` 2,757,491 -> 2,752,483 instructions, `rock` 2,299,261
/// -> 2,295,649, `tri4` -14.3 K, `fill` 8.75 -> 8.74 a pixel), where the
/// out-of-line walk of the shader draws kept its count (with it,
/// `demo-textured-lit` +14.8 K).
pub(super) const SLOTS_LEFT: bool = cfg!(any(target_pointer_width = "32", test));

/// Walks the rows `row..stop` between the edges `left` and `right`,
/// recording the non-empty spans, clipped to columns `x0..x1`, in `out`
/// from `out[n]` on; returns the new count. (A triangle within the
/// columns is walked by [`half_packed`](super::packed::half_packed) instead.)
///
/// Where [`SLOTS_LEFT`] says, or for the tile loop's inline walk
/// (`INLINE`), a span is written to the first of the slots left, which a
/// non-empty one then leaves (a pointer and a length in registers, where
/// the other way keeps the base, the count and the length): fewer live
/// values in the loop on a 32-bit core, slower on a 64-bit host where
/// the walk was out of line (x86-64 `demo` +1.5 %; see [`SLOTS_LEFT`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn half<const INLINE: bool>(
    out: &mut [Span],
    mut n: usize,
    row: i32,
    stop: i32,
    left: &mut EdgeStepper,
    right: &mut EdgeStepper,
    x0: i32,
    x1: i32,
) -> usize {
    let (mut lc, mut le) = (left.col, left.err);
    let (mut rc, mut re) = (right.col, right.err);
    let (ls, lse, ld) = (left.step_col, left.step_err, left.den);
    let (rs, rse, rd) = (right.step_col, right.step_err, right.den);
    let slots = SLOTS_LEFT || INLINE;
    let len = out.len();
    let (out, mut rest) = out.split_at_mut(if slots { n.min(len) } else { len });
    for j in row..stop {
        let s = Span {
            j,
            x0: lc.max(x0),
            x1: rc.min(x1),
        };
        // Written whether empty or not, kept only if not: no branch.
        if slots {
            let r = core::mem::take(&mut rest);
            let Some(o) = r.first_mut() else {
                // No slot left: the caller's rows never exceed them.
                break;
            };
            *o = s;
            // A select of the two slices (see `half_packed`).
            rest = if s.x0 < s.x1 { &mut r[1..] } else { r };
        } else {
            if let Some(o) = out.get_mut(n) {
                *o = s;
            }
            n += (s.x0 < s.x1) as usize;
        }
        lc += ls;
        le += lse;
        if le >= 0 {
            le -= ld;
            lc -= 1;
        }
        rc += rs;
        re += rse;
        if re >= 0 {
            re -= rd;
            rc -= 1;
        }
    }
    (left.col, left.err, right.col, right.err) = (lc, le, rc, re);
    if slots {
        len - rest.len()
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ceil_div_rem_matches_definition() {
        for n in -50i64..50 {
            for d in 1i64..7 {
                let (q, r) = ceil_div_rem(n, d);
                assert!(q * d >= n && (q - 1) * d < n);
                assert_eq!(r, q * d - n);
                assert!((0..d).contains(&r));
            }
        }
    }

    /// The compares' quotient and remainder, and [`div_rem_long`]'s, are
    /// the division's: around every small multiple of every kind of
    /// divisor and around the reciprocal digit's bound, up to the `u32`
    /// range's end.
    #[test]
    fn div_rem_compare_is_the_division() {
        let mut next = crate::testing::rng();
        let check = |m: u32, d: u32| {
            let nz = NonZeroU32::new(d).unwrap();
            assert_eq!(div_rem_compare(m, nz), (m / d, m % d), "{m} / {d}");
        };
        let extremes = [u32::MAX, u32::MAX - 1, 1 << 31, (1 << 30) + 1, u32::MAX / 3];
        for k in 0..20_000u32 {
            let d = match k {
                0..2_000 => k + 1,
                2_000..2_005 => extremes[(k - 2_000) as usize],
                _ => (next(1 << 32) as u32 >> next(32)).max(1),
            };
            for m in [0, 1, u32::MAX, u32::MAX - 1, next(1 << 32) as u32] {
                check(m, d);
            }
            // The compares' quotients, then the reciprocal digit's
            // (below 2^12) and the division's beyond.
            let qs = [0, 1, 2, 3, 4, 5, 6, 15, 16, 4_094, 4_095, 4_096, 4_097];
            for q in qs.into_iter().chain([next(1 << 13), next(1 << 20)]) {
                for e in [-1i64, 0, 1] {
                    if let Ok(m) = u32::try_from(q as i64 * d as i64 + e) {
                        check(m, d);
                    }
                }
            }
        }
    }

    /// Both far starts are the `i64` ceiling of the numerator
    /// `(p.x - ½) dy + t dx` over `16 dy`: edges of every slope and
    /// height, from the compares' range to the guard band's (2^18).
    #[test]
    fn far_starts_are_the_division() {
        let mut next = crate::testing::rng();
        let mut signed = |bits: u64| next(2 << bits) as i32 - (1 << bits);
        for k in 0..200_000u32 {
            let bits = [4, 8, 13, 14, 15, 18][k as usize % 6];
            let (px, dx) = (signed(bits), signed(bits));
            let dy = (signed(bits).unsigned_abs() >> (k % 7)).max(1);
            // Any row of the edge, and a little past its ends.
            let t = (k as i32 % 40) - 4 + (signed(bits).unsigned_abs() % (dy * 2 + 1)) as i32;
            let nz = NonZeroU32::new(dy).unwrap();
            let num = (px - HALF_PIXEL) as i64 * dy as i64 + t as i64 * dx as i64;
            let (q, r) = ceil_div_rem(num, dy as i64 * SUBPIXEL as i64);
            let want = (q as i32, r as i32);
            assert_eq!(
                far_start(SubPoint::new(px, 0), dx, nz, t),
                want,
                "{px} {dx} {dy} {t}"
            );
            let (s, rs) = ceil_div_rem32(dx, nz);
            assert_eq!(
                far_start_stepped(px, nz, t, s, rs),
                want,
                "{px} {dx} {dy} {t}"
            );
        }
    }

    #[test]
    fn ceil_div_rem32_matches_the_i64_one() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for k in 0..100_000i32 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let n = match k % 3 {
                0 => (x >> 32) as i32,
                1 => (x >> 48) as i32 - (1 << 15),
                _ => k % 97 - 48,
            };
            let d = ((x as u32) >> (1 + x % 31) as u32).max(1);
            let (q, r) = ceil_div_rem32(n, NonZeroU32::new(d).unwrap());
            assert_eq!(
                (q as i64, r as i64),
                ceil_div_rem(n as i64, d as i64),
                "{n} / {d}"
            );
        }
    }

    #[test]
    fn ceil_div_rem_matches_definition_for_large_values() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let n = (x >> 20) as i64 - (1 << 43);
            let d = (x & 0xff_ffff) as i64 + 1;
            let (q, r) = ceil_div_rem(n, d);
            assert_eq!(q, -((-n).div_euclid(d)));
            assert_eq!(r, q * d - n);
        }
    }
}
