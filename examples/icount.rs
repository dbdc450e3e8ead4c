//! Instruction counts per frame on Cortex-M, under QEMU with
//! `-icount shift=0`: benchmark firmware for the emulated TI LM3S6965EVB
//! (Cortex-M3, `thumbv7m-none-eabi`) and Arm MPS2-AN386 (Cortex-M4F,
//! `thumbv7em-none-eabihf`; and `thumbv6m-none-eabi`, whose ARMv6-M code
//! the M4F runs unchanged: a Cortex-M0+'s instruction stream, built with
//! `--cfg microraster_board="mps2-an386"` for that board's memory map, see
//! build.rs).
//!
//! ```text
//! scripts/icount.sh                # the three boards, every scene, twice
//! cargo run --release --example icount --target thumbv7m-none-eabi -- -icount shift=0
//! cargo run --release --example icount --target thumbv7em-none-eabihf -- -icount shift=0
//! ```
//!
//! (The cargo runners pass what follows `--` to QEMU; without
//! `-icount shift=0` the calibration fails and says so.) The scenes are
//! those of `examples/icount_scenes/mod.rs`, rendered at 320x240 into a
//! `NullSink`. Built with `MICRORASTER_ICOUNT_SCENES="fill grid4"` (names
//! separated by spaces or commas) in the environment, only those scenes
//! are built in and run: without the variable, every scene, which is more
//! than the LM3S6965's flash holds (`scripts/icount.sh` builds it in
//! parts).
//!
//! # What is counted, and how
//!
//! With `-icount shift=0`, QEMU's virtual clock advances exactly 1 ns per
//! executed instruction, and the SysTick timer counts that clock: on the
//! LM3S6965EVB from the system clock, whose period QEMU sets to
//! 5 ns x (RCC.SYSDIV + 1) (`hw/arm/stellaris.c`), 80 ns after reset
//! (RCC = 0x078E3AC0, SYSDIV = 15); on the MPS2 from its fixed 25 MHz
//! SYSCLK (`hw/arm/mps2.c`), 40 ns. One tick is thus 80 or 40 instructions.
//! QEMU is not cycle-accurate: these are *instructions*, never cycles.
//!
//! A plain timer read is only good to one tick. [`timer::stamp`] resolves
//! the instruction exactly, vernier fashion, in a fixed assembly sequence:
//! it spins (4 instructions a turn) until the counter changes, which places
//! that edge within 4 instructions, waits `PERIOD - 8` instructions, and
//! reads the counter 5 times in a row, one instruction apart, across the
//! next edge: where the value changes gives the edge's instruction, and the
//! counter's value gives the edge's time. What the stamp itself executes
//! (the spin included) is known or constant, and is taken out: the firmware
//! first measures straight runs of N `nop`s between two stamps, from many
//! starting phases, and checks that they count as exactly N (and a
//! 1,000,002-instruction loop as exactly that), or it stops with an error.
//!
//! Each frame is measured twice: once plain (`Renderer::render`), all-in
//! from before the scene's set-up to after the render returns; once through
//! `render_profiled` with a profiler that stamps every stage entry, which
//! splits the frame into set-up, vertex stage, binning, rasterization and
//! shading, and the sink. Both are repeated, and must repeat exactly.
//!
//! It also prints each scene's peak stack, measured by painting the free
//! RAM before the scene and finding how far down its frames wrote
//! (`examples/stack_gauge/mod.rs`); the painting is outside the counts.
//!
//! On a host build this file is only a stub that says how to run it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "icount is firmware for QEMU: scripts/icount.sh, or cargo run --release --example icount --target thumbv7m-none-eabi (or thumbv7em-none-eabihf)"
    );
}

// A thumbv6m build is for the MPS2-AN386 only, which must be asked for: by
// default build.rs links thumbv6m for the RP2040 (and Cargo.toml brings its
// HAL in). thumbv6m is the one bare-metal Arm target here without 32-bit
// compare-and-swap, which is how stable Rust's `cfg` can tell it.
#[cfg(all(
    target_os = "none",
    not(target_has_atomic = "32"),
    not(microraster_board = "mps2-an386")
))]
compile_error!(
    "icount for thumbv6m-none-eabi runs on QEMU's mps2-an386 only: build it with \
     --cfg microraster_board=\"mps2-an386\" in the target's rustflags, as \
     scripts/icount.sh does for its board mps2-an386-v6m"
);

#[cfg(target_os = "none")]
mod icount_scenes;
#[cfg(target_os = "none")]
mod stack_gauge;

/// Exact instruction stamps from SysTick under `-icount shift=0`.
#[cfg(target_os = "none")]
mod timer {
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
}

#[cfg(target_os = "none")]
mod firmware {
    use crate::icount_scenes::{
        frame, renderer, BenchWorkspace, FrameError, Meshes, SceneId, HEIGHT, WIDTH,
    };
    use crate::stack_gauge;
    use crate::timer::{self, Stamps, END, PERIOD, START};
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use microraster::{FrameStats, Profiler, Stage};
    use panic_semihosting as _;
    use static_cell::ConstStaticCell;

    // About 41 KB, built in place and never moved through the stack; the
    // 4 KB renderer lives on the stack of `measure`.
    static WORKSPACE: ConstStaticCell<BenchWorkspace> = ConstStaticCell::new(BenchWorkspace::new());
    static TEXELS: ConstStaticCell<[u16; 32 * 32]> = ConstStaticCell::new([0; 32 * 32]);

    /// The board this build is for.
    #[cfg(target_abi = "eabihf")]
    const BOARD: (&str, &str, u32) = ("mps2-an386", "Cortex-M4F", 0xC24);
    /// ARMv6-M code on the MPS2's M4F: what a Cortex-M0+ would execute.
    #[cfg(all(not(target_abi = "eabihf"), microraster_board = "mps2-an386"))]
    const BOARD: (&str, &str, u32) = ("mps2-an386", "ARMv6-M code on a Cortex-M4F", 0xC24);
    #[cfg(not(any(target_abi = "eabihf", microraster_board = "mps2-an386")))]
    const BOARD: (&str, &str, u32) = ("lm3s6965evb", "Cortex-M3", 0xC23);

    const NOT_COUNTING: &str = "SysTick does not count";

    /// Why the benchmark stopped.
    enum Error {
        Setup(&'static str),
        Calibration {
            what: &'static str,
            expected: u32,
            measured: u32,
        },
        Scene(&'static str),
        Mesh(microraster::mesh::MeshError),
        Frame(&'static str, FrameError),
        Unrepeatable(&'static str),
    }

    impl core::fmt::Display for Error {
        fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
            match self {
                Self::Setup(s) => write!(f, "{s}"),
                Self::Calibration {
                    what,
                    expected,
                    measured,
                } => write!(
                    f,
                    "calibration failed: {what}: expected {expected} instructions, measured \
                     {measured} (is QEMU running with -icount shift=0?)"
                ),
                Self::Scene(s) => write!(f, "unknown scene {s:?} in MICRORASTER_ICOUNT_SCENES"),
                Self::Mesh(e) => write!(f, "a scene mesh is invalid: {e}"),
                Self::Frame(s, e) => write!(f, "scene {s}: {e}"),
                Self::Unrepeatable(s) => {
                    write!(f, "scene {s}: two identical frames counted differently")
                }
            }
        }
    }

    /// A number with thousands separators.
    struct Sep(u64);

    impl core::fmt::Display for Sep {
        fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
            let mut groups = [0u16; 7];
            let (mut v, mut n) = (self.0, 0);
            loop {
                groups[n] = (v % 1000) as u16;
                n += 1;
                v /= 1000;
                if v == 0 {
                    break;
                }
            }
            write!(f, "{}", groups[n - 1])?;
            for g in groups[..n - 1].iter().rev() {
                write!(f, ",{g:03}")?;
            }
            Ok(())
        }
    }

    /// `num / den` with `decimals` decimals, rounded.
    struct Ratio(u64, u64, u32);

    impl core::fmt::Display for Ratio {
        fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
            let Ratio(num, den, decimals) = *self;
            if den == 0 {
                return write!(f, "-");
            }
            let scale = 10u64.pow(decimals);
            let v = (num * scale + den / 2) / den;
            if decimals == 0 {
                write!(f, "{}", Sep(v))
            } else {
                write!(
                    f,
                    "{}.{:0w$}",
                    Sep(v / scale),
                    v % scale,
                    w = decimals as usize
                )
            }
        }
    }

    /// The profiler: a stamp at every stage entry.
    struct Hooks<'a>(&'a mut Stamps);

    impl Profiler for Hooks<'_> {
        #[inline(always)]
        fn enter(&mut self, stage: Stage) {
            timer::stamp(self.0, stage as u32);
        }
    }

    /// A calibration measurement: two stamps around known instructions.
    type Measurement = fn(&mut Stamps) -> u32;

    /// The stamp overhead, and the calibration's proof that stamps count
    /// exactly.
    fn calibrate(s: &mut Stamps, syst: &mut SYST) -> Result<u32, Error> {
        /// Measures `f` from `PERIOD` starting phases, that is with the
        /// first stamp starting at every distance from a SysTick edge
        /// (checked): every measurement must agree.
        fn phases(
            s: &mut Stamps,
            syst: &mut SYST,
            what: &'static str,
            f: Measurement,
        ) -> Result<u32, Error> {
            let mut first = None;
            let (mut kmask, mut seen) = (0, [0u32; 4]);
            for q in 0..PERIOD {
                if !timer::restart(syst) {
                    return Err(Error::Setup(NOT_COUNTING));
                }
                timer::shift(q);
                let m = f(s);
                if !s.sane() {
                    return Err(Error::Setup(
                        "a stamp did not find the SysTick edge where it must be (is QEMU \
                         running with -icount shift=0? is the tick period right?)",
                    ));
                }
                kmask |= s.kmask;
                let p = s.phase[0].min(127);
                seen[(p / 32) as usize] |= 1 << (p % 32);
                match first {
                    None => first = Some(m),
                    Some(m0) if m0 != m => {
                        return Err(Error::Calibration {
                            what,
                            expected: m0,
                            measured: m,
                        })
                    }
                    _ => {}
                }
            }
            let distinct: u32 = seen.iter().map(|w| w.count_ones()).sum();
            if kmask != 0b1_1110 || distinct != PERIOD {
                return Err(Error::Setup(
                    "the calibration did not meet every phase of the SysTick edge",
                ));
            }
            Ok(first.unwrap_or_default())
        }

        let overhead = phases(s, syst, "0 nops", timer::around_nops::<0>)?;
        let runs: [(u32, &'static str, Measurement); 9] = [
            (1, "1 nop", timer::around_nops::<1>),
            (2, "2 nops", timer::around_nops::<2>),
            (3, "3 nops", timer::around_nops::<3>),
            (4, "4 nops", timer::around_nops::<4>),
            (7, "7 nops", timer::around_nops::<7>),
            (41, "41 nops", timer::around_nops::<41>),
            (83, "83 nops", timer::around_nops::<83>),
            (256, "256 nops", timer::around_nops::<256>),
            (timer::LOOP_INSTRUCTIONS, "the loop", timer::around_loop),
        ];
        for (n, what, f) in runs {
            let m = phases(s, syst, what, f)?.wrapping_sub(overhead);
            if m != n {
                return Err(Error::Calibration {
                    what,
                    expected: n,
                    measured: m,
                });
            }
        }
        Ok(overhead)
    }

    /// One measured frame.
    #[derive(Clone, Copy, PartialEq, Eq)]
    struct Measured {
        /// Plain `render`, all-in.
        total: u32,
        /// With stage stamps: set-up (scene, matrices, checks, and the
        /// return after the last stage), vertex, binning, raster, sink.
        stages: [u32; 5],
        stats: FrameStats,
    }

    fn measure(
        scene: SceneId,
        meshes: &Meshes,
        ws: &mut BenchWorkspace,
        s: &mut Stamps,
        syst: &mut SYST,
        overhead: u32,
    ) -> Result<Measured, Error> {
        let mut r = renderer();
        let fail = |e| Error::Frame(scene.name(), e);
        let too_long = Error::Setup("a frame is longer than SysTick's 24 bits of ticks");

        // All-in, without stage stamps.
        if !timer::restart(syst) {
            return Err(Error::Setup(NOT_COUNTING));
        }
        s.reset();
        timer::stamp(s, START);
        let plain = frame(scene, meshes, &mut r, ws, &mut ());
        timer::stamp(s, END);
        let stats = plain.map_err(fail)?;
        if timer::wrapped(syst) {
            return Err(too_long);
        }
        let total = s.charge[START as usize].wrapping_sub(overhead);
        if !s.sane() {
            return Err(Error::Setup("a stamp lost the SysTick edge"));
        }

        // The stages.
        if !timer::restart(syst) {
            return Err(Error::Setup(NOT_COUNTING));
        }
        s.reset();
        timer::stamp(s, START);
        let profiled = frame(scene, meshes, &mut r, ws, &mut Hooks(s));
        timer::stamp(s, END);
        let stats2 = profiled.map_err(fail)?;
        if timer::wrapped(syst) {
            return Err(too_long);
        }
        if !s.sane() {
            return Err(Error::Setup("a stamp lost the SysTick edge"));
        }
        if stats2 != stats {
            return Err(Error::Unrepeatable(scene.name()));
        }
        let net = |tag: u32| {
            let t = tag as usize;
            s.charge[t].wrapping_sub(s.calls[t].wrapping_mul(overhead))
        };
        let stages = [
            net(START) + net(Stage::Done as u32),
            net(Stage::Vertex as u32),
            net(Stage::Binning as u32),
            net(Stage::Raster as u32),
            net(Stage::Sink as u32),
        ];
        Ok(Measured {
            total,
            stages,
            stats,
        })
    }

    fn run() -> Result<(), Error> {
        let mut cp =
            cortex_m::Peripherals::take().ok_or(Error::Setup("the core peripherals are taken"))?;
        let (board, core, part) = BOARD;
        let cpuid = cp.CPUID.base.read();
        if (cpuid >> 4) & 0xFFF != part {
            return Err(Error::Setup(
                "this build is for the other board (CPUID part number differs)",
            ));
        }
        hprintln!(
            "icount: {} ({} r{}p{}), {}x{} Rgb565, 32x32 tiles, NullSink",
            board,
            core,
            (cpuid >> 20) & 0xF,
            cpuid & 0xF,
            WIDTH,
            HEIGHT
        );

        let syst = &mut cp.SYST;
        timer::start(syst);
        let mut stamps = Stamps::new();
        let s = &mut stamps;
        let overhead = calibrate(s, syst)?;
        hprintln!(
            "calibration: SysTick tick = {} instructions; a stamp costs {} (taken out); \
             runs of 0, 1, 2, 3, 4, 7, 41, 83, 256 nops and a {}-instruction loop, each \
             from {} starting phases, counted exactly",
            PERIOD,
            overhead,
            Sep(timer::LOOP_INSTRUCTIONS as u64),
            PERIOD
        );

        // The scenes named at build time, or all of them.
        let mut scenes = SceneId::ALL.map(Some);
        let list = crate::icount_scenes::SCENE_LIST;
        let mut names = list.split([' ', ',']).filter(|n| !n.is_empty()).peekable();
        if names.peek().is_some() {
            scenes = [None; SceneId::ALL.len()];
            for (slot, name) in scenes.iter_mut().zip(names) {
                *slot = Some(SceneId::from_name(name).ok_or(Error::Scene(name))?);
            }
        }

        // The shader scenes' texture, in RAM (2 KiB), only when one of them
        // is built in.
        let texels: Option<&'static [u16]> = if crate::icount_scenes::SHADER_SCENES {
            let t = TEXELS.take();
            crate::icount_scenes::checker_texels(t);
            Some(t)
        } else {
            None
        };
        let meshes = Meshes::new(texels).map_err(Error::Mesh)?;
        let ws = WORKSPACE.take();
        // The stack since boot (calibration, printing); then each scene's
        // own, painted afresh below this frame before it.
        let boot_stack = stack_gauge::peak();
        let mut results = [None; SceneId::ALL.len()];
        for (slot, scene) in results.iter_mut().zip(scenes.into_iter().flatten()) {
            stack_gauge::paint();
            let a = measure(scene, &meshes, ws, s, syst, overhead)?;
            let b = measure(scene, &meshes, ws, s, syst, overhead)?;
            if a != b {
                return Err(Error::Unrepeatable(scene.name()));
            }
            *slot = Some((scene, a, stack_gauge::peak()));
        }
        let results = results.iter().flatten();

        hprintln!();
        hprintln!("| scene | instructions per frame | pixels shaded | per pixel | triangles | per triangle |");
        hprintln!("|---|---:|---:|---:|---:|---:|");
        for (scene, m, _) in results.clone() {
            let (px, tris) = (m.stats.pixels_shaded as u64, m.stats.triangles_in as u64);
            hprintln!(
                "| `{}` | {} | {} | {} | {} | {} |",
                scene.name(),
                Sep(m.total as u64),
                Sep(px),
                Ratio(m.total as u64, px, 2),
                Sep(tris),
                Ratio(m.total as u64, tris, 0)
            );
        }
        hprintln!();
        hprintln!(
            "| scene | set-up | vertex | binning | raster + shade | sink | sum (profiled build) | minus plain |"
        );
        hprintln!("|---|---:|---:|---:|---:|---:|---:|---:|");
        for (scene, m, _) in results.clone() {
            let sum = m.stages.iter().fold(0u32, |a, &b| a.wrapping_add(b));
            hprintln!(
                "| `{}` | {} | {} | {} | {} | {} | {} | {} |",
                scene.name(),
                Sep(m.stages[0] as u64),
                Sep(m.stages[1] as u64),
                Sep(m.stages[2] as u64),
                Sep(m.stages[3] as u64),
                Sep(m.stages[4] as u64),
                Sep(sum as u64),
                sum as i64 - m.total as i64
            );
        }
        hprintln!();
        // Painted RAM that a scene's frames wrote: from the top of RAM, so
        // `main`, `run` and the renderer on `measure`'s stack included.
        hprintln!("| scene | peak stack |");
        hprintln!("|---|---:|");
        let mut deepest = ("start-up and calibration", boot_stack);
        for &(scene, _, peak) in results.clone() {
            hprintln!("| `{}` | {} B |", scene.name(), Sep(peak as u64));
            if peak > deepest.1 {
                deepest = (scene.name(), peak);
            }
        }
        hprintln!(
            "peak stack: {} B ({}); start-up and calibration {} B; {} B painted below the top of RAM",
            Sep(deepest.1 as u64),
            deepest.0,
            Sep(boot_stack as u64),
            Sep(stack_gauge::room() as u64)
        );
        hprintln!();
        for (scene, m, _) in results {
            let st = &m.stats;
            hprintln!(
                "{}: {} triangles in, {} culled, {} rejected, {} clipped, {} drawn; {} tiles, {} bin passes, {} rescanned",
                scene.name(),
                st.triangles_in,
                st.culled,
                st.rejected,
                st.clipped,
                st.drawn,
                st.tiles,
                st.bin_passes,
                st.rescanned_tiles
            );
        }
        hprintln!(
            "every frame was measured twice, plain and profiled; both runs agree to the instruction"
        );
        Ok(())
    }

    #[entry]
    fn main() -> ! {
        // All the free RAM under `main`: `run` reads how deep start-up and
        // calibration went, then repaints for each scene.
        crate::stack_gauge::paint();
        match run() {
            Ok(()) => {
                hprintln!("icount: done");
                debug::exit(debug::EXIT_SUCCESS);
            }
            Err(e) => {
                hprintln!("icount: error: {}", e);
                debug::exit(debug::EXIT_FAILURE);
            }
        }
        loop {
            cortex_m::asm::wfi();
        }
    }
}
