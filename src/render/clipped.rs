//! Triangles that must be clipped: classified and drawn through their clipped pieces.

use super::binning::{Fate, Tally, LOOP_COUNTS_VISIBLE};
use super::state::{covering, grow, margin, meet, FrameState, SetupCache};
use crate::clip::{clip_triangle, MAX_CLIPPED_VERTICES};
use crate::raster::{signed_area2, PixelRect};
use crate::vertex::ScreenVertex;

impl FrameState<'_> {
    /// [`classify`](Self::classify) for a triangle that must be clipped:
    /// the bounds of all its visible pieces. The triangle's vertex indices
    /// `i0, i1, i2` come one by one: an array argument lives in memory,
    /// and the binning loop stored it there for every triangle, clipped or
    /// not (three stores a triangle on the Cortex-M3).
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn classify_clipped(
        &self,
        d: usize,
        i0: u32,
        i1: u32,
        i2: u32,
        any: u8,
        flat: [u8; 3],
        margin: i32,
        cache: &mut SetupCache,
        tally: &mut Tally,
    ) -> Option<PixelRect> {
        let mut r = PixelRect::new(i32::MAX, i32::MAX, i32::MIN, i32::MIN);
        let idx = [i0, i1, i2];
        let fate = self.clipped_pieces(d, idx, any, flat, cache, &mut |piece, _| {
            let sv = &piece.sv;
            let b = covering(&[sv[0].xy(), sv[1].xy(), sv[2].xy()]);
            r = PixelRect::new(
                r.x0.min(b.x0),
                r.y0.min(b.y0),
                r.x1.max(b.x1),
                r.y1.max(b.y1),
            );
        });
        tally.clipped += 1;
        // Culled triangles are counted by the binning pass, visible ones
        // by the binning loop on most cores (see `Tally`).
        if fate == Fate::Rejected || (fate == Fate::Visible && !LOOP_COUNTS_VISIBLE) {
            tally.fates[fate as usize] += 1;
        }
        (fate == Fate::Visible).then(|| meet(&grow(&r, margin), &self.frame))
    }

    /// Clips triangle `idx` of draw `d` (outcodes or-ed to `any`) and
    /// calls `f` with every piece of the fan that faces the right way and
    /// may touch the frame, and the flat colour `flat` of the triangle's
    /// provoking vertex.
    #[inline(never)]
    pub(super) fn clipped_pieces(
        &self,
        d: usize,
        idx: [u32; 3],
        any: u8,
        flat: [u8; 3],
        cache: &mut SetupCache,
        // Dynamic: the clipper is rare, and one copy of it serves every
        // monomorphized span loop.
        f: &mut dyn FnMut(&Piece, [u8; 3]),
    ) -> Fate {
        let draw = &self.draws[d];
        // Transform the three vertices again and clip.
        let Some(setup) = self.setup(d, cache) else {
            return Fate::Rejected;
        };
        let mut tri = [crate::vertex::ClipVertex::default(); 3];
        for (k, cv) in tri.iter_mut().enumerate() {
            match setup.clip_vertex(draw.mesh, idx[k] as usize) {
                Ok(v) => *cv = v,
                Err(_) => return Fate::Rejected,
            }
        }
        let poly = clip_triangle(&tri, any);
        if poly.len() < 3 {
            return Fate::Rejected;
        }
        let project = |k: usize| -> ScreenVertex {
            let [x, y, z, w] = poly[k].pos;
            let (p, z) = self.viewport.project_wide(x, y, z, w);
            let c = poly[k].color;
            // Inside the guard band up to clipping round-off: within
            // `(K + 1.07) * 2^15 < 2^18` sub-pixels, in the coordinate fields.
            ScreenVertex::new_clipped(
                p.x,
                p.y,
                z,
                [
                    c[0].clamp(0, 255) as u8,
                    c[1].clamp(0, 255) as u8,
                    c[2].clamp(0, 255) as u8,
                ],
            )
        };
        // Project once. Snapping to the sub-pixel grid can make the
        // polygon very slightly concave, so facing is decided once, from the
        // whole polygon's area, and fan pieces of the other sign (slivers
        // of round-off) are dropped rather than culled one by one: a
        // back-facing polygon never leaks a piece, and no pixel is shaded
        // twice.
        let mut proj: heapless::Vec<ScreenVertex, MAX_CLIPPED_VERTICES> = heapless::Vec::new();
        for k in 0..poly.len() {
            // Cannot fail: `poly` has the same capacity.
            let _ = proj.push(project(k));
        }
        let xy = |v: &ScreenVertex| v.xy();
        let mut total = 0i64;
        for k in 2..proj.len() {
            total += turn(&proj, [0, k - 1, k]);
        }
        if !self.keeps(total) {
            return Fate::Culled;
        }
        // A polygon made very slightly concave by snapping has reflex
        // vertices (turning against the polygon's orientation), and a fan
        // over it may overlap itself there, shading pixels twice; one that
        // snapping folded over itself (a spike whose sides cross, a sliver
        // bent back and forth) may be star-shaped from no vertex at all.
        // Such a polygon is fanned over its convex hull, which every fan
        // tiles and which differs from it by slivers narrower than the
        // snapping; a convex one (every golden) from its first corner.
        let n = proj.len();
        let reflex = |k: usize| {
            let turn = turn(&proj, [(k + n - 1) % n, k, (k + 1) % n]);
            turn != 0 && (turn > 0) != (total > 0)
        };
        let mut order = [0; MAX_CLIPPED_VERTICES];
        let corners = if (0..n).any(reflex) {
            convex_hull(&proj, total > 0, &mut order)
        } else {
            for (k, c) in order.iter_mut().enumerate().take(n) {
                *c = k;
            }
            n
        };
        // The margin of the draw's lines and points, which may reach pixels
        // beyond a piece's covered centres.
        let margin = margin(draw);
        let mut fate = Fate::Rejected;
        // Every index is in range (`order` holds `corners <= n` indices
        // below `n`), but looked up with `get`: indexing made a panic call
        // and location for each of the nine look-ups (flash, in rare code).
        let corner = |c: usize| Some((*proj.get(c)?, poly.get(c)?));
        let fan = order.get(..corners).unwrap_or(&[]);
        let Some((&first, rest)) = fan.split_first() else {
            return fate;
        };
        let Some(a) = corner(first) else {
            return fate;
        };
        for pair in rest.windows(2) {
            let (Some(b), Some(c)) = (corner(pair[0]), corner(pair[1])) else {
                continue;
            };
            let piece = Piece {
                sv: [a.0, b.0, c.0],
                w: [a.1.pos[3], b.1.pos[3], c.1.pos[3]],
                bary: [a.1.bary, b.1.bary, c.1.bary],
            };
            let v = piece.sv.map(|v| xy(&v));
            let area2 = signed_area2(&v);
            if area2 == 0 || (area2 > 0) != (total > 0) {
                continue;
            }
            // Flat shading keeps the original provoking vertex's colour.
            if !meet(&grow(&covering(&v), margin), &self.frame).is_empty() {
                f(&piece, flat);
                fate = Fate::Visible;
            }
        }
        fate
    }
}

/// A piece of a clipped triangle: its projected corners, their clip-space
/// `w` and their places in the original triangle.
pub(super) struct Piece {
    pub(super) sv: [ScreenVertex; 3],
    pub(super) w: [i32; 3],
    pub(super) bary: [[i32; 2]; 3],
}

/// The convex hull of the snapped corners `proj` into `out`, as indices
/// (how many is returned) turning the polygon's way (`positive`: the sign of [`signed_area2`]),
/// without repeated or collinear points: Andrew's monotone chain (A. M.
/// Andrew, *Another efficient algorithm for convex hulls in two
/// dimensions*, Information Processing Letters 9(5), 1979), the lower
/// chain left to right, then the upper one back.
fn convex_hull(
    proj: &[ScreenVertex],
    positive: bool,
    out: &mut [usize; MAX_CLIPPED_VERTICES],
) -> usize {
    let p = |k: usize| proj[k].xy();
    let key = |k: usize| (p(k).x, p(k).y);
    // Sorted by x, then y, by insertion (with swaps: core's sort, or a
    // vector's insert and its `memmove`, would link kilobytes of code for
    // at most 16 points).
    let mut by_x = [0; MAX_CLIPPED_VERTICES];
    let n = proj.len().min(MAX_CLIPPED_VERTICES);
    for c in 0..n {
        by_x[c] = c;
        let mut j = c;
        while j > 0 && key(by_x[j - 1]) > key(by_x[j]) {
            by_x.swap(j - 1, j);
            j -= 1;
        }
    }
    // The chains' points, popped while they do not turn left: the lower
    // chain (by_x in order), then the upper one (back, from the one before
    // the last), which keeps the lower whole. Never more than twice the
    // corners.
    let mut hull = [0; 2 * MAX_CLIPPED_VERTICES];
    let (mut len, mut keep) = (0, 2);
    for step in 0..(2 * n).saturating_sub(1) {
        let c = if step < n {
            by_x[step]
        } else {
            by_x[2 * n - 2 - step]
        };
        if step == n {
            keep = len + 1;
        }
        while len >= keep && turn(proj, [hull[len - 2], hull[len - 1], c]) <= 0 {
            len -= 1;
        }
        hull[len] = c;
        len += 1;
    }
    // The last point closes the chain: it is the first. (At most `n`
    // corners are left.)
    let hull = &mut hull[..len.saturating_sub(1).min(MAX_CLIPPED_VERTICES)];
    if !positive {
        hull.reverse();
    }
    out[..hull.len()].copy_from_slice(hull);
    hull.len()
}

/// [`signed_area2`] of the snapped corners `k` of `proj`: out of line, as
/// the clipper asks it in five places (rare code: flash, not time).
#[inline(never)]
fn turn(proj: &[ScreenVertex], k: [usize; 3]) -> i64 {
    signed_area2(&k.map(|c| proj[c].xy()))
}
