//! Double-buffered streaming: a frame sent through a `TileTransfer` (a fake
//! DMA channel that completes a tile only when it is waited for) or an
//! `AsyncTileSink` (whose writes pend) delivers every tile once, in
//! visiting order, from the two buffers in turn, drawing each tile only
//! into the buffer that is not in flight, with the pixels of
//! `Renderer::render`; a failed transfer stops the frame with nothing in
//! flight. Tiles in the wire format (`Rgb565Be`) are Rgb565 byte-swapped.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use core::future::Future;
use core::pin::{pin, Pin};
use core::task::{Context, Poll, Waker};
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use microraster::embedded_graphics::prelude::IntoStorage;
use microraster::prelude::*;
use microraster::shader::Dithered;
use microraster::sink::wire::{self, Window, CASET, RAMWR, RASET};
use std::rc::Rc;
use support::dma::{self, buffers, ids, Event, FakeDma, Shared, WireError};
use support::{Capture, Order};

type Tile<C> = dma::Tile<C>;

/// `render`'s tiles in order and its frame.
fn reference<C, const B: usize, const T: usize>(
    scene: &Scene<'_, impl ShaderSet<C>>,
    config: Config<C>,
) -> (Vec<Rectangle>, Capture<C>, FrameStats)
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
{
    let mut renderer: Renderer<C, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, B, T>> = Box::new(Workspace::new());
    let mut sink = Order::new(config.size, config.clear_color);
    let stats = renderer.render(&mut ws, scene, &mut sink).unwrap();
    (sink.0, sink.1, stats)
}

/// The scene sent through the fake DMA channel; checks the order of
/// events, every tile and every pixel against `render`'s.
fn double_buffered<const B: usize, const T: usize>(
    scene: &Scene<'_>,
    config: Config<Rgb565>,
) -> FrameStats {
    let (order, expected, stats) = reference::<Rgb565, B, T>(scene, config);
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, B, T>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store = Box::new([
        Tile::new(Rgb565::new(0, 63, 0)),
        Tile::new(Rgb565::new(0, 0, 31)),
    ]);
    let mut dma = FakeDma::new(config.size, 1, &book, Rgb565::new(31, 0, 31));
    let tiles = buffers(&mut store, &book);
    let (back, result) = renderer.render_double_buffered(&mut ws, scene, tiles, &mut dma);
    assert_eq!(result.unwrap(), stats, "the same statistics");
    assert_eq!(ids(&back), [0, 1], "both buffers come back");
    assert!(dma.queue.is_empty());

    // Every tile once, in visiting order, from the buffers in turn.
    let log = &book.borrow().events;
    let starts: Vec<(usize, Rectangle)> = log
        .iter()
        .filter_map(|e| match *e {
            Event::Start(id, area) => Some((id, area)),
            _ => None,
        })
        .collect();
    assert_eq!(starts.iter().map(|s| s.1).collect::<Vec<_>>(), order);
    for (k, s) in starts.iter().enumerate() {
        assert_eq!(s.0, k % 2, "tile {k} from buffer {}", s.0);
    }
    // Draw into one buffer while the other is in flight: the first tile,
    // then per tile start, draw the next (the last draw finds none), done.
    let mut want = vec![Event::Draw(0)];
    for (k, &(id, area)) in starts.iter().enumerate() {
        want.extend([
            Event::Start(id, area),
            Event::Draw(1 - k % 2),
            Event::Done(id),
        ]);
    }
    assert_eq!(*log, want);

    dma.frame.assert_once_and_equal(&expected);
    stats
}

fn demo<'a>(knot: &'a Mesh<'a>, cube: &'a Mesh<'a>, t: f32) -> [Draw<'a>; 2] {
    draws(knot, cube, t, Shading::Gouraud)
}

/// Runs `f` on the demo scene at time `t`, with its config, at a size that
/// is not a multiple of the tile size: the right column's tiles are packed,
/// the bottom row's are short.
fn with_odd_size_scene(t: f32, f: impl FnOnce(&Scene<'_>, Config<Rgb565>)) {
    let size = Size::new(317, 233);
    with_demo_scene(t, size, |scene| {
        f(scene, Config::new(size, Rgb565::new(2, 4, 6)));
    });
}

#[test]
fn double_buffered_frames_match_render_in_both_tile_orders() {
    with_odd_size_scene(0.7, |scene, config| {
        let s = double_buffered::<8192, 80>(scene, config);
        assert_eq!((s.bin_passes, s.tiles), (1, 80));
        assert!(s.pixels_shaded > 10_000, "{s:?}");
        double_buffered::<8192, 80>(scene, config.tile_order(TileOrder::Hilbert));
    });
}

#[test]
fn double_buffered_frames_match_render_over_many_passes() {
    with_odd_size_scene(1.3, |scene, config| {
        let s = double_buffered::<8192, 7>(scene, config);
        assert!(s.bin_passes >= 12, "{s:?}");
        let s = double_buffered::<64, 80>(scene, config.tile_order(TileOrder::Hilbert));
        assert!(s.bin_passes > 12 && s.rescanned_tiles > 0, "{s:?}");
    });
}

/// A double-buffered frame whose transfer fails at tile `k`'s start or
/// wait: the error comes back typed, no tile is started after it, nothing
/// is left in flight, and both buffers come back.
fn failing(fail_start: Option<usize>, fail_wait: Option<usize>) -> (usize, Vec<Event>) {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(160, 96);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 1024, 16>> = Box::new(Workspace::new());
    let book: Shared = Rc::default();
    let mut store = [Tile::new(Rgb565::BLACK), Tile::new(Rgb565::BLACK)];
    let mut dma = FakeDma::new(size, 1, &book, Rgb565::BLACK);
    dma.fail_start = fail_start;
    dma.fail_wait = fail_wait;
    let tiles = buffers(&mut store, &book);
    let (back, result) = renderer.render_double_buffered(&mut ws, &scene, tiles, &mut dma);
    let k = fail_start.or(fail_wait).unwrap();
    assert_eq!(result, Err(RenderError::Sink(WireError(k))));
    assert_eq!(ids(&back), [0, 1], "both buffers come back");
    assert!(dma.queue.is_empty(), "nothing left in flight");
    let events = book.borrow().events.clone();
    (dma.started, events)
}

#[test]
fn a_failed_transfer_stops_the_frame_cleanly() {
    // The start of tile 3 fails: tiles 0..3 were sent, and the last event
    // is the wait for tile 2.
    let (started, log) = failing(Some(3), None);
    assert_eq!(started, 3);
    assert_eq!(log.last(), Some(&Event::Done(0)));
    // The first tile's start.
    let (started, log) = failing(Some(0), None);
    assert_eq!((started, log), (0, vec![Event::Draw(0)]));
    // Tile 4's transfer fails when waited for: tile 5 was drawn, never
    // started.
    let (started, log) = failing(None, Some(4));
    assert_eq!(started, 5);
    assert_eq!(&log[log.len() - 2..], [Event::Draw(1), Event::Done(0)]);
    // The last tile's transfer (15 tiles of 32x32 in 160x96).
    let (started, log) = failing(None, Some(14));
    assert_eq!(started, 15);
    assert_eq!(log.last(), Some(&Event::Done(0)));
}

#[test]
fn scene_errors_come_back_before_any_transfer_with_the_buffers() {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let scene = Scene::new(camera(64, 64), &d);
    let renderer: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(Size::new(64, 64), Rgb565::BLACK));
    let mut ws: Workspace<4, 64, 4> = Workspace::new();
    let book: Shared = Rc::default();
    let mut store = [Tile::new(Rgb565::BLACK), Tile::new(Rgb565::BLACK)];
    let mut dma = FakeDma::new(Size::new(64, 64), 1, &book, Rgb565::BLACK);
    let tiles = buffers(&mut store, &book);
    let (back, result) = renderer.render_double_buffered(&mut ws, &scene, tiles, &mut dma);
    assert!(matches!(result, Err(RenderError::VertexCapacity { .. })));
    assert_eq!(back.map(|t| t.id), [0, 1]);
    assert!(book.borrow().events.is_empty());
}

// ---- The async form ----

/// A future that is pending on its first `n` polls (waking its task each
/// time), then ready: a transfer that completes "later".
struct Pend(u32);

impl Future for Pend {
    type Output = ();
    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<()> {
        if self.0 == 0 {
            return Poll::Ready(());
        }
        self.0 -= 1;
        cx.waker().wake_by_ref();
        Poll::Pending
    }
}

/// An async sink whose every write pends `pends` times: it records the
/// start of each tile (its first poll), and copies the pixels when it
/// completes.
struct AsyncFake<C> {
    frame: Capture<C>,
    order: Vec<Rectangle>,
    /// The address of each tile's block, to tell the buffers apart.
    blocks: Vec<usize>,
    events: Vec<&'static str>,
    fail_at: Option<usize>,
    pends: u32,
}

impl<C: PixelColor> AsyncTileSink<C> for AsyncFake<C> {
    type Error = WireError;
    async fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, C>,
    ) -> Result<(), WireError> {
        let k = self.order.len();
        self.order.push(*area);
        let block = tile.contiguous().expect("a packed tile");
        self.blocks.push(block.as_ptr() as usize);
        self.events.push("start");
        if self.fail_at == Some(k) {
            return Err(WireError(k));
        }
        Pend(self.pends).await;
        self.events.push("done");
        self.frame
            .fill_contiguous(area, block.iter().copied())
            .unwrap();
        Ok(())
    }
}

/// Runs `future` to completion on this thread: polls until ready and
/// counts the polls.
fn block_on<F: Future>(future: F) -> (F::Output, usize) {
    let mut future = pin!(future);
    let mut cx = Context::from_waker(Waker::noop());
    let mut polls = 0;
    loop {
        polls += 1;
        if let Poll::Ready(out) = future.as_mut().poll(&mut cx) {
            return (out, polls);
        }
    }
}

fn async_frame<const B: usize, const T: usize>(
    scene: &Scene<'_>,
    config: Config<Rgb565>,
    pends: u32,
) {
    let (order, expected, stats) = reference::<Rgb565, B, T>(scene, config);
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, B, T>> = Box::new(Workspace::new());
    let mut tiles = Box::new([Tile::new(Rgb565::GREEN), Tile::new(Rgb565::BLUE)]);
    let mut sink = AsyncFake {
        frame: Capture::new(config.size, Rgb565::new(31, 0, 31)),
        order: Vec::new(),
        blocks: Vec::new(),
        events: Vec::new(),
        fail_at: None,
        pends,
    };
    let (result, polls) = block_on(renderer.render_async(&mut ws, scene, &mut tiles, &mut sink));
    assert_eq!(result.unwrap(), stats);
    // The write's first poll starts it, before the next tile is drawn;
    // the await after the drawing polls it again, and the frame is
    // suspended only while the write is still pending after that.
    let suspended = order.len() * pends.saturating_sub(1) as usize;
    assert_eq!(polls, suspended + 1);
    assert_eq!(sink.order, order, "every tile once, in visiting order");
    let n = order.len();
    assert_eq!(sink.events, ["start", "done"].repeat(n));
    let (a, b) = (sink.blocks[0], sink.blocks[1]);
    assert_ne!(a, b);
    for (k, &block) in sink.blocks.iter().enumerate() {
        assert_eq!(block, [a, b][k % 2], "tile {k} from the other buffer");
    }
    sink.frame.assert_once_and_equal(&expected);
}

#[test]
fn async_frames_match_render() {
    with_odd_size_scene(0.4, |scene, config| {
        for pends in [0, 1, 2, 3] {
            async_frame::<8192, 80>(scene, config, pends);
        }
        async_frame::<8192, 80>(scene, config.tile_order(TileOrder::Hilbert), 2);
        async_frame::<64, 80>(scene, config, 2);
    });
}

#[test]
fn an_async_sink_error_stops_the_frame() {
    let cube = cube();
    let d = [Draw::new(&cube)];
    let size = Size::new(160, 96);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    let renderer: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, Rgb565::BLACK));
    let mut ws: Box<Workspace<2048, 1024, 16>> = Box::new(Workspace::new());
    let mut tiles = Box::new([Tile::new(Rgb565::BLACK), Tile::new(Rgb565::BLACK)]);
    let mut sink = AsyncFake {
        frame: Capture::new(size, Rgb565::BLACK),
        order: Vec::new(),
        blocks: Vec::new(),
        events: Vec::new(),
        fail_at: Some(6),
        pends: 2,
    };
    let (result, _) = block_on(renderer.render_async(&mut ws, &scene, &mut tiles, &mut sink));
    assert_eq!(result, Err(RenderError::Sink(WireError(6))));
    assert_eq!(sink.order.len(), 7, "no write after the failed one");
}

// ---- The wire format ----

/// The scene rendered in Rgb565 and in Rgb565Be: every pixel's wire bytes
/// are the Rgb565 pixel's bits, high byte first.
fn wire_matches<F>(scene: &Scene<'_, F>, size: Size)
where
    F: ShaderSet<Rgb565> + ShaderSet<Rgb565Be>,
{
    let clear = Rgb565::new(3, 7, 11);
    let (_, native, _) = reference::<Rgb565, 8192, 80>(scene, Config::new(size, clear));
    let (_, wire, _) = reference::<Rgb565Be, 8192, 80>(scene, Config::new(size, clear.into()));
    let mut differ = 0;
    for (n, w) in native.pixels.iter().zip(&wire.pixels) {
        // High byte first; on this little-endian host, the native pixel's
        // bytes in memory swapped.
        let [lo, hi] = n.into_storage().to_le_bytes();
        differ += usize::from(w.to_be_bytes() != [hi, lo]);
        differ += usize::from(Rgb565::from(*w) != *n);
    }
    assert_eq!(differ, 0);
    assert!(
        native.pixels.iter().any(|&c| c != clear),
        "something is drawn"
    );
}

#[test]
fn wire_format_tiles_are_rgb565_byte_swapped() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let size = Size::new(200, 150);
    let d = demo(&knot, &cube, 0.9);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    wire_matches(&scene, size);
    // Through a shader with ordered dithering, which has its own
    // conversion.
    let d = draws(&knot, &cube, 0.9, Shading::Shader);
    let dithered = Dithered(Gouraud);
    let scene = Scene::new(camera(size.width, size.height), &d)
        .light(light())
        .shader(&dithered);
    wire_matches(&scene, size);
}

#[test]
fn the_wire_bytes_of_a_packed_tile_are_the_frame_in_panel_order() {
    let size = Size::new(100, 70); // edge tiles 4 wide, 6 high
    with_demo_scene(0.2, size, |scene| {
        let (_, native, _) =
            reference::<Rgb565, 8192, 80>(scene, Config::new(size, Rgb565::new(1, 2, 3)));

        let renderer: Renderer<Rgb565Be, 32, 32> =
            Renderer::new(Config::new(size, Rgb565::new(1, 2, 3).into()));
        let mut ws: Box<Workspace<2048, 8192, 80>> = Box::new(Workspace::new());
        let mut tile = Tile::new(Rgb565Be::BLACK);
        let mut frame = renderer.begin(&mut ws, scene).unwrap();
        let mut panel = vec![0u8; (size.width * size.height * 2) as usize];
        while let Some(area) = frame.render_next(&mut tile) {
            let full_width = area.size.width == 32;
            assert_eq!(tile.view(&area).contiguous().is_some(), full_width);
            let (ptr, len) = wire::wire_bytes(tile.pack(&area));
            assert_eq!(len, (2 * area.size.width * area.size.height) as usize);
            // What the DMA channel reads.
            let bytes = unsafe { core::slice::from_raw_parts(ptr, len) };
            let row = 2 * area.size.width as usize;
            for (j, line) in bytes.chunks(row).enumerate() {
                let y = area.top_left.y as usize + j;
                let at = 2 * (y * size.width as usize + area.top_left.x as usize);
                panel[at..at + row].copy_from_slice(line);
            }
        }
        let expected: Vec<u8> = native
            .pixels
            .iter()
            .flat_map(|c| c.into_storage().to_be_bytes())
            .collect();
        assert!(panel == expected, "the panel's bytes differ");
    });
}

#[test]
fn rgb565be_converts_like_rgb565() {
    for v in (0..=u16::MAX).step_by(7) {
        let native = Rgb565::from(RawU16::new(v));
        let wire = Rgb565Be::from(native);
        assert_eq!(wire.value(), v);
        assert_eq!(wire.to_be_bytes(), v.to_be_bytes());
        assert_eq!(Rgb565Be::from_be_bytes(v.to_be_bytes()), wire);
        assert_eq!(Rgb565Be::from_value(v), wire);
        assert_eq!(Rgb565Be::from(RawU16::new(v)), wire);
        assert_eq!(RawU16::from(wire).into_inner(), v);
        assert_eq!(Rgb888::from(wire), Rgb888::from(native));
        assert_eq!(
            (wire.r(), wire.g(), wire.b()),
            (native.r(), native.g(), native.b())
        );
        assert_eq!(Rgb565Be::new(native.r(), native.g(), native.b()), wire);
    }
    for c in [0u8, 1, 7, 8, 127, 128, 200, 254, 255] {
        let rgb = Rgb888::new(c, c.wrapping_mul(3), 255 - c);
        assert_eq!(
            Rgb565Be::from(rgb).value(),
            Rgb565::from(rgb).into_storage()
        );
    }
    let consts = [
        (Rgb565Be::BLACK, Rgb565::BLACK),
        (Rgb565Be::RED, Rgb565::RED),
        (Rgb565Be::GREEN, Rgb565::GREEN),
        (Rgb565Be::BLUE, Rgb565::BLUE),
        (Rgb565Be::YELLOW, Rgb565::YELLOW),
        (Rgb565Be::MAGENTA, Rgb565::MAGENTA),
        (Rgb565Be::CYAN, Rgb565::CYAN),
        (Rgb565Be::WHITE, Rgb565::WHITE),
    ];
    for (w, n) in consts {
        assert_eq!(Rgb565::from(w), n);
    }
    assert_eq!(format!("{:?}", Rgb565Be::RED), "Rgb565Be(0xf800)");
}

#[test]
fn window_commands_for_a_tile() {
    let area = Rectangle::new(Point::new(288, 224), Size::new(32, 16));
    let w = Window::new(&area, Point::zero()).unwrap();
    assert_eq!(w.columns, [0x01, 0x20, 0x01, 0x3f]); // 288..=319
    assert_eq!(w.rows, [0x00, 0xe0, 0x00, 0xef]); // 224..=239
    let bytes: Vec<(u8, Vec<u8>)> = w.commands().iter().map(|(c, p)| (*c, p.to_vec())).collect();
    assert_eq!(
        bytes,
        [
            (0x2a, vec![0x01, 0x20, 0x01, 0x3f]),
            (0x2b, vec![0x00, 0xe0, 0x00, 0xef]),
            (0x2c, vec![]),
        ]
    );
    assert_eq!((CASET, RASET, RAMWR), (0x2a, 0x2b, 0x2c));
    // A 135x240 panel's offset (52, 40).
    let one = Rectangle::new(Point::new(0, 0), Size::new(1, 1));
    let w = Window::new(&one, Point::new(52, 40)).unwrap();
    assert_eq!((w.columns, w.rows), ([0, 52, 0, 52], [0, 40, 0, 40]));
    // Empty, negative or beyond 16-bit addresses: no window.
    assert_eq!(
        Window::new(
            &Rectangle::new(Point::zero(), Size::new(0, 4)),
            Point::zero()
        ),
        None
    );
    assert_eq!(Window::new(&one, Point::new(-1, 0)), None);
    let far = Rectangle::new(Point::new(65_535, 0), Size::new(2, 1));
    assert_eq!(Window::new(&far, Point::zero()), None);
}
