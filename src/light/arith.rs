//! The integer arithmetic of lighting: the fixed-point formats, constant
//! scales, normalization by a table-driven reciprocal square root, powers
//! for highlights, attenuation and `2^-x` for fog. Everything here runs per
//! vertex (see the module docs of [`light`](super) for the ranges and the
//! accuracy).

/// 1.0 in Q16.
pub(super) const ONE: u32 = 1 << 16;

/// Full intensity in the units of the colour terms (1 / 65,280 of a byte
/// per unit of base colour): 255 · 256.
pub(super) const FULL: u32 = 255 * 256;

/// The largest useful scaled diffuse sum `K`: with it, any non-zero base
/// colour already saturates the byte (`base · K / FULL >= 255`).
pub(super) const K_MAX: u32 = 255 * FULL;

/// A non-negative constant `m · 2^-s`, `m` in `[2^15, 2^16)` or 0: an `f32`
/// factor applied per vertex with one 32-bit product and a shift.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Scale {
    pub(super) m: u32,
    pub(super) s: i32,
}

/// Where [`Scale::apply`] saturates (far beyond any Q16 fraction used).
pub(super) const SCALE_CAP: u64 = 1 << 47;

impl Scale {
    /// The scale of a finite `x >= 0`, its mantissa rounded to 16 bits.
    pub(super) fn from_f32(x: f32) -> Option<Self> {
        if !x.is_finite() || x < 0.0 {
            return None;
        }
        let bits = x.to_bits();
        let biased = ((bits >> 23) & 0xff) as i32;
        // Zero or subnormal: below 2^-126, which times any length below
        // 2^62 rounds to 0 in Q16.
        if biased == 0 {
            return Some(Self { m: 0, s: 0 });
        }
        let mant = (bits & 0x7f_ffff) | 0x80_0000;
        let mut m = (mant + 0x80) >> 8;
        let mut e = biased - 127;
        if m == 1 << 16 {
            m = 1 << 15;
            e += 1;
        }
        // x = mant · 2^(e - 23) ≈ m · 2^(e - 15).
        Some(Self { m, s: 15 - e })
    }

    /// `round(len · 2^exp · self)`, saturated at [`SCALE_CAP`], for
    /// `len <= 2^16`.
    #[inline]
    pub(super) fn apply(self, len: u32, exp: i32) -> u64 {
        // len.min(2^16) · m <= 2^16 · (2^16 - 1) < 2^32.
        let prod = len.min(ONE) * self.m;
        let sh = self.s - exp;
        if sh > 0 {
            if sh > 32 {
                0
            } else {
                // Rounded, in 32 bits (sh - 1 < 32; no carry out).
                let twice = prod >> (sh - 1);
                ((twice >> 1) + (twice & 1)) as u64
            }
        } else if sh < -16 {
            if prod == 0 {
                0
            } else {
                SCALE_CAP
            }
        } else {
            ((prod as u64) << -sh).min(SCALE_CAP)
        }
    }
}

/// A light in the draw's model space.
/// `target - p` for a model-space point `target` (raw 16.16 in `i64`, below
/// 2^60) and a vertex position.
#[inline(always)]
pub(super) fn offset(target: [i64; 3], p: [i32; 3]) -> [i64; 3] {
    [
        target[0] - p[0] as i64,
        target[1] - p[1] as i64,
        target[2] - p[2] as i64,
    ]
}

/// A vertex normal, and whether it needs the wide dot product.
#[derive(Clone, Copy, Debug)]
pub(super) struct Normal {
    pub(super) n: [i32; 3],
    /// A component beyond ±2 (raw ±2^17): only broken meshes have one.
    pub(super) wide: bool,
}

impl Normal {
    pub(super) fn new(n: [i32; 3]) -> Self {
        Self {
            n,
            wide: n.iter().any(|c| c.unsigned_abs() > 1 << 17),
        }
    }

    /// `floor(n·u / 2^16)` for a Q16 `u` with components up to ±2^17: the
    /// dot product in Q16. Exact (clamped to ±2^30 on the wide path).
    #[inline]
    pub(super) fn dot(&self, u: [i32; 3]) -> i32 {
        let n = &self.n;
        if self.wide {
            let d: i64 = (0..3).map(|i| n[i] as i64 * u[i] as i64).sum();
            return (d >> 16).clamp(-(1 << 30), 1 << 30) as i32;
        }
        // n·u = 256 Σ n_i (u_i >> 8) + Σ n_i (u_i & 255), so
        // floor(n·u / 2^16) = floor((a + floor(b / 256)) / 256), where
        // |a| <= 3 · 2^17 · 2^9 and |b| < 3 · 2^17 · 2^8 fit easily.
        let mut a = 0i32;
        let mut b = 0i32;
        for i in 0..3 {
            a += n[i] * (u[i] >> 8);
            b += n[i] * (u[i] & 255);
        }
        (a + (b >> 8)) >> 8
    }
}

/// A vector as a unit direction and a length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Unit {
    /// The direction, Q16.
    pub(super) dir: [i32; 3],
    /// The length is `len · 2^exp`; `len` is in `[2^15, 2^16]`.
    pub(super) len: u32,
    pub(super) exp: i32,
}

/// The direction and length of `v` (components below 2^62 in magnitude), or
/// `None` for the zero vector.
///
/// The vector is shifted (rounding) so that its largest component has 15
/// bits, or, if its squared length would then be below 2^30, 16 bits: its
/// squared length `s` then lies in `[2^30, 2^32)`, the domain of [`rsqrt`].
#[inline]
pub(super) fn normalize(v: [i64; 3]) -> Option<Unit> {
    let m = v[0]
        .unsigned_abs()
        .max(v[1].unsigned_abs())
        .max(v[2].unsigned_abs());
    if m == 0 {
        return None;
    }
    // Shift so that m >> exp lies in [2^14, 2^15) (rounding may give 2^15).
    let (mut exp, mut w) = if m < 1 << 30 {
        // The usual case, in 32 bits: 64-bit shifts are library calls on a
        // 32-bit core. exp <= 15, so the rounded sums stay below 2^31, and
        // a left shift (exp <= 0) brings m below 2^15.
        let exp = 17 - (m as u32).leading_zeros() as i32;
        let w = v.map(|c| {
            let c = c as i32;
            if exp <= 0 {
                c << -exp
            } else {
                (c + (1 << (exp - 1))) >> exp
            }
        });
        (exp, w)
    } else {
        let exp = 49 - m.leading_zeros() as i32;
        (exp, v.map(|c| ((c + (1 << (exp - 1))) >> exp) as i32))
    };
    // Each square at most 2^30: the sum below 2^32.
    let mut s: u32 = w.iter().map(|c| c.unsigned_abs() * c.unsigned_abs()).sum();
    if s < 1 << 30 {
        // Then every |w_i| < 2^15, and the doubled vector's s < 2^32.
        for c in &mut w {
            *c <<= 1;
        }
        s <<= 2;
        exp -= 1;
    }
    let r = rsqrt(s);
    let mut dir = [0i32; 3];
    for (d, &c) in dir.iter_mut().zip(&w) {
        // |w_i| · r <= sqrt(s) · r ≈ 2^31.
        let a = ((c.unsigned_abs() * r + (1 << 14)) >> 15) as i32;
        *d = if c < 0 { -a } else { a };
    }
    // sqrt(s) = s · r / 2^31, with s split into 16-bit halves so that each
    // product stays below 2^32 ((s >> 16) · r ≈ sqrt(s) · 2^15).
    let len = ((s >> 16) * r + (((s & 0xffff) * r) >> 16) + (1 << 14)) >> 15;
    Some(Unit { dir, len, exp })
}

/// `floor(sqrt(x))`, exact, by the digit-by-digit method (used at compile
/// time, for the [`rsqrt`] table).
pub(super) const fn isqrt(x: u64) -> u64 {
    let mut rem = x;
    let mut root = 0u64;
    let mut bit = 1u64 << 62;
    while bit > x {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// `round(2^16 / sqrt(m))` for `m = 2^k (1 + i / 128)`, less 2^15 (so that
/// it fits 16 bits): `RSQRT[k][i]` for the two octaves `k` of `[1, 4)`.
/// Since `round(sqrt(q)) = (floor(sqrt(floor(4q))) + 1) / 2`, the entries
/// are exact roundings.
pub(super) const RSQRT: [[u16; 129]; 2] = {
    let mut t = [[0u16; 129]; 2];
    let mut k = 0;
    while k < 2 {
        let mut i = 0;
        while i < 129 {
            // 4 · 2^32 / m = 2^(41 - k) / (128 + i).
            let q4 = (1u64 << (41 - k)) / (128 + i as u64);
            t[k][i] = (isqrt(q4).div_ceil(2) - (1 << 15)) as u16;
            i += 1;
        }
        k += 1;
    }
    t
};

/// `2^31 / sqrt(s)` for `s` in `[2^30, 2^32)`: a value in `(2^15, 2^16]`,
/// within 1.25 of the exact one (tested over the whole domain). The table's
/// rounding (½), the linear interpolation's own error (at most
/// (1/128)² / 8 · 3/4 · 2^16 ≈ 0.37, where `m^-½` bends most) and the
/// interpolation's rounding (½) add up to at most 1.37.
#[inline]
pub(super) fn rsqrt(s: u32) -> u32 {
    debug_assert!(s >= 1 << 30);
    // s = 2^30 m, m in [1, 4): octave k, 128 steps of 2^k / 128 in it.
    let k = (s >> 31) as usize;
    // In 0..128 for s >= 2^30; the mask only spares a bounds check.
    let i = ((s >> (23 + k)) - 128) as usize & 127;
    let frac = (s >> (7 + k)) & 0xffff;
    let a = RSQRT[k][i] as u32 + (1 << 15);
    let b = RSQRT[k][i + 1] as u32 + (1 << 15);
    // a - b <= 2^16 (1 - 1 / sqrt(1 + 1/128)) < 2^8.
    a - (((a - b) * frac + (1 << 15)) >> 16)
}

/// `a · b` for Q16 fractions in `[0, 1]`, rounded.
#[inline]
pub(super) fn frac_mul(a: u32, b: u32) -> u32 {
    if a >= ONE {
        b
    } else if b >= ONE {
        a
    } else {
        // (2^16 - 1)² + 2^15 < 2^32.
        (a * b + (1 << 15)) >> 16
    }
}

/// `x^e` for a Q16 `x` in `[0, 1]`, by binary exponentiation, each product
/// rounded; `x^0 = 1`.
#[inline]
pub(super) fn pow(x: u32, e: u8) -> u32 {
    if e == 0 || x >= ONE {
        return ONE;
    }
    let (mut acc, mut b, mut e) = (ONE, x, e);
    loop {
        if e & 1 != 0 {
            acc = frac_mul(acc, b);
        }
        e >>= 1;
        if e == 0 {
            return acc;
        }
        b = frac_mul(b, b);
        if b == 0 {
            // A higher bit of e is set, so the result is 0 too.
            return 0;
        }
    }
}

/// The windowed falloff `(1 - t²)²` of `t = d / r` in `[0, 1)`, Q16.
#[inline]
pub(super) fn attenuation(t: u32) -> u32 {
    let u = ONE - ((t * t + (1 << 15)) >> 16).min(ONE);
    frac_mul(u, u)
}

/// `2^(-i/32)` in Q16, `i` in `0..=32`, rounded; built at compile time from
/// the series of `exp(-i ln 2 / 32)` (alternating, 30 terms: far below the
/// rounding).
pub(super) const EXP2: [u32; 33] = {
    let mut t = [0u32; 33];
    let mut i = 0;
    while i < 33 {
        let x = i as f64 * core::f64::consts::LN_2 / 32.0;
        let mut sum = 0.0;
        let mut term = 1.0;
        let mut k = 1;
        while k < 30 {
            sum += term;
            term = -term * x / k as f64;
            k += 1;
        }
        t[i] = (sum * 65536.0 + 0.5) as u32;
        i += 1;
    }
    t
};

/// `2^-q` for a Q16 `q`, in Q16: the integer part of `q` shifts, the
/// fraction interpolates [`EXP2`].
#[inline]
pub(super) fn exp2_neg(q: u64) -> u32 {
    let ip = (q >> 16) as u32;
    if ip >= 17 {
        return 0;
    }
    let frac = (q & 0xffff) as u32;
    let i = (frac >> 11) as usize;
    let t = frac & 0x7ff;
    let (a, b) = (EXP2[i], EXP2[i + 1]);
    // a - b < 2^11, so the product stays below 2^22.
    let y = a - (((a - b) * t + (1 << 10)) >> 11);
    (y + ((1 << ip) >> 1)) >> ip
}

/// `floor(x / 255)` for any `u32`, exact, by shifts and adds (a Cortex-M0+
/// has no divider, and no multiply-high for a division by a constant).
#[inline]
pub(crate) fn div255(x: u32) -> u32 {
    // x/256 + x/2^16 + x/2^24, each floored: at most x/255 (the rest of
    // the series x/256 + x/2^16 + ...) and less than 3 + 2^32/(255 · 2^24)
    // below it, so the remainder r lies in [0, 1022) ...
    let q = (x >> 8) + (x >> 16) + (x >> 24);
    let r = x - q * 255;
    // ... where floor(r / 255) = (r + 1 + r / 256) / 256.
    q + ((r + 1 + (r >> 8)) >> 8)
}
