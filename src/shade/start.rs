//! A triangle's planes evaluated at the start of a span ([`TriangleSetup`]
//! set them up once a pair): depth alone for the flat span loops, all four
//! attributes clamped to their ranges (tested first, or taken as they are
//! for an interior triangle), shifted for the targets with SIMD, and the
//! steps along the span. The packed starts of 64-bit hosts are in
//! `packed`.

use super::setup::{Corners, TriangleSetup, C_HI, C_LO, Z_HI, Z_LO};
use super::sliver::wide_start;

impl TriangleSetup {
    /// Depth at the centre of pixel `(i, j)`, in `Z_LO..=Z_HI` (as
    /// [`TriangleSetup::start`], for depth alone).
    #[inline(always)]
    pub(crate) fn z_start(&self, t: &Corners<'_>, i: i32, j: i32) -> i32 {
        if self.wide {
            return wide_start(t, i, j)[0];
        }
        // Constant bounds: `clamp`'s check of them is done at compile
        // time. (A test and branch as in `start` made the flat span loops
        // slower on the Cortex-M3: `fill` 16.17 -> 17.10 per pixel.)
        self.planes[0].at(i, j).clamp(Z_LO, Z_HI)
    }
    /// The steps along a span of depth, red, green and blue.
    #[inline(always)]
    pub(super) fn steps(&self) -> [i32; 4] {
        [
            self.zstep,
            self.planes[1].step(),
            self.planes[2].step(),
            self.planes[3].step(),
        ]
    }

    /// Depth, red, green and blue at the centre of pixel `(i, j)`, for
    /// [`TriangleSetup::wide`] triangles from [`wide_start`].
    ///
    /// An [`interior`](TriangleSetup::interior) triangle's values are
    /// inside their ranges, and taken as they are. Any other triangle's
    /// values are each clamped to their range, but first tested: a covered
    /// pixel's values are almost always inside (see [`Plane`](super::plane::Plane)), and an
    /// unsigned comparison with a constant per attribute and a branch that
    /// is not taken cost less than two comparisons and selects per
    /// attribute with the bounds built in registers (the Cortex-M3).
    ///
    /// Where the target has SIMD for the span loops (64-bit hosts), the
    /// clamps as selects measured faster (x86-64 `demo` 5,248,309
    /// instructions, 5,264,430 with the tests; `rock` 4,406,488 and
    /// 4,407,977).
    // The span loops take `start_shifted` (targets with SIMD) or
    // `start_tested_as`: only the tests call this.
    #[cfg_attr(not(test), allow(dead_code))]
    #[inline(always)]
    pub(crate) fn start(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        if super::VECTOR_LOOPS {
            self.start_selects(t, i, j)
        } else {
            self.start_tested(t, i, j)
        }
    }

    /// [`TriangleSetup::start_selects`] of a set-up whose colour planes
    /// are shifted left by 8 ([`SHIFTED_COLOR`](super::setup::SHIFTED_COLOR)), with
    /// [`interior`](Self::interior) given (the span loops of an interior
    /// triangle are a copy of their own, see `SPLIT_INTERIOR`): depth as
    /// there, each channel shifted left by 8 (wrapping), clamped in that
    /// form.
    ///
    /// The clamp of a shifted channel is the channel's clamp shifted: a
    /// covered pixel's channel lies within 20,481 units of `C_LO..=C_HI`
    /// (see [`Plane`](super::plane::Plane)), within `12,287..=16,764,929`, inside `0..2^24`,
    /// where the shift, taken as `u32`, keeps the order.
    #[inline(always)]
    pub(super) fn start_shifted(
        &self,
        t: &Corners<'_>,
        i: i32,
        j: i32,
        interior: bool,
    ) -> [i32; 4] {
        const _: () = assert!(C_LO - 20_481 >= 0 && C_HI + 20_481 < 1 << 24);
        if interior {
            return self.values_at(i, j);
        }
        self.clamped_shifted(t, i, j, self.values_at(i, j))
    }

    /// The clamped starts of a shifted set-up's span that may leave the
    /// channels' range ([`TriangleSetup::start_shifted`]), from its values
    /// at the start `v`: a wide set-up's from the corners, clamped there,
    /// and shifted; any other's clamped in the shifted form.
    #[inline(always)]
    fn clamped_shifted(&self, t: &Corners<'_>, i: i32, j: i32, v: [i32; 4]) -> [i32; 4] {
        let shift = |c: i32| c.wrapping_shl(8);
        if self.wide {
            // Clamped already.
            let [z, r, g, b] = wide_start(t, i, j);
            return [z, shift(r), shift(g), shift(b)];
        }
        let [z, r, g, b] = v;
        let clamp = |c: i32| (c as u32).clamp(shift(C_LO) as u32, shift(C_HI) as u32) as i32;
        [z.clamp(Z_LO, Z_HI), clamp(r), clamp(g), clamp(b)]
    }

    /// [`TriangleSetup::start_tested_as`] of a set-up whose colour planes
    /// are shifted left by 8 ([`SHIFTED_TOP`](super::setup::SHIFTED_TOP):
    /// ARMv6-M), each channel shifted (wrapping): the starts of
    /// [`TriangleSetup::start_shifted`], tested before their clamps as
    /// `start_tested_as` tests. A covered pixel's channel lies inside
    /// `0..2^24` (see there), where the shift, taken as `u32`, keeps the
    /// order, so the shifted test and clamp are the plain ones shifted.
    #[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
    #[inline(always)]
    pub(super) fn start_tested_shifted(
        &self,
        t: &Corners<'_>,
        i: i32,
        j: i32,
        interior: bool,
    ) -> [i32; 4] {
        let shift = |c: i32| c.wrapping_shl(8);
        let v = self.values_at(i, j);
        let inside = |c: i32| (c.wrapping_sub(shift(C_LO)) as u32) < shift(C_HI - C_LO) as u32;
        if interior || z_inside(v[0]) && inside(v[1]) && inside(v[2]) && inside(v[3]) {
            v
        } else {
            self.clamped_shifted(t, i, j, v)
        }
    }

    /// [`TriangleSetup::start`] with the clamps as selects.
    // The span loops take `start_shifted` (targets with SIMD) or
    // `start_tested_as`: only the tests call this.
    #[cfg_attr(not(test), allow(dead_code))]
    #[inline(always)]
    pub(super) fn start_selects(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        if self.interior() {
            return self.values_at(i, j);
        }
        if self.wide {
            return wide_start(t, i, j);
        }
        clamped(self.values_at(i, j))
    }

    /// [`TriangleSetup::start`] with the values tested first.
    // The span loops take `start_shifted` (targets with SIMD) or
    // `start_tested_as`: only the tests call this.
    #[cfg_attr(not(test), allow(dead_code))]
    #[inline(always)]
    pub(super) fn start_tested(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 4] {
        self.start_tested_as(t, i, j, self.interior())
    }

    /// [`TriangleSetup::start_tested`] with [`interior`](Self::interior)
    /// given: the span loops of a triangle that is not interior test it
    /// once, not at every span start.
    #[inline(always)]
    pub(super) fn start_tested_as(
        &self,
        t: &Corners<'_>,
        i: i32,
        j: i32,
        interior: bool,
    ) -> [i32; 4] {
        if super::VECTOR_LOOPS && self.wide {
            // Where `start` takes `start_selects` (only the tests call this
            // there), `finish` leaves a wide triangle's depth plane as it
            // is.
            return wide_start(t, i, j);
        }
        let v = self.values_at(i, j);
        if interior || z_inside(v[0]) && c_inside(v[1]) && c_inside(v[2]) && c_inside(v[3]) {
            v
        } else {
            // Marked rare, so that the register allocator favours the
            // span loop over this path (the Cortex-M3's `demo` 4,610,743
            // -> 4,601,655 instructions, `rock` 3,767,471 -> 3,759,915);
            // not on the Thumb-1 targets, where it measured worse (ARMv6-M
            // `demo` 15,674,314 -> 15,741,570).
            #[cfg(not(microraster_narrow_multiply))]
            crate::hint::cold();
            // On this rare path the set-up escapes, so that, as far as the
            // optimiser knows, its planes may change from span to span: it
            // then reads them per span where the set-up left them, rather
            // than loading them all before the span loop and copying them
            // to spill slots (26 instructions per triangle-tile pair on the
            // Cortex-M3; `demo` 4,821,094 -> 4,805,038 instructions). Not
            // on the Thumb-1 targets (the build script's cfg for them),
            // with their eight low registers: the copy measured cheaper
            // there (ARMv6-M `demo` 15,851,848, 15,874,675 with it).
            #[cfg(not(microraster_narrow_multiply))]
            core::hint::black_box(self);
            // A wide triangle's depth plane fails `z_inside` everywhere.
            // `wide_start`'s values are clamped already, and clamped again
            // they stay: the values meet the fast path's in registers.
            clamped(if self.wide { wide_start(t, i, j) } else { v })
        }
    }

    /// Red, green and blue at the centre of pixel `(i, j)`: the colour of
    /// [`TriangleSetup::start_tested_as`] (not interior), without its
    /// depth, whose plane and test that start took for colour planes
    /// alone ([`ColourPlanes`](super::ColourPlanes)). The same values: a
    /// channel inside its range is left by the clamp, and a wide
    /// triangle's come from [`wide_start`] either way.
    #[inline(always)]
    pub(super) fn colour_start(&self, t: &Corners<'_>, i: i32, j: i32) -> [i32; 3] {
        if self.wide {
            let [_, r, g, b] = wide_start(t, i, j);
            return [r, g, b];
        }
        let v = [
            self.planes[1].at(i, j),
            self.planes[2].at(i, j),
            self.planes[3].at(i, j),
        ];
        if c_inside(v[0]) && c_inside(v[1]) && c_inside(v[2]) {
            v
        } else {
            // Rare, as in `start_tested_as`.
            #[cfg(not(microraster_narrow_multiply))]
            crate::hint::cold();
            v.map(|c| c.clamp(C_LO, C_HI))
        }
    }

    /// Depth, red, green and blue at the centre of pixel `(i, j)` of an
    /// [`interior`](Self::interior) triangle, depth shifted left by
    /// `16 - Z_FRAC` (wrapping) as the Gouraud span loop steps it: the
    /// same values as [`TriangleSetup::start_tested_as`]'s, depth then
    /// shifted.
    ///
    /// An interior triangle is not [`wide`](Self::wide), so its depth step
    /// is its depth plane's `gx` shifted ([`TriangleSetup::for_gouraud_spans`]),
    /// and modulo 2^32 `(k + gy j + gx i) << s` is `((k + gy j) << s) +
    /// (gx << s) i`: the start takes the step, which the span loop holds
    /// anyway, for `gx`.
    #[cfg_attr(not(any(test, microraster_armv7m)), allow(dead_code))]
    #[inline(always)]
    pub(super) fn start_interior_depth_shifted(&self, i: i32, j: i32) -> [i32; 4] {
        let z = &self.planes[0];
        let row = (z.k.wrapping_add(z.gy.wrapping_mul(j)) as u32) << (16 - super::Z_FRAC);
        [
            (row as i32).wrapping_add(self.zstep.wrapping_mul(i)),
            self.planes[1].at(i, j),
            self.planes[2].at(i, j),
            self.planes[3].at(i, j),
        ]
    }

    /// Depth, red, green and blue of the planes at the centre of pixel
    /// `(i, j)`, before any clamp.
    #[inline(always)]
    fn values_at(&self, i: i32, j: i32) -> [i32; 4] {
        [
            self.planes[0].at(i, j),
            self.planes[1].at(i, j),
            self.planes[2].at(i, j),
            self.planes[3].at(i, j),
        ]
    }
}

/// Depth, red, green and blue clamped to their ranges (constant bounds:
/// `clamp`'s check of them is done at compile time).
#[inline(always)]
fn clamped([z, r, g, b]: [i32; 4]) -> [i32; 4] {
    [
        z.clamp(Z_LO, Z_HI),
        r.clamp(C_LO, C_HI),
        g.clamp(C_LO, C_HI),
        b.clamp(C_LO, C_HI),
    ]
}

/// Whether depth `z` is surely in `Z_LO..=Z_HI`: a conservative test (by
/// a constant an instruction can hold; depths of 65,280 and more fail it
/// and take the clamp, which leaves them as they are). Wrapping: a wide
/// triangle's depth plane gives `i32::MIN`.
#[inline(always)]
fn z_inside(z: i32) -> bool {
    const _: () = assert!(0x3FC0_0000 <= Z_HI - Z_LO);
    (z.wrapping_sub(Z_LO) as u32) < 0x3FC0_0000
}

/// Whether colour channel `c` is surely in `C_LO..=C_HI`: `C_HI` itself
/// fails (and takes the clamp, which leaves it), so that the constant
/// `C_HI - C_LO` fits an instruction.
#[inline(always)]
fn c_inside(c: i32) -> bool {
    (c.wrapping_sub(C_LO) as u32) < (C_HI - C_LO) as u32
}
