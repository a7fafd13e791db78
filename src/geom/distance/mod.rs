//! Distance queries on the exact boundary: nearest point of a trimmed face, of an edge, of the
//! whole boundary (through a bounding-volume hierarchy), faces within a radius, and
//! point-in-solid.
//!
//! - `hit.rs`: what a query answers ([`FaceHit`]);
//! - `edge.rs`: the nearest point of an edge ([`nearest_on_edge`]);
//! - `face.rs`: the nearest point of a trimmed face ([`nearest_on_face`]), from a foot point
//!   on its surface ([`descend`] on B-spline and NURBS patches), its edges and its poles;
//! - `revolution.rs`: a surface of revolution's axis and profile samples, from which the
//!   search for a foot also starts in the plane through the axis and the point;
//! - `index.rs`: the boundary prepared for many queries ([`Boundary`]): cells with boxes over
//!   every curved face, edge samples with a cover radius, the faces' trim grids and a
//!   bounding-volume hierarchy over the faces;
//! - `query.rs`: the nearest point of the boundary and the faces within a radius, by branch
//!   and bound on a [`Boundary`];
//! - `normal.rs`: where a boundary point lies on a face, face normals and vertex
//!   pseudo-normals;
//! - `inside.rs`: point-in-solid ([`Boundary::contains_point`]), from the nearest point and
//!   the pseudo-normal there.
//!
//! **Limits.**
//! - The trim is the loops' UV polygons (`ingest::domain`, 32 samples per curved edge): a
//!   foot point in the sliver between a polygon chord and the exact edge is accepted although
//!   it is just outside the face (by at most the chord's sagitta, 0.5 % of a circle's radius),
//!   and one in the opposite sliver rejected (the edge then gives a point at most that much
//!   farther).
//! - The nearest point is only as global as the seeds: a face's foot point comes from the
//!   nearest cell centre (or the caller's hint), so a second, nearer basin of the distance
//!   inside the same face that no cell centre is closest to is missed (on a surface of
//!   revolution the plane through the axis and the point is searched too). Tested against
//!   dense brute force on every face of every sample and of the real-world corpus.
//! - Point-in-solid has the limits of its theorem (see `inside.rs`).
//!
//! All distances are in model units (millimetres).

mod edge;
mod face;
mod hit;
mod index;
mod inside;
mod normal;
mod query;
mod revolution;

pub use edge::{
    nearest_on_edge, MAX_DESCENT_HALVINGS, MAX_DESCENT_ITER, MAX_EDGE_SAMPLES, MIN_EDGE_SAMPLES,
    SAMPLES_PER_QUARTER_TURN, SAMPLES_PER_SPAN,
};
pub use face::{descend, nearest_on_face, EXTRA_SEED_GRID, FACE_SEED_GRID, MAX_EXTRA_SEEDS};
pub use hit::FaceHit;
pub use index::{
    Boundary, ARC_LENGTH_REL_CHORDS, CELL_CURVATURE_REL_CORNERS, MAX_FACE_GRID, MAX_TRIM_GRID,
    MIN_FACE_GRID, ON_BOUNDARY_REL_DIAGONAL,
};
pub use normal::{face_normal, EDGE_ON_SURFACE_REL_COORD, POLE_NORMAL_SAMPLES};
