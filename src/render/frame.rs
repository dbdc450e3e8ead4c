//! Tiles on demand: a frame is begun once (checks and the vertex stage),
//! then rendered one tile at a time, in visiting order, into tile buffers
//! the caller owns.
//!
//! Binning happens inside [`Frame::render_next`], one pass at a time: a
//! pass bins the longest run of tiles the workspace's pool holds, and its
//! tiles are then handed out one by one before the next pass is binned.
//! What a tile reads is the frame's state (`FrameState`: the draws, the
//! vertex buffer, the matrices), which never changes after
//! [`Renderer::begin`](super::Renderer::begin), and its own bin, which
//! does not change while the pass lasts: only a small cache of the last
//! draw's fixed-point set-up and the statistics are written. A second core
//! could therefore draw other tiles of the same pass from the same state.

use super::bin::{BinIter, Bins};
use super::binning::{bin_pass, Fate, Tally};
use super::cursor::{Scan, ScanState, TileList};
use super::dispatch::Shaders;
use super::state::{DrawOrder, FrameState, SetupCache};
use super::tile_loop::raster_tile;
use super::{vertex_stage, Config, Features, FrameStats, Profiler, RenderError, Stage, Workspace};
use crate::raster::PixelRect;
use crate::scene::Scene;
use crate::shade::{DLessEqual, DepthTest};
use crate::shader::ShaderSet;
use crate::sink::rectangle;
use crate::tile::{TileBuffer, TileGrid, TileOrder};
use crate::vertex::ScreenVertex;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::primitives::Rectangle;

/// Which tile of a binning pass [`Frame::render_picked`] draws next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pick {
    /// The next in visiting order.
    InOrder,
    /// A tile with an empty bin or one with triangles, whichever keeps
    /// the two kinds spread evenly over the pass: an empty one while the
    /// share of the pass's empty tiles drawn is at most the share of its
    /// other tiles drawn, so that the cheap tiles, which the wire takes
    /// longer to send than the core to draw, come between the dear ones
    /// all through the pass rather than at its start.
    Spread,
    /// The next with triangles if any is left, else the next.
    Dear,
}

/// A frame being rendered tile by tile: made by
/// [`Renderer::begin`](super::Renderer::begin), drawn by
/// [`render_next`](Self::render_next).
///
/// It borrows the workspace and the scene until it is dropped.
pub struct Frame<'a, C, F, const TW: usize, const TH: usize, P = super::All> {
    config: Config<C>,
    state: FrameState<'a>,
    shaders: &'a F,
    grid: TileGrid,
    bins: Bins<'a>,
    /// The current pass: its first tile (visiting position) and how many
    /// tiles it holds; the next tile with an empty bin (`cheap`) and the
    /// next with triangles (`dear`) not yet drawn (`len` when there is
    /// none), and how many of its tiles have been drawn. In visiting order
    /// the lower of the two comes next; `render_queued` may take a cheap
    /// tile ahead of a dear one, or the other way round (see
    /// [`Frame::render_picked`]).
    t0: usize,
    len: usize,
    cheap: usize,
    dear: usize,
    taken: usize,
    /// How many of the pass's tiles have an empty bin, counted when
    /// [`Pick::Spread`] first needs it (`usize::MAX` until then), and how
    /// many of those have been drawn.
    cheap_total: usize,
    cheap_taken: usize,
    /// The current pass is tile `t0` alone, whose bin overflowed the pool:
    /// it is drawn by scanning every triangle against it.
    rescan: bool,
    cache: SetupCache,
    stats: FrameStats,
    features: core::marker::PhantomData<P>,
}

impl<'a, C, F, const TW: usize, const TH: usize, P> Frame<'a, C, F, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    /// Begins a frame of `scene` with the settings `config`: what
    /// [`Renderer::begin`](super::Renderer::begin) does, without a
    /// renderer. A program that draws only into tile buffers of its own
    /// ([`render_double_buffered`](Self::render_double_buffered),
    /// [`render_queued`](Self::render_queued),
    /// [`render_async`](Self::render_async)) then holds no renderer, and
    /// no renderer's tile buffer (`TW x TH` pixels it would never use).
    ///
    /// Every error is found here, before any tile is drawn.
    pub fn begin<const V: usize, const B: usize, const T: usize>(
        config: Config<C>,
        ws: &'a mut Workspace<V, B, T>,
        scene: &'a Scene<'a, F>,
    ) -> Result<Self, RenderError> {
        Self::begin_profiled(config, ws, scene, &mut ())
    }

    /// [`begin`](Self::begin), telling `profiler` when the vertex stage
    /// starts.
    pub(super) fn begin_profiled<Q: Profiler, const V: usize, const B: usize, const T: usize>(
        config: Config<C>,
        ws: &'a mut Workspace<V, B, T>,
        scene: &'a Scene<'a, F>,
        profiler: &mut Q,
    ) -> Result<Self, RenderError> {
        let Workspace {
            vertices,
            bins,
            heads,
            tails,
        } = ws;
        let done = vertex_stage::run::<C, F, P, Q>(&config, scene, &mut vertices[..], profiler)?;
        Ok(Self::assemble(
            config,
            &vertices[..],
            bins,
            heads,
            tails,
            scene,
            done,
        ))
    }

    /// The frame [`begin_profiled`](Self::begin_profiled) returns, once the
    /// vertex stage is done. Out of line, so that its locals (the frame's
    /// state and sorted-draw tables, about 600 bytes) are not on the stack
    /// while the vertex stage runs, on the frame's deepest path.
    #[inline(never)]
    fn assemble(
        config: Config<C>,
        vertices: &'a [ScreenVertex],
        bins: &'a mut [u16],
        heads: &'a mut [u16],
        tails: &'a mut [u16],
        scene: &'a Scene<'a, F>,
        done: vertex_stage::Transformed,
    ) -> Self {
        let size = config.size;
        let grid =
            TileGrid::new(size.width, size.height, TW as u32, TH as u32).ordered(config.tile_order);
        // `run` refused the setting if P leaves sorting out.
        let order = match P::SORT && config.sort_draws {
            true => DrawOrder::new(&scene.camera.view, scene.draws),
            false => None,
        };
        let state = FrameState {
            order,
            draws: scene.draws,
            light: scene.light,
            lighting: scene.lighting,
            make_setup: vertex_stage::setup_fn::<P>(),
            eye: done.eye,
            vertices: &vertices[..done.vertices],
            view_proj: done.view_proj,
            viewport: done.viewport,
            cull: config.cull,
            // `frustum` also asks `P::CULL`, at compile time.
            cull_draws: config.frustum_cull,
            outside: done.outside,
            frame: PixelRect::new(0, 0, size.width as i32, size.height as i32),
        };
        Self {
            config,
            state,
            shaders: &scene.shaders,
            grid,
            bins: Bins::new(bins, heads, tails),
            t0: 0,
            len: 0,
            cheap: 0,
            dear: 0,
            taken: 0,
            cheap_total: usize::MAX,
            cheap_taken: 0,
            rescan: false,
            cache: SetupCache::empty(),
            stats: FrameStats {
                triangles_in: done.triangles as u32,
                vertices: done.transformed,
                vertex_slots: done.vertices as u32,
                ..FrameStats::default()
            },
            features: core::marker::PhantomData,
        }
    }

    /// Renders the next tile into `tile` and returns the part of the
    /// frame it covers (the tile's top-left `width x height` pixels hold
    /// it: see [`TileBuffer::view`]), or `None` when every tile has been
    /// rendered.
    pub fn render_next(&mut self, tile: &mut TileBuffer<C, TW, TH>) -> Option<Rectangle> {
        self.render_next_profiled(tile, &mut ())
    }

    /// [`render_next`](Self::render_next), telling `profiler` when
    /// binning and rasterization start.
    pub fn render_next_profiled<Q: Profiler>(
        &mut self,
        tile: &mut TileBuffer<C, TW, TH>,
        profiler: &mut Q,
    ) -> Option<Rectangle> {
        self.render_picked(tile, profiler, Pick::InOrder)
            .map(|(area, _)| area)
    }

    /// Renders a tile of the current binning pass (binning the next pass
    /// first if every tile of this one is drawn) into `tile`: the next in
    /// visiting order, or with `Pick::Cheap` the next whose bin is empty
    /// (a clear and nothing else) and with `Pick::Dear` the next with
    /// triangles, each falling back on the other kind when the pass has
    /// none left. Returns the tile's area and whether it was cheap, or
    /// `None` after the last tile.
    ///
    /// Every tile is drawn once whatever the picks: a pass's tiles are
    /// drawn before the next pass is binned, and the two kinds are taken
    /// in visiting order each. What a tile holds does not depend on the
    /// order (its bin, the frame's state and the clear), so neither do
    /// its pixels.
    pub(crate) fn render_picked<Q: Profiler>(
        &mut self,
        tile: &mut TileBuffer<C, TW, TH>,
        profiler: &mut Q,
        pick: Pick,
    ) -> Option<(Rectangle, bool)> {
        if self.taken == self.len {
            let t0 = self.t0 + self.len;
            if t0 >= self.grid.count() as usize {
                return None;
            }
            profiler.enter(Stage::Binning);
            self.bin(t0);
        }
        let cheap = match pick {
            Pick::InOrder => self.cheap < self.dear,
            Pick::Spread => self.spread(),
            Pick::Dear => self.dear == self.len,
        };
        let k = if cheap {
            let k = self.cheap;
            self.cheap = self.seek(k + 1, true);
            self.cheap_taken += 1;
            k
        } else {
            let k = self.dear;
            self.dear = self.seek(k + 1, false);
            k
        };
        self.taken += 1;
        let t = self.grid.tile_at((self.t0 + k) as u32);
        let rect = self.grid.rect(t);
        profiler.enter(Stage::Raster);
        let cfg = &self.config;
        // Rewrites only the rows drawn since the buffer's last clear (when
        // that was with the same colour and depth), whichever tile or
        // frame they belonged to.
        tile.clear(cfg.clear_color, cfg.clear_depth);
        let state = &self.state;
        let mut scan;
        if cheap {
            // An empty bin (the cheap stream holds only those): nothing to
            // draw, no tile loop (its cursor, its spans' array) at all.
            self.stats.tiles += 1;
            return Some((rectangle(&rect), true));
        }
        let bin = self.bins.iter(k);
        let list = if self.rescan {
            scan = ScanState::new(state);
            TileList {
                bin: BinIter::empty(),
                scan: Some(Scan {
                    frame: state,
                    rect,
                    next: 0,
                    state: &mut scan,
                }),
            }
        } else {
            TileList { bin, scan: None }
        };
        // LessEqual with writes, the default, has span loops of its own;
        // every other comparison shares one set (see `DepthFn`).
        let shader = self.shaders;
        let shaders = match (cfg.depth_test, cfg.depth_write) {
            (DepthTest::Never, _) => None,
            (DepthTest::LessEqual, true) => Some(Shaders::new::<DLessEqual, true, P>(cfg, shader)),
            // Refused by `begin`.
            _ if !P::DEPTH_TESTS => None,
            (_, true) => Some(Shaders::new::<DepthTest, true, P>(cfg, shader)),
            (_, false) => Some(Shaders::new::<DepthTest, false, P>(cfg, shader)),
        };
        let shaded = match shaders {
            Some(shaders) => {
                raster_tile::<C, F, P, TW, TH>(tile, &rect, state, &mut self.cache, list, shaders)
            }
            None => 0,
        };
        self.stats.pixels_shaded += shaded;
        self.stats.tiles += 1;
        Some((rectangle(&rect), false))
    }

    /// [`Pick::Spread`]'s choice: a cheap tile (an empty bin) if dear
    /// ones have been drawn in at least the share of the pass's cheap ones
    /// drawn, `cheap_taken / cheap_total <= dear_taken / dear_total`, or
    /// if no dear one is left.
    fn spread(&mut self) -> bool {
        if self.cheap == self.len || self.dear == self.len {
            return self.dear == self.len;
        }
        if self.cheap_total == usize::MAX {
            let empty = |k: &usize| !self.rescan && self.bins.is_empty(*k);
            self.cheap_total = (0..self.len).filter(empty).count();
        }
        let dear_taken = self.taken - self.cheap_taken;
        let dear_total = self.len - self.cheap_total;
        // In u64: a pass may hold more than 2^16 tiles.
        self.cheap_taken as u64 * dear_total as u64 <= dear_taken as u64 * self.cheap_total as u64
    }

    /// The first tile of the pass at or after position `k` whose bin is
    /// empty (`cheap`) or not (`!cheap`), or the pass's length if none
    /// is. A rescanned tile counts as dear.
    fn seek(&self, mut k: usize, cheap: bool) -> usize {
        while k < self.len && (!self.rescan && self.bins.is_empty(k)) != cheap {
            k += 1;
        }
        k
    }

    /// Bins the pass starting at tile `t0` (visiting position): the
    /// longest run of tiles the pool holds, or tile `t0` alone to be
    /// rescanned.
    fn bin(&mut self, t0: usize) {
        let n_tiles = self.grid.count() as usize;
        let first_pass = self.stats.bin_passes == 0;
        self.stats.bin_passes += 1;
        let mut tally = Tally::default();
        // Monomorphized per tile order, so the row-major loop keeps its
        // shape.
        let (state, grid, cache) = (&self.state, &self.grid, &mut self.cache);
        let hilbert = self.config.tile_order == TileOrder::Hilbert;
        self.bins.pass(n_tiles - t0, |bins| {
            if hilbert {
                bin_pass::<TW, TH, true, P>(state, grid, t0, bins, cache, &mut tally);
            } else {
                bin_pass::<TW, TH, false, P>(state, grid, t0, bins, cache, &mut tally);
            }
        });
        if first_pass {
            let s = &mut self.stats;
            s.rejected = tally.fates[Fate::Rejected as usize];
            s.culled = tally.fates[Fate::Culled as usize];
            s.drawn = tally.fates[Fate::Visible as usize];
            s.clipped = tally.clipped;
            s.draws_culled = tally.draws_culled;
            s.clusters_culled = tally.clusters_culled;
            s.tile_pairs = tally.pairs;
        }
        self.t0 = t0;
        self.rescan = self.bins.tiles() == 0;
        if self.rescan {
            // Tile t0 alone overflows the pool: scan every triangle
            // against it.
            self.stats.rescanned_tiles += 1;
            self.len = 1;
        } else {
            self.len = self.bins.tiles();
        }
        self.taken = 0;
        self.cheap_total = usize::MAX;
        self.cheap_taken = 0;
        self.cheap = self.seek(0, true);
        self.dear = self.seek(0, false);
        let s = &mut self.stats;
        s.peak_bin_entries = self.bins.peak() as u32;
        s.peak_tiles_per_pass = s.peak_tiles_per_pass.max(self.bins.tiles() as u32);
    }

    /// What the frame did so far: after the last tile, the whole frame.
    pub fn stats(&self) -> FrameStats {
        self.stats
    }

    /// The number of tiles of the frame.
    pub fn tile_count(&self) -> usize {
        self.grid.count() as usize
    }
}
