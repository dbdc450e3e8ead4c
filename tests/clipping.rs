//! Clipping: triangles crossing the near or far plane, behind the camera,
//! or reaching far beyond the guard band render as an `f64` reference says.
//!
//! The reference transforms the triangle with the scene's matrices in
//! `f64`, clips it in homogeneous space against near (`z >= -w`) and far
//! (`z <= w`) with Sutherland–Hodgman, projects it with the documented
//! viewport (NDC x in [-1, 1] to [0, width], y up to y down) and tests pixel
//! centres. The renderer snaps to 1/16 pixel and runs in 16.16, so pixels
//! whose centre lies within ~0.1 px of an edge of the reference polygon are
//! not compared. Where a matrix element is not a multiple of 2^-16 the
//! renderer necessarily rounds it; the reference turns that rounding into a
//! per-vertex error bound, so the margin only grows where it must (far
//! outside the viewport, along an edge's extension).

mod support;

use embedded_graphics::pixelcolor::{Gray8, GrayColor, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use proptest::prelude::*;
use support::Capture;

const W: u32 = 64;
const H: u32 = 48;

// ---------------------------------------------------------------------------
// The f64 reference.
// ---------------------------------------------------------------------------

/// Column-major like `Mat4`: `m[column][row]`.
type M4 = [[f64; 4]; 4];

fn m64(m: &Mat4) -> M4 {
    m.m.map(|c| c.map(|v| v as f64))
}

fn mul(a: &M4, b: &M4) -> M4 {
    let mut out = [[0.0; 4]; 4];
    for (c, col) in out.iter_mut().enumerate() {
        for (r, o) in col.iter_mut().enumerate() {
            *o = (0..4).map(|k| a[k][r] * b[c][k]).sum();
        }
    }
    out
}

/// A clip-space vertex and a bound on how far the renderer's 16.16 version
/// of it may be off, per component.
#[derive(Clone, Copy, Debug)]
struct HVert {
    p: [f64; 4],
    err: f64,
}

/// Half a unit in the last place of 16.16.
const HALF_ULP: f64 = 1.0 / 131_072.0;

/// The rounding error bound of each element of `m` once converted to 16.16:
/// none when the element is a multiple of 2^-16 (the f32 product then rounds
/// back to it), half a step plus f32 round-off otherwise.
fn quantisation(m: &M4) -> M4 {
    m.map(|c| {
        c.map(|v| {
            if (v * 65_536.0).fract() == 0.0 && v.abs() < 64.0 {
                0.0
            } else {
                HALF_ULP + 1e-6 * (1.0 + v.abs())
            }
        })
    })
}

fn transform(m: &M4, q: &M4, p: [f64; 3]) -> HVert {
    let ph = [p[0], p[1], p[2], 1.0];
    let mut out = [0.0; 4];
    let mut err: f64 = 0.0;
    for (r, o) in out.iter_mut().enumerate() {
        *o = (0..4).map(|c| m[c][r] * ph[c]).sum();
        // The renderer rounds each result to 16.16 once more.
        let e = HALF_ULP + (0..4).map(|c| q[c][r] * ph[c].abs()).sum::<f64>();
        err = err.max(e);
    }
    HVert { p: out, err }
}

/// Sutherland–Hodgman against one plane, keeping `dist >= 0`.
fn clip_plane(poly: &[HVert], dist: impl Fn(&[f64; 4]) -> f64) -> Vec<HVert> {
    let mut out = Vec::new();
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let (da, db) = (dist(&a.p), dist(&b.p));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            let p: [f64; 4] = core::array::from_fn(|k| a.p[k] + t * (b.p[k] - a.p[k]));
            let span = (0..4).map(|k| (b.p[k] - a.p[k]).abs()).fold(0.0, f64::max);
            // The crossing moves along the edge when the distances are off
            // (each distance sums two components), and is rounded once.
            let e_ends = (1.0 - t) * a.err + t * b.err;
            let err = e_ends + span * 2.0 * e_ends / (da - db).abs() + HALF_ULP;
            out.push(HVert { p, err });
        }
    }
    out
}

/// The reference polygon on screen (pixels), with per-vertex error bounds
/// (pixels).
#[derive(Clone, Debug)]
struct Reference {
    pts: Vec<[f64; 2]>,
    err: Vec<f64>,
    /// Twice the signed area in NDC (y up): positive is counter-clockwise,
    /// the front face.
    ndc_area2: f64,
}

fn reference(mvp: &M4, tri: &[Vec3Fx; 3], w: u32, h: u32) -> Reference {
    let q = quantisation(mvp);
    let verts: Vec<HVert> = tri
        .iter()
        .map(|p| transform(mvp, &q, p.map(|c| c.to_num::<f64>())))
        .collect();
    let verts = clip_plane(&verts, |p| p[2] + p[3]); // near
    let verts = clip_plane(&verts, |p| p[3] - p[2]); // far
    let (hw, hh) = (w as f64 / 2.0, h as f64 / 2.0);
    let mut pts = Vec::new();
    let mut err = Vec::new();
    let mut ndc = Vec::new();
    for v in &verts {
        let [x, y, _, wc] = v.p;
        let (nx, ny) = (x / wc, y / wc);
        ndc.push([nx, ny]);
        pts.push([(nx + 1.0) * hw, (1.0 - ny) * hh]);
        // Perspective divide of an error e: (e + |ndc| e) / w per axis, plus
        // the snap to 1/16 px (at most sqrt(2)/32 px).
        let r = v.err / wc;
        err.push(0.045 + r * (1.0 + nx.abs()) * hw + r * (1.0 + ny.abs()) * hh);
    }
    let n = ndc.len();
    let ndc_area2 = (0..n)
        .map(|k| {
            let (a, b) = (ndc[k], ndc[(k + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    Reference {
        pts,
        err,
        ndc_area2,
    }
}

impl Reference {
    /// `Some(true)` when the point is inside by more than the margin of every
    /// edge, `Some(false)` when it is outside some edge by more than its
    /// margin, `None` when it is too close to call.
    fn classify(&self, x: f64, y: f64) -> Option<bool> {
        let n = self.pts.len();
        if n < 3 {
            return Some(false);
        }
        let area2: f64 = (0..n)
            .map(|k| {
                let (a, b) = (self.pts[k], self.pts[(k + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum();
        let s = if area2 < 0.0 { -1.0 } else { 1.0 };
        let mut inside = true;
        let mut edges = 0;
        for k in 0..n {
            let (a, b) = (self.pts[k], self.pts[(k + 1) % n]);
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let len2 = ex * ex + ey * ey;
            if len2 < 1e-18 {
                continue;
            }
            edges += 1;
            let len = len2.sqrt();
            let (px, py) = (x - a[0], y - a[1]);
            let d = s * (ex * py - ey * px) / len;
            let t = (px * ex + py * ey) / len2;
            let margin = (self.err[k] * (1.0 - t).abs() + self.err[(k + 1) % n] * t.abs()).max(0.1);
            if d < -margin {
                return Some(false);
            }
            if d <= margin {
                inside = false;
            }
        }
        if edges == 0 {
            // A polygon collapsed to a point (a triangle seen edge-on
            // along the line of sight) holds no pixel centre: outside
            // beyond its corners' error, too close to call within.
            let [x0, y0] = self.pts[0];
            let near = self.err.iter().fold(0.1f64, |m, &e| m.max(e));
            let far = (x - x0).hypot(y - y0) > near;
            return far.then_some(false);
        }
        inside.then_some(true)
    }
}

// ---------------------------------------------------------------------------
// The renderer side.
// ---------------------------------------------------------------------------

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

fn p3(x: f32, y: f32, z: f32) -> Vec3Fx {
    [fx(x), fx(y), fx(z)]
}

/// Renders one white triangle (Gray8, black background).
fn render_triangle(
    camera: Camera,
    model: Mat4,
    tri: &[Vec3Fx; 3],
    cull: CullMode,
) -> (Capture<Gray8>, FrameStats) {
    let triangles = [[0u16, 1, 2]];
    let mesh = Mesh::new(tri, &triangles).unwrap();
    let draws = [Draw::new(&mesh).transform(model).color(Rgb888::WHITE)];
    let scene = Scene::new(camera, &draws);
    let size = Size::new(W, H);
    let mut renderer: Renderer<Gray8, 32, 32> = Renderer::new(
        Config::new(size, Gray8::BLACK)
            .cull(cull)
            .depth_test(DepthTest::Always),
    );
    let mut ws: Workspace<3, 64, 8> = Workspace::new();
    let mut cap = Capture::new(size, Gray8::new(99));
    let stats = renderer
        .render(&mut ws, &scene, &mut cap)
        .expect("the triangle renders");
    assert!(cap.writes.iter().all(|&n| n == 1));
    (cap, stats)
}

#[derive(Debug, Default)]
struct Tally {
    must_draw: u32,
    must_not: u32,
    drawn: u32,
}

/// Compares a render with the reference; the error names the first pixel
/// that disagrees. With `once`, also requires every drawn pixel to be
/// shaded exactly once (no overlap between the pieces of a clipped fan).
fn compare(
    camera: Camera,
    model: Mat4,
    tri: &[Vec3Fx; 3],
    cull: CullMode,
    once: bool,
) -> Result<(Tally, Reference, FrameStats), String> {
    let mvp = mul(
        &mul(&m64(&camera.projection), &m64(&camera.view)),
        &m64(&model),
    );
    let r = reference(&mvp, tri, W, H);
    let (cap, stats) = render_triangle(camera, model, tri, cull);
    let lit = Gray8::from(Rgb888::WHITE);
    let mut t = Tally::default();
    for j in 0..H {
        for i in 0..W {
            let drawn = cap.get(i, j) == lit;
            t.drawn += drawn as u32;
            match r.classify(i as f64 + 0.5, j as f64 + 0.5) {
                Some(true) => {
                    t.must_draw += 1;
                    if !drawn {
                        return Err(format!(
                            "pixel ({i}, {j}) is inside the reference but not drawn; {r:?}"
                        ));
                    }
                }
                Some(false) => {
                    t.must_not += 1;
                    if drawn {
                        return Err(format!(
                            "pixel ({i}, {j}) is outside the reference but drawn; {r:?}"
                        ));
                    }
                }
                None => {}
            }
        }
    }
    // One triangle, even when clipped into a fan, shades each pixel once.
    if stats.pixels_shaded < t.drawn || (once && stats.pixels_shaded != t.drawn) {
        return Err(format!(
            "{} fragments shaded for {} pixels drawn: clipped pieces overlap ({stats:?})",
            stats.pixels_shaded, t.drawn
        ));
    }
    Ok((t, r, stats))
}

fn perspective_camera(eye: Vec3, target: Vec3, far: f32) -> Camera {
    Camera::new(
        Mat4::look_at(eye, target, Vec3::new(0.0, 1.0, 0.0)).unwrap(),
        Mat4::perspective(1.1, W as f32 / H as f32, 0.5, far).unwrap(),
    )
}

// ---------------------------------------------------------------------------
// Fixed cases.
// ---------------------------------------------------------------------------

#[test]
fn triangle_behind_the_camera_draws_nothing() {
    // Camera at z = 3 looking at the origin; near plane at z = 2.5.
    let cam = perspective_camera(Vec3::new(0.0, 0.0, 3.0), Vec3::default(), 20.0);
    let cases = [
        // Well behind the eye: projected through w < 0 it would cover the
        // middle of the screen, mirrored.
        [p3(-2.0, -2.0, 6.0), p3(2.0, -2.0, 6.0), p3(0.0, 2.0, 6.0)],
        // Straddling the eye plane (w = 0): partly between the eye and the
        // near plane (z = 2.5), partly behind the eye, nowhere in front of
        // the near plane.
        [p3(-3.0, -1.0, 2.7), p3(3.0, -1.0, 3.6), p3(0.0, 2.0, 2.9)],
        // Huge, behind the eye.
        [
            p3(-3000.0, -3000.0, 4.0),
            p3(3000.0, -3000.0, 4.0),
            p3(0.0, 3000.0, 4.0),
        ],
    ];
    for tri in cases {
        for t in [tri, [tri[0], tri[2], tri[1]]] {
            let (cap, stats) = render_triangle(cam, Mat4::IDENTITY, &t, CullMode::None);
            assert!(
                cap.pixels.iter().all(|&c| c == Gray8::BLACK),
                "{t:?} drew something"
            );
            assert_eq!(stats.pixels_shaded, 0);
            assert_eq!(stats.drawn, 0);
            assert_eq!(stats.rejected, 1, "{stats:?}");
            // And the reference agrees there is nothing to draw.
            compare(cam, Mat4::IDENTITY, &t, CullMode::None, true).unwrap();
        }
    }
}

#[test]
fn floor_through_the_near_plane_draws_its_visible_part() {
    // A floor triangle y = 0 under a camera at height 1, with one vertex
    // far behind the camera: only the part in front of the near plane shows,
    // in the lower part of the screen.
    let cam = perspective_camera(Vec3::new(0.0, 1.0, 3.0), Vec3::new(0.0, 0.6, 0.0), 20.0);
    let tri = [p3(-3.0, 0.0, -4.0), p3(3.0, 0.0, -4.0), p3(0.0, 0.0, 9.0)];
    let (t, r, stats) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
    assert_eq!(stats.clipped, 1, "{stats:?}");
    assert!(t.must_draw > 300, "{t:?}");
    assert!(t.must_not > 300, "{t:?}");
    // Bottom centre is floor in front of the camera, top centre is sky.
    let (cap, _) = render_triangle(cam, Mat4::IDENTITY, &tri, CullMode::None);
    let lit = Gray8::from(Rgb888::WHITE);
    assert_eq!(cap.get(W / 2, H - 1), lit);
    assert_eq!(cap.get(W / 2, 0), Gray8::BLACK);
    // Front or back, decided on the clipped pieces, agrees with the
    // triangle: exactly one winding survives back-face culling, and it
    // draws the same pixels as with culling off.
    let front_is_ccw = r.ndc_area2 > 0.0;
    for (tri, ccw) in [
        (tri, front_is_ccw),
        ([tri[0], tri[2], tri[1]], !front_is_ccw),
    ] {
        let (culled, _) = render_triangle(cam, Mat4::IDENTITY, &tri, CullMode::Back);
        let (all, _) = render_triangle(cam, Mat4::IDENTITY, &tri, CullMode::None);
        if ccw {
            assert_eq!(culled.pixels, all.pixels, "the front face was culled");
        } else {
            assert!(
                culled.pixels.iter().all(|&c| c == Gray8::BLACK),
                "the back face was drawn"
            );
        }
    }
}

#[test]
fn wall_through_the_near_plane_beside_the_camera() {
    // A wall x = 0.8 from behind the camera to far ahead: the near plane cuts
    // it in the right half of the screen.
    let cam = perspective_camera(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 20.0);
    let tri = [p3(0.8, -1.0, 2.0), p3(0.8, -1.0, -6.0), p3(0.8, 1.5, -1.0)];
    let (t, _, stats) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
    assert_eq!(stats.clipped, 1);
    assert!(t.must_draw > 100 && t.must_not > 100, "{t:?}");
}

#[test]
fn triangle_through_the_far_plane_loses_its_far_part() {
    let cam = perspective_camera(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 9.0);
    // From 3 to 30 units away, leaning back: the far plane (9) cuts it.
    let tri = [
        p3(-1.5, -1.0, -3.0),
        p3(1.5, -1.0, -3.0),
        p3(0.0, 20.0, -30.0),
    ];
    let (t, r, stats) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
    assert_eq!(stats.clipped, 1);
    assert!(t.must_draw > 100, "{t:?}");
    // Without the far plane the triangle would reach higher up the screen:
    // the topmost drawn row lies well below the projected far vertex.
    let top = r.pts.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    let far_vertex_y = {
        let z = 30.0f64;
        let f = 1.0 / (1.1f64 / 2.0).tan();
        (1.0 - 20.0 * f / z) * H as f64 / 2.0
    };
    assert!(top > far_vertex_y + 2.0, "{top} vs {far_vertex_y}");
}

#[test]
fn vertices_far_outside_the_guard_band() {
    // Identity camera: clip space is model space, w = 1, and the matrices
    // are exact, so the reference is exact up to the 1/16 px snap. The
    // vertices lie ~1000 viewports away.
    let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
    let cases = [
        // Covers the whole viewport.
        [
            p3(-1000.0, -1000.0, 0.0),
            p3(1000.0, -1000.0, 0.2),
            p3(0.0, 1000.0, -0.2),
        ],
        // One long edge crossing the viewport diagonally.
        [
            p3(-1000.0, -999.3, 0.0),
            p3(1000.0, 1000.45, 0.0),
            p3(-1000.0, 1000.0, 0.0),
        ],
        // A long wedge, 0.2 NDC high here, crossing the whole viewport.
        [
            p3(-1200.0, 0.1, 0.0),
            p3(1300.0, 0.12, 0.0),
            p3(1300.0, 0.52, 0.0),
        ],
        // One vertex inside, two far away on either side.
        [
            p3(0.1, 0.3, 0.0),
            p3(-900.0, -1000.0, 0.0),
            p3(1100.0, -1000.0, 0.0),
        ],
        // Far outside and through the near plane (z < -1) at once.
        [
            p3(0.2, 0.1, -0.5),
            p3(-1000.0, -700.0, -900.0),
            p3(1000.0, -800.0, 5.0),
        ],
    ];
    for tri in cases {
        let (t, _, stats) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true)
            .unwrap_or_else(|e| panic!("{tri:?}: {e}"));
        assert_eq!(stats.clipped, 1);
        assert!(t.must_draw > 50, "{tri:?}: {t:?}");
    }

    // The same through a real perspective camera, the far vertices 1000
    // viewports out to the sides at depth 3.
    let cam = perspective_camera(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 20.0);
    let cases = [
        [
            p3(0.1, 0.2, -3.0),
            p3(-3000.0, -1500.0, -3.0),
            p3(3000.0, -2000.0, -3.0),
        ],
        [
            p3(-0.3, -0.1, -2.5),
            p3(2500.0, 800.0, -3.0),
            p3(2000.0, 3000.0, -3.5),
        ],
    ];
    for tri in cases {
        let (t, _, stats) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true)
            .unwrap_or_else(|e| panic!("{tri:?}: {e}"));
        assert_eq!(stats.clipped, 1);
        assert!(t.must_draw > 50, "{tri:?}: {t:?}");
    }
}

// ---------------------------------------------------------------------------
// Random triangles.
// ---------------------------------------------------------------------------

/// A 16.16 coordinate in `[lo, hi]`, any raw value.
fn coord_in(lo: i32, hi: i32) -> impl Strategy<Value = I16F16> {
    (lo * 65_536..=hi * 65_536).prop_map(I16F16::from_bits)
}

/// A 16.16 coordinate in `[-r, r]`.
fn coord(r: i32) -> impl Strategy<Value = I16F16> {
    coord_in(-r, r)
}

/// Anywhere around the camera: in front, behind, beyond the far plane,
/// beside the eye (huge NDC), or inside the central view.
fn vertex() -> impl Strategy<Value = Vec3Fx> {
    prop_oneof![
        3 => [coord_in(-5, 5), coord_in(-4, 4), coord_in(-11, 11)],
        1 => [coord_in(-1, 1), coord_in(-1, 1), coord_in(-4, 1)],
        1 => [coord_in(-6, 6), coord_in(-6, 6), coord_in(2, 3)],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, ..ProptestConfig::default() })]

    /// Random triangles through a perspective camera at z = 2.5 looking
    /// down -z (near 0.5, far 9) match the reference.
    #[test]
    fn random_triangles_match_the_reference(tri in [vertex(), vertex(), vertex()]) {
        let cam = perspective_camera(
            Vec3::new(0.4, 0.3, 2.5),
            Vec3::new(0.0, 0.0, -1.0),
            9.0,
        );
        // Snapping can make a clipped polygon very slightly concave; the
        // renderer must still shade every pixel exactly once.
        if let Err(e) = compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true) {
            return Err(TestCaseError::fail(e));
        }
    }

    /// Random triangles with exact matrices, vertices up to 1200 viewports
    /// away in x and y and beyond near and far in z.
    #[test]
    fn random_huge_triangles_match_the_reference(
        a in [coord(2), coord(2), coord(2)],
        b in [coord(1200), coord(1200), coord(3)],
        c in [coord(1200), coord(1200), coord(3)],
    ) {
        let cam = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
        if let Err(e) = compare(cam, Mat4::IDENTITY, &[a, b, c], CullMode::None, true) {
            return Err(TestCaseError::fail(e));
        }
    }
}

/// A back-facing triangle whose clipped, snapped polygon is very slightly
/// concave: no fan piece may escape culling, and with culling off every
/// pixel is shaded exactly once. (Found by the random search above.)
#[test]
fn slightly_concave_clipped_polygon_is_culled_and_shaded_once() {
    let cam = Camera::new(
        Mat4::look_at(
            Vec3::default(),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(1.0, 1.0, 0.5, 10.0).unwrap(),
    );
    let v = p3;
    let back = [
        v(1.765625, 3.53125, -9.609375),
        v(1.859375, -0.234375, 1.890625),
        v(-2.171875, 3.0625, -11.453125),
    ];
    let (cap, stats) = render_triangle(cam, Mat4::IDENTITY, &back, CullMode::Back);
    assert_eq!(stats.pixels_shaded, 0, "{stats:?}");
    assert_eq!(stats.culled, 1, "{stats:?}");
    assert!(cap.pixels.iter().all(|&c| c == Gray8::BLACK));

    let front = [back[0], back[2], back[1]];
    for cull in [CullMode::None, CullMode::Back] {
        let (cap, stats) = render_triangle(cam, Mat4::IDENTITY, &front, cull);
        let drawn = cap.pixels.iter().filter(|&&c| c != Gray8::BLACK).count() as u32;
        assert!(drawn > 0);
        assert_eq!(stats.pixels_shaded, drawn, "{cull:?}: {stats:?}");
    }
}

/// A clipped, snapped polygon with two reflex vertices, star-shaped from
/// the second only: fanned from the first, two pieces overlapped and a
/// pixel was shaded twice. (Found by the random search above.)
#[test]
fn polygon_with_two_reflex_vertices_is_shaded_once() {
    let cam = perspective_camera(Vec3::new(0.4, 0.3, 2.5), Vec3::new(0.0, 0.0, -1.0), 9.0);
    let tri = [
        p3(-0.09938, -4.9563, 2.03772),
        p3(0.40562, 1.764, -8.9905),
        p3(0.17711, -2.16167, 7.01346),
    ];
    compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
}

/// A clipped polygon whose snapped vertices fan into overlapping pieces
/// from every vertex: still every pixel shaded once. (Found by the random
/// search above.)
#[test]
fn polygon_fanning_from_no_vertex_is_shaded_once() {
    let cam = perspective_camera(Vec3::new(0.4, 0.3, 2.5), Vec3::new(0.0, 0.0, -1.0), 9.0);
    let tri = [
        p3(-0.5273, -0.35722, -0.56526),
        p3(2.7879, -2.16945, 9.38312),
        p3(-2.62396, 0.03519, -7.02246),
    ];
    compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
}

/// A clipped polygon that snapping folds over itself (a spike whose sides
/// cross), star-shaped from no vertex: still every pixel shaded once.
/// (Found by the random search above.)
#[test]
fn folded_polygon_is_shaded_once() {
    let cam = perspective_camera(Vec3::new(0.4, 0.3, 2.5), Vec3::new(0.0, 0.0, -1.0), 9.0);
    let tri = [
        p3(-3.47757, 0.04996, 7.23784),
        p3(-0.09161, 0.26251, -1.59828),
        p3(1.23158, 0.3245, -9.69272),
    ];
    compare(cam, Mat4::IDENTITY, &tri, CullMode::None, true).unwrap();
}
