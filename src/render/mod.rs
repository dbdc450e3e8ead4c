//! The frame loop: vertex stage once, then bin, rasterize, shade and stream
//! tile by tile.
//!
//! # The path of a frame, file by file
//!
//! * [`Renderer::begin`] (`frame`) checks the scene and runs the vertex
//!   stage (`vertex_stage`): every vertex transformed, lit and projected
//!   once into the [`Workspace`] (`workspace`); `state` holds what
//!   the rest of the frame reads and never changes, and classifies
//!   triangles (`clipped` for those that must be clipped).
//! * [`Frame::render_next`] bins a run of tiles when it needs one
//!   (`binning`, into the `bin` pool) and renders the next tile into
//!   a tile buffer the caller owns: the tile loop (`tile_loop`) walks
//!   the tile's triangles (`cursor`) and draws each one (`fill`:
//!   spans found, then shaded by the span loop `dispatch` chose for the
//!   frame's configuration).
//! * [`Renderer::render`] is that loop, handing each tile to a
//!   [`TileSink`]. [`FrameStats`] and the [`Profiler`]
//!   (`stats`) say what a frame did and where its time went; errors are
//!   [`RenderError`] (`error`).
//!
//! # How triangles reach their tiles
//!
//! The vertex stage writes one 12-byte [`ScreenVertex`](crate::vertex::ScreenVertex) per mesh vertex
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
//!    the vertex buffer, set up and rasterized, and the tile is handed out.
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

mod bin;
mod binning;
mod clipped;
mod config;
mod cursor;
mod dispatch;
mod error;
mod features;
mod fill;
mod find;
mod frame;
mod state;
mod stats;
mod tile_loop;
mod vertex_stage;
mod workspace;

pub use crate::vertex::MAX_LIGHTS;
pub use bin::CHUNK;
pub use config::Config;
pub use error::RenderError;
pub use features::{All, Features, GouraudTriangles, Path, Triangles};
pub use frame::Frame;
pub(crate) use frame::Pick;
pub use state::MAX_SORTED_DRAWS;
pub use stats::{FrameStats, Profiler, Stage};
pub use tile_loop::MAX_TRANSPARENT;
pub use workspace::{Workspace, MAX_TRIANGLES};

use crate::scene::Scene;
use crate::shader::ShaderSet;
use crate::sink::TileSink;
use crate::tile::TileBuffer;
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};

/// The tiled renderer: a tile buffer of `TW x TH` pixels of colour `C`
/// plus its settings, linking the optional paths of `P` ([`All`] unless
/// named; see [`Features`]).
///
/// `C` is any embedded-graphics colour type that converts from and to
/// `Rgb888`, and is `'static` (every colour type is: it holds no
/// reference): the span loops convert their colours to `Rgb565` (and the
/// crate's [`Rgb565Be`](crate::sink::Rgb565Be)) by tables rather than
/// embedded-graphics' arithmetic, bit for bit the same, and pick that path
/// by comparing `C`'s `TypeId`, which needs `'static`.
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
pub struct Renderer<C, const TW: usize, const TH: usize, P = All> {
    tile: TileBuffer<C, TW, TH>,
    config: Config<C>,
    features: core::marker::PhantomData<P>,
}

impl<C, const TW: usize, const TH: usize, P> Renderer<C, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888>,
    P: Features,
{
    /// A renderer with the given settings.
    pub fn new(config: Config<C>) -> Self {
        Self {
            tile: TileBuffer::new_at_run_time(config.clear_color),
            config,
            features: core::marker::PhantomData,
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

    /// The tile buffer, holding the last tile [`render`](Self::render)
    /// drew.
    pub fn tile(&self) -> &TileBuffer<C, TW, TH> {
        &self.tile
    }
}

/// Drawing: `C` must be `'static` here (see [`Renderer`]).
impl<C, const TW: usize, const TH: usize, P> Renderer<C, TW, TH, P>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    P: Features,
{
    /// Renders `scene` tile by tile into `sink`.
    ///
    /// Every error but [`RenderError::Sink`] is detected before anything is
    /// sent to the sink.
    ///
    /// The renderer is monomorphized for each of the scene's fragment
    /// shaders `F` (a [`ShaderSet`]: [`NoShader`](crate::shader::NoShader)
    /// unless [`Scene::shader`] or [`Scene::shaders`] set them).
    pub fn render<S, F, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_, F>,
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
        F: ShaderSet<C>,
    {
        self.render_profiled(ws, scene, sink, &mut ())
    }

    /// [`render`](Self::render), telling `profiler` when each [`Stage`]
    /// starts.
    pub fn render_profiled<S, Q, F, const V: usize, const B: usize, const T: usize>(
        &mut self,
        ws: &mut Workspace<V, B, T>,
        scene: &Scene<'_, F>,
        sink: &mut S,
        profiler: &mut Q,
    ) -> Result<FrameStats, RenderError<S::Error>>
    where
        S: TileSink<C>,
        Q: Profiler,
        F: ShaderSet<C>,
    {
        // The frame is used where `begin_profiled` returned it, inside its
        // `Result`: moving it out would take a second copy of its 1.3 KB
        // (the sorted-draw tables, the set-up cache) on this stack.
        let mut begun = Frame::<C, F, TW, TH, P>::begin_profiled(self.config, ws, scene, profiler);
        let frame = match &mut begun {
            Ok(frame) => frame,
            Err(e) => return Err(e.for_sink()),
        };
        while let Some(area) = frame.render_next_profiled(&mut self.tile, profiler) {
            profiler.enter(Stage::Sink);
            sink.write_tile(&area, &self.tile.view(&area))
                .map_err(RenderError::Sink)?;
        }
        profiler.enter(Stage::Done);
        Ok(frame.stats())
    }

    /// Begins a frame of `scene`: checks it and runs the vertex stage, then
    /// hands out its tiles one at a time, in visiting order, through
    /// [`Frame::render_next`], into tile buffers the caller owns. That is
    /// what [`render`](Self::render) does with the renderer's own tile
    /// buffer; a caller holding two buffers can draw one tile while the
    /// other is still on its way to the display.
    ///
    /// Every error is found here, before any tile is drawn.
    ///
    /// ```
    /// use microraster::prelude::*;
    /// use microraster::TileBuffer;
    /// use embedded_graphics::pixelcolor::{Gray8, GrayColor};
    /// use fixed::types::I16F16;
    ///
    /// let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
    /// let positions = [p(-0.5, -0.5), p(0.5, -0.5), p(0.0, 0.5)];
    /// let mesh = Mesh::new(&positions, &[[0u16, 1, 2]]).unwrap();
    /// let draws = [Draw::new(&mesh)];
    /// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    /// let renderer: Renderer<Gray8, 16, 16> =
    ///     Renderer::new(Config::new(Size::new(32, 32), Gray8::BLACK));
    /// let mut ws: Workspace<4, 64, 4> = Workspace::new();
    ///
    /// // Two tile buffers, used in turn.
    /// let mut tiles = [TileBuffer::new(Gray8::BLACK), TileBuffer::new(Gray8::BLACK)];
    /// let mut frame = renderer.begin(&mut ws, &scene).unwrap();
    /// let mut k = 0;
    /// while let Some(area) = frame.render_next(&mut tiles[k % 2]) {
    ///     let view = tiles[k % 2].view(&area);
    ///     assert_eq!(view.width(), 16);
    ///     k += 1;
    /// }
    /// assert_eq!(k, 4);
    /// assert_eq!(frame.stats().drawn, 1);
    /// ```
    pub fn begin<'a, F, const V: usize, const B: usize, const T: usize>(
        &self,
        ws: &'a mut Workspace<V, B, T>,
        scene: &'a Scene<'a, F>,
    ) -> Result<Frame<'a, C, F, TW, TH, P>, RenderError>
    where
        F: ShaderSet<C>,
    {
        Frame::begin(self.config, ws, scene)
    }
}
