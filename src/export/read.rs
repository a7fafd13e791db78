//! Reading a report back: the medial axis it describes and the accuracy it claims, for
//! verifying any report against its part (`matrace verify`).

use crate::medial::{Degenerate, Junction, MedialAxis, Seam, SkeletalEdge, TraceStats};

/// What verification needs of a report.
#[derive(Clone, Debug)]
pub struct ReportedAxis {
    /// The seams, junctions, degenerate pieces and skeletal edges, as the report gives them.
    pub axis: MedialAxis,
    /// The accuracy the report claims (mm).
    pub accuracy: f64,
    /// The faces' tangency angle the report was made with (degrees).
    pub angle_tol_deg: f64,
    /// The part the report says it describes, as written there.
    pub input_path: String,
    /// The sheets the report lists (`None` in a report without `mat.sheets`).
    pub sheets: Option<Vec<crate::medial::verify::ListedSheet>>,
}

/// Reads the medial axis and the options of a report (`matrace.report/1`). The error says
/// which part of the report is missing or malformed.
pub fn read_report(text: &str) -> Result<ReportedAxis, String> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    if v["schema"] != super::report::SCHEMA {
        return Err(format!(
            "schema is {}, not {}",
            v["schema"],
            super::report::SCHEMA
        ));
    }
    let mat = &v["mat"];
    let field = |name: &str| -> Result<serde_json::Value, String> {
        match &mat[name] {
            serde_json::Value::Null => Err(format!("mat.{name} is missing")),
            x => Ok(x.clone()),
        }
    };
    let seams: Vec<Seam> =
        serde_json::from_value(field("seams")?).map_err(|e| format!("mat.seams: {e}"))?;
    let junctions: Vec<Junction> =
        serde_json::from_value(field("junctions")?).map_err(|e| format!("mat.junctions: {e}"))?;
    let degenerate: Vec<Degenerate> =
        serde_json::from_value(field("degenerate")?).map_err(|e| format!("mat.degenerate: {e}"))?;
    // Reports made before skeletal edges were traced have none.
    let skeletal_edges: Vec<SkeletalEdge> = match &mat["skeletal_edges"] {
        serde_json::Value::Null => vec![],
        x => serde_json::from_value(x.clone()).map_err(|e| format!("mat.skeletal_edges: {e}"))?,
    };
    // A NaN is written as null: read it back as NaN, so that verification fails on it.
    let number = |x: &serde_json::Value, what: &str| -> Result<f64, String> {
        match x {
            serde_json::Value::Null => Ok(f64::NAN),
            x => x.as_f64().ok_or_else(|| format!("{what} is not a number")),
        }
    };
    let sheets = match &mat["sheets"] {
        serde_json::Value::Null => None,
        x => Some(serde_json::from_value(x.clone()).map_err(|e| format!("mat.sheets: {e}"))?),
    };
    let accuracy = number(&v["options"]["accuracy"], "options.accuracy")?;
    let angle_tol_deg = number(&v["options"]["angle_tol_deg"], "options.angle_tol_deg")?;
    Ok(ReportedAxis {
        axis: MedialAxis {
            seams,
            junctions,
            degenerate,
            skeletal_edges,
            stats: TraceStats::default(),
        },
        accuracy,
        angle_tol_deg,
        input_path: v["input"]["path"].as_str().unwrap_or_default().to_string(),
        sheets,
    })
}
