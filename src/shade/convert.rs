//! The span loops' colour conversion: `C::from(Rgb888::new(r, g, b))`, by
//! tables for the 16-bit target formats.
//!
//! embedded-graphics converts a channel by rounding `v * MAX / 255` with a
//! multiply, an add and a shift; for `Rgb565` that is three multiplies (and
//! their constants, which the span loops, short of registers, rebuild at
//! every pixel on the Cortex-M3), about 15 of a Gouraud pixel's 31
//! instructions there. One 512-byte table of the same results (5-bit
//! channels in its first half, 6-bit in its second) takes a load per
//! channel instead: one table, so that a span loop keeps one address in
//! a register for all three (two tables had it rebuild two per pixel).
//!
//! The span loops are generic over any colour type; stable Rust has no
//! specialization, so [`rgb`] compares `C`'s [`TypeId`] with the formats it
//! has a table for (a comparison of constants, folded in each
//! monomorphization, so a firmware that draws in `Gray4` neither tests nor
//! links the tables) and hands the result back through a checked
//! downcast, which cannot fail there and falls back to `C::from`
//! anyway. That is why the renderer's colour type must be `'static`.

use crate::sink::Rgb565Be;
use crate::texture::FromTexel;
use core::any::{Any, TypeId};
use embedded_graphics::pixelcolor::{raw::RawU16, Rgb565, Rgb888};

/// embedded-graphics' conversion of a channel `v` of 0 to 255 to 0 to
/// `max` (`convert_channel`): `round(v max / 255)` in 8.24 fixed point.
const fn channel(v: u8, max: u8) -> u8 {
    const SHIFT: u32 = 24;
    ((v as u32 * (((max as u32) << SHIFT) / 255) + (1 << (SHIFT - 1))) >> SHIFT) as u8
}

/// [`channel`] for every `v`: to 5 bits at `v`, to 6 bits at `256 + v`.
const fn table() -> [u8; 512] {
    let mut t = [0; 512];
    let mut v = 0;
    while v < 256 {
        t[v] = channel(v as u8, 31);
        t[256 + v] = channel(v as u8, 63);
        v += 1;
    }
    t
}

/// An entry of [`to565`]: 16 bits where its 6-bit half holds green
/// already in its place (shifted left by 5), which spares a written
/// Gouraud pixel the shift on Thumb-2 (a halfword load with its index
/// shifted costs what a byte load does). Bytes in builds optimised for
/// size (the build script's `microraster_size`), where the 512 bytes of
/// table are worth more than the speed, and on ARMv6-M, whose loops take
/// green from `TO6`.
#[cfg(all(
    any(test, not(target_pointer_width = "64")),
    not(any(microraster_size, microraster_narrow_multiply))
))]
type Entry = u16;
/// See the other `Entry`.
#[cfg(all(
    any(test, not(target_pointer_width = "64")),
    any(microraster_size, microraster_narrow_multiply)
))]
type Entry = u8;

/// How far the 6-bit half of [`to565`] holds green shifted left: 5 with
/// 16-bit entries (its place in the 16 bits), 0 with bytes.
#[cfg(any(test, not(target_pointer_width = "64")))]
const GREEN_SHIFT: u32 = 5 * (core::mem::size_of::<Entry>() as u32 - 1);

/// 8-bit channels to 5 bits, as embedded-graphics rounds them, then to 6
/// bits (shifted by [`GREEN_SHIFT`]): one table, so that the span loops,
/// short of registers on the Cortex-M3, keep one address for both rather
/// than rebuilding two at every pixel.
#[cfg(any(test, not(target_pointer_width = "64")))]
const fn to565() -> [Entry; 512] {
    let t = table();
    let mut p = [0; 512];
    let mut v = 0;
    while v < 256 {
        p[v] = t[v] as Entry;
        // At most 63 << 5: within 16 bits.
        p[256 + v] = (t[256 + v] as Entry) << GREEN_SHIFT;
        v += 1;
    }
    p
}

/// [`TABLES`]: the colour conversion's table and the lit texel's, one
/// after the other.
#[cfg(any(test, not(target_pointer_width = "64")))]
#[repr(C)]
struct Tables {
    /// [`to565`].
    to565: [Entry; 512],
    /// An `Rgb565` channel's 8-bit expansion times 257
    /// (`crate::texture::expanded257`).
    e257: [u16; 96],
}

/// [`to565`] and, after it, `TexturedLit`'s table of expanded channels:
/// one static, so that a lit texel's pixel builds one address (a
/// `MOVW`/`MOVT` pair on Thumb-2, at every pixel of the span loops,
/// short of registers) for both rather than two. The conversion alone
/// reads its first field, at the same address as before.
#[cfg(any(test, not(target_pointer_width = "64")))]
static TABLES: Tables = Tables {
    to565: to565(),
    e257: crate::texture::expanded257(),
};

/// 8-bit channel `v` to 5 bits.
#[cfg(any(test, not(target_pointer_width = "64")))]
#[inline(always)]
// `Entry` is a byte in some builds: not always the same type.
#[allow(clippy::useless_conversion)]
fn to5(v: u8) -> u16 {
    to5_in(&TABLES.to565, v)
}

/// [`to5`] from the table at `t`.
#[cfg(any(test, not(target_pointer_width = "64")))]
#[inline(always)]
// `Entry` is a byte in some builds: not always the same type.
#[allow(clippy::useless_conversion)]
fn to5_in(t: &[Entry; 512], v: u8) -> u16 {
    u16::from(t[v as usize])
}

/// Entry `i` of the 6-bit half of [`to565`] (`256 + v` for channel `v`)
/// in its place in the 16 bits, shifted left by 5.
#[cfg(any(test, not(target_pointer_width = "64")))]
#[inline(always)]
// `Entry` is a byte in some builds: not always the same type.
#[allow(clippy::useless_conversion)]
fn green_placed(t: &[Entry; 512], i: usize) -> u16 {
    u16::from(t[i]) << (5 - GREEN_SHIFT)
}

/// 8-bit channel `v` to 6 bits, shifted left by 5 (its place).
#[cfg(any(test, not(target_pointer_width = "64")))]
#[inline(always)]
fn to6_placed(v: u8) -> u16 {
    #[cfg(microraster_narrow_multiply)]
    {
        (TO6[v as usize] as u16) << 5
    }
    #[cfg(not(microraster_narrow_multiply))]
    {
        green_placed(&TABLES.to565, 256 + v as usize)
    }
}

/// The 6-bit half of [`to565`] as a table of its own on ARMv6-M, whose
/// span loops load its address from the literal pool in one instruction
/// where `TO565 + 256` took an add of 256 built from a hoisted constant.
#[cfg(microraster_narrow_multiply)]
static TO6: [u8; 256] = {
    let t = table();
    let mut h = [0; 256];
    let mut v = 0;
    while v < 256 {
        h[v] = t[256 + v];
        v += 1;
    }
    h
};

/// The 5- and 6-bit channels of [`table`] already in their places in the
/// 16 bits: red at `v`, green at `256 + v`, blue at `512 + v`. On 64-bit hosts, where
/// 1,536 bytes of table cost nothing that matters and a pixel then takes
/// three loads and two `or`s, without the two shifts (x86-64's `demo`
/// -2 instructions a written pixel).
#[cfg(target_pointer_width = "64")]
static TO565_PLACED: [u16; 768] = {
    let t = table();
    let mut p = [0; 768];
    let mut v = 0;
    while v < 256 {
        p[v] = (t[v] as u16) << 11;
        p[256 + v] = (t[256 + v] as u16) << 5;
        p[512 + v] = t[v] as u16;
        v += 1;
    }
    p
};

/// `TexturedLit`'s texel bits for the `Rgb565` targets (the crate's
/// `texture::lit565_bits`): each channel's expansion times 257 read from
/// [`TABLES`]' second field, multiplied by the light and rounded, then
/// converted by its first, both from one address.
#[cfg(microraster_armv7m)]
#[inline(always)]
pub(crate) fn lit565_bits(raw: u16, light: [u8; 3]) -> u16 {
    lit565_bits_in(&TABLES, raw, light)
}

/// Where the nearest-texel loops find a lit `Rgb565` texel's tables: on
/// the Cortex-M3 (ARMv7-M, the build script's `microraster_armv7m`)
/// `TABLES`' address passed through a `black_box` once a span, which the
/// optimiser keeps in a register or reloads in one instruction, where it
/// had rebuilt it by a `MOVW`/`MOVT` pair at each of its three uses a
/// pixel, the loop short of registers: `fill-lit-exact` 85.50 -> 83.48
/// instructions a fragment (single-scene builds). Elsewhere nothing: the
/// Cortex-M4F took 90.93 -> 91.71 with it (its scheduler), ARMv6-M, whose
/// literal pool gives the address in one load, 131.99 -> 134.96.
#[derive(Clone, Copy)]
pub(crate) struct LitTables(#[cfg(microraster_armv7m)] &'static Tables);

impl LitTables {
    /// The tables for a span's loop.
    #[inline(always)]
    pub(crate) fn for_span() -> Self {
        Self(
            #[cfg(microraster_armv7m)]
            core::hint::black_box(&TABLES),
        )
    }

    /// `C::from_lit_rgb565(raw, light)`: on the Cortex-M3 the lit bits
    /// built from these tables where `C` holds `Rgb565` bits.
    #[inline(always)]
    pub(crate) fn texel<C: FromTexel>(self, raw: u16, light: [u8; 3]) -> C {
        #[cfg(microraster_armv7m)]
        {
            lit_texel_in(self.0, raw, light)
        }
        #[cfg(not(microraster_armv7m))]
        {
            C::from_lit_rgb565(raw, light)
        }
    }
}

/// `C::from_lit_rgb565(raw, light)`, the lit bits built from the tables
/// at `t` ([`lit565_bits_in`]) where `C` is `Rgb565` or [`Rgb565Be`]
/// (the type test folds away in each instance): what
/// [`LitTables::texel`] gives on the Cortex-M3, built for the tests too,
/// which hold it to every colour type's own lit texel.
#[cfg(any(test, microraster_armv7m))]
#[inline(always)]
fn lit_texel_in<C: FromTexel>(t: &Tables, raw: u16, light: [u8; 3]) -> C {
    from_bits(|| lit565_bits_in(t, raw, light)).unwrap_or_else(|| C::from_lit_rgb565(raw, light))
}

/// [`lit565_bits`] from the tables at `t` (built for the tests too, which
/// hold it to the host's lit texels).
#[cfg(any(test, microraster_armv7m))]
#[inline(always)]
// `Entry` is a byte in some builds: not always the same type.
#[allow(clippy::useless_conversion)]
fn lit565_bits_in(t: &Tables, raw: u16, light: [u8; 3]) -> u16 {
    let raw = raw as usize;
    let m = |i: usize, l: u8| usize::from(crate::texture::lit_channel(&t.e257, i, l));
    let (r, g, b) = (
        m(raw >> 11, light[0]),
        m(32 + (raw >> 5 & 0x3F), light[1]),
        m(raw & 0x1F, light[2]),
    );
    (u16::from(t.to565[r]) << 11)
        | (u16::from(t.to565[256 + g]) << (5 - GREEN_SHIFT))
        | u16::from(t.to565[b])
}

/// The bits of `Rgb565::from(Rgb888::new(r, g, b))`, by the table.
#[inline(always)]
pub(crate) fn rgb565_bits(r: u8, g: u8, b: u8) -> u16 {
    #[cfg(target_pointer_width = "64")]
    {
        let t = &TO565_PLACED;
        t[r as usize] | t[256 + g as usize] | t[512 + b as usize]
    }
    #[cfg(not(target_pointer_width = "64"))]
    {
        (to5(r) << 11) | to6_placed(g) | to5(b)
    }
}

/// [`rgb`] with red's and blue's table reads first, one address of the
/// 5-bit table for both, then green's (ARMv6-M's Gouraud loop,
/// `gouraud::TOP_BYTE`): the same bits. There the pixel loop's registers
/// then fall better: `demo` 5,935,524 -> 5,906,658 instructions (red and
/// green first, as `rgb565_bits`, 5,935,524; green and blue first
/// 5,989,942).
#[cfg(microraster_narrow_multiply)]
#[inline(always)]
pub(super) fn rgb_red_blue_first<C: From<Rgb888> + 'static>(r: u8, g: u8, b: u8) -> C {
    from_bits(|| {
        let red_blue = (to5(r) << 11) | to5(b);
        red_blue | to6_placed(g)
    })
    .unwrap_or_else(|| C::from(Rgb888::new(r, g, b)))
}

/// `v` as a `C`, when `C` is `T` (a checked downcast).
#[inline(always)]
fn cast<T: 'static, C: 'static>(v: T) -> Option<C> {
    (&mut Some(v) as &mut dyn Any)
        .downcast_mut::<Option<C>>()?
        .take()
}

/// `C::from(Rgb888::new(r, g, b))`, bit for bit, through tables where `C`
/// is `Rgb565` or [`Rgb565Be`] (see the [module docs](self)).
#[inline(always)]
pub(crate) fn rgb<C: From<Rgb888> + 'static>(r: u8, g: u8, b: u8) -> C {
    from_bits(|| rgb565_bits(r, g, b)).unwrap_or_else(|| C::from(Rgb888::new(r, g, b)))
}

/// `C` from `Rgb565` bits where `C` is `Rgb565` or [`Rgb565Be`], `None`
/// otherwise: the type test folds away in each instance, and `bits` runs
/// only where it answers.
#[inline(always)]
fn from_bits<C: 'static>(bits: impl FnOnce() -> u16) -> Option<C> {
    let c = TypeId::of::<C>();
    if c == TypeId::of::<Rgb565>() {
        cast(Rgb565::from(RawU16::new(bits())))
    } else if c == TypeId::of::<Rgb565Be>() {
        cast(Rgb565Be::from(RawU16::new(bits())))
    } else {
        None
    }
}

/// How far [`rgb16_green_up`] takes green up: 256 in its integer part,
/// the offset of the 6-bit half of `TO565`.
pub(crate) const GREEN_UP: u32 = 256 << 16;

/// [`rgb`] of the integer bytes of `r`, `g - GREEN_UP` and `b`, channels
/// in 8.16 fixed point (`(c >> 16) as u8`, as the Gouraud span loops take
/// them), for a green channel `g`
/// within `GREEN_UP..GREEN_UP + 2^24` (8.16 fixed point, 256 added to its
/// integer part): bits 16 to 24 of `g` are then the index of its 6-bit
/// value in `TO565`, taken by one bit-field extract, where the channel's
/// byte took an extract, and an add of 256 to the table's address (a
/// register short of an instruction's offset) at every pixel. The low
/// byte of that integer part is green's byte, so any other colour type
/// converts the same byte.
///
/// It reads the table at `table` (see [`To565`]).
#[inline(always)]
pub(crate) fn rgb16_green_up<C: From<Rgb888> + 'static>(table: To565, r: u32, g: u32, b: u32) -> C {
    #[cfg(any(test, not(target_pointer_width = "64")))]
    {
        let (r, g9, b) = ((r >> 16) as u8, (g >> 16) as usize & 511, (b >> 16) as u8);
        let t = table.0;
        from_bits(|| {
            // The empty `black_box`es (inline assembly of no instruction,
            // as in the Gouraud loop) only part the three lookups for the
            // optimiser: the Cortex-M4F's Gouraud pixel loops then keep a
            // step more in a register (3 instructions fewer a written
            // pixel, `demo` 3,293,360 -> 3,251,382 instructions, `rock`
            // 2,748,045 -> 2,710,189); the Cortex-M3's code is the same.
            let c = to5_in(t, r) << 11;
            core::hint::black_box(());
            let c = c | green_placed(t, g9);
            core::hint::black_box(());
            c | to5_in(t, b)
        })
        .unwrap_or_else(|| C::from(Rgb888::new(r, g9 as u8, b)))
    }
    #[cfg(not(any(test, not(target_pointer_width = "64"))))]
    {
        let _ = table;
        rgb((r >> 16) as u8, (g >> 16) as u8, (b >> 16) as u8)
    }
}

/// Where [`rgb16_green_up`] reads the conversion's table (`TABLES`'
/// first field; nothing on 64-bit hosts, which take [`rgb`]).
#[derive(Clone, Copy)]
pub(crate) struct To565(#[cfg(any(test, not(target_pointer_width = "64")))] &'static [Entry; 512]);

impl To565 {
    /// The table at its address, a constant: the optimiser may build the
    /// address anew wherever it is used, and move the table's loads as
    /// it likes (it knows the table never changes).
    #[inline(always)]
    pub(crate) fn fixed() -> Self {
        Self(
            #[cfg(any(test, not(target_pointer_width = "64")))]
            &TABLES.to565,
        )
    }

    /// The table's address passed through a `black_box` (once a pair):
    /// for the optimiser a value in a register like any other, which it
    /// can no longer rebuild from two instructions at each use, and whose
    /// loads it no longer moves across the empty `black_box`es that part
    /// [`rgb16_green_up`]'s three lookups (they are loads of memory it
    /// does not know to be constant).
    #[inline(always)]
    pub(crate) fn opaque() -> Self {
        Self(
            #[cfg(any(test, not(target_pointer_width = "64")))]
            core::hint::black_box(&TABLES.to565),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics::pixelcolor::{Gray4, IntoStorage, RgbColor};

    /// Every one of the 2^24 colours converts as embedded-graphics
    /// converts it.
    #[test]
    fn tables_match_embedded_graphics() {
        // Each channel on its own first (cheap, and the clearest failure).
        for v in 0..=255u8 {
            let e = Rgb565::from(Rgb888::new(v, v, v));
            assert_eq!(to5(v), e.r() as u16, "{v}");
            assert_eq!(to6_placed(v) >> 5, e.g() as u16, "{v}");
        }
        // Then every colour (about two seconds in a debug build).
        for r in 0..=255u8 {
            for g in 0..=255u8 {
                for b in 0..=255u8 {
                    let e = Rgb565::from(Rgb888::new(r, g, b));
                    assert_eq!(rgb565_bits(r, g, b), e.into_storage(), "{r} {g} {b}");
                    let fast: Rgb565 = rgb(r, g, b);
                    assert_eq!(fast, e, "{r} {g} {b}");
                    let be: Rgb565Be = rgb(r, g, b);
                    assert_eq!(be, Rgb565Be::from(Rgb888::new(r, g, b)), "{r} {g} {b}");
                }
            }
        }
        for r in [0, 255] {
            assert_eq!(rgb::<Rgb565>(r, 255, 255).r(), r >> 3);
        }
    }

    /// The Cortex-M3's lit texels ([`lit_texel_in`], which its nearest
    /// loops reach through [`LitTables`]) are the host's
    /// `from_lit_rgb565`, for every texel and a spread of lights, in the
    /// two formats that take the tables' bits and in others, which do not.
    #[test]
    fn tables_light_texels_as_the_host() {
        use crate::texture::FromTexel;
        use embedded_graphics::pixelcolor::{Bgr565, Gray8};
        fn same<C: FromTexel + PartialEq + core::fmt::Debug>(raw: u16, light: [u8; 3]) {
            assert_eq!(
                lit_texel_in::<C>(&TABLES, raw, light),
                C::from_lit_rgb565(raw, light),
                "{raw:04x} {light:?}"
            );
        }
        for l in [0u8, 1, 2, 77, 127, 128, 200, 254, 255] {
            let light = [l, 255 - l, l ^ 0x5A];
            for raw in 0..=u16::MAX {
                assert_eq!(
                    lit565_bits_in(&TABLES, raw, light),
                    Rgb565::from_lit_rgb565(raw, light).into_storage(),
                    "{raw:04x} {light:?}"
                );
                same::<Rgb565>(raw, light);
                same::<Rgb565Be>(raw, light);
                if raw % 61 == 0 {
                    same::<Rgb888>(raw, light);
                    same::<Bgr565>(raw, light);
                    same::<Gray8>(raw, light);
                }
            }
        }
    }

    /// Other formats take embedded-graphics' conversion itself.
    #[test]
    fn other_formats_convert_as_before() {
        for (r, g, b) in [(0, 0, 0), (255, 255, 255), (12, 200, 99), (254, 1, 128)] {
            let e = Gray4::from(Rgb888::new(r, g, b));
            assert_eq!(rgb::<Gray4>(r, g, b), e);
            assert_eq!(rgb::<Rgb888>(r, g, b), Rgb888::new(r, g, b));
        }
    }

    /// [`rgb16_green_up`] (its table path, which the tests take on every
    /// target) converts the channels' integer bytes as [`rgb`] does, for
    /// every green byte, in every format, whatever the fraction bits.
    #[test]
    fn green_up_converts_the_bytes() {
        for v in 0..=255u32 {
            let (r, b) = (255 - v, (v * 7) & 255);
            for frac in [0, 1, 0x8000, 0xffff] {
                let up = |c: u32| (c << 16) | frac;
                let g = up(v) + GREEN_UP;
                let (r8, g8, b8) = (r as u8, v as u8, b as u8);
                assert_eq!(
                    rgb16_green_up::<Rgb565>(To565::fixed(), up(r), g, up(b)),
                    rgb(r8, g8, b8)
                );
                assert_eq!(
                    rgb16_green_up::<Rgb565Be>(To565::opaque(), up(r), g, up(b)),
                    rgb(r8, g8, b8)
                );
                assert_eq!(
                    rgb16_green_up::<Gray4>(To565::fixed(), up(r), g, up(b)),
                    rgb(r8, g8, b8)
                );
                assert_eq!(
                    rgb16_green_up::<Rgb888>(To565::fixed(), up(r), g, up(b)),
                    rgb(r8, g8, b8)
                );
            }
        }
    }
}
