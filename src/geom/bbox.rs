//! Axis-aligned bounding boxes.

use crate::model::Model;
use glam::DVec3;
use truck_geometry::prelude::{Point3, Vector4};

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

    /// The box of all space: every query reaches it, at distance 0.
    pub const UNBOUNDED: Aabb = Aabb {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };

    /// Grows the box to contain `p`.
    pub fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when `p` is in the box (borders included).
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
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

/// Bounding box of a model's vertices and densely sampled edges: what [`model_bounding_box`]
/// starts from, and all that is known of the model's size before its faces' UV domains are.
pub fn edges_bounding_box(model: &Model) -> Aabb {
    let mut b = Aabb::EMPTY;
    for v in &model.vertices {
        b.add(v.point);
    }
    for e in &model.edges {
        // A line's extent is its end points'. A curve inside a box that is already in the
        // model's box adds nothing (every vertex is in by now).
        if curve_hull_within(&e.curve, &b) {
            continue;
        }
        let n = if matches!(e.curve, crate::model::Curve3D::Line(_)) {
            1
        } else {
            BBOX_EDGE_SAMPLES
        };
        for k in 0..=n {
            let t = e.range.0 + (e.range.1 - e.range.0) * k as f64 / n as f64;
            b.add(super::eval::curve_point(&e.curve, t));
        }
    }
    b
}

/// Bounding box of a model (see [`Model::bounding_box`]): vertices, densely sampled edges, and
/// for faces whose extent the edges do not show (a sphere bounded by a vertex loop, a torus),
/// a grid over the face's UV domain. It is an inner estimate, within the sampling's chordal
/// error of the exact box.
pub fn model_bounding_box(model: &Model) -> (DVec3, DVec3) {
    let mut b = edges_bounding_box(model);
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
        let us: Vec<f64> = (0..=n)
            .map(|i| f.domain.u.0 + (f.domain.u.1 - f.domain.u.0) * i as f64 / n as f64)
            .collect();
        let vs: Vec<f64> = (0..=n)
            .map(|j| f.domain.v.0 + (f.domain.v.1 - f.domain.v.0) * j as f64 / n as f64)
            .collect();
        super::eval::surface_grid(&f.surface, &us, &vs, |i, j, p| {
            // Most grid points are inside the box already: test the trim (a walk over the
            // loops' polygons) only for a point that would grow it.
            if b.contains(p) {
                return;
            }
            if f.outer.is_some() && !super::trim::contains(f, glam::DVec2::new(us[i], vs[j])) {
                return;
            }
            b.add(p);
        });
    }
    (b.min, b.max)
}

/// True when `surface` is a B-spline or NURBS patch whose control points (NURBS: with
/// positive weights) all lie in `b`.
fn control_points_within(surface: &crate::model::Surface, b: &Aabb) -> bool {
    use crate::model::Surface;
    match surface {
        Surface::BSplineSurface(s) => points_within(s.control_points().iter().flatten(), b),
        Surface::NurbsSurface(s) => weighted_within(s.control_points().iter().flatten(), b),
        _ => false,
    }
}

/// True when a box around the whole of `curve` (not just its trimmed range) lies in `b`: an
/// ellipse's `centre ± (|a| + |b|)` per axis, a B-spline's or NURBS curve's (positive
/// weights) control points.
fn curve_hull_within(curve: &crate::model::Curve3D, b: &Aabb) -> bool {
    use crate::model::Curve3D;
    use truck_stepio::r#in::alias::Conic3D;
    match curve {
        Curve3D::Conic(Conic3D::Ellipse(_)) => {
            let Some((c, u, v)) = crate::geom::eval::ellipse_axes(curve) else {
                return false;
            };
            let r = u.abs() + v.abs();
            c.is_finite() && r.is_finite() && b.contains(c - r) && b.contains(c + r)
        }
        Curve3D::BSplineCurve(c) => points_within(c.control_points(), b),
        Curve3D::NurbsCurve(c) => weighted_within(c.control_points(), b),
        _ => false,
    }
}

/// True when every control point lies in `b`.
fn points_within<'a>(points: impl IntoIterator<Item = &'a Point3>, b: &Aabb) -> bool {
    points
        .into_iter()
        .all(|p| b.contains(DVec3::new(p.x, p.y, p.z)))
}

/// True when every homogeneous control point has a positive weight and lies in `b`.
fn weighted_within<'a>(points: impl IntoIterator<Item = &'a Vector4>, b: &Aabb) -> bool {
    points
        .into_iter()
        .all(|h| h.w > 0.0 && b.contains(DVec3::new(h.x, h.y, h.z) / h.w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Curve3D;
    use truck_geometry::prelude::*;
    use truck_stepio::r#in::alias::Conic3D;

    /// `curve_hull_within` never passes a box that misses part of a placed, scaled ellipse
    /// or of a B-spline (sampled 10,001 times), so a curve it skips cannot grow the model's
    /// box; it passes a box around everything.
    #[test]
    fn curve_hulls_hold_their_curves() {
        let m = Matrix4::from_translation(Vector3::new(3.0, -1.0, 2.0))
            * Matrix4::from_axis_angle(Vector3::new(1.0, 2.0, 0.5).normalize(), Rad(0.8))
            * Matrix4::from_nonuniform_scale(4.0, 1.5, 1.0);
        let ellipse = Curve3D::Conic(Conic3D::Ellipse(
            Processor::new(TrimmedCurve::new(UnitCircle::<Point3>::new(), (0.0, 6.3)))
                .transformed(m),
        ));
        let spline = Curve3D::BSplineCurve(BSplineCurve::new(
            KnotVec::bezier_knot(3),
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 3.0, -1.0),
                Point3::new(2.0, -2.0, 1.0),
                Point3::new(3.0, 0.0, 0.5),
            ],
        ));
        for c in [ellipse, spline] {
            let mut pts = Aabb::EMPTY;
            for k in 0..=10_000 {
                let t = match &c {
                    Curve3D::Conic(_) => 6.3 * k as f64 / 10_000.0,
                    _ => k as f64 / 10_000.0,
                };
                pts.add(crate::geom::eval_curve(&c, t).p);
            }
            let hull_ok = |b: &Aabb| curve_hull_within(&c, b);
            let huge = Aabb {
                min: DVec3::splat(-100.0),
                max: DVec3::splat(100.0),
            };
            assert!(hull_ok(&huge));
            // A box smaller than the curve's own extent never passes.
            let shrunk = Aabb {
                min: pts.min + 1e-3,
                max: pts.max - 1e-3,
            };
            assert!(!hull_ok(&shrunk));
        }
    }
}
