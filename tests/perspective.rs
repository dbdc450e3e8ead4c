//! Perspective-correct varyings against an `f64` reference: a textured
//! floor receding to the horizon, seen at a grazing angle, rendered with
//! a shader that writes its interpolated texture coordinates out as the
//! "colour". Exact mode must match the reference within the bound the
//! weights' precision gives; the quasi-perspective modes within that plus
//! the documented error of linear steps between samples; affine mode
//! interpolates linearly in screen space.

mod support;

use embedded_graphics::pixelcolor::{raw::RawU1, PixelColor, Rgb888};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shader::{Fragment, VertexInput};
use support::Capture;

/// The texture coordinates of a fragment, as a colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Probe {
    uv: Option<[i32; 2]>,
}

impl PixelColor for Probe {
    type Raw = RawU1;
}

impl From<Rgb888> for Probe {
    fn from(_: Rgb888) -> Self {
        Probe::default()
    }
}

// The renderer reads tiles back as Rgb888 only to blend; this scene does
// not blend.
impl From<Probe> for Rgb888 {
    fn from(_: Probe) -> Self {
        Rgb888::new(0, 0, 0)
    }
}

struct UvOut;

impl FragmentShader<Probe> for UvOut {
    type Varyings = [I16F16; 2];
    const INTERPOLATE_COLOR: bool = false;
    fn vertex(&self, v: &VertexInput<'_>) -> [I16F16; 2] {
        v.uv()
    }
    fn fragment(&self, f: &Fragment<'_, [I16F16; 2]>) -> Option<Probe> {
        Some(Probe {
            uv: Some(f.varyings.map(|a| a.to_bits())),
        })
    }
}

const W: u32 = 160;
const H: u32 = 120;

/// Every perspective mode.
const MODES: [Perspective; 4] = [
    Perspective::Exact,
    Perspective::Quasi8,
    Perspective::Quasi16,
    Perspective::Affine,
];

fn fx(v: f32) -> I16F16 {
    I16F16::from_num(v)
}

/// A floor quad from z = -0.5 to z = -60, u across 0..1, v along 0..16.
fn floor() -> (Vec<Vec3Fx>, Vec<[I16F16; 2]>, Vec<[u16; 3]>) {
    let p = |x: f32, z: f32| [fx(x), fx(0.0), fx(z)];
    let positions = vec![p(-4.0, -0.5), p(4.0, -0.5), p(4.0, -60.0), p(-4.0, -60.0)];
    let uvs = vec![
        [fx(0.0), fx(0.0)],
        [fx(1.0), fx(0.0)],
        [fx(1.0), fx(16.0)],
        [fx(0.0), fx(16.0)],
    ];
    (positions, uvs, vec![[0, 1, 2], [0, 2, 3]])
}

fn camera() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(0.0, 0.6, -10.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(1.0, W as f32 / H as f32, 0.25, 100.0).unwrap(),
    )
}

struct Frame {
    probe: Capture<Probe>,
    /// Snapped screen positions of the four vertices, in pixels.
    screen: Vec<[f64; 2]>,
}

/// The floor seen from above through an orthographic camera: every
/// vertex has the same clip-space `w`.
fn orthographic_camera() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 30.0, -10.0),
            Vec3::new(0.0, 0.0, -30.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::orthographic(-5.0, 5.0, -27.0, 27.0, 0.25, 100.0).unwrap(),
    )
}

fn render<const TW: usize, const TH: usize>(perspective: Perspective, raster: Rasterizer) -> Frame {
    render_with::<TW, TH>(&camera(), perspective, raster)
}

fn render_with<const TW: usize, const TH: usize>(
    camera: &Camera,
    perspective: Perspective,
    raster: Rasterizer,
) -> Frame {
    let (positions, uvs, triangles) = floor();
    let mesh = Mesh::new(&positions, &triangles)
        .unwrap()
        .with_uvs(&uvs)
        .unwrap();
    let draws = [Draw::new(&mesh).shading(Shading::Shader)];
    let scene = Scene::new(*camera, &draws).shader(&UvOut);
    let config = Config::new(Size::new(W, H), Probe::default())
        .cull(CullMode::None)
        .perspective(perspective)
        .rasterizer(raster);
    let mut r: Renderer<Probe, TW, TH> = Renderer::new(config);
    let mut ws: Box<Workspace<8, 1024, 128>> = Box::new(Workspace::new());
    let mut probe = Capture::new(Size::new(W, H), Probe::default());
    let stats = r.render(&mut ws, &scene, &mut probe).unwrap();
    assert_eq!(stats.clipped, 0, "the test scene needs no clipping");
    let screen = ws.vertices()[..4]
        .iter()
        .map(|v| [v.x() as f64 / 16.0, v.y() as f64 / 16.0])
        .collect();
    Frame { probe, screen }
}

/// The reference: `1 / w` of each vertex (from the `f32` matrices, in
/// `f64`), and the perspective-correct texture coordinates at any screen
/// point of the floor's plane, from the snapped screen positions.
struct Reference {
    screen: Vec<[f64; 2]>,
    inv_w: Vec<f64>,
    uvs: Vec<[f64; 2]>,
}

impl Reference {
    fn new(screen: Vec<[f64; 2]>) -> Self {
        Self::with_camera(screen, &camera())
    }

    fn with_camera(screen: Vec<[f64; 2]>, cam: &Camera) -> Self {
        let (positions, uvs, _) = floor();
        let vp = cam.projection * cam.view;
        let inv_w = positions
            .iter()
            .map(|p| {
                let p = p.map(|c| c.to_num::<f64>());
                let m = &vp.m;
                let w = m[0][3] as f64 * p[0]
                    + m[1][3] as f64 * p[1]
                    + m[2][3] as f64 * p[2]
                    + m[3][3] as f64;
                1.0 / w
            })
            .collect();
        let uvs = uvs.iter().map(|t| t.map(|c| c.to_num::<f64>())).collect();
        Self { screen, inv_w, uvs }
    }

    /// Screen barycentrics of `(x, y)` in triangle `t` of the quad.
    fn lambda(&self, t: [usize; 3], x: f64, y: f64) -> [f64; 3] {
        let [a, b, c] = t.map(|i| self.screen[i]);
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / area;
        let l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / area;
        [1.0 - l1 - l2, l1, l2]
    }

    /// The triangle holding `(x, y)` (either, on the diagonal: the quad is
    /// a parallelogram in texture space, so both give the same map).
    fn triangle(&self, x: f64, y: f64) -> [usize; 3] {
        let t = [0, 2, 3];
        if self.lambda(t, x, y).iter().all(|&l| l >= -1e-9) {
            t
        } else {
            [0, 1, 2]
        }
    }

    /// Perspective-correct `(u, v)` and `1 / w` at `(x, y)`, extended
    /// beyond the triangle by the same plane.
    fn at(&self, t: [usize; 3], x: f64, y: f64) -> ([f64; 2], f64) {
        let l = self.lambda(t, x, y);
        let q: f64 = (0..3).map(|k| l[k] * self.inv_w[t[k]]).sum();
        let uv = [0, 1].map(|c| {
            (0..3)
                .map(|k| l[k] * self.inv_w[t[k]] * self.uvs[t[k]][c])
                .sum::<f64>()
                / q
        });
        (uv, q)
    }

    /// Screen-space linear `(u, v)` at `(x, y)`.
    fn affine(&self, t: [usize; 3], x: f64, y: f64) -> [f64; 2] {
        let l = self.lambda(t, x, y);
        [0, 1].map(|c| (0..3).map(|k| l[k] * self.uvs[t[k]][c]).sum())
    }
}

/// The tolerance of exact mode, in units of 2^-16: each weight is within
/// 7/65,536 of exact (see `shade::perspective::weights`), plus the
/// rounding of the planes and of the vertices' `w`, so a varying is within
/// `8 (|a1 - a0| + |a2 - a0|) / 65,536` plus one unit. For the floor's
/// `v` (0 to 16 over a triangle) that is 257 units, under 1/250 of a
/// texture repeat.
fn exact_tolerance(r: &Reference, t: [usize; 3], c: usize) -> f64 {
    let d = |k: usize| (r.uvs[t[k]][c] - r.uvs[t[0]][c]).abs() * 65_536.0;
    8.0 * (d(1) + d(2)) / 65_536.0 + 1.0
}

/// Affine mode's tolerance, in units of 2^-16 of coordinate `c`: each
/// value is its sum over the plane values `B1`, `B2` (weights in units of
/// 2^-28) rounded once, half a unit; the planes' gradients are rounded to
/// whole units of 2^-28, half a unit a pixel, so 2^-20 of each difference
/// `d` allows 2^9 pixels between a pixel and a plane's origin (this
/// frame's worst is 0.51 units; weights truncated to 16 bits before the
/// sum, as affine mode took them before, cost up to 30).
fn affine_tolerance(r: &Reference, t: [usize; 3], c: usize) -> f64 {
    let d = |k: usize| (r.uvs[t[k]][c] - r.uvs[t[0]][c]).abs() * 65_536.0;
    (d(1) + d(2)) / (1u32 << 20) as f64 + 0.5 + 1e-9
}

/// Every probed pixel, with its reference triangle and pixel centre.
fn pixels(f: &Frame) -> Vec<(u32, u32, [i32; 2])> {
    let mut out = Vec::new();
    for y in 0..H {
        for x in 0..W {
            if let Some(uv) = f.probe.get(x, y).uv {
                out.push((x, y, uv));
            }
        }
    }
    assert!(out.len() > 5_000, "the floor covers much of the frame");
    out
}

#[test]
fn exact_mode_matches_the_f64_reference() {
    let f = render::<16, 16>(Perspective::Exact, Rasterizer::Scanline);
    let r = Reference::new(f.screen.clone());
    let mut worst = [0f64; 2];
    for (x, y, uv) in pixels(&f) {
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        let t = r.triangle(cx, cy);
        let (reference, _) = r.at(t, cx, cy);
        for c in 0..2 {
            let err = (uv[c] as f64 - reference[c] * 65_536.0).abs();
            worst[c] = worst[c].max(err);
            assert!(
                err <= exact_tolerance(&r, t, c),
                "pixel ({x}, {y}) coordinate {c}: {} vs {} ({err} units)",
                uv[c],
                reference[c] * 65_536.0
            );
        }
    }
    // The bound is not vacuous: the floor's v spans 16 repeats, so a
    // plain affine interpolation would miss by thousands of units.
    assert!(worst[1] > 0.0);
    eprintln!(
        "exact mode: worst error u {} v {} units",
        worst[0], worst[1]
    );
}

/// `(sqrt r - 1) / (sqrt r + 1)`: the largest relative error of linear
/// interpolation between two samples whose `1 / w` are in ratio `r`.
fn hyperbola_error(r: f64) -> f64 {
    let s = r.max(1.0 / r).sqrt();
    (s - 1.0) / (s + 1.0)
}

fn check_quasi(mode: Perspective, n: usize) {
    let f = render::<16, 16>(mode, Rasterizer::Scanline);
    let exact = render::<16, 16>(Perspective::Exact, Rasterizer::Scanline);
    let r = Reference::new(f.screen.clone());
    let mut differs = 0;
    let mut worst_ratio = 0f64;
    for (x, y, uv) in pixels(&f) {
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        let t = r.triangle(cx, cy);
        let (reference, _) = r.at(t, cx, cy);
        differs += (exact.probe.get(x, y).uv != Some(uv)) as u32;
        for c in 0..2 {
            // Whatever segment of n pixels holds this pixel, the linear
            // step between its samples is off the hyperbola by at most
            // |Δa| (√r - 1) / (√r + 1), plus the exact mode's error at the
            // samples, plus the step's rounding (n units).
            let mut bound = 0f64;
            for start in x as i64 - n as i64..=x as i64 {
                let (a, qa) = r.at(t, start as f64 + 0.5, cy);
                let (b, qb) = r.at(t, (start + n as i64) as f64 + 0.5, cy);
                let span = (b[c] - a[c]).abs() * 65_536.0;
                bound = bound.max(span * hyperbola_error(qb / qa));
            }
            let tol = bound + exact_tolerance(&r, t, c) + n as f64;
            let err = (uv[c] as f64 - reference[c] * 65_536.0).abs();
            worst_ratio = worst_ratio.max(err / tol);
            assert!(
                err <= tol,
                "{mode:?} pixel ({x}, {y}) coordinate {c}: {err} units, bound {tol}"
            );
        }
    }
    assert!(
        differs > 100,
        "{mode:?} should differ from exact: {differs}"
    );
    eprintln!("{mode:?}: worst error / bound {worst_ratio:.3}");
}

#[test]
fn quasi_perspective_stays_within_its_bound() {
    check_quasi(Perspective::Quasi8, 8);
    check_quasi(Perspective::Quasi16, 16);
}

#[test]
fn affine_mode_is_linear_in_screen_space() {
    let f = render::<16, 16>(Perspective::Affine, Rasterizer::Scanline);
    let r = Reference::new(f.screen.clone());
    let (worst, far_from_perspective) =
        within_affine_tolerance(&f, &r, |t, x, y| r.affine(t, x, y));
    assert!(far_from_perspective > 100, "the scene shows the difference");
    eprintln!("affine: worst error {worst:.3} units");
}

/// Holds every pixel of `f` to affine mode's tolerance of `expected` (its
/// values at a pixel centre in a triangle of `r`); returns the worst error
/// and how many coordinates `expected` puts more than 0.5 (half a texture
/// repeat) from the perspective-correct value.
fn within_affine_tolerance(
    f: &Frame,
    r: &Reference,
    expected: impl Fn([usize; 3], f64, f64) -> [f64; 2],
) -> (f64, u32) {
    let mut far_from_perspective = 0;
    let mut worst = 0f64;
    for (x, y, uv) in pixels(f) {
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        let t = r.triangle(cx, cy);
        let reference = expected(t, cx, cy);
        let (correct, _) = r.at(t, cx, cy);
        for c in 0..2 {
            let err = (uv[c] as f64 - reference[c] * 65_536.0).abs();
            worst = worst.max(err);
            assert!(
                err <= affine_tolerance(r, t, c),
                "pixel ({x}, {y}) coordinate {c}: {err} units"
            );
            far_from_perspective += ((correct[c] - reference[c]).abs() > 0.5) as u32;
        }
    }
    (worst, far_from_perspective)
}

/// Through an orthographic camera every vertex has the same `w`, so the
/// perspective-correct varyings are the affine ones, and every mode
/// interpolates them affinely: the same values in all four modes, each
/// within affine mode's tolerance of the `f64` reference (the exact
/// weights, truncated to 16 bits before their sum, would miss it).
#[test]
fn an_orthographic_frame_is_affine_in_every_mode() {
    let cam = orthographic_camera();
    let frames = MODES.map(|m| render_with::<16, 16>(&cam, m, Rasterizer::Scanline));
    for (mode, f) in MODES.iter().zip(&frames).skip(1) {
        assert!(
            f.probe.pixels == frames[0].probe.pixels,
            "{mode:?} draws what Exact draws"
        );
    }
    let r = Reference::with_camera(frames[0].screen.clone(), &cam);
    assert!(r.inv_w.iter().all(|&q| q == r.inv_w[0]), "one w");
    let (worst, _) = within_affine_tolerance(&frames[0], &r, |t, x, y| r.at(t, x, y).0);
    eprintln!("orthographic: worst error {worst:.3} units");
}

/// Every mode gives the same varyings with either rasterizer and any tile
/// size whose width is a multiple of 16: spans are the same, and the
/// quasi-perspective samples are the screen columns `x = 0 (mod N)` (and
/// each span's ends, which a tile's edge at such a column does not move).
#[test]
fn rasterizers_agree_on_varyings() {
    for mode in MODES {
        let a = render::<16, 16>(mode, Rasterizer::Scanline);
        for raster in [Rasterizer::Hilbert, Rasterizer::Auto] {
            let b = render::<16, 16>(mode, raster);
            assert!(a.probe.pixels == b.probe.pixels, "{mode:?} {raster:?}");
        }
    }
    // No mode's values depend on where tiles cut the spans.
    for mode in MODES {
        let a = render::<16, 16>(mode, Rasterizer::Scanline);
        for b in [
            render::<64, 8>(mode, Rasterizer::Scanline),
            render::<32, 24>(mode, Rasterizer::Auto),
            render::<48, 5>(mode, Rasterizer::Scanline),
        ] {
            let same = a
                .probe
                .pixels
                .iter()
                .zip(&b.probe.pixels)
                .filter(|(p, q)| p == q)
                .count();
            assert_eq!(same, a.probe.pixels.len(), "{mode:?} across tile sizes");
        }
    }
    // Exact and affine values do not depend on it even at other widths.
    for mode in [Perspective::Exact, Perspective::Affine] {
        let a = render::<16, 16>(mode, Rasterizer::Scanline);
        let b = render::<24, 8>(mode, Rasterizer::Scanline);
        assert!(a.probe.pixels == b.probe.pixels, "{mode:?} at width 24");
    }
}
