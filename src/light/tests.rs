//! Tests of lighting: the set-up, the per-vertex arithmetic against `f64`
//! references, and the documented error bounds.

use super::arith::*;
use super::setup::*;
use super::*;
use crate::math::Mat4;
use embedded_graphics::prelude::RgbColor;

/// xorshift64, as the crate's other tests use.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Log-uniform in [lo, hi).
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    fn color(&mut self) -> Rgb888 {
        Rgb888::new(self.byte(), self.byte(), self.byte())
    }
    /// A uniformly distributed unit vector.
    fn dir(&mut self) -> [f64; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let l = dot(v, v).sqrt();
            if l > 0.1 && l <= 1.0 {
                return [v[0] / l, v[1] / l, v[2] / l];
            }
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(a, a).sqrt();
    (l > 0.0).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

fn f64v(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn raw(v: [f64; 3]) -> [i32; 3] {
    v.map(|c| (c * 65536.0).round() as i32)
}

fn unraw(v: [i32; 3]) -> [f64; 3] {
    v.map(|c| c as f64 / 65536.0)
}

fn c01(c: Rgb888) -> [f64; 3] {
    rgb(c).map(|x| x as f64 / 255.0)
}

#[test]
fn isqrt_is_exact() {
    for x in 0..1u64 << 20 {
        let r = isqrt(x);
        assert!(r * r <= x && (r + 1) * (r + 1) > x, "{x}");
    }
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for _ in 0..200_000 {
        let x = rng.next() >> (rng.next() % 64);
        let r = isqrt(x) as u128;
        assert!(r * r <= x as u128 && (r + 1) * (r + 1) > x as u128, "{x}");
    }
    for k in 1..=u32::MAX as u64 >> 16 {
        let k = k << 16 | 0xffff;
        assert_eq!(isqrt(k * k), k);
        assert_eq!(isqrt(k * k - 1), k - 1);
    }
    assert_eq!(isqrt(u64::MAX), u32::MAX as u64);
}

#[test]
fn rsqrt_table_is_exactly_rounded() {
    for (k, row) in RSQRT.iter().enumerate() {
        for (i, &e) in row.iter().enumerate() {
            let m = (1 << k) as f64 * (1.0 + i as f64 / 128.0);
            let exact = 65536.0 / m.sqrt();
            let v = e as f64 + 32768.0;
            assert!((v - exact).abs() <= 0.5, "{k} {i}: {v} {exact}");
        }
    }
}

/// Over the whole domain `[2^30, 2^32)` at a fine stride, both
/// octaves' ends, and at random.
#[test]
fn rsqrt_error_is_bounded() {
    let mut worst = 0.0f64;
    let mut worst_rel = 0.0f64;
    let mut check = |s: u32| {
        let r = rsqrt(s) as f64;
        let exact = 2f64.powi(31) / (s as f64).sqrt();
        worst = worst.max((r - exact).abs());
        worst_rel = worst_rel.max((r / exact - 1.0).abs());
    };
    let mut s = 1u64 << 30;
    while s < 1 << 32 {
        check(s as u32);
        s += 1021;
    }
    for s in [1u32 << 30, (1 << 31) - 1, 1 << 31, u32::MAX] {
        check(s);
    }
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..1_000_000 {
        check((rng.next() as u32) | 1 << 30);
    }
    println!("rsqrt: {worst} units, {worst_rel} relative");
    assert!(worst <= 1.25, "{worst}");
}

#[test]
fn div255_is_exact() {
    // The final correction, over every remainder it can see.
    for r in 0..1100u32 {
        assert_eq!((r + 1 + (r >> 8)) >> 8, r / 255, "{r}");
    }
    for x in 0..1u32 << 24 {
        assert_eq!(div255(x), x / 255, "{x}");
    }
    let mut rng = Rng(0x1234_5678_9abc_def1);
    for _ in 0..1_000_000 {
        let x = rng.next() as u32;
        assert_eq!(div255(x), x / 255, "{x}");
    }
    for x in (u32::MAX - 70_000)..=u32::MAX {
        assert_eq!(div255(x), x / 255, "{x}");
    }
}

#[test]
fn normalize_finds_direction_and_length() {
    let mut rng = Rng(0x0dd_ba11_cafe_f00d);
    let mut worst_dir = 0.0f64;
    let mut worst_len = 0.0f64;
    for _ in 0..200_000 {
        let mag = rng.log(1.0, 2f64.powi(61));
        let d = rng.dir();
        let v = d.map(|c| (c * mag).round() as i64);
        let Some(u) = normalize(v) else {
            assert_eq!(v, [0; 3]);
            continue;
        };
        let exact = v.map(|c| c as f64);
        let len = dot(exact, exact).sqrt();
        let e = norm(exact).unwrap();
        for (&d, e) in u.dir.iter().zip(e) {
            worst_dir = worst_dir.max((d as f64 / 65536.0 - e).abs());
        }
        let l = u.len as f64 * 2f64.powi(u.exp);
        worst_len = worst_len.max((l / len - 1.0).abs());
        assert!((1 << 15..=1 << 16).contains(&u.len), "{u:?}");
    }
    assert_eq!(normalize([0; 3]), None);
    // Small integer vectors are exact up to rounding of the direction.
    assert_eq!(
        normalize([0, 0, -1]),
        Some(Unit {
            dir: [0, 0, -65536],
            len: 1 << 15,
            exp: -15
        })
    );
    println!("direction {worst_dir}, length {worst_len}");
    assert!(worst_dir < 4.5e-5, "{worst_dir}");
    assert!(worst_len < 6.5e-5, "{worst_len}");
}

#[test]
fn pow_matches_f64() {
    let mut worst = [0.0f64; 256];
    for e in 0..=255u8 {
        for k in 0..=2048u32 {
            let x = (k * 32).min(ONE);
            for x in [x, x.saturating_sub(7), x.saturating_sub(1)] {
                let exact = (x as f64 / 65536.0).powi(e as i32);
                let got = pow(x, e) as f64 / 65536.0;
                let w = &mut worst[e as usize];
                *w = w.max((got - exact).abs());
            }
        }
    }
    for (e, &w) in worst.iter().enumerate() {
        // Rounding errors of the products, amplified by the later
        // squarings: about e / 2^17.
        assert!(w <= (e as f64 + 2.0) / 131_072.0, "{e}: {w}");
    }
    assert_eq!(pow(0, 0), ONE);
    assert_eq!(pow(0, 1), 0);
    assert_eq!(pow(ONE, 255), ONE);
    assert_eq!(pow(ONE / 2, 1), ONE / 2);
    assert_eq!(pow(ONE / 2, 16), 1);
}

#[test]
fn exp2_matches_f64() {
    for (i, &e) in EXP2.iter().enumerate() {
        let exact = 65536.0 * 2f64.powf(-(i as f64) / 32.0);
        assert!((e as f64 - exact).abs() <= 0.5, "{i}");
    }
    let mut worst = 0.0f64;
    for q in (0..20u64 << 16).step_by(7) {
        let exact = 2f64.powf(-(q as f64) / 65536.0);
        let got = exp2_neg(q) as f64 / 65536.0;
        worst = worst.max((got - exact).abs());
    }
    // The interpolation's error, (1/32)² / 8 · ln(2)², plus roundings.
    assert!(worst < 7.5e-5, "{worst}");
    assert_eq!(exp2_neg(0), ONE);
    assert_eq!(exp2_neg(1 << 40), 0);
}

#[test]
fn attenuation_is_one_at_the_light_and_zero_at_the_range() {
    assert_eq!(attenuation(0), ONE);
    let mut last = ONE;
    for t in 0..ONE {
        let a = attenuation(t);
        assert!(a <= last, "{t}");
        let x = t as f64 / 65536.0;
        let exact = (1.0 - x * x).powi(2) * 65536.0;
        assert!((a as f64 - exact).abs() <= 1.5, "{t}");
        last = a;
    }
    assert_eq!(attenuation(ONE - 1), 0);

    // Through shade: a light of range 2 at distance 2 and beyond adds
    // nothing, one very close adds everything.
    let mat = Material::new();
    let n = [0, 0, 1 << 16];
    let shade_at = |z: f32, x: f32| {
        let lamp = [PointLight::new(
            Vec3::new(x, 0.0, z),
            Rgb888::new(200, 200, 200),
            2.0,
        )];
        let lighting = Lighting::new(Rgb888::new(20, 20, 20)).point(&lamp);
        let s: LightSetup<1> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
        s.shade(&mat, [255; 3], [0; 3], n)
    };
    assert_eq!(shade_at(2.0, 0.0), [20; 3]);
    assert_eq!(shade_at(1.6, 1.2), [20; 3]);
    assert_eq!(shade_at(2.5, 0.0), [20; 3]);
    assert_eq!(shade_at(1e30, 0.0), [20; 3]);
    assert_eq!(shade_at(1.0 / 65536.0, 0.0), [220; 3]);
    assert_eq!(shade_at(1.999, 0.0), [20; 3]);
    assert!(shade_at(1.9, 0.0)[0] > 20);
    // Exactly at the light: no direction, no light.
    assert_eq!(shade_at(0.0, 0.0), [20; 3]);
}

#[test]
fn linear_fog_is_zero_at_the_eye_and_full_from_its_end() {
    let mat = Material::new();
    let fogged = |eye: f32| {
        let lighting = Lighting::new(Rgb888::new(100, 150, 200))
            .fog(Fog::Linear {
                start: 1.0,
                end: 5.0,
            })
            .fog_color(Rgb888::new(10, 20, 30));
        let s: LightSetup<0> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::new(0.0, 0.0, eye)).unwrap();
        s.shade(&mat, [255; 3], [0; 3], [0, 0, 1 << 16])
    };
    assert_eq!(fogged(0.0), [100, 150, 200]);
    assert_eq!(fogged(1.0), [100, 150, 200]);
    assert_eq!(fogged(3.0), [55, 85, 115]);
    assert_eq!(fogged(5.0), [10, 20, 30]);
    assert_eq!(fogged(5.001), [10, 20, 30]);
    assert_eq!(fogged(-7.0), [10, 20, 30]);
    assert_eq!(fogged(1e9), [10, 20, 30]);

    // The factor itself: 0 up to start, 1 from end on.
    let s: LightSetup<0> = LightSetup::new(
        &Lighting::new(Rgb888::BLACK).fog(Fog::Linear {
            start: 0.0,
            end: 3.0,
        }),
        &Mat4::IDENTITY,
        Vec3::default(),
    )
    .unwrap();
    let FixedFog::Linear { scale, offset } = s.core.fog else {
        panic!()
    };
    let f = |d: i64| {
        let q = normalize([d, 0, 0]).map_or(0, |u| scale.apply(u.len, u.exp));
        (q as i64 - offset).clamp(0, ONE as i64)
    };
    assert_eq!(f(0), 0);
    assert_eq!(f(3 << 16), ONE as i64);
    assert_eq!(f(4 << 16), ONE as i64);
    assert_eq!(f(3 << 15), ONE as i64 / 2);
}

/// The vertex stage's lighting before this module, copied.
fn old_light_vertex(
    dir: [i32; 3],
    color: [u32; 3],
    ambient: [u32; 3],
    n: [i32; 3],
    base: [u8; 3],
) -> [u8; 3] {
    let d = n[0] as i64 * dir[0] as i64 + n[1] as i64 * dir[1] as i64 + n[2] as i64 * dir[2] as i64;
    let ndotl = (d >> 24).clamp(0, 256) as u32;
    let mut out = [0u8; 3];
    for c in 0..3 {
        let intensity = ambient[c] * 256 + color[c] * ndotl;
        let v = (base[c] as u32 * intensity + 32_640) / 65_280;
        out[c] = v.min(255) as u8;
    }
    out
}

/// The old vertex stage's set-up of `scene::Light`, copied.
fn old_dir(model: &Mat4, direction: Vec3) -> [i32; 3] {
    let local = model
        .inverse_transform_vector(direction)
        .and_then(|v| v.normalize())
        .unwrap();
    let fx = |v: f32| (v * 65536.0) as i32;
    [fx(local.x), fx(local.y), fx(local.z)]
}

#[test]
fn reproduces_scene_light_bit_for_bit() {
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let mat = Material::new();
    let mut n_lit = 0;
    for case in 0..4_000 {
        let model = Mat4::rotation_y(rng.range(-3.0, 3.0) as f32)
            * Mat4::rotation_x(rng.range(-3.0, 3.0) as f32)
            * Mat4::scale(Vec3::new(
                rng.log(0.1, 10.0) as f32,
                rng.log(0.1, 10.0) as f32,
                rng.log(0.1, 10.0) as f32,
            ));
        let model = Mat4::translation(vec3([0.0; 3].map(|_| rng.range(-9.0, 9.0)))) * model;
        let direction = vec3(rng.dir().map(|c| c * rng.log(0.01, 100.0)));
        let light = crate::scene::Light::new(direction)
            .color(rng.color())
            .ambient(rng.color());
        let dl = [DirectionalLight::new(light.direction, light.color)];
        let lighting = Lighting::new(light.ambient).directional(&dl);
        let eye = vec3([0.0; 3].map(|_| rng.range(-50.0, 50.0)));
        let setup: LightSetup<3> = LightSetup::new(&lighting, &model, eye).unwrap();
        let dir = old_dir(&model, light.direction);
        let (color, ambient) = (
            rgb(light.color).map(u32::from),
            rgb(light.ambient).map(u32::from),
        );
        for k in 0..250 {
            // Unit normals as meshes hold them, and every few
            // vertices arbitrary bits.
            let normal = if k % 5 == 4 {
                let mut b = || (rng.next() as i32) >> (rng.next() % 32);
                [b(), b(), b()]
            } else {
                raw(rng.dir())
            };
            let base = [rng.byte(), rng.byte(), rng.byte()];
            let p = [rng.next() as i32, rng.next() as i32, rng.next() as i32];
            let expected = old_light_vertex(dir, color, ambient, normal, base);
            let got = setup.shade(&mat, base, p, normal);
            assert_eq!(got, expected, "case {case}: n {normal:?} base {base:?}");
            n_lit += (expected != old_light_vertex(dir, color, ambient, [0; 3], base)) as u32;
        }
    }
    assert!(n_lit > 300_000, "{n_lit}");
}

/// The model in `f64`, in world space.
struct Reference<'a> {
    lighting: &'a Lighting<'a>,
    eye: [f64; 3],
}

impl Reference<'_> {
    /// The exact colour, and whether a highlight is cut off right at
    /// this vertex (`n·l` about 0, where the model is discontinuous).
    fn shade(&self, mat: &Material, base: [u8; 3], p: [f64; 3], n: [f64; 3]) -> ([f64; 3], bool) {
        let mut cut = false;
        let base = base.map(|b| b as f64 / 255.0);
        let (ma, md, ms) = (c01(mat.ambient), c01(mat.diffuse), c01(mat.specular));
        let amb = c01(self.lighting.ambient);
        let mut lit = [0.0; 3];
        for c in 0..3 {
            lit[c] = base[c] * ma[c] * amb[c];
        }
        let to_eye = sub(self.eye, p);
        let v = norm(to_eye);
        let mut add = |l: [f64; 3], att: f64, color: [f64; 3]| {
            let nl = dot(n, l);
            cut |= mat.specular != Rgb888::BLACK && nl.abs() < 1e-3;
            if nl <= 0.0 {
                return;
            }
            let nl = nl.min(1.0);
            let spec = match v.and_then(|v| norm([l[0] + v[0], l[1] + v[1], l[2] + v[2]])) {
                Some(h) => dot(n, h).clamp(0.0, 1.0).powi(mat.shininess as i32),
                None => 0.0,
            };
            for c in 0..3 {
                lit[c] += att * color[c] * (base[c] * md[c] * nl + ms[c] * spec);
            }
        };
        for l in self.lighting.directional {
            add(norm(f64v(l.direction)).unwrap(), 1.0, c01(l.color));
        }
        for l in self.lighting.point {
            let d = sub(f64v(l.position), p);
            let dist = dot(d, d).sqrt();
            let r = l.range as f64;
            if dist >= r || dist == 0.0 {
                continue;
            }
            let x = dist / r;
            add(norm(d).unwrap(), (1.0 - x * x).powi(2), c01(l.color));
        }
        let dist = dot(to_eye, to_eye).sqrt();
        let f = match self.lighting.fog {
            Fog::None => 0.0,
            Fog::Linear { start, end } => {
                ((dist - start as f64) / (end as f64 - start as f64)).clamp(0.0, 1.0)
            }
            Fog::Exponential { density } => 1.0 - (-(density as f64) * dist).exp(),
        };
        let fog = c01(self.lighting.fog_color);
        let mut out = [0.0; 3];
        for c in 0..3 {
            out[c] = 255.0 * (lit[c].min(1.0) * (1.0 - f) + fog[c] * f);
        }
        (out, cut)
    }
}

/// A random scene around a vertex: lights and the eye at random
/// distances, random materials, fog of a scale that matters.
struct Case {
    directional: Vec<DirectionalLight>,
    point: Vec<PointLight>,
    ambient: Rgb888,
    fog: Fog,
    fog_color: Rgb888,
    eye: [f64; 3],
    material: Material,
    base: [u8; 3],
}

impl Case {
    /// `near`: the shortest range and eye distance, in units of
    /// `world_scale` (point lights are at least a tenth of their range
    /// away when `near >= 1`).
    fn random(rng: &mut Rng, p: [f64; 3], world_scale: f64, near: f64, shininess: u8) -> Self {
        let mut directional = Vec::new();
        for _ in 0..rng.next() % 3 {
            let d = rng.dir().map(|c| c * rng.log(0.01, 100.0));
            directional.push(DirectionalLight::new(vec3(d), rng.color()));
        }
        let mut point = Vec::new();
        for _ in 0..rng.next() % 3 {
            let range = rng.log(near, 500.0) * world_scale;
            let closest = if near >= 1.0 { 0.1 } else { 0.0 };
            let d = rng.dir().map(|c| c * range * rng.range(closest, 1.1));
            let pos = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
            point.push(PointLight::new(vec3(pos), rng.color(), range as f32));
        }
        let e = rng
            .dir()
            .map(|c| c * rng.log(near * 10.0, 5000.0) * world_scale);
        let eye = f64v(vec3([p[0] + e[0], p[1] + e[1], p[2] + e[2]]));
        let dist = dot(sub(eye, p), sub(eye, p)).sqrt();
        let fog = match rng.next() % 3 {
            0 => Fog::None,
            1 => {
                let start = dist * rng.range(-0.5, 1.2);
                Fog::Linear {
                    start: start as f32,
                    end: (start + dist * rng.range(0.05, 2.0)) as f32,
                }
            }
            _ => Fog::Exponential {
                density: (rng.range(0.0, 3.0) / dist) as f32,
            },
        };
        Self {
            directional,
            point,
            ambient: rng.color(),
            fog,
            fog_color: rng.color(),
            eye,
            material: Material {
                ambient: rng.color(),
                diffuse: rng.color(),
                specular: if rng.next().is_multiple_of(4) {
                    Rgb888::BLACK
                } else {
                    rng.color()
                },
                shininess,
            },
            base: [rng.byte(), rng.byte(), rng.byte()],
        }
    }

    fn lighting(&self) -> Lighting<'_> {
        Lighting {
            ambient: self.ambient,
            directional: &self.directional,
            point: &self.point,
            fog: self.fog,
            fog_color: self.fog_color,
        }
    }

    /// A unit normal, world space: uniformly random, or (half the time)
    /// near the half vector of one of the lights, to probe highlights.
    fn normal(&self, rng: &mut Rng, p: [f64; 3]) -> [f64; 3] {
        let lights: Vec<[f64; 3]> = self
            .directional
            .iter()
            .map(|l| f64v(l.direction))
            .chain(self.point.iter().map(|l| sub(f64v(l.position), p)))
            .collect();
        if lights.is_empty() || rng.next().is_multiple_of(2) {
            return rng.dir();
        }
        let l = norm(lights[(rng.next() % lights.len() as u64) as usize]);
        let v = norm(sub(self.eye, p));
        let (Some(l), Some(v)) = (l, v) else {
            return rng.dir();
        };
        let Some(h) = norm([l[0] + v[0], l[1] + v[1], l[2] + v[2]]) else {
            return rng.dir();
        };
        let sigma = rng.log(1e-4, 0.5);
        let d = rng.dir();
        norm([
            h[0] + sigma * d[0],
            h[1] + sigma * d[1],
            h[2] + sigma * d[2],
        ])
        .unwrap_or(h)
    }

    /// Whether a half vector is ill-conditioned (`|l + v|` small), where
    /// no implementation's highlight is accurate.
    fn ill_conditioned(&self, p: [f64; 3]) -> bool {
        let Some(v) = norm(sub(self.eye, p)) else {
            return true;
        };
        let lights = self
            .directional
            .iter()
            .map(|l| f64v(l.direction))
            .chain(self.point.iter().map(|l| sub(f64v(l.position), p)));
        lights.into_iter().any(|l| {
            let l = norm(l).unwrap_or([0.0; 3]);
            let h = [l[0] + v[0], l[1] + v[1], l[2] + v[2]];
            dot(h, h) < 0.01
        })
    }
}

/// The largest error per shininess band against the `f64` model, with
/// the identity model matrix, so that set-up in `f32` is exact and only
/// the fixed-point evaluation is measured. Positions over the whole
/// 16.16 range (mostly within ±1000), lights from 0.05 to 500 units
/// of range, normals half random, half near a highlight. The bounds
/// asserted, ±1.5 up to shininess 160 and ±2.5 above, are a little above
/// the worst errors found over 600,000 cases (this runs 30,000): 1.23,
/// 1.36 and 2.03 for shininess up to 64, up to 160 and above.
#[test]
fn matches_the_f64_model() {
    let mut rng = Rng(0xfeed_beef_0bad_cafe);
    let bands: [(u8, u8, f64); 3] = [(0, 64, 1.5), (65, 160, 1.5), (161, 255, 2.5)];
    let mut worst = [0.0f64; 3];
    let mut worst_case: [String; 3] = Default::default();
    let mut hist = [0u32; 8];
    for case in 0..30_000 {
        let band = case % 3;
        let (lo, hi, _) = bands[band];
        let shininess = lo + (rng.next() % (hi - lo + 1) as u64) as u8;
        let extent = if rng.next().is_multiple_of(8) {
            30_000.0
        } else {
            1000.0
        };
        let p = raw([0.0; 3].map(|_| rng.range(-extent, extent)));
        let pf = unraw(p);
        let c = Case::random(&mut rng, pf, 1.0, 0.05, shininess);
        if c.material.specular != Rgb888::BLACK && c.ill_conditioned(pf) {
            continue;
        }
        let lighting = c.lighting();
        let setup: LightSetup<4> =
            LightSetup::new(&lighting, &Mat4::IDENTITY, vec3(c.eye)).unwrap();
        let reference = Reference {
            lighting: &lighting,
            eye: c.eye,
        };
        for _ in 0..8 {
            let n = raw(c.normal(&mut rng, pf));
            let got = setup.shade(&c.material, c.base, p, n);
            let (exact, cut) = reference.shade(&c.material, c.base, pf, unraw(n));
            if cut {
                continue;
            }
            for ch in 0..3 {
                let e = (got[ch] as f64 - exact[ch]).abs();
                hist[(e as usize).min(7)] += 1;
                if e > worst[band] {
                    worst[band] = e;
                    worst_case[band] = format!(
                        "case {case}: got {got:?}, exact {exact:?}, p {pf:?}, n {n:?}, base {:?}, ambient {:?}, fog colour {:?}, {:?} {:?} {:?} {:?} {:?}",
                        c.base,
                        c.ambient,
                        c.fog_color,
                        c.material,
                        c.directional,
                        c.point,
                        c.fog,
                        c.eye
                    );
                }
                assert!(e <= bands[band].2, "{}", worst_case[band]);
            }
        }
    }
    println!("worst {worst:?}, histogram of |error| {hist:?}");
    for w in &worst_case {
        println!("{w}");
    }
}

/// Rigid transforms with uniform scale (and reflections): the model in
/// world space against set-up into model space. Set-up's `f32` adds its
/// relative error of about 2^-24 to light and eye positions, so lights
/// and the eye keep some distance (ranges from 1 unit, lights beyond a
/// tenth of their range, the eye beyond 10 units) and shininess stays
/// up to 32. The worst error found over 200,000 cases was 1.36.
/// A fraction of white is the grey of that many 255ths, rounded, and
/// lights the same as that colour.
#[test]
fn fractions_are_grey_intensities() {
    for (f, level) in [
        (0.8f32, 204u8),
        (0.0, 0),
        (1.0, 255),
        (0.5, 128),
        (0.001, 0),
        (0.003, 1),
        (-2.0, 0),
        (7.0, 255),
        (f32::NAN, 0),
        (f32::INFINITY, 255),
    ] {
        let grey = Rgb888::new(level, level, level);
        assert_eq!(Intensity::from(f).0, grey, "{f}");
        assert_eq!(Intensity::from(f as f64).0, grey, "{f}");
    }
    let dir = Vec3::new(0.3, 1.0, 0.2);
    let (a, b) = (
        [DirectionalLight::new(dir, 0.8)],
        [DirectionalLight::new(dir, Rgb888::new(204, 204, 204))],
    );
    assert_eq!(a, b);
    let (la, lb) = (
        Lighting::new(0.2).directional(&a),
        Lighting::new(Rgb888::new(51, 51, 51)).directional(&b),
    );
    assert_eq!(la, lb);
    let lamp = PointLight::new(Vec3::new(0.0, 0.0, 2.0), 0.5, 4.0);
    assert_eq!(lamp.color, Rgb888::new(128, 128, 128));
}

#[test]
fn model_space_matches_world_space() {
    let mut rng = Rng(0xabad_1dea_f00d_0042);
    let mut worst = 0.0f64;
    for case in 0..6_000 {
        let s = rng.log(0.1, 10.0);
        // A rotation from a random unit quaternion, orthogonal to f64
        // precision (the f32 rotation matrices are only to f32's).
        let q = loop {
            let q = [0.0; 4].map(|_| rng.range(-1.0, 1.0));
            let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if l > 0.1 && l <= 1.0 {
                break q.map(|x| x / l);
            }
        };
        let [w, x, y, z] = q;
        let rot = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y + w * z),
                2.0 * (x * z - w * y),
            ],
            [
                2.0 * (x * y - w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z + w * x),
            ],
            [
                2.0 * (x * z + w * y),
                2.0 * (y * z - w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let flip = if case % 2 == 1 { -1.0 } else { 1.0 };
        let col = |c: usize| {
            let k = s * if c == 1 { flip } else { 1.0 };
            [
                (rot[c][0] * k) as f32,
                (rot[c][1] * k) as f32,
                (rot[c][2] * k) as f32,
                0.0,
            ]
        };
        let model = Mat4 {
            m: [col(0), col(1), col(2), [0.0, 0.0, 0.0, 1.0]],
        };
        let model = Mat4::translation(vec3([0.0; 3].map(|_| rng.range(-100.0, 100.0)))) * model;
        let mf = model.m.map(|c| c.map(|x| x as f64));
        let p = raw([0.0; 3].map(|_| rng.range(-300.0, 300.0)));
        let pm = unraw(p);
        let pw: [f64; 3] = core::array::from_fn(|r| {
            mf[0][r] * pm[0] + mf[1][r] * pm[1] + mf[2][r] * pm[2] + mf[3][r]
        });
        let scale = (0..3)
            .map(|c| {
                dot(
                    [mf[c][0], mf[c][1], mf[c][2]],
                    [mf[c][0], mf[c][1], mf[c][2]],
                )
            })
            .sum::<f64>()
            / 3.0;
        let scale = scale.sqrt();
        let shininess = (rng.next() % 33) as u8;
        let c = Case::random(&mut rng, pw, s.max(1.0), 1.0, shininess);
        if c.material.specular != Rgb888::BLACK && c.ill_conditioned(pw) {
            continue;
        }
        let lighting = c.lighting();
        let setup: LightSetup<4> = LightSetup::new(&lighting, &model, vec3(c.eye)).unwrap();
        let reference = Reference {
            lighting: &lighting,
            eye: c.eye,
        };
        for _ in 0..8 {
            // The model-space normal Qᵀ n = Mᵀ n / s.
            let nw = c.normal(&mut rng, pw);
            let n = raw(core::array::from_fn(|k| {
                (mf[k][0] * nw[0] + mf[k][1] * nw[1] + mf[k][2] * nw[2]) / scale
            }));
            let nm = unraw(n);
            // For a similarity M = s Q, model-space n·l is (Q n)·l, and
            // Q n = M n / s.
            let nw: [f64; 3] = core::array::from_fn(|r| {
                (mf[0][r] * nm[0] + mf[1][r] * nm[1] + mf[2][r] * nm[2]) / scale
            });
            let got = setup.shade(&c.material, c.base, p, n);
            let (exact, cut) = reference.shade(&c.material, c.base, pw, nw);
            if cut {
                continue;
            }
            for ch in 0..3 {
                let e = (got[ch] as f64 - exact[ch]).abs();
                worst = worst.max(e);
                assert!(
                    e <= 1.5,
                    "case {case}: got {got:?}, exact {exact:?}, {:?} {:?} {:?} {:?}",
                    c.material,
                    c.directional,
                    c.point,
                    c.fog
                );
            }
        }
    }
    println!("worst {worst}");
}

#[test]
fn bad_input_is_an_error() {
    let white = Rgb888::WHITE;
    let id = Mat4::IDENTITY;
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let setup = |l: &Lighting<'_>| LightSetup::<2>::new(l, &id, eye).map(|_| ());
    let dir = |d: Vec3| [DirectionalLight::new(d, white)];
    for (i, d) in [
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
        Vec3::default(),
    ]
    .into_iter()
    .enumerate()
    {
        let ok = DirectionalLight::new(Vec3::new(0.0, 1.0, 0.0), white);
        let lights = [ok, dir(d)[0]];
        assert_eq!(
            setup(&Lighting::new(white).directional(&lights)),
            Err(LightError::BadDirection { light: 1 }),
            "{i}"
        );
    }
    let point = |p: Vec3, r: f32| [PointLight::new(p, white, r)];
    for p in [
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
    ] {
        assert_eq!(
            setup(&Lighting::new(white).point(&point(p, 1.0))),
            Err(LightError::BadPosition { light: 0 })
        );
    }
    for r in [0.0, -1.0, f32::NAN, f32::INFINITY, -0.0] {
        assert_eq!(
            setup(&Lighting::new(white).point(&point(Vec3::default(), r))),
            Err(LightError::BadRange { light: 0 }),
            "{r}"
        );
    }
    for fog in [
        Fog::Linear {
            start: 2.0,
            end: 2.0,
        },
        Fog::Linear {
            start: 3.0,
            end: 2.0,
        },
        Fog::Linear {
            start: f32::NAN,
            end: 2.0,
        },
        Fog::Linear {
            start: 0.0,
            end: f32::INFINITY,
        },
        Fog::Linear {
            start: -3e38,
            end: 3e38,
        },
        Fog::Exponential { density: -1.0 },
        Fog::Exponential { density: f32::NAN },
        Fog::Exponential {
            density: f32::INFINITY,
        },
    ] {
        assert_eq!(
            setup(&Lighting::new(white).fog(fog)),
            Err(LightError::BadFog),
            "{fog:?}"
        );
    }
    let three = dir(Vec3::new(1.0, 0.0, 0.0)).repeat(3);
    assert_eq!(
        setup(&Lighting::new(white).directional(&three)),
        Err(LightError::TooManyLights { count: 3, max: 2 })
    );
    let one_point = point(Vec3::default(), 1.0);
    let one_each = Lighting::new(white)
        .directional(&three[..1])
        .point(&one_point);
    assert_eq!(setup(&one_each), Ok(()));
    let two_points = [point(Vec3::default(), 1.0)[0]; 2];
    assert_eq!(
        setup(&one_each.point(&two_points)),
        Err(LightError::TooManyLights { count: 3, max: 2 })
    );
    for m in [
        Mat4::scale(Vec3::new(1.0, 0.0, 1.0)),
        Mat4::translation(Vec3::new(f32::NAN, 0.0, 0.0)),
    ] {
        assert_eq!(
            LightSetup::<1>::new(&Lighting::new(white), &m, eye).map(|_| ()),
            Err(LightError::BadMatrix)
        );
    }
    assert_eq!(
        LightSetup::<1>::new(&Lighting::new(white), &id, Vec3::new(f32::NAN, 0.0, 0.0)).map(|_| ()),
        Err(LightError::BadMatrix)
    );
    // Every error has a message.
    let e = LightError::TooManyLights { count: 3, max: 2 };
    assert_eq!(format!("{e}"), "3 lights exceed the capacity of 2");
}

/// Zero, huge and random normals, extreme positions, and lights and
/// eyes far out: a defined colour, never a panic (the tests run with
/// overflow checks).
#[test]
fn any_normal_and_position_gives_a_colour() {
    let mut rng = Rng(0x7777_1234_5678_9999);
    let dl = [
        DirectionalLight::new(Vec3::new(1.0, 2.0, 3.0), Rgb888::WHITE),
        DirectionalLight::new(Vec3::new(-1.0, 0.0, 0.0), Rgb888::new(9, 99, 199)),
    ];
    let pl = [
        PointLight::new(Vec3::new(30000.0, -30000.0, 0.0), Rgb888::WHITE, 1e5),
        PointLight::new(Vec3::new(1.0, 0.0, 0.0), Rgb888::new(255, 0, 0), 1e-4),
    ];
    let mat = Material::new()
        .specular(Rgb888::WHITE)
        .shininess(255)
        .diffuse(Rgb888::new(1, 128, 255));
    let mut seen = [0u32; 3];
    for fog in [
        Fog::None,
        Fog::Linear {
            start: 1.0,
            end: 1.000_001,
        },
        Fog::Exponential { density: 1e30 },
    ] {
        for model in [
            Mat4::IDENTITY,
            Mat4::scale(Vec3::new(1e-6, 1e-6, 1e-6)),
            Mat4::scale(Vec3::new(3e4, 3e4, 3e4)),
        ] {
            let lighting = Lighting::new(Rgb888::new(10, 20, 30))
                .directional(&dl)
                .point(&pl)
                .fog(fog)
                .fog_color(Rgb888::new(1, 2, 3));
            let s: LightSetup<4> =
                LightSetup::new(&lighting, &model, Vec3::new(-1e3, 2e3, 1e4)).unwrap();
            let edge = [
                0,
                1,
                -1,
                i32::MAX,
                i32::MIN,
                1 << 17,
                (1 << 17) + 1,
                -(1 << 17) - 1,
            ];
            for &a in &edge {
                for &b in &edge {
                    for &c in &edge {
                        let out = s.shade(&mat, [255, 128, 0], [a, b, c], [c, a, b]);
                        seen[0] += out[0] as u32;
                    }
                }
            }
            for _ in 0..20_000 {
                let mut r = || (rng.next() as i32) >> (rng.next() % 32);
                let out = s.shade(&mat, [255; 3], [r(), r(), r()], [r(), r(), r()]);
                seen[1] += out[1] as u32;
            }
            // A zero normal: ambient only (and fog).
            let z = s.shade(&mat, [255; 3], [0; 3], [0; 3]);
            seen[2] += z[2] as u32;
        }
    }
    assert!(seen.iter().all(|&s| s > 0), "{seen:?}");

    // Zero normal, no fog: exactly the ambient term.
    let lighting = Lighting::new(Rgb888::new(10, 20, 30))
        .directional(&dl)
        .point(&pl);
    let s: LightSetup<4> = LightSetup::new(&lighting, &Mat4::IDENTITY, Vec3::default()).unwrap();
    assert_eq!(s.shade(&mat, [255; 3], [0; 3], [0; 3]), [10, 20, 30]);
    // A huge normal: saturated diffuse light from the lights in front.
    assert_eq!(
        s.shade(
            &Material::new(),
            [255; 3],
            [0; 3],
            [i32::MAX, i32::MAX, i32::MAX]
        ),
        [255, 255, 255]
    );
}

#[test]
fn far_and_unreachable_lights_are_off() {
    let pl = [
        PointLight::new(Vec3::new(1e20, 0.0, 0.0), Rgb888::WHITE, 10.0),
        PointLight::new(Vec3::new(0.0, 0.0, 1.0), Rgb888::WHITE, 1e-9),
    ];
    let s: LightSetup<2> = LightSetup::new(
        &Lighting::new(Rgb888::BLACK).point(&pl),
        &Mat4::IDENTITY,
        Vec3::default(),
    )
    .unwrap();
    assert!(s.lights.iter().all(|l| l.source == Source::Off));
    assert_eq!(
        LightSetup::<2>::new(
            &Lighting::new(Rgb888::BLACK).point(&[PointLight::new(
                Vec3::default(),
                Rgb888::WHITE,
                1e30
            )]),
            &Mat4::IDENTITY,
            Vec3::default()
        )
        .map(|_| ()),
        Err(LightError::BadRange { light: 0 })
    );
}

#[test]
fn raw_positions_are_rounded() {
    for x in [189.1292f32, -189.1292, 0.3, -0.3, 32767.99, 1e6, -3.5e12] {
        let exact = (x as f64 * 65536.0).round() as i64;
        assert_eq!(to_raw(Vec3::new(x, 0.0, 0.0)), Some([exact, 0, 0]), "{x}");
    }
    // Half a raw unit rounds away from zero.
    let half = 0.5 / 65536.0;
    assert_eq!(to_raw(Vec3::new(half, -half, 0.0)), Some([1, -1, 0]));
    assert_eq!(to_raw(Vec3::new(f32::NAN, 0.0, 0.0)), None);
    assert_eq!(to_raw(Vec3::new(0.0, 2e13, 0.0)), None);
}

#[test]
fn scale_applies_like_f64() {
    let mut rng = Rng(0x3141_5926_5358_9793);
    for _ in 0..100_000 {
        let x = rng.log(1e-30, 1e30) as f32;
        let s = Scale::from_f32(x).unwrap();
        let len = (1 << 15) + (rng.next() % (1 << 15)) as u32;
        let exp = (rng.next() % 120) as i32 - 60;
        let exact = len as f64 * 2f64.powi(exp) * x as f64;
        let got = s.apply(len, exp) as f64;
        if exact < SCALE_CAP as f64 / 2.0 {
            // The mantissa's rounding to 16 bits: 2^-16 relative.
            let bound = 0.5 + exact / 65536.0;
            assert!(
                (got - exact).abs() <= bound,
                "{x} {len} {exp}: {got} {exact}"
            );
        } else {
            assert!(got >= SCALE_CAP as f64 / 2.0 - 1.0);
        }
    }
    assert_eq!(Scale::from_f32(0.0), Some(Scale { m: 0, s: 0 }));
    assert_eq!(Scale::from_f32(-1.0), None);
    assert_eq!(Scale::from_f32(f32::NAN), None);
    assert_eq!(Scale::from_f32(1.0).unwrap().apply(1 << 15, -15), 1);
}

/// The set-ups without the general lighting's code (`check_lighting` for a
/// frame's lights, `one_light` and `model_checks` per draw) give the
/// general set-up's results and errors, edge cases included.
#[test]
fn checks_without_conversions_agree_with_the_general_setup() {
    let specials = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        1e-30,
        1e-45,
        3e38,
        -3e38,
        1e13,
        2e13,
        1.8e13,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ];
    let mut rng = Rng(0x5eed_1234_abcd_0042);
    let mut pick = |rng: &mut Rng| -> f32 {
        if rng.next().is_multiple_of(3) {
            specials[(rng.next() % specials.len() as u64) as usize]
        } else {
            rng.log(1e-6, 1e15) as f32
                * if rng.next().is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                }
        }
    };
    let mut agreed = [0usize; 2];
    for case in 0..20_000 {
        let v = |rng: &mut Rng, pick: &mut dyn FnMut(&mut Rng) -> f32| {
            Vec3::new(pick(rng), pick(rng), pick(rng))
        };
        let eye = if case % 4 == 0 {
            v(&mut rng, &mut pick)
        } else {
            Vec3::new(0.0, 1.0, 5.0)
        };
        let dirs = [
            DirectionalLight::new(v(&mut rng, &mut pick), 0.5),
            DirectionalLight::new(Vec3::new(0.3, -1.0, 0.2), 0.7),
        ];
        let points = [
            PointLight::new(v(&mut rng, &mut pick), 0.8, pick(&mut rng)),
            PointLight::new(Vec3::new(1.0, 2.0, 3.0), 0.8, pick(&mut rng)),
        ];
        let fog = match rng.next() % 4 {
            0 => Fog::None,
            1 => Fog::Linear {
                start: pick(&mut rng),
                end: pick(&mut rng),
            },
            2 => Fog::Exponential {
                density: pick(&mut rng),
            },
            _ => Fog::Linear {
                start: 1.0,
                end: 1.0 + pick(&mut rng).abs(),
            },
        };
        let nd = (rng.next() % 3) as usize;
        let np = (rng.next() % 3) as usize;
        let mut lighting = Lighting::new(0.2)
            .directional(&dirs[..nd])
            .point(&points[..np]);
        lighting.fog = fog;
        let max = [1, 8][(rng.next() % 2) as usize];
        let general = match max {
            1 => LightSetup::<1>::new(&lighting, &Mat4::IDENTITY, eye).map(|_| ()),
            _ => LightSetup::<8>::new(&lighting, &Mat4::IDENTITY, eye).map(|_| ()),
        };
        assert_eq!(
            check_lighting(&lighting, eye, max),
            general,
            "{lighting:?} eye {eye:?}"
        );

        // One light under a draw's matrix.
        let model = match rng.next() % 4 {
            0 => Mat4::scale(v(&mut rng, &mut pick)),
            1 => Mat4::translation(v(&mut rng, &mut pick)),
            2 => Mat4::rotation_y(pick(&mut rng)) * Mat4::scale(Vec3::new(2.0, 2.0, 2.0)),
            _ => Mat4::IDENTITY,
        };
        let one = Lighting::new(0.2).directional(&dirs[..1]);
        let general: Result<LightSetup<8>, _> = LightSetup::new(&one, &model, eye);
        let fast = one_light(dirs[0].direction, &model, eye);
        match general {
            Ok(s) => {
                let (dir, _, _) = s.single_directional().unwrap();
                assert_eq!(fast, Ok(dir), "{model:?} eye {eye:?}");
                agreed[0] += 1;
            }
            Err(e) => {
                assert_eq!(fast, Err(e), "{model:?} eye {eye:?}");
                agreed[1] += 1;
            }
        }
        let unlit = Lighting::new(0.2);
        let general: Result<LightSetup<8>, _> = LightSetup::new(&unlit, &model, eye);
        assert_eq!(model_checks(&model, eye), general.map(|_| ()));
    }
    // Both outcomes were exercised.
    assert!(agreed.iter().all(|&n| n > 1_000), "{agreed:?}");
}
