//! Fitting a traced seam with one clamped B-spline curve: the centres `[x, y, z]` and the
//! radius `r` as a fourth coordinate along the same parameter.
//!
//! The algorithm is the classic least-squares fit with adaptive knot placement (Piegl &
//! Tiller, *The NURBS Book*, 2nd ed., Springer 1997, §9.4.1 "least squares curve
//! approximation" and §9.4.4 "approximation to within a specified accuracy"), with the
//! parameter correction of Hoschek ("Intrinsic parametrization for approximation",
//! *Computer Aided Geometric Design* 5(1), 1988):
//!
//! 1. Parameters `tᵢ` by chord length of the centres, so the curve is parametrised roughly
//!    by arc length in millimetres (`t ∈ [0, L]`, `L` the polyline length).
//! 2. A straight seam within `tol` of the line between its ends is that line (degree 1, two
//!    control points). Otherwise degree `p = min(3, n − 1)`, starting with one Bézier span
//!    (`p + 1` control points).
//! 3. Solve `min Σ ‖C(tᵢ) − Qᵢ‖²` over the inner control points with the first and last
//!    control points fixed at the first and last traced points (so both ends interpolate;
//!    a closed seam, first point = last point, comes out as a clamped curve whose ends
//!    coincide).
//! 4. Measure every traced point's distance to the curve: evaluate at `tᵢ`, then project by
//!    Newton's method on `(C(t) − Q)·C′(t) = 0`; the radius error is `|r(t) − rᵢ|` at the
//!    projected parameter (the ball on the curve nearest the traced centre). Once the worst
//!    distance is within `CORRECTION_START_REL_TOL` tolerances and the projected parameters
//!    are still in order, they replace `tᵢ` for the next solve (parameter correction; on a
//!    poor curve projections would scramble the parameters).
//! 5. Stop when both errors are within `tol` at every traced point. Otherwise place new knots,
//!    first by equidistributing the error (a degree-`p` span of length `h` has error ~`h^(p+1)`,
//!    so a span with worst error `e` wants `(e/tol)^(1/(p+1))` spans: de Boor, *A Practical
//!    Guide to Splines*, ch. XII), which reaches a near-minimal count in a few rounds; once a
//!    redistribution makes the fit worse, go back to the last good knots and from then on
//!    only insert one knot in each span over the tolerance, at the median parameter of its
//!    points (nested spaces: the least-squares residual cannot grow). Knots that would leave
//!    a span without points, or closer than `MIN_KNOT_GAP_REL_RANGE` of the range, are
//!    dropped.
//! 6. When the knots would reach the number of points, or the round budget runs out,
//!    interpolate every point instead (averaged knots, §9.2.1): no error at the points. An
//!    interpolant clearly longer than the polyline swings between the points (very uneven
//!    spacing); then the polyline itself (degree 1) is the answer.
//!
//! Measured: a 2 rad helical arc of radius 10 sampled at 400 points needs 6, 11, 27 and 78
//! control points at 1e-2, 1e-4, 1e-6 and 1e-8 (chord-length parameters make the order h⁴),
//! in about 2 ms each; straight seams are lines.
//!
//! The least-squares normal equations `NᵀN P = Nᵀ Q` are banded (half-bandwidth `p`), so they
//! are solved by a banded Cholesky factorisation in `O(m p²)` instead of nalgebra's dense
//! `O(m³)` (seams have up to 20 000 points). A tiny ridge term pulls each control point
//! towards the traced point at its Greville abscissa, which keeps the system positive definite
//! when a knot span holds no point; its bias is ~`RIDGE_REL_MAX_DIAGONAL_ENTRY ×` the part
//! size, far below any tolerance, and the errors are measured after the fact anyway.
//!
//! What the tolerance guarantees: the distance from every traced point to the curve, and the
//! radius error there, are at most `tol` (reported as `max_error`, `max_radius_error`). It
//! says nothing between traced points; the tracer bounds the chord error of its own polyline
//! (see `medial::trace::MAX_TURN`), so the curve stays about as close to the true seam as the
//! polyline does, plus `tol`.
//!
//! The code: `seam` runs the rounds of one fit ([`fit_bspline`]), `knots` places the
//! parameters and knots, `least_squares` solves each round, `basis` evaluates the B-spline
//! basis, and `curve` is the result ([`SeamFit`]) with its evaluation and point projection.

mod basis;
mod curve;
mod knots;
mod least_squares;
mod seam;
#[cfg(test)]
mod test_support;

pub use curve::{SeamFit, MAX_NEWTON_STEPS};
pub use seam::{fit_bspline, MAX_DEGREE, MAX_ROUNDS};

use crate::medial::MedialAxis;
use rayon::prelude::*;
use serde::Serialize;

pub use crate::model::tolerances::DEFAULT_FIT_TOL_REL_DIAGONAL;

/// Options of [`fit_mat`].
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Largest distance (mm) from a traced point to the curve, and largest radius error.
    pub tol: f64,
}

impl FitOptions {
    /// Defaults for a part: [`DEFAULT_FIT_TOL_REL_DIAGONAL`] × its diagonal, never below the
    /// trace accuracy (fitting closer than the points are known is meaningless).
    pub fn for_model(diagonal: f64, accuracy: f64) -> FitOptions {
        FitOptions {
            tol: (DEFAULT_FIT_TOL_REL_DIAGONAL * diagonal).max(accuracy),
        }
    }
}

/// The report's summary of one fit.
#[derive(Clone, Debug, Serialize)]
pub struct FitSummary {
    pub seam: usize,
    pub degree: usize,
    pub control_points: usize,
    pub max_error: f64,
    pub max_radius_error: f64,
}

/// The report's `fit` object: the tolerance and each seam's summary.
#[derive(Clone, Debug, Serialize)]
pub struct FitReport {
    /// Fit tolerance (mm).
    pub tol: f64,
    pub worst_error: f64,
    pub worst_radius_error: f64,
    pub control_points: usize,
    pub seams: Vec<FitSummary>,
}

impl FitReport {
    /// Summarises `fits`, one per seam of `mat`, in order.
    pub fn new(mat: &MedialAxis, fits: &[SeamFit], tol: f64) -> FitReport {
        let seams: Vec<FitSummary> = mat
            .seams
            .iter()
            .zip(fits)
            .map(|(s, f)| FitSummary {
                seam: s.id,
                degree: f.degree,
                control_points: f.control_points.len(),
                max_error: f.max_error,
                max_radius_error: f.max_radius_error,
            })
            .collect();
        FitReport {
            tol,
            worst_error: seams.iter().map(|s| s.max_error).fold(0.0, f64::max),
            worst_radius_error: seams.iter().map(|s| s.max_radius_error).fold(0.0, f64::max),
            control_points: seams.iter().map(|s| s.control_points).sum(),
            seams,
        }
    }
}

/// Fits every degenerate curve of `mat` with two balls or more (its centres, a closed one's
/// back to its first), in the order of `mat.degenerate`; `None` for points and single balls.
pub fn fit_degenerate(mat: &MedialAxis, opts: &FitOptions) -> Vec<Option<SeamFit>> {
    use crate::medial::axis::{DegenerateEnd, DegenerateKind};
    mat.degenerate
        .par_iter()
        .map(|d| {
            if d.kind != DegenerateKind::Curve || d.balls.len() < 2 {
                return None;
            }
            let mut balls = d.balls.clone();
            if d.ends == [DegenerateEnd::Closed] {
                balls.push(d.balls[0]);
            }
            fit_bspline(&balls, opts.tol)
        })
        .collect()
}

/// Fits every seam of `mat` (in parallel), in the order of `mat.seams`. A seam without
/// points (the tracer never outputs one) gets a zero-length line at the origin.
pub fn fit_mat(mat: &MedialAxis, opts: &FitOptions) -> Vec<SeamFit> {
    mat.seams
        .par_iter()
        .map(|s| {
            let points: Vec<[f64; 4]> = s.points.iter().map(|p| p.point).collect();
            fit_bspline(&points, opts.tol).unwrap_or_else(|| SeamFit {
                degree: 1,
                knots: vec![0.0, 0.0, 1.0, 1.0],
                control_points: vec![[0.0; 3]; 2],
                radii: vec![0.0; 2],
                max_error: 0.0,
                max_radius_error: 0.0,
            })
        })
        .collect()
}
