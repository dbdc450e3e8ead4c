//! PNG decoding and texture conversion, on PNGs made here with the `png`
//! encoder, with hand-computed Rgb565, Gray8 and palette values.

mod common;

use std::path::{Path, PathBuf};

use common::{declared_len, parse_items};
use microraster_import::{
    decode_png, png_to_rust, texture_to_rust, ErrorKind, Texels, Texture, TextureFormat,
};
use png::{BitDepth, ColorType};

/// A PNG of `width` x `height` with the given raw (packed, big-endian)
/// sample rows.
fn encode(
    width: u32,
    height: u32,
    color: ColorType,
    depth: BitDepth,
    data: &[u8],
    palette: Option<&[u8]>,
    trns: Option<&[u8]>,
) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, width, height);
        e.set_color(color);
        e.set_depth(depth);
        if let Some(p) = palette {
            e.set_palette(p.to_vec());
        }
        if let Some(t) = trns {
            e.set_trns(t.to_vec());
        }
        let mut w = e.write_header().unwrap();
        w.write_image_data(data).unwrap();
    }
    out
}

fn rgb8(width: u32, height: u32, data: &[u8]) -> Vec<u8> {
    encode(
        width,
        height,
        ColorType::Rgb,
        BitDepth::Eight,
        data,
        None,
        None,
    )
}

fn decode(bytes: &[u8]) -> Texture {
    decode_png(bytes, Path::new("t.png")).unwrap_or_else(|e| panic!("{e}"))
}

const RED: u16 = 0xF800;
const GREEN: u16 = 0x07E0;
const BLUE: u16 = 0x001F;

#[test]
fn rgb8_to_rgb565_and_gray8() {
    let t = decode(&rgb8(2, 2, &[255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 64, 32]));
    assert_eq!((t.width, t.height), (2, 2));
    assert_eq!(t.pixels[3], [128 * 257, 64 * 257, 32 * 257, 65535]);
    // (128, 64, 32): 128*31/255 = 15.56 -> 16, 64*63/255 = 15.81 -> 16,
    // 32*31/255 = 3.89 -> 4.
    assert_eq!(
        t.to_rgb565(),
        [RED, GREEN, BLUE, (16 << 11) | (16 << 5) | 4]
    );
    // Rec. 601: 76.245, 149.685, 29.07, and (38272 + 37568 + 3648) / 1000
    // = 79.488.
    assert_eq!(t.to_gray8(), [76, 150, 29, 79]);
    assert!(!t.is_translucent());
    let d = t.convert(TextureFormat::Rgb565).unwrap();
    assert_eq!(d.texels, Texels::U16(t.to_rgb565()));
    assert!(d.palette.is_empty());
    assert_eq!((d.stride(), d.texel_bytes()), (2, 8));
}

#[test]
fn gray_and_gray_alpha() {
    let t = decode(&encode(
        3,
        1,
        ColorType::Grayscale,
        BitDepth::Eight,
        &[0, 100, 255],
        None,
        None,
    ));
    // 100: 12.16 -> 12 of 31, 24.71 -> 25 of 63.
    assert_eq!(t.to_rgb565(), [0, (12 << 11) | (25 << 5) | 12, 0xFFFF]);
    assert_eq!(t.to_gray8(), [0, 100, 255]);

    let t = decode(&encode(
        2,
        1,
        ColorType::GrayscaleAlpha,
        BitDepth::Eight,
        &[200, 255, 50, 0],
        None,
        None,
    ));
    // Alpha is read but not used for the colour.
    assert_eq!(t.pixels[1], [50 * 257, 50 * 257, 50 * 257, 0]);
    assert_eq!(t.to_gray8(), [200, 50]);
    assert!(t.is_translucent());
    assert!(t.convert(TextureFormat::Gray8).unwrap().translucent);
}

#[test]
fn low_bit_depth_gray_is_scaled() {
    // 1-bit: 1 is white. Row of 3 pixels 1, 0, 1 packed as 0b101_00000.
    let t = decode(&encode(
        3,
        1,
        ColorType::Grayscale,
        BitDepth::One,
        &[0b1010_0000],
        None,
        None,
    ));
    assert_eq!(t.to_gray8(), [255, 0, 255]);
    // 2-bit: 0..3 -> 0, 85, 170, 255.
    let t = decode(&encode(
        4,
        1,
        ColorType::Grayscale,
        BitDepth::Two,
        &[0b00_01_10_11],
        None,
        None,
    ));
    assert_eq!(t.to_gray8(), [0, 85, 170, 255]);
}

#[test]
fn rgba8_and_sixteen_bit() {
    let t = decode(&encode(
        1,
        1,
        ColorType::Rgba,
        BitDepth::Eight,
        &[10, 20, 30, 40],
        None,
        None,
    ));
    assert_eq!(t.pixels, [[10 * 257, 20 * 257, 30 * 257, 40 * 257]]);
    assert!(t.is_translucent());

    // 16-bit RGB, big-endian samples, kept exactly.
    let t = decode(&encode(
        2,
        1,
        ColorType::Rgb,
        BitDepth::Sixteen,
        &[
            0x12, 0x34, 0x80, 0x00, 0xFF, 0xFF, 0x00, 0x00, 0x03, 0xE8, 0x80, 0x80,
        ],
        None,
        None,
    ));
    assert_eq!(
        t.pixels,
        [[0x1234, 0x8000, 0xFFFF, 65535], [0, 1000, 0x8080, 65535]]
    );
    // 0x1234 = 4660: *31/65535 = 2.20 -> 2; 0x8000: *63/65535 = 31.50048
    // -> 32; 1000: *63/65535 = 0.96 -> 1; 0x8080: *31/65535 = 15.5 + 1/514
    // -> 16.
    assert_eq!(t.to_rgb565(), [(2 << 11) | (32 << 5) | 31, (1 << 5) | 16]);
    // Gray8 of 16-bit: (299 * 4660 + 587 * 32768 + 114 * 65535) * 255
    // / 65535000 = 108.73 -> 109.
    assert_eq!(t.to_gray8()[0], 109);

    let t = decode(&encode(
        1,
        1,
        ColorType::GrayscaleAlpha,
        BitDepth::Sixteen,
        &[0x80, 0x80, 0xFF, 0xFF],
        None,
        None,
    ));
    assert_eq!(t.to_gray8(), [128]);
    assert!(!t.is_translucent());
}

#[test]
fn palette_images_are_expanded() {
    let palette = [255, 0, 0, 0, 0, 255, 0, 255, 0, 255, 255, 255];
    // 2-bit indices 0, 1, 2, 3, 1 in a row of 5: 0b00_01_10_11, 0b01_000000.
    let t = decode(&encode(
        5,
        1,
        ColorType::Indexed,
        BitDepth::Two,
        &[0b0001_1011, 0b0100_0000],
        Some(&palette),
        None,
    ));
    assert_eq!(t.to_rgb565(), [RED, BLUE, GREEN, 0xFFFF, BLUE]);
    assert!(!t.is_translucent());
    // With tRNS, entry 1 is transparent.
    let t = decode(&encode(
        2,
        1,
        ColorType::Indexed,
        BitDepth::Eight,
        &[0, 1],
        Some(&palette),
        Some(&[255, 0]),
    ));
    assert_eq!(t.pixels[1][3], 0);
    assert!(t.is_translucent());
    assert_eq!(t.to_rgb565(), [RED, BLUE]);
}

#[test]
fn indexed8_palette_in_order_of_first_appearance() {
    let t = decode(&rgb8(
        4,
        1,
        &[0, 0, 255, 255, 0, 0, 0, 0, 255, 255, 255, 255],
    ));
    let d = t.convert(TextureFormat::Indexed8).unwrap();
    assert_eq!(d.palette, [BLUE, RED, 0xFFFF]);
    assert_eq!(d.texels, Texels::U8(vec![0, 1, 0, 2]));
    assert_eq!(d.stride(), 4);
}

#[test]
fn indexed4_packs_two_pixels_per_byte_high_nibble_first() {
    // 3 x 2: A B C / C A B with A red, B green, C blue.
    let (a, b, c) = ([255, 0, 0], [0, 255, 0], [0, 0, 255]);
    let data: Vec<u8> = [a, b, c, c, a, b].concat();
    let d = decode(&rgb8(3, 2, &data))
        .convert(TextureFormat::Indexed4)
        .unwrap();
    assert_eq!(d.palette, [RED, GREEN, BLUE]);
    // Row 0: 0 1 | 2 pad; row 1: 2 0 | 1 pad.
    assert_eq!(d.texels, Texels::U8(vec![0x01, 0x20, 0x20, 0x10]));
    assert_eq!((d.stride(), d.texel_bytes()), (2, 4));
}

/// An 8-bit RGB image of `n` pixels in a row, all of different Rgb565
/// colours.
fn distinct_colours(n: usize) -> Vec<u8> {
    let to8 = |v: usize, max: usize| ((v * 255) as f64 / max as f64).round() as u8;
    let data: Vec<u8> = (0..n)
        .flat_map(|i| [to8(i % 32, 31), to8(i / 32 % 64, 63), to8(i / 2048, 31)])
        .collect();
    rgb8(n as u32, 1, &data)
}

#[test]
fn too_many_colours_for_a_palette() {
    let t = decode(&distinct_colours(17));
    let e = t.convert(TextureFormat::Indexed4).unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::TooManyColors {
            count: 17,
            limit: 16
        }
    ));
    assert_eq!(
        e.to_string(),
        "t.png: image has 17 distinct colours (as Rgb565), more than the 16 of the palette; \
         use --format rgb565 (TextureFormat::Rgb565)"
    );
    assert_eq!(
        t.convert(TextureFormat::Indexed8).unwrap().palette.len(),
        17
    );
    let d = decode(&distinct_colours(16))
        .convert(TextureFormat::Indexed4)
        .unwrap();
    assert_eq!(d.palette.len(), 16);
    // Index i at pixel i: bytes 0x01, 0x23, ..., 0xEF.
    assert_eq!(
        d.texels,
        Texels::U8((0..8).map(|k| ((2 * k) << 4) | (2 * k + 1)).collect())
    );

    let e = decode(&distinct_colours(289))
        .convert(TextureFormat::Indexed8)
        .unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::TooManyColors {
            count: 289,
            limit: 256
        }
    ));
}

/// `png` with its IHDR width and height replaced (and the CRC fixed).
fn with_size(png: &[u8], width: u32, height: u32) -> Vec<u8> {
    let mut out = png.to_vec();
    // Signature (8), length (4), "IHDR" (4), then width and height.
    assert_eq!(&out[12..16], b"IHDR");
    out[16..20].copy_from_slice(&width.to_be_bytes());
    out[20..24].copy_from_slice(&height.to_be_bytes());
    let crc = common::crc32(&out[12..29]);
    out[29..33].copy_from_slice(&crc.to_be_bytes());
    out
}

#[test]
fn bad_sizes_and_data_are_errors_naming_the_file() {
    let good = rgb8(2, 2, &[0; 12]);
    assert!(decode_png(&good, Path::new("t.png")).is_ok());
    // The patched header is still read as before when the size is kept.
    assert!(decode_png(&with_size(&good, 2, 2), Path::new("t.png")).is_ok());
    for (w, h) in [(0, 2), (2, 0), (0, 0), (100_000, 100_000), (2049, 2048)] {
        let e = decode_png(&with_size(&good, w, h), Path::new("dir/big.png")).unwrap_err();
        assert_eq!(e.path(), Path::new("dir/big.png"));
        assert!(
            matches!(
                e.kind(),
                ErrorKind::ImageSize { .. } | ErrorKind::Png { .. }
            ),
            "{w}x{h}: {e}"
        );
    }
    let e = decode_png(&with_size(&good, 2049, 2048), Path::new("a.png")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "a.png: image is 2049x2048; it needs at least one pixel and at most 4194304 pixels"
    );
    // Not a PNG at all.
    let e = decode_png(b"GIF89a...", Path::new("x.png")).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Png { .. }));
    assert!(e.to_string().starts_with("x.png: PNG: "), "{e}");
    // Every truncation that cuts into the image data fails cleanly; only
    // the final IEND chunk (12 bytes) is not needed.
    assert_eq!(&good[good.len() - 8..good.len() - 4], b"IEND");
    let full = decode(&good);
    for len in 0..good.len() {
        match decode_png(&good[..len], Path::new("t.png")) {
            Ok(t) => {
                assert!(len >= good.len() - 12, "truncated to {len} bytes");
                assert_eq!(t, full);
            }
            Err(e) => assert_eq!(e.path(), Path::new("t.png")),
        }
    }
    assert!(decode_png(&good[..good.len() - 13], Path::new("t.png")).is_err());
}

#[test]
fn texture_source_round_trip() {
    let (a, b, c) = ([255, 0, 0], [0, 255, 0], [0, 0, 255]);
    let t = decode(&rgb8(3, 2, &[a, b, c, c, a, b].concat()));
    for format in [
        TextureFormat::Rgb565,
        TextureFormat::Gray8,
        TextureFormat::Indexed8,
        TextureFormat::Indexed4,
    ] {
        let d = t.convert(format).unwrap();
        let text = texture_to_rust(&d, "brickWall").unwrap();
        let items = parse_items(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(items["BRICK_WALL_WIDTH"].value.int(), 3);
        assert_eq!(items["BRICK_WALL_WIDTH"].ty, "u32");
        assert_eq!(items["BRICK_WALL_HEIGHT"].value.int(), 2);
        assert_eq!(items["BRICK_WALL_STRIDE"].value.int(), d.stride() as i64);
        let texels = &items["BRICK_WALL_TEXELS"];
        assert_eq!(declared_len(&texels.ty), texels.value.array().len());
        let read: Vec<i64> = texels.value.array().iter().map(|v| v.int()).collect();
        let expected: Vec<i64> = match &d.texels {
            Texels::U16(v) => {
                assert!(texels.ty.starts_with("[u16;"));
                v.iter().map(|&x| x as i64).collect()
            }
            Texels::U8(v) => {
                assert!(texels.ty.starts_with("[u8;"));
                v.iter().map(|&x| x as i64).collect()
            }
        };
        assert_eq!(read, expected, "{format:?}");
        match items.get("BRICK_WALL_PALETTE") {
            Some(p) => {
                assert_eq!(p.ty, format!("[u16; {}]", d.palette.len()));
                let read: Vec<u16> = p.value.array().iter().map(|v| v.int() as u16).collect();
                assert_eq!(read, d.palette);
                assert_eq!(read, [RED, GREEN, BLUE]);
            }
            None => assert!(d.palette.is_empty()),
        }
        assert_eq!(items.len(), if d.palette.is_empty() { 4 } else { 5 });
        assert!(text.contains(&format!("format {}", format.name())));
    }
}

#[test]
fn png_to_rust_writes_atomically() {
    let dir = std::env::temp_dir().join(format!("mri-png-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("tile.png");
    std::fs::write(&png, distinct_colours(20)).unwrap();
    let out = dir.join("tile.rs");
    let s = png_to_rust(&png, &out, "tile", TextureFormat::Indexed8).unwrap();
    assert_eq!(
        (s.width, s.height, s.palette, s.bytes),
        (20, 1, 20, 20 + 40)
    );
    assert_eq!(s.files, std::slice::from_ref(&png));
    assert_eq!(s.to_string(), "20x1 indexed8, 60 bytes, 20 palette colours");
    assert_eq!(
        s.rerun_if_changed(),
        format!("cargo:rerun-if-changed={}\n", png.display())
    );
    let first = std::fs::read_to_string(&out).unwrap();
    assert!(first.contains("pub static TILE_PALETTE: [u16; 20]"));

    // Too many colours for indexed4: an error, and the old output stays.
    let e = png_to_rust(&png, &out, "tile", TextureFormat::Indexed4).unwrap_err();
    assert_eq!(e.path(), png);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), first);
    // A missing input names itself.
    let e = png_to_rust(dir.join("none.png"), &out, "tile", TextureFormat::Gray8).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Io(_)));
    assert_eq!(e.path(), dir.join("none.png"));
    let names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
