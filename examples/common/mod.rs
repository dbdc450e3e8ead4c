//! The demo scene, shared by the demo, the tests and the benchmarks: a lit
//! torus knot of 4,000 triangles next to a spinning cube.
#![allow(dead_code)]

use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shapes::{
    torus_knot, torus_knot_size, CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES,
};

mod png_file;
// Each example or test that includes this file uses a different subset.
#[allow(unused_imports)]
pub use png_file::{render_png, write_png};

#[path = "../demo_scene/mod.rs"]
mod demo_scene;
use demo_scene::checker;
/// The `rock` scene's mesh, camera and draw, shared with the RP2040
/// benchmark firmware (`examples/rp2040_bench.rs`).
#[path = "../rock_scene/mod.rs"]
pub mod rock_scene;

// Host-only parts that only some includers use: the benchmark scenes, the
// shading gallery and the demo's command line.
pub mod demo_args;
pub mod gallery;
pub mod scenes;
// Each example or test that includes this file uses a different subset.
#[allow(unused_imports)]
pub use demo_scene::{
    draws, light, textured_draws, DEMO_CLEAR, KNOT_P, KNOT_Q, KNOT_RADIUS, KNOT_SEGMENTS,
    KNOT_SIDES, KNOT_TUBE, KNOT_UV_REPEATS,
};

/// Vertices of the whole demo scene (knot + cube).
pub const SCENE_VERTICES: usize = KNOT_SEGMENTS * KNOT_SIDES + 24;

/// Generated mesh data of the demo.
pub struct DemoAssets {
    pub knot_positions: Vec<Vec3Fx>,
    pub knot_normals: Vec<Vec3Fx>,
    pub knot_triangles: Vec<[u16; 3]>,
}

impl DemoAssets {
    pub fn new() -> Self {
        Self::with_knot(KNOT_SEGMENTS, KNOT_SIDES)
    }

    /// The demo's knot with `segments` x `sides` quads (the demo's is
    /// [`KNOT_SEGMENTS`] x [`KNOT_SIDES`]).
    pub fn with_knot(segments: usize, sides: usize) -> Self {
        let (nv, nt) = torus_knot_size(segments, sides);
        let mut p = vec![[I16F16::ZERO; 3]; nv];
        let mut n = vec![[I16F16::ZERO; 3]; nv];
        let mut t = vec![[0u16; 3]; nt];
        torus_knot(
            KNOT_P,
            KNOT_Q,
            KNOT_RADIUS,
            KNOT_TUBE,
            segments,
            sides,
            &mut p,
            &mut n,
            &mut t,
        )
        .expect("demo knot parameters are valid");
        Self {
            knot_positions: p,
            knot_normals: n,
            knot_triangles: t,
        }
    }

    pub fn knot(&self) -> Mesh<'_> {
        Mesh::new(&self.knot_positions, &self.knot_triangles)
            .and_then(|m| m.with_normals(&self.knot_normals))
            .expect("generated knot is valid")
    }
}

pub fn cube() -> Mesh<'static> {
    Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES)
        .and_then(|m| m.with_normals(&CUBE_NORMALS))
        .expect("cube is valid")
}

/// The demo camera for a `width` x `height` frame.
pub fn camera(width: u32, height: u32) -> Camera {
    demo_scene::camera(width, height).expect("the demo camera is valid for a non-empty frame")
}

/// A floor through the near plane and a wall far beyond the guard band: with
/// the demo's knot and cube, a scene whose triangles are clipped in every
/// binning pass and re-scanned tile (used by the tests).
pub struct ClippedExtras {
    floor_positions: [Vec3Fx; 4],
    floor_colors: [embedded_graphics::pixelcolor::Rgb888; 4],
    wall_positions: [Vec3Fx; 4],
}

/// The two triangles of a quad.
pub const QUAD: [[u16; 3]; 2] = [[0, 2, 1], [0, 3, 2]];

impl ClippedExtras {
    pub fn new() -> Self {
        use embedded_graphics::pixelcolor::Rgb888;
        let p = |x: f32, y: f32, z: f32| {
            [
                I16F16::from_num(x),
                I16F16::from_num(y),
                I16F16::from_num(z),
            ]
        };
        Self {
            floor_positions: [
                p(-6.0, -0.9, -8.0),
                p(6.0, -0.9, -8.0),
                p(6.0, -0.9, 9.0),
                p(-6.0, -0.9, 9.0),
            ],
            floor_colors: [
                Rgb888::new(90, 90, 90),
                Rgb888::new(200, 60, 60),
                Rgb888::new(60, 200, 60),
                Rgb888::new(60, 60, 200),
            ],
            wall_positions: [
                p(-3000.0, -0.2, -6.0),
                p(3000.0, -0.2, -6.0),
                p(3000.0, 0.1, -6.5),
                p(-3000.0, 0.1, -6.5),
            ],
        }
    }

    pub fn floor(&self) -> Mesh<'_> {
        Mesh::new(&self.floor_positions, &QUAD)
            .and_then(|m| m.with_colors(&self.floor_colors))
            .expect("the floor is valid")
    }

    pub fn wall(&self) -> Mesh<'_> {
        Mesh::new(&self.wall_positions, &QUAD).expect("the wall is valid")
    }
}

/// The clipped scene's draws: knot (Gouraud), floor, cube (flat), wall.
pub fn clipped_draws<'a>(
    knot: &'a Mesh<'a>,
    cube: &'a Mesh<'a>,
    floor: &'a Mesh<'a>,
    wall: &'a Mesh<'a>,
) -> [Draw<'a>; 4] {
    let [k, c] = draws(knot, cube, 2.1, Shading::Gouraud);
    [
        k,
        Draw::new(floor),
        c.shading(Shading::Flat),
        Draw::new(wall).color(embedded_graphics::pixelcolor::Rgb888::new(250, 250, 120)),
    ]
}

/// The demo scene (knot and cube, Gouraud, lit) at animation time `t`,
/// framed for `size`, handed to `f`.
pub fn with_demo_scene<R>(t: f32, size: Size, f: impl FnOnce(&Scene<'_>) -> R) -> R {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, t, Shading::Gouraud);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    f(&scene)
}

/// The clipped scene at 150x110 (the demo's knot and cube, Gouraud, at
/// time 2.1, with [`ClippedExtras`]' floor and wall; no culling needed to
/// see the clipped triangles), handed to `f` with its size.
pub fn with_clipped_scene<R>(f: impl FnOnce(&Scene<'_>, Size) -> R) -> R {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let extras = ClippedExtras::new();
    let (floor, wall) = (extras.floor(), extras.wall());
    let d = clipped_draws(&knot, &cube, &floor, &wall);
    let size = Size::new(150, 110);
    let scene = Scene::new(camera(size.width, size.height), &d).light(light());
    f(&scene, size)
}

/// A procedural `size` x `size` Rgb565 texture (row-major, as
/// `Texels::Rgb565` reads): a checkerboard of 8-texel squares, warm and
/// cool, shaded by a diagonal gradient, with a bright border one texel wide
/// so that every repeat's edge shows.
pub fn checker_texels(size: u32) -> Vec<u16> {
    (0..size * size)
        .map(|i| checker::checker_texel(i % size, i / size, size))
        .collect()
}

/// Texture coordinates for the demo knot ([`demo_scene::knot_uv`]).
pub fn knot_uvs(u_repeats: f32, v_repeats: f32) -> Vec<[I16F16; 2]> {
    knot_uvs_of((KNOT_SEGMENTS, KNOT_SIDES), u_repeats, v_repeats)
}

/// Texture coordinates for a knot of `(segments, sides)`
/// ([`demo_scene::knot_uv_of`]).
pub fn knot_uvs_of(knot: (usize, usize), u_repeats: f32, v_repeats: f32) -> Vec<[I16F16; 2]> {
    let mut out = Vec::with_capacity(knot.0 * knot.1);
    for i in 0..knot.0 {
        for j in 0..knot.1 {
            out.push(demo_scene::knot_uv_of(i, j, knot, u_repeats, v_repeats));
        }
    }
    out
}

/// The cube with texture coordinates (each face shows the texture once).
pub fn textured_cube() -> Mesh<'static> {
    cube()
        .with_uvs(&microraster::shapes::CUBE_UVS)
        .expect("the cube's coordinates match its vertices")
}

/// A rolling terrain of `n` x `n` quads (`2 n^2` triangles) over
/// `-n/2 .. n/2` in x and z, as OBJ text: two groups (the near and far
/// halves), so that clustering stays within groups. The heights come from
/// integer tent waves, the same on every machine.
pub fn terrain_obj(n: usize) -> String {
    use std::fmt::Write;
    let tent = |v: i64, period: i64| {
        let m = v.rem_euclid(period);
        (m.min(period - m)) as f32 / period as f32
    };
    let mut s = String::new();
    for z in 0..=n as i64 {
        for x in 0..=n as i64 {
            let h = 9.0 * tent(x, 30) * tent(z, 26) + 1.5 * tent(x + 2 * z, 11) - 2.0;
            let (px, pz) = (x as f32 - n as f32 / 2.0, z as f32 - n as f32 / 2.0);
            let _ = writeln!(s, "v {px} {h:.4} {pz}");
        }
    }
    let row = n + 1;
    for (name, zs) in [("near", 0..n / 2), ("far", n / 2..n)] {
        let _ = writeln!(s, "g {name}");
        for z in zs {
            for x in 0..n {
                // OBJ indices are 1-based; counter-clockwise seen from
                // above (+y).
                let a = z * row + x + 1;
                let (b, c, d) = (a + 1, a + row + 1, a + row);
                let _ = writeln!(s, "f {a} {d} {c} {b}");
            }
        }
    }
    s
}

/// A model imported from OBJ text by the workspace importer, held as the
/// 16.16 arrays its generated source would hold, with its clusters.
pub struct ImportedModel {
    pub positions: Vec<Vec3Fx>,
    pub normals: Vec<Vec3Fx>,
    pub triangles: Vec<[u16; 3]>,
    pub clusters: Vec<microraster::mesh::Cluster>,
}

impl ImportedModel {
    /// Imports `obj` at its own scale (`Fit::Keep`), in clusters of at
    /// most `cluster_triangles` triangles (0: no clusters).
    pub fn new(obj: &str, cluster_triangles: usize) -> Self {
        use microraster_import::{parse_obj, Fit, ObjOptions};
        let options = ObjOptions::default()
            .with_fit(Fit::Keep)
            .with_cluster_triangles(cluster_triangles);
        let model = parse_obj(obj, std::path::Path::new("terrain.obj"), |_| None, &options)
            .expect("the OBJ text imports");
        let fx = |v: [i32; 3]| v.map(I16F16::from_bits);
        let clusters = model
            .clusters
            .iter()
            .zip(model.cluster_bounds_fixed())
            .map(|(c, [lo, hi])| {
                microraster::mesh::Cluster::new(
                    c.triangles.len() as u32,
                    c.vertices.start as u32,
                    c.vertices.len() as u32,
                    fx(lo),
                    fx(hi),
                )
            })
            .collect();
        Self {
            positions: model.positions_fixed().into_iter().map(fx).collect(),
            normals: model.normals_fixed().into_iter().map(fx).collect(),
            triangles: model
                .triangles
                .iter()
                .map(|t| t.map(|i| i as u16))
                .collect(),
            clusters,
        }
    }

    /// The mesh, without its clusters.
    pub fn whole(&self) -> Mesh<'_> {
        Mesh::new(&self.positions, &self.triangles)
            .and_then(|m| m.with_normals(&self.normals))
            .expect("the imported model is a valid mesh")
    }

    /// The mesh with its clusters.
    pub fn clustered(&self) -> Mesh<'_> {
        self.whole()
            .with_clusters(&self.clusters)
            .expect("the importer's clusters are valid")
    }
}
