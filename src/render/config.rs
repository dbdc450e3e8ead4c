//! Renderer settings.

use crate::raster::Rasterizer;
use crate::scene::CullMode;
use crate::shade::DepthTest;
use crate::shader::Perspective;
use crate::tile::TileOrder;
use embedded_graphics::prelude::Size;

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
    /// be a [`RenderError::Draw`](super::RenderError::Draw).
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
    /// it. Frames with more than [`MAX_SORTED_DRAWS`](super::MAX_SORTED_DRAWS) draws are not sorted.
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
