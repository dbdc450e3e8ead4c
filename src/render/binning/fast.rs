//! Binning's own loop for the common draw: filled triangles with `u16`
//! indices in row-major tile order ([`bin_fast`]), the search for the
//! next visible triangle kept in registers; its cull test and bounds from
//! one vertex and two edges ([`Edges`]) or the coordinates ([`centres`]),
//! and the out-of-line classification of the triangles it cannot take
//! ([`classify_apart`]).

use super::{
    close_tally, push_one, push_row_major, push_rows, BinDraw, Fate, Tally, LOOP_COUNTS_VISIBLE,
    SINGLE_PUSH, VISIBLE,
};
use crate::raster::{first_centre_at_or_after, PixelRect, SubPoint, HALF_PIXEL, SUBPIXEL_BITS};
use crate::render::bin::Pass;
use crate::render::state::{keeps_banded, SetupCache};
use crate::scene::CullMode;

/// The binning loop of a draw of filled triangles (margin 0) with `u16`
/// indices, in row-major tile order: the triangles `tris`, the first
/// numbered `*t`, classified under cull mode `cull` and appended to their
/// tiles' bins, as [`bin_triangles`](super::bin_triangles) does; with `SMALL`, for a frame known
/// to be [`small`](crate::render::state::FrameState::small).
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
pub(super) fn bin_fast<const TW: usize, const TH: usize, const SMALL: bool>(
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
    // The visible count before the loop, for the first pairs
    // ([`ONE_TILE_FIRST`]).
    let visible_before = tally.fates[Fate::Visible as usize];
    // The visible triangles the search finds, where counted apart
    // ([`LOCAL_COUNT`]).
    let mut found_visible = 0u32;
    // The triangles left: as an iterator, or where [`COUNT_DOWN`] as a
    // slice, with the number after the last.
    let mut iter = tris.iter();
    let mut rest = tris;
    let last = tt + tris.len();
    'done: loop {
        // The next visible triangle: its number and its pixels.
        // A triangle with an outcode bit set leaves the search (`Err`),
        // so that the search's values need not survive a call.
        let found = loop {
            let tri = if COUNT_DOWN {
                let [tri, tail @ ..] = rest else {
                    break 'done;
                };
                rest = tail;
                tri
            } else {
                let Some(tri) = iter.next() else {
                    break 'done;
                };
                tri
            };
            // The indices read one by one ([`INDEX_BY_REF`]) or copied.
            let copied;
            let idx: &[u16; 3] = if INDEX_BY_REF {
                tri
            } else {
                copied = *tri;
                &copied
            };
            // At most 2^16 triangles a frame: no overflow.
            let k = match COUNT_DOWN {
                true => last - 1 - rest.len(),
                false => tt,
            };
            if !COUNT_DOWN {
                tt += 1;
            }
            let sv = [
                &verts[idx[0] as usize],
                &verts[idx[1] as usize],
                &verts[idx[2] as usize],
            ];
            // ARMv6-M's small frames test the outcodes with the area
            // (see [`wrapping_area2`]).
            let joint = SMALL && !WORDS;
            if !joint && sv[0].outcode() | sv[1].outcode() | sv[2].outcode() != 0 {
                break Err((k, *idx));
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
            } else if joint {
                let v = [sv[0].xy(), sv[1].xy(), sv[2].xy()];
                let oc = sv[0].outcode() | sv[1].outcode() | sv[2].outcode();
                let keep = crate::render::state::keeps_by(cull, wrapping_area2(&v) as i64, 0);
                if oc != 0 {
                    break Err((k, *idx));
                }
                if !keep {
                    continue;
                }
                debug_assert_eq!(keep, keeps_banded(cull, &v, small));
                centres(&v)
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
                    && (r == crate::render::state::meet(&crate::render::state::reach(&v, 0), f)
                        || r.is_empty())
            });
            if r.is_empty() {
                continue;
            }
            if !LOOP_COUNTS_VISIBLE {
                if LOCAL_COUNT {
                    found_visible += 1;
                } else {
                    tally.fates[Fate::Visible as usize] += 1;
                }
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
        // Inside the frame: not negative. In `u32` (x86-64 had extended
        // each coordinate to 64 bits first).
        let tiles = |a: i32, b: i32, size: usize| {
            let size = size as u32;
            ((a as u32 / size) as usize, ((b as u32 - 1) / size) as usize)
        };
        let (c0, cl) = tiles(r.x0, r.x1, TW);
        let (r0, rl) = tiles(r.y0, r.y1, TH);
        if ONE_TILE_FIRST && c0 == cl && r0 == rl {
            // One tile (about two in three visible triangles): one pair,
            // tested by the first and last tiles' equality, not their
            // product, and counted with the visible count at the end.
            push_one(bins, (c0, r0), cols, ctx.t0, k as u16);
            continue;
        }
        let (c1, r1) = (cl + 1, rl + 1);
        let pairs = (c1 - c0) * (r1 - r0);
        if LOOP_COUNTS_VISIBLE {
            sum += VISIBLE + pairs as u64;
        } else if ONE_TILE_FIRST {
            // The first pair is counted with the triangle, at the end.
            // A visible rectangle holds a pixel (`classify`'s and the
            // search's are not empty): at least one pair.
            pairs_sum = pairs_sum.saturating_add(pairs as u32 - 1);
        } else {
            pairs_sum = pairs_sum.saturating_add(pairs as u32);
        }
        if ONE_TILE_FIRST {
            push_rows(bins, (c0, c1), (r0, r1), cols, ctx.t0, k as u16);
        } else {
            push_row_major(bins, (c0, c1), (r0, r1), cols, ctx.t0, k as u16);
        }
    }
    // At most one a triangle, 2^16 a frame: no overflow.
    tally.fates[Fate::Visible as usize] += found_visible;
    if ONE_TILE_FIRST {
        // Every visible triangle of the loop (counted by it or by
        // `classify`) has a first pair. Saturating sums of counts that
        // are not negative: the same total either way.
        let visible = tally.fates[Fate::Visible as usize] - visible_before;
        pairs_sum = pairs_sum.saturating_add(visible);
    }
    *t = match COUNT_DOWN {
        true => last,
        false => tt,
    };
    close_tally(tally, sum, pairs_sum);
}

/// Whether [`bin_fast`]'s search walks the triangles as a slice it
/// shortens by one each time, ending when its length is 0, and takes a
/// triangle's number from that length when the search leaves (the
/// number after the last less the length), rather than by an iterator
/// (a pointer and an end) and a count of its own: on ARMv6-M, whose
/// search loop then held one value fewer across each triangle (the
/// count had been stored and reloaded each triangle, the end reloaded):
/// binning on the `demo` frame 466,774 -> 458,290 instructions, `rock`
/// 407,660 -> 397,828, `grid4` 127,437 -> 127,295. (The number from the
/// iterator's remaining length, `tris.len() - 1 - rest.len()`, kept both
/// the end and a count: `demo` -0.7 K, `rock` -2.1 K, `grid4` +1.6 K;
/// from the pointer's offset, `demo` +2.4 K.)
const COUNT_DOWN: bool = crate::math::SPLIT;

/// Whether [`bin_fast`]'s search reads a triangle's three indices one by
/// one through its reference (the exit to [`classify_apart`] copying
/// them), rather than as one copied `[u16; 3]`, which x86-64 loaded as a
/// 32-bit word and a half-word and took apart again: on 64-bit hosts
/// (binning on the `demo` frame 355,968 -> 346,631 instructions, `rock`
/// 310,532 -> 301,650, `tri4` -22.5 K, `tri100` -4.9 K) and ARMv6-M,
/// where the search's registers moved for the better (494,887 ->
/// 483,068, `rock` -12.9 K, `grid4` -3.2 K); not on the Cortex-M3 (+1.9
/// K) and M4F (+0.6 K).
const INDEX_BY_REF: bool = crate::math::SPLIT || cfg!(target_pointer_width = "64");

/// Whether [`bin_fast`] counts the visible triangles its search finds in
/// a local, added to the tally at the loop's end, rather than in the
/// tally itself (a load of its address, a load, an add and a store): on
/// ARMv6-M (binning on the `demo` frame 483,068 -> 475,207 instructions,
/// `rock` 425,756 -> 416,944, but `grid4` 127,116 -> 129,381); not on
/// x86-64 (`demo` +10.1 K, `tri4` +33 K) nor the Thumb-2 cores (the
/// Cortex-M4F's search then copied its registers round each triangle).
const LOCAL_COUNT: bool = crate::math::SPLIT;

/// Twice the signed area of the triangle `v` in wrapping `i32` products:
/// [`keeps_banded`]'s area for a small frame's vertices inside it (within
/// `0..=2^15` sub-pixels, where nothing wraps).
///
/// On ARMv6-M's small frames ([`bin_fast`] with `SMALL`) the search
/// computes it before the outcodes are known, on vertices that may lie
/// outside (whose area it then ignores): the triangle's values were then
/// held in fewer registers (binning on the `demo` frame 499,579 ->
/// 494,887 instructions, `grid4` -4.5 K, `rock` -0.2 K; the same search
/// on the Thumb-2 cores' words cost the Cortex-M3 +37 K and the M4F
/// +16 K). Its two exits are then tested one after the other, the
/// outcodes first, not as one branch on both: the compiler had tested
/// the outcodes first anyway and a culled triangle then reloaded them
/// from the stack to choose its exit (binning on `demo` 471,751 ->
/// 466,774, `rock` 414,307 -> 407,660, `grid4` 128,229 -> 127,437).
#[inline(always)]
fn wrapping_area2(v: &[SubPoint; 3]) -> i32 {
    let (x1, y1) = (v[1].x.wrapping_sub(v[0].x), v[1].y.wrapping_sub(v[0].y));
    let (x2, y2) = (v[2].x.wrapping_sub(v[0].x), v[2].y.wrapping_sub(v[0].y));
    x1.wrapping_mul(y2).wrapping_sub(x2.wrapping_mul(y1))
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
/// [`reach`]: crate::render::state::reach
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

/// Whether [`bin_fast`] tests for a triangle within one tile before it
/// counts its pairs, by its first and last tiles' equality, and pushes it
/// at once ([`push_one`]; the rest through [`push_rows`]): on ARMv6-M
/// (binning on the `demo` frame 518,011 -> 503,361 instructions, `rock`
/// 455,437 -> 439,816), on 64-bit hosts and on the Cortex-M4F (ARMv7E-M:
/// see [`LOOP_COUNTS_VISIBLE`]), with the visible triangles counted
/// apart ([`LOOP_COUNTS_VISIBLE`]). Not where
/// the loop's 64-bit sum counts them, whose search loop then held its
/// values in other registers and copied them (binning on `demo`: the
/// Cortex-M3 +19.8 K, the M4F +31.5 K, x86-64 +13.4 K), nor with the
/// two paths joined after the push rather than by `continue` (+1.8 K to
/// +8.5 K on each target): there one [`push_row_major`] tests the pairs'
/// product. On RISC-V too (the ESP32-C3's frame 0 of the boards' scene
/// 2,556,595 -> 2,551,260 instructions); not on the Pico 2's Cortex-M33
/// (+8.5 K).
///
/// So exactly where the loop does not count the visible triangles: they
/// are then counted in `tally`, not the loop's sum, and each one's first
/// pair once at the loop's end from that count, so that a one-tile
/// triangle adds nothing (ARMv6-M's binning on the `demo` frame 503,361
/// -> 499,579 instructions, `rock` -1.1 K, `grid4` -6.2 K; the frames'
/// pair counts the same), which [`bin_fast`] relies on.
const ONE_TILE_FIRST: bool = SINGLE_PUSH && !LOOP_COUNTS_VISIBLE;

/// Whether [`bin_fast`] culls and bounds a triangle from its vertices'
/// words ([`ScreenVertex::xy_words`](crate::vertex::ScreenVertex::xy_words), [`Edges`]) rather than from their
/// coordinates: not on ARMv6-M, whose `i32` area (see [`keeps_banded`])
/// takes the coordinates themselves.
const WORDS: bool = !crate::math::SPLIT;

/// A triangle whose three outcodes are 0, from its vertices' words `w`
/// ([`ScreenVertex::xy_words`](crate::vertex::ScreenVertex::xy_words)) for [`bin_fast`]: vertex 0's x word and y,
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
    /// Vertex 0's y, times `2^Y_SHIFT` ([`Y_SHIFT`]).
    y0: i32,
    /// Vertex 1's x word less vertex 0's, and vertex 0's less vertex 2's:
    /// the second negated, so that the area is a multiply and a
    /// multiply-accumulate, with the negation on the visible path alone
    /// (Cortex-M3 -1.2 K).
    dx: (Word, Word),
    /// Vertex 1's and 2's y less vertex 0's, times `2^Y_SHIFT`.
    dy: (Word, Word),
    /// Vertex 1's and 2's x words, for the pixels on 64-bit hosts
    /// ([`centres`](Self::centres)).
    x12: (i32, i32),
}

/// The scale of [`Edges`]' y values, `y 2^Y_SHIFT`: on 64-bit hosts the
/// y words with their low 9 bits cleared (`y 2^9`, within `±2^27`; their
/// differences within `±2^28`, each area product below `2^56`), so that
/// the differences are 64-bit subtractions of the sign-extended loads,
/// where `y` shifted out of each word had been subtracted in 32 bits and
/// each difference sign-extended again; elsewhere `y` itself (the
/// Thumb-2 cores shift it within the subtraction).
const Y_SHIFT: u32 = if cfg!(target_pointer_width = "64") {
    9
} else {
    0
};

/// The type of [`Edges`]' differences: `i64` on 64-bit hosts, where the
/// words are then sign-extended as they are loaded and the area's
/// products take them as they are (x86-64 had extended each of the four
/// before its multiplies), `i32` elsewhere.
#[cfg(target_pointer_width = "64")]
type Word = i64;
#[cfg(not(target_pointer_width = "64"))]
type Word = i32;

// `Word` is `i32` or `i64` by target: a cast that is a no-op on one
// converts on the other.
#[allow(clippy::unnecessary_cast)]
impl Edges {
    #[inline(always)]
    fn of(w: &[(i32, i32); 3]) -> Self {
        let [(x0, y0), (x1, y1), (x2, y2)] = w.map(|(x, y)| (x as Word, y as Word));
        // y as `y 2^Y_SHIFT` ([`Y_SHIFT`]): the word's low bits cleared,
        // or shifted out.
        let y = |w: Word| match Y_SHIFT {
            9 => w & !511,
            _ => w >> 9,
        };
        let y0 = y(y0);
        Self {
            x0: x0 as i32,
            y0: y0 as i32,
            dx: (x1 - x0, x0 - x2),
            dy: (y(y1) - y0, y(y2) - y0),
            x12: (x1 as i32, x2 as i32),
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
        let a = if cfg!(target_pointer_width = "64") {
            x1 as i64 * y2 as i64 + neg_x2 as i64 * y1 as i64
        } else {
            let m = |a: Word, b: Word| crate::math::mul_wide(a as i32, b as i32);
            m(x1, y2) + m(neg_x2, y1)
        };
        crate::render::state::keeps_by(cull, a, 0)
    }

    /// [`centres`]: the least and greatest x word are vertex 0's plus the
    /// least and greatest of 0 and the two differences, `2^8` times the
    /// least and greatest x, so `(x + 7) >> 4` is `(word + 7 2^8) >> 12`;
    /// y's likewise from the y differences.
    #[inline(always)]
    fn centres(&self) -> PixelRect {
        const UP: i32 = HALF_PIXEL - 1;
        let span = |a: Word, b: Word| {
            let (a, b) = (a as i32, b as i32);
            (a.min(b).min(0), a.max(b).max(0))
        };
        // On 64-bit hosts from the x words themselves, so that the area's
        // two-operand products may overwrite the x differences rather
        // than copy them (binning on the `demo` frame 345,097 -> 342,353
        // instructions, `rock` -1.4 K, `tri4` -22 K).
        let (lx, hx) = if cfg!(target_pointer_width = "64") {
            let (x1, x2) = self.x12;
            let x0 = self.x0;
            (x0.min(x1).min(x2) - x0, x0.max(x1).max(x2) - x0)
        } else {
            span(self.dx.0, -self.dx.1)
        };
        let (ly, hy) = span(self.dy.0, self.dy.1);
        PixelRect::new(
            (self.x0 + lx + (UP << 8)) >> (SUBPIXEL_BITS + 8),
            (self.y0 + ly + (UP << Y_SHIFT)) >> (SUBPIXEL_BITS + Y_SHIFT),
            (self.x0 + hx + (UP << 8)) >> (SUBPIXEL_BITS + 8),
            (self.y0 + hy + (UP << Y_SHIFT)) >> (SUBPIXEL_BITS + Y_SHIFT),
        )
    }
}

/// [`FrameState::classify`] of triangle `idx` of the draw `ctx`, out of
/// line: for [`bin_fast`]'s triangles with an outcode bit set.
///
/// Cold on ARMv6-M, 64-bit hosts and the Cortex-M3 (ARMv7-M), where its
/// branch's weight moved the search loop's registers and blocks for the
/// better (binning on the `demo` frame: ARMv6-M 531,813 -> 524,538
/// instructions, x86-64 391,087 -> 383,293, the M3 340,103 -> 338,226,
/// its `rock` -1.5 K, `grid4` -0.8 K), and on the M4F (ARMv7E-M) with
/// its one-tile triangles first ([`ONE_TILE_FIRST`]; see
/// [`LOOP_COUNTS_VISIBLE`]). (Cold on the M4F with the loop's 64-bit sum:
/// its binning 345,991 -> 364,150, its loop then copied two registers
/// round each triangle.)
///
/// [`FrameState::classify`]: crate::render::state::FrameState::classify
#[inline(never)]
#[cfg_attr(
    any(
        microraster_narrow_multiply,
        target_pointer_width = "64",
        microraster_armv7m,
        microraster_armv7em
    ),
    cold
)]
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
