//! The STEP reader's errors.
//!
//! An error is about the file, or names the entity at fault; truck's errors and panics are
//! turned into one-line reasons.

use crate::error::Error;
use std::path::Path;

/// Runs `f`, turning a panic into an error message (truck panics on some bad data).
pub fn guarded<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    crate::panic_guard::catch(f)
}

/// The first line of a message, at most 200 bytes.
pub fn first_line(s: &str) -> String {
    let line = s.lines().next().unwrap_or("").trim();
    if line.len() > 200 {
        format!("{}…", &line[..line.floor_char_boundary(200)])
    } else {
        line.to_string()
    }
}

/// An error about the whole file (no entity to blame).
pub fn model_err(path: &Path, reason: impl Into<String>) -> Error {
    Error::Model {
        path: path.into(),
        reason: reason.into(),
    }
}

/// An error naming the entity at fault.
pub fn entity_err(
    path: &Path,
    id: u64,
    entity: impl Into<String>,
    reason: impl Into<String>,
) -> Error {
    Error::Entity {
        path: path.into(),
        id,
        entity: entity.into(),
        reason: reason.into(),
    }
}
