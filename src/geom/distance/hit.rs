//! What a distance query answers: the nearest point of a face or of the boundary, and the
//! feature (face interior, edge, vertex) it lies on.

use glam::DVec3;

/// Which feature of the boundary a nearest point lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feature {
    /// Inside face `0` (an interior foot point).
    Face(usize),
    /// On edge `0` at curve parameter `1` (not at its ends).
    Edge(usize, f64),
    /// At vertex `0` (an end of an open edge).
    Vertex(usize),
}

/// The nearest point of a face (or of the boundary) to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHit {
    /// The nearest point (on the face's surface, inside its trim or on one of its edges).
    pub point: DVec3,
    /// `‖p − point‖`, model units.
    pub distance: f64,
    /// Parameters of `point` on the face's surface: the hint for the next nearby query.
    pub uv: (f64, f64),
    /// The feature the point lies on.
    pub on: Feature,
}
