//! Frames into PNG files for the host examples, through the library's
//! [`FrameBuffer`] sink: one call renders a scene into a file.

use embedded_graphics::pixelcolor::{PixelColor, Rgb888, RgbColor};
use microraster::prelude::*;
use std::path::Path;

/// Renders `scene` into a frame of the renderer's size and writes it to
/// `path` as an 8-bit RGB PNG (creating its directory): the frame's
/// statistics, or a one-line error naming what failed.
pub fn render_png<
    C,
    S,
    const TW: usize,
    const TH: usize,
    const V: usize,
    const B: usize,
    const T: usize,
>(
    renderer: &mut Renderer<C, TW, TH>,
    workspace: &mut Workspace<V, B, T>,
    scene: &Scene<'_, S>,
    path: &Path,
) -> Result<FrameStats, String>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + 'static,
    S: ShaderSet<C>,
{
    let config = renderer.config();
    let (size, clear) = (config.size, config.clear_color);
    let mut pixels = vec![clear; (size.width * size.height) as usize];
    let mut frame = FrameBuffer::new(&mut pixels, size).map_err(|e| e.to_string())?;
    let stats = renderer
        .render(workspace, scene, &mut frame)
        .map_err(|e| e.to_string())?;
    write_png(path, size, &pixels)?;
    Ok(stats)
}

/// Writes `pixels` (row-major, `size`) to `path` as an 8-bit RGB PNG,
/// creating its directory.
pub fn write_png<C: PixelColor + Into<Rgb888>>(
    path: &Path,
    size: Size,
    pixels: &[C],
) -> Result<(), String> {
    let fail = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", path.display());
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
    }
    let file = std::fs::File::create(path).map_err(|e| fail(&e))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), size.width, size.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // The pictures go into docs/ and the repository: small files over
    // fast writes.
    encoder.set_compression(png::Compression::Best);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let rgb: Vec<u8> = pixels
        .iter()
        .flat_map(|&c| {
            let c: Rgb888 = c.into();
            [c.r(), c.g(), c.b()]
        })
        .collect();
    let mut writer = encoder.write_header().map_err(|e| fail(&e))?;
    writer.write_image_data(&rgb).map_err(|e| fail(&e))?;
    writer.finish().map_err(|e| fail(&e))
}
