//! The packed Gouraud span starts of 64-bit hosts ([`PACKED`]): a
//! triangle's red/green and depth/blue planes, one `u64` each, made once
//! a pair ([`TriangleSetup::packs`]) from the wrapped `i32` planes and the
//! set-up's exact `i64` coefficients ([`TriangleSetup::plane_exact`]),
//! evaluated at a span start ([`TriangleSetup::start_packed`]; clamped
//! for a triangle that is not interior,
//! [`TriangleSetup::start_packed_clamped`]) and stepped by two adds a
//! pixel. Every triangle but the wide ones takes them.

use super::plane::{Basis, Plane};
use super::setup::{Corners, TriangleSetup, C_HI, C_LO, SHIFTED_COLOR, Z_HI, Z_LO};
use crate::vertex::ScreenVertex;

/// Whether a Gouraud triangle's span starts (a triangle that is not
/// [`wide`](TriangleSetup::wide)) are evaluated packed, red/green and depth/blue in one `u64` each (64-bit hosts with
/// [`SHIFTED_COLOR`]), from planes packed once a pair
/// ([`TriangleSetup::packs`]), and its span loop steps them so.
pub(crate) const PACKED: bool = SHIFTED_COLOR && cfg!(target_pointer_width = "64");

impl TriangleSetup {
    /// [`TriangleSetup::plane`], with its `gx`, `gy` and `k` in `i64`
    /// (exact unless the gradients are beyond the limit, see
    /// [`TriangleSetup::exact`]).
    #[inline(always)]
    pub(super) fn plane_exact(
        f: &Basis,
        t: &Corners<'_>,
        a: usize,
        range: &mut u64,
    ) -> (Plane, [i64; 3]) {
        let (values, frac) = t.values(a);
        Self::plane_and_exact(f, values, frac, range)
    }

    /// The packed planes' `gx`, `gy` and `k` ([`PACKED`]): red/green and
    /// depth/blue, the first of each pair in the upper 32 bits as the span
    /// loop holds it (red shifted left by 8, depth by `16 - Z_FRAC`,
    /// wrapping: only its value modulo 2^32 matters there), the second
    /// from its exact `i64` coefficients, shifted left by 8.
    ///
    /// `u64` arithmetic is exact modulo 2^64, so the packed plane's value
    /// at pixel `(i, j)` is `(hi << 32) + lo` modulo 2^64, `hi` the upper
    /// lane's value (modulo 2^32) and `lo` the lower lane's exact value,
    /// the shifted channel. At a covered pixel of a triangle that is not
    /// wide that channel is within `12,287..=16,764,929` (see
    /// `start_shifted`), shifted within `3,145,472..=4,291,821,824`,
    /// inside `0..2^32`: no carry or borrow reaches the upper lane, which
    /// then holds exactly `hi` modulo 2^32, the lower lane exactly `lo`.
    /// An interior triangle's starts take no clamp, and the steps are the
    /// packed `gx`, so every covered pixel of its spans holds the plane's
    /// packed value; any other triangle that is not wide takes them
    /// clamped ([`TriangleSetup::start_packed_clamped`]).
    #[inline(always)]
    pub(super) fn packs(&self) -> [[u64; 3]; 2] {
        const _: () = assert!(((C_HI as i64 + 20_481) << 8) < 1 << 32 && C_LO >= 20_481);
        let hi = |v: i32| (v as u32 as u64) << 32;
        let lo = |v: i64| (v << 8) as u64;
        let [r, z] = [self.planes[1], self.planes[0]];
        let zs = 16 - super::Z_FRAC;
        let [eg, eb] = self.exact;
        [
            [
                hi(r.gx).wrapping_add(lo(eg[0])),
                hi(r.gy).wrapping_add(lo(eg[1])),
                hi(r.k).wrapping_add(lo(eg[2])),
            ],
            [
                hi(self.zstep).wrapping_add(lo(eb[0])),
                hi(z.gy.wrapping_shl(zs)).wrapping_add(lo(eb[1])),
                hi(z.k.wrapping_shl(zs)).wrapping_add(lo(eb[2])),
            ],
        ]
    }

    /// The packed planes' values at pixel `(i, j)` (see
    /// [`TriangleSetup::packs`]): red/green and depth/blue.
    #[inline(always)]
    pub(super) fn start_packed(&self, i: i32, j: i32) -> [u64; 2] {
        let at = |[gx, gy, k]: [u64; 3]| {
            k.wrapping_add(gy.wrapping_mul(j as i64 as u64))
                .wrapping_add(gx.wrapping_mul(i as i64 as u64))
        };
        [at(self.packed[0]), at(self.packed[1])]
    }

    /// [`TriangleSetup::start_packed`] of a triangle that is not
    /// [`interior`](TriangleSetup::interior) nor
    /// [`wide`](TriangleSetup::wide), clamped as [`TriangleSetup::start_shifted`] clamps: the same starts
    /// as there, packed.
    ///
    /// Each colour lane holds its channel shifted, exactly: the lower
    /// lanes do (see [`TriangleSetup::packs`]), and red's upper lane is
    /// the shifted channel modulo 2^32, which at a covered pixel lies
    /// within `3,145,472..=4,291,821,824`, inside `0..2^32`. So each lane
    /// is tested and clamped as a `u32`. Depth's lane, wrapping, cannot be
    /// tested so: where every vertex's depth is within `2..=65533` (the
    /// depth half of [`ScreenVertex::interior`]) no covered pixel's depth
    /// needs its clamp; any other triangle's depth is clamped from its
    /// plane, on the rare path. Stepped from the clamped starts, each
    /// channel stays within `0..256` units at every pixel of the span (the
    /// four-lane loop relies on it too), its shifted value within
    /// `0..2^32`: the lower lanes carry into the upper ones at no pixel.
    #[inline(always)]
    pub(super) fn start_packed_clamped(&self, t: &Corners<'_>, i: i32, j: i32) -> [u64; 2] {
        const LO: u32 = (C_LO as u32) << 8;
        const HI: u32 = (C_HI as u32) << 8;
        let [rg, zb] = self.start_packed(i, j);
        let inside = |c: u32| c.wrapping_sub(LO) <= HI - LO;
        let depth = |v: &ScreenVertex| (v.z() as u32).wrapping_sub(2) <= 65_531;
        let [u, v, w] = t.0;
        if inside((rg >> 32) as u32)
            & inside(rg as u32)
            & inside(zb as u32)
            & depth(u)
            & depth(v)
            & depth(w)
        {
            return [rg, zb];
        }
        crate::hint::cold();
        let clamp = |c: u64| (c as u32).clamp(LO, HI) as u64;
        let z = self.planes[0].at(i, j).clamp(Z_LO, Z_HI);
        let z = (z as u32) << (16 - super::Z_FRAC);
        [
            clamp(rg >> 32) << 32 | clamp(rg),
            (z as u64) << 32 | clamp(zb),
        ]
    }
}
