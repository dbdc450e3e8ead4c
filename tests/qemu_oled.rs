//! End to end on the emulated board: builds the LM3S6965EVB firmware, boots
//! it in `qemu-system-arm -M lm3s6965evb`, lets it render one frame onto the
//! SSD0323 OLED over SPI, takes the panel's picture through the QEMU monitor
//! (`screendump`) and requires it to equal, pixel for pixel, the same scene
//! rendered on the host in Gray4. Fixed point makes the two agree.
//!
//! Without `qemu-system-arm` or the `thumbv7m-none-eabi` target the test
//! is skipped with a line saying how to install them, or fails in CI
//! (`tests/support/host.rs`).

#[path = "../examples/oled_scene/mod.rs"]
mod oled_scene;
mod support;

use support::host;

use embedded_graphics::pixelcolor::{Gray4, GrayColor};
use microraster::prelude::*;
use oled_scene::*;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Builds the firmware so that it stops after one frame, with the `size`
/// profile it is flashed with (README): the pixels must not depend on how
/// the code was optimised.
fn build_firmware() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target_dir = root.join("target").join("qemu-e2e");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root)
        .args([
            "build",
            "--profile",
            "size",
            "--example",
            "lm3s6965_oled",
            "--target",
            "thumbv7m-none-eabi",
        ])
        .args(if cfg!(feature = "assets") {
            &["--features", "assets"][..]
        } else {
            &[]
        })
        .env("CARGO_TARGET_DIR", &target_dir)
        .env("MICRORASTER_OLED_FRAMES", "1")
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the firmware builds");
    target_dir.join("thumbv7m-none-eabi/size/examples/lm3s6965_oled")
}

/// Sends one monitor command and reads until the next prompt.
fn monitor(sock: &mut UnixStream, cmd: &str) -> String {
    sock.write_all(cmd.as_bytes()).unwrap();
    sock.write_all(b"\n").unwrap();
    read_until_prompt(sock)
}

fn read_until_prompt(sock: &mut UnixStream) -> String {
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    let deadline = Instant::now() + Duration::from_secs(30);
    while !String::from_utf8_lossy(&out).ends_with("(qemu) ") {
        assert!(Instant::now() < deadline, "no monitor prompt");
        let n = sock.read(&mut buf).expect("monitor readable");
        assert!(n > 0, "monitor closed");
        out.extend_from_slice(&buf[..n]);
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The panel's 128x64 grey levels from QEMU's 4x magnified P6 dump, where
/// level `v` is shown as grey `(v << 4) | v`.
fn panel_from_ppm(data: &[u8]) -> Vec<u8> {
    let mut fields = Vec::new();
    let mut pos = 0;
    while fields.len() < 4 {
        while data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while !data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        fields.push(String::from_utf8_lossy(&data[start..pos]).into_owned());
    }
    pos += 1;
    assert_eq!(fields[0], "P6");
    let (w, h): (usize, usize) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    assert_eq!(
        (w, h),
        (WIDTH as usize * 4, HEIGHT as usize * 4),
        "magnified 4x"
    );
    let px = &data[pos..];
    assert_eq!(px.len(), w * h * 3);
    let mut out = Vec::with_capacity((WIDTH * HEIGHT) as usize);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            let i = ((y * 4) * w + x * 4) * 3;
            let (r, g, b) = (px[i], px[i + 1], px[i + 2]);
            assert!(
                r == g && g == b && r >> 4 == r & 15,
                "not an OLED grey: {r} {g} {b}"
            );
            // The whole 4x4 block shows the same level.
            for dy in 0..4 {
                for dx in 0..4 {
                    let j = ((y * 4 + dy) * w + x * 4 + dx) * 3;
                    assert_eq!(px[j], r, "block at ({x}, {y}) is not uniform");
                }
            }
            out.push(r & 15);
        }
    }
    out
}

fn host_frame() -> Vec<u8> {
    // The firmware's scene: the imported rocket with `--features assets`,
    // the knot otherwise.
    #[cfg(feature = "assets")]
    let (meshes, cam) = (rocket::meshes(), rocket::camera());
    #[cfg(feature = "assets")]
    let draws = rocket::draws(&meshes, 0);
    #[cfg(not(feature = "assets"))]
    let mut knot = Box::new(KnotData::new());
    #[cfg(not(feature = "assets"))]
    knot.generate();
    #[cfg(not(feature = "assets"))]
    let mesh = knot.mesh();
    #[cfg(not(feature = "assets"))]
    let (draws, cam) = ([draw(&mesh, 0)], camera());
    let scene = Scene::new(cam, &draws).light(light());
    let mut renderer = OledRenderer::new(config());
    let mut ws: Box<OledWorkspace> = Box::new(OledWorkspace::new());
    let mut cap = support::Capture::new(Size::new(WIDTH, HEIGHT), Gray4::new(0));
    let stats = renderer.render(&mut ws, &scene, &mut cap).unwrap();
    assert!(stats.pixels_shaded > 1000, "{stats:?}");
    cap.pixels.iter().map(|c| c.luma()).collect()
}

#[test]
fn oled_firmware_in_qemu_matches_host_render() {
    let needs = [host::QEMU_ARM, host::Need::Target("thumbv7m-none-eabi")];
    if !host::require("qemu_oled", &needs) {
        return;
    }
    let elf = build_firmware();
    let dir = std::env::temp_dir().join(format!("microraster-qemu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sock_path = dir.join("monitor.sock");
    let ppm_path = dir.join("oled.ppm");

    let mut qemu = Command::new("qemu-system-arm")
        .args(["-M", "lm3s6965evb", "-display", "none", "-serial", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .arg("-monitor")
        .arg(format!("unix:{},server,nowait", sock_path.display()))
        .arg("-kernel")
        .arg(&elf)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("qemu starts");

    // Wait for the firmware's "done" (after its one frame).
    let stdout = qemu.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let mut log = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(line) => {
                let done = line == "done";
                log.push(line);
                if done {
                    break;
                }
            }
            Err(_) => {
                let _ = qemu.kill();
                panic!("the firmware did not finish its frame; it printed {log:?}");
            }
        }
    }

    let mut sock = UnixStream::connect(&sock_path).expect("monitor socket");
    read_until_prompt(&mut sock);
    let reply = monitor(&mut sock, &format!("screendump {}", ppm_path.display()));
    assert!(!reply.contains("rror"), "screendump failed: {reply}");
    let _ = sock.write_all(b"quit\n");
    let status = qemu.wait().unwrap();
    let mut stderr = String::new();
    qemu.stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    assert!(
        !stderr.contains("ssd0323: error"),
        "the OLED rejected a command:\n{stderr}"
    );
    assert!(
        status.success() || status.code().is_some(),
        "qemu ended: {status:?}"
    );
    let frame0 = log
        .iter()
        .find(|l| l.starts_with("frame 0:"))
        .unwrap_or_else(|| panic!("the firmware reported its frame: {log:?}"));
    // "...; peak stack N B of M B free": painted and measured on the board
    // (examples/stack_gauge/mod.rs). It must have seen the renderer's frames
    // and must not have run into the statics.
    let stack: Vec<u64> = frame0
        .rsplit("; peak stack ")
        .next()
        .into_iter()
        .flat_map(|t| t.split(' ').filter_map(|w| w.parse().ok()))
        .collect();
    println!("qemu_oled: {frame0}");
    assert!(
        matches!(stack[..], [peak, free] if peak > 1024 && peak < free),
        "implausible peak stack: {frame0}"
    );

    let panel = panel_from_ppm(&std::fs::read(&ppm_path).expect("screendump wrote the file"));
    let host = host_frame();
    let diff = panel.iter().zip(&host).filter(|(a, b)| a != b).count();
    let to_rgb = |v: &[u8]| -> Vec<embedded_graphics::pixelcolor::Rgb888> {
        v.iter()
            .map(|&l| embedded_graphics::pixelcolor::Rgb888::new(l * 17, l * 17, l * 17))
            .collect()
    };
    // The emulated panel's picture, for people to look at; the README
    // shows it (the knot, and with `--features assets` the imported
    // rocket), so it must be the current one.
    let name = if cfg!(feature = "assets") {
        "oled_panel_rocket.png"
    } else {
        "oled_panel.png"
    };
    let shots = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/qemu-e2e");
    support::write_png(&shots.join(name), Size::new(WIDTH, HEIGHT), &to_rgb(&panel));
    let docs = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(name);
    let readme = support::read_png(&docs).unwrap_or_else(|| panic!("docs/{name} exists"));
    if diff == 0 {
        assert!(
            readme.1 == to_rgb(&panel),
            "docs/{name} is stale: copy target/qemu-e2e/{name} over it"
        );
    }
    if diff != 0 {
        let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/golden-diff");
        support::write_png(
            &out.join("qemu_oled.panel.png"),
            Size::new(WIDTH, HEIGHT),
            &to_rgb(&panel),
        );
        support::write_png(
            &out.join("qemu_oled.host.png"),
            Size::new(WIDTH, HEIGHT),
            &to_rgb(&host),
        );
    }
    assert_eq!(
        diff, 0,
        "{diff} pixels differ between the emulated OLED and the host render"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
