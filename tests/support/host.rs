//! What a test needs from the machine beyond a rustup install: an emulator
//! on `PATH`, a Rust target's standard library.
//!
//! The rule, written once for every such test: on a developer's machine a
//! missing requirement skips the test loudly (one line saying what was
//! skipped and how to install what is missing), so that the rest of
//! `cargo test --workspace` still runs; in CI (`CI` set, as every CI service
//! sets it) it is a failure, so that CI can never pass by skipping.
//!
//! `MICRORASTER_PRETEND_MISSING`, a comma-separated list of program names
//! and target triples, treats those as missing: the skip can be seen (and
//! tested) without uninstalling anything that other builds on the machine
//! are using.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// The variable naming programs and targets to treat as missing.
pub const PRETEND_MISSING: &str = "MICRORASTER_PRETEND_MISSING";

/// One thing a test needs.
#[derive(Clone, Copy, Debug)]
pub enum Need<'a> {
    /// A program on `PATH` that answers `--version`, and how to install it.
    Program { name: &'a str, install: &'a str },
    /// A Rust target whose standard library rustup has installed.
    Target(&'a str),
    /// A file that an install step creates (for example the `package.json`
    /// of a Node.js package that `npm ci` installs), relative to the
    /// repository; `name` is what `MICRORASTER_PRETEND_MISSING` calls it.
    File {
        name: &'a str,
        path: &'a str,
        install: &'a str,
    },
}

/// QEMU's Arm system emulator (the emulated boards).
pub const QEMU_ARM: Need<'static> = Need::Program {
    name: "qemu-system-arm",
    install: "apt-get install qemu-system-arm (Debian, Ubuntu), \
              dnf install qemu-system-arm (Fedora) or brew install qemu (macOS)",
};

/// QEMU's 32-bit RISC-V system emulator (the `virt` machine, for the stack
/// probe of the ESP32-C3's instruction set).
pub const QEMU_RISCV32: Need<'static> = Need::Program {
    name: "qemu-system-riscv32",
    install: "apt-get install qemu-system-misc (Debian, Ubuntu), \
              dnf install qemu-system-riscv (Fedora) or brew install qemu (macOS)",
};

/// Node.js (the emulated Raspberry Pi Pico runs in rp2040js).
pub const NODE: Need<'static> = Need::Program {
    name: "node",
    install: "apt-get install nodejs npm (Debian, Ubuntu; Node.js 18 or later), \
              or from https://nodejs.org",
};

/// What a test does about its needs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Everything is there.
    Run,
    /// Skip, printing this line.
    Skip(String),
    /// Fail with this message.
    Fail(String),
}

impl Need<'_> {
    /// Why this need is not met, with the fix, or `None` when it is.
    /// `pretend` is the value of [`PRETEND_MISSING`].
    pub fn missing(&self, pretend: &str) -> Option<String> {
        let pretended = |name: &str| pretend.split(',').any(|p| p.trim() == name);
        match *self {
            Need::Program { name, install } => (pretended(name) || !program_runs(name))
                .then(|| format!("{name} is not installed; install it with {install}")),
            Need::Target(triple) => (pretended(triple) || !target_installed(triple)).then(|| {
                format!(
                    "the Rust target {triple} is not installed \
                     (rustup does not add rust-toolchain.toml's targets to a \
                     toolchain that is already installed); \
                     install it with: rustup target add {triple}"
                )
            }),
            Need::File {
                name,
                path,
                install,
            } => (pretended(name)
                || !std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join(path)
                    .exists())
            .then(|| {
                format!("{name} is not installed ({path} is missing); install it with {install}")
            }),
        }
    }
}

/// The rule: run when nothing is `missing`; otherwise skip, or fail in CI.
pub fn verdict(test: &str, missing: &[String], ci: bool) -> Verdict {
    if missing.is_empty() {
        return Verdict::Run;
    }
    let why = missing.join("; ");
    if ci {
        Verdict::Fail(format!("{test} cannot run in CI: {why}"))
    } else {
        Verdict::Skip(format!(
            "*** SKIPPED {test}: {why} (in CI, with CI set, this fails) ***"
        ))
    }
}

/// Whether `CI` is set to something other than empty, `0` or `false`.
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| !matches!(v.trim(), "" | "0" | "false"))
}

/// Applies the rule to `needs` for `test`: `true` when it can run; `false`
/// after printing the skip line; a panic in CI.
pub fn require(test: &str, needs: &[Need<'_>]) -> bool {
    let pretend = std::env::var(PRETEND_MISSING).unwrap_or_default();
    let missing: Vec<String> = needs.iter().filter_map(|n| n.missing(&pretend)).collect();
    match verdict(test, &missing, in_ci()) {
        Verdict::Run => true,
        Verdict::Skip(line) => {
            // Straight to the stderr handle: the test harness captures
            // `eprintln!` (and shows it only for failures), not this, so
            // the line shows in `cargo test`'s output though the test
            // passes.
            let _ = writeln!(std::io::stderr(), "\n{line}\n");
            false
        }
        Verdict::Fail(message) => panic!("{message}"),
    }
}

/// Whether `name --version` runs and succeeds.
fn program_runs(name: &str) -> bool {
    Command::new(name)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The rustc of the cargo running the tests (rustup's toolchain directory
/// holds both), else the one on `PATH`.
pub fn rustc() -> PathBuf {
    std::env::var_os("CARGO")
        .map(PathBuf::from)
        .and_then(|cargo| Some(cargo.parent()?.join("rustc")))
        .filter(|rustc| rustc.exists())
        .unwrap_or_else(|| PathBuf::from("rustc"))
}

/// Whether the toolchain's sysroot holds `triple`'s standard library
/// (`lib/rustlib/<triple>/lib/libcore-*.rlib`), which `rustup target add`
/// installs.
pub fn target_installed(triple: &str) -> bool {
    let Ok(out) = Command::new(rustc()).args(["--print", "sysroot"]).output() else {
        return false;
    };
    let sysroot = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    let lib = sysroot.join("lib/rustlib").join(triple).join("lib");
    std::fs::read_dir(lib).is_ok_and(|entries| {
        entries.filter_map(Result::ok).any(|e| {
            let name = e.file_name();
            let name = name.to_string_lossy();
            name.starts_with("libcore-") && name.ends_with(".rlib")
        })
    })
}
