//! Which files a model may name: material libraries (`mtllib`) and
//! textures (`map_Kd`) are resolved inside the OBJ file's folder.
//!
//! A model file is input like any other, and may come from elsewhere: with
//! `mtllib ../../../../etc/passwd` it could make the importer read any file
//! the build can read, and a texture name such as `/home/me/.ssh/id_rsa`
//! would reach the generated source, where a build script could read it.
//! So a name that leaves the model's folder, by `..` or by being absolute,
//! is refused (with a warning) unless
//! [`ObjOptions::outside_files`](crate::ObjOptions::outside_files) allows
//! it.
//!
//! The check is on the names as written, not on the file system: `..` that
//! stays inside (`sub/../a.mtl`) is fine, and a symbolic link inside the
//! folder is followed, since whoever made the folder put it there. `/` and
//! `\` both separate folders, whatever the host, because OBJ files are
//! written on every system.

/// The end of the warning for a refused name, after the name.
pub(crate) const REFUSED: &str = "is outside the model's folder; \
     allow it with ObjOptions::with_outside_files (--allow-outside-files)";

fn is_separator(c: char) -> bool {
    c == '/' || c == '\\'
}

/// Whether `name` is absolute: from a root (`/x`, `\x`, `\\server\x`) or a
/// drive (`C:x`, `C:\x`).
fn is_absolute(name: &str) -> bool {
    let mut chars = name.chars();
    match (chars.next(), chars.next()) {
        (Some(c), _) if is_separator(c) => true,
        (Some(drive), Some(':')) => drive.is_ascii_alphabetic(),
        _ => false,
    }
}

/// Whether the file `name`, written in a file that lies in `folder` (a
/// path relative to the model's folder, `""` for the model's own), lies
/// outside the model's folder: `name` is absolute, or its `..` parts climb
/// above the model's folder.
///
/// ```
/// use microraster_import::paths::leaves_folder;
/// assert!(!leaves_folder("", "ship.mtl"));
/// assert!(!leaves_folder("", "sub/../ship.mtl"));
/// assert!(leaves_folder("", "../../../../etc/passwd"));
/// assert!(leaves_folder("", "/etc/passwd"));
/// assert!(leaves_folder("", "C:\\ship.mtl"));
/// // A texture named in `mats/ship.mtl`:
/// assert!(!leaves_folder("mats", "../textures/hull.png"));
/// assert!(leaves_folder("mats", "../../hull.png"));
/// ```
pub fn leaves_folder(folder: &str, name: &str) -> bool {
    if is_absolute(name) {
        return true;
    }
    let mut depth = 0usize;
    for part in folder.split(is_separator).chain(name.split(is_separator)) {
        match part {
            "" | "." => {}
            ".." => match depth.checked_sub(1) {
                Some(d) => depth = d,
                None => return true,
            },
            _ => depth += 1,
        }
    }
    false
}

/// The folder part of a relative file name as written: everything before
/// its last separator, `""` for none.
pub(crate) fn folder_of(name: &str) -> &str {
    name.rfind(is_separator).map_or("", |i| &name[..i])
}
