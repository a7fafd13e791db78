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

use crate::error::{Error, Result};
pub use crate::pipeline::PartOptions;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// The schema name written into `summary.json`.
pub const SCHEMA: &str = "matrace.batch/1";

/// Default per-part time limit (seconds).
pub const DEFAULT_TIMEOUT_SECS: f64 = 300.0;

/// File extensions (lower case) a folder is searched for.
pub const EXTENSIONS: [&str; 4] = ["step", "stp", "igs", "iges"];

/// Bytes of a child's stderr kept for the error message (the end is kept).
const STDERR_KEEP: usize = 16 * 1024;

/// Longest error message in the summary (characters).
const ERROR_MAX_CHARS: usize = 2000;

/// One part to trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The file, as found (a folder argument joined with the path below it, or a file
    /// argument as given).
    pub path: PathBuf,
    /// Where its outputs go, relative to the output folder, without the output suffixes:
    /// `sub/part` for `DIR/sub/part.step`, `part` for a file argument `x/part.step`. When two
    /// inputs would get the same location (compared without regard to case, as some file
    /// systems do), each of them gets `-` and 8 hex digits of the FNV-1a hash of its path
    /// appended (`part-1f0c33ab`): the same input list always gives the same names.
    pub out_rel: PathBuf,
}

impl Input {
    /// The output file stem (`out_rel`'s last component).
    pub fn stem(&self) -> String {
        self.out_rel
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "part".into())
    }

    /// The folder of the outputs inside `out_dir`.
    pub fn out_dir(&self, out_dir: &Path) -> PathBuf {
        match self.out_rel.parent() {
            Some(p) => out_dir.join(p),
            None => out_dir.to_path_buf(),
        }
    }
}

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

/// True when `path`'s extension is one we read.
pub fn is_part_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// The inputs named by `args` (files, or folders searched recursively), deduplicated (by
/// canonical path) and sorted by output location, then path. A file argument is taken
/// whatever its extension; an argument that does not exist is an error, as is finding nothing.
/// The folder `out_dir` is not searched (an output folder inside an input folder holds
/// `.mat.step` files, which are not parts).
pub fn collect_inputs(args: &[PathBuf], out_dir: &Path) -> Result<Vec<Input>, BatchError> {
    let skip = std::fs::canonicalize(out_dir).ok();
    let mut found: Vec<(PathBuf, PathBuf)> = vec![]; // (path, out_rel before disambiguation)
    for arg in args {
        let meta = std::fs::metadata(arg).map_err(|_| BatchError::Missing(arg.clone()))?;
        if meta.is_dir() {
            let mut files = vec![];
            walk(arg, skip.as_deref(), &mut files)?;
            for f in files {
                let rel = f.strip_prefix(arg).unwrap_or(&f).with_extension("");
                found.push((f, rel));
            }
        } else {
            let name = arg.file_stem().map(PathBuf::from).unwrap_or("part".into());
            found.push((arg.clone(), name));
        }
    }
    if found.is_empty() {
        let names: Vec<String> = args.iter().map(|a| a.display().to_string()).collect();
        return Err(BatchError::NoInputs(names.join(", ")));
    }
    found.sort();
    let mut seen = BTreeSet::new();
    found.retain(|(p, _)| seen.insert(std::fs::canonicalize(p).unwrap_or_else(|_| p.clone())));
    let mut by_key: BTreeMap<String, usize> = BTreeMap::new();
    for (_, rel) in &found {
        *by_key.entry(collision_key(rel)).or_default() += 1;
    }
    let mut inputs: Vec<Input> = found
        .into_iter()
        .map(|(path, rel)| {
            let out_rel = if by_key[&collision_key(&rel)] > 1 {
                let name = rel.file_name().unwrap_or_default().to_string_lossy();
                let hash = fnv1a(path.to_string_lossy().as_bytes());
                rel.with_file_name(format!("{name}-{:08x}", hash as u32))
            } else {
                rel
            };
            Input { path, out_rel }
        })
        .collect();
    inputs.sort_by(|a, b| (&a.out_rel, &a.path).cmp(&(&b.out_rel, &b.path)));
    Ok(inputs)
}

/// Output locations that the file system might take for the same.
fn collision_key(rel: &Path) -> String {
    rel.to_string_lossy().to_lowercase()
}

/// 64-bit FNV-1a.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Appends the part files below `dir` (recursively, symlinked folders not followed, the
/// folder `skip` (canonical) left out).
fn walk(dir: &Path, skip: Option<&Path>, out: &mut Vec<PathBuf>) -> Result<(), BatchError> {
    if skip.is_some_and(|s| std::fs::canonicalize(dir).is_ok_and(|d| d == s)) {
        return Ok(());
    }
    let entries = std::fs::read_dir(dir).map_err(|source| BatchError::ReadDir {
        path: dir.into(),
        source,
    })?;
    let mut entries: Vec<_> = entries.filter_map(|e| e.ok()).collect();
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let path = e.path();
        let Ok(kind) = e.file_type() else { continue };
        if kind.is_dir() {
            walk(&path, skip, out)?;
        } else if is_part_file(&path) && std::fs::metadata(&path).is_ok_and(|m| m.is_file()) {
            out.push(path);
        }
    }
    Ok(())
}

/// `--shard K/N`: the inputs whose 0-based index `i` in the sorted list has `i mod N = K − 1`
/// (K counts from 1, as Slurm array indices and `parallel`'s `{%}` may be made to). The N
/// shards are disjoint, their union is every input, and their sizes differ by at most one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard number.
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = BatchError;
    fn from_str(s: &str) -> Result<Shard, BatchError> {
        let bad = || BatchError::Shard(s.to_string());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// This shard's inputs, in order.
    pub fn select(&self, inputs: Vec<Input>) -> Vec<Input> {
        inputs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % self.n == self.k - 1)
            .map(|(_, x)| x)
            .collect()
    }

    /// The file name of this shard's summary: `summary.K-of-N.json` (or `.csv`), so shards
    /// sharing one output folder do not overwrite each other's.
    pub fn summary_name(&self, ext: &str) -> String {
        format!("summary.{}-of-{}.{ext}", self.k, self.n)
    }
}

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

/// How a part ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PartStatus {
    /// Traced, every output written (and verified within the accuracy, when verifying).
    Ok,
    /// An error, a crash, or a verification above the accuracy: see the message.
    Failed,
    /// Killed at the time limit.
    Timeout,
}

impl PartStatus {
    pub fn as_str(&self) -> &'static str {
        match self {
            PartStatus::Ok => "ok",
            PartStatus::Failed => "failed",
            PartStatus::Timeout => "timeout",
        }
    }
}

/// One line of the summary.
#[derive(Clone, Debug, Serialize)]
pub struct PartRecord {
    /// The input file.
    pub part: String,
    /// Output location inside the output folder, without suffixes (`sub/part`).
    pub output: String,
    pub status: PartStatus,
    /// Not run: its outputs were complete (`--resume`); the numbers are its report's.
    pub resumed: bool,
    pub error: Option<String>,
    pub faces: Option<usize>,
    pub seams: Option<usize>,
    pub junctions: Option<usize>,
    /// The trace's own time (`stats.seconds` of its report) when it has one, else the
    /// wall-clock time of the failed attempt.
    pub seconds: f64,
    /// Worst verification error (mm) when verified.
    pub worst_error: Option<f64>,
    /// Output files written, relative to the output folder.
    pub outputs: Vec<String>,
}

/// Per-status counts.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Counts {
    pub ok: usize,
    pub failed: usize,
    pub timeout: usize,
    /// Parts skipped by `--resume` (counted in `ok`, or in `failed` when their report shows a
    /// verification above the accuracy).
    pub resumed: usize,
}

/// The options a batch ran with, as written into the summary.
#[derive(Clone, Debug, Serialize)]
pub struct SummaryOptions {
    #[serde(flatten)]
    pub part: PartOptions,
    pub resume: bool,
}

/// `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub schema: &'static str,
    /// `K/N` when sharded.
    pub shard: Option<String>,
    /// Inputs found before sharding.
    pub inputs: usize,
    pub jobs: usize,
    pub timeout_seconds: Option<f64>,
    /// The address-space limit actually applied to each part (`null`: none).
    pub memory_limit_bytes: Option<u64>,
    pub options: SummaryOptions,
    pub counts: Counts,
    /// Wall-clock seconds of the whole batch.
    pub seconds: f64,
    /// One record per part, in input order.
    pub parts: Vec<PartRecord>,
}

impl Summary {
    /// True when every part is `ok`.
    pub fn all_ok(&self) -> bool {
        self.counts.failed == 0 && self.counts.timeout == 0
    }
}

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
    let mut counts = Counts::default();
    for p in &parts {
        match p.status {
            PartStatus::Ok => counts.ok += 1,
            PartStatus::Failed => counts.failed += 1,
            PartStatus::Timeout => counts.timeout += 1,
        }
        counts.resumed += usize::from(p.resumed);
    }
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

/// The report of `input` if its outputs are complete and were made with `opts`: the report
/// `<stem>.mat.json` exists, parses, is not older than the input file, lists exactly the
/// outputs `opts` asks for, every one of them exists, and its options agree with `opts`
/// (verify, mesh, picture, `--accuracy`, `--fit-tol`; `--with-solid` is not recorded in reports and
/// not checked).
pub fn completed_report(input: &Input, opts: &BatchOptions) -> Option<serde_json::Value> {
    let dir = input.out_dir(&opts.out_dir);
    let stem = input.stem();
    let path = dir.join(format!("{stem}.mat.json"));
    let report_time = std::fs::metadata(&path).and_then(|m| m.modified()).ok()?;
    let input_time = std::fs::metadata(&input.path)
        .and_then(|m| m.modified())
        .ok()?;
    if input_time > report_time {
        return None;
    }
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).ok()?).ok()?;
    let outputs: Vec<&str> = report["outputs"]
        .as_array()?
        .iter()
        .map(|o| o.as_str())
        .collect::<Option<_>>()?;
    if outputs != opts.output_names(&stem) || !outputs.iter().all(|o| dir.join(o).is_file()) {
        return None;
    }
    let o = &report["options"];
    let same = o["verify"].as_bool() == Some(opts.part.verify)
        && (o["mesh_samples"].as_u64() != Some(0)) == opts.part.mesh
        && match opts.part.accuracy {
            Some(t) => o["accuracy_from"] == "--tol" && o["accuracy"].as_f64() == Some(t),
            None => o["accuracy_from"] != "--tol",
        }
        && opts.part.fit_tol.is_none_or(|t| {
            o["fit_tolerance"].as_f64() == Some(t.max(o["accuracy"].as_f64().unwrap_or(0.0)))
        });
    same.then_some(report)
}

/// The summary record of a part from its report.
fn record_from_report(
    input: &Input,
    opts: &BatchOptions,
    report: &serde_json::Value,
    resumed: bool,
) -> PartRecord {
    let stats = &report["stats"];
    let count = |v: &serde_json::Value| v.as_u64().map(|n| n as usize);
    let worst_error = stats["verification"].as_object().map(|v| {
        [
            "worst_distance_error",
            "worst_touch_error",
            "worst_touch_off_boundary",
        ]
        .iter()
        .filter_map(|k| v.get(*k).and_then(|x| x.as_f64()))
        .fold(0.0, f64::max)
    });
    let accuracy = report["options"]["accuracy"].as_f64().unwrap_or(0.0);
    let mut error = None;
    if let Some(w) = worst_error.filter(|w| *w > accuracy) {
        error = Some(format!(
            "{}: verification failed: worst error {w:.2e} mm exceeds the accuracy {accuracy:.2e} mm",
            input.path.display()
        ));
    }
    let dir_rel = input.out_rel.parent().unwrap_or(Path::new(""));
    PartRecord {
        part: input.path.display().to_string(),
        output: input.out_rel.display().to_string(),
        status: if error.is_some() {
            PartStatus::Failed
        } else {
            PartStatus::Ok
        },
        resumed,
        error,
        faces: report["model"]["faces"].as_array().map(|f| f.len()),
        seams: count(&stats["seams"]),
        junctions: count(&stats["junctions"]),
        seconds: stats["seconds"].as_f64().unwrap_or(0.0),
        worst_error,
        outputs: opts
            .output_names(&input.stem())
            .iter()
            .map(|o| dir_rel.join(o).display().to_string())
            .collect(),
    }
}

/// A record for a part that did not finish.
fn failed_record(input: &Input, status: PartStatus, error: String, seconds: f64) -> PartRecord {
    let mut error = error;
    if error.chars().count() > ERROR_MAX_CHARS {
        error = error.chars().take(ERROR_MAX_CHARS).collect::<String>() + " …";
    }
    PartRecord {
        part: input.path.display().to_string(),
        output: input.out_rel.display().to_string(),
        status,
        resumed: false,
        error: Some(error),
        faces: None,
        seams: None,
        junctions: None,
        seconds,
        worst_error: None,
        outputs: vec![],
    }
}

/// The child's command line: `[prlimit --as=BYTES] WORKER trace PART -o DIR --stem STEM …`.
fn part_command(
    input: &Input,
    opts: &BatchOptions,
    prlimit: Option<&Path>,
    child_threads: usize,
) -> Command {
    let mut args: Vec<OsString> = vec!["trace".into(), input.path.clone().into_os_string()];
    args.push("-o".into());
    args.push(input.out_dir(&opts.out_dir).into_os_string());
    args.push("--stem".into());
    args.push(input.stem().into());
    if let Some(t) = opts.part.accuracy {
        args.push("--accuracy".into());
        args.push(t.to_string().into());
    }
    if let Some(t) = opts.part.fit_tol {
        args.push("--fit-tol".into());
        args.push(t.to_string().into());
    }
    for (on, flag) in [
        (opts.part.verify, "--verify"),
        (!opts.part.mesh, "--no-mesh"),
        (!opts.part.picture, "--no-svg"),
        (opts.part.with_solid, "--with-solid"),
    ] {
        if on {
            args.push(flag.into());
        }
    }
    let mut cmd = match (prlimit, opts.memory_limit) {
        (Some(prlimit), Some(bytes)) => {
            let mut c = Command::new(prlimit);
            c.arg(format!("--as={bytes}")).arg(&opts.worker);
            c
        }
        _ => Command::new(&opts.worker),
    };
    cmd.args(args)
        .env("RAYON_NUM_THREADS", child_threads.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

/// Runs one part in a child process and makes its record.
fn run_part(
    input: &Input,
    opts: &BatchOptions,
    prlimit: Option<&Path>,
    child_threads: usize,
) -> PartRecord {
    let started = Instant::now();
    let mut child = match part_command(input, opts, prlimit, child_threads).spawn() {
        Ok(c) => c,
        Err(e) => {
            return failed_record(
                input,
                PartStatus::Failed,
                format!(
                    "{}: cannot start {}: {e}",
                    input.path.display(),
                    opts.worker.display()
                ),
                0.0,
            )
        }
    };
    let pid = child.id();
    let stderr = child.stderr.take().map(|mut pipe| {
        std::thread::spawn(move || {
            let mut kept = Vec::new();
            let mut buf = [0u8; 8192];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                kept.extend_from_slice(&buf[..n]);
                if kept.len() > 2 * STDERR_KEEP {
                    kept.drain(..kept.len() - STDERR_KEEP);
                }
            }
            kept
        })
    });
    let waited = wait_with_timeout(&mut child, opts.timeout);
    let seconds = started.elapsed().as_secs_f64();
    let stderr = stderr
        .and_then(|h| h.join().ok())
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    let record = match waited {
        Err(e) => failed_record(
            input,
            PartStatus::Failed,
            format!("{}: lost the child process: {e}", input.path.display()),
            seconds,
        ),
        Ok(None) => failed_record(
            input,
            PartStatus::Timeout,
            format!(
                "{}: killed after the time limit of {} s",
                input.path.display(),
                opts.timeout.map_or(0.0, |t| t.as_secs_f64())
            ),
            seconds,
        ),
        // 0: traced; 1: traced, verification above the accuracy (the report says so).
        Ok(Some(status)) if matches!(status.code(), Some(0 | 1)) => {
            let path = input
                .out_dir(&opts.out_dir)
                .join(format!("{}.mat.json", input.stem()));
            match std::fs::read(&path)
                .ok()
                .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
            {
                Some(report) => record_from_report(input, opts, &report, false),
                None => failed_record(
                    input,
                    PartStatus::Failed,
                    format!("{}: no readable report after the trace", path.display()),
                    seconds,
                ),
            }
        }
        Ok(Some(status)) => failed_record(
            input,
            PartStatus::Failed,
            child_failure(input, status, &stderr, opts.memory_limit.and(prlimit)),
            seconds,
        ),
    };
    if record.status != PartStatus::Ok {
        remove_temp_files(&input.out_dir(&opts.out_dir), &input.stem(), pid);
    }
    record
}

/// Waits for `child`; kills it at `timeout` and returns `None`.
fn wait_with_timeout(
    child: &mut std::process::Child,
    timeout: Option<Duration>,
) -> std::io::Result<Option<ExitStatus>> {
    let started = Instant::now();
    let mut nap = Duration::from_millis(1);
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(Some(status));
        }
        if timeout.is_some_and(|t| started.elapsed() >= t) {
            let _ = child.kill();
            child.wait()?;
            return Ok(None);
        }
        let mut sleep = nap;
        if let Some(t) = timeout {
            sleep = sleep.min(t.saturating_sub(started.elapsed()));
        }
        std::thread::sleep(sleep.max(Duration::from_micros(100)));
        nap = (nap * 2).min(Duration::from_millis(50));
    }
}

/// The error message of a child that ended with `status` (not 0 or 1).
fn child_failure(
    input: &Input,
    status: ExitStatus,
    stderr: &str,
    memory_limited: Option<&Path>,
) -> String {
    // The messages, without a backtrace and the notes about one.
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim_end)
        .take_while(|l| *l != "stack backtrace:")
        .filter(|l| !l.is_empty() && !l.starts_with("note: "))
        .collect();
    // `trace` reports an unusable part as one line that names the file (exit status 2).
    if status.code() == Some(2) {
        if let Some(l) = lines
            .iter()
            .rev()
            .find(|l| l.starts_with("matrace: error: "))
        {
            return l.trim_start_matches("matrace: error: ").to_string();
        }
    }
    let how = describe_exit(status);
    let oom = stderr.contains("memory allocation of");
    let mut msg = format!("{}: crashed ({how})", input.path.display());
    if oom {
        msg.push_str(if memory_limited.is_some() {
            ": out of memory (the per-part memory limit)"
        } else {
            ": out of memory"
        });
    }
    if !lines.is_empty() {
        msg.push_str(": ");
        msg.push_str(&lines.join(" | "));
    }
    msg
}

#[cfg(unix)]
fn describe_exit(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(c), _) => format!("exit status {c}"),
        (None, Some(s)) => format!("killed by signal {s}"),
        _ => status.to_string(),
    }
}

#[cfg(not(unix))]
fn describe_exit(status: ExitStatus) -> String {
    status.to_string()
}

/// Removes the temporary files `output::write_atomic` of process `pid` left for stem `stem`
/// (`.<stem>.<suffix>.<pid>.tmp`) when that process was killed or crashed mid-write.
fn remove_temp_files(dir: &Path, stem: &str, pid: u32) {
    let prefix = format!(".{stem}.");
    let suffix = format!(".{pid}.tmp");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(&prefix) && name.ends_with(&suffix) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// An executable `name` on the `PATH`.
pub fn find_in_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}

/// Physical memory in bytes (Linux `/proc/meminfo`), if known.
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Writes `summary.json` and `summary.csv` (or `summary.K-of-N.*` for a shard) into
/// `out_dir`, atomically; returns the JSON path.
pub fn write_summary(summary: &Summary, out_dir: &Path, shard: Option<Shard>) -> Result<PathBuf> {
    let name = |ext: &str| match shard {
        Some(s) => s.summary_name(ext),
        None => format!("summary.{ext}"),
    };
    let json_path = out_dir.join(name("json"));
    let json = serde_json::to_string_pretty(summary).map_err(|e| Error::Write {
        path: json_path.clone(),
        source: std::io::Error::other(e),
    })?;
    crate::export::write_atomic(&out_dir.join(name("csv")), summary_csv(summary).as_bytes())?;
    crate::export::write_atomic(&json_path, (json + "\n").as_bytes())?;
    Ok(json_path)
}

/// The CSV table: `part,status,error,faces,seams,junctions,seconds,worst_error,resumed,output`
/// (RFC 4180 quoting; empty cells for unknown numbers).
pub fn summary_csv(summary: &Summary) -> String {
    let mut s = String::from(
        "part,status,error,faces,seams,junctions,seconds,worst_error,resumed,output\n",
    );
    let num = |n: Option<usize>| n.map(|n| n.to_string()).unwrap_or_default();
    for p in &summary.parts {
        let cells = [
            csv_cell(&p.part),
            p.status.as_str().to_string(),
            csv_cell(p.error.as_deref().unwrap_or("")),
            num(p.faces),
            num(p.seams),
            num(p.junctions),
            format!("{:.3}", p.seconds),
            p.worst_error.map(|w| format!("{w:e}")).unwrap_or_default(),
            p.resumed.to_string(),
            csv_cell(&p.output),
        ];
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

fn csv_cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_are_disjoint_balanced_and_cover_everything() {
        let inputs: Vec<Input> = (0..11)
            .map(|i| Input {
                path: format!("p{i:02}.step").into(),
                out_rel: format!("p{i:02}").into(),
            })
            .collect();
        for n in 1..=5 {
            let mut all = vec![];
            let mut sizes = vec![];
            for k in 1..=n {
                let s = Shard { k, n }.select(inputs.clone());
                sizes.push(s.len());
                all.extend(s);
            }
            all.sort_by(|a, b| a.path.cmp(&b.path));
            assert_eq!(all, inputs, "n = {n}");
            assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        }
        assert_eq!(
            Shard { k: 2, n: 3 }.select(inputs.clone())[0].path,
            inputs[1].path
        );
    }

    #[test]
    fn shard_specs_parse() {
        assert_eq!("3/8".parse::<Shard>().unwrap(), Shard { k: 3, n: 8 });
        for bad in ["0/4", "5/4", "1/0", "1", "a/b", "1/2/3", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn csv_cells_are_quoted() {
        assert_eq!(csv_cell("a.step"), "a.step");
        assert_eq!(csv_cell("x, \"y\""), "\"x, \"\"y\"\"\"");
    }

    #[test]
    fn inputs_are_found_sorted_and_kept_apart() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in [
            "b/part.step",
            "a/part.STEP",
            "a/part.stp",
            "z.iges",
            "a/notes.txt",
        ] {
            let p = d.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, "x").unwrap();
        }
        let extra = d.join("b/part.step");
        let none = d.join("no-output-folder");
        let inputs = collect_inputs(&[d.to_path_buf(), extra], &none).unwrap();
        let rels: Vec<String> = inputs
            .iter()
            .map(|i| i.out_rel.display().to_string())
            .collect();
        // a/part.STEP and a/part.stp collide (hashed), b/part.step is found once, notes.txt
        // is not a part.
        assert_eq!(rels.len(), 4, "{rels:?}");
        assert!(rels[0].starts_with("a/part-") && rels[1].starts_with("a/part-"));
        assert_ne!(rels[0], rels[1]);
        assert_eq!(&rels[2..], ["b/part", "z"]);
        assert_eq!(inputs, collect_inputs(&[d.to_path_buf()], &none).unwrap());
        // An output folder inside the input folder is not searched.
        let with_b: Vec<Input> = collect_inputs(&[d.to_path_buf()], &d.join("b/.")).unwrap();
        assert_eq!(with_b.len(), 3);
        assert!(with_b.iter().all(|i| !i.out_rel.starts_with("b")));
        assert!(matches!(
            collect_inputs(&[d.join("a/notes.txt").with_extension("none")], &none),
            Err(BatchError::Missing(_))
        ));
        let empty = tempfile::tempdir().unwrap();
        assert!(matches!(
            collect_inputs(&[empty.path().to_path_buf()], &none),
            Err(BatchError::NoInputs(_))
        ));
    }
}
