//! Frustum culling of whole draws: on random camera poses over a field of
//! meshes, rendering with culling and without gives the same image (and the
//! same triangles drawn and pixels shaded), while culling does remove the
//! draws out of view, with their vertex work.

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
    let cfg = Config::new(Size::new(W, H), Rgb565::new(0, 0, 0)).frustum_cull(cull);
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
    let mut ws: Box<Workspace<16384, 32768, 16>> = Box::new(Workspace::new());
    let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
    let s = r
        .render(&mut ws, scene, &mut cap)
        .expect("the field renders");
    (cap, s)
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
        let (with, s1) = render(&scene, true);
        let (without, s0) = render(&scene, false);
        assert!(
            with.pixels == without.pixels,
            "pose {pose}: culling changed the image"
        );
        assert_eq!(
            (s1.drawn, s1.pixels_shaded, s1.clipped),
            (s0.drawn, s0.pixels_shaded, s0.clipped),
            "pose {pose}"
        );
        assert_eq!(s0.draws_culled, 0);
        assert_eq!(
            s1.triangles_in,
            s1.culled + s1.rejected + s1.drawn,
            "pose {pose}: every triangle accounted for"
        );
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
