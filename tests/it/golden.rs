//! Golden reports: `trace --verify` on three reference parts, compared with reports kept in
//! `tests/golden/` — the schema (every key path) exactly, and a stable subset of the content
//! with tolerances: seams (segments, how they end, their end points), junctions (point, radius,
//! segments), sheets (segments, boundary loops), topology, counts and options.
//!
//! Regenerate after an intended change with `MATRACE_BLESS=1 cargo test --test it golden`,
//! and review the diff of `tests/golden/` like code.

use crate::common::{matrace, root, sample};
use serde_json::{json, Value};
use std::collections::BTreeSet;

/// True when the goldens are to be rewritten: `MATRACE_BLESS=1`, and never under CI (a CI
/// run that rewrote its goldens would compare nothing). Any other value is a mistake.
fn blessing() -> bool {
    match std::env::var("MATRACE_BLESS").ok().as_deref() {
        None => false,
        Some("1") => {
            assert!(
                !crate::tools::under_ci(),
                "MATRACE_BLESS=1 under CI: the goldens are compared in CI, never rewritten"
            );
            true
        }
        Some(other) => panic!("MATRACE_BLESS={other:?}: set it to 1 to rewrite the goldens"),
    }
}

/// Every key path of a JSON value, arrays written `[]` (their elements merged).
fn key_paths(v: &Value, prefix: &str, out: &mut BTreeSet<String>) {
    match v {
        Value::Object(map) => {
            for (k, x) in map {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                out.insert(p.clone());
                key_paths(x, &p, out);
            }
        }
        Value::Array(items) => {
            for x in items {
                key_paths(x, &format!("{prefix}[]"), out);
            }
        }
        _ => {}
    }
}

/// The part of a report that must not change unless the medial axis changes: no timings, no
/// intermediate seam points (their spacing is the tracer's business), no solver counters.
fn stable(report: &Value) -> Value {
    let mat = &report["mat"];
    let seams: Vec<Value> = mat["seams"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let pts = s["points"].as_array().unwrap();
            json!({
                "segments": s["segments"],
                "end_segments": s["end_segments"],
                "ends": s["ends"],
                "first": pts.first().map(|p| p["point"].clone()),
                "last": pts.last().map(|p| p["point"].clone()),
            })
        })
        .collect();
    json!({
        "input": {"format": report["input"]["format"], "length_unit": report["input"]["length_unit"]},
        "options": {
            "accuracy": report["options"]["accuracy"],
            "diagonal": report["options"]["diagonal"],
            "fit_tolerance": report["options"]["fit_tolerance"],
        },
        "model": {
            "faces": report["model"]["faces"].as_array().unwrap().len(),
            "edges": report["model"]["edges"].as_array().unwrap().len(),
            "vertices": report["model"]["vertices"].as_array().unwrap().len(),
        },
        "seams": seams,
        "junctions": mat["junctions"],
        "sheets": mat["sheets"],
        "degenerate": mat["degenerate"],
        "topology": mat["topology"],
        "counts": {
            "seams": report["stats"]["seams"],
            "junctions": report["stats"]["junctions"],
            "sheets": report["stats"]["sheets"],
            "open_ends": report["stats"]["open_ends"],
        },
        "outputs": report["outputs"],
    })
}

/// Compares `got` with `want`: same shape, equal strings, integers and booleans, reals within
/// `tol`. Returns the first difference's path.
fn compare(got: &Value, want: &Value, tol: f64, path: &str) -> Result<(), String> {
    match (got, want) {
        (Value::Object(g), Value::Object(w)) => {
            let gk: BTreeSet<_> = g.keys().collect();
            let wk: BTreeSet<_> = w.keys().collect();
            if gk != wk {
                return Err(format!("{path}: keys {gk:?} != {wk:?}"));
            }
            for k in wk {
                compare(&g[k], &w[k], tol, &format!("{path}.{k}"))?;
            }
            Ok(())
        }
        (Value::Array(g), Value::Array(w)) => {
            if g.len() != w.len() {
                return Err(format!("{path}: {} items, golden {}", g.len(), w.len()));
            }
            for (i, (a, b)) in g.iter().zip(w).enumerate() {
                compare(a, b, tol, &format!("{path}[{i}]"))?;
            }
            Ok(())
        }
        (Value::Number(a), Value::Number(b)) if a.is_f64() || b.is_f64() => {
            let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            if (a - b).abs() <= tol {
                Ok(())
            } else {
                Err(format!("{path}: {a} != golden {b} (tolerance {tol:e})"))
            }
        }
        _ if got == want => Ok(()),
        _ => Err(format!("{path}: {got} != golden {want}")),
    }
}

fn traced(name: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let out = matrace(
        &[
            "trace",
            sample(&format!("{name}.step")).to_str().unwrap(),
            "-o",
            dir.path().to_str().unwrap(),
            "--verify",
            "--no-mesh",
        ],
        &root(),
    );
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.path().join(format!("{name}.mat.json"))).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn check(name: &str) {
    let report = traced(name);
    let golden_dir = root().join("tests/golden");
    let mut paths = BTreeSet::new();
    key_paths(&report, "", &mut paths);
    let schema: String = paths.iter().map(|p| format!("{p}\n")).collect();
    let got = stable(&report);
    let golden_path = golden_dir.join(format!("{name}.json"));
    let schema_path = golden_dir.join(format!("{name}.schema.txt"));
    if blessing() {
        std::fs::create_dir_all(&golden_dir).unwrap();
        std::fs::write(
            &golden_path,
            serde_json::to_string_pretty(&got).unwrap() + "\n",
        )
        .unwrap();
        std::fs::write(&schema_path, &schema).unwrap();
        return;
    }
    let want_schema = std::fs::read_to_string(&schema_path).expect("golden schema");
    if schema != want_schema {
        let want: BTreeSet<&str> = want_schema.lines().collect();
        let have: BTreeSet<&str> = schema.lines().collect();
        panic!(
            "{name}: report schema changed (bump `matrace.report/N` if intended, then bless)\n  new: {:?}\n  gone: {:?}",
            have.difference(&want).collect::<Vec<_>>(),
            want.difference(&have).collect::<Vec<_>>()
        );
    }
    let want: Value =
        serde_json::from_str(&std::fs::read_to_string(&golden_path).unwrap()).unwrap();
    // Coordinates and radii to 10× the trace accuracy (1e-6 × diagonal): the golden values are
    // the same computation, so only a change of the medial axis itself moves them that far.
    let tol = 10.0 * want["options"]["accuracy"].as_f64().unwrap();
    if let Err(e) = compare(&got, &want, tol, name) {
        panic!("{name}: report differs from tests/golden/{name}.json: {e}");
    }
}

#[test]
fn golden_box() {
    check("box");
}

#[test]
fn golden_l_bracket() {
    check("l_bracket");
}

#[test]
fn golden_plate_with_holes() {
    check("plate_with_holes");
}

/// The comparison itself: a moved junction, a lost seam or a renamed key is caught.
#[test]
fn golden_comparison_catches_changes() {
    let a = json!({"j": [{"point": [1.0, 2.0, 3.0], "segments": ["F0", "F1"]}], "n": 4});
    assert!(compare(&a, &a, 1e-9, "x").is_ok());
    let moved = json!({"j": [{"point": [1.0, 2.0, 3.001], "segments": ["F0", "F1"]}], "n": 4});
    assert!(compare(&moved, &a, 1e-6, "x")
        .unwrap_err()
        .contains("x.j[0].point[2]"));
    assert!(compare(&moved, &a, 1e-2, "x").is_ok());
    let renamed = json!({"j": [{"point": [1.0, 2.0, 3.0], "segments": ["F0", "F2"]}], "n": 4});
    assert!(compare(&renamed, &a, 1e-2, "x").is_err());
    let fewer = json!({"j": [], "n": 4});
    assert!(compare(&fewer, &a, 1e-2, "x")
        .unwrap_err()
        .contains("0 items"));
    let key = json!({"j": [], "m": 4});
    assert!(compare(&key, &a, 1e-2, "x").unwrap_err().contains("keys"));
}
