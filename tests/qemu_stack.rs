//! The peak stack of the Pico 2 (RP2350) and ESP32-C3 firmwares' frame
//! code, measured on QEMU machines with their instruction sets: builds
//! `examples/stack_probe.rs` for `thumbv8m.main-none-eabihf` (run on
//! `qemu-system-arm -M mps2-an505`, a Cortex-M33 as the RP2350's) and for
//! `riscv32imc-unknown-none-elf` (run on `qemu-system-riscv32 -M virt`, the
//! ESP32-C3's instruction set), and requires of each that every frame
//! completes, that its wire bytes' checksum equals the host's render of
//! the same frame through the same code, and that the peak stack, painted
//! and read back, stays within the firmwares' budget. Run with `-icount
//! shift=0`, it also requires each frame's count of instructions, drawn
//! again with its tiles packed but not checksummed (the probe's readings
//! of RISC-V's `minstret`, exact, or of the Cortex-M33's SysTick, to a
//! tick). Prints the figures (`-- --nocapture`).
//!
//! The probe splits the peak at the call of `Frames::draw`: below it the
//! boards' own code, above it the probe's `main`. The depth at that call
//! is also read from the disassembly (`llvm-objdump`, from rustup's
//! `llvm-tools`): the frames (pushes and stack-pointer subtractions) of
//! the functions on the call chain from the entry point to the call. On
//! the probe it must equal the measured depth; given a board's ELF
//! (`MICRORASTER_RP2350_ELF`, `MICRORASTER_ESP32C3_ELF`; CI builds and
//! names them), the same reading of the board's chain plus the measured
//! depth below the call is the board's peak, which is printed and held to
//! the budget too.
//!
//! Without the emulator or the target the test is skipped with a line
//! saying how to install them, or fails in CI (`tests/support/host.rs`).

#[path = "../examples/stack_probe_firmware/panel.rs"]
mod panel;
#[path = "../examples/st7789_scene/mod.rs"]
mod st7789_scene;
mod support;

use panel::{ChecksumPanel, FRAME_TIMES, STACK_BUDGET};
use st7789_scene::{Frames, KnotData, PicoTile, PicoWorkspace};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use support::host;

/// The ARM probe's link: cortex-m-rt's `link.x` with the MPS2-AN505's map,
/// which build.rs puts on the examples' search path, and lld run from
/// `memory/` so that the root `memory.x` (the LM3S6965's) is not found
/// first (`scripts/lld-in-out-dir.sh`). Given here rather than in
/// `.cargo/config.toml`, where they would reach the Pico 2 board crate's
/// builds too.
const ARM_CONFIG: [&str; 2] = [
    r#"target.thumbv8m.main-none-eabihf.linker="scripts/lld-in-out-dir.sh""#,
    r#"target.thumbv8m.main-none-eabihf.rustflags=["-C","link-arg=-Tlink.x"]"#,
];

/// Builds the probe for `target` and returns its ELF.
fn build_probe(target: &str, config: &[&str]) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target_dir = root.join("target").join("stack-probe");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut command = Command::new(cargo);
    command
        .current_dir(root)
        .args([
            "build",
            "--release",
            "--example",
            "stack_probe",
            "--target",
            target,
        ])
        .env("CARGO_TARGET_DIR", &target_dir);
    for c in config {
        command.args(["--config", c]);
    }
    let status = command.status().expect("cargo runs");
    assert!(status.success(), "the probe builds for {target}");
    target_dir.join(target).join("release/examples/stack_probe")
}

/// Runs QEMU to its end (the probe exits through semihosting or the test
/// device) and returns its output; fails on a non-zero exit or a hang.
fn run(mut command: Command) -> String {
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("qemu starts");
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut out = String::new();
        let _ = stdout.read_to_string(&mut out);
        out
    });
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "the probe did not finish in 120 s: {}",
                reader.join().unwrap()
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let out = reader.join().unwrap();
    let mut err = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut err);
    assert!(
        status.success(),
        "the probe failed ({status:?}):\n{out}\n{err}"
    );
    out
}

/// The host's checksum of each frame of `FRAME_TIMES`, through the same
/// frame code and panel.
fn host_checksums() -> Vec<(u32, u32)> {
    let mut knot = Box::new(KnotData::new());
    let mut workspace: Box<PicoWorkspace> = Box::new(PicoWorkspace::new());
    let mut frames = Frames::new(&mut knot, &mut workspace).expect("the scene sets up");
    let clear = microraster::sink::Rgb565Be::new(0, 0, 0);
    let (mut a, mut b) = (
        Box::new(PicoTile::new(clear)),
        Box::new(PicoTile::new(clear)),
    );
    let mut tiles = [&mut *a, &mut *b];
    let mut panel = ChecksumPanel::new();
    let mut checksums = Vec::new();
    for &time in &FRAME_TIMES {
        let (back, result) = frames.draw(time, tiles, &mut panel);
        tiles = back;
        result.expect("the host draws the frame");
        checksums.push(panel.take());
    }
    checksums
}

/// The number after `prefix` in `line`.
fn number_after(line: &str, prefix: &str) -> usize {
    line.split(prefix)
        .nth(1)
        .and_then(|t| t.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no number after {prefix:?} in {line:?}"))
}

/// rustup's `llvm-objdump` (the `llvm-tools` component), if installed.
fn objdump() -> Option<PathBuf> {
    let out = Command::new(host::rustc())
        .args(["--print", "sysroot"])
        .output()
        .ok()?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    let lib = sysroot.join("lib/rustlib");
    std::fs::read_dir(&lib)
        .ok()?
        .filter_map(Result::ok)
        .map(|e| e.path().join("bin/llvm-objdump"))
        .find(|p| p.exists())
}

/// A function of a disassembly: its stack frame and its direct calls
/// (`true` for a tail call, which leaves the caller's frame).
struct Function {
    frame: usize,
    calls: Vec<(String, bool)>,
}

/// The instruction of a line of `llvm-objdump -d` (`  addr:   \top args`).
fn instruction(line: &str) -> Option<&str> {
    let (address, rest) = line.trim_start().split_once(':')?;
    (!address.is_empty() && address.chars().all(|c| c.is_ascii_hexdigit())).then(|| rest.trim())
}

/// The stack frame its prologue sets up, from its first instructions:
/// Arm's `push`/`vpush` and `sub sp`, RISC-V's `addi sp, sp, -n` and
/// `lui`/`addi`/`sub sp, sp, r` for large frames.
fn prologue_frame(lines: &[&str]) -> usize {
    let mut frame = 0;
    let mut upper = std::collections::HashMap::<String, i64>::new();
    let num = |t: &str| -> Option<i64> {
        let t = t.trim().trim_start_matches('#');
        let (neg, t) = t.strip_prefix('-').map_or((false, t), |t| (true, t));
        let v = match t.strip_prefix("0x") {
            Some(h) => i64::from_str_radix(h, 16).ok()?,
            None => t.parse().ok()?,
        };
        Some(if neg { -v } else { v })
    };
    let registers = |list: &str| -> usize {
        list.split(',')
            .map(|r| match r.trim().split_once('-') {
                Some((a, b)) => {
                    let n = |r: &str| r.trim()[1..].parse::<usize>().unwrap_or(0);
                    n(b) - n(a) + 1
                }
                None => 1,
            })
            .sum()
    };
    for line in lines.iter().take(40) {
        let Some(ins) = instruction(line) else {
            continue;
        };
        let mut parts = ins.trim().splitn(2, char::is_whitespace);
        let (op, args) = (
            parts.next().unwrap_or(""),
            parts.next().unwrap_or("").trim(),
        );
        let args: Vec<&str> = args.split(", ").collect();
        match op {
            "push" | "push.w" => {
                frame += 4 * registers(args.join(",").trim_matches(|c| c == '{' || c == '}'))
            }
            "vpush" => {
                frame += 8 * registers(args.join(",").trim_matches(|c| c == '{' || c == '}'))
            }
            "sub" | "subw" | "sub.w" if args[0] == "sp" => {
                if let Some(v) = args
                    .last()
                    .filter(|a| a.starts_with('#'))
                    .and_then(|a| num(a))
                {
                    frame += v as usize;
                } else if let Some(v) = args.last().and_then(|r| upper.get(*r)) {
                    frame += *v as usize;
                }
            }
            "addi" if args.len() == 3 && args[0] == "sp" && args[1] == "sp" => {
                if let Some(v) = num(args[2]).filter(|v| *v < 0) {
                    frame += (-v) as usize;
                }
            }
            "lui" if args.len() == 2 => {
                if let Some(v) = num(args[1]) {
                    upper.insert(args[0].into(), v << 12);
                }
            }
            "addi" if args.len() == 3 && upper.contains_key(args[1]) => {
                if let Some(v) = num(args[2]) {
                    let base = upper[args[1]];
                    upper.insert(args[0].into(), base + v);
                }
            }
            _ => {}
        }
    }
    frame
}

/// The functions of `elf`, by name, from `llvm-objdump -d`.
fn functions(objdump: &Path, elf: &Path) -> std::collections::HashMap<String, Function> {
    let out = Command::new(objdump)
        .args(["-d", "-C", "--no-show-raw-insn"])
        .arg(elf)
        .output()
        .expect("llvm-objdump runs");
    assert!(out.status.success(), "llvm-objdump {}", elf.display());
    let text = String::from_utf8_lossy(&out.stdout);
    let mut functions = std::collections::HashMap::new();
    let mut name: Option<String> = None;
    let mut body: Vec<&str> = Vec::new();
    let mut finish = |name: Option<String>, body: &[&str]| {
        let Some(name) = name else { return };
        let calls = body
            .iter()
            .filter_map(|l| {
                let ins = instruction(l)?;
                let op = ins.split_whitespace().next()?;
                let tail = matches!(op, "b" | "b.w" | "j" | "jr" | "tail");
                let call = matches!(op, "bl" | "blx" | "jal" | "jalr" | "call");
                let target = ins.split_once('<')?.1.split(['>', '+']).next()?;
                (tail || call).then(|| (target.to_string(), tail))
            })
            .filter(|(target, _)| *target != name)
            .collect();
        let frame = prologue_frame(body);
        functions.insert(name, Function { frame, calls });
    };
    for line in text.lines() {
        if let Some(label) = line.strip_suffix(">:").and_then(|l| l.split_once(" <")) {
            finish(name.take(), &body);
            body.clear();
            name = Some(label.1.to_string());
        } else if name.is_some() && instruction(line).is_some() {
            body.push(line);
        }
    }
    finish(name, &body);
    functions
}

/// Whether `name` is the boards' frame function.
fn is_draw(name: &str) -> bool {
    name.contains("st7789_scene::Frames::draw")
}

/// What `elf`'s disassembly says of the stack around `Frames::draw`: the
/// depth at its call (the deepest chain of direct calls from `entry` to
/// it, each caller's frame counted), and the deepest its own chains of
/// direct calls go below that (indirect calls not followed).
fn draw_depths(objdump: &Path, elf: &Path, entry: &str) -> (usize, usize) {
    type Functions = std::collections::HashMap<String, Function>;
    let functions = functions(objdump, elf);
    fn to_draw(
        functions: &Functions,
        name: &str,
        depth: usize,
        path: &mut Vec<String>,
    ) -> Option<usize> {
        if is_draw(name) {
            return Some(depth);
        }
        let function = functions.get(name)?;
        if path.len() > 8 || path.iter().any(|p| p == name) {
            return None;
        }
        path.push(name.to_string());
        let found = function
            .calls
            .iter()
            .filter_map(|(callee, tail)| {
                let below = if *tail { depth } else { depth + function.frame };
                to_draw(functions, callee, below, path)
            })
            .max();
        path.pop();
        found
    }
    fn deepest(functions: &Functions, name: &str, path: &mut Vec<String>) -> usize {
        let Some(function) = functions.get(name) else {
            return 0;
        };
        if path.iter().any(|p| p == name) {
            return 0;
        }
        path.push(name.to_string());
        let below = function
            .calls
            .iter()
            .map(|(callee, tail)| {
                let d = deepest(functions, callee, path);
                if *tail {
                    d.saturating_sub(function.frame)
                } else {
                    d
                }
            })
            .max()
            .unwrap_or(0);
        path.pop();
        function.frame + below
    }
    let at = to_draw(&functions, entry, 0, &mut Vec::new()).unwrap_or_else(|| {
        panic!(
            "no call chain from {entry} to Frames::draw in {}",
            elf.display()
        )
    });
    let draw = functions
        .keys()
        .find(|name| is_draw(name))
        .expect("Frames::draw is in the ELF");
    (at, deepest(&functions, draw, &mut Vec::new()))
}

/// The probe's frames' peak stack, split at the call of `Frames::draw`.
struct Report {
    above: usize,
    below: usize,
}

/// Checks the probe's report against the host and the budget, prints its
/// figures, and returns them.
fn check(name: &str, out: &str) -> Report {
    let host = host_checksums();
    let frames: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("stack_probe: frame ") && l.contains(" at "))
        .collect();
    assert_eq!(
        frames.len(),
        FRAME_TIMES.len(),
        "every frame reported:\n{out}"
    );
    for (i, (line, (checksum, tiles))) in frames.iter().zip(&host).enumerate() {
        let expected = format!(
            "frame {i} at {} us: checksum {checksum:#010x}, {tiles} tiles,",
            FRAME_TIMES[i]
        );
        assert!(
            line.contains(&expected),
            "{name}: frame {i} differs from the host's ({expected}):\n{line}"
        );
    }
    let start_up = out
        .lines()
        .find(|l| l.contains("start-up peak stack"))
        .unwrap_or_else(|| panic!("no start-up peak:\n{out}"));
    let peak_line = out
        .lines()
        .find(|l| l.contains("frames peak stack"))
        .unwrap_or_else(|| panic!("no frames' peak:\n{out}"));
    let start_up = number_after(start_up, "peak stack ");
    let peak = number_after(peak_line, "peak stack ");
    let room = number_after(peak_line, " B of ");
    let above = number_after(peak_line, "; ");
    let below = number_after(peak_line, "draw, ");
    for line in out.lines() {
        println!("{name}: {line}");
    }
    // The frames went deep into the renderer (a tile's set-up and span
    // loops), and neither the start-up nor the frames reached the end of
    // the painted window or the budget.
    assert!(
        below > 4096,
        "{name}: implausibly shallow frame code: {peak_line}"
    );
    for (what, bytes) in [("start-up", start_up), ("frames", peak)] {
        assert!(
            bytes < room && bytes <= STACK_BUDGET,
            "{name}: the {what}' peak stack, {bytes} B, is over the budget of {STACK_BUDGET} B \
             (or the painted {room} B)"
        );
    }
    Report { above, below }
}

/// Requires a count of instructions for each frame, and a plausible one:
/// a 240x240 frame of about 2,000 triangles takes millions, and none a
/// billion.
fn counted(name: &str, out: &str) {
    let counts: Vec<usize> = out
        .lines()
        .filter(|l| l.contains("its tiles packed but not checksummed"))
        // "stack_probe: frame I: N instructions (counted to ...), ..."
        .filter_map(|l| l.split(": ").nth(2)?.split(' ').next()?.parse().ok())
        .collect();
    assert_eq!(
        counts.len(),
        FRAME_TIMES.len(),
        "{name}: a count a frame:\n{out}"
    );
    for c in counts {
        assert!(
            (1_000_000..1_000_000_000).contains(&c),
            "{name}: implausible count of a frame's instructions, {c}:\n{out}"
        );
    }
}

/// Reads the depth at the call of `Frames::draw` from the probe's
/// disassembly, which must equal the measured one, and from the board's
/// ELF named by `board_var` if set: the board's peak is that depth plus
/// the measured depth below the call.
fn static_depths(name: &str, report: &Report, probe: &Path, entry: &str, board: (&str, &str)) {
    let Some(objdump) = objdump() else {
        println!(
            "{name}: llvm-objdump not found (rustup component add llvm-tools): \
             no depth read from the disassembly"
        );
        return;
    };
    let (probe_at, probe_below) = draw_depths(&objdump, probe, entry);
    assert_eq!(
        probe_at, report.above,
        "{name}: the disassembly's depth at the call of Frames::draw is not the measured one"
    );
    let (board_var, board_entry) = board;
    let Some(elf) = std::env::var_os(board_var) else {
        println!("{name}: {board_var} not set: no board figure (CI sets it)");
        return;
    };
    let elf = PathBuf::from(elf);
    let (at, below) = draw_depths(&objdump, &elf, board_entry);
    // Below the call, the board's code differs from the probe's only in
    // the transfer (its panel, the SPI and DMA drivers): if the
    // disassembly has the board's direct calls go deeper than the
    // probe's, the difference is added.
    let extra = below.saturating_sub(probe_below);
    let peak = at + report.below + extra;
    println!(
        "{name}: board {}: {at} B at the call of Frames::draw (its disassembly) + {} B below \
         it (measured) + {extra} B for deeper calls below it (disassemblies: the board's go \
         {below} B deep, the probe's {probe_below} B) = peak stack {peak} B",
        elf.display(),
        report.below
    );
    assert!(
        peak <= STACK_BUDGET,
        "{name}: the board's peak stack, {peak} B, is over the budget of {STACK_BUDGET} B"
    );
}

#[test]
fn pico2_frame_code_on_qemu_cortex_m33_stack_within_budget() {
    let target = "thumbv8m.main-none-eabihf";
    if !host::require(
        "qemu_stack (Cortex-M33)",
        &[host::QEMU_ARM, host::Need::Target(target)],
    ) {
        return;
    }
    let elf = build_probe(target, &ARM_CONFIG);
    // `-icount shift=0`: SysTick then counts instructions, by which the
    // probe reports each frame's.
    let mut qemu = Command::new("qemu-system-arm");
    qemu.args([
        "-icount",
        "shift=0",
        "-M",
        "mps2-an505",
        "-display",
        "none",
        "-serial",
        "none",
        "-monitor",
        "none",
    ])
    .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
    .arg(&elf);
    // cortex-m-rt's Reset calls `main` from the top of the stack, pushing
    // nothing.
    measure(
        "qemu_stack mps2-an505 (Cortex-M33)",
        qemu,
        &elf,
        "main",
        ("MICRORASTER_RP2350_ELF", "main"),
    );
}

#[test]
fn esp32c3_frame_code_on_qemu_riscv32_stack_within_budget() {
    let target = "riscv32imc-unknown-none-elf";
    if !host::require(
        "qemu_stack (RISC-V)",
        &[host::QEMU_RISCV32, host::Need::Target(target)],
    ) {
        return;
    }
    let elf = build_probe(target, &[]);
    let mut qemu = Command::new("qemu-system-riscv32");
    // `-icount shift=0`: QEMU's `minstret` then counts exactly the
    // instructions executed, which the probe reports per frame.
    qemu.args([
        "-M", "virt", "-bios", "none", "-display", "none", "-serial", "stdio",
    ])
    .args(["-icount", "shift=0", "-monitor", "none", "-kernel"])
    .arg(&elf);
    // The probe's `_start` and esp-riscv-rt's set the stack pointer and
    // call these, pushing nothing.
    measure(
        "qemu_stack virt (RV32IMC)",
        qemu,
        &elf,
        "probe_main",
        ("MICRORASTER_ESP32C3_ELF", "_start_rust"),
    );
}

/// Runs the probe `elf` under `qemu` and holds it to everything above:
/// each frame's checksum the host's and its stack within the budget
/// ([`check`]), a count for every frame ([`counted`]), and the probe's
/// and the board's depths at the call of `Frames::draw`, read from their
/// disassemblies from `entry` and from the board's (`board`: the
/// variable naming its ELF, and its entry), within the budget too
/// ([`static_depths`]).
fn measure(name: &str, qemu: Command, elf: &Path, entry: &str, board: (&str, &str)) {
    let out = run(qemu);
    let report = check(name, &out);
    counted(name, &out);
    static_depths(name, &report, elf, entry, board);
}
