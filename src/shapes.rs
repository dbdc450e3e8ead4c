//! Procedural meshes, computed in integer fixed point by `const fn`s.
//!
//! Everything here is integer arithmetic (angles in fractions of a turn,
//! 2.30 fixed point inside, 16.16 out), so the same parameters give the same
//! bits on every target, and a firmware can build a mesh *at compile time*
//! into flash:
//!
//! ```
//! use microraster::shapes::{torus_knot_data, MeshData};
//! use microraster::mesh::Mesh;
//!
//! // 64 x 6 vertices and 768 triangles, evaluated by the compiler.
//! static KNOT: MeshData<384, 768> = match torus_knot_data(2, 3, 1.0, 0.25, 64, 6) {
//!     Ok(m) => m,
//!     Err(_) => panic!("invalid knot parameters"),
//! };
//! let mesh: Mesh<'static> = KNOT.mesh().unwrap();
//! assert_eq!(mesh.triangle_count(), 768);
//! ```

use crate::mesh::{Mesh, MeshError, Vec3Fx};
use fixed::types::I16F16;

/// Why a shape could not be generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeError {
    /// An output slice or array does not have the size the shape needs.
    BufferTooSmall {
        /// Which output.
        what: &'static str,
        /// Entries needed.
        needed: usize,
        /// Entries given.
        given: usize,
    },
    /// Fewer than 3 segments or sides, or more vertices than `u16` indices
    /// reach.
    BadResolution,
    /// A size is not positive, or the shape would leave the 16.16 range.
    BadSize,
}

/// One in 2.30 fixed point, the internal format.
const ONE: i64 = 1 << 30;

/// `sin` and `cos` of `turns` (a full turn is 2^32), in 2.30, from odd and
/// even Taylor polynomials on the first quadrant (error below 2^-23).
pub const fn sin_cos_turns(turns: u32) -> (i64, i64) {
    let quadrant = turns >> 30;
    // The angle inside the quadrant, in radians, 2.30: f * (π/2) / 2^30.
    let f = (turns & ((1 << 30) - 1)) as i64;
    // π/2 in 2.30.
    const HALF_PI: i64 = 1_686_629_713;
    let x = (f * HALF_PI) >> 30;
    let x2 = (x * x) >> 30;
    // Horner: sin x = x (1 - x²/6 (1 - x²/20 (1 - x²/42 (1 - x²/72 (1 - x²/110))))).
    let sin = (x * horner(x2, &[110, 72, 42, 20, 6])) >> 30;
    // cos x = 1 - x²/2 (1 - x²/12 (1 - x²/30 (1 - x²/56 (1 - x²/90 (1 - x²/132))))).
    let c = horner(x2, &[132, 90, 56, 30, 12, 2]);
    match quadrant {
        0 => (sin, c),
        1 => (c, -sin),
        2 => (-sin, -c),
        _ => (-c, sin),
    }
}

/// The Horner chain `1 - x²/d[n-1] (... (1 - x²/d[0]))` of
/// [`sin_cos_turns`] in 2.30, for `x2` = x² in 2.30: the divisors from the
/// innermost term out.
const fn horner(x2: i64, divisors: &[i64]) -> i64 {
    // The innermost term starts at one: `(x2 * ONE) >> 30` is `x2` exactly.
    let mut s = ONE;
    let mut i = 0;
    while i < divisors.len() {
        s = ONE - ((x2 * s) >> 30) / divisors[i];
        i += 1;
    }
    s
}

type V3 = [i64; 3];

const fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Cross product of two 2.30 vectors with components below 8, in 2.30.
const fn cross(a: V3, b: V3) -> V3 {
    [
        (a[1] * b[2] - a[2] * b[1]) >> 30,
        (a[2] * b[0] - a[0] * b[2]) >> 30,
        (a[0] * b[1] - a[1] * b[0]) >> 30,
    ]
}

/// `floor(sqrt(n))`, as `u128::isqrt`, digit by digit: a generator runs
/// it a few times per vertex, once, and the library's version, unrolled
/// for speed, took 2 KB of a firmware's flash.
const fn isqrt(n: u128) -> u128 {
    if n == 0 {
        return 0;
    }
    // The highest power of 4 not above n.
    let mut bit = 1u128 << ((127 - n.leading_zeros()) & !1);
    let (mut x, mut r) = (n, 0u128);
    while bit != 0 {
        if x >= r + bit {
            x -= r + bit;
            r = (r >> 1) + bit;
        } else {
            r >>= 1;
        }
        bit >>= 2;
    }
    r
}

/// The unit vector along `v` (2.30), or `None` when `v` is zero.
const fn normalize(v: V3) -> Option<V3> {
    let sq = (v[0] as i128 * v[0] as i128
        + v[1] as i128 * v[1] as i128
        + v[2] as i128 * v[2] as i128) as u128;
    let len = isqrt(sq) as i64; // 2.30, since sq is 4.60
    if len == 0 {
        return None;
    }
    Some([
        ((v[0] as i128) << 30) as i64 / len,
        ((v[1] as i128) << 30) as i64 / len,
        ((v[2] as i128) << 30) as i64 / len,
    ])
}

/// A point of the unit `(p, q)` torus knot at `t` turns (as 2^32 fractions).
const fn knot_curve(p: u32, q: u32, t: u32) -> V3 {
    let (sq, cq) = sin_cos_turns(t.wrapping_mul(q));
    let (sp, cp) = sin_cos_turns(t.wrapping_mul(p));
    let r = (2 * ONE + cq) / 3;
    [(r * cp) >> 30, (r * sp) >> 30, -sq / 3]
}

/// 2.30 times 16.16 to 16.16, rounded; `None` outside the 16.16 range.
const fn scale(v: i64, s: I16F16) -> Option<I16F16> {
    let x = (v as i128 * s.to_bits() as i128 + (1 << 29)) >> 30;
    if x > i32::MAX as i128 || x < i32::MIN as i128 {
        None
    } else {
        Some(I16F16::from_bits(x as i32))
    }
}

/// Vertex and triangle counts of a torus knot with this resolution.
pub const fn torus_knot_size(segments: usize, sides: usize) -> (usize, usize) {
    (segments * sides, 2 * segments * sides)
}

/// Writes a `(p, q)` torus knot into caller buffers: a tube of radius
/// `tube` around the curve that winds `p` times around the z axis and `q`
/// times through the hole of a torus of radius `radius`; `segments` rings of
/// `sides` vertices, unit normals, triangles counter-clockwise seen from
/// outside. Returns the vertex and triangle counts written.
#[allow(clippy::too_many_arguments)]
pub const fn torus_knot(
    p: u32,
    q: u32,
    radius: f32,
    tube: f32,
    segments: usize,
    sides: usize,
    positions: &mut [Vec3Fx],
    normals: &mut [Vec3Fx],
    triangles: &mut [[u16; 3]],
) -> Result<(usize, usize), ShapeError> {
    let (nv, nt) = torus_knot_size(segments, sides);
    if segments < 3
        || sides < 3
        || nv > u16::MAX as usize + 1
        || segments > (1 << 24)
        || sides > (1 << 24)
    {
        return Err(ShapeError::BadResolution);
    }
    if !(radius.is_finite() && tube.is_finite() && radius > 0.0 && tube > 0.0 && radius < 32_768.0)
    {
        return Err(ShapeError::BadSize);
    }
    // The only floats: the two sizes, converted once (exactly, for sizes
    // that are multiples of 2^-16).
    let radius = I16F16::from_bits(crate::math::f32_to_i32(radius * 65_536.0));
    // Scaling by 2^16 is exact in `f32` (an overflow to infinity saturates
    // as the `i64` would).
    let tube_bits = crate::math::f32_to_i64(tube * 65_536.0);
    if radius.to_bits() == 0 || tube_bits == 0 {
        return Err(ShapeError::BadSize);
    }
    if positions.len() < nv {
        return Err(ShapeError::BufferTooSmall {
            what: "positions",
            needed: nv,
            given: positions.len(),
        });
    }
    if normals.len() < nv {
        return Err(ShapeError::BufferTooSmall {
            what: "normals",
            needed: nv,
            given: normals.len(),
        });
    }
    if triangles.len() < nt {
        return Err(ShapeError::BufferTooSmall {
            what: "triangles",
            needed: nt,
            given: triangles.len(),
        });
    }
    // The tube radius relative to the knot's radius, 2.30.
    let rel = ((tube_bits as i128) << 30) / radius.to_bits() as i128;
    if rel > 4 * ONE as i128 {
        return Err(ShapeError::BadSize);
    }
    let rel = rel as i64;
    let step = (1u64 << 32) / segments as u64;
    let mut i = 0;
    while i < segments {
        // Parameters as fractions of a turn: t and t ± half a step.
        let t = (i as u64 * (1u64 << 32) / segments as u64) as u32;
        let half = (step / 2) as u32;
        let c = knot_curve(p, q, t);
        let tangent = sub(
            knot_curve(p, q, t.wrapping_add(half)),
            knot_curve(p, q, t.wrapping_sub(half)),
        );
        let n = match normalize(cross(tangent, c)) {
            Some(n) => n,
            None => return Err(ShapeError::BadSize),
        };
        let b = match normalize(cross(tangent, n)) {
            Some(b) => b,
            None => return Err(ShapeError::BadSize),
        };
        let mut j = 0;
        while j < sides {
            let a = (j as u64 * (1u64 << 32) / sides as u64) as u32;
            let (sa, ca) = sin_cos_turns(a);
            let dir = [
                (ca * n[0] + sa * b[0]) >> 30,
                (ca * n[1] + sa * b[1]) >> 30,
                (ca * n[2] + sa * b[2]) >> 30,
            ];
            let dir = match normalize(dir) {
                Some(d) => d,
                None => return Err(ShapeError::BadSize),
            };
            let k = i * sides + j;
            let mut axis = 0;
            while axis < 3 {
                let unit = c[axis] + ((rel * dir[axis]) >> 30);
                positions[k][axis] = match scale(unit, radius) {
                    Some(v) => v,
                    None => return Err(ShapeError::BadSize),
                };
                normals[k][axis] = I16F16::from_bits(((dir[axis] + (1 << 13)) >> 14) as i32);
                axis += 1;
            }
            j += 1;
        }
        i += 1;
    }
    let mut k = 0;
    let mut i = 0;
    while i < segments {
        let i1 = (i + 1) % segments;
        let mut j = 0;
        while j < sides {
            let j1 = (j + 1) % sides;
            let a = (i * sides + j) as u16;
            let b = (i1 * sides + j) as u16;
            let c = (i1 * sides + j1) as u16;
            let d = (i * sides + j1) as u16;
            triangles[k] = [a, c, b];
            triangles[k + 1] = [a, d, c];
            k += 2;
            j += 1;
        }
        i += 1;
    }
    Ok((nv, nt))
}

/// Mesh arrays owned by value, sized at compile time: what a `static` mesh
/// built by a `const fn` holds.
#[derive(Clone, Debug)]
pub struct MeshData<const V: usize, const T: usize> {
    /// Positions.
    pub positions: [Vec3Fx; V],
    /// Unit normals.
    pub normals: [Vec3Fx; V],
    /// Triangles.
    pub triangles: [[u16; 3]; T],
}

impl<const V: usize, const T: usize> MeshData<V, T> {
    /// All zero.
    pub const fn zeroed() -> Self {
        Self {
            positions: [[I16F16::ZERO; 3]; V],
            normals: [[I16F16::ZERO; 3]; V],
            triangles: [[0; 3]; T],
        }
    }

    /// The mesh over these arrays.
    pub fn mesh(&self) -> Result<Mesh<'_>, MeshError> {
        Mesh::new(&self.positions, &self.triangles)?.with_normals(&self.normals)
    }
}

/// [`torus_knot`] into a [`MeshData`] whose sizes must equal
/// [`torus_knot_size`]; usable in a `static` initialiser.
pub const fn torus_knot_data<const V: usize, const T: usize>(
    p: u32,
    q: u32,
    radius: f32,
    tube: f32,
    segments: usize,
    sides: usize,
) -> Result<MeshData<V, T>, ShapeError> {
    let (nv, nt) = torus_knot_size(segments, sides);
    if nv != V {
        return Err(ShapeError::BufferTooSmall {
            what: "positions",
            needed: nv,
            given: V,
        });
    }
    if nt != T {
        return Err(ShapeError::BufferTooSmall {
            what: "triangles",
            needed: nt,
            given: T,
        });
    }
    let mut m = MeshData::zeroed();
    match torus_knot(
        p,
        q,
        radius,
        tube,
        segments,
        sides,
        &mut m.positions,
        &mut m.normals,
        &mut m.triangles,
    ) {
        Ok(_) => Ok(m),
        Err(e) => Err(e),
    }
}

const fn f(v: i32) -> I16F16 {
    I16F16::from_bits(v << 16)
}

/// The 24 vertices (4 per face, so faces have their own normals) of the
/// cube `[-1, 1]³`.
pub static CUBE_POSITIONS: [Vec3Fx; 24] = cube_positions();
/// Unit normals of [`CUBE_POSITIONS`].
pub static CUBE_NORMALS: [Vec3Fx; 24] = cube_normals();
/// The 12 outward-facing triangles of the cube.
pub static CUBE_TRIANGLES: [[u16; 3]; 12] = cube_triangles();
/// Texture coordinates of [`CUBE_POSITIONS`]: each face shows the whole
/// texture once, upright when the face is seen with its `v` axis up.
pub static CUBE_UVS: [[I16F16; 2]; 24] = cube_uvs();

const fn cube_uvs() -> [[I16F16; 2]; 24] {
    // Corners (-1,-1), (1,-1), (1,1), (-1,1) of every face, as in
    // `cube_positions`; texture v runs down.
    let corner = [[0, 1], [1, 1], [1, 0], [0, 0]];
    let mut out = [[f(0); 2]; 24];
    let mut k = 0;
    while k < 24 {
        out[k] = [f(corner[k % 4][0]), f(corner[k % 4][1])];
        k += 1;
    }
    out
}

/// Face axes: normal, then two in-plane axes `u`, `v` with `u x v = n`.
const FACES: [[[i32; 3]; 3]; 6] = [
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    [[-1, 0, 0], [0, 0, 1], [0, 1, 0]],
    [[0, 1, 0], [0, 0, 1], [1, 0, 0]],
    [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
    [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
    [[0, 0, -1], [0, 1, 0], [1, 0, 0]],
];

const fn cube_positions() -> [Vec3Fx; 24] {
    let mut out = [[f(0); 3]; 24];
    let corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)];
    let mut face = 0;
    while face < 6 {
        let [n, u, v] = FACES[face];
        let mut k = 0;
        while k < 4 {
            let (a, b) = corners[k];
            let mut c = 0;
            while c < 3 {
                out[face * 4 + k][c] = f(n[c] + a * u[c] + b * v[c]);
                c += 1;
            }
            k += 1;
        }
        face += 1;
    }
    out
}

const fn cube_normals() -> [Vec3Fx; 24] {
    let mut out = [[f(0); 3]; 24];
    let mut i = 0;
    while i < 24 {
        let n = FACES[i / 4][0];
        out[i] = [f(n[0]), f(n[1]), f(n[2])];
        i += 1;
    }
    out
}

const fn cube_triangles() -> [[u16; 3]; 12] {
    let mut out = [[0u16; 3]; 12];
    let mut face = 0;
    while face < 6 {
        let b = (face * 4) as u16;
        out[face * 2] = [b, b + 1, b + 2];
        out[face * 2 + 1] = [b, b + 2, b + 3];
        face += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// The digit-by-digit square root is the library's.
    #[test]
    fn isqrt_is_the_librarys() {
        let mut x = 0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c834u128;
        for k in 0..128 {
            for n in [
                1u128 << k,
                (1u128 << k) - 1,
                (1u128 << k) + 1,
                x >> k,
                u128::MAX >> k,
            ] {
                for m in [n, n.wrapping_mul(n) >> 64, (n >> 64).pow(2)] {
                    assert_eq!(isqrt(m), m.isqrt(), "{m}");
                }
            }
            x = x.rotate_left(7) ^ (x >> 3);
        }
        for n in 0..100_000u128 {
            assert_eq!(isqrt(n), n.isqrt());
        }
    }

    /// Every cube triangle's winding agrees with its face normal.
    #[test]
    fn cube_faces_point_outwards() {
        for t in CUBE_TRIANGLES {
            let p = |i: u16| CUBE_POSITIONS[i as usize].map(|v| v.to_num::<i32>());
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let fnorm = CUBE_NORMALS[t[0] as usize].map(|v| v.to_num::<i32>());
            assert!(n[0] * fnorm[0] + n[1] * fnorm[1] + n[2] * fnorm[2] > 0);
        }
    }

    #[test]
    fn torus_knot_faces_point_outwards_and_checks_buffers() {
        let mut pos = [[I16F16::ZERO; 3]; 64 * 4];
        let mut nrm = pos;
        let mut tri = [[0u16; 3]; 2 * 64 * 4];
        torus_knot(2, 3, 1.0, 0.25, 64, 4, &mut pos, &mut nrm, &mut tri).unwrap();
        for t in tri {
            let p = |i: u16| pos[i as usize].map(|v| v.to_num::<f32>());
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let e1 = Vec3::new(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
            let e2 = Vec3::new(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
            let n = nrm[t[0] as usize].map(|v| v.to_num::<f32>());
            assert!(e1.cross(e2).dot(Vec3::new(n[0], n[1], n[2])) > 0.0);
        }
        assert_eq!(
            torus_knot(2, 3, 1.0, 0.25, 64, 4, &mut pos[..10], &mut nrm, &mut tri),
            Err(ShapeError::BufferTooSmall {
                what: "positions",
                needed: 256,
                given: 10
            })
        );
        assert_eq!(
            torus_knot(2, 3, f32::NAN, 0.25, 64, 4, &mut pos, &mut nrm, &mut tri),
            Err(ShapeError::BadSize)
        );
    }
}
