//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

/// The project root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A sample file.
pub fn sample(name: &str) -> PathBuf {
    root().join("samples").join(name)
}

/// The third-party corpus, beside the project (`../shared/realworld`), if present.
pub fn realworld_dir() -> Option<PathBuf> {
    let d = root().join("..").join("shared").join("realworld");
    d.is_dir().then_some(d)
}

/// The manifest of the reference samples.
pub fn manifest() -> serde_json::Value {
    let text = std::fs::read_to_string(root().join("samples/manifest.json")).expect("manifest");
    serde_json::from_str(&text).expect("manifest is JSON")
}

/// Runs the `matrace` binary.
pub fn matrace(args: &[&str], cwd: &Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_matrace"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run matrace")
}

/// Every STEP file of `samples/`, sorted.
pub fn sample_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("samples"))
        .expect("samples/")
        .map(|e| e.expect("samples/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "step"))
        .collect();
    files.sort();
    files
}
