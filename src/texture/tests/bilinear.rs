//! Bilinear filtering: the taps and weights against `i64` and `f64`
//! references, hand-checked values, nearest at texel centres.

use super::*;

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

/// The sampler's power-of-two `Rgb565` path, with its four texels kept
/// from one sample to the next, gives [`Texture::sample`]'s colour: along
/// walks in small steps (the texels reused, or one texel over), and after
/// jumps (read anew).
#[test]
fn pow2_rgb565_bilinear_matches_sample() {
    let mut rng = XorShift(0x0BAD_F00D);
    let sizes = [(1, 1), (1, 8), (2, 2), (4, 1), (8, 32), (32, 32), (64, 16)];
    // Random texels, and black and white ones in a checker (the largest
    // differences, of both signs, in every channel).
    for ((w, h), checker) in sizes.into_iter().flat_map(|s| [(s, false), (s, true)]) {
        let texels: Vec<u16> = (0..w * h)
            .map(|i| match checker {
                false => rng.next() as u16,
                true if (i % w + i / w) % 2 == 0 => 0xFFFF,
                true => 0,
            })
            .collect();
        let t = Texture::new(w, h, Texels::Rgb565(&texels))
            .unwrap()
            .filter(Filter::Bilinear);
        let Sampler::BilinearRgb565(p) = t.sampler() else {
            panic!("{w}x{h} not on the fast path");
        };
        let mut quad = Quad::NONE;
        // The 64-bit own loop's blend, on the texels cut to their count.
        #[cfg(target_pointer_width = "64")]
        let (cut, mut packed) = (p.cut().unwrap(), crate::texture::PackedQuad::NONE);
        for _ in 0..200 {
            let (mut u, mut v) = (rng.coordinate(), rng.coordinate());
            let step = [rng.next() as i32 % 3_000, rng.next() as i32 % 3_000];
            for _ in 0..40 {
                let expected = t.sample(fx(u), fx(v));
                assert_eq!(
                    p.bilinear_reusing(u, v, &mut quad),
                    expected,
                    "{w}x{h} {u} {v}"
                );
                assert_eq!(p.bilinear(u, v), expected, "{w}x{h} {u} {v}");
                // From the fractions to 32 bits: the raw values' low 16
                // bits on top, any bits below.
                let (fu, fv) = ((u as u32) << 16 | rng.next() >> 16, (v as u32) << 16);
                assert_eq!(
                    p.bilinear_fine(fu, fv, &mut quad),
                    expected,
                    "{w}x{h} {u} {v}"
                );
                #[cfg(target_pointer_width = "64")]
                assert_eq!(
                    cut.bilinear_packed(fu, fv, &mut packed),
                    expected,
                    "{w}x{h} {u} {v}"
                );
                u = u.wrapping_add(step[0]);
                v = v.wrapping_add(step[1]);
            }
        }
    }
}
