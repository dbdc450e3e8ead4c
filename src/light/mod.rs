//! Per-vertex lighting in fixed point: ambient, Lambert diffuse and
//! Blinn-Phong specular from directional and point lights, and fog,
//! evaluated in a draw's model space.
//!
//! A [`Lighting`] describes the lights of a frame in world space, in `f32`.
//! Once per draw, [`LightSetup::new`] moves them into the draw's model space
//! and converts them to fixed point; per vertex, [`LightSetup::shade`] needs
//! only integer arithmetic, so every target computes the same bits and a
//! core without an FPU does no soft-float per vertex.
//!
//! # The model
//!
//! With colours as fractions (a byte over 255) and `⊙` the per-channel
//! product:
//!
//! ```text
//! lit    = base ⊙ (Ma ⊙ A + Σ att_l · Md ⊙ C_l · max(0, n·l_l))
//!        +         Σ att_l · Ms ⊙ C_l · spec_l
//! spec_l = max(0, n·h_l)^shininess,   h_l = normalize(l_l + v)   (0 when n·l_l <= 0)
//! colour = mix(min(lit, 1), fog_color, f)
//! ```
//!
//! `base` is the vertex (or draw) colour, `Ma`, `Md`, `Ms` the [`Material`]'s
//! ambient, diffuse and specular colours, `A` the ambient light, `C_l` the
//! colour of light `l`, `l_l` the unit vector from the vertex towards the
//! light, `v` the one towards the eye, `n` the vertex normal. The result is
//! rounded to the nearest byte.
//!
//! * Directional lights have `att = 1`. A point light at distance `d` and
//!   with range `r` has the windowed falloff `att = (1 - (d/r)²)²` for
//!   `d < r` and 0 beyond: 1 at the light, falling smoothly to exactly 0,
//!   with zero slope, at the range, so no light pops at its edge.
//! * Fog, with `d` the distance from the eye in world units:
//!   [`Fog::Linear`] `f = clamp((d - start) / (end - start), 0, 1)`,
//!   [`Fog::Exponential`] `f = 1 - exp(-density · d)`.
//! * The normal is used as given, not normalised: `n·l` and `n·h` are
//!   clamped to `[0, 1]`, so a normal shorter than unit darkens and a longer
//!   one brightens, as with [`scene::Light`](crate::scene::Light). Mesh
//!   normals are unit vectors ([`Mesh::with_normals`](crate::mesh::Mesh::with_normals)).
//!   Any normal gives a defined colour: a zero normal gets the ambient term
//!   only, a huge one full diffuse light.
//! * Undefined directions contribute nothing: a vertex exactly at a point
//!   light gets nothing from it, one exactly at the eye no specular, and no
//!   light has a specular term when `l + v = 0`.
//!
//! # Model space
//!
//! Per vertex, everything happens in the draw's model space, where the
//! mesh's positions and normals are: set-up moves light directions there as
//! `M⁻¹ L` (normalised, exactly as [`scene::Light`](crate::scene::Light) is),
//! positions (lights, eye) as `M⁻¹ (P - t)`, and divides ranges and fog
//! distances by the draw's scale `s`, the root mean square of the lengths of
//! the matrix's three axes. The bottom row of the model matrix is ignored (it
//! is taken as affine).
//!
//! This is exact for similarity transforms: rotations, reflections,
//! translations and uniform scales. With a non-uniform scale, lighting is
//! computed in the squashed model space: `n·l` pairs the model-space normal
//! with `M⁻¹ L` rather than the world normal with `L` (the approximation
//! `scene::Light` makes), half vectors are taken there too, and distances are
//! model-space distances times `s`, so a point light's sphere of influence
//! and the fog's distance shells become ellipsoids in world space.
//!
//! # Fixed-point formats
//!
//! | Quantity | Format |
//! |---|---|
//! | vertex position, normal | raw 16.16 (`i32`), model space |
//! | light and eye positions | raw 16.16 in `i64`, below 2^60 in magnitude |
//! | unit vectors `l`, `v`, `h` | Q16 (`i32`, 1.0 = 65,536) |
//! | `n·l`, `n·h`, `att`, `spec_l`, fog `f` | Q16 (`u32`, `0..=65,536`) |
//! | lengths | a 16-bit mantissa and a power of two |
//! | `1 / range`, fog scales | a 16-bit mantissa and a power of two |
//! | colour sums | `u32`, in 1 / 65,280 of a byte (see below) |
//!
//! # Ranges, and why nothing overflows
//!
//! Every product in [`LightSetup::shade`] is 32 x 32 -> 32 bits, on operands
//! bounded so that it fits:
//!
//! * A dot product of the normal with a Q16 unit vector `u` (components up
//!   to ±2^17) splits `u` into its high and low bytes:
//!   `n·u = 256 Σ n_i hi_i + Σ n_i lo_i`. For normal components up to ±2
//!   (raw ±2^17) both sums stay below 3 · 2^26, and the result is the exact
//!   floor of `n·u / 2^16`. A normal with a larger component (a broken mesh)
//!   takes an exact `i64` path instead, so any normal is defined.
//! * A vector is normalised by shifting it (rounding) until its largest
//!   component has 15 bits, or 16 if its squared length `s` would be below
//!   2^30: then `s` lies in `[2^30, 2^32)`, `r = 2^31 / sqrt(s)` comes from a
//!   table, and the unit vector's components `|w_i| r / 2^15` have products
//!   at most `sqrt(s) r ≈ 2^31`. Its length `s r / 2^31` is computed from the
//!   16-bit halves of `s`, each product again about `sqrt(s) 2^15`.
//! * A length (16-bit mantissa) times a 16-bit mantissa scale is below 2^32;
//!   the shifted result (`d / r`, fog distance) saturates at 2^47.
//! * Q16 fractions are multiplied only below 1.0 ((2^16 - 1)² + 2^15 <
//!   2^32); a factor of exactly 1.0 is passed through.
//! * Colours are multiplied at full precision. Per light and channel,
//!   `Md · C_l` (at most 65,025) times a Q16 factor (`n·l · att`) is at most
//!   65,025 · 65,536 < 2^32 - 128, and shifted down 8 bits. The diffuse sum
//!   `I = Ma · A · 256 + Σ (Md · C_l · n·l · att) / 256` is in 1 / (255 ·
//!   65,280) of the base colour, so that `K = I / 255` is in the units of the
//!   vertex stage's old intensity (full intensity = 65,280); the specular sum
//!   `J` is in 1 / 65,280 of a byte. Both add with saturation, and are then
//!   clamped where the byte saturates anyway (`K` at 255 times full
//!   intensity, where any non-zero base colour gives 255; `J` at 255 bytes),
//!   which changes no result and bounds `base · K + J` to 256 · 255 · 65,280
//!   < 2^32 - 2^15. The byte is `(base · K + J + 32,640) / 65,280`.
//! * Fog mixes the lit colour, in 1/256 of a byte, with the fog colour in
//!   Q16: a convex combination, at most 65,280 · 2^16 + 2^23 < 2^32.
//!
//! Divisions by 255 are done by shifts and adds (exact for every `u32`): a
//! Cortex-M0+ has neither a divider nor the multiply-high a compiler
//! divides by a constant with.
//!
//! 64-bit arithmetic appears only in the vectors from a vertex to a point
//! light or the eye, which can exceed 32 bits when the draw's model space is
//! small (subtractions, comparisons and shifts; no 64-bit multiply, which a
//! Cortex-M0+ lacks), and in the broken-normal path above.
//!
//! # Accuracy
//!
//! * `1 / sqrt`: two 129-entry tables (one per octave of `m` in `[1, 4)`) of
//!   `2^16 / sqrt(m)`, built at compile time with an exact integer square
//!   root and interpolated linearly: within 1.25 units of `2^31 / sqrt(s)`
//!   (relative error below 3 · 10^-5). Unit vectors are then within
//!   4.5 · 10^-5 of the exact direction (per component) and lengths within
//!   6.5 · 10^-5 (relative).
//! * `1 / range` and the fog scales keep 16-bit mantissas (relative error
//!   2^-16); the attenuation polynomial is within 1.5 / 65,536.
//! * `x^shininess`: binary exponentiation in Q16, every product rounded (at
//!   most 14 products), within `(shininess + 2) / 2^17`; any exponent
//!   `0..=255`, no table.
//! * Exponential fog: `2^-x` from a 33-entry table of `2^(-i/32)` (built at
//!   compile time) interpolated linearly, within 7.5 · 10^-5.
//! * Altogether, against an `f64` evaluation of the same model (random
//!   materials, lights, ranges, fog, normals, and positions up to ±30,000
//!   model units), every channel is within ±1.5 of the exact value for
//!   shininess up to 160, and within ±2.5 above (measured worst cases over 14
//!   million channels: 1.23, 1.36 and 2.03 for shininess up to 64, up to 160
//!   and above; 99.99 % are within ±1, the rounding's ±0.5 included). The
//!   largest errors come from sharp highlights, whose error is the shininess
//!   times the error of `n·h` (about 2^-16), and from the 1/256 `n·l` steps
//!   of the compatible case (below).
//!
//! Some conditions amplify errors in any implementation: a fog band narrow
//! compared with its distance (`d / (end - start)` large); a half vector
//! near zero (`l ≈ -v`); the model's own discontinuity at `n·l = 0`, where a
//! highlight is cut off (a vertex within about 10^-4 of it may keep or lose
//! it). Set-up is `f32`, so light and eye positions in model space carry its
//! relative error of about 2^-24 of their coordinates, which matters only
//! for lights very close (compared with their distance from the model's
//! origin) to a vertex.
//!
//! # Compatibility with `scene::Light`
//!
//! A [`Lighting`] with exactly one directional light, no point lights and no
//! fog, shading with white ambient and diffuse reflectance and black
//! specular (the default [`Material`]), reproduces the vertex stage's
//! [`scene::Light`](crate::scene::Light) lighting bit for bit, for any normal:
//! for that one light set `n·l` is floored to 1/256 as it always was (an
//! error of up to one byte in bright light, included in the bounds above).
//! Every other light set keeps `n·l` to 1/65,536.
//!
//! # Cost
//!
//! Per vertex, roughly ("mul" is a 32 x 32 -> 32-bit multiply, "ops" other
//! integer operations):
//!
//! * always: 3 mul for the ambient term; 3 mul and two divisions by 255
//!   (about 25 ops) per channel to combine;
//! * each directional light: 6 mul for `n·l`, 6 for the colour, about 30 ops;
//! * each point light: three 64-bit subtractions and range tests (about 25
//!   ops; the end of it for a vertex out of range), then a normalisation
//!   (about 9 mul and 80 ops, including a 64-bit leading-zero count and
//!   three 64-bit shifts), 3 mul for `d / r` and the falloff, and then as a
//!   directional light plus 1 mul;
//! * each light's highlight, when the material's specular colour is not
//!   black and `n·l > 0`: a normalisation of the half vector, 6 mul for
//!   `n·h`, up to 14 for the power (5 for shininess 16), 7 for the colour;
//!   and once per vertex, for highlights or fog, a normalisation of the
//!   vector to the eye;
//! * fog: 1 mul for the distance, 1 for exponential fog's table, 6 to mix.
//!
//! [`LightSetup::new`] costs some tens of `f32` operations per light (an
//! `M⁻¹` product with one division each, a square root per directional
//! light): once per draw, not per vertex.
//!
//! ```
//! use embedded_graphics::pixelcolor::Rgb888;
//! use microraster::light::{DirectionalLight, Lighting, LightSetup, Material, PointLight};
//! use microraster::math::{Mat4, Vec3};
//!
//! let sun = [DirectionalLight::new(Vec3::new(0.0, 1.0, 0.0), Rgb888::new(200, 200, 200))];
//! let lamp = [PointLight::new(Vec3::new(0.0, 0.0, 2.0), Rgb888::new(255, 128, 0), 5.0)];
//! let lighting = Lighting::new(Rgb888::new(30, 30, 30)).directional(&sun).point(&lamp);
//!
//! // One draw, placed at the origin; the camera at (0, 0, 10).
//! let setup: LightSetup<4> =
//!     LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::new(0.0, 0.0, 10.0)).unwrap();
//!
//! // A vertex at the origin facing +z (towards the lamp), raw 16.16.
//! let material = Material::new()
//!     .specular(Rgb888::new(255, 255, 255))
//!     .shininess(32);
//! let lit = setup.shade(&material, [255, 255, 255], [0, 0, 0], [0, 0, 1 << 16]);
//! // Ambient 30; the sun grazes (n·l = 0); the lamp, 2 units away out of 5,
//! // has att = (1 - 0.16)² = 0.7056, and both its diffuse term (n·l = 1) and
//! // its highlight (h = n) are full: green is 30 + 2 · 0.7056 · 128 = 210.6.
//! assert_eq!(lit, [255, 211, 30]);
//!
//! // Facing away from both lights: ambient only.
//! let dark = setup.shade(&material, [255, 255, 255], [0, 0, 0], [0, 0, -1 << 16]);
//! assert_eq!(dark, [30, 30, 30]);
//! ```

mod arith;
mod setup;
mod shade;
// The tests (in a file of their own) run on the host, with std: its
// names they use are imported here, under the same `cfg(test)`.
#[cfg(test)]
extern crate std;
#[cfg(test)]
use std::{format, println, string::String, vec::Vec};
#[cfg(test)]
mod tests;

pub(crate) use arith::div255;
pub use setup::LightSetup;
pub(crate) use setup::{check_lighting, directional_lights};

use crate::math::Vec3;
use embedded_graphics::pixelcolor::Rgb888;

/// How a surface reflects light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Material {
    /// Reflectance of the ambient light (multiplied by the vertex colour).
    pub ambient: Rgb888,
    /// Reflectance of the lights' diffuse (Lambert) term (multiplied by the
    /// vertex colour).
    pub diffuse: Rgb888,
    /// Colour of the specular highlights (not multiplied by the vertex
    /// colour); black turns them off, and skips their cost.
    pub specular: Rgb888,
    /// Blinn-Phong exponent: larger is a smaller, sharper highlight.
    pub shininess: u8,
}

impl Material {
    /// White ambient and diffuse reflectance, no specular highlight,
    /// shininess 16: the vertex colour lit as by
    /// [`scene::Light`](crate::scene::Light).
    pub const fn new() -> Self {
        Self {
            ambient: Rgb888::new(255, 255, 255),
            diffuse: Rgb888::new(255, 255, 255),
            specular: Rgb888::new(0, 0, 0),
            shininess: 16,
        }
    }

    /// Sets the ambient reflectance.
    pub const fn ambient(mut self, ambient: Rgb888) -> Self {
        self.ambient = ambient;
        self
    }

    /// Sets the diffuse reflectance.
    pub const fn diffuse(mut self, diffuse: Rgb888) -> Self {
        self.diffuse = diffuse;
        self
    }

    /// Sets the specular colour.
    pub const fn specular(mut self, specular: Rgb888) -> Self {
        self.specular = specular;
        self
    }

    /// Sets the Blinn-Phong exponent.
    pub const fn shininess(mut self, shininess: u8) -> Self {
        self.shininess = shininess;
        self
    }
}

impl Default for Material {
    fn default() -> Self {
        Self::new()
    }
}

/// The colour and strength of a light or of an ambient term: a colour, or
/// a plain fraction of white.
///
/// Every constructor of a light ([`DirectionalLight::new`],
/// [`PointLight::new`], [`Lighting::new`]'s ambient term, and
/// [`scene::Light`](crate::scene::Light)'s `color` and `ambient`) takes
/// `impl Into<Intensity>`, so `0.8` and `Rgb888::new(204, 204, 204)` are the
/// same light. A fraction is clamped to `[0, 1]` (NaN counts as 0) and
/// rounded to the nearest of 256 levels, in `f32`.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microraster::light::{DirectionalLight, Intensity, Lighting};
/// use microraster::math::Vec3;
///
/// let sun = [DirectionalLight::new(Vec3::new(0.0, 1.0, 0.0), 0.8)];
/// assert_eq!(sun[0].color, Rgb888::new(204, 204, 204));
/// let lighting = Lighting::new(0.2).directional(&sun);
/// assert_eq!(lighting.ambient, Rgb888::new(51, 51, 51));
/// // A colour as before; a fraction beyond 1 is white.
/// let warm = DirectionalLight::new(Vec3::new(1.0, 0.0, 0.0), Rgb888::new(255, 160, 64));
/// assert_eq!(warm.color, Rgb888::new(255, 160, 64));
/// assert_eq!(Intensity::from(1.5), Intensity(Rgb888::new(255, 255, 255)));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Intensity(pub Rgb888);

impl From<Rgb888> for Intensity {
    fn from(c: Rgb888) -> Self {
        Self(c)
    }
}

impl From<f32> for Intensity {
    fn from(fraction: f32) -> Self {
        // NaN fails the test and becomes 0; the sum is below 256, so the
        // conversion only truncates.
        let f = if fraction > 0.0 {
            fraction.min(1.0)
        } else {
            0.0
        };
        let level = crate::math::f32_to_u8(f * 255.0 + 0.5);
        Self(Rgb888::new(level, level, level))
    }
}

/// For a fraction written as a literal (`0.8` is an `f64` where nothing
/// says otherwise): converted to `f32` first, so no `f64` arithmetic runs.
impl From<f64> for Intensity {
    fn from(fraction: f64) -> Self {
        Self::from(fraction as f32)
    }
}

impl From<Intensity> for Rgb888 {
    fn from(i: Intensity) -> Self {
        i.0
    }
}

/// A light infinitely far away, shining from one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Direction *towards* the light, in world space (need not be unit).
    pub direction: Vec3,
    /// Colour of the light.
    pub color: Rgb888,
}

impl DirectionalLight {
    /// A light shining from `direction` (towards the light, world space),
    /// of a colour or a fraction of white ([`Intensity`]).
    pub fn new(direction: Vec3, color: impl Into<Intensity>) -> Self {
        Self {
            direction,
            color: color.into().0,
        }
    }
}

/// A light at a point, fading out with distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Position in world space.
    pub position: Vec3,
    /// Colour of the light (at the light itself).
    pub color: Rgb888,
    /// Distance, in world units, at which the light has faded out entirely:
    /// the attenuation is `(1 - (d / range)²)²` at distance `d < range`, and
    /// 0 beyond.
    pub range: f32,
}

impl PointLight {
    /// A light at `position` reaching `range` world units, of a colour or
    /// a fraction of white ([`Intensity`]).
    pub fn new(position: Vec3, color: impl Into<Intensity>, range: f32) -> Self {
        Self {
            position,
            color: color.into().0,
            range,
        }
    }
}

/// Fog: the lit colour fades towards [`Lighting::fog_color`] with the
/// distance from the eye.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Fog {
    /// No fog.
    #[default]
    None,
    /// No fog up to distance `start`, then linearly more, full fog from
    /// `end` on (`start < end`, world units).
    Linear {
        /// Distance where the fog begins.
        start: f32,
        /// Distance where the fog is complete.
        end: f32,
    },
    /// Fog fraction `1 - exp(-density · d)` at distance `d` (world units,
    /// `density >= 0`).
    Exponential {
        /// Extinction per world unit.
        density: f32,
    },
}

/// The lights of a frame, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting<'a> {
    /// Ambient light, added everywhere (times the material's ambient
    /// reflectance and the vertex colour).
    pub ambient: Rgb888,
    /// Directional lights.
    pub directional: &'a [DirectionalLight],
    /// Point lights.
    pub point: &'a [PointLight],
    /// Fog.
    pub fog: Fog,
    /// The colour fog fades to.
    pub fog_color: Rgb888,
}

impl<'a> Lighting<'a> {
    /// Ambient light only (a colour or a fraction of white, see
    /// [`Intensity`]): no lights, no fog (fog colour black).
    pub fn new(ambient: impl Into<Intensity>) -> Self {
        Self {
            ambient: ambient.into().0,
            directional: &[],
            point: &[],
            fog: Fog::None,
            fog_color: Rgb888::new(0, 0, 0),
        }
    }

    /// Sets the directional lights.
    pub const fn directional(mut self, lights: &'a [DirectionalLight]) -> Self {
        self.directional = lights;
        self
    }

    /// Sets the point lights.
    pub const fn point(mut self, lights: &'a [PointLight]) -> Self {
        self.point = lights;
        self
    }

    /// Sets the fog.
    pub const fn fog(mut self, fog: Fog) -> Self {
        self.fog = fog;
        self
    }

    /// Sets the fog colour.
    pub const fn fog_color(mut self, color: Rgb888) -> Self {
        self.fog_color = color;
        self
    }
}

/// Why [`LightSetup::new`] refused a [`Lighting`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightError {
    /// More lights (directional and point together) than the set-up holds.
    TooManyLights {
        /// Lights given.
        count: usize,
        /// The set-up's capacity `N`.
        max: usize,
    },
    /// A directional light's direction is zero or not finite.
    BadDirection {
        /// Index in [`Lighting::directional`].
        light: usize,
    },
    /// A point light's position is not finite (in world or model space).
    BadPosition {
        /// Index in [`Lighting::point`].
        light: usize,
    },
    /// A point light's range is not finite and positive, or is beyond 2^43
    /// units of the draw's model space.
    BadRange {
        /// Index in [`Lighting::point`].
        light: usize,
    },
    /// Linear fog without finite `start < end`, or exponential fog without
    /// a finite `density >= 0`, or fog whose scale overflows `f32` in the
    /// draw's model space.
    BadFog,
    /// The model matrix is not finite or singular, or the eye is not finite
    /// or beyond 2^44 units of the draw's model space.
    BadMatrix,
}

impl core::fmt::Display for LightError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::TooManyLights { count, max } => {
                write!(f, "{count} lights exceed the capacity of {max}")
            }
            Self::BadDirection { light } => write!(
                f,
                "directional light {light} has a zero or non-finite direction"
            ),
            Self::BadPosition { light } => {
                write!(f, "point light {light} has a non-finite position")
            }
            Self::BadRange { light } => {
                write!(f, "point light {light} has a bad range")
            }
            Self::BadFog => write!(f, "the fog parameters are not usable"),
            Self::BadMatrix => write!(
                f,
                "the model matrix is singular or not finite, or the eye is not usable"
            ),
        }
    }
}
