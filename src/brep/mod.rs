//! The B-rep model and its ingestion from STEP.

mod domain;
pub mod model;
mod records;
mod step;

pub use model::{
    Edge, Face, Loop, Model, OrientedEdge, Shell, Solid, SourceInfo, UvDomain, Vertex,
};
pub use step::{read_model, read_model_from_bytes, MAX_FILE_BYTES};
