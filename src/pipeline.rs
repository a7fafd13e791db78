//! One part through the whole pipeline: read, classify, trace, sheets, sheet mesh, picture,
//! verification, and the outputs written atomically beside each other. The `trace` command
//! and the batch runner both call [`trace_part`]; neither prints from here.

use crate::error::{Error, Result};
use crate::export::report::{OptionsReport, Timings, TraceReport};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The choices made for every part, the same for `matrace trace` and for each part of a
/// `matrace batch` (which passes them on to its workers and records them in its summary).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PartOptions {
    /// Output accuracy in mm; `None`: 1e-6 × the part's bounding-box diagonal.
    pub tol: Option<f64>,
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
            tol: None,
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
    /// True when a verification ran and found an error above the accuracy.
    pub fn verification_failed(&self) -> bool {
        self.report
            .stats
            .verification
            .as_ref()
            .is_some_and(|v| v.worst() > self.report.options.accuracy)
    }
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
    let mut t = Timings::default();
    let lap = |since: &mut Instant| {
        let s = since.elapsed().as_secs_f64();
        *since = Instant::now();
        s
    };
    let mut clock = Instant::now();
    let model = crate::ingest::read_model(part)?;
    t.read = lap(&mut clock);
    let class = crate::classify(&model, &Default::default());
    t.classify = lap(&mut clock);
    let mut trace_opts = crate::medial::TraceOptions::for_model(&model);
    let accuracy_from = match opts.part.tol {
        Some(tol) if tol.is_finite() && tol > 0.0 => {
            trace_opts.accuracy = tol;
            "--tol"
        }
        Some(tol) => {
            return Err(Error::Model {
                path: part.into(),
                reason: format!("the accuracy must be a positive length in mm, got {tol}"),
            })
        }
        None => "1e-6 x diagonal",
    };
    let boundary = crate::geom::Boundary::new(&model);
    let mat = crate::medial::trace_with_boundary(&model, &boundary, &class, &trace_opts);
    t.trace = lap(&mut clock);
    let sheets = crate::medial::sheets(&model, &class, &mat);
    t.sheets = lap(&mut clock);
    let mut fit_opts = crate::fit::FitOptions::for_model(model.diagonal(), trace_opts.accuracy);
    if let Some(tol) = opts.part.fit_tol {
        fit_opts.tol = tol.max(trace_opts.accuracy);
    }
    let options = OptionsReport {
        accuracy: trace_opts.accuracy,
        accuracy_from: accuracy_from.into(),
        diagonal: model.diagonal(),
        solver_tolerance: 1e-3 * trace_opts.accuracy,
        angle_tol_deg: crate::classify::DEFAULT_ANGLE_TOL_DEG,
        fit_tolerance: fit_opts.tol,
        mesh_samples: opts.mesh_points(),
        verify: opts.part.verify,
    };
    let mut report = TraceReport::new(&model, &class, &mat, &sheets, options);

    std::fs::create_dir_all(&opts.out_dir).map_err(|source| Error::Write {
        path: opts.out_dir.clone(),
        source,
    })?;
    let stem = opts.stem.clone().unwrap_or_else(|| stem(part));
    let mut written = vec![];
    // The seams as B-splines in STEP, beside the part (optionally with it).
    let fits = crate::fit::fit_mat(&mat, &fit_opts);
    report.mat.fit = Some(crate::fit::FitReport::new(&mat, &fits, fit_opts.tol));
    let path = opts.out_dir.join(format!("{stem}.mat.step"));
    crate::export::step::write_mat_step(
        &path,
        &stem,
        &mat,
        &fits,
        opts.part.with_solid.then_some(part),
    )?;
    written.push(path);
    t.fit = lap(&mut clock);
    if opts.mesh_points() > 0 {
        let mesh = crate::medial::sheet_mesh(
            &model,
            &boundary,
            &class,
            &sheets,
            &crate::medial::MeshOptions {
                samples: opts.mesh_points(),
                ..crate::medial::MeshOptions::new(trace_opts.accuracy)
            },
        );
        let path = opts.out_dir.join(format!("{stem}.sheets.obj"));
        crate::export::write_atomic(
            &path,
            crate::export::obj::sheet_mesh_obj(&mesh, &part.display().to_string()).as_bytes(),
        )?;
        report.stats.mesh_triangles = mesh.triangles();
        written.push(path);
        t.mesh = lap(&mut clock);
    }
    if opts.part.picture {
        let svg_opts = crate::export::svg::SvgOptions {
            title: part
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            accuracy: Some(trace_opts.accuracy),
            ..Default::default()
        };
        let svg = crate::export::svg::render_svg(&model, &class, &mat, &svg_opts);
        let path = opts.out_dir.join(format!("{stem}.mat.svg"));
        crate::export::svg::write_svg(&path, &svg)?;
        written.push(path);
        t.picture = lap(&mut clock);
    }
    if opts.part.verify {
        report.stats.verification = Some(crate::medial::verify(&model, &boundary, &mat));
        t.verify = lap(&mut clock);
    }
    let report_path = opts.out_dir.join(format!("{stem}.mat.json"));
    written.push(report_path.clone());
    report.outputs = written
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    t.total = started.elapsed().as_secs_f64();
    report.stats.seconds = t.total;
    report.stats.timings = t;
    let json = serde_json::to_string_pretty(&report).map_err(|e| Error::Model {
        path: part.into(),
        reason: format!("report not serialisable: {e}"),
    })?;
    crate::export::write_atomic(&report_path, json.as_bytes())?;
    Ok(PartOutcome {
        report,
        report_path,
        written,
    })
}
