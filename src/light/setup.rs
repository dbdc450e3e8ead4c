//! The set-up of a [`Lighting`] for one draw ([`LightSetup`]): lights, eye
//! and fog moved into the draw's model space and converted to fixed point,
//! once per draw, in `f32`.

use super::arith::*;
use super::{Fog, LightError, Lighting, Material};
use crate::math::{sqrt, Inverse3, Mat4, Vec3};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::RgbColor;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Source {
    /// A point light whose range cannot reach any vertex.
    Off,
    /// Unit direction towards the light, Q16.
    Directional { dir: [i32; 3] },
    /// `pos`: raw 16.16; `reach`: the range in raw units (a vertex
    /// differing from `pos` by `reach` in any coordinate is out of range);
    /// `inv_range`: `1 / range` in model units, so that a length times it
    /// is `d / r` in Q16.
    Point {
        pos: [i64; 3],
        reach: u64,
        inv_range: Scale,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FixedLight {
    pub(super) source: Source,
    pub(super) color: [u8; 3],
}

impl FixedLight {
    const OFF: Self = Self {
        source: Source::Off,
        color: [0; 3],
    };
}

/// Fog in the draw's model space: `scale` turns a model-space distance into
/// Q16 (of `d / (end - start)` for linear fog, of `log2(e) · density · d`
/// for exponential fog).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FixedFog {
    None,
    /// `f = scale · d - offset`, with `offset = start / (end - start)` in Q16.
    Linear {
        scale: Scale,
        offset: i64,
    },
    Exponential {
        scale: Scale,
    },
}

/// The fixed-point set-up of a [`Lighting`] for one draw: lights, eye and
/// fog moved into the draw's model space. It holds at most `N` lights
/// (directional and point together).
///
/// Building it costs a few dozen `f32` operations per light (one `M⁻¹`
/// product each, a square root per directional light) and none per vertex;
/// it is deterministic, so rebuilding it gives the same bits. Its size is
/// 56 bytes per light plus about 64.
#[derive(Clone, Copy, Debug)]
pub struct LightSetup<const N: usize> {
    pub(super) lights: [FixedLight; N],
    pub(super) core: Core,
}

/// The part of a [`LightSetup`] that does not depend on its capacity.
#[derive(Clone, Copy, Debug)]
pub(super) struct Core {
    pub(super) count: usize,
    pub(super) ambient: [u8; 3],
    /// The eye in model space, raw 16.16.
    pub(super) eye: [i64; 3],
    pub(super) fog: FixedFog,
    pub(super) fog_color: [u8; 3],
    /// One directional light and nothing else: `n·l` in 1/256 steps, floored,
    /// as the vertex stage's `scene::Light` always did.
    pub(super) coarse: bool,
}

pub(super) fn rgb(c: Rgb888) -> [u8; 3] {
    [c.r(), c.g(), c.b()]
}

/// A model-space point or offset as raw 16.16 in `i64`, rounded; `None` when
/// not finite or beyond 2^60 raw (2^44 units).
pub(super) fn to_raw(v: Vec3) -> Option<[i64; 3]> {
    Some([raw_coord(v.x)?, raw_coord(v.y)?, raw_coord(v.z)?])
}

/// One coordinate of [`to_raw`], by the bits: what `x = c 65536` rounded
/// half away from zero as `f32` arithmetic gives (`x ± ½` rounded to
/// nearest even, then truncated; from 2^23 on `x` itself), without the
/// half-dozen soft-float calls (a multiply, four compares, an add) that
/// cost a Cortex-M3 a few hundred instructions a coordinate. `None` when
/// not finite or when `|x| > 2^60`.
pub(super) fn raw_coord(c: f32) -> Option<i64> {
    let bits = c.to_bits();
    let abs = bits & 0x7fff_ffff;
    // NaN, infinite, or |c| > 2^44 (the multiply by 2^16 is exact, or
    // infinite past f32's range: beyond 2^60 either way).
    if abs > 171 << 23 {
        return None;
    }
    let field = abs >> 23;
    let m = u64::from((abs & 0x7f_ffff) | 0x80_0000);
    let mag = if field >= 134 {
        // |x| >= 2^23: an integer, x = m 2^(field - 134), below 2^61.
        m << (field - 134)
    } else if field < 109 {
        // |x| < 1/4: |x| + ½ rounds below 1 (zero and subnormals too).
        0
    } else {
        // |x| in [1/4, 2^23): in units of 2^-25 it is the integer
        // m 2^(field - 109) < 2^48, and ½ is 2^24. Round the sum to 24
        // significant bits, nearest even, as the f32 add does, and
        // truncate to units.
        let s = (m << (field - 109)) + (1 << 24);
        let width = 64 - s.leading_zeros();
        let r = match width.checked_sub(24) {
            None | Some(0) => s,
            Some(shift) => {
                let q = s >> shift;
                let rem = s - (q << shift);
                let half = 1u64 << (shift - 1);
                let up = rem > half || (rem == half && q & 1 == 1);
                (q + u64::from(up)) << shift
            }
        };
        r >> 25
    };
    // Both the add and the truncation are symmetric in the sign.
    let mag = mag as i64;
    Some(if bits >> 31 == 1 { -mag } else { mag })
}

impl<const N: usize> LightSetup<N> {
    /// Moves `lighting` into the model space of a draw with model-to-world
    /// matrix `model`, seen from `eye` (the camera position, world space).
    ///
    /// Errors: more than `N` lights; a zero or non-finite direction; a
    /// non-finite position; a range that is not finite and positive; bad fog
    /// parameters; a singular or non-finite matrix or a non-finite eye (see
    /// [`LightError`]). Light indices count within their own slice.
    pub fn new(lighting: &Lighting<'_>, model: &Mat4, eye: Vec3) -> Result<Self, LightError> {
        let mut lights = [FixedLight::OFF; N];
        let core = Core::new(lighting, model, eye, &mut lights)?;
        Ok(Self { lights, core })
    }

    /// [`new`](Self::new) built in `slot` (left `None` on an error): the
    /// set-up is about 500 bytes, and a second copy on the stack would be
    /// on a frame's deepest path (the vertex stage's draw set-up).
    pub(crate) fn new_in<'s>(
        slot: &'s mut Option<Self>,
        lighting: &Lighting<'_>,
        model: &Mat4,
        eye: Vec3,
    ) -> Result<&'s Self, LightError> {
        let s = slot.insert(Self {
            lights: [FixedLight::OFF; N],
            core: Core::OFF,
        });
        let made = Core::new(lighting, model, eye, &mut s.lights).map(|core| s.core = core);
        match (made, slot) {
            (Ok(()), Some(s)) => Ok(s),
            (made, slot) => {
                *slot = None;
                Err(made.err().unwrap_or(LightError::BadMatrix))
            }
        }
    }

    /// The lit colour of a vertex.
    ///
    /// `base` is the vertex or draw colour (it multiplies the material's
    /// ambient and diffuse reflectance); `position` and `normal` are in the
    /// draw's model space, raw 16.16 bits. The normal should be unit length
    /// (it is not normalised; see the [module docs](crate::light)), but any normal,
    /// zero or huge, gives a defined colour.
    #[inline]
    pub fn shade(
        &self,
        material: &Material,
        base: [u8; 3],
        position: [i32; 3],
        normal: [i32; 3],
    ) -> [u8; 3] {
        let lights = &self.lights[..self.core.count.min(N)];
        self.core.shade(lights, material, base, position, normal)
    }

    /// For one directional light without fog (the lighting of a
    /// [`scene::Light`](crate::scene::Light)): its model-space unit
    /// direction (Q16), its colour and the ambient light, with which a
    /// white material without highlights is lit as
    /// `(base (256 ambient + colour · n·l) + 32,640) / 65,280`, `n·l` in
    /// 1/256 steps, floored, clamped to `0..=256` (the same bits as
    /// [`shade`](Self::shade), which the tests check): the vertex stage's
    /// fast path.
    pub(crate) fn single_directional(&self) -> Option<([i32; 3], [u8; 3], [u8; 3])> {
        self.core
            .single_directional(&self.lights[..self.core.count.min(N)])
    }
}

/// Everything of a [`LightSetup`] but its lights: the code that does not
/// depend on `N` lives here, so that it is compiled once (in this crate)
/// rather than once per instance and codegen unit of every user.
impl Core {
    /// No light, no fog: what [`LightSetup::new_in`] starts from.
    const OFF: Self = Self {
        count: 0,
        ambient: [0; 3],
        eye: [0; 3],
        fog: FixedFog::None,
        fog_color: [0; 3],
        coarse: false,
    };

    /// [`LightSetup::new`] into the light slots `lights`.
    pub(super) fn new(
        lighting: &Lighting<'_>,
        model: &Mat4,
        eye: Vec3,
        lights: &mut [FixedLight],
    ) -> Result<Self, LightError> {
        let count = lighting
            .directional
            .len()
            .saturating_add(lighting.point.len());
        if count > lights.len() {
            return Err(LightError::TooManyLights {
                count,
                max: lights.len(),
            });
        }
        // Made once, for the eye and every light.
        let inverse = model.inverse3();
        let (model_scale, eye) = model_space(model, eye, inverse.as_ref())?;
        let eye = to_raw(eye).ok_or(LightError::BadMatrix)?;
        let t = translation(model);
        let to_model = |p: Vec3| inverse.as_ref().and_then(|i| i.apply(p - t));

        let coarse = lighting.directional.len() == 1 && lighting.point.is_empty();
        let mut slots = lights.iter_mut();
        for (i, l) in lighting.directional.iter().enumerate() {
            let dir = directional_by(i, l.direction, inverse.as_ref(), coarse)?;
            if let Some(slot) = slots.next() {
                *slot = FixedLight {
                    source: Source::Directional { dir },
                    color: rgb(l.color),
                };
            }
        }
        for (i, l) in lighting.point.iter().enumerate() {
            if !l.position.is_finite() {
                return Err(LightError::BadPosition { light: i });
            }
            if !(l.range.is_finite() && l.range > 0.0) {
                return Err(LightError::BadRange { light: i });
            }
            let p = to_model(l.position).ok_or(LightError::BadPosition { light: i })?;
            let r = l.range / model_scale.get();
            if r.is_nan() || r * 65536.0 > (1u64 << 59) as f32 {
                return Err(LightError::BadRange { light: i });
            }
            // Vertices lie within ±32768 units: a light whose sphere misses
            // that cube lights nothing (and its position need not fit).
            let misses = [p.x, p.y, p.z].iter().any(|c| c.abs() - r > 32769.0);
            let reach = crate::math::f32_to_u64(r * 65536.0);
            let source = match (misses, to_raw(p), Scale::from_f32(1.0 / r)) {
                (false, Some(pos), Some(inv_range)) if reach > 0 => Source::Point {
                    pos,
                    reach,
                    inv_range,
                },
                _ => Source::Off,
            };
            if let Some(slot) = slots.next() {
                *slot = FixedLight {
                    source,
                    color: rgb(l.color),
                };
            }
        }

        let fog = match lighting.fog {
            Fog::None => FixedFog::None,
            Fog::Linear { start, end } => {
                let width = end - start;
                if !(start.is_finite() && end.is_finite() && width > 0.0 && width.is_finite()) {
                    return Err(LightError::BadFog);
                }
                let scale = Scale::from_f32(model_scale.get() / width).ok_or(LightError::BadFog)?;
                const LIMIT: f32 = (1u64 << 46) as f32;
                let offset =
                    crate::math::f32_to_i64((start / width * 65536.0).clamp(-LIMIT, LIMIT));
                FixedFog::Linear { scale, offset }
            }
            Fog::Exponential { density } => {
                if !(density.is_finite() && density >= 0.0) {
                    return Err(LightError::BadFog);
                }
                let scale =
                    Scale::from_f32(density * model_scale.get() * core::f32::consts::LOG2_E)
                        .ok_or(LightError::BadFog)?;
                FixedFog::Exponential { scale }
            }
        };

        Ok(Core {
            count,
            ambient: rgb(lighting.ambient),
            eye,
            fog,
            fog_color: rgb(lighting.fog_color),
            coarse,
        })
    }
}

/// The checks every set-up makes of a draw's model matrix and the eye, in
/// [`Core::new`]'s order: the model scale (world units per model unit), the
/// eye in model space, not yet known to fit raw 16.16, moved by `inverse`,
/// the model's [`Mat4::inverse3`] (made by the caller, which moves the
/// lights by it too: passed rather than returned, the Cortex-M3's
/// firmware optimised for size copied it about, some 200 bytes).
fn model_space<'m>(
    model: &'m Mat4,
    eye: Vec3,
    inverse: Option<&Inverse3>,
) -> Result<(ModelScale<'m>, Vec3), LightError> {
    let (scale, inverse) = model_scale(model, eye, inverse)?;
    match inverse.apply(eye - translation(model)) {
        Some(eye) => Ok((scale, eye)),
        None => Err(LightError::BadMatrix),
    }
}

/// The checks of [`model_space`] before the eye is moved: the model
/// scale, and the inverse known to be there.
fn model_scale<'m, 'i>(
    model: &'m Mat4,
    eye: Vec3,
    inverse: Option<&'i Inverse3>,
) -> Result<(ModelScale<'m>, &'i Inverse3), LightError> {
    // Every failure here is the same error: the order of the tests does
    // not show.
    let bad = Err(LightError::BadMatrix);
    // None for a singular matrix, too.
    let Some(inverse) = inverse else {
        return bad;
    };
    if !model.is_finite() || !eye.is_finite() {
        return bad;
    }
    let scale = ModelScale(model);
    // `sqrt(square)` is finite and positive exactly when `square` is
    // (math's tests check it); and when the 3x3 part's largest element
    // is within 2^-60 and 2^62 (`Inverse3::moderate`) it is: its square
    // is a normal f32 and the nine squares' sum below 2^128. Only a
    // matrix outside that has its square made here; the root is taken
    // only where a point light or fog asks for it (`ModelScale::get`).
    if !inverse.moderate() {
        let square = scale.square();
        if !(square.is_finite() && square > 0.0) {
            return bad;
        }
    }
    Ok((scale, inverse))
}

/// The model scale of [`model_space`] (world units per model unit, exact
/// for a uniform scale), made only where a point light or fog asks for it:
/// most set-ups never need it, its sum of squares and a root with three
/// divisions (some 2,000 instructions on the Cortex-M3).
#[derive(Clone, Copy)]
pub(crate) struct ModelScale<'m>(&'m Mat4);

impl ModelScale<'_> {
    /// The mean square of the model's three axes.
    fn square(self) -> f32 {
        let m = &self.0.m;
        let axis = |c: usize| Vec3::new(m[c][0], m[c][1], m[c][2]);
        (axis(0).dot(axis(0)) + axis(1).dot(axis(1)) + axis(2).dot(axis(2))) / 3.0
    }

    /// World units per model unit.
    pub(crate) fn get(self) -> f32 {
        sqrt(self.square())
    }
}

/// Directional light `i` (direction `direction`, world space) in the model
/// space of a model matrix whose [`Mat4::inverse3`] is `inverse` (`None`:
/// singular): its unit direction in Q16, truncated when `coarse` (one
/// directional light and nothing else), rounded otherwise. The inverse is
/// made once for the eye and every light.
fn directional_by(
    i: usize,
    direction: Vec3,
    inverse: Option<&Inverse3>,
    coarse: bool,
) -> Result<[i32; 3], LightError> {
    if !normalizes(direction) {
        return Err(LightError::BadDirection { light: i });
    }
    let local = inverse
        .and_then(|inverse| inverse.apply_unit(direction))
        .ok_or(LightError::BadMatrix)?;
    let fx = |v: f32| {
        // 2^16 by the exponent where `f32` is in software.
        let x = crate::math::times_pow2(v, 65536.0);
        if coarse {
            // Truncated, as the vertex stage converts scene::Light.
            crate::math::f32_to_i32(x)
        } else {
            // Where `f32` is in software, the sign by its bit rather than
            // a soft-float compare: they differ only for -0 (and NaN),
            // where -0.5 and 0.5 both truncate to 0.
            let negative = match crate::math::SOFT_FLOAT {
                true => x.to_bits() >> 31 != 0,
                false => x < 0.0,
            };
            let half = if negative { -0.5 } else { 0.5 };
            // The sum through the integer addition where `f32` is in
            // software (the same bits).
            crate::math::f32_to_i32(crate::math::soft_float::add(x, half))
        }
    };
    Ok([fx(local.x), fx(local.y), fx(local.z)])
}

/// Whether `to_raw(v)` is `Some`.
fn fits_raw(v: Vec3) -> bool {
    const LIMIT: f32 = (1u64 << 60) as f32;
    [v.x, v.y, v.z]
        .iter()
        .all(|&c| !(c * 65536.0).is_nan() && (c * 65536.0).abs() <= LIMIT)
}

/// The set-up of a draw lit by the directional lights `lights` and
/// nothing else, without the general lighting's code: the model-space
/// model scale (see [`model_space`]) and the unit direction (Q16) of the
/// last of the lights (`[0; 3]` for none) under
/// `model`, truncated when `coarse` (one light, as
/// [`LightSetup::single_directional`] gives it), rounded otherwise, with
/// the errors [`LightSetup::new`] gives for a [`Lighting`] of those
/// lights: the model and eye checks ([`model_checks_by`]) first. One
/// [`Mat4::inverse3`] for the eye and the lights.
pub(crate) fn directional_lights<'m>(
    lights: &[super::DirectionalLight],
    model: &'m Mat4,
    eye: Vec3,
    coarse: bool,
) -> Result<(ModelScale<'m>, [i32; 3]), LightError> {
    let inverse = model.inverse3();
    let scale = model_checks_by(model, eye, inverse.as_ref())?;
    let mut dir = [0; 3];
    for (i, l) in lights.iter().enumerate() {
        dir = directional_by(i, l.direction, inverse.as_ref(), coarse)?;
    }
    Ok((scale, dir))
}

/// [`directional_lights`] of one light (direction `direction`), coarse.
#[cfg(test)]
pub(crate) fn one_light(direction: Vec3, model: &Mat4, eye: Vec3) -> Result<[i32; 3], LightError> {
    let one = [super::DirectionalLight::new(direction, 1.0)];
    directional_lights(&one, model, eye, true).map(|(_, dir)| dir)
}

/// The checks of a draw's matrix and the eye that [`LightSetup::new`]
/// makes whatever the lights.
#[cfg(test)]
pub(crate) fn model_checks(model: &Mat4, eye: Vec3) -> Result<(), LightError> {
    model_checks_by(model, eye, model.inverse3().as_ref()).map(|_| ())
}

/// The checks of a draw's matrix and the eye that [`LightSetup::new`]
/// makes whatever the lights, with the model's [`Mat4::inverse3`] made
/// already; the model scale.
fn model_checks_by<'m>(
    model: &'m Mat4,
    eye: Vec3,
    inverse: Option<&Inverse3>,
) -> Result<ModelScale<'m>, LightError> {
    if BOUND_EYE {
        // The eye in model space is only tested here: where its bound
        // (from the exponents) fits, it is not made.
        let (scale, inverse) = model_scale(model, eye, inverse)?;
        if inverse.moves_within_2_44(eye, translation(model)) {
            return Ok(scale);
        }
    }
    let (scale, eye) = model_space(model, eye, inverse)?;
    match fits_raw(eye) {
        true => Ok(scale),
        false => Err(LightError::BadMatrix),
    }
}

/// Whether [`model_checks_by`] bounds the model-space eye from the
/// exponents before making it: where `f32` arithmetic is in software (the
/// eye's product and tests were some 1,600 instructions a draw on the
/// Cortex-M3), not in builds optimised for size (flash), and in the
/// library's own tests ([`SOFT_FLOAT`](crate::math::SOFT_FLOAT)).
const BOUND_EYE: bool = crate::math::SOFT_FLOAT;

/// The errors of [`directional_lights`] with the identity model matrix,
/// without its arithmetic: the identity's [`Mat4::inverse3`] is itself
/// (moderate, its `apply` of a finite vector finite: the vector, up to the
/// signs of zeros), so the model checks fail exactly for an eye that is
/// not finite or does not fit raw 16.16, and a light's direction exactly
/// where [`normalizes`] fails (as in [`directional_by`]; a finite non-zero
/// vector always normalizes). The inverse, two products by it and a
/// normalization were some 5,000 instructions a frame on the Cortex-M3,
/// for directions that were never used.
fn identity_checks(lights: &[super::DirectionalLight], eye: Vec3) -> Result<(), LightError> {
    if !(eye.is_finite() && fits_raw(eye)) {
        return Err(LightError::BadMatrix);
    }
    for (i, l) in lights.iter().enumerate() {
        if !normalizes(l.direction) {
            return Err(LightError::BadDirection { light: i });
        }
    }
    Ok(())
}

/// Whether `d.normalize()` is `Some`: `d` finite and not zero (a finite
/// non-zero vector always normalizes, scaled first if its squared length
/// leaves f32). Tested so rather than normalized, a square root and three
/// divisions the Cortex-M3 spent per draw, and by the bits (the sign
/// shifted out: a finite `f32`'s are below `0xff00_0000`, an infinite or
/// NaN one's are not), without soft-float compares.
#[inline(always)]
fn normalizes(d: Vec3) -> bool {
    const INF_BITS: u32 = 0xff00_0000;
    let (x, y, z) = (d.x.to_bits() << 1, d.y.to_bits() << 1, d.z.to_bits() << 1);
    x < INF_BITS && y < INF_BITS && z < INF_BITS && (x | y | z) != 0
}

/// The translation of the model matrix `m` (its last column).
#[inline(always)]
fn translation(m: &Mat4) -> Vec3 {
    Vec3::new(m.m[3][0], m.m[3][1], m.m[3][2])
}

/// Checks `lighting` as [`LightSetup::new`] with at most `max` lights, an
/// identity model matrix and the eye `eye` does, with the same errors, but
/// converts nothing: the check of a frame's lights in a renderer that does
/// not link the general lighting.
pub(crate) fn check_lighting(
    lighting: &Lighting<'_>,
    eye: Vec3,
    max: usize,
) -> Result<(), LightError> {
    let count = lighting
        .directional
        .len()
        .saturating_add(lighting.point.len());
    if count > max {
        return Err(LightError::TooManyLights { count, max });
    }
    // Builds optimised for size keep the one set-up (`identity_checks`
    // was 156 bytes of the OLED firmware).
    match cfg!(microraster_size) {
        true => directional_lights(lighting.directional, &Mat4::IDENTITY, eye, true).map(|_| ())?,
        false => identity_checks(lighting.directional, eye)?,
    }
    let scale = ModelScale(&Mat4::IDENTITY);
    for (i, l) in lighting.point.iter().enumerate() {
        // In the identity's model space a finite position stays finite.
        if !l.position.is_finite() {
            return Err(LightError::BadPosition { light: i });
        }
        if !(l.range.is_finite() && l.range > 0.0) {
            return Err(LightError::BadRange { light: i });
        }
        let r = l.range / scale.get();
        if r.is_nan() || r * 65536.0 > (1u64 << 59) as f32 {
            return Err(LightError::BadRange { light: i });
        }
    }
    // `Scale::from_f32` refuses only what is not finite or is negative.
    let fog_scale = match lighting.fog {
        Fog::None => return Ok(()),
        Fog::Linear { start, end } => {
            let width = end - start;
            if !(start.is_finite() && end.is_finite() && width > 0.0 && width.is_finite()) {
                return Err(LightError::BadFog);
            }
            scale.get() / width
        }
        Fog::Exponential { density } => {
            if !(density.is_finite() && density >= 0.0) {
                return Err(LightError::BadFog);
            }
            density * scale.get() * core::f32::consts::LOG2_E
        }
    };
    match fog_scale.is_finite() && fog_scale >= 0.0 {
        true => Ok(()),
        false => Err(LightError::BadFog),
    }
}
