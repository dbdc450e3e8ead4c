//! What begins a frame: the scene checked, then every vertex transformed,
//! lit and projected once into the workspace's vertex buffer.

use super::{Config, Features, Path, Profiler, RenderError, Stage, MAX_LIGHTS, MAX_TRIANGLES};
use crate::cull::Frustum;
use crate::light::{DirectionalLight, LightError, Lighting};
use crate::math::{Mat4, Vec3};
use crate::mesh::Indices;
use crate::scene::Draw;
use crate::scene::{Blend, Light, Scene, Shading};
use crate::shade::DepthTest;
use crate::shader::ShaderSet;
use crate::vertex::{DrawSetup, ScreenVertex, VertexError, Viewport, MAX_VIEWPORT};
use embedded_graphics::pixelcolor::PixelColor;

/// What the vertex stage found, for the rest of the frame.
pub(super) struct Transformed {
    pub(super) view_proj: Mat4,
    pub(super) eye: Vec3,
    pub(super) viewport: Viewport,
    /// Vertices of the frame's draws: the first `vertices` of the buffer.
    pub(super) vertices: usize,
    /// Triangles of the frame's draws.
    pub(super) triangles: usize,
    /// Vertices actually transformed (none of culled draws and clusters).
    pub(super) transformed: u32,
    /// Bit `d` set when draw `d` (of the first 64) lies wholly outside
    /// the view frustum: binning asks this rather than building the
    /// draw's frustum again ([`FrameState::view_test`](super::state::FrameState::view_test)).
    pub(super) outside: u64,
}

/// How a frame sets up a draw: with or without the general lighting
/// ([`Features::LIGHTING`]), chosen once so that the other is not linked.
/// Built in the caller's slot ([`DrawSetup::new_in`]), so that the set-up
/// is on the stack once. It takes the draw's `view_proj * transform`,
/// normalized (`None` where that failed).
pub(super) type SetupFn = fn(
    &mut Option<DrawSetup>,
    &Draw<'_>,
    Option<&Mat4>,
    Option<&Lighting<'_>>,
    Vec3,
) -> Result<(), VertexError>;

/// The [`SetupFn`] of the paths `P` links.
pub(super) fn setup_fn<P: Features>() -> SetupFn {
    if P::LIGHTING {
        |slot, draw, mvp, lighting, eye| {
            DrawSetup::new_in::<true>(slot, draw, mvp, lighting, eye).map(|_| ())
        }
    } else {
        |slot, draw, mvp, lighting, eye| {
            DrawSetup::new_in::<false>(slot, draw, mvp, lighting, eye).map(|_| ())
        }
    }
}

/// The error of draw `draw`'s set-up: the general lighting, when it is not
/// linked, is a path left out.
pub(super) fn draw_error(draw: usize, error: VertexError) -> RenderError {
    match error {
        VertexError::GeneralLighting => RenderError::Unsupported {
            draw: Some(draw),
            path: Path::Lighting,
        },
        error => RenderError::Draw { draw, error },
    }
}

/// The frame's lighting, passed to `f`: the scene's lighting, or its one
/// light as a lighting of one directional light, or none. Built on the
/// stack each time it is needed (once per frame and per draw set-up), so
/// that a frame borrows nothing but the scene.
pub(super) fn with_lighting<R>(
    light: Option<&Light>,
    lighting: Option<&Lighting<'_>>,
    f: impl FnOnce(Option<&Lighting<'_>>) -> R,
) -> R {
    let one = light.map(|l| [DirectionalLight::new(l.direction, l.color)]);
    let simple = match (light, &one) {
        (Some(l), Some(one)) => Some(Lighting::new(l.ambient).directional(one)),
        _ => None,
    };
    f(lighting.or(simple.as_ref()))
}

/// Checks the scene's lights, once per frame (with an identity model
/// matrix), so that per draw only the draw's own matrix can fail. Out of
/// line, so that its lighting (built on the stack) is not on the stack
/// while the vertex stage runs.
#[inline(never)]
fn check_lights(
    light: Option<&Light>,
    lighting: Option<&Lighting<'_>>,
    eye: Vec3,
) -> Result<(), RenderError> {
    with_lighting(light, lighting, |lighting| match lighting {
        // The checks and errors of `LightSetup::new` with an identity
        // matrix, without its conversions (with the general lighting
        // linked too: building the set-up took the Cortex-M3 some 1,300
        // instructions a frame more).
        Some(l) => crate::light::check_lighting(l, eye, MAX_LIGHTS).map_err(|e| match e {
            LightError::BadMatrix => RenderError::BadCamera,
            e => RenderError::Light(e),
        }),
        None => Ok(()),
    })
}

/// Checks `scene` against `config` and the vertex buffer's capacity, then
/// runs the vertex stage into `vertices`. Every error of a frame is found
/// here.
pub(super) fn run<C, F, P, Q>(
    config: &Config<C>,
    scene: &Scene<'_, F>,
    vertices: &mut [ScreenVertex],
    profiler: &mut Q,
) -> Result<Transformed, RenderError>
where
    C: PixelColor,
    F: ShaderSet<C>,
    P: Features,
    Q: Profiler,
{
    let size = config.size;
    if size.width == 0 || size.height == 0 {
        return Err(RenderError::ZeroViewport);
    }
    if size.width > MAX_VIEWPORT || size.height > MAX_VIEWPORT {
        return Err(RenderError::ViewportTooLarge { size });
    }
    // Where `f32` is in software, out of line (`camera_product`); with an
    // FPU as it was (out of line, the Cortex-M4F's vertex stage took
    // 2,024 instructions more).
    #[cfg(any(test, microraster_soft_float))]
    let view_proj = camera_product(&scene.camera);
    #[cfg(not(any(test, microraster_soft_float)))]
    let view_proj = scene.camera.projection * scene.camera.view;
    // Normalized, as the vertex stage converts each draw's product: a
    // camera in any units is fine; only a non-finite or zero one is bad.
    // (Not `to_fixed_normalized`: a camera alone may lose a row that a
    // draw's model matrix restores.)
    if view_proj.normal_scale().is_none() {
        return Err(RenderError::BadCamera);
    }
    let eye = scene.camera.eye();
    check_lights(scene.light.as_ref(), scene.lighting, eye)?;

    // Capacities first, so nothing is half done.
    let needed: usize = scene.draws.iter().map(|d| d.mesh.vertex_count()).sum();
    if needed > vertices.len() {
        return Err(RenderError::VertexCapacity {
            needed,
            capacity: vertices.len(),
        });
    }
    let triangles: usize = scene.draws.iter().map(|d| d.mesh.triangle_count()).sum();
    if triangles > MAX_TRIANGLES {
        return Err(RenderError::TooManyTriangles { count: triangles });
    }
    let default_depth = matches!(
        (config.depth_test, config.depth_write),
        (DepthTest::LessEqual, true) | (DepthTest::Never, _)
    );
    for (asked, linked, path) in [
        (config.sort_draws, P::SORT, Path::Sort),
        (!default_depth, P::DEPTH_TESTS, Path::DepthTests),
    ] {
        if asked && !linked {
            return Err(RenderError::Unsupported { draw: None, path });
        }
    }
    for (draw, d) in scene.draws.iter().enumerate() {
        let unsupported = |path| RenderError::Unsupported {
            draw: Some(draw),
            path,
        };
        let lines =
            matches!(d.shading, Shading::Wireframe | Shading::Points(_)) || d.edges.is_some();
        if lines && !P::LINES {
            return Err(unsupported(Path::Lines));
        }
        if matches!(d.mesh.triangles(), Indices::U32(_)) && !P::U32_INDICES {
            return Err(unsupported(Path::U32Indices));
        }
        if d.blend != Blend::Opaque && !P::BLEND {
            return Err(unsupported(Path::Blend));
        }
        for (shading, linked, path) in [
            (Shading::Shader, P::SHADERS, Path::Shaders),
            (Shading::Flat, P::FLAT, Path::Flat),
            (Shading::Gouraud, P::GOURAUD, Path::Gouraud),
        ] {
            if d.shading == shading && !linked {
                return Err(unsupported(path));
            }
        }
        if d.shading == Shading::Shader {
            let index = d.shader as usize;
            crate::shader::check_in_set(&scene.shaders, index, d)
                .ok_or(RenderError::MissingShader { draw, index })?
                .map_err(|error| RenderError::Shader { draw, error })?;
        }
    }

    profiler.enter(Stage::Vertex);
    let viewport = Viewport::new(size.width, size.height);
    let (transformed, outside) = with_lighting(scene.light.as_ref(), scene.lighting, |lighting| {
        let cull = P::CULL && config.frustum_cull;
        transform(
            cull,
            setup_fn::<P>(),
            scene,
            &view_proj,
            lighting,
            eye,
            &viewport,
            vertices,
        )
    })?;
    Ok(Transformed {
        view_proj,
        eye,
        viewport,
        vertices: needed,
        triangles,
        transformed,
        outside,
    })
}

/// The vertex stage: every vertex of every draw in view (or of every
/// cluster in view) to a [`ScreenVertex`]; returns how many, and which of
/// the first 64 draws lie wholly outside the frustum
/// ([`Transformed::outside`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn transform<F>(
    cull: bool,
    make: SetupFn,
    scene: &Scene<'_, F>,
    view_proj: &Mat4,
    lighting: Option<&Lighting<'_>>,
    eye: Vec3,
    viewport: &Viewport,
    vertices: &mut [ScreenVertex],
) -> Result<(u32, u64), RenderError> {
    let mut base = 0;
    let mut count = 0u32;
    let mut outside = 0u64;
    for (di, draw) in scene.draws.iter().enumerate() {
        // The set-up checks the draw's matrix whether the draw is seen
        // or not; a draw wholly outside the frustum is then not
        // transformed (its vertices cannot overflow what is never
        // computed), and binning skips it the same way.
        // Built in place, one slot for every draw: a second copy of it
        // (about 600 bytes, its `LightSetup`) would be on the stack, on
        // the frame's deepest path. Read from the local slot, not through
        // a reference the call returns, which the compiler could not tell
        // from the vertex buffer (the loop would reload it per vertex).
        // The draw's product, once for its set-up and its frustum (each
        // made it apart: a `Mat4` product and 16 `f32` divisions).
        let mvp = (*view_proj * draw.transform).normalized();
        let mut made = None;
        let made_ok = make(&mut made, draw, mvp.as_ref(), lighting, eye);
        let setup = match (made_ok, &made) {
            (Ok(()), Some(setup)) => setup,
            (Err(e), _) => return Err(draw_error(di, e)),
            (Ok(()), None) => return Err(draw_error(di, VertexError::BadMatrix)),
        };
        let out = &mut vertices[base..base + draw.mesh.vertex_count()];
        base += draw.mesh.vertex_count();
        let frustum = match cull {
            true => mvp.as_ref().and_then(|m| Frustum::from_normalized(m, draw)),
            false => None,
        };
        if frustum.as_ref().is_some_and(|f| f.excludes_mesh(draw.mesh)) {
            if di < 64 {
                outside |= 1 << di;
            }
            continue;
        }
        // The clusters in view one by one (the others' vertices are
        // never read: binning skips the same clusters), or the whole
        // mesh as one run; one copy of the vertex loop for both.
        let clusters = frustum.and(draw.mesh.clusters());
        for k in 0..clusters.map_or(1, |c| c.len()) {
            let range = match (&frustum, clusters) {
                (Some(f), Some(c)) => {
                    // An empty cluster's vertices serve no triangle.
                    if c[k].triangle_count() == 0 || f.excludes_box(&c[k].bounds()) {
                        continue;
                    }
                    let first = c[k].first_vertex() as usize;
                    first..first + c[k].vertex_count() as usize
                }
                _ => 0..out.len(),
            };
            // Runs do not overlap (Mesh::with_clusters), so this counts
            // at most the frame's vertices.
            count = count.saturating_add(range.len() as u32);
            let first = range.start;
            // The range lies within the mesh (checked when the
            // mesh was built).
            // The colour after the projection (see `screen_vertex_lit`).
            run_vertices(setup, draw, first, viewport, &mut out[range])
                .map_err(|error| RenderError::Draw { draw: di, error })?;
        }
    }
    Ok((count, outside))
}

/// The camera's `projection * view`, out of line: the product takes its
/// operands by value, and their copies would otherwise stay in the
/// vertex stage's frame, on the deepest path (ARMv6-M's stack took 48 B
/// more when the soft-float product's term-by-term form made them
/// copies).
#[cfg(any(test, microraster_soft_float))]
#[inline(never)]
fn camera_product(camera: &crate::scene::Camera) -> Mat4 {
    camera.projection * camera.view
}

/// The vertex loop of one run of a draw's vertices, `first` on, into
/// `out`. A function of its own: its arguments tell the compiler that the
/// set-up (built in place by a call it cannot see) is not the vertex
/// buffer, so that the loop keeps the set-up's values in registers.
#[inline(never)]
fn run_vertices(
    setup: &DrawSetup,
    draw: &Draw<'_>,
    first: usize,
    viewport: &Viewport,
    out: &mut [ScreenVertex],
) -> Result<(), VertexError> {
    // Only a Gouraud draw's vertices carry the interior bit
    // ([`ScreenVertex::interior`]), which only the Gouraud span starts
    // read: a flat, fragment-shader or line draw's are left clear, at no
    // cost per vertex (see `DrawSetup::screen_vertices`). Where no vertex
    // carries it (the Cortex-M4F's builds and those optimised for size),
    // false: the flag passed on and unused took the M4F's vertex loop a
    // register (`demo` +10 K).
    let gouraud = crate::vertex::INTERIOR_STARTS && matches!(draw.shading, Shading::Gouraud);
    setup.screen_vertices(draw.mesh, first, viewport, out, gouraud)
}
