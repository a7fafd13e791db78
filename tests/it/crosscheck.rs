//! The independent cross-check (DESIGN.md, "Verification"): trace the samples whose MAT the
//! first tracer covers, then let OpenCASCADE (scripts/ocp/crosscheck_mat.py, the OCP venv,
//! no code shared with matrace) check every junction and sampled seam points: inside the
//! solid, at distance r from the boundary, touching ≥ 3 (≥ 4) faces. Needs `.venv-ocp`
//! (`.ci/run` creates it); without it the test says so and passes, except under CI.

use crate::common::{matrace, root, sample};

#[test]
fn traced_samples_pass_the_opencascade_crosscheck() {
    let python = root().join(".venv-ocp/bin/python");
    if !python.exists() {
        assert!(
            std::env::var("CI").is_err(),
            "CI must create .venv-ocp (see .ci/run)"
        );
        eprintln!(".venv-ocp missing: OpenCASCADE cross-check not run");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut bad = vec![];
    for name in [
        "box",
        "box_nurbs",
        "box_inch",
        "cube",
        "tetrahedron",
        "wedge",
        "pyramid",
        "box_bspline_top",
        "moved_part",
    ] {
        let step = sample(&format!("{name}.step"));
        let out = matrace(
            &[
                "trace",
                step.to_str().unwrap(),
                "-o",
                dir.path().to_str().unwrap(),
            ],
            &root(),
        );
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report = dir.path().join(format!("{name}.mat.json"));
        let check = std::process::Command::new(&python)
            .arg(root().join("scripts/ocp/crosscheck_mat.py"))
            .arg(&step)
            .arg(&report)
            .output()
            .expect("run the OCP cross-check");
        if !check.status.success() {
            bad.push(format!(
                "{name}:\n{}{}",
                String::from_utf8_lossy(&check.stdout),
                String::from_utf8_lossy(&check.stderr)
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
