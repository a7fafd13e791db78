//! Writing a file atomically, so that a reader (or a batch resumed after a crash) never sees
//! half of it: every output of the crate is written this way.

use crate::error::{Error, Result};
use std::path::Path;

/// Writes `bytes` to `path` atomically: into a temporary file in the same folder, then
/// renamed over `path`, so a reader (or a batch resumed after a crash) never sees half a file.
/// The error names the file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    result.map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        Error::Write {
            path: path.to_owned(),
            source,
        }
    })
}
