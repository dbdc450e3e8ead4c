//! Firmware for a Raspberry Pi Pico 2 (RP2350, Cortex-M33): the Pico
//! firmware (`examples/rp2040_st7789.rs`) on the RP2350. The same lit torus
//! knot and orbiting cube (`examples/st7789_scene`), rendered with
//! `Renderer::render_double_buffered`: each finished tile goes over SPI1 by
//! DMA, paced by SPI1's TX DREQ, while the next is drawn, to a 240x240
//! ST7789 wired as on the Pico (Waveshare's Pico-LCD-1.3 fits both boards).
//! The tiles are drawn in the panel's byte order (`Rgb565Be`), so DMA
//! sends them as they are; the core only sends each tile's window commands,
//! and mipidsi only brings the panel up. CS stays low after the set-up: the
//! panel is the bus's only device.
//!
//! ```text
//! cargo build --release --manifest-path boards/rp2350-st7789/Cargo.toml --target thumbv8m.main-none-eabihf
//! ```
//!
//! Wiring (SPI1; the pinout of Waveshare's Pico-LCD-1.3 board):
//!
//! | ST7789 | Pico 2             |
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
//! The on-board LED (GP25) toggles once per frame. If the board cannot be
//! brought up or a frame fails, the LED blinks a code instead, forever:
//! 2 = clocks, 3 = display, 4 = scene set-up, 5 = render.
//!
//! The firmware measures its own peak stack: it paints the free RAM under
//! the stack at start-up and, after every frame, stores how far down the
//! stack has written (in bytes from the top of RAM) in `PEAK_STACK_BYTES`,
//! for a debugger to read (`probe-rs attach`, or GDB's
//! `print PEAK_STACK_BYTES`). `tests/qemu_stack.rs` measures the same
//! frame code on QEMU's Cortex-M33 (`examples/stack_probe.rs`).
//!
//! The RP2350 boots without a second-stage bootloader: its boot ROM looks
//! for an IMAGE_DEF block in the first 4 KiB of flash (`memory.x` puts it
//! right after the vector table) and starts the image it describes.

#![no_std]
#![no_main]

#[path = "../../../examples/board_support/mod.rs"]
mod board_support;
#[path = "../../../examples/st7789_scene/mod.rs"]
mod st7789_scene;
#[path = "../../../examples/stack_gauge/mod.rs"]
mod stack_gauge;
#[path = "../../../examples/board_support/tile_bytes.rs"]
mod tile_bytes;

use core::convert::Infallible;
use core::mem;
use core::sync::atomic::{AtomicUsize, Ordering};
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::{OutputPin, StatefulOutputPin};
use embedded_hal::spi::{SpiBus, MODE_3};
use microraster::prelude::*;
use microraster::sink::wire::Window;
use panic_halt as _;
use rp235x_hal as hal;
use st7789_scene::*;
use static_cell::ConstStaticCell;
use tile_bytes::TileBytes;

use hal::clocks::{init_clocks_and_plls, Clock};
use hal::dma::single_buffer::{self, Transfer};
use hal::dma::{DMAExt, SingleChannel, WriteTarget};
use hal::fugit::RateExtU32;
use hal::gpio::{FunctionSpi, PinState, Pins};
use hal::{pac, Sio, Spi, Timer, Watchdog};

/// Tells the boot ROM that this is a secure-mode Arm executable: the one
/// block of the image, in `.start_block` (see `memory.x`).
#[link_section = ".start_block"]
#[used]
pub static IMAGE_DEF: hal::block::ImageDef = hal::block::ImageDef::secure_exe();

/// The Pico 2's crystal.
const XTAL_HZ: u32 = 12_000_000;
/// The SPI clock asked for: the ST7789's limit. The SPI divides the
/// 150 MHz peripheral clock by an even number at least 4 below 75 MHz, so
/// this gives 37.5 MHz (75 MHz would be beyond the panel's specification).
const SPI_HZ: u32 = 62_500_000;
/// Half a period of the fault blink: 0.2 s at 150 MHz (slower if the clocks
/// never came up).
const BLINK_CYCLES: u32 = 30_000_000;

// Built in place in RAM (.bss), never moved through the stack.
static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
// The two tile buffers. `'static`, as a DMA transfer's buffer must be: a
// transfer that was leaked must not go on reading freed memory. Built by
// the compiler, all zeros (`TileBuffer::new_nearest` with black), so that
// they start in RAM cleared at start-up (.bss) and take no flash (a
// `TileBuffer::new` buffer, the farthest depth, would be initial data,
// .data, stored in flash too), and are never built on the stack and moved
// in. (Their first colour is never seen: each tile is cleared first.)
static TILE_A: ConstStaticCell<PicoTile> =
    ConstStaticCell::new(PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)));
static TILE_B: ConstStaticCell<PicoTile> =
    ConstStaticCell::new(PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)));

/// The deepest the stack has gone, in bytes below the top of RAM, as of
/// the last frame (`examples/stack_gauge`): for a debugger to read.
#[no_mangle]
static PEAK_STACK_BYTES: AtomicUsize = AtomicUsize::new(0);

/// The two tile buffers, once (`None` the second time).
fn tiles() -> Option<[&'static mut PicoTile; 2]> {
    Some([TILE_A.try_take()?, TILE_B.try_take()?])
}

/// Where the bus is: free, or carrying a tile by DMA.
enum Link<CH: SingleChannel, S: WriteTarget<TransmittedWord = u8>> {
    Idle(CH, S),
    Sending(Transfer<CH, TileBytes, S>),
    /// Only while a transition is under way.
    Taken,
}

/// Why a tile could not be started.
#[derive(Debug)]
enum PanelError {
    /// A transfer was still in flight.
    Busy,
    /// The tile's window lies outside the panel's addresses.
    Window,
}

/// The panel, past its set-up, as a `TileTransfer`: the window commands of
/// each tile from the core, then its pixels by DMA.
struct Panel<CH: SingleChannel, S: WriteTarget<TransmittedWord = u8>, DC> {
    link: Link<CH, S>,
    dc: DC,
}

impl<CH, S, DC> TileTransfer<&'static mut PicoTile> for Panel<CH, S, DC>
where
    CH: SingleChannel,
    S: WriteTarget<TransmittedWord = u8> + SpiBus<u8, Error = Infallible>,
    DC: OutputPin<Error = Infallible>,
{
    type Error = PanelError;

    fn start(
        &mut self,
        area: &Rectangle,
        tile: &'static mut PicoTile,
    ) -> Result<(), (PanelError, &'static mut PicoTile)> {
        let Some(window) = Window::new(area, Point::zero()) else {
            return Err((PanelError::Window, tile));
        };
        let (channel, mut spi) = match mem::replace(&mut self.link, Link::Taken) {
            Link::Idle(channel, spi) => (channel, spi),
            busy => {
                self.link = busy;
                return Err((PanelError::Busy, tile));
            }
        };
        // The window's commands, DC left high for the pixels.
        let Ok(()) = board_support::send_window(&mut spi, &mut self.dc, &window);
        // After RAMWR, DC high: the pixels, by DMA, paced by SPI1's TX DREQ
        // (the FIFO's room).
        let bytes = TileBytes::new(tile, area);
        self.link = Link::Sending(single_buffer::Config::new(channel, bytes, spi).start());
        Ok(())
    }

    fn wait(&mut self) -> (&'static mut PicoTile, Result<(), PanelError>) {
        let (channel, bytes, spi) = match mem::replace(&mut self.link, Link::Taken) {
            // Done once the channel has written the last byte into the
            // FIFO; the next `start` waits for the FIFO to drain.
            Link::Sending(transfer) => transfer.wait(),
            // `render_double_buffered` waits only after a successful start,
            // so there is always a buffer to give back here.
            Link::Idle(..) | Link::Taken => park(),
        };
        self.link = Link::Idle(channel, spi);
        (bytes.tile, Ok(()))
    }
}

board_support::rp_park_and_fault!(hal::arch);

#[hal::entry]
fn main() -> ! {
    // First, before any interrupt can push a frame below the stack pointer.
    stack_gauge::paint();
    // 150 MHz clocks, the timer, the panel's wiring and start-up
    // (board_support::rp_st7789_bring_up).
    let (mut led, spi, dc, mut backlight, timer, dma) =
        board_support::rp_st7789_bring_up!(TIMER0, new_timer0);
    let mut panel = Panel {
        link: Link::Idle(dma.ch0, spi),
        dc,
    };

    // The scene: the knot is generated once, into its static. These lines
    // and the frame loop read as the ESP32-C3's on purpose: each board keeps
    // them in its own `main`, beside its own clock, LED and fault codes; a
    // function shared over those would add a frame above `Frames::draw`,
    // on the deepest path (tests/qemu_stack.rs measures it).
    let Some(mut frames) = Frames::new(KNOT.take(), WORKSPACE.take()) else {
        fault(&mut led, 4)
    };
    let Some(mut tiles) = tiles() else {
        fault(&mut led, 4)
    };

    loop {
        // The timer counts microseconds from its reset above.
        let (back, result) = frames.draw(timer.get_counter().ticks(), tiles, &mut panel);
        tiles = back;
        if result.is_err() {
            fault(&mut led, 5);
        }
        PEAK_STACK_BYTES.store(stack_gauge::peak(), Ordering::Relaxed);
        // Lit once the first frame is on the panel, so the panel's
        // power-up contents are never seen; a no-op after that.
        let Ok(()) = backlight.set_high();
        let Ok(()) = led.toggle();
    }
}
