//! Attribute set-up and span shading: depth test, flat or Gouraud colour.
//! One plane's arithmetic is in `plane`, a triangle's set-up of its planes
//! in `setup` (`small` for small triangles on 32-bit cores), the depth
//! test in `depth`, the flat span loops here and the Gouraud ones in
//! `gouraud`.
//!
//! Following Hecker, each attribute `a` (depth and the three colour
//! channels) is a plane over the screen, `a(x, y) = a0 + A (x - x0) +
//! B (y - y0)`, whose gradients `A = ∂a/∂x` and `B = ∂a/∂y` are computed
//! once per triangle (and tile) from the three vertices, by Cramer's rule
//! over twice the signed area: eight divisions by the same denominator,
//! which a 64-bit host does with its division instruction and a 32-bit
//! target, for a triangle under 64 pixels, in 32-bit steps (`Small`), for a
//! larger one through one reciprocal (`math::Divisor`). At the
//! first pixel of every span the plane is evaluated directly, so error
//! never accumulates from row to row; along the span the value steps by the
//! x gradient. Depth uses 14 fraction bits and colour 16, each biased by one
//! half so truncation rounds.
//!
//! The evaluation is `gx i + gy j + k` in wrapping `i32`: two 32-bit
//! multiplies and adds per attribute, cheap on every core, and exact, as
//! `Plane` shows: at a covered pixel the value is within a few thousand
//! units of its range, so the `i32` sum equals the exact one. The bias plus
//! a clamp at the span start keeps every value inside its range although
//! the rounded gradients can carry it a little beyond, and each x step
//! carries up to half a unit in the last place of rounding error (at most
//! `TILE_W / 2` such units over a span, far below the half-unit margin for
//! tiles up to 1,024 pixels wide).
//!
//! Gradients beyond ±2^40 are clamped, and such a triangle's spans start
//! from the planes evaluated in `i64` (`wide_start`). Only a sliver
//! narrower than about 1/1,000 pixel can reach that clamp; its at most one
//! pixel per row keeps a depth within its triangle's range.
//!
//! The flat span loops of targets with SIMD have no branch for spans of
//! 8 pixels or more: the depth stored is the min or max of the
//! new and the old depth (`DepthFn::merge`), the colour a select and the
//! count a sum, so the compiler can vectorize them. Depth is stepped as
//! `z << 2` in a `u32`, whose upper half is then the 16-bit depth. The
//! results are exactly those of the plain per-pixel test.

mod convert;
mod depth;
mod gouraud;
#[cfg(target_pointer_width = "64")]
mod offset;
#[cfg(target_pointer_width = "64")]
mod packed;
pub(crate) mod perspective;
mod plane;
mod setup;
mod sliver;
mod small;
mod start;

#[cfg(microraster_armv7m)]
pub(crate) use convert::lit565_bits;
pub(crate) use convert::LitTables;
pub(crate) use convert::To565;
pub(crate) use convert::{rgb, rgb565_bits};
use convert::{rgb16_green_up, GREEN_UP};
pub(crate) use depth::depth16;
pub use depth::DepthTest;
pub(crate) use depth::{DLessEqual, DepthFn};
pub(crate) use gouraud::{
    span_gouraud, FIXED_GOURAUD, OPAQUE_FLAT, OPAQUE_TABLE, SPLIT_INTERIOR, STEPS_IN_PLACE,
};
use plane::Basis;
pub(crate) use setup::{ColourPlanes, Corners, TriangleSetup, OFFSET_SETUP, SMALL_INLINE};

/// Fraction bits of interpolated depth.
pub const Z_FRAC: u32 = 14;
/// Fraction bits of interpolated colour channels.
pub const C_FRAC: u32 = 16;
const GRADIENT_LIMIT: i64 = 1 << 40;

/// Where a span lies: screen row `j`, columns `x0..x1`, in a slice of
/// pixels whose first would be screen column `ox` on row `j` (a tile row
/// starting at `ox`, or the whole tile: see `render::fill::each_span`);
/// for the Gouraud span loop where [`NEGATED_OX`], `ox` negated.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpanPos {
    pub ox: i32,
    pub j: i32,
    pub x0: i32,
    pub x1: i32,
}

/// Whether [`span_gouraud`]'s [`SpanPos::ox`] is negated (targets with
/// SIMD, whose Gouraud loop adds it to both ends of the span, see
/// `render::fill::each_span`). The offsets are zero-extended there, as
/// they are never negative within the tile (sign-extended, x86-64 `demo`
/// 3,369,702 -> 3,376,708 instructions; once the vector loop was gone,
/// 3,277,579 -> 3,388,717).
pub(crate) const NEGATED_OX: bool = VECTOR_LOOPS;

impl SpanPos {
    /// The position of span `(j, x0, x1)` for the Gouraud span loops in a
    /// tile `width` pixels wide whose first element is screen column
    /// `base` on row 0 (the tile's left column plus its top row times
    /// `width`): `ox` is `base` less the span's row start, negated where
    /// [`NEGATED_OX`] (see `render::fill::each_span`).
    #[inline(always)]
    pub(crate) fn in_tile(base: i32, width: i32, j: i32, x0: i32, x1: i32) -> Self {
        let ox = if NEGATED_OX {
            j * width - base
        } else {
            base - j * width
        };
        Self { ox, j, x0, x1 }
    }
}

/// Flat spans shorter than this are shaded by a plain loop; longer ones,
/// on targets with SIMD, by a branch-free loop the compiler can vectorize
/// (out of line, so its vector set-up is paid per long span, not hoisted
/// into every triangle).
const SHORT_SPAN: usize = 8;

/// Whether the target has SIMD for the flat span's branch-free loop.
/// Targets without (the microcontrollers) always take the plain loop:
/// there the branch-free one only adds a load and two stores for every
/// fragment that fails. Both loops give the same pixels. The Gouraud span
/// loop of these targets (64-bit hosts) is a plain loop of its own, see
/// [`span_gouraud`].
const VECTOR_LOOPS: bool = cfg!(any(
    target_arch = "x86_64",
    target_arch = "x86",
    target_arch = "aarch64",
    target_feature = "simd128"
));

/// Shades one span: `color` and `depth` are the tile row. Returns the
/// number of fragments written.
#[inline(always)]
pub(crate) fn span_flat<C: Copy, D: DepthFn, const WRITE: bool>(
    dt: D,
    s: &TriangleSetup,
    t: &Corners<'_>,
    flat: C,
    color: &mut [C],
    depth: &mut [u16],
    sp: SpanPos,
) -> u32 {
    let SpanPos { ox, j, x0, x1 } = sp;
    // Depth with its 16 integer bits in the upper half of a u32 (see
    // `depth16`).
    let mut z = (s.z_start(t, x0, j) as u32) << (16 - Z_FRAC);
    let gz = (s.steps()[0] as u32) << (16 - Z_FRAC);
    let (a, b) = ((x0 - ox) as usize, (x1 - ox) as usize);
    let (color, depth) = (&mut color[a..b], &mut depth[a..b]);
    if VECTOR_LOOPS && color.len() >= SHORT_SPAN {
        return flat_run::<C, D, WRITE>(dt, flat, color, depth, z, gz);
    }
    // Where `FLAT_FAILS`, the fragments that fail are counted (down from
    // the span's length, or up and taken off it at the end where
    // `FAILS_AFTER`): the written path, nearly every pixel's, keeps no
    // count.
    let len = color.len() as u32;
    let mut n = if FLAT_FAILS && !FAILS_AFTER { len } else { 0 };
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if dt.pass(zz, *d) {
            if WRITE {
                *d = zz;
            }
            *c = flat;
            if !FLAT_FAILS {
                n += 1;
            }
        } else if FLAT_FAILS && FAILS_AFTER {
            n += 1;
        } else if FLAT_FAILS {
            n -= 1;
        }
        z = z.wrapping_add(gz);
    }
    if FLAT_FAILS && FAILS_AFTER {
        len - n
    } else {
        n
    }
}

/// Whether [`span_flat`]'s plain loop counts the fragments that fail
/// rather than those written: on targets without SIMD (not
/// [`VECTOR_LOOPS`], whose long spans take the branch-free loop and whose
/// short ones took more this way: x86-64 `fill` 8.75 -> 8.81 a pixel).
/// The written path then keeps no count: `fill` 14.37 -> 13.48
/// instructions a pixel on the Cortex-M4F, 23.01 -> 20.06 on ARMv6-M
/// (`demo-flat` 2,499,024 -> 2,480,230 and 4,748,645 -> 4,716,831; `demo`
/// -779 and -3,125; `rock` and `grid4` the same counts). In the unit
/// tests too, which thereby count as those cores do.
const FLAT_FAILS: bool = !VECTOR_LOOPS || cfg!(test);

/// Whether [`span_flat`]'s failures (where [`FLAT_FAILS`]) are counted up
/// from zero and taken off the span's length at its end, rather than
/// counted down from it: on the Cortex-M3 (the build script's
/// `microraster_armv7m`), whose short spans' registers fell worse the
/// other way. `fill` 14.37 -> 14.03 a pixel, `demo-flat` 2,523,315 ->
/// 2,527,247 (+3.9 K), `demo` -174; counted down, `fill` 13.73 but
/// `demo-flat` +15.3 K; counted down with the failure marked cold
/// (`crate::hint::cold`), `fill` 14.18, `demo-flat` +23.4 K.
const FAILS_AFTER: bool = cfg!(microraster_armv7m);

/// The branch-free loop of [`span_flat`].
#[inline(never)]
fn flat_run<C: Copy, D: DepthFn, const WRITE: bool>(
    dt: D,
    flat: C,
    color: &mut [C],
    depth: &mut [u16],
    mut z: u32,
    gz: u32,
) -> u32 {
    // A span is at most a tile row, at most 1,024 pixels: a u16 count
    // cannot overflow, and vectorizes in 16-bit lanes.
    let mut n = 0u16;
    // Branch-free, so the compiler can vectorize it.
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        let old = *d;
        let pass = dt.pass(zz, old);
        if WRITE {
            *d = dt.merge(zz, old);
        }
        *c = if pass { flat } else { *c };
        n += pass as u16;
        z = z.wrapping_add(gz);
    }
    n as u32
}

#[cfg(test)]
mod tests {
    use super::plane::Plane;
    use super::setup::*;
    use super::small::*;
    use super::*;
    use crate::math::{leading_zeros_search, Recip16};
    use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
    use crate::vertex::ScreenVertex;
    use core::num::NonZeroU32;

    fn merge_matches_pass<D: DepthFn + core::fmt::Debug>(d: D) {
        let values = [0u16, 1, 2, 1000, 32_767, 32_768, 65_534, 65_535];
        for &n in &values {
            for &o in &values {
                let expected = if d.pass(n, o) { n } else { o };
                assert_eq!(d.merge(n, o), expected, "{d:?}: new {n}, old {o}");
            }
        }
    }

    #[test]
    fn depth_merge_is_the_written_depth() {
        merge_matches_pass(DLessEqual);
        for test in [
            DepthTest::Always,
            DepthTest::Less,
            DepthTest::LessEqual,
            DepthTest::Equal,
            DepthTest::GreaterEqual,
            DepthTest::Greater,
            DepthTest::Never,
        ] {
            merge_matches_pass(test);
            // The comparison is the one the test names.
            assert_eq!(DepthTest::new(test), test);
        }
        // LessEqual compiled in agrees with LessEqual decided per pixel.
        for (n, o) in [(0, 0), (1, 0), (0, 1), (65_535, 65_534)] {
            assert_eq!(DLessEqual.pass(n, o), DepthTest::LessEqual.pass(n, o));
        }
    }

    /// The 32-bit division of small triangles against the 64-bit one, on
    /// every target (the host sets up with the latter).
    #[test]
    fn small_division_matches_the_64_bit_one() {
        let mut next = crate::testing::rng();
        let check = |n: i32, area: u32, shift: u32| {
            let small = Small {
                area: NonZeroU32::new(area).unwrap(),
                half: area / 2,
            };
            let m = (n.unsigned_abs() as u64) << shift;
            let q = ((m + (area / 2) as u64) / area as u64) as i64;
            let expected = if n < 0 { -q } else { q };
            assert_eq!(
                small.div_round(n, shift),
                expected,
                "{n} << {shift} / {area}"
            );
        };
        let max_area = 2 * (SMALL_EDGE as u32 - 1) * (SMALL_EDGE as u32 - 1);
        for area in [1, 2, 3, 255, 256, 65_535, max_area - 1, max_area] {
            for n in [0, 1, -1, 7, -7, (1 << 27) - 1, -(1 << 27) + 1] {
                for shift in [4, 18, 20] {
                    check(n, area, shift);
                }
            }
        }
        for k in 0..300_000 {
            let area = (1 + next(max_area as u64) as u32) >> (k % 20);
            let n = next(1 << 28) as i32 - (1 << 27);
            // Ties: n 2^shift an odd multiple of area / 2.
            let n = if k % 7 == 0 {
                (n % 64) * area as i32 / 2
            } else {
                n
            };
            check(n, area.max(1), [4, 18, 20][k % 3]);
        }
    }

    /// The `i32` set-up's division, signed and unsigned, against the
    /// 64-bit one over its whole domain's edges: numerators within
    /// -2^21..2^21, twice the area of either sign up to `2 * 1023^2`,
    /// first digits up to `2^(40 - shift)`, and ties.
    #[test]
    fn small_i32_division_matches_the_64_bit_one() {
        let mut next = crate::testing::rng();
        let max_area = 2 * 1023 * 1023;
        let mut checked = 0;
        for k in 0..400_000u64 {
            let mut area = match k % 5 {
                0 => max_area,
                1 => 1 + next(8) as i32,
                _ => 1 + next(max_area as u64) as i32,
            };
            let mut shift = [18, 20][(k / 2) as usize % 2];
            // Ties: `n 2^shift` an odd multiple of `area / 2`, which needs
            // `2^(shift + 1)` to divide `area`: depth's shift and twice the
            // area 2^19, 3 2^19 or 2^20, and an odd multiple of
            // `area / 2^19`.
            let tie = k % 7 == 2;
            if tie {
                area = [1 << 19, 3 << 19, 1 << 20][(k / 7) as usize % 3];
                shift = 18;
            }
            let area2 = if k % 2 == 0 { area } else { -area };
            if area2 == -1 {
                continue;
            }
            // The largest numerator whose first digit is at most
            // 2^(40 - shift), and 2^21.
            let limit = ((area as i64) << (30 - shift)).min(1 << 21);
            let n = match k % 7 {
                0 => limit - 1,
                1 => -limit,
                2 => (2 * next(8) as i64 - 7) * (area >> 19) as i64,
                _ => next(2 * limit as u64) as i64 - limit,
            };
            if n.abs() > limit || n >= 1 << 21 {
                continue;
            }
            let n = n as i32;
            let f = SmallBasis {
                e: [0; 4],
                o: [0; 2],
                area2,
                half: area / 2,
                divisor: ShortDivisor::new(NonZeroU32::new(area as u32).unwrap()),
            };
            // The depth plane's form: the area's own reciprocal, unscaled.
            let plain = SmallBasis {
                e: f.e,
                o: f.o,
                area2,
                half: f.half,
                divisor: Recip16::new_small(NonZeroU32::new(area as u32).unwrap()),
            };
            let small = Small {
                area: NonZeroU32::new(area as u32).unwrap(),
                half: area as u32 / 2,
            };
            if tie {
                let m = (n as i64) << shift;
                assert_eq!(m.abs() % area as i64 * 2, area as i64, "{n} {area}");
            }
            let expected = small.div_round(n, shift) * area2.signum() as i64;
            for q in [
                f.div_round32_with::<true>(n, shift),
                f.div_round32_with::<false>(n, shift),
                f.div_round32_short(n, shift),
                plain.div_round32_short(n, shift),
                f.div_round32_of_m(n << 10, shift),
            ] {
                assert_eq!(q as i64, expected, "{n} << {shift} / {area2}");
            }
            checked += 1;
        }
        assert!(checked > 300_000, "{checked}");
    }

    /// [`Recip16::digit`] is the library's quotient and remainder for
    /// every divisor of a small triangle (its extremes, the powers of two
    /// and their neighbours where the reciprocal changes form, random
    /// ones) and every dividend of its range: 0, the multiples of `d`
    /// and their neighbours, `d 2^12` and the range's end `2^(t + 13) -
    /// 1`, and random ones.
    #[test]
    fn short_reciprocal_digits_are_exact() {
        let mut next = crate::testing::rng();
        let check = |d: u32, next: &mut dyn FnMut(u64) -> u64| {
            let f = Recip16::new(NonZeroU32::new(d).unwrap());
            let t = 31 - d.leading_zeros();
            let end = 1u64 << (t + 13);
            let max = d as u64 * 4096;
            assert!(max < end, "{d}");
            let digit = |x: u64| {
                if x < end {
                    let x = x as u32;
                    assert_eq!(f.digit(x), (x / d, x % d), "{x} / {d}");
                }
            };
            for x in [0u64, 1, end - 1, max, max - 1, max + 1] {
                digit(x);
            }
            for q in [1u64, 2, 1023, 1024, 1025, 4095] {
                for x in [q * d as u64 - 1, q * d as u64, q * d as u64 + 1] {
                    digit(x);
                }
            }
            for _ in 0..200 {
                digit(next(end));
            }
        };
        for d in [1u32, 2, 3, 4, 5, 7, 8, 9, 2 * 1023 * 1023, (1 << 21) - 1] {
            check(d, &mut next);
        }
        for t in 3..21 {
            for d in [(1u32 << t) - 1, 1 << t, (1 << t) + 1] {
                check(d, &mut next);
            }
        }
        for _ in 0..2_000 {
            let d = 1 + next((1 << 21) - 1) as u32;
            check(d, &mut next);
        }
    }

    /// [`Recip16`]'s reciprocal of every divisor of a small triangle is
    /// within the bounds its digits' exactness rests on: never above
    /// `E = 2^(t + 16) / d` (times `2^(3 - t)` for `d < 8`), and below it
    /// by less than 5.1 (3.1 where `d < 2^16` is exact), and at most 2^16.
    #[test]
    fn short_reciprocal_is_within_its_bounds() {
        // (And the inline leading zeros: every bit position, both ends.)
        for b in 0..32 {
            for d in [
                1u32 << b,
                (1 << b) | 1,
                ((2u64 << b) - 1) as u32,
                0x9e37_79b9 >> (31 - b),
            ] {
                let d = NonZeroU32::new(d.max(1)).unwrap();
                assert_eq!(leading_zeros_search(d), d.leading_zeros(), "{d}");
            }
        }
        for d in 1u32..1 << 21 {
            let f = Recip16::new(NonZeroU32::new(d).unwrap());
            let (r, t) = (f.r as u64, 31 - d.leading_zeros());
            let scale = 1u64 << 3u32.saturating_sub(t);
            let e = (1u64 << (t + 16)) * scale;
            // r <= e / d, and (e / d - r) < limit: in integers, times 10 d.
            assert!(r * d as u64 <= e, "{d}");
            let limit = if t <= 15 { 31 } else { 51 };
            assert!(
                (e - r * d as u64) * 10 < limit * scale * d as u64,
                "{d}: {r}"
            );
            assert!(r <= (1 << 16) * scale, "{d}");
        }
    }

    /// The reciprocal's rounded quotients ([`SmallBasis::div_round32_short`],
    /// ARMv6-M's) equal the library divisions' at the bounds: twice the
    /// area ±1, ±2, ±3 and ±2 1023^2, numerators ±2^21 (less one for the
    /// positive), the largest first digits, `2^(40 - shift)`, and either
    /// side of the two-digit quotients' bound, `area 2^(23 - shift)`.
    #[test]
    fn short_division_matches_at_the_bounds() {
        let max_area = 2 * 1023 * 1023;
        for area2 in [1i32, 2, -2, 3, -3, 1 << 20, -(1 << 20), max_area, -max_area] {
            let area = area2.unsigned_abs();
            let f = SmallBasis {
                e: [0; 4],
                o: [0; 2],
                area2,
                half: (area / 2) as i32,
                divisor: ShortDivisor::new(NonZeroU32::new(area).unwrap()),
            };
            // The depth plane's form: the area's own reciprocal, unscaled.
            let plain = SmallBasis {
                e: f.e,
                o: f.o,
                area2,
                half: f.half,
                divisor: Recip16::new_small(NonZeroU32::new(area).unwrap()),
            };
            let small = Small {
                area: NonZeroU32::new(area).unwrap(),
                half: area / 2,
            };
            for shift in [18, 20] {
                let limit = ((area as i64) << (30 - shift)).min(1 << 21);
                for n in [
                    0,
                    1,
                    -1,
                    limit - 1,
                    -limit,
                    (1 << 21) - 1,
                    -(1 << 21),
                    area as i64,
                    -(area as i64),
                    area as i64 / 2,
                    -(area as i64 / 2) - 1,
                    // Where the two-digit quotient gives way to three.
                    ((area as i64) << (23 - shift)) - 1,
                    (area as i64) << (23 - shift),
                    -((area as i64) << (23 - shift)) + 1,
                    -((area as i64) << (23 - shift)),
                ] {
                    if n.abs() > limit || n >= 1 << 21 {
                        continue;
                    }
                    let n = n as i32;
                    let expected = f.div_round32_with::<false>(n, shift);
                    assert_eq!(
                        f.div_round32_short(n, shift),
                        expected,
                        "{n} {shift} {area2}"
                    );
                    assert_eq!(
                        plain.div_round32_short(n, shift),
                        expected,
                        "{n} {shift} {area2}"
                    );
                    assert_eq!(
                        expected as i64,
                        small.div_round(n, shift) * area2.signum() as i64
                    );
                }
            }
        }
    }

    /// `term` against the wrapped `i64` plane constant term: the 81
    /// pairs of `edges`, then random gradients from `gradient` (given a
    /// random `u64`), with offsets from the ends of their range and random
    /// ones.
    fn check_offset_term(
        term: fn(i32, i32, [i32; 2]) -> i32,
        edges: [i32; 9],
        gradient: impl Fn(u64) -> i32,
        span: u64,
    ) {
        let mut next = crate::testing::rng();
        let offsets = [0, 1, -1, 8, -8, 15, -17, (1 << 19) + 8, -(1 << 19) - 8];
        for k in 0..200_000 {
            let (gx, gy) = if k < 81 {
                (edges[k % 9], edges[k / 9])
            } else {
                (gradient(next(span)), gradient(next(span)))
            };
            let o = if k % 3 == 0 {
                [offsets[k % 9], offsets[(k / 9) % 9]]
            } else {
                [
                    next(1 << 21) as i32 - (1 << 20),
                    next(1 << 21) as i32 - (1 << 20),
                ]
            };
            let t = gx as i64 * o[0] as i64 + gy as i64 * o[1] as i64;
            let expected = (t >> SUBPIXEL_BITS) as i32;
            assert_eq!(term(gx, gy, o), expected, "{gx} {gy} {o:?}");
        }
    }

    /// ARMv6-M's plane constant term from `i32` products
    /// ([`offset_term_split`]) is the wrapped `i64` one, for random and
    /// extreme gradients and offsets.
    #[test]
    fn split_offset_term_matches_the_64_bit_one() {
        let edges = [
            0,
            1,
            -1,
            15,
            -16,
            i32::MAX,
            i32::MIN + 1,
            (1 << 30) + 1024,
            -(1 << 30) - 1025,
        ];
        check_offset_term(offset_term_split, edges, |v| v as i64 as i32, 1 << 32);
    }

    /// ARMv6-M's plane constant term for gradients below 2^26 in magnitude
    /// ([`offset_term_narrow`]) is the wrapped `i64` one, at the range's
    /// ends and on random gradients and offsets.
    #[test]
    fn narrow_offset_term_matches_the_64_bit_one() {
        let edges = [
            0,
            1,
            -1,
            15,
            -16,
            (1 << 26) - 1,
            -(1 << 26) + 1,
            1 << 23,
            -(1 << 23),
        ];
        let gradient = |v: u64| v as i32 - (1 << 26) + 1;
        check_offset_term(offset_term_narrow, edges, gradient, (1 << 27) - 1);
    }

    /// ARMv6-M's plane ([`SmallBasis::plane_short`]: one test for both
    /// gradients, then two digits each and the narrow constant term, or
    /// the per-gradient path) against the library divisions and the
    /// 64-bit constant term, over numerators of the whole domain and
    /// either side of the two-digit bound, both signs of the area.
    #[test]
    fn short_plane_matches_the_divisions() {
        let mut next = crate::testing::rng();
        let max_area = 2 * 1023 * 1023;
        let mut two = 0;
        for k in 0..300_000u64 {
            let area = match k % 4 {
                0 => 1 + next(8) as i32,
                1 => max_area - next(8) as i32,
                _ => 1 + next(max_area as u64) as i32,
            };
            let area2 = if k % 2 == 0 { area } else { -area };
            if area2 == -1 {
                continue;
            }
            let shift = [18, 20][(k / 2) as usize % 2];
            let limit = ((area as i64) << (30 - shift)).min(1 << 21);
            let bound = (area as i64) << (23 - shift);
            let mut n = || {
                let n = match next(4) {
                    0 => bound - 2 + next(4) as i64,
                    1 => -bound - 1 + next(4) as i64,
                    _ => next(2 * limit as u64) as i64 - limit,
                };
                n.clamp(-limit, (limit - 1).min((1 << 21) - 1)) as i32
            };
            let (n1, n2) = (n(), n());
            let f = SmallBasis {
                e: [0; 4],
                o: [
                    next(1 << 21) as i32 - (1 << 20),
                    next(1 << 21) as i32 - (1 << 20),
                ],
                area2,
                half: area / 2,
                divisor: ShortDivisor::new(NonZeroU32::new(area as u32).unwrap()),
            };
            let (gx, gy) = (
                f.div_round32_with::<false>(n1, shift),
                f.div_round32_with::<false>(n2, shift),
            );
            let t = gx as i64 * f.o[0] as i64 + gy as i64 * f.o[1] as i64;
            let expected = (gx, gy, (t >> SUBPIXEL_BITS) as i32);
            assert_eq!(
                f.plane_short(n1, n2, shift),
                expected,
                "{n1} {n2} << {shift} / {area2}"
            );
            two += (((n1.unsigned_abs() | n2.unsigned_abs()) as i64) < bound) as u32;
        }
        assert!(two > 100_000, "{two}");
    }

    /// Gradients of small triangles through the 32-bit divisions against
    /// the 64-bit ones, for depth, colour and the perspective weights.
    /// The 32-bit long division of the perspective planes' gradients
    /// gives the 64-bit quotient, extremes included.
    #[test]
    fn small_wide_division_matches() {
        let mut next = crate::testing::rng();
        for k in 0..200_000u64 {
            let area = match k % 4 {
                0 => 1,
                1 => (1 << 21) - 1,
                _ => 1 + next((1 << 21) - 1) as u32,
            };
            let small = Small {
                area: NonZeroU32::new(area).unwrap(),
                half: area / 2,
            };
            let n = match k % 3 {
                0 => (1i64 << 43) - 1 - next(1 << 20) as i64,
                _ => next(1 << 43) as i64,
            };
            let n = if k % 2 == 0 { n } else { -n };
            let q = ((n.unsigned_abs() + (area / 2) as u64) / area as u64) as i64;
            let q = if n < 0 { -q } else { q };
            assert_eq!(small.div_round_wide(n), q, "{n} / {area}");
        }
    }

    #[test]
    fn small_gradients_match() {
        let mut next = crate::testing::rng();
        let mut small = 0;
        for k in 0..100_000u64 {
            let r = [64, 600, 2_100][k as usize % 3];
            let mut p = || SubPoint::new(next(r) as i32 - 300, next(r) as i32 - 300);
            let v = [p(), p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let (a, b) = (Basis::with_small(&v, true), Basis::with_small(&v, false));
            small += a.small.is_some() as u32;
            for (max, frac) in [(65_536, Z_FRAC), (256, C_FRAC), (1 << 28, 0)] {
                let values = [next(max) as i64, next(max) as i64, next(max) as i64];
                assert_eq!(
                    a.gradients(values, frac),
                    b.gradients(values, frac),
                    "{v:?}"
                );
            }
        }
        assert!(small > 30_000, "{small} small triangles");
    }

    /// The `i32` set-up of small triangles against the general one, on
    /// every target: the same planes whenever it applies.
    #[test]
    fn small_setup_matches_the_general_one() {
        let mut next = crate::testing::rng();
        let mut applied = 0;
        for k in 0..100_000u64 {
            let r = [24, 64, 600, 2_100][k as usize % 4];
            let mut p = || SubPoint::new(next(r) as i32 - 300, next(r) as i32 - 300);
            let v = [p(), p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let sv = random_vertices(&v, &mut next);
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            let f = Basis::with_small(&v, true);
            for gouraud in [false, true] {
                let general = TriangleSetup::with_basis(&f, &corners, gouraud);
                if let Some(small) = TriangleSetup::small(&v, &corners, gouraud) {
                    assert!(f.small.is_some(), "{v:?}");
                    applied += 1;
                    assert!(!general.wide, "{v:?}");
                    for (a, b) in small.planes.iter().zip(&general.planes) {
                        assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?}");
                    }
                }
            }
        }
        assert!(applied > 50_000, "{applied} small set-ups");
    }

    /// Screen vertices at `v` with random depths and colours.
    fn random_vertices(v: &[SubPoint; 3], next: &mut impl FnMut(u64) -> u64) -> [ScreenVertex; 3] {
        [0, 1, 2].map(|k| {
            let z = next(65_536) as u16;
            let color = [next(256) as u8, next(256) as u8, next(256) as u8];
            ScreenVertex::new(v[k].x, v[k].y, z, 0, color)
        })
    }

    /// The offset set-up of 64-bit hosts against the general one: the
    /// same planes wherever it applies, and `None` exactly where its
    /// bounds say (twice-areas of 2^26 and more or a multiple of 2^19,
    /// gradients beyond 2^36). On triangles small and large, slivers
    /// whose gradients reach far beyond its bound and others near it, and
    /// twice-areas that are multiples of 2^19, where a numerator can be an
    /// exact tie (which the floor of `offset` would round the other way
    /// for a negative one).
    #[cfg(target_pointer_width = "64")]
    #[test]
    fn offset_setup_matches_the_general_one() {
        let mut next = crate::testing::rng();
        let (mut applied, mut near, mut ties, mut beyond) = (0u32, 0u32, 0u32, 0u32);
        for k in 0..300_000u64 {
            let r = [24, 600, 2_100, 40_000, 1 << 19, 1 << 22][k as usize % 6];
            let mut p =
                || SubPoint::new(next(r) as i32 - r as i32 / 2, next(r) as i32 - r as i32 / 2);
            let mut v = [p(), p(), p()];
            match k % 4 {
                1 => {
                    // A sliver: the third vertex a few sub-pixels beside
                    // the first edge's midpoint.
                    let t = 1 + next(8) as i32;
                    v[2] = SubPoint::new((v[0].x + v[1].x) / 2 + t, (v[0].y + v[1].y) / 2);
                }
                2 => {
                    // Twice the area a multiple of 2^19: edge vectors
                    // (2^10 a, b) and (c, 2^9 d) less b c, with b c a
                    // multiple of 2^19 (or 0).
                    let o = v[0];
                    let (a, d) = (1 + next(4) as i32, 1 + next(4) as i32);
                    let b = [0, 1, -1, 3][next(4) as usize];
                    let c = if b == 0 { next(64) as i32 - 32 } else { 0 };
                    let s = if next(2) == 0 { 1 } else { -1 };
                    v[1] = SubPoint::new(o.x + s * (a << 10), o.y + b);
                    v[2] = SubPoint::new(o.x + c, o.y + s * (d << 9));
                }
                _ => {}
            }
            let area2 = crate::raster::signed_area2(&v);
            if area2 == 0 {
                continue;
            }
            let sv = random_vertices(&v, &mut next);
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            let f = Basis::with_small(&v, false);
            // The largest gradient's magnitude, of depth or colour.
            let mut most = 0u64;
            for a in 0..4 {
                let (values, frac) = corners.values(a);
                let (gx, gy) = f.gradients(values, frac);
                most = most.max(gx.unsigned_abs()).max(gy.unsigned_abs());
            }
            let d = area2.unsigned_abs();
            ties += d.is_multiple_of(1 << 19) as u32;
            near += (most >> 35 == 1) as u32;
            for gouraud in [false, true] {
                let general = TriangleSetup::with_basis(&f, &corners, gouraud);
                let offset = TriangleSetup::offset(&v, &corners, gouraud);
                // Depth's gradients alone where flat.
                let most = if gouraud {
                    most
                } else {
                    let (gx, gy) = f.gradients(corners.values(0).0, Z_FRAC);
                    gx.unsigned_abs().max(gy.unsigned_abs())
                };
                // What `offset` takes: q + 2^36 below 2^37 for every
                // gradient q (a positive one of 2^36 fails).
                let takes = d < 1 << 26 && !d.is_multiple_of(1 << 19) && {
                    let mut all = true;
                    for a in 0..if gouraud { 4 } else { 1 } {
                        let (values, frac) = corners.values(a);
                        let (gx, gy) = f.gradients(values, frac);
                        all &= (-(1 << 36)..1 << 36).contains(&gx)
                            && (-(1 << 36)..1 << 36).contains(&gy);
                    }
                    all
                };
                assert_eq!(offset.is_some(), takes, "{v:?} {sv:?} {most}");
                beyond += (d < 1 << 26 && !d.is_multiple_of(1 << 19) && !takes) as u32;
                let Some(offset) = offset else { continue };
                applied += 1;
                assert!(!general.wide, "{v:?}");
                assert_eq!(offset.zstep, general.zstep, "{v:?}");
                for (a, b) in offset.planes.iter().zip(&general.planes) {
                    assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?} {sv:?}");
                }
                // And `new`, which takes it.
                let new = TriangleSetup::new(&corners, gouraud);
                for (a, b) in new.planes.iter().zip(&general.planes) {
                    assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?} {sv:?}");
                }
            }
        }
        assert!(
            applied > 300_000 && near > 1_000 && ties > 10_000 && beyond > 1_000,
            "{applied} {near} {ties} {beyond}"
        );
    }

    /// The general set-up with its colour planes out of line (32-bit
    /// cores) against the inline one, on every target: the same planes,
    /// on triangles small and large, slivers (wide) included.
    #[test]
    fn apart_setup_matches_the_inline_one() {
        let mut next = crate::testing::rng();
        let mut wide = 0;
        for k in 0..100_000u64 {
            let r = [24, 600, 2_100, 40_000, 1 << 22][k as usize % 5];
            let mut p = || SubPoint::new(next(r) as i32 - 300, next(r) as i32 - 300);
            let mut v = [p(), p(), p()];
            if k % 7 == 0 {
                // A sliver: the third vertex next to the first edge's
                // midpoint.
                v[2] = SubPoint::new((v[0].x + v[1].x) / 2 + 1, (v[0].y + v[1].y) / 2);
            }
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let sv = random_vertices(&v, &mut next);
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            let f = Basis::with_small(&v, k % 2 == 0);
            for gouraud in [false, true] {
                let a = TriangleSetup::with_basis(&f, &corners, gouraud);
                let b = TriangleSetup::with_basis_apart(&f, &corners, gouraud);
                wide += a.wide as u32;
                assert_eq!((a.wide, a.zstep), (b.wide, b.zstep), "{v:?}");
                for (a, b) in a.planes.iter().zip(&b.planes) {
                    assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?}");
                }
            }
        }
        assert!(wide > 0, "no wide triangle");
    }

    #[test]
    fn depth16_is_the_integer_part() {
        for z in [
            0i32,
            1 << 13,
            5 << 14,
            (65_535 << 14) + (1 << 13),
            (1 << 30) - 1,
        ] {
            for k in 0..5i32 {
                let gz = -3_000_017 + 1_500_000 * k;
                let exact = z.wrapping_add(gz.wrapping_mul(k));
                let shifted =
                    ((z as u32) << 2).wrapping_add(((gz as u32) << 2).wrapping_mul(k as u32));
                assert_eq!(depth16(shifted), (exact >> Z_FRAC) as u16);
            }
        }
    }

    /// The attribute evaluation as it was before the `i32` planes: `i64`
    /// planes `(gx16 i + gy16 j + k) >> 4` with gradients clamped to ±2^40
    /// and every value clamped to its range at the span start.
    fn reference_start(v: &[SubPoint; 3], vals: [[i64; 3]; 4], i: i32, j: i32) -> [i32; 4] {
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        let area2 = x1 * y2 - x2 * y1;
        let s = if area2 < 0 { -1 } else { 1 };
        let (x1, y1, x2, y2, area) = (s * x1, s * y1, s * x2, s * y2, s * area2);
        let div_round = |n: i64, d: i64| {
            if n >= 0 {
                (n + d / 2) / d
            } else {
                -((-n + d / 2) / d)
            }
        };
        let mut out = [0; 4];
        for (a, o) in out.iter_mut().enumerate() {
            let (frac, max) = if a == 0 {
                (Z_FRAC, 65_535)
            } else {
                (C_FRAC, 255)
            };
            let d1 = vals[a][1] - vals[a][0];
            let d2 = vals[a][2] - vals[a][0];
            let scale = 1i64 << (frac + SUBPIXEL_BITS);
            let gx =
                div_round((d1 * y2 - d2 * y1) * scale, area).clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
            let gy =
                div_round((d2 * x1 - d1 * x2) * scale, area).clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
            let bias = 1i64 << (frac - 1);
            let base = (vals[a][0] << frac) + bias;
            let k = (base << SUBPIXEL_BITS)
                + gx * (HALF_PIXEL as i64 - v[0].x as i64)
                + gy * (HALF_PIXEL as i64 - v[0].y as i64);
            let value = ((gx << SUBPIXEL_BITS) * i as i64 + (gy << SUBPIXEL_BITS) * j as i64 + k)
                >> SUBPIXEL_BITS;
            *o = value.clamp(bias, (max << frac) + bias) as i32;
        }
        out
    }

    /// Span starts and steps of `TriangleSetup` against the previous `i64`
    /// evaluation at every covered pixel of random triangles: ordinary
    /// ones, huge ones reaching the guard band, and slivers whose gradients
    /// exceed the clamp. Along a span the reference is the stepped start,
    /// as the span loops step it.
    #[test]
    fn planes_match_the_i64_evaluation() {
        use crate::raster::{scanline::spans, PixelRect};
        let mut next = crate::testing::rng();
        let (mut pixels, mut wide, mut interiors) = (0u64, 0u32, 0u32);
        for n in 0..6_000 {
            let (range, offset) = match n % 4 {
                0 => (4_000, 0),
                1 => (1 << 19, 1 << 18),
                _ => (600, 0),
            };
            let mut p = || SubPoint::new(next(range) as i32 - offset, next(range) as i32 - offset);
            let mut v = [p(), p(), p()];
            if n % 4 == 3 {
                // A sliver of twice-area 1, up to 2^17 sub-pixels long:
                // edge vectors (F(k+1), F(k)) and (F(k), F(k-1)) of
                // consecutive Fibonacci numbers, whose cross product is
                // ±1, so its gradients go far beyond the clamp.
                let (mut f0, mut f1) = (1i32, 1i32);
                for _ in 0..8 + next(17) {
                    (f0, f1) = (f1, f0 + f1);
                }
                let f2 = f0 + f1;
                let sx = if next(2) == 0 { 1 } else { -1 };
                let sy = if next(2) == 0 { 1 } else { -1 };
                let o = v[0];
                v[1] = SubPoint::new(o.x + sx * f2, o.y + sy * f1);
                v[2] = SubPoint::new(o.x + sx * f1, o.y + sy * f0);
                if next(2) == 0 {
                    v.swap(0, 2);
                }
            }
            // Every other triangle's values are all within the ranges of
            // `ScreenVertex::interior`, half of them at its ends, where
            // only its margin keeps the unclamped start inside.
            let interior = n % 2 == 0;
            let sv = [0, 1, 2].map(|k| {
                let (z, color) = if interior {
                    let z = match next(4) {
                        0 => 2,
                        1 => 65_533,
                        _ => 2 + next(65_532) as u16,
                    };
                    let mut c = || match next(4) {
                        0 => 1,
                        1 => 254,
                        _ => 1 + next(254) as u8,
                    };
                    (z, [c(), c(), c()])
                } else {
                    // Half the channels at 0 or 255, where a start's
                    // rounding can take it outside the range and the clamp
                    // matters.
                    // Depth too, at times at its ends (where the
                    // packed starts clamp it from its plane).
                    let z = match next(8) {
                        0 => 0,
                        1 => 65_535,
                        _ => next(65_536) as u16,
                    };
                    let mut c = || match next(4) {
                        0 => 0,
                        1 => 255,
                        _ => next(256) as u8,
                    };
                    (z, [c(), c(), c()])
                };
                ScreenVertex::new(v[k].x, v[k].y, z, 0, color)
            });
            let vals = [0, 1, 2, 3].map(|a| {
                [0, 1, 2].map(|k| {
                    if a == 0 {
                        sv[k].z() as i64
                    } else {
                        sv[k].color()[a - 1] as i64
                    }
                })
            });
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            let setup = TriangleSetup::new(&corners, true);
            wide += setup.wide as u32;
            // The span loops' set-up, which takes an interior triangle's
            // starts without their clamps.
            let for_spans = TriangleSetup::for_spans::<true>(&corners);
            let all = sv.iter().all(|v| v.interior());
            assert_eq!(for_spans.interior(), all && !setup.wide, "{v:?}");
            interiors += for_spans.interior() as u32;
            let steps = setup.steps();
            let clip = PixelRect::new(0, 0, 4096, 4096);
            spans(&v, clip, |j, x0, x1| {
                let start = setup.start(&corners, x0, j);
                let reference = reference_start(&v, vals, x0, j);
                assert_eq!(start, reference, "{v:?} at ({x0}, {j})");
                // Both forms, whichever this target takes, of both set-ups
                // (the span loops' set-up with its colour planes shifted
                // where `SHIFTED_COLOR`, its starts then shifted too).
                for s in [&setup, &for_spans] {
                    if SHIFTED_COLOR && core::ptr::eq(s, &for_spans) {
                        let [z, r, g, b] = reference;
                        let shifted = [z, r.wrapping_shl(8), g.wrapping_shl(8), b.wrapping_shl(8)];
                        assert_eq!(s.start_shifted(&corners, x0, j, s.interior()), shifted);
                        // ARMv6-M's tested form (`SHIFTED_TOP`).
                        assert_eq!(
                            s.start_tested_shifted(&corners, x0, j, s.interior()),
                            shifted
                        );
                        continue;
                    }
                    assert_eq!(s.start_selects(&corners, x0, j), reference);
                    assert_eq!(s.start_tested(&corners, x0, j), reference);
                }
                // The shifted starts, of a set-up shifted as the span
                // loops' is.
                let mut shifted = setup.for_gouraud_spans(&corners);
                if !SHIFTED_COLOR {
                    for p in &mut shifted.planes[1..] {
                        *p = Plane {
                            gx: p.gx.wrapping_shl(8),
                            gy: p.gy.wrapping_shl(8),
                            k: p.k.wrapping_shl(8),
                        };
                    }
                }
                let [z, r, g, b] = reference;
                assert_eq!(
                    shifted.start_shifted(&corners, x0, j, shifted.interior()),
                    [z, r.wrapping_shl(8), g.wrapping_shl(8), b.wrapping_shl(8)]
                );
                // An interior triangle's starts with depth from the step
                // (the Cortex-M3's `DEPTH_BY_STEP`): the planes' values,
                // depth shifted as the span loop steps it.
                if for_spans.interior() {
                    let [pz, pr, pg, pb] = for_spans.planes.map(|p| p.at(x0, j));
                    assert_eq!(
                        for_spans.start_interior_depth_shifted(x0, j),
                        [pz.wrapping_shl(16 - Z_FRAC), pr, pg, pb],
                        "{v:?} at ({x0}, {j})"
                    );
                    assert_eq!(pz, z);
                }
                // The packed starts (`PACKED`), as the span loop steps
                // them, against the exact planes: for an interior triangle,
                // whose starts they are, the reference itself; for any
                // triangle not wide, the planes' unclamped values (the
                // lanes carry into each other at no covered pixel). At the
                // span's two ends only: the packed value after k steps is
                // the start plus k steps modulo 2^64, and each lane's exact
                // value is linear in x, so a lower lane within 0..2^32 at
                // both ends is within it at every pixel between them (every
                // pixel stepped made the debug lib tests take minutes).
                #[cfg(target_pointer_width = "64")]
                if packed::PACKED && !for_spans.wide && x1 > x0 {
                    let pack = |hi: i32, lo: i32| ((hi as u32 as u64) << 32) | lo as u32 as u64;
                    let [rg0, zb0] = for_spans.start_packed(x0, j);
                    for x in [x0, x1 - 1] {
                        let k = (x - x0) as u64;
                        let rg = rg0.wrapping_add(for_spans.packed[0][0].wrapping_mul(k));
                        let zb = zb0.wrapping_add(for_spans.packed[1][0].wrapping_mul(k));
                        let p = for_spans.planes.map(|p| p.at(x, j));
                        let zs = 16 - Z_FRAC;
                        assert_eq!(rg, pack(p[1], p[2]), "{v:?} at ({x}, {j})");
                        assert_eq!(zb, pack(p[0].wrapping_shl(zs), p[3]), "{v:?} at ({x}, {j})");
                        if for_spans.interior() {
                            let [z, r, g, b] = reference_start(&v, vals, x, j);
                            assert_eq!(rg, pack(r << 8, g << 8));
                            assert_eq!(zb, pack(z.wrapping_shl(zs), b << 8));
                        }
                    }
                    // The clamped packed starts of any triangle, as the
                    // span loop of one that is not interior takes them:
                    // the four-lane loop's starts, packed, at the span's
                    // start and, stepped, at its last pixel (the lanes
                    // carry into each other at neither).
                    let packs = for_spans.packed;
                    let [rg0, zb0] = for_spans.start_packed_clamped(&corners, x0, j);
                    let [z, r, g, b] = for_spans.start_shifted(&corners, x0, j, false);
                    let [gz, gr, gg, gb] = for_spans.steps();
                    let zs = 16 - Z_FRAC;
                    for k in [0, x1 - x0 - 1] {
                        let step = |v: i32, g: i32| v.wrapping_add(g.wrapping_mul(k));
                        let kk = k as u64;
                        let rg = rg0.wrapping_add(packs[0][0].wrapping_mul(kk));
                        let zb = zb0.wrapping_add(packs[1][0].wrapping_mul(kk));
                        assert_eq!(rg, pack(step(r, gr), step(g, gg)), "{v:?} at ({x0}, {j})");
                        let z = step(z.wrapping_shl(zs), gz);
                        assert_eq!(zb, pack(z, step(b, gb)), "{v:?} at ({x0}, {j})");
                    }
                }
                // Along a span of two pixels or more the step is the exact
                // x gradient (the old one, saturated to i32, was the same).
                if x1 - x0 >= 2 {
                    let next = reference_start(&v, vals, x0 + 1, j);
                    for a in 0..4 {
                        let unclamped = |x: [i32; 4]| {
                            x[a] > if a == 0 { Z_LO } else { C_LO }
                                && x[a] < if a == 0 { Z_HI } else { C_HI }
                        };
                        if unclamped(reference) && unclamped(next) {
                            assert_eq!(next[a] - reference[a], steps[a], "{v:?} at ({x0}, {j})");
                        }
                    }
                }
                // Every pixel's channels, stepped from the start, within
                // `0..256` units: the Gouraud loop's table index of green
                // raised by `GREEN_UP` relies on it (`rgb16_green_up`).
                // The exact value `start + steps k` is linear in `k`, so it
                // lies in the range at every pixel iff it does at the
                // span's two ends; there it is below 2^31 in magnitude, so
                // the loop's wrapping `i32` steps are exact at every pixel
                // too. (Two checks a span rather than one a pixel: some
                // spans are 4,096 pixels long.)
                let last = (x1 - x0 - 1) as i64;
                for a in 1..4 {
                    for k in [0, last].into_iter().filter(|_| last >= 0) {
                        let c = start[a] as i64 + steps[a] as i64 * k;
                        assert!(
                            (0..256 << C_FRAC).contains(&c),
                            "{v:?} at ({x0}, {j}) + {k}"
                        );
                    }
                }
                pixels += (x1 - x0) as u64;
            });
        }
        assert!(pixels > 100_000, "{pixels} pixels");
        assert!(wide > 100, "{wide} wide triangles");
        assert!(interiors > 2_000, "{interiors} interior triangles");
    }
}
