//! Imported assets on the renderer's side: the Rust source that
//! `microraster-import` writes for `import/tests/data/cube.obj`, and for
//! `examples/assets/rocket.obj` in clusters, is checked in
//! (`tests/data/imported_cube.rs`, `tests/data/imported_rocket_clusters.rs`,
//! regenerated with `BLESS=1 cargo test --test import`), compiles as-is
//! (this file `include!`s it), holds exactly the importer's data, and
//! renders: the cube the same image as the same cube built in code, the
//! rocket's clusters the same image with and without culling; and its
//! count constants size a workspace exactly.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster_import::{load_obj, model_to_rust, Fit, ObjOptions};
use std::path::{Path, PathBuf};
use support::Capture;

/// The generated source, compiled here as a firmware would `include!` it.
#[allow(dead_code)]
mod imported {
    include!("data/imported_cube.rs");
}

/// The rocket in clusters of at most 8 triangles, compiled the same way.
#[allow(dead_code)]
mod rocket {
    include!("data/imported_rocket_clusters.rs");
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn cube_obj() -> PathBuf {
    root().join("import/tests/data/cube.obj")
}

fn options() -> ObjOptions {
    ObjOptions::new().with_fit(Fit::Keep)
}

/// `source` equals the checked-in `tests/data/{name}.rs` (written with
/// `BLESS=1`).
fn assert_checked_in(name: &str, source: &str) {
    let path = root().join(format!("tests/data/{name}.rs"));
    if std::env::var_os("BLESS").is_some() {
        std::fs::write(&path, source).unwrap();
    }
    let checked_in = std::fs::read_to_string(&path).unwrap();
    assert!(
        checked_in == source,
        "tests/data/{name}.rs is stale: BLESS=1 cargo test --test import"
    );
}

#[test]
fn checked_in_source_is_what_the_importer_writes() {
    let model = load_obj(&cube_obj(), &options()).expect("the test cube imports");
    let source = model_to_rust(&model, "imported_cube").expect("a valid name");
    assert_checked_in("imported_cube", &source);
}

fn rocket_model() -> microraster_import::Model {
    let options = ObjOptions::new().with_cluster_triangles(8);
    load_obj(&root().join("examples/assets/rocket.obj"), &options).expect("the rocket imports")
}

#[test]
fn clustered_source_is_what_the_importer_writes_and_its_clusters_hold() {
    let model = rocket_model();
    let source = model_to_rust(&model, "imported_rocket_clusters").expect("a valid name");
    assert_checked_in("imported_rocket_clusters", &source);
    assert_eq!(
        rocket::IMPORTED_ROCKET_CLUSTERS_CLUSTERS.len(),
        model.clusters.len()
    );
    assert!(
        model.clusters.len() >= 10,
        "{} clusters",
        model.clusters.len()
    );
    // The whole model, and each group with its run of clusters, pass the
    // mesh's cluster checks as written to flash.
    let (p, t) = (
        &rocket::IMPORTED_ROCKET_CLUSTERS_POSITIONS,
        &rocket::IMPORTED_ROCKET_CLUSTERS_TRIANGLES,
    );
    let clusters = &rocket::IMPORTED_ROCKET_CLUSTERS_CLUSTERS;
    Mesh::new(p, t)
        .and_then(|m| m.with_clusters(clusters))
        .expect("the whole rocket takes its clusters");
    for (&(_, first, count), &(c0, cn)) in rocket::IMPORTED_ROCKET_CLUSTERS_GROUPS
        .iter()
        .zip(&rocket::IMPORTED_ROCKET_CLUSTERS_GROUP_CLUSTERS)
    {
        Mesh::new(p, &t[first..first + count])
            .and_then(|m| m.with_clusters(&clusters[c0..c0 + cn]))
            .expect("each group takes its clusters");
    }
}

/// The rocket's groups as draws of their own, with their clusters, seen
/// close up so that part of it is out of view: culling removes clusters and
/// leaves the image as it was.
#[test]
fn imported_clusters_cull_without_changing_the_image() {
    let (p, t, n) = (
        &rocket::IMPORTED_ROCKET_CLUSTERS_POSITIONS,
        &rocket::IMPORTED_ROCKET_CLUSTERS_TRIANGLES,
        &rocket::IMPORTED_ROCKET_CLUSTERS_NORMALS,
    );
    let clusters = &rocket::IMPORTED_ROCKET_CLUSTERS_CLUSTERS;
    let meshes: Vec<Mesh<'static>> = rocket::IMPORTED_ROCKET_CLUSTERS_GROUPS
        .iter()
        .zip(&rocket::IMPORTED_ROCKET_CLUSTERS_GROUP_CLUSTERS)
        .map(|(&(_, first, count), &(c0, cn))| {
            Mesh::new(p, &t[first..first + count])
                .and_then(|m| m.with_normals(n))
                .and_then(|m| m.with_clusters(&clusters[c0..c0 + cn]))
                .unwrap()
        })
        .collect();
    let draws: Vec<Draw<'_>> = meshes
        .iter()
        .zip(rocket::IMPORTED_ROCKET_CLUSTERS_GROUP_COLORS)
        .map(|(m, c)| Draw::new(m).color(c).transform(Mat4::rotation_z(1.2)))
        .collect();
    let size = Size::new(96, 72);
    let view = Mat4::look_at(
        Vec3::new(0.2, 0.6, 1.1),
        Vec3::new(0.1, 0.4, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    )
    .unwrap();
    let proj = Mat4::perspective(0.7, 96.0 / 72.0, 0.1, 10.0).unwrap();
    let scene = Scene::new(Camera::new(view, proj), &draws).light(common::light());
    let render = |cull: bool| {
        let cfg = Config::new(size, common::DEMO_CLEAR).frustum_cull(cull);
        let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
        let mut ws: Box<Workspace<1024, 1024, 16>> = Box::default();
        let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
        let s = r
            .render(&mut ws, &scene, &mut cap)
            .expect("the rocket renders");
        (cap, s)
    };
    let ((with, s1), (without, s0)) = (render(true), render(false));
    assert!(with.pixels == without.pixels, "culling changed the image");
    assert_eq!(s1.drawn, s0.drawn);
    assert!(s1.drawn > 0, "{s1}");
    assert!(s1.clusters_culled > 0, "{s1}");
    assert!(s1.vertices < s0.vertices, "{s1} / {s0}");
}

#[test]
fn compiled_statics_hold_the_imported_data() {
    let model = load_obj(&cube_obj(), &options()).unwrap();
    let bits = |v: &[[I16F16; 3]]| v.iter().map(|p| p.map(|c| c.to_bits())).collect::<Vec<_>>();
    assert_eq!(
        bits(&imported::IMPORTED_CUBE_POSITIONS),
        model.positions_fixed()
    );
    assert_eq!(
        bits(&imported::IMPORTED_CUBE_NORMALS),
        model.normals_fixed()
    );
    let tris: Vec<[u32; 3]> = imported::IMPORTED_CUBE_TRIANGLES
        .iter()
        .map(|t| t.map(u32::from))
        .collect();
    assert_eq!(tris, model.triangles);
    assert_eq!(
        imported::IMPORTED_CUBE_GROUP_COLORS[0],
        Rgb888::new(255, 0, 0)
    );
    // The mesh checks pass on the flash-resident arrays.
    Mesh::new(
        &imported::IMPORTED_CUBE_POSITIONS,
        &imported::IMPORTED_CUBE_TRIANGLES,
    )
    .and_then(|m| m.with_normals(&imported::IMPORTED_CUBE_NORMALS))
    .expect("the imported cube is a valid mesh");
}

/// The cube of `cube.obj` written out by hand: its six faces (corners as in
/// the file, counter-clockwise from outside) with their normals, each quad
/// split as a fan from its first corner.
fn cube_in_code() -> (Vec<Vec3Fx>, Vec<Vec3Fx>, Vec<[u16; 3]>) {
    let corner = |k: usize| {
        let c = [
            [-1, -1, -1],
            [1, -1, -1],
            [1, 1, -1],
            [-1, 1, -1],
            [-1, -1, 1],
            [1, -1, 1],
            [1, 1, 1],
            [-1, 1, 1],
        ][k - 1];
        c.map(I16F16::from_num)
    };
    let faces: [([usize; 4], [i32; 3]); 6] = [
        ([1, 4, 3, 2], [0, 0, -1]),
        ([5, 6, 7, 8], [0, 0, 1]),
        ([1, 2, 6, 5], [0, -1, 0]),
        ([4, 8, 7, 3], [0, 1, 0]),
        ([1, 5, 8, 4], [-1, 0, 0]),
        ([2, 3, 7, 6], [1, 0, 0]),
    ];
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (corners, n) in faces {
        let base = positions.len() as u16;
        for k in corners {
            positions.push(corner(k));
            normals.push(n.map(I16F16::from_num));
        }
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    (positions, normals, triangles)
}

fn render(mesh: &Mesh<'_>, raster: Rasterizer) -> Capture<Rgb565> {
    let size = Size::new(96, 72);
    let draws = [Draw::new(mesh)
        .transform(
            Mat4::rotation_y(0.6) * Mat4::rotation_x(0.4) * Mat4::scale(Vec3::new(0.8, 0.8, 0.8)),
        )
        .color(Rgb888::new(255, 0, 0))];
    let scene = Scene::new(common::camera(size.width, size.height), &draws).light(common::light());
    let mut r: Renderer<Rgb565, 32, 32> =
        Renderer::new(Config::new(size, common::DEMO_CLEAR).rasterizer(raster));
    let mut ws: Box<Workspace<64, 256, 16>> = Box::default();
    let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
    r.render(&mut ws, &scene, &mut cap)
        .expect("the cube renders");
    cap
}

#[test]
fn imported_cube_renders_like_the_cube_built_in_code() {
    let imported = Mesh::new(
        &imported::IMPORTED_CUBE_POSITIONS,
        &imported::IMPORTED_CUBE_TRIANGLES,
    )
    .and_then(|m| m.with_normals(&imported::IMPORTED_CUBE_NORMALS))
    .unwrap();
    let (positions, normals, triangles) = cube_in_code();
    let in_code = Mesh::new(&positions, &triangles)
        .and_then(|m| m.with_normals(&normals))
        .unwrap();
    for raster in [Rasterizer::Scanline, Rasterizer::Hilbert] {
        let a = render(&imported, raster);
        let b = render(&in_code, raster);
        let lit = a
            .pixels
            .iter()
            .filter(|&&c| c != common::DEMO_CLEAR)
            .count();
        assert!(lit > 1000, "the cube covers {lit} pixels");
        assert!(
            a.pixels == b.pixels,
            "{raster:?}: imported and hand-built cubes differ"
        );
    }
}

/// `meshes` as one draw each, turned like the rocket above, into `ws`.
fn render_draws<const V: usize>(
    meshes: &[Mesh<'_>],
    ws: &mut Workspace<V, 1024, 16>,
) -> Result<Capture<Rgb565>, RenderError<core::convert::Infallible>> {
    let size = Size::new(96, 72);
    let draws: Vec<Draw<'_>> = meshes
        .iter()
        .map(|m| Draw::new(m).transform(Mat4::rotation_z(1.2)))
        .collect();
    let scene = Scene::new(common::camera(size.width, size.height), &draws).light(common::light());
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(Config::new(size, common::DEMO_CLEAR));
    let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
    r.render(ws, &scene, &mut cap).map(|_| cap)
}

/// The counts that the generated source gives as constants size a
/// firmware's workspace: the rocket's groups, each its own draw on the
/// prefix of the vertex arrays that its triangles use, need exactly
/// `_GROUP_DRAWS_VERTEX_COUNT` vertices, and one fewer is refused; they
/// show what draws on the whole arrays show.
#[test]
fn generated_counts_size_the_workspace() {
    use rocket::*;
    const VERTICES: usize = IMPORTED_ROCKET_CLUSTERS_GROUP_DRAWS_VERTEX_COUNT;
    const ALL: usize = IMPORTED_ROCKET_CLUSTERS_VERTEX_COUNT;
    let (p, t, n) = (
        &IMPORTED_ROCKET_CLUSTERS_POSITIONS,
        &IMPORTED_ROCKET_CLUSTERS_TRIANGLES,
        &IMPORTED_ROCKET_CLUSTERS_NORMALS,
    );
    assert_eq!(
        (ALL, IMPORTED_ROCKET_CLUSTERS_TRIANGLE_COUNT),
        (p.len(), t.len())
    );
    let clusters = &IMPORTED_ROCKET_CLUSTERS_CLUSTERS;
    let groups = |prefix: bool| -> Vec<Mesh<'static>> {
        (0..IMPORTED_ROCKET_CLUSTERS_GROUPS.len())
            .map(|g| {
                let (_, first, count) = IMPORTED_ROCKET_CLUSTERS_GROUPS[g];
                assert_eq!(count, IMPORTED_ROCKET_CLUSTERS_GROUP_TRIANGLE_COUNTS[g]);
                let (c0, cn) = IMPORTED_ROCKET_CLUSTERS_GROUP_CLUSTERS[g];
                let v = if prefix {
                    IMPORTED_ROCKET_CLUSTERS_GROUP_VERTEX_COUNTS[g]
                } else {
                    ALL
                };
                Mesh::new(&p[..v], &t[first..first + count])
                    .and_then(|m| m.with_normals(&n[..v]))
                    .and_then(|m| m.with_clusters(&clusters[c0..c0 + cn]))
                    .expect("a group's prefix holds its vertices")
            })
            .collect()
    };
    let prefix = groups(true);
    assert!(VERTICES < prefix.len() * ALL, "the prefixes save vertices");
    let mut ws: Box<Workspace<VERTICES, 1024, 16>> = Box::default();
    let image = render_draws(&prefix, &mut ws).expect("the workspace holds every group");
    let mut large: Box<Workspace<{ 4 * ALL }, 1024, 16>> = Box::default();
    let whole = render_draws(&groups(false), &mut large).expect("4 groups of all vertices");
    let lit = image.pixels.iter().filter(|&&c| c != common::DEMO_CLEAR);
    assert!(lit.count() > 100, "the rocket is in view");
    assert!(image.pixels == whole.pixels, "prefix draws differ");
    let mut small: Box<Workspace<{ VERTICES - 1 }, 1024, 16>> = Box::default();
    assert!(matches!(
        render_draws(&prefix, &mut small),
        Err(RenderError::VertexCapacity { needed, capacity })
            if needed == VERTICES && capacity == VERTICES - 1
    ));
    // The whole model as one draw needs `_VERTEX_COUNT`.
    let one = Mesh::new(p, t).and_then(|m| m.with_normals(n)).unwrap();
    let mut exact: Box<Workspace<ALL, 1024, 16>> = Box::default();
    render_draws(&[one], &mut exact).expect("one draw of every vertex");
}
