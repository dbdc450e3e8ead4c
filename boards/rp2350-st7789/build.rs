//! Links the firmware with cortex-m-rt's `link.x` and this board's
//! `memory.x`, whatever directory cargo runs from: the map is copied to
//! `$OUT_DIR` and put on the linker's search path, and the linker arguments
//! are given here rather than in `.cargo/config.toml` (which cargo reads
//! only from its working directory upwards, not from a `--manifest-path`).

use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("copying memory.x to OUT_DIR");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    // No page alignment of the load segments: the vector table, the boot
    // block and the code share the first page of flash.
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
