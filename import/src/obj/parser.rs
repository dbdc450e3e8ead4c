//! The parser of OBJ statements (`v`, `vt`, `vn`, `f`, `o`, `g`,
//! `usemtl`; `mtllib` is in [`super::mtl`]), which gathers the elements and
//! the faces' triangles group by group, and its helpers for numbers,
//! indices and messages.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use super::lines::Lines;
use super::vector::{cross, dot, sub};
use super::{to_fixed, triangulate, Material, Model, ObjOptions};
use crate::error::{ErrorKind, ImportError};

pub(super) type Loader<'a> = dyn FnMut(&str) -> Result<Option<(PathBuf, String)>, ImportError> + 'a;

/// Which of a corner's parts are present: (texture coordinate, normal).
type Form = (bool, bool);

pub(super) const NONE: u32 = u32::MAX;

/// A resolved face corner: 0-based (position, texture coordinate, normal),
/// [`NONE`] where absent.
pub(super) type Corner = [u32; 3];

pub(super) struct GroupBuild {
    pub(super) name: String,
    pub(super) material: Option<String>,
    pub(super) triangles: Vec<[Corner; 3]>,
}

pub(super) struct Parser<'p> {
    pub(super) path: &'p Path,
    pub(super) options: &'p ObjOptions,
    pub(super) positions: Vec<[f32; 3]>,
    /// Per position; empty until the first coloured `v`.
    pub(super) colors: Vec<Option<[f32; 3]>>,
    pub(super) texcoords: Vec<[f32; 2]>,
    pub(super) normals: Vec<[f32; 3]>,
    pub(super) groups: Vec<GroupBuild>,
    group_index: HashMap<(String, Option<String>), usize>,
    /// The index in `groups` of the current (group, material), once known.
    current: Option<usize>,
    group: String,
    material: Option<String>,
    pub(super) materials: HashMap<String, Material>,
    pub(super) triangle_count: usize,
    pub(super) degenerate: usize,
    pub(super) ignored: BTreeMap<String, usize>,
    pub(super) files: Vec<PathBuf>,
    pub(super) warnings: Vec<String>,
}

const MAX_IGNORED_KINDS: usize = 32;

pub(super) fn parse(
    source: &str,
    path: &Path,
    loader: &mut Loader<'_>,
    options: &ObjOptions,
) -> Result<Model, ImportError> {
    let mut p = Parser {
        path,
        options,
        positions: Vec::new(),
        colors: Vec::new(),
        texcoords: Vec::new(),
        normals: Vec::new(),
        groups: Vec::new(),
        group_index: HashMap::new(),
        current: None,
        group: "default".to_string(),
        material: None,
        materials: HashMap::new(),
        triangle_count: 0,
        degenerate: 0,
        ignored: BTreeMap::new(),
        files: vec![path.to_path_buf()],
        warnings: Vec::new(),
    };
    for (line, text) in Lines::new(source) {
        p.statement(line, &text, loader)?;
    }
    p.finish()
}

pub(super) fn malformed(statement: &str, message: String) -> ErrorKind {
    ErrorKind::Malformed {
        statement: statement.to_string(),
        message,
    }
}

/// At most 40 characters of `s`, for messages.
pub(super) fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(40).collect();
        t.push_str("...");
        t
    }
}

pub(super) fn number(statement: &str, token: &str) -> Result<f32, ErrorKind> {
    match token.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(ErrorKind::NonFinite { token: clip(token) }),
        Err(_) => Err(malformed(
            statement,
            format!("expected a number, found `{}`", clip(token)),
        )),
    }
}

pub(super) fn numbers<const N: usize>(
    statement: &str,
    tokens: &[&str],
) -> Result<[f32; N], ErrorKind> {
    let mut out = [0.0; N];
    for (o, t) in out.iter_mut().zip(tokens) {
        *o = number(statement, t)?;
    }
    Ok(out)
}

/// The rest of a statement after its keyword, whitespace runs collapsed.
pub(super) fn rest(tokens: &[&str]) -> String {
    tokens.join(" ")
}

fn resolve(index: i64, defined: usize, element: &'static str) -> Result<u32, ErrorKind> {
    let out_of_range = ErrorKind::IndexOutOfRange {
        element,
        index,
        defined,
    };
    let i = match index {
        0 => return Err(ErrorKind::ZeroIndex { element }),
        i if i > 0 => i as u64 - 1,
        i => match (defined as u64).checked_sub(i.unsigned_abs()) {
            Some(i) => i,
            None => return Err(out_of_range),
        },
    };
    if i < defined as u64 {
        // `defined` is bounded by `max_elements`, itself below u32::MAX.
        u32::try_from(i).map_err(|_| out_of_range)
    } else {
        Err(out_of_range)
    }
}

/// A corner's written indices: position, optional texture coordinate,
/// optional normal.
fn parse_corner(token: &str) -> Result<(i64, Option<i64>, Option<i64>), ErrorKind> {
    let bad = |what: &str| {
        malformed(
            "f",
            format!(
                "{what} in corner `{}` (expected v, v/vt, v//vn or v/vt/vn)",
                clip(token)
            ),
        )
    };
    let mut parts = token.split('/');
    let v = parts.next().unwrap_or("");
    let vt = parts.next().unwrap_or("");
    let vn = parts.next().unwrap_or("");
    if parts.next().is_some() {
        return Err(bad("too many `/`"));
    }
    let index = |s: &str| -> Result<Option<i64>, ErrorKind> {
        if s.is_empty() {
            Ok(None)
        } else {
            s.parse::<i64>()
                .map(Some)
                .map_err(|_| bad(&format!("bad index `{}`", clip(s))))
        }
    };
    let v = index(v)?.ok_or_else(|| bad("no vertex index"))?;
    Ok((v, index(vt)?, index(vn)?))
}

impl Parser<'_> {
    fn err(&self, line: usize, kind: ErrorKind) -> ImportError {
        ImportError::new(self.path, Some(line), kind)
    }

    fn statement(
        &mut self,
        line: usize,
        text: &str,
        loader: &mut Loader<'_>,
    ) -> Result<(), ImportError> {
        let mut tokens = text.split_whitespace();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        let args: Vec<&str> = tokens.collect();
        let result = match keyword {
            "v" => self.vertex(&args),
            "vt" => self.texcoord(&args),
            "vn" => self.normal(&args),
            "f" => self.face(&args),
            "o" | "g" => {
                self.current = None;
                let name = rest(&args);
                self.group = if name.is_empty() {
                    "default".to_string()
                } else {
                    name
                };
                Ok(())
            }
            "usemtl" => {
                self.current = None;
                let name = rest(&args);
                self.material = (!name.is_empty()).then_some(name);
                Ok(())
            }
            "mtllib" => return self.mtllib(line, &args, loader),
            other => {
                let n = self.ignored.len();
                match self.ignored.get_mut(other) {
                    Some(count) => *count += 1,
                    None if n < MAX_IGNORED_KINDS => {
                        self.ignored.insert(other.to_string(), 1);
                    }
                    None => *self.ignored.entry("(other)".to_string()).or_insert(0) += 1,
                }
                Ok(())
            }
        };
        result.map_err(|kind| self.err(line, kind))
    }

    fn check_count(&self, len: usize, element: &'static str) -> Result<(), ErrorKind> {
        let limit = self.options.max_elements.min(NONE as usize - 1);
        if len >= limit {
            Err(ErrorKind::TooManyElements { element, limit })
        } else {
            Ok(())
        }
    }

    fn vertex(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.positions.len(), "vertex")?;
        let (position, color) = match args.len() {
            3 | 4 => {
                if let Some(w) = args.get(3) {
                    number("v", w)?;
                }
                (numbers("v", args)?, None)
            }
            6 => {
                let [x, y, z, r, g, b] = numbers("v", args)?;
                ([x, y, z], Some([r, g, b]))
            }
            n => {
                return Err(malformed(
                    "v",
                    format!("expected x y z, x y z w or x y z r g b; found {n} values"),
                ))
            }
        };
        self.positions.push(position);
        if color.is_some() || !self.colors.is_empty() {
            // Earlier vertices (before the first coloured one) have none.
            self.colors.resize(self.positions.len() - 1, None);
            self.colors.push(color);
        }
        Ok(())
    }

    fn texcoord(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.texcoords.len(), "texture coordinate")?;
        if args.is_empty() || args.len() > 3 {
            return Err(malformed(
                "vt",
                format!("expected u, u v or u v w; found {} values", args.len()),
            ));
        }
        let u = number("vt", args[0])?;
        let v = match args.get(1) {
            Some(t) => number("vt", t)?,
            None => 0.0,
        };
        if let Some(w) = args.get(2) {
            number("vt", w)?;
        }
        for value in [u, v] {
            if to_fixed(value as f64).is_none() {
                return Err(ErrorKind::OutOfFixedRange {
                    what: "texture",
                    value: value as f64,
                });
            }
        }
        self.texcoords.push([u, v]);
        Ok(())
    }

    fn normal(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        self.check_count(self.normals.len(), "normal")?;
        if args.len() != 3 {
            return Err(malformed(
                "vn",
                format!("expected x y z; found {} values", args.len()),
            ));
        }
        self.normals.push(numbers("vn", args)?);
        Ok(())
    }

    fn face(&mut self, args: &[&str]) -> Result<(), ErrorKind> {
        if args.len() < 3 {
            return Err(malformed(
                "f",
                format!("a face needs at least 3 corners, found {}", args.len()),
            ));
        }
        if args.len() > self.options.max_face_corners {
            return Err(ErrorKind::TooManyCorners {
                count: args.len(),
                limit: self.options.max_face_corners,
            });
        }
        let mut corners: Vec<Corner> = Vec::with_capacity(args.len());
        let mut form: Option<Form> = None;
        for token in args {
            let (v, vt, vn) = parse_corner(token)?;
            let this: Form = (vt.is_some(), vn.is_some());
            match form {
                None => form = Some(this),
                Some(f) if f != this => {
                    return Err(ErrorKind::MixedFaceForms {
                        first: clip(args[0]),
                        other: clip(token),
                    })
                }
                Some(_) => {}
            }
            let v = resolve(v, self.positions.len(), "vertex")?;
            let vt = match vt {
                Some(i) => resolve(i, self.texcoords.len(), "texture coordinate")?,
                None => NONE,
            };
            let vn = match vn {
                Some(i) => resolve(i, self.normals.len(), "normal")?,
                None => NONE,
            };
            corners.push([v, vt, vn]);
        }
        let points: Vec<[f64; 3]> = corners
            .iter()
            .map(|c| self.positions[c[0] as usize].map(f64::from))
            .collect();
        for [a, b, c] in triangulate(&points) {
            let tri = [corners[a], corners[b], corners[c]];
            let area2 = cross(sub(points[b], points[a]), sub(points[c], points[a]));
            if tri[0][0] == tri[1][0]
                || tri[1][0] == tri[2][0]
                || tri[0][0] == tri[2][0]
                || dot(area2, area2) == 0.0
            {
                self.degenerate += 1;
                continue;
            }
            if self.triangle_count >= self.options.max_triangles {
                return Err(ErrorKind::TooManyTriangles {
                    limit: self.options.max_triangles,
                });
            }
            self.triangle_count += 1;
            let g = match self.current {
                Some(g) => g,
                None => {
                    let key = (self.group.clone(), self.material.clone());
                    let next = self.groups.len();
                    let g = *self.group_index.entry(key).or_insert(next);
                    if g == next {
                        self.groups.push(GroupBuild {
                            name: self.group.clone(),
                            material: self.material.clone(),
                            triangles: Vec::new(),
                        });
                    }
                    self.current = Some(g);
                    g
                }
            };
            self.groups[g].triangles.push(tri);
        }
        Ok(())
    }
}
