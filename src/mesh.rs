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
            Indices::U16(tris) => tris[t].map(u32::from),
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
        let extent = positions
            .iter()
            .flatten()
            .map(|c| c.to_bits().unsigned_abs())
            .max()
            .unwrap_or(0);
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
        Ok(Self {
            positions,
            normals: None,
            colors: None,
            uvs: None,
            triangles,
            extent,
            bounds,
        })
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
