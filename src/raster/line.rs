//! Lines and points: wireframes and point clouds, drawn into one tile.
//!
//! # Which pixels a line has
//!
//! A line from `a` to `b` has the pixels that J. E. Bresenham's algorithm
//! ("Algorithm for computer control of a digital plotter", *IBM Systems
//! Journal* 4(1), 25–30, 1965) steps through between the pixels `P` and `Q`
//! that contain its two end points: pixel `(x >> 4, y >> 4)` for a
//! sub-pixel position `(x, y)`, the pixel whose square holds the point.
//! Both end pixels are drawn; when `P = Q` the line is that one pixel.
//!
//! The *major* axis is x when `|Q.x - P.x| >= |Q.y - P.y|` and y otherwise
//! (an exact diagonal is x-major, which changes nothing: its minor offset is
//! always the step count). With `n` the major-axis distance and `m` the
//! minor-axis one (`0 <= m <= n`), the line has exactly `n + 1` pixels, one
//! per major step `k = 0..=n`: the major coordinate moves `k` pixels from
//! `P` towards `Q` and the minor one `v_k` pixels, where `v_k` is the
//! integer nearest to `k m / n`, **a half rounding down**, towards `P`:
//!
//! ```text
//! v_k = floor((2 k m + n - 1) / (2 n))
//! ```
//!
//! That is Bresenham's sequence: his decision variable is the remainder of
//! this division less `2n`, in `[-2n, 0)`; it grows by `2m` per step, and
//! when it reaches zero the minor coordinate steps and it drops by `2n`.
//! A half (`2 k m / n` an odd integer) needs `n` even.
//!
//! # Ordering
//!
//! Which end is `P` decides the tie rule, the order pixels are visited in
//! and where the depth and colour interpolation starts. The two end points
//! are therefore put in a canonical order first: the one with the smaller
//! `(y, x)` sub-pixel position is `P` (then the smaller depth, then the
//! smaller colour, so that the order is total). Drawing `b -> a` is then
//! the very same call as `a -> b`: same pixels, same depths, same colours.
//! Only the flat colour, which is `a`'s by definition, follows the caller's
//! order.
//!
//! # Clipping without moving a pixel
//!
//! A renderer draws the same line into every tile it crosses, so clipping
//! must select a sub-sequence of the whole line's pixels, never a new line
//! between clipped end points (which would round differently and leave a
//! kink at every tile border). The clipping follows Cohen and Sutherland
//! (W. M. Newman and R. F. Sproull, *Principles of Interactive Computer
//! Graphics*, McGraw-Hill, 1973): each end pixel gets a four-bit outcode of
//! the clip-rectangle sides it lies beyond; a line with a side common to
//! both outcodes is rejected, one with both outcodes zero is drawn whole,
//! and otherwise the line is cut at the sides the outcodes name.
//!
//! The cut is made not in real coordinates but in the step count `k`.
//! A Bresenham line is monotonic in both axes, so the steps whose pixel
//! lies between two parallel sides form one interval of `k`: on the major
//! axis it is read off directly, and on the minor axis the first `k` with
//! `v_k >= t` and the last with `v_k <= t` follow from the formula above
//! by one integer division each. The intersection `k0..=k1` of these
//! intervals with `0..=n` holds exactly the line's pixels inside the
//! rectangle (an empty one rejects the line: it passes a corner). The walk
//! then starts at step `k0` with the decision variable computed there
//! exactly, `v_{k0}` and its remainder from one `i64` division, so every
//! pixel it visits is the one the unclipped walk visits at that step.
//!
//! # Depth and colour
//!
//! Depth (and, when interpolated, each colour channel) is linear in the
//! step count, rounded to the nearest integer, a half rounding up:
//!
//! ```text
//! z_k = z_P + floor((2 k (z_Q - z_P) + n) / (2 n))        (z_P when n = 0)
//! ```
//!
//! so `z_0 = z_P` and `z_n = z_Q` exactly, and every value lies between
//! them. A walk entering at `k0` computes `z_{k0}` and its remainder with one
//! division, then steps with an integer quotient and remainder (a
//! digital differential analyser), so a pixel gets the same value in
//! whichever tile it is drawn. `depth_bias` is then subtracted, saturating
//! at 0.
//!
//! # Ranges
//!
//! Any `i32` sub-pixel positions are accepted, not just the guard band of
//! ±2^18 sub-pixels the vertex stage produces: end pixels then lie within
//! ±2^27, so `n < 2^28` and every per-pixel quantity (pixel coordinates,
//! the decision variable in `[-2n, 2m)`, interpolation remainders below
//! `4n`) is below 2^30 in magnitude, in `i32`. Set-up (the clipped
//! entry, the interpolation start) uses `i64`, whose products stay below
//! 2^59. Any clip rectangle, depth, colour, bias and point size are
//! accepted; nothing overflows or panics.
//!
//! # Cost
//!
//! Per pixel, all in `i32`: the Bresenham step (three adds and a sign test,
//! three more adds on a minor step), the loop count, the depth step (two
//! adds and a compare, one more add when it carries), the saturating bias
//! subtraction, the tile address, the depth load and test, and the stores.
//! An interpolated colour adds three more steps like the depth's and, for
//! each pixel that passes, a conversion to the tile's colour type. Per line
//! and tile: the canonical order and two outcodes; only when the tile cuts
//! the line, up to four `i64` divisions to enter it and four per
//! interpolated value to start its stepping.

use super::{PixelRect, SubPoint, SUBPIXEL_BITS};
use crate::shade::DepthTest;
use crate::tile::TileBuffer;
use embedded_graphics::pixelcolor::Rgb888;

/// A line end point: screen position in sub-pixels, depth, colour.
///
/// Also the position, depth and colour of a drawn point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct LinePoint {
    /// Screen position in `1 / SUBPIXEL` px; the pixel containing it is
    /// the line's end pixel.
    pub pos: SubPoint,
    /// Depth, `0` nearest, `65535` farthest.
    pub z: u16,
    /// Colour as 8-bit red, green, blue.
    pub color: [u8; 3],
}

impl LinePoint {
    /// Creates an end point.
    pub const fn new(pos: SubPoint, z: u16, color: [u8; 3]) -> Self {
        Self { pos, z, color }
    }
}

/// The two end points in canonical order (see the module docs): the one
/// with the smaller `(y, x, z, colour)` first.
#[inline]
fn canonical<'p>(a: &'p LinePoint, b: &'p LinePoint) -> (&'p LinePoint, &'p LinePoint) {
    let key = |p: &LinePoint| (p.pos.y, p.pos.x, p.z, p.color);
    if key(b) < key(a) {
        (b, a)
    } else {
        (a, b)
    }
}

const LEFT: u8 = 1;
const RIGHT: u8 = 2;
const TOP: u8 = 4;
const BOTTOM: u8 = 8;

/// The Cohen–Sutherland outcode of pixel `(i, j)` against `clip`.
#[inline]
fn outcode(i: i32, j: i32, clip: &PixelRect) -> u8 {
    let mut code = 0;
    if i < clip.x0 {
        code |= LEFT;
    } else if i >= clip.x1 {
        code |= RIGHT;
    }
    if j < clip.y0 {
        code |= TOP;
    } else if j >= clip.y1 {
        code |= BOTTOM;
    }
    code
}

/// The offsets `t` for which `c0 + s t` lies in `lo..hi` (`s = ±1`), as an
/// inclusive range (empty when `lo >= hi`).
#[inline]
fn axis_range(c0: i64, s: i64, lo: i64, hi: i64) -> (i64, i64) {
    if s > 0 {
        (lo - c0, hi - 1 - c0)
    } else {
        (c0 - hi + 1, c0 - lo)
    }
}

/// The Bresenham walk of a line over a clip rectangle, positioned at its
/// first pixel inside.
#[derive(Clone, Copy, Debug)]
struct Walk {
    /// The current pixel.
    i: i32,
    j: i32,
    /// Its step index from the first end, and the line's step count.
    k: u32,
    n: u32,
    /// Steps still to take after the current pixel.
    left: u32,
    /// Pixel moves on every step (major) and on a minor step.
    major: (i32, i32),
    minor: (i32, i32),
    /// The decision variable, in `[-dec, 0)`; `inc = 2m`, `dec = 2n`.
    e: i32,
    inc: i32,
    dec: i32,
}

impl Walk {
    /// The walk of the line from the pixel containing `p` to the one
    /// containing `q`, restricted to `clip`; `None` when no pixel of it is
    /// inside.
    fn new(p: SubPoint, q: SubPoint, clip: &PixelRect) -> Option<Self> {
        if clip.is_empty() {
            return None;
        }
        let (i0, j0) = (p.x >> SUBPIXEL_BITS, p.y >> SUBPIXEL_BITS);
        let (i1, j1) = (q.x >> SUBPIXEL_BITS, q.y >> SUBPIXEL_BITS);
        let (code0, code1) = (outcode(i0, j0, clip), outcode(i1, j1, clip));
        if code0 & code1 != 0 {
            return None;
        }
        // Pixel coordinates are within ±2^27, so differences fit easily.
        let (di, dj) = (i1 - i0, j1 - j0);
        let (si, sj) = (if di < 0 { -1 } else { 1 }, if dj < 0 { -1 } else { 1 });
        let x_major = di.abs() >= dj.abs();
        let (n, m, major, minor) = if x_major {
            (di.abs(), dj.abs(), (si, 0), (0, sj))
        } else {
            (dj.abs(), di.abs(), (0, sj), (si, 0))
        };
        let (k0, k1) = if code0 | code1 == 0 {
            (0, n as i64)
        } else {
            Self::clipped_steps(p, q, clip, code0 | code1)?
        };
        let (n64, m64) = (n as i64, m as i64);
        // The minor offset at k0 and Bresenham's decision variable there:
        // v = floor((2 k m + n - 1) / (2 n)), e = remainder - 2n.
        let (v, e) = if k0 == 0 {
            (0, -n - 1)
        } else {
            // k0 > 0 implies n >= 1.
            let num = 2 * k0 * m64 + n64 - 1;
            (num / (2 * n64), (num % (2 * n64) - 2 * n64) as i32)
        };
        // Both lie on the line, inside its bounding box of i32 pixels.
        let i = i0 as i64 + major.0 as i64 * k0 + minor.0 as i64 * v;
        let j = j0 as i64 + major.1 as i64 * k0 + minor.1 as i64 * v;
        Some(Self {
            i: i as i32,
            j: j as i32,
            k: k0 as u32,
            n: n as u32,
            left: (k1 - k0) as u32,
            major,
            minor,
            e,
            inc: 2 * m,
            dec: 2 * n,
        })
    }

    /// The steps `k0..=k1` whose pixels lie inside `clip`, cutting only at
    /// the sides named in the outcodes `codes` (the whole line lies within
    /// the bounding box of its end pixels, so no other side can cut it).
    #[inline(never)]
    fn clipped_steps(p: SubPoint, q: SubPoint, clip: &PixelRect, codes: u8) -> Option<(i64, i64)> {
        let (i0, j0) = ((p.x >> SUBPIXEL_BITS) as i64, (p.y >> SUBPIXEL_BITS) as i64);
        let (i1, j1) = ((q.x >> SUBPIXEL_BITS) as i64, (q.y >> SUBPIXEL_BITS) as i64);
        let (di, dj) = (i1 - i0, j1 - j0);
        let (si, sj) = (di.signum() | 1, dj.signum() | 1);
        let (cx, cy) = (codes & (LEFT | RIGHT) != 0, codes & (TOP | BOTTOM) != 0);
        let (x0, x1, y0, y1) = (
            clip.x0 as i64,
            clip.x1 as i64,
            clip.y0 as i64,
            clip.y1 as i64,
        );
        // (offset range on the major axis if cut, on the minor axis if cut)
        let (n, m, major_cut, minor_cut) = if di.abs() >= dj.abs() {
            (
                di.abs(),
                dj.abs(),
                cx.then(|| axis_range(i0, si, x0, x1)),
                cy.then(|| axis_range(j0, sj, y0, y1)),
            )
        } else {
            (
                dj.abs(),
                di.abs(),
                cy.then(|| axis_range(j0, sj, y0, y1)),
                cx.then(|| axis_range(i0, si, x0, x1)),
            )
        };
        let (mut k0, mut k1) = (0, n);
        if let Some((lo, hi)) = major_cut {
            k0 = k0.max(lo);
            k1 = k1.min(hi);
        }
        if let Some((lo, hi)) = minor_cut {
            // Clamping to the offsets the line has keeps the products
            // below 2^59 whatever the rectangle.
            let (lo, hi) = (lo.clamp(0, m + 1), hi.clamp(-1, m));
            if lo > hi {
                return None;
            }
            // First k with v_k >= lo: 2 k m >= 2 n lo - n + 1.
            if lo > 0 {
                k0 = k0.max((2 * n * lo - n + 1 + 2 * m - 1) / (2 * m));
            }
            // Last k with v_k <= hi: 2 k m <= 2 n hi + n (all k if hi = m).
            if hi < m {
                k1 = k1.min((2 * n * hi + n) / (2 * m));
            }
        }
        (k0 <= k1).then_some((k0, k1))
    }

    /// Calls `f` with each pixel from the current one to the last inside,
    /// in order.
    #[inline(always)]
    fn run(mut self, mut f: impl FnMut(i32, i32)) {
        loop {
            f(self.i, self.j);
            if self.left == 0 {
                return;
            }
            self.left -= 1;
            self.i += self.major.0;
            self.j += self.major.1;
            self.e += self.inc;
            if self.e >= 0 {
                self.e -= self.dec;
                self.i += self.minor.0;
                self.j += self.minor.1;
            }
        }
    }
}

/// A value interpolated along a line by the step count, stepped exactly:
/// `v + rem / den` is `v_0 + k (v_1 - v_0) / n + 1/2` at step `k`.
#[derive(Clone, Copy, Debug)]
struct Lerp {
    v: i32,
    rem: i32,
    q: i32,
    r: i32,
    den: i32,
}

impl Lerp {
    /// At step `k` of `n` from `v0` to `v1` (values below 2^16, `n < 2^28`):
    /// `v0 + floor((2 k (v1 - v0) + n) / (2 n))`.
    #[inline]
    fn at(v0: i32, v1: i32, k: u32, n: u32) -> Self {
        if n == 0 {
            return Self {
                v: v0,
                rem: 0,
                q: 0,
                r: 0,
                den: 1,
            };
        }
        let den = 2 * n as i32;
        let d2 = 2 * (v1 - v0);
        let (v, rem) = if k == 0 {
            (v0, n as i32)
        } else {
            let (den, num) = (den as i64, 2 * k as i64 * (v1 - v0) as i64 + n as i64);
            (v0 + num.div_euclid(den) as i32, num.rem_euclid(den) as i32)
        };
        Self {
            v,
            rem,
            q: d2.div_euclid(den),
            r: d2.rem_euclid(den),
            den,
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        self.v += self.q;
        self.rem += self.r;
        if self.rem >= self.den {
            self.rem -= self.den;
            self.v += 1;
        }
    }
}

/// Calls `plot(i, j, k, n)` for every pixel `(i, j)` of the line from `a`
/// to `b` (see the module docs) that lies inside `clip`, in order from the
/// canonical first end: `k` is the pixel's step from that end and `n` the
/// line's step count, so `k / n` is how far along the line it lies.
///
/// The pixels, and their `k`, are those of the whole line whatever `clip`
/// is, and the same whichever order `a` and `b` are given in.
// The tests' view of the pixel sequence; the renderer draws through
// `draw_line`.
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) fn line_pixels(
    a: &LinePoint,
    b: &LinePoint,
    clip: PixelRect,
    mut plot: impl FnMut(i32, i32, u32, u32),
) {
    let (p, q) = canonical(a, b);
    if let Some(walk) = Walk::new(p.pos, q.pos, &clip) {
        let (mut k, n) = (walk.k, walk.n);
        walk.run(|i, j| {
            plot(i, j, k, n);
            k += 1;
        });
    }
}

/// The pixels a tile can hold: `rect` (whose top-left pixel is the tile's
/// first), limited to the buffer's `W x H`.
#[inline]
fn tile_clip<const W: usize, const H: usize>(rect: &PixelRect) -> PixelRect {
    // A tile buffer is at most 1,024 pixels a side.
    rect.intersect(&PixelRect::new(
        rect.x0,
        rect.y0,
        rect.x0.saturating_add(W as i32),
        rect.y0.saturating_add(H as i32),
    ))
}

/// How lines and points are depth tested and written: at run time (one
/// predictable branch per pixel), so the line code exists once per colour
/// type rather than once per depth test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DepthMode {
    pub test: DepthTest,
    pub write: bool,
}

/// Depth-tests one tile-local pixel (inside the buffer) and writes it.
#[inline(always)]
fn put<C: Copy, const W: usize, const H: usize>(
    tile: &mut TileBuffer<C, W, H>,
    mode: DepthMode,
    x: usize,
    y: usize,
    z: u16,
    color: impl FnOnce() -> C,
) -> u32 {
    let depth = &mut tile.depth.0[y][x];
    if !mode.test.passes(z, *depth) {
        return 0;
    }
    if mode.write {
        *depth = z;
    }
    tile.color[y][x] = color();
    1
}

/// Draws the line from `a` to `b` into a tile whose top-left pixel is
/// screen pixel `(rect.x0, rect.y0)`, `rect` being the tile's pixels (it is
/// further limited to the buffer's `W x H`); returns the pixels written.
///
/// Every pixel is depth tested with `mode.test` and its depth stored when
/// `mode.write`.
/// The depth is interpolated along the line (module docs) and then lowered
/// by `depth_bias`, saturating at 0. That is for a wireframe overlay drawn
/// over the triangles it outlines: at each pixel the line has about the
/// depth of those triangles, but rounded differently, and a Bresenham
/// pixel may lie just outside the edge's own triangle, in its neighbour,
/// so without a bias about half its pixels would lose the depth test. A
/// bias covering the faces' depth change across a pixel or two (a few
/// units for faces seen head-on, more for grazing ones) lets the edges win
/// against their own faces while edges hidden behind other geometry stay
/// hidden. Use 0 for lines drawn on their own.
///
/// The colour is `a`'s colour when `interpolate` is false, and otherwise
/// each channel interpolated between the two ends like the depth.
///
/// Drawing a line into every tile gives exactly the pixels, depths and
/// colours of drawing it into one buffer holding the whole screen.
pub(crate) fn draw_line<C: Copy + From<Rgb888>, const W: usize, const H: usize>(
    tile: &mut TileBuffer<C, W, H>,
    rect: &PixelRect,
    mode: DepthMode,
    a: &LinePoint,
    b: &LinePoint,
    interpolate: bool,
    depth_bias: u16,
) -> u32 {
    let (p, q) = canonical(a, b);
    let clip = tile_clip::<W, H>(rect);
    let Some(mut walk) = Walk::new(p.pos, q.pos, &clip) else {
        return 0;
    };
    // The walk goes down (or along a row) from its first pixel, inside
    // the clip, to `q`'s row at most.
    let last = (q.pos.y >> SUBPIXEL_BITS).min(clip.y1 - 1);
    tile.written((walk.j - rect.y0) as usize, (last - rect.y0) as usize);
    // Walk in tile-local pixels: the clip keeps them in 0..W, 0..H.
    walk.i -= rect.x0;
    walk.j -= rect.y0;
    let (k, n) = (walk.k, walk.n);
    let mut z = Lerp::at(p.z as i32, q.z as i32, k, n);
    let mut written = 0;
    if interpolate {
        let ch = |c: usize| Lerp::at(p.color[c] as i32, q.color[c] as i32, k, n);
        let (mut r, mut g, mut b) = (ch(0), ch(1), ch(2));
        walk.run(|i, j| {
            // Within a step of the line, z and the channels lie between
            // the end values, so the casts are exact.
            let depth = (z.v as u16).saturating_sub(depth_bias);
            written += put::<C, W, H>(tile, mode, i as usize, j as usize, depth, || {
                C::from(Rgb888::new(r.v as u8, g.v as u8, b.v as u8))
            });
            z.step();
            r.step();
            g.step();
            b.step();
        });
    } else {
        let color = C::from(Rgb888::new(a.color[0], a.color[1], a.color[2]));
        walk.run(|i, j| {
            let depth = (z.v as u16).saturating_sub(depth_bias);
            written += put::<C, W, H>(tile, mode, i as usize, j as usize, depth, || color);
            z.step();
        });
    }
    written
}

/// Draws a point into a tile (`rect` as for [`draw_line`]): the square of
/// `size x size` pixels whose centre is nearest to `p`, depth tested with
/// `mode` at `p.z` (lower it for a bias) and coloured `p.color`; returns the
/// pixels written.
///
/// For an odd `size` the square is centred on the pixel containing `p`
/// (size 1 is that pixel), for an even one on the pixel corner nearest to
/// `p` (a half, `p` on a pixel centre, rounding right and down): its
/// first column is
/// `floor((x - 8 (size - 1)) / 16)`, likewise its first row. A `size` of 0
/// draws nothing.
pub(crate) fn draw_point<C: Copy + From<Rgb888>, const W: usize, const H: usize>(
    tile: &mut TileBuffer<C, W, H>,
    rect: &PixelRect,
    mode: DepthMode,
    p: &LinePoint,
    size: u32,
) -> u32 {
    let clip = tile_clip::<W, H>(rect);
    if size == 0 || clip.is_empty() {
        return 0;
    }
    // In i64: 8 (size - 1) reaches 2^35.
    let half = (size as i64 - 1) << (SUBPIXEL_BITS - 1);
    let first = |c: i32| (c as i64 - half) >> SUBPIXEL_BITS;
    let (x0, y0) = (first(p.pos.x), first(p.pos.y));
    // Inside the clip, so every bound fits i32 and is tile-local >= 0.
    let xa = x0.max(clip.x0 as i64) as i32;
    let xb = (x0 + size as i64).min(clip.x1 as i64) as i32;
    let ya = y0.max(clip.y0 as i64) as i32;
    let yb = (y0 + size as i64).min(clip.y1 as i64) as i32;
    let color = C::from(Rgb888::new(p.color[0], p.color[1], p.color[2]));
    if ya < yb && xa < xb {
        tile.written((ya - rect.y0) as usize, (yb - 1 - rect.y0) as usize);
    }
    let mut written = 0;
    for j in ya..yb {
        for i in xa..xb {
            written += put::<C, W, H>(
                tile,
                mode,
                (i - rect.x0) as usize,
                (j - rect.y0) as usize,
                p.z,
                || color,
            );
        }
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALWAYS: DepthMode = DepthMode {
        test: DepthTest::Always,
        write: true,
    };
    const LESS: DepthMode = DepthMode {
        test: DepthTest::Less,
        write: true,
    };
    const LESS_EQUAL: DepthMode = DepthMode {
        test: DepthTest::LessEqual,
        write: true,
    };
    const LESS_EQUAL_NO_WRITE: DepthMode = DepthMode {
        test: DepthTest::LessEqual,
        write: false,
    };

    /// The test generator (xorshift64), returning values in `0..m`.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self, m: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % m
        }

        /// A value in `lo..hi`.
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + self.next((hi - lo) as u64) as i64
        }
    }

    fn pt(x: i32, y: i32, z: u16, color: [u8; 3]) -> LinePoint {
        LinePoint::new(SubPoint::new(x, y), z, color)
    }

    /// The end points in the documented canonical order.
    fn ordered(a: LinePoint, b: LinePoint) -> (LinePoint, LinePoint) {
        let (ka, kb) = (
            (a.pos.y, a.pos.x, a.z, a.color),
            (b.pos.y, b.pos.x, b.z, b.color),
        );
        if kb < ka {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// The documented line, straight from its definition in rationals: the
    /// pixel at major step `k` from `p` to `q` (end pixels, canonical
    /// order) has the minor offset nearest to `k m / n`, a half going to
    /// the smaller offset. Returns the pixel and the step count `n`.
    fn reference_pixel(p: (i64, i64), q: (i64, i64), k: i64) -> ((i64, i64), i64) {
        let (di, dj) = (q.0 - p.0, q.1 - p.1);
        let x_major = di.abs() >= dj.abs();
        let (big, small) = if x_major { (di, dj) } else { (dj, di) };
        let n = big.abs();
        if n == 0 {
            return (p, 0);
        }
        let exact = k * small.abs();
        let (whole, frac) = (exact / n, exact % n);
        // frac / n > 1/2 rounds up; exactly 1/2 rounds down.
        let off = (whole + (2 * frac > n) as i64) * small.signum();
        let along = k * big.signum();
        let px = if x_major {
            (p.0 + along, p.1 + off)
        } else {
            (p.0 + off, p.1 + along)
        };
        (px, n)
    }

    /// The nearest integer to `v0 + k (v1 - v0) / n`, a half going up.
    fn reference_value(v0: i64, v1: i64, k: i64, n: i64) -> i64 {
        if n == 0 {
            return v0;
        }
        let t = k * (v1 - v0);
        v0 + t.div_euclid(n) + (2 * t.rem_euclid(n) >= n) as i64
    }

    fn end_pixels(a: &LinePoint, b: &LinePoint) -> ((i64, i64), (i64, i64)) {
        let (p, q) = ordered(*a, *b);
        let px = |s: SubPoint| ((s.x as i64).div_euclid(16), (s.y as i64).div_euclid(16));
        (px(p.pos), px(q.pos))
    }

    const ALL: PixelRect = PixelRect::new(i32::MIN, i32::MIN, i32::MAX, i32::MAX);

    /// Checks every pixel `line_pixels` gives in `clip` against the
    /// reference and that they are exactly the reference pixels inside
    /// `clip` (enumerating the whole line).
    fn check_against_reference(a: &LinePoint, b: &LinePoint, clip: PixelRect) -> u32 {
        let (p, q) = end_pixels(a, b);
        let inside = |(i, j): (i64, i64)| {
            i >= clip.x0 as i64 && i < clip.x1 as i64 && j >= clip.y0 as i64 && j < clip.y1 as i64
        };
        let n = reference_pixel(p, q, 0).1;
        let mut expected_k = (0..=n).filter(|&k| inside(reference_pixel(p, q, k).0));
        let mut count = 0;
        line_pixels(a, b, clip, |i, j, k, kn| {
            assert_eq!(kn as i64, n, "{a:?} {b:?} {clip:?}");
            assert_eq!(Some(k as i64), expected_k.next(), "{a:?} {b:?} {clip:?}");
            assert_eq!(
                (i as i64, j as i64),
                reference_pixel(p, q, k as i64).0,
                "{a:?} {b:?} {clip:?} k {k}"
            );
            count += 1;
        });
        assert_eq!(expected_k.next(), None, "{a:?} {b:?} {clip:?}");
        count
    }

    #[test]
    fn known_lines_in_every_octant() {
        // (0,0) -> (5,2): minor offsets 0, .4, .8, 1.2, 1.6, 2 rounded.
        let shallow = [(0, 0), (1, 0), (2, 1), (3, 1), (4, 2), (5, 2)];
        // (0,0) -> (4,2): halves at k = 1 and 3 round towards the start.
        let tie = [(0, 0), (1, 0), (2, 1), (3, 1), (4, 2)];
        for (end, table) in [((5, 2), &shallow[..]), ((4, 2), &tie[..])] {
            // All eight octants: mirror in x, in y, and swap the axes. The
            // walk starts at the canonical (upper) end; from there the
            // mirrored table applies, ties included.
            for flags in 0..8 {
                let map = |(x, y): (i32, i32)| {
                    let (x, y) = if flags & 4 != 0 { (y, x) } else { (x, y) };
                    let x = if flags & 1 != 0 { -x } else { x };
                    let y = if flags & 2 != 0 { -y } else { y };
                    (x, y)
                };
                let (ex, ey) = map(end);
                let a = pt(100 * 16 + 3, 100 * 16 + 9, 0, [0; 3]);
                let b = pt((100 + ex) * 16 + 15, (100 + ey) * 16, 0, [0; 3]);
                let from_b = (b.pos.y, b.pos.x) < (a.pos.y, a.pos.x);
                let want: heapless::Vec<(i32, i32), 8> = table
                    .iter()
                    .map(|&t| {
                        let (x, y) = map(t);
                        if from_b {
                            (100 + ex - x, 100 + ey - y)
                        } else {
                            (100 + x, 100 + y)
                        }
                    })
                    .collect();
                for (p, q) in [(&a, &b), (&b, &a)] {
                    let mut got: heapless::Vec<(i32, i32), 8> = heapless::Vec::new();
                    line_pixels(p, q, ALL, |i, j, _, _| got.push((i, j)).unwrap());
                    assert_eq!(got, want, "end {end:?} flags {flags}");
                }
                assert_eq!(check_against_reference(&a, &b, ALL), want.len() as u32);
            }
        }
    }

    #[test]
    fn fixed_lines_and_ties() {
        let p = |x: i32, y: i32| pt(x * 16 + 8, y * 16 + 8, 0, [0; 3]);
        let collect = |a: &LinePoint, b: &LinePoint| {
            let mut v: heapless::Vec<(i32, i32), 16> = heapless::Vec::new();
            line_pixels(a, b, ALL, |i, j, _, _| v.push((i, j)).unwrap());
            v
        };
        // Horizontal, vertical, both diagonals, zero length.
        assert_eq!(
            collect(&p(2, 3), &p(5, 3)),
            [(2, 3), (3, 3), (4, 3), (5, 3)]
        );
        assert_eq!(
            collect(&p(5, 3), &p(2, 3)),
            [(2, 3), (3, 3), (4, 3), (5, 3)]
        );
        assert_eq!(
            collect(&p(1, 5), &p(1, 2)),
            [(1, 2), (1, 3), (1, 4), (1, 5)]
        );
        assert_eq!(
            collect(&p(0, 0), &p(3, 3)),
            [(0, 0), (1, 1), (2, 2), (3, 3)]
        );
        assert_eq!(
            collect(&p(3, 0), &p(0, 3)),
            [(3, 0), (2, 1), (1, 2), (0, 3)]
        );
        assert_eq!(collect(&p(7, 7), &p(7, 7)), [(7, 7)]);
        // Two points in one pixel: one pixel.
        assert_eq!(
            collect(&pt(16, 16, 0, [0; 3]), &pt(31, 31, 0, [0; 3])),
            [(1, 1)]
        );
        // Steep tie: (0,0) -> (1,2); at k = 1 the offset 1/2 rounds to 0.
        assert_eq!(collect(&p(0, 0), &p(1, 2)), [(0, 0), (0, 1), (1, 2)]);
        assert_eq!(collect(&p(1, 2), &p(0, 0)), [(0, 0), (0, 1), (1, 2)]);
        assert_eq!(collect(&p(1, 0), &p(0, 2)), [(1, 0), (1, 1), (0, 2)]);
        // Negative coordinates floor.
        assert_eq!(
            collect(&pt(-1, -17, 0, [0; 3]), &pt(-16, -1, 0, [0; 3])),
            [(-1, -2), (-1, -1)]
        );
    }

    #[test]
    fn random_lines_match_the_reference() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for round in 0..20_000 {
            let span = [64, 800, 4000][round % 3];
            let mut c = || rng.range(-span, span) as i32;
            let (ax, ay, mut bx, mut by) = (c(), c(), c(), c());
            match round % 7 {
                // Horizontal, vertical, diagonal, anti-diagonal, one pixel.
                0 => by = ay,
                1 => bx = ax,
                2 => (bx, by) = (ax + (by - ay), by),
                3 => (bx, by) = (ax - (by - ay), by),
                4 => (bx, by) = (ax + (bx & 15) - (ax & 15), ay + (by & 15) - (ay & 15)),
                _ => {}
            }
            let a = pt(ax, ay, 0, [0; 3]);
            let b = pt(bx, by, 0, [0; 3]);
            let (p, q) = end_pixels(&a, &b);
            let n = (q.0 - p.0).abs().max((q.1 - p.1).abs());
            assert_eq!(check_against_reference(&a, &b, ALL) as i64, n + 1);
            // The ends are the pixels containing the end points.
            let mut ends = (None, None);
            line_pixels(&a, &b, ALL, |i, j, k, n| {
                if k == 0 {
                    ends.0 = Some((i as i64, j as i64));
                }
                if k == n {
                    ends.1 = Some((i as i64, j as i64));
                }
            });
            assert_eq!(ends, (Some(p), Some(q)));
        }
    }

    #[test]
    fn every_small_line_in_every_clip_rectangle() {
        // End pixels in a 6 x 6 grid, every clip rectangle over -1..7.
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for e in 0..36 * 36 {
            let (s, t) = (e % 36, e / 36);
            let mut sub = || rng.next(16) as i32;
            let a = pt((s % 6) * 16 + sub(), (s / 6) * 16 + sub(), 0, [0; 3]);
            let b = pt((t % 6) * 16 + sub(), (t / 6) * 16 + sub(), 0, [0; 3]);
            for r in 0..36 * 36 {
                let (xs, ys) = (r % 36, r / 36);
                let pair = |v: i32| {
                    // The 36 pairs lo < hi of -1..=7.
                    let (mut lo, mut v) = (0, v);
                    while v >= 8 - lo {
                        v -= 8 - lo;
                        lo += 1;
                    }
                    (lo - 1, lo + v)
                };
                let ((x0, x1), (y0, y1)) = (pair(xs), pair(ys));
                check_against_reference(&a, &b, PixelRect::new(x0, y0, x1, y1));
            }
        }
    }

    type Canvas = TileBuffer<Rgb888, 96, 96>;
    const SENTINEL: Rgb888 = Rgb888::new(1, 2, 3);

    /// Draws the line into tiles of `tw x th` (at most `W x H`) covering
    /// `area`, with the grid shifted by `(sx, sy)`, and checks the result
    /// against `whole`, the line drawn into one buffer for all of `area`.
    #[allow(clippy::too_many_arguments)]
    fn check_tiled<const W: usize, const H: usize>(
        whole: &Canvas,
        area: PixelRect,
        count: u32,
        (tw, th): (i32, i32),
        (sx, sy): (i32, i32),
        a: &LinePoint,
        b: &LinePoint,
        interpolate: bool,
        bias: u16,
    ) {
        let mut total = 0;
        let mut ty = area.y0 - sy;
        while ty < area.y1 {
            let mut tx = area.x0 - sx;
            while tx < area.x1 {
                let rect = PixelRect::new(tx, ty, tx + tw, ty + th).intersect(&area);
                let mut tile: TileBuffer<Rgb888, W, H> = TileBuffer::new(SENTINEL);
                total +=
                    draw_line::<_, W, H>(&mut tile, &rect, LESS_EQUAL, a, b, interpolate, bias);
                for j in rect.y0..rect.y1 {
                    for i in rect.x0..rect.x1 {
                        let (li, lj) = ((i - rect.x0) as usize, (j - rect.y0) as usize);
                        let (ci, cj) = ((i - area.x0) as usize, (j - area.y0) as usize);
                        assert_eq!(
                            (tile.color(li, lj), tile.depth(li, lj)),
                            (whole.color(ci, cj), whole.depth(ci, cj)),
                            "pixel ({i}, {j}) tile {rect:?} line {a:?} {b:?}"
                        );
                    }
                }
                tx += tw;
            }
            ty += th;
        }
        assert_eq!(total, count, "{a:?} {b:?} tiles {tw}x{th}");
    }

    fn random_point(rng: &mut Rng, guard: bool) -> LinePoint {
        let coord = |rng: &mut Rng| {
            if guard && rng.next(2) == 0 {
                rng.range(-(1 << 18), 1 << 18) as i32
            } else {
                rng.range(-60 * 16, 150 * 16) as i32
            }
        };
        let (x, y) = (coord(rng), coord(rng));
        let z = match rng.next(4) {
            0 => 0,
            1 => u16::MAX,
            _ => rng.next(65_536) as u16,
        };
        let mut ch = || rng.next(256) as u8;
        pt(x, y, z, [ch(), ch(), ch()])
    }

    #[test]
    fn tiles_draw_exactly_the_whole_line() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        for round in 0..150 {
            let (a, b) = (
                random_point(&mut rng, round % 3 == 0),
                random_point(&mut rng, round % 5 == 0),
            );
            let area = PixelRect::new(-16, -8, 80, 88);
            for interpolate in [false, true] {
                let bias = [0, 1, 300][round % 3];
                let mut whole = Canvas::new(SENTINEL);
                let count = draw_line::<_, 96, 96>(
                    &mut whole,
                    &area,
                    LESS_EQUAL,
                    &a,
                    &b,
                    interpolate,
                    bias,
                );
                // The whole drawing itself: reference pixels, depths and
                // colours.
                let (p, q) = ordered(a, b);
                let (pp, qp) = end_pixels(&a, &b);
                let mut seen = 0;
                line_pixels(&a, &b, area, |i, j, k, n| {
                    let (ci, cj) = ((i - area.x0) as usize, (j - area.y0) as usize);
                    let (k, n) = (k as i64, n as i64);
                    assert_eq!((i as i64, j as i64), reference_pixel(pp, qp, k).0);
                    let z = reference_value(p.z as i64, q.z as i64, k, n);
                    let z = (z - bias as i64).max(0) as u16;
                    let lerp = |c: usize| {
                        reference_value(p.color[c] as i64, q.color[c] as i64, k, n) as u8
                    };
                    let color = if interpolate {
                        Rgb888::new(lerp(0), lerp(1), lerp(2))
                    } else {
                        Rgb888::new(a.color[0], a.color[1], a.color[2])
                    };
                    assert_eq!(whole.depth(ci, cj), Some(z));
                    assert_eq!(whole.color(ci, cj), Some(color));
                    seen += 1;
                });
                assert_eq!(seen, count);
                let (sx, sy) = (rng.next(16) as i32, rng.next(16) as i32);
                let args = (&a, &b, interpolate, bias);
                check_tiled::<16, 16>(
                    &whole,
                    area,
                    count,
                    (16, 16),
                    (sx, sy),
                    args.0,
                    args.1,
                    args.2,
                    args.3,
                );
                check_tiled::<13, 7>(
                    &whole,
                    area,
                    count,
                    (13, 7),
                    (sx % 13, sy % 7),
                    args.0,
                    args.1,
                    args.2,
                    args.3,
                );
                check_tiled::<1, 1>(
                    &whole,
                    area,
                    count,
                    (1, 1),
                    (0, 0),
                    args.0,
                    args.1,
                    args.2,
                    args.3,
                );
                // Random tile sizes in a bigger buffer (rect smaller than it).
                let tw = 1 + rng.next(16) as i32;
                let th = 1 + rng.next(16) as i32;
                let shift = (rng.next(tw as u64) as i32, rng.next(th as u64) as i32);
                check_tiled::<16, 16>(
                    &whole,
                    area,
                    count,
                    (tw, th),
                    shift,
                    args.0,
                    args.1,
                    args.2,
                    args.3,
                );
            }
        }
    }

    #[test]
    fn reversed_ends_draw_the_same() {
        let mut rng = Rng(0x0bad_cafe_dead_beef);
        let area = PixelRect::new(-16, -8, 80, 88);
        for round in 0..2_000 {
            let (a, mut b) = (
                random_point(&mut rng, round % 4 == 0),
                random_point(&mut rng, false),
            );
            if round % 10 == 0 {
                // Same position, different depth and colour.
                b.pos = a.pos;
            }
            let bias = rng.next(100) as u16;
            for interpolate in [false, true] {
                let mut ab = Canvas::new(SENTINEL);
                let mut ba = Canvas::new(SENTINEL);
                let n1 = draw_line::<_, 96, 96>(&mut ab, &area, ALWAYS, &a, &b, interpolate, bias);
                let n2 = draw_line::<_, 96, 96>(&mut ba, &area, ALWAYS, &b, &a, interpolate, bias);
                assert_eq!(n1, n2);
                assert_eq!(ab.depth, ba.depth, "{a:?} {b:?}");
                if interpolate {
                    assert_eq!(ab.color, ba.color, "{a:?} {b:?}");
                } else {
                    // Flat colour is the first argument's: same pixels.
                    let ca = Rgb888::new(a.color[0], a.color[1], a.color[2]);
                    let cb = Rgb888::new(b.color[0], b.color[1], b.color[2]);
                    for (r1, r2) in ab.color.iter().zip(&ba.color) {
                        for (&c1, &c2) in r1.iter().zip(r2) {
                            assert_eq!(c1 == SENTINEL, c2 == SENTINEL);
                            assert!(c1 == SENTINEL || (c1 == ca && c2 == cb));
                        }
                    }
                }
            }
            let mut seq = [
                heapless::Vec::<(i32, i32, u32), 256>::new(),
                heapless::Vec::new(),
            ];
            line_pixels(&a, &b, area, |i, j, k, _| seq[0].push((i, j, k)).unwrap());
            line_pixels(&b, &a, area, |i, j, k, _| seq[1].push((i, j, k)).unwrap());
            assert_eq!(seq[0], seq[1]);
        }
    }

    #[test]
    fn guard_band_lines_clip_exactly() {
        let mut rng = Rng(0x5151_5151_aaaa_0001);
        let g = 1i64 << 18;
        for round in 0..300 {
            // Both ends far outside (on the guard band's border or inside
            // it), the clip a tile somewhere on a 4096-pixel screen.
            let far = |rng: &mut Rng| {
                let edge = [-g, g][rng.next(2) as usize];
                let other = rng.range(-g, g + 1);
                if rng.next(2) == 0 {
                    (edge as i32, other as i32)
                } else {
                    (other as i32, edge as i32)
                }
            };
            let (a, b) = (far(&mut rng), far(&mut rng));
            let a = pt(a.0, a.1, 0, [0; 3]);
            let b = pt(b.0, b.1, 65_535, [255; 3]);
            let (tx, ty) = (rng.range(0, 4096) as i32, rng.range(0, 4096) as i32);
            let (tw, th) = (1 + rng.next(64) as i32, 1 + rng.next(64) as i32);
            check_against_reference(&a, &b, PixelRect::new(tx, ty, tx + tw, ty + th));
            // A tile the line crosses for sure: around one of its pixels.
            let (p, q) = end_pixels(&a, &b);
            let n = reference_pixel(p, q, 0).1;
            let k = rng.range(0, n + 1);
            let ((ci, cj), _) = reference_pixel(p, q, k);
            let (ox, oy) = (rng.next(16) as i32, rng.next(16) as i32);
            let rect = PixelRect::new(
                ci as i32 - ox,
                cj as i32 - oy,
                ci as i32 - ox + 16,
                cj as i32 - oy + 16,
            );
            assert!(check_against_reference(&a, &b, rect) > 0, "round {round}");
            let mut tile: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
            let drawn = draw_line::<_, 16, 16>(&mut tile, &rect, ALWAYS, &a, &b, true, 0);
            assert!(drawn > 0);
            let (first, last) = ordered(a, b);
            let z = reference_value(first.z as i64, last.z as i64, k, n) as u16;
            assert_eq!(tile.depth(ox as usize, oy as usize), Some(z));
        }
    }

    #[test]
    fn extreme_coordinates_do_not_overflow() {
        let mut rng = Rng(0x7777_1234_4321_7777);
        let extremes = [
            i32::MIN,
            i32::MIN + 1,
            -(1 << 18),
            -1,
            0,
            1 << 18,
            i32::MAX - 1,
            i32::MAX,
        ];
        for round in 0..20_000 {
            let c = |rng: &mut Rng| {
                if rng.next(2) == 0 {
                    extremes[rng.next(extremes.len() as u64) as usize]
                } else {
                    rng.next(1 << 32) as u32 as i32
                }
            };
            let a = pt(c(&mut rng), c(&mut rng), rng.next(65_536) as u16, [0, 0, 0]);
            let b = pt(
                c(&mut rng),
                c(&mut rng),
                rng.next(65_536) as u16,
                [255, 128, 7],
            );
            let clip = if round % 2 == 0 {
                let (x, y) = (c(&mut rng), c(&mut rng));
                PixelRect::new(x, y, x.saturating_add(40), y.saturating_add(40))
            } else {
                // Around a pixel of the line, so that some are drawn.
                let (p, q) = end_pixels(&a, &b);
                let n = reference_pixel(p, q, 0).1;
                let ((ci, cj), _) = reference_pixel(p, q, rng.range(0, n + 1));
                let (x, y) = (ci as i32 - 3, cj as i32 - 20);
                PixelRect::new(x, y, x.saturating_add(24), y.saturating_add(24))
            };
            // Each pixel is the reference one at its step, steps are
            // consecutive, and the steps just outside are outside.
            let (p, q) = end_pixels(&a, &b);
            let mut range: Option<(u32, u32)> = None;
            line_pixels(&a, &b, clip, |i, j, k, n| {
                assert_eq!((i as i64, j as i64), reference_pixel(p, q, k as i64).0);
                assert!(i >= clip.x0 && i < clip.x1 && j >= clip.y0 && j < clip.y1);
                range = match range {
                    None => Some((k, k)),
                    Some((k0, k1)) => {
                        assert_eq!(k, k1 + 1);
                        Some((k0, k))
                    }
                };
                assert!(k <= n);
            });
            let n = reference_pixel(p, q, 0).1;
            let outside = |k: i64| {
                let ((i, j), _) = reference_pixel(p, q, k);
                !(i >= clip.x0 as i64
                    && i < clip.x1 as i64
                    && j >= clip.y0 as i64
                    && j < clip.y1 as i64)
            };
            match range {
                Some((k0, k1)) => {
                    assert!(k0 == 0 || outside(k0 as i64 - 1));
                    assert!(k1 as i64 == n || outside(k1 as i64 + 1));
                }
                None => {
                    if round % 2 == 1 {
                        panic!("a pixel of the line was in the clip: {a:?} {b:?} {clip:?}");
                    }
                }
            }
            // Drawing and points there as well: nothing may panic.
            let rect = PixelRect::new(
                clip.x0,
                clip.y0,
                clip.x0.saturating_add(16),
                clip.y0.saturating_add(16),
            );
            let mut tile: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
            draw_line::<_, 16, 16>(&mut tile, &rect, LESS, &a, &b, true, u16::MAX);
            draw_line::<_, 16, 16>(&mut tile, &rect, LESS_EQUAL_NO_WRITE, &a, &b, false, 7);
            draw_point::<_, 16, 16>(&mut tile, &rect, LESS_EQUAL, &a, rng.next(1 << 32) as u32);
            draw_point::<_, 16, 16>(&mut tile, &rect, ALWAYS, &b, u32::MAX);
        }
    }

    #[test]
    fn depth_test_bias_and_writes() {
        let rect = PixelRect::new(32, 16, 48, 32);
        let a = pt(30 * 16, 20 * 16 + 5, 1000, [200, 0, 0]);
        let b = pt(50 * 16, 25 * 16, 1000, [200, 0, 0]);
        let filled = || {
            let mut t: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
            for row in t.depth.0.iter_mut() {
                row.fill(1000);
            }
            t
        };
        let mut inside = 0;
        line_pixels(&a, &b, rect, |_, _, _, _| inside += 1);
        assert_eq!(inside, 16);
        // Equal depth loses a strict test...
        let mut t = filled();
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS, &a, &b, false, 0),
            0
        );
        assert!(t.color.iter().flatten().all(|&c| c == SENTINEL));
        // ...and wins it with a bias of one, writing the biased depth.
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS, &a, &b, false, 1),
            inside
        );
        let mut biased = 0;
        line_pixels(&a, &b, rect, |i, j, _, _| {
            let (x, y) = ((i - 32) as usize, (j - 16) as usize);
            assert_eq!(t.depth(x, y), Some(999));
            assert_eq!(t.color(x, y), Some(Rgb888::new(200, 0, 0)));
            biased += 1;
        });
        assert_eq!(biased, inside);
        assert_eq!(
            t.depth.0.iter().flatten().filter(|&&z| z == 999).count() as u32,
            inside
        );
        // A line behind loses even a less-or-equal test.
        let mut t = filled();
        let (mut a2, mut b2) = (a, b);
        (a2.z, b2.z) = (2000, 1500);
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS_EQUAL, &a2, &b2, true, 0),
            0
        );
        assert!(t.depth.0.iter().flatten().all(|&z| z == 1000));
        // Unless the bias brings it in front; without writes the depth
        // stays and only the colour is drawn.
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS_EQUAL_NO_WRITE, &a2, &b2, true, 1000),
            inside
        );
        assert!(t.depth.0.iter().flatten().all(|&z| z == 1000));
        assert_eq!(
            t.color.iter().flatten().filter(|&&c| c != SENTINEL).count() as u32,
            inside
        );
        // The bias saturates at the nearest depth.
        let mut t = filled();
        let (mut a3, mut b3) = (a, b);
        (a3.z, b3.z) = (5, 0);
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS, &a3, &b3, false, 100),
            inside
        );
        assert_eq!(
            t.depth.0.iter().flatten().filter(|&&z| z == 0).count() as u32,
            inside
        );
        // Depth interpolated along the line: its own pixels only, ends exact.
        let mut t: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
        let (c, d) = (
            pt(32 * 16, 16 * 16, 100, [0; 3]),
            pt(47 * 16, 16 * 16, 400, [0; 3]),
        );
        assert_eq!(
            draw_line::<_, 16, 16>(&mut t, &rect, LESS_EQUAL, &c, &d, false, 0),
            16
        );
        for x in 0..16 {
            assert_eq!(t.depth(x, 0), Some(100 + 20 * x as u16));
        }
    }

    #[test]
    fn points_of_every_small_size_near_tile_edges() {
        let mut rng = Rng(0x0123_4567_89ab_cdef);
        let rect = PixelRect::new(64, 32, 80, 48);
        for round in 0..4_000 {
            let size = [1u32, 2, 3][round % 3];
            // Positions within two pixels of the tile's sides.
            let near = |rng: &mut Rng, lo: i32, hi: i32| {
                let side = if rng.next(2) == 0 { lo } else { hi };
                (side * 16) + rng.range(-40, 40) as i32
            };
            let p = pt(
                near(&mut rng, 64, 80),
                near(&mut rng, 32, 48),
                500,
                [9, 8, 7],
            );
            // The square: the pixel containing p, grown to 3x3 around it;
            // for 2x2, the pixels sharing the corner nearest to p.
            let square = |c: i32| -> (i32, i32) {
                let cell = c.div_euclid(16);
                match size {
                    1 => (cell, cell),
                    3 => (cell - 1, cell + 1),
                    _ => {
                        let corner = cell + (c.rem_euclid(16) >= 8) as i32;
                        (corner - 1, corner)
                    }
                }
            };
            let ((xa, xb), (ya, yb)) = (square(p.pos.x), square(p.pos.y));
            let mut t: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
            let n = draw_point::<_, 16, 16>(&mut t, &rect, LESS_EQUAL, &p, size);
            let mut expected = 0;
            for y in 0..16 {
                for x in 0..16 {
                    let (i, j) = (x as i32 + 64, y as i32 + 32);
                    let hit = (xa..=xb).contains(&i) && (ya..=yb).contains(&j);
                    expected += hit as u32;
                    let want = if hit {
                        (Rgb888::new(9, 8, 7), 500)
                    } else {
                        (SENTINEL, u16::MAX)
                    };
                    assert_eq!(
                        (t.color(x, y), t.depth(x, y)),
                        (Some(want.0), Some(want.1)),
                        "{p:?} size {size}"
                    );
                }
            }
            assert_eq!(n, expected);
            // Depth tested: a point behind draws nothing.
            let mut behind = p;
            behind.z = 501;
            assert_eq!(
                draw_point::<_, 16, 16>(&mut t, &rect, LESS, &behind, size),
                0
            );
        }
        // Size 0 draws nothing; a big point fills the tile.
        let p = pt(70 * 16, 40 * 16, 0, [1; 3]);
        let mut t: TileBuffer<Rgb888, 16, 16> = TileBuffer::new(SENTINEL);
        assert_eq!(draw_point::<_, 16, 16>(&mut t, &rect, ALWAYS, &p, 0), 0);
        assert_eq!(
            draw_point::<_, 16, 16>(&mut t, &rect, ALWAYS, &p, 1000),
            256
        );
    }

    #[test]
    fn lerp_steps_match_the_formula() {
        let mut rng = Rng(0xfeed_f00d_1234_0042);
        for _ in 0..2_000 {
            let n = rng.next(300) as u32;
            let (v0, v1) = (rng.next(65_536) as i32, rng.next(65_536) as i32);
            let k0 = rng.next(n as u64 + 1) as u32;
            let mut l = Lerp::at(v0, v1, k0, n);
            for k in k0..=n {
                assert_eq!(
                    l.v as i64,
                    reference_value(v0 as i64, v1 as i64, k as i64, n as i64)
                );
                l.step();
            }
        }
        // The largest step counts, entering near the end.
        let n = (1 << 28) - 1;
        let mut l = Lerp::at(65_535, 0, n - 3, n);
        for k in n - 3..=n {
            assert_eq!(l.v as i64, reference_value(65_535, 0, k as i64, n as i64));
            l.step();
        }
    }
}
