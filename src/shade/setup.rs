//! The attribute planes of a triangle: gradients by Cramer's rule over
//! twice its signed area, computed once per triangle-tile pair, and each
//! plane's value at the start of a span (see the [parent module](super)
//! for the method, the fixed-point formats and why the `i32` evaluation is
//! exact).

use super::sliver::wide_start;
use super::small::{Small, SMALL_EDGE, SMALL_SETUP};
use super::{C_FRAC, GRADIENT_LIMIT, Z_FRAC};
use crate::math::Divisor;
use crate::raster::{SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use crate::vertex::ScreenVertex;
use core::num::{NonZeroU32, NonZeroU64};

/// One interpolated attribute, with `frac` fraction bits: its value at the
/// centre of pixel `(i, j)` is `gx i + gy j + k`.
///
/// That is the plane `base + floor((gx dx + gy dy) / SUBPIXEL)` through
/// vertex `o`, with `dx = SUBPIXEL i + HALF_PIXEL - o.x` (likewise `dy`)
/// and `base` the biased value at `o`, regrouped exactly: `gx SUBPIXEL i`
/// is a multiple of `SUBPIXEL`, so it passes through the floor unchanged,
/// and the terms that do not depend on the pixel are summed once into `k`.
///
/// # Why `i32` arithmetic is exact
///
/// The gradients are rounded to the nearest integer, so at a pixel centre
/// `(dx, dy)` sub-pixels from `o` the value is within
/// `(|dx| + |dy|) / 32 + 1` of the exact plane. Span starts are covered
/// centres, which lie in the triangle, where the exact plane is between
/// the smallest and largest vertex value; vertices lie within 2^18
/// sub-pixels of the origin and pixels within 2^16, so the value is within
/// 20,481 of `lo..=hi`, far inside `i32` (`hi < 2^30`). The sum
/// `gx i + gy j + k` may wrap on the way there, but wrapping arithmetic is
/// exact modulo 2^32, so its result is that value exactly, as the `i64`
/// sum would give. This holds unless a gradient had to be clamped to
/// ±2^40 (only for a sliver narrower than about 1/1,000 pixel, see the
/// module docs); then [`TriangleSetup::wide`] is set and the span starts
/// come from [`wide_start`], in `i64`, which never wraps.
///
/// The value is then clamped to `lo..=hi`, as a span starts there and
/// steps from there.
///
/// Along a span the value steps by `gx`. A span of two or more pixels has
/// two covered centres one pixel apart, where the exact values differ by
/// at most the attribute's range, so `|gx| < 2^30` there and the step is
/// exact too.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plane {
    pub(super) gx: i32,
    pub(super) gy: i32,
    pub(super) k: i32,
}

/// The geometry every plane of a triangle shares: the edge vectors from
/// vertex 0, with signs chosen so that the Cramer denominator (twice the
/// absolute area) is positive, that denominator, and the offset of the
/// first pixel centre from vertex 0.
#[derive(Clone, Copy, Debug)]
pub(super) struct Basis {
    pub(super) x1: i64,
    pub(super) y1: i64,
    pub(super) x2: i64,
    pub(super) y2: i64,
    /// Twice the absolute area, by which all eight gradients are divided
    /// (through its reciprocal on 32-bit targets, see [`Divisor`]; not
    /// made for a [`Small`] triangle, whose gradients take 32-bit
    /// divisions instead).
    pub(super) area: Divisor,
    /// Twice the absolute area, for the divisions of a [`Small`] triangle's
    /// gradients that do not fit its 32-bit ones.
    pub(super) area64: NonZeroU64,
    /// Half of twice the absolute area, for rounding.
    pub(super) half: u64,
    /// `HALF_PIXEL - o.x` and `HALF_PIXEL - o.y` of vertex 0.
    pub(super) ox: i64,
    pub(super) oy: i64,
    /// On 32-bit targets, a triangle whose edge vectors are below
    /// [`SMALL_EDGE`] in magnitude.
    pub(super) small: Option<Small>,
}

impl Basis {
    #[inline(always)]
    pub(super) fn new(v: &[SubPoint; 3]) -> Self {
        Self::with_small(v, SMALL_SETUP)
    }

    /// [`Basis::new`], with small triangles set up in 32-bit divisions
    /// when `small_setup` (the tests compare both on the host).
    #[inline(always)]
    pub(super) fn with_small(v: &[SubPoint; 3], small_setup: bool) -> Self {
        let (x1, y1) = (v[1].x as i64 - v[0].x as i64, v[1].y as i64 - v[0].y as i64);
        let (x2, y2) = (v[2].x as i64 - v[0].x as i64, v[2].y as i64 - v[0].y as i64);
        // Twice the signed area, as `crate::raster::signed_area2` (the
        // vertices lie within the guard band).
        let area2 = crate::raster::signed_area2_banded(v);
        // Callers never set up a zero-area triangle (it has no spans); the
        // fallback only keeps this total.
        let area = NonZeroU64::new(area2.unsigned_abs()).unwrap_or(NonZeroU64::MIN);
        // n / d with d < 0 is (-n) / (-d); negating the edge vectors negates
        // every numerator exactly, so every division has a positive
        // denominator and the same rounded result.
        let s = if area2 < 0 { -1 } else { 1 };
        let small = match small_setup && [x1, y1, x2, y2].iter().all(|c| c.abs() < SMALL_EDGE) {
            // Twice the area of a small triangle is below 2^21.
            true => NonZeroU32::new(area.get() as u32).map(|area| Small {
                area,
                half: area.get() / 2,
            }),
            false => None,
        };
        Self {
            x1: s * x1,
            y1: s * y1,
            x2: s * x2,
            y2: s * y2,
            area: match small {
                Some(_) => Divisor::new(NonZeroU64::MIN),
                None => Divisor::new(area),
            },
            area64: area,
            half: area.get() / 2,
            ox: HALF_PIXEL as i64 - v[0].x as i64,
            oy: HALF_PIXEL as i64 - v[0].y as i64,
            small,
        }
    }

    /// `n / area` rounded to nearest, ties away from zero, as
    /// the vertex stage rounds too.
    #[inline(always)]
    pub(super) fn div_round(&self, n: i64) -> i64 {
        if self.small.is_some() {
            // A small triangle's attribute beyond its 32-bit divisions
            // (the perspective weights): a plain division.
            let q = ((n.unsigned_abs() + self.half) / self.area64) as i64;
            return if n >= 0 { q } else { -q };
        }
        // |n| < 2^57 and half < 2^39: within `Reciprocal::div`'s range.
        if n >= 0 {
            self.area.div(n as u64 + self.half) as i64
        } else {
            -(self.area.div(n.unsigned_abs() + self.half) as i64)
        }
    }
}

impl Basis {
    /// The gradients `(gx, gy)` of an attribute with `values` at the three
    /// vertices and `frac` fraction bits, per pixel, rounded to nearest
    /// (Cramer's rule), not yet clamped.
    #[inline(always)]
    pub(super) fn gradients(&self, values: [i64; 3], frac: u32) -> (i64, i64) {
        let d1 = values[1] - values[0];
        let d2 = values[2] - values[0];
        let shift = frac + SUBPIXEL_BITS;
        if let Some(small) = &self.small {
            if d1.abs() < 1 << 16 && d2.abs() < 1 << 16 {
                // |d| < 2^16 and edge vectors below 2^10: the numerators
                // are below 2^27, and the shift at most 20.
                let [x1, y1, x2, y2] = [
                    self.x1 as i32,
                    self.y1 as i32,
                    self.x2 as i32,
                    self.y2 as i32,
                ];
                let (d1, d2) = (d1 as i32, d2 as i32);
                return (
                    small.div_round(d1 * y2 - d2 * y1, shift),
                    small.div_round(d2 * x1 - d1 * x2, shift),
                );
            }
            if frac == 0 && d1.abs() <= 1 << 28 && d2.abs() <= 1 << 28 {
                // The perspective planes (values up to 2^28, no fraction
                // bits): numerators below 2^39 before the shift of 4, so
                // within `div_round_wide`'s 2^43.
                return (
                    small.div_round_wide((d1 * self.y2 - d2 * self.y1) << shift),
                    small.div_round_wide((d2 * self.x1 - d1 * self.x2) << shift),
                );
            }
        }
        (
            self.div_round((d1 * self.y2 - d2 * self.y1) << shift),
            self.div_round((d2 * self.x1 - d1 * self.x2) << shift),
        )
    }

    /// The plane constant `k` of an attribute whose value at vertex 0 is
    /// `value`, in wrapping arithmetic: exact for gradients within
    /// ±[`GRADIENT_LIMIT`], no overflow check beyond.
    #[inline(always)]
    pub(super) fn constant_wrapping(&self, value: i64, frac: u32, (gx, gy): (i64, i64)) -> i64 {
        let base = (value << frac) + (1i64 << (frac - 1));
        let t = gx
            .wrapping_mul(self.ox)
            .wrapping_add(gy.wrapping_mul(self.oy));
        base.wrapping_add(t >> SUBPIXEL_BITS)
    }
}

impl Plane {
    /// The value at the centre of pixel `(i, j)`, exact (see the type's
    /// docs), not clamped to the attribute's range.
    #[inline(always)]
    pub(super) fn at(&self, i: i32, j: i32) -> i32 {
        // `k + gy j` first: two multiply-accumulates (wrapping, so any
        // order gives the same value).
        self.k
            .wrapping_add(self.gy.wrapping_mul(j))
            .wrapping_add(self.gx.wrapping_mul(i))
    }

    /// The step along a span (exact for every span of two pixels or more,
    /// see the type's docs).
    #[inline(always)]
    pub(super) fn step(&self) -> i32 {
        self.gx
    }
}

/// Depth interpolated with [`Z_FRAC`] bits and its half-unit bias: the
/// range of values that round to `0..=65535`.
pub(super) const Z_LO: i32 = 1 << (Z_FRAC - 1);
pub(super) const Z_HI: i32 = (65_535 << Z_FRAC) + Z_LO;
/// Likewise for colour channels, `0..=255` with [`C_FRAC`] bits.
pub(super) const C_LO: i32 = 1 << (C_FRAC - 1);
pub(super) const C_HI: i32 = (255 << C_FRAC) + C_LO;

/// The triangle the attribute set-up reads: its three screen vertices (in
/// submission order: vertex 0 anchors the planes).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corners<'a>(pub [&'a ScreenVertex; 3]);

impl Corners<'_> {
    /// The screen positions.
    #[inline(always)]
    pub(super) fn points(&self) -> [SubPoint; 3] {
        // Written out, as in `values`: `[T; 3]::map` is a call per use
        // where the optimiser does not inline it (the `size` profile).
        let [a, b, c] = self.0;
        [a.xy(), b.xy(), c.xy()]
    }

    /// The values of attribute `a` (0 depth, 1 to 3 red, green, blue) at
    /// the three vertices, and its fraction bits.
    #[inline(always)]
    pub(super) fn values(&self, a: usize) -> ([i64; 3], u32) {
        let [u, v, w] = &self.0;
        if a == 0 {
            ([u.z() as i64, v.z() as i64, w.z() as i64], Z_FRAC)
        } else {
            let c = a - 1;
            (
                [
                    u.channel(c) as i64,
                    v.channel(c) as i64,
                    w.channel(c) as i64,
                ],
                C_FRAC,
            )
        }
    }
}

/// A triangle ready to shade: its attribute planes (depth, then red,
/// green and blue for Gouraud shading).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleSetup {
    pub(super) planes: [Plane; 4],
    /// A gradient was beyond ±[`GRADIENT_LIMIT`]: span starts come from
    /// [`wide_start`] instead of `planes` (only the steps are used).
    pub(super) wide: bool,
    /// The depth step along a span: the depth plane's `gx`, kept here
    /// because a wide triangle's depth plane is replaced by one that is
    /// outside the depth range everywhere, so that [`TriangleSetup::start`]
    /// finds it there with the range tests it makes anyway, and tests no
    /// flag per span.
    pub(super) zstep: i32,
}

impl TriangleSetup {
    /// The set-up of `planes`, `wide` or not (see
    /// [`TriangleSetup::zstep`]).
    #[inline(always)]
    pub(super) fn finish(mut planes: [Plane; 4], wide: bool) -> Self {
        let zstep = planes[0].gx;
        if wide {
            planes[0] = Plane {
                gx: 0,
                gy: 0,
                k: i32::MIN,
            };
        }
        Self {
            planes,
            wide,
            zstep,
        }
    }

    /// Sets up the planes of a non-degenerate triangle. Colour planes are
    /// only computed for `gouraud` (flat shading needs only depth).
    #[inline(always)]
    pub(crate) fn new(t: &Corners<'_>, gouraud: bool) -> Self {
        let v = &t.points();
        if SMALL_SETUP {
            if let Some(s) = Self::small(v, t, gouraud) {
                return s;
            }
            if !cfg!(microraster_narrow_multiply) {
                return Self::with_basis_apart(&Basis::new(v), t, gouraud);
            }
        }
        Self::with_basis(&Basis::new(v), t, gouraud)
    }

    /// [`TriangleSetup::with_basis`] with the colour planes set up by one
    /// out-of-line function, called per channel
    /// ([`TriangleSetup::color_plane_apart`]), for 32-bit cores with a long
    /// multiply, whose small triangles take [`TriangleSetup::small`]: the
    /// general set-up is left for the others (large triangles, a few
    /// slivers and steep depths), rare on such cores, where its three
    /// colour planes unrolled took about 1.5 KB of flash (each plane's
    /// 64-bit reciprocal divisions are a dozen long multiplies).
    ///
    /// The OLED firmware 46,196 -> 44,724 B, microraster's code in it
    /// 25,584 -> 24,038 B; Cortex-M3 `demo` 4,113,898 -> 4,115,893
    /// instructions, `rock` 3,387,223 -> 3,387,318, `fill` 15.12 -> 15.11
    /// per pixel. Depth's plane stays inline: all four planes out of line
    /// (one function, the attribute a run-time argument) took 2.2 KB off
    /// but `fill` to 15.20 and `demo` +5,061. Not on ARMv6-M (`demo`
    /// +14,252: the inline small set-up beside it lost registers).
    #[inline(always)]
    pub(super) fn with_basis_apart(f: &Basis, t: &Corners<'_>, gouraud: bool) -> Self {
        let mut range = 0u64;
        let mut planes = [Plane::default(); 4];
        planes[0] = Self::plane(f, t, 0, &mut range);
        if gouraud {
            for (a, p) in planes.iter_mut().enumerate().skip(1) {
                *p = Self::color_plane_apart(f, t, a, &mut range);
            }
        }
        Self::finish(planes, range >= 2 * GRADIENT_LIMIT as u64)
    }

    /// [`TriangleSetup::plane`] of colour channel `a - 1`, out of line (see
    /// [`TriangleSetup::with_basis_apart`]).
    #[inline(never)]
    fn color_plane_apart(f: &Basis, t: &Corners<'_>, a: usize, range: &mut u64) -> Plane {
        let [u, v, w] = &t.0;
        let c = a - 1;
        let values = [
            u.channel(c) as i64,
            v.channel(c) as i64,
            w.channel(c) as i64,
        ];
        Self::plane_of(f, values, super::C_FRAC, range)
    }

    /// [`TriangleSetup::new`] on the triangle's [`Basis`] `f`, which the
    /// perspective set-up shares.
    #[inline(always)]
    pub(super) fn with_basis(f: &Basis, t: &Corners<'_>, gouraud: bool) -> Self {
        // Or-ing `gradient + LIMIT` over all gradients: below 2^41 only if
        // every one is within ±LIMIT (2^40 itself is sent to the wide path
        // too, which gives the same values).
        let mut range = 0u64;
        // Written out rather than a loop over the attributes: each plane's
        // shifts are then constants and the shared values stay in
        // registers, also where the optimiser would not unroll a loop (the
        // `size` profile, BENCHMARKS.md).
        let z = Self::plane(f, t, 0, &mut range);
        let planes = if gouraud {
            [
                z,
                Self::plane(f, t, 1, &mut range),
                Self::plane(f, t, 2, &mut range),
                Self::plane(f, t, 3, &mut range),
            ]
        } else {
            [z, Plane::default(), Plane::default(), Plane::default()]
        };
        Self::finish(planes, range >= 2 * GRADIENT_LIMIT as u64)
    }

    /// The plane of attribute `a` (see [`Corners::values`]) over the
    /// basis `f`, its gradients or-ed into `range` (offset by the limit).
    #[inline(always)]
    fn plane(f: &Basis, t: &Corners<'_>, a: usize, range: &mut u64) -> Plane {
        let (values, frac) = t.values(a);
        Self::plane_of(f, values, frac, range)
    }

    /// [`TriangleSetup::plane`] of the attribute with `values` at the
    /// vertices and `frac` fraction bits.
    #[inline(always)]
    fn plane_of(f: &Basis, values: [i64; 3], frac: u32, range: &mut u64) -> Plane {
        let g = f.gradients(values, frac);
        *range |= (g.0 + GRADIENT_LIMIT) as u64 | (g.1 + GRADIENT_LIMIT) as u64;
        // Wrapping to i32 keeps everything `Plane::at` needs. Within ±LIMIT
        // the constant does not wrap; beyond, its wrapped value is not used
        // (a wide triangle's starts come from `wide_start`).
        let k = f.constant_wrapping(values[0], frac, g);
        Plane {
            gx: g.0 as i32,
            gy: g.1 as i32,
            k: k as i32,
        }
    }

    /// [`TriangleSetup::new`] for the span loops, Gouraud (`GOURAUD`) or
    /// flat. Inlined into each span loop on a 64-bit host, where that
    /// measured fastest; on 32-bit targets one copy for each shading, out
    /// of line, rather than one in each of the eight span loops of a colour
    /// type (over a kilobyte of flash each), and the span loops keep their
    /// registers.
    ///
    /// A Gouraud set-up's [`zstep`](TriangleSetup::zstep) is shifted for
    /// its span loop ([`TriangleSetup::span_zstep`]); a flat one's is not.
    #[inline(always)]
    pub(crate) fn for_spans<const GOURAUD: bool>(t: &Corners<'_>) -> Self {
        if GOURAUD {
            Self::gouraud(t).span_zstep()
        } else {
            Self::flat(t)
        }
    }

    /// This set-up with its depth step shifted left by `16 - Z_FRAC`
    /// (wrapping), as the Gouraud span loop steps depth (see `depth16`):
    /// once per triangle, where each span shifted it (the set-up's rare
    /// path lets it escape, so the optimiser made the shift again for
    /// every span). Cortex-M3 `demo` 3,925,390 -> 3,918,578 instructions,
    /// `rock` 3,225,860 -> 3,220,055. Only for the Gouraud span loop
    /// ([`TriangleSetup::for_spans`]): the flat loop given the shifted
    /// step moved its registers on the Cortex-M4F (`fill` 15.19 -> 16.03
    /// a pixel, the M3's unchanged), and the shifted step in every set-up
    /// moved the fragment-shader loops' registers (M3
    /// `fill-nearest-affine` 49.79 -> 54.97 per pixel, `fill-gouraud-exact`
    /// 67.86 -> 73.02), though it took the M3's `fill` from 15.06 to
    /// 14.32.
    #[inline(always)]
    fn span_zstep(mut self) -> Self {
        self.zstep = ((self.zstep as u32) << (16 - super::Z_FRAC)) as i32;
        self
    }

    /// [`TriangleSetup::for_spans`] for the span loops that nearly every
    /// frame takes (the caller's choice), with the [`Small`] set-up
    /// inlined on 32-bit cores with a long multiply: its planes are then
    /// written where the span loop reads them, without a call, the
    /// returned set-up's stores through a pointer and the spills around
    /// them. Any other triangle takes the out-of-line set-up.
    ///
    /// Cortex-M3: `demo` 4,442,124 -> 4,427,326 instructions, `demo-flat`
    /// 3,882,021 -> 3,758,164, `rock` 3,641,659 -> 3,629,468, `fill`
    /// 15.70 -> 15.78 per pixel (its quads are not small: the test, then
    /// the call); about 1,080 B more flash for one colour type. Only
    /// there: inlined in every span loop, with the general set-up too,
    /// `demo` gave 4,419,784, but the set-up's copies overflowed the
    /// flash of a firmware that links many span loops (`icount` with
    /// `demo-textured-lit`). Not on the Thumb-1 cores, where the
    /// out-of-line set-up measured cheaper (ARMv6-M `demo` 10,241,926,
    /// inlined 10,272,942).
    #[inline(always)]
    pub(crate) fn for_spans_inline<const GOURAUD: bool>(t: &Corners<'_>) -> Self {
        if SMALL_SETUP && !cfg!(microraster_narrow_multiply) {
            if let Some(s) = Self::small(&t.points(), t, GOURAUD) {
                return if GOURAUD { s.span_zstep() } else { s };
            }
        }
        Self::for_spans::<GOURAUD>(t)
    }

    /// [`TriangleSetup::new`] of a Gouraud triangle.
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    pub(super) fn gouraud(t: &Corners<'_>) -> Self {
        Self::new(t, true)
    }

    /// [`TriangleSetup::new`] of a flat triangle.
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    pub(super) fn flat(t: &Corners<'_>) -> Self {
        Self::new(t, false)
    }

    /// Depth at the centre of pixel `(i, j)`, in `Z_LO..=Z_HI` (as
    /// [`TriangleSetup::start`], for depth alone).
    #[inline(always)]
    pub(crate) fn z_start(&self, t: &Corners<'_>, i: i32, j: i32) -> i32 {
        if self.wide {
            return wide_start(t, i, j)[0];
        }
        // Constant bounds: `clamp`'s check of them is done at compile
        // time. (A test and branch as in `start` made the flat span loops
        // slower on the Cortex-M3: `fill` 16.17 -> 17.10 per pixel.)
        self.planes[0].at(i, j).clamp(Z_LO, Z_HI)
    }
    /// The steps along a span of depth, red, green and blue.
    #[inline(always)]
    pub(super) fn steps(&self) -> [i32; 4] {
        [
            self.zstep,
            self.planes[1].step(),
            self.planes[2].step(),
            self.planes[3].step(),
        ]
    }

    /// Depth, red, green and blue at the centre of pixel `(i, j)`, for
    /// [`TriangleSetup::wide`] triangles from [`wide_start`].
    ///
    /// Each value is clamped to its range, but first tested: a covered
    /// pixel's values are almost always inside (see [`Plane`]), and an
    /// unsigned comparison with a constant per attribute and a branch that
    /// is not taken cost less than two comparisons and selects per
    /// attribute with the bounds built in registers (the Cortex-M3).
    ///
    /// Where the target has SIMD for the span loops (64-bit hosts), the
    /// clamps as selects measured faster (x86-64 `demo` 5,248,309
    /// instructions, 5,264,430 with the tests; `rock` 4,406,488 and
    /// 4,407,977).
    #[inline(always)]
    pub(crate) fn start(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        if super::VECTOR_LOOPS {
            self.start_selects(t, i, j)
        } else {
            self.start_tested(t, i, j)
        }
    }

    /// [`TriangleSetup::start`] with the clamps as selects.
    #[inline(always)]
    pub(super) fn start_selects(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        if self.wide {
            return wide_start(t, i, j);
        }
        clamped(self.values_at(i, j))
    }

    /// [`TriangleSetup::start`] with the values tested first.
    #[inline(always)]
    pub(super) fn start_tested(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        let v = self.values_at(i, j);
        if z_inside(v[0]) && c_inside(v[1]) && c_inside(v[2]) && c_inside(v[3]) {
            v
        } else {
            // Marked rare, so that the register allocator favours the
            // span loop over this path (the Cortex-M3's `demo` 4,610,743
            // -> 4,601,655 instructions, `rock` 3,767,471 -> 3,759,915);
            // not on the Thumb-1 targets, where it measured worse (ARMv6-M
            // `demo` 15,674,314 -> 15,741,570).
            #[cfg(not(microraster_narrow_multiply))]
            super::cold();
            // On this rare path the set-up escapes, so that, as far as the
            // optimiser knows, its planes may change from span to span: it
            // then reads them per span where the set-up left them, rather
            // than loading them all before the span loop and copying them
            // to spill slots (26 instructions per triangle-tile pair on the
            // Cortex-M3; `demo` 4,821,094 -> 4,805,038 instructions). Not
            // on the Thumb-1 targets (the build script's cfg for them),
            // with their eight low registers: the copy measured cheaper
            // there (ARMv6-M `demo` 15,851,848, 15,874,675 with it).
            #[cfg(not(microraster_narrow_multiply))]
            core::hint::black_box(self);
            // A wide triangle's depth plane fails `z_inside` everywhere.
            // `wide_start`'s values are clamped already, and clamped again
            // they stay: the values meet the fast path's in registers.
            clamped(if self.wide { wide_start(t, i, j) } else { v })
        }
    }

    /// Depth, red, green and blue of the planes at the centre of pixel
    /// `(i, j)`, before any clamp.
    #[inline(always)]
    fn values_at(&self, i: i32, j: i32) -> [i32; 4] {
        [
            self.planes[0].at(i, j),
            self.planes[1].at(i, j),
            self.planes[2].at(i, j),
            self.planes[3].at(i, j),
        ]
    }
}

/// Depth, red, green and blue clamped to their ranges (constant bounds:
/// `clamp`'s check of them is done at compile time).
#[inline(always)]
fn clamped([z, r, g, b]: [i32; 4]) -> [i32; 4] {
    [
        z.clamp(Z_LO, Z_HI),
        r.clamp(C_LO, C_HI),
        g.clamp(C_LO, C_HI),
        b.clamp(C_LO, C_HI),
    ]
}

/// Whether depth `z` is surely in `Z_LO..=Z_HI`: a conservative test (by
/// a constant an instruction can hold; depths of 65,280 and more fail it
/// and take the clamp, which leaves them as they are). Wrapping: a wide
/// triangle's depth plane gives `i32::MIN`.
#[inline(always)]
fn z_inside(z: i32) -> bool {
    const _: () = assert!(0x3FC0_0000 <= Z_HI - Z_LO);
    (z.wrapping_sub(Z_LO) as u32) < 0x3FC0_0000
}

/// Whether colour channel `c` is surely in `C_LO..=C_HI`: `C_HI` itself
/// fails (and takes the clamp, which leaves it), so that the constant
/// `C_HI - C_LO` fits an instruction.
#[inline(always)]
fn c_inside(c: i32) -> bool {
    (c.wrapping_sub(C_LO) as u32) < (C_HI - C_LO) as u32
}
