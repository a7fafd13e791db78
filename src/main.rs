//! `matrace` command line: thin glue around the library (argument parsing, printing, exit
//! codes). Exit status: 0 success, 2 unusable input or arguments.

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
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("matrace: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
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
            Ok(())
        }
    }
}
