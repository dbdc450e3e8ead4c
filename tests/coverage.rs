//! Coverage: both rasterizers against an independent, exact edge-function
//! reference with the top-left rule, and watertightness of meshes that tile
//! a region exactly, both through `microraster::raster::scanline::spans` /
//! `microraster::raster::hilbert::spans` (which must give the very same
//! spans) and through the whole renderer with every rasterizer.
//!
//! Conventions under test (see `src/raster/mod.rs`): pixel `(i, j)` has its
//! centre at sub-pixel `(16 i + 8, 16 j + 8)`; a centre is covered when it is
//! strictly inside the triangle, or exactly on a top edge (horizontal, the
//! triangle below it, y down) or a left edge (the triangle to its right).

mod support;

use embedded_graphics::pixelcolor::{Gray8, GrayColor, Rgb888, RgbColor};
use fixed::types::I16F16;
use microraster::mesh::Vec3Fx;
use microraster::prelude::*;
use microraster::raster::{hilbert, scanline, PixelRect, SubPoint};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use support::Capture;

// ---------------------------------------------------------------------------
// The reference.
// ---------------------------------------------------------------------------

/// Sub-pixels per pixel and the offset of a pixel centre.
const SUB: i64 = 16;
const HALF: i64 = 8;

/// Whether the convex polygon `poly` (any winding, vertices in sub-pixels)
/// covers the point `(px, py)` (sub-pixels) under the top-left rule,
/// written from the definition with exact `i64` edge functions.
///
/// A polygon of zero area covers nothing.
fn ref_covers(poly: &[SubPoint], px: i64, py: i64) -> bool {
    let n = poly.len();
    let at = |k: usize| (poly[k % n].x as i64, poly[k % n].y as i64);
    // Twice the signed area (shoelace). For a triangle (a, b, c) this is
    // (b - a) x (c - a), so with this orientation every edge a -> b has the
    // interior where E(p) = (b - a) x (p - a) is positive.
    let area2: i64 = (0..n)
        .map(|k| {
            let (a, b) = (at(k), at(k + 1));
            a.0 * b.1 - b.0 * a.1
        })
        .sum();
    if area2 == 0 {
        return false;
    }
    for k in 0..n {
        let (a, b) = if area2 > 0 {
            (at(k), at(k + 1))
        } else {
            (at(k + 1), at(k))
        };
        let e = (b.0 - a.0) * (py - a.1) - (b.1 - a.1) * (px - a.0);
        if e > 0 {
            continue;
        }
        if e < 0 {
            return false;
        }
        // Exactly on this edge's line. The interior lies where E grows:
        // dE/dx > 0 means the triangle is to the right (a left edge);
        // dE/dx == 0 is a horizontal edge, and dE/dy > 0 puts the triangle
        // below it (y down: a top edge). Only those edges own their points.
        let (de_dx, de_dy) = (-(b.1 - a.1), b.0 - a.0);
        let top_left = de_dx > 0 || (de_dx == 0 && de_dy > 0);
        if !top_left {
            return false;
        }
    }
    true
}

/// Centre of pixel index `i`, in sub-pixels.
fn centre(i: i32) -> i64 {
    i as i64 * SUB + HALF
}

/// Runs the scanline and the Hilbert rasterizer's `spans` for `tris`
/// within `clip` and counts hits per pixel of `clip`. The two must give the
/// same spans in the same order; any span outside `clip`, empty or inverted
/// is an error.
fn count_hits(tris: &[[SubPoint; 3]], clip: PixelRect) -> Result<Vec<u32>, TestCaseError> {
    let w = (clip.x1 - clip.x0).max(0) as usize;
    let h = (clip.y1 - clip.y0).max(0) as usize;
    let mut hits = vec![0u32; w * h];
    for tri in tris {
        let (mut by_scanline, mut by_hilbert) = (Vec::new(), Vec::new());
        scanline::spans(tri, clip, |row, x0, x1| by_scanline.push((row, x0, x1)));
        hilbert::spans(tri, clip, |row, x0, x1| by_hilbert.push((row, x0, x1)));
        prop_assert_eq!(
            &by_scanline,
            &by_hilbert,
            "scanline vs. Hilbert spans of {:?} in {:?}",
            tri,
            clip
        );
        for (row, x0, x1) in by_scanline {
            if !(x0 < x1 && clip.x0 <= x0 && x1 <= clip.x1 && clip.y0 <= row && row < clip.y1) {
                return Err(TestCaseError::fail(format!(
                    "span row {row} x {x0}..{x1} of {tri:?} is empty or outside {clip:?}"
                )));
            }
            let r = (row - clip.y0) as usize * w;
            for x in x0..x1 {
                hits[r + (x - clip.x0) as usize] += 1;
            }
        }
    }
    Ok(hits)
}

// ---------------------------------------------------------------------------
// Single triangles against the reference.
// ---------------------------------------------------------------------------

fn pt(r: i32) -> impl Strategy<Value = SubPoint> {
    (-r..=r, -r..=r).prop_map(|(x, y)| SubPoint::new(x, y))
}

/// A point on the half-pixel grid, so that many pixel centres fall exactly
/// on edges and vertices.
fn pt_snapped(r: i32) -> impl Strategy<Value = SubPoint> {
    (-r..=r, -r..=r).prop_map(|(x, y)| SubPoint::new(x * 8, y * 8))
}

fn add(a: SubPoint, dx: i64, dy: i64) -> SubPoint {
    SubPoint::new((a.x as i64 + dx) as i32, (a.y as i64 + dy) as i32)
}

/// Random triangles of every kind the brief names.
fn triangle() -> impl Strategy<Value = [SubPoint; 3]> {
    const HUGE: i32 = 1 << 17;
    let tri =
        prop_oneof![
            // Ordinary, up to ~200 px.
            [pt(3000), pt(3000), pt(3000)],
            // Huge: the whole +-2^17 sub-pixel range.
            [pt(HUGE), pt(HUGE), pt(HUGE)],
            // Tiny: within 3 px, mostly sub-pixel.
            (pt(4000), [pt(24), pt(24), pt(24)])
                .prop_map(|(b, o)| o.map(|d| add(b, d.x as i64, d.y as i64))),
            // On the half-pixel grid: exact ties on edges and at vertices.
            [pt_snapped(40), pt_snapped(40), pt_snapped(40)],
            // Slivers: c within a few sub-pixels of the segment a-b.
            (
                prop_oneof![Just(3000), Just(HUGE)],
                any::<(i32, i32, i32, i32)>(),
                0..=1024i64,
                -40..=40i64,
                -40..=40i64
            )
                .prop_map(|(r, (ax, ay, bx, by), t, ox, oy)| {
                    let a = SubPoint::new(ax % r, ay % r);
                    let b = SubPoint::new(bx % r, by % r);
                    let c = add(
                        a,
                        (b.x as i64 - a.x as i64) * t / 1024 + ox,
                        (b.y as i64 - a.y as i64) * t / 1024 + oy,
                    );
                    [a, b, c]
                }),
            // Right triangles: horizontal and vertical edges.
            (pt(2000), -900..=900i64, -900..=900i64).prop_map(|(a, dx, dy)| [
                a,
                add(a, dx, 0),
                add(a, 0, dy)
            ]),
            // Flat top or flat bottom with a third vertex anywhere.
            (pt(2000), -900..=900i64, pt(2000)).prop_map(|(a, dx, c)| [a, add(a, dx, 0), c]),
            // Degenerate: coincident or collinear vertices.
            (pt(3000), -60..=60i64, -60..=60i64, -8..=8i64, -8..=8i64)
                .prop_map(|(a, dx, dy, k, m)| [a, add(a, k * dx, k * dy), add(a, m * dx, m * dy)]),
        ];
    // Either winding, any vertex first.
    (tri, 0..6usize).prop_map(|(t, p)| {
        const PERM: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        PERM[p].map(|k| t[k])
    })
}

/// A clip rectangle (pixels) placed where the triangle has edges: around a
/// vertex, a point on an edge, or the bounding-box centre. Sometimes a wide
/// strip, sometimes empty or inverted.
fn triangle_and_clip() -> impl Strategy<Value = ([SubPoint; 3], PixelRect)> {
    (
        triangle(),
        0..7usize,
        0..=256i64,
        prop_oneof![
            4 => (0..=40i32, 0..=40i32, 0..=40i32, 0..=40i32),
            1 => (0..=1500i32, 0..=2i32, 0..=1500i32, 0..=2i32),
            1 => (-3..=3i32, -3..=3i32, -3..=3i32, -3..=3i32),
        ],
    )
        .prop_map(|(t, focus, s, (l, u, r, d))| {
            let f = match focus {
                0..=2 => t[focus],
                3..=5 => {
                    let (a, b) = (t[focus - 3], t[(focus - 2) % 3]);
                    add(
                        a,
                        (b.x as i64 - a.x as i64) * s / 256,
                        (b.y as i64 - a.y as i64) * s / 256,
                    )
                }
                _ => SubPoint::new(
                    ((t[0].x as i64 + t[1].x as i64 + t[2].x as i64) / 3) as i32,
                    ((t[0].y as i64 + t[1].y as i64 + t[2].y as i64) / 3) as i32,
                ),
            };
            let (fx, fy) = (f.x.div_euclid(16), f.y.div_euclid(16));
            (t, PixelRect::new(fx - l, fy - u, fx + r, fy + d))
        })
}

/// Compares `spans` with the reference for one triangle within `clip`.
fn check_triangle(t: [SubPoint; 3], clip: PixelRect) -> Result<(), TestCaseError> {
    let hits = count_hits(&[t], clip)?;
    let w = (clip.x1 - clip.x0).max(0) as usize;
    for j in clip.y0..clip.y1 {
        for i in clip.x0..clip.x1 {
            let got = hits[(j - clip.y0) as usize * w + (i - clip.x0) as usize];
            let want = ref_covers(&t, centre(i), centre(j)) as u32;
            prop_assert_eq!(
                got,
                want,
                "pixel ({}, {}) of triangle {:?} in clip {:?}: {} hits, reference {}",
                i,
                j,
                t,
                clip,
                got,
                want
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6000, ..ProptestConfig::default() })]

    #[test]
    fn spans_match_the_exact_reference((t, clip) in triangle_and_clip()) {
        check_triangle(t, clip)?;
    }
}

/// Hand-picked cases where every tie of the rule matters.
#[test]
fn reference_and_spans_agree_on_exact_ties() {
    let p = |x: i32, y: i32| SubPoint::new(x, y);
    let clip = PixelRect::new(-8, -8, 12, 12);
    let cases = [
        // Vertices on pixel centres, horizontal top and bottom edges.
        [p(8, 8), p(72, 8), p(8, 72)],
        [p(8, 72), p(72, 72), p(72, 8)],
        // A vertical left edge and a vertical right edge through centres.
        [p(8, 8), p(8, 72), p(72, 40)],
        [p(72, 8), p(72, 72), p(8, 40)],
        // Diagonal edges through centres, both windings.
        [p(8, 8), p(72, 72), p(8, 72)],
        [p(8, 8), p(8, 72), p(72, 72)],
        // Middle vertex exactly on a centre, left and right.
        [p(40, 8), p(8, 40), p(40, 72)],
        [p(40, 8), p(72, 40), p(40, 72)],
        // Tiny triangles around a single centre.
        [p(8, 7), p(9, 9), p(7, 9)],
        [p(7, 7), p(9, 8), p(8, 9)],
        [p(8, 8), p(9, 8), p(8, 9)],
        [p(8, 8), p(7, 8), p(8, 7)],
    ];
    for t in cases {
        check_triangle(t, clip).unwrap();
    }
    // The rule itself, on the square split along its diagonal: centres on
    // the shared diagonal go to exactly one half.
    let a = [p(8, 8), p(72, 8), p(72, 72)];
    let b = [p(8, 8), p(72, 72), p(8, 72)];
    for j in 0..5 {
        for i in 0..5 {
            let (x, y) = (centre(i), centre(j));
            let n = ref_covers(&a, x, y) as u32 + ref_covers(&b, x, y) as u32;
            let inside_square = (i < 4 && j < 4) as u32;
            assert_eq!(n, inside_square, "centre ({i}, {j})");
        }
    }
}

// ---------------------------------------------------------------------------
// Watertightness through `spans`.
// ---------------------------------------------------------------------------

/// A jittered grid that tiles the rectangle `[x0, x0 + sum(widths)) x
/// [y0, y0 + sum(heights))` (sub-pixels) exactly: interior vertices move by
/// at most 1/8 of their neighbouring cells (so no triangle flips), boundary
/// vertices move only along the boundary, corners stay.
#[derive(Clone, Debug)]
struct Grid {
    x0: i32,
    y0: i32,
    widths: Vec<i32>,
    heights: Vec<i32>,
    /// Per vertex, in 1/64 of the allowed jitter.
    jitter: Vec<(i32, i32)>,
    /// Per cell: which diagonal splits it.
    diagonal: Vec<bool>,
    /// Per triangle: reverse the winding.
    flip: Vec<bool>,
}

impl Grid {
    fn region(&self) -> (i64, i64, i64, i64) {
        let w: i64 = self.widths.iter().map(|&v| v as i64).sum();
        let h: i64 = self.heights.iter().map(|&v| v as i64).sum();
        (
            self.x0 as i64,
            self.y0 as i64,
            self.x0 as i64 + w,
            self.y0 as i64 + h,
        )
    }

    /// Vertices (row-major, `(nc + 1) x (nr + 1)`) and triangles.
    fn mesh(&self) -> (Vec<SubPoint>, Vec<[usize; 3]>) {
        let (nc, nr) = (self.widths.len(), self.heights.len());
        let mut xs = vec![self.x0];
        for &w in &self.widths {
            xs.push(xs.last().unwrap() + w);
        }
        let mut ys = vec![self.y0];
        for &h in &self.heights {
            ys.push(ys.last().unwrap() + h);
        }
        let mut verts = Vec::new();
        for (j, &y) in ys.iter().enumerate() {
            for (i, &x) in xs.iter().enumerate() {
                let (jx, jy) = self.jitter[j * (nc + 1) + i];
                let dx = if i == 0 || i == nc {
                    0
                } else {
                    jx * (self.widths[i - 1].min(self.widths[i]) / 8) / 64
                };
                let dy = if j == 0 || j == nr {
                    0
                } else {
                    jy * (self.heights[j - 1].min(self.heights[j]) / 8) / 64
                };
                verts.push(SubPoint::new(x + dx, y + dy));
            }
        }
        let id = |i: usize, j: usize| j * (nc + 1) + i;
        let mut tris = Vec::new();
        for j in 0..nr {
            for i in 0..nc {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                let pair = if self.diagonal[j * nc + i] {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for t in pair {
                    let k = tris.len();
                    tris.push(if self.flip[k] { [t[0], t[2], t[1]] } else { t });
                }
            }
        }
        (verts, tris)
    }
}

fn grid(
    x0: impl Strategy<Value = i32>,
    y0: impl Strategy<Value = i32>,
    cells: usize,
    cell: std::ops::RangeInclusive<i32>,
) -> impl Strategy<Value = Grid> {
    (x0, y0, 1..=cells, 1..=cells).prop_flat_map(move |(x0, y0, nc, nr)| {
        (
            Just(x0),
            Just(y0),
            prop::collection::vec(cell.clone(), nc),
            prop::collection::vec(cell.clone(), nr),
            prop::collection::vec((-64..=64i32, -64..=64i32), (nc + 1) * (nr + 1)),
            prop::collection::vec(any::<bool>(), nc * nr),
            prop::collection::vec(any::<bool>(), 2 * nc * nr),
        )
            .prop_map(|(x0, y0, widths, heights, jitter, diagonal, flip)| Grid {
                x0,
                y0,
                widths,
                heights,
                jitter,
                diagonal,
                flip,
            })
    })
}

/// The pixels whose centres lie in `[x0, x1) x [y0, y1)`: the top-left rule
/// applied to an axis-aligned rectangle.
fn in_region(r: (i64, i64, i64, i64), i: i32, j: i32) -> bool {
    let (x, y) = (centre(i), centre(j));
    r.0 <= x && x < r.2 && r.1 <= y && y < r.3
}

/// Every hit count in `clip` is 1 where `expected` says so and 0 elsewhere.
fn check_exactly_once(
    hits: &[u32],
    clip: PixelRect,
    expected: impl Fn(i32, i32) -> bool,
    what: &dyn Fn() -> String,
) -> Result<(), TestCaseError> {
    let w = (clip.x1 - clip.x0) as usize;
    for j in clip.y0..clip.y1 {
        for i in clip.x0..clip.x1 {
            let got = hits[(j - clip.y0) as usize * w + (i - clip.x0) as usize];
            let want = expected(i, j) as u32;
            if got != want {
                return Err(TestCaseError::fail(format!(
                    "pixel ({i}, {j}): {got} hits, expected {want}; {}",
                    what()
                )));
            }
        }
    }
    Ok(())
}

/// The strict convex hull of `pts` (no collinear vertices), by Andrew's
/// monotone chain with exact `i64` cross products. Its winding does not
/// matter to the reference.
fn convex_hull(mut pts: Vec<SubPoint>) -> Vec<SubPoint> {
    pts.sort_by_key(|p| (p.x, p.y));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: SubPoint, a: SubPoint, b: SubPoint| {
        (a.x as i64 - o.x as i64) * (b.y as i64 - o.y as i64)
            - (a.y as i64 - o.y as i64) * (b.x as i64 - o.x as i64)
    };
    let mut hull: Vec<SubPoint> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &SubPoint>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[derive(Clone, Debug)]
struct Fan {
    points: Vec<SubPoint>,
    /// Weights of the hull vertices that place the hub.
    weights: Vec<u8>,
    /// Per triangle: reverse the winding.
    flip: Vec<bool>,
    /// Which hull vertex the counting window is centred on.
    focus: usize,
}

fn fan() -> impl Strategy<Value = Fan> {
    (
        pt(1 << 12),
        prop_oneof![Just(40), Just(400), Just(2500), Just(1 << 16)],
        3..=14usize,
    )
        .prop_flat_map(|(c, r, n)| {
            (
                prop::collection::vec(pt(r), n).prop_map(move |v| {
                    v.into_iter()
                        .map(|p| add(c, p.x as i64, p.y as i64))
                        .collect()
                }),
                prop::collection::vec(0..=20u8, n),
                prop::collection::vec(any::<bool>(), n),
                0..n,
            )
                .prop_map(|(points, weights, flip, focus)| Fan {
                    points,
                    weights,
                    flip,
                    focus,
                })
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]

    /// A jittered, randomly split grid covers every pixel centre of its
    /// rectangle exactly once and nothing around it.
    #[test]
    fn jittered_grid_is_watertight(
        g in grid(-(1 << 12)..=(1 << 12), -(1 << 12)..=(1 << 12), 8, 2..=400)
    ) {
        let (verts, tris) = g.mesh();
        let tris: Vec<[SubPoint; 3]> = tris.iter().map(|t| t.map(|k| verts[k])).collect();
        let r = g.region();
        let clip = PixelRect::new(
            (r.0 >> 4) as i32 - 2,
            (r.1 >> 4) as i32 - 2,
            (r.2 >> 4) as i32 + 3,
            (r.3 >> 4) as i32 + 3,
        );
        let hits = count_hits(&tris, clip)?;
        check_exactly_once(&hits, clip, |i, j| in_region(r, i, j), &|| format!("{g:?}"))?;
    }

    /// A fan around a point of a convex polygon covers exactly the centres
    /// the polygon covers under the same rule, each once.
    #[test]
    fn fan_is_watertight(f in fan()) {
        let hull = convex_hull(f.points.clone());
        if hull.len() < 3 {
            return Ok(()); // all points collinear: no polygon
        }
        // The hub: a weighted mean of the hull vertices, or a hull vertex
        // when rounding put the mean outside (a fan around a vertex tiles
        // the polygon too, with two empty triangles).
        let wsum: i64 = f.weights.iter().take(hull.len()).map(|&w| w as i64).sum::<i64>().max(1);
        let mean = |get: fn(&SubPoint) -> i32| -> i32 {
            (hull.iter().zip(&f.weights).map(|(p, &w)| get(p) as i64 * w as i64).sum::<i64>()
                / wsum) as i32
        };
        let mut hub = SubPoint::new(mean(|p| p.x), mean(|p| p.y));
        let inside_closed = (0..hull.len()).all(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
            (b.x as i64 - a.x as i64) * (hub.y as i64 - a.y as i64)
                - (b.y as i64 - a.y as i64) * (hub.x as i64 - a.x as i64)
                >= 0
        });
        if !inside_closed {
            hub = hull[0];
        }
        let tris: Vec<[SubPoint; 3]> = (0..hull.len())
            .map(|k| {
                let t = [hub, hull[k], hull[(k + 1) % hull.len()]];
                if f.flip[k] { [t[0], t[2], t[1]] } else { t }
            })
            .collect();
        // Count within the polygon's box, limited to 160 x 160 pixels
        // around one of its vertices.
        let fo = hull[f.focus % hull.len()];
        let (fx, fy) = (fo.x.div_euclid(16), fo.y.div_euclid(16));
        let bx0 = hull.iter().map(|p| p.x).min().unwrap().div_euclid(16) - 1;
        let by0 = hull.iter().map(|p| p.y).min().unwrap().div_euclid(16) - 1;
        let bx1 = hull.iter().map(|p| p.x).max().unwrap().div_euclid(16) + 2;
        let by1 = hull.iter().map(|p| p.y).max().unwrap().div_euclid(16) + 2;
        let clip = PixelRect::new(bx0, by0, bx1, by1)
            .intersect(&PixelRect::new(fx - 80, fy - 80, fx + 80, fy + 80));
        let hits = count_hits(&tris, clip)?;
        check_exactly_once(
            &hits,
            clip,
            |i, j| ref_covers(&hull, centre(i), centre(j)),
            &|| format!("hull {hull:?}, hub {hub:?}"),
        )?;
    }
}

// ---------------------------------------------------------------------------
// Watertightness through the renderer.
// ---------------------------------------------------------------------------

/// A frame and a jittered grid in its screen space (sub-pixels). The grid
/// may reach beyond the frame and beyond the guard band.
fn screen_grid() -> impl Strategy<Value = (u32, u32, Grid)> {
    (1..=150u32, 1..=120u32).prop_flat_map(|(w, h)| {
        let (w16, h16) = (16 * w as i32, 16 * h as i32);
        (
            Just(w),
            Just(h),
            grid(
                -2 * w16..=w16,
                -2 * h16..=h16,
                8,
                4..=(3 * w16.max(h16) / 4).max(8),
            ),
        )
    })
}

/// `n / d` rounded to nearest, `d > 0`.
fn div_round(n: i64, d: i64) -> i64 {
    (2 * n + d).div_euclid(2 * d)
}

/// Renders the grid, placed in clip space so that the viewport maps its
/// vertices back to exactly the chosen sub-pixel positions, and checks that
/// each pixel centre of the region inside the frame is shaded exactly once.
fn render_grid<const TW: usize, const TH: usize>(
    w: u32,
    h: u32,
    g: &Grid,
) -> Result<(), TestCaseError> {
    for (raster, order) in [
        (Rasterizer::Scanline, TileOrder::RowMajor),
        (Rasterizer::Hilbert, TileOrder::RowMajor),
        (Rasterizer::Auto, TileOrder::Hilbert),
    ] {
        render_grid_with::<TW, TH>(w, h, g, raster, order)?;
    }
    Ok(())
}

/// [`render_grid`] with one rasterizer and tile order.
fn render_grid_with<const TW: usize, const TH: usize>(
    w: u32,
    h: u32,
    g: &Grid,
    raster: Rasterizer,
    order: TileOrder,
) -> Result<(), TestCaseError> {
    let (verts, tris) = g.mesh();
    // The viewport maps NDC x to half_w + x * half_w sub-pixels (and y
    // flipped), rounding to nearest. A clip x rounded to 1/65536 is off by
    // at most half_w / 2^17 < 1/2 sub-pixel, so it maps back exactly.
    let (hw, hh) = (8 * w as i64, 8 * h as i64);
    let positions: Vec<Vec3Fx> = verts
        .iter()
        .map(|p| {
            let x = div_round((p.x as i64 - hw) << 16, hw);
            let y = div_round((hh - p.y as i64) << 16, hh);
            [
                I16F16::from_bits(x as i32),
                I16F16::from_bits(y as i32),
                I16F16::ZERO,
            ]
        })
        .collect();
    let triangles: Vec<[u16; 3]> = tris.iter().map(|t| t.map(|k| k as u16)).collect();
    let mesh = Mesh::new(&positions, &triangles).expect("valid grid mesh");
    let draws = [Draw::new(&mesh).color(Rgb888::WHITE)];
    let scene = Scene::new(Camera::new(Mat4::IDENTITY, Mat4::IDENTITY), &draws);
    let size = Size::new(w, h);
    let mut renderer: Renderer<Gray8, TW, TH> = Renderer::new(
        Config::new(size, Gray8::BLACK)
            .cull(CullMode::None)
            .depth_test(DepthTest::Always)
            .rasterizer(raster)
            .tile_order(order),
    );
    let mut ws: Box<Workspace<128, 4096, 128>> = Box::new(Workspace::new());
    let mut cap = Capture::new(size, Gray8::new(77));
    let stats = renderer
        .render(&mut ws, &scene, &mut cap)
        .map_err(|e| TestCaseError::fail(format!("render failed: {e:?}")))?;
    let lit = Gray8::from(Rgb888::WHITE);
    prop_assert!(lit != Gray8::BLACK);
    prop_assert!(
        cap.writes.iter().all(|&n| n == 1),
        "{TW}x{TH} {raster:?} {order:?}: a pixel was not sent exactly once"
    );
    let r = g.region();
    let mut expected = 0u32;
    for j in 0..h as i32 {
        for i in 0..w as i32 {
            let want = in_region(r, i, j);
            expected += want as u32;
            let got = cap.get(i as u32, j as u32);
            prop_assert_eq!(
                got == lit,
                want,
                "{:?} {:?}, {}x{} tiles, {}x{} frame: pixel ({}, {}) is {:?}; region {:?}",
                raster,
                order,
                TW,
                TH,
                w,
                h,
                i,
                j,
                got,
                r
            );
        }
    }
    prop_assert_eq!(
        stats.pixels_shaded,
        expected,
        "{}x{} tiles: fragments shaded vs. centres covered ({:?})",
        TW,
        TH,
        stats
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 150, ..ProptestConfig::default() })]

    #[test]
    fn renderer_is_watertight_16x16((w, h, g) in screen_grid()) {
        render_grid::<16, 16>(w, h, &g)?;
    }

    #[test]
    fn renderer_is_watertight_32x32((w, h, g) in screen_grid()) {
        render_grid::<32, 32>(w, h, &g)?;
    }

    #[test]
    fn renderer_is_watertight_64x32((w, h, g) in screen_grid()) {
        render_grid::<64, 32>(w, h, &g)?;
    }

    #[test]
    fn renderer_is_watertight_24x20((w, h, g) in screen_grid()) {
        render_grid::<24, 20>(w, h, &g)?;
    }
}

/// A fixed grid that fills the whole frame and crosses every tile border.
#[test]
fn full_frame_grid_is_drawn_once_per_pixel() {
    let g = Grid {
        x0: 0,
        y0: 0,
        widths: vec![16 * 13 + 5, 16 * 30 + 3, 16 * 7 + 11, 16 * 48 + 13],
        heights: vec![16 * 21 + 7, 16 * 9 + 1, 16 * 40 + 8],
        jitter: (0..20)
            .map(|k| ((k * 37) % 129 - 64, (k * 53) % 129 - 64))
            .collect(),
        diagonal: (0..12).map(|k| k % 3 == 0).collect(),
        flip: (0..24).map(|k| k % 5 < 2).collect(),
    };
    // The region is exactly the frame.
    let (w, h) = (100, 71);
    assert_eq!(g.region(), (0, 0, 16 * 100, 16 * 71));
    render_grid::<16, 16>(w, h, &g).unwrap();
    render_grid::<32, 32>(w, h, &g).unwrap();
    render_grid::<64, 32>(w, h, &g).unwrap();
    render_grid::<24, 20>(w, h, &g).unwrap();
}
