//! The one error type of the crate: which file, which line, and why.

use std::fmt;
use std::path::{Path, PathBuf};

/// An import failed.
///
/// Every error names the file it is about and, when the cause is on one
/// line of that file, the 1-based line number. [`Display`](fmt::Display)
/// writes it on one line, as `path:line: reason` (or `path: reason` when no
/// single line is to blame), the form compilers use, so editors can jump to
/// it. What it quotes of a file (a token, a name, a path that the file
/// gave) is shown with control characters escaped (`\u{0}`, `\t`, ...),
/// so that a NUL byte or a terminal escape sequence is seen rather than
/// hidden or obeyed; the [`ErrorKind`] keeps the text as written.
///
/// ```
/// use std::path::Path;
/// use microraster_import::{parse_obj, ErrorKind, ObjOptions};
///
/// let source = "v 0 0 0\nv 1 0 0\nf 1 2 3\n";
/// let err = parse_obj(source, Path::new("tri.obj"), |_| None, &ObjOptions::default())
///     .unwrap_err();
/// assert_eq!(err.line(), Some(3));
/// assert!(matches!(err.kind(), ErrorKind::IndexOutOfRange { index: 3, .. }));
/// assert_eq!(
///     err.to_string(),
///     "tri.obj:3: vertex index 3 is out of range (2 vertices are defined before this line)"
/// );
/// ```
#[derive(Debug)]
pub struct ImportError {
    path: PathBuf,
    line: Option<usize>,
    kind: ErrorKind,
}

/// Why an import failed (see [`ImportError`] for the file and line).
#[derive(Debug)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A file could not be read or written.
    Io(std::io::Error),
    /// A statement does not have the shape its keyword requires.
    Malformed {
        /// The statement's keyword (`v`, `f`, `Kd`, ...).
        statement: String,
        /// What is wrong, naming the offending token.
        message: String,
    },
    /// A number is NaN, infinite, or too large for an `f32`.
    NonFinite {
        /// The token as written.
        token: String,
    },
    /// A face refers to an element that does not exist (yet).
    IndexOutOfRange {
        /// `"vertex"`, `"texture coordinate"` or `"normal"`.
        element: &'static str,
        /// The index as written (1-based, or negative for relative).
        index: i64,
        /// How many such elements were defined before the face.
        defined: usize,
    },
    /// A face uses index 0, which OBJ does not have (indices start at 1).
    ZeroIndex {
        /// `"vertex"`, `"texture coordinate"` or `"normal"`.
        element: &'static str,
    },
    /// A face mixes corner forms, such as `1/1` and `2`.
    MixedFaceForms {
        /// The first corner as written.
        first: String,
        /// The first corner of a different form.
        other: String,
    },
    /// A face has more corners than [`ObjOptions::max_face_corners`](crate::ObjOptions::max_face_corners).
    TooManyCorners {
        /// Corners in the face.
        count: usize,
        /// The configured limit.
        limit: usize,
    },
    /// More `v`, `vt` or `vn` statements than
    /// [`ObjOptions::max_elements`](crate::ObjOptions::max_elements).
    TooManyElements {
        /// `"vertex"`, `"texture coordinate"` or `"normal"`.
        element: &'static str,
        /// The configured limit.
        limit: usize,
    },
    /// More triangles (after triangulation) than
    /// [`ObjOptions::max_triangles`](crate::ObjOptions::max_triangles).
    TooManyTriangles {
        /// The configured limit.
        limit: usize,
    },
    /// More vertices than the chosen index width can address.
    TooManyVertices {
        /// Unique (position, texture coordinate, normal) combinations, plus
        /// the copies that clustering made.
        count: usize,
        /// How many the index width addresses.
        limit: usize,
        /// How many of `count` are copies of vertices that several
        /// clusters share ([`ObjOptions::cluster_triangles`](crate::ObjOptions::cluster_triangles));
        /// 0 without clusters.
        duplicated: usize,
    },
    /// The file has no face that gives a triangle with an area.
    NoTriangles {
        /// Degenerate triangles that were dropped.
        degenerate: usize,
    },
    /// A coordinate cannot be held in 16.16 fixed point.
    OutOfFixedRange {
        /// What kind of value: `"position"` or `"texture"`.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// An output name is not usable as a Rust identifier prefix.
    BadName {
        /// The name given.
        name: String,
    },
    /// PNG data could not be decoded.
    Png {
        /// The decoder's message.
        message: String,
    },
    /// An image has no pixels, or more than the importer accepts.
    ImageSize {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An image has more distinct colours than an indexed format holds.
    TooManyColors {
        /// Distinct colours after conversion to Rgb565.
        count: usize,
        /// The palette size of the format (256 or 16).
        limit: usize,
    },
}

impl ImportError {
    /// An error about `path`, at `line` (1-based) if one line is to blame.
    pub fn new(path: impl Into<PathBuf>, line: Option<usize>, kind: ErrorKind) -> Self {
        Self {
            path: path.into(),
            line,
            kind,
        }
    }

    pub(crate) fn io(path: &Path, error: std::io::Error) -> Self {
        Self::new(path, None, ErrorKind::Io(error))
    }

    /// The file the error is about.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The 1-based line of [`path`](Self::path) at fault, if there is one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// Why the import failed.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The path can come from the file itself (an MTL named by `mtllib`).
        write!(f, "{}", escape_controls(&self.path.display().to_string()))?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": {}", self.kind)
    }
}

impl std::error::Error for ImportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Io(e) => Some(e),
            _ => None,
        }
    }
}

/// `s` fit to quote in a message: control characters, and the invisible
/// byte-order mark, become `\t`, `\n`, `\r` or `\u{..}` escapes. A NUL
/// byte in a number would otherwise vanish on a terminal (`0\u{0}5` shown
/// as `05`), and an escape sequence act on it. The escapes hold no control
/// characters, so escaping twice changes nothing.
pub(crate) fn escape_controls(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\t' | '\n' | '\r' => out.extend(c.escape_default()),
            c if c.is_control() || c == '\u{FEFF}' => out.extend(c.escape_unicode()),
            c => out.push(c),
        }
    }
    out
}

fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("{n} {one}")
    } else {
        format!("{n} {many}")
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "{e}"),
            Self::Malformed { statement, message } => {
                write!(
                    f,
                    "malformed `{}` statement: {}",
                    escape_controls(statement),
                    escape_controls(message)
                )
            }
            Self::NonFinite { token } => {
                write!(
                    f,
                    "number `{}` is not finite (NaN, infinite or beyond f32)",
                    escape_controls(token)
                )
            }
            Self::IndexOutOfRange {
                element,
                index,
                defined,
            } => {
                let (one, many) = match *element {
                    "vertex" => ("vertex is", "vertices are"),
                    "normal" => ("normal is", "normals are"),
                    _ => ("texture coordinate is", "texture coordinates are"),
                };
                write!(
                    f,
                    "{element} index {index} is out of range ({} defined before this line)",
                    plural(*defined, one, many)
                )
            }
            Self::ZeroIndex { element } => {
                write!(f, "{element} index 0 is invalid (OBJ indices start at 1)")
            }
            Self::MixedFaceForms { first, other } => write!(
                f,
                "face mixes corner forms `{}` and `{}` (all corners need the same v/vt/vn parts)",
                escape_controls(first),
                escape_controls(other)
            ),
            Self::TooManyCorners { count, limit } => {
                write!(
                    f,
                    "face has {count} corners, more than the limit of {limit}; \
                     raise it with ObjOptions::with_max_face_corners (--max-face-corners N)"
                )
            }
            Self::TooManyElements { element, limit } => {
                write!(f, "more than {limit} {element} statements (the configured limit)")
            }
            Self::TooManyTriangles { limit } => write!(
                f,
                "more than {limit} triangles after triangulation (the configured limit)"
            ),
            Self::TooManyVertices {
                count,
                limit,
                duplicated: 0,
            } => write!(
                f,
                "model has {count} unique vertices but u16 indices address only {limit}; \
                 use 32-bit indices (IndexWidth::U32, --u32) or split the model"
            ),
            Self::TooManyVertices {
                count,
                limit,
                duplicated,
            } => write!(
                f,
                "model has {count} vertices, {duplicated} of them copies that clustering made \
                 of vertices shared by clusters, but u16 indices address only {limit}; \
                 use 32-bit indices (IndexWidth::U32, --u32), larger clusters (--clusters) \
                 or split the model"
            ),
            Self::NoTriangles { degenerate } => write!(
                f,
                "no triangles to draw ({} dropped)",
                plural(*degenerate, "degenerate triangle", "degenerate triangles")
            ),
            Self::OutOfFixedRange { what, value } => {
                write!(
                    f,
                    "{what} coordinate {value} does not fit 16.16 fixed point (-32768 to 32767.99998)"
                )?;
                if *what == "position" {
                    write!(f, "; use Fit::Unit or Fit::Auto (--fit unit|auto)")?;
                }
                Ok(())
            }
            Self::BadName { name } => write!(
                f,
                "name `{}` is not an identifier (ASCII letters, digits and `_`, not starting with a digit)",
                name.escape_debug()
            ),
            Self::Png { message } => write!(f, "PNG: {}", escape_controls(message)),
            Self::ImageSize { width, height } => write!(
                f,
                "image is {width}x{height}; it needs at least one pixel and at most {} pixels",
                crate::image::MAX_PIXELS
            ),
            Self::TooManyColors { count, limit } => write!(
                f,
                "image has {count} distinct colours (as Rgb565), more than the {limit} of the palette; \
                 use --format rgb565 (TextureFormat::Rgb565)"
            ),
        }
    }
}
