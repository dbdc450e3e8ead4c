//! The scanline walk's edges evaluated row by row with one division each
//! ([`Direct`]), and the row loop that divides ([`half_direct`]): how a
//! core with a division instruction (the Cortex-M3 and M4) takes a
//! triangle whose columns lie within `0..DIRECT_COLS`.
//!
//! An edge's column at a row is `ceil((x_edge(y_c) - ½) / 1)` in pixels,
//! the ceiling of the numerator `N = (p.x - ½) dy + t dx` (`t` the row
//! centre's offset below `p`) over `16 dy`. The stepped edges of
//! [`EdgeStepper`](super::edge::EdgeStepper) and [`Packed`](super::packed::Packed)
//! keep that quotient and its remainder, and set them up with a division
//! for the step, a start from it, the sign of each tested; here the
//! numerator itself is kept, biased to be non-negative and divided by 16
//! (floored, exact: its step per row is a multiple of 16), and divided
//! by `dy` at each row: its set-up is two multiplies, and a row's step
//! one add and one division, where the stepper takes an add, a compare
//! and a subtract.
//! On the Cortex-M3 a division is one instruction (2 to 12 cycles).

use crate::raster::{Span, SubPoint, HALF_PIXEL, SUBPIXEL};
use core::num::NonZeroU32;

/// Columns a [`Direct`] edge may take, `0..DIRECT_COLS`: its vertices'
/// `x` within `-7..DIRECT_COLS * SUBPIXEL - 8`, so that `x + 8`, with
/// the edge at most [`DIRECT_DY`] sub-pixels tall, keeps the numerator
/// below 2^29.
pub(super) const DIRECT_COLS: i32 = 1 << 10;

/// Height in sub-pixels below which an edge can be [`Direct`].
pub(super) const DIRECT_DY: i32 = 1 << 15;

/// One edge being walked down the rows, as the numerator of its column
/// at the current row: `m / d` is the column.
#[derive(Clone, Copy, Debug)]
pub(super) struct Direct {
    /// `floor((N + 16 dy - 1) / 16)`, with `N = (p.x - ½) dy + t dx` the
    /// edge's numerator at the current row: `floor(m / d) = ceil(N / 16
    /// dy)`. Non-negative at every row of the edge, where `x_edge >= -7`
    /// sub-pixels makes `N > -16 dy`.
    m: u32,
    /// `dx`: the numerator's step per row (wrapping: `dx` may be
    /// negative).
    s: u32,
    /// `dy`.
    d: NonZeroU32,
}

impl Direct {
    /// Starts the edge `p -> q` (`q.y > p.y`) at pixel row `row`, whose
    /// centre lies within the edge's rows (`p.y <= y_c < q.y`). The
    /// vertices' `x` must lie within `-7..DIRECT_COLS * SUBPIXEL - 8` and
    /// the edge's height below [`DIRECT_DY`].
    ///
    /// Any row: with `0 <= t < dy < 2^15`, `|dx| < 2^14` and
    /// `0 < p.x + 8 <= 2^14`, both products are below 2^29.
    ///
    /// `MAX`: the divisor's fallback written as `max(d, 1)` on the
    /// Cortex-M3 too (below).
    #[inline(always)]
    pub(super) fn new<const MAX: bool>(p: SubPoint, q: SubPoint, row: i32) -> Self {
        let dx = q.x - p.x;
        let dy = q.y - p.y;
        debug_assert!(dy > 0 && dy < DIRECT_DY);
        debug_assert!(p.x >= 1 - HALF_PIXEL && p.x <= DIRECT_COLS * SUBPIXEL - HALF_PIXEL);
        let t = row * SUBPIXEL + HALF_PIXEL - p.y;
        debug_assert!(t >= 0 && t < dy);
        // (p.x - ½) dy + t dx + 16 dy - 1, divided by 16 (floored): the
        // column `floor(m / 16 dy)` is `floor(floor(m / 16) / dy)`, and
        // the row's step `16 dx` a multiple of 16, so `floor(m / 16)`
        // steps by `dx` exactly.
        const _: () = assert!(SUBPIXEL == 1 << 4);
        let m = ((p.x + HALF_PIXEL) * dy + t * dx - 1) >> 4;
        debug_assert!(m >= 0);
        let d = dy as u32;
        // dy > 0 (the caller walks edges downwards); the fallback only
        // spares the divisions their checks. On a 64-bit host as
        // `max(d, 1)`, which the compiler knows is not zero: on x86-64 a
        // compare and an add with carry where `unwrap_or` took a compare,
        // a move and a select (`demo` 3,390,172 -> 3,371,343
        // instructions). The Cortex-M3's `demo` took -9.4 K but its `fill`
        // 14.64 -> 14.67 a pixel, the M4F's `demo` +5.5 K: they keep
        // `unwrap_or`, but for the M3's upper short edge (`MAX`): the
        // same instructions a set-up, where the walk's registers fell
        // better (M3 `demo` 3,119,285 -> 3,112,233, `rock` 2,555,054 ->
        // 2,550,565, `fill` 14.64 -> 14.63 a pixel; `max` for the long
        // edge or the lower one too measured +1 K to +34 K, `fill` up to
        // 14.72).
        let d = if cfg!(target_pointer_width = "64") || MAX && cfg!(microraster_armv7m) {
            NonZeroU32::new(d.max(1)).unwrap_or(NonZeroU32::MIN)
        } else {
            NonZeroU32::new(d).unwrap_or(NonZeroU32::MIN)
        };
        Self {
            m: m as u32,
            s: dx as u32,
            d,
        }
    }
}

/// Which sides [`half_direct`] clamps a span to, with `CLAMP`: the left
/// (`x0`), the right (`x1`) or both.
pub(super) const LEFT: u8 = 1;
/// See [`LEFT`].
pub(super) const RIGHT: u8 = 2;
/// See [`LEFT`].
pub(super) const BOTH: u8 = LEFT | RIGHT;

/// [`half`](super::half) for [`Direct`] edges: records the non-empty
/// spans of rows `row..stop` in `out` from its start, and returns the
/// slots left. With `CLAMP`, the spans clipped to columns `x0..x1` (a
/// triangle across its tile's side columns) on the `SIDES` side or
/// sides ([`LEFT`], [`RIGHT`], [`BOTH`]), without (a triangle within
/// them; `x0` and `x1` unused). `FRESH`: the clamped rows take the
/// columns as values of their own (see below).
#[inline(always)]
pub(super) fn half_direct<'a, const CLAMP: bool, const SIDES: u8, const FRESH: bool>(
    out: &'a mut [Span],
    row: i32,
    stop: i32,
    left: &mut Direct,
    right: &mut Direct,
    x0: i32,
    x1: i32,
) -> &'a mut [Span] {
    let (mut lm, ls, ld) = (left.m, left.s, left.d);
    let (mut rm, rs, rd) = (right.m, right.s, right.d);
    // With `FRESH` (the walk inlined in the tile loop of 64-bit hosts,
    // whose clip is a copy held for the whole tile), the columns through
    // an empty `black_box`: values of this half, which the clamped row
    // loop keeps in registers, where it had reloaded the tile's copy
    // from the stack at every row (x86-64 `fill` 8.82 -> 8.76 a pixel,
    // `tri10000` 24,523,787 -> 24,437,426 instructions, for `demo`
    // 2,810,655 -> 2,814,923 and `rock` 2,335,261 -> 2,339,073). Only
    // the column a one-side walk clamps to: the `black_box` of both had
    // stored and loaded the unused one too, at every such half (x86-64
    // `demo` 2,814,923 -> 2,812,399, `rock` -1.9 K, `tri4` -3.2 K,
    // `tri100` -7.9 K, `tri10000` -1.5 K, `fill` -308).
    let (x0, x1) = if CLAMP && FRESH {
        match SIDES {
            LEFT => (core::hint::black_box(x0), x1),
            RIGHT => (x0, core::hint::black_box(x1)),
            _ => core::hint::black_box((x0, x1)),
        }
    } else {
        (x0, x1)
    };
    let mut rest = out;
    for j in row..stop {
        // Below 2^29 / 16: the casts keep the value.
        let (c0, c1) = ((lm / ld) as i32, (rm / rd) as i32);
        let (x0, x1) = if CLAMP {
            match SIDES {
                LEFT => (c0.max(x0), c1),
                RIGHT => (c0, c1.min(x1)),
                _ => (c0.max(x0), c1.min(x1)),
            }
        } else {
            (c0, c1)
        };
        // Only a non-empty span takes a slot, and is written: an empty
        // row (half the rows walked, at a triangle's tips) then costs a
        // compare and a branch rather than the stores and the slot test.
        if x0 < x1 {
            let Some((o, r)) = core::mem::take(&mut rest).split_first_mut() else {
                // No slot left.
                break;
            };
            *o = Span { j, x0, x1 };
            rest = r;
        }
        // Past the edge's last row the numerator is never divided.
        lm = lm.wrapping_add(ls);
        rm = rm.wrapping_add(rs);
    }
    (left.m, right.m) = (lm, rm);
    rest
}
