//! The stack probe's runtime on QEMU's `mps2-an505` (Cortex-M33,
//! `thumbv8m.main-none-eabihf`, the RP2350's core): cortex-m-rt's start-up
//! and vector table (as on the Pico 2, whose rp235x-hal uses the same
//! runtime), output and exit through semihosting.

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
    crate::firmware::run()
}

/// The instructions executed since reset: none counted here (the
/// Cortex-M figures come from the `icount` firmware's timer instead).
pub fn instructions() -> Option<u64> {
    None
}
