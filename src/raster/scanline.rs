//! The scanline (edge-walking) rasterizer.
//!
//! This follows Chris Hecker's *Perspective Texture Mapping* articles (Game
//! Developer, 1995–96): sort the vertices by y, split the triangle at the
//! middle vertex, and walk the long edge and the two short edges one pixel
//! row at a time. Every edge is *pre-stepped* to the first pixel-centre row
//! it covers, and every span starts at the first pixel centre at or right of
//! the left edge, so sub-pixel vertex positions are honoured exactly.
//!
//! Hecker walks x with a 16.16 slope, which accumulates rounding error. Here
//! the slope is split, as in his `FloorDivMod` stepper, into an integer
//! column step and an exact remainder with the edge's own denominator, so
//! the column where each span starts and ends is the exact
//! `ceil((x_edge(y_c) - ½) )` of the rational edge position. That makes the
//! coverage identical to an exact edge-function test with the top-left rule
//! (see [`crate::raster`]):
//!
//! * rows: a centre row `y_c` is inside when `y_top <= y_c < y_bottom`, so a
//!   horizontal top edge is drawn and a horizontal bottom edge is not;
//! * columns: a span is `[ceil(x_left - ½), ceil(x_right - ½))`, so a centre
//!   on a left edge is drawn and one on a right edge is not.
//!
//! Set-up needs `i64` products (screen coordinates within the guard band
//! reach ±2^18 sub-pixels); the per-row stepping is `i32` adds and one
//! compare per edge.

use super::{first_centre_at_or_after, PixelRect, SubPoint, HALF_PIXEL, SUBPIXEL};

/// One edge being walked down the rows: the first covered column at the
/// current row, and the exact remainder of that ceiling.
#[derive(Clone, Copy, Debug)]
struct EdgeStepper {
    /// `ceil(N / den)` for the current row, with `N` the edge's numerator.
    col: i32,
    /// `col * den - N`, always in `0..den`.
    rem: i32,
    /// Column step per row: `ceil(SUBPIXEL * dx / den)`.
    step_col: i32,
    /// Remainder step per row: `step_col * den - SUBPIXEL * dx`.
    step_rem: i32,
    /// `SUBPIXEL * dy`.
    den: i32,
}

impl EdgeStepper {
    /// Starts the edge `p -> q` (`q.y > p.y`) at pixel row `row`.
    #[inline]
    fn new(p: SubPoint, q: SubPoint, row: i32) -> Self {
        let dx = q.x as i64 - p.x as i64;
        let dy = q.y as i64 - p.y as i64;
        debug_assert!(dy > 0);
        let den = SUBPIXEL as i64 * dy;
        // x_edge(y_c) - ½px, times den, as a sub-pixel numerator:
        // (p.x - ½) * dy + (y_c - p.y) * dx, over SUBPIXEL * dy.
        let yc = row as i64 * SUBPIXEL as i64 + HALF_PIXEL as i64;
        let num = (p.x as i64 - HALF_PIXEL as i64) * dy + (yc - p.y as i64) * dx;
        let (col, rem) = ceil_div_rem(num, den);
        let (step_col, step_rem) = ceil_div_rem(SUBPIXEL as i64 * dx, den);
        // Within the guard band every quantity here fits i32; see the
        // module docs of `crate::vertex` for the bound.
        Self {
            col: col as i32,
            rem: rem as i32,
            step_col: step_col as i32,
            step_rem: step_rem as i32,
            den: den as i32,
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        self.col += self.step_col;
        self.rem += self.step_rem;
        if self.rem >= self.den {
            self.rem -= self.den;
            self.col -= 1;
        }
    }
}

/// `(q, r)` with `q = ceil(n / d)` and `r = q * d - n` in `0..d`, for `d > 0`.
#[inline]
fn ceil_div_rem(n: i64, d: i64) -> (i64, i64) {
    let q = -((-n).div_euclid(d));
    (q, q * d - n)
}

/// Calls `span(row, x_start, x_end)` for every non-empty run of covered
/// pixels `x_start..x_end` of the triangle `v`, row by row from the top,
/// restricted to `clip`.
///
/// Works for either winding and does nothing for a zero-area triangle.
/// Vertices must lie within the guard band of [`crate::vertex`] (±2^18
/// sub-pixels), which the vertex stage guarantees.
///
/// ```
/// use microraster::raster::{scanline::spans, PixelRect, SubPoint};
/// // A 4x4-pixel right triangle: centres strictly above its hypotenuse are
/// // covered; the three centres exactly on it lie on a right edge and are not.
/// let tri = [SubPoint::new(0, 0), SubPoint::new(64, 0), SubPoint::new(0, 64)];
/// let mut covered = 0;
/// spans(&tri, PixelRect::new(0, 0, 16, 16), |_row, x0, x1| covered += x1 - x0);
/// assert_eq!(covered, 3 + 2 + 1);
/// ```
#[inline]
pub fn spans<F: FnMut(i32, i32, i32)>(v: &[SubPoint; 3], clip: PixelRect, mut span: F) {
    // Sort by y: a on top, c at the bottom.
    let (mut a, mut b, mut c) = (v[0], v[1], v[2]);
    if a.y > b.y {
        core::mem::swap(&mut a, &mut b);
    }
    if b.y > c.y {
        core::mem::swap(&mut b, &mut c);
    }
    if a.y > b.y {
        core::mem::swap(&mut a, &mut b);
    }
    let cross = (b.x as i64 - a.x as i64) * (c.y as i64 - a.y as i64)
        - (c.x as i64 - a.x as i64) * (b.y as i64 - a.y as i64);
    if cross == 0 || clip.is_empty() {
        return;
    }
    // cross > 0: the middle vertex is right of the long edge a -> c.
    let long_on_left = cross > 0;

    let row_top = first_centre_at_or_after(a.y).max(clip.y0);
    let row_mid = first_centre_at_or_after(b.y);
    let row_end = first_centre_at_or_after(c.y).min(clip.y1);
    if row_top >= row_end {
        return;
    }
    let mut long = EdgeStepper::new(a, c, row_top);

    let mut walk = |long: &mut EdgeStepper, short: &mut EdgeStepper, from: i32, to: i32| {
        for row in from..to {
            let (l, r) = if long_on_left {
                (long.col, short.col)
            } else {
                (short.col, long.col)
            };
            let (x0, x1) = (l.max(clip.x0), r.min(clip.x1));
            if x0 < x1 {
                span(row, x0, x1);
            }
            long.step();
            short.step();
        }
    };

    // Upper half: rows whose centre lies above the middle vertex.
    let upper_end = row_mid.min(row_end);
    if row_top < upper_end {
        let mut short = EdgeStepper::new(a, b, row_top);
        walk(&mut long, &mut short, row_top, upper_end);
    }
    // Lower half.
    let lower_start = row_mid.max(row_top);
    if lower_start < row_end {
        let mut short = EdgeStepper::new(b, c, lower_start);
        walk(&mut long, &mut short, lower_start, row_end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(v: [SubPoint; 3]) -> i32 {
        let mut n = 0;
        spans(&v, PixelRect::new(-100, -100, 100, 100), |_, a, b| {
            n += b - a
        });
        n
    }

    #[test]
    fn ceil_div_rem_matches_definition() {
        for n in -50i64..50 {
            for d in 1i64..7 {
                let (q, r) = ceil_div_rem(n, d);
                assert!(q * d >= n && (q - 1) * d < n);
                assert_eq!(r, q * d - n);
                assert!((0..d).contains(&r));
            }
        }
    }

    #[test]
    fn square_split_in_two_covers_each_pixel_once() {
        let p = |x, y| SubPoint::new(x * 16, y * 16);
        let a = count([p(0, 0), p(4, 0), p(4, 4)]);
        let b = count([p(0, 0), p(4, 4), p(0, 4)]);
        assert_eq!(a + b, 16);
    }

    #[test]
    fn degenerate_triangles_cover_nothing() {
        let p = |x, y| SubPoint::new(x, y);
        assert_eq!(count([p(0, 0), p(100, 100), p(200, 200)]), 0);
        assert_eq!(count([p(5, 5), p(5, 5), p(5, 5)]), 0);
        assert_eq!(count([p(0, 8), p(100, 8), p(200, 8)]), 0);
    }
}
