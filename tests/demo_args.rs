//! The demo's command line (`examples/common/demo_args.rs`): `--help`,
//! separate outputs for the animation (a directory) and a model (a PNG
//! file), flags that do not apply refused rather than ignored, nothing
//! written into the repository root by default, and every error naming
//! its flag.

#[path = "../examples/common/demo_args.rs"]
#[allow(dead_code)]
mod demo_args;

use demo_args::{default_out_dir, Args, Mode, Parsed, USAGE};
use microraster::prelude::*;
use std::path::{Path, PathBuf};

/// The flags that take a value.
const VALUE_FLAGS: [&str; 10] = [
    "--frames",
    "--out-dir",
    "--obj",
    "--out",
    "--yaw",
    "--size",
    "--shader",
    "--texture",
    "--perspective",
    "--raster",
];

fn parse(args: &[&str]) -> Result<Parsed, String> {
    demo_args::parse(args.iter().map(|s| s.to_string()))
}

fn run(args: &[&str]) -> Args {
    match parse(args) {
        Ok(Parsed::Run(a)) => a,
        other => panic!("{args:?}: {other:?}"),
    }
}

#[test]
fn help_lists_every_option() {
    assert_eq!(parse(&["--help"]), Ok(Parsed::Help));
    assert_eq!(parse(&["--frames", "2", "-h"]), Ok(Parsed::Help));
    let switches = ["--flat", "--hilbert", "--hilbert-tiles", "--help"];
    for flag in VALUE_FLAGS.iter().chain(&switches) {
        assert!(USAGE.contains(flag), "--help does not mention {flag}");
    }
}

#[test]
fn the_defaults_write_under_target_not_the_repository_root() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert_eq!(default_out_dir(), root.join("target/demo"));
    let a = run(&[]);
    assert_eq!(
        a.mode,
        Mode::Animation {
            frames: 8,
            out_dir: root.join("target/demo")
        }
    );
    assert_eq!(a.size, Size::new(320, 240));
    let Mode::Model { out, yaw, .. } = run(&["--obj", "some/where/my.rocket.obj"]).mode else {
        panic!("a model")
    };
    assert_eq!(out, root.join("target/demo/my.rocket.png"));
    assert_eq!(yaw, 30.0);
}

#[test]
fn the_animation_writes_into_out_dir_and_a_model_into_out() {
    let a = run(&["--out-dir", "frames", "--frames", "3"]);
    assert_eq!(
        a.mode,
        Mode::Animation {
            frames: 3,
            out_dir: PathBuf::from("frames")
        }
    );
    let a = run(&["--obj", "m.obj", "--out", "pic.PNG", "--yaw", "90"]);
    assert_eq!(
        a.mode,
        Mode::Model {
            obj: PathBuf::from("m.obj"),
            out: PathBuf::from("pic.PNG"),
            yaw: 90.0
        }
    );
}

#[test]
fn outputs_of_the_other_mode_are_refused() {
    let e = parse(&["--out", "x.png"]).unwrap_err();
    assert!(e.starts_with("--out ") && e.contains("--out-dir"), "{e}");
    let e = parse(&["--obj", "m.obj", "--out-dir", "d"]).unwrap_err();
    assert!(e.starts_with("--out-dir ") && e.contains("--out "), "{e}");
    let e = parse(&["--obj", "m.obj", "--out", "picture"]).unwrap_err();
    assert!(e.starts_with("--out ") && e.contains(".png"), "{e}");
}

#[test]
fn size_applies_to_both_and_yaw_and_frames_only_where_they_mean_something() {
    assert_eq!(run(&["--size", "100x50"]).size, Size::new(100, 50));
    assert_eq!(
        run(&["--obj", "m.obj", "--size", "64x64"]).size,
        Size::new(64, 64)
    );
    let e = parse(&["--yaw", "10"]).unwrap_err();
    assert!(e.starts_with("--yaw "), "{e}");
    let e = parse(&["--obj", "m.obj", "--frames", "2"]).unwrap_err();
    assert!(e.starts_with("--frames "), "{e}");
}

#[test]
fn any_finite_yaw_is_a_turn_within_one_revolution() {
    for (given, expected) in [("370", 10.0), ("-90", 270.0), ("720", 0.0)] {
        let Mode::Model { yaw, .. } = run(&["--obj", "m.obj", "--yaw", given]).mode else {
            panic!("a model")
        };
        assert_eq!(yaw, expected, "--yaw {given}");
    }
    // Once blamed on "draw 0": the rotation of a huge angle was not finite.
    let Mode::Model { yaw, .. } = run(&["--obj", "m.obj", "--yaw", "1e30"]).mode else {
        panic!("a model")
    };
    assert!((0.0..360.0).contains(&yaw), "{yaw}");
    for bad in ["nan", "inf", "ten"] {
        let e = parse(&["--obj", "m.obj", "--yaw", bad]).unwrap_err();
        assert!(e.starts_with("--yaw "), "{e}");
    }
}

#[test]
fn every_error_names_its_flag() {
    for flag in VALUE_FLAGS {
        let e = parse(&[flag]).unwrap_err();
        assert!(e.starts_with(&format!("{flag} needs")), "{flag}: {e}");
    }
    for (flag, bad) in [
        ("--frames", "0"),
        ("--frames", "many"),
        ("--size", "0x10"),
        ("--size", "big"),
        ("--shader", "toon"),
        ("--perspective", "fisheye"),
        ("--raster", "zigzag"),
    ] {
        let e = parse(&[flag, bad]).unwrap_err();
        assert!(e.starts_with(flag) && e.contains(bad), "{flag} {bad}: {e}");
    }
    let e = parse(&["--frame", "2"]).unwrap_err();
    assert!(e.starts_with("--frame ") && e.contains("--help"), "{e}");
}
