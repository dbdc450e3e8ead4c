//! The vertex stage: model-view-projection, lighting, outcodes and the
//! viewport transform, all in fixed point.
//!
//! Per frame (and per draw) the `f32` matrices of the [`Scene`](crate::scene::Scene) are combined,
//! normalized (divided by their largest element: clip coordinates are
//! homogeneous, so this leaves the picture alone but makes it independent
//! of the scene's units, see [`Mat4::normalized`](crate::math::Mat4::normalized)) and converted once to
//! 16.16 ([`FixedMat4`](crate::math::FixedMat4)); the world-space lights are
//! moved into the draw's model space ([`LightSetup`](crate::light::LightSetup), see [`crate::light`]),
//! so per vertex the stage needs only integer multiply-adds: 12 products for
//! the position, a few per light, and 3 quotients by `w` for the
//! perspective divide, which share one divisor (on a 32-bit core, one
//! reciprocal of `w` and three multiply-highs instead of three 64-bit
//! divisions; the quotients are the same). A Cortex-M0+ therefore does no
//! soft-float per vertex.
//!
//! The transform's sums of products are checked for overflow only for a
//! draw whose matrix and mesh could overflow them: the mesh knows its
//! largest coordinate ([`Mesh::extent`](crate::mesh::Mesh::extent)), so [`DrawSetup::new`] decides once
//! per draw whether any vertex could ([`FixedMat4::bounded`](crate::math::FixedMat4::bounded)).
//!
//! The files follow the vertex: `setup` (the per-draw set-up and the
//! vertex loop, with the common lit loop in `lit_loop`, the Lambert fast
//! path in `lambert` and the common loop's per-draw constants and colour
//! table in `lit_work`), `clip_space`
//! (the clipper's vertex, outcodes and the guard band), `viewport` (the
//! projection to screen sub-pixels and depth) and `screen` (the packed
//! [`ScreenVertex`]).

mod clip_space;
mod lambert;
mod lit_loop;
mod lit_work;
mod screen;
mod setup;
mod viewport;

pub use clip_space::{
    outcode, ClipVertex, BARY_ONE, GUARD_K, MUST_CLIP, OUT_BOTTOM, OUT_FAR, OUT_GUARD, OUT_LEFT,
    OUT_NEAR, OUT_RIGHT, OUT_TOP, OUT_W, REJECT_MASK, W_MIN,
};
pub(crate) use screen::INTERIOR_STARTS;
pub use screen::{ScreenVertex, COORD_BITS, COORD_MAX, COORD_MIN};
pub use setup::{DrawSetup, VertexError, MAX_LIGHTS};
pub use viewport::{Viewport, MAX_VIEWPORT};

/// `n / d` rounded to nearest (ties away from zero), for `d > 0`: the
/// rounding of every quotient of the vertex and attribute set-up (which
/// compute it through [`Divisor`]; the tests check them against this).
#[cfg(test)]
pub(crate) fn div_round(n: i64, d: i64) -> i64 {
    if n >= 0 {
        (n + d / 2) / d
    } else {
        -((-n + d / 2) / d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn div_round_rounds_half_away_from_zero() {
        assert_eq!(div_round(5, 2), 3);
        assert_eq!(div_round(-5, 2), -3);
        assert_eq!(div_round(4, 3), 1);
        assert_eq!(div_round(-4, 3), -1);
    }
}
