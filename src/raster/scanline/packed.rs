//! The scanline walk's edges packed into one word each ([`Packed`]), and
//! the row loop that steps them ([`half_packed`]): how the walk takes a
//! triangle that lies within its tile's columns, and on a 32-bit core
//! one whose columns lie within `0..PACKED_COLS` (with clamps).

use super::edge::{ceil_div_rem32, far_start_of, EdgeStepper};
use crate::raster::{Span, SubPoint, HALF_PIXEL, SUBPIXEL, SUBPIXEL_BITS};
use core::num::NonZeroU32;

/// Bits of a [`Packed`] edge's column: with `NARROW` (ARMv6-M) 11 from
/// bit 0, read sign-extended by two shifts (the columns `0..PACKED_COLS`
/// read the same), where a shift and a mask had the mask's constant loaded
/// from the literal pool at every row (no register left for it).
const COL_BITS: u32 = if NARROW { 11 } else { 10 };

/// Where a [`Packed`] edge's column starts: bit 1, not 0, so that the
/// column is read by one bit-field extract (`ubfx` on Arm), which leaves
/// the word in its register. A mask of the low bits made the M3 copy each
/// word before clearing its upper bits in place (two instructions a row).
/// With `NARROW`, bit 0 (see [`COL_BITS`]).
const COL_SHIFT: u32 = if NARROW { 0 } else { 1 };

/// Bits below a [`Packed`] edge's error term: the column and, but for
/// `NARROW`, bit 0 (always clear).
const PACKED_BITS: u32 = COL_BITS + COL_SHIFT;

/// Columns a [`Packed`] edge may take, `0..PACKED_COLS`, less one: a step
/// passes through its column plus one before a carry takes it back.
pub(super) const PACKED_COLS: i32 = (1 << (PACKED_BITS - 1)) - 1;

/// Height in sub-pixels up to which an edge can be [`Packed`]: its error
/// term (below `SUBPIXEL * PACKED_DY`, 2^19), shifted, and a step's column
/// change (below 2^14 for an edge within `PACKED_COLS` columns) then fit
/// an `i32` with room to spare. 2,048 pixels: taller edges are walked as
/// [`EdgeStepper`]s.
pub(super) const PACKED_DY: i32 = 1 << 15;

/// An [`EdgeStepper`] whose columns lie within `0..PACKED_COLS` (a
/// triangle within a tile's columns), with its column in [`COL_BITS`]
/// from bit [`COL_SHIFT`] of one word and its error term above: a row's step is
/// one add, and the carry one compare and one subtract, with three words
/// live per edge rather than five, so that the row loop of a 32-bit core
/// keeps both edges in registers.
///
/// The error term is negative, and the column stays within its bits at
/// every row of the edge (the step's column change, before and after a
/// carry, lands on the columns of two rows of the edge, or one past), so
/// the word is negative exactly when the error term is: the same compare
/// as [`half`](super::half)'s, the same columns. Only the step past an edge's last
/// row may take the column out of its bits, and that value is never read.
#[derive(Clone, Copy, Debug)]
pub(super) struct Packed {
    /// `err << PACKED_BITS | col << COL_SHIFT`.
    p: i32,
    /// `step_err << PACKED_BITS + step_col << COL_SHIFT`.
    s: i32,
    /// `den << PACKED_BITS + 1 << COL_SHIFT`: a carry takes one column
    /// back.
    d: i32,
}

impl EdgeStepper {
    /// This edge [`Packed`]; its column at the current row must lie
    /// within `0..PACKED_COLS` and its height within [`PACKED_DY`].
    #[inline(always)]
    fn packed(&self) -> Packed {
        debug_assert!((0..PACKED_COLS).contains(&self.col));
        debug_assert!(self.den <= PACKED_DY * SUBPIXEL);
        Packed {
            p: (self.err << PACKED_BITS) | (self.col << COL_SHIFT),
            s: (self.step_err << PACKED_BITS) + (self.step_col << COL_SHIFT),
            d: (self.den << PACKED_BITS) + (1 << COL_SHIFT),
        }
    }
}

impl Packed {
    /// [`EdgeStepper::new`], packed: the edge's columns must lie within
    /// `0..PACKED_COLS` and its height within [`PACKED_DY`].
    ///
    /// The start's error term and column come packed from the numerator
    /// `n` of the near start with no test of its sign: with `P = 16 Q +
    /// R`, the word `-n << PACKED_BITS` plus `Q + 1 << COL_SHIFT` is
    /// negative exactly
    /// when the ceiling is `Q + 1` (`n > 0`), the word of the error term
    /// `-n` and that column; otherwise the carry of the row loop, taking
    /// `d` off, gives the error term `-n - den` and the column `Q`.
    #[inline(always)]
    pub(super) fn new<const NEAR: bool>(p: SubPoint, q: SubPoint, row: i32) -> Self {
        let dx = q.x - p.x;
        let dy = q.y - p.y;
        debug_assert!(dy > 0 && dy <= PACKED_DY);
        let dy = NonZeroU32::new(dy as u32).unwrap_or(NonZeroU32::MIN);
        let (step_col, r) = ceil_div_rem32(dx, dy);
        const SHIFT: u32 = PACKED_BITS + SUBPIXEL_BITS;
        // `den << PACKED_BITS` plus one column, `den = SUBPIXEL dy` at
        // most 2^19.
        let d = ((dy.get() as i32) << SHIFT) + (1 << COL_SHIFT);
        let s = (r << SHIFT) + (step_col << COL_SHIFT);
        let t = row * SUBPIXEL + HALF_PIXEL - p.y;
        debug_assert!(!NEAR || (t as u32) < SUBPIXEL as u32);
        let w = if NEAR || (t as u32) < SUBPIXEL as u32 {
            // As in `EdgeStepper::new`: |n| < den.
            let big_p = p.x - HALF_PIXEL + t * step_col;
            let n = dy.get() as i32 * (big_p & (SUBPIXEL - 1)) - t * r;
            // The column `Q + 1` from bit 1 by one shift: bit 0 takes bit
            // 3 of `P`, which no step or carry changes (both are even),
            // and which the row loop never reads.
            let w = (-n << PACKED_BITS) + (big_p >> (SUBPIXEL_BITS - COL_SHIFT)) + (1 << COL_SHIFT);
            if w >= 0 {
                w - d
            } else {
                w
            }
        } else {
            let (col, rem) = far_start_of(p, dx, dy, t, (step_col, r));
            // The error term `rem - den`, and the column.
            ((rem - (d >> PACKED_BITS)) << PACKED_BITS) | (col << COL_SHIFT)
        };
        debug_assert_eq!(
            w & !((1 << COL_SHIFT) - 1),
            EdgeStepper::new::<false>(p, q, row).packed().p
        );
        Self { p: w, s, d }
    }
}

/// A [`Packed`] word's column.
const MASK: i32 = (1 << COL_BITS) - 1;

/// A [`Packed`] word `p`'s column.
#[inline(always)]
fn column(p: i32) -> i32 {
    if NARROW {
        (p << (32 - COL_BITS)) >> (32 - COL_BITS)
    } else {
        (p >> COL_SHIFT) & MASK
    }
}

/// A [`Packed`] word `p` one row on, by its step `s` and, when the error
/// term turns non-negative, its correction `d`.
#[inline(always)]
fn next_row(p: i32, s: i32, d: i32) -> i32 {
    let p = p + s;
    if p >= 0 {
        p - d
    } else {
        p
    }
}

/// Whether [`half_packed`] takes its narrow loop: on ARMv6-M
/// (and ARMv8-M Baseline, `microraster_narrow_multiply`), and in the unit
/// tests, which thereby walk as those cores do (the integration tests
/// walk the other way).
const NARROW: bool = cfg!(any(microraster_narrow_multiply, test));

/// [`half`](super::half) for [`Packed`] edges: with `CLAMP`, the spans
/// clipped to columns `x0..x1` (a triangle across its tile's side
/// columns), without (a triangle within them; `x0` and `x1` unused), as the walk
/// takes most small triangles.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn half_packed<const CLAMP: bool>(
    out: &mut [Span],
    n: usize,
    row: i32,
    stop: i32,
    left: &mut Packed,
    right: &mut Packed,
    x0: i32,
    x1: i32,
) -> usize {
    let (mut lp, ls, ld) = (left.p, left.s, left.d);
    let (mut rp, rs, rd) = (right.p, right.s, right.d);
    let len = out.len();
    let mut rest = &mut out[n.min(len)..];
    if NARROW {
        // For a core with 8 low registers and no predication (ARMv6-M):
        // the same spans, from a loop with fewer values live.
        //
        // A span is written only when it is not empty: the select of the
        // slots left, which Thumb-2 predicates, takes branches here, and an
        // empty row (half the rows walked, at a triangle's tips) then skips
        // the stores and the slot's step (ARMv6-M `demo` 6,381,174 ->
        // 6,315,346 instructions, in the other loop).
        //
        // The slots are taken by a slice iterator, its pointer compared
        // with the end's, and the rows counted by `j` itself: with the
        // column read by two shifts (`COL_BITS`) the loop keeps both
        // words, the row and the pointer in registers, where the slice's
        // length was a count read and written in a stack slot at each
        // non-empty row (`demo` 5,965,273 -> 5,935,524 instructions).
        // (Rows counted up to zero from `row - stop` took 5,971,356 with
        // the iterator; the iterator with the mask, 5,955,160.)
        let mut slots = core::mem::take(&mut rest).iter_mut();
        let mut j = row;
        while j < stop {
            let (c0, c1) = (column(lp), column(rp));
            let (c0, c1) = if CLAMP {
                (c0.max(x0), c1.min(x1))
            } else {
                (c0, c1)
            };
            if c0 < c1 {
                let Some(o) = slots.next() else {
                    // No slot left.
                    break;
                };
                *o = Span { j, x0: c0, x1: c1 };
            }
            (lp, rp) = (next_row(lp, ls, ld), next_row(rp, rs, rd));
            j += 1;
        }
        (left.p, right.p) = (lp, rp);
        return len - slots.into_slice().len();
    }
    for j in row..stop {
        let (c0, c1) = (column(lp), column(rp));
        let s = if CLAMP {
            Span {
                j,
                x0: c0.max(x0),
                x1: c1.min(x1),
            }
        } else {
            Span { j, x0: c0, x1: c1 }
        };
        // Written whether empty or not, kept only if not: no branch.
        let r = core::mem::take(&mut rest);
        let Some(o) = r.first_mut() else {
            // No slot left: the caller's rows never exceed them.
            break;
        };
        *o = s;
        // A select of the two slices, which Thumb-2 predicates (two adds),
        // where `&mut r[k..]` of a 0 or 1 took six instructions.
        rest = if s.x0 < s.x1 { &mut r[1..] } else { r };
        (lp, rp) = (next_row(lp, ls, ld), next_row(rp, rs, rd));
    }
    (left.p, right.p) = (lp, rp);
    len - rest.len()
}
