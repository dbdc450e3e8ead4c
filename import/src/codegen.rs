//! Rust source output: `static` arrays for flash, and atomic file writes.
//!
//! The generated text has no `use` lines and names every type by its full
//! path (`::fixed::types::I16F16`, `::embedded_graphics::pixelcolor::Rgb888`),
//! so it can be `include!`d anywhere in a crate that depends on `fixed` and
//! `embedded-graphics`. Fixed-point numbers are written as their raw bits
//! (`I16F16::from_bits(65536)` is 1.0), so nothing is rounded twice, and the
//! same input always gives the same bytes.
//!
//! A model with clusters ([`ObjOptions::cluster_triangles`]) also gets
//! `::microraster::mesh::Cluster` values, so its source compiles only in a
//! crate that depends on microraster as well.

use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::error::{ErrorKind, ImportError};
use crate::image::{decode_png, Texels, TextureData, TextureFormat};
use crate::obj::{load_obj, unit_to_u8, Fit, Model, ObjOptions};

const FX: &str = "::fixed::types::I16F16";
const RGB888: &str = "::embedded_graphics::pixelcolor::Rgb888";
const CLUSTER: &str = "::microraster::mesh::Cluster";

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

/// `s` made safe for a `//` comment: control characters become `?`.
fn comment_text(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

fn file_name(path: &Path) -> String {
    comment_text(
        &path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| path.display().to_string()),
    )
}

/// An `f32` as a Rust literal that reads back as the same value.
fn f32_literal(x: f32) -> String {
    let s = format!("{x:?}");
    debug_assert!(x.is_finite());
    s
}

fn f32x3_literal(v: [f32; 3]) -> String {
    format!(
        "[{}, {}, {}]",
        f32_literal(v[0]),
        f32_literal(v[1]),
        f32_literal(v[2])
    )
}

fn fixed_row(values: &[i32]) -> String {
    let items: Vec<String> = values
        .iter()
        .map(|v| format!("{FX}::from_bits({v})"))
        .collect();
    format!("[{}]", items.join(", "))
}

/// Rust source for a model: `pub static` arrays and `pub const`s whose
/// names start with [`rust_prefix`]`(name)` (`P` below).
///
/// | item | type | present |
/// |---|---|---|
/// | `P_VERTEX_COUNT`, `P_TRIANGLE_COUNT` | `const usize`: V and T | always |
/// | `P_GROUP_TRIANGLE_COUNTS` | `const [usize; G]`: each group's triangle count | always |
/// | `P_GROUP_VERTEX_COUNTS` | `const [usize; G]`: each group's vertex count as a draw of its own, one more than the largest index its triangles use | always |
/// | `P_GROUP_DRAWS_VERTEX_COUNT` | `const usize`: the sum of `P_GROUP_VERTEX_COUNTS` | always |
/// | `P_POSITIONS` | `[[I16F16; 3]; V]` | always |
/// | `P_NORMALS` | `[[I16F16; 3]; V]` | if the model has normals |
/// | `P_UVS` | `[[I16F16; 2]; V]` | if it has texture coordinates; `v` flipped to `1 - v` ([`Model::uvs_fixed`]) |
/// | `P_COLORS` | `[Rgb888; V]` | if it has vertex colours |
/// | `P_TRIANGLES` | `[[u16; 3]; T]` (or `u32`, per [`IndexWidth`](crate::IndexWidth)) | always |
/// | `P_CLUSTERS` | `[Cluster; C]`: `Cluster::new(triangle count, first vertex, vertex count, min, max)` ([`Model::clusters`], [`Model::cluster_bounds_fixed`]) | if the model has clusters |
/// | `P_GROUPS` | `[(&str, usize, usize); G]`: name, first triangle, triangle count | always |
/// | `P_GROUP_COLORS` | `[Rgb888; G]`: the material's `Kd`, white without one | always |
/// | `P_GROUP_TEXTURES` | `[Option<&str>; G]`: the material's `map_Kd` | always |
/// | `P_GROUP_CLUSTERS` | `[(usize, usize); G]`: first cluster, cluster count | if the model has clusters |
/// | `P_SCALE`, `P_OFFSET` | `f32`, `[f32; 3]`: position = (original + offset) × scale | always |
/// | `P_BOUNDS_MIN`, `P_BOUNDS_MAX` | `[f32; 3]` | always |
/// | `P_SPHERE_CENTER`, `P_SPHERE_RADIUS` | `[f32; 3]`, `f32` | always |
///
/// `I16F16` and `Rgb888` are written as `::fixed::types::I16F16` and
/// `::embedded_graphics::pixelcolor::Rgb888`, `Cluster` as
/// `::microraster::mesh::Cluster` (so a model with clusters needs a crate
/// that depends on microraster). A header comment names the source file,
/// the options, the counts and any warnings. Without clusters, nothing
/// about them is written.
///
/// The counts are constants so that a firmware can size microraster's
/// `Workspace<VERTICES, ..>` with them, which holds the vertex arrays of
/// every draw of a frame: `P_VERTEX_COUNT` for the whole model as one
/// draw, `P_GROUP_DRAWS_VERTEX_COUNT` for each group as a draw of its own
/// on the prefix `P_POSITIONS[..P_GROUP_VERTEX_COUNTS[g]]` (and the same
/// prefix of the other per-vertex arrays), which holds every vertex the
/// group's triangles use.
///
/// ```
/// use std::path::Path;
/// use microraster_import::{model_to_rust, parse_obj, ObjOptions};
/// let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// let model = parse_obj(obj, Path::new("tri.obj"), |_| None, &ObjOptions::default()).unwrap();
/// let rust = model_to_rust(&model, "tri").unwrap();
/// assert!(rust.contains("pub static TRI_TRIANGLES: [[u16; 3]; 1] = [\n    [0, 1, 2],\n];"));
/// ```
pub fn model_to_rust(model: &Model, name: &str) -> Result<String, ImportError> {
    let p = rust_prefix(name, &model.source)?;
    let mut s = String::new();
    let n = model.positions.len();
    // Writing to a String cannot fail: `let _ =` below.
    let _ = writeln!(
        s,
        "// Generated by microraster-import {} from `{}`. Do not edit.",
        env!("CARGO_PKG_VERSION"),
        file_name(&model.source)
    );
    if model.files.len() > 1 {
        let mtls: Vec<String> = model.files[1..].iter().map(|f| file_name(f)).collect();
        let _ = writeln!(s, "// Materials from `{}`.", mtls.join("`, `"));
    }
    let fit = if model.options.fit == Fit::Auto {
        format!("auto (applied: {})", model.fit_applied.name())
    } else {
        model.options.fit.name().to_string()
    };
    let clusters = if model.options.cluster_triangles > 0 {
        format!(
            ", clusters of at most {} triangles",
            model.options.cluster_triangles
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        s,
        "// Options: fit {fit}, {} indices, computed normals {}{clusters}.",
        model.options.index_width.rust_type(),
        if model.options.compute_normals {
            "on"
        } else {
            "off"
        }
    );
    let clusters = if model.clusters.is_empty() {
        String::new()
    } else {
        format!(", {} clusters", model.clusters.len())
    };
    let _ = writeln!(
        s,
        "// {n} vertices, {} triangles, {} groups{clusters}; {} degenerate triangles dropped.",
        model.triangles.len(),
        model.groups.len(),
        model.degenerate
    );
    let _ = writeln!(
        s,
        "// Positions are (original + {p}_OFFSET) * {p}_SCALE, so original = position / {p}_SCALE - {p}_OFFSET."
    );
    for w in &model.warnings {
        let _ = writeln!(s, "// Warning: {}", comment_text(w));
    }

    write_counts(&mut s, &p, model);

    let _ = writeln!(
        s,
        "\n/// Vertex positions, model space, 16.16 fixed point.\npub static {p}_POSITIONS: [[{FX}; 3]; {n}] = ["
    );
    for v in model.positions_fixed() {
        let _ = writeln!(s, "    {},", fixed_row(&v));
    }
    s.push_str("];\n");

    if !model.normals.is_empty() {
        let _ = writeln!(
            s,
            "\n/// Unit vertex normals, 16.16 fixed point.\npub static {p}_NORMALS: [[{FX}; 3]; {}] = [",
            model.normals.len()
        );
        for v in model.normals_fixed() {
            let _ = writeln!(s, "    {},", fixed_row(&v));
        }
        s.push_str("];\n");
    }

    if !model.uvs.is_empty() {
        let _ = writeln!(
            s,
            "\n/// Texture coordinates (u, v), 16.16 fixed point.\npub static {p}_UVS: [[{FX}; 2]; {}] = [",
            model.uvs.len()
        );
        for v in model.uvs_fixed() {
            let _ = writeln!(s, "    {},", fixed_row(&v));
        }
        s.push_str("];\n");
    }

    if !model.colors.is_empty() {
        let _ = writeln!(
            s,
            "\n/// Vertex colours.\npub static {p}_COLORS: [{RGB888}; {}] = [",
            model.colors.len()
        );
        for [r, g, b] in &model.colors {
            let _ = writeln!(s, "    {RGB888}::new({r}, {g}, {b}),");
        }
        s.push_str("];\n");
    }

    let index = model.options.index_width.rust_type();
    let _ = writeln!(
        s,
        "\n/// Triangles: vertex indices, counter-clockwise from the front, group by group.\npub static {p}_TRIANGLES: [[{index}; 3]; {}] = [",
        model.triangles.len()
    );
    for t in &model.triangles {
        let _ = writeln!(s, "    [{}, {}, {}],", t[0], t[1], t[2]);
    }
    s.push_str("];\n");

    if !model.clusters.is_empty() {
        let _ = writeln!(
            s,
            "
/// Clusters of the triangles, for culling the parts of the mesh outside the view:
/// `Cluster::new(triangle count, first vertex, vertex count, min, max)`. They tile
/// `{p}_TRIANGLES` in order (each holds the next `triangle count` triangles), each one's
/// triangles use only its vertices, and those lie in its box; see
/// `microraster::mesh::Mesh::with_clusters`, which takes them, or a group's run of them
/// (`{p}_GROUP_CLUSTERS`) with the group's triangles.
pub static {p}_CLUSTERS: [{CLUSTER}; {}] = [",
            model.clusters.len()
        );
        for (c, [min, max]) in model.clusters.iter().zip(model.cluster_bounds_fixed()) {
            let _ = writeln!(
                s,
                "    {CLUSTER}::new({}, {}, {}, {}, {}),",
                c.triangles.len(),
                c.vertices.start,
                c.vertices.len(),
                fixed_row(&min),
                fixed_row(&max)
            );
        }
        s.push_str("];\n");
    }

    let g = model.groups.len();
    let _ = writeln!(
        s,
        "\n/// Groups: (name, first triangle, triangle count).\npub static {p}_GROUPS: [(&str, usize, usize); {g}] = ["
    );
    for group in &model.groups {
        let _ = writeln!(
            s,
            "    ({:?}, {}, {}),",
            group.name,
            group.triangles.start,
            group.triangles.len()
        );
    }
    s.push_str("];\n");

    let _ = writeln!(
        s,
        "\n/// Each group's diffuse colour (its material's `Kd`; white without one).\npub static {p}_GROUP_COLORS: [{RGB888}; {g}] = ["
    );
    for group in &model.groups {
        let [r, gr, b] = group
            .material
            .as_ref()
            .map_or([1.0; 3], |m| m.diffuse)
            .map(unit_to_u8);
        let _ = writeln!(s, "    {RGB888}::new({r}, {gr}, {b}),");
    }
    s.push_str("];\n");

    let _ = writeln!(
        s,
        "\n/// Each group's diffuse texture file (its material's `map_Kd`), if any.\npub static {p}_GROUP_TEXTURES: [Option<&str>; {g}] = ["
    );
    for group in &model.groups {
        match group.material.as_ref().and_then(|m| m.texture.as_ref()) {
            Some(t) => {
                let _ = writeln!(s, "    Some({t:?}),");
            }
            None => s.push_str("    None,\n"),
        }
    }
    s.push_str("];\n");

    if !model.clusters.is_empty() {
        let _ = writeln!(
            s,
            "\n/// Each group's clusters: (first cluster in `{p}_CLUSTERS`, cluster count).\npub static {p}_GROUP_CLUSTERS: [(usize, usize); {g}] = ["
        );
        for group in &model.groups {
            let _ = writeln!(
                s,
                "    ({}, {}),",
                group.clusters.start,
                group.clusters.len()
            );
        }
        s.push_str("];\n");
    }

    let offset = model.offset.map(|x| x as f32);
    let _ = write!(
        s,
        "
/// The uniform scale applied to the original positions (after the offset).
pub const {p}_SCALE: f32 = {};
/// The offset added to the original positions (before the scale).
pub const {p}_OFFSET: [f32; 3] = {};
/// The smallest position coordinates.
pub const {p}_BOUNDS_MIN: [f32; 3] = {};
/// The largest position coordinates.
pub const {p}_BOUNDS_MAX: [f32; 3] = {};
/// The bounding sphere's centre (the bounding box's centre).
pub const {p}_SPHERE_CENTER: [f32; 3] = {};
/// The bounding sphere's radius.
pub const {p}_SPHERE_RADIUS: f32 = {};
",
        f32_literal(model.scale as f32),
        f32x3_literal(offset),
        f32x3_literal(model.bounds.min),
        f32x3_literal(model.bounds.max),
        f32x3_literal(model.sphere.center),
        f32_literal(model.sphere.radius),
    );
    Ok(s)
}

/// For each group, how many vertices a draw of it alone needs: one more
/// than the largest index its triangles use, so that it can be drawn on
/// that prefix of the vertex arrays (the renderer's workspace holds every
/// vertex of a draw's arrays, used or not). 0 for a group without
/// triangles.
fn group_vertex_counts(model: &Model) -> Vec<usize> {
    model
        .groups
        .iter()
        .map(|g| {
            let top = model.triangles.get(g.triangles.clone()).unwrap_or(&[]);
            top.iter().flatten().max().map_or(0, |&i| i as usize + 1)
        })
        .collect()
}

/// The counts a firmware sizes its renderer's `Workspace` with, as
/// constants (a `static`'s length cannot be read in a const context).
fn write_counts(s: &mut String, p: &str, model: &Model) {
    let per_group = group_vertex_counts(model);
    let list = |counts: &mut dyn Iterator<Item = usize>| {
        counts.map(|c| c.to_string()).collect::<Vec<_>>().join(", ")
    };
    let g = model.groups.len();
    let _ = write!(
        s,
        "
/// Vertices of `{p}_POSITIONS` (and of the other per-vertex arrays): the
/// `VERTICES` a renderer workspace needs to draw the whole model at once.
pub const {p}_VERTEX_COUNT: usize = {};
/// Triangles of `{p}_TRIANGLES`.
pub const {p}_TRIANGLE_COUNT: usize = {};
/// Each group's triangle count (as in `{p}_GROUPS`).
pub const {p}_GROUP_TRIANGLE_COUNTS: [usize; {g}] = [{}];
/// Each group's vertex count as a draw of its own: its triangles use only the first
/// `{p}_GROUP_VERTEX_COUNTS[g]` vertices, so its mesh can take that prefix of the
/// per-vertex arrays, and the workspace needs that many vertices for it.
pub const {p}_GROUP_VERTEX_COUNTS: [usize; {g}] = [{}];
/// The sum of `{p}_GROUP_VERTEX_COUNTS`: the `VERTICES` a workspace needs to draw
/// every group once, each as a draw of its own.
pub const {p}_GROUP_DRAWS_VERTEX_COUNT: usize = {};
",
        model.positions.len(),
        model.triangles.len(),
        list(&mut model.groups.iter().map(|g| g.triangles.len())),
        list(&mut per_group.iter().copied()),
        per_group.iter().sum::<usize>(),
    );
}

/// What [`obj_to_rust`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSummary {
    /// The file written.
    pub output: PathBuf,
    /// Vertices written.
    pub vertices: usize,
    /// Triangles written.
    pub triangles: usize,
    /// Groups written.
    pub groups: usize,
    /// Clusters written (0 without clustering).
    pub clusters: usize,
    /// Degenerate triangles dropped.
    pub degenerate: usize,
    /// What the fit resolved to ([`Fit::Keep`] or [`Fit::Unit`]).
    pub fit_applied: Fit,
    /// The scale applied ([`Model::scale`]).
    pub scale: f64,
    /// The offset applied ([`Model::offset`]).
    pub offset: [f64; 3],
    /// The files read: the OBJ, then its MTL files ([`Model::files`]).
    pub files: Vec<PathBuf>,
    /// The import's warnings ([`Model::warnings`]).
    pub warnings: Vec<String>,
}

impl ModelSummary {
    /// A summary of `model` written to `output`.
    pub fn new(model: &Model, output: impl Into<PathBuf>) -> Self {
        Self {
            output: output.into(),
            vertices: model.positions.len(),
            triangles: model.triangles.len(),
            groups: model.groups.len(),
            clusters: model.clusters.len(),
            degenerate: model.degenerate,
            fit_applied: model.fit_applied,
            scale: model.scale,
            offset: model.offset,
            files: model.files.clone(),
            warnings: model.warnings.clone(),
        }
    }

    /// `cargo:rerun-if-changed=` lines for every file read, for a build
    /// script to print.
    pub fn rerun_if_changed(&self) -> String {
        rerun_lines(&self.files)
    }
}

fn rerun_lines(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| format!("cargo:rerun-if-changed={}\n", f.display()))
        .collect()
}

impl std::fmt::Display for ModelSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} vertices, {} triangles, {} groups",
            self.vertices, self.triangles, self.groups
        )?;
        if self.clusters > 0 {
            write!(f, ", {} clusters", self.clusters)?;
        }
        write!(
            f,
            ", scale {} (fit {})",
            self.scale,
            self.fit_applied.name()
        )?;
        if self.degenerate > 0 {
            write!(f, ", {} degenerate triangles dropped", self.degenerate)?;
        }
        Ok(())
    }
}

/// Imports the OBJ file `obj` (with its MTL files) and writes the Rust
/// source of [`model_to_rust`] to `out`, atomically (see [`write_atomic`]).
/// For build scripts: prints nothing; the summary lists the files read
/// ([`ModelSummary::rerun_if_changed`]).
///
/// ```no_run
/// // build.rs
/// use std::path::PathBuf;
/// use microraster_import::{obj_to_rust, ObjOptions};
///
/// let out = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("teapot.rs");
/// let summary = obj_to_rust("assets/teapot.obj", &out, "teapot", &ObjOptions::default())
///     .unwrap_or_else(|e| panic!("{e}"));
/// print!("{}", summary.rerun_if_changed());
/// // In the crate: include!(concat!(env!("OUT_DIR"), "/teapot.rs"));
/// ```
pub fn obj_to_rust(
    obj: impl AsRef<Path>,
    out: impl AsRef<Path>,
    name: &str,
    options: &ObjOptions,
) -> Result<ModelSummary, ImportError> {
    let (obj, out) = (obj.as_ref(), out.as_ref());
    rust_prefix(name, obj)?;
    let model = load_obj(obj, options)?;
    let text = model_to_rust(&model, name)?;
    write_atomic(out, &text)?;
    Ok(ModelSummary::new(&model, out))
}

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

/// Rust source for a texture: `pub` items whose names start with
/// [`rust_prefix`]`(name)` (`P` below).
///
/// | item | type |
/// |---|---|
/// | `P_WIDTH`, `P_HEIGHT` | `u32` |
/// | `P_STRIDE` | `usize`: array elements per row |
/// | `P_TEXELS` | `[u16; N]` (Rgb565) or `[u8; N]` (the other formats) |
/// | `P_PALETTE` | `[u16; K]` of Rgb565 colours (indexed formats only) |
///
/// Rows are top to bottom, pixels left to right; the layouts are those of
/// [`TextureFormat`].
pub fn texture_to_rust(texture: &TextureData, name: &str) -> Result<String, ImportError> {
    let p = rust_prefix(name, &texture.source)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "// Generated by microraster-import {} from `{}`. Do not edit.",
        env!("CARGO_PKG_VERSION"),
        file_name(&texture.source)
    );
    let _ = writeln!(
        s,
        "// {}x{} pixels, format {}: {}.",
        texture.width,
        texture.height,
        texture.format.name(),
        texture.format.layout()
    );
    let _ = writeln!(
        s,
        "// {} bytes of texels, {} bytes of palette.{}",
        texture.texel_bytes(),
        texture.palette.len() * 2,
        if texture.translucent {
            " The image's transparency is ignored."
        } else {
            ""
        }
    );
    let _ = write!(
        s,
        "
/// Width in pixels.
pub const {p}_WIDTH: u32 = {};
/// Height in pixels.
pub const {p}_HEIGHT: u32 = {};
/// Elements of `{p}_TEXELS` per row.
pub const {p}_STRIDE: usize = {};
",
        texture.width,
        texture.height,
        texture.stride()
    );
    match &texture.texels {
        Texels::U16(t) => hex_array(&mut s, &format!("{p}_TEXELS"), "u16", t, 4, "Texels"),
        Texels::U8(t) => hex_array(&mut s, &format!("{p}_TEXELS"), "u8", t, 2, "Texels"),
    }
    if matches!(
        texture.format,
        TextureFormat::Indexed8 | TextureFormat::Indexed4
    ) {
        hex_array(
            &mut s,
            &format!("{p}_PALETTE"),
            "u16",
            &texture.palette,
            4,
            "Palette: Rgb565 colours",
        );
    }
    Ok(s)
}

fn hex_array<T: Copy + Into<u32>>(
    s: &mut String,
    item: &str,
    ty: &str,
    values: &[T],
    digits: usize,
    doc: &str,
) {
    let _ = writeln!(
        s,
        "/// {doc}.\npub static {item}: [{ty}; {}] = [",
        values.len()
    );
    let per_line = if digits == 4 { 12 } else { 16 };
    for chunk in values.chunks(per_line) {
        let items: Vec<String> = chunk
            .iter()
            .map(|&v| format!("0x{:0digits$X}", v.into()))
            .collect();
        let _ = writeln!(s, "    {},", items.join(", "));
    }
    s.push_str("];\n");
}

/// What [`png_to_rust`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureSummary {
    /// The file written.
    pub output: PathBuf,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The format written.
    pub format: TextureFormat,
    /// Palette entries (0 for formats without a palette).
    pub palette: usize,
    /// Bytes of texels plus palette.
    pub bytes: usize,
    /// Whether the image had transparency (which is ignored).
    pub translucent: bool,
    /// The files read (the PNG).
    pub files: Vec<PathBuf>,
}

impl TextureSummary {
    /// `cargo:rerun-if-changed=` lines for every file read, for a build
    /// script to print.
    pub fn rerun_if_changed(&self) -> String {
        rerun_lines(&self.files)
    }
}

impl std::fmt::Display for TextureSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}x{} {}, {} bytes",
            self.width,
            self.height,
            self.format.name(),
            self.bytes
        )?;
        if self.palette > 0 {
            write!(f, ", {} palette colours", self.palette)?;
        }
        if self.translucent {
            write!(f, " (transparency ignored)")?;
        }
        Ok(())
    }
}

/// Decodes the PNG file `png`, converts it to `format` and writes the Rust
/// source of [`texture_to_rust`] to `out`, atomically (see
/// [`write_atomic`]). Prints nothing.
pub fn png_to_rust(
    png: impl AsRef<Path>,
    out: impl AsRef<Path>,
    name: &str,
    format: TextureFormat,
) -> Result<TextureSummary, ImportError> {
    let (png, out) = (png.as_ref(), out.as_ref());
    rust_prefix(name, png)?;
    let bytes = fs::read(png).map_err(|e| ImportError::io(png, e))?;
    let texture = decode_png(&bytes, png)?.convert(format)?;
    let text = texture_to_rust(&texture, name)?;
    write_atomic(out, &text)?;
    Ok(TextureSummary {
        output: out.to_path_buf(),
        width: texture.width,
        height: texture.height,
        format,
        palette: texture.palette.len(),
        bytes: texture.texel_bytes() + 2 * texture.palette.len(),
        translucent: texture.translucent,
        files: vec![png.to_path_buf()],
    })
}
