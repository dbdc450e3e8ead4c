//! The span loop behind [`SpanInput`]: a span's start from the planes,
//! then its pixels, exact (a weight per pixel) or quasi-perspective
//! (exact samples at screen-aligned columns, linear steps between), in
//! the general loop or in the opaque ones.

#[cfg(target_pointer_width = "64")]
use super::barycentric::span_shift_convex;
#[cfg(microraster_narrow_multiply)]
use super::barycentric::span_shift_convex32;
use super::barycentric::{
    flat_weights, shifted_weights, span_reciprocal, span_shift, weights_guessed,
};
use super::quasi::{quasi_segments, segment_length, segment_step, RECIPROCAL};
use super::*;
use crate::shade::ColourPlanes;

/// Whether an opaque exact span of a shader that reads only the colour
/// takes [`SpanInput::run_colour_shifted`]: on Thumb-2 cores (32-bit Arm
/// but ARMv6-M and ARMv8-M Baseline), where it was measured faster (see
/// there). ARMv6-M's `fill-gouraud-exact` took 194.0 -> 200.3
/// instructions per fragment with it. `build.rs` sets the cfg for those
/// targets, and on any target with `MICRORASTER_COLOUR_LOOP=1`, so that
/// CI runs the host's span-shader and golden tests through this loop too.
/// The same cfg has [`SpanInput::run_opaque`]'s exact loops count the
/// pixels that fail rather than those written (see there).
pub(crate) const COLOUR_LOOP: bool = cfg!(microraster_colour_loop);

/// Whether the built-in shaders take the span loops chosen for 32-bit
/// targets, where they were measured faster than on a 64-bit host
/// (`Textured`'s nearest loop for spans of constant `Q`, `TexturedLit`'s
/// quasi-perspective loop): on every target whose pointers are not 64 bits
/// wide, and on any target with `MICRORASTER_LOOPS32=1` (`build.rs`), so
/// that CI runs the host's span-shader and golden tests through them too.
pub(crate) const LOOPS32: bool = cfg!(any(not(target_pointer_width = "64"), microraster_loops32));

/// [`SpanInput::run_opaque`]'s weights: affine (`B1`, `B2` themselves,
/// [`PerspectiveSetup::values_affine`]), or
/// exact from [`shifted_weights`] with the span's shift, or exact from
/// [`weights`] (its clamps and normalisation per pixel).
pub(crate) const AFFINE: u8 = 0;
/// See [`AFFINE`].
pub(crate) const SHIFTED: u8 = 1;
/// [`AFFINE`] with each varying's sum stepped where [`STEP_AFFINE`]
/// (ARMv6-M; [`PerspectiveSetup::affine_sums`]) and the colour from the
/// colour planes: for the affine copy's spans
/// ([`SpanInput::shade_affine`](crate::shader::SpanInput::shade_affine)).
pub(crate) const AFFINE_SUMS: u8 = 4;
/// See [`AFFINE`].
pub(crate) const CLAMPED: u8 = 2;
/// [`SHIFTED`] for a span whose `Q` does not change along it (its step is
/// zero): the reciprocal taken once per span ([`span_reciprocal`]), the
/// same bits with no division per pixel.
pub(crate) const FLAT_Q: u8 = 3;

/// How the fragments of a span are tested and written.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Output {
    pub mode: Perspective,
    pub blend: Blend,
    pub test: DepthTest,
    pub write: bool,
}

impl Output {
    /// Whether the spans take the opaque loops
    /// ([`SpanInput::run_opaque`]): an opaque draw with the default depth
    /// test and depth writes. Decided once per triangle and tile.
    #[inline(always)]
    pub(crate) fn opaque(&self) -> bool {
        self.blend == Blend::Opaque && self.write && self.test == DepthTest::LessEqual
    }

    /// Whether the spans take the opaque affine loops: an
    /// [`opaque`](Self::opaque) draw in [`Perspective::Affine`].
    #[inline(always)]
    pub(crate) fn affine_opaque(&self) -> bool {
        self.mode == Perspective::Affine && self.opaque()
    }

    /// Whether the spans take the opaque quasi-perspective loop: an
    /// [`opaque`](Self::opaque) draw in [`Perspective::Quasi8`] or
    /// [`Perspective::Quasi16`].
    #[inline(always)]
    pub(crate) fn quasi_opaque(&self) -> bool {
        matches!(self.mode, Perspective::Quasi8 | Perspective::Quasi16) && self.opaque()
    }
}

/// The [`SpanInput`] of span `sp` of triangle `t` set up as `p`, whose
/// pixels are `color` and `depth` (the span's part of its tile rows).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn span_input<'a, C, V: Varyings>(
    p: &'a PerspectiveSetup<V>,
    colour: Option<&'a ColourPlanes<'a>>,
    t: &Corners<'_>,
    texture: Option<&'a Texture<'a>>,
    out: Output,
    color: &'a mut [C],
    depth: &'a mut [u16],
    sp: SpanPos,
    opaque: bool,
) -> SpanInput<'a, C, V> {
    let SpanPos { j, x0, .. } = sp;
    let [pq, p1, p2] = &p.planes;
    SpanInput {
        draw: p.draw,
        x0,
        y: j,
        color,
        depth,
        texture,
        setup: p,
        z: (p.depth.z_start(t, x0, j) as u32) << (16 - Z_FRAC),
        gz: (p.depth.steps()[0] as u32) << (16 - Z_FRAC),
        planes: p.plane_starts(x0, j),
        steps: [pq.step(), p1.step(), p2.step()],
        colour,
        mode: out.mode,
        blend: out.blend,
        test: out.test,
        write: out.write,
        opaque,
    }
}

/// The colour constants and steps that [`SpanInput::run_colour_shifted`]
/// reads, per channel `c0 · 2^16 + 2^15`, `c1 - c0`, `c2 - c0`, then the
/// steps of depth (as `SpanInput`'s `gz`), `Q`, `B1` and `B2`: all of them
/// the triangle's, so gathered once per triangle and tile
/// ([`TriangleSpans::each_colour`](crate::shader::TriangleSpans::each_colour))
/// rather than copied at every span (13 words loaded and stored a span).
#[inline(always)]
pub(crate) fn colour_constants<V: Varyings>(p: &PerspectiveSetup<V>) -> [i32; 13] {
    let [base, e1, e2] = p.color;
    let [pq, p1, p2] = &p.planes;
    [
        base[0],
        e1[0],
        e2[0],
        base[1],
        e1[1],
        e2[1],
        base[2],
        e1[2],
        e2[2],
        ((p.depth.steps()[0] as u32) << (16 - Z_FRAC)) as i32,
        pq.step(),
        p1.step(),
        p2.step(),
    ]
}

/// What [`colour_span_flat`] reads: the colour constants and steps of
/// [`SpanInput::run_colour_shifted`], the span's shift and reciprocal,
/// depth and `B1`, `B2` at its first pixel.
struct ColourSpan<'a> {
    k: &'a [i32; 13],
    sh: u32,
    r: u32,
    z: u32,
    b: [i32; 2],
    x0: i32,
}

/// One pixel of the colour loops ([`colour_span_flat`] and
/// [`SpanInput::run_colour_shifted`]): at depth `$z`, if it passes the test
/// against `*$d`, the colour from the constants `$k` at the weights (taken
/// only then), the fragment at `$x`, written to `*$c` and `*$d`; a pixel
/// that fails the test or the fragment adds one to `$fails`. A macro, so
/// that each loop is its own code written out: the flat one keeps its
/// failures behind `black_box`, the other its reads (see there).
macro_rules! colour_pixel {
    ($c:ident, $d:ident, $z:ident, $x:expr, $k:ident, $weights:expr, $fragment:ident, $fails:expr) => {
        let zz = depth16($z);
        if zz <= *$d {
            let (w1, w2) = $weights;
            let color = [
                $k[0] + $k[1] * w1 + $k[2] * w2,
                $k[3] + $k[4] * w1 + $k[5] * w2,
                $k[6] + $k[7] * w1 + $k[8] * w2,
            ];
            let it = Interpolated {
                x: $x,
                depth: zz,
                varyings: V::zeroed(),
                color,
                fine: None,
                convex: false,
            };
            match $fragment.pixel(&it) {
                Some(out) => {
                    *$c = out;
                    *$d = zz;
                }
                None => $fails += 1,
            }
        } else {
            $fails += 1;
        }
    };
}

/// [`SpanInput::run_colour_shifted`]'s loop for a span whose `Q` does not
/// change ([`FLAT_Q`] weights), out of line: inlined into the tile's
/// shading function, its values were kept in stack slots and moved
/// between registers at every pixel.
#[inline(never)]
fn colour_span_flat<C, V: Varyings, F: PixelFn<V, C>>(
    color: &mut [C],
    depth: &mut [u16],
    s: &ColourSpan,
    fragment: &mut F,
) -> u32 {
    let k = s.k;
    let (sh, r) = (s.sh & 15, s.r);
    let [mut b1, mut b2] = s.b;
    let mut z = s.z;
    let len = color.len() as u32;
    let mut fails = [0u32];
    let fails = core::hint::black_box(&mut fails);
    for (i, (c, d)) in color.iter_mut().zip(depth.iter_mut()).enumerate() {
        colour_pixel!(
            c,
            d,
            z,
            s.x0 + i as i32,
            k,
            flat_weights(b1, b2, sh, r),
            fragment,
            fails[0]
        );
        z = z.wrapping_add(k[9] as u32);
        b1 = b1.wrapping_add(k[11]);
        b2 = b2.wrapping_add(k[12]);
    }
    len - fails[0]
}

impl<C, V: Varyings> SpanInput<'_, C, V> {
    /// For an exact-mode span: the shift that normalises `Q` to 16
    /// significant bits in [`weights`], if it is the same at every pixel
    /// and none of `weights`' clamps changes a value there; `None`
    /// otherwise. That holds when, at both ends of the span, `Q` is in
    /// `1..2^31` with the same number of bits and `0 <= B1, B2 <= Q`: the
    /// planes are linear along the span (their wrapping steps are exact
    /// while the values stay in `i32`), so what holds at its ends holds
    /// between, and `B >> sh <= Q >> sh` follows from `B <= Q`. Checked
    /// once per span in `i32` with overflow checks ([`span_shift`]): a span
    /// whose ends overflow takes the clamped loop.
    #[inline(always)]
    pub(crate) fn opaque_shift(&self) -> Option<u32> {
        span_shift(self.planes, self.steps, self.color.len())
    }

    /// [`opaque_shift`](Self::opaque_shift) in `i64` (the same answer),
    /// on a 64-bit host only, where its sums and products
    /// are single instructions and need no overflow checks: for a shader
    /// with varyings that interpolates the colour (`TexturedLit`). x86-64
    /// `demo-textured-lit` 6,915,378 -> 6,901,401 instructions,
    /// `fill-lit-exact` 116.90 -> 116.69 a fragment; for every shader,
    /// `fill-gouraud-exact` took 77.97 -> 80.66 and `fill-bilinear-exact`
    /// 167.49 -> 169.27 (their loops' code moved). With it, whether the
    /// weights sum to one at most along the span ([`span_shift_convex`]:
    /// the colour then needs no clamp). With `CONVEX_ONLY`, `None` for
    /// the spans that are not convex too, for a shader without varyings
    /// (`Gouraud`), which takes those through the general loop: fewer
    /// tests (see [`span_shift_convex`]).
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub(crate) fn opaque_shift_convex<const CONVEX_ONLY: bool>(&self) -> Option<(u32, bool)> {
        span_shift_convex::<CONVEX_ONLY>(self.planes, self.steps, self.color.len())
    }

    /// `opaque_shift_convex` (64-bit hosts) in `i32`
    /// ([`span_shift_convex32`]), on cores without a 64-bit product.
    #[cfg(microraster_narrow_multiply)]
    #[inline(always)]
    pub(crate) fn opaque_shift_convex32(&self) -> Option<(u32, bool)> {
        span_shift_convex32(self.planes, self.steps, self.color.len())
    }

    /// The span loop of an opaque draw with the default depth test
    /// (`LessEqual`) and depth writes: [`run`](Self::run) with the test,
    /// the write and the blend known, so nothing but the depth comparison
    /// branches per pixel. `WEIGHTS` is [`AFFINE`] (or [`AFFINE_SUMS`], its
    /// sums stepped where [`STEP_AFFINE`]), or for exact mode
    /// [`SHIFTED`], the weights with the span's shift `sh`
    /// ([`opaque_shift`](Self::opaque_shift): the bits of [`weights`],
    /// without its clamps and normalisation), or [`CLAMPED`], [`weights`]
    /// itself (spans too short for the test, or that fail it). A shader
    /// that reads neither varyings nor colour runs with `AFFINE`. With
    /// `CONVEX`, the colour takes no clamp (the caller checked the span's
    /// weights: `span_shift_convex` and its 32-bit form); nor does the
    /// colour planes' ([`ColourPlanes::start`]).
    #[inline(always)]
    pub(crate) fn run_opaque<const WEIGHTS: u8, const CONVEX: bool>(
        self,
        ic: bool,
        mut fragment: impl PixelFn<V, C>,
        sh: u32,
    ) -> u32 {
        // The pixels that fail counted on Thumb-2 (see below), and in the
        // convex loops of a shader that reads the colour and no varyings
        // (`Gouraud`) on a 64-bit host: x86-64 `fill-gouraud-exact` 51.68
        // -> 50.88 a fragment (for `TexturedLit` too,
        // `knot1k-textured-lit` took +44 K).
        let fails_counted = (COLOUR_LOOP
            || (CONVEX && V::LEN == 0 && cfg!(target_pointer_width = "64")))
            && WEIGHTS != AFFINE
            && WEIGHTS != AFFINE_SUMS;
        let (x0, p, gz) = (self.x0, self.setup, self.gz);
        let [mut q, mut b1, mut b2] = self.planes;
        let [gq, g1, g2] = self.steps;
        let mut z = self.z;
        let weighted = V::LEN > 0 || ic;
        // On Thumb-2 ([`COLOUR_LOOP`]) the exact loops count the pixels
        // that fail rather than those written, as `run_colour_shifted`
        // does: nothing to count on the common path, and one value fewer
        // held across a written pixel (the count had a stack slot, loaded,
        // incremented and stored at every pixel). Cortex-M3 instructions
        // per fragment: `fill-nearest-exact` 72.2 -> 68.4,
        // `fill-bilinear-exact` 164.2 -> 161.1, `fill-lit-exact` 117.2 ->
        // 112.3. Not in affine mode (`fill-nearest-affine` 53.1 -> 59.2
        // with it), nor on x86-64 (`fill-lit-exact` 128.4 -> 129.4,
        // `demo-textured-lit` +0.6 %).
        let len = self.color.len() as u32;
        let r = if WEIGHTS == FLAT_Q {
            span_reciprocal(q, sh)
        } else {
            0
        };
        // Where `STEP_AFFINE` (ARMv6-M), each varying's affine sum stepped
        // by one 64-bit addition a pixel, its products taken once a span.
        // Only in the affine copy (`AFFINE_SUMS`): in the general one's
        // affine loop it moved the exact loops' registers (ARMv6-M
        // `demo-textured-lit` 12,469,072 -> 12,882,252).
        let stepped = WEIGHTS == AFFINE_SUMS && STEP_AFFINE && V::LEN > 0 && V::LEN <= STEPPED;
        let (mut sums, dsums) = if stepped {
            p.affine_sums((b1, b2), (g1, g2))
        } else {
            ([0; STEPPED], [0; STEPPED])
        };
        // With `AFFINE_SUMS` (the affine copy's `shade_affine`, whose
        // spans have them) the colour planes' colour, stepped: a constant
        // (tested at run time, ARMv6-M's `demo-textured-lit` +7 %).
        let planes = ic && WEIGHTS == AFFINE_SUMS;
        debug_assert!(!planes || self.colour.is_some(), "no colour planes");
        let (mut col, gcol) = match self.colour.filter(|_| planes) {
            Some(c) => c.start(x0, self.y),
            None => ([0; 3], [0; 3]),
        };
        let mut fails = 0;
        let mut n = 0;
        for (k, (c, d)) in self.color.iter_mut().zip(self.depth.iter_mut()).enumerate() {
            let zz = depth16(z);
            if zz <= *d {
                let (varyings, color, fine) = if !weighted {
                    (V::zeroed(), [0; 3], None)
                } else if WEIGHTS == AFFINE || WEIGHTS == AFFINE_SUMS {
                    // The sums from the differences of `dvar` where `fits`
                    // tested them ([`FIT_PRODUCTS`]: the opaque loops take
                    // only such triangles there), else from the vertex
                    // values. (Chosen by a flag in each span saying which
                    // of the renderer's copies it is in, the test was not
                    // folded away: ARMv6-M's `demo-textured-lit` +7 %.)
                    let (v, c, f) = if stepped {
                        p.values_stepped(&sums, (b1, b2), ic && !planes)
                    } else {
                        p.values_affine::<FIT_PRODUCTS>((b1, b2), ic && !planes)
                    };
                    // A convex span's colour on a 64-bit host: red and
                    // green from one product pair (`color_convex`).
                    #[cfg(target_pointer_width = "64")]
                    let c = if CONVEX && ic && !planes {
                        p.color_convex((b1 >> 12, b2 >> 12))
                    } else {
                        c
                    };
                    (v, if planes { col } else { c }, Some(f))
                } else if WEIGHTS == SHIFTED {
                    p.values_fit(shifted_weights(q, b1, b2, sh), ic, false, CONVEX)
                } else if WEIGHTS == FLAT_Q {
                    p.values_fit(flat_weights(b1, b2, sh, r), ic, false, CONVEX)
                } else {
                    p.values_fit(weights_guessed(q, b1, b2), ic, false, false)
                };
                let it = Interpolated {
                    x: x0 + k as i32,
                    depth: zz,
                    varyings,
                    color,
                    fine,
                    // The colour planes' bytes need no clamp (see
                    // `ColourPlanes::start`).
                    convex: CONVEX || planes,
                };
                match fragment.pixel(&it) {
                    Some(out) => {
                        *c = out;
                        *d = zz;
                        n += !fails_counted as u32;
                    }
                    None => fails += fails_counted as u32,
                }
            } else {
                fails += fails_counted as u32;
            }
            z = z.wrapping_add(gz);
            if WEIGHTS != FLAT_Q {
                q = q.wrapping_add(gq);
            }
            b1 = b1.wrapping_add(g1);
            b2 = b2.wrapping_add(g2);
            if planes {
                for (c, g) in col.iter_mut().zip(gcol) {
                    *c = c.wrapping_add(g);
                }
            }
            if stepped {
                for (s, d) in sums.iter_mut().zip(&dsums).take(V::LEN) {
                    *s = s.wrapping_add(*d);
                }
            }
        }
        if fails_counted {
            len - fails
        } else {
            n
        }
    }

    /// [`run_opaque`](Self::run_opaque) with [`SHIFTED`] weights for a
    /// shader that reads the colour and no varyings ([`Gouraud`]) (with
    /// `FLAT`, those of [`FLAT_Q`] for a span whose `Q` does not change), on
    /// Thumb-2 ([`COLOUR_LOOP`]): the same bits, with fewer registers
    /// held across the pixels. Inlined into the tile's shading function,
    /// the shared loop kept the plane steps, the count and the nine
    /// colour constants in stack slots and reloaded them one by one, with
    /// register moves between, at every pixel (65 instructions a pixel
    /// in `fill-gouraud-exact`). Here the constants and steps sit in one
    /// array read through a pointer that `black_box` hides, and a
    /// `black_box(())` per pixel (a compiler barrier, no instruction)
    /// keeps the compiler from hoisting those reads out of the loop: they
    /// are read where they are used, mostly in pairs (`LDRD`), and free
    /// the registers for the planes. The loop counts the pixels that fail
    /// rather than those written (nothing to count on the common path).
    /// 57 instructions a pixel; `fill-gouraud-exact` 75.3 -> 68.3 per
    /// fragment on the Cortex-M3. (Neither the barrier nor this loop
    /// helps x86-64: 87.1 -> 88.3 with, 90.3 without the barrier.)
    ///
    /// [`Gouraud`]: crate::shader::Gouraud
    #[inline(always)]
    pub(crate) fn run_colour_shifted<const FLAT: bool>(
        self,
        mut fragment: impl PixelFn<V, C>,
        sh: u32,
        k: &[i32; 13],
    ) -> u32 {
        let [mut q, mut b1, mut b2] = self.planes;
        let r = if FLAT { span_reciprocal(q, sh) } else { 0 };
        let mut z = self.z;
        if FLAT {
            let s = ColourSpan {
                k,
                sh,
                r,
                z,
                b: [b1, b2],
                x0: self.x0,
            };
            return colour_span_flat::<C, V, _>(self.color, self.depth, &s, &mut fragment);
        }
        let k = core::hint::black_box(k);
        let len = self.color.len() as u32;
        let mut fails = 0;
        let x0 = self.x0;
        for (i, (c, d)) in self.color.iter_mut().zip(self.depth.iter_mut()).enumerate() {
            core::hint::black_box(());
            colour_pixel!(
                c,
                d,
                z,
                x0 + i as i32,
                k,
                if FLAT {
                    flat_weights(b1, b2, sh, r)
                } else {
                    shifted_weights(q, b1, b2, sh)
                },
                fragment,
                fails
            );
            z = z.wrapping_add(k[9] as u32);
            if !FLAT {
                q = q.wrapping_add(k[10]);
            }
            b1 = b1.wrapping_add(k[11]);
            b2 = b2.wrapping_add(k[12]);
        }
        len - fails
    }

    /// The span loop: for each pixel that passes the depth test, the
    /// values there (weights and varyings only if there are varyings or
    /// `ic`, the colour only if `ic`), then `put` with the pixel's colour
    /// and depth, which returns whether it wrote. A fragment that fails
    /// the test costs no division. Returns the number written.
    #[inline(always)]
    pub(crate) fn run(self, ic: bool, mut put: impl PutPixel<V, C>) -> u32 {
        let SpanInput {
            x0,
            color,
            depth,
            setup: p,
            mut z,
            gz,
            planes: [mut q, mut b1, mut b2],
            steps: [gq, g1, g2],
            mode,
            test,
            ..
        } = self;
        let mut n = 0;
        // A shader that reads neither varyings nor colour needs no
        // weights: every pixel is then a depth test and the shader.
        let weighted = V::LEN > 0 || ic;
        let seg = if weighted { mode.segment() as i32 } else { 0 };
        if seg <= 1 {
            // Exact or affine: the weights at every pixel (affine: `Q` is
            // constant, so they are a shift of `B1`, `B2`).
            let affine = seg == 0;
            for (k, (c, d)) in color.iter_mut().zip(depth.iter_mut()).enumerate() {
                let zz = depth16(z);
                if test.passes(zz, *d) {
                    let (varyings, color) = if !weighted {
                        (V::zeroed(), [0; 3])
                    } else if affine {
                        let (v, c, _) = p.values_affine::<false>((b1, b2), ic);
                        (v, c)
                    } else {
                        p.values_weighted(weights(q, b1, b2), ic)
                    };
                    let it = Interpolated {
                        x: x0 + k as i32,
                        depth: zz,
                        varyings,
                        color,
                        fine: None,
                        convex: false,
                    };
                    n += put.put(&it, c, d) as u32;
                }
                z = z.wrapping_add(gz);
                q = q.wrapping_add(gq);
                b1 = b1.wrapping_add(g1);
                b2 = b2.wrapping_add(g2);
            }
            return n;
        }
        // Quasi-perspective: exact at the columns x = 0 (mod seg), at the
        // span's first and at its last pixel; linear between.
        quasi_segments!(
            (x0, color, depth, p),
            (z, gz, [q, b1, b2], [gq, g1, g2]),
            (ic, put, n, seg),
            |zz, d| test.passes(zz, *d)
        )
    }
}
