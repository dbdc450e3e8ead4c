//! Attribute set-up and span shading: depth test, flat or Gouraud colour.
//!
//! Following Hecker, each attribute `a` (depth and the three colour
//! channels) is a plane over the screen, `a(x, y) = a0 + A (x - x0) +
//! B (y - y0)`, whose gradients `A = ∂a/∂x` and `B = ∂a/∂y` are computed
//! once per triangle from the three vertices (Cramer's rule over twice the
//! signed area). At the first pixel of every span the plane is evaluated
//! directly from the vertex with one `i64` multiply-add per gradient, so
//! error never accumulates from row to row; along the span the value steps
//! by the `i32` x gradient. Depth uses 14 fraction bits and colour 16, each
//! biased by one half so truncation rounds; the bias plus a clamp at the
//! span start keeps every value inside its range although each x step
//! carries up to half a unit in the last place of rounding error (at most
//! `TILE_W / 2` such units over a span, far below the half-unit margin for
//! tiles up to 1,024 pixels wide).
//!
//! Gradients are clamped to ±2^40 so the span-start products fit `i64`.
//! Only a sliver narrower than about 1/1,000 pixel can reach that clamp;
//! its at most one pixel per row keeps a depth within its triangle's range.
//!
//! The span loops have no branch where that pays (flat spans, and Gouraud
//! spans of 8 pixels or more): the depth stored is the min or max of the
//! new and the old depth (`DepthFn::merge`), the colour a select and the
//! count a sum, so the compiler can vectorize them. Depth is stepped as
//! `z << 2` in a `u32`, whose upper half is then the 16-bit depth. The
//! results are exactly those of the plain per-pixel test.

use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use embedded_graphics::pixelcolor::Rgb888;

/// Fraction bits of interpolated depth.
pub const Z_FRAC: u32 = 14;
/// Fraction bits of interpolated colour channels.
pub const C_FRAC: u32 = 16;
const GRADIENT_LIMIT: i64 = 1 << 40;

/// The depth comparison of a fragment against the depth buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum DepthTest {
    /// Always passes (no depth test).
    Always,
    /// Passes when nearer.
    Less,
    /// Passes when nearer or equal: later triangles win ties (default).
    #[default]
    LessEqual,
    /// Passes when equal.
    Equal,
    /// Passes when farther or equal.
    GreaterEqual,
    /// Passes when farther.
    Greater,
    /// Never passes.
    Never,
}

/// A depth comparison, monomorphized into the span loop.
pub(crate) trait DepthFn {
    /// Whether a fragment at depth `new` passes against the stored `old`.
    fn pass(new: u16, old: u16) -> bool;
    /// The depth to store after testing `new` against `old` with depth
    /// writes on: `if pass(new, old) { new } else { old }`, written as the
    /// min, max or plain value it always equals, so the span loops need no
    /// branch or conditional store.
    fn merge(new: u16, old: u16) -> u16;
}

macro_rules! depth_fn {
    ($name:ident, |$n:ident, $o:ident| $e:expr, |$mn:ident, $mo:ident| $m:expr) => {
        pub(crate) struct $name;
        impl DepthFn for $name {
            #[inline(always)]
            fn pass($n: u16, $o: u16) -> bool {
                $e
            }
            #[inline(always)]
            fn merge($mn: u16, $mo: u16) -> u16 {
                $m
            }
        }
    };
}
depth_fn!(DAlways, |_n, _o| true, |n, _o| n);
depth_fn!(DLess, |n, o| n < o, |n, o| n.min(o));
depth_fn!(DLessEqual, |n, o| n <= o, |n, o| n.min(o));
depth_fn!(DEqual, |n, o| n == o, |_n, o| o);
depth_fn!(DGreaterEqual, |n, o| n >= o, |n, o| n.max(o));
depth_fn!(DGreater, |n, o| n > o, |n, o| n.max(o));

/// One interpolated attribute, with `frac` fraction bits: its value at the
/// centre of pixel `(i, j)` is `(gx16 i + gy16 j + k) >> SUBPIXEL_BITS`,
/// clamped to `lo..=hi`.
///
/// That is the plane `base + ((gx dx + gy dy) >> SUBPIXEL_BITS)` through
/// vertex `o`, with `dx = SUBPIXEL i + HALF_PIXEL - o.x` (likewise `dy`) and
/// `base` the biased value at `o`, regrouped exactly: the terms that do not
/// depend on the pixel are summed once into `k` (`base` times `SUBPIXEL`
/// passes through the shift unchanged). Every term stays below 2^59 for
/// screen coordinates inside the guard band and pixels inside the frame.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plane {
    gx16: i64,
    gy16: i64,
    k: i64,
    lo: i64,
    hi: i64,
    /// The x gradient saturated to `i32`: the step along a span.
    step: i32,
}

/// The geometry every plane of a triangle shares: vertex 0 and the edge
/// vectors from it, with signs chosen so that the Cramer denominator `area`
/// (twice the absolute area) is positive.
#[derive(Clone, Copy, Debug)]
struct Basis {
    o: SubPoint,
    x1: i64,
    y1: i64,
    x2: i64,
    y2: i64,
    area: i64,
}

impl Basis {
    #[inline(always)]
    fn new(v: &[SubPoint; 3], area2: i64) -> Self {
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        // n / d with d < 0 is (-n) / (-d); negating the edge vectors negates
        // both numerators exactly, so every division below has a positive
        // denominator and the same rounded result.
        let s = if area2 < 0 { -1 } else { 1 };
        Self {
            o: v[0],
            x1: s * x1,
            y1: s * y1,
            x2: s * x2,
            y2: s * y2,
            area: s * area2,
        }
    }
}

impl Plane {
    /// `frac` fraction bits; `values` at the three vertices, `max` the
    /// largest value the attribute may take.
    #[inline(always)]
    fn new(f: &Basis, values: [i64; 3], frac: u32, max: i64) -> Self {
        let d1 = values[1] - values[0];
        let d2 = values[2] - values[0];
        let scale = 1i64 << (frac + SUBPIXEL_BITS);
        let gx = crate::vertex::div_round((d1 * f.y2 - d2 * f.y1) * scale, f.area);
        let gy = crate::vertex::div_round((d2 * f.x1 - d1 * f.x2) * scale, f.area);
        let gx = gx.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
        let gy = gy.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT);
        let bias = 1i64 << (frac - 1);
        let base = (values[0] << frac) + bias;
        Self {
            gx16: gx << SUBPIXEL_BITS,
            gy16: gy << SUBPIXEL_BITS,
            k: (base << SUBPIXEL_BITS)
                + gx * (HALF_PIXEL as i64 - f.o.x as i64)
                + gy * (HALF_PIXEL as i64 - f.o.y as i64),
            lo: bias,
            hi: (max << frac) + bias,
            step: gx.clamp(i32::MIN as i64, i32::MAX as i64) as i32,
        }
    }

    /// The value at the centre of pixel `(i, j)`.
    #[inline(always)]
    fn at(&self, i: i32, j: i32) -> i32 {
        let v = (self.gx16 * i as i64 + self.gy16 * j as i64 + self.k) >> SUBPIXEL_BITS;
        // `lo < hi`, so this is `clamp` without its panic check.
        v.max(self.lo).min(self.hi) as i32
    }

    #[inline(always)]
    fn step(&self) -> i32 {
        self.step
    }
}

/// A triangle ready to shade: its attribute planes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleSetup {
    z: Plane,
    rgb: [Plane; 3],
}

impl TriangleSetup {
    /// Sets up the planes of a non-degenerate triangle (`area2 != 0`).
    /// Colour planes are only computed for `gouraud` (flat shading needs
    /// only depth).
    #[inline]
    pub(crate) fn new(
        v: &[SubPoint; 3],
        area2: i64,
        z: [u16; 3],
        colors: &[[u8; 3]; 3],
        gouraud: bool,
    ) -> Self {
        let f = Basis::new(v, area2);
        let zp = Plane::new(&f, [z[0] as i64, z[1] as i64, z[2] as i64], Z_FRAC, 65_535);
        let mut rgb = [Plane::default(); 3];
        if gouraud {
            for (c, p) in rgb.iter_mut().enumerate() {
                let vals = [
                    colors[0][c] as i64,
                    colors[1][c] as i64,
                    colors[2][c] as i64,
                ];
                *p = Plane::new(&f, vals, C_FRAC, 255);
            }
        }
        Self { z: zp, rgb }
    }
}

/// Where a span lies: screen row `j`, columns `x0..x1`, in a tile row whose
/// first pixel is screen column `ox`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpanPos {
    pub ox: i32,
    pub j: i32,
    pub x0: i32,
    pub x1: i32,
}

/// The 16-bit depth of an interpolated depth `z` held as `z << 2`
/// (`Z_FRAC = 14`): the integer part `(z >> 14) as u16` is then the upper
/// half of the `u32`, and stepping `z << 2` by `gz << 2` with wrapping
/// arithmetic keeps exactly the bits that matter. Taking the upper half
/// with an arithmetic shift lets x86 pack eight of them with one
/// signed-saturating instruction.
#[inline(always)]
fn depth16(z: u32) -> u16 {
    ((z as i32) >> 16) as u16
}

/// Shades one span: `color` and `depth` are the tile row. Returns the
/// number of fragments written.
#[inline(always)]
pub(crate) fn span_flat<C: Copy, D: DepthFn, const WRITE: bool>(
    s: &TriangleSetup,
    flat: C,
    color: &mut [C],
    depth: &mut [u16],
    sp: SpanPos,
) -> u32 {
    let SpanPos { ox, j, x0, x1 } = sp;
    // Depth with its 16 integer bits in the upper half of a u32 (see
    // `depth16`).
    let mut z = (s.z.at(x0, j) as u32) << (16 - Z_FRAC);
    let gz = (s.z.step() as u32) << (16 - Z_FRAC);
    let (a, b) = ((x0 - ox) as usize, (x1 - ox) as usize);
    // A span is at most a tile row, at most 1,024 pixels: a u16 count
    // cannot overflow, and vectorizes in 16-bit lanes.
    let mut n = 0u16;
    // Branch-free, so the compiler can vectorize it.
    for (c, d) in color[a..b].iter_mut().zip(depth[a..b].iter_mut()) {
        let zz = depth16(z);
        let old = *d;
        let pass = D::pass(zz, old);
        if WRITE {
            *d = D::merge(zz, old);
        }
        *c = if pass { flat } else { *c };
        n += pass as u16;
        z = z.wrapping_add(gz);
    }
    n as u32
}

/// Like [`span_flat`], with colour interpolated per pixel.
#[inline(always)]
pub(crate) fn span_gouraud<C: Copy + From<Rgb888>, D: DepthFn, const WRITE: bool>(
    s: &TriangleSetup,
    color: &mut [C],
    depth: &mut [u16],
    sp: SpanPos,
) -> u32 {
    let SpanPos { ox, j, x0, x1 } = sp;
    let mut z = (s.z.at(x0, j) as u32) << (16 - Z_FRAC);
    let mut r = s.rgb[0].at(x0, j);
    let mut g = s.rgb[1].at(x0, j);
    let mut b = s.rgb[2].at(x0, j);
    let (gz, gr, gg, gb) = (
        (s.z.step() as u32) << (16 - Z_FRAC),
        s.rgb[0].step(),
        s.rgb[1].step(),
        s.rgb[2].step(),
    );
    let (a0, a1) = ((x0 - ox) as usize, (x1 - ox) as usize);
    let (color, depth) = (&mut color[a0..a1], &mut depth[a0..a1]);
    // Short spans (most of them, in a detailed mesh): the colour is only
    // computed for fragments that pass.
    if color.len() < 8 {
        let mut n = 0;
        for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
            let zz = depth16(z);
            if D::pass(zz, *d) {
                if WRITE {
                    *d = zz;
                }
                *c = C::from(Rgb888::new(
                    (r >> C_FRAC) as u8,
                    (g >> C_FRAC) as u8,
                    (b >> C_FRAC) as u8,
                ));
                n += 1;
            }
            z = z.wrapping_add(gz);
            r = r.wrapping_add(gr);
            g = g.wrapping_add(gg);
            b = b.wrapping_add(gb);
        }
        return n;
    }
    // Longer spans: as in `span_flat`, a u16 count and no branch in the
    // loop, so the compiler can vectorize it.
    let mut n = 0u16;
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        let old = *d;
        let pass = D::pass(zz, old);
        if WRITE {
            *d = D::merge(zz, old);
        }
        let shaded = C::from(Rgb888::new(
            (r >> C_FRAC) as u8,
            (g >> C_FRAC) as u8,
            (b >> C_FRAC) as u8,
        ));
        *c = if pass { shaded } else { *c };
        n += pass as u16;
        z = z.wrapping_add(gz);
        r = r.wrapping_add(gr);
        g = g.wrapping_add(gg);
        b = b.wrapping_add(gb);
    }
    n as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn merge_matches_pass<D: DepthFn>() {
        let values = [0u16, 1, 2, 1000, 32_767, 32_768, 65_534, 65_535];
        for &n in &values {
            for &o in &values {
                let expected = if D::pass(n, o) { n } else { o };
                assert_eq!(D::merge(n, o), expected, "new {n}, old {o}");
            }
        }
    }

    #[test]
    fn depth_merge_is_the_written_depth() {
        merge_matches_pass::<DAlways>();
        merge_matches_pass::<DLess>();
        merge_matches_pass::<DLessEqual>();
        merge_matches_pass::<DEqual>();
        merge_matches_pass::<DGreaterEqual>();
        merge_matches_pass::<DGreater>();
    }

    #[test]
    fn depth16_is_the_integer_part() {
        for z in [
            0i32,
            1 << 13,
            5 << 14,
            (65_535 << 14) + (1 << 13),
            (1 << 30) - 1,
        ] {
            for k in 0..5i32 {
                let gz = -3_000_017 + 1_500_000 * k;
                let exact = z.wrapping_add(gz.wrapping_mul(k));
                let shifted =
                    ((z as u32) << 2).wrapping_add(((gz as u32) << 2).wrapping_mul(k as u32));
                assert_eq!(depth16(shifted), (exact >> Z_FRAC) as u16);
            }
        }
    }
}
