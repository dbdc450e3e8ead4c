//! The classic shading scenes, shared by the golden tests
//! (`tests/shading.rs`) and the gallery (`examples/gallery.rs`, which
//! draws `docs/gallery.png` for the README): an unshaded triangle, a
//! Gouraud triangle, textured triangles, a textured plane receding to the
//! horizon, a depth-shaded scene, normals as colour, a lit textured cube,
//! several lights with highlights and fog, wireframe over shaded,
//! wireframe alone, points, and transparency.
//!
//! `common::gallery` (it uses the demo scene of `common`).
#![allow(dead_code)]

use crate::common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::light::{DirectionalLight, Fog, Lighting, Material, PointLight};
use microraster::mesh::Vec3Fx;
use microraster::shader::{DepthShade, Normals, Textured, TexturedLit};
use microraster::texture::{Filter, Texels, Texture};

/// Width of every scene.
pub const W: u32 = 160;
/// Height of every scene.
pub const H: u32 = 120;
/// The background.
pub const BACKGROUND: Rgb565 = Rgb565::new(3, 6, 8);

/// Every scene, in gallery order: the name of its golden image and a
/// caption.
pub const SCENES: [(&str, &str); 16] = [
    ("unshaded_triangle", "unshaded"),
    ("gouraud_triangle", "Gouraud"),
    ("textured_triangle", "textured, nearest"),
    ("textured_triangle_bilinear", "textured, bilinear"),
    ("textured_plane", "perspective-correct"),
    ("textured_plane_quasi16", "quasi-perspective 16"),
    ("textured_plane_affine", "affine"),
    ("depth_scene", "depth"),
    ("normals_scene", "normals"),
    ("lit_textured_cube", "lit textured cube"),
    ("lights_and_fog", "lights, highlights, fog"),
    ("wireframe_over_shaded", "wireframe over shaded"),
    ("wireframe", "wireframe"),
    ("points", "points"),
    ("transparent", "alpha and additive"),
    ("knot_flat", "flat"),
];

/// The meshes and textures the scenes use, generated once.
pub struct Gallery {
    assets: DemoAssets,
    coarse: CoarseKnot,
    texels: Vec<u16>,
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
        .expect("the coarse knot's parameters are valid");
        k
    }

    fn mesh(&self) -> Mesh<'_> {
        Mesh::new(&self.positions, &self.triangles)
            .and_then(|m| m.with_normals(&self.normals))
            .expect("the coarse knot is valid")
    }
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
        .expect("a valid view"),
        Mat4::perspective(0.9, W as f32 / H as f32, 0.5, 20.0).expect("a valid projection"),
    )
}

/// A camera 1 unit above a floor, looking towards its far end.
fn floor_camera() -> Camera {
    Camera::new(
        Mat4::look_at(
            Vec3::new(0.0, 1.0, 3.0),
            Vec3::new(0.0, 0.5, -10.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .expect("a valid view"),
        Mat4::perspective(1.0, W as f32 / H as f32, 0.3, 80.0).expect("a valid projection"),
    )
}

static TRIANGLE: [[u16; 3]; 1] = [[0, 1, 2]];
static QUAD_TRIANGLES: [[u16; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

fn triangle_positions() -> [Vec3Fx; 3] {
    [p(-1.2, -0.9, 0.0), p(1.3, -0.7, -0.4), p(-0.1, 1.0, 0.3)]
}

/// The configuration every scene starts from.
pub fn config() -> Config<Rgb565> {
    Config::new(Size::new(W, H), BACKGROUND)
}

/// A scene's configuration (the floor and the glass are seen from both
/// sides).
pub fn scene_config(name: &str) -> Config<Rgb565> {
    match name {
        "textured_plane" => config().cull(CullMode::None),
        "textured_plane_quasi16" => config()
            .cull(CullMode::None)
            .perspective(Perspective::Quasi16),
        "textured_plane_affine" => config()
            .cull(CullMode::None)
            .perspective(Perspective::Affine),
        "transparent" => config().cull(CullMode::None),
        _ => config(),
    }
}

/// Renders `scene` with a 32x32-tile renderer into `sink`.
fn draw<F, S>(scene: &Scene<'_, F>, cfg: Config<Rgb565>, sink: &mut S) -> FrameStats
where
    F: ShaderSet<Rgb565>,
    S: TileSink<Rgb565>,
    S::Error: core::fmt::Debug,
{
    let mut r: Renderer<Rgb565, 32, 32> = Renderer::new(cfg);
    let mut ws: Box<Workspace<2048, 4096, 80>> = Box::default();
    r.render(&mut ws, scene, sink)
        .expect("a gallery scene renders")
}

impl Gallery {
    /// Generates the meshes and the texture.
    pub fn new() -> Self {
        Self {
            assets: DemoAssets::new(),
            coarse: CoarseKnot::new(),
            texels: checker_texels(32),
        }
    }

    fn texture(&self) -> Texture<'_> {
        Texture::new(32, 32, Texels::Rgb565(&self.texels)).expect("the checker texture is valid")
    }

    /// Renders scene `name` of [`SCENES`] with configuration `cfg` into
    /// `sink`; `None` for an unknown name.
    pub fn render<S>(&self, name: &str, cfg: Config<Rgb565>, sink: &mut S) -> Option<FrameStats>
    where
        S: TileSink<Rgb565>,
        S::Error: core::fmt::Debug,
    {
        let nearest = self.texture();
        let bilinear = nearest.filter(Filter::Bilinear);
        let knot = self.assets.knot();
        let coarse = self.coarse.mesh();
        let cube = cube();
        let tcube = textured_cube();
        let tri = triangle_positions();
        Some(match name {
            "unshaded_triangle" => {
                let mesh = Mesh::new(&tri, &TRIANGLE).ok()?;
                let d = [Draw::new(&mesh)
                    .color(Rgb888::new(240, 200, 60))
                    .shading(Shading::Flat)];
                draw(&Scene::new(front_camera(), &d), cfg, sink)
            }
            "gouraud_triangle" => {
                let colors = [Rgb888::RED, Rgb888::GREEN, Rgb888::BLUE];
                let mesh = Mesh::new(&tri, &TRIANGLE).ok()?.with_colors(&colors).ok()?;
                let d = [Draw::new(&mesh)];
                draw(&Scene::new(front_camera(), &d), cfg, sink)
            }
            "textured_triangle" | "textured_triangle_bilinear" => {
                let uvs = [uv(0.0, 2.0), uv(2.0, 2.0), uv(1.0, 0.0)];
                let mesh = Mesh::new(&tri, &TRIANGLE).ok()?.with_uvs(&uvs).ok()?;
                let tex = if name == "textured_triangle" {
                    &nearest
                } else {
                    &bilinear
                };
                let d = [Draw::new(&mesh).shading(Shading::Shader).texture(tex)];
                draw(&Scene::new(front_camera(), &d).shader(&Textured), cfg, sink)
            }
            // A floor from just in front of the camera to far away: its
            // squares shrink towards the horizon and stay straight only
            // with perspective-correct interpolation.
            "textured_plane" | "textured_plane_quasi16" | "textured_plane_affine" => {
                let pos = [
                    p(-6.0, 0.0, 1.0),
                    p(6.0, 0.0, 1.0),
                    p(6.0, 0.0, -60.0),
                    p(-6.0, 0.0, -60.0),
                ];
                let uvs = [uv(0.0, 0.0), uv(4.0, 0.0), uv(4.0, 40.0), uv(0.0, 40.0)];
                let mesh = Mesh::new(&pos, &QUAD_TRIANGLES).ok()?.with_uvs(&uvs).ok()?;
                let d = [Draw::new(&mesh).shading(Shading::Shader).texture(&nearest)];
                draw(&Scene::new(floor_camera(), &d).shader(&Textured), cfg, sink)
            }
            "depth_scene" => {
                let d = draws(&knot, &cube, 0.7, Shading::Shader);
                // Perspective depth (z / w) of this scene lies in the upper
                // part of the 16-bit range: stretch that to full contrast.
                let shade = DepthShade::new(56_000, 62_000);
                draw(&Scene::new(camera(W, H), &d).shader(&shade), cfg, sink)
            }
            "normals_scene" => {
                let d = draws(&knot, &cube, 0.7, Shading::Shader);
                draw(&Scene::new(camera(W, H), &d).shader(&Normals), cfg, sink)
            }
            "lit_textured_cube" => {
                let d = [Draw::new(&tcube)
                    .transform(
                        Mat4::rotation_y(0.6)
                            * Mat4::rotation_x(0.5)
                            * Mat4::scale(Vec3::new(0.8, 0.8, 0.8)),
                    )
                    .shading(Shading::Shader)
                    .texture(&bilinear)];
                let scene = Scene::new(front_camera(), &d)
                    .light(light())
                    .shader(&TexturedLit);
                draw(&scene, cfg, sink)
            }
            // A dim directional light, a warm and a cool point light, shiny
            // materials and linear fog.
            "lights_and_fog" => {
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
                let [k, c] = draws(&knot, &tcube, 0.7, Shading::Gouraud);
                let d = [
                    k.material(shiny),
                    c.material(shiny.shininess(12))
                        .shading(Shading::Shader)
                        .texture(&bilinear),
                ];
                let scene = Scene::new(camera(W, H), &d)
                    .lighting(&lighting)
                    .shader(&TexturedLit);
                draw(&scene, cfg, sink)
            }
            "wireframe_over_shaded" => {
                let [k, c] = draws(&coarse, &cube, 0.7, Shading::Gouraud);
                let d = [
                    k.edges(Edges::new(Rgb888::new(20, 20, 20))),
                    c.edges(Edges::new(Rgb888::WHITE)),
                ];
                draw(&Scene::new(camera(W, H), &d).light(light()), cfg, sink)
            }
            "wireframe" => {
                let [k, c] = draws(&coarse, &cube, 0.7, Shading::Wireframe);
                let d = [k, c.edges(Edges::new(Rgb888::WHITE))];
                draw(&Scene::new(camera(W, H), &d).light(light()), cfg, sink)
            }
            "points" => {
                let [k, c] = draws(&coarse, &cube, 0.7, Shading::Points(1));
                let d = [k, c.shading(Shading::Points(3))];
                draw(&Scene::new(camera(W, H), &d).light(light()), cfg, sink)
            }
            // A glass cube around the knot (both faces, back to front) and
            // the small cube glowing additively.
            "transparent" => {
                let [k, c] = draws(&knot, &cube, 0.7, Shading::Gouraud);
                let glass = Draw::new(&cube)
                    .transform(Mat4::translation(Vec3::new(-0.3, 0.0, 0.0)) * Mat4::rotation_y(0.4))
                    .color(Rgb888::new(120, 200, 255))
                    .blend(Blend::Alpha(96));
                let d = [k, c.blend(Blend::Additive), glass];
                draw(&Scene::new(camera(W, H), &d).light(light()), cfg, sink)
            }
            "knot_flat" => {
                let d = draws(&knot, &cube, 0.7, Shading::Flat);
                draw(&Scene::new(camera(W, H), &d).light(light()), cfg, sink)
            }
            _ => return None,
        })
    }
}

/// Columns of the contact sheet.
pub const SHEET_COLUMNS: u32 = 4;
/// Height of a caption strip under each scene.
pub const CAPTION: u32 = 14;

/// The size of the contact sheet of all [`SCENES`].
pub fn sheet_size() -> Size {
    let rows = (SCENES.len() as u32).div_ceil(SHEET_COLUMNS);
    Size::new(SHEET_COLUMNS * W, rows * (H + CAPTION))
}

/// Draws the contact sheet of every scene, each with its caption, into
/// `target` (of [`sheet_size`]).
pub fn draw_sheet<D>(gallery: &Gallery, target: &mut D)
where
    D: embedded_graphics::draw_target::DrawTarget<Color = Rgb565>,
    D::Error: core::fmt::Debug,
{
    use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
    use embedded_graphics::prelude::*;
    use embedded_graphics::text::Text;
    target.clear(Rgb565::BLACK).expect("the sheet clears");
    for (k, (name, caption)) in SCENES.iter().enumerate() {
        let (col, row) = (k as u32 % SHEET_COLUMNS, k as u32 / SHEET_COLUMNS);
        let origin = Point::new((col * W) as i32, (row * (H + CAPTION)) as i32);
        let mut cell = target.translated(origin);
        gallery
            .render(name, scene_config(name), &mut cell)
            .expect("every gallery scene exists");
        let style = MonoTextStyle::new(&FONT_6X10, Rgb565::new(28, 56, 28));
        Text::new(caption, origin + Point::new(3, H as i32 + 10), style)
            .draw(target)
            .expect("the caption draws");
    }
}
