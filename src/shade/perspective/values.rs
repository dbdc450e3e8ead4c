//! A triangle's varyings and colour at a pixel: from its perspective
//! weights (exact and quasi-perspective samples: [`values`](PerspectiveSetup::values),
//! its 32-bit forms [`values_weighted`](PerspectiveSetup::values_weighted)
//! and [`values_fit`](PerspectiveSetup::values_fit)) or, in affine mode,
//! from the planes themselves
//! ([`values_affine`](PerspectiveSetup::values_affine)).

use super::lerp::{fine_fit, lerp32, lerp_fit, FIT_PRODUCTS, NARROW_MULTIPLY};
use super::PerspectiveSetup;
#[allow(unused_imports)] // the rustdoc links
use super::{weights, Interpolated, Perspective};
use crate::math::mul_wide;
use crate::shader::Varyings;
use fixed::types::I16F16;

/// Whether the opaque affine loop steps each varying's sum
/// ([`PerspectiveSetup::affine_sums`]) rather than taking its products at
/// every pixel: on ARMv6-M, whose 64-bit products are library calls
/// (about 40 instructions each, four a pixel for two varyings where the
/// triangle's differences are not all 32-bit, two 16-bit splits each
/// where they are); and on a host built with `MICRORASTER_LOOPS32=1`
/// (`build.rs`), so that CI's span-shader tests run it.
pub(crate) const STEP_AFFINE: bool = cfg!(any(microraster_narrow_multiply, microraster_loops32));

/// The most varyings whose sums the opaque affine loop steps (see
/// [`STEP_AFFINE`]); a shader with more takes the products.
pub(crate) const STEPPED: usize = 4;

impl<V: Varyings> PerspectiveSetup<V> {
    /// [`values`](Self::values) for weights from [`weights`] (in
    /// `0..=2^16`). Where the core has a 32x32 to 64-bit multiply that is
    /// `values` itself; on ARMv6-M (no such instruction: every `i64`
    /// product is a library call) the same bits in 32-bit arithmetic
    /// ([`lerp32`]).
    #[inline(always)]
    pub(crate) fn values_weighted(&self, w: (i32, i32), interpolate_color: bool) -> (V, [i32; 3]) {
        if !NARROW_MULTIPLY {
            return self.values(w, interpolate_color);
        }
        // `values`' loop written again: shared through one inlined function
        // taking the lerp, it changed the code of `shade_custom` (x86-64, M4F).
        let mut out = V::zeroed();
        let [a0, a1, a2] = self.vertex_values();
        for (k, o) in out.as_mut_slice().iter_mut().enumerate() {
            *o = I16F16::from_bits(lerp32(a0[k].to_bits(), a1[k].to_bits(), a2[k].to_bits(), w));
        }
        (out, self.color_at(w, interpolate_color))
    }

    /// [`values`](Self::values) (`affine`) or
    /// [`values_weighted`](Self::values_weighted) for a triangle that
    /// [`fits`](Self::fits): the same bits from the differences of
    /// `dvar`, each an `i32`, so that each product is one 32x32 to 64-bit
    /// multiply (`SMULL`, `SMLAL` on a Cortex-M3) rather than a 64x32 one
    /// (two or three instructions, and twice the values to load). Only
    /// where [`FIT_PRODUCTS`]; elsewhere as before.
    ///
    /// Also each varying's fraction to 32 bits
    /// (see [`Interpolated`]'s `fine`): the low word of the same sum with
    /// `a0` scaled in, `T = a0 · 2^16 + 2^15 + d1 b1 + d2 b2`, whose bits
    /// 16 to 31 are the value's (`floor(T / 2^16)`) low 16 bits. The low
    /// word of a product depends only on the low words of its factors, so
    /// wrapping 32-bit products (two `MLA`s) give it exactly. A shader that
    /// needs only the fraction (a repeated power-of-two texture) leaves the
    /// value unused, and the compiler drops its 64-bit sums
    /// (`fill-nearest-exact` per fragment 83.9 to 72.9 on the Cortex-M3,
    /// 72.9 to 65.0 on x86-64; `demo-textured-lit` -3.3 % on ARMv6-M, whose
    /// `lerp32` goes unused too).
    #[inline(always)]
    pub(crate) fn values_fit(
        &self,
        (b1, b2): (i32, i32),
        interpolate_color: bool,
        affine: bool,
        convex: bool,
    ) -> (V, [i32; 3], Option<V>) {
        let [a0, d1, d2] = [
            self.var[0].as_slice(),
            self.dvar[0].as_slice(),
            self.dvar[1].as_slice(),
        ];
        let (out, color) = if FIT_PRODUCTS {
            debug_assert!(self.fits());
            let mut out = V::zeroed();
            for (k, o) in out.as_mut_slice().iter_mut().enumerate() {
                let (d1, d2) = (d1[k].to_bits(), d2[k].to_bits());
                *o = I16F16::from_bits(lerp_fit(a0[k].to_bits(), d1, d2, (b1, b2)));
            }
            (out, self.color_at((b1, b2), interpolate_color))
        } else if affine {
            self.values((b1, b2), interpolate_color)
        } else {
            self.values_weighted((b1, b2), interpolate_color)
        };
        // The colour's `color_at` above goes unused there, and is dropped.
        #[cfg(target_pointer_width = "64")]
        let color = if convex && interpolate_color {
            self.color_convex((b1, b2))
        } else {
            color
        };
        #[cfg(not(target_pointer_width = "64"))]
        let _ = convex;
        (out, color, Some(Self::fine(self, (b1, b2))))
    }

    /// Each varying's fraction to 32 bits at weights `(b1, b2)` (see
    /// [`values_fit`](Self::values_fit)).
    #[inline(always)]
    fn fine(&self, (b1, b2): (i32, i32)) -> V {
        let [d1, d2, f0] = [
            self.dvar[0].as_slice(),
            self.dvar[1].as_slice(),
            self.fine0.as_slice(),
        ];
        let mut fine = V::zeroed();
        for (k, f) in fine.as_mut_slice().iter_mut().enumerate() {
            let (d1, d2) = (d1[k].to_bits(), d2[k].to_bits());
            *f = I16F16::from_bits(fine_fit(f0[k].to_bits(), d1, d2, (b1, b2)));
        }
        fine
    }

    /// [`color_at`](Self::color_at) for weights that sum to at most one
    /// (`span_shift_convex`), on a 64-bit host: red and green from one
    /// 64-bit multiply-add pair on `color_rg`. Each channel's value is then
    /// in `0..2^24`, so the packed sum, exact modulo 2^64 whatever the
    /// lanes' signs on the way, holds red in its bits 40 to 63 and green
    /// in bits 8 to 31 (a shader without varyings) or 0 to 23, with no
    /// borrow between them: two products and two sums a pixel fewer.
    /// Without varyings (`Gouraud`), blue, from `color_b`, sits in bits 8
    /// to 31 of a wrapping `u32` sum, exact modulo 2^32 likewise, and each
    /// channel's byte is the top of a word (`rg >> 56`, `rg as u32 >> 24`,
    /// `b >> 24`), taken with no mask: x86-64 `fill-gouraud-exact` 50.88
    /// -> 49.88 instructions a fragment with red's, -> 47.86 with all
    /// three.
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub(super) fn color_convex(&self, (b1, b2): (i32, i32)) -> [i32; 3] {
        let [base, d1, d2] = self.color_rg;
        let rg = base
            .wrapping_add(d1.wrapping_mul(b1 as u64))
            .wrapping_add(d2.wrapping_mul(b2 as u64));
        if V::LEN > 0 {
            let [b0, e1, e2] = &self.color;
            return [
                (rg >> 40) as i32,
                rg as u32 as i32,
                b0[2] + e1[2] * b1 + e2[2] * b2,
            ];
        }
        let [b0, e1, e2] = self.color_b;
        let b = b0
            .wrapping_add(e1.wrapping_mul(b1 as u32))
            .wrapping_add(e2.wrapping_mul(b2 as u32));
        [(rg >> 40) as i32, (rg as u32 >> 8) as i32, (b >> 8) as i32]
    }

    /// The varyings, the colour (8.16 a channel, at the weights `B >> 12`,
    /// as [`values`](Self::values) takes it: where the triangle has no
    /// colour planes, see [`ColourPlanes`](crate::shade::ColourPlanes))
    /// and each varying's fraction to 32 bits in [`Perspective::Affine`],
    /// where the planes' values
    /// `B1`, `B2` are the weights themselves in units of 2^-28: each
    /// varying is `a0 + floor((d1 B1 + d2 B2 + 2^27) / 2^28)`, the sum
    /// rounded once ([`affine_sum`](Self::affine_sum)), so that it is
    /// exactly affine along a span and a loop may step it (a weight
    /// truncated to 16 bits before the sum had cost up to about 30 units
    /// of 2^-16 against the exact value). Its fraction is the low word of
    /// `floor(T / 2^12)` of the same sum with `a0` scaled in, `T = a0 ·
    /// 2^28 + 2^27 + d1 B1 + d2 B2`: `fine0 + floor((d1 B1 + d2 B2) /
    /// 2^12)`, whose bits 16 to 31 are the value's low 16 bits. With
    /// `FIT`, for a triangle that [`fits`](Self::fits), from the
    /// differences of `dvar` (32x32 to 64-bit products).
    #[inline(always)]
    pub(crate) fn values_affine<const FIT: bool>(
        &self,
        b: (i32, i32),
        interpolate_color: bool,
    ) -> (V, [i32; 3], V) {
        self.values_of_sums(|k| self.affine_sum::<FIT>(k, b), b, interpolate_color)
    }

    /// [`values_affine`](Self::values_affine) from each varying's sum
    /// `sum(k)`, the colour from the planes' values `(b1, b2)`.
    #[inline(always)]
    fn values_of_sums(
        &self,
        sum: impl Fn(usize) -> i64,
        (b1, b2): (i32, i32),
        interpolate_color: bool,
    ) -> (V, [i32; 3], V) {
        let mut out = V::zeroed();
        let mut fine = V::zeroed();
        let (a0, f0) = (self.var[0].as_slice(), self.fine0.as_slice());
        for (k, (o, f)) in out
            .as_mut_slice()
            .iter_mut()
            .zip(fine.as_mut_slice())
            .enumerate()
        {
            let s = sum(k);
            *o = I16F16::from_bits(a0[k].to_bits().wrapping_add(((s + (1 << 27)) >> 28) as i32));
            *f = I16F16::from_bits(f0[k].to_bits().wrapping_add((s >> 12) as i32));
        }
        (
            out,
            self.color_at((b1 >> 12, b2 >> 12), interpolate_color),
            fine,
        )
    }

    /// Each varying's affine sum `d1 B1 + d2 B2` at the planes' values
    /// `(b1, b2)` (as [`affine_sum`](Self::affine_sum) from the vertex
    /// values) and its change for a step `(g1, g2)` of the planes, modulo
    /// 2^64: along a span the planes change by their steps exactly, so the
    /// sum at each pixel is the first plus as many changes, exactly where
    /// it fits `i64` (every covered pixel, see `affine_sum`). For the
    /// first [`STEPPED`] varyings (zeros beyond), once a span; the loop
    /// then takes [`values_stepped`](Self::values_stepped) and adds the
    /// changes. (Only where [`STEP_AFFINE`], whose targets take the sums
    /// from the vertex values, not `dvar`: no `FIT_PRODUCTS` there.)
    #[inline(always)]
    pub(crate) fn affine_sums(
        &self,
        (b1, b2): (i32, i32),
        (g1, g2): (i32, i32),
    ) -> ([i64; STEPPED], [i64; STEPPED]) {
        let (mut sums, mut steps) = ([0; STEPPED], [0; STEPPED]);
        let [a0, a1, a2] = self.vertex_values();
        for k in 0..V::LEN.min(STEPPED) {
            // The differences in `i64` (exact); the sum's products exact
            // (`affine_sum`), the change's wrapping: a step's change may
            // not fit, the sums it reaches do.
            let base = a0[k].to_bits() as i64;
            let (d1, d2) = (a1[k].to_bits() as i64 - base, a2[k].to_bits() as i64 - base);
            sums[k] = d1 * b1 as i64 + d2 * b2 as i64;
            steps[k] = d1
                .wrapping_mul(g1 as i64)
                .wrapping_add(d2.wrapping_mul(g2 as i64));
        }
        (sums, steps)
    }

    /// [`values_affine`](Self::values_affine) from each varying's sum
    /// `sums` (from [`affine_sums`](Self::affine_sums), stepped), the
    /// colour from the planes' values `(b1, b2)`.
    #[inline(always)]
    pub(crate) fn values_stepped(
        &self,
        sums: &[i64; STEPPED],
        b: (i32, i32),
        interpolate_color: bool,
    ) -> (V, [i32; 3], V) {
        // Only `V::LEN <= STEPPED` comes here (`run_opaque`).
        self.values_of_sums(|k| sums.get(k).copied().unwrap_or(0), b, interpolate_color)
    }

    /// `d1 B1 + d2 B2` for varying `k` ([`values_affine`](Self::values_affine)),
    /// exact: `|d| < 2^32` and, at a covered pixel of a span, `|B| < 2^30`
    /// (a span start is clamped to ±2^29, and along a span of two pixels
    /// or more the plane changes by at most about 2^28, the most a weight
    /// changes between two covered pixels), so each product is below 2^62
    /// and the sum below 2^63. With `FIT` (where [`FIT_PRODUCTS`]), from
    /// `dvar` (each an `i32`, [`fits`](Self::fits)): one 32x32 to 64-bit
    /// product each ([`mul_wide`]); else from the vertex values in `i64`.
    #[inline(always)]
    fn affine_sum<const FIT: bool>(&self, k: usize, (b1, b2): (i32, i32)) -> i64 {
        if FIT {
            debug_assert!(self.fits);
            let (d1, d2) = (self.dvar[0].as_slice(), self.dvar[1].as_slice());
            return mul_wide(d1[k].to_bits(), b1) + mul_wide(d2[k].to_bits(), b2);
        }
        let [a0, a1, a2] = [
            self.var[0].as_slice()[k].to_bits() as i64,
            self.var[1].as_slice()[k].to_bits() as i64,
            self.var[2].as_slice()[k].to_bits() as i64,
        ];
        let (d1, d2) = (a1 - a0, a2 - a0);
        d1 * b1 as i64 + d2 * b2 as i64
    }

    /// The vertices' varyings.
    #[inline(always)]
    fn vertex_values(&self) -> [&[I16F16]; 3] {
        [
            self.var[0].as_slice(),
            self.var[1].as_slice(),
            self.var[2].as_slice(),
        ]
    }

    /// The varyings and colour (8.16 per channel) at weights `(b1, b2)`.
    #[inline(always)]
    pub(crate) fn values(&self, (b1, b2): (i32, i32), interpolate_color: bool) -> (V, [i32; 3]) {
        let mut out = V::zeroed();
        let [a0, a1, a2] = self.vertex_values();
        for (k, o) in out.as_mut_slice().iter_mut().enumerate() {
            let base = a0[k].to_bits() as i64;
            let d1 = a1[k].to_bits() as i64 - base;
            let d2 = a2[k].to_bits() as i64 - base;
            // |d| < 2^32, |b| < 2^20 (affine weights of a span start
            // clamped to ±2^29, shifted by 12): the sum stays below 2^53. A value
            // outside 16.16 (weights a hair beyond the triangle) wraps,
            // never panics.
            let v = base + ((d1 * b1 as i64 + d2 * b2 as i64 + (1 << 15)) >> 16);
            *o = I16F16::from_bits(v as i32);
        }
        (out, self.color_at((b1, b2), interpolate_color))
    }

    /// The colour (8.16 per channel, rounding bias included) at weights
    /// `(b1, b2)`, or zeros without `interpolate_color`.
    #[inline(always)]
    fn color_at(&self, (b1, b2): (i32, i32), interpolate_color: bool) -> [i32; 3] {
        let mut c = [0i32; 3];
        if interpolate_color {
            let [base, d1, d2] = &self.color;
            for (k, o) in c.iter_mut().enumerate() {
                // |d| <= 255, |b| < 2^20: below 2^29.
                *o = base[k] + d1[k] * b1 + d2[k] * b2;
            }
        }
        c
    }
}
