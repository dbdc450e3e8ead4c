//! A firmware that depends on microraster links with its own memory map,
//! never with the LM3S6965's that microraster's build script provides for
//! its own examples.
//!
//! A tiny firmware is written to a temporary directory with a
//! board-support crate, `stm32-board`, whose build script puts its board's
//! `memory.x` (flash at `0x0800_0000`, an STM32-like map) on the linker's
//! search path, as board-support crates do. Cargo orders the search paths
//! of dependencies by name, so microraster's comes first: whatever map it
//! offers there wins. The firmware is built for `thumbv7m-none-eabi` (the
//! LM3S6965's target, where microraster's build script has a map) with
//! cortex-m-rt's `link.x`, and its entry point must lie in the board's
//! flash.

mod support;

use std::path::Path;
use std::process::Command;
use support::host;

const TARGET: &str = "thumbv7m-none-eabi";
/// The board's flash, as its `memory.x` says.
const FLASH: std::ops::Range<u32> = 0x0800_0000..0x0802_0000;

const MANIFEST: &str = r#"[package]
name = "board-firmware"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
microraster = { path = "@ROOT@" }
stm32-board = { path = "board" }
cortex-m-rt = "0.7"

[profile.release]
debug = true

# Not part of any workspace above the temporary directory.
[workspace]
"#;

const BOARD_MANIFEST: &str = r#"[package]
name = "stm32-board"
version = "0.0.0"
edition = "2021"
publish = false
"#;

const BOARD_BUILD_RS: &str = r#"fn main() {
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").unwrap());
    std::fs::copy("memory.x", out.join("memory.x")).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
}
"#;

const MEMORY_X: &str = "MEMORY
{
  FLASH : ORIGIN = 0x08000000, LENGTH = 128K
  RAM   : ORIGIN = 0x20000000, LENGTH = 20K
}
";

const MAIN_RS: &str = r#"#![no_std]
#![no_main]

use cortex_m_rt::entry;
use microraster::prelude::*;
use stm32_board as _;

#[entry]
fn main() -> ! {
    let size = core::hint::black_box(Size::new(16, 16));
    core::hint::black_box(size);
    loop {}
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
"#;

const CONFIG: &str = r#"[target.thumbv7m-none-eabi]
rustflags = ["-C", "link-arg=-Tlink.x"]
"#;

/// The entry point of a 32-bit little-endian ELF file.
fn elf32_entry(elf: &[u8]) -> u32 {
    assert_eq!(&elf[..4], b"\x7fELF", "an ELF file");
    assert_eq!(elf[4], 1, "32-bit");
    assert_eq!(elf[5], 1, "little-endian");
    u32::from_le_bytes(elf[0x18..0x1c].try_into().unwrap())
}

#[test]
fn a_dependent_firmware_links_with_its_own_memory_map() {
    if !host::require("dependent_memory_map", &[host::Need::Target(TARGET)]) {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("microraster-board-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["src", "board/src", ".cargo"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
    }
    let manifest = MANIFEST.replace("@ROOT@", &root.display().to_string());
    std::fs::write(dir.join("Cargo.toml"), manifest).unwrap();
    std::fs::write(dir.join("src/main.rs"), MAIN_RS).unwrap();
    std::fs::write(dir.join("board/Cargo.toml"), BOARD_MANIFEST).unwrap();
    std::fs::write(dir.join("board/build.rs"), BOARD_BUILD_RS).unwrap();
    std::fs::write(dir.join("board/memory.x"), MEMORY_X).unwrap();
    std::fs::write(dir.join("board/src/lib.rs"), "#![no_std]\n").unwrap();
    std::fs::write(dir.join(".cargo/config.toml"), CONFIG).unwrap();
    // The workspace's lock file: the same, already fetched, versions.
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock")).unwrap();

    // A target directory of its own, kept between runs: the dependencies
    // build once.
    let target_dir = root.join("target").join("dependent-firmware");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(&dir)
        .args(["build", "--release", "--target", TARGET])
        .env("CARGO_TARGET_DIR", &target_dir)
        // The toolchain running this test (the temporary directory is
        // outside the repository and its rust-toolchain.toml).
        .env("RUSTC", host::rustc())
        .output()
        .expect("cargo runs");
    assert!(
        output.status.success(),
        "the board firmware builds:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let elf = std::fs::read(target_dir.join(TARGET).join("release/board-firmware")).unwrap();
    let entry = elf32_entry(&elf);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        FLASH.contains(&entry),
        "the firmware's entry point {entry:#010x} is outside its board's flash \
         {FLASH:#010x?}: it was linked with another memory map (microraster's?)"
    );
}
