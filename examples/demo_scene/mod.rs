//! The demo scene's parameters, `no_std` and allocation-free: shared by the
//! host demo, tests and benchmarks (through `examples/common/mod.rs`) and by
//! the Cortex-M instruction-count firmware (`examples/icount_scenes`), so
//! every one of them renders the very same scene.
#![allow(dead_code)]

/// The checker texture, the same texels on the host and the firmware.
pub mod checker;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use microraster::fixed::types::I16F16;
use microraster::prelude::*;

/// The demo's background.
pub const DEMO_CLEAR: Rgb565 = Rgb565::new(3, 6, 8);

/// The knot: a (2, 3) torus knot of radius 1 with a tube of 0.28.
pub const KNOT_P: u32 = 2;
/// See [`KNOT_P`].
pub const KNOT_Q: u32 = 3;
/// See [`KNOT_P`].
pub const KNOT_RADIUS: f32 = 1.0;
/// See [`KNOT_P`].
pub const KNOT_TUBE: f32 = 0.28;
/// Knot resolution: 200 x 10 = 2,000 vertices, 4,000 triangles.
pub const KNOT_SEGMENTS: usize = 200;
/// See [`KNOT_SEGMENTS`].
pub const KNOT_SIDES: usize = 10;

/// Texture repeats along the knot and around its tube
/// ([`knot_uv`]), as the demo's textured looks map it.
pub const KNOT_UV_REPEATS: (f32, f32) = (6.0, 1.0);

/// The texture coordinates of knot vertex `(i, j)` (segment, side):
/// `u_repeats` along the knot and `v_repeats` around the tube, each a tent
/// (up then back down), so that they are continuous across the mesh's
/// seams (where a vertex cannot hold two coordinates) and the texture
/// shows mirrored in each half. A `const fn`, so that a firmware holds
/// them in flash, the same values as the host's.
pub const fn knot_uv(i: usize, j: usize, u_repeats: f32, v_repeats: f32) -> [I16F16; 2] {
    knot_uv_of(i, j, (KNOT_SEGMENTS, KNOT_SIDES), u_repeats, v_repeats)
}

/// [`knot_uv`] for a knot of `(segments, sides)` other than the demo's
/// (the benchmarks' 1,024-triangle textured knot).
pub const fn knot_uv_of(
    i: usize,
    j: usize,
    (segments, sides): (usize, usize),
    u_repeats: f32,
    v_repeats: f32,
) -> [I16F16; 2] {
    const fn tent(k: usize, n: usize, r: f32) -> I16F16 {
        let k = if k < n - k { k } else { n - k };
        fx(2.0 * (k as f32 / n as f32) * r)
    }
    [tent(i, segments, u_repeats), tent(j, sides, v_repeats)]
}

/// The demo's textured and lit look at animation time `t`: [`draws`]
/// through the scene's shader (`TexturedLit` in the benchmarks), white so
/// that the texture gives the colour, each draw sampling `texture`.
pub fn textured_draws<'a>(
    knot: &'a Mesh<'a>,
    cube: &'a Mesh<'a>,
    texture: &'a Texture<'a>,
    t: f32,
) -> [Draw<'a>; 2] {
    draws(knot, cube, t, Shading::Shader)
        .map(|d| d.color(Rgb888::new(255, 255, 255)).texture(texture))
}

/// The camera for a `width` x `height` frame; `None` only for a zero height.
pub fn camera(width: u32, height: u32) -> Option<Camera> {
    let view = Mat4::look_at(
        Vec3::new(0.0, 0.6, 4.2),
        Vec3::new(0.35, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    )?;
    let proj = Mat4::perspective(0.9, width as f32 / height as f32, 0.5, 20.0)?;
    Some(Camera::new(view, proj))
}

/// One white light from the upper left, with a bluish ambient term.
pub fn light() -> Light {
    Light::new(Vec3::new(-0.6, 0.8, 0.9)).ambient(Rgb888::new(40, 40, 56))
}

/// The knot and the cube at animation time `t` (radians of knot spin).
pub fn draws<'a>(
    knot: &'a Mesh<'a>,
    cube: &'a Mesh<'a>,
    t: f32,
    shading: Shading,
) -> [Draw<'a>; 2] {
    [
        Draw::new(knot)
            .transform(
                Mat4::translation(Vec3::new(-0.3, 0.0, 0.0))
                    * Mat4::rotation_y(t)
                    * Mat4::rotation_x(0.4),
            )
            .color(Rgb888::new(230, 120, 40))
            .shading(shading),
        Draw::new(cube)
            .transform(
                Mat4::translation(Vec3::new(1.75, 0.1, -0.3))
                    * Mat4::rotation_y(-1.3 * t + 0.5)
                    * Mat4::rotation_x(0.6)
                    * Mat4::scale(Vec3::new(0.42, 0.42, 0.42)),
            )
            .color(Rgb888::new(70, 150, 230))
            .shading(shading),
    ]
}

/// `v` in 16.16 in a `const` context (meshes built into flash), rounded to the nearest with ties to even, as
/// `I16F16::from_num` rounds (`v` well inside the 16.16 range).
pub const fn fx(v: f32) -> I16F16 {
    // Scaling by a power of two is exact, so one rounding happens, here.
    let x = v * 65536.0;
    let t = x as i64; // towards zero
    let frac = x - t as f32;
    let r = if frac > 0.5 || (frac == 0.5 && t % 2 != 0) {
        t + 1
    } else if frac < -0.5 || (frac == -0.5 && t % 2 != 0) {
        t - 1
    } else {
        t
    };
    I16F16::from_bits(r as i32)
}
