//! A draw's set-up in fixed point ([`DrawSetup`]): its model-view-projection
//! matrix normalized and converted once to 16.16, its lights moved into
//! model space (one directional light on a plain material through a
//! dozen-instruction fast path, any other lighting through
//! [`LightSetup`]), and per vertex the clip-space position and lit colour
//! ([`DrawSetup::clip_vertex`]).

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

/// One directional light in model space (see
/// [`LightSetup::single_directional`]).
#[derive(Clone, Copy, Debug)]
struct Lambert {
    dir: [i32; 3],
    color: [u32; 3],
    ambient: [u32; 3],
}

impl Lambert {
    fn new((dir, color, ambient): ([i32; 3], [u8; 3], [u8; 3])) -> Self {
        Lambert {
            dir,
            color: color.map(u32::from),
            ambient: ambient.map(u32::from),
        }
    }

    /// n·l in 1/256 steps, clamped to `0..=256` ([`shade`](Self::shade)'s).
    #[inline(always)]
    fn ndotl(&self, n: crate::mesh::Vec3Fx) -> u32 {
        use crate::math::mul_wide;
        let n = [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()];
        let wide = || {
            let d = mul_wide(n[0], self.dir[0])
                + mul_wide(n[1], self.dir[1])
                + mul_wide(n[2], self.dir[2]);
            // n·l in 1/256 steps, floored, clamped to [0, 1]. On 32-bit
            // cores from d's upper word, which is 0 exactly when d >> 24 is
            // 0 to 255 (the 64-bit clamp took twice the instructions on
            // the Cortex-M3); 64-bit ones keep the clamp, which measured
            // fewer there.
            if cfg!(target_pointer_width = "64") {
                (d >> 24).clamp(0, 256) as u32
            } else {
                clamp_ndotl_words(d)
            }
        };
        // ARMv6-M builds each 64-bit product from four 16-bit ones: a
        // normal within ±1 takes n·l from six 32-bit products instead.
        match crate::math::SPLIT {
            true => ndotl_narrow(n, self.dir).unwrap_or_else(wide),
            false => wide(),
        }
    }

    /// Per channel `c`, for the draw's colour `base`: `base[c] ambient[c]
    /// 256 + 32,640` and `base[c] color[c]`, so that [`shade`](Self::shade)'s
    /// `base[c] (ambient[c] 256 + color[c] n·l) + 32,640` is one
    /// multiply-add (the same value: every term is below `2^26`). Once per
    /// draw, for the common loop's constants.
    fn folded(&self, base: [u8; 3]) -> [[u32; 2]; 3] {
        let mut out = [[0; 2]; 3];
        for (c, ch) in out.iter_mut().enumerate() {
            let b = base[c] as u32;
            *ch = [b * self.ambient[c] * 256 + 32_640, b * self.color[c]];
        }
        out
    }

    #[inline(always)]
    fn shade(&self, n: crate::mesh::Vec3Fx, base: [u8; 3]) -> [u8; 3] {
        let ndotl = self.ndotl(n);
        let mut out = [0u8; 3];
        for c in 0..3 {
            // At most 2^17.
            let k = self.ambient[c] * 256 + self.color[c] * ndotl;
            let x = base[c] as u32 * k + 32_640;
            // floor(x / 65,280) = floor(floor(x / 256) / 255): ARMv6-M,
            // without a multiply-high, divides by a constant through the
            // library (about a hundred instructions), `div255` in eight.
            out[c] = if cfg!(microraster_narrow_multiply) {
                crate::light::div255(x >> 8).min(255) as u8
            } else if cfg!(target_pointer_width = "32") {
                div65280_sat(x)
            } else {
                (x / 65_280).min(255) as u8
            };
        }
        out
    }
}

/// `floor(x / 65,280)`, at most 255, for `x < 2^31` (the Lambert colour's
/// `x` is below 2^26): the quotient by the multiply-high LLVM makes of it
/// (`floor(x 0x8080_8081 / 2^47)`, exact for every `u32`), its upper word
/// taken as signed (below 2^31 for such `x`, so the shift is the same) so
/// that the clamp to `0..=255` is one `USAT` on ARMv7-M, where the
/// unsigned minimum took a compare, an `IT` and a conditional shift a
/// channel.
#[inline(always)]
fn div65280_sat(x: u32) -> u8 {
    debug_assert!(x < 1 << 31);
    let high = ((x as u64 * 0x8080_8081) >> 32) as u32 as i32;
    (high >> 15).clamp(0, 255) as u8
}

/// The Lambert fast path's n·l, `(n·l >> 24).clamp(0, 256)`, in 32-bit
/// products, when every `|n[i]| <= 2^16` and `|l[i]| <= 2^20`; `None`
/// otherwise. With `n[i] = h[i] 2^8 + o[i]` (`|h[i]| <= 2^8`, `0 <= o[i] <
/// 2^8`), `n·l = 2^8 A + B` for `A = Σ h[i] l[i]` and `B = Σ o[i] l[i]`,
/// each below `3 2^28` in magnitude; so `floor(n·l / 2^8) = A + floor(B /
/// 2^8)` fits `i32`, and shifting it by 16 more floors `n·l / 2^24`.
#[inline(always)]
fn ndotl_narrow(n: [i32; 3], l: [i32; 3]) -> Option<u32> {
    let within = |v: i32, m: u32| v.unsigned_abs() <= m;
    if !(n.iter().all(|&v| within(v, 1 << 16)) && l.iter().all(|&v| within(v, 1 << 20))) {
        return None;
    }
    let (mut a, mut b) = (0i32, 0i32);
    for i in 0..3 {
        a += (n[i] >> 8) * l[i];
        b += (n[i] & 0xff) * l[i];
    }
    Some(((a + (b >> 8)) >> 16).clamp(0, 256) as u32)
}

/// Whether the vertex stage's common loop reads its per-draw constants
/// from a [`LoopConstants`]: on 32-bit cores with a 32 x 32 -> 64-bit
/// multiply (the Cortex-M3 and M4, RISC-V `rv32im`).
const LOOP_CONSTANTS: bool = cfg!(all(
    target_pointer_width = "32",
    not(microraster_narrow_multiply)
));

/// The per-draw constants of the vertex stage's common loop (a bounded
/// matrix, the Lambert fast path, no vertex colours), laid out in the
/// order the loop reads them and read through a reference the compiler
/// cannot see into (`black_box`). The loop has more constants (28) than
/// a Cortex-M3 has registers: held as values, the allocator spilled them
/// to slots of their own and reloaded each with one `LDR` a vertex; read
/// from here, neighbours load together (`LDRD`), the translation's two
/// words straight into a row's accumulator, and the Lambert colour's
/// constants are folded per draw (two per channel where there were
/// three and a multiply more).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
struct LoopConstants {
    /// Per row `r` of the matrix: the low and high words of `m[3][r] 2^16 +
    /// 2^15` (translation and rounding, as in
    /// [`FixedMat4::transform_point_bounded`]), then `m[0][r]`, `m[1][r]`
    /// and `m[2][r]`.
    rows: [[i32; 5]; 4],
    /// The light's direction (as [`Lambert`]'s).
    dir: [i32; 3],
    /// The Lambert colour's factors per channel ([`Lambert::folded`]).
    channels: [[u32; 2]; 3],
}

#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
impl LoopConstants {
    fn new(m: &FixedMat4, l: &Lambert, base: [u8; 3]) -> Self {
        // Loops rather than `map`s, here and below: the size profile
        // (the OLED firmware's) keeps a `map` as a loop through a
        // temporary array and a `memcpy`.
        let mut k = Self {
            rows: [[0; 5]; 4],
            dir: l.dir,
            channels: [[0; 2]; 3],
        };
        for (r, row) in k.rows.iter_mut().enumerate() {
            let t = (m.m[3][r] as i64) << 16 | 1 << 15;
            *row = [t as i32, (t >> 32) as i32, m.m[0][r], m.m[1][r], m.m[2][r]];
        }
        k.channels = l.folded(base);
        k
    }

    /// [`FixedMat4::transform_point_bounded`] of `p`: the same sums.
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        use crate::math::mul_wide;
        let mut out = [0i32; 4];
        for (o, k) in out.iter_mut().zip(&self.rows) {
            let acc = ((k[1] as i64) << 32 | k[0] as u32 as i64)
                .wrapping_add(mul_wide(k[2], p[0]))
                .wrapping_add(mul_wide(k[3], p[1]))
                .wrapping_add(mul_wide(k[4], p[2]));
            *o = (acc >> 16) as i32;
        }
        out
    }

    /// [`Lambert::shade`] of normal `n` on the draw's colour: the same
    /// colour.
    #[inline(always)]
    fn shade(&self, n: crate::mesh::Vec3Fx) -> [u8; 3] {
        use crate::math::mul_wide;
        let d = mul_wide(n[0].to_bits(), self.dir[0])
            + mul_wide(n[1].to_bits(), self.dir[1])
            + mul_wide(n[2].to_bits(), self.dir[2]);
        let ndotl = clamp_ndotl_words(d);
        let mut out = [0u8; 3];
        for (o, &[a, c]) in out.iter_mut().zip(&self.channels) {
            *o = div65280_sat(a + c * ndotl);
        }
        out
    }
}

/// The rows of a [`narrow`](FixedMat4::narrow) matrix for ARMv6-M's
/// common vertex loop, its elements split rather than the point:
/// `FixedMat4::transform_point_narrow` (now the tests' reference) split each coordinate `p[i] =
/// a[i] 2^8 + b[i]` per vertex (six values besides the point, more than
/// Thumb-1's eight low registers held with the matrix: spilled, and each
/// element copied before its `MULS`). Here each element `m = h 2^8 + l`
/// (`0 <= l < 2^8`, `|h| <= 2^8` for `|m| <= 2^16`) is split once per
/// draw, and a row's `Σ m[i] p[i] = 2^8 H + L` for `H = Σ h[i] p[i]` and
/// `L = Σ l[i] p[i]`: with `|p[i]| <= 2^21` each product is below `2^29`
/// in magnitude and each sum below `3 2^29`, exact in `i32`; then the
/// rounding is `transform_point_narrow`'s, `floor((H + floor((L + 2^15) /
/// 2^8)) / 2^8)`, and the same result. Read through an opaque reference
/// (as [`LoopConstants`]), each element is loaded into the register its
/// `MULS` overwrites.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
struct NarrowRows {
    /// Per row `r`: `h` of `m[0][r]`, `m[1][r]`, `m[2][r]`, then their
    /// `l`, then the translation `m[3][r]`.
    rows: [[i32; 7]; 4],
    /// The Lambert colour's factors per channel ([`Lambert::folded`]: one
    /// `MULS` a channel fewer).
    channels: [[u32; 2]; 3],
}

#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
impl NarrowRows {
    fn new(m: &FixedMat4, l: &Lambert, base: [u8; 3]) -> Self {
        let mut k = Self {
            rows: [[0; 7]; 4],
            channels: [[0; 2]; 3],
        };
        k.channels = l.folded(base);
        for (r, row) in k.rows.iter_mut().enumerate() {
            let e = [m.m[0][r], m.m[1][r], m.m[2][r]];
            *row = [
                e[0] >> 8,
                e[1] >> 8,
                e[2] >> 8,
                e[0] & 0xff,
                e[1] & 0xff,
                e[2] & 0xff,
                m.m[3][r],
            ];
        }
        k
    }

    /// `FixedMat4::transform_point_narrow` of `p`, for the matrix this
    /// was made of and a point within its narrow extent: the same point.
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        let mut out = [0i32; 4];
        for (o, k) in out.iter_mut().zip(&self.rows) {
            let h = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
            let l = k[3] * p[0] + k[4] * p[1] + k[5] * p[2];
            *o = k[6].wrapping_add((h + ((l + (1 << 15)) >> 8)) >> 8);
        }
        out
    }

    /// [`Lambert::shade`] of normal `n` on the draw's colour, `l` the
    /// light this was made with: the same colour.
    #[inline(always)]
    fn shade(&self, l: &Lambert, n: crate::mesh::Vec3Fx) -> [u8; 3] {
        let ndotl = l.ndotl(n);
        let mut out = [0u8; 3];
        for (o, &[a, c]) in out.iter_mut().zip(&self.channels) {
            // Lambert::shade's division on cores without a multiply-high.
            *o = crate::light::div255((a + c * ndotl) >> 8).min(255) as u8;
        }
        out
    }
}

/// `(d >> 24).clamp(0, 256)` from `d`'s upper word, which is 0 exactly
/// when `d >> 24` is 0 to 255: the Lambert fast path's n·l on 32-bit cores.
#[inline(always)]
fn clamp_ndotl_words(d: i64) -> u32 {
    match (d >> 32) as i32 {
        0 => d as u32 >> 24,
        1.. => 256,
        _ => 0,
    }
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
