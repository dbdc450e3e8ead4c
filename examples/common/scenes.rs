//! Benchmark scenes, shared by `benches/raster.rs`, `examples/count.rs`
//! and `examples/raster_plot.rs` (`common::scenes`; they use the demo
//! scene of `common`).
//!
//! * [`DemoScene`]: the demo frame (torus knot + cube, frame 0 of the demo)
//!   at 320x240, as the demo renders it.
//! * [`FillScene`]: `layers` flat-shaded 320x240 quads, drawn back to front
//!   with the depth test on, so every fragment passes and is written.
//! * [`Copies`]: many copies of one triangle of a given pixel area,
//!   scattered over the frame, for per-triangle costs.
//! * [`EucDemo`]: the demo frame rendered by the `euc` crate, for comparison.
//! * [`TerrainScene`]: a terrain of 18,432 triangles imported in clusters,
//!   seen from on it: most of it lies outside the view.
#![allow(dead_code)]

use crate::common;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::IntoStorage;
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;

/// Frame width of every scene.
pub const WIDTH: u32 = 320;
/// Frame height of every scene.
pub const HEIGHT: u32 = 240;

/// The renderer every benchmark uses: 32x32 tiles of `Rgb565`.
pub type BenchRenderer = Renderer<Rgb565, 32, 32>;
/// The demo's workspace: the whole demo scene, all 80 tiles in one pass.
pub type DemoWorkspace = Workspace<2048, 4096, 80>;
/// A workspace for the triangle-copies scenes (up to 24,000 vertices).
pub type CopiesWorkspace = Workspace<24_000, 32_768, 80>;

/// A workspace for the terrain scene (every vertex of the clustered
/// terrain, a slot each whether culled or not).
pub type TerrainWorkspace = Workspace<16_384, 16_384, 80>;

/// A renderer with the demo's settings (back-face culling, `LessEqual`,
/// depth writes) and the scanline rasterizer.
pub fn renderer() -> BenchRenderer {
    renderer_with(Rasterizer::Scanline)
}

/// [`renderer`] with the given rasterizer.
pub fn renderer_with(raster: Rasterizer) -> BenchRenderer {
    BenchRenderer::new(Config::new(Size::new(WIDTH, HEIGHT), common::DEMO_CLEAR).rasterizer(raster))
}

/// The rasterizer named on a command line: `scanline`, `hilbert` or
/// `auto`.
pub fn parse_rasterizer(name: &str) -> Option<Rasterizer> {
    match name {
        "scanline" => Some(Rasterizer::Scanline),
        "hilbert" => Some(Rasterizer::Hilbert),
        "auto" => Some(Rasterizer::Auto),
        _ => None,
    }
}

/// A camera whose clip space is the model space: x, y, z in `[-1, 1]` are
/// the frame, z = -1 nearest.
pub fn ndc_camera() -> Camera {
    Camera::new(Mat4::IDENTITY, Mat4::IDENTITY)
}

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

/// Pixel position (x right, y down) to a normalised-device-coordinate
/// vertex at depth `z`.
fn ndc(px: f32, py: f32, z: f32) -> Vec3Fx {
    [
        fx(px * 2.0 / WIDTH as f32 - 1.0),
        fx(1.0 - py * 2.0 / HEIGHT as f32),
        fx(z),
    ]
}

/// Leaks `v` so a mesh can borrow it for the rest of the program (scenes
/// are built once per process, and building a [`Mesh`] validates every
/// index, which is not per-frame work).
fn leak<T>(v: Vec<T>) -> &'static [T] {
    Vec::leak(v)
}

/// The demo scene: the knot and the cube, generated and validated once.
pub struct DemoScene {
    knot: Mesh<'static>,
    cube: Mesh<'static>,
}

impl Default for DemoScene {
    fn default() -> Self {
        Self::new()
    }
}

impl DemoScene {
    /// Generates the knot.
    pub fn new() -> Self {
        let assets: &'static common::DemoAssets = Box::leak(Box::new(common::DemoAssets::new()));
        Self {
            knot: assets.knot(),
            cube: common::cube(),
        }
    }

    /// Renders demo frame 0 (animation time 0) with `shading`, exactly as
    /// `examples/demo.rs` builds it.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        shading: Shading,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = common::draws(&self.knot, &self.cube, 0.0, shading);
        let scene = Scene::new(common::camera(WIDTH, HEIGHT), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("demo frame renders")
    }

    /// The knot.
    pub fn knot(&self) -> &Mesh<'static> {
        &self.knot
    }

    /// The cube.
    pub fn cube(&self) -> &Mesh<'static> {
        &self.cube
    }
}

/// `layers` full-frame quads (two triangles each), flat shaded, from the
/// back (z = 0.8) to the front (z = -0.8).
pub struct FillScene {
    mesh: Mesh<'static>,
    /// A 32x32 checker texture (`common::checker_texels`), repeated four
    /// times across each quad by the mesh's texture coordinates.
    pub texture: microraster::texture::Texture<'static>,
}

impl FillScene {
    /// Builds the quads.
    pub fn new(layers: usize) -> Self {
        let mut positions = Vec::new();
        let mut colors = Vec::new();
        let mut triangles = Vec::new();
        let mut uvs = Vec::new();
        for l in 0..layers {
            let z = 0.8 - 1.6 * l as f32 / (layers.max(2) - 1) as f32;
            let b = positions.len() as u16;
            let (w, h) = (WIDTH as f32, HEIGHT as f32);
            // Counter-clockwise in NDC (y up): the front face.
            positions.extend([
                ndc(0.0, h, z),
                ndc(w, h, z),
                ndc(w, 0.0, z),
                ndc(0.0, 0.0, z),
            ]);
            let c = Rgb888::new(
                (40 + (25 * l) % 200) as u8,
                (200 - (20 * l) % 160) as u8,
                90,
            );
            colors.extend([c; 4]);
            uvs.extend([
                [fx(0.0), fx(3.0)],
                [fx(4.0), fx(3.0)],
                [fx(4.0), fx(0.0)],
                [fx(0.0), fx(0.0)],
            ]);
            triangles.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
        }
        let mesh = Mesh::new(leak(positions), leak(triangles))
            .and_then(|m| m.with_colors(leak(colors)))
            .and_then(|m| m.with_uvs(leak(uvs)))
            .expect("fill quads are valid");
        let texels = leak(common::checker_texels(32));
        let texture = microraster::texture::Texture::new(
            32,
            32,
            microraster::texture::Texels::Rgb565(texels),
        )
        .expect("the checker texture is valid");
        Self { mesh, texture }
    }

    /// Renders the quads through fragment shader `shader` (every draw
    /// [`Shading::Shader`], sampling `texture`), with the depth test.
    pub fn render_shader<S, F>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        shader: &F,
        texture: &microraster::texture::Texture<'_>,
        sink: &mut S,
    ) -> FrameStats
    where
        S: TileSink<Rgb565>,
        S::Error: core::fmt::Debug,
        F: FragmentShader<Rgb565>,
    {
        let draws = [Draw::new(&self.mesh)
            .shading(Shading::Shader)
            .texture(texture)];
        let scene = Scene::new(ndc_camera(), &draws).shader(shader);
        r.render(ws, &scene, sink).expect("fill frame renders")
    }

    /// Renders the quads with flat shading and the depth test.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut DemoWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = [Draw::new(&self.mesh).shading(Shading::Flat)];
        let scene = Scene::new(ndc_camera(), &draws);
        r.render(ws, &scene, sink).expect("fill frame renders")
    }
}

/// `count` copies of one triangle of about `area` pixels, scattered over
/// the frame (an R2 low-discrepancy sequence of sub-pixel offsets), all at
/// the same depth, Gouraud shaded with three vertex colours.
pub struct Copies {
    mesh: Mesh<'static>,
}

impl Copies {
    /// Builds the copies; `3 * count` must fit the vertex buffer of
    /// [`CopiesWorkspace`].
    pub fn new(area: f32, count: usize) -> Self {
        // The shape (0, 0), (0.4 s, s), (s, 0.25 s) has area 0.45 s^2 and
        // is counter-clockwise in NDC (clockwise on the y-down screen).
        let s = (area / 0.45).sqrt();
        let (room_x, room_y) = (WIDTH as f32 - s - 1.0, HEIGHT as f32 - s - 1.0);
        let (mut positions, mut colors, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..count {
            let fx = (0.5 + k as f32 * 0.754_877_7).fract();
            let fy = (0.5 + k as f32 * 0.569_840_3).fract();
            let (x, y) = (0.5 + fx * room_x.max(0.0), 0.5 + fy * room_y.max(0.0));
            let b = positions.len() as u16;
            positions.extend([
                ndc(x, y, 0.0),
                ndc(x + 0.4 * s, y + s, 0.0),
                ndc(x + s, y + 0.25 * s, 0.0),
            ]);
            colors.extend([
                Rgb888::new(250, 40, 40),
                Rgb888::new(40, 250, 40),
                Rgb888::new(40, 40, 250),
            ]);
            triangles.push([b, b + 1, b + 2]);
        }
        let mesh = Mesh::new(leak(positions), leak(triangles))
            .and_then(|m| m.with_colors(leak(colors)))
            .expect("triangle copies are valid");
        Self { mesh }
    }

    /// Number of triangles.
    pub fn count(&self) -> usize {
        self.mesh.triangle_count()
    }

    /// Renders every copy (Gouraud, `LessEqual`: overlapping copies at the
    /// same depth are all drawn).
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut CopiesWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = [Draw::new(&self.mesh)];
        let scene = Scene::new(ndc_camera(), &draws);
        r.render(ws, &scene, sink).expect("triangle copies render")
    }
}

/// The triangle sizes of the throughput benchmarks: (name, target pixel
/// area, copies per frame).
pub const TRIANGLE_SIZES: [(&str, f32, usize); 5] = [
    ("4px", 4.0, 8_000),
    ("32px", 32.0, 4_000),
    ("100px", 100.0, 2_000),
    ("1000px", 1_000.0, 400),
    ("10000px", 10_000.0, 100),
];

/// The demo frame rendered by [`euc`] 0.5: the same meshes, transforms,
/// camera, light and size; per-vertex (Lambert) colour interpolated over
/// the triangle, an `f32` depth buffer with a less-or-equal test, back
/// faces culled, `Rgb565` output into a full frame buffer.
///
/// euc has no index buffer with a vertex cache: its vertex shader runs for
/// each corner of each triangle. So that both renderers light and transform
/// each vertex once, a per-frame pass (part of the measured frame) computes
/// every vertex's clip position and colour in `f32`, and euc's vertex
/// shader only looks them up.
pub struct EucDemo {
    /// Model-space positions and normals of the knot then the cube.
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    /// Vertex count of the knot (the cube's vertices follow).
    knot_vertices: usize,
    /// Triangle corners, the cube's indices offset past the knot's.
    indices: Vec<u32>,
    /// Per frame: clip-space positions and colours (0..=255).
    clip: Vec<[f32; 4]>,
    rgb: Vec<(f32, f32, f32)>,
    /// The frame.
    pub color: euc::buffer::Buffer2d<u16>,
    /// The demo's clear colour as raw `Rgb565` bits.
    clear: u16,
    depth: euc::buffer::Buffer2d<f32>,
    demo: DemoScene,
}

struct EucPipe<'a> {
    clip: &'a [[f32; 4]],
    rgb: &'a [(f32, f32, f32)],
}

impl euc::Pipeline for EucPipe<'_> {
    type Vertex = u32;
    type VsOut = (f32, f32, f32);
    type Pixel = u16;

    #[inline(always)]
    fn vert(&self, i: &u32) -> ([f32; 4], Self::VsOut) {
        (self.clip[*i as usize], self.rgb[*i as usize])
    }

    #[inline(always)]
    fn frag(&self, c: &Self::VsOut) -> u16 {
        let (r, g, b) = (c.0 as u16, c.1 as u16, c.2 as u16);
        ((r >> 3) << 11) | ((g >> 2) << 5) | (b >> 3)
    }
}

impl Default for EucDemo {
    fn default() -> Self {
        Self::new()
    }
}

impl EucDemo {
    /// Converts the demo meshes to `f32` and allocates the frame.
    pub fn new() -> Self {
        let demo = DemoScene::new();
        let f = |v: &Vec3Fx| [v[0].to_num(), v[1].to_num(), v[2].to_num()];
        let (knot, cube) = (demo.knot(), demo.cube());
        let mut positions: Vec<[f32; 3]> = knot.positions().iter().map(f).collect();
        let mut normals: Vec<[f32; 3]> = knot.normals().unwrap().iter().map(f).collect();
        let knot_vertices = positions.len();
        positions.extend(cube.positions().iter().map(f));
        normals.extend(cube.normals().unwrap().iter().map(f));
        let mut indices = Vec::new();
        for t in knot.triangles().iter() {
            indices.extend(t);
        }
        for t in cube.triangles().iter() {
            indices.extend(t.map(|i| i + knot_vertices as u32));
        }
        let n = positions.len();
        let clear = common::DEMO_CLEAR.into_storage();
        Self {
            positions,
            normals,
            knot_vertices,
            indices,
            clip: vec![[0.0; 4]; n],
            rgb: vec![(0.0, 0.0, 0.0); n],
            color: euc::buffer::Buffer2d::new([WIDTH as usize, HEIGHT as usize], clear),
            clear,
            depth: euc::buffer::Buffer2d::new([WIDTH as usize, HEIGHT as usize], 1.0),
            demo,
        }
    }

    /// Renders demo frame 0: vertex pass, clear, draw.
    pub fn render(&mut self) {
        use euc::{Pipeline, Target};
        let draws = common::draws(self.demo.knot(), self.demo.cube(), 0.0, Shading::Gouraud);
        let camera = common::camera(WIDTH, HEIGHT);
        let light = common::light();
        let view_proj = camera.projection * camera.view;
        let ldir = light.direction.normalize().expect("demo light is valid");
        let ranges = [
            (0, self.knot_vertices),
            (self.knot_vertices, self.positions.len()),
        ];
        for (draw, (from, to)) in draws.iter().zip(ranges) {
            let m = (view_proj * draw.transform).m;
            let base = [draw.color.r(), draw.color.g(), draw.color.b()].map(|c| c as f32);
            for i in from..to {
                let p = self.positions[i];
                let mut c = [0.0f32; 4];
                for (r, out) in c.iter_mut().enumerate() {
                    *out = m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r];
                }
                self.clip[i] = c;
                let n = self.normals[i];
                let wn = draw.transform.transform_vector(Vec3::new(n[0], n[1], n[2]));
                let ndotl = (wn.dot(ldir) / wn.length()).max(0.0);
                let lit = |k: usize, amb: u8, lc: u8| {
                    (base[k] * (amb as f32 + lc as f32 * ndotl) / 255.0).min(255.0)
                };
                self.rgb[i] = (
                    lit(0, light.ambient.r(), light.color.r()),
                    lit(1, light.ambient.g(), light.color.g()),
                    lit(2, light.ambient.b(), light.color.b()),
                );
            }
        }
        self.color.clear(self.clear);
        self.depth.clear(1.0);
        EucPipe {
            clip: &self.clip,
            rgb: &self.rgb,
        }
        .draw::<euc::rasterizer::Triangles<'_, _, euc::rasterizer::BackfaceCullingEnabled>, _>(
            &self.indices,
            &mut self.color,
            Some(&mut self.depth),
        );
    }

    /// Pixels of the frame that are not the clear colour.
    pub fn covered(&self) -> usize {
        self.color
            .as_ref()
            .iter()
            .filter(|&&p| p != self.clear)
            .count()
    }
}

/// Quads per side of [`TerrainScene`]'s terrain.
pub const TERRAIN_QUADS: usize = 96;
/// Most triangles per cluster of [`TerrainScene`]'s terrain.
pub const TERRAIN_CLUSTER: usize = 64;

/// A terrain of 96x96 quads (18,432 triangles) imported in clusters of at
/// most 64 triangles, seen from a point on it looking across: what lies
/// behind and beside the view is culled cluster by cluster.
pub struct TerrainScene {
    clustered: Mesh<'static>,
    whole: Mesh<'static>,
}

impl TerrainScene {
    /// Imports the terrain, in clusters and without, and builds the meshes
    /// once (building one checks every index: set-up, not frame, work).
    pub fn new() -> Self {
        let obj = common::terrain_obj(TERRAIN_QUADS);
        let clustered: &'static common::ImportedModel =
            Box::leak(Box::new(common::ImportedModel::new(&obj, TERRAIN_CLUSTER)));
        let whole: &'static common::ImportedModel =
            Box::leak(Box::new(common::ImportedModel::new(&obj, 0)));
        Self {
            clustered: clustered.clustered(),
            whole: whole.whole(),
        }
    }

    /// The camera: above the terrain's centre, looking along -z.
    pub fn camera() -> Camera {
        let view = Mat4::look_at(
            Vec3::new(0.0, 5.0, 8.0),
            Vec3::new(-6.0, 1.0, -20.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .expect("a valid view");
        let proj = Mat4::perspective(1.0, WIDTH as f32 / HEIGHT as f32, 0.3, 60.0)
            .expect("a valid projection");
        Camera::new(view, proj)
    }

    /// Renders the terrain: imported in clusters, or imported without them
    /// (the file's triangle order, no copied vertices).
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut TerrainWorkspace,
        clustered: bool,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let mesh = if clustered {
            &self.clustered
        } else {
            &self.whole
        };
        let draws = [Draw::new(mesh).color(Rgb888::new(120, 200, 90))];
        let scene = Scene::new(Self::camera(), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("the terrain renders")
    }
}

/// Subdivision frequency of the rock: `20 n²` triangles, `10 n² + 2`
/// vertices (3,920 and 1,962).
pub const ROCK_FREQUENCY: usize = 14;

/// A workspace for the rock: all its vertices, all 80 tiles in one pass.
pub type RockWorkspace = Workspace<2048, 6144, 80>;

/// A small-triangle mesh like a scanned or modelled one: a geodesic sphere
/// of frequency [`ROCK_FREQUENCY`] (3,920 triangles), every vertex pushed
/// in or out by a smooth bulge and a small random bump, so that the
/// triangles differ in size and shape, with per-vertex normals. It fills
/// most of the 320x240 frame at 5 to 20 pixels per visible triangle.
pub struct RockScene {
    mesh: Mesh<'static>,
}

impl RockScene {
    /// Builds the mesh (in `f32` with IEEE basic operations and square
    /// roots only, so every machine makes the same one).
    pub fn new() -> Self {
        let (positions, normals, triangles) = rock(ROCK_FREQUENCY);
        let mesh = Mesh::new(leak(positions), leak(triangles))
            .and_then(|m| m.with_normals(leak(normals)))
            .expect("a valid rock");
        Self { mesh }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh<'static> {
        &self.mesh
    }

    /// The camera: the rock seen from its front, slightly above.
    pub fn camera() -> Camera {
        let view = Mat4::look_at(
            Vec3::new(0.0, 1.0, 3.6),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .expect("a valid view");
        let proj = Mat4::perspective(0.8, WIDTH as f32 / HEIGHT as f32, 0.5, 10.0)
            .expect("a valid projection");
        Camera::new(view, proj)
    }

    /// Renders the rock, Gouraud-shaded and lit like the demo.
    pub fn render<S: TileSink<Rgb565>>(
        &self,
        r: &mut BenchRenderer,
        ws: &mut RockWorkspace,
        sink: &mut S,
    ) -> FrameStats
    where
        S::Error: core::fmt::Debug,
    {
        let draws = [Draw::new(&self.mesh)
            .transform(Mat4::rotation_y(0.4))
            .color(Rgb888::new(170, 150, 120))];
        let scene = Scene::new(Self::camera(), &draws).light(common::light());
        r.render(ws, &scene, sink).expect("the rock renders")
    }
}

/// The rock's positions, normals and triangles (see [`RockScene`]). The
/// grid loops index by (i, j) because those are the point's coordinates.
#[allow(clippy::type_complexity, clippy::needless_range_loop)]
fn rock(n: usize) -> (Vec<Vec3Fx>, Vec<Vec3Fx>, Vec<[u16; 3]>) {
    // The icosahedron: 12 corners, 20 faces (counter-clockwise seen from
    // outside).
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let corners: [[f32; 3]; 12] = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let faces: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    // Vertices: the corners, then n - 1 per edge (shared by its two
    // faces, found by the edge's sorted corners), then the faces' inside
    // points.
    let mut points: Vec<[f32; 3]> = corners.to_vec();
    let mut edges: std::collections::BTreeMap<(usize, usize), usize> = Default::default();
    let lerp = |a: [f32; 3], b: [f32; 3], t: f32| [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t);
    let mut triangles = Vec::new();
    for f in faces {
        let [a, b, c] = f.map(|i| corners[i]);
        // Grid point (i, j): i steps from a towards b, j from a towards c.
        let mut index = vec![vec![0usize; n + 1]; n + 1];
        for i in 0..=n {
            for j in 0..=n - i {
                let k = n - i - j;
                index[i][j] = if i == n {
                    f[1]
                } else if j == n {
                    f[2]
                } else if k == n {
                    f[0]
                } else if j == 0 || i == 0 || k == 0 {
                    // On an edge: from corner p to corner q at step s.
                    let (p, q, s) = if j == 0 {
                        (f[0], f[1], i)
                    } else if i == 0 {
                        (f[0], f[2], j)
                    } else {
                        (f[1], f[2], j)
                    };
                    let (lo, hi, s) = if p < q { (p, q, s) } else { (q, p, n - s) };
                    let base = *edges.entry((lo, hi)).or_insert_with(|| {
                        let base = points.len();
                        for t in 1..n {
                            points.push(lerp(corners[lo], corners[hi], t as f32 / n as f32));
                        }
                        base
                    });
                    base + s - 1
                } else {
                    let ab = lerp(a, b, i as f32 / n as f32);
                    let p = [0, 1, 2].map(|m| ab[m] + (c[m] - a[m]) * j as f32 / n as f32);
                    points.push(p);
                    points.len() - 1
                };
            }
        }
        for i in 0..n {
            for j in 0..n - i {
                triangles.push([index[i][j], index[i + 1][j], index[i][j + 1]]);
                if i + j + 1 < n {
                    triangles.push([index[i + 1][j], index[i + 1][j + 1], index[i][j + 1]]);
                }
            }
        }
    }
    // On the unit sphere, then displaced: a smooth bulge from three fixed
    // directions plus a small bump from a hash of the vertex number.
    let unit = |p: [f32; 3]| {
        let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|v| v / l)
    };
    let dirs = [[0.6, 0.8, 0.0], [-0.48, 0.0, 0.877], [0.0, -0.6, -0.8]];
    let positions: Vec<[f32; 3]> = points
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let u = unit(p);
            let bulge: f32 = dirs
                .iter()
                .map(|d| {
                    let t = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
                    t * t * t
                })
                .sum();
            let mut h = (i as u32).wrapping_mul(0x9e37_79b9) ^ 0x5bd1_e995;
            h ^= h >> 15;
            h = h.wrapping_mul(0x2c1b_3c6d);
            h ^= h >> 12;
            let bump = (h & 0xffff) as f32 / 65_535.0 - 0.5;
            let r = 1.0 + 0.18 * bulge + 0.05 * bump;
            u.map(|v| v * r)
        })
        .collect();
    // Normals: the area-weighted face normals around each vertex.
    let mut normals = vec![[0f32; 3]; positions.len()];
    for t in &triangles {
        let [a, b, c] = t.map(|i| positions[i]);
        let (e1, e2) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let nrm = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        for &i in t {
            for k in 0..3 {
                normals[i][k] += nrm[k];
            }
        }
    }
    let to_fx = |p: [f32; 3]| p.map(fx);
    (
        positions.iter().map(|&p| to_fx(p)).collect(),
        normals.iter().map(|&p| to_fx(unit(p))).collect(),
        triangles.iter().map(|t| t.map(|i| i as u16)).collect(),
    )
}
