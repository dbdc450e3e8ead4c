//! Material libraries: `mtllib` statements and the MTL files they name
//! (`newmtl`, `Kd`, `map_Kd`), read into the parser's materials, with the
//! names of files outside the model's folder refused (see
//! [`crate::paths`]).

use std::path::Path;

use super::lines::Lines;
use super::parser::{malformed, number, numbers, rest, Loader, Parser};
use crate::error::{escape_controls, ImportError};
use crate::obj::Material;
use crate::paths;

impl Parser<'_> {
    /// Whether the file `name`, written in a file in `folder` (relative to
    /// the OBJ's folder), may be used (see [`crate::paths`]).
    fn may_use(&self, folder: &str, name: &str) -> bool {
        self.options.outside_files || !paths::leaves_folder(folder, name)
    }

    pub(super) fn mtllib(
        &mut self,
        line: usize,
        args: &[&str],
        loader: &mut Loader<'_>,
    ) -> Result<(), ImportError> {
        if args.is_empty() {
            return Ok(());
        }
        // A file name with spaces, or several names.
        let whole = rest(args);
        let names: Vec<String> = if args.len() == 1 {
            vec![whole]
        } else {
            let found = if self.may_use("", &whole) {
                loader(&whole)?
            } else {
                None
            };
            match found {
                Some((path, text)) => return self.mtl(&path, &whole, &text),
                None => args.iter().map(|s| s.to_string()).collect(),
            }
        };
        for name in names {
            if !self.may_use("", &name) {
                self.warnings.push(format!(
                    "{}:{line}: material library `{}` {}; not read",
                    escape_controls(&self.path.display().to_string()),
                    escape_controls(&name),
                    paths::REFUSED
                ));
                continue;
            }
            match loader(&name)? {
                Some((path, text)) => self.mtl(&path, &name, &text)?,
                None => self.warnings.push(format!(
                    "material library `{}` not found; its materials are white",
                    escape_controls(&name)
                )),
            }
        }
        Ok(())
    }

    /// Reads the MTL text of the file `path`, named `name` in the OBJ.
    fn mtl(&mut self, path: &Path, name: &str, text: &str) -> Result<(), ImportError> {
        // Textures are named relative to the MTL file.
        let folder = paths::folder_of(name);
        if !self.files.iter().any(|f| f == path) {
            self.files.push(path.to_path_buf());
        }
        let mut current: Option<String> = None;
        for (line, statement) in Lines::new(text) {
            let tokens: Vec<&str> = statement.split_whitespace().collect();
            let Some((&keyword, args)) = tokens.split_first() else {
                continue;
            };
            let err = |kind| ImportError::new(path, Some(line), kind);
            match keyword {
                "newmtl" => {
                    let name = rest(args);
                    if name.is_empty() {
                        return Err(err(malformed(
                            "newmtl",
                            "expected a material name".to_string(),
                        )));
                    }
                    self.materials.insert(
                        name.clone(),
                        Material {
                            name: name.clone(),
                            diffuse: [1.0; 3],
                            texture: None,
                        },
                    );
                    current = Some(name);
                }
                "Kd" | "map_Kd" => {
                    let Some(material) = current.as_ref().and_then(|n| self.materials.get_mut(n))
                    else {
                        self.warnings.push(format!(
                            "{}:{line}: `{keyword}` before any `newmtl` ignored",
                            escape_controls(&path.display().to_string())
                        ));
                        continue;
                    };
                    if keyword == "map_Kd" {
                        let name = texture_name(args);
                        if name.is_empty() {
                            return Err(err(malformed(
                                "map_Kd",
                                "expected a file name".to_string(),
                            )));
                        }
                        // `self.may_use` would borrow all of `self`,
                        // `material` included.
                        if self.options.outside_files || !paths::leaves_folder(folder, &name) {
                            material.texture = Some(name);
                        } else {
                            self.warnings.push(format!(
                                "{}:{line}: texture `{}` {}; dropped",
                                escape_controls(&path.display().to_string()),
                                escape_controls(&name),
                                paths::REFUSED
                            ));
                        }
                    } else if matches!(args.first(), Some(&"spectral") | Some(&"xyz")) {
                        self.warnings.push(format!(
                            "{}:{line}: `Kd {}` is not supported; the colour stays white",
                            escape_controls(&path.display().to_string()),
                            args[0]
                        ));
                    } else {
                        material.diffuse = match args.len() {
                            1 => [number("Kd", args[0]).map_err(err)?; 3],
                            3 => numbers("Kd", args).map_err(err)?,
                            n => {
                                return Err(err(malformed(
                                    "Kd",
                                    format!("expected r g b; found {n} values"),
                                )))
                            }
                        };
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The file name of a `map_Kd` statement: the arguments after its options
/// (`-s 1 1 1`, `-clamp on`, `-mm 0 1`, ...). The last argument is always
/// part of the name.
fn texture_name(args: &[&str]) -> String {
    let Some(last) = args.len().checked_sub(1) else {
        return String::new();
    };
    let mut i = 0;
    while i < last && args[i].starts_with('-') {
        let option = args[i];
        i += 1;
        match option {
            // One to three numbers.
            "-o" | "-s" | "-t" => {
                let mut k = 0;
                while k < 3 && i < last && args[i].parse::<f32>().is_ok() {
                    i += 1;
                    k += 1;
                }
            }
            "-mm" => i = (i + 2).min(last),
            _ => i = (i + 1).min(last),
        }
    }
    rest(&args[i..])
}
