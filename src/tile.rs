//! The tile buffer: colour in the sink's pixel format plus 16-bit depth.
//!
//! A frame is rendered one `W x H` tile at a time into this buffer, which is
//! the only per-pixel memory the renderer owns: `W * H * (size_of::<C>() +
//! 2)` bytes, e.g. 4 KiB for 32 x 32 `Rgb565`, and a few bytes more that
//! record its last clear (and, where the colour plane's bytes are not a
//! multiple of 4, up to 3 that align the depth plane). Tiles at the right
//! and bottom of a frame whose size is not a multiple of the tile size use
//! only their top-left part.
//!
//! Clearing the buffer for the next tile rewrites only the rows written
//! since its last clear (when that was with the same colour and depth):
//! every writer of the buffer (the triangles' spans, per triangle and
//! tile; lines; points; [`TileBuffer::pack`]) records the rows it writes.

use crate::raster::hilbert::{cell_at_rank, rank_in_grid};
use crate::raster::PixelRect;
use embedded_graphics::primitives::Rectangle;

/// The order in which a frame's tiles are rendered and streamed.
///
/// Both orders give the same image: every tile gets the same triangles in
/// the same order. They differ in which tiles follow each other, which
/// matters to a cache: along the Hilbert curve consecutive tiles are
/// neighbours, so textures and meshes read from cached flash (the RP2040's
/// XIP cache, the ESP32-C3's) are reused before they are evicted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum TileOrder {
    /// Left to right, top to bottom (default).
    #[default]
    RowMajor,
    /// Along the Hilbert curve over the smallest power-of-two square of
    /// tiles holding the grid, skipping the cells outside it.
    Hilbert,
}

/// Colour and depth for one tile, sized at compile time.
///
/// Colour plane first, each plane word-aligned, so that the stores of the
/// clear between tiles are aligned words, two a `strd` on Thumb-2 cores.
#[derive(Clone, Debug)]
#[repr(C, align(4))]
pub struct TileBuffer<C, const W: usize, const H: usize> {
    pub(crate) color: [[C; W]; H],
    pub(crate) depth: WordAligned<[[u16; W]; H]>,
    /// What the buffer was last cleared with and which rows were written
    /// since, so that the next clear rewrites only those.
    cleared: Cleared<C>,
}

/// The last clear of a [`TileBuffer`]: every row outside `lo..hi` holds
/// `color` and `depth` in all its `W` pixels. Every writer of the buffer
/// widens `lo..hi` to the rows it writes (`lo >= hi`: none).
#[derive(Clone, Copy, Debug)]
struct Cleared<C> {
    color: C,
    depth: u16,
    lo: u16,
    hi: u16,
}

impl<C: Copy, const W: usize, const H: usize> TileBuffer<C, W, H> {
    const VALID: () = assert!(
        W > 0 && H > 0 && W <= 1024 && H <= 1024,
        "tile sides must be 1..=1024 pixels"
    );

    /// The depth plane of a new buffer. A constant of one repeated byte,
    /// so that the compiler fills the buffer's own plane in place (one
    /// memset): written as the expression `[[u16::MAX; W]; H]` in `new`,
    /// the plane was built in a temporary on the caller's stack and copied,
    /// `W * H * 2` bytes more peak stack wherever a renderer is built
    /// (2 KiB for 32 x 32 tiles).
    const FAR: [[u16; W]; H] = [[u16::MAX; W]; H];

    /// A tile buffer filled with `color` and the farthest depth.
    pub const fn new(color: C) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::VALID;
        Self {
            color: [[color; W]; H],
            depth: WordAligned(Self::FAR),
            cleared: Self::fresh(color),
        }
    }

    /// A tile buffer filled with `color` and the nearest depth, 0: every
    /// byte of it is zero when `color`'s are, so that a `static` holding
    /// one starts in RAM cleared at start-up (.bss), where one from
    /// [`new`](Self::new) (the farthest depth, all ones) is initial data
    /// kept in flash as well (.data). What it holds is never seen: the
    /// renderer clears each tile before it draws into it.
    ///
    /// ```
    /// use microraster::{sink::Rgb565Be, TileBuffer};
    ///
    /// static TILE: TileBuffer<Rgb565Be, 32, 32> = TileBuffer::new_nearest(Rgb565Be::new(0, 0, 0));
    /// assert_eq!(TILE.depth(0, 0), Some(0));
    /// ```
    pub const fn new_nearest(color: C) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::VALID;
        Self {
            color: [[color; W]; H],
            depth: WordAligned([[0; W]; H]),
            // Every row holds `color` and depth 0; `lo == hi == 0` (no row
            // written) keeps the record's bytes zero too.
            cleared: Cleared {
                color,
                depth: 0,
                lo: 0,
                hi: 0,
            },
        }
    }

    /// [`new`](Self::new) for a buffer built at run time (the renderer's
    /// own): the same buffer. Out of line, and the colour plane built one
    /// row a turn: the compiler unrolls `new`'s `[[color; W]; H]` into one
    /// store per word of the plane wherever it is inlined (1.6 KB of code
    /// for 32 x 32 `Rgb565`, at every site that builds a renderer in a
    /// speed build). The rows are built in this function's frame and
    /// copied, so that stack is given back before anything is drawn.
    #[inline(never)]
    pub(crate) fn new_at_run_time(color: C) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::VALID;
        Self {
            color: core::array::from_fn(|_| [color; W]),
            depth: WordAligned(Self::FAR),
            cleared: Self::fresh(color),
        }
    }

    /// The record of a buffer that holds `color` and the farthest depth
    /// everywhere, no row written since.
    const fn fresh(color: C) -> Cleared<C> {
        Cleared {
            color,
            depth: u16::MAX,
            lo: H as u16,
            hi: 0,
        }
    }

    /// The colour of tile-local pixel `(x, y)`.
    pub fn color(&self, x: usize, y: usize) -> Option<C> {
        self.color.get(y).and_then(|r| r.get(x)).copied()
    }

    /// The depth of tile-local pixel `(x, y)`.
    pub fn depth(&self, x: usize, y: usize) -> Option<u16> {
        self.depth.0.get(y).and_then(|r| r.get(x)).copied()
    }

    /// The finished pixels of the tile that covers `area` of the frame
    /// (as [`Frame::render_next`](crate::render::Frame::render_next)
    /// returns it): the buffer's top-left `area.size` pixels, clamped to
    /// the buffer.
    pub fn view(&self, area: &Rectangle) -> TileView<'_, C> {
        TileView {
            pixels: self.color.as_flattened(),
            stride: W,
            width: (area.size.width as usize).min(W),
            height: (area.size.height as usize).min(H),
        }
    }

    /// The finished pixels of the tile that covers `area`, moved together
    /// into one contiguous run, row-major: `width * height` pixels, for a
    /// DMA channel that reads one block.
    ///
    /// A tile lies in the buffer's top-left `area.size` pixels with the
    /// buffer's row stride `W`, so a tile as wide as the buffer (every
    /// tile but those on the right edge of a frame whose width is not a
    /// multiple of `W`) is contiguous already and nothing moves. A
    /// narrower one has its rows moved left in place, one `copy_within`
    /// per row, after which the buffer no longer holds the tile in its
    /// usual layout: call this once per drawn tile, after it is drawn and
    /// instead of [`view`](Self::view) (the next
    /// [`render_next`](crate::render::Frame::render_next) into this
    /// buffer clears it and lays the next tile out again).
    ///
    /// ```
    /// use microraster::embedded_graphics::pixelcolor::{Rgb565, RgbColor};
    /// use microraster::{prelude::*, TileBuffer};
    ///
    /// let draws = [];
    /// let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    /// // A 24-pixel-wide frame of 16x16 tiles: the second tile is 8 wide.
    /// let renderer: Renderer<Rgb565, 16, 16> =
    ///     Renderer::new(Config::new(Size::new(24, 16), Rgb565::BLUE));
    /// let mut ws: Workspace<4, 64, 4> = Workspace::new();
    /// let mut tile = TileBuffer::new(Rgb565::BLACK);
    /// let mut frame = renderer.begin(&mut ws, &scene).unwrap();
    /// frame.render_next(&mut tile).unwrap();
    /// let area = frame.render_next(&mut tile).unwrap();
    /// assert_eq!(area.size, Size::new(8, 16));
    /// assert_eq!(tile.view(&area).contiguous(), None); // rows 16 pixels apart
    /// let expected: Vec<Rgb565> = tile.view(&area).pixels().collect();
    /// assert_eq!(tile.pack(&area), &expected[..]); // 8 x 16 pixels in a row
    /// ```
    pub fn pack(&mut self, area: &Rectangle) -> &[C] {
        let width = (area.size.width as usize).min(W);
        let height = (area.size.height as usize).min(H);
        if width < W && height > 1 {
            self.written(0, height - 1);
        }
        let pixels = self.color.as_flattened_mut();
        if width < W {
            // Row 0 is in place; each later row moves left, onto pixels
            // that are either already moved or the row's own.
            for row in 1..height {
                pixels.copy_within(row * W..row * W + width, row * width);
            }
        }
        &pixels[..width * height]
    }
}

impl<C, const W: usize, const H: usize> TileBuffer<C, W, H> {
    /// Records that rows `first..=last` (tile-local, `last < H`) may be
    /// written: the next [`clear`](Self::clear) rewrites them.
    #[inline(always)]
    pub(crate) fn written(&mut self, first: usize, last: usize) {
        let c = &mut self.cleared;
        // Both are below H <= 1024.
        c.lo = c.lo.min(first as u16);
        c.hi = c.hi.max(last as u16 + 1);
    }
}

impl<C: Copy + PartialEq, const W: usize, const H: usize> TileBuffer<C, W, H> {
    /// Fills the whole buffer with `color` and `depth`: rewrites only the
    /// rows written since the last clear when that was with the same
    /// values, every row otherwise.
    pub(crate) fn clear(&mut self, color: C, depth: u16) {
        let c = self.cleared;
        let (lo, hi) = match c.color == color && c.depth == depth {
            true => (c.lo as usize, c.hi as usize),
            false => (0, H),
        };
        let record = Cleared {
            color,
            depth,
            lo: H as u16,
            hi: 0,
        };
        if PAIR_FILL {
            // The record first: its values then need no register across
            // the fill (Cortex-M3 `demo` -300 instructions).
            self.cleared = record;
            self.fill_rows_by_pairs(lo, hi, color, depth);
        } else {
            // Whole rows: one fill over the rows' contiguous storage,
            // rather than a fill per row. None when no row was written
            // (lo >= hi).
            if let Some(rows) = self.color.get_mut(lo..hi) {
                fill(rows.as_flattened_mut(), color);
            }
            if let Some(rows) = self.depth.0.get_mut(lo..hi) {
                fill(rows.as_flattened_mut(), depth);
            }
            self.cleared = record;
        }
    }

    /// Rows `lo..hi` of both planes filled with `color` and `depth` on
    /// Thumb-2 cores ([`PAIR_FILL`]; built on the host for its tests too),
    /// a pair of values a word store, a row of each plane a turn:
    ///
    /// * LLVM does not merge two `strh` of a run-time value into one `str`,
    ///   but copies a pair read from memory it cannot see into
    ///   (`black_box`) as one word;
    /// * stores at constant offsets from a row's start, which LLVM knows
    ///   word-aligned, pair into `strd` (the same word twice), where the
    ///   planes' fill over their contiguous rows had taken `str` each,
    ///   its first with the pointer's write-back;
    /// * the depth plane's rows through a reference that LLVM cannot tie
    ///   to the colour plane's (`black_box`; word-aligned as a
    ///   [`WordAligned`]): tied, their 2 KiB apart (32 x 32 tiles) are folded
    ///   into offsets beyond `strd`'s reach, and the depth plane takes
    ///   `str` each;
    /// * the pair values copied out of the `black_box`'s memory once,
    ///   before the rows, into values of their own: read from that memory
    ///   at each row (as `fill_row`'s arguments), they were loaded from
    ///   the stack twice a row, since the escaped depth plane's stores
    ///   might alias it (Cortex-M3 `demo` -1,340 instructions, M4F -590);
    /// * one `black_box` for the two pairs and the depth plane: one stack
    ///   address made for the three, and the pairs loaded by one `ldrd`
    ///   (-288 on both).
    ///
    /// 16 `strd` a row of both planes where 32 `str` were: Cortex-M3
    /// `demo` 2,917,195 -> 2,904,369 instructions.
    #[inline(always)]
    fn fill_rows_by_pairs(&mut self, lo: usize, hi: usize, color: C, depth: u16) {
        let (pc, pd, depth_plane) =
            core::hint::black_box((Pair([color; 2]), Pair([depth; 2]), &mut self.depth));
        // Out of the `black_box`'s memory here, once (see above).
        let (pc, pd): ([C; 2], [u16; 2]) = (pc.0, pd.0);
        // Back first when there is no row, or rows past the planes' (never:
        // every writer records rows below H). The rows' index checks below
        // then fold away, and the row loop takes its remainder rows before
        // its turns unrolled by four, which step two pointers and a count:
        // 6 instructions a turn, where the planes' zipped
        // `get_mut(lo..hi)` took 7 and tested each slice apart (Cortex-M3
        // and M4F `demo` -64 for the early return, -309 for the rows by
        // index).
        if lo >= hi || hi > H {
            return;
        }
        for r in lo..hi {
            fill_row(&mut self.color[r], pc);
            fill_row(&mut depth_plane.0[r], pd);
        }
    }
}

/// `slice.fill(value)`, 32 values a turn: stores with constant offsets, one
/// loop test per 32 (`fill` tests every 4 on the Cortex-M3).
#[inline(always)]
fn fill<T: Copy>(slice: &mut [T], value: T) {
    let (chunks, rest) = slice.as_chunks_mut::<32>();
    for c in chunks {
        *c = [value; 32];
    }
    rest.fill(value);
}

/// One plane of a [`TileBuffer`], word-aligned wherever it lies (the
/// depth plane after a colour plane of an odd number of bytes too), so
/// that a reference to it tells LLVM so ([`TileBuffer::fill_rows_by_pairs`]).
#[derive(Clone, Debug, PartialEq, Eq)]
#[repr(C, align(4))]
pub(crate) struct WordAligned<T>(pub(crate) T);

/// Whether the clear fills its rows by pairs ([`TileBuffer::fill_rows_by_pairs`]):
/// on Thumb-2 cores (ARMv7-M, ARMv7E-M, ARMv8-M Mainline). Not on ARMv6-M
/// and ARMv8-M Baseline (`microraster_narrow_multiply`: no unaligned
/// stores nor `strd`, a pair still two `strh`) nor x86 (its splat fill is
/// vector stores already).
const PAIR_FILL: bool = cfg!(all(target_arch = "arm", not(microraster_narrow_multiply)));

/// `row` filled with `pair`, a pair a copy, and an odd last value.
#[inline(always)]
fn fill_row<T: Copy>(row: &mut [T], pair: [T; 2]) {
    let (pairs, rest) = row.as_chunks_mut::<2>();
    for p in pairs {
        *p = pair;
    }
    rest.fill(pair[0]);
}

/// Two values side by side, word-aligned: copied as one unit.
#[repr(C, align(4))]
#[derive(Clone, Copy)]
struct Pair<T>([T; 2]);

/// The finished pixels of one tile, row-major, as handed to a sink.
#[derive(Clone, Copy, Debug)]
pub struct TileView<'a, C> {
    pixels: &'a [C],
    stride: usize,
    width: usize,
    height: usize,
}

impl<'a, C: Copy> TileView<'a, C> {
    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The rows, each `width` pixels long, top to bottom.
    pub fn rows(&self) -> impl Iterator<Item = &'a [C]> + 'a {
        let (stride, width) = (self.stride, self.width);
        self.pixels
            .chunks(stride)
            .take(self.height)
            .map(move |r| &r[..width])
    }

    /// Every pixel, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = C> + 'a {
        self.rows().flat_map(|r| r.iter().copied())
    }

    /// Every pixel, row by row, as one slice when the rows follow each
    /// other in memory: when the tile is as wide as its buffer, is one row
    /// high, or was packed ([`TileBuffer::pack`]; the views that
    /// [`render_async`](crate::Renderer::render_async) hands to an
    /// [`AsyncTileSink`](crate::sink::AsyncTileSink) always are). `None`
    /// for a tile narrower than its buffer: its rows are `width` pixels
    /// `W` apart, and [`rows`](Self::rows) gives them one by one.
    pub fn contiguous(&self) -> Option<&'a [C]> {
        let len = self.width * self.height;
        match self.width == self.stride || self.height <= 1 {
            true => self.pixels.get(..len),
            false => None,
        }
    }

    /// A view of `width x height` pixels that follow each other in
    /// `pixels`, as [`TileBuffer::pack`] leaves them.
    pub(crate) fn packed(pixels: &'a [C], width: usize, height: usize) -> Self {
        Self {
            pixels,
            stride: width.max(1),
            width,
            height,
        }
    }
}

/// The layout of a frame in tiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileGrid {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Tile width.
    pub tile_w: u32,
    /// Tile height.
    pub tile_h: u32,
    /// Tiles per row.
    pub cols: u32,
    /// Tile rows.
    pub rows: u32,
    /// The order tiles are visited in.
    pub order: TileOrder,
}

impl TileGrid {
    /// The grid of `tile_w x tile_h` tiles covering a `width x height` frame.
    pub fn new(width: u32, height: u32, tile_w: u32, tile_h: u32) -> Self {
        Self {
            width,
            height,
            tile_w,
            tile_h,
            cols: width.div_ceil(tile_w),
            rows: height.div_ceil(tile_h),
            order: TileOrder::RowMajor,
        }
    }

    /// The same grid, visited in `order`.
    pub fn ordered(mut self, order: TileOrder) -> Self {
        self.order = order;
        self
    }

    /// The row-major index of the tile visited `position`-th
    /// (`position < count()`).
    ///
    /// ```
    /// use microraster::tile::{TileGrid, TileOrder};
    /// let grid = TileGrid::new(96, 64, 32, 32).ordered(TileOrder::Hilbert);
    /// // 3 x 2 tiles: right, down, left, then the third column upwards.
    /// let visits: Vec<u32> = (0..grid.count()).map(|p| grid.tile_at(p)).collect();
    /// assert_eq!(visits, [0, 1, 4, 3, 5, 2]);
    /// ```
    #[inline]
    pub fn tile_at(&self, position: u32) -> u32 {
        match self.order {
            TileOrder::RowMajor => position,
            TileOrder::Hilbert => {
                let (x, y) = cell_at_rank(self.cols, self.rows, position);
                y * self.cols + x
            }
        }
    }

    /// When the tile at column `col` and row `row` is visited: the inverse
    /// of [`tile_at`](Self::tile_at).
    #[inline]
    pub fn position(&self, col: u32, row: u32) -> u32 {
        match self.order {
            TileOrder::RowMajor => row * self.cols + col,
            TileOrder::Hilbert => rank_in_grid(self.cols, self.rows, col, row),
        }
    }

    /// Number of tiles.
    pub fn count(&self) -> u32 {
        self.cols * self.rows
    }

    /// The pixels of tile `t` (row-major index), clipped to the frame.
    pub fn rect(&self, t: u32) -> PixelRect {
        let (tx, ty) = (t % self.cols, t / self.cols);
        let x0 = tx * self.tile_w;
        let y0 = ty * self.tile_h;
        PixelRect::new(
            x0 as i32,
            y0 as i32,
            (x0 + self.tile_w).min(self.width) as i32,
            (y0 + self.tile_h).min(self.height) as i32,
        )
    }

    /// The range of tile columns and rows (`[c0, c1) x [r0, r1)`) that a
    /// pixel rectangle inside the frame touches; `None` when it is empty.
    pub fn span(&self, r: &PixelRect) -> Option<(u32, u32, u32, u32)> {
        let frame = PixelRect::new(0, 0, self.width as i32, self.height as i32);
        let r = r.intersect(&frame);
        if r.is_empty() {
            return None;
        }
        Some((
            r.x0 as u32 / self.tile_w,
            (r.x1 as u32 - 1) / self.tile_w + 1,
            r.y0 as u32 / self.tile_h,
            (r.y1 as u32 - 1) / self.tile_h + 1,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Thumb-2 clear's fill by pairs ([`TileBuffer::fill_rows_by_pairs`],
    /// which the host's clear does not take) writes every value of rows
    /// `lo..hi` of both planes, and only those, for even and odd widths,
    /// one- and two-byte colours, and any rows (`lo >= hi`: none).
    #[test]
    fn fill_by_pairs_writes_exactly_the_rows() {
        fn check<C: Copy + PartialEq + core::fmt::Debug, const W: usize, const H: usize>(
            old: C,
            new: C,
        ) {
            for lo in 0..=H + 1 {
                for hi in 0..=H + 1 {
                    let mut t = TileBuffer::<C, W, H>::new(old);
                    t.fill_rows_by_pairs(lo, hi, new, 77);
                    for y in 0..H {
                        let inside = lo < hi && hi <= H && (lo..hi).contains(&y);
                        for x in 0..W {
                            assert_eq!(
                                t.color[y][x],
                                if inside { new } else { old },
                                "{lo} {hi} {x} {y}"
                            );
                            let d = if inside { 77 } else { u16::MAX };
                            assert_eq!(t.depth.0[y][x], d, "{lo} {hi} {x} {y}");
                        }
                    }
                }
            }
        }
        check::<u16, 32, 4>(1, 0xBEEF);
        // Rows before, in and after the loop's unrolled turns of four.
        check::<u16, 32, 11>(1, 0xBEEF);
        check::<u16, 7, 5>(1, 0xBEEF);
        check::<u8, 5, 3>(1, 0xEE);
        check::<u8, 6, 1>(1, 0xEE);
    }

    /// A clear after drawing leaves every pixel of both planes at the
    /// clear's values, whichever fill the target takes.
    #[test]
    fn clear_rewrites_the_written_rows() {
        let mut t = TileBuffer::<u16, 6, 5>::new(1);
        t.color[2][3] = 9;
        t.depth.0[3][0] = 4;
        t.written(2, 3);
        t.clear(1, u16::MAX);
        assert!(t.color.as_flattened().iter().all(|&c| c == 1));
        assert!(t.depth.0.as_flattened().iter().all(|&d| d == u16::MAX));
        t.clear(5, 100);
        assert!(t.color.as_flattened().iter().all(|&c| c == 5));
        assert!(t.depth.0.as_flattened().iter().all(|&d| d == 100));
    }
}
