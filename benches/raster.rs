//! Criterion benchmarks of the whole renderer, all through the public API
//! (`Renderer::render` into a sink). See BENCHMARKS.md for the figures.
//!
//! ```text
//! cargo bench --bench raster                 # everything, a couple of minutes
//! cargo bench --bench raster -- demo_320x240 # one group
//! ```
//!
//! * `triangles/{scanline,hilbert,auto}/{4px,32px,100px,1000px,10000px}`:
//!   a frame of many copies of one Gouraud-shaded triangle of about that
//!   many pixels, scattered over a 320x240 frame, into `NullSink`, with
//!   each rasterizer; the throughput is in triangles.
//! * `fill/flat_depth_8_layers`: 8 flat-shaded, depth-tested 320x240 quads
//!   drawn back to front (every fragment passes and is written), into
//!   `NullSink`; the throughput is in shaded pixels.
//! * `fill_shader/{flat,gouraud,textured_nearest,textured_bilinear,textured_lit}/{exact,quasi8,quasi16,affine}[_facing]`:
//!   the same 8 layers through each built-in fragment shader (32x32
//!   Rgb565 checker texture, repeated 4 x 3 times per quad) in each
//!   perspective mode; their clip-space `w` is one constant, so every
//!   mode draws them affinely, but with `_facing` (a camera whose `w`
//!   depends on depth, each quad still of one `w`: quads facing a
//!   perspective camera), where the mode's own loops draw them.
//! * `demo_320x240/*`: frame 0 of the demo (4,000-triangle lit torus knot
//!   plus a cube), Gouraud, depth-tested, `Renderer<Rgb565, 32, 32>` and
//!   `Workspace<2048, 4096, 80>`, into `NullSink` or into a full frame
//!   buffer (`_hilbert` and `_auto`: with those rasterizers); and the same
//!   frame rendered by the euc crate.
//! * `terrain/{clusters,whole}`: a 96x96-quad terrain (18,432 triangles)
//!   seen from on it, imported in clusters of at most 64 triangles (culled
//!   cluster by cluster) or without clusters, into `NullSink`.
//! * `rock/gouraud`: a 3,920-triangle displaced geodesic sphere, the
//!   small triangles of a scanned or modelled mesh (Gouraud, 320x240).

#[path = "../examples/common/mod.rs"]
mod common;

use common::scenes::*;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use microraster::prelude::*;
use std::hint::black_box;
use std::time::Duration;

/// Layers of the fill-rate scene.
const FILL_LAYERS: usize = 8;

/// The rasterizers compared, with their names in benchmark ids.
const RASTERIZERS: [(&str, Rasterizer); 3] = [
    ("scanline", Rasterizer::Scanline),
    ("hilbert", Rasterizer::Hilbert),
    ("auto", Rasterizer::Auto),
];

fn triangles(c: &mut Criterion) {
    let mut g = c.benchmark_group("triangles");
    let mut ws: Box<CopiesWorkspace> = Box::default();
    for (name, area, count) in TRIANGLE_SIZES {
        let scene = Copies::new(area, count);
        for (raster_name, raster) in RASTERIZERS {
            let mut r = renderer_with(raster);
            let stats = scene.render(&mut r, &mut ws, &mut NullSink);
            assert_eq!(stats.drawn as usize, count);
            println!(
                "triangles/{raster_name}/{name}: {count} triangles, {:.1} pixels each, {} tile visits",
                stats.pixels_shaded as f64 / count as f64,
                stats.tiles
            );
            g.throughput(Throughput::Elements(count as u64));
            g.bench_function(BenchmarkId::new(raster_name, name), |b| {
                b.iter(|| black_box(scene.render(&mut r, &mut ws, &mut NullSink)))
            });
        }
    }
    g.finish();
}

fn fill(c: &mut Criterion) {
    let mut g = c.benchmark_group("fill");
    let mut r = renderer();
    let mut ws: Box<DemoWorkspace> = Box::default();
    let scene = FillScene::new(FILL_LAYERS);
    let stats = scene.render(&mut r, &mut ws, &mut NullSink);
    assert_eq!(stats.pixels_shaded, FILL_LAYERS as u32 * WIDTH * HEIGHT);
    g.throughput(Throughput::Elements(stats.pixels_shaded as u64));
    g.bench_function("flat_depth_8_layers", |b| {
        b.iter(|| black_box(scene.render(&mut r, &mut ws, &mut NullSink)))
    });
    g.finish();
}

/// Fill rate of every built-in fragment shader in every perspective mode:
/// the fill scene's 8 layers through `Shading::Shader`.
fn fill_shaders(c: &mut Criterion) {
    use microraster::shader::{Flat, Gouraud, Textured, TexturedLit};
    use microraster::texture::Filter;
    let mut g = c.benchmark_group("fill_shader");
    let mut ws: Box<DemoWorkspace> = Box::default();
    let scene = FillScene::new(FILL_LAYERS);
    let nearest = scene.texture;
    let bilinear = nearest.filter(Filter::Bilinear);
    for ((mode_name, mode), facing) in PERSPECTIVE_MODES
        .into_iter()
        .flat_map(|m| [(m, false), (m, true)])
    {
        let mut r = BenchRenderer::new(renderer().config().perspective(mode));
        let id = if facing {
            format!("{mode_name}_facing")
        } else {
            mode_name.to_string()
        };
        macro_rules! bench {
            ($name:literal, $shader:expr, $tex:expr) => {{
                let stats =
                    scene.render_shader(&mut r, &mut ws, &$shader, $tex, facing, &mut NullSink);
                assert_eq!(stats.pixels_shaded, FILL_LAYERS as u32 * WIDTH * HEIGHT);
                g.throughput(Throughput::Elements(stats.pixels_shaded as u64));
                g.bench_function(BenchmarkId::new($name, &id), |b| {
                    b.iter(|| {
                        black_box(scene.render_shader(
                            &mut r,
                            &mut ws,
                            &$shader,
                            $tex,
                            facing,
                            &mut NullSink,
                        ))
                    })
                });
            }};
        }
        bench!("flat", Flat, &nearest);
        bench!("gouraud", Gouraud, &nearest);
        bench!("textured_nearest", Textured, &nearest);
        bench!("textured_bilinear", Textured, &bilinear);
        bench!("textured_lit", TexturedLit, &nearest);
    }
    g.finish();
}

/// The perspective modes, with their names in benchmark ids.
const PERSPECTIVE_MODES: [(&str, Perspective); 4] = [
    ("exact", Perspective::Exact),
    ("quasi8", Perspective::Quasi8),
    ("quasi16", Perspective::Quasi16),
    ("affine", Perspective::Affine),
];

fn demo(c: &mut Criterion) {
    let mut g = c.benchmark_group("demo_320x240");
    let scene = DemoScene::new();
    let mut r = renderer();
    let mut ws: Box<DemoWorkspace> = Box::default();
    g.bench_function("microraster_gouraud_nullsink", |b| {
        b.iter(|| black_box(scene.render(&mut r, &mut ws, Shading::Gouraud, &mut NullSink)))
    });
    for (raster_name, raster) in &RASTERIZERS[1..] {
        let mut r = renderer_with(*raster);
        g.bench_function(format!("microraster_gouraud_nullsink_{raster_name}"), |b| {
            b.iter(|| black_box(scene.render(&mut r, &mut ws, Shading::Gouraud, &mut NullSink)))
        });
    }
    // A sink that keeps the whole frame, like a display's frame buffer:
    // the library's, over a 320x240 Rgb565 array.
    let mut pixels = vec![Rgb565::BLACK; (WIDTH * HEIGHT) as usize];
    let mut fb = FrameBuffer::new(&mut pixels, Size::new(WIDTH, HEIGHT)).expect("sized to match");
    g.bench_function("microraster_gouraud_framebuffer", |b| {
        b.iter(|| black_box(scene.render(&mut r, &mut ws, Shading::Gouraud, &mut fb)))
    });
    g.bench_function("microraster_flat_nullsink", |b| {
        b.iter(|| black_box(scene.render(&mut r, &mut ws, Shading::Flat, &mut NullSink)))
    });
    let mut euc: Box<EucDemo> = Box::default();
    g.bench_function("euc_gouraud_framebuffer", |b| {
        b.iter(|| {
            euc.render();
            black_box(&euc.color);
        })
    });
    g.finish();
}

/// The small-triangle mesh: a 3,920-triangle rock, Gouraud.
fn rock(c: &mut Criterion) {
    let mut g = c.benchmark_group("rock");
    let scene = RockScene::new();
    let mut r = renderer();
    let mut ws: Box<RockWorkspace> = Box::default();
    g.bench_function("gouraud", |b| {
        b.iter(|| scene.render(&mut r, &mut ws, &mut NullSink))
    });
    g.finish();
}

/// Per-cluster culling: the terrain with and without its clusters.
fn terrain(c: &mut Criterion) {
    let mut g = c.benchmark_group("terrain");
    let mut r = renderer();
    let mut ws: Box<TerrainWorkspace> = Box::default();
    let scene = TerrainScene::new();
    for (name, clustered) in [("clusters", true), ("whole", false)] {
        g.bench_function(name, |b| {
            b.iter(|| black_box(scene.render(&mut r, &mut ws, clustered, &mut NullSink)))
        });
    }
    g.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
}

criterion_group! {
    name = benches;
    config = config();
    targets = triangles, fill, fill_shaders, demo, terrain, rock
}
criterion_main!(benches);
