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
    fn pass(new: u16, old: u16) -> bool;
}

macro_rules! depth_fn {
    ($name:ident, |$n:ident, $o:ident| $e:expr) => {
        pub(crate) struct $name;
        impl DepthFn for $name {
            #[inline(always)]
            fn pass($n: u16, $o: u16) -> bool {
                $e
            }
        }
    };
}
depth_fn!(DAlways, |_n, _o| true);
depth_fn!(DLess, |n, o| n < o);
depth_fn!(DLessEqual, |n, o| n <= o);
depth_fn!(DEqual, |n, o| n == o);
depth_fn!(DGreaterEqual, |n, o| n >= o);
depth_fn!(DGreater, |n, o| n > o);

/// One interpolated attribute: value at vertex 0 (with rounding bias) and
/// its per-pixel gradients, all with `F` fraction bits.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plane {
    base: i64,
    gx: i64,
    gy: i64,
    lo: i64,
    hi: i64,
}

impl Plane {
    /// `frac` fraction bits; `values` at the three vertices, `max` the
    /// largest value the attribute may take.
    #[inline]
    fn new(v: &[SubPoint; 3], values: [i64; 3], area2: i64, frac: u32, max: i64) -> Self {
        let d1 = values[1] - values[0];
        let d2 = values[2] - values[0];
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        let scale = 1i64 << (frac + SUBPIXEL_BITS);
        let gx = div_round_signed((d1 * y2 - d2 * y1) * scale, area2);
        let gy = div_round_signed((d2 * x1 - d1 * x2) * scale, area2);
        let bias = 1i64 << (frac - 1);
        Self {
            base: (values[0] << frac) + bias,
            gx: gx.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT),
            gy: gy.clamp(-GRADIENT_LIMIT, GRADIENT_LIMIT),
            lo: bias,
            hi: (max << frac) + bias,
        }
    }

    /// The value at the centre of pixel `(i, j)`, relative to vertex `o`.
    #[inline(always)]
    fn at(&self, o: SubPoint, i: i32, j: i32) -> i32 {
        let dx = ((i as i64) << SUBPIXEL_BITS) + HALF_PIXEL as i64 - o.x as i64;
        let dy = ((j as i64) << SUBPIXEL_BITS) + HALF_PIXEL as i64 - o.y as i64;
        let v = self.base + ((self.gx * dx + self.gy * dy) >> SUBPIXEL_BITS);
        v.clamp(self.lo, self.hi) as i32
    }

    #[inline(always)]
    fn step(&self) -> i32 {
        self.gx.clamp(i32::MIN as i64, i32::MAX as i64) as i32
    }
}

/// `n / d` rounded to nearest for any nonzero `d`.
#[inline]
fn div_round_signed(n: i64, d: i64) -> i64 {
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    crate::vertex::div_round(n, d)
}

/// A triangle ready to shade: its vertex 0 and attribute planes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleSetup {
    origin: SubPoint,
    z: Plane,
    rgb: [Plane; 3],
    flat: [u8; 3],
}

impl TriangleSetup {
    /// Sets up the planes of a non-degenerate triangle (`area2 != 0`).
    /// Colour planes are only computed for `gouraud`; `flat` is the colour
    /// used otherwise.
    #[inline]
    pub(crate) fn new(
        v: &[SubPoint; 3],
        area2: i64,
        z: [u16; 3],
        colors: &[[u8; 3]; 3],
        flat: [u8; 3],
        gouraud: bool,
    ) -> Self {
        let zp = Plane::new(
            v,
            [z[0] as i64, z[1] as i64, z[2] as i64],
            area2,
            Z_FRAC,
            65_535,
        );
        let mut rgb = [Plane::default(); 3];
        if gouraud {
            for (c, p) in rgb.iter_mut().enumerate() {
                let vals = [
                    colors[0][c] as i64,
                    colors[1][c] as i64,
                    colors[2][c] as i64,
                ];
                *p = Plane::new(v, vals, area2, C_FRAC, 255);
            }
        }
        Self {
            origin: v[0],
            z: zp,
            rgb,
            flat,
        }
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
    let mut z = s.z.at(s.origin, x0, j);
    let gz = s.z.step();
    let (a, b) = ((x0 - ox) as usize, (x1 - ox) as usize);
    let mut n = 0;
    for (c, d) in color[a..b].iter_mut().zip(depth[a..b].iter_mut()) {
        let zz = (z >> Z_FRAC) as u16;
        if D::pass(zz, *d) {
            if WRITE {
                *d = zz;
            }
            *c = flat;
            n += 1;
        }
        z = z.wrapping_add(gz);
    }
    n
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
    let o = s.origin;
    let mut z = s.z.at(o, x0, j);
    let mut r = s.rgb[0].at(o, x0, j);
    let mut g = s.rgb[1].at(o, x0, j);
    let mut b = s.rgb[2].at(o, x0, j);
    let (gz, gr, gg, gb) = (
        s.z.step(),
        s.rgb[0].step(),
        s.rgb[1].step(),
        s.rgb[2].step(),
    );
    let (a0, a1) = ((x0 - ox) as usize, (x1 - ox) as usize);
    let mut n = 0;
    for (c, d) in color[a0..a1].iter_mut().zip(depth[a0..a1].iter_mut()) {
        let zz = (z >> Z_FRAC) as u16;
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
    n
}

impl TriangleSetup {
    /// The flat colour of the triangle.
    #[inline]
    pub(crate) fn flat_color<C: From<Rgb888>>(&self) -> C {
        C::from(Rgb888::new(self.flat[0], self.flat[1], self.flat[2]))
    }
}
