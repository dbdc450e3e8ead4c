//! Set-up trigonometry and square roots in `f32`, the same bits on every
//! target.
//!
//! [`sin_cos`] and [`tan`] (which [`Mat4::rotation_x`](super::Mat4::rotation_x) and its siblings and
//! [`Mat4::perspective`](super::Mat4::perspective) use) are within a few ulps at any angle, so that a
//! rotation matrix is orthonormal to `f32` precision and a perspective's
//! focal length exact to about 2^-22:
//!
//! * **Range reduction** by the method of Payne and Hanek (M. Payne and R.
//!   Hanek, *Radian reduction for trigonometric functions*, SIGNUM
//!   Newsletter 18, 1983), in integers: `|x| = m 2^e` is multiplied by
//!   only the 96 bits of 2/π that can matter (the earlier ones give whole
//!   turns, the later ones less than 2^-70 of a quarter turn), exactly,
//!   in `u128`. This gives the quadrant and the remainder in `[-π/4, π/4]`
//!   as an integer fraction, which is multiplied by π/2 and rounded once
//!   to `f32`. So `rotation_y(1e8)` turns by `1e8 mod 2π` as exactly as
//!   `rotation_y(0.5)` by 0.5; Cody–Waite reduction (`x - n π/2` with π/2
//!   split in two or three floats) is cheaper but exact only up to a few
//!   thousand radians in `f32`.
//! * **Kernels**: the Taylor series of sine (to `r⁹`) and cosine (to
//!   `r¹⁰`) on `[-π/4, π/4]`, whose truncation is below 2^-28 of the
//!   result, by Horner's rule in `f32`, the remainder carried as two
//!   `f32`s and `r²` made exact by Dekker's product where it matters.
//!
//! Against `f64`, sine and cosine are within 1 ulp (0.79 at worst, checked
//! once for every finite `f32`), the tangent within 3 ulps (2.21 at worst
//! over every 16th `f32`); the tests check every 8191st `f32` of either
//! sign and the worst cases.
//!
//! Only integer arithmetic and the basic IEEE operations are used (see
//! the [parent module](super)); [`sqrt`] refines micromath's estimate with
//! Newton steps.

use super::soft_float::{add, mul, sub};
use super::{times_pow2, SOFT_FLOAT};

/// Square root to full `f32` precision: micromath's bit-trick estimate
/// (about 5 % off) refined by three Newton steps. Only basic IEEE
/// operations, so it gives the same bits on every target.
pub fn sqrt(x: f32) -> f32 {
    if SOFT_FLOAT {
        // The same tests by the bits, without soft-float compares: a zero
        // of either sign and infinity are themselves, a NaN or a negative
        // value (whose bits are above infinity's) NaN.
        let b = core::hint::black_box(x.to_bits());
        if b << 1 == 0 || b == 0x7f80_0000 {
            return x;
        }
        if b > 0x7f80_0000 {
            return f32::NAN;
        }
    } else {
        if x.is_nan() || x < 0.0 {
            return f32::NAN;
        }
        if x == 0.0 || x == f32::INFINITY {
            return x;
        }
    }
    let mut y = micromath::F32Ext::sqrt(x);
    for _ in 0..3 {
        // The sum through `add` and the half by the exponent where `f32`
        // is in software (the same bits).
        y = times_pow2(add(y, x / y), 0.5);
    }
    y
}

/// 2/π in binary, most significant first: a zero word (the bits before
/// the point, and the window's reach below them for angles under 2^26),
/// then the first 256 bits after the point: enough for the reduction of
/// the largest `f32` (2^128 needs the bits from the 103rd on, and 96 of
/// them).
const TWO_OVER_PI: [u64; 5] = [
    0,
    0xa2f9_836e_4e44_1529,
    0xfc27_57d1_f534_ddc0,
    0xdb62_9599_3c43_9041,
    0xfe51_63ab_debb_c561,
];

/// π/2 in 2.62 fixed point, rounded to nearest.
const FRAC_PI_2_Q62: u64 = 0x6487_ed51_10b4_611a;

/// Payne–Hanek reduction of a finite `a >= π/4`: the quadrant `n mod 4` and
/// `r = a - n π/2` in `[-π/4, π/4]` as the sum of two `f32`s, the nearest
/// to `r` and what it misses (to 2^-40 of `r`), with `n` the nearest
/// integer to `a · 2/π`.
///
/// `a = m 2^e` with a 24-bit integer `m`. The bits of 2/π before index
/// `e - 1` contribute multiples of 4 to `a · 2/π` (whole turns), so only a
/// 96-bit window of 2/π from there on is multiplied by `m`, exactly, in
/// `u128` (bits at index 0 and below, before the point, are zero); the
/// bits after the window change the product by less than `m 2^-94`,
/// 2^-70 quarter turns. The window starts at `e - 1` for every `e`, so
/// the product's point is always at bit 94 and every shift but the
/// window's is by a constant. The fraction of a quarter turn that is left
/// is then multiplied by π/2 in integers and split into two `f32`s.
fn reduce(a: f32) -> (u32, f32, f32) {
    const SH: u32 = 94;
    let bits = a.to_bits();
    let m = u128::from((bits & 0x7f_ffff) | 0x80_0000);
    // a >= π/4, so e >= -24; a finite, so e <= 104.
    let e = (bits >> 23) as i32 - 150;
    // The window: bits e - 1 ..= e + 94 of 2/π (the first bit after the
    // point is bit 1, at 64 in the table), as an integer.
    let start = (e + 62) as usize; // 38 ..= 166
    let (k, off) = (start / 64, start % 64);
    let hi = (u128::from(TWO_OVER_PI[k]) << 64) | u128::from(TWO_OVER_PI[k + 1]);
    let window = match off {
        0 => hi,
        _ => (hi << off) | u128::from(TWO_OVER_PI[k + 2] >> (64 - off)),
    } >> 32;
    // a · 2/π = m · window · 2^-94, modulo 4 and the ignored tail.
    let p = (m * window) & ((1u128 << (SH + 2)) - 1);
    let one = 1u128 << SH;
    let (mut n, frac) = ((p >> SH) as u32, p & (one - 1));
    // The nearest quadrant: a fraction above one half counts from the next.
    let negative = frac >= one >> 1;
    let mag = if negative {
        n += 1;
        one - frac
    } else {
        frac
    };
    if mag == 0 {
        return (n & 3, 0.0, 0.0);
    }
    // |fraction| = top 2^(64 - lz - sh), top with its highest bit set; times
    // π/2 (2^62 scaled) that is r = r_top 2^(66 - lz - lz2 - sh).
    let lz = mag.leading_zeros();
    let top = ((mag << lz) >> 64) as u64;
    let prod = u128::from(top) * u128::from(FRAC_PI_2_Q62);
    let lz2 = prod.leading_zeros();
    let r_top = ((prod << lz2) >> 64) as u64;
    // r <= π/4 and r_top >= 2^63, so the exponent is at most -64; a
    // remainder below 2^-60 (no f32 comes that close to a multiple of π/2)
    // would take the power of two out of f32's normal range: zero then.
    let k = 66 - lz as i32 - lz2 as i32 - SH as i32 + 64;
    if !(-126..=0).contains(&k) {
        return (n & 3, 0.0, 0.0);
    }
    let scale = f32::from_bits(((127 + k) as u32) << 23);
    // r_top's top 24 bits rounded (half up), and the rest, below 2^39 in
    // magnitude; both exact or once rounded as f32, then scaled by
    // powers of two, exactly.
    let head = ((r_top >> 39) + 1) >> 1; // at most 2^24
                                         // Below 2^39 in magnitude, so exact from the wrapping difference.
    let tail = r_top.wrapping_sub(head << 40) as i64;
    let unit = (1.0 / 16_777_216.0) * scale; // 2^(k - 24)
    let hi = head as f32 * unit;
    let lo = tail as f32 * (1.0 / 1_099_511_627_776.0) * unit;
    match negative {
        true => (n & 3, -hi, -lo),
        false => (n & 3, hi, lo),
    }
}

/// `a²` as the sum of two `f32`s, exactly (Dekker's product, with
/// Veltkamp's split of `a` into two halves of 12 bits; no fused
/// multiply-add needed), for `|a| <= 1`.
///
/// The products through [`mul`] and [`times_pow2`], the same bits without
/// the library's multiply where `f32` is in software (as in
/// [`sin_cos_kernel`]).
fn square_exact(a: f32) -> (f32, f32) {
    let c = mul(4097.0, a);
    let ah = sub(c, sub(c, a));
    let al = sub(a, ah);
    let z = mul(a, a);
    (
        z,
        add(
            add(sub(mul(ah, ah), z), mul(times_pow2(ah, 2.0), al)),
            mul(al, al),
        ),
    )
}

/// sin(r) and cos(r) for `r = hi + lo`, `|r| <= π/4`, `|lo|` below 2^-23
/// of `|hi|`: the Taylor series of sine to r⁹ and of cosine to r¹⁰ (the
/// next terms are below 2^-28 of the results) by Horner's rule, with `lo`
/// to first order. The leading terms are added last: `hi` for the sine;
/// for the cosine `1 - hi²/2` with `hi²` exact and the rounding error of
/// the subtraction recovered (it is exact in `f32`: `1 - w` by Sterbenz's
/// lemma).
///
/// The products through [`mul`] and the halves through [`times_pow2`]:
/// the same bits, where `f32` is in software without the library's
/// multiply (some 100 instructions each on ARMv6-M; the kernel has
/// nineteen, five a frame of the demo's camera and model).
fn sin_cos_kernel(hi: f32, lo: f32) -> (f32, f32) {
    let (z, z_err) = square_exact(hi);
    let p = add(
        -1.0 / 6.0,
        mul(
            z,
            add(
                1.0 / 120.0,
                mul(z, add(-1.0 / 5_040.0, mul(z, 1.0 / 362_880.0))),
            ),
        ),
    );
    let half = times_pow2(z, 0.5);
    let s = add(hi, add(mul(mul(hi, z), p), mul(lo, sub(1.0, half))));
    let q = add(
        1.0 / 24.0,
        mul(
            z,
            add(
                -1.0 / 720.0,
                mul(z, add(1.0 / 40_320.0, mul(z, -1.0 / 3_628_800.0))),
            ),
        ),
    );
    let w = sub(1.0, half);
    let c = add(
        w,
        add(
            sub(sub(1.0, w), half),
            sub(mul(mul(z, z), q), add(times_pow2(z_err, 0.5), mul(hi, lo))),
        ),
    );
    (s, c)
}

/// Sine and cosine of `x` radians, each within 1 ulp of the exact value
/// for every finite `f32` (NaN for infinities and NaN), with one range
/// reduction for both (see [the method](crate::math#trigonometry)).
///
/// ```
/// let (s, c) = microraster::math::sin_cos(1e8);
/// // sin(1e8) = 0.9316390..., cos(1e8) = -0.3633851...
/// assert!((s - 0.931_639_0).abs() < 1e-6 && (c + 0.363_385_1).abs() < 1e-6);
/// ```
pub fn sin_cos(x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    let a = x.abs();
    // `a` is finite and not negative: where `f32` is in software, its
    // order is that of its bits (no soft-float compare).
    let small = match SOFT_FLOAT {
        true => a.to_bits() < core::f32::consts::FRAC_PI_4.to_bits(),
        false => a < core::f32::consts::FRAC_PI_4,
    };
    let (n, hi, lo) = if small { (0, a, 0.0) } else { reduce(a) };
    let (s, c) = sin_cos_kernel(hi, lo);
    let (s, c) = match n {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    };
    (if x.is_sign_negative() { -s } else { s }, c)
}

/// Tangent of `x` radians, `sin / cos` from [`sin_cos`]: within 3 ulps of
/// the exact value for every finite `f32`.
///
/// ```
/// let t = microraster::math::tan(core::f32::consts::FRAC_PI_8);
/// assert!((t - 0.414_213_57).abs() <= 6e-8); // √2 - 1
/// ```
pub fn tan(x: f32) -> f32 {
    let (s, c) = sin_cos(x);
    s / c
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The distance of `r` from the exact `e`, in units of the last place
    /// of `e` rounded to `f32`.
    pub(crate) fn ulps(r: f32, e: f64) -> f64 {
        let b = (e as f32).abs().to_bits().min(0x7f7f_ffff);
        let ulp = (f32::from_bits(b + 1) - f32::from_bits(b)) as f64;
        (r as f64 - e).abs() / ulp
    }

    /// Every 8191st `f32` of either sign, zero to the largest finite value,
    /// and angles that are hard for range reduction (near multiples of π/2,
    /// where the window of 2/π moves, the largest): sine and cosine within
    /// 1 ulp of `f64`, tangent within 3 ulps (an exhaustive run found 0.79
    /// and 2.21 at worst; the three worst inputs are here).
    #[test]
    fn trigonometry_is_within_an_ulp_over_the_whole_range() {
        let hard = [
            1e7f32,
            1e8,
            1e30,
            f32::MAX,
            core::f32::consts::FRAC_PI_2,
            core::f32::consts::PI,
            f32::from_bits(0x4dc9_0fdb), // 2^28 π/2
            f32::from_bits(0x4080_0000), // 4: the window starts to move
            f32::from_bits(0x5f80_0000), // 2^64: the window crosses a word
            f32::from_bits(0x48ab_f838), // sine's worst, 0.79 ulp
            f32::from_bits(0x6916_2f28), // cosine's worst, 0.78 ulp
            f32::from_bits(0x4016_e450), // the tangent's worst found, 2.21 ulps
            f32::from_bits(0x5922_8000), // 2.85e15, within 1e-8 of k π/2
            f32::from_bits(0x6a80_c25b),
        ];
        let sweep = (0..0x7f80_0000u32).step_by(8191).map(f32::from_bits);
        let (mut worst_sc, mut worst_t) = (0.0f64, 0.0f64);
        for x in sweep.chain(hard).flat_map(|x| [x, -x]) {
            let (s, c) = sin_cos(x);
            let t = tan(x);
            let xd = x as f64;
            let (es, ec, et) = (ulps(s, xd.sin()), ulps(c, xd.cos()), ulps(t, xd.tan()));
            assert!(
                es < 1.0 && ec < 1.0,
                "{x:e}: sin {s} ({es} ulp), cos {c} ({ec} ulp)"
            );
            assert!(et < 3.0, "{x:e}: tan {t} ({et} ulp)");
            worst_sc = worst_sc.max(es).max(ec);
            worst_t = worst_t.max(et);
        }
        // The bounds are close to what is reached: the sweep is not trivial.
        assert!(worst_sc > 0.78 && worst_t > 2.2, "{worst_sc} {worst_t}");
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan() && tan(x).is_nan());
        }
    }

    #[test]
    fn sqrt_is_accurate() {
        for &x in &[1e-6f32, 0.01, 0.5, 1.0, 2.0, 3.0, 10.0, 12345.0, 1e9] {
            let r = sqrt(x);
            assert!((r * r - x).abs() <= x * 1e-6, "{x}: {r}");
        }
        assert_eq!(sqrt(0.0), 0.0);
        assert!(sqrt(-1.0).is_nan());
    }
}
