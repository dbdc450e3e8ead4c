//! Firmware for a Raspberry Pi Pico (RP2040) on Embassy: the same lit torus
//! knot and orbiting cube as `examples/rp2040_st7789.rs`
//! (`examples/st7789_scene`), rendered by microraster in an async main task
//! with `Frame::render_async`, which draws each tile while DMA carries
//! the previous one over SPI1 (embassy-rp's async `Spi::write`) to a
//! 240x240 ST7789, frame after frame.
//!
//! The tiles are drawn in the panel's wire format, big-endian Rgb565
//! (`Rgb565Be`), so each one goes to the DMA channel as it is, after its
//! window commands (`CASET`, `RASET`, `RAMWR`). mipidsi only initialises
//! the panel.
//!
//! ```text
//! cargo build --release --manifest-path boards/rp2040-embassy-st7789/Cargo.toml --target thumbv6m-none-eabi
//! ```
//!
//! Wiring (SPI1; the pinout of Waveshare's Pico-LCD-1.3 board), as for
//! the rp2040-hal firmware:
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
//! The on-board LED (GP25) toggles once per frame. If the display cannot be
//! brought up or a frame fails, the LED blinks a code instead, forever:
//! 3 = display, 4 = scene set-up, 5 = render. (embassy-rp brings the clocks
//! up before `main` runs.)

#![no_std]
#![no_main]

#[path = "../../../examples/board_support/mod.rs"]
mod board_support;
#[path = "../../../examples/st7789_scene/mod.rs"]
mod st7789_scene;

use embassy_executor::Spawner;
use embassy_rp::bind_interrupts;
use embassy_rp::dma;
use embassy_rp::gpio::{Level, Output};
use embassy_rp::peripherals::{DMA_CH0, SPI1};
use embassy_rp::spi::{self, Async, Spi};
use embassy_time::{Delay, Instant, Timer};
use embedded_graphics::primitives::Rectangle;
use microraster::prelude::*;
use microraster::sink::wire::{wire_bytes, Window};
use panic_halt as _;
use st7789_scene::*;
use static_cell::ConstStaticCell;

bind_interrupts!(struct Irqs {
    DMA_IRQ_0 => dma::InterruptHandler<DMA_CH0>;
});

/// The SPI clock: the ST7789's limit and the RP2040's fastest (the 125 MHz
/// peripheral clock halved). Lower it if long wires garble the picture.
const SPI_HZ: u32 = 62_500_000;

// Built in place in RAM (.bss), never moved through the stack or into the
// main task's future.
static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
/// The two tile buffers: one is drawn while DMA sends the other. A
/// `const` pair, never built on the stack (`render_async` takes the pair
/// as one array: built at run time and moved into its static, it raised
/// the peak stack from 9.9 to 20.8 KB in rp2040js), and all zeros
/// (`TileBuffer::new_nearest` with black), so in RAM cleared at start-up
/// (.bss): a `TileBuffer::new` pair, the farthest depth, would be initial
/// data (.data), its 8 KiB stored in flash too. (Their first colour is
/// never seen: each tile is cleared first.)
static TILES: ConstStaticCell<[PicoTile; 2]> = ConstStaticCell::new([
    PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)),
    PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)),
]);

/// What can go wrong with a tile on its way to the panel.
#[derive(Debug)]
enum PanelError {
    /// The SPI driver's error.
    Spi(spi::Error),
    /// A tile outside the controller's addresses, or not one block (the
    /// renderer hands every tile over packed, so neither happens).
    Tile,
}

/// The ST7789 on SPI1 after mipidsi's start-up sequence: each tile goes out
/// as its window commands (a few bytes, written at once) and its pixels,
/// sent by DMA while the renderer draws the next tile.
struct Panel<'d> {
    spi: Spi<'d, SPI1, Async>,
    cs: Output<'d>,
    dc: Output<'d>,
}

impl Panel<'_> {
    /// Opens the tile's window and sends its pixels; CS is low throughout.
    async fn send(&mut self, window: &Window, pixels: &[u8]) -> Result<(), spi::Error> {
        for (command, parameters) in window.commands() {
            self.dc.set_low();
            self.spi.blocking_write(&[command])?;
            self.dc.set_high();
            self.spi.blocking_write(parameters)?;
        }
        // DC stays high: the pixels are RAMWR's data. The transfer starts
        // in the first poll; embassy-rp's future returns once the last
        // byte has left the shift register.
        self.spi.write(pixels).await
    }
}

impl AsyncTileSink<Rgb565Be> for Panel<'_> {
    type Error = PanelError;

    async fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, Rgb565Be>,
    ) -> Result<(), PanelError> {
        // The 240x240 panel is the controller's top-left corner in
        // mipidsi's default orientation: no offset.
        let window = Window::new(area, Point::zero()).ok_or(PanelError::Tile)?;
        let (address, len) = wire_bytes(tile.contiguous().ok_or(PanelError::Tile)?);
        // SAFETY: `wire_bytes` gives the address and length of the tile's
        // pixels, `len` initialised bytes in wire order, borrowed from
        // `tile` for as long as this future lives; the bytes are only read.
        let pixels = unsafe { core::slice::from_raw_parts(address, len) };
        self.cs.set_low();
        let sent = self.send(&window, pixels).await;
        self.cs.set_high();
        sent.map_err(PanelError::Spi)
    }
}

/// Blinks `code` times, pauses, and again, forever: what the firmware does
/// instead of panicking when the board cannot be brought up.
async fn fault(led: &mut Output<'_>, code: u32) -> ! {
    loop {
        for _ in 0..code {
            led.set_high();
            Timer::after_millis(200).await;
            led.set_low();
            Timer::after_millis(200).await;
        }
        Timer::after_millis(800).await;
    }
}

#[embassy_executor::main]
async fn main(_spawner: Spawner) {
    // 125 MHz system and peripheral clocks from the crystal.
    let p = embassy_rp::init(Default::default());
    let mut led = Output::new(p.PIN_25, Level::Low);

    // The display: SPI1 transmit-only with a DMA channel, mode 3 (which
    // also suits modules whose CS is tied low), CS driven as a GPIO around
    // each tile.
    let mut spi_config = spi::Config::default();
    spi_config.frequency = SPI_HZ;
    spi_config.phase = spi::Phase::CaptureOnSecondTransition;
    spi_config.polarity = spi::Polarity::IdleHigh;
    let mut spi = Spi::new_txonly(p.SPI1, p.PIN_10, p.PIN_11, p.DMA_CH0, Irqs, spi_config);
    let mut cs = Output::new(p.PIN_9, Level::High);
    let mut dc = Output::new(p.PIN_8, Level::Low);
    let mut rst = Output::new(p.PIN_12, Level::High);
    let mut backlight = Output::new(p.PIN_13, Level::Low);

    // The panel's start-up sequence, CS driven as a GPIO around each
    // command.
    if board_support::init_st7789(
        &mut spi,
        &mut cs,
        &mut dc,
        &mut rst,
        Delay,
        (WIDTH as u16, HEIGHT as u16),
    )
    .is_err()
    {
        fault(&mut led, 3).await
    }
    let mut panel = Panel { spi, cs, dc };

    // The scene: the knot is generated once, into its static.
    let (Some(knot), Some(cube), Some(camera)) = (KNOT.take().generate(), cube(), camera()) else {
        fault(&mut led, 4).await
    };
    let workspace = WORKSPACE.take();
    // No `Renderer`: its own tile buffer would go unused (each frame is
    // begun with `Frame::begin` and drawn into `tiles`).
    let config = config();
    let tiles = TILES.take();

    loop {
        // Microseconds since boot: embassy-time's tick is 1 MHz here.
        let draws = draws(&knot, &cube, Instant::now().as_micros());
        let scene = Scene::new(camera, &draws).light(light());
        let drawn = match PicoFrame::begin(config, workspace, &scene) {
            Ok(frame) => frame.render_async(tiles, &mut panel).await.is_ok(),
            Err(_) => false,
        };
        if !drawn {
            fault(&mut led, 5).await;
        }
        // Lit once the first frame is on the panel, so the panel's
        // power-up contents are never seen; a no-op after that.
        backlight.set_high();
        led.toggle();
    }
}
