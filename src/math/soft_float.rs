//! Short cuts around `f32` arithmetic where it is in software (Arm cores
//! without an FPU, where each operation is a library call of some 40 to
//! 100 instructions): the same bits as the IEEE operations, from the
//! floats' bit patterns.

use super::Vec3;

/// Whether `f32` arithmetic is in software (ARM cores without an FPU),
/// where the library takes short cuts around it: there [`Mat4`](super::Mat4)'s product
/// skips the terms of zeros and ones, whose tests cost more than the
/// products they save where an FPU does them (the Cortex-M4F's `demo`
/// frame took 2,065 instructions more for an affine matrix's last row). Not in builds optimised
/// for size (`microraster_size`: the OLED firmware's flash took 320 B
/// more). The library's own tests take the short cut too, to compare it
/// with the full product.
/// The build script's `microraster_soft_float` says which builds; the
/// items that exist only there are gated by the same `cfg`.
pub(crate) const SOFT_FLOAT: bool = cfg!(any(test, microraster_soft_float));

/// `x * k` for `k` a positive normal power of two (an [`Inverse3`](super::Inverse3)'s
/// scale), the same bits: where `f32` arithmetic is in software
/// ([`SOFT_FLOAT`]), a zero is itself and a normal `x` whose product is
/// normal has `k`'s exponent added to its own (exact), without the
/// soft-float multiply (some 45 instructions on the Cortex-M3, twelve a
/// draw's light set-up); any other `x` is multiplied.
#[inline]
pub(crate) fn times_pow2(x: f32, k: f32) -> f32 {
    if !SOFT_FLOAT {
        return x * k;
    }
    // The bits through `black_box`: LLVM turned the zero test into a
    // soft-float compare (a library call each, as in `Mat4`'s product).
    // (Not where the product is kept: the Cortex-M4F's `demo` took 76
    // instructions more through it.)
    let (b, kb) = (core::hint::black_box(x.to_bits()), k.to_bits());
    let field = (b >> 23) & 0xff;
    let sum = field as i32 + (kb >> 23) as i32 - 127;
    match b << 1 == 0 {
        true => x,
        false if field != 0 && field != 255 && (1..=254).contains(&sum) => {
            f32::from_bits(b.wrapping_add(kb.wrapping_sub(127 << 23)))
        }
        false => x * k,
    }
}

/// Whether [`mul`] takes its integer form: where `f32` arithmetic is in
/// software and the core has no 32 x 32 -> 64-bit multiply (ARMv6-M,
/// whose library multiply takes a 64-bit library product too, some 140
/// instructions in all), and in the library's own tests. Not on the
/// Cortex-M3, whose library multiply has `UMULL`: its `demo` frame took
/// 631 instructions more with it.
const SOFT_MUL: bool = cfg!(any(
    test,
    all(microraster_soft_float, microraster_narrow_multiply)
));

/// `x * y`, the same bits: where [`SOFT_MUL`] says, two normal operands
/// whose product is normal (before or by its rounding: one past the
/// largest rounds to infinity, as the IEEE product does) are multiplied
/// in integers ([`mul_normal`]), a zero by a finite value is a zero; any
/// other pair is multiplied.
#[inline]
pub(crate) fn mul(x: f32, y: f32) -> f32 {
    if !SOFT_MUL {
        return x * y;
    }
    mul_normal(x, y)
}

/// [`mul`]'s integer form, out of line (one copy for the set-up's
/// dozens of products: inlined, each took some 120 B of flash and
/// spilled its caller's values). The significands' product `p`
/// (`2^46 <= p < 2^48`) is shifted to 48 bits, its top 24 the result's
/// significand and the 24 below it what rounds it to nearest, ties to
/// even: adding `2^23 - 1` and the last bit of the significand carries
/// into it exactly when the rest is above half, or half and the last bit
/// odd. A carry to `2^24` makes the next power of two (the field
/// incremented through the implicit bit's sum).
#[inline(never)]
fn mul_normal(x: f32, y: f32) -> f32 {
    // The bits through `black_box`: LLVM turned the zero tests into
    // soft-float compares (a library call each, as in `times_pow2`).
    let (a, b) = (
        core::hint::black_box(x.to_bits()),
        core::hint::black_box(y.to_bits()),
    );
    let (fa, fb) = ((a >> 23) & 0xff, (b >> 23) & 0xff);
    // A zero by a finite value: a zero, its sign the operands' (the
    // set-up's axes and rotations have many zero elements: `look_at`'s and
    // `Inverse3`'s cross products took the library's multiply 144 times a
    // frame of `demo-textured-lit`).
    if (a << 1 == 0 || b << 1 == 0) && fa != 255 && fb != 255 {
        return f32::from_bits((a ^ b) & 0x8000_0000);
    }
    // Both fields in 1..=254: both operands normal.
    if fa.wrapping_sub(1) < 254 && fb.wrapping_sub(1) < 254 {
        let (ma, mb) = ((a & 0x7f_ffff) | 0x80_0000, (b & 0x7f_ffff) | 0x80_0000);
        let p = if super::wide::SPLIT {
            super::wide::mul_split_u(ma, mb)
        } else {
            u64::from(ma) * u64::from(mb)
        };
        // The product's field, its significand in [1, 2).
        let (p, field) = if p >> 47 != 0 {
            (p, (fa + fb) as i32 - 126)
        } else {
            (p << 1, (fa + fb) as i32 - 127)
        };
        if (1..=254).contains(&field) {
            let (q, rest) = ((p >> 24) as u32, p as u32 & 0xff_ffff);
            let sig = q + ((rest + 0x7f_ffff + (q & 1)) >> 24);
            let sign = (a ^ b) & 0x8000_0000;
            return f32::from_bits(sign | ((((field - 1) as u32) << 23) + sig));
        }
    }
    x * y
}

/// Whether [`add`] takes its integer form: where `f32` arithmetic is in
/// software (the library's addition is some 65 instructions on the
/// Cortex-M3, with its entry), and in the library's own tests.
pub(crate) const SOFT_ADD: bool = cfg!(any(test, microraster_soft_float));

/// `x + y`, the same bits: where [`SOFT_ADD`] says, two normal operands
/// whose sum is normal (or overflows by its rounding) are added in
/// integers ([`add_normal`]), a finite value plus a zero is that value
/// (two zeros `-0` only if both are); any other pair is added.
#[inline]
pub(crate) fn add(x: f32, y: f32) -> f32 {
    if !SOFT_ADD {
        return x + y;
    }
    add_normal(x, y)
}

/// [`add`]'s integer form, out of line (one copy). With `a` the operand
/// of the larger magnitude and `d` the exponents' difference, a `d` of
/// 26 or more leaves `a` (`|b|` is below a quarter of `a`'s ulp, and
/// below half of the ulp under it where `a` is a power of two). Else
/// both significands (the implicit bit included) are shifted up by 6
/// (below 2^30), `b`'s then down by `d`, the bits it loses kept as one
/// sticky bit (its lowest): the sum or difference then lies in the same
/// open interval between two multiples of 2 as the exact one, and
/// rounding (at bit 6, or bit 5 for a sum that carried) needs no more
/// (where a difference is normalised by more than one place, `d <= 1`
/// and nothing was lost). The significand is rounded to nearest, ties
/// to even, as in [`mul_normal`], a carry to 2^24 making the next power
/// of two. A difference of zero is `+0`. A finite value plus a zero is
/// that value (two zeros `-0` only if both are); subnormals, infinities
/// and NaNs are added by the library, as is a result outside the normal
/// range.
#[inline(never)]
fn add_normal(x: f32, y: f32) -> f32 {
    let (a, b) = (x.to_bits(), y.to_bits());
    let (a, b) = if a << 1 >= b << 1 { (a, b) } else { (b, a) };
    let (fa, fb) = (a << 1 >> 24, b << 1 >> 24);
    // `fb <= fa`: both fields in 1..=254, both operands normal.
    if fa.wrapping_sub(1) < 254 && fb != 0 {
        let d = fa - fb;
        if d >= 26 {
            return f32::from_bits(a);
        }
        let ma = ((a & 0x7f_ffff) | 0x80_0000) << 6;
        let mb = ((b & 0x7f_ffff) | 0x80_0000) << 6;
        // The bits `mb >> d` loses (none where `d` is 0: `mb`'s lowest
        // bit is clear).
        let lost = (mb << 1) << (31 - d);
        let mb = (mb >> d) | u32::from(lost != 0);
        let (m, field) = if (a ^ b) >> 31 == 0 {
            let s = ma + mb;
            match s >> 30 {
                0 => (s, fa),
                _ => ((s >> 1) | (s & 1), fa + 1),
            }
        } else {
            // `ma >= mb`: `|a| >= |b|`.
            let s = ma - mb;
            if s == 0 {
                return 0.0;
            }
            let lz = s.leading_zeros() - 2;
            (s << lz, fa.wrapping_sub(lz))
        };
        if field.wrapping_sub(1) < 254 {
            let sig = m >> 6;
            let sig = sig + (((m & 0x3f) + 0x1f + (sig & 1)) >> 6);
            return f32::from_bits((a & 0x8000_0000) | (((field - 1) << 23) + sig));
        }
        return x + y;
    }
    // A finite `a` plus a zero: `a`, but for a zero `a`, whose sum is `-0`
    // only if both are (the set-up adds many zeros: a plane's sums of a
    // projection's rows, a kernel's first-order term at a remainder of
    // zero). The bits through `black_box` here only: LLVM turns the zero
    // tests into soft-float compares (as in `mul_normal`).
    let (a, b) = core::hint::black_box((a, b));
    if b << 1 == 0 && fa != 255 {
        return f32::from_bits(if a << 1 == 0 { a & b } else { a });
    }
    x + y
}

/// [`Vec3::dot`] through [`mul`] and [`add`]: the same bits, in the same order.
#[inline]
pub(crate) fn dot(a: Vec3, b: Vec3) -> f32 {
    if !SOFT_MUL && !SOFT_ADD {
        // The method itself: the size build of the OLED firmware kept it
        // out of line, and took 252 B more with its products inlined.
        return a.dot(b);
    }
    add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z))
}

/// [`Vec3::cross`] through [`mul`] and [`add`]: the same bits.
#[inline]
pub(crate) fn cross(a: Vec3, b: Vec3) -> Vec3 {
    if !SOFT_MUL && !SOFT_ADD {
        // The method itself, as in `dot`.
        return a.cross(b);
    }
    Vec3::new(
        sub(mul(a.y, b.z), mul(a.z, b.y)),
        sub(mul(a.z, b.x), mul(a.x, b.z)),
        sub(mul(a.x, b.y), mul(a.y, b.x)),
    )
}

/// `x - y` through [`add`] (`x - y` is `x + (-y)` in IEEE arithmetic,
/// the same bits).
#[inline]
pub(crate) fn sub(x: f32, y: f32) -> f32 {
    add(x, -y)
}

/// `a - b` through [`sub`], the same bits.
#[inline]
pub(crate) fn sub_vec(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z))
}

/// [`Vec3::normalize`] through [`dot`] where `f32` arithmetic is in
/// software, the same bits: a squared length that is a positive normal
/// `f32` (finite and at least `f32::MIN_POSITIVE`, tested by its bits)
/// takes the same square root and divisions; any other vector is
/// [`Vec3::normalize`]'s.
#[inline]
pub(crate) fn normalize(v: Vec3) -> Option<Vec3> {
    if !SOFT_FLOAT {
        return v.normalize();
    }
    let sq = dot(v, v);
    if (0x0080_0000..0x7f80_0000).contains(&core::hint::black_box(sq.to_bits())) {
        let len = super::sqrt(sq);
        return Some(Vec3::new(v.x / len, v.y / len, v.z / len));
    }
    v.normalize()
}

/// Division of `f32`s by one positive normal `f32`, correctly rounded
/// (the same bits as `/`), through an integer reciprocal of the
/// divisor's significand: [`Mat4::normalized`](super::Mat4::normalized)'s sixteen divisions by its
/// largest element where `f32` arithmetic is in software.
///
/// With `a` and `b` the dividend's and the divisor's significands (24
/// bits, `2^23 <= a, b < 2^24`) and `a' = a` or `2 a` (whichever makes
/// `a' >= b`), the quotient's significand rounded to 24 bits is that of
/// `q = floor(a' 2^24 / b)`, which has 25 bits, rounded by its last: a
/// quotient is never exactly halfway between two 24-bit values (then
/// `a' 2^25 = (2 Q + 1) b` for an integer `Q >= 2^23`, and the odd part
/// of the left side, that of `a`, below 2^24, would be a multiple of
/// `2 Q + 1 > 2^24`), so the bit below the last says which way it
/// rounds. `q` comes from `r = floor((2^64 - 1) / (2^9 b))`, within 2
/// under `2^55 / b` and below 2^32: `floor(a' r / 2^31)` (`a' < 2^25`)
/// falls short of `a' 2^24 / b` by less than 2^-5, so it is `q` or
/// `q - 1`, which the remainder (below `2 b`, exact in wrapping `u32`
/// arithmetic) tells apart.
#[derive(Clone, Copy, Debug)]
pub(super) struct ScaleDivisor {
    /// The divisor.
    d: f32,
    /// Its significand `b`, the implicit bit included.
    b: u32,
    /// Its exponent field.
    field: i32,
    /// `floor((2^64 - 1) / (2^9 b))`.
    r: u32,
}

impl ScaleDivisor {
    /// The divisor `d`, positive and normal.
    #[inline(always)]
    pub(super) fn new(d: f32) -> Self {
        let bits = d.to_bits();
        let b = (bits & 0x7f_ffff) | 0x80_0000;
        // `b` is not zero.
        let nz = core::num::NonZeroU64::new(u64::from(b)).unwrap_or(core::num::NonZeroU64::MIN);
        Self {
            d,
            b,
            field: ((bits >> 23) & 0xff) as i32,
            r: (super::divisor::max_div_long(nz) >> 9) as u32,
        }
    }

    /// `v / d`, the same bits. A zero is itself (`d` is positive); a
    /// subnormal, infinite or NaN `v`, or a quotient outside the normal
    /// range, is divided.
    #[inline(always)]
    pub(super) fn div(&self, v: f32) -> f32 {
        // The bits through `black_box`: LLVM turned the zero test into a
        // soft-float compare (a library call each, as in `Mat4`'s
        // product).
        let x = core::hint::black_box(v.to_bits());
        if x << 1 == 0 {
            return v;
        }
        let fv = ((x >> 23) & 0xff) as i32;
        let a = (x & 0x7f_ffff) | 0x80_0000;
        let below = u32::from(a < self.b);
        let a = a << below;
        // The quotient's exponent field, before a carry of its rounding.
        let field = fv - self.field + 127 - below as i32;
        if fv == 0 || fv == 255 || !(1..=254).contains(&field) {
            return v / self.d;
        }
        let product = if super::wide::SPLIT {
            super::wide::mul_split_u(a, self.r)
        } else {
            u64::from(a) * u64::from(self.r)
        };
        let est = (product >> 31) as u32;
        let rem = (a << 24).wrapping_sub(est.wrapping_mul(self.b));
        let q = est + u32::from(rem >= self.b);
        // The significand rounded, its implicit bit added to the field
        // (and a carry to 2^24 makes the next power of two).
        let sig = (q + 1) >> 1;
        f32::from_bits((x & 0x8000_0000) | ((((field - 1) as u32) << 23) + sig))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random `f32`: any bits, or one of a few special values, or one
    /// near 1 (whose products stay normal), or whose field puts the
    /// product near the ends of the normal range.
    fn any_f32(next: &mut impl FnMut(u64) -> u64) -> f32 {
        let bits = next(1 << 32) as u32;
        match next(4) {
            0 => f32::from_bits(bits),
            1 => f32::from_bits((bits & 0x807f_ffff) | (127 + next(9) as u32 - 4) << 23),
            2 => f32::from_bits((bits & 0x807f_ffff) | (next(40) as u32 + 1) << 23),
            _ => [
                0.0,
                -0.0,
                1.0,
                -1.0,
                0.5,
                f32::MAX,
                f32::MIN_POSITIVE,
                1e-40,
                f32::INFINITY,
            ][next(9) as usize],
        }
    }

    /// [`add`] is the sum, bit for bit (NaNs as NaNs): every pair of
    /// exponent fields with random significands and signs (significands
    /// of all ones and zeros often: carries to the next power of two,
    /// exact cancellations), ties, zeros, overflows, subnormals.
    #[test]
    fn add_is_the_sum() {
        let mut next = crate::testing::rng();
        let same =
            |got: f32, want: f32| got.to_bits() == want.to_bits() || got.is_nan() && want.is_nan();
        let sig = |next: &mut dyn FnMut(u64) -> u64| match next(6) {
            0 => 0,
            1 => 0x7f_ffff,
            2 => next(4) as u32,
            3 => 0x7f_ffff - next(4) as u32,
            _ => next(1 << 23) as u32,
        };
        let rounds = if cfg!(debug_assertions) { 2 } else { 64 };
        for fa in 0..256u32 {
            for fb in 0..256u32 {
                for _ in 0..rounds {
                    let sa = (next(2) as u32) << 31;
                    let sb = (next(2) as u32) << 31;
                    let x = f32::from_bits(sa | fa << 23 | sig(&mut next));
                    // Often the same significand: cancellation.
                    let y = match next(4) {
                        0 => f32::from_bits(sb | fb << 23 | (x.to_bits() & 0x7f_ffff)),
                        _ => f32::from_bits(sb | fb << 23 | sig(&mut next)),
                    };
                    assert!(same(add(x, y), x + y), "{x:e} + {y:e}: {:e}", add(x, y));
                }
            }
        }
        let ulp = f32::EPSILON / 2.0; // 2^-24
        for (x, y) in [
            // Ties, to even both ways, in sums and differences.
            (1.0f32, ulp),
            (1.0 + f32::EPSILON, ulp),
            (1.0, -ulp / 2.0),
            (1.0 + f32::EPSILON, -ulp / 2.0),
            (2.0, -ulp),
            (1.5, 3.0 * ulp),
            // Carries to the next power of two, and to infinity.
            (2.0 - f32::EPSILON, ulp),
            (f32::MAX, f32::MAX),
            (f32::MAX, f32::MAX * ulp),
            (-f32::MAX, -f32::MAX * ulp / 2.0),
            // Cancellation to zero, and below the normal range.
            (1.5, -1.5),
            (-1.5, 1.5),
            (f32::MIN_POSITIVE * 1.5, -f32::MIN_POSITIVE),
            (f32::MIN_POSITIVE, 1e-40),
            // Zeros, infinities and NaNs.
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (2.5, -0.0),
            (-0.0, 2.5),
            (1e-40, 0.0),
            (-0.0, -1e-40),
            (f32::INFINITY, -f32::INFINITY),
            (f32::INFINITY, 1.0),
            (f32::NEG_INFINITY, -0.0),
            (f32::NAN, 0.0),
            (0.0, f32::NAN),
            (f32::NAN, 1.0),
        ] {
            assert!(same(add(x, y), x + y), "{x:e} + {y:e}: {:e}", add(x, y));
            assert!(same(add(y, x), y + x), "{y:e} + {x:e}: {:e}", add(y, x));
        }
    }

    /// [`mul`] is the product, bit for bit (NaNs as NaNs), and its
    /// vectors' forms are [`Vec3`]'s.
    #[test]
    fn mul_is_the_product() {
        let mut next = crate::testing::rng();
        let same =
            |got: f32, want: f32| got.to_bits() == want.to_bits() || got.is_nan() && want.is_nan();
        for _ in 0..2_000_000 {
            let (x, y) = (any_f32(&mut next), any_f32(&mut next));
            let y = match next(3) {
                // A large operand against a small one: products near the
                // largest and the smallest normal values.
                0 => f32::from_bits(y.to_bits() ^ 0x4000_0000),
                _ => y,
            };
            assert!(same(mul(x, y), x * y), "{x:e} * {y:e}: {:e}", mul(x, y));
        }
        // Ties: significands whose product has exactly half an ulp left.
        for (x, y) in [
            (1.000_000_1f32, 1.000_000_1f32),
            (1.5, 1.000_000_1),
            (3.0, 1.000_000_1),
        ] {
            assert!(same(mul(x, y), x * y));
        }
        for _ in 0..200_000 {
            let v = Vec3::new(any_f32(&mut next), any_f32(&mut next), any_f32(&mut next));
            let w = Vec3::new(any_f32(&mut next), any_f32(&mut next), any_f32(&mut next));
            assert!(same(dot(v, w), v.dot(w)));
            let (c, d) = (cross(v, w), v.cross(w));
            assert!(same(c.x, d.x) && same(c.y, d.y) && same(c.z, d.z));
            match (normalize(v), v.normalize()) {
                (Some(a), Some(b)) => assert!(same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z)),
                (a, b) => assert_eq!(a, b),
            }
        }
    }
}
