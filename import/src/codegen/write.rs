//! Atomic file writes that leave an unchanged file alone.

use std::fs;
use std::io;
use std::path::Path;

use crate::error::ImportError;

/// Writes `contents` to `path` so that it is never seen partly written: into
/// a temporary file in the same directory, then renamed over `path`. If
/// `path` already holds exactly `contents`, it is left alone (so its
/// modification time does not trigger rebuilds); the result says whether
/// the file was written.
pub fn write_atomic(path: &Path, contents: &str) -> Result<bool, ImportError> {
    if fs::read(path).is_ok_and(|old| old == contents.as_bytes()) {
        return Ok(false);
    }
    let Some(name) = path.file_name() else {
        return Err(ImportError::io(
            path,
            io::Error::new(io::ErrorKind::InvalidInput, "not a file path"),
        ));
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = dir.join(tmp_name);
    let result = fs::write(&tmp, contents)
        .map_err(|e| ImportError::io(&tmp, e))
        .and_then(|()| fs::rename(&tmp, path).map_err(|e| ImportError::io(path, e)));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.map(|()| true)
}
