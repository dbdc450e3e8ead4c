//! Clip space: the clipper's vertex, outcodes and the guard band.
//!
//! Each clip-space vertex gets an outcode: one bit per frustum half-space it
//! lies outside (`x < -w`, `x > w`, `y < -w`, `y > w`, `z < -w`, `z > w`),
//! one for `w` below [`W_MIN`], and one for leaving the *guard band*
//! `|x| <= K w, |y| <= K w` with `K =` [`GUARD_K`]. A triangle whose three
//! outcodes share a half-space bit is rejected; a triangle with any vertex
//! outside near, far, `W_MIN` or the guard band is clipped by
//! [`crate::clip`]; every other triangle is projected directly.
//!
//! The guard band is what bounds the fixed-point ranges downstream: after
//! clipping, `|x / w| <= K + 1/16`, so with the viewport limited to
//! [`MAX_VIEWPORT`](super::MAX_VIEWPORT) pixels a side, screen coordinates stay within
//! `(K + 1.07) * 4096 * 16 < 2^18` sub-pixels. The rasterizer's set-up then
//! needs at most 2^39 in `i64` and its per-row stepping fits `i32`
//! (denominators below 2^24, columns below 2^15).

/// Outside `x >= -w`.
pub const OUT_LEFT: u8 = 1;
/// Outside `x <= w`.
pub const OUT_RIGHT: u8 = 2;
/// Outside `y >= -w`.
pub const OUT_BOTTOM: u8 = 4;
/// Outside `y <= w`.
pub const OUT_TOP: u8 = 8;
/// Outside the near plane `z >= -w`.
pub const OUT_NEAR: u8 = 16;
/// Outside the far plane `z <= w`.
pub const OUT_FAR: u8 = 32;
/// `w` below [`W_MIN`] (behind or too close to the eye to divide by).
pub const OUT_W: u8 = 64;
/// Outside the guard band `|x| <= K w, |y| <= K w`.
pub const OUT_GUARD: u8 = 128;
/// Bits that force a triangle through the clipper.
pub const MUST_CLIP: u8 = OUT_NEAR | OUT_FAR | OUT_W | OUT_GUARD;
/// Bits that are single half-spaces, usable for trivial reject.
pub const REJECT_MASK: u8 = !OUT_GUARD;

/// Guard-band size in multiples of the viewport half-extent.
pub const GUARD_K: i64 = 4;
/// Smallest `w` (raw 16.16, i.e. 2^-12) that is divided by.
pub const W_MIN: i64 = 16;

/// A vertex in homogeneous clip space, for the clipper.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipVertex {
    /// `x, y, z, w` as raw 16.16.
    pub pos: [i32; 4],
    /// Lit colour, 8 bits per channel (kept as `i32` for interpolation).
    pub color: [i32; 3],
    /// Where the vertex lies in the triangle it was clipped from: the
    /// weights of that triangle's vertices 1 and 2, [`BARY_ONE`] being 1.
    /// [`clip_triangle`](crate::clip::clip_triangle) sets and interpolates
    /// them, so shaders' varyings need not pass through the clipper.
    pub bary: [i32; 2],
}

/// The barycentric weight 1 of [`ClipVertex::bary`].
pub const BARY_ONE: i32 = 1 << 30;

/// The outcode of a clip-space position.
#[inline(always)]
pub fn outcode(p: &[i32; 4]) -> u8 {
    // Most vertices are inside the view volume: then every bit is clear
    // (inside `|x| <= w` is inside the guard band too).
    let inside = match (cfg!(target_pointer_width = "64"), crate::math::SPLIT) {
        (true, _) => inside_wide(p),
        (false, true) => inside_signs(p),
        (false, false) => inside_words(p),
    };
    if inside {
        return 0;
    }
    match crate::math::SPLIT || cfg!(target_pointer_width = "64") {
        true => outcode_slow_wide(p[0] as i64, p[1] as i64, p[2] as i64, p[3] as i64),
        false => outcode_slow(p[0], p[1], p[2], p[3]),
    }
}

/// Whether `p` is inside the view volume (`W_MIN <= w`, `|x|, |y|, |z| <=
/// w`), in `i64`: fewer instructions where that is a register.
#[inline(always)]
fn inside_wide(p: &[i32; 4]) -> bool {
    let (x, y, z, w) = (p[0] as i64, p[1] as i64, p[2] as i64, p[3] as i64);
    w >= W_MIN && x.abs() <= w && y.abs() <= w && z.abs() <= w
}

/// [`inside_words`] by one sign test of the three `w - |v|` or-ed, for
/// ARMv6-M, whose vertex loop made each compare of `inside_words` a flag
/// in a stack slot and combined the flags (about 25 instructions a
/// vertex). With `W_MIN <= w < 2^31` and `|v| <= 2^31`, `w - |v|` as an
/// unsigned word is `0..=w` (below `2^31`) where `|v| <= w`, and
/// otherwise wraps to `2^32 - (|v| - w)` with `0 < |v| - w < 2^31`
/// (above `2^31`): its top bit is set exactly when `|v| > w`.
#[inline(always)]
#[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
fn inside_signs(p: &[i32; 4]) -> bool {
    let w = p[3];
    if (w as i64) < W_MIN {
        return false;
    }
    let wu = w as u32;
    let d = [p[0], p[1], p[2]].map(|v| wu.wrapping_sub(v.unsigned_abs()));
    (d[0] | d[1] | d[2]) >> 31 == 0
}

/// [`inside_wide`] in 32 bits, for 32-bit cores: with `w` positive,
/// `|x| <= w` compares the same as unsigned.
#[inline(always)]
fn inside_words(p: &[i32; 4]) -> bool {
    let w = p[3];
    let wu = w as u32;
    w as i64 >= W_MIN
        && p[0].unsigned_abs() <= wu
        && p[1].unsigned_abs() <= wu
        && p[2].unsigned_abs() <= wu
}

/// [`outcode`] of a vertex outside the view volume. The coordinates as
/// `i32`, widened here: four registers at each call on 32-bit cores, where
/// four `i64` took eight and their sign extensions (84 bytes less flash in
/// the OLED firmware).
#[inline(never)]
#[cfg_attr(
    any(microraster_narrow_multiply, target_pointer_width = "64"),
    allow(dead_code)
)]
fn outcode_slow(x: i32, y: i32, z: i32, w: i32) -> u8 {
    outcode_wide(x as i64, y as i64, z as i64, w as i64)
}

/// [`outcode_slow`] of `i64` coordinates, for ARMv6-M and 64-bit hosts:
/// their vertex loops measured 12,000 (ARMv6-M) and 11,700 (x86-64)
/// instructions a `demo` frame slower calling the `i32` one (registers
/// allocated worse), though the call is rare.
#[inline(never)]
#[cfg_attr(
    not(any(microraster_narrow_multiply, target_pointer_width = "64")),
    allow(dead_code)
)]
fn outcode_slow_wide(x: i64, y: i64, z: i64, w: i64) -> u8 {
    outcode_wide(x, y, z, w)
}

/// The outcode of `(x, y, z, w)`, every plane tested.
#[inline(always)]
fn outcode_wide(x: i64, y: i64, z: i64, w: i64) -> u8 {
    let mut c = 0;
    if x < -w {
        c |= OUT_LEFT;
    }
    if x > w {
        c |= OUT_RIGHT;
    }
    if y < -w {
        c |= OUT_BOTTOM;
    }
    if y > w {
        c |= OUT_TOP;
    }
    if z < -w {
        c |= OUT_NEAR;
    }
    if z > w {
        c |= OUT_FAR;
    }
    if w < W_MIN {
        c |= OUT_W;
    }
    let g = GUARD_K * w;
    if x.abs() > g || y.abs() > g {
        c |= OUT_GUARD;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcodes_flag_each_half_space() {
        let w = 1 << 16;
        assert_eq!(outcode(&[0, 0, 0, w]), 0);
        assert_eq!(outcode(&[-2 * w, 0, 0, w]), OUT_LEFT);
        assert_eq!(outcode(&[0, 5 * w, 0, w]), OUT_TOP | OUT_GUARD);
        assert_eq!(outcode(&[0, 0, -2 * w, w]), OUT_NEAR);
        assert_eq!(outcode(&[0, 0, 0, -w]) & OUT_W, OUT_W);
    }

    /// The tests of a vertex inside the view volume (32- and 64-bit, and
    /// ARMv6-M's by signs) agree
    /// with the full outcode everywhere: the extremes of `i32`, `w` around `W_MIN`,
    /// coordinates around `±w`.
    #[test]
    fn the_inside_test_agrees_with_the_full_outcode() {
        let mut next = crate::testing::rng();
        let full = |p: &[i32; 4]| outcode_slow(p[0], p[1], p[2], p[3]);
        let ws = [
            i32::MIN,
            -1,
            0,
            1,
            15,
            16,
            17,
            1 << 16,
            i32::MAX - 1,
            i32::MAX,
        ];
        for w in ws {
            let near = |d: i32| [w.saturating_add(d), w.saturating_neg().saturating_add(d)];
            let mut cs: heapless::Vec<i32, 16> = heapless::Vec::new();
            for c in [i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX] {
                cs.push(c).unwrap();
            }
            for d in [-1, 0, 1] {
                cs.extend_from_slice(&near(d)).unwrap();
            }
            for &x in &cs {
                for &y in &cs {
                    for &z in &cs {
                        let p = [x, y, z, w];
                        assert_eq!(outcode(&p), full(&p), "{p:?}");
                        assert_eq!(inside_words(&p), inside_wide(&p), "{p:?}");
                        assert_eq!(inside_signs(&p), inside_wide(&p), "{p:?}");
                    }
                }
            }
        }
        for _ in 0..100_000 {
            let w = (next(1 << 32) as u32 as i32) >> next(32);
            let mut c = || (next(1 << 32) as u32 as i32) >> next(32);
            let p = [c(), c(), c(), w];
            assert_eq!(outcode(&p), full(&p), "{p:?}");
            assert_eq!(inside_words(&p), inside_wide(&p), "{p:?}");
            assert_eq!(inside_signs(&p), inside_wide(&p), "{p:?}");
        }
    }
}
