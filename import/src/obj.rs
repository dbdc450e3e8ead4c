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
//!   plane (see [`triangulate`]). A face of more than
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

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::io;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{escape_controls, ErrorKind, ImportError};

mod mtl;

/// How positions are fitted into 16.16 fixed point (range ±32768,
/// resolution 1/65536).
///
/// Whatever is applied, `output = (input + offset) * scale` with the
/// [`Model::offset`] and [`Model::scale`] reported, so
/// `input = output / scale - offset`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Fit {
    /// Keep the coordinates as they are (offset 0, scale 1); it is an error
    /// if one cannot be represented in 16.16.
    Keep,
    /// Move the bounding box centre to the origin and scale uniformly so
    /// that the bounding sphere's radius is 1.
    Unit,
    /// [`Keep`](Fit::Keep) when every coordinate is within ±1024 and the
    /// bounding sphere's radius is at least 1/64 (so the model has at least
    /// ~1,000 steps of 16.16 resolution across it), [`Unit`](Fit::Unit)
    /// otherwise.
    #[default]
    Auto,
}

impl Fit {
    /// The lower-case name used on the command line: `keep`, `unit`, `auto`.
    pub fn name(self) -> &'static str {
        match self {
            Fit::Keep => "keep",
            Fit::Unit => "unit",
            Fit::Auto => "auto",
        }
    }

    /// The fit of that [`name`](Fit::name), if any.
    pub fn from_name(name: &str) -> Option<Fit> {
        match name {
            "keep" => Some(Fit::Keep),
            "unit" => Some(Fit::Unit),
            "auto" => Some(Fit::Auto),
            _ => None,
        }
    }
}

/// The integer type of the output's triangle indices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IndexWidth {
    /// `u16`, what microraster's `Mesh` takes: at most 65,536 vertices.
    #[default]
    U16,
    /// `u32`, for models too big for `u16` (split them before drawing).
    U32,
}

impl IndexWidth {
    /// How many vertices indices of this width address.
    pub fn max_vertices(self) -> usize {
        match self {
            IndexWidth::U16 => 1 << 16,
            IndexWidth::U32 => usize::try_from(1u64 << 32).unwrap_or(usize::MAX),
        }
    }

    /// The Rust type name: `u16` or `u32`.
    pub fn rust_type(self) -> &'static str {
        match self {
            IndexWidth::U16 => "u16",
            IndexWidth::U32 => "u32",
        }
    }
}

/// Options of the OBJ import.
///
/// ```
/// use microraster_import::{Fit, IndexWidth, ObjOptions};
/// let options = ObjOptions::default()
///     .with_fit(Fit::Unit)
///     .with_index_width(IndexWidth::U32)
///     .with_compute_normals(false);
/// assert_eq!(options.fit, Fit::Unit);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct ObjOptions {
    /// How positions are moved into the 16.16 range (default [`Fit::Auto`]).
    pub fit: Fit,
    /// Triangle index type (default [`IndexWidth::U16`]); more unique
    /// vertices than it addresses is an error.
    pub index_width: IndexWidth,
    /// Compute area-weighted normals for vertices that have no `vn`
    /// (default `true`). When `false`, normals are output only if every
    /// vertex has a `vn`.
    pub compute_normals: bool,
    /// The most `v`, `vt` and `vn` statements accepted, each
    /// (default 4,194,304).
    pub max_elements: usize,
    /// The most triangles accepted, after triangulation (default
    /// 1,048,576).
    pub max_triangles: usize,
    /// The most corners accepted in one face (default 256); a face of more
    /// is an error ([`ErrorKind::TooManyCorners`]). Raised above
    /// [`EAR_CLIPPING_MAX_CORNERS`] (256), it lets larger faces in, and
    /// those are fan-triangulated around their first corner (ear clipping
    /// costs up to the cube of the corner count), which is right for
    /// convex faces only.
    pub max_face_corners: usize,
    /// The most triangles per cluster, or 0 (the default) for no clusters.
    ///
    /// When it is not 0, each group's triangles are split in space into
    /// clusters of at most this many, for per-cluster frustum culling: see
    /// [`Model::clusters`] and [the module documentation](self#clusters).
    /// Vertices that several clusters share are copied into each, so the
    /// model can have more vertices than without clusters (and more than
    /// [`index_width`](ObjOptions::index_width) addresses, an error);
    /// smaller clusters cull more finely but copy more vertices.
    pub cluster_triangles: usize,
    /// Read material libraries and keep texture names that lie outside the
    /// OBJ file's folder (default `false`).
    ///
    /// A name with `..` that climbs out of the folder, or an absolute one
    /// (`/etc/passwd`, `C:\\x.mtl`), is otherwise refused with a warning:
    /// the library is not read, the texture name is dropped. A model from
    /// elsewhere cannot make the importer read, or the firmware build use,
    /// files beside it then. See [`crate::paths`].
    pub outside_files: bool,
}

impl Default for ObjOptions {
    fn default() -> Self {
        Self {
            fit: Fit::Auto,
            index_width: IndexWidth::U16,
            compute_normals: true,
            max_elements: 1 << 22,
            max_triangles: 1 << 20,
            max_face_corners: 256,
            cluster_triangles: 0,
            outside_files: false,
        }
    }
}

impl ObjOptions {
    /// The defaults.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets [`fit`](ObjOptions::fit).
    pub fn with_fit(mut self, fit: Fit) -> Self {
        self.fit = fit;
        self
    }

    /// Sets [`index_width`](ObjOptions::index_width).
    pub fn with_index_width(mut self, index_width: IndexWidth) -> Self {
        self.index_width = index_width;
        self
    }

    /// Sets [`compute_normals`](ObjOptions::compute_normals).
    pub fn with_compute_normals(mut self, compute_normals: bool) -> Self {
        self.compute_normals = compute_normals;
        self
    }

    /// Sets [`max_elements`](ObjOptions::max_elements).
    pub fn with_max_elements(mut self, max_elements: usize) -> Self {
        self.max_elements = max_elements;
        self
    }

    /// Sets [`max_triangles`](ObjOptions::max_triangles).
    pub fn with_max_triangles(mut self, max_triangles: usize) -> Self {
        self.max_triangles = max_triangles;
        self
    }

    /// Sets [`max_face_corners`](ObjOptions::max_face_corners).
    pub fn with_max_face_corners(mut self, max_face_corners: usize) -> Self {
        self.max_face_corners = max_face_corners;
        self
    }

    /// Sets [`cluster_triangles`](ObjOptions::cluster_triangles): the most
    /// triangles per cluster, 0 for no clusters.
    ///
    /// ```
    /// use std::path::Path;
    /// use microraster_import::{parse_obj, ObjOptions};
    /// // Two quads far apart: one cluster each.
    /// let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
    ///            v 9 0 0\nv 10 0 0\nv 10 1 0\nv 9 1 0\n\
    ///            f 1 2 3 4\nf 5 6 7 8\n";
    /// let options = ObjOptions::default().with_cluster_triangles(2);
    /// let model = parse_obj(obj, Path::new("quads.obj"), |_| None, &options).unwrap();
    /// assert_eq!(model.clusters.len(), 2);
    /// assert_eq!(model.clusters[1].triangles, 2..4);
    /// assert_eq!(model.clusters[1].vertices, 4..8);
    /// assert_eq!(model.groups[0].clusters, 0..2);
    /// ```
    pub fn with_cluster_triangles(mut self, cluster_triangles: usize) -> Self {
        self.cluster_triangles = cluster_triangles;
        self
    }

    /// Sets [`outside_files`](ObjOptions::outside_files): whether files
    /// outside the OBJ file's folder may be named.
    pub fn with_outside_files(mut self, outside_files: bool) -> Self {
        self.outside_files = outside_files;
        self
    }
}

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
/// [the module documentation](self#clusters)).
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
fn to_fixed_saturating(x: f32) -> i32 {
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

    /// Lays the triangles and vertices out in clusters of at most `max`
    /// triangles (see [the module documentation](self#clusters)).
    ///
    /// Expects what the parser makes: groups that tile the triangles in
    /// order, indices in range, per-vertex arrays full or empty.
    fn cluster(&mut self, max: usize) -> Result<(), ErrorKind> {
        // The generated `Cluster` holds counts as u32, and a cluster has at
        // most three vertices per triangle: this keeps both in range.
        let max = max.clamp(1, u32::MAX as usize / 3);
        let centroids: Vec<[f64; 3]> = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize].map(f64::from));
                std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0)
            })
            .collect();
        // The triangles in their new order (old indices), and the clusters
        // as ranges of it, which are also the new triangle ranges.
        let mut order: Vec<usize> = Vec::with_capacity(self.triangles.len());
        let mut leaves: Vec<Range<usize>> = Vec::new();
        for g in &mut self.groups {
            let first = leaves.len();
            let start = order.len();
            order.extend(g.triangles.clone());
            split(&mut order[start..], start, &centroids, max, &mut leaves);
            g.clusters = first..leaves.len();
        }

        let old_count = self.positions.len();
        // Per old vertex: the last cluster that used it, and its index there.
        let mut owner = vec![usize::MAX; old_count];
        let mut local = vec![0u32; old_count];
        // The old vertex of each new one.
        let mut source: Vec<usize> = Vec::new();
        let mut triangles = Vec::with_capacity(order.len());
        let mut clusters = Vec::with_capacity(leaves.len());
        for (k, leaf) in leaves.into_iter().enumerate() {
            let first = source.len();
            for &t in &order[leaf.clone()] {
                triangles.push(self.triangles[t].map(|v| {
                    let v = v as usize;
                    if owner[v] != k {
                        owner[v] = k;
                        // Saturate rather than wrap: the count check below
                        // fails first.
                        local[v] = u32::try_from(source.len()).unwrap_or(u32::MAX);
                        source.push(v);
                    }
                    local[v]
                }));
            }
            clusters.push(ClusterRange {
                triangles: leaf,
                vertices: first..source.len(),
            });
        }
        let limit = self.options.index_width.max_vertices();
        if source.len() > limit {
            let used = owner.iter().filter(|&&k| k != usize::MAX).count();
            return Err(ErrorKind::TooManyVertices {
                count: source.len(),
                limit,
                duplicated: source.len() - used,
            });
        }
        self.positions = gather(&self.positions, &source);
        self.normals = gather(&self.normals, &source);
        self.uvs = gather(&self.uvs, &source);
        self.colors = gather(&self.colors, &source);
        self.triangles = triangles;
        self.clusters = clusters;
        Ok(())
    }
}

/// Splits `triangles` (indices into `centroids`, at `offset` in the new
/// order) along the longest axis of their centroids' box, the lower part
/// holding half the full clusters needed, recursively, until a part has at
/// most `max`; appends the parts' ranges to `out`, the lower part's first,
/// so that neighbours in the list are neighbours in space. `max` must be
/// at least 1.
fn split(
    triangles: &mut [usize],
    offset: usize,
    centroids: &[[f64; 3]],
    max: usize,
    out: &mut Vec<Range<usize>>,
) {
    if triangles.is_empty() {
        return;
    }
    if triangles.len() <= max {
        // The file's order: it is usually the modeller's strip order, and
        // a cluster no larger than its group stays as it was.
        triangles.sort_unstable();
        out.push(offset..offset + triangles.len());
        return;
    }
    let (lo, hi) = bounds(triangles.iter().map(|&t| centroids[t]));
    let axis = (1..3).fold(0, |a, k| if hi[k] - lo[k] > hi[a] - lo[a] { k } else { a });
    // The index breaks ties, so the order is total and the output the same
    // whatever the sort algorithm.
    triangles.sort_unstable_by(|&a, &b| {
        centroids[a][axis]
            .total_cmp(&centroids[b][axis])
            .then(a.cmp(&b))
    });
    // Cut where the lower part holds a whole number of full clusters, half
    // of them (rounded up): clusters come out full rather than halved
    // below the limit (9,216 triangles in clusters of 64 make 144
    // clusters, not 256 of 36). With k = ceil(len / max) >= 2 clusters
    // needed, the lower part holds max ceil(k / 2) < len triangles and the
    // upper part at least one.
    let k = triangles.len().div_ceil(max);
    let mid = max * k.div_ceil(2);
    let (low, high) = triangles.split_at_mut(mid);
    split(low, offset, centroids, max, out);
    split(high, offset + mid, centroids, max, out);
}

/// `values[i]` for each `i` of `source`; empty for an absent array.
fn gather<T: Copy>(values: &[T], source: &[usize]) -> Vec<T> {
    if values.is_empty() {
        return Vec::new();
    }
    source.iter().map(|&i| values[i]).collect()
}

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

type Loader<'a> = dyn FnMut(&str) -> Result<Option<(PathBuf, String)>, ImportError> + 'a;

/// Logical lines: comments stripped, `\` continuations joined, with the
/// 1-based number of each one's first physical line.
struct Lines<'a> {
    physical: std::iter::Enumerate<std::str::Split<'a, char>>,
}

impl<'a> Lines<'a> {
    fn new(source: &'a str) -> Self {
        // Editors on Windows save UTF-8 with a byte-order mark; left in, it
        // would glue onto the first keyword and that statement be ignored.
        let source = source.strip_prefix('\u{FEFF}').unwrap_or(source);
        Self {
            physical: source.split('\n').enumerate(),
        }
    }
}

impl Iterator for Lines<'_> {
    type Item = (usize, String);

    fn next(&mut self) -> Option<(usize, String)> {
        let mut logical = String::new();
        let mut start = None;
        for (i, raw) in self.physical.by_ref() {
            start.get_or_insert(i + 1);
            let content = match raw.find('#') {
                Some(p) => &raw[..p],
                None => raw,
            };
            let content = content.trim_end();
            match content.strip_suffix('\\') {
                Some(head) => {
                    logical.push_str(head);
                    logical.push(' ');
                }
                None => {
                    logical.push_str(content);
                    return Some((start.unwrap_or(i + 1), logical));
                }
            }
        }
        start.map(|line| (line, logical))
    }
}

/// Which of a corner's parts are present: (texture coordinate, normal).
type Form = (bool, bool);

const NONE: u32 = u32::MAX;

/// A resolved face corner: 0-based (position, texture coordinate, normal),
/// [`NONE`] where absent.
type Corner = [u32; 3];

struct GroupBuild {
    name: String,
    material: Option<String>,
    triangles: Vec<[Corner; 3]>,
}

struct Parser<'p> {
    path: &'p Path,
    options: &'p ObjOptions,
    positions: Vec<[f32; 3]>,
    /// Per position; empty until the first coloured `v`.
    colors: Vec<Option<[f32; 3]>>,
    texcoords: Vec<[f32; 2]>,
    normals: Vec<[f32; 3]>,
    groups: Vec<GroupBuild>,
    group_index: HashMap<(String, Option<String>), usize>,
    /// The index in `groups` of the current (group, material), once known.
    current: Option<usize>,
    group: String,
    material: Option<String>,
    materials: HashMap<String, Material>,
    triangle_count: usize,
    degenerate: usize,
    ignored: BTreeMap<String, usize>,
    files: Vec<PathBuf>,
    warnings: Vec<String>,
}

const MAX_IGNORED_KINDS: usize = 32;

fn parse(
    source: &str,
    path: &Path,
    loader: &mut Loader<'_>,
    options: &ObjOptions,
) -> Result<Model, ImportError> {
    let mut p = Parser {
        path,
        options,
        positions: Vec::new(),
        colors: Vec::new(),
        texcoords: Vec::new(),
        normals: Vec::new(),
        groups: Vec::new(),
        group_index: HashMap::new(),
        current: None,
        group: "default".to_string(),
        material: None,
        materials: HashMap::new(),
        triangle_count: 0,
        degenerate: 0,
        ignored: BTreeMap::new(),
        files: vec![path.to_path_buf()],
        warnings: Vec::new(),
    };
    for (line, text) in Lines::new(source) {
        p.statement(line, &text, loader)?;
    }
    p.finish()
}

fn malformed(statement: &str, message: String) -> ErrorKind {
    ErrorKind::Malformed {
        statement: statement.to_string(),
        message,
    }
}

/// At most 40 characters of `s`, for messages.
fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(40).collect();
        t.push_str("...");
        t
    }
}

fn number(statement: &str, token: &str) -> Result<f32, ErrorKind> {
    match token.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(ErrorKind::NonFinite { token: clip(token) }),
        Err(_) => Err(malformed(
            statement,
            format!("expected a number, found `{}`", clip(token)),
        )),
    }
}

fn numbers<const N: usize>(statement: &str, tokens: &[&str]) -> Result<[f32; N], ErrorKind> {
    let mut out = [0.0; N];
    for (o, t) in out.iter_mut().zip(tokens) {
        *o = number(statement, t)?;
    }
    Ok(out)
}

/// The rest of a statement after its keyword, whitespace runs collapsed.
fn rest(tokens: &[&str]) -> String {
    tokens.join(" ")
}

fn resolve(index: i64, defined: usize, element: &'static str) -> Result<u32, ErrorKind> {
    let out_of_range = ErrorKind::IndexOutOfRange {
        element,
        index,
        defined,
    };
    let i = match index {
        0 => return Err(ErrorKind::ZeroIndex { element }),
        i if i > 0 => i as u64 - 1,
        i => match (defined as u64).checked_sub(i.unsigned_abs()) {
            Some(i) => i,
            None => return Err(out_of_range),
        },
    };
    if i < defined as u64 {
        // `defined` is bounded by `max_elements`, itself below u32::MAX.
        u32::try_from(i).map_err(|_| out_of_range)
    } else {
        Err(out_of_range)
    }
}

/// A corner's written indices: position, optional texture coordinate,
/// optional normal.
fn parse_corner(token: &str) -> Result<(i64, Option<i64>, Option<i64>), ErrorKind> {
    let bad = |what: &str| {
        malformed(
            "f",
            format!(
                "{what} in corner `{}` (expected v, v/vt, v//vn or v/vt/vn)",
                clip(token)
            ),
        )
    };
    let mut parts = token.split('/');
    let v = parts.next().unwrap_or("");
    let vt = parts.next().unwrap_or("");
    let vn = parts.next().unwrap_or("");
    if parts.next().is_some() {
        return Err(bad("too many `/`"));
    }
    let index = |s: &str| -> Result<Option<i64>, ErrorKind> {
        if s.is_empty() {
            Ok(None)
        } else {
            s.parse::<i64>()
                .map(Some)
                .map_err(|_| bad(&format!("bad index `{}`", clip(s))))
        }
    };
    let v = index(v)?.ok_or_else(|| bad("no vertex index"))?;
    Ok((v, index(vt)?, index(vn)?))
}

impl Parser<'_> {
    fn err(&self, line: usize, kind: ErrorKind) -> ImportError {
        ImportError::new(self.path, Some(line), kind)
    }

    fn statement(
        &mut self,
        line: usize,
        text: &str,
        loader: &mut Loader<'_>,
    ) -> Result<(), ImportError> {
        let mut tokens = text.split_whitespace();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        let args: Vec<&str> = tokens.collect();
        let result = match keyword {
            "v" => self.vertex(&args),
            "vt" => self.texcoord(&args),
            "vn" => self.normal(&args),
            "f" => self.face(&args),
            "o" | "g" => {
                self.current = None;
                let name = rest(&args);
                self.group = if name.is_empty() {
                    "default".to_string()
                } else {
                    name
                };
                Ok(())
            }
            "usemtl" => {
                self.current = None;
                let name = rest(&args);
                self.material = (!name.is_empty()).then_some(name);
                Ok(())
            }
            "mtllib" => return self.mtllib(line, &args, loader),
            other => {
                let n = self.ignored.len();
                match self.ignored.get_mut(other) {
                    Some(count) => *count += 1,
                    None if n < MAX_IGNORED_KINDS => {
                        self.ignored.insert(other.to_string(), 1);
                    }
                    None => *self.ignored.entry("(other)".to_string()).or_insert(0) += 1,
                }
                Ok(())
            }
        };
        result.map_err(|kind| self.err(line, kind))
    }

    fn check_count(&self, len: usize, element: &'static str) -> Result<(), ErrorKind> {
        let limit = self.options.max_elements.min(NONE as usize - 1);
        if len >= limit {
            Err(ErrorKind::TooManyElements { element, limit })
        } else {
            Ok(())
        }
    }

    fn vertex(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.positions.len(), "vertex")?;
        let (position, color) = match args.len() {
            3 | 4 => {
                if let Some(w) = args.get(3) {
                    number("v", w)?;
                }
                (numbers("v", args)?, None)
            }
            6 => {
                let [x, y, z, r, g, b] = numbers("v", args)?;
                ([x, y, z], Some([r, g, b]))
            }
            n => {
                return Err(malformed(
                    "v",
                    format!("expected x y z, x y z w or x y z r g b; found {n} values"),
                ))
            }
        };
        self.positions.push(position);
        if color.is_some() || !self.colors.is_empty() {
            // Earlier vertices (before the first coloured one) have none.
            self.colors.resize(self.positions.len() - 1, None);
            self.colors.push(color);
        }
        Ok(())
    }

    fn texcoord(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.texcoords.len(), "texture coordinate")?;
        if args.is_empty() || args.len() > 3 {
            return Err(malformed(
                "vt",
                format!("expected u, u v or u v w; found {} values", args.len()),
            ));
        }
        let u = number("vt", args[0])?;
        let v = match args.get(1) {
            Some(t) => number("vt", t)?,
            None => 0.0,
        };
        if let Some(w) = args.get(2) {
            number("vt", w)?;
        }
        for value in [u, v] {
            if to_fixed(value as f64).is_none() {
                return Err(ErrorKind::OutOfFixedRange {
                    what: "texture",
                    value: value as f64,
                });
            }
        }
        self.texcoords.push([u, v]);
        Ok(())
    }

    fn normal(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.normals.len(), "normal")?;
        if args.len() != 3 {
            return Err(malformed(
                "vn",
                format!("expected x y z; found {} values", args.len()),
            ));
        }
        self.normals.push(numbers("vn", args)?);
        Ok(())
    }

    fn face(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        if args.len() < 3 {
            return Err(malformed(
                "f",
                format!("a face needs at least 3 corners, found {}", args.len()),
            ));
        }
        if args.len() > self.options.max_face_corners {
            return Err(ErrorKind::TooManyCorners {
                count: args.len(),
                limit: self.options.max_face_corners,
            });
        }
        let mut corners: Vec<Corner> = Vec::with_capacity(args.len());
        let mut form: Option<Form> = None;
        for token in args {
            let (v, vt, vn) = parse_corner(token)?;
            let this: Form = (vt.is_some(), vn.is_some());
            match form {
                None => form = Some(this),
                Some(f) if f != this => {
                    return Err(ErrorKind::MixedFaceForms {
                        first: clip(args[0]),
                        other: clip(token),
                    })
                }
                Some(_) => {}
            }
            let v = resolve(v, self.positions.len(), "vertex")?;
            let vt = match vt {
                Some(i) => resolve(i, self.texcoords.len(), "texture coordinate")?,
                None => NONE,
            };
            let vn = match vn {
                Some(i) => resolve(i, self.normals.len(), "normal")?,
                None => NONE,
            };
            corners.push([v, vt, vn]);
        }
        let points: Vec<[f64; 3]> = corners
            .iter()
            .map(|c| self.positions[c[0] as usize].map(f64::from))
            .collect();
        for [a, b, c] in triangulate(&points) {
            let tri = [corners[a], corners[b], corners[c]];
            let area2 = cross(sub(points[b], points[a]), sub(points[c], points[a]));
            if tri[0][0] == tri[1][0]
                || tri[1][0] == tri[2][0]
                || tri[0][0] == tri[2][0]
                || dot(area2, area2) == 0.0
            {
                self.degenerate += 1;
                continue;
            }
            if self.triangle_count >= self.options.max_triangles {
                return Err(ErrorKind::TooManyTriangles {
                    limit: self.options.max_triangles,
                });
            }
            self.triangle_count += 1;
            let g = match self.current {
                Some(g) => g,
                None => {
                    let key = (self.group.clone(), self.material.clone());
                    let next = self.groups.len();
                    let g = *self.group_index.entry(key).or_insert(next);
                    if g == next {
                        self.groups.push(GroupBuild {
                            name: self.group.clone(),
                            material: self.material.clone(),
                            triangles: Vec::new(),
                        });
                    }
                    self.current = Some(g);
                    g
                }
            };
            self.groups[g].triangles.push(tri);
        }
        Ok(())
    }

    fn finish(self) -> Result<Model, ImportError> {
        let whole = |kind| ImportError::new(self.path, None, kind);
        if self.triangle_count == 0 {
            return Err(whole(ErrorKind::NoTriangles {
                degenerate: self.degenerate,
            }));
        }
        let mut warnings = self.warnings;

        // Unique vertices, numbered in the order triangles first use them.
        let mut index: HashMap<Corner, u32> = HashMap::new();
        let mut corners: Vec<Corner> = Vec::new();
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(self.triangle_count);
        let mut groups = Vec::with_capacity(self.groups.len());
        let mut undefined: Vec<String> = Vec::new();
        for g in &self.groups {
            let start = triangles.len();
            for tri in &g.triangles {
                triangles.push(tri.map(|c| {
                    *index.entry(c).or_insert_with(|| {
                        corners.push(c);
                        // At most 3 * max_triangles corners; saturate rather
                        // than wrap (the count check below fails first).
                        u32::try_from(corners.len() - 1).unwrap_or(u32::MAX)
                    })
                }));
            }
            let material = g.material.as_ref().map(|name| {
                self.materials.get(name).cloned().unwrap_or_else(|| {
                    if !undefined.contains(name) {
                        undefined.push(name.clone());
                    }
                    Material {
                        name: name.clone(),
                        diffuse: [1.0; 3],
                        texture: None,
                    }
                })
            });
            groups.push(Group {
                name: g.name.clone(),
                material,
                triangles: start..triangles.len(),
                clusters: 0..0,
            });
        }
        for name in undefined {
            warnings.push(format!(
                "material `{}` is not defined; it is white",
                escape_controls(&name)
            ));
        }
        let limit = self.options.index_width.max_vertices();
        if corners.len() > limit {
            return Err(whole(ErrorKind::TooManyVertices {
                count: corners.len(),
                limit,
                duplicated: 0,
            }));
        }

        let source_pos = |c: &Corner| self.positions[c[0] as usize].map(f64::from);

        // Fit into 16.16.
        let (min, max) = bounds(corners.iter().map(source_pos));
        let center: [f64; 3] = std::array::from_fn(|k| (min[k] + max[k]) / 2.0);
        let radius = corners
            .iter()
            .map(|c| length(sub(source_pos(c), center)))
            .fold(0.0, f64::max);
        let largest = (0..3)
            .map(|k| min[k].abs().max(max[k].abs()))
            .fold(0.0, f64::max);
        let fit_applied = match self.options.fit {
            Fit::Auto if largest <= 1024.0 && radius >= 1.0 / 64.0 => Fit::Keep,
            Fit::Auto => Fit::Unit,
            f => f,
        };
        let (offset, scale) =
            if fit_applied == Fit::Unit && radius > 0.0 && (1.0 / radius).is_finite() {
                (center.map(|c| -c), 1.0 / radius)
            } else {
                ([0.0; 3], 1.0)
            };
        if fit_applied == Fit::Keep {
            for value in [min, max].iter().flatten() {
                if to_fixed(*value).is_none() {
                    return Err(whole(ErrorKind::OutOfFixedRange {
                        what: "position",
                        value: *value,
                    }));
                }
            }
        }
        let positions: Vec<[f32; 3]> = corners
            .iter()
            .map(|c| {
                let p = source_pos(c);
                std::array::from_fn(|k| ((p[k] + offset[k]) * scale) as f32)
            })
            .collect();
        // Triangles that 16.16 rounding flattens (far smaller than the
        // model): kept, but worth knowing about.
        let fixed: Vec<[i128; 3]> = positions
            .iter()
            .map(|p| p.map(|c| to_fixed_saturating(c) as i128))
            .collect();
        let collapsed = triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| fixed[i as usize]);
                let (u, v) = (
                    [0, 1, 2].map(|k| b[k] - a[k]),
                    [0, 1, 2].map(|k| c[k] - a[k]),
                );
                u[1] * v[2] == u[2] * v[1]
                    && u[2] * v[0] == u[0] * v[2]
                    && u[0] * v[1] == u[1] * v[0]
            })
            .count();
        if collapsed > 0 {
            warnings.push(format!(
                "{collapsed} triangle(s) have no area at 16.16 resolution \
                 (too small for the model's size)"
            ));
        }
        let (min, max) = bounds(positions.iter().map(|p| p.map(f64::from)));
        let center: [f64; 3] = std::array::from_fn(|k| (min[k] + max[k]) / 2.0);
        let radius = positions
            .iter()
            .map(|p| length(sub(p.map(f64::from), center)))
            .fold(0.0, f64::max);

        // Normals.
        let given = |c: &Corner| -> Option<[f64; 3]> {
            let n = self.normals.get(c[2] as usize)?.map(f64::from);
            normalize(n)
        };
        let all_given = corners.iter().all(|c| given(c).is_some());
        let any_given = corners.iter().any(|c| c[2] != NONE);
        let normals: Vec<[f32; 3]> = if all_given {
            corners
                .iter()
                .map(|c| given(c).unwrap_or([0.0, 0.0, 1.0]).map(|x| x as f32))
                .collect()
        } else if self.options.compute_normals {
            let mut sums = vec![[0.0f64; 3]; self.positions.len()];
            let mut first: Vec<Option<[f64; 3]>> = vec![None; self.positions.len()];
            for tri in &triangles {
                let [a, b, c] = tri.map(|i| source_pos(&corners[i as usize]));
                let n = cross(sub(b, a), sub(c, a));
                for &i in tri {
                    let v = corners[i as usize][0] as usize;
                    sums[v] = add(sums[v], n);
                    first[v].get_or_insert(n);
                }
            }
            corners
                .iter()
                .map(|c| {
                    let v = c[0] as usize;
                    given(c)
                        .or_else(|| normalize(sums[v]))
                        .or_else(|| first[v].and_then(normalize))
                        .unwrap_or([0.0, 0.0, 1.0])
                        .map(|x| x as f32)
                })
                .collect()
        } else {
            if any_given {
                warnings.push(
                    "some vertices have no usable `vn` and normal computation is off; normals dropped"
                        .to_string(),
                );
            }
            Vec::new()
        };

        // Texture coordinates.
        let missing_uv = corners.iter().filter(|c| c[1] == NONE).count();
        let uvs: Vec<[f32; 2]> = if missing_uv == corners.len() {
            Vec::new()
        } else {
            if missing_uv > 0 {
                warnings.push(format!(
                    "{missing_uv} vertices have no `vt`; their texture coordinates are (0, 0)"
                ));
            }
            corners
                .iter()
                .map(|c| {
                    self.texcoords
                        .get(c[1] as usize)
                        .copied()
                        .unwrap_or([0.0; 2])
                })
                .collect()
        };

        // Colours.
        let color = |c: &Corner| self.colors.get(c[0] as usize).copied().flatten();
        let missing_color = corners.iter().filter(|c| color(c).is_none()).count();
        let colors: Vec<[u8; 3]> = if missing_color == corners.len() {
            Vec::new()
        } else {
            if missing_color > 0 {
                warnings.push(format!(
                    "{missing_color} vertices have no colour; they are white"
                ));
            }
            corners
                .iter()
                .map(|c| color(c).unwrap_or([1.0; 3]).map(unit_to_u8))
                .collect()
        };

        if self.degenerate > 0 {
            warnings.push(format!(
                "dropped {} degenerate triangle(s) (no area)",
                self.degenerate
            ));
        }
        for (keyword, count) in &self.ignored {
            warnings.push(format!(
                "ignored {count} `{}` statement(s)",
                escape_controls(&clip(keyword))
            ));
        }

        let mut model = Model {
            source: self.path.to_path_buf(),
            options: self.options.clone(),
            fit_applied,
            positions,
            normals,
            uvs,
            colors,
            triangles,
            groups,
            clusters: Vec::new(),
            bounds: Aabb {
                min: min.map(|x| x as f32),
                max: max.map(|x| x as f32),
            },
            sphere: Sphere {
                center: center.map(|x| x as f32),
                radius: radius as f32,
            },
            offset,
            scale,
            degenerate: self.degenerate,
            files: self.files,
            warnings,
        };
        // Last, on the final arrays: the layout changes, the data does not.
        if self.options.cluster_triangles > 0 {
            model
                .cluster(self.options.cluster_triangles)
                .map_err(whole)?;
        }
        Ok(model)
    }
}

/// A colour channel in 0..1 (clamped) to 0..255, rounded to nearest.
pub(crate) fn unit_to_u8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn bounds(points: impl Iterator<Item = [f64; 3]>) -> ([f64; 3], [f64; 3]) {
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    if min[0] > max[0] {
        ([0.0; 3], [0.0; 3])
    } else {
        (min, max)
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = length(a);
    (l > 0.0 && l.is_finite()).then(|| a.map(|x| x / l))
}

/// Polygons with more corners than this are fan-triangulated: ear clipping
/// costs up to the cube of the corner count.
pub const EAR_CLIPPING_MAX_CORNERS: usize = 256;

/// Splits a polygon into triangles, as indices into `points`, keeping its
/// winding.
///
/// A triangle is returned as is. A larger polygon is projected onto the
/// plane of its dominant axis (from Newell's normal) and ear-clipped there,
/// so convex and concave simple polygons are split exactly, into
/// `points.len() - 2` triangles. Polygons with no area, self-intersecting
/// ones where no ear is left, and ones with more than
/// [`EAR_CLIPPING_MAX_CORNERS`] corners fall back to a fan around the
/// first remaining corner; any degenerate triangles that gives are dropped
/// by the importer. Never panics.
///
/// ```
/// use microraster_import::triangulate;
/// // An L shape: a fan from corner 0 would cover the notch.
/// let l = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0],
///          [1.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
/// assert_eq!(triangulate(&l).len(), 4);
/// ```
pub fn triangulate(points: &[[f64; 3]]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let fan = |rest: &[usize]| -> Vec<[usize; 3]> {
        (1..rest.len().saturating_sub(1))
            .map(|i| [rest[0], rest[i], rest[i + 1]])
            .collect()
    };
    let all: Vec<usize> = (0..n).collect();
    if n > EAR_CLIPPING_MAX_CORNERS {
        return fan(&all);
    }
    // Newell's normal, and the plane of its largest component.
    let mut normal = [0.0f64; 3];
    for i in 0..n {
        let a = points[i];
        let b = points[(i + 1) % n];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let axis = (0..3)
        .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
        .unwrap_or(2);
    if normal[axis] == 0.0 || !normal[axis].is_finite() {
        return fan(&all);
    }
    // Project so that the polygon winds counter-clockwise in 2D.
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let flip = normal[axis] < 0.0;
    let p2: Vec<[f64; 2]> = points
        .iter()
        .map(|p| if flip { [p[v], p[u]] } else { [p[u], p[v]] })
        .collect();
    let turn = |a: usize, b: usize, c: usize| -> f64 {
        let (a, b, c) = (p2[a], p2[b], p2[c]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let mut remaining = all;
    let mut out = Vec::with_capacity(n - 2);
    // Starting at corner 1 makes a convex polygon's triangles those of the
    // fan around corner 0: (0, 1, 2), (0, 2, 3), ...
    let mut start = 1;
    while remaining.len() > 3 {
        let m = remaining.len();
        let ear = (0..m).map(|k| (start + k) % m).find(|&i| {
            let (a, b, c) = (
                remaining[(i + m - 1) % m],
                remaining[i],
                remaining[(i + 1) % m],
            );
            if turn(a, b, c) <= 0.0 {
                return false;
            }
            remaining.iter().all(|&q| {
                if q == a || q == b || q == c {
                    return true;
                }
                let pq = p2[q];
                if pq == p2[a] || pq == p2[b] || pq == p2[c] {
                    return true;
                }
                // Outside (strictly) of at least one edge.
                turn(a, b, q) < 0.0 || turn(b, c, q) < 0.0 || turn(c, a, q) < 0.0
            })
        });
        match ear {
            Some(i) => {
                out.push([
                    remaining[(i + m - 1) % m],
                    remaining[i],
                    remaining[(i + 1) % m],
                ]);
                remaining.remove(i);
                start = i % remaining.len();
            }
            None => {
                out.extend(fan(&remaining));
                return out;
            }
        }
    }
    out.push([remaining[0], remaining[1], remaining[2]]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_group_without_triangles_gets_an_empty_run_of_clusters() {
        // The parser drops empty groups; a model built by hand may have one.
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
                   g a\nf 1 2 3\nf 4 5 6\ng b\nf 3 2 1\n";
        let mut model = parse_obj(obj, Path::new("e.obj"), |_| None, &ObjOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let empty = |at: usize| Group {
            name: "empty".to_string(),
            material: None,
            triangles: at..at,
            clusters: 0..0,
        };
        model.groups.insert(0, empty(0));
        model.groups.insert(2, empty(2));
        model.groups.push(empty(3));
        model.cluster(1).unwrap_or_else(|e| panic!("{e}"));
        let runs: Vec<Range<usize>> = model.groups.iter().map(|g| g.clusters.clone()).collect();
        assert_eq!(runs, [0..0, 0..2, 2..2, 2..3, 3..3]);
        let triangles: Vec<Range<usize>> =
            model.groups.iter().map(|g| g.triangles.clone()).collect();
        assert_eq!(triangles, [0..0, 0..2, 2..2, 2..3, 3..3]);
        // Each cluster numbers its own copies in the order it uses them.
        assert_eq!(model.triangles, [[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
        assert_eq!(
            model.positions[6..],
            [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
        );
        assert_eq!(model.normals.len(), 9);
    }
}
