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
//! spread evenly between the others, at most `N - 2` in a row, so that no
//! run of them makes the core wait (see [`Renderer::render_queued`]). A
//! [`TileQueue`] keeps the buffers from one frame to the next
//! ([`Frame::render_to_queue`]), so that a frame's last tiles are sent
//! while the next frame's vertex stage and binning run.
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
    /// streams, each in visiting order within a binning pass, and the
    /// empty ones spread evenly over the others: an empty tile next while
    /// the share of the pass's empty tiles drawn is at most the share of
    /// its other tiles drawn, and at most `N - 2` of them in a row (the
    /// wire sends them while the core draws the next tile with triangles);
    /// the other kind when one runs out. Taken as early as the wire allows
    /// (up to `N - 2` after each tile with triangles) the empty tiles ran
    /// out a third of the way through the Pico firmware's frame, whose
    /// core then waited for the wire in its first tiles: 0.27 M cycles a
    /// frame, against 0.03 M spread. The driver gets each tile's area with
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

    /// Renders `scene` into the buffers of `queue` as
    /// [`render_queued`](Self::render_queued) does, but returns with the
    /// frame's last tiles still in flight, sent while the caller begins
    /// the next frame: [`Frame::render_to_queue`], for a frame begun by
    /// this renderer.
    pub fn render_to_queue<
        X,
        B,
        F,
        const N: usize,
        const V: usize,
        const BN: usize,
        const T: usize,
    >(
        &self,
        ws: &mut Workspace<V, BN, T>,
        scene: &Scene<'_, F>,
        queue: &mut TileQueue<B, N>,
        transfer: &mut X,
    ) -> Result<FrameStats, RenderError<X::Error>>
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
        F: ShaderSet<C>,
    {
        self.begin(ws, scene)
            .map_err(RenderError::for_sink)?
            .render_to_queue(queue, transfer)
    }
}

// The methods' bounds repeat on purpose: each public entry point states its
// own, where rustdoc shows them.
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
    ///
    /// [`render_to_queue`](Self::render_to_queue) does the same but leaves
    /// the frame's last tiles in flight, to be sent while the next frame's
    /// vertex stage and binning run.
    #[must_use = "the tile buffers come back with the frame's result"]
    pub fn render_queued<X, B, const N: usize>(
        self,
        tiles: [B; N],
        transfer: &mut X,
    ) -> ([B; N], Result<FrameStats, RenderError<X::Error>>)
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
    {
        let mut queue = TileQueue::new(tiles);
        let result = self.render_to_queue(&mut queue, transfer);
        // Nothing is in flight after an error; after a frame, its last
        // tiles are.
        let (tiles, sent) = queue.into_tiles(transfer);
        let result = match (result, sent) {
            (Ok(stats), Ok(())) => Ok(stats),
            (Err(e), _) => Err(e),
            (Ok(_), Err(e)) => Err(RenderError::Sink(e)),
        };
        (tiles, result)
    }

    /// Draws the frame's tiles into the buffers of `queue`, in the order of
    /// [`Renderer::render_queued`], with up to `N - 1` finished tiles in
    /// flight in `transfer`, and returns with the frame's last tiles still
    /// in flight: the next frame's vertex stage and binning (which use no
    /// tile buffer) then run while the wire sends them, where
    /// [`render_queued`](Self::render_queued) would wait for the wire to
    /// empty. Tiles in flight from the frame before are waited for as this
    /// frame's buffers are needed, oldest first.
    ///
    /// Returns the frame's statistics, or the first error; a transfer's
    /// error may be that of a tile of the frame before, waited for during
    /// this one. After an error no tile is started, the tiles in flight
    /// are waited for, and none is in flight when this returns.
    /// [`TileQueue::into_tiles`] waits for the last ones and gives the
    /// buffers back.
    ///
    /// ```
    /// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// use microraster::prelude::*;
    /// use microraster::render::Frame;
    /// use microraster::{TileBuffer, TileQueue};
    /// use std::collections::VecDeque;
    ///
    /// type Tile = Box<TileBuffer<Rgb565, 16, 16>>;
    ///
    /// /// A queued DMA driver that sends nothing: it holds the buffers in
    /// /// flight and gives the oldest back first.
    /// struct Dma(VecDeque<Tile>);
    ///
    /// impl TileTransfer<Tile> for Dma {
    ///     type Error = ();
    ///     fn start(&mut self, _: &Rectangle, tile: Tile) -> Result<(), ((), Tile)> {
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
    /// let config = Config::new(Size::new(40, 30), Rgb565::BLACK);
    /// let mut ws: Workspace<4, 64, 8> = Workspace::new();
    /// let mut queue = TileQueue::new([0; 4].map(|_| Box::new(TileBuffer::new(Rgb565::BLACK))));
    /// let mut dma = Dma(VecDeque::new());
    /// for _ in 0..3 {
    ///     let frame: Frame<'_, Rgb565, _, 16, 16> = Frame::begin(config, &mut ws, &scene).unwrap();
    ///     let stats = frame.render_to_queue(&mut queue, &mut dma).unwrap();
    ///     assert_eq!(stats.tiles, 6);
    ///     // The frame's last three tiles are still on the wire.
    ///     assert_eq!((queue.in_flight(), dma.0.len()), (3, 3));
    /// }
    /// let (tiles, sent) = queue.into_tiles(&mut dma);
    /// assert_eq!((tiles.len(), sent, dma.0.len()), (4, Ok(()), 0));
    /// ```
    pub fn render_to_queue<X, B, const N: usize>(
        mut self,
        queue: &mut TileQueue<B, N>,
        transfer: &mut X,
    ) -> Result<FrameStats, RenderError<X::Error>>
    where
        X: TileTransfer<B>,
        B: BorrowMut<TileBuffer<C, TW, TH>>,
    {
        const {
            assert!(N >= 2, "a tile queue needs at least two tile buffers");
        }
        let TileQueue {
            slots,
            next,
            in_flight,
        } = queue;
        // Cheap tiles (an empty bin: a clear and nothing else) drawn since
        // the last dear one. See the order in `render_queued`'s docs.
        let mut cheap_run = 0;
        let outcome = loop {
            // Always a buffer here, whatever order the driver gives them
            // back in: slot `next` holds one while fewer than `N` are in
            // flight, and once `N - 1` are, the wait before each start
            // fills the slot after. (Were it empty, the frame would end
            // here rather than panic.)
            let Some(mut tile) = slots[*next].take() else {
                break Ok(());
            };
            let pick = if N == 2 {
                Pick::InOrder
            } else if cheap_run < N - 2 {
                Pick::Spread
            } else {
                Pick::Dear
            };
            let Some((area, cheap)) = self.render_picked(tile.borrow_mut(), &mut (), pick) else {
                slots[*next] = Some(tile);
                return Ok(self.stats());
            };
            cheap_run = if cheap { cheap_run + 1 } else { 0 };
            let after = (*next + 1) % N;
            if *in_flight == N - 1 {
                let (done, result) = transfer.wait();
                *in_flight -= 1;
                put_back(slots, after, done);
                if let Err(e) = result {
                    slots[*next] = Some(tile);
                    break Err(e);
                }
            }
            if let Err((e, back)) = transfer.start(&area, tile) {
                slots[*next] = Some(back);
                break Err(e);
            }
            *in_flight += 1;
            *next = after;
        };
        // An error (or a slot left empty by a driver that kept a buffer):
        // the tiles still in flight are waited for, so that none is left
        // with the driver. The first error is the one returned.
        let sent = queue.flush(transfer);
        match outcome.and(sent) {
            Ok(()) => Ok(self.stats()),
            Err(e) => Err(RenderError::Sink(e)),
        }
    }
}

/// `N` tile buffers and which of them are in flight in a
/// [`TileTransfer`], kept from frame to frame by
/// [`Frame::render_to_queue`] (and its
/// [`Renderer`](Renderer::render_to_queue) form), so that a frame's last
/// tiles are sent while the next frame begins.
///
/// Tile `k` (counting across frames) is drawn into slot `k % N`; the
/// transfer gives buffers back oldest first, so the oldest tile in flight
/// is the one drawn `in_flight` tiles before the next, and its buffer goes
/// back to its slot.
#[derive(Debug)]
pub struct TileQueue<B, const N: usize> {
    /// The buffers not in flight.
    slots: [Option<B>; N],
    /// The slot the next tile is drawn into.
    next: usize,
    /// Tiles started and not yet waited for.
    in_flight: usize,
}

impl<B, const N: usize> TileQueue<B, N> {
    /// A queue of the `N` buffers `tiles`, none in flight.
    pub fn new(tiles: [B; N]) -> Self {
        Self {
            slots: tiles.map(Some),
            next: 0,
            in_flight: 0,
        }
    }

    /// How many tiles are in flight: started and not yet waited for.
    pub fn in_flight(&self) -> usize {
        self.in_flight
    }

    /// Waits for every tile in flight, oldest first, and gives the `N`
    /// buffers back (in any order) with the first transfer error among
    /// them.
    #[must_use = "the tile buffers come back with the transfers' result"]
    pub fn into_tiles<X: TileTransfer<B>>(
        mut self,
        transfer: &mut X,
    ) -> ([B; N], Result<(), X::Error>) {
        let sent = self.flush(transfer);
        // Every slot is full now: `N` buffers came back into `N` slots. (A
        // slot that were not would take one more buffer from the driver
        // rather than panic.)
        let tiles = self
            .slots
            .map(|slot| slot.unwrap_or_else(|| transfer.wait().0));
        (tiles, sent)
    }

    /// Waits for every tile in flight, oldest first (the one drawn
    /// `in_flight` tiles before the next), each buffer back into the
    /// queue, and returns the first transfer error among them: for a
    /// caller that must know the frame is on the panel (before lighting
    /// it, say) or the wire idle.
    pub fn flush<X: TileTransfer<B>>(&mut self, transfer: &mut X) -> Result<(), X::Error> {
        let mut outcome = Ok(());
        while self.in_flight > 0 {
            let (done, result) = transfer.wait();
            put_back(&mut self.slots, (self.next + N - self.in_flight) % N, done);
            self.in_flight -= 1;
            outcome = outcome.and(result);
        }
        outcome
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
    /// `cheap` (in visiting order) over `N` buffers: a cheap tile while
    /// the share of cheap tiles taken is at most that of dear ones, at
    /// most `N - 2` in a row, each kind in visiting order, the other kind
    /// when one runs out; visiting order for two buffers.
    fn policy<const N: usize>(tiles: &[(Rectangle, bool)]) -> Vec<Rectangle, 64> {
        let cheap: Vec<_, 64> = tiles.iter().filter(|t| t.1).map(|t| t.0).collect();
        let dear: Vec<_, 64> = tiles.iter().filter(|t| !t.1).map(|t| t.0).collect();
        if N == 2 {
            return tiles.iter().map(|t| t.0).collect();
        }
        let (mut c, mut d, mut run) = (0, 0, 0);
        let mut out = Vec::new();
        while c + d < tiles.len() {
            let take_cheap = if c == cheap.len() || d == dear.len() {
                d == dear.len()
            } else {
                run < N - 2 && c * dear.len() <= d * cheap.len()
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

    /// `render_queued` spreads the tiles with an empty bin evenly between
    /// those with triangles, at most `N - 2` in a row, so that a run of
    /// empty tiles (drawn in no time) does not make the core wait for the
    /// wire while it could be drawing: every tile once, each kind in
    /// visiting order.
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
