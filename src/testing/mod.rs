//! Fixtures shared by the unit tests (compiled in test builds only): the reference samples
//! (`samples/`) and the third-party corpus beside the project, read, classified and traced
//! the way the pipeline does it with default options.

pub mod distance;
pub mod geometry;

use crate::classify::Classification;
use crate::medial::MedialAxis;
use crate::model::Model;
use std::path::PathBuf;

/// The project root (where `Cargo.toml` is).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The path of a reference sample, `samples/<name>`.
pub fn sample_path(name: &str) -> PathBuf {
    root().join("samples").join(name)
}

/// Every STEP file of `samples/`, sorted.
pub fn sample_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("samples"))
        .expect("samples/ is readable")
        .map(|e| e.expect("samples/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "step"))
        .collect();
    files.sort();
    files
}

/// The third-party corpus `../shared/realworld`, when it is there.
pub fn realworld_dir() -> Option<PathBuf> {
    let d = root().join("../shared/realworld");
    d.is_dir().then_some(d)
}

/// A reference sample, read (panics with the error when it cannot be).
pub fn sample(name: &str) -> Model {
    let path = sample_path(name);
    crate::ingest::read_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A reference sample, read and classified with the default options.
pub fn classified(name: &str) -> (Model, Classification) {
    let model = sample(name);
    let class = crate::classify::classify(&model, &Default::default());
    (model, class)
}

/// A reference sample, read, classified and traced at the default accuracy.
pub fn traced(name: &str) -> (Model, Classification, MedialAxis) {
    let (model, class) = classified(name);
    let axis = crate::medial::trace(
        &model,
        &class,
        &crate::medial::TraceOptions::for_model(&model),
    );
    (model, class, axis)
}
