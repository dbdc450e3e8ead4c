//! The per-frame memory of the renderer: the vertex buffer and the bins.

use crate::vertex::ScreenVertex;

/// Most triangles one frame can hold: bins store `u16` indices.
pub const MAX_TRIANGLES: usize = 1 << 16;

/// The per-frame memory of the renderer, sized at compile time.
///
/// * `VERTICES`: capacity of the vertex buffer, 12 bytes each; at least the
///   total vertex count of all draws of a frame
///   ([`FrameStats::vertex_slots`](super::FrameStats::vertex_slots); for
///   an imported model, the importer's `*_VERTEX_COUNT` constants).
/// * `BIN_ENTRIES`: the bin pool, 2 bytes each (at most 65,535), used in
///   chunks of [`CHUNK`](super::CHUNK). A frame needs about its (triangle,
///   tile) pairs ([`FrameStats::tile_pairs`](super::FrameStats::tile_pairs))
///   x 8/7 for the chunks' links, plus half a chunk per tile; less still
///   renders correctly, in more passes.
/// * `TILES`: tiles binned per pass, 4 bytes each; the number of tiles of
///   the frame for a single pass.
///
/// To size one from a real frame, render it once with a generous
/// workspace (on the host) and read its [`FrameStats`](super::FrameStats):
/// `vertex_slots`, `peak_bin_entries` (with `bin_passes == 1`, a pool of
/// that many entries holds the frame in one pass) and
/// `peak_tiles_per_pass`, then leave a margin for the poses the animation
/// has not shown yet.
///
/// ```
/// use microraster::prelude::*;
/// use microraster::embedded_graphics::pixelcolor::BinaryColor;
/// use microraster::fixed::types::I16F16;
///
/// let p = |x: f32, y: f32| [I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO];
/// let positions = [p(-0.9, -0.9), p(0.9, -0.9), p(0.0, 0.9)];
/// let mesh = Mesh::new(&positions, &[[0u16, 1, 2]]).unwrap();
/// let draws = [Draw::new(&mesh)];
/// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
/// let mut renderer: Renderer<BinaryColor, 16, 16> =
///     Renderer::new(Config::new(Size::new(64, 64), BinaryColor::Off));
/// let mut generous: Workspace<64, 4096, 64> = Workspace::new();
/// let s = renderer.render(&mut generous, &scene, &mut NullSink).unwrap();
/// assert_eq!((s.vertex_slots, s.bin_passes, s.peak_tiles_per_pass), (3, 1, 16));
/// // So Workspace<3, { s.peak_bin_entries }, 16> holds this frame in one pass.
/// assert!(s.peak_bin_entries as usize <= 4096);
/// ```
///
/// It is large: put it in a `static` (for example with
/// `cortex_m::singleton!` or `static_cell`) on a microcontroller, or `Box`
/// it on a host.
#[derive(Clone, Debug)]
pub struct Workspace<const VERTICES: usize, const BIN_ENTRIES: usize, const TILES: usize> {
    pub(super) vertices: [ScreenVertex; VERTICES],
    pub(super) bins: [u16; BIN_ENTRIES],
    /// Per tile of the current pass: its first chunk.
    pub(super) heads: [u16; TILES],
    /// Per tile of the current pass: the slot its next entry goes to, or
    /// `u16::MAX` (`bin::EMPTY`: none).
    pub(super) tails: [u16; TILES],
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
            vertices: [ScreenVertex::new(0, 0, 0, 0, [0; 3]); V],
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
