//! Exact instruction stamps from SysTick under `-icount shift=0`.

use core::arch::asm;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;

/// SysTick's current value register (SYST_CVR).
const SYST_CVR: u32 = 0xE000_E018;
/// The reload value: the full 24 bits.
pub const RELOAD: u32 = 0x00FF_FFFF;

/// Instructions per SysTick tick on the MPS2-AN386: SYSCLK is 25 MHz.
#[cfg(any(target_abi = "eabihf", microraster_board = "mps2-an386"))]
pub const PERIOD: u32 = 40;
/// Instructions per SysTick tick on the LM3S6965EVB: the system clock
/// after reset, 200 MHz / 16.
#[cfg(not(any(target_abi = "eabihf", microraster_board = "mps2-an386")))]
pub const PERIOD: u32 = 80;

/// Stamp tags: the renderer's stages (`Stage as u32`), then ours.
pub const START: u32 = 5;
/// The stamp after the frame.
pub const END: u32 = 6;
/// The tag before the first stamp.
const NONE: u32 = 7;

/// Instructions charged to each tag: from the end of a stamp with that
/// tag to the start of the next stamp.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stamps {
    /// Instructions per tag, stamp overhead included.
    pub charge: [u32; 8],
    /// Intervals per tag.
    pub calls: [u32; 8],
    /// The end of the last stamp (relative instruction time).
    end: u32,
    /// The last stamp's tag.
    tag: u32,
    /// Bit `k` is set when a stamp saw the edge at burst read `k`; only
    /// bits 1 to 4 may be set.
    pub kmask: u32,
    /// Stamps since the reset.
    count: u32,
    /// Where the last stamps found the edge, relative to their start
    /// (`4n + k`, in `7..=PERIOD + 6`), by the parity of their number
    /// since the reset: `phase[0]` is the first of a pair.
    pub phase: [u32; 2],
}

impl Stamps {
    /// Nothing charged yet.
    pub const fn new() -> Self {
        Self {
            charge: [0; 8],
            calls: [0; 8],
            end: 0,
            tag: NONE,
            kmask: 0,
            count: 0,
            phase: [0; 2],
        }
    }

    /// Forgets every charge.
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// Whether every stamp found its edge where the method assumes.
    pub fn sane(&self) -> bool {
        self.kmask & !0b1_1110 == 0
    }
}

/// Starts SysTick from the core clock, counting down over all 24 bits,
/// without its interrupt (a handler would be counted too).
pub fn start(syst: &mut SYST) {
    syst.disable_interrupt();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_counter();
}

/// Restarts the count from the reload value, so that a measurement of
/// up to `PERIOD * 2^24` instructions does not see it wrap, and clears
/// the wrap flag. `false` if SysTick does not count.
#[must_use]
pub fn restart(syst: &mut SYST) -> bool {
    syst.clear_current();
    // Let the reload happen and a few ticks pass: the first edges after
    // a write are not the steady count down that stamps rely on.
    for _ in 0..100_000 {
        let v = SYST::get_current();
        if v != 0 && v < RELOAD - 2 {
            let _ = syst.has_wrapped();
            return true;
        }
    }
    false
}

/// Whether the counter wrapped since the last `restart` (or call).
pub fn wrapped(syst: &mut SYST) -> bool {
    syst.has_wrapped()
}

/// The stamp's timer reads (see [`stamp`]): the spin loop's turns `n`,
/// the burst read `k` that saw the edge (plus 8 if none did) and the
/// counter's value `v2` after it. ARMv6-M code (loads only into r0-r7,
/// no `it` blocks, so `k` is computed without branches), which the
/// ARMv7-M cores run as well: one sequence for every board.
#[inline(always)]
fn vernier() -> (u32, u32, u32) {
    let (n, k, v2): (u32, u32, u32);
    // SAFETY: the sequence only reads SysTick's current-value register,
    // a read-only memory-mapped register that no Rust object aliases
    // and whose reads have no side effects, and clobbers only the
    // registers it declares. It has to be assembly: the method depends
    // on the exact distance, in instructions, between the reads.
    //
    // r0: SYST_CVR, then k. Instruction 0 reads v0; the loop (reads at
    // instructions 2 + 4m) stops at the first value v1 != v0, read at
    // 4n - 2 with n turns, so that edge fell in (4n - 6, 4n - 2] and
    // the next one, PERIOD later, in (4n - 6 + P, 4n - 2 + P]. After
    // PERIOD - 8 instructions (two `mov`s that keep n and v1 out of the
    // burst's five low registers, then nops) the burst reads at
    // 4n - 6 + P + i, i = 0..=4: the first one that sees v2 = v1 - 1 is
    // that edge, so k = (reads still at v1) is in 1..=4, and 8 is added
    // if the last read has not changed (which must never happen). Each
    // read is v1 or v1 - 1, so with d_i = v1 - read_i (0 or 1),
    // k = 12 - (d_0 + d_1 + d_2 + d_3) - 8 d_4. Outputs only in low
    // registers (Thumb-1 allows high ones as clobbers only): n comes
    // back to r1.
    unsafe {
        asm!(
            "ldr r1, [r0]",
            "movs r2, #0",
            "2:",
            "ldr r3, [r0]",
            "adds r2, r2, #1",
            "cmp r3, r1",
            "beq 2b",
            "mov r8, r2",
            "mov r9, r3",
            ".rept {delay}",
            "nop",
            ".endr",
            "ldr r1, [r0]",
            "ldr r2, [r0]",
            "ldr r3, [r0]",
            "ldr r4, [r0]",
            "ldr r5, [r0]",
            "mov r0, r9",
            "subs r1, r0, r1",
            "subs r2, r0, r2",
            "adds r1, r1, r2",
            "subs r2, r0, r3",
            "adds r1, r1, r2",
            "subs r2, r0, r4",
            "adds r1, r1, r2",
            "subs r0, r0, r5",
            "lsls r0, r0, #3",
            "adds r0, r0, r1",
            "movs r1, #12",
            "subs r0, r1, r0",
            "mov r1, r8",
            delay = const PERIOD - 10,
            inout("r0") SYST_CVR => k,
            out("r1") n,
            out("r2") _,
            out("r3") _,
            out("r4") _,
            out("r5") v2,
            out("r8") _,
            out("r9") _,
            options(nostack),
        );
    }
    (n, k, v2)
}

/// Charges the instructions since the last stamp to the last stamp's
/// tag and starts charging `tag`. Every call executes the same
/// instructions, except the spin loop, whose 4 instructions a turn are
/// left out; the constant rest is measured by the firmware's
/// calibration and taken out by the caller.
#[inline(never)]
pub extern "C" fn stamp(s: &mut Stamps, tag: u32) {
    let (n, k, v2) = vernier();
    // The edge to v2 came PERIOD * (RELOAD - v2) after the reload; this
    // stamp's end is a constant after it, less k, and its start (the
    // first read) 4n before that. Straight-line code: every call runs
    // the same instructions.
    let end = PERIOD
        .wrapping_mul(RELOAD.wrapping_sub(v2))
        .wrapping_sub(k & 7);
    let start = end.wrapping_sub(n.wrapping_mul(4));
    let slot = (s.tag & 7) as usize;
    s.charge[slot] = s.charge[slot].wrapping_add(start.wrapping_sub(s.end));
    s.calls[slot] = s.calls[slot].wrapping_add(1);
    s.end = end;
    s.tag = tag;
    s.kmask |= 1u32.wrapping_shl(k);
    s.phase[(s.count & 1) as usize] = n.wrapping_mul(4).wrapping_add(k);
    s.count = s.count.wrapping_add(1);
}

/// Shifts the phase of what follows by `q` instructions, for `q` below
/// 128: the assembly executes exactly `q + 3`, a jump into a run of 128
/// `nop`s, `q` from its end; the call around it, a constant more.
/// ARMv6-M code, as every sequence here. Never inlined: LLVM counts a
/// `.rept` as one instruction when it places a function's literal pool,
/// which ARMv6-M's loads reach only 1,020 bytes ahead, so 128 `nop`s
/// inlined into the calibration loop would push its pool out of reach.
#[inline(never)]
pub fn shift(q: u32) {
    // `mov r0, pc` reads its own address + 4, the address of the first
    // nop less 2 (the three instructions are 2 bytes each); bit 0 set:
    // `bx` needs a Thumb address.
    let offset = (2 + 2 * (128 - q.min(128))) | 1;
    // SAFETY: the jump lands inside the run of nops, which follows the
    // `bx` directly, on a Thumb address; nothing but nops runs there,
    // then execution falls through. Assembly, because the count of
    // instructions is the point. `mov` and `add` without `s` keep the
    // flags.
    unsafe {
        asm!(
            "mov r0, pc",
            "add r0, {o}",
            "bx r0",
            ".rept 128",
            "nop",
            ".endr",
            o = in(reg) offset,
            out("r0") _,
            options(nomem, nostack, preserves_flags),
        );
    }
}

/// Two stamps around exactly `N` `nop`s: returns what is charged.
#[inline(never)]
pub fn around_nops<const N: usize>(s: &mut Stamps) -> u32 {
    s.reset();
    stamp(s, START);
    // SAFETY: only nops: the instructions measured, which must be
    // exactly these.
    unsafe {
        asm!(
            ".rept {n}",
            "nop",
            ".endr",
            n = const N,
            options(nomem, nostack, preserves_flags),
        );
    }
    stamp(s, END);
    s.charge[START as usize]
}

/// Iterations of the long calibration loop: what `movs` (8 bits) and a
/// shift make in two instructions, the ARMv6-M way (no `movw`).
pub const LOOP_TURNS: u32 = 0x7A << 12;
/// Instructions the long calibration loop executes: `movs`, `lsls`,
/// then `subs` and `bne` per turn.
pub const LOOP_INSTRUCTIONS: u32 = 2 + 2 * LOOP_TURNS;

/// Two stamps around a loop of [`LOOP_INSTRUCTIONS`] instructions.
#[inline(never)]
pub fn around_loop(s: &mut Stamps) -> u32 {
    s.reset();
    stamp(s, START);
    // SAFETY: a counted loop on a scratch register, nothing else (r0:
    // ARMv6-M's `movs` and `lsls` take only low registers).
    unsafe {
        asm!(
            "movs r0, #{hi}",
            "lsls r0, r0, #12",
            "2:",
            "subs r0, r0, #1",
            "bne 2b",
            hi = const LOOP_TURNS >> 12,
            out("r0") _,
            options(nomem, nostack),
        );
    }
    stamp(s, END);
    s.charge[START as usize]
}
