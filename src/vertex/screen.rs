//! The vertex stage's output: [`ScreenVertex`], packed in three words.

use crate::raster::SubPoint;

/// A vertex after the vertex stage, as stored in the frame's vertex buffer:
/// 12 bytes, three words.
///
/// | bits | 0..8 | 8..32 | 32..40 | 40 | 41..64 | 64..72 | 72..80 | 80..96 |
/// |---|---|---|---|---|---|---|---|---|
/// | | outcode | x (24-bit signed) | red | [`interior`](Self::interior) | y (23-bit signed) | green | blue | depth |
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
/// x and y are signed fields of 24 and 23 bits, both limited to
/// [`COORD_MIN`]`..=`[`COORD_MAX`] sub-pixels ([`COORD_BITS`], 23). The guard band bounds every vertex that is drawn without
/// clipping well inside them: its screen coordinates are within
/// `(GUARD_K + 1) * MAX_VIEWPORT / 2 * 16 < 2^18` sub-pixels (the
/// clipper's vertices are within `(GUARD_K + 1.07) * 4096 * 16 < 2^18`).
/// A vertex that must be clipped (`outcode & MUST_CLIP != 0`) stores 0
/// there, and nothing reads them. [`try_new`](Self::try_new) refuses
/// coordinates outside the fields; the vertex stage's own constructor,
/// which relies on the guard band, checks them in debug builds.
///
/// The bit below y, [`interior`](Self::interior), is made from the
/// colour and depth by every constructor, once per vertex: it says that
/// the vertex's values are far enough from the ends of their ranges that a
/// triangle of three such vertices needs no clamp at its span starts (see
/// [`interior`](Self::interior)). A per-triangle test of the same values
/// cost the Gouraud set-up as much as the clamps it spared; this bit is
/// made once per vertex, where the values are in registers, and the set-up
/// ands three words it loads anyway.
#[derive(Clone, Copy, Default, PartialEq, Eq)]
#[repr(C)]
pub struct ScreenVertex {
    /// x (high 24 bits) and the outcode (low 8 bits).
    xo: u32,
    /// y (high 23 bits), the [`interior`](Self::interior) bit (bit 8)
    /// and the lit colour's red (low 8 bits).
    yr: u32,
    /// Green (bits 0..8) and blue (bits 8..16) and depth (high 16 bits).
    gbz: u32,
}

/// The size of [`ScreenVertex`]: 12 bytes per slot of the vertex buffer.
const _: () = assert!(core::mem::size_of::<ScreenVertex>() == 12);

/// Bits of [`ScreenVertex`]'s y field, which bound x too (x has 24).
pub const COORD_BITS: u32 = 23;
/// Smallest screen coordinate a [`ScreenVertex`] holds, in sub-pixels
/// (`-2^22`).
pub const COORD_MIN: i32 = -(1 << (COORD_BITS - 1));
/// Largest screen coordinate a [`ScreenVertex`] holds, in sub-pixels
/// (`2^22 - 1`).
pub const COORD_MAX: i32 = (1 << (COORD_BITS - 1)) - 1;

/// Where [`ScreenVertex::interior`] is kept in the word of y and red.
const INTERIOR: u32 = 1 << 8;

/// Whether the vertex stage makes [`ScreenVertex::interior`] and the
/// Gouraud span starts use it (the build script's `microraster_interior`):
/// everywhere but in builds optimised for size (the OLED firmware's,
/// where it took 172 bytes: the test in both vertex loops, the flag in
/// the set-up). The Cortex-M4F, left out while the bit cost its vertex
/// stage more than it spared the span starts, takes it since they test
/// the flag once a pair: `demo` 3,352,005 -> 3,293,360 instructions (the
/// vertex stage +29 K, raster and shade -88 K), `rock` 2,818,161 ->
/// 2,748,045. On the others:
/// x86-64 `demo` 4,317,453 -> 4,258,981, `rock` 3,584,878 -> 3,520,426;
/// Cortex-M3 `demo` 3,904,200 -> 3,856,708, `rock` 3,207,716 ->
/// 3,158,427; ARMv6-M `demo` 7,759,390 -> 7,716,260, `rock` 6,421,527 ->
/// 6,367,693.
pub(crate) const INTERIOR_STARTS: bool = cfg!(microraster_interior);

/// [`ScreenVertex::interior`] of a vertex with depth `z` and colour `c`:
/// depth in `2..=65533` and every channel in `1..=254` (never, without
/// [`INTERIOR_STARTS`]).
#[inline(always)]
const fn interior(z: u16, c: [u8; 3]) -> bool {
    depth_interior(z as u32) & channels_interior(c)
}

/// The depth half of [`interior`]: `z` (at most 65,535) in `2..=65533`,
/// as one subtraction and one unsigned compare (never, without
/// [`INTERIOR_STARTS`]). A word, not a `u16`: the projection's depth is
/// a word known to be below 2^16, which as a `u16` the Cortex-M cores
/// zero-extended again for this test (a `UXTH` a vertex).
#[inline(always)]
const fn depth_interior(z: u32) -> bool {
    INTERIOR_STARTS && z.wrapping_sub(2) <= 65_531
}

/// The colour half of [`interior`]: every channel of `c` in `1..=254`,
/// each as one subtraction and one unsigned compare. (The channels as the
/// bytes of one word, tested together by carries, took the x86-64 vertex
/// stage 8,000 instructions more on `demo`.) The vertex stage's Lambert
/// loops test n·l against an interval instead (`Lambert::interior_ndotl`).
#[inline(always)]
pub(crate) const fn channels_interior(c: [u8; 3]) -> bool {
    (c[0].wrapping_sub(1) <= 253) & (c[1].wrapping_sub(1) <= 253) & (c[2].wrapping_sub(1) <= 253)
}

/// A lit colour and whether it may carry the [`interior`](ScreenVertex::interior)
/// bit as far as the colour goes (`inside`), as one word laid out for
/// [`ScreenVertex::with_color_word`]: red in bits 0..8, `inside` in bit 8
/// (where the word of y and red keeps the bit), green in bits 16..24 and
/// blue in 24..32 (the word of depth, green and blue, shifted down by 16).
#[inline(always)]
pub(crate) const fn color_word(color: [u8; 3], inside: bool) -> u32 {
    let inside = if inside { COLOR_WORD_INTERIOR } else { 0 };
    color[0] as u32 | inside | (color[1] as u32) << 16 | (color[2] as u32) << 24
}

/// The bit of a [`color_word`] that holds the colour's half of the
/// [`interior`](ScreenVertex::interior) bit.
pub(crate) const COLOR_WORD_INTERIOR: u32 = 1 << 8;

impl ScreenVertex {
    /// A vertex at `(x, y)` sub-pixels, depth `z`, with outcode `outcode`
    /// and lit colour `color`, for the vertex stage and the clipper, whose
    /// guard band keeps `x` and `y` within [`COORD_MIN`]`..=`[`COORD_MAX`]
    /// ([`Viewport::project`](super::Viewport::project) of a vertex without [`MUST_CLIP`](super::MUST_CLIP) bits, or of
    /// a clipped polygon's vertex). Checked in debug builds (where every
    /// test runs); outside the range the high bits would be lost.
    #[inline(always)]
    pub(crate) const fn new(x: i32, y: i32, z: u16, outcode: u8, color: [u8; 3]) -> Self {
        Self::with_interior(x, y, z as u32, outcode, color, interior(z, color))
    }

    /// [`ScreenVertex::new`] of a vertex whose colour the caller has
    /// tested already: `color_inside` says that every channel of `color`
    /// is in `1..=254` (the vertex stage's Lambert loops know it from n·l,
    /// in two instructions), or is false for a vertex that should not
    /// carry the [`interior`](Self::interior) bit (of a draw that is not
    /// Gouraud shaded: only the Gouraud span starts read it). The depth is
    /// tested here; it is a word at most 65,535 (the projection's, see
    /// `depth_interior`), checked in debug builds.
    #[inline(always)]
    pub(crate) const fn new_tested(
        x: i32,
        y: i32,
        z: u32,
        outcode: u8,
        color: [u8; 3],
        color_inside: bool,
    ) -> Self {
        let inside = color_inside & depth_interior(z);
        Self::with_interior(x, y, z, outcode, color, inside)
    }

    /// The word of x and the outcode of a vertex with outcode 0, written
    /// alone: ARMv6-M's vertex loop stores it before the colour, so that
    /// x is not held across it; [`set_lit_word`](Self::set_lit_word) then writes
    /// the rest, as [`new_tested`](Self::new_tested) would.
    #[inline(always)]
    pub(crate) fn set_x(&mut self, x: i32) {
        debug_assert!((COORD_MIN..=COORD_MAX).contains(&x));
        self.xo = (x as u32) << 8;
    }

    /// [`ScreenVertex::new_tested`] of a vertex whose colour and its
    /// half of the [`interior`](Self::interior) bit come as one
    /// [`color_word`]: the vertex stage's Lambert loops, which look the
    /// word up in a table of the draw's colours by n·l
    /// (`vertex::lit_work`'s `ColorTable`), so that per vertex the colour
    /// is one load, one mask and one shift into the two words it shares
    /// with y and depth. The depth is tested here, as in `new_tested`.
    #[inline(always)]
    pub(crate) const fn with_color_word(x: i32, y: i32, z: u32, outcode: u8, word: u32) -> Self {
        debug_assert!(
            COORD_MIN <= x && x <= COORD_MAX && COORD_MIN <= y && y <= COORD_MAX,
            "screen vertex outside the coordinate fields"
        );
        Self::with_xo_color_word(Self::xo_word(x, outcode), y, z, word)
    }

    /// The word of x and the outcode of a vertex at `x` sub-pixels with
    /// outcode `outcode`, for [`with_xo_color_word`](Self::with_xo_color_word).
    #[inline(always)]
    pub(crate) const fn xo_word(x: i32, outcode: u8) -> u32 {
        debug_assert!(
            COORD_MIN <= x && x <= COORD_MAX,
            "screen vertex outside the coordinate fields"
        );
        (x as u32) << 8 | outcode as u32
    }

    /// [`with_color_word`](Self::with_color_word) of the word of x and
    /// the outcode `xo` ([`xo_word`](Self::xo_word)): the Cortex-M3's and
    /// M4F's vertex loop makes that word on each of its two paths (the
    /// vertex inside the view volume, the other), which then meet with
    /// one value for x and the outcode rather than two.
    #[inline(always)]
    pub(crate) const fn with_xo_color_word(xo: u32, y: i32, z: u32, word: u32) -> Self {
        debug_assert!(
            COORD_MIN <= y && y <= COORD_MAX,
            "screen vertex outside the coordinate fields"
        );
        debug_assert!(z <= 65_535, "screen vertex depth beyond 16 bits");
        // Red and the colour's half of the bit, the bit then cleared where
        // the depth is not interior: one conditional clear of the packed
        // word, where the mask of red with or without the bit (0xff or
        // 0x1ff) took the Cortex-M cores a register and an instruction
        // more a vertex (M3 `demo` vertex stage 271,356 -> 269,308,
        // ARMv6-M 699,741 -> 695,669).
        let yr = (y as u32) << 9 | (word & (0xff | COLOR_WORD_INTERIOR));
        Self {
            xo,
            yr: match depth_interior(z) {
                true => yr,
                false => yr & !INTERIOR,
            },
            gbz: z << 16 | word >> 16,
        }
    }

    /// A [`color_word`] `word` for [`with_wide_word`](Self::with_wide_word):
    /// the word in the low 32 bits, its red and interior bit (its low 9
    /// bits) again in the top 9.
    #[inline(always)]
    pub(crate) const fn wide_word(word: u32) -> u64 {
        ((word & (0xff | COLOR_WORD_INTERIOR)) as u64) << 55 | word as u64
    }

    /// [`with_color_word`](Self::with_color_word) (outcode 0) of a
    /// [`wide_word`](Self::wide_word): y's word is `y 2^9` and the top 9
    /// bits, depth's `z 2^16` and green and blue (bits 16 to 31), a double
    /// shift each (`SHLD`) without masking red out of the colour word.
    #[inline(always)]
    pub(crate) fn with_wide_word(x: i32, y: i32, z: u32, word: u64) -> Self {
        debug_assert!(
            (COORD_MIN..=COORD_MAX).contains(&x) && (COORD_MIN..=COORD_MAX).contains(&y),
            "screen vertex outside the coordinate fields"
        );
        debug_assert!(z <= 65_535, "screen vertex depth beyond 16 bits");
        // y within 23 bits (any sign): its word's bits are the low 32 of
        // the 64-bit shift.
        let mut yr = ((y as u32 as u64) << 9 | word >> 55) as u32;
        // Nearly every depth is interior: the bit cleared on a branch
        // hinted rare, where the select copied and masked the word every
        // vertex.
        if !depth_interior(z) {
            crate::hint::cold();
            yr &= !INTERIOR;
        }
        Self {
            xo: Self::xo_word(x, 0),
            yr,
            gbz: z << 16 | (word as u32) >> 16,
        }
    }

    /// The words of y, depth and the colour of
    /// [`with_color_word`](Self::with_color_word), after
    /// [`set_x`](Self::set_x).
    #[inline(always)]
    pub(crate) fn set_lit_word(&mut self, y: i32, z: u32, word: u32) {
        let v = Self::with_color_word(0, y, z, 0, word);
        self.yr = v.yr;
        self.gbz = v.gbz;
    }

    /// [`ScreenVertex::new`] of a clipped polygon's vertex: outcode 0, and
    /// its [`interior`](Self::interior) bit clear, so that the pieces of a
    /// clipped triangle keep their clamps. Clipping is rare (the `demo`
    /// frame clips nothing), and the bit's test there took 52 bytes of the
    /// OLED firmware's flash.
    #[inline(always)]
    pub(crate) const fn new_clipped(x: i32, y: i32, z: u16, color: [u8; 3]) -> Self {
        Self::with_interior(x, y, z as u32, 0, color, false)
    }

    /// [`ScreenVertex::new`] with the [`interior`](Self::interior) bit
    /// `inside` (which only `interior` may set), for a depth `z` of at most
    /// 65,535.
    #[inline(always)]
    const fn with_interior(
        x: i32,
        y: i32,
        z: u32,
        outcode: u8,
        color: [u8; 3],
        inside: bool,
    ) -> Self {
        debug_assert!(
            COORD_MIN <= x && x <= COORD_MAX && COORD_MIN <= y && y <= COORD_MAX,
            "screen vertex outside the coordinate fields"
        );
        debug_assert!(z <= 65_535, "screen vertex depth beyond 16 bits");
        let inside = if inside { INTERIOR } else { 0 };
        Self {
            xo: (x as u32) << 8 | outcode as u32,
            yr: (y as u32) << 9 | inside | color[0] as u32,
            gbz: z << 16 | (color[2] as u32) << 8 | color[1] as u32,
        }
    }

    /// A vertex at `(x, y)` sub-pixels, depth `z`, with outcode `outcode`
    /// and lit colour `color`, or `None` if `x` or `y` is outside
    /// [`COORD_MIN`]`..=`[`COORD_MAX`] (y's field has 23 bits).
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
        self.yr as i32 >> 9
    }

    /// The words that hold x and y, as they are: x times 2^8 plus the
    /// outcode, and y times 2^9 plus the interior bit and red (so `x()`
    /// is the first `>> 8` and `y()` the second `>> 9`). For binning's
    /// common loop, which culls and bounds a triangle whose outcodes are
    /// 0 from them without shifting each coordinate out.
    #[inline(always)]
    pub(crate) const fn xy_words(&self) -> (i32, i32) {
        (self.xo as i32, self.yr as i32)
    }

    /// Whether depth is in `2..=65533` and every colour channel in
    /// `1..=254` (always false in the builds that do not use it, those
    /// optimised for size): a triangle whose three vertices have this bit set has
    /// every covered pixel centre's plane values inside their ranges, so
    /// its span starts need no clamp (the Gouraud set-up's start).
    ///
    /// Why: a span starts at a covered centre, inside the (closed)
    /// triangle, where the exact interpolant of each attribute lies between
    /// its smallest and largest vertex value. The plane's value there
    /// (exact in `i32` unless the set-up is wide, which keeps its clamps)
    /// is within `(|dx| + |dy|) / 32 + 1` units of the exact one, `dx`
    /// and `dy` the centre's offset from vertex 0 in sub-pixels (the
    /// gradients' rounding and the floor, see `shade::plane::Plane`): with
    /// vertices within 2^18 sub-pixels of the origin (the guard band) and
    /// centres within 2^16 (`MAX_VIEWPORT`), at most `2 (2^18 + 2^16) /
    /// 32 + 1 = 20,481` units. Depth has 14 fraction bits, so 2 depth
    /// units are 32,768 units, more than the bound: a depth of `2..=65533`
    /// at every vertex keeps the start inside `Z_LO..=Z_HI`, the values
    /// that round to `0..=65535`. Colour has 16 fraction bits, so 1 unit
    /// (65,536) covers it: channels of `1..=254` keep it inside
    /// `C_LO..=C_HI`. Inside, the clamp leaves the value as it is, so the
    /// start without it is the same, bit for bit.
    #[inline(always)]
    pub const fn interior(&self) -> bool {
        self.yr & INTERIOR != 0
    }

    /// Whether all three vertices are [`interior`](Self::interior): the
    /// set-up ands the words that hold the bit. Only where the vertex
    /// stage makes the bit (`INTERIOR_STARTS`).
    #[cfg(microraster_interior)]
    #[inline(always)]
    pub(crate) fn all_interior(v: [&Self; 3]) -> bool {
        v[0].yr & v[1].yr & v[2].yr & INTERIOR != 0
    }

    /// Lit colour, 8 bits per channel.
    #[inline(always)]
    pub const fn color(&self) -> [u8; 3] {
        [self.yr as u8, self.gbz as u8, (self.gbz >> 8) as u8]
    }

    /// Replaces the lit colour (flat shading's provoking colour on a
    /// clipped piece) and clears the [`interior`](Self::interior) bit,
    /// which only flat pieces, which never read it, come here with. (Where
    /// the bit is never made, only the colour: a wider mask cost the
    /// size-optimised OLED firmware 12 bytes.)
    #[inline(always)]
    pub(crate) fn set_color(&mut self, color: [u8; 3]) {
        let keep = match INTERIOR_STARTS {
            true => !(0xff | INTERIOR),
            false => !0xff,
        };
        self.yr = self.yr & keep | color[0] as u32;
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
            .field("interior", &self.interior())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field comes back out of a [`ScreenVertex`] unchanged: x and
    /// y over their whole range (every 97th value, the extremes and
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
            let inside = INTERIOR_STARTS
                && (2..=65_533).contains(&z)
                && c.iter().all(|c| (1..=254).contains(c));
            assert_eq!(v.interior(), inside, "{z} {c:?}");
            assert_eq!(ScreenVertex::all_interior([&v; 3]), inside);
            // Replacing the colour clears the bit; so does the clipper.
            let mut w = ScreenVertex::new(x, y, z, o, [128; 3]);
            w.set_color(c);
            let clipped = ScreenVertex::new_clipped(x, y, z, c);
            for w in [w, clipped] {
                assert_eq!((w.x(), w.y(), w.z(), w.color()), (x, y, z, c));
                assert!(!w.interior());
            }
            assert_eq!(w.outcode(), o);
            assert_eq!(clipped.outcode(), 0);
            // The Lambert loops' colour word packs as `new_tested`.
            for inside in [false, true] {
                let word = color_word(c, inside);
                let want = ScreenVertex::new_tested(x, y, z as u32, o, c, inside);
                let v = ScreenVertex::with_color_word(x, y, z as u32, o, word);
                assert_eq!(v, want, "{x} {y} {z} {o} {c:?} {inside}");
                let mut s = ScreenVertex::default();
                s.set_x(x);
                s.set_lit_word(y, z as u32, word);
                let want = ScreenVertex::new_tested(x, y, z as u32, 0, c, inside);
                assert_eq!(s, want, "{x} {y} {z} {c:?} {inside}");
                // 64-bit hosts' table words pack the same.
                let v = ScreenVertex::with_wide_word(x, y, z as u32, ScreenVertex::wide_word(word));
                assert_eq!(v, want, "{x} {y} {z} {c:?} {inside}");
            }
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
                for z in [0, 1, 2, 255, 256, 32_768, 65_533, 65_534, u16::MAX] {
                    for o in [0, 1, 0x7f, 0x80, u8::MAX] {
                        for c in [
                            [0; 3],
                            [255; 3],
                            [255, 0, 255],
                            [0, 255, 0],
                            [1, 254, 1],
                            [254, 1, 254],
                            [1, 1, 0],
                            [254, 255, 254],
                            [128, 1, 255],
                        ] {
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

    /// Coordinates outside the fields are refused by `try_new`.
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
    #[should_panic(expected = "outside the coordinate fields")]
    fn screen_vertex_checks_its_fields_in_debug_builds() {
        let _ = ScreenVertex::new(COORD_MAX + 1, 0, 0, 0, [0; 3]);
    }
}
