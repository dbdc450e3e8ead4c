//! The Gouraud and flat set-up of 64-bit hosts: each gradient one
//! unsigned division of an offset numerator ([`TriangleSetup::offset`]),
//! for the triangles it can take; the others take the general set-up
//! (`setup.rs`).

use super::plane::Plane;
use super::setup::{Corners, TriangleSetup};
use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};

impl TriangleSetup {
    /// On 64-bit hosts, the planes of [`TriangleSetup::with_basis`] with
    /// each gradient one unsigned division of an offset numerator, no sign
    /// test and no fix-up of the quotient; `None` for the triangles it
    /// does not take (about one in a thousand: very large ones, those
    /// whose twice-area is a multiple of 2^19, and slivers), which the
    /// general set-up takes.
    ///
    /// With the edge vectors negated for a positive divisor `d` (twice the
    /// absolute area, as [`Basis`](super::plane::Basis)) and `n` a gradient's numerator shifted
    /// (`|n| < 2^58`: edge vectors below 2^23, differences below 2^16,
    /// shifts up to 20), the gradient is `q = floor((n + half) / d)` when
    /// no tie arises, which it never does where `d` is not a multiple of
    /// 2^19: a tie `2 n = (2 m + 1) d` needs `d` to have as many factors of
    /// two as `2 n`, at least 19 (`n` is a multiple of 2^18). For every
    /// other `n` the floor is the rounded quotient with either tie rule,
    /// so `Basis::div_round`'s ties away from zero make no difference.
    ///
    /// The floor is taken as `q' = floor((n + half + 2^36 d) / d) = q +
    /// 2^36`, an unsigned division of a non-negative dividend whenever
    /// `q >= -2^36`. For `d < 2^26` the dividend stays below `2^58 + 2^62
    /// + 2^25 < 2^64`; where `n + half + 2^36 d` is negative its wrapped
    /// value is at least `2^64 - 2^58` and `q'` at least 2^37. So every
    /// `q'` below 2^37 is `q + 2^36` with `|q| <= 2^36`, far inside the
    /// gradient limit (not wide), and one test of all eight quotients or-ed
    /// sends the rest to the general set-up. The offset changes no bit
    /// that the planes keep: it is a multiple of 2^32 (the `i32`
    /// gradients), and `2^36 (ox + oy)`, which it adds to the constant's
    /// products, a multiple of 2^36 (bits 4 to 35 of their sum are the
    /// constant's `i32`).
    #[inline(always)]
    pub(in crate::shade) fn offset(
        v: &[SubPoint; 3],
        t: &Corners<'_>,
        gouraud: bool,
    ) -> Option<Self> {
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        let area2 = x1 * y2 - x2 * y1;
        let d = area2.unsigned_abs();
        // Also rejects a zero area (never set up).
        if (d >> 26 != 0) | (d & ((1 << 19) - 1) == 0) {
            return None;
        }
        // Negated on the sign's own path (the optimiser branches on the
        // sign for the divisor anyway), where the products by the sign
        // `±1` took four multiplies on the common one: x86-64 `demo`
        // 2,870,002 -> 2,855,742 instructions, `rock` 2,380,899 ->
        // 2,370,417, `tri4` -52 K, `tri100` -22 K.
        let e = if area2 < 0 {
            [-x1, -y1, -x2, -y2]
        } else {
            [x1, y1, x2, y2]
        };
        let f = Offset {
            e,
            o: [
                HALF_PIXEL as i64 - v[0].x as i64,
                HALF_PIXEL as i64 - v[0].y as i64,
            ],
            div: crate::math::Divisor::new(core::num::NonZeroU64::new(d)?),
            c: ((d << OFFSET_BITS) + d / 2) as i64,
        };
        let mut range = 0u64;
        let z = f.plane(t, 0, &mut range).0;
        let mut exact = [[0i64; 3]; 2];
        let planes = if gouraud {
            let r = f.plane(t, 1, &mut range).0;
            let (g, eg) = f.plane(t, 2, &mut range);
            let (b, eb) = f.plane(t, 3, &mut range);
            exact = [eg, eb];
            [z, r, g, b]
        } else {
            [z, Plane::default(), Plane::default(), Plane::default()]
        };
        if range >> (OFFSET_BITS + 1) != 0 {
            return None;
        }
        let mut s = Self::finish(planes, false);
        s.exact = exact;
        Some(s)
    }
}

/// The offset of [`TriangleSetup::offset`]'s quotients: `2^36`.
const OFFSET_BITS: u32 = 36;

/// What the planes of [`TriangleSetup::offset`] share: the edge vectors
/// from vertex 0 negated for a positive divisor, the first pixel centre's
/// offset from vertex 0, the divisor and the numerators' offset `2^36 d +
/// half`.
struct Offset {
    e: [i64; 4],
    o: [i64; 2],
    div: crate::math::Divisor,
    c: i64,
}

impl Offset {
    /// The plane of attribute `a` (see [`Corners::values`]), its offset
    /// quotients or-ed into `range`.
    #[inline(always)]
    ///
    /// Also the plane's `gx`, `gy` and `k` in `i64`, exact where the
    /// quotients are below 2^37 (the set-up's condition): the offset
    /// `2^36` taken off each gradient, and `2^32 (ox + oy)` off the
    /// constant (the offset's `2^36 (ox + oy)` in the products, a multiple
    /// of 16, passes through the shift as that).
    fn plane(&self, t: &Corners<'_>, a: usize, range: &mut u64) -> (Plane, [i64; 3]) {
        let (values, frac) = t.values(a);
        let (d1, d2) = (values[1] - values[0], values[2] - values[0]);
        let [x1, y1, x2, y2] = self.e;
        let shift = frac + SUBPIXEL_BITS;
        let gx = self
            .div
            .div((((d1 * y2 - d2 * y1) << shift) + self.c) as u64);
        let gy = self
            .div
            .div((((d2 * x1 - d1 * x2) << shift) + self.c) as u64);
        *range |= gx | gy;
        let term = (gx as i64)
            .wrapping_mul(self.o[0])
            .wrapping_add((gy as i64).wrapping_mul(self.o[1]));
        let base = (values[0] << frac) + (1i64 << (frac - 1));
        // An empty `black_box` (inline assembly of no instruction) after
        // each plane: the optimiser then finishes a plane before it starts
        // the next, where it had made all eight numerators before the
        // first division and spilled them (x86-64 `demo` 3,483,659 ->
        // 3,450,391 instructions, `rock` 2,892,528 -> 2,866,412).
        core::hint::black_box(());
        let k = base.wrapping_add(term >> SUBPIXEL_BITS);
        (
            Plane {
                gx: gx as i32,
                gy: gy as i32,
                k: k as i32,
            },
            [
                (gx as i64).wrapping_sub(1 << OFFSET_BITS),
                (gy as i64).wrapping_sub(1 << OFFSET_BITS),
                k.wrapping_sub((self.o[0] + self.o[1]) << 32),
            ],
        )
    }
}
