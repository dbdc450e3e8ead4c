//! [`WithPlanes`]: a span's per-pixel function given the colour of its
//! triangle's colour planes (an opaque affine span of the renderer's
//! affine copy, whose shader reads the colour: see
//! [`ColourPlanes`]), for the span loops that do not step it themselves.

use super::span::{Interpolated, PixelFn, SpanInput};
#[allow(unused_imports)] // the rustdoc links
use crate::shade::ColourPlanes;

/// A pixel function given the colour of the colour planes
/// ([`ColourPlanes::start`]) of an affine span starting at column `x0`:
/// `col` there, stepped by `gcol` a pixel, as the opaque loops step it.
pub(super) struct WithPlanes<F> {
    fragment: F,
    col: [i32; 3],
    gcol: [i32; 3],
    x0: i32,
}

impl<F> WithPlanes<F> {
    /// `fragment` given the planes' colour where the span has colour
    /// planes and the colour is interpolated (`Ok`), else as it is.
    #[inline(always)]
    pub(super) fn of<C, V>(
        span: &SpanInput<'_, C, V>,
        interpolate_color: bool,
        fragment: F,
    ) -> Result<Self, F> {
        match span.colour.filter(|_| interpolate_color) {
            Some(planes) => {
                let (col, gcol) = planes.start(span.x0, span.y);
                Ok(Self {
                    fragment,
                    col,
                    gcol,
                    x0: span.x0,
                })
            }
            None => Err(fragment),
        }
    }
}

impl<V: Copy, C, F: PixelFn<V, C>> PixelFn<V, C> for WithPlanes<F> {
    #[inline(always)]
    fn pixel(&mut self, p: &Interpolated<V>) -> Option<C> {
        let k = p.x.wrapping_sub(self.x0);
        let (c, g) = (self.col, self.gcol);
        let color = [0, 1, 2].map(|i| c[i].wrapping_add(g[i].wrapping_mul(k)));
        // In range: no clamp (see `ColourPlanes::start`).
        self.fragment.pixel(&Interpolated {
            color,
            convex: true,
            ..*p
        })
    }
}
