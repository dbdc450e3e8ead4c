//! The attribute set-up of a small triangle on a 32-bit core: edge
//! vectors below 2^10 sub-pixels (64 pixels), twice the area below 2^21,
//! so the gradients come from long divisions in 32-bit steps (one
//! instruction each on a Cortex-M3/M4) and, where every value fits, the
//! whole set-up runs in `i32` ([`TriangleSetup::small`]). The planes are
//! exactly those of the general set-up ([`TriangleSetup::with_basis`]),
//! which the tests check on random triangles.

#[cfg(doc)]
use super::setup::Basis;
use super::setup::{Corners, Plane, TriangleSetup};
use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use core::num::NonZeroU32;

/// On 32-bit targets, the attribute set-up of a small triangle (edge
/// vectors from vertex 0 below this, in sub-pixels: 64 pixels) divides in
/// 32-bit operations ([`Small::div_round`]) instead of through the 64-bit
/// reciprocal of its area; 64-bit targets keep their division instruction.
/// The gradients are the same.
pub(super) const SMALL_EDGE: i64 = 1 << 10;
/// Whether the target sets small triangles up in 32-bit divisions.
pub(super) const SMALL_SETUP: bool = cfg!(not(target_pointer_width = "64"));

/// What the `i32` set-up of a [`Small`] triangle shares
/// ([`TriangleSetup::small`]): [`Basis`]'s edge vectors `x1, y1, x2, y2`
/// and offsets `ox, oy`, in `i32`, and the divisor.
struct SmallBasis {
    e: [i32; 4],
    o: [i32; 2],
    small: Small,
}

/// The divisor of a small triangle's gradients: twice its absolute area,
/// below `2 * SMALL_EDGE^2 = 2^21`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Small {
    pub(super) area: NonZeroU32,
    pub(super) half: u32,
}

impl Small {
    /// `n 2^shift / area` rounded to nearest, ties away from zero, for
    /// `|n| < 2^31` and `area < 2^21`: [`Basis::div_round`]'s quotient, by
    /// long division in 32-bit steps of at most 10 bits. With
    /// `|n| = q area + r`, `|n| 2^10 = (q 2^10 + d) area + r'` for
    /// `d = floor(r 2^10 / area)`, and so on down the shift; every partial
    /// dividend is below `area 2^10 + half < 2^32`. Three divisions for
    /// the shifts of depth and colour (18 and 20), each one instruction on
    /// a Cortex-M3/M4.
    #[inline(always)]
    pub(super) fn div_round(&self, n: i32, shift: u32) -> i64 {
        let d = self.area;
        let a = n.unsigned_abs();
        let mut q = (a / d) as u64;
        let mut r = a % d;
        let mut left = shift;
        while left > 10 {
            let part = r << 10;
            q = (q << 10) | (part / d) as u64;
            r = part % d;
            left -= 10;
        }
        let q = ((q << left) + (((r << left) + self.half) / d) as u64) as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    }
}

impl Small {
    /// [`Small::div_round`] in `u32` arithmetic, for `|n| < 2^22` and
    /// `10 <= shift < 30`: the same digits, exact while `|n| / area <
    /// 2^(30 - shift)` (the quotient is then below 2^30); `fits` is
    /// cleared otherwise, and the result is then meaningless. The first
    /// two digits come from one division, `|n| 2^10 / area`, which
    /// `|n| < 2^22` keeps in `u32`. On a Cortex-M3 this spares
    /// `div_round`'s 64-bit shifts, additions and negation and one of its
    /// three divisions.
    #[inline(always)]
    pub(super) fn div_round32(&self, n: i32, shift: u32, fits: &mut bool) -> i32 {
        let d = self.area;
        // Below 2^32 for |n| < 2^22 (beyond, `fits` is cleared by the
        // caller and the bits lost do not matter).
        let m = n.unsigned_abs() << 10;
        let (mut q, mut r, mut left) = (m / d, m % d, shift - 10);
        // The first digit alone is q >> 10.
        *fits &= q < 1 << (40 - shift);
        while left > 10 {
            let part = r << 10;
            q = (q << 10) | (part / d);
            r = part % d;
            left -= 10;
        }
        let q = (q << left).wrapping_add(((r << left) + self.half) / d) as i32;
        if n < 0 {
            q.wrapping_neg()
        } else {
            q
        }
    }
}

impl Small {
    /// `n / area` rounded to nearest, ties away from zero (as
    /// [`Basis::div_round`]), for `|n| < 2^43` and `area < 2^21`: the
    /// perspective planes' numerators, whose values reach 2^28. Long
    /// division in 32-bit steps of 11 bits (every partial dividend is
    /// below `area 2^11 < 2^32`): four divisions, each one instruction on a
    /// Cortex-M3/M4, where a 64-bit division is a library call.
    #[inline(always)]
    pub(super) fn div_round_wide(&self, n: i64) -> i64 {
        let d = self.area;
        // Below 2^43 + 2^20 < 2^44: four chunks of 11 bits.
        let a = n.unsigned_abs() + self.half as u64;
        let top = (a >> 33) as u32;
        let mut q = (top / d) as u64;
        let mut r = top % d;
        for shift in [22, 11, 0] {
            let part = (r << 11) | ((a >> shift) as u32 & 0x7FF);
            q = (q << 11) | (part / d) as u64;
            r = part % d;
        }
        let q = q as i64;
        if n < 0 {
            -q
        } else {
            q
        }
    }
}

impl TriangleSetup {
    /// The set-up of a [`Small`] triangle `v` (on 32-bit targets) all in
    /// `i32` arithmetic, when every gradient is below 2^30 in magnitude
    /// and depth's numerators below 2^22 ([`Small::div_round32`]): the
    /// planes [`TriangleSetup::with_basis`]
    /// gives on [`Basis::new`], without building the basis's 64-bit
    /// values or its 64-bit quotients, constants and range test; `None`
    /// for any other triangle.
    #[inline(always)]
    pub(super) fn small(v: &[SubPoint; 3], t: &Corners<'_>, gouraud: bool) -> Option<Self> {
        // Within the guard band the edge vectors fit i32.
        let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
        let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
        let e = SMALL_EDGE as i32;
        if !(x1.abs() < e && y1.abs() < e && x2.abs() < e && y2.abs() < e) {
            return None;
        }
        // Below 2^21 (`Basis`'s twice the signed area).
        let area2 = x1 * y2 - x2 * y1;
        let area = NonZeroU32::new(area2.unsigned_abs())?;
        // As in `Basis`: the edge vectors negated for a positive divisor.
        let n = |c: i32| if area2 < 0 { -c } else { c };
        let f = &SmallBasis {
            e: [n(x1), n(y1), n(x2), n(y2)],
            o: [HALF_PIXEL - v[0].x, HALF_PIXEL - v[0].y],
            small: Small {
                area,
                half: area.get() / 2,
            },
        };
        let mut fits = true;
        let z = Self::plane_small(f, t, 0, &mut fits);
        let planes = if gouraud {
            [
                z,
                Self::plane_small(f, t, 1, &mut fits),
                Self::plane_small(f, t, 2, &mut fits),
                Self::plane_small(f, t, 3, &mut fits),
            ]
        } else {
            [z, Plane::default(), Plane::default(), Plane::default()]
        };
        // Gradients below 2^30 are far inside the clamp: never wide.
        fits.then_some(Self::finish(planes, false))
    }

    /// [`TriangleSetup::plane`] of a [`Small`] triangle in `i32`: its
    /// values' differences are below 2^16 and its edge vectors below
    /// 2^10, so the numerators are below 2^27 (as in
    /// [`Basis::gradients`]); with gradients below 2^30 and the offsets of
    /// the first pixel centre below 2^19 + 8, the constant's products
    /// need no wrapping (`i32` by `i32`), and its wrapped `i32` is
    /// `constant_wrapping`'s.
    #[inline(always)]
    fn plane_small(f: &SmallBasis, t: &Corners<'_>, a: usize, fits: &mut bool) -> Plane {
        let (values, frac) = t.values(a);
        // Depths and colour channels: 16 and 8 bits.
        let v = [values[0] as i32, values[1] as i32, values[2] as i32];
        let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
        let [x1, y1, x2, y2] = f.e;
        let shift = frac + SUBPIXEL_BITS;
        let (n1, n2) = (d1 * y2 - d2 * y1, d2 * x1 - d1 * x2);
        // Numerators below 2^22 are divided in two steps rather than
        // three: a colour channel's always (its differences are below
        // 2^8: numerators below 2^19), depth's when they are (below 2^27
        // in general; a larger one sends the triangle to the general
        // set-up).
        if a == 0 {
            *fits &= (n1.unsigned_abs() | n2.unsigned_abs()) < 1 << 22;
        }
        let gx = f.small.div_round32(n1, shift, fits);
        let gy = f.small.div_round32(n2, shift, fits);
        let base = (v[0] << frac) + (1 << (frac - 1));
        let t = gx as i64 * f.o[0] as i64 + gy as i64 * f.o[1] as i64;
        Plane {
            gx,
            gy,
            k: base.wrapping_add((t >> SUBPIXEL_BITS) as i32),
        }
    }
}
