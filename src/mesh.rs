//! Indexed triangle meshes borrowed from flash (or any `'a` memory).
//!
//! A [`Mesh`] only borrows slices, so `static` arrays stay in flash and cost
//! no RAM. Every layout rule is checked once, when the mesh is built: an
//! index out of range or a per-vertex array of the wrong length is an error
//! then, never a panic or a wrong picture later. Building it also finds the
//! largest coordinate, so that the vertex stage knows once per draw whether
//! its fixed-point transform can overflow at all.

use embedded_graphics::pixelcolor::Rgb888;
use fixed::types::I16F16;

/// A vertex position or normal in model space, 16.16 fixed point.
pub type Vec3Fx = [I16F16; 3];

/// Texture coordinates `(u, v)` of a vertex, 16.16 fixed point: `0..1`
/// spans a texture once, `v = 0` is its top row (see
/// [`Texture::sample`](crate::texture::Texture::sample)).
pub type UvFx = [I16F16; 2];

/// An indexed triangle mesh.
///
/// Triangles list vertex indices counter-clockwise as seen from the front
/// (after projection, in normalised device coordinates with y up).
///
/// ```
/// use fixed::types::I16F16;
/// use microraster::mesh::{Mesh, MeshError};
/// const fn fx(v: i32) -> I16F16 { I16F16::from_bits(v << 16) }
/// static POSITIONS: [[I16F16; 3]; 3] = [
///     [fx(0), fx(0), fx(0)], [fx(1), fx(0), fx(0)], [fx(0), fx(1), fx(0)],
/// ];
/// static TRIANGLES: [[u16; 3]; 1] = [[0, 1, 2]];
/// let mesh = Mesh::new(&POSITIONS, &TRIANGLES).unwrap();
/// assert_eq!(mesh.triangle_count(), 1);
///
/// static BAD: [[u16; 3]; 1] = [[0, 1, 3]];
/// assert_eq!(
///     Mesh::new(&POSITIONS, &BAD).unwrap_err(),
///     MeshError::IndexOutOfRange { triangle: 0, index: 3, vertex_count: 3 }
/// );
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    positions: &'a [Vec3Fx],
    normals: Option<&'a [Vec3Fx]>,
    colors: Option<&'a [Rgb888]>,
    uvs: Option<&'a [UvFx]>,
    triangles: Indices<'a>,
    /// The largest magnitude of any position coordinate (raw 16.16), which
    /// bounds the vertex transform's sums once per draw.
    extent: u32,
    /// The smallest and largest coordinates of the positions (raw 16.16):
    /// the bounding box, for culling whole draws.
    bounds: [[i32; 3]; 2],
    /// Spatial clusters of the triangles, for culling parts of the mesh.
    clusters: Option<&'a [Cluster]>,
}

/// A cluster of a mesh's triangles: a run of consecutive triangles that
/// lie close together, the run of vertices they use, and the bounding box of
/// those vertices.
///
/// The clusters of a mesh ([`Mesh::with_clusters`]) tile its triangles in
/// order: the first cluster holds the first `triangle_count` triangles, the
/// next the following ones, and so on. The renderer tests each cluster's box
/// against the view frustum and, when it is outside, neither transforms the
/// cluster's vertices nor bins its triangles ([`crate::cull`]); a large
/// static mesh (a level, a terrain) then costs what is in view.
///
/// The importer makes clusters (`microraster-import obj --clusters N`),
/// each with a run of vertices of its own: a vertex that several clusters
/// use is copied into each (on the benchmark terrain, 43% more vertices in
/// clusters of 64 triangles, 20% in clusters of 256). Vertex runs must
/// ascend without overlapping (gaps are allowed), so that the vertex stage
/// never transforms a vertex twice. Culled clusters save time, not RAM: the
/// vertex buffer still holds a slot for every vertex of the frame's
/// meshes.
///
/// ```
/// use fixed::types::I16F16;
/// use microraster::mesh::{Cluster, Mesh};
/// const fn fx(v: i32) -> I16F16 { I16F16::from_bits(v << 16) }
/// // Two triangles far apart, one cluster each.
/// static POSITIONS: [[I16F16; 3]; 6] = [
///     [fx(0), fx(0), fx(0)], [fx(1), fx(0), fx(0)], [fx(0), fx(1), fx(0)],
///     [fx(9), fx(0), fx(0)], [fx(10), fx(0), fx(0)], [fx(9), fx(1), fx(0)],
/// ];
/// static TRIANGLES: [[u16; 3]; 2] = [[0, 1, 2], [3, 4, 5]];
/// static CLUSTERS: [Cluster; 2] = [
///     Cluster::new(1, 0, 3, [fx(0), fx(0), fx(0)], [fx(1), fx(1), fx(0)]),
///     Cluster::new(1, 3, 3, [fx(9), fx(0), fx(0)], [fx(10), fx(1), fx(0)]),
/// ];
/// let mesh = Mesh::new(&POSITIONS, &TRIANGLES)?.with_clusters(&CLUSTERS)?;
/// assert_eq!(mesh.clusters().map(|c| c.len()), Some(2));
/// # Ok::<(), microraster::mesh::MeshError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cluster {
    triangle_count: u32,
    first_vertex: u32,
    vertex_count: u32,
    min: Vec3Fx,
    max: Vec3Fx,
}

impl Cluster {
    /// A cluster of `triangle_count` triangles, using only the vertices
    /// `first_vertex .. first_vertex + vertex_count`, all of which lie in
    /// the box from `min` to `max` (checked by [`Mesh::with_clusters`]).
    pub const fn new(
        triangle_count: u32,
        first_vertex: u32,
        vertex_count: u32,
        min: Vec3Fx,
        max: Vec3Fx,
    ) -> Self {
        Self {
            triangle_count,
            first_vertex,
            vertex_count,
            min,
            max,
        }
    }

    /// The number of triangles.
    pub const fn triangle_count(&self) -> u32 {
        self.triangle_count
    }

    /// The first vertex its triangles may use.
    pub const fn first_vertex(&self) -> u32 {
        self.first_vertex
    }

    /// The number of vertices its triangles may use.
    pub const fn vertex_count(&self) -> u32 {
        self.vertex_count
    }

    /// The bounding box of its vertices: the smallest and the largest
    /// coordinates.
    pub const fn bounds(&self) -> [Vec3Fx; 2] {
        [self.min, self.max]
    }
}

/// A mesh's triangles: vertex indices, `u16` (compact, up to 65,536
/// vertices) or `u32` (for meshes with more vertices).
#[derive(Clone, Copy, Debug)]
pub enum Indices<'a> {
    /// Three `u16` indices per triangle.
    U16(&'a [[u16; 3]]),
    /// Three `u32` indices per triangle.
    U32(&'a [[u32; 3]]),
}

impl Indices<'_> {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        match self {
            Indices::U16(t) => t.len(),
            Indices::U32(t) => t.len(),
        }
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The triangles' vertex indices, in order.
    pub fn iter(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        (0..self.len()).map(|t| self.get(t))
    }

    /// The vertex indices of triangle `t` (which must be in range).
    #[inline(always)]
    pub fn get(&self, t: usize) -> [u32; 3] {
        match self {
            Indices::U16(tris) => {
                // Not `map`: a call per triangle where the optimiser does
                // not inline it (the `size` profile).
                let [a, b, c] = tris[t];
                [a as u32, b as u32, c as u32]
            }
            Indices::U32(tris) => tris[t],
        }
    }
}

/// Why a mesh could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshError {
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The out-of-range vertex index.
        index: u32,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A per-vertex array has a different length from `positions`.
    LengthMismatch {
        /// Which array: `"normals"`, `"colors"` or `"uvs"`.
        what: &'static str,
        /// Its length.
        len: usize,
        /// The number of positions.
        expected: usize,
    },
    /// More vertices than a `u16` index can reach (65,536).
    TooManyVertices {
        /// The number of positions given.
        count: usize,
    },
    /// The clusters hold a different number of triangles from the mesh.
    ClusterTriangles {
        /// The sum of the clusters' triangle counts.
        clustered: u64,
        /// The mesh's triangles.
        triangles: usize,
    },
    /// A cluster's vertex range goes past the last vertex.
    ClusterVertices {
        /// Index of the cluster.
        cluster: usize,
        /// One past the range's last vertex.
        end: u64,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A triangle uses a vertex outside its cluster's vertex range.
    ClusterIndex {
        /// Index of the cluster.
        cluster: usize,
        /// Index of the triangle (in the mesh).
        triangle: usize,
        /// The vertex index outside the cluster's range.
        index: u32,
    },
    /// A vertex of a cluster lies outside the cluster's bounding box.
    ClusterBounds {
        /// Index of the cluster.
        cluster: usize,
        /// The vertex outside the box.
        vertex: usize,
    },
    /// A cluster's bounding box has a minimum above its maximum.
    ClusterBox {
        /// Index of the cluster.
        cluster: usize,
    },
    /// A cluster's vertex run starts before the previous cluster's ends.
    ClusterOverlap {
        /// Index of the cluster.
        cluster: usize,
        /// Its first vertex.
        first_vertex: u32,
        /// One past the previous cluster's last vertex.
        previous_end: u64,
    },
}

impl core::fmt::Display for MeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::IndexOutOfRange {
                triangle,
                index,
                vertex_count,
            } => write!(
                f,
                "triangle {triangle} uses vertex index {index}, but the mesh has {vertex_count} vertices"
            ),
            Self::LengthMismatch {
                what,
                len,
                expected,
            } => write!(f, "{what} has {len} entries but there are {expected} positions"),
            Self::TooManyVertices { count } => {
                write!(f, "{count} vertices exceed the u16 index range")
            }
            Self::ClusterTriangles {
                clustered,
                triangles,
            } => write!(
                f,
                "the clusters hold {clustered} triangles but the mesh has {triangles}"
            ),
            Self::ClusterVertices {
                cluster,
                end,
                vertex_count,
            } => write!(
                f,
                "cluster {cluster}'s vertices end at {end}, but the mesh has {vertex_count} vertices"
            ),
            Self::ClusterIndex {
                cluster,
                triangle,
                index,
            } => write!(
                f,
                "triangle {triangle} uses vertex {index}, outside the vertex range of its cluster {cluster}"
            ),
            Self::ClusterBounds { cluster, vertex } => write!(
                f,
                "vertex {vertex} lies outside the bounding box of cluster {cluster}"
            ),
            Self::ClusterBox { cluster } => write!(
                f,
                "cluster {cluster}'s bounding box has a minimum above its maximum"
            ),
            Self::ClusterOverlap {
                cluster,
                first_vertex,
                previous_end,
            } => write!(
                f,
                "cluster {cluster}'s vertices start at {first_vertex}, before the previous cluster's end at {previous_end}"
            ),
        }
    }
}

impl<'a> Mesh<'a> {
    /// Builds a mesh from positions and `u16` triangles, checking every
    /// index.
    pub fn new(positions: &'a [Vec3Fx], triangles: &'a [[u16; 3]]) -> Result<Self, MeshError> {
        if positions.len() > u16::MAX as usize + 1 {
            return Err(MeshError::TooManyVertices {
                count: positions.len(),
            });
        }
        Self::with_indices(positions, Indices::U16(triangles))
    }

    /// Builds a mesh from positions and `u32` triangles (for more than
    /// 65,536 vertices), checking every index.
    ///
    /// ```
    /// use fixed::types::I16F16;
    /// use microraster::mesh::{Mesh, MeshError};
    /// let p = [[I16F16::ZERO; 3]; 3];
    /// static TRIS: [[u32; 3]; 1] = [[0, 1, 2]];
    /// assert_eq!(Mesh::new_u32(&p, &TRIS).unwrap().triangle_count(), 1);
    /// static BAD: [[u32; 3]; 1] = [[0, 1, 70_000]];
    /// assert_eq!(
    ///     Mesh::new_u32(&p, &BAD).unwrap_err(),
    ///     MeshError::IndexOutOfRange { triangle: 0, index: 70_000, vertex_count: 3 }
    /// );
    /// ```
    pub fn new_u32(positions: &'a [Vec3Fx], triangles: &'a [[u32; 3]]) -> Result<Self, MeshError> {
        Self::with_indices(positions, Indices::U32(triangles))
    }

    fn with_indices(positions: &'a [Vec3Fx], triangles: Indices<'a>) -> Result<Self, MeshError> {
        for t in 0..triangles.len() {
            for i in triangles.get(t) {
                if i as usize >= positions.len() {
                    return Err(MeshError::IndexOutOfRange {
                        triangle: t,
                        index: i,
                        vertex_count: positions.len(),
                    });
                }
            }
        }
        let mut bounds = [[i32::MAX; 3], [i32::MIN; 3]];
        for p in positions {
            for k in 0..3 {
                bounds[0][k] = bounds[0][k].min(p[k].to_bits());
                bounds[1][k] = bounds[1][k].max(p[k].to_bits());
            }
        }
        if positions.is_empty() {
            bounds = [[0; 3]; 2];
        }
        // The largest coordinate magnitude is at a bound (one pass over
        // the positions instead of two; the same value).
        let mut extent = 0;
        for (lo, hi) in bounds[0].iter().zip(&bounds[1]) {
            extent = extent.max(lo.unsigned_abs()).max(hi.unsigned_abs());
        }
        Ok(Self {
            positions,
            normals: None,
            colors: None,
            uvs: None,
            triangles,
            extent,
            bounds,
            clusters: None,
        })
    }

    /// Adds spatial clusters of the triangles ([`Cluster`]), so that the
    /// renderer culls the parts of the mesh outside the view frustum.
    ///
    /// Checks that the clusters tile the triangles exactly, that the vertex
    /// ranges lie within the positions in ascending order without
    /// overlapping, that every triangle uses only its cluster's vertices,
    /// and that those vertices lie in the cluster's box: culling a cluster
    /// can then never remove a visible triangle, and the vertex stage
    /// transforms each vertex at most once. A run of clusters and the matching run of triangles (one
    /// group of an imported model) make a mesh as well.
    ///
    /// ```
    /// use fixed::types::I16F16;
    /// use microraster::mesh::{Cluster, Mesh, MeshError};
    /// let z = I16F16::ZERO;
    /// let p = [[z; 3], [I16F16::ONE, z, z], [z, I16F16::ONE, z]];
    /// let tris = [[0u16, 1, 2]];
    /// // The box misses vertex 1 (at x = 1).
    /// let tight = [Cluster::new(1, 0, 3, [z; 3], [z, I16F16::ONE, z])];
    /// assert_eq!(
    ///     Mesh::new(&p, &tris).unwrap().with_clusters(&tight).unwrap_err(),
    ///     MeshError::ClusterBounds { cluster: 0, vertex: 1 }
    /// );
    /// ```
    pub fn with_clusters(mut self, clusters: &'a [Cluster]) -> Result<Self, MeshError> {
        let clustered: u64 = clusters.iter().map(|c| u64::from(c.triangle_count)).sum();
        if clustered != self.triangles.len() as u64 {
            return Err(MeshError::ClusterTriangles {
                clustered,
                triangles: self.triangles.len(),
            });
        }
        let mut t = 0usize;
        let mut previous_end = 0u64;
        for (k, c) in clusters.iter().enumerate() {
            let first = c.first_vertex as usize;
            let end = u64::from(c.first_vertex) + u64::from(c.vertex_count);
            if u64::from(c.first_vertex) < previous_end {
                return Err(MeshError::ClusterOverlap {
                    cluster: k,
                    first_vertex: c.first_vertex,
                    previous_end,
                });
            }
            previous_end = end;
            if end > self.positions.len() as u64 {
                return Err(MeshError::ClusterVertices {
                    cluster: k,
                    end,
                    vertex_count: self.positions.len(),
                });
            }
            let range = first..end as usize;
            let (lo, hi) = (c.min, c.max);
            if (0..3).any(|i| lo[i] > hi[i]) {
                return Err(MeshError::ClusterBox { cluster: k });
            }
            for (v, p) in self.positions[range.clone()].iter().enumerate() {
                if (0..3).any(|i| p[i] < lo[i] || p[i] > hi[i]) {
                    return Err(MeshError::ClusterBounds {
                        cluster: k,
                        vertex: first + v,
                    });
                }
            }
            // The counts sum to the triangle count, so this stays in range.
            for triangle in t..t + c.triangle_count as usize {
                for index in self.triangles.get(triangle) {
                    if !range.contains(&(index as usize)) {
                        return Err(MeshError::ClusterIndex {
                            cluster: k,
                            triangle,
                            index,
                        });
                    }
                }
            }
            t += c.triangle_count as usize;
        }
        self.clusters = Some(clusters);
        Ok(self)
    }

    /// Adds per-vertex unit normals (model space), used for lighting.
    pub fn with_normals(mut self, normals: &'a [Vec3Fx]) -> Result<Self, MeshError> {
        check_len("normals", normals.len(), self.positions.len())?;
        self.normals = Some(normals);
        Ok(self)
    }

    /// Adds per-vertex colours, which replace the material colour.
    pub fn with_colors(mut self, colors: &'a [Rgb888]) -> Result<Self, MeshError> {
        check_len("colors", colors.len(), self.positions.len())?;
        self.colors = Some(colors);
        Ok(self)
    }

    /// Adds per-vertex texture coordinates, read by textured shaders.
    pub fn with_uvs(mut self, uvs: &'a [UvFx]) -> Result<Self, MeshError> {
        check_len("uvs", uvs.len(), self.positions.len())?;
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// The vertex positions.
    pub fn positions(&self) -> &'a [Vec3Fx] {
        self.positions
    }

    /// The mesh with its positions cut to the first `n`, for `n` at most
    /// their count (the renderer passes the count of the draw's slice of
    /// the vertex buffer, which is the mesh's vertex count): the copy's
    /// positions then have the length of that slice, so an index of the
    /// slice needs no bounds check on them.
    #[inline(always)]
    pub(crate) fn cut(&self, n: usize) -> Self {
        Self {
            positions: &self.positions[..n],
            ..*self
        }
    }

    /// The vertex normals, if any.
    pub fn normals(&self) -> Option<&'a [Vec3Fx]> {
        self.normals
    }

    /// The vertex colours, if any.
    pub fn colors(&self) -> Option<&'a [Rgb888]> {
        self.colors
    }

    /// The texture coordinates, if any.
    pub fn uvs(&self) -> Option<&'a [UvFx]> {
        self.uvs
    }

    /// The clusters, if any ([`with_clusters`](Self::with_clusters)).
    pub fn clusters(&self) -> Option<&'a [Cluster]> {
        self.clusters
    }

    /// The triangles, as vertex indices.
    pub fn triangles(&self) -> Indices<'a> {
        self.triangles
    }

    /// The largest magnitude of any position coordinate, as raw 16.16 bits
    /// (found when the mesh was built).
    pub fn extent(&self) -> u32 {
        self.extent
    }

    /// The bounding box of the positions: the smallest and the largest
    /// coordinates (found when the mesh was built; zeros for no vertices).
    pub fn bounds(&self) -> [Vec3Fx; 2] {
        self.bounds.map(|c| c.map(I16F16::from_bits))
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
}

fn check_len(what: &'static str, len: usize, expected: usize) -> Result<(), MeshError> {
    if len == expected {
        Ok(())
    } else {
        Err(MeshError::LengthMismatch {
            what,
            len,
            expected,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fx(v: i32) -> I16F16 {
        I16F16::from_num(v)
    }

    /// The extent is the largest coordinate magnitude, as the two-pass
    /// maximum over every coordinate found it.
    #[test]
    fn extent_is_the_largest_magnitude() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for n in 0..200usize {
            let mut p = [[I16F16::ZERO; 3]; 7];
            for v in p.iter_mut().take(n % 8) {
                for c in v.iter_mut() {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    let bits = match x % 5 {
                        0 => i32::MIN,
                        1 => i32::MAX,
                        _ => (x >> 32) as i32 >> (x % 31),
                    };
                    *c = I16F16::from_bits(bits);
                }
            }
            let p = &p[..(n % 8).min(7)];
            let want = p
                .iter()
                .flatten()
                .map(|c| c.to_bits().unsigned_abs())
                .max()
                .unwrap_or(0);
            let tris: [[u16; 3]; 0] = [];
            assert_eq!(Mesh::new(p, &tris).unwrap().extent(), want);
        }
    }

    fn p(x: i32, y: i32, z: i32) -> Vec3Fx {
        [fx(x), fx(y), fx(z)]
    }

    const POS: [[i32; 3]; 6] = [
        [0, 0, 0],
        [1, 0, 0],
        [0, 1, 0],
        [5, 5, 5],
        [6, 5, 5],
        [5, 6, 5],
    ];

    fn positions() -> [Vec3Fx; 6] {
        POS.map(|[x, y, z]| p(x, y, z))
    }

    #[test]
    fn clusters_are_checked_against_triangles_vertices_and_boxes() {
        let pos = positions();
        let tris = [[0u16, 1, 2], [3, 4, 5], [4, 3, 5]];
        let mesh = Mesh::new(&pos, &tris).unwrap();
        let a = Cluster::new(1, 0, 3, p(0, 0, 0), p(1, 1, 0));
        let b = Cluster::new(2, 3, 3, p(5, 5, 5), p(6, 6, 5));
        let good = [a, b];
        let m = mesh.with_clusters(&good).unwrap();
        assert_eq!(m.clusters(), Some(&good[..]));
        assert_eq!(mesh.clusters(), None);

        let short = [a];
        assert_eq!(
            mesh.with_clusters(&short).unwrap_err(),
            MeshError::ClusterTriangles {
                clustered: 1,
                triangles: 3
            }
        );
        let huge = [a, Cluster::new(u32::MAX, 3, 3, p(5, 5, 5), p(6, 6, 5)), b];
        assert!(matches!(
            mesh.with_clusters(&huge).unwrap_err(),
            MeshError::ClusterTriangles { .. }
        ));
        let past = [a, Cluster::new(2, 3, u32::MAX, p(5, 5, 5), p(6, 6, 5))];
        assert_eq!(
            mesh.with_clusters(&past).unwrap_err(),
            MeshError::ClusterVertices {
                cluster: 1,
                end: 3 + u64::from(u32::MAX),
                vertex_count: 6
            }
        );
        // Triangle 0 uses vertices 0..3, outside the range 3..6.
        let wrong_range = [Cluster::new(1, 3, 3, p(5, 5, 5), p(6, 6, 5)), b];
        assert_eq!(
            mesh.with_clusters(&wrong_range).unwrap_err(),
            MeshError::ClusterIndex {
                cluster: 0,
                triangle: 0,
                index: 0
            }
        );
        // Vertex 4 (x = 6) sticks out of a box ending at x = 5.
        let tight = [a, Cluster::new(2, 3, 3, p(5, 5, 5), p(5, 6, 5))];
        assert_eq!(
            mesh.with_clusters(&tight).unwrap_err(),
            MeshError::ClusterBounds {
                cluster: 1,
                vertex: 4
            }
        );
        // An inverted box, even around no vertices.
        let inverted = [a, Cluster::new(2, 6, 0, p(6, 6, 6), p(5, 5, 5))];
        assert_eq!(
            mesh.with_clusters(&inverted).unwrap_err(),
            MeshError::ClusterBox { cluster: 1 }
        );
        // Vertex runs must ascend without overlapping (a descending run
        // starts before the previous one's end too).
        let overlap = [
            Cluster::new(1, 0, 4, p(0, 0, 0), p(5, 5, 5)),
            Cluster::new(2, 3, 3, p(5, 5, 5), p(6, 6, 5)),
        ];
        assert_eq!(
            mesh.with_clusters(&overlap).unwrap_err(),
            MeshError::ClusterOverlap {
                cluster: 1,
                first_vertex: 3,
                previous_end: 4
            }
        );
        // Every error displays a sentence naming the cluster.
        for e in [
            mesh.with_clusters(&past).unwrap_err(),
            mesh.with_clusters(&wrong_range).unwrap_err(),
            mesh.with_clusters(&tight).unwrap_err(),
            mesh.with_clusters(&inverted).unwrap_err(),
            mesh.with_clusters(&overlap).unwrap_err(),
        ] {
            let mut buf = heapless::String::<128>::new();
            core::fmt::write(&mut buf, format_args!("{e}")).unwrap();
            assert!(buf.contains("cluster"), "{buf}");
        }
    }

    #[test]
    fn empty_meshes_take_empty_clusters_and_runs_may_leave_gaps() {
        let pos = positions();
        let none: [[u16; 3]; 0] = [];
        assert!(Mesh::new(&pos, &none).unwrap().with_clusters(&[]).is_ok());
        // Vertices 1, 2 and 4..6 belong to no cluster; an empty cluster
        // sits between the others.
        let tris = [[0u16, 0, 0], [3, 3, 3]];
        let gaps = [
            Cluster::new(1, 0, 1, p(0, 0, 0), p(0, 0, 0)),
            Cluster::new(0, 2, 0, p(0, 0, 0), p(0, 0, 0)),
            Cluster::new(1, 3, 1, p(5, 5, 5), p(5, 5, 5)),
        ];
        assert!(Mesh::new(&pos, &tris).unwrap().with_clusters(&gaps).is_ok());
    }
}
