//! Fuzz-style property tests: random bytes, OBJ token soups, truncated
//! files and damaged PNGs never panic, and every model that does come out
//! is consistent (indices in range, arrays of matching lengths, groups
//! covering the triangles, clusters obeying the mesh rules, coordinates
//! that fit 16.16, output that parses). Every kind of input is also tried
//! with clustering on.

mod common;

use std::path::Path;

use microraster_import::{
    decode_png, model_to_rust, parse_obj, to_fixed, Fit, IndexWidth, Model, ObjOptions,
    TextureFormat,
};
use proptest::prelude::*;

fn check_model(m: &Model) {
    let n = m.positions.len();
    assert!(n > 0 && n <= m.options.index_width.max_vertices());
    assert!(!m.triangles.is_empty());
    for t in &m.triangles {
        for &i in t {
            assert!((i as usize) < n, "{t:?} of {n}");
        }
    }
    for len in [m.normals.len(), m.uvs.len(), m.colors.len()] {
        assert!(len == 0 || len == n);
    }
    let mut next = 0;
    for g in &m.groups {
        assert_eq!(g.triangles.start, next);
        assert!(!g.triangles.is_empty());
        next = g.triangles.end;
    }
    assert_eq!(next, m.triangles.len());
    for p in &m.positions {
        for &c in p {
            assert!(to_fixed(c as f64).is_some(), "{c}");
        }
    }
    for v in &m.normals {
        let len: f32 = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        assert!((len - 1.0).abs() < 1e-5, "{v:?}");
    }
    assert!(m.scale.is_finite() && m.scale > 0.0);
    assert!(m.sphere.radius.is_finite());
    common::check_clusters(m);
    let text = model_to_rust(m, "fuzz").unwrap();
    let items = common::parse_items(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(
        common::declared_len(&items["FUZZ_POSITIONS"].ty),
        m.positions.len()
    );
    match items.get("FUZZ_CLUSTERS") {
        Some(c) => assert_eq!(common::declared_len(&c.ty), m.clusters.len()),
        None => assert!(m.clusters.is_empty()),
    }
}

/// The defaults, with clusters of at most `max` triangles.
fn clustered(max: usize) -> ObjOptions {
    ObjOptions::default().with_cluster_triangles(max)
}

fn run(source: &str, mtl: Option<&str>, options: &ObjOptions) {
    let result = parse_obj(
        source,
        Path::new("fuzz.obj"),
        |_| mtl.map(str::to_string),
        options,
    );
    match result {
        Ok(m) => {
            check_model(&m);
            for w in &m.warnings {
                assert!(!w.contains(char::is_control), "{w:?}");
            }
        }
        Err(e) => {
            // One line, naming the file: the OBJ or an MTL beside it, and
            // whatever of the file it quotes shown with control characters
            // escaped.
            let s = e.to_string();
            assert!(s.starts_with(&format!("{}", e.path().display())), "{s}");
            assert!(!s.contains(char::is_control), "{s:?}");
        }
    }
}

const KEYWORDS: &[&str] = &[
    "v", "v", "v", "vt", "vn", "f", "f", "f", "o", "g", "usemtl", "mtllib", "s", "l", "vp", "p",
    "#", "\\",
];
const ARGS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "3",
    "4",
    "0.5",
    "-2.5",
    "1e3",
    "5000",
    "1e39",
    "nan",
    "inf",
    "-0",
    "1/1",
    "1//1",
    "1/1/1",
    "-1/-1/-1",
    "2/",
    "-2//-1",
    "/",
    "//",
    "0/0",
    "-9",
    "a",
    "mat",
    "x.mtl",
    "1e-30",
    "3/2/1",
    "99999999999999999999",
    "\\",
];
const MTL: &[&str] = &[
    "newmtl mat\n",
    "newmtl a\n",
    "Kd 1 0 0\n",
    "Kd 0.5\n",
    "Kd nan 1 1\n",
    "Kd 1 2\n",
    "Kd spectral f.spd\n",
    "map_Kd -s 1 1 1 t.png\n",
    "map_Kd\n",
    "map_Kd -o\n",
    "Ka 1 1 1\n",
    "newmtl\n",
    "# c\n",
    "\\\n",
];

fn line() -> impl Strategy<Value = String> {
    (
        prop::sample::select(KEYWORDS),
        prop::collection::vec(prop::sample::select(ARGS), 0..7),
        prop::sample::select(&["\n", "\r\n", " \\\n", "\t\n", "  # c\n"][..]),
    )
        .prop_map(|(k, args, end)| format!("{k} {}{end}", args.join(" ")))
}

fn options() -> impl Strategy<Value = ObjOptions> {
    (
        prop::sample::select(&[Fit::Auto, Fit::Keep, Fit::Unit][..]),
        any::<bool>(),
        any::<bool>(),
        1usize..40,
        prop::sample::select(&[0, 0, 1, 2, 3, 5, 64][..]),
    )
        .prop_map(|(fit, wide, normals, limit, clusters)| {
            ObjOptions::default()
                .with_fit(fit)
                .with_index_width(if wide {
                    IndexWidth::U32
                } else {
                    IndexWidth::U16
                })
                .with_compute_normals(normals)
                .with_max_triangles(limit)
                .with_max_face_corners(limit.max(3))
                .with_max_elements(limit * 2)
                .with_cluster_triangles(clusters)
        })
}

/// Numbers for well-formed statements: small, large, tiny and negative.
const NUMBERS: &[&str] = &[
    "0", "1", "-1", "0.5", "2", "-3.25", "1000", "3000", "1e-3", "7",
];

/// A well-formed statement (faces refer to the first 4 vertices, 2 texture
/// coordinates and 2 normals, or relatively back by up to 3).
fn good_line() -> impl Strategy<Value = String> {
    let number = || prop::sample::select(NUMBERS);
    let index = || prop_oneof![(1i32..=4).boxed(), (-3i32..=-1).boxed()];
    let corner = (index(), 1i32..=2, 1i32..=2);
    prop_oneof![
        3 => (number(), number(), number()).prop_map(|(x, y, z)| format!("v {x} {y} {z}\n")),
        1 => (number(), number(), number(), 0.0f32..=1.0)
            .prop_map(|(x, y, z, c)| format!("v {x} {y} {z} {c} 0.5 1\n")),
        1 => (number(), number()).prop_map(|(u, v)| format!("vt {u} {v}\n")),
        1 => (number(), number(), number()).prop_map(|(x, y, z)| format!("vn {x} {y} {z}\n")),
        6 => (prop::collection::vec(corner, 3..7), 0usize..4).prop_map(|(corners, form)| {
            let c: Vec<String> = corners
                .iter()
                .map(|&(v, t, n)| match form {
                    0 => format!("{v}"),
                    1 => format!("{v}/{t}"),
                    2 => format!("{v}//{n}"),
                    _ => format!("{v}/{t}/{n}"),
                })
                .collect();
            format!("f {}\n", c.join(" "))
        }),
        1 => prop::sample::select(&["o A\n", "g B\n", "g\n", "usemtl mat\n", "usemtl a\n",
            "usemtl none\n", "s 1\n", "# c\n", "\n", "l 1 2\n"][..])
            .prop_map(str::to_string),
    ]
}

const BASE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 1\nvn 0 0 1\nvn 1 0 0\n";

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn well_formed_files_import_consistently(
        lines in prop::collection::vec(good_line(), 1..60),
        options in options(),
    ) {
        let source = format!("mtllib m.mtl\n{BASE}{}f 1 2 3\n", lines.concat());
        let mtl = "newmtl mat\nKd 1 0 0\nnewmtl a\nKd 0.5\nmap_Kd -s 2 2 1 a b.png\n";
        let generous = options
            .clone()
            .with_max_triangles(1000)
            .with_max_elements(1000)
            .with_max_face_corners(8);
        // Always a triangle (the last face), so this imports.
        let m = parse_obj(&source, Path::new("good.obj"), |_| Some(mtl.to_string()), &generous)
            .unwrap_or_else(|e| panic!("{e}\n{source}"));
        check_model(&m);
        // With the random limits, an error or a consistent model.
        run(&source, Some(mtl), &options);
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let text = String::from_utf8_lossy(&bytes);
        run(&text, Some(&text), &ObjOptions::default());
        run(&text, Some(&text), &clustered(2));
    }

    #[test]
    fn token_soups_never_panic(
        lines in prop::collection::vec(line(), 0..40),
        mtl in prop::collection::vec(prop::sample::select(MTL), 0..8),
        options in options(),
    ) {
        let source = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n{}", lines.concat());
        run(&source, Some(&mtl.concat()), &options);
        run(&source, None, &ObjOptions::default());
        run(&source, None, &clustered(1));
    }

    #[test]
    fn free_token_soups_never_panic(
        tokens in prop::collection::vec(
            prop::sample::select(
                [KEYWORDS, ARGS, &[" ", "\n", "\r\n", "\t", "\\\n", "#", "\r", "\u{0}", "\u{1b}", "\u{7f}"]].concat()
            ),
            0..120,
        ),
    ) {
        run(&tokens.join(" "), Some("newmtl mat\nKd 1 1 1\n"), &ObjOptions::default());
        run(&tokens.concat(), None, &ObjOptions::default());
        run(&tokens.join(" "), None, &clustered(3));
    }
}

#[test]
fn truncations_of_valid_files_never_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mtl = std::fs::read_to_string(dir.join("cube.mtl")).unwrap();
    let mut oks = 0;
    for file in ["cube.obj", "colored.obj", "missing_mtl.obj"] {
        let source = std::fs::read_to_string(dir.join(file)).unwrap();
        for cut in (0..=source.len()).filter(|&c| source.is_char_boundary(c)) {
            for options in [ObjOptions::default(), clustered(1), clustered(4)] {
                let result = parse_obj(
                    &source[..cut],
                    Path::new(file),
                    |_| Some(mtl[..cut.min(mtl.len())].to_string()),
                    &options,
                );
                if let Ok(m) = result {
                    check_model(&m);
                    oks += 1;
                }
            }
        }
        // The whole file imports.
        assert!(parse_obj(
            &source,
            Path::new(file),
            |_| Some(mtl.clone()),
            &ObjOptions::default()
        )
        .is_ok());
    }
    assert!(oks > 0);
}

/// Small valid PNGs of several kinds.
fn sample_pngs() -> Vec<Vec<u8>> {
    let encode = |w: u32, h: u32, color, depth, data: &[u8], palette: Option<&[u8]>| {
        let mut out = Vec::new();
        {
            let mut e = png::Encoder::new(&mut out, w, h);
            e.set_color(color);
            e.set_depth(depth);
            if let Some(p) = palette {
                e.set_palette(p.to_vec());
            }
            let mut w = e.write_header().unwrap();
            w.write_image_data(data).unwrap();
        }
        out
    };
    use png::{BitDepth, ColorType};
    vec![
        encode(3, 2, ColorType::Rgb, BitDepth::Eight, &[7; 18], None),
        encode(2, 2, ColorType::Rgba, BitDepth::Sixteen, &[200; 32], None),
        encode(5, 3, ColorType::Grayscale, BitDepth::One, &[0xA5; 3], None),
        encode(
            4,
            2,
            ColorType::Indexed,
            BitDepth::Four,
            &[0x01, 0x10, 0x11, 0x00],
            Some(&[0, 0, 0, 255, 255, 255]),
        ),
    ]
}

/// Recomputes the CRC of every whole chunk, so damage reaches the decoder
/// past the checksum test.
fn fix_crcs(bytes: &mut [u8]) {
    let mut at = 8;
    while at + 12 <= bytes.len() {
        let len =
            u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as usize;
        let Some(end) = (at + 8).checked_add(len) else {
            return;
        };
        if end + 4 > bytes.len() {
            return;
        }
        let crc = common::crc32(&bytes[at + 4..end]);
        bytes[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

fn check_png(bytes: &[u8]) {
    if let Ok(t) = decode_png(bytes, Path::new("f.png")) {
        assert_eq!(t.pixels.len(), t.width as usize * t.height as usize);
        for format in [
            TextureFormat::Rgb565,
            TextureFormat::Gray8,
            TextureFormat::Indexed8,
            TextureFormat::Indexed4,
        ] {
            let _ = t.convert(format);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn damaged_pngs_never_panic(
        which in 0usize..4,
        flips in prop::collection::vec((any::<prop::sample::Index>(), 1u8..=255), 0..6),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
        fix in any::<bool>(),
    ) {
        let mut bytes = sample_pngs().swap_remove(which);
        for (at, mask) in flips {
            let i = at.index(bytes.len());
            bytes[i] ^= mask;
        }
        if truncate {
            bytes.truncate(cut.index(bytes.len() + 1));
        }
        if fix {
            fix_crcs(&mut bytes);
        }
        check_png(&bytes);
    }

    #[test]
    fn random_bytes_are_not_pngs(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let mut with_signature = b"\x89PNG\r\n\x1a\n".to_vec();
        with_signature.extend_from_slice(&bytes);
        check_png(&bytes);
        check_png(&with_signature);
    }
}
