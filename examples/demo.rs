//! The host demo: a lit, rotating torus knot and cube, rendered tile by tile
//! into the embedded-graphics simulator; or any OBJ model, rendered once
//! into a PNG.
//!
//! Headless by default: writes PNG frames to the repository's
//! `target/demo/` and prints the statistics of every frame. With
//! `--features window` it opens the live simulator window instead (needs
//! SDL2). `--help` lists the options (`examples/common/demo_args.rs`):
//!
//! ```text
//! cargo run --release --example demo [-- --frames N --out-dir DIR]
//!     [--size WxH] [--shader flat|gouraud|textured|textured-lit|depth|normals|wireframe|points]
//!     [--perspective exact|quasi8|quasi16|affine]
//!     [--hilbert | --raster scanline|hilbert|auto] [--hilbert-tiles]
//!
//! cargo run --release --example demo -- --obj MODEL.obj [--out MODEL.png]
//!     [--size WxH] [--yaw DEG] [--shader ...] [--texture IMAGE.png]
//! ```
//!
//! The animation's frames go into a directory (`--out-dir`), a model's
//! picture into a file (`--out`, default `target/demo/MODEL.png`); a flag
//! that does not apply is refused. `--hilbert` (or `--raster hilbert`)
//! renders with the Hilbert-order rasterizer, `--hilbert-tiles` visits the
//! tiles along the Hilbert curve; both give the same images as the
//! defaults. `--flat` is `--shader flat`. The textured shaders use a
//! procedural checker texture unless `--texture` names a PNG.
//!
//! With `--obj`, the model is recentred and scaled by the importer, framed
//! from its bounding sphere, turned by `--yaw` degrees about the vertical
//! and lit; the importer's warnings are shown. A bad file gives a one-line
//! error and exit status 1; a bad argument, one naming the flag and exit
//! status 2.

mod common;

use common::demo_args::{self, Args, Look, Mode, Parsed};
use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use fixed::types::I16F16;
use microraster::light::{DirectionalLight, Lighting, Material, PointLight};
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::shader::{DepthShade, Normals, Textured, TexturedLit};
use microraster::texture::{Filter, Texels, Texture};
use std::path::Path;

/// The configuration of the RAM budget: 32x32 tiles, room for the whole
/// demo scene and every tile of a 320x240 frame in one binning pass.
type DemoRenderer = Renderer<Rgb565, 32, 32>;
type DemoWorkspace = Workspace<2048, 4096, 80>;
/// For `--obj`: room for 262,144 vertices (4 MiB, boxed); triangles beyond
/// the bin pool are drawn in more binning passes. A frame holds at most
/// 65,536 triangles (`render::MAX_TRIANGLES`): a larger model is a
/// one-line error.
type ModelWorkspace = Workspace<262_144, 65_535, 4096>;

fn fail(message: impl std::fmt::Display) -> ! {
    eprintln!("demo: {message}");
    std::process::exit(1);
}

fn main() {
    let args = match demo_args::parse(std::env::args().skip(1)) {
        Ok(Parsed::Run(a)) => a,
        Ok(Parsed::Help) => {
            print!("{}", demo_args::USAGE);
            return;
        }
        Err(e) => {
            eprintln!("demo: {e}");
            std::process::exit(2);
        }
    };
    // The texture of the textured shaders: a PNG, or the procedural
    // checker.
    let (tex_size, texels) = match &args.texture {
        Some(path) => {
            let image = microraster_import::load_png(path)
                .unwrap_or_else(|e| fail(format!("--texture: {e}")));
            let data = image
                .convert(microraster_import::TextureFormat::Rgb565)
                .unwrap_or_else(|e| fail(format!("--texture: {e}")));
            let microraster_import::Texels::U16(t) = data.texels else {
                fail("the importer gave no Rgb565 texels")
            };
            ((data.width, data.height), t)
        }
        None => ((32, 32), checker_texels(32)),
    };
    let texture = Texture::new(tex_size.0, tex_size.1, Texels::Rgb565(&texels))
        .unwrap_or_else(|e| fail(format!("--texture: {e}")))
        .filter(Filter::Bilinear);
    match &args.mode {
        // The model's workspace is megabytes: built on a thread whose
        // stack holds it on its way into the box.
        Mode::Model { obj, out, yaw } => std::thread::scope(|s| {
            let job = std::thread::Builder::new()
                .stack_size(64 << 20)
                .spawn_scoped(s, || render_model(&args, obj, out, *yaw, &texture))
                .unwrap_or_else(|e| fail(format!("cannot start the renderer thread: {e}")));
            if job.join().is_err() {
                std::process::exit(1);
            }
        }),
        Mode::Animation { frames, out_dir } => demo(&args, *frames, out_dir, &texture),
    }
}

/// The scene's fragment shader for `look`, and the scene rendered with it
/// by `f`.
fn with_shader<R>(look: Look, f: impl ShaderUser<R>) -> R {
    match look {
        Look::TexturedLit => f.call(&TexturedLit),
        Look::Depth => f.call(&DepthShade::new(56_000, 64_000)),
        Look::Normals => f.call(&Normals),
        _ => f.call(&Textured),
    }
}

/// Something generic over the scene's shader type (a closure cannot be).
trait ShaderUser<R> {
    fn call<S: FragmentShader<Rgb565>>(self, shader: &S) -> R;
}

/// The rotating knot and cube.
fn demo(args: &Args, frames: usize, out_dir: &Path, texture: &Texture<'_>) {
    let assets = DemoAssets::new();
    let knot_uvs = knot_uvs(KNOT_UV_REPEATS.0, KNOT_UV_REPEATS.1);
    let knot = assets.knot();
    let knot = if args.look.textured() {
        knot.with_uvs(&knot_uvs).expect("one coordinate per vertex")
    } else {
        knot
    };
    let cube = textured_cube();
    let size = args.size;
    let mut renderer = DemoRenderer::new(
        Config::new(size, DEMO_CLEAR)
            .rasterizer(args.raster)
            .tile_order(args.tile_order)
            .perspective(args.perspective),
    );
    let mut workspace = Box::new(DemoWorkspace::new());
    println!(
        "renderer RAM: tile buffer + settings {} B, workspace {} B; {:?} rasterizer, {:?} tiles, {:?}",
        core::mem::size_of::<DemoRenderer>(),
        core::mem::size_of::<DemoWorkspace>(),
        args.raster,
        args.tile_order,
        args.look,
    );
    struct Frames<'a> {
        args: &'a Args,
        frames: usize,
        out_dir: &'a Path,
        knot: &'a Mesh<'a>,
        cube: &'a Mesh<'a>,
        texture: &'a Texture<'a>,
        renderer: &'a mut DemoRenderer,
        workspace: &'a mut DemoWorkspace,
    }
    impl ShaderUser<()> for Frames<'_> {
        fn call<S: FragmentShader<Rgb565>>(self, shader: &S) {
            let look = self.args.look;
            let size = self.args.size;
            // Textured and lit: white surfaces (the texture gives the
            // colour), shiny, under a sun and a warm lamp.
            let sun = [DirectionalLight::new(
                Vec3::new(-0.6, 0.8, 0.9),
                Rgb888::new(200, 200, 210),
            )];
            let lamp = [PointLight::new(
                Vec3::new(1.0, 1.4, 2.2),
                Rgb888::new(255, 190, 120),
                4.5,
            )];
            let lighting = Lighting::new(Rgb888::new(40, 40, 56))
                .directional(&sun)
                .point(&lamp);
            let shiny = Material::new()
                .specular(Rgb888::new(200, 200, 200))
                .shininess(24);
            let scene_at = |t: f32| {
                draws(self.knot, self.cube, t, look.shading()).map(|d| {
                    let d = d.texture(self.texture);
                    if look == Look::TexturedLit {
                        d.color(Rgb888::new(255, 255, 255)).material(shiny)
                    } else {
                        d
                    }
                })
            };
            let lit = (look == Look::TexturedLit).then_some(&lighting);
            #[cfg(feature = "window")]
            {
                use embedded_graphics_simulator::{
                    OutputSettingsBuilder, SimulatorDisplay, SimulatorEvent, Window,
                };
                // The window shows frames until it is closed: no count,
                // no files (as --help says).
                let _ = (self.frames, self.out_dir);
                let mut display = SimulatorDisplay::<Rgb565>::new(self.args.size);
                let mut window = Window::new(
                    "microraster demo",
                    &OutputSettingsBuilder::new().scale(2).build(),
                );
                let mut t = 0.0f32;
                loop {
                    let d = scene_at(t);
                    let scene = light_up(
                        Scene::new(camera(size.width, size.height), &d).shader(shader),
                        lit,
                    );
                    self.renderer
                        .render(self.workspace, &scene, &mut display)
                        .expect("demo scene renders");
                    window.update(&display);
                    if window.events().any(|e| e == SimulatorEvent::Quit) {
                        break;
                    }
                    t += 0.03;
                }
            }
            #[cfg(not(feature = "window"))]
            {
                let (out, frames) = (self.out_dir, self.frames);
                if let Err(e) = std::fs::create_dir_all(out) {
                    fail(format!("--out-dir: cannot create {}: {e}", out.display()));
                }
                println!("frame  tris_in culled rejected clipped drawn  pixels tiles passes");
                for f in 0..frames {
                    let t = f as f32 * core::f32::consts::TAU / frames.max(1) as f32 / 3.0;
                    let d = scene_at(t);
                    let scene = light_up(
                        Scene::new(camera(size.width, size.height), &d).shader(shader),
                        lit,
                    );
                    let path = out.join(format!("frame_{f:03}.png"));
                    let s = render_png(self.renderer, self.workspace, &scene, &path)
                        .unwrap_or_else(|e| fail(e));
                    println!(
                        "{f:5} {:8} {:6} {:8} {:7} {:5} {:7} {:5} {:6}",
                        s.triangles_in,
                        s.culled,
                        s.rejected,
                        s.clipped,
                        s.drawn,
                        s.pixels_shaded,
                        s.tiles,
                        s.bin_passes
                    );
                }
                println!("wrote {frames} frames to {}", out.display());
            }
        }
    }
    with_shader(
        args.look,
        Frames {
            args,
            frames,
            out_dir,
            knot: &knot,
            cube: &cube,
            texture,
            renderer: &mut renderer,
            workspace: &mut workspace,
        },
    );
}

/// Lights `scene` with `lighting`, or else with the demo's one light.
fn light_up<'a, S>(scene: Scene<'a, S>, lighting: Option<&'a Lighting<'a>>) -> Scene<'a, S> {
    match lighting {
        Some(l) => scene.lighting(l),
        None => scene.light(light()),
    }
}

/// One model's mesh data in 16.16, split into pieces of at most 65,536
/// vertices (the reach of `u16` indices).
struct ModelPieces {
    pieces: Vec<Piece>,
}

struct Piece {
    /// The group's diffuse colour (`Kd`), if its material has one.
    color: Option<Rgb888>,
    positions: Vec<Vec3Fx>,
    normals: Vec<Vec3Fx>,
    uvs: Vec<[I16F16; 2]>,
    colors: Vec<Rgb888>,
    triangles: Vec<[u16; 3]>,
}

impl ModelPieces {
    fn new(m: &microraster_import::Model) -> Result<Self, String> {
        let fx = |v: f32| -> Result<I16F16, String> {
            I16F16::checked_from_num(v).ok_or(format!("coordinate {v} is outside 16.16"))
        };
        let mut pieces: Vec<Piece> = Vec::new();
        let mut map: std::collections::HashMap<u32, u16> = std::collections::HashMap::new();
        // Groups in order; each starts a piece (its own draw and colour).
        let mut starts = m.groups.iter().peekable();
        let mut color = None;
        for (ti, t) in m.triangles.iter().enumerate() {
            let mut new_group = false;
            while let Some(g) = starts.next_if(|g| g.triangles.start <= ti) {
                new_group = true;
                color = g.material.as_ref().map(|mat| {
                    let c = mat
                        .diffuse
                        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
                    Rgb888::new(c[0], c[1], c[2])
                });
            }
            let fits = !new_group
                && pieces.last().is_some_and(|p| {
                    let new = t.iter().filter(|i| !map.contains_key(i)).count();
                    p.positions.len() + new <= 1 << 16
                });
            if !fits {
                map.clear();
                pieces.push(Piece {
                    color,
                    positions: Vec::new(),
                    normals: Vec::new(),
                    uvs: Vec::new(),
                    colors: Vec::new(),
                    triangles: Vec::new(),
                });
            }
            let piece = pieces.last_mut().expect("a piece was just pushed");
            let mut tri = [0u16; 3];
            for (k, &i) in t.iter().enumerate() {
                let v = i as usize;
                tri[k] = match map.get(&i) {
                    Some(&j) => j,
                    None => {
                        let j = piece.positions.len() as u16;
                        let p = m.positions[v];
                        piece.positions.push([fx(p[0])?, fx(p[1])?, fx(p[2])?]);
                        if let Some(n) = m.normals.get(v) {
                            piece.normals.push([fx(n[0])?, fx(n[1])?, fx(n[2])?]);
                        }
                        if let Some(uv) = m.uvs.get(v) {
                            // OBJ puts v = 0 at the bottom of the image,
                            // textures here at the top.
                            piece.uvs.push([fx(uv[0])?, fx(1.0 - uv[1])?]);
                        }
                        if let Some(c) = m.colors.get(v) {
                            piece.colors.push(Rgb888::new(c[0], c[1], c[2]));
                        }
                        map.insert(i, j);
                        j
                    }
                };
            }
            piece.triangles.push(tri);
        }
        Ok(Self { pieces })
    }

    fn meshes(&self) -> Result<Vec<(Mesh<'_>, Option<Rgb888>)>, String> {
        self.pieces
            .iter()
            .map(|p| {
                let mut mesh = Mesh::new(&p.positions, &p.triangles).map_err(|e| e.to_string())?;
                if !p.normals.is_empty() {
                    mesh = mesh.with_normals(&p.normals).map_err(|e| e.to_string())?;
                }
                if !p.uvs.is_empty() {
                    mesh = mesh.with_uvs(&p.uvs).map_err(|e| e.to_string())?;
                }
                if !p.colors.is_empty() {
                    mesh = mesh.with_colors(&p.colors).map_err(|e| e.to_string())?;
                }
                Ok((mesh, p.color))
            })
            .collect()
    }
}

/// `--obj`: one frame of the model into a PNG.
fn render_model(args: &Args, path: &Path, out: &Path, yaw: f32, texture: &Texture<'_>) {
    let options = microraster_import::ObjOptions::new().with_fit(microraster_import::Fit::Unit);
    let model = microraster_import::load_obj(path, &options)
        .unwrap_or_else(|e| fail(format!("--obj: {e}")));
    // What the importer skipped or guessed (unsupported statements,
    // missing materials) shows in the picture: say so.
    for warning in &model.warnings {
        eprintln!("demo: --obj: warning: {warning}");
    }
    if model.triangles.is_empty() {
        fail(format!("{}: no triangles", path.display()));
    }
    let pieces =
        ModelPieces::new(&model).unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
    let meshes = pieces
        .meshes()
        .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
    if args.look.textured() && meshes.iter().any(|(m, _)| m.uvs().is_none()) {
        fail(format!(
            "{}: --shader {:?} needs texture coordinates (vt) and the model has none",
            path.display(),
            args.look
        ));
    }
    let yaw = Mat4::rotation_y(yaw.to_radians());
    let draws: Vec<Draw<'_>> = meshes
        .iter()
        .map(|(m, color)| {
            let d = Draw::new(m)
                .transform(yaw)
                .color(color.unwrap_or(Rgb888::new(210, 200, 190)))
                .shading(args.look.shading())
                .texture(texture);
            if args.look == Look::Wireframe {
                d.edges(Edges::new(Rgb888::new(230, 230, 230)).depth_bias(0))
            } else {
                d
            }
        })
        .collect();
    // Framing: the bounding sphere, seen slightly from above, fills the
    // smaller field of view with a margin.
    let s = &model.sphere;
    let (c, r) = (
        Vec3::new(s.center[0] as f32, s.center[1] as f32, s.center[2] as f32),
        (s.radius as f32).max(1e-3),
    );
    let size = args.size;
    let aspect = size.width as f32 / size.height as f32;
    let fovy = 0.8f32;
    let half = 0.5 * fovy.min(2.0 * ((0.5 * fovy).tan() * aspect).atan());
    let dist = 1.15 * r / half.sin();
    let dir = Vec3::new(0.0, 0.35, 1.0)
        .normalize()
        .expect("a unit vector");
    let eye = Vec3::new(c.x + dir.x * dist, c.y + dir.y * dist, c.z + dir.z * dist);
    let camera = Camera::new(
        Mat4::look_at(eye, c, Vec3::new(0.0, 1.0, 0.0))
            .unwrap_or_else(|| fail("cannot aim the camera")),
        Mat4::perspective(
            fovy,
            aspect,
            (dist - 1.5 * r).max(dist * 0.01),
            dist + 1.5 * r,
        )
        .unwrap_or_else(|| fail("cannot frame the model")),
    );
    let light = Light::new(Vec3::new(-0.5, 0.8, 0.7)).ambient(Rgb888::new(50, 50, 60));
    let mut renderer = DemoRenderer::new(
        Config::new(size, DEMO_CLEAR)
            .rasterizer(args.raster)
            .tile_order(args.tile_order)
            .perspective(args.perspective),
    );
    let mut workspace: Box<ModelWorkspace> = Box::default();
    struct One<'a> {
        draws: &'a [Draw<'a>],
        camera: Camera,
        light: Light,
        renderer: &'a mut DemoRenderer,
        workspace: &'a mut ModelWorkspace,
        out: &'a Path,
    }
    impl ShaderUser<FrameStats> for One<'_> {
        fn call<S: FragmentShader<Rgb565>>(self, shader: &S) -> FrameStats {
            let scene = Scene::new(self.camera, self.draws)
                .light(self.light)
                .shader(shader);
            render_png(self.renderer, self.workspace, &scene, self.out).unwrap_or_else(|e| fail(e))
        }
    }
    let stats = with_shader(
        args.look,
        One {
            draws: &draws,
            camera,
            light,
            renderer: &mut renderer,
            workspace: &mut workspace,
            out,
        },
    );
    println!(
        "{}: {} triangles in {} draw(s), scale {:.4}; {} drawn, {} pixels; wrote {}",
        path.display(),
        stats.triangles_in,
        draws.len(),
        model.scale,
        stats.drawn,
        stats.pixels_shaded,
        out.display()
    );
}
