//! Regenerating the reference solids with the scripts gives the same topology as the
//! committed files (the generators are deterministic; see scripts/README.md). Needs FreeCAD,
//! OpenSCAD and the OCP venv (`scripts/setup_tools.sh`); without them the test is skipped
//! loudly, and under CI it fails (see `tools.rs`).

use crate::common::{root, sample};
use crate::tools::{require, Tool};

#[test]
fn regenerated_samples_have_the_same_topology() {
    if !require(
        "regenerate::regenerated_samples_have_the_same_topology",
        &[Tool::FreeCad, Tool::OpenScad, Tool::Occt],
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new("bash")
        .arg(root().join("scripts/make_samples.sh"))
        .arg(dir.path())
        .current_dir(root())
        .output()
        .expect("run make_samples.sh");
    assert!(
        out.status.success(),
        "make_samples.sh failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let mut compared = 0;
    let mut bad = vec![];
    for entry in std::fs::read_dir(root().join("samples")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("step") {
            continue;
        }
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let fresh = dir.path().join(&name);
        let (a, b) = match (
            matrace::read_model(&sample(&name)),
            matrace::read_model(&fresh),
        ) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                bad.push(format!(
                    "{name}: committed {:?} / regenerated {:?}",
                    a.err(),
                    b.err()
                ));
                continue;
            }
        };
        let ca = matrace::classify(&a, &Default::default());
        let cb = matrace::classify(&b, &Default::default());
        let sig = |m: &matrace::Model, c: &matrace::Classification| {
            (
                m.solids.len(),
                m.shells.len(),
                m.faces
                    .iter()
                    .map(|f| matrace::geom::surface_kind(&f.surface))
                    .collect::<Vec<_>>(),
                c.edges.iter().map(|e| e.kind).collect::<Vec<_>>(),
                c.vertices.clone(),
            )
        };
        if sig(&a, &ca) != sig(&b, &cb) {
            bad.push(format!("{name}: topology differs after regeneration"));
        }
        compared += 1;
    }
    assert!(compared >= 25, "only {compared} samples compared");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn regenerated_trace_regression_parts_match_their_manifest() {
    regenerated_parts_match_their_manifest(
        "regenerate::regenerated_trace_regression_parts_match_their_manifest",
        "scripts/freecad/make_trace_regressions.py",
        "samples/trace",
    );
}

#[test]
fn regenerated_distance_regression_parts_match_their_manifest() {
    regenerated_parts_match_their_manifest(
        "regenerate::regenerated_distance_regression_parts_match_their_manifest",
        "scripts/freecad/make_distance_regressions.py",
        "samples/distance",
    );
}

/// Running a FreeCAD `script` that writes parts and their `manifest.json` gives the manifest
/// committed in `samples_dir`, and parts of the same topology.
fn regenerated_parts_match_their_manifest(test: &str, script: &str, samples_dir: &str) {
    if !require(test, &[Tool::FreeCad]) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new("/usr/bin/python3")
        .arg(root().join(script))
        .arg(dir.path())
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| panic!("run {script}: {e}"));
    assert!(
        out.status.success(),
        "{script} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let read = |p: std::path::PathBuf| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let committed = read(root().join(samples_dir).join("manifest.json"));
    let fresh = read(dir.path().join("manifest.json"));
    assert_eq!(
        committed, fresh,
        "the regenerated manifest differs from {samples_dir}/manifest.json"
    );
    for p in committed["parts"].as_array().unwrap() {
        let name = p["file"].as_str().unwrap();
        let a = matrace::read_model(&root().join(samples_dir).join(name)).unwrap();
        let b = matrace::read_model(&dir.path().join(name)).unwrap();
        // The faces' kinds as a multiset: the order of the faces a boolean returns is not
        // stable from run to run (the threaded bottle's fuse gives its 59 faces in another
        // order now and then), and is no part of the topology.
        let sig = |m: &matrace::Model| {
            let mut kinds: Vec<_> = m
                .faces
                .iter()
                .map(|f| matrace::geom::surface_kind(&f.surface))
                .collect();
            kinds.sort_unstable();
            (m.faces.len(), m.edges.len(), m.vertices.len(), kinds)
        };
        assert_eq!(
            sig(&a),
            sig(&b),
            "{name}: topology differs after regeneration"
        );
    }
}

#[test]
fn nurbs_variants_classify_like_the_originals() {
    for (orig, nurbs) in [
        ("box.step", "box_nurbs.step"),
        ("l_bracket.step", "l_bracket_nurbs.step"),
        ("cylinder.step", "cylinder_nurbs.step"),
        ("sphere.step", "sphere_nurbs.step"),
    ] {
        let a = matrace::read_model(&sample(orig)).unwrap();
        let b = matrace::read_model(&sample(nurbs)).unwrap();
        let ca = matrace::classify(&a, &Default::default());
        let cb = matrace::classify(&b, &Default::default());
        let kinds = |c: &matrace::Classification| {
            let mut e: Vec<_> = c.edges.iter().map(|e| e.kind.name()).collect();
            let mut v: Vec<_> = c.vertices.iter().map(|v| v.name()).collect();
            e.sort();
            v.sort();
            (e, v)
        };
        assert_eq!(kinds(&ca), kinds(&cb), "{orig} vs {nurbs}");
        assert!(
            b.faces
                .iter()
                .all(|f| matches!(matrace::geom::surface_kind(&f.surface), "nurbs" | "bspline")),
            "{nurbs} is not free-form"
        );
        // Same geometry: the same box to within the sampling of the bounding box.
        let (la, ha) = a.bounding_box();
        let (lb, hb) = b.bounding_box();
        let tol = 1e-3 * a.diagonal();
        assert!(
            la.distance(lb) < tol && ha.distance(hb) < tol,
            "{orig}: {la} {ha} vs {lb} {hb}"
        );
    }
}

#[test]
fn void_shell_normals_point_into_the_void() {
    // box_with_void: a spherical void inside a box. Its face's outward (out-of-material)
    // normal must point towards the sphere's centre.
    let m = matrace::read_model(&sample("box_with_void.step")).unwrap();
    assert_eq!(m.solids.len(), 1);
    assert_eq!(m.solids[0].shells.len(), 2);
    let void = &m.shells[m.solids[0].shells[1]];
    assert!(void.is_void);
    let face = &m.faces[void.faces[0]];
    assert_eq!(matrace::geom::surface_kind(&face.surface), "sphere");
    // The sphere's centre: the mean of its points over the domain grid.
    let mut pts = vec![];
    for i in 0..8 {
        for j in 1..8 {
            let u = face.domain.u.0 + (face.domain.u.1 - face.domain.u.0) * i as f64 / 8.0;
            let v = face.domain.v.0 + (face.domain.v.1 - face.domain.v.0) * j as f64 / 8.0;
            pts.push((u, v));
        }
    }
    let centre = pts
        .iter()
        .map(|&(u, v)| matrace::geom::eval_surface(&face.surface, u, v).p)
        .sum::<glam::DVec3>()
        / pts.len() as f64;
    for (u, v) in pts {
        let d = matrace::geom::eval_surface(&face.surface, u, v);
        let n = d.su.cross(d.sv).normalize() * face.sign;
        assert!(
            n.dot(centre - d.p) > 0.99 * (centre - d.p).length(),
            "normal {n} at {}",
            d.p
        );
    }
    // And the outer shell's normals point away from the box's centre.
    let outer = &m.shells[m.solids[0].shells[0]];
    assert!(!outer.is_void);
    let (lo, hi) = m.bounding_box();
    let mid = (lo + hi) * 0.5;
    for &f in &outer.faces {
        let face = &m.faces[f];
        let (u, v) = (
            0.5 * (face.domain.u.0 + face.domain.u.1),
            0.5 * (face.domain.v.0 + face.domain.v.1),
        );
        let d = matrace::geom::eval_surface(&face.surface, u, v);
        let n = d.su.cross(d.sv).normalize() * face.sign;
        assert!(
            n.dot(d.p - mid) > 0.0,
            "outer face F{f} normal {n} at {}",
            d.p
        );
    }
}
