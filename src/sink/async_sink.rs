//! The async form of double buffering, for executors such as embassy:
//! [`AsyncTileSink`] and [`Renderer::render_async`].

use crate::render::{Frame, FrameStats, Renderer, Workspace};
use crate::scene::Scene;
use crate::shader::ShaderSet;
use crate::tile::{TileBuffer, TileView};
use crate::{Features, RenderError};
use core::future::{poll_fn, Future};
use core::pin::pin;
use core::task::Poll;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::primitives::Rectangle;

/// A consumer of finished tiles whose writes are futures, such as an SPI
/// panel driven through embassy's async DMA: the async twin of
/// [`TileSink`](super::TileSink), for [`Renderer::render_async`].
///
/// # Why the tile is borrowed, and when the next one is drawn
///
/// An async SPI or DMA driver (embassy's `Spi::write`, for one) borrows
/// the bytes it sends for as long as its future lives, so the borrow
/// checker already forbids drawing into a buffer in flight: the tile is
/// lent by reference, not handed over as to a
/// [`TileTransfer`](super::TileTransfer).
///
/// Drawing the next tile while a write's future is pending needs the two
/// to run concurrently. [`Renderer::render_async`] does it within one
/// task, without a second task, `join` or allocation: it polls the
/// write's future once, which starts the transfer (and gives the driver
/// the task's waker), then draws the next tile into the other buffer while
/// the hardware sends, and only then awaits the write, which by then has
/// often finished:
///
/// start tile `k` → draw tile `k + 1` → await tile `k` → start tile
/// `k + 1` → …
///
/// Drawing does not yield to the executor: it is CPU work like any other
/// between two awaits, and the transfer does not need the CPU. Other tasks
/// of the executor wait for one tile's drawing (a few milliseconds on a
/// Cortex-M0+); drawing in awaitable steps would cost every tile for their
/// sake.
///
/// # What an implementation does
///
/// `write_tile` should start the transfer when its future is first
/// polled, and do the rest in the background: [`Renderer::render_async`]
/// polls it once, then draws the next tile before polling it again. A
/// future that awaits something else first (the window commands sent by
/// an awaited DMA transfer of their own, say) starts the pixels' transfer
/// only after the next tile is drawn, and nothing overlaps; send those few
/// bytes with a blocking write in the first poll instead.
///
/// The future borrows the tile's pixels until it completes or is dropped,
/// so dropping it must stop the transfer, as embassy's drivers do.
///
/// The view's pixels are always one contiguous block
/// ([`TileView::contiguous`] is `Some`), in the tile's rows, top to bottom.
// No `Send` bound on the future: embassy's executors keep a task on its
// thread, and a `Send` bound would refuse drivers that hold a `RefCell`.
#[allow(async_fn_in_trait)]
pub trait AsyncTileSink<C> {
    /// The sink's error, returned as [`RenderError::Sink`].
    type Error;

    /// Writes one finished tile covering `area` of the frame.
    async fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, C>,
    ) -> Result<(), Self::Error>;
}

impl<C, const TW: usize, const TH: usize, P> Renderer<C, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    P: Features,
{
    /// Renders `scene` into the two tile buffers `tiles` in turn, writing
    /// each finished tile to `sink` while the next one is drawn: the
    /// `write_tile` future of tile `k` is polled once (which starts its
    /// transfer), tile `k + 1` is drawn into the other buffer, and then
    /// the future is awaited. [`AsyncTileSink`] says why in this order.
    ///
    /// Each tile is packed ([`TileBuffer::pack`]) before it is written, so
    /// the sink's view is one contiguous block. Every error but
    /// [`RenderError::Sink`] is found before the first tile is drawn;
    /// after a sink's error no tile is written. The tiles, their order and
    /// every pixel are those of [`render`](Self::render).
    ///
    /// ```
    /// use core::future::Future;
    /// use core::pin::pin;
    /// use core::task::{Context, Poll, Waker};
    /// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// use microraster::prelude::*;
    /// use microraster::TileBuffer;
    ///
    /// struct Count(usize);
    ///
    /// impl AsyncTileSink<Rgb565> for Count {
    ///     type Error = ();
    ///     async fn write_tile(&mut self, _: &Rectangle, tile: &TileView<'_, Rgb565>)
    ///         -> Result<(), ()> {
    ///         // An async SPI driver would send this block by DMA.
    ///         self.0 += tile.contiguous().unwrap().len();
    ///         Ok(())
    ///     }
    /// }
    ///
    /// let draws = [];
    /// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    /// let renderer: Renderer<Rgb565, 16, 16> =
    ///     Renderer::new(Config::new(Size::new(40, 30), Rgb565::BLACK));
    /// let mut ws: Workspace<4, 64, 8> = Workspace::new();
    /// let mut tiles = [TileBuffer::new(Rgb565::BLACK), TileBuffer::new(Rgb565::BLACK)];
    /// let mut sink = Count(0);
    ///
    /// // With embassy: `renderer.render_async(...).await` in a task.
    /// // Here, a minimal executor: poll until it is done.
    /// let stats = {
    ///     let mut frame = pin!(renderer.render_async(&mut ws, &scene, &mut tiles, &mut sink));
    ///     let mut cx = Context::from_waker(Waker::noop());
    ///     loop {
    ///         if let Poll::Ready(r) = frame.as_mut().poll(&mut cx) {
    ///             break r.unwrap();
    ///         }
    ///     }
    /// };
    /// assert_eq!(stats.tiles, 6);
    /// assert_eq!(sink.0, 40 * 30);
    /// ```
    pub async fn render_async<S, F, const V: usize, const BN: usize, const T: usize>(
        &self,
        ws: &mut Workspace<V, BN, T>,
        scene: &Scene<'_, F>,
        tiles: &mut [TileBuffer<C, TW, TH>; 2],
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: AsyncTileSink<C>,
        F: ShaderSet<C>,
    {
        self.begin(ws, scene)
            .map_err(RenderError::for_sink)?
            .render_async(tiles, sink)
            .await
    }
}

impl<C, F, const TW: usize, const TH: usize, P> Frame<'_, C, F, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    /// Draws the frame's tiles into `tiles` in turn, each finished tile
    /// written to `sink` while the next one is drawn: the loop of
    /// [`Renderer::render_async`], for a frame begun without a renderer
    /// ([`Frame::begin`]).
    pub async fn render_async<S>(
        mut self,
        tiles: &mut [TileBuffer<C, TW, TH>; 2],
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: AsyncTileSink<C>,
    {
        let [sending, free] = tiles;
        let (mut sending, mut free) = (sending, free);
        let Some(mut area) = self.render_next(sending) else {
            return Ok(self.stats());
        };
        loop {
            let next = {
                let (w, h) = (area.size.width as usize, area.size.height as usize);
                let view = TileView::packed(sending.pack(&area), w.min(TW), h.min(TH));
                let mut write = pin!(sink.write_tile(&area, &view));
                // Start the transfer: one poll, with this task's waker.
                let first = poll_fn(|cx| Poll::Ready(write.as_mut().poll(cx))).await;
                let next = self.render_next(free);
                match first {
                    Poll::Ready(outcome) => outcome,
                    Poll::Pending => write.await,
                }
                .map_err(RenderError::Sink)?;
                next
            };
            match next {
                None => return Ok(self.stats()),
                Some(a) => {
                    area = a;
                    core::mem::swap(&mut sending, &mut free);
                }
            }
        }
    }
}
