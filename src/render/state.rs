//! The read-only state of a frame being rendered, and triangle classification.

use super::binning::{Fate, Tally, LOOP_COUNTS_VISIBLE};
use super::vertex_stage::{with_lighting, SetupFn};
use super::Features;
use crate::cull::Frustum;
use crate::light::Lighting;
use crate::raster::{first_centre_at_or_after, signed_area2_banded, PixelRect, SubPoint};

use crate::scene::{Blend, CullMode, Draw, Light, Shading};
use crate::vertex::{DrawSetup, ScreenVertex, Viewport, MUST_CLIP, REJECT_MASK};

/// The state of a frame that every tile reads and none changes: the
/// draws, the vertex buffer the vertex stage filled, the matrices and the
/// settings the tile loop needs.
pub(super) struct FrameState<'a> {
    pub(super) draws: &'a [Draw<'a>],
    /// The scene's one light and its lighting ([`with_lighting`] makes
    /// the frame's lighting of them).
    pub(super) light: Option<Light>,
    pub(super) lighting: Option<&'a Lighting<'a>>,
    /// How a draw is set up (with or without the general lighting).
    pub(super) make_setup: SetupFn,
    /// The camera's position, world space.
    pub(super) eye: crate::math::Vec3,
    /// Cull draws outside the frustum ([`Config::frustum_cull`](super::Config::frustum_cull)).
    pub(super) cull_draws: bool,
    /// The draws the vertex stage found wholly outside the frustum (bit
    /// `d` for draw `d`, of the first 64).
    pub(super) outside: u64,
    /// The order draws are visited in, when sorted
    /// ([`Config::sort_draws`](super::Config::sort_draws)); `None` for submission order.
    pub(super) order: Option<DrawOrder>,
    pub(super) vertices: &'a [ScreenVertex],
    pub(super) view_proj: crate::math::Mat4,
    pub(super) viewport: Viewport,
    pub(super) cull: CullMode,
    /// The frame's pixels: from the origin to the viewport's size.
    pub(super) frame: PixelRect,
}

/// The order draws are visited in when sorted ([`Config::sort_draws`](super::Config::sort_draws)),
/// and the first vertex of each draw (by draw index) in the vertex
/// buffer: 6 bytes per draw.
pub(super) struct DrawOrder {
    order: heapless::Vec<u16, MAX_SORTED_DRAWS>,
    bases: heapless::Vec<u32, MAX_SORTED_DRAWS>,
}

impl DrawOrder {
    /// Opaque draws front to back, then transparent ones back to front,
    /// by the view depth of their bounding box's centre; ties in
    /// submission order. `None` when there are more than
    /// [`MAX_SORTED_DRAWS`] draws.
    pub(super) fn new(view: &crate::math::Mat4, draws: &[Draw<'_>]) -> Option<Self> {
        if draws.len() > MAX_SORTED_DRAWS {
            return None;
        }
        let mut s = Self {
            order: heapless::Vec::new(),
            bases: heapless::Vec::new(),
        };
        let mut keys: heapless::Vec<(bool, f32), MAX_SORTED_DRAWS> = heapless::Vec::new();
        let mut base = 0u32;
        for (d, draw) in draws.iter().enumerate() {
            let transparent = draw.blend != Blend::Opaque;
            let depth = view_depth(view, draw);
            // Transparent draws sort far first: negate their depth.
            let key = if transparent { -depth } else { depth };
            // Capacity: at most MAX_SORTED_DRAWS draws here.
            let _ = keys.push((transparent, key));
            let _ = s.order.push(d as u16);
            let _ = s.bases.push(base);
            base += draw.mesh.vertex_count() as u32;
        }
        // Stable insertion sort: opaque before transparent, then by key
        // (NaN keys, from non-finite set-ups, compare as equal).
        let before = |a: (bool, f32), b: (bool, f32)| (!a.0 && b.0) || (a.0 == b.0 && a.1 < b.1);
        let order = &mut s.order;
        for k in 1..order.len() {
            let e = order[k];
            let mut i = k;
            while i > 0 && before(keys[e as usize], keys[order[i - 1] as usize]) {
                order[i] = order[i - 1];
                i -= 1;
            }
            order[i] = e;
        }
        Some(s)
    }

    /// The visiting order (draw indices) and each draw's first vertex.
    pub(super) fn slices(&self) -> (&[u16], &[u32]) {
        (&self.order, &self.bases)
    }
}

/// The fixed-point set-up of the last draw a clipped triangle needed.
pub(super) struct SetupCache {
    /// The draw whose set-up `setup` holds, when it holds one.
    draw: usize,
    setup: Option<DrawSetup>,
}

impl SetupCache {
    /// Holding no draw's set-up. A function, not a constant: a constant
    /// is copied from flash in full (about 650 bytes of it), where this
    /// writes the `None`.
    pub(super) fn empty() -> Self {
        Self {
            draw: 0,
            setup: None,
        }
    }
}

/// The vertices' least and greatest `x` and `y`, in that order.
#[inline(always)]
fn extent(v: &[SubPoint; 3]) -> [i32; 4] {
    [
        v[0].x.min(v[1].x).min(v[2].x),
        v[0].x.max(v[1].x).max(v[2].x),
        v[0].y.min(v[1].y).min(v[2].y),
        v[0].y.max(v[1].y).max(v[2].y),
    ]
}

/// The pixels whose centres may be covered by a triangle with these
/// vertices: [`PixelRect::covering`], inlined into the binning loop.
#[inline(always)]
pub(super) fn covering(v: &[SubPoint; 3]) -> PixelRect {
    let [xmin, xmax, ymin, ymax] = extent(v);
    PixelRect::new(
        first_centre_at_or_after(xmin),
        first_centre_at_or_after(ymin),
        first_centre_at_or_after(xmax) + 1,
        first_centre_at_or_after(ymax) + 1,
    )
}

/// The pixels a triangle with these vertices may draw, `margin` pixels
/// beyond the centres it may cover ([`margin`]). A filled triangle
/// (`margin` 0) covers only the centres strictly before its rightmost
/// and lowest vertices: a centre on its right or bottom extreme lies on a
/// right or bottom edge (or on a vertex that is on one), which the fill
/// rule leaves out ([`crate::raster`]). So its columns end at the first
/// centre at or after the rightmost vertex, where [`covering`] (for any
/// triangle) ends one column later, and a triangle between two centre
/// columns or rows is found empty here, before it takes a bin entry in a
/// tile it cannot draw into. Lines and points keep `covering`'s bounds,
/// grown by their margin.
#[inline(always)]
pub(super) fn reach(v: &[SubPoint; 3], margin: i32) -> PixelRect {
    let [xmin, xmax, ymin, ymax] = extent(v);
    let end = margin + (margin != 0) as i32;
    PixelRect::new(
        first_centre_at_or_after(xmin) - margin,
        first_centre_at_or_after(ymin) - margin,
        first_centre_at_or_after(xmax) + end,
        first_centre_at_or_after(ymax) + end,
    )
}

/// `r` grown by `m` pixels on every side.
#[inline(always)]
pub(super) fn grow(r: &PixelRect, m: i32) -> PixelRect {
    PixelRect::new(r.x0 - m, r.y0 - m, r.x1 + m, r.y1 + m)
}

/// Most draws a frame sorts ([`Config::sort_draws`](super::Config::sort_draws)): the visiting order
/// and the vertex bases live in the [`Frame`](super::Frame), 6 bytes per draw (and 8
/// more on the stack while sorting).
pub const MAX_SORTED_DRAWS: usize = 64;

/// The distance in front of the eye of the centre of `draw`'s bounding
/// box, along the view direction (`-z` in eye space).
pub(super) fn view_depth(view: &crate::math::Mat4, draw: &Draw<'_>) -> f32 {
    let [lo, hi] = draw.mesh.bounds().map(|c| c.map(|v| v.to_num::<f32>()));
    let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let m = *view * draw.transform;
    let z = m.m[0][2] * c[0] + m.m[1][2] * c[1] + m.m[2][2] * c[2] + m.m[3][2];
    -z
}

/// How far beyond the pixel centres it covers a triangle of `draw` may
/// draw: the lines of its edges reach the pixels holding its vertices
/// (one pixel), its points half their size.
pub(super) fn margin(draw: &Draw<'_>) -> i32 {
    match (draw.shading, draw.edges) {
        (Shading::Points(size), _) => size as i32 / 2 + 1,
        (Shading::Wireframe, _) | (_, Some(_)) => 1,
        _ => 0,
    }
}

/// [`PixelRect::intersect`], inlined.
#[inline(always)]
pub(super) fn meet(a: &PixelRect, b: &PixelRect) -> PixelRect {
    PixelRect::new(
        a.x0.max(b.x0),
        a.y0.max(b.y0),
        a.x1.min(b.x1),
        a.y1.min(b.y1),
    )
}

/// [`FrameState::keeps`] for cull mode `cull`: the binning loop reads the
/// mode once per run of triangles rather than from the frame state for
/// each.
#[inline(always)]
pub(super) fn keeps(cull: CullMode, area2: i64) -> bool {
    match cull {
        CullMode::None => area2 != 0,
        // Negative area is counter-clockwise in NDC: the front face.
        CullMode::Back => area2 < 0,
        CullMode::Front => area2 > 0,
    }
}

/// [`keeps`] of the signed area of a triangle within the guard band
/// ([`signed_area2_banded`]). On ARMv6-M, whose 32 x 32 -> 64-bit products
/// are built from four 16-bit ones, a triangle whose edge vectors from
/// vertex 0 lie within `-(2^15 - 1)..=2^15` (nearly every triangle the
/// binning loop sees) takes its area from two 32-bit products: each is at
/// most `2^30` in magnitude, and their difference within `±(2^31 -
/// 2^15)`, exact in `i32`.
///
/// With `inside` (all three outcodes 0, in a frame of at most 2,048
/// pixels a side: [`FrameState::small`]) every coordinate is within
/// `0..=2^15` sub-pixels, so each product is at most `2^30` in magnitude
/// and so is twice the area (at most the bounding box's, `2^15 2^15`):
/// on ARMv6-M the `i32` area is then taken without the range test
/// (binning 731,122 -> 705,367 instructions on the `demo` frame; on the
/// Cortex-M3, whose `i64` area is two `SMULL`, the same test cost binning
/// 10,800 more).
#[inline(always)]
pub(super) fn keeps_banded(cull: CullMode, v: &[SubPoint; 3], inside: bool) -> bool {
    if crate::math::SPLIT && inside {
        return keeps(cull, inside_area2(v) as i64);
    }
    if crate::math::SPLIT {
        if let Some(area2) = narrow_area2(v) {
            return keeps(cull, area2 as i64);
        }
    }
    if cfg!(target_pointer_width = "32") && !crate::math::SPLIT {
        // Twice the area is `p - q`: its sign and zero by comparing the
        // two products, without their difference (the Cortex-M3 had
        // spilled the difference's low word for the `None` mode's test:
        // binning 487,791 -> 484,657 instructions on the `demo` frame;
        // ARMv6-M's rare wide area measured 28,000 slower this way).
        return keeps_products(cull, v);
    }
    keeps(cull, signed_area2_banded(v))
}

/// [`keeps`] of [`signed_area2_banded`], from its two products compared.
#[inline(always)]
fn keeps_products(cull: CullMode, v: &[SubPoint; 3]) -> bool {
    let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
    let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
    let (p, q) = (crate::math::mul_wide(x1, y2), crate::math::mul_wide(x2, y1));
    keeps_by(cull, p, q)
}

/// Whether `cull` keeps a triangle whose twice-area is `p - q` (the two
/// products compared, not subtracted: no overflow).
#[inline(always)]
pub(super) fn keeps_by(cull: CullMode, p: i64, q: i64) -> bool {
    match cull {
        CullMode::None => p != q,
        CullMode::Back => p < q,
        CullMode::Front => p > q,
    }
}

/// [`signed_area2_banded`] in `i32` products, for vertices within
/// `0..=2^15` sub-pixels (see [`keeps_banded`]).
#[inline(always)]
fn inside_area2(v: &[SubPoint; 3]) -> i32 {
    let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
    let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
    x1 * y2 - x2 * y1
}

/// [`signed_area2_banded`] in `i32` products, when the edge vectors from
/// vertex 0 lie within `-(2^15 - 1)..=2^15` (see [`keeps_banded`]).
#[inline(always)]
fn narrow_area2(v: &[SubPoint; 3]) -> Option<i32> {
    let (x1, y1) = (v[1].x - v[0].x, v[1].y - v[0].y);
    let (x2, y2) = (v[2].x - v[0].x, v[2].y - v[0].y);
    // Each `d + 2^15 - 1` in `0..2^16` (the coordinates are within ±2^18,
    // so neither the differences nor the sums wrap).
    let lift = |d: i32| (d + 0x7fff) as u32;
    ((lift(x1) | lift(y1) | lift(x2) | lift(y2)) >> 16 == 0).then(|| x1 * y2 - x2 * y1)
}

impl FrameState<'_> {
    /// The draw visited `k`-th.
    #[inline(always)]
    pub(super) fn visit(&self, k: usize) -> usize {
        match &self.order {
            Some(o) => o.order[k] as usize,
            None => k,
        }
    }

    /// Whether draw `d` lies wholly outside the view frustum, and, when
    /// culling is on and the draw has clusters, its frustum in the draw's
    /// model space to test them (the same answers every time it is asked:
    /// the tests are deterministic, so binning, rescans and the vertex
    /// stage agree). For the first 64 draws without clusters the answer
    /// is the vertex stage's ([`FrameState::outside`]): a frustum costs a
    /// `Mat4` product, 16 `f32` divisions and six planes' set-up.
    pub(super) fn view_test<P: Features>(&self, d: usize) -> (bool, Option<Frustum>) {
        // Known at compile time without culling: no frustum code linked.
        if !(P::CULL && self.cull_draws) {
            return (false, None);
        }
        let draw = &self.draws[d];
        if d < 64 && draw.mesh.clusters().is_none() {
            return (self.outside >> d & 1 != 0, None);
        }
        let frustum = Frustum::new(&self.view_proj, draw);
        let outside = frustum.as_ref().is_some_and(|f| f.excludes_mesh(draw.mesh));
        (outside, frustum)
    }

    /// The fixed-point set-up of draw `d`, from `cache` or computed again
    /// (and cached). `None` cannot happen: the vertex stage accepted the
    /// draw, and the set-up is deterministic. Borrowed from the cache, not
    /// copied: the set-up is a few hundred bytes, and the shader path asks
    /// for it once per triangle and tile (a copy was about 90 x86
    /// instructions of `memcpy` each time).
    #[inline(always)]
    pub(super) fn setup<'c>(&self, d: usize, cache: &'c mut SetupCache) -> Option<&'c DrawSetup> {
        if cache.draw != d || cache.setup.is_none() {
            self.setup_again(d, cache)?;
        }
        cache.setup.as_ref()
    }

    /// [`setup`](Self::setup) when the cache holds another draw's: built
    /// in the cache's slot.
    #[inline(never)]
    fn setup_again(&self, d: usize, cache: &mut SetupCache) -> Option<()> {
        cache.draw = d;
        let draw = &self.draws[d];
        let mvp = (self.view_proj * draw.transform).normalized();
        with_lighting(self.light.as_ref(), self.lighting, |lighting| {
            (self.make_setup)(&mut cache.setup, draw, mvp.as_ref(), lighting, self.eye)
        })
        .ok()
    }

    /// Whether the frame is at most 2,048 pixels a side, so that a
    /// triangle inside the view volume is within `0..=2^15` sub-pixels
    /// (for [`classify`](Self::classify)'s `small`).
    #[inline(always)]
    pub(super) fn small(&self) -> bool {
        self.frame.x1 <= 2048 && self.frame.y1 <= 2048
    }

    /// Whether a triangle or polygon of twice signed screen area `area2`
    /// survives culling: never with zero area, otherwise by the cull mode.
    #[inline(always)]
    pub(super) fn keeps(&self, area2: i64) -> bool {
        keeps(self.cull, area2)
    }

    /// Classifies triangle `idx` of draw `d`, whose vertices are `verts`,
    /// under cull mode `cull` (the frame's, passed in so that a loop reads
    /// it once):
    /// counts its fate in `tally` (but for [`Fate::Culled`], which the
    /// binning pass counts as what is left, and [`Fate::Visible`], which
    /// the binning loop counts where [`LOOP_COUNTS_VISIBLE`]) and, if it
    /// is visible, returns the pixels it may cover. The common case (no clipping) reads only the three
    /// screen vertices; a rejected or culled triangle costs a few dozen
    /// instructions.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn classify(
        &self,
        d: usize,
        verts: &[ScreenVertex],
        idx: [u32; 3],
        margin: i32,
        (cull, small): (CullMode, bool),
        cache: &mut SetupCache,
        tally: &mut Tally,
    ) -> Option<PixelRect> {
        let sv = [
            &verts[idx[0] as usize],
            &verts[idx[1] as usize],
            &verts[idx[2] as usize],
        ];
        let and = sv[0].outcode() & sv[1].outcode() & sv[2].outcode();
        let any = sv[0].outcode() | sv[1].outcode() | sv[2].outcode();
        if and & REJECT_MASK == 0 {
            if any & MUST_CLIP != 0 {
                let [i0, i1, i2] = idx;
                // Rebuilt from its fields: the rectangle the call returns
                // through memory is then not the one the common path
                // returns, which stays in registers (the Cortex-M3 had
                // stored every visible triangle's rectangle for the join:
                // binning -3.7 K instructions on the `demo` frame). Not on
                // ARMv6-M, whose loop's registers it moved (with the
                // loop's visible count, +12.5 K there).
                if crate::math::SPLIT {
                    return self.classify_clipped(
                        d,
                        i0,
                        i1,
                        i2,
                        any,
                        sv[0].color(),
                        margin,
                        cache,
                        tally,
                    );
                }
                let r =
                    self.classify_clipped(d, i0, i1, i2, any, sv[0].color(), margin, cache, tally)?;
                return Some(PixelRect::new(r.x0, r.y0, r.x1, r.y1));
            }
            let v = [sv[0].xy(), sv[1].xy(), sv[2].xy()];
            if !keeps_banded(cull, &v, small && any == 0) {
                // Culled: counted by the binning pass as the rest (see
                // `Tally`), on ARMv6-M too, where a count here (and for an
                // empty `reach` below), once 27,000 instructions faster on
                // the `demo` frame for its registers, now measured slower:
                // binning 743,788 -> 731,122 without both, `rock` 657,363
                // -> 644,357.
                return None;
            }
            let reach = reach(&v, margin);
            // The frame's corner is the origin: with that known, the clamp
            // of the rectangle's corner to it is one instruction a side
            // on the Cortex-M3 rather than a load and three.
            debug_assert!(self.frame.x0 == 0 && self.frame.y0 == 0);
            let frame = PixelRect::new(0, 0, self.frame.x1, self.frame.y1);
            let rect = meet(&reach, &frame);
            if !rect.is_empty() {
                // Counted by the binning loop on most cores (see `Tally`).
                if !LOOP_COUNTS_VISIBLE {
                    tally.fates[Fate::Visible as usize] += 1;
                }
                return Some(rect);
            }
            if reach.is_empty() {
                // No pixel centre within the bounds: nothing to draw, as
                // for a zero-area triangle (a filled one: `reach` keeps a
                // line's pixels).
                return None;
            }
        }
        tally.fates[Fate::Rejected as usize] += 1;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::{inside_area2, keeps, keeps_products, narrow_area2, reach};

    /// The cull test from the two products compared is the one of the
    /// signed area, in every mode: random triangles within the guard band
    /// of every size, zero areas among them.
    #[test]
    fn the_compared_products_cull_as_the_area() {
        use crate::raster::{signed_area2, SubPoint};
        use crate::scene::CullMode;
        let mut next = crate::testing::rng();
        for i in 0..300_000 {
            let span = 1i64 << next(19);
            let mut c = || (next(2 * span as u64 + 1) as i64 - span) as i32;
            let (a, b) = (SubPoint::new(c(), c()), SubPoint::new(c(), c()));
            // Every fourth triangle degenerate: its third vertex on a line.
            let v = match i % 4 {
                0 => [a, b, SubPoint::new(2 * b.x - a.x, 2 * b.y - a.y)],
                _ => [a, b, SubPoint::new(c(), c())],
            };
            for cull in [CullMode::None, CullMode::Back, CullMode::Front] {
                assert_eq!(
                    keeps_products(cull, &v),
                    keeps(cull, signed_area2(&v)),
                    "{v:?} {cull:?}"
                );
            }
        }
    }

    /// The `i32` area of vertices within `0..=2^15` sub-pixels (inside
    /// the view volume of a frame of at most 2,048 pixels a side) is the
    /// 64-bit one: random triangles of every size, and the corners of the
    /// range (where each product and the area reach `2^30`).
    #[test]
    fn inside_area_is_the_signed_area() {
        use crate::raster::{signed_area2, SubPoint};
        let mut next = crate::testing::rng();
        let top = 1i32 << 15;
        let ends = [0, 1, top / 2, top - 1, top];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &d in &ends {
                        for v in [
                            [
                                SubPoint::new(a, b),
                                SubPoint::new(c, d),
                                SubPoint::new(0, top),
                            ],
                            [
                                SubPoint::new(a, 0),
                                SubPoint::new(top, b),
                                SubPoint::new(c, d),
                            ],
                            [
                                SubPoint::new(0, 0),
                                SubPoint::new(a, b),
                                SubPoint::new(c, d),
                            ],
                        ] {
                            assert_eq!(inside_area2(&v) as i64, signed_area2(&v), "{v:?}");
                        }
                    }
                }
            }
        }
        for _ in 0..500_000 {
            let span = 1u64 << next(16);
            let base = next((1 << 15) - span + 1) as i32;
            let mut c = || base + next(span + 1) as i32;
            let v = [
                SubPoint::new(c(), c()),
                SubPoint::new(c(), c()),
                SubPoint::new(c(), c()),
            ];
            assert_eq!(inside_area2(&v) as i64, signed_area2(&v), "{v:?}");
        }
    }

    /// The `i32` area is the 64-bit one wherever it is taken, and is taken
    /// for edge vectors up to the ends of its range: random triangles
    /// within the guard band, of every size, and edge vectors at and just
    /// beyond `-(2^15 - 1)` and `2^15`.
    #[test]
    fn narrow_area_is_the_signed_area() {
        use crate::raster::{signed_area2, SubPoint};
        let mut next = crate::testing::rng();
        let mut taken = 0;
        for _ in 0..500_000 {
            let span = 1i64 << next(20);
            let mut c = || (next(2 * span as u64 + 1) as i64 - span) as i32;
            let v = [
                SubPoint::new(c(), c()),
                SubPoint::new(c(), c()),
                SubPoint::new(c(), c()),
            ];
            if let Some(a) = narrow_area2(&v) {
                assert_eq!(a as i64, signed_area2(&v), "{v:?}");
                taken += 1;
            }
        }
        assert!(taken > 100_000, "{taken}");
        let ends = [
            -(1 << 15) - 1,
            -(1 << 15),
            -(1 << 15) + 1,
            0,
            (1 << 15) - 1,
            1 << 15,
            (1 << 15) + 1,
        ];
        for x1 in ends {
            for y1 in ends {
                for x2 in ends {
                    for y2 in ends {
                        let v = [
                            SubPoint::new(7, -3),
                            SubPoint::new(7 + x1, y1 - 3),
                            SubPoint::new(7 + x2, y2 - 3),
                        ];
                        let inside = [x1, y1, x2, y2]
                            .iter()
                            .all(|d| (-(1 << 15) + 1..=1 << 15).contains(d));
                        assert_eq!(
                            narrow_area2(&v).map(i64::from),
                            inside.then(|| signed_area2(&v)),
                            "{v:?}"
                        );
                    }
                }
            }
        }
    }
    use crate::raster::{scanline::spans, PixelRect, SubPoint};

    /// Every centre a filled triangle covers lies within `reach` with no
    /// margin (which ends a column and a row before `covering`), and a
    /// triangle it finds empty covers none: random small triangles, their
    /// vertices often on or near pixel centres, where the fill rule
    /// decides.
    #[test]
    fn filled_triangles_cover_nothing_beyond_their_reach() {
        let mut next = crate::testing::rng();
        let mut empty = 0;
        for _ in 0..200_000 {
            let mut p = || {
                let mut c = || match next(3) {
                    // A pixel centre, or a sub-pixel from one.
                    0 => 8 + 16 * next(6) as i32 + next(3) as i32 - 1,
                    _ => next(96) as i32,
                };
                SubPoint::new(c(), c())
            };
            let v = [p(), p(), p()];
            let r = reach(&v, 0);
            let mut inside = true;
            let mut covered = 0;
            spans(&v, PixelRect::new(-2, -2, 10, 10), |j, x0, x1| {
                covered += x1 - x0;
                inside &= r.y0 <= j && j < r.y1 && r.x0 <= x0 && x1 <= r.x1;
            });
            assert!(inside, "{v:?} {r:?}");
            if r.is_empty() {
                assert_eq!(covered, 0, "{v:?}");
                empty += 1;
            }
        }
        assert!(empty > 1_000, "the test should find empty reaches");
    }
}
