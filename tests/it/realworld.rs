//! The third-party corpus (`../shared/realworld`): every file is one closed solid; our
//! counts must equal what the file defines (ADVANCED_FACE / EDGE_CURVE / VERTEX_POINT
//! entities, counted from the text independently of the reader), units must come out in mm
//! with OCCT's exact bounding box.

use crate::common::realworld_dir;

/// Counts `NAME(` occurrences of an entity at the start of an instance body.
fn count_entities(text: &str, name: &str) -> usize {
    text.split(';')
        .filter(|inst| {
            inst.split_once('=').is_some_and(|(_, body)| {
                let body = body.trim_start();
                body.strip_prefix(name)
                    .is_some_and(|r| r.trim_start().starts_with('('))
            })
        })
        .count()
}

/// (file, file unit, bbox extents in mm): OCCT 8.0.1's exact (optimal) box of the file's
/// solids, `BRepBndLib::AddOptimal(solid, box, false, false)` over every solid of the shape
/// (MANIFEST.md's boxes are the enlarged ones, and CTC 01's and FTC 06's include more than
/// the solid).
const CORPUS: &[(&str, &str, [f64; 3])] = &[
    ("axom_tet.step", "cm", [20.0, 20.0, 20.0]),
    (
        "axom_sliced_cylinder.step",
        "cm",
        [100.0, 200.0, 137.167464],
    ),
    ("axom_revolved_sphere.step", "mm", [10.0, 10.0, 10.0]),
    (
        "stepswift_nist_ctc_01_asme1_rd.stp",
        "mm",
        [800.0, 450.0, 150.0],
    ),
    (
        "stepswift_nist_ftc_06_asme1_rd.stp",
        "inch",
        [304.8, 97.79, 247.65],
    ),
    (
        "stepswift_nist_ftc_09_asme1_rd.stp",
        "inch",
        [190.5, 3.03784, 279.4],
    ),
    (
        "stepswift_nist_ftc_11_asme1_rb.stp",
        "mm",
        [63.0, 63.0, 3.0],
    ),
    ("trimesh_featuretype.STEP", "inch", [127.0, 63.5, 34.925]),
    (
        "b3d_M6-1x12-countersunk-screw.step",
        "mm",
        [10.229794, 10.363604, 12.0],
    ),
];

#[test]
fn every_realworld_solid_reads_with_all_its_entities_and_units() {
    let Some(dir) = realworld_dir() else {
        crate::tools::require(
            "realworld::every_realworld_solid_reads_with_all_its_entities_and_units",
            &[crate::tools::Tool::Corpus],
        );
        return;
    };
    let mut bad = vec![];
    for (file, unit, extent) in CORPUS {
        let path = dir.join(file);
        let text = std::fs::read_to_string(&path).expect("read");
        let model = match matrace::read_model(&path) {
            Ok(m) => m,
            Err(e) => {
                bad.push(format!("{e}"));
                continue;
            }
        };
        let class = matrace::classify(&model, &Default::default());
        let r = matrace::export::report::Report::new(&model, &class);
        let want = (
            count_entities(&text, "ADVANCED_FACE"),
            count_entities(&text, "EDGE_CURVE"),
            count_entities(&text, "VERTEX_POINT"),
        );
        let got = (model.faces.len(), model.edges.len(), model.vertices.len());
        if got != want {
            bad.push(format!(
                "{file}: faces/edges/vertices {got:?}, file defines {want:?}"
            ));
        }
        if model.solids.len() != 1 {
            bad.push(format!("{file}: {} solids", model.solids.len()));
        }
        if r.input.file_unit != *unit {
            bad.push(format!(
                "{file}: unit {} (expected {unit})",
                r.input.file_unit
            ));
        }
        // Our box samples edges and faces, so it is an inner estimate of the exact one: never
        // larger (beyond OCCT's 6 printed decimals), and short by at most the sampling's sag
        // (a circle sampled 128 times: 3e-4 of its radius; a torus's 32-step grid on FTC 11:
        // 9e-4 mm of 3 mm), within 1e-4 of the diagonal on every part here.
        let diag = model.diagonal();
        for (k, want) in extent.iter().enumerate() {
            let e = r.model.bbox[1][k] - r.model.bbox[0][k];
            if e > want + 1e-6 || e < want - 1e-4 * diag {
                bad.push(format!(
                    "{file}: extent[{k}] = {e:.6} mm; OCCT's exact box {want}"
                ));
            }
        }
        // Every edge of a closed solid has two faces and a kind; no NaN angle.
        for (i, e) in class.edges.iter().enumerate() {
            if !(e.angle_range_deg.0.is_finite() && e.angle_range_deg.1.is_finite()) {
                bad.push(format!("{file}: E{i} has a non-finite dihedral angle"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn entity_counter_counts_instances_not_references() {
    let text = "DATA;\n#1=ADVANCED_FACE('',(#2),#3,.T.);\n#4 = ADVANCED_FACE('',(#5),#6,.F.);\n#7=FACE_BOUND('',#8,.T.);\nENDSEC;";
    assert_eq!(count_entities(text, "ADVANCED_FACE"), 2);
    assert_eq!(count_entities(text, "FACE_BOUND"), 1);
}
