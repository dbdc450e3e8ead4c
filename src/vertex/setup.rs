//! A draw's set-up in fixed point ([`DrawSetup`]): its model-view-projection
//! matrix normalized and converted once to 16.16, its lights moved into
//! model space (one directional light on a plain material through a
//! dozen-instruction fast path, any other lighting through
//! [`LightSetup`]), and per vertex the clip-space position and lit colour
//! ([`DrawSetup::clip_vertex`]).

use super::lambert::Lambert;
use super::lit_loop::{lit_loop, DUPLICATE};
use super::lit_work::{loop_takes, LoopConstants, NarrowRows, LOOP_CONSTANTS};
use super::{ClipVertex, ScreenVertex, Viewport};
use crate::light::{LightSetup, Lighting, Material};
use crate::math::{FixedMat4, Mat4, Vec3};
use crate::mesh::Mesh;
use crate::scene::Draw;

/// Why the vertex stage refused a draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexError {
    /// A matrix (model, view or projection, or their product) has a
    /// non-finite element, or the product cannot be represented in 16.16
    /// even normalized ([`Mat4::to_fixed_normalized`]: zero or nearly so,
    /// or a row lost next to the largest element).
    BadMatrix,
    /// A transformed vertex left the 16.16 range of clip space.
    OutOfRange {
        /// Index of the vertex within its mesh.
        vertex: usize,
    },
    /// The draw needs the general lighting (more than one light, a point
    /// light, fog, or a material other than white and matte), which the
    /// renderer does not link
    /// ([`Features::LIGHTING`](crate::render::Features::LIGHTING)).
    GeneralLighting,
}

/// Everything the vertex stage needs for one draw, in fixed point.
#[derive(Clone, Copy, Debug)]
pub struct DrawSetup {
    mvp: FixedMat4,
    /// `mvp` cannot overflow on this draw's mesh (see
    /// [`FixedMat4::bounded`]), so vertices take the unchecked transform.
    bounded: bool,
    /// On cores without a 32 x 32 -> 64-bit multiply (ARMv6-M), `mvp` is
    /// also [`narrow`](FixedMat4::narrow) for the mesh: the vertex loop
    /// transforms in 32-bit products. Always `false` elsewhere.
    narrow: bool,
    light: Option<LightSetup<MAX_LIGHTS>>,
    /// The same lighting when it is one directional light on a white
    /// material without highlights or fog: a dozen instructions per vertex
    /// instead of the general loop, same colours.
    lambert: Option<Lambert>,
    /// The general lighting loop, when the set-up links it and the fast
    /// path does not apply: through a pointer, so that a set-up made
    /// without it (`with_lighting::<false>`) does not link it at all.
    general: Option<GeneralShade>,
    material: Material,
    color: [u8; 3],
}

/// [`LightSetup::shade`] as a function pointer.
type GeneralShade = fn(&LightSetup<MAX_LIGHTS>, &Material, [u8; 3], [i32; 3], [i32; 3]) -> [u8; 3];

fn rgb(c: embedded_graphics::pixelcolor::Rgb888) -> [u8; 3] {
    use embedded_graphics::prelude::RgbColor;
    [c.r(), c.g(), c.b()]
}

/// Most lights (directional and point together) a frame's
/// [`Lighting`] may hold: the size of the per-draw set-up, which lives on
/// the stack while a frame renders (56 bytes per light).
pub const MAX_LIGHTS: usize = 8;

impl DrawSetup {
    /// Converts a draw's `f32` set-up to fixed point. Deterministic: the
    /// same inputs always give the same bits, which the tile loop relies on
    /// when it redoes this for clipped triangles.
    pub fn new(
        draw: &Draw<'_>,
        view_proj: &Mat4,
        lighting: Option<&Lighting<'_>>,
        eye: Vec3,
    ) -> Result<Self, VertexError> {
        Self::with_lighting::<true>(draw, view_proj, lighting, eye)
    }

    /// [`new`](Self::new), linking the general lighting loop only with
    /// `GENERAL`; without it, a draw that needs more than the fast path
    /// (one directional light on a white, matte material) is
    /// [`VertexError::GeneralLighting`].
    pub fn with_lighting<const GENERAL: bool>(
        draw: &Draw<'_>,
        view_proj: &Mat4,
        lighting: Option<&Lighting<'_>>,
        eye: Vec3,
    ) -> Result<Self, VertexError> {
        let mvp = (*view_proj * draw.transform).normalized();
        let mut slot = None;
        Self::new_in::<GENERAL>(&mut slot, draw, mvp.as_ref(), lighting, eye)?;
        slot.ok_or(VertexError::BadMatrix)
    }

    /// [`with_lighting`](Self::with_lighting) from `view_proj *
    /// draw.transform` already [`normalized`](Mat4::normalized) (`None`
    /// where that failed), built in `slot` (left `None` on an error). The
    /// renderer's way: the vertex stage makes the product once for the
    /// set-up and the draw's frustum; and the set-up holds a
    /// [`LightSetup`] of [`MAX_LIGHTS`] lights (about 500 bytes), which
    /// built in place is not copied on the stack of the vertex stage, the
    /// frame's deepest path.
    pub(crate) fn new_in<'s, const GENERAL: bool>(
        slot: &'s mut Option<Self>,
        draw: &Draw<'_>,
        mvp: Option<&Mat4>,
        lighting: Option<&Lighting<'_>>,
        eye: Vec3,
    ) -> Result<&'s Self, VertexError> {
        *slot = None;
        let m = &draw.transform;
        if !m.is_finite() {
            return Err(VertexError::BadMatrix);
        }
        // Normalized: the same picture whatever the scene's units.
        let mvp = mvp
            .and_then(Mat4::fixed_whole)
            .ok_or(VertexError::BadMatrix)?;
        use embedded_graphics::prelude::RgbColor;
        let material = &draw.material;
        let white = [material.ambient, material.diffuse]
            .iter()
            .all(|c| (c.r() & c.g() & c.b()) == 255);
        let dark = (material.specular.r() | material.specular.g() | material.specular.b()) == 0;
        let (extent, bounded) = (draw.mesh.extent(), mvp.bounded(draw.mesh.extent()));
        let s = slot.insert(Self {
            mvp,
            bounded,
            narrow: crate::math::SPLIT && bounded && mvp.narrow(extent) && NarrowRows::fits(&mvp),
            light: None,
            lambert: None,
            general: None,
            material: draw.material,
            color: [draw.color.r(), draw.color.g(), draw.color.b()],
        });
        // The renderer checked the lights themselves (with an identity
        // model matrix): what is left to fail is this draw's matrix.
        // One directional light without fog on a white, matte material
        // (the fast path's case) takes the fast path's set-up alone, with
        // the same errors and light: the general set-up, its eight light
        // slots and the eye converted for highlights, is not made.
        let plain = white && dark;
        let lit = match lighting {
            Some(l) if GENERAL && !(plain && Self::single_light(l)) => {
                match LightSetup::new_in(&mut s.light, l, m, eye) {
                    Ok(light) => {
                        s.lambert = match white && dark {
                            true => light.single_directional().map(Lambert::new),
                            false => None,
                        };
                        if s.lambert.is_none() {
                            s.general = Some(|l, m, b, p, n| l.shade(m, b, p, n));
                        }
                        Ok(())
                    }
                    Err(_) => Err(VertexError::BadMatrix),
                }
            }
            Some(l) => Self::one_light(l, m, eye, plain).map(|lambert| s.lambert = lambert),
            None => Ok(()),
        };
        // Unlit vertices (no normals) need no lighting at all.
        let unlit = lighting.is_some()
            && s.lambert.is_none()
            && s.general.is_none()
            && draw.mesh.normals().is_some();
        let failed = match (lit, unlit) {
            (Err(e), _) => Some(e),
            (Ok(()), true) => Some(VertexError::GeneralLighting),
            (Ok(()), false) => None,
        };
        match (failed, slot) {
            (None, Some(s)) => Ok(s),
            (failed, slot) => {
                *slot = None;
                Err(failed.unwrap_or(VertexError::BadMatrix))
            }
        }
    }

    /// Whether `lighting` is one directional light and nothing else (no
    /// point light, no fog): with a white, matte material, the case of
    /// [`LightSetup::single_directional`].
    fn single_light(lighting: &Lighting<'_>) -> bool {
        lighting.directional.len() == 1
            && lighting.point.is_empty()
            && lighting.fog == crate::light::Fog::None
    }

    /// The fast path's set-up without the general lighting's code: for
    /// one directional light and nothing else (no fog), on a white, matte
    /// material (`plain`), the light in the draw's model space; otherwise
    /// none. The draw's matrix is checked as [`LightSetup::new`] checks it
    /// (for a single light, with the same errors; for more, the checks that
    /// do not depend on point lights' ranges and fog).
    #[inline(never)]
    fn one_light(
        lighting: &Lighting<'_>,
        model: &Mat4,
        eye: Vec3,
        plain: bool,
    ) -> Result<Option<Lambert>, VertexError> {
        let bad = |_| VertexError::BadMatrix;
        match (lighting.directional, lighting.point.is_empty()) {
            ([sun], true) => {
                let (_, dir) =
                    crate::light::directional_lights(core::slice::from_ref(sun), model, eye, true)
                        .map_err(bad)?;
                let fog = lighting.fog != crate::light::Fog::None;
                Ok((plain && !fog)
                    .then(|| Lambert::new((dir, rgb(sun.color), rgb(lighting.ambient)))))
            }
            _ => {
                crate::light::directional_lights(lighting.directional, model, eye, false)
                    .map_err(bad)?;
                Ok(None)
            }
        }
    }

    /// Vertices `first` on of `mesh` (the mesh of the draw this was set up
    /// for), each as [`clip_position`](Self::clip_position) and
    /// [`lit_color`](Self::lit_color) give it, projected by `viewport` into
    /// `out`: the vertex stage's loop. Each vertex's
    /// [`interior`](ScreenVertex::interior) bit is made only if `gouraud`
    /// (the draw is Gouraud shaded).
    ///
    /// What holds for the whole draw is asked once, not per vertex: in the
    /// common case (a matrix [`bounded`](FixedMat4::bounded) for the mesh,
    /// on ARMv6-M [`narrow`](FixedMat4::narrow) too and a light
    /// [`NarrowRows::takes`], no vertex colours,
    /// the Lambert fast path on the mesh's normals) a loop of its own walks
    /// the positions and normals as two slices, with no index check and no
    /// test of the matrix, the colours or the lighting; any other draw
    /// takes both values from the general functions, out of line on
    /// 32-bit cores (flash) and inline on 64-bit hosts (out of line, the
    /// `tri4` scene's 24,000 coloured vertices cost x86-64 1.1 M
    /// instructions more: 16,758,876 against 15,630,992). (One loop for
    /// both, with a flag per vertex, was 22 K instructions a frame slower
    /// on the Cortex-M3 and 292 bytes smaller.)
    #[inline(always)]
    pub(crate) fn screen_vertices(
        &self,
        mesh: &Mesh<'_>,
        first: usize,
        viewport: &Viewport,
        out: &mut [ScreenVertex],
        gouraud: bool,
    ) -> Result<(), VertexError> {
        let n = out.len();
        let run = first..first + n;
        let positions = mesh
            .positions()
            .get(run.clone())
            .ok_or(VertexError::OutOfRange { vertex: first })?;
        // On ARMv6-M the common case's matrix is narrow too (its 32-bit
        // products; the others' by the 64-bit ones, out of line).
        let quick = match crate::math::SPLIT {
            true => self.narrow,
            false => self.bounded,
        };
        let common = match (&self.lambert, quick, mesh.colors(), mesh.normals()) {
            // With a light the target's loop work takes.
            (Some(l), true, None, Some(normals)) if loop_takes(l) => {
                normals.get(run).map(|s| (l, s))
            }
            _ => None,
        };
        match common {
            Some((l, normals)) if LOOP_CONSTANTS => {
                let k = LoopConstants::new(&self.mvp, l, self.color, gouraud);
                // Opaque: the loop loads each constant where it uses it,
                // neighbours in one instruction (see `LoopConstants`).
                lit_loop(
                    out,
                    positions,
                    normals,
                    viewport,
                    core::hint::black_box(&k),
                    gouraud,
                );
            }
            Some((l, normals)) if crate::math::SPLIT => {
                let k = NarrowRows::new(&self.mvp, l, self.color, gouraud);
                // Opaque, as `LoopConstants` (see `NarrowRows`): 10,000
                // instructions a `demo` frame fewer than without.
                let k = core::hint::black_box(&k);
                lit_loop(out, positions, normals, viewport, &(k, l), gouraud);
            }
            // 64-bit cores: 32-bit ones took an arm above.
            Some((l, normals)) => {
                let inside = l.interior_ndotl(self.color, gouraud);
                lit_loop(
                    out,
                    positions,
                    normals,
                    viewport,
                    &(&self.mvp, l, self.color, inside),
                    gouraud,
                )
            }
            None => {
                for (k, o) in out.iter_mut().enumerate() {
                    let pos = self.clip_position_apart(mesh, first + k)?;
                    // On 64-bit hosts (`DUPLICATE`) a vertex inside the
                    // view volume is projected inline here too
                    // (`Viewport::project_fast_wide`); on 32-bit cores
                    // out of line, for flash.
                    *o = viewport.screen_vertex_lit::<DUPLICATE>(&pos, DUPLICATE, || {
                        self.lit_color_apart(mesh, first + k, gouraud)
                    });
                }
            }
        }
        Ok(())
    }

    /// [`clip_position`](Self::clip_position) out of line, for the draws
    /// outside [`screen_vertices`](Self::screen_vertices)' common case.
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    fn clip_position_apart(&self, mesh: &Mesh<'_>, i: usize) -> Result<[i32; 4], VertexError> {
        self.clip_position(mesh, i)
    }

    /// [`lit_color`](Self::lit_color) out of line, for the draws outside
    /// [`screen_vertices`](Self::screen_vertices)' common case, with
    /// whether the vertex may carry the interior bit as far as its colour
    /// goes: never unless `gouraud` (tested here, out of line, so that the
    /// loop is not made twice for the flag).
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    fn lit_color_apart(&self, mesh: &Mesh<'_>, i: usize, gouraud: bool) -> ([u8; 3], bool) {
        let color = self.lit_color(mesh, i);
        // On 64-bit hosts the channels are tested with the depth instead
        // (`screen_vertex_lit`'s `CHANNELS`), and every draw's vertices
        // tested: a flag tested per vertex, or the channels tested here,
        // took x86-64's `tri4` 5 instructions a vertex more.
        match DUPLICATE {
            true => (color, true),
            false => (
                color,
                super::screen::INTERIOR_STARTS
                    && gouraud
                    && super::screen::channels_interior(color),
            ),
        }
    }

    /// The clip-space position and lit colour of vertex `i` of `mesh`, the
    /// mesh of the draw this was set up for.
    #[inline(always)]
    pub fn clip_vertex(&self, mesh: &Mesh<'_>, i: usize) -> Result<ClipVertex, VertexError> {
        let pos = self.clip_position(mesh, i)?;
        let color = self.lit_color(mesh, i);
        Ok(ClipVertex {
            pos,
            color: [color[0] as i32, color[1] as i32, color[2] as i32],
            bary: [0; 2],
        })
    }

    /// The clip-space position of vertex `i` of `mesh` (that of
    /// [`clip_vertex`](Self::clip_vertex)).
    #[inline(always)]
    pub(crate) fn clip_position(&self, mesh: &Mesh<'_>, i: usize) -> Result<[i32; 4], VertexError> {
        let p = mesh.positions()[i];
        let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        if self.bounded {
            Ok(self.mvp.transform_point_bounded(p))
        } else {
            self.mvp
                .transform_point(p)
                .ok_or(VertexError::OutOfRange { vertex: i })
        }
    }

    /// The lit colour of vertex `i` of `mesh` (that of
    /// [`clip_vertex`](Self::clip_vertex)).
    #[inline(always)]
    pub(crate) fn lit_color(&self, mesh: &Mesh<'_>, i: usize) -> [u8; 3] {
        let base = match mesh.colors() {
            Some(c) => {
                use embedded_graphics::prelude::RgbColor;
                [c[i].r(), c[i].g(), c[i].b()]
            }
            None => self.color,
        };
        match (&self.light, mesh.normals()) {
            (_, Some(n)) if self.lambert.is_some() => match &self.lambert {
                Some(l) => l.shade(n[i], base),
                None => base,
            },
            (Some(l), Some(n)) => match self.general {
                Some(shade) => {
                    let p = mesh.positions()[i];
                    let n = n[i];
                    shade(
                        l,
                        &self.material,
                        base,
                        [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()],
                        [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()],
                    )
                }
                None => base,
            },
            _ => base,
        }
    }

    /// Whether every vertex of the draw has the same clip-space `w`: its
    /// transform's `w` row is `(0, 0, 0, c)` (an orthographic or 2D
    /// camera, no perspective). Fragment shaders interpolate such a draw
    /// affinely in every perspective mode (see
    /// [`Perspective`](crate::shader::Perspective)).
    #[inline(always)]
    pub fn constant_w(&self) -> bool {
        let m = &self.mvp.m;
        m[0][3] | m[1][3] | m[2][3] == 0
    }

    /// The clip-space `w` of vertex `i` of `mesh`, exactly as
    /// [`clip_vertex`](Self::clip_vertex) computes it, for a vertex that
    /// the vertex stage already transformed without error (then the
    /// unchecked sum equals the checked one).
    #[inline(always)]
    pub fn clip_w(&self, mesh: &Mesh<'_>, i: usize) -> i32 {
        let p = mesh.positions()[i];
        self.mvp
            .transform_w_unchecked([p[0].to_bits(), p[1].to_bits(), p[2].to_bits()])
    }
}
