//! Rust source output: `static` arrays for flash, and atomic file writes.
//!
//! The generated text has no `use` lines and names every type by its full
//! path (`::fixed::types::I16F16`, `::embedded_graphics::pixelcolor::Rgb888`),
//! so it can be `include!`d anywhere in a crate that depends on `fixed` and
//! `embedded-graphics`. Fixed-point numbers are written as their raw bits
//! (`I16F16::from_bits(65536)` is 1.0), so nothing is rounded twice, and the
//! same input always gives the same bytes.
//!
//! A model with clusters
//! ([`ObjOptions::cluster_triangles`](crate::ObjOptions::cluster_triangles))
//! also gets `::microraster::mesh::Cluster` values, so its source compiles
//! only in a crate that depends on microraster as well.

use std::path::PathBuf;

mod literal;
mod model;
mod names;
mod texture;
mod write;

pub use model::{model_to_rust, obj_to_rust, ModelSummary};
pub use names::{rust_prefix, sanitize_name};
pub use texture::{png_to_rust, texture_to_rust, TextureSummary};
pub use write::write_atomic;

fn rerun_lines(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| format!("cargo:rerun-if-changed={}\n", f.display()))
        .collect()
}
