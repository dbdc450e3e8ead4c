//! The firmware: checks the board, calibrates the stamps, measures each
//! scene's frames and prints the tables.

mod timer;

use self::timer::{Stamps, END, PERIOD, START};
use crate::icount_scenes::{
    frame, renderer, BenchWorkspace, FrameError, FrameSink, Meshes, SceneId, HEIGHT, WIDTH,
};
use crate::stack_gauge;
use cortex_m::peripheral::SYST;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use microraster::{FrameStats, Profiler, Stage};
use panic_semihosting as _;
use static_cell::ConstStaticCell;

// About 33 KB, built in place and never moved through the stack; the
// 4 KB renderer lives on the stack of `measure`.
static WORKSPACE: ConstStaticCell<BenchWorkspace> = ConstStaticCell::new(BenchWorkspace::new());
static TEXELS: ConstStaticCell<[u16; 32 * 32]> = ConstStaticCell::new([0; 32 * 32]);
/// The shader scenes' texture in flash (see `icount_scenes::TEXTURE_IN_FLASH`).
static FLASH_TEXELS: [u16; 32 * 32] = crate::icount_scenes::CHECKER_TEXELS;

/// The board this build is for.
#[cfg(target_abi = "eabihf")]
const BOARD: (&str, &str, u32) = ("mps2-an386", "Cortex-M4F", 0xC24);
/// ARMv6-M code on the MPS2's M4F: what a Cortex-M0+ would execute.
#[cfg(all(not(target_abi = "eabihf"), microraster_board = "mps2-an386"))]
const BOARD: (&str, &str, u32) = ("mps2-an386", "ARMv6-M code on a Cortex-M4F", 0xC24);
#[cfg(not(any(target_abi = "eabihf", microraster_board = "mps2-an386")))]
const BOARD: (&str, &str, u32) = ("lm3s6965evb", "Cortex-M3", 0xC23);

const NOT_COUNTING: &str = "SysTick does not count";

/// Why the benchmark stopped.
enum Error {
    Setup(&'static str),
    Calibration {
        what: &'static str,
        expected: u32,
        measured: u32,
    },
    Scene(&'static str),
    Mesh(microraster::mesh::MeshError),
    Frame(&'static str, FrameError),
    Unrepeatable(&'static str),
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Setup(s) => write!(f, "{s}"),
            Self::Calibration {
                what,
                expected,
                measured,
            } => write!(
                f,
                "calibration failed: {what}: expected {expected} instructions, measured \
                 {measured} (is QEMU running with -icount shift=0?)"
            ),
            Self::Scene(s) => write!(f, "unknown scene {s:?} in MICRORASTER_ICOUNT_SCENES"),
            Self::Mesh(e) => write!(f, "a scene mesh is invalid: {e}"),
            Self::Frame(s, e) => write!(f, "scene {s}: {e}"),
            Self::Unrepeatable(s) => {
                write!(f, "scene {s}: two identical frames counted differently")
            }
        }
    }
}

/// A number with thousands separators.
struct Sep(u64);

impl core::fmt::Display for Sep {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mut groups = [0u16; 7];
        let (mut v, mut n) = (self.0, 0);
        loop {
            groups[n] = (v % 1000) as u16;
            n += 1;
            v /= 1000;
            if v == 0 {
                break;
            }
        }
        write!(f, "{}", groups[n - 1])?;
        for g in groups[..n - 1].iter().rev() {
            write!(f, ",{g:03}")?;
        }
        Ok(())
    }
}

/// `num / den` with `decimals` decimals, rounded.
struct Ratio(u64, u64, u32);

impl core::fmt::Display for Ratio {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let Ratio(num, den, decimals) = *self;
        if den == 0 {
            return write!(f, "-");
        }
        let scale = 10u64.pow(decimals);
        let v = (num * scale + den / 2) / den;
        if decimals == 0 {
            write!(f, "{}", Sep(v))
        } else {
            write!(
                f,
                "{}.{:0w$}",
                Sep(v / scale),
                v % scale,
                w = decimals as usize
            )
        }
    }
}

/// The profiler: a stamp at every stage entry.
struct Hooks<'a>(&'a mut Stamps);

impl Profiler for Hooks<'_> {
    #[inline(always)]
    fn enter(&mut self, stage: Stage) {
        timer::stamp(self.0, stage as u32);
    }
}

/// A calibration measurement: two stamps around known instructions.
type Measurement = fn(&mut Stamps) -> u32;

/// The stamp overhead, and the calibration's proof that stamps count
/// exactly.
fn calibrate(s: &mut Stamps, syst: &mut SYST) -> Result<u32, Error> {
    /// Measures `f` from `PERIOD` starting phases, that is with the
    /// first stamp starting at every distance from a SysTick edge
    /// (checked): every measurement must agree.
    fn phases(
        s: &mut Stamps,
        syst: &mut SYST,
        what: &'static str,
        f: Measurement,
    ) -> Result<u32, Error> {
        let mut first = None;
        let (mut kmask, mut seen) = (0, [0u32; 4]);
        for q in 0..PERIOD {
            if !timer::restart(syst) {
                return Err(Error::Setup(NOT_COUNTING));
            }
            timer::shift(q);
            let m = f(s);
            if !s.sane() {
                return Err(Error::Setup(
                    "a stamp did not find the SysTick edge where it must be (is QEMU \
                     running with -icount shift=0? is the tick period right?)",
                ));
            }
            kmask |= s.kmask;
            let p = s.phase[0].min(127);
            seen[(p / 32) as usize] |= 1 << (p % 32);
            match first {
                None => first = Some(m),
                Some(m0) if m0 != m => {
                    return Err(Error::Calibration {
                        what,
                        expected: m0,
                        measured: m,
                    })
                }
                _ => {}
            }
        }
        let distinct: u32 = seen.iter().map(|w| w.count_ones()).sum();
        if kmask != 0b1_1110 || distinct != PERIOD {
            return Err(Error::Setup(
                "the calibration did not meet every phase of the SysTick edge",
            ));
        }
        Ok(first.unwrap_or_default())
    }

    let overhead = phases(s, syst, "0 nops", timer::around_nops::<0>)?;
    let runs: [(u32, &'static str, Measurement); 9] = [
        (1, "1 nop", timer::around_nops::<1>),
        (2, "2 nops", timer::around_nops::<2>),
        (3, "3 nops", timer::around_nops::<3>),
        (4, "4 nops", timer::around_nops::<4>),
        (7, "7 nops", timer::around_nops::<7>),
        (41, "41 nops", timer::around_nops::<41>),
        (83, "83 nops", timer::around_nops::<83>),
        (256, "256 nops", timer::around_nops::<256>),
        (timer::LOOP_INSTRUCTIONS, "the loop", timer::around_loop),
    ];
    for (n, what, f) in runs {
        let m = phases(s, syst, what, f)?.wrapping_sub(overhead);
        if m != n {
            return Err(Error::Calibration {
                what,
                expected: n,
                measured: m,
            });
        }
    }
    Ok(overhead)
}

/// One measured frame.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Measured {
    /// Plain `render`, all-in.
    total: u32,
    /// With stage stamps: set-up (scene, matrices, checks, and the
    /// return after the last stage), vertex, binning, raster, sink.
    stages: [u32; 5],
    stats: FrameStats,
}

fn measure(
    scene: SceneId,
    meshes: &Meshes,
    ws: &mut BenchWorkspace,
    s: &mut Stamps,
    syst: &mut SYST,
    overhead: u32,
) -> Result<Measured, Error> {
    let mut r = renderer();
    // The name looked up once: looked up in the closure, the closure was
    // left out of line with the scenes' table of names (two scenes more,
    // `3e209da`), and `measure`'s frame, under every scene's render, took
    // 160 bytes more stack.
    let name = scene.name();
    let fail = |e| Error::Frame(name, e);
    let too_long = Error::Setup("a frame is longer than SysTick's 24 bits of ticks");

    // All-in, without stage stamps.
    if !timer::restart(syst) {
        return Err(Error::Setup(NOT_COUNTING));
    }
    s.reset();
    timer::stamp(s, START);
    let plain = frame(
        scene,
        meshes,
        &mut r,
        ws,
        &mut (),
        &mut FrameSink { hash: None },
    );
    timer::stamp(s, END);
    let stats = plain.map_err(fail)?;
    if timer::wrapped(syst) {
        return Err(too_long);
    }
    let total = s.charge[START as usize].wrapping_sub(overhead);
    if !s.sane() {
        return Err(Error::Setup("a stamp lost the SysTick edge"));
    }

    // The stages.
    if !timer::restart(syst) {
        return Err(Error::Setup(NOT_COUNTING));
    }
    s.reset();
    timer::stamp(s, START);
    let profiled = frame(
        scene,
        meshes,
        &mut r,
        ws,
        &mut Hooks(s),
        &mut FrameSink { hash: None },
    );
    timer::stamp(s, END);
    let stats2 = profiled.map_err(fail)?;
    if timer::wrapped(syst) {
        return Err(too_long);
    }
    if !s.sane() {
        return Err(Error::Setup("a stamp lost the SysTick edge"));
    }
    if stats2 != stats {
        return Err(Error::Unrepeatable(scene.name()));
    }
    let net = |tag: u32| {
        let t = tag as usize;
        s.charge[t].wrapping_sub(s.calls[t].wrapping_mul(overhead))
    };
    let stages = [
        net(START) + net(Stage::Done as u32),
        net(Stage::Vertex as u32),
        net(Stage::Binning as u32),
        net(Stage::Raster as u32),
        net(Stage::Sink as u32),
    ];
    Ok(Measured {
        total,
        stages,
        stats,
    })
}

/// The hash of `scene`'s image ([`FrameSink`]). Out of line, so that its
/// renderer (with its tile buffer) is on the stack only during the call,
/// not in `run`'s frame under every measured scene's.
#[inline(never)]
fn image_hash(scene: SceneId, meshes: &Meshes, ws: &mut BenchWorkspace) -> Result<u32, Error> {
    let mut sink = FrameSink::hashing();
    frame(scene, meshes, &mut renderer(), ws, &mut (), &mut sink)
        .map_err(|e| Error::Frame(scene.name(), e))?;
    Ok(sink.hash.unwrap_or(0))
}

fn run() -> Result<(), Error> {
    let mut cp =
        cortex_m::Peripherals::take().ok_or(Error::Setup("the core peripherals are taken"))?;
    let (board, core, part) = BOARD;
    let cpuid = cp.CPUID.base.read();
    if (cpuid >> 4) & 0xFFF != part {
        return Err(Error::Setup(
            "this build is for the other board (CPUID part number differs)",
        ));
    }
    hprintln!(
        "icount: {} ({} r{}p{}), {}x{} Rgb565, 32x32 tiles, a sink that discards each tile",
        board,
        core,
        (cpuid >> 20) & 0xF,
        cpuid & 0xF,
        WIDTH,
        HEIGHT
    );

    let syst = &mut cp.SYST;
    timer::start(syst);
    let mut stamps = Stamps::new();
    let s = &mut stamps;
    let overhead = calibrate(s, syst)?;
    hprintln!(
        "calibration: SysTick tick = {} instructions; a stamp costs {} (taken out); \
         runs of 0, 1, 2, 3, 4, 7, 41, 83, 256 nops and a {}-instruction loop, each \
         from {} starting phases, counted exactly",
        PERIOD,
        overhead,
        Sep(timer::LOOP_INSTRUCTIONS as u64),
        PERIOD
    );

    // The scenes named at build time, or all of them.
    let mut scenes = SceneId::ALL.map(Some);
    let list = crate::icount_scenes::SCENE_LIST;
    let mut names = list.split([' ', ',']).filter(|n| !n.is_empty()).peekable();
    if names.peek().is_some() {
        scenes = [None; SceneId::ALL.len()];
        for (slot, name) in scenes.iter_mut().zip(names) {
            *slot = Some(SceneId::from_name(name).ok_or(Error::Scene(name))?);
        }
    }

    // The shader scenes' texture, in RAM (2 KiB), only when one of them
    // is built in; or, built with `MICRORASTER_ICOUNT_TEXTURE_IN_FLASH`,
    // the same texels from flash.
    let texels: Option<&'static [u16]> = if crate::icount_scenes::SHADER_SCENES {
        let t = TEXELS.take();
        crate::icount_scenes::checker_texels(t);
        if crate::icount_scenes::TEXTURE_IN_FLASH {
            if *t != FLASH_TEXELS {
                return Err(Error::Setup(
                    "the texture in flash differs from the computed one",
                ));
            }
            hprintln!("texture: in flash");
            Some(&FLASH_TEXELS)
        } else {
            Some(t)
        }
    } else {
        None
    };
    let meshes = Meshes::new(texels).map_err(Error::Mesh)?;
    let ws = WORKSPACE.take();
    // The stack since boot (calibration, printing); then each scene's
    // own, painted afresh below this frame before it.
    let boot_stack = stack_gauge::peak();
    let mut results = [None; crate::icount_scenes::BUILT_SCENES];
    for (slot, scene) in results.iter_mut().zip(scenes.into_iter().flatten()) {
        stack_gauge::paint();
        let a = measure(scene, &meshes, ws, s, syst, overhead)?;
        let b = measure(scene, &meshes, ws, s, syst, overhead)?;
        if a != b {
            return Err(Error::Unrepeatable(scene.name()));
        }
        *slot = Some((scene, a, stack_gauge::peak()));
    }
    let results = results.iter().flatten();

    // Each scene once more, unmeasured, its image hashed: the host build
    // of `icount` prints the host's hashes, `scripts/icount.sh` compares.
    hprintln!();
    for (scene, _, _) in results.clone() {
        // In decimal, as the counts are printed (`{:08x}` linked
        // `core::fmt`'s hex formatting, flash that the M3's
        // `demo-textured-lit` build does not have).
        let hash = image_hash(*scene, &meshes, ws)?;
        hprintln!("image: {} {}", scene.name(), hash);
    }

    hprintln!();
    hprintln!(
        "| scene | instructions per frame | pixels shaded | per pixel | triangles | per triangle |"
    );
    hprintln!("|---|---:|---:|---:|---:|---:|");
    for (scene, m, _) in results.clone() {
        let (px, tris) = (m.stats.pixels_shaded as u64, m.stats.triangles_in as u64);
        hprintln!(
            "| `{}` | {} | {} | {} | {} | {} |",
            scene.name(),
            Sep(m.total as u64),
            Sep(px),
            Ratio(m.total as u64, px, 2),
            Sep(tris),
            Ratio(m.total as u64, tris, 0)
        );
    }
    hprintln!();
    hprintln!(
        "| scene | set-up | vertex | binning | raster + shade | sink | sum (profiled build) | minus plain |"
    );
    hprintln!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for (scene, m, _) in results.clone() {
        let sum = m.stages.iter().fold(0u32, |a, &b| a.wrapping_add(b));
        hprintln!(
            "| `{}` | {} | {} | {} | {} | {} | {} | {} |",
            scene.name(),
            Sep(m.stages[0] as u64),
            Sep(m.stages[1] as u64),
            Sep(m.stages[2] as u64),
            Sep(m.stages[3] as u64),
            Sep(m.stages[4] as u64),
            Sep(sum as u64),
            sum as i64 - m.total as i64
        );
    }
    hprintln!();
    // Painted RAM that a scene's frames wrote: from the top of RAM, so
    // `main`, `run` and the renderer on `measure`'s stack included.
    hprintln!("| scene | peak stack |");
    hprintln!("|---|---:|");
    let mut deepest = ("start-up and calibration", boot_stack);
    for &(scene, _, peak) in results.clone() {
        hprintln!("| `{}` | {} B |", scene.name(), Sep(peak as u64));
        if peak > deepest.1 {
            deepest = (scene.name(), peak);
        }
    }
    hprintln!(
        "peak stack: {} B ({}); start-up and calibration {} B; {} B painted below the top of RAM",
        Sep(deepest.1 as u64),
        deepest.0,
        Sep(boot_stack as u64),
        Sep(stack_gauge::room() as u64)
    );
    hprintln!();
    for (scene, m, _) in results {
        let st = &m.stats;
        hprintln!(
            "{}: {} triangles in, {} culled, {} rejected, {} clipped, {} drawn; {} tiles, {} bin passes, {} rescanned",
            scene.name(),
            st.triangles_in,
            st.culled,
            st.rejected,
            st.clipped,
            st.drawn,
            st.tiles,
            st.bin_passes,
            st.rescanned_tiles
        );
    }
    hprintln!(
        "every frame was measured twice, plain and profiled; both runs agree to the instruction"
    );
    Ok(())
}

#[entry]
fn main() -> ! {
    // All the free RAM under `main`: `run` reads how deep start-up and
    // calibration went, then repaints for each scene.
    crate::stack_gauge::paint();
    match run() {
        Ok(()) => {
            hprintln!("icount: done");
            debug::exit(debug::EXIT_SUCCESS);
        }
        Err(e) => {
            hprintln!("icount: error: {}", e);
            debug::exit(debug::EXIT_FAILURE);
        }
    }
    loop {
        cortex_m::asm::wfi();
    }
}
