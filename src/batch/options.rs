//! What a batch computes and how it runs.

use super::shard::Shard;
pub use crate::pipeline::PartOptions;
use std::path::PathBuf;
use std::time::Duration;

/// Default per-part time limit (seconds).
pub const DEFAULT_TIMEOUT_SECS: f64 = 300.0;

/// What a batch computes and how it runs.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    /// Output folder (created if missing).
    pub out_dir: PathBuf,
    /// The executable run for each part as `WORKER trace PART -o DIR --stem STEM …`: the
    /// `matrace` binary (`std::env::current_exe()`).
    pub worker: PathBuf,
    /// Parts traced at once (at least 1).
    pub jobs: usize,
    /// Per-part wall-clock limit; `None`: none.
    pub timeout: Option<Duration>,
    /// Per-part address-space limit in bytes, applied through `prlimit --as` when that tool
    /// is on the `PATH` (else no limit; [`Summary::memory_limit_bytes`] says which).
    pub memory_limit: Option<u64>,
    /// Only this slice of the inputs.
    pub shard: Option<Shard>,
    /// Skip parts whose outputs are complete ([`completed_report`]).
    pub resume: bool,
    /// What each part computes and writes, as `matrace trace` takes it. With
    /// `part.verify`, a part whose worst error exceeds the accuracy counts as failed.
    pub part: PartOptions,
}

impl BatchOptions {
    /// Every output, default tolerances, one job per core, the default time limit and no
    /// memory limit.
    pub fn new(out_dir: impl Into<PathBuf>, worker: impl Into<PathBuf>) -> BatchOptions {
        BatchOptions {
            out_dir: out_dir.into(),
            worker: worker.into(),
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            timeout: Some(Duration::from_secs_f64(DEFAULT_TIMEOUT_SECS)),
            memory_limit: None,
            shard: None,
            resume: false,
            part: PartOptions::default(),
        }
    }

    /// The output file names of a part with stem `stem`, the report last.
    pub fn output_names(&self, stem: &str) -> Vec<String> {
        let mut v = vec![format!("{stem}.mat.step")];
        if self.part.mesh {
            v.push(format!("{stem}.sheets.obj"));
        }
        if self.part.picture {
            v.push(format!("{stem}.mat.svg"));
        }
        v.push(format!("{stem}.mat.json"));
        v
    }
}
