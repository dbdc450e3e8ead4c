//! The exact product of two `i32` as an `i64`, without a 64-bit multiply
//! where the core has none.
//!
//! ARMv6-M (Cortex-M0/M0+, the RP2040) has only a 32x32->32 multiply:
//! `a as i64 * b as i64` becomes a call of `__aeabi_lmul`, a full 64x64
//! product of about 37 instructions plus the call. [`mul_wide`] builds the
//! same product from four 16x16 products instead, each exact in 32 bits,
//! and a few 64-bit shifts and adds. Other targets have a widening
//! multiply instruction and keep the plain product.

/// Whether the core lacks a 32x32 to 64-bit multiply (ARMv6-M, ARMv8-M
/// Baseline): `build.rs` sets `microraster_narrow_multiply` from the
/// target's name, the one test the span loops use too.
pub(crate) const SPLIT: bool = cfg!(microraster_narrow_multiply);

/// `a b`, exactly (`a as i64 * b as i64`).
#[inline(always)]
pub(crate) fn mul_wide(a: i32, b: i32) -> i64 {
    if SPLIT {
        mul_split(a, b)
    } else {
        a as i64 * b as i64
    }
}

/// `v a` exactly where the upper word of `v` (rounded for a negative low
/// word) times `a` fits `i32`, from 32-bit pieces: with `v = h 2^32 + l`,
/// `l` the signed low word and `h` the rest, `v a = (h a) 2^32 + l a`,
/// the first a 32-bit product, the second [`mul_wide`]'s (four 16-bit
/// products on ARMv6-M, where an `i64` product is a library call of
/// about 40 instructions). Used there for the wide perspective planes'
/// constants and the draw's box test.
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
#[inline(always)]
pub(crate) fn mul_wide_by_narrow(v: i64, a: i32) -> i64 {
    let l = v as i32;
    // `l` negative borrows 2^32 from the upper word: `h` one more.
    let h = (v >> 32) as i32 - (l >> 31);
    (((h * a) as i64) << 32) + mul_wide(l, a)
}

/// [`mul_wide`] from 16-bit halves: with `a = ah 2^16 + al` (`ah` signed,
/// `-2^15 <= ah < 2^15`; `0 <= al < 2^16`) and likewise `b`,
/// `a b = ah bh 2^32 + (ah bl + al bh) 2^16 + al bl`. Each product fits its
/// 32-bit type: `al bl < 2^32` unsigned, `|ah bl|` and `|al bh|` below
/// `2^31`, `|ah bh| <= 2^30`; the sum is exact in `i64` (`|a b| <= 2^62`).
#[inline(always)]
pub(crate) fn mul_split(a: i32, b: i32) -> i64 {
    let (ah, al) = (a >> 16, a & 0xffff);
    let (bh, bl) = (b >> 16, b & 0xffff);
    let lo = (al as u32 * bl as u32) as i64;
    let mid = (ah * bl) as i64 + (al * bh) as i64;
    let hi = (ah * bh) as i64;
    (hi << 32) + (mid << 16) + lo
}

/// [`mul_split`] for unsigned operands: `a b = ah bh 2^32 + (ah bl + al bh)
/// 2^16 + al bl` with every half below `2^16`, each product below `2^32`.
#[inline(always)]
pub(crate) fn mul_split_u(a: u32, b: u32) -> u64 {
    let (ah, al) = (a >> 16, a & 0xffff);
    let (bh, bl) = (b >> 16, b & 0xffff);
    let mid = (ah * bl) as u64 + (al * bh) as u64;
    (((ah * bh) as u64) << 32) + (mid << 16) + (al * bl) as u64
}

/// The upper 64 bits of the 128-bit product `m r`:
/// `((m as u128 * r as u128) >> 64) as u64`. On ARMv6-M from four
/// [`mul_split_u`] products of the 32-bit halves (schoolbook: the middle
/// column, at most `3 (2^32 - 1)`, carries into the upper word). Not
/// for the attribute set-up, where it measured slower: see
/// `Reciprocal::div_split`.
#[inline(always)]
pub(crate) fn mul_high_u64(m: u64, r: u64) -> u64 {
    if SPLIT {
        mul_high_split(m, r)
    } else {
        ((m as u128 * r as u128) >> 64) as u64
    }
}

/// [`mul_high_u64`] by halves, each product from [`mul_split_u`].
#[inline(always)]
pub(crate) fn mul_high_split(m: u64, r: u64) -> u64 {
    let (mh, ml) = ((m >> 32) as u32, m as u32);
    let (rh, rl) = ((r >> 32) as u32, r as u32);
    let (p0, p1) = (mul_split_u(ml, rl), mul_split_u(ml, rh));
    let (p2, p3) = (mul_split_u(mh, rl), mul_split_u(mh, rh));
    let mid = (p0 >> 32) + (p1 & 0xffff_ffff) + (p2 & 0xffff_ffff);
    p3 + (p1 >> 32) + (p2 >> 32) + (mid >> 32)
}

/// The lower 64 bits of `q d`, `q.wrapping_mul(d)`: on ARMv6-M one widening
/// product of the lower halves ([`mul_split_u`]) and two 32-bit products.
#[inline(always)]
pub(crate) fn mul_low_u64(q: u64, d: u64) -> u64 {
    if SPLIT {
        mul_low_split(q, d)
    } else {
        q.wrapping_mul(d)
    }
}

/// [`mul_low_u64`] by halves.
#[inline(always)]
pub(crate) fn mul_low_split(q: u64, d: u64) -> u64 {
    let (qh, ql) = ((q >> 32) as u32, q as u32);
    let (dh, dl) = ((d >> 32) as u32, d as u32);
    let cross = qh.wrapping_mul(dl).wrapping_add(ql.wrapping_mul(dh));
    mul_split_u(ql, dl).wrapping_add((cross as u64) << 32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_product_is_exact() {
        let edges = [
            i32::MIN,
            i32::MIN + 1,
            -65_537,
            -65_536,
            -65_535,
            -32_768,
            -1,
            0,
            1,
            32_767,
            65_535,
            65_536,
            65_537,
            i32::MAX - 1,
            i32::MAX,
        ];
        for &a in &edges {
            for &b in &edges {
                assert_eq!(mul_split(a, b), a as i64 * b as i64, "{a} * {b}");
            }
        }
        let mut next = crate::testing::rng();
        for _ in 0..1_000_000 {
            let a = next(1 << 32) as u32 as i32;
            let b = next(1 << 32) as u32 as i32;
            assert_eq!(mul_split(a, b), a as i64 * b as i64, "{a} * {b}");
            assert_eq!(mul_wide(a, b), a as i64 * b as i64, "{a} * {b}");
            let (a, b) = (a as u32, b as u32);
            assert_eq!(mul_split_u(a, b), a as u64 * b as u64, "{a} * {b}");
        }
    }

    #[test]
    fn split_64_bit_products_are_exact() {
        let mut next = crate::testing::rng();
        let edges = [
            0u64,
            1,
            0xffff,
            1 << 32,
            u32::MAX as u64,
            u64::MAX - 1,
            u64::MAX,
        ];
        let check = |m: u64, r: u64| {
            let high = ((m as u128 * r as u128) >> 64) as u64;
            assert_eq!(mul_high_split(m, r), high, "{m} * {r}");
            assert_eq!(mul_high_u64(m, r), high, "{m} * {r}");
            assert_eq!(mul_low_split(m, r), m.wrapping_mul(r), "{m} * {r}");
            assert_eq!(mul_low_u64(m, r), m.wrapping_mul(r), "{m} * {r}");
        };
        for &m in &edges {
            for &r in &edges {
                check(m, r);
            }
        }
        for _ in 0..1_000_000 {
            // `rng` gives values below its argument: two draws make 64 bits.
            let m = (next(1 << 32) << 32 | next(1 << 32)) >> next(64);
            let r = (next(1 << 32) << 32 | next(1 << 32)) >> next(64);
            check(m, r);
        }
    }
}
