//! The frame loop: vertex stage once, then bin, rasterize, shade and stream
//! tile by tile.
//!
//! # How triangles reach their tiles
//!
//! The vertex stage writes one 16-byte [`ScreenVertex`] per mesh vertex
//! into the [`Workspace`]'s vertex buffer, once per frame. Triangles are
//! never stored set up: a set-up triangle (edges plus attribute planes) is
//! about 150 bytes, which for 4,000 triangles would be several times the RAM
//! of a small MCU. Instead the renderer *bins* triangle indices (`u16`) per
//! tile, with a counting sort over a fixed pool:
//!
//! 1. a count pass walks every triangle (outcodes, culling, screen bounds)
//!    and counts, per tile, the triangles whose bounds touch it;
//! 2. the longest run of tiles whose counts fit the pool is chosen;
//! 3. a fill pass writes the triangle indices of those tiles, in draw order;
//! 4. each of those tiles is cleared, its triangles are set up and
//!    rasterized, and the tile is streamed to the sink.
//!
//! When the pool or the per-pass tile table is too small for the whole frame,
//! the frame is simply done in several such passes, each re-scanning the
//! triangle list (a few dozen instructions per triangle). A single tile that
//! alone overflows the pool is drawn by scanning every triangle against it.
//! The image is identical in every case; only the time changes, and
//! [`FrameStats`] reports the passes.
//!
//! A triangle that must be clipped (near, far, `w` or guard band) keeps no
//! clipped vertices: each time it is needed its three vertices are
//! transformed again from the mesh and clipped again. That costs a few
//! hundred instructions per such triangle and tile, saves a variable-size
//! store, and gives bit-identical vertices every time.

use crate::clip::{clip_triangle, MAX_CLIPPED_VERTICES};
use crate::raster::{scanline::spans, signed_area2, PixelRect, SubPoint};
use crate::scene::{CullMode, Scene, Shading};
use crate::shade::{
    span_flat, span_gouraud, DAlways, DEqual, DGreater, DGreaterEqual, DLess, DLessEqual, DepthFn,
    DepthTest, SpanPos, TriangleSetup,
};
use crate::sink::{rectangle, TileSink};
use crate::tile::{TileBuffer, TileGrid};
use crate::vertex::{
    DrawSetup, ScreenVertex, VertexError, Viewport, MAX_VIEWPORT, MUST_CLIP, REJECT_MASK,
};
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::prelude::Size;

/// Most triangles one frame can hold: bins store `u16` indices.
pub const MAX_TRIANGLES: usize = 1 << 16;

/// The per-frame memory of the renderer, sized at compile time.
///
/// * `VERTICES`: capacity of the vertex buffer, 16 bytes each; at least the
///   total vertex count of all draws of a frame.
/// * `BIN_ENTRIES`: the bin pool, 2 bytes each (at most 65,535). A frame
///   needs about (visible triangles) x (1 + average extra tiles touched);
///   less still renders correctly, in more passes.
/// * `TILES`: tiles binned per pass, 2 bytes each; the number of tiles of
///   the frame for a single pass.
///
/// It is large: put it in a `static` (for example with
/// `cortex_m::singleton!` or `static_cell`) on a microcontroller, or `Box`
/// it on a host.
#[derive(Clone, Debug)]
pub struct Workspace<const VERTICES: usize, const BIN_ENTRIES: usize, const TILES: usize> {
    vertices: [ScreenVertex; VERTICES],
    bins: [u16; BIN_ENTRIES],
    /// Per tile of the current pass: bin count, then start, then end.
    bin_end: [u16; TILES],
}

impl<const V: usize, const B: usize, const T: usize> Default for Workspace<V, B, T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const V: usize, const B: usize, const T: usize> Workspace<V, B, T> {
    const VALID: () = assert!(
        B <= u16::MAX as usize && B > 0 && T > 0,
        "BIN_ENTRIES must be 1..=65535 and TILES at least 1"
    );

    /// An empty workspace (usable in a `static`).
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::VALID;
        Self {
            vertices: [ScreenVertex {
                x: 0,
                y: 0,
                z: 0,
                outcode: 0,
                color: [0; 3],
            }; V],
            bins: [0; B],
            bin_end: [0; T],
        }
    }

    /// The vertices of the last frame's vertex stage.
    pub fn vertices(&self) -> &[ScreenVertex] {
        &self.vertices
    }
}

/// Renderer settings, built embedded-graphics style.
///
/// ```
/// use microraster::prelude::*;
/// use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
/// let config = Config::new(Size::new(320, 240), Rgb565::BLACK)
///     .cull(CullMode::None)
///     .depth_test(DepthTest::Less);
/// assert_eq!(config.size, Size::new(320, 240));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config<C> {
    /// Frame size in pixels, 1..=4096 a side; any multiple of the tile
    /// size or not.
    pub size: Size,
    /// Colour every tile is cleared to.
    pub clear_color: C,
    /// Depth every tile is cleared to (65535 = farthest).
    pub clear_depth: u16,
    /// Face culling.
    pub cull: CullMode,
    /// Depth comparison.
    pub depth_test: DepthTest,
    /// Whether passing fragments write depth.
    pub depth_write: bool,
}

impl<C> Config<C> {
    /// Defaults: clear depth 65535, back-face culling, `LessEqual` with
    /// depth writes.
    pub const fn new(size: Size, clear_color: C) -> Self {
        Self {
            size,
            clear_color,
            clear_depth: u16::MAX,
            cull: CullMode::Back,
            depth_test: DepthTest::LessEqual,
            depth_write: true,
        }
    }

    /// Sets the clear colour.
    pub fn clear_color(mut self, c: C) -> Self {
        self.clear_color = c;
        self
    }

    /// Sets the clear depth.
    pub fn clear_depth(mut self, d: u16) -> Self {
        self.clear_depth = d;
        self
    }

    /// Sets face culling.
    pub fn cull(mut self, cull: CullMode) -> Self {
        self.cull = cull;
        self
    }

    /// Sets the depth comparison.
    pub fn depth_test(mut self, t: DepthTest) -> Self {
        self.depth_test = t;
        self
    }

    /// Enables or disables depth writes.
    pub fn depth_write(mut self, w: bool) -> Self {
        self.depth_write = w;
        self
    }
}

/// What a frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Triangles submitted.
    pub triangles_in: u32,
    /// Triangles discarded as back- or front-facing or zero-area.
    pub culled: u32,
    /// Triangles outside the view (trivially, or after clipping).
    pub rejected: u32,
    /// Triangles that went through the clipper.
    pub clipped: u32,
    /// Triangles that reached at least one tile.
    pub drawn: u32,
    /// Fragments that passed the depth test and were written.
    pub pixels_shaded: u32,
    /// Tiles streamed to the sink.
    pub tiles: u32,
    /// Binning passes over the triangle list.
    pub bin_passes: u32,
    /// Tiles drawn by scanning all triangles because their bin overflowed.
    pub rescanned_tiles: u32,
}

/// A stage of a frame, as reported to a [`Profiler`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Transforming, lighting and projecting every vertex.
    Vertex,
    /// Classifying, culling and clipping triangles and binning them to
    /// tiles (a count and a fill pass per binning pass).
    Binning,
    /// Clearing a tile, setting up its triangles, rasterizing and shading.
    Raster,
    /// Handing a finished tile to the sink.
    Sink,
    /// The frame is finished.
    Done,
}

/// Observes where a frame spends its time: [`Renderer::render_profiled`]
/// calls [`enter`](Profiler::enter) at the start of every stage, so a
/// profiler that reads a timer there can charge the time since its last
/// call to the previous stage. `()` is the profiler that does nothing, and
/// compiles to nothing.
///
/// ```
/// use embedded_graphics::pixelcolor::BinaryColor;
/// use microraster::prelude::*;
/// use microraster::{Profiler, Stage};
///
/// struct Counts([u32; 5]);
/// impl Profiler for Counts {
///     fn enter(&mut self, stage: Stage) {
///         self.0[stage as usize] += 1;
///     }
/// }
/// let mut renderer: Renderer<BinaryColor, 16, 16> =
///     Renderer::new(Config::new(Size::new(32, 32), BinaryColor::Off));
/// let mut ws: Workspace<4, 16, 4> = Workspace::new();
/// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &[]);
/// let mut counts = Counts([0; 5]);
/// renderer.render_profiled(&mut ws, &scene, &mut NullSink, &mut counts).unwrap();
/// // Vertex once, a count and a fill pass, then four tiles each rasterized
/// // and sent, then done.
/// assert_eq!(counts.0, [1, 2, 4, 4, 1]);
/// ```
pub trait Profiler {
    /// The frame enters `stage`.
    fn enter(&mut self, stage: Stage);
}

impl Profiler for () {
    #[inline(always)]
    fn enter(&mut self, _: Stage) {}
}

/// Why a frame could not be rendered. Every error except `Sink` is found
/// before the first tile is sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError<E> {
    /// The frame has a zero width or height.
    ZeroViewport,
    /// A side is larger than [`MAX_VIEWPORT`].
    ViewportTooLarge {
        /// Requested size.
        size: Size,
    },
    /// The camera's matrices are not finite or not representable.
    BadCamera,
    /// The light's direction is zero or not finite.
    BadLight,
    /// A draw's matrices or vertices could not be transformed.
    Draw {
        /// Index of the draw in the scene.
        draw: usize,
        /// What went wrong.
        error: VertexError,
    },
    /// The scene has more vertices than the workspace holds.
    VertexCapacity {
        /// Vertices in the scene.
        needed: usize,
        /// `VERTICES` of the workspace.
        capacity: usize,
    },
    /// The scene has more than [`MAX_TRIANGLES`] triangles.
    TooManyTriangles {
        /// Triangles in the scene.
        count: usize,
    },
    /// The sink failed; tiles before it were delivered.
    Sink(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::ZeroViewport => write!(f, "the frame has zero width or height"),
            Self::ViewportTooLarge { size } => write!(
                f,
                "frame {}x{} exceeds the {MAX_VIEWPORT}-pixel limit per side",
                size.width, size.height
            ),
            Self::BadCamera => write!(f, "the camera matrices are not finite or exceed 16.16"),
            Self::BadLight => write!(f, "the light direction is zero or not finite"),
            Self::Draw { draw, error } => match error {
                VertexError::BadMatrix => write!(
                    f,
                    "draw {draw}: its transform is not finite, singular, or exceeds 16.16"
                ),
                VertexError::OutOfRange { vertex } => write!(
                    f,
                    "draw {draw}: vertex {vertex} leaves the 16.16 range of clip space"
                ),
            },
            Self::VertexCapacity { needed, capacity } => write!(
                f,
                "the scene has {needed} vertices but the workspace holds {capacity}"
            ),
            Self::TooManyTriangles { count } => write!(
                f,
                "the scene has {count} triangles, more than {MAX_TRIANGLES}"
            ),
            Self::Sink(e) => write!(f, "the sink failed: {e:?}"),
        }
    }
}

/// The tiled renderer: a tile buffer of `TW x TH` pixels of colour `C`
/// plus its settings.
///
/// ```
/// use microraster::prelude::*;
/// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::BinaryColor};
///
/// let mut renderer: Renderer<BinaryColor, 16, 16> =
///     Renderer::new(Config::new(Size::new(16, 16), BinaryColor::Off));
/// let mut workspace: Workspace<8, 64, 4> = Workspace::new();
/// let camera = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
/// let mut display = MockDisplay::new();
/// let stats = renderer.render(&mut workspace, &Scene::new(camera, &[]), &mut display).unwrap();
/// assert_eq!(stats.tiles, 1);
/// ```
pub struct Renderer<C, const TW: usize, const TH: usize> {
    tile: TileBuffer<C, TW, TH>,
    config: Config<C>,
}

/// One screen-space triangle ready for set-up.
#[derive(Clone, Copy, Debug)]
struct Piece {
    v: [SubPoint; 3],
    z: [u16; 3],
    colors: [[u8; 3]; 3],
    /// The provoking vertex's colour, for flat shading.
    flat: [u8; 3],
    area2: i64,
}

/// How one submitted triangle turned out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fate {
    Rejected,
    Culled,
    Visible,
}

/// Read-only state of the frame being rendered.
struct Frame<'s, 'v> {
    scene: &'s Scene<'s>,
    vertices: &'v [ScreenVertex],
    view_proj: crate::math::Mat4,
    viewport: Viewport,
    cull: CullMode,
    frame: PixelRect,
}

/// Walks draws alongside increasing global triangle indices.
#[derive(Clone, Copy, Debug, Default)]
struct Cursor {
    draw: usize,
    tri_base: usize,
    vert_base: usize,
}

impl Cursor {
    #[inline]
    fn seek(&mut self, draws: &[crate::scene::Draw<'_>], t: usize) {
        while t >= self.tri_base + draws[self.draw].mesh.triangle_count() {
            self.tri_base += draws[self.draw].mesh.triangle_count();
            self.vert_base += draws[self.draw].mesh.vertex_count();
            self.draw += 1;
        }
    }
}

/// The fixed-point set-up of the last draw a clipped triangle needed.
type SetupCache = Option<(usize, DrawSetup)>;

impl Frame<'_, '_> {
    /// Calls `f` with every visible screen triangle of global triangle `t`
    /// (one, or a fan after clipping). `cur` must not be past `t`.
    #[inline]
    fn pieces(
        &self,
        t: usize,
        cur: &mut Cursor,
        cache: &mut SetupCache,
        mut f: impl FnMut(&Piece),
    ) -> (Fate, bool) {
        let draws = self.scene.draws;
        cur.seek(draws, t);
        let draw = &draws[cur.draw];
        let idx = draw.mesh.triangles()[t - cur.tri_base];
        let sv = [
            &self.vertices[cur.vert_base + idx[0] as usize],
            &self.vertices[cur.vert_base + idx[1] as usize],
            &self.vertices[cur.vert_base + idx[2] as usize],
        ];
        if sv[0].outcode & sv[1].outcode & sv[2].outcode & REJECT_MASK != 0 {
            return (Fate::Rejected, false);
        }
        let colors = [sv[0].color, sv[1].color, sv[2].color];
        let any = sv[0].outcode | sv[1].outcode | sv[2].outcode;
        if any & MUST_CLIP == 0 {
            let v = [
                SubPoint::new(sv[0].x, sv[0].y),
                SubPoint::new(sv[1].x, sv[1].y),
                SubPoint::new(sv[2].x, sv[2].y),
            ];
            let piece = Piece {
                v,
                z: [sv[0].z, sv[1].z, sv[2].z],
                colors,
                flat: colors[0],
                area2: signed_area2(&v),
            };
            return (self.keep(&piece, &mut f), false);
        }

        // Clip path: transform the three vertices again and clip.
        let setup = match cache {
            Some((d, s)) if *d == cur.draw => *s,
            _ => match DrawSetup::new(draw, &self.view_proj, self.scene.light.as_ref()) {
                Ok(s) => {
                    *cache = Some((cur.draw, s));
                    s
                }
                // Cannot happen: the vertex stage accepted this draw.
                Err(_) => return (Fate::Rejected, true),
            },
        };
        let mut tri = [crate::vertex::ClipVertex::default(); 3];
        for (k, cv) in tri.iter_mut().enumerate() {
            match setup.clip_vertex(draw.mesh, idx[k] as usize) {
                Ok(v) => *cv = v,
                Err(_) => return (Fate::Rejected, true),
            }
        }
        let poly = clip_triangle(&tri, any);
        if poly.len() < 3 {
            return (Fate::Rejected, true);
        }
        let project = |k: usize| -> (SubPoint, u16, [u8; 3]) {
            let (p, z) = self.viewport.project(&poly[k].pos);
            let c = poly[k].color;
            (
                p,
                z,
                [
                    c[0].clamp(0, 255) as u8,
                    c[1].clamp(0, 255) as u8,
                    c[2].clamp(0, 255) as u8,
                ],
            )
        };
        // Project once. Snapping to the sub-pixel grid can make the
        // polygon very slightly concave, so facing is decided once, from the
        // whole polygon's area, and fan pieces of the other sign (slivers
        // of round-off) are dropped rather than culled one by one: a
        // back-facing polygon never leaks a piece, and no pixel is shaded
        // twice.
        let mut proj: heapless::Vec<(SubPoint, u16, [u8; 3]), MAX_CLIPPED_VERTICES> =
            heapless::Vec::new();
        for k in 0..poly.len() {
            // Cannot fail: `poly` has the same capacity.
            let _ = proj.push(project(k));
        }
        let mut total = 0i64;
        for k in 2..proj.len() {
            total += signed_area2(&[proj[0].0, proj[k - 1].0, proj[k].0]);
        }
        if self.culled(total) {
            return (Fate::Culled, true);
        }
        let mut fate = Fate::Rejected;
        for k in 2..proj.len() {
            let (first, prev, next) = (proj[0], proj[k - 1], proj[k]);
            let v = [first.0, prev.0, next.0];
            let area2 = signed_area2(&v);
            if area2 == 0 || (area2 > 0) != (total > 0) {
                continue;
            }
            let piece = Piece {
                v,
                z: [first.1, prev.1, next.1],
                colors: [first.2, prev.2, next.2],
                // Flat shading keeps the original provoking vertex's colour.
                flat: colors[0],
                area2,
            };
            if self.visible(&piece, &mut f) {
                fate = Fate::Visible;
            }
        }
        (fate, true)
    }

    /// Whether a triangle or polygon of twice signed screen area `area2`
    /// is culled: zero area always, otherwise by the cull mode.
    #[inline]
    fn culled(&self, area2: i64) -> bool {
        match self.cull {
            _ if area2 == 0 => true,
            CullMode::None => false,
            // Negative area is counter-clockwise in NDC: the front face.
            CullMode::Back => area2 > 0,
            CullMode::Front => area2 < 0,
        }
    }

    /// Passes `p` on when it may touch the frame.
    #[inline]
    fn visible(&self, p: &Piece, f: &mut impl FnMut(&Piece)) -> bool {
        if PixelRect::covering(&p.v).intersect(&self.frame).is_empty() {
            return false;
        }
        f(p);
        true
    }

    /// Culls `p` and passes it on when it faces the right way and may touch
    /// the frame.
    #[inline]
    fn keep(&self, p: &Piece, f: &mut impl FnMut(&Piece)) -> Fate {
        if self.culled(p.area2) {
            Fate::Culled
        } else if self.visible(p, f) {
            Fate::Visible
        } else {
            Fate::Rejected
        }
    }

    /// The pixel bounds of every visible piece of triangle `t`.
    #[inline]
    fn bounds(
        &self,
        t: usize,
        cur: &mut Cursor,
        cache: &mut SetupCache,
    ) -> (Fate, bool, PixelRect) {
        let mut r = PixelRect::new(i32::MAX, i32::MAX, i32::MIN, i32::MIN);
        let (fate, clipped) = self.pieces(t, cur, cache, |p| {
            let b = PixelRect::covering(&p.v);
            r = PixelRect::new(
                r.x0.min(b.x0),
                r.y0.min(b.y0),
                r.x1.max(b.x1),
                r.y1.max(b.y1),
            );
        });
        (fate, clipped, r.intersect(&self.frame))
    }
}

impl<C, const TW: usize, const TH: usize> Renderer<C, TW, TH>
where
    C: PixelColor + From<Rgb888>,
{
    /// A renderer with the given settings.
    pub fn new(config: Config<C>) -> Self {
        Self {
            tile: TileBuffer::new(config.clear_color),
            config,
        }
    }

    /// The settings.
    pub fn config(&self) -> &Config<C> {
        &self.config
    }

    /// The settings, to change between frames.
    pub fn config_mut(&mut self) -> &mut Config<C> {
        &mut self.config
    }

    /// The tile buffer, holding the last tile rendered.
    pub fn tile(&self) -> &TileBuffer<C, TW, TH> {
        &self.tile
    }

    /// Renders `scene` tile by tile into `sink`.
    ///
    /// Every error but [`RenderError::Sink`] is detected before anything is
    /// sent to the sink.
    pub fn render<S, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_>,
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
    {
        self.render_profiled(ws, scene, sink, &mut ())
    }

    /// [`render`](Self::render), telling `profiler` when each [`Stage`]
    /// starts.
    pub fn render_profiled<S, P, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_>,
        sink: &mut S,
        profiler: &mut P,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
        P: Profiler,
    {
        let size = self.config.size;
        if size.width == 0 || size.height == 0 {
            return Err(RenderError::ZeroViewport);
        }
        if size.width > MAX_VIEWPORT || size.height > MAX_VIEWPORT {
            return Err(RenderError::ViewportTooLarge { size });
        }
        let view_proj = scene.camera.projection * scene.camera.view;
        if !view_proj.is_finite() || view_proj.to_fixed().is_none() {
            return Err(RenderError::BadCamera);
        }
        if let Some(light) = &scene.light {
            if light.direction.normalize().is_none() {
                return Err(RenderError::BadLight);
            }
        }

        // Capacities first, so nothing is half done.
        let needed: usize = scene.draws.iter().map(|d| d.mesh.vertex_count()).sum();
        if needed > V {
            return Err(RenderError::VertexCapacity {
                needed,
                capacity: V,
            });
        }
        let n_tris: usize = scene.draws.iter().map(|d| d.mesh.triangle_count()).sum();
        if n_tris > MAX_TRIANGLES {
            return Err(RenderError::TooManyTriangles { count: n_tris });
        }

        // Vertex stage, once per frame.
        profiler.enter(Stage::Vertex);
        let viewport = Viewport::new(size.width, size.height);
        let mut base = 0;
        for (di, draw) in scene.draws.iter().enumerate() {
            let setup = DrawSetup::new(draw, &view_proj, scene.light.as_ref())
                .map_err(|error| RenderError::Draw { draw: di, error })?;
            let out = &mut ws.vertices[base..base + draw.mesh.vertex_count()];
            for (i, sv) in out.iter_mut().enumerate() {
                let cv = setup
                    .clip_vertex(draw.mesh, i)
                    .map_err(|error| RenderError::Draw { draw: di, error })?;
                *sv = viewport.screen_vertex(&cv);
            }
            base += draw.mesh.vertex_count();
        }

        let grid = TileGrid::new(size.width, size.height, TW as u32, TH as u32);
        let frame = Frame {
            scene,
            vertices: &ws.vertices[..needed],
            view_proj,
            viewport,
            cull: self.config.cull,
            frame: PixelRect::new(0, 0, size.width as i32, size.height as i32),
        };
        let mut stats = FrameStats {
            triangles_in: n_tris as u32,
            ..FrameStats::default()
        };
        let mut cache: SetupCache = None;
        let n_tiles = grid.count() as usize;
        let mut t0 = 0usize;
        while t0 < n_tiles {
            let t_end = (t0 + T).min(n_tiles);
            let counts = &mut ws.bin_end[..t_end - t0];
            counts.fill(0);

            // Count pass (and the frame's triangle statistics, once).
            profiler.enter(Stage::Binning);
            let first_pass = stats.bin_passes == 0;
            stats.bin_passes += 1;
            let mut cur = Cursor::default();
            for t in 0..n_tris {
                let (fate, clipped, r) = frame.bounds(t, &mut cur, &mut cache);
                if first_pass {
                    stats.clipped += clipped as u32;
                    match fate {
                        Fate::Rejected => stats.rejected += 1,
                        Fate::Culled => stats.culled += 1,
                        Fate::Visible => stats.drawn += 1,
                    }
                }
                if fate == Fate::Visible {
                    for_tiles(&grid, &r, t0, t_end, |k| {
                        counts[k] = counts[k].saturating_add(1)
                    });
                }
            }

            // The longest run of tiles whose bins fit the pool.
            // Counts saturate at u16::MAX, which therefore means "too many"
            // even when BIN_ENTRIES is 65,535.
            let overflows = |c: u16| c == u16::MAX || c as usize > B;
            if overflows(counts[0]) {
                stats.rescanned_tiles += 1;
                self.draw_tile(
                    &frame,
                    &grid,
                    t0,
                    &mut cache,
                    (sink, &mut *profiler),
                    &mut stats,
                    |f, cur, cache, out| {
                        let rect = grid.rect(t0 as u32);
                        for t in 0..n_tris {
                            let (fate, _, r) = f.bounds(t, cur, cache);
                            if fate == Fate::Visible && !r.intersect(&rect).is_empty() {
                                out(t, cur, cache);
                            }
                        }
                    },
                )?;
                t0 += 1;
                continue;
            }
            let mut total = 0usize;
            let mut t1 = t0;
            for (k, c) in counts.iter_mut().enumerate() {
                if overflows(*c) || total + *c as usize > B {
                    break;
                }
                let start = total;
                total += *c as usize;
                *c = start as u16;
                t1 = t0 + k + 1;
            }

            // Fill pass: counts become bin ends.
            profiler.enter(Stage::Binning);
            let mut cur = Cursor::default();
            for t in 0..n_tris {
                let (fate, _, r) = frame.bounds(t, &mut cur, &mut cache);
                if fate == Fate::Visible {
                    for_tiles(&grid, &r, t0, t1, |k| {
                        ws.bins[counts[k] as usize] = t as u16;
                        counts[k] += 1;
                    });
                }
            }

            for k in 0..t1 - t0 {
                let start = if k == 0 { 0 } else { counts[k - 1] as usize };
                let bin = &ws.bins[start..counts[k] as usize];
                self.draw_tile(
                    &frame,
                    &grid,
                    t0 + k,
                    &mut cache,
                    (sink, &mut *profiler),
                    &mut stats,
                    |_, cur, cache, out| {
                        for &t in bin {
                            out(t as usize, cur, cache);
                        }
                    },
                )?;
            }
            t0 = t1;
        }
        profiler.enter(Stage::Done);
        Ok(stats)
    }

    /// Clears tile `t`, rasterizes the triangles `list` yields into it and
    /// streams it.
    #[allow(clippy::too_many_arguments)]
    fn draw_tile<S: TileSink<C>, P: Profiler>(
        &mut self,
        frame: &Frame<'_, '_>,
        grid: &TileGrid,
        t: usize,
        cache: &mut SetupCache,
        (sink, profiler): (&mut S, &mut P),
        stats: &mut FrameStats,
        list: impl FnOnce(
            &Frame<'_, '_>,
            &mut Cursor,
            &mut SetupCache,
            &mut dyn FnMut(usize, &mut Cursor, &mut SetupCache),
        ),
    ) -> Result<(), RenderError<S::Error>> {
        let rect = grid.rect(t as u32);
        let (w, h) = ((rect.x1 - rect.x0) as usize, (rect.y1 - rect.y0) as usize);
        let cfg = self.config;
        profiler.enter(Stage::Raster);
        self.tile.clear(w, h, cfg.clear_color, cfg.clear_depth);
        let tile = &mut self.tile;
        let mut shaded = 0u32;
        let mut cur = Cursor::default();
        list(frame, &mut cur, cache, &mut |t, cur, cache| {
            let shading = frame.scene.draws[{
                cur.seek(frame.scene.draws, t);
                cur.draw
            }]
            .shading;
            frame.pieces(t, cur, cache, |p| {
                shaded += raster_piece(tile, &rect, p, shading, &cfg);
            });
        });
        stats.pixels_shaded += shaded;
        stats.tiles += 1;
        profiler.enter(Stage::Sink);
        sink.write_tile(&rectangle(&rect), &self.tile.view(w, h))
            .map_err(RenderError::Sink)
    }
}

/// Calls `f(k)` for every tile `t0 + k < t1` (row-major) that the pixel
/// rectangle `r` touches.
#[inline]
fn for_tiles(grid: &TileGrid, r: &PixelRect, t0: usize, t1: usize, mut f: impl FnMut(usize)) {
    if let Some((c0, c1, r0, r1)) = grid.span(r) {
        let cols = grid.cols as usize;
        let (row_lo, row_hi) = (t0 / cols, (t1 - 1) / cols + 1);
        for row in (r0 as usize).max(row_lo)..(r1 as usize).min(row_hi) {
            for col in c0 as usize..c1 as usize {
                let t = row * cols + col;
                if t >= t0 && t < t1 {
                    f(t - t0);
                }
            }
        }
    }
}

/// Rasterizes one piece into the tile with the configured depth test.
#[inline]
fn raster_piece<C, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    p: &Piece,
    shading: Shading,
    cfg: &Config<C>,
) -> u32
where
    C: PixelColor + From<Rgb888>,
{
    let gouraud = shading == Shading::Gouraud;
    macro_rules! go {
        ($d:ty) => {
            match (cfg.depth_write, gouraud) {
                (true, true) => fill::<C, $d, true, true, TW, TH>(tile, rect, p),
                (true, false) => fill::<C, $d, true, false, TW, TH>(tile, rect, p),
                (false, true) => fill::<C, $d, false, true, TW, TH>(tile, rect, p),
                (false, false) => fill::<C, $d, false, false, TW, TH>(tile, rect, p),
            }
        };
    }
    match cfg.depth_test {
        DepthTest::Never => 0,
        DepthTest::Always => go!(DAlways),
        DepthTest::Less => go!(DLess),
        DepthTest::LessEqual => go!(DLessEqual),
        DepthTest::Equal => go!(DEqual),
        DepthTest::GreaterEqual => go!(DGreaterEqual),
        DepthTest::Greater => go!(DGreater),
    }
}

/// The monomorphized triangle loop: spans from the scanline rasterizer,
/// shaded with depth test `D`. The attribute planes are set up at the
/// first span, so a triangle that only grazes the tile's bounds costs no
/// set-up.
#[inline(never)]
fn fill<C, D: DepthFn, const WRITE: bool, const GOURAUD: bool, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    p: &Piece,
) -> u32
where
    C: PixelColor + From<Rgb888>,
{
    let flat = C::from(Rgb888::new(p.flat[0], p.flat[1], p.flat[2]));
    let mut setup: Option<TriangleSetup> = None;
    let mut n = 0;
    spans(&p.v, *rect, |j, x0, x1| {
        let setup =
            setup.get_or_insert_with(|| TriangleSetup::new(&p.v, p.area2, p.z, &p.colors, GOURAUD));
        let row = (j - rect.y0) as usize;
        let (color, depth) = (&mut tile.color[row][..], &mut tile.depth[row][..]);
        let sp = SpanPos {
            ox: rect.x0,
            j,
            x0,
            x1,
        };
        n += if GOURAUD {
            span_gouraud::<C, D, WRITE>(setup, color, depth, sp)
        } else {
            span_flat::<C, D, WRITE>(setup, flat, color, depth, sp)
        };
    });
    n
}
