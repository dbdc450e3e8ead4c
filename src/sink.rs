//! Where finished tiles go.
//!
//! A [`TileSink`] receives each tile once, as its screen rectangle and its
//! pixels. Every embedded-graphics [`DrawTarget`] is a sink: it gets one
//! `fill_contiguous` call per tile, so any e-g display driver (mipidsi,
//! ssd1306, the simulator, …) works unchanged. A driver that wants the raw
//! bytes, for example to start a DMA transfer per tile, implements
//! [`TileSink`] directly and reads [`TileView::rows`]. [`FrameBuffer`]
//! places the tiles into a whole frame in the caller's memory.
//!
//! A sink returns when its tile is gone, so drawing and sending take
//! turns. To overlap them, a DMA driver implements [`TileTransfer`]
//! (start sending a tile, wait for it later) for
//! [`Renderer::render_double_buffered`](crate::Renderer::render_double_buffered),
//! or [`AsyncTileSink`] for
//! [`Renderer::render_async`](crate::Renderer::render_async); both draw
//! the next tile into a second buffer while the previous one is on the
//! wire. A driver that moves on to the next queued tile by itself (a
//! DMA-completion interrupt) lets the core draw further ahead, over `N`
//! buffers: [`Renderer::render_queued`](crate::Renderer::render_queued); a
//! [`TileQueue`] keeps those buffers from frame to frame, so that a
//! frame's last tiles are sent while the next frame begins
//! ([`Frame::render_to_queue`](crate::render::Frame::render_to_queue)).
//! [`Rgb565Be`] draws tiles in an SPI panel's byte order, and
//! [`wire`] has the window commands that precede a tile's pixels.
//!
//! | file | what |
//! |---|---|
//! | `sink.rs` | [`TileSink`], every `DrawTarget` as one, [`NullSink`] |
//! | `sink/framebuffer.rs` | [`FrameBuffer`]: tiles placed in a whole frame |
//! | `sink/transfer.rs` | [`TileTransfer`] and the double-buffered frame loop |
//! | `sink/queue.rs` | the frame loop over `N` buffers, `N - 1` tiles in flight; [`TileQueue`] |
//! | `sink/async_sink.rs` | [`AsyncTileSink`] and the async frame loop |
//! | `sink/wire.rs` | [`Rgb565Be`], [`wire::Window`]: the panel's wire format |

mod async_sink;
mod framebuffer;
mod queue;
mod transfer;
pub mod wire;

pub use async_sink::AsyncTileSink;
pub use framebuffer::{FrameBuffer, FrameBufferError};
pub use queue::TileQueue;
pub use transfer::TileTransfer;
pub use wire::Rgb565Be;

use crate::tile::TileView;
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::PixelColor;
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;

/// A consumer of finished tiles.
pub trait TileSink<C: PixelColor> {
    /// The sink's error, returned by [`crate::Renderer::render`] unchanged.
    type Error;

    /// Writes one finished tile covering `area` of the frame.
    fn write_tile(&mut self, area: &Rectangle, tile: &TileView<'_, C>) -> Result<(), Self::Error>;
}

impl<D: DrawTarget> TileSink<D::Color> for D {
    type Error = D::Error;

    #[inline]
    fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, D::Color>,
    ) -> Result<(), D::Error> {
        self.fill_contiguous(area, tile.pixels())
    }
}

/// A sink that discards every tile; for benchmarks and instruction counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NullSink;

impl<C: PixelColor> TileSink<C> for NullSink {
    type Error = core::convert::Infallible;

    #[inline]
    fn write_tile(&mut self, _: &Rectangle, tile: &TileView<'_, C>) -> Result<(), Self::Error> {
        // Touch the data so the optimiser cannot drop the rendering.
        core::hint::black_box(tile.rows().next());
        Ok(())
    }
}

/// The e-g rectangle of a tile's pixel rectangle.
pub(crate) fn rectangle(r: &crate::raster::PixelRect) -> Rectangle {
    Rectangle::new(
        Point::new(r.x0, r.y0),
        Size::new((r.x1 - r.x0) as u32, (r.y1 - r.y0) as u32),
    )
}
