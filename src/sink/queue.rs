//! A queue of tiles on the wire: the core draws ahead while a driver that
//! moves on to the next tile by itself (a DMA-completion interrupt, say)
//! sends the ones already drawn.
//!
//! With two buffers each tile costs the longer of its drawing and the
//! transfer of the previous tile: a tile cheaper to draw than to send
//! makes the core wait for the wire, and a dear one leaves the wire idle.
//! With `N` buffers up to `N - 1` finished tiles wait on the wire, so a
//! run of cheap tiles fills the queue while the wire catches up on them
//! during the dear ones that follow.
//!
//! [`Frame::render_double_buffered`] keeps its own loop although it makes
//! the calls of this one with `N = 2`: the slots and the count here cost
//! the Pico firmware 252 bytes more flash than that loop's two variables.

use super::TileTransfer;
use crate::render::{Frame, FrameStats, Renderer, Workspace};
use crate::scene::Scene;
use crate::shader::ShaderSet;
use crate::tile::TileBuffer;
use crate::{Features, RenderError};
use core::borrow::BorrowMut;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};

impl<C, const TW: usize, const TH: usize, P> Renderer<C, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    P: Features,
{
    /// Renders `scene` into the `N` tile buffers `tiles` in turn, handing
    /// each finished tile to `transfer` and drawing on while up to `N - 1`
    /// tiles are in flight: draw a tile, wait for the oldest tile in
    /// flight only if `N - 1` are, start the drawn tile, draw the next.
    /// For `N = 2` that is the loop of
    /// [`render_double_buffered`](Self::render_double_buffered), call for
    /// call; for `N > 2` the driver must queue a tile started while
    /// others are in flight and send them one after the other (see
    /// [`TileTransfer`]), so that the wire moves on to the next tile
    /// without the core. `N < 2` does not compile.
    ///
    /// Returns the `N` buffers (in any order), and the frame's statistics
    /// or the first error. Every error but [`RenderError::Sink`] is found
    /// before the first tile is drawn; after a transfer's error no tile is
    /// started, the tiles still in flight are waited for, and nothing is
    /// in flight when this returns. The tiles, the order they are sent in
    /// and every pixel are those of [`render`](Self::render).
    ///
    /// ```
    /// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// use microraster::prelude::*;
    /// use microraster::TileBuffer;
    /// use std::collections::VecDeque;
    ///
    /// type Tile = Box<TileBuffer<Rgb565, 16, 16>>;
    ///
    /// /// Sends nothing, but as a queued DMA driver would: holds the buffers
    /// /// in flight and gives the oldest back first.
    /// struct Dma(VecDeque<Tile>, usize);
    ///
    /// impl TileTransfer<Tile> for Dma {
    ///     type Error = ();
    ///     fn start(&mut self, area: &Rectangle, mut tile: Tile) -> Result<(), ((), Tile)> {
    ///         let pixels = tile.pack(area); // one block for the DMA channel
    ///         self.1 += pixels.len();
    ///         self.0.push_back(tile);
    ///         Ok(())
    ///     }
    ///     fn wait(&mut self) -> (Tile, Result<(), ()>) {
    ///         (self.0.pop_front().expect("a tile in flight"), Ok(()))
    ///     }
    /// }
    ///
    /// let draws = [];
    /// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    /// let renderer: Renderer<Rgb565, 16, 16> =
    ///     Renderer::new(Config::new(Size::new(40, 30), Rgb565::BLACK));
    /// let mut ws: Workspace<4, 64, 8> = Workspace::new();
    /// let mut tiles = [0; 4].map(|_| Box::new(TileBuffer::new(Rgb565::BLACK)));
    /// let mut dma = Dma(VecDeque::new(), 0);
    ///
    /// let (back, result) = renderer.render_queued(&mut ws, &scene, tiles, &mut dma);
    /// tiles = back; // for the next frame
    /// assert_eq!(result.unwrap().tiles, 6);
    /// assert!(dma.0.is_empty(), "nothing in flight");
    /// # assert_eq!(tiles.len(), 4);
    /// assert_eq!(dma.1, 40 * 30);
    /// ```
    #[must_use = "the tile buffers come back with the frame's result"]
    pub fn render_queued<X, B, F, const N: usize, const V: usize, const BN: usize, const T: usize>(
        &self,
        ws: &mut Workspace<V, BN, T>,
        scene: &Scene<'_, F>,
        tiles: [B; N],
        transfer: &mut X,
    ) -> ([B; N], Result<FrameStats, RenderError<X::Error>>)
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
        F: ShaderSet<C>,
    {
        match self.begin(ws, scene) {
            Ok(frame) => frame.render_queued(tiles, transfer),
            Err(e) => (tiles, Err(e.for_sink())),
        }
    }
}

impl<C, F, const TW: usize, const TH: usize, P> Frame<'_, C, F, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    /// Draws the frame's tiles into the `N` buffers `tiles` in turn, with
    /// up to `N - 1` finished tiles in flight in `transfer`: the loop of
    /// [`Renderer::render_queued`], for a frame begun without a renderer
    /// ([`Frame::begin`]). Gives the buffers back with the frame's
    /// statistics or the transfer's first error, nothing in flight.
    #[must_use = "the tile buffers come back with the frame's result"]
    pub fn render_queued<X, B, const N: usize>(
        mut self,
        tiles: [B; N],
        transfer: &mut X,
    ) -> ([B; N], Result<FrameStats, RenderError<X::Error>>)
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
    {
        const {
            assert!(N >= 2, "render_queued needs at least two tile buffers");
        }
        // The buffers not in flight. Transfers come back oldest first, so
        // tile `k` is drawn into slot `k % N`, and the oldest tile in
        // flight while tile `k` is drawn is the one from slot `k + 1`
        // (mod `N`): its buffer goes back there.
        let mut slots = tiles.map(Some);
        let mut next = 0;
        let mut in_flight = 0;
        let outcome = loop {
            // Always a buffer here, whatever order the driver gives them
            // back in: slot `next` holds one of the `N` to begin with, and
            // once `N - 1` are in flight, the wait before each start
            // fills the slot after. (Were it empty, the frame would end
            // here rather than panic.)
            let Some(mut tile) = slots[next].take() else {
                break Ok(());
            };
            let Some(area) = self.render_next(tile.borrow_mut()) else {
                slots[next] = Some(tile);
                break Ok(());
            };
            let after = (next + 1) % N;
            if in_flight == N - 1 {
                let (done, result) = transfer.wait();
                in_flight -= 1;
                put_back(&mut slots, after, done);
                if let Err(e) = result {
                    slots[next] = Some(tile);
                    break Err(e);
                }
            }
            if let Err((e, back)) = transfer.start(&area, tile) {
                slots[next] = Some(back);
                break Err(e);
            }
            in_flight += 1;
            next = after;
        };
        // The end of the frame, or its first error: the tiles still in
        // flight are waited for, oldest first (the one drawn `in_flight`
        // tiles before `next`), so that every buffer comes back and none
        // is left with the driver. The first error is the one returned.
        let mut outcome = outcome;
        while in_flight > 0 {
            let (done, result) = transfer.wait();
            put_back(&mut slots, (next + N - in_flight) % N, done);
            in_flight -= 1;
            outcome = outcome.and(result);
        }
        // Every slot is full now: `N` buffers came back into `N` slots. (A
        // slot that were not would take one more buffer from the driver
        // rather than panic.)
        let tiles = slots.map(|slot| slot.unwrap_or_else(|| transfer.wait().0));
        let result = match outcome {
            Ok(()) => Ok(self.stats()),
            Err(e) => Err(RenderError::Sink(e)),
        };
        (tiles, result)
    }
}

/// Puts a buffer that came back from the transfer into slot `at`, where a
/// FIFO transfer's oldest buffer belongs, or into the first empty slot
/// should a driver give them back in another order (a buffer is never
/// dropped while a slot is free, and there are `N` slots for `N`).
fn put_back<B, const N: usize>(slots: &mut [Option<B>; N], at: usize, tile: B) {
    let slot = match slots[at] {
        None => Some(&mut slots[at]),
        Some(_) => slots.iter_mut().find(|s| s.is_none()),
    };
    if let Some(slot) = slot {
        *slot = Some(tile);
    }
}
