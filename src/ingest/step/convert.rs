//! STEP geometry converted by truck, one entity at a time.
//!
//! A face's surface and an edge's curve are moved by the solid's placement; the edge gets the
//! parameter interval between its vertices. A conversion that fails (or panics inside truck)
//! is an error naming the entity, instead of a face that silently disappears.

use super::error::{first_line, guarded};
use super::source::Source;
use crate::error::{Error, Result};
use crate::ingest::tolerance::{
    vertex_gap_allowed, VERTEX_AT_END_REL_COORD, VERTEX_ON_CURVE_REL_COORD,
};
use crate::ingest::transform::{placed, Mat4};
use crate::model::{Curve3D, Surface};
use glam::DVec3;
use truck_geometry::prelude::Point3;
use truck_stepio::r#in::ruststep::ast::Name;
use truck_stepio::r#in::ruststep::tables::{IntoOwned, PlaceHolder};
use truck_stepio::r#in::{EdgeCurveHolder, SurfaceAnyHolder};

impl Source<'_> {
    fn undecodable(&self, id: u64) -> Option<Error> {
        self.undecodable
            .get(&id)
            .map(|reason| self.err(id, format!("cannot be read: {reason}")))
    }

    /// Runs a truck conversion for entity `id`: its error becomes `failure: …`, a panic
    /// inside truck `reader panicked: …`.
    fn with_truck<T>(
        &self,
        id: u64,
        failure: &str,
        f: impl FnOnce() -> std::result::Result<T, String>,
    ) -> Result<T> {
        match guarded(f) {
            Ok(Ok(x)) => Ok(x),
            Ok(Err(e)) => Err(self.err(id, format!("{failure}: {e}"))),
            Err(p) => Err(self.err(id, format!("reader panicked: {p}"))),
        }
    }

    /// The surface `id`, moved by `m`.
    pub fn convert_surface(&self, id: u64, m: &Mat4) -> Result<Surface> {
        if let Some(e) = self.undecodable(id) {
            return Err(e);
        }
        let known = [
            "PLANE",
            "CYLINDRICAL_SURFACE",
            "CONICAL_SURFACE",
            "SPHERICAL_SURFACE",
            "TOROIDAL_SURFACE",
            "B_SPLINE_SURFACE_WITH_KNOTS",
            "BEZIER_SURFACE",
            "UNIFORM_SURFACE",
            "QUASI_UNIFORM_SURFACE",
            "SURFACE_OF_LINEAR_EXTRUSION",
            "SURFACE_OF_REVOLUTION",
            "RATIONAL_B_SPLINE_SURFACE",
        ];
        if !known.iter().any(|k| self.recs.is(id, k)) {
            return Err(self.err(id, "unsupported surface type"));
        }
        let table = self.table;
        let surface = self.with_truck(id, "cannot be converted", || {
            let any = PlaceHolder::<SurfaceAnyHolder>::Ref(Name::Entity(id))
                .into_owned(table)
                .map_err(|e| first_line(&e.to_string()))?;
            Surface::try_from(&any).map_err(|e| first_line(&e.to_string()))
        })?;
        Ok(placed(surface, m))
    }

    /// The 3D curve of the edge curve `id` (its geometry is `geometry`), moved by `m`.
    pub fn convert_edge_curve(&self, id: u64, geometry: u64, m: &Mat4) -> Result<Curve3D> {
        if let Some(e) = self.undecodable(id).or_else(|| self.undecodable(geometry)) {
            return Err(e);
        }
        let known = [
            "LINE",
            "CIRCLE",
            "ELLIPSE",
            "B_SPLINE_CURVE_WITH_KNOTS",
            "BEZIER_CURVE",
            "UNIFORM_CURVE",
            "QUASI_UNIFORM_CURVE",
            "RATIONAL_B_SPLINE_CURVE",
            "POLYLINE",
            "SURFACE_CURVE",
            "SEAM_CURVE",
            "HYPERBOLA",
            "PARABOLA",
        ];
        if !known.iter().any(|k| self.recs.is(geometry, k)) {
            return Err(self.err(geometry, "unsupported curve type"));
        }
        let table = self.table;
        let curve = self.with_truck(id, "curve cannot be converted", || {
            let ec = PlaceHolder::<EdgeCurveHolder>::Ref(Name::Entity(id))
                .into_owned(table)
                .map_err(|e| first_line(&e.to_string()))?;
            ec.parse_curve3d().map_err(|e| first_line(&e.to_string()))
        })?;
        if matches!(curve, Curve3D::PCurve(_)) {
            return Err(self.err(id, "edge has only a pcurve, no 3D curve"));
        }
        Ok(placed(curve, m))
    }

    /// The parameter interval of `curve` between the edge's vertices `pa` and `pb` (the same
    /// vertex when `closed`); truck trims lines and conics to the vertices, B-splines keep
    /// their own range (check it, project if needed).
    pub fn edge_range(
        &self,
        id: u64,
        curve: &Curve3D,
        (pa, pb): (DVec3, DVec3),
        closed: bool,
    ) -> Result<(f64, f64)> {
        use truck_geometry::prelude::{ParametricCurve, SearchNearestParameter};
        let (t0, t1) = match curve {
            // An unclamped (periodic-style) knot vector is only valid between the p-th and
            // the (m−p)-th knot; truck reports the whole knot range, where the curve is
            // undefined.
            Curve3D::BSplineCurve(c) => valid_knot_range(c.knot_vec(), c.degree()),
            Curve3D::NurbsCurve(c) => valid_knot_range(c.knot_vec(), c.degree()),
            _ => None,
        }
        .or_else(|| guarded(|| curve.try_range_tuple()).ok().flatten())
        .ok_or_else(|| self.err(id, "edge curve is unbounded"))?;
        let at = |t: f64| {
            let q = curve.subs(t);
            DVec3::new(q.x, q.y, q.z)
        };
        let scale = 1.0 + pa.abs().max_element().max(pb.abs().max_element());
        let tol = VERTEX_AT_END_REL_COORD * scale;
        if at(t0).distance(pa) <= tol && at(t1).distance(pb) <= tol {
            return Ok((t0, t1));
        }
        // Project the vertices (hint: the nearer end); on a hyperbola or parabola in closed
        // form (truck trims both to the parameters −1..1 whatever the edge, and its search
        // stays there: a countersink's cone cut by a slanted plane ends 2.4 and 4.1 mm off).
        // Where the search from the nearer end fails (an edge on a short stretch of a long
        // spline, its far vertex in the middle of the curve: a FreeCAD fillet's edge on a
        // sphere), it starts again from the nearest of samples along the curve.
        let allowed = vertex_gap_allowed(scale, self.uncertainty_mm);
        let search = |p: DVec3, hint: f64| {
            guarded(|| curve.search_nearest_parameter(Point3::new(p.x, p.y, p.z), Some(hint), 100))
                .ok()
                .flatten()
                .filter(|&s| at(s).distance(p) <= allowed)
        };
        let proj = |p: DVec3, hint: f64| {
            open_conic_parameter(curve, p)
                .or_else(|| search(p, hint))
                .or_else(|| {
                    let sample = |k: usize| t0 + (t1 - t0) * k as f64 / PROJECTION_SAMPLES as f64;
                    let nearest = (0..=PROJECTION_SAMPLES)
                        .map(sample)
                        .min_by(|&a, &b| at(a).distance(p).total_cmp(&at(b).distance(p)))?;
                    search(p, nearest)
                })
        };
        let s0 = proj(pa, t0);
        let s1 = proj(pb, t1);
        match (s0, s1) {
            (Some(s0), Some(s1))
                if at(s0).distance(pa) <= allowed && at(s1).distance(pb) <= allowed =>
            {
                let gap = at(s0).distance(pa).max(at(s1).distance(pb));
                if gap > VERTEX_ON_CURVE_REL_COORD * scale {
                    self.warn_gap(
                        "gap",
                        id,
                        "vertex off its edge curve by more than matrace's tolerance, within the \
                         file's declared uncertainty",
                        "accepted: the edge ends at the curve points nearest its vertices",
                        Some(gap),
                    );
                }
                if closed || (s1 - s0).abs() < 1e-12 {
                    Ok((t0, t1))
                } else {
                    Ok((s0, s1))
                }
            }
            _ => Err(self.err(
                id,
                format!(
                    "the edge's vertices are not on its curve (distance {:.3e} mm and {:.3e} mm)",
                    at(t0).distance(pa),
                    at(t1).distance(pb)
                ),
            )),
        }
    }
}

/// Samples along an edge's curve from whose nearest a vertex's projection starts again when
/// the search from the curve's nearer end fails.
const PROJECTION_SAMPLES: usize = 256;

/// The parameter of a hyperbola's or parabola's point whose local `y` is that of `p` (the
/// point itself, for a point on the curve): truck's unit hyperbola is `(cosh t, sinh t)` and
/// its unit parabola `(t², 2t)` before the placement's transform, whose inverse gives `p`'s
/// local coordinates; a reversed curve runs `t ↦ t0 + t1 − t` over its range. `None` for
/// other curves (or a singular placement).
fn open_conic_parameter(curve: &Curve3D, p: DVec3) -> Option<f64> {
    use truck_geometry::prelude::{BoundedCurve, SquareMatrix, Transform};
    use truck_stepio::r#in::alias::Conic3D;
    let p = Point3::new(p.x, p.y, p.z);
    let (t, orientation, (t0, t1)) = match curve {
        Curve3D::Conic(Conic3D::Hyperbola(h)) => {
            let q = h.transform().invert()?.transform_point(p);
            (q.y.asinh(), h.orientation(), h.range_tuple())
        }
        Curve3D::Conic(Conic3D::Parabola(c)) => {
            let q = c.transform().invert()?.transform_point(p);
            (0.5 * q.y, c.orientation(), c.range_tuple())
        }
        _ => return None,
    };
    let t = if orientation { t } else { t0 + t1 - t };
    t.is_finite().then_some(t)
}

/// `[k_p, k_{m−p}]` of a knot vector of degree `p` (m + 1 knots).
fn valid_knot_range(knots: &truck_geometry::prelude::KnotVec, degree: usize) -> Option<(f64, f64)> {
    let m = knots.len();
    (m > 2 * degree + 1).then(|| (knots[degree], knots[m - degree - 1]))
}
