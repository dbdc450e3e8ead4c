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
//! tile, in one pass over the triangles:
//!
//! 1. each triangle is classified from its three screen vertices: rejected
//!    by its outcodes, culled by the sign of its area, or visible, with the
//!    pixel rectangle it may cover. A rejected or culled triangle costs a few
//!    dozen instructions;
//! 2. a visible triangle's index is appended to the bin of every tile its
//!    rectangle touches. Bins are chains of small fixed-size chunks drawn
//!    from one pool ([`CHUNK`] slots, the last one linking to the tile's next
//!    chunk), so no count pass is needed to lay them out, and each tile's
//!    triangles stay in submission order;
//! 3. each tile of the pass is cleared, its triangles are fetched again from
//!    the vertex buffer, set up and rasterized, and the tile is streamed to
//!    the sink.
//!
//! When the pool runs dry, the pass gives up its last tiles (their chunks
//! go back to the pool) until the triangle fits: the pass then covers the
//! longest run of tiles its bins hold, and the next pass starts where it
//! stopped, re-scanning the triangle list. The same happens when the
//! frame has more tiles than the per-pass tile table. A single tile that
//! alone overflows the pool is drawn by scanning every triangle against it.
//! The image is identical in every case; only the time changes, and
//! [`FrameStats`] reports the passes.
//!
//! The pool is used in chunks rather than laid out by a count pass because
//! the count pass cost as much as the fill pass it prepared: both had to
//! classify every triangle, back faces included. A chunk's link and a
//! tile's last, partly filled chunk cost some slots (an eighth, and half a
//! chunk per tile), which the budget configuration's pool easily spares.
//!
//! # A triangle in a tile
//!
//! The demo's triangles are small (about 11 pixels, spans of 2 or 3), so a
//! frame's time goes to what is done per triangle and tile, per row and
//! per span rather than per pixel. The tile loop therefore works in two phases,
//! each in a function of its own: the scanline walk records the triangle's
//! spans in the tile in a stack buffer (one per tile row), and only if
//! there is one are the attribute planes set up and the spans shaded.
//!
//! A triangle that must be clipped (near, far, `w` or guard band) keeps no
//! clipped vertices: each time it is needed its three vertices are
//! transformed again from the mesh and clipped again. That costs a few
//! hundred instructions per such triangle and tile, saves a variable-size
//! store, and gives bit-identical vertices every time.

use crate::clip::{clip_triangle, MAX_CLIPPED_VERTICES};
use crate::cull::Frustum;
use crate::light::{DirectionalLight, LightError, LightSetup, Lighting};
use crate::mesh::Indices;
use crate::raster::line::{draw_line, draw_point, DepthMode, LinePoint};
use crate::raster::scanline::Walker;
use crate::raster::{
    first_centre_at_or_after, hilbert, signed_area2, PixelRect, Rasterizer, Span, SubPoint,
};
use crate::scene::{Blend, CullMode, Draw, Scene, Shading};
use crate::shade::perspective::{span_shader, Output, PerspectiveSetup, ShaderTriangle};
use crate::shade::{
    span_flat, span_gouraud, Corners, DAlways, DEqual, DGreater, DGreaterEqual, DLess, DLessEqual,
    DepthFn, DepthTest, SpanPos, TriangleSetup,
};
use crate::shader::{self, FragmentShader, Perspective, ShaderError, Varyings, VertexInput};
use crate::sink::{rectangle, TileSink};
use crate::texture::Texture;
use crate::tile::{TileBuffer, TileGrid, TileOrder};
pub use crate::vertex::MAX_LIGHTS;
use crate::vertex::{
    DrawSetup, ScreenVertex, VertexError, Viewport, BARY_ONE, MAX_VIEWPORT, MUST_CLIP, REJECT_MASK,
};
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::prelude::Size;
use fixed::types::I16F16;

/// Most triangles one frame can hold: bins store `u16` indices.
pub const MAX_TRIANGLES: usize = 1 << 16;

/// Slots per chunk of the bin pool: `CHUNK - 1` triangle indices and the
/// index of the tile's next chunk. Small, because a tile wastes half a
/// chunk on average and a chunk an eighth of its slots on the link.
pub const CHUNK: usize = 8;

/// The per-frame memory of the renderer, sized at compile time.
///
/// * `VERTICES`: capacity of the vertex buffer, 16 bytes each; at least the
///   total vertex count of all draws of a frame.
/// * `BIN_ENTRIES`: the bin pool, 2 bytes each (at most 65,535), used in
///   chunks of [`CHUNK`]. A frame needs about (visible triangles) x (1 +
///   average extra tiles touched) x 8/7, plus half a chunk per tile; less
///   still renders correctly, in more passes.
/// * `TILES`: tiles binned per pass, 4 bytes each; the number of tiles of
///   the frame for a single pass.
///
/// It is large: put it in a `static` (for example with
/// `cortex_m::singleton!` or `static_cell`) on a microcontroller, or `Box`
/// it on a host.
#[derive(Clone, Debug)]
pub struct Workspace<const VERTICES: usize, const BIN_ENTRIES: usize, const TILES: usize> {
    vertices: [ScreenVertex; VERTICES],
    bins: [u16; BIN_ENTRIES],
    /// Per tile of the current pass: its first chunk.
    heads: [u16; TILES],
    /// Per tile of the current pass: the slot its next entry goes to, or
    /// [`EMPTY`].
    tails: [u16; TILES],
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
            // All zeros, so that a `static` workspace lives in `.bss` and
            // costs no flash (each pass sets the tails up anyway).
            heads: [0; T],
            tails: [0; T],
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
    /// Which rasterizer finds covered pixels (the image is the same).
    pub rasterizer: Rasterizer,
    /// The order tiles are rendered and streamed in (the image is the
    /// same).
    pub tile_order: TileOrder,
    /// How fragment shaders' varyings are interpolated.
    pub perspective: Perspective,
    /// Whether draws wholly outside the view frustum, and the
    /// [clusters](crate::mesh::Cluster) outside it of the draws in view, are
    /// culled before the vertex stage ([`crate::cull`]). The image is the
    /// same. Culled vertices are not transformed, so a vertex that would
    /// leave the 16.16 range of clip space is culled with its draw or
    /// cluster rather than reported: with culling off the same frame may
    /// be a [`RenderError::Draw`].
    pub frustum_cull: bool,
    /// Whether draws are visited sorted by depth: opaque ones front to
    /// back, then transparent ones back to front (see
    /// [`sort_draws`](Self::sort_draws)).
    pub sort_draws: bool,
}

impl<C> Config<C> {
    /// Defaults: clear depth 65535, back-face culling, `LessEqual` with
    /// depth writes, the scanline rasterizer, row-major tiles.
    pub const fn new(size: Size, clear_color: C) -> Self {
        Self {
            size,
            clear_color,
            clear_depth: u16::MAX,
            cull: CullMode::Back,
            depth_test: DepthTest::LessEqual,
            depth_write: true,
            rasterizer: Rasterizer::Scanline,
            tile_order: TileOrder::RowMajor,
            perspective: Perspective::Exact,
            frustum_cull: true,
            sort_draws: false,
        }
    }

    /// Selects the rasterizer. A `const fn`, so a configuration fixed at
    /// compile time can be a `const`:
    ///
    /// ```
    /// use microraster::prelude::*;
    /// use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// const CONFIG: Config<Rgb565> = Config::new(Size::new(128, 96), Rgb565::BLACK)
    ///     .rasterizer(Rasterizer::Hilbert)
    ///     .tile_order(TileOrder::Hilbert);
    /// assert_eq!(CONFIG.rasterizer, Rasterizer::Hilbert);
    /// ```
    pub const fn rasterizer(mut self, r: Rasterizer) -> Self {
        self.rasterizer = r;
        self
    }

    /// Selects the order tiles are rendered in.
    pub const fn tile_order(mut self, order: TileOrder) -> Self {
        self.tile_order = order;
        self
    }

    /// Enables or disables culling draws and mesh clusters against the view
    /// frustum (default on; the image is the same either way, see
    /// [`frustum_cull`](Self::frustum_cull)).
    pub const fn frustum_cull(mut self, on: bool) -> Self {
        self.frustum_cull = on;
        self
    }

    /// Sorts the draws of each frame by the view depth of their bounding
    /// box's centre: opaque draws front to back, so that fewer fragments
    /// are shaded only to be covered, then transparent draws back to
    /// front. Off by default: it changes which of two draws wins a depth
    /// tie (the later one, under [`DepthTest::LessEqual`]), so coplanar
    /// overlaps such as decals keep their submission order only without
    /// it. Frames with more than [`MAX_SORTED_DRAWS`] draws are not sorted.
    pub const fn sort_draws(mut self, on: bool) -> Self {
        self.sort_draws = on;
        self
    }

    /// Selects how fragment shaders' varyings are interpolated (default
    /// [`Perspective::Exact`]).
    pub const fn perspective(mut self, p: Perspective) -> Self {
        self.perspective = p;
        self
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
    /// Draws culled whole against the view frustum (their triangles are
    /// counted in `rejected`).
    pub draws_culled: u32,
    /// Mesh clusters culled against the view frustum, in draws that were
    /// not culled whole (their triangles are counted in `rejected`).
    pub clusters_culled: u32,
    /// Vertices transformed by the vertex stage (none of culled draws and
    /// clusters).
    pub vertices: u32,
}

/// One line of `name=value` pairs, every field in declaration order, for
/// logs and benchmark output:
///
/// ```
/// use microraster::FrameStats;
/// let s = FrameStats { triangles_in: 12, drawn: 6, ..FrameStats::default() };
/// assert!(s.to_string().starts_with("triangles_in=12 culled=0 rejected=0 clipped=0 drawn=6 "));
/// ```
impl core::fmt::Display for FrameStats {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "triangles_in={} culled={} rejected={} clipped={} drawn={} pixels_shaded={} \
             tiles={} bin_passes={} rescanned_tiles={} draws_culled={} clusters_culled={} \
             vertices={}",
            self.triangles_in,
            self.culled,
            self.rejected,
            self.clipped,
            self.drawn,
            self.pixels_shaded,
            self.tiles,
            self.bin_passes,
            self.rescanned_tiles,
            self.draws_culled,
            self.clusters_culled,
            self.vertices
        )
    }
}

/// A stage of a frame, as reported to a [`Profiler`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Transforming, lighting and projecting every vertex.
    Vertex,
    /// Classifying, culling and clipping triangles and binning them to
    /// tiles (once per binning pass).
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
/// // Vertex once, one binning pass, then four tiles each rasterized and
/// // sent, then done.
/// assert_eq!(counts.0, [1, 1, 4, 4, 1]);
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
    /// The scene's light or lighting is invalid: a zero or non-finite
    /// direction or position, a bad range or fog, or more than
    /// [`MAX_LIGHTS`] lights.
    Light(LightError),
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
    /// A draw uses [`Shading::Shader`] and the scene has no shader.
    MissingShader {
        /// Index of the draw in the scene.
        draw: usize,
    },
    /// A draw lacks what the scene's shader reads.
    Shader {
        /// Index of the draw in the scene.
        draw: usize,
        /// What is missing.
        error: ShaderError,
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
            Self::Light(e) => write!(f, "lighting: {e}"),
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
            Self::MissingShader { draw } => write!(
                f,
                "draw {draw} uses Shading::Shader but the scene has no shader"
            ),
            Self::Shader { draw, error } => write!(f, "draw {draw}: {error}"),
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

/// The tail of a tile that has no chunk yet. `EMPTY % CHUNK == CHUNK - 1`,
/// so it reads as a full chunk and the tile's first entry allocates one.
const EMPTY: u16 = u16::MAX;
/// The end of the free-chunk list.
const NO_CHUNK: u16 = u16::MAX;
const _: () = assert!(CHUNK.is_power_of_two() && CHUNK >= 2 && EMPTY as usize % CHUNK == CHUNK - 1);

/// The slot of chunk `c` that links to the next chunk.
#[inline(always)]
fn link(c: u16) -> usize {
    c as usize * CHUNK + CHUNK - 1
}

/// The bins of one pass: per tile, a chain of chunks of the pool holding
/// triangle indices in submission order.
struct Bins<'w> {
    pool: &'w mut [u16],
    heads: &'w mut [u16],
    /// Per tile the pass still holds (a prefix of the pass's tiles: the
    /// pass gives up tiles from its end when the pool runs dry), the slot
    /// its next entry goes to.
    tails: &'w mut [u16],
    /// Chunks `fresh..chunks` have never been used.
    fresh: u16,
    chunks: u16,
    /// Chunks given back, linked through their last slot.
    free: u16,
}

impl<'w> Bins<'w> {
    fn new(pool: &'w mut [u16], heads: &'w mut [u16], tails: &'w mut [u16]) -> Self {
        tails.fill(EMPTY);
        Self {
            // At most 65,535 / CHUNK chunks: every slot index fits `u16`
            // below `EMPTY`.
            chunks: (pool.len() / CHUNK) as u16,
            pool,
            heads,
            tails,
            fresh: 0,
            free: NO_CHUNK,
        }
    }

    /// The number of tiles the pass holds.
    fn tiles(&self) -> usize {
        self.tails.len()
    }

    /// Appends triangle `t` to the bin of tile `k` of the pass, unless the
    /// pass does not hold that tile.
    #[inline(always)]
    fn push(&mut self, k: usize, t: u16) {
        let Some(&tail) = self.tails.get(k) else {
            return;
        };
        let mut slot = tail as usize;
        if slot % CHUNK == CHUNK - 1 {
            match self.grow(k) {
                Some(s) => slot = s,
                None => return,
            }
        }
        self.pool[slot] = t;
        self.tails[k] = slot as u16 + 1;
    }

    /// Links a new chunk to tile `k`, whose chunk is full (or which has
    /// none), and returns the chunk's first slot. When the pool is
    /// exhausted, the pass gives up its last tile, whose chunks go back to
    /// the pool, until a chunk is found; `None` when tile `k` itself had to
    /// go.
    #[cold]
    #[inline(never)]
    fn grow(&mut self, k: usize) -> Option<usize> {
        loop {
            if let Some(c) = self.alloc() {
                let tail = self.tails[k];
                if tail == EMPTY {
                    self.heads[k] = c;
                } else {
                    self.pool[tail as usize] = c;
                }
                return Some(c as usize * CHUNK);
            }
            // `k` is held, so there is a last tile.
            let last = self.tails.len() - 1;
            self.release(last);
            let tails = core::mem::take(&mut self.tails);
            self.tails = &mut tails[..last];
            if last == k {
                return None;
            }
        }
    }

    fn alloc(&mut self) -> Option<u16> {
        if self.fresh < self.chunks {
            self.fresh += 1;
            Some(self.fresh - 1)
        } else if self.free != NO_CHUNK {
            let c = self.free;
            self.free = self.pool[link(c)];
            Some(c)
        } else {
            None
        }
    }

    /// Gives the chunks of tile `k` back to the pool.
    fn release(&mut self, k: usize) {
        let tail = self.tails[k];
        if tail == EMPTY {
            return;
        }
        let mut c = self.heads[k];
        loop {
            // The chunk holding the tail is the last; its link slot holds
            // no link.
            let last = tail as usize / CHUNK == c as usize;
            let next = self.pool[link(c)];
            self.pool[link(c)] = self.free;
            self.free = c;
            if last {
                break;
            }
            c = next;
        }
        self.tails[k] = EMPTY;
    }

    /// The triangles of tile `k`, in submission order.
    fn iter(&self, k: usize) -> BinIter<'_> {
        let tail = self.tails[k];
        let (pos, end) = if tail == EMPTY {
            (0, 0)
        } else {
            (self.heads[k] as usize * CHUNK, tail as usize)
        };
        BinIter {
            pool: self.pool,
            pos,
            end,
        }
    }
}

/// The triangle indices of one bin.
struct BinIter<'a> {
    pool: &'a [u16],
    pos: usize,
    end: usize,
}

impl Iterator for BinIter<'_> {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.pos == self.end {
            return None;
        }
        if self.pos % CHUNK == CHUNK - 1 {
            self.pos = self.pool[self.pos] as usize * CHUNK;
        }
        let t = self.pool[self.pos];
        self.pos += 1;
        Some(t as usize)
    }
}

/// How one submitted triangle turned out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fate {
    Rejected,
    Culled,
    Visible,
}

/// How many triangles of a pass met each fate.
#[derive(Clone, Copy, Debug, Default)]
struct Tally {
    fates: [u32; 3],
    clipped: u32,
    draws_culled: u32,
    clusters_culled: u32,
}

/// Read-only state of the frame being rendered.
struct Frame<'s, 'v> {
    draws: &'s [Draw<'s>],
    lighting: Option<Lighting<'s>>,
    /// The camera's position, world space.
    eye: crate::math::Vec3,
    /// Cull draws outside the frustum ([`Config::frustum_cull`]).
    cull_draws: bool,
    /// The order draws are visited in, when sorted
    /// ([`Config::sort_draws`]), and the first vertex of each draw (by
    /// draw index) in the vertex buffer; `None` for submission order.
    order: Option<(&'s [u16], &'s [u32])>,
    vertices: &'v [ScreenVertex],
    view_proj: crate::math::Mat4,
    viewport: Viewport,
    cull: CullMode,
    frame: PixelRect,
}

/// The fixed-point set-up of the last draw a clipped triangle needed.
type SetupCache = Option<(usize, DrawSetup)>;

/// The pixels whose centres may be covered by a triangle with these
/// vertices: [`PixelRect::covering`], inlined into the binning loop.
#[inline(always)]
fn covering(v: &[SubPoint; 3]) -> PixelRect {
    let (xmin, xmax) = (
        v[0].x.min(v[1].x).min(v[2].x),
        v[0].x.max(v[1].x).max(v[2].x),
    );
    let (ymin, ymax) = (
        v[0].y.min(v[1].y).min(v[2].y),
        v[0].y.max(v[1].y).max(v[2].y),
    );
    PixelRect::new(
        first_centre_at_or_after(xmin),
        first_centre_at_or_after(ymin),
        first_centre_at_or_after(xmax) + 1,
        first_centre_at_or_after(ymax) + 1,
    )
}

/// `r` grown by `m` pixels on every side.
#[inline(always)]
fn grow(r: &PixelRect, m: i32) -> PixelRect {
    PixelRect::new(r.x0 - m, r.y0 - m, r.x1 + m, r.y1 + m)
}

/// Most draws a frame sorts ([`Config::sort_draws`]): the visiting order
/// and the vertex bases live on the stack, 6 bytes per draw (and 8 more
/// while sorting).
pub const MAX_SORTED_DRAWS: usize = 64;

/// The distance in front of the eye of the centre of `draw`'s bounding
/// box, along the view direction (`-z` in eye space).
fn view_depth(view: &crate::math::Mat4, draw: &Draw<'_>) -> f32 {
    let [lo, hi] = draw.mesh.bounds().map(|c| c.map(|v| v.to_num::<f32>()));
    let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let m = *view * draw.transform;
    let z = m.m[0][2] * c[0] + m.m[1][2] * c[1] + m.m[2][2] * c[2] + m.m[3][2];
    -z
}

/// How far beyond the pixel centres it covers a triangle of `draw` may
/// draw: the lines of its edges reach the pixels holding its vertices
/// (one pixel), its points half their size.
fn margin(draw: &Draw<'_>) -> i32 {
    match (draw.shading, draw.edges) {
        (Shading::Points(size), _) => size as i32 / 2 + 1,
        (Shading::Wireframe, _) | (_, Some(_)) => 1,
        _ => 0,
    }
}

/// [`PixelRect::intersect`], inlined.
#[inline(always)]
fn meet(a: &PixelRect, b: &PixelRect) -> PixelRect {
    PixelRect::new(
        a.x0.max(b.x0),
        a.y0.max(b.y0),
        a.x1.min(b.x1),
        a.y1.min(b.y1),
    )
}

impl Frame<'_, '_> {
    /// The draw visited `k`-th.
    #[inline(always)]
    fn visit(&self, k: usize) -> usize {
        match self.order {
            Some((order, _)) => order[k] as usize,
            None => k,
        }
    }

    /// The view frustum in the model space of draw `d`, when culling is on
    /// (the same answers every time it is asked: the tests are
    /// deterministic, so binning, rescans and the vertex stage agree).
    fn frustum(&self, d: usize) -> Option<Frustum> {
        match self.cull_draws {
            true => Frustum::new(&self.view_proj, &self.draws[d]),
            false => None,
        }
    }

    /// The fixed-point set-up of draw `d`, from `cache` or computed again
    /// (and cached). `None` cannot happen: the vertex stage accepted the
    /// draw, and the set-up is deterministic.
    #[inline(never)]
    fn setup(&self, d: usize, cache: &mut SetupCache) -> Option<DrawSetup> {
        match cache {
            Some((c, s)) if *c == d => Some(*s),
            _ => {
                let s = DrawSetup::new(
                    &self.draws[d],
                    &self.view_proj,
                    self.lighting.as_ref(),
                    self.eye,
                )
                .ok()?;
                *cache = Some((d, s));
                Some(s)
            }
        }
    }

    /// Whether a triangle or polygon of twice signed screen area `area2`
    /// survives culling: never with zero area, otherwise by the cull mode.
    #[inline(always)]
    fn keeps(&self, area2: i64) -> bool {
        match self.cull {
            CullMode::None => area2 != 0,
            // Negative area is counter-clockwise in NDC: the front face.
            CullMode::Back => area2 < 0,
            CullMode::Front => area2 > 0,
        }
    }

    /// Classifies triangle `idx` of draw `d`, whose vertices are `verts`:
    /// counts its fate in `tally` and, if it is visible, returns the pixels
    /// it may cover. The common case (no clipping) reads only the three
    /// screen vertices; a rejected or culled triangle costs a few dozen
    /// instructions.
    #[inline(always)]
    fn classify(
        &self,
        d: usize,
        verts: &[ScreenVertex],
        idx: [u32; 3],
        margin: i32,
        cache: &mut SetupCache,
        tally: &mut Tally,
    ) -> Option<PixelRect> {
        let sv = [
            &verts[idx[0] as usize],
            &verts[idx[1] as usize],
            &verts[idx[2] as usize],
        ];
        let and = sv[0].outcode & sv[1].outcode & sv[2].outcode;
        let any = sv[0].outcode | sv[1].outcode | sv[2].outcode;
        let fate = if and & REJECT_MASK != 0 {
            Fate::Rejected
        } else if any & MUST_CLIP != 0 {
            return self.classify_clipped(d, idx, any, sv[0].color, margin, cache, tally);
        } else {
            let v = [
                SubPoint::new(sv[0].x, sv[0].y),
                SubPoint::new(sv[1].x, sv[1].y),
                SubPoint::new(sv[2].x, sv[2].y),
            ];
            let area2 = signed_area2(&v);
            if !self.keeps(area2) {
                Fate::Culled
            } else {
                let rect = meet(&grow(&covering(&v), margin), &self.frame);
                if !rect.is_empty() {
                    tally.fates[Fate::Visible as usize] += 1;
                    return Some(rect);
                }
                Fate::Rejected
            }
        };
        tally.fates[fate as usize] += 1;
        None
    }

    /// [`classify`](Self::classify) for a triangle that must be clipped:
    /// the bounds of all its visible pieces.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn classify_clipped(
        &self,
        d: usize,
        idx: [u32; 3],
        any: u8,
        flat: [u8; 3],
        margin: i32,
        cache: &mut SetupCache,
        tally: &mut Tally,
    ) -> Option<PixelRect> {
        let mut r = PixelRect::new(i32::MAX, i32::MAX, i32::MIN, i32::MIN);
        let fate = self.clipped_pieces(d, idx, any, flat, cache, &mut |piece, _| {
            let sv = &piece.sv;
            let b = covering(&[
                SubPoint::new(sv[0].x, sv[0].y),
                SubPoint::new(sv[1].x, sv[1].y),
                SubPoint::new(sv[2].x, sv[2].y),
            ]);
            r = PixelRect::new(
                r.x0.min(b.x0),
                r.y0.min(b.y0),
                r.x1.max(b.x1),
                r.y1.max(b.y1),
            );
        });
        tally.clipped += 1;
        tally.fates[fate as usize] += 1;
        (fate == Fate::Visible).then(|| meet(&grow(&r, margin), &self.frame))
    }

    /// Clips triangle `idx` of draw `d` (outcodes or-ed to `any`) and
    /// calls `f` with every piece of the fan that faces the right way and
    /// may touch the frame, and the flat colour `flat` of the triangle's
    /// provoking vertex.
    #[inline(never)]
    fn clipped_pieces(
        &self,
        d: usize,
        idx: [u32; 3],
        any: u8,
        flat: [u8; 3],
        cache: &mut SetupCache,
        // Dynamic: the clipper is rare, and one copy of it serves every
        // monomorphized span loop.
        f: &mut dyn FnMut(&Piece, [u8; 3]),
    ) -> Fate {
        let draw = &self.draws[d];
        // Transform the three vertices again and clip.
        let Some(setup) = self.setup(d, cache) else {
            return Fate::Rejected;
        };
        let mut tri = [crate::vertex::ClipVertex::default(); 3];
        for (k, cv) in tri.iter_mut().enumerate() {
            match setup.clip_vertex(draw.mesh, idx[k] as usize) {
                Ok(v) => *cv = v,
                Err(_) => return Fate::Rejected,
            }
        }
        let poly = clip_triangle(&tri, any);
        if poly.len() < 3 {
            return Fate::Rejected;
        }
        let project = |k: usize| -> ScreenVertex {
            let (p, z) = self.viewport.project(&poly[k].pos);
            let c = poly[k].color;
            ScreenVertex {
                x: p.x,
                y: p.y,
                z,
                outcode: 0,
                color: [
                    c[0].clamp(0, 255) as u8,
                    c[1].clamp(0, 255) as u8,
                    c[2].clamp(0, 255) as u8,
                ],
            }
        };
        // Project once. Snapping to the sub-pixel grid can make the
        // polygon very slightly concave, so facing is decided once, from the
        // whole polygon's area, and fan pieces of the other sign (slivers
        // of round-off) are dropped rather than culled one by one: a
        // back-facing polygon never leaks a piece, and no pixel is shaded
        // twice.
        let mut proj: heapless::Vec<ScreenVertex, MAX_CLIPPED_VERTICES> = heapless::Vec::new();
        for k in 0..poly.len() {
            // Cannot fail: `poly` has the same capacity.
            let _ = proj.push(project(k));
        }
        let xy = |v: &ScreenVertex| SubPoint::new(v.x, v.y);
        let mut total = 0i64;
        for k in 2..proj.len() {
            total += signed_area2(&[xy(&proj[0]), xy(&proj[k - 1]), xy(&proj[k])]);
        }
        if !self.keeps(total) {
            return Fate::Culled;
        }
        // A polygon made very slightly concave by snapping has a reflex
        // vertex (turning against the polygon's orientation), and a fan
        // from another vertex would overlap itself there, shading pixels
        // twice. Nearly convex, it is star-shaped from that vertex: fan
        // from it, and the pieces tile the polygon exactly.
        let n = proj.len();
        let apex = (0..n)
            .find(|&k| {
                let turn = signed_area2(&[
                    xy(&proj[(k + n - 1) % n]),
                    xy(&proj[k]),
                    xy(&proj[(k + 1) % n]),
                ]);
                turn != 0 && (turn > 0) != (total > 0)
            })
            .unwrap_or(0);
        // The margin of the draw's lines and points, which may reach pixels
        // beyond a piece's covered centres.
        let margin = margin(draw);
        let mut fate = Fate::Rejected;
        for k in 2..n {
            let corners = [apex, (apex + k - 1) % n, (apex + k) % n];
            let piece = Piece {
                sv: corners.map(|c| proj[c]),
                w: corners.map(|c| poly[c].pos[3]),
                bary: corners.map(|c| poly[c].bary),
            };
            let v = piece.sv.map(|v| xy(&v));
            let area2 = signed_area2(&v);
            if area2 == 0 || (area2 > 0) != (total > 0) {
                continue;
            }
            // Flat shading keeps the original provoking vertex's colour.
            if !meet(&grow(&covering(&v), margin), &self.frame).is_empty() {
                f(&piece, flat);
                fate = Fate::Visible;
            }
        }
        fate
    }
}

/// A piece of a clipped triangle: its projected corners, their clip-space
/// `w` and their places in the original triangle.
struct Piece {
    sv: [ScreenVertex; 3],
    w: [i32; 3],
    bary: [[i32; 2]; 3],
}

/// One binning pass over every triangle: classifies it and appends a
/// visible one to the bin of each tile of the pass its bounds touch. The
/// pass holds the tiles visited `t0..`: in row-major order, or with
/// `HILBERT` along the Hilbert curve over the tile grid.
#[inline(always)]
fn bin_pass<const TW: usize, const TH: usize, const HILBERT: bool>(
    frame: &Frame<'_, '_>,
    grid: &TileGrid,
    t0: usize,
    bins: &mut Bins<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let mut t = 0usize;
    let mut vbase = 0usize;
    for k in 0..frame.draws.len() {
        let d = frame.visit(k);
        let draw = &frame.draws[d];
        let base = match frame.order {
            Some((_, bases)) => bases[d] as usize,
            None => vbase,
        };
        let verts = &frame.vertices[base..base + draw.mesh.vertex_count()];
        vbase += verts.len();
        let frustum = frame.frustum(d);
        let n = draw.mesh.triangle_count();
        if frustum.as_ref().is_some_and(|f| f.excludes_mesh(draw.mesh)) {
            t += n;
            tally.fates[Fate::Rejected as usize] += n as u32;
            tally.draws_culled += 1;
            continue;
        }
        let margin = margin(draw);
        let ctx = BinDraw {
            frame,
            grid,
            t0,
            d,
            verts,
            margin,
        };
        // The clusters in view one by one, or the whole mesh as one run.
        let clusters = frustum.and(draw.mesh.clusters());
        let mut first = 0;
        for k in 0..clusters.map_or(1, |c| c.len()) {
            let len = match (&frustum, clusters) {
                (Some(f), Some(c)) => {
                    let len = c[k].triangle_count() as usize;
                    if len == 0 {
                        continue;
                    }
                    if f.excludes_box(&c[k].bounds()) {
                        t += len;
                        first += len;
                        tally.fates[Fate::Rejected as usize] += len as u32;
                        tally.clusters_culled += 1;
                        continue;
                    }
                    len
                }
                _ => n,
            };
            let run = first..first + len;
            first += len;
            // The u16 loop is inlined here, per tile order; the u32 one
            // (meshes beyond 65,536 vertices, rare) is one out-of-line copy
            // for both.
            match draw.mesh.triangles() {
                Indices::U16(tris) => bin_triangles::<TW, TH, u16>(
                    &ctx, &tris[run], HILBERT, &mut t, bins, cache, tally,
                ),
                Indices::U32(tris) => {
                    bin_wide::<TW, TH>(&ctx, &tris[run], HILBERT, &mut t, bins, cache, tally)
                }
            }
        }
    }
}

/// [`bin_triangles`] for `u32` indices, out of line.
#[inline(never)]
fn bin_wide<const TW: usize, const TH: usize>(
    ctx: &BinDraw<'_, '_>,
    tris: &[[u32; 3]],
    hilbert: bool,
    t: &mut usize,
    bins: &mut Bins<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    bin_triangles::<TW, TH, u32>(ctx, tris, hilbert, t, bins, cache, tally)
}

/// What [`bin_triangles`] needs of the draw it bins.
struct BinDraw<'a, 'f> {
    frame: &'a Frame<'f, 'f>,
    grid: &'a TileGrid,
    t0: usize,
    d: usize,
    verts: &'a [ScreenVertex],
    margin: i32,
}

/// The triangles `tris` of one draw, the first numbered `*t`, classified
/// and appended to their tiles' bins (see [`bin_pass`]).
#[inline(always)]
fn bin_triangles<const TW: usize, const TH: usize, I: Copy + Into<u32>>(
    ctx: &BinDraw<'_, '_>,
    tris: &[[I; 3]],
    hilbert: bool,
    t: &mut usize,
    bins: &mut Bins<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let cols = ctx.grid.cols as usize;
    for &idx in tris {
        let idx = idx.map(Into::into);
        if let Some(r) = ctx
            .frame
            .classify(ctx.d, ctx.verts, idx, ctx.margin, cache, tally)
        {
            // A visible rectangle lies inside the frame, so its
            // coordinates are not negative.
            let (c0, c1) = (r.x0 as usize / TW, (r.x1 as usize - 1) / TW + 1);
            let (r0, r1) = (r.y0 as usize / TH, (r.y1 as usize - 1) / TH + 1);
            for row in r0..r1 {
                if hilbert {
                    for col in c0..c1 {
                        let p = ctx.grid.position(col as u32, row as u32) as usize;
                        bins.push(p.wrapping_sub(ctx.t0), *t as u16);
                    }
                } else {
                    // Tiles before the pass wrap around to indices the
                    // pass does not hold.
                    let first = (row * cols).wrapping_sub(ctx.t0);
                    for col in c0..c1 {
                        bins.push(first.wrapping_add(col), *t as u16);
                    }
                }
            }
        }
        *t += 1;
    }
}

/// Walks the draws alongside increasing global triangle indices, with the
/// slices of the current draw at hand.
struct DrawCursor<'f> {
    draws: &'f [crate::scene::Draw<'f>],
    vertices: &'f [ScreenVertex],
    /// The visiting order and vertex bases, when draws are sorted.
    order: Option<(&'f [u16], &'f [u32])>,
    /// The current draw's place in the visiting order, and its index.
    pos: usize,
    draw: usize,
    /// Global index of the draw's first triangle, and one past its last.
    first: usize,
    end: usize,
    /// Index of the draw's first vertex in the vertex buffer.
    vbase: usize,
    triangles: Indices<'f>,
    verts: &'f [ScreenVertex],
    shading: Shading,
    blend: Blend,
    /// The draw has edges or points to draw.
    lines: bool,
}

impl<'f> DrawCursor<'f> {
    fn new(frame: &'f Frame<'f, 'f>) -> Self {
        let draws = frame.draws;
        let mut c = Self {
            draws,
            vertices: frame.vertices,
            order: frame.order,
            pos: 0,
            draw: 0,
            first: 0,
            end: 0,
            vbase: 0,
            triangles: Indices::U16(&[]),
            verts: &[],
            shading: Shading::Flat,
            blend: Blend::Opaque,
            lines: false,
        };
        if !draws.is_empty() {
            c.enter(0);
        }
        c
    }

    /// Enters the draw visited `k`-th (with `vbase` already its first
    /// vertex in submission order).
    fn enter(&mut self, k: usize) {
        let d = match self.order {
            Some((order, bases)) => {
                let d = order[k] as usize;
                self.vbase = bases[d] as usize;
                d
            }
            None => k,
        };
        let draw = &self.draws[d];
        self.pos = k;
        self.draw = d;
        self.triangles = draw.mesh.triangles();
        self.verts = &self.vertices[self.vbase..self.vbase + draw.mesh.vertex_count()];
        self.end = self.first + self.triangles.len();
        self.shading = draw.shading;
        self.blend = draw.blend;
        self.lines = margin(draw) != 0;
    }

    /// Moves to the draw holding global triangle `t`, which must not lie
    /// before the current draw.
    #[inline(always)]
    fn seek(&mut self, t: usize) {
        while t >= self.end {
            self.advance();
        }
    }

    /// Moves to the draw holding global triangle `t`, before or after the
    /// current draw.
    fn go_to(&mut self, t: usize) {
        if t < self.first {
            self.first = 0;
            self.vbase = 0;
            self.enter(0);
        }
        self.seek(t);
    }

    #[inline(never)]
    fn advance(&mut self) {
        self.first = self.end;
        self.vbase += self.verts.len();
        self.enter(self.pos + 1);
    }
}

/// The triangles of one tile: its bin, or, for a tile whose bin overflowed
/// the pool, every visible triangle whose bounds touch it.
// One per tile, moved by value into the tile loop: the rare variant keeps
// its large state behind a reference.
enum TileList<'a, 'f> {
    Bin(BinIter<'a>),
    Scan {
        frame: &'f Frame<'f, 'f>,
        rect: PixelRect,
        next: usize,
        state: &'a mut ScanState<'f>,
    },
}

/// What a rescanned tile's walk over every triangle keeps.
struct ScanState<'f> {
    cur: DrawCursor<'f>,
    cache: SetupCache,
    /// The current draw's frustum (when culling), its next cluster, and
    /// the global index of the current cluster's end.
    frustum: Option<Frustum>,
    cluster: usize,
    cluster_end: usize,
}

impl Iterator for TileList<'_, '_> {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        match self {
            TileList::Bin(b) => b.next(),
            TileList::Scan {
                frame,
                rect,
                next,
                state,
            } => loop {
                let ScanState {
                    cur,
                    cache,
                    frustum,
                    cluster,
                    cluster_end,
                } = &mut **state;
                let t = *next;
                if t >= cur.end {
                    if cur.pos + 1 >= cur.draws.len() {
                        return None;
                    }
                    cur.advance();
                    continue;
                }
                // The same tests as binning's, in the same order.
                let mesh = frame.draws[cur.draw].mesh;
                if t == cur.first {
                    *frustum = frame.frustum(cur.draw);
                    if frustum.as_ref().is_some_and(|f| f.excludes_mesh(mesh)) {
                        *next = cur.end;
                        continue;
                    }
                    (*cluster, *cluster_end) = (0, t);
                }
                if let (Some(f), Some(clusters)) = (frustum.as_ref(), mesh.clusters()) {
                    // Enter the cluster holding t (past any empty ones).
                    let mut skip = false;
                    while t >= *cluster_end && *cluster < clusters.len() {
                        let c = &clusters[*cluster];
                        *cluster += 1;
                        *cluster_end += c.triangle_count() as usize;
                        skip = f.excludes_box(&c.bounds());
                    }
                    if skip {
                        *next = *cluster_end;
                        continue;
                    }
                }
                *next += 1;
                let idx = cur.triangles.get(t - cur.first);
                let mut tally = Tally::default();
                let m = margin(&frame.draws[cur.draw]);
                let vis = frame.classify(cur.draw, cur.verts, idx, m, cache, &mut tally);
                if vis.is_some_and(|r| !meet(&r, rect).is_empty()) {
                    return Some(t);
                }
            },
        }
    }
}

impl<C, const TW: usize, const TH: usize> Renderer<C, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
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
    ///
    /// The renderer is monomorphized for the scene's fragment shader `F`
    /// ([`NoShader`](crate::shader::NoShader) unless
    /// [`Scene::shader`] set one).
    pub fn render<S, F, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_, F>,
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
        F: FragmentShader<C>,
    {
        self.render_profiled(ws, scene, sink, &mut ())
    }

    /// [`render`](Self::render), telling `profiler` when each [`Stage`]
    /// starts.
    pub fn render_profiled<S, P, F, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_, F>,
        sink: &mut S,
        profiler: &mut P,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
        P: Profiler,
        F: FragmentShader<C>,
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
        // The lights: the scene's lighting, or its one light as a
        // lighting of one directional light. Checked once here (with an
        // identity model matrix), so that per draw only the draw's own
        // matrix can fail.
        let one = scene
            .light
            .map(|l| [DirectionalLight::new(l.direction, l.color)]);
        let simple = match (&scene.light, &one) {
            (Some(l), Some(one)) => Some(Lighting::new(l.ambient).directional(one)),
            _ => None,
        };
        let lighting = scene.lighting.copied().or(simple);
        let eye = scene.camera.eye();
        if let Some(l) = &lighting {
            LightSetup::<MAX_LIGHTS>::new(l, &crate::math::Mat4::IDENTITY, eye).map_err(
                |e| match e {
                    LightError::BadMatrix => RenderError::BadCamera,
                    e => RenderError::Light(e),
                },
            )?;
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
        for (draw, d) in scene.draws.iter().enumerate() {
            if d.shading == Shading::Shader {
                let shader = scene.shader.ok_or(RenderError::MissingShader { draw })?;
                shader
                    .check(d)
                    .map_err(|error| RenderError::Shader { draw, error })?;
            }
        }

        // Vertex stage, once per frame.
        profiler.enter(Stage::Vertex);
        let viewport = Viewport::new(size.width, size.height);
        let mut base = 0;
        let mut vertex_count = 0u32;
        for (di, draw) in scene.draws.iter().enumerate() {
            // The set-up checks the draw's matrix whether the draw is seen
            // or not; a draw wholly outside the frustum is then not
            // transformed (its vertices cannot overflow what is never
            // computed), and binning skips it the same way.
            let setup = DrawSetup::new(draw, &view_proj, lighting.as_ref(), eye)
                .map_err(|error| RenderError::Draw { draw: di, error })?;
            let out = &mut ws.vertices[base..base + draw.mesh.vertex_count()];
            base += draw.mesh.vertex_count();
            let frustum = match self.config.frustum_cull {
                true => Frustum::new(&view_proj, draw),
                false => None,
            };
            if frustum.as_ref().is_some_and(|f| f.excludes_mesh(draw.mesh)) {
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
                vertex_count = vertex_count.saturating_add(range.len() as u32);
                let first = range.start;
                // The range lies within the mesh (checked when the
                // mesh was built).
                for (i, sv) in out[range].iter_mut().enumerate() {
                    let cv = setup
                        .clip_vertex(draw.mesh, first + i)
                        .map_err(|error| RenderError::Draw { draw: di, error })?;
                    *sv = viewport.screen_vertex(&cv);
                }
            }
        }

        let Workspace {
            vertices,
            bins: pool,
            heads,
            tails,
        } = ws;
        let grid = TileGrid::new(size.width, size.height, TW as u32, TH as u32)
            .ordered(self.config.tile_order);
        let hilbert_tiles = self.config.tile_order == TileOrder::Hilbert;
        // The visiting order, when sorted: opaque draws front to back, then
        // transparent ones back to front, by the view depth of their
        // bounding box's centre; ties in submission order.
        let mut order: heapless::Vec<u16, MAX_SORTED_DRAWS> = heapless::Vec::new();
        let mut bases: heapless::Vec<u32, MAX_SORTED_DRAWS> = heapless::Vec::new();
        let sorted = self.config.sort_draws && scene.draws.len() <= MAX_SORTED_DRAWS;
        if sorted {
            let mut keys: heapless::Vec<(bool, f32), MAX_SORTED_DRAWS> = heapless::Vec::new();
            let mut base = 0u32;
            for (d, draw) in scene.draws.iter().enumerate() {
                let transparent = draw.blend != Blend::Opaque;
                let depth = view_depth(&scene.camera.view, draw);
                // Transparent draws sort far first: negate their depth.
                let key = if transparent { -depth } else { depth };
                // Capacity: at most MAX_SORTED_DRAWS draws here.
                let _ = keys.push((transparent, key));
                let _ = order.push(d as u16);
                let _ = bases.push(base);
                base += draw.mesh.vertex_count() as u32;
            }
            // Stable insertion sort: opaque before transparent, then by key
            // (NaN keys, from non-finite set-ups, compare as equal).
            let before =
                |a: (bool, f32), b: (bool, f32)| (!a.0 && b.0) || (a.0 == b.0 && a.1 < b.1);
            for k in 1..order.len() {
                let e = order[k];
                let mut i = k;
                while i > 0 && before(keys[e as usize], keys[order[i - 1] as usize]) {
                    order[i] = order[i - 1];
                    i -= 1;
                }
                order[i] = e;
            }
        }
        let frame = Frame {
            order: sorted.then_some((&order[..], &bases[..])),
            draws: scene.draws,
            lighting,
            eye,
            vertices: &vertices[..needed],
            view_proj,
            viewport,
            cull: self.config.cull,
            cull_draws: self.config.frustum_cull,
            frame: PixelRect::new(0, 0, size.width as i32, size.height as i32),
        };
        let mut stats = FrameStats {
            triangles_in: n_tris as u32,
            vertices: vertex_count,
            ..FrameStats::default()
        };
        let mut cache: SetupCache = None;
        let n_tiles = grid.count() as usize;
        let mut t0 = 0usize;
        while t0 < n_tiles {
            let t_end = (t0 + T).min(n_tiles);
            let mut bins = Bins::new(
                &mut pool[..],
                &mut heads[..t_end - t0],
                &mut tails[..t_end - t0],
            );

            // Binning: one pass over the triangles (and the frame's triangle
            // statistics, once).
            profiler.enter(Stage::Binning);
            let first_pass = stats.bin_passes == 0;
            stats.bin_passes += 1;
            let mut tally = Tally::default();
            // Monomorphized per tile order, so the row-major loop keeps its
            // shape.
            if hilbert_tiles {
                bin_pass::<TW, TH, true>(&frame, &grid, t0, &mut bins, &mut cache, &mut tally);
            } else {
                bin_pass::<TW, TH, false>(&frame, &grid, t0, &mut bins, &mut cache, &mut tally);
            }
            if first_pass {
                stats.rejected = tally.fates[Fate::Rejected as usize];
                stats.culled = tally.fates[Fate::Culled as usize];
                stats.drawn = tally.fates[Fate::Visible as usize];
                stats.clipped = tally.clipped;
                stats.draws_culled = tally.draws_culled;
                stats.clusters_culled = tally.clusters_culled;
            }

            if bins.tiles() == 0 {
                // Tile t0 alone overflows the pool: scan every triangle
                // against it.
                stats.rescanned_tiles += 1;
                let tile = grid.tile_at(t0 as u32) as usize;
                let rect = grid.rect(tile as u32);
                let mut state = ScanState {
                    cur: DrawCursor::new(&frame),
                    cache: None,
                    frustum: None,
                    cluster: 0,
                    cluster_end: 0,
                };
                let list = TileList::Scan {
                    frame: &frame,
                    rect,
                    next: 0,
                    state: &mut state,
                };
                self.draw_tile(
                    &frame,
                    &grid,
                    tile,
                    &mut cache,
                    (sink, &mut *profiler, scene.shader),
                    &mut stats,
                    list,
                )?;
                t0 += 1;
                continue;
            }
            for k in 0..bins.tiles() {
                self.draw_tile(
                    &frame,
                    &grid,
                    grid.tile_at((t0 + k) as u32) as usize,
                    &mut cache,
                    (sink, &mut *profiler, scene.shader),
                    &mut stats,
                    TileList::Bin(bins.iter(k)),
                )?;
            }
            t0 += bins.tiles();
        }
        profiler.enter(Stage::Done);
        Ok(stats)
    }

    /// Clears tile `t`, rasterizes the triangles of `list` into it and
    /// streams it.
    #[allow(clippy::too_many_arguments)]
    fn draw_tile<'f, S: TileSink<C>, P: Profiler, F: FragmentShader<C>>(
        &mut self,
        frame: &'f Frame<'f, 'f>,
        grid: &TileGrid,
        t: usize,
        cache: &mut SetupCache,
        (sink, profiler, shader): (&mut S, &mut P, Option<&F>),
        stats: &mut FrameStats,
        list: TileList<'_, 'f>,
    ) -> Result<(), RenderError<S::Error>> {
        let rect = grid.rect(t as u32);
        let (w, h) = ((rect.x1 - rect.x0) as usize, (rect.y1 - rect.y0) as usize);
        let cfg = self.config;
        profiler.enter(Stage::Raster);
        self.tile.clear(w, h, cfg.clear_color, cfg.clear_depth);
        let tile = &mut self.tile;
        macro_rules! go {
            ($d:ty) => {
                if cfg.depth_write {
                    Shaders::new::<$d, true>(&cfg, shader)
                } else {
                    Shaders::new::<$d, false>(&cfg, shader)
                }
            };
        }
        let shaders = match cfg.depth_test {
            DepthTest::Never => None,
            DepthTest::Always => Some(go!(DAlways)),
            DepthTest::Less => Some(go!(DLess)),
            DepthTest::LessEqual => Some(go!(DLessEqual)),
            DepthTest::Equal => Some(go!(DEqual)),
            DepthTest::GreaterEqual => Some(go!(DGreaterEqual)),
            DepthTest::Greater => Some(go!(DGreater)),
        };
        let shaded = match shaders {
            Some(shaders) => raster_tile(tile, &rect, frame, cache, list, shaders),
            None => 0,
        };
        stats.pixels_shaded += shaded;
        stats.tiles += 1;
        profiler.enter(Stage::Sink);
        sink.write_tile(&rectangle(&rect), &self.tile.view(w, h))
            .map_err(RenderError::Sink)
    }
}

/// Rasterizes the triangles of `list` into the tile: fetches each one's
/// vertices from the vertex buffer (or clips it again) and draws it with
/// [`fill`], shading with `shaders`.
#[inline(never)]
fn raster_tile<'f, C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &'f Frame<'f, 'f>,
    cache: &mut SetupCache,
    list: TileList<'_, 'f>,
    shaders: Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let mut cur = DrawCursor::new(frame);
    // The spans of one triangle, reused by all of the tile's triangles:
    // `TH` of 12 bytes on the stack.
    let mut found = [Span::default(); TH];
    // Transparent triangles, drawn after the opaque ones: (depth key,
    // triangle), 4 bytes each on the stack.
    let mut later: heapless::Vec<(u16, u16), MAX_TRANSPARENT> = heapless::Vec::new();
    let mut n = 0;
    for t in list {
        cur.seek(t);
        let idx = cur.triangles.get(t - cur.first);
        let sv = [
            &cur.verts[idx[0] as usize],
            &cur.verts[idx[1] as usize],
            &cur.verts[idx[2] as usize],
        ];
        let any = sv[0].outcode | sv[1].outcode | sv[2].outcode;
        if cur.lines {
            n += raster_lines(tile, rect, frame, cache, &cur, idx, any, &shaders);
            if matches!(cur.shading, Shading::Wireframe | Shading::Points(_)) {
                continue;
            }
        }
        if cur.blend != Blend::Opaque {
            // Farthest vertex first; a clipped triangle (whose depths the
            // vertex buffer does not hold) reaches the near plane: last.
            let key = if any & MUST_CLIP != 0 {
                0
            } else {
                sv[0].z.max(sv[1].z).max(sv[2].z)
            };
            // `t < MAX_TRIANGLES`, so it fits u16. A full list is drawn
            // (sorted) and emptied first: a tile with more transparent
            // triangles than the list holds sorts them in batches of
            // `MAX_TRANSPARENT`, in submission order between batches.
            if later.is_full() {
                n += draw_later(tile, rect, frame, cache, &mut later, &mut found, &shaders);
            }
            let _ = later.push((key, t as u16));
            continue;
        }
        n += if cur.shading == Shading::Shader {
            match shaders.shader {
                Some(s) => raster_shaded(
                    tile,
                    rect,
                    frame,
                    cache,
                    &cur,
                    idx,
                    any,
                    &mut found,
                    shaders.pass(s, shaders.custom, Blend::Opaque),
                ),
                // `render` checked that shader draws have a shader.
                None => 0,
            }
        } else if any & MUST_CLIP != 0 {
            raster_clipped(
                tile,
                rect,
                frame,
                cache,
                &cur,
                idx,
                any,
                sv[0].color,
                &mut found,
                &shaders,
            )
        } else {
            fill(
                tile,
                rect,
                sv,
                sv[0].color,
                cur.shading == Shading::Gouraud,
                &mut found,
                &shaders,
            )
        };
    }
    n += draw_later(tile, rect, frame, cache, &mut later, &mut found, &shaders);
    n
}

/// Draws the transparent triangles of `later` back to front (equal keys in
/// submission order) and empties it.
#[inline(never)]
fn draw_later<'f, C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &'f Frame<'f, 'f>,
    cache: &mut SetupCache,
    later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    found: &mut [Span; TH],
    shaders: &Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    if later.is_empty() {
        return 0;
    }
    // A stable insertion sort: a few dozen instructions of code, where
    // the library's sort brings kilobytes, and at most 128 entries.
    for k in 1..later.len() {
        let e = later[k];
        let mut i = k;
        while i > 0 && later[i - 1].0 < e.0 {
            later[i] = later[i - 1];
            i -= 1;
        }
        later[i] = e;
    }
    let mut n = 0;
    let mut cur = DrawCursor::new(frame);
    for &(_, t) in later.iter() {
        let t = t as usize;
        cur.go_to(t);
        let idx = cur.triangles.get(t - cur.first);
        let any = idx
            .iter()
            .fold(0, |a, &i| a | cur.verts[i as usize].outcode);
        n += raster_transparent(tile, rect, frame, cache, &cur, idx, any, found, shaders);
    }
    later.clear();
    n
}

/// Most transparent triangles one tile sorts back to front at once (4
/// bytes each on the stack); a tile with more sorts them in batches of
/// this many, in submission order between batches.
pub const MAX_TRANSPARENT: usize = 128;

/// Draws a transparent triangle of the cursor's draw through the
/// fragment-shader path: the scene's shader, or the flat or Gouraud
/// colour, blended, depth tested and never writing depth.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn raster_transparent<C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &Frame<'_, '_>,
    cache: &mut SetupCache,
    cur: &DrawCursor<'_>,
    idx: [u32; 3],
    any: u8,
    found: &mut [Span; TH],
    shaders: &Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let blend = cur.blend;
    let no_write = |mut out: Output| {
        out.write = false;
        out.blend = blend;
        out
    };
    match cur.shading {
        Shading::Shader => match shaders.shader {
            Some(s) => raster_shaded(
                tile,
                rect,
                frame,
                cache,
                cur,
                idx,
                any,
                found,
                shaders.pass(s, shaders.custom, blend).with(no_write),
            ),
            None => 0,
        },
        Shading::Flat => raster_shaded(
            tile,
            rect,
            frame,
            cache,
            cur,
            idx,
            any,
            found,
            shaders
                .pass(&shader::Flat, shaders.flat_t, blend)
                .with(no_write),
        ),
        Shading::Gouraud => raster_shaded(
            tile,
            rect,
            frame,
            cache,
            cur,
            idx,
            any,
            found,
            shaders
                .pass(&shader::Gouraud, shaders.gouraud_t, blend)
                .with(no_write),
        ),
        // Never deferred: they have no fill.
        Shading::Wireframe | Shading::Points(_) => 0,
    }
}

/// Draws the lines or points of triangle `idx` of the cursor's draw: its
/// three edges (or, for a clipped triangle, the parts of them that survive
/// clipping), or a point at each vertex in front of the near plane.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn raster_lines<C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &Frame<'_, '_>,
    cache: &mut SetupCache,
    cur: &DrawCursor<'_>,
    idx: [u32; 3],
    any: u8,
    shaders: &Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let draw = &frame.draws[cur.draw];
    let sv = idx.map(|i| &cur.verts[i as usize]);
    let mode = DepthMode {
        test: shaders.out.test,
        write: shaders.out.write,
    };
    let mut n = 0;
    if let Shading::Points(size) = draw.shading {
        for v in sv {
            if v.outcode & MUST_CLIP == 0 {
                let p = LinePoint::new(SubPoint::new(v.x, v.y), v.z, v.color);
                n += draw_point(tile, rect, mode, &p, size as u32);
            }
        }
        return n;
    }
    let style = draw.edges.unwrap_or_default();
    let end = |v: &ScreenVertex| {
        let color = match style.color {
            Some(c) => {
                use embedded_graphics::prelude::RgbColor;
                [c.r(), c.g(), c.b()]
            }
            None => v.color,
        };
        LinePoint::new(SubPoint::new(v.x, v.y), v.z, color)
    };
    let interpolate = style.color.is_none();
    if any & MUST_CLIP == 0 {
        for k in 0..3 {
            let (a, b) = (end(sv[k]), end(sv[(k + 1) % 3]));
            n += draw_line(tile, rect, mode, &a, &b, interpolate, style.depth_bias);
        }
        return n;
    }
    let flat = sv[0].color;
    frame.clipped_pieces(cur.draw, idx, any, flat, cache, &mut |piece, _| {
        // Only the sides lying on the triangle's own edges: where both
        // ends have the same zero weight (clipping interpolates the
        // weights, and zero between zeros stays exactly zero).
        let w = piece.bary.map(|[b1, b2]| {
            [
                BARY_ONE as i64 - b1 as i64 - b2 as i64,
                b1 as i64,
                b2 as i64,
            ]
        });
        for k in 0..3 {
            let k2 = (k + 1) % 3;
            if (0..3).any(|c| w[k][c] == 0 && w[k2][c] == 0) {
                let (a, b) = (end(&piece.sv[k]), end(&piece.sv[k2]));
                n += draw_line(tile, rect, mode, &a, &b, interpolate, style.depth_bias);
            }
        }
    });
    n
}

/// Clips triangle `idx` of the cursor's draw again and rasterizes its
/// pieces.
#[cold]
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn raster_clipped<C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &Frame<'_, '_>,
    cache: &mut SetupCache,
    cur: &DrawCursor<'_>,
    idx: [u32; 3],
    any: u8,
    flat: [u8; 3],
    found: &mut [Span; TH],
    shaders: &Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let mut n = 0;
    let gouraud = cur.shading == Shading::Gouraud;
    frame.clipped_pieces(cur.draw, idx, any, flat, cache, &mut |piece, flat| {
        let sv = &piece.sv;
        let sv = [&sv[0], &sv[1], &sv[2]];
        n += fill(tile, rect, sv, flat, gouraud, found, shaders);
    });
    n
}

/// Draws triangle `idx` of the cursor's draw, a [`Shading::Shader`] draw,
/// through the frame's fragment shader: its varyings from the shader's
/// vertex function and its `w` from the draw's transform, both evaluated
/// again (the vertex buffer keeps neither), or, for a triangle that must
/// be clipped, its pieces with varyings interpolated at their corners.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn raster_shaded<C, G, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &Frame<'_, '_>,
    cache: &mut SetupCache,
    cur: &DrawCursor<'_>,
    idx: [u32; 3],
    any: u8,
    found: &mut [Span; TH],
    pass: ShaderPass<'_, C, G, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    G: FragmentShader<C>,
{
    let shader = pass.shader;
    let draw = &frame.draws[cur.draw];
    let mesh = draw.mesh;
    let var = idx.map(|i| {
        shader.vertex(&VertexInput {
            draw: cur.draw,
            index: i as usize,
            mesh,
        })
    });
    let sv = [
        &cur.verts[idx[0] as usize],
        &cur.verts[idx[1] as usize],
        &cur.verts[idx[2] as usize],
    ];
    let flat = sv[0].color;
    if any & MUST_CLIP != 0 {
        let mut n = 0;
        frame.clipped_pieces(cur.draw, idx, any, flat, cache, &mut |piece, _| {
            let mut pv = piece.sv;
            // Flat colour stays the provoking vertex's, as on other paths.
            pv[0].color = if G::INTERPOLATE_COLOR {
                pv[0].color
            } else {
                flat
            };
            let tri = ShaderTriangle {
                corners: Corners([&pv[0], &pv[1], &pv[2]]),
                w: piece.w,
                var: piece.bary.map(|b| lerp_varyings(&var, b)),
            };
            n += fill_shaded(tile, rect, &tri, draw.texture, found, &pass);
        });
        return n;
    }
    let Some(setup) = frame.setup(cur.draw, cache) else {
        return 0;
    };
    let tri = ShaderTriangle {
        corners: Corners(sv),
        w: idx.map(|i| setup.clip_w(mesh, i as usize)),
        var,
    };
    fill_shaded(tile, rect, &tri, draw.texture, found, &pass)
}

/// The varyings at barycentric weights `b` (of vertices 1 and 2,
/// [`BARY_ONE`] being 1) of a triangle whose vertices have `var`,
/// rounded to nearest.
fn lerp_varyings<V: Varyings>(var: &[V; 3], b: [i32; 2]) -> V {
    let mut out = V::zeroed();
    let [a0, a1, a2] = [var[0].as_slice(), var[1].as_slice(), var[2].as_slice()];
    for (k, o) in out.as_mut_slice().iter_mut().enumerate() {
        let base = a0[k].to_bits() as i128;
        let d1 = a1[k].to_bits() as i128 - base;
        let d2 = a2[k].to_bits() as i128 - base;
        let sum = d1 * b[0] as i128 + d2 * b[1] as i128 + (BARY_ONE as i128 >> 1);
        *o = I16F16::from_bits((base + (sum >> 30)) as i32);
    }
    out
}

/// Finds the spans of triangle `v` in the tile with `raster`: the first
/// phase of [`fill`] and [`fill_shaded`].
#[inline(always)]
fn find(v: &[SubPoint; 3], rect: &PixelRect, found: &mut [Span], raster: Rasterizer) -> usize {
    match raster {
        Rasterizer::Scanline => find_spans(v, rect, found),
        Rasterizer::Hilbert => hilbert::find_spans(v, *rect, found),
        Rasterizer::Auto => match whole_tile(v, rect, found) {
            Some(n) => n,
            None => find_spans(v, rect, found),
        },
    }
}

/// Draws one triangle into the tile, Gouraud or flat shaded (`flat` is the
/// colour of flat shading) by `shaders`.
///
/// Two phases: the scanline rasterizer first walks the edges and records
/// the triangle's spans in the tile in `found` (at most one per row), then,
/// if there is any, the attribute planes are set up and the spans shaded,
/// both out of line. Each loop then keeps only its own state in
/// registers (the edge walk its two edges, the shading its planes), and a
/// triangle that merely grazes the tile's bounds costs no set-up.
#[inline(always)]
fn fill<C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    sv: [&ScreenVertex; 3],
    flat: [u8; 3],
    gouraud: bool,
    found: &mut [Span; TH],
    shaders: &Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let v = sv.map(|v| SubPoint::new(v.x, v.y));
    let count = find(&v, rect, found, shaders.raster);
    if count == 0 {
        return 0;
    }
    let found = &found[..count];
    let shade = if gouraud {
        shaders.gouraud
    } else {
        shaders.flat
    };
    shade(tile, rect, sv, flat, found)
}

/// [`fill`] for a triangle coloured by a fragment shader.
#[inline(always)]
fn fill_shaded<C, G, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    tri: &ShaderTriangle<'_, G::Varyings>,
    texture: Option<&Texture<'_>>,
    found: &mut [Span; TH],
    pass: &ShaderPass<'_, C, G, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    G: FragmentShader<C>,
{
    let v = tri.corners.0.map(|v| SubPoint::new(v.x, v.y));
    let count = find(&v, rect, found, pass.raster);
    if count == 0 {
        return 0;
    }
    (pass.shade)(
        tile,
        rect,
        tri,
        &found[..count],
        pass.shader,
        texture,
        pass.out,
    )
}

/// The second phase of a triangle's drawing, as monomorphized for the
/// frame's depth test and writes: the only code that depends on them, so
/// the tile loop exists once per colour and tile size.
type ShadeFn<C, const TW: usize, const TH: usize> =
    fn(&mut TileBuffer<C, TW, TH>, &PixelRect, [&ScreenVertex; 3], [u8; 3], &[Span]) -> u32;

/// The second phase for a fragment shader `G`: one function per shader
/// and colour type (the depth test is decided at run time there).
type CustomFn<C, G, const TW: usize, const TH: usize> = fn(
    &mut TileBuffer<C, TW, TH>,
    &PixelRect,
    &ShaderTriangle<'_, <G as FragmentShader<C>>::Varyings>,
    &[Span],
    &G,
    Option<&Texture<'_>>,
    Output,
) -> u32;

/// How a frame draws a triangle: its rasterizer and its shading
/// functions: Gouraud, flat, the fragment shader's, and for transparent
/// draws flat and Gouraud through the fragment-shader path.
struct Shaders<'s, C: From<Rgb888>, F: FragmentShader<C>, const TW: usize, const TH: usize> {
    raster: Rasterizer,
    out: Output,
    gouraud: ShadeFn<C, TW, TH>,
    flat: ShadeFn<C, TW, TH>,
    custom: CustomFn<C, F, TW, TH>,
    flat_t: CustomFn<C, shader::Flat, TW, TH>,
    gouraud_t: CustomFn<C, shader::Gouraud, TW, TH>,
    shader: Option<&'s F>,
}

impl<'s, C, F, const TW: usize, const TH: usize> Shaders<'s, C, F, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    fn new<D: DepthFn, const WRITE: bool>(cfg: &Config<C>, shader: Option<&'s F>) -> Self {
        Self {
            raster: cfg.rasterizer,
            out: Output {
                mode: cfg.perspective,
                blend: Blend::Opaque,
                test: cfg.depth_test,
                write: WRITE,
            },
            gouraud: shade::<C, D, WRITE, true, TW, TH>,
            flat: shade::<C, D, WRITE, false, TW, TH>,
            custom: shade_custom::<C, F, TW, TH>,
            flat_t: shade_custom::<C, shader::Flat, TW, TH>,
            gouraud_t: shade_custom::<C, shader::Gouraud, TW, TH>,
            shader,
        }
    }

    /// A pass through fragment shader `g` with its function `shade`.
    fn pass<'g, G: FragmentShader<C>>(
        &self,
        g: &'g G,
        shade: CustomFn<C, G, TW, TH>,
        blend: Blend,
    ) -> ShaderPass<'g, C, G, TW, TH> {
        let mut out = self.out;
        out.blend = blend;
        ShaderPass {
            shader: g,
            shade,
            raster: self.raster,
            out,
        }
    }
}

/// Everything the fragment-shader path needs to draw a triangle.
struct ShaderPass<'g, C, G: FragmentShader<C>, const TW: usize, const TH: usize> {
    shader: &'g G,
    shade: CustomFn<C, G, TW, TH>,
    raster: Rasterizer,
    out: Output,
}

impl<'g, C, G: FragmentShader<C>, const TW: usize, const TH: usize> ShaderPass<'g, C, G, TW, TH> {
    /// The pass with its output changed by `f`.
    fn with(mut self, f: impl FnOnce(Output) -> Output) -> Self {
        self.out = f(self.out);
        self
    }
}

/// The first phase of [`fill`] with the scanline rasterizer: records the
/// spans of triangle `v` in the tile `rect` in `found`, and returns how
/// many (the Hilbert rasterizer finds the same spans). Out of line, so that
/// the edge walk has the registers to itself.
#[inline(never)]
fn find_spans(v: &[SubPoint; 3], rect: &PixelRect, found: &mut [Span]) -> usize {
    // The walk stays inside `rect`, at most as many rows as `found` holds
    // (TH), so one call records every span.
    match Walker::new(v, *rect) {
        Some(mut walker) => walker.walk(found),
        None => 0,
    }
}

/// For [`Rasterizer::Auto`]: when triangle `v`'s bounds hold the whole
/// tile `rect` and the Hilbert rasterizer's block test finds every pixel
/// centre of the tile covered, records one full span per row and returns
/// how many; otherwise `None` (the scanline walk then finds the spans).
#[inline(never)]
fn whole_tile(v: &[SubPoint; 3], rect: &PixelRect, found: &mut [Span]) -> Option<usize> {
    let b = PixelRect::covering(v);
    let holds = b.x0 <= rect.x0 && b.y0 <= rect.y0 && b.x1 >= rect.x1 && b.y1 >= rect.y1;
    if !holds || !hilbert::covers_rect(v, rect) {
        return None;
    }
    let rows = (rect.y1 - rect.y0) as usize;
    for (r, s) in found[..rows].iter_mut().enumerate() {
        *s = Span {
            j: rect.y0 + r as i32,
            x0: rect.x0,
            x1: rect.x1,
        };
    }
    Some(rows)
}

/// The second phase of [`fill`]: sets up the attribute planes of the
/// triangle `sv` and shades its spans `found`. In a function of its own so
/// that its loops get the registers to themselves, and with the set-up
/// inlined so that the planes are computed where the span loop reads them.
#[inline(never)]
fn shade<C, D: DepthFn, const WRITE: bool, const GOURAUD: bool, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    sv: [&ScreenVertex; 3],
    flat: [u8; 3],
    found: &[Span],
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
{
    let corners = &Corners(sv);
    let setup = &TriangleSetup::new(corners, GOURAUD);
    let flat = C::from(Rgb888::new(flat[0], flat[1], flat[2]));
    let mut n = 0;
    for &Span { j, x0, x1 } in found {
        let row = (j - rect.y0) as usize;
        let (color, depth) = (&mut tile.color[row][..], &mut tile.depth[row][..]);
        let sp = SpanPos {
            ox: rect.x0,
            j,
            x0,
            x1,
        };
        n += if GOURAUD {
            span_gouraud::<C, D, WRITE>(setup, corners, color, depth, sp)
        } else {
            span_flat::<C, D, WRITE>(setup, corners, flat, color, depth, sp)
        };
    }
    n
}

/// The second phase of [`fill_shaded`]: the perspective set-up of the
/// triangle and its spans shaded through the fragment shader.
#[inline(never)]
fn shade_custom<C, F, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    tri: &ShaderTriangle<'_, F::Varyings>,
    found: &[Span],
    shader: &F,
    texture: Option<&Texture<'_>>,
    out: Output,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    F: FragmentShader<C>,
{
    let setup = &PerspectiveSetup::new(tri, out.mode == Perspective::Affine);
    let mut n = 0;
    for &Span { j, x0, x1 } in found {
        let row = (j - rect.y0) as usize;
        let (color, depth) = (&mut tile.color[row][..], &mut tile.depth[row][..]);
        let sp = SpanPos {
            ox: rect.x0,
            j,
            x0,
            x1,
        };
        n += span_shader::<C, F>(setup, &tri.corners, shader, texture, out, color, depth, sp);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bins against a plain list per tile: random appends into pools of
    /// every small size. A tile the pass still holds at the end must hold
    /// exactly its triangles, in order; the tiles given up are the last.
    #[test]
    fn bins_keep_every_held_tile_complete_and_in_order() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |m: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % m as u64) as usize
        };
        let mut gave_up = 0;
        for round in 0..3_000 {
            let tiles = 1 + next(12);
            let pool_len = 1 + next(if round % 2 == 0 { 40 } else { 400 });
            let mut pool = [0u16; 400];
            let (mut heads, mut tails) = ([0u16; 12], [0u16; 12]);
            let mut bins = Bins::new(
                &mut pool[..pool_len],
                &mut heads[..tiles],
                &mut tails[..tiles],
            );
            let mut expected: [heapless::Vec<u16, 256>; 12] = Default::default();
            for t in 0..next(200) as u16 {
                // A triangle touches one to four consecutive tiles, some
                // beyond the pass.
                let first = next(tiles + 2);
                for k in first..first + 1 + next(4) {
                    bins.push(k, t);
                    if let Some(e) = expected.get_mut(k).filter(|_| k < tiles) {
                        e.push(t).unwrap();
                    }
                }
            }
            let held = bins.tiles();
            gave_up += (held < tiles) as u32;
            for (k, e) in expected.iter().enumerate().take(held) {
                assert!(
                    bins.iter(k).map(|t| t as u16).eq(e.iter().copied()),
                    "round {round} tile {k}"
                );
            }
        }
        assert!(gave_up > 100, "the test should exhaust pools: {gave_up}");
    }
}
