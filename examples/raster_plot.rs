//! Plots the rasterizer benchmarks: time per triangle against triangle
//! size for each rasterizer, from criterion's results, as a PNG (for
//! BENCHMARKS.md), and prints the same figures as a Markdown table.
//!
//! ```text
//! cargo bench --bench raster -- triangles     # writes target/criterion/
//! cargo run --release --example raster_plot -- docs/rasterizers.png
//! ```
//!
//! Reads `target/criterion/triangles/{RASTERIZER}/{SIZE}/new/estimates.json`
//! (the mean of the last run) for every rasterizer and size of
//! `examples/common/scenes/` and draws with embedded-graphics into a frame in memory.

mod common;

use common::scenes::TRIANGLE_SIZES;
use common::write_png;
use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Circle, Line, PrimitiveStyle, Rectangle};
use embedded_graphics::text::{Alignment, Text};
use std::path::{Path, PathBuf};

const W: u32 = 560;
const H: u32 = 360;
/// The plot area inside the frame.
const LEFT: i32 = 70;
const RIGHT: i32 = 400;
const TOP: i32 = 30;
const BOTTOM: i32 = 310;

const SERIES: [(&str, Rgb888); 3] = [
    ("scanline", Rgb888::new(30, 110, 220)),
    ("hilbert", Rgb888::new(220, 70, 40)),
    ("auto", Rgb888::new(40, 160, 70)),
];

/// A frame in memory.
struct Canvas {
    pixels: Vec<Rgb888>,
}

impl OriginDimensions for Canvas {
    fn size(&self) -> Size {
        Size::new(W, H)
    }
}

impl DrawTarget for Canvas {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if p.x >= 0 && p.y >= 0 && (p.x as u32) < W && (p.y as u32) < H {
                self.pixels[(p.y as u32 * W + p.x as u32) as usize] = c;
            }
        }
        Ok(())
    }
}

/// The mean, in nanoseconds, of a criterion `estimates.json`.
fn mean_ns(path: &Path) -> Result<f64, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rest = text
        .split_once("\"mean\"")
        .and_then(|(_, r)| r.split_once("\"point_estimate\":"))
        .map(|(_, r)| r)
        .ok_or_else(|| format!("{}: no mean point estimate", path.display()))?;
    let end = rest
        .find(|c: char| {
            !(c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+')
        })
        .unwrap_or(rest.len());
    rest[..end]
        .parse()
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("docs/rasterizers.png"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/criterion/triangles");
    // ns per triangle, per rasterizer and size.
    let mut data = vec![vec![0.0f64; TRIANGLE_SIZES.len()]; SERIES.len()];
    for (s, (name, _)) in SERIES.iter().enumerate() {
        for (k, (size, _, count)) in TRIANGLE_SIZES.iter().enumerate() {
            let path = root.join(name).join(size).join("new/estimates.json");
            match mean_ns(&path) {
                Ok(ns) => data[s][k] = ns / *count as f64,
                Err(e) => {
                    eprintln!(
                        "raster_plot: {e} (run `cargo bench --bench raster -- triangles` first)"
                    );
                    std::process::exit(1);
                }
            }
        }
    }

    println!("| triangle | scanline | hilbert | auto | hilbert / scanline |");
    println!("|---|---|---|---|---|");
    for (k, (size, _, _)) in TRIANGLE_SIZES.iter().enumerate() {
        println!(
            "| {size} | {:.0} ns | {:.0} ns | {:.0} ns | {:.2} |",
            data[0][k],
            data[1][k],
            data[2][k],
            data[1][k] / data[0][k]
        );
    }

    let mut c = Canvas {
        pixels: vec![Rgb888::WHITE; (W * H) as usize],
    };
    let grey = PrimitiveStyle::with_stroke(Rgb888::new(200, 200, 200), 1);
    let black = PrimitiveStyle::with_stroke(Rgb888::BLACK, 1);
    let text = MonoTextStyle::new(&FONT_6X10, Rgb888::BLACK);
    // Log-log axes: x the triangle's pixels, y nanoseconds per triangle,
    // both over whole decades around the data.
    let x_lo = 0.0f64; // 1 px
    let x_hi = 4.0f64; // 10,000 px
    let all = data.iter().flatten().copied();
    let y_lo = all.clone().fold(f64::MAX, f64::min).log10().floor();
    let y_hi = all.fold(0.0, f64::max).log10().ceil();
    let px = |pixels: f64| {
        LEFT + ((pixels.log10() - x_lo) / (x_hi - x_lo) * (RIGHT - LEFT) as f64) as i32
    };
    let py =
        |ns: f64| BOTTOM - ((ns.log10() - y_lo) / (y_hi - y_lo) * (BOTTOM - TOP) as f64) as i32;
    for d in 0..=(x_hi - x_lo) as i32 {
        let x = px(10f64.powi(d));
        let _ = Line::new(Point::new(x, TOP), Point::new(x, BOTTOM))
            .into_styled(grey)
            .draw(&mut c);
        let label = format!("{}", 10u32.pow(d as u32));
        let _ = Text::with_alignment(&label, Point::new(x, BOTTOM + 14), text, Alignment::Center)
            .draw(&mut c);
    }
    for d in y_lo as i32..=y_hi as i32 {
        let y = py(10f64.powi(d));
        let _ = Line::new(Point::new(LEFT, y), Point::new(RIGHT, y))
            .into_styled(grey)
            .draw(&mut c);
        let label = if d >= 3 {
            format!("{} us", 10u32.pow(d as u32 - 3))
        } else {
            format!("{} ns", 10u32.pow(d.max(0) as u32))
        };
        let _ = Text::with_alignment(&label, Point::new(LEFT - 6, y + 3), text, Alignment::Right)
            .draw(&mut c);
    }
    let _ = Rectangle::with_corners(Point::new(LEFT, TOP), Point::new(RIGHT, BOTTOM))
        .into_styled(black)
        .draw(&mut c);
    let _ = Text::with_alignment(
        "pixels per triangle",
        Point::new((LEFT + RIGHT) / 2, BOTTOM + 32),
        text,
        Alignment::Center,
    )
    .draw(&mut c);
    let _ = Text::new(
        "time per triangle, whole frame (x86-64, criterion mean)",
        Point::new(LEFT, TOP - 12),
        text,
    )
    .draw(&mut c);
    for (s, (name, colour)) in SERIES.iter().enumerate() {
        let stroke = PrimitiveStyle::with_stroke(*colour, 2);
        let points: Vec<Point> = TRIANGLE_SIZES
            .iter()
            .enumerate()
            .map(|(k, (_, area, _))| Point::new(px(*area as f64), py(data[s][k])))
            .collect();
        for w in points.windows(2) {
            let _ = Line::new(w[0], w[1]).into_styled(stroke).draw(&mut c);
        }
        for p in &points {
            let _ = Circle::with_center(*p, 7)
                .into_styled(PrimitiveStyle::with_fill(*colour))
                .draw(&mut c);
        }
        let ly = TOP + 20 + 18 * s as i32;
        let _ = Line::new(Point::new(RIGHT + 20, ly), Point::new(RIGHT + 44, ly))
            .into_styled(stroke)
            .draw(&mut c);
        let _ = Text::new(name, Point::new(RIGHT + 52, ly + 3), text).draw(&mut c);
    }

    if let Err(e) = write_png(&out, Size::new(W, H), &c.pixels) {
        eprintln!("raster_plot: {e}");
        std::process::exit(1);
    }
    eprintln!("raster_plot: wrote {}", out.display());
}
