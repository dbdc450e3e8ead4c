//! The viewport transform: clip space to screen sub-pixels and depth.
//!
//! NDC x in `[-1, 1]` maps to `[0, width]` pixels left to right, NDC y in
//! `[-1, 1]` to `[height, 0]` (screen y grows downwards), both rounded to the
//! nearest 1/16 pixel. NDC z in `[-1, 1]` maps to depth `0..=65535`.

use super::{outcode, ClipVertex, ScreenVertex, MUST_CLIP, W_MIN};
use crate::math::Recip16;
use crate::math::WDivisor;
use crate::raster::{SubPoint, SUBPIXEL};
use core::num::{NonZeroU32, NonZeroU64};

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

    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`] bits
    /// and `w` below `short_w` (and `2^23`) by 32-bit division: x's and
    /// y's dividends `|x| h + w / 2 <= 4 w h + w / 2` fit 32 bits, so
    /// each quotient is one division (where the long division below took
    /// two and their shifts); depth's quotient is two divisions
    /// ([`depth_digits`]).
    #[inline(always)]
    pub(crate) fn project_digits(&self, p: &[i32; 4], w: NonZeroU32) -> (SubPoint, u32) {
        debug_assert!(w.get() < self.short_w && w.get() as i64 >= W_MIN);
        let half = w.get() / 2;
        // Half a viewport side in sub-pixels is at most 2^15; |x|, |y| <=
        // 4w.
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        // div_round(n hw, w) with the sign of n.
        let round = |n: i32, h: u32| -> i32 {
            let q = ((n.unsigned_abs() * h + half) / w) as i32;
            if n < 0 {
                -q
            } else {
                q
            }
        };
        let x = self.half_w as i32 + round(p[0], hw);
        let y = self.half_h as i32 - round(p[1], hh);
        // div_round((z + w) 65535, 2w) = floor(((z + w) 65535 + w) / w) / 2,
        // and -w <= z <= w: not negative, at most
        // floor((2w 65535 + w) / w) / 2 = 65535, no clamp. (The 64-bit
        // dividend's two divisions took its shifts and leading-zero count
        // besides: 8 instructions a vertex more on the Cortex-M3.)
        let z = depth_digits((p[2] + w.get() as i32) as u32, w);
        (SubPoint::new(x, y), z)
    }

    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`] bits
    /// and `w <` [`RECIP_W`] by `w`'s 16-bit reciprocal ([`Recip16`]), for
    /// ARMv6-M, which has neither a divide instruction nor a 32 x 32 ->
    /// 64-bit multiply: every quotient is three digits of a long division
    /// ([`Recip16::digit`]: two `MULS` and one correction each), with no
    /// 64-bit product, where `w`'s 32-bit reciprocal and its 64-bit
    /// multiply-highs took about 350 instructions a vertex more. The
    /// quotients are the same.
    ///
    /// x's quotient `floor((|x| hw + e) / w)` (`e = floor(w / 2)`,
    /// `|x| <= 4w`, `hw <= 2^15`) from `|x| = a w + b` (`b < w`) and `hw =
    /// c1 2^7 + c0` (`c1 <= 2^8`, `c0 < 2^7`): with `b c1 = d1 w + r1`,
    /// `|x| hw + e = (a hw + d1 2^7) w + (r1 2^7 + b c0 + e)`, the last
    /// term below `w (2^8 + 1)`; so the quotient is `a hw + d1 2^7 +
    /// floor((r1 2^7 + b c0 + e) / w)`. Likewise y. Depth's `floor((c
    /// 65535 + w) / w)` (`c = z + w` in `0..=2w`) as [`depth_digits`]'.
    /// The first digit of each pair is left uncorrected
    /// ([`Recip16::estimate`]): the identities hold for any `d1`, `r1`
    /// with `b c1 = d1 w + r1` (or `c 2^8`), and `r1 < 2w` keeps the last
    /// term below `w 2^9` and `w 514`. Every digit's dividend is below `w
    /// 2^12` (within [`Recip16::digit`]'s range) and, with `w <`
    /// [`RECIP_W`], below `2^32`.
    ///
    /// Where both half sides are below `2^12` and `w` is at most `one_w`,
    /// x's and y's `floor((b h + e) / w)` is one digit (its dividend below
    /// `w 2^12` and `2^32`): ARMv6-M `demo` 6,746,451 to 6,663,049
    /// instructions (vertex 1,060,241 to 976,845). For a vertex inside the
    /// view volume (`inside`: `|x|, |y| <= w`, so `a` is 0 or `b = 0`)
    /// the whole `floor((|x| h + e) / w)` is that one digit, without the
    /// first digit's compare and `a h`: `demo` 6,661,509 to 6,630,124
    /// (vertex 927,437 to 896,052).
    #[inline(always)]
    #[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
    pub(crate) fn project_recip(
        &self,
        p: &[i32; 4],
        w: NonZeroU32,
        inside: bool,
    ) -> (SubPoint, u32) {
        debug_assert!(w.get() < RECIP_W && w.get() as i64 >= W_MIN);
        // w < 2^23: its logarithm from a table, not a search.
        let f = Recip16::new_w23(w);
        let wu = w.get();
        let half = wu / 2;
        // floor((|n| h + half) / w) for |n| <= 4w, h <= 2^15. A function
        // inline, not a closure: LLVM kept the closure out of line (two
        // calls a vertex).
        #[inline(always)]
        fn quotient(f: &Recip16, half: u32, n: i32, h: u32, one: bool) -> u32 {
            // The first digit is 0 for nearly every vertex (inside the
            // view volume, `|n| <= w`): a compare rather than a digit's
            // two products and correction.
            let m = n.unsigned_abs();
            let (a, b) = if m < f.d { (0, m) } else { f.digit(m) };
            // One digit where `one_w` allows it (a small viewport and
            // `w`), else two of 8 and 7 bits.
            let rest = match one {
                true => f.digit(b * h + half).0,
                false => {
                    // The first uncorrected: `r1 < 2w` keeps the second's
                    // dividend below `w 2^9` (and 2^32).
                    let (d1, r1) = f.estimate(b * (h >> 7));
                    let (d0, _) = f.digit((r1 << 7) + b * (h & 127) + half);
                    (d1 << 7) + d0
                }
            };
            a * h + rest
        }
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        let one = wu <= self.one_w();
        let (qx, qy) = match inside && one {
            // `|n| <= w` (inside the view volume: nearly every vertex):
            // `|n| h + half < w (h + 1)`, below `w 2^12` and, for `w <=
            // one_w`, `2^32`, so each quotient is one digit, without the
            // first digit's compare and its product `a h`.
            true => {
                let digit = |n: i32, h: u32| f.digit(n.unsigned_abs() * h + half).0;
                (digit(p[0], hw), digit(p[1], hh))
            }
            false => (
                quotient(&f, half, p[0], hw, one),
                quotient(&f, half, p[1], hh, one),
            ),
        };
        // div_round(n h, w) with the sign of n.
        let signed = |n: i32, q: u32| if n < 0 { -(q as i32) } else { q as i32 };
        let x = self.half_w as i32 + signed(p[0], qx);
        let y = self.half_h as i32 - signed(p[1], qy);
        // -w <= z <= w (`depth_recip`).
        (SubPoint::new(x, y), depth_recip(&f, p[2], wu))
    }

    /// [`project_recip`](Self::project_recip) of a vertex inside the view
    /// volume (outcode 0) with `2^15 <= w <= one_w` (nearly every vertex:
    /// `w` from half a unit up), inline in ARMv6-M's vertex loop; `None`
    /// for any other vertex, which the loop sends out of line
    /// (`vertex::setup`'s `lit_rest`, the whole vertex). Its outcode is then the
    /// constant 0 and its `inside` true, where the loop's one inline path
    /// for every vertex carried both (and the outcode) as values from the
    /// outcode's paths to the packing, and `w`'s reciprocal is
    /// [`Recip16::new_w15`], without `new_w23`'s branch below `2^15`. The
    /// test of the view volume is [`outcode`]'s for ARMv6-M (the three
    /// `w - |v|` or-ed, one sign test), its `|v|` kept for the digits.
    #[inline(always)]
    #[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
    pub(crate) fn project_recip_fast(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        let wu = p[3] as u32;
        // 2^15 <= w <= one_w (W_MIN <= 2^15, one_w < RECIP_W < 2^23).
        if wu.wrapping_sub(1 << 15) >= self.fast_w() {
            return None;
        }
        let m = [p[0], p[1], p[2]].map(|v| v.unsigned_abs());
        // |v| <= w for each, as `w - |v|` below 2^31 (see `outcode`).
        if (wu.wrapping_sub(m[0]) | wu.wrapping_sub(m[1]) | wu.wrapping_sub(m[2])) >> 31 != 0 {
            return None;
        }
        let f = Recip16::new_w15(wu);
        let half = wu / 2;
        // `|n| h + half < w (h + 1)`, below `w 2^12` and, for `w <=
        // one_w`, `2^32`: one digit (as `project_recip`'s).
        let (hw, hh) = (self.half_w as u32, self.half_h as u32);
        let qx = f.digit(m[0] * hw + half).0;
        let qy = f.digit(m[1] * hh + half).0;
        let signed = |n: i32, q: u32| if n < 0 { -(q as i32) } else { q as i32 };
        let x = self.half_w as i32 + signed(p[0], qx);
        let y = self.half_h as i32 - signed(p[1], qy);
        Some((SubPoint::new(x, y), depth_recip(&f, p[2], wu)))
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
    /// division is an instruction, or by `w`'s [`Recip16`] on ARMv6-M) and
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

    /// [`project`](Self::project) of a vertex inside the view volume
    /// (outcode 0: `W_MIN <= w`, `|x|, |y|, |z| <= w`) with `w` below
    /// `short_w`, by 32-bit divisions; `None` for any other vertex. With
    /// `c = v + w` for each coordinate `v` (`0..=2w` inside, and outside
    /// it as an unsigned word, for `w < 2^23`: so the inside test is three
    /// unsigned compares with `2w`):
    ///
    /// * x's `div_round(x hw, w)` (ties away from zero) is `floor((x hw +
    ///   o) / w)` with `o = floor(w / 2)` for `x >= 0` and `floor((w - 1) /
    ///   2)` for `x < 0`; adding `hw w` (`hw` half the width), the screen
    ///   `x = hw + div_round(x hw, w)` is `floor((c hw + o) / w)`, which is
    ///   `floor((2 c hw + w - s) / (2w))` (`s = 1` for `x < 0`, else 0: an
    ///   odd numerator is never a multiple of `2w`), no sign test; the
    ///   numerator is at most `4 w hw + w < 2^32` (`short_w`);
    /// * y likewise, as `2 hh - floor((2 c hh + w - s) / (2w))`;
    /// * depth by two divisions ([`depth_digits`]).
    ///
    /// The same results; about 30 instructions a vertex fewer on the
    /// Cortex-M3 than the outcode and [`project_digits`](Self::project_digits).
    #[inline(always)]
    pub(crate) fn project_fast(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        let w = p[3] as u32;
        // W_MIN <= w < short_w, as one unsigned compare (short_w > W_MIN).
        // The bound masked to 23 bits, which leaves it as it is (`short_w
        // <= 2^23`) but shows the compiler that `w < 2^24`, so that `2w`
        // is not 0 (once per loop: the bound is the loop's; it tested `2w`
        // every vertex).
        let bound = (self.short_w - W_MIN as u32) & ((1 << DIGITS_W_BITS) - 1);
        if w.wrapping_sub(W_MIN as u32) >= bound {
            return None;
        }
        // Not 0 (the compiler sees it through the bound, see above).
        let w2n = NonZeroU32::new(w << 1)?;
        let w2 = w2n.get();
        let c = [p[0], p[1], p[2]].map(|v| (v as u32).wrapping_add(w));
        if c[0] > w2 || c[1] > w2 || c[2] > w2 {
            return None;
        }
        // The width and height in sub-pixels, 2 hw and 2 hh.
        let (tw, th) = ((self.half_w as u32) << 1, (self.half_h as u32) << 1);
        // w - s, for s = 1 where the coordinate is negative.
        let odd = |v: i32| w.wrapping_add((v >> 31) as u32);
        let x = (c[0] * tw + odd(p[0])) / w2n;
        let y = th - (c[1] * th + odd(p[1])) / w2n;
        // 3w - c = 2w - z: one subtraction (from `c`, `3w` took one more).
        let z = depth_by_2w(c[2], w2.wrapping_sub(p[2] as u32), w2n);
        Some((SubPoint::new(x as i32, y as i32), z))
    }

    /// [`project_fast`](Self::project_fast) in 64-bit words, for any `w`
    /// from `W_MIN` up, where a 64-bit division is an instruction
    /// ([`WIDE_DIVISION`]): the same three quotients by `2w` (depth's
    /// `floor(floor((c 65535 + w) / w) / 2)` is `floor((c 65535 + w) /
    /// (2w))`), whose numerators (below `2^50`) cannot overflow; `None`
    /// for a vertex outside the view volume. The general projection's
    /// sign tests, clamp and `w`'s divisor took x86-64 about 20
    /// instructions a vertex more, besides the outcode.
    #[inline(always)]
    pub(crate) fn project_fast_wide(&self, p: &[i32; 4]) -> Option<(SubPoint, u32)> {
        self.project_fast_words(&p.map(i64::from))
    }

    /// [`project_fast_wide`](Self::project_fast_wide) of clip coordinates
    /// given as 64-bit words, each within `i32` (x86-64's common vertex
    /// loop, whose transform sums in 64 bits: from 32-bit words it
    /// sign-extended each again).
    #[inline(always)]
    pub(crate) fn project_fast_words(&self, p: &[i64; 4]) -> Option<(SubPoint, u32)> {
        debug_assert!(p.iter().all(|&v| i32::try_from(v).is_ok()));
        let w = p[3];
        if w < W_MIN {
            return None;
        }
        // At least 2 W_MIN: not zero (the compiler does not see it). The
        // `xor` with zero keeps LLVM's 32-bit test off the three
        // divisions (see `hash`).
        let w2n = NonZeroU64::new(((w as u64) << 1) ^ self.hash())?;
        let w2 = w2n.get();
        // `v + w`, in `0..=2w` inside the view volume (a negative one
        // wraps above it).
        let c = [p[0], p[1], p[2]].map(|v| (v + w) as u64);
        if c[0] > w2 || c[1] > w2 || c[2] > w2 {
            return None;
        }
        let (tw, th) = ((self.half_w as u64) << 1, (self.half_h as u64) << 1);
        // w - s, for s = 1 where the coordinate is negative.
        let odd = |v: i64| (w + (v >> 63)) as u64;
        let x = (c[0] * tw + odd(p[0])) / w2n;
        let y = th - (c[1] * th + odd(p[1])) / w2n;
        let z = (c[2] * 65_535 + w as u64) / w2n;
        debug_assert!(z <= 65_535);
        Some((SubPoint::new(x as i32, y as i32), z as u32))
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

/// Depth `floor((c 65535 + w) / w) / 2` (at most 65,535) of `c = z + w`
/// in `0..=2w`, for `w < 2^23`, by two 32-bit divisions: with `c 2^8 = d1
/// w + r1`, `c 65535 + w = c 2^16 - c + w = d1 2^8 w + (r1 2^8 + w - c)`,
/// and `w - c >= -w`, so the quotient is `d1 2^8 + floor((r1 2^8 + 2w - c)
/// / w) - 1`; every dividend is below `2^32` (`c 2^8 <= w 2^9`, `r1 2^8 +
/// 2w < w 2^8 + 2w`). (Three digits of one division each, the first `c /
/// w`, took a multiply and three instructions more.)
#[inline(always)]
fn depth_digits(c: u32, w: NonZeroU32) -> u32 {
    debug_assert!(w.get() >> DIGITS_W_BITS == 0 && c <= 2 * w.get());
    let c8 = c << 8;
    let (d1, r1) = (c8 / w, c8 % w);
    let d0 = ((r1 << 8) + (2 * w.get() - c)) / w;
    depth_of_digits(d1, d0)
}

/// Depth `floor((c 65535 + w) / (2w))` (at most 65,535) of `c = z + w`
/// in `0..=2w`, given `e = 3w - c` and `w2 = 2w`, for `w <` [`FAST_W`],
/// by two 32-bit divisions by `2w`
/// ([`Viewport::project_fast`]'s divisor for x and y): with `c 2^8 = d1
/// 2w + r1` (`r1 < 2w`), `c 65535 + w = d1 2^8 2w + (r1 2^8 + w - c)`,
/// and `w - c >= -w`, so the depth is `d1 2^8 + floor((r1 2^8 + 3w - c)
/// / (2w)) - 1`, whose dividend is at least `w` and below `515 w <= 2^32`
/// (`c 2^8 <= w 2^9` too); and not negative (where `r1 2^8 + w < c`,
/// `c > w` and `d1 >= 128`). [`depth_digits`]' quotients by `w` took a
/// halving more: one instruction a vertex on the Cortex-M3 and M4F.
#[inline(always)]
fn depth_by_2w(c: u32, e: u32, w2: NonZeroU32) -> u32 {
    let w = w2.get() / 2;
    debug_assert!(w < FAST_W && w2.get() == 2 * w && c <= 2 * w && e == 3 * w - c);
    let c8 = c << 8;
    let (d1, r1) = (c8 / w2, c8 % w2);
    let d0 = ((r1 << 8) + e) / w2;
    let z = (d1 << 8) + d0 - 1;
    debug_assert!(z <= 65_535);
    z
}

/// The bound of `short_w`: [`depth_by_2w`] takes `w` below it, `515 w <
/// 2^32` (below `2^23`, `DIGITS_W_BITS`).
const FAST_W: u32 = u32::MAX / 515;

/// Depth from the two digits of [`depth_digits`] (and of
/// [`Viewport::project_recip`]'s), `d1 2^8 + d0 = floor((c 65535 + w) /
/// w) + 1`: that quotient halved.
#[inline(always)]
fn depth_of_digits(d1: u32, d0: u32) -> u32 {
    // Not negative: the quotient is at least 1.
    let z = ((d1 << 8) + d0 - 1) >> 1;
    debug_assert!(z <= 65_535);
    z
}

/// Depth of `z` by `w`'s [`Recip16`] `f` (`-w <= z <= w`, `w <`
/// [`RECIP_W`]), as [`depth_digits`]' two digits of `c = z + w` in
/// `0..=2w`, the first uncorrected (`estimate`: `r1 < 2w`, `c 2^8 = d1 w +
/// r1` all the same), the second's dividend below `w 514` and so below
/// 2^32 (`RECIP_W`).
#[inline(always)]
fn depth_recip(f: &Recip16, z: i32, w: u32) -> u32 {
    let c = (z + w as i32) as u32;
    let (d1, r1) = f.estimate(c << 8);
    let (d0, _) = f.digit((r1 << 8) + (2 * w - c));
    depth_of_digits(d1, d0)
}

/// [`Viewport::project_digits`] takes `w` below `2^DIGITS_W_BITS`.
const DIGITS_W_BITS: u32 = 23;

/// [`Viewport::project_recip`] takes `w` below this: below `2^23` (its
/// logarithm's table) and such that `514 w < 2^32`, the bound of depth's
/// second dividend after an uncorrected first digit.
const RECIP_W: u32 = u32::MAX / 514;

#[cfg(test)]
mod tests {
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
