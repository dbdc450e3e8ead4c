//! How the nearest-texel loops colour a texel: as it is ([`Unlit`],
//! `Textured`), or modulated by the interpolated colour ([`Lit`],
//! `TexturedLit`), which the loop steps beside its other values.

use crate::shade::LitTables;
use crate::shader::interpolated::byte;
use crate::texture::FromTexel;

/// How a nearest-texel loop (`nearest_span`, `nearest_pixels`) colours a
/// texel, as its caller gives it: as it is ([`Unlit`], `Textured`), or
/// lit ([`Lit`], `TexturedLit`).
pub(super) trait Light {
    /// The light as the loop steps it along its span.
    type Span: SpanLight;
    /// The light's values at the first pixel, as a new value for the
    /// loop to step, and its steps, which the loop reads beside its other
    /// constants. The loop steps the new value, not its argument: a light
    /// of more than two words is passed by reference to the caller's
    /// copy, which LLVM had updated in memory at every pixel where a
    /// compiler barrier is in the loop (`nearest_pixels`: the Cortex-M4F's
    /// `fill-lit-quasi16-facing` 102.68 -> 96.68 instructions a fragment
    /// with a copy, ARMv6-M's 198.45 -> 196.39, the Cortex-M3's 97.26 ->
    /// 97.87, whose build's layout changed with the affine lit loop).
    fn start(&self) -> (Self::Span, <Self::Span as SpanLight>::Steps);
}

/// A [`Light`] started on a span ([`Light::start`]): each pixel's colour
/// of its texel, and the step to the next pixel.
pub(super) trait SpanLight {
    /// What the light steps by at each pixel.
    type Steps;
    /// The pixel's colour of the texel's `Rgb565` bits `raw`.
    fn texel<C: FromTexel>(&self, raw: u16) -> C;
    /// To the next pixel.
    fn step(&mut self, steps: &Self::Steps);
}

/// `Textured`'s texel, in the target's format.
pub(super) struct Unlit;

impl Light for Unlit {
    type Span = Unlit;

    #[inline(always)]
    fn start(&self) -> (Unlit, ()) {
        (Unlit, ())
    }
}

impl SpanLight for Unlit {
    type Steps = ();

    #[inline(always)]
    fn texel<C: FromTexel>(&self, raw: u16) -> C {
        C::from_rgb565(raw)
    }

    #[inline(always)]
    fn step(&mut self, _: &()) {}
}

/// `TexturedLit`'s texel, modulated by the colour `col` (8.16 a channel,
/// rounding bias included), stepped by `dc` a pixel. With `CLAMP`, each
/// channel clamped to a byte as
/// [`Interpolated::rgb`](crate::shader::span::Interpolated::rgb) clamps
/// it (the quasi-perspective loop's samples); without, its bits 16 to 23
/// as they are, for the colour planes' values, which stay in range along
/// a span (`ColourPlanes::start`).
///
/// The steps are declared first but on ARMv7E-M: the fields' order moves
/// the loops' registers. Against the colour first, per fragment: the
/// Cortex-M3's `fill-lit-quasi16-facing` 99.66 -> 96.47, `fill-lit-exact`
/// 83.33 -> 83.39, its `demo-textured-lit-affine` 6,627,064 -> 6,627,234;
/// ARMv6-M's 196.39 -> 193.39, 131.99 -> 130.52 and 13,332,152 ->
/// 13,278,287; x86-64 the same; but the Cortex-M4F's `fill-lit-exact`
/// 90.93 -> 92.33 (the build script's `microraster_armv7em`).
pub(super) struct Lit<const CLAMP: bool> {
    #[cfg(not(microraster_armv7em))]
    dc: [i32; 3],
    col: [i32; 3],
    #[cfg(microraster_armv7em)]
    dc: [i32; 3],
}

impl<const CLAMP: bool> Lit<CLAMP> {
    /// The light of colour `col` (8.16 a channel), stepped by `dc`.
    #[inline(always)]
    pub(super) fn new(col: [i32; 3], dc: [i32; 3]) -> Self {
        Self { col, dc }
    }
}

impl<const CLAMP: bool> Light for Lit<CLAMP> {
    type Span = LitSpan<CLAMP>;

    #[inline(always)]
    fn start(&self) -> (LitSpan<CLAMP>, [i32; 3]) {
        let col = self.col;
        (
            LitSpan {
                col,
                t: LitTables::for_span(),
            },
            self.dc,
        )
    }
}

/// [`Lit`] started on a span: the colour at the pixel, and the tables
/// that light the texel, made for the span ([`LitTables::for_span`]).
pub(super) struct LitSpan<const CLAMP: bool> {
    col: [i32; 3],
    t: LitTables,
}

impl<const CLAMP: bool> SpanLight for LitSpan<CLAMP> {
    type Steps = [i32; 3];

    #[inline(always)]
    fn texel<C: FromTexel>(&self, raw: u16) -> C {
        let light = if CLAMP {
            self.col.map(byte)
        } else {
            self.col.map(|c| (c >> 16) as u8)
        };
        self.t.texel(raw, light)
    }

    #[inline(always)]
    fn step(&mut self, dc: &[i32; 3]) {
        for (c, d) in self.col.iter_mut().zip(dc) {
            *c = c.wrapping_add(*d);
        }
    }
}

/// [`Lit`] without the clamp on a 64-bit host, red and green packed in
/// one `u64` (red in the high word): each channel of the colour planes
/// stays within `0..2^24` at every pixel of a span
/// (`ColourPlanes::start`), so green's stepped lane never borrows from
/// or carries into red's, and the packed sum holds both exactly. Two
/// registers fewer in the loop.
#[cfg(target_pointer_width = "64")]
pub(super) struct LitPacked {
    rg: u64,
    b: u32,
    steps: (u64, u32),
}

#[cfg(target_pointer_width = "64")]
impl LitPacked {
    /// The light of colour `col` (8.16 a channel, each within `0..2^24`
    /// along the span) stepped by `dc`.
    #[inline(always)]
    pub(super) fn new([r, g, b]: [i32; 3], [dr, dg, db]: [i32; 3]) -> Self {
        let pack = |hi: i32, lo: i32| ((hi as i64) << 32).wrapping_add(lo as i64) as u64;
        Self {
            rg: pack(r, g),
            b: b as u32,
            steps: (pack(dr, dg), db as u32),
        }
    }
}

#[cfg(target_pointer_width = "64")]
impl Light for LitPacked {
    type Span = PackedSpan;

    #[inline(always)]
    fn start(&self) -> (PackedSpan, (u64, u32)) {
        let (rg, b) = (self.rg, self.b);
        (PackedSpan { rg, b }, self.steps)
    }
}

/// [`LitPacked`] started on a span: red and green at the pixel in one
/// `u64`, blue in a `u32`.
#[cfg(target_pointer_width = "64")]
pub(super) struct PackedSpan {
    rg: u64,
    b: u32,
}

#[cfg(target_pointer_width = "64")]
impl SpanLight for PackedSpan {
    type Steps = (u64, u32);

    #[inline(always)]
    fn texel<C: FromTexel>(&self, raw: u16) -> C {
        let light = [
            (self.rg >> 48) as u8,
            (self.rg >> 16) as u8,
            (self.b >> 16) as u8,
        ];
        C::from_lit_rgb565(raw, light)
    }

    #[inline(always)]
    fn step(&mut self, &(drg, db): &(u64, u32)) {
        self.rg = self.rg.wrapping_add(drg);
        self.b = self.b.wrapping_add(db);
    }
}
