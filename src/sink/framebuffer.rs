//! A sink over a frame buffer that the caller owns.

use super::TileSink;
use crate::tile::TileView;
use embedded_graphics::pixelcolor::PixelColor;
use embedded_graphics::prelude::Size;
use embedded_graphics::primitives::Rectangle;

/// A [`TileSink`] that places each tile into a whole frame held by the
/// caller: `width * height` pixels, row-major, in a `&mut [C]` from
/// anywhere (a `static`, the stack, a `Vec`). It allocates nothing; for
/// host programs, and for microcontrollers with RAM for a frame.
///
/// ```
/// use microraster::embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
/// use microraster::fixed::types::I16F16;
/// use microraster::prelude::*;
/// use microraster::sink::FrameBuffer;
///
/// let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
/// let positions = [p(-0.5, -0.5), p(0.5, -0.5), p(0.0, 0.5)];
/// let triangles = [[0u16, 1, 2]];
/// let mesh = Mesh::new(&positions, &triangles).unwrap();
/// let draws = [Draw::new(&mesh).color(Rgb888::new(255, 0, 0))];
/// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
///
/// let size = Size::new(40, 30);
/// let mut renderer: Renderer<Rgb565, 16, 16> =
///     Renderer::new(Config::new(size, Rgb565::BLACK));
/// let mut workspace: Workspace<8, 32, 8> = Workspace::new();
///
/// let mut pixels = [Rgb565::BLACK; 40 * 30];
/// let mut frame = FrameBuffer::new(&mut pixels, size).unwrap();
/// renderer.render(&mut workspace, &scene, &mut frame).unwrap();
/// assert_eq!(frame.pixel(20, 15), Some(Rgb565::RED));
/// // The buffer is the caller's again once the sink is gone.
/// assert_eq!(pixels[15 * 40 + 20], Rgb565::RED);
/// assert_eq!(pixels[0], Rgb565::BLACK);
/// ```
#[derive(Debug)]
pub struct FrameBuffer<'a, C> {
    pixels: &'a mut [C],
    size: Size,
}

/// Why a [`FrameBuffer`] cannot be made, or cannot take a tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameBufferError {
    /// The buffer does not hold `size.width * size.height` pixels.
    WrongLength {
        /// The frame's size.
        size: Size,
        /// The buffer's length in pixels.
        len: usize,
    },
    /// A tile reaches outside the frame: the renderer's frame
    /// ([`Config::size`](crate::Config)) is larger than the buffer's.
    /// Nothing of that tile is written.
    TileOutside {
        /// The tile's rectangle on the screen.
        area: Rectangle,
        /// The frame buffer's size.
        size: Size,
    },
}

impl core::fmt::Display for FrameBufferError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FrameBufferError::WrongLength { size, len } => write!(
                f,
                "a {}x{} frame needs {} pixels and the buffer holds {len}",
                size.width,
                size.height,
                // In u64: the product of two u32 cannot overflow it.
                u64::from(size.width) * u64::from(size.height)
            ),
            FrameBufferError::TileOutside { area, size } => write!(
                f,
                "the {}x{} tile at ({}, {}) reaches outside the {}x{} frame buffer",
                area.size.width,
                area.size.height,
                area.top_left.x,
                area.top_left.y,
                size.width,
                size.height
            ),
        }
    }
}

impl<'a, C: PixelColor> FrameBuffer<'a, C> {
    /// A frame of `size` over `pixels`, row-major, which must hold exactly
    /// `size.width * size.height` pixels. Their contents are kept until
    /// tiles overwrite them.
    pub fn new(pixels: &'a mut [C], size: Size) -> Result<Self, FrameBufferError> {
        let needed = (size.width as usize).checked_mul(size.height as usize);
        if needed != Some(pixels.len()) {
            return Err(FrameBufferError::WrongLength {
                size,
                len: pixels.len(),
            });
        }
        Ok(Self { pixels, size })
    }

    /// The frame's size.
    pub fn size(&self) -> Size {
        self.size
    }

    /// Every pixel, row-major.
    pub fn pixels(&self) -> &[C] {
        self.pixels
    }

    /// The pixel at column `x`, row `y`, or `None` outside the frame.
    pub fn pixel(&self, x: u32, y: u32) -> Option<C> {
        if x >= self.size.width {
            return None;
        }
        let i = (y as usize)
            .checked_mul(self.size.width as usize)?
            .checked_add(x as usize)?;
        self.pixels.get(i).copied()
    }

    /// The buffer's index of the first pixel of each of `area`'s rows, if
    /// the whole area lies inside the frame.
    fn rows_of(&self, area: &Rectangle) -> Option<impl Iterator<Item = usize>> {
        let x0 = u32::try_from(area.top_left.x).ok()?;
        let y0 = u32::try_from(area.top_left.y).ok()?;
        let fits =
            |start: u32, len: u32, side: u32| start.checked_add(len).is_some_and(|end| end <= side);
        if !fits(x0, area.size.width, self.size.width)
            || !fits(y0, area.size.height, self.size.height)
        {
            return None;
        }
        let (x0, y0, width) = (x0 as usize, y0 as usize, self.size.width as usize);
        Some((y0..y0 + area.size.height as usize).map(move |y| y * width + x0))
    }
}

impl<C: PixelColor> TileSink<C> for FrameBuffer<'_, C> {
    type Error = FrameBufferError;

    fn write_tile(&mut self, area: &Rectangle, tile: &TileView<'_, C>) -> Result<(), Self::Error> {
        let starts = self.rows_of(area).ok_or(FrameBufferError::TileOutside {
            area: *area,
            size: self.size,
        })?;
        let width = area.size.width as usize;
        for (start, row) in starts.zip(tile.rows()) {
            // Inside the frame, as checked above; `zip` copies no more
            // than the shorter of the two rows.
            if let Some(dst) = self.pixels.get_mut(start..start + width) {
                for (d, s) in dst.iter_mut().zip(row) {
                    *d = *s;
                }
            }
        }
        Ok(())
    }
}
