//! Sampling decided once per span: the texture's format, filter and wrap
//! modes are matched before a span's loop rather than at every pixel, and
//! the common case (an `Rgb565` texture of power-of-two sides repeated on
//! both axes) gets a loop of its own, addressed with shifts and masks and
//! its texels read in place; every other texture goes through
//! [`Texture::sample`]. Both give the same colour at every coordinate.

use super::{rgb565_to_rgb888, Filter, Kind, Texels, Texture, HALF, WEIGHT_BITS};

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
