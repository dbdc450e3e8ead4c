//! A triangle's set-up for shading: its depth and colour planes (see
//! [`Plane`] for one plane and why its `i32` evaluation is exact), computed
//! once per triangle-tile pair by the general path or the small
//! triangles' 32-bit one (their values at a span's start are in `start`;
//! see the [parent module](super) for the method and the fixed-point
//! formats).

use super::plane::{Basis, Plane};
use super::small::SMALL_SETUP;
use super::{C_FRAC, GRADIENT_LIMIT, Z_FRAC};
use crate::raster::SubPoint;
use crate::vertex::ScreenVertex;

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

/// Whether [`TriangleSetup::small_for_spans`] inlines the small set-up:
/// on 32-bit cores with a long multiply.
pub(crate) const SMALL_INLINE: bool = SMALL_SETUP && !cfg!(microraster_narrow_multiply);

/// Whether [`TriangleSetup::small_for_spans`] gives the set-up of
/// [`TriangleSetup::offset`] (64-bit hosts), whose triangles then take a
/// span loop of their own.
pub(crate) const OFFSET_SETUP: bool = cfg!(target_pointer_width = "64");

/// Whether [`TriangleSetup::for_spans`] holds a Gouraud triangle's colour
/// planes shifted left by 8 (wrapping), as the span loops of targets with
/// SIMD step the channels (see `span_gouraud`): a plane's value at a
/// pixel is then the channel shifted, whose top byte is the byte `rgb`
/// takes, and its step is the loop's. Once a pair, where each span shifted
/// its three starts and each pair its three steps (x86-64 `demo`
/// 3,390,160 -> 3,376,708 instructions; 3,294,874 -> 3,277,579 once the
/// Gouraud loop had lost its vector loop). Depth cannot be: its range is
/// too wide (see [`TriangleSetup::start_shifted`] for colour's).
///
/// On ARMv6-M too ([`SHIFTED_TOP`]), whose Gouraud loop steps the
/// channels shifted (`gouraud::TOP_BYTE`'s form).
pub(crate) const SHIFTED_COLOR: bool = super::VECTOR_LOOPS || SHIFTED_TOP;

/// Whether the Gouraud set-up of a target without SIMD (ARMv6-M, the
/// build script's `microraster_narrow_multiply`) holds its colour planes
/// shifted left by 8 ([`SHIFTED_COLOR`]), for its Gouraud loop, which
/// steps the channels shifted (`gouraud::TOP_BYTE`): once a pair
/// where each span shifted its three starts and each pair its three
/// steps; the span starts are then tested against the shifted bounds
/// ([`TriangleSetup::start_tested_shifted`]).
pub(crate) const SHIFTED_TOP: bool = cfg!(microraster_narrow_multiply);

/// An affine triangle's colour planes for a fragment shader that reads
/// the colour, with its corners: the colour at a pixel of a span is the
/// built-in Gouraud shading's ([`ColourPlanes::start`]). Set up by the
/// renderer's affine copy of its shading function (opaque draws) alone:
/// see `render::fill::shade_custom`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColourPlanes<'a> {
    pub(crate) setup: TriangleSetup,
    pub(crate) corners: &'a Corners<'a>,
}

impl ColourPlanes<'_> {
    /// Red, green and blue (8.16 a channel, rounding bias included) at
    /// the first pixel `(i, j)` of a span, and their steps along it: the
    /// Gouraud span loops' values, the planes' at the span's start, tested
    /// and clamped there ([`TriangleSetup::start_tested_as`]), then
    /// stepped by their `gx`, so that along the span each channel stays
    /// within `0..2^24` and its byte is bits 16 to 23 (see the
    /// [`Plane`] bounds), no clamp needed. Out of line: inlined into each
    /// of the shaders' span loops that read the colour, it took about
    /// 3 KB of a Cortex-M3 firmware holding five shader fills.
    #[inline(never)]
    pub(crate) fn start(&self, i: i32, j: i32) -> ([i32; 3], [i32; 3]) {
        self.start_inline(i, j)
    }

    /// [`start`](Self::start) inlined, for a caller that takes one
    /// triangle's spans in a loop of its own (one copy a shader).
    #[inline(always)]
    pub(crate) fn start_inline(&self, i: i32, j: i32) -> ([i32; 3], [i32; 3]) {
        let [r, g, b] = self.setup.colour_start(self.corners, i, j);
        let [_, gr, gg, gb] = self.setup.steps();
        ([r, g, b], [gr, gg, gb])
    }

    /// Whether a gradient was beyond the planes' limit
    /// ([`TriangleSetup::wide`]): a sliver whose steps the loops that pack
    /// two channels in one word (as the 64-bit Gouraud loop) leave alone.
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub(crate) fn wide(&self) -> bool {
        self.setup.wide
    }
}

/// A triangle ready to shade: its attribute planes (depth, then red,
/// green and blue for Gouraud shading).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleSetup {
    pub(super) planes: [Plane; 4],
    /// A gradient was beyond ±[`GRADIENT_LIMIT`]: span starts come from
    /// [`wide_start`](super::sliver::wide_start) instead of `planes` (only the steps are used).
    pub(super) wide: bool,
    /// The depth step along a span: the depth plane's `gx`, kept here
    /// because a wide triangle's depth plane is replaced by one that is
    /// outside the depth range everywhere, so that [`TriangleSetup::start`]
    /// finds it there with the range tests it makes anyway, and tests no
    /// flag per span.
    pub(super) zstep: i32,
    /// Every vertex is [`interior`](ScreenVertex::interior) and the
    /// triangle is not [`wide`](TriangleSetup::wide): every span start's
    /// plane values are inside their ranges (the proof is at
    /// [`ScreenVertex::interior`]), so [`TriangleSetup::start`] takes them
    /// without its clamps. Set only for the Gouraud span loops
    /// ([`TriangleSetup::for_spans`]), the only ones that call `start`.
    /// Only where the vertex stage makes the bit (`INTERIOR_STARTS`): the
    /// field's stores took flash where it is never set.
    #[cfg(microraster_interior)]
    interior: bool,
    /// On 64-bit hosts, the exact (`i64`, not wrapped) `gx`, `gy` and `k`
    /// of the green and blue planes, unshifted, for the packed span starts
    /// ([`TriangleSetup::packed`]); exact for a triangle that is not
    /// [`wide`](TriangleSetup::wide).
    #[cfg(target_pointer_width = "64")]
    pub(super) exact: [[i64; 3]; 2],
    /// On 64-bit hosts, once [`TriangleSetup::for_gouraud_spans`] made
    /// them ([`PACKED`](super::packed::PACKED)): `gx`, `gy` and `k` of the packed planes
    /// red/green and depth/blue, see `start_packed`.
    #[cfg(target_pointer_width = "64")]
    pub(super) packed: [[u64; 3]; 2],
}

impl TriangleSetup {
    /// The set-up of `planes`, `wide` or not (see
    /// [`TriangleSetup::zstep`]).
    #[inline(always)]
    pub(super) fn finish(mut planes: [Plane; 4], wide: bool) -> Self {
        let zstep = planes[0].gx;
        // Only `start_tested` needs the replaced plane: `start_selects`
        // tests `wide` itself, and with the plane replaced the optimiser
        // kept both depth planes live into its span loop, the replaced one
        // for the clamped starts and the other for the interior ones.
        if wide && !super::VECTOR_LOOPS {
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
            #[cfg(microraster_interior)]
            interior: false,
            #[cfg(target_pointer_width = "64")]
            exact: [[0; 3]; 2],
            #[cfg(target_pointer_width = "64")]
            packed: [[0; 3]; 2],
        }
    }

    /// Whether the span starts may skip their clamps (see the field
    /// `interior`; never where the vertex stage does not make the bit).
    #[inline(always)]
    pub(crate) fn interior(&self) -> bool {
        #[cfg(microraster_interior)]
        return self.interior;
        #[cfg(not(microraster_interior))]
        false
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
            return Self::general(t, gouraud);
        }
        #[cfg(target_pointer_width = "64")]
        {
            if let Some(s) = Self::offset(v, t, gouraud) {
                return s;
            }
            Self::general(t, gouraud)
        }
        #[cfg(not(target_pointer_width = "64"))]
        Self::with_basis(&Basis::new(v), t, gouraud)
    }

    /// [`TriangleSetup::with_basis`] out of line, for ARMv6-M's triangles
    /// that the small set-up does not take (about 1 % of `demo`'s): inline,
    /// the general path's values (the edge vectors, their signs and
    /// magnitudes) were computed and spilled on the small set-up's way
    /// in. Also the colour planes of a fragment shader's affine triangle
    /// that the small and offset set-ups decline
    /// ([`TriangleSetup::colour_planes`]).
    #[inline(never)]
    pub(crate) fn general(t: &Corners<'_>, gouraud: bool) -> Self {
        Self::with_basis(&Basis::new(&t.points()), t, gouraud)
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
        // 64-bit hosts also keep green's and blue's exact coefficients
        // (`exact`, for the packed span starts); 32-bit targets take the
        // planes alone, as before (their code unchanged).
        #[cfg(target_pointer_width = "64")]
        {
            let mut exact = [[0i64; 3]; 2];
            let planes = if gouraud {
                let r = Self::plane(f, t, 1, &mut range);
                let (g, eg) = Self::plane_exact(f, t, 2, &mut range);
                let (b, eb) = Self::plane_exact(f, t, 3, &mut range);
                exact = [eg, eb];
                [z, r, g, b]
            } else {
                [z, Plane::default(), Plane::default(), Plane::default()]
            };
            let mut s = Self::finish(planes, range >= 2 * GRADIENT_LIMIT as u64);
            s.exact = exact;
            s
        }
        #[cfg(not(target_pointer_width = "64"))]
        {
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
        Self::plane_and_exact(f, values, frac, range).0
    }

    /// [`TriangleSetup::plane_of`], and its `gx`, `gy` and `k` in `i64`
    /// (which the callers that do not use them leave uncomputed: it is
    /// inlined).
    #[inline(always)]
    pub(super) fn plane_and_exact(
        f: &Basis,
        values: [i64; 3],
        frac: u32,
        range: &mut u64,
    ) -> (Plane, [i64; 3]) {
        let g = f.gradients(values, frac);
        *range |= (g.0 + GRADIENT_LIMIT) as u64 | (g.1 + GRADIENT_LIMIT) as u64;
        // Wrapping to i32 keeps everything `Plane::at` needs. Within ±LIMIT
        // the constant does not wrap; beyond, its wrapped value is not used
        // (a wide triangle's starts come from `wide_start`).
        let k = f.constant_wrapping(values[0], frac, g);
        let plane = Plane {
            gx: g.0 as i32,
            gy: g.1 as i32,
            k: k as i32,
        };
        (plane, [g.0, g.1, k])
    }

    /// [`TriangleSetup::new`] for the span loops, Gouraud (`GOURAUD`) or
    /// flat. Inlined into each span loop on a 64-bit host, where that
    /// measured fastest; on 32-bit targets one copy for each shading, out
    /// of line, rather than one in each of the eight span loops of a colour
    /// type (over a kilobyte of flash each), and the span loops keep their
    /// registers.
    ///
    /// A Gouraud set-up's [`zstep`](TriangleSetup::zstep) is shifted for
    /// its span loop, and its [`interior`](TriangleSetup::interior) set
    /// ([`TriangleSetup::for_gouraud_spans`]); a flat one's is not.
    #[inline(always)]
    pub(crate) fn for_spans<const GOURAUD: bool>(t: &Corners<'_>) -> Self {
        if GOURAUD && SHIFTED_TOP {
            Self::gouraud_spans(t)
        } else if GOURAUD {
            Self::gouraud(t).for_gouraud_spans(t)
        } else {
            Self::flat(t)
        }
    }

    /// This set-up for the Gouraud span loop: [`interior`](Self::interior)
    /// from its vertices, and its depth step shifted left by `16 - Z_FRAC`
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
    pub(crate) fn for_gouraud_spans(mut self, t: &Corners<'_>) -> Self {
        #[cfg(microraster_interior)]
        {
            self.interior = ScreenVertex::all_interior(t.0) && !self.wide;
        }
        #[cfg(not(microraster_interior))]
        let _ = t;
        self.zstep = ((self.zstep as u32) << (16 - super::Z_FRAC)) as i32;
        if SHIFTED_COLOR {
            for p in &mut self.planes[1..] {
                *p = Plane {
                    gx: p.gx.wrapping_shl(8),
                    gy: p.gy.wrapping_shl(8),
                    k: p.k.wrapping_shl(8),
                };
            }
        }
        #[cfg(target_pointer_width = "64")]
        if super::packed::PACKED {
            self.packed = self.packs();
        }
        self
    }

    /// [`TriangleSetup::for_spans`] of a small triangle, inlined, for the
    /// span loops that nearly every frame takes (the caller's choice), on
    /// 32-bit cores with a long multiply ([`SMALL_INLINE`]); `None` for
    /// any other triangle (which the caller sets up by the out-of-line
    /// `for_spans`) and on other cores. The [`Small`](super::small::Small)
    /// set-up's planes are then written where the span loop reads them,
    /// without a call, the returned set-up's stores through a pointer and
    /// the spills around them.
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
    pub(crate) fn small_for_spans<const GOURAUD: bool>(t: &Corners<'_>) -> Option<Self> {
        if SMALL_INLINE {
            if let Some(s) = Self::small(&t.points(), t, GOURAUD) {
                return Some(if GOURAUD { s.for_gouraud_spans(t) } else { s });
            }
        }
        #[cfg(target_pointer_width = "64")]
        if let Some(s) = Self::offset(&t.points(), t, GOURAUD) {
            return Some(if GOURAUD { s.for_gouraud_spans(t) } else { s });
        }
        None
    }

    /// [`TriangleSetup::new`] of a Gouraud triangle.
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    pub(super) fn gouraud(t: &Corners<'_>) -> Self {
        Self::new(t, true)
    }

    /// [`TriangleSetup::gouraud`] made ready for the span loops
    /// ([`TriangleSetup::for_gouraud_spans`]) in one call, where the
    /// colour planes are shifted ([`SHIFTED_TOP`]: ARMv6-M): their nine
    /// shifts then come before the set-up's stores, from the registers that
    /// computed the planes, rather than in the caller, reloaded.
    #[inline(never)]
    pub(super) fn gouraud_spans(t: &Corners<'_>) -> Self {
        if let Some(s) = Self::small_as(&t.points(), t, true, true) {
            return s;
        }
        Self::general(t, true).for_gouraud_spans(t)
    }

    /// [`TriangleSetup::new`] of a Gouraud triangle, out of line: the
    /// colour planes of a fragment shader's affine triangle
    /// ([`ColourPlanes`], `render::fill::shade_custom`), by the small
    /// triangles' 32-bit divisions on 32-bit cores and the offset set-up
    /// on 64-bit hosts where the triangle allows (the same planes as the
    /// general set-up's).
    #[inline(never)]
    pub(crate) fn colour_planes(t: &Corners<'_>) -> Self {
        Self::new(t, true)
    }

    /// [`TriangleSetup::new`] of a flat triangle.
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    pub(super) fn flat(t: &Corners<'_>) -> Self {
        Self::new(t, false)
    }
}
