//! matrace — the exact 3D medial axis transform of CAD solids.
//!
//! The pipeline (see `DESIGN.md` in the shared folder): read a STEP B-rep into our own
//! model ([`brep`]), evaluate and query its exact surfaces ([`geom`]), classify its edges and
//! vertices ([`classify`]); the medial tracer, fitting and exporters build on these.
//!
//! The library never prints; the `matrace` binary is thin glue around it.
#![forbid(unsafe_code)]

pub mod batch;
pub mod brep;
pub mod classify;
pub mod error;
pub mod geom;
pub mod medial;
pub mod output;
pub mod panic_guard;
pub mod report;
pub mod run;

pub use brep::{read_model, Model};
pub use classify::{classify, Classification, ClassifyOptions, EdgeKind, VertexKind};
pub use error::{Error, Result};
