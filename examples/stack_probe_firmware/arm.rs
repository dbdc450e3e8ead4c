//! The stack probe's runtime on QEMU's `mps2-an505` (Cortex-M33,
//! `thumbv8m.main-none-eabihf`, the RP2350's core): cortex-m-rt's start-up
//! and vector table (as on the Pico 2, whose rp235x-hal uses the same
//! runtime), output and exit through semihosting.

use core::cell::Cell;
use cortex_m::interrupt::{free, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use panic_semihosting as _;

/// The probe's output: semihosting's stdout.
pub struct Out;

impl core::fmt::Write for Out {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        cortex_m_semihosting::hprint!("{}", s);
        Ok(())
    }
}

/// Ends the emulation with the probe's verdict as QEMU's exit status.
pub fn exit(ok: bool) -> ! {
    use cortex_m_semihosting::debug;
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

#[cortex_m_rt::entry]
fn main() -> ! {
    // First, before anything has used the stack.
    crate::stack_gauge::paint();
    start_counting();
    crate::firmware::run()
}

/// SysTick's current value register (SYST_CVR), counting down.
const SYST_CVR: *const u32 = 0xE000_E018 as *const u32;

/// The counter's state: instructions per SysTick tick, from
/// [`start_counting`] (0 before, or where SysTick does not count
/// instructions); SysTick's value at the last reading; the ticks counted
/// up to it.
static COUNTER: Mutex<Cell<(u32, u32, u64)>> = Mutex::new(Cell::new((0, 0, 0)));

/// Starts SysTick counting down from its full 24 bits on the core's
/// clock, which QEMU's `-icount shift=0` advances 1 ns an instruction,
/// and finds how many instructions a tick is by timing a loop of known
/// length; without `-icount` the ratio is not a whole number and nothing
/// is counted. Once, before [`instructions`].
pub fn start_counting() {
    let Some(mut core) = cortex_m::Peripherals::take() else {
        return;
    };
    let syst = &mut core.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00FF_FFFF);
    syst.clear_current();
    syst.enable_counter();
    // SAFETY: SysTick's value register, read-only here.
    let read = || unsafe { core::ptr::read_volatile(SYST_CVR) };
    const TURNS: u32 = crate::firmware::CALIBRATION_TURNS;
    let before = read();
    // Two instructions a turn: 200,000 instructions, plus the reads'.
    // SAFETY: a counted loop on one scratch register, nothing else.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, #1",
            "bne 2b",
            n = inout(reg) TURNS => _,
            options(nomem, nostack),
        );
    }
    let ticks = before.wrapping_sub(read()) & 0x00FF_FFFF;
    // 200,000 instructions in whole ticks, give or take the one the reads
    // straddle.
    let per_tick = (2 * TURNS + ticks / 2) / ticks.max(1);
    if ticks > 0 && (2 * TURNS).abs_diff(per_tick * ticks) <= per_tick {
        free(|cs| COUNTER.borrow(cs).set((per_tick, read(), 0)));
    }
}

/// The instructions a reading of [`instructions`] may be off by: a tick.
pub fn resolution() -> u32 {
    free(|cs| COUNTER.borrow(cs).get().0)
}

/// The instructions executed since [`start_counting`], to within a SysTick
/// tick (its instructions a tick; the readings come at least once a
/// frame, far less than the counter's 2^24 ticks apart), or `None`
/// where SysTick does not count instructions.
pub fn instructions() -> Option<u64> {
    free(|cs| {
        let state = COUNTER.borrow(cs);
        let (per_tick, last, ticks) = state.get();
        if per_tick == 0 {
            return None;
        }
        // SAFETY: SysTick's value register, read-only here.
        let now = unsafe { core::ptr::read_volatile(SYST_CVR) };
        let ticks = ticks + u64::from(last.wrapping_sub(now) & 0x00FF_FFFF);
        state.set((per_tick, now, ticks));
        Some(ticks * u64::from(per_tick))
    })
}
