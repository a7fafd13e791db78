//! Many parts at once: `matrace batch DIR|FILES… -o OUTDIR`.
//!
//! The steps, each a function here so the binary stays glue:
//! 1. [`collect_inputs`]: folders are searched recursively for `.step`/`.stp`/`.igs`/`.iges`
//!    (any case); the inputs are deduplicated and sorted, and each gets its output location
//!    ([`Input::out_rel`], see there for how names are kept apart).
//! 2. [`Shard::select`]: `--shard K/N` keeps every N-th input, so N machines share a library.
//! 3. [`run_batch`]: each part runs in a child process of its own (the `matrace` executable's
//!    `trace` command, [`BatchOptions::worker`]), up to `jobs` at once on a rayon pool. A
//!    child is killed when it exceeds the time limit and, where `prlimit` exists, it cannot
//!    map more than the memory limit; a panic, abort, stack overflow or allocation failure in
//!    one part therefore ends that child only, and the batch records it and goes on. With
//!    `resume`, parts whose outputs are complete are not run again ([`completed_report`]).
//! 4. [`write_summary`]: `summary.json` (schema [`SCHEMA`]) and `summary.csv`, one record per
//!    part in input order, written atomically.
//!
//! Determinism: every part's outputs come from one child that sees only that part, so they do
//! not depend on `jobs` (nor on the child's own thread count: its parallel loops collect in
//! order); the summary lists parts in input order. Only timings differ between runs.
//!
//! The library does not print: progress goes to a callback ([`Progress`]).

mod child;
mod error;
mod inputs;
mod options;
mod resume;
mod run;
mod shard;
mod summary;

pub use child::{find_in_path, physical_memory};
pub use error::BatchError;
pub use inputs::{collect_inputs, is_part_file, Input, EXTENSIONS};
pub use options::{BatchOptions, PartOptions, DEFAULT_TIMEOUT_SECS};
pub use resume::completed_report;
pub use run::{run_batch, Progress};
pub use shard::Shard;
pub use summary::{
    summary_csv, write_summary, Counts, PartRecord, PartStatus, Summary, SummaryOptions, SCHEMA,
};
