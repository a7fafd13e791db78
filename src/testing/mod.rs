//! Fixtures shared by the unit tests (compiled in test builds only): the reference samples
//! (`samples/`) and the third-party corpus beside the project, read, classified and traced
//! the way the pipeline does it with default options; and small inputs written by the tests
//! (IGES files, STEP instances).

pub mod distance;
pub mod geometry;

use crate::classify::Classification;
use crate::medial::MedialAxis;
use crate::model::Model;
use std::path::PathBuf;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Parameter, Record};

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

/// The STEP files of `samples/` and, where present, `../shared/realworld/` (see
/// [`realworld_dir`]).
pub fn corpus_step_files() -> Vec<PathBuf> {
    let mut files = vec![];
    let dirs = std::iter::once(root().join("samples")).chain(realworld_dir());
    for dir in dirs {
        for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let p = e.path();
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
            if ["step", "stp", "STEP", "STP"].contains(&ext) {
                files.push(p);
            }
        }
    }
    assert!(files.len() >= 25, "found only {} files", files.len());
    files
}

/// The third-party corpus `../shared/realworld`, when it is there. When it is not, the test
/// (named by its thread, as the test harness names it) says so on the terminal, past the
/// harness's output capture, and goes on without it; under CI (the `CI` variable set, not
/// `false` or `0`), where the corpus must be present, it fails.
pub fn realworld_dir() -> Option<PathBuf> {
    let d = root().join("../shared/realworld");
    if d.is_dir() {
        return Some(d);
    }
    let test = std::thread::current()
        .name()
        .unwrap_or("a unit test")
        .to_string();
    let ci = std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0");
    assert!(
        !ci,
        "{test}: needs the third-party corpus (../shared/realworld), which CI must provide"
    );
    use std::io::Write;
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED (the corpus part of) {test}: needs the third-party corpus (../shared/realworld beside the project)"
    );
    None
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

/// One entity of a small IGES file written by a test: type, form, DE of its transformation
/// matrix (0: none), parameters (without the type number and the record delimiter).
pub type IgesEntity<'a> = (i64, i64, usize, &'a str);

/// A fixed-format IGES file holding `entities` (DE numbers 1, 3, 5, … in order), with unit
/// flag `unit`.
pub fn iges_file(entities: &[IgesEntity], unit: i64) -> String {
    let mut d = vec![];
    let mut p: Vec<String> = vec![];
    for (k, (ty, form, tr, params)) in entities.iter().enumerate() {
        let de = 2 * k + 1;
        let first = p.len() + 1;
        // Split the record at delimiters into lines of at most 64 columns.
        let text = format!("{ty},{params};");
        let mut line = String::new();
        for piece in text.split_inclusive(',') {
            if line.len() + piece.len() > 64 {
                p.push(format!("{line:<64}{de:>8}P{:>7}", p.len() + 1));
                line.clear();
            }
            line.push_str(piece);
        }
        p.push(format!("{line:<64}{de:>8}P{:>7}", p.len() + 1));
        let count = p.len() + 1 - first;
        d.push(format!(
            "{ty:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{tr:>8}{:>8}{:>8}D{de:>7}",
            0, 0, 0, 0, 0, "00010000"
        ));
        d.push(format!(
            "{ty:>8}{:>8}{:>8}{count:>8}{form:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            0,
            0,
            "",
            "",
            "",
            0,
            de + 1
        ));
    }
    let g = format!(",,4Htest,,,,,,,,,,1.,{unit},,,,,1E-07,;");
    let mut out = vec![format!("{:<72}S{:>7}", "unit test", 1)];
    out.push(format!("{g:<72}G{:>7}", 1));
    out.extend(d.iter().cloned());
    out.extend(p.iter().cloned());
    out.push(format!(
        "{:<72}T{:>7}",
        format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, 1, d.len(), p.len()),
        1
    ));
    out.join("\n") + "\n"
}

/// A simple STEP instance `#id=NAME();` (no parameters).
pub fn simple_instance(id: u64, name: &str) -> EntityInstance {
    EntityInstance::Simple {
        id,
        record: Record {
            name: name.into(),
            parameter: Parameter::List(vec![]),
        },
    }
}
