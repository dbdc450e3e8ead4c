//! The RP2040 benchmark in rp2040js: builds the release firmware
//! `examples/rp2040_bench.rs`, runs it with `tests/pico/run.mjs --bench`,
//! and requires every frame it rendered, `demo` and `rock` at 240x240 and
//! 320x240, to be the host's frame: the same `FrameStats`, field for field
//! (at 320x240 those of `examples/count.rs`). So the cycles per frame that
//! BENCHMARKS.md reports are cycles of the host's work. Prints the
//! harness's table.
//!
//! Without Node.js, the harness's npm packages or the `thumbv6m-none-eabi`
//! target the test is skipped with a line saying how to install them, or
//! fails in CI (`tests/support/host.rs`).

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::rock_scene;
use common::scenes::{DemoWorkspace, RockWorkspace};
use embedded_graphics::pixelcolor::Rgb565;
use microraster::prelude::*;
use std::process::Command;
use std::time::Instant;
use support::host;
use support::pico::{build_example, root, RP2040JS, TARGET};

/// The host's `FrameStats` of `scene` at `width` x `height`, as the
/// firmware renders it (and, at 320x240, `examples/count.rs`), printed as
/// `count` prints them.
fn host_stats(scene: &str, width: u32, height: u32) -> String {
    let mut r =
        Renderer::<Rgb565, 32, 32>::new(Config::new(Size::new(width, height), common::DEMO_CLEAR));
    let stats = match scene {
        "demo" => {
            let assets = common::DemoAssets::new();
            let (knot, cube) = (assets.knot(), common::cube());
            let draws = common::draws(&knot, &cube, 0.0, Shading::Gouraud);
            let scene = Scene::new(common::camera(width, height), &draws).light(common::light());
            let mut ws: Box<DemoWorkspace> = Box::default();
            r.render(&mut ws, &scene, &mut NullSink)
        }
        "rock" => {
            let rock = common::scenes::RockScene::new();
            let draws = rock_scene::draws(rock.mesh());
            let camera = rock_scene::camera(width, height).expect("the camera");
            let scene = Scene::new(camera, &draws).light(common::light());
            let mut ws: Box<RockWorkspace> = Box::default();
            r.render(&mut ws, &scene, &mut NullSink)
        }
        other => panic!("no scene {other}"),
    };
    stats.expect("the host renders").to_string()
}

#[test]
fn rp2040_bench_renders_the_host_frames() {
    if !host::require(
        "rp2040_bench_renders_the_host_frames",
        &[host::NODE, RP2040JS, host::Need::Target(TARGET)],
    ) {
        return;
    }
    let elf = build_example("rp2040_bench");
    let started = Instant::now();
    let run = Command::new("node")
        .arg(root().join("tests/pico/run.mjs"))
        .arg(&elf)
        .arg("--bench")
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success(),
        "the benchmark failed:\n{stdout}\n{stderr}"
    );
    println!(
        "rp2040_bench in rp2040js ({:.1} s):\n{stdout}",
        started.elapsed().as_secs_f32()
    );
    // "SCENE WxH: N cycles (ROM stubs M); FrameStats"
    let mut seen = 0;
    for line in stdout.lines() {
        let Some((head, stats)) = line.split_once("); ") else {
            continue;
        };
        let (scene, rest) = head.split_once(' ').expect("scene and size");
        let size = rest.split(':').next().expect("a size");
        let (w, h) = size.split_once('x').expect("WxH");
        let (w, h) = (w.parse().expect("width"), h.parse().expect("height"));
        assert_eq!(
            stats,
            host_stats(scene, w, h),
            "{scene} {w}x{h}: the Pico's frame (left) is not the host's"
        );
        seen += 1;
    }
    assert_eq!(seen, 8, "2 frames of 2 scenes at 2 sizes:\n{stdout}");
}
