//! Renders one benchmark scene N times into a `NullSink`, for instruction
//! counts under valgrind (see `scripts/count-instructions.sh`).
//!
//! ```text
//! cargo run --release --example count -- SCENE [N [RASTERIZER]]
//! ```
//!
//! `SCENE` is one of `demo` (the demo frame 0, Gouraud, depth-tested),
//! `demo-flat`, `fill` (8 flat, depth-tested 320x240 quads drawn back to
//! front), `tri4`, `tri32`, `tri100`, `tri1000`, `tri10000` (copies of one
//! triangle of about that many pixels), `euc` (the demo frame rendered by
//! the euc crate), or `fill-SHADER-MODE`: the fill scene through a
//! fragment shader, `SHADER` one of `flat`, `gouraud`, `nearest`,
//! `bilinear` (textured) and `lit` (textured and lit), `MODE` one of
//! `exact`, `quasi8`, `quasi16` and `affine` (the quads' clip-space `w`
//! is one constant, so every mode draws them through the affine loops),
//! or `fill-SHADER-MODE-facing`: the same through a camera whose `w`
//! depends on depth (each quad still of one `w`), as quads facing a
//! perspective camera, which take the mode's own loops; `terrain` (a terrain of
//! 18,432 triangles imported in clusters of 64, mostly outside the view)
//! and `terrain-whole` (the same terrain imported without clusters),
//! `rock` (a 3,920-triangle mesh of small, uneven triangles) and
//! `demo-textured-lit` (the demo frame through `TexturedLit`: the checker
//! texture, nearest, times the Lambert-lit vertex colour) and
//! `knot1k-textured-lit` (the same frame with a 1,024-triangle knot), in
//! exact perspective, or with `-MODE` (`demo-textured-lit-affine`) in
//! another.
//! `RASTERIZER` is `scanline` (default), `hilbert` or `auto`.
//! Every frame of a run is identical; each is rendered by the function
//! `count::frame`, so `valgrind --tool=callgrind
//! --toggle-collect='*count::frame*'` counts exactly N frames, all-in (scene
//! set-up, vertex stage, binning, rasterization, shading, tile clears).
//! The program prints the statistics of one frame.

mod common;

use common::scenes::*;
use microraster::prelude::*;

/// Fill-rate layers.
const FILL_LAYERS: usize = 8;

enum Job {
    Demo {
        scene: DemoScene,
        shading: Shading,
        ws: Box<DemoWorkspace>,
    },
    Fill {
        scene: FillScene,
        ws: Box<DemoWorkspace>,
    },
    Copies {
        scene: Copies,
        ws: Box<CopiesWorkspace>,
    },
    Euc(Box<EucDemo>),
    Shaded {
        scene: FillScene,
        ws: Box<DemoWorkspace>,
        shader: FillShader,
        /// Through `facing_camera` (the `-facing` scenes).
        facing: bool,
    },
    Terrain {
        scene: Box<TerrainScene>,
        ws: Box<TerrainWorkspace>,
        clustered: bool,
    },
    Rock {
        scene: RockScene,
        ws: Box<RockWorkspace>,
    },
    TexturedDemo {
        scene: TexturedDemoScene,
        ws: Box<DemoWorkspace>,
    },
}

/// The fragment shaders of the `fill-*` scenes.
#[derive(Clone, Copy)]
enum FillShader {
    Flat,
    Gouraud,
    Nearest,
    Bilinear,
    Lit,
}

/// One frame, all-in. Not inlined, so callgrind can collect exactly it.
#[inline(never)]
fn frame(job: &mut Job, r: &mut BenchRenderer) -> Option<FrameStats> {
    let sink = &mut NullSink;
    match job {
        Job::Demo { scene, shading, ws } => Some(scene.render(r, ws, *shading, sink)),
        Job::Fill { scene, ws } => Some(scene.render(r, ws, sink)),
        Job::Copies { scene, ws } => Some(scene.render(r, ws, sink)),
        Job::Terrain {
            scene,
            ws,
            clustered,
        } => Some(scene.render(r, ws, *clustered, sink)),
        Job::Rock { scene, ws } => Some(scene.render(r, ws, sink)),
        Job::TexturedDemo { scene, ws } => Some(scene.render(r, ws, sink)),
        Job::Euc(e) => {
            e.render();
            None
        }
        Job::Shaded {
            scene,
            ws,
            shader,
            facing,
        } => {
            let f = *facing;
            use microraster::shader::{Flat, Gouraud, Textured, TexturedLit};
            let nearest = scene.texture;
            let bilinear = nearest.filter(microraster::texture::Filter::Bilinear);
            Some(match shader {
                FillShader::Flat => scene.render_shader(r, ws, &Flat, &nearest, f, sink),
                FillShader::Gouraud => scene.render_shader(r, ws, &Gouraud, &nearest, f, sink),
                FillShader::Nearest => scene.render_shader(r, ws, &Textured, &nearest, f, sink),
                FillShader::Bilinear => scene.render_shader(r, ws, &Textured, &bilinear, f, sink),
                FillShader::Lit => scene.render_shader(r, ws, &TexturedLit, &nearest, f, sink),
            })
        }
    }
}

/// The job and perspective mode of a `fill-SHADER-MODE` or
/// `fill-SHADER-MODE-facing` scene name.
fn shaded(name: &str) -> Option<(Job, Perspective)> {
    let rest = name.strip_prefix("fill-")?;
    let (rest, facing) = match rest.strip_suffix("-facing") {
        Some(rest) => (rest, true),
        None => (rest, false),
    };
    let (shader, mode) = rest.split_once('-')?;
    let shader = match shader {
        "flat" => FillShader::Flat,
        "gouraud" => FillShader::Gouraud,
        "nearest" => FillShader::Nearest,
        "bilinear" => FillShader::Bilinear,
        "lit" => FillShader::Lit,
        _ => return None,
    };
    let mode = perspective_mode(mode)?;
    Some((
        Job::Shaded {
            scene: FillScene::new(FILL_LAYERS),
            ws: Box::default(),
            shader,
            facing,
        },
        mode,
    ))
}

/// The job and perspective mode of a `demo-textured-lit[-MODE]` or
/// `knot1k-textured-lit[-MODE]` scene name (`MODE` as in
/// `fill-SHADER-MODE`, exact without one).
fn textured(name: &str) -> Option<(Job, Perspective)> {
    let (scene, mode) = match name.split_once("-lit") {
        Some((scene, "")) => (scene, Perspective::Exact),
        Some((scene, mode)) => (scene, perspective_mode(mode.strip_prefix('-')?)?),
        None => return None,
    };
    let scene = match scene {
        "demo-textured" => TexturedDemoScene::new(),
        "knot1k-textured" => TexturedDemoScene::with_knot(64, 8),
        _ => return None,
    };
    Some((
        Job::TexturedDemo {
            scene,
            ws: Box::default(),
        },
        mode,
    ))
}

/// A perspective mode by name: `exact`, `quasi8`, `quasi16` or `affine`.
fn perspective_mode(name: &str) -> Option<Perspective> {
    Some(match name {
        "exact" => Perspective::Exact,
        "quasi8" => Perspective::Quasi8,
        "quasi16" => Perspective::Quasi16,
        "affine" => Perspective::Affine,
        _ => return None,
    })
}

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "demo".into());
    let n: usize = match args.next().map(|a| a.parse()) {
        None => 1,
        Some(Ok(n)) if n > 0 => n,
        _ => {
            eprintln!("count: N must be a positive number");
            std::process::exit(2);
        }
    };
    let raster = match args.next() {
        None => Rasterizer::Scanline,
        Some(a) => parse_rasterizer(&a).unwrap_or_else(|| {
            eprintln!("count: RASTERIZER is scanline, hilbert or auto, not {a:?}");
            std::process::exit(2);
        }),
    };
    let copies = |size: &str| {
        let (_, area, count) = TRIANGLE_SIZES
            .iter()
            .find(|t| t.0 == size)
            .copied()
            .expect("known size");
        Job::Copies {
            scene: Copies::new(area, count),
            ws: Box::default(),
        }
    };
    let mut perspective = Perspective::Exact;
    let mut job = match name.as_str() {
        "demo" | "demo-flat" => Job::Demo {
            scene: DemoScene::new(),
            shading: if name == "demo" {
                Shading::Gouraud
            } else {
                Shading::Flat
            },
            ws: Box::default(),
        },
        "fill" => Job::Fill {
            scene: FillScene::new(FILL_LAYERS),
            ws: Box::default(),
        },
        "tri4" => copies("4px"),
        "tri32" => copies("32px"),
        "tri100" => copies("100px"),
        "tri1000" => copies("1000px"),
        "tri10000" => copies("10000px"),
        "euc" => Job::Euc(Box::default()),
        "terrain" | "terrain-whole" => Job::Terrain {
            scene: Box::new(TerrainScene::new()),
            ws: Box::default(),
            clustered: name == "terrain",
        },
        "rock" => Job::Rock {
            scene: RockScene::new(),
            ws: Box::default(),
        },
        other if textured(other).is_some() => {
            let (job, mode) = textured(other).expect("just checked");
            perspective = mode;
            job
        }
        other if shaded(other).is_some() => {
            let (job, mode) = shaded(other).expect("just checked");
            perspective = mode;
            job
        }
        other => {
            eprintln!(
                "count: unknown scene {other:?} \
                 (demo, demo-flat, fill, tri4, tri32, tri100, tri1000, tri10000, euc, \
                 fill-SHADER-MODE[-facing], terrain, terrain-whole, rock, demo-textured-lit[-MODE], knot1k-textured-lit[-MODE])"
            );
            std::process::exit(2);
        }
    };
    let mut r = BenchRenderer::new(renderer_with(raster).config().perspective(perspective));
    let mut first = None;
    for _ in 0..n {
        let s = frame(&mut job, &mut r);
        match first {
            None => first = Some(s),
            Some(f) => assert_eq!(f, s, "every frame must be identical"),
        }
    }
    match first.flatten() {
        Some(s) => println!("scene={name} frames={n} rasterizer={raster:?} {s}"),
        None => {
            let Job::Euc(e) = &job else { unreachable!() };
            println!("scene={name} frames={n} pixels_covered={}", e.covered());
        }
    }
}
