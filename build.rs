//! Puts the board's `memory.x` where cortex-m-rt's `link.x` finds it, for
//! the firmware examples. Host and library-only builds ignore it.

use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    let target = env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv7m-") {
        let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        fs::copy("memory.x", out.join("memory.x")).expect("memory.x is in the crate root");
        println!("cargo:rustc-link-search={}", out.display());
    }
}
