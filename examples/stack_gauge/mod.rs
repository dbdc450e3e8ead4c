//! Peak stack use of a firmware, measured by painting: [`paint`]
//! fills the RAM below the stack pointer with a pattern, and [`peak`] later
//! finds the lowest word that no longer holds it. The stack has used at
//! least down to there, so the peak is the distance from the top of RAM
//! (cortex-m-rt's `_stack_start`, the initial stack pointer) to that word.
//!
//! cortex-m-rt puts the stack at the top of RAM, growing down towards the
//! end of the statics (`_stack_end`, after `.bss` and `.uninit`); nothing
//! else uses the RAM between them in these firmwares (no heap). esp-hal's
//! runtime (the ESP32-C3) and the QEMU RISC-V probe's linker script
//! (`memory/qemu-riscv32-virt.x`) define the same two symbols with the same
//! meaning; on RISC-V the lowest [`GUARD`] bytes are left alone, where
//! esp-hal keeps its stack-overflow canary (`__stack_chk_guard`, 60 bytes
//! above `_stack_end` by default). The stack pointer is read with one
//! instruction (`mov` on Arm, `mv` on RISC-V), so no HAL or runtime crate
//! is needed: the board crates include this file too. A function
//! that uses stack without writing it (a large array it never fills) would
//! go unseen, so the figure is a lower bound; the renderer writes its tile
//! buffer whole at every tile.
//!
//! Only a window of [`WINDOW`] bytes under the top is painted and scanned:
//! the whole free RAM of the LM3S6965 and of the boards' chips, and on the
//! MPS2's 4 MiB one MiB, room for a renderer whose one tile is a whole
//! 320x240 frame (about 310 KB of colour and depth, built on the
//! firmware's stack), without painting megabytes at every scene.
#![allow(dead_code)]

/// What free stack holds until something writes it. An odd value, so that
/// neither a zero, a small count, an address in RAM or flash nor a Thumb
/// return address (odd, but below 0x2000_0000) is likely to equal it.
const PAINT: u32 = 0xC5AC_CE55;

/// The most that is painted and scanned, in bytes below the top of RAM.
pub const WINDOW: usize = 1024 * 1024;

/// Left unpainted under the caller's stack pointer, in bytes: room for the
/// frame of `paint` itself.
const MARGIN: usize = 64;

/// Left unpainted above the end of the statics, in bytes: none on Arm; on
/// RISC-V, room for esp-hal's stack canary, which a debugger may watch.
#[cfg(target_arch = "riscv32")]
const GUARD: usize = 256;
/// Left unpainted above the end of the statics, in bytes.
#[cfg(not(target_arch = "riscv32"))]
const GUARD: usize = 0;

extern "C" {
    /// The runtime's initial stack pointer, the top of RAM.
    static _stack_start: u32;
    /// The runtime's end of the statics, the lowest address the stack may
    /// reach.
    static _stack_end: u32;
}

/// The stack pointer, now.
#[inline(always)]
fn stack_pointer() -> usize {
    let sp: usize;
    // SAFETY: copies the stack pointer to a register; no memory is touched.
    #[cfg(target_arch = "arm")]
    unsafe {
        core::arch::asm!("mov {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags))
    };
    // SAFETY: as above.
    #[cfg(target_arch = "riscv32")]
    unsafe {
        core::arch::asm!("mv {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags))
    };
    sp
}

/// The top of the stack, and the lowest address painted and scanned.
fn bounds() -> (usize, usize) {
    // Only the symbols' addresses are taken, never read through.
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let end = core::ptr::addr_of!(_stack_end) as usize + GUARD;
    (top, end.max(top.saturating_sub(WINDOW)))
}

/// How deep the stack is now, in bytes below its top.
#[inline(always)]
pub fn depth() -> usize {
    bounds().0 - stack_pointer()
}

/// The bytes the stack may use before it reaches the statics (or the
/// window's end): the most [`peak`] can report.
pub fn room() -> usize {
    let (top, bottom) = bounds();
    top - bottom
}

/// Paints the free stack under the caller: from [`MARGIN`] bytes below the
/// current stack pointer down to the bottom of the window. Call it from as
/// high up the stack as the measurement should start (`main`, or a loop
/// that [`peak`] is read from).
#[inline(never)]
pub fn paint() {
    let (_, bottom) = bounds();
    let sp = stack_pointer();
    let start = sp.saturating_sub(MARGIN) & !3;
    let mut p = bottom;
    while p < start {
        // SAFETY: `p` is word-aligned (both symbols are, by the runtimes'
        // assertions and alignment, `GUARD` is a multiple of 4, and `start`
        // is rounded down) and lies between the end
        // of the statics and below the stack pointer, memory that holds no
        // live object: the stack grows down, nothing lives below the stack
        // pointer (no interrupt is enabled to push a frame there), and no
        // Rust object is allocated in this range. Word writes only.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// The peak stack use since the last [`paint`], in bytes from the top of
/// RAM; [`room`] if the stack reached the bottom of the window (then it
/// may have gone further).
#[inline(never)]
pub fn peak() -> usize {
    let (top, bottom) = bounds();
    let mut p = bottom;
    // The scan stops at the first word that is not the paint: every word
    // read before it is below that mark, so below the lowest the stack has
    // reached, where no live object is. The last word read may belong to a
    // live frame, which a volatile word read does not disturb.
    //
    // SAFETY: word-aligned reads inside RAM, between the end of the
    // statics and the top of RAM, as for `paint`.
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    top - p
}
