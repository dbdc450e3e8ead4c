//! Features: a renderer that links fewer paths draws what it supports
//! exactly as the full one does, and refuses, with a typed error, a scene
//! that needs a path it left out.

#[path = "../examples/common/mod.rs"]
mod common;
mod support;

use common::*;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::prelude::*;
use microraster::render::{All, Features, GouraudTriangles, Path, Triangles};
use microraster::shader::Gouraud;
use support::Capture;

const SIZE: Size = Size::new(160, 120);

/// Triangles plus lines and culling, as a firmware might choose.
struct Lines;
impl Features for Lines {
    const HILBERT: bool = false;
    const SHADERS: bool = false;
    const BLEND: bool = false;
    const SORT: bool = false;
}

/// [`Triangles`] without Gouraud: a firmware that draws flat triangles
/// only (the library's [`GouraudTriangles`] is the other half).
type FlatTriangles = Triangles<true, false>;

fn render<P: Features, F: ShaderSet<Rgb565>>(
    scene: &Scene<'_, F>,
    config: Config<Rgb565>,
) -> Result<(Vec<Rgb565>, FrameStats), RenderError<core::convert::Infallible>> {
    let mut r: Renderer<Rgb565, 32, 32, P> = Renderer::new(config);
    let mut ws: Box<Workspace<2048, 8192, 64>> = Box::new(Workspace::new());
    let mut cap = Capture::new(SIZE, Rgb565::new(31, 0, 31));
    let stats = r.render(&mut ws, scene, &mut cap)?;
    Ok((cap.pixels, stats))
}

#[test]
fn fewer_paths_draw_the_same_triangles() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let d = draws(&knot, &cube, 0.4, Shading::Gouraud);
    let scene = Scene::new(camera(SIZE.width, SIZE.height), &d).light(light());
    let config = Config::new(SIZE, Rgb565::new(1, 2, 3));
    let (all, stats) = render::<All, _>(&scene, config).unwrap();
    assert!(stats.pixels_shaded > 3000, "{stats:?}");
    // The Hilbert and Auto rasterizers and frustum culling only change the
    // speed: without them the scanline rasterizer draws, nothing is culled.
    for raster in [Rasterizer::Scanline, Rasterizer::Hilbert, Rasterizer::Auto] {
        let config = config.rasterizer(raster);
        let (small, s) = render::<Triangles, _>(&scene, config).unwrap();
        assert!(small == all, "{raster:?}: the same image");
        assert_eq!(s.pixels_shaded, stats.pixels_shaded);
        assert_eq!((s.draws_culled, s.clusters_culled), (0, 0));
    }
    // Other depth tests, and no depth writes, where they are linked.
    for (test, write) in [
        (DepthTest::Less, true),
        (DepthTest::GreaterEqual, true),
        (DepthTest::Always, false),
        (DepthTest::LessEqual, false),
    ] {
        let config = config.depth_test(test).depth_write(write);
        let (a, _) = render::<All, _>(&scene, config).unwrap();
        let (l, _) = render::<Lines, _>(&scene, config).unwrap();
        assert!(a == l, "{test:?} write {write}");
        assert_eq!(
            render::<Triangles, _>(&scene, config).unwrap_err(),
            RenderError::Unsupported {
                draw: None,
                path: Path::DepthTests
            }
        );
    }
}

#[test]
fn one_triangle_path_draws_like_both_and_refuses_the_other() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let config = Config::new(SIZE, Rgb565::new(1, 2, 3));
    for (shading, path) in [
        (Shading::Gouraud, Path::Gouraud),
        (Shading::Flat, Path::Flat),
    ] {
        let d = draws(&knot, &cube, 0.4, shading);
        let scene = Scene::new(camera(SIZE.width, SIZE.height), &d).light(light());
        let (both, stats) = render::<Triangles, _>(&scene, config).unwrap();
        assert!(stats.pixels_shaded > 3000, "{stats:?}");
        let (gouraud, flat) = (
            render::<GouraudTriangles, _>(&scene, config),
            render::<FlatTriangles, _>(&scene, config),
        );
        let (drawn, refused) = if shading == Shading::Gouraud {
            (gouraud, flat)
        } else {
            (flat, gouraud)
        };
        let (one, s) = drawn.unwrap();
        assert!(one == both, "{shading:?}: the same image");
        assert_eq!(s.pixels_shaded, stats.pixels_shaded);
        // Both draws use the one shading: the first is named.
        assert_eq!(
            refused.unwrap_err(),
            RenderError::Unsupported {
                draw: Some(0),
                path
            }
        );
    }
}

#[test]
fn a_path_left_out_is_a_typed_error() {
    let cube = cube();
    let config = Config::new(SIZE, Rgb565::new(1, 2, 3));
    let cam = camera(SIZE.width, SIZE.height);
    let base = Draw::new(&cube).transform(Mat4::translation(Vec3::new(0.0, 0.0, -1.0)));
    let cases = [
        (base.shading(Shading::Wireframe), Path::Lines),
        (base.shading(Shading::Points(2)), Path::Lines),
        (base.edges(Edges::default()), Path::Lines),
        (base.blend(Blend::Alpha(128)), Path::Blend),
        (base.shading(Shading::Shader), Path::Shaders),
    ];
    for (draw, path) in cases {
        // The draw is the second one: the error names it.
        let d = [base, draw];
        let scene = Scene::new(cam, &d).shader(&Gouraud);
        let err = render::<Triangles, _>(&scene, config).unwrap_err();
        assert_eq!(
            err,
            RenderError::Unsupported {
                draw: Some(1),
                path
            }
        );
        assert!(err.to_string().starts_with("draw 1: "), "{err}");
        // The full renderer draws it.
        render::<All, _>(&scene, config).unwrap();
    }
    // The general lighting: a point light, or a shiny material under the
    // one directional light. Unlit draws and the plain light are fine.
    let lamp = [PointLight::new(Vec3::new(0.0, 1.0, 2.0), 0.8, 10.0)];
    let sun = [DirectionalLight::new(Vec3::new(0.0, 1.0, 1.0), 0.9)];
    let lights = Lighting::new(0.2).directional(&sun).point(&lamp);
    let shiny = base.material(Material::new().specular(Rgb888::new(255, 255, 255)));
    for (scene_lighting, draw) in [(Some(&lights), base), (None, shiny)] {
        let d = [base, draw];
        let mut scene = Scene::new(cam, &d).light(Light::new(Vec3::new(0.0, 1.0, 1.0)));
        scene.lighting = scene_lighting;
        let err = render::<Triangles, _>(&scene, config).unwrap_err();
        let want = if scene_lighting.is_some() { 0 } else { 1 };
        assert_eq!(
            err,
            RenderError::Unsupported {
                draw: Some(want),
                path: Path::Lighting
            }
        );
        render::<All, _>(&scene, config).unwrap();
    }
    // `u32` indices: the same cube through them is refused without them.
    let tris32: Vec<[u32; 3]> = cube.triangles().iter().collect();
    let cube32 = Mesh::new_u32(cube.positions(), &tris32).unwrap();
    let cube32 = match cube.normals() {
        Some(n) => cube32.with_normals(n).unwrap(),
        None => cube32,
    };
    let d = [base, Draw::new(&cube32).transform(base.transform)];
    let scene = Scene::new(cam, &d);
    assert_eq!(
        render::<Triangles, _>(&scene, config).unwrap_err(),
        RenderError::Unsupported {
            draw: Some(1),
            path: Path::U32Indices
        }
    );
    let (wide, _) = render::<All, _>(&scene, config).unwrap();
    let d = [base, base];
    let (narrow, _) = render::<Triangles, _>(&Scene::new(cam, &d), config).unwrap();
    assert!(wide == narrow, "u32 indices draw as u16 ones");
    let d = [base];
    let scene = Scene::new(cam, &d);
    assert_eq!(
        render::<Triangles, _>(&scene, config.sort_draws(true)).unwrap_err(),
        RenderError::Unsupported {
            draw: None,
            path: Path::Sort
        }
    );
}

#[test]
fn a_firmwares_own_set_draws_its_lines_like_the_full_renderer() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let mut d = draws(&knot, &cube, 1.1, Shading::Gouraud);
    d[1] = d[1].edges(Edges::new(Rgb888::new(255, 255, 255)));
    let scene = Scene::new(camera(SIZE.width, SIZE.height), &d).light(light());
    let config = Config::new(SIZE, Rgb565::new(1, 2, 3));
    let (all, _) = render::<All, _>(&scene, config).unwrap();
    let (lines, _) = render::<Lines, _>(&scene, config).unwrap();
    assert!(all == lines);
    assert!(render::<Triangles, _>(&scene, config).is_err());
}

/// A Gouraud triangle whose three vertices have one colour draws what a
/// flat one draws, pixel for pixel, depth included: the Cortex-M builds
/// send such triangles to the flat span loops (`fill::ONE_COLOUR_FLAT`;
/// the image hashes of `scripts/icount.sh` compare those builds with the
/// host), so the two loops must agree on them. Unlit, every triangle of
/// the demo is of its draw's colour.
#[test]
fn one_colour_gouraud_triangles_draw_as_flat_ones() {
    let assets = DemoAssets::new();
    let (knot, cube) = (assets.knot(), cube());
    let config = Config::new(SIZE, Rgb565::new(1, 2, 3));
    for test in [DepthTest::LessEqual, DepthTest::Less, DepthTest::Always] {
        let config = config.depth_test(test);
        let [gouraud, flat] = [Shading::Gouraud, Shading::Flat].map(|shading| {
            let d = draws(&knot, &cube, 0.4, shading);
            let scene = Scene::new(camera(SIZE.width, SIZE.height), &d);
            render::<All, _>(&scene, config).unwrap()
        });
        assert!(gouraud.1.pixels_shaded > 3000, "{:?}", gouraud.1);
        assert!(gouraud.0 == flat.0, "{test:?}: the same image");
        assert_eq!(gouraud.1.pixels_shaded, flat.1.pixels_shaded);
    }
}

/// Every path but the opaque quasi-perspective and affine loops.
struct NoModeLoops;
impl Features for NoModeLoops {
    const QUASI: bool = false;
    const AFFINE: bool = false;
}

#[test]
fn frames_draw_the_same_without_the_quasi_and_affine_copies() {
    use microraster::shader::{Textured, TexturedLit};
    use microraster::texture::{Filter, Texels, Texture};
    let texels = checker_texels(32);
    let cube = textured_cube();
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let texture = Texture::new(32, 32, Texels::Rgb565(&texels))
            .unwrap()
            .filter(filter);
        // An opaque draw (the copy with the mode's loops) and a
        // blended one (handed on to the other copy), in front of it.
        let opaque = Draw::new(&cube)
            .shading(Shading::Shader)
            .texture(&texture)
            .transform(Mat4::rotation_y(0.6) * Mat4::rotation_x(0.4));
        let blended = Draw::new(&cube)
            .shading(Shading::Shader)
            .texture(&texture)
            .blend(Blend::Alpha(120))
            .transform(
                Mat4::translation(Vec3::new(0.4, 0.2, 0.8)) * Mat4::scale(Vec3::new(0.5, 0.5, 0.5)),
            );
        let d = [opaque, blended];
        let scene = Scene::new(camera(SIZE.width, SIZE.height), &d).light(light());
        // Through an orthographic camera, whose draws every mode
        // interpolates affinely (their opaque passes in the affine copy,
        // where it is linked), exact frames too.
        let ortho = Camera::new(
            camera(SIZE.width, SIZE.height).view,
            Mat4::orthographic(-2.0, 2.0, -1.5, 1.5, 0.5, 20.0).unwrap(),
        );
        let ortho = Scene::new(ortho, &d).light(light());
        for (scene, mode) in [
            (&scene, Perspective::Quasi8),
            (&scene, Perspective::Quasi16),
            (&scene, Perspective::Affine),
            (&ortho, Perspective::Exact),
            (&ortho, Perspective::Quasi16),
        ] {
            let config = Config::new(SIZE, Rgb565::new(1, 2, 3)).perspective(mode);
            let shaders = [
                render::<All, _>(&scene.shader(&Textured), config),
                render::<NoModeLoops, _>(&scene.shader(&Textured), config),
                render::<All, _>(&scene.shader(&TexturedLit), config),
                render::<NoModeLoops, _>(&scene.shader(&TexturedLit), config),
                render::<All, _>(&scene.shader(&Gouraud), config),
                render::<NoModeLoops, _>(&scene.shader(&Gouraud), config),
            ];
            let shaders: Vec<_> = shaders.into_iter().map(Result::unwrap).collect();
            for pair in shaders.chunks(2) {
                assert!(pair[0].1.pixels_shaded > 2000, "{:?}", pair[0].1);
                assert!(
                    pair[0].0 == pair[1].0,
                    "{filter:?} {mode:?}: the same image"
                );
            }
        }
    }
}
