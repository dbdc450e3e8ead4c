//! The quasi-perspective nearest-texel loop of
//! [`Textured`](crate::shader::Textured) and
//! [`TexturedLit`](crate::shader::TexturedLit) on a repeated
//! power-of-two `Rgb565` texture: the general loop's exact samples at
//! screen-aligned columns and its segments between
//! ([`quasi_span`]), each segment's pixels stepping the texture
//! coordinates' fractions ([`nearest_pixels`]), lit by the interpolated
//! colour for `TexturedLit` ([`Lit`]).

use super::super::quasi::{quasi_span, segment_step, Segments};
use super::super::{depth16, signed_weights, PerspectiveSetup, SpanInput};
use super::light::{Light, Lit, SpanLight, Unlit};
use super::{
    at, index_shifts, masked_index, narrow_shifts, texel_index, NearestConstants, MASKED_INDEX,
};
use crate::texture::FromTexel;
use fixed::types::I16F16;

impl<C: FromTexel> SpanInput<'_, C, [I16F16; 2]> {
    /// The opaque quasi-perspective loop
    /// ([`run_quasi_opaque`](Self::run_quasi_opaque)) for
    /// [`Textured`](crate::shader::Textured) (`LIT` false) and
    /// [`TexturedLit`](crate::shader::TexturedLit) (`LIT`: the texel
    /// modulated by the interpolated colour) on a repeated power-of-two
    /// `Rgb565` texture, nearest (its constants `c`): the same bits, in a
    /// function of its own ([`nearest_quasi_span`]).
    #[inline(always)]
    pub(crate) fn run_nearest_quasi<const LIT: bool>(self, c: &NearestConstants<'_>) -> u32 {
        let s = QuasiSpan {
            c,
            setup: self.setup,
            seg: self.mode.segment() as i32,
            x0: self.x0,
            z: self.z,
            planes: self.planes,
        };
        nearest_quasi_span::<C, LIT>(self.color, self.depth, &s)
    }
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

/// The texture coordinates (raw 16.16) at the weights of the planes'
/// values `q`, `b1`, `b2` ([`signed_weights`]), as the general
/// quasi-perspective loop takes its samples (`values`' bits), through
/// [`PerspectiveSetup::values_fit`]: the triangle fits, and its `affine`
/// form is `values` itself where it takes no 32x32 products, for weights
/// of any sign (the sample one pixel past a span's end). With `LIT`, also
/// the colour there (8.16 a channel, as `values`), zeros without.
#[inline(always)]
fn quasi_sample<const LIT: bool>(
    p: &PerspectiveSetup<[I16F16; 2]>,
    (q, b1, b2): (i32, i32, i32),
) -> ([i32; 2], [i32; 3]) {
    let (var, col, _) = p.values_fit(signed_weights(q, b1, b2), LIT, true, false);
    (var.map(I16F16::to_bits), col)
}

/// The loop of [`SpanInput::run_nearest_quasi`], out of line as
/// [`nearest_span`](super::nearest_span) is: the quasi-perspective samples and segments of
/// [`SpanInput::run`] ([`quasi_span`]), with the texture coordinates
/// stepped as fractions to 32 bits (`fu = u << 16`: the general loop
/// steps `u` in wrapping `i32`, and the texel reads only its low 16 bits,
/// so `fu` stepped by `du << 16` holds them at every pixel) and the texel
/// read as `nearest_span` reads it; with `LIT`, the colour sampled and
/// stepped beside them, as the general loop steps it, modulating the
/// texel ([`LitSegments`]).
#[inline(never)]
fn nearest_quasi_span<C: FromTexel, const LIT: bool>(
    color: &mut [C],
    depth: &mut [u16],
    s: &QuasiSpan,
) -> u32 {
    let k = &s.c.k;
    let t = SegmentConstants {
        texels: s.c.texels,
        k,
        shifts: narrow_shifts(k),
    };
    let steps = [k[at::DQ] as i32, k[at::DB1] as i32, k[at::DB2] as i32];
    let (at, start) = ((s.seg, s.x0), (s.z, s.planes, steps));
    let setup = s.setup;
    if LIT {
        quasi_span(color, depth, &mut LitSegments { setup, t }, at, start)
    } else {
        quasi_span(color, depth, &mut NearestSegments { setup, t }, at, start)
    }
}

/// [`nearest_quasi_span`]'s segments: the texture coordinates at the
/// samples ([`quasi_sample`]), each segment's pixels in
/// [`nearest_pixels`].
struct NearestSegments<'a> {
    setup: &'a PerspectiveSetup<[I16F16; 2]>,
    t: SegmentConstants<'a>,
}

impl<C: FromTexel> Segments<C> for NearestSegments<'_> {
    type Values = [i32; 2];

    #[inline(always)]
    fn sample(&self, q: i32, b1: i32, b2: i32) -> [i32; 2] {
        quasi_sample::<false>(self.setup, (q, b1, b2)).0
    }

    #[inline(always)]
    fn steps(&self, from: &[i32; 2], to: &[i32; 2], r: i64) -> [i32; 2] {
        [
            segment_step(from[0], to[0], r),
            segment_step(from[1], to[1], r),
        ]
    }

    #[inline(always)]
    fn still(&self) -> [i32; 2] {
        [0; 2]
    }

    #[inline(always)]
    fn pixels(
        &mut self,
        color: &mut [C],
        depth: &mut [u16],
        z: u32,
        [u, v]: [i32; 2],
        [du, dv]: [i32; 2],
    ) -> (u32, u32) {
        let (f, df) = fractions([u, v], [du, dv]);
        nearest_pixels(color, depth, &self.t, z, f, df, Unlit)
    }
}

/// The fractions to 32 bits of texture coordinates `uv` (raw 16.16) and
/// of their steps `duv` (see [`nearest_quasi_span`]).
#[inline(always)]
fn fractions([u, v]: [i32; 2], [du, dv]: [i32; 2]) -> ([u32; 2], [u32; 2]) {
    (
        [(u as u32) << 16, (v as u32) << 16],
        [(du as u32) << 16, (dv as u32) << 16],
    )
}

/// [`NearestSegments`] for `TexturedLit`: the colour beside the texture
/// coordinates, each segment's pixels in [`nearest_pixels`] with [`Lit`].
struct LitSegments<'a> {
    setup: &'a PerspectiveSetup<[I16F16; 2]>,
    t: SegmentConstants<'a>,
}

impl<C: FromTexel> Segments<C> for LitSegments<'_> {
    type Values = ([i32; 2], [i32; 3]);

    #[inline(always)]
    fn sample(&self, q: i32, b1: i32, b2: i32) -> Self::Values {
        quasi_sample::<true>(self.setup, (q, b1, b2))
    }

    #[inline(always)]
    fn steps(&self, (uv, c): &Self::Values, (nuv, nc): &Self::Values, r: i64) -> Self::Values {
        (
            [0, 1].map(|i| segment_step(uv[i], nuv[i], r)),
            [0, 1, 2].map(|ch| segment_step(c[ch], nc[ch], r)),
        )
    }

    #[inline(always)]
    fn still(&self) -> Self::Values {
        ([0; 2], [0; 3])
    }

    #[inline(always)]
    fn pixels(
        &mut self,
        color: &mut [C],
        depth: &mut [u16],
        z: u32,
        (uv, col): Self::Values,
        (duv, dc): Self::Values,
    ) -> (u32, u32) {
        let (f, df) = fractions(uv, duv);
        nearest_pixels(color, depth, &self.t, z, f, df, Lit::<true>::new(col, dc))
    }
}

/// What [`nearest_pixels`] reads: the texels, the triangle's constants,
/// [`narrow_shifts`].
struct SegmentConstants<'a> {
    texels: &'a [u16],
    k: &'a [u32; at::LEN],
    shifts: (u32, u32, u32),
}

/// The pixels of one segment of [`nearest_quasi_span`]: depth `z` and the
/// fractions `f` at the first, stepped by `k[DZ]` and `df`, the texel as
/// `light` gives it; returns the pixels that fail and the depth after the
/// last. Out of line: inlined, the segments' values took the registers,
/// and the loop reloaded the texels', the tile's and the constants'
/// addresses from the stack at every pixel.
#[inline(never)]
fn nearest_pixels<C: FromTexel, L: Light>(
    color: &mut [C],
    depth: &mut [u16],
    t: &SegmentConstants,
    mut z: u32,
    f: [u32; 2],
    df: [u32; 2],
    light: L,
) -> (u32, u32) {
    // The constants in locals: read through `t`, they were read again at
    // every pixel (the stores might have changed them, for all the
    // compiler knows). On ARMv7-M and ARMv7E-M (the build script's
    // `microraster_armv7m`, `microraster_armv7em`) those the loop steps
    // by (the light's too) and the texture's sides are read in the loop,
    // through a pointer hidden by `black_box`, and the pixels that fail
    // counted in memory through another, as in `nearest_span`: in
    // registers, the loop spilled four of them, and LLVM unrolled it by
    // four, spilling more. The Cortex-M4F's per fragment:
    // `fill-nearest-quasi16-facing` 51.95 -> 45.77,
    // `fill-lit-quasi16-facing` 105.24 -> 102.68; ARMv6-M's took 100.04
    // -> 101.41 and 198.45 -> 205.89 with it.
    let (m, shifts) = (t.k[at::LAST] as usize, t.shifts);
    // The texels cut to the count here, where the loop is, so that the
    // masked index needs no bounds check (as in `nearest_span`); never
    // short (`nearest_constants` checked), and then nothing is written.
    let Some(texels) = t.texels.get(..=m) else {
        return (color.len() as u32, z);
    };
    let (mut light, light_steps) = light.start();
    let consts = (
        [t.k[at::DZ], df[0], df[1], t.k[at::WIDTH], t.k[at::HEIGHT]],
        light_steps,
    );
    let (k, steps) = if cfg!(microraster_armv7m) || cfg!(microraster_armv7em) {
        core::hint::black_box(&consts)
    } else {
        &consts
    };
    let [mut fu, mut fv] = f;
    // Where `MASKED_INDEX`, the fractions and their steps in 64 bits,
    // shifted up by `log2(w)` (`u`) and `log2(w h)` (`v`, at most 30):
    // the high word of `u`'s then holds the column in its low `log2(w)`
    // bits, that of `v`'s the row times `w` in its bits from `log2(w)` to
    // `log2(w h)` (the wrapping additions keep the bits below as the
    // 32-bit ones do), and the index is a few shifts and masks, without
    // `texel_index`'s products.
    let (mut su, mut sv, dsu, dsv, column) = if MASKED_INDEX {
        let (lw, lv) = index_shifts(k[3], k[4]);
        (
            (fu as u64) << lw,
            (fv as u64) << lv,
            (k[1] as u64) << lw,
            (k[2] as u64) << lv,
            k[3].wrapping_sub(1),
        )
    } else {
        (0, 0, 0, 0, 0)
    };
    let mut fails = [0u32];
    let fails = if cfg!(microraster_armv7m) || cfg!(microraster_armv7em) {
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
            let i = if MASKED_INDEX {
                masked_index(su, sv, 32, column)
            } else {
                texel_index(k[3], k[4], fu, fv, shifts)
            };
            *c = light.texel(texels[i as usize & m]);
            *d = zz;
        } else {
            fails[0] += 1;
        }
        z = z.wrapping_add(k[0]);
        if MASKED_INDEX {
            su = su.wrapping_add(dsu);
            sv = sv.wrapping_add(dsv);
        } else {
            fu = fu.wrapping_add(k[1]);
            fv = fv.wrapping_add(k[2]);
        }
        light.step(steps);
    }
    (fails[0], z)
}
