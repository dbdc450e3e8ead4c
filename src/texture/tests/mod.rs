//! Tests of texture layout checks, addressing and filtering. Shared here:
//! a reproducible random source, the wrap modes' references and small
//! grey textures.

mod bilinear;
mod formats;
mod nearest;

use super::*;

/// A small xorshift generator: reproducible pseudo-random raw values.
struct XorShift(u32);

impl XorShift {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// A raw 16.16 coordinate: mostly near `-3..3`, sometimes anywhere.
    fn coordinate(&mut self) -> i32 {
        let r = self.next();
        match r % 4 {
            0 => r as i32,
            _ => (self.next() % (6 << 16)) as i32 - (3 << 16),
        }
    }
}

const WRAPS: [Wrap; 3] = [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge];

/// Extreme and seam raw coordinates, tried everywhere.
const SPECIAL: [i32; 16] = [
    i32::MIN,
    i32::MIN + 1,
    i32::MAX,
    i32::MAX - 1,
    -(2 << 16),
    -(1 << 16) - 1,
    -(1 << 16),
    -(1 << 16) + 1,
    -1,
    0,
    1,
    (1 << 16) - 1,
    1 << 16,
    (1 << 16) + 1,
    (2 << 16) - 1,
    2 << 16,
];

fn fx(raw: i32) -> I16F16 {
    I16F16::from_bits(raw)
}

/// Maps integer texel coordinate `i` by `wrap` onto `0..size`, written
/// straight from the OpenGL specification, in `i64`.
fn wrap_reference(i: i64, size: i64, wrap: Wrap) -> i64 {
    match wrap {
        Wrap::Repeat => i.rem_euclid(size),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * size);
            if m < size {
                m
            } else {
                2 * size - 1 - m
            }
        }
        Wrap::ClampToEdge => i.clamp(0, size - 1),
    }
}

/// The nearest texel of `floor(u · size)`, in `i64`.
fn nearest_reference(raw: i32, size: u32, wrap: Wrap) -> u32 {
    let i = (raw as i64 * size as i64).div_euclid(1 << 16);
    wrap_reference(i, size as i64, wrap) as u32
}

fn axis(size: u32, wrap: Wrap) -> Axis {
    Axis {
        wrap,
        ..Axis::new(size)
    }
}

/// Gray8 texture whose texel `(x, y)` is `value(x, y)`.
fn gray(width: u32, height: u32, value: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| value(x, y))
        .collect()
}

/// A distinct grey per texel, so the texel read is identifiable.
fn id(width: u32) -> impl Fn(u32, u32) -> u8 {
    move |x, y| (y * width + x) as u8
}

/// Bilinear in `f64` with exact weights, before rounding.
fn bilinear_reference(t: &Texture, data: &[u8], raw_u: i32, raw_v: i32) -> f64 {
    let axis = |raw: i32, size: u32, wrap: Wrap| {
        let s = raw as f64 / 65_536.0 * size as f64 - 0.5;
        let i0 = s.floor();
        let n = size as i64;
        (
            wrap_reference(i0 as i64, n, wrap) as usize,
            wrap_reference(i0 as i64 + 1, n, wrap) as usize,
            s - i0,
        )
    };
    let (wu, wv) = t.wrap_modes();
    let (x0, x1, a) = axis(raw_u, t.width(), wu);
    let (y0, y1, b) = axis(raw_v, t.height(), wv);
    let w = t.width() as usize;
    let c = |x: usize, y: usize| data[y * w + x] as f64;
    (1.0 - a) * (1.0 - b) * c(x0, y0)
        + a * (1.0 - b) * c(x1, y0)
        + (1.0 - a) * b * c(x0, y1)
        + a * b * c(x1, y1)
}
