//! The cameras of the fill benchmarks, shared by the host scenes
//! (`examples/common/scenes`) and the Cortex-M firmware's
//! (`examples/icount_scenes`). `no_std`, no allocation.
#![allow(dead_code)]

use microraster::prelude::*;

/// A camera whose clip space is the model space: x, y, z in `[-1, 1]` are
/// the frame, z = -1 nearest. Every vertex has the same `w`, so fragment
/// shaders interpolate affinely in every mode
/// ([`DrawSetup::constant_w`](microraster::vertex::DrawSetup::constant_w)).
pub fn ndc_camera() -> Camera {
    Camera::new(Mat4::IDENTITY, Mat4::IDENTITY)
}

/// [`ndc_camera`] whose clip-space `w` grows by 2^-12 a unit of depth:
/// each fill quad (one depth) still has one `w`, but the transform's is
/// not constant, so fragment shaders take their exact or
/// quasi-perspective loops, as for a quad facing a perspective camera
/// (the `fill-*-*-facing` scenes).
pub fn facing_camera() -> Camera {
    let mut projection = Mat4::IDENTITY;
    projection.m[2][3] = 1.0 / 4096.0;
    Camera::new(Mat4::IDENTITY, projection)
}
