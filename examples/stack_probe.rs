//! The peak stack of the Pico 2 (RP2350) and ESP32-C3 firmwares, measured
//! on QEMU machines with their instruction sets, since no emulator runs
//! those chips: `mps2-an505` (Cortex-M33, `thumbv8m.main-none-eabihf`, the
//! RP2350's core) and RISC-V `virt` (`riscv32imc-unknown-none-elf`, the
//! ESP32-C3's).
//!
//! ```text
//! cargo test --test qemu_stack -- --nocapture    # builds, runs and checks both
//! ```
//!
//! The probe runs the boards' own frame code, `st7789_scene::Frames` (the
//! same scene, configuration, 32x32 `Rgb565Be` tiles and
//! `Renderer::render_double_buffered` call, built for the same target),
//! with a `TileTransfer` that does what the boards' panels do with a tile
//! short of the SPI and DMA driver calls, and checksums the bytes instead
//! (`stack_probe_firmware/panel.rs`). It paints the stack first thing
//! (`examples/stack_gauge`), sets the scene up as the boards do, reports
//! the start-up's peak, paints again and draws the frames of
//! `FRAME_TIMES`, printing each one's checksum (the test compares them
//! with the host's), its count of instructions (each frame drawn again
//! with its tiles packed but not checksummed, between two readings of
//! RISC-V's `minstret` or the Cortex-M33's SysTick, which count
//! instructions under QEMU's `-icount shift=0`), and the frames' peak
//! stack, split at the call of
//! `Frames::draw`: above it, the probe's `main` and runtime; below it, the
//! boards' code. What the boards add is their own `main`'s frame and their
//! SPI/DMA drivers' frames under `TileTransfer::start` and `wait`, which
//! the figures leave out (BENCHMARKS.md, Footprint).
//!
//! On a host build this file is only a stub that says how to run it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "stack_probe is firmware for QEMU's mps2-an505 (thumbv8m.main-none-eabihf) and RISC-V \
         virt (riscv32imc-unknown-none-elf) machines: cargo test --test qemu_stack -- --nocapture"
    );
}

#[cfg(target_os = "none")]
#[path = "st7789_scene/mod.rs"]
mod st7789_scene;

#[cfg(target_os = "none")]
mod stack_gauge;

#[cfg(target_os = "none")]
#[path = "stack_probe_firmware/mod.rs"]
mod firmware;

#[cfg(all(target_os = "none", target_arch = "arm"))]
#[path = "stack_probe_firmware/arm.rs"]
mod rt;

#[cfg(all(target_os = "none", target_arch = "riscv32"))]
#[path = "stack_probe_firmware/riscv.rs"]
mod rt;
