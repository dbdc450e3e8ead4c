//! The nearest-texel span loops of [`Textured`](crate::shader::Textured)
//! and [`TexturedLit`](crate::shader::TexturedLit) on a repeated
//! power-of-two `Rgb565` texture: their per-triangle constants
//! ([`TriangleSpans::nearest_constants`]) and the loops themselves, out of
//! line: [`nearest_span`], with affine, shifted or constant-`Q` weights
//! (and with affine ones `TexturedLit`'s texels lit by the colour planes'
//! colour); in [`affine`], a triangle's affine spans at once (on 64-bit
//! hosts with the pixel loop of their own, elsewhere through
//! `nearest_span`); and, in [`quasi`], `nearest_quasi_span`,
//! quasi-perspective (the same bits as the general loop's), which also
//! draws `TexturedLit`'s texels lit by the interpolated colour. How a
//! loop colours its texel is [`light`]'s.

use super::barycentric::{flat_weights, shifted_weights, span_reciprocal};
use super::lerp::NARROW_MULTIPLY;
use super::span::{AFFINE, FLAT_Q};
use super::{depth16, SpanInput, Z_FRAC};
use crate::math::mul_wide;
use crate::shader::TriangleSpans;
use crate::texture::FromTexel;
use fixed::types::I16F16;
use light::{Light, SpanLight, Unlit};

mod affine;
#[cfg(not(target_pointer_width = "64"))]
pub(crate) use affine::SHORT_SPANS;
mod light;
mod quasi;

impl<C> TriangleSpans<'_, C, [I16F16; 2]> {
    /// What [`SpanInput::run_nearest`] reads that is the same for every
    /// span of the triangle in the tile, for a repeated power-of-two
    /// `Rgb565` texture (`texels` and `parts`, the width, height and texel
    /// count less one, from `Pow2Rgb565::fine_parts`; on ARMv6-M the
    /// shifts of `fu` and `fv` in place of the width and height), with the
    /// affine loop's steps if `affine`: gathered once per
    /// triangle and tile rather than copied into each span's record (about
    /// 30 instructions a span on the Cortex-M3). `None` if the texels are
    /// short of the count (never, by `Texture::new`).
    #[inline(always)]
    pub(crate) fn nearest_constants<'t>(
        &self,
        texels: &'t [u16],
        parts: [u32; 3],
        affine: bool,
    ) -> Option<NearestConstants<'t>> {
        let p = self.setup;
        let [f0u, f0v] = p.fine0;
        let [[d1u, d1v], [d2u, d2v]] = p.dvar;
        let [pq, p1, p2] = &p.planes;
        // The texels hold the count (`Pow2Rgb565::fine_parts`; never short,
        // by `Texture::new`).
        let texels = texels.get(..=parts[2] as usize)?;
        let mut k = [0; at::LEN];
        k[at::F0U] = f0u.to_bits() as u32;
        k[at::D1U] = d1u.to_bits() as u32;
        k[at::D2U] = d2u.to_bits() as u32;
        k[at::F0V] = f0v.to_bits() as u32;
        k[at::D1V] = d1v.to_bits() as u32;
        k[at::D2V] = d2v.to_bits() as u32;
        k[at::DZ] = (p.depth.steps()[0] as u32) << (16 - Z_FRAC);
        k[at::DQ] = pq.step() as u32;
        k[at::DB1] = p1.step() as u32;
        k[at::DB2] = p2.step() as u32;
        [k[at::WIDTH], k[at::HEIGHT], k[at::LAST]] = parts;
        if !(affine && TRIANGLE_STEPS) {
            return Some(NearestConstants { texels, k });
        }
        // With `affine`, where `TRIANGLE_STEPS`, the affine loop's steps
        // of its sums (`nearest_span`), the same for every span: `2^20 (d1
        // g1 + d2 g2)` modulo 2^64 for `u` and `v`, or where
        // `MASKED_INDEX` `2^0` of that, shifted up by `log2(w)` and
        // `log2(w h)` (stored too).
        let (lu, lv) = if MASKED_INDEX {
            index_shifts(parts[0], parts[1])
        } else {
            (0, 0)
        };
        let g = (p1.step(), p2.step());
        let step = |d1: I16F16, d2: I16F16| affine_sum((d1.to_bits(), d2.to_bits()), g);
        let (gu, gv) = (step(d1u, d2u) << lu, step(d1v, d2v) << lv);
        // (None where `at::LEN` leaves the words out.)
        if let [a, b, c, d, e, f] = &mut k[at::GU..] {
            [*a, *b, *c, *d, *e, *f] = [
                gu as u32,
                (gu >> 32) as u32,
                gv as u32,
                (gv >> 32) as u32,
                lu,
                lv,
            ];
        }
        Some(NearestConstants { texels, k })
    }
}

impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// [`run_opaque`](Self::run_opaque) for
    /// [`Textured`](crate::shader::Textured) on a repeated power-of-two
    /// `Rgb565` texture, nearest (its constants `c`, from
    /// [`TriangleSpans::nearest_constants`]), with
    /// [`SHIFTED`](super::span::SHIFTED) weights of the span's shift `sh`
    /// or [`FLAT_Q`] ones: the same bits, in a function of its own
    /// ([`nearest_span`]). (Affine spans go through
    /// [`TriangleSpans::run_nearest_affine`], a triangle's at once.)
    #[inline(always)]
    pub(crate) fn run_nearest<const WEIGHTS: u8>(self, c: &NearestConstants<'_>, sh: u32) -> u32 {
        let s = NearestSpan {
            c,
            sh,
            z: self.z,
            planes: self.planes,
        };
        nearest_span::<C, _, WEIGHTS>(self.color, self.depth, &s, Unlit)
    }
}

/// Where each of [`NearestConstants`]'s words sits in `k`: the fractions'
/// bases and differences, the steps of depth, `Q`, `B1` and `B2`, the
/// texture's width, height and texel count less one. `nearest_span` reads
/// them by index through one pointer on ARMv7-M (see there).
mod at {
    pub(super) const F0U: usize = 0;
    pub(super) const D1U: usize = 1;
    pub(super) const D2U: usize = 2;
    pub(super) const F0V: usize = 3;
    pub(super) const D1V: usize = 4;
    pub(super) const D2V: usize = 5;
    pub(super) const DZ: usize = 6;
    pub(super) const DQ: usize = 7;
    pub(super) const DB1: usize = 8;
    pub(super) const DB2: usize = 9;
    pub(super) const WIDTH: usize = 10;
    pub(super) const HEIGHT: usize = 11;
    pub(super) const LAST: usize = 12;
    /// The affine loop's steps of its sums, low word first (two words
    /// each), and where `MASKED_INDEX` the sums' shifts (`u`'s, `v`'s).
    pub(super) const GU: usize = 13;
    pub(super) const GV: usize = 15;
    #[cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]
    pub(super) const SHIFTS: usize = 17;
    /// The words: those after `LAST` only where `TRIANGLE_STEPS` (on
    /// ARMv7-M, six words more to clear and copy per triangle and tile
    /// cost the Cortex-M3's `fill-nearest-affine` 36.74 -> 36.81
    /// instructions a fragment).
    pub(super) const LEN: usize = if super::TRIANGLE_STEPS { 19 } else { LAST + 1 };
}

/// What [`nearest_span`] reads that is the same for all of a triangle's
/// spans in a tile: the texels, cut to the texel count; the fractions'
/// bases and differences (`f0u, d1u, d2u, f0v, d1v, d2v`), the steps of
/// depth, `Q`, `B1`, `B2`, the texture's width, height and texel count
/// less one (`Pow2Rgb565::fine_parts`).
pub(crate) struct NearestConstants<'a> {
    texels: &'a [u16],
    k: [u32; at::LEN],
}

/// What [`nearest_span`] reads: the triangle's constants, the span's
/// shift, depth and the planes at the first pixel.
struct NearestSpan<'a, 't> {
    c: &'a NearestConstants<'t>,
    sh: u32,
    z: u32,
    planes: [i32; 3],
}

/// The top `log2(m)` bits of `f`, for `m` a power of two below 2^32:
/// `f >> (32 - log2(m))` as the high word of a product (one `UMULL` on a
/// Cortex-M3), with no shift by a register to mask.
#[inline(always)]
fn top_bits(f: u32, m: u32) -> u32 {
    ((f as u64 * m as u64) >> 32) as u32
}

/// On ARMv6-M, the shifts of `fu` and `fv` and the row's bits for
/// [`texel_index`]: `WIDTH` and `HEIGHT` hold `Pow2Rgb565::fine_parts`'
/// shifts there, masked so that the shifts by them need no mask of their
/// own, and the row's bits come from `LAST`. Zeros elsewhere.
#[inline(always)]
fn narrow_shifts(k: &[u32; at::LEN]) -> (u32, u32, u32) {
    if NARROW_MULTIPLY {
        let (su, sv) = (k[at::WIDTH] & 31, k[at::HEIGHT] & 31);
        (su, sv, k[at::LAST] & !(u32::MAX >> su))
    } else {
        (0, 0, 0)
    }
}

/// `Pow2Rgb565::nearest_fine`'s index of the texel at fractions `fu`,
/// `fv` for a texture `w` by `h`: the row `y < h` (the top `log2(h)`
/// bits of `fv`) times the width, plus `x < w` (those of `fu`); one
/// multiply-add where the row had taken a mask and an `or`, without the
/// row mask's constant. Below the count already, so a mask by `LAST`
/// changes nothing. On ARMv6-M, whose 64-bit products (`top_bits`) are
/// library calls of about 40 instructions each, `nearest_fine`'s shifts
/// and mask instead (the same index; `shifts` from [`narrow_shifts`]).
#[inline(always)]
fn texel_index(w: u32, h: u32, fu: u32, fv: u32, shifts: (u32, u32, u32)) -> u32 {
    if NARROW_MULTIPLY {
        let (su, sv, row) = shifts;
        ((fv >> sv) & row) | (fu >> su)
    } else {
        top_bits(fv, h) * w + top_bits(fu, w)
    }
}

/// Whether [`nearest_span`]'s affine loop and [`quasi`]'s
/// `nearest_pixels` take the texel's index from 64-bit sums shifted by
/// the texture's sides (see there) rather than from the fractions by
/// [`texel_index`]: 64-bit hosts, where the index took two products, two
/// shifts and an addition (x86-64 `fill-nearest-affine` 34.63 -> 31.39
/// instructions a fragment, its loop 27 -> 23 a written pixel;
/// `fill-nearest-quasi16-facing` 46.49 -> 45.38). The affine loop's for
/// textures of at most [`MASKED_TEXELS`] texels; the others take the
/// general affine loop.
pub(crate) const MASKED_INDEX: bool = cfg!(target_pointer_width = "64");

/// Where [`MASKED_INDEX`], the texel's index from the sums `su` and `sv`
/// shifted right by `shift` (see there): the column's bits from `u`'s,
/// the others from `v`'s (cut to the row's by the mask by `LAST` that
/// the loops apply); `column` is the texture's width less one.
#[inline(always)]
fn masked_index(su: u64, sv: u64, shift: u32, column: u32) -> u32 {
    let v = (sv >> shift) as u32;
    v ^ (((su ^ sv) >> shift) as u32 & column)
}

/// Whether [`nearest_span`]'s affine loop takes the steps of its sums
/// from [`NearestConstants`], computed once per triangle and tile, rather
/// than at every span: per fragment, `fill-nearest-affine` x86-64 31.39
/// -> 30.67, Cortex-M4F 40.37 -> 39.12, ARMv6-M 68.74 -> 63.60; not on
/// ARMv7-M (the build script's `microraster_armv7m`), whose Cortex-M3
/// took 36.74 -> 37.10 (37.34 with the steps read before the loop).
const TRIANGLE_STEPS: bool = !cfg!(microraster_armv7m);

/// The shifts of the sums and fractions where [`MASKED_INDEX`]:
/// `log2(w)` for `u` and `log2(w h)` for `v`, of a texture `w` by `h`
/// (powers of two, `Pow2Rgb565::fine_parts`).
#[inline(always)]
fn index_shifts(w: u32, h: u32) -> (u32, u32) {
    let lw = w.trailing_zeros() & 31;
    (lw, (lw + h.trailing_zeros()) & 63)
}

/// The scale of [`nearest_span`]'s affine sums: `2^20` of `d1 b1 + d2
/// b2`, the fraction in the high word, or where [`MASKED_INDEX`] `2^0`
/// (the fraction in bits 12 to 43, see there).
const SUM_SCALE: u32 = if MASKED_INDEX { 0 } else { 20 };

/// `d1 b1 + d2 b2` of `d = (d1, d2)` and `b = (b1, b2)` (32x32 to 64-bit
/// products), times [`SUM_SCALE`], modulo 2^64: an affine loop's sum of a
/// texture coordinate at the planes' values `b`, or its step for the
/// planes' steps.
#[inline(always)]
fn affine_sum((d1, d2): (i32, i32), (b1, b2): (i32, i32)) -> u64 {
    scaled_sum::<SUM_SCALE>((d1, d2), (b1, b2), 0)
}

/// `2^S (d1 b1 + d2 b2) + 2^(S + 12) f0` modulo 2^64, of `d = (d1, d2)`,
/// the planes' values `b = (b1, b2)` (32x32 to 64-bit products) and a
/// texture coordinate's fraction to 32 bits `f0` at the first vertex:
/// the affine loops' sum of that coordinate ([`nearest_span`], the
/// bilinear loop), whose fraction is its high word for `S = 20`; with
/// the planes' steps and no `f0`, its step.
#[inline(always)]
pub(super) fn scaled_sum<const S: u32>((d1, d2): (i32, i32), (b1, b2): (i32, i32), f0: u32) -> u64 {
    (((mul_wide(d1, b1) + mul_wide(d2, b2)) as u64) << S).wrapping_add((f0 as u64) << (S + 12))
}

/// The most texels of a texture whose affine spans [`MASKED_INDEX`]
/// draws: 2^20, whose sums shifted by `log2(w h)` keep every bit the
/// index reads.
pub(crate) const MASKED_TEXELS: u32 = 1 << 20;

/// The loop of [`SpanInput::run_nearest`], out of line: inlined into the
/// tile's shading function beside its other loops, the planes were kept
/// in stack slots (a load and a store each per pixel) and the constants
/// reloaded with register moves between. Cortex-M3 per fragment
/// (`fill-nearest-exact`, `fill-nearest-affine`): 69.85, 49.79 inline;
/// 67.3, 52.9 out of line with the count in a register; 64.6, 49.1 with it
/// in memory; 62.6, 49.5 without the bounds check; 59.9, 47.1 with the
/// index by one multiply-add; 53.45, 45.14 -> 51.73, 42.91 with the
/// constants read in the loop on ARMv7-M (see there) rather than copied
/// to stack slots at every call. Also the loop of a span of
/// [`affine`]'s spans on 32-bit targets. The texel as `light` colours
/// it: as it is, or with [`AFFINE`] weights lit by `TexturedLit`'s
/// colour, stepped beside the texture coordinates
/// (`TriangleSpans::run_nearest_affine_lit`). With the colour from the
/// weights (six products a pixel, before the colour planes) the lit loop
/// had been slower than the general one (`fill-lit-exact` 112.2 ->
/// 116.3; again at `20d410c`, 111.33 -> 114.28); with the planes' three
/// additions, faster (Cortex-M3 `fill-lit-exact` 90.91 -> 85.86, x86-64
/// 79.79 -> 64.99 with red and green packed in one `u64`). The same loop
/// for bilinear sampling was slower too (162.1 -> 192.2).
#[inline(never)]
fn nearest_span<C: FromTexel, L: Light, const WEIGHTS: u8>(
    color: &mut [C],
    depth: &mut [u16],
    s: &NearestSpan,
    light: L,
) -> u32 {
    // The constants read where they are used, through a pointer that
    // `black_box` hides: the count of failed pixels is stored through
    // another such pointer, which might alias it, so the reads stay in
    // the loop (mostly in pairs, `LDRD`, or `LDM`) rather than being
    // hoisted, copied to stack slots at every call (about 30 instructions
    // a span on the Cortex-M3) and reloaded from there one by one. Only
    // for ARMv7-M (`thumbv7m`, the Cortex-M3: the build script's
    // `microraster_armv7m`), where it was measured faster: per fragment,
    // x86-64 `fill-nearest-exact` took 56.28 -> 59.91 with it, the
    // Cortex-M4F 53.32 -> 57.52 (affine 43.81 -> 44.01), ARMv6-M 172.43
    // -> 177.90 (affine 151.94 -> 157.43).
    let copied = s.c.k;
    let k = if cfg!(microraster_armv7m) {
        core::hint::black_box(&s.c.k)
    } else {
        &copied
    };
    let last = k[at::LAST];
    // The light's values in locals and its steps (`TexturedLit`'s
    // colour), the steps read as the constants are.
    let (mut light, light_steps) = light.start();
    let light_steps = if cfg!(microraster_armv7m) {
        core::hint::black_box(&light_steps)
    } else {
        &light_steps
    };
    let [mut q, mut b1, mut b2] = s.planes;
    let mut z = s.z;
    // At most 15 (`span_shift`): masked, the shifts by it need no mask.
    let sh = s.sh & 15;
    let r = if WEIGHTS == FLAT_Q {
        span_reciprocal(q, sh)
    } else {
        0
    };
    // The texels cut to the count, a power of two (`nearest_constants`
    // checked that the slice holds them), here rather than once per
    // triangle, so that the compiler knows the length: an index masked by
    // `m` then needs no bounds check, `at & m <= m < m + 1`.
    let m = last as usize;
    let Some(texels) = s.c.texels.get(..=m) else {
        return 0;
    };
    let shifts = narrow_shifts(k);
    let len = color.len() as u32;
    // Affine (on 32-bit targets: 64-bit hosts take `affine`'s loop): the
    // sums stepped as `affine::affine_spans` steps them (see there); the
    // steps from the constants (`nearest_constants`) where
    // `TRIANGLE_STEPS`, else made here.
    let sum = |d1: usize, d2: usize, b: (i32, i32)| affine_sum((k[d1] as i32, k[d2] as i32), b);
    let step = |k: &[u32; at::LEN], at: usize| (k[at + 1] as u64) << 32 | k[at] as u64;
    let (gu, gv) = if WEIGHTS == AFFINE && !TRIANGLE_STEPS {
        let g = (k[at::DB1] as i32, k[at::DB2] as i32);
        (sum(at::D1U, at::D2U, g), sum(at::D1V, at::D2V, g))
    } else {
        (0, 0)
    };
    let (mut su, mut sv) = if WEIGHTS == AFFINE {
        // `2^20 (d1 b1 + d2 b2)` modulo 2^64.
        let b = (b1, b2);
        (
            scaled_sum::<SUM_SCALE>((k[at::D1U] as i32, k[at::D2U] as i32), b, k[at::F0U]),
            scaled_sum::<SUM_SCALE>((k[at::D1V] as i32, k[at::D2V] as i32), b, k[at::F0V]),
        )
    } else {
        (0, 0)
    };
    // The pixels that fail, counted in memory: the common path holds no
    // count (a register fewer; it had been spilled around every pixel
    // written).
    let mut fails = [0u32];
    let fails = core::hint::black_box(&mut fails);
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if zz <= *d {
            let (fu, fv) = if WEIGHTS == AFFINE {
                ((su >> 32) as u32, (sv >> 32) as u32)
            } else {
                let (w1, w2) = if WEIGHTS == FLAT_Q {
                    flat_weights(b1, b2, sh, r)
                } else {
                    shifted_weights(q, b1, b2, sh)
                };
                let (w1, w2) = (w1 as u32, w2 as u32);
                (
                    k[at::F0U]
                        .wrapping_add(k[at::D1U].wrapping_mul(w1))
                        .wrapping_add(k[at::D2U].wrapping_mul(w2)),
                    k[at::F0V]
                        .wrapping_add(k[at::D1V].wrapping_mul(w1))
                        .wrapping_add(k[at::D2V].wrapping_mul(w2)),
                )
            };
            let at = texel_index(k[at::WIDTH], k[at::HEIGHT], fu, fv, shifts);
            *c = light.texel(texels[at as usize & m]);
            *d = zz;
        } else {
            fails[0] += 1;
        }
        if WEIGHTS == AFFINE {
            if TRIANGLE_STEPS {
                su = su.wrapping_add(step(k, at::GU));
                sv = sv.wrapping_add(step(k, at::GV));
            } else {
                su = su.wrapping_add(gu);
                sv = sv.wrapping_add(gv);
            }
        }
        z = z.wrapping_add(k[at::DZ]);
        if WEIGHTS != FLAT_Q {
            q = q.wrapping_add(k[at::DQ] as i32);
        }
        b1 = b1.wrapping_add(k[at::DB1] as i32);
        b2 = b2.wrapping_add(k[at::DB2] as i32);
        light.step(light_steps);
    }
    len - fails[0]
}
