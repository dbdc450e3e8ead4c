//! A texel in the target's format ([`FromTexel`]): an `Rgb565` texel's
//! bits as they are where the target is `Rgb565`, and a lit texel
//! (`TexturedLit`'s) by tables rather than through `Rgb888`.

use super::rgb565_to_rgb888;
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
/// The default converts through `Rgb888`, as [`Texture::sample`](super::Texture::sample) reads it;
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
pub trait FromTexel: From<Rgb888> + 'static {
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
#[cfg(any(test, not(target_pointer_width = "64")))]
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

/// [`FromTexel`] for a colour type that holds `Rgb565` bits (`Rgb565`
/// and `Rgb565Be`, whose wire order is the sink's concern): built from
/// `RawU16`, the texel's bits as they are.
macro_rules! rgb565_bits_texel {
    ($t:ty) => {
        impl FromTexel for $t {
            /// The bits as they are: `Rgb888`'s rounding conversion of an
            /// expanded channel gives the channel back.
            #[inline(always)]
            fn from_rgb565(raw: u16) -> Self {
                Self::from(RawU16::new(raw))
            }

            /// By the 512-byte table of embedded-graphics' rounding
            /// (`shade::convert`), rather than its three multiplies.
            #[inline(always)]
            fn from_rgb888([r, g, b]: [u8; 3]) -> Self {
                Self::from(RawU16::new(crate::shade::rgb565_bits(r, g, b)))
            }

            /// Each channel expanded and multiplied by the light in one
            /// step and rounded as the default does, then put in place by
            /// the 512-byte table (the crate's `lit565_bits`), without the
            /// `Rgb888` round trip.
            #[inline(always)]
            fn from_lit_rgb565(raw: u16, light: [u8; 3]) -> Self {
                Self::from(RawU16::new(lit565_bits(raw, light)))
            }
        }
    };
}

rgb565_bits_texel!(Rgb565);
rgb565_bits_texel!(crate::sink::Rgb565Be);

impl FromTexel for Rgb888 {}
impl FromTexel for Bgr888 {}
impl FromTexel for Bgr565 {}
impl FromTexel for Rgb555 {}
impl FromTexel for Bgr555 {}
impl FromTexel for Gray8 {}
impl FromTexel for Gray4 {}
impl FromTexel for Gray2 {}
impl FromTexel for BinaryColor {}

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

    /// `Rgb565` and `Rgb565Be` take a texel's bits as they are.
    #[test]
    fn rgb565_types_keep_the_bits() {
        use crate::sink::Rgb565Be;
        use embedded_graphics::pixelcolor::IntoStorage;
        for raw in 0..=u16::MAX {
            assert_eq!(Rgb565::from_rgb565(raw).into_storage(), raw);
            // Its value and its wire bytes, not its own conversion again.
            let be = Rgb565Be::from_rgb565(raw);
            assert_eq!(be.value(), raw);
            assert_eq!(be.to_be_bytes(), raw.to_be_bytes());
        }
    }
}
