//! The values at one pixel of a span that a span shader's per-pixel
//! function reads: position, depth, the interpolated varyings and colour.

/// The values at one pixel of a span, as [`SpanInput::shade`](super::SpanInput::shade)'s
/// per-pixel function gets them.
#[derive(Clone, Copy, Debug)]
pub struct Interpolated<V> {
    /// Screen column of the pixel.
    pub x: i32,
    /// Its depth, 0 (near) to 65535 (far).
    pub depth: u16,
    /// The varyings, interpolated.
    pub varyings: V,
    /// The lit vertex colour, interpolated (perspective-correct; in an
    /// opaque draw in [`Perspective::Affine`](super::Perspective::Affine)
    /// as the Gouraud shading interpolates it): each channel in 8.16 fixed
    /// point, rounding bias included, not yet clamped (see
    /// [`Interpolated::rgb`]). Zeros unless the span was shaded with colour
    /// interpolation on (in an opaque affine span, also unless the
    /// shader's [`INTERPOLATE_COLOR`](super::FragmentShader::INTERPOLATE_COLOR)
    /// is true: only then are the colour planes set up).
    pub color: [i32; 3],
    /// Where the span loop has them (the opaque loops): each varying's
    /// fraction to 32
    /// bits, as an `I16F16`'s raw bits. Its bits 16 to 31 are the low 16
    /// bits of the varying's raw value (`frac(v) · 2^16`), its bits 0 to 15
    /// the part that the 16.16 value rounds away (plus one half). All that
    /// a repeated power-of-two texture reads, from wrapping 32-bit
    /// products (see `PerspectiveSetup::values_fit`).
    pub(crate) fine: Option<V>,
    /// Whether [`color`](Self::color) is known to lie within `0..256` after
    /// its shift (weights that sum to at most one, see
    /// `span_shift_convex`): [`rgb`](Self::rgb) then takes no clamp. A
    /// constant in each span loop, so the test is decided at compile time.
    pub(crate) convex: bool,
}

impl<V> Interpolated<V> {
    /// [`Interpolated::color`] as bytes: rounded and clamped.
    #[inline(always)]
    pub fn rgb(&self) -> [u8; 3] {
        if self.convex {
            // In range already: the clamps' six instructions a channel
            // left out on x86-64.
            self.color.map(|c| (c >> 16) as u8)
        } else {
            self.color.map(byte)
        }
    }
}

/// A colour channel in 8.16 (rounding bias included) clamped to a byte.
#[inline(always)]
pub(crate) fn byte(c: i32) -> u8 {
    (c >> 16).clamp(0, 255) as u8
}
