//! A DMA queue on the host for `render_double_buffered` and
//! `render_queued`: `start` packs the tile and queues its buffer; a tile
//! "arrives" only when it is waited for, oldest first, read from its
//! buffer then, so a buffer drawn into while in flight would show. With a
//! depth of one it is a double-buffered channel; of `N - 1`, the queue of
//! `N` buffers.

use super::Capture;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microraster::prelude::*;
use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

pub type Tile<C> = TileBuffer<C, 32, 32>;

/// What happened to the buffers, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// The renderer took buffer `n` to draw into.
    Draw(usize),
    /// The transfer started sending buffer `n`, holding tile `area`.
    Start(usize, Rectangle),
    /// The transfer of buffer `n` completed (or failed) when waited for.
    Done(usize),
}

/// What the queue saw, shared with the buffer handles.
#[derive(Default)]
pub struct Book {
    /// The ids of the buffers in flight, oldest first.
    pub in_flight: VecDeque<usize>,
    /// The most tiles ever in flight at once.
    pub most: usize,
    /// Draws, successful starts and waits.
    pub events: Vec<Event>,
    /// Each call, in order: `d` a draw, `s` a start (a failed one too),
    /// `w` a wait.
    pub calls: String,
}

impl Book {
    /// The ids of the buffers drawn into, in order.
    pub fn draws(&self) -> Vec<usize> {
        let draw = |e: &Event| match *e {
            Event::Draw(id) => Some(id),
            _ => None,
        };
        self.events.iter().filter_map(draw).collect()
    }
}

pub type Shared = Rc<RefCell<Book>>;

/// A buffer handle that checks, each time the renderer draws into it,
/// that it is not in flight, and logs the draw.
pub struct Buffer<'t, C> {
    pub id: usize,
    pub tile: &'t mut Tile<C>,
    pub book: Shared,
}

impl<C> core::borrow::Borrow<Tile<C>> for Buffer<'_, C> {
    fn borrow(&self) -> &Tile<C> {
        self.tile
    }
}

impl<C> core::borrow::BorrowMut<Tile<C>> for Buffer<'_, C> {
    fn borrow_mut(&mut self) -> &mut Tile<C> {
        let mut book = RefCell::borrow_mut(&self.book);
        assert!(
            !book.in_flight.contains(&self.id),
            "buffer {} drawn into while in flight",
            self.id
        );
        book.events.push(Event::Draw(self.id));
        book.calls.push('d');
        self.tile
    }
}

/// `N` handles over `store`, under ids `0..N`.
pub fn buffers<'t, C, const N: usize>(
    store: &'t mut [Tile<C>; N],
    book: &Shared,
) -> [Buffer<'t, C>; N] {
    let mut it = store.iter_mut().enumerate();
    core::array::from_fn(|_| {
        let (id, tile) = it.next().expect("N tiles for N handles");
        Buffer {
            id,
            tile,
            book: book.clone(),
        }
    })
}

/// The ids of the buffers given back, sorted.
pub fn ids<C, const N: usize>(back: &[Buffer<'_, C>; N]) -> Vec<usize> {
    let mut ids: Vec<usize> = back.iter().map(|b| b.id).collect();
    ids.sort();
    ids
}

#[derive(Debug, PartialEq, Eq)]
pub struct WireError(pub usize);

/// The queue: at most `depth` tiles in flight.
pub struct FakeDma<'t, C> {
    pub queue: VecDeque<(Buffer<'t, C>, Rectangle)>,
    depth: usize,
    /// The frame as the tiles arrived.
    pub frame: Capture<C>,
    /// The areas of the tiles started, in order.
    pub order: Vec<Rectangle>,
    book: Shared,
    /// Fail the start of this tile (counted from 0 among the starts), or
    /// the wait of this one (among the waits).
    pub fail_start: Option<usize>,
    pub fail_wait: Option<usize>,
    /// Give the newest tile back first, against the contract.
    pub newest_first: bool,
    pub started: usize,
    pub waited: usize,
}

impl<C: PixelColor> FakeDma<'_, C> {
    pub fn new(size: Size, depth: usize, book: &Shared, background: C) -> Self {
        Self {
            queue: VecDeque::new(),
            depth,
            frame: Capture::new(size, background),
            order: Vec::new(),
            book: book.clone(),
            fail_start: None,
            fail_wait: None,
            newest_first: false,
            started: 0,
            waited: 0,
        }
    }
}

impl<'t, C: PixelColor> TileTransfer<Buffer<'t, C>> for FakeDma<'t, C> {
    type Error = WireError;

    fn start(
        &mut self,
        area: &Rectangle,
        tile: Buffer<'t, C>,
    ) -> Result<(), (WireError, Buffer<'t, C>)> {
        let mut book = self.book.borrow_mut();
        book.calls.push('s');
        assert!(
            self.queue.len() < self.depth,
            "a start with {} tiles in flight",
            self.depth
        );
        let k = self.started;
        if self.fail_start == Some(k) {
            return Err((WireError(k), tile));
        }
        self.started += 1;
        // What a DMA driver does: one block, then the channel is started.
        let packed = tile.tile.pack(area).len();
        assert_eq!(packed, (area.size.width * area.size.height) as usize);
        book.events.push(Event::Start(tile.id, *area));
        book.in_flight.push_back(tile.id);
        book.most = book.most.max(book.in_flight.len());
        self.order.push(*area);
        self.queue.push_back((tile, *area));
        Ok(())
    }

    fn wait(&mut self) -> (Buffer<'t, C>, Result<(), WireError>) {
        let (tile, area) = match self.newest_first {
            false => self.queue.pop_front(),
            true => self.queue.pop_back(),
        }
        .expect("wait with nothing in flight");
        let mut book = self.book.borrow_mut();
        book.calls.push('w');
        book.events.push(Event::Done(tile.id));
        book.in_flight.retain(|&id| id != tile.id);
        let k = self.waited;
        self.waited += 1;
        if self.fail_wait == Some(k) {
            return (tile, Err(WireError(k)));
        }
        // The bytes go out now, from the packed block (`pack` of a
        // whole-width area moves nothing, so the view reads it back).
        let whole = Rectangle::new(Point::zero(), Size::new(32, 32));
        let block: Vec<C> = tile.tile.view(&whole).pixels().collect();
        let n = (area.size.width * area.size.height) as usize;
        let width = area.size.width as usize;
        for (i, &c) in block[..n].iter().enumerate() {
            let x = area.top_left.x as u32 + (i % width) as u32;
            let y = area.top_left.y as u32 + (i / width) as u32;
            let at = (y * self.frame.size.width + x) as usize;
            self.frame.pixels[at] = c;
            self.frame.writes[at] += 1;
        }
        (tile, Ok(()))
    }
}
