//! Links the firmware with cortex-m-rt's `link.x`, embassy-rp's `link-rp.x`
//! (which puts boot2 first in flash) and this board's `memory.x`, whatever
//! directory cargo runs from: the map is copied to `$OUT_DIR` and put on the
//! linker's search path, and the linker arguments are given here rather
//! than in `.cargo/config.toml` (which cargo reads only from its working
//! directory upwards, never from a `--manifest-path`).
//!
//! Cargo does read every `.cargo/config.toml` from its working directory
//! upwards, so a build started inside microraster's repository also gets
//! the root config's thumbv6m flags (`--nmagic`, `-Tlink.x`, for the
//! rp2040-hal firmware). A linker script must not be read twice (its
//! sections and symbols would be defined again), so an argument already
//! among the rustflags is not repeated.

use std::env;

#[path = "../memory_map.rs"]
mod memory_map;

fn main() {
    memory_map::memory_x_on_search_path();
    let rustflags = env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
    let given: Vec<&str> = rustflags.split('\x1f').collect();
    // No page alignment of the load segments: boot2, the vector table and
    // the code share the first page of flash.
    for arg in ["--nmagic", "-Tlink.x", "-Tlink-rp.x"] {
        if !given.contains(&format!("link-arg={arg}").as_str()) {
            println!("cargo:rustc-link-arg-bins={arg}");
        }
    }
}
