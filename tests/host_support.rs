//! The rule for tests that need more than rustup installs (an emulator, a
//! Rust target): skip loudly on a developer's machine, fail in CI.

mod support;

use support::host::{verdict, Need, Verdict, QEMU_ARM};

#[test]
fn nothing_missing_runs() {
    assert_eq!(verdict("t", &[], false), Verdict::Run);
    assert_eq!(verdict("t", &[], true), Verdict::Run);
}

#[test]
fn missing_skips_loudly_off_ci_and_fails_in_ci() {
    let missing = ["qemu-system-arm is not installed".to_string()];
    match verdict("qemu_oled", &missing, false) {
        Verdict::Skip(line) => {
            assert!(line.contains("SKIPPED qemu_oled"), "{line}");
            assert!(line.contains("qemu-system-arm is not installed"), "{line}");
        }
        other => panic!("expected a skip, got {other:?}"),
    }
    assert!(matches!(
        verdict("qemu_oled", &missing, true),
        Verdict::Fail(m) if m.contains("qemu-system-arm")
    ));
}

#[test]
fn an_absent_program_says_how_to_install_it() {
    let need = Need::Program {
        name: "microraster-no-such-emulator",
        install: "the package manager",
    };
    let why = need.missing("").expect("the program does not exist");
    assert!(why.contains("microraster-no-such-emulator"), "{why}");
    assert!(why.contains("the package manager"), "{why}");
    // QEMU's own hint names the package.
    let why = QEMU_ARM
        .missing("qemu-system-arm")
        .expect("pretended missing");
    assert!(why.contains("apt-get install qemu-system-arm"), "{why}");
}

#[test]
fn targets_are_found_in_the_sysroot_or_pretended_missing() {
    let why = Need::Target("microraster-no-such-target")
        .missing("")
        .expect("no such target");
    assert!(
        why.contains("rustup target add microraster-no-such-target"),
        "{why}"
    );
    // The host's own standard library is always installed...
    let host = String::from_utf8(
        std::process::Command::new(support::host::rustc())
            .arg("-vV")
            .output()
            .expect("rustc runs")
            .stdout,
    )
    .unwrap();
    let host = host
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .expect("rustc -vV names the host");
    assert_eq!(Need::Target(host).missing(""), None);
    // ...unless the variable says to pretend otherwise.
    let pretend = format!("qemu-system-arm, {host}");
    assert!(Need::Target(host).missing(&pretend).is_some());
}

#[test]
fn installed_files_are_looked_for_in_the_repository() {
    let need = |path| Need::File {
        name: "some-package",
        path,
        install: "npm ci --prefix somewhere",
    };
    let why = need("tests/no-such-dir/package.json")
        .missing("")
        .expect("no such file");
    assert!(why.contains("some-package is not installed"), "{why}");
    assert!(why.contains("npm ci --prefix somewhere"), "{why}");
    // Cargo.toml is always there, unless pretended missing by name.
    assert_eq!(need("Cargo.toml").missing(""), None);
    assert!(need("Cargo.toml").missing("some-package").is_some());
}
