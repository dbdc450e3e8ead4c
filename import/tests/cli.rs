//! The `microraster-import` command: output files, summary lines, one-line
//! errors and exit codes.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_microraster-import"))
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn data(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
        .display()
        .to_string()
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mri-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn obj_conversion() {
    let dir = temp_dir("obj");
    let out = dir.join("cube.rs").display().to_string();
    let o = run(&["obj", &data("cube.obj"), "--out", &out, "--fit", "unit"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        format!(
            "{} -> {out}: 24 vertices, 12 triangles, 2 groups, scale 0.5773502691896258 (fit unit)\n",
            data("cube.obj")
        )
    );
    assert_eq!(stderr(&o), "warning: ignored 1 `s` statement(s)\n");
    let text = std::fs::read_to_string(&out).unwrap();
    // The name defaults to the file stem.
    assert!(text.contains("pub static CUBE_POSITIONS: [[::fixed::types::I16F16; 3]; 24]"));

    let o = run(&[
        "obj",
        &data("colored.obj"),
        "--out",
        &out,
        "--name",
        "quad",
        "--u32",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("pub static QUAD_TRIANGLES: [[u32; 3]; 2]"));
    assert!(text.contains("pub static QUAD_COLORS"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_conversion() {
    let dir = temp_dir("png");
    let png = dir.join("chk.png");
    {
        let file = std::fs::File::create(&png).unwrap();
        let mut e = png::Encoder::new(file, 2, 2);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(png::BitDepth::Eight);
        e.write_header()
            .unwrap()
            .write_image_data(&[0, 255, 255, 0])
            .unwrap();
    }
    let out = dir.join("chk.rs").display().to_string();
    let o = run(&[
        "png",
        &png.display().to_string(),
        "--format",
        "indexed4",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        format!(
            "{} -> {out}: 2x2 indexed4, 6 bytes, 2 palette colours\n",
            png.display()
        )
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("pub static CHK_TEXELS: [u8; 2] = [\n    0x01, 0x10,\n];"));
    assert!(text.contains("pub static CHK_PALETTE: [u16; 2] = [\n    0x0000, 0xFFFF,\n];"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn errors_are_one_line_with_exit_status() {
    let dir = temp_dir("err");
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
    let out = dir.join("bad.rs").display().to_string();
    let o = run(&["obj", &bad.display().to_string(), "--out", &out]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        format!(
            "error: {}:3: vertex index 3 is out of range (2 vertices are defined before this line)\n",
            bad.display()
        )
    );
    assert!(stdout(&o).is_empty());
    assert!(!Path::new(&out).exists());

    // Usage errors: exit status 2, with the usage.
    let o = run(&["obj", "x.obj"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).starts_with("error: missing --out FILE.rs\nusage: "));
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["--help"]);
    assert!(o.status.success());
    assert!(stdout(&o).starts_with("usage: microraster-import obj MODEL.obj"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn obj_conversion_with_clusters() {
    let dir = temp_dir("clusters");
    let out = dir.join("cube.rs").display().to_string();
    let o = run(&["obj", &data("cube.obj"), "--out", &out, "--clusters", "64"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Both groups are smaller than 64 triangles: one cluster each, and
    // only the vertices the groups share are copied (none on this cube).
    assert_eq!(
        stdout(&o),
        format!(
            "{} -> {out}: 24 vertices, 12 triangles, 2 groups, 2 clusters, scale 1 (fit keep)\n",
            data("cube.obj")
        )
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("// Options: fit auto (applied: keep), u16 indices, computed normals on, clusters of at most 64 triangles.\n"));
    assert!(text.contains("pub static CUBE_CLUSTERS: [::microraster::mesh::Cluster; 2] = [\n"));
    assert!(text.contains(
        "pub static CUBE_GROUP_CLUSTERS: [(usize, usize); 2] = [\n    (0, 1),\n    (1, 1),\n];"
    ));

    // Not a positive number: a usage error, and nothing written.
    let out = dir.join("bad.rs").display().to_string();
    for bad in ["0", "x", "-3"] {
        let o = run(&["obj", &data("cube.obj"), "--out", &out, "--clusters", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            stderr(&o).starts_with(&format!(
                "error: bad cluster size `{bad}` (expected the most triangles per cluster, at least 1)\nusage: "
            )),
            "{}",
            stderr(&o)
        );
        assert!(stdout(&o).is_empty());
    }
    let o = run(&["obj", &data("cube.obj"), "--out", &out, "--clusters"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).starts_with("error: --clusters needs a value\n"));
    assert!(!Path::new(&out).exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn faces_above_the_corner_limit_need_the_option() {
    // A convex 300-gon: more corners than the default limit of 256.
    let dir = temp_dir("corners");
    let obj = dir.join("disc.obj");
    std::fs::write(&obj, common::regular_polygon_obj(300)).unwrap();
    let (obj, out) = (
        obj.display().to_string(),
        dir.join("disc.rs").display().to_string(),
    );
    let o = run(&["obj", &obj, "--out", &out]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        format!(
            "error: {obj}:301: face has 300 corners, more than the limit of 256; \
             raise it with ObjOptions::with_max_face_corners (--max-face-corners N)\n"
        )
    );
    assert!(!Path::new(&out).exists());
    // Allowed, it becomes a fan of 298 triangles.
    let o = run(&["obj", &obj, "--out", &out, "--max-face-corners", "300"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(": 300 vertices, 298 triangles, 1 groups,"),
        "{}",
        stdout(&o)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn material_libraries_outside_the_folder_need_the_option() {
    let dir = temp_dir("outside");
    std::fs::create_dir_all(dir.join("model")).unwrap();
    let obj = dir.join("model/t.obj").display().to_string();
    std::fs::write(
        &obj,
        "mtllib ../up.mtl\nusemtl g\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.join("up.mtl"), "newmtl g\nKd 0 1 0\n").unwrap();
    let out = dir.join("t.rs").display().to_string();
    let o = run(&["obj", &obj, "--out", &out]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with(&format!(
            "warning: {obj}:1: material library `../up.mtl` is outside the model's folder; \
             allow it with ObjOptions::with_outside_files (--allow-outside-files); not read\n"
        )),
        "{}",
        stderr(&o)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("::embedded_graphics::pixelcolor::Rgb888::new(255, 255, 255),"));
    let o = run(&["obj", &obj, "--out", &out, "--allow-outside-files"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("::embedded_graphics::pixelcolor::Rgb888::new(0, 255, 0),"));
    std::fs::remove_dir_all(&dir).unwrap();
}
