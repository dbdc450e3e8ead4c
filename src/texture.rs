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

use fixed::types::I16F16;

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

/// The addressing of one axis: its size and wrap mode, and whether the size
/// is a power of two (then `log2` is its exponent, and `shift` is
/// `16 - log2`, stored so nearest sampling need not subtract), decided once.
#[derive(Clone, Copy, Debug)]
struct Axis {
    size: u32,
    log2: u8,
    shift: u8,
    pow2: bool,
    wrap: Wrap,
}

impl Axis {
    const fn new(size: u32) -> Self {
        Self {
            size,
            log2: size.trailing_zeros() as u8,
            // Only used for powers of two, where `log2 <= 15`.
            shift: 16u32.saturating_sub(size.trailing_zeros()) as u8,
            pow2: size.is_power_of_two(),
            wrap: Wrap::Repeat,
        }
    }

    /// `floor(u · size) mod size`, for `u` with raw 16.16 bits `raw`.
    #[inline(always)]
    fn repeat(self, raw: i32) -> u32 {
        if self.pow2 {
            // The arithmetic shift is `floor(u · 2^log2)`.
            (raw >> self.shift) as u32 & (self.size - 1)
        } else {
            // `floor(u · size) = floor(u) · size + floor(frac(u) · size)`,
            // and the second term is already in `0..size`. The product is
            // below 2^16 · 2^15.
            ((raw as u32 & 0xFFFF) * self.size) >> 16
        }
    }

    /// The texel of [`Filter::Nearest`]: `floor(u · size)` mapped by the
    /// wrap mode.
    #[inline(always)]
    fn nearest(self, raw: i32) -> u32 {
        match self.wrap {
            Wrap::Repeat => self.repeat(raw),
            Wrap::MirroredRepeat => {
                let i = self.repeat(raw);
                // Copies with odd `floor(u)` (bit 16) are the mirrored ones.
                if raw & 0x1_0000 != 0 {
                    self.size - 1 - i
                } else {
                    i
                }
            }
            // `u` clamped to `[0, 1)` gives the same texel as `floor(u · size)`
            // clamped: 0xFFFF · size / 2^16 is just below `size`.
            Wrap::ClampToEdge => (raw.clamp(0, 0xFFFF) as u32 * self.size) >> 16,
        }
    }

    /// Mirrored repeat of texel coordinate `c` (taken modulo `2 · size`,
    /// which divides 2^32) for a power-of-two size.
    #[inline(always)]
    fn mirror_pow2(self, c: u32) -> u32 {
        let flip = ((c >> self.log2) & 1).wrapping_neg();
        (c ^ flip) & (self.size - 1)
    }

    /// Mirrored repeat of texel coordinate `c` in `0..=2 · size` (any size).
    #[inline(always)]
    fn mirror(self, c: u32) -> u32 {
        if c < self.size {
            c
        } else if c < 2 * self.size {
            2 * self.size - 1 - c
        } else {
            // `2 · size` is coordinate 0 of the next period.
            0
        }
    }

    /// The two texels of [`Filter::Bilinear`] and the weight of the second:
    /// `(i0, i1, fx)` with `s = u · size - ½`, `i0 = floor(s)` and
    /// `i1 = i0 + 1` mapped by the wrap mode, and `fx` the fraction of `s`
    /// in [`WEIGHT_BITS`] bits, truncated.
    ///
    /// Below, `j = i1 = floor(u · size + ½)` and `s + 1` is computed as
    /// `(j << 16) + fraction`, so no step needs a negative number.
    #[inline(always)]
    fn taps(self, raw: i32) -> (u32, u32, u32) {
        let (i0, i1, frac) = match self.wrap {
            Wrap::Repeat | Wrap::MirroredRepeat if self.pow2 => {
                // Wrapping arithmetic is exact modulo 2^32, and both modes
                // only need `j` modulo `2 · size`, which divides 2^16.
                let s = ((raw as u32) << self.log2).wrapping_add(HALF);
                let j = s >> 16;
                let pair = if self.wrap == Wrap::Repeat {
                    let mask = self.size - 1;
                    (j.wrapping_sub(1) & mask, j & mask)
                } else {
                    (self.mirror_pow2(j.wrapping_sub(1)), self.mirror_pow2(j))
                };
                (pair.0, pair.1, s)
            }
            Wrap::Repeat => {
                // `u mod 1` shifts `s` by a multiple of `size`: the same
                // texels modulo `size`, the same fraction. Below 2^31 + 2^15.
                let s = (raw as u32 & 0xFFFF) * self.size + HALF;
                let j = s >> 16; // 0..=size
                let i0 = if j == 0 { self.size - 1 } else { j - 1 };
                let i1 = if j == self.size { 0 } else { j };
                (i0, i1, s)
            }
            Wrap::MirroredRepeat => {
                // `u mod 2` shifts `s` by a multiple of the period `2 · size`.
                // `t` is below 2^17 · 2^15 = 2^32, but `t + ½` may not be,
                // so the half is added to the fraction alone.
                let t = (raw as u32 & 0x1_FFFF) * self.size;
                let j = (t >> 16) + (((t & 0xFFFF) + HALF) >> 16); // 0..=2·size
                let i0 = if j == 0 { 0 } else { self.mirror(j - 1) };
                (i0, self.mirror(j), t.wrapping_add(HALF))
            }
            Wrap::ClampToEdge => {
                // Beyond `0..=1` both texels clamp to the same edge texel, as
                // they do at `u = 0` or `u = 1`, so clamping `u` first changes
                // nothing. At most 2^31 + 2^15.
                let s = raw.clamp(0, 0x1_0000) as u32 * self.size + HALF;
                let j = s >> 16; // 0..=size
                (j.saturating_sub(1), j.min(self.size - 1), s)
            }
        };
        (i0, i1, (frac & 0xFFFF) >> (16 - WEIGHT_BITS))
    }
}

/// One channel of the bilinear blend, exactly `floor((Σ w_ij c_ij + 2^23) /
/// 2^24)` of the module docs, as two linear interpolations.
#[inline(always)]
fn blend_channel(c00: u8, c10: u8, c01: u8, c11: u8, fx: u32, fy: u32) -> u8 {
    let lerp_x = |a: u8, b: u8| ((a as i32) << WEIGHT_BITS) + (b as i32 - a as i32) * fx as i32;
    // Both rows are in `0..=255 · 2^12`.
    let (top, bottom) = (lerp_x(c00, c10), lerp_x(c01, c11));
    // The exact value is in `0..=255 · 2^24`, which fits a `u32` but not an
    // `i32`; wrapping arithmetic is exact modulo 2^32, so the `u32` result
    // is that value, even though `bottom - top` may be negative.
    let v = ((top as u32) << WEIGHT_BITS).wrapping_add(((bottom - top) as u32).wrapping_mul(fy));
    // At most 255 · 2^24 + 2^23 < 2^32.
    ((v + (1 << (2 * WEIGHT_BITS - 1))) >> (2 * WEIGHT_BITS)) as u8
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
        })
    }

    /// The texture with filter `filter`.
    #[must_use]
    pub const fn filter(self, filter: Filter) -> Self {
        Self { filter, ..self }
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
        t
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

    /// [`sample`](Self::sample) with [`Filter::Bilinear`].
    #[inline(never)]
    fn bilinear(&self, u: i32, v: i32) -> [u8; 3] {
        let (x0, x1, fx) = self.u.taps(u);
        let (y0, y1, fy) = self.v.taps(v);
        let (a, b) = (self.fetch_call(x0, y0), self.fetch_call(x1, y0));
        let (c, d) = (self.fetch_call(x0, y1), self.fetch_call(x1, y1));
        let mut out = [0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            *o = blend_channel(a[k], b[k], c[k], d[k], fx, fy);
        }
        out
    }

    /// [`fetch`](Self::fetch) as a call: bilinear filtering reads four
    /// texels, and four inlined copies of the format match would more
    /// than double the code of `sample` for a few cycles each.
    #[inline(never)]
    fn fetch_call(&self, x: u32, y: u32) -> [u8; 3] {
        self.fetch(x, y)
    }

    /// Texel `(x, y)`, for `x < width` and `y < height`.
    #[inline(always)]
    fn fetch(&self, x: u32, y: u32) -> [u8; 3] {
        let row = y as usize * self.stride as usize;
        let i = row + x as usize;
        // `new` checked the lengths and every index, so each `get` below
        // succeeds; the fallbacks (black) only keep the lookups free of
        // panic paths, which `forbid(unsafe_code)` cannot remove otherwise.
        match self.texels {
            Texels::Rgb565(t) => rgb565_to_rgb888(match t.get(i) {
                Some(&c) => c,
                None => 0,
            }),
            Texels::Gray8(t) => {
                let g = match t.get(i) {
                    Some(&g) => g,
                    None => 0,
                };
                [g, g, g]
            }
            Texels::Indexed8 { indices, palette } => {
                let index = match indices.get(i) {
                    Some(&n) => n,
                    None => 0,
                };
                palette_color(palette, index)
            }
            Texels::Indexed4 { indices, palette } => {
                let byte = match indices.get(row + x as usize / 2) {
                    Some(&b) => b,
                    None => 0,
                };
                // The left (even) texel is in the high nibble.
                let index = (byte >> (4 - 4 * (x & 1))) & 0x0F;
                palette_color(palette, index)
            }
        }
    }
}

#[inline(always)]
fn palette_color(palette: &[u16], index: u8) -> [u8; 3] {
    rgb565_to_rgb888(match palette.get(index as usize) {
        Some(&c) => c,
        None => 0,
    })
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::vec::Vec;

    /// A small xorshift generator: reproducible pseudo-random raw values.
    struct XorShift(u32);

    impl XorShift {
        fn next(&mut self) -> u32 {
            let mut x = self.0;
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            self.0 = x;
            x
        }

        /// A raw 16.16 coordinate: mostly near `-3..3`, sometimes anywhere.
        fn coordinate(&mut self) -> i32 {
            let r = self.next();
            match r % 4 {
                0 => r as i32,
                _ => (self.next() % (6 << 16)) as i32 - (3 << 16),
            }
        }
    }

    const WRAPS: [Wrap; 3] = [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge];

    /// Extreme and seam raw coordinates, tried everywhere.
    const SPECIAL: [i32; 16] = [
        i32::MIN,
        i32::MIN + 1,
        i32::MAX,
        i32::MAX - 1,
        -(2 << 16),
        -(1 << 16) - 1,
        -(1 << 16),
        -(1 << 16) + 1,
        -1,
        0,
        1,
        (1 << 16) - 1,
        1 << 16,
        (1 << 16) + 1,
        (2 << 16) - 1,
        2 << 16,
    ];

    fn fx(raw: i32) -> I16F16 {
        I16F16::from_bits(raw)
    }

    /// Maps integer texel coordinate `i` by `wrap` onto `0..size`, written
    /// straight from the OpenGL specification, in `i64`.
    fn wrap_reference(i: i64, size: i64, wrap: Wrap) -> i64 {
        match wrap {
            Wrap::Repeat => i.rem_euclid(size),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * size);
                if m < size {
                    m
                } else {
                    2 * size - 1 - m
                }
            }
            Wrap::ClampToEdge => i.clamp(0, size - 1),
        }
    }

    /// The nearest texel of `floor(u · size)`, in `i64`.
    fn nearest_reference(raw: i32, size: u32, wrap: Wrap) -> u32 {
        let i = (raw as i64 * size as i64).div_euclid(1 << 16);
        wrap_reference(i, size as i64, wrap) as u32
    }

    fn axis(size: u32, wrap: Wrap) -> Axis {
        Axis {
            wrap,
            ..Axis::new(size)
        }
    }

    /// Gray8 texture whose texel `(x, y)` is `value(x, y)`.
    fn gray(width: u32, height: u32, value: impl Fn(u32, u32) -> u8) -> Vec<u8> {
        (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| value(x, y))
            .collect()
    }

    /// A distinct grey per texel, so the texel read is identifiable.
    fn id(width: u32) -> impl Fn(u32, u32) -> u8 {
        move |x, y| (y * width + x) as u8
    }

    #[test]
    fn nearest_hand_checked() {
        // (raw u, [repeat, mirrored, clamp]) for a side of 3.
        let three: [(i32, [u32; 3]); 15] = [
            (0, [0, 0, 0]),
            (21_845, [0, 0, 0]), // 0.33333 · 3 = 0.99998
            (21_846, [1, 1, 1]), // 1.00003
            (43_690, [1, 1, 1]),
            (43_691, [2, 2, 2]),
            (65_535, [2, 2, 2]),
            (65_536, [0, 2, 2]), // u = 1: the seam
            (65_536 + 21_846, [1, 1, 2]),
            (131_072, [0, 0, 2]), // u = 2: the mirror's period
            (-1, [2, 0, 0]),
            (-21_846, [1, 1, 0]),
            (-65_536, [0, 2, 0]),
            (-65_537, [2, 2, 0]),
            (i32::MIN, [0, 0, 0]), // u = -32768: -98304 texels
            (i32::MAX, [2, 0, 2]), // 98303.99995: 98303 = 6 · 16383 + 5
        ];
        // A side of 2 (a power of two: the fast path).
        let two: [(i32, [u32; 3]); 11] = [
            (0, [0, 0, 0]),
            (32_767, [0, 0, 0]),
            (32_768, [1, 1, 1]),
            (65_535, [1, 1, 1]),
            (65_536, [0, 1, 1]),
            (98_304, [1, 0, 1]),
            (-1, [1, 0, 0]),
            (-32_768, [1, 0, 0]),
            (-32_769, [0, 1, 0]),
            (i32::MIN, [0, 0, 0]),
            (i32::MAX, [1, 0, 1]),
        ];
        // 5 (odd, not a power of two) and 4.
        let five: [(i32, [u32; 3]); 8] = [
            (13_107, [0, 0, 0]), // 0.199997 · 5 = 0.99998
            (13_108, [1, 1, 1]),
            (52_429, [4, 4, 4]), // 4.00002
            (65_536 + 13_108, [1, 3, 4]),
            (-13_107, [4, 0, 0]),
            (-13_108, [3, 1, 0]),
            (i32::MIN, [0, 0, 0]),
            (i32::MAX, [4, 0, 4]),
        ];
        let four: [(i32, [u32; 3]); 8] = [
            (16_383, [0, 0, 0]),
            (16_384, [1, 1, 1]),
            (49_152, [3, 3, 3]),
            (65_536 + 16_384, [1, 2, 3]),
            (-16_384, [3, 0, 0]),
            (-16_385, [2, 1, 0]),
            (i32::MIN, [0, 0, 0]),
            (i32::MAX, [3, 0, 3]),
        ];
        type Table<'t> = &'t [(i32, [u32; 3])];
        let cases: [(u32, Table); 4] = [(3, &three), (2, &two), (5, &five), (4, &four)];
        for (size, table) in cases {
            for &(raw, expected) in table {
                for (w, &wrap) in WRAPS.iter().enumerate() {
                    assert_eq!(
                        axis(size, wrap).nearest(raw),
                        expected[w],
                        "size {size}, {wrap:?}, raw {raw}"
                    );
                    assert_eq!(nearest_reference(raw, size, wrap), expected[w]);
                }
            }
        }
    }

    #[test]
    fn nearest_samples_the_right_texel() {
        // 5x3 and 4x4 textures: a texel's grey is its index; every texel
        // centre, and the same point one period (or two) away.
        for (w, h) in [(5u32, 3u32), (4, 4), (2, 2), (3, 2)] {
            let data = gray(w, h, id(w));
            let t = Texture::new(w, h, Texels::Gray8(&data)).unwrap();
            for y in 0..h {
                for x in 0..w {
                    let u = ((2 * x + 1) << 16) as i32 / (2 * w) as i32;
                    let v = ((2 * y + 1) << 16) as i32 / (2 * h) as i32;
                    let g = (y * w + x) as u8;
                    assert_eq!(t.sample(fx(u), fx(v)), [g, g, g]);
                    assert_eq!(t.sample(fx(u + (1 << 16)), fx(v - (3 << 16))), [g, g, g]);
                    let m = t.wrap(Wrap::MirroredRepeat);
                    assert_eq!(m.sample(fx(u + (2 << 16)), fx(v - (2 << 16))), [g, g, g]);
                    // Mirrored once: the other end of the row and column.
                    let mirrored = ((h - 1 - y) * w + (w - 1 - x)) as u8;
                    let s = m.sample(fx(u + (1 << 16)), fx(v - (1 << 16)));
                    assert_eq!(s, [mirrored; 3]);
                    assert_eq!(t.texel(x, y), [g, g, g]);
                }
            }
        }
    }

    #[test]
    fn wrap_modes_per_axis() {
        let data = gray(3, 2, id(3));
        let t = Texture::new(3, 2, Texels::Gray8(&data))
            .unwrap()
            .wrap_uv(Wrap::ClampToEdge, Wrap::Repeat);
        assert_eq!(t.wrap_modes(), (Wrap::ClampToEdge, Wrap::Repeat));
        // u = 1.1 clamps to column 2; v = 1.25 repeats to row 0.
        assert_eq!(t.sample(fx(72_090), fx(81_920)), [2; 3]);
        // u = -0.5 clamps to column 0; v = -0.25 repeats to row 1.
        assert_eq!(t.sample(fx(-32_768), fx(-16_384)), [3; 3]);
        let t = t.wrap_uv(Wrap::Repeat, Wrap::MirroredRepeat);
        // u = 1.1 repeats to column 0; v = 1.25 mirrors to row 1.
        assert_eq!(t.sample(fx(72_090), fx(81_920)), [3; 3]);
    }

    #[test]
    fn nearest_fast_path_matches_generic_and_reference() {
        let mut rng = XorShift(0x2545_F491);
        for k in 0..=15 {
            let size = 1u32 << k;
            for wrap in WRAPS {
                let fast = axis(size, wrap);
                assert!(fast.pow2);
                let generic = Axis {
                    pow2: false,
                    ..fast
                };
                let raws = (0..2_000).map(|_| rng.coordinate()).chain(SPECIAL);
                for raw in raws.collect::<Vec<_>>() {
                    let expected = nearest_reference(raw, size, wrap);
                    assert_eq!(fast.nearest(raw), expected, "2^{k} {wrap:?} {raw}");
                    assert_eq!(generic.nearest(raw), expected, "2^{k} {wrap:?} {raw}");
                    assert_eq!(fast.taps(raw), generic.taps(raw), "2^{k} {wrap:?} {raw}");
                }
            }
        }
    }

    #[test]
    fn nearest_any_size_matches_reference() {
        let mut rng = XorShift(0x9E37_79B9);
        let sizes = [1u32, 3, 5, 6, 7, 100, 255, 1000, 4095, 32_767, MAX_SIDE];
        for size in sizes {
            for wrap in WRAPS {
                let a = axis(size, wrap);
                for _ in 0..3_000 {
                    let raw = rng.coordinate();
                    assert_eq!(a.nearest(raw), nearest_reference(raw, size, wrap));
                }
                for raw in SPECIAL {
                    assert_eq!(a.nearest(raw), nearest_reference(raw, size, wrap));
                }
            }
        }
    }

    /// The bilinear taps in `i64`: `(i0, i1, fraction of s in 16 bits)`.
    fn taps_reference(raw: i32, size: u32, wrap: Wrap) -> (u32, u32, u32) {
        let s = raw as i64 * size as i64 - (1 << 15);
        let i0 = s.div_euclid(1 << 16);
        let n = size as i64;
        (
            wrap_reference(i0, n, wrap) as u32,
            wrap_reference(i0 + 1, n, wrap) as u32,
            s.rem_euclid(1 << 16) as u32,
        )
    }

    #[test]
    fn bilinear_taps_match_reference() {
        let mut rng = XorShift(0xDEAD_BEEF);
        let sizes = [1u32, 2, 3, 4, 5, 7, 8, 64, 100, 1024, 32_767, MAX_SIDE];
        for size in sizes {
            for wrap in WRAPS {
                let a = axis(size, wrap);
                let raws: Vec<i32> = (0..3_000)
                    .map(|_| rng.coordinate())
                    .chain(SPECIAL)
                    .collect();
                for raw in raws {
                    let (r0, r1, rf) = taps_reference(raw, size, wrap);
                    let (i0, i1, f) = a.taps(raw);
                    assert_eq!((i0, i1), (r0, r1), "size {size} {wrap:?} raw {raw}");
                    // Clamped coordinates may differ in weight only where
                    // both taps are the same texel.
                    if r0 != r1 {
                        assert_eq!(f, rf >> 4, "size {size} {wrap:?} raw {raw}");
                    }
                }
            }
        }
    }

    /// Bilinear in `f64` with exact weights, before rounding.
    fn bilinear_reference(t: &Texture, data: &[u8], raw_u: i32, raw_v: i32) -> f64 {
        let axis = |raw: i32, size: u32, wrap: Wrap| {
            let s = raw as f64 / 65_536.0 * size as f64 - 0.5;
            let i0 = s.floor();
            let n = size as i64;
            (
                wrap_reference(i0 as i64, n, wrap) as usize,
                wrap_reference(i0 as i64 + 1, n, wrap) as usize,
                s - i0,
            )
        };
        let (wu, wv) = t.wrap_modes();
        let (x0, x1, a) = axis(raw_u, t.width(), wu);
        let (y0, y1, b) = axis(raw_v, t.height(), wv);
        let w = t.width() as usize;
        let c = |x: usize, y: usize| data[y * w + x] as f64;
        (1.0 - a) * (1.0 - b) * c(x0, y0)
            + a * (1.0 - b) * c(x1, y0)
            + (1.0 - a) * b * c(x0, y1)
            + a * b * c(x1, y1)
    }

    #[test]
    fn bilinear_matches_f64_within_tolerance() {
        let mut rng = XorShift(0x1234_5678);
        let noise: Vec<u8> = (0..64).map(|_| rng.next() as u8).collect();
        for (w, h) in [(2u32, 2u32), (3, 2), (4, 4), (5, 3), (1, 7), (8, 8)] {
            // Extremes side by side make the steepest blends.
            let data: Vec<u8> = (0..w * h)
                .map(|i| {
                    if i % 3 == 0 {
                        noise[i as usize]
                    } else {
                        255 * (i as u8 & 1)
                    }
                })
                .collect();
            for wu in WRAPS {
                for wv in WRAPS {
                    let t = Texture::new(w, h, Texels::Gray8(&data))
                        .unwrap()
                        .filter(Filter::Bilinear)
                        .wrap_uv(wu, wv);
                    let check = |u: i32, v: i32| {
                        let exact = bilinear_reference(&t, &data, u, v);
                        let got = t.sample(fx(u), fx(v));
                        assert_eq!(got[0], got[1]);
                        assert_eq!(got[0], got[2]);
                        let err = (got[0] as f64 - exact).abs();
                        assert!(
                            err < 0.625,
                            "{w}x{h} {wu:?} {wv:?} ({u}, {v}): {got:?} vs {exact}"
                        );
                    };
                    for _ in 0..2_000 {
                        check(rng.coordinate(), rng.coordinate());
                    }
                    for u in SPECIAL {
                        for v in SPECIAL {
                            check(u, v);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn bilinear_hand_checked() {
        // 2x1: grey 0 then 200.
        static DATA: [u8; 2] = [0, 200];
        let t = Texture::new(2, 1, Texels::Gray8(&DATA))
            .unwrap()
            .filter(Filter::Bilinear);
        // (u raw, [repeat, mirrored, clamp])
        let cases: [(i32, [u8; 3]); 8] = [
            (16_384, [0, 0, 0]),       // centre of texel 0
            (49_152, [200, 200, 200]), // centre of texel 1
            (32_768, [100, 100, 100]), // halfway
            (0, [100, 0, 0]),          // the left edge: seam
            (65_536, [100, 200, 200]), // the right edge: seam
            (8_192, [50, 0, 0]),       // s = -0.25: 3/4 of texel -1
            (-16_384, [200, 0, 0]),    // centre of texel -1
            (i32::MIN, [100, 0, 0]),   // u = -32768: an edge
        ];
        for (raw, expected) in cases {
            for (k, &wrap) in WRAPS.iter().enumerate() {
                let g = t.wrap(wrap).sample(fx(raw), fx(raw));
                assert_eq!(g, [expected[k]; 3], "{wrap:?} raw {raw}");
            }
        }
        // Halves round up: 0 and 255 halfway is 127.5.
        static EDGE: [u8; 2] = [0, 255];
        let t = Texture::new(2, 1, Texels::Gray8(&EDGE))
            .unwrap()
            .filter(Filter::Bilinear);
        assert_eq!(t.sample(fx(32_768), fx(0)), [128; 3]);
        // One weight step (1/4096) from texel 0's centre: 255 / 4096 < ½.
        assert_eq!(t.sample(fx(16_384 + 8), fx(0)), [0; 3]);
        // 384 units of 2^-16 past it: weight 48/4096 of 255, 2.99, gives 3.
        assert_eq!(t.sample(fx(16_384 + 384), fx(0)), [3; 3]);
    }

    #[test]
    fn bilinear_at_texel_centres_is_nearest() {
        for (w, h) in [(2u32, 2u32), (4, 4), (3, 2), (5, 3), (7, 5)] {
            let data = gray(w, h, |x, y| (x * 71 + y * 113) as u8);
            for wu in WRAPS {
                for wv in WRAPS {
                    let nearest = Texture::new(w, h, Texels::Gray8(&data))
                        .unwrap()
                        .wrap_uv(wu, wv);
                    let bilinear = nearest.filter(Filter::Bilinear);
                    for y in 0..h as i32 {
                        for x in 0..w as i32 {
                            // Centres a period away too (exact only for
                            // powers of two; otherwise the nearest raw
                            // value, less than a weight step away).
                            for period in [-2i64, -1, 0, 1, 3] {
                                let centre = |i: i32, n: u32| {
                                    let c = ((2 * i as i64 + 1 + 2 * period * n as i64) << 16)
                                        as f64
                                        / (2 * n) as f64;
                                    c.round() as i32
                                };
                                let (u, v) = (fx(centre(x, w)), fx(centre(y, h)));
                                assert_eq!(bilinear.sample(u, v), nearest.sample(u, v));
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn formats() {
        // Rgb565: one colour per texel, expanded by bit replication.
        static RGB: [u16; 3] = [0xF800, 0x07E0, 3 << 11 | 7 << 5 | 17];
        let t = Texture::new(3, 1, Texels::Rgb565(&RGB)).unwrap();
        assert_eq!(t.texel(0, 0), [255, 0, 0]);
        assert_eq!(t.texel(1, 0), [0, 255, 0]);
        assert_eq!(t.texel(2, 0), [24, 28, 140]);

        // Gray8.
        static GRAY: [u8; 4] = [0, 1, 128, 255];
        let t = Texture::new(2, 2, Texels::Gray8(&GRAY)).unwrap();
        assert_eq!(t.texel(1, 0), [1; 3]);
        assert_eq!(t.texel(0, 1), [128; 3]);
        assert_eq!(t.texel(1, 1), [255; 3]);

        // Indexed8, with a full palette (no index is checked).
        let palette: Vec<u16> = (0..=255u16).map(|i| i << 8).collect();
        let indices: Vec<u8> = (0..=255u8).collect();
        let t = Texture::new(
            16,
            16,
            Texels::Indexed8 {
                indices: &indices,
                palette: &palette,
            },
        )
        .unwrap();
        assert_eq!(t.texel(3, 2), rgb565_to_rgb888(35 << 8));
        assert_eq!(t.texel(15, 15), rgb565_to_rgb888(255 << 8));

        // Indexed4, odd width 3: stride 2, left texel in the high nibble; a
        // padding nibble past the palette is never read.
        static PALETTE4: [u16; 3] = [0x0000, 0xF800, 0x001F];
        static INDICES4: [u8; 4] = [0x01, 0x2F, 0x21, 0x0F];
        let t = Texture::new(
            3,
            2,
            Texels::Indexed4 {
                indices: &INDICES4,
                palette: &PALETTE4,
            },
        )
        .unwrap();
        let (k, r, b) = ([0, 0, 0], [255, 0, 0], [0, 0, 255]);
        assert_eq!([t.texel(0, 0), t.texel(1, 0), t.texel(2, 0)], [k, r, b]);
        assert_eq!([t.texel(0, 1), t.texel(1, 1), t.texel(2, 1)], [b, r, k]);
        // Out of range clamps to the last column and row.
        assert_eq!(t.texel(7, 9), k);
        assert_eq!(t.texel(u32::MAX, 0), b);
        // The same through sample: u = 5/6 is column 2, v = 3/4 row 1.
        assert_eq!(t.sample(fx(54_613), fx(49_152)), k);
        assert_eq!(t.sample(fx(54_613), fx(16_384)), b);

        // Indexed4 with an even width and a full palette.
        let palette: Vec<u16> = (0..16u16).map(|i| i * 0x1111).collect();
        let indices = [0x01u8, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF];
        let t = Texture::new(
            4,
            4,
            Texels::Indexed4 {
                indices: &indices,
                palette: &palette,
            },
        )
        .unwrap();
        for y in 0..4 {
            for x in 0..4 {
                let i = (y * 4 + x) as u16;
                assert_eq!(t.texel(x, y), rgb565_to_rgb888(i * 0x1111));
            }
        }
    }

    #[test]
    fn rgb565_expansion() {
        for raw in 0..=u16::MAX {
            let [r, g, b] = rgb565_to_rgb888(raw);
            let (r5, g6, b5) = (raw >> 11, (raw >> 5) & 63, raw & 31);
            assert_eq!(r as u16, r5 << 3 | r5 >> 2);
            assert_eq!(g as u16, g6 << 2 | g6 >> 4);
            assert_eq!(b as u16, b5 << 3 | b5 >> 2);
            // Back to Rgb565, rounding to nearest as the importer does:
            // the original bits.
            let quantize = |c: u8, max: u32| (c as u32 * 257 * max + 32_767) / 65_535;
            let back = quantize(r, 31) << 11 | quantize(g, 63) << 5 | quantize(b, 31);
            assert_eq!(back, raw as u32);
        }
    }

    /// What the docs of `rgb565_to_rgb888` say about embedded-graphics.
    #[test]
    fn rgb565_against_embedded_graphics() {
        use embedded_graphics::pixelcolor::raw::RawU16;
        use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
        let (mut red, mut green) = (Vec::new(), Vec::new());
        for raw in 0..=u16::MAX {
            let ours = rgb565_to_rgb888(raw);
            let theirs = Rgb888::from(Rgb565::from(RawU16::new(raw)));
            let theirs = [theirs.r(), theirs.g(), theirs.b()];
            for k in 0..3 {
                assert!(ours[k].abs_diff(theirs[k]) <= 1, "{raw:#06X}");
            }
            if ours[0] != theirs[0] && !red.contains(&(raw >> 11)) {
                red.push(raw >> 11);
            }
            if ours[1] != theirs[1] && !green.contains(&((raw >> 5) & 63)) {
                green.push((raw >> 5) & 63);
            }
        }
        red.sort();
        green.sort();
        assert_eq!(red, [3, 7, 24, 28]);
        assert_eq!(green, [11, 12, 13, 14, 15, 48, 49, 50, 51, 52]);
        // Blue differs at exactly the red levels.
        for b5 in 0..32u16 {
            let theirs = Rgb888::from(Rgb565::from(RawU16::new(b5))).b();
            assert_eq!(rgb565_to_rgb888(b5)[2] != theirs, red.contains(&b5));
        }
    }

    #[test]
    fn largest_sizes_any_coordinate() {
        // Sides of 2^15 and 2^15 - 1 with the extreme coordinates: no
        // overflow (this runs with overflow checks in debug builds), and
        // the texel and the blend the references give.
        let mut rng = XorShift(0x0BAD_F00D);
        for (w, h) in [
            (MAX_SIDE, 2u32),
            (2, MAX_SIDE),
            (MAX_SIDE - 1, 3),
            (3, MAX_SIDE - 1),
        ] {
            let data: Vec<u8> = (0..w * h).map(|_| rng.next() as u8).collect();
            let packed: Vec<u8> = (0..h * w.div_ceil(2)).map(|_| rng.next() as u8).collect();
            let palette: Vec<u16> = (0..16).map(|_| rng.next() as u16).collect();
            let indexed = Texture::new(
                w,
                h,
                Texels::Indexed4 {
                    indices: &packed,
                    palette: &palette,
                },
            )
            .unwrap();
            for wrap in WRAPS {
                let t = Texture::new(w, h, Texels::Gray8(&data)).unwrap().wrap(wrap);
                let smooth = t.filter(Filter::Bilinear);
                let raws: Vec<i32> = SPECIAL
                    .into_iter()
                    .chain((0..40).map(|_| rng.coordinate()))
                    .collect();
                for &u in &raws {
                    for &v in &raws {
                        let x = nearest_reference(u, w, wrap);
                        let y = nearest_reference(v, h, wrap);
                        assert_eq!(t.sample(fx(u), fx(v)), [data[(y * w + x) as usize]; 3]);
                        let exact = bilinear_reference(&smooth, &data, u, v);
                        let got = smooth.sample(fx(u), fx(v))[0] as f64;
                        assert!((got - exact).abs() < 0.625, "{w}x{h} {wrap:?} ({u}, {v})");
                        let i = indexed.wrap(wrap);
                        assert_eq!(i.sample(fx(u), fx(v)), i.texel(x, y));
                        let _ = i.filter(Filter::Bilinear).sample(fx(u), fx(v));
                    }
                }
            }
        }
    }

    #[test]
    fn error_messages() {
        use std::string::ToString;
        let cases = [
            (
                TextureError::ZeroSize {
                    width: 0,
                    height: 4,
                },
                "texture size 0x4 has no texels",
            ),
            (
                TextureError::TooLarge {
                    width: 40_000,
                    height: 4,
                },
                "texture size 40000x4 exceeds the limit of 32768 texels per side",
            ),
            (
                TextureError::LengthMismatch {
                    expected: 8,
                    actual: 6,
                },
                "texel slice has 6 elements, but the size needs 8 (stride x height)",
            ),
            (
                TextureError::PaletteSize { len: 17, max: 16 },
                "palette has 17 colours, but the format needs 1 to 16",
            ),
            (
                TextureError::IndexOutOfRange {
                    x: 1,
                    y: 2,
                    index: 9,
                    palette_len: 4,
                },
                "texel (1, 2) has palette index 9, but the palette has 4 colours",
            ),
        ];
        for (error, text) in cases {
            assert_eq!(error.to_string(), text);
        }
    }

    #[test]
    fn errors() {
        static G: [u8; 6] = [0; 6];
        static C: [u16; 6] = [0; 6];
        let gray = Texels::Gray8(&G);
        assert_eq!(
            Texture::new(0, 3, gray).unwrap_err(),
            TextureError::ZeroSize {
                width: 0,
                height: 3
            }
        );
        assert_eq!(
            Texture::new(3, 0, gray).unwrap_err(),
            TextureError::ZeroSize {
                width: 3,
                height: 0
            }
        );
        assert_eq!(
            Texture::new(MAX_SIDE + 1, 1, gray).unwrap_err(),
            TextureError::TooLarge {
                width: MAX_SIDE + 1,
                height: 1
            }
        );
        assert_eq!(
            Texture::new(1, u32::MAX, gray).unwrap_err(),
            TextureError::TooLarge {
                width: 1,
                height: u32::MAX
            }
        );
        assert_eq!(
            Texture::new(2, 2, gray).unwrap_err(),
            TextureError::LengthMismatch {
                expected: 4,
                actual: 6
            }
        );
        assert_eq!(
            Texture::new(7, 1, Texels::Rgb565(&C)).unwrap_err(),
            TextureError::LengthMismatch {
                expected: 7,
                actual: 6
            }
        );
        assert!(Texture::new(3, 2, Texels::Rgb565(&C)).is_ok());
        // Indexed4 needs (width + 1) / 2 bytes per row: 3x2 needs 4.
        static P: [u16; 2] = [0, 0xFFFF];
        let indexed4 = |i: &'static [u8], p: &'static [u16]| Texels::Indexed4 {
            indices: i,
            palette: p,
        };
        assert_eq!(
            Texture::new(3, 2, indexed4(&G, &P)).unwrap_err(),
            TextureError::LengthMismatch {
                expected: 4,
                actual: 6
            }
        );
        assert!(Texture::new(3, 3, indexed4(&G, &P)).is_ok());
        assert!(Texture::new(4, 3, indexed4(&G, &P)).is_ok());
        // Palette sizes.
        assert_eq!(
            Texture::new(3, 3, indexed4(&G, &[])).unwrap_err(),
            TextureError::PaletteSize { len: 0, max: 16 }
        );
        static P17: [u16; 17] = [0; 17];
        assert_eq!(
            Texture::new(3, 3, indexed4(&G, &P17)).unwrap_err(),
            TextureError::PaletteSize { len: 17, max: 16 }
        );
        let indexed8 = |i: &'static [u8], p: &'static [u16]| Texels::Indexed8 {
            indices: i,
            palette: p,
        };
        assert_eq!(
            Texture::new(3, 2, indexed8(&G, &[])).unwrap_err(),
            TextureError::PaletteSize { len: 0, max: 256 }
        );
        static P257: [u16; 257] = [0; 257];
        assert_eq!(
            Texture::new(3, 2, indexed8(&G, &P257)).unwrap_err(),
            TextureError::PaletteSize { len: 257, max: 256 }
        );
        // Indices past the palette: the first in row order.
        static I8: [u8; 6] = [0, 1, 1, 0, 5, 2];
        assert_eq!(
            Texture::new(3, 2, indexed8(&I8, &P)).unwrap_err(),
            TextureError::IndexOutOfRange {
                x: 1,
                y: 1,
                index: 5,
                palette_len: 2
            }
        );
        static P6: [u16; 6] = [0; 6];
        assert!(Texture::new(3, 2, indexed8(&I8, &P6)).is_ok());
        // Indexed4: padding nibbles (here 0xF) are not checked, and the
        // low nibble of a byte is the right texel.
        static I4: [u8; 4] = [0x10, 0x1F, 0x01, 0x1F];
        assert!(Texture::new(3, 2, indexed4(&I4, &P)).is_ok());
        static I4B: [u8; 4] = [0x10, 0x0F, 0x03, 0x0F];
        assert_eq!(
            Texture::new(3, 2, indexed4(&I4B, &P)).unwrap_err(),
            TextureError::IndexOutOfRange {
                x: 1,
                y: 1,
                index: 3,
                palette_len: 2
            }
        );
    }
}
