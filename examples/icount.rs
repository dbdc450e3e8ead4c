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
//! sink that discards each tile (and, once more after the counts, hashes
//! it: the host build prints the same scenes' hashes, which
//! `scripts/icount.sh` compares). Built with `MICRORASTER_ICOUNT_SCENES="fill grid4"` (names
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
//! A plain timer read is only good to one tick.
//! [`timer::stamp`](icount_firmware::timer::stamp) resolves the
//! instruction exactly, vernier fashion, in a fixed assembly sequence:
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
//! The firmware is in `examples/icount_firmware/` (the stamps in its
//! `timer.rs`); on a host build this file is only a stub that says how to
//! run it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

/// On the host: the image hash of every scene built in, as the firmware
/// prints it after its counts (`image: <scene> <hash>`), for
/// `scripts/icount.sh` to compare with each board's.
#[cfg(not(target_os = "none"))]
fn main() {
    use icount_scenes::{frame, renderer, BenchWorkspace, FrameSink, Meshes, SceneId};
    eprintln!(
        "icount is firmware for QEMU: scripts/icount.sh, or cargo run --release --example icount --target thumbv7m-none-eabi (or thumbv7em-none-eabihf); on the host it prints the scenes' image hashes"
    );
    let texels: &'static mut [u16; 32 * 32] = Box::leak(Box::new([0; 32 * 32]));
    icount_scenes::checker_texels(texels);
    let meshes = Meshes::new(Some(texels)).expect("the benchmark meshes are valid");
    let mut ws: Box<BenchWorkspace> = Box::default();
    for scene in SceneId::ALL.into_iter().filter(|s| s.built()) {
        let mut sink = FrameSink::hashing();
        frame(scene, &meshes, &mut renderer(), &mut ws, &mut (), &mut sink)
            .unwrap_or_else(|e| panic!("{}: {e}", scene.name()));
        println!("image: {} {}", scene.name(), sink.hash.unwrap_or(0));
    }
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
mod icount_firmware;
mod icount_scenes;
#[cfg(target_os = "none")]
mod stack_gauge;
// The LM3S6965's own interrupt table (cortex-m-rt's `device` feature).
#[cfg(microraster_lm3s6965)]
mod lm3s6965_vectors;
