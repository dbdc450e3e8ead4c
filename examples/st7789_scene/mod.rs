//! The scene the Raspberry Pi Pico firmware draws on its 240x240 ST7789
//! (no_std, no alloc): a lit torus knot of 2,048 triangles turning in the
//! middle, and a cube orbiting it, passing in front and behind. Kept apart
//! from the board code so that a host program can render the same frames.
//!
//! [`Frames`] is the render loop's body of the Pico 2 and ESP32-C3
//! firmwares (`boards/`), which the QEMU stack probe
//! (`examples/stack_probe.rs`) also runs on the same instruction sets: the
//! code whose peak stack it measures is the boards' own.
#![allow(dead_code)]

use core::borrow::BorrowMut;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::render::{Frame, GouraudTriangles};
use microraster::shapes::{
    torus_knot, torus_knot_size, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
};
use microraster::sink::Rgb565Be;
use microraster::TileBuffer;

/// Panel size.
pub const WIDTH: u32 = 240;
/// Panel size.
pub const HEIGHT: u32 = 240;

/// Tile side: a 32x32 tile is 2 KiB of Rgb565 colour and 2 KiB of depth.
pub const TILE: usize = 32;
/// Tiles of the frame: 8 x 8, the last row and column 16 pixels wide.
pub const TILES: usize =
    WIDTH.div_ceil(TILE as u32) as usize * HEIGHT.div_ceil(TILE as u32) as usize;

/// Knot resolution: 128 x 8 = 1,024 vertices, 2,048 triangles.
pub const KNOT_SEGMENTS: usize = 128;
/// Knot resolution.
pub const KNOT_SIDES: usize = 8;
/// Vertices of the knot.
pub const KNOT_VERTICES: usize = torus_knot_size(KNOT_SEGMENTS, KNOT_SIDES).0;
/// Triangles of the knot.
pub const KNOT_TRIANGLES: usize = torus_knot_size(KNOT_SEGMENTS, KNOT_SIDES).1;
/// Vertices of the whole scene: the knot and the cube.
pub const SCENE_VERTICES: usize = KNOT_VERTICES + CUBE_POSITIONS.len();
/// Bin entries: about 1,000 triangles face the camera, and the busiest pose
/// of the animation needs between 1,536 and 1,792 entries, so 2,048 keep
/// every frame a single binning pass (a smaller pool draws the same frame,
/// in more passes).
pub const BIN_ENTRIES: usize = 2048;

/// The firmware's renderer: Rgb565 in the panel's byte order
/// ([`Rgb565Be`], so that DMA sends a finished tile as it is), in 32x32
/// tiles, Gouraud triangles only ([`GouraudTriangles`]: nothing else is
/// linked).
pub type PicoRenderer = Renderer<Rgb565Be, TILE, TILE, GouraudTriangles>;
/// The same renderer in plain [`Rgb565`], the host's reference: its
/// frames are the firmware's pixel for pixel, each pixel's two bytes in
/// the MCU's order instead of the wire's.
pub type Rgb565Renderer = Renderer<Rgb565, TILE, TILE, GouraudTriangles>;
/// A frame of [`PicoRenderer`]'s, begun without a renderer
/// ([`Frame::begin`]): what the double-buffered firmwares draw.
pub type PicoFrame<'a> =
    Frame<'a, Rgb565Be, microraster::shader::NoShader, TILE, TILE, GouraudTriangles>;
/// One of the firmware's two tile buffers: one is drawn into while DMA
/// sends the other.
pub type PicoTile = TileBuffer<Rgb565Be, TILE, TILE>;
/// The whole scene and all 64 tiles in one binning pass.
pub type PicoWorkspace = Workspace<SCENE_VERTICES, BIN_ENTRIES, TILES>;

/// The knot's mesh data, generated at start-up into caller memory.
pub struct KnotData {
    pub positions: [Vec3Fx; KNOT_VERTICES],
    pub normals: [Vec3Fx; KNOT_VERTICES],
    pub triangles: [[u16; 3]; KNOT_TRIANGLES],
}

impl KnotData {
    /// Zeroed storage (usable in a `static`).
    pub const fn new() -> Self {
        Self {
            positions: [[I16F16::ZERO; 3]; KNOT_VERTICES],
            normals: [[I16F16::ZERO; 3]; KNOT_VERTICES],
            triangles: [[0; 3]; KNOT_TRIANGLES],
        }
    }

    /// Generates the knot (the same bits on every target) and returns its
    /// mesh.
    pub fn generate(&mut self) -> Option<Mesh<'_>> {
        torus_knot(
            2,
            3,
            1.0,
            0.28,
            KNOT_SEGMENTS,
            KNOT_SIDES,
            &mut self.positions,
            &mut self.normals,
            &mut self.triangles,
        )
        .ok()?;
        Mesh::new(&self.positions, &self.triangles)
            .and_then(|m| m.with_normals(&self.normals))
            .ok()
    }
}

/// The cube, straight from flash.
pub fn cube() -> Option<Mesh<'static>> {
    Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES)
        .and_then(|m| m.with_normals(&CUBE_NORMALS))
        .ok()
}

/// Background.
pub const CLEAR: Rgb565 = Rgb565::new(2, 5, 8);

/// The angle, in radians, of a motion that turns once every `period_us`
/// microseconds, at time `time_us`. The time is reduced modulo the period
/// before it becomes an `f32`, so no precision is lost however long the
/// firmware runs, and the motion never jumps.
pub fn phase(time_us: u64, period_us: u64) -> f32 {
    (time_us % period_us) as f32 / period_us as f32 * core::f32::consts::TAU
}

/// The knot and the cube at `time_us` microseconds after start.
pub fn draws<'a>(knot: &'a Mesh<'a>, cube: &'a Mesh<'a>, time_us: u64) -> [Draw<'a>; 2] {
    let spin = phase(time_us, 12_000_000);
    let tumble = phase(time_us, 30_000_000);
    let orbit = phase(time_us, 7_500_000);
    let cube_spin = phase(time_us, 3_000_000);
    // The orbit: radius 1.55 in a plane tilted 0.35 rad towards the camera.
    // The crate's own sine and cosine, in basic float operations only: the
    // same bits on the host and the Pico. (micromath's cast negative
    // fractions to integers, which the RP2040's ROM rounds towards -inf
    // where the host truncates.)
    let (s, c) = microraster::math::sin_cos(orbit);
    let centre = Mat4::rotation_x(0.35) * Mat4::translation(Vec3::new(1.55 * s, 0.0, 1.55 * c));
    let (tumble_sin, _) = microraster::math::sin_cos(tumble);
    [
        Draw::new(knot)
            .transform(Mat4::rotation_y(spin) * Mat4::rotation_x(0.5 + 0.4 * tumble_sin))
            .color(Rgb888::new(235, 125, 40)),
        Draw::new(cube)
            .transform(
                centre
                    * Mat4::rotation_y(cube_spin)
                    * Mat4::rotation_x(0.6)
                    * Mat4::scale(Vec3::new(0.22, 0.22, 0.22)),
            )
            .color(Rgb888::new(70, 150, 235)),
    ]
}

/// The camera: the knot fills most of the square panel.
pub fn camera() -> Option<Camera> {
    let view = Mat4::look_at(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::default(),
        Vec3::new(0.0, 1.0, 0.0),
    )?;
    let proj = Mat4::perspective(0.9, WIDTH as f32 / HEIGHT as f32, 0.5, 10.0)?;
    Some(Camera::new(view, proj))
}

/// One white light from the upper left, with a dim bluish ambient term.
pub fn light() -> Light {
    Light::new(Vec3::new(-0.6, 0.8, 0.9)).ambient(Rgb888::new(40, 40, 56))
}

/// The scene, set up once, and the renderer's settings: what a firmware's
/// frame loop needs besides its panel and its two tile buffers. It holds
/// no [`Renderer`] (whose own tile buffer a double-buffered frame never
/// uses): each frame is begun with [`Frame::begin`].
pub struct Frames<'a> {
    config: Config<Rgb565Be>,
    workspace: &'a mut PicoWorkspace,
    knot: Mesh<'a>,
    cube: Mesh<'static>,
    camera: Camera,
}

impl<'a> Frames<'a> {
    /// Generates the knot into `knot` and sets the scene up; `None` if the
    /// scene's data does not make valid meshes or a camera.
    pub fn new(knot: &'a mut KnotData, workspace: &'a mut PicoWorkspace) -> Option<Self> {
        Some(Self {
            config: config(),
            workspace,
            knot: knot.generate()?,
            cube: cube()?,
            camera: camera()?,
        })
    }

    /// Draws the frame at `time_us` microseconds after start into `tiles`
    /// in turn, each finished tile handed to `panel` while the next one is
    /// drawn (`Frame::render_double_buffered`), and gives the tile
    /// buffers back. Never inlined: the boards and the stack probe call
    /// the same function, whose stack use the probe measures from its
    /// call.
    #[inline(never)]
    pub fn draw<B, X>(
        &mut self,
        time_us: u64,
        tiles: [B; 2],
        panel: &mut X,
    ) -> ([B; 2], Result<FrameStats, RenderError<X::Error>>)
    where
        B: BorrowMut<PicoTile>,
        X: TileTransfer<B>,
    {
        let draws = draws(&self.knot, &self.cube, time_us);
        let scene = Scene::new(self.camera, &draws).light(light());
        match PicoFrame::begin(self.config, self.workspace, &scene) {
            Ok(frame) => frame.render_double_buffered(tiles, panel),
            Err(e) => (tiles, Err(e.for_sink())),
        }
    }
}

/// The renderer's settings, in [`Rgb565Be`] for the firmware or
/// [`Rgb565`] for the host's reference.
pub fn config<C: From<Rgb565>>() -> Config<C> {
    Config::new(Size::new(WIDTH, HEIGHT), CLEAR.into())
}
