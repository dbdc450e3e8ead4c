//! A panel's wire format: big-endian Rgb565 pixels, and the window
//! commands that precede them.
//!
//! The SPI panels of small boards (ST7789, ILI9341, ST7735, GC9A01, …)
//! take Rgb565 pixels in 16-bit big-endian order, high byte first, after a
//! window set by `CASET`, `RASET` and `RAMWR`. A little-endian MCU that
//! renders [`Rgb565`] holds every pixel low byte first, so a driver that
//! sends bytes swaps each pixel before sending it. A renderer of
//! [`Rgb565Be`] instead draws the tile in the wire's byte order directly:
//! [`TileBuffer::pack`](crate::TileBuffer::pack) then gives the tile's
//! pixels as one block that a DMA channel sends as it is (see
//! [`wire_bytes`]), and [`Window`] gives the commands that go before it.

use crate::shader::Dither;
use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{PixelColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{IntoStorage, Point};
use embedded_graphics::primitives::Rectangle;

/// An Rgb565 colour stored in the panel's byte order: its two bytes in
/// memory are the colour's 16 bits big-endian (red and the top of green
/// first), whatever the MCU's own byte order.
///
/// It is a colour like [`Rgb565`] for the renderer (`Renderer<Rgb565Be,
/// TW, TH>`), with the same conversions, so a frame drawn in `Rgb565Be` is
/// the frame drawn in `Rgb565`, pixel for pixel, with each pixel's bytes in
/// wire order. The conversion from [`Rgb888`] costs one byte swap (a single
/// instruction, `rev16`, on every Cortex-M) beside `Rgb565`'s.
///
/// The type is `#[repr(transparent)]` over a `u16` that holds the bytes:
/// `n` pixels are `2 n` bytes in wire order, aligned to 2, with no
/// padding. That is what [`wire_bytes`] hands to a DMA channel.
///
/// ```
/// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
/// use microraster::sink::Rgb565Be;
///
/// let c = Rgb565Be::from(Rgb565::new(31, 0, 1)); // 0xF801
/// assert_eq!(c.to_be_bytes(), [0xF8, 0x01]);
/// assert_eq!(c.value(), 0xF801);
/// assert_eq!(Rgb565::from(c), Rgb565::new(31, 0, 1));
/// assert_eq!(Rgb565Be::RED.to_be_bytes(), [0xF8, 0x00]);
/// ```
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct Rgb565Be(u16);

impl Rgb565Be {
    /// The colour of 5-bit red, 6-bit green and 5-bit blue components;
    /// larger values lose their high bits, as in [`Rgb565::new`].
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        let v = ((r as u16 & 0x1f) << 11) | ((g as u16 & 0x3f) << 5) | (b as u16 & 0x1f);
        Self::from_value(v)
    }

    /// The colour whose Rgb565 bits are `value` (red in the top five).
    pub const fn from_value(value: u16) -> Self {
        Self(value.to_be())
    }

    /// The colour's Rgb565 bits (red in the top five), as
    /// [`Rgb565`]'s `into_storage` gives them.
    pub const fn value(self) -> u16 {
        u16::from_be(self.0)
    }

    /// The colour whose two bytes on the wire are `bytes`.
    pub const fn from_be_bytes(bytes: [u8; 2]) -> Self {
        Self(u16::from_ne_bytes(bytes))
    }

    /// The colour's two bytes as they are in memory and on the wire: the
    /// high byte of [`value`](Self::value) first.
    pub const fn to_be_bytes(self) -> [u8; 2] {
        self.0.to_ne_bytes()
    }
}

impl core::fmt::Debug for Rgb565Be {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Rgb565Be({:#06x})", self.value())
    }
}

impl PixelColor for Rgb565Be {
    type Raw = RawU16;
}

impl From<Rgb565> for Rgb565Be {
    #[inline(always)]
    fn from(c: Rgb565) -> Self {
        Self::from_value(c.into_storage())
    }
}

impl From<Rgb565Be> for Rgb565 {
    #[inline(always)]
    fn from(c: Rgb565Be) -> Self {
        Rgb565::from(RawU16::new(c.value()))
    }
}

impl From<Rgb888> for Rgb565Be {
    #[inline(always)]
    fn from(c: Rgb888) -> Self {
        Rgb565::from(c).into()
    }
}

impl From<Rgb565Be> for Rgb888 {
    #[inline(always)]
    fn from(c: Rgb565Be) -> Self {
        Rgb565::from(c).into()
    }
}

impl From<RawU16> for Rgb565Be {
    #[inline(always)]
    fn from(raw: RawU16) -> Self {
        Rgb565::from(raw).into()
    }
}

/// The colour's Rgb565 bits (red in the top five), not its wire bytes: what
/// an embedded-graphics driver's `into_storage` expects.
impl From<Rgb565Be> for RawU16 {
    #[inline(always)]
    fn from(c: Rgb565Be) -> Self {
        RawU16::new(c.value())
    }
}

impl RgbColor for Rgb565Be {
    fn r(&self) -> u8 {
        Rgb565::from(*self).r()
    }
    fn g(&self) -> u8 {
        Rgb565::from(*self).g()
    }
    fn b(&self) -> u8 {
        Rgb565::from(*self).b()
    }
    const MAX_R: u8 = Rgb565::MAX_R;
    const MAX_G: u8 = Rgb565::MAX_G;
    const MAX_B: u8 = Rgb565::MAX_B;
    const BLACK: Self = Self::new(0, 0, 0);
    const RED: Self = Self::new(31, 0, 0);
    const GREEN: Self = Self::new(0, 63, 0);
    const BLUE: Self = Self::new(0, 0, 31);
    const YELLOW: Self = Self::new(31, 63, 0);
    const MAGENTA: Self = Self::new(31, 0, 31);
    const CYAN: Self = Self::new(0, 63, 31);
    const WHITE: Self = Self::new(31, 63, 31);
}

/// The same levels as [`Rgb565`]'s dithering, in wire order.
impl Dither for Rgb565Be {
    #[inline(always)]
    fn dither(c: [u8; 3], x: i32, y: i32) -> Self {
        Rgb565::dither(c, x, y).into()
    }
}

/// The bytes of `pixels` for a DMA channel: the address of the first byte
/// and the number of bytes, `2 * pixels.len()`, in wire order (see
/// [`Rgb565Be`]).
///
/// This is what a DMA driver needs (`embedded_dma::ReadBuffer` returns
/// exactly this pair), and making it is safe: reading through the pointer
/// is the driver's `unsafe`, valid while `pixels` is borrowed, which the
/// driver ensures by holding the tile buffer for as long as the transfer
/// runs (see [`TileTransfer`](super::TileTransfer)). This crate forbids
/// `unsafe` code, so it gives no `&[u8]` over the pixels itself; a driver
/// that wants one makes it from this pair with
/// `core::slice::from_raw_parts`.
pub fn wire_bytes(pixels: &[Rgb565Be]) -> (*const u8, usize) {
    (pixels.as_ptr().cast::<u8>(), 2 * pixels.len())
}

/// Column address set: the window's first and last column follow.
pub const CASET: u8 = 0x2a;
/// Row address set: the window's first and last row follow.
pub const RASET: u8 = 0x2b;
/// Memory write: pixels follow, filling the window row by row.
pub const RAMWR: u8 = 0x2c;

/// The commands that open a window of the panel's memory for one tile, in
/// the command set of the ST7789, ILI9341, ST7735, GC9A01 and other
/// MIPI DCS panels: `CASET` (first and last column), `RASET` (first and
/// last row), `RAMWR`; after them the tile's pixels, row by row.
///
/// On a 4-wire SPI bus each command byte goes out with the DC line low
/// and its parameters with DC high; the pixels follow with DC high.
///
/// ```
/// use microraster::prelude::*;
/// use microraster::sink::wire::{Window, CASET, RAMWR, RASET};
///
/// let area = Rectangle::new(Point::new(224, 32), Size::new(16, 32));
/// // A 240x240 panel on a 240x320 controller, shifted 80 rows.
/// let window = Window::new(&area, Point::new(0, 80)).unwrap();
/// assert_eq!(
///     window.commands(),
///     [
///         (CASET, &[0, 224, 0, 239][..]),
///         (RASET, &[0, 112, 0, 143][..]),
///         (RAMWR, &[][..]),
///     ]
/// );
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Window {
    /// `CASET`'s parameters: first and last column, big-endian.
    pub columns: [u8; 4],
    /// `RASET`'s parameters: first and last row, big-endian.
    pub rows: [u8; 4],
}

impl Window {
    /// The window of `area` (a tile's rectangle on the screen), moved by
    /// `offset`: where the screen's top-left pixel lies in the
    /// controller's memory (non-zero when the panel is smaller than the
    /// controller's 240x320, depending on its rotation). `None` when the
    /// area is empty or reaches outside the controller's 16-bit
    /// addresses.
    pub fn new(area: &Rectangle, offset: Point) -> Option<Self> {
        let range = |start: i32, len: u32, offset: i32| -> Option<[u8; 4]> {
            let first = start.checked_add(offset)?;
            let last = first.checked_add(i32::try_from(len).ok()?.checked_sub(1)?)?;
            let (first, last) = (u16::try_from(first).ok()?, u16::try_from(last).ok()?);
            (len > 0).then_some(())?;
            let ([a, b], [c, d]) = (first.to_be_bytes(), last.to_be_bytes());
            Some([a, b, c, d])
        };
        Some(Self {
            columns: range(area.top_left.x, area.size.width, offset.x)?,
            rows: range(area.top_left.y, area.size.height, offset.y)?,
        })
    }

    /// The three commands, each with its parameter bytes, in the order
    /// they are sent: `CASET`, `RASET`, `RAMWR`.
    pub fn commands(&self) -> [(u8, &[u8]); 3] {
        [(CASET, &self.columns), (RASET, &self.rows), (RAMWR, &[])]
    }
}
