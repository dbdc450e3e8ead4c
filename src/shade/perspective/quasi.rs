//! Quasi-perspective span loops ([`Perspective::Quasi8`],
//! [`Perspective::Quasi16`]): the values exact at the screen columns
//! `x = 0 (mod N)` and at a span's first and last pixels, and linear in
//! between: the subdivided span of the classic software texture mappers
//! (C. Hecker, *Perspective Texture Mapping*, Game Developer, 1995–96;
//! the Quake technique). The samples sit at screen columns, not at span
//! offsets, so the picture does not depend on the tile width.
//!
//! Each segment's steps are `(next - this) / l`, rounded, from a table of
//! reciprocals (`2^24 / l`), in wrapping `i32`: exact modulo 2^32, and the
//! next sample starts again from exact values, so nothing drifts past a
//! segment. The general loop tests and writes each pixel as the draw says
//! ([`PutPixel`]); an opaque draw's ([`Output::opaque`](super::Output::opaque))
//! takes the same loop with the `LessEqual` test and the write known.
//!
//! [`Perspective::Quasi8`]: crate::shader::Perspective::Quasi8
//! [`Perspective::Quasi16`]: crate::shader::Perspective::Quasi16

use super::*;

/// `round(2^24 / l)` for segment lengths `l` of 1 to 16.
pub(super) const RECIPROCAL: [i64; 17] = {
    let mut t = [0i64; 17];
    let mut l = 1;
    while l <= 16 {
        t[l] = ((1i64 << 25) / l as i64 + 1) >> 1;
        l += 1;
    }
    t
};

/// The quasi-perspective segments of a span, for [`SpanInput::run`] and
/// [`SpanInput::run_quasi_opaque`]: the span's locals by name (where the
/// span is, its depth and planes with their steps, and how it is
/// coloured), and whether pixel `$d` passes at depth `$zz` as an
/// expression of them. A macro
/// rather than a function, so that `run`'s loop is the code written out:
/// as a call of a function of its own, even inlined, it changed that
/// loop's code on the Cortex-M3 (`demo-textured-lit` 6,932,924 ->
/// 6,966,901 instructions) and on x86-64 (`fill-gouraud-exact` 47.76 ->
/// 49.66 a fragment).
macro_rules! quasi_segments {
    (
        ($x0:ident, $color:ident, $depth:ident, $p:ident),
        ($z:ident, $gz:ident, [$q:ident, $b1:ident, $b2:ident], [$gq:ident, $g1:ident, $g2:ident]),
        ($ic:ident, $put:ident, $n:ident, $seg:ident),
        |$zz:ident, $d:ident| $passes:expr
    ) => {{
        let len = $color.len() as i32;
        let (mut var, mut col) = $p.values(signed_weights($q, $b1, $b2), $ic);
        let mut k = 0;
        while k < len {
            let l = segment_length($seg, $x0 + k, len - k);
            let (mut dv, mut dc) = (V::zeroed(), [0i32; 3]);
            let (mut nvar, mut ncol) = (var, col);
            if l > 0 {
                // One pixel beyond the span's end, the weights may be a
                // little negative.
                let w = signed_weights(
                    $q.wrapping_add($gq.wrapping_mul(l)),
                    $b1.wrapping_add($g1.wrapping_mul(l)),
                    $b2.wrapping_add($g2.wrapping_mul(l)),
                );
                (nvar, ncol) = $p.values(w, $ic);
                let r = RECIPROCAL[l as usize];
                for (s, (a, b)) in dv
                    .as_mut_slice()
                    .iter_mut()
                    .zip(var.as_slice().iter().zip(nvar.as_slice()))
                {
                    *s = I16F16::from_bits(segment_step(a.to_bits(), b.to_bits(), r));
                }
                if $ic {
                    for ch in 0..3 {
                        dc[ch] = segment_step(col[ch], ncol[ch], r);
                    }
                }
            }
            // Pixels k..k + l step from the exact values at k; the last
            // pixel of the span (l = 0) is drawn from exact values too.
            let stop = if l == 0 { k + 1 } else { k + l };
            for m in k as usize..stop as usize {
                let $zz = depth16($z);
                if let (Some(c), Some($d)) = ($color.get_mut(m), $depth.get_mut(m)) {
                    if $passes {
                        let it = Interpolated {
                            x: $x0 + m as i32,
                            depth: $zz,
                            varyings: var,
                            color: col,
                            fine: None,
                            convex: false,
                        };
                        $n += $put.put(&it, c, $d) as u32;
                    }
                }
                $z = $z.wrapping_add($gz);
                for (a, s) in var.as_mut_slice().iter_mut().zip(dv.as_slice()) {
                    *a = I16F16::from_bits(a.to_bits().wrapping_add(s.to_bits()));
                }
                for ch in 0..3 {
                    col[ch] = col[ch].wrapping_add(dc[ch]);
                }
            }
            let li = stop - k;
            $q = $q.wrapping_add($gq.wrapping_mul(li));
            $b1 = $b1.wrapping_add($g1.wrapping_mul(li));
            $b2 = $b2.wrapping_add($g2.wrapping_mul(li));
            (var, col) = (nvar, ncol);
            k = stop;
        }
        $n
    }};
}
pub(super) use quasi_segments;

impl<C, V: Varyings> SpanInput<'_, C, V> {
    /// The quasi-perspective loop of an opaque draw in a quasi-perspective
    /// frame: [`run`](Self::run)'s, with the `LessEqual` test and `put`
    /// writing colour and depth.
    #[inline(always)]
    pub(crate) fn run_quasi_opaque(self, ic: bool, mut put: impl PutPixel<V, C>) -> u32 {
        let (x0, p, gz, seg) = (self.x0, self.setup, self.gz, self.mode.segment() as i32);
        let ([mut q, mut b1, mut b2], [gq, g1, g2]) = (self.planes, self.steps);
        let (color, depth, mut z, mut n) = (self.color, self.depth, self.z, 0);
        quasi_segments!(
            (x0, color, depth, p),
            (z, gz, [q, b1, b2], [gq, g1, g2]),
            (ic, put, n, seg),
            |zz, d| zz <= *d
        )
    }
}

/// How a quasi-perspective span's segments are drawn ([`quasi_span`]):
/// the values a sample holds, the steps between two samples, and the
/// pixels of one segment.
pub(super) trait Segments<C> {
    /// The values at a sample, or their steps per pixel.
    type Values: Copy;
    /// The values at the weights of the planes' values `q`, `b1`, `b2`
    /// ([`signed_weights`]).
    fn sample(&self, q: i32, b1: i32, b2: i32) -> Self::Values;
    /// The steps per pixel from `from` to `to` over a segment whose
    /// length's reciprocal is `r` ([`segment_step`]).
    fn steps(&self, from: &Self::Values, to: &Self::Values, r: i64) -> Self::Values;
    /// No steps (the span's last pixel, a segment of its own).
    fn still(&self) -> Self::Values;
    /// Draws a segment's pixels, the first at depth `z` with values `at`,
    /// stepped by `steps`: returns the pixels that failed the depth test
    /// and the depth after the last.
    fn pixels(
        &mut self,
        color: &mut [C],
        depth: &mut [u16],
        z: u32,
        at: Self::Values,
        steps: Self::Values,
    ) -> (u32, u32);
}

/// A quasi-perspective span of an opaque draw, segment by segment, in a
/// loop of its own (`nearest_quasi_span`): the segments of
/// [`quasi_segments!`], exact values at its first pixel and at each
/// sample ([`segment_length`]), and `s`'s pixels stepped linearly from one
/// to the next. `(seg, x0)` are
/// the segment length and the span's first column; `(z, planes, steps)`
/// the depth and the planes `Q`, `B1`, `B2` at its first pixel, and the
/// planes' steps. Returns the pixels written.
#[inline(always)]
pub(super) fn quasi_span<C, S: Segments<C>>(
    color: &mut [C],
    depth: &mut [u16],
    s: &mut S,
    (seg, x0): (i32, i32),
    (mut z, [mut q, mut b1, mut b2], [gq, g1, g2]): (u32, [i32; 3], [i32; 3]),
) -> u32 {
    let len = color.len() as i32;
    let mut fails = 0;
    let mut at = s.sample(q, b1, b2);
    let mut pos = 0;
    while pos < len {
        let l = segment_length(seg, x0 + pos, len - pos);
        let (mut steps, mut next) = (s.still(), at);
        if l > 0 {
            // One pixel beyond the span's end, the weights may be a
            // little negative (`signed_weights`).
            next = s.sample(
                q.wrapping_add(gq.wrapping_mul(l)),
                b1.wrapping_add(g1.wrapping_mul(l)),
                b2.wrapping_add(g2.wrapping_mul(l)),
            );
            steps = s.steps(&at, &next, RECIPROCAL[l as usize]);
        }
        // Pixels pos..pos + l step from the exact values at pos; the last
        // pixel of the span (l = 0) is drawn from exact values too.
        let stop = if l == 0 { pos + 1 } else { pos + l };
        let (a, b) = (pos as usize, stop as usize);
        if let (Some(cs), Some(ds)) = (color.get_mut(a..b), depth.get_mut(a..b)) {
            let (failed, zn) = s.pixels(cs, ds, z, at, steps);
            fails += failed;
            z = zn;
        }
        let li = stop - pos;
        q = q.wrapping_add(gq.wrapping_mul(li));
        b1 = b1.wrapping_add(g1.wrapping_mul(li));
        b2 = b2.wrapping_add(g2.wrapping_mul(li));
        at = next;
        pos = stop;
    }
    len as u32 - fails
}

/// Pixels from column `x` (with `left` pixels of the span from it) to the
/// next sample: the next column that is a multiple of `seg` (a power of
/// two) if the span reaches it or ends just before it (a tile cut there
/// leaves the samples where they were), or else the span's last pixel (0
/// at the last pixel itself, which is drawn from its exact values).
#[inline(always)]
pub(super) fn segment_length(seg: i32, x: i32, left: i32) -> i32 {
    let next = seg - (x & (seg - 1));
    if next <= left {
        next
    } else {
        left - 1
    }
}

/// The step per pixel from `from` to `to` over a segment whose length's
/// reciprocal is `r` (2^24 / l), rounded: the differences are below 2^32,
/// times 2^24, so nothing overflows; the result wraps to `i32` like the
/// values it steps.
#[inline(always)]
pub(super) fn segment_step(from: i32, to: i32, r: i64) -> i32 {
    (((to as i64 - from as i64) * r + (1 << 23)) >> 24) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reciprocals_round() {
        for (l, &r) in RECIPROCAL.iter().enumerate().skip(1) {
            let exact = (1u64 << 24) as f64 / l as f64;
            assert!((r as f64 - exact).abs() <= 0.5);
        }
    }
}
