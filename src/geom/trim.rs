//! Inside/outside a face's loops, in UV space.

use crate::brep::model::Face;
use glam::DVec2;

/// True when `uv` lies inside the trimmed face (even–odd rule over the face's edge loops).
///
/// Placeholder until the full version (periodic faces, wrapping loops) lands: correct for
/// faces whose loops are closed polygons in UV.
pub fn contains(face: &Face, uv: DVec2) -> bool {
    let mut inside = false;
    for l in face.loops.iter().filter(|l| l.vertex.is_none()) {
        let poly = &l.uv;
        let n = poly.len();
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            if (a.y > uv.y) != (b.y > uv.y) {
                let x = a.x + (uv.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if uv.x < x {
                    inside = !inside;
                }
            }
        }
    }
    inside
}
