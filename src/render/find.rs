//! The first phase of drawing a triangle in a tile: its spans found, one
//! per tile row at most, by the rasterizer the frame selects (the scanline
//! walk, the Hilbert-order block search, or the whole tile at once).

#[allow(unused_imports)] // the rustdoc links
use super::fill::{fill, fill_shaded};
use super::Features;
use crate::raster::scanline;
use crate::raster::{hilbert, PixelRect, Rasterizer, Span, SubPoint};
use crate::vertex::ScreenVertex;

/// The first phase of [`fill`] and [`fill_shaded`]: records the spans of
/// a triangle in the tile (one per row at most) and returns how many.
///
/// It takes the triangle's vertices, whose positions it reads itself:
/// the tile loop holds their addresses on the stack for the second phase
/// anyway, where building the positions there took stores of all six
/// coordinates per pair, loaded again by the walk.
pub(super) type FindFn = fn(&[&ScreenVertex; 3], &PixelRect, &mut [Span]) -> usize;

/// The screen positions of the vertices `sv`.
#[inline(always)]
fn points(sv: &[&ScreenVertex; 3]) -> [SubPoint; 3] {
    [sv[0].xy(), sv[1].xy(), sv[2].xy()]
}

/// The first phase for `raster`, of the rasterizers `P` links (the
/// scanline one when it links no other: the same spans).
pub(super) fn finder<P: Features>(raster: Rasterizer) -> FindFn {
    match raster {
        Rasterizer::Hilbert if P::HILBERT => find_hilbert,
        Rasterizer::Auto if P::HILBERT => find_auto,
        _ => find_spans,
    }
}

/// [`hilbert::find_spans`] as a [`FindFn`].
fn find_hilbert(sv: &[&ScreenVertex; 3], rect: &PixelRect, found: &mut [Span]) -> usize {
    hilbert::find_spans(&points(sv), *rect, found)
}

/// [`Rasterizer::Auto`]: the whole tile at once when the triangle covers
/// it, the scanline walk otherwise.
fn find_auto(sv: &[&ScreenVertex; 3], rect: &PixelRect, found: &mut [Span]) -> usize {
    match whole_tile(&points(sv), rect, found) {
        Some(n) => n,
        None => find_spans(sv, rect, found),
    }
}

/// The first phase of [`fill`] with the scanline rasterizer: records the
/// spans of triangle `v` in the tile `rect` in `found`, and returns how
/// many (the Hilbert rasterizer finds the same spans). Out of line, so that
/// the edge walk has the registers to itself.
#[inline(never)]
fn find_spans(sv: &[&ScreenVertex; 3], rect: &PixelRect, found: &mut [Span]) -> usize {
    // `found` holds a span for each row of `rect` (TH).
    scanline::find_spans(&points(sv), *rect, found)
}

/// For [`Rasterizer::Auto`]: when triangle `v`'s bounds hold the whole
/// tile `rect` and the Hilbert rasterizer's block test finds every pixel
/// centre of the tile covered, records one full span per row and returns
/// how many; otherwise `None` (the scanline walk then finds the spans).
#[inline(never)]
fn whole_tile(v: &[SubPoint; 3], rect: &PixelRect, found: &mut [Span]) -> Option<usize> {
    let b = PixelRect::covering(v);
    let holds = b.x0 <= rect.x0 && b.y0 <= rect.y0 && b.x1 >= rect.x1 && b.y1 >= rect.y1;
    if !holds || !hilbert::covers_rect(v, rect) {
        return None;
    }
    let rows = (rect.y1 - rect.y0) as usize;
    for (r, s) in found[..rows].iter_mut().enumerate() {
        *s = Span {
            j: rect.y0 + r as i32,
            x0: rect.x0,
            x1: rect.x1,
        };
    }
    Some(rows)
}
