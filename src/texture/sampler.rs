//! Sampling decided once per span: the texture's format, filter and wrap
//! modes are matched before a span's loop rather than at every pixel, and
//! the common case (an `Rgb565` texture of power-of-two sides repeated on
//! both axes) gets a loop of its own, addressed with shifts and masks and
//! its texels read in place; every other texture goes through
//! [`Texture::sample`]. Both give the same colour at every coordinate.

use super::bilinear::blend_channel;
use super::{rgb565_to_rgb888, Filter, Texels, Texture, Wrap, HALF, WEIGHT_BITS};
use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{
    Bgr555, Bgr565, Bgr888, BinaryColor, Gray2, Gray4, Gray8, Rgb555, Rgb565, Rgb888,
};

/// A colour that a texel can be written as: an `Rgb565` texel's bits
/// converted directly, with no round trip through `Rgb888` where the
/// colour is `Rgb565` itself.
///
/// The default converts through `Rgb888`, as [`Texture::sample`] reads it;
/// a colour type of your own takes it with an empty `impl`:
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microraster::texture::FromTexel;
/// #[derive(Clone, Copy)]
/// struct Mine(Rgb888);
/// impl From<Rgb888> for Mine {
///     fn from(c: Rgb888) -> Self {
///         Mine(c)
///     }
/// }
/// impl FromTexel for Mine {}
/// ```
pub trait FromTexel: From<Rgb888> {
    /// The colour of an `Rgb565` texel with bits `raw` (red in the top
    /// five): must equal `Self::from` of its `Rgb888` expansion.
    #[inline(always)]
    fn from_rgb565(raw: u16) -> Self {
        let [r, g, b] = rgb565_to_rgb888(raw);
        Self::from(Rgb888::new(r, g, b))
    }

    /// The colour of 8-bit channels `[r, g, b]` (a filtered or lit
    /// texel): must equal `Self::from(Rgb888::new(r, g, b))`, which the
    /// default returns.
    #[inline(always)]
    fn from_rgb888([r, g, b]: [u8; 3]) -> Self {
        Self::from(Rgb888::new(r, g, b))
    }
}

impl FromTexel for Rgb565 {
    /// The bits as they are: `Rgb888`'s rounding conversion of an
    /// expanded channel gives the channel back.
    #[inline(always)]
    fn from_rgb565(raw: u16) -> Self {
        Rgb565::from(RawU16::new(raw))
    }

    /// By the 512-byte table of embedded-graphics' rounding
    /// (`shade::convert`), rather than its three multiplies.
    #[inline(always)]
    fn from_rgb888([r, g, b]: [u8; 3]) -> Self {
        Rgb565::from(RawU16::new(crate::shade::rgb565_bits(r, g, b)))
    }
}

impl FromTexel for crate::sink::Rgb565Be {
    #[inline(always)]
    fn from_rgb565(raw: u16) -> Self {
        Self::from(RawU16::new(raw))
    }

    /// As `Rgb565`'s.
    #[inline(always)]
    fn from_rgb888([r, g, b]: [u8; 3]) -> Self {
        Self::from(RawU16::new(crate::shade::rgb565_bits(r, g, b)))
    }
}

impl FromTexel for Rgb888 {}
impl FromTexel for Bgr888 {}
impl FromTexel for Bgr565 {}
impl FromTexel for Rgb555 {}
impl FromTexel for Bgr555 {}
impl FromTexel for Gray8 {}
impl FromTexel for Gray4 {}
impl FromTexel for Gray2 {}
impl FromTexel for BinaryColor {}

/// How a span samples a texture: decided by [`Texture::sampler`].
#[derive(Clone, Copy, Debug)]
pub enum Sampler<'t> {
    /// Nearest, `Rgb565` texels, power-of-two sides, [`Wrap::Repeat`] on
    /// both axes.
    NearestRgb565(Pow2Rgb565<'t>),
    /// Bilinear, with the same texels, sides and wrap.
    BilinearRgb565(Pow2Rgb565<'t>),
    /// Any other texture: [`Texture::sample`].
    General(&'t Texture<'t>),
}

/// An `Rgb565` texture of power-of-two sides, repeated: addressed with
/// shifts and masks.
#[derive(Clone, Copy, Debug)]
pub struct Pow2Rgb565<'t> {
    texels: &'t [u16],
    /// `16 - log2` of each side: `raw >> shift` is the texel coordinate.
    shift: [u32; 2],
    /// `log2` of each side.
    log2: [u32; 2],
    /// `side - 1`.
    mask: [u32; 2],
}

impl<'t> Texture<'t> {
    /// How a span should sample this texture.
    #[inline(always)]
    pub fn sampler(&'t self) -> Sampler<'t> {
        let fast = self.u.pow2
            && self.v.pow2
            && self.u.wrap == Wrap::Repeat
            && self.v.wrap == Wrap::Repeat;
        match self.texels {
            Texels::Rgb565(texels) if fast => {
                let p = Pow2Rgb565 {
                    texels,
                    shift: [self.u.shift as u32, self.v.shift as u32],
                    log2: [self.u.log2 as u32, self.v.log2 as u32],
                    mask: [self.u.size - 1, self.v.size - 1],
                };
                match self.filter {
                    Filter::Nearest => Sampler::NearestRgb565(p),
                    Filter::Bilinear => Sampler::BilinearRgb565(p),
                }
            }
            _ => Sampler::General(self),
        }
    }
}

impl Pow2Rgb565<'_> {
    /// The texel `(x, y)`'s bits, coordinates already masked; black only
    /// if the slice were short, which `Texture::new` rules out.
    #[inline(always)]
    fn at(&self, x: u32, y: u32) -> u16 {
        match self.texels.get(((y << self.log2[0]) | x) as usize) {
            Some(&c) => c,
            None => 0,
        }
    }

    /// The nearest texel's bits at `(u, v)` (raw 16.16): `floor(u · size)`
    /// modulo the size, as [`Texture::sample`] takes it.
    #[inline(always)]
    pub fn nearest(&self, u: i32, v: i32) -> u16 {
        let x = (u >> self.shift[0]) as u32 & self.mask[0];
        let y = (v >> self.shift[1]) as u32 & self.mask[1];
        self.at(x, y)
    }

    /// The bilinear sample at `(u, v)`: the same taps, weights and blend
    /// as [`Texture::sample`], the four reads inlined.
    #[inline(always)]
    pub fn bilinear(&self, u: i32, v: i32) -> [u8; 3] {
        let taps = |raw: i32, axis: usize| {
            let s = ((raw as u32) << self.log2[axis]).wrapping_add(HALF);
            let j = s >> 16;
            let m = self.mask[axis];
            (
                j.wrapping_sub(1) & m,
                j & m,
                (s & 0xFFFF) >> (16 - WEIGHT_BITS),
            )
        };
        let (x0, x1, fx) = taps(u, 0);
        let (y0, y1, fy) = taps(v, 1);
        let a = rgb565_to_rgb888(self.at(x0, y0));
        let b = rgb565_to_rgb888(self.at(x1, y0));
        let c = rgb565_to_rgb888(self.at(x0, y1));
        let d = rgb565_to_rgb888(self.at(x1, y1));
        let mut out = [0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            *o = blend_channel(a[k], b[k], c[k], d[k], fx, fy);
        }
        out
    }
}
