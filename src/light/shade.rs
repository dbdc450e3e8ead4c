//! Lighting one vertex from a [`LightSetup`](super::LightSetup): ambient,
//! Lambert diffuse and Blinn–Phong highlights per light, attenuation of
//! point lights, then fog, all in integers.

use super::arith::*;
use super::setup::{rgb, Core, FixedFog, FixedLight, Source};
use super::Material;

impl Core {
    /// The lit colour of a vertex.
    ///
    /// `base` is the vertex or draw colour (it multiplies the material's
    /// ambient and diffuse reflectance); `position` and `normal` are in the
    /// draw's model space, raw 16.16 bits. The normal should be unit length
    /// (it is not normalised; see the [module docs](crate::light)), but any normal,
    /// zero or huge, gives a defined colour.
    pub(super) fn shade(
        &self,
        lights: &[FixedLight],
        material: &Material,
        base: [u8; 3],
        position: [i32; 3],
        normal: [i32; 3],
    ) -> [u8; 3] {
        let n = Normal::new(normal);
        let (ma, md, ms) = (
            rgb(material.ambient),
            rgb(material.diffuse),
            rgb(material.specular),
        );
        // Bitwise, as an array comparison would call memcmp.
        let specular_on = (ms[0] | ms[1] | ms[2]) != 0;
        if let (true, false, FixedFog::None, Some(Source::Directional { dir })) = (
            self.coarse,
            specular_on,
            self.fog,
            lights.first().map(|l| l.source),
        ) {
            return self.lambert(lights, ma, md, base, &n, dir);
        }

        // Diffuse and ambient sum I, in 1 / (255 · FULL) of the base colour
        // (so that the sum for a white material is 255 times the vertex
        // stage's old intensity), and specular sum J in 1 / FULL of a byte.
        let mut diffuse = [0u32; 3];
        for c in 0..3 {
            diffuse[c] = ma[c] as u32 * self.ambient[c] as u32 * 256;
        }
        let mut specular = [0u32; 3];
        // The unit vector towards the eye and its length: needed only for
        // specular highlights and fog, so found at most once, on first use.
        let mut view: Option<Option<Unit>> = None;
        let to_eye = || normalize(offset(self.eye, position));

        for light in lights.iter() {
            let (l, att) = match light.source {
                Source::Off => continue,
                Source::Directional { dir } => (dir, ONE),
                Source::Point {
                    pos,
                    reach,
                    inv_range,
                } => {
                    let d = offset(pos, position);
                    // Out of range in one coordinate: out of range. Most
                    // vertices of a scene with many small lights end here.
                    if d.iter().any(|c| c.unsigned_abs() >= reach) {
                        continue;
                    }
                    let Some(u) = normalize(d) else { continue };
                    let t = inv_range.apply(u.len, u.exp);
                    if t >= ONE as u64 {
                        continue;
                    }
                    (u.dir, attenuation(t as u32))
                }
            };
            let nl = n.dot(l);
            if nl <= 0 {
                continue;
            }
            let nl = if self.coarse {
                ((nl as u32 >> 8).min(256)) << 8
            } else {
                (nl as u32).min(ONE)
            };
            let g = frac_mul(nl, att);
            for c in 0..3 {
                // (Md · C) · g <= 65,025 · 65,536 < 2^32 - 128.
                let p = md[c] as u32 * light.color[c] as u32;
                diffuse[c] = diffuse[c].saturating_add((p * g + 128) >> 8);
            }
            if specular_on {
                let ps = [
                    ms[0] as u32 * light.color[0] as u32,
                    ms[1] as u32 * light.color[1] as u32,
                    ms[2] as u32 * light.color[2] as u32,
                ];
                if (ps[0] | ps[1] | ps[2]) == 0 {
                    continue;
                }
                let Some(v) = *view.get_or_insert_with(to_eye) else {
                    continue;
                };
                // |l + v| <= 2^17 + 2.
                let h = [
                    l[0] as i64 + v.dir[0] as i64,
                    l[1] as i64 + v.dir[1] as i64,
                    l[2] as i64 + v.dir[2] as i64,
                ];
                let Some(h) = normalize(h) else { continue };
                let nh = n.dot(h.dir).clamp(0, ONE as i32) as u32;
                let gs = frac_mul(pow(nh, material.shininess), att);
                for c in 0..3 {
                    specular[c] = specular[c].saturating_add((ps[c] * gs + 128) >> 8);
                }
            }
        }

        let f = match self.fog {
            FixedFog::None => 0,
            FixedFog::Linear { scale, offset } => {
                let q = view
                    .get_or_insert_with(to_eye)
                    .map_or(0, |u| scale.apply(u.len, u.exp));
                (q as i64 - offset).clamp(0, ONE as i64) as u32
            }
            FixedFog::Exponential { scale } => {
                let q = view
                    .get_or_insert_with(to_eye)
                    .map_or(0, |u| scale.apply(u.len, u.exp));
                ONE - exp2_neg(q)
            }
        };

        let mut out = [0u8; 3];
        for c in 0..3 {
            // Clamped where the byte saturates anyway, so exact: then
            // base · K + J <= 256 · K_MAX < 2^32 - 32,640.
            let k = div255(diffuse[c].min(255 * K_MAX));
            let x = base[c] as u32 * k + specular[c].min(K_MAX);
            out[c] = if f == 0 {
                // round(x / FULL), as the vertex stage rounds.
                div255((x + FULL / 2) >> 8).min(255) as u8
            } else {
                // The lit colour in 1/256 of a byte, mixed in Q16: a convex
                // combination, at most 65,280 · 2^16 < 2^32 - 2^23.
                let lit = div255(x).min(FULL);
                let fog = self.fog_color[c] as u32 * 256;
                ((lit * (ONE - f) + fog * f + (1 << 23)) >> 24) as u8
            };
        }
        out
    }

    /// For one directional light without fog (the lighting of a
    /// [`scene::Light`](crate::scene::Light)): its model-space unit
    /// direction (Q16), its colour and the ambient light, with which a
    /// white material without highlights is lit as
    /// `(base (256 ambient + colour · n·l) + 32,640) / 65,280`, `n·l` in
    /// 1/256 steps, floored, clamped to `0..=256` (the same bits as
    /// [`shade`](Self::shade), which the tests check): the vertex stage's
    /// fast path.
    pub(super) fn single_directional(
        &self,
        lights: &[FixedLight],
    ) -> Option<([i32; 3], [u8; 3], [u8; 3])> {
        match (self.coarse, self.fog, lights.first()) {
            (true, FixedFog::None, Some(l)) => match l.source {
                Source::Directional { dir } => Some((dir, l.color, self.ambient)),
                _ => None,
            },
            _ => None,
        }
    }

    /// [`shade`](Self::shade) for the commonest case, as fast as the
    /// vertex stage's old single-light code: one directional light (the
    /// coarse `n·l` of [`scene::Light`](crate::scene::Light)), no
    /// highlights, no fog. The same steps as the general loop with
    /// everything that cannot apply left out, so the same bits.
    #[inline(always)]
    pub(super) fn lambert(
        &self,
        lights: &[FixedLight],
        ma: [u8; 3],
        md: [u8; 3],
        base: [u8; 3],
        n: &Normal,
        dir: [i32; 3],
    ) -> [u8; 3] {
        let nl = n.dot(dir);
        // frac_mul(nl, ONE) = min(nl, ONE) for the coarse n·l.
        let g = if nl > 0 {
            (((nl as u32 >> 8).min(256)) << 8).min(ONE)
        } else {
            0
        };
        let color = lights[0].color;
        let mut out = [0u8; 3];
        if (ma[0] & ma[1] & ma[2] & md[0] & md[1] & md[2]) == 255 {
            // A white material: then `k` below is exactly
            // `256 ambient + colour · n·l` (in 1/256 steps), and the two
            // divisions by 255 one division by 65,280, which the compiler
            // does by a multiply.
            let nl = g >> 8;
            for c in 0..3 {
                let k = self.ambient[c] as u32 * 256 + color[c] as u32 * nl;
                let x = base[c] as u32 * k + FULL / 2;
                // As `vertex::setup`'s Lambert path: ARMv6-M's division
                // by a constant is a library call, `div255` is not.
                let q = if cfg!(microraster_narrow_multiply) {
                    div255(x >> 8)
                } else {
                    x / FULL
                };
                out[c] = q.min(255) as u8;
            }
            return out;
        }
        for c in 0..3 {
            let mut diffuse = ma[c] as u32 * self.ambient[c] as u32 * 256;
            if g > 0 {
                let p = md[c] as u32 * color[c] as u32;
                diffuse = diffuse.saturating_add((p * g + 128) >> 8);
            }
            let k = div255(diffuse.min(255 * K_MAX));
            let x = base[c] as u32 * k;
            out[c] = div255((x + FULL / 2) >> 8).min(255) as u8;
        }
        out
    }
}
