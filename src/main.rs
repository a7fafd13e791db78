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
    /// Trace the medial seams and junctions and write DIR/<stem>.mat.json and the picture
    /// DIR/<stem>.mat.svg.
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
            std::fs::create_dir_all(&out).map_err(|e| {
                anyhow::anyhow!("{}: cannot create output folder: {e}", out.display())
            })?;
            let stem = part.file_stem().and_then(|s| s.to_str()).unwrap_or("part");
            let path = out.join(format!("{stem}.mat.json"));
            matrace::output::write_atomic(
                &path,
                serde_json::to_string_pretty(&report)?.as_bytes(),
            )?;
            // The sheets' geometry, as a triangle mesh (OBJ), next to the report.
            let sheets = matrace::medial::sheets(&model, &class, &mat);
            let mesh = matrace::medial::sheet_mesh(
                &model,
                &boundary,
                &class,
                &sheets,
                &matrace::medial::MeshOptions::new(opts.accuracy),
            );
            let obj_path = out.join(format!("{stem}.sheets.obj"));
            matrace::output::write_atomic(
                &obj_path,
                mesh.to_obj(&part.display().to_string()).as_bytes(),
            )?;
            let svg_opts = matrace::output::svg::SvgOptions {
                title: part
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                accuracy: Some(opts.accuracy),
                ..Default::default()
            };
            let svg = matrace::output::svg::render_svg(&model, &class, &mat, &svg_opts);
            matrace::output::svg::write_svg(&out.join(format!("{stem}.mat.svg")), &svg)?;
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
            for e in &report.mat.topology.euler {
                let sheets = report
                    .mat
                    .sheets
                    .iter()
                    .filter(|s| s.solid == e.solid)
                    .count();
                match (e.mat_euler, &e.unknown) {
                    (Some(chi), _) => println!(
                        "solid {}: {sheets} sheets; Euler characteristic {chi} (solid {})",
                        e.solid, e.solid_euler
                    ),
                    (None, why) => println!(
                        "solid {}: {sheets} sheets; Euler characteristic not counted: {} (solid {})",
                        e.solid,
                        why.as_deref().unwrap_or("unknown"),
                        e.solid_euler
                    ),
                }
            }
            println!(
                "sheet mesh: {} triangles on {} sheets -> {}",
                mesh.triangles(),
                mesh.parts.len(),
                obj_path.display()
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
