//! Frustum culling of whole draws and of mesh clusters: on random camera
//! poses over a field of meshes, and over a terrain imported in clusters,
//! rendering with culling and without gives the same image (and the same
//! triangles drawn and pixels shaded), while culling does remove the draws
//! and clusters out of view, with their vertex work.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;
use support::Capture;

const W: u32 = 96;
const H: u32 = 72;

fn render(scene: &Scene<'_>, cull: bool) -> (Capture<Rgb565>, FrameStats) {
    render_pool::<32768>(scene, cull)
}

/// Renders `scene` with culling on or off, into a workspace whose bin pool
/// holds `B` entries (a small pool makes tiles rescan every triangle).
fn render_pool<const B: usize>(scene: &Scene<'_>, cull: bool) -> (Capture<Rgb565>, FrameStats) {
    let cfg = Config::new(Size::new(W, H), Rgb565::new(0, 0, 0)).frustum_cull(cull);
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
    let mut ws: Box<Workspace<16384, B, 16>> = Box::new(Workspace::new());
    let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
    let s = r
        .render(&mut ws, scene, &mut cap)
        .expect("the scene renders");
    (cap, s)
}

/// Renders `scene` with culling and without, checks that the images and
/// the triangles drawn are the same and that every triangle is accounted
/// for, and returns the image and both statistics.
fn with_and_without(scene: &Scene<'_>, pose: u32) -> (Capture<Rgb565>, FrameStats, FrameStats) {
    let (with, s1) = render(scene, true);
    let (without, s0) = render(scene, false);
    assert!(
        with.pixels == without.pixels,
        "pose {pose}: culling changed the image"
    );
    assert_eq!(
        (s1.drawn, s1.pixels_shaded, s1.clipped, s1.culled),
        (s0.drawn, s0.pixels_shaded, s0.clipped, s0.culled),
        "pose {pose}"
    );
    assert_eq!((s0.draws_culled, s0.clusters_culled), (0, 0));
    assert_eq!(
        s1.triangles_in,
        s1.culled + s1.rejected + s1.drawn,
        "pose {pose}: every triangle accounted for"
    );
    (with, s1, s0)
}

#[test]
fn culling_never_changes_the_image_and_removes_what_is_out_of_view() {
    let assets = DemoAssets::new();
    let knot = assets.knot();
    let cube = cube();
    let mut x = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f32 / (1u64 << 53) as f32
    };
    // A field of cubes on a 6x6 grid, a few knots among them, each turned
    // and scaled its own way; some straddle the edges of every view.
    let mut draws = Vec::new();
    for i in 0..36 {
        let (gx, gz) = ((i % 6) as f32 * 3.0 - 7.5, (i / 6) as f32 * 3.0 - 7.5);
        let mesh = if i % 7 == 3 { &knot } else { &cube };
        let s = 0.3 + 0.5 * next();
        draws.push(
            Draw::new(mesh)
                .transform(
                    Mat4::translation(Vec3::new(gx, next() * 2.0 - 1.0, gz))
                        * Mat4::rotation_y(next() * 6.0)
                        * Mat4::scale(Vec3::new(s, s * (0.5 + next()), s)),
                )
                .color(Rgb888::new(
                    (80.0 + 170.0 * next()) as u8,
                    (80.0 + 170.0 * next()) as u8,
                    200,
                )),
        );
    }
    let (mut culled, mut visible, mut poses) = (0u32, 0u32, 0u32);
    for pose in 0..48 {
        let eye = Vec3::new(
            next() * 24.0 - 12.0,
            0.5 + next() * 6.0,
            next() * 24.0 - 12.0,
        );
        let target = Vec3::new(next() * 10.0 - 5.0, next() * 2.0 - 1.0, next() * 10.0 - 5.0);
        let Some(view) = Mat4::look_at(eye, target, Vec3::new(0.0, 1.0, 0.0)) else {
            continue;
        };
        let fovy = 0.5 + next() * 1.2;
        let near = 0.2 + next() * 2.0;
        let proj = Mat4::perspective(fovy, W as f32 / H as f32, near, near + 4.0 + next() * 30.0)
            .expect("a valid projection");
        let scene = Scene::new(Camera::new(view, proj), &draws).light(light());
        let (_, s1, _) = with_and_without(&scene, pose);
        culled += s1.draws_culled;
        visible += draws.len() as u32 - s1.draws_culled;
        poses += 1;
    }
    assert!(poses >= 40);
    // The views see part of the field: culling must have removed a good
    // share of the draws, and kept a good share.
    assert!(
        culled > 10 * poses,
        "{culled} draws culled over {poses} poses"
    );
    assert!(
        visible > 3 * poses,
        "{visible} draws kept over {poses} poses"
    );
}

/// A terrain imported in clusters, seen from random places on it: culling
/// clusters never changes the image (nor the triangles drawn), also when
/// tiles are drawn by rescanning every triangle; it removes the clusters out
/// of view, with their vertices; and the clusters render exactly what the
/// same mesh renders whole.
#[test]
fn culling_clusters_never_changes_the_image_and_skips_their_vertices() {
    let model = ImportedModel::new(&terrain_obj(40), 48);
    let clustered = model.clustered();
    let whole = model.whole();
    let n_clusters = model.clusters.len() as u32;
    assert!(n_clusters >= 3200 / 48, "{n_clusters} clusters");
    let mut r = uniform();
    let (mut culled, mut kept, mut saved, mut poses) = (0u32, 0u32, 0u32, 0u32);
    for pose in 0..40 {
        let eye = Vec3::new(r() * 36.0 - 18.0, 0.8 + r() * 5.0, r() * 36.0 - 18.0);
        let target = Vec3::new(r() * 40.0 - 20.0, r() * 2.0 - 1.5, r() * 40.0 - 20.0);
        let Some(view) = Mat4::look_at(eye, target, Vec3::new(0.0, 1.0, 0.0)) else {
            continue;
        };
        let near = 0.1 + r();
        let proj = Mat4::perspective(
            0.6 + r(),
            W as f32 / H as f32,
            near,
            near + 8.0 + r() * 40.0,
        )
        .expect("a valid projection");
        let camera = Camera::new(view, proj);
        let spin = Mat4::rotation_y(r() * 6.0);
        let draws = [Draw::new(&clustered).transform(spin)];
        let scene = Scene::new(camera, &draws).light(light());
        let (with, s1, s0) = with_and_without(&scene, pose);
        // Tiles drawn by rescanning skip the same clusters.
        let (rescanned, s2) = render_pool::<8>(&scene, true);
        assert!(
            rescanned.pixels == with.pixels,
            "pose {pose}: rescans differ"
        );
        assert!(s2.rescanned_tiles > 0 || s1.drawn < 20, "pose {pose}: {s2}");
        assert_eq!(s2.clusters_culled, s1.clusters_culled);
        // The same mesh without clusters: the same triangles in the same
        // order, so the same image.
        let whole_draws = [Draw::new(&whole).transform(spin)];
        let (plain, s3) = render(&Scene::new(camera, &whole_draws).light(light()), true);
        assert!(
            plain.pixels == with.pixels,
            "pose {pose}: clusters changed the image"
        );
        assert_eq!(s3.drawn, s1.drawn);
        if s1.draws_culled == 0 {
            culled += s1.clusters_culled;
            kept += n_clusters - s1.clusters_culled;
            saved += s0.vertices - s1.vertices;
            assert!(s1.vertices < s0.vertices || s1.clusters_culled == 0);
        }
        poses += 1;
    }
    assert!(poses >= 35);
    assert!(
        culled > 10 * poses,
        "{culled} clusters culled over {poses} poses"
    );
    assert!(kept > 5 * poses, "{kept} clusters kept over {poses} poses");
    assert!(
        saved > 100 * poses,
        "{saved} vertices saved over {poses} poses"
    );
}

/// Uniform numbers in `[0, 1)`, reproducibly.
fn uniform() -> impl FnMut() -> f32 {
    let mut x = 0x2545_f491_4f6c_dd1du64;
    move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 40) as f32 / (1u64 << 24) as f32
    }
}
