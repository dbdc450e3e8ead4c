//! Texel formats and their expansion, the largest sizes, and malformed
//! textures as typed errors.

use super::*;

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

/// The sampler's kind, decided when a texture is built or its modes set
/// (`Texture::decided`), is the one its texels, sides, filter and wrap
/// modes give, whatever order the modes were set in: the fast loops
/// only for `Rgb565` texels of power-of-two sides repeated on both axes
/// (nearest at least two texels wide).
#[test]
fn sampler_kind_follows_every_setter() {
    let rgb = [0u16; 64];
    let gray = [0u8; 64];
    let wraps = [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat];
    for (w, h) in [(8, 8), (1, 8), (8, 1), (6, 8), (8, 6), (2, 2)] {
        for format in 0..2 {
            let n = (w * h) as usize;
            let texels = if format == 0 {
                Texels::Rgb565(&rgb[..n])
            } else {
                Texels::Gray8(&gray[..n])
            };
            let base = Texture::new(w, h, texels).unwrap();
            for filter in [Filter::Nearest, Filter::Bilinear] {
                for u in wraps {
                    for v in wraps {
                        let fast = format == 0
                            && w.is_power_of_two()
                            && h.is_power_of_two()
                            && u == Wrap::Repeat
                            && v == Wrap::Repeat;
                        let want = match filter {
                            Filter::Bilinear if fast => "bilinear",
                            Filter::Nearest if fast && w > 1 => "nearest",
                            _ => "general",
                        };
                        let kind = |t: &Texture<'_>| match t.sampler() {
                            Sampler::NearestRgb565(_) => "nearest",
                            Sampler::BilinearRgb565(_) => "bilinear",
                            Sampler::General(_) => "general",
                        };
                        let a = base.filter(filter).wrap_uv(u, v);
                        let b = base.wrap_uv(u, v).filter(filter);
                        // Modes set twice: the last setting decides.
                        let c = base
                            .filter(Filter::Bilinear)
                            .wrap(Wrap::Repeat)
                            .filter(filter)
                            .wrap_uv(u, v);
                        for t in [a, b, c] {
                            assert_eq!(kind(&t), want, "{w}x{h} {format} {filter:?} {u:?} {v:?}");
                        }
                    }
                }
            }
        }
    }
}
