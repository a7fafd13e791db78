//! The medial equations and their solver (DESIGN.md, "Geometry: the medial equations").
//!
//! A ball of centre `B` and radius `r` touches boundary segment *i* tangentially when
//! `B = Pᵢ(sᵢ) − r·Nᵢ(sᵢ)`, with `(Pᵢ, Nᵢ)` the segment's *normal field* (a face: its points
//! and outward unit normals). Two segments give a sheet point, three a seam point, four a
//! junction. This module states those equations with analytic Jacobians ([`equations`]) and
//! solves them by damped Newton ([`solver`]); the tracer builds on both.

pub mod equations;
pub mod sheet_mesh;
pub mod sheets;
pub mod solver;
pub mod trace;
pub mod verify;

pub use equations::{FieldEval, MedialSystem, Segment};
pub use sheet_mesh::{sheet_mesh, MeshOptions, SheetMesh};
pub use sheets::{sheets, BoundaryRef, Sheet, Sheets, SolidEuler};
pub use solver::{solve, Solution, SolveOptions, SolveStatus};
pub use trace::{
    trace, trace_with_boundary, trace_with_seeds, Degenerate, Handover, Junction, Mat, Seam,
    SeamEnd, SeamPoint, Seed, TraceOptions,
};
pub use verify::{verify, Verification};
