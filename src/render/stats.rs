//! What a frame did ([`FrameStats`]) and where its time goes ([`Profiler`]).

/// What a frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Triangles submitted.
    pub triangles_in: u32,
    /// Triangles discarded as back- or front-facing, zero-area, or (filled
    /// ones) with no pixel centre between their vertices' columns or rows.
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
    /// Vertex slots of the workspace the frame used: every vertex of every
    /// draw, culled or not. `VERTICES` must be at least this.
    pub vertex_slots: u32,
    /// (Triangle, tile) pairs of the frame: the bin entries it needs,
    /// before the chunks' links and their unused slots. A triangle takes
    /// one for each tile its pixel bounds touch, whether or not it covers
    /// a pixel centre there (on the `demo` frame 363 of 2,597 pairs cover
    /// none).
    pub tile_pairs: u32,
    /// The most bin-pool slots one binning pass took (whole chunks of
    /// [`CHUNK`](super::CHUNK), links included). With `bin_passes == 1`, a
    /// `BIN_ENTRIES` of this many holds the frame in one pass.
    pub peak_bin_entries: u32,
    /// The most tiles one binning pass held: at most `TILES`, and the
    /// frame's tile count when a pass holds them all.
    pub peak_tiles_per_pass: u32,
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
             vertices={} vertex_slots={} tile_pairs={} peak_bin_entries={} \
             peak_tiles_per_pass={}",
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
            self.vertices,
            self.vertex_slots,
            self.tile_pairs,
            self.peak_bin_entries,
            self.peak_tiles_per_pass
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

/// Observes where a frame spends its time: [`Renderer::render_profiled`](super::Renderer::render_profiled)
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
