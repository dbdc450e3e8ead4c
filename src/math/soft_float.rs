//! Short cuts around `f32` arithmetic where it is in software (Arm cores
//! without an FPU, where each operation is a library call of some 40 to
//! 100 instructions): the same bits as the IEEE operations, from the
//! floats' bit patterns.

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
