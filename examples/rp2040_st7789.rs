//! Firmware for a Raspberry Pi Pico (RP2040): renders a lit torus knot of
//! 2,048 triangles with a cube orbiting it, with microraster, in 32x32
//! tiles, on a 240x240 ST7789 on SPI1, frame after frame. A DMA channel
//! sends the finished tiles while the core draws the next ones
//! (`Frame::render_to_queue` over five tile buffers, up to four tiles on
//! the wire): the channel's completion interrupt starts the next queued
//! tile by itself, so the core draws ahead through cheap tiles while the
//! wire catches up during dear ones, and a frame takes about the longer
//! of the drawing and the sending, not their sum. The buffers stay in a
//! `TileQueue` from frame to frame, so a frame's last tiles are sent
//! while the next frame's vertex stage and binning run.
//!
//! ```text
//! cargo build --release --example rp2040_st7789 --target thumbv6m-none-eabi
//! ```
//!
//! Wiring (SPI1; the pinout of Waveshare's Pico-LCD-1.3 board):
//!
//! | ST7789 | Pico               |
//! |--------|--------------------|
//! | SCL    | GP10 (SPI1 SCK)    |
//! | SDA    | GP11 (SPI1 TX)     |
//! | CS     | GP9                |
//! | DC     | GP8                |
//! | RES    | GP12               |
//! | BLK    | GP13 (backlight)   |
//! | VCC    | 3V3(OUT), pin 36   |
//! | GND    | GND                |
//!
//! mipidsi brings the panel up (reset, SLPOUT, MADCTL, INVON, COLMOD,
//! NORON, DISPON); from then on the firmware drives the bus itself. Per
//! tile: the window's CASET/RASET/RAMWR (DC low for each command byte,
//! high for its parameters), from `start` if the bus is free, else from
//! `DMA_IRQ_0` once the tile before is sent, then the tile's pixels by DMA
//! (DMA channel 0, paced by SPI1's TX DREQ), already in the panel's
//! big-endian byte order (`Rgb565Be`): no per-pixel pass before sending.
//! CS stays low from the end of the set-up on: the panel is the bus's only
//! device.
//!
//! The on-board LED (GP25) toggles once per frame. If the board cannot be
//! brought up or a frame fails, the LED blinks a code instead, forever:
//! 2 = clocks, 3 = display, 4 = scene set-up, 5 = render.
//!
//! The memory map is `memory/rp2040.x`, which `build.rs` copies for this
//! target; the 256-byte second-stage bootloader goes first in flash.
//!
//! On a host build this file is only a stub that says how to build it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "rp2040_st7789 is firmware: cargo build --release --example rp2040_st7789 --target thumbv6m-none-eabi"
    );
}

#[cfg(target_os = "none")]
mod board_support;
#[cfg(target_os = "none")]
mod st7789_scene;
#[cfg(target_os = "none")]
#[path = "board_support/tile_bytes.rs"]
mod tile_bytes;

#[cfg(target_os = "none")]
mod firmware {
    use crate::board_support;
    use crate::st7789_scene::*;
    use crate::tile_bytes::TileBytes;
    use core::cell::RefCell;
    use core::convert::Infallible;
    use core::mem;
    use critical_section::Mutex;
    use embedded_hal::digital::{OutputPin, StatefulOutputPin};
    use embedded_hal::spi::{SpiBus, MODE_3};
    use heapless::Deque;
    use microraster::prelude::*;
    use microraster::sink::wire::Window;
    use panic_halt as _;
    use rp2040_hal::clocks::{init_clocks_and_plls, Clock};
    use rp2040_hal::dma::single_buffer::{self, Transfer};
    use rp2040_hal::dma::{Channel, DMAExt, SingleChannel, CH0};
    use rp2040_hal::fugit::RateExtU32;
    use rp2040_hal::gpio::bank0::{Gpio10, Gpio11, Gpio8};
    use rp2040_hal::gpio::{FunctionSioOutput, FunctionSpi, Pin, PinState, Pins, PullDown};
    use rp2040_hal::pac::interrupt;
    use rp2040_hal::spi::Enabled;
    use rp2040_hal::{pac, Sio, Spi, Timer, Watchdog};
    use static_cell::ConstStaticCell;

    /// The second-stage bootloader, which the boot ROM loads from the first
    /// 256 bytes of flash to set the flash up for execute-in-place; the
    /// Pico's W25Q16JV flash takes the W25Q080 one. `memory/rp2040.x` puts
    /// the `.boot2` section there. (`link_section` is the only attribute
    /// here that the compiler cannot check: the map gives the section its
    /// own 256-byte region, so nothing else can land there.)
    #[link_section = ".boot2"]
    #[used]
    static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

    /// 0 in every build: draw the next tile while DMA sends this one. Any
    /// other value makes each transfer wait until its tile has left the
    /// wire before the next tile is drawn, so that a frame is the drawing
    /// and the sending one after the other: how the emulator's harness
    /// measures the render alone (`tests/pico/run.mjs --serial` sets this
    /// byte in the image it loads; the test and BENCHMARKS.md report both
    /// runs). A byte in flash, read once at start-up.
    #[no_mangle]
    #[used]
    static MICRORASTER_PICO_SERIAL: u8 = 0;

    /// 0 in every build: each frame shows the animation at the timer's
    /// time. Any other value `N`: frame `k` shows the animation at `k N`
    /// microseconds (the timer runs all the same), so that two runs of the
    /// emulator's harness, with and without `--serial`, draw the very same
    /// frames and their cycles compare exactly (`tests/pico/run.mjs
    /// --frame-us N` sets it in the image it loads). In flash, read once.
    #[no_mangle]
    #[used]
    static MICRORASTER_PICO_FRAME_US: u32 = 0;

    /// The Pico's crystal.
    const XTAL_HZ: u32 = 12_000_000;
    /// The SPI clock asked for: the RP2040's fastest (the 125 MHz
    /// peripheral clock halved). Lower it if long wires garble the picture.
    const SPI_HZ: u32 = 62_500_000;
    /// Half a period of the fault blink: 0.2 s at 125 MHz (slower if the
    /// clocks never came up).
    const BLINK_CYCLES: u32 = 25_000_000;

    // Built in place in RAM (.bss), never moved through the stack.
    static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
    static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
    /// How many tile buffers (colour and depth, 4,120 B each with its
    /// cell): up to `TILES - 1` finished tiles wait on the wire while the
    /// core draws the next, so that a run of cheap tiles (background) is
    /// drawn ahead while the wire catches up during the dear ones. In
    /// rp2040js (BENCHMARKS.md), frames 1 to 11 take 1.051x max(render,
    /// transfer) with 3, 1.043x with 4 (one frame 1.052x), 1.038x with 5
    /// (at most 1.043x) and 1.035x with 6: 5 is the fewest that keeps every
    /// frame under the 1.05x aimed at.
    const TILES: usize = 5;

    // The tile buffers. `'static`, as a DMA transfer's buffer must be: a
    // transfer that was leaked must not go on reading freed memory. Built
    // by the compiler, all zeros (`TileBuffer::new_nearest` with black), so
    // that they start in RAM cleared at start-up (.bss) and take no flash
    // (a `TileBuffer::new` buffer, the farthest depth, would be initial
    // data, .data, stored in flash too), and are never built on the stack
    // and moved in: that took 4 KiB of stack at start-up, 8,172 B in all.
    // (Their first colour is never seen: each tile is cleared first.)
    static TILE_BUFFERS: [ConstStaticCell<PicoTile>; TILES] =
        [const { ConstStaticCell::new(PicoTile::new_nearest(Rgb565Be::new(0, 0, 0))) }; TILES];

    /// The tile buffers, once (`None` the second time).
    fn tiles() -> Option<[&'static mut PicoTile; TILES]> {
        let tiles: heapless::Vec<_, TILES> = TILE_BUFFERS
            .iter()
            .map(ConstStaticCell::try_take)
            .collect::<Option<_>>()?;
        tiles.into_array().ok()
    }

    /// SPI1 as the firmware sets it up: TX on GP11, SCK on GP10, bytes.
    type Bus = Spi<
        Enabled,
        pac::SPI1,
        (
            Pin<Gpio11, FunctionSpi, PullDown>,
            Pin<Gpio10, FunctionSpi, PullDown>,
        ),
        8,
    >;
    /// The panel's DC pin, GP8.
    type Dc = Pin<Gpio8, FunctionSioOutput, PullDown>;

    /// Where the bus is: free, or carrying a tile by DMA.
    enum Link {
        Idle(Channel<CH0>, Bus),
        Sending(Transfer<Channel<CH0>, TileBytes, Bus>),
        /// Only while a transition is under way.
        Taken,
    }

    /// The wire, shared by the core (`Panel::start` queues a tile) and the
    /// DMA-completion interrupt (which gives the tile sent back and starts
    /// the next queued one): so the wire moves on to the next tile while
    /// the core draws, however long that takes.
    struct Wire {
        link: Link,
        dc: Dc,
        /// Tiles drawn and packed, to be sent in this order.
        queued: Deque<(Window, TileBytes), TILES>,
        /// Tiles sent (their last byte in the SPI's FIFO), oldest first,
        /// for `Panel::wait` to give back.
        sent: Deque<&'static mut PicoTile, TILES>,
    }

    impl Wire {
        /// If the bus is free, sends the next queued tile: its window
        /// commands from the core, then its pixels by DMA.
        fn send_next(&mut self) {
            let Link::Idle(..) = self.link else {
                return;
            };
            let Some((window, bytes)) = self.queued.pop_front() else {
                return;
            };
            let Link::Idle(channel, mut spi) = mem::replace(&mut self.link, Link::Taken) else {
                return;
            };
            // The window's commands, DC left high for the pixels.
            let Ok(()) = board_support::send_window(&mut spi, &mut self.dc, &window);
            // After RAMWR, DC high: the pixels, by DMA, paced by SPI1's TX
            // DREQ (the FIFO's room); the channel raises DMA_IRQ_0 when
            // done (`enable_irq0` at start-up, but in serial mode).
            self.link = Link::Sending(single_buffer::Config::new(channel, bytes, spi).start());
        }

        /// If the tile on the wire has been sent, moves it to `sent` and
        /// frees the bus. `flush`: also wait for the SPI to be idle.
        fn finish(&mut self, flush: bool) {
            let transfer = match mem::replace(&mut self.link, Link::Taken) {
                Link::Sending(transfer) if transfer.is_done() => transfer,
                other => {
                    self.link = other;
                    return;
                }
            };
            let (channel, bytes, mut spi) = transfer.wait();
            if flush {
                let Ok(()) = spi.flush();
            }
            self.link = Link::Idle(channel, spi);
            // Never full: it holds the tiles in flight, fewer than TILES.
            let _ = self.sent.push_back(bytes.tile);
        }
    }

    /// The wire, once `main` has set it up.
    static WIRE: Mutex<RefCell<Option<Wire>>> = Mutex::new(RefCell::new(None));

    /// The channel's transfer is done: hands its tile to `Panel::wait` and
    /// starts the next queued tile, so that the wire idles only while the
    /// queue is empty.
    #[interrupt]
    fn DMA_IRQ_0() {
        critical_section::with(|cs| {
            if let Some(wire) = WIRE.borrow_ref_mut(cs).as_mut() {
                if let Link::Sending(transfer) = &mut wire.link {
                    // Clears the channel's interrupt, which would fire again.
                    transfer.check_irq0();
                }
                wire.finish(false);
                wire.send_next();
            }
        });
    }

    /// Why a tile could not be started.
    #[derive(Debug)]
    enum PanelError {
        /// The queue was full: more tiles in flight than buffers.
        Busy,
        /// The tile's window lies outside the panel's addresses.
        Window,
    }

    /// The panel, past its set-up, as a [`TileTransfer`] with a queue: a
    /// tile started while another is on the wire waits in `WIRE`, and the
    /// DMA interrupt sends it.
    struct Panel {
        /// Tiles started and not yet given back by `wait`.
        in_flight: usize,
        /// Wait for every tile to be on the wire (`MICRORASTER_PICO_SERIAL`).
        serial: bool,
    }

    impl TileTransfer<&'static mut PicoTile> for Panel {
        type Error = PanelError;

        fn start(
            &mut self,
            area: &Rectangle,
            tile: &'static mut PicoTile,
        ) -> Result<(), (PanelError, &'static mut PicoTile)> {
            let Some(window) = Window::new(area, Point::zero()) else {
                return Err((PanelError::Window, tile));
            };
            // Packed here, by the core, before the interrupt may send it.
            let bytes = TileBytes::new(tile, area);
            critical_section::with(|cs| {
                let mut wire = WIRE.borrow_ref_mut(cs);
                let Some(wire) = wire.as_mut() else {
                    return Err((PanelError::Busy, bytes.tile));
                };
                if let Err((_, bytes)) = wire.queued.push_back((window, bytes)) {
                    return Err((PanelError::Busy, bytes.tile));
                }
                wire.send_next();
                if self.serial {
                    // No interrupt in serial mode: the tile leaves the wire
                    // before the next is drawn.
                    while let Link::Sending(transfer) = &wire.link {
                        if transfer.is_done() {
                            break;
                        }
                    }
                    wire.finish(true);
                }
                Ok(())
            })?;
            self.in_flight += 1;
            Ok(())
        }

        fn wait(&mut self) -> (&'static mut PicoTile, Result<(), PanelError>) {
            // `render_queued` waits only with a tile in flight, so there is
            // always a buffer to give back here.
            if self.in_flight == 0 {
                park();
            }
            loop {
                let sent = critical_section::with(|cs| {
                    let sent = WIRE.borrow_ref_mut(cs).as_mut()?.sent.pop_front();
                    if sent.is_none() {
                        // Sleeps until the DMA interrupt is pending, which
                        // runs once the critical section ends: no interrupt
                        // is missed between the look and the sleep. (`WIRE`
                        // is not borrowed meanwhile.)
                        cortex_m::asm::wfi();
                    }
                    sent
                });
                if let Some(tile) = sent {
                    self.in_flight -= 1;
                    return (tile, Ok(()));
                }
            }
        }
    }

    board_support::rp_park_and_fault!(cortex_m::asm);

    #[rp2040_hal::entry]
    fn main() -> ! {
        // 125 MHz clocks, the timer, the panel's wiring and start-up
        // (board_support::rp_st7789_bring_up).
        let (mut led, spi, dc, mut backlight, timer, dma) =
            board_support::rp_st7789_bring_up!(TIMER, new);
        // Read once, as a value the compiler cannot assume (the harness
        // may have changed it in the image).
        // SAFETY: a valid, aligned `'static` byte that nothing writes.
        let serial = unsafe { core::ptr::read_volatile(&MICRORASTER_PICO_SERIAL) } != 0;
        // SAFETY: as for the byte above, a valid, aligned `'static` word.
        let frame_us = unsafe { core::ptr::read_volatile(&MICRORASTER_PICO_FRAME_US) } as u64;
        let mut channel = dma.ch0;
        if !serial {
            channel.enable_irq0();
        }
        critical_section::with(|cs| {
            WIRE.replace(
                cs,
                Some(Wire {
                    link: Link::Idle(channel, spi),
                    dc,
                    queued: Deque::new(),
                    sent: Deque::new(),
                }),
            )
        });
        // SAFETY: the interrupt's handler, `DMA_IRQ_0`, shares nothing with
        // this thread but `WIRE`, through its critical sections, which mask
        // every interrupt; unmasking cannot break them.
        unsafe { cortex_m::peripheral::NVIC::unmask(pac::Interrupt::DMA_IRQ_0) };
        let mut panel = Panel {
            in_flight: 0,
            serial,
        };

        // The scene: the knot is generated once, into its static.
        let (Some(knot), Some(cube), Some(camera)) = (KNOT.take().generate(), cube(), camera())
        else {
            fault(&mut led, 4)
        };
        let workspace = WORKSPACE.take();
        // No `Renderer`: its own tile buffer would go unused (each frame
        // is begun with `Frame::begin` and drawn into `tiles`).
        let config = config();
        // Kept from frame to frame: a frame returns with its last tiles
        // still on the wire, sent while the next one's vertex stage and
        // binning run.
        let Some(tiles) = tiles() else {
            fault(&mut led, 4)
        };
        let mut queue = TileQueue::new(tiles);
        let mut lit = false;

        let mut frame = 0u64;
        loop {
            // The timer counts microseconds from its reset above.
            let now = timer.get_counter().ticks();
            let time_us = match frame_us {
                0 => now,
                step => frame * step,
            };
            frame += 1;
            let draws = draws(&knot, &cube, time_us);
            let scene = Scene::new(camera, &draws).light(light());
            let result = match PicoFrame::begin(config, workspace, &scene) {
                Ok(frame) => frame.render_to_queue(&mut queue, &mut panel),
                Err(e) => Err(e.for_sink()),
            };
            if result.is_err() {
                fault(&mut led, 5);
            }
            // Lit once the first frame is on the panel (its last tiles
            // sent), so the panel's power-up contents are never seen.
            if !lit {
                if queue.flush(&mut panel).is_err() {
                    fault(&mut led, 5);
                }
                let Ok(()) = backlight.set_high();
                lit = true;
            }
            let Ok(()) = led.toggle();
        }
    }
}
