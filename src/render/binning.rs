//! One binning pass: every triangle classified once and appended to its tiles' bins.

use super::bin::Pass;
use super::state::{keeps_banded, margin, DrawOrder, FrameState, SetupCache};
use super::Features;
use crate::mesh::Indices;
use crate::raster::{first_centre_at_or_after, PixelRect, SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use crate::scene::CullMode;
use crate::tile::TileGrid;
use crate::vertex::ScreenVertex;

/// How one submitted triangle turned out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Fate {
    Rejected,
    Culled,
    Visible,
}

/// How many triangles of a pass met each fate.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Tally {
    /// Per [`Fate`]. Classification counts the rejected triangles, the
    /// binning loop the visible ones (with its pairs, in one sum:
    /// [`LOOP_COUNTS_VISIBLE`]; on ARMv6-M classification counts them);
    /// [`bin_pass`] sets the culled ones (the most common fate, whose
    /// count would be a memory increment on the binning loop's shortest
    /// path) to the rest of the pass's triangles.
    pub(super) fates: [u32; 3],
    pub(super) clipped: u32,
    pub(super) draws_culled: u32,
    pub(super) clusters_culled: u32,
    /// (Triangle, tile) pairs, over every tile of the frame.
    pub(super) pairs: u32,
}

/// One binning pass over every triangle: classifies it and appends a
/// visible one to the bin of each tile of the pass its bounds touch. The
/// pass holds the tiles visited `t0..`: in row-major order, or with
/// `HILBERT` along the Hilbert curve over the tile grid.
#[inline(always)]
pub(super) fn bin_pass<const TW: usize, const TH: usize, const HILBERT: bool, P: Features>(
    frame: &FrameState<'_>,
    grid: &TileGrid,
    t0: usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let mut t = 0usize;
    let mut vbase = 0usize;
    for k in 0..frame.draws.len() {
        let d = frame.visit(k);
        let draw = &frame.draws[d];
        let base = match frame.order.as_ref().map(DrawOrder::slices) {
            Some((_, bases)) => bases[d] as usize,
            None => vbase,
        };
        let verts = &frame.vertices[base..base + draw.mesh.vertex_count()];
        vbase += verts.len();
        let (outside, frustum) = frame.view_test::<P>(d);
        let n = draw.mesh.triangle_count();
        if outside {
            t += n;
            tally.fates[Fate::Rejected as usize] += n as u32;
            tally.draws_culled += 1;
            continue;
        }
        let margin = margin(draw);
        let ctx = BinDraw {
            frame,
            grid,
            t0,
            d,
            verts,
            margin,
        };
        // The clusters in view one by one, or the whole mesh as one run.
        let clusters = frustum.and(draw.mesh.clusters());
        let mut first = 0;
        for k in 0..clusters.map_or(1, |c| c.len()) {
            let len = match (&frustum, clusters) {
                (Some(f), Some(c)) => {
                    let len = c[k].triangle_count() as usize;
                    if len == 0 {
                        continue;
                    }
                    if f.excludes_box(&c[k].bounds()) {
                        t += len;
                        first += len;
                        tally.fates[Fate::Rejected as usize] += len as u32;
                        tally.clusters_culled += 1;
                        continue;
                    }
                    len
                }
                _ => n,
            };
            let run = first..first + len;
            first += len;
            // The common loop (filled triangles, `u16` indices, row-major
            // tiles) is inlined here; the others (lines and points, the
            // Hilbert order, meshes beyond 65,536 vertices) share one
            // out-of-line copy, which tests the order and the indices'
            // width as it goes: a copy of its own for the Hilbert order had
            // cost about 2 KB of flash. In builds optimised for size, one
            // inlined loop for `u16` indices in either order (see
            // [`FAST`]).
            match draw.mesh.triangles() {
                Indices::U16(tris) if FAST && !HILBERT && margin == 0 => {
                    // A copy of the loop for back-face culling, the usual
                    // mode, with the mode a constant in it.
                    let tris = &tris[run];
                    match frame.cull {
                        // On ARMv6-M a third copy for frames of at most
                        // 2,048 px a side, whose area is one `i32`
                        // product each ([`keeps_banded`]), without the
                        // test of the frame's size a triangle (binning
                        // -3.4 K on `demo`, -4.1 K on `rock`; about 700
                        // bytes of flash).
                        CullMode::Back if crate::math::SPLIT && frame.small() => {
                            bin_fast::<TW, TH, true>(
                                &ctx,
                                tris,
                                CullMode::Back,
                                &mut t,
                                bins,
                                cache,
                                tally,
                            )
                        }
                        CullMode::Back => bin_fast::<TW, TH, false>(
                            &ctx,
                            tris,
                            CullMode::Back,
                            &mut t,
                            bins,
                            cache,
                            tally,
                        ),
                        cull => {
                            bin_fast::<TW, TH, false>(&ctx, tris, cull, &mut t, bins, cache, tally)
                        }
                    }
                }
                Indices::U16(tris) if !FAST => {
                    let tris = tris[run].iter().copied();
                    bin_triangles::<TW, TH, u16>(&ctx, tris, HILBERT, &mut t, bins, cache, tally)
                }
                Indices::U32(tris) if !FAST && P::U32_INDICES => {
                    bin_wide::<TW, TH>(&ctx, &tris[run], HILBERT, &mut t, bins, cache, tally)
                }
                // Refused by the vertex stage (Path::U32Indices).
                Indices::U32(_) if !P::U32_INDICES => {
                    t += len;
                    tally.fates[Fate::Rejected as usize] += len as u32;
                }
                tris => bin_other::<TW, TH>(&ctx, tris, run, HILBERT, &mut t, bins, cache, tally),
            }
        }
    }
    // Every triangle of the pass met one fate: the culled ones are the
    // rest (at most 2^16 triangles a frame).
    let f = &mut tally.fates;
    f[Fate::Culled as usize] =
        (t as u32).saturating_sub(f[Fate::Rejected as usize] + f[Fate::Visible as usize]);
}

/// Whether the row-major binning loop pushes a triangle that lies in a
/// single tile (about two in three of `demo`'s visible triangles) by one
/// [`Pass::push`] rather than through the row loop of
/// [`Pass::push_run`]: not in builds optimised for size (the build
/// script's `microraster_size`), where its code weighs more.
const SINGLE_PUSH: bool = !cfg!(microraster_size);

/// Whether the common draws (`u16` indices, row-major tiles, filled:
/// margin 0) take [`bin_fast`], and every other draw the shared
/// out-of-line loop [`bin_other`] (binning on the `demo` frame: the
/// Cortex-M3 467,419 -> 412,287 instructions, ARMv6-M 705,365 ->
/// 592,573): not in builds optimised for size, where the two loops
/// weigh more than the one.
const FAST: bool = !cfg!(microraster_size);

/// Whether the binning loop counts the visible triangles (with their
/// pairs, in one 64-bit sum), rather than [`FrameState::classify`] (a
/// memory increment for each): not on ARMv6-M, where the sum measured
/// slower (binning +12.5 K instructions on the `demo` frame).
///
/// [`FrameState::classify`]: super::state::FrameState::classify
pub(super) const LOOP_COUNTS_VISIBLE: bool = !crate::math::SPLIT;

/// The binning loops count the visible triangles and their pairs in one
/// sum, `VISIBLE` a triangle above the pairs: one 64-bit add a triangle
/// (two instructions on a 32-bit core) rather than a saturating add and a
/// memory increment. At most 2^16 triangles of at most 2^24 tiles each:
/// the pairs stay below 2^40, and the count below 2^16. On ARMv6-M
/// (`SPLIT`), whose 64-bit add costs it registers, the visible triangles
/// are counted by `classify` and the pairs alone apart
/// ([`LOOP_COUNTS_VISIBLE`]).
const VISIBLE: u64 = 1 << 42;

/// A binning loop's counts added to `tally` once, at its end: the visible
/// triangles and pairs of `sum` ([`VISIBLE`]) and the pairs `pairs_sum`
/// (which started at `tally.pairs`).
#[inline(always)]
fn close_tally(tally: &mut Tally, sum: u64, pairs_sum: u32) {
    tally.fates[Fate::Visible as usize] += (sum / VISIBLE) as u32;
    // Over every tile of the frame: saturate, never wrap.
    let pairs = u32::try_from(sum % VISIBLE).unwrap_or(u32::MAX);
    tally.pairs = pairs_sum.saturating_add(pairs);
}

/// [`bin_triangles`] for `u32` indices, out of line: in builds
/// optimised for size, where the shared loop [`bin_other`] measured
/// larger (the OLED firmware +120 B).
#[inline(never)]
pub(super) fn bin_wide<const TW: usize, const TH: usize>(
    ctx: &BinDraw<'_, '_>,
    tris: &[[u32; 3]],
    hilbert: bool,
    t: &mut usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    bin_triangles::<TW, TH, u32>(ctx, tris.iter().copied(), hilbert, t, bins, cache, tally)
}

/// [`bin_triangles`] for the triangles `run` of `tris`, in either tile
/// order, out of line: the Hilbert order, `u32` indices, and lines and
/// points (a margin), where [`FAST`].
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn bin_other<const TW: usize, const TH: usize>(
    ctx: &BinDraw<'_, '_>,
    tris: Indices<'_>,
    run: core::ops::Range<usize>,
    hilbert: bool,
    t: &mut usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let tris = run.map(|k| tris.get(k));
    bin_triangles::<TW, TH, u32>(ctx, tris, hilbert, t, bins, cache, tally)
}

/// The binning loop of a draw of filled triangles (margin 0) with `u16`
/// indices, in row-major tile order: the triangles `tris`, the first
/// numbered `*t`, classified under cull mode `cull` and appended to their
/// tiles' bins, as [`bin_triangles`] does; with `SMALL`, for a frame known
/// to be [`small`](FrameState::small).
///
/// A triangle whose three outcodes are 0 (nearly all the visible ones)
/// is classified here: the cull test, then its pixels, which lie inside
/// the frame (the viewport's projection of a point inside the view
/// volume is within the frame's sub-pixels, `0..=16 w`), so their meet
/// with the frame is not needed, nor the rejected count: a rectangle
/// without a pixel centre is the empty reach of `classify`, not counted.
/// Any other triangle (partly outside, clipped, rejected) goes to
/// [`classify_apart`]. The search for the next visible triangle is a loop
/// of its own, so that the values it needs stay in registers and the
/// pushes' values are the ones spilled.
#[inline(always)]
fn bin_fast<const TW: usize, const TH: usize, const SMALL: bool>(
    ctx: &BinDraw<'_, '_>,
    tris: &[[u16; 3]],
    cull: CullMode,
    t: &mut usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let cols = ctx.grid.cols as usize;
    let verts = ctx.verts;
    debug_assert!(!SMALL || ctx.frame.small());
    let small = SMALL || ctx.frame.small();
    // The visible triangles and their pairs ([`VISIBLE`]).
    let mut tt = *t;
    let (mut sum, mut pairs_sum) = (0u64, tally.pairs);
    let mut rest = tris.iter();
    'done: loop {
        // The next visible triangle: its number and its pixels.
        // A triangle with an outcode bit set leaves the search (`Err`),
        // so that the search's values need not survive a call.
        let found = loop {
            let Some(&idx) = rest.next() else {
                break 'done;
            };
            let k = tt;
            tt += 1;
            let sv = [
                &verts[idx[0] as usize],
                &verts[idx[1] as usize],
                &verts[idx[2] as usize],
            ];
            if sv[0].outcode() | sv[1].outcode() | sv[2].outcode() != 0 {
                break Err((k, idx));
            }
            let r = if WORDS {
                let w = [sv[0].xy_words(), sv[1].xy_words(), sv[2].xy_words()];
                let e = Edges::of(&w);
                let keep = e.keeps(cull);
                debug_assert_eq!(
                    keep,
                    keeps_banded(cull, &[sv[0].xy(), sv[1].xy(), sv[2].xy()], small)
                );
                if !keep {
                    continue;
                }
                e.centres()
            } else {
                let v = [sv[0].xy(), sv[1].xy(), sv[2].xy()];
                if !keeps_banded(cull, &v, small) {
                    continue;
                }
                centres(&v)
            };
            debug_assert!({
                let v = [sv[0].xy(), sv[1].xy(), sv[2].xy()];
                let f = &ctx.frame.frame;
                r == centres(&v)
                    && (r == super::state::meet(&super::state::reach(&v, 0), f) || r.is_empty())
            });
            if r.is_empty() {
                continue;
            }
            if !LOOP_COUNTS_VISIBLE {
                tally.fates[Fate::Visible as usize] += 1;
            }
            break Ok((k, r));
        };
        let (k, r) = match found {
            Ok(kr) => kr,
            Err((k, idx)) => {
                let idx = idx.map(Into::into);
                match classify_apart(ctx, idx, (cull, small), cache, tally) {
                    Some(r) => (k, r),
                    None => continue,
                }
            }
        };
        // Inside the frame: not negative.
        let (c0, c1) = (r.x0 as usize / TW, (r.x1 as usize - 1) / TW + 1);
        let (r0, r1) = (r.y0 as usize / TH, (r.y1 as usize - 1) / TH + 1);
        let pairs = (c1 - c0) * (r1 - r0);
        if LOOP_COUNTS_VISIBLE {
            sum += VISIBLE + pairs as u64;
        } else {
            pairs_sum = pairs_sum.saturating_add(pairs as u32);
        }
        push_row_major(bins, (c0, c1), (r0, r1), cols, ctx.t0, k as u16);
    }
    *t = tt;
    close_tally(tally, sum, pairs_sum);
}

/// Pushes triangle `k` into the tiles of columns `c0..c1` and rows
/// `r0..r1` of a row-major grid of `cols` columns, numbered in the pass
/// from tile `t0`.
///
/// Every tile of the bounds, covered or not. On the `demo` frame 363 of
/// the 2,597 pairs hold no pixel centre of their triangle: 56 of the
/// 1,279 one-tile triangles, 101 of the 502 pairs of 2x1-tile bounds, 100
/// of 540 of 1x2, 100 of 252 of 2x2, 6 of 24 larger (`rock`: 202 of
/// 1,951; 52, 60 of 390, 47 of 380, 43 of 148). The trivial-reject corner
/// of each edge against the tile's centres within the bounds (exact, in
/// `i32`) finds 45, 42, 81 and 6 of them (against the whole tile 3, 5,
/// 69, 6). Tried for bounds of at least 2x2 tiles, out of line after the
/// search loop, and not kept: it spared the walk 87 pairs (the M3's
/// raster and shading 2,453,567 -> 2,428,930, about 280 a pair) but
/// binning took 359,554 -> 434,733 (the test about 360 a triangle, and
/// the call's mere presence in the loop about 47 K, measured with a test
/// that kept every tile), the frame 3,184,820 -> 3,235,362; x86-64 `demo`
/// 3,605,150 -> 3,640,843 (binning +61 K, raster -25.5 K), `rock`
/// 3,011,708 -> 3,045,114. For 2x1 and 1x2 bounds the test would cost
/// in 521 triangles what it spares in 87 pairs. (Also tried: the search
/// loop without its triangle count, the number taken from the
/// iterator's position when a triangle leaves it: binning 382,796.)
#[inline(always)]
fn push_row_major(
    bins: &mut Pass<'_>,
    (c0, c1): (usize, usize),
    (r0, r1): (usize, usize),
    cols: usize,
    t0: usize,
    k: u16,
) {
    if SINGLE_PUSH && (c1 - c0) * (r1 - r0) == 1 {
        // Most visible triangles lie in one tile: one push, without the
        // row loop's set-up. At most 2^24 tiles: no overflow; a tile
        // before the pass wraps to an index it does not hold.
        bins.push((r0 * cols + c0).wrapping_sub(t0), k);
    } else {
        // Each row's tiles in the pass's numbering, from `t0`: those
        // before the pass are negative, and the pass holds none of them
        // (it gives up tiles from its end). At most 2^24 tiles: no
        // overflow.
        let mut lo = (r0 * cols + c0) as isize - t0 as isize;
        let mut hi = lo + (c1 - c0) as isize;
        for _ in r0..r1 {
            bins.push_run(lo.max(0) as usize..hi.max(0) as usize, k);
            lo += cols as isize;
            hi += cols as isize;
        }
    }
}

/// The pixels whose centres a filled triangle with vertices `v` may
/// cover ([`reach`] with margin 0): `first_centre_at_or_after(x)` as
/// `(x + 7) >> 4` (`-floor((8 - x) / 16) = floor((x + 7) / 16)`), an add
/// and a shift without `first_centre_at_or_after`'s negations (the
/// Cortex-M3's `demo` binning 407,901 -> 400,433 instructions). (The
/// extremes as vertex 0's coordinate plus the least and greatest of 0 and
/// the two offsets, fewer instructions on paper, measured 427,102: the
/// registers of the loop.)
///
/// [`reach`]: super::state::reach
#[inline(always)]
fn centres(v: &[SubPoint; 3]) -> PixelRect {
    const UP: i32 = HALF_PIXEL - 1;
    let axis = |a: i32, b: i32, c: i32| {
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        ((lo + UP) >> SUBPIXEL_BITS, (hi + UP) >> SUBPIXEL_BITS)
    };
    let (x0, x1) = axis(v[0].x, v[1].x, v[2].x);
    let (y0, y1) = axis(v[0].y, v[1].y, v[2].y);
    debug_assert!(x0 == first_centre_at_or_after(v[0].x.min(v[1].x).min(v[2].x)));
    debug_assert!(x1 == first_centre_at_or_after(v[0].x.max(v[1].x).max(v[2].x)));
    debug_assert!(y0 == first_centre_at_or_after(v[0].y.min(v[1].y).min(v[2].y)));
    debug_assert!(y1 == first_centre_at_or_after(v[0].y.max(v[1].y).max(v[2].y)));
    PixelRect::new(x0, y0, x1, y1)
}

/// Whether [`bin_fast`] culls and bounds a triangle from its vertices'
/// words ([`ScreenVertex::xy_words`], [`Edges`]) rather than from their
/// coordinates: not on ARMv6-M, whose `i32` area (see [`keeps_banded`])
/// takes the coordinates themselves.
const WORDS: bool = !crate::math::SPLIT;

/// A triangle whose three outcodes are 0, from its vertices' words `w`
/// ([`ScreenVertex::xy_words`]) for [`bin_fast`]: vertex 0's x word and y,
/// and its two edges from vertex 0, from which both the cull test
/// ([`keeps`](Self::keeps)) and the pixels ([`centres`](Self::centres))
/// follow. Each x word is then `x 2^8` exactly, so an x difference is one
/// subtraction of words (`2^8` times the coordinates'); a y word is `y 2^9
/// + l` with `0 <= l < 2^9`, so its y is the word shifted by 9 (an operand
/// shift on Thumb-2). The words are within `±2^27`: no overflow.
///
/// The four differences, rather than the six words, are what the cull
/// test leaves for the pixels: fewer values live across the search loop's
/// products, which had spilled the loop's own registers on the
/// Cortex-M3 (binning on the `demo` frame 359,554 -> 344,559
/// instructions; the Cortex-M4F 363,102 -> 345,991, x86-64 396,883 ->
/// 391,087).
struct Edges {
    /// Vertex 0's x word (`x 2^8`).
    x0: i32,
    /// Vertex 0's y.
    y0: i32,
    /// Vertex 1's x word less vertex 0's, and vertex 0's less vertex 2's:
    /// the second negated, so that the area is a multiply and a
    /// multiply-accumulate, with the negation on the visible path alone
    /// (Cortex-M3 -1.2 K).
    dx: (i32, i32),
    /// Vertex 1's and 2's y less vertex 0's.
    dy: (i32, i32),
}

impl Edges {
    #[inline(always)]
    fn of(w: &[(i32, i32); 3]) -> Self {
        let y0 = w[0].1 >> 9;
        Self {
            x0: w[0].0,
            y0,
            dx: (w[1].0 - w[0].0, w[0].0 - w[2].0),
            dy: ((w[1].1 >> 9) - y0, (w[2].1 >> 9) - y0),
        }
    }

    /// [`keeps_banded`] (on cores with a long multiply): twice the signed
    /// area, `x1 y2 - x2 y1`, as one sum `x1 y2 + (-x2) y1` (a multiply
    /// and a multiply-accumulate on Thumb-2, against two products
    /// compared) is `2^8` times the coordinates' (x within `±2^18`, so
    /// below `2^47`): its sign is theirs.
    #[inline(always)]
    fn keeps(&self, cull: CullMode) -> bool {
        let (x1, neg_x2) = self.dx;
        let (y1, y2) = self.dy;
        let a = crate::math::mul_wide(x1, y2) + crate::math::mul_wide(neg_x2, y1);
        super::state::keeps_by(cull, a, 0)
    }

    /// [`centres`]: the least and greatest x word are vertex 0's plus the
    /// least and greatest of 0 and the two differences, `2^8` times the
    /// least and greatest x, so `(x + 7) >> 4` is `(word + 7 2^8) >> 12`;
    /// y's likewise from the y differences.
    #[inline(always)]
    fn centres(&self) -> PixelRect {
        const UP: i32 = HALF_PIXEL - 1;
        let span = |a: i32, b: i32| (a.min(b).min(0), a.max(b).max(0));
        let (lx, hx) = span(self.dx.0, -self.dx.1);
        let (ly, hy) = span(self.dy.0, self.dy.1);
        PixelRect::new(
            (self.x0 + lx + (UP << 8)) >> (SUBPIXEL_BITS + 8),
            (self.y0 + ly + UP) >> SUBPIXEL_BITS,
            (self.x0 + hx + (UP << 8)) >> (SUBPIXEL_BITS + 8),
            (self.y0 + hy + UP) >> SUBPIXEL_BITS,
        )
    }
}

/// [`FrameState::classify`] of triangle `idx` of the draw `ctx`, out of
/// line: for [`bin_fast`]'s triangles with an outcode bit set.
///
/// Cold on ARMv6-M and 64-bit hosts, where its branch's weight moved the
/// search loop's registers and blocks for the better (binning on the
/// `demo` frame: ARMv6-M 531,813 -> 524,538 instructions, x86-64 391,087
/// -> 383,293); not on the Cortex-M3 and M4F (the M4F's binning 345,991
/// -> 364,150: its loop then copied two registers round each triangle).
///
/// [`FrameState::classify`]: super::state::FrameState::classify
#[inline(never)]
#[cfg_attr(any(microraster_narrow_multiply, target_pointer_width = "64"), cold)]
fn classify_apart(
    ctx: &BinDraw<'_, '_>,
    idx: [u32; 3],
    cull: (CullMode, bool),
    cache: &mut SetupCache,
    tally: &mut Tally,
) -> Option<PixelRect> {
    ctx.frame
        .classify(ctx.d, ctx.verts, idx, ctx.margin, cull, cache, tally)
}

/// What [`bin_triangles`] needs of the draw it bins.
pub(super) struct BinDraw<'a, 'f> {
    pub(super) frame: &'a FrameState<'f>,
    pub(super) grid: &'a TileGrid,
    pub(super) t0: usize,
    pub(super) d: usize,
    pub(super) verts: &'a [ScreenVertex],
    pub(super) margin: i32,
}

/// The triangles `tris` of one draw, the first numbered `*t`, classified
/// and appended to their tiles' bins (see [`bin_pass`]).
///
/// On 64-bit hosts, which have the code space, a copy of the loop for
/// each of the usual cull modes, the mode a constant in it, rather than
/// tested for every triangle (x86-64 `demo` binning 546,176 -> 532,255
/// instructions, `rock` -13 K).
#[inline(always)]
pub(super) fn bin_triangles<const TW: usize, const TH: usize, I: Copy + Into<u32>>(
    ctx: &BinDraw<'_, '_>,
    tris: impl Iterator<Item = [I; 3]>,
    hilbert: bool,
    t: &mut usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let copies = cfg!(target_pointer_width = "64");
    let with = |cull| (ctx, tris, hilbert, cull);
    match ctx.frame.cull {
        CullMode::Back if copies => {
            bin_culled::<TW, TH, I>(with(CullMode::Back), t, bins, cache, tally)
        }
        CullMode::None if copies => {
            bin_culled::<TW, TH, I>(with(CullMode::None), t, bins, cache, tally)
        }
        cull => bin_culled::<TW, TH, I>(with(cull), t, bins, cache, tally),
    }
}

/// [`bin_triangles`] with the cull mode `cull`: the draw `ctx`, its
/// triangles `tris` and the tile order (`hilbert`) with it in `draw`.
#[inline(always)]
fn bin_culled<const TW: usize, const TH: usize, I: Copy + Into<u32>>(
    draw: (
        &BinDraw<'_, '_>,
        impl Iterator<Item = [I; 3]>,
        bool,
        CullMode,
    ),
    t: &mut usize,
    bins: &mut Pass<'_>,
    cache: &mut SetupCache,
    tally: &mut Tally,
) {
    let (ctx, tris, hilbert, cull) = draw;
    let cols = ctx.grid.cols as usize;
    // Counted here and added once: `t` and `tally` live in the caller.
    // The visible triangles and their pairs ([`VISIBLE`]).
    let mut tt = *t;
    let (mut sum, mut pairs_sum) = (0u64, tally.pairs);
    let small = ctx.frame.small();
    for idx in tris {
        let idx = idx.map(Into::into);
        if let Some(r) = ctx.frame.classify(
            ctx.d,
            ctx.verts,
            idx,
            ctx.margin,
            (cull, small),
            cache,
            tally,
        ) {
            // A visible rectangle lies inside the frame, so its
            // coordinates are not negative.
            let (c0, c1) = (r.x0 as usize / TW, (r.x1 as usize - 1) / TW + 1);
            let (r0, r1) = (r.y0 as usize / TH, (r.y1 as usize - 1) / TH + 1);
            let pairs = (c1 - c0) * (r1 - r0);
            if LOOP_COUNTS_VISIBLE {
                sum += VISIBLE + pairs as u64;
            } else {
                pairs_sum = pairs_sum.saturating_add(pairs as u32);
            }
            if hilbert || crate::math::SPLIT {
                for row in r0..r1 {
                    for col in c0..c1 {
                        let p = match hilbert {
                            true => ctx.grid.position(col as u32, row as u32) as usize,
                            false => row * cols + col,
                        };
                        // Tiles before the pass wrap around to indices
                        // the pass does not hold.
                        bins.push(p.wrapping_sub(ctx.t0), tt as u16);
                    }
                }
            } else {
                push_row_major(bins, (c0, c1), (r0, r1), cols, ctx.t0, tt as u16);
            }
        }
        tt += 1;
    }
    *t = tt;
    close_tally(tally, sum, pairs_sum);
}

#[cfg(test)]
mod tests {
    use crate::raster::first_centre_at_or_after;

    /// `centres`' `(x + 7) >> 4` is `first_centre_at_or_after` at every
    /// coordinate a screen vertex holds (`-2^22..2^22`).
    #[test]
    fn centre_by_one_shift() {
        for x in -(1 << 22)..(1 << 22) {
            assert_eq!((x + 7) >> 4, first_centre_at_or_after(x), "{x}");
        }
    }
}
