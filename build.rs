//! Puts the right board's memory map where cortex-m-rt's `link.x` finds it,
//! for the firmware examples. `link.x` says `INCLUDE memory.x`; the board's
//! map is copied to `$OUT_DIR/memory.x`, which is put on the linker's search
//! path of this package's examples only, according to the target:
//!
//! | target                  | board                        | map                   |
//! |-------------------------|------------------------------|-----------------------|
//! | `thumbv7m-none-eabi`    | TI LM3S6965EVB (reference)   | `memory.x` (root)     |
//! | `thumbv6m-none-eabi`    | Raspberry Pi Pico (RP2040)   | `memory/rp2040.x`     |
//! | `thumbv7em-none-eabihf` | Arm MPS2-AN386 (Cortex-M4F)  | `memory/mps2-an386.x` |
//! | `thumbv8m.main-none-eabihf` | Arm MPS2-AN505 (Cortex-M33, the stack probe) | `memory/mps2-an505.x` |
//!
//! The RISC-V stack probe (`examples/stack_probe.rs` for QEMU's `virt`
//! machine, `riscv32imc-unknown-none-elf`) links with a whole script of its
//! own, `memory/qemu-riscv32-virt.x`, given by absolute path.
//!
//! A thumbv6m build may instead be for QEMU's MPS2-AN386, which runs the
//! ARMv6-M instruction stream unchanged (the instruction counts of a
//! Cortex-M0+, `scripts/icount.sh`): built with
//! `--cfg microraster_board="mps2-an386"` in its rustflags, it gets that
//! board's map. A cfg rather than an environment variable, because the same
//! switch must also keep the RP2040's HAL out of the build (`Cargo.toml`
//! selects those dependencies on it; cargo sees rustflags' cfgs, never the
//! environment), and one switch cannot disagree with itself. The build script
//! reads it as `CARGO_CFG_MICRORASTER_BOARD`.
//!
//! lld looks for an `INCLUDE`d file in its working directory (the package
//! root) before its search path, so the root `memory.x` would win for every
//! target. `.cargo/config.toml` therefore links the other two boards through
//! `scripts/lld-in-out-dir.sh`, which runs lld from `memory/`. Host, RISC-V
//! and library-only builds ignore all of this.
//!
//! `cargo:rustc-link-arg-examples=-L...`, not `cargo:rustc-link-search`: a
//! search path reaches the link of every firmware that depends on
//! microraster, where the LM3S6965's map would be found before a board
//! crate's own `memory.x` later in the search order, and the firmware
//! would silently link for the wrong chip (tests/dependent_memory_map.rs).
//!
//! For the library itself it sets `--cfg microraster_narrow_multiply` on
//! ARM cores without a 32x32 to 64-bit multiply (ARMv6-M, ARMv8-M
//! Baseline: `thumbv6m`, `thumbv8m.base`), where the span loops take their
//! varyings in 32-bit arithmetic. Stable Rust sets no `target_feature` cfg
//! for ARM (`thumb2` among them), so the target's name decides.
//!
//! With the `assets` feature it also converts `examples/assets/rocket.obj`
//! (and its materials) into `$OUT_DIR/rocket.rs`, `static` arrays that the
//! OLED firmware and its end-to-end test `include!`: the model goes from
//! the OBJ file to flash at build time, through the workspace's importer.

use std::{env, fs, path::PathBuf};

/// The memory map for a target triple, if it is one of the boards, or for
/// the board named by the `microraster_board` cfg (`board`). Only targets
/// that `.cargo/config.toml` links from `memory/` can take the MPS2's map
/// (for thumbv7m, lld would find the root `memory.x` first).
fn board_map(target: &str, board: Option<&str>) -> Option<&'static str> {
    let arch = target.split('-').next().unwrap_or_default();
    match (arch, board) {
        ("thumbv6m" | "thumbv7em", Some("mps2-an386")) => Some("memory/mps2-an386.x"),
        (_, Some(other)) => panic!(
            "--cfg microraster_board=\"{other}\" is not a board for {target} \
             (the one board to pick is \"mps2-an386\", for thumbv6m or thumbv7em)"
        ),
        ("thumbv7m", None) => Some("memory.x"),
        ("thumbv6m", None) => Some("memory/rp2040.x"),
        ("thumbv7em", None) => Some("memory/mps2-an386.x"),
        ("thumbv8m.main", None) => Some("memory/mps2-an505.x"),
        _ => None,
    }
}

/// `examples/assets/rocket.obj` to `$OUT_DIR/rocket.rs` (feature `assets`):
/// recentred and scaled to the unit sphere, normals computed, `u16`
/// indices. A bad file stops the build with the importer's message.
#[cfg(feature = "assets")]
fn convert_assets() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("rocket.rs");
    let options = microraster_import::ObjOptions::new().with_fit(microraster_import::Fit::Unit);
    match microraster_import::obj_to_rust("examples/assets/rocket.obj", &out, "rocket", &options) {
        Ok(summary) => print!("{}", summary.rerun_if_changed()),
        Err(e) => panic!("{e}"),
    }
}

fn main() {
    #[cfg(feature = "assets")]
    convert_assets();
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo::rustc-check-cfg=cfg(microraster_board, values(\"mps2-an386\"))");
    let target = env::var("TARGET").unwrap_or_default();
    let board = env::var("CARGO_CFG_MICRORASTER_BOARD").ok();
    println!("cargo::rustc-check-cfg=cfg(microraster_narrow_multiply)");
    if matches!(
        target.split('-').next().unwrap_or_default(),
        "thumbv6m" | "thumbv8m.base"
    ) {
        println!("cargo:rustc-cfg=microraster_narrow_multiply");
    }
    // The Gouraud shader's loop of its own (`shade::perspective`'s
    // `COLOUR_LOOP`): on 32-bit Arm cores with a long multiply (Thumb-2),
    // where it is faster; anywhere with `MICRORASTER_COLOUR_LOOP=1`, so
    // that the host's span-shader and golden tests can run it too (CI).
    println!("cargo::rustc-check-cfg=cfg(microraster_colour_loop)");
    println!("cargo:rerun-if-env-changed=MICRORASTER_COLOUR_LOOP");
    let thumb2 = target.starts_with("thumbv7") || target.starts_with("thumbv8m.main");
    if thumb2 || env::var("MICRORASTER_COLOUR_LOOP").is_ok_and(|v| v == "1") {
        println!("cargo:rustc-cfg=microraster_colour_loop");
    }
    // The built-in shaders' loops of 32-bit targets (`shade::perspective`'s
    // `LOOPS32`), on a 64-bit host too with `MICRORASTER_LOOPS32=1`, for
    // the same tests.
    println!("cargo::rustc-check-cfg=cfg(microraster_loops32)");
    println!("cargo:rerun-if-env-changed=MICRORASTER_LOOPS32");
    if env::var("MICRORASTER_LOOPS32").is_ok_and(|v| v == "1") {
        println!("cargo:rustc-cfg=microraster_loops32");
    }
    // `vertex::screen`'s interior bit and the clamp-free Gouraud span
    // starts it allows (`INTERIOR_STARTS`): not in builds optimised for
    // size (opt-level "s" or "z": the `size` profile of the OLED firmware,
    // where its code is worth more than its speed). The Cortex-M4F takes
    // it too since the span starts' second loop (an interior triangle's
    // flag tested once a pair): `demo` 3,352,005 -> 3,293,360
    // instructions (vertex +29 K, raster and shade -88 K), `rock`
    // 2,818,161 -> 2,748,045 (it had been off there, when it cost +10.9 K).
    println!("cargo::rustc-check-cfg=cfg(microraster_interior)");
    println!("cargo:rerun-if-env-changed=OPT_LEVEL");
    let size = matches!(env::var("OPT_LEVEL").as_deref(), Ok("s" | "z"));
    if !size {
        println!("cargo:rustc-cfg=microraster_interior");
    }
    // ARMv7-M without the DSP extension (`thumbv7m`: the Cortex-M3), for
    // code generation choices measured faster on it alone (the nearest
    // texture loop's constants read in place, `shade::perspective`).
    println!("cargo::rustc-check-cfg=cfg(microraster_armv7m)");
    if target.starts_with("thumbv7m-") {
        println!("cargo:rustc-cfg=microraster_armv7m");
    }
    // ARMv7E-M (`thumbv7em`: the Cortex-M4 and M7), for code generation
    // choices measured faster on the Cortex-M4F alone (the colour table's
    // address made opaque in the Gouraud loop of the triangles that are
    // not interior, `shade::OPAQUE_TABLE`).
    println!("cargo::rustc-check-cfg=cfg(microraster_armv7em)");
    if target.starts_with("thumbv7em-") {
        println!("cargo:rustc-cfg=microraster_armv7em");
    }
    // ARMv8-M Mainline (`thumbv8m.main`: the Cortex-M33 of the Pico 2's
    // RP2350), for the choices measured faster on it (its frame code's
    // instructions counted on QEMU's MPS2-AN505 by the stack probe,
    // `tests/qemu_stack.rs`).
    println!("cargo::rustc-check-cfg=cfg(microraster_armv8m)");
    if target.starts_with("thumbv8m.main-") {
        println!("cargo:rustc-cfg=microraster_armv8m");
    }
    // Builds optimised for size: code that buys speed with flash (the
    // binning loop's single-tile push) is left out of them.
    println!("cargo::rustc-check-cfg=cfg(microraster_size)");
    if size {
        println!("cargo:rustc-cfg=microraster_size");
    }
    // Cores without an FPU (`f32` in library calls), not optimised for
    // size: Arm's soft-float ABIs, and RISC-V without the F extension
    // (the ESP32-C3's RV32IMC, whose frames of the boards' scene took
    // about 18,000 instructions fewer each with them). The per-draw
    // set-up's short cuts around soft-float arithmetic
    // (`math::SOFT_FLOAT`) cost more than they save where an FPU does the
    // arithmetic, and flash where size counts.
    println!("cargo::rustc-check-cfg=cfg(microraster_soft_float)");
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let hard_float = env::var("CARGO_CFG_TARGET_ABI").is_ok_and(|a| a == "eabihf");
    let f_extension = env::var("CARGO_CFG_TARGET_FEATURE")
        .is_ok_and(|f| f.split(',').any(|feature| feature == "f"));
    let soft_float = match arch.as_str() {
        "arm" => !hard_float,
        "riscv32" => !f_extension,
        _ => false,
    };
    if soft_float && !size {
        println!("cargo:rustc-cfg=microraster_soft_float");
    }
    println!("cargo::rustc-check-cfg=cfg(microraster_lm3s6965)");
    if let Some(map) = board_map(&target, board.as_deref()) {
        let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        fs::copy(map, out.join("memory.x"))
            .unwrap_or_else(|e| panic!("copying {map} to OUT_DIR/memory.x: {e}"));
        if map == "memory.x" {
            // The LM3S6965's firmwares bind its 44 interrupts themselves
            // (examples/lm3s6965_vectors), with cortex-m-rt's `device`
            // feature (Cargo.toml), rather than the 240 of a device-agnostic
            // table: 784 bytes of flash. cortex-m-rt's link.x then includes
            // a `device.x`, which names no handler here.
            fs::write(out.join("device.x"), "/* examples/lm3s6965_vectors */\n")
                .unwrap_or_else(|e| panic!("writing OUT_DIR/device.x: {e}"));
            println!("cargo:rustc-cfg=microraster_lm3s6965");
        }
        println!("cargo:rustc-link-arg-examples=-L{}", out.display());
    }
    if target.starts_with("riscv32") && target.ends_with("-none-elf") {
        let root = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
        let script = root.join("memory/qemu-riscv32-virt.x");
        println!("cargo:rustc-link-arg-examples=-T{}", script.display());
    }
}
