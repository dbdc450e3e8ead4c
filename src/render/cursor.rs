//! Walking the draws along global triangle indices, and the triangle list of one tile.

use super::bin::BinIter;
use super::binning::Tally;
use super::state::{margin, meet, DrawOrder, FrameState, SetupCache};
use super::Features;
use crate::cull::Frustum;
use crate::mesh::Indices;
use crate::raster::PixelRect;
use crate::scene::{Blend, Shading};
use crate::vertex::ScreenVertex;

/// Walks the draws alongside increasing global triangle indices, with the
/// slices of the current draw at hand.
pub(super) struct DrawCursor<'f> {
    pub(super) draws: &'f [crate::scene::Draw<'f>],
    pub(super) vertices: &'f [ScreenVertex],
    /// The visiting order and vertex bases, when draws are sorted.
    pub(super) order: Option<(&'f [u16], &'f [u32])>,
    /// The current draw's place in the visiting order, and its index.
    pub(super) pos: usize,
    pub(super) draw: usize,
    /// Global index of the draw's first triangle, and one past its last.
    pub(super) first: usize,
    pub(super) end: usize,
    /// Index of the draw's first vertex in the vertex buffer.
    pub(super) vbase: usize,
    pub(super) triangles: Indices<'f>,
    /// The draw's triangles when its indices are `u16` (the common
    /// case), else empty: see [`indices`](Self::indices).
    pub(super) tris16: &'f [[u16; 3]],
    /// The draw's triangles when it takes the tile loop's common path
    /// (`u16` indices and [`plain`](Self::plain)), else empty: a global
    /// triangle index `t` of the draw is `fast[t - first]`, and any other
    /// (a later draw's, or a rare path's) misses it, which the tile loop
    /// then sends down its general path, with one bounds check a pair.
    pub(super) fast: &'f [[u16; 3]],
    pub(super) verts: &'f [ScreenVertex],
    pub(super) shading: Shading,
    /// `shading == Shading::Gouraud`, decided once per draw: the tile
    /// loop indexes its shading functions by it for every triangle.
    pub(super) gouraud: bool,
    pub(super) blend: Blend,
    /// The draw has edges or points to draw.
    pub(super) lines: bool,
    /// The draw is filled only, opaque, without a fragment shader: the
    /// tile loop's common path, tested once rather than once per rare path.
    pub(super) plain: bool,
}

impl<'f> DrawCursor<'f> {
    pub(super) fn new(frame: &'f FrameState<'f>) -> Self {
        let draws = frame.draws;
        let mut c = Self {
            draws,
            vertices: frame.vertices,
            order: frame.order.as_ref().map(DrawOrder::slices),
            pos: 0,
            draw: 0,
            first: 0,
            end: 0,
            vbase: 0,
            triangles: Indices::U16(&[]),
            tris16: &[],
            fast: &[],
            verts: &[],
            shading: Shading::Flat,
            gouraud: false,
            blend: Blend::Opaque,
            lines: false,
            plain: true,
        };
        if !draws.is_empty() {
            c.enter(0);
        }
        c
    }

    /// Enters the draw visited `k`-th (with `vbase` already its first
    /// vertex in submission order).
    pub(super) fn enter(&mut self, k: usize) {
        let d = match self.order {
            Some((order, bases)) => {
                let d = order[k] as usize;
                self.vbase = bases[d] as usize;
                d
            }
            None => k,
        };
        let draw = &self.draws[d];
        self.pos = k;
        self.draw = d;
        self.triangles = draw.mesh.triangles();
        self.tris16 = match self.triangles {
            Indices::U16(tris) => tris,
            Indices::U32(_) => &[],
        };
        self.verts = &self.vertices[self.vbase..self.vbase + draw.mesh.vertex_count()];
        self.end = self.first + self.triangles.len();
        self.shading = draw.shading;
        self.gouraud = draw.shading == Shading::Gouraud;
        self.blend = draw.blend;
        self.lines = margin(draw) != 0;
        self.plain = !self.lines && self.blend == Blend::Opaque && self.shading != Shading::Shader;
        self.fast = if self.plain { self.tris16 } else { &[] };
    }

    /// The vertex indices of global triangle `t` of the current draw:
    /// for `u16` indices one bounds check, which also tells them from
    /// `u32` ones (rather than a test of the indices' kind and then a
    /// bounds check).
    #[inline(always)]
    pub(super) fn indices(&self, t: usize) -> [u32; 3] {
        match self.tris16.get(t - self.first) {
            Some(&[a, b, c]) => [a as u32, b as u32, c as u32],
            None => self.triangles.get(t - self.first),
        }
    }

    /// Moves to the draw holding global triangle `t`, which must not lie
    /// before the current draw.
    #[inline(always)]
    pub(super) fn seek(&mut self, t: usize) {
        while t >= self.end {
            self.advance();
        }
    }

    /// Moves to the draw holding global triangle `t`, before or after the
    /// current draw.
    pub(super) fn go_to(&mut self, t: usize) {
        if t < self.first {
            self.first = 0;
            self.vbase = 0;
            self.enter(0);
        }
        self.seek(t);
    }

    #[inline(never)]
    pub(super) fn advance(&mut self) {
        self.first = self.end;
        self.vbase += self.verts.len();
        self.enter(self.pos + 1);
    }
}

/// The triangles of one tile: its bin, or, for a tile whose bin overflowed
/// the pool, every visible triangle whose bounds touch it (then the bin
/// is empty). Not an enum: the common bin's next entry is then taken
/// without a test of the variant, and the scan is asked once the bin is
/// exhausted.
// One per tile, moved by value into the tile loop: the rare scan keeps
// its large state behind a reference.
pub(super) struct TileList<'a, 'f, P> {
    pub(super) bin: BinIter<'a>,
    pub(super) scan: Option<Scan<'a, 'f, P>>,
}

/// A rescanned tile's walk over every triangle of the frame.
pub(super) struct Scan<'a, 'f, P> {
    pub(super) frame: &'f FrameState<'f>,
    pub(super) rect: PixelRect,
    pub(super) next: usize,
    pub(super) state: &'a mut ScanState<'f, P>,
}

/// What a rescanned tile's walk over every triangle keeps.
pub(super) struct ScanState<'f, P> {
    pub(super) cur: DrawCursor<'f>,
    pub(super) cache: SetupCache,
    /// The current draw's frustum (when culling), its next cluster, and
    /// the global index of the current cluster's end.
    pub(super) frustum: Option<Frustum>,
    pub(super) cluster: usize,
    pub(super) cluster_end: usize,
    /// The renderer's features, which say whether to cull.
    features: core::marker::PhantomData<P>,
}

impl<'f, P> ScanState<'f, P> {
    /// The state of a scan from the frame's first triangle.
    pub(super) fn new(frame: &'f FrameState<'f>) -> Self {
        Self {
            cur: DrawCursor::new(frame),
            cache: SetupCache::empty(),
            frustum: None,
            cluster: 0,
            cluster_end: 0,
            features: core::marker::PhantomData,
        }
    }
}

impl<P: Features> Iterator for TileList<'_, '_, P> {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if let Some(t) = self.bin.next() {
            return Some(t);
        }
        self.scan.as_mut()?.next_touching()
    }
}

impl<P: Features> Scan<'_, '_, P> {
    /// A rescanned tile's next triangle: out of line, so that the tile
    /// loop, into which [`TileList::next`] is inlined, does not carry the
    /// scan's code and state (a tile rescans only when its bin overflowed
    /// the pool). Inlined in builds optimised for size (the build script's
    /// `microraster_size`), where the tile loop calls it from one place
    /// (the OLED firmware 44,096 -> 43,316 bytes with the loop's form).
    #[cfg_attr(microraster_size, inline(always))]
    #[cfg_attr(not(microraster_size), inline(never))]
    fn next_touching(&mut self) -> Option<usize> {
        let Scan {
            frame,
            rect,
            next,
            state,
        } = self;
        loop {
            let ScanState {
                cur,
                cache,
                frustum,
                cluster,
                cluster_end,
                ..
            } = &mut **state;
            let t = *next;
            if t >= cur.end {
                if cur.pos + 1 >= cur.draws.len() {
                    return None;
                }
                cur.advance();
                continue;
            }
            // The same tests as binning's, in the same order.
            let mesh = frame.draws[cur.draw].mesh;
            if t == cur.first {
                let outside;
                (outside, *frustum) = frame.view_test::<P>(cur.draw);
                if outside {
                    *next = cur.end;
                    continue;
                }
                (*cluster, *cluster_end) = (0, t);
            }
            if let (Some(f), Some(clusters)) = (frustum.as_ref(), mesh.clusters()) {
                // Enter the cluster holding t (past any empty ones).
                let mut skip = false;
                while t >= *cluster_end && *cluster < clusters.len() {
                    let c = &clusters[*cluster];
                    *cluster += 1;
                    *cluster_end += c.triangle_count() as usize;
                    skip = f.excludes_box(&c.bounds());
                }
                if skip {
                    *next = *cluster_end;
                    continue;
                }
            }
            *next += 1;
            let idx = cur.indices(t);
            if scan_touches(frame, cur.draw, cur.verts, idx, cache, rect) {
                return Some(t);
            }
        }
    }
}

/// Whether triangle `idx` of draw `d` is visible and touches `rect`: a
/// rescanned tile's classification, out of line so that the tile loop,
/// into which the scan is inlined, does not carry it: inlined, it cost
/// the tile loop registers, and the Cortex-M3's `demo` frame (which
/// rescans nothing) 19,000 instructions of rasterization.
#[inline(never)]
fn scan_touches(
    frame: &FrameState<'_>,
    d: usize,
    verts: &[ScreenVertex],
    idx: [u32; 3],
    cache: &mut SetupCache,
    rect: &PixelRect,
) -> bool {
    let mut tally = Tally::default();
    let m = margin(&frame.draws[d]);
    let vis = frame.classify(
        d,
        verts,
        idx,
        m,
        (frame.cull, frame.small()),
        cache,
        &mut tally,
    );
    vis.is_some_and(|r| !meet(&r, rect).is_empty())
}
