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

/// Renders `scene` with culling on or off.
fn render(scene: &Scene<'_>, cull: bool) -> (Capture<Rgb565>, FrameStats) {
    let cfg = Config::new(Size::new(W, H), Rgb565::new(0, 0, 0)).frustum_cull(cull);
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
    let mut ws: Box<Workspace<16384, 32768, 16>> = Box::new(Workspace::new());
    let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
    let s = r
        .render(&mut ws, scene, &mut cap)
        .expect("the scene renders");
    (cap, s)
}

/// A renderer and a workspace with a bin pool of 8 entries, so that most
/// tiles are drawn by rescanning every triangle, kept from frame to frame:
/// the vertex slots of culled draws and clusters hold what an earlier frame
/// left there, and a rescan that failed to skip them would draw it.
struct Rescanner {
    renderer: Renderer<Rgb565, 32, 32>,
    ws: Box<Workspace<16384, 8, 16>>,
}

impl Rescanner {
    fn new() -> Self {
        let cfg = Config::new(Size::new(W, H), Rgb565::new(0, 0, 0));
        Self {
            renderer: Renderer::new(cfg),
            ws: Box::new(Workspace::new()),
        }
    }

    /// Renders `draws` from high above without culling (every vertex slot
    /// filled), then `scene` with culling.
    fn render(&mut self, draws: &[Draw<'_>], scene: &Scene<'_>) -> (Capture<Rgb565>, FrameStats) {
        let view = Mat4::look_at(
            Vec3::new(0.0, 60.0, 1.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        let proj = Mat4::perspective(1.2, W as f32 / H as f32, 1.0, 200.0).unwrap();
        let overview = Scene::new(Camera::new(view, proj), draws).light(light());
        let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
        self.renderer.config_mut().frustum_cull = false;
        self.renderer
            .render(&mut self.ws, &overview, &mut cap)
            .expect("the overview renders");
        self.renderer.config_mut().frustum_cull = true;
        let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
        let s = self
            .renderer
            .render(&mut self.ws, scene, &mut cap)
            .expect("the scene renders");
        (cap, s)
    }
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
    let mut rescanner = Rescanner::new();
    let mut rescans = 0;
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
        let (with, s1, _) = with_and_without(&scene, pose);
        // Tiles drawn by rescanning skip the same draws, whatever their
        // vertex slots hold.
        let (rescanned, s2) = rescanner.render(&draws, &scene);
        assert!(
            rescanned.pixels == with.pixels,
            "pose {pose}: rescans differ"
        );
        assert_eq!(s2.draws_culled, s1.draws_culled);
        rescans += s2.rescanned_tiles;
        culled += s1.draws_culled;
        visible += draws.len() as u32 - s1.draws_culled;
        poses += 1;
    }
    assert!(poses >= 40);
    assert!(rescans > 2 * poses, "{rescans} tiles rescanned");
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
    let mut rescanner = Rescanner::new();
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
        // Tiles drawn by rescanning skip the same clusters, whatever their
        // vertex slots hold.
        let (rescanned, s2) = rescanner.render(&draws, &scene);
        assert!(
            rescanned.pixels == with.pixels,
            "pose {pose}: rescans differ"
        );
        assert!(s2.rescanned_tiles > 0 || s1.drawn < 20, "pose {pose}: {s2}");
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
