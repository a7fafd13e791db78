//! The command line: `inspect` prints a table and `--json` the report's `input` and `model`.

use crate::common::{matrace, root, sample};

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
