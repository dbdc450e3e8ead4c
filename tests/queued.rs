//! Queued streaming: a frame sent through `render_queued` over `N` tile
//! buffers, to a fake DMA queue whose tiles complete only later (each
//! tile's pixels are read from its buffer when it is waited for, oldest
//! first), delivers every tile once (in visiting order for two buffers), with the pixels
//! of `Renderer::render`; never more than `N - 1` tiles are in flight, a
//! buffer is never drawn into while it is, and every error gives all `N`
//! buffers back with nothing left in flight.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use microraster::prelude::*;
use std::rc::Rc;
use support::dma::{self, buffers, ids, FakeDma, Shared, WireError};
use support::Order;

type Tile = dma::Tile<Rgb565>;
type Queue<'t> = FakeDma<'t, Rgb565>;

/// The scene through `render_queued` over `N` buffers: every tile once
/// (in `render`'s order for two) and with its pixels and statistics, at most
/// `N - 1` in flight (and that many reached), the buffers in turn.
fn queued<const N: usize, const B: usize, const T: usize>(
    scene: &Scene<'_>,
    config: Config<Rgb565>,
) -> FrameStats {
    let mut renderer: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, B, T>> = Box::new(Workspace::new());
    let mut sink = Order::new(config.size, config.clear_color);
    let stats = renderer.render(&mut ws, scene, &mut sink).unwrap();

    let book: Shared = Rc::default();
    let mut store: Box<[Tile; N]> = Box::new(core::array::from_fn(|k| {
        Tile::new(Rgb565::new(k as u8, 63, 0))
    }));
    let mut queue = Queue::new(config.size, N - 1, &book, Rgb565::new(31, 0, 31));
    let (back, result) =
        renderer.render_queued(&mut ws, scene, buffers(&mut store, &book), &mut queue);
    assert_eq!(result.unwrap(), stats, "the same statistics");
    assert_eq!(ids(&back), (0..N).collect::<Vec<_>>(), "every buffer back");
    assert!(queue.queue.is_empty(), "nothing in flight");
    // Two buffers keep the visiting order; more may take tiles with an
    // empty bin ahead within a binning pass (the order itself is tested
    // in src/sink/queue.rs).
    if N == 2 {
        assert_eq!(queue.order, sink.0, "every tile once, in visiting order");
    } else {
        let key = |r: &Rectangle| (r.top_left.y, r.top_left.x);
        let (mut sent, mut want) = (queue.order.clone(), sink.0.clone());
        sent.sort_by_key(key);
        want.sort_by_key(key);
        assert_eq!(sent, want, "every tile once");
    }
    queue.frame.assert_once_and_equal(&sink.1);

    let book = book.borrow();
    assert_eq!(
        book.most,
        (N - 1).min(sink.0.len()),
        "up to N - 1 in flight"
    );
    // Tile k from buffer k % N (the last draw finds no tile).
    for (k, &id) in book.draws().iter().enumerate() {
        assert_eq!(id, k % N, "draw {k}");
    }
    assert_eq!(book.draws().len(), sink.0.len() + 1);
    // Draw, wait only with N - 1 in flight, start; at the end the last
    // (empty) draw and the waits for what is still in flight.
    let n = sink.0.len();
    let mut want = String::new();
    for k in 0..n {
        want.push('d');
        want.push_str(if k >= N - 1 { "ws" } else { "s" });
    }
    want.push('d');
    want.push_str(&"w".repeat(n.min(N - 1)));
    assert_eq!(book.calls, want);
    stats
}

fn scene_of<'a>(draws: &'a [Draw<'a>], size: Size) -> Scene<'a> {
    Scene::new(camera(size.width, size.height), draws).light(light())
}

#[test]
fn queued_frames_match_render_for_every_depth() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.7, Shading::Gouraud);
    // Not a multiple of the tile size: edge tiles are packed and short.
    let size = Size::new(317, 233);
    let scene = scene_of(&d, size);
    let config = Config::new(size, Rgb565::new(2, 4, 6));
    let s = queued::<3, 8192, 80>(&scene, config);
    assert_eq!((s.bin_passes, s.tiles), (1, 80));
    assert!(s.pixels_shaded > 10_000, "{s:?}");
    queued::<2, 8192, 80>(&scene, config);
    queued::<4, 8192, 80>(&scene, config.tile_order(TileOrder::Hilbert));
    queued::<6, 8192, 80>(&scene, config);
    // Many binning passes, and more buffers than tiles.
    let s = queued::<5, 8192, 7>(&scene, config);
    assert!(s.bin_passes >= 12, "{s:?}");
    queued::<4, 64, 80>(&scene, config.tile_order(TileOrder::Hilbert));
    let small = Size::new(40, 30);
    queued::<8, 8192, 80>(
        &scene_of(&d, small),
        Config::new(small, Rgb565::new(2, 4, 6)),
    );
}

/// A frame over `N` buffers whose transfer fails at tile `k`'s start or
/// wait: the error comes back typed, no tile is started after it, every
/// tile started is waited for, and all `N` buffers come back. Returns
/// the tiles started and the calls.
fn failing<const N: usize>(fail_start: Option<usize>, fail_wait: Option<usize>) -> (usize, String) {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(160, 96); // 15 tiles
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 1024, 16>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store: Box<[Tile; N]> = Box::new(core::array::from_fn(|_| Tile::new(Rgb565::BLACK)));
    let mut queue = Queue::new(size, N - 1, &book, Rgb565::new(31, 0, 31));
    queue.fail_start = fail_start;
    queue.fail_wait = fail_wait;
    let (back, result) = renderer.render_queued(
        &mut ws,
        &scene_of(&d, size),
        buffers(&mut store, &book),
        &mut queue,
    );
    let k = fail_start.or(fail_wait).unwrap();
    assert_eq!(result, Err(RenderError::Sink(WireError(k))));
    assert_eq!(ids(&back), (0..N).collect::<Vec<_>>(), "every buffer back");
    assert!(queue.queue.is_empty(), "nothing left in flight");
    assert_eq!(
        queue.waited, queue.started,
        "every tile started is waited for"
    );
    let calls = book.borrow().calls.clone();
    (queue.started, calls)
}

#[test]
fn a_failed_transfer_gives_every_buffer_back() {
    // `d` draw, `w` wait, `s` start (also a failed one).
    let calls =
        |parts: &[(&str, usize)]| -> String { parts.iter().map(|(p, n)| p.repeat(*n)).collect() };
    // Tile 5's start fails, after tile 2 was waited for to make room:
    // tiles 3 and 4 are still waited for, nothing more is drawn.
    let want = calls(&[("ds", 3), ("dws", 3), ("w", 2)]);
    assert_eq!(failing::<4>(Some(5), None), (5, want));
    // The first start.
    assert_eq!(failing::<3>(Some(0), None), (0, "ds".into()));
    // Tile 2's wait fails, to make room for tile 7: tile 7 is never
    // started, tiles 3 to 6 are waited for.
    let want = calls(&[("ds", 5), ("dws", 2), ("dw", 1), ("w", 4)]);
    assert_eq!(failing::<6>(None, Some(2)), (7, want));
    // Tile 12's wait, among those at the end of the frame (15 tiles): the
    // two after it are still waited for.
    let want = calls(&[("ds", 3), ("dws", 12), ("dwww", 1)]);
    assert_eq!(failing::<4>(None, Some(12)), (15, want));
    // Two buffers: the calls of `render_double_buffered` (tile 5 drawn,
    // never started).
    let want = calls(&[("ds", 1), ("dws", 4), ("dw", 1)]);
    assert_eq!(failing::<2>(None, Some(4)), (5, want));
}

#[test]
fn scene_errors_come_back_before_any_transfer_with_every_buffer() {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(64, 64);
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Workspace<4, 64, 4> = Workspace::new();
    let book: Shared = Rc::default();
    let mut store: Box<[Tile; 3]> = Box::new(core::array::from_fn(|_| Tile::new(Rgb565::BLACK)));
    let mut queue = Queue::new(size, 2, &book, Rgb565::new(31, 0, 31));
    let (back, result) = renderer.render_queued(
        &mut ws,
        &scene_of(&d, size),
        buffers(&mut store, &book),
        &mut queue,
    );
    assert!(matches!(result, Err(RenderError::VertexCapacity { .. })));
    assert_eq!(back.map(|b| b.id), [0, 1, 2]);
    assert!(book.borrow().calls.is_empty());
}

/// A driver that breaks the FIFO contract, giving the newest tile back
/// first, still gets every tile once and gives every buffer back, and
/// the renderer never draws into a buffer in flight.
#[test]
fn buffers_given_back_out_of_order_are_used_all_the_same() {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(160, 96);
    let scene = scene_of(&d, size);
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 1024, 16>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store: Box<[Tile; 4]> = Box::new(core::array::from_fn(|_| Tile::new(Rgb565::BLACK)));
    let mut queue = Queue::new(size, 3, &book, Rgb565::new(31, 0, 31));
    queue.newest_first = true;
    let (back, result) =
        renderer.render_queued(&mut ws, &scene, buffers(&mut store, &book), &mut queue);
    assert_eq!(result.unwrap().tiles, 15);
    assert_eq!(ids(&back), [0, 1, 2, 3], "every buffer back");
    assert!(queue.queue.is_empty(), "nothing in flight");
    assert_eq!((queue.started, queue.waited), (15, 15));
    assert_eq!(book.borrow().most, 3);
}

/// Frames through one `TileQueue` (`render_to_queue`): each returns with
/// its last `N - 1` tiles in flight, which the next frame waits for as it
/// needs their buffers; no buffer is drawn into while in flight, never
/// more than `N - 1` are, each frame's statistics are `render`'s, and once
/// the queue is emptied the panel holds the last frame.
#[test]
fn a_kept_queue_sends_each_frames_last_tiles_during_the_next() {
    const N: usize = 4;
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let size = Size::new(160, 96); // 15 tiles
    let config = Config::new(size, Rgb565::new(2, 4, 6));
    let mut renderer: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, 8192, 16>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store: Box<[Tile; N]> = Box::new(core::array::from_fn(|_| Tile::new(Rgb565::BLACK)));
    let mut dma = Queue::new(size, N - 1, &book, Rgb565::new(31, 0, 31));
    let mut queue = TileQueue::new(buffers(&mut store, &book));
    let times = [0.1, 0.5, 0.9];
    let mut last = Order::new(size, config.clear_color);
    let mut first = Order::new(size, config.clear_color);
    for (i, &t) in times.iter().enumerate() {
        let d = draws(&knot, &cube, t, Shading::Gouraud);
        let scene = scene_of(&d, size);
        let mut sink = Order::new(size, config.clear_color);
        let want = renderer.render(&mut ws, &scene, &mut sink).unwrap();
        let stats = renderer
            .render_to_queue(&mut ws, &scene, &mut queue, &mut dma)
            .unwrap();
        assert_eq!(stats, want, "frame {i}");
        assert_eq!(queue.in_flight(), N - 1, "frame {i}'s last tiles in flight");
        assert_eq!(dma.queue.len(), N - 1);
        assert_eq!(dma.started, 15 * (i + 1));
        if i == 0 {
            first = sink;
        } else {
            last = sink;
        }
    }
    let (back, sent) = queue.into_tiles(&mut dma);
    assert_eq!(sent, Ok(()));
    assert_eq!(ids(&back), (0..N).collect::<Vec<_>>(), "every buffer back");
    assert!(dma.queue.is_empty(), "nothing in flight");
    assert_eq!((dma.started, dma.waited), (45, 45));
    assert_eq!(book.borrow().most, N - 1);
    // Tile k (counted across frames) from buffer k % N: the queue goes on
    // where the frame before left it. Each frame's last draw finds no
    // tile and leaves its buffer for the next frame's first.
    let draws = book.borrow().draws();
    assert_eq!(draws.len(), 3 * 16);
    for (j, &id) in draws.iter().enumerate() {
        let (frame, m) = (j / 16, j % 16);
        assert_eq!(id, (15 * frame + m) % N, "frame {frame}, draw {m}");
    }
    // Every pixel sent once a frame, the last frame's last.
    assert!(dma.frame.writes.iter().all(|&w| w == 3));
    assert_ne!(first.1.pixels, last.1.pixels, "the frames differ");
    assert_eq!(
        dma.frame.pixels, last.1.pixels,
        "the panel shows the last frame"
    );
}

/// A tile of the frame before that fails when the next frame waits for
/// it: that frame returns the error, starts nothing more, and leaves
/// nothing in flight; every buffer comes back.
#[test]
fn an_error_of_the_frame_before_comes_back_from_the_next() {
    const N: usize = 4;
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(160, 96); // 15 tiles
    let scene = scene_of(&d, size);
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 1024, 16>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store: Box<[Tile; N]> = Box::new(core::array::from_fn(|_| Tile::new(Rgb565::BLACK)));
    let mut dma = Queue::new(size, N - 1, &book, Rgb565::new(31, 0, 31));
    // Tiles 12, 13 and 14 are in flight when the first frame returns.
    dma.fail_wait = Some(13);
    let mut queue = TileQueue::new(buffers(&mut store, &book));
    let first = renderer.render_to_queue(&mut ws, &scene, &mut queue, &mut dma);
    assert_eq!(first.unwrap().tiles, 15);
    assert_eq!(queue.in_flight(), 3);
    book.borrow_mut().calls.clear();
    let second = renderer.render_to_queue(&mut ws, &scene, &mut queue, &mut dma);
    assert_eq!(second, Err(RenderError::Sink(WireError(13))));
    // Tile 15 drawn, 12 waited for, 15 started; tile 16 drawn, 13's wait
    // fails; 14 and 15 are waited for.
    assert_eq!(book.borrow().calls, "dwsdwww");
    assert_eq!(queue.in_flight(), 0);
    assert!(dma.queue.is_empty(), "nothing left in flight");
    assert_eq!((dma.started, dma.waited), (16, 16));
    let (back, sent) = queue.into_tiles(&mut dma);
    assert_eq!(sent, Ok(()));
    assert_eq!(ids(&back), (0..N).collect::<Vec<_>>(), "every buffer back");
}
