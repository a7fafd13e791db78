//! Axis-aligned bounding boxes.

use crate::brep::Model;
use glam::DVec3;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (grows from nothing).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// Grows the box to contain `p`.
    pub fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
}

/// Samples per edge for the model's bounding box (a circle sampled 128 times is within
/// 0.03 % of its radius of its true extent).
pub const BBOX_EDGE_SAMPLES: usize = 128;

/// Grid per face (in each UV direction) for the model's bounding box.
pub const BBOX_FACE_GRID: usize = 32;

/// Bounding box of a model (see [`Model::bounding_box`]): vertices, densely sampled edges, and
/// for faces whose extent the edges do not show (a sphere bounded by a vertex loop, a torus),
/// a grid over the face's UV domain. It is an inner estimate, within the sampling's chordal
/// error of the exact box.
pub fn model_bounding_box(model: &Model) -> (DVec3, DVec3) {
    let mut b = Aabb::EMPTY;
    for v in &model.vertices {
        b.add(v.point);
    }
    for e in &model.edges {
        // A line's extent is its end points'.
        let n = if matches!(e.curve, crate::brep::model::Curve3D::Line(_)) {
            1
        } else {
            BBOX_EDGE_SAMPLES
        };
        for k in 0..=n {
            let t = e.range.0 + (e.range.1 - e.range.0) * k as f64 / n as f64;
            b.add(super::eval::curve_point(&e.curve, t));
        }
    }
    // Face interiors: a free-form face can bulge beyond its edges (a B-spline top with a
    // bump), and a periodic face without a closed outer loop (a sphere bounded by a vertex
    // loop, a torus) has edges that show nothing of its extent. A ruled face cannot
    // (planes, cylinders, cones, extrusions): a coordinate is linear along each ruling, so its
    // extremes over the face lie on the face's boundary.
    let n = BBOX_FACE_GRID;
    for f in &model.faces {
        if matches!(
            crate::geom::surface_kind(&f.surface),
            "plane" | "cylinder" | "cone" | "extrusion"
        ) {
            continue;
        }
        // A B-spline or NURBS patch (positive weights) lies in the convex hull of its control
        // points: when they are all in the box, so is the face.
        if control_points_within(&f.surface, &b) {
            continue;
        }
        for i in 0..=n {
            for j in 0..=n {
                let u = f.domain.u.0 + (f.domain.u.1 - f.domain.u.0) * i as f64 / n as f64;
                let v = f.domain.v.0 + (f.domain.v.1 - f.domain.v.0) * j as f64 / n as f64;
                // Most grid points are inside the box already: test the trim (a walk over
                // the loops' polygons) only for a point that would grow it.
                let p = super::eval_surface(&f.surface, u, v).p;
                if p.cmpge(b.min).all() && p.cmple(b.max).all() {
                    continue;
                }
                if f.outer.is_some() && !super::trim::contains(f, glam::DVec2::new(u, v)) {
                    continue;
                }
                b.add(p);
            }
        }
    }
    (b.min, b.max)
}

/// True when `surface` is a B-spline or NURBS patch whose control points (NURBS: with
/// positive weights) all lie in `b`.
fn control_points_within(surface: &crate::brep::model::Surface, b: &Aabb) -> bool {
    use crate::brep::model::Surface;
    let inside = |p: DVec3| p.cmpge(b.min).all() && p.cmple(b.max).all();
    match surface {
        Surface::BSplineSurface(s) => s
            .control_points()
            .iter()
            .flatten()
            .all(|p| inside(DVec3::new(p.x, p.y, p.z))),
        Surface::NurbsSurface(s) => s
            .control_points()
            .iter()
            .flatten()
            .all(|h| h.w > 0.0 && inside(DVec3::new(h.x, h.y, h.z) / h.w)),
        _ => false,
    }
}
