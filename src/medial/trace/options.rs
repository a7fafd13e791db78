//! The tracer's options and budgets.

use crate::model::{Model, Tolerances};

/// Largest centre step, relative to the diagonal.
pub const MAX_STEP_REL_DIAGONAL: f64 = 0.02;
/// Smallest centre step before a seam is abandoned, relative to the diagonal.
pub const MIN_STEP_REL_DIAGONAL: f64 = 1e-9;
/// The first step of a march, relative to the diagonal.
pub const FIRST_STEP_REL_DIAGONAL: f64 = 1e-3;
/// Largest turn of the seam's direction over one step (radians): the step control by seam
/// curvature. A step that turns more is retried at half the length, so consecutive points are
/// never more than this apart in direction and the chord between them stays within
/// `h·MAX_TURN_RAD/8` of the curve.
pub const MAX_TURN_RAD: f64 = 0.15;
/// Largest turn of a touch point's edge over one step (radians): the curve's tangent at the
/// touch point may turn this much. Where a small arc is touched by a large ball, the touch
/// point runs round it much faster than the centre turns, and a step whose linear predictor
/// overshoots lands the corrector on another foot of the ball on that arc (the far side of a
/// rib's rounded end) — a different seam, not the next point. Looser than [`MAX_TURN_RAD`]:
/// it bites only where the touch point outruns the centre.
pub const MAX_TOUCH_TURN_RAD: f64 = 0.5;
/// Budget of points per seam.
pub const MAX_POINTS: usize = 20_000;
/// Hand-overs in a row, with no ordinary step between, after which a march ends as
/// oscillating (a touch point handed between a vertex and its edges without the seam moving).
/// A seam passing a corner needs a few (onto an edge, its vertex, the next edge, a face).
pub const MAX_HANDOVERS_IN_PLACE: usize = 8;
/// Points a face no seam touches is sampled at, at least, for seeds (the grid over its domain
/// made finer until as many of its cells' centres are on the face).
pub const MIN_FACE_SAMPLES: usize = 4;
/// Most cells a side of the sampling grid over a face's domain (a face covering less than
/// about `MIN_FACE_SAMPLES / MAX_SAMPLE_GRID²` of its domain may get fewer samples).
pub const MAX_SAMPLE_GRID: usize = 32;
/// Steps of a walk across a face's domain from a sample to its end, looking for the seam that
/// bounds the sampled ball's sheet: a change of the segment touched between two steps is
/// bracketed by bisection (two changes within one step are not seen).
pub const WALK_STEPS: usize = 8;
/// Budget of seams per part (guards against a tracer loop on unexpected geometry).
pub const MAX_SEAMS: usize = 10_000;
/// Distance between unit directions under which a branch leaving a junction is the seam that
/// arrived there (its tangent a step before the junction), where the elements cannot tell.
pub const SAME_BRANCH: f64 = 0.05;
/// Newton iterations of a corrector step (and of the other polishing solves).
pub const MAX_CORRECTOR_ITER: usize = 12;
/// Newton iterations when refining a seed, or solving a junction from a seam point.
pub const MAX_REFINE_ITER: usize = 30;
/// Most steps of the shrinking ball that brackets a maximal ball's radius.
pub const SHRINK_STEPS: usize = 60;
/// Newton iterations of a step that fixes only the centre's advance (near an end).
pub const MAX_CENTRE_STEP_ITER: usize = 40;

/// Growth of the step after a corrector that converged in at most
/// [`FAST_CONVERGENCE_ITER`] iterations (up to [`MAX_STEP_REL_DIAGONAL`]).
pub const STEP_GROWTH: f64 = 1.5;
/// Shrinking of the step after a corrector that needed more iterations.
pub const STEP_SHRINK: f64 = 0.7;
/// Corrector iterations that count as fast convergence.
pub const FAST_CONVERGENCE_ITER: usize = 3;

/// Points, or radii, closer than this times the accuracy are taken as the same (a seam back
/// at its seed, a junction found twice, a touch point at an edge's end or at a vertex, a ball
/// too small to be told from a convex edge).
pub const SAME_PLACE_REL_ACCURACY: f64 = 10.0;
/// How far, in accuracies, a centre may be from the vertex it lands at, or a touch point from
/// the edge it is taken to have crossed.
pub const REACH_REL_ACCURACY: f64 = 1e3;
/// A crossing whose ball is within this many accuracies of nothing may stand for the convex
/// vertex ahead (a fin folded to its tip): the rest of the seam is within a quarter of the
/// radius of the chord to it.
pub const TIP_REL_ACCURACY: f64 = 4.0;
/// How near (radians) the seam's direction must point to the vertex a crossing stands for.
pub const TIP_AHEAD_RAD: f64 = 0.1;
/// Two touch points closer than this times `r` are one place, when refining a seed or a
/// junction (the solve found one touch twice) or sampling a ball (it osculates the face).
pub const DISTINCT_TOUCH_REL_RADIUS: f64 = 1e-3;
/// While marching, two touch points closer than this times `r` have met: the centre is then
/// within about `(1e-4·r)²/ρ` of the end, far below the accuracy.
pub const MERGED_TOUCH_REL_RADIUS: f64 = 1e-4;
/// A ball within this relative margin of osculating an element (`r·κmax ≥ 1 − margin`)
/// counts as osculating it.
pub const OSCULATING_REL_RADIUS: f64 = 1e-6;
/// Two unit directions closer than this are one direction.
pub const SAME_DIRECTION: f64 = 1e-9;
/// Allowance for rounding in comparisons of quantities of order one (angles in radians, dot
/// products and determinants of unit vectors, relative lengths).
pub const UNIT_ROUNDING: f64 = 1e-9;

/// Options of [`crate::medial::trace`].
#[derive(Clone, Debug)]
pub struct TraceOptions {
    /// The trace accuracy in model units (mm; `Tolerances::trace`): residuals of every
    /// point, and junction location.
    pub accuracy: f64,
    /// Newton's residual target (mm), well inside the accuracy.
    pub solver_tol: f64,
    /// Two reflex edges meeting at less than this angle (radians) continue each other: a
    /// touch point runs on from one into the other.
    pub tangent_angle_rad: f64,
}

impl TraceOptions {
    /// The tracer's share of a run's tolerances.
    pub fn new(tol: &Tolerances) -> TraceOptions {
        TraceOptions {
            accuracy: tol.trace,
            solver_tol: tol.solver,
            tangent_angle_rad: tol.angle_deg.to_radians(),
        }
    }

    /// Defaults for a model: the default tolerances of its diagonal.
    pub fn for_model(model: &Model) -> TraceOptions {
        TraceOptions::new(&Tolerances::for_diagonal(model.diagonal()))
    }
}
