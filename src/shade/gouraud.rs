//! The Gouraud span loops: depth and three colour channels stepped along a
//! span from the planes' values at its first pixel, each pixel's colour
//! through the target's table; with the switches that choose their form
//! per core (ARCHITECTURE.md, the switch table).

#[cfg(target_pointer_width = "64")]
use super::packed::PACKED;
use super::setup::SHIFTED_TOP;
use super::{
    depth16, rgb, rgb16_green_up, Corners, DepthFn, SpanPos, To565, TriangleSetup, GREEN_UP,
    NEGATED_OX, VECTOR_LOOPS, Z_FRAC,
};
use embedded_graphics::pixelcolor::Rgb888;

/// Like [`span_flat`](super::span_flat), with colour interpolated per pixel; returns `n`, the
/// fragments written before, plus its own. `s` is from
/// [`TriangleSetup::for_spans`] (its depth step shifted); `table`, where
/// the span loop reads the colour table (see [`OPAQUE_TABLE`]).
#[inline(always)]
pub(crate) fn span_gouraud<
    C: Copy + From<Rgb888> + 'static,
    D: DepthFn,
    const WRITE: bool,
    const INTERIOR: bool,
>(
    (dt, table): (D, To565),
    s: &TriangleSetup,
    t: &Corners<'_>,
    color: &mut [C],
    depth: &mut [u16],
    sp: SpanPos,
    n: u32,
) -> u32 {
    let SpanPos { ox, j, x0, x1 } = sp;
    let (a0, a1) = if NEGATED_OX {
        (
            x0.wrapping_add(ox) as u32 as usize,
            x1.wrapping_add(ox) as u32 as usize,
        )
    } else {
        ((x0 - ox) as usize, (x1 - ox) as usize)
    };
    // Never taken (see `gouraud_loop`), but here before the starts
    // ([`EARLY_END`]).
    if EARLY_END && !INTERIOR && (a0 >= a1 || a1 > color.len() || a1 > depth.len()) {
        return n;
    }
    if !VECTOR_LOOPS {
        // At its constant address where `FIXED_GOURAUD`.
        let table = if FIXED_GOURAUD { To565::fixed() } else { table };
        // `INTERIOR` is the triangle's, tested once ([`SPLIT_INTERIOR`]).
        // The colour planes shifted already where `SHIFTED_TOP`.
        let [z, r, g, b] = if SHIFTED_TOP {
            s.start_tested_shifted(t, x0, j, INTERIOR)
        } else if DEPTH_BY_STEP && INTERIOR {
            // Depth shifted already.
            s.start_interior_depth_shifted(x0, j)
        } else {
            s.start_tested_as(t, x0, j, INTERIOR)
        };
        // The branch's condition written again: as one `let` for both the
        // Cortex-M3's `demo` took 2,952,741 -> 2,964,108 instructions.
        let z = if DEPTH_BY_STEP && INTERIOR && !SHIFTED_TOP {
            z
        } else {
            z << (16 - Z_FRAC)
        };
        let [gz, gr, gg, gb] = s.steps();
        // The depth step is shifted already ([`TriangleSetup::for_spans`]).
        let (start, step) = loop_values(
            [z, r, g, b].map(|v| v as u32),
            [gz, gr, gg, gb].map(|v| v as u32),
        );
        let place = if STEPS_IN_PLACE { Some(s) } else { None };
        return gouraud_loop::<C, D, WRITE, INTERIOR>(
            (dt, table),
            color,
            depth,
            (a0, a1),
            (start, step, place),
            n,
        );
    }
    #[cfg(target_pointer_width = "64")]
    if PACKED && (INTERIOR || !s.wide) {
        // Red/green and depth/blue packed in a `u64` each, the starts
        // evaluated packed (see `TriangleSetup::packs` for why the lanes
        // never carry into each other at a covered pixel); a triangle
        // that is not interior has its lanes tested and clamped
        // (`TriangleSetup::start_packed_clamped`). Every triangle that is
        // not wide takes this loop: the four-lane loop below is left to
        // the wide ones, and its clamped starts no longer take registers
        // from the set-up that both loops share (x86-64 `demo` 3,097,082
        // -> 3,052,140 instructions, `rock` 2,564,079 -> 2,541,971).
        // Taken only by the triangles whose vertices' depths are all
        // interior (the others to the four-lane loop, their planes packed
        // there), `demo` measured 3,093,276 and `rock` 2,579,820: that
        // test and the four-lane loop's registers cost more than they
        // spared.
        let [mut rg, mut zb] = if INTERIOR {
            s.start_packed(x0, j)
        } else {
            s.start_packed_clamped(t, x0, j)
        };
        let [grg, gzb] = [s.packed[0][0], s.packed[1][0]];
        if a0 >= a1 {
            return n;
        }
        let (color, depth) = (&mut color[a0..a1], &mut depth[a0..a1]);
        let mut n = n + color.len() as u32;
        for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
            // `depth16` of the upper lane, the top bytes of the shifted
            // channels.
            let zz = (zb >> 48) as u16;
            if dt.pass(zz, *d) {
                if WRITE {
                    *d = zz;
                }
                *c = rgb::<C>((rg >> 56) as u8, (rg >> 24) as u8, (zb >> 24) as u8);
            } else {
                crate::hint::cold();
                n -= 1;
            }
            rg = rg.wrapping_add(grg);
            zb = zb.wrapping_add(gzb);
        }
        return n;
    }
    // The channels shifted left by 8 already (`SHIFTED_COLOR`): the byte
    // that `rgb` takes, bits 16 to 23, is then the top byte, taken by one
    // shift and no mask; the wrapping steps keep exactly the bits that
    // matter. `INTERIOR` is the triangle's, tested once
    // ([`SPLIT_INTERIOR`]).
    let [z, r, g, b] = s.start_shifted(t, x0, j, INTERIOR);
    let z = (z as u32) << (16 - Z_FRAC);
    let [gz, gr, gg, gb] = s.steps();
    // Shifted already ([`TriangleSetup::for_spans`]).
    let gz = gz as u32;
    // Never taken: the walk keeps only spans of a pixel or more. (With it
    // the set-up inlined above spills less: x86-64 `demo` 4,356,901 ->
    // 4,345,743 instructions, `rock` 3,619,381 -> 3,610,624, `tri100`
    // 13,438,526 -> 13,419,816; without it, once the vector loop was
    // gone, `demo` 3,277,579 -> 3,313,931.)
    if a0 >= a1 {
        return n;
    }
    let (color, depth) = (&mut color[a0..a1], &mut depth[a0..a1]);
    // Only targets with SIMD reach here (on 64-bit hosts, only the spans
    // of wide triangles: the others take the packed loop above), but
    // every span takes this plain loop. A vector loop (`gouraud_run`,
    // branch-free, for the whole groups of eight of spans of 24 pixels
    // or more, until `ae3b025`) was
    // a call in the span loop, around which the span starts' and this
    // loop's registers were spilled; without it x86-64 `demo` 3,369,702
    // -> 3,277,579 instructions, `rock` -92 K, `tri4`, `tri100` and
    // `tri1000` -230 K to -320 K, only `tri10000` (spans about a tile
    // wide) +110 K of 27.5 M. Called only for the long spans, the whole
    // span in the vector loop, `demo` took 3,354,257.
    let [mut z, mut r, mut g, mut b] = [z, r as u32, g as u32, b as u32];
    let [gz, gr, gg, gb] = [gz, gr as u32, gg as u32, gb as u32];
    // Every fragment counted as written, those that fail taken off on a
    // path marked rare, as in `gouraud_loop`.
    let mut n = n + color.len() as u32;
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        let zz = depth16(z);
        if dt.pass(zz, *d) {
            if WRITE {
                *d = zz;
            }
            *c = rgb::<C>((r >> 24) as u8, (g >> 24) as u8, (b >> 24) as u8);
        } else {
            crate::hint::cold();
            n -= 1;
        }
        z = z.wrapping_add(gz);
        r = r.wrapping_add(gr);
        g = g.wrapping_add(gg);
        b = b.wrapping_add(gb);
    }
    n
}

/// Whether the Gouraud span loops of an [`interior`](TriangleSetup::interior)
/// triangle are a copy of their own, [`span_gouraud`] with `INTERIOR`:
/// the triangle tested once, not at every span start. On every target
/// since x86-64's Gouraud loop lost its vector loop (there `demo`
/// 3,277,579 -> 3,268,079 instructions, `rock` 2,734,575 -> 2,728,649;
/// with the vector loop's call in the span loop it had measured +59 K).
pub(crate) const SPLIT_INTERIOR: bool = true;

/// On ARMv6-M the Gouraud loop holds the channels shifted left by 8
/// (wrapping, as in `span_gouraud`'s remainder loop): the byte that
/// `rgb` takes, bits 16 to 23, is then the top byte, taken by one shift
/// and no `uxtb`. `(c << 8) + k (g << 8)` is `(c + k g) << 8` modulo
/// 2^32, whose top byte is bits 16 to 23 of `c + k g`: the same bytes.
const TOP_BYTE: bool = cfg!(microraster_narrow_multiply);

/// Whether [`gouraud_loop`]'s empty `black_box` (which keeps the loop
/// from being unrolled, and the steps' loads in it where
/// [`STEPS_IN_PLACE`]) ends each pixel rather than begins it: on ARMv6-M
/// ([`TOP_BYTE`]). The pixel loop's instructions are the same, the code
/// of the spans around it shorter: `demo` 6,007,178 -> 5,991,471
/// instructions; `rock`, `grid4` and `demo-flat` the same.
const FENCE_LAST: bool = TOP_BYTE;

/// Whether [`gouraud_loop`] reads its four steps from the set-up at each
/// pixel (ARMv6-M, with the colour planes shifted by the set-up,
/// [`SHIFTED_TOP`]: the steps are the set-up's fields as they are),
/// the set-up's address passed once a pair through an empty `black_box`
/// (`render::fill::shade`), so that the pixel loop's own `black_box` (a
/// memory clobber) keeps the loads in the loop. The span starts and the
/// loop then read the planes where the set-up stored them: no copy of
/// the fields to spill slots once a pair.
pub(crate) const STEPS_IN_PLACE: bool = SHIFTED_TOP;

/// Whether an [`interior`](TriangleSetup::interior) triangle's span
/// starts take depth shifted for the loop from the depth step
/// ([`TriangleSetup::start_interior_depth_shifted`]): on the Cortex-M3
/// (the build script's `microraster_armv7m`), where the span start then
/// holds one plane coefficient fewer, and on RISC-V (the ESP32-C3's
/// frame 0 of the boards' scene 2,515,461 -> 2,514,330 instructions);
/// not on the Pico 2's Cortex-M33 (+21 K).
const DEPTH_BY_STEP: bool = cfg!(any(microraster_armv7m, target_arch = "riscv32"));

/// The start and step of depth (shifted, see `depth16`), red, green and
/// blue as [`gouraud_loop`] takes them: the channels shifted left by 8
/// on ARMv6-M ([`TOP_BYTE`]), green raised by [`GREEN_UP`] elsewhere (see
/// `rgb16_green_up`: a covered pixel's channel is within `0..256` units,
/// see `Plane`, so its bits 16 to 24 are then its index in the 6-bit half
/// of the table).
#[inline(always)]
fn loop_values(start: [u32; 4], step: [u32; 4]) -> ([u32; 4], [u32; 4]) {
    let ([z, r, g, b], [gz, gr, gg, gb]) = (start, step);
    if SHIFTED_TOP {
        // Shifted by the set-up ([`SHIFTED_TOP`]).
        (start, step)
    } else if TOP_BYTE {
        ([z, r << 8, g << 8, b << 8], [gz, gr << 8, gg << 8, gb << 8])
    } else {
        ([z, r, g.wrapping_add(GREEN_UP), b], step)
    }
}

/// The loop of [`span_gouraud`] on targets without SIMD: pixels `a0..a1`
/// of the tile row, not unrolled. Spans are 2 to 3 pixels long: unrolled
/// by four (as LLVM does for the Cortex-M targets), the loop costs more
/// per span, in its set-up and its remainder, than it saves per pixel.
///
/// What keeps LLVM from unrolling it is the empty `black_box` in its
/// body, inline assembly that costs no instruction: the Arm targets'
/// unrolling preferences give up on a loop that holds a call. (Before,
/// each pixel was indexed with its bounds check, whose second exit stopped
/// the unroller too, but took a compare and a branch per pixel and a
/// register for the index; the Cortex-M3's `demo` 4,742,681 -> 4,670,545
/// instructions, `rock` about 3,915,040 -> 3,840,867.) Should the hint
/// ever stop doing that, the pixels stay the same; only the speed moves.
///
/// The count of written fragments is the span's length less those that
/// fail, on a path marked cold ([`crate::hint::cold`]): about one fragment in twenty
/// fails in `demo`. Weighted so, the register allocator keeps the written
/// path's values, the four steps and the colour table's address, in
/// registers and the count in memory, 23 instructions a written pixel
/// where there were 27 with two steps reloaded and the table's address
/// rebuilt (the Cortex-M3's `demo` 4,670,545 -> 4,610,743, `rock`
/// 3,840,867 -> 3,767,471; either change alone measured worse: the count
/// of failures without the hint 4,716,282, the hint with the count of
/// writes 4,713,809).
#[inline(always)]
fn gouraud_loop<
    C: Copy + From<Rgb888> + 'static,
    D: DepthFn,
    const WRITE: bool,
    const INTERIOR: bool,
>(
    (dt, table): (D, To565),
    color: &mut [C],
    depth: &mut [u16],
    (a0, a1): (usize, usize),
    (start, step, place): ([u32; 4], [u32; 4], Option<&TriangleSetup>),
    mut n: u32,
) -> u32 {
    // As `loop_values` makes them.
    let [mut z, mut r, mut g, mut b] = start;
    let [gz, gr, gg, gb] = step;
    const TOP: bool = TOP_BYTE;
    // Never taken: the walk keeps spans of a pixel or more, inside the
    // tile. One test for the slices' ranges and the loop's first pixel,
    // where the slices' checks and the loop's own test of an empty span
    // took three.
    if a0 >= a1 || a1 > color.len() || a1 > depth.len() {
        return n;
    }
    let (color, depth) = (&mut color[a0..a1], &mut depth[a0..a1]);
    // Every fragment counted as written; those that fail are taken off
    // (wrapping: where `COUNT_AFTER`, before the span's own are added;
    // an interior triangle's loop only, see there).
    let len = color.len() as u32;
    let count_after = COUNT_AFTER && INTERIOR;
    if !count_after {
        n += len;
    }
    for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
        // Not unrolled (see above): no instruction, no value.
        if !FENCE_LAST {
            core::hint::black_box(());
        }
        let zz = depth16(z);
        if STORE_AFTER {
            let shaded = if dt.pass(zz, *d) {
                if WRITE {
                    *d = zz;
                }
                rgb16_green_up(table, r, g, b)
            } else {
                crate::hint::cold();
                n = n.wrapping_sub(1);
                // Stored back as it was (see `STORE_AFTER`).
                *c
            };
            *c = shaded;
        } else if dt.pass(zz, *d) {
            if WRITE {
                *d = zz;
            }
            *c = if TOP {
                top_rgb::<C>(r, g, b)
            } else {
                rgb16_green_up(table, r, g, b)
            };
        } else {
            // Counted in `n` already: rare (see above). Marked cold on
            // ARMv6-M too since `top_rgb` and the steps' order there:
            // `demo` 5,902,459 -> 5,898,746 instructions (all-scenes
            // build 5,902,505 -> 5,898,792, `rock`, `grid4`, `demo-flat`
            // and `fill` the same). It had cost there before (`demo`
            // 7,801,997 -> 7,849,110, `rock` 6,455,162 -> 6,503,035;
            // +26 K against 6,007,178 in the round of `8570c89`):
            // the counter and a channel then lived in stack slots around
            // the written path.
            crate::hint::cold();
            n = n.wrapping_sub(1);
        }
        // Read where the set-up holds them, after the `black_box` above
        // (see `STEPS_IN_PLACE`); `step` elsewhere.
        let [gz, gr, gg, gb] = match place {
            Some(s) if STEPS_IN_PLACE => s.steps().map(|v| v as u32),
            _ => [gz, gr, gg, gb],
        };
        if FENCE_LAST {
            // Blue, then red, then green: the written path's registers
            // then fall best (ARMv6-M `demo` 5,906,658 -> 5,902,459
            // instructions with `top_rgb`'s order; blue, green, red
            // 5,906,658, other orders up to 5,940,733; before `top_rgb`,
            // green before red took 5,991,471 to 5,965,273).
            b = b.wrapping_add(gb);
            r = r.wrapping_add(gr);
            g = g.wrapping_add(gg);
            z = z.wrapping_add(gz);
        } else {
            z = z.wrapping_add(gz);
            r = r.wrapping_add(gr);
            g = g.wrapping_add(gg);
            b = b.wrapping_add(gb);
        }
        // At the end of the pixel where `FENCE_LAST`: the next pixel's
        // steps are read after it all the same.
        if FENCE_LAST {
            core::hint::black_box(());
        }
    }
    if count_after {
        n.wrapping_add(len)
    } else {
        n
    }
}

/// The colour of channels whose top bytes are `r`, `g` and `b`, as
/// [`gouraud_loop`] takes it where [`TOP_BYTE`]: on ARMv6-M with red's and
/// blue's table reads first (`convert::rgb_red_blue_first`, the same
/// bits).
#[inline(always)]
fn top_rgb<C: From<Rgb888> + 'static>(r: u32, g: u32, b: u32) -> C {
    let [r, g, b] = [r, g, b].map(|c| (c >> 24) as u8);
    #[cfg(microraster_narrow_multiply)]
    return super::convert::rgb_red_blue_first::<C>(r, g, b);
    #[cfg(not(microraster_narrow_multiply))]
    rgb::<C>(r, g, b)
}

/// Whether [`gouraud_loop`] adds a span's fragments to the count after
/// its pixels rather than before (those that fail are taken off in the
/// loop either way, so the sum is the same): on the Cortex-M3 (the build
/// script's `microraster_armv7m`), with [`STORE_AFTER`]. There the count,
/// held in a stack slot, is then read and written once a span after the
/// loop rather than before it, and the span start's registers come out
/// better: `demo` 3,091,310 -> 3,082,151 instructions with `STORE_AFTER`
/// (3,135,395 without it). Not on the Cortex-M4F (`demo` 3,061,846 ->
/// 3,080,948) nor ARMv6-M (6,250,433 -> 6,282,373).
///
/// Only in the loop of an [`interior`](TriangleSetup::interior)
/// triangle (`gouraud_loop`'s `INTERIOR`): the loop of the others counts
/// before its pixels, from the span's ends, and no longer spills the
/// span's length to read it back after the loop (`demo` 2,952,741 ->
/// 2,949,074 against `b54a8eb`, `rock` 2,436,640 -> 2,429,006, `grid4`
/// 838,843 -> 838,495). The interior loop counting before too measured
/// worse (`demo` 2,968,383).
const COUNT_AFTER: bool = cfg!(microraster_armv7m);

/// Whether [`span_gouraud`] tests the span's ends against the slices
/// (the test `gouraud_loop` makes, never taken) before it evaluates the
/// starts of a triangle that is not interior, where the loop made it
/// after the clamped starts, with the end read back from a stack slot
/// (`gouraud_loop`'s own test then folds away; kept as measured:
/// the registers around the clamped starts move with it).
/// On the Cortex-M3 and ARMv6-M. On the Cortex-M3: `demo` 2,946,917 ->
/// 2,940,881 instructions, `rock` 2,429,001 -> 2,424,965, `grid4`
/// 838,495 -> 838,356, `fill` the same.
/// (The interior loop tested early too: the same count. The end masked
/// into the tile instead, so that its test could go: `demo` +11 K, and
/// +112 K in both loops.) On ARMv6-M too: `demo` 5,846,622 -> 5,844,402
/// (single-scene build); `rock`, `demo-flat`, `grid4`, `fill`, the
/// shader fills and `demo-textured-lit` the same.
const EARLY_END: bool = cfg!(any(microraster_armv7m, microraster_narrow_multiply));

/// Whether [`gouraud_loop`] stores the colour after the depth test's two
/// paths meet, a fragment that fails storing back the colour it read
/// (ARMv7E-M and the Cortex-M3, the build script's `microraster_armv7em`
/// and `microraster_armv7m`): the store is then in the block that steps
/// the pointer, and folds that step in (a post-indexed `STRH`), one
/// instruction fewer a written pixel in both Gouraud loops (the
/// Cortex-M4F's `demo` 3,146,311 -> 3,141,501 instructions, `rock`
/// 2,610,488 -> 2,604,224), for a load on the rare path of a fragment
/// that fails. On the Cortex-M3 only with [`COUNT_AFTER`]: alone its
/// span starts took three instructions more (`demo` 3,091,310 ->
/// 3,092,626). Not on ARMv6-M, which has no post-indexed store. On
/// ARMv8-M Mainline too (`microraster_armv8m`: the Pico 2's frame 0 of
/// the boards' scene 2,221,600 -> 2,204,950 instructions); not on
/// RISC-V (+2.5 K), which has no post-indexed store either.
const STORE_AFTER: bool = cfg!(any(
    microraster_armv7em,
    microraster_armv7m,
    microraster_armv8m
));

/// Whether the Gouraud loop of a triangle that is not
/// [`interior`](TriangleSetup::interior) reads the colour table through
/// its address made opaque once a pair ([`To565::opaque`], in
/// `render::fill::shade`): on ARMv7E-M (the build script's
/// `microraster_armv7em`), where that loop otherwise rebuilt the address
/// (`MOVW`, `MOVT`) at each written pixel and kept it in no register. It
/// now keeps the address in a register across the pair, and reloads a
/// second step from the stack instead: one instruction fewer a written
/// pixel (the Cortex-M4F's `demo` 3,158,058 -> 3,154,971 instructions).
/// On the Cortex-M3 (`microraster_armv7m`) too from `demo` 3,082,151
/// -> 3,078,465 instructions, but no longer since that loop counts
/// before its pixels ([`COUNT_AFTER`] for the interior loop only): with
/// the constant address `demo` 2,949,074 -> 2,946,917, `rock` -5,
/// `grid4` the same; never in builds optimised for size (the build
/// script's `microraster_size`: the OLED firmware 43,304 -> 44,020 B).
/// The interior loop, which keeps the address already, reads the table
/// at its constant address. (The Cortex-M4F's Gouraud loops now read it
/// at its constant address in either case: [`FIXED_GOURAUD`].) On
/// ARMv8-M Mainline (`microraster_armv8m`) with the table's address used
/// as it is passed: the Pico 2's frame 0 of the boards' scene 2,175,350
/// -> 2,155,650 instructions (with [`FIXED_GOURAUD`] or [`OPAQUE_FLAT`]
/// too: no better).
pub(crate) const OPAQUE_TABLE: bool = cfg!(any(microraster_armv7em, microraster_armv8m));

/// Whether the table's address is made opaque ([`OPAQUE_TABLE`]) for the
/// flat span loops too, which never read it: on ARMv7E-M, whose flat loop
/// the `black_box` left better (the Cortex-M4F's `fill` 14.62 per pixel,
/// 14.70 without it); not on the Cortex-M3 (`fill` 8,989,683 ->
/// 8,990,443 instructions with it).
pub(crate) const OPAQUE_FLAT: bool = cfg!(microraster_armv7em);

/// Whether [`span_gouraud`] reads the colour table at its constant address
/// whatever the caller passes (the address made opaque where
/// [`OPAQUE_TABLE`]): on ARMv7E-M (the build script's
/// `microraster_armv7em`), whose flat span loops keep the opaque address
/// ([`OPAQUE_FLAT`]). The Cortex-M4F's code around the Gouraud loop of the
/// triangles that are not interior spills less so, although that loop
/// rebuilds the address (`MOVW`, `MOVT`) at each written pixel again
/// (LLVM schedules a core with a floating-point unit for latency: its
/// registers fall differently from the Cortex-M3's). `demo` 3,010,132 ->
/// 3,003,718 instructions, `rock` 2,506,296 -> 2,496,993; in the
/// all-scenes build `demo` 3,017,989 -> 3,011,575, `rock` 2,514,074 ->
/// 2,504,771, `grid4` 861,024 -> 858,285, `fill` and `demo-flat` the
/// same. (`OPAQUE_TABLE` off for the M4F, its flat loops' table fixed
/// too: `demo` 2,999,703 but `demo-flat` 2,536,732 -> 2,553,160, `fill`
/// 14.39 -> 14.47 a pixel.)
pub(crate) const FIXED_GOURAUD: bool = cfg!(microraster_armv7em);
