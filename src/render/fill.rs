//! A triangle in a tile: its spans found, then shaded.

use super::dispatch::{ShaderPass, Shaders};
use crate::raster::{PixelRect, Span};
use crate::shade::perspective::{Output, PerspectiveSetup, ShaderTriangle};
use crate::shade::{
    span_flat, span_gouraud, ColourPlanes, Corners, DepthFn, DepthTest, SpanPos, To565,
    TriangleSetup, FIXED_GOURAUD, OFFSET_SETUP, OPAQUE_FLAT, OPAQUE_TABLE, SMALL_INLINE,
    SPLIT_INTERIOR,
};
use crate::shader::{FragmentShader, Perspective, ShaderSet, TriangleSpans};
use crate::texture::Texture;
use crate::tile::TileBuffer;
use crate::vertex::ScreenVertex;
use embedded_graphics::pixelcolor::{PixelColor, Rgb565, Rgb888};

/// Where a triangle is drawn: the tile, its place in the frame, the
/// spans of the triangle being drawn (at most one per tile row) and the
/// frame's span loops.
pub(super) struct Target<'j, C, F: ShaderSet<C>, const TW: usize, const TH: usize>
where
    C: From<Rgb888> + 'static,
{
    pub(super) tile: &'j mut TileBuffer<C, TW, TH>,
    pub(super) rect: &'j PixelRect,
    pub(super) found: [Span; TH],
    pub(super) shaders: &'j Shaders<'j, C, F, TW, TH>,
    /// The first and last screen rows of the spans drawn so far (first >
    /// last: none), recorded in the tile when it is done
    /// ([`Target::finish`]).
    pub(super) rows: (i32, i32),
    /// On 64-bit hosts, the fragments the tile loop's common path has
    /// written so far in the tile: kept here, in memory, where the loop
    /// adds a pair's count in one instruction (a local was spilled around
    /// the span loop's call, loaded, added and stored again).
    #[cfg(target_pointer_width = "64")]
    pub(super) shaded: u32,
}

impl<C, F: ShaderSet<C>, const TW: usize, const TH: usize> Target<'_, C, F, TW, TH>
where
    C: From<Rgb888>,
{
    /// Records in the tile the rows drawn (see [`TileBuffer::written`]):
    /// every row where `whole`, as where the tile loop's common path,
    /// which records no rows ([`WHOLE_TILE_ROWS`]), wrote a fragment.
    #[inline(always)]
    pub(super) fn finish(&mut self, whole: bool) {
        if whole {
            self.tile.written(0, TH - 1);
        }
        let (first, last) = self.rows;
        if first <= last {
            // Spans lie inside the tile.
            let y0 = self.rect.y0;
            self.tile
                .written((first - y0) as usize, (last - y0) as usize);
        }
    }
}

/// The first `count` spans of `found`, about to be drawn, with their
/// rows noted in `rows` (see [`Target::rows`]); `None` when there is
/// none. Per triangle and tile, never per pixel. (`count` is at most
/// `TH`, a span per row: taken by `get`, without a panic's call and
/// location in flash.)
#[inline(always)]
pub(super) fn drawn<'f>(
    found: &'f [Span],
    count: usize,
    rows: &mut (i32, i32),
) -> Option<&'f [Span]> {
    // The last span first, by `count - 1`: one unsigned compare tells
    // `1..=found.len()` (ARMv6-M built the range test's constant in two
    // instructions: `demo` -2,588 in the tile loop's common path), and
    // leaves the others unchecked.
    let last = found.get(count.wrapping_sub(1))?;
    let found = found.get(..count)?;
    let first = found.first()?;
    // Stored only when they grow, which few pairs of a tile make them:
    // a compare and a branch each, where the minimum and maximum took a
    // store too (Cortex-M3 `demo` 3,918,578 -> 3,915,255 instructions,
    // `rock` 3,220,055 -> 3,217,700; ARMv6-M `demo` -8,400; x86-64
    // `demo` -6,300).
    if first.j < rows.0 {
        rows.0 = first.j;
    }
    if last.j > rows.1 {
        rows.1 = last.j;
    }
    Some(found)
}

/// Whether the tile loop's common path leaves its pairs' rows unrecorded
/// ([`drawn_any`]), and a tile where it wrote a pixel is cleared whole
/// ([`Target::finish`]; the other paths' pairs record their rows, and
/// their fragments are counted apart so as not to widen the clear):
/// 64-bit hosts, where a pair's two compares with the rows so far, in
/// memory, and the load of its last span's row took ten instructions,
/// and the Cortex-M cores: the Cortex-M3's `demo` 2,864,006 ->
/// 2,835,784 instructions, `rock` 2,353,523 -> 2,331,109, `fill` 13.89
/// -> 13.84 a pixel; the M4F's
/// `demo` 2,866,231 -> 2,833,903, `rock` 2,376,393 -> 2,350,182;
/// ARMv6-M's `demo` 5,844,263 -> 5,827,392, `rock` -16.6 K; the Pico 2's
/// Cortex-M33 on the boards' scene 2,155,650 -> 2,139,200 (frame 0);
/// the shader and textured scenes +130 to +430. Not on RISC-V (the
/// ESP32-C3's four frames 2,514,327 ... 2,375,792 -> 2,521,897 ...
/// 2,378,979, its loop's registers moved). (Clearing a row that was
/// not written rewrites the values it holds: the same images.)
pub(super) const WHOLE_TILE_ROWS: bool = !cfg!(target_arch = "riscv32");

/// [`drawn`] without the rows (see [`WHOLE_TILE_ROWS`]).
#[inline(always)]
pub(super) fn drawn_any(found: &[Span], count: usize) -> Option<&[Span]> {
    // As in `drawn`: one unsigned compare tells `1..=found.len()`.
    found.get(count.wrapping_sub(1))?;
    found.get(..count)
}

/// Draws one triangle into the tile, Gouraud or flat shaded (flat in the
/// colour of its first vertex) by `shaders`.
///
/// Two phases: the scanline rasterizer first walks the edges and records
/// the triangle's spans in the tile in `found` (at most one per row), then,
/// if there is any, the attribute planes are set up and the spans shaded,
/// both out of line. Each loop then keeps only its own state in
/// registers (the edge walk its two edges, the shading its planes), and a
/// triangle that merely grazes the tile's bounds costs no set-up.
#[inline(always)]
pub(super) fn fill<C, F, const TW: usize, const TH: usize>(
    to: &mut Target<'_, C, F, TW, TH>,
    sv: [&ScreenVertex; 3],
    gouraud: bool,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    let count = (to.shaders.find)(&sv, to.rect, &mut to.found);
    let Some(found) = drawn(&to.found, count, &mut to.rows) else {
        return 0;
    };
    // A Gouraud triangle of one colour at its three vertices (faces that
    // the light does not reach: one pair in seven of `demo`, with a
    // quarter of its pixels) is shaded by the flat span loops, where
    // `ONE_COLOUR_FLAT`: its colour planes are constant, the colour of
    // each of its pixels is the vertices' (the same conversion as the
    // Gouraud loop's table, see `rgb`), and depth and the count of written
    // fragments are the same.
    let flat = ONE_COLOUR_FLAT && gouraud && one_colour(&sv);
    let shade = to.shaders.fill[(gouraud && !flat) as usize];
    shade(to.tile, to.rect, &sv, found, to.shaders.out.test)
}

/// [`fill`] for a triangle coloured by a fragment shader.
#[inline(always)]
pub(super) fn fill_shaded<C, F, G, const TW: usize, const TH: usize>(
    to: &mut Target<'_, C, F, TW, TH>,
    tri: &ShaderTriangle<'_, G::Varyings>,
    texture: Option<&Texture<'_>>,
    pass: &ShaderPass<'_, C, G, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    G: FragmentShader<C>,
{
    let count = (pass.find)(&tri.corners.0, to.rect, &mut to.found);
    let Some(found) = drawn(&to.found, count, &mut to.rows) else {
        return 0;
    };
    (pass.shade)(to.tile, to.rect, tri, found, pass.shader, texture, pass.out)
}

/// The second phase of [`fill`]: sets up the attribute planes of the
/// triangle `sv` and shades its spans `found`. In a function of its own so
/// that its loops get the registers to themselves, and with the set-up
/// inlined so that the planes are computed where the span loop reads them.
#[inline(never)]
pub(super) fn shade<
    C,
    D: DepthFn,
    const WRITE: bool,
    const GOURAUD: bool,
    const TW: usize,
    const TH: usize,
>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    sv: &[&ScreenVertex; 3],
    found: &[Span],
    test: DepthTest,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
{
    let dt = D::new(test);
    let corners = &Corners(*sv);
    // The default depth comparison (known at compile time: no state) with
    // depth writes, into `Rgb565`: the span loops of nearly every frame on
    // a microcontroller, which get the small set-up inlined (see
    // `TriangleSetup::small_for_spans`; constants, decided at compile
    // time).
    let common = WRITE
        && core::mem::size_of::<D>() == 0
        && core::any::TypeId::of::<C>() == core::any::TypeId::of::<Rgb565>();
    // Where `EARLY_INTERIOR`, the interior bit from the vertices.
    #[cfg(microraster_interior)]
    let early = EARLY_INTERIOR && ScreenVertex::all_interior(*sv);
    let small = if common {
        TriangleSetup::small_for_spans::<GOURAUD>(corners)
    } else {
        None
    };
    // Where the small set-up is inlined, only its triangles take the
    // interior loop (the others, about 1 %, the tested starts): its
    // planes then go from the registers that computed them to the loop's
    // spill slots, where the set-up that both paths share had them
    // stored, loaded and copied to those slots once a pair (Cortex-M3
    // `demo` 3,265,769 -> 3,211,719 instructions, `rock` 2,682,037 ->
    // 2,629,032; Cortex-M4F `demo` 3,251,382 -> 3,177,168).
    if let Some(setup) = &small {
        #[cfg(microraster_interior)]
        let interior = if EARLY_INTERIOR {
            early
        } else {
            setup.interior()
        };
        #[cfg(not(microraster_interior))]
        let interior = setup.interior();
        if GOURAUD && SPLIT_INTERIOR && interior {
            // The same call as the one for the other triangles below,
            // written out twice: shared by one local closure, ARMv6-M's
            // `demo` took 6,663,049 -> 6,710,917 (the raster's registers;
            // the Cortex-M3's and M4F's code the same).
            return each_span::<C, GOURAUD, TW, TH>(tile, rect, found, |color, depth, sp, n| {
                span_gouraud::<C, D, WRITE, true>(
                    (dt, To565::fixed()),
                    setup,
                    corners,
                    color,
                    depth,
                    sp,
                    n,
                )
            });
        }
    }
    // The span loops of a triangle's `setup`, written out once for the
    // offset set-up's triangles (64-bit hosts: their planes go to the loop
    // without a merge with the general set-up's, see `OFFSET_SETUP`) and
    // once for the others: a macro, so that each has a closure of its own,
    // inlined (one function called from both, the closure was not).
    macro_rules! spans {
        ($setup:expr, $corners:expr) => {{
            let (setup, corners): (&TriangleSetup, &Corners<'_>) = ($setup, $corners);
            // Flat shading's colour is the first vertex's (the tile loop gives a
            // clipped piece the colour of the triangle's own first vertex there):
            // read here, by the flat span loops only, rather than loaded and
            // passed for every pair.
            let [r, g, b] = sv[0].color();
            let flat = crate::shade::rgb::<C>(r, g, b);
            if GOURAUD && SPLIT_INTERIOR && !(common && SMALL_INLINE) && setup.interior() {
                // Tested once, not at every span start (the interior bit is
                // never set where the vertex stage does not make it: no copy).
                // Not where the loop above took the interior triangles: one
                // interior loop in each span loop's code.
                return each_span::<C, GOURAUD, TW, TH>(
                    tile,
                    rect,
                    found,
                    |color, depth, sp, n| {
                        span_gouraud::<C, D, WRITE, true>(
                            (dt, To565::fixed()),
                            setup,
                            corners,
                            color,
                            depth,
                            sp,
                            n,
                        )
                    },
                );
            }
            // Gouraud loops that read the table at its constant address
            // (`FIXED_GOURAUD`, the M4F) would throw an opaque copy away:
            // M4F `demo` -4.4 K, `rock` -1.8 K.
            let table = if OPAQUE_TABLE && (GOURAUD && !FIXED_GOURAUD || !GOURAUD && OPAQUE_FLAT) {
                To565::opaque()
            } else {
                To565::fixed()
            };
            each_span::<C, GOURAUD, TW, TH>(tile, rect, found, |color, depth, sp, n| {
                if GOURAUD {
                    span_gouraud::<C, D, WRITE, false>(
                        (dt, table),
                        setup,
                        corners,
                        color,
                        depth,
                        sp,
                        n,
                    )
                } else {
                    n + span_flat::<C, D, WRITE>(dt, setup, corners, flat, color, depth, sp)
                }
            })
        }};
    }
    if OFFSET_SETUP {
        if let Some(setup) = &small {
            return spans!(setup, corners);
        }
    }
    // Where the offset set-up's triangles took the loops above, the
    // others' corners are a copy of their own: the general set-up and
    // `wide_start` take their address, and with one copy for both paths
    // its stores were made at every call.
    let apart;
    let corners = if OFFSET_SETUP {
        apart = Corners(*sv);
        &apart
    } else {
        corners
    };
    let setup = &match small {
        Some(s) => s,
        None => TriangleSetup::for_spans::<GOURAUD>(corners),
    };
    if crate::shade::STEPS_IN_PLACE {
        // Its address escapes: see `STEPS_IN_PLACE`. The flat span
        // loops' set-up too, whose span starts then read the depth plane
        // where the set-up stored it, not from copies made once a pair
        // (ARMv6-M `demo-flat` 4,800,858 -> 4,778,426 instructions, `fill`
        // 23.25 -> 23.23 a pixel).
        core::hint::black_box(setup);
    }
    spans!(setup, corners)
}

/// Whether [`shade`] takes the interior bit of a triangle with a small
/// set-up from its vertices (`ScreenVertex::all_interior`, read before the
/// set-up) rather than from the set-up's field: the same bit (a small
/// set-up is never wide), on ARMv7E-M (the build script's
/// `microraster_armv7em`), with the small set-up's half-area bound
/// (`shade::small`'s `HALF_TEST`). The registers of the set-up and of the
/// interior span start then fall so that the span start keeps its 42
/// instructions where the bound alone moved them (two more a span): the
/// Cortex-M4F's `demo` 2,953,379 -> 2,937,011 instructions with both,
/// 2,967,907 with the bound alone, 2,960,827 with this alone (see
/// `HALF_TEST` for the other scenes). (Only where vertices carry the
/// interior bit, `microraster_interior`: not in builds for size.)
#[cfg(microraster_interior)]
const EARLY_INTERIOR: bool = cfg!(microraster_armv7em);

/// Whether [`fill`] sends a Gouraud triangle of one colour to the flat
/// span loops: in every build but those optimised for size
/// (`microraster_size`), whose Gouraud-only firmwares (the OLED's) then
/// link no flat span loop; a Gouraud-only firmware built for speed links
/// one for it (`rp2040_st7789` +2,088 B of flash). Measured first on the
/// Cortex-M4F (the build script's `microraster_armv7em`), ARMv6-M
/// (`microraster_narrow_multiply`) and the Cortex-M3
/// (`microraster_armv7m`), `demo`: Cortex-M3
/// 3,104,250 -> 3,091,310 instructions, Cortex-M4F 3,074,997 ->
/// 3,061,846, ARMv6-M 6,282,412 -> 6,250,433; `rock` and `grid4` the same
/// counts (their pairs take the tile loop's common path, which calls the
/// span loop directly). The test at the top of [`shade`] instead, for
/// every pair of every path, gave `demo` -45 K, -65 K and -119 K but cost
/// `rock` +16 K, +5 K and +7 K and the M3's `grid4` +20 K: a test every
/// pair makes costs more than it saves where few faces are of one colour.
/// On the Pico 2's Cortex-M33 (`microraster_armv8m`) and the ESP32-C3's
/// RV32IMC too, whose boards' scene has a flat-shaded cube: its four
/// frames 2,204,950, 2,138,000, 2,007,950 and 2,075,550 -> 2,182,150,
/// 2,127,750, 2,004,900 and 2,070,150 instructions on the M33, 2,551,260
/// ... 2,389,052 -> 2,519,113 ... 2,380,326 on RV32IMC. And on 64-bit
/// hosts, measured again with the tile loop's walk inline there
/// (`demo` 2,768,616 -> 2,757,491, `rock` the same, the textured frames
/// -36; before, with the test in `shade`, `demo` 3,097,082 -> 3,078,652
/// but `rock` 2,564,079 -> 2,591,383).
pub(super) const ONE_COLOUR_FLAT: bool = !cfg!(microraster_size);

/// Whether the three vertices `sv` have the same colour. (The Cortex-M3's
/// words compared whole, which paid where every pair made the test,
/// measured 18 instructions a `demo` frame slower here.)
#[inline(always)]
fn one_colour(sv: &[&ScreenVertex; 3]) -> bool {
    let key = |v: &ScreenVertex| {
        let [r, g, b] = v.color();
        u32::from(r) | u32::from(g) << 8 | u32::from(b) << 16
    };
    let k = key(sv[0]);
    (k ^ key(sv[1])) | (k ^ key(sv[2])) == 0
}

/// Calls `shade` with the tile's colour and depth buffers, the place of
/// each span of `found` and the fragments written so far, which it returns
/// with its own added (so that a span loop can count in the running total).
///
/// The buffers are passed whole, as one slice each, and each span's
/// [`SpanPos::ox`] is the screen column that the slice's first element
/// would have on the span's row: the span loop's one range check then
/// holds the span in the tile, where a row's index took a check (and a
/// panic's call and location in flash) of its own. The same instructions
/// a span on the M3.
///
/// With `BASE`, `ox` is the column of the tile's first element on screen
/// row 0, computed once per pair, less the span's row (negated where
/// [`NEGATED_OX`](crate::shade::NEGATED_OX); only the Gouraud span loops take `BASE`): one shifted
/// subtraction a span, where `ox` had been the tile's column less the
/// span's row within the tile (the Cortex-M3's Gouraud span starts
/// then keep fewer values in stack slots: `demo` 4,069,639 -> 4,035,521
/// instructions, `rock` 3,353,413 -> 3,324,938). Not for the flat span
/// loops, whose registers it moved: the M3's `fill` went from 15.03 to
/// 15.86 instructions per pixel.
#[inline(always)]
fn each_span<C, const BASE: bool, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    found: &[Span],
    mut shade: impl FnMut(&mut [C], &mut [u16], SpanPos, u32) -> u32,
) -> u32 {
    let mut n = 0;
    let (color, depth) = (
        tile.color.as_flattened_mut(),
        tile.depth.0.as_flattened_mut(),
    );
    // Within the tile and the guard band: far below 2^31.
    let base = rect.x0 + rect.y0 * TW as i32;
    for &Span { j, x0, x1 } in found {
        // Within the tile (the walk clips the spans to it): at most
        // `TW * TH`, far below 2^31.
        let row = (j - rect.y0) * TW as i32;
        // Where `NEGATED_OX` (64-bit hosts), the negated form, which the
        // Gouraud span loop adds (see `SpanPos::ox`): one shift and one
        // subtraction for both ends rather than a copy of the base and
        // three (x86-64 `demo` 3,268,079 -> 3,235,954 instructions, `rock`
        // 2,728,649 -> 2,703,865).
        let sp = if BASE {
            SpanPos::in_tile(base, TW as i32, j, x0, x1)
        } else {
            SpanPos {
                ox: rect.x0 - row,
                j,
                x0,
                x1,
            }
        };
        n = shade(color, depth, sp, n);
    }
    n
}

/// [`shade_custom`]'s copy for every pass but those below: its spans go
/// to [`FragmentShader::shade_spans`].
pub(super) const GENERAL: u8 = 0;
/// [`shade_custom`]'s copy for the opaque passes of a quasi-perspective
/// frame: their spans go to [`FragmentShader::shade_quasi_spans`].
pub(super) const QUASI: u8 = 1;
/// [`shade_custom`]'s copy for the opaque passes of an affine frame: their
/// spans go to [`FragmentShader::shade_affine_spans`].
pub(super) const AFFINE: u8 = 2;

/// The second phase of [`fill_shaded`]: the perspective set-up of the
/// triangle and its spans shaded through the fragment shader, in the copy
/// `COPY` ([`GENERAL`], [`QUASI`] or [`AFFINE`]); a triangle that the
/// opaque loops of `QUASI` or `AFFINE` cannot take goes to `GENERAL`. A
/// function a copy, so that each shader's loops for the other frames are
/// compiled as they were: one calling every method had the closures of
/// `shade_spans` called from two places, and the compiler then left them
/// out of line (x86-64 `demo-textured-lit` 5,975,883 -> 7,047,718
/// instructions).
#[inline(never)]
pub(super) fn shade_custom<C, F, const TW: usize, const TH: usize, const COPY: u8>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    tri: &ShaderTriangle<'_, F::Varyings>,
    found: &[Span],
    shader: &F,
    texture: Option<&Texture<'_>>,
    out: Output,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: FragmentShader<C>,
{
    let setup = &PerspectiveSetup::new(tri, COPY == AFFINE || out.mode == Perspective::Affine);
    if COPY == GENERAL {
        return shader.shade_spans(triangle_spans(
            tile,
            rect,
            tri,
            found,
            (setup, None),
            texture,
            out,
        ));
    }
    // A triangle whose varyings' differences do not fit `i32`
    // (`PerspectiveSetup::fits`, `fits_affine`: slivers, huge texture
    // coordinates) goes to the general copy, which sets it up again
    // (blended passes never come here: `Shaders::custom`).
    let fits = if COPY == QUASI {
        out.quasi_opaque() && setup.fits()
    } else {
        out.affine_opaque() && setup.fits_affine()
    };
    if !fits {
        return shade_custom::<C, F, TW, TH, GENERAL>(tile, rect, tri, found, shader, texture, out);
    }
    // In this copy, where the shader reads the colour, the colour planes
    // ([`ColourPlanes`]): the affine spans' colour is then the Gouraud
    // shading's. Set up beside the perspective set-up, which stays as it
    // was (with them in its fields, x86-64 `demo-textured-lit` took +5 %
    // to +8 %, the set-up's copies), and out of line: one copy for every
    // shader (inlined, each took about 1.5 KB of a Cortex-M3's flash).
    // Only here: in the general copy, whose exact spans share its loops
    // with the affine ones, they took x86-64 `demo-textured-lit` +1 % to
    // +3 % and the Cortex-M4F's +1 % to +2 % (the loops' registers), so
    // its affine spans (blended draws, and the few triangles that do not
    // fit) keep the perspective weights' colour.
    let colour = if COPY == AFFINE && F::INTERPOLATE_COLOR {
        Some(ColourPlanes {
            setup: TriangleSetup::colour_planes(&tri.corners),
            corners: &tri.corners,
        })
    } else {
        None
    };
    let mut spans = triangle_spans(
        tile,
        rect,
        tri,
        found,
        (setup, colour.as_ref()),
        texture,
        out,
    );
    if COPY == QUASI {
        spans.quasi_opaque = true;
        shader.shade_quasi_spans(spans)
    } else {
        spans.affine_opaque = true;
        shader.shade_affine_spans(spans)
    }
}

/// The spans `found` of triangle `tri` (set up as `setup`, with its
/// `colour` planes if affine and the shader reads the colour) in `tile`,
/// at `rect`, for the shader; neither
/// [`quasi_opaque`](TriangleSpans::quasi_opaque) nor
/// [`affine_opaque`](TriangleSpans::affine_opaque).
#[inline(always)]
fn triangle_spans<'a, C, V, const TW: usize, const TH: usize>(
    tile: &'a mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    tri: &'a ShaderTriangle<'a, V>,
    found: &'a [Span],
    (setup, colour): (&'a PerspectiveSetup<V>, Option<&'a ColourPlanes<'a>>),
    texture: Option<&'a Texture<'a>>,
    out: Output,
) -> TriangleSpans<'a, C, V> {
    TriangleSpans {
        color: tile.color.as_flattened_mut(),
        depth: tile.depth.0.as_flattened_mut(),
        width: TW,
        ox: rect.x0,
        oy: rect.y0,
        found,
        setup,
        colour,
        corners: &tri.corners,
        texture,
        out,
        quasi_opaque: false,
        affine_opaque: false,
    }
}
