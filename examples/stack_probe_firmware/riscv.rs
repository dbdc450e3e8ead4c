//! The stack probe's runtime on QEMU's RISC-V `virt` machine
//! (`riscv32imc-unknown-none-elf`, the ESP32-C3's instruction set): a
//! start-up of a few instructions (stack pointer, `.bss` cleared, then
//! `probe_main`), the memory map of `memory/qemu-riscv32-virt.x`, output
//! on the machine's 16550 UART and exit through its SiFive test device.
//! esp-hal's own start-up does more (clocks, watchdogs, `.data` copied
//! from flash) before its `main`, none of it on the frame's stack.

use core::arch::global_asm;
use core::sync::atomic::{AtomicBool, Ordering};

/// The 16550 UART's registers.
const UART: usize = 0x1000_0000;
/// Line status register: bit 5, room in the transmitter.
const UART_LSR: usize = UART + 5;
/// The SiFive test device: a write ends the emulation.
const TEST_DEVICE: usize = 0x0010_0000;
/// Its "pass" value; "fail" is `code << 16 | 0x3333`.
const PASS: u32 = 0x5555;
const FAIL: u32 = 0x3333;

global_asm!(
    r#"
    .section .text.start, "ax"
    .global _start
_start:
    .option push
    .option norelax
    la sp, _stack_start
    .option pop
    la t0, _sbss
    la t1, _ebss
1:
    bgeu t0, t1, 2f
    sw zero, 0(t0)
    addi t0, t0, 4
    j 1b
2:
    call probe_main
3:
    j 3b
"#
);

/// The probe's output: the UART.
pub struct Out;

impl core::fmt::Write for Out {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for &b in s.as_bytes() {
            // SAFETY: the `virt` machine's UART registers, byte-wide
            // device memory that nothing else uses.
            unsafe {
                while core::ptr::read_volatile(UART_LSR as *const u8) & 0x20 == 0 {}
                core::ptr::write_volatile(UART as *mut u8, b);
            }
        }
        Ok(())
    }
}

/// Ends the emulation with the probe's verdict as QEMU's exit status.
pub fn exit(ok: bool) -> ! {
    let value = if ok { PASS } else { (1 << 16) | FAIL };
    // SAFETY: the `virt` machine's test device register.
    unsafe { core::ptr::write_volatile(TEST_DEVICE as *mut u32, value) };
    loop {
        core::hint::spin_loop();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    use core::fmt::Write;
    let _ = writeln!(Out, "stack_probe: {info}");
    exit(false)
}

/// Where `_start` goes once the stack and `.bss` are ready.
#[no_mangle]
extern "C" fn probe_main() -> ! {
    // First, before anything has used the stack.
    crate::stack_gauge::paint();
    start_counting();
    crate::firmware::run()
}

/// Whether `minstret` counts instructions: [`start_counting`] found it so.
static COUNTING: AtomicBool = AtomicBool::new(false);

/// Checks that `minstret` counts exactly the instructions executed, as
/// QEMU's does under `-icount shift=0` (without it, QEMU derives it from
/// the host's clock): a loop of 200,000 instructions between two readings
/// must count as that, give or take the readings' own. Once, before
/// [`instructions`], which counts nothing otherwise.
pub fn start_counting() {
    const TURNS: u32 = crate::firmware::CALIBRATION_TURNS;
    let before = read_instret();
    // Two instructions a turn.
    // SAFETY: a counted loop on one scratch register, nothing else.
    unsafe {
        core::arch::asm!(
            "2:",
            "addi {n}, {n}, -1",
            "bnez {n}, 2b",
            n = inout(reg) TURNS => _,
            options(nomem, nostack),
        );
    }
    let counted = read_instret().wrapping_sub(before);
    COUNTING.store(
        counted.abs_diff(u64::from(2 * TURNS)) < 32,
        Ordering::Relaxed,
    );
}

/// The instructions a reading of [`instructions`] may be off by: none.
pub fn resolution() -> u32 {
    1
}

/// The instructions executed since reset, where [`start_counting`] found
/// `minstret` counting them.
pub fn instructions() -> Option<u64> {
    COUNTING.load(Ordering::Relaxed).then(read_instret)
}

/// The `minstret` counter, with `minstreth` read until the high word
/// holds still.
fn read_instret() -> u64 {
    loop {
        let (high, low, again): (u32, u32, u32);
        // SAFETY: reads of the machine-mode counters, which the probe
        // (in machine mode from reset) may read; nothing is written.
        unsafe {
            core::arch::asm!(
                "csrr {0}, minstreth",
                "csrr {1}, minstret",
                "csrr {2}, minstreth",
                out(reg) high,
                out(reg) low,
                out(reg) again,
                options(nomem, nostack),
            );
        }
        if high == again {
            return u64::from(high) << 32 | u64::from(low);
        }
    }
}
