//! One part through the whole pipeline: read, classify, trace, sheets, sheet mesh, picture,
//! verification, and the outputs written atomically beside each other. The `trace` command
//! and the batch runner both call [`trace_part`]; neither prints from here.

use crate::classify::Classification;
use crate::error::{Error, Result};
use crate::export::report::{OptionsReport, Timings, TraceReport};
use crate::medial::MedialAxis;
use crate::model::{Model, Tolerances};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The choices made for every part, the same for `matrace trace` and for each part of a
/// `matrace batch` (which passes them on to its workers and records them in its summary).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PartOptions {
    /// Output accuracy in mm; `None`: the default, 1e-6 × the part's bounding-box diagonal.
    /// (`tol` in the batch summary, the option's name when summaries began.)
    #[serde(rename = "tol")]
    pub accuracy: Option<f64>,
    /// Fit tolerance in mm for the seams' B-splines; `None`: 1e-4 × the diagonal (never
    /// below the accuracy).
    pub fit_tol: Option<f64>,
    /// Check every ball against the definition.
    pub verify: bool,
    /// Write the sheet mesh `<stem>.sheets.obj`.
    pub mesh: bool,
    /// Write the picture `<stem>.mat.svg`.
    pub picture: bool,
    /// Copy the input part into `<stem>.mat.step`.
    pub with_solid: bool,
}

impl Default for PartOptions {
    /// Every output, default tolerances, no verification.
    fn default() -> PartOptions {
        PartOptions {
            accuracy: None,
            fit_tol: None,
            verify: false,
            mesh: true,
            picture: true,
            with_solid: false,
        }
    }
}

/// What to compute and write for a part, and where.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Folder for the outputs (created if missing).
    pub out_dir: PathBuf,
    pub part: PartOptions,
    /// Grid points for the sheet mesh, when `part.mesh`.
    pub mesh_samples: usize,
    /// File stem of the outputs; `None`: the part's file name without its extension
    /// ([`stem`]). The batch runner sets it when two inputs would share one.
    pub stem: Option<String>,
}

impl RunOptions {
    /// `part` into `out_dir`, with the default mesh density.
    pub fn new(out_dir: impl Into<PathBuf>, part: PartOptions) -> RunOptions {
        RunOptions {
            out_dir: out_dir.into(),
            part,
            mesh_samples: crate::medial::sheet_mesh::DEFAULT_SAMPLES,
            stem: None,
        }
    }

    /// Sheet-mesh grid points; 0 when no mesh is wanted.
    pub fn mesh_points(&self) -> usize {
        if self.part.mesh {
            self.mesh_samples
        } else {
            0
        }
    }
}

/// The result of one part: the report (as written) and where the outputs went.
#[derive(Clone, Debug)]
pub struct PartOutcome {
    pub report: TraceReport,
    /// `<stem>.mat.json`.
    pub report_path: PathBuf,
    /// Every file written, the report last.
    pub written: Vec<PathBuf>,
}

impl PartOutcome {
    /// True when a verification ran and some check failed.
    pub fn verification_failed(&self) -> bool {
        self.report
            .stats
            .verification
            .as_ref()
            .is_some_and(|v| !v.ok)
    }
}

/// `matrace verify`: checks the report at `report` against the part `part`, whatever run made
/// it: every ball and the graph, to `accuracy` when given, else to the accuracy the report
/// claims ([`crate::medial::verify`]). An error when the part cannot be read or the report is
/// not one; a failed check is in the [`Verification`](crate::medial::Verification), not an
/// error.
pub fn verify_report(
    part: &Path,
    report: &Path,
    accuracy: Option<f64>,
) -> Result<crate::medial::Verification> {
    let text = std::fs::read_to_string(report).map_err(|source| Error::Io {
        path: report.into(),
        source,
    })?;
    let reported = crate::export::read::read_report(&text).map_err(|reason| Error::Model {
        path: report.into(),
        reason: format!("not a usable report: {reason}"),
    })?;
    let model = crate::ingest::read_model(part)?;
    let angle = reported.angle_tol_deg;
    let class_opts = crate::classify::ClassifyOptions {
        angle_tol: if angle.is_finite() && angle > 0.0 {
            angle.to_radians()
        } else {
            crate::classify::DEFAULT_ANGLE_TOL_DEG.to_radians()
        },
        ..Default::default()
    };
    let class = crate::classify::classify(&model, &class_opts);
    let boundary = crate::geom::Boundary::new(&model);
    let mut v = crate::medial::verify(
        &model,
        &boundary,
        &class,
        &reported.axis,
        accuracy.unwrap_or(reported.accuracy),
    );
    if let Some(listed) = &reported.sheets {
        crate::medial::verify::check_listed_sheets(&model, &class, &reported.axis, listed, &mut v);
    }
    Ok(v)
}

/// The output file stem of `part` (its file name without the extension).
pub fn stem(part: &Path) -> String {
    part.file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("part")
        .to_string()
}

/// Runs the pipeline on `part` and writes `<stem>.mat.json` (last, so a complete report
/// means complete outputs), `<stem>.mat.step`, `<stem>.sheets.obj` and `<stem>.mat.svg` into
/// `opts.out_dir`.
pub fn trace_part(part: &Path, opts: &RunOptions) -> Result<PartOutcome> {
    if opts.part.with_solid && crate::ingest::is_iges_path(part) {
        return Err(Error::Model {
            path: part.into(),
            reason: "--with-solid copies a STEP input into the .mat.step file; an IGES part \
                     cannot be copied (open the part beside the .mat.step file instead)"
                .into(),
        });
    }
    let started = Instant::now();
    let mut clock = Clock::default();
    let traced = trace_stages(part, opts, &mut clock)?;
    std::fs::create_dir_all(&opts.out_dir).map_err(|source| Error::Write {
        path: opts.out_dir.clone(),
        source,
    })?;
    let stem = opts.stem.clone().unwrap_or_else(|| stem(part));
    let mut outcome = write_outputs(part, opts, &stem, &traced, &mut clock)?;
    let mut t = clock.timings;
    t.total = started.elapsed().as_secs_f64();
    outcome.report.stats.seconds = t.total;
    outcome.report.stats.timings = t;
    let json = serde_json::to_string_pretty(&outcome.report).map_err(|e| Error::Model {
        path: part.into(),
        reason: format!("report not serialisable: {e}"),
    })?;
    crate::export::write_atomic(&outcome.report_path, json.as_bytes())?;
    Ok(outcome)
}

/// The stage timings of one part, and the clock between laps.
struct Clock {
    timings: Timings,
    since: Instant,
}

impl Default for Clock {
    fn default() -> Clock {
        Clock {
            timings: Timings::default(),
            since: Instant::now(),
        }
    }
}

impl Clock {
    /// Seconds since the last lap.
    fn lap(&mut self) -> f64 {
        let s = self.since.elapsed().as_secs_f64();
        self.since = Instant::now();
        s
    }
}

/// What the computing stages made of a part.
struct Traced {
    model: Model,
    class: Classification,
    tol: Tolerances,
    boundary: crate::geom::Boundary,
    axis: MedialAxis,
    sheets: crate::medial::Sheets,
}

/// Reads, classifies, traces and finds the sheets.
fn trace_stages(part: &Path, opts: &RunOptions, clock: &mut Clock) -> Result<Traced> {
    let model = crate::ingest::read_model(part)?;
    clock.timings.read = clock.lap();
    let tol = Tolerances::new(model.diagonal(), opts.part.accuracy, opts.part.fit_tol).map_err(
        |reason| Error::Model {
            path: part.into(),
            reason,
        },
    )?;
    let class_opts = crate::classify::ClassifyOptions {
        angle_tol: tol.angle_deg.to_radians(),
        ..Default::default()
    };
    let class = crate::classify::classify(&model, &class_opts);
    clock.timings.classify = clock.lap();
    let boundary = crate::geom::Boundary::new(&model);
    let axis = crate::medial::trace_with_boundary(
        &model,
        &boundary,
        &class,
        &crate::medial::TraceOptions::new(&tol),
    );
    clock.timings.trace = clock.lap();
    let sheets = crate::medial::sheets(&model, &class, &axis);
    clock.timings.sheets = clock.lap();
    Ok(Traced {
        model,
        class,
        tol,
        boundary,
        axis,
        sheets,
    })
}

/// Writes the seams' STEP file, the sheet mesh and the picture, verifies when asked, and
/// returns the report (not yet written) with every output it describes.
fn write_outputs(
    part: &Path,
    opts: &RunOptions,
    stem: &str,
    traced: &Traced,
    clock: &mut Clock,
) -> Result<PartOutcome> {
    let Traced {
        model,
        class,
        tol,
        boundary,
        axis,
        sheets,
    } = traced;
    let options = OptionsReport {
        accuracy: tol.accuracy,
        accuracy_from: tol.accuracy_from.as_str().into(),
        diagonal: tol.diagonal,
        trace_accuracy: tol.trace,
        solver_tolerance: tol.solver,
        angle_tol_deg: tol.angle_deg,
        fit_tolerance: tol.fit,
        mesh_samples: opts.mesh_points(),
        verify: opts.part.verify,
    };
    let mut report = TraceReport::new(model, class, axis, sheets, options);
    report
        .input
        .warnings
        .extend(crate::model::warnings::gaps_beyond(model, tol.accuracy));
    report
        .input
        .warnings
        .extend(crate::classify::folds(model, class));
    let mut written = vec![];
    // The seams as B-splines in STEP, beside the part (optionally with it).
    let fit_opts = crate::fit::FitOptions { tol: tol.fit };
    let fits = crate::fit::fit_mat(axis, &fit_opts);
    report.mat.fit = Some(crate::fit::FitReport::new(axis, &fits, fit_opts.tol));
    let path = opts.out_dir.join(format!("{stem}.mat.step"));
    let degenerate_fits = crate::fit::fit_degenerate(axis, &fit_opts);
    crate::export::step::write_mat_step(
        &path,
        stem,
        axis,
        (&fits, &degenerate_fits),
        opts.part.with_solid.then_some(part),
    )?;
    written.push(path);
    clock.timings.fit = clock.lap();
    if opts.mesh_points() > 0 {
        let mesh = crate::medial::sheet_mesh(
            model,
            boundary,
            class,
            sheets,
            &crate::medial::MeshOptions {
                samples: opts.mesh_points(),
                ..crate::medial::MeshOptions::new(tol.trace)
            },
        );
        let path = opts.out_dir.join(format!("{stem}.sheets.obj"));
        crate::export::write_atomic(
            &path,
            crate::export::obj::sheet_mesh_obj(&mesh, &part.display().to_string()).as_bytes(),
        )?;
        report.stats.mesh_triangles = mesh.triangles();
        written.push(path);
        clock.timings.mesh = clock.lap();
    }
    if opts.part.picture {
        let svg_opts = crate::export::svg::SvgOptions {
            title: part
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            accuracy: Some(tol.accuracy),
            ..Default::default()
        };
        let svg = crate::export::svg::render_svg(model, class, axis, &svg_opts);
        let path = opts.out_dir.join(format!("{stem}.mat.svg"));
        crate::export::svg::write_svg(&path, &svg)?;
        written.push(path);
        clock.timings.picture = clock.lap();
    }
    if opts.part.verify {
        report.stats.verification = Some(crate::medial::verify(
            model,
            boundary,
            class,
            axis,
            tol.accuracy,
        ));
        clock.timings.verify = clock.lap();
    }
    let report_path = opts.out_dir.join(format!("{stem}.mat.json"));
    written.push(report_path.clone());
    report.outputs = written
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    Ok(PartOutcome {
        report,
        report_path,
        written,
    })
}
