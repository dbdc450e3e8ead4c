//! The per-vertex transform's matrix: 16.16 fixed point, applied with
//! exact 64-bit sums (or, where a bound allows, without their checks, or
//! in 32-bit products), so that no core does floating point per vertex.

use super::mul_wide;

/// A 4x4 matrix in 16.16 fixed point (raw `I16F16` bits), column-major.
///
/// Produced by [`Mat4::to_fixed`](super::Mat4::to_fixed); applied per vertex with `i64`
/// accumulation, so a core without an FPU does no soft-float per vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FixedMat4 {
    /// Columns of raw 16.16 values; `m[c][r]`.
    pub m: [[i32; 4]; 4],
}

impl FixedMat4 {
    /// Transforms the point `(p, 1)` (raw 16.16 components) to homogeneous
    /// coordinates, each the exact `i64` sum of products rounded once to
    /// 16.16. Returns `None` if a result leaves the `I16F16` range.
    #[inline]
    pub fn transform_point(&self, p: [i32; 3]) -> Option<[i32; 4]> {
        let mut out = [0i32; 4];
        for (r, o) in out.iter_mut().enumerate() {
            *o = self.row_checked(r, p)?;
        }
        Some(out)
    }

    /// Row `r` (`0..4`) of [`transform_point`](Self::transform_point).
    /// Out of line on 32-bit cores: the vertex stage takes it only for a
    /// draw whose matrix is not [`bounded`](Self::bounded) for its mesh,
    /// and its four rows inlined took the Cortex-M3's firmware about 400
    /// bytes.
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    fn row_checked(&self, r: usize, p: [i32; 3]) -> Option<i32> {
        let m = &self.m;
        let r = r & 3;
        // Each product is below 2^62 in magnitude, but three of them
        // can leave i64 (all elements and coordinates near +-32768),
        // which panicked in debug builds and wrapped to a wrong vertex
        // in release. A partial sum that overflows is more than 2^61
        // away from zero whatever the remaining terms (each below 2^62,
        // the translation below 2^47), far outside 16.16: `None`.
        let acc = mul_wide(m[0][r], p[0])
            .checked_add(mul_wide(m[1][r], p[1]))?
            .checked_add(mul_wide(m[2][r], p[2]))?
            .checked_add((m[3][r] as i64) << 16)?;
        i32::try_from(acc.checked_add(1 << 15)? >> 16).ok()
    }

    /// Whether [`transform_point_bounded`](Self::transform_point_bounded)
    /// is exact for every point whose coordinates are at most `extent` in
    /// magnitude: when every row's sum of products, its translation and the
    /// rounding stay below 2^47, no partial sum can leave `i64` and the
    /// rounded result always fits `i32`, so neither needs checking.
    pub fn bounded(&self, extent: u32) -> bool {
        (0..4).all(|r| {
            let sum: u64 = (0..3)
                .map(|c| self.m[c][r].unsigned_abs() as u64 * extent as u64)
                .sum::<u64>()
                + ((self.m[3][r].unsigned_abs() as u64) << 16)
                + (1 << 15);
            sum < 1 << 47
        })
    }

    /// Whether a row's products in 32 bits (`transform_point_narrow`,
    /// and the split rows of ARMv6-M's vertex loop) are
    /// exact for every point whose coordinates are at most `extent` in
    /// magnitude, for a matrix also [`bounded`](Self::bounded) for it: the
    /// elements that multiply coordinates at most `2^16` (1.0: those of a
    /// normalized matrix) and `extent` at most `2^21`.
    pub(crate) fn narrow(&self, extent: u32) -> bool {
        extent <= 1 << 21
            && self.m[..3]
                .iter()
                .flatten()
                .all(|v| v.unsigned_abs() <= 1 << 16)
    }

    /// [`transform_point_bounded`](Self::transform_point_bounded) in 32-bit
    /// products, for a matrix [`narrow`](Self::narrow) and bounded for the
    /// point's extent: on ARMv6-M each 64-bit product is four 16-bit ones
    /// and their carries, here each is two `MULS`.
    ///
    /// With `p[i] = a[i] 2^8 + b[i]` (`0 <= b[i] < 2^8`, so `|a[i]| <=
    /// 2^13`), a row's `Σ m[i] p[i] = 2^8 A + B` for `A = Σ m[i] a[i]` and
    /// `B = Σ m[i] b[i]`, below `3 2^29` and `3 2^24` in magnitude: both
    /// exact in `i32`. Then `floor((Σ m[i] p[i] + 2^15) / 2^16) = floor((A +
    /// floor((B + 2^15) / 2^8)) / 2^8)`, the sum below `2^31` in magnitude,
    /// and the translation (a multiple of `2^16` in the bounded transform's
    /// sum) is added after the shift; the result is the bounded one's,
    /// which fits `i32`.
    /// Only the tests call it: the reference that the vertex loop's split
    /// rows (`NarrowRows` in `vertex::lit_work`) are checked against.
    #[cfg(test)]
    pub(crate) fn transform_point_narrow(&self, p: [i32; 3]) -> [i32; 4] {
        let m = &self.m;
        let a = p.map(|v| v >> 8);
        let b = p.map(|v| v & 0xff);
        let mut out = [0i32; 4];
        for (r, o) in out.iter_mut().enumerate() {
            let hi = m[0][r] * a[0] + m[1][r] * a[1] + m[2][r] * a[2];
            let lo = m[0][r] * b[0] + m[1][r] * b[1] + m[2][r] * b[2];
            *o = m[3][r].wrapping_add((hi + ((lo + (1 << 15)) >> 8)) >> 8);
        }
        out
    }

    /// The `w` row of [`transform_point_bounded`](Self::transform_point_bounded),
    /// in wrapping arithmetic: equal to `transform_point`'s `w` whenever
    /// that succeeded.
    #[inline(always)]
    pub fn transform_w_unchecked(&self, p: [i32; 3]) -> i32 {
        let m = &self.m;
        let acc = mul_wide(m[0][3], p[0])
            .wrapping_add(mul_wide(m[1][3], p[1]))
            .wrapping_add(mul_wide(m[2][3], p[2]))
            .wrapping_add((m[3][3] as i64) << 16);
        (acc.wrapping_add(1 << 15) >> 16) as i32
    }

    /// [`transform_point`](Self::transform_point) without its overflow
    /// checks, for a matrix that is [`bounded`](Self::bounded) for the
    /// point's extent; then it gives the same result (the sums are exact,
    /// the result in range).
    #[inline(always)]
    pub fn transform_point_bounded(&self, p: [i32; 3]) -> [i32; 4] {
        let mut out = [0i32; 4];
        for (r, o) in out.iter_mut().enumerate() {
            *o = self.bounded_row(r, p) as i32;
        }
        out
    }

    /// Row `r` of [`transform_point_bounded`](Self::transform_point_bounded)
    /// before its narrowing to `i32`. Within the bound nothing wraps;
    /// wrapping arithmetic only spares the checks. The translation and
    /// the rounding first: one constant per row (kept out of the vertex
    /// loop) that the products accumulate onto (`smlal` on ARMv7-M),
    /// rather than a 64-bit add of each after the products.
    #[inline(always)]
    fn bounded_row(&self, r: usize, p: [i32; 3]) -> i64 {
        let m = &self.m;
        let acc = ((m[3][r] as i64) << 16 | 1 << 15)
            .wrapping_add(mul_wide(m[0][r], p[0]))
            .wrapping_add(mul_wide(m[1][r], p[1]))
            .wrapping_add(mul_wide(m[2][r], p[2]));
        acc >> 16
    }

    /// [`transform_point_bounded`](Self::transform_point_bounded) as
    /// 64-bit words (each within `i32`, for a matrix bounded for the
    /// point): x86-64's vertex loop adds `w` to them in 64 bits, where
    /// from 32-bit results it sign-extended each again (four `MOVSXD` a
    /// vertex).
    #[inline(always)]
    pub(crate) fn transform_point_bounded_wide(&self, p: [i32; 3]) -> [i64; 4] {
        let mut out = [0i64; 4];
        for (r, o) in out.iter_mut().enumerate() {
            *o = self.bounded_row(r, p);
            debug_assert!(i32::try_from(*o).is_ok(), "bounded transform beyond i32");
        }
        out
    }
}
