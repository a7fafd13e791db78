//! Verification of a medial axis against the definition, point by point, and of its graph.
//!
//! A point `B` with radius `r` is on the medial axis of a solid Ω when `B` is inside Ω, its
//! nearest boundary points are at distance `r`, and there are at least two of them in
//! separate places (three along a seam, four at a junction). [`verify`] checks that for every
//! ball a result holds, to the result's accuracy `a` (itself checked first, `accuracy`: it
//! must be positive and at most [`MAX_ACCURACY_REL_DIAGONAL`] × the diagonal):
//! - every number is finite (a NaN is a failure, never a pass);
//! - `inside`: the centre is inside the ball's solid (point in solid by the pseudo-normal);
//! - `distance`: `|d(B, ∂Ω) − r| ≤ a`, with the exact trimmed-face distance: nothing of the
//!   boundary is closer than `r`, so the ball is maximal in the global sense;
//! - `touch_on_boundary` and `touch_at_radius`: every reported touch point `t` is on the
//!   boundary (`d(t, ∂Ω) ≤ a`) and on the ball (`|‖t − B‖ − r| ≤ a`);
//! - `separated`: the touch points lie in enough separate places (the most of them that are
//!   pairwise separate) — two touch points count as separate when they are farther apart
//!   than `√(8·r·e)`, the chord over which a sphere of radius `r` and a surface tangent to it
//!   stay within `e` of each other, so that one smooth contact cannot pass for two (`e` the
//!   ball's own error — its distance's and its touch points' — where finer than `a`, and no
//!   finer than 1e-7 mm or 1e-9 of the diagonal: a touch point that close to another on
//!   one contact would be off the ball by more than that error); or when they are on one
//!   edge that curls round the ball between them (the second derivative of the squared
//!   distance along it is at most what the accuracy of the centre allows: the distance has a
//!   maximum between them, as near the edge's centre of curvature). Seam points need 3
//!   places (2 at a curvature-limit end, where the ball osculates a face, and at a pinch,
//!   where two touch points meet at a vertex), junctions 4, degenerate balls 2. A ball with
//!   `r ≤ a` (a seam's end at a convex vertex) is a point and is exempt from this and from
//!   `inside`. A seam point the seam lists as `unresolved` (a junction marked so) needs one
//!   place fewer where the geometry explains the shortfall: the touch points closer than the separation are on faces that meet (a
//!   shallow crease, a sliver face), found from where they are, or on the face of the
//!   element where the seam ends at its curvature limit or a pinch.
//!
//! Then the graph ([`topology`]): every seam end is proper (a convex vertex, a junction, a
//! closed loop, a curvature limit, or a pinch whose two touch points are at its vertex to
//! `a`; an open end is a failure), every generic junction has
//! four seam ends and every junction a seam names exists, every sheet's boundary closes,
//! where the Euler characteristic of a solid's medial axis is counted it equals the solid's
//! (where it is withheld, that is listed), every face of every solid is touched by some ball,
//! and every convex vertex is the end of a seam. The sheets and the Euler characteristics
//! are computed afresh from the seams given, not taken from a report; a report's own list of
//! sheets is then held to them ([`check_listed_sheets`], `matrace verify`).
//!
//! [`Verification`] counts each check (made, failed), keeps the first failures with where
//! they are, and the worst errors; `ok` only when nothing failed.

mod balls;
mod limits;
mod outcome;
pub mod topology;

pub use balls::{junction_unresolved, separation, unresolved_points};
pub use outcome::{nan_max, CheckCount, Verification, MAX_FAILURES_KEPT};
pub use topology::{check_topology, Topology};

use crate::classify::Classification;
use crate::geom::Boundary;
use crate::medial::axis::MedialAxis;
use crate::model::Model;

pub use crate::model::tolerances::MAX_ACCURACY_REL_DIAGONAL;

/// Verifies `axis` against `model` to `accuracy` (mm): every ball, then the graph, as the
/// module docs say. `class` is the model's classification (for convex vertices, mixed edges
/// and the sheets).
pub fn verify(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    axis: &MedialAxis,
    accuracy: f64,
) -> Verification {
    let mut v = Verification {
        accuracy,
        ..Default::default()
    };
    // An accuracy that is not a small positive length would let anything pass.
    let diagonal = model.diagonal();
    v.record(
        "accuracy",
        accuracy > 0.0 && accuracy <= MAX_ACCURACY_REL_DIAGONAL * diagonal,
        || {
            format!(
                "the accuracy {accuracy:e} mm is not in (0, {MAX_ACCURACY_REL_DIAGONAL} × the \
                 diagonal {diagonal:.4} mm]"
            )
        },
    );
    balls::check_balls(model, boundary, axis, accuracy, &mut v);
    // The graph's checks index the model by the elements the axis names: only when they
    // all exist.
    if topology::check_elements(model, axis, &mut v) {
        topology::check_graph(model, boundary, class, axis, &mut v);
    }
    v.settle();
    v
}

/// A sheet as a report lists it: its solid and its boundary loops.
#[derive(Clone, Debug, serde::Deserialize)]
pub struct ListedSheet {
    pub solid: usize,
    pub loops: Vec<Vec<crate::medial::BoundaryRef>>,
}

/// Holds the sheets a report lists (`listed`) to the ones its medial axis bounds (found
/// again from `axis`, as [`verify`] does): per solid, `sheets_listed` (the same sheets, each
/// with the same loops of seams, rims, skeletal edges and rounds' axes), and `euler` counted
/// with the listed sheets in place of the found ones, where the count is made at all. So a
/// report with a sheet taken out, or a loop, fails on the Euler characteristic: a medial
/// axis with a sheet fewer is not the solid's. Settles `v.ok` again.
pub fn check_listed_sheets(
    model: &Model,
    class: &Classification,
    axis: &MedialAxis,
    listed: &[ListedSheet],
    v: &mut Verification,
) {
    let found = crate::medial::sheets(model, class, axis);
    // A sheet as a sorted list of sorted loops: the order of loops and arcs is not meaning.
    let key = |loops: &[Vec<crate::medial::BoundaryRef>]| {
        let mut loops: Vec<Vec<_>> = loops
            .iter()
            .map(|l| {
                let mut l = l.clone();
                l.sort();
                l
            })
            .collect();
        loops.sort();
        loops
    };
    for e in &found.solids {
        let mut mine: Vec<_> = found
            .sheets
            .iter()
            .filter(|s| s.solid == e.solid)
            .map(|s| key(&s.loops))
            .collect();
        let mut theirs: Vec<_> = listed
            .iter()
            .filter(|s| s.solid == e.solid)
            .map(|s| key(&s.loops))
            .collect();
        mine.sort();
        theirs.sort();
        v.record("sheets_listed", mine == theirs, || {
            format!(
                "solid {}: the report lists {} sheets, the medial axis bounds {} ({} listed \
                 that it does not bound)",
                e.solid,
                theirs.len(),
                mine.len(),
                theirs.iter().filter(|t| !mine.contains(t)).count()
            )
        });
        let Some(chi) = e.mat_euler else { continue };
        let sum = |sheets: &[Vec<Vec<crate::medial::BoundaryRef>>]| -> i64 {
            sheets.iter().map(|s| 2 - s.len() as i64).sum()
        };
        let claimed = chi - sum(&mine) + sum(&theirs);
        v.record("euler", claimed == e.solid_euler, || {
            format!(
                "solid {}: with the report's sheets the medial axis has Euler characteristic \
                 {claimed}, the solid {}",
                e.solid, e.solid_euler
            )
        });
    }
    v.settle();
}
