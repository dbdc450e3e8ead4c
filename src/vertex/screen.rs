//! The vertex stage's output: [`ScreenVertex`], packed in three words.

use crate::raster::SubPoint;

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
    /// ([`Viewport::project`](super::Viewport::project) of a vertex without [`MUST_CLIP`](super::MUST_CLIP) bits, or of
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
}
