//! Seam tracing by pseudo-arclength continuation (Ramanathan & Gurumoorthy 2005, §4; Allgower
//! & Georg's predictor–corrector, the paper's ref. \[1\]).
//!
//! A seam is a curve of the 3-segment medial system (9 equations, 10 unknowns). From a known
//! point `x` with unit tangent `t` (the null vector of the Jacobian, scaled so that its centre
//! part `t_B` has unit length), the predictor is `x + h·t` and the corrector solves the square
//! system `[F(x); t_B·(B − B_pred)] = 0` (the hyperplane across the centre's direction; see
//! `docs/design.md`, continuation). The step `h` (millimetres of centre travel) grows when
//! the corrector converges in few iterations, shrinks when it needs many, and halves when it
//! fails or the seam turns by more than [`MAX_TURN_RAD`].
//!
//! Segments (the paper's word) are faces, reflex edges and reflex (or mixed) vertices
//! ([`Element`](crate::model::Element)). Seams start
//! at convex vertices (`r = 0`), leaving along each direction that moves equally away from
//! three tangent planes and no slower from the others; then from seeds: maximal balls sampled
//! on faces no seam touches (holes, solids without corners), and on the sheets of reflex edges
//! no seam touches, where the element the ball touches besides the edge changes (the closed
//! loop of seams round a shallow pocket). A seam ends
//! - at a junction, when another part of the solid comes closer than `r` (located by
//!   bisection, then exactly by the 4-segment system); the other triplets leave along the
//!   normal of the plane through their touch points, in the sense in which the omitted
//!   segment moves away;
//! - at a convex vertex, when `r` returns to 0;
//! - at a curvature limit, where the ball osculates a face (two touch points on one face
//!   meet, or the curvature criterion fails): a skeletal edge starts there;
//! - at a pinch, where two touch points on different segments meet at a vertex both reach
//!   (a hole tangent to a slot's wall): located exactly on the normal line there (`pinch`);
//!   where the two that meet (here or at a curvature limit) are on one part of the boundary,
//!   at a vertex of it (a box standing on a plate, below each of its vertical edges), the
//!   sheet ends along the straight line of balls touching that vertex alone: its skeletal
//!   edge, from the seam's end to the vertex (`skeletal`);
//! - closed, back at its seed;
//! - or open, with the reason, where none of these is reached.
//!
//! A touch point that leaves its segment is handed over: across a smooth edge to the next
//! face, onto and off reflex edges, from a reflex edge into the next one or onto its vertex,
//! onto and off a cone's apex (a drill point's tip).

//!
//! The files: [`options`] (options and budgets), `entry` (the public functions), `tracer`
//! (state and model queries), `unknowns` (the layout of the unknowns), `queue`, `starts`,
//! `seeds`, `arcs` (seeds on reflex edges' sheets), `march`, `limits` (curvature limits of a
//! march), `handover`, `junctions`, `pinch`,
//! `skeletal` (skeletal edges at vertices), `degenerate` (degenerate curves traced), `apex` (cone apexes at vertices),
//! `join` (seam halves that stop at one place, joined), `contacts` (non-generic seams: more
//! than three elements touching every ball), `merge` (junctions found twice, merged), `through` (seams carried across a junction, dropped).

mod apex;
mod arcs;
mod contacts;
mod degenerate;
mod degenerate_join;
mod entry;
mod handover;
mod join;
mod junctions;
mod limits;
mod march;
mod merge;
pub mod options;
mod pinch;
mod queue;
mod seeds;
mod shrink;
mod skeletal;
mod starts;
#[cfg(test)]
mod tests;
mod through;
mod tracer;
mod unknowns;

pub use entry::{trace, trace_with_boundary, trace_with_seeds};
pub use options::{
    TraceOptions, MAX_POINTS, MAX_SEAMS, MAX_STEP_REL_DIAGONAL, MAX_TURN_RAD, MIN_STEP_REL_DIAGONAL,
};
pub use seeds::Seed;
