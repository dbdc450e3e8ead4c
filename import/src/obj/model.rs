//! What an import gives: the [`Model`] with its [`Group`]s, [`Material`]s,
//! clusters and bounds, and its arrays as raw 16.16 bits ([`to_fixed`]).

use std::ops::Range;
use std::path::PathBuf;

use super::{Fit, ObjOptions};

/// A material from an MTL file (or a name `usemtl` used without one).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The name given by `newmtl` / `usemtl`.
    pub name: String,
    /// The diffuse colour `Kd`, as written (white when absent or when the
    /// material is not defined).
    pub diffuse: [f32; 3],
    /// The diffuse texture's file name (`map_Kd`), as written (relative to
    /// the MTL file), without its options. A name outside the OBJ file's
    /// folder is dropped with a warning unless
    /// [`ObjOptions::outside_files`] allows it.
    pub texture: Option<String>,
}

/// A run of triangles with one name and one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// The `o` or `g` name (`default` for faces before any).
    pub name: String,
    /// The material set by `usemtl`, if any.
    pub material: Option<Material>,
    /// The group's triangles: a range of [`Model::triangles`].
    pub triangles: Range<usize>,
    /// The group's clusters: a range of [`Model::clusters`] (empty without
    /// clusters). They hold exactly the group's triangles.
    pub clusters: Range<usize>,
}

/// A cluster of a model's triangles ([`ObjOptions::cluster_triangles`]):
/// consecutive triangles of one group that lie close together, and the run
/// of vertices that they, and only they, use.
///
/// The clusters of a model tile its triangles in order, and their vertex
/// runs tile its vertices in order; each has at least one triangle.
/// [`Model::cluster_bounds_fixed`] gives their bounding boxes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClusterRange {
    /// Its triangles: a range of [`Model::triangles`], within one group's.
    pub triangles: Range<usize>,
    /// The vertices its triangles use: a range of [`Model::positions`] (and
    /// of the other per-vertex arrays).
    pub vertices: Range<usize>,
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    /// The smallest coordinates.
    pub min: [f32; 3],
    /// The largest coordinates.
    pub max: [f32; 3],
}

impl Aabb {
    /// The box's centre.
    pub fn center(&self) -> [f32; 3] {
        std::array::from_fn(|k| ((self.min[k] as f64 + self.max[k] as f64) / 2.0) as f32)
    }
}

/// A bounding sphere.
///
/// This importer's sphere is centred on the bounding box's centre, with the
/// largest distance from there to a position as its radius: not the
/// smallest sphere (Ritter's is up to ~5% tighter on typical models), but
/// exact and the one [`Fit::Unit`] scales to radius 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sphere {
    /// The centre.
    pub center: [f32; 3],
    /// The radius.
    pub radius: f32,
}

/// An imported model: flat arrays ready to become 16.16 `static`s.
///
/// Per-vertex arrays are either as long as [`positions`](Model::positions)
/// or empty:
///
/// * **normals**: unit length. A `vn` is used where a vertex has one (a
///   zero-length `vn` counts as none); the others get the normalised sum of
///   the face normals (cross products, so weighted by area) of all the
///   triangles around their position, if
///   [`ObjOptions::compute_normals`] is on. With it off, normals are empty
///   unless every vertex has a `vn`.
/// * **uvs**: present when any vertex has a `vt`; vertices without get
///   `[0, 0]` (and a warning).
/// * **colors**: present when any used `v` has a colour; the others are
///   white (and a warning).
///
/// With [`ObjOptions::cluster_triangles`] on, the triangles and vertices
/// are laid out by [`clusters`](Model::clusters) (see
/// [the module documentation](super#clusters)).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// The OBJ file's path (as given).
    pub source: PathBuf,
    /// The options it was imported with.
    pub options: ObjOptions,
    /// What [`Fit::Auto`] resolved to: [`Fit::Keep`] or [`Fit::Unit`].
    pub fit_applied: Fit,
    /// Positions after fitting: `(original + offset) * scale`.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals, one per position, or empty.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates, one per position, or empty.
    pub uvs: Vec<[f32; 2]>,
    /// Vertex colours, one per position, or empty.
    pub colors: Vec<[u8; 3]>,
    /// Triangles as indices into the per-vertex arrays, counter-clockwise
    /// as in the file, group by group (and, with clusters, cluster by
    /// cluster within a group).
    pub triangles: Vec<[u32; 3]>,
    /// The groups, in the order of their first triangle in the file.
    pub groups: Vec<Group>,
    /// The clusters, in order: empty unless
    /// [`ObjOptions::cluster_triangles`] is set.
    pub clusters: Vec<ClusterRange>,
    /// The bounding box of [`positions`](Model::positions).
    pub bounds: Aabb,
    /// The bounding sphere of [`positions`](Model::positions).
    pub sphere: Sphere,
    /// Added to the original positions before scaling.
    pub offset: [f64; 3],
    /// The uniform scale applied after the offset.
    pub scale: f64,
    /// Degenerate triangles (no area) that were dropped.
    pub degenerate: usize,
    /// The files read: the OBJ's path, then each MTL file found.
    pub files: Vec<PathBuf>,
    /// Things that did not stop the import, one line each.
    pub warnings: Vec<String>,
}

/// `x` as raw 16.16 bits, rounded to nearest (ties away from zero), or
/// `None` if it is not finite or outside the 16.16 range.
///
/// ```
/// use microraster_import::to_fixed;
/// assert_eq!(to_fixed(1.0), Some(65536));
/// assert_eq!(to_fixed(-0.5), Some(-32768));
/// assert_eq!(to_fixed(1.0 / 131072.0), Some(1)); // a tie rounds away from zero
/// assert_eq!(to_fixed(32768.0), None);
/// ```
pub fn to_fixed(x: f64) -> Option<i32> {
    let r = (x * 65536.0).round();
    if r.is_finite() && r >= i32::MIN as f64 && r <= i32::MAX as f64 {
        Some(r as i32)
    } else {
        None
    }
}

/// [`to_fixed`], saturating at the range's ends (and 0 for NaN).
pub(super) fn to_fixed_saturating(x: f32) -> i32 {
    // `as` saturates and maps NaN to 0.
    (x as f64 * 65536.0).round() as i32
}

impl Model {
    /// The positions as raw I16F16 bits (round to nearest; saturating,
    /// which only matters if the positions were changed after import).
    pub fn positions_fixed(&self) -> Vec<[i32; 3]> {
        self.positions
            .iter()
            .map(|p| p.map(to_fixed_saturating))
            .collect()
    }

    /// The normals as raw I16F16 bits (round to nearest).
    pub fn normals_fixed(&self) -> Vec<[i32; 3]> {
        self.normals
            .iter()
            .map(|p| p.map(to_fixed_saturating))
            .collect()
    }

    /// The texture coordinates as raw I16F16 bits (round to nearest), in
    /// microraster's convention: `(u, 1 - v)`. An OBJ file's `v = 0` is
    /// the bottom of the image, a `microraster::texture::Texture`'s the top
    /// row (as in the PNG the importer converts), so `v` is flipped here and
    /// an imported model shows its textures upright. `uvs` keeps the
    /// file's values.
    pub fn uvs_fixed(&self) -> Vec<[i32; 2]> {
        self.uvs
            .iter()
            .map(|&[u, v]| [to_fixed_saturating(u), to_fixed_saturating(1.0 - v)])
            .collect()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Each cluster's bounding box, `[min, max]` of
    /// [`positions_fixed`](Model::positions_fixed) over its vertex run: the
    /// generated positions' own bits, so the box holds them exactly.
    /// A cluster without vertices (or with a run outside the positions, if
    /// the model was changed after import) gets zeros.
    ///
    /// ```
    /// use std::path::Path;
    /// use microraster_import::{parse_obj, ObjOptions};
    /// let obj = "v 0 0 0\nv 1 0 0\nv 0 2 0\nf 1 2 3\n";
    /// let options = ObjOptions::default().with_cluster_triangles(8);
    /// let model = parse_obj(obj, Path::new("t.obj"), |_| None, &options).unwrap();
    /// assert_eq!(model.cluster_bounds_fixed(), [[[0, 0, 0], [65536, 131072, 0]]]);
    /// ```
    pub fn cluster_bounds_fixed(&self) -> Vec<[[i32; 3]; 2]> {
        let fixed = self.positions_fixed();
        self.clusters
            .iter()
            .map(|c| {
                let run = fixed.get(c.vertices.clone()).unwrap_or(&[]);
                if run.is_empty() {
                    return [[0; 3]; 2];
                }
                let mut b = [[i32::MAX; 3], [i32::MIN; 3]];
                for p in run {
                    for k in 0..3 {
                        b[0][k] = b[0][k].min(p[k]);
                        b[1][k] = b[1][k].max(p[k]);
                    }
                }
                b
            })
            .collect()
    }
}

/// A colour channel in 0..1 (clamped) to 0..255, rounded to nearest.
pub(crate) fn unit_to_u8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}
