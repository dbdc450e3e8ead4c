//! Textures borrowed from flash: texel formats, addressing, wrap modes and
//! nearest or bilinear filtering, in integer arithmetic.
//!
//! A [`Texture`] borrows its texels (and palette) as `&'a` slices, normally
//! the `static` arrays that `microraster-import` generates, so they stay in
//! flash. Every layout rule is checked once, in [`Texture::new`]: the size,
//! the slice lengths, the palette size and every palette index. After that
//! no lookup can go out of range, and [`Texture::sample`] is total: any `u`
//! and `v`, including the extreme raw values `i32::MIN` and `i32::MAX`,
//! give a colour, never a panic or an overflow.
//!
//! # Coordinates
//!
//! Texel `(x, y)` is column `x` from the left and row `y` from the top of
//! the image, the order the importer writes rows in. In normalised
//! coordinates `u` runs left to right and `v` top to bottom: `u = 0..1`
//! spans the width once and `v = 0..1` the height, so `v = 0` is the top
//! edge of the image, not the bottom as in OpenGL's texture space and in
//! OBJ files (whose `vt` the importer copies unchanged): such UVs need
//! `v' = 1 - v` (which maps texel centres to texel centres). As in OpenGL,
//! texel `i` covers `[i / width, (i + 1) / width)` and its centre is at
//! `(i + ½) / width`.
//!
//! # Addressing
//!
//! [`Filter::Nearest`] picks the texel whose square contains the sample
//! point: `floor(u · width)`, then mapped into `0..width` by the axis'
//! [`Wrap`] mode (and likewise `v` with the height):
//!
//! * [`Wrap::Repeat`]: `i mod width` (the image tiles the plane).
//! * [`Wrap::MirroredRepeat`]: period `2 · width`, every other copy
//!   mirrored, as OpenGL's `MIRRORED_REPEAT`: `m = i mod 2·width`, then `m`
//!   if `m < width`, else `2·width - 1 - m`.
//! * [`Wrap::ClampToEdge`]: `i` clamped to `0..=width - 1`.
//!
//! A side is at most [`MAX_SIDE`] (2^15) texels, so the product of a
//! coordinate reduced to 17 bits (`0 <= u < 2`) and a side always fits 32
//! bits. Each mode first reduces `u` to the part that matters, exactly:
//! repeat keeps `u mod 1`, mirrored repeat `u mod 1` and whether `floor(u)`
//! is odd (the mirrored copies; bilinear filtering keeps `u mod 2`), and
//! clamping clamps `u` to `0..=1`. Then `floor(u · width)` is one 32-bit
//! multiply and a shift, with no `i64` and no division. For a power-of-two
//! side `2^k`, decided once in [`Texture::new`], repeat needs no multiply
//! at all: the texel is `(u_bits >> (16 - k)) & (2^k - 1)`, an arithmetic
//! shift and a mask, and mirrored repeat then takes `2^k - 1 - i` in the
//! odd copies. Both paths give exactly the same texels.
//!
//! # Bilinear filtering
//!
//! [`Filter::Bilinear`] blends the four texels around the sample point with
//! OpenGL's `LINEAR` weights. Per axis, `s = u · width - ½` (exact in
//! 16.16); the two texels are `i0 = floor(s)` and `i1 = i0 + 1`, each
//! mapped by the wrap mode on its own (so a repeating texture blends its
//! last column with its first across the seam, a mirrored one blends the
//! edge texel with itself, and so does a clamped one). The weight of `i1`
//! is the fraction of `s` truncated to 12 bits, `fx = floor(frac(s) ·
//! 4096)`, and `i0` gets `4096 - fx`; likewise `fy` for the rows. Each
//! channel is then
//!
//! ```text
//! c = floor((Σ w_ij · c_ij + 2^23) / 2^24)
//! ```
//!
//! with `w_00 = (4096 - fx)(4096 - fy)`, `w_10 = fx (4096 - fy)`,
//! `w_01 = (4096 - fx) fy` and `w_11 = fx fy` (which sum to 2^24): the
//! blend computed exactly in integers and rounded to nearest, halves up.
//! Truncating the weights moves the blend by less than `2 · 255 / 4096 ≈
//! 0.125`, so every channel is within 0.625 of the exact bilinear value
//! (the one with untruncated weights), hence within ±1 after rounding. At
//! a texel centre the fraction is 0 and the result is that texel exactly,
//! as with [`Filter::Nearest`].
//!
//! Everything at sample time is `u32`/`i32` arithmetic (no `f32`, no
//! `i64`), so every target gives the same bits.
//!
//! # Colours
//!
//! [`Texture::texel`] and [`Texture::sample`] return RGB with 8 bits per
//! channel. Rgb565 texels and palette entries are expanded by bit
//! replication ([`rgb565_to_rgb888`]), [`Texels::Gray8`] gives `[g, g, g]`.
//!
//! # Cost
//!
//! The texels stay where they are: an Rgb565 texture takes `2 · width ·
//! height` bytes of flash, Gray8 and Indexed8 one byte per texel (plus 2
//! bytes per palette colour), Indexed4 `height · ⌈width / 2⌉` bytes. The
//! [`Texture`] itself is a few words, 44 bytes on a 32-bit target: the
//! two slices, the stride, the sizes and the modes. Building it reads every
//! index of an indexed texture whose palette is not full, once; sampling
//! reads one texel (nearest) or four (bilinear). On a Cortex-M0+ the whole
//! of [`Texture::sample`] is about 600 instructions of code, of which a
//! nearest sample runs a few dozen.
//!
//! # Example
//!
//! ```
//! use fixed::types::I16F16;
//! use microraster::texture::{Filter, Texels, Texture, Wrap};
//!
//! // A 2x2 checker: red, green on the top row; blue, white below.
//! static TEXELS: [u16; 4] = [0xF800, 0x07E0, 0x001F, 0xFFFF];
//! let texture = Texture::new(2, 2, Texels::Rgb565(&TEXELS)).unwrap();
//!
//! let fx = |x: f32| I16F16::from_num(x);
//! // Nearest (the default): the texel whose square holds the point.
//! assert_eq!(texture.sample(fx(0.25), fx(0.25)), [255, 0, 0]);
//! assert_eq!(texture.sample(fx(0.75), fx(0.25)), [0, 255, 0]);
//! assert_eq!(texture.sample(fx(0.25), fx(0.75)), [0, 0, 255]);
//! // Repeat (the default): u = 1.25 is u = 0.25 again; u = -0.25 is 0.75.
//! assert_eq!(texture.sample(fx(1.25), fx(0.75)), [0, 0, 255]);
//! assert_eq!(texture.sample(fx(-0.25), fx(0.75)), [255, 255, 255]);
//!
//! // Bilinear: halfway between red and green, rounded to nearest.
//! let smooth = texture.filter(Filter::Bilinear).wrap(Wrap::ClampToEdge);
//! assert_eq!(smooth.sample(fx(0.5), fx(0.25)), [128, 128, 0]);
//! // The middle of the image blends all four texels equally.
//! assert_eq!(smooth.sample(fx(0.5), fx(0.5)), [128, 128, 128]);
//! // At a texel centre, exactly that texel.
//! assert_eq!(smooth.sample(fx(0.75), fx(0.75)), [255, 255, 255]);
//! ```

mod axis;
mod bilinear;
mod fetch;
mod from_texel;
mod sampler;
// The tests (in a file of their own) run on the host, with std: its
// names they use are imported here, under the same `cfg(test)`.
#[cfg(test)]
extern crate std;
#[cfg(test)]
use std::{string::ToString, vec::Vec};
#[cfg(test)]
mod tests;

use axis::Axis;
#[cfg(target_pointer_width = "64")]
pub(crate) use bilinear::PackedQuad;
use fixed::types::I16F16;
#[cfg(any(test, not(target_pointer_width = "64")))]
pub(crate) use from_texel::expanded257;
#[cfg(any(test, microraster_armv7m))]
pub(crate) use from_texel::lit_channel;
pub use from_texel::FromTexel;
pub(crate) use sampler::Quad;
pub use sampler::{Pow2Rgb565, Sampler};

/// The largest width or height accepted by [`Texture::new`]: 32,768 texels.
///
/// It keeps every product of a 16-bit coordinate fraction and a side within
/// 32 bits, and the texel count of an image (at most 2^30) within a 32-bit
/// `usize`.
pub const MAX_SIDE: u32 = 1 << 15;

/// One half in 16.16: moves `u · width` to texel centres (bilinear) and
/// rounds.
const HALF: u32 = 1 << 15;
/// Fraction bits of the bilinear weights.
const WEIGHT_BITS: u32 = 12;

/// Texel storage: the layouts `microraster-import` generates (its
/// `TextureFormat`), rows from the top, texels left to right.
///
/// Indexed palettes are Rgb565 colours, as in [`Texels::Rgb565`].
#[derive(Clone, Copy, Debug)]
pub enum Texels<'a> {
    /// One `u16` per texel: red in bits 15-11, green 10-5, blue 4-0 (the
    /// raw data of embedded-graphics' `Rgb565`); `width · height` entries.
    Rgb565(&'a [u16]),
    /// One luma byte per texel, shown as grey `[g, g, g]`;
    /// `width · height` entries.
    Gray8(&'a [u8]),
    /// One palette index per texel; `width · height` entries.
    Indexed8 {
        /// The palette index of every texel.
        indices: &'a [u8],
        /// Rgb565 colours, 1 to 256 of them.
        palette: &'a [u16],
    },
    /// Two palette indices per byte, the left texel in the high nibble.
    /// Each row starts on a new byte, so the stride is `(width + 1) / 2`
    /// bytes and there are `height · stride` of them; in a row of odd
    /// width the last byte's low nibble is padding, never read or checked.
    Indexed4 {
        /// The palette indices, two per byte.
        indices: &'a [u8],
        /// Rgb565 colours, 1 to 16 of them.
        palette: &'a [u16],
    },
}

/// How a texture is sampled between texel centres.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Filter {
    /// The texel whose square contains the sample point (default).
    #[default]
    Nearest,
    /// The four texels around the sample point, blended by distance (see
    /// the [module docs](self#bilinear-filtering) for the exact rounding).
    Bilinear,
}

/// How coordinates outside `0..1` map onto the texture, per axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Wrap {
    /// The texture tiles the plane: only the fraction of the coordinate
    /// counts (default).
    #[default]
    Repeat,
    /// Every other copy is mirrored (period 2), as OpenGL's
    /// `MIRRORED_REPEAT`: no seam at whole coordinates.
    MirroredRepeat,
    /// Coordinates are clamped so the edge texels extend outwards (and
    /// bilinear filtering never blends in the opposite edge).
    ClampToEdge,
}

/// Why a texture could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureError {
    /// The width or the height is zero.
    ZeroSize {
        /// The width given.
        width: u32,
        /// The height given.
        height: u32,
    },
    /// The width or the height exceeds [`MAX_SIDE`] (or the texel count
    /// exceeds the address space, on a target with a 16-bit `usize`).
    TooLarge {
        /// The width given.
        width: u32,
        /// The height given.
        height: u32,
    },
    /// The texel slice (the indices, for the indexed formats) does not
    /// have the length the size needs: `stride · height` elements, where
    /// the stride is the width, or `(width + 1) / 2` for
    /// [`Texels::Indexed4`].
    LengthMismatch {
        /// The length the size needs.
        expected: usize,
        /// The slice's length.
        actual: usize,
    },
    /// The palette is empty, or longer than the format can index (256
    /// colours for [`Texels::Indexed8`], 16 for [`Texels::Indexed4`]).
    PaletteSize {
        /// The palette's length.
        len: usize,
        /// The most colours the format can index.
        max: usize,
    },
    /// A texel's palette index is past the end of the palette (the first
    /// such texel, in row order).
    IndexOutOfRange {
        /// The texel's column.
        x: u32,
        /// The texel's row.
        y: u32,
        /// Its palette index.
        index: u8,
        /// The palette's length.
        palette_len: usize,
    },
}

impl core::fmt::Display for TextureError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::ZeroSize { width, height } => {
                write!(f, "texture size {width}x{height} has no texels")
            }
            Self::TooLarge { width, height } => write!(
                f,
                "texture size {width}x{height} exceeds the limit of {MAX_SIDE} texels per side"
            ),
            Self::LengthMismatch { expected, actual } => write!(
                f,
                "texel slice has {actual} elements, but the size needs {expected} (stride x height)"
            ),
            Self::PaletteSize { len, max } => write!(
                f,
                "palette has {len} colours, but the format needs 1 to {max}"
            ),
            Self::IndexOutOfRange {
                x,
                y,
                index,
                palette_len,
            } => write!(
                f,
                "texel ({x}, {y}) has palette index {index}, but the palette has {palette_len} colours"
            ),
        }
    }
}

impl core::error::Error for TextureError {}

/// An Rgb565 colour (red in bits 15-11, green 10-5, blue 4-0) as 8-bit RGB,
/// each channel expanded by bit replication: `r8 = r5 << 3 | r5 >> 2`,
/// `g8 = g6 << 2 | g6 >> 4`, likewise blue.
///
/// That maps 0 to 0 and the largest value to 255, and converting back to
/// Rgb565 rounding to nearest (as the importer does) gives the original
/// bits. embedded-graphics' `Rgb888::from(Rgb565)` rounds `v · 255 / 31`
/// (or `/ 63`) to nearest instead; the two differ by one in 4 of the 32
/// red/blue levels (3, 7, 24, 28) and 10 of the 64 green levels (11 to 15
/// and 48 to 52), and agree everywhere else.
///
/// ```
/// use microraster::texture::rgb565_to_rgb888;
/// assert_eq!(rgb565_to_rgb888(0xFFFF), [255, 255, 255]);
/// assert_eq!(rgb565_to_rgb888(0xF800), [255, 0, 0]);
/// assert_eq!(rgb565_to_rgb888(16 << 11 | 32 << 5 | 16), [132, 130, 132]);
/// ```
#[inline]
pub const fn rgb565_to_rgb888(raw: u16) -> [u8; 3] {
    let r = (raw >> 11) as u8;
    let g = ((raw >> 5) & 0x3F) as u8;
    let b = (raw & 0x1F) as u8;
    [r << 3 | r >> 2, g << 2 | g >> 4, b << 3 | b >> 2]
}

/// A texture: texels borrowed from flash (or any `'a` memory), with a
/// filter and a wrap mode per axis.
///
/// Build it with [`Texture::new`], which checks every layout rule, then
/// set the modes with the `const` builders [`filter`](Texture::filter),
/// [`wrap`](Texture::wrap) and [`wrap_uv`](Texture::wrap_uv). It is
/// [`Copy`] and a few words long (see the [module docs](self#cost)).
/// Since `new` is a `const fn`, a texture can itself be a `static`:
///
/// ```
/// use microraster::texture::{Filter, Texels, Texture, Wrap};
///
/// static PALETTE: [u16; 2] = [0x0000, 0xFFFF];
/// static INDICES: [u8; 2] = [0x10, 0x01]; // 2x2 Indexed4: a byte per row
/// static TEXTURE: Texture<'static> = match Texture::new(
///     2,
///     2,
///     Texels::Indexed4 { indices: &INDICES, palette: &PALETTE },
/// ) {
///     Ok(t) => t.filter(Filter::Bilinear).wrap(Wrap::MirroredRepeat),
///     Err(_) => panic!("bad texture"),
/// };
/// assert_eq!(TEXTURE.texel(0, 0), [255, 255, 255]);
/// assert_eq!(TEXTURE.texel(1, 1), [255, 255, 255]);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Texture<'a> {
    texels: Texels<'a>,
    /// Elements of `texels` per row.
    stride: u32,
    u: Axis,
    v: Axis,
    filter: Filter,
    /// The sampler's kind ([`Texture::sampler`]), decided whenever the
    /// texels, filter or wrap modes are set rather than at every
    /// triangle-tile pair: about twenty tests a pair down to one (it fits
    /// the struct's padding).
    kind: Kind,
}

/// What [`Texture::sampler`] returns for a texture: the `Rgb565`
/// power-of-two repeated loops, or the general path. `sampler` tests
/// only `General`; the other two repeat the filter, yet as a `bool` the
/// field changed the textured loops' code (ARMv6-M `demo-textured-lit`
/// 12,423,162 -> 12,448,780 instructions, x86-64 5,993,431 -> 5,979,110).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// [`Sampler::General`].
    General,
    /// [`Sampler::NearestRgb565`].
    Nearest,
    /// [`Sampler::BilinearRgb565`].
    Bilinear,
}

// The documented RAM cost.
#[cfg(target_pointer_width = "32")]
const _: () = assert!(core::mem::size_of::<Texture<'static>>() <= 44);

impl<'a> Texture<'a> {
    /// A `width` x `height` texture over `texels`, laid out as [`Texels`]
    /// says, with [`Filter::Nearest`] and [`Wrap::Repeat`] on both axes.
    ///
    /// Checks, in this order: both sides are non-zero and at most
    /// [`MAX_SIDE`]; the texel (or index) slice has exactly `stride ·
    /// height` elements; a palette has 1 to 256 ([`Texels::Indexed8`]) or 1
    /// to 16 ([`Texels::Indexed4`]) colours; every texel's palette index is
    /// within the palette (unless the palette is full, when every index
    /// is). The first rule broken is the error.
    ///
    /// ```
    /// use microraster::texture::{Texels, Texture, TextureError};
    ///
    /// static INDICES: [u8; 4] = [0, 1, 2, 1];
    /// static PALETTE: [u16; 2] = [0x0000, 0xFFFF];
    /// let texels = Texels::Indexed8 { indices: &INDICES, palette: &PALETTE };
    /// assert_eq!(
    ///     Texture::new(2, 2, texels).unwrap_err(),
    ///     TextureError::IndexOutOfRange { x: 0, y: 1, index: 2, palette_len: 2 }
    /// );
    /// assert_eq!(
    ///     Texture::new(3, 2, texels).unwrap_err(),
    ///     TextureError::LengthMismatch { expected: 6, actual: 4 }
    /// );
    /// ```
    pub const fn new(width: u32, height: u32, texels: Texels<'a>) -> Result<Self, TextureError> {
        if width == 0 || height == 0 {
            return Err(TextureError::ZeroSize { width, height });
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(TextureError::TooLarge { width, height });
        }
        let (stride, actual, palette_max) = match texels {
            Texels::Rgb565(t) => (width, t.len(), 0),
            Texels::Gray8(t) => (width, t.len(), 0),
            Texels::Indexed8 { indices, .. } => (width, indices.len(), 256),
            Texels::Indexed4 { indices, .. } => (width.div_ceil(2), indices.len(), 16),
        };
        // At most 2^30: only a 16-bit `usize` can overflow.
        let Some(expected) = (stride as usize).checked_mul(height as usize) else {
            return Err(TextureError::TooLarge { width, height });
        };
        if actual != expected {
            return Err(TextureError::LengthMismatch { expected, actual });
        }
        match texels {
            Texels::Indexed8 { indices, palette } | Texels::Indexed4 { indices, palette } => {
                let len = palette.len();
                if len == 0 || len > palette_max {
                    return Err(TextureError::PaletteSize {
                        len,
                        max: palette_max,
                    });
                }
                // A full palette makes every index valid.
                if len < palette_max {
                    let nibbles = palette_max == 16;
                    let mut y = 0;
                    while y < height {
                        let mut x = 0;
                        while x < width {
                            let row = y as usize * stride as usize;
                            let index = if nibbles {
                                let byte = indices[row + x as usize / 2];
                                if x & 1 == 0 {
                                    byte >> 4
                                } else {
                                    byte & 0x0F
                                }
                            } else {
                                indices[row + x as usize]
                            };
                            if index as usize >= len {
                                return Err(TextureError::IndexOutOfRange {
                                    x,
                                    y,
                                    index,
                                    palette_len: len,
                                });
                            }
                            x += 1;
                        }
                        y += 1;
                    }
                }
            }
            Texels::Rgb565(_) | Texels::Gray8(_) => {}
        }
        Ok(Self {
            texels,
            stride,
            u: Axis::new(width),
            v: Axis::new(height),
            filter: Filter::Nearest,
            kind: Kind::General,
        }
        .decided())
    }

    /// The texture with filter `filter`.
    #[must_use]
    pub const fn filter(self, filter: Filter) -> Self {
        Self { filter, ..self }.decided()
    }

    /// The texture with wrap mode `wrap` on both axes.
    #[must_use]
    pub const fn wrap(self, wrap: Wrap) -> Self {
        self.wrap_uv(wrap, wrap)
    }

    /// The texture with wrap mode `u` across (columns) and `v` down (rows).
    #[must_use]
    pub const fn wrap_uv(self, u: Wrap, v: Wrap) -> Self {
        let mut t = self;
        t.u.wrap = u;
        t.v.wrap = v;
        t.decided()
    }

    /// The texture with its `kind` set from its texels,
    /// sides, filter and wrap modes: an `Rgb565` texture of power-of-two
    /// sides repeated on both axes takes the fast loops, if bilinear or
    /// at least two texels wide (nearest's
    /// [`nearest_fine`](sampler::Pow2Rgb565::nearest_fine) needs that
    /// width; one texel wide it takes the general path).
    const fn decided(self) -> Self {
        let fast = self.u.pow2
            && self.v.pow2
            && matches!(self.u.wrap, Wrap::Repeat)
            && matches!(self.v.wrap, Wrap::Repeat)
            && matches!(self.texels, Texels::Rgb565(_));
        let kind = match self.filter {
            Filter::Bilinear if fast => Kind::Bilinear,
            Filter::Nearest if fast && self.u.log2 > 0 => Kind::Nearest,
            _ => Kind::General,
        };
        Self { kind, ..self }
    }

    /// Width in texels.
    pub const fn width(&self) -> u32 {
        self.u.size
    }

    /// Height in texels.
    pub const fn height(&self) -> u32 {
        self.v.size
    }

    /// The texel storage.
    pub const fn texels(&self) -> Texels<'a> {
        self.texels
    }

    /// The filter ([`Filter::Nearest`] unless set by
    /// [`filter`](Texture::filter)).
    pub const fn filter_mode(&self) -> Filter {
        self.filter
    }

    /// The wrap modes `(u, v)` ([`Wrap::Repeat`] unless set).
    pub const fn wrap_modes(&self) -> (Wrap, Wrap) {
        (self.u.wrap, self.v.wrap)
    }

    /// Texel `(x, y)` as 8-bit RGB: column `x` from the left, row `y` from
    /// the top of the image (`(0, 0)` is the top-left), for `x < width` and
    /// `y < height`. Coordinates out of range are clamped to the last
    /// column or row, never a panic.
    pub fn texel(&self, x: u32, y: u32) -> [u8; 3] {
        self.fetch(x.min(self.u.size - 1), y.min(self.v.size - 1))
    }

    /// Samples the texture at normalised coordinates: `u = 0..1` spans the
    /// width once (left to right), `v = 0..1` the height (top to bottom;
    /// `v = 0` is the image's top edge). Texel `i`'s centre is at
    /// `(i + ½) / width`, as in OpenGL. Applies the filter and the wrap
    /// modes (see the [module docs](self)); any `u`, `v` is valid.
    ///
    /// The nearest-texel path is inlined into the caller (the span loop);
    /// bilinear filtering, four times the work, is a call.
    #[inline(always)]
    pub fn sample(&self, u: I16F16, v: I16F16) -> [u8; 3] {
        let (u, v) = (u.to_bits(), v.to_bits());
        match self.filter {
            Filter::Nearest => self.fetch(self.u.nearest(u), self.v.nearest(v)),
            Filter::Bilinear => self.bilinear(u, v),
        }
    }
}
