//! Sampling decided once per span: the texture's format, filter and wrap
//! modes are matched before a span's loop rather than at every pixel, and
//! the common case (an `Rgb565` texture of power-of-two sides repeated on
//! both axes) gets a loop of its own, addressed with shifts and masks and
//! its texels read in place; every other texture goes through
//! [`Texture::sample`]. Both give the same colour at every coordinate.

use super::{rgb565_to_rgb888, Filter, Kind, Texels, Texture, HALF, WEIGHT_BITS};
#[cfg(microraster_armv7m)]
use crate::shade::lit565_bits;
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
    /// Whether [`from_rgb565`](Self::from_rgb565) is the texel's bits as
    /// they are, as for the `Rgb565` targets (`Rgb565`, `Rgb565Be`): the
    /// built-in shaders may then light an `Rgb565` texel in those bits
    /// themselves and pass the lit bits to `from_rgb565`, which must then
    /// equal [`from_lit_rgb565`](Self::from_lit_rgb565). `false` unless a
    /// type says otherwise.
    const RGB565_BITS: bool = false;
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

    /// The colour of an `Rgb565` texel with bits `raw` lit by `light`
    /// (as [`TexturedLit`](crate::shader::TexturedLit) modulates it): must
    /// equal [`from_rgb888`](Self::from_rgb888) of its `Rgb888` expansion
    /// times `light / 255` per channel, rounded
    /// ([`mul255`](crate::shader::mul255)), which the default returns.
    #[inline(always)]
    fn from_lit_rgb565(raw: u16, light: [u8; 3]) -> Self {
        Self::from_rgb888(crate::shader::modulate(rgb565_to_rgb888(raw), light))
    }
}

/// An `Rgb565` channel's 8-bit expansion ([`rgb565_to_rgb888`]) times
/// 257: at `c` for a 5-bit channel `c`, at `32 + c` for a 6-bit one.
pub(crate) const fn expanded257() -> [u16; 96] {
    let mut t = [0; 96];
    let mut c = 0;
    while c < 64 {
        if c < 32 {
            t[c] = ((c << 3 | c >> 2) * 257) as u16;
        }
        t[32 + c] = ((c << 2 | c >> 4) * 257) as u16;
        c += 1;
    }
    t
}

/// [`expanded257`]: a channel's expansion and its factor 257 in one load
/// (three instructions less per channel on the Cortex-M3 than the
/// expansion's shifts and the product's rounding steps). On ARMv7-M the
/// same table sits after the colour conversion's (`shade::convert`'s
/// `TABLES`), read there instead.
#[cfg(not(any(microraster_armv7m, target_pointer_width = "64")))]
static EXPANDED257: [u16; 96] = expanded257();

/// A lit channel of an `Rgb565` texel: entry `i` of `e257` (an
/// [`expanded257`] table: `i` is a 5-bit channel, or 32 plus a 6-bit
/// one) times the light `l`, rounded by `mul255`'s identity (see
/// `lit565_bits`); 0 for an index beyond the table, which a texel's
/// channels never give.
#[cfg(not(target_pointer_width = "64"))]
#[inline(always)]
pub(crate) fn lit_channel(e257: &[u16; 96], i: usize, l: u8) -> u8 {
    // At most 65,535 · 255 + 32,896 < 2^24: no overflow.
    match e257.get(i) {
        Some(&e) => ((e as u32 * l as u32 + 32_896) >> 16) as u8,
        None => 0,
    }
}

/// [`FromTexel::from_lit_rgb565`]'s bits for the `Rgb565` targets: each
/// channel's product by [`mul255`](crate::shader::mul255)'s identity
/// `round(p / 255) = ((p + 128) · 257) >> 16` (for `p <= 255 · 255`),
/// the expanded channel times 257 read from [`EXPANDED257`], so a
/// channel is a load, one multiply-add and a shift, then the table's
/// conversion to 5 or 6 bits, as `from_rgb888` takes it.
#[cfg(not(any(microraster_armv7m, target_pointer_width = "64")))]
#[inline(always)]
fn lit565_bits(raw: u16, light: [u8; 3]) -> u16 {
    let raw = raw as usize;
    let m = |i: usize, l: u8| lit_channel(&EXPANDED257, i, l);
    crate::shade::rgb565_bits(
        m(raw >> 11, light[0]),
        m(32 + (raw >> 5 & 0x3F), light[1]),
        m(raw & 0x1F, light[2]),
    )
}

/// Where an `Rgb565` texel's channel sits in a row of [`LIT565`]: red
/// at its 5 bits, blue at 32 plus its 5 bits, green at 64 plus its 6
/// bits, so that a row's index is the channel or'ed with a constant.
#[cfg(target_pointer_width = "64")]
const LIT_BLUE: usize = 32;
/// See [`LIT_BLUE`].
#[cfg(target_pointer_width = "64")]
const LIT_GREEN: usize = 64;

/// `lit565_bits`' table on 64-bit hosts: at `l · 128 + slot` (a
/// channel's slot as [`LIT_BLUE`] says, `l` the light), that channel lit
/// by `l` as the default rounds it ([`mul255`](crate::shader::mul255) of
/// its 8-bit expansion), converted to 5 or 6 bits as `Rgb565::from`
/// rounds it and put in its place in the 16 bits. A lit channel is then
/// one load, where the product, its rounding and the conversion's load
/// took about eight instructions (64 KiB, which a host does not miss).
#[cfg(target_pointer_width = "64")]
static LIT565: [u16; 256 * 128] = {
    let e = expanded257();
    let mut t = [0u16; 256 * 128];
    let mut l = 0;
    while l < 256 {
        let mut c = 0;
        while c < 64 {
            // `lit_channel`'s product and rounding, then `Rgb565`'s
            // rounding of a channel (`round(v · max / 255)` in 8.24).
            if c < 32 {
                let v = lit_to(lit_of(e[c], l), 31);
                t[l * 128 + c] = v << 11;
                t[l * 128 + LIT_BLUE + c] = v;
            }
            t[l * 128 + LIT_GREEN + c] = lit_to(lit_of(e[32 + c], l), 63) << 5;
            c += 1;
        }
        l += 1;
    }
    t
};

/// An expanded channel times 257 (`e`) lit by `l`: `lit_channel`'s
/// product and rounding.
#[cfg(target_pointer_width = "64")]
const fn lit_of(e: u16, l: usize) -> u32 {
    (e as u32 * l as u32 + 32_896) >> 16
}

/// 8-bit channel `v` to `0..=max` as `Rgb565::from` rounds it
/// (`round(v · max / 255)` in 8.24 fixed point).
#[cfg(target_pointer_width = "64")]
const fn lit_to(v: u32, max: u32) -> u16 {
    ((v * ((max << 24) / 255) + (1 << 23)) >> 24) as u16
}

/// [`FromTexel::from_lit_rgb565`]'s bits for the `Rgb565` targets on a
/// 64-bit host: three loads from [`LIT565`], or'ed.
#[cfg(target_pointer_width = "64")]
#[inline(always)]
fn lit565_bits(raw: u16, light: [u8; 3]) -> u16 {
    let raw = raw as usize;
    let t = &LIT565;
    // `l << 7` and a slot below 128: within the table, so no check.
    let at = |l: u8, slot: usize| t[(l as usize) << 7 | slot];
    at(light[0], raw >> 11)
        | at(light[1], LIT_GREEN | (raw >> 5 & 0x3F))
        | at(light[2], LIT_BLUE | (raw & 0x1F))
}

impl FromTexel for Rgb565 {
    const RGB565_BITS: bool = true;
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

    /// Each channel expanded and multiplied by the light in one step and
    /// rounded as the default does, then put in place by the 512-byte
    /// table (the crate's `lit565_bits`), without the `Rgb888` round trip.
    #[inline(always)]
    fn from_lit_rgb565(raw: u16, light: [u8; 3]) -> Self {
        Rgb565::from(RawU16::new(lit565_bits(raw, light)))
    }
}

impl FromTexel for crate::sink::Rgb565Be {
    const RGB565_BITS: bool = true;
    #[inline(always)]
    fn from_rgb565(raw: u16) -> Self {
        Self::from(RawU16::new(raw))
    }

    /// As `Rgb565`'s.
    #[inline(always)]
    fn from_rgb888([r, g, b]: [u8; 3]) -> Self {
        Self::from(RawU16::new(crate::shade::rgb565_bits(r, g, b)))
    }

    /// As `Rgb565`'s.
    #[inline(always)]
    fn from_lit_rgb565(raw: u16, light: [u8; 3]) -> Self {
        Self::from(RawU16::new(lit565_bits(raw, light)))
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
    /// Nearest, `Rgb565` texels, power-of-two sides, [`Wrap::Repeat`](super::Wrap::Repeat) on
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
    /// For [`nearest_fine`](Self::nearest_fine): `32 - log2` of the
    /// width, `32 - log2` of both sides, and `(height - 1) << log2(width)`.
    fine: [u32; 3],
    /// On 64-bit hosts, the texel count less one: `texels` is cut to the
    /// count, so an index masked by it needs no check
    /// ([`nearest_fine`](Self::nearest_fine)).
    #[cfg(target_pointer_width = "64")]
    last: usize,
}

impl<'t> Texture<'t> {
    /// How a span should sample this texture.
    #[inline(always)]
    pub fn sampler(&'t self) -> Sampler<'t> {
        // The kind was decided when the texture was built or its modes
        // set (`Texture::decided`): one test here rather than the
        // sides', wrap modes', filter's and format's at every pair.
        match self.texels {
            Texels::Rgb565(texels) if self.kind != Kind::General => {
                let log2 = [self.u.log2 as u32, self.v.log2 as u32];
                // Sides of at most 2^15: the count fits `u32`, and
                // `Texture::new` checked that the texels hold it (were
                // they short, the general path would take them).
                #[cfg(target_pointer_width = "64")]
                let last = ((1u32 << (log2[0] + log2[1])) - 1) as usize;
                #[cfg(target_pointer_width = "64")]
                let Some(texels) = texels.get(..=last) else {
                    return Sampler::General(self);
                };
                let p = Pow2Rgb565 {
                    texels,
                    #[cfg(target_pointer_width = "64")]
                    last,
                    shift: [self.u.shift as u32, self.v.shift as u32],
                    log2,
                    mask: [self.u.size - 1, self.v.size - 1],
                    // Sides of at most 2^15: the shifts are below 32 for
                    // a width of 2 or more (and unused otherwise).
                    fine: [
                        32 - log2[0],
                        32u32.saturating_sub(log2[0] + log2[1]),
                        (self.v.size - 1) << log2[0],
                    ],
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

    /// [`nearest`](Self::nearest) from the coordinates' fractions to 32
    /// bits (`fu`, `fv`; see [`Interpolated`](crate::shader::span::Interpolated)'s
    /// `fine`), for a width of two texels or more: `x`, the raw `u`'s
    /// bits `shift..16`, are `fu`'s top `log2` bits, and `y`, with the
    /// row's `log2(width)` below it, `fv`'s top `log2(width) + log2(height)`
    /// bits masked; no sign or mask for `x`, one shift for both of `y`'s.
    #[inline(always)]
    pub(crate) fn nearest_fine(&self, fu: u32, fv: u32) -> u16 {
        let x = fu >> self.fine[0];
        let y = (fv >> self.fine[1]) & self.fine[2];
        // Below the count already: on a 64-bit host the mask changes
        // nothing but shows the index within the texels (cut to the
        // count), so the read needs no check, and the loops' registers
        // went further (x86-64 `knot1k-textured-lit` -3.6 %). The
        // Cortex-M cores lost with it (`demo-textured-lit` M3 +1.4 %,
        // M4F +0.5 %, ARMv6-M +0.4 %).
        #[cfg(target_pointer_width = "64")]
        return self.texels[(y | x) as usize & self.last];
        #[cfg(not(target_pointer_width = "64"))]
        match self.texels.get((y | x) as usize) {
            Some(&c) => c,
            None => 0,
        }
    }

    /// What a span loop that addresses the texture itself
    /// (`SpanInput::run_nearest`) needs for
    /// [`nearest_fine`](Self::nearest_fine)'s texel: the texels, the
    /// width, the height and the texel count less one (sides of at most
    /// 2^15); `None` if the slice were shorter than the count, which
    /// `Texture::new` rules out. On ARMv6-M (no 32x32 to 64-bit
    /// multiply, by which the loop takes the top bits) the shifts of
    /// `nearest_fine` (`fine[0]`, `fine[1]`) in place of the width and
    /// height.
    #[inline(always)]
    pub(crate) fn fine_parts(&self) -> Option<(&[u16], [u32; 3])> {
        let count = 1u32 << (self.log2[0] + self.log2[1]);
        let sides = if cfg!(microraster_narrow_multiply) {
            [self.fine[0], self.fine[1]]
        } else {
            [1 << self.log2[0], 1 << self.log2[1]]
        };
        (self.texels.len() >= count as usize)
            .then_some((self.texels, [sides[0], sides[1], count - 1]))
    }

    /// [`bilinear_reusing`](Self::bilinear_reusing) from the coordinates'
    /// fractions to 32 bits: its taps and weights read only the raw
    /// coordinates' low 16 bits, which are the fractions' top 16.
    #[inline(always)]
    pub(crate) fn bilinear_fine(&self, fu: u32, fv: u32, quad: &mut Quad) -> [u8; 3] {
        self.bilinear_reusing((fu >> 16) as i32, (fv >> 16) as i32, quad)
    }

    /// The bilinear sample at `(u, v)`: the same taps, weights and blend
    /// as [`Texture::sample`], the four reads inlined.
    #[inline(always)]
    pub fn bilinear(&self, u: i32, v: i32) -> [u8; 3] {
        let mut quad = Quad::NONE;
        self.bilinear_reusing(u, v, &mut quad)
    }

    /// This sampler with its texels cut to their count in the caller: a
    /// loop that reads them by [`bilinear_packed`](Self::bilinear_packed)
    /// then knows their number and reads them with no check. `None` if
    /// the slice were shorter, which `Texture::new` rules out.
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub(crate) fn cut(&self) -> Option<Self> {
        Some(Self {
            texels: self.texels.get(..=self.last)?,
            ..*self
        })
    }

    /// [`at`](Self::at) with the index masked by the count, which changes
    /// nothing but lets a caller that has [`cut`](Self::cut) the texels
    /// read them unchecked (64-bit hosts).
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub(super) fn at_cut(&self, x: u32, y: u32) -> u16 {
        let i = ((y << self.log2[0]) | x) as usize & self.last;
        self.texels.get(i).copied().unwrap_or(0)
    }

    /// The taps of the bilinear sample at `(u, v)` (raw 16.16): the
    /// columns and rows of the four texels, the weights' fractions (12
    /// bits) and the top left texel's index.
    #[inline(always)]
    pub(super) fn taps(&self, u: i32, v: i32) -> Taps {
        let taps = |raw: i32, axis: usize| {
            let s = ((raw as u32) << self.log2[axis]).wrapping_add(HALF);
            let j = s >> 16;
            let m = self.mask[axis];
            (
                [j.wrapping_sub(1) & m, j & m],
                (s & 0xFFFF) >> (16 - WEIGHT_BITS),
            )
        };
        let (x, fx) = taps(u, 0);
        let (y, fy) = taps(v, 1);
        // `(x0, y0)` decides the other three, and is below the texel
        // count, so below `Quad::NONE`'s.
        let at = (y[0] << self.log2[0]) | x[0];
        Taps {
            x,
            y,
            f: [fx, fy],
            at,
        }
    }

    /// [`bilinear`](Self::bilinear), reading the four texels only if they
    /// are not those of `quad`, and leaving them there: along a span of a
    /// magnified texture, consecutive pixels mostly fall between the same
    /// four texels, and reading and expanding them again is most of a
    /// sample.
    #[inline(always)]
    pub(crate) fn bilinear_reusing(&self, u: i32, v: i32, quad: &mut Quad) -> [u8; 3] {
        let Taps {
            x,
            y,
            f: [fx, fy],
            at,
        } = self.taps(u, v);
        let ([x0, x1], [y0, y1]) = (x, y);
        if at != quad.at {
            quad.at = at;
            // Written out: `map` over the four was left out of line.
            let texels = [
                expand(self.at(x0, y0)),
                expand(self.at(x1, y0)),
                expand(self.at(x0, y1)),
                expand(self.at(x1, y1)),
            ];
            #[cfg(not(target_pointer_width = "64"))]
            {
                quad.texels = texels;
            }
            #[cfg(target_pointer_width = "64")]
            {
                let [c00, c10, c01, c11] = texels;
                let term = |k: usize| {
                    let [a, b, c, d] = [c00[k], c10[k], c01[k], c11[k]].map(u32::from);
                    blend_terms(a, b, c, d)
                };
                quad.terms = [term(0), term(1), term(2)];
            }
        }
        // On a 64-bit host, the blend of the module docs, `Σ w_ij c_ij +
        // 2^23` with `w00 = (2^12 - fx)(2^12 - fy)`, `w10 = fx (2^12 -
        // fy)`, `w01 = (2^12 - fx) fy` and `w11 = fx fy`, expanded:
        // `2^24 c00 + 2^12 fx (c10 - c00) + 2^12 fy (c01 - c00) + fx fy
        // (c11 - c10 - c01 + c00) + 2^23`, the same integer. The sum is in
        // `0..=255 · 2^24 + 2^23`, below 2^32, so its wrapping `u32` terms
        // (some differences are negative) give it exactly: three products
        // a channel where the four weights took four, and the terms found
        // once per four texels read (x86-64 `fill-bilinear-exact` 168.80
        // -> 162.08 instructions a fragment). The Cortex-M3 lost with it
        // (150.69 -> 163.95): the weights as before there.
        #[cfg(target_pointer_width = "64")]
        {
            let (wx, wy, wxy) = (fx << WEIGHT_BITS, fy << WEIGHT_BITS, fx * fy);
            let blend = |t: [u32; 4]| (blend_sum(t, [wx, wy, wxy]) >> (2 * WEIGHT_BITS)) as u8;
            let t = &quad.terms;
            [blend(t[0]), blend(t[1]), blend(t[2])]
        }
        #[cfg(not(target_pointer_width = "64"))]
        {
            // The four weights of the module docs, each at most 2^24, summing
            // to 2^24: from one product, the others by subtraction.
            let w11 = fx * fy;
            let w10 = (fx << WEIGHT_BITS) - w11;
            let w01 = (fy << WEIGHT_BITS) - w11;
            let w00 = (((1 << WEIGHT_BITS) - fx) << WEIGHT_BITS) - w01;
            // Every partial sum is at most the whole, `255 · 2^24 + 2^23`.
            let mut acc = [1 << (2 * WEIGHT_BITS - 1); 3];
            for (c, w) in quad.texels.iter().zip([w00, w10, w01, w11]) {
                for (a, c) in acc.iter_mut().zip(c) {
                    *a += w * *c as u32;
                }
            }
            acc.map(|a| (a >> (2 * WEIGHT_BITS)) as u8)
        }
    }
}

/// Where a bilinear sample reads ([`Pow2Rgb565::taps`]).
pub(super) struct Taps {
    /// The left and right columns.
    pub(super) x: [u32; 2],
    /// The top and bottom rows.
    pub(super) y: [u32; 2],
    /// The weights' fractions across and down, in `0..2^12`.
    pub(super) f: [u32; 2],
    /// The top left texel's index.
    pub(super) at: u32,
}

/// On a 64-bit host, one channel's terms of the expanded bilinear blend
/// (see [`Pow2Rgb565::bilinear_reusing`]) from its four texels' 8-bit
/// values `a` (top left), `b` (top right), `c` (bottom left) and `d`:
/// `a · 2^24 + 2^23`, `b - a`, `c - a` and `d - b - c + a`, wrapping.
#[cfg(target_pointer_width = "64")]
#[inline(always)]
pub(super) fn blend_terms(a: u32, b: u32, c: u32, d: u32) -> [u32; 4] {
    [
        (a << (2 * WEIGHT_BITS)) + (1 << (2 * WEIGHT_BITS - 1)),
        b.wrapping_sub(a),
        c.wrapping_sub(a),
        d.wrapping_sub(b).wrapping_sub(c).wrapping_add(a),
    ]
}

/// On a 64-bit host, the blend's sum from a channel's
/// [`blend_terms`] and the weights `2^12 fx`, `2^12 fy` and `fx fy`:
/// exact, below 2^32 (see [`Pow2Rgb565::bilinear_reusing`]).
#[cfg(target_pointer_width = "64")]
#[inline(always)]
pub(super) fn blend_sum([c, dx, dy, dxy]: [u32; 4], [wx, wy, wxy]: [u32; 3]) -> u32 {
    c.wrapping_add(wx.wrapping_mul(dx))
        .wrapping_add(wy.wrapping_mul(dy))
        .wrapping_add(wxy.wrapping_mul(dxy))
}

/// [`rgb565_to_rgb888`] for every 5-bit channel value (at `c`) and 6-bit
/// one (at `32 + c`).
static EXPANDED: [u8; 96] = {
    let mut t = [0; 96];
    let mut c = 0;
    while c < 64 {
        let [_, g, b] = rgb565_to_rgb888(c << 5 | c & 31);
        if c < 32 {
            t[c as usize] = b;
        }
        t[32 + c as usize] = g;
        c += 1;
    }
    t
};

/// [`rgb565_to_rgb888`] by [`EXPANDED`]: a load per channel rather than a
/// shift and an or.
#[inline(always)]
pub(super) fn expand(raw: u16) -> [u8; 3] {
    [
        EXPANDED[(raw >> 11) as usize],
        EXPANDED[32 + ((raw >> 5) & 63) as usize],
        EXPANDED[(raw & 31) as usize],
    ]
}

/// The four texels of a bilinear sample, expanded to 8 bits (on a 64-bit
/// host, the blend's terms made from them), and where they were read (the
/// index of the top left one): see [`Pow2Rgb565::bilinear_reusing`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Quad {
    at: u32,
    #[cfg(not(target_pointer_width = "64"))]
    texels: [[u8; 3]; 4],
    /// On a 64-bit host, per channel, from the four texels expanded to
    /// 8 bits: `c00 · 2^24 + 2^23`, `c10 - c00`, `c01 - c00` and `c11 -
    /// c10 - c01 + c00`, in wrapping `u32` (the blend's terms; see
    /// [`Pow2Rgb565::bilinear_reusing`]).
    #[cfg(target_pointer_width = "64")]
    terms: [[u32; 4]; 3],
}

impl Quad {
    /// No texels yet: an index no texture has (a slice of `u16` is
    /// shorter than 2^31 entries).
    pub(crate) const NONE: Quad = Quad {
        at: u32::MAX,
        #[cfg(not(target_pointer_width = "64"))]
        texels: [[0; 3]; 4],
        #[cfg(target_pointer_width = "64")]
        terms: [[0; 4]; 3],
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`lit565_bits`] against the default (`Rgb888`, `mul255`, the
    /// table) for every channel value and light, each channel on its own
    /// (they do not mix).
    #[test]
    fn lit565_is_the_default() {
        for l in 0..=255u8 {
            let light = [l, 255 - l, l ^ 0x5A];
            for t in 0..64u16 {
                let raw = (t >> 1) << 11 | t << 5 | (31 - (t >> 1));
                let [r, g, b] = crate::shader::modulate(rgb565_to_rgb888(raw), light);
                let want = Rgb565::from(Rgb888::new(r, g, b));
                assert_eq!(
                    Rgb565::from_lit_rgb565(raw, light),
                    want,
                    "{raw:04x} {light:?}"
                );
            }
        }
    }

    /// The colour types that say [`FromTexel::RGB565_BITS`] take a
    /// texel's bits as they are, and their lit texel is the lit bits so
    /// taken (what the Cortex-M3's nearest loops build); the others say
    /// no.
    #[test]
    fn rgb565_bits_types_keep_the_bits() {
        use crate::sink::Rgb565Be;
        use embedded_graphics::pixelcolor::IntoStorage;
        const { assert!(Rgb565::RGB565_BITS && Rgb565Be::RGB565_BITS) };
        const { assert!(!Rgb888::RGB565_BITS && !Gray8::RGB565_BITS && !Bgr565::RGB565_BITS) };
        for raw in 0..=u16::MAX {
            assert_eq!(Rgb565::from_rgb565(raw).into_storage(), raw);
            assert_eq!(Rgb565Be::from_rgb565(raw), Rgb565Be::from(RawU16::new(raw)));
        }
        for l in [0u8, 1, 77, 128, 254, 255] {
            let light = [l, 255 - l, l ^ 0x5A];
            for raw in (0..=u16::MAX).step_by(7) {
                let lit = Rgb565::from_lit_rgb565(raw, light).into_storage();
                assert_eq!(
                    Rgb565::from_rgb565(lit),
                    Rgb565::from_lit_rgb565(raw, light)
                );
                assert_eq!(
                    Rgb565Be::from_rgb565(lit),
                    Rgb565Be::from_lit_rgb565(raw, light),
                    "{raw:04x} {light:?}"
                );
            }
        }
    }
}
