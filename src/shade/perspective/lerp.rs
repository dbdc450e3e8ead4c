//! A varying's value from a pixel's perspective weights in 32-bit
//! arithmetic, the same bits as [`PerspectiveSetup::values`]' `i64`
//! formula: [`lerp32`] where the core has no 32x32 to 64-bit multiply,
//! [`lerp_fit`] and [`fine_fit`] where the differences fit `i32`.

#[allow(unused_imports)] // the rustdoc links
use super::PerspectiveSetup;

/// Whether the target lacks a 32x32 to 64-bit multiply (ARMv6-M and
/// ARMv8-M Baseline, whose Thumb-1 has none; every Thumb-2 core has
/// `SMULL`). Set by the build script from the target's name: stable Rust
/// sets no `target_feature` cfg for ARM, so the test that was here,
/// `not(target_feature = "thumb2")`, held on the Cortex-M3 and M4F too,
/// which took the 32-bit form (demo-textured-lit +2.8 % on the M3, +4.0 %
/// on the M4F).
pub(super) const NARROW_MULTIPLY: bool = cfg!(microraster_narrow_multiply);

/// Whether the opaque span loops take the varyings' differences per
/// triangle in `i32` ([`PerspectiveSetup::values_fit`]): on 32-bit cores
/// with a 32x32 to 64-bit multiply (Cortex-M3 `fill-nearest-affine` 88.7
/// to 70.7 instructions per fragment). Not on ARMv6-M (no such multiply,
/// [`lerp32`] instead), nor on 64-bit hosts, where a 64-bit product is
/// one instruction anyway (with the differences set up for this alone,
/// `demo-textured-lit` took +0.8 % on x86-64).
pub(super) const FIT_PRODUCTS: bool = !NARROW_MULTIPLY && cfg!(not(target_pointer_width = "64"));

/// The low word of `a0 · 2^16 + 2^15 + d1 b1 + d2 b2` for `f0 = a0 · 2^16
/// + 2^15` and differences `d1`, `d2` wrapped (exact modulo 2^32): its
/// bits 16 to 31 are the low 16 bits of [`PerspectiveSetup::values`]'
/// value, whatever the differences (see
/// [`values_fit`](PerspectiveSetup::values_fit)).
#[inline(always)]
pub(super) fn fine_fit(f0: i32, d1: i32, d2: i32, (b1, b2): (i32, i32)) -> i32 {
    f0.wrapping_add(d1.wrapping_mul(b1))
        .wrapping_add(d2.wrapping_mul(b2))
}

/// `a0 + ((d1 b1 + d2 b2 + 2^15) >> 16)` wrapped to `i32`, for exact
/// differences `d1`, `d2` that fit `i32`: the bits of
/// [`PerspectiveSetup::values`]' `i64` formula (whose sum is the same, and
/// whose result is the same modulo 2^32), with 32x32 to 64-bit products.
/// `|b| < 2^20`, so the sum stays below 2^52.
#[inline(always)]
pub(super) fn lerp_fit(a0: i32, d1: i32, d2: i32, (b1, b2): (i32, i32)) -> i32 {
    let s = d1 as i64 * b1 as i64 + d2 as i64 * b2 as i64 + (1 << 15);
    a0.wrapping_add((s >> 16) as i32)
}

/// `a0 + ((d1 b1 + d2 b2 + 2^15) >> 16)` wrapped to `i32`, with
/// `d_i = a_i - a0` exact (up to 33 bits) and weights `b` in `0..=2^16`,
/// in 32-bit arithmetic: the same bits as the `i64` formula of
/// [`PerspectiveSetup::values`]. Each difference is split as
/// `d = h 2^16 + l` with `0 <= l < 2^16`; the `h` products are whole units
/// and only matter modulo 2^32, so they wrap; the `l` products are below
/// 2^32 each, and their sum's carry into bit 32 is counted by hand.
#[inline(always)]
pub(super) fn lerp32(a0: i32, a1: i32, a2: i32, (b1, b2): (i32, i32)) -> i32 {
    // The 33-bit differences as (high, low) halves: a wrapping subtract
    // gives the low 32 bits, the borrow the sign-extension.
    let split = |a: i32| -> (i32, u32) {
        let (d, borrow) = a.overflowing_sub(a0);
        // When it overflowed, the true difference is `d - 2^32` (a < a0)
        // or `d + 2^32`: its high half is `d >> 16` minus or plus 2^16.
        let h = (d >> 16).wrapping_add(if borrow {
            if a < a0 {
                -(1 << 16)
            } else {
                1 << 16
            }
        } else {
            0
        });
        (h, d as u32 & 0xFFFF)
    };
    let ((h1, l1), (h2, l2)) = (split(a1), split(a2));
    let (b1, b2) = (b1 as u32, b2 as u32);
    let (s, c1) = l1.wrapping_mul(b1).overflowing_add(l2.wrapping_mul(b2));
    let (s, c2) = s.overflowing_add(1 << 15);
    let low = (s >> 16).wrapping_add((c1 as u32 + c2 as u32) << 16);
    a0.wrapping_add(h1.wrapping_mul(b1 as i32))
        .wrapping_add(h2.wrapping_mul(b2 as i32))
        .wrapping_add(low as i32)
}
