//! The scenes of the Cortex-M instruction-count firmware
//! (`examples/icount.rs`): `no_std`, no allocation, and every mesh built by
//! `const fn`s into `static`s, so that the meshes live in flash and the
//! LM3S6965's 64 KiB of RAM holds only the renderer and its workspace.
//!
//! The first three are the host benchmark scenes of `examples/common/scenes/`,
//! at the same size and with the same renderer settings (320x240, `Rgb565`, 32x32
//! tiles, back-face culling, `LessEqual` with depth writes):
//!
//! * `demo`, `demo-flat`: frame 0 of the demo (the 4,000-triangle torus
//!   knot and the 12-triangle cube, with the camera, light and transforms of
//!   `examples/common/mod.rs` at t = 0), Gouraud or flat shaded;
//! * `fill`: 8 flat-shaded 320x240 quads drawn back to front, so that every
//!   one of their 614,400 fragments passes the depth test and is written;
//! * `grid4`: a grid of 800 Gouraud triangles of 4 pixels each, for the
//!   cost per small triangle (the host's `tri4` scene scatters 8,000
//!   separate triangles, whose 24,000 vertices fit neither the LM3S6965's
//!   RAM nor its flash).
//! * `fill-gouraud-exact`, `fill-nearest-exact`, `fill-nearest-affine`,
//!   `fill-bilinear-exact`, `fill-lit-exact`: the fill quads through the
//!   `Gouraud`, `Textured` (nearest or bilinear) and `TexturedLit` fragment
//!   shaders, with the host's 32x32 checker texture, as the host's
//!   `fill-SHADER-MODE` scenes (their clip-space `w` is one constant, so
//!   every mode draws them through the affine loops);
//! * `fill-nearest-quasi16-facing`, `fill-gouraud-quasi16-facing`,
//!   `fill-lit-quasi16-facing`: the same quads through a camera whose `w`
//!   depends on depth, each quad still of one `w` (as quads facing a
//!   perspective camera), quasi-perspective every 16 columns: the opaque
//!   quasi-perspective loops, as the host's `fill-SHADER-quasi16-facing`;
//! * `rock`: the host's small-triangle mesh (`examples/rock_scene`, 3,920
//!   triangles of 5 to 20 pixels), lit, Gouraud; in this workspace's 4,096
//!   bin entries (the host's has 6,144), so it may take more bin passes;
//! * `demo-textured-lit`: demo frame 0 through `TexturedLit` with the
//!   checker texture (nearest, exact perspective) and the demo's light, as
//!   the host's `demo-textured-lit`; `demo-textured-lit-affine` the same
//!   in affine mode.
//!
//! A build holds only the scenes named in `MICRORASTER_ICOUNT_SCENES` (all
//! without it): their meshes, and through [`frame`]'s constant guards,
//! their code.
#![allow(dead_code)]

use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::primitives::Rectangle;
use fixed::types::I16F16;
use microraster::mesh::{Mesh, MeshError, UvFx, Vec3Fx};
use microraster::prelude::*;
use microraster::shader::{Gouraud, Textured, TexturedLit};
use microraster::shapes::{
    torus_knot_data, torus_knot_size, MeshData, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
};
use microraster::sink::TileSink;
use microraster::texture::{Filter, Texels, Texture};
use microraster::tile::TileView;
use microraster::Profiler;

#[path = "../demo_scene/mod.rs"]
mod demo_scene;
use demo_scene::{checker, fx};
#[path = "../bench_tile/mod.rs"]
mod bench_tile;
#[path = "../fill_camera/mod.rs"]
mod fill_camera;
#[path = "../rock_scene/mod.rs"]
mod rock_scene;
use fill_camera::{facing_camera, ndc_camera};

/// Frame width.
pub const WIDTH: u32 = 320;
/// Frame height.
pub const HEIGHT: u32 = 240;

/// The renderer of every scene: 32x32 tiles of `Rgb565` (4,112 bytes),
/// with the paths of [`BenchFeatures`]; or, for a study of the tile size,
/// the tiles named at build time in `MICRORASTER_BENCH_TILE=WxH`
/// (`examples/bench_tile`).
pub type BenchRenderer =
    Renderer<Rgb565, { bench_tile::TILE_W }, { bench_tile::TILE_H }, BenchFeatures>;

/// Whether the build holds the textured frame (`demo-textured-lit`, its
/// affine form or both).
const TEXTURED: bool = SceneId::DemoTexturedLit.built() || SceneId::DemoTexturedLitAffine.built();

/// Whether the build holds the textured frame ([`TEXTURED`]) and no other
/// scene.
const TEXTURED_ALONE: bool = {
    let mut alone = TEXTURED;
    let mut i = 0;
    while i < SceneId::ALL.len() {
        let s = SceneId::ALL[i];
        alone &= s as usize == SceneId::DemoTexturedLit as usize
            || s as usize == SceneId::DemoTexturedLitAffine as usize
            || !s.built();
        i += 1;
    }
    alone
};

/// Every path of the renderer ([`All`](microraster::render::All)'s), but in
/// a build of the textured frame alone, which leaves out what that frame
/// never takes, as a firmware drawing only textured models would: the
/// Hilbert rasterizer, lines, blending, the depth tests other than the
/// default, `u32` indices and the flat and Gouraud span loops. Its code
/// (the other depth tests' copies of the shader span loops above all) no
/// longer fits the LM3S6965's 256 KiB of flash beside the knot's 88,000
/// bytes of mesh data; the frame's work is the same, as the image is.
/// Every build but those with the `*-quasi16-facing` fills leaves out the
/// opaque quasi-perspective loops ([`Features::QUASI`]), which no other
/// scene takes, and every build but those with the other shader fills
/// (of constant `w`, drawn affinely in every mode) the opaque affine loops
/// ([`Features::AFFINE`]).
///
/// [`Features::QUASI`]: microraster::Features::QUASI
/// [`Features::AFFINE`]: microraster::Features::AFFINE
pub struct BenchFeatures;

impl microraster::Features for BenchFeatures {
    const HILBERT: bool = !TEXTURED_ALONE;
    const LINES: bool = !TEXTURED_ALONE;
    const BLEND: bool = !TEXTURED_ALONE;
    const DEPTH_TESTS: bool = !TEXTURED_ALONE;
    const U32_INDICES: bool = !TEXTURED_ALONE;
    const FLAT: bool = !TEXTURED_ALONE;
    const GOURAUD: bool = !TEXTURED_ALONE;
    const QUASI: bool = SceneId::FillNearestQuasi16.built()
        || SceneId::FillGouraudQuasi16.built()
        || SceneId::FillLitQuasi16.built();
    const AFFINE: bool = SceneId::FillNearestAffine.built()
        || SceneId::DemoTexturedLitAffine.built()
        || SceneId::FillGouraud.built()
        || SceneId::FillNearest.built()
        || SceneId::FillBilinear.built()
        || SceneId::FillLit.built();
}
/// The workspace of every scene: 2,048 vertices, 4,096 bin entries, all 80
/// tiles in one pass (33,088 bytes); `MICRORASTER_BENCH_BINS` bin entries
/// if set at build time, and as many tiles as `MICRORASTER_BENCH_TILE`'s
/// make.
pub type BenchWorkspace =
    Workspace<2048, { bench_tile::bin_entries(4096) }, { bench_tile::tiles(WIDTH, HEIGHT) }>;

/// The demo's background (`examples/common/mod.rs`).
pub const CLEAR: Rgb565 = demo_scene::DEMO_CLEAR;

use demo_scene::{KNOT_SEGMENTS, KNOT_SIDES};
const KNOT_VERTICES: usize = torus_knot_size(KNOT_SEGMENTS, KNOT_SIDES).0;
const KNOT_TRIANGLES: usize = torus_knot_size(KNOT_SEGMENTS, KNOT_SIDES).1;

/// The demo's torus knot (`examples/demo_scene`), evaluated by the compiler
/// into flash (72,000 bytes).
pub static KNOT: MeshData<KNOT_VERTICES, KNOT_TRIANGLES> = match torus_knot_data(
    demo_scene::KNOT_P,
    demo_scene::KNOT_Q,
    demo_scene::KNOT_RADIUS,
    demo_scene::KNOT_TUBE,
    KNOT_SEGMENTS,
    KNOT_SIDES,
) {
    Ok(m) => m,
    Err(_) => panic!("the demo knot's parameters are valid"),
};

/// The knot's texture coordinates (`demo_scene::knot_uv`), evaluated by
/// the compiler into flash (16,000 bytes).
static KNOT_UVS: [UvFx; KNOT_VERTICES] = {
    let mut uv = [[I16F16::ZERO; 2]; KNOT_VERTICES];
    let (u, v) = demo_scene::KNOT_UV_REPEATS;
    let mut k = 0;
    while k < KNOT_VERTICES {
        uv[k] = demo_scene::knot_uv(k / KNOT_SIDES, k % KNOT_SIDES, u, v);
        k += 1;
    }
    uv
};

/// The rock, evaluated by the compiler into flash (70,608 bytes).
static ROCK: rock_scene::RockData = rock_scene::rock_data();

/// Pixel position (x right, y down) to a normalised-device-coordinate
/// vertex at depth `z`, as `examples/common/scenes/mod.rs` computes it.
const fn ndc(px: f32, py: f32, z: f32) -> Vec3Fx {
    [
        fx(px * 2.0 / WIDTH as f32 - 1.0),
        fx(1.0 - py * 2.0 / HEIGHT as f32),
        fx(z),
    ]
}

/// Quads of the fill-rate scene.
pub const FILL_LAYERS: usize = 8;

/// The fill scene's mesh: `FILL_LAYERS` full-frame quads (counter-clockwise
/// in NDC), from z = 0.8 at the back to z = -0.8 at the front.
struct FillData {
    positions: [Vec3Fx; 4 * FILL_LAYERS],
    colors: [Rgb888; 4 * FILL_LAYERS],
    /// The checker texture four times across and three times down each
    /// quad, as the host's fill scene maps it.
    uvs: [UvFx; 4 * FILL_LAYERS],
    triangles: [[u16; 3]; 2 * FILL_LAYERS],
}

const fn fill_data() -> FillData {
    let mut d = FillData {
        positions: [[I16F16::ZERO; 3]; 4 * FILL_LAYERS],
        colors: [Rgb888::new(0, 0, 0); 4 * FILL_LAYERS],
        uvs: [[I16F16::ZERO; 2]; 4 * FILL_LAYERS],
        triangles: [[0; 3]; 2 * FILL_LAYERS],
    };
    let (w, h) = (WIDTH as f32, HEIGHT as f32);
    let mut l = 0;
    while l < FILL_LAYERS {
        let z = 0.8 - 1.6 * l as f32 / (FILL_LAYERS - 1) as f32;
        let b = 4 * l;
        d.positions[b] = ndc(0.0, h, z);
        d.positions[b + 1] = ndc(w, h, z);
        d.positions[b + 2] = ndc(w, 0.0, z);
        d.positions[b + 3] = ndc(0.0, 0.0, z);
        let c = Rgb888::new(
            (40 + (25 * l) % 200) as u8,
            (200 - (20 * l) % 160) as u8,
            90,
        );
        let mut i = 0;
        while i < 4 {
            d.colors[b + i] = c;
            i += 1;
        }
        d.uvs[b] = [fx(0.0), fx(3.0)];
        d.uvs[b + 1] = [fx(4.0), fx(3.0)];
        d.uvs[b + 2] = [fx(4.0), fx(0.0)];
        d.uvs[b + 3] = [fx(0.0), fx(0.0)];
        let b = b as u16;
        d.triangles[2 * l] = [b, b + 1, b + 2];
        d.triangles[2 * l + 1] = [b, b + 2, b + 3];
        l += 1;
    }
    d
}

static FILL: FillData = fill_data();

/// Vertices per side of the small-triangle grid.
pub const GRID_SIDE: usize = 21;
/// Triangles of the small-triangle grid: 20 x 20 cells of two.
pub const GRID_TRIANGLES: usize = 2 * (GRID_SIDE - 1) * (GRID_SIDE - 1);
/// The grid's cell, in pixels: 2 sqrt(2), so that each triangle covers 4
/// pixels.
const GRID_CELL: f32 = 2.828_427;

/// The small-triangle scene's mesh: a 21 x 21-vertex grid of 800
/// triangles of 4 pixels each (a 57x57-pixel patch near the centre of the
/// frame, at a sub-pixel offset), all at depth 0, Gouraud shaded with a
/// colour gradient. A grid shares its vertices as real meshes do (2
/// triangles per vertex), which also keeps the mesh small enough for the
/// LM3S6965's flash.
struct GridData {
    positions: [Vec3Fx; GRID_SIDE * GRID_SIDE],
    colors: [Rgb888; GRID_SIDE * GRID_SIDE],
    triangles: [[u16; 3]; GRID_TRIANGLES],
}

const fn grid_data() -> GridData {
    let mut d = GridData {
        positions: [[I16F16::ZERO; 3]; GRID_SIDE * GRID_SIDE],
        colors: [Rgb888::new(0, 0, 0); GRID_SIDE * GRID_SIDE],
        triangles: [[0; 3]; GRID_TRIANGLES],
    };
    let side = (GRID_SIDE - 1) as f32 * GRID_CELL;
    let (x0, y0) = (
        (WIDTH as f32 - side) / 2.0 + 0.3,
        (HEIGHT as f32 - side) / 2.0 + 0.45,
    );
    let mut j = 0;
    while j < GRID_SIDE {
        let mut i = 0;
        while i < GRID_SIDE {
            let v = j * GRID_SIDE + i;
            d.positions[v] = ndc(x0 + i as f32 * GRID_CELL, y0 + j as f32 * GRID_CELL, 0.0);
            d.colors[v] = Rgb888::new(
                (40 + 200 * i / (GRID_SIDE - 1)) as u8,
                (40 + 200 * j / (GRID_SIDE - 1)) as u8,
                120,
            );
            i += 1;
        }
        j += 1;
    }
    let mut k = 0;
    let mut j = 0;
    while j + 1 < GRID_SIDE {
        let mut i = 0;
        while i + 1 < GRID_SIDE {
            // a b (y down on the screen, so counter-clockwise in NDC is
            // c d  a, c, d and a, d, b)
            let a = (j * GRID_SIDE + i) as u16;
            let (b, c) = (a + 1, a + GRID_SIDE as u16);
            let d_ = c + 1;
            d.triangles[k] = [a, c, d_];
            d.triangles[k + 1] = [a, d_, b];
            k += 2;
            i += 1;
        }
        j += 1;
    }
    d
}

static GRID: GridData = grid_data();

/// A benchmark scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneId {
    /// The demo frame, Gouraud.
    Demo,
    /// The demo frame, flat.
    DemoFlat,
    /// The fill-rate quads.
    Fill,
    /// The small triangles.
    Grid4,
    /// The fill quads through the `Gouraud` fragment shader, exact
    /// perspective.
    FillGouraud,
    /// Textured, nearest texel, exact perspective.
    FillNearest,
    /// Textured, nearest texel, affine.
    FillNearestAffine,
    /// Textured, nearest texel, quasi-perspective every 16 columns,
    /// through the facing camera ([`facing_camera`]).
    FillNearestQuasi16,
    /// The fill quads through the `Gouraud` fragment shader,
    /// quasi-perspective every 16 columns, through the facing camera.
    FillGouraudQuasi16,
    /// Textured and lit, nearest texel, quasi-perspective every 16
    /// columns, through the facing camera.
    FillLitQuasi16,
    /// Textured, bilinear, exact perspective.
    FillBilinear,
    /// Textured and lit (`TexturedLit`), nearest texel, exact perspective.
    FillLit,
    /// The small-triangle rock, Gouraud.
    Rock,
    /// The demo frame, textured and lit.
    DemoTexturedLit,
    /// The demo frame, textured and lit, in affine mode.
    DemoTexturedLitAffine,
}

impl SceneId {
    /// Every scene, in the order of the tables.
    pub const ALL: [SceneId; 15] = [
        Self::Demo,
        Self::DemoFlat,
        Self::Fill,
        Self::Grid4,
        Self::FillGouraud,
        Self::FillNearest,
        Self::FillNearestAffine,
        Self::FillNearestQuasi16,
        Self::FillGouraudQuasi16,
        Self::FillLitQuasi16,
        Self::FillBilinear,
        Self::FillLit,
        Self::Rock,
        Self::DemoTexturedLit,
        Self::DemoTexturedLitAffine,
    ];

    /// The scene's name, as in the host benchmarks.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Demo => "demo",
            Self::DemoFlat => "demo-flat",
            Self::Fill => "fill",
            Self::Grid4 => "grid4",
            Self::FillGouraud => "fill-gouraud-exact",
            Self::FillNearest => "fill-nearest-exact",
            Self::FillNearestAffine => "fill-nearest-affine",
            Self::FillNearestQuasi16 => "fill-nearest-quasi16-facing",
            Self::FillGouraudQuasi16 => "fill-gouraud-quasi16-facing",
            Self::FillLitQuasi16 => "fill-lit-quasi16-facing",
            Self::FillBilinear => "fill-bilinear-exact",
            Self::FillLit => "fill-lit-exact",
            Self::Rock => "rock",
            Self::DemoTexturedLit => "demo-textured-lit",
            Self::DemoTexturedLitAffine => "demo-textured-lit-affine",
        }
    }

    /// The scene called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether the scene is [built in](built_in): a constant per scene,
    /// so that [`frame`] holds the code of the built-in scenes only.
    pub const fn built(self) -> bool {
        const ON: [bool; SceneId::ALL.len()] = {
            let mut on = [false; SceneId::ALL.len()];
            let mut i = 0;
            while i < on.len() {
                on[i] = built_in(SceneId::ALL[i].name());
                i += 1;
            }
            on
        };
        ON[self as usize]
    }
}

/// How many scenes are [built in](SceneId::built): the firmware's table of
/// results has a row for each, so that its stack (which the peak
/// measured includes) does not grow with scenes a build leaves out.
pub const BUILT_SCENES: usize = {
    let (mut n, mut i) = (0, 0);
    while i < SceneId::ALL.len() {
        n += SceneId::ALL[i].built() as usize;
        i += 1;
    }
    n
};

/// Whether any fragment-shader scene is built in (they need the texture).
pub const SHADER_SCENES: bool = TEXTURED
    || SceneId::FillGouraud.built()
    || SceneId::FillNearest.built()
    || SceneId::FillNearestAffine.built()
    || SceneId::FillNearestQuasi16.built()
    || SceneId::FillGouraudQuasi16.built()
    || SceneId::FillLitQuasi16.built()
    || SceneId::FillBilinear.built()
    || SceneId::FillLit.built();

/// The host's 32x32 checker texture (`examples/common::checker_texels`),
/// computed at start-up (the `Rgb888` to `Rgb565` conversion is not a
/// `const fn`) into `out`.
pub fn checker_texels(out: &mut [u16; 32 * 32]) {
    for (i, t) in (0u32..).zip(out.iter_mut()) {
        *t = checker::checker_texel(i % 32, i / 32, 32);
    }
}

/// The same checker as [`checker_texels`], computed at compile time: the
/// texture of a build with `MICRORASTER_ICOUNT_TEXTURE_IN_FLASH` set, read
/// from flash (the firmware checks at start-up that the two agree).
pub const CHECKER_TEXELS: [u16; 32 * 32] = {
    let mut t = [0u16; 32 * 32];
    let mut i = 0;
    while i < t.len() {
        t[i] = checker_texel_const(i as u32 % 32, i as u32 / 32, 32);
        i += 1;
    }
    t
};

/// [`checker::checker_texel`] at compile time: [`checker::checker_rgb`]
/// with embedded-graphics' `Rgb888` to `Rgb565` channel conversion written
/// out (`value · (max << 24) / 255`, rounded).
const fn checker_texel_const(x: u32, y: u32, size: u32) -> u16 {
    let [r, g, b] = checker::checker_rgb(x, y, size);
    ((channel(r, 31) << 11) | (channel(g, 63) << 5) | channel(b, 31)) as u16
}

/// An 8-bit channel to `0..=max`, as embedded-graphics converts it.
const fn channel(v: u32, max: u32) -> u32 {
    (v * ((max << 24) / 255) + (1 << 23)) >> 24
}

/// Whether the shader scenes read their texture from flash
/// ([`CHECKER_TEXELS`]) rather than from RAM (set at build time by
/// `MICRORASTER_ICOUNT_TEXTURE_IN_FLASH`).
pub const TEXTURE_IN_FLASH: bool = option_env!("MICRORASTER_ICOUNT_TEXTURE_IN_FLASH").is_some();

/// The scenes named at build time in `MICRORASTER_ICOUNT_SCENES`
/// (separated by spaces or commas), or `""` for all of them.
pub const SCENE_LIST: &str = match option_env!("MICRORASTER_ICOUNT_SCENES") {
    Some(list) => list,
    None => "",
};

/// Whether scene `name` is built in: named in [`SCENE_LIST`], or the list
/// is blank. A `const fn`, so that the meshes of the other scenes are never
/// referenced and stay out of flash (all of them together do not fit the
/// LM3S6965's 256 KiB beside the renderer).
pub const fn built_in(name: &str) -> bool {
    let (list, name) = (SCENE_LIST.as_bytes(), name.as_bytes());
    let (mut i, mut blank) = (0, true);
    const fn sep(b: u8) -> bool {
        b == b' ' || b == b','
    }
    while i < list.len() {
        if sep(list[i]) {
            i += 1;
            continue;
        }
        blank = false;
        let mut end = i;
        while end < list.len() && !sep(list[end]) {
            end += 1;
        }
        if end - i == name.len() {
            let mut k = 0;
            while k < name.len() && list[i + k] == name[k] {
                k += 1;
            }
            if k == name.len() {
                return true;
            }
        }
        i = end;
    }
    blank
}

/// The validated meshes of every scene (building a [`Mesh`] checks every
/// index, which is set-up work, not per-frame work); the meshes of scenes
/// not [built in](built_in) are empty.
pub struct Meshes {
    knot: Mesh<'static>,
    cube: Mesh<'static>,
    /// The knot and the cube with texture coordinates.
    knot_uv: Mesh<'static>,
    cube_uv: Mesh<'static>,
    rock: Mesh<'static>,
    fill: Mesh<'static>,
    grid: Mesh<'static>,
    /// The checker texture, when a shader scene is built in.
    texture: Option<Texture<'static>>,
}

impl Meshes {
    /// Validates the meshes; `texels` (from [`checker_texels`]) make the
    /// shader scenes' texture.
    pub fn new(texels: Option<&'static [u16]>) -> Result<Self, MeshError> {
        // Constants, so that the branches not taken are gone at compile time.
        const DEMO: bool = built_in("demo") || built_in("demo-flat");
        const GRID4: bool = built_in("grid4");
        const ROCK_SCENE: bool = built_in("rock");
        let empty = || Mesh::new(&[], &[]);
        let cube = Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES)?.with_normals(&CUBE_NORMALS)?;
        Ok(Self {
            knot: if DEMO { KNOT.mesh()? } else { empty()? },
            cube,
            knot_uv: if TEXTURED {
                KNOT.mesh()?.with_uvs(&KNOT_UVS)?
            } else {
                empty()?
            },
            cube_uv: cube.with_uvs(&microraster::shapes::CUBE_UVS)?,
            rock: if ROCK_SCENE {
                Mesh::new(&ROCK.positions, &ROCK.triangles)?.with_normals(&ROCK.normals)?
            } else {
                empty()?
            },
            fill: Mesh::new(&FILL.positions, &FILL.triangles)?
                .with_colors(&FILL.colors)?
                .with_uvs(&FILL.uvs)?,
            grid: if GRID4 {
                Mesh::new(&GRID.positions, &GRID.triangles)?.with_colors(&GRID.colors)?
            } else {
                empty()?
            },
            texture: texels.and_then(|t| Texture::new(32, 32, Texels::Rgb565(t)).ok()),
        })
    }
}

/// Why a frame could not be rendered.
#[derive(Debug)]
pub enum FrameError {
    /// The demo camera's matrices could not be built.
    Camera,
    /// The scene is not built in, or its texture is missing.
    NotBuilt,
    /// The renderer refused the scene.
    Render(RenderError<core::convert::Infallible>),
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Camera => write!(f, "the demo camera's matrices are degenerate"),
            Self::NotBuilt => write!(f, "the scene is not built in (or has no texture)"),
            Self::Render(e) => write!(f, "render error: {e}"),
        }
    }
}

use demo_scene::{camera as demo_camera, draws as demo_draws, light as demo_light};

/// A renderer with the benchmark settings.
pub fn renderer() -> BenchRenderer {
    BenchRenderer::new(Config::new(Size::new(WIDTH, HEIGHT), CLEAR))
}

/// The benchmark's sink. While frames are measured (`hash: None`) it
/// discards every tile as `NullSink` does, touching its first row so that
/// the rendering cannot be optimised away; with `hash` set it folds each
/// tile's rectangle and pixels (raw `Rgb565` bits, row by row) into a
/// hash of the frame (FNV-1a's step, over words). The firmware prints that hash after its
/// measured runs, the host build of `icount` prints it for the same
/// scenes, and `scripts/icount.sh` requires the two to be equal: the
/// Cortex-M builds' own code paths (Thumb-2 and ARMv6-M span loops and
/// set-ups) render the host's image, bit for bit.
pub struct FrameSink {
    /// The hash so far, or `None` while measuring.
    pub hash: Option<u32>,
}

/// FNV-1a's offset basis, the hash of nothing.
pub const FNV_OFFSET: u32 = 0x811c_9dc5;

impl FrameSink {
    /// A sink that hashes what it is given.
    pub fn hashing() -> Self {
        Self {
            hash: Some(FNV_OFFSET),
        }
    }
}

impl TileSink<Rgb565> for FrameSink {
    type Error = core::convert::Infallible;

    #[inline]
    fn write_tile(
        &mut self,
        area: &Rectangle,
        tile: &TileView<'_, Rgb565>,
    ) -> Result<(), Self::Error> {
        match &mut self.hash {
            None => {
                core::hint::black_box(tile.rows().next());
            }
            Some(h) => *h = hash_tile(*h, area, tile),
        }
        Ok(())
    }
}

/// `h` with the tile's rectangle and pixels folded in, FNV-1a's step
/// over 32-bit words rather than bytes (a quarter of the multiplies, and
/// less code in the M3's full `demo-textured-lit` firmware). Out of line:
/// the measured runs never call it.
#[inline(never)]
fn hash_tile(mut h: u32, area: &Rectangle, tile: &TileView<'_, Rgb565>) -> u32 {
    let mut eat = |w: u32| h = (h ^ w).wrapping_mul(0x0100_0193);
    eat(area.top_left.x as u32);
    eat(area.top_left.y as u32);
    eat(area.size.width);
    eat(area.size.height);
    for row in tile.rows() {
        for &c in row {
            eat(RawU16::from(c).into_inner() as u32);
        }
    }
    h
}

/// One whole frame of `scene` into `sink`: the scene's set-up
/// (camera, transforms) and the render, reporting stages to `profiler`.
///
/// The animation time (0, demo frame 0) and the frame size reach the
/// set-up through [`black_box`](core::hint::black_box), as a real
/// program's time and viewport would: the matrices are computed in every
/// frame, not folded by the compiler or hoisted out of the benchmark loop.
/// So does the scene, and the function is never inlined, so that its code,
/// and the renderer's, do not depend on which scenes a build runs.
#[inline(never)]
pub fn frame<P: Profiler>(
    scene: SceneId,
    meshes: &Meshes,
    renderer: &mut BenchRenderer,
    ws: &mut BenchWorkspace,
    profiler: &mut P,
    sink: &mut FrameSink,
) -> Result<FrameStats, FrameError> {
    let (scene, t, width, height) = core::hint::black_box((scene, 0.0f32, WIDTH, HEIGHT));
    // One constant per scene: the arms of scenes not built in are gone at
    // compile time, with the renderer monomorphizations only they use.
    const DEMO: bool = SceneId::Demo.built() || SceneId::DemoFlat.built();
    const FILL: bool = SceneId::Fill.built();
    const GRID4: bool = SceneId::Grid4.built();
    const GOURAUD: bool = SceneId::FillGouraud.built();
    const NEAREST: bool = SceneId::FillNearest.built();
    const AFFINE: bool = SceneId::FillNearestAffine.built();
    const QUASI: bool = SceneId::FillNearestQuasi16.built();
    const GOURAUD_QUASI: bool = SceneId::FillGouraudQuasi16.built();
    const LIT_QUASI: bool = SceneId::FillLitQuasi16.built();
    const BILINEAR: bool = SceneId::FillBilinear.built();
    const LIT: bool = SceneId::FillLit.built();
    const ROCK_SCENE: bool = SceneId::Rock.built();
    const EXACT: Perspective = Perspective::Exact;
    const AFFINE_MODE: Perspective = Perspective::Affine;
    const QUASI_MODE: Perspective = Perspective::Quasi16;
    // A shader fill: the frame's result, returned from its arm.
    macro_rules! fill {
        ($shader:expr, $filter:expr, $mode:expr) => {
            fill!($shader, $filter, $mode, ndc_camera())
        };
        ($shader:expr, $filter:expr, $mode:expr, $camera:expr) => {
            return fill_shader(
                meshes,
                renderer,
                ws,
                profiler,
                sink,
                $shader,
                ($filter, $mode, $camera),
            )
        };
    }
    let r = match scene {
        SceneId::Demo | SceneId::DemoFlat if DEMO => {
            let shading = if scene == SceneId::Demo {
                Shading::Gouraud
            } else {
                Shading::Flat
            };
            let draws = demo_draws(&meshes.knot, &meshes.cube, t, shading);
            let camera = demo_camera(width, height).ok_or(FrameError::Camera)?;
            let s = Scene::new(camera, &draws).light(demo_light());
            renderer.render_profiled(ws, &s, sink, profiler)
        }
        SceneId::Fill if FILL => {
            let draws = [Draw::new(&meshes.fill).shading(Shading::Flat)];
            let s = Scene::new(ndc_camera(), &draws);
            renderer.render_profiled(ws, &s, sink, profiler)
        }
        SceneId::Grid4 if GRID4 => {
            let draws = [Draw::new(&meshes.grid)];
            let s = Scene::new(ndc_camera(), &draws);
            renderer.render_profiled(ws, &s, sink, profiler)
        }
        SceneId::Rock if ROCK_SCENE => {
            let draws = rock_scene::draws(&meshes.rock);
            let camera = rock_scene::camera(width, height).ok_or(FrameError::Camera)?;
            let s = Scene::new(camera, &draws).light(demo_light());
            renderer.render_profiled(ws, &s, sink, profiler)
        }
        SceneId::DemoTexturedLit | SceneId::DemoTexturedLitAffine if TEXTURED && scene.built() => {
            let texture = meshes.texture.as_ref().ok_or(FrameError::NotBuilt)?;
            renderer.config_mut().perspective = if scene == SceneId::DemoTexturedLit {
                EXACT
            } else {
                AFFINE_MODE
            };
            let draws = demo_scene::textured_draws(&meshes.knot_uv, &meshes.cube_uv, texture, t);
            let camera = demo_camera(width, height).ok_or(FrameError::Camera)?;
            let s = Scene::new(camera, &draws)
                .light(demo_light())
                .shader(&TexturedLit);
            renderer.render_profiled(ws, &s, sink, profiler)
        }
        SceneId::FillGouraud if GOURAUD => fill!(&Gouraud, Filter::Nearest, EXACT),
        SceneId::FillNearest if NEAREST => fill!(&Textured, Filter::Nearest, EXACT),
        SceneId::FillNearestAffine if AFFINE => fill!(&Textured, Filter::Nearest, AFFINE_MODE),
        SceneId::FillNearestQuasi16 if QUASI => {
            fill!(&Textured, Filter::Nearest, QUASI_MODE, facing_camera())
        }
        SceneId::FillGouraudQuasi16 if GOURAUD_QUASI => {
            fill!(&Gouraud, Filter::Nearest, QUASI_MODE, facing_camera())
        }
        SceneId::FillLitQuasi16 if LIT_QUASI => {
            fill!(&TexturedLit, Filter::Nearest, QUASI_MODE, facing_camera())
        }
        SceneId::FillBilinear if BILINEAR => fill!(&Textured, Filter::Bilinear, EXACT),
        SceneId::FillLit if LIT => fill!(&TexturedLit, Filter::Nearest, EXACT),
        _ => return Err(FrameError::NotBuilt),
    };
    r.map_err(FrameError::Render)
}

/// The fill quads through fragment shader `shader`, sampling the checker
/// texture with `filter`, with perspective `mode`, through `camera`: the
/// host's `fill-SHADER-MODE` scenes ([`ndc_camera`]) and
/// `fill-SHADER-MODE-facing` ones ([`facing_camera`]).
fn fill_shader<P: Profiler, F: FragmentShader<Rgb565>>(
    meshes: &Meshes,
    renderer: &mut BenchRenderer,
    ws: &mut BenchWorkspace,
    profiler: &mut P,
    sink: &mut FrameSink,
    shader: &F,
    (filter, mode, camera): (Filter, Perspective, Camera),
) -> Result<FrameStats, FrameError> {
    let texture = meshes.texture.ok_or(FrameError::NotBuilt)?.filter(filter);
    renderer.config_mut().perspective = mode;
    let draws = [Draw::new(&meshes.fill)
        .shading(Shading::Shader)
        .texture(&texture)];
    let s = Scene::new(camera, &draws).shader(shader);
    renderer
        .render_profiled(ws, &s, sink, profiler)
        .map_err(FrameError::Render)
}
