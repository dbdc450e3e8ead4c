//! The pieces of generated text: the full paths of the types it names,
//! comments, `f32` and 16.16 literals, and arrays of 16.16 rows.

use std::fmt::Write as _;
use std::path::Path;

const FX: &str = "::fixed::types::I16F16";
pub(super) const RGB888: &str = "::embedded_graphics::pixelcolor::Rgb888";
pub(super) const CLUSTER: &str = "::microraster::mesh::Cluster";

/// `s` made safe for a `//` comment: control characters become `?`.
pub(super) fn comment_text(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

pub(super) fn file_name(path: &Path) -> String {
    comment_text(
        &path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| path.display().to_string()),
    )
}

/// An `f32` as a Rust literal that reads back as the same value.
pub(super) fn f32_literal(x: f32) -> String {
    let s = format!("{x:?}");
    debug_assert!(x.is_finite());
    s
}

pub(super) fn f32x3_literal(v: [f32; 3]) -> String {
    format!(
        "[{}, {}, {}]",
        f32_literal(v[0]),
        f32_literal(v[1]),
        f32_literal(v[2])
    )
}

pub(super) fn fixed_row(values: &[i32]) -> String {
    let items: Vec<String> = values
        .iter()
        .map(|v| format!("{FX}::from_bits({v})"))
        .collect();
    format!("[{}]", items.join(", "))
}

/// A `pub static` array of 16.16 rows named `item`, documented as `doc`
/// (and "16.16 fixed point"), one row a line.
pub(super) fn fixed_array<const N: usize>(
    s: &mut String,
    doc: &str,
    item: &str,
    rows: &[[i32; N]],
) {
    let _ = writeln!(
        s,
        "\n/// {doc}, 16.16 fixed point.\npub static {item}: [[{FX}; {N}]; {}] = [",
        rows.len()
    );
    for v in rows {
        let _ = writeln!(s, "    {},", fixed_row(v));
    }
    s.push_str("];\n");
}
