//! Bad input: non-finite and huge matrices and light directions, clip-space
//! overflow, degenerate triangles, bad viewports, malformed meshes, too
//! small workspaces and failing sinks. Every case must give the documented
//! error (or a correct picture), never a panic; errors found before the
//! first tile must leave the sink untouched. A tiny bin pool must render
//! exactly the same image as a big one.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use embedded_graphics::pixelcolor::{BinaryColor, Gray8, GrayColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics::primitives::Rectangle;
use fixed::types::I16F16;
use microraster::light::LightError;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::render::MAX_TRIANGLES;
use microraster::vertex::VertexError;
use microraster::TileView;
use support::Capture;

// ---------------------------------------------------------------------------
// Helpers.
// ---------------------------------------------------------------------------

/// The error of [`Recorder`]: the 0-based index of the tile it refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Refused(u32);

/// A tile sink that counts what it is given and can fail on one call.
#[derive(Debug, Default)]
struct Recorder {
    calls: u32,
    pixels: u64,
    fail_at: Option<u32>,
}

impl<C: embedded_graphics::pixelcolor::PixelColor> TileSink<C> for Recorder {
    type Error = Refused;

    fn write_tile(&mut self, area: &Rectangle, tile: &TileView<'_, C>) -> Result<(), Refused> {
        let k = self.calls;
        self.calls += 1;
        if self.fail_at == Some(k) {
            return Err(Refused(k));
        }
        assert_eq!(tile.width() as u32, area.size.width);
        assert_eq!(tile.height() as u32, area.size.height);
        self.pixels += tile.pixels().count() as u64;
        Ok(())
    }
}

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

fn p3(x: f32, y: f32, z: f32) -> Vec3Fx {
    [fx(x), fx(y), fx(z)]
}

static TRI_POS: [Vec3Fx; 3] = [
    [
        I16F16::from_bits(-32768),
        I16F16::from_bits(-32768),
        I16F16::ZERO,
    ],
    [
        I16F16::from_bits(32768),
        I16F16::from_bits(-32768),
        I16F16::ZERO,
    ],
    [I16F16::ZERO, I16F16::from_bits(32768), I16F16::ZERO],
];
static TRI_IDX: [[u16; 3]; 1] = [[0, 1, 2]];
static TRI_NRM: [Vec3Fx; 3] = [[I16F16::ZERO, I16F16::ZERO, I16F16::ONE]; 3];

/// A lit, front-facing triangle in the middle of the view.
fn triangle() -> Mesh<'static> {
    Mesh::new(&TRI_POS, &TRI_IDX)
        .and_then(|m| m.with_normals(&TRI_NRM))
        .unwrap()
}

fn ortho() -> Camera {
    Camera::new(Mat4::IDENTITY, Mat4::IDENTITY)
}

fn perspective() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(1.0, 1.0, 0.5, 20.0).unwrap(),
    )
}

const SIZE: Size = Size::new(32, 24);

/// Every test here runs with each rasterizer and tile order, which must
/// agree exactly: the first is the reference.
const COMBOS: [(Rasterizer, TileOrder); 3] = [
    (Rasterizer::Scanline, TileOrder::RowMajor),
    (Rasterizer::Hilbert, TileOrder::RowMajor),
    (Rasterizer::Auto, TileOrder::Hilbert),
];

fn renderer((raster, order): (Rasterizer, TileOrder)) -> Renderer<Rgb565, 16, 16> {
    Renderer::new(
        Config::new(SIZE, Rgb565::BLACK)
            .rasterizer(raster)
            .tile_order(order),
    )
}

/// Renders into a fresh [`Recorder`] with a roomy workspace, with every
/// rasterizer and tile order (which must agree).
fn render_to_recorder(scene: &Scene<'_>) -> (Result<FrameStats, RenderError<Refused>>, Recorder) {
    let mut first: Option<(Result<FrameStats, RenderError<Refused>>, Recorder)> = None;
    for combo in COMBOS {
        let mut ws: Box<Workspace<64, 256, 16>> = Box::new(Workspace::new());
        let mut rec = Recorder::default();
        let res = renderer(combo).render(&mut ws, scene, &mut rec);
        match &first {
            None => first = Some((res, rec)),
            Some((r0, rec0)) => {
                assert_eq!(&res, r0, "{combo:?}");
                assert_eq!(
                    (rec.calls, rec.pixels),
                    (rec0.calls, rec0.pixels),
                    "{combo:?}"
                );
            }
        }
    }
    first.expect("at least one combination")
}

/// Asserts a pre-flight error: exactly `want`, and nothing sent.
#[track_caller]
fn assert_preflight(scene: &Scene<'_>, want: RenderError<Refused>) {
    let (res, rec) = render_to_recorder(scene);
    assert_eq!(res, Err(want));
    assert_eq!(rec.calls, 0, "the sink received tiles before {want:?}");
}

/// Renders to an image, with every rasterizer and tile order (which must
/// give the same image and statistics).
fn image(scene: &Scene<'_>) -> (Vec<Rgb565>, FrameStats) {
    let mut first: Option<(Vec<Rgb565>, FrameStats)> = None;
    for combo in COMBOS {
        let mut ws: Box<Workspace<64, 256, 16>> = Box::new(Workspace::new());
        let mut cap = Capture::new(SIZE, Rgb565::new(31, 0, 31));
        let stats = renderer(combo).render(&mut ws, scene, &mut cap).unwrap();
        assert!(cap.writes.iter().all(|&n| n == 1));
        match &first {
            None => first = Some((cap.pixels, stats)),
            Some(f) => assert_same(&format!("{combo:?}"), &(cap.pixels, stats), f),
        }
    }
    first.expect("at least one combination")
}

fn with_element(mut m: Mat4, c: usize, r: usize, v: f32) -> Mat4 {
    m.m[c][r] = v;
    m
}

const NON_FINITE: [f32; 3] = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];

// ---------------------------------------------------------------------------
// Matrices and lights.
// ---------------------------------------------------------------------------

#[test]
fn non_finite_or_huge_camera_is_bad_camera() {
    let mesh = triangle();
    let draws = [Draw::new(&mesh)];
    let cameras = |bad: Mat4| {
        [
            Camera::new(bad, Mat4::IDENTITY),
            Camera::new(Mat4::IDENTITY, bad),
            Camera::new(perspective().view, bad),
        ]
    };
    for v in NON_FINITE {
        for (c, r) in [(0, 0), (1, 2), (3, 1), (2, 3)] {
            for cam in cameras(with_element(Mat4::IDENTITY, c, r, v)) {
                assert_preflight(&Scene::new(cam, &draws), RenderError::BadCamera);
            }
        }
    }
    // Huge but finite elements: the matrix is normalized before 16.16, so
    // the camera is fine; the frame renders, or a draw whose product cannot
    // be represented is a typed draw error, found before any tile.
    for v in [1e6, -1e6, 40_000.0, f32::MAX] {
        for (c, r) in [(0, 0), (1, 2), (3, 1), (2, 3)] {
            for cam in cameras(with_element(Mat4::IDENTITY, c, r, v)) {
                let (res, rec) = render_to_recorder(&Scene::new(cam, &draws));
                match res {
                    Ok(_) => {}
                    Err(RenderError::Draw { draw: 0, .. }) | Err(RenderError::BadCamera) => {
                        assert_eq!(rec.calls, 0, "{v}: tiles before the error")
                    }
                    Err(e) => panic!("{v} at ({c}, {r}): {e:?}"),
                }
            }
        }
    }
    // Finite factors whose product overflows f32.
    let big = Mat4::scale(Vec3::new(1e30, 1e30, 1e30));
    assert_preflight(
        &Scene::new(Camera::new(big, big), &draws),
        RenderError::BadCamera,
    );
    // A product far outside 16.16 is normalized: it renders.
    let s = Mat4::scale(Vec3::new(256.0, 1.0, 1.0));
    assert!(render_to_recorder(&Scene::new(Camera::new(s, s), &draws))
        .0
        .is_ok());
    // Even with no draws at all.
    assert_preflight(
        &Scene::new(Camera::new(big, big), &[]),
        RenderError::BadCamera,
    );
}

#[test]
fn non_finite_or_huge_model_matrix_is_a_draw_error() {
    let mesh = triangle();
    for v in NON_FINITE.into_iter().chain([1e6, -1e6, 1e30]) {
        for (c, r) in [(0, 0), (2, 1), (3, 0), (1, 3)] {
            let bad = with_element(Mat4::IDENTITY, c, r, v);
            for cam in [ortho(), perspective()] {
                // The bad draw is the second one: its index is reported.
                let draws = [Draw::new(&mesh), Draw::new(&mesh).transform(bad)];
                let want = RenderError::Draw {
                    draw: 1,
                    error: VertexError::BadMatrix,
                };
                assert_preflight(&Scene::new(cam, &draws), want);
                let lit = Scene::new(cam, &draws).light(Light::new(Vec3::new(0.0, 0.0, 1.0)));
                assert_preflight(&lit, want);
            }
        }
    }
}

#[test]
fn huge_model_matrix_cancelled_by_the_camera_renders() {
    // 1e5 does not fit 16.16, but the model-view-projection product does:
    // only the product is converted.
    let mesh = triangle();
    let model = Mat4::scale(Vec3::new(1e5, 1e5, 1e5));
    let draws = [Draw::new(&mesh).transform(model)];
    let cam = Camera::new(Mat4::IDENTITY, Mat4::scale(Vec3::new(1e-5, 1e-5, 1e-5)));
    let (img, stats) = image(&Scene::new(cam, &draws));
    let plain = [Draw::new(&mesh)];
    let (reference, _) = image(&Scene::new(ortho(), &plain));
    assert_eq!(stats.drawn, 1);
    assert_eq!(img, reference);
}

#[test]
fn zero_or_non_finite_light_is_bad_light() {
    let mesh = triangle();
    let draws = [Draw::new(&mesh)];
    for d in [
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 1.0),
        Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
        Vec3::new(f32::MAX, f32::INFINITY, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(-0.0, 0.0, -0.0),
    ] {
        for cam in [ortho(), perspective()] {
            assert_preflight(
                &Scene::new(cam, &draws).light(Light::new(d)),
                RenderError::Light(LightError::BadDirection { light: 0 }),
            );
            assert_preflight(
                &Scene::new(cam, &[]).light(Light::new(d)),
                RenderError::Light(LightError::BadDirection { light: 0 }),
            );
        }
    }
}

#[test]
fn huge_or_tiny_light_direction_is_just_a_direction() {
    // A direction is a direction at any finite, non-zero length: 1e30 and
    // 1e-30 times a vector light exactly like the vector itself.
    let mesh = triangle();
    let draws = [Draw::new(&mesh).color(Rgb888::new(200, 180, 160))];
    for cam in [ortho(), perspective()] {
        let dir = Vec3::new(0.5, -0.25, 1.0);
        let (reference, _) = image(&Scene::new(cam, &draws).light(Light::new(dir)));
        for k in [1e30f32, 3e38, 1e-30, 1e-37] {
            let scaled = Vec3::new(dir.x * k, dir.y * k, dir.z * k);
            let scene = Scene::new(cam, &draws).light(Light::new(scaled));
            let (res, rec) = render_to_recorder(&scene);
            assert!(res.is_ok(), "light {scaled:?}: {res:?}");
            assert_eq!(rec.calls, 4);
            let (img, _) = image(&scene);
            assert_eq!(img, reference, "light {scaled:?}");
        }
    }
}

// ---------------------------------------------------------------------------
// Vertices.
// ---------------------------------------------------------------------------

#[test]
fn clip_space_overflow_is_reported_with_the_vertex() {
    let big = I16F16::from_bits(i32::MAX); // just under 32768
    let positions = [
        p3(0.0, 0.0, 0.0),
        p3(0.5, 0.0, 0.0),
        p3(0.0, 0.5, 0.0),
        [big, fx(0.0), fx(0.0)],
        [fx(0.0), fx(0.0), big],
    ];
    let triangles = [[0u16, 1, 2], [0, 3, 4]];
    let mesh = Mesh::new(&positions, &triangles).unwrap();
    let ok = triangle();
    // The model-view-projection matrix is normalized before the vertex
    // stage (its largest element becomes 1, the picture stays), so scaling
    // alone cannot overflow: clip x here is x's largest element times
    // (x + 0.5) or (x + 1), past 32768 at vertex 3.
    for cam in [ortho(), perspective()] {
        for model in [
            Mat4::scale(Vec3::new(10.0, 1.0, 1.0)) * Mat4::translation(Vec3::new(0.5, 0.0, 0.0)),
            Mat4::scale(Vec3::new(-40.0, 2.0, 2.0)) * Mat4::translation(Vec3::new(1.0, 0.0, 0.0)),
        ] {
            let draws = [Draw::new(&ok), Draw::new(&mesh).transform(model)];
            let res = render_to_recorder(&Scene::new(cam, &draws));
            assert_eq!(res.1.calls, 0);
            assert_eq!(
                res.0,
                Err(RenderError::Draw {
                    draw: 1,
                    error: VertexError::OutOfRange { vertex: 3 },
                }),
                "{model:?}"
            );
        }
    }
}

#[test]
fn products_near_the_16_16_limits_do_not_overflow() {
    // Every element of the matrix and every coordinate close to +-32768.
    // The vertex stage normalizes the matrix (elements -1 here, w's
    // translation 2^-15), so each product is about 2^47 and a sum of three
    // leaves 16.16: the vertex must be reported as out of range, not wrap
    // around or panic. (FixedMat4's own tests take products of 2^62.)
    let m = Mat4 {
        m: [
            [-32_000.0; 4],
            [-32_000.0; 4],
            [-32_000.0; 4],
            [0.0, 0.0, 0.0, 1.0],
        ],
    };
    let lo = I16F16::from_bits(-0x7fff_0000);
    let hi = I16F16::from_bits(0x7fff_0000);
    for p in [[lo, lo, lo], [hi, hi, hi], [hi, lo, hi]] {
        let positions = [p, p3(0.0, 0.0, 0.0), p3(0.1, 0.0, 0.0)];
        if p == [hi, lo, hi] {
            // The sum cancels to -hi: in range, and the frame renders.
            let mesh = Mesh::new(&positions, &TRI_IDX).unwrap();
            let draws = [Draw::new(&mesh).transform(m)];
            assert!(render_to_recorder(&Scene::new(ortho(), &draws)).0.is_ok());
            continue;
        }
        let mesh = Mesh::new(&positions, &TRI_IDX).unwrap();
        let draws = [Draw::new(&mesh).transform(m)];
        assert_preflight(
            &Scene::new(ortho(), &draws),
            RenderError::Draw {
                draw: 0,
                error: VertexError::OutOfRange { vertex: 0 },
            },
        );
    }
}

#[test]
fn vertices_at_the_16_16_limits_render() {
    // The largest coordinates, unscaled: clip space still fits, the
    // triangle is clipped to the guard band and covers the whole frame.
    let lo = I16F16::MIN;
    let hi = I16F16::MAX;
    let positions = [[lo, lo, fx(0.0)], [hi, lo, fx(0.0)], [fx(0.0), hi, fx(0.0)]];
    let mesh = Mesh::new(&positions, &TRI_IDX).unwrap();
    let draws = [Draw::new(&mesh).color(Rgb888::WHITE)];
    for (raster, order) in COMBOS {
        let mut r: Renderer<BinaryColor, 16, 16> = Renderer::new(
            Config::new(SIZE, BinaryColor::Off)
                .rasterizer(raster)
                .tile_order(order),
        );
        let mut ws: Workspace<3, 16, 8> = Workspace::new();
        let mut cap = Capture::new(SIZE, BinaryColor::Off);
        let stats = r
            .render(&mut ws, &Scene::new(ortho(), &draws), &mut cap)
            .unwrap();
        assert_eq!(stats.clipped, 1);
        assert_eq!(stats.pixels_shaded, SIZE.width * SIZE.height);
        assert!(cap.pixels.iter().all(|&c| c == BinaryColor::On));
    }
}

#[test]
fn huge_normals_do_not_overflow_lighting() {
    let n = [I16F16::MAX, I16F16::MIN, I16F16::MAX];
    let normals = [n; 3];
    let mesh = Mesh::new(&TRI_POS, &TRI_IDX)
        .and_then(|m| m.with_normals(&normals))
        .unwrap();
    let draws = [Draw::new(&mesh)];
    for d in [Vec3::new(1.0, -1.0, 1.0), Vec3::new(-1.0, 1.0, -1.0)] {
        let scene = Scene::new(ortho(), &draws).light(Light::new(d));
        let (res, rec) = render_to_recorder(&scene);
        assert_eq!(res.map(|s| s.drawn), Ok(1));
        assert_eq!(rec.calls, 4);
    }
}

#[test]
fn degenerate_triangles_draw_nothing() {
    let positions = [
        p3(0.1, 0.2, 0.0),
        p3(-0.5, -0.5, 0.0),
        p3(0.0, 0.0, 0.0),
        p3(0.5, 0.5, 0.0),
        p3(0.5, -0.5, 0.3),
        // Collinear through the near plane of the perspective camera.
        p3(0.0, 0.0, 5.0),
        p3(0.0, 0.0, -5.0),
    ];
    let triangles = [
        [0u16, 0, 0], // one point
        [1, 1, 3],    // a segment
        [1, 2, 3],    // collinear
        [3, 2, 1],    // collinear, other order
        [4, 4, 0],
        [5, 6, 2], // collinear, crossing the near plane
        [6, 5, 6],
    ];
    let mesh = Mesh::new(&positions, &triangles).unwrap();
    let draws = [Draw::new(&mesh).color(Rgb888::WHITE)];
    for cam in [ortho(), perspective()] {
        for (cull, (raster, order)) in [CullMode::None, CullMode::Back, CullMode::Front]
            .into_iter()
            .flat_map(|c| COMBOS.map(|k| (c, k)))
        {
            let mut r: Renderer<Gray8, 16, 16> = Renderer::new(
                Config::new(SIZE, Gray8::BLACK)
                    .cull(cull)
                    .rasterizer(raster)
                    .tile_order(order),
            );
            let mut ws: Workspace<8, 64, 8> = Workspace::new();
            let mut cap = Capture::new(SIZE, Gray8::new(9));
            let stats = r
                .render(&mut ws, &Scene::new(cam, &draws), &mut cap)
                .unwrap();
            assert_eq!(stats.pixels_shaded, 0, "{stats:?}");
            assert_eq!(stats.drawn, 0, "{stats:?}");
            assert_eq!(
                stats.culled + stats.rejected,
                triangles.len() as u32,
                "{stats:?}"
            );
            assert!(cap.pixels.iter().all(|&c| c == Gray8::BLACK));
        }
    }
}

// ---------------------------------------------------------------------------
// Viewports, meshes and capacities.
// ---------------------------------------------------------------------------

#[test]
fn bad_viewports_are_rejected_before_any_tile() {
    let mesh = triangle();
    let draws = [Draw::new(&mesh)];
    let scene = Scene::new(ortho(), &draws);
    let mut ws: Workspace<3, 16, 4> = Workspace::new();
    let cases = [
        (Size::new(0, 10), RenderError::ZeroViewport),
        (Size::new(10, 0), RenderError::ZeroViewport),
        (Size::new(0, 0), RenderError::ZeroViewport),
        (Size::new(0, 5000), RenderError::ZeroViewport),
        (
            Size::new(4097, 10),
            RenderError::ViewportTooLarge {
                size: Size::new(4097, 10),
            },
        ),
        (
            Size::new(10, 4097),
            RenderError::ViewportTooLarge {
                size: Size::new(10, 4097),
            },
        ),
        (
            Size::new(u32::MAX, u32::MAX),
            RenderError::ViewportTooLarge {
                size: Size::new(u32::MAX, u32::MAX),
            },
        ),
    ];
    for (size, want) in cases {
        let mut r: Renderer<Rgb565, 16, 16> = Renderer::new(Config::new(size, Rgb565::BLACK));
        let mut rec = Recorder::default();
        assert_eq!(r.render(&mut ws, &scene, &mut rec), Err(want));
        assert_eq!(rec.calls, 0);
        // Even with a bad camera as well, the viewport is reported.
        let nan = Camera::new(with_element(Mat4::IDENTITY, 0, 0, f32::NAN), Mat4::IDENTITY);
        assert_eq!(
            r.render(&mut ws, &Scene::new(nan, &draws), &mut rec),
            Err(want)
        );
        assert_eq!(rec.calls, 0);
    }
}

#[test]
fn largest_viewports_render() {
    let mesh = triangle();
    let draws = [Draw::new(&mesh)];
    let scene = Scene::new(ortho(), &draws);
    let mut ws: Box<Workspace<3, 64, 64>> = Box::new(Workspace::new());
    for (size, (raster, order)) in [Size::new(4096, 3), Size::new(2, 4096), Size::new(1, 1)]
        .into_iter()
        .flat_map(|s| COMBOS.map(|k| (s, k)))
    {
        let mut r: Renderer<Rgb565, 64, 64> = Renderer::new(
            Config::new(size, Rgb565::BLACK)
                .rasterizer(raster)
                .tile_order(order),
        );
        let mut rec = Recorder::default();
        let stats = r.render(&mut ws, &scene, &mut rec).unwrap();
        assert_eq!(rec.pixels, size.width as u64 * size.height as u64);
        assert_eq!(stats.tiles, rec.calls);
        assert_eq!(
            stats.tiles,
            size.width.div_ceil(64) * size.height.div_ceil(64)
        );
    }
}

#[test]
fn malformed_meshes_are_rejected() {
    use microraster::mesh::MeshError;
    let positions = [p3(0.0, 0.0, 0.0), p3(1.0, 0.0, 0.0), p3(0.0, 1.0, 0.0)];
    assert_eq!(
        Mesh::new(&positions, &[[0, 1, 2], [2, 1, 3]]).unwrap_err(),
        MeshError::IndexOutOfRange {
            triangle: 1,
            index: 3,
            vertex_count: 3
        }
    );
    assert_eq!(
        Mesh::new(&positions, &[[0, 1, 2], [0, u16::MAX, 1]]).unwrap_err(),
        MeshError::IndexOutOfRange {
            triangle: 1,
            index: u16::MAX as u32,
            vertex_count: 3
        }
    );
    assert_eq!(
        Mesh::new(&[], &[[0, 0, 0]]).unwrap_err(),
        MeshError::IndexOutOfRange {
            triangle: 0,
            index: 0,
            vertex_count: 0
        }
    );
    // An empty mesh is fine.
    assert_eq!(Mesh::new(&[], &[]).unwrap().triangle_count(), 0);

    let mesh = Mesh::new(&positions, &[[0, 1, 2]]).unwrap();
    let normals = [p3(0.0, 0.0, 1.0); 4];
    assert_eq!(
        mesh.with_normals(&normals[..2]).unwrap_err(),
        MeshError::LengthMismatch {
            what: "normals",
            len: 2,
            expected: 3
        }
    );
    assert_eq!(
        mesh.with_normals(&normals).unwrap_err(),
        MeshError::LengthMismatch {
            what: "normals",
            len: 4,
            expected: 3
        }
    );
    let colors = [Rgb888::RED; 4];
    assert_eq!(
        mesh.with_colors(&colors[..1]).unwrap_err(),
        MeshError::LengthMismatch {
            what: "colors",
            len: 1,
            expected: 3
        }
    );
    assert_eq!(
        mesh.with_colors(&colors).unwrap_err(),
        MeshError::LengthMismatch {
            what: "colors",
            len: 4,
            expected: 3
        }
    );
    assert_eq!(
        mesh.with_colors(&[]).unwrap_err(),
        MeshError::LengthMismatch {
            what: "colors",
            len: 0,
            expected: 3
        }
    );
    assert!(mesh
        .with_normals(&normals[..3])
        .and_then(|m| m.with_colors(&colors[..3]))
        .is_ok());

    // More vertices than u16 indices reach; exactly 65,536 is fine.
    let many = vec![p3(0.0, 0.0, 0.0); 65_537];
    assert_eq!(
        Mesh::new(&many, &[]).unwrap_err(),
        MeshError::TooManyVertices { count: 65_537 }
    );
    let m = Mesh::new(&many[..65_536], &[[0, 65_535, 1]]).unwrap();
    assert_eq!(m.vertex_count(), 65_536);
}

#[test]
fn too_many_vertices_for_the_workspace() {
    let a = triangle();
    let draws = [Draw::new(&a), Draw::new(&a)];
    let scene = Scene::new(ortho(), &draws);
    let mut r = renderer(COMBOS[0]);
    let mut rec = Recorder::default();
    let mut ws: Workspace<5, 64, 8> = Workspace::new();
    assert_eq!(
        r.render(&mut ws, &scene, &mut rec),
        Err(RenderError::VertexCapacity {
            needed: 6,
            capacity: 5
        })
    );
    assert_eq!(rec.calls, 0);
    let mut ws: Workspace<0, 1, 1> = Workspace::new();
    assert_eq!(
        r.render(&mut ws, &Scene::new(ortho(), &draws[..1]), &mut rec),
        Err(RenderError::VertexCapacity {
            needed: 3,
            capacity: 0
        })
    );
    assert_eq!(rec.calls, 0);
    // Exactly enough is enough.
    let mut ws: Workspace<6, 64, 8> = Workspace::new();
    assert!(r.render(&mut ws, &scene, &mut rec).is_ok());
}

#[test]
fn too_many_triangles() {
    let positions = [p3(0.0, 0.0, 0.0)];
    let tris = vec![[0u16, 0, 0]; MAX_TRIANGLES];
    let mesh = Mesh::new(&positions, &tris).unwrap();
    let one = Mesh::new(&positions, &tris[..1]).unwrap();
    let draws = [Draw::new(&mesh), Draw::new(&one)];
    assert_preflight(
        &Scene::new(ortho(), &draws),
        RenderError::TooManyTriangles {
            count: MAX_TRIANGLES + 1,
        },
    );
    // Exactly the maximum renders (all of them are degenerate).
    let (res, rec) = render_to_recorder(&Scene::new(ortho(), &draws[..1]));
    let stats = res.unwrap();
    assert_eq!(stats.triangles_in as usize, MAX_TRIANGLES);
    assert_eq!(stats.culled as usize, MAX_TRIANGLES);
    assert_eq!(rec.calls, 4);
}

// ---------------------------------------------------------------------------
// Sinks.
// ---------------------------------------------------------------------------

#[test]
fn sink_errors_are_returned_and_stop_the_frame() {
    let mesh = triangle();
    let draws = [Draw::new(&mesh)];
    let scene = Scene::new(perspective(), &draws);
    // 32 x 24 in 16 x 16 tiles: 4 tiles. Fail on each in turn.
    for k in 0..4 {
        for (name, pool) in [("big pool", false), ("tiny pool", true)] {
            let mut rec = Recorder {
                fail_at: Some(k),
                ..Recorder::default()
            };
            let res = if pool {
                let mut ws: Workspace<3, 1, 1> = Workspace::new();
                renderer(COMBOS[0]).render(&mut ws, &scene, &mut rec)
            } else {
                let mut ws: Workspace<3, 64, 8> = Workspace::new();
                renderer(COMBOS[0]).render(&mut ws, &scene, &mut rec)
            };
            assert_eq!(res, Err(RenderError::Sink(Refused(k))), "{name}");
            // The tiles before the failing one were delivered; none after.
            assert_eq!(rec.calls, k + 1, "{name}");
            // Tiles are 16x16, 16x16, 16x8, 16x8.
            let before: u64 = [256, 256, 128, 128][..k as usize].iter().sum();
            assert_eq!(rec.pixels, before, "{name}");
        }
    }
}

// ---------------------------------------------------------------------------
// Capacity fallbacks.
// ---------------------------------------------------------------------------

/// Renders with every rasterizer and tile order (which must give the same
/// image) and returns the first result.
fn render_rgb565<const V: usize, const B: usize, const T: usize>(
    scene: &Scene<'_>,
    size: Size,
) -> (Vec<Rgb565>, FrameStats) {
    let mut first: Option<(Vec<Rgb565>, FrameStats)> = None;
    for (raster, order) in COMBOS {
        let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(
            Config::new(size, common::DEMO_CLEAR)
                .rasterizer(raster)
                .tile_order(order),
        );
        let mut ws: Box<Workspace<V, B, T>> = Box::new(Workspace::new());
        let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
        let stats = r.render(&mut ws, scene, &mut cap).unwrap();
        assert!(cap.writes.iter().all(|&n| n == 1));
        match &first {
            None => first = Some((cap.pixels, stats)),
            // The passes may differ: which tiles share a pass depends on
            // the order they are visited in.
            Some(f) => assert_same(&format!("{raster:?} {order:?}"), &(cap.pixels, stats), f),
        }
    }
    first.expect("at least one combination")
}

fn assert_same(name: &str, img: &(Vec<Rgb565>, FrameStats), reference: &(Vec<Rgb565>, FrameStats)) {
    support::assert_same_frame(name, img, reference, true);
}

#[test]
fn tiny_bin_pool_renders_the_demo_scene_identically() {
    let assets = common::DemoAssets::new();
    let (knot, cube) = (assets.knot(), common::cube());
    let size = Size::new(160, 120);
    let d = common::draws(&knot, &cube, 0.9, Shading::Gouraud);
    let scene = Scene::new(common::camera(size.width, size.height), &d).light(common::light());

    let big = render_rgb565::<2048, 8192, 80>(&scene, size);
    assert_eq!(big.1.bin_passes, 1);
    assert_eq!(big.1.rescanned_tiles, 0);
    assert!(big.1.pixels_shaded > 2000, "{:?}", big.1);

    let tiny = render_rgb565::<2048, 8, 2>(&scene, size);
    assert!(tiny.1.bin_passes > 1, "{:?}", tiny.1);
    assert!(tiny.1.rescanned_tiles > 0, "{:?}", tiny.1);
    assert_same("Workspace<2048, 8, 2>", &tiny, &big);

    let one_tile = render_rgb565::<2048, 8192, 1>(&scene, size);
    assert_eq!(one_tile.1.bin_passes, 20);
    assert_same("Workspace<2048, 8192, 1>", &one_tile, &big);

    let one_entry = render_rgb565::<2048, 1, 80>(&scene, size);
    assert_same("Workspace<2048, 1, 80>", &one_entry, &big);
}

#[test]
fn tiny_bin_pool_renders_clipped_triangles_identically() {
    // The demo scene plus a floor through the near plane and a wall far
    // beyond the guard band: clipped triangles in every pass and rescan.
    common::with_clipped_scene(|scene, size| {
        let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(
            Config::new(size, common::DEMO_CLEAR)
                .cull(CullMode::None)
                .rasterizer(Rasterizer::Hilbert)
                .tile_order(TileOrder::Hilbert),
        );
        let hilbert_tiny = {
            let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
            let mut ws: Box<Workspace<2100, 8, 2>> = Box::new(Workspace::new());
            let stats = r.render(&mut ws, scene, &mut cap).unwrap();
            (cap.pixels, stats)
        };
        r.config_mut().rasterizer = Rasterizer::Scanline;
        r.config_mut().tile_order = TileOrder::RowMajor;
        let run = |r: &mut Renderer<Rgb565, 32, 32>, big: bool| {
            let mut cap = Capture::new(size, Rgb565::new(31, 0, 31));
            let stats = if big {
                let mut ws: Box<Workspace<2100, 16384, 64>> = Box::new(Workspace::new());
                r.render(&mut ws, scene, &mut cap).unwrap()
            } else {
                let mut ws: Box<Workspace<2100, 8, 2>> = Box::new(Workspace::new());
                r.render(&mut ws, scene, &mut cap).unwrap()
            };
            assert!(cap.writes.iter().all(|&n| n == 1));
            (cap.pixels, stats)
        };
        let big = run(&mut r, true);
        assert!(big.1.clipped >= 3, "{:?}", big.1);
        let tiny = run(&mut r, false);
        assert!(
            tiny.1.bin_passes > 1 && tiny.1.rescanned_tiles > 0,
            "{:?}",
            tiny.1
        );
        assert_same("clipped scene, Workspace<2100, 8, 2>", &tiny, &big);
        assert_same(
            "clipped scene, Hilbert rasterizer and tiles, Workspace<2100, 8, 2>",
            &hilbert_tiny,
            &big,
        );
    });
}

/// One tile holding 65,536 triangles with a pool of 65,535 entries: the
/// per-tile count saturates at u16::MAX, which must read as "does not fit"
/// (the tile is drawn by re-scanning), never as a count that fits.
#[test]
fn saturated_bin_count_is_an_overflow_not_a_fit() {
    let fx = |v: f32| I16F16::from_num(v);
    let positions: [Vec3Fx; 3] = [
        [fx(-1.0), fx(-1.0), fx(0.0)],
        [fx(1.0), fx(-1.0), fx(0.0)],
        [fx(-1.0), fx(1.0), fx(0.0)],
    ];
    let triangles = vec![[0u16, 1, 2]; MAX_TRIANGLES];
    let mesh = Mesh::new(&positions, &triangles).unwrap();
    let draws = [Draw::new(&mesh).color(Rgb888::WHITE)];
    let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    let size = Size::new(16, 16);
    let mut renderer: Renderer<Gray8, 16, 16> = Renderer::new(Config::new(size, Gray8::BLACK));
    let mut ws: Box<Workspace<3, 65_535, 1>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, Gray8::new(9));
    let stats = renderer.render(&mut ws, &scene, &mut cap).unwrap();
    assert_eq!(stats.rescanned_tiles, 1, "{stats:?}");
    assert_eq!(stats.drawn, MAX_TRIANGLES as u32);
    // The lower-left half (NDC y up) of the frame is white.
    assert_eq!(cap.get(1, 14), Gray8::WHITE);
    assert_eq!(cap.get(14, 1), Gray8::BLACK);
}

// ---------------------------------------------------------------------------
// Shaders, textures, lines and blending.
// ---------------------------------------------------------------------------

/// A shader draw without a shader, or without what the shader reads, is an
/// error before the first tile; nothing reaches the sink.
#[test]
fn shader_draws_need_a_shader_and_its_inputs() {
    use microraster::shader::{Normals, ShaderError, Textured};
    use microraster::texture::{Texels, Texture};
    let pos = [p3(-0.5, -0.5, 0.0), p3(0.5, -0.5, 0.0), p3(0.0, 0.5, 0.0)];
    let uvs = [[fx(0.0); 2]; 3];
    let tris = [[0u16, 1, 2]];
    let bare = Mesh::new(&pos, &tris).unwrap();
    let with_uvs = bare.with_uvs(&uvs).unwrap();
    let texels = [0u16; 4];
    let tex = Texture::new(2, 2, Texels::Rgb565(&texels)).unwrap();
    let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let mut r: Renderer<Rgb565, 16, 16> =
        Renderer::new(Config::new(Size::new(16, 16), Rgb565::BLACK));
    let mut ws: Workspace<8, 64, 4> = Workspace::new();
    let mut sink = Recorder::default();

    let d = [Draw::new(&bare), Draw::new(&bare).shading(Shading::Shader)];
    let e = r.render(&mut ws, &Scene::new(cam, &d), &mut sink);
    assert_eq!(e, Err(RenderError::MissingShader { draw: 1, index: 0 }));
    // An index past the scene's shaders, one or several.
    let d = [Draw::new(&bare), Draw::new(&with_uvs).shader(1)];
    let e = r.render(&mut ws, &Scene::new(cam, &d).shader(&Normals), &mut sink);
    assert_eq!(e, Err(RenderError::MissingShader { draw: 1, index: 1 }));
    let d = [Draw::new(&with_uvs).texture(&tex).shader(2)];
    let two = Scene::new(cam, &d).shaders((Textured, Normals));
    let e = r.render(&mut ws, &two, &mut sink);
    assert_eq!(e, Err(RenderError::MissingShader { draw: 0, index: 2 }));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("draw 0 uses shader 2, which the scene does not have"));
    // The shader a draw picks is the one whose inputs are checked.
    let d = [Draw::new(&with_uvs).texture(&tex).shader(1)];
    let e = r.render(
        &mut ws,
        &Scene::new(cam, &d).shaders((Textured, Normals)),
        &mut sink,
    );
    assert_eq!(
        e,
        Err(RenderError::Shader {
            draw: 0,
            error: ShaderError::MissingNormals
        })
    );

    let d = [Draw::new(&with_uvs).shading(Shading::Shader)];
    let e = r.render(&mut ws, &Scene::new(cam, &d).shader(&Textured), &mut sink);
    assert_eq!(
        e,
        Err(RenderError::Shader {
            draw: 0,
            error: ShaderError::MissingTexture
        })
    );
    let d = [Draw::new(&bare).shading(Shading::Shader).texture(&tex)];
    let e = r.render(&mut ws, &Scene::new(cam, &d).shader(&Textured), &mut sink);
    assert_eq!(
        e,
        Err(RenderError::Shader {
            draw: 0,
            error: ShaderError::MissingUvs
        })
    );
    let e = r.render(&mut ws, &Scene::new(cam, &d).shader(&Normals), &mut sink);
    assert_eq!(
        e,
        Err(RenderError::Shader {
            draw: 0,
            error: ShaderError::MissingNormals
        })
    );
    assert_eq!(sink.calls, 0, "errors come before the first tile");
    assert!(e.unwrap_err().to_string().contains("normals"));

    // With everything present, it draws.
    let d = [Draw::new(&with_uvs).shading(Shading::Shader).texture(&tex)];
    let s = r
        .render(&mut ws, &Scene::new(cam, &d).shader(&Textured), &mut sink)
        .unwrap();
    assert!(s.pixels_shaded > 0);
}

/// Texture slices that do not match their size are errors, never a panic
/// later.
#[test]
fn mismatched_texture_slices_are_errors() {
    use microraster::texture::{Texels, Texture, TextureError};
    let t = [0u16; 5];
    assert!(matches!(
        Texture::new(0, 2, Texels::Rgb565(&t)),
        Err(TextureError::ZeroSize { .. })
    ));
    assert!(matches!(
        Texture::new(2, 2, Texels::Rgb565(&t)),
        Err(TextureError::LengthMismatch {
            expected: 4,
            actual: 5
        })
    ));
    let idx = [0x00u8, 0x20];
    let pal = [0u16; 2];
    assert!(matches!(
        Texture::new(
            2,
            2,
            Texels::Indexed4 {
                indices: &idx,
                palette: &pal
            }
        ),
        Err(TextureError::IndexOutOfRange { index: 2, .. })
    ));
}

/// Shader varyings of any value, triangles crossing the near plane and the
/// guard band, lines and points from clipped triangles, and transparent
/// draws: no panic (debug builds check overflow), every rasterizer and
/// perspective mode gives the same image as the scanline one of its mode.
#[test]
fn shader_lines_and_blending_survive_clipped_and_extreme_input() {
    use microraster::shader::{Fragment, FragmentShader, VertexInput};
    struct Extreme;
    impl FragmentShader<Rgb565> for Extreme {
        type Varyings = [I16F16; 3];
        fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 3] {
            let k = v.index as i32;
            [
                I16F16::MAX,
                I16F16::MIN,
                I16F16::from_bits(k.wrapping_mul(0x3fff_ffff)),
            ]
        }
        fn fragment(&self, f: &Fragment<'_, [I16F16; 3]>) -> Option<Rgb565> {
            let bits = f.varyings.iter().fold(0u32, |a, v| a ^ v.to_bits() as u32);
            (bits & 1 == 0).then_some(Rgb565::new(bits as u8 & 31, 20, 9))
        }
    }
    let extras = common::ClippedExtras::new();
    let (floor, wall) = (extras.floor(), extras.wall());
    let draws = [
        Draw::new(&floor)
            .shading(Shading::Shader)
            .edges(Edges::default()),
        Draw::new(&wall)
            .blend(Blend::Alpha(100))
            .edges(Edges::new(Rgb888::RED)),
        Draw::new(&floor).shading(Shading::Points(4)),
        Draw::new(&wall)
            .shading(Shading::Wireframe)
            .blend(Blend::Additive),
    ];
    let scene = Scene::new(common::camera(160, 120), &draws).shader(&Extreme);
    for mode in [
        Perspective::Exact,
        Perspective::Quasi8,
        Perspective::Quasi16,
        Perspective::Affine,
    ] {
        let mut images = Vec::new();
        for raster in [Rasterizer::Scanline, Rasterizer::Hilbert, Rasterizer::Auto] {
            let cfg = Config::new(Size::new(160, 120), Rgb565::BLACK)
                .cull(CullMode::None)
                .perspective(mode)
                .rasterizer(raster);
            let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
            let mut ws: Box<Workspace<64, 512, 32>> = Box::new(Workspace::new());
            let mut cap = Capture::new(Size::new(160, 120), Rgb565::BLACK);
            let s = r.render(&mut ws, &scene, &mut cap).unwrap();
            assert!(s.clipped > 0 && s.pixels_shaded > 0, "{s:?}");
            images.push(cap.pixels);
        }
        assert!(images.iter().all(|i| *i == images[0]), "{mode:?}");
    }
}

/// A transparent draw is blended over what the tile holds and leaves its
/// depth alone.
#[test]
fn transparent_draws_blend_and_write_no_depth() {
    let pos = [
        p3(-1.0, -1.0, 0.0),
        p3(1.0, -1.0, 0.0),
        p3(1.0, 1.0, 0.0),
        p3(-1.0, 1.0, 0.0),
    ];
    let tris = [[0u16, 1, 2], [0, 2, 3]];
    let quad = Mesh::new(&pos, &tris).unwrap();
    let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let d = [Draw::new(&quad)
        .color(Rgb888::new(200, 100, 0))
        .shading(Shading::Flat)
        .blend(Blend::Alpha(128))];
    let clear = Rgb888::new(0, 0, 200);
    let mut r: Renderer<Rgb888, 16, 16> =
        Renderer::new(Config::new(Size::new(16, 16), clear).clear_depth(60_000));
    let mut ws: Workspace<4, 64, 1> = Workspace::new();
    let mut cap = Capture::new(Size::new(16, 16), clear);
    let s = r.render(&mut ws, &Scene::new(cam, &d), &mut cap).unwrap();
    assert_eq!(s.pixels_shaded, 256);
    let expect = Blend::Alpha(128).apply([200, 100, 0], [0, 0, 200]);
    assert_eq!(expect, [100, 50, 100]);
    assert!(cap.pixels.iter().all(|&c| c == Rgb888::new(100, 50, 100)));
    for y in 0..16 {
        for x in 0..16 {
            assert_eq!(r.tile().depth(x, y), Some(60_000));
        }
    }
}

/// More transparent triangles in a tile than its sort list holds: they are
/// sorted in batches, so a far triangle submitted before the list filled
/// is still drawn before a near one submitted after (any tile size).
#[test]
fn transparent_triangles_beyond_the_sort_list_keep_back_to_front() {
    use microraster::render::MAX_TRANSPARENT;
    // MAX_TRANSPARENT - 1 tiny transparent triangles next to the middle
    // pixel (in its tile for every tile size below, not covering it), then
    // a far red quad and a near green one over the middle.
    let mut pos = Vec::new();
    let mut tris: Vec<[u16; 3]> = Vec::new();
    for k in 0..MAX_TRANSPARENT - 1 {
        let b = pos.len() as u16;
        let z = 0.5 - k as f32 / 1000.0;
        pos.extend([p3(0.1, -0.1, z), p3(0.15, -0.1, z), p3(0.1, -0.05, z)]);
        tris.push([b, b + 1, b + 2]);
    }
    let quad = |pos: &mut Vec<Vec3Fx>, tris: &mut Vec<[u16; 3]>, z: f32| {
        let b = pos.len() as u16;
        pos.extend([
            p3(-0.5, -0.5, z),
            p3(0.5, -0.5, z),
            p3(0.5, 0.5, z),
            p3(-0.5, 0.5, z),
        ]);
        tris.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
    };
    quad(&mut pos, &mut tris, 0.8);
    let far_end = tris.len();
    quad(&mut pos, &mut tris, -0.8);
    let mut colors = vec![Rgb888::new(0, 0, 255); pos.len()];
    for c in &mut colors[pos.len() - 8..pos.len() - 4] {
        *c = Rgb888::new(200, 0, 0);
    }
    for c in &mut colors[pos.len() - 4..] {
        *c = Rgb888::new(0, 200, 0);
    }
    assert_eq!(far_end + 2, tris.len());
    let mesh = Mesh::new(&pos, &tris)
        .unwrap()
        .with_colors(&colors)
        .unwrap();
    let d = [Draw::new(&mesh)
        .shading(Shading::Flat)
        .blend(Blend::Alpha(200))];
    let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let scene = Scene::new(cam, &d);
    let black = Rgb888::new(0, 0, 0);
    let red_over_black = Blend::Alpha(200).apply([200, 0, 0], [0, 0, 0]);
    let expect = Blend::Alpha(200).apply([0, 200, 0], red_over_black);
    let expect = Rgb888::new(expect[0], expect[1], expect[2]);
    macro_rules! check {
        ($tw:literal, $th:literal) => {{
            let mut r: Renderer<Rgb888, $tw, $th> =
                Renderer::new(Config::new(Size::new(64, 64), black).cull(CullMode::None));
            let mut ws: Box<Workspace<1024, 4096, 64>> = Box::new(Workspace::new());
            let mut cap = Capture::new(Size::new(64, 64), black);
            r.render(&mut ws, &scene, &mut cap).unwrap();
            assert_eq!(cap.get(32, 32), expect, "{}x{} tiles", $tw, $th);
        }};
    }
    check!(16, 16);
    check!(32, 16);
    check!(64, 64);
}
