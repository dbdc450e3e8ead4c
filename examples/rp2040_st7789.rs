//! Firmware for a Raspberry Pi Pico (RP2040): renders a lit torus knot of
//! 2,048 triangles with a cube orbiting it, with microraster, and streams
//! every finished 32x32 Rgb565 tile over SPI1 to a 240x240 ST7789 through
//! mipidsi, frame after frame.
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
mod st7789_scene;

#[cfg(target_os = "none")]
mod firmware {
    use crate::st7789_scene::*;
    use core::convert::Infallible;
    use embedded_hal::digital::{OutputPin, StatefulOutputPin};
    use embedded_hal::spi::MODE_3;
    use embedded_hal_bus::spi::ExclusiveDevice;
    use microraster::prelude::*;
    use mipidsi::interface::SpiInterface;
    use mipidsi::models::ST7789;
    use mipidsi::options::ColorInversion;
    use mipidsi::Builder;
    use panic_halt as _;
    use rp2040_hal::clocks::{init_clocks_and_plls, Clock};
    use rp2040_hal::fugit::RateExtU32;
    use rp2040_hal::gpio::{FunctionSpi, PinState, Pins};
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

    /// The Pico's crystal.
    const XTAL_HZ: u32 = 12_000_000;
    /// The SPI clock asked for: the RP2040's fastest (the 125 MHz
    /// peripheral clock halved). Lower it if long wires garble the picture.
    const SPI_HZ: u32 = 62_500_000;
    /// mipidsi gathers pixels into this buffer before each SPI write: one
    /// 32x32 Rgb565 tile, so one transfer per tile.
    const SPI_BUFFER_BYTES: usize = TILE * TILE * 2;
    /// Half a period of the fault blink: 0.2 s at 125 MHz (slower if the
    /// clocks never came up).
    const BLINK_CYCLES: u32 = 25_000_000;

    // Built in place in RAM (.bss), never moved through the stack.
    static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
    static WORKSPACE: ConstStaticCell<PicoWorkspace> = ConstStaticCell::new(PicoWorkspace::new());
    static SPI_BUFFER: ConstStaticCell<[u8; SPI_BUFFER_BYTES]> =
        ConstStaticCell::new([0; SPI_BUFFER_BYTES]);

    /// Sleeps forever: for the one state in which not even the LED can be
    /// reached.
    fn park() -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// Blinks `code` times, pauses, and again, forever: what the firmware
    /// does instead of panicking when the board cannot be brought up.
    fn fault(led: &mut impl OutputPin<Error = Infallible>, code: u32) -> ! {
        loop {
            for _ in 0..code {
                let Ok(()) = led.set_high();
                cortex_m::asm::delay(BLINK_CYCLES);
                let Ok(()) = led.set_low();
                cortex_m::asm::delay(BLINK_CYCLES);
            }
            cortex_m::asm::delay(4 * BLINK_CYCLES);
        }
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
        let mut delay = timer;
        let Ok(mut display) = Builder::new(ST7789, interface)
            .display_size(WIDTH as u16, HEIGHT as u16)
            .invert_colors(ColorInversion::Inverted)
            .reset_pin(rst)
            .init(&mut delay)
        else {
            fault(&mut led, 3)
        };

        // The scene: the knot is generated once, into its static.
        let (Some(knot), Some(cube), Some(camera)) = (KNOT.take().generate(), cube(), camera())
        else {
            fault(&mut led, 4)
        };
        let workspace = WORKSPACE.take();
        let mut renderer = PicoRenderer::new(config());

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
}
