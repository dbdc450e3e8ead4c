//! Tests of texture layout checks, addressing and filtering.

use super::*;

/// A small xorshift generator: reproducible pseudo-random raw values.
struct XorShift(u32);

impl XorShift {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// A raw 16.16 coordinate: mostly near `-3..3`, sometimes anywhere.
    fn coordinate(&mut self) -> i32 {
        let r = self.next();
        match r % 4 {
            0 => r as i32,
            _ => (self.next() % (6 << 16)) as i32 - (3 << 16),
        }
    }
}

const WRAPS: [Wrap; 3] = [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge];

/// Extreme and seam raw coordinates, tried everywhere.
const SPECIAL: [i32; 16] = [
    i32::MIN,
    i32::MIN + 1,
    i32::MAX,
    i32::MAX - 1,
    -(2 << 16),
    -(1 << 16) - 1,
    -(1 << 16),
    -(1 << 16) + 1,
    -1,
    0,
    1,
    (1 << 16) - 1,
    1 << 16,
    (1 << 16) + 1,
    (2 << 16) - 1,
    2 << 16,
];

fn fx(raw: i32) -> I16F16 {
    I16F16::from_bits(raw)
}

/// Maps integer texel coordinate `i` by `wrap` onto `0..size`, written
/// straight from the OpenGL specification, in `i64`.
fn wrap_reference(i: i64, size: i64, wrap: Wrap) -> i64 {
    match wrap {
        Wrap::Repeat => i.rem_euclid(size),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * size);
            if m < size {
                m
            } else {
                2 * size - 1 - m
            }
        }
        Wrap::ClampToEdge => i.clamp(0, size - 1),
    }
}

/// The nearest texel of `floor(u · size)`, in `i64`.
fn nearest_reference(raw: i32, size: u32, wrap: Wrap) -> u32 {
    let i = (raw as i64 * size as i64).div_euclid(1 << 16);
    wrap_reference(i, size as i64, wrap) as u32
}

fn axis(size: u32, wrap: Wrap) -> Axis {
    Axis {
        wrap,
        ..Axis::new(size)
    }
}

/// Gray8 texture whose texel `(x, y)` is `value(x, y)`.
fn gray(width: u32, height: u32, value: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| value(x, y))
        .collect()
}

/// A distinct grey per texel, so the texel read is identifiable.
fn id(width: u32) -> impl Fn(u32, u32) -> u8 {
    move |x, y| (y * width + x) as u8
}

#[test]
fn nearest_hand_checked() {
    // (raw u, [repeat, mirrored, clamp]) for a side of 3.
    let three: [(i32, [u32; 3]); 15] = [
        (0, [0, 0, 0]),
        (21_845, [0, 0, 0]), // 0.33333 · 3 = 0.99998
        (21_846, [1, 1, 1]), // 1.00003
        (43_690, [1, 1, 1]),
        (43_691, [2, 2, 2]),
        (65_535, [2, 2, 2]),
        (65_536, [0, 2, 2]), // u = 1: the seam
        (65_536 + 21_846, [1, 1, 2]),
        (131_072, [0, 0, 2]), // u = 2: the mirror's period
        (-1, [2, 0, 0]),
        (-21_846, [1, 1, 0]),
        (-65_536, [0, 2, 0]),
        (-65_537, [2, 2, 0]),
        (i32::MIN, [0, 0, 0]), // u = -32768: -98304 texels
        (i32::MAX, [2, 0, 2]), // 98303.99995: 98303 = 6 · 16383 + 5
    ];
    // A side of 2 (a power of two: the fast path).
    let two: [(i32, [u32; 3]); 11] = [
        (0, [0, 0, 0]),
        (32_767, [0, 0, 0]),
        (32_768, [1, 1, 1]),
        (65_535, [1, 1, 1]),
        (65_536, [0, 1, 1]),
        (98_304, [1, 0, 1]),
        (-1, [1, 0, 0]),
        (-32_768, [1, 0, 0]),
        (-32_769, [0, 1, 0]),
        (i32::MIN, [0, 0, 0]),
        (i32::MAX, [1, 0, 1]),
    ];
    // 5 (odd, not a power of two) and 4.
    let five: [(i32, [u32; 3]); 8] = [
        (13_107, [0, 0, 0]), // 0.199997 · 5 = 0.99998
        (13_108, [1, 1, 1]),
        (52_429, [4, 4, 4]), // 4.00002
        (65_536 + 13_108, [1, 3, 4]),
        (-13_107, [4, 0, 0]),
        (-13_108, [3, 1, 0]),
        (i32::MIN, [0, 0, 0]),
        (i32::MAX, [4, 0, 4]),
    ];
    let four: [(i32, [u32; 3]); 8] = [
        (16_383, [0, 0, 0]),
        (16_384, [1, 1, 1]),
        (49_152, [3, 3, 3]),
        (65_536 + 16_384, [1, 2, 3]),
        (-16_384, [3, 0, 0]),
        (-16_385, [2, 1, 0]),
        (i32::MIN, [0, 0, 0]),
        (i32::MAX, [3, 0, 3]),
    ];
    type Table<'t> = &'t [(i32, [u32; 3])];
    let cases: [(u32, Table); 4] = [(3, &three), (2, &two), (5, &five), (4, &four)];
    for (size, table) in cases {
        for &(raw, expected) in table {
            for (w, &wrap) in WRAPS.iter().enumerate() {
                assert_eq!(
                    axis(size, wrap).nearest(raw),
                    expected[w],
                    "size {size}, {wrap:?}, raw {raw}"
                );
                assert_eq!(nearest_reference(raw, size, wrap), expected[w]);
            }
        }
    }
}

#[test]
fn nearest_samples_the_right_texel() {
    // 5x3 and 4x4 textures: a texel's grey is its index; every texel
    // centre, and the same point one period (or two) away.
    for (w, h) in [(5u32, 3u32), (4, 4), (2, 2), (3, 2)] {
        let data = gray(w, h, id(w));
        let t = Texture::new(w, h, Texels::Gray8(&data)).unwrap();
        for y in 0..h {
            for x in 0..w {
                let u = ((2 * x + 1) << 16) as i32 / (2 * w) as i32;
                let v = ((2 * y + 1) << 16) as i32 / (2 * h) as i32;
                let g = (y * w + x) as u8;
                assert_eq!(t.sample(fx(u), fx(v)), [g, g, g]);
                assert_eq!(t.sample(fx(u + (1 << 16)), fx(v - (3 << 16))), [g, g, g]);
                let m = t.wrap(Wrap::MirroredRepeat);
                assert_eq!(m.sample(fx(u + (2 << 16)), fx(v - (2 << 16))), [g, g, g]);
                // Mirrored once: the other end of the row and column.
                let mirrored = ((h - 1 - y) * w + (w - 1 - x)) as u8;
                let s = m.sample(fx(u + (1 << 16)), fx(v - (1 << 16)));
                assert_eq!(s, [mirrored; 3]);
                assert_eq!(t.texel(x, y), [g, g, g]);
            }
        }
    }
}

#[test]
fn wrap_modes_per_axis() {
    let data = gray(3, 2, id(3));
    let t = Texture::new(3, 2, Texels::Gray8(&data))
        .unwrap()
        .wrap_uv(Wrap::ClampToEdge, Wrap::Repeat);
    assert_eq!(t.wrap_modes(), (Wrap::ClampToEdge, Wrap::Repeat));
    // u = 1.1 clamps to column 2; v = 1.25 repeats to row 0.
    assert_eq!(t.sample(fx(72_090), fx(81_920)), [2; 3]);
    // u = -0.5 clamps to column 0; v = -0.25 repeats to row 1.
    assert_eq!(t.sample(fx(-32_768), fx(-16_384)), [3; 3]);
    let t = t.wrap_uv(Wrap::Repeat, Wrap::MirroredRepeat);
    // u = 1.1 repeats to column 0; v = 1.25 mirrors to row 1.
    assert_eq!(t.sample(fx(72_090), fx(81_920)), [3; 3]);
}

#[test]
fn nearest_fast_path_matches_generic_and_reference() {
    let mut rng = XorShift(0x2545_F491);
    for k in 0..=15 {
        let size = 1u32 << k;
        for wrap in WRAPS {
            let fast = axis(size, wrap);
            assert!(fast.pow2);
            let generic = Axis {
                pow2: false,
                ..fast
            };
            let raws = (0..2_000).map(|_| rng.coordinate()).chain(SPECIAL);
            for raw in raws.collect::<Vec<_>>() {
                let expected = nearest_reference(raw, size, wrap);
                assert_eq!(fast.nearest(raw), expected, "2^{k} {wrap:?} {raw}");
                assert_eq!(generic.nearest(raw), expected, "2^{k} {wrap:?} {raw}");
                assert_eq!(fast.taps(raw), generic.taps(raw), "2^{k} {wrap:?} {raw}");
            }
        }
    }
}

#[test]
fn nearest_any_size_matches_reference() {
    let mut rng = XorShift(0x9E37_79B9);
    let sizes = [1u32, 3, 5, 6, 7, 100, 255, 1000, 4095, 32_767, MAX_SIDE];
    for size in sizes {
        for wrap in WRAPS {
            let a = axis(size, wrap);
            for _ in 0..3_000 {
                let raw = rng.coordinate();
                assert_eq!(a.nearest(raw), nearest_reference(raw, size, wrap));
            }
            for raw in SPECIAL {
                assert_eq!(a.nearest(raw), nearest_reference(raw, size, wrap));
            }
        }
    }
}

/// The bilinear taps in `i64`: `(i0, i1, fraction of s in 16 bits)`.
fn taps_reference(raw: i32, size: u32, wrap: Wrap) -> (u32, u32, u32) {
    let s = raw as i64 * size as i64 - (1 << 15);
    let i0 = s.div_euclid(1 << 16);
    let n = size as i64;
    (
        wrap_reference(i0, n, wrap) as u32,
        wrap_reference(i0 + 1, n, wrap) as u32,
        s.rem_euclid(1 << 16) as u32,
    )
}

#[test]
fn bilinear_taps_match_reference() {
    let mut rng = XorShift(0xDEAD_BEEF);
    let sizes = [1u32, 2, 3, 4, 5, 7, 8, 64, 100, 1024, 32_767, MAX_SIDE];
    for size in sizes {
        for wrap in WRAPS {
            let a = axis(size, wrap);
            let raws: Vec<i32> = (0..3_000)
                .map(|_| rng.coordinate())
                .chain(SPECIAL)
                .collect();
            for raw in raws {
                let (r0, r1, rf) = taps_reference(raw, size, wrap);
                let (i0, i1, f) = a.taps(raw);
                assert_eq!((i0, i1), (r0, r1), "size {size} {wrap:?} raw {raw}");
                // Clamped coordinates may differ in weight only where
                // both taps are the same texel.
                if r0 != r1 {
                    assert_eq!(f, rf >> 4, "size {size} {wrap:?} raw {raw}");
                }
            }
        }
    }
}

/// Bilinear in `f64` with exact weights, before rounding.
fn bilinear_reference(t: &Texture, data: &[u8], raw_u: i32, raw_v: i32) -> f64 {
    let axis = |raw: i32, size: u32, wrap: Wrap| {
        let s = raw as f64 / 65_536.0 * size as f64 - 0.5;
        let i0 = s.floor();
        let n = size as i64;
        (
            wrap_reference(i0 as i64, n, wrap) as usize,
            wrap_reference(i0 as i64 + 1, n, wrap) as usize,
            s - i0,
        )
    };
    let (wu, wv) = t.wrap_modes();
    let (x0, x1, a) = axis(raw_u, t.width(), wu);
    let (y0, y1, b) = axis(raw_v, t.height(), wv);
    let w = t.width() as usize;
    let c = |x: usize, y: usize| data[y * w + x] as f64;
    (1.0 - a) * (1.0 - b) * c(x0, y0)
        + a * (1.0 - b) * c(x1, y0)
        + (1.0 - a) * b * c(x0, y1)
        + a * b * c(x1, y1)
}

#[test]
fn bilinear_matches_f64_within_tolerance() {
    let mut rng = XorShift(0x1234_5678);
    let noise: Vec<u8> = (0..64).map(|_| rng.next() as u8).collect();
    for (w, h) in [(2u32, 2u32), (3, 2), (4, 4), (5, 3), (1, 7), (8, 8)] {
        // Extremes side by side make the steepest blends.
        let data: Vec<u8> = (0..w * h)
            .map(|i| {
                if i % 3 == 0 {
                    noise[i as usize]
                } else {
                    255 * (i as u8 & 1)
                }
            })
            .collect();
        for wu in WRAPS {
            for wv in WRAPS {
                let t = Texture::new(w, h, Texels::Gray8(&data))
                    .unwrap()
                    .filter(Filter::Bilinear)
                    .wrap_uv(wu, wv);
                let check = |u: i32, v: i32| {
                    let exact = bilinear_reference(&t, &data, u, v);
                    let got = t.sample(fx(u), fx(v));
                    assert_eq!(got[0], got[1]);
                    assert_eq!(got[0], got[2]);
                    let err = (got[0] as f64 - exact).abs();
                    assert!(
                        err < 0.625,
                        "{w}x{h} {wu:?} {wv:?} ({u}, {v}): {got:?} vs {exact}"
                    );
                };
                for _ in 0..2_000 {
                    check(rng.coordinate(), rng.coordinate());
                }
                for u in SPECIAL {
                    for v in SPECIAL {
                        check(u, v);
                    }
                }
            }
        }
    }
}

#[test]
fn bilinear_hand_checked() {
    // 2x1: grey 0 then 200.
    static DATA: [u8; 2] = [0, 200];
    let t = Texture::new(2, 1, Texels::Gray8(&DATA))
        .unwrap()
        .filter(Filter::Bilinear);
    // (u raw, [repeat, mirrored, clamp])
    let cases: [(i32, [u8; 3]); 8] = [
        (16_384, [0, 0, 0]),       // centre of texel 0
        (49_152, [200, 200, 200]), // centre of texel 1
        (32_768, [100, 100, 100]), // halfway
        (0, [100, 0, 0]),          // the left edge: seam
        (65_536, [100, 200, 200]), // the right edge: seam
        (8_192, [50, 0, 0]),       // s = -0.25: 3/4 of texel -1
        (-16_384, [200, 0, 0]),    // centre of texel -1
        (i32::MIN, [100, 0, 0]),   // u = -32768: an edge
    ];
    for (raw, expected) in cases {
        for (k, &wrap) in WRAPS.iter().enumerate() {
            let g = t.wrap(wrap).sample(fx(raw), fx(raw));
            assert_eq!(g, [expected[k]; 3], "{wrap:?} raw {raw}");
        }
    }
    // Halves round up: 0 and 255 halfway is 127.5.
    static EDGE: [u8; 2] = [0, 255];
    let t = Texture::new(2, 1, Texels::Gray8(&EDGE))
        .unwrap()
        .filter(Filter::Bilinear);
    assert_eq!(t.sample(fx(32_768), fx(0)), [128; 3]);
    // One weight step (1/4096) from texel 0's centre: 255 / 4096 < ½.
    assert_eq!(t.sample(fx(16_384 + 8), fx(0)), [0; 3]);
    // 384 units of 2^-16 past it: weight 48/4096 of 255, 2.99, gives 3.
    assert_eq!(t.sample(fx(16_384 + 384), fx(0)), [3; 3]);
}

#[test]
fn bilinear_at_texel_centres_is_nearest() {
    for (w, h) in [(2u32, 2u32), (4, 4), (3, 2), (5, 3), (7, 5)] {
        let data = gray(w, h, |x, y| (x * 71 + y * 113) as u8);
        for wu in WRAPS {
            for wv in WRAPS {
                let nearest = Texture::new(w, h, Texels::Gray8(&data))
                    .unwrap()
                    .wrap_uv(wu, wv);
                let bilinear = nearest.filter(Filter::Bilinear);
                for y in 0..h as i32 {
                    for x in 0..w as i32 {
                        // Centres a period away too (exact only for
                        // powers of two; otherwise the nearest raw
                        // value, less than a weight step away).
                        for period in [-2i64, -1, 0, 1, 3] {
                            let centre = |i: i32, n: u32| {
                                let c = ((2 * i as i64 + 1 + 2 * period * n as i64) << 16) as f64
                                    / (2 * n) as f64;
                                c.round() as i32
                            };
                            let (u, v) = (fx(centre(x, w)), fx(centre(y, h)));
                            assert_eq!(bilinear.sample(u, v), nearest.sample(u, v));
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn formats() {
    // Rgb565: one colour per texel, expanded by bit replication.
    static RGB: [u16; 3] = [0xF800, 0x07E0, 3 << 11 | 7 << 5 | 17];
    let t = Texture::new(3, 1, Texels::Rgb565(&RGB)).unwrap();
    assert_eq!(t.texel(0, 0), [255, 0, 0]);
    assert_eq!(t.texel(1, 0), [0, 255, 0]);
    assert_eq!(t.texel(2, 0), [24, 28, 140]);

    // Gray8.
    static GRAY: [u8; 4] = [0, 1, 128, 255];
    let t = Texture::new(2, 2, Texels::Gray8(&GRAY)).unwrap();
    assert_eq!(t.texel(1, 0), [1; 3]);
    assert_eq!(t.texel(0, 1), [128; 3]);
    assert_eq!(t.texel(1, 1), [255; 3]);

    // Indexed8, with a full palette (no index is checked).
    let palette: Vec<u16> = (0..=255u16).map(|i| i << 8).collect();
    let indices: Vec<u8> = (0..=255u8).collect();
    let t = Texture::new(
        16,
        16,
        Texels::Indexed8 {
            indices: &indices,
            palette: &palette,
        },
    )
    .unwrap();
    assert_eq!(t.texel(3, 2), rgb565_to_rgb888(35 << 8));
    assert_eq!(t.texel(15, 15), rgb565_to_rgb888(255 << 8));

    // Indexed4, odd width 3: stride 2, left texel in the high nibble; a
    // padding nibble past the palette is never read.
    static PALETTE4: [u16; 3] = [0x0000, 0xF800, 0x001F];
    static INDICES4: [u8; 4] = [0x01, 0x2F, 0x21, 0x0F];
    let t = Texture::new(
        3,
        2,
        Texels::Indexed4 {
            indices: &INDICES4,
            palette: &PALETTE4,
        },
    )
    .unwrap();
    let (k, r, b) = ([0, 0, 0], [255, 0, 0], [0, 0, 255]);
    assert_eq!([t.texel(0, 0), t.texel(1, 0), t.texel(2, 0)], [k, r, b]);
    assert_eq!([t.texel(0, 1), t.texel(1, 1), t.texel(2, 1)], [b, r, k]);
    // Out of range clamps to the last column and row.
    assert_eq!(t.texel(7, 9), k);
    assert_eq!(t.texel(u32::MAX, 0), b);
    // The same through sample: u = 5/6 is column 2, v = 3/4 row 1.
    assert_eq!(t.sample(fx(54_613), fx(49_152)), k);
    assert_eq!(t.sample(fx(54_613), fx(16_384)), b);

    // Indexed4 with an even width and a full palette.
    let palette: Vec<u16> = (0..16u16).map(|i| i * 0x1111).collect();
    let indices = [0x01u8, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF];
    let t = Texture::new(
        4,
        4,
        Texels::Indexed4 {
            indices: &indices,
            palette: &palette,
        },
    )
    .unwrap();
    for y in 0..4 {
        for x in 0..4 {
            let i = (y * 4 + x) as u16;
            assert_eq!(t.texel(x, y), rgb565_to_rgb888(i * 0x1111));
        }
    }
}

#[test]
fn rgb565_expansion() {
    for raw in 0..=u16::MAX {
        let [r, g, b] = rgb565_to_rgb888(raw);
        let (r5, g6, b5) = (raw >> 11, (raw >> 5) & 63, raw & 31);
        assert_eq!(r as u16, r5 << 3 | r5 >> 2);
        assert_eq!(g as u16, g6 << 2 | g6 >> 4);
        assert_eq!(b as u16, b5 << 3 | b5 >> 2);
        // Back to Rgb565, rounding to nearest as the importer does:
        // the original bits.
        let quantize = |c: u8, max: u32| (c as u32 * 257 * max + 32_767) / 65_535;
        let back = quantize(r, 31) << 11 | quantize(g, 63) << 5 | quantize(b, 31);
        assert_eq!(back, raw as u32);
    }
}

/// What the docs of `rgb565_to_rgb888` say about embedded-graphics.
#[test]
fn rgb565_against_embedded_graphics() {
    use embedded_graphics::pixelcolor::raw::RawU16;
    use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
    let (mut red, mut green) = (Vec::new(), Vec::new());
    for raw in 0..=u16::MAX {
        let ours = rgb565_to_rgb888(raw);
        let theirs = Rgb888::from(Rgb565::from(RawU16::new(raw)));
        let theirs = [theirs.r(), theirs.g(), theirs.b()];
        for k in 0..3 {
            assert!(ours[k].abs_diff(theirs[k]) <= 1, "{raw:#06X}");
        }
        if ours[0] != theirs[0] && !red.contains(&(raw >> 11)) {
            red.push(raw >> 11);
        }
        if ours[1] != theirs[1] && !green.contains(&((raw >> 5) & 63)) {
            green.push((raw >> 5) & 63);
        }
    }
    red.sort();
    green.sort();
    assert_eq!(red, [3, 7, 24, 28]);
    assert_eq!(green, [11, 12, 13, 14, 15, 48, 49, 50, 51, 52]);
    // Blue differs at exactly the red levels.
    for b5 in 0..32u16 {
        let theirs = Rgb888::from(Rgb565::from(RawU16::new(b5))).b();
        assert_eq!(rgb565_to_rgb888(b5)[2] != theirs, red.contains(&b5));
    }
}

#[test]
fn largest_sizes_any_coordinate() {
    // Sides of 2^15 and 2^15 - 1 with the extreme coordinates: no
    // overflow (this runs with overflow checks in debug builds), and
    // the texel and the blend the references give.
    let mut rng = XorShift(0x0BAD_F00D);
    for (w, h) in [
        (MAX_SIDE, 2u32),
        (2, MAX_SIDE),
        (MAX_SIDE - 1, 3),
        (3, MAX_SIDE - 1),
    ] {
        let data: Vec<u8> = (0..w * h).map(|_| rng.next() as u8).collect();
        let packed: Vec<u8> = (0..h * w.div_ceil(2)).map(|_| rng.next() as u8).collect();
        let palette: Vec<u16> = (0..16).map(|_| rng.next() as u16).collect();
        let indexed = Texture::new(
            w,
            h,
            Texels::Indexed4 {
                indices: &packed,
                palette: &palette,
            },
        )
        .unwrap();
        for wrap in WRAPS {
            let t = Texture::new(w, h, Texels::Gray8(&data)).unwrap().wrap(wrap);
            let smooth = t.filter(Filter::Bilinear);
            let raws: Vec<i32> = SPECIAL
                .into_iter()
                .chain((0..40).map(|_| rng.coordinate()))
                .collect();
            for &u in &raws {
                for &v in &raws {
                    let x = nearest_reference(u, w, wrap);
                    let y = nearest_reference(v, h, wrap);
                    assert_eq!(t.sample(fx(u), fx(v)), [data[(y * w + x) as usize]; 3]);
                    let exact = bilinear_reference(&smooth, &data, u, v);
                    let got = smooth.sample(fx(u), fx(v))[0] as f64;
                    assert!((got - exact).abs() < 0.625, "{w}x{h} {wrap:?} ({u}, {v})");
                    let i = indexed.wrap(wrap);
                    assert_eq!(i.sample(fx(u), fx(v)), i.texel(x, y));
                    let _ = i.filter(Filter::Bilinear).sample(fx(u), fx(v));
                }
            }
        }
    }
}

#[test]
fn error_messages() {
    let cases = [
        (
            TextureError::ZeroSize {
                width: 0,
                height: 4,
            },
            "texture size 0x4 has no texels",
        ),
        (
            TextureError::TooLarge {
                width: 40_000,
                height: 4,
            },
            "texture size 40000x4 exceeds the limit of 32768 texels per side",
        ),
        (
            TextureError::LengthMismatch {
                expected: 8,
                actual: 6,
            },
            "texel slice has 6 elements, but the size needs 8 (stride x height)",
        ),
        (
            TextureError::PaletteSize { len: 17, max: 16 },
            "palette has 17 colours, but the format needs 1 to 16",
        ),
        (
            TextureError::IndexOutOfRange {
                x: 1,
                y: 2,
                index: 9,
                palette_len: 4,
            },
            "texel (1, 2) has palette index 9, but the palette has 4 colours",
        ),
    ];
    for (error, text) in cases {
        assert_eq!(error.to_string(), text);
    }
}

#[test]
fn errors() {
    static G: [u8; 6] = [0; 6];
    static C: [u16; 6] = [0; 6];
    let gray = Texels::Gray8(&G);
    assert_eq!(
        Texture::new(0, 3, gray).unwrap_err(),
        TextureError::ZeroSize {
            width: 0,
            height: 3
        }
    );
    assert_eq!(
        Texture::new(3, 0, gray).unwrap_err(),
        TextureError::ZeroSize {
            width: 3,
            height: 0
        }
    );
    assert_eq!(
        Texture::new(MAX_SIDE + 1, 1, gray).unwrap_err(),
        TextureError::TooLarge {
            width: MAX_SIDE + 1,
            height: 1
        }
    );
    assert_eq!(
        Texture::new(1, u32::MAX, gray).unwrap_err(),
        TextureError::TooLarge {
            width: 1,
            height: u32::MAX
        }
    );
    assert_eq!(
        Texture::new(2, 2, gray).unwrap_err(),
        TextureError::LengthMismatch {
            expected: 4,
            actual: 6
        }
    );
    assert_eq!(
        Texture::new(7, 1, Texels::Rgb565(&C)).unwrap_err(),
        TextureError::LengthMismatch {
            expected: 7,
            actual: 6
        }
    );
    assert!(Texture::new(3, 2, Texels::Rgb565(&C)).is_ok());
    // Indexed4 needs (width + 1) / 2 bytes per row: 3x2 needs 4.
    static P: [u16; 2] = [0, 0xFFFF];
    let indexed4 = |i: &'static [u8], p: &'static [u16]| Texels::Indexed4 {
        indices: i,
        palette: p,
    };
    assert_eq!(
        Texture::new(3, 2, indexed4(&G, &P)).unwrap_err(),
        TextureError::LengthMismatch {
            expected: 4,
            actual: 6
        }
    );
    assert!(Texture::new(3, 3, indexed4(&G, &P)).is_ok());
    assert!(Texture::new(4, 3, indexed4(&G, &P)).is_ok());
    // Palette sizes.
    assert_eq!(
        Texture::new(3, 3, indexed4(&G, &[])).unwrap_err(),
        TextureError::PaletteSize { len: 0, max: 16 }
    );
    static P17: [u16; 17] = [0; 17];
    assert_eq!(
        Texture::new(3, 3, indexed4(&G, &P17)).unwrap_err(),
        TextureError::PaletteSize { len: 17, max: 16 }
    );
    let indexed8 = |i: &'static [u8], p: &'static [u16]| Texels::Indexed8 {
        indices: i,
        palette: p,
    };
    assert_eq!(
        Texture::new(3, 2, indexed8(&G, &[])).unwrap_err(),
        TextureError::PaletteSize { len: 0, max: 256 }
    );
    static P257: [u16; 257] = [0; 257];
    assert_eq!(
        Texture::new(3, 2, indexed8(&G, &P257)).unwrap_err(),
        TextureError::PaletteSize { len: 257, max: 256 }
    );
    // Indices past the palette: the first in row order.
    static I8: [u8; 6] = [0, 1, 1, 0, 5, 2];
    assert_eq!(
        Texture::new(3, 2, indexed8(&I8, &P)).unwrap_err(),
        TextureError::IndexOutOfRange {
            x: 1,
            y: 1,
            index: 5,
            palette_len: 2
        }
    );
    static P6: [u16; 6] = [0; 6];
    assert!(Texture::new(3, 2, indexed8(&I8, &P6)).is_ok());
    // Indexed4: padding nibbles (here 0xF) are not checked, and the
    // low nibble of a byte is the right texel.
    static I4: [u8; 4] = [0x10, 0x1F, 0x01, 0x1F];
    assert!(Texture::new(3, 2, indexed4(&I4, &P)).is_ok());
    static I4B: [u8; 4] = [0x10, 0x0F, 0x03, 0x0F];
    assert_eq!(
        Texture::new(3, 2, indexed4(&I4B, &P)).unwrap_err(),
        TextureError::IndexOutOfRange {
            x: 1,
            y: 1,
            index: 3,
            palette_len: 2
        }
    );
}
