//! Units: a scene and its camera scaled by the same factor are the same
//! picture in exact arithmetic (clip coordinates are homogeneous), so the
//! renderer must draw the same image at any scale, or refuse the scene
//! with a typed error, never draw a different picture or a blank frame.

mod support;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microraster::prelude::*;
use microraster::shapes::{CUBE_NORMALS, CUBE_POSITIONS, CUBE_TRIANGLES};
use microraster::vertex::VertexError;
use proptest::prelude::*;
use std::convert::Infallible;
use support::Capture;

const SIZE: Size = Size::new(160, 120);
const BACKGROUND: Rgb888 = Rgb888::new(10, 20, 30);

/// A lit cube (its own model matrix: scaled by `s`, turned by `yaw`), the
/// eye, near and far planes scaled by `s` too: the same picture for every
/// `s` in exact arithmetic.
fn render(s: f32, yaw: f32) -> Result<(Vec<Rgb888>, FrameStats), RenderError<Infallible>> {
    let mesh = Mesh::new(&CUBE_POSITIONS, &CUBE_TRIANGLES)
        .and_then(|m| m.with_normals(&CUBE_NORMALS))
        .unwrap();
    let model = Mat4::scale(Vec3::new(s, s, s))
        * Mat4::rotation_y(yaw)
        * Mat4::rotation_x(0.4)
        * Mat4::scale(Vec3::new(0.5, 0.5, 0.5));
    let draws = [Draw::new(&mesh)
        .transform(model)
        .color(Rgb888::new(230, 180, 90))];
    // The eye 2.95 units away: the view matrix's translation, 2.95 s, fits
    // 16.16 up to s = 1e4 (the renderer still checks the camera's own
    // product against 16.16).
    let eye = Vec3::new(1.2 * s, 1.0 * s, 2.5 * s);
    let camera = Camera::new(
        Mat4::look_at(eye, Vec3::default(), Vec3::new(0.0, 1.0, 0.0))
            .ok_or(RenderError::BadCamera)?,
        Mat4::perspective(0.9, 4.0 / 3.0, 0.5 * s, 20.0 * s).ok_or(RenderError::BadCamera)?,
    );
    let scene = Scene::new(camera, &draws).light(Light::new(Vec3::new(0.3, 1.0, 0.6)));
    let mut renderer: Renderer<Rgb888, 32, 32> = Renderer::new(Config::new(SIZE, BACKGROUND));
    let mut ws: Box<Workspace<24, 64, 20>> = Box::new(Workspace::new());
    let mut cap = Capture::new(SIZE, BACKGROUND);
    let stats = renderer.render(&mut ws, &scene, &mut cap)?;
    Ok((cap.pixels, stats))
}

/// The pixels that differ from the background.
fn covered(img: &[Rgb888]) -> usize {
    img.iter().filter(|&&c| c != BACKGROUND).count()
}

/// The most pixels a scale that is not a power of two may change. Such a
/// scale rounds the `f32` set-up (model, eye, near and far planes)
/// differently in the last bit, and after normalization and rounding to
/// 16.16 a vertex may land one step away: a pixel whose centre lies within
/// that step of an edge flips. The drift the normalization removed was
/// hundreds of pixels, and a blank frame.
const EDGE_FLIPS: usize = 12;

/// Whether pixel `i` of `img` touches (4-neighbourhood) a pixel of another
/// colour: a pixel on an edge of the picture, which the last bit of the
/// set-up may move.
fn on_edge(img: &[Rgb888], i: usize) -> bool {
    let (w, h) = (SIZE.width as usize, SIZE.height as usize);
    let (x, y) = (i % w, i / w);
    let mut neighbours = Vec::with_capacity(4);
    if x > 0 {
        neighbours.push(i - 1);
    }
    if x + 1 < w {
        neighbours.push(i + 1);
    }
    if y > 0 {
        neighbours.push(i - w);
    }
    if y + 1 < h {
        neighbours.push(i + w);
    }
    neighbours.iter().any(|&n| img[n] != img[i])
}

/// Asserts that scale `s` draws what scale 1 draws: the same pixels but
/// for at most [`EDGE_FLIPS`], each on an edge of the reference.
#[track_caller]
fn assert_same_picture(s: f32, yaw: f32) {
    let (reference, _) = render(1.0, yaw).unwrap();
    let (img, _) = render(s, yaw).unwrap_or_else(|e| panic!("scale {s:e}: {e:?}"));
    let differ: Vec<usize> = (0..img.len()).filter(|&i| img[i] != reference[i]).collect();
    assert!(
        differ.len() <= EDGE_FLIPS,
        "scale {s:e}, yaw {yaw}: {} pixels differ ({} covered, {} at scale 1)",
        differ.len(),
        covered(&img),
        covered(&reference)
    );
    for &i in &differ {
        assert!(
            on_edge(&reference, i),
            "scale {s:e}, yaw {yaw}: pixel ({}, {}) differs inside a face",
            i % SIZE.width as usize,
            i / SIZE.width as usize
        );
    }
}

/// The scales of the issue: 3e-5 drew nothing (with `Ok`), 1e-3 and 1e-4
/// drifted by a few hundred pixels.
#[test]
fn small_and_large_units_draw_the_same_picture() {
    // The picture compared: a cube, lit, each face in its own shade.
    let (img, stats) = render(1.0, 0.6).unwrap();
    assert!(covered(&img) > 2_000, "{}", covered(&img));
    assert!(stats.drawn >= 4, "{stats:?}");
    let mut colours: Vec<_> = img.iter().filter(|&&c| c != BACKGROUND).collect();
    colours.sort_by_key(|c| (c.r(), c.g(), c.b()));
    colours.dedup();
    assert!(colours.len() >= 2);
    for s in [3e-5f32, 1e-3, 1e-4, 1e-6, 0.37, 2.5, 1e3, 1e4] {
        assert_same_picture(s, 0.6);
    }
}

/// Powers of two scale every `f32` of the set-up exactly: the pictures are
/// the same bit for bit from 2^-73 (1e-22) to 2^13 (8192). Beyond, the
/// scene is refused with a typed error, never drawn differently: below,
/// the draw (`BadMatrix`: the lighting measures the model's scale by a sum
/// of squares, which underflows `f32`); above, the camera, whose
/// translation leaves 16.16 (the renderer checks the camera's own product,
/// unnormalized, against it).
#[test]
fn extreme_units_are_the_same_picture_or_refused() {
    let (reference, _) = render(1.0, 0.6).unwrap();
    for e in -126..=127 {
        let s = 2f32.powi(e);
        match render(s, 0.6) {
            Ok((img, _)) => assert!(img == reference, "scale 2^{e}: a different picture"),
            Err(err) => {
                assert!(!(-73..=13).contains(&e), "scale 2^{e} refused: {err:?}");
                let draw = RenderError::Draw {
                    draw: 0,
                    error: VertexError::BadMatrix,
                };
                assert!(
                    err == RenderError::BadCamera || err == draw,
                    "2^{e}: {err:?}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Any scale from 1e-6 to 1e4, any turn of the cube: the picture of
    /// scale 1, up to a few pixels on its edges.
    #[test]
    fn any_scale_draws_the_picture_of_scale_one(
        exponent in -6.0f32..4.0,
        yaw in -3.2f32..3.2,
    ) {
        assert_same_picture(10f32.powf(exponent), yaw);
    }
}
