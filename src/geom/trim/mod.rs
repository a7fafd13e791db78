//! Inside/outside a face's trimming loops, in UV space, and what else asks about the loops.
//!
//! A face is its surface restricted to the region its edge loops enclose in the face's
//! (unwrapped) UV space, [`Loop::uv`](crate::model::Loop::uv):
//! - [`contains`] decides whether a parameter point lies in that region (the ray-crossing test,
//!   with the loops' orientation where they wrap around a period), and [`Trim`] prepares a
//!   face's loops for many such tests with the same answers (`loops.rs`);
//! - [`covered_domain`] is the parameter rectangle the face covers, reaching beyond loops that
//!   wrap around a period to a pole no vertex loop records (`covered.rs`);
//! - [`path_crosses_loops`] tells whether a straight UV path leaves the face and comes back,
//!   reading only the [`LoopChunks`] near the path (`path.rs`);
//! - `TrimGrid` answers most inside tests of a face from a grid of cells classified inside,
//!   outside or near a loop, for the distance queries' cache (`grid.rs`).
//!
//! Points on a loop (to rounding) may be classified either way; callers that need the
//! boundary handle the edges separately (see [`super::distance`]).

mod covered;
mod grid;
mod loops;
mod path;
mod samples;

pub use covered::covered_domain;
pub(crate) use grid::TrimGrid;
pub use loops::{
    contains, Trim, DOMAIN_TOL_REL_WIDTH, MAX_COLUMNS, SEAM_TOL_REL_PERIOD, SEGMENTS_PER_COLUMN,
};
pub(crate) use loops::{is_edge_loop, wrap_near, wrapping};
pub use path::{path_crosses_loops, LoopChunks};
pub use samples::{edge_samples, SAMPLES_PER_CURVED_EDGE};
