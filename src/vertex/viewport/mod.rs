//! The viewport transform: clip space to screen sub-pixels and depth.
//!
//! NDC x in `[-1, 1]` maps to `[0, width]` pixels left to right, NDC y in
//! `[-1, 1]` to `[height, 0]` (screen y grows downwards), both rounded to the
//! nearest 1/16 pixel. NDC z in `[-1, 1]` maps to depth `0..=65535`.
//!
//! The projection divides by `w` in the form the core is fastest at:
//! [`long`] by 32-bit division where it is an instruction (ARMv7-M,
//! ARMv8-M Mainline, RISC-V `rv32im`), [`recip`] by `w`'s 16-bit
//! reciprocal on ARMv6-M, [`wide`] by 64-bit division on 64-bit hosts; the
//! general form here serves the rare vertex far away or clipped.

mod long;
mod recip;
mod wide;

use super::{outcode, ClipVertex, ScreenVertex, MUST_CLIP, W_MIN};
use crate::math::WDivisor;
use crate::raster::{SubPoint, SUBPIXEL};
use core::num::{NonZeroU32, NonZeroU64};

use long::FAST_W;
use recip::RECIP_W;

/// Largest viewport side in pixels.
pub const MAX_VIEWPORT: u32 = 4096;

/// The viewport transform of a validated viewport size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Viewport {
    /// Half the width, in sub-pixels.
    half_w: i64,
    /// Half the height, in sub-pixels.
    half_h: i64,
    /// [`Viewport::project_inside`] divides by a `w` below this in 32 bits
    /// ([`Viewport::project_digits`]): below `2^23`, and such that `(4 w h
    /// + w / 2) < 2^32` for either half side `h` and `515 w < 2^32`
    /// ([`depth_by_2w`]'s dividends, [`FAST_W`]).
    short_w: u32,
    /// [`Viewport::project_recip`] takes x's and y's remainders' quotient
    /// in one digit for a `w` up to this (0 for none): with both half
    /// sides below `2^12`, `b h + w / 2 < w 2^12` (one digit's range) for
    /// `b < w`, and below `2^32` for `w (h + 1) <= 2^32 - 1`; and below
    /// [`RECIP_W`], so that [`Viewport::project_inside`] sends a vertex
    /// inside the view volume to `project_recip`'s one digit after one
    /// bound (ARMv6-M `demo` 6,599,789 to 6,578,535 instructions). Only
    /// where `project_recip` is used (elsewhere 8 instructions a `demo`
    /// frame more on the Cortex-M3 for nothing).
    #[cfg(any(test, microraster_narrow_multiply))]
    one_w: u32,
    /// `one_w + 1 - 2^15` (0 where `one_w` is below `2^15`): the `w` of
    /// [`Viewport::project_recip_fast`] are `2^15 <= w <= one_w`, one
    /// unsigned compare of `w - 2^15` with this.
    #[cfg(any(test, microraster_narrow_multiply))]
    fast_w: u32,
    /// Zero, through `black_box`: [`Viewport::project_fast_wide`] divides
    /// by `2w ^ hash`, which LLVM takes for a hash and so does not guard
    /// with its test of whether the dividend and the divisor fit 32 bits
    /// (x86-64: an `or`, a shift and a branch a division, and the
    /// shorter `div`'s moves; `math::divisor`'s `Hardware` does the
    /// same). On 64-bit targets only, where that division is.
    #[cfg(target_pointer_width = "64")]
    hash: u64,
}

impl Viewport {
    /// A viewport of `width` x `height` pixels, both in `1..=MAX_VIEWPORT`
    /// (checked by the renderer).
    pub fn new(width: u32, height: u32) -> Self {
        debug_assert!((1..=MAX_VIEWPORT).contains(&width) && (1..=MAX_VIEWPORT).contains(&height));
        let (half_w, half_h) = (width * SUBPIXEL as u32 / 2, height * SUBPIXEL as u32 / 2);
        // w (4 h + 1) <= 2^32 - 1 bounds 4 w h + w / 2.
        let short_w = (u32::MAX / (4 * half_w.max(half_h) + 1) + 1).min(FAST_W);
        #[cfg(any(test, microraster_narrow_multiply))]
        let one_w = match half_w.max(half_h) < 1 << 12 {
            // Below RECIP_W too: `project_inside` then tests one bound.
            true => (u32::MAX / (half_w.max(half_h) + 1)).min(RECIP_W - 1),
            false => 0,
        };
        Self {
            half_w: half_w as i64,
            half_h: half_h as i64,
            short_w,
            #[cfg(any(test, microraster_narrow_multiply))]
            one_w,
            #[cfg(any(test, microraster_narrow_multiply))]
            fast_w: (one_w + 1).saturating_sub(1 << 15),
            #[cfg(target_pointer_width = "64")]
            hash: core::hint::black_box(0),
        }
    }

    /// Screen position and depth of a clip-space point with `w >= W_MIN - 1`
    /// inside the guard band (up to clipping round-off).
    ///
    /// The three quotients by `w` share one divisor (through `w`'s
    /// reciprocal on 32-bit targets); each is `n / w` rounded to nearest,
    /// ties away from zero, as three divisions would give.
    #[inline(always)]
    pub fn project(&self, p: &[i32; 4]) -> (SubPoint, u16) {
        let w = (p[3] as i64).max(1);
        // `w >= 1`, so this never falls back. By long division: `w` is
        // mostly 2^16 to 2^22, where the set-up's `new` divides in 64 bits;
        // on ARMv6-M a 32-bit reciprocal (`WDivisor`). Here the three
        // quotients are taken one by one: the Cortex-M3's vertex stage
        // measured 51,000 instructions slower with them taken together
        // (one check of the three dividends, one fallback for all).
        let d = WDivisor::new_long(NonZeroU64::new(w as u64).unwrap_or(NonZeroU64::MIN));
        self.project_by(p, w, |m| d.div_split(m))
    }

    /// [`project`](Self::project) with `w = max(p[3], 1)` and `div(m) =
    /// floor(m / w)`, for `m < 2^49`: each quotient `n / w` rounded to
    /// nearest, ties away from zero.
    #[inline(always)]
    fn project_by(&self, p: &[i32; 4], w: i64, div: impl Fn(u64) -> u64) -> (SubPoint, u16) {
        let half = w as u64 / 2;
        // div_round(n, w), for |n| < 2^48.
        let round = |n: i64| -> i64 {
            let q = div(n.unsigned_abs() + half) as i64;
            if n < 0 {
                -q
            } else {
                q
            }
        };
        // Half a viewport side in sub-pixels is at most 2^15: the products
        // are of two i32 (a library call each on ARMv6-M as i64 x i64).
        let (hw, hh) = (self.half_w as i32, self.half_h as i32);
        let x = self.half_w + round(crate::math::mul_wide(p[0], hw));
        let y = self.half_h - round(crate::math::mul_wide(p[1], hh));
        // div_round(n, 2w) = floor((|n| + w) / (2w)) = floor((|n| + w) / w) / 2.
        let n = (p[2] as i64 + w) * 65_535;
        let z = (div(n.unsigned_abs() + w as u64) >> 1) as i64;
        let z = if n < 0 { -z } else { z }.clamp(0, 65_535);
        (SubPoint::new(x as i32, y as i32), z as u16)
    }

    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`] bits
    /// (`W_MIN <= w`, `|x|, |y| <= K w`, `|z| <= w`): the same results.
    /// Where a 32-bit division is an instruction ([`LONG_DIVISION`]) and
    /// `w < 2^23`, x's and y's quotients are one of them, depth's three, rather
    /// than a multiply-high by `w`'s 64-bit reciprocal, which itself took
    /// two to four divisions: on the Cortex-M3 about 110 instructions a
    /// vertex fewer.
    ///
    /// `inside` says the vertex is inside the view volume (outcode 0:
    /// `|x|, |y|, |z| <= w`), which ARMv6-M's projection
    /// ([`project_recip`](Self::project_recip)) takes as the bound of its
    /// one-digit quotients.
    #[inline(always)]
    pub(crate) fn project_inside(&self, p: &[i32; 4], inside: bool) -> (SubPoint, u32) {
        let wide = |(p, z): (SubPoint, u16)| (p, z as u32);
        if !LONG_DIVISION {
            if !crate::math::SPLIT {
                return wide(self.project(p));
            }
            return match NonZeroU32::new(p[3] as u32) {
                // Nearly every vertex: `w <= one_w` (below `RECIP_W`) and
                // inside the view volume, one bound and one flag tested.
                Some(w) if inside && w.get() <= self.one_w() => self.project_recip(p, w, true),
                Some(w) if w.get() < RECIP_W => self.project_recip(p, w, false),
                _ => wide(self.project_wide(p[0], p[1], p[2], p[3])),
            };
        }
        match NonZeroU32::new(p[3] as u32) {
            Some(w) if w.get() < self.short_w => self.project_digits(p, w),
            _ => wide(self.project_wide(p[0], p[1], p[2], p[3])),
        }
    }

    /// [`project`](Self::project), out of line: for the rare vertex of
    /// [`project_inside`](Self::project_inside) with `w` from `short_w` up
    /// (for 320 x 240 and a normalized matrix, more than 6.4 units), and
    /// for the clipper's vertices (rare too: one copy of the projection's
    /// long divisions for both). (The coordinates by value: a reference
    /// would keep the vertex in memory.)
    #[inline(never)]
    #[cold]
    pub(crate) fn project_wide(&self, x: i32, y: i32, z: i32, w: i32) -> (SubPoint, u16) {
        match LONG_DIVISION {
            true => self.project_plain(&[x, y, z, w]),
            false => self.project(&[x, y, z, w]),
        }
    }

    /// [`project`](Self::project) by three 64-bit divisions (the library's
    /// on 32-bit cores): the same quotients, `n / w` rounded to nearest,
    /// ties away from zero. [`project_wide`](Self::project_wide)'s, where
    /// `w`'s reciprocal and its multiply-highs were about 400 bytes more
    /// code for the rare vertex far away or clipped.
    #[inline(always)]
    #[cfg_attr(not(test), allow(dead_code))]
    fn project_plain(&self, p: &[i32; 4]) -> (SubPoint, u16) {
        let w = (p[3] as i64).max(1);
        let d = NonZeroU64::new(w as u64).unwrap_or(NonZeroU64::MIN);
        self.project_by(p, w, |m| m / d)
    }

    /// `hash` (0, where the field is not kept: `project_fast_wide`
    /// unused).
    #[inline(always)]
    fn hash(&self) -> u64 {
        #[cfg(target_pointer_width = "64")]
        return self.hash;
        #[cfg(not(target_pointer_width = "64"))]
        0
    }

    /// `fast_w` (0 where the field is not kept: `project_recip_fast`
    /// unused).
    #[inline(always)]
    fn fast_w(&self) -> u32 {
        #[cfg(any(test, microraster_narrow_multiply))]
        return self.fast_w;
        #[cfg(not(any(test, microraster_narrow_multiply)))]
        0
    }

    /// The largest `w` of [`project_recip`](Self::project_recip)'s one
    /// digit (0 where the field is not kept: `project_recip` unused).
    #[inline(always)]
    fn one_w(&self) -> u32 {
        #[cfg(any(test, microraster_narrow_multiply))]
        return self.one_w;
        #[cfg(not(any(test, microraster_narrow_multiply)))]
        0
    }

    /// Runs the vertex stage on one vertex.
    #[inline(always)]
    pub fn screen_vertex(&self, v: &ClipVertex) -> ScreenVertex {
        let color = [v.color[0] as u8, v.color[1] as u8, v.color[2] as u8];
        let inside = super::screen::channels_interior(color);
        self.screen_vertex_lit::<false>(&v.pos, true, || (color, inside))
    }

    /// [`screen_vertex`](Self::screen_vertex) of the vertex at clip-space
    /// position `pos` whose lit colour `color` gives, asked for after the
    /// projection: the vertex stage's loop then keeps neither the colour
    /// nor the lighting's constants in registers (or on the stack) across
    /// the divisions. With `fast`, where a 32-bit division is an
    /// instruction, a vertex inside the view volume (nearly all) is tested
    /// and projected inline ([`project_fast`](Self::project_fast)), any
    /// other out of line; without it, every vertex out of line (the vertex
    /// stage's general loop, which calls out of line for its position and
    /// colour anyway: one inline copy of the projection fewer in flash).
    /// `color` also says whether the vertex may carry the
    /// [`interior`](ScreenVertex::interior) bit as far as its colour goes
    /// (see [`ScreenVertex::new_tested`]); with `CHANNELS` the colour's
    /// channels are tested here too.
    #[inline(always)]
    pub(crate) fn screen_vertex_lit<const CHANNELS: bool>(
        &self,
        pos: &[i32; 4],
        fast: bool,
        color: impl FnOnce() -> ([u8; 3], bool),
    ) -> ScreenVertex {
        let (outcode, p, z) = self.project_any(pos, fast);
        // Within the coordinate fields: `p` is 0 for a vertex that must be
        // clipped, otherwise inside the guard band (`|x|, |y| <= K w`), so
        // within `(K + 1) * 2^15 < 2^18` sub-pixels.
        let (color, inside) = color();
        match CHANNELS {
            true => ScreenVertex::new(p.x, p.y, z as u16, outcode, color),
            false => ScreenVertex::new_tested(p.x, p.y, z, outcode, color, inside),
        }
    }

    /// [`screen_vertex_lit`](Self::screen_vertex_lit) (without
    /// `CHANNELS`) of a vertex whose colour `word` gives as a
    /// [`color_word`](super::screen::color_word): the vertex stage's
    /// Lambert loops.
    #[inline(always)]
    pub(crate) fn screen_vertex_word(
        &self,
        pos: &[i32; 4],
        fast: bool,
        word: impl FnOnce() -> u32,
    ) -> ScreenVertex {
        if LONG_DIVISION && fast {
            let (xo, y, z) = match self.project_fast(pos) {
                Some((p, z)) => (ScreenVertex::xo_word(p.x, 0), p.y, z),
                None => {
                    let (outcode, p, z) = self.project_rest(pos[0], pos[1], pos[2], pos[3]);
                    (ScreenVertex::xo_word(p.x, outcode), p.y, z)
                }
            };
            return ScreenVertex::with_xo_color_word(xo, y, z, word());
        }
        let (outcode, p, z) = self.project_any(pos, fast);
        ScreenVertex::with_color_word(p.x, p.y, z, outcode, word())
    }

    /// The outcode and projection of [`screen_vertex_lit`](Self::screen_vertex_lit):
    /// with `fast`, a vertex inside the view volume inline (where a
    /// division is an instruction, or by `w`'s [`Recip16`](crate::math::Recip16) on ARMv6-M) and
    /// any other out of line; without, every vertex inline.
    #[inline(always)]
    fn project_any(&self, pos: &[i32; 4], fast: bool) -> (u8, SubPoint, u32) {
        if LONG_DIVISION || WIDE_DIVISION {
            match fast.then(|| self.project_fast_any(pos)).flatten() {
                Some((p, z)) => (0, p, z),
                None => self.project_rest(pos[0], pos[1], pos[2], pos[3]),
            }
        } else if fast {
            // ARMv6-M: nearly every vertex inline, any other out of line.
            match self.project_recip_fast(pos) {
                Some((p, z)) => (0, p, z),
                None => self.project_rest(pos[0], pos[1], pos[2], pos[3]),
            }
        } else {
            self.outcode_and_project(pos)
        }
    }

    /// The inline projection of a vertex inside the view volume where a
    /// division is an instruction: [`project_fast_wide`](Self::project_fast_wide)
    /// on 64-bit targets ([`WIDE_DIVISION`]), otherwise
    /// [`project_fast`](Self::project_fast). Chosen by a constant, so
    /// [`screen_vertex_lit`](Self::screen_vertex_lit) keeps one match.
    #[inline(always)]
    fn project_fast_any(&self, pos: &[i32; 4]) -> Option<(SubPoint, u32)> {
        if WIDE_DIVISION {
            self.project_fast_wide(pos)
        } else {
            self.project_fast(pos)
        }
    }

    /// The outcode of `pos` and, for a vertex without [`MUST_CLIP`] bits,
    /// its projection ([`project_inside`](Self::project_inside)).
    #[inline(always)]
    fn outcode_and_project(&self, pos: &[i32; 4]) -> (u8, SubPoint, u32) {
        let outcode = outcode(pos);
        let (p, z) = if outcode & MUST_CLIP == 0 {
            self.project_inside(pos, outcode == 0)
        } else {
            (SubPoint::default(), 0)
        };
        (outcode, p, z)
    }

    /// [`outcode_and_project`](Self::outcode_and_project) out of line, for
    /// the vertices [`project_fast`](Self::project_fast) declines. (The
    /// coordinates by value: a reference would keep the vertex in memory.)
    #[inline(never)]
    #[cold]
    fn project_rest(&self, x: i32, y: i32, z: i32, w: i32) -> (u8, SubPoint, u32) {
        self.outcode_and_project(&[x, y, z, w])
    }
}

/// Whether the vertex stage projects a vertex inside the view volume by
/// 64-bit divisions ([`Viewport::project_fast_wide`]): on 64-bit targets.
const WIDE_DIVISION: bool = cfg!(target_pointer_width = "64");

/// Whether the vertex stage divides by `w` through 32-bit divisions
/// ([`Viewport::project_inside`]): on 32-bit cores with a 32 x 32 -> 64-bit
/// multiply, which have a divide instruction too (ARMv7-M, ARMv8-M
/// Mainline, RISC-V `rv32im`). ARMv6-M, whose division is a library call,
/// keeps `w`'s 32-bit reciprocal; 64-bit targets their 64-bit division.
const LONG_DIVISION: bool = cfg!(all(
    not(microraster_narrow_multiply),
    not(target_pointer_width = "64")
));

#[cfg(test)]
mod tests {
    use super::long::DIGITS_W_BITS;
    use super::*;
    use crate::vertex::{div_round, GUARD_K};

    /// The guard band keeps every projected vertex inside the fields: the
    /// largest viewport, a vertex on the guard band's corner.
    #[test]
    fn the_guard_band_fits_the_coordinate_fields() {
        let vp = Viewport::new(MAX_VIEWPORT, MAX_VIEWPORT);
        let w = 1 << 16;
        let g = GUARD_K as i32 * w;
        for (x, y) in [(g, g), (-g, -g), (g, -g), (-g, g)] {
            let c = ClipVertex {
                pos: [x, y, 0, w],
                ..ClipVertex::default()
            };
            assert_eq!(outcode(&c.pos) & MUST_CLIP, 0);
            let v = vp.screen_vertex(&c);
            let (p, _) = vp.project(&c.pos);
            assert_eq!(v.xy(), p);
            assert!(p.x.abs() < 1 << 18 && p.y.abs() < 1 << 18, "{p:?}");
        }
    }

    #[test]
    fn viewport_maps_ndc_corners_to_pixel_corners() {
        let vp = Viewport::new(320, 240);
        let one = 1 << 16;
        let (p, z) = vp.project(&[-one, one, -one, one]);
        assert_eq!((p.x, p.y, z), (0, 0, 0));
        let (p, z) = vp.project(&[one, -one, one, one]);
        assert_eq!((p.x, p.y, z), (320 * 16, 240 * 16, 65_535));
        let (p, _) = vp.project(&[0, 0, 0, 2 * one]);
        assert_eq!((p.x, p.y), (160 * 16, 120 * 16));
    }

    /// `project_inside` (32-bit divisions for `w < 2^23`)
    /// against `project`, for vertices without `MUST_CLIP` bits: `w` from
    /// `W_MIN` to beyond 2^23, coordinates up to the guard band, the
    /// extremes of each.
    #[test]
    fn projection_inside_matches_project() {
        let mut next = crate::testing::rng();
        // (511 and 512 pixels: half sides just below and at 2^12 sub-pixels,
        // the ends of `project_recip`'s one digit.)
        for (width, height) in [
            (320, 240),
            (4096, 4096),
            (1, 4096),
            (4096, 3001),
            (511, 2),
            (2, 512),
        ] {
            let vp = Viewport::new(width, height);
            for i in 0..200_000u64 {
                let w = match i % 8 {
                    0 => W_MIN + next(16) as i64,
                    // `project_recip`'s largest w of one digit, and beyond.
                    3 if vp.one_w > 0 => {
                        (vp.one_w as i64 - 2 + next(4) as i64).min((1 << DIGITS_W_BITS) - 1)
                    }
                    1 => (1 << DIGITS_W_BITS) - 1 - next(4) as i64,
                    // `project_recip`'s largest w, and beyond.
                    4 => RECIP_W as i64 - 2 + next(4) as i64,
                    // The largest w of the 32-bit quotients.
                    2 => vp.short_w as i64 - 1 - next(4) as i64,
                    _ => W_MIN + (next(1 << 28) >> next(24)) as i64,
                } as i32;
                let g = GUARD_K as i32 * w;
                let mut c = |limit: i32| match next(6) {
                    0 => limit,
                    1 => -limit,
                    _ => (next(2 * limit as u64 + 1) as i64 - limit as i64) as i32,
                };
                // A third inside the view volume (`project_recip`'s one
                // digit).
                let p = match i % 3 {
                    0 => [c(w), c(w), c(w), w],
                    _ => [c(g), c(g), c(w), w],
                };
                assert_eq!(outcode(&p) & MUST_CLIP, 0, "{p:?}");
                let want = vp.project(&p);
                let want = (want.0, want.1 as u32);
                let inside = outcode(&p) == 0;
                assert_eq!(vp.project_inside(&p, inside), want, "{p:?}");
                let nz = NonZeroU32::new(w as u32).unwrap();
                if nz.get() < vp.short_w {
                    assert_eq!(vp.project_digits(&p, nz), want, "{p:?}");
                }
                if inside && (1 << 15..=vp.one_w).contains(&nz.get()) {
                    assert_eq!(vp.project_recip_fast(&p), Some(want), "{p:?}");
                }
                if nz.get() < RECIP_W {
                    assert_eq!(vp.project_recip(&p, nz, inside), want, "{p:?}");
                    assert_eq!(vp.project_recip(&p, nz, false), want, "{p:?}");
                }
            }
        }
    }

    /// `project_fast` against `project` where it projects, and against
    /// the outcode where it declines: `w` from below `W_MIN` to beyond
    /// `short_w`, coordinates inside the view volume (its faces and
    /// corners included), just outside it and anywhere in `i32`.
    #[test]
    fn fast_projection_matches_project_inside_the_view_volume() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        for (width, height) in [(320, 240), (4096, 4096), (1, 4096), (4096, 3001), (2, 1)] {
            let vp = Viewport::new(width, height);
            for i in 0..300_000u64 {
                let w = match i % 8 {
                    0 => W_MIN - 2 + next(8) as i64,
                    1 => vp.short_w as i64 - 3 + next(6) as i64,
                    2 => (next(1 << 32) as u32 as i32) as i64,
                    3 => 1 << DIGITS_W_BITS,
                    4 => FAST_W as i64 - 3 + next(6) as i64,
                    _ => W_MIN + (next(1 << 28) >> next(24)) as i64,
                } as i32;
                let mut c = || match next(8) {
                    0 => w,
                    1 => w.wrapping_neg(),
                    2 => w.wrapping_add(1),
                    3 => w.wrapping_neg().wrapping_sub(1),
                    4 => next(1 << 32) as u32 as i32,
                    _ => {
                        (next(2 * w.unsigned_abs() as u64 + 1) as i64 - w.unsigned_abs() as i64)
                            as i32
                    }
                };
                let p = [c(), c(), c(), w];
                let inside = outcode(&p) == 0 && (w as u32) < vp.short_w;
                let fast = vp.project_fast(&p);
                let want = inside.then(|| vp.project(&p)).map(|(p, z)| (p, z as u32));
                assert_eq!(fast, want, "{p:?}");
                // ARMv6-M's inline path: outcode 0 and `2^15 <= w <=
                // one_w`, otherwise declined.
                let recip = outcode(&p) == 0 && (1 << 15..=vp.one_w).contains(&(w as u32));
                let want = recip.then(|| vp.project(&p)).map(|(p, z)| (p, z as u32));
                assert_eq!(vp.project_recip_fast(&p), want, "{p:?}");
                // The 64-bit form for every `w` (no `short_w`).
                let wide = vp.project_fast_wide(&p);
                let want = (outcode(&p) == 0).then(|| vp.project(&p));
                assert_eq!(wide, want.map(|(p, z)| (p, z as u32)), "{p:?}");
                taken += inside as u32;
            }
        }
        assert!(taken > 100_000, "{taken}");
    }

    /// `project` (one divisor for the three quotients) against the three
    /// `div_round`s it replaces, over `w` from 1 to 2^31 and coordinates
    /// up to the guard band and a little beyond (clipping round-off).
    #[test]
    fn projection_matches_three_divisions() {
        let vp = Viewport::new(4096, 3001);
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..200_000 {
            let w = ((next() >> (33 + next() % 31)) as i64).max(1);
            let mut c = || {
                let r = (next() % (10 * w as u64 + 1)) as i64 - 5 * w;
                r.clamp(i32::MIN as i64, i32::MAX as i64) as i32
            };
            let p = [c(), c(), c(), w as i32];
            let (s, z) = vp.project(&p);
            assert_eq!(vp.project_plain(&p), (s, z), "{p:?}");
            let ex = vp.half_w + div_round(p[0] as i64 * vp.half_w, w);
            let ey = vp.half_h - div_round(p[1] as i64 * vp.half_h, w);
            let ez = div_round((p[2] as i64 + w) * 65_535, 2 * w).clamp(0, 65_535);
            assert_eq!((s.x as i64, s.y as i64, z as i64), (ex, ey, ez), "{p:?}");
        }
    }
}
