//! Every reference sample against what its manifest entry knows by construction: topology
//! counts, surface kinds, edge and vertex kinds, length unit and bounding box.

use crate::common::{manifest, sample};
use matrace::export::report::Report;
use serde_json::Value;
use std::collections::BTreeMap;

fn kinds(v: &Value) -> BTreeMap<String, u64> {
    v.as_object()
        .expect("kind map")
        .iter()
        .map(|(k, n)| (k.clone(), n.as_u64().expect("count")))
        .filter(|(_, n)| *n > 0)
        .collect()
}

fn ours(map: &BTreeMap<&'static str, usize>) -> BTreeMap<String, u64> {
    map.iter()
        .filter(|(_, n)| **n > 0)
        .map(|(k, n)| (k.to_string(), *n as u64))
        .collect()
}

/// Reads and classifies one sample; returns the differences from its manifest entry.
fn check(entry: &Value) -> Vec<String> {
    let file = entry["file"].as_str().expect("file");
    let model = match matrace::read_model(&sample(file)) {
        Ok(m) => m,
        Err(e) => return vec![format!("{file}: {e}")],
    };
    let class = matrace::classify(&model, &Default::default());
    let r = Report::new(&model, &class);
    let mut bad = vec![];
    let mut eq = |what: &str, got: Value, want: &Value| {
        if &got != want {
            bad.push(format!("{file}: {what}: got {got}, manifest says {want}"));
        }
    };
    eq("solids", r.model.solids.into(), &entry["solids"]);
    eq("shells", r.model.shells.into(), &entry["shells"]);
    eq("faces", r.model.counts.faces.into(), &entry["faces"]);
    eq("edges", r.model.counts.edges.into(), &entry["edges"]);
    eq(
        "vertices",
        r.model.counts.vertices.into(),
        &entry["vertices"],
    );
    let mut cmp = |what: &str, got: BTreeMap<String, u64>, want: BTreeMap<String, u64>| {
        if got != want {
            bad.push(format!(
                "{file}: {what}: got {got:?}, manifest says {want:?}"
            ));
        }
    };
    cmp(
        "surfaces",
        ours(&r.model.counts.surfaces),
        kinds(&entry["surfaces"]),
    );
    cmp(
        "edge kinds",
        ours(&r.model.counts.edge_kinds),
        kinds(&entry["edge_kinds"]),
    );
    cmp(
        "vertex kinds",
        ours(&r.model.counts.vertex_kinds),
        kinds(&entry["vertex_kinds"]),
    );
    let unit = entry["length_unit"].as_str().unwrap_or("mm");
    if r.input.file_unit != unit {
        bad.push(format!(
            "{file}: file unit {} (manifest {unit})",
            r.input.file_unit
        ));
    }
    // Bounding box in mm. Ours samples curves (128 points per edge), an inner estimate within
    // r·(1 − cos(π/128)) ≈ 3e-4·r of the exact box; 1e-3 of the diagonal covers it.
    let want: Vec<f64> = entry["bbox"]
        .as_array()
        .expect("bbox")
        .iter()
        .flat_map(|c| {
            c.as_array()
                .expect("corner")
                .iter()
                .map(|x| x.as_f64().expect("num"))
        })
        .collect();
    let got: Vec<f64> = r.model.bbox.iter().flatten().copied().collect();
    let tol = 1e-3 * r.model.diagonal;
    if got.iter().zip(&want).any(|(a, b)| (a - b).abs() > tol) {
        bad.push(format!("{file}: bbox {got:?}, manifest {want:?}"));
    }
    // Volume by the divergence theorem over the loops' fourth-order paths: within 1e-4 (the
    // worst sample, a NURBS cylinder, is at 2.4e-5).
    let want = entry["volume"].as_f64().expect("volume");
    let got: Option<f64> = r.model.volumes.iter().copied().sum();
    match got {
        Some(v) if (v - want).abs() <= 1e-4 * want => {}
        _ => bad.push(format!("{file}: volume {got:?} mm³, manifest {want}")),
    }
    bad
}

#[test]
fn every_sample_matches_its_manifest() {
    let m = manifest();
    let samples = m["samples"].as_array().expect("samples");
    assert!(
        samples.len() >= 25,
        "manifest lists {} samples",
        samples.len()
    );
    let bad: Vec<String> = samples.iter().flat_map(check).collect();
    assert!(
        bad.is_empty(),
        "{} differences:\n{}",
        bad.len(),
        bad.join("\n")
    );
}
