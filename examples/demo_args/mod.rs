//! The demo's command line (`examples/demo.rs`), apart from the program so
//! that tests/demo_args.rs can test it.

use microraster::prelude::*;
use std::path::PathBuf;

/// The animation's frame size.
pub const WIDTH: u32 = 320;
/// The animation's frame size.
pub const HEIGHT: u32 = 240;

/// What colours the draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    Flat,
    Gouraud,
    Textured,
    TexturedLit,
    Depth,
    Normals,
    Wireframe,
    Points,
}

impl Look {
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "flat" => Look::Flat,
            "gouraud" => Look::Gouraud,
            "textured" => Look::Textured,
            "textured-lit" => Look::TexturedLit,
            "depth" => Look::Depth,
            "normals" => Look::Normals,
            "wireframe" => Look::Wireframe,
            "points" => Look::Points,
            _ => return None,
        })
    }

    pub fn shading(self) -> Shading {
        match self {
            Look::Flat => Shading::Flat,
            Look::Gouraud => Shading::Gouraud,
            Look::Wireframe => Shading::Wireframe,
            Look::Points => Shading::Points(2),
            _ => Shading::Shader,
        }
    }

    pub fn textured(self) -> bool {
        matches!(self, Look::Textured | Look::TexturedLit)
    }
}

pub struct Args {
    pub frames: usize,
    pub out: Option<PathBuf>,
    pub look: Look,
    pub perspective: Perspective,
    pub raster: Rasterizer,
    pub tile_order: TileOrder,
    pub obj: Option<PathBuf>,
    pub size: Size,
    pub yaw: f32,
    pub texture: Option<PathBuf>,
}

/// Parses the demo's arguments (without the program's name).
pub fn parse(argv: impl IntoIterator<Item = String>) -> Result<Args, String> {
    let mut args = Args {
        frames: 8,
        out: None,
        look: Look::Gouraud,
        perspective: Perspective::Exact,
        raster: Rasterizer::Scanline,
        tile_order: TileOrder::RowMajor,
        obj: None,
        size: Size::new(WIDTH, HEIGHT),
        yaw: 30.0,
        texture: None,
    };
    let mut it = argv.into_iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--frames" => {
                args.frames = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .ok_or("--frames needs a number")?
            }
            "--out" => args.out = Some(it.next().ok_or("--out needs a path")?.into()),
            "--flat" => args.look = Look::Flat,
            "--shader" => {
                args.look = it.next().as_deref().and_then(Look::parse).ok_or(
                    "--shader needs flat, gouraud, textured, textured-lit, depth, normals, wireframe or points",
                )?
            }
            "--perspective" => {
                args.perspective = match it.next().as_deref() {
                    Some("exact") => Perspective::Exact,
                    Some("quasi8") => Perspective::Quasi8,
                    Some("quasi16") => Perspective::Quasi16,
                    Some("affine") => Perspective::Affine,
                    _ => return Err("--perspective needs exact, quasi8, quasi16 or affine".into()),
                }
            }
            "--hilbert" => args.raster = Rasterizer::Hilbert,
            "--raster" => {
                args.raster = match it.next().as_deref() {
                    Some("scanline") => Rasterizer::Scanline,
                    Some("hilbert") => Rasterizer::Hilbert,
                    Some("auto") => Rasterizer::Auto,
                    _ => return Err("--raster needs scanline, hilbert or auto".into()),
                }
            }
            "--hilbert-tiles" => args.tile_order = TileOrder::Hilbert,
            "--obj" => args.obj = Some(it.next().ok_or("--obj needs a file")?.into()),
            "--texture" => args.texture = Some(it.next().ok_or("--texture needs a PNG file")?.into()),
            "--yaw" => {
                args.yaw = it
                    .next()
                    .and_then(|v| v.parse::<f32>().ok())
                    .filter(|v| v.is_finite())
                    .ok_or("--yaw needs an angle in degrees")?
            }
            "--size" => {
                let v = it.next().ok_or("--size needs WxH")?;
                let (w, h) = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
                    .filter(|&(w, h)| (1..=4096).contains(&w) && (1..=4096).contains(&h))
                    .ok_or(format!("--size needs WxH, each 1 to 4096, not {v:?}"))?;
                args.size = Size::new(w, h);
            }
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    Ok(args)
}
