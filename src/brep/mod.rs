//! The B-rep model and its ingestion from STEP and IGES.

mod domain;
pub mod iges;
pub mod model;
mod records;
mod step;

pub use model::{
    Edge, Face, Loop, Model, OrientedEdge, Shell, Solid, SourceInfo, UvDomain, Vertex,
};
pub use step::MAX_FILE_BYTES;

use crate::error::Result;
use std::path::Path;

/// True when `path` names an IGES file (`.igs` / `.iges`, any case).
pub fn is_iges_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("igs") || e.eq_ignore_ascii_case("iges"))
}

/// Reads a STEP or IGES file into a [`Model`]: IGES for the `.igs` / `.iges` extensions,
/// STEP otherwise.
pub fn read_model(path: &Path) -> Result<Model> {
    if is_iges_path(path) {
        iges::read_model(path)
    } else {
        step::read_model(path)
    }
}

/// Reads STEP or IGES text already in memory: IGES when `path` has an IGES extension or the
/// text has IGES's `S` in column 73 of its first record, STEP otherwise.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    if is_iges_path(path) || iges::looks_like_iges(bytes) {
        iges::read_model_from_bytes(path, bytes)
    } else {
        step::read_model_from_bytes(path, bytes)
    }
}
