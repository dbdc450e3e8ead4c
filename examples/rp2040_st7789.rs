//! Firmware for a Raspberry Pi Pico (RP2040): renders a lit torus knot of
//! 2,048 triangles with a cube orbiting it, with microraster, in 32x32
//! tiles, on a 240x240 ST7789 on SPI1, frame after frame. A DMA channel
//! sends each finished tile while the core draws the next one
//! (`Frame::render_double_buffered` over two tile buffers), so a frame
//! takes about the longer of the drawing and the sending, not their sum.
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
//! tile: the window's CASET/RASET/RAMWR from the core (DC low for each
//! command byte, high for its parameters), then the tile's pixels by DMA
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
mod firmware {
    use crate::board_support;
    use crate::st7789_scene::*;
    use core::convert::Infallible;
    use core::mem;
    use embedded_dma::ReadBuffer;
    use embedded_hal::digital::{OutputPin, StatefulOutputPin};
    use embedded_hal::spi::{SpiBus, MODE_3};
    use embedded_hal_bus::spi::ExclusiveDevice;
    use microraster::prelude::*;
    use microraster::sink::wire::{wire_bytes, Window};
    use mipidsi::interface::SpiInterface;
    use mipidsi::models::ST7789;
    use mipidsi::options::ColorInversion;
    use mipidsi::Builder;
    use panic_halt as _;
    use rp2040_hal::clocks::{init_clocks_and_plls, Clock};
    use rp2040_hal::dma::single_buffer::{self, Transfer};
    use rp2040_hal::dma::{DMAExt, SingleChannel, WriteTarget};
    use rp2040_hal::fugit::RateExtU32;
    use rp2040_hal::gpio::{FunctionSpi, PinState, Pins};
    use rp2040_hal::{pac, Sio, Spi, Timer, Watchdog};
    use static_cell::{ConstStaticCell, StaticCell};

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
    // The two tile buffers. `'static`, as a DMA transfer's buffer must be:
    // a transfer that was leaked must not go on reading freed memory.
    // Built at start-up (see `tiles`), so that they take RAM (.bss) and no
    // flash: a `const` tile buffer holds the farthest depth, not zeros,
    // and would be stored in flash as initial data (.data).
    static TILE_A: StaticCell<PicoTile> = StaticCell::new();
    static TILE_B: StaticCell<PicoTile> = StaticCell::new();

    /// The two tile buffers, once (`None` the second time). Not inlined: the
    /// compiler builds each 4 KiB buffer on the stack before it moves it
    /// into its static, and here that stack is given back before the first
    /// frame instead of staying in `main`'s frame under every render. (The
    /// buffers' first colour is never seen: each tile is cleared first.)
    #[inline(never)]
    fn tiles() -> Option<[&'static mut PicoTile; 2]> {
        let new = || PicoTile::new(Rgb565Be::new(0, 0, 0));
        Some([TILE_A.try_init_with(new)?, TILE_B.try_init_with(new)?])
    }

    /// A finished tile, packed into one block of wire bytes, as the DMA
    /// channel reads it: the buffer and the block's address and length.
    struct TileBytes {
        tile: &'static mut PicoTile,
        bytes: (*const u8, usize),
    }

    impl TileBytes {
        /// Packs the tile that covers `area` of the frame (see
        /// `TileBuffer::pack`) and takes its buffer.
        fn new(tile: &'static mut PicoTile, area: &Rectangle) -> Self {
            let bytes = wire_bytes(tile.pack(area));
            Self { tile, bytes }
        }
    }

    // SAFETY: `bytes` lies within `*tile` (it was made from the tile's
    // packed pixels, `2 n` bytes for `n` pixels) and never changes. The
    // buffer is `'static` and borrowed exclusively by `self`, so nothing
    // else writes or frees it while the DMA channel reads it: the channel's
    // `Transfer` owns `self` until it is done, and only then gives the
    // buffer back (`TileTransfer::wait`).
    unsafe impl ReadBuffer for TileBytes {
        type Word = u8;

        unsafe fn read_buffer(&self) -> (*const u8, usize) {
            self.bytes
        }
    }

    /// Where the bus is: free, carrying a tile by DMA, or (in serial mode)
    /// done with a tile that `wait` has not yet given back.
    enum Link<CH: SingleChannel, S: WriteTarget<TransmittedWord = u8>> {
        Idle(CH, S),
        Sending(Transfer<CH, TileBytes, S>),
        Sent(CH, TileBytes, S),
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

    /// The panel, past its set-up, as a [`TileTransfer`]: the window
    /// commands of each tile from the core, then its pixels by DMA.
    struct Panel<CH: SingleChannel, S: WriteTarget<TransmittedWord = u8>, DC> {
        link: Link<CH, S>,
        dc: DC,
        /// Wait for every tile to be on the wire (`MICRORASTER_PICO_SERIAL`).
        serial: bool,
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
            // A finished DMA transfer has only put its last bytes into the
            // SPI's FIFO: DC changes only once the SPI is idle (`flush`),
            // so that no byte goes out with the wrong DC.
            for (command, parameters) in window.commands() {
                let Ok(()) = spi.flush();
                let Ok(()) = self.dc.set_low();
                let Ok(()) = spi.write(&[command]);
                let Ok(()) = spi.flush();
                let Ok(()) = self.dc.set_high();
                let Ok(()) = spi.write(parameters);
            }
            // After RAMWR, DC high: the pixels, by DMA, paced by SPI1's TX
            // DREQ (the FIFO's room).
            let bytes = TileBytes::new(tile, area);
            let transfer = single_buffer::Config::new(channel, bytes, spi).start();
            self.link = if self.serial {
                let (channel, bytes, mut spi) = transfer.wait();
                let Ok(()) = spi.flush();
                Link::Sent(channel, bytes, spi)
            } else {
                Link::Sending(transfer)
            };
            Ok(())
        }

        fn wait(&mut self) -> (&'static mut PicoTile, Result<(), PanelError>) {
            let (channel, bytes, spi) = match mem::replace(&mut self.link, Link::Taken) {
                // Done once the channel has written the last byte into the
                // FIFO; the next `start` waits for the FIFO to drain.
                Link::Sending(transfer) => transfer.wait(),
                Link::Sent(channel, bytes, spi) => (channel, bytes, spi),
                // `render_double_buffered` waits only after a successful
                // start, so there is always a buffer to give back here.
                Link::Idle(..) | Link::Taken => park(),
            };
            self.link = Link::Idle(channel, spi);
            (bytes.tile, Ok(()))
        }
    }

    /// Sleeps forever: for the one state in which not even the LED can be
    /// reached.
    fn park() -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// The board's fault blink (`board_support::fault`), timed by busy
    /// loops.
    fn fault(led: &mut impl OutputPin<Error = Infallible>, code: u32) -> ! {
        board_support::fault(led, code, false, |n| cortex_m::asm::delay(n * BLINK_CYCLES))
    }

    #[rp2040_hal::entry]
    fn main() -> ! {
        // Taken once, at the entry point: never `None` here.
        let Some(mut pac) = pac::Peripherals::take() else {
            park()
        };
        let sio = Sio::new(pac.SIO);
        let pins = Pins::new(
            pac.IO_BANK0,
            pac.PADS_BANK0,
            sio.gpio_bank0,
            &mut pac.RESETS,
        );
        let mut led = pins.gpio25.into_push_pull_output_in_state(PinState::Low);

        // 125 MHz system and peripheral clocks from the crystal.
        let mut watchdog = Watchdog::new(pac.WATCHDOG);
        let Ok(clocks) = init_clocks_and_plls(
            XTAL_HZ,
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            &mut watchdog,
        ) else {
            fault(&mut led, 2)
        };
        let timer = Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

        // The display: SPI1 transmit-only, mode 3 (which also suits modules
        // whose CS is tied low).
        let sck = pins.gpio10.into_function::<FunctionSpi>();
        let mosi = pins.gpio11.into_function::<FunctionSpi>();
        let mut cs = pins.gpio9.into_push_pull_output_in_state(PinState::High);
        let mut dc = pins.gpio8.into_push_pull_output_in_state(PinState::Low);
        let mut rst = pins.gpio12.into_push_pull_output_in_state(PinState::High);
        let mut backlight = pins.gpio13.into_push_pull_output_in_state(PinState::Low);
        let mut spi = Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sck)).init(
            &mut pac.RESETS,
            clocks.peripheral_clock.freq(),
            SPI_HZ.Hz(),
            MODE_3,
        );
        // mipidsi's start-up sequence, through borrowed pins and bus (CS
        // driven as a GPIO around each command), which come back when the
        // display is dropped. 240x240 ST7789 panels are IPS panels that
        // need inverted colours. mipidsi draws no pixel here, so its pixel
        // buffer can be tiny.
        {
            let mut delay = board_support::AtLeast(timer);
            let mut scratch = [0; 4];
            let Ok(device) = ExclusiveDevice::new(&mut spi, &mut cs, timer);
            let interface = SpiInterface::new(device, &mut dc, &mut scratch);
            if Builder::new(ST7789, interface)
                .display_size(WIDTH as u16, HEIGHT as u16)
                .invert_colors(ColorInversion::Inverted)
                .reset_pin(&mut rst)
                .init(&mut delay)
                .is_err()
            {
                fault(&mut led, 3)
            }
        }
        // From here on the panel is the bus's: CS low for good.
        let Ok(()) = cs.set_low();
        let dma = pac.DMA.split(&mut pac.RESETS);
        // Read once, as a value the compiler cannot assume (the harness
        // may have changed it in the image).
        // SAFETY: a valid, aligned `'static` byte that nothing writes.
        let serial = unsafe { core::ptr::read_volatile(&MICRORASTER_PICO_SERIAL) } != 0;
        // SAFETY: as for the byte above, a valid, aligned `'static` word.
        let frame_us = unsafe { core::ptr::read_volatile(&MICRORASTER_PICO_FRAME_US) } as u64;
        let mut panel = Panel {
            link: Link::Idle(dma.ch0, spi),
            dc,
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
        let Some(mut tiles) = tiles() else {
            fault(&mut led, 4)
        };

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
            let (back, result) = match PicoFrame::begin(config, workspace, &scene) {
                Ok(frame) => frame.render_double_buffered(tiles, &mut panel),
                Err(e) => (tiles, Err(e.for_sink())),
            };
            tiles = back;
            if result.is_err() {
                fault(&mut led, 5);
            }
            // Lit once the first frame is on the panel, so the panel's
            // power-up contents are never seen; a no-op after that.
            let Ok(()) = backlight.set_high();
            let Ok(()) = led.toggle();
        }
    }
}
