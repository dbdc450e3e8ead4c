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

use crate::math::{sqrt, Mat4, Vec3};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::RgbColor;

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

/// 1.0 in Q16.
const ONE: u32 = 1 << 16;

/// Full intensity in the units of the colour terms (1 / 65,280 of a byte
/// per unit of base colour): 255 · 256.
const FULL: u32 = 255 * 256;

/// The largest useful scaled diffuse sum `K`: with it, any non-zero base
/// colour already saturates the byte (`base · K / FULL >= 255`).
const K_MAX: u32 = 255 * FULL;

/// A non-negative constant `m · 2^-s`, `m` in `[2^15, 2^16)` or 0: an `f32`
/// factor applied per vertex with one 32-bit product and a shift.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Scale {
    m: u32,
    s: i32,
}

/// Where [`Scale::apply`] saturates (far beyond any Q16 fraction used).
const SCALE_CAP: u64 = 1 << 47;

impl Scale {
    /// The scale of a finite `x >= 0`, its mantissa rounded to 16 bits.
    fn from_f32(x: f32) -> Option<Self> {
        if !x.is_finite() || x < 0.0 {
            return None;
        }
        let bits = x.to_bits();
        let biased = ((bits >> 23) & 0xff) as i32;
        // Zero or subnormal: below 2^-126, which times any length below
        // 2^62 rounds to 0 in Q16.
        if biased == 0 {
            return Some(Self { m: 0, s: 0 });
        }
        let mant = (bits & 0x7f_ffff) | 0x80_0000;
        let mut m = (mant + 0x80) >> 8;
        let mut e = biased - 127;
        if m == 1 << 16 {
            m = 1 << 15;
            e += 1;
        }
        // x = mant · 2^(e - 23) ≈ m · 2^(e - 15).
        Some(Self { m, s: 15 - e })
    }

    /// `round(len · 2^exp · self)`, saturated at [`SCALE_CAP`], for
    /// `len <= 2^16`.
    #[inline]
    fn apply(self, len: u32, exp: i32) -> u64 {
        // len.min(2^16) · m <= 2^16 · (2^16 - 1) < 2^32.
        let prod = len.min(ONE) * self.m;
        let sh = self.s - exp;
        if sh > 0 {
            if sh > 32 {
                0
            } else {
                // Rounded, in 32 bits (sh - 1 < 32; no carry out).
                let twice = prod >> (sh - 1);
                ((twice >> 1) + (twice & 1)) as u64
            }
        } else if sh < -16 {
            if prod == 0 {
                0
            } else {
                SCALE_CAP
            }
        } else {
            ((prod as u64) << -sh).min(SCALE_CAP)
        }
    }
}

/// A light in the draw's model space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
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
struct FixedLight {
    source: Source,
    color: [u8; 3],
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
enum FixedFog {
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
    lights: [FixedLight; N],
    core: Core,
}

/// The part of a [`LightSetup`] that does not depend on its capacity.
#[derive(Clone, Copy, Debug)]
struct Core {
    count: usize,
    ambient: [u8; 3],
    /// The eye in model space, raw 16.16.
    eye: [i64; 3],
    fog: FixedFog,
    fog_color: [u8; 3],
    /// One directional light and nothing else: `n·l` in 1/256 steps, floored,
    /// as the vertex stage's `scene::Light` always did.
    coarse: bool,
}

fn rgb(c: Rgb888) -> [u8; 3] {
    [c.r(), c.g(), c.b()]
}

/// A model-space point or offset as raw 16.16 in `i64`, rounded; `None` when
/// not finite or beyond 2^60 raw (2^44 units).
fn to_raw(v: Vec3) -> Option<[i64; 3]> {
    const LIMIT: f32 = (1u64 << 60) as f32;
    let mut out = [0i64; 3];
    for (o, c) in out.iter_mut().zip([v.x, v.y, v.z]) {
        let x = c * 65536.0;
        if x.is_nan() || x.abs() > LIMIT {
            return None;
        }
        // Round half away from zero (the conversion truncates). From 2^23 on, `x`
        // is an integer, and adding ½ would round to even instead.
        let half = if x.abs() >= 8_388_608.0 {
            0.0
        } else if x < 0.0 {
            -0.5
        } else {
            0.5
        };
        *o = crate::math::f32_to_i64(x + half);
    }
    Some(out)
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

    /// The lit colour of a vertex.
    ///
    /// `base` is the vertex or draw colour (it multiplies the material's
    /// ambient and diffuse reflectance); `position` and `normal` are in the
    /// draw's model space, raw 16.16 bits. The normal should be unit length
    /// (it is not normalised; see the [module docs](self)), but any normal,
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
    /// [`LightSetup::new`] into the light slots `lights`.
    fn new(
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
        if !model.is_finite() {
            return Err(LightError::BadMatrix);
        }
        let m = &model.m;
        let t = Vec3::new(m[3][0], m[3][1], m[3][2]);
        let to_model = |p: Vec3| model.inverse_transform_vector(p - t);
        // World units per model unit (exact for a uniform scale).
        let axis = |c: usize| Vec3::new(m[c][0], m[c][1], m[c][2]);
        let model_scale =
            sqrt((axis(0).dot(axis(0)) + axis(1).dot(axis(1)) + axis(2).dot(axis(2))) / 3.0);
        if !(model_scale.is_finite() && model_scale > 0.0) {
            return Err(LightError::BadMatrix);
        }
        if !eye.is_finite() {
            return Err(LightError::BadMatrix);
        }
        // None for a singular matrix, too.
        let eye = to_model(eye)
            .and_then(to_raw)
            .ok_or(LightError::BadMatrix)?;

        let coarse = lighting.directional.len() == 1 && lighting.point.is_empty();
        let mut slots = lights.iter_mut();
        for (i, l) in lighting.directional.iter().enumerate() {
            if l.direction.normalize().is_none() {
                return Err(LightError::BadDirection { light: i });
            }
            let local = model
                .inverse_transform_vector(l.direction)
                .and_then(|v| v.normalize())
                .ok_or(LightError::BadMatrix)?;
            let fx = |v: f32| {
                let x = v * 65536.0;
                if coarse {
                    // Truncated, as the vertex stage converts scene::Light.
                    crate::math::f32_to_i32(x)
                } else {
                    crate::math::f32_to_i32(x + if x < 0.0 { -0.5 } else { 0.5 })
                }
            };
            if let Some(slot) = slots.next() {
                *slot = FixedLight {
                    source: Source::Directional {
                        dir: [fx(local.x), fx(local.y), fx(local.z)],
                    },
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
            let r = l.range / model_scale;
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
                let scale = Scale::from_f32(model_scale / width).ok_or(LightError::BadFog)?;
                const LIMIT: f32 = (1u64 << 46) as f32;
                let offset =
                    crate::math::f32_to_i64((start / width * 65536.0).clamp(-LIMIT, LIMIT));
                FixedFog::Linear { scale, offset }
            }
            Fog::Exponential { density } => {
                if !(density.is_finite() && density >= 0.0) {
                    return Err(LightError::BadFog);
                }
                let scale = Scale::from_f32(density * model_scale * core::f32::consts::LOG2_E)
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

    /// The lit colour of a vertex.
    ///
    /// `base` is the vertex or draw colour (it multiplies the material's
    /// ambient and diffuse reflectance); `position` and `normal` are in the
    /// draw's model space, raw 16.16 bits. The normal should be unit length
    /// (it is not normalised; see the [module docs](self)), but any normal,
    /// zero or huge, gives a defined colour.
    fn shade(
        &self,
        lights: &[FixedLight],
        material: &Material,
        base: [u8; 3],
        position: [i32; 3],
        normal: [i32; 3],
    ) -> [u8; 3] {
        let n = Normal::new(normal);
        let (ma, md, ms) = (
            rgb(material.ambient),
            rgb(material.diffuse),
            rgb(material.specular),
        );
        // Bitwise, as an array comparison would call memcmp.
        let specular_on = (ms[0] | ms[1] | ms[2]) != 0;
        if let (true, false, FixedFog::None, Some(Source::Directional { dir })) = (
            self.coarse,
            specular_on,
            self.fog,
            lights.first().map(|l| l.source),
        ) {
            return self.lambert(lights, ma, md, base, &n, dir);
        }

        // Diffuse and ambient sum I, in 1 / (255 · FULL) of the base colour
        // (so that the sum for a white material is 255 times the vertex
        // stage's old intensity), and specular sum J in 1 / FULL of a byte.
        let mut diffuse = [0u32; 3];
        for c in 0..3 {
            diffuse[c] = ma[c] as u32 * self.ambient[c] as u32 * 256;
        }
        let mut specular = [0u32; 3];
        // The unit vector towards the eye and its length: needed only for
        // specular highlights and fog, so found at most once, on first use.
        let mut view: Option<Option<Unit>> = None;
        let to_eye = || normalize(offset(self.eye, position));

        for light in lights.iter() {
            let (l, att) = match light.source {
                Source::Off => continue,
                Source::Directional { dir } => (dir, ONE),
                Source::Point {
                    pos,
                    reach,
                    inv_range,
                } => {
                    let d = offset(pos, position);
                    // Out of range in one coordinate: out of range. Most
                    // vertices of a scene with many small lights end here.
                    if d.iter().any(|c| c.unsigned_abs() >= reach) {
                        continue;
                    }
                    let Some(u) = normalize(d) else { continue };
                    let t = inv_range.apply(u.len, u.exp);
                    if t >= ONE as u64 {
                        continue;
                    }
                    (u.dir, attenuation(t as u32))
                }
            };
            let nl = n.dot(l);
            if nl <= 0 {
                continue;
            }
            let nl = if self.coarse {
                ((nl as u32 >> 8).min(256)) << 8
            } else {
                (nl as u32).min(ONE)
            };
            let g = frac_mul(nl, att);
            for c in 0..3 {
                // (Md · C) · g <= 65,025 · 65,536 < 2^32 - 128.
                let p = md[c] as u32 * light.color[c] as u32;
                diffuse[c] = diffuse[c].saturating_add((p * g + 128) >> 8);
            }
            if specular_on {
                let ps = [
                    ms[0] as u32 * light.color[0] as u32,
                    ms[1] as u32 * light.color[1] as u32,
                    ms[2] as u32 * light.color[2] as u32,
                ];
                if (ps[0] | ps[1] | ps[2]) == 0 {
                    continue;
                }
                let Some(v) = *view.get_or_insert_with(to_eye) else {
                    continue;
                };
                // |l + v| <= 2^17 + 2.
                let h = [
                    l[0] as i64 + v.dir[0] as i64,
                    l[1] as i64 + v.dir[1] as i64,
                    l[2] as i64 + v.dir[2] as i64,
                ];
                let Some(h) = normalize(h) else { continue };
                let nh = n.dot(h.dir).clamp(0, ONE as i32) as u32;
                let gs = frac_mul(pow(nh, material.shininess), att);
                for c in 0..3 {
                    specular[c] = specular[c].saturating_add((ps[c] * gs + 128) >> 8);
                }
            }
        }

        let f = match self.fog {
            FixedFog::None => 0,
            FixedFog::Linear { scale, offset } => {
                let q = view
                    .get_or_insert_with(to_eye)
                    .map_or(0, |u| scale.apply(u.len, u.exp));
                (q as i64 - offset).clamp(0, ONE as i64) as u32
            }
            FixedFog::Exponential { scale } => {
                let q = view
                    .get_or_insert_with(to_eye)
                    .map_or(0, |u| scale.apply(u.len, u.exp));
                ONE - exp2_neg(q)
            }
        };

        let mut out = [0u8; 3];
        for c in 0..3 {
            // Clamped where the byte saturates anyway, so exact: then
            // base · K + J <= 256 · K_MAX < 2^32 - 32,640.
            let k = div255(diffuse[c].min(255 * K_MAX));
            let x = base[c] as u32 * k + specular[c].min(K_MAX);
            out[c] = if f == 0 {
                // round(x / FULL), as the vertex stage rounds.
                div255((x + FULL / 2) >> 8).min(255) as u8
            } else {
                // The lit colour in 1/256 of a byte, mixed in Q16: a convex
                // combination, at most 65,280 · 2^16 < 2^32 - 2^23.
                let lit = div255(x).min(FULL);
                let fog = self.fog_color[c] as u32 * 256;
                ((lit * (ONE - f) + fog * f + (1 << 23)) >> 24) as u8
            };
        }
        out
    }

    /// For one directional light without fog (the lighting of a
    /// [`scene::Light`](crate::scene::Light)): its model-space unit
    /// direction (Q16), its colour and the ambient light, with which a
    /// white material without highlights is lit as
    /// `(base (256 ambient + colour · n·l) + 32,640) / 65,280`, `n·l` in
    /// 1/256 steps, floored, clamped to `0..=256` (the same bits as
    /// [`shade`](Self::shade), which the tests check): the vertex stage's
    /// fast path.
    fn single_directional(&self, lights: &[FixedLight]) -> Option<([i32; 3], [u8; 3], [u8; 3])> {
        match (self.coarse, self.fog, lights.first()) {
            (true, FixedFog::None, Some(l)) => match l.source {
                Source::Directional { dir } => Some((dir, l.color, self.ambient)),
                _ => None,
            },
            _ => None,
        }
    }

    /// [`shade`](Self::shade) for the commonest case, as fast as the
    /// vertex stage's old single-light code: one directional light (the
    /// coarse `n·l` of [`scene::Light`](crate::scene::Light)), no
    /// highlights, no fog. The same steps as the general loop with
    /// everything that cannot apply left out, so the same bits.
    #[inline(always)]
    fn lambert(
        &self,
        lights: &[FixedLight],
        ma: [u8; 3],
        md: [u8; 3],
        base: [u8; 3],
        n: &Normal,
        dir: [i32; 3],
    ) -> [u8; 3] {
        let nl = n.dot(dir);
        // frac_mul(nl, ONE) = min(nl, ONE) for the coarse n·l.
        let g = if nl > 0 {
            (((nl as u32 >> 8).min(256)) << 8).min(ONE)
        } else {
            0
        };
        let color = lights[0].color;
        let mut out = [0u8; 3];
        if (ma[0] & ma[1] & ma[2] & md[0] & md[1] & md[2]) == 255 {
            // A white material: then `k` below is exactly
            // `256 ambient + colour · n·l` (in 1/256 steps), and the two
            // divisions by 255 one division by 65,280, which the compiler
            // does by a multiply.
            let nl = g >> 8;
            for c in 0..3 {
                let k = self.ambient[c] as u32 * 256 + color[c] as u32 * nl;
                out[c] = ((base[c] as u32 * k + FULL / 2) / FULL).min(255) as u8;
            }
            return out;
        }
        for c in 0..3 {
            let mut diffuse = ma[c] as u32 * self.ambient[c] as u32 * 256;
            if g > 0 {
                let p = md[c] as u32 * color[c] as u32;
                diffuse = diffuse.saturating_add((p * g + 128) >> 8);
            }
            let k = div255(diffuse.min(255 * K_MAX));
            let x = base[c] as u32 * k;
            out[c] = div255((x + FULL / 2) >> 8).min(255) as u8;
        }
        out
    }
}

/// `target - p` for a model-space point `target` (raw 16.16 in `i64`, below
/// 2^60) and a vertex position.
#[inline(always)]
fn offset(target: [i64; 3], p: [i32; 3]) -> [i64; 3] {
    [
        target[0] - p[0] as i64,
        target[1] - p[1] as i64,
        target[2] - p[2] as i64,
    ]
}

/// A vertex normal, and whether it needs the wide dot product.
#[derive(Clone, Copy, Debug)]
struct Normal {
    n: [i32; 3],
    /// A component beyond ±2 (raw ±2^17): only broken meshes have one.
    wide: bool,
}

impl Normal {
    fn new(n: [i32; 3]) -> Self {
        Self {
            n,
            wide: n.iter().any(|c| c.unsigned_abs() > 1 << 17),
        }
    }

    /// `floor(n·u / 2^16)` for a Q16 `u` with components up to ±2^17: the
    /// dot product in Q16. Exact (clamped to ±2^30 on the wide path).
    #[inline]
    fn dot(&self, u: [i32; 3]) -> i32 {
        let n = &self.n;
        if self.wide {
            let d: i64 = (0..3).map(|i| n[i] as i64 * u[i] as i64).sum();
            return (d >> 16).clamp(-(1 << 30), 1 << 30) as i32;
        }
        // n·u = 256 Σ n_i (u_i >> 8) + Σ n_i (u_i & 255), so
        // floor(n·u / 2^16) = floor((a + floor(b / 256)) / 256), where
        // |a| <= 3 · 2^17 · 2^9 and |b| < 3 · 2^17 · 2^8 fit easily.
        let mut a = 0i32;
        let mut b = 0i32;
        for i in 0..3 {
            a += n[i] * (u[i] >> 8);
            b += n[i] * (u[i] & 255);
        }
        (a + (b >> 8)) >> 8
    }
}

/// A vector as a unit direction and a length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Unit {
    /// The direction, Q16.
    dir: [i32; 3],
    /// The length is `len · 2^exp`; `len` is in `[2^15, 2^16]`.
    len: u32,
    exp: i32,
}

/// The direction and length of `v` (components below 2^62 in magnitude), or
/// `None` for the zero vector.
///
/// The vector is shifted (rounding) so that its largest component has 15
/// bits, or, if its squared length would then be below 2^30, 16 bits: its
/// squared length `s` then lies in `[2^30, 2^32)`, the domain of [`rsqrt`].
#[inline]
fn normalize(v: [i64; 3]) -> Option<Unit> {
    let m = v[0]
        .unsigned_abs()
        .max(v[1].unsigned_abs())
        .max(v[2].unsigned_abs());
    if m == 0 {
        return None;
    }
    // Shift so that m >> exp lies in [2^14, 2^15) (rounding may give 2^15).
    let (mut exp, mut w) = if m < 1 << 30 {
        // The usual case, in 32 bits: 64-bit shifts are library calls on a
        // 32-bit core. exp <= 15, so the rounded sums stay below 2^31, and
        // a left shift (exp <= 0) brings m below 2^15.
        let exp = 17 - (m as u32).leading_zeros() as i32;
        let w = v.map(|c| {
            let c = c as i32;
            if exp <= 0 {
                c << -exp
            } else {
                (c + (1 << (exp - 1))) >> exp
            }
        });
        (exp, w)
    } else {
        let exp = 49 - m.leading_zeros() as i32;
        (exp, v.map(|c| ((c + (1 << (exp - 1))) >> exp) as i32))
    };
    // Each square at most 2^30: the sum below 2^32.
    let mut s: u32 = w.iter().map(|c| c.unsigned_abs() * c.unsigned_abs()).sum();
    if s < 1 << 30 {
        // Then every |w_i| < 2^15, and the doubled vector's s < 2^32.
        for c in &mut w {
            *c <<= 1;
        }
        s <<= 2;
        exp -= 1;
    }
    let r = rsqrt(s);
    let mut dir = [0i32; 3];
    for (d, &c) in dir.iter_mut().zip(&w) {
        // |w_i| · r <= sqrt(s) · r ≈ 2^31.
        let a = ((c.unsigned_abs() * r + (1 << 14)) >> 15) as i32;
        *d = if c < 0 { -a } else { a };
    }
    // sqrt(s) = s · r / 2^31, with s split into 16-bit halves so that each
    // product stays below 2^32 ((s >> 16) · r ≈ sqrt(s) · 2^15).
    let len = ((s >> 16) * r + (((s & 0xffff) * r) >> 16) + (1 << 14)) >> 15;
    Some(Unit { dir, len, exp })
}

/// `floor(sqrt(x))`, exact, by the digit-by-digit method (used at compile
/// time, for the [`rsqrt`] table).
const fn isqrt(x: u64) -> u64 {
    let mut rem = x;
    let mut root = 0u64;
    let mut bit = 1u64 << 62;
    while bit > x {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// `round(2^16 / sqrt(m))` for `m = 2^k (1 + i / 128)`, less 2^15 (so that
/// it fits 16 bits): `RSQRT[k][i]` for the two octaves `k` of `[1, 4)`.
/// Since `round(sqrt(q)) = (floor(sqrt(floor(4q))) + 1) / 2`, the entries
/// are exact roundings.
const RSQRT: [[u16; 129]; 2] = {
    let mut t = [[0u16; 129]; 2];
    let mut k = 0;
    while k < 2 {
        let mut i = 0;
        while i < 129 {
            // 4 · 2^32 / m = 2^(41 - k) / (128 + i).
            let q4 = (1u64 << (41 - k)) / (128 + i as u64);
            t[k][i] = (isqrt(q4).div_ceil(2) - (1 << 15)) as u16;
            i += 1;
        }
        k += 1;
    }
    t
};

/// `2^31 / sqrt(s)` for `s` in `[2^30, 2^32)`: a value in `(2^15, 2^16]`,
/// within 1.25 of the exact one (tested over the whole domain). The table's
/// rounding (½), the linear interpolation's own error (at most
/// (1/128)² / 8 · 3/4 · 2^16 ≈ 0.37, where `m^-½` bends most) and the
/// interpolation's rounding (½) add up to at most 1.37.
#[inline]
fn rsqrt(s: u32) -> u32 {
    debug_assert!(s >= 1 << 30);
    // s = 2^30 m, m in [1, 4): octave k, 128 steps of 2^k / 128 in it.
    let k = (s >> 31) as usize;
    // In 0..128 for s >= 2^30; the mask only spares a bounds check.
    let i = ((s >> (23 + k)) - 128) as usize & 127;
    let frac = (s >> (7 + k)) & 0xffff;
    let a = RSQRT[k][i] as u32 + (1 << 15);
    let b = RSQRT[k][i + 1] as u32 + (1 << 15);
    // a - b <= 2^16 (1 - 1 / sqrt(1 + 1/128)) < 2^8.
    a - (((a - b) * frac + (1 << 15)) >> 16)
}

/// `a · b` for Q16 fractions in `[0, 1]`, rounded.
#[inline]
fn frac_mul(a: u32, b: u32) -> u32 {
    if a >= ONE {
        b
    } else if b >= ONE {
        a
    } else {
        // (2^16 - 1)² + 2^15 < 2^32.
        (a * b + (1 << 15)) >> 16
    }
}

/// `x^e` for a Q16 `x` in `[0, 1]`, by binary exponentiation, each product
/// rounded; `x^0 = 1`.
#[inline]
fn pow(x: u32, e: u8) -> u32 {
    if e == 0 || x >= ONE {
        return ONE;
    }
    let (mut acc, mut b, mut e) = (ONE, x, e);
    loop {
        if e & 1 != 0 {
            acc = frac_mul(acc, b);
        }
        e >>= 1;
        if e == 0 {
            return acc;
        }
        b = frac_mul(b, b);
        if b == 0 {
            // A higher bit of e is set, so the result is 0 too.
            return 0;
        }
    }
}

/// The windowed falloff `(1 - t²)²` of `t = d / r` in `[0, 1)`, Q16.
#[inline]
fn attenuation(t: u32) -> u32 {
    let u = ONE - ((t * t + (1 << 15)) >> 16).min(ONE);
    frac_mul(u, u)
}

/// `2^(-i/32)` in Q16, `i` in `0..=32`, rounded; built at compile time from
/// the series of `exp(-i ln 2 / 32)` (alternating, 30 terms: far below the
/// rounding).
const EXP2: [u32; 33] = {
    let mut t = [0u32; 33];
    let mut i = 0;
    while i < 33 {
        let x = i as f64 * core::f64::consts::LN_2 / 32.0;
        let mut sum = 0.0;
        let mut term = 1.0;
        let mut k = 1;
        while k < 30 {
            sum += term;
            term = -term * x / k as f64;
            k += 1;
        }
        t[i] = (sum * 65536.0 + 0.5) as u32;
        i += 1;
    }
    t
};

/// `2^-q` for a Q16 `q`, in Q16: the integer part of `q` shifts, the
/// fraction interpolates [`EXP2`].
#[inline]
fn exp2_neg(q: u64) -> u32 {
    let ip = (q >> 16) as u32;
    if ip >= 17 {
        return 0;
    }
    let frac = (q & 0xffff) as u32;
    let i = (frac >> 11) as usize;
    let t = frac & 0x7ff;
    let (a, b) = (EXP2[i], EXP2[i + 1]);
    // a - b < 2^11, so the product stays below 2^22.
    let y = a - (((a - b) * t + (1 << 10)) >> 11);
    (y + ((1 << ip) >> 1)) >> ip
}

/// `floor(x / 255)` for any `u32`, exact, by shifts and adds (a Cortex-M0+
/// has no divider, and no multiply-high for a division by a constant).
#[inline]
fn div255(x: u32) -> u32 {
    // x/256 + x/2^16 + x/2^24, each floored: at most x/255 (the rest of
    // the series x/256 + x/2^16 + ...) and less than 3 + 2^32/(255 · 2^24)
    // below it, so the remainder r lies in [0, 1022) ...
    let q = (x >> 8) + (x >> 16) + (x >> 24);
    let r = x - q * 255;
    // ... where floor(r / 255) = (r + 1 + r / 256) / 256.
    q + ((r + 1 + (r >> 8)) >> 8)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// xorshift64, as the crate's other tests use.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        /// Uniform in [0, 1).
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.unit()
        }
        /// Log-uniform in [lo, hi).
        fn log(&mut self, lo: f64, hi: f64) -> f64 {
            (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
        }
        fn byte(&mut self) -> u8 {
            self.next() as u8
        }
        fn color(&mut self) -> Rgb888 {
            Rgb888::new(self.byte(), self.byte(), self.byte())
        }
        /// A uniformly distributed unit vector.
        fn dir(&mut self) -> [f64; 3] {
            loop {
                let v = [
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                ];
                let l = dot(v, v).sqrt();
                if l > 0.1 && l <= 1.0 {
                    return [v[0] / l, v[1] / l, v[2] / l];
                }
            }
        }
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    fn norm(a: [f64; 3]) -> Option<[f64; 3]> {
        let l = dot(a, a).sqrt();
        (l > 0.0).then(|| [a[0] / l, a[1] / l, a[2] / l])
    }

    fn vec3(v: [f64; 3]) -> Vec3 {
        Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
    }

    fn f64v(v: Vec3) -> [f64; 3] {
        [v.x as f64, v.y as f64, v.z as f64]
    }

    fn raw(v: [f64; 3]) -> [i32; 3] {
        v.map(|c| (c * 65536.0).round() as i32)
    }

    fn unraw(v: [i32; 3]) -> [f64; 3] {
        v.map(|c| c as f64 / 65536.0)
    }

    fn c01(c: Rgb888) -> [f64; 3] {
        rgb(c).map(|x| x as f64 / 255.0)
    }

    #[test]
    fn isqrt_is_exact() {
        for x in 0..1u64 << 20 {
            let r = isqrt(x);
            assert!(r * r <= x && (r + 1) * (r + 1) > x, "{x}");
        }
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for _ in 0..200_000 {
            let x = rng.next() >> (rng.next() % 64);
            let r = isqrt(x) as u128;
            assert!(r * r <= x as u128 && (r + 1) * (r + 1) > x as u128, "{x}");
        }
        for k in 1..=u32::MAX as u64 >> 16 {
            let k = k << 16 | 0xffff;
            assert_eq!(isqrt(k * k), k);
            assert_eq!(isqrt(k * k - 1), k - 1);
        }
        assert_eq!(isqrt(u64::MAX), u32::MAX as u64);
    }

    #[test]
    fn rsqrt_table_is_exactly_rounded() {
        for (k, row) in RSQRT.iter().enumerate() {
            for (i, &e) in row.iter().enumerate() {
                let m = (1 << k) as f64 * (1.0 + i as f64 / 128.0);
                let exact = 65536.0 / m.sqrt();
                let v = e as f64 + 32768.0;
                assert!((v - exact).abs() <= 0.5, "{k} {i}: {v} {exact}");
            }
        }
    }

    /// Over the whole domain `[2^30, 2^32)` at a fine stride, both
    /// octaves' ends, and at random.
    #[test]
    fn rsqrt_error_is_bounded() {
        let mut worst = 0.0f64;
        let mut worst_rel = 0.0f64;
        let mut check = |s: u32| {
            let r = rsqrt(s) as f64;
            let exact = 2f64.powi(31) / (s as f64).sqrt();
            worst = worst.max((r - exact).abs());
            worst_rel = worst_rel.max((r / exact - 1.0).abs());
        };
        let mut s = 1u64 << 30;
        while s < 1 << 32 {
            check(s as u32);
            s += 1021;
        }
        for s in [1u32 << 30, (1 << 31) - 1, 1 << 31, u32::MAX] {
            check(s);
        }
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..1_000_000 {
            check((rng.next() as u32) | 1 << 30);
        }
        std::println!("rsqrt: {worst} units, {worst_rel} relative");
        assert!(worst <= 1.25, "{worst}");
    }

    #[test]
    fn div255_is_exact() {
        // The final correction, over every remainder it can see.
        for r in 0..1100u32 {
            assert_eq!((r + 1 + (r >> 8)) >> 8, r / 255, "{r}");
        }
        for x in 0..1u32 << 24 {
            assert_eq!(div255(x), x / 255, "{x}");
        }
        let mut rng = Rng(0x1234_5678_9abc_def1);
        for _ in 0..1_000_000 {
            let x = rng.next() as u32;
            assert_eq!(div255(x), x / 255, "{x}");
        }
        for x in (u32::MAX - 70_000)..=u32::MAX {
            assert_eq!(div255(x), x / 255, "{x}");
        }
    }

    #[test]
    fn normalize_finds_direction_and_length() {
        let mut rng = Rng(0x0dd_ba11_cafe_f00d);
        let mut worst_dir = 0.0f64;
        let mut worst_len = 0.0f64;
        for _ in 0..200_000 {
            let mag = rng.log(1.0, 2f64.powi(61));
            let d = rng.dir();
            let v = d.map(|c| (c * mag).round() as i64);
            let Some(u) = normalize(v) else {
                assert_eq!(v, [0; 3]);
                continue;
            };
            let exact = v.map(|c| c as f64);
            let len = dot(exact, exact).sqrt();
            let e = norm(exact).unwrap();
            for (&d, e) in u.dir.iter().zip(e) {
                worst_dir = worst_dir.max((d as f64 / 65536.0 - e).abs());
            }
            let l = u.len as f64 * 2f64.powi(u.exp);
            worst_len = worst_len.max((l / len - 1.0).abs());
            assert!((1 << 15..=1 << 16).contains(&u.len), "{u:?}");
        }
        assert_eq!(normalize([0; 3]), None);
        // Small integer vectors are exact up to rounding of the direction.
        assert_eq!(
            normalize([0, 0, -1]),
            Some(Unit {
                dir: [0, 0, -65536],
                len: 1 << 15,
                exp: -15
            })
        );
        std::println!("direction {worst_dir}, length {worst_len}");
        assert!(worst_dir < 4.5e-5, "{worst_dir}");
        assert!(worst_len < 6.5e-5, "{worst_len}");
    }

    #[test]
    fn pow_matches_f64() {
        let mut worst = [0.0f64; 256];
        for e in 0..=255u8 {
            for k in 0..=2048u32 {
                let x = (k * 32).min(ONE);
                for x in [x, x.saturating_sub(7), x.saturating_sub(1)] {
                    let exact = (x as f64 / 65536.0).powi(e as i32);
                    let got = pow(x, e) as f64 / 65536.0;
                    let w = &mut worst[e as usize];
                    *w = w.max((got - exact).abs());
                }
            }
        }
        for (e, &w) in worst.iter().enumerate() {
            // Rounding errors of the products, amplified by the later
            // squarings: about e / 2^17.
            assert!(w <= (e as f64 + 2.0) / 131_072.0, "{e}: {w}");
        }
        assert_eq!(pow(0, 0), ONE);
        assert_eq!(pow(0, 1), 0);
        assert_eq!(pow(ONE, 255), ONE);
        assert_eq!(pow(ONE / 2, 1), ONE / 2);
        assert_eq!(pow(ONE / 2, 16), 1);
    }

    #[test]
    fn exp2_matches_f64() {
        for (i, &e) in EXP2.iter().enumerate() {
            let exact = 65536.0 * 2f64.powf(-(i as f64) / 32.0);
            assert!((e as f64 - exact).abs() <= 0.5, "{i}");
        }
        let mut worst = 0.0f64;
        for q in (0..20u64 << 16).step_by(7) {
            let exact = 2f64.powf(-(q as f64) / 65536.0);
            let got = exp2_neg(q) as f64 / 65536.0;
            worst = worst.max((got - exact).abs());
        }
        // The interpolation's error, (1/32)² / 8 · ln(2)², plus roundings.
        assert!(worst < 7.5e-5, "{worst}");
        assert_eq!(exp2_neg(0), ONE);
        assert_eq!(exp2_neg(1 << 40), 0);
    }

    #[test]
    fn attenuation_is_one_at_the_light_and_zero_at_the_range() {
        assert_eq!(attenuation(0), ONE);
        let mut last = ONE;
        for t in 0..ONE {
            let a = attenuation(t);
            assert!(a <= last, "{t}");
            let x = t as f64 / 65536.0;
            let exact = (1.0 - x * x).powi(2) * 65536.0;
            assert!((a as f64 - exact).abs() <= 1.5, "{t}");
            last = a;
        }
        assert_eq!(attenuation(ONE - 1), 0);

        // Through shade: a light of range 2 at distance 2 and beyond adds
        // nothing, one very close adds everything.
        let mat = Material::new();
        let n = [0, 0, 1 << 16];
        let shade_at = |z: f32, x: f32| {
            let lamp = [PointLight::new(
                Vec3::new(x, 0.0, z),
                Rgb888::new(200, 200, 200),
                2.0,
            )];
            let lighting = Lighting::new(Rgb888::new(20, 20, 20)).point(&lamp);
            let s: LightSetup<1> =
                LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
            s.shade(&mat, [255; 3], [0; 3], n)
        };
        assert_eq!(shade_at(2.0, 0.0), [20; 3]);
        assert_eq!(shade_at(1.6, 1.2), [20; 3]);
        assert_eq!(shade_at(2.5, 0.0), [20; 3]);
        assert_eq!(shade_at(1e30, 0.0), [20; 3]);
        assert_eq!(shade_at(1.0 / 65536.0, 0.0), [220; 3]);
        assert_eq!(shade_at(1.999, 0.0), [20; 3]);
        assert!(shade_at(1.9, 0.0)[0] > 20);
        // Exactly at the light: no direction, no light.
        assert_eq!(shade_at(0.0, 0.0), [20; 3]);
    }

    #[test]
    fn linear_fog_is_zero_at_the_eye_and_full_from_its_end() {
        let mat = Material::new();
        let fogged = |eye: f32| {
            let lighting = Lighting::new(Rgb888::new(100, 150, 200))
                .fog(Fog::Linear {
                    start: 1.0,
                    end: 5.0,
                })
                .fog_color(Rgb888::new(10, 20, 30));
            let s: LightSetup<0> =
                LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::new(0.0, 0.0, eye)).unwrap();
            s.shade(&mat, [255; 3], [0; 3], [0, 0, 1 << 16])
        };
        assert_eq!(fogged(0.0), [100, 150, 200]);
        assert_eq!(fogged(1.0), [100, 150, 200]);
        assert_eq!(fogged(3.0), [55, 85, 115]);
        assert_eq!(fogged(5.0), [10, 20, 30]);
        assert_eq!(fogged(5.001), [10, 20, 30]);
        assert_eq!(fogged(-7.0), [10, 20, 30]);
        assert_eq!(fogged(1e9), [10, 20, 30]);

        // The factor itself: 0 up to start, 1 from end on.
        let s: LightSetup<0> = LightSetup::new(
            &Lighting::new(Rgb888::BLACK).fog(Fog::Linear {
                start: 0.0,
                end: 3.0,
            }),
            &Mat4::IDENTITY,
            Vec3::default(),
        )
        .unwrap();
        let FixedFog::Linear { scale, offset } = s.core.fog else {
            panic!()
        };
        let f = |d: i64| {
            let q = normalize([d, 0, 0]).map_or(0, |u| scale.apply(u.len, u.exp));
            (q as i64 - offset).clamp(0, ONE as i64)
        };
        assert_eq!(f(0), 0);
        assert_eq!(f(3 << 16), ONE as i64);
        assert_eq!(f(4 << 16), ONE as i64);
        assert_eq!(f(3 << 15), ONE as i64 / 2);
    }

    /// The vertex stage's lighting before this module, copied.
    fn old_light_vertex(
        dir: [i32; 3],
        color: [u32; 3],
        ambient: [u32; 3],
        n: [i32; 3],
        base: [u8; 3],
    ) -> [u8; 3] {
        let d =
            n[0] as i64 * dir[0] as i64 + n[1] as i64 * dir[1] as i64 + n[2] as i64 * dir[2] as i64;
        let ndotl = (d >> 24).clamp(0, 256) as u32;
        let mut out = [0u8; 3];
        for c in 0..3 {
            let intensity = ambient[c] * 256 + color[c] * ndotl;
            let v = (base[c] as u32 * intensity + 32_640) / 65_280;
            out[c] = v.min(255) as u8;
        }
        out
    }

    /// The old vertex stage's set-up of `scene::Light`, copied.
    fn old_dir(model: &Mat4, direction: Vec3) -> [i32; 3] {
        let local = model
            .inverse_transform_vector(direction)
            .and_then(|v| v.normalize())
            .unwrap();
        let fx = |v: f32| (v * 65536.0) as i32;
        [fx(local.x), fx(local.y), fx(local.z)]
    }

    #[test]
    fn reproduces_scene_light_bit_for_bit() {
        let mut rng = Rng(0x5eed_1234_abcd_0001);
        let mat = Material::new();
        let mut n_lit = 0;
        for case in 0..4_000 {
            let model = Mat4::rotation_y(rng.range(-3.0, 3.0) as f32)
                * Mat4::rotation_x(rng.range(-3.0, 3.0) as f32)
                * Mat4::scale(Vec3::new(
                    rng.log(0.1, 10.0) as f32,
                    rng.log(0.1, 10.0) as f32,
                    rng.log(0.1, 10.0) as f32,
                ));
            let model = Mat4::translation(vec3([0.0; 3].map(|_| rng.range(-9.0, 9.0)))) * model;
            let direction = vec3(rng.dir().map(|c| c * rng.log(0.01, 100.0)));
            let light = crate::scene::Light::new(direction)
                .color(rng.color())
                .ambient(rng.color());
            let dl = [DirectionalLight::new(light.direction, light.color)];
            let lighting = Lighting::new(light.ambient).directional(&dl);
            let eye = vec3([0.0; 3].map(|_| rng.range(-50.0, 50.0)));
            let setup: LightSetup<3> = LightSetup::new(&lighting, &model, eye).unwrap();
            let dir = old_dir(&model, light.direction);
            let (color, ambient) = (
                rgb(light.color).map(u32::from),
                rgb(light.ambient).map(u32::from),
            );
            for k in 0..250 {
                // Unit normals as meshes hold them, and every few
                // vertices arbitrary bits.
                let normal = if k % 5 == 4 {
                    let mut b = || (rng.next() as i32) >> (rng.next() % 32);
                    [b(), b(), b()]
                } else {
                    raw(rng.dir())
                };
                let base = [rng.byte(), rng.byte(), rng.byte()];
                let p = [rng.next() as i32, rng.next() as i32, rng.next() as i32];
                let expected = old_light_vertex(dir, color, ambient, normal, base);
                let got = setup.shade(&mat, base, p, normal);
                assert_eq!(got, expected, "case {case}: n {normal:?} base {base:?}");
                n_lit += (expected != old_light_vertex(dir, color, ambient, [0; 3], base)) as u32;
            }
        }
        assert!(n_lit > 300_000, "{n_lit}");
    }

    /// The model in `f64`, in world space.
    struct Reference<'a> {
        lighting: &'a Lighting<'a>,
        eye: [f64; 3],
    }

    impl Reference<'_> {
        /// The exact colour, and whether a highlight is cut off right at
        /// this vertex (`n·l` about 0, where the model is discontinuous).
        fn shade(
            &self,
            mat: &Material,
            base: [u8; 3],
            p: [f64; 3],
            n: [f64; 3],
        ) -> ([f64; 3], bool) {
            let mut cut = false;
            let base = base.map(|b| b as f64 / 255.0);
            let (ma, md, ms) = (c01(mat.ambient), c01(mat.diffuse), c01(mat.specular));
            let amb = c01(self.lighting.ambient);
            let mut lit = [0.0; 3];
            for c in 0..3 {
                lit[c] = base[c] * ma[c] * amb[c];
            }
            let to_eye = sub(self.eye, p);
            let v = norm(to_eye);
            let mut add = |l: [f64; 3], att: f64, color: [f64; 3]| {
                let nl = dot(n, l);
                cut |= mat.specular != Rgb888::BLACK && nl.abs() < 1e-3;
                if nl <= 0.0 {
                    return;
                }
                let nl = nl.min(1.0);
                let spec = match v.and_then(|v| norm([l[0] + v[0], l[1] + v[1], l[2] + v[2]])) {
                    Some(h) => dot(n, h).clamp(0.0, 1.0).powi(mat.shininess as i32),
                    None => 0.0,
                };
                for c in 0..3 {
                    lit[c] += att * color[c] * (base[c] * md[c] * nl + ms[c] * spec);
                }
            };
            for l in self.lighting.directional {
                add(norm(f64v(l.direction)).unwrap(), 1.0, c01(l.color));
            }
            for l in self.lighting.point {
                let d = sub(f64v(l.position), p);
                let dist = dot(d, d).sqrt();
                let r = l.range as f64;
                if dist >= r || dist == 0.0 {
                    continue;
                }
                let x = dist / r;
                add(norm(d).unwrap(), (1.0 - x * x).powi(2), c01(l.color));
            }
            let dist = dot(to_eye, to_eye).sqrt();
            let f = match self.lighting.fog {
                Fog::None => 0.0,
                Fog::Linear { start, end } => {
                    ((dist - start as f64) / (end as f64 - start as f64)).clamp(0.0, 1.0)
                }
                Fog::Exponential { density } => 1.0 - (-(density as f64) * dist).exp(),
            };
            let fog = c01(self.lighting.fog_color);
            let mut out = [0.0; 3];
            for c in 0..3 {
                out[c] = 255.0 * (lit[c].min(1.0) * (1.0 - f) + fog[c] * f);
            }
            (out, cut)
        }
    }

    /// A random scene around a vertex: lights and the eye at random
    /// distances, random materials, fog of a scale that matters.
    struct Case {
        directional: Vec<DirectionalLight>,
        point: Vec<PointLight>,
        ambient: Rgb888,
        fog: Fog,
        fog_color: Rgb888,
        eye: [f64; 3],
        material: Material,
        base: [u8; 3],
    }

    impl Case {
        /// `near`: the shortest range and eye distance, in units of
        /// `world_scale` (point lights are at least a tenth of their range
        /// away when `near >= 1`).
        fn random(rng: &mut Rng, p: [f64; 3], world_scale: f64, near: f64, shininess: u8) -> Self {
            let mut directional = Vec::new();
            for _ in 0..rng.next() % 3 {
                let d = rng.dir().map(|c| c * rng.log(0.01, 100.0));
                directional.push(DirectionalLight::new(vec3(d), rng.color()));
            }
            let mut point = Vec::new();
            for _ in 0..rng.next() % 3 {
                let range = rng.log(near, 500.0) * world_scale;
                let closest = if near >= 1.0 { 0.1 } else { 0.0 };
                let d = rng.dir().map(|c| c * range * rng.range(closest, 1.1));
                let pos = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
                point.push(PointLight::new(vec3(pos), rng.color(), range as f32));
            }
            let e = rng
                .dir()
                .map(|c| c * rng.log(near * 10.0, 5000.0) * world_scale);
            let eye = f64v(vec3([p[0] + e[0], p[1] + e[1], p[2] + e[2]]));
            let dist = dot(sub(eye, p), sub(eye, p)).sqrt();
            let fog = match rng.next() % 3 {
                0 => Fog::None,
                1 => {
                    let start = dist * rng.range(-0.5, 1.2);
                    Fog::Linear {
                        start: start as f32,
                        end: (start + dist * rng.range(0.05, 2.0)) as f32,
                    }
                }
                _ => Fog::Exponential {
                    density: (rng.range(0.0, 3.0) / dist) as f32,
                },
            };
            Self {
                directional,
                point,
                ambient: rng.color(),
                fog,
                fog_color: rng.color(),
                eye,
                material: Material {
                    ambient: rng.color(),
                    diffuse: rng.color(),
                    specular: if rng.next().is_multiple_of(4) {
                        Rgb888::BLACK
                    } else {
                        rng.color()
                    },
                    shininess,
                },
                base: [rng.byte(), rng.byte(), rng.byte()],
            }
        }

        fn lighting(&self) -> Lighting<'_> {
            Lighting {
                ambient: self.ambient,
                directional: &self.directional,
                point: &self.point,
                fog: self.fog,
                fog_color: self.fog_color,
            }
        }

        /// A unit normal, world space: uniformly random, or (half the time)
        /// near the half vector of one of the lights, to probe highlights.
        fn normal(&self, rng: &mut Rng, p: [f64; 3]) -> [f64; 3] {
            let lights: Vec<[f64; 3]> = self
                .directional
                .iter()
                .map(|l| f64v(l.direction))
                .chain(self.point.iter().map(|l| sub(f64v(l.position), p)))
                .collect();
            if lights.is_empty() || rng.next().is_multiple_of(2) {
                return rng.dir();
            }
            let l = norm(lights[(rng.next() % lights.len() as u64) as usize]);
            let v = norm(sub(self.eye, p));
            let (Some(l), Some(v)) = (l, v) else {
                return rng.dir();
            };
            let Some(h) = norm([l[0] + v[0], l[1] + v[1], l[2] + v[2]]) else {
                return rng.dir();
            };
            let sigma = rng.log(1e-4, 0.5);
            let d = rng.dir();
            norm([
                h[0] + sigma * d[0],
                h[1] + sigma * d[1],
                h[2] + sigma * d[2],
            ])
            .unwrap_or(h)
        }

        /// Whether a half vector is ill-conditioned (`|l + v|` small), where
        /// no implementation's highlight is accurate.
        fn ill_conditioned(&self, p: [f64; 3]) -> bool {
            let Some(v) = norm(sub(self.eye, p)) else {
                return true;
            };
            let lights = self
                .directional
                .iter()
                .map(|l| f64v(l.direction))
                .chain(self.point.iter().map(|l| sub(f64v(l.position), p)));
            lights.into_iter().any(|l| {
                let l = norm(l).unwrap_or([0.0; 3]);
                let h = [l[0] + v[0], l[1] + v[1], l[2] + v[2]];
                dot(h, h) < 0.01
            })
        }
    }

    /// The largest error per shininess band against the `f64` model, with
    /// the identity model matrix, so that set-up in `f32` is exact and only
    /// the fixed-point evaluation is measured. Positions over the whole
    /// 16.16 range (mostly within ±1000), lights from 0.05 to 500 units
    /// of range, normals half random, half near a highlight. The bounds
    /// asserted, ±1.5 up to shininess 160 and ±2.5 above, are a little above
    /// the worst errors found over 600,000 cases (this runs 30,000): 1.23,
    /// 1.36 and 2.03 for shininess up to 64, up to 160 and above.
    #[test]
    fn matches_the_f64_model() {
        let mut rng = Rng(0xfeed_beef_0bad_cafe);
        let bands: [(u8, u8, f64); 3] = [(0, 64, 1.5), (65, 160, 1.5), (161, 255, 2.5)];
        let mut worst = [0.0f64; 3];
        let mut worst_case: [std::string::String; 3] = Default::default();
        let mut hist = [0u32; 8];
        for case in 0..30_000 {
            let band = case % 3;
            let (lo, hi, _) = bands[band];
            let shininess = lo + (rng.next() % (hi - lo + 1) as u64) as u8;
            let extent = if rng.next().is_multiple_of(8) {
                30_000.0
            } else {
                1000.0
            };
            let p = raw([0.0; 3].map(|_| rng.range(-extent, extent)));
            let pf = unraw(p);
            let c = Case::random(&mut rng, pf, 1.0, 0.05, shininess);
            if c.material.specular != Rgb888::BLACK && c.ill_conditioned(pf) {
                continue;
            }
            let lighting = c.lighting();
            let setup: LightSetup<4> =
                LightSetup::new(&lighting, &Mat4::IDENTITY, vec3(c.eye)).unwrap();
            let reference = Reference {
                lighting: &lighting,
                eye: c.eye,
            };
            for _ in 0..8 {
                let n = raw(c.normal(&mut rng, pf));
                let got = setup.shade(&c.material, c.base, p, n);
                let (exact, cut) = reference.shade(&c.material, c.base, pf, unraw(n));
                if cut {
                    continue;
                }
                for ch in 0..3 {
                    let e = (got[ch] as f64 - exact[ch]).abs();
                    hist[(e as usize).min(7)] += 1;
                    if e > worst[band] {
                        worst[band] = e;
                        worst_case[band] = std::format!(
                            "case {case}: got {got:?}, exact {exact:?}, p {pf:?}, n {n:?}, base {:?}, ambient {:?}, fog colour {:?}, {:?} {:?} {:?} {:?} {:?}",
                            c.base,
                            c.ambient,
                            c.fog_color,
                            c.material,
                            c.directional,
                            c.point,
                            c.fog,
                            c.eye
                        );
                    }
                    assert!(e <= bands[band].2, "{}", worst_case[band]);
                }
            }
        }
        std::println!("worst {worst:?}, histogram of |error| {hist:?}");
        for w in &worst_case {
            std::println!("{w}");
        }
    }

    /// Rigid transforms with uniform scale (and reflections): the model in
    /// world space against set-up into model space. Set-up's `f32` adds its
    /// relative error of about 2^-24 to light and eye positions, so lights
    /// and the eye keep some distance (ranges from 1 unit, lights beyond a
    /// tenth of their range, the eye beyond 10 units) and shininess stays
    /// up to 32. The worst error found over 200,000 cases was 1.36.
    /// A fraction of white is the grey of that many 255ths, rounded, and
    /// lights the same as that colour.
    #[test]
    fn fractions_are_grey_intensities() {
        for (f, level) in [
            (0.8f32, 204u8),
            (0.0, 0),
            (1.0, 255),
            (0.5, 128),
            (0.001, 0),
            (0.003, 1),
            (-2.0, 0),
            (7.0, 255),
            (f32::NAN, 0),
            (f32::INFINITY, 255),
        ] {
            let grey = Rgb888::new(level, level, level);
            assert_eq!(Intensity::from(f).0, grey, "{f}");
            assert_eq!(Intensity::from(f as f64).0, grey, "{f}");
        }
        let dir = Vec3::new(0.3, 1.0, 0.2);
        let (a, b) = (
            [DirectionalLight::new(dir, 0.8)],
            [DirectionalLight::new(dir, Rgb888::new(204, 204, 204))],
        );
        assert_eq!(a, b);
        let (la, lb) = (
            Lighting::new(0.2).directional(&a),
            Lighting::new(Rgb888::new(51, 51, 51)).directional(&b),
        );
        assert_eq!(la, lb);
        let lamp = PointLight::new(Vec3::new(0.0, 0.0, 2.0), 0.5, 4.0);
        assert_eq!(lamp.color, Rgb888::new(128, 128, 128));
    }

    #[test]
    fn model_space_matches_world_space() {
        let mut rng = Rng(0xabad_1dea_f00d_0042);
        let mut worst = 0.0f64;
        for case in 0..6_000 {
            let s = rng.log(0.1, 10.0);
            // A rotation from a random unit quaternion, orthogonal to f64
            // precision (the f32 rotation matrices are only to f32's).
            let q = loop {
                let q = [0.0; 4].map(|_| rng.range(-1.0, 1.0));
                let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                if l > 0.1 && l <= 1.0 {
                    break q.map(|x| x / l);
                }
            };
            let [w, x, y, z] = q;
            let rot = [
                [
                    1.0 - 2.0 * (y * y + z * z),
                    2.0 * (x * y + w * z),
                    2.0 * (x * z - w * y),
                ],
                [
                    2.0 * (x * y - w * z),
                    1.0 - 2.0 * (x * x + z * z),
                    2.0 * (y * z + w * x),
                ],
                [
                    2.0 * (x * z + w * y),
                    2.0 * (y * z - w * x),
                    1.0 - 2.0 * (x * x + y * y),
                ],
            ];
            let flip = if case % 2 == 1 { -1.0 } else { 1.0 };
            let col = |c: usize| {
                let k = s * if c == 1 { flip } else { 1.0 };
                [
                    (rot[c][0] * k) as f32,
                    (rot[c][1] * k) as f32,
                    (rot[c][2] * k) as f32,
                    0.0,
                ]
            };
            let model = Mat4 {
                m: [col(0), col(1), col(2), [0.0, 0.0, 0.0, 1.0]],
            };
            let model = Mat4::translation(vec3([0.0; 3].map(|_| rng.range(-100.0, 100.0)))) * model;
            let mf = model.m.map(|c| c.map(|x| x as f64));
            let p = raw([0.0; 3].map(|_| rng.range(-300.0, 300.0)));
            let pm = unraw(p);
            let pw: [f64; 3] = core::array::from_fn(|r| {
                mf[0][r] * pm[0] + mf[1][r] * pm[1] + mf[2][r] * pm[2] + mf[3][r]
            });
            let scale = (0..3)
                .map(|c| {
                    dot(
                        [mf[c][0], mf[c][1], mf[c][2]],
                        [mf[c][0], mf[c][1], mf[c][2]],
                    )
                })
                .sum::<f64>()
                / 3.0;
            let scale = scale.sqrt();
            let shininess = (rng.next() % 33) as u8;
            let c = Case::random(&mut rng, pw, s.max(1.0), 1.0, shininess);
            if c.material.specular != Rgb888::BLACK && c.ill_conditioned(pw) {
                continue;
            }
            let lighting = c.lighting();
            let setup: LightSetup<4> = LightSetup::new(&lighting, &model, vec3(c.eye)).unwrap();
            let reference = Reference {
                lighting: &lighting,
                eye: c.eye,
            };
            for _ in 0..8 {
                // The model-space normal Qᵀ n = Mᵀ n / s.
                let nw = c.normal(&mut rng, pw);
                let n = raw(core::array::from_fn(|k| {
                    (mf[k][0] * nw[0] + mf[k][1] * nw[1] + mf[k][2] * nw[2]) / scale
                }));
                let nm = unraw(n);
                // For a similarity M = s Q, model-space n·l is (Q n)·l, and
                // Q n = M n / s.
                let nw: [f64; 3] = core::array::from_fn(|r| {
                    (mf[0][r] * nm[0] + mf[1][r] * nm[1] + mf[2][r] * nm[2]) / scale
                });
                let got = setup.shade(&c.material, c.base, p, n);
                let (exact, cut) = reference.shade(&c.material, c.base, pw, nw);
                if cut {
                    continue;
                }
                for ch in 0..3 {
                    let e = (got[ch] as f64 - exact[ch]).abs();
                    worst = worst.max(e);
                    assert!(
                        e <= 1.5,
                        "case {case}: got {got:?}, exact {exact:?}, {:?} {:?} {:?} {:?}",
                        c.material,
                        c.directional,
                        c.point,
                        c.fog
                    );
                }
            }
        }
        std::println!("worst {worst}");
    }

    #[test]
    fn bad_input_is_an_error() {
        let white = Rgb888::WHITE;
        let id = Mat4::IDENTITY;
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let setup = |l: &Lighting<'_>| LightSetup::<2>::new(l, &id, eye).map(|_| ());
        let dir = |d: Vec3| [DirectionalLight::new(d, white)];
        for (i, d) in [
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(0.0, f32::INFINITY, 0.0),
            Vec3::default(),
        ]
        .into_iter()
        .enumerate()
        {
            let ok = DirectionalLight::new(Vec3::new(0.0, 1.0, 0.0), white);
            let lights = [ok, dir(d)[0]];
            assert_eq!(
                setup(&Lighting::new(white).directional(&lights)),
                Err(LightError::BadDirection { light: 1 }),
                "{i}"
            );
        }
        let point = |p: Vec3, r: f32| [PointLight::new(p, white, r)];
        for p in [
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
        ] {
            assert_eq!(
                setup(&Lighting::new(white).point(&point(p, 1.0))),
                Err(LightError::BadPosition { light: 0 })
            );
        }
        for r in [0.0, -1.0, f32::NAN, f32::INFINITY, -0.0] {
            assert_eq!(
                setup(&Lighting::new(white).point(&point(Vec3::default(), r))),
                Err(LightError::BadRange { light: 0 }),
                "{r}"
            );
        }
        for fog in [
            Fog::Linear {
                start: 2.0,
                end: 2.0,
            },
            Fog::Linear {
                start: 3.0,
                end: 2.0,
            },
            Fog::Linear {
                start: f32::NAN,
                end: 2.0,
            },
            Fog::Linear {
                start: 0.0,
                end: f32::INFINITY,
            },
            Fog::Linear {
                start: -3e38,
                end: 3e38,
            },
            Fog::Exponential { density: -1.0 },
            Fog::Exponential { density: f32::NAN },
            Fog::Exponential {
                density: f32::INFINITY,
            },
        ] {
            assert_eq!(
                setup(&Lighting::new(white).fog(fog)),
                Err(LightError::BadFog),
                "{fog:?}"
            );
        }
        let three = dir(Vec3::new(1.0, 0.0, 0.0)).repeat(3);
        assert_eq!(
            setup(&Lighting::new(white).directional(&three)),
            Err(LightError::TooManyLights { count: 3, max: 2 })
        );
        let one_point = point(Vec3::default(), 1.0);
        let one_each = Lighting::new(white)
            .directional(&three[..1])
            .point(&one_point);
        assert_eq!(setup(&one_each), Ok(()));
        let two_points = [point(Vec3::default(), 1.0)[0]; 2];
        assert_eq!(
            setup(&one_each.point(&two_points)),
            Err(LightError::TooManyLights { count: 3, max: 2 })
        );
        for m in [
            Mat4::scale(Vec3::new(1.0, 0.0, 1.0)),
            Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0)),
        ] {
            assert_eq!(
                LightSetup::<1>::new(&Lighting::new(white), &m, eye).map(|_| ()),
                Err(LightError::BadMatrix)
            );
        }
        assert_eq!(
            LightSetup::<1>::new(&Lighting::new(white), &id, Vec3::new(f32::NAN, 0.0, 0.0))
                .map(|_| ()),
            Err(LightError::BadMatrix)
        );
        // Every error has a message.
        let e = LightError::TooManyLights { count: 3, max: 2 };
        assert_eq!(std::format!("{e}"), "3 lights exceed the capacity of 2");
    }

    /// Zero, huge and random normals, extreme positions, and lights and
    /// eyes far out: a defined colour, never a panic (the tests run with
    /// overflow checks).
    #[test]
    fn any_normal_and_position_gives_a_colour() {
        let mut rng = Rng(0x7777_1234_5678_9999);
        let dl = [
            DirectionalLight::new(Vec3::new(1.0, 2.0, 3.0), Rgb888::WHITE),
            DirectionalLight::new(Vec3::new(-1.0, 0.0, 0.0), Rgb888::new(9, 99, 199)),
        ];
        let pl = [
            PointLight::new(Vec3::new(30000.0, -30000.0, 0.0), Rgb888::WHITE, 1e5),
            PointLight::new(Vec3::new(1.0, 0.0, 0.0), Rgb888::new(255, 0, 0), 1e-4),
        ];
        let mat = Material::new()
            .specular(Rgb888::WHITE)
            .shininess(255)
            .diffuse(Rgb888::new(1, 128, 255));
        let mut seen = [0u32; 3];
        for fog in [
            Fog::None,
            Fog::Linear {
                start: 1.0,
                end: 1.000_001,
            },
            Fog::Exponential { density: 1e30 },
        ] {
            for model in [
                Mat4::IDENTITY,
                Mat4::scale(Vec3::new(1e-6, 1e-6, 1e-6)),
                Mat4::scale(Vec3::new(3e4, 3e4, 3e4)),
            ] {
                let lighting = Lighting::new(Rgb888::new(10, 20, 30))
                    .directional(&dl)
                    .point(&pl)
                    .fog(fog)
                    .fog_color(Rgb888::new(1, 2, 3));
                let s: LightSetup<4> =
                    LightSetup::new(&lighting, &model, Vec3::new(-1e3, 2e3, 1e4)).unwrap();
                let edge = [
                    0,
                    1,
                    -1,
                    i32::MAX,
                    i32::MIN,
                    1 << 17,
                    (1 << 17) + 1,
                    -(1 << 17) - 1,
                ];
                for &a in &edge {
                    for &b in &edge {
                        for &c in &edge {
                            let out = s.shade(&mat, [255, 128, 0], [a, b, c], [c, a, b]);
                            seen[0] += out[0] as u32;
                        }
                    }
                }
                for _ in 0..20_000 {
                    let mut r = || (rng.next() as i32) >> (rng.next() % 32);
                    let out = s.shade(&mat, [255; 3], [r(), r(), r()], [r(), r(), r()]);
                    seen[1] += out[1] as u32;
                }
                // A zero normal: ambient only (and fog).
                let z = s.shade(&mat, [255; 3], [0; 3], [0; 3]);
                seen[2] += z[2] as u32;
            }
        }
        assert!(seen.iter().all(|&s| s > 0), "{seen:?}");

        // Zero normal, no fog: exactly the ambient term.
        let lighting = Lighting::new(Rgb888::new(10, 20, 30))
            .directional(&dl)
            .point(&pl);
        let s: LightSetup<4> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
        assert_eq!(s.shade(&mat, [255; 3], [0; 3], [0; 3]), [10, 20, 30]);
        // A huge normal: saturated diffuse light from the lights in front.
        assert_eq!(
            s.shade(
                &Material::new(),
                [255; 3],
                [0; 3],
                [i32::MAX, i32::MAX, i32::MAX]
            ),
            [255, 255, 255]
        );
    }

    #[test]
    fn far_and_unreachable_lights_are_off() {
        let pl = [
            PointLight::new(Vec3::new(1e20, 0.0, 0.0), Rgb888::WHITE, 10.0),
            PointLight::new(Vec3::new(0.0, 0.0, 1.0), Rgb888::WHITE, 1e-9),
        ];
        let s: LightSetup<2> = LightSetup::new(
            &Lighting::new(Rgb888::BLACK).point(&pl),
            &Mat4::IDENTITY,
            Vec3::default(),
        )
        .unwrap();
        assert!(s.lights.iter().all(|l| l.source == Source::Off));
        assert_eq!(
            LightSetup::<2>::new(
                &Lighting::new(Rgb888::BLACK).point(&[PointLight::new(
                    Vec3::default(),
                    Rgb888::WHITE,
                    1e30
                )]),
                &Mat4::IDENTITY,
                Vec3::default()
            )
            .map(|_| ()),
            Err(LightError::BadRange { light: 0 })
        );
    }

    #[test]
    fn raw_positions_are_rounded() {
        for x in [189.1292f32, -189.1292, 0.3, -0.3, 32767.99, 1e6, -3.5e12] {
            let exact = (x as f64 * 65536.0).round() as i64;
            assert_eq!(to_raw(Vec3::new(x, 0.0, 0.0)), Some([exact, 0, 0]), "{x}");
        }
        // Half a raw unit rounds away from zero.
        let half = 0.5 / 65536.0;
        assert_eq!(to_raw(Vec3::new(half, -half, 0.0)), Some([1, -1, 0]));
        assert_eq!(to_raw(Vec3::new(f32::NAN, 0.0, 0.0)), None);
        assert_eq!(to_raw(Vec3::new(0.0, 2e13, 0.0)), None);
    }

    #[test]
    fn scale_applies_like_f64() {
        let mut rng = Rng(0x3141_5926_5358_9793);
        for _ in 0..100_000 {
            let x = rng.log(1e-30, 1e30) as f32;
            let s = Scale::from_f32(x).unwrap();
            let len = (1 << 15) + (rng.next() % (1 << 15)) as u32;
            let exp = (rng.next() % 120) as i32 - 60;
            let exact = len as f64 * 2f64.powi(exp) * x as f64;
            let got = s.apply(len, exp) as f64;
            if exact < SCALE_CAP as f64 / 2.0 {
                // The mantissa's rounding to 16 bits: 2^-16 relative.
                let bound = 0.5 + exact / 65536.0;
                assert!(
                    (got - exact).abs() <= bound,
                    "{x} {len} {exp}: {got} {exact}"
                );
            } else {
                assert!(got >= SCALE_CAP as f64 / 2.0 - 1.0);
            }
        }
        assert_eq!(Scale::from_f32(0.0), Some(Scale { m: 0, s: 0 }));
        assert_eq!(Scale::from_f32(-1.0), None);
        assert_eq!(Scale::from_f32(f32::NAN), None);
        assert_eq!(Scale::from_f32(1.0).unwrap().apply(1 << 15, -15), 1);
    }
}
