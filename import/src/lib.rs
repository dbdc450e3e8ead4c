//! Host-side asset importer for the `microraster` rasterizer: Wavefront OBJ models (with
//! their MTL materials) and PNG images become Rust source of `static`
//! arrays, so that the firmware keeps them in flash and never parses a file.
//!
//! This crate needs `std` and runs on the host, in a build script or as the
//! `microraster-import` command. It does not depend on microraster; the
//! source it writes names `::fixed::types::I16F16` and
//! `::embedded_graphics::pixelcolor::Rgb888`, so the crate that includes it
//! needs `fixed` and `embedded-graphics` (as microraster users have).
//! Only with clusters on ([`ObjOptions::cluster_triangles`], `--clusters`)
//! does it also name `::microraster::mesh::Cluster`, and then only a crate
//! that depends on microraster can compile it.
//!
//! # In a build script
//!
//! ```no_run
//! // build.rs (with microraster-import in [build-dependencies])
//! use std::path::PathBuf;
//! use microraster_import::{obj_to_rust, png_to_rust, ObjOptions, TextureFormat};
//!
//! fn main() {
//!     let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
//!     let model = obj_to_rust("assets/ship.obj", out.join("ship.rs"), "ship", &ObjOptions::default())
//!         .unwrap_or_else(|e| panic!("{e}"));
//!     print!("{}", model.rerun_if_changed());
//!     let tex = png_to_rust("assets/hull.png", out.join("hull.rs"), "hull", TextureFormat::Indexed4)
//!         .unwrap_or_else(|e| panic!("{e}"));
//!     print!("{}", tex.rerun_if_changed());
//! }
//! ```
//!
//! and in the firmware:
//!
//! ```text
//! include!(concat!(env!("OUT_DIR"), "/ship.rs"));
//! let mesh = Mesh::new(&SHIP_POSITIONS, &SHIP_TRIANGLES)?.with_normals(&SHIP_NORMALS)?;
//! ```
//!
//! # Sizing the workspace
//!
//! microraster's `Workspace<VERTICES, ..>` holds the vertex arrays of every
//! draw of a frame. The generated source gives the counts as constants
//! (see [`model_to_rust`]), so a firmware sizes it at compile time:
//!
//! ```text
//! // The whole model as one draw:
//! static WS: ConstStaticCell<Workspace<SHIP_VERTEX_COUNT, 2048, 64>> = ConstStaticCell::new(Workspace::new());
//! // Or each group as a draw of its own, on the prefix of the arrays it uses:
//! static WS: ConstStaticCell<Workspace<SHIP_GROUP_DRAWS_VERTEX_COUNT, 2048, 64>> = ConstStaticCell::new(Workspace::new());
//! let (_, first, count) = SHIP_GROUPS[g];
//! let v = SHIP_GROUP_VERTEX_COUNTS[g];
//! let part = Mesh::new(&SHIP_POSITIONS[..v], &SHIP_TRIANGLES[first..first + count])?;
//! ```
//!
//! # Clusters
//!
//! A large model (a level, a terrain) is cheaper to draw when the renderer
//! can skip the parts outside the view. With
//! [`ObjOptions::with_cluster_triangles`]`(n)` (`--clusters N`) the importer
//! splits each group's triangles in space into clusters of at most `n`,
//! lays triangles and vertices out cluster by cluster (see
//! [`obj`](crate::obj#clusters)), and writes `SHIP_CLUSTERS` (each
//! cluster's triangle count, vertex run and bounding box) and
//! `SHIP_GROUP_CLUSTERS` (each group's run of them):
//!
//! ```text
//! let mesh = Mesh::new(&SHIP_POSITIONS, &SHIP_TRIANGLES)?.with_clusters(&SHIP_CLUSTERS)?;
//! // or one mesh per group:
//! let (first, count) = (SHIP_GROUPS[g].1, SHIP_GROUPS[g].2);
//! let (c0, cn) = SHIP_GROUP_CLUSTERS[g];
//! let part = Mesh::new(&SHIP_POSITIONS, &SHIP_TRIANGLES[first..first + count])?
//!     .with_clusters(&SHIP_CLUSTERS[c0..c0 + cn])?;
//! ```
//!
//! # From the command line
//!
//! ```text
//! microraster-import obj MODEL.obj --out model.rs [--name NAME] [--fit auto|keep|unit] [--u32] [--no-normals] [--clusters N] [--max-face-corners N] [--allow-outside-files]
//! microraster-import png IMAGE.png --out tex.rs [--name NAME] --format rgb565|gray8|indexed8|indexed4
//! ```
//!
//! # In memory
//!
//! [`parse_obj`] and [`decode_png`] take text and bytes; the [`Model`] and
//! [`Texture`] they return are plain data, with [`Model::positions_fixed`]
//! and friends giving the raw 16.16 bits, and [`model_to_rust`] /
//! [`texture_to_rust`] the source text.
//!
//! # Errors
//!
//! Every failure is an [`ImportError`] naming the file and, where one line
//! is to blame, its 1-based number; it displays as `path:line: reason`.
//! Nothing panics on bad input, and nothing is partly written: output files
//! are written to a temporary file and renamed ([`write_atomic`]).

#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod codegen;
pub mod error;
pub mod image;
pub mod obj;
pub mod paths;

pub use codegen::{
    model_to_rust, obj_to_rust, png_to_rust, rust_prefix, sanitize_name, texture_to_rust,
    write_atomic, ModelSummary, TextureSummary,
};
pub use error::{ErrorKind, ImportError};
pub use image::{decode_png, gray8, load_png, rgb565, Texels, Texture, TextureData, TextureFormat};
pub use obj::{
    load_obj, parse_obj, to_fixed, triangulate, Aabb, ClusterRange, Fit, Group, IndexWidth,
    Material, Model, ObjOptions, Sphere,
};
