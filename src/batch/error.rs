//! Errors that make a batch impossible to start (exit status 2).

use crate::error::Error;
use std::path::PathBuf;

/// Errors that make a batch impossible to start (exit status 2).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    #[error("{0}: no such file or folder")]
    Missing(PathBuf),
    #[error("{path}: cannot read folder: {source}")]
    ReadDir {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("no STEP or IGES files (.step, .stp, .igs, .iges) found in {0}")]
    NoInputs(String),
    #[error("bad shard {0:?}: expected K/N with 1 <= K <= N, e.g. 3/8")]
    Shard(String),
    #[error("cannot start {jobs} worker threads: {reason}")]
    Threads { jobs: usize, reason: String },
    #[error(transparent)]
    Output(#[from] Error),
}
