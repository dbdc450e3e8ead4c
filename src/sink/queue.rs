//! A queue of tiles on the wire: the core draws ahead while a driver that
//! moves on to the next tile by itself (a DMA-completion interrupt, say)
//! sends the ones already drawn.
//!
//! With two buffers each tile costs the longer of its drawing and the
//! transfer of the previous tile: a tile cheaper to draw than to send
//! makes the core wait for the wire, and a dear one leaves the wire idle.
//! With `N` buffers up to `N - 1` finished tiles wait on the wire, so a
//! run of cheap tiles fills the queue while the wire catches up on them
//! during the dear ones that follow; and tiles with nothing to draw are
//! taken between the others, at most `N - 2` in a row, so that no long
//! run of them makes the core wait (see [`Renderer::render_queued`]).
//!
//! [`Frame::render_double_buffered`] keeps its own loop although it makes
//! the calls of this one with `N = 2`: the slots and the count here cost
//! the Pico firmware 252 bytes more flash than that loop's two variables.

use super::TileTransfer;
use crate::render::{Frame, FrameStats, Pick, Renderer, Workspace};
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
    /// in flight when this returns. The tiles and every pixel are those
    /// of [`render`](Self::render); for `N = 2` the order too.
    ///
    /// # Order
    ///
    /// A tile whose bin is empty (no triangle touches it) costs a clear
    /// and nothing else: drawn in no time, it waits for the wire if
    /// `N - 1` tiles are in flight, and a run of such tiles (the sky, the
    /// floor, the margins around a model) makes the core wait where it
    /// could be drawing. So for `N > 2` the frame's tiles are taken in two
    /// streams, each in visiting order within a binning pass: up to
    /// `N - 2` empty tiles after each tile with triangles (the wire sends
    /// them while the core draws that one, whose buffer's transfer is the
    /// only one left to wait for), then the next tile with triangles; the
    /// other kind when one runs out. The driver gets each tile's area with
    /// it (as a display's window), so the order changes nothing on screen.
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
    /// up to `N - 1` finished tiles in flight in `transfer`, in the order
    /// [`Renderer::render_queued`] describes: its loop, for a frame begun without a renderer
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
        // Cheap tiles (an empty bin: a clear and nothing else) drawn since
        // the last dear one. See the order in `render_queued`'s docs.
        let mut cheap_run = 0;
        let outcome = loop {
            // Always a buffer here, whatever order the driver gives them
            // back in: slot `next` holds one of the `N` to begin with, and
            // once `N - 1` are in flight, the wait before each start
            // fills the slot after. (Were it empty, the frame would end
            // here rather than panic.)
            let Some(mut tile) = slots[next].take() else {
                break Ok(());
            };
            let pick = if N == 2 {
                Pick::InOrder
            } else if cheap_run < N - 2 {
                Pick::Cheap
            } else {
                Pick::Dear
            };
            let Some((area, cheap)) = self.render_picked(tile.borrow_mut(), &mut (), pick) else {
                slots[next] = Some(tile);
                break Ok(());
            };
            cheap_run = if cheap { cheap_run + 1 } else { 0 };
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

#[cfg(test)]
mod tests {
    use crate::prelude::*;
    use crate::render::{Frame, Pick};
    use crate::TileBuffer;
    use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
    use fixed::types::I16F16;
    use heapless::{Deque, Vec};

    type Tile = TileBuffer<Rgb565, 16, 16>;

    /// A queued driver that sends nothing: it keeps the buffers in flight,
    /// gives the oldest back first, and records the areas started.
    struct Fifo<'t> {
        queue: Deque<&'t mut Tile, 8>,
        order: Vec<Rectangle, 64>,
    }

    impl<'t> TileTransfer<&'t mut Tile> for Fifo<'t> {
        type Error = ();
        fn start(
            &mut self,
            area: &Rectangle,
            tile: &'t mut Tile,
        ) -> Result<(), ((), &'t mut Tile)> {
            // Room for every tile of the test's frames; a full queue
            // gives the tile back with the error.
            if self.order.push(*area).is_err() {
                return Err(((), tile));
            }
            self.queue.push_back(tile).map_err(|tile| ((), tile))
        }
        fn wait(&mut self) -> (&'t mut Tile, Result<(), ()>) {
            (self.queue.pop_front().expect("a tile in flight"), Ok(()))
        }
    }

    /// The order `render_queued`'s policy gives tiles of the kinds
    /// `cheap` (in visiting order) over `N` buffers: up to `N - 2` cheap
    /// tiles after each dear one (`N - 2` at the start), each kind in
    /// visiting order, the other kind when one runs out; visiting order
    /// for two buffers.
    fn policy<const N: usize>(tiles: &[(Rectangle, bool)]) -> Vec<Rectangle, 64> {
        let cheap: Vec<_, 64> = tiles.iter().filter(|t| t.1).map(|t| t.0).collect();
        let dear: Vec<_, 64> = tiles.iter().filter(|t| !t.1).map(|t| t.0).collect();
        if N == 2 {
            return tiles.iter().map(|t| t.0).collect();
        }
        let (mut c, mut d, mut run) = (0, 0, 0);
        let mut out = Vec::new();
        while c + d < tiles.len() {
            let take_cheap = if run < N - 2 {
                c < cheap.len()
            } else {
                d == dear.len()
            };
            if take_cheap {
                out.push(cheap[c]).unwrap();
                c += 1;
                run += 1;
            } else {
                out.push(dear[d]).unwrap();
                d += 1;
                run = 0;
            }
        }
        out
    }

    fn queued<const N: usize>(scene: &Scene<'_>, config: Config<Rgb565>) {
        let renderer: Renderer<Rgb565, 16, 16> = Renderer::new(config);
        let mut ws: Workspace<8, 1024, 64> = Workspace::new();
        // Visiting order, and which tiles have an empty bin.
        let mut visit: Vec<(Rectangle, bool), 64> = Vec::new();
        let mut tile = Tile::new(Rgb565::BLACK);
        let mut frame: Frame<'_, _, _, 16, 16> = renderer.begin(&mut ws, scene).unwrap();
        while let Some(t) = frame.render_picked(&mut tile, &mut (), Pick::InOrder) {
            visit.push(t).unwrap();
        }
        let cheap = visit.iter().filter(|t| t.1).count();
        assert!(
            cheap > 10 && visit.len() - cheap > 3,
            "{cheap} of {}",
            visit.len()
        );

        let mut store = [(); N].map(|_| Tile::new(Rgb565::BLACK));
        let mut fifo = Fifo {
            queue: Deque::new(),
            order: Vec::new(),
        };
        let tiles = {
            let mut it = store.iter_mut();
            [(); N].map(|_| it.next().unwrap())
        };
        let (_, result) = renderer.render_queued(&mut ws, scene, tiles, &mut fifo);
        let stats = result.unwrap();
        // One binning pass: the order is chosen within a pass.
        assert_eq!((stats.tiles as usize, stats.bin_passes), (visit.len(), 1));
        let want = policy::<N>(&visit);
        assert_eq!(fifo.order, want, "{N} buffers");
        if N > 2 {
            let in_order: Vec<_, 64> = visit.iter().map(|t| t.0).collect();
            assert_ne!(fifo.order, in_order, "cheap tiles taken ahead");
        }
    }

    /// `render_queued` draws up to `N - 2` tiles with an empty bin after
    /// each tile with triangles, so that a run of empty tiles (drawn in
    /// no time) does not make the core wait for the wire while it could
    /// be drawing: every tile once, each kind in visiting order.
    #[test]
    fn queued_tiles_interleave_cheap_and_dear() {
        let p = |x: f32, y: f32| {
            [
                I16F16::from_num(x),
                I16F16::from_num(y),
                I16F16::from_num(0.5),
            ]
        };
        let positions = [p(-0.1, -0.3), p(0.5, -0.3), p(0.5, 0.4), p(-0.1, 0.4)];
        let triangles = [[0u16, 1, 2], [0, 2, 3]];
        let mesh = Mesh::new(&positions, &triangles).unwrap();
        let draws = [Draw::new(&mesh).color(Rgb888::new(255, 0, 0))];
        let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
        // 10 x 6 tiles of 16 x 16.
        let config = Config::new(Size::new(160, 96), Rgb565::BLACK);
        queued::<2>(&scene, config);
        queued::<3>(&scene, config);
        queued::<5>(&scene, config);
        queued::<5>(&scene, config.tile_order(TileOrder::Hilbert));
    }
}
