//! `f32` to integer conversions in integer arithmetic only.
//!
//! `x as i32` on a core without an FPU is a call to a conversion routine
//! (`__aeabi_f2iz` and its kin) that a platform may replace: rp2040-hal
//! routes it to the RP2040 boot ROM's `float_to_int`, which rounds towards
//! −∞ where Rust truncates towards zero. A set-up that cast a negative
//! fraction through it would give different pixels on the Pico than on the
//! host. The functions here compute exactly what Rust's `as` defines
//! (truncation towards zero, saturation at the integer's bounds, NaN to 0)
//! from the float's bits, so no platform routine is involved. The crate's
//! set-up converts every float through them; firmware can too.

/// The integer part of a finite, non-NaN `x` with `|x| >= 1` as a sign and
/// a magnitude, or `None` for `|x| < 1`, zero and NaN. Saturates the
/// magnitude at `2^64 - 1`.
const fn split(x: f32) -> Option<(bool, u64)> {
    let bits = x.to_bits();
    let negative = bits >> 31 != 0;
    let biased = (bits >> 23) & 0xff;
    let fraction = bits & 0x7f_ffff;
    if biased == 0xff && fraction != 0 {
        return None; // NaN
    }
    if biased < 127 {
        return None; // |x| < 1, zero, subnormal
    }
    // x = ±m · 2^e with m the 24-bit significand.
    let m = (fraction | 0x80_0000) as u64;
    let e = biased as i32 - 150;
    let magnitude = if e >= 41 {
        u64::MAX // beyond every integer type here (infinity too)
    } else if e >= 0 {
        m << e
    } else {
        m >> -e
    };
    Some((negative, magnitude))
}

/// `x as i64`: truncated towards zero, saturated, NaN to 0, in integer
/// arithmetic only.
pub const fn f32_to_i64(x: f32) -> i64 {
    match split(x) {
        None => 0,
        Some((false, m)) => {
            if m > i64::MAX as u64 {
                i64::MAX
            } else {
                m as i64
            }
        }
        Some((true, m)) => {
            if m >= 1 << 63 {
                i64::MIN
            } else {
                -(m as i64)
            }
        }
    }
}

/// `x as i32`: truncated towards zero, saturated, NaN to 0, in integer
/// arithmetic only.
pub const fn f32_to_i32(x: f32) -> i32 {
    let v = f32_to_i64(x);
    if v < i32::MIN as i64 {
        i32::MIN
    } else if v > i32::MAX as i64 {
        i32::MAX
    } else {
        v as i32
    }
}

/// `x as u64`: truncated towards zero, saturated (negative values to 0),
/// NaN to 0, in integer arithmetic only.
pub const fn f32_to_u64(x: f32) -> u64 {
    match split(x) {
        Some((false, m)) => m,
        _ => 0,
    }
}

/// `x as u8`: truncated towards zero, saturated, NaN to 0, in integer
/// arithmetic only.
pub const fn f32_to_u8(x: f32) -> u8 {
    let v = f32_to_u64(x);
    if v > u8::MAX as u64 {
        u8::MAX
    } else {
        v as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every special and boundary value, then a sweep of bit patterns
    /// covering each exponent: the same as Rust's `as`.
    #[test]
    fn equal_to_rusts_casts() {
        let check = |x: f32| {
            assert_eq!(f32_to_i64(x), x as i64, "{x:e} ({:#x}) as i64", x.to_bits());
            assert_eq!(f32_to_i32(x), x as i32, "{x:e} as i32");
            assert_eq!(f32_to_u64(x), x as u64, "{x:e} as u64");
            assert_eq!(f32_to_u8(x), x as u8, "{x:e} as u8");
        };
        for x in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            0.999_999_94,
            -0.999_999_94,
            1.0,
            -1.0,
            1.5,
            -1.5,
            -2.5,
            255.5,
            256.0,
            2_147_483_520.0,
            -2_147_483_648.0,
            2_147_483_648.0,
            -2_147_483_904.0,
            9.223_371_5e18,
            9.223_372e18,
            -9.223_372e18,
            1.844_674_4e19,
            3.0e38,
            -3.0e38,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
        ] {
            check(x);
        }
        // 2^32 patterns are too many for a debug test; a stride that is
        // prime to 2^23 visits every exponent and many significands.
        let mut bits = 0u32;
        for _ in 0..400_000 {
            check(f32::from_bits(bits));
            bits = bits.wrapping_add(10_737);
        }
    }
}
