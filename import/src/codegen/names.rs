//! The names of the generated items: the `SCREAMING_CASE` prefix made
//! from a name, and a valid name made from a file name.

use std::path::Path;

use crate::error::{ErrorKind, ImportError};

/// The `SCREAMING_CASE` prefix of the generated items for `name`.
///
/// `name` must be ASCII letters, digits and `_`, not starting with a digit;
/// camel case is split (`torusKnot` gives `TORUS_KNOT`) and everything is
/// upper-cased. Anything else is an error ([`ErrorKind::BadName`], reported
/// against `path`); [`sanitize_name`] makes a valid name from a file name.
///
/// ```
/// use std::path::Path;
/// use microraster_import::rust_prefix;
/// assert_eq!(rust_prefix("torusKnot", Path::new("k.obj")).unwrap(), "TORUS_KNOT");
/// assert_eq!(rust_prefix("cube_2", Path::new("c.obj")).unwrap(), "CUBE_2");
/// assert!(rust_prefix("2cube", Path::new("c.obj")).is_err());
/// assert!(rust_prefix("my-cube", Path::new("c.obj")).is_err());
/// ```
pub fn rust_prefix(name: &str, path: &Path) -> Result<String, ImportError> {
    let valid = name.chars().next().is_some_and(|c| !c.is_ascii_digit())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && name.chars().any(|c| c.is_ascii_alphanumeric());
    if !valid {
        return Err(ImportError::new(
            path,
            None,
            ErrorKind::BadName {
                name: name.to_string(),
            },
        ));
    }
    let mut out = String::with_capacity(name.len() + 4);
    let mut previous: Option<char> = None;
    for c in name.chars() {
        if c.is_ascii_uppercase()
            && previous.is_some_and(|p| p.is_ascii_lowercase() || p.is_ascii_digit())
        {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
        previous = Some(c);
    }
    Ok(out)
}

/// A valid name for [`rust_prefix`] made from any string, such as a file
/// stem: runs of other characters become one `_`, a leading digit gets a
/// `_` before it, and an empty result is `model`.
///
/// ```
/// use microraster_import::sanitize_name;
/// assert_eq!(sanitize_name("my cube-v2"), "my_cube_v2");
/// assert_eq!(sanitize_name("3d"), "_3d");
/// assert_eq!(sanitize_name("ü"), "model");
/// ```
pub fn sanitize_name(name: &str) -> String {
    let mut out = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c);
        } else if !out.is_empty() && !out.ends_with('_') {
            out.push('_');
        }
    }
    while out.ends_with('_') {
        out.pop();
    }
    if out.is_empty() {
        return "model".to_string();
    }
    if out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert(0, '_');
    }
    out
}
