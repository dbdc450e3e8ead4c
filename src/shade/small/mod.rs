//! The attribute set-up of a small triangle on a 32-bit core: edge
//! vectors below 2^10 sub-pixels (64 pixels), twice the area below 2^21,
//! so the gradients come from long divisions in 32-bit steps (one
//! instruction each on a Cortex-M3/M4) and, where every value fits, the
//! whole set-up runs in `i32` ([`TriangleSetup::small`]; on ARMv6-M,
//! which has no divider, by one reciprocal of the area and 16-bit
//! products instead: [`Recip16`]). The planes are
//! exactly those of the general set-up ([`TriangleSetup::with_basis`]),
//! which the tests check on random triangles.

use super::plane::{Basis, Plane};
use super::setup::{Corners, TriangleSetup};
use crate::math::Recip16;
use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use core::num::NonZeroU32;

mod divide;

pub(super) use divide::{AreaDivisor, ShortDivisor, Small, SmallBasis};

/// On 32-bit targets, the attribute set-up of a small triangle (edge
/// vectors from vertex 0 below this, in sub-pixels: 64 pixels) divides in
/// 32-bit operations ([`Small::div_round`]) instead of through the 64-bit
/// reciprocal of its area; 64-bit targets keep their division instruction.
/// The gradients are the same.
pub(super) const SMALL_EDGE: i64 = 1 << 10;
/// Whether the target sets small triangles up in 32-bit divisions.
pub(super) const SMALL_SETUP: bool = cfg!(not(target_pointer_width = "64"));

/// Whether a colour plane of [`TriangleSetup::small`] takes its numerators
/// times 2^10 from the edge vectors shifted left by 10
/// ([`SmallBasis::div_round32_of_m`]) rather than shifting the
/// numerators: on ARMv7E-M (the build script's `microraster_armv7em`)
/// and ARMv7-M (below),
/// where each gradient's remainder then takes one multiply-subtract
/// (`MLS`) instead of a multiply and a subtract of a shifted operand,
/// and the numerator no shift of its own, for four shifts a triangle
/// (the three planes share them). The same gradients. Cortex-M4F `demo`
/// 2,974,002 -> 2,953,379 instructions; in the all-scenes build `demo`
/// 2,974,029 -> 2,953,406, `rock` 2,472,087 -> 2,456,357, `grid4`
/// 852,270 -> 844,539, the others the same.
///
/// The M4F's set-up had read each channel's vertex values after an empty
/// `black_box` (LLVM schedules a core with a floating-point unit for
/// latency, and started the three channels' products and divisions
/// together: `demo` 3,015,727 -> 3,010,132 when they came in); with
/// this set-up they cost: the three barriers `demo` 2,961,124, green's
/// and blue's 2,963,179, none 2,953,379. The colour differences shifted
/// instead of the edge vectors (two shifts a plane) gave 2,969,379 with
/// green's and blue's barriers, 2,994,182 with none, 3,015,296 with
/// three; without this set-up, no barrier gave 2,972,444.
///
/// On ARMv7-M (the build script's `microraster_armv7m`: the Cortex-M3 has
/// `MLS` too), with [`HALF_TEST`]: `demo` 2,976,189 -> 2,959,005, `rock`
/// 2,449,967 -> 2,441,859, `grid4` 848,800 -> 841,417, `demo-flat` and
/// `fill` the same (with `render::fill`'s `EARLY_INTERIOR` as well,
/// `demo` 2,975,330, `rock` 2,456,407, `grid4` 846,733: not taken). Not
/// on ARMv6-M (no `MLS`; the set-up out of line): `demo` 6,081,152 ->
/// 9,073,694.
///
/// On the Pico 2's Cortex-M33 (ARMv8-M Mainline, `microraster_armv8m`)
/// and the ESP32-C3's RV32IMC, without `HALF_TEST` (with it +5 K on
/// each): frame 0 of the boards' scene 2,182,150 -> 2,178,150 and
/// 2,584,513 -> 2,576,467 instructions.
const SHIFTED_NUMERATORS: bool = cfg!(any(
    microraster_armv7em,
    microraster_armv7m,
    microraster_armv8m,
    target_arch = "riscv32"
));

/// Whether [`TriangleSetup::small`] bounds depth's first digits by half
/// the area (`m >> 13 < half`, see [`half_bound_holds`]) rather than by the
/// area (`m >> 12 < area`): on ARMv7E-M (the build script's
/// `microraster_armv7em`) and ARMv7-M (below), and in the unit tests, which compare the small
/// set-up with the general one under it. Half the area is then a value
/// that the tests compare before the branch, held in a register, where
/// each gradient's rounding took it as the area shifted, an operand that
/// the signed half's `EOR` folded in (`lsr #1`), so that the numerator's
/// sign took an `ASR` of its own: each of a Gouraud triangle's eight
/// gradients now takes the half with its sign in two instructions
/// (`EOR` with the numerator shifted, `ADD` of its sign bit), where it
/// took three. With the interior bit read from the vertices
/// (`render::fill`'s `EARLY_INTERIOR`) the Cortex-M4F's `demo` 2,953,379
/// -> 2,937,011 instructions, in the all-scenes build `demo` 2,953,406 ->
/// 2,937,038, `rock` 2,456,357 -> 2,442,369, `grid4` 844,539 -> 837,667,
/// `demo-flat` 2,503,569 -> 2,499,119 (the small set-up, about 7
/// instructions fewer a pair), `fill` 8,839,841 -> 8,839,081, the shader
/// fills and `demo-textured-lit` the same. Alone, `demo` measured
/// 2,967,907 (the span start's registers moved: two instructions more a
/// span). The bound is stricter (a triangle it turns away takes the
/// general set-up, the same planes); in `demo` the same 95 pairs a run
/// take the general set-up either way.
///
/// On ARMv7-M (the build script's `microraster_armv7m`: the Cortex-M3) the
/// bound alone measured best: `demo` 2,986,611 -> 2,976,189, `rock`
/// 2,458,702 -> 2,449,967, `grid4` 853,095 -> 848,800, `demo-flat`
/// 2,525,643 -> 2,523,355, `fill` 8,846,204 -> 8,840,124 (with
/// `EARLY_INTERIOR` too, `demo` 2,978,987, `rock` 2,451,716, `grid4`
/// 849,659; that alone, `demo` 2,985,527). Not on ARMv6-M, where the
/// set-up is out of line: `demo` 6,081,152 -> 6,107,238, `rock`
/// 5,077,935 -> 5,098,200. 64-bit targets take no small set-up.
const HALF_TEST: bool = cfg!(any(microraster_armv7em, microraster_armv7m, test));

/// The depth bound of [`HALF_TEST`]: `m >> 13 < half` (with `half =
/// area / 2`) implies `m >> 12 < area`, the bound that keeps the first
/// digits of depth's gradients at most 2^22 (see
/// [`SmallBasis::div_round32`]), as `m >> 12 <= 2 (m >> 13) + 1 <=
/// 2 half - 1 < area`.
#[inline(always)]
const fn half_bound_holds(m: u32, half: u32) -> bool {
    m >> 13 < half
}

impl TriangleSetup {
    /// The set-up of a [`Small`] triangle `v` (on 32-bit targets) all in
    /// `i32` arithmetic, when its gradients' first digits are small enough
    /// and depth's numerators below 2^21 ([`SmallBasis::div_round32`]):
    /// the planes [`TriangleSetup::with_basis`] gives on [`Basis::new`],
    /// without building the basis's 64-bit values or its 64-bit
    /// quotients, constants and range test; `None` for any other
    /// triangle.
    ///
    /// Both bounds are checked before any division, colour's from the
    /// edge vectors alone: a test of the quotients themselves made the
    /// optimiser take every plane's first digits before the test (they
    /// decide whether the rest is needed), more live values than a
    /// Cortex-M3 has registers.
    #[inline(always)]
    pub(super) fn small(v: &[SubPoint; 3], t: &Corners<'_>, gouraud: bool) -> Option<Self> {
        Self::small_as(v, t, gouraud, false)
    }

    /// [`TriangleSetup::small`], made ready for the span loops
    /// ([`TriangleSetup::for_gouraud_spans`]) where `spans`: ARMv6-M's
    /// [`TriangleSetup::gouraud_spans`], whose shifted colour planes
    /// ([`SHIFTED_TOP`](super::setup::SHIFTED_TOP)) are then shifted in
    /// the registers that computed them, before the set-up's stores.
    #[inline(always)]
    pub(super) fn small_as(
        v: &[SubPoint; 3],
        t: &Corners<'_>,
        gouraud: bool,
        spans: bool,
    ) -> Option<Self> {
        // Within the guard band the edge vectors fit i32.
        let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
        let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
        // The edge vectors' magnitudes, less one for negative ones, or-ed:
        // below 1023 only if every one is within -1023..=1022, inside
        // `Basis`'s small triangles (|c| < SMALL_EDGE).
        let e = fold_sign(x1) | fold_sign(y1) | fold_sign(x2) | fold_sign(y2);
        // Every test below decides one `None`, or-ed: with a return of
        // its own each (the depth test's in `plane_small`), the
        // Cortex-M3 reloaded the span loop's stack argument before each
        // branch (`demo` 3,934,041 -> 3,925,390 instructions, `rock`
        // 3,232,869 -> 3,225,860, ARMv6-M `demo` 8,303,170 ->
        // 8,216,578). The values are wrapped where a test that fails
        // made them meaningless (edge vectors of 2^10 or more), and exact
        // where every test passes. (The same tests as the signs of
        // differences, or-ed into one word, compiled to one branch but
        // moved the span loop's registers: M3 `demo` +185,000.)
        //
        // At most 2 * 1023^2 in magnitude (`Basis`'s twice the signed
        // area). -1 goes to the general set-up too: the divisions by it
        // then need no check for `i32::MIN / -1`.
        let area2 = x1.wrapping_mul(y2).wrapping_sub(x2.wrapping_mul(y1));
        let area = area2.unsigned_abs();
        // Depth's numerators reach 2^27: within -2^21..2^21 (`m`, the
        // magnitudes less one when negative, below 2^21) and below
        // `area 2^12` (first digits at most 2^22), or the general set-up.
        let (z, zfrac) = t.values(0);
        let z = [z[0] as i32, z[1] as i32, z[2] as i32];
        let (d1, d2) = (z[1] - z[0], z[2] - z[0]);
        let n1 = d1.wrapping_mul(y2).wrapping_sub(d2.wrapping_mul(y1));
        let n2 = d2.wrapping_mul(x1).wrapping_sub(d1.wrapping_mul(x2));
        let m = fold_sign(n1) | fold_sign(n2);
        // A colour channel's numerators `d1 y2 - d2 y1` and `d2 x1 - d1 x2`
        // are at most `2 * 255 (e + 1)` in magnitude, below `1024 area`
        // for `e < 2 area`, so their first digits are below 2^20. Only
        // slivers fail this (a triangle's height is below its sides).
        // (`2 area` wraps only for edge vectors that fail the first test.)
        let bad = (e >= SMALL_EDGE as u32 - 1)
            | ((area2.wrapping_add(1) as u32) <= 1)
            | (m >> 21 != 0)
            | if HALF_TEST {
                // Stricter (see `half_bound_holds`), and half the area a
                // register of its own for the gradients (`HALF_TEST`).
                !half_bound_holds(m, area / 2)
            } else {
                m >> 12 >= area
            }
            | (gouraud & (e >= area.wrapping_mul(2)));
        if bad {
            return None;
        }
        let f = &SmallBasis {
            e: [x1, y1, x2, y2],
            o: [HALF_PIXEL - v[0].x, HALF_PIXEL - v[0].y],
            area2,
            half: (area / 2) as i32,
            // Only ARMv6-M divides by it (`area` is not 0).
            divisor: match NonZeroU32::new(area) {
                Some(a) if cfg!(microraster_narrow_multiply) => ShortDivisor::new(a),
                _ => ShortDivisor::default(),
            },
        };
        let z = Self::plane_small_of(f, z[0], zfrac, n1, n2);
        let planes = if gouraud {
            let r = Self::plane_small(f, t, 1);
            let g = Self::plane_small(f, t, 2);
            let b = Self::plane_small(f, t, 3);
            [z, r, g, b]
        } else {
            [z, Plane::default(), Plane::default(), Plane::default()]
        };
        // Gradients within 2^30 + 2^10 are far inside the clamp: never
        // wide.
        let s = Self::finish(planes, false);
        Some(if spans { s.for_gouraud_spans(t) } else { s })
    }

    /// [`TriangleSetup::plane`] of a colour channel `a` (1 to 3) of a
    /// [`Small`] triangle in `i32`: its values' differences are below 2^8
    /// and its edge vectors below 2^10, so the numerators are below 2^19
    /// (as in [`Basis::gradients`]), whose first digits
    /// [`TriangleSetup::small`] checked.
    #[inline(always)]
    fn plane_small(f: &SmallBasis, t: &Corners<'_>, a: usize) -> Plane {
        let (values, frac) = t.values(a);
        let v = [values[0] as i32, values[1] as i32, values[2] as i32];
        let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
        if cfg!(any(microraster_narrow_multiply, test)) && d1 | d2 == 0 {
            // A channel of the same value at the three vertices (a face
            // that the light does not reach, lit by the ambient colour
            // alone): its gradients and term are 0 (the numerators are),
            // without the digits and products. ARMv6-M `demo`
            // 7,416,546 -> 7,350,435 instructions, `rock` 6,140,689 ->
            // 6,123,092. (Also in the unit tests, which compare it with
            // the general set-up.)
            return Plane {
                gx: 0,
                gy: 0,
                k: (v[0] << frac) + (1 << (frac - 1)),
            };
        }
        let [x1, y1, x2, y2] = f.e;
        if SHIFTED_NUMERATORS {
            // The numerators times 2^10 from the edge vectors shifted
            // (see `SHIFTED_NUMERATORS`): `|d| < 2^8`, edge vectors below
            // 2^10, so each product is below 2^28 and the sums below
            // 2^29 in magnitude.
            let [x1, y1, x2, y2] = [x1 << 10, y1 << 10, x2 << 10, y2 << 10];
            let (m1, m2) = (d1 * y2 - d2 * y1, d2 * x1 - d1 * x2);
            let shift = frac + SUBPIXEL_BITS;
            let (gx, gy) = (f.div_round32_of_m(m1, shift), f.div_round32_of_m(m2, shift));
            let base = (v[0] << frac) + (1 << (frac - 1));
            return Plane {
                gx,
                gy,
                k: base.wrapping_add(offset_term(gx, gy, f.o)),
            };
        }
        let (n1, n2) = (d1 * y2 - d2 * y1, d2 * x1 - d1 * x2);
        Self::plane_small_of(f, v[0], frac, n1, n2)
    }

    /// The plane of an attribute of a [`Small`] triangle whose value at
    /// vertex 0 is `v0` (`frac` fraction bits) and whose gradients'
    /// numerators are `n1, n2`, within [`SmallBasis::div_round32`]'s
    /// bounds. With gradients within 2^31 and the offsets of the first
    /// pixel centre below 2^19 + 8, the constant's products need no
    /// wrapping (`i32` by `i32`), and its wrapped `i32` is
    /// `constant_wrapping`'s.
    #[inline(always)]
    fn plane_small_of<D: AreaDivisor>(
        f: &SmallBasis<D>,
        v0: i32,
        frac: u32,
        n1: i32,
        n2: i32,
    ) -> Plane {
        let shift = frac + SUBPIXEL_BITS;
        let (gx, gy, term) = if cfg!(microraster_narrow_multiply) {
            f.plane_short(n1, n2, shift)
        } else {
            let (gx, gy) = (f.div_round32(n1, shift), f.div_round32(n2, shift));
            (gx, gy, offset_term(gx, gy, f.o))
        };
        let base = (v0 << frac) + (1 << (frac - 1));
        Plane {
            gx,
            gy,
            k: base.wrapping_add(term),
        }
    }
}

impl TriangleSetup {
    /// The depth plane of [`TriangleSetup::with_basis`] (flat: no colour
    /// planes) for a [`Small`] triangle `s` whose basis is `f`, by the
    /// `i32` set-up of [`TriangleSetup::small`] where depth's numerators
    /// allow (within `-2^21..2^21` and below `area 2^12`, as there;
    /// `None` otherwise), its gradients by `recip`, the area's
    /// [`Recip16`] (unscaled, as an [`AreaDivisor`]): ARMv6-M's perspective
    /// set-up, which makes that reciprocal once for its planes and this
    /// one, where the general set-up divided each depth gradient in three
    /// digits with 64-bit partial quotients after a reciprocal of its own.
    ///
    /// The numerators are the general set-up's: `Basis`'s edge vectors
    /// (negated where the area is negative) and its positive twice the
    /// area, whose quotients [`SmallBasis::div_round32`] rounds as
    /// [`Small::div_round`] does (magnitudes, the sign of the
    /// numerator), and the constant's low 32 bits are
    /// [`Basis::constant_low`]'s (see [`offset_term`]). The same plane.
    #[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
    #[inline(always)]
    pub(super) fn depth_small(
        f: &Basis,
        s: &Small,
        recip: Recip16,
        t: &Corners<'_>,
    ) -> Option<Self> {
        // A small triangle's edge vectors are below 2^10 in magnitude.
        let [x1, y1, x2, y2] = [f.x1 as i32, f.y1 as i32, f.x2 as i32, f.y2 as i32];
        let area = s.area.get();
        let (z, zfrac) = t.values(0);
        let z = [z[0] as i32, z[1] as i32, z[2] as i32];
        let (d1, d2) = (z[1] - z[0], z[2] - z[0]);
        // |d| < 2^16: each numerator below 2^27 in magnitude.
        let (n1, n2) = (d1 * y2 - d2 * y1, d2 * x1 - d1 * x2);
        let m = fold_sign(n1) | fold_sign(n2);
        if (m >> 21 != 0) | (m >> 12 >= area) {
            return None;
        }
        let b = &SmallBasis {
            e: [x1, y1, x2, y2],
            o: [f.ox as i32, f.oy as i32],
            // Below 2^21: positive in `i32`.
            area2: area as i32,
            half: s.half as i32,
            divisor: recip,
        };
        let z = Self::plane_small_of(b, z[0], zfrac, n1, n2);
        let none = Plane::default();
        Some(Self::finish([z, none, none, none], false))
    }
}

impl<D: AreaDivisor> SmallBasis<D> {
    /// The bound of the numerators' magnitudes over `2^(23 - shift)` below
    /// which a gradient takes [`SmallBasis::div_round_two_digits`]: `d`,
    /// or 0 where `d >= 2^20` (twice an area of 2,048 pixels and more,
    /// where the uncorrected first remainder shifted left by 11 could
    /// overflow; those take three digits).
    #[inline(always)]
    fn two_digit_bound(&self) -> u32 {
        self.divisor.bound()
    }

    /// ARMv6-M's gradients of numerators `n1`, `n2` (as
    /// [`SmallBasis::div_round32_short`]) and the plane constant's term
    /// (as [`offset_term`]), tested once for the plane rather than once a
    /// gradient: where both magnitudes or-ed are below
    /// `d 2^(23 - shift)`, each is (so both gradients take two digits,
    /// [`SmallBasis::div_round_two_digits`]), and both gradients are below
    /// `2^23 + 2^11 + 1 < 2^26` in magnitude, within
    /// [`offset_term_narrow`]'s range. Any other plane: the per-gradient
    /// test and [`offset_term_split`]. ARMv6-M `demo` 8,189,046 ->
    /// 7,965,098 instructions, `rock` 6,771,913 -> 6,596,192: one branch
    /// a plane where there were two, and two products fewer.
    #[inline(always)]
    pub(super) fn plane_short(&self, n1: i32, n2: i32, shift: u32) -> (i32, i32, i32) {
        let (a1, a2) = (n1.unsigned_abs(), n2.unsigned_abs());
        if (a1 | a2) >> (23 - shift) < self.two_digit_bound() {
            let gx = self.div_round_two_digits(n1, shift);
            let gy = self.div_round_two_digits(n2, shift);
            (gx, gy, offset_term_narrow(gx, gy, self.o))
        } else {
            // Marked rare (about one plane in thirty in `demo`), so that
            // the register allocator favours the two-digit path: ARMv6-M
            // `demo` 7,320,133 -> 7,297,225 instructions, `rock` 6,101,954
            // -> 6,084,454.
            crate::hint::cold();
            let gx = self.div_round32_short(n1, shift);
            let gy = self.div_round32_short(n2, shift);
            (gx, gy, offset_term_split(gx, gy, self.o))
        }
    }
}

/// The plane constant's term `(gx ox + gy oy) >> SUBPIXEL_BITS` wrapped to
/// `i32` (as `plane_small` adds it), for `|gx|, |gy| < 2^31`.
///
/// On ARMv6-M without `i64` products (each a library call there): with
/// `o = 16 a + b` and `g = 16 h + l` (`b`, `l` in `0..16`, arithmetic
/// shifts), `g o = 16 (g a + h b) + l b`, so
/// `floor((gx ox + gy oy) / 16) = gx ax + gy ay + hx bx + hy by +
/// floor((lx bx + ly by) / 16)` exactly; the last sum is below 2^9 and
/// the rest is needed only modulo 2^32 (wrapping `i32` products).
#[inline(always)]
fn offset_term(gx: i32, gy: i32, o: [i32; 2]) -> i32 {
    if cfg!(microraster_narrow_multiply) {
        offset_term_split(gx, gy, o)
    } else {
        let t = gx as i64 * o[0] as i64 + gy as i64 * o[1] as i64;
        (t >> SUBPIXEL_BITS) as i32
    }
}

/// [`offset_term`] from `i32` products (ARMv6-M).
#[inline(always)]
pub(super) fn offset_term_split(gx: i32, gy: i32, o: [i32; 2]) -> i32 {
    const MASK: i32 = (1 << SUBPIXEL_BITS) - 1;
    let (ax, bx) = (o[0] >> SUBPIXEL_BITS, o[0] & MASK);
    let (ay, by) = (o[1] >> SUBPIXEL_BITS, o[1] & MASK);
    let low = ((gx & MASK) * bx + (gy & MASK) * by) >> SUBPIXEL_BITS;
    gx.wrapping_mul(ax)
        .wrapping_add(gy.wrapping_mul(ay))
        .wrapping_add((gx >> SUBPIXEL_BITS).wrapping_mul(bx))
        .wrapping_add((gy >> SUBPIXEL_BITS).wrapping_mul(by))
        .wrapping_add(low)
}

/// [`offset_term`] from four `i32` products, for `|gx|, |gy| < 2^26`
/// (ARMv6-M's usual planes, [`SmallBasis::plane_short`]): with
/// `o = 16 a + b` (`b` in `0..16`), `gx ox + gy oy = 16 (gx ax + gy ay) +
/// gx bx + gy by`, so its floor over 16 is `gx ax + gy ay +
/// floor((gx bx + gy by) / 16)`, where the last sum is below `2^31` in
/// magnitude (exact in `i32`) and the rest is needed only modulo 2^32.
/// Two products fewer than [`offset_term_split`], which splits the
/// gradients too.
#[inline(always)]
pub(super) fn offset_term_narrow(gx: i32, gy: i32, o: [i32; 2]) -> i32 {
    const MASK: i32 = (1 << SUBPIXEL_BITS) - 1;
    let (ax, bx) = (o[0] >> SUBPIXEL_BITS, o[0] & MASK);
    let (ay, by) = (o[1] >> SUBPIXEL_BITS, o[1] & MASK);
    gx.wrapping_mul(ax)
        .wrapping_add(gy.wrapping_mul(ay))
        .wrapping_add((gx * bx + gy * by) >> SUBPIXEL_BITS)
}

/// `c`'s magnitude, less one when `c` is negative: or-ed over several
/// values, below `2^k` exactly when every one is within `-2^k..2^k`, in
/// two instructions a value and one compare for all.
#[inline(always)]
fn fold_sign(c: i32) -> u32 {
    (c ^ (c >> 31)) as u32
}

#[cfg(test)]
mod tests {
    use super::super::plane::Basis;
    use super::*;
    use crate::vertex::ScreenVertex;

    /// [`half_bound_holds`] implies the depth bound it replaces
    /// (`m >> 12 < area`) for every area up to `2 * 1023^2` and
    /// numerators' magnitudes below 2^21, near the bound and at random.
    #[test]
    fn half_bound_implies_the_area_bound() {
        let mut next = crate::testing::rng();
        let max_area = 2 * 1023 * 1023;
        let mut checked = 0;
        for k in 0..200_000u64 {
            let area = match k % 4 {
                0 => next(64) as u32,
                1 => next(max_area + 1) as u32,
                _ => (next(max_area / 2) as u32) * 2 + (k % 2) as u32,
            };
            let half = area / 2;
            // Around the bound's edge: `m` near `half 2^13`.
            let edge = (half << 13).min((1 << 21) - 1);
            let m = match k % 3 {
                0 => next(1 << 21) as u32,
                _ => edge.saturating_sub(next(1 << 14) as u32) + next(1 << 14) as u32,
            }
            .min((1 << 21) - 1);
            if half_bound_holds(m, half) {
                assert!(m >> 12 < area, "{m} {area}");
                checked += 1;
            }
        }
        assert!(checked > 10_000, "{checked}");
    }

    /// ARMv6-M's perspective depth plane ([`TriangleSetup::depth_small`],
    /// from `Basis`'s edge vectors and the area's reciprocal) against the
    /// general set-up's flat one: the same plane wherever it applies (all
    /// but slivers and steep depths).
    #[test]
    fn depth_small_matches_the_general_setup() {
        let mut next = crate::testing::rng();
        let (mut small, mut applied) = (0, 0);
        for k in 0..60_000u64 {
            let r = [24, 64, 600, 2040][k as usize % 4];
            let mut p = || SubPoint::new(next(r) as i32 - 1020, next(r) as i32 - 1020);
            let v = [p(), p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            // Depths near one another, or anywhere.
            let z0 = next(65_536) as i64;
            let spread = [16, 1024, 65_536][next(3) as usize];
            let mut z = || (z0 + next(spread) as i64 - spread as i64 / 2).clamp(0, 65_535) as u16;
            let sv = [0, 1, 2].map(|i| ScreenVertex::new(v[i].x, v[i].y, z(), 0, [0; 3]));
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            let f = Basis::with_small(&v, true);
            let general = TriangleSetup::with_basis(&f, &corners, false);
            let Some(s) = &f.small else {
                continue;
            };
            small += 1;
            let recip = Recip16::new_small(s.area);
            if let Some(d) = TriangleSetup::depth_small(&f, s, recip, &corners) {
                applied += 1;
                let (a, b) = (d.planes[0], general.planes[0]);
                assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?} {sv:?}");
                assert_eq!((d.zstep, d.wide), (general.zstep, general.wide));
            }
        }
        assert!(small > 20_000 && applied > 30_000, "{small} {applied}");
    }

    /// The small set-up of triangles whose colour channels often have one
    /// value at the three vertices (its flat planes, taken without their
    /// divisions) against the general set-up: the same planes.
    #[test]
    fn flat_channels_match_the_general_setup() {
        let mut next = crate::testing::rng();
        let (mut flat, mut applied) = (0, 0);
        for k in 0..60_000u64 {
            let r = [24, 64, 600][k as usize % 3];
            let mut p = || SubPoint::new(next(r) as i32 - 300, next(r) as i32 - 300);
            let v = [p(), p(), p()];
            if crate::raster::signed_area2(&v) == 0 {
                continue;
            }
            // Channels from two values, one of them an end of the range.
            let ends = [0, 255, next(256) as u8];
            let base = [
                ends[next(3) as usize],
                ends[next(3) as usize],
                ends[next(3) as usize],
            ];
            let sv = [0, 1, 2].map(|i| {
                let mut c = base;
                if next(4) == 0 {
                    c[i % 3] = next(256) as u8;
                }
                ScreenVertex::new(v[i].x, v[i].y, next(65_536) as u16, 0, c)
            });
            let corners = Corners([&sv[0], &sv[1], &sv[2]]);
            let general = TriangleSetup::with_basis(&Basis::with_small(&v, true), &corners, true);
            if let Some(small) = TriangleSetup::small(&v, &corners, true) {
                applied += 1;
                for (a, b) in small.planes.iter().zip(&general.planes) {
                    assert_eq!((a.gx, a.gy, a.k), (b.gx, b.gy, b.k), "{v:?} {sv:?}");
                    flat += (a.gx | a.gy == 0) as u32;
                }
            }
        }
        assert!(applied > 20_000 && flat > 20_000, "{applied} {flat}");
    }
}
