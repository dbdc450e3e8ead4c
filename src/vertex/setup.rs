//! A draw's set-up in fixed point ([`DrawSetup`]): its model-view-projection
//! matrix normalized and converted once to 16.16, its lights moved into
//! model space (one directional light on a plain material through a
//! dozen-instruction fast path, any other lighting through
//! [`LightSetup`]), and per vertex the clip-space position and lit colour
//! ([`DrawSetup::clip_vertex`]).

use super::lambert::{Lambert, LoopConstants, NarrowRows, LOOP_CONSTANTS};
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
            narrow: crate::math::SPLIT && bounded && mvp.narrow(extent),
            light: None,
            lambert: None,
            general: None,
            material: draw.material,
            color: [draw.color.r(), draw.color.g(), draw.color.b()],
        });
        // The renderer checked the lights themselves (with an identity
        // model matrix): what is left to fail is this draw's matrix.
        let lit = match lighting {
            Some(l) if GENERAL => match LightSetup::new_in(&mut s.light, l, m, eye) {
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
            },
            Some(l) => Self::one_light(l, m, eye, white && dark).map(|lambert| s.lambert = lambert),
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
                let dir = crate::light::one_light(sun.direction, model, eye).map_err(bad)?;
                let fog = lighting.fog != crate::light::Fog::None;
                Ok((plain && !fog)
                    .then(|| Lambert::new((dir, rgb(sun.color), rgb(lighting.ambient)))))
            }
            _ => {
                crate::light::model_checks(model, eye).map_err(bad)?;
                for (i, l) in lighting.directional.iter().enumerate() {
                    crate::light::directional(i, l.direction, model, false).map_err(bad)?;
                }
                Ok(None)
            }
        }
    }

    /// Vertices `first` on of `mesh` (the mesh of the draw this was set up
    /// for), each as [`clip_position`](Self::clip_position) and
    /// [`lit_color`](Self::lit_color) give it, projected by `viewport` into
    /// `out`: the vertex stage's loop.
    ///
    /// What holds for the whole draw is asked once, not per vertex: in the
    /// common case (a matrix [`bounded`](FixedMat4::bounded) for the mesh,
    /// on ARMv6-M [`narrow`](FixedMat4::narrow) too, no vertex colours,
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
            (Some(l), true, None, Some(normals)) => normals.get(run).map(|s| (l, s)),
            _ => None,
        };
        match common {
            Some((l, normals)) if LOOP_CONSTANTS => {
                let k = LoopConstants::new(&self.mvp, l, self.color);
                // Opaque: the loop loads each constant where it uses it,
                // neighbours in one instruction (see `LoopConstants`).
                let k = core::hint::black_box(&k);
                for (o, (p, nv)) in out.iter_mut().zip(positions.iter().zip(normals)) {
                    let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
                    let pos = k.transform(p);
                    *o = viewport.screen_vertex_lit(&pos, || k.shade(*nv));
                }
            }
            Some((l, normals)) if crate::math::SPLIT => {
                let k = NarrowRows::new(&self.mvp, l, self.color);
                // Opaque, as `LoopConstants` (see `NarrowRows`): 10,000
                // instructions a `demo` frame fewer than without.
                let k = core::hint::black_box(&k);
                for (o, (p, nv)) in out.iter_mut().zip(positions.iter().zip(normals)) {
                    let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
                    let pos = k.transform(p);
                    *o = viewport.screen_vertex_lit(&pos, || k.shade(l, *nv));
                }
            }
            Some((l, normals)) => {
                for (o, (p, nv)) in out.iter_mut().zip(positions.iter().zip(normals)) {
                    let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
                    // 64-bit cores: 32-bit ones took an arm above.
                    let pos = self.mvp.transform_point_bounded(p);
                    *o = viewport.screen_vertex_lit(&pos, || l.shade(*nv, self.color));
                }
            }
            None => {
                for (k, o) in out.iter_mut().enumerate() {
                    let pos = self.clip_position_apart(mesh, first + k)?;
                    *o = viewport.screen_vertex_lit(&pos, || self.lit_color_apart(mesh, first + k));
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
    /// [`screen_vertices`](Self::screen_vertices)' common case.
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    fn lit_color_apart(&self, mesh: &Mesh<'_>, i: usize) -> [u8; 3] {
        self.lit_color(mesh, i)
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

#[cfg(test)]
mod tests {
    use super::super::lambert::{clamp_ndotl_words, div65280_sat, ndotl_narrow};
    use super::*;

    /// n·l's clamp from the upper word is the 64-bit clamp.
    #[test]
    fn ndotl_from_words_is_the_clamp() {
        let mut next = crate::testing::rng();
        let check =
            |d: i64| assert_eq!(clamp_ndotl_words(d), (d >> 24).clamp(0, 256) as u32, "{d}");
        for b in 0..64 {
            let p = 1i64 << b;
            for d in [p, p.wrapping_sub(1), p.wrapping_neg(), p.wrapping_neg() + 1] {
                check(d);
            }
        }
        for d in [
            0,
            -1,
            i64::MIN,
            i64::MAX,
            (256 << 24) - 1,
            256 << 24,
            255 << 24,
        ] {
            check(d);
        }
        for _ in 0..100_000 {
            check(((next(1 << 32) << 32 | next(1 << 32)) as i64) >> next(64));
        }
    }

    /// The saturated quotient by 65,280 of the Lambert colour is the
    /// division's, for every `x` below 2^31 (every 127th value, the ends
    /// of each quotient's range, and the top of the range).
    #[test]
    fn div65280_sat_is_the_clamped_quotient() {
        let check = |x: u32| assert_eq!(div65280_sat(x), (x / 65_280).min(255) as u8, "{x}");
        for x in (0..1u32 << 31).step_by(127) {
            check(x);
        }
        for q in 1..32_896u32 {
            check(q * 65_280);
            check(q * 65_280 - 1);
        }
        for x in (1 << 31) - 1_000..1 << 31 {
            check(x);
        }
    }

    /// The narrow n·l is the 64-bit one wherever it is taken: random and
    /// extreme normals and light directions within its bounds, and just
    /// beyond them (where it declines).
    #[test]
    fn narrow_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let ends = [
            -(1 << 16) - 1,
            -(1 << 16),
            -(1 << 16) + 1,
            -256,
            -255,
            -1,
            0,
            1,
            255,
            256,
            (1 << 16) - 1,
            1 << 16,
            (1 << 16) + 1,
        ];
        let lends = [
            -(1 << 20) - 1,
            -(1 << 20),
            -(1 << 16),
            -1,
            0,
            1,
            1 << 16,
            1 << 20,
            (1 << 20) + 1,
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &l in &lends {
                        for l in [[l, l, l], [l, -l, l], [-l, l, 1 << 16]] {
                            let n = [a, b, c];
                            let inside = n.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 16)
                                && l.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 20);
                            assert_eq!(
                                ndotl_narrow(n, l),
                                inside.then(|| wide(n, l)),
                                "{n:?} {l:?}"
                            );
                        }
                    }
                }
            }
        }
        for _ in 0..1_000_000 {
            let mut r = |m: u64| (next(2 * m + 1) as i64 - m as i64) as i32;
            let n = [r(1 << 16), r(1 << 16), r(1 << 16)];
            let l = [r(1 << 20), r(1 << 20), r(1 << 20)];
            assert_eq!(ndotl_narrow(n, l), Some(wide(n, l)), "{n:?} {l:?}");
        }
    }

    /// The fast path of one directional light gives the general
    /// lighting's colours, for any normal, colour and light.
    #[test]
    fn lambert_fast_path_matches_the_light_setup() {
        use crate::light::{DirectionalLight, Lighting};
        use embedded_graphics::pixelcolor::Rgb888;
        let mut next = crate::testing::rng();
        for _ in 0..200 {
            let mut f = || next(2001) as f32 / 1000.0 - 1.0;
            let dir = Vec3::new(f(), f(), f() + 0.01);
            let model = Mat4::rotation_y(f() * 3.0) * Mat4::rotation_x(f() * 3.0);
            let mut c = || Rgb888::new(next(256) as u8, next(256) as u8, next(256) as u8);
            let one = [DirectionalLight::new(dir, c())];
            let lighting = Lighting::new(c()).directional(&one);
            let setup: LightSetup<MAX_LIGHTS> =
                LightSetup::new(&lighting, &model, Vec3::new(0.0, 0.0, 5.0)).unwrap();
            let (dir, color, ambient) = setup.single_directional().unwrap();
            let fast = Lambert {
                dir,
                color: color.map(u32::from),
                ambient: ambient.map(u32::from),
            };
            for _ in 0..500 {
                let n = [0; 3]
                    .map(|_| fixed::types::I16F16::from_bits(next(1 << 18) as i32 - (1 << 17)));
                let base = [next(256) as u8, next(256) as u8, next(256) as u8];
                let general = setup.shade(&Material::new(), base, [0; 3], n.map(|v| v.to_bits()));
                assert_eq!(fast.shade(n, base), general, "{n:?} {base:?}");
                let k = LoopConstants::new(&FixedMat4 { m: [[0; 4]; 4] }, &fast, base);
                assert_eq!(k.shade(n), general, "{n:?} {base:?}");
                let k = NarrowRows::new(&FixedMat4 { m: [[0; 4]; 4] }, &fast, base);
                assert_eq!(k.shade(&fast, n), general, "{n:?} {base:?}");
            }
        }
    }

    /// A light that adds nothing, for the transform tests.
    const NO_LIGHT: Lambert = Lambert {
        dir: [0; 3],
        color: [0; 3],
        ambient: [0; 3],
    };

    /// The common loop's rows are the bounded transform: random matrices
    /// of every magnitude (the translation up to the `i32` extremes), and
    /// points within an extent they are bounded for.
    #[test]
    fn loop_constants_transform_as_the_bounded_matrix() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        let none = NO_LIGHT;
        for _ in 0..50_000 {
            let span = (1i64 << next(32)) - 1;
            let mut e = || (next(2 * span as u64 + 1) as i64 - span) as i32;
            let m = FixedMat4 {
                m: [[0; 4]; 4].map(|c| c.map(|_| e())),
            };
            let extent = 1u32 << next(23);
            if !m.bounded(extent) {
                continue;
            }
            taken += 1;
            let k = LoopConstants::new(&m, &none, [0; 3]);
            for _ in 0..20 {
                let ext = extent as i64;
                let p = [0; 3].map(|_| (next(2 * ext as u64 + 1) as i64 - ext) as i32);
                assert_eq!(k.transform(p), m.transform_point_bounded(p), "{m:?} {p:?}");
            }
        }
        assert!(taken > 5_000, "{taken}");
    }

    /// ARMv6-M's split rows are the narrow transform, hence the bounded
    /// one: random narrow matrices (elements up to `±2^16`, translations
    /// of any size) and points up to the narrow extent `2^21`, the
    /// extremes included.
    #[test]
    fn narrow_rows_transform_as_the_bounded_matrix() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        let none = NO_LIGHT;
        for i in 0..50_000 {
            let mut e = |span: i64| (next(2 * span as u64 + 1) as i64 - span) as i32;
            let mut m = FixedMat4 { m: [[0; 4]; 4] };
            for c in 0..4 {
                for r in 0..4 {
                    m.m[c][r] = match (c, i % 7) {
                        (3, _) => e((1 << (i % 31)) - 1),
                        (_, 0) => [-(1 << 16), 1 << 16][(r + c) % 2],
                        _ => e(1 << 16),
                    };
                }
            }
            let extent = 1u32 << (i % 22);
            if !(m.bounded(extent) && m.narrow(extent)) {
                continue;
            }
            taken += 1;
            let k = NarrowRows::new(&m, &none, [0; 3]);
            let ext = extent as i64;
            for j in 0..20 {
                let mut c = || match (j + i) % 5 {
                    0 => extent as i32,
                    1 => -(extent as i32),
                    _ => (next(2 * ext as u64 + 1) as i64 - ext) as i32,
                };
                let p = [c(), c(), c()];
                assert_eq!(k.transform(p), m.transform_point_bounded(p), "{m:?} {p:?}");
                assert_eq!(k.transform(p), m.transform_point_narrow(p), "{m:?} {p:?}");
            }
        }
        assert!(taken > 5_000, "{taken}");
    }
}
