//! Span shaders: a triangle's run of pixels in one tile row, coloured in
//! one call.
//!
//! The renderer hands [`FragmentShader::shade_span`] a [`SpanInput`]: the
//! span's colour and depth rows, where it lies, the draw's texture, and
//! the interpolation state at its first pixel (depth, the perspective
//! planes `Q`, `B1`, `B2` of [`crate::shader`]'s docs) with its step per
//! pixel. The default `shade_span` runs [`SpanInput::fragments`], which
//! calls [`FragmentShader::fragment`] at every pixel that passes the depth
//! test: since the renderer is generic over the shader, that call is
//! inlined into the loop, and a per-fragment shader pays no call per pixel.
//!
//! A shader that overrides `shade_span` (every built-in does) decides
//! once per span what does not change along it (which texture format,
//! filter and wrap; whether the target can take a texel as it is stored)
//! and hands [`SpanInput::shade`] a per-pixel function specialised for
//! that: the stepping, depth test, perspective division and write stay in
//! the renderer's loop, and only what the shader needs is computed.
//!
//! The renderer hands a shader a triangle's spans in one tile together
//! ([`FragmentShader::shade_spans`], a [`TriangleSpans`]); the default
//! calls `shade_span` for each. The built-in textured shaders override it
//! to decide the texture's kind once per triangle and tile: most spans of
//! a mesh are two or three pixels long, so what is decided per span is
//! paid per few pixels.
//!
//! # The stepping
//!
//! Depth and the planes `Q`, `B1`, `B2` step by one add per pixel. At a
//! *sample* pixel the weights `b1 = B1 / Q`, `b2 = B2 / Q` come from one
//! 32-bit reciprocal ([`Perspective::Exact`]: every pixel), and the
//! varyings and colour from the weights; between samples
//! ([`Perspective::Quasi8`], [`Perspective::Quasi16`]) the varyings and
//! colour step linearly by one add each (Hecker's and Quake's
//! subdivision). The samples are the screen columns `x ≡ 0 (mod N)`,
//! each span's first pixel, and its last unless the column after it is
//! a multiple of `N` (then that column, one pixel beyond the span, is the
//! sample). So where a tile's edge at a multiple of `N` cuts a span, both
//! halves have the samples the whole span has, and the image does not
//! depend on the tile size (for any tile width that is a multiple of 16).
//! [`Perspective::Affine`] takes the weights as `B1`, `B2` themselves (all
//! `1 / w` equal, units of 2^-28) and rounds each varying once after its
//! sum, so that it is exactly linear along a span.

use crate::scene::Blend;
use crate::shade::perspective::{
    colour_constants, PerspectiveSetup, AFFINE, AFFINE_SUMS, CLAMPED, COLOUR_LOOP, FLAT_Q, SHIFTED,
};
use crate::shade::{ColourPlanes, DepthTest};
use crate::shader::{Fragment, FragmentShader, Perspective, Varyings};
use crate::texture::Texture;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};

pub use super::interpolated::Interpolated;
pub use super::triangle_spans::TriangleSpans;
use super::with_planes::WithPlanes;

/// One span of a triangle in a tile row, handed to
/// [`FragmentShader::shade_span`]: the pixels `x()..x() + len()` of row
/// `y()`, and everything needed to colour them.
///
/// A shader colours it with [`shade`](Self::shade) (a function of the
/// interpolated values per pixel) or [`fragments`](Self::fragments) (a
/// function of a [`Fragment`]); either tests depth first, interpolates
/// only for the pixels that pass, and writes colour (blended as the draw
/// says) and depth for those the function does not discard.
#[derive(Debug)]
pub struct SpanInput<'a, C, V> {
    /// Index of the triangle's draw in the scene.
    pub(crate) draw: usize,
    pub(crate) x0: i32,
    pub(crate) y: i32,
    pub(crate) color: &'a mut [C],
    pub(crate) depth: &'a mut [u16],
    pub(crate) texture: Option<&'a Texture<'a>>,
    pub(crate) setup: &'a PerspectiveSetup<V>,
    /// Depth as `z << 2` (see `shade::depth16`) and its step.
    pub(crate) z: u32,
    pub(crate) gz: u32,
    /// `Q`, `B1`, `B2` at the first pixel, and their steps.
    pub(crate) planes: [i32; 3],
    pub(crate) steps: [i32; 3],
    /// An affine triangle's colour planes, where its shader reads the
    /// colour, in the renderer's affine copy alone (`ColourPlanes::start`).
    pub(crate) colour: Option<&'a ColourPlanes<'a>>,
    pub(crate) mode: Perspective,
    pub(crate) blend: Blend,
    pub(crate) test: DepthTest,
    pub(crate) write: bool,
    /// Whether the draw is opaque, with the default depth test and
    /// writes (`Output::opaque`, decided per triangle and tile), and the
    /// triangle's varyings' differences fit `i32`
    /// (`PerspectiveSetup::fits`).
    pub(crate) opaque: bool,
}

impl<'a, C, V: Varyings> SpanInput<'a, C, V> {
    /// Index of the draw in the scene (see [`Fragment::draw`]).
    #[inline(always)]
    pub fn draw(&self) -> usize {
        self.draw
    }

    /// Screen column of the span's first pixel.
    #[inline(always)]
    pub fn x(&self) -> i32 {
        self.x0
    }

    /// Screen row of the span.
    #[inline(always)]
    pub fn y(&self) -> i32 {
        self.y
    }

    /// Number of pixels.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.color.len()
    }

    /// Whether the span has no pixel (never, as the renderer hands them).
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.color.is_empty()
    }

    /// The draw's texture, if it has one.
    #[inline(always)]
    pub fn texture(&self) -> Option<&'a Texture<'a>> {
        self.texture
    }

    /// How the varyings are interpolated along the span: the frame's mode, or
    /// [`Perspective::Affine`] for a draw whose clip-space `w` is the same
    /// at every vertex (see [`Perspective`]).
    #[inline(always)]
    pub fn perspective(&self) -> Perspective {
        self.mode
    }

    /// The provoking vertex's lit colour (what
    /// [`Fragment::color`] holds without colour interpolation).
    #[inline(always)]
    pub fn flat_color(&self) -> [u8; 3] {
        self.setup.flat()
    }

    /// Colours the span through `fragment`, called with the values at
    /// each pixel that passes the depth test (the colour interpolated only
    /// if `interpolate_color`); `None` writes nothing there. Returns the
    /// number of pixels written. (A closure that the compiler leaves out
    /// of line costs a call per pixel: see [`PixelFn`] and
    /// [`shade_with`](Self::shade_with).)
    #[inline(always)]
    pub fn shade(
        self,
        interpolate_color: bool,
        fragment: impl FnMut(&Interpolated<V>) -> Option<C>,
    ) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        self.shade_with(interpolate_color, fragment)
    }

    /// [`shade`](Self::shade) through a [`PixelFn`].
    #[inline(always)]
    pub fn shade_with(self, interpolate_color: bool, fragment: impl PixelFn<V, C>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        // An opaque affine span (of the renderer's affine copy, whose
        // shader reads the colour): the colour planes' colour.
        match WithPlanes::of(&self, interpolate_color, fragment) {
            Ok(planes) => self.shade_plain(false, planes),
            Err(fragment) => self.shade_plain(interpolate_color, fragment),
        }
    }

    /// [`shade_with`](Self::shade_with) for a span without colour planes:
    /// the built-in shaders' spans of every copy of the renderer's
    /// shading function but the affine one (which gives them their own
    /// loops). Where the planes are not known absent at compile time, a
    /// test for them in `shade_with` made a copy of every loop for them
    /// (in the general copy, where ARMv6-M's `demo-textured-lit` took
    /// +7 %, the exact loops' registers).
    #[inline(always)]
    pub(crate) fn shade_plain(self, interpolate_color: bool, fragment: impl PixelFn<V, C>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        self.shade_with_loops::<true>(interpolate_color, fragment, None)
    }

    /// [`shade_with`](Self::shade_with) for a span of
    /// [`FragmentShader::shade_affine_spans`] (an opaque draw, affine), in
    /// the loop that steps the varyings' sums where [`AFFINE_SUMS`] says.
    /// Only in the affine copy, so that the general copy's loops stay as
    /// they are.
    #[inline(always)]
    pub(crate) fn shade_affine(self, interpolate_color: bool, fragment: impl PixelFn<V, C>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        if !(self.opaque && self.mode == Perspective::Affine) {
            return self.shade_plain(interpolate_color, fragment);
        }
        self.run_opaque::<AFFINE_SUMS, false>(interpolate_color, fragment, 0)
    }

    /// [`shade_with`](Self::shade_with) for a span that
    /// [`shifted_opaque`](Self::shifted_opaque) declined (`Textured`'s
    /// nearest spans, whose shifted ones take a loop of their own): without
    /// the loops with the span's shift, which it would never take, and
    /// whose copies beside the others moved their registers (x86-64
    /// `fill-nearest-affine`).
    #[inline(always)]
    pub(crate) fn shade_unshifted(
        self,
        interpolate_color: bool,
        fragment: impl PixelFn<V, C>,
    ) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        self.shade_with_loops::<false>(interpolate_color, fragment, None)
    }

    /// [`shade_with`](Self::shade_with), with the loops with the span's
    /// shift only if `SHIFT`, and the colour loop's constants `k` if the
    /// caller gathered them ([`colour_constants`]).
    #[inline(always)]
    pub(super) fn shade_with_loops<const SHIFT: bool>(
        self,
        interpolate_color: bool,
        fragment: impl PixelFn<V, C>,
        k: Option<&[i32; 13]>,
    ) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        // The common case, an opaque draw with the default depth test and
        // writes, has loops of its own with none of the three decided per
        // pixel (exact mode: spans of `OPAQUE_EXACT_MIN` pixels or more
        // where the weights need no clamp, see `opaque_shift`; shorter
        // ones, most of a mesh's, with `weights` per pixel where the shader
        // has varyings: with none, `Gouraud`, its fill on the Cortex-M3
        // went from 78.0 to 80.9 instructions per fragment).
        let opaque = self.opaque;
        let weighted = V::LEN > 0 || interpolate_color;
        match self.mode {
            // Affine spans in either copy (`fill::shade_custom`): the
            // opaque affine loops kept in the general one too, where
            // without them the exact loops beside took other registers
            // (x86-64 `demo-textured-lit` +2.7 %).
            Perspective::Affine if opaque => {
                self.run_opaque::<AFFINE, false>(interpolate_color, fragment, 0)
            }
            _ if opaque && !weighted => {
                self.run_opaque::<AFFINE, false>(interpolate_color, fragment, 0)
            }
            Perspective::Exact if opaque && self.len() >= OPAQUE_EXACT_MIN && !SHIFT => {
                self.run_put(interpolate_color, fragment)
            }
            Perspective::Exact if opaque && self.len() >= OPAQUE_EXACT_MIN => {
                // A span whose `Q` does not change (its step zero: faces
                // whose `1 / w` is the same along the screen's rows) takes
                // the weights' reciprocal once ([`FLAT_Q`]).
                let flat = self.steps[0] == 0;
                // A shader that interpolates the colour (`TexturedLit`,
                // `Gouraud` where it has no loop of its own) takes the test
                // in `i64` on a 64-bit host, with whether the weights sum
                // to one at most along the span: its colour then needs no
                // clamp (`opaque_shift_convex`; x86-64 `demo-textured-lit`
                // 6,609,446 -> 6,475,226 instructions, `fill-lit-exact`
                // 116.41 -> 103.83 a fragment, `fill-gouraud-exact` 77.71
                // -> 73.80). The Cortex-M cores clamp a channel in one
                // `USAT`.
                #[cfg(target_pointer_width = "64")]
                if interpolate_color && !COLOUR_LOOP {
                    let shift = if V::LEN == 0 {
                        self.opaque_shift_convex::<true>()
                    } else {
                        self.opaque_shift_convex::<false>()
                    };
                    return match shift {
                        Some((sh, true)) if flat => {
                            self.run_opaque::<FLAT_Q, true>(interpolate_color, fragment, sh)
                        }
                        Some((sh, true)) => {
                            self.run_opaque::<SHIFTED, true>(interpolate_color, fragment, sh)
                        }
                        // The few others (16 of the textured frame's
                        // 12,960 pixels) keep the loops with the clamps,
                        // but for a shader without varyings (`Gouraud`),
                        // whose loops' registers their copies moved:
                        // x86-64 `fill-gouraud-exact` 73.80 -> 70.66 a
                        // fragment through the general loop (the textured
                        // frame's loops took +1.2 % without them).
                        Some((sh, false)) if V::LEN > 0 && flat => {
                            self.run_opaque::<FLAT_Q, false>(interpolate_color, fragment, sh)
                        }
                        Some((sh, false)) if V::LEN > 0 => {
                            self.run_opaque::<SHIFTED, false>(interpolate_color, fragment, sh)
                        }
                        _ => self.run_put(interpolate_color, fragment),
                    };
                }
                // The same on ARMv6-M, in `i32`: no `USAT` there, so each
                // channel's clamp is a compare and a branch or two.
                #[cfg(microraster_narrow_multiply)]
                if interpolate_color {
                    let fq = flat && flat_q_loop(V::LEN, interpolate_color);
                    return match self.opaque_shift_convex32() {
                        Some((sh, true)) if fq => {
                            self.run_opaque::<FLAT_Q, true>(interpolate_color, fragment, sh)
                        }
                        Some((sh, true)) => {
                            self.run_opaque::<SHIFTED, true>(interpolate_color, fragment, sh)
                        }
                        Some((sh, false)) if fq => {
                            self.run_opaque::<FLAT_Q, false>(interpolate_color, fragment, sh)
                        }
                        Some((sh, false)) => {
                            self.run_opaque::<SHIFTED, false>(interpolate_color, fragment, sh)
                        }
                        None => self.run_put(interpolate_color, fragment),
                    };
                }
                let shift = self.opaque_shift();
                match shift {
                    Some(sh) if COLOUR_LOOP && V::LEN == 0 && interpolate_color => {
                        let own;
                        let k = match k {
                            Some(k) => k,
                            None => {
                                own = colour_constants(self.setup);
                                &own
                            }
                        };
                        if flat {
                            self.run_colour_shifted::<true>(fragment, sh, k)
                        } else {
                            self.run_colour_shifted::<false>(fragment, sh, k)
                        }
                    }
                    Some(sh) if flat && flat_q_loop(V::LEN, interpolate_color) => {
                        self.run_opaque::<FLAT_Q, false>(interpolate_color, fragment, sh)
                    }
                    Some(sh) => self.run_opaque::<SHIFTED, false>(interpolate_color, fragment, sh),
                    None => self.run_put(interpolate_color, fragment),
                }
            }
            Perspective::Exact if opaque && V::LEN > 0 => {
                self.run_opaque::<CLAMPED, false>(interpolate_color, fragment, 0)
            }
            _ => self.run_put(interpolate_color, fragment),
        }
    }

    /// The span's shift where [`shade_with`](Self::shade_with) would take
    /// the opaque exact loop with the span's shift (an opaque draw's
    /// exact span of [`OPAQUE_EXACT_MIN`] pixels or more that passes
    /// `opaque_shift`), for the built-in shaders' loops of their own.
    #[inline(always)]
    pub(crate) fn shifted_opaque(&self) -> Option<u32> {
        if self.opaque && self.mode == Perspective::Exact && self.len() >= OPAQUE_EXACT_MIN {
            self.opaque_shift()
        } else {
            None
        }
    }

    /// Whether `Q` is the same at every pixel of the span (its step is
    /// zero): the weights' reciprocal is then taken once
    /// ([`FLAT_Q`]).
    #[inline(always)]
    pub(crate) fn flat_q(&self) -> bool {
        self.steps[0] == 0
    }

    /// [`shade_with`](Self::shade_with) without the opaque draw's loops
    /// of its own. For the general texture path of
    /// [`Textured`](crate::shader::Textured) and
    /// [`TexturedLit`](crate::shader::TexturedLit), whose texel costs far
    /// more than the per-pixel decisions they save and whose copies would
    /// not fit the LM3S6965's flash beside the rest of that firmware.
    /// (`Textured`'s power-of-two paths took it too while the Cortex-M3
    /// computed the varyings in the 32-bit form of ARMv6-M: the opaque
    /// loops were slower there then.)
    #[inline(always)]
    pub(crate) fn shade_unspecialised(
        self,
        interpolate_color: bool,
        fragment: impl PixelFn<V, C>,
    ) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        // An affine span of the renderer's affine copy, the only spans
        // with colour planes: the colour theirs, given to `fragment`, so
        // that the general loop, which the other copies' exact spans
        // share, is the same code in every copy (with the planes' colour
        // in it, x86-64 `demo-textured-lit` +1.1 %).
        match WithPlanes::of(&self, interpolate_color, fragment) {
            Ok(planes) => self.run_put(false, planes),
            Err(fragment) => self.run_put(interpolate_color, fragment),
        }
    }

    /// [`run`](Self::run) with the draw's blend and depth write decided
    /// per pixel.
    #[inline(always)]
    fn run_put(self, interpolate_color: bool, fragment: impl PixelFn<V, C>) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        let put = Put {
            fragment,
            blend: self.blend,
            write: self.write,
        };
        self.run(interpolate_color, put)
    }

    /// Colours the span through a per-fragment function: what the default
    /// [`FragmentShader::shade_span`] does with
    /// [`FragmentShader::fragment`]. `interpolate_color` is the shader's
    /// [`FragmentShader::INTERPOLATE_COLOR`]: without it, every fragment
    /// gets the provoking vertex's colour.
    #[inline(always)]
    pub fn fragments(
        self,
        interpolate_color: bool,
        mut fragment: impl FnMut(&Fragment<'_, V>) -> Option<C>,
    ) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        let (y, texture, flat) = (self.y, self.texture, self.flat_color());
        let draw = self.draw;
        self.shade(interpolate_color, |it| {
            fragment(&Fragment {
                draw,
                x: it.x,
                y,
                depth: it.depth,
                color: if interpolate_color { it.rgb() } else { flat },
                varyings: it.varyings,
                texture,
            })
        })
    }

    /// [`FragmentShader::shade_span`] as `shader`'s default would run it,
    /// even if `shader` overrides it: the reference that the specialised
    /// span loops are tested against.
    #[inline(always)]
    pub fn fragments_of<S: FragmentShader<C, Varyings = V>>(self, shader: &S) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        self.fragments(S::INTERPOLATE_COLOR, |f| shader.fragment(f))
    }
}

/// The shortest span that takes the opaque exact loop with the span's
/// shift: the test per span (`opaque_shift`: three products and a dozen
/// comparisons) is not paid by spans of one or two pixels, most of the
/// textured frame's, which take the opaque loop with [`weights`] per pixel
/// instead. Tuned on `demo-textured-lit` (Cortex-M3): 8 pixels 8,256,167
/// instructions, 4 8,207,289, 3 8,198,446, 2 8,198,437; x86-64 at 3
/// 7,709,280 -> 7,696,985 against 4; the shader fills' 32-pixel spans
/// unchanged. ARMv6-M (no 32x32 to 64-bit multiply) kept 4: at 3 its
/// `demo-textured-lit` took 25,713,431 -> 25,906,607 (the Cortex-M4F
/// 7,900,918 -> 7,904,071). Since its per-pixel weights test a guessed
/// shift (`weights_guessed`), it takes 5: `demo-textured-lit`
/// 12,486,713 -> 12,462,540 (single-scene builds: 4 12,482,396, 5
/// 12,458,223, 6 12,457,475, 7 12,460,891, 8 12,464,780, 12
/// 12,478,648), the shader fills the same (at 6 they took +0.05 to
/// +0.10 a fragment).
///
/// [`weights`]: crate::shade::perspective::weights
const OPAQUE_EXACT_MIN: usize = if cfg!(microraster_narrow_multiply) {
    5
} else {
    3
};

/// Whether an opaque exact span whose `Q` does not change takes
/// [`SpanInput::run_opaque`]'s copy with [`FLAT_Q`] weights, for a shader
/// with `len` varyings that interpolates the colour or not: everywhere but
/// for a shader with both (`TexturedLit`) on the Cortex-M3 and ARMv6-M,
/// whose loops' registers moved with the copy beside them (Cortex-M3
/// `demo-textured-lit`, whose spans rarely take it, 8,130,275 ->
/// 8,222,806 instructions, 1,468 B more flash; out of line, its firmware
/// no longer fit the LM3S6965's flash; again at `76d1e8b`: 7,057,017 ->
/// 7,109,584, though `fill-lit-exact` 106.93 -> 103.24 a fragment; out of
/// line, a call per span, 8,512,440 and 122.53). On x86-64
/// `fill-lit-exact` 128.21 -> 117.48 per fragment and
/// `demo-textured-lit` -1.1 % with it; on the Cortex-M4F
/// (`microraster_armv7em`, the build script's) at `76d1e8b`
/// `fill-lit-exact` 111.94 -> 106.39 and `demo-textured-lit` 7,085,728 ->
/// 7,072,276.
const fn flat_q_loop(len: usize, interpolate_color: bool) -> bool {
    cfg!(target_pointer_width = "64") || cfg!(microraster_armv7em) || len == 0 || !interpolate_color
}

/// A span shader's colour at one pixel, for [`SpanInput::shade_with`]:
/// any closure `FnMut(&Interpolated<V>) -> Option<C>` is one.
///
/// The span loop calls it from two places (one loop for exact and affine
/// interpolation, one for quasi-perspective), and the compiler may leave
/// a closure that is called twice out of line: a call per pixel. A type
/// of your own whose `pixel` is `#[inline(always)]` is always inlined
/// into both; the built-in shaders' are such types.
pub trait PixelFn<V, C> {
    /// The colour at the pixel with values `it`, or `None` to write
    /// nothing there.
    fn pixel(&mut self, it: &Interpolated<V>) -> Option<C>;
}

impl<V, C, F: FnMut(&Interpolated<V>) -> Option<C>> PixelFn<V, C> for F {
    #[inline(always)]
    fn pixel(&mut self, it: &Interpolated<V>) -> Option<C> {
        self(it)
    }
}

/// What the span loop does at a pixel that passes the depth test: a
/// trait whose method is always inlined, rather than a closure, because
/// the loop calls it from two places (the exact and the quasi-perspective
/// loops), and a closure called twice is left out of line.
pub(crate) trait PutPixel<V, C> {
    /// Colours pixel `out` (depth `d`) from `it`; whether it wrote.
    fn put(&mut self, it: &Interpolated<V>, out: &mut C, d: &mut u16) -> bool;
}

/// An opaque draw's pixel (no blend, depth written): the shader's
/// function alone.
pub(crate) struct Opaque<F>(pub F);

impl<V, C, F: PixelFn<V, C>> PutPixel<V, C> for Opaque<F> {
    #[inline(always)]
    fn put(&mut self, it: &Interpolated<V>, out: &mut C, d: &mut u16) -> bool {
        match self.0.pixel(it) {
            Some(c) => {
                *out = c;
                *d = it.depth;
                true
            }
            None => false,
        }
    }
}

/// [`SpanInput::shade`]'s pixel: the shader's function, the blend, the
/// depth write.
struct Put<F> {
    fragment: F,
    blend: Blend,
    write: bool,
}

impl<V, C, F> PutPixel<V, C> for Put<F>
where
    C: Copy + From<Rgb888> + Into<Rgb888>,
    F: PixelFn<V, C>,
{
    #[inline(always)]
    fn put(&mut self, it: &Interpolated<V>, out: &mut C, d: &mut u16) -> bool {
        match self.fragment.pixel(it) {
            Some(c) => {
                *out = match self.blend {
                    Blend::Opaque => c,
                    blend => {
                        let (s, d): (Rgb888, Rgb888) = (c.into(), (*out).into());
                        let [r, g, b] = blend.apply([s.r(), s.g(), s.b()], [d.r(), d.g(), d.b()]);
                        C::from(Rgb888::new(r, g, b))
                    }
                };
                if self.write {
                    *d = it.depth;
                }
                true
            }
            None => false,
        }
    }
}
