//! Benchmark firmware for the Raspberry Pi Pico (RP2040) in rp2040js: the
//! cycles of a frame of the benchmark scenes, rendered alone (into a
//! `NullSink`, nothing sent), for the emulator's harness to time.
//!
//! ```text
//! cargo build --release --example rp2040_bench --target thumbv6m-none-eabi
//! node tests/pico/run.mjs target/thumbv6m-none-eabi/release/examples/rp2040_bench --bench
//! ```
//!
//! The scenes are those of the host's `examples/count.rs` and of the QEMU
//! instruction counts (`examples/icount_scenes`), with the same meshes,
//! camera, light and renderer settings (`Renderer<Rgb565, 32, 32>`,
//! back-face culling, `LessEqual` with depth writes, the scanline
//! rasterizer) and the host's workspaces:
//!
//! * `demo`: frame 0 of the demo (`examples/demo_scene`: the 4,000-triangle
//!   torus knot, evaluated by the compiler into flash, and the cube, lit,
//!   Gouraud), `Workspace<2048, 4096, 80>`;
//! * `rock`: the 3,920-triangle displaced geodesic sphere
//!   (`examples/rock_scene`, in flash), lit, Gouraud,
//!   `Workspace<2048, 6144, 80>`.
//!
//! Each at 240x240 (the Pico example's panel) and 320x240, [`FRAMES`]
//! frames in a row. A frame is what `count::frame` measures on the host:
//! the scene's set-up (draws, camera, matrices) and the render.
//!
//! Frame boundaries are `bkpt` instructions with immediates of their own,
//! which the harness (`tests/pico/run.mjs --bench`) takes when they are
//! executed from flash (its stub ROM's traps are in the ROM): `bkpt
//! #0x60` before a frame (r0 = scene, r1 = width, r2 = height), `bkpt
//! #0x61` after it, then `bkpt #0x62` with r0 = the address of the frame's
//! [`FrameStats`] as 16 words (in the order `FrameStats` prints them);
//! `bkpt #0x6f` when every frame is done and `bkpt #0x6e` (r0 = a code) on
//! a failure. The harness
//! charges the cycles between the two marks to the frame; the marks are
//! firmware for the emulator only (a Pico without a debugger would take a
//! HardFault at the first one).
//!
//! On a host build this file is only a stub that says how to run it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "rp2040_bench is firmware for rp2040js: cargo build --release --example rp2040_bench \
         --target thumbv6m-none-eabi, then node tests/pico/run.mjs \
         target/thumbv6m-none-eabi/release/examples/rp2040_bench --bench"
    );
}

#[cfg(target_os = "none")]
mod demo_scene;
#[cfg(target_os = "none")]
mod rock_scene;

#[cfg(target_os = "none")]
mod firmware {
    use crate::{demo_scene, rock_scene};
    use core::arch::asm;
    use embedded_graphics::pixelcolor::Rgb565;
    use microraster::prelude::*;
    use microraster::shapes::{
        torus_knot_data, torus_knot_size, MeshData, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
    };
    use panic_halt as _;
    use rp2040_hal::clocks::init_clocks_and_plls;
    use rp2040_hal::{pac, Watchdog};
    use static_cell::ConstStaticCell;

    /// The second-stage bootloader (see `examples/rp2040_st7789.rs`).
    #[link_section = ".boot2"]
    #[used]
    static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

    /// The Pico's crystal.
    const XTAL_HZ: u32 = 12_000_000;

    /// Frames rendered per scene and size.
    pub const FRAMES: u32 = 2;

    /// The frame sizes: the Pico example's 240x240 panel, and 320x240.
    const SIZES: [(u32, u32); 2] = [(240, 240), (320, 240)];

    /// The scenes, by the number the harness gets in r0.
    #[derive(Clone, Copy)]
    enum SceneId {
        Demo = 0,
        Rock = 1,
    }

    /// Failure codes (r0 of `bkpt #0x6e`).
    #[derive(Clone, Copy)]
    enum Fail {
        Clocks = 1,
        Mesh = 2,
        Camera = 3,
        Render = 4,
    }

    const KNOT_VERTICES: usize =
        torus_knot_size(demo_scene::KNOT_SEGMENTS, demo_scene::KNOT_SIDES).0;
    const KNOT_TRIANGLES: usize =
        torus_knot_size(demo_scene::KNOT_SEGMENTS, demo_scene::KNOT_SIDES).1;

    /// The demo's torus knot, evaluated by the compiler into flash, as the
    /// QEMU firmware's (`examples/icount_scenes`).
    static KNOT: MeshData<KNOT_VERTICES, KNOT_TRIANGLES> = match torus_knot_data(
        demo_scene::KNOT_P,
        demo_scene::KNOT_Q,
        demo_scene::KNOT_RADIUS,
        demo_scene::KNOT_TUBE,
        demo_scene::KNOT_SEGMENTS,
        demo_scene::KNOT_SIDES,
    ) {
        Ok(m) => m,
        Err(_) => panic!("the demo knot's parameters are valid"),
    };

    /// The rock, evaluated by the compiler into flash (70,608 bytes).
    static ROCK: rock_scene::RockData = rock_scene::rock_data();

    /// The host's workspaces (`examples/common/scenes`), built in place.
    type DemoWorkspace = Workspace<2048, 4096, 80>;
    type RockWorkspace = Workspace<2048, 6144, 80>;
    static DEMO_WS: ConstStaticCell<DemoWorkspace> = ConstStaticCell::new(DemoWorkspace::new());
    static ROCK_WS: ConstStaticCell<RockWorkspace> = ConstStaticCell::new(RockWorkspace::new());

    type BenchRenderer = Renderer<Rgb565, 32, 32>;

    /// Tells the harness that a frame of `scene` at `width` x `height`
    /// starts.
    #[inline(always)]
    fn mark_start(scene: SceneId, width: u32, height: u32) {
        // SAFETY: a breakpoint that the harness handles and returns from;
        // no memory or register is changed.
        unsafe {
            asm!("bkpt #0x60", in("r0") scene as u32, in("r1") width, in("r2") height,
                 options(nomem, nostack, preserves_flags));
        }
    }

    /// Tells the harness that the frame ended.
    #[inline(always)]
    fn mark_end() {
        // SAFETY: as above.
        unsafe {
            asm!("bkpt #0x61", options(nomem, nostack, preserves_flags));
        }
    }

    /// Gives the harness the frame's statistics.
    #[inline(always)]
    fn report(stats: &FrameStats) {
        // examples/demo.rs and tests/support list these fields too, as a
        // printed row and a comparison key: other subsets, not one list.
        let s = stats;
        let words: [u32; 16] = [
            s.triangles_in,
            s.culled,
            s.rejected,
            s.clipped,
            s.drawn,
            s.pixels_shaded,
            s.tiles,
            s.bin_passes,
            s.rescanned_tiles,
            s.draws_culled,
            s.clusters_culled,
            s.vertices,
            s.vertex_slots,
            s.tile_pairs,
            s.peak_bin_entries,
            s.peak_tiles_per_pass,
        ];
        // SAFETY: as above; the harness only reads the 64 bytes at r0.
        unsafe {
            asm!("bkpt #0x62", in("r0") words.as_ptr(), options(readonly, nostack, preserves_flags));
        }
    }

    /// Tells the harness that the run failed, and stops.
    fn fail(code: Fail) -> ! {
        // SAFETY: as above.
        unsafe {
            asm!("bkpt #0x6e", in("r0") code as u32, options(nomem, nostack, preserves_flags));
        }
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// One demo frame, as `count::frame` renders it on the host: frame 0,
    /// Gouraud.
    #[inline(never)]
    fn demo_frame(
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        knot: &Mesh<'_>,
        cube: &Mesh<'_>,
        width: u32,
        height: u32,
    ) -> Result<FrameStats, Fail> {
        let (t, width, height) = core::hint::black_box((0.0f32, width, height));
        let draws = demo_scene::draws(knot, cube, t, Shading::Gouraud);
        let camera = demo_scene::camera(width, height).ok_or(Fail::Camera)?;
        let scene = Scene::new(camera, &draws).light(demo_scene::light());
        r.render(ws, &scene, &mut NullSink)
            .map_err(|_| Fail::Render)
    }

    /// One rock frame, as `count::frame` renders it on the host.
    #[inline(never)]
    fn rock_frame(
        r: &mut BenchRenderer,
        ws: &mut RockWorkspace,
        rock: &Mesh<'_>,
        width: u32,
        height: u32,
    ) -> Result<FrameStats, Fail> {
        let (width, height) = core::hint::black_box((width, height));
        let draws = rock_scene::draws(rock);
        let camera = rock_scene::camera(width, height).ok_or(Fail::Camera)?;
        let scene = Scene::new(camera, &draws).light(demo_scene::light());
        r.render(ws, &scene, &mut NullSink)
            .map_err(|_| Fail::Render)
    }

    #[rp2040_hal::entry]
    fn main() -> ! {
        let Some(mut pac) = pac::Peripherals::take() else {
            fail(Fail::Clocks)
        };
        // 125 MHz from the crystal, as the Pico example runs. Not
        // board_support::rp_st7789_bring_up: the bench has no panel or LED.
        let mut watchdog = Watchdog::new(pac.WATCHDOG);
        if init_clocks_and_plls(
            XTAL_HZ,
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            &mut watchdog,
        )
        .is_err()
        {
            fail(Fail::Clocks)
        }

        // Validated once, outside the frames (as on the host).
        let (Ok(knot), Ok(cube), Ok(rock)) = (
            KNOT.mesh(),
            Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES).and_then(|m| m.with_normals(&CUBE_NORMALS)),
            Mesh::new(&ROCK.positions, &ROCK.triangles).and_then(|m| m.with_normals(&ROCK.normals)),
        ) else {
            fail(Fail::Mesh)
        };
        let demo_ws = DEMO_WS.take();
        let rock_ws = ROCK_WS.take();

        // One renderer, built once and given each size in turn: built
        // in the loop, its tile buffer was made in a temporary beside it
        // and copied in (4 KiB more under every frame: peak stack 14,788 B
        // against 11,020 B).
        let config =
            |(width, height)| Config::new(Size::new(width, height), demo_scene::DEMO_CLEAR);
        let mut r = BenchRenderer::new(config(SIZES[0]));
        for (width, height) in SIZES {
            *r.config_mut() = config((width, height));
            for _ in 0..FRAMES {
                mark_start(SceneId::Demo, width, height);
                let stats = demo_frame(&mut r, demo_ws, &knot, &cube, width, height);
                mark_end();
                match stats {
                    Ok(s) => report(&s),
                    Err(e) => fail(e),
                }
            }
            for _ in 0..FRAMES {
                mark_start(SceneId::Rock, width, height);
                let stats = rock_frame(&mut r, rock_ws, &rock, width, height);
                mark_end();
                match stats {
                    Ok(s) => report(&s),
                    Err(e) => fail(e),
                }
            }
        }
        // SAFETY: as above.
        unsafe {
            asm!("bkpt #0x6f", options(nomem, nostack, preserves_flags));
        }
        loop {
            cortex_m::asm::wfi();
        }
    }
}
