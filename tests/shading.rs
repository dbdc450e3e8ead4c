//! Golden images of the classic shading scenes, each rendered with every
//! rasterizer and tile order (which must agree pixel for pixel) and
//! compared exactly with `tests/golden/`: an unshaded triangle, a Gouraud
//! triangle, a textured triangle, a textured plane receding to the
//! horizon (perspective-correct and affine), a depth-shaded scene, normals
//! as colour, a lit textured cube, wireframe over shaded, points, and a
//! transparent object. `BLESS=1 cargo test --test shading` regenerates them
//! (look at them before committing).

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shader::{DepthShade, Normals, Textured, TexturedLit};
use microraster::texture::{Filter, Texels, Texture};
use support::{check_golden, Capture};

const W: u32 = 160;
const H: u32 = 120;
const BACKGROUND: Rgb565 = Rgb565::new(3, 6, 8);

/// Renders `scene` with every rasterizer and tile order, requires the same
/// pixels from all, and compares them with the golden image `name`.
fn golden<F: FragmentShader<Rgb565>>(name: &str, scene: &Scene<'_, F>, config: Config<Rgb565>) {
    let reference = render(scene, config);
    for (raster, order) in [
        (Rasterizer::Hilbert, TileOrder::RowMajor),
        (Rasterizer::Auto, TileOrder::RowMajor),
        (Rasterizer::Hilbert, TileOrder::Hilbert),
    ] {
        let other = render(scene, config.rasterizer(raster).tile_order(order));
        assert!(
            other.pixels == reference.pixels,
            "{name}: {raster:?} with {order:?} tiles differs from the scanline rasterizer"
        );
    }
    check_golden(name, config.size, &reference.to_rgb());
}

fn render<F: FragmentShader<Rgb565>>(
    scene: &Scene<'_, F>,
    config: Config<Rgb565>,
) -> Capture<Rgb565> {
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, 4096, 80>> = Box::new(Workspace::new());
    let mut cap = Capture::new(config.size, config.clear_color);
    r.render(&mut ws, scene, &mut cap).expect("scene renders");
    assert!(cap.writes.iter().all(|&w| w == 1), "every pixel sent once");
    cap
}

fn config() -> Config<Rgb565> {
    Config::new(Size::new(W, H), BACKGROUND)
}

fn p(x: f32, y: f32, z: f32) -> Vec3Fx {
    [
        I16F16::from_num(x),
        I16F16::from_num(y),
        I16F16::from_num(z),
    ]
}

fn uv(u: f32, v: f32) -> [I16F16; 2] {
    [I16F16::from_num(u), I16F16::from_num(v)]
}

/// A camera looking down -z from z = 3 at the origin.
fn front_camera() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(0.9, W as f32 / H as f32, 0.5, 20.0).unwrap(),
    )
}

static TRIANGLE: [[u16; 3]; 1] = [[0, 1, 2]];

fn triangle_positions() -> [Vec3Fx; 3] {
    [p(-1.2, -0.9, 0.0), p(1.3, -0.7, -0.4), p(-0.1, 1.0, 0.3)]
}

#[test]
fn unshaded_triangle() {
    let pos = triangle_positions();
    let mesh = Mesh::new(&pos, &TRIANGLE).unwrap();
    let draws = [Draw::new(&mesh)
        .color(Rgb888::new(240, 200, 60))
        .shading(Shading::Flat)];
    golden(
        "unshaded_triangle",
        &Scene::new(front_camera(), &draws),
        config(),
    );
}

#[test]
fn gouraud_triangle() {
    let pos = triangle_positions();
    let colors = [Rgb888::RED, Rgb888::GREEN, Rgb888::BLUE];
    let mesh = Mesh::new(&pos, &TRIANGLE)
        .unwrap()
        .with_colors(&colors)
        .unwrap();
    let draws = [Draw::new(&mesh)];
    golden(
        "gouraud_triangle",
        &Scene::new(front_camera(), &draws),
        config(),
    );
}

#[test]
fn textured_triangle() {
    let texels = checker_texels(32);
    let nearest = Texture::new(32, 32, Texels::Rgb565(&texels)).unwrap();
    let bilinear = nearest.filter(Filter::Bilinear);
    let pos = triangle_positions();
    let uvs = [uv(0.0, 2.0), uv(2.0, 2.0), uv(1.0, 0.0)];
    let mesh = Mesh::new(&pos, &TRIANGLE).unwrap().with_uvs(&uvs).unwrap();
    for (name, tex) in [
        ("textured_triangle", &nearest),
        ("textured_triangle_bilinear", &bilinear),
    ] {
        let draws = [Draw::new(&mesh).shading(Shading::Shader).texture(tex)];
        let scene = Scene::new(front_camera(), &draws).shader(&Textured);
        golden(name, &scene, config());
    }
}

/// A floor from just in front of the camera to far away: the texture's
/// squares must shrink towards the horizon and stay straight, which only
/// perspective-correct interpolation gives; the affine image shows the
/// bent squares it would have instead.
#[test]
fn textured_plane_to_the_horizon() {
    let texels = checker_texels(32);
    let tex = Texture::new(32, 32, Texels::Rgb565(&texels)).unwrap();
    let pos = [
        p(-6.0, 0.0, 1.0),
        p(6.0, 0.0, 1.0),
        p(6.0, 0.0, -60.0),
        p(-6.0, 0.0, -60.0),
    ];
    let uvs = [uv(0.0, 0.0), uv(4.0, 0.0), uv(4.0, 40.0), uv(0.0, 40.0)];
    let tris = [[0u16, 1, 2], [0, 2, 3]];
    let mesh = Mesh::new(&pos, &tris).unwrap().with_uvs(&uvs).unwrap();
    let draws = [Draw::new(&mesh).shading(Shading::Shader).texture(&tex)];
    let camera = Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 1.0, 3.0),
            Vec3::new(0.0, 0.5, -10.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap(),
        Mat4::perspective(1.0, W as f32 / H as f32, 0.3, 80.0).unwrap(),
    );
    let scene = Scene::new(camera, &draws).shader(&Textured);
    let cfg = config().cull(CullMode::None);
    golden("textured_plane", &scene, cfg);
    golden(
        "textured_plane_quasi16",
        &scene,
        cfg.perspective(Perspective::Quasi16),
    );
    golden(
        "textured_plane_affine",
        &scene,
        cfg.perspective(Perspective::Affine),
    );
}

#[test]
fn depth_shaded_scene() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.7, Shading::Shader);
    // The scene's depths lie in the upper part of the 16-bit range
    // (perspective depth is z / w): stretch that part to full contrast.
    let shade = DepthShade::new(56_000, 62_000);
    let scene = Scene::new(camera(W, H), &d).shader(&shade);
    golden("depth_scene", &scene, config());
}

#[test]
fn normals_as_colour() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.7, Shading::Shader);
    let scene = Scene::new(camera(W, H), &d).shader(&Normals);
    golden("normals_scene", &scene, config());
}

#[test]
fn lit_textured_cube() {
    let texels = checker_texels(32);
    let tex = Texture::new(32, 32, Texels::Rgb565(&texels))
        .unwrap()
        .filter(Filter::Bilinear);
    let cube = textured_cube();
    let draws = [Draw::new(&cube)
        .transform(
            Mat4::rotation_y(0.6) * Mat4::rotation_x(0.5) * Mat4::scale(Vec3::new(0.8, 0.8, 0.8)),
        )
        .shading(Shading::Shader)
        .texture(&tex)];
    let scene = Scene::new(front_camera(), &draws)
        .light(light())
        .shader(&TexturedLit);
    golden("lit_textured_cube", &scene, config());
}

/// A coarse knot (60 x 6), whose edges stay apart at this size.
struct CoarseKnot {
    positions: Vec<Vec3Fx>,
    normals: Vec<Vec3Fx>,
    triangles: Vec<[u16; 3]>,
}

impl CoarseKnot {
    fn new() -> Self {
        use microraster::shapes::{torus_knot, torus_knot_size};
        let (nv, nt) = torus_knot_size(60, 6);
        let mut k = Self {
            positions: vec![[I16F16::ZERO; 3]; nv],
            normals: vec![[I16F16::ZERO; 3]; nv],
            triangles: vec![[0; 3]; nt],
        };
        torus_knot(
            KNOT_P,
            KNOT_Q,
            KNOT_RADIUS,
            KNOT_TUBE,
            60,
            6,
            &mut k.positions,
            &mut k.normals,
            &mut k.triangles,
        )
        .unwrap();
        k
    }

    fn mesh(&self) -> Mesh<'_> {
        Mesh::new(&self.positions, &self.triangles)
            .unwrap()
            .with_normals(&self.normals)
            .unwrap()
    }
}

#[test]
fn wireframe_over_shaded_and_alone() {
    let coarse = CoarseKnot::new();
    let (knot, cube) = (coarse.mesh(), cube());
    let [k, c] = draws(&knot, &cube, 0.7, Shading::Gouraud);
    let overlay = [
        k.edges(Edges::new(Rgb888::new(20, 20, 20))),
        c.edges(Edges::new(Rgb888::WHITE)),
    ];
    let scene = Scene::new(camera(W, H), &overlay).light(light());
    golden("wireframe_over_shaded", &scene, config());
    let alone = [
        k.shading(Shading::Wireframe),
        c.shading(Shading::Wireframe)
            .edges(Edges::new(Rgb888::WHITE)),
    ];
    let scene = Scene::new(camera(W, H), &alone).light(light());
    golden("wireframe", &scene, config());
    let points = [k.shading(Shading::Points(1)), c.shading(Shading::Points(3))];
    let scene = Scene::new(camera(W, H), &points).light(light());
    golden("points", &scene, config());
}

#[test]
fn transparent_object() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let [k, c] = draws(&knot, &cube, 0.7, Shading::Gouraud);
    // A big glass cube around the knot (both faces of it, back to front),
    // and the small cube glowing additively.
    let glass = Draw::new(&cube)
        .transform(Mat4::translation(Vec3::new(-0.3, 0.0, 0.0)) * Mat4::rotation_y(0.4))
        .color(Rgb888::new(120, 200, 255))
        .blend(Blend::Alpha(96));
    let d = [k, c.blend(Blend::Additive), glass];
    let scene = Scene::new(camera(W, H), &d).light(light());
    golden("transparent", &scene, config().cull(CullMode::None));
}

/// Several lights at once: a dim directional light, a warm and a cool
/// point light, shiny materials (Blinn-Phong highlights) and linear fog,
/// on the knot (Gouraud) and the lit textured cube.
#[test]
fn lights_highlights_and_fog() {
    use microraster::light::{DirectionalLight, Fog, Lighting, Material, PointLight};
    let assets = DemoAssets::new();
    let knot = assets.knot();
    let texels = checker_texels(32);
    let tex = Texture::new(32, 32, Texels::Rgb565(&texels))
        .unwrap()
        .filter(Filter::Bilinear);
    let cube = textured_cube();
    let sun = [DirectionalLight::new(
        Vec3::new(-0.3, 1.0, 0.4),
        Rgb888::new(70, 70, 90),
    )];
    let lamps = [
        PointLight::new(Vec3::new(-1.8, 1.2, 1.5), Rgb888::new(255, 170, 90), 5.0),
        PointLight::new(Vec3::new(2.2, -0.8, 1.8), Rgb888::new(80, 160, 255), 5.0),
    ];
    let lighting = Lighting::new(Rgb888::new(25, 25, 35))
        .directional(&sun)
        .point(&lamps)
        .fog(Fog::Linear {
            start: 3.5,
            end: 7.0,
        })
        .fog_color(Rgb888::new(24, 24, 64));
    let shiny = Material::new()
        .specular(Rgb888::new(255, 255, 255))
        .shininess(40);
    let [k, c] = draws(&knot, &cube, 0.7, Shading::Gouraud);
    let d = [
        k.material(shiny),
        c.material(shiny.shininess(12))
            .shading(Shading::Shader)
            .texture(&tex),
    ];
    let scene = Scene::new(camera(W, H), &d)
        .lighting(&lighting)
        .shader(&TexturedLit);
    golden("lights_and_fog", &scene, config());
}
