//! Wavefront OBJ (and MTL) parsing into a [`Model`] ready for 16.16 fixed
//! point.
//!
//! # What is read
//!
//! * `v x y z [w]` positions (`w` is ignored) and the common colour
//!   extension `v x y z r g b` (`r g b` in 0..1, clamped).
//! * `vt u [v [w]]` texture coordinates (`v` defaults to 0, `w` is ignored).
//! * `vn x y z` normals (normalised on import).
//! * `f` faces in the `v`, `v/vt`, `v//vn` and `v/vt/vn` forms (one form per
//!   face), with 1-based or negative (relative) indices that refer to
//!   elements defined *before* the face. Polygons with more than three
//!   corners are triangulated by ear clipping in the polygon's dominant
//!   plane (see [`triangulate`](fn@triangulate)). A face of more than
//!   [`ObjOptions::max_face_corners`] (default 256) is an error; with the
//!   limit raised, faces above 256 corners become a fan.
//! * `o` and `g` start a group; faces before either go into the group
//!   `default`. `usemtl` sets the material of the faces that follow, and
//!   `mtllib` loads material libraries (`newmtl`, `Kd`, `map_Kd`).
//!   Material libraries and textures are looked for in the OBJ file's
//!   folder; a name that leaves it (`..`, absolute) is refused with a
//!   warning unless [`ObjOptions::outside_files`] allows it
//!   ([`crate::paths`]).
//!   A group's faces with different materials become separate [`Group`]s of
//!   the same name; groups with no triangle are dropped, and faces of the
//!   same group and material are merged into one range even when the file
//!   interleaves them.
//! * `#` starts a comment (anywhere on a line, so names cannot contain `#`).
//!   A line ending in `\` continues on the next. CRLF line endings, tabs,
//!   trailing whitespace and a leading UTF-8 byte-order mark (in OBJ and
//!   MTL files) are fine. Other statements (`s`, `l`, `p`, `vp`,
//!   curves and surfaces, ...) are ignored and counted in
//!   [`Model::warnings`].
//!
//! # What comes out
//!
//! One vertex per unique (position, texture coordinate, normal) triple that
//! a kept triangle uses, numbered in the order the triangles first use them;
//! triangles ordered group by group; normals, texture coordinates and
//! colours either for every vertex or not at all (the rules are on
//! [`Model`]); and the bounding box and sphere of the positions after
//! [`Fit`] has moved them into the 16.16 range.
//!
//! # Clusters
//!
//! With [`ObjOptions::cluster_triangles`] set, the model is then laid out
//! again for microraster's per-cluster frustum culling
//! (`microraster::mesh::Mesh::with_clusters`). Each group's triangles are
//! split in space: sorted along the longest axis of the bounding box of
//! their centroids and cut so that the lower part holds half the clusters
//! needed (rounded up, each full), and the parts again, until a part has
//! at most that many triangles; that part is a cluster ([`ClusterRange`]),
//! and all but the last of each group are full.
//! Triangles are reordered within their group to follow the clusters (the
//! file's order within a cluster, corners untouched), and each cluster gets
//! its own run of vertices, in the order its triangles first use them: a
//! vertex that several clusters use is copied into each, with its normal,
//! texture coordinate and colour. Groups keep their ranges, and the model
//! its bounding box and sphere.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::error::ImportError;

mod assemble;
mod cluster;
mod lines;
mod model;
mod mtl;
mod options;
mod parser;
mod triangulate;
mod vector;

pub(crate) use model::unit_to_u8;
pub use model::{to_fixed, Aabb, ClusterRange, Group, Material, Model, Sphere};
pub use options::{Fit, IndexWidth, ObjOptions};
pub use triangulate::{triangulate, EAR_CLIPPING_MAX_CORNERS};

use parser::parse;

/// Reads the OBJ file at `path`, and the MTL files it names (relative to its
/// directory; a missing one is a warning, an unreadable one an error, one
/// outside the directory refused with a warning unless
/// [`ObjOptions::outside_files`] allows it: see [`crate::paths`]).
///
/// Bytes that are not UTF-8 are replaced (OBJ is ASCII; this only affects
/// names).
pub fn load_obj(path: &Path, options: &ObjOptions) -> Result<Model, ImportError> {
    let bytes = fs::read(path).map_err(|e| ImportError::io(path, e))?;
    let source = String::from_utf8_lossy(&bytes);
    let dir = parent_dir(path);
    let mut loader = |name: &str| -> Result<Option<(PathBuf, String)>, ImportError> {
        let mtl = dir.join(name);
        match fs::read(&mtl) {
            Ok(bytes) => Ok(Some((mtl, String::from_utf8_lossy(&bytes).into_owned()))),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(ImportError::io(&mtl, e)),
        }
    };
    parse(&source, path, &mut loader, options)
}

/// Parses OBJ text held in memory.
///
/// `path` is only used in errors, warnings and [`Model::source`], and to
/// name MTL files: `mtl_loader` gets each `mtllib` file name as written and
/// returns the file's text, or `None` if there is no such file (a warning).
/// A name outside the folder of `path` (see [`crate::paths`]) is not passed
/// to it, but refused with a warning, unless [`ObjOptions::outside_files`]
/// allows it.
///
/// ```
/// use std::path::Path;
/// use microraster_import::{parse_obj, ObjOptions};
///
/// let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3 4\n";
/// let mtl = "newmtl red\nKd 1 0 0\n";
/// let model = parse_obj(obj, Path::new("quad.obj"), |name| {
///     (name == "m.mtl").then(|| mtl.to_string())
/// }, &ObjOptions::default())
/// .unwrap();
/// assert_eq!(model.triangles.len(), 2);
/// assert_eq!(model.groups[0].material.as_ref().unwrap().diffuse, [1.0, 0.0, 0.0]);
/// ```
pub fn parse_obj(
    source: &str,
    path: &Path,
    mut mtl_loader: impl FnMut(&str) -> Option<String>,
    options: &ObjOptions,
) -> Result<Model, ImportError> {
    let dir = parent_dir(path);
    let mut loader = |name: &str| -> Result<Option<(PathBuf, String)>, ImportError> {
        Ok(mtl_loader(name).map(|text| (dir.join(name), text)))
    };
    parse(source, path, &mut loader, options)
}

fn parent_dir(path: &Path) -> PathBuf {
    path.parent().map(Path::to_path_buf).unwrap_or_default()
}
