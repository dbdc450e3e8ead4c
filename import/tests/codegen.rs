//! Rust source output: the arrays read back equal the model's fixed-point
//! data exactly, and files are written atomically.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{declared_len, parse_items, Item, Value};
use microraster_import::{
    load_obj, model_to_rust, obj_to_rust, parse_obj, write_atomic, ErrorKind, Fit, IndexWidth,
    Model, ObjOptions,
};

const FX: &str = "::fixed::types::I16F16::from_bits";
const RGB: &str = "::embedded_graphics::pixelcolor::Rgb888::new";

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mri-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The rows of a fixed-point array item, checking its declared length.
fn fixed_rows<const N: usize>(item: &Item) -> Vec<[i32; N]> {
    let rows = item.value.array();
    assert_eq!(declared_len(&item.ty), rows.len(), "{}", item.ty);
    rows.iter()
        .map(|row| {
            let row = row.array();
            assert_eq!(row.len(), N);
            std::array::from_fn(|k| row[k].call(FX)[0].int() as i32)
        })
        .collect()
}

fn int_rows(item: &Item) -> Vec<[u32; 3]> {
    let rows = item.value.array();
    assert_eq!(declared_len(&item.ty), rows.len(), "{}", item.ty);
    rows.iter()
        .map(|row| {
            let row = row.array();
            std::array::from_fn(|k| row[k].int() as u32)
        })
        .collect()
}

fn colors(item: &Item) -> Vec<[u8; 3]> {
    let rows = item.value.array();
    assert_eq!(declared_len(&item.ty), rows.len(), "{}", item.ty);
    rows.iter()
        .map(|c| {
            let args = c.call(RGB);
            std::array::from_fn(|k| u8::try_from(args[k].int()).unwrap())
        })
        .collect()
}

fn f32s(item: &Item) -> Vec<f32> {
    match &item.value {
        Value::Array(v) => v.iter().map(|x| x.float() as f32).collect(),
        v => vec![v.float() as f32],
    }
}

/// Parses `text` and checks every item against `model`.
fn check_round_trip(model: &Model, text: &str, p: &str) -> BTreeMap<String, Item> {
    let items = parse_items(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let get = |name: &str| {
        items
            .get(&format!("{p}_{name}"))
            .unwrap_or_else(|| panic!("no {p}_{name}"))
    };
    let positions = get("POSITIONS");
    assert_eq!(
        positions.ty,
        format!("[[::fixed::types::I16F16; 3]; {}]", model.positions.len())
    );
    assert_eq!(positions.kind, "static");
    assert_eq!(fixed_rows::<3>(positions), model.positions_fixed());
    match items.get(&format!("{p}_NORMALS")) {
        Some(n) => assert_eq!(fixed_rows::<3>(n), model.normals_fixed()),
        None => assert!(model.normals.is_empty()),
    }
    match items.get(&format!("{p}_UVS")) {
        Some(n) => {
            assert_eq!(
                n.ty,
                format!("[[::fixed::types::I16F16; 2]; {}]", model.uvs.len())
            );
            assert_eq!(fixed_rows::<2>(n), model.uvs_fixed());
        }
        None => assert!(model.uvs.is_empty()),
    }
    match items.get(&format!("{p}_COLORS")) {
        Some(c) => assert_eq!(colors(c), model.colors),
        None => assert!(model.colors.is_empty()),
    }
    let triangles = get("TRIANGLES");
    let index = model.options.index_width.rust_type();
    assert_eq!(
        triangles.ty,
        format!("[[{index}; 3]; {}]", model.triangles.len())
    );
    assert_eq!(int_rows(triangles), model.triangles);

    let groups = get("GROUPS");
    assert_eq!(
        groups.ty,
        format!("[(&str, usize, usize); {}]", model.groups.len())
    );
    let read: Vec<(String, usize, usize)> = groups
        .value
        .array()
        .iter()
        .map(|g| match g {
            Value::Tuple(t) => match &t[..] {
                [Value::Str(name), Value::Int(first), Value::Int(count)] => {
                    (name.clone(), *first as usize, *count as usize)
                }
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        })
        .collect();
    let expected: Vec<(String, usize, usize)> = model
        .groups
        .iter()
        .map(|g| (g.name.clone(), g.triangles.start, g.triangles.len()))
        .collect();
    assert_eq!(read, expected);
    let group_colors = colors(get("GROUP_COLORS"));
    let expected: Vec<[u8; 3]> = model
        .groups
        .iter()
        .map(|g| {
            g.material
                .as_ref()
                .map_or([1.0; 3], |m| m.diffuse)
                .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
        })
        .collect();
    assert_eq!(group_colors, expected);
    let textures: Vec<Option<String>> = get("GROUP_TEXTURES")
        .value
        .array()
        .iter()
        .map(|t| match t {
            Value::Path(p) if p == "None" => None,
            Value::Call(p, args) if p == "Some" => match &args[..] {
                [Value::Str(s)] => Some(s.clone()),
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        })
        .collect();
    let expected: Vec<Option<String>> = model
        .groups
        .iter()
        .map(|g| g.material.as_ref().and_then(|m| m.texture.clone()))
        .collect();
    assert_eq!(textures, expected);

    // The counts that size a renderer's workspace, as constants.
    let count = |name: &str| {
        let item = get(name);
        assert_eq!((item.kind.as_str(), item.ty.as_str()), ("const", "usize"));
        item.value.int() as usize
    };
    let counts = |name: &str| -> Vec<usize> {
        let item = get(name);
        assert_eq!(item.kind, "const");
        assert_eq!(item.ty, format!("[usize; {}]", model.groups.len()));
        item.value
            .array()
            .iter()
            .map(|v| v.int() as usize)
            .collect()
    };
    assert_eq!(count("VERTEX_COUNT"), model.positions.len());
    assert_eq!(count("TRIANGLE_COUNT"), model.triangles.len());
    let group_triangles: Vec<usize> = model.groups.iter().map(|g| g.triangles.len()).collect();
    assert_eq!(counts("GROUP_TRIANGLE_COUNTS"), group_triangles);
    // A group's draw takes the prefix of the vertex arrays up to the
    // largest index its triangles use, as written.
    let written = int_rows(get("TRIANGLES"));
    let group_vertices: Vec<usize> = read
        .iter()
        .map(|&(_, first, n)| {
            let top = written[first..first + n].iter().flatten().max();
            top.map_or(0, |&i| i as usize + 1)
        })
        .collect();
    assert_eq!(counts("GROUP_VERTEX_COUNTS"), group_vertices);
    assert_eq!(
        count("GROUP_DRAWS_VERTEX_COUNT"),
        group_vertices.iter().sum::<usize>()
    );

    assert_eq!(f32s(get("SCALE")), [model.scale as f32]);
    assert_eq!(get("SCALE").kind, "const");
    assert_eq!(f32s(get("OFFSET")), model.offset.map(|x| x as f32));
    assert_eq!(f32s(get("BOUNDS_MIN")), model.bounds.min);
    assert_eq!(f32s(get("BOUNDS_MAX")), model.bounds.max);
    assert_eq!(f32s(get("SPHERE_CENTER")), model.sphere.center);
    assert_eq!(f32s(get("SPHERE_RADIUS")), [model.sphere.radius]);
    items
}

#[test]
fn cube_round_trip() {
    let model = load_obj(
        &data("cube.obj"),
        &ObjOptions::default().with_fit(Fit::Unit),
    )
    .unwrap();
    let text = model_to_rust(&model, "texturedCube").unwrap();
    let items = check_round_trip(&model, &text, "TEXTURED_CUBE");
    assert!(items.contains_key("TEXTURED_CUBE_UVS"));
    assert!(items.contains_key("TEXTURED_CUBE_NORMALS"));
    assert!(!items.contains_key("TEXTURED_CUBE_COLORS"));
    assert_eq!(items.len(), 18);
    // Unit fit of [-1, 1]^3: radius √3, so 1 becomes 1/√3 = 37837.23/65536.
    assert_eq!(
        fixed_rows::<3>(&items["TEXTURED_CUBE_POSITIONS"])[0],
        [-37837; 3]
    );
    // The header says where it came from and how.
    assert!(text.starts_with(
        "// Generated by microraster-import 0.1.0 from `cube.obj`. Do not edit.\n\
         // Materials from `cube.mtl`.\n\
         // Options: fit unit, u16 indices, computed normals on.\n\
         // 24 vertices, 12 triangles, 2 groups; 0 degenerate triangles dropped.\n"
    ));
    assert!(text.contains("// Warning: ignored 1 `s` statement(s)\n"));
    // Deterministic.
    assert_eq!(text, model_to_rust(&model, "texturedCube").unwrap());
}

#[test]
fn coloured_u32_model_with_odd_names_round_trip() {
    let obj = "mtllib m.mtl\n\
               g \"quoted\\name\" \n\
               v 0 0 0 1 0 0\nv 3000 0 0 0 1 0\nv 0 3000 0 0 0 1\nv 3000 3000 0 0.5 0.5 0.5\n\
               usemtl m\nf 1 2 3\n\
               g default\nusemtl other\nf 2 4 3\n";
    let mtl = "newmtl m\nKd 0.2 0.4 2\nmap_Kd tex \"1\".png\n";
    let model = parse_obj(
        obj,
        Path::new("weird dir/odd.obj"),
        |_| Some(mtl.to_string()),
        &ObjOptions::default().with_index_width(IndexWidth::U32),
    )
    .unwrap();
    assert_eq!(model.fit_applied, Fit::Unit);
    assert_eq!(model.groups[0].name, "\"quoted\\name\"");
    let text = model_to_rust(&model, "odd").unwrap();
    let items = check_round_trip(&model, &text, "ODD");
    assert!(items.contains_key("ODD_COLORS"));
    assert!(!items.contains_key("ODD_UVS"));
    assert!(text.contains("// Options: fit auto (applied: unit), u32 indices"));
    // Kd is clamped for the colour: 0.2, 0.4, 2 -> 51, 102, 255.
    assert_eq!(
        colors(&items["ODD_GROUP_COLORS"]),
        [[51, 102, 255], [255; 3]]
    );
}

#[test]
fn bad_names_are_errors() {
    let model = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        Path::new("t.obj"),
        |_| None,
        &ObjOptions::default(),
    )
    .unwrap();
    for bad in ["", "1abc", "a-b", "a b", "ü", "_", "x\n"] {
        let e = model_to_rust(&model, bad).unwrap_err();
        assert!(matches!(e.kind(), ErrorKind::BadName { name } if name == bad));
        assert_eq!(
            e.to_string(),
            format!(
                "t.obj: name `{}` is not an identifier (ASCII letters, digits and `_`, \
                 not starting with a digit)",
                bad.escape_debug()
            )
        );
        assert!(!e.to_string().contains('\n'));
    }
    assert!(model_to_rust(&model, "_private")
        .unwrap()
        .contains("pub static _PRIVATE_POSITIONS"));
}

#[test]
fn obj_to_rust_writes_the_file_and_lists_what_it_read() {
    let dir = temp_dir("obj-to-rust");
    let out = dir.join("cube.rs");
    let summary = obj_to_rust(data("cube.obj"), &out, "cube", &ObjOptions::default()).unwrap();
    assert_eq!(
        (summary.vertices, summary.triangles, summary.groups),
        (24, 12, 2)
    );
    assert_eq!(summary.fit_applied, Fit::Keep);
    assert_eq!(summary.files, [data("cube.obj"), data("cube.mtl")]);
    assert_eq!(
        summary.rerun_if_changed(),
        format!(
            "cargo:rerun-if-changed={}\ncargo:rerun-if-changed={}\n",
            data("cube.obj").display(),
            data("cube.mtl").display()
        )
    );
    assert_eq!(
        summary.to_string(),
        "24 vertices, 12 triangles, 2 groups, scale 1 (fit keep)"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let model = load_obj(&data("cube.obj"), &ObjOptions::default()).unwrap();
    check_round_trip(&model, &text, "CUBE");
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["cube.rs"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failed_conversion_leaves_the_output_alone() {
    let dir = temp_dir("atomic");
    let out = dir.join("model.rs");
    std::fs::write(&out, "// the previous version\n").unwrap();
    // Bad input: an error naming the file and line; the output untouched.
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nf 1 1 7\n").unwrap();
    let e = obj_to_rust(&bad, &out, "model", &ObjOptions::default()).unwrap_err();
    assert_eq!(e.line(), Some(2));
    assert_eq!(e.path(), bad);
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "// the previous version\n"
    );
    // A bad name fails before anything is read or written.
    let e = obj_to_rust(
        dir.join("missing.obj"),
        &out,
        "no good",
        &ObjOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::BadName { .. }));
    // An output directory that does not exist: an I/O error naming the
    // temporary file, nothing left behind.
    let e = obj_to_rust(
        data("cube.obj"),
        dir.join("nowhere/model.rs"),
        "model",
        &ObjOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Io(_)));
    assert!(e.path().starts_with(dir.join("nowhere")));
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    assert_eq!(names, ["bad.obj", "model.rs"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn write_atomic_skips_identical_content() {
    let dir = temp_dir("write");
    let path = dir.join("x.rs");
    assert!(write_atomic(&path, "a").unwrap());
    assert!(!write_atomic(&path, "a").unwrap());
    assert!(write_atomic(&path, "b").unwrap());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "b");
    let e = write_atomic(Path::new("/"), "x").unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Io(_)));
    std::fs::remove_dir_all(&dir).unwrap();
}

const CLUSTER: &str = "::microraster::mesh::Cluster::new";

/// A `Cluster::new` as (triangle count, first vertex, vertex count, min, max).
type ClusterArgs = (usize, usize, usize, [i32; 3], [i32; 3]);

fn cluster_rows(item: &Item) -> Vec<ClusterArgs> {
    let rows = item.value.array();
    assert_eq!(declared_len(&item.ty), rows.len(), "{}", item.ty);
    rows.iter()
        .map(|c| match c.call(CLUSTER) {
            [t, f, v, min, max] => {
                let corner = |a: &Value| -> [i32; 3] {
                    let a = a.array();
                    assert_eq!(a.len(), 3);
                    std::array::from_fn(|k| a[k].call(FX)[0].int() as i32)
                };
                (
                    t.int() as usize,
                    f.int() as usize,
                    v.int() as usize,
                    corner(min),
                    corner(max),
                )
            }
            other => panic!("{other:?}"),
        })
        .collect()
}

fn pairs(item: &Item) -> Vec<(usize, usize)> {
    item.value
        .array()
        .iter()
        .map(|p| match p {
            Value::Tuple(t) => match &t[..] {
                [Value::Int(a), Value::Int(b)] => (*a as usize, *b as usize),
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        })
        .collect()
}

/// A `w` x `h` grid of quads on the x-y plane, in groups of `band` rows
/// (each with its own material).
fn grid(w: usize, h: usize, band: usize) -> String {
    let mut s = String::new();
    for y in 0..=h {
        for x in 0..=w {
            s += &format!("v {x} {y} {}\n", (x * y) % 3);
        }
    }
    for y in 0..h {
        if y % band == 0 {
            s += &format!("g band{}\nusemtl m{}\n", y / band, y / band);
        }
        for x in 0..w {
            let i = y * (w + 1) + x + 1;
            s += &format!("f {i} {} {} {}\n", i + 1, i + w + 2, i + w + 1);
        }
    }
    s
}

#[test]
fn clusters_are_written_and_obey_the_mesh_rules() {
    let cube = load_obj(
        &data("cube.obj"),
        &ObjOptions::default()
            .with_fit(Fit::Unit)
            .with_cluster_triangles(3),
    )
    .unwrap();
    let grid = parse_obj(
        &grid(30, 24, 10),
        Path::new("grid.obj"),
        |_| None,
        &ObjOptions::default()
            .with_index_width(IndexWidth::U32)
            .with_cluster_triangles(40),
    )
    .unwrap();
    for (model, name, p) in [(&cube, "cube", "CUBE"), (&grid, "grid", "GRID")] {
        assert!(!model.clusters.is_empty());
        common::check_clusters(model);
        let text = model_to_rust(model, name).unwrap();
        let items = check_round_trip(model, &text, p);
        assert_eq!(items.len(), 20 - usize::from(model.uvs.is_empty()), "{p}");
        assert!(text.contains(&format!(
            "computed normals on, clusters of at most {} triangles.\n// {} vertices, {} triangles, {} groups, {} clusters; ",
            model.options.cluster_triangles,
            model.positions.len(),
            model.triangles.len(),
            model.groups.len(),
            model.clusters.len()
        )));

        let clusters = &items[&format!("{p}_CLUSTERS")];
        assert_eq!(clusters.kind, "static");
        assert_eq!(
            clusters.ty,
            format!("[::microraster::mesh::Cluster; {}]", model.clusters.len())
        );
        let read = cluster_rows(clusters);
        let expected: Vec<ClusterArgs> = model
            .clusters
            .iter()
            .zip(model.cluster_bounds_fixed())
            .map(|(c, [min, max])| {
                (
                    c.triangles.len(),
                    c.vertices.start,
                    c.vertices.len(),
                    min,
                    max,
                )
            })
            .collect();
        assert_eq!(read, expected);
        let group_clusters = &items[&format!("{p}_GROUP_CLUSTERS")];
        assert_eq!(
            group_clusters.ty,
            format!("[(usize, usize); {}]", model.groups.len())
        );
        let runs = pairs(group_clusters);
        let expected: Vec<(usize, usize)> = model
            .groups
            .iter()
            .map(|g| (g.clusters.start, g.clusters.len()))
            .collect();
        assert_eq!(runs, expected);

        // What `Mesh::with_clusters` checks, on the arrays as written: the
        // clusters tile the triangles, which use only their cluster's
        // vertices, which lie in its box; and a group's run of clusters
        // holds exactly the group's triangles.
        let positions = fixed_rows::<3>(&items[&format!("{p}_POSITIONS")]);
        let triangles = int_rows(&items[&format!("{p}_TRIANGLES")]);
        let mut t = 0;
        for &(count, first, vertices, min, max) in &read {
            let range = first..first + vertices;
            assert!(range.end <= positions.len());
            assert!((0..3).all(|k| min[k] <= max[k]));
            for q in &positions[range.clone()] {
                assert!((0..3).all(|k| min[k] <= q[k] && q[k] <= max[k]));
            }
            for tri in &triangles[t..t + count] {
                assert!(tri.iter().all(|&i| range.contains(&(i as usize))));
            }
            t += count;
        }
        assert_eq!(t, triangles.len());
        for (g, &(c0, cn)) in model.groups.iter().zip(&runs) {
            let held: usize = read[c0..c0 + cn].iter().map(|c| c.0).sum();
            assert_eq!(held, g.triangles.len());
        }
    }
    // Bands of 600, 600 and 240 triangles, in full clusters of 40.
    assert_eq!(grid.groups.len(), 3);
    assert_eq!(grid.clusters.len(), 15 + 15 + 6);
}

#[test]
fn without_clusters_the_output_is_what_it_was() {
    let options = ObjOptions::default().with_fit(Fit::Keep);
    let model = load_obj(&data("cube.obj"), &options).unwrap();
    let text = model_to_rust(&model, "imported_cube").unwrap();
    // The renderer's checked-in copy of this output, written before
    // clusters existed (its own test keeps it current).
    let checked_in = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/imported_cube.rs");
    assert_eq!(text, std::fs::read_to_string(checked_in).unwrap());
    let zero = load_obj(&data("cube.obj"), &options.with_cluster_triangles(0)).unwrap();
    assert_eq!(zero, model);
    assert!(!text.contains("CLUSTERS") && !text.contains("::microraster::"));
}

#[test]
fn the_summary_counts_clusters() {
    let dir = temp_dir("summary-clusters");
    let out = dir.join("cube.rs");
    let options = ObjOptions::default().with_cluster_triangles(4);
    let summary = obj_to_rust(data("cube.obj"), &out, "cube", &options).unwrap();
    let model = load_obj(&data("cube.obj"), &options).unwrap();
    assert_eq!(summary.clusters, model.clusters.len());
    assert_eq!(
        summary.to_string(),
        format!(
            "{} vertices, 12 triangles, 2 groups, {} clusters, scale 1 (fit keep)",
            model.positions.len(),
            model.clusters.len()
        )
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text, model_to_rust(&model, "cube").unwrap());
    assert!(text.contains(&format!(
        "pub static CUBE_CLUSTERS: [::microraster::mesh::Cluster; {}]",
        model.clusters.len()
    )));
    assert!(text.contains("pub static CUBE_GROUP_CLUSTERS: [(usize, usize); 2]"));
    std::fs::remove_dir_all(&dir).unwrap();
}
