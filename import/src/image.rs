//! PNG images to texture data: Rgb565, 8-bit grey, or an Rgb565 palette
//! with 8-bit or 4-bit indices.
//!
//! Every PNG colour type and bit depth is read (grey, grey + alpha, RGB,
//! RGBA, palette; 1 to 16 bits per sample), through the `png` crate's
//! `EXPAND` normalisation, and kept at 16 bits per channel until the final
//! conversion so 16-bit images are rounded once. Transparency is ignored
//! (the colour channels are used as they are).

use std::collections::HashMap;
use std::fs;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use crate::error::{ErrorKind, ImportError};

/// The largest image accepted, in pixels (2048 x 2048).
pub const MAX_PIXELS: u64 = 1 << 22;

/// A decoded image: RGBA, 16 bits per channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Texture {
    /// The file it came from (for errors and output comments).
    pub source: PathBuf,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, row by row from the top, RGBA with 16 bits per channel
    /// (8-bit images are scaled by 257, so 255 becomes 65535).
    pub pixels: Vec<[u16; 4]>,
}

/// A texel layout for the generated source.
///
/// Texels are stored row by row from the top, left to right.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TextureFormat {
    /// One `u16` per pixel: red in bits 15-11, green 10-5, blue 4-0 (each
    /// channel rounded to nearest); the layout of embedded-graphics'
    /// `Rgb565` raw data.
    #[default]
    Rgb565,
    /// One `u8` luma per pixel: Rec. 601 weights
    /// `(299 R + 587 G + 114 B) / 1000`, rounded to nearest (halves up).
    Gray8,
    /// One `u8` palette index per pixel, with a palette of up to 256 Rgb565
    /// colours: the image's distinct colours (after conversion to Rgb565)
    /// in the order they first appear.
    Indexed8,
    /// Two pixels per byte, the first (left) pixel in the high nibble, with
    /// a palette of up to 16 Rgb565 colours as for
    /// [`Indexed8`](TextureFormat::Indexed8). Each row starts on a new byte:
    /// a row of odd width ends in a byte whose low nibble is 0, and the
    /// stride is `(width + 1) / 2` bytes.
    Indexed4,
}

impl TextureFormat {
    /// The lower-case name used on the command line: `rgb565`, `gray8`,
    /// `indexed8`, `indexed4`.
    pub fn name(self) -> &'static str {
        match self {
            TextureFormat::Rgb565 => "rgb565",
            TextureFormat::Gray8 => "gray8",
            TextureFormat::Indexed8 => "indexed8",
            TextureFormat::Indexed4 => "indexed4",
        }
    }

    /// The format of that [`name`](TextureFormat::name), if any.
    pub fn from_name(name: &str) -> Option<TextureFormat> {
        [
            TextureFormat::Rgb565,
            TextureFormat::Gray8,
            TextureFormat::Indexed8,
            TextureFormat::Indexed4,
        ]
        .into_iter()
        .find(|f| f.name() == name)
    }

    /// A one-line description of the layout.
    pub fn layout(self) -> &'static str {
        match self {
            TextureFormat::Rgb565 => "one u16 per pixel, red in bits 15-11, green 10-5, blue 4-0",
            TextureFormat::Gray8 => "one u8 luma per pixel (Rec. 601)",
            TextureFormat::Indexed8 => "one u8 palette index per pixel; palette of Rgb565 u16s",
            TextureFormat::Indexed4 => {
                "two 4-bit palette indices per byte, the left pixel in the high nibble, \
                 rows padded to whole bytes; palette of Rgb565 u16s"
            }
        }
    }

    /// The largest palette of an indexed format (0 for the others).
    pub fn palette_limit(self) -> usize {
        match self {
            TextureFormat::Indexed8 => 256,
            TextureFormat::Indexed4 => 16,
            _ => 0,
        }
    }
}

/// Texels of a [`TextureData`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Texels {
    /// [`TextureFormat::Rgb565`] texels.
    U16(Vec<u16>),
    /// [`TextureFormat::Gray8`] luma or indexed-format bytes.
    U8(Vec<u8>),
}

/// A texture converted to one [`TextureFormat`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureData {
    /// The file it came from.
    pub source: PathBuf,
    /// The format.
    pub format: TextureFormat,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The texels, laid out as [`format`](TextureData::format) says.
    pub texels: Texels,
    /// Rgb565 palette of the indexed formats (empty for the others).
    pub palette: Vec<u16>,
    /// Whether any pixel was not fully opaque (transparency is dropped).
    pub translucent: bool,
}

impl TextureData {
    /// Array elements per row of [`texels`](TextureData::texels).
    pub fn stride(&self) -> usize {
        match self.format {
            TextureFormat::Indexed4 => (self.width as usize).div_ceil(2),
            _ => self.width as usize,
        }
    }

    /// Size of the texels in bytes.
    pub fn texel_bytes(&self) -> usize {
        match &self.texels {
            Texels::U16(t) => t.len() * 2,
            Texels::U8(t) => t.len(),
        }
    }
}

/// A 16-bit channel value to `bits` bits, rounded to nearest.
fn channel(c: u16, bits: u32) -> u32 {
    let max = (1u32 << bits) - 1;
    // No ties: 2 * c * max is even and 65535 is odd.
    (c as u32 * max + 32767) / 65535
}

/// An RGB colour with 16 bits per channel as Rgb565, each channel rounded
/// to nearest (for 8-bit values `v`, pass `v * 257`).
///
/// ```
/// use microraster_import::rgb565;
/// assert_eq!(rgb565([65535, 65535, 65535]), 0xFFFF);
/// assert_eq!(rgb565([65535, 0, 0]), 0xF800);
/// // 8-bit 128 is 15.56 of 31 (rounds to 16) and 31.62 of 63 (to 32).
/// assert_eq!(rgb565([128 * 257, 128 * 257, 128 * 257]), (16 << 11) | (32 << 5) | 16);
/// ```
pub fn rgb565(rgb: [u16; 3]) -> u16 {
    ((channel(rgb[0], 5) << 11) | (channel(rgb[1], 6) << 5) | channel(rgb[2], 5)) as u16
}

/// Rec. 601 luma of an RGB colour with 16 bits per channel, as 8 bits:
/// `(299 R + 587 G + 114 B) / 1000`, rounded to nearest, halves up.
///
/// ```
/// use microraster_import::gray8;
/// assert_eq!(gray8([65535, 0, 0]), 76); // 0.299 * 255 = 76.245
/// assert_eq!(gray8([0, 65535, 0]), 150); // 149.685
/// assert_eq!(gray8([0, 0, 65535]), 29); // 29.07
/// ```
pub fn gray8(rgb: [u16; 3]) -> u8 {
    let weighted = 299 * rgb[0] as u64 + 587 * rgb[1] as u64 + 114 * rgb[2] as u64;
    let den = 1000 * 65535u64;
    ((weighted * 255 + den / 2) / den) as u8
}

/// Reads and decodes the PNG file at `path`.
pub fn load_png(path: &Path) -> Result<Texture, ImportError> {
    let bytes = fs::read(path).map_err(|e| ImportError::io(path, e))?;
    decode_png(&bytes, path)
}

/// Decodes PNG data held in memory; `path` names it in errors.
///
/// Truncated or malformed data, an image with no pixels or more than
/// [`MAX_PIXELS`] is an error, never a panic.
pub fn decode_png(bytes: &[u8], path: &Path) -> Result<Texture, ImportError> {
    let fail = |message: String| ImportError::new(path, None, ErrorKind::Png { message });
    let mut decoder = png::Decoder::new_with_limits(
        Cursor::new(bytes),
        png::Limits {
            bytes: 64 << 20, // 2048 * 2048 RGBA at 16 bits is 32 MiB.
        },
    );
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| fail(e.to_string()))?;
    let (width, height) = (reader.info().width, reader.info().height);
    if width == 0 || height == 0 || width as u64 * height as u64 > MAX_PIXELS {
        return Err(ImportError::new(
            path,
            None,
            ErrorKind::ImageSize { width, height },
        ));
    }
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| fail(e.to_string()))?;
    let samples = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err(fail("palette was not expanded".to_string())),
    };
    let wide = match info.bit_depth {
        png::BitDepth::Eight => false,
        png::BitDepth::Sixteen => true,
        other => {
            return Err(fail(format!(
                "unexpected bit depth {other:?} after expansion"
            )))
        }
    };
    let (width, height) = (info.width, info.height);
    let count = width as usize * height as usize;
    let bytes_per_pixel = samples * if wide { 2 } else { 1 };
    let row = width as usize * bytes_per_pixel;
    if width == 0
        || height == 0
        || info.line_size < row
        || buf.len() < info.line_size * height as usize
    {
        return Err(fail("frame does not match the image size".to_string()));
    }
    let mut pixels = Vec::with_capacity(count);
    for line in buf.chunks(info.line_size).take(height as usize) {
        for px in line[..row].chunks_exact(bytes_per_pixel) {
            let sample = |i: usize| -> u16 {
                if wide {
                    u16::from_be_bytes([px[2 * i], px[2 * i + 1]])
                } else {
                    px[i] as u16 * 257
                }
            };
            pixels.push(match samples {
                1 => [sample(0), sample(0), sample(0), 65535],
                2 => [sample(0), sample(0), sample(0), sample(1)],
                3 => [sample(0), sample(1), sample(2), 65535],
                _ => [sample(0), sample(1), sample(2), sample(3)],
            });
        }
    }
    Ok(Texture {
        source: path.to_path_buf(),
        width,
        height,
        pixels,
    })
}

impl Texture {
    /// The pixels as Rgb565 (see [`rgb565`]).
    pub fn to_rgb565(&self) -> Vec<u16> {
        self.pixels
            .iter()
            .map(|&[r, g, b, _]| rgb565([r, g, b]))
            .collect()
    }

    /// The pixels as 8-bit luma (see [`gray8`]).
    pub fn to_gray8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .map(|&[r, g, b, _]| gray8([r, g, b]))
            .collect()
    }

    /// Whether any pixel is not fully opaque.
    pub fn is_translucent(&self) -> bool {
        self.pixels.iter().any(|p| p[3] != 65535)
    }

    /// The image converted to `format`.
    ///
    /// For the indexed formats, an image with more distinct colours (as
    /// Rgb565) than the palette holds is an error
    /// ([`ErrorKind::TooManyColors`]) saying how many it has; there is no
    /// quantisation.
    pub fn convert(&self, format: TextureFormat) -> Result<TextureData, ImportError> {
        let (texels, palette) = match format {
            TextureFormat::Rgb565 => (Texels::U16(self.to_rgb565()), Vec::new()),
            TextureFormat::Gray8 => (Texels::U8(self.to_gray8()), Vec::new()),
            TextureFormat::Indexed8 | TextureFormat::Indexed4 => {
                let limit = format.palette_limit();
                let colors = self.to_rgb565();
                let mut palette: Vec<u16> = Vec::new();
                let mut index: HashMap<u16, u8> = HashMap::new();
                let mut indices = Vec::with_capacity(colors.len());
                for &c in &colors {
                    let i = *index.entry(c).or_insert_with(|| {
                        palette.push(c);
                        // Saturates past 256 colours, which is an error below.
                        u8::try_from(palette.len() - 1).unwrap_or(u8::MAX)
                    });
                    indices.push(i);
                }
                if palette.len() > limit {
                    return Err(ImportError::new(
                        &self.source,
                        None,
                        ErrorKind::TooManyColors {
                            count: palette.len(),
                            limit,
                        },
                    ));
                }
                let texels = if format == TextureFormat::Indexed4 {
                    let w = (self.width as usize).max(1);
                    indices
                        .chunks(w)
                        .flat_map(|row| {
                            row.chunks(2)
                                .map(|pair| (pair[0] << 4) | pair.get(1).copied().unwrap_or(0))
                        })
                        .collect()
                } else {
                    indices
                };
                (Texels::U8(texels), palette)
            }
        };
        Ok(TextureData {
            source: self.source.clone(),
            format,
            width: self.width,
            height: self.height,
            texels,
            palette,
            translucent: self.is_translucent(),
        })
    }
}
