//! matrace — the exact 3D medial axis transform of CAD solids.
//!
//! The pipeline (see `DESIGN.md` in the shared folder): read a STEP B-rep into our own
//! model ([`brep`]), evaluate and query its exact surfaces ([`geom`]), classify its edges and
//! vertices ([`classify`]); the medial tracer, fitting and exporters build on these.
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

pub use classify::{classify, Classification, ClassifyOptions, EdgeKind, VertexKind};
pub use error::{Error, Result};
pub use ingest::read_model;
pub use model::Model;
