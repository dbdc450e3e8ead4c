//! The part of the Cortex-M boards' build scripts that they share (included
//! with `#[path]`, as their firmware includes `examples/board_support`):
//! the board's `memory.x` copied to `$OUT_DIR` and put on the linker's
//! search path, where cortex-m-rt's `link.x` looks for it, whatever
//! directory cargo runs from.

use std::{env, fs, path::PathBuf};

/// Puts the board's `memory.x` on the linker's search path and reruns the
/// build script when it or the script changes.
pub fn memory_x_on_search_path() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("copying memory.x to OUT_DIR");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=../memory_map.rs");
}
