//! What the board firmwares share besides the scene
//! (`examples/st7789_scene`): the ST7789's start-up sequence, the panel's
//! set-up delays made "at least", and the fault blink that stands in for a
//! panic. `no_std`, and generic over embedded-hal's traits, so the Pico
//! (rp2040-hal, and embassy-rp), Pico 2 (rp235x-hal) and ESP32-C3
//! (esp-hal) firmwares include the same file.
#![allow(dead_code)]

use core::convert::Infallible;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{OutputPin, PinState};
use embedded_hal::spi::SpiBus;
use embedded_hal_bus::spi::ExclusiveDevice;
use microraster::sink::wire::Window;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use mipidsi::Builder;

/// The ST7789 did not take its start-up sequence (a pin or the bus failed).
pub struct PanelInitFailed;

/// Sends the ST7789's start-up sequence through mipidsi (hardware reset on
/// `rst`, SLPOUT, MADCTL, INVON, COLMOD 0x55, NORON, DISPON) for a
/// `width` x `height` panel, borrowing the bus and the pins, which come
/// back when it returns; the panel keeps its state. CS is driven as a GPIO
/// around each command. 240x240 ST7789 panels are IPS panels that need
/// inverted colours. mipidsi draws no pixel here, so its pixel buffer can
/// be tiny. `delay` times the bus's transactions, and, made
/// [`AtLeast`], the reset pulse and the waits of the sequence.
pub fn init_st7789<S, CS, DC, RST, D>(
    spi: &mut S,
    cs: &mut CS,
    dc: &mut DC,
    rst: &mut RST,
    delay: D,
    (width, height): (u16, u16),
) -> Result<(), PanelInitFailed>
where
    S: SpiBus,
    CS: OutputPin,
    DC: OutputPin,
    RST: OutputPin,
    D: DelayNs + Clone,
{
    let device = ExclusiveDevice::new(spi, cs, delay.clone()).map_err(|_| PanelInitFailed)?;
    let mut scratch = [0; 4];
    let interface = SpiInterface::new(device, dc, &mut scratch);
    Builder::new(ST7789, interface)
        .display_size(width, height)
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut AtLeast(delay))
        .map(drop)
        .map_err(|_| PanelInitFailed)
}

/// A delay made "at least": the RP2040's and RP2350's `Timer` count whole
/// ticks of a 1 MHz counter from the one they start in, so a delay can end
/// up to 1 us early. That matters for the panel's reset pulse (mipidsi
/// holds RES low for the 10 us minimum of the ST7789's datasheet, no
/// more): one more tick makes every set-up delay at least what mipidsi
/// asks for.
pub struct AtLeast<D>(pub D);

impl<D: DelayNs> DelayNs for AtLeast<D> {
    fn delay_ns(&mut self, ns: u32) {
        self.0.delay_us(ns.div_ceil(1_000).saturating_add(1));
    }
}

/// Blinks `code` times, pauses, and again, forever: what a firmware does
/// instead of panicking when the board cannot be brought up. `wait(n)`
/// waits `n` blink units (a busy loop: a fault can come before any timer
/// runs); `active_low` for an LED lit by a low pin.
pub fn fault<P: OutputPin>(
    led: &mut P,
    code: u32,
    active_low: bool,
    mut wait: impl FnMut(u32),
) -> ! {
    let (on, off) = (PinState::from(!active_low), PinState::from(active_low));
    loop {
        for _ in 0..code {
            // A pin that fails to switch leaves nothing better to do.
            let _ = led.set_state(on);
            wait(1);
            let _ = led.set_state(off);
            wait(1);
        }
        wait(4);
    }
}

/// Sends the panel's window commands for a tile (`CASET`, `RASET`,
/// `RAMWR`, each with its parameters) and leaves DC high for `RAMWR`'s
/// data. A finished DMA transfer may still have its last bytes in the
/// SPI's FIFO: DC changes only once the SPI is idle (`flush`), so that no
/// byte goes out with the wrong DC.
pub fn send_window<S, DC>(spi: &mut S, dc: &mut DC, window: &Window) -> Result<(), S::Error>
where
    S: SpiBus,
    DC: OutputPin<Error = Infallible>,
{
    for (command, parameters) in window.commands() {
        spi.flush()?;
        let Ok(()) = dc.set_low();
        spi.write(&[command])?;
        spi.flush()?;
        let Ok(()) = dc.set_high();
        spi.write(parameters)?;
    }
    Ok(())
}

/// The bring-up the Pico and Pico 2 firmwares share, expanded in their
/// `main`: the peripherals taken, the system and peripheral clocks from
/// the crystal (`XTAL_HZ`), the timer (`$timer`, made by `Timer::$new`),
/// the wiring of README's table (LED GP25; SPI1 transmit-only in mode 3 at
/// `SPI_HZ`, SCK GP10, MOSI GP11; CS GP9, DC GP8, reset GP12, backlight
/// GP13) and the ST7789's start-up ([`init_st7789`], `WIDTH` x `HEIGHT`),
/// after which CS stays low. rp2040-hal and rp235x-hal agree here name for
/// name but not type for type, so this is a macro, whose names resolve
/// where it is expanded: the firmware imports them, and provides `park`
/// and `fault` (code 2: the clocks, 3: the panel). Gives `(led, spi, dc,
/// backlight, timer, dma)`.
#[allow(unused_macros)]
macro_rules! rp_st7789_bring_up {
    ($timer:ident, $new:ident) => {{
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
        let timer = Timer::$new(pac.$timer, &mut pac.RESETS, &clocks);
        let sck = pins.gpio10.into_function::<FunctionSpi>();
        let mosi = pins.gpio11.into_function::<FunctionSpi>();
        let mut cs = pins.gpio9.into_push_pull_output_in_state(PinState::High);
        let mut dc = pins.gpio8.into_push_pull_output_in_state(PinState::Low);
        let mut rst = pins.gpio12.into_push_pull_output_in_state(PinState::High);
        let backlight = pins.gpio13.into_push_pull_output_in_state(PinState::Low);
        // Mode 3 also suits modules whose CS is tied low.
        let mut spi = Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sck)).init(
            &mut pac.RESETS,
            clocks.peripheral_clock.freq(),
            SPI_HZ.Hz(),
            MODE_3,
        );
        if board_support::init_st7789(
            &mut spi,
            &mut cs,
            &mut dc,
            &mut rst,
            timer,
            (WIDTH as u16, HEIGHT as u16),
        )
        .is_err()
        {
            fault(&mut led, 3)
        }
        // From here on the panel is the bus's: CS low for good.
        let Ok(()) = cs.set_low();
        let dma = pac.DMA.split(&mut pac.RESETS);
        (led, spi, dc, backlight, timer, dma)
    }};
}
#[allow(unused_imports)]
pub(crate) use rp_st7789_bring_up;

/// The `park` and `fault` of the Pico and Pico 2 firmwares (which
/// [`rp_st7789_bring_up`] calls), over `$arch`'s `wfi` and `delay`:
/// `cortex_m::asm` on the Pico, rp235x-hal's `hal::arch` on the Pico 2.
/// Expanded where the firmware imports `OutputPin` and `Infallible` and
/// defines `BLINK_CYCLES`, the busy-loop cycles of a blink unit.
#[allow(unused_macros)]
macro_rules! rp_park_and_fault {
    ($($arch:ident)::+) => {
        /// Sleeps forever: for the one state in which not even the LED can
        /// be reached.
        fn park() -> ! {
            loop {
                $($arch)::+::wfi();
            }
        }

        /// The board's fault blink (`board_support::fault`), timed by busy
        /// loops.
        fn fault(led: &mut impl OutputPin<Error = Infallible>, code: u32) -> ! {
            board_support::fault(led, code, false, |n| {
                $($arch)::+::delay(n * BLINK_CYCLES)
            })
        }
    };
}
#[allow(unused_imports)]
pub(crate) use rp_park_and_fault;
