//! [`Tolerances`]: the absolute tolerances of one run, built once from the part's size and
//! the user's options, carried to every stage and written to the report.
//!
//! Naming rule for every tolerance and repeated factor in the crate: `<WHAT>_REL_<OF>` is a
//! factor relative to something (`SOLVER_TOL_REL_ACCURACY`: the solver's tolerance is this
//! times the accuracy), `_MM` an absolute length, `_RAD`/`_DEG` an angle, `MAX_*`/`MIN_*` a
//! budget or bound. `accuracy` is the bound on output error; `tol` an equality or merge
//! distance.

/// Default output accuracy, relative to the part's bounding-box diagonal.
pub const DEFAULT_ACCURACY_REL_DIAGONAL: f64 = 1e-6;
/// The coarsest accuracy a run accepts, relative to the diagonal: a ball off by more could lie
/// anywhere across a wall that thin, so no check could hold a medial axis to it (`--verify`
/// refuses a coarser one too).
pub const MAX_ACCURACY_REL_DIAGONAL: f64 = 1e-3;
/// Newton's residual target relative to the trace accuracy: residuals well inside it.
pub const SOLVER_TOL_REL_ACCURACY: f64 = 1e-3;
/// Default fit tolerance (largest distance from a traced point to its fitted curve, and
/// largest radius error), relative to the diagonal. The seams are exported for looking at
/// and for downstream CAD use: 1e-4 × the diagonal is 10 µm on a 100 mm part, below typical
/// machining tolerances and far below what a screen shows, yet 100× looser than the trace
/// accuracy, so a seam needs only a few control points per bend instead of one per traced
/// point.
pub const DEFAULT_FIT_TOL_REL_DIAGONAL: f64 = 1e-4;
/// Default angle (degrees) below which two faces meeting at an edge count as tangent: 1°.
/// CAD tangency is exact to far better than this; true creases in parts are rarely below a
/// few degrees.
pub const DEFAULT_ANGLE_TOL_DEG: f64 = 1.0;

/// Where the accuracy came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccuracySource {
    /// [`DEFAULT_ACCURACY_REL_DIAGONAL`] × the diagonal.
    Default,
    /// Given by the user (`--accuracy`).
    User,
}

impl AccuracySource {
    /// As the report writes it: `"1e-6 x diagonal"` or `"--tol"` (the option's name when
    /// reports began; `--tol` is still accepted as an alias of `--accuracy`).
    pub fn as_str(&self) -> &'static str {
        match self {
            AccuracySource::Default => "1e-6 x diagonal",
            AccuracySource::User => "--tol",
        }
    }
}

/// The absolute tolerances (mm, or degrees where named so) of one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// The part's bounding-box diagonal, the scale of every default.
    pub diagonal: f64,
    /// Output accuracy: every ball is medial to within it, every junction located to it.
    pub accuracy: f64,
    pub accuracy_from: AccuracySource,
    /// The accuracy the medial axis is computed to: the output accuracy, or the default
    /// ([`DEFAULT_ACCURACY_REL_DIAGONAL`] × the diagonal) where that is finer. The tracer's
    /// events (a ball reaching `r = 0`, an intrusion by more than it, two touch points one
    /// place) are decided to it, so a coarse output accuracy never lets them swallow the
    /// part's features: the same medial axis comes out at every accuracy, fitted and
    /// checked to the one asked for.
    pub trace: f64,
    /// Newton's residual target: [`SOLVER_TOL_REL_ACCURACY`] × the trace accuracy.
    pub solver: f64,
    /// Largest distance from a traced point to its seam's fitted B-spline (and largest
    /// radius error); never below the accuracy.
    pub fit: f64,
    /// Faces meeting at less than this angle (degrees) are tangent.
    pub angle_deg: f64,
}

impl Tolerances {
    /// The defaults for a part of bounding-box diagonal `diagonal`.
    pub fn for_diagonal(diagonal: f64) -> Tolerances {
        let accuracy = DEFAULT_ACCURACY_REL_DIAGONAL * diagonal;
        Tolerances {
            diagonal,
            accuracy,
            accuracy_from: AccuracySource::Default,
            trace: accuracy,
            solver: SOLVER_TOL_REL_ACCURACY * accuracy,
            fit: (DEFAULT_FIT_TOL_REL_DIAGONAL * diagonal).max(accuracy),
            angle_deg: DEFAULT_ANGLE_TOL_DEG,
        }
    }

    /// The defaults, with the accuracy and the fit tolerance given where `Some` (a fit
    /// tolerance below the accuracy is raised to it: fitting closer than the points are
    /// known is meaningless). Refuses lengths that are not positive and finite, and an
    /// accuracy coarser than [`MAX_ACCURACY_REL_DIAGONAL`] × the diagonal.
    pub fn new(
        diagonal: f64,
        accuracy: Option<f64>,
        fit: Option<f64>,
    ) -> Result<Tolerances, String> {
        let mut t = Tolerances::for_diagonal(diagonal);
        for (name, v) in [("accuracy", accuracy), ("fit tolerance", fit)] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(format!(
                    "the {name} must be a positive length in mm, got {v}"
                ));
            }
        }
        if let Some(a) = accuracy {
            let most = MAX_ACCURACY_REL_DIAGONAL * diagonal;
            if a > most {
                return Err(format!(
                    "the accuracy {a} mm is coarser than the part allows: at most \
                     {MAX_ACCURACY_REL_DIAGONAL} × its bounding-box diagonal {diagonal:.4} mm, \
                     {most:.3e} mm (a ball that far off could lie anywhere across a wall that \
                     thin); for a coarser fit of the seams, use --fit-tol"
                ));
            }
            t.accuracy = a;
            t.accuracy_from = AccuracySource::User;
            t.trace = a.min(t.trace);
            t.solver = SOLVER_TOL_REL_ACCURACY * t.trace;
            t.fit = (DEFAULT_FIT_TOL_REL_DIAGONAL * diagonal).max(a);
        }
        if let Some(f) = fit {
            t.fit = f.max(t.accuracy);
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_scale_with_the_diagonal() {
        let t = Tolerances::for_diagonal(100.0);
        assert_eq!(t.accuracy, 1e-6 * 100.0);
        assert_eq!(t.solver, 1e-3 * t.accuracy);
        assert_eq!(t.trace, t.accuracy);
        assert_eq!(t.fit, 1e-4 * 100.0);
        assert_eq!(t.accuracy_from, AccuracySource::Default);
        assert_eq!(Tolerances::new(100.0, None, None), Ok(t));
    }

    #[test]
    fn given_lengths_are_checked_and_the_fit_never_below_the_accuracy() {
        let t = Tolerances::new(100.0, Some(0.05), None).unwrap();
        assert_eq!((t.accuracy, t.fit), (0.05, 0.05));
        assert_eq!(t.accuracy_from.as_str(), "--tol");
        // Traced to the default where that is finer, to the accuracy where it is finer.
        let default = Tolerances::for_diagonal(100.0);
        assert_eq!((t.trace, t.solver), (default.accuracy, default.solver));
        let t = Tolerances::new(100.0, Some(1e-9), None).unwrap();
        assert_eq!((t.accuracy, t.trace, t.solver), (1e-9, 1e-9, 1e-3 * 1e-9));
        // Coarser than 1e-3 of the diagonal: refused, saying the most it may be.
        assert_eq!(
            Tolerances::new(100.0, Some(0.09), None).unwrap().accuracy,
            0.09
        );
        let e = Tolerances::new(100.0, Some(0.1000001), None).unwrap_err();
        assert!(e.contains("at most") && e.contains("1.000e-1 mm"), "{e}");
        let t = Tolerances::new(100.0, None, Some(1e-9)).unwrap();
        assert_eq!(t.fit, t.accuracy);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(Tolerances::new(100.0, Some(bad), None).is_err(), "{bad}");
            assert!(Tolerances::new(100.0, None, Some(bad)).is_err(), "{bad}");
        }
    }
}
