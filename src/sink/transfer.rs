//! Double buffering: one tile is drawn while the previous one is on the
//! wire.
//!
//! A [`TileSink`](super::TileSink) returns when its tile has gone, so the
//! CPU waits for the wire and the wire for the CPU, and a frame takes the
//! sum of both. A [`TileTransfer`] only starts sending a tile and is asked
//! later to wait for it; [`Renderer::render_double_buffered`] keeps two
//! tile buffers and draws the next tile into one while the other is in
//! flight, so a frame takes about the longer of the two.
//!
//! A buffer in flight belongs to the transfer: [`TileTransfer::start`]
//! takes it by value and [`TileTransfer::wait`] gives it back, as the
//! embedded DMA APIs do (rp2040-hal's `single_buffer::Config::start` and
//! `Transfer::wait`, esp-hal's `SpiDmaTransfer::wait`), so the borrow
//! checker forbids drawing into a buffer that DMA is still reading. The
//! buffer handle `B` is whatever the driver needs: a `&'static mut
//! TileBuffer` for a DMA channel (a transfer must not outlive its buffer
//! even if the driver is leaked, hence `'static`), or any other
//! [`BorrowMut`] of a [`TileBuffer`] on a host.

use crate::render::{Frame, FrameStats, Renderer, Workspace};
use crate::scene::Scene;
use crate::shader::ShaderSet;
use crate::tile::TileBuffer;
use crate::{Features, RenderError};
use core::borrow::BorrowMut;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::primitives::Rectangle;

/// A driver that sends a finished tile in the background (a DMA channel
/// feeding SPI, typically) and is asked later to wait for it.
///
/// [`Renderer::render_double_buffered`] calls `start` and `wait` in turn,
/// never `start` twice without a `wait` between, and never `wait` without
/// a transfer in flight:
///
/// `start(tile 0)`, draw tile 1, `wait`, `start(tile 1)`, draw tile 2,
/// `wait`, …, `start(last tile)`, `wait`.
///
/// [`Renderer::render_queued`] over `N` buffers keeps up to `N - 1` tiles
/// in flight: it calls `start` while others are, and a driver used with
/// `N > 2` must accept that, queue the tile and send the queued tiles one
/// after the other in the order they were started, without the core (a
/// DMA-completion interrupt starts the next one, say). `wait` then gives
/// back the oldest tile in flight, once it is sent: first in, first out.
/// (`render_queued` puts a buffer that comes back out of order to use all
/// the same, but the tiles on the panel are the driver's business.) With
/// `N = 2` the calls are those of `render_double_buffered`.
///
/// An implementation for a DMA channel takes the tile's pixels with
/// [`TileBuffer::pack`] (they are then one contiguous block; for
/// [`Rgb565Be`](super::Rgb565Be) pixels,
/// [`wire_bytes`](super::wire::wire_bytes) gives the block's address and
/// length), sends the panel's window commands for `area` (see
/// [`Window`](super::wire::Window)), starts the channel and keeps the
/// buffer until the channel is done.
///
/// The buffer always comes back, with the error if there is one, so a
/// failed transfer loses no buffer: the caller gets them all back from
/// [`Renderer::render_double_buffered`] and
/// [`Renderer::render_queued`] whatever happens.
pub trait TileTransfer<B> {
    /// The driver's error, returned as [`RenderError::Sink`].
    type Error;

    /// Starts sending the tile held by `tile`, which covers `area` of the
    /// frame (the buffer's top-left `area.size` pixels, as
    /// [`TileBuffer::view`] reads them), and returns without waiting for
    /// the bytes to be on the wire. The transfer keeps `tile` until
    /// [`wait`](Self::wait) gives it back. Called with fewer than `N - 1`
    /// tiles in flight for `N` buffers: none for two.
    ///
    /// On an error `tile` comes back with it and is not in flight; the
    /// tiles in flight before are still waited for.
    fn start(&mut self, area: &Rectangle, tile: B) -> Result<(), (Self::Error, B)>;

    /// Waits until the oldest transfer in flight is done, and gives its
    /// buffer back with its outcome. Called only with a tile in flight
    /// (after a successful [`start`](Self::start) not yet waited for).
    fn wait(&mut self) -> (B, Result<(), Self::Error>);
}

// Bounds that repeat queue.rs's on purpose: each public entry point states
// its own, where rustdoc shows them.
impl<C, const TW: usize, const TH: usize, P> Renderer<C, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    P: Features,
{
    /// Renders `scene` into the two tile buffers `tiles` in turn, handing
    /// each finished tile to `transfer` and drawing the next one while it
    /// is sent: `start(tile k)`, draw tile `k + 1` into the other buffer,
    /// `wait` for tile `k`, `start(tile k + 1)`, and so on. A frame then
    /// takes about the longer of its drawing and its sending instead of
    /// their sum.
    ///
    /// Returns both buffers (in either order), and the frame's statistics
    /// or the first error. Every error but [`RenderError::Sink`] is found
    /// before the first tile is drawn; after a transfer's error no tile is
    /// started, and nothing is in flight when this returns. The tiles, the
    /// order they are sent in and every pixel are those of
    /// [`render`](Self::render).
    ///
    /// ```
    /// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// use microraster::prelude::*;
    /// use microraster::TileBuffer;
    ///
    /// /// Sends nothing, but as a DMA driver would: holds the buffer in flight.
    /// struct Dma(Option<Box<TileBuffer<Rgb565, 16, 16>>>, usize);
    ///
    /// impl TileTransfer<Box<TileBuffer<Rgb565, 16, 16>>> for Dma {
    ///     type Error = ();
    ///     fn start(&mut self, area: &Rectangle, mut tile: Box<TileBuffer<Rgb565, 16, 16>>)
    ///         -> Result<(), ((), Box<TileBuffer<Rgb565, 16, 16>>)> {
    ///         let pixels = tile.pack(area); // one block for the DMA channel
    ///         self.1 += pixels.len();
    ///         self.0 = Some(tile);
    ///         Ok(())
    ///     }
    ///     fn wait(&mut self) -> (Box<TileBuffer<Rgb565, 16, 16>>, Result<(), ()>) {
    ///         (self.0.take().expect("a tile in flight"), Ok(()))
    ///     }
    /// }
    ///
    /// let draws = [];
    /// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    /// let renderer: Renderer<Rgb565, 16, 16> =
    ///     Renderer::new(Config::new(Size::new(40, 30), Rgb565::BLACK));
    /// let mut ws: Workspace<4, 64, 8> = Workspace::new();
    /// let mut tiles = [0; 2].map(|_| Box::new(TileBuffer::new(Rgb565::BLACK)));
    /// let mut dma = Dma(None, 0);
    ///
    /// let (back, result) = renderer.render_double_buffered(&mut ws, &scene, tiles, &mut dma);
    /// tiles = back; // for the next frame
    /// assert_eq!(result.unwrap().tiles, 6);
    /// # assert_eq!(tiles.len(), 2);
    /// assert_eq!(dma.1, 40 * 30);
    /// ```
    #[must_use = "the tile buffers come back with the frame's result"]
    pub fn render_double_buffered<X, B, F, const V: usize, const BN: usize, const T: usize>(
        &self,
        ws: &mut Workspace<V, BN, T>,
        scene: &Scene<'_, F>,
        tiles: [B; 2],
        transfer: &mut X,
    ) -> ([B; 2], Result<FrameStats, RenderError<X::Error>>)
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
        F: ShaderSet<C>,
    {
        // Two buffers: the queue's loop keeps one tile in flight.
        self.render_queued(ws, scene, tiles, transfer)
    }
}

// Bounds that repeat queue.rs's on purpose: each public entry point states
// its own, where rustdoc shows them.
impl<C, F, const TW: usize, const TH: usize, P> Frame<'_, C, F, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    /// Draws the frame's tiles into `tiles` in turn, each finished tile
    /// handed to `transfer` while the next one is drawn: the loop of
    /// [`Renderer::render_double_buffered`], for a frame begun without a
    /// renderer ([`Frame::begin`]). Gives the buffers back with the
    /// frame's statistics or the transfer's first error. The same as
    /// [`Frame::render_queued`] with two buffers.
    #[must_use = "the tile buffers come back with the frame's result"]
    pub fn render_double_buffered<X, B>(
        self,
        tiles: [B; 2],
        transfer: &mut X,
    ) -> ([B; 2], Result<FrameStats, RenderError<X::Error>>)
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
    {
        // The queue's loop with two buffers: `start(tile k)`, draw tile
        // `k + 1`, `wait`, `start(tile k + 1)`, ... (see `render_queued`).
        self.render_queued(tiles, transfer)
    }
}
