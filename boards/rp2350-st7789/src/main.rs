//! Firmware for a Raspberry Pi Pico 2 (RP2350, Cortex-M33): the Pico
//! example's lit torus knot and orbiting cube (`examples/st7789_scene`),
//! rendered by microraster and streamed tile by tile over SPI1 to a 240x240
//! ST7789 through mipidsi, frame after frame, wired as on the Pico
//! (Waveshare's Pico-LCD-1.3 fits both boards).
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
//! The RP2350 boots without a second-stage bootloader: its boot ROM looks
//! for an IMAGE_DEF block in the first 4 KiB of flash (`memory.x` puts it
//! right after the vector table) and starts the image it describes.

#![no_std]
#![no_main]

#[path = "../../../examples/st7789_scene/mod.rs"]
mod st7789_scene;

use core::convert::Infallible;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{OutputPin, StatefulOutputPin};
use embedded_hal::spi::MODE_3;
use embedded_hal_bus::spi::ExclusiveDevice;
use microraster::prelude::*;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use mipidsi::Builder;
use panic_halt as _;
use rp235x_hal as hal;
use st7789_scene::*;
use static_cell::ConstStaticCell;

use hal::clocks::{init_clocks_and_plls, Clock};
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
/// mipidsi gathers pixels into this buffer before each SPI write: one
/// 32x32 Rgb565 tile, so one transfer per tile.
const SPI_BUFFER_BYTES: usize = TILE * TILE * 2;
/// Half a period of the fault blink: 0.2 s at 150 MHz (slower if the clocks
/// never came up).
const BLINK_CYCLES: u32 = 30_000_000;

// Built in place in RAM (.bss), never moved through the stack.
static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
static SPI_BUFFER: ConstStaticCell<[u8; SPI_BUFFER_BYTES]> =
    ConstStaticCell::new([0; SPI_BUFFER_BYTES]);

/// The timer's delays made "at least": rp235x-hal's `Timer` counts whole
/// ticks of its 1 MHz counter from the one it starts in, so a delay can end
/// up to 1 us early. That matters for the panel's reset pulse (mipidsi
/// holds RES low for the 10 us minimum of the ST7789's datasheet, no more):
/// one more tick makes every set-up delay at least what mipidsi asks for.
struct AtLeast<D>(D);

impl<D: DelayNs> DelayNs for AtLeast<D> {
    fn delay_ns(&mut self, ns: u32) {
        self.0.delay_us(ns.div_ceil(1_000).saturating_add(1));
    }
}

/// Sleeps forever: for the one state in which not even the LED can be
/// reached.
fn park() -> ! {
    loop {
        hal::arch::wfi();
    }
}

/// Blinks `code` times, pauses, and again, forever: what the firmware does
/// instead of panicking when the board cannot be brought up.
fn fault(led: &mut impl OutputPin<Error = Infallible>, code: u32) -> ! {
    loop {
        for _ in 0..code {
            let Ok(()) = led.set_high();
            hal::arch::delay(BLINK_CYCLES);
            let Ok(()) = led.set_low();
            hal::arch::delay(BLINK_CYCLES);
        }
        hal::arch::delay(4 * BLINK_CYCLES);
    }
}

#[hal::entry]
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

    // 150 MHz system and peripheral clocks from the crystal.
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
    let timer = Timer::new_timer0(pac.TIMER0, &mut pac.RESETS, &clocks);

    // The display: SPI1 transmit-only, mode 3 (which also suits modules
    // whose CS is tied low), CS driven as a GPIO around each transfer.
    let sck = pins.gpio10.into_function::<FunctionSpi>();
    let mosi = pins.gpio11.into_function::<FunctionSpi>();
    let cs = pins.gpio9.into_push_pull_output_in_state(PinState::High);
    let dc = pins.gpio8.into_push_pull_output_in_state(PinState::Low);
    let rst = pins.gpio12.into_push_pull_output_in_state(PinState::High);
    let mut backlight = pins.gpio13.into_push_pull_output_in_state(PinState::Low);
    let spi = Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        SPI_HZ.Hz(),
        MODE_3,
    );
    let Ok(spi) = ExclusiveDevice::new(spi, cs, timer);
    let interface = SpiInterface::new(spi, dc, SPI_BUFFER.take());
    // 240x240 ST7789 panels are IPS panels that need inverted colours.
    let mut delay = AtLeast(timer);
    let Ok(mut display) = Builder::new(ST7789, interface)
        .display_size(WIDTH as u16, HEIGHT as u16)
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut delay)
    else {
        fault(&mut led, 3)
    };

    // The scene: the knot is generated once, into its static.
    let (Some(knot), Some(cube), Some(camera)) = (KNOT.take().generate(), cube(), camera()) else {
        fault(&mut led, 4)
    };
    let workspace = WORKSPACE.take();
    let mut renderer = Rgb565Renderer::new(config());

    loop {
        // The timer counts microseconds from its reset above.
        let draws = draws(&knot, &cube, timer.get_counter().ticks());
        let scene = Scene::new(camera, &draws).light(light());
        if renderer.render(workspace, &scene, &mut display).is_err() {
            fault(&mut led, 5);
        }
        // Lit once the first frame is on the panel, so the panel's
        // power-up contents are never seen; a no-op after that.
        let Ok(()) = backlight.set_high();
        let Ok(()) = led.toggle();
    }
}
