//! Test support: a capturing draw target and PNG golden-image comparison.
#![allow(dead_code)]

pub mod dma;
pub mod host;
pub mod pico;

use embedded_graphics::pixelcolor::{PixelColor, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use std::path::{Path, PathBuf};

/// A frame in memory that records what the renderer sends, and how often
/// each pixel was written.
pub struct Capture<C> {
    pub size: Size,
    pub pixels: Vec<C>,
    pub writes: Vec<u32>,
    pub fills: u32,
}

impl<C: PixelColor> Capture<C> {
    pub fn new(size: Size, background: C) -> Self {
        let n = (size.width * size.height) as usize;
        Self {
            size,
            pixels: vec![background; n],
            writes: vec![0; n],
            fills: 0,
        }
    }

    pub fn get(&self, x: u32, y: u32) -> C {
        self.pixels[(y * self.size.width + x) as usize]
    }

    /// Asserts that every pixel was written exactly once, and that the
    /// frame equals `expected` (which may have been drawn any way).
    pub fn assert_once_and_equal(&self, expected: &Capture<C>) {
        assert!(self.writes.iter().all(|&w| w == 1), "every pixel once");
        let diff = self
            .pixels
            .iter()
            .zip(&expected.pixels)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(diff, 0, "pixels differ");
    }

    pub fn to_rgb(&self) -> Vec<Rgb888>
    where
        C: Into<Rgb888>,
    {
        self.pixels.iter().map(|&c| c.into()).collect()
    }
}

impl<C: PixelColor> OriginDimensions for Capture<C> {
    fn size(&self) -> Size {
        self.size
    }
}

impl<C: PixelColor> DrawTarget for Capture<C> {
    type Color = C;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            assert!(
                p.x >= 0
                    && p.y >= 0
                    && (p.x as u32) < self.size.width
                    && (p.y as u32) < self.size.height,
                "pixel {p:?} outside the frame"
            );
            let i = (p.y as u32 * self.size.width + p.x as u32) as usize;
            self.pixels[i] = c;
            self.writes[i] += 1;
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = C>>(
        &mut self,
        area: &embedded_graphics::primitives::Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        self.fills += 1;
        let mut it = colors.into_iter();
        for y in 0..area.size.height as i32 {
            for x in 0..area.size.width as i32 {
                let c = it.next().expect("fill_contiguous got too few pixels");
                self.draw_iter([Pixel(area.top_left + Point::new(x, y), c)])?;
            }
        }
        assert!(it.next().is_none(), "fill_contiguous got too many pixels");
        Ok(())
    }
}

/// Asserts that two renders of one scene agree: no pixel differs, and
/// neither does what the frame statistics count of triangles and pixels,
/// nor (with `same_tiles`) the number of tiles. The binning passes may
/// differ (they depend on the pool and the visiting order).
pub fn assert_same_frame<C: PixelColor>(
    name: &str,
    (img, stats): &(Vec<C>, microraster::FrameStats),
    (ref_img, ref_stats): &(Vec<C>, microraster::FrameStats),
    same_tiles: bool,
) {
    let diff = img.iter().zip(ref_img).filter(|(a, b)| a != b).count();
    assert_eq!(diff, 0, "{name}: {diff} pixels differ");
    let key = |s: &microraster::FrameStats| {
        (
            s.triangles_in,
            s.culled,
            s.rejected,
            s.clipped,
            s.drawn,
            s.pixels_shaded,
            if same_tiles { s.tiles } else { 0 },
        )
    };
    assert_eq!(key(stats), key(ref_stats), "{name}: {stats:?}");
}

/// A sink that keeps the order of the tiles it receives, and the frame
/// they make.
pub struct Order<C>(
    pub Vec<embedded_graphics::primitives::Rectangle>,
    pub Capture<C>,
);

impl<C: PixelColor> Order<C> {
    pub fn new(size: Size, background: C) -> Self {
        Self(Vec::new(), Capture::new(size, background))
    }
}

impl<C: PixelColor> microraster::TileSink<C> for Order<C> {
    type Error = core::convert::Infallible;
    fn write_tile(
        &mut self,
        area: &embedded_graphics::primitives::Rectangle,
        tile: &microraster::TileView<'_, C>,
    ) -> Result<(), Self::Error> {
        self.0.push(*area);
        self.1.write_tile(area, tile)
    }
}

pub fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("golden")
}

pub fn write_png(path: &Path, size: Size, px: &[Rgb888]) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), size.width, size.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().unwrap();
    let data: Vec<u8> = px.iter().flat_map(|c| [c.r(), c.g(), c.b()]).collect();
    w.write_image_data(&data).unwrap();
}

pub fn read_png(path: &Path) -> Option<(Size, Vec<Rgb888>)> {
    let file = std::fs::File::open(path).ok()?;
    let dec = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = dec.read_info().ok()?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).ok()?;
    assert_eq!(
        info.color_type,
        png::ColorType::Rgb,
        "{} is not RGB",
        path.display()
    );
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let px = buf[..info.buffer_size()]
        .chunks(3)
        .map(|c| Rgb888::new(c[0], c[1], c[2]))
        .collect();
    Some((Size::new(info.width, info.height), px))
}

/// Compares `px` with `tests/golden/<name>.png` pixel for pixel. With
/// `BLESS=1` the golden file is (re)written instead. On a mismatch the
/// actual image and a diff (mismatches in magenta over a dimmed copy) are
/// written to `target/golden-diff/`.
pub fn check_golden(name: &str, size: Size, px: &[Rgb888]) {
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var_os("BLESS").is_some_and(|v| v == "1") {
        write_png(&path, size, px);
        return;
    }
    let (gsize, gpx) = read_png(&path).unwrap_or_else(|| {
        panic!(
            "missing golden image {}; run with BLESS=1 to create it",
            path.display()
        )
    });
    assert_eq!(gsize, size, "{name}: golden image size differs");
    let mismatches = px.iter().zip(&gpx).filter(|(a, b)| a != b).count();
    if mismatches != 0 {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("target")
            .join("golden-diff");
        write_png(&dir.join(format!("{name}.actual.png")), size, px);
        let diff: Vec<Rgb888> = px
            .iter()
            .zip(&gpx)
            .map(|(a, b)| {
                if a == b {
                    Rgb888::new(a.r() / 3, a.g() / 3, a.b() / 3)
                } else {
                    Rgb888::new(255, 0, 255)
                }
            })
            .collect();
        write_png(&dir.join(format!("{name}.diff.png")), size, &diff);
        panic!(
            "{name}: {mismatches} pixels differ from {}; see {}",
            path.display(),
            dir.display()
        );
    }
}
