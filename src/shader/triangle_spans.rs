//! [`TriangleSpans`]: a triangle's spans in one tile, handed to a shader
//! together ([`FragmentShader::shade_spans`](crate::shader::FragmentShader::shade_spans)) so that what is the same
//! for all of them is decided once per triangle and tile.

use super::span::{Opaque, PixelFn, SpanInput};
use crate::raster::Span;
use crate::shade::perspective::{
    colour_constants, span_input, Output, PerspectiveSetup, COLOUR_LOOP,
};
use crate::shade::{
    span_gouraud, ColourPlanes, Corners, DLessEqual, SpanPos, To565, FIXED_GOURAUD, OPAQUE_TABLE,
    SPLIT_INTERIOR,
};
use crate::shader::{Perspective, Varyings};
use crate::texture::Texture;
use embedded_graphics::pixelcolor::Rgb888;

/// The spans of one triangle in one tile, handed to
/// [`FragmentShader::shade_spans`](crate::shader::FragmentShader::shade_spans): what is the same for all of them (the
/// draw, its texture, the perspective mode, the triangle's set-up) is
/// known before the first, so a shader can decide it once per triangle
/// and tile rather than once per span, then colour each span with
/// [`each`](Self::each).
///
/// Most triangles of a mesh cover a few pixels in two or three spans:
/// what a shader decides per span (which texture format, filter and wrap)
/// is then paid two or three times per triangle and tile, for a few
/// pixels.
#[derive(Debug)]
pub struct TriangleSpans<'a, C, V> {
    /// The tile's colour and depth, row after row of `width` pixels.
    pub(crate) color: &'a mut [C],
    pub(crate) depth: &'a mut [u16],
    pub(crate) width: usize,
    /// The screen column and row of the tile's top left pixel.
    pub(crate) ox: i32,
    pub(crate) oy: i32,
    /// The spans, at most one per row, inside the tile.
    pub(crate) found: &'a [Span],
    pub(crate) setup: &'a PerspectiveSetup<V>,
    /// An affine triangle's colour planes, where its shader reads the
    /// colour, in the renderer's affine copy alone
    /// ([`ColourPlanes::start`]).
    pub(crate) colour: Option<&'a ColourPlanes<'a>>,
    pub(crate) corners: &'a Corners<'a>,
    pub(crate) texture: Option<&'a Texture<'a>>,
    pub(crate) out: Output,
    /// See [`quasi_opaque`](Self::quasi_opaque): set by the renderer,
    /// a constant in each of its shading functions, so that code for
    /// the other case is left out of each.
    pub(crate) quasi_opaque: bool,
    /// See [`affine_opaque`](Self::affine_opaque), likewise.
    pub(crate) affine_opaque: bool,
}

impl<'a, C, V: Varyings> TriangleSpans<'a, C, V> {
    /// Index of the triangle's draw in the scene (see [`Fragment::draw`](crate::shader::Fragment::draw)).
    #[inline(always)]
    pub fn draw(&self) -> usize {
        self.setup.draw()
    }

    /// The draw's texture, if it has one.
    #[inline(always)]
    pub fn texture(&self) -> Option<&'a Texture<'a>> {
        self.texture
    }

    /// How the varyings are interpolated along the spans: the frame's mode, or
    /// [`Perspective::Affine`] for a draw whose clip-space `w` is the same
    /// at every vertex (see [`Perspective`]).
    #[inline(always)]
    pub fn perspective(&self) -> Perspective {
        self.out.mode
    }

    /// The provoking vertex's lit colour (see
    /// [`SpanInput::flat_color`]).
    #[inline(always)]
    pub fn flat_color(&self) -> [u8; 3] {
        self.setup.flat()
    }

    /// Number of spans (at least one, as the renderer hands them).
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.found.len()
    }

    /// Whether there is no span (never, as the renderer hands them).
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.found.is_empty()
    }

    /// Colours each span through `shade` (typically a shader's
    /// [`FragmentShader::shade_span`](crate::shader::FragmentShader::shade_span), or [`SpanInput::shade_with`] with a
    /// per-pixel function chosen before the first span), top to bottom,
    /// and returns the sum of what it returns: the pixels written.
    #[inline(always)]
    pub fn each(self, mut shade: impl FnMut(SpanInput<'_, C, V>) -> u32) -> u32 {
        let Self {
            color,
            depth,
            width,
            ox,
            oy,
            found,
            setup,
            colour,
            corners,
            texture,
            out,
            ..
        } = self;
        // A triangle whose varyings' differences do not fit `i32` takes
        // the general loop (`PerspectiveSetup::fits`).
        let opaque = out.opaque() && setup.fits();
        let mut n = 0;
        for &Span { j, x0, x1 } in found {
            // The spans lie inside the tile (the walk clips them to it).
            let row = (j - oy) as usize * width;
            let (a, b) = (row + (x0 - ox) as usize, row + (x1 - ox) as usize);
            let sp = SpanPos { ox, j, x0, x1 };
            n += shade(span_input(
                setup,
                colour,
                corners,
                texture,
                out,
                &mut color[a..b],
                &mut depth[a..b],
                sp,
                opaque,
            ));
        }
        n
    }
}

impl<C, V: Varyings> TriangleSpans<'_, C, V> {
    /// Whether the spans are an opaque draw's (no blend, the `LessEqual`
    /// depth test, depth written) in a quasi-perspective frame
    /// ([`Perspective::Quasi8`], [`Perspective::Quasi16`]): those that
    /// the renderer hands to
    /// [`FragmentShader::shade_quasi_spans`](crate::shader::FragmentShader::shade_quasi_spans).
    #[inline(always)]
    pub fn quasi_opaque(&self) -> bool {
        self.quasi_opaque
    }

    /// Whether the spans are an opaque draw's in an affine frame
    /// ([`Perspective::Affine`]), or of an opaque draw interpolated
    /// affinely in any frame (its clip-space `w` the same at every vertex,
    /// see [`Perspective`]): those that the renderer hands to
    /// [`FragmentShader::shade_affine_spans`](crate::shader::FragmentShader::shade_affine_spans),
    /// and which [`SpanInput::shade_with`] colours in the opaque affine
    /// loop.
    #[inline(always)]
    pub fn affine_opaque(&self) -> bool {
        self.affine_opaque
    }

    /// Colours each span through `fragment` as
    /// [`each`](Self::each) with [`SpanInput::shade_with`] would, the
    /// colour interpolated if `interpolate_color`; for spans that are
    /// [`quasi_opaque`](Self::quasi_opaque), in the opaque
    /// quasi-perspective loop (the depth test, write and blend known, so
    /// only the depth comparison branches per pixel).
    #[inline(always)]
    pub fn each_quasi<F: PixelFn<V, C> + Copy>(self, interpolate_color: bool, fragment: F) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        if !self.quasi_opaque() {
            return self.each(|s| s.shade_plain(interpolate_color, fragment));
        }
        self.each(|s| s.run_quasi_opaque(interpolate_color, Opaque(fragment)))
    }

    /// `Gouraud`'s spans of an affine opaque draw
    /// ([`affine_opaque`](Self::affine_opaque)): the colour planes'
    /// values ([`ColourPlanes::start`]) are those of the
    /// built-in Gouraud shading, so its span loops
    /// ([`span_gouraud`]) colour them, with the depth test and writes of
    /// an opaque draw and the same bits as [`SpanInput::shade_affine`];
    /// the others there.
    #[inline(always)]
    pub(crate) fn each_gouraud<F: PixelFn<V, C> + Copy>(self, fragment: F) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888> + 'static,
    {
        // Without planes never (the affine copy, which alone calls this,
        // sets them up for `Gouraud`; `run_opaque` asserts it in debug).
        // Through `shade_plain` here, x86-64's fill took +0.16 a fragment.
        let Some(planes) = self.colour.filter(|_| self.affine_opaque) else {
            return self.each(|s| s.shade_affine(true, fragment));
        };
        let (color, depth, corners) = (self.color, self.depth, self.corners);
        // Made ready for the Gouraud span loops, which then step the
        // values of `ColourPlanes::start` and `span_input`'s depth as the
        // shader's loops do.
        let s = &planes.setup.for_gouraud_spans(corners);
        // As `render::fill`'s span loops: the tile's first element's
        // screen column on row 0 (within the tile and the guard band, far
        // below 2^31).
        let width = self.width as i32;
        let base = self.ox + self.oy * width;
        let pos = |&Span { j, x0, x1 }: &Span| SpanPos::in_tile(base, width, j, x0, x1);
        let mut n = 0;
        if SPLIT_INTERIOR && s.interior() {
            for span in self.found {
                let t = (DLessEqual, To565::fixed());
                n = span_gouraud::<C, _, true, true>(t, s, corners, color, depth, pos(span), n);
            }
            return n;
        }
        let table = if OPAQUE_TABLE && !FIXED_GOURAUD {
            To565::opaque()
        } else {
            To565::fixed()
        };
        for span in self.found {
            let t = (DLessEqual, table);
            n = span_gouraud::<C, _, true, false>(t, s, corners, color, depth, pos(span), n);
        }
        n
    }

    /// [`each`](Self::each) with [`SpanInput::shade_with`]`(true,
    /// fragment)` for a shader that reads the colour and no varyings
    /// (`Gouraud`), the constants of Thumb-2's colour loop ([`COLOUR_LOOP`],
    /// `run_colour_shifted`) gathered once for the triangle's spans
    /// ([`colour_constants`]) where they had been copied at every span:
    /// Cortex-M3 `fill-gouraud-exact` 58.67 -> 57.27 instructions a
    /// fragment, Cortex-M4F 69.19 -> 67.72. Elsewhere `shade_with` itself.
    #[inline(always)]
    pub(crate) fn each_colour<F: PixelFn<V, C> + Copy>(self, fragment: F) -> u32
    where
        C: Copy + From<Rgb888> + Into<Rgb888>,
    {
        if COLOUR_LOOP && V::LEN == 0 && self.out.opaque() && self.out.mode == Perspective::Exact {
            let k = colour_constants(self.setup);
            self.each(|s| s.shade_with_loops::<true>(true, fragment, Some(&k)))
        } else {
            self.each(|s| s.shade_plain(true, fragment))
        }
    }
}
