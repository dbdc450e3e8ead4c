//! Homogeneous clipping (Sutherland & Hodgman, *Reentrant Polygon
//! Clipping*, CACM 1974).
//!
//! A triangle that crosses the near or far plane, comes too close to `w = 0`,
//! or reaches beyond the guard band is clipped in clip space, before the
//! perspective divide, against only the planes its vertices' outcodes name.
//! Each plane keeps the polygon's inside vertices unchanged and inserts the
//! intersection where an edge crosses it. Clipping a triangle against up to
//! seven planes gives at most ten vertices, so the polygon lives in a
//! fixed-capacity `heapless::Vec`.
//!
//! The intersection of an edge is always computed from its inside end
//! towards its outside end, with exact `i128` products and one rounding, so
//! two triangles sharing an edge produce the very same new vertex and stay
//! watertight after clipping.

use crate::vertex::{ClipVertex, BARY_ONE, GUARD_K, OUT_FAR, OUT_GUARD, OUT_NEAR, OUT_W, W_MIN};

/// Capacity of a clipped polygon. A convex triangle clipped by seven planes
/// has at most ten vertices; the margin absorbs a vertex that fixed-point
/// round-off could add on a nearly degenerate polygon.
pub const MAX_CLIPPED_VERTICES: usize = 16;

/// A convex polygon in clip space.
pub type Polygon = heapless::Vec<ClipVertex, MAX_CLIPPED_VERTICES>;

#[derive(Clone, Copy)]
enum Plane {
    Near,
    Far,
    WMin,
    Left,
    Right,
    Bottom,
    Top,
}

impl Plane {
    /// Signed distance; the inside is `>= 0`.
    #[inline]
    fn distance(self, p: &[i32; 4]) -> i64 {
        let (x, y, z, w) = (p[0] as i64, p[1] as i64, p[2] as i64, p[3] as i64);
        match self {
            Plane::Near => z + w,
            Plane::Far => w - z,
            Plane::WMin => w - W_MIN,
            Plane::Left => GUARD_K * w + x,
            Plane::Right => GUARD_K * w - x,
            Plane::Bottom => GUARD_K * w + y,
            Plane::Top => GUARD_K * w - y,
        }
    }
}

/// The point where the edge from `inside` (distance `d_in >= 0`) to
/// `outside` (distance `d_out < 0`) meets the plane.
fn intersect(inside: &ClipVertex, d_in: i64, outside: &ClipVertex, d_out: i64) -> ClipVertex {
    let den = d_in - d_out;
    let mut v = ClipVertex::default();
    for k in 0..4 {
        v.pos[k] = lerp(inside.pos[k], outside.pos[k], d_in, den);
    }
    for k in 0..3 {
        v.color[k] = lerp(inside.color[k], outside.color[k], d_in, den);
    }
    for k in 0..2 {
        v.bary[k] = lerp(inside.bary[k], outside.bary[k], d_in, den);
    }
    v
}

/// `a + (b - a) d_in / den`, rounded to nearest (halves away from `a`),
/// for `0 <= d_in <= den`, `den > 0`. Out of line: clipping is rare, so one
/// copy serves all nine values.
///
/// The quotient `q = floor((|b - a| d_in + floor(den / 2)) / den)` is at
/// most `|b - a| < 2^32`, but its numerator needs up to 95 bits. No `i128`
/// division (a large library routine on a 32-bit core, 1.3 KB of a
/// firmware's flash): a `den` below 2^32 keeps the numerator below 2^64,
/// one `u64` division; a larger one is shifted to its top 32 bits, whose
/// `u64` quotient is at most 2 too large (the divisor then has its top bit
/// set), and the remainder in `i128` takes the excess back.
#[inline(never)]
fn lerp(a: i32, b: i32, d_in: i64, den: i64) -> i32 {
    let span = b as i64 - a as i64;
    let (m, d, big_d) = (span.unsigned_abs(), d_in.max(0) as u64, den.max(1) as u64);
    // m < 2^32 and d <= den < 2^63: below 2^95.
    let num = m as u128 * d as u128 + (big_d / 2) as u128;
    let q = if big_d >> 32 == 0 {
        // d <= den < 2^32: num < 2^64.
        num as u64 / big_d
    } else {
        let sh = 32 - big_d.leading_zeros();
        // num < 2^32 den, so num >> sh < 2^64 and the estimate is at
        // least the quotient; den_top >= 2^31 bounds its excess by 2.
        let den_top = big_d >> sh;
        let mut q = (num >> sh) as u64 / den_top;
        let mut r = num as i128 - q as i128 * big_d as i128;
        while r < 0 && q > 0 {
            q -= 1;
            r += big_d as i128;
        }
        q
    };
    let q = q as i64;
    (a as i64 + if span < 0 { -q } else { q }) as i32
}

fn clip_against(input: &Polygon, plane: Plane, out: &mut Polygon) {
    out.clear();
    let n = input.len();
    for i in 0..n {
        let cur = &input[i];
        let next = &input[(i + 1) % n];
        let dc = plane.distance(&cur.pos);
        let dn = plane.distance(&next.pos);
        if dc >= 0 {
            // Capacity: each plane adds at most one vertex to a convex
            // polygon; MAX_CLIPPED_VERTICES has room for every plane.
            let _ = out.push(*cur);
            if dn < 0 {
                let _ = out.push(intersect(cur, dc, next, dn));
            }
        } else if dn >= 0 {
            let _ = out.push(intersect(next, dn, cur, dc));
        }
    }
}

/// Clips triangle `tri` against the planes selected by `outcodes` (the OR
/// of its vertices' outcodes). The result may be empty. Every vertex of
/// the result has in [`ClipVertex::bary`] its place in `tri` (whatever the
/// input's `bary`).
///
/// ```
/// use microraster::clip::clip_triangle;
/// use microraster::vertex::{outcode, ClipVertex};
/// let one = 1 << 16;
/// let v = |x: i32, z: i32| ClipVertex { pos: [x, 0, z, one], color: [0; 3], bary: [0; 2] };
/// // One vertex in front of the near plane (z < -w), two inside.
/// let tri = [v(0, -2 * one), v(one / 2, 0), v(-one / 2, 0)];
/// let codes = tri.iter().fold(0, |c, v| c | outcode(&v.pos));
/// let poly = clip_triangle(&tri, codes);
/// assert_eq!(poly.len(), 4);
/// assert!(poly.iter().all(|v| v.pos[2] >= -v.pos[3]));
/// ```
pub fn clip_triangle(tri: &[ClipVertex; 3], outcodes: u8) -> Polygon {
    let mut a = Polygon::new();
    let mut b = Polygon::new();
    for (k, v) in tri.iter().enumerate() {
        let mut v = *v;
        v.bary = [(k == 1) as i32 * BARY_ONE, (k == 2) as i32 * BARY_ONE];
        let _ = a.push(v);
    }
    let mut planes: heapless::Vec<Plane, 7> = heapless::Vec::new();
    if outcodes & OUT_W != 0 {
        let _ = planes.push(Plane::WMin);
    }
    if outcodes & OUT_NEAR != 0 {
        let _ = planes.push(Plane::Near);
    }
    if outcodes & OUT_FAR != 0 {
        let _ = planes.push(Plane::Far);
    }
    if outcodes & OUT_GUARD != 0 {
        for p in [Plane::Left, Plane::Right, Plane::Bottom, Plane::Top] {
            let _ = planes.push(p);
        }
    }
    for &p in &planes {
        clip_against(&a, p, &mut b);
        core::mem::swap(&mut a, &mut b);
        if a.len() < 3 {
            a.clear();
            break;
        }
    }
    a
}

#[cfg(test)]
mod tests {
    use super::lerp;

    /// The rounded quotient in `i128`, as `lerp` took it before.
    fn reference(a: i32, b: i32, d_in: i64, den: i64) -> i32 {
        let (num, den) = ((b as i128 - a as i128) * d_in as i128, den as i128);
        let q = if num >= 0 {
            (num + den / 2) / den
        } else {
            -((-num + den / 2) / den)
        };
        (a as i128 + q) as i32
    }

    #[test]
    fn lerp_matches_the_wide_division() {
        let mut next = crate::testing::rng();
        let ends = [i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX - 1, i32::MAX];
        for _ in 0..400_000 {
            let a = match next(4) {
                0 => ends[next(ends.len() as u64) as usize],
                _ => next(1 << 32) as u32 as i32,
            };
            let b = match next(4) {
                0 => ends[next(ends.len() as u64) as usize],
                1 => a.wrapping_add(next(1000) as i32 - 500),
                _ => next(1 << 32) as u32 as i32,
            };
            // Denominators of every size up to 2^63 - 1, the distance
            // anywhere in 0..=den (both ends often).
            let bits = 1 + next(63);
            let den = (1 + next(1u64 << (bits - 1)) + (1u64 << (bits - 1)) - 1).min(i64::MAX as u64)
                as i64;
            let d_in = match next(5) {
                0 => 0,
                1 => den,
                2 => den / 2,
                _ => next(den as u64 + 1).min(den as u64) as i64,
            };
            assert_eq!(
                lerp(a, b, d_in, den),
                reference(a, b, d_in, den),
                "lerp({a}, {b}, {d_in}, {den})"
            );
        }
    }
}
