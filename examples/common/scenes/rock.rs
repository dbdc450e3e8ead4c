//! [`RockScene`]: a geodesic sphere of small, uneven triangles.

use super::{fx, leak, BenchRenderer, HEIGHT, WIDTH};
use crate::common;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;

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
