//! matrace — the exact 3D medial axis transform of CAD solids.
//!
//! The crate is the pipeline in layers, each importing only from those before it
//! (`docs/architecture.md`; `tests/it/architecture.rs` checks it):
//! - [`model`]: the B-rep data types; [`error`], [`panic_guard`]: the library's error type
//!   and the guard around third-party code that may panic;
//! - [`geom`]: evaluation, curvature, projection, trimming and distance on the exact faces;
//! - [`ingest`]: STEP and IGES files into a [`Model`];
//! - [`classify`]: edges and vertices convex, reflex, smooth, …;
//! - [`medial`]: the medial equations, the tracer, sheets and verification;
//! - [`fit`]: B-spline curves through the traced seams;
//! - [`export`]: the report, the STEP file, the sheet mesh and the picture;
//! - [`pipeline`]: one part through every stage; [`batch`]: many parts, each in a process.
//!
//! The library never prints; the `matrace` binary is thin glue around it.
#![forbid(unsafe_code)]

pub mod batch;
pub mod classify;
pub mod error;
pub mod export;
pub mod fit;
pub mod geom;
pub mod ingest;
pub mod medial;
pub mod model;
pub mod panic_guard;
pub mod pipeline;
#[cfg(test)]
pub(crate) mod testing;

pub use classify::{classify, Classification, ClassifyOptions, EdgeKind, VertexKind};
pub use error::{Error, Result};
pub use ingest::read_model;
pub use model::Model;
