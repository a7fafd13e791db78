//! The library's one error type.
//!
//! Every error names the file it is about and, where there is one, the STEP entity
//! (`#123 B_SPLINE_SURFACE_WITH_KNOTS: knots not sorted`).

use std::path::PathBuf;

/// Result alias for the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong reading or processing a part.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file could not be read from disk.
    #[error("{path}: cannot read file: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// An output file could not be written.
    #[error("{path}: cannot write file: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The file is not a STEP exchange structure we can parse.
    #[error("{path}: not a readable STEP file: {reason}")]
    Syntax { path: PathBuf, reason: String },
    /// The file parsed, but what it describes cannot be used (no solid, open shell, …).
    #[error("{path}: {reason}")]
    Model { path: PathBuf, reason: String },
    /// One entity of the file is unusable (unsupported type, bad data, lost in conversion).
    #[error("{path}: #{id} {entity}: {reason}")]
    Entity {
        path: PathBuf,
        id: u64,
        entity: String,
        reason: String,
    },
}

impl Error {
    /// The path of the file the error is about.
    pub fn path(&self) -> &std::path::Path {
        match self {
            Error::Io { path, .. }
            | Error::Write { path, .. }
            | Error::Syntax { path, .. }
            | Error::Model { path, .. }
            | Error::Entity { path, .. } => path,
        }
    }
}
