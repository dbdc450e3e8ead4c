//! The vertex stage: model-view-projection, lighting, outcodes and the
//! viewport transform, all in fixed point.
//!
//! Per frame (and per draw) the `f32` matrices of the [`Scene`](crate::scene::Scene) are combined,
//! normalized (divided by their largest element: clip coordinates are
//! homogeneous, so this leaves the picture alone but makes it independent
//! of the scene's units, see [`Mat4::normalized`](crate::math::Mat4::normalized)) and converted once to
//! 16.16 ([`FixedMat4`](crate::math::FixedMat4)); the world-space lights are
//! moved into the draw's model space ([`LightSetup`](crate::light::LightSetup), see [`crate::light`]),
//! so per vertex the stage needs only integer multiply-adds: 12 products for
//! the position, a few per light, and 3 quotients by `w` for the
//! perspective divide, which share one divisor (on a 32-bit core, one
//! reciprocal of `w` and three multiply-highs instead of three 64-bit
//! divisions; the quotients are the same). A Cortex-M0+ therefore does no
//! soft-float per vertex.
//!
//! The transform's sums of products are checked for overflow only for a
//! draw whose matrix and mesh could overflow them: the mesh knows its
//! largest coordinate ([`Mesh::extent`](crate::mesh::Mesh::extent)), so [`DrawSetup::new`] decides once
//! per draw whether any vertex could ([`FixedMat4::bounded`](crate::math::FixedMat4::bounded)).
//!
//! # Outcodes and the guard band
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
//! [`MAX_VIEWPORT`] pixels a side, screen coordinates stay within
//! `(K + 1.07) * 4096 * 16 < 2^18` sub-pixels. The rasterizer's set-up then
//! needs at most 2^39 in `i64` and its per-row stepping fits `i32`
//! (denominators below 2^24, columns below 2^15).
//!
//! # Viewport
//!
//! NDC x in `[-1, 1]` maps to `[0, width]` pixels left to right, NDC y in
//! `[-1, 1]` to `[height, 0]` (screen y grows downwards), both rounded to the
//! nearest 1/16 pixel. NDC z in `[-1, 1]` maps to depth `0..=65535`.

mod lambert;
mod setup;

pub use setup::{DrawSetup, VertexError, MAX_LIGHTS};

use crate::math::WDivisor;
use crate::raster::{SubPoint, SUBPIXEL};
use crate::shade::Recip16;
use core::num::{NonZeroU32, NonZeroU64};

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
/// Largest viewport side in pixels.
pub const MAX_VIEWPORT: u32 = 4096;

/// A vertex after the vertex stage, as stored in the frame's vertex buffer:
/// 12 bytes, three words.
///
/// | bytes | 0 | 1..=3 | 4 | 5..=7 | 8 | 9 | 10..=11 |
/// |---|---|---|---|---|---|---|---|
/// | | outcode | x (24-bit signed) | red | y (24-bit signed) | green | blue | depth |
///
/// Every field is read through an accessor: [`x`](Self::x), [`y`](Self::y),
/// [`z`](Self::z), [`outcode`](Self::outcode) and [`color`](Self::color)
/// (the colour was once a public `[u8; 3]` field). The outcode is a
/// byte load, and binning, which reads it first, loads the word it shares
/// with x: x is then one shift, and y likewise one load and one shift.
/// The attribute set-up reads the colour channels from the words that
/// hold y and depth, which it loads anyway, extracting each by a shift:
/// with the colour a byte array beside y's high byte (y then two loads and
/// an `or`), it loaded the nine channel bytes of its three vertices
/// first, spilled them to the stack and reloaded them. This layout took
/// the Cortex-M3's `demo` frame 3,982,907 -> 3,934,041 instructions
/// (binning -4,600, the set-up and raster -40,000). (Of the earlier
/// layouts with the colour in one piece, y and depth in one word, depth's
/// high byte beside the colour, cost the demo frame 0.45 % more than the
/// byte array.)
///
/// x and y are 24-bit signed fields, [`COORD_MIN`]`..=`[`COORD_MAX`]
/// sub-pixels. The guard band bounds every vertex that is drawn without
/// clipping well inside them: its screen coordinates are within
/// `(GUARD_K + 1) * MAX_VIEWPORT / 2 * 16 < 2^18` sub-pixels (the
/// clipper's vertices are within `(GUARD_K + 1.07) * 4096 * 16 < 2^18`).
/// A vertex that must be clipped (`outcode & MUST_CLIP != 0`) stores 0
/// there, and nothing reads them. [`try_new`](Self::try_new) refuses
/// coordinates outside the fields; the vertex stage's own constructor,
/// which relies on the guard band, checks them in debug builds.
#[derive(Clone, Copy, Default, PartialEq, Eq)]
#[repr(C)]
pub struct ScreenVertex {
    /// x (high 24 bits) and the outcode (low 8 bits).
    xo: u32,
    /// y (high 24 bits) and the lit colour's red (low 8 bits).
    yr: u32,
    /// Green (bits 0..8) and blue (bits 8..16) and depth (high 16 bits).
    gbz: u32,
}

/// The size of [`ScreenVertex`]: 12 bytes per slot of the vertex buffer.
const _: () = assert!(core::mem::size_of::<ScreenVertex>() == 12);

/// Bits of [`ScreenVertex`]'s x and y fields.
pub const COORD_BITS: u32 = 24;
/// Smallest screen coordinate a [`ScreenVertex`] holds, in sub-pixels
/// (`-2^23`).
pub const COORD_MIN: i32 = -(1 << (COORD_BITS - 1));
/// Largest screen coordinate a [`ScreenVertex`] holds, in sub-pixels
/// (`2^23 - 1`).
pub const COORD_MAX: i32 = (1 << (COORD_BITS - 1)) - 1;

impl ScreenVertex {
    /// A vertex at `(x, y)` sub-pixels, depth `z`, with outcode `outcode`
    /// and lit colour `color`, for the vertex stage and the clipper, whose
    /// guard band keeps `x` and `y` within [`COORD_MIN`]`..=`[`COORD_MAX`]
    /// ([`Viewport::project`] of a vertex without [`MUST_CLIP`] bits, or of
    /// a clipped polygon's vertex). Checked in debug builds (where every
    /// test runs); outside the range the high bits would be lost.
    #[inline(always)]
    pub(crate) const fn new(x: i32, y: i32, z: u16, outcode: u8, color: [u8; 3]) -> Self {
        debug_assert!(
            COORD_MIN <= x && x <= COORD_MAX && COORD_MIN <= y && y <= COORD_MAX,
            "screen vertex outside the 24-bit fields"
        );
        Self {
            xo: (x as u32) << 8 | outcode as u32,
            yr: (y as u32) << 8 | color[0] as u32,
            gbz: (z as u32) << 16 | (color[2] as u32) << 8 | color[1] as u32,
        }
    }

    /// A vertex at `(x, y)` sub-pixels, depth `z`, with outcode `outcode`
    /// and lit colour `color`, or `None` if `x` or `y` is outside
    /// [`COORD_MIN`]`..=`[`COORD_MAX`] (the fields' 24 bits).
    pub const fn try_new(x: i32, y: i32, z: u16, outcode: u8, color: [u8; 3]) -> Option<Self> {
        if COORD_MIN <= x && x <= COORD_MAX && COORD_MIN <= y && y <= COORD_MAX {
            Some(Self::new(x, y, z, outcode, color))
        } else {
            None
        }
    }

    /// Screen x in sub-pixels (meaningful when `outcode() & MUST_CLIP == 0`).
    #[inline(always)]
    pub const fn x(&self) -> i32 {
        self.xo as i32 >> 8
    }

    /// Screen y in sub-pixels (meaningful when `outcode() & MUST_CLIP == 0`).
    #[inline(always)]
    pub const fn y(&self) -> i32 {
        self.yr as i32 >> 8
    }

    /// Lit colour, 8 bits per channel.
    #[inline(always)]
    pub const fn color(&self) -> [u8; 3] {
        [self.yr as u8, self.gbz as u8, (self.gbz >> 8) as u8]
    }

    /// Replaces the lit colour (flat shading's provoking colour on a
    /// clipped piece).
    #[inline(always)]
    pub(crate) fn set_color(&mut self, color: [u8; 3]) {
        self.yr = self.yr & !0xff | color[0] as u32;
        self.gbz = self.gbz & !0xffff | (color[2] as u32) << 8 | color[1] as u32;
    }

    /// Colour channel `c` (0 red, 1 green, 2 blue) of the word that holds
    /// all three.
    #[inline(always)]
    pub(crate) const fn channel(&self, c: usize) -> u8 {
        match c {
            0 => self.yr as u8,
            _ => (self.gbz >> (8 * (c - 1))) as u8,
        }
    }

    /// Screen position in sub-pixels (meaningful when
    /// `outcode() & MUST_CLIP == 0`).
    #[inline(always)]
    pub const fn xy(&self) -> SubPoint {
        SubPoint::new(self.x(), self.y())
    }

    /// Depth, 0 (near) to 65535 (far).
    #[inline(always)]
    pub const fn z(&self) -> u16 {
        (self.gbz >> 16) as u16
    }

    /// Outcode bits (`OUT_*`).
    #[inline(always)]
    pub const fn outcode(&self) -> u8 {
        self.xo as u8
    }
}

impl core::fmt::Debug for ScreenVertex {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ScreenVertex")
            .field("x", &self.x())
            .field("y", &self.y())
            .field("z", &self.z())
            .field("outcode", &self.outcode())
            .field("color", &self.color())
            .finish()
    }
}

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
    let inside = match cfg!(target_pointer_width = "64") {
        true => inside_wide(p),
        false => inside_words(p),
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

/// The viewport transform of a validated viewport size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Viewport {
    /// Half the width, in sub-pixels.
    half_w: i64,
    /// Half the height, in sub-pixels.
    half_h: i64,
    /// [`Viewport::project_inside`] divides by a `w` below this in 32 bits
    /// ([`Viewport::project_digits`]): below `2^23`, and such that `(4 w h
    /// + w / 2) < 2^32` for either half side `h`.
    short_w: u32,
}

impl Viewport {
    /// A viewport of `width` x `height` pixels, both in `1..=MAX_VIEWPORT`
    /// (checked by the renderer).
    pub fn new(width: u32, height: u32) -> Self {
        debug_assert!((1..=MAX_VIEWPORT).contains(&width) && (1..=MAX_VIEWPORT).contains(&height));
        let (half_w, half_h) = (width * SUBPIXEL as u32 / 2, height * SUBPIXEL as u32 / 2);
        // w (4 h + 1) <= 2^32 - 1 bounds 4 w h + w / 2.
        let short_w = (u32::MAX / (4 * half_w.max(half_h) + 1) + 1).min(1 << DIGITS_W_BITS);
        Self {
            half_w: half_w as i64,
            half_h: half_h as i64,
            short_w,
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
    #[inline(always)]
    pub(crate) fn project_inside(&self, p: &[i32; 4]) -> (SubPoint, u16) {
        if !LONG_DIVISION {
            if !crate::math::SPLIT {
                return self.project(p);
            }
            return match NonZeroU32::new(p[3] as u32) {
                Some(w) if w.get() >> DIGITS_W_BITS == 0 => self.project_recip(p, w),
                _ => self.project_wide(p[0], p[1], p[2], p[3]),
            };
        }
        match NonZeroU32::new(p[3] as u32) {
            Some(w) if w.get() < self.short_w => self.project_digits(p, w),
            _ => self.project_wide(p[0], p[1], p[2], p[3]),
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
    /// two and their shifts); depth's quotient is three digits of one
    /// division each.
    #[inline(always)]
    pub(crate) fn project_digits(&self, p: &[i32; 4], w: NonZeroU32) -> (SubPoint, u16) {
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
        // floor((2w 65535 + w) / w) / 2 = 65535, no clamp. The quotient by
        // three digits, as `project_recip` takes it (see there), each one
        // division: `c = a w + b`, `b 2^8 = d1 w + r1`, then `(r1 2^8 + w
        // - b) / w`; with `w < 2^23` every dividend is below `2^32`. (The
        // 64-bit dividend's two divisions took its shifts and leading-zero
        // count besides: 8 instructions a vertex more on the Cortex-M3.)
        let wu = w.get();
        let c = (p[2] + wu as i32) as u32;
        let (a, b) = (c / w, c % w);
        let (d1, r1) = ((b << 8) / w, (b << 8) % w);
        let d0 = ((r1 << 8) + (wu - b)) / w;
        let z = (a * 65_535 + (d1 << 8) + d0) >> 1;
        debug_assert!(z <= 65_535);
        (SubPoint::new(x, y), z as u16)
    }

    /// [`project`](Self::project) of a vertex without [`MUST_CLIP`] bits
    /// and `w < 2^23` by `w`'s 16-bit reciprocal ([`Recip16`]), for
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
    /// 65535 + w) / w)` (`c = z + w` in `0..=2w`) from `c = a w + b` and
    /// `b 2^8 = d1 w + r1`: `c 65535 + w = (a 65535 + d1 2^8) w + (r1 2^8
    /// + w - b)`, the last term below `w (2^8 + 1)`. Every digit's dividend
    /// is below `w 2^12` (within [`Recip16::digit`]'s range) and, with
    /// `w < 2^23`, below `2^32`.
    #[inline(always)]
    #[cfg_attr(not(microraster_narrow_multiply), allow(dead_code))]
    pub(crate) fn project_recip(&self, p: &[i32; 4], w: NonZeroU32) -> (SubPoint, u16) {
        debug_assert!(w.get() >> DIGITS_W_BITS == 0 && w.get() as i64 >= W_MIN);
        let f = Recip16::new(w);
        let wu = w.get();
        let half = wu / 2;
        // div_round(n h, w) with the sign of n: floor((|n| h + half) / w)
        // for |n| <= 4w, h <= 2^15. A function inline, not a closure: LLVM
        // kept the closure out of line (two calls a vertex).
        #[inline(always)]
        fn round(f: &Recip16, half: u32, n: i32, h: u32) -> i32 {
            let (a, b) = f.digit(n.unsigned_abs());
            let (d1, r1) = f.digit(b * (h >> 7));
            let (d0, _) = f.digit((r1 << 7) + b * (h & 127) + half);
            let q = (a * h + (d1 << 7) + d0) as i32;
            if n < 0 {
                -q
            } else {
                q
            }
        }
        let x = self.half_w as i32 + round(&f, half, p[0], self.half_w as u32);
        let y = self.half_h as i32 - round(&f, half, p[1], self.half_h as u32);
        // -w <= z <= w: c in 0..=2w, and the quotient at most 2 * 65535 + 1.
        let c = (p[2] + wu as i32) as u32;
        let (a, b) = f.digit(c);
        let (d1, r1) = f.digit(b << 8);
        let (d0, _) = f.digit((r1 << 8) + (wu - b));
        let z = (a * 65_535 + (d1 << 8) + d0) >> 1;
        debug_assert!(z <= 65_535);
        (SubPoint::new(x, y), z as u16)
    }

    /// Runs the vertex stage on one vertex.
    #[inline(always)]
    pub fn screen_vertex(&self, v: &ClipVertex) -> ScreenVertex {
        let color = [v.color[0] as u8, v.color[1] as u8, v.color[2] as u8];
        self.screen_vertex_lit(&v.pos, || color)
    }

    /// [`screen_vertex`](Self::screen_vertex) of the vertex at clip-space
    /// position `pos` whose lit colour `color` gives, asked for after the
    /// projection: the vertex stage's loop then keeps neither the colour
    /// nor the lighting's constants in registers (or on the stack) across
    /// the divisions.
    #[inline(always)]
    pub(crate) fn screen_vertex_lit(
        &self,
        pos: &[i32; 4],
        color: impl FnOnce() -> [u8; 3],
    ) -> ScreenVertex {
        let outcode = outcode(pos);
        let (p, z) = if outcode & MUST_CLIP == 0 {
            self.project_inside(pos)
        } else {
            (SubPoint::default(), 0)
        };
        // Within the 24-bit fields: `p` is 0 for a vertex that must be
        // clipped, otherwise inside the guard band (`|x|, |y| <= K w`), so
        // within `(K + 1) * 2^15 < 2^18` sub-pixels.
        ScreenVertex::new(p.x, p.y, z, outcode, color())
    }
}

/// Whether the vertex stage divides by `w` through 32-bit divisions
/// ([`Viewport::project_inside`]): on 32-bit cores with a 32 x 32 -> 64-bit
/// multiply, which have a divide instruction too (ARMv7-M, ARMv8-M
/// Mainline, RISC-V `rv32im`). ARMv6-M, whose division is a library call,
/// keeps `w`'s 32-bit reciprocal; 64-bit targets their 64-bit division.
const LONG_DIVISION: bool = cfg!(all(
    not(microraster_narrow_multiply),
    not(target_pointer_width = "64")
));

/// [`Viewport::project_digits`] takes `w` below `2^DIGITS_W_BITS`.
const DIGITS_W_BITS: u32 = 23;

/// `n / d` rounded to nearest (ties away from zero), for `d > 0`: the
/// rounding of every quotient of the vertex and attribute set-up (which
/// compute it through [`Divisor`]; the tests check them against this).
#[cfg(test)]
pub(crate) fn div_round(n: i64, d: i64) -> i64 {
    if n >= 0 {
        (n + d / 2) / d
    } else {
        -((-n + d / 2) / d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field comes back out of a [`ScreenVertex`] unchanged: x and
    /// y over their whole 24-bit range (every 97th value, the extremes and
    /// the values around 0 and the byte boundaries), depth, outcode and
    /// each colour channel over all of theirs, and the extremes of each
    /// field beside the extremes of the others.
    #[test]
    fn screen_vertex_round_trips_every_field() {
        let check = |x: i32, y: i32, z: u16, o: u8, c: [u8; 3]| {
            let v = ScreenVertex::new(x, y, z, o, c);
            assert_eq!(
                (v.x(), v.y(), v.xy(), v.z(), v.outcode(), v.color()),
                (x, y, SubPoint::new(x, y), z, o, c),
                "{x} {y} {z} {o} {c:?}"
            );
            assert_eq!(ScreenVertex::try_new(x, y, z, o, c), Some(v));
        };
        for i in (0..1u32 << COORD_BITS).step_by(97) {
            let x = COORD_MIN + i as i32;
            let y = COORD_MAX - i as i32;
            let c = [i as u8, (i >> 5) as u8, (i >> 12) as u8];
            check(x, y, i.wrapping_mul(40_503) as u16, (i >> 3) as u8, c);
        }
        let mut coords = [
            COORD_MIN,
            COORD_MIN + 1,
            COORD_MAX - 1,
            COORD_MAX,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
        ];
        for (k, b) in [(4, 0), (6, 8), (8, 16), (10, 18)] {
            coords[k] = 1 << b;
            coords[k + 1] = -(1 << b) - 1;
        }
        for x in coords {
            for y in coords {
                for z in [0, 1, 255, 256, 32_768, u16::MAX] {
                    for o in [0, 1, 0x7f, 0x80, u8::MAX] {
                        for c in [[0; 3], [255; 3], [255, 0, 255], [0, 255, 0]] {
                            check(x, y, z, o, c);
                        }
                    }
                }
            }
        }
        assert_eq!(
            ScreenVertex::default(),
            ScreenVertex::new(0, 0, 0, 0, [0; 3])
        );
        assert_eq!(core::mem::size_of::<ScreenVertex>(), 12);
    }

    /// Coordinates outside the 24-bit fields are refused by `try_new`.
    #[test]
    fn screen_vertex_refuses_coordinates_outside_its_fields() {
        for bad in [
            COORD_MIN - 1,
            COORD_MAX + 1,
            i32::MIN,
            i32::MAX,
            1 << 24,
            -(1 << 24),
        ] {
            assert_eq!(ScreenVertex::try_new(bad, 0, 0, 0, [0; 3]), None, "{bad}");
            assert_eq!(ScreenVertex::try_new(0, bad, 0, 0, [0; 3]), None, "{bad}");
        }
    }

    /// And the vertex stage's constructor stops on them in debug builds.
    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "outside the 24-bit fields")]
    fn screen_vertex_checks_its_fields_in_debug_builds() {
        let _ = ScreenVertex::new(COORD_MAX + 1, 0, 0, 0, [0; 3]);
    }

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

    #[test]
    fn outcodes_flag_each_half_space() {
        let w = 1 << 16;
        assert_eq!(outcode(&[0, 0, 0, w]), 0);
        assert_eq!(outcode(&[-2 * w, 0, 0, w]), OUT_LEFT);
        assert_eq!(outcode(&[0, 5 * w, 0, w]), OUT_TOP | OUT_GUARD);
        assert_eq!(outcode(&[0, 0, -2 * w, w]), OUT_NEAR);
        assert_eq!(outcode(&[0, 0, 0, -w]) & OUT_W, OUT_W);
    }

    /// The tests of a vertex inside the view volume (32- and 64-bit) agree
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
        }
    }

    #[test]
    fn div_round_rounds_half_away_from_zero() {
        assert_eq!(div_round(5, 2), 3);
        assert_eq!(div_round(-5, 2), -3);
        assert_eq!(div_round(4, 3), 1);
        assert_eq!(div_round(-4, 3), -1);
    }

    /// `project_inside` (32-bit divisions for `w < 2^23`)
    /// against `project`, for vertices without `MUST_CLIP` bits: `w` from
    /// `W_MIN` to beyond 2^23, coordinates up to the guard band, the
    /// extremes of each.
    #[test]
    fn projection_inside_matches_project() {
        let mut next = crate::testing::rng();
        for (width, height) in [(320, 240), (4096, 4096), (1, 4096), (4096, 3001)] {
            let vp = Viewport::new(width, height);
            for i in 0..200_000u64 {
                let w = match i % 8 {
                    0 => W_MIN + next(16) as i64,
                    1 => (1 << DIGITS_W_BITS) - 1 - next(4) as i64,
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
                let p = [c(g), c(g), c(w), w];
                assert_eq!(outcode(&p) & MUST_CLIP, 0, "{p:?}");
                assert_eq!(vp.project_inside(&p), vp.project(&p), "{p:?}");
                let nz = NonZeroU32::new(w as u32).unwrap();
                if nz.get() < vp.short_w {
                    assert_eq!(vp.project_digits(&p, nz), vp.project(&p), "{p:?}");
                }
                if w >> DIGITS_W_BITS == 0 {
                    assert_eq!(vp.project_recip(&p, nz), vp.project(&p), "{p:?}");
                }
            }
        }
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
