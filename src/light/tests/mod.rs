//! Tests of lighting: the set-up, the per-vertex arithmetic against `f64`
//! references, and the documented error bounds. Shared here: a
//! reproducible random source and `f64` vector helpers.

mod arith;
mod model;
mod setup;

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
