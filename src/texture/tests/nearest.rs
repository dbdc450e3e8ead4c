//! Nearest sampling: hand-checked texels, wrap modes per axis, the fast
//! power-of-two path against the generic one and the reference.

use super::*;

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

/// The sampler's power-of-two `Rgb565` nearest path from the coordinates'
/// fractions to 32 bits (`nearest_fine`: the raw values' low 16 bits on
/// top, any bits below) gives [`Texture::sample`]'s texel, for every
/// shape it takes (two texels wide or more); one texel wide, the texture
/// takes the general path.
#[test]
fn pow2_rgb565_nearest_fine_matches_sample() {
    let mut rng = XorShift(0x1234_5678);
    for lw in 0..=15u32 {
        for lh in [0, 1, 3, 15 - lw.min(14), lw.min(15)] {
            let (w, h) = (1u32 << lw, 1u32 << lh);
            if w * h > 1 << 16 {
                continue;
            }
            let texels: Vec<u16> = (0..w * h).map(|_| rng.next() as u16).collect();
            let t = Texture::new(w, h, Texels::Rgb565(&texels)).unwrap();
            let p = match t.sampler() {
                Sampler::NearestRgb565(p) => p,
                _ => {
                    assert_eq!(w, 1, "{w}x{h} not on the fast path");
                    continue;
                }
            };
            let raws = (0..500)
                .map(|_| (rng.coordinate(), rng.coordinate()))
                .chain(
                    SPECIAL
                        .iter()
                        .flat_map(|&u| SPECIAL.iter().map(move |&v| (u, v))),
                );
            for (u, v) in raws.collect::<Vec<_>>() {
                let (fu, fv) = (
                    (u as u32) << 16 | rng.next() >> 16,
                    (v as u32) << 16 | 0xFFFF,
                );
                let expected = t.sample(fx(u), fx(v));
                assert_eq!(p.nearest(u, v), p.nearest_fine(fu, fv), "{w}x{h} {u} {v}");
                assert_eq!(
                    rgb565_to_rgb888(p.nearest_fine(fu, fv)),
                    expected,
                    "{w}x{h} {u} {v}"
                );
            }
        }
    }
}
