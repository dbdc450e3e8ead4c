//! What the importer is asked to do: how positions are fitted into 16.16
//! ([`Fit`]), the width of the generated indices ([`IndexWidth`]), and the
//! options and limits of an import ([`ObjOptions`]).

/// How positions are fitted into 16.16 fixed point (range ±32768,
/// resolution 1/65536).
///
/// Whatever is applied, `output = (input + offset) * scale` with the
/// [`Model::offset`](super::Model::offset) and
/// [`Model::scale`](super::Model::scale) reported, so
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
    /// is an error
    /// ([`ErrorKind::TooManyCorners`](crate::ErrorKind::TooManyCorners)).
    /// Raised above
    /// [`EAR_CLIPPING_MAX_CORNERS`](super::EAR_CLIPPING_MAX_CORNERS)
    /// (256), it lets larger faces in, and those are fan-triangulated
    /// around their first corner (ear clipping
    /// costs up to the cube of the corner count), which is right for
    /// convex faces only.
    pub max_face_corners: usize,
    /// The most triangles per cluster, or 0 (the default) for no clusters.
    ///
    /// When it is not 0, each group's triangles are split in space into
    /// clusters of at most this many, for per-cluster frustum culling: see
    /// [`Model::clusters`](super::Model::clusters) and
    /// [the module documentation](super#clusters).
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
