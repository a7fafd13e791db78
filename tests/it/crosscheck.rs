//! Completeness and the independent cross-check (`docs/testing.md`), on every
//! reference sample and every part of the real-world corpus: `trace --verify` must exit 0
//! with no open seam end and a consistent seam–junction graph, and OpenCASCADE
//! (scripts/ocp/crosscheck_mat.py, the OCP venv, no code shared with matrace) must accept
//! every junction, every degenerate ball and sampled seam points: inside the solid, at
//! distance r from the boundary, touching ≥ 3 (≥ 4) places.
//!
//! Parts that do not pass yet are listed in [`EXPECTED_FAILURES`] with the reason; the test
//! fails when an unlisted part fails and when a listed part passes (take it off the list).
//! Without `.venv-ocp` the OCCT half, and without `../shared/realworld` the corpus, is
//! skipped loudly (under CI, where both must be present, that is a failure: `tools.rs`).

use crate::common::{matrace, realworld_dir, root};
use crate::tools::Tool;
use std::path::PathBuf;

const OPEN_AT_HANDOVERS: &str = "a few seams end open (CTC 01: 15 of 198 ends, FTC 06: 9 of \
    210, FTC 09: 6 of 156) where a touch point is handed to the next segment near a vertex and \
    the system there is singular or converges to another ball, or the step size underflows \
    beside such a point: the event is a junction with the vertex or edge, not located yet";

/// Parts known not to pass, and why.
const EXPECTED_FAILURES: &[(&str, &str)] = &[
    (
        "b3d_M6-1x12-countersunk-screw.step",
        "verification fails: touch points up to 0.16 mm off the degree-13 B-spline thread \
         faces (their trim is a 32-point polygon per edge); seams end open at hand-overs",
    ),
    ("stepswift_nist_ctc_01_asme1_rd.stp", OPEN_AT_HANDOVERS),
    ("stepswift_nist_ftc_06_asme1_rd.stp", OPEN_AT_HANDOVERS),
    ("stepswift_nist_ftc_09_asme1_rd.stp", OPEN_AT_HANDOVERS),
    (
        "trimesh_featuretype.STEP",
        "22 of 268 seam ends open: 20 where a ball fits a 12.7 mm channel exactly (r = 6.35) \
         just as its touch point reaches a counterbore's bottom edge, so a junction and a \
         hand-over coincide and the touch point is handed back and forth",
    ),
];

/// Every STEP file of the samples and of the corpus.
fn parts() -> Vec<PathBuf> {
    let mut dirs = vec![root().join("samples")];
    dirs.extend(realworld_dir());
    let mut parts: Vec<PathBuf> = dirs
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "step" | "stp"))
        })
        .collect();
    parts.sort();
    parts
}

/// Why `part` does not pass, or `None` when it does (with `occt`, OpenCASCADE's check too).
fn failure(part: &std::path::Path, out_dir: &std::path::Path, occt: bool) -> Option<String> {
    let out = matrace(
        &[
            "trace",
            part.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "--verify",
        ],
        &root(),
    );
    let mut why = vec![];
    if !out.status.success() {
        why.push(format!(
            "trace --verify exit {:?}: {}",
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let stem = part.file_stem().unwrap().to_str().unwrap();
    let report = out_dir.join(format!("{stem}.mat.json"));
    let Ok(text) = std::fs::read_to_string(&report) else {
        why.push("no report".into());
        return Some(why.join("; "));
    };
    let json: serde_json::Value = serde_json::from_str(&text).expect("report is JSON");
    let topo = &json["mat"]["topology"];
    let open = topo["open_ends"].as_u64().expect("open_ends");
    if open > 0 {
        why.push(format!("{open} open seam ends"));
    }
    let bad = topo["inconsistencies"].as_array().expect("inconsistencies");
    if !bad.is_empty() {
        why.push(format!("graph: {bad:?}"));
    }
    // Where the sheets are complete, the medial axis must have the solid's Euler
    // characteristic (it is a deformation retract of the solid).
    for e in topo["euler"].as_array().expect("euler") {
        if let Some(chi) = e["mat_euler"].as_i64() {
            if Some(chi) != e["solid_euler"].as_i64() {
                why.push(format!("Euler characteristics differ: {e}"));
            }
        }
    }
    if occt {
        let check = std::process::Command::new(crate::tools::occt_python())
            .arg(root().join("scripts/ocp/crosscheck_mat.py"))
            .arg(part)
            .arg(&report)
            .args(["--every", "10"])
            .output()
            .expect("run the OCP cross-check");
        if !check.status.success() {
            why.push(format!(
                "OCCT cross-check: {}{}",
                String::from_utf8_lossy(&check.stdout).trim(),
                String::from_utf8_lossy(&check.stderr).trim()
            ));
        }
    }
    (!why.is_empty()).then(|| why.join("; "))
}

#[test]
fn every_part_traces_completely_and_passes_the_opencascade_crosscheck() {
    const TEST: &str =
        "crosscheck::every_part_traces_completely_and_passes_the_opencascade_crosscheck";
    let corpus = crate::tools::require(&format!("{TEST} (on the corpus)"), &[Tool::Corpus]);
    let occt = crate::tools::require(&format!("{TEST} (OCCT half)"), &[Tool::Occt]);
    let parts = parts();
    assert!(parts.len() >= 25, "only {} parts found", parts.len());
    let dir = tempfile::tempdir().unwrap();
    // Two workers (the OCCT check is single-threaded Python).
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(vec![None; parts.len()]);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(part) = parts.get(i) else { break };
                let why = failure(part, dir.path(), occt);
                results.lock().unwrap()[i] = Some(why);
            });
        }
    });
    let results = results.into_inner().unwrap();
    let mut problems = vec![];
    for (part, result) in parts.iter().zip(results) {
        let name = part.file_name().unwrap().to_str().unwrap();
        let expected = EXPECTED_FAILURES.iter().find(|(n, _)| *n == name);
        match (result.expect("every part checked"), expected) {
            (None, None) | (Some(_), Some(_)) => {}
            (Some(why), None) => problems.push(format!("{name} fails: {why}")),
            (None, Some(_)) => {
                problems.push(format!("{name} passes now: take it off EXPECTED_FAILURES"))
            }
        }
    }
    for (name, _) in EXPECTED_FAILURES {
        if corpus && !parts.iter().any(|p| p.file_name().unwrap() == *name) {
            problems.push(format!("{name} is listed but not found"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
