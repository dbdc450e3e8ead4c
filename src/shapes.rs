//! Procedural meshes written into caller-supplied slices.
//!
//! Generation is set-up work done once (in `f32`, with micromath), not per
//! frame; the results are ordinary fixed-point mesh arrays. The same
//! parameters give the same bits on every target, so a host test and a
//! firmware render the very same mesh.

use crate::math::{sqrt, Vec3};
use crate::mesh::Vec3Fx;
use fixed::types::I16F16;
use micromath::F32Ext;

/// Why a shape could not be generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeError {
    /// An output slice is shorter than the shape needs.
    BufferTooSmall {
        /// Which slice.
        what: &'static str,
        /// Entries needed.
        needed: usize,
        /// Entries given.
        given: usize,
    },
    /// Fewer than 3 segments or sides, or more vertices than `u16` indices
    /// reach.
    BadResolution,
    /// A size parameter is not finite, or the shape leaves the 16.16 range.
    BadSize,
}

fn fx(v: f32) -> Result<I16F16, ShapeError> {
    I16F16::checked_from_num(v).ok_or(ShapeError::BadSize)
}

fn fx3(v: Vec3) -> Result<Vec3Fx, ShapeError> {
    Ok([fx(v.x)?, fx(v.y)?, fx(v.z)?])
}

fn need(what: &'static str, needed: usize, given: usize) -> Result<(), ShapeError> {
    if given < needed {
        Err(ShapeError::BufferTooSmall {
            what,
            needed,
            given,
        })
    } else {
        Ok(())
    }
}

/// Vertex and triangle counts of [`torus_knot`] with this resolution.
pub const fn torus_knot_size(segments: usize, sides: usize) -> (usize, usize) {
    (segments * sides, 2 * segments * sides)
}

/// A `(p, q)` torus knot: a tube of radius `tube` around the curve that
/// winds `p` times around the z axis and `q` times through the torus hole,
/// on a torus of radius `radius`. `segments` rings of `sides` vertices
/// each, with unit normals; triangles face outwards (counter-clockwise).
///
/// Returns the vertex and triangle counts written.
///
/// ```
/// use microraster::shapes::{torus_knot, torus_knot_size};
/// use fixed::types::I16F16;
/// let (nv, nt) = torus_knot_size(64, 6);
/// let mut pos = [[I16F16::ZERO; 3]; 384];
/// let mut nrm = [[I16F16::ZERO; 3]; 384];
/// let mut tri = [[0u16; 3]; 768];
/// assert_eq!(torus_knot(2, 3, 1.0, 0.3, 64, 6, &mut pos, &mut nrm, &mut tri), Ok((nv, nt)));
/// ```
#[allow(clippy::too_many_arguments)]
pub fn torus_knot(
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
    if segments < 3 || sides < 3 || nv > u16::MAX as usize + 1 {
        return Err(ShapeError::BadResolution);
    }
    if !(radius.is_finite() && tube.is_finite() && radius > 0.0 && tube > 0.0) {
        return Err(ShapeError::BadSize);
    }
    need("positions", nv, positions.len())?;
    need("normals", nv, normals.len())?;
    need("triangles", nt, triangles.len())?;

    let tau = core::f32::consts::TAU;
    let curve = |t: f32| {
        let r = radius * (2.0 + F32Ext::cos(q as f32 * t)) / 3.0;
        Vec3::new(
            r * F32Ext::cos(p as f32 * t),
            r * F32Ext::sin(p as f32 * t),
            -radius * F32Ext::sin(q as f32 * t) / 3.0,
        )
    };
    let dt = tau / segments as f32;
    for i in 0..segments {
        let t = i as f32 * dt;
        let c = curve(t);
        let tangent = curve(t + dt * 0.5) - curve(t - dt * 0.5);
        let n = tangent.cross(c).normalize().ok_or(ShapeError::BadSize)?;
        let b = tangent.cross(n).normalize().ok_or(ShapeError::BadSize)?;
        for j in 0..sides {
            let a = j as f32 * tau / sides as f32;
            let (ca, sa) = (F32Ext::cos(a), F32Ext::sin(a));
            let dir = Vec3::new(
                ca * n.x + sa * b.x,
                ca * n.y + sa * b.y,
                ca * n.z + sa * b.z,
            );
            let len = sqrt(dir.dot(dir));
            let dir = Vec3::new(dir.x / len, dir.y / len, dir.z / len);
            let k = i * sides + j;
            positions[k] = fx3(Vec3::new(
                c.x + tube * dir.x,
                c.y + tube * dir.y,
                c.z + tube * dir.z,
            ))?;
            normals[k] = fx3(dir)?;
        }
    }
    let mut k = 0;
    for i in 0..segments {
        let i1 = (i + 1) % segments;
        for j in 0..sides {
            let j1 = (j + 1) % sides;
            let a = (i * sides + j) as u16;
            let b = (i1 * sides + j) as u16;
            let c = (i1 * sides + j1) as u16;
            let d = (i * sides + j1) as u16;
            triangles[k] = [a, c, b];
            triangles[k + 1] = [a, d, c];
            k += 2;
        }
    }
    Ok((nv, nt))
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
