//! Links the firmware with cortex-m-rt's `link.x` and this board's
//! `memory.x`, whatever directory cargo runs from: the map is copied to
//! `$OUT_DIR` and put on the linker's search path, and the linker arguments
//! are given here rather than in `.cargo/config.toml` (which cargo reads
//! only from its working directory upwards, not from a `--manifest-path`).

#[path = "../memory_map.rs"]
mod memory_map;

fn main() {
    memory_map::memory_x_on_search_path();
    // No page alignment of the load segments: the vector table, the boot
    // block and the code share the first page of flash.
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
