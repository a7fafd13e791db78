//! `--resume`: a part whose outputs are complete, and made with the same options, is not
//! traced again.

use super::inputs::Input;
use super::options::BatchOptions;

/// The report of `input` if its outputs are complete and were made with `opts`: the report
/// `<stem>.mat.json` exists, parses, is not older than the input file, lists exactly the
/// outputs `opts` asks for, every one of them exists, and its options agree with `opts`
/// (verify, mesh, picture, `--accuracy`, `--fit-tol`; `--with-solid` is not recorded in reports and
/// not checked).
pub fn completed_report(input: &Input, opts: &BatchOptions) -> Option<serde_json::Value> {
    let dir = input.out_dir(&opts.out_dir);
    let stem = input.stem();
    let path = dir.join(format!("{stem}.mat.json"));
    let report_time = std::fs::metadata(&path).and_then(|m| m.modified()).ok()?;
    let input_time = std::fs::metadata(&input.path)
        .and_then(|m| m.modified())
        .ok()?;
    if input_time > report_time {
        return None;
    }
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).ok()?).ok()?;
    let outputs: Vec<&str> = report["outputs"]
        .as_array()?
        .iter()
        .map(|o| o.as_str())
        .collect::<Option<_>>()?;
    if outputs != opts.output_names(&stem) || !outputs.iter().all(|o| dir.join(o).is_file()) {
        return None;
    }
    let o = &report["options"];
    let same = o["verify"].as_bool() == Some(opts.part.verify)
        && (o["mesh_samples"].as_u64() != Some(0)) == opts.part.mesh
        && match opts.part.accuracy {
            Some(t) => o["accuracy_from"] == "--tol" && o["accuracy"].as_f64() == Some(t),
            None => o["accuracy_from"] != "--tol",
        }
        && opts.part.fit_tol.is_none_or(|t| {
            o["fit_tolerance"].as_f64() == Some(t.max(o["accuracy"].as_f64().unwrap_or(0.0)))
        });
    same.then_some(report)
}
