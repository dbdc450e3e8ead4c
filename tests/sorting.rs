//! Sorted draws (`Config::sort_draws`): a row of cubes submitted back to
//! front renders the same image sorted, with fewer fragments shaded (the
//! near cubes are drawn first and the far ones fail the depth test), also
//! when a tiny bin pool makes every tile rescan its triangles; with more
//! draws than `MAX_SORTED_DRAWS` nothing is sorted.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;
use microraster::render::MAX_SORTED_DRAWS;
use support::Capture;

const W: u32 = 96;
const H: u32 = 64;

fn render<const B: usize>(scene: &Scene<'_>, sort: bool) -> (Vec<Rgb565>, FrameStats) {
    let cfg = Config::new(Size::new(W, H), Rgb565::new(0, 0, 0)).sort_draws(sort);
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
    let mut ws: Box<Workspace<4096, B, 16>> = Box::new(Workspace::new());
    let mut cap = Capture::new(Size::new(W, H), Rgb565::new(0, 0, 0));
    let s = r.render(&mut ws, scene, &mut cap).expect("renders");
    (cap.pixels, s)
}

fn row_of_cubes<'a>(cube: &'a Mesh<'a>, n: usize) -> Vec<Draw<'a>> {
    // Farthest first, each one nearer and a little to the side, all
    // overlapping on screen; none touches another (spacing 3 > diagonal).
    (0..n)
        .map(|k| {
            let z = -3.0 * (n - k) as f32;
            Draw::new(cube)
                .transform(
                    Mat4::translation(Vec3::new(0.2 * k as f32, 0.0, z))
                        * Mat4::rotation_y(0.3 * k as f32)
                        * Mat4::scale(Vec3::new(0.9, 0.9, 0.9)),
                )
                .color(Rgb888::new((40 * k % 256) as u8, 200, 120))
        })
        .collect()
}

fn camera() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 1.5, 3.0),
            Vec3::new(0.0, 0.0, -6.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(0.9, W as f32 / H as f32, 0.5, 60.0).unwrap(),
    )
}

#[test]
fn sorting_keeps_the_image_and_shades_less() {
    let cube = cube();
    let draws = row_of_cubes(&cube, 8);
    let scene = Scene::new(camera(), &draws).light(light());
    let (plain, s0) = render::<4096>(&scene, false);
    let (sorted, s1) = render::<4096>(&scene, true);
    assert!(plain == sorted, "sorting changed the image");
    assert_eq!((s0.drawn, s0.tiles), (s1.drawn, s1.tiles));
    assert!(
        s1.pixels_shaded < s0.pixels_shaded,
        "front to back should shade fewer fragments: {} vs {}",
        s1.pixels_shaded,
        s0.pixels_shaded
    );
    // A pool too small for any tile: every tile rescans all triangles, in
    // the sorted order too.
    let (tiny, s2) = render::<1>(&scene, true);
    assert!(s2.rescanned_tiles > 0);
    assert!(tiny == sorted);
    assert_eq!(s2.pixels_shaded, s1.pixels_shaded);
}

#[test]
fn too_many_draws_are_not_sorted() {
    let cube = cube();
    let draws = row_of_cubes(&cube, MAX_SORTED_DRAWS + 1);
    let scene = Scene::new(camera(), &draws).light(light());
    let (plain, s0) = render::<8192>(&scene, false);
    let (sorted, s1) = render::<8192>(&scene, true);
    assert!(plain == sorted);
    assert_eq!(s0, s1, "with too many draws, the frame is the unsorted one");
}
