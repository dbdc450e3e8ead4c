//! The packed Gouraud span starts of 64-bit hosts ([`PACKED`]): an
//! interior triangle's red/green and depth/blue planes, one `u64` each,
//! made once a pair ([`TriangleSetup::packs`]) from the wrapped `i32`
//! planes and the set-up's exact `i64` coefficients
//! ([`TriangleSetup::plane_exact`]), evaluated at a span start
//! ([`TriangleSetup::start_packed`]) and stepped by two adds a pixel.

use super::plane::{Basis, Plane};
use super::setup::{Corners, TriangleSetup, C_HI, C_LO, SHIFTED_COLOR};

/// Whether an interior triangle's Gouraud span starts are evaluated
/// packed, red/green and depth/blue in one `u64` each (64-bit hosts with
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
    /// The packed starts are taken only for interior triangles (never
    /// wide), whose starts take no clamp; the steps are the packed `gx`,
    /// so every covered pixel of a span holds the plane's packed value.
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
}
