//! What the rp2040js tests share: the repository's root, the firmware's
//! target, building a Pico example, and the harness's npm packages as a
//! need (`host::require`).

use super::host;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Pico's (and the RP2040's Cortex-M0+'s) target.
pub const TARGET: &str = "thumbv6m-none-eabi";

/// The harness's npm packages.
pub const RP2040JS: host::Need<'static> = host::Need::File {
    name: "rp2040js",
    path: "tests/pico/node_modules/rp2040js/package.json",
    install: "npm ci --prefix tests/pico (Node.js's npm; the versions are in \
              tests/pico/package-lock.json)",
};

/// The repository's root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Builds the release firmware `examples/{example}.rs` for the Pico, as CI
/// and the README build it (into the same target directory: the same
/// command builds nothing twice), and returns its ELF.
pub fn build_example(example: &str) -> PathBuf {
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root())
        .args(["build", "--release", "--example", example])
        .args(["--target", TARGET])
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the firmware {example} builds");
    target_dir
        .join(TARGET)
        .join("release/examples")
        .join(example)
}
