//! The medial axis: its equations, their solver, the tracer, the sheets and the checks.
//!
//! A ball of centre `B` and radius `r` touches boundary element *i* tangentially when
//! `B = Pᵢ(sᵢ) − r·Nᵢ(sᵢ)`, with `(Pᵢ, Nᵢ)` the element's *normal field* (a face: its points
//! and outward unit normals). Two elements give a sheet point, three a seam point, four a
//! junction. [`equations`] states those equations with analytic Jacobians and [`solver`]
//! solves them by damped Newton; [`trace`] follows seams from convex vertices and seeds,
//! locating junctions; [`sheets`] finds the sheets from their boundaries and
//! [`sheet_mesh`] samples them; [`verify`] checks a result against the definition and its
//! topology. The results are the types of [`axis`].

pub mod axis;
pub mod equations;
pub mod maximal;
pub mod segments;
pub mod sheet_mesh;
pub mod sheets;
pub mod solver;
pub mod trace;
pub mod verify;

pub use axis::{
    Degenerate, DegenerateEnd, DegenerateKind, DegenerateOpen, Handover, Junction, MedialAxis,
    Node, OpenReason, Seam, SeamEnd, SeamPoint, SkeletalEdge, TraceStats,
};
pub use equations::{FieldEval, MedialSystem, NormalField};
pub use sheet_mesh::{sheet_mesh, MeshOptions, SheetMesh};
pub use sheets::{sheets, BoundaryRef, Sheet, Sheets, SolidEuler};
pub use solver::{solve, Solution, SolveOptions, SolveStatus};
pub use trace::{trace, trace_with_boundary, trace_with_seeds, Seed, TraceOptions};
pub use verify::{verify, Topology, Verification};
