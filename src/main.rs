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
        /// STEP (.step, .stp) or IGES (.igs, .iges) file.
        part: PathBuf,
        /// Print the report's `input` and `model` objects as JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Angle (degrees) below which two faces meeting at an edge count as tangent.
        #[arg(long, default_value_t = matrace::classify::DEFAULT_ANGLE_TOL_DEG)]
        angle_tol: f64,
    },
    /// Trace the medial axis; write DIR/<stem>.mat.json (report), <stem>.mat.step (the seams as
    /// B-spline curves, the junctions as points), <stem>.sheets.obj (sheet mesh) and
    /// <stem>.mat.svg (picture).
    Trace {
        /// STEP (.step, .stp) or IGES (.igs, .iges) file.
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
        /// Do not write the sheet mesh <stem>.sheets.obj.
        #[arg(long)]
        no_mesh: bool,
        /// Do not write the picture <stem>.mat.svg.
        #[arg(long)]
        no_svg: bool,
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
                emit(&format!("{}\n", serde_json::to_string_pretty(&report)?));
            } else {
                emit(&matrace::report::render_table(&report));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Trace {
            part,
            out,
            tol,
            verify,
            no_mesh,
            no_svg,
            fit_tol,
            with_solid,
        } => {
            if let Some(t) = tol {
                if !(t.is_finite() && t > 0.0) {
                    anyhow::bail!("--tol must be a positive length in mm, got {t}");
                }
            }
            if let Some(t) = fit_tol {
                if !(t.is_finite() && t > 0.0) {
                    anyhow::bail!("--fit-tol must be a positive length in mm, got {t}");
                }
            }
            let opts = matrace::run::RunOptions {
                tol,
                fit_tol,
                with_solid,
                verify,
                mesh_samples: if no_mesh {
                    0
                } else {
                    matrace::medial::sheet_mesh::DEFAULT_SAMPLES
                },
                picture: !no_svg,
                ..matrace::run::RunOptions::new(out)
            };
            let outcome = matrace::run::trace_part(&part, &opts)?;
            emit(&summary(&part, &outcome));
            if outcome.verification_failed() {
                let v = outcome.report.stats.verification.as_ref().unwrap();
                eprintln!(
                    "matrace: verification failed: worst error {:.2e} mm exceeds the accuracy {:.2e} mm",
                    v.worst(),
                    outcome.report.options.accuracy
                );
                return Ok(ExitCode::from(1));
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Writes to stdout; a closed pipe (`matrace … | head`) is not an error worth a panic.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// The human summary of a traced part (stdout).
fn summary(part: &std::path::Path, outcome: &matrace::run::PartOutcome) -> String {
    use std::fmt::Write;
    let r = &outcome.report;
    let st = &r.stats;
    let t = &st.timings;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{}: {} seams ({} open), {} junctions, {} sheets, {} degenerate, {} points, {:.3} s, worst residual {:.2e} mm -> {}",
        part.display(),
        st.seams,
        st.open_ends,
        st.junctions,
        st.sheets,
        st.degenerate,
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
        let _ = writeln!(
            s,
            "verified {} balls: worst error {:.2e} mm{} (distance {:.2e}, touch {:.2e}, touch off boundary {:.2e}; accuracy {:.2e})",
            v.balls,
            v.worst(),
            v.worst_at.as_deref().map(|a| format!(" at {a}")).unwrap_or_default(),
            v.worst_distance_error,
            v.worst_touch_error,
            v.worst_touch_off_boundary,
            r.options.accuracy
        );
    }
    s
}
