//! The command line: `inspect` prints a table and `--json` the report's `input` and `model`.

use crate::common::{matrace, root, sample};
use std::path::Path;

#[test]
fn inspect_prints_a_table() {
    let out = matrace(
        &["inspect", sample("l_bracket.step").to_str().unwrap()],
        &root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("faces 8  edges 18  vertices 12"), "{text}");
    assert!(text.contains("17 convex, 1 reflex"), "{text}");
    assert!(text.contains("reflex    270.00"), "{text}");
}

#[test]
fn inspect_json_follows_the_report_schema() {
    let out = matrace(
        &[
            "inspect",
            "--json",
            sample("box_inch.step").to_str().unwrap(),
        ],
        &root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["schema"], "matrace.report/1");
    assert_eq!(v["input"]["format"], "step");
    assert_eq!(v["input"]["length_unit"], "mm");
    assert_eq!(v["input"]["file_unit"], "inch");
    assert_eq!(v["input"]["mm_per_unit"], 25.4);
    assert_eq!(v["model"]["solids"], 1);
    assert_eq!(v["model"]["faces"].as_array().unwrap().len(), 6);
    assert_eq!(v["model"]["faces"][0]["surface"], "plane");
    let e0 = &v["model"]["edges"][0];
    assert_eq!(e0["id"], 0);
    assert_eq!(e0["kind"], "convex");
    assert_eq!(e0["faces"].as_array().unwrap().len(), 2);
    let v0 = &v["model"]["vertices"][0];
    assert_eq!(v0["kind"], "convex");
    assert_eq!(v0["point"].as_array().unwrap().len(), 3);
    // The inch box is the 60×40×20 mm box: its far corner comes out in millimetres.
    let hi = &v["model"]["bbox"][1];
    for (k, want) in [60.0, 40.0, 20.0].iter().enumerate() {
        let got = hi[k].as_f64().unwrap();
        assert!((got - want).abs() < 1e-9, "bbox max {k}: {got} vs {want}");
    }
}

#[test]
fn bad_arguments_exit_2() {
    let out = matrace(&["inspect"], &root());
    assert_eq!(out.status.code(), Some(2));
    let out = matrace(&["frobnicate"], &root());
    assert_eq!(out.status.code(), Some(2));
    let out = matrace(
        &[
            "inspect",
            "--angle-tol",
            "-3",
            sample("box.step").to_str().unwrap(),
        ],
        &root(),
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn trace_writes_the_report_and_prints_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = matrace(
        &[
            "trace",
            sample("box.step").to_str().unwrap(),
            "-o",
            dir.path().to_str().unwrap(),
        ],
        &root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("12 seams (0 open), 4 junctions"), "{text}");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("box.mat.json")).unwrap()).unwrap();
    assert_eq!(v["schema"], "matrace.report/1");
    assert_eq!(v["mat"]["seams"].as_array().unwrap().len(), 12);
    assert_eq!(v["mat"]["junctions"].as_array().unwrap().len(), 4);
    let seam = &v["mat"]["seams"][0];
    assert_eq!(seam["segments"].as_array().unwrap().len(), 3);
    assert!(seam["ends"][0]["vertex"].as_u64().is_some());
    let p = seam["points"][1]["point"].as_array().unwrap();
    assert_eq!(p.len(), 4, "[x, y, z, r]");
    assert_eq!(seam["points"][1]["touch"].as_array().unwrap().len(), 3);
    let j = &v["mat"]["junctions"][0];
    assert!((j["radius"].as_f64().unwrap() - 10.0).abs() < 1e-9);
    assert_eq!(v["stats"]["seams"], 12);
    // A bad --accuracy (or --tol, its alias) is an argument error naming the option.
    for flag in ["--accuracy", "--tol"] {
        let bad = matrace(
            &["trace", sample("box.step").to_str().unwrap(), flag, "0"],
            &root(),
        );
        assert_eq!(bad.status.code(), Some(2), "{flag}");
        let err = String::from_utf8_lossy(&bad.stderr);
        assert!(
            err.contains("--accuracy must be a positive length"),
            "{flag}: {err}"
        );
    }
}

/// Every ball `trace` outputs on every sample satisfies the definition to the accuracy (the
/// checks of `trace --verify` on balls: finite, inside, at distance r, touching the boundary
/// at r in separate places). The graph's checks (open ends, Euler characteristics, faces and
/// convex vertices reached) are the cross-check's business, with its expected failures. The
/// exit status says whether every check passed.
#[test]
fn every_traced_ball_of_every_sample_verifies() {
    const BALL_CHECKS: [&str; 7] = [
        "finite",
        "elements",
        "inside",
        "distance",
        "touch_on_boundary",
        "touch_at_radius",
        "separated",
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut bad = vec![];
    for path in crate::common::sample_files() {
        let out = matrace(
            &[
                "trace",
                path.to_str().unwrap(),
                "-o",
                dir.path().to_str().unwrap(),
                "--verify",
                "--no-mesh",
                "--no-svg",
            ],
            &root(),
        );
        let stem = path.file_stem().unwrap().to_str().unwrap();
        let report: serde_json::Value = serde_json::from_slice(
            &std::fs::read(dir.path().join(format!("{stem}.mat.json"))).unwrap(),
        )
        .unwrap();
        let v = &report["stats"]["verification"];
        for check in BALL_CHECKS {
            let c = &v["checks"][check];
            if c["failed"].as_u64() != Some(0) && !c.is_null() {
                bad.push(format!("{stem}: {check} failed {}", c["failed"]));
            }
        }
        let ok = v["ok"].as_bool().expect("verification.ok");
        if out.status.code() != Some(if ok { 0 } else { 1 }) {
            bad.push(format!(
                "{stem}: exit {:?} with ok = {ok}",
                out.status.code()
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Any accuracy gives the medial axis of the default run, or exit 2 saying the most it may
/// be: from 1e-9 mm to 1e-3 × the diagonal the box, L-bracket, U-channel and tetrahedron keep
/// their seams, junctions, sheets and Euler characteristic, every junction within the
/// accuracy of the default run's, and `--verify` passes; coarser accuracies are refused.
/// (Before the trace accuracy was held to the default, `--accuracy 0.15` on the box walked
/// every seam 0.04 mm from its corner and back, "8 seams, 0 junctions, 0 sheets", exit 0;
/// the tetrahedron lost a sheet at 6e-4 × its diagonal.)
#[test]
fn every_accuracy_gives_the_same_medial_axis_or_a_refusal() {
    let dir = tempfile::tempdir().unwrap();
    let run = |part: &Path, accuracy: Option<f64>| {
        let out_dir = dir.path().join(format!("{accuracy:?}"));
        let mut args = vec![
            "trace".to_string(),
            part.to_str().unwrap().to_string(),
            "-o".into(),
            out_dir.to_str().unwrap().to_string(),
            "--verify".into(),
            "--no-svg".into(),
            "--no-mesh".into(),
        ];
        if let Some(a) = accuracy {
            args.extend(["--accuracy".to_string(), format!("{a:e}")]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = matrace(&args, &root());
        let stem = part.file_stem().unwrap().to_str().unwrap();
        let report = std::fs::read_to_string(out_dir.join(format!("{stem}.mat.json")))
            .ok()
            .map(|t| serde_json::from_str::<serde_json::Value>(&t).unwrap());
        let _ = std::fs::remove_dir_all(&out_dir);
        (out, report)
    };
    let shape = |r: &serde_json::Value| {
        let count = |k: &str| r["mat"][k].as_array().unwrap().len();
        let euler: Vec<_> = r["mat"]["topology"]["euler"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| (e["mat_euler"].as_i64(), e["solid_euler"].as_i64()))
            .collect();
        (count("seams"), count("junctions"), count("sheets"), euler)
    };
    let junctions = |r: &serde_json::Value| -> Vec<[f64; 3]> {
        r["mat"]["junctions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| {
                let c = j["point"].as_array().unwrap();
                [0, 1, 2].map(|k| c[k].as_f64().unwrap())
            })
            .collect()
    };
    for name in [
        "box.step",
        "l_bracket.step",
        "u_channel.step",
        "tetrahedron.step",
    ] {
        let part = sample(name);
        let (out, base) = run(&part, None);
        assert_eq!(out.status.code(), Some(0), "{name}");
        let base = base.unwrap();
        let diagonal = base["options"]["diagonal"].as_f64().unwrap();
        let (base_shape, base_junctions) = (shape(&base), junctions(&base));
        assert!(
            base_shape.0 >= 4 && base_shape.2 >= 6,
            "{name}: {base_shape:?}"
        );
        for accuracy in [1e-9, 1e-6 * diagonal, 1e-4 * diagonal, 0.999e-3 * diagonal] {
            let (out, report) = run(&part, Some(accuracy));
            assert_eq!(
                out.status.code(),
                Some(0),
                "{name} at {accuracy:e}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let report = report.unwrap();
            assert_eq!(shape(&report), base_shape, "{name} at {accuracy:e}");
            let reached = junctions(&report);
            for (a, b) in reached.iter().zip(&base_junctions) {
                let d = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
                assert!(
                    d <= accuracy.max(1e-6 * diagonal),
                    "{name} at {accuracy:e}: {d}"
                );
            }
        }
        for accuracy in [1.001e-3 * diagonal, 0.5, 1.0] {
            let (out, report) = run(&part, Some(accuracy));
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{name} at {accuracy:e}: {err}");
            assert!(
                report.is_none(),
                "{name} at {accuracy:e}: a report was written"
            );
            assert!(
                err.contains("is coarser than the part allows: at most 0.001 ×"),
                "{name} at {accuracy:e}: {err}"
            );
        }
    }
}
