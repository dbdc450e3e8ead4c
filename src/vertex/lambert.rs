//! The vertex stage's Lambert fast path: one directional light on a plain
//! material, n·l and the lit colour in integers ([`Lambert`]), the n·l
//! interval of the colour's half of the interior bit
//! ([`Lambert::interior_ndotl`]), and the arithmetic the vertex loop's
//! per-draw work builds on (n·l from 32-bit products on ARMv6-M, the
//! quotients by 65,280). The loop's per-draw constants and colour table
//! are in [`lit_work`](super::lit_work).

/// One directional light in model space (see
/// [`LightSetup::single_directional`](crate::light::LightSetup::single_directional)).
#[derive(Clone, Copy, Debug)]
pub(super) struct Lambert {
    pub(super) dir: [i32; 3],
    pub(super) color: [u32; 3],
    pub(super) ambient: [u32; 3],
}

impl Lambert {
    pub(super) fn new((dir, color, ambient): ([i32; 3], [u8; 3], [u8; 3])) -> Self {
        Lambert {
            dir,
            color: color.map(u32::from),
            ambient: ambient.map(u32::from),
        }
    }

    /// n·l in 1/256 steps, clamped to `0..=256` ([`shade`](Self::shade)'s).
    #[inline(always)]
    pub(super) fn ndotl(&self, n: crate::mesh::Vec3Fx) -> u32 {
        let n = [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()];
        // ARMv6-M builds each 64-bit product from four 16-bit ones: a
        // normal within ±1 takes n·l from six 32-bit products instead.
        match crate::math::SPLIT {
            true => ndotl_narrow(n, self.dir).unwrap_or_else(|| self.ndotl_wide(n)),
            false => self.ndotl_wide(n),
        }
    }

    /// n·l of the normal `n` in 1/256 steps, floored but not clamped
    /// ([`ndotl`](Self::ndotl) before its clamp), by 64-bit products.
    #[inline(always)]
    pub(super) fn ndotl_steps(&self, n: crate::mesh::Vec3Fx) -> i64 {
        use crate::math::mul_wide;
        let n = [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()];
        let d =
            mul_wide(n[0], self.dir[0]) + mul_wide(n[1], self.dir[1]) + mul_wide(n[2], self.dir[2]);
        d >> 24
    }

    /// [`ndotl`](Self::ndotl) of the normal's bits `n` by 64-bit products.
    #[inline(always)]
    pub(super) fn ndotl_wide(&self, n: [i32; 3]) -> u32 {
        use crate::math::mul_wide;
        let d =
            mul_wide(n[0], self.dir[0]) + mul_wide(n[1], self.dir[1]) + mul_wide(n[2], self.dir[2]);
        // n·l in 1/256 steps, floored, clamped to [0, 1]. On 32-bit
        // cores from d's upper word, which is 0 exactly when d >> 24 is
        // 0 to 255 (the 64-bit clamp took twice the instructions on
        // the Cortex-M3); 64-bit ones keep the clamp, which measured
        // fewer there.
        if cfg!(target_pointer_width = "64") {
            (d >> 24).clamp(0, 256) as u32
        } else {
            clamp_ndotl_words(d)
        }
    }

    /// Per channel `c`, for the draw's colour `base`: `base[c] ambient[c]
    /// 256 + 32,640` and `base[c] color[c]`, so that [`shade`](Self::shade)'s
    /// `base[c] (ambient[c] 256 + color[c] n·l) + 32,640` is one
    /// multiply-add (the same value: every term is below `2^26`). Once per
    /// draw, for the common loop's constants.
    pub(super) fn folded(&self, base: [u8; 3]) -> [[u32; 2]; 3] {
        let mut out = [[0; 2]; 3];
        for (c, ch) in out.iter_mut().enumerate() {
            let b = base[c] as u32;
            *ch = [b * self.ambient[c] * 256 + 32_640, b * self.color[c]];
        }
        out
    }

    /// The n·l (`0..=256`) whose colour on `base` has every channel in
    /// `1..=254`, as `[lo, span]`: n·l is such exactly when `n·l - lo <=
    /// span` (wrapping; [`within`]); none unless `gouraud`. Each channel's
    /// `floor((a + k n·l) / 65,280)` (`[a, k]` of [`folded`](Self::folded))
    /// grows with n·l, so the n·l where it is at least 1 are those from
    /// `ceil((65,280 - a) / k)` up, where it is at most 254 those up to
    /// `floor((255 · 65,280 - 1 - a) / k)`: the three channels' meet is
    /// one interval. Per vertex, then, the colour's half of the interior
    /// bit (see [`ScreenVertex::interior`](super::ScreenVertex::interior))
    /// is a subtraction and a compare, not three of each, and a draw that
    /// is not Gouraud shaded (whose vertices' bit nothing reads) gets an
    /// empty interval and the bit clear at the same cost.
    pub(super) fn interior_ndotl(&self, base: [u8; 3], gouraud: bool) -> [u32; 2] {
        interior_ndotl(&self.folded(base), gouraud)
    }

    /// The lit colour of normal `n` on the colour `base`.
    #[inline(always)]
    pub(super) fn shade(&self, n: crate::mesh::Vec3Fx, base: [u8; 3]) -> [u8; 3] {
        self.shade_ndotl(self.ndotl(n), base)
    }

    /// The lit colour for n·l `ndotl` (`0..=256`, [`ndotl`](Self::ndotl))
    /// on `base`: each channel `floor((base (256 ambient + color n·l) +
    /// 32,640) / 65,280)`, at most 255.
    #[inline(always)]
    pub(super) fn shade_ndotl(&self, ndotl: u32, base: [u8; 3]) -> [u8; 3] {
        let mut out = [0u8; 3];
        for c in 0..3 {
            // At most 2^17.
            let k = self.ambient[c] * 256 + self.color[c] * ndotl;
            let x = base[c] as u32 * k + 32_640;
            // floor(x / 65,280) = floor(floor(x / 256) / 255): ARMv6-M,
            // without a multiply-high, divides by a constant through the
            // library (about a hundred instructions), `div255` in eight.
            out[c] = if cfg!(microraster_narrow_multiply) {
                crate::light::div255(x >> 8).min(255) as u8
            } else if cfg!(target_pointer_width = "32") {
                div65280_sat(x)
            } else {
                (x / 65_280).min(255) as u8
            };
        }
        out
    }
}

/// [`Lambert::interior_ndotl`] from the channels' `[a, k]`
/// ([`Lambert::folded`]): the first n·l with every channel at least 1
/// and the last with every channel at most 254, each by a binary search
/// over `0..=256` (each channel grows with n·l, so each test holds on one
/// end of the range only). Out of line, and called once the loop's
/// constants are made (inlined, the Cortex-M3 kept the matrix's elements
/// on the stack across it); searches rather than a division per channel
/// and end, which took the Cortex-M3's firmware 120 bytes more.
#[inline(never)]
pub(super) fn interior_ndotl(channels: &[[u32; 2]; 3], gouraud: bool) -> [u32; 2] {
    // Where no vertex carries the bit (a size build's flash).
    if !super::screen::INTERIOR_STARTS {
        return [257, 0];
    }
    const ONE: u32 = 65_280;
    const TOP: u32 = 255 * ONE - 1;
    // Where `a + k n·l` is at least `ONE`: from `lo` on (`257`: nowhere).
    let (mut lo, mut end) = (0u32, 257u32);
    while lo < end {
        let mid = (lo + end) / 2;
        match channels.iter().all(|&[a, k]| a + k * mid >= ONE) {
            true => end = mid,
            false => lo = mid + 1,
        }
    }
    // Where it is at most `TOP`: below `hi` (`0`: nowhere).
    let (mut start, mut hi) = (0u32, 257u32);
    while start < hi {
        let mid = (start + hi) / 2;
        match channels.iter().all(|&[a, k]| a + k * mid <= TOP) {
            true => start = mid + 1,
            false => hi = mid,
        }
    }
    match gouraud && lo < hi {
        true => [lo, hi - 1 - lo],
        // n·l is at most 256: `n·l - 257` wraps above 0.
        false => [257, 0],
    }
}

/// Whether n·l `ndotl` is in the interval `[lo, span]` of
/// [`Lambert::interior_ndotl`].
#[inline(always)]
pub(super) fn within(ndotl: u32, [lo, span]: [u32; 2]) -> bool {
    ndotl.wrapping_sub(lo) <= span
}

/// `floor(x / 65,280)`, at most 255, for `x < 2^31` (the Lambert colour's
/// `x` is below 2^26): the quotient by the multiply-high LLVM makes of it
/// (`floor(x 0x8080_8081 / 2^47)`, exact for every `u32`), its upper word
/// taken as signed (below 2^31 for such `x`, so the shift is the same) so
/// that the clamp to `0..=255` is one `USAT` on ARMv7-M, where the
/// unsigned minimum took a compare, an `IT` and a conditional shift a
/// channel.
#[inline(always)]
pub(super) fn div65280_sat(x: u32) -> u8 {
    div65280_sat_by(x, DIV65280)
}

/// [`div65280_sat`]'s multiplier: `floor(x / 65,280) = floor(x
/// 0x8080_8081 / 2^47)`.
pub(super) const DIV65280: u32 = 0x8080_8081;

/// [`div65280_sat`] with its multiplier `magic` ([`DIV65280`]) passed in,
/// for the common loop, which reads it from its constants.
#[inline(always)]
pub(super) fn div65280_sat_by(x: u32, magic: u32) -> u8 {
    debug_assert!(x < 1 << 31 && magic == DIV65280);
    let high = ((x as u64 * magic as u64) >> 32) as u32 as i32;
    (high >> 15).clamp(0, 255) as u8
}

/// The Lambert fast path's n·l, `(n·l >> 24).clamp(0, 256)`, in 32-bit
/// products, when every `|n[i]| <= 2^16` and `|l[i]| <= 2^20`; `None`
/// otherwise. With `n[i] = h[i] 2^8 + o[i]` (`|h[i]| <= 2^8`, `0 <= o[i] <
/// 2^8`), `n·l = 2^8 A + B` for `A = Σ h[i] l[i]` and `B = Σ o[i] l[i]`,
/// each below `3 2^28` in magnitude; so `floor(n·l / 2^8) = A + floor(B /
/// 2^8)` fits `i32`, and shifting it by 16 more floors `n·l / 2^24`.
#[inline(always)]
pub(super) fn ndotl_narrow(n: [i32; 3], l: [i32; 3]) -> Option<u32> {
    let within = |v: i32, m: u32| v.unsigned_abs() <= m;
    if !(n.iter().all(|&v| within(v, 1 << 16)) && l.iter().all(|&v| within(v, 1 << 20))) {
        return None;
    }
    let (mut a, mut b) = (0i32, 0i32);
    for i in 0..3 {
        a += (n[i] >> 8) * l[i];
        b += (n[i] & 0xff) * l[i];
    }
    Some(((a + (b >> 8)) >> 16).clamp(0, 256) as u32)
}

/// The n·l of [`ndotl_narrow`]'s sums, unchecked, for ARMv6-M's common
/// loop ([`NarrowRows`](super::lit_work::NarrowRows)), which checks the light once per draw
/// ([`SPLIT_LIGHT`]) and the normal by one compare ([`split_normal`]):
/// for `-2^17 <= n[i] < 2^17` and the light `l` split once per draw
/// ([`split_light`]: `l[i] = h[i] 2^8 + o[i]`, `0 <= o[i] < 2^8`) from
/// `|l[i]| <= 2^18`, so that the normal is not split per vertex (six
/// instructions a vertex fewer). Then `|h[i]| <= 2^10`, each `|n[i]
/// h[i]| <= 2^27` and `A = Σ n[i] h[i]` within `3 2^27`; `|n[i] o[i]| <
/// 2^25`, `B = Σ n[i] o[i]` within `3 2^25`; so every sum fits `i32`,
/// `n·l = 2^8 A + B`, and `floor(n·l / 2^24) = floor((A + floor(B /
/// 2^8)) / 2^16)`: `ndotl_narrow`'s result.
#[inline(always)]
pub(super) fn ndotl_split(n: [i32; 3], [h, o]: &[[i32; 3]; 2]) -> u32 {
    debug_assert!(split_normal(n));
    let (mut a, mut b) = (0i32, 0i32);
    for i in 0..3 {
        a += n[i] * h[i];
        b += n[i] * o[i];
    }
    ((a + (b >> 8)) >> 16).clamp(0, 256) as u32
}

/// [`ndotl_split`]'s light: each component of `l` (within
/// [`SPLIT_LIGHT`]) as `h 2^8 + o`, `0 <= o < 2^8`, the `h` first.
pub(super) fn split_light(l: [i32; 3]) -> [[i32; 3]; 2] {
    debug_assert!(l.iter().all(|&v| v.unsigned_abs() <= SPLIT_LIGHT));
    [l.map(|v| v >> 8), l.map(|v| v & 0xff)]
}

/// The largest light component [`ndotl_split`] takes (checked once per
/// draw by [`NarrowRows::takes`](super::lit_work::NarrowRows::takes)).
pub(super) const SPLIT_LIGHT: u32 = 1 << 18;

/// Whether every `n[i]` is in `-2^17..2^17` ([`ndotl_split`]'s normals):
/// each `n[i] + 2^17` below `2^18` as a word, so all three are when
/// their `or` is (two instructions a component on ARMv6-M, where
/// `ndotl_narrow`'s test of the normal and of the light took about 27 a
/// vertex).
#[inline(always)]
pub(super) fn split_normal(n: [i32; 3]) -> bool {
    split_bits(n) >> 18 == 0
}

/// The `or` of [`split_normal`]'s three offset components.
#[inline(always)]
fn split_bits(n: [i32; 3]) -> u32 {
    let k = 1i32 << 17;
    (n[0].wrapping_add(k) | n[1].wrapping_add(k) | n[2].wrapping_add(k)) as u32
}

/// `min(floor((x - 256) / 65,280), 255)` for `256 <= x < 2^32`, by one
/// 32-bit multiply, for ARMv6-M's loop (whose channel constants hold the
/// 256: [`NarrowRows`](super::lit_work::NarrowRows)): with `y = floor((x - 256) / 256)`, `x >> 8` is
/// `y + 1`, and `z = min(y + 1, 65,280)` gives `floor((z - 1) / 255) = min(
/// floor(y / 255), 255) = min(floor((x - 256) / 65,280), 255)`, which is
/// `(z 257) >> 16` for every `z` in `1..=65,280` (the tests try them
/// all; the product is below `2^24`). `div255` and its clamp took about
/// 19 instructions a channel.
#[inline(always)]
pub(super) fn div65280_narrow(x: u32) -> u8 {
    debug_assert!(x >= 256);
    let z = (x >> 8).min(65_280);
    ((z * 257) >> 16) as u8
}

/// `(d >> 24).clamp(0, 256)` from `d`'s upper word, which is 0 exactly
/// when `d >> 24` is 0 to 255: the Lambert fast path's n·l on 32-bit cores.
#[inline(always)]
pub(super) fn clamp_ndotl_words(d: i64) -> u32 {
    match (d >> 32) as i32 {
        0 => d as u32 >> 24,
        1.. => 256,
        _ => 0,
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::light::{LightSetup, Material};
    use crate::math::{Mat4, Vec3};
    use crate::mesh::Vec3Fx;
    use crate::vertex::MAX_LIGHTS;

    /// n·l's clamp from the upper word is the 64-bit clamp.
    #[test]
    fn ndotl_from_words_is_the_clamp() {
        let mut next = crate::testing::rng();
        let check =
            |d: i64| assert_eq!(clamp_ndotl_words(d), (d >> 24).clamp(0, 256) as u32, "{d}");
        for b in 0..64 {
            let p = 1i64 << b;
            for d in [p, p.wrapping_sub(1), p.wrapping_neg(), p.wrapping_neg() + 1] {
                check(d);
            }
        }
        for d in [
            0,
            -1,
            i64::MIN,
            i64::MAX,
            (256 << 24) - 1,
            256 << 24,
            255 << 24,
        ] {
            check(d);
        }
        for _ in 0..100_000 {
            check(((next(1 << 32) << 32 | next(1 << 32)) as i64) >> next(64));
        }
    }

    /// The saturated quotient by 65,280 of the Lambert colour is the
    /// division's, for every `x` below 2^31 (every 127th value, the ends
    /// of each quotient's range, and the top of the range).
    #[test]
    fn div65280_sat_is_the_clamped_quotient() {
        let check = |x: u32| assert_eq!(div65280_sat(x), (x / 65_280).min(255) as u8, "{x}");
        for x in (0..1u32 << 31).step_by(127) {
            check(x);
        }
        for q in 1..32_896u32 {
            check(q * 65_280);
            check(q * 65_280 - 1);
        }
        for x in (1 << 31) - 1_000..1 << 31 {
            check(x);
        }
    }

    /// ARMv6-M's quotient by 65,280 is the clamped division: every `z`
    /// of its proof, and `x` across the colour's range with every
    /// quotient's ends.
    #[test]
    fn div65280_narrow_is_the_clamped_quotient() {
        for z in 1..=65_280u32 {
            assert_eq!((z * 257) >> 16, (z - 1) / 255, "{z}");
        }
        let check = |x0: u32| {
            let want = (x0 / 65_280).min(255) as u8;
            assert_eq!(div65280_narrow(x0 + 256), want, "{x0}");
        };
        for x0 in (0..1u32 << 26).step_by(61) {
            check(x0);
        }
        for q in 1..1_030u32 {
            check(q * 65_280);
            check(q * 65_280 - 1);
        }
        check(u32::MAX - 256);
    }

    /// The narrow n·l is the 64-bit one wherever it is taken: random and
    /// extreme normals and light directions within its bounds, and just
    /// beyond them (where it declines).
    #[test]
    fn narrow_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let ends = [
            -(1 << 16) - 1,
            -(1 << 16),
            -(1 << 16) + 1,
            -256,
            -255,
            -1,
            0,
            1,
            255,
            256,
            (1 << 16) - 1,
            1 << 16,
            (1 << 16) + 1,
        ];
        let lends = [
            -(1 << 20) - 1,
            -(1 << 20),
            -(1 << 16),
            -1,
            0,
            1,
            1 << 16,
            1 << 20,
            (1 << 20) + 1,
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &l in &lends {
                        for l in [[l, l, l], [l, -l, l], [-l, l, 1 << 16]] {
                            let n = [a, b, c];
                            let inside = n.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 16)
                                && l.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 20);
                            assert_eq!(
                                ndotl_narrow(n, l),
                                inside.then(|| wide(n, l)),
                                "{n:?} {l:?}"
                            );
                        }
                    }
                }
            }
        }
        for _ in 0..1_000_000 {
            let mut r = |m: u64| (next(2 * m + 1) as i64 - m as i64) as i32;
            let n = [r(1 << 16), r(1 << 16), r(1 << 16)];
            let l = [r(1 << 20), r(1 << 20), r(1 << 20)];
            assert_eq!(ndotl_narrow(n, l), Some(wide(n, l)), "{n:?} {l:?}");
        }
    }

    /// The split n·l of ARMv6-M's loop is the 64-bit one over its whole
    /// range: the ends of the normal's and the light's, and random ones.
    #[test]
    fn split_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let ends = [
            -(1 << 17),
            -(1 << 17) + 1,
            -257,
            -256,
            -1,
            0,
            1,
            255,
            256,
            (1 << 17) - 1,
        ];
        let lends = [
            -(1 << 18),
            -(1 << 18) + 1,
            -1,
            0,
            1,
            1 << 16,
            (1 << 18) - 1,
            1 << 18,
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &l in &lends {
                        for l in [[l, l, l], [l, -l, l], [-l, l, 1 << 18]] {
                            let n = [a, b, c];
                            assert!(split_normal(n));
                            let s = split_light(l);
                            assert_eq!(ndotl_split(n, &s), wide(n, l), "{n:?} {l:?}");
                        }
                    }
                }
            }
        }
        for bad in [1 << 17, -(1 << 17) - 1, i32::MIN, i32::MAX] {
            for i in 0..3 {
                let mut n = [0; 3];
                n[i] = bad;
                assert!(!split_normal(n), "{n:?}");
            }
        }
        for _ in 0..1_000_000 {
            let mut r = |m: u64| (next(2 * m) as i64 - m as i64) as i32;
            let n = [r(1 << 17), r(1 << 17), r(1 << 17)];
            let l = [r(1 << 18), r(1 << 18), r(1 << 18)];
            assert_eq!(ndotl_split(n, &split_light(l)), wide(n, l), "{n:?} {l:?}");
        }
    }

    /// The fast path of one directional light gives the general
    /// lighting's colours, for any normal, colour and light.
    #[test]
    fn lambert_fast_path_matches_the_light_setup() {
        each_lit_case(|fast, n, base, general| {
            assert_eq!(fast.shade(n, base), general, "{n:?} {base:?}");
        });
    }

    /// `f` of 200 random directional lights, 500 random normals and
    /// colours each, and the general lighting's colour of each: the
    /// cases the fast path's tests share.
    pub(in crate::vertex) fn each_lit_case(mut f: impl FnMut(&Lambert, Vec3Fx, [u8; 3], [u8; 3])) {
        let mut next = crate::testing::rng();
        for _ in 0..200 {
            let (setup, fast) = random_light(&mut next);
            for _ in 0..500 {
                let (n, base) = random_normal_and_color(&mut next);
                let general = setup.shade(&Material::new(), base, [0; 3], n.map(|v| v.to_bits()));
                f(&fast, n, base, general);
            }
        }
    }

    /// A random directional light and ambient colour, as the general
    /// lighting sets them up for a random model matrix, and its fast path
    /// (for the tests of the loop's [`LitWork`](super::super::lit_work::LitWork)
    /// too).
    fn random_light(next: &mut impl FnMut(u64) -> u64) -> (LightSetup<MAX_LIGHTS>, Lambert) {
        use crate::light::{DirectionalLight, Lighting};
        use embedded_graphics::pixelcolor::Rgb888;
        let mut f = || next(2001) as f32 / 1000.0 - 1.0;
        let dir = Vec3::new(f(), f(), f() + 0.01);
        let model = Mat4::rotation_y(f() * 3.0) * Mat4::rotation_x(f() * 3.0);
        let mut c = || Rgb888::new(next(256) as u8, next(256) as u8, next(256) as u8);
        let one = [DirectionalLight::new(dir, c())];
        let lighting = Lighting::new(c()).directional(&one);
        let setup: LightSetup<MAX_LIGHTS> =
            LightSetup::new(&lighting, &model, Vec3::new(0.0, 0.0, 5.0)).unwrap();
        let (dir, color, ambient) = setup.single_directional().unwrap();
        let fast = Lambert {
            dir,
            color: color.map(u32::from),
            ambient: ambient.map(u32::from),
        };
        (setup, fast)
    }

    /// A random normal, each component within `±2`, and a random colour.
    fn random_normal_and_color(next: &mut impl FnMut(u64) -> u64) -> (Vec3Fx, [u8; 3]) {
        let n = [0; 3].map(|_| fixed::types::I16F16::from_bits(next(1 << 18) as i32 - (1 << 17)));
        (n, [next(256) as u8, next(256) as u8, next(256) as u8])
    }

    /// The n·l interval of the interior bit holds exactly the n·l whose
    /// colour has every channel in `1..=254`: every n·l, for random
    /// lights and colours and their extremes.
    #[test]
    fn interior_ndotl_is_exact() {
        let mut next = crate::testing::rng();
        let ends = [0u8, 1, 2, 127, 128, 253, 254, 255];
        for i in 0..20_000 {
            let mut c = |j: u64| match (i + j) % 3 {
                0 => ends[next(ends.len() as u64) as usize],
                _ => next(256) as u8,
            };
            let l = Lambert {
                dir: [0; 3],
                color: [c(0), c(1), c(2)].map(u32::from),
                ambient: [c(3), c(4), c(5)].map(u32::from),
            };
            let base = [c(6), c(7), c(8)];
            for gouraud in [false, true] {
                let b = l.interior_ndotl(base, gouraud);
                for n in 0..=256 {
                    let inside = crate::vertex::screen::channels_interior(l.shade_ndotl(n, base));
                    assert_eq!(within(n, b), gouraud && inside, "{l:?} {base:?} {n}");
                }
            }
        }
    }
}
