//! `microraster-import`: converts OBJ models and PNG images to Rust source.
//!
//! ```text
//! microraster-import obj MODEL.obj --out model.rs [--name NAME] [--fit auto|keep|unit] [--u32] [--no-normals] [--clusters N] [--max-face-corners N] [--allow-outside-files]
//! microraster-import png IMAGE.png --out tex.rs [--name NAME] --format rgb565|gray8|indexed8|indexed4
//! ```
//!
//! `--clusters N` splits each group into spatial clusters of at most `N`
//! triangles (N >= 1) and also writes `NAME_CLUSTERS` and
//! `NAME_GROUP_CLUSTERS`, for microraster's per-cluster frustum culling
//! (`Mesh::with_clusters`); that output needs a crate that depends on
//! microraster.
//!
//! `--max-face-corners N` (N >= 3, default 256) accepts faces of up to `N`
//! corners; a face of more is an error. Faces above 256 corners are
//! triangulated as a fan around their first corner, not ear-clipped.
//!
//! `--allow-outside-files` lets the model name material libraries and
//! textures outside its folder (by `..` or an absolute path), which are
//! otherwise refused with a warning.
//!
//! Prints a one-line summary on success (and any warnings on stderr); on
//! failure, one `error:` line on stderr and exit status 1 (2 for a usage
//! error).

#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use microraster_import::{
    obj_to_rust, png_to_rust, sanitize_name, Fit, IndexWidth, ObjOptions, TextureFormat,
};

const USAGE: &str = "\
usage: microraster-import obj MODEL.obj --out FILE.rs [--name NAME] [--fit auto|keep|unit] [--u32] [--no-normals] [--clusters N] [--max-face-corners N] [--allow-outside-files]
       microraster-import png IMAGE.png --out FILE.rs [--name NAME] --format rgb565|gray8|indexed8|indexed4";

/// A parsed command line.
#[derive(Debug, PartialEq)]
enum Command {
    Help,
    Obj {
        input: PathBuf,
        out: PathBuf,
        name: String,
        options: ObjOptions,
    },
    Png {
        input: PathBuf,
        out: PathBuf,
        name: String,
        format: TextureFormat,
    },
}

/// The name from `--name`, or else from the input's file stem.
fn default_name(input: &Path) -> String {
    sanitize_name(
        &input
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    )
}

fn parse_args(args: &[String]) -> Result<Command, String> {
    let Some(kind) = args.first() else {
        return Err("missing command (obj or png)".to_string());
    };
    if matches!(kind.as_str(), "-h" | "--help" | "help") {
        return Ok(Command::Help);
    }
    if kind != "obj" && kind != "png" {
        return Err(format!("unknown command `{kind}` (expected obj or png)"));
    }
    let mut input = None;
    let mut out = None;
    let mut name = None;
    let mut fit = None;
    let mut u32_indices = false;
    let mut no_normals = false;
    let mut clusters = 0;
    let mut max_face_corners = None;
    let mut outside_files = false;
    let mut format = None;
    let mut rest = args[1..].iter();
    while let Some(arg) = rest.next() {
        let mut value = |flag: &str| {
            rest.next()
                .cloned()
                .ok_or_else(|| format!("{flag} needs a value"))
        };
        match arg.as_str() {
            "-h" | "--help" => return Ok(Command::Help),
            "--out" | "-o" => out = Some(PathBuf::from(value("--out")?)),
            "--name" => name = Some(value("--name")?),
            "--fit" if kind == "obj" => {
                let v = value("--fit")?;
                fit =
                    Some(Fit::from_name(&v).ok_or_else(|| {
                        format!("unknown fit `{v}` (expected auto, keep or unit)")
                    })?);
            }
            "--u32" if kind == "obj" => u32_indices = true,
            "--allow-outside-files" if kind == "obj" => outside_files = true,
            "--no-normals" if kind == "obj" => no_normals = true,
            "--clusters" if kind == "obj" => {
                let v = value("--clusters")?;
                clusters = v.parse::<usize>().ok().filter(|&n| n > 0).ok_or_else(|| {
                    format!("bad cluster size `{v}` (expected the most triangles per cluster, at least 1)")
                })?;
            }
            "--max-face-corners" if kind == "obj" => {
                let v = value("--max-face-corners")?;
                let n = v.parse::<usize>().ok().filter(|&n| n >= 3).ok_or_else(|| {
                    format!(
                        "bad corner limit `{v}` (expected the most corners per face, at least 3)"
                    )
                })?;
                max_face_corners = Some(n);
            }
            "--format" if kind == "png" => {
                let v = value("--format")?;
                format = Some(TextureFormat::from_name(&v).ok_or_else(|| {
                    format!("unknown format `{v}` (expected rgb565, gray8, indexed8 or indexed4)")
                })?);
            }
            flag if flag.starts_with('-') && flag.len() > 1 => {
                return Err(format!("unknown option `{flag}` for `{kind}`"))
            }
            path => {
                if input.is_some() {
                    return Err(format!("unexpected argument `{path}`"));
                }
                input = Some(PathBuf::from(path));
            }
        }
    }
    let input = input.ok_or_else(|| format!("missing the input file for `{kind}`"))?;
    let out = out.ok_or_else(|| "missing --out FILE.rs".to_string())?;
    let name = name.unwrap_or_else(|| default_name(&input));
    if kind == "obj" {
        let mut options = ObjOptions::default();
        if let Some(n) = max_face_corners {
            options = options.with_max_face_corners(n);
        }
        let options = options
            .with_fit(fit.unwrap_or_default())
            .with_index_width(if u32_indices {
                IndexWidth::U32
            } else {
                IndexWidth::U16
            })
            .with_compute_normals(!no_normals)
            .with_cluster_triangles(clusters)
            .with_outside_files(outside_files);
        Ok(Command::Obj {
            input,
            out,
            name,
            options,
        })
    } else {
        let format =
            format.ok_or_else(|| "missing --format rgb565|gray8|indexed8|indexed4".to_string())?;
        Ok(Command::Png {
            input,
            out,
            name,
            format,
        })
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let command = match parse_args(&args) {
        Ok(c) => c,
        Err(message) => {
            eprintln!("error: {message}");
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    let result = match command {
        Command::Help => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Command::Obj {
            input,
            out,
            name,
            options,
        } => obj_to_rust(&input, &out, &name, &options).map(|summary| {
            for w in &summary.warnings {
                eprintln!("warning: {w}");
            }
            format!("{} -> {}: {summary}", input.display(), out.display())
        }),
        Command::Png {
            input,
            out,
            name,
            format,
        } => png_to_rust(&input, &out, &name, format)
            .map(|summary| format!("{} -> {}: {summary}", input.display(), out.display())),
    };
    match result {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn obj_command_with_every_option() {
        assert_eq!(
            parse_args(&args(
                "obj m/my-ship.obj --out o.rs --fit unit --u32 --no-normals --clusters 64 --max-face-corners 1000 --allow-outside-files"
            )),
            Ok(Command::Obj {
                input: "m/my-ship.obj".into(),
                out: "o.rs".into(),
                name: "my_ship".into(),
                options: ObjOptions::default()
                    .with_fit(Fit::Unit)
                    .with_index_width(IndexWidth::U32)
                    .with_compute_normals(false)
                    .with_cluster_triangles(64)
                    .with_max_face_corners(1000)
                    .with_outside_files(true),
            })
        );
        assert_eq!(
            parse_args(&args("obj a.obj --name Hull -o x.rs")),
            Ok(Command::Obj {
                input: "a.obj".into(),
                out: "x.rs".into(),
                name: "Hull".into(),
                options: ObjOptions::default(),
            })
        );
    }

    #[test]
    fn png_command() {
        assert_eq!(
            parse_args(&args("png t.png --format indexed4 --out t.rs")),
            Ok(Command::Png {
                input: "t.png".into(),
                out: "t.rs".into(),
                name: "t".into(),
                format: TextureFormat::Indexed4,
            })
        );
    }

    #[test]
    fn usage_errors() {
        let err = |s: &str| parse_args(&args(s)).unwrap_err();
        assert_eq!(err(""), "missing command (obj or png)");
        assert_eq!(
            err("stl a.stl"),
            "unknown command `stl` (expected obj or png)"
        );
        assert_eq!(err("obj a.obj"), "missing --out FILE.rs");
        assert_eq!(err("obj --out a.rs"), "missing the input file for `obj`");
        assert_eq!(
            err("obj a.obj b.obj --out a.rs"),
            "unexpected argument `b.obj`"
        );
        assert_eq!(
            err("obj a.obj --out a.rs --fit huge"),
            "unknown fit `huge` (expected auto, keep or unit)"
        );
        assert_eq!(err("obj a.obj --out"), "--out needs a value");
        for bad in ["0", "x", "-1", "1.5", ""] {
            assert_eq!(
                parse_args(&[
                    "obj".to_string(),
                    "a.obj".to_string(),
                    "--out".to_string(),
                    "a.rs".to_string(),
                    "--clusters".to_string(),
                    bad.to_string(),
                ])
                .unwrap_err(),
                format!(
                    "bad cluster size `{bad}` (expected the most triangles per cluster, at least 1)"
                )
            );
        }
        for bad in ["2", "x", "-4"] {
            assert_eq!(
                err(&format!("obj a.obj --out a.rs --max-face-corners {bad}")),
                format!(
                    "bad corner limit `{bad}` (expected the most corners per face, at least 3)"
                )
            );
        }
        assert_eq!(
            err("png a.png --out a.rs --format gray8 --max-face-corners 9"),
            "unknown option `--max-face-corners` for `png`"
        );
        assert_eq!(
            err("obj a.obj --out a.rs --clusters"),
            "--clusters needs a value"
        );
        assert_eq!(
            err("png a.png --out a.rs --format gray8 --clusters 4"),
            "unknown option `--clusters` for `png`"
        );
        assert_eq!(
            err("obj a.obj --out a.rs --format gray8"),
            "unknown option `--format` for `obj`"
        );
        assert_eq!(
            err("png a.png --out a.rs"),
            "missing --format rgb565|gray8|indexed8|indexed4"
        );
        assert_eq!(
            err("png a.png --out a.rs --format rgb888"),
            "unknown format `rgb888` (expected rgb565, gray8, indexed8 or indexed4)"
        );
        assert_eq!(parse_args(&args("--help")), Ok(Command::Help));
    }
}
