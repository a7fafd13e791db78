//! The batch summary, schema `matrace.batch/1`: one record per part, `summary.json` and
//! `summary.csv`, written atomically.

use super::inputs::Input;
use super::options::{BatchOptions, PartOptions};
use super::shard::Shard;
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The schema name written into `summary.json`.
pub const SCHEMA: &str = "matrace.batch/1";

/// Longest error message in the summary (characters).
const ERROR_MAX_CHARS: usize = 2000;

/// How a part ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PartStatus {
    /// Traced, every output written (and verified within the accuracy, when verifying).
    Ok,
    /// An error, a crash, or a verification above the accuracy: see the message.
    Failed,
    /// Killed at the time limit.
    Timeout,
}

impl PartStatus {
    pub fn as_str(&self) -> &'static str {
        match self {
            PartStatus::Ok => "ok",
            PartStatus::Failed => "failed",
            PartStatus::Timeout => "timeout",
        }
    }
}

/// One line of the summary.
#[derive(Clone, Debug, Serialize)]
pub struct PartRecord {
    /// The input file.
    pub part: String,
    /// Output location inside the output folder, without suffixes (`sub/part`).
    pub output: String,
    pub status: PartStatus,
    /// Not run: its outputs were complete (`--resume`); the numbers are its report's.
    pub resumed: bool,
    pub error: Option<String>,
    pub faces: Option<usize>,
    pub seams: Option<usize>,
    pub junctions: Option<usize>,
    /// Open seam ends (`stats.open_ends` of the report), and how many for each reason
    /// (`stats.open_ends_by_reason`; empty without a report).
    pub open_ends: Option<usize>,
    pub open_ends_by_reason: BTreeMap<String, usize>,
    /// Degenerate-curve ends not located (`stats.degenerate_open_ends`), and by cause
    /// (`stats.degenerate_open_ends_by_reason`; empty without a report, or in a report
    /// written before they were counted).
    pub degenerate_open_ends: Option<usize>,
    pub degenerate_open_ends_by_reason: BTreeMap<String, usize>,
    /// The trace's own time (`stats.seconds` of its report) when it has one, else the
    /// wall-clock time of the failed attempt.
    pub seconds: f64,
    /// Worst verification error (mm) when verified.
    pub worst_error: Option<f64>,
    /// Output files written, relative to the output folder.
    pub outputs: Vec<String>,
}

/// Per-status counts.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Counts {
    pub ok: usize,
    pub failed: usize,
    pub timeout: usize,
    /// Parts skipped by `--resume` (counted in `ok`, or in `failed` when their report shows a
    /// verification above the accuracy).
    pub resumed: usize,
    /// Open seam ends over every part with a report, and by reason: where the tracer still
    /// gives up over a library.
    pub open_ends: usize,
    pub open_ends_by_reason: BTreeMap<String, usize>,
    /// Degenerate-curve ends not located over every part with a report, and by cause.
    pub degenerate_open_ends: usize,
    pub degenerate_open_ends_by_reason: BTreeMap<String, usize>,
}

impl Counts {
    /// The counts of `parts`.
    pub fn of(parts: &[PartRecord]) -> Counts {
        let mut counts = Counts::default();
        for p in parts {
            match p.status {
                PartStatus::Ok => counts.ok += 1,
                PartStatus::Failed => counts.failed += 1,
                PartStatus::Timeout => counts.timeout += 1,
            }
            counts.resumed += usize::from(p.resumed);
            counts.open_ends += p.open_ends.unwrap_or(0);
            for (why, n) in &p.open_ends_by_reason {
                *counts.open_ends_by_reason.entry(why.clone()).or_default() += n;
            }
            counts.degenerate_open_ends += p.degenerate_open_ends.unwrap_or(0);
            for (why, n) in &p.degenerate_open_ends_by_reason {
                *counts
                    .degenerate_open_ends_by_reason
                    .entry(why.clone())
                    .or_default() += n;
            }
        }
        counts
    }
}

/// The options a batch ran with, as written into the summary.
#[derive(Clone, Debug, Serialize)]
pub struct SummaryOptions {
    #[serde(flatten)]
    pub part: PartOptions,
    pub resume: bool,
}

/// `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub schema: &'static str,
    /// `K/N` when sharded.
    pub shard: Option<String>,
    /// Inputs found before sharding.
    pub inputs: usize,
    pub jobs: usize,
    pub timeout_seconds: Option<f64>,
    /// The address-space limit actually applied to each part (`null`: none).
    pub memory_limit_bytes: Option<u64>,
    pub options: SummaryOptions,
    pub counts: Counts,
    /// Wall-clock seconds of the whole batch.
    pub seconds: f64,
    /// One record per part, in input order.
    pub parts: Vec<PartRecord>,
}

impl Summary {
    /// True when every part is `ok`.
    pub fn all_ok(&self) -> bool {
        self.counts.failed == 0 && self.counts.timeout == 0
    }
}

/// The summary record of a part from its report.
pub(super) fn record_from_report(
    input: &Input,
    opts: &BatchOptions,
    report: &serde_json::Value,
    resumed: bool,
) -> PartRecord {
    let stats = &report["stats"];
    let count = |v: &serde_json::Value| v.as_u64().map(|n| n as usize);
    let verification = stats["verification"].as_object();
    // The worst of the three errors; a NaN (written as null) is the worst of all.
    let worst_error = verification.map(|v| {
        [
            "worst_distance_error",
            "worst_touch_error",
            "worst_touch_off_boundary",
        ]
        .iter()
        .map(|k| v.get(*k).and_then(|x| x.as_f64()).unwrap_or(f64::NAN))
        .fold(0.0, crate::medial::verify::nan_max)
    });
    let mut error = None;
    if let Some(v) = verification.filter(|v| v.get("ok") != Some(&serde_json::Value::Bool(true))) {
        let failed: Vec<String> = v
            .get("checks")
            .and_then(|c| c.as_object())
            .into_iter()
            .flatten()
            .filter_map(|(k, c)| {
                let n = c["failed"].as_u64().unwrap_or(0);
                (n > 0).then(|| format!("{k} {n}"))
            })
            .collect();
        error = Some(format!(
            "{}: verification failed: {}",
            input.path.display(),
            if failed.is_empty() {
                "the report says so".to_string()
            } else {
                failed.join(", ")
            }
        ));
    }
    let dir_rel = input.out_rel.parent().unwrap_or(Path::new(""));
    PartRecord {
        part: input.path.display().to_string(),
        output: input.out_rel.display().to_string(),
        status: if error.is_some() {
            PartStatus::Failed
        } else {
            PartStatus::Ok
        },
        resumed,
        error,
        faces: report["model"]["faces"].as_array().map(|f| f.len()),
        seams: count(&stats["seams"]),
        junctions: count(&stats["junctions"]),
        open_ends: count(&stats["open_ends"]),
        open_ends_by_reason: by_reason(&stats["open_ends_by_reason"]),
        degenerate_open_ends: count(&stats["degenerate_open_ends"]),
        degenerate_open_ends_by_reason: by_reason(&stats["degenerate_open_ends_by_reason"]),
        seconds: stats["seconds"].as_f64().unwrap_or(0.0),
        worst_error,
        outputs: opts
            .output_names(&input.stem())
            .iter()
            .map(|o| dir_rel.join(o).display().to_string())
            .collect(),
    }
}

/// A report's counts by reason (`{"left_face": 2, …}`); empty where it has none.
fn by_reason(v: &serde_json::Value) -> BTreeMap<String, usize> {
    v.as_object()
        .into_iter()
        .flatten()
        .filter_map(|(why, n)| Some((why.clone(), n.as_u64()? as usize)))
        .collect()
}

/// A record for a part that did not finish.
pub(super) fn failed_record(
    input: &Input,
    status: PartStatus,
    error: String,
    seconds: f64,
) -> PartRecord {
    let mut error = error;
    if error.chars().count() > ERROR_MAX_CHARS {
        error = error.chars().take(ERROR_MAX_CHARS).collect::<String>() + " …";
    }
    PartRecord {
        part: input.path.display().to_string(),
        output: input.out_rel.display().to_string(),
        status,
        resumed: false,
        error: Some(error),
        faces: None,
        seams: None,
        junctions: None,
        open_ends: None,
        open_ends_by_reason: BTreeMap::new(),
        degenerate_open_ends: None,
        degenerate_open_ends_by_reason: BTreeMap::new(),
        seconds,
        worst_error: None,
        outputs: vec![],
    }
}

/// Writes `summary.json` and `summary.csv` (or `summary.K-of-N.*` for a shard) into
/// `out_dir`, atomically; returns the JSON path.
pub fn write_summary(summary: &Summary, out_dir: &Path, shard: Option<Shard>) -> Result<PathBuf> {
    let name = |ext: &str| match shard {
        Some(s) => s.summary_name(ext),
        None => format!("summary.{ext}"),
    };
    let json_path = out_dir.join(name("json"));
    let json = serde_json::to_string_pretty(summary).map_err(|e| Error::Write {
        path: json_path.clone(),
        source: std::io::Error::other(e),
    })?;
    crate::export::write_atomic(&out_dir.join(name("csv")), summary_csv(summary).as_bytes())?;
    crate::export::write_atomic(&json_path, (json + "\n").as_bytes())?;
    Ok(json_path)
}

/// The CSV table:
/// `part,status,error,faces,seams,junctions,seconds,worst_error,resumed,output,open_ends,`
/// `degenerate_open_ends`
/// (RFC 4180 quoting; empty cells for unknown numbers).
pub fn summary_csv(summary: &Summary) -> String {
    let mut s = String::from(
        "part,status,error,faces,seams,junctions,seconds,worst_error,resumed,output,open_ends,\
         degenerate_open_ends\n",
    );
    let num = |n: Option<usize>| n.map(|n| n.to_string()).unwrap_or_default();
    for p in &summary.parts {
        let cells = [
            csv_cell(&p.part),
            p.status.as_str().to_string(),
            csv_cell(p.error.as_deref().unwrap_or("")),
            num(p.faces),
            num(p.seams),
            num(p.junctions),
            format!("{:.3}", p.seconds),
            p.worst_error.map(|w| format!("{w:e}")).unwrap_or_default(),
            p.resumed.to_string(),
            csv_cell(&p.output),
            num(p.open_ends),
            num(p.degenerate_open_ends),
        ];
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

fn csv_cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(status: PartStatus, open: Option<(usize, &[(&str, usize)])>) -> PartRecord {
        PartRecord {
            part: "p.step".into(),
            output: "p".into(),
            status,
            resumed: false,
            error: None,
            faces: None,
            seams: None,
            junctions: None,
            open_ends: open.map(|(n, _)| n),
            open_ends_by_reason: open
                .map(|(_, by)| by.iter().map(|(k, n)| (k.to_string(), *n)).collect())
                .unwrap_or_default(),
            // One open degenerate end wherever a report has open seam ends.
            degenerate_open_ends: open.map(|(n, _)| usize::from(n > 0)),
            degenerate_open_ends_by_reason: open
                .filter(|(n, _)| *n > 0)
                .map(|_| [("left_face".to_string(), 1)].into())
                .unwrap_or_default(),
            seconds: 0.0,
            worst_error: None,
            outputs: vec![],
        }
    }

    #[test]
    fn counts_add_open_ends_by_reason_over_parts() {
        let parts = [
            record(PartStatus::Ok, Some((0, &[]))),
            record(
                PartStatus::Failed,
                Some((3, &[("no_junction", 2), ("reached_edge", 1)])),
            ),
            record(PartStatus::Failed, Some((2, &[("no_junction", 2)]))),
            record(PartStatus::Timeout, None),
        ];
        let c = Counts::of(&parts);
        assert_eq!((c.ok, c.failed, c.timeout), (1, 2, 1));
        assert_eq!(c.open_ends, 5);
        let by: Vec<(&str, usize)> = c
            .open_ends_by_reason
            .iter()
            .map(|(k, n)| (k.as_str(), *n))
            .collect();
        assert_eq!(by, [("no_junction", 4), ("reached_edge", 1)]);
        assert_eq!(c.degenerate_open_ends, 2);
        assert_eq!(c.degenerate_open_ends_by_reason["left_face"], 2);
        let csv = summary_csv(&Summary {
            schema: SCHEMA,
            shard: None,
            inputs: 4,
            jobs: 1,
            timeout_seconds: None,
            memory_limit_bytes: None,
            options: SummaryOptions {
                part: PartOptions::default(),
                resume: false,
            },
            counts: c,
            seconds: 0.0,
            parts: parts.to_vec(),
        });
        let rows: Vec<&str> = csv.lines().collect();
        assert!(
            rows[0].ends_with(",output,open_ends,degenerate_open_ends"),
            "{}",
            rows[0]
        );
        assert!(rows[2].ends_with(",p,3,1"), "{}", rows[2]);
        assert!(rows[4].ends_with(",p,,"), "{}", rows[4]);
    }

    #[test]
    fn csv_cells_are_quoted() {
        assert_eq!(csv_cell("a.step"), "a.step");
        assert_eq!(csv_cell("x, \"y\""), "\"x, \"\"y\"\"\"");
    }
}
