//! The stack probe's firmware, whatever the core: sets the Pico firmwares'
//! scene up as the boards do, draws `panel::FRAME_TIMES` through the boards' own
//! frame code (`st7789_scene::Frames::draw`) into a [`ChecksumPanel`], and
//! prints each frame's checksum and the peak stack. The core's runtime
//! (`arm.rs`, `riscv.rs`) provides the entry, the output and the exit.

use core::fmt::Write;
use core::ptr::addr_of_mut;

use crate::rt;
use crate::st7789_scene::{Frames, KnotData, PicoTile, PicoWorkspace};
use crate::stack_gauge;
use microraster::sink::Rgb565Be;

pub mod panel;
use panel::{ChecksumPanel, FRAME_TIMES, STACK_BUDGET};

/// The turns of the loop each runtime times before it counts anything
/// (`rt::start_counting`): a decrement and a branch a turn, in its
/// instruction set's own assembly, so 200,000 instructions in all.
pub const CALIBRATION_TURNS: u32 = 100_000;

// In RAM (.bss), as on the boards: the knot's mesh, the workspace, the two
// tile buffers (all zeros, `TileBuffer::new_nearest`: never built on the
// stack). Reached once each, from `run`, through `addr_of_mut!`.
static mut KNOT: KnotData = KnotData::new();
static mut WORKSPACE: PicoWorkspace = PicoWorkspace::new();
static mut TILES: [PicoTile; 2] = [
    PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)),
    PicoTile::new_nearest(Rgb565Be::new(0, 0, 0)),
];

/// The probe. `paint` has painted the stack before; everything after that
/// counts: start-up as on the boards, then the frames.
pub fn run() -> ! {
    let mut out = rt::Out;
    // SAFETY: `run` is entered once, and these are its only references to
    // the statics, so each is exclusive.
    let (knot, workspace, slots) = unsafe {
        (
            &mut *addr_of_mut!(KNOT),
            &mut *addr_of_mut!(WORKSPACE),
            &mut *addr_of_mut!(TILES),
        )
    };
    let Some(mut frames) = Frames::new(knot, workspace) else {
        let _ = writeln!(out, "stack_probe: the scene did not set up");
        rt::exit(false)
    };
    let mut tiles = slots.each_mut();
    let start_up = stack_gauge::peak();
    let room = stack_gauge::room();
    let _ = writeln!(
        out,
        "stack_probe: start-up peak stack {start_up} B of {room} B"
    );

    // The frames alone: painted again, from here.
    stack_gauge::paint();
    let mut panel = ChecksumPanel::new();
    // Where the core counts its instructions (RISC-V's `minstret`, the
    // Cortex-M33's SysTick, under `-icount`), each frame is drawn once more
    // into a panel that packs its tiles and does nothing else, and counted.
    let mut packing = ChecksumPanel::packing_only();
    let mut ok = true;
    let mut at_draw = 0;
    for (i, &time) in FRAME_TIMES.iter().enumerate() {
        at_draw = stack_gauge::depth();
        let (back, result) = frames.draw(time, tiles, &mut panel);
        tiles = back;
        let (checksum, count) = panel.take();
        match result {
            Ok(stats) => {
                let _ = writeln!(
                    out,
                    "stack_probe: frame {i} at {time} us: checksum {checksum:#010x}, {count} tiles, \
                     {} triangles drawn, {} pixels shaded, {} binning passes",
                    stats.drawn, stats.pixels_shaded, stats.bin_passes
                );
                let before = rt::instructions();
                let (back, again) = frames.draw(time, tiles, &mut packing);
                let after = rt::instructions();
                tiles = back;
                if let (Some(before), Some(after), Ok(_)) = (before, after, again) {
                    let _ = writeln!(
                        out,
                        "stack_probe: frame {i}: {} instructions ({}), its tiles packed but \
                         not checksummed",
                        after.wrapping_sub(before),
                        Resolution(rt::resolution())
                    );
                }
            }
            Err(e) => {
                let _ = writeln!(out, "stack_probe: frame {i} failed: {e:?}");
                ok = false;
            }
        }
    }
    let peak = stack_gauge::peak();
    let _ = writeln!(
        out,
        "stack_probe: frames peak stack {peak} B of {room} B; {at_draw} B above the call of \
         Frames::draw, {} B below it",
        peak.saturating_sub(at_draw)
    );
    if start_up.max(peak) > STACK_BUDGET {
        let _ = writeln!(out, "stack_probe: over the budget of {STACK_BUDGET} B");
        ok = false;
    }
    rt::exit(ok)
}

/// How exactly a count of instructions is known: to the instruction, or
/// to within that many.
struct Resolution(u32);

impl core::fmt::Display for Resolution {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.0 {
            1 => write!(f, "exact"),
            n => write!(f, "to within {n}"),
        }
    }
}
