//! The demo's command line (`examples/demo.rs`), apart from the program so
//! that tests/demo_args.rs can test it.
//!
//! The two things the demo does take separate output flags: the animation
//! writes its frames into a directory (`--out-dir`), an `--obj` model one
//! picture into a PNG file (`--out`). A flag that does not apply to what
//! is asked for is refused, never ignored, and every error names its flag.
//! Nothing is written outside the repository's `target/` by default.

use microraster::prelude::*;
use std::path::{Path, PathBuf};

/// The frame size unless `--size` says otherwise.
pub const WIDTH: u32 = 320;
/// The frame size unless `--size` says otherwise.
pub const HEIGHT: u32 = 240;

/// `--help`.
pub const USAGE: &str = "\
The microraster demo.

Usage:
  cargo run --release --example demo [-- OPTIONS]
      The lit, rotating torus knot and cube: PNG frames into --out-dir,
      with each frame's statistics.
  cargo run --release --example demo -- --obj MODEL.obj [OPTIONS]
      One picture of an OBJ model into the PNG file --out.

The animation:
  --frames N           frames to render, 1 or more (default 8)
  --out-dir DIR        where the frames go (default target/demo/)
A model:
  --obj FILE.obj       the model: recentred, scaled, framed and lit
  --out FILE.png       the picture (default target/demo/MODEL.png)
  --yaw DEG            turns the model about the vertical (default 30)
Both:
  --size WxH           frame size, each side 1 to 4096 (default 320x240)
  --shader NAME        flat, gouraud (default), textured, textured-lit,
                       depth, normals, wireframe or points
  --flat               --shader flat
  --texture FILE.png   the textured shaders' texture (default a checker)
  --perspective MODE   exact (default), quasi8, quasi16 or affine
  --raster NAME        scanline (default), hilbert or auto
  --hilbert            --raster hilbert (the same images)
  --hilbert-tiles      tiles visited along the Hilbert curve (the same images)
  -h, --help           this text

With `--features window` the animation shows in a window instead
(needs SDL2); --frames and --out-dir are then unused.
";

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

/// What the demo renders, with the flags that apply to it alone.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    /// The knot and the cube, turning.
    Animation {
        /// How many frames.
        frames: usize,
        /// Where they go (`frame_000.png`, ...).
        out_dir: PathBuf,
    },
    /// One picture of an OBJ model.
    Model {
        /// The OBJ file.
        obj: PathBuf,
        /// The PNG file.
        out: PathBuf,
        /// Degrees about the vertical, in `0..360`.
        yaw: f32,
    },
}

/// The parsed command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Args {
    pub mode: Mode,
    pub size: Size,
    pub look: Look,
    pub perspective: Perspective,
    pub raster: Rasterizer,
    pub tile_order: TileOrder,
    pub texture: Option<PathBuf>,
}

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Parsed {
    /// `--help`: print [`USAGE`].
    Help,
    /// Render.
    Run(Args),
}

/// The default output directory: `target/demo/` of the repository, wherever
/// the demo is run from.
pub fn default_out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join("demo")
}

/// Parses the demo's arguments (without the program's name). An error is
/// one line that starts with the flag at fault.
pub fn parse(argv: impl IntoIterator<Item = String>) -> Result<Parsed, String> {
    let mut args = Args {
        mode: Mode::Animation {
            frames: 8,
            out_dir: default_out_dir(),
        },
        size: Size::new(WIDTH, HEIGHT),
        look: Look::Gouraud,
        perspective: Perspective::Exact,
        raster: Rasterizer::Scanline,
        tile_order: TileOrder::RowMajor,
        texture: None,
    };
    let (mut frames, mut out_dir, mut obj, mut out, mut yaw) = (None, None, None, None, None);
    let mut it = argv.into_iter();
    while let Some(flag) = it.next() {
        // The flag's value, or an error saying what it needs.
        let mut value = |needs: &str| it.next().ok_or(format!("{flag} needs {needs}"));
        match flag.as_str() {
            "-h" | "--help" => return Ok(Parsed::Help),
            "--frames" => {
                let v = value("a number of frames")?;
                frames = Some(v.parse::<usize>().ok().filter(|&n| n > 0).ok_or(format!(
                    "--frames needs a number of frames, 1 or more, not {v:?}"
                ))?);
            }
            "--out-dir" => out_dir = Some(PathBuf::from(value("a directory")?)),
            "--out" => {
                let v = PathBuf::from(value("a PNG file")?);
                let png = v.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
                if !png {
                    return Err(format!(
                        "--out names the PNG file that --obj writes, ending in .png, not {:?}",
                        v.display().to_string()
                    ));
                }
                out = Some(v);
            }
            "--obj" => obj = Some(PathBuf::from(value("an OBJ file")?)),
            "--yaw" => {
                let v = value("an angle in degrees")?;
                let deg = v
                    .parse::<f32>()
                    .ok()
                    .filter(|d| d.is_finite())
                    .ok_or(format!("--yaw needs a finite angle in degrees, not {v:?}"))?;
                // A whole number of turns changes nothing; without them
                // the angle stays small enough for the rotation's 16.16
                // entries at any input.
                yaw = Some(deg.rem_euclid(360.0));
            }
            "--size" => {
                let v = value("WxH")?;
                let (w, h) = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
                    .filter(|&(w, h)| (1..=4096).contains(&w) && (1..=4096).contains(&h))
                    .ok_or(format!("--size needs WxH, each 1 to 4096, not {v:?}"))?;
                args.size = Size::new(w, h);
            }
            "--flat" => args.look = Look::Flat,
            "--shader" => {
                let names =
                    "flat, gouraud, textured, textured-lit, depth, normals, wireframe or points";
                let v = value(names)?;
                args.look = Look::parse(&v).ok_or(format!("--shader needs {names}, not {v:?}"))?;
            }
            "--texture" => args.texture = Some(PathBuf::from(value("a PNG file")?)),
            "--perspective" => {
                let names = "exact, quasi8, quasi16 or affine";
                let v = value(names)?;
                args.perspective = match v.as_str() {
                    "exact" => Perspective::Exact,
                    "quasi8" => Perspective::Quasi8,
                    "quasi16" => Perspective::Quasi16,
                    "affine" => Perspective::Affine,
                    _ => return Err(format!("--perspective needs {names}, not {v:?}")),
                }
            }
            "--hilbert" => args.raster = Rasterizer::Hilbert,
            "--raster" => {
                let names = "scanline, hilbert or auto";
                let v = value(names)?;
                args.raster = match v.as_str() {
                    "scanline" => Rasterizer::Scanline,
                    "hilbert" => Rasterizer::Hilbert,
                    "auto" => Rasterizer::Auto,
                    _ => return Err(format!("--raster needs {names}, not {v:?}")),
                }
            }
            "--hilbert-tiles" => args.tile_order = TileOrder::Hilbert,
            other => {
                return Err(format!(
                    "{other} is not an option of the demo (--help lists them)"
                ))
            }
        }
    }
    args.mode = match obj {
        Some(obj) => {
            if frames.is_some() {
                return Err("--frames is for the animation; --obj renders one picture".into());
            }
            if out_dir.is_some() {
                return Err(
                    "--out-dir is for the animation's frames; with --obj, --out names the PNG file"
                        .into(),
                );
            }
            let out = out.unwrap_or_else(|| {
                let stem = obj.file_stem().unwrap_or("model".as_ref());
                default_out_dir().join(format!("{}.png", stem.to_string_lossy()))
            });
            Mode::Model {
                obj,
                out,
                yaw: yaw.unwrap_or(30.0),
            }
        }
        None => {
            if out.is_some() {
                return Err(
                    "--out names the PNG file of an --obj model; the animation's frames go to --out-dir DIR"
                        .into(),
                );
            }
            if yaw.is_some() {
                return Err("--yaw turns an --obj model; the animation turns by itself".into());
            }
            Mode::Animation {
                frames: frames.unwrap_or(8),
                out_dir: out_dir.unwrap_or_else(default_out_dir),
            }
        }
    };
    Ok(Parsed::Run(args))
}
