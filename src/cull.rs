//! Culling whole draws against the view frustum, before the vertex stage.
//!
//! A scene of many meshes (a room, a level) usually has most of them out of
//! view. Each draw's mesh knows its bounding box ([`Mesh::bounds`](crate::mesh::Mesh::bounds)); per
//! frame and draw, the six frustum planes are taken from the rows of the
//! model-view-projection matrix `P V M` in the mesh's own model space
//! (Gribb and Hartmann, *Fast Extraction of Viewing Frustum Planes from the
//! World-View-Projection Matrix*, 2001): `left = r3 + r0`, `right = r3 -
//! r0`, `bottom = r3 + r1`, `top = r3 - r1`, `near = r3 + r2`, `far = r3 -
//! r2`, where a point `p` is inside plane `(a, b, c, d)` when
//! `a x + b y + c z + d >= 0`. In model space the test is exact for any
//! model matrix, and needs no normalised planes:
//!
//! 1. the box's bounding sphere (its centre, its half diagonal) is outside a
//!    plane when the centre's signed distance is below `-ρ |(a, b, c)|`,
//!    compared squared, without a square root;
//! 2. otherwise the box itself, in centre-extent form, is outside when the
//!    distance is below `-(|a| e_x + |b| e_y + |c| e_z)`.
//!
//! A draw outside any plane is culled: none of its vertices is
//! transformed, none of its triangles binned. The renderer would have
//! rejected every one of its triangles anyway (all three vertices outside
//! one half-space), so culling never changes the picture; to keep that
//! true although the test runs in `f32` and the vertex stage in rounded
//! 16.16, a draw is culled only when it is outside by a margin that covers
//! both roundings (the property tests render random poses with and without
//! culling and compare).

use crate::math::Mat4;
use crate::scene::Draw;

/// Whether `draw`, seen through `view_proj`, lies wholly outside the view
/// frustum (with the rounding margin of the module docs). A non-finite
/// matrix is never culled here (the vertex stage reports it).
pub fn outside(view_proj: &Mat4, draw: &Draw<'_>) -> bool {
    let m = *view_proj * draw.transform;
    if !m.is_finite() {
        return false;
    }
    let [lo, hi] = draw.mesh.bounds().map(|c| c.map(|v| v.to_num::<f32>()));
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let half = [0, 1, 2].map(|k| 0.5 * (hi[k] - lo[k]));
    let radius2 = half[0] * half[0] + half[1] * half[1] + half[2] * half[2];
    // The vertex stage's 16.16 matrix differs from this one by at most
    // 2^-17 per element, and a transformed coordinate by at most
    // (3 E + 2) 2^-17 with E the largest model coordinate; a plane sums
    // two rows, so twice that (and a little for f32 itself).
    let extent = draw.mesh.extent() as f32 / 65_536.0;
    let fixed = (3.0 * extent + 2.0) * 2.0 / 131_072.0;
    let row = |r: usize| [m.m[0][r], m.m[1][r], m.m[2][r], m.m[3][r]];
    let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
    let plane = |a: [f32; 4], b: [f32; 4], s: f32| [0, 1, 2, 3].map(|k| a[k] + s * b[k]);
    let planes = [
        plane(r3, r0, 1.0),
        plane(r3, r0, -1.0),
        plane(r3, r1, 1.0),
        plane(r3, r1, -1.0),
        plane(r3, r2, 1.0),
        plane(r3, r2, -1.0),
    ];
    planes.iter().any(|p| {
        let terms = [p[0] * centre[0], p[1] * centre[1], p[2] * centre[2], p[3]];
        let dist = terms[0] + terms[1] + terms[2] + terms[3];
        let box_r = p[0].abs() * half[0] + p[1].abs() * half[1] + p[2].abs() * half[2];
        // f32 rounding of these sums, generously.
        let slack = 1e-4 * (terms.iter().map(|t| t.abs()).sum::<f32>() + box_r) + fixed;
        let limit = dist + slack;
        if limit >= 0.0 {
            return false;
        }
        // The sphere first: outside when limit² > ρ² |n|² (limit < 0).
        let n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        if limit * limit > radius2 * n2 * 1.0001 {
            return true;
        }
        limit < -box_r
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::mesh::Mesh;
    use fixed::types::I16F16;

    fn p(x: f32, y: f32, z: f32) -> [I16F16; 3] {
        [
            I16F16::from_num(x),
            I16F16::from_num(y),
            I16F16::from_num(z),
        ]
    }

    #[test]
    fn boxes_in_front_are_kept_and_behind_or_aside_culled() {
        let pos = [p(-1.0, -1.0, -1.0), p(1.0, 1.0, 1.0)];
        let tris = [[0u16, 1, 1]];
        let mesh = Mesh::new(&pos, &tris).unwrap();
        let view = Mat4::look_at(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::default(),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        let vp = Mat4::perspective(1.0, 1.0, 0.5, 20.0).unwrap() * view;
        let at = |x: f32, y: f32, z: f32| {
            Draw::new(&mesh).transform(Mat4::translation(Vec3::new(x, y, z)))
        };
        assert!(!outside(&vp, &at(0.0, 0.0, 0.0)));
        // Behind the camera, beyond far, far to the side, above.
        assert!(outside(&vp, &at(0.0, 0.0, 10.0)));
        assert!(outside(&vp, &at(0.0, 0.0, -30.0)));
        assert!(outside(&vp, &at(40.0, 0.0, 0.0)));
        assert!(outside(&vp, &at(0.0, -40.0, 0.0)));
        // Straddling the near plane or an edge: kept.
        assert!(!outside(&vp, &at(0.0, 0.0, 4.0)));
        assert!(!outside(&vp, &at(3.5, 0.0, 0.0)));
        // A non-finite transform is left to the vertex stage.
        let nan = Draw::new(&mesh).transform(Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0)));
        assert!(!outside(&vp, &nan));
    }
}
