//! Coverage: which pixel centres a screen-space triangle covers.
//!
//! Screen positions are integers in units of `1 / SUBPIXEL` pixel (28.4 for
//! the default 4 sub-pixel bits). Pixel `(i, j)` has its centre at
//! `(16 i + 8, 16 j + 8)` in these units. A centre strictly inside the
//! triangle is covered; a centre exactly on an edge is covered only when that
//! edge is a *top* edge (horizontal, with the triangle below it) or a *left*
//! edge (the triangle lies to its right). Two triangles sharing an edge
//! therefore never both cover a pixel and never both miss one.
//!
//! [`scanline`] is the edge-walking rasterizer, [`hilbert`] the Hilbert-order
//! hierarchical one ([`Rasterizer`] selects). Both produce exactly this
//! coverage; the tests check it against an independent edge-function
//! reference and against each other.

pub mod hilbert;
pub mod line;
pub mod scanline;

/// Which rasterizer finds the pixels a triangle covers.
///
/// Both give exactly the same coverage (the tests prove it on random
/// triangles and meshes), and shading is shared, so every choice renders
/// the same image; they differ only in speed. BENCHMARKS.md has the
/// measurements behind [`Rasterizer::Auto`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Rasterizer {
    /// The edge-walking [`scanline`] rasterizer (default).
    #[default]
    Scanline,
    /// The Hilbert-order hierarchical edge-equation rasterizer
    /// ([`hilbert`]).
    Hilbert,
    /// Per triangle and tile: a triangle whose bounds hold the whole tile
    /// gets the Hilbert rasterizer's block test on the tile as one block,
    /// and a tile wholly inside it is filled with no edge walk; everything
    /// else takes the scanline walk. Measured faster on scenes of big,
    /// screen-filling triangles, slightly slower on small ones.
    Auto,
}

/// Sub-pixel precision of screen coordinates, in bits.
pub const SUBPIXEL_BITS: u32 = 4;
/// Sub-pixel steps per pixel.
pub const SUBPIXEL: i32 = 1 << SUBPIXEL_BITS;
/// Offset of a pixel centre from the pixel's top-left corner, in sub-pixels.
pub const HALF_PIXEL: i32 = SUBPIXEL / 2;

/// A screen position in sub-pixel units (x right, y down).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct SubPoint {
    /// x in `1 / SUBPIXEL` px.
    pub x: i32,
    /// y in `1 / SUBPIXEL` px.
    pub y: i32,
}

impl SubPoint {
    /// Creates a point from sub-pixel coordinates.
    pub const fn new(x: i32, y: i32) -> Self {
        Self { x, y }
    }
}

/// A run of covered pixels: row `j`, columns `x0..x1`, as both
/// rasterizers record them for shading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Span {
    pub j: i32,
    pub x0: i32,
    pub x1: i32,
}

/// A half-open rectangle of whole pixels: columns `x0..x1`, rows `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct PixelRect {
    /// First column.
    pub x0: i32,
    /// First row.
    pub y0: i32,
    /// One past the last column.
    pub x1: i32,
    /// One past the last row.
    pub y1: i32,
}

impl PixelRect {
    /// Creates a rectangle; an inverted one is simply empty.
    pub const fn new(x0: i32, y0: i32, x1: i32, y1: i32) -> Self {
        Self { x0, y0, x1, y1 }
    }

    /// Whether the rectangle holds no pixel.
    pub const fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    /// The overlap of two rectangles (possibly empty).
    pub fn intersect(&self, o: &Self) -> Self {
        Self::new(
            self.x0.max(o.x0),
            self.y0.max(o.y0),
            self.x1.min(o.x1),
            self.y1.min(o.y1),
        )
    }

    /// The pixels whose centres may be covered by a triangle with these
    /// vertices: a conservative box, exact on the pixel-centre grid.
    pub fn covering(v: &[SubPoint; 3]) -> Self {
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (v[0].x, v[0].x, v[0].y, v[0].y);
        for p in &v[1..] {
            xmin = xmin.min(p.x);
            xmax = xmax.max(p.x);
            ymin = ymin.min(p.y);
            ymax = ymax.max(p.y);
        }
        Self::new(
            first_centre_at_or_after(xmin),
            first_centre_at_or_after(ymin),
            first_centre_at_or_after(xmax) + 1,
            first_centre_at_or_after(ymax) + 1,
        )
    }
}

/// The index of the first pixel whose centre is at or after sub-pixel `v`:
/// `ceil((v - HALF_PIXEL) / SUBPIXEL)`.
#[inline]
pub const fn first_centre_at_or_after(v: i32) -> i32 {
    // Arithmetic shift floors; ceil(a / 2^k) = -floor(-a / 2^k).
    -((HALF_PIXEL - v) >> SUBPIXEL_BITS)
}

/// Twice the signed area of a screen triangle, in sub-pixels squared.
///
/// Negative means counter-clockwise in normalised device coordinates (y up),
/// i.e. clockwise on the y-down screen: the front face by default.
#[inline]
pub fn signed_area2(v: &[SubPoint; 3]) -> i64 {
    (v[1].x as i64 - v[0].x as i64) * (v[2].y as i64 - v[0].y as i64)
        - (v[2].x as i64 - v[0].x as i64) * (v[1].y as i64 - v[0].y as i64)
}

/// [`signed_area2`] of a triangle within the guard band (coordinates
/// within ±2^18 sub-pixels, as the vertex stage gives them): the edge
/// vectors fit `i32`, so each product is `i32 x i32`
/// ([`crate::math::mul_wide`], which avoids a 64-bit library multiply on
/// ARMv6-M). The same value. 64-bit targets keep [`signed_area2`]'s
/// `i64` differences, which measured faster there (1.4 % of the x86
/// `demo` frame); 32-bit ones gain (1.7 % on the Cortex-M3, 8 % on ARMv6-M
/// with the vertex stage's products).
#[inline(always)]
pub(crate) fn signed_area2_banded(v: &[SubPoint; 3]) -> i64 {
    if cfg!(target_pointer_width = "64") {
        return signed_area2(v);
    }
    let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
    let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
    crate::math::mul_wide(x1, y2) - crate::math::mul_wide(x2, y1)
}
