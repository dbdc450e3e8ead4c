//! One binning pass: every triangle classified once and appended to its
//! tiles' bins. The common draw (filled, `u16` indices, row-major) has a
//! loop of its own, in `fast`.

mod fast;

use super::bin::Pass;
use super::state::{margin, DrawOrder, FrameState, SetupCache};
use super::Features;
use crate::mesh::Indices;
use crate::scene::CullMode;
use crate::tile::TileGrid;
use crate::vertex::ScreenVertex;
use fast::bin_fast;

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
/// slower (binning +12.5 K instructions on the `demo` frame), nor on
/// 64-bit hosts, whose `bin_fast` then pushes a one-tile triangle first
/// and counts its pair with the visible count, as ARMv6-M does (x86-64
/// `demo` binning 362,752 -> 355,968, `rock` -5.1 K, `tri4` -66 K,
/// `demo-textured-lit` -6.8 K, `tri100` +2.3 K). Nor on the Cortex-M4F
/// (ARMv7E-M, the build script's `microraster_armv7em`), the same way
/// with `fast`'s `classify_apart` cold: binning on the `demo` frame
/// 344,127 -> 338,865 instructions, `rock` -4.6 K, `grid4` -4.5 K,
/// `demo-textured-lit` -8.7 K (without the cold hint `demo` -2.3 K but
/// `demo-textured-lit` +21.7 K: that loop copied two registers round
/// each triangle). (The M3 the same way: `demo` +22 K.) Nor on RISC-V
/// (see `fast`'s `ONE_TILE_FIRST`, which takes the cores this leaves).
///
/// [`FrameState::classify`]: super::state::FrameState::classify
pub(super) const LOOP_COUNTS_VISIBLE: bool = !crate::math::SPLIT
    && !cfg!(target_pointer_width = "64")
    && !cfg!(microraster_armv7em)
    && !cfg!(target_arch = "riscv32");

/// The binning loops count the visible triangles and their pairs in one
/// sum, `VISIBLE` a triangle above the pairs: one 64-bit add a triangle
/// (two instructions on a 32-bit core) rather than a saturating add and a
/// memory increment. At most 2^16 triangles of at most 2^24 tiles each:
/// the pairs stay below 2^40, and the count below 2^16. On ARMv6-M
/// (`SPLIT`), whose 64-bit add costs it registers, the visible triangles
/// are counted by `classify` and the pairs alone apart
/// ([`LOOP_COUNTS_VISIBLE`]); so are 64-bit hosts'. (x86-64's sum with
/// the count as the low 20 bits and the pairs above, so that a one-tile
/// triangle's add took an immediate: `demo` +8.0 K, the search loop's
/// registers moved.)
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
        push_one(bins, (c0, r0), cols, t0, k);
    } else {
        push_rows(bins, (c0, c1), (r0, r1), cols, t0, k);
    }
}

/// [`push_row_major`] of a triangle within the one tile of column `c0`
/// and row `r0` (about two in three of `demo`'s visible triangles): one
/// push, without the row loop's set-up.
#[inline(always)]
fn push_one(bins: &mut Pass<'_>, (c0, r0): (usize, usize), cols: usize, t0: usize, k: u16) {
    // At most 2^24 tiles: no overflow; a tile before the pass wraps to
    // an index it does not hold.
    bins.push((r0 * cols + c0).wrapping_sub(t0), k);
}

/// [`push_row_major`] through the row loop: each row's tiles by one
/// [`Pass::push_run`].
// `push_row_major`'s parameters again: `fast.rs` calls this past its own one-tile test.
#[inline(always)]
fn push_rows(
    bins: &mut Pass<'_>,
    (c0, c1): (usize, usize),
    (r0, r1): (usize, usize),
    cols: usize,
    t0: usize,
    k: u16,
) {
    // Each row's tiles in the pass's numbering, from `t0`: those before
    // the pass are negative, and the pass holds none of them (it gives
    // up tiles from its end). At most 2^24 tiles: no overflow.
    let mut lo = (r0 * cols + c0) as isize - t0 as isize;
    let mut hi = lo + (c1 - c0) as isize;
    if ROWS_BY_TILE {
        // `lo` of the row after the last.
        let end = lo + ((r1 - r0) * cols) as isize;
        while lo != end {
            bins.push_run(lo.max(0) as usize..hi.max(0) as usize, k);
            lo += cols as isize;
            hi += cols as isize;
        }
        return;
    }
    for _ in r0..r1 {
        // On 64-bit hosts a row within the pass (`lo`, and so `hi`, not
        // negative: every row of the first pass) by one test rather than
        // two clamps (x86-64 `demo` binning 365,971 -> 362,752, `rock`
        // -2.3 K); on the Cortex-M3 and ARMv6-M it cost +0.4 K and
        // +1.7 K (their clamps are one instruction each), the M4F -0.2 K.
        if cfg!(target_pointer_width = "64") && lo >= 0 {
            bins.push_run(lo as usize..hi as usize, k);
        } else {
            bins.push_run(lo.max(0) as usize..hi.max(0) as usize, k);
        }
        lo += cols as isize;
        hi += cols as isize;
    }
}

/// Whether [`push_rows`] counts its rows by the first tile's index
/// itself, not by a row number of its own (which the Cortex-M3 kept on
/// the stack, loaded and stored each row): on the Cortex-M3 (`demo`
/// binning 338,226 -> 334,595, `rock` -2.7 K, `grid4` -1.2 K), not in
/// its builds optimised for size (their loop as it was); the M4F
/// +14.8 K, ARMv6-M +8.2 K, x86-64 +5.1 K. On the cores of the Pico 2
/// and the ESP32-C3 too (frame 0 of the boards' scene: Cortex-M33
/// 2,178,150 -> 2,176,400 instructions, RV32IMC 2,519,113 ->
/// 2,515,461).
const ROWS_BY_TILE: bool = cfg!(any(
    microraster_armv7m,
    microraster_armv8m,
    target_arch = "riscv32"
)) && !cfg!(microraster_size);

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
