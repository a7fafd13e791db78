//! `matrace` command line: thin glue around the library (argument parsing, printing, exit
//! codes). Exit status: 0 success, 1 a check of `trace --verify` or `verify` failed or
//! `batch` finished with some parts failed, 2 unusable input or arguments.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// mimalloc: reading a STEP file allocates tens of thousands of small objects (the parsed
/// records, truck's tables) and frees them again. With mimalloc instead of glibc's allocator,
/// repeated reads of the NIST parts in one process take 8–20 % less time; a single read in a
/// fresh process takes about the same (`docs/performance.md`).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "matrace",
    version,
    about = "Exact 3D medial axis transform of CAD solids"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Read a part and print its topology and edge/vertex classification.
    Inspect(InspectArgs),
    /// Trace the medial axis; write DIR/<stem>.mat.json (report), <stem>.mat.step (the seams as
    /// B-spline curves, the junctions as points), <stem>.sheets.obj (sheet mesh) and
    /// <stem>.mat.svg (picture).
    Trace(TraceCommand),
    /// Trace many parts, each in a process of its own, into OUTDIR (the outputs of
    /// DIR/sub/part.step go to OUTDIR/sub/part.*), with OUTDIR/summary.json and summary.csv.
    /// Exit status 1 when some part failed or timed out.
    Batch(BatchArgs),
    /// Check a report against its part, whatever run made it: every ball (centre inside, its
    /// nearest boundary at distance r, touching the boundary in 3 separate places along a seam,
    /// 4 at a junction, 2 for a degenerate piece) and the graph (no seam end open, junctions
    /// with their seams, Euler characteristics, every face and convex vertex reached), to the
    /// report's accuracy. Exit status 1 when a check fails.
    Verify(VerifyArgs),
}

#[derive(clap::Args)]
struct VerifyArgs {
    /// The part: STEP (.step, .stp) or IGES (.igs, .iges) file.
    part: PathBuf,
    /// Its report, <stem>.mat.json.
    report: PathBuf,
    /// Print the verification as JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Hold the report to this accuracy in mm instead of the one it claims.
    #[arg(long, value_name = "MM")]
    accuracy: Option<f64>,
}

#[derive(clap::Args)]
struct InspectArgs {
    /// STEP (.step, .stp) or IGES (.igs, .iges) file.
    part: PathBuf,
    /// Print the report's `input` and `model` objects as JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Angle (degrees) below which two faces meeting at an edge count as tangent.
    #[arg(long, default_value_t = matrace::classify::DEFAULT_ANGLE_TOL_DEG)]
    angle_tol: f64,
}

#[derive(clap::Args)]
struct TraceCommand {
    /// STEP (.step, .stp) or IGES (.igs, .iges) file.
    part: PathBuf,
    /// Output folder (created if missing).
    #[arg(short = 'o', long = "out", default_value = ".")]
    out: PathBuf,
    #[command(flatten)]
    trace: TraceArgs,
    /// Output file stem (default: the part's file name without extension). Used by
    /// `batch` to keep parts with the same name apart.
    #[arg(long, hide = true)]
    stem: Option<String>,
}

#[derive(clap::Args)]
struct BatchArgs {
    /// Folders (searched recursively for .step/.stp/.igs/.iges) and files.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Output folder (created if missing).
    #[arg(short = 'o', long = "out")]
    out: PathBuf,
    /// Parts traced at once (default: the number of cores).
    #[arg(short = 'j', long)]
    jobs: Option<usize>,
    /// Per-part time limit in seconds (fractions allowed; 0: none); a part over it is
    /// killed and recorded as `timeout`.
    #[arg(long, default_value_t = matrace::batch::DEFAULT_TIMEOUT_SECS)]
    timeout: f64,
    /// Per-part memory (address-space) limit in MiB, through `prlimit` when installed
    /// (default: physical memory / jobs; 0: none).
    #[arg(long)]
    max_memory: Option<u64>,
    /// Skip parts whose outputs are complete and made with the same options; failed
    /// parts are tried again.
    #[arg(long)]
    resume: bool,
    /// Trace only the K-th of N slices of the sorted inputs (K from 1): inputs number
    /// K, K+N, K+2N, … The summary is then OUTDIR/summary.K-of-N.json/.csv.
    #[arg(long, value_name = "K/N")]
    shard: Option<matrace::batch::Shard>,
    #[command(flatten)]
    trace: TraceArgs,
}

/// What to compute and write for each part: shared by `trace` and `batch`.
#[derive(clap::Args)]
struct TraceArgs {
    /// Accuracy in mm: every output ball is medial to within it (default: 1e-6 × the part's
    /// bounding-box diagonal). `--tol` is an alias.
    #[arg(long, visible_alias = "tol", value_name = "MM")]
    accuracy: Option<f64>,
    /// Check every output ball against the definition and the medial axis's graph, as
    /// `matrace verify` does. `trace` exits 1, and `batch` counts the part as failed, when a
    /// check fails.
    #[arg(long)]
    verify: bool,
    /// Do not write the sheet mesh <stem>.sheets.obj.
    #[arg(long)]
    no_mesh: bool,
    /// Do not write the picture <stem>.mat.svg.
    #[arg(long)]
    no_svg: bool,
    /// Largest distance in mm from a traced point to its seam's B-spline curve in the
    /// .mat.step file, and largest radius error (default: 1e-4 × the part's diagonal; never
    /// below the accuracy).
    #[arg(long, value_name = "MM")]
    fit_tol: Option<f64>,
    /// Include the input part in the .mat.step file (one open shows part and MAT).
    #[arg(long)]
    with_solid: bool,
}

fn main() -> ExitCode {
    matrace::panic_guard::install_quiet_hook();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("matrace: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Inspect(args) => inspect(args),
        Command::Trace(args) => trace(args),
        Command::Batch(args) => batch(args),
        Command::Verify(args) => verify(args),
    }
}

/// `matrace verify`: exit 1 when any check fails.
fn verify(args: VerifyArgs) -> anyhow::Result<ExitCode> {
    if let Some(a) = args.accuracy {
        if !(a.is_finite() && a > 0.0) {
            anyhow::bail!("--accuracy must be a positive length in mm, got {a}");
        }
    }
    let v = matrace::pipeline::verify_report(&args.part, &args.report, args.accuracy)?;
    if args.json {
        emit(&format!("{}\n", serde_json::to_string_pretty(&v)?));
    } else {
        emit(&verification_text(
            &format!("{} against {}", args.report.display(), args.part.display()),
            &v,
        ));
    }
    Ok(if v.ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// A verification for people: the verdict, every check's count, the worst errors and the
/// first failures.
fn verification_text(what: &str, v: &matrace::medial::Verification) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let verdict = if v.ok { "ok" } else { "FAILED" };
    let _ = writeln!(
        s,
        "{what}: {verdict}: {} balls, worst error {:.2e} mm{} (accuracy {:.2e} mm)",
        v.balls,
        v.worst(),
        v.worst_at
            .as_deref()
            .map(|a| format!(" at {a}"))
            .unwrap_or_default(),
        v.accuracy
    );
    let checks: Vec<String> = v
        .checks
        .iter()
        .map(|(k, c)| format!("{k} {}/{}", c.checked - c.failed, c.checked))
        .collect();
    let _ = writeln!(s, "  checks passed: {}", checks.join(", "));
    if v.held_to_gap > 0 {
        let _ = writeln!(
            s,
            "  {} errors beyond the accuracy, up to {:.2e} mm, are within the file's own gaps \
             (edges written off their faces' surfaces) and passed",
            v.held_to_gap, v.largest_gap_held
        );
    }
    for w in &v.euler_withheld {
        let _ = writeln!(s, "  Euler characteristic not compared: {w}");
    }
    for f in v.failures.iter().take(20) {
        let _ = writeln!(s, "  {f}");
    }
    if v.failures.len() > 20 {
        let _ = writeln!(
            s,
            "  … {} failures in all",
            v.checks.values().map(|c| c.failed).sum::<usize>()
        );
    }
    s
}

/// `matrace inspect`: the table, or the report's `input` and `model` as JSON.
fn inspect(args: InspectArgs) -> anyhow::Result<ExitCode> {
    let angle_tol = args.angle_tol;
    if !(angle_tol.is_finite() && angle_tol > 0.0 && angle_tol < 90.0) {
        anyhow::bail!("--angle-tol must be between 0 and 90 degrees, got {angle_tol}");
    }
    let model = matrace::read_model(&args.part)?;
    let opts = matrace::ClassifyOptions {
        angle_tol: angle_tol.to_radians(),
        ..Default::default()
    };
    let class = matrace::classify(&model, &opts);
    let report = matrace::export::report::Report::new(&model, &class);
    warn_repairs(&args.part, &report.input.warnings);
    if args.json {
        emit(&format!("{}\n", serde_json::to_string_pretty(&report)?));
    } else {
        emit(&matrace::export::report::render_table(&report));
    }
    Ok(ExitCode::SUCCESS)
}

/// One line on stderr for what the reader repaired or ignored in `part`, if anything.
fn warn_repairs(part: &std::path::Path, warnings: &[matrace::model::ReadWarning]) {
    if !warnings.is_empty() {
        eprintln!(
            "matrace: warning: {}: read with {} repair(s) or omission(s): {}",
            part.display(),
            warnings.iter().map(|w| w.count).sum::<usize>(),
            matrace::model::warnings::summary_line(warnings)
        );
    }
}

/// `matrace trace`: one part; exit 1 when a check of `--verify` fails.
fn trace(args: TraceCommand) -> anyhow::Result<ExitCode> {
    args.trace.check()?;
    let opts = matrace::pipeline::RunOptions {
        stem: args.stem,
        ..matrace::pipeline::RunOptions::new(args.out, args.trace.part_options())
    };
    let outcome = matrace::pipeline::trace_part(&args.part, &opts)?;
    warn_repairs(&args.part, &outcome.report.input.warnings);
    emit(&summary(&args.part, &outcome));
    if outcome.verification_failed() {
        let v = outcome.report.stats.verification.as_ref().unwrap();
        let failed: Vec<String> = v
            .failed_checks()
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        eprintln!(
            "matrace: verification failed: {}{}",
            failed.join(", "),
            v.failures
                .first()
                .map(|f| format!(" (first: {f})"))
                .unwrap_or_default()
        );
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

/// `matrace batch`: many parts; exit 1 when some part failed or timed out.
fn batch(args: BatchArgs) -> anyhow::Result<ExitCode> {
    let opts = args.batch_options()?;
    let found = matrace::batch::collect_inputs(&args.inputs, &opts.out_dir)?;
    let n_found = found.len();
    let parts = match args.shard {
        Some(s) => s.select(found),
        None => found,
    };
    let progress = progress::Progress::new();
    let summary = matrace::batch::run_batch(&parts, n_found, &opts, &|e| progress.show(&e))?;
    progress.finish();
    let path = matrace::batch::write_summary(&summary, &opts.out_dir, args.shard)?;
    let c = &summary.counts;
    emit(&format!(
        "{} parts: {} ok ({} resumed), {} failed, {} timed out, {:.1} s -> {}\n",
        summary.parts.len(),
        c.ok,
        c.resumed,
        c.failed,
        c.timeout,
        summary.seconds,
        path.display()
    ));
    for (n, by, what) in [
        (c.open_ends, &c.open_ends_by_reason, "open seam ends"),
        (
            c.degenerate_open_ends,
            &c.degenerate_open_ends_by_reason,
            "open degenerate-curve ends",
        ),
    ] {
        if n > 0 {
            let why: Vec<String> = by.iter().map(|(why, n)| format!("{why} {n}")).collect();
            emit(&format!("{n} {what}: {}\n", why.join(", ")));
        }
    }
    Ok(if summary.all_ok() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

impl BatchArgs {
    /// The library's batch options, the arguments checked.
    fn batch_options(&self) -> anyhow::Result<matrace::batch::BatchOptions> {
        self.trace.check()?;
        let timeout = self.timeout;
        if !(timeout.is_finite() && timeout >= 0.0) {
            anyhow::bail!("--timeout must be a number of seconds >= 0, got {timeout}");
        }
        if self.jobs == Some(0) {
            anyhow::bail!("-j must be at least 1");
        }
        let worker = std::env::current_exe()?;
        let mut opts = matrace::batch::BatchOptions::new(self.out.clone(), worker);
        opts.jobs = self.jobs.unwrap_or(opts.jobs);
        opts.timeout = (timeout > 0.0).then(|| std::time::Duration::from_secs_f64(timeout));
        opts.memory_limit = match self.max_memory {
            Some(0) => None,
            Some(mib) => Some(mib.saturating_mul(1 << 20)),
            None => matrace::batch::physical_memory().map(|m| (m / opts.jobs as u64).max(1 << 30)),
        };
        opts.shard = self.shard;
        opts.resume = self.resume;
        opts.part = self.trace.part_options();
        Ok(opts)
    }
}

/// Checks `--accuracy` and `--fit-tol`.
impl TraceArgs {
    /// Refuses lengths that are not positive and finite.
    fn check(&self) -> anyhow::Result<()> {
        for (name, t) in [("--accuracy", self.accuracy), ("--fit-tol", self.fit_tol)] {
            if let Some(t) = t {
                if !(t.is_finite() && t > 0.0) {
                    anyhow::bail!("{name} must be a positive length in mm, got {t}");
                }
            }
        }
        Ok(())
    }

    /// The library's per-part options.
    fn part_options(&self) -> matrace::pipeline::PartOptions {
        matrace::pipeline::PartOptions {
            accuracy: self.accuracy,
            fit_tol: self.fit_tol,
            verify: self.verify,
            mesh: !self.no_mesh,
            picture: !self.no_svg,
            with_solid: self.with_solid,
        }
    }
}

/// Batch progress on stderr: a bar on a terminal, else one line per finished part.
mod progress {
    use indicatif::{ProgressBar, ProgressStyle};
    use matrace::batch::{PartRecord, PartStatus, Progress as Event};
    use std::io::IsTerminal;
    use std::sync::OnceLock;

    pub struct Progress {
        terminal: bool,
        bar: OnceLock<ProgressBar>,
    }

    impl Progress {
        pub fn new() -> Progress {
            Progress {
                terminal: std::io::stderr().is_terminal(),
                bar: OnceLock::new(),
            }
        }

        pub fn show(&self, event: &Event) {
            match event {
                Event::Started { total } if self.terminal => {
                    let bar = ProgressBar::new(*total as u64);
                    if let Ok(style) = ProgressStyle::with_template(
                        "{elapsed_precise} [{bar:30}] {pos}/{len} (eta {eta}) {wide_msg}",
                    ) {
                        bar.set_style(style.progress_chars("=> "));
                    }
                    let _ = self.bar.set(bar);
                }
                Event::Started { .. } => {}
                Event::Finished {
                    done,
                    total,
                    record,
                } => match self.bar.get() {
                    Some(bar) => {
                        bar.inc(1);
                        bar.set_message(record.part.clone());
                        if record.status != PartStatus::Ok {
                            bar.println(line(*done, *total, record));
                        }
                    }
                    None => eprintln!("{}", line(*done, *total, record)),
                },
            }
        }

        pub fn finish(&self) {
            if let Some(bar) = self.bar.get() {
                bar.finish_and_clear();
            }
        }
    }

    fn line(done: usize, total: usize, r: &PartRecord) -> String {
        let status = r.status.as_str();
        match &r.error {
            // The message names the file.
            Some(e) => format!("[{done}/{total}] {status:<7} {e}"),
            None => format!(
                "[{done}/{total}] {status:<7} {}: {} seams, {} junctions, {:.2} s{}",
                r.part,
                r.seams.unwrap_or(0),
                r.junctions.unwrap_or(0),
                r.seconds,
                if r.resumed { " (resumed)" } else { "" }
            ),
        }
    }
}

/// Writes to stdout; a closed pipe (`matrace … | head`) is not an error worth a panic.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// The human summary of a traced part (stdout).
fn summary(part: &std::path::Path, outcome: &matrace::pipeline::PartOutcome) -> String {
    use std::fmt::Write;
    let r = &outcome.report;
    let st = &r.stats;
    let t = &st.timings;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{}: {} seams ({} open), {} junctions, {} sheets, {} degenerate ({} open ends), {} points, {:.3} s, worst residual {:.2e} mm -> {}",
        part.display(),
        st.seams,
        st.open_ends,
        st.junctions,
        st.sheets,
        st.degenerate,
        st.degenerate_open_ends,
        st.points,
        st.seconds,
        st.worst_residual,
        outcome.report_path.display()
    );
    let _ = writeln!(
        s,
        "  time: read {:.3} s, classify {:.3}, trace {:.3}, sheets {:.3}, fit+step {:.3}, mesh {:.3}, picture {:.3}, verify {:.3}",
        t.read, t.classify, t.trace, t.sheets, t.fit, t.mesh, t.picture, t.verify
    );
    for e in &r.mat.topology.euler {
        match (e.mat_euler, &e.unknown) {
            (Some(chi), _) => {
                let _ = writeln!(
                    s,
                    "  solid {}: Euler characteristic {chi} (solid {})",
                    e.solid, e.solid_euler
                );
            }
            (None, why) => {
                let _ = writeln!(
                    s,
                    "  solid {}: Euler characteristic not counted: {} (solid {})",
                    e.solid,
                    why.as_deref().unwrap_or("unknown"),
                    e.solid_euler
                );
            }
        }
    }
    if let Some(f) = &r.mat.fit {
        let _ = writeln!(
            s,
            "  fitted {} seams with {} control points: worst error {:.2e} mm, radius {:.2e} mm (fit tolerance {:.2e})",
            r.mat.seams.len(),
            f.control_points,
            f.worst_error,
            f.worst_radius_error,
            f.tol
        );
    }
    if st.mesh_triangles > 0 {
        let _ = writeln!(s, "  sheet mesh: {} triangles", st.mesh_triangles);
    }
    let _ = writeln!(s, "  wrote {}", r.outputs.join(", "));
    if let Some(v) = &st.verification {
        s.push_str(&verification_text("verified", v));
    }
    s
}
