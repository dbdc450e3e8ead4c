//! The tile loop: each triangle of a tile fetched and sent down its path.

mod shaded;

use super::cursor::{DrawCursor, TileList};
use super::dispatch::{ShaderPass, Shaders};
use super::fill::{drawn, drawn_any, fill, fill_shaded, Target, WHOLE_TILE_ROWS};
use super::state::{FrameState, SetupCache};
use super::Features;
use crate::raster::line::{draw_line, draw_point, DepthMode, LinePoint};
use crate::raster::{PixelRect, Span};
use crate::scene::{Blend, Shading};
use crate::shade::perspective::{Output, ShaderTriangle};
use crate::shade::Corners;
use crate::shader::{self, FragmentShader, ShaderSet, Varyings, VertexInput, VisitShader};
use crate::tile::TileBuffer;
use crate::vertex::{ScreenVertex, BARY_ONE, MUST_CLIP};
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use fixed::types::I16F16;

/// Rasterizes the triangles of `list` into the tile: fetches each one's
/// vertices from the vertex buffer (or clips it again) and draws it with
/// [`fill`], shading with `shaders`.
#[inline(never)]
pub(super) fn raster_tile<'f, C, F, P, const TW: usize, const TH: usize>(
    tile: &mut TileBuffer<C, TW, TH>,
    rect: &PixelRect,
    frame: &'f FrameState<'f>,
    cache: &mut SetupCache,
    list: TileList<'_, 'f, P>,
    shaders: Shaders<'_, C, F, TW, TH>,
) -> u32
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
    P: Features,
{
    let mut cur = DrawCursor::new(frame);
    // Per tile, in locals: the pair's path reads them without going
    // through `shaders`.
    let (find, test) = (shaders.find, shaders.out.test);
    // Whether the tile's rasterizer is the scanline walk (see
    // `WALK_INLINE`): its function compared by address, so that any other
    // (or a copy the linker did not merge) keeps the call.
    let scan = WALK_INLINE
        && find as usize == super::find::finder::<P>(crate::raster::Rasterizer::Scanline) as usize;
    let job = &mut TileJob {
        frame,
        cache,
        to: Target {
            tile,
            rect,
            // The spans of one triangle, reused by all of the tile's
            // triangles: `TH` of 12 bytes on the stack.
            found: [Span::default(); TH],
            shaders: &shaders,
            rows: (i32::MAX, i32::MIN),
            #[cfg(target_pointer_width = "64")]
            shaded: 0,
        },
    };
    // Transparent triangles, drawn after the opaque ones: (depth key,
    // triangle), 4 bytes each on the stack.
    let mut later: heapless::Vec<(u16, u16), MAX_TRANSPARENT> = heapless::Vec::new();
    // The fragments written. Where the common path records no rows
    // (`WHOLE_TILE_ROWS`), a tile where it wrote one is cleared whole:
    // its count is then kept apart from that of the paths that record
    // their rows (the general path's, clipped and transparent
    // triangles'), which go to `other`; on 64-bit hosts it is
    // `job.to.shaded`, elsewhere `n`.
    let mut other = 0;
    let mut n = 0;
    let mut list = list;
    // The tile's rectangle for the inline walk (`WALK_INLINE`), copied
    // once a tile: read through `rect` its columns were loaded and
    // spilled again for every pair; the clamped walks take them afresh
    // per half (`half_direct`'s `FRESH`). x86-64 `demo` 2,826,270 ->
    // 2,814,923 instructions, `rock` 2,347,692 -> 2,339,073, `tri4`
    // -37.7 K, `tri100` -4.4 K; `tri10000` +5.9 K and `fill` +160 (8.76 a
    // pixel), whose large triangles take the clamped walks.
    let clip = *rect;
    if cfg!(microraster_size) {
        // Built for size (the build script's `microraster_size`): every
        // pair down the general path, inline, the loop's code there once
        // (the OLED firmware's flash 44,096 -> 43,316 bytes).
        for t in list {
            let m = job.general_one::<P>(&mut cur, t, &mut later);
            add_apart(&mut n, &mut other, m);
        }
    } else {
        // The loop written twice, for the scanline walk inline and for
        // the tile's other rasterizers: the test of `scan` (the
        // rasterizer's address, compared again for every pair) out of
        // the loop.
        macro_rules! common {
            ($scan:expr) => {{
                // The current draw's common path, per draw rather than per
                // pair (a bin's entries come in draw order): its triangles
                // (empty unless the draw is plain with `u16` indices), its
                // first triangle, its vertices and its span loop.
                let (mut fast, mut first, mut verts, mut shade) = (
                    cur.fast,
                    cur.first,
                    cur.verts,
                    shaders.fill[cur.gouraud as usize],
                );
                let mut next = list.next();
                while let Some(t) = next {
                    // One bounds check finds the common pair: a triangle of the
                    // current draw, which is plain. Any other (the next draw's, a
                    // rare path's, `u32` indices) takes the general path, which
                    // moves the cursor, draws the rest of that draw's run of pairs
                    // if the draw is not plain, and gives back the entry after
                    // them.
                    let Some(&[i0, i1, i2]) = fast.get(t.wrapping_sub(first)) else {
                        let (m, after) = job.general::<P>(&mut cur, t, &mut list, &mut later);
                        add_apart(&mut n, &mut other, m);
                        next = after;
                        (fast, first, verts) = (cur.fast, cur.first, cur.verts);
                        shade = shaders.fill[cur.gouraud as usize];
                        continue;
                    };
                    let sv = [
                        &verts[i0 as usize],
                        &verts[i1 as usize],
                        &verts[i2 as usize],
                    ];
                    // The outcodes tested in the vertices' whole first words (their
                    // low byte): one `tst` rather than a byte extension and a
                    // compare.
                    let any = sv[0].xy_words().0 | sv[1].xy_words().0 | sv[2].xy_words().0;
                    if any & MUST_CLIP as i32 != 0 {
                        let idx = [i0 as u32, i1 as u32, i2 as u32];
                        let m = job.clipped(&cur, idx, any as u8, sv[0].color());
                        add_apart(&mut n, &mut other, m);
                    } else {
                        // `fill`, with the tile's rasterizer, the draw's span loop
                        // and the depth test from locals.
                        let to = &mut job.to;
                        let count = if $scan {
                            // The walk of `fill`'s `find_spans`, inline.
                            let v = [sv[0].xy(), sv[1].xy(), sv[2].xy()];
                            crate::raster::scanline::find_spans_inline(&v, clip, &mut to.found)
                        } else {
                            find(&sv, to.rect, &mut to.found)
                        };
                        let found = if WHOLE_TILE_ROWS {
                            drawn_any(&to.found, count)
                        } else {
                            drawn(&to.found, count, &mut to.rows)
                        };
                        if let Some(found) = found {
                            let m = shade(to.tile, to.rect, &sv, found, test);
                            // Added in memory on 64-bit hosts (see `Target::shaded`).
                            #[cfg(target_pointer_width = "64")]
                            {
                                to.shaded += m;
                            }
                            #[cfg(not(target_pointer_width = "64"))]
                            {
                                n += m;
                            }
                        }
                    }
                    next = list.next();
                }
            }};
        }
        if WALK_INLINE && scan {
            common!(true)
        } else {
            common!(false)
        }
    }
    if P::BLEND {
        let m = job.draw_later::<P>(&mut later);
        add_apart(&mut n, &mut other, m);
    }
    #[cfg(target_pointer_width = "64")]
    {
        n += job.to.shaded;
    }
    job.to.finish(WHOLE_TILE_ROWS && n > 0);
    n + other
}

/// Adds `m` fragments of a path that records its rows (the general path,
/// clipped and transparent triangles) to `other` where the common path's
/// are counted apart ([`WHOLE_TILE_ROWS`]), to `n` with them elsewhere.
#[inline(always)]
fn add_apart(n: &mut u32, other: &mut u32, m: u32) {
    *if WHOLE_TILE_ROWS { other } else { n } += m;
}

/// One tile being drawn, and what drawing a triangle into it needs.
struct TileJob<'j, 'f, C, F: ShaderSet<C>, const TW: usize, const TH: usize>
where
    C: PixelColor + From<Rgb888> + 'static,
{
    frame: &'f FrameState<'f>,
    /// The last draw's fixed-point set-up, for clipped and shaded triangles.
    cache: &'j mut SetupCache,
    /// Where the triangles go.
    to: Target<'j, C, F, TW, TH>,
}

impl<C, F, const TW: usize, const TH: usize> TileJob<'_, '_, C, F, TW, TH>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    F: ShaderSet<C>,
{
    /// Draws global triangle `t`, of the cursor's draw or a later one,
    /// down whichever path its draw takes: the tile loop's general path,
    /// for a pair its common path does not take (see [`DrawCursor::fast`]),
    /// out of line and cold so that the common path keeps its registers.
    ///
    /// Then the pairs that follow in `list`, while they belong to the same
    /// draw and it has no common path (a shader draw's, a blended one's):
    /// one call for the run, not one a pair (x86-64 `demo-textured-lit`
    /// 7,012,406 -> 6,938,850 instructions), and for an opaque shader
    /// draw's run the shader picked once ([`shader_run`](Self::shader_run)).
    /// Returns the count of pixels shaded and the entry after the run,
    /// which the caller draws.
    #[cold]
    #[inline(never)]
    fn general<P: Features>(
        &mut self,
        cur: &mut DrawCursor<'_>,
        t: usize,
        list: &mut TileList<'_, '_, P>,
        later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    ) -> (u32, Option<usize>) {
        if !P::SHADERS {
            // No shader run to split off: the run in this function, as
            // one loop (`general_rest`'s copy of it had cost the
            // ESP32-C3's Gouraud firmware 712 B).
            return self.general_loop::<P>(cur, t, list, later);
        }
        let n = self.general_one::<P>(cur, t, later);
        match list.next() {
            Some(u) if u < cur.end && cur.fast.is_empty() => {
                let (m, after) = self.general_rest::<P>(cur, u, list, later);
                (n + m, after)
            }
            after => (n, after),
        }
    }

    /// The rest of [`general`](Self::general)'s run, from its second pair
    /// `t`: out of line, so that `general`, which the first pair of every
    /// draw takes, has the code of one pair only.
    #[inline(never)]
    fn general_rest<P: Features>(
        &mut self,
        cur: &mut DrawCursor<'_>,
        t: usize,
        list: &mut TileList<'_, '_, P>,
        later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    ) -> (u32, Option<usize>) {
        // An opaque shader draw without lines: the rest of its run with
        // the shader picked once, not once a pair.
        if P::SHADERS
            && cur.shading == Shading::Shader
            && !(P::LINES && cur.lines)
            && !(P::BLEND && cur.blend != Blend::Opaque)
        {
            return self.shader_runs::<P>(cur, t, list);
        }
        self.general_loop::<P>(cur, t, list, later)
    }

    /// [`general_one`](Self::general_one) for pair `t` and the pairs that
    /// follow in `list` while they belong to the same draw and it has no
    /// common path. Returns the count of pixels shaded and the entry
    /// after the run.
    #[inline(always)]
    fn general_loop<P: Features>(
        &mut self,
        cur: &mut DrawCursor<'_>,
        mut t: usize,
        list: &mut TileList<'_, '_, P>,
        later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    ) -> (u32, Option<usize>) {
        let mut n = 0;
        loop {
            n += self.general_one::<P>(cur, t, later);
            match list.next() {
                Some(u) if u < cur.end && cur.fast.is_empty() => t = u,
                after => return (n, after),
            }
        }
    }

    /// One pair of [`general`](Self::general)'s run.
    #[inline(always)]
    fn general_one<P: Features>(
        &mut self,
        cur: &mut DrawCursor<'_>,
        t: usize,
        later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    ) -> u32 {
        cur.seek(t);
        let mut n = 0;
        // The indices one by one: an array handed to the rare paths below
        // would live in memory, stored there for every triangle.
        let [i0, i1, i2] = cur.indices(t);
        let sv = [
            &cur.verts[i0 as usize],
            &cur.verts[i1 as usize],
            &cur.verts[i2 as usize],
        ];
        let any = sv[0].outcode() | sv[1].outcode() | sv[2].outcode();
        // One test for the common draw, rather than one per rare path.
        if (P::LINES || P::BLEND || P::SHADERS) && !cur.plain {
            if P::LINES && cur.lines {
                n += self.lines(cur, [i0, i1, i2], any);
                if matches!(cur.shading, Shading::Wireframe | Shading::Points(_)) {
                    return n;
                }
            }
            if P::BLEND && cur.blend != Blend::Opaque {
                // Farthest vertex first; a clipped triangle (whose depths the
                // vertex buffer does not hold) reaches the near plane: last.
                let key = if any & MUST_CLIP != 0 {
                    0
                } else {
                    sv[0].z().max(sv[1].z()).max(sv[2].z())
                };
                // `t < MAX_TRIANGLES`, so it fits u16. A full list is drawn
                // (sorted) and emptied first: a tile with more transparent
                // triangles than the list holds sorts them in batches of
                // `MAX_TRANSPARENT`, in submission order between batches.
                if later.is_full() {
                    n += self.draw_later::<P>(later);
                }
                let _ = later.push((key, t as u16));
                return n;
            }
            if P::SHADERS && cur.shading == Shading::Shader {
                return n + self.with_shader::<P>(cur, [i0, i1, i2], any, Blend::Opaque);
            }
        }
        n + if any & MUST_CLIP != 0 {
            self.clipped(cur, [i0, i1, i2], any, sv[0].color())
        } else {
            fill(&mut self.to, sv, cur.gouraud)
        }
    }

    /// Draws the transparent triangles of `later` back to front (equal keys in
    /// submission order) and empties it.
    #[inline(never)]
    fn draw_later<P: Features>(
        &mut self,
        later: &mut heapless::Vec<(u16, u16), MAX_TRANSPARENT>,
    ) -> u32 {
        if later.is_empty() {
            return 0;
        }
        // A stable insertion sort: a few dozen instructions of code, where
        // the library's sort brings kilobytes, and at most 128 entries.
        for k in 1..later.len() {
            let e = later[k];
            let mut i = k;
            while i > 0 && later[i - 1].0 < e.0 {
                later[i] = later[i - 1];
                i -= 1;
            }
            later[i] = e;
        }
        let mut n = 0;
        let mut cur = DrawCursor::new(self.frame);
        for &(_, t) in later.iter() {
            let t = t as usize;
            cur.go_to(t);
            let idx = cur.triangles.get(t - cur.first);
            let any = idx
                .iter()
                .fold(0, |a, &i| a | cur.verts[i as usize].outcode());
            n += self.transparent::<P>(&cur, idx, any);
        }
        later.clear();
        n
    }

    /// Draws a transparent triangle of the cursor's draw through the
    /// fragment-shader path: the scene's shader, or the flat or Gouraud
    /// colour, blended, depth tested and never writing depth.
    #[inline(never)]
    fn transparent<P: Features>(&mut self, cur: &DrawCursor<'_>, idx: [u32; 3], any: u8) -> u32 {
        let blend = cur.blend;
        let shaders = self.to.shaders;
        match cur.shading {
            Shading::Shader => self.with_shader::<P>(cur, idx, any, blend),
            Shading::Flat => self.shaded(
                cur,
                idx,
                any,
                shaders
                    .pass(&shader::Flat, [shaders.flat_t; 2], blend)
                    .with(no_write(blend)),
            ),
            Shading::Gouraud => self.shaded(
                cur,
                idx,
                any,
                shaders
                    .pass(&shader::Gouraud, [shaders.gouraud_t; 2], blend)
                    .with(no_write(blend)),
            ),
            // Never deferred: they have no fill.
            Shading::Wireframe | Shading::Points(_) => 0,
        }
    }

    /// Draws the lines or points of triangle `idx` of the cursor's draw: its
    /// three edges (or, for a clipped triangle, the parts of them that survive
    /// clipping), or a point at each vertex in front of the near plane.
    #[inline(never)]
    fn lines(&mut self, cur: &DrawCursor<'_>, idx: [u32; 3], any: u8) -> u32 {
        let (frame, to) = (self.frame, &mut self.to);
        let (tile, rect) = (&mut *to.tile, to.rect);
        let draw = &frame.draws[cur.draw];
        let sv = idx.map(|i| &cur.verts[i as usize]);
        let mode = DepthMode {
            test: to.shaders.out.test,
            write: to.shaders.out.write,
        };
        let mut n = 0;
        if let Shading::Points(size) = draw.shading {
            for v in sv {
                if v.outcode() & MUST_CLIP == 0 {
                    let p = LinePoint::new(v.xy(), v.z(), v.color());
                    n += draw_point(tile, rect, mode, &p, size as u32);
                }
            }
            return n;
        }
        let style = draw.edges.unwrap_or_default();
        let end = |v: &ScreenVertex| {
            let color = match style.color {
                Some(c) => {
                    use embedded_graphics::prelude::RgbColor;
                    [c.r(), c.g(), c.b()]
                }
                None => v.color(),
            };
            LinePoint::new(v.xy(), v.z(), color)
        };
        let interpolate = style.color.is_none();
        if any & MUST_CLIP == 0 {
            for k in 0..3 {
                let (a, b) = (end(sv[k]), end(sv[(k + 1) % 3]));
                n += draw_line(tile, rect, mode, &a, &b, interpolate, style.depth_bias);
            }
            return n;
        }
        let flat = sv[0].color();
        frame.clipped_pieces(cur.draw, idx, any, flat, self.cache, &mut |piece, _| {
            // Only the sides lying on the triangle's own edges: where both
            // ends have the same zero weight (clipping interpolates the
            // weights, and zero between zeros stays exactly zero).
            let w = piece.bary.map(|[b1, b2]| {
                [
                    BARY_ONE as i64 - b1 as i64 - b2 as i64,
                    b1 as i64,
                    b2 as i64,
                ]
            });
            for k in 0..3 {
                let k2 = (k + 1) % 3;
                if (0..3).any(|c| w[k][c] == 0 && w[k2][c] == 0) {
                    let (a, b) = (end(&piece.sv[k]), end(&piece.sv[k2]));
                    n += draw_line(tile, rect, mode, &a, &b, interpolate, style.depth_bias);
                }
            }
        });
        n
    }

    /// Clips triangle `idx` of the cursor's draw again and rasterizes its
    /// pieces.
    #[cold]
    #[inline(never)]
    fn clipped(&mut self, cur: &DrawCursor<'_>, idx: [u32; 3], any: u8, flat: [u8; 3]) -> u32 {
        let mut n = 0;
        let gouraud = cur.gouraud;
        let to = &mut self.to;
        let frame = self.frame;
        frame.clipped_pieces(cur.draw, idx, any, flat, self.cache, &mut |piece, flat| {
            // Flat shading takes the colour of the first vertex.
            let mut sv = piece.sv;
            if !gouraud {
                sv[0].set_color(flat);
            }
            let sv = [&sv[0], &sv[1], &sv[2]];
            n += fill(to, sv, gouraud);
        });
        n
    }
}

/// The output of a transparent triangle: blended by `blend`, never
/// writing depth.
fn no_write(blend: Blend) -> impl FnOnce(Output) -> Output {
    move |mut out: Output| {
        out.write = false;
        out.blend = blend;
        out
    }
}

/// Most transparent triangles one tile sorts back to front at once (4
/// bytes each on the stack); a tile with more sorts them in batches of
/// this many, in submission order between batches.
pub const MAX_TRANSPARENT: usize = 128;

/// Whether the common path of the tile loop walks a triangle's rows
/// itself, the scanline walk inlined (`scanline::find_spans_inline`),
/// where the tile's rasterizer is the scanline one: on every core with a
/// long multiply, whose tile loop then keeps its values in registers and
/// stack slots across the walk, and the walk its own, without the call,
/// the out-of-line walk's saved registers and its reloads of the
/// vertices' words (about 15 instructions a pair on x86-64, 13 on the
/// Cortex-M3). The test of a tall triangle stays out of
/// line (`misses_apart`): inline, or marked cold, the tile loop's
/// registers fell worse for the large triangles (`fill` up to 9.20 a
/// pixel, `tri10000` +63 K). x86-64 `demo` 2,920,341 -> 2,879,993
/// instructions (raster 2,277,553 -> 2,237,217), `rock` 2,418,526 ->
/// 2,388,313, `demo-flat` 2,531,604 -> 2,491,256, `tri4` -147 K, `tri100`
/// -73 K, `tri10000` -13 K, `fill` 5,414,298 -> 5,412,342 (8.81 a pixel);
/// the shader draws, which take the call, +340 (`demo-textured-lit`,
/// `knot1k-textured-lit`). On the Cortex-M3 `demo` 2,897,539 ->
/// 2,864,008, `rock` 2,381,154 -> 2,353,523, `grid4` -11.6 K, `fill`
/// 13.83 -> 13.89 a pixel, the shader scenes +500 to +1,300 and each
/// build's flash about +2.9 KB (the five shader fills' +8.7 KB); the
/// Cortex-M4F `demo` 2,897,613 -> 2,866,227, `rock` 2,400,457 ->
/// 2,376,397, `fill` +0.13 %; the boards' scene (the stack probe's
/// frame 0) on the Pico 2's Cortex-M33 2,241,000 -> 2,221,600 and on
/// the ESP32-C3's RV32IMC 2,661,429 -> 2,584,513. Not on ARMv6-M
/// (`SPLIT`), whose seven low registers hold less of the tile loop
/// across the walk: `demo` 5,844,263 -> 5,852,321. Builds optimised for
/// size never take the common path (`microraster_size`).
const WALK_INLINE: bool = !crate::math::SPLIT;
