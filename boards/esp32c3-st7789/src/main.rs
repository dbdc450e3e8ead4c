//! Firmware for an ESP32-C3 (RISC-V, 160 MHz): the Pico example's lit torus
//! knot and orbiting cube (`examples/st7789_scene`), rendered by
//! microraster with `Renderer::render_double_buffered`, which draws each
//! tile while a GDMA channel carries the previous one over SPI2 to a
//! 240x240 ST7789, frame after frame.
//!
//! The tiles are drawn in the panel's wire format, big-endian Rgb565
//! (`Rgb565Be`), so each one goes to the DMA channel as it is, after its
//! window commands (`CASET`, `RASET`, `RAMWR`): the `Panel` below is the
//! library's `TileTransfer` over esp-hal's `SpiDma::write_buffer`. mipidsi
//! only initialises the panel.
//!
//! ```text
//! cargo build --release --manifest-path boards/esp32c3-st7789/Cargo.toml --target riscv32imc-unknown-none-elf
//! ```
//!
//! Wiring: an ESP32-C3 SuperMini (the pins its silkscreen marks SCK, MOSI
//! and SS) and a 1.3" 240x240 ST7789 IPS module; any ESP32-C3 board with
//! these GPIOs free will do (the GPIO matrix can route SPI2 to any of them;
//! GPIO2, GPIO8 and GPIO9 are strapping pins, GPIO18/19 the USB port).
//!
//! | ST7789 | ESP32-C3                                        |
//! |--------|-------------------------------------------------|
//! | SCL    | GPIO4 (SPI2 clock)                              |
//! | SDA    | GPIO6 (SPI2 data out)                           |
//! | CS     | GPIO7 (the 7-pin modules without CS: no wire)   |
//! | DC     | GPIO5                                           |
//! | RES    | GPIO10                                          |
//! | BLK    | GPIO3 (backlight)                               |
//! | VCC    | 3V3                                             |
//! | GND    | GND                                             |
//!
//! SPI mode 3, which the modules without CS need. The SuperMini's blue LED
//! (GPIO8, lit when low) toggles once per frame; if the display cannot be
//! brought up or a frame fails, it blinks a code instead, forever:
//! 3 = display, 4 = scene set-up, 5 = render.
//!
//! The firmware measures its own peak stack: it paints the free RAM under
//! the stack at start-up and, after every frame, stores how far down the
//! stack has written (in bytes from the top of the stack) in
//! `PEAK_STACK_BYTES`, for a debugger to read (`probe-rs attach`, or GDB's
//! `print PEAK_STACK_BYTES` through the C3's USB-JTAG). `tests/qemu_stack.rs`
//! measures the same frame code on QEMU's RISC-V `virt` machine
//! (`examples/stack_probe.rs`).

#![no_std]
#![no_main]

#[path = "../../../examples/board_support/mod.rs"]
mod board_support;
#[path = "../../../examples/st7789_scene/mod.rs"]
mod st7789_scene;
#[path = "../../../examples/stack_gauge/mod.rs"]
mod stack_gauge;

use core::ptr::NonNull;
use core::sync::atomic::{AtomicUsize, Ordering};
use embedded_graphics::primitives::Rectangle;
use embedded_hal::delay::DelayNs;
use esp_hal::clock::CpuClock;
use esp_hal::delay::Delay;
use esp_hal::dma::aligned::{DmaAlignedMut, InternalMemory};
use esp_hal::dma::{DmaDescriptor, DmaTxBuf, CHUNK_SIZE};
use esp_hal::gpio::{Level, Output, OutputConfig};
use esp_hal::spi::master::{Config as SpiConfig, Spi, SpiDma, SpiDmaTransfer};
use esp_hal::spi::{Error as SpiError, Mode};
use esp_hal::time::{Instant, Rate};
use esp_hal::Blocking;
use microraster::prelude::*;
use microraster::sink::wire::{wire_bytes, Window};
use panic_halt as _;
use st7789_scene::*;
use static_cell::ConstStaticCell;

// The application descriptor that the ESP-IDF bootloader checks.
esp_bootloader_esp_idf::esp_app_desc!();

/// The SPI clock: the 80 MHz APB clock halved, the fastest within the
/// ST7789's 62.5 MHz. Lower it if long wires garble the picture.
const SPI_MHZ: u32 = 40;
/// Writes shorter than this go through the SPI's FIFO, written by the CPU,
/// not by GDMA: the commands and their parameters, from the window's and
/// mipidsi's start-up sequence, some of them constants in flash, which
/// GDMA cannot read (the DMA driver would need a bounce buffer for them).
/// The tiles' pixels (512 bytes and more) always go by DMA.
const SMALL_WRITE: usize = 64;
/// The bytes of a whole tile on the wire.
const TILE_BYTES: usize = TILE * TILE * 2;
/// GDMA descriptors for one tile (each covers up to 4,092 bytes).
const DESCRIPTORS: usize = TILE_BYTES.div_ceil(CHUNK_SIZE);

/// One tile: 2 KiB of wire-order colour, 2 KiB of depth.
type Tile = PicoTile;

/// A tile buffer aligned for GDMA, which reads internal RAM in 4-byte
/// words: the colour block starts the buffer or follows the 2 KiB depth
/// block, and a packed tile's pixels start the colour block.
#[repr(C, align(4))]
struct DmaTile(Tile);

// Built in place in RAM (.bss), never moved through the stack.
static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
/// The two tile buffers: one is drawn while DMA sends the other. Built by
/// the compiler, all zeros (`TileBuffer::new_nearest` with black), so that
/// they start in RAM cleared at start-up (.bss) and take no flash (a
/// `TileBuffer::new` buffer, the farthest depth, would be initial data,
/// .data, stored in flash too), and are never built on the stack and moved
/// in. (Their first colour is never seen: each tile is cleared first.)
static TILE_A: ConstStaticCell<DmaTile> =
    ConstStaticCell::new(DmaTile(Tile::new_nearest(Rgb565Be::new(0, 0, 0))));
static TILE_B: ConstStaticCell<DmaTile> =
    ConstStaticCell::new(DmaTile(Tile::new_nearest(Rgb565Be::new(0, 0, 0))));
/// The descriptors of the transfer in flight.
static DMA_DESCRIPTORS: ConstStaticCell<InternalMemory<[DmaDescriptor; DESCRIPTORS]>> =
    ConstStaticCell::new(InternalMemory::new([DmaDescriptor::EMPTY; DESCRIPTORS]));

/// The deepest the stack has gone, in bytes below its top, as of the last
/// frame (`examples/stack_gauge`): for a debugger to read.
#[no_mangle]
static PEAK_STACK_BYTES: AtomicUsize = AtomicUsize::new(0);

/// The two tile buffers, once (`None` the second time).
fn tiles() -> Option<[&'static mut Tile; 2]> {
    Some([&mut TILE_A.try_take()?.0, &mut TILE_B.try_take()?.0])
}

/// What can go wrong with a tile on its way to the panel.
#[derive(Debug)]
enum PanelError {
    /// The SPI driver failed (its error says little more: the LED can
    /// only blink).
    Spi,
    /// The tile's pixels are not a block GDMA can read, or lie outside the
    /// controller's addresses (neither happens with `DmaTile`s).
    Tile,
    /// An earlier failure kept the DMA driver or its descriptors.
    Lost,
}

/// The ST7789 on SPI2 after mipidsi's start-up sequence, as a
/// `TileTransfer`: `start` writes the tile's window commands (a few bytes,
/// at once) and starts GDMA on its pixels; `wait` waits for the last byte
/// and gives the tile buffer back.
struct Panel {
    /// The driver, when no transfer is in flight.
    spi: Option<SpiDma<'static, Blocking>>,
    /// The descriptors, when no transfer is in flight.
    descriptors: Option<DmaAlignedMut<'static, [DmaDescriptor]>>,
    /// The transfer in flight and the tile buffer whose pixels it reads.
    in_flight: Option<(SpiDmaTransfer<'static, Blocking, DmaTxBuf>, NonNull<Tile>)>,
    cs: Output<'static>,
    dc: Output<'static>,
}

impl Panel {
    /// The window commands, each command byte with DC low and its
    /// parameters with DC high; DC stays high for the pixels.
    fn open(
        &mut self,
        spi: &mut SpiDma<'static, Blocking>,
        window: &Window,
    ) -> Result<(), SpiError> {
        for (command, parameters) in window.commands() {
            self.dc.set_low();
            spi.write(&[command])?;
            self.dc.set_high();
            if !parameters.is_empty() {
                spi.write(parameters)?;
            }
        }
        Ok(())
    }
}

impl TileTransfer<&'static mut Tile> for Panel {
    type Error = PanelError;

    fn start(
        &mut self,
        area: &Rectangle,
        tile: &'static mut Tile,
    ) -> Result<(), (PanelError, &'static mut Tile)> {
        // The 240x240 panel is the controller's top-left corner in
        // mipidsi's default orientation: no offset.
        let Some(window) = Window::new(area, Point::zero()) else {
            return Err((PanelError::Tile, tile));
        };
        let (Some(mut spi), Some(descriptors)) = (self.spi.take(), self.descriptors.take()) else {
            return Err((PanelError::Lost, tile));
        };
        // The packed pixels' place in the buffer; then the buffer is held
        // by address only, until `wait` makes it a reference again.
        let (address, len) = wire_bytes(tile.pack(area));
        let offset = address as usize - core::ptr::from_ref::<Tile>(tile) as usize;
        let buffer = NonNull::from(tile);
        // SAFETY: `offset + len` bytes lie within the tile buffer (the
        // packed pixels are a prefix of its colour block), initialised, and
        // derived from the one exclusive reference to it, which is given
        // up above: nothing else reads or writes the buffer until `wait`
        // has waited for the transfer and dropped this slice.
        let pixels: &'static mut [u8] = unsafe {
            core::slice::from_raw_parts_mut(buffer.as_ptr().cast::<u8>().add(offset), len)
        };
        // SAFETY (for the error paths): as above, the slice is gone.
        let give_back = |buffer: NonNull<Tile>| unsafe { &mut *buffer.as_ptr() };
        let dma_buffer = match DmaAlignedMut::new(pixels) {
            Ok(pixels) => match DmaTxBuf::new(descriptors, pixels) {
                Ok(dma_buffer) => dma_buffer,
                Err(_) => {
                    self.spi = Some(spi);
                    return Err((PanelError::Lost, give_back(buffer)));
                }
            },
            Err(_) => {
                self.spi = Some(spi);
                self.descriptors = Some(descriptors);
                return Err((PanelError::Tile, give_back(buffer)));
            }
        };
        self.cs.set_low();
        if self.open(&mut spi, &window).is_err() {
            self.cs.set_high();
            self.spi = Some(spi);
            self.descriptors = Some(dma_buffer.split().0);
            return Err((PanelError::Spi, give_back(buffer)));
        }
        match spi.write_buffer(len, dma_buffer) {
            Ok(transfer) => {
                self.in_flight = Some((transfer, buffer));
                Ok(())
            }
            Err((_, spi, dma_buffer)) => {
                self.cs.set_high();
                self.spi = Some(spi);
                self.descriptors = Some(dma_buffer.split().0);
                Err((PanelError::Spi, give_back(buffer)))
            }
        }
    }

    fn wait(&mut self) -> (&'static mut Tile, Result<(), PanelError>) {
        // `render_double_buffered` calls `wait` only after a successful
        // `start`, so a transfer is in flight.
        let Some((transfer, buffer)) = self.in_flight.take() else {
            unreachable!("TileTransfer::wait without a transfer in flight")
        };
        let (spi, dma_buffer) = transfer.wait();
        self.cs.set_high();
        self.spi = Some(spi);
        // The descriptors back, and the slice over the pixels dropped.
        self.descriptors = Some(dma_buffer.split().0);
        // SAFETY: the transfer is over and the only other reference to the
        // buffer's memory, the DMA slice, is gone.
        (unsafe { &mut *buffer.as_ptr() }, Ok(()))
    }
}

/// The board's fault blink (`board_support::fault`; the LED is lit by a
/// low pin).
fn fault(led: &mut Output<'_>, code: u32) -> ! {
    let mut delay = Delay::new();
    board_support::fault(led, code, true, |n| delay.delay_ms(200 * n))
}

#[esp_hal::main]
fn main() -> ! {
    // First, before any interrupt can push a frame below the stack pointer.
    stack_gauge::paint();
    let peripherals = esp_hal::init(esp_hal::Config::default().with_cpu_clock(CpuClock::max()));
    let mut led = Output::new(peripherals.GPIO8, Level::High, OutputConfig::default());

    // The display: SPI2 transmit-only through GDMA channel 0, CS driven as
    // a GPIO around each tile.
    let Ok(spi) = Spi::new(
        peripherals.SPI2,
        SpiConfig::default()
            .with_frequency(Rate::from_mhz(SPI_MHZ))
            .with_mode(Mode::_3)
            .with_min_async_transfer_size(SMALL_WRITE),
    ) else {
        fault(&mut led, 3)
    };
    let mut spi = spi
        .with_sck(peripherals.GPIO4)
        .with_mosi(peripherals.GPIO6)
        .with_dma(peripherals.DMA_CH0);
    let mut cs = Output::new(peripherals.GPIO7, Level::High, OutputConfig::default());
    let mut dc = Output::new(peripherals.GPIO5, Level::Low, OutputConfig::default());
    let mut rst = Output::new(peripherals.GPIO10, Level::High, OutputConfig::default());
    let mut backlight = Output::new(peripherals.GPIO3, Level::Low, OutputConfig::default());

    // The panel's start-up sequence, CS driven as a GPIO around each
    // command.
    if board_support::init_st7789(
        &mut spi,
        &mut cs,
        &mut dc,
        &mut rst,
        Delay::new(),
        (WIDTH as u16, HEIGHT as u16),
    )
    .is_err()
    {
        fault(&mut led, 3)
    }
    let mut panel = Panel {
        spi: Some(spi),
        descriptors: Some(DMA_DESCRIPTORS.take().get_mut().unsize()),
        in_flight: None,
        cs,
        dc,
    };

    // The scene: the knot is generated once, into its static. These lines
    // and the frame loop read as the Pico 2's on purpose: each board keeps
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
        // Microseconds since boot.
        let now = Instant::now().duration_since_epoch().as_micros();
        let (back, result) = frames.draw(now, tiles, &mut panel);
        tiles = back;
        if result.is_err() {
            fault(&mut led, 5);
        }
        PEAK_STACK_BYTES.store(stack_gauge::peak(), Ordering::Relaxed);
        // Lit once the first frame is on the panel, so the panel's
        // power-up contents are never seen; a no-op after that.
        backlight.set_high();
        led.toggle();
    }
}
