//! The outcome of a verification: each check counted (made, failed), the first failures
//! with where they are, and the worst errors.

use serde::Serialize;
use std::collections::BTreeMap;

/// Failures kept in a [`Verification`] (the counts cover all of them).
pub const MAX_FAILURES_KEPT: usize = 100;

/// How often one check was made, and how often it failed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct CheckCount {
    pub checked: usize,
    pub failed: usize,
}

/// The outcome of verifying a medial axis.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Verification {
    /// Balls checked: seam points, junctions, degenerate balls.
    pub balls: usize,
    /// Worst `|d(B, ∂Ω) − r|` (mm; NaN when any was not a number).
    pub worst_distance_error: f64,
    /// Worst `|‖t − B‖ − r|` over touch points.
    pub worst_touch_error: f64,
    /// Worst distance of a touch point from the boundary.
    pub worst_touch_off_boundary: f64,
    /// Where the worst of the three errors is: `seam S point K`, `junction J`, …
    pub worst_at: Option<String>,
    /// The accuracy the errors were held to (mm).
    pub accuracy: f64,
    /// Every check by name: how often it was made and how often it failed.
    pub checks: BTreeMap<&'static str, CheckCount>,
    /// The first [`MAX_FAILURES_KEPT`] failures, each saying where and what.
    pub failures: Vec<String>,
    /// Ball errors beyond the accuracy that were held to the accuracy plus the file's own
    /// gap there (edges written off their faces' surfaces, `Face::gap_mm`), and the largest
    /// such error (mm; 0 when none).
    pub held_to_gap: usize,
    pub largest_gap_held: f64,
    /// Solids whose medial axis's Euler characteristic is not counted, with why.
    pub euler_withheld: Vec<String>,
    /// True when no check failed.
    pub ok: bool,
}

impl Verification {
    /// The largest of the three errors (NaN when any is).
    pub fn worst(&self) -> f64 {
        nan_max(
            nan_max(self.worst_distance_error, self.worst_touch_error),
            self.worst_touch_off_boundary,
        )
    }

    /// Sets `ok`: every check passed, and every error beyond the accuracy passed its check
    /// only within the file's own gap there (`held_to_gap`); a NaN passes neither comparison.
    pub(super) fn settle(&mut self) {
        let worst = self.worst();
        self.ok = self.checks.values().all(|c| c.failed == 0)
            && (worst <= self.accuracy || (self.held_to_gap > 0 && worst <= self.largest_gap_held));
    }

    /// Failures by check, the checks that failed only (`{"separated": 3}`).
    pub fn failed_checks(&self) -> BTreeMap<&'static str, usize> {
        self.checks
            .iter()
            .filter(|(_, c)| c.failed > 0)
            .map(|(k, c)| (*k, c.failed))
            .collect()
    }

    /// Records one check: made, and failed unless `passed` (then `what` says where and why).
    pub(super) fn record(
        &mut self,
        check: &'static str,
        passed: bool,
        what: impl FnOnce() -> String,
    ) {
        let c = self.checks.entry(check).or_default();
        c.checked += 1;
        if !passed {
            c.failed += 1;
            if self.failures.len() < MAX_FAILURES_KEPT {
                self.failures.push(format!("{check}: {}", what()));
            }
        }
    }
}

/// The larger of two numbers, NaN when either is (`f64::max` would drop the NaN).
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}
