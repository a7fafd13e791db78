//! `<stem>.mat.step`: `matrace trace` writes the seams as B-spline curves and the junctions as
//! points; FreeCAD opens the file and sees one edge per seam within the fit tolerance of the
//! traced points (scripts/freecad/check_mat_step.py, Debian's python
//! with the FreeCAD modules, which CI installs), `--with-solid` adds the input part, and
//! truck's STEP reader finds one B-spline curve per seam.

use crate::common::{matrace, realworld_dir, root, sample};
use crate::tools::{require, Tool};
use std::path::{Path, PathBuf};
use truck_geometry::prelude::{BSplineCurve, BoundedCurve, MetricSpace, ParametricCurve, Point3};
use truck_stepio::r#in::ruststep::ast::Name;
use truck_stepio::r#in::ruststep::tables::{IntoOwned, PlaceHolder};
use truck_stepio::r#in::{BSplineCurveWithKnotsHolder, Table};

/// Samples with straight seams only (box), with curved seams (the holes' plate, the L-bracket
/// with a concave fillet), and in inches (the file's unit is not the output's).
const SAMPLES: &[&str] = &[
    "box.step",
    "plate_with_holes.step",
    "l_bracket_concave_fillet.step",
    "box_inch.step",
];

/// Runs `matrace trace PART -o DIR ARGS...`, asserts success, returns the report and the
/// path of the STEP file.
fn trace(part: &Path, dir: &Path, args: &[&str]) -> (serde_json::Value, PathBuf) {
    let mut all = vec!["trace", part.to_str().unwrap(), "-o", dir.to_str().unwrap()];
    all.extend(args);
    let out = matrace(&all, &root());
    assert!(
        out.status.success(),
        "{}: {}",
        part.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("fitted "), "{stdout}");
    let stem = part.file_stem().unwrap().to_str().unwrap();
    let report = std::fs::read(dir.join(format!("{stem}.mat.json"))).unwrap();
    let step = dir.join(format!("{stem}.mat.step"));
    assert!(step.is_file(), "{} not written", step.display());
    (serde_json::from_slice(&report).unwrap(), step)
}

/// Runs the FreeCAD check; `Ok(stdout)` or `Err(stderr)`.
fn freecad_check(step: &Path, report: &Path, args: &[&str]) -> Result<String, String> {
    let out = std::process::Command::new("/usr/bin/python3")
        .arg(root().join("scripts/freecad/check_mat_step.py"))
        .arg(step)
        .arg(report)
        .args(args)
        .output()
        .expect("run /usr/bin/python3 (Debian's, with FreeCAD: see .ci/run)");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!("exit {:?}: {stdout}{stderr}", out.status.code()))
    }
}

fn report_path(step: &Path) -> PathBuf {
    PathBuf::from(step.to_str().unwrap().replace(".mat.step", ".mat.json"))
}

#[test]
fn freecad_sees_one_edge_per_seam_within_the_fit_tolerance_and_the_junctions() {
    if !require(
        "step_out::freecad_sees_one_edge_per_seam_within_the_fit_tolerance_and_the_junctions",
        &[Tool::FreeCad],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for name in SAMPLES {
        let (report, step) = trace(&sample(name), dir.path(), &[]);
        let seams = report["mat"]["seams"].as_array().unwrap();
        assert!(!seams.is_empty(), "{name}: no seams to check");
        let fit = &report["mat"]["fit"];
        let tol = fit["tol"].as_f64().unwrap();
        // The default fit tolerance is DEFAULT_FIT_TOL_REL_DIAGONAL × the diagonal.
        let diagonal = report["model"]["diagonal"].as_f64().unwrap();
        let want = matrace::fit::DEFAULT_FIT_TOL_REL_DIAGONAL * diagonal;
        assert!(
            (tol - want).abs() <= 1e-12 * want,
            "{name}: tol {tol} vs {want}"
        );
        let fits = fit["seams"].as_array().unwrap();
        assert_eq!(fits.len(), seams.len(), "{name}");
        for (s, f) in seams.iter().zip(fits) {
            assert_eq!(s["id"], f["seam"], "{name}");
            assert!(f["max_error"].as_f64().unwrap() <= tol, "{name}: {f}");
            assert!(
                f["max_radius_error"].as_f64().unwrap() <= tol,
                "{name}: {f}"
            );
            let n = f["control_points"].as_u64().unwrap() as usize;
            let points = s["points"].as_array().unwrap().len();
            assert!(n >= 2 && n <= points.max(2), "{name}: {f}");
        }
        if name.starts_with("box") {
            // The box's seams are straight: lines.
            assert!(fits.iter().all(|f| f["degree"] == 1), "{name}: {fit}");
        } else {
            assert!(fits.iter().any(|f| f["degree"] == 3), "{name}: {fit}");
        }
        let checked = freecad_check(&step, &report_path(&step), &[]).unwrap_or_else(|e| {
            panic!("{name}: {e}");
        });
        assert!(checked.contains("\"solids\": 0"), "{name}: {checked}");
    }
}

#[test]
fn a_part_without_seams_gives_a_file_freecad_opens_empty() {
    if !require(
        "step_out::a_part_without_seams_gives_a_file_freecad_opens_empty",
        &[Tool::FreeCad],
    ) {
        return;
    }
    // A sphere's MAT is its centre (a degenerate point, not a seam or a junction).
    let dir = tempfile::tempdir().unwrap();
    let (report, step) = trace(&sample("sphere.step"), dir.path(), &[]);
    assert!(report["mat"]["seams"].as_array().unwrap().is_empty());
    let checked = freecad_check(&step, &report_path(&step), &[]).unwrap();
    assert!(checked.contains("\"edges\": 0"), "{checked}");
}

#[test]
fn with_solid_freecad_sees_the_part_and_the_seams() {
    if !require(
        "step_out::with_solid_freecad_sees_the_part_and_the_seams",
        &[Tool::FreeCad],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // An inch file and a moved part: the copied entities keep their own units and placement,
    // and the check finds every junction inside the solid. NIST CTC-01 (from the real-world
    // corpus, where present as for the other corpus tests) adds free wireframe edges of its own.
    let mut parts: Vec<PathBuf> = ["plate_with_holes.step", "box_inch.step", "moved_part.step"]
        .iter()
        .map(|n| sample(n))
        .collect();
    match realworld_dir() {
        Some(d) => parts.push(d.join("stepswift_nist_ctc_01_asme1_rd.stp")),
        None => {
            require("step_out::with_solid (NIST CTC 01)", &[Tool::Corpus]);
        }
    }
    for part in parts {
        let name = part.file_name().unwrap().to_str().unwrap();
        let (_, step) = trace(&part, dir.path(), &["--with-solid"]);
        let checked = freecad_check(
            &step,
            &report_path(&step),
            &["--with-solid", part.to_str().unwrap(), "--every", "3"],
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(checked.contains("\"solids\": 1"), "{name}: {checked}");
    }
}

#[test]
fn the_freecad_check_fails_on_a_wrong_report() {
    if !require(
        "step_out::the_freecad_check_fails_on_a_wrong_report",
        &[Tool::FreeCad],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (report, step) = trace(&sample("plate_with_holes.step"), dir.path(), &[]);
    let write = |name: &str, v: &serde_json::Value| {
        let p = dir.path().join(name);
        std::fs::write(&p, serde_json::to_string(v).unwrap()).unwrap();
        p
    };
    // A tolerance the fit did not honour: the distances give it away.
    let mut tight = report.clone();
    tight["mat"]["fit"]["tol"] = 1e-9.into();
    let e = freecad_check(&step, &write("tight.json", &tight), &[]).unwrap_err();
    assert!(e.contains("from its edge"), "{e}");
    // One seam fewer than the file has edges.
    let mut fewer = report.clone();
    fewer["mat"]["seams"].as_array_mut().unwrap().pop();
    let e = freecad_check(&step, &write("fewer.json", &fewer), &[]).unwrap_err();
    assert!(e.contains("15 free edges for 14 seams"), "{e}");
    // A junction that is not there.
    let mut moved = report.clone();
    moved["mat"]["junctions"][0]["point"][0] = 1000.0.into();
    let e = freecad_check(&step, &write("moved.json", &moved), &[]).unwrap_err();
    assert!(e.contains("junction 0"), "{e}");
    // A solid that is not there.
    let e = freecad_check(
        &step,
        &report_path(&step),
        &[
            "--with-solid",
            sample("plate_with_holes.step").to_str().unwrap(),
        ],
    )
    .unwrap_err();
    assert!(e.contains("0 solids"), "{e}");
}

#[test]
fn truck_reads_back_one_bspline_curve_per_seam() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["plate_with_holes.step", "l_bracket_concave_fillet.step"] {
        let (report, step) = trace(&sample(name), dir.path(), &[]);
        let text = std::fs::read_to_string(&step).unwrap();
        let exchange = truck_stepio::r#in::ruststep::parser::parse(&text)
            .unwrap_or_else(|e| panic!("{name}: truck cannot parse the file: {e}"));
        let table = Table::from_data_section(&exchange.data[0]);
        let seams = report["mat"]["seams"].as_array().unwrap();
        let fits = report["mat"]["fit"]["seams"].as_array().unwrap();
        assert_eq!(table.b_spline_curve_with_knots.len(), seams.len(), "{name}");
        for (id, holder) in &table.b_spline_curve_with_knots {
            let seam: usize = holder
                .label
                .strip_prefix("seam ")
                .and_then(|s| s.parse().ok())
                .unwrap_or_else(|| panic!("{name}: #{id} is named {:?}", holder.label));
            let owned = PlaceHolder::<BSplineCurveWithKnotsHolder>::Ref(Name::Entity(*id))
                .into_owned(&table)
                .unwrap();
            let curve = BSplineCurve::<Point3>::try_from(&owned).unwrap();
            assert_eq!(
                curve.control_points().len() as u64,
                fits[seam]["control_points"].as_u64().unwrap(),
                "{name}: seam {seam}"
            );
            assert_eq!(
                curve.degree() as u64,
                fits[seam]["degree"].as_u64().unwrap()
            );
            // The curve runs from the seam's first traced point to its last.
            let points = seams[seam]["points"].as_array().unwrap();
            let (t0, t1) = curve.range_tuple();
            for (t, p) in [(t0, &points[0]), (t1, &points[points.len() - 1])] {
                let want = Point3::new(
                    p["point"][0].as_f64().unwrap(),
                    p["point"][1].as_f64().unwrap(),
                    p["point"][2].as_f64().unwrap(),
                );
                assert!(curve.subs(t).distance(want) < 1e-9, "{name}: seam {seam}");
            }
        }
        let junctions = table
            .cartesian_point
            .values()
            .filter(|p| p.label.starts_with("junction "))
            .count();
        assert_eq!(
            junctions,
            report["mat"]["junctions"].as_array().unwrap().len()
        );
    }
}

#[test]
fn fit_tol_is_never_below_the_accuracy_and_must_be_positive() {
    let dir = tempfile::tempdir().unwrap();
    let (report, _) = trace(&sample("box.step"), dir.path(), &["--fit-tol", "1e-12"]);
    assert_eq!(report["mat"]["fit"]["tol"], report["stats"]["accuracy"]);
    let (report, _) = trace(&sample("box.step"), dir.path(), &["--fit-tol", "0.5"]);
    assert_eq!(report["mat"]["fit"]["tol"], 0.5);
    for bad in ["0", "-1", "nan"] {
        let out = matrace(
            &[
                "trace",
                sample("box.step").to_str().unwrap(),
                "-o",
                dir.path().to_str().unwrap(),
                "--fit-tol",
                bad,
            ],
            &root(),
        );
        assert_eq!(out.status.code(), Some(2), "--fit-tol {bad}");
    }
}

#[test]
fn an_unwritable_output_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // A folder where the STEP file should go: the rename fails.
    std::fs::create_dir(dir.path().join("box.mat.step")).unwrap();
    let out = matrace(
        &[
            "trace",
            sample("box.step").to_str().unwrap(),
            "-o",
            dir.path().to_str().unwrap(),
        ],
        &root(),
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("box.mat.step: cannot write file"),
        "{stderr}"
    );
    // No temporary file is left behind.
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// The skeletal edges below a box standing on a plate are edges of the file too: FreeCAD
/// finds one straight edge per skeletal edge after the seams, through its balls; a report
/// with one fewer is refused.
#[test]
fn freecad_sees_the_skeletal_edges_below_a_box_on_a_plate() {
    if !require(
        "step_out::freecad_sees_the_skeletal_edges_below_a_box_on_a_plate",
        &[Tool::FreeCad],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (report, step) = trace(&sample("trace/box_boss_on_plate.step"), dir.path(), &[]);
    let seams = report["mat"]["seams"].as_array().unwrap().len();
    let skeletal = report["mat"]["skeletal_edges"].as_array().unwrap().len();
    assert_eq!(skeletal, 4);
    let checked = freecad_check(&step, &report_path(&step), &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        checked.contains(&format!("\"edges\": {}", seams + skeletal)),
        "{checked}"
    );
    let mut fewer = report.clone();
    fewer["mat"]["skeletal_edges"].as_array_mut().unwrap().pop();
    let p = dir.path().join("fewer.json");
    std::fs::write(&p, serde_json::to_string(&fewer).unwrap()).unwrap();
    let e = freecad_check(&step, &p, &[]).unwrap_err();
    assert!(
        e.contains(&format!(
            "{} free edges for {seams} seams, 3 skeletal edges",
            seams + 4
        )),
        "{e}"
    );
}

/// Degenerate curves are edges of the file too, after the seams and skeletal edges: the
/// cylinder's axis and the torus's closed core circle one edge each, the filleted box's 12
/// fillet axes 12 edges beside its seams, every ball within the fit tolerance of its edge; a
/// report without the cylinder's axis is refused.
#[test]
fn freecad_sees_the_degenerate_curves_as_edges() {
    if !require(
        "step_out::freecad_sees_the_degenerate_curves_as_edges",
        &[Tool::FreeCad],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (name, curves) in [
        ("cylinder.step", 1),
        ("torus.step", 1),
        ("filleted_box.step", 12),
    ] {
        let out = dir.path().join(name);
        std::fs::create_dir_all(&out).unwrap();
        let (report, step) = trace(&sample(name), &out, &[]);
        let seams = report["mat"]["seams"].as_array().unwrap().len();
        let checked = freecad_check(&step, &report_path(&step), &[])
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            checked.contains(&format!("\"edges\": {}", seams + curves)),
            "{name}: {checked}"
        );
        if name == "cylinder.step" {
            let mut without = report.clone();
            without["mat"]["degenerate"] = serde_json::json!([]);
            let p = out.join("without.json");
            std::fs::write(&p, serde_json::to_string(&without).unwrap()).unwrap();
            let e = freecad_check(&step, &p, &[]).unwrap_err();
            assert!(e.contains("1 free edges for 0 seams"), "{e}");
        }
    }
}
