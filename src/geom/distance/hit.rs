//! What a distance query answers: the nearest point of a face or of the boundary, and the
//! element (face interior, edge, vertex) it lies on.

use crate::model::Element;
use glam::DVec3;

/// The nearest point of a face (or of the boundary) to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHit {
    /// The nearest point (on the face's surface, inside its trim or on one of its edges).
    pub point: DVec3,
    /// `‖p − point‖`, model units.
    pub distance: f64,
    /// Parameters of `point` on the face's surface: the hint for the next nearby query.
    pub uv: (f64, f64),
    /// The element the point lies on: the face (an interior foot point), an edge (not at its
    /// ends) or a vertex (an end of an open edge).
    pub on: Element,
    /// The curve parameter of the point when it lies on an edge.
    pub t: Option<f64>,
}

impl FaceHit {
    /// The edge and curve parameter of the point, when it lies on an edge.
    pub fn edge(&self) -> Option<(usize, f64)> {
        match (self.on, self.t) {
            (Element::Edge(e), Some(t)) => Some((e, t)),
            _ => None,
        }
    }
}
