//! OBJ/MTL parsing: every face form, triangulation, groups, materials,
//! normals, de-duplication, fitting, and every error with its line.

mod common;

use std::path::{Path, PathBuf};

use microraster_import::{
    load_obj, parse_obj, triangulate, ErrorKind, Fit, ImportError, IndexWidth, Model, ObjOptions,
};

fn parse_with(source: &str, options: &ObjOptions) -> Result<Model, ImportError> {
    parse_obj(source, Path::new("test.obj"), |_| None, options)
}

fn parse(source: &str) -> Model {
    parse_with(source, &ObjOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn parse_err(source: &str) -> ImportError {
    parse_with(source, &ObjOptions::default()).expect_err("expected an error")
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [
        a[0] as f64 - b[0] as f64,
        a[1] as f64 - b[1] as f64,
        a[2] as f64 - b[2] as f64,
    ]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Twice each triangle's area vector (its normal times twice its area).
fn area_vectors(m: &Model) -> Vec<[f64; 3]> {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            cross(sub(b, a), sub(c, a))
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * (1.0 + a.abs().max(b.abs()))
}

fn close3(a: [f32; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| close(a[k] as f64, b[k]))
}

/// The index of the vertex at `p`.
fn vertex_at(m: &Model, p: [f32; 3]) -> usize {
    m.positions
        .iter()
        .position(|&q| q == p)
        .unwrap_or_else(|| panic!("no vertex at {p:?}"))
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn face_form_position_only() {
    let m = parse(&format!("{TRIANGLE}f 1 2 3\n"));
    assert_eq!(
        m.positions,
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(m.triangles, [[0, 1, 2]]);
    assert!(m.uvs.is_empty());
    assert!(m.colors.is_empty());
    // Computed: the triangle faces +z.
    assert_eq!(m.normals, [[0.0, 0.0, 1.0]; 3]);
    assert_eq!(m.fit_applied, Fit::Keep);
    assert_eq!((m.offset, m.scale), ([0.0; 3], 1.0));
}

#[test]
fn face_form_with_texture_coordinates() {
    let m = parse(&format!(
        "{TRIANGLE}vt 0.25 0.5\nvt 0.75 0.5 0.9\nvt 0.5\nf 1/3 2/1 3/2\n"
    ));
    assert_eq!(m.uvs, [[0.5, 0.0], [0.25, 0.5], [0.75, 0.5]]);
    assert_eq!(m.normals.len(), 3);
}

#[test]
fn face_form_with_normals() {
    // Normals are normalised and used as given (not recomputed).
    let m = parse(&format!("{TRIANGLE}vn 0 0 2\nvn 0 3 4\nf 1//2 2//1 3//2\n"));
    assert_eq!(
        m.normals,
        [[0.0, 0.6, 0.8], [0.0, 0.0, 1.0], [0.0, 0.6, 0.8]]
    );
    assert!(m.uvs.is_empty());
}

#[test]
fn face_form_with_everything() {
    let m = parse(&format!(
        "{TRIANGLE}vt 0 0\nvt 1 0\nvt 0 1\nvn 1 0 0\nf 1/1/1 2/2/1 3/3/1\n"
    ));
    assert_eq!(m.uvs, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    assert_eq!(m.normals, [[1.0, 0.0, 0.0]; 3]);
    assert_eq!(m.triangles, [[0, 1, 2]]);
}

#[test]
fn empty_texture_part_means_absent() {
    // `1/` is read like `1`.
    let m = parse(&format!("{TRIANGLE}f 1/ 2/ 3/\n"));
    assert_eq!(m.triangles.len(), 1);
    assert!(m.uvs.is_empty());
}

#[test]
fn negative_indices_are_relative() {
    let absolute = parse(&format!(
        "{TRIANGLE}v 1 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\nf 2/1/1 4/2/1 3/2/1\n"
    ));
    let relative = parse(&format!(
        "{TRIANGLE}v 1 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\nf -3/-2/-1 -1/-1/-1 -2/-1/-1\n"
    ));
    assert_eq!(absolute, relative);
    assert_eq!(
        relative.positions,
        [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
    );
    // Relative to the vertices defined so far, not to the whole file.
    let m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf -3 -2 -1\n");
    assert_eq!(m.triangles, [[0, 1, 2], [3, 4, 5]]);
    assert_eq!(m.positions[3], [5.0, 5.0, 5.0]);
}

fn total_area(m: &Model) -> f64 {
    area_vectors(m)
        .iter()
        .map(|a| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() / 2.0)
        .sum()
}

/// Every triangle turns the same way as `normal`.
fn all_facing(m: &Model, normal: [f64; 3]) -> bool {
    area_vectors(m)
        .iter()
        .all(|a| a[0] * normal[0] + a[1] * normal[1] + a[2] * normal[2] > 0.0)
}

#[test]
fn quad_is_two_triangles_of_its_area() {
    let m = parse("v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nf 1 2 3 4\n");
    assert_eq!(m.triangles.len(), 2);
    assert!(close(total_area(&m), 6.0));
    assert!(all_facing(&m, [0.0, 0.0, 1.0]));
}

#[test]
fn regular_hexagon_is_four_triangles_of_its_area() {
    let mut src = String::new();
    for k in 0..6 {
        let a = k as f64 * std::f64::consts::PI / 3.0;
        src += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    src += "f 1 2 3 4 5 6\n";
    let m = parse(&src);
    assert_eq!(m.triangles.len(), 4);
    assert!(close(total_area(&m), 3.0 * 3f64.sqrt() / 2.0));
    assert!(all_facing(&m, [0.0, 0.0, 1.0]));
}

#[test]
fn concave_polygon_is_ear_clipped_in_its_plane() {
    // An L shape in the x-z plane, wound clockwise seen from +y (its normal
    // is -y), starting next to the reflex corner (1, 1), where a fan's
    // first triangle would fill the notch: the triangles must cover exactly
    // its area of 3, all facing -y.
    let m = parse("v 2 5 1\nv 1 5 1\nv 1 5 2\nv 0 5 2\nv 0 5 0\nv 2 5 0\nf 1 2 3 4 5 6\n");
    assert_eq!(m.triangles.len(), 4);
    assert!(close(total_area(&m), 3.0));
    assert!(all_facing(&m, [0.0, -1.0, 0.0]));
}

#[test]
fn tilted_concave_polygon() {
    // An arrow head (concave at corner 3) tilted out of every axis plane.
    let flat = [[0.0, 0.0], [4.0, 2.0], [0.0, 4.0], [1.0, 2.0]];
    let place = |[x, y]: [f64; 2]| [x, y * 0.6, y * 0.8 + x * 0.1];
    let mut src = String::new();
    for p in flat {
        let [x, y, z] = place(p);
        src += &format!("v {x} {y} {z}\n");
    }
    src += "f 4 1 2 3\n";
    let m = parse(&src);
    assert_eq!(m.triangles.len(), 2);
    // Area in the plane: the quadrilateral's shoelace area is 4; the plane
    // is sheared (x also moves z), so compare with the exact 3D area.
    let e1 = sub(
        place(flat[1]).map(|x| x as f32),
        place(flat[0]).map(|x| x as f32),
    );
    let e2 = sub(
        place(flat[2]).map(|x| x as f32),
        place(flat[0]).map(|x| x as f32),
    );
    let n = cross(e1, e2);
    let big = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0; // the triangle 1 2 3
                                                                      // Less the notch triangle 1 4 3: 2 of the big one's 8 in 2D, and the
                                                                      // placement is linear, so the ratio holds in 3D.
    assert!(close(total_area(&m), big * 0.75));
    assert!(all_facing(&m, n));
}

#[test]
fn triangulate_direct() {
    // Convex, clockwise and counter-clockwise, and the fan fallback.
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(triangulate(&square).len(), 2);
    let mut cw = square;
    cw.reverse();
    assert_eq!(triangulate(&cw).len(), 2);
    assert_eq!(triangulate(&square[..3]), [[0, 1, 2]]);
    assert!(triangulate(&square[..2]).is_empty());
    // No area at all: a fan, which the importer then drops.
    let line = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
    ];
    assert_eq!(triangulate(&line), [[0, 1, 2], [0, 2, 3]]);
    // Self-intersecting (a bow tie) still gives n - 2 triangles.
    let bow = [
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(triangulate(&bow).len(), 2);
    // Non-finite input does not panic.
    let bad = [
        [f64::NAN, 0.0, 0.0],
        [1.0, f64::INFINITY, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(triangulate(&bad).len(), 2);
}

#[test]
fn degenerate_faces_are_dropped_and_counted() {
    let m = parse(
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n\
         f 1 2 3\n\
         f 1 1 4\n\
         f 1 2 4\n\
         f 1 2 3 2\n",
    );
    assert_eq!(m.triangles.len(), 1);
    assert_eq!(m.degenerate, 4);
    assert!(m
        .warnings
        .iter()
        .any(|w| w.contains("dropped 4 degenerate")));
    // Unused vertices are not output: vertex 3 only appears in dropped faces.
    assert_eq!(m.positions.len(), 3);

    let e = parse_err("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n");
    assert!(matches!(e.kind(), ErrorKind::NoTriangles { degenerate: 2 }));
    assert_eq!(e.line(), None);
    assert_eq!(
        e.to_string(),
        "test.obj: no triangles to draw (2 degenerate triangles dropped)"
    );
    let e = parse_err("v 0 0 0\n# nothing else\n");
    assert_eq!(
        e.to_string(),
        "test.obj: no triangles to draw (0 degenerate triangles dropped)"
    );
}

#[test]
fn groups_are_contiguous_named_and_merged() {
    let m = parse(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         f 1 2 3\n\
         o Empty\n\
         g Body\n\
         f 2 4 3\n\
         g Wing\n\
         f 1 2 3\nf 1 2 4\n\
         g Body\n\
         f 1 2 4\n\
         g\n\
         f 3 2 4\n",
    );
    let names: Vec<&str> = m.groups.iter().map(|g| g.name.as_str()).collect();
    // `default` comes back for the nameless `g` and merges with the first.
    assert_eq!(names, ["default", "Body", "Wing"]);
    let ranges: Vec<_> = m.groups.iter().map(|g| g.triangles.clone()).collect();
    assert_eq!(ranges, [0..2, 2..4, 4..6]);
    assert!(m.groups.iter().all(|g| g.material.is_none()));
    // Triangles keep their own vertices: Body's second triangle is 1 2 4.
    let body: Vec<[f32; 3]> = m.triangles[3]
        .iter()
        .map(|&i| m.positions[i as usize])
        .collect();
    assert_eq!(body, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]);
}

#[test]
fn materials_split_groups_and_come_from_the_mtl() {
    let obj = "mtllib mats.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
               g Hull\nusemtl red\nf 1 2 3\nusemtl grey\nf 2 4 3\n\
               g Deck\nf 1 2 4\nusemtl red\nf 1 4 3\n";
    let mtl = "newmtl red\r\nKd 1 0 0\r\n\
               newmtl grey\nKd 0.5\nmap_Kd -o 0.5 0.5 -bm 0.2 -mm 0 1 deck wood.png\n";
    let mut asked = Vec::new();
    let m = parse_obj(
        obj,
        Path::new("models/ship.obj"),
        |name| {
            asked.push(name.to_string());
            (name == "mats.mtl").then(|| mtl.to_string())
        },
        &ObjOptions::default(),
    )
    .unwrap();
    assert_eq!(asked, ["mats.mtl"]);
    assert_eq!(
        m.files,
        [
            PathBuf::from("models/ship.obj"),
            PathBuf::from("models/mats.mtl")
        ]
    );
    type Row<'a> = (&'a str, &'a str, [f32; 3], Option<&'a str>, usize);
    let summary: Vec<Row> = m
        .groups
        .iter()
        .map(|g| {
            let mat = g.material.as_ref().unwrap();
            (
                g.name.as_str(),
                mat.name.as_str(),
                mat.diffuse,
                mat.texture.as_deref(),
                g.triangles.len(),
            )
        })
        .collect();
    assert_eq!(
        summary,
        [
            ("Hull", "red", [1.0, 0.0, 0.0], None, 1),
            ("Hull", "grey", [0.5; 3], Some("deck wood.png"), 1),
            ("Deck", "grey", [0.5; 3], Some("deck wood.png"), 1),
            ("Deck", "red", [1.0, 0.0, 0.0], None, 1),
        ]
    );
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

#[test]
fn missing_material_library_is_a_warning() {
    let m = parse("mtllib gone.mtl\nusemtl paint\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let mat = m.groups[0].material.as_ref().unwrap();
    assert_eq!((mat.name.as_str(), mat.diffuse), ("paint", [1.0; 3]));
    assert_eq!(
        m.warnings,
        [
            "material library `gone.mtl` not found; its materials are white",
            "material `paint` is not defined; it is white",
        ]
    );
    assert_eq!(m.files, [PathBuf::from("test.obj")]);
}

#[test]
fn material_library_names_with_spaces_or_several() {
    let mut asked = Vec::new();
    let m = parse_obj(
        "mtllib a.mtl b.mtl\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        Path::new("t.obj"),
        |name| {
            asked.push(name.to_string());
            (name == "b.mtl").then(|| "newmtl x\nKd 0 0 1\n".to_string())
        },
        &ObjOptions::default(),
    )
    .unwrap();
    assert_eq!(asked, ["a.mtl b.mtl", "a.mtl", "b.mtl"]);
    assert_eq!(
        m.groups[0].material.as_ref().unwrap().diffuse,
        [0.0, 0.0, 1.0]
    );
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
}

#[test]
fn mtl_statement_before_newmtl_is_a_warning_and_bad_kd_an_error() {
    let load = |mtl: &'static str| {
        parse_obj(
            "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            Path::new("dir/t.obj"),
            move |_| Some(mtl.to_string()),
            &ObjOptions::default(),
        )
    };
    let m = load("Kd 1 1 1\nnewmtl a\nKd spectral x.spd\n").unwrap();
    assert_eq!(
        m.warnings,
        [
            "dir/m.mtl:1: `Kd` before any `newmtl` ignored",
            "dir/m.mtl:3: `Kd spectral` is not supported; the colour stays white",
        ]
    );
    let e = load("newmtl a\n\nKd 1 0\n").unwrap_err();
    assert_eq!(e.path(), Path::new("dir/m.mtl"));
    assert_eq!(e.line(), Some(3));
    assert_eq!(
        e.to_string(),
        "dir/m.mtl:3: malformed `Kd` statement: expected r g b; found 2 values"
    );
    let e = load("newmtl a\nKd 1 nan 0\n").unwrap_err();
    assert_eq!(
        e.to_string(),
        "dir/m.mtl:2: number `nan` is not finite (NaN, infinite or beyond f32)"
    );
}

#[test]
fn load_obj_reads_the_mtl_next_to_it() {
    let path = data("cube.obj");
    let m = load_obj(&path, &ObjOptions::default()).unwrap();
    assert_eq!(m.files, [path.clone(), data("cube.mtl")]);
    assert_eq!(m.positions.len(), 24);
    assert_eq!(m.triangles.len(), 12);
    assert_eq!(m.groups.len(), 2);
    let red = m.groups[0].material.as_ref().unwrap();
    let crate_ = m.groups[1].material.as_ref().unwrap();
    assert_eq!(
        (red.name.as_str(), red.diffuse, &red.texture),
        ("red", [1.0, 0.0, 0.0], &None)
    );
    assert_eq!(crate_.diffuse, [0.5; 3]);
    assert_eq!(crate_.texture.as_deref(), Some("crate.png"));
    assert_eq!(
        (m.groups[0].triangles.clone(), m.groups[1].triangles.clone()),
        (0..8, 8..12)
    );
    assert!(m.groups.iter().all(|g| g.name == "Cube"));
    // Every vertex's normal is its face's: perpendicular to its triangles.
    for (t, a) in m.triangles.iter().zip(area_vectors(&m)) {
        for &i in t {
            let n = m.normals[i as usize];
            let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            assert!(close3(n, a.map(|x| x / len)), "{n:?} vs {a:?}");
        }
    }
    assert_eq!(m.warnings, ["ignored 1 `s` statement(s)"]);
    assert_eq!(m.uvs.len(), 24);
}

#[test]
fn load_obj_with_a_missing_mtl_warns() {
    let m = load_obj(&data("missing_mtl.obj"), &ObjOptions::default()).unwrap();
    assert_eq!(m.files, [data("missing_mtl.obj")]);
    assert_eq!(m.warnings.len(), 2);
    assert!(m.warnings[0].contains("`nowhere.mtl` not found"));
}

#[test]
fn load_obj_from_a_temporary_directory() {
    let dir = std::env::temp_dir().join(format!("mri-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("t.obj"),
        "mtllib t.mtl\nusemtl green\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.join("t.mtl"), "newmtl green\nKd 0 1 0\n").unwrap();
    let m = load_obj(&dir.join("t.obj"), &ObjOptions::default()).unwrap();
    assert_eq!(
        m.groups[0].material.as_ref().unwrap().diffuse,
        [0.0, 1.0, 0.0]
    );
    assert_eq!(m.files, [dir.join("t.obj"), dir.join("t.mtl")]);

    // An MTL that exists but cannot be read (a directory) is an error.
    std::fs::remove_file(dir.join("t.mtl")).unwrap();
    std::fs::create_dir_all(dir.join("t.mtl")).unwrap();
    let e = load_obj(&dir.join("t.obj"), &ObjOptions::default()).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Io(_)));
    assert_eq!(e.path(), dir.join("t.mtl"));
    assert!(std::error::Error::source(&e).is_some());
    std::fs::remove_dir_all(&dir).unwrap();
}

const OUTSIDE: &str = "is outside the model's folder; \
                       allow it with ObjOptions::with_outside_files (--allow-outside-files)";

#[test]
fn material_libraries_outside_the_models_folder_are_refused() {
    let allowed = ObjOptions::default().with_outside_files(true);
    for name in [
        "../../../../etc/passwd",
        "/etc/passwd",
        "sub/../../m.mtl",
        "..\\m.mtl",
        "C:\\m.mtl",
    ] {
        let obj = format!("mtllib {name}\nusemtl red\n{TRIANGLE}f 1 2 3\n");
        let import = |options: &ObjOptions| {
            let mut asked = Vec::new();
            let loader = |n: &str| {
                asked.push(n.to_string());
                Some("newmtl red\nKd 1 0 0\n".to_string())
            };
            let m = parse_obj(&obj, Path::new("m/t.obj"), loader, options)
                .unwrap_or_else(|e| panic!("{e}"));
            (m, asked)
        };
        let (m, asked) = import(&ObjOptions::default());
        assert!(asked.is_empty(), "{name}: {asked:?}");
        assert_eq!(m.files, [PathBuf::from("m/t.obj")], "{name}");
        assert_eq!(
            m.warnings,
            [
                format!("m/t.obj:1: material library `{name}` {OUTSIDE}; not read"),
                "material `red` is not defined; it is white".to_string(),
            ]
        );
        // Allowed, it is read as before.
        let (m, asked) = import(&allowed);
        assert_eq!(asked, [name], "{name}");
        assert_eq!(
            m.groups[0].material.as_ref().unwrap().diffuse,
            [1.0, 0.0, 0.0]
        );
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    }
    // `..` that stays inside is fine.
    let mut asked = Vec::new();
    parse_obj(
        &format!("mtllib sub/../a.mtl ./b.mtl\n{TRIANGLE}f 1 2 3\n"),
        Path::new("t.obj"),
        |n| {
            asked.push(n.to_string());
            None
        },
        &ObjOptions::default(),
    )
    .unwrap();
    assert_eq!(asked, ["sub/../a.mtl ./b.mtl", "sub/../a.mtl", "./b.mtl"]);
}

#[test]
fn textures_outside_the_models_folder_are_refused() {
    let obj = format!("mtllib mats/m.mtl\nusemtl a\n{TRIANGLE}f 1 2 3\nusemtl b\nf 3 2 1\n");
    let mtl = "newmtl a\nmap_Kd -s 1 1 1 ../tex/a.png\nnewmtl b\nmap_Kd ../../b.png\n";
    let load = |options: &ObjOptions| {
        parse_obj(&obj, Path::new("t.obj"), |_| Some(mtl.to_string()), options).unwrap()
    };
    let textures = |m: &Model| -> Vec<Option<String>> {
        m.groups
            .iter()
            .map(|g| g.material.as_ref().unwrap().texture.clone())
            .collect()
    };
    // `mats/../tex/a.png` is inside, `mats/../../b.png` is not.
    let m = load(&ObjOptions::default());
    assert_eq!(textures(&m), [Some("../tex/a.png".to_string()), None]);
    assert_eq!(
        m.warnings,
        [format!(
            "mats/m.mtl:4: texture `../../b.png` {OUTSIDE}; dropped"
        )]
    );
    let m = load(&ObjOptions::default().with_outside_files(true));
    assert_eq!(
        textures(&m),
        [
            Some("../tex/a.png".to_string()),
            Some("../../b.png".to_string())
        ]
    );
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

#[test]
fn load_obj_reads_a_library_outside_its_folder_only_when_allowed() {
    let dir = std::env::temp_dir().join(format!("mri-outside-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("model")).unwrap();
    let obj = dir.join("model/t.obj");
    std::fs::write(
        &obj,
        format!("mtllib ../up.mtl\nusemtl g\n{TRIANGLE}f 1 2 3\n"),
    )
    .unwrap();
    std::fs::write(dir.join("up.mtl"), "newmtl g\nKd 0 1 0\n").unwrap();
    let m = load_obj(&obj, &ObjOptions::default()).unwrap();
    assert_eq!(m.files.len(), 1);
    assert_eq!(m.groups[0].material.as_ref().unwrap().diffuse, [1.0; 3]);
    assert!(
        m.warnings[0].contains("`../up.mtl` is outside"),
        "{:?}",
        m.warnings
    );
    let m = load_obj(&obj, &ObjOptions::default().with_outside_files(true)).unwrap();
    assert_eq!(m.files, [obj.clone(), dir.join("model/../up.mtl")]);
    assert_eq!(
        m.groups[0].material.as_ref().unwrap().diffuse,
        [0.0, 1.0, 0.0]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unreadable_obj_is_an_io_error_naming_it() {
    let path = data("does_not_exist.obj");
    let e = load_obj(&path, &ObjOptions::default()).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Io(io) if io.kind() == std::io::ErrorKind::NotFound));
    assert_eq!(e.line(), None);
    assert!(e.to_string().starts_with(&format!("{}: ", path.display())));
}

#[test]
fn crlf_tabs_comments_trailing_space_and_continuations() {
    let plain = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
    let messy = parse(
        "# header\r\n\
         v\t0 0 0   \r\n\
         \r\n\
         v 1 \\\r\n   0 0 # continued\r\n\
         v 0 1 0 # a comment\\\r\n\
         \t  v 1 1 0\t\r\n\
         f 1 2 \\\n\
         4 3",
    );
    assert_eq!(plain, messy);
    // Lines are counted physically: the error is on the 4th line, after a
    // two-line statement.
    let e = parse_err("v 0 0 \\\r\n 0\r\nv 1 0 0\r\nv 1 x 0\r\n");
    assert_eq!(e.line(), Some(4));
    assert_eq!(
        e.to_string(),
        "test.obj:4: malformed `v` statement: expected a number, found `x`"
    );
}

#[test]
fn a_leading_byte_order_mark_is_skipped() {
    // Editors on Windows often save with a UTF-8 BOM. Read as part of the
    // first keyword, it turned the first `v` into an ignored statement and
    // shifted every index after it.
    let src = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf -4 -3 -1 -2\n";
    let with_bom = parse(&format!("\u{FEFF}{src}"));
    assert_eq!(with_bom, parse(src));
    assert_eq!(with_bom.positions.len(), 4);
    assert!(with_bom.warnings.is_empty(), "{:?}", with_bom.warnings);
    // Only at the very start: anywhere else it is not whitespace.
    let e = parse_err("v 0 0 0\nv 1 0 \u{FEFF}0\n");
    assert_eq!(e.line(), Some(2));

    // The files on disk, an MTL with a BOM too.
    let dir = std::env::temp_dir().join(format!("mri-bom-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bom = "\u{FEFF}";
    std::fs::write(
        dir.join("b.obj"),
        format!("{bom}v 0 0 0\nmtllib b.mtl\nusemtl red\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    )
    .unwrap();
    std::fs::write(dir.join("b.mtl"), format!("{bom}newmtl red\nKd 1 0 0\n")).unwrap();
    let m = load_obj(&dir.join("b.obj"), &ObjOptions::default()).unwrap();
    assert_eq!(
        m.positions,
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    let red = m.groups[0].material.as_ref().unwrap();
    assert_eq!(red.diffuse, [1.0, 0.0, 0.0]);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_statements_are_counted() {
    let m = parse(&format!(
        "{TRIANGLE}s 1\nl 1 2\np 1\nvp 0.5\ns off\ncstype bezier\nf 1 2 3\n"
    ));
    assert_eq!(
        m.warnings,
        [
            "ignored 1 `cstype` statement(s)",
            "ignored 1 `l` statement(s)",
            "ignored 1 `p` statement(s)",
            "ignored 2 `s` statement(s)",
            "ignored 1 `vp` statement(s)",
        ]
    );
}

const CUBE_V: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n\
                      v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n";

#[test]
fn shared_corners_are_deduplicated() {
    let m = parse(&format!(
        "{CUBE_V}f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n"
    ));
    assert_eq!(m.positions.len(), 8);
    assert_eq!(m.triangles.len(), 12);
    // Closed and consistently wound: the area vectors cancel out.
    let sum = area_vectors(&m)
        .iter()
        .fold([0.0; 3], |s, a| [s[0] + a[0], s[1] + a[1], s[2] + a[2]]);
    assert_eq!(sum, [0.0; 3]);
    // Outward: each triangle's normal points away from the centre.
    for (t, a) in m.triangles.iter().zip(area_vectors(&m)) {
        let p = m.positions[t[0] as usize];
        assert!(p[0] as f64 * a[0] + p[1] as f64 * a[1] + p[2] as f64 * a[2] > 0.0);
    }
    // Every corner's computed normal points out along its diagonal octant.
    for (p, n) in m.positions.iter().zip(&m.normals) {
        for k in 0..3 {
            assert_eq!(p[k].signum(), n[k].signum(), "{p:?} {n:?}");
        }
        let len: f32 = n.iter().map(|x| x * x).sum();
        assert!((len - 1.0).abs() < 1e-6);
    }

    let m = parse(&format!(
        "{CUBE_V}vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n\
         f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1//3 2//3 6//3 5//3\n\
         f 4//4 8//4 7//4 3//4\nf 1//5 5//5 8//5 4//5\nf 2//6 3//6 7//6 6//6\n"
    ));
    assert_eq!(m.positions.len(), 24);
    assert_eq!(m.triangles.len(), 12);
}

#[test]
fn computed_normals_are_area_weighted() {
    // A tetrahedron on the axes. Face normals times twice the area:
    // (0,0,-1), (0,-1,0), (-1,0,0) and (1,1,1) for the slanted face, so the
    // origin gets -(1,1,1)/√3 and each other corner its own axis, e.g.
    // (0,-1,0) + (0,0,-1) + (1,1,1) = (1,0,0).
    let m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    assert_eq!(m.positions.len(), 4);
    let s = 1.0 / 3f64.sqrt();
    let expect: [([f32; 3], [f64; 3]); 4] = [
        ([0.0, 0.0, 0.0], [-s, -s, -s]),
        ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
    ];
    for (p, n) in expect {
        let got = m.normals[vertex_at(&m, p)];
        assert!(close3(got, n), "{p:?}: {got:?} vs {n:?}");
    }
    // The raw 16.16 bits: 1/√3 = 37837.23 / 65536.
    let fixed = m.normals_fixed();
    assert_eq!(fixed[vertex_at(&m, [0.0; 3])], [-37837; 3]);
    assert_eq!(fixed[vertex_at(&m, [1.0, 0.0, 0.0])], [65536, 0, 0]);

    // Area weighting: a big and a small triangle sharing an edge, folded at
    // 90°; the shared vertices lean towards the big one's normal in the
    // ratio of the areas (4 : 1).
    let m = parse("v 0 0 0\nv 0 1 0\nv 4 0 0\nv 0 0 -1\nf 1 3 2\nf 1 2 4\n");
    let n = m.normals[vertex_at(&m, [0.0, 0.0, 0.0])];
    // Big: (4,0,0)x(0,1,0) = (0,0,4); small: (0,1,0)x(0,0,-1) = (-1,0,0).
    let l = 17f64.sqrt();
    assert!(close3(n, [-1.0 / l, 0.0, 4.0 / l]), "{n:?}");
}

#[test]
fn missing_normals_in_a_normal_carrying_file() {
    // The first face has vn, the second none: its vertices get computed
    // normals, including the shared position 2, which becomes a second
    // vertex.
    let src = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nvn 0 0 1\n\
               f 1//1 2//1 3//1\nf 2 4 3\n";
    let m = parse(src);
    assert_eq!(m.positions.len(), 6);
    assert_eq!(m.normals.len(), 6);
    assert_eq!(m.normals[0], [0.0, 0.0, 1.0]);
    // Computed at position 4, used only by the second face:
    // (0,1,1) x (-1,1,0) = (-1,-1,1).
    let n = m.normals[vertex_at(&m, [1.0, 1.0, 1.0])];
    let s = 1.0 / 3f64.sqrt();
    assert!(close3(n, [-s, -s, s]), "{n:?}");

    // Without computation the partial normals are dropped, with a warning.
    let m = parse_with(src, &ObjOptions::default().with_compute_normals(false)).unwrap();
    assert!(m.normals.is_empty());
    assert!(m.warnings[0].contains("normals dropped"));
    // ...and a file without any vn has none.
    let m = parse_with(
        &format!("{TRIANGLE}f 1 2 3\n"),
        &ObjOptions::default().with_compute_normals(false),
    )
    .unwrap();
    assert!(m.normals.is_empty());
    assert!(m.warnings.is_empty());
}

#[test]
fn vertex_colours() {
    let m = load_obj(&data("colored.obj"), &ObjOptions::default()).unwrap();
    assert_eq!(
        m.colors,
        [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]]
    );
    assert_eq!(m.groups[0].name, "Quad");
    // Uncoloured vertices in a coloured file are white; values are clamped.
    let m = parse("v 0 0 0\nv 1 0 0 0.5 2 -1\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(m.colors, [[255, 255, 255], [128, 255, 0], [255, 255, 255]]);
    assert!(m.warnings[0].contains("2 vertices have no colour"));
}

#[test]
fn partial_texture_coordinates_default_to_zero() {
    let m = parse(&format!(
        "{TRIANGLE}v 1 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\nf 2 4 3\n"
    ));
    assert_eq!(m.uvs.len(), m.positions.len());
    assert_eq!(m.uvs[vertex_at(&m, [1.0, 1.0, 0.0])], [0.0, 0.0]);
    assert_eq!(m.uvs[0], [0.5, 0.5]);
    assert!(m.warnings[0].contains("no `vt`"));
}

#[test]
fn bounds_and_sphere() {
    let m = parse("v -1 0 0\nv 3 0 0\nv 1 2 0\nv 1 0 -4\nf 1 2 3\nf 1 4 2\n");
    assert_eq!(m.bounds.min, [-1.0, 0.0, -4.0]);
    assert_eq!(m.bounds.max, [3.0, 2.0, 0.0]);
    // Centred on the box; the farthest points are (-1,0,0) and (3,0,0), at
    // distance √(4 + 1 + 4) = 3 from (1, 1, -2).
    assert_eq!(m.sphere.center, [1.0, 1.0, -2.0]);
    assert_eq!(m.sphere.radius, 3.0);
    for p in &m.positions {
        let d = sub(*p, m.sphere.center);
        assert!((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() <= m.sphere.radius as f64 + 1e-6);
    }
}

/// Undoing the reported fit gives the file's coordinates back.
fn assert_fit_undoes(m: &Model, original: &[[f64; 3]]) {
    for (p, o) in m.positions.iter().zip(original) {
        for k in 0..3 {
            let back = p[k] as f64 / m.scale - m.offset[k];
            // Positions are f32 within the unit sphere (or kept exactly).
            let tolerance = 2e-7 / m.scale + 1e-12 * o[k].abs();
            assert!((back - o[k]).abs() <= tolerance, "{back} vs {}", o[k]);
        }
    }
}

#[test]
fn fit_modes() {
    let big = "v 10 10 10\nv 2010 10 10\nv 10 1010 10\nf 1 2 3\n";
    let original = [
        [10.0, 10.0, 10.0],
        [2010.0, 10.0, 10.0],
        [10.0, 1010.0, 10.0],
    ];

    // Keep: unchanged.
    let m = parse_with(big, &ObjOptions::default().with_fit(Fit::Keep)).unwrap();
    assert_eq!(
        (m.fit_applied, m.offset, m.scale),
        (Fit::Keep, [0.0; 3], 1.0)
    );
    assert_eq!(m.positions[1], [2010.0, 10.0, 10.0]);
    assert_eq!(m.positions_fixed()[1], [2010 << 16, 10 << 16, 10 << 16]);

    // Unit: box centre (1010, 510, 10) to the origin; radius √(1000² + 500²).
    let m = parse_with(big, &ObjOptions::default().with_fit(Fit::Unit)).unwrap();
    assert_eq!(m.fit_applied, Fit::Unit);
    assert_eq!(m.offset, [-1010.0, -510.0, -10.0]);
    assert!(close(m.scale, 1.0 / 1_250_000f64.sqrt()));
    assert!(close(m.sphere.radius as f64, 1.0));
    assert_eq!(m.sphere.center, [0.0; 3]);
    assert_fit_undoes(&m, &original);

    // Auto: a coordinate beyond 1024 rescales...
    let m = parse(big);
    assert_eq!((m.fit_applied, m.options.fit), (Fit::Unit, Fit::Auto));
    assert_fit_undoes(&m, &original);
    // ...and so does a model too small for 16.16 resolution.
    let tiny = "v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nf 1 2 3\n";
    let m = parse(tiny);
    assert_eq!(m.fit_applied, Fit::Unit);
    assert!(close(m.sphere.radius as f64, 1.0));
    // A moderate model is kept.
    let m = parse("v 0 0 0\nv 1024 0 0\nv 0 0.5 0\nf 1 2 3\n");
    assert_eq!((m.fit_applied, m.scale), (Fit::Keep, 1.0));

    // Keep fails when a coordinate does not fit 16.16.
    let e = parse_with(
        "v 0 0 0\nv 40000 0 0\nv 0 1 0\nf 1 2 3\n",
        &ObjOptions::default().with_fit(Fit::Keep),
    )
    .unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::OutOfFixedRange { what: "position", value } if *value == 40000.0
    ));
    assert_eq!(
        e.to_string(),
        "test.obj: position coordinate 40000 does not fit 16.16 fixed point \
         (-32768 to 32767.99998); use Fit::Unit or Fit::Auto (--fit unit|auto)"
    );
    // A sliver 40,000 long and 0.001 wide rescales to one 5e-8 wide, less
    // than 16.16 resolves: kept, with a warning.
    let m = parse("v 0 0 0\nv 40000 0 0\nv 0 0.001 0\nf 1 2 3\n");
    assert_eq!((m.fit_applied, m.triangles.len()), (Fit::Unit, 1));
    assert_eq!(
        m.warnings,
        ["1 triangle(s) have no area at 16.16 resolution (too small for the model's size)"]
    );
    assert!(parse(TINY_OK).warnings.is_empty());

    // The limits themselves: -32768 fits, 32768 does not.
    assert!(parse_with(
        "v -32768 0 0\nv 32767 0 0\nv 0 1 0\nf 1 2 3\n",
        &ObjOptions::default().with_fit(Fit::Keep)
    )
    .is_ok());
    assert!(parse_with(
        "v -32768 0 0\nv 32768 0 0\nv 0 1 0\nf 1 2 3\n",
        &ObjOptions::default().with_fit(Fit::Keep)
    )
    .is_err());
}

/// A triangle one 16.16 step high: still has an area.
const TINY_OK: &str = "v 0 0 0\nv 1 0 0\nv 0 0.0000153 0\nf 1 2 3\n";

#[test]
fn fixed_point_helpers_round_to_nearest() {
    let m = parse("v 0.5 -0.25 3\nv 1.00001 0 0\nv -1.00001 1 0\nvt 0.1 0.9\nf 1/1 2/1 3/1\n");
    let p = m.positions_fixed();
    assert_eq!(p[0], [32768, -16384, 196608]);
    // 1.00001 * 65536 = 65536.655... (in f32: 65536.656)
    assert_eq!(p[1][0], 65537);
    assert_eq!(p[2][0], -65537);
    // 0.1 * 65536 = 6553.6; v is flipped to 1 - 0.9 = 0.1 (microraster's
    // textures have v = 0 at the top, OBJ at the bottom).
    assert_eq!(m.uvs[0], [0.1, 0.9]);
    assert_eq!(m.uvs_fixed()[0], [6554, 6554]);
}

#[test]
fn u16_index_limit_and_u32() {
    // 21,846 separate triangles: 65,538 unique vertices.
    let n = 21_846;
    let mut src = String::with_capacity(n * 60);
    for i in 0..n {
        let x = (i % 200) as f32;
        let y = (i / 200) as f32;
        src += &format!("v {x} {y} 0\nv {x}.5 {y} 0\nv {x} {y}.5 0\nf -3 -2 -1\n");
    }
    let e = parse_err(&src);
    assert!(matches!(
        e.kind(),
        ErrorKind::TooManyVertices {
            count: 65_538,
            limit: 65_536,
            duplicated: 0
        }
    ));
    assert_eq!(
        e.to_string(),
        "test.obj: model has 65538 unique vertices but u16 indices address only 65536; \
         use 32-bit indices (IndexWidth::U32, --u32) or split the model"
    );
    let m = parse_with(
        &src,
        &ObjOptions::default().with_index_width(IndexWidth::U32),
    )
    .unwrap();
    assert_eq!(m.positions.len(), 65_538);
    assert_eq!(m.triangles[n - 1], [65_535, 65_536, 65_537]);
}

/// The error of `source`, as (line, message).
fn error_of(source: &str, options: &ObjOptions) -> (Option<usize>, String) {
    let e = parse_with(source, options).expect_err(source);
    (e.line(), e.to_string())
}

#[test]
fn every_error_with_its_line_and_message() {
    let d = ObjOptions::default();
    let cases: &[(&str, &ObjOptions, usize, &str)] = &[
        ("v 1 2\n", &d, 1, "malformed `v` statement: expected x y z, x y z w or x y z r g b; found 2 values"),
        ("\nv 1 2 3 4 5\n", &d, 2, "malformed `v` statement: expected x y z, x y z w or x y z r g b; found 5 values"),
        ("v 1 2 abc\n", &d, 1, "malformed `v` statement: expected a number, found `abc`"),
        ("v 1 2 3 w\n", &d, 1, "malformed `v` statement: expected a number, found `w`"),
        ("vt\n", &d, 1, "malformed `vt` statement: expected u, u v or u v w; found 0 values"),
        ("vn 1 0\n", &d, 1, "malformed `vn` statement: expected x y z; found 2 values"),
        ("v 0 0 0\nv nan 0 0\n", &d, 2, "number `nan` is not finite (NaN, infinite or beyond f32)"),
        ("v inf 0 0\n", &d, 1, "number `inf` is not finite (NaN, infinite or beyond f32)"),
        ("vn 0 1e39 0\n", &d, 1, "number `1e39` is not finite (NaN, infinite or beyond f32)"),
        ("vt 40000 0\n", &d, 1, "texture coordinate 40000 does not fit 16.16 fixed point (-32768 to 32767.99998)"),
        (TRIANGLE_F_TWO, &d, 4, "malformed `f` statement: a face needs at least 3 corners, found 2"),
        ("v 0 0 0\nf 1/2/3/4 1 1\n", &d, 2, "malformed `f` statement: too many `/` in corner `1/2/3/4` (expected v, v/vt, v//vn or v/vt/vn)"),
        ("v 0 0 0\nf /1 1 1\n", &d, 2, "malformed `f` statement: no vertex index in corner `/1` (expected v, v/vt, v//vn or v/vt/vn)"),
        ("v 0 0 0\nf 1 1 x\n", &d, 2, "malformed `f` statement: bad index `x` in corner `x` (expected v, v/vt, v//vn or v/vt/vn)"),
        ("v 0 0 0\nf 1 1 99999999999999999999\n", &d, 2, "malformed `f` statement: bad index `99999999999999999999` in corner `99999999999999999999` (expected v, v/vt, v//vn or v/vt/vn)"),
        ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", &d, 3, "vertex index 3 is out of range (2 vertices are defined before this line)"),
        ("v 0 0 0\nf 1 -1 -2\n", &d, 2, "vertex index -2 is out of range (1 vertex is defined before this line)"),
        ("v 0 0 0\nvt 0 0\nf 1/1 1/2 1/1\n", &d, 3, "texture coordinate index 2 is out of range (1 texture coordinate is defined before this line)"),
        ("v 0 0 0\nf 1//1 1//1 1//1\n", &d, 2, "normal index 1 is out of range (0 normals are defined before this line)"),
        ("v 0 0 0\nf 0 1 1\n", &d, 2, "vertex index 0 is invalid (OBJ indices start at 1)"),
        ("v 0 0 0\nvt 0 0\nf 1/0 1/1 1/1\n", &d, 3, "texture coordinate index 0 is invalid (OBJ indices start at 1)"),
        ("v 0 0 0\nvt 0 0\nf 1/1 1 1\n", &d, 3, "face mixes corner forms `1/1` and `1` (all corners need the same v/vt/vn parts)"),
        ("v 0 0 0\nvn 0 0 1\nf 1//1 1/1/1 1//1\n", &d, 3, "face mixes corner forms `1//1` and `1/1/1` (all corners need the same v/vt/vn parts)"),
    ];
    for &(source, options, line, message) in cases {
        let (got_line, got) = error_of(source, options);
        assert_eq!(got_line, Some(line), "{source:?}");
        assert_eq!(got, format!("test.obj:{line}: {message}"), "{source:?}");
    }
}

#[test]
fn control_characters_in_quoted_content_are_escaped() {
    // A NUL inside a number showed as `found `0`` on a terminal.
    let d = ObjOptions::default();
    let cases: &[(&str, usize, &str)] = &[
        ("v 1 2 0\u{0}5\n", 1, "malformed `v` statement: expected a number, found `0\\u{0}5`"),
        ("v 1 2 \u{FEFF}3\n", 1, "malformed `v` statement: expected a number, found `\\u{feff}3`"),
        ("vt 0\u{1b}[31m\n", 1, "malformed `vt` statement: expected a number, found `0\\u{1b}[31m`"),
        ("v 0 0 0\nf 1 1 1\u{7}\n", 2, "malformed `f` statement: bad index `1\\u{7}` in corner `1\\u{7}` (expected v, v/vt, v//vn or v/vt/vn)"),
        ("v 0 0 0\nf 1/\u{0} 1 1\n", 2, "malformed `f` statement: bad index `\\u{0}` in corner `1/\\u{0}` (expected v, v/vt, v//vn or v/vt/vn)"),
    ];
    for &(source, line, message) in cases {
        let (got_line, got) = error_of(source, &d);
        assert_eq!(got_line, Some(line), "{source:?}");
        assert_eq!(got, format!("test.obj:{line}: {message}"), "{source:?}");
    }
    // The error keeps what was written; only its display escapes it.
    let e = parse_err("v 1 2 0\u{0}5\n");
    assert!(
        matches!(e.kind(), ErrorKind::Malformed { message, .. } if message.contains("0\u{0}5")),
        "{e:?}"
    );
    // Paths (an MTL's name comes from the OBJ) and MTL content too.
    let e = parse_obj(
        "mtllib a\u{1}.mtl\nv 0 0 0\n",
        Path::new("dir/t.obj"),
        |_| Some("newmtl a\nKd 1 \u{0} 1\n".to_string()),
        &d,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "dir/a\\u{1}.mtl:2: malformed `Kd` statement: expected a number, found `\\u{0}`"
    );
    // Warnings quote the file as well: unknown keywords, library and
    // material names.
    let m = parse(&format!(
        "{TRIANGLE}x\u{0}y 1\nmtllib m\u{8}.mtl\nusemtl \u{1b}c\nf 1 2 3\n"
    ));
    assert_eq!(
        m.warnings,
        [
            "material library `m\\u{8}.mtl` not found; its materials are white",
            "material `\\u{1b}c` is not defined; it is white",
            "ignored 1 `x\\u{0}y` statement(s)",
        ]
    );
}

const TRIANGLE_F_TWO: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n";

#[test]
fn limits_are_errors_not_allocations() {
    let opts = ObjOptions::default()
        .with_max_elements(3)
        .with_max_triangles(2)
        .with_max_face_corners(4);
    assert_eq!(
        error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n", &opts),
        (
            Some(4),
            "test.obj:4: more than 3 vertex statements (the configured limit)".to_string()
        )
    );
    assert_eq!(
        error_of("vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n", &opts).1,
        "test.obj:4: more than 3 normal statements (the configured limit)"
    );
    assert_eq!(
        error_of("vt 0\nvt 0\nvt 0\nvt 0\n", &opts).1,
        "test.obj:4: more than 3 texture coordinate statements (the configured limit)"
    );
    assert_eq!(
        error_of(&format!("{TRIANGLE}f 1 2 3 1 2\n"), &opts),
        (
            Some(4),
            "test.obj:4: face has 5 corners, more than the limit of 4; \
             raise it with ObjOptions::with_max_face_corners (--max-face-corners N)"
                .to_string()
        )
    );
    assert_eq!(
        error_of(&format!("{TRIANGLE}f 1 2 3\nf 1 2 3\n\nf 3 2 1\n"), &opts),
        (
            Some(7),
            "test.obj:7: more than 2 triangles after triangulation (the configured limit)"
                .to_string()
        )
    );
    // Within the limits it works.
    assert_eq!(
        parse_with(&format!("{TRIANGLE}f 1 2 3\nf 3 2 1\n"), &opts)
            .unwrap()
            .triangles
            .len(),
        2
    );
}

#[test]
fn large_polygons_fall_back_to_a_fan() {
    // A convex 300-gon (more than ear clipping takes): still 298 triangles.
    let src = common::regular_polygon_obj(300);
    let m = parse_with(&src, &ObjOptions::default().with_max_face_corners(300)).unwrap();
    assert_eq!(m.triangles.len(), 298);
    assert!(all_facing(&m, [0.0, 0.0, 1.0]));
    // Only once the limit is raised: by default such a face is an error
    // that says how to allow it.
    let e = parse_with(&src, &ObjOptions::default()).unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::TooManyCorners {
            count: 300,
            limit: 256
        }
    ));
    assert!(e.to_string().contains("--max-face-corners"), "{e}");
}
