//! Running the parts: up to `jobs` children at once, resumed parts skipped, progress
//! reported to a callback.

use super::child::{find_in_path, run_part};
use super::error::BatchError;
use super::inputs::Input;
use super::options::BatchOptions;
use super::resume::completed_report;
use super::summary::{record_from_report, Counts, PartRecord, Summary, SummaryOptions, SCHEMA};
use crate::error::Error;
use rayon::prelude::*;
use std::time::Instant;

/// What [`run_batch`] reports while it runs.
#[derive(Debug)]
pub enum Progress<'a> {
    /// About to run `total` parts.
    Started { total: usize },
    /// A part ended (`done` of `total` so far, in completion order).
    Finished {
        done: usize,
        total: usize,
        record: &'a PartRecord,
    },
}

/// Runs `inputs` (already sharded) and returns the summary (not yet written). `inputs_found`
/// is the number of inputs before sharding, for the summary.
pub fn run_batch(
    inputs: &[Input],
    inputs_found: usize,
    opts: &BatchOptions,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Summary, BatchError> {
    let started = Instant::now();
    std::fs::create_dir_all(&opts.out_dir).map_err(|source| Error::Write {
        path: opts.out_dir.clone(),
        source,
    })?;
    let jobs = opts.jobs.max(1);
    let prlimit = opts.memory_limit.and_then(|_| find_in_path("prlimit"));
    let memory_limit = prlimit.as_ref().and(opts.memory_limit);
    // Each child may use the cores left over by the other jobs for its own parallel loops.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let child_threads = (cores / jobs).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| BatchError::Threads {
            jobs,
            reason: e.to_string(),
        })?;
    progress(Progress::Started {
        total: inputs.len(),
    });
    let done = std::sync::atomic::AtomicUsize::new(0);
    let parts: Vec<PartRecord> = pool.install(|| {
        inputs
            .par_iter()
            .map(|input| {
                let record = match opts.resume.then(|| completed_report(input, opts)).flatten() {
                    Some(report) => record_from_report(input, opts, &report, true),
                    None => run_part(input, opts, prlimit.as_deref(), child_threads),
                };
                let n = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
                progress(Progress::Finished {
                    done: n,
                    total: inputs.len(),
                    record: &record,
                });
                record
            })
            .collect()
    });
    let counts = Counts::of(&parts);
    Ok(Summary {
        schema: SCHEMA,
        shard: opts.shard.map(|s| s.to_string()),
        inputs: inputs_found,
        jobs,
        timeout_seconds: opts.timeout.map(|t| t.as_secs_f64()),
        memory_limit_bytes: memory_limit,
        options: SummaryOptions {
            part: opts.part.clone(),
            resume: opts.resume,
        },
        counts,
        seconds: started.elapsed().as_secs_f64(),
        parts,
    })
}
