//! The nearest-texel span loops of [`Textured`](crate::shader::Textured)
//! on a repeated power-of-two `Rgb565` texture: their per-triangle
//! constants ([`TriangleSpans::nearest_constants`]) and the loops
//! themselves, out of line: [`nearest_span`], with affine, shifted or
//! constant-`Q` weights, and [`nearest_quasi_span`], quasi-perspective
//! (the same bits as the general loop's).

use super::barycentric::{flat_weights, shifted_weights, span_reciprocal};
use super::lerp::NARROW_MULTIPLY;
use super::quasi::{segment_length, segment_step, RECIPROCAL};
use super::span::{AFFINE, FLAT_Q};
use super::{depth16, signed_weights, PerspectiveSetup, SpanInput, Z_FRAC};
use crate::shader::TriangleSpans;
use crate::texture::FromTexel;
use fixed::types::I16F16;

impl<C> TriangleSpans<'_, C, [I16F16; 2]> {
    /// What [`SpanInput::run_nearest`] reads that is the same for every
    /// span of the triangle in the tile, for a repeated power-of-two
    /// `Rgb565` texture (`texels` and `parts`, the width, height and texel
    /// count less one, from `Pow2Rgb565::fine_parts`; on ARMv6-M the
    /// shifts of `fu` and `fv` in place of the width and height): gathered once per
    /// triangle and tile rather than copied into each span's record (about
    /// 30 instructions a span on the Cortex-M3). `None` if the texels are
    /// short of the count (never, by `Texture::new`).
    #[inline(always)]
    pub(crate) fn nearest_constants<'t>(
        &self,
        texels: &'t [u16],
        parts: [u32; 3],
    ) -> Option<NearestConstants<'t>> {
        let p = self.setup;
        let [f0u, f0v] = p.fine0;
        let [[d1u, d1v], [d2u, d2v]] = p.dvar;
        let [pq, p1, p2] = &p.planes;
        // The texels hold the count (`Pow2Rgb565::fine_parts`; never short,
        // by `Texture::new`).
        let texels = texels.get(..=parts[2] as usize)?;
        let mut k = [0; at::LAST + 1];
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
        Some(NearestConstants { texels, k })
    }
}

impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// [`run_opaque`](Self::run_opaque) for
    /// [`Textured`](crate::shader::Textured) on a repeated power-of-two
    /// `Rgb565` texture, nearest (its constants `c`, from
    /// [`TriangleSpans::nearest_constants`]), with [`AFFINE`] weights (`sh`
    /// unused) or [`SHIFTED`](super::span::SHIFTED) ones with the span's shift `sh`: the same
    /// bits, in a function of its own ([`nearest_span`]).
    #[inline(always)]
    pub(crate) fn run_nearest<const WEIGHTS: u8>(self, c: &NearestConstants<'_>, sh: u32) -> u32 {
        let s = NearestSpan {
            c,
            sh,
            z: self.z,
            planes: self.planes,
        };
        nearest_span::<C, WEIGHTS>(self.color, self.depth, &s)
    }

    /// The opaque quasi-perspective loop
    /// ([`run_quasi_opaque`](Self::run_quasi_opaque)) for
    /// [`Textured`](crate::shader::Textured) on a repeated power-of-two
    /// `Rgb565` texture, nearest (its constants `c`): the same bits, in a
    /// function of its own ([`nearest_quasi_span`]).
    #[inline(always)]
    pub(crate) fn run_nearest_quasi(self, c: &NearestConstants<'_>) -> u32 {
        let s = QuasiSpan {
            c,
            setup: self.setup,
            seg: self.mode.segment() as i32,
            x0: self.x0,
            z: self.z,
            planes: self.planes,
        };
        nearest_quasi_span::<C>(self.color, self.depth, &s)
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
}

/// What [`nearest_span`] reads that is the same for all of a triangle's
/// spans in a tile: the texels, cut to the texel count; the fractions'
/// bases and differences (`f0u, d1u, d2u, f0v, d1v, d2v`), the steps of
/// depth, `Q`, `B1`, `B2`, the texture's width, height and texel count
/// less one (`Pow2Rgb565::fine_parts`).
pub(crate) struct NearestConstants<'a> {
    texels: &'a [u16],
    k: [u32; at::LAST + 1],
}

/// What [`nearest_span`] reads: the triangle's constants, the span's
/// shift, depth and the planes at the first pixel.
struct NearestSpan<'a, 't> {
    c: &'a NearestConstants<'t>,
    sh: u32,
    z: u32,
    planes: [i32; 3],
}

/// What [`nearest_quasi_span`] reads: the triangle's constants and
/// set-up, the segment length, the span's first column, depth and the
/// planes at its first pixel.
struct QuasiSpan<'a, 't> {
    c: &'a NearestConstants<'t>,
    setup: &'a PerspectiveSetup<[I16F16; 2]>,
    seg: i32,
    x0: i32,
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
fn narrow_shifts(k: &[u32; at::LAST + 1]) -> (u32, u32, u32) {
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

/// The loop of [`SpanInput::run_nearest`], out of line: inlined into the
/// tile's shading function beside its other loops, the planes were kept
/// in stack slots (a load and a store each per pixel) and the constants
/// reloaded with register moves between. Cortex-M3 per fragment
/// (`fill-nearest-exact`, `fill-nearest-affine`): 69.85, 49.79 inline;
/// 67.3, 52.9 out of line with the count in a register; 64.6, 49.1 with it
/// in memory; 62.6, 49.5 without the bounds check; 59.9, 47.1 with the
/// index by one multiply-add; 53.45, 45.14 -> 51.73, 42.91 with the
/// constants read in the loop on ARMv7-M (see there) rather than copied
/// to stack slots at every call. The same loop for `TexturedLit` (its colour
/// beside the texel) was slower (`fill-lit-exact` 112.2 -> 116.3; again
/// at `20d410c`, 111.33 -> 114.28, and 117.93 with its constants read in
/// the loop: its two tables' addresses are rebuilt at every pixel), and
/// one for bilinear sampling too (162.1 -> 192.2).
#[inline(never)]
fn nearest_span<C: FromTexel, const WEIGHTS: u8>(
    color: &mut [C],
    depth: &mut [u16],
    s: &NearestSpan,
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
    // The pixels that fail, counted in memory: the common path holds no
    // count (a register fewer; it had been spilled around every pixel
    // written).
    let mut fails = [0u32];
    let fails = core::hint::black_box(&mut fails);
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if zz <= *d {
            let (w1, w2) = if WEIGHTS == AFFINE {
                (b1 >> 12, b2 >> 12)
            } else if WEIGHTS == FLAT_Q {
                flat_weights(b1, b2, sh, r)
            } else {
                shifted_weights(q, b1, b2, sh)
            };
            let (w1, w2) = (w1 as u32, w2 as u32);
            let fu = k[at::F0U]
                .wrapping_add(k[at::D1U].wrapping_mul(w1))
                .wrapping_add(k[at::D2U].wrapping_mul(w2));
            let fv = k[at::F0V]
                .wrapping_add(k[at::D1V].wrapping_mul(w1))
                .wrapping_add(k[at::D2V].wrapping_mul(w2));
            let at = texel_index(k[at::WIDTH], k[at::HEIGHT], fu, fv, shifts);
            *c = C::from_rgb565(texels[at as usize & m]);
            *d = zz;
        } else {
            fails[0] += 1;
        }
        z = z.wrapping_add(k[at::DZ]);
        if WEIGHTS != FLAT_Q {
            q = q.wrapping_add(k[at::DQ] as i32);
        }
        b1 = b1.wrapping_add(k[at::DB1] as i32);
        b2 = b2.wrapping_add(k[at::DB2] as i32);
    }
    len - fails[0]
}

/// The texture coordinates (raw 16.16) at the weights of the planes'
/// values `q`, `b1`, `b2` ([`signed_weights`]), as the general
/// quasi-perspective loop takes its samples (`values`' bits), through
/// [`PerspectiveSetup::values_fit`]: the triangle fits, and its `affine`
/// form is `values` itself where it takes no 32x32 products, for weights
/// of any sign (the sample one pixel past a span's end).
#[inline(always)]
fn quasi_sample(p: &PerspectiveSetup<[I16F16; 2]>, q: i32, b1: i32, b2: i32) -> [i32; 2] {
    let (var, _, _) = p.values_fit(signed_weights(q, b1, b2), false, true, false);
    var.map(I16F16::to_bits)
}

/// The loop of [`SpanInput::run_nearest_quasi`], out of line as
/// [`nearest_span`] is: the quasi-perspective samples and segments of
/// [`SpanInput::run`], with the texture coordinates stepped as fractions
/// to 32 bits (`fu = u << 16`: the general loop steps `u` in wrapping
/// `i32`, and the texel reads only its low 16 bits, so `fu` stepped by
/// `du << 16` holds them at every pixel) and the texel read as
/// `nearest_span` reads it.
#[inline(never)]
fn nearest_quasi_span<C: FromTexel>(color: &mut [C], depth: &mut [u16], s: &QuasiSpan) -> u32 {
    let k = &s.c.k;
    let p = s.setup;
    let (seg, x0) = (s.seg, s.x0);
    let t = SegmentConstants {
        texels: s.c.texels,
        k,
        shifts: narrow_shifts(k),
    };
    let [mut q, mut b1, mut b2] = s.planes;
    let [gq, g1, g2] = [k[at::DQ] as i32, k[at::DB1] as i32, k[at::DB2] as i32];
    let mut z = s.z;
    let len = color.len() as i32;
    let mut fails = 0;
    let [mut u, mut v] = quasi_sample(p, q, b1, b2);
    let mut pos = 0;
    while pos < len {
        let l = segment_length(seg, x0 + pos, len - pos);
        let (mut du, mut dv) = (0, 0);
        let [mut nu, mut nv] = [u, v];
        if l > 0 {
            [nu, nv] = quasi_sample(
                p,
                q.wrapping_add(gq.wrapping_mul(l)),
                b1.wrapping_add(g1.wrapping_mul(l)),
                b2.wrapping_add(g2.wrapping_mul(l)),
            );
            let r = RECIPROCAL[l as usize];
            (du, dv) = (segment_step(u, nu, r), segment_step(v, nv, r));
        }
        let stop = if l == 0 { pos + 1 } else { pos + l };
        let (a, b) = (pos as usize, stop as usize);
        let steps = [(du as u32) << 16, (dv as u32) << 16];
        if let (Some(cs), Some(ds)) = (color.get_mut(a..b), depth.get_mut(a..b)) {
            let f = [(u as u32) << 16, (v as u32) << 16];
            let (failed, zn) = nearest_pixels(cs, ds, &t, z, f, steps);
            fails += failed;
            z = zn;
        }
        let li = stop - pos;
        q = q.wrapping_add(gq.wrapping_mul(li));
        b1 = b1.wrapping_add(g1.wrapping_mul(li));
        b2 = b2.wrapping_add(g2.wrapping_mul(li));
        [u, v] = [nu, nv];
        pos = stop;
    }
    len as u32 - fails
}

/// What [`nearest_pixels`] reads: the texels, the triangle's constants,
/// [`narrow_shifts`].
struct SegmentConstants<'a> {
    texels: &'a [u16],
    k: &'a [u32; at::LAST + 1],
    shifts: (u32, u32, u32),
}

/// The pixels of one segment of [`nearest_quasi_span`]: depth `z` and the
/// fractions `f` at the first, stepped by `k[DZ]` and `df`; returns the
/// pixels that fail and the depth after the last. Out of line: inlined,
/// the segments' values took the registers, and the loop reloaded the
/// texels', the tile's and the constants' addresses from the stack at
/// every pixel.
#[inline(never)]
fn nearest_pixels<C: FromTexel>(
    color: &mut [C],
    depth: &mut [u16],
    t: &SegmentConstants,
    mut z: u32,
    f: [u32; 2],
    df: [u32; 2],
) -> (u32, u32) {
    // The constants in locals: read through `t`, they were read again at
    // every pixel (the stores might have changed them, for all the
    // compiler knows). On ARMv7-M those the loop steps by and the
    // texture's sides are read in the loop, through a pointer hidden by
    // `black_box`, and the pixels that fail counted in memory through
    // another, as in `nearest_span`: in registers, the loop spilled four
    // of them, and LLVM unrolled it by four, spilling more.
    let (m, shifts) = (t.k[at::LAST] as usize, t.shifts);
    // The texels cut to the count here, where the loop is, so that the
    // masked index needs no bounds check (as in `nearest_span`); never
    // short (`nearest_constants` checked), and then nothing is written.
    let Some(texels) = t.texels.get(..=m) else {
        return (color.len() as u32, z);
    };
    let consts = [t.k[at::DZ], df[0], df[1], t.k[at::WIDTH], t.k[at::HEIGHT]];
    let k = if cfg!(microraster_armv7m) {
        core::hint::black_box(&consts)
    } else {
        &consts
    };
    let [mut fu, mut fv] = f;
    let mut fails = [0u32];
    let fails = if cfg!(microraster_armv7m) {
        core::hint::black_box(&mut fails)
    } else {
        &mut fails
    };
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        // A compiler barrier (no instruction): LLVM does not unroll a loop
        // that holds one.
        core::hint::black_box(());
        let zz = depth16(z);
        if zz <= *d {
            let i = texel_index(k[3], k[4], fu, fv, shifts);
            *c = C::from_rgb565(texels[i as usize & m]);
            *d = zz;
        } else {
            fails[0] += 1;
        }
        z = z.wrapping_add(k[0]);
        fu = fu.wrapping_add(k[1]);
        fv = fv.wrapping_add(k[2]);
    }
    (fails[0], z)
}
