//! `matrace` command line: thin glue around the library (argument parsing, printing, exit
//! codes). Exit status: 0 success, 1 `trace --verify` found an error above the accuracy,
//! 2 unusable input or arguments.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

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
    Inspect {
        /// STEP file (.step, .stp).
        part: PathBuf,
        /// Print the report's `input` and `model` objects as JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Angle (degrees) below which two faces meeting at an edge count as tangent.
        #[arg(long, default_value_t = matrace::classify::DEFAULT_ANGLE_TOL_DEG)]
        angle_tol: f64,
    },
    /// Trace the medial seams and junctions and write DIR/<stem>.mat.json and
    /// DIR/<stem>.mat.step (the seams as B-spline curves, the junctions as points).
    Trace {
        /// STEP file (.step, .stp).
        part: PathBuf,
        /// Output folder (created if missing).
        #[arg(short = 'o', long = "out", default_value = ".")]
        out: PathBuf,
        /// Accuracy in mm (default: 1e-6 × the part's bounding-box diagonal).
        #[arg(long)]
        tol: Option<f64>,
        /// Check every output ball against the definition (nearest boundary at distance r,
        /// touch points on the boundary at r); exit status 1 when the worst error exceeds the
        /// accuracy.
        #[arg(long)]
        verify: bool,
        /// Largest distance in mm from a traced point to its seam's B-spline curve in the
        /// .mat.step file, and largest radius error (default: 1e-4 × the part's diagonal;
        /// never below the accuracy).
        #[arg(long)]
        fit_tol: Option<f64>,
        /// Include the input part in the .mat.step file (one open shows part and MAT).
        #[arg(long)]
        with_solid: bool,
    },
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
        Command::Inspect {
            part,
            json,
            angle_tol,
        } => {
            if !(angle_tol.is_finite() && angle_tol > 0.0 && angle_tol < 90.0) {
                anyhow::bail!("--angle-tol must be between 0 and 90 degrees, got {angle_tol}");
            }
            let model = matrace::read_model(&part)?;
            let opts = matrace::ClassifyOptions {
                angle_tol: angle_tol.to_radians(),
                ..Default::default()
            };
            let class = matrace::classify(&model, &opts);
            let report = matrace::report::Report::new(&model, &class);
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", matrace::report::render_table(&report));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Trace {
            part,
            out,
            tol,
            verify,
            fit_tol,
            with_solid,
        } => {
            let started = std::time::Instant::now();
            let model = matrace::read_model(&part)?;
            let class = matrace::classify(&model, &Default::default());
            let mut opts = matrace::medial::TraceOptions::for_model(&model);
            if let Some(t) = tol {
                if !(t.is_finite() && t > 0.0) {
                    anyhow::bail!("--tol must be a positive length in mm, got {t}");
                }
                opts.accuracy = t;
            }
            let boundary = matrace::geom::Boundary::new(&model);
            let mat = matrace::medial::trace_with_boundary(&model, &boundary, &class, &opts);
            let seconds = started.elapsed().as_secs_f64();
            let mut report =
                matrace::report::TraceReport::new(&model, &class, &mat, opts.accuracy, seconds);
            let verification = verify.then(|| matrace::medial::verify(&model, &boundary, &mat));
            report.stats.verification = verification.clone();
            let fitted = std::time::Instant::now();
            let mut fit_opts =
                matrace::output::fit::FitOptions::for_model(model.diagonal(), opts.accuracy);
            if let Some(t) = fit_tol {
                if !(t.is_finite() && t > 0.0) {
                    anyhow::bail!("--fit-tol must be a positive length in mm, got {t}");
                }
                fit_opts.tol = t.max(opts.accuracy);
            }
            let fits = matrace::output::fit::fit_mat(&mat, &fit_opts);
            let fit_report = matrace::output::fit::FitReport::new(&mat, &fits, fit_opts.tol);
            report.mat.fit = Some(fit_report.clone());
            std::fs::create_dir_all(&out).map_err(|e| {
                anyhow::anyhow!("{}: cannot create output folder: {e}", out.display())
            })?;
            let stem = part.file_stem().and_then(|s| s.to_str()).unwrap_or("part");
            let path = out.join(format!("{stem}.mat.json"));
            std::fs::write(&path, serde_json::to_string_pretty(&report)?)
                .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", path.display()))?;
            let step_path = out.join(format!("{stem}.mat.step"));
            matrace::output::step::write_mat_step(
                &step_path,
                stem,
                &mat,
                &fits,
                with_solid.then_some(part.as_path()),
            )?;
            let fit_seconds = fitted.elapsed().as_secs_f64();
            let open = mat
                .seams
                .iter()
                .filter(|s| {
                    s.ends
                        .iter()
                        .any(|e| matches!(e, matrace::medial::SeamEnd::Open(_)))
                })
                .count();
            println!(
                "{}: {} seams ({} open), {} junctions, {} degenerate, {} points, {:.3} s, worst residual {:.2e} mm -> {}",
                part.display(),
                mat.seams.len(),
                open,
                mat.junctions.len(),
                mat.degenerate.len(),
                mat.stats.points,
                seconds,
                mat.stats.worst_residual,
                path.display()
            );
            println!(
                "fitted {} seams with {} control points: worst error {:.2e} mm, radius {:.2e} mm (fit tolerance {:.2e}), {:.3} s -> {}",
                fits.len(),
                fit_report.control_points,
                fit_report.worst_error,
                fit_report.worst_radius_error,
                fit_opts.tol,
                fit_seconds,
                step_path.display()
            );
            if let Some(v) = verification {
                println!(
                    "verified {} balls: worst error {:.2e} mm{} (distance {:.2e}, touch {:.2e}, touch off boundary {:.2e}; accuracy {:.2e})",
                    v.balls,
                    v.worst(),
                    v.worst_at.as_deref().map(|a| format!(" at {a}")).unwrap_or_default(),
                    v.worst_distance_error,
                    v.worst_touch_error,
                    v.worst_touch_off_boundary,
                    opts.accuracy
                );
                if v.worst() > opts.accuracy {
                    eprintln!("matrace: verification failed: worst error {:.2e} mm exceeds the accuracy {:.2e} mm", v.worst(), opts.accuracy);
                    return Ok(ExitCode::from(1));
                }
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
