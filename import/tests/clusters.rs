//! Clusters (`ObjOptions::cluster_triangles`): the re-laid model draws the
//! same triangles, the layout follows every rule of
//! `Mesh::with_clusters`, the clusters are compact in space, and limits
//! still hold after vertices are copied.

mod common;

use std::path::{Path, PathBuf};

use microraster_import::{
    obj_to_rust, parse_obj, ErrorKind, ImportError, IndexWidth, Model, ObjOptions,
};

/// A terrain of `w` x `h` quads on the x-z plane (heights, texture
/// coordinates, normals and colours varying per vertex), in two groups:
/// `west` (the first `split` columns) and `east` (the rest). Every vertex
/// has a `vt` and a `vn`, so inner vertices are shared by six triangles
/// and the column at `split` by both groups.
fn terrain(w: usize, h: usize, split: usize) -> String {
    let mut s = String::new();
    for z in 0..=h {
        for x in 0..=w {
            let y = ((x * 7 + z * 13) % 5) as f32 * 0.25;
            let (r, g) = (x as f32 / w as f32, z as f32 / h as f32);
            s += &format!("v {x} {y} {z} {r} {g} 0.5\n");
            s += &format!("vt {r} {g}\n");
            s += &format!("vn {} 4 {}\n", x % 3, z % 3);
        }
    }
    let corner = |x: usize, z: usize| {
        let i = z * (w + 1) + x + 1;
        format!("{i}/{i}/{i}")
    };
    for (name, columns) in [("west", 0..split), ("east", split..w)] {
        s += &format!("g {name}\n");
        for z in 0..h {
            for x in columns.clone() {
                s += &format!(
                    "f {} {} {} {}\n",
                    corner(x, z),
                    corner(x, z + 1),
                    corner(x + 1, z + 1),
                    corner(x + 1, z)
                );
            }
        }
    }
    s
}

fn import(source: &str, options: &ObjOptions) -> Result<Model, ImportError> {
    parse_obj(source, Path::new("terrain.obj"), |_| None, options)
}

fn clustered(source: &str, max: usize) -> Model {
    let m = import(source, &ObjOptions::default().with_cluster_triangles(max))
        .unwrap_or_else(|e| panic!("{e}"));
    common::check_clusters(&m);
    m
}

/// Everything a corner draws with, as bits: position, normal, texture
/// coordinate, colour.
type Corner = ([u32; 3], [u32; 3], [u32; 2], [u8; 3]);

/// The triangles of `range`, each as its corners' data in corner order.
fn corner_triangles(m: &Model, range: std::ops::Range<usize>) -> Vec<[Corner; 3]> {
    m.triangles[range]
        .iter()
        .map(|t| {
            t.map(|i| {
                let i = i as usize;
                (
                    m.positions[i].map(f32::to_bits),
                    m.normals.get(i).map_or([0; 3], |n| n.map(f32::to_bits)),
                    m.uvs.get(i).map_or([0; 2], |u| u.map(f32::to_bits)),
                    m.colors.get(i).copied().unwrap_or([0; 3]),
                )
            })
        })
        .collect()
}

/// Each group's triangles as a sorted list (a multiset), with its name.
fn group_multisets(m: &Model) -> Vec<(String, Vec<[Corner; 3]>)> {
    m.groups
        .iter()
        .map(|g| {
            let mut t = corner_triangles(m, g.triangles.clone());
            t.sort_unstable();
            (g.name.clone(), t)
        })
        .collect()
}

#[test]
fn clustering_keeps_every_triangle_with_its_corners() {
    let source = terrain(40, 40, 16);
    let plain = import(&source, &ObjOptions::default()).unwrap();
    assert_eq!(plain.triangles.len(), 3200);
    assert_eq!(plain.positions.len(), 41 * 41);
    assert!(!plain.normals.is_empty() && !plain.uvs.is_empty() && !plain.colors.is_empty());
    common::check_clusters(&plain);
    let expected = group_multisets(&plain);
    for max in [1, 7, 64, 500, 5000] {
        let m = clustered(&source, max);
        assert_eq!(group_multisets(&m), expected, "max {max}");
        // Same group ranges, same whole-model data.
        let ranges =
            |m: &Model| -> Vec<_> { m.groups.iter().map(|g| g.triangles.clone()).collect() };
        assert_eq!(ranges(&m), ranges(&plain));
        assert_eq!((m.bounds, m.sphere), (plain.bounds, plain.sphere));
        assert_eq!((m.offset, m.scale), (plain.offset, plain.scale));
        assert_eq!(m.warnings, plain.warnings);
        // Full clusters (checked by check_clusters), so as few as can be.
        for g in &m.groups {
            assert_eq!(g.clusters.len(), g.triangles.len().div_ceil(max), "{g:?}");
        }
    }
}

#[test]
fn clusters_are_compact_in_space() {
    let source = terrain(40, 40, 16);
    let m = clustered(&source, 64);
    let bounds = m.cluster_bounds_fixed();
    let fixed = m.positions_fixed();
    // The terrain lies on x-z: compare areas there.
    let area = |[lo, hi]: [[i32; 3]; 2]| {
        let side = |k: usize| (hi[k] - lo[k]) as f64 / 65536.0;
        side(0) * side(2)
    };
    for g in &m.groups {
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        for t in &m.triangles[g.triangles.clone()] {
            for &i in t {
                for k in 0..3 {
                    lo[k] = lo[k].min(fixed[i as usize][k]);
                    hi[k] = hi[k].max(fixed[i as usize][k]);
                }
            }
        }
        let group_area = area([lo, hi]);
        let boxes = &bounds[g.clusters.clone()];
        let count = boxes.len();
        assert_eq!(count, g.triangles.len().div_ceil(64), "{}", g.name);
        // Clusters of triangles picked at random would each span nearly
        // the whole group; spatial ones cover about their share of it.
        let total: f64 = boxes.iter().map(|&b| area(b)).sum();
        assert!(
            total < group_area * count as f64 / 8.0,
            "{}: {total} vs {group_area} x {count}",
            g.name
        );
        // Halving the longest side keeps boxes squarish, not strips.
        for &[lo, hi] in boxes {
            let (x, z) = ((hi[0] - lo[0]) as f64, (hi[2] - lo[2]) as f64);
            assert!(x.max(z) <= 3.0 * x.min(z), "{lo:?} {hi:?}");
        }
        // Consecutive clusters are neighbours (a random order would jump
        // across the group).
        let centre = |[lo, hi]: [[i32; 3]; 2]| [0, 2].map(|k| (lo[k] + hi[k]) as f64 / 131072.0);
        let steps: f64 = boxes
            .windows(2)
            .map(|w| {
                let (a, b) = (centre(w[0]), centre(w[1]));
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
            })
            .sum();
        let diagonal =
            (((hi[0] - lo[0]) as f64).powi(2) + ((hi[2] - lo[2]) as f64).powi(2)).sqrt() / 65536.0;
        assert!(
            steps / ((count - 1) as f64) < diagonal / 4.0,
            "{}: mean step {}",
            g.name,
            steps / ((count - 1) as f64)
        );
    }
}

#[test]
fn clustering_is_deterministic() {
    let source = terrain(30, 20, 11);
    let a = clustered(&source, 50);
    let b = clustered(&source, 50);
    assert_eq!(a, b);
    assert_eq!(
        microraster_import::model_to_rust(&a, "t").unwrap(),
        microraster_import::model_to_rust(&b, "t").unwrap()
    );
    // A flat, regular grid is full of equal centroid coordinates: ties are
    // broken the same way every time too.
    let flat = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
                f 1 2 3\nf 1 3 4\nf 2 5 6\nf 2 6 3\nf 1 2 3\nf 2 5 6\n";
    let c = clustered(flat, 1);
    assert_eq!(c, clustered(flat, 1));
}

#[test]
fn one_triangle_per_cluster() {
    let source = terrain(12, 10, 5);
    let m = clustered(&source, 1);
    assert_eq!(m.clusters.len(), 240);
    assert_eq!(m.positions.len(), 3 * 240);
    for (k, c) in m.clusters.iter().enumerate() {
        assert_eq!(c.triangles, k..k + 1);
        assert_eq!(c.vertices, 3 * k..3 * k + 3);
        assert_eq!(m.triangles[k], [0, 1, 2].map(|i| (3 * k + i) as u32));
    }
    assert_eq!(m.groups[0].clusters, 0..100);
    assert_eq!(m.groups[1].clusters, 100..240);
}

#[test]
fn a_cluster_as_large_as_its_group_keeps_the_order() {
    // Groups of 100 and 140 triangles.
    let source = terrain(12, 10, 5);
    let plain = import(&source, &ObjOptions::default()).unwrap();
    for max in [140, 1_000_000, usize::MAX] {
        let m = clustered(&source, max);
        assert_eq!(m.clusters.len(), 2, "max {max}");
        assert_eq!(m.clusters[0].triangles, 0..100);
        assert_eq!(m.clusters[1].triangles, 100..240);
        assert_eq!(m.groups[0].clusters, 0..1);
        assert_eq!(m.groups[1].clusters, 1..2);
        // The triangles in the file's order, corners and all.
        assert_eq!(
            corner_triangles(&m, 0..240),
            corner_triangles(&plain, 0..240)
        );
        // Only the column the groups share is copied.
        assert_eq!(m.positions.len(), plain.positions.len() + 11);
        assert_eq!(m.clusters[0].vertices, 0..6 * 11);
        assert_eq!(m.clusters[1].vertices, 6 * 11..6 * 11 + 8 * 11);
    }
}

#[test]
fn groups_without_triangles_get_no_clusters() {
    // The parser drops a group with no triangles (here `empty`, and the
    // faces-less material switch), so no group is left without a cluster.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\ng empty\nusemtl x\ng full\nf 1 2 3\ng empty2\n";
    let m = clustered(obj, 4);
    assert_eq!(m.groups.len(), 1);
    assert_eq!(m.groups[0].clusters, 0..1);
}

#[test]
fn copies_beyond_the_index_width_are_an_error() {
    // 22,000 triangles on 11,211 vertices: one triangle per cluster needs
    // 66,000, more than u16 indices address.
    let source = terrain(110, 100, 50);
    let options = ObjOptions::default().with_cluster_triangles(1);
    let e = import(&source, &options).unwrap_err();
    assert!(
        matches!(
            e.kind(),
            ErrorKind::TooManyVertices {
                count: 66_000,
                limit: 65_536,
                duplicated: 54_789,
            }
        ),
        "{e:?}"
    );
    assert_eq!(e.line(), None);
    assert_eq!(
        e.to_string(),
        "terrain.obj: model has 66000 vertices, 54789 of them copies that clustering made \
         of vertices shared by clusters, but u16 indices address only 65536; use 32-bit \
         indices (IndexWidth::U32, --u32), larger clusters (--clusters) or split the model"
    );
    // With u32 indices it fits; with larger clusters it fits in u16.
    let wide = import(&source, &options.clone().with_index_width(IndexWidth::U32)).unwrap();
    assert_eq!(wide.positions.len(), 66_000);
    common::check_clusters(&wide);
    let m = clustered(&source, 256);
    assert!(m.positions.len() < 65_536);

    // Through a file: the error names it, and nothing is written.
    let dir = std::env::temp_dir().join(format!("mri-clusters-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("big.obj");
    std::fs::write(&obj, &source).unwrap();
    let out: PathBuf = dir.join("big.rs");
    let e = obj_to_rust(&obj, &out, "big", &options).unwrap_err();
    assert_eq!(e.path(), obj);
    assert!(e
        .to_string()
        .starts_with(&format!("{}: model has 66000 vertices", obj.display())));
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
