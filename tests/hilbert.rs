//! The Hilbert-order traversal covers exactly the pixels the scanline
//! rasterizer covers, on random triangles (tiny, slivers, huge, off-tile,
//! on the half-pixel grid, both windings) in random power-of-two regions
//! and clip rectangles, each pixel once.

use microraster::raster::hilbert::{order_for, walk, Edges};
use microraster::raster::{scanline::spans, PixelRect, SubPoint};
use proptest::prelude::*;
use std::collections::BTreeSet;

fn scanline_set(v: &[SubPoint; 3], clip: PixelRect) -> BTreeSet<(i32, i32)> {
    let mut s = BTreeSet::new();
    spans(v, clip, |j, x0, x1| {
        for i in x0..x1 {
            assert!(s.insert((i, j)), "scanline reported ({i}, {j}) twice");
        }
    });
    s
}

fn hilbert_set(
    v: &[SubPoint; 3],
    x0: i32,
    y0: i32,
    order: u32,
    clip: PixelRect,
) -> BTreeSet<(i32, i32)> {
    let mut s = BTreeSet::new();
    if let Some(e) = Edges::new(v) {
        walk(&e, x0, y0, order, clip, |x, y, w, h| {
            assert!(w > 0 && (h == w || h == 1), "block {w}x{h}");
            for j in y..y + h {
                for i in x..x + w {
                    assert!(s.insert((i, j)), "hilbert reported ({i}, {j}) twice");
                }
            }
        });
    }
    s
}

/// A vertex coordinate: anywhere within `range` sub-pixels of the region,
/// or on the half-pixel grid (exact ties with pixel centres).
fn coord(range: i32) -> impl Strategy<Value = i32> {
    prop_oneof![
        3 => -range..range,
        1 => (-range / 16..range / 16).prop_map(|v| v * 16 + 8),
        1 => (-range / 16..range / 16).prop_map(|v| v * 16),
    ]
}

fn small() -> impl Strategy<Value = SubPoint> {
    (coord(1200), coord(1200)).prop_map(|(x, y)| SubPoint::new(x, y))
}

fn huge() -> impl Strategy<Value = SubPoint> {
    (-(1 << 17)..(1 << 17), -(1 << 17)..(1 << 17)).prop_map(|(x, y)| SubPoint::new(x, y))
}

fn triangle() -> impl Strategy<Value = [SubPoint; 3]> {
    let sliver = (
        (coord(1200), coord(1200)),
        (-3..4i32, -3..4i32),
        (coord(1200), coord(1200)),
    )
        .prop_map(|((ax, ay), (dx, dy), (bx, by))| {
            [
                SubPoint::new(ax, ay),
                SubPoint::new(bx, by),
                SubPoint::new(bx + dx, by + dy),
            ]
        });
    prop_oneof![
        4 => [small(), small(), small()],
        1 => [huge().boxed(), small().boxed(), huge().boxed()],
        2 => sliver,
        1 => (coord(1200), coord(1200), 1..40i32).prop_map(|(x, y, d)| {
            [SubPoint::new(x, y), SubPoint::new(x + d, y), SubPoint::new(x, y + d)]
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn hilbert_covers_exactly_what_scanline_covers(
        v in triangle(),
        order in 0u32..7,
        (x0, y0) in (-20i32..60, -20i32..60),
        (cw, ch, cx, cy) in (0i32..70, 0i32..70, -5i32..10, -5i32..10),
    ) {
        let n = 1 << order;
        // The region's own square, or a clip inside or across it.
        let clip = PixelRect::new(x0 + cx, y0 + cy, x0 + cx + cw.min(n + 4), y0 + cy + ch.min(n + 4));
        let region = PixelRect::new(x0, y0, x0 + n, y0 + n);
        let inside = clip.intersect(&region);
        let expected = scanline_set(&v, inside);
        let got = hilbert_set(&v, x0, y0, order, clip);
        prop_assert_eq!(got, expected, "triangle {:?} region {:?} clip {:?}", v, region, clip);
    }
}

#[test]
fn a_tile_sized_region_is_found_for_any_tile() {
    for (w, h) in [(16, 16), (32, 32), (64, 32), (24, 20), (13, 7), (1, 1)] {
        let n = 1u32 << order_for(w, h);
        assert!(n >= w && n >= h && (n == 1 || n / 2 < w.max(h)));
    }
}

/// Whole blocks are found: a big triangle over a 64x64 region is reported
/// in far fewer blocks than pixels.
#[test]
fn interior_blocks_are_filled_whole() {
    let v = [
        SubPoint::new(-500, -500),
        SubPoint::new(3000, -400),
        SubPoint::new(-300, 2900),
    ];
    let e = Edges::new(&v).unwrap();
    let mut blocks = 0;
    let mut pixels = 0;
    let classified = walk(&e, 0, 0, 6, PixelRect::new(0, 0, 64, 64), |_, _, w, h| {
        blocks += 1;
        pixels += w * h;
    });
    assert_eq!(
        pixels as usize,
        scanline_set(&v, PixelRect::new(0, 0, 64, 64)).len()
    );
    assert!(blocks * 4 < pixels, "{blocks} blocks for {pixels} pixels");
    assert!(classified < 1000, "{classified} blocks classified");
}
