//! End to end on an emulated Raspberry Pi Pico: builds the release firmware
//! `examples/rp2040_st7789.rs`, runs it in rp2040js (Node.js) with a stub
//! boot ROM and a model of the ST7789 panel (`tests/pico/`), and requires
//! each frame the panel shows to equal, pixel for pixel, the host's render
//! of the same scene at the animation time the firmware read from its
//! timer. The ROM's float-to-integer conversion rounds towards -infinity as
//! the real one does, so a difference between host and Pico arithmetic
//! shows here.
//!
//! Without Node.js, the harness's npm packages (`npm ci` in `tests/pico`)
//! or the `thumbv6m-none-eabi` target the test is skipped with a line
//! saying how to install them, or fails in CI (`tests/support/host.rs`).
//! `MICRORASTER_PICO_FRAMES=N` checks N frames instead of 2.

#[path = "../examples/st7789_scene/mod.rs"]
mod st7789_scene;
mod support;

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::RawData;
use microraster::prelude::*;
use st7789_scene::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use support::host;

const TARGET: &str = "thumbv6m-none-eabi";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Builds the release firmware, as CI and the README build it (into the
/// same target directory: the same command builds nothing twice).
fn build_firmware() -> PathBuf {
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root())
        .args(["build", "--release", "--example", "rp2040_st7789"])
        .args(["--target", TARGET])
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the firmware builds");
    target_dir
        .join(TARGET)
        .join("release/examples/rp2040_st7789")
}

/// The host's render of the firmware's scene at `time_us`, as raw Rgb565.
fn host_frame(knot: &Mesh<'_>, cube: &Mesh<'_>, time_us: u64) -> Vec<u16> {
    let draws = draws(knot, cube, time_us);
    let scene = Scene::new(camera().expect("the camera"), &draws).light(light());
    let mut renderer = PicoRenderer::new(config());
    let mut ws: Box<PicoWorkspace> = Box::new(PicoWorkspace::new());
    let mut cap = support::Capture::new(Size::new(WIDTH, HEIGHT), CLEAR);
    renderer.render(&mut ws, &scene, &mut cap).expect("renders");
    cap.pixels
        .iter()
        .map(|&c| RawU16::from(c).into_inner())
        .collect()
}

fn to_rgb(px: &[u16]) -> Vec<Rgb888> {
    px.iter()
        .map(|&v| Rgb565::from(RawU16::new(v)).into())
        .collect()
}

/// One frame of the harness's report.json (a few fields, read by hand: no
/// JSON crate for one test).
#[derive(Debug)]
struct Frame {
    time_us: u64,
    period: u64,
    spi: u64,
    idle: u64,
}

fn field(obj: &str, name: &str) -> u64 {
    let key = format!("\"{name}\":");
    let at = obj.find(&key).unwrap_or_else(|| panic!("{name} in {obj}")) + key.len();
    obj[at..]
        .trim_start()
        .split(|c: char| !c.is_ascii_digit())
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("a number for {name} in {obj}"))
}

fn frames_of(report: &str) -> Vec<Frame> {
    let frames = &report[report.find("\"frames\"").expect("frames in the report")..];
    frames
        .split("\"index\"")
        .skip(1)
        .map(|f| Frame {
            time_us: field(f, "time_us"),
            period: field(f, "period_cycles"),
            spi: field(f, "spi_cycles"),
            idle: field(f, "idle_cycles"),
        })
        .collect()
}

/// The harness's npm packages.
const RP2040JS: host::Need<'static> = host::Need::File {
    name: "rp2040js",
    path: "tests/pico/node_modules/rp2040js/package.json",
    install: "npm ci --prefix tests/pico (Node.js's npm; the versions are in \
              tests/pico/package-lock.json)",
};

/// The harness's panel model refuses malformed command streams and its
/// ROM rounds as the RP2040's does (`tests/pico/models.test.mjs`).
#[test]
fn pico_harness_models() {
    if !host::require("pico_harness_models", &[host::NODE, RP2040JS]) {
        return;
    }
    let run = Command::new("node")
        .current_dir(root().join("tests/pico"))
        .args(["--test", "models.test.mjs"])
        .output()
        .expect("node runs");
    assert!(
        run.status.success(),
        "the harness's model tests failed:\n{}\n{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
}

#[test]
fn pico_firmware_in_rp2040js_matches_host_render() {
    let needs = [host::NODE, RP2040JS, host::Need::Target(TARGET)];
    if !host::require("pico_emulated", &needs) {
        return;
    }
    let frames: usize = std::env::var("MICRORASTER_PICO_FRAMES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(2);
    let elf = build_firmware();
    let out = root().join("target/pico-e2e/panel");
    let _ = std::fs::remove_dir_all(&out);

    let started = Instant::now();
    let run = Command::new("node")
        .arg(root().join("tests/pico/run.mjs"))
        .arg(&elf)
        .args(["--frames", &frames.to_string()])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success(),
        "the emulated Pico failed:\n{stdout}\n{stderr}"
    );
    println!(
        "pico_emulated ({:.1} s):\n{stdout}",
        started.elapsed().as_secs_f32()
    );

    let report = std::fs::read_to_string(out.join("report.json")).expect("report.json");
    let reported = frames_of(&report);
    assert_eq!(reported.len(), frames, "{report}");
    // The stack, painted before reset and read back after the last frame,
    // stayed clear of the statics (RAM is 256 KiB; a stack that reached
    // them would have left no painted word).
    let statics = field(&report, "static_ram_bytes");
    let stack = field(&report, "peak_stack_bytes");
    assert!(
        stack > 1_024 && statics + stack < 256 * 1024,
        "peak stack {stack} B over statics of {statics} B"
    );

    let mut knot_data = Box::new(KnotData::new());
    let knot = knot_data.generate().expect("the knot");
    let cube = cube().expect("the cube");
    let mut failures = Vec::new();
    for (i, f) in reported.iter().enumerate() {
        // Every frame sends all of its 240x240 pixels: 115,200 bytes and
        // 64 windows of 11 command bytes, 16 cycles a byte at 62.5 MHz.
        assert_eq!(f.spi, (115_200 + 64 * 11) * 16, "frame {i}: {f:?}");
        assert!(f.idle > 0 && f.period == f.spi + f.idle, "frame {i}: {f:?}");
        let raw = std::fs::read(out.join(format!("frame_{i:03}.rgb565"))).expect("the frame");
        let panel: Vec<u16> = raw
            .chunks(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect();
        let host = host_frame(&knot, &cube, f.time_us);
        let size = Size::new(WIDTH, HEIGHT);
        if i == 0 {
            // For the README (docs/pico_panel.png). Not compared with it:
            // the first frame's time, so its picture, moves whenever the
            // firmware's speed does.
            support::write_png(
                &root().join("target/pico-e2e/pico_panel.png"),
                size,
                &to_rgb(&panel),
            );
        }
        let diff = panel.iter().zip(&host).filter(|(a, b)| a != b).count();
        if diff != 0 {
            let dir = root().join("target/golden-diff");
            support::write_png(
                &dir.join(format!("pico_{i:03}.panel.png")),
                size,
                &to_rgb(&panel),
            );
            support::write_png(
                &dir.join(format!("pico_{i:03}.host.png")),
                size,
                &to_rgb(&host),
            );
            failures.push(format!("frame {i} (t = {} us): {diff} pixels", f.time_us));
        }
    }
    assert!(
        failures.is_empty(),
        "the emulated panel differs from the host render: {} (target/golden-diff/pico_*.png)",
        failures.join("; ")
    );
}
