//! Maximality of a ball beyond the medial equations: the curvature criterion.
//!
//! A solution of the medial equations is only a bisector point; it is on the medial axis
//! when, besides nothing of the boundary being closer than `r` (a distance query, done by
//! the tracer), the ball does not poke through a face it touches.

use crate::model::{Element, Model};

/// Rounding allowance of the criterion `r·κmax ≤ 1`, relative (balls that osculate exactly,
/// a sphere's centre).
pub const CURVATURE_ROUNDING_REL: f64 = 1e-9;

/// The curvature criterion at a touch point: a ball of radius `r` tangent to the face from
/// inside stays inside near the touch point only if `r·κmax ≤ 1`, with `κmax` the larger
/// principal curvature (positive where the face bends towards the ball, as a convex solid's
/// boundary does). Where the normal is undefined (a pole) the criterion cannot fail.
pub fn curvature_allows(model: &Model, seg: Element, s: [f64; 2], r: f64) -> bool {
    match seg {
        Element::Face(f) => {
            let face = &model.faces[f];
            let d = crate::geom::eval_surface(&face.surface, s[0], s[1]);
            match crate::geom::principal_curvatures(&d, face.sign) {
                Some(k) => r * k.k1 <= 1.0 + CURVATURE_ROUNDING_REL,
                None => true,
            }
        }
        // Reflex edges and vertices bend away from every ball that touches them from inside.
        Element::Edge(_) | Element::Vertex(_) => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sphere sample (radius 15, outward normals): a ball of radius 14 fits against its
    /// wall, one of radius 16 pokes through; a plane never fails.
    #[test]
    fn curvature_criterion_on_a_sphere() {
        let m = crate::testing::sample("sphere.step");
        let s = [1.0, 0.3];
        assert!(curvature_allows(&m, Element::Face(0), s, 14.0));
        assert!(curvature_allows(&m, Element::Face(0), s, 15.0));
        assert!(!curvature_allows(&m, Element::Face(0), s, 16.0));
        let b = crate::testing::sample("box.step");
        assert!(curvature_allows(&b, Element::Face(0), [1.0, 1.0], 1e6));
    }
}
