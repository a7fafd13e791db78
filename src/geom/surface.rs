//! What a surface is, as the rest of the crate asks: its kind as the report names it, its
//! periods (truck's, plus the closed B-spline and NURBS patches truck does not call periodic)
//! and its valid parameter range (truck's, corrected for unclamped B-spline knot vectors).

use super::eval::{eval_surface, surface_point, SurfaceDerivs};
use crate::model::Surface;

/// Evaluates face `face`'s surface and its derivatives at `(u, v)`, taking a parameter past
/// the end of a closed B-spline, NURBS or swept surface (a cylinder written as NURBS) round
/// by its period ([`crate::model::UvDomain`]'s `u_period`/`v_period`). [`eval_surface`]
/// extrapolates the end piece there instead, which leaves the surface: a touch point
/// marching across the seam of a NURBS cylinder would run off along the extrapolated arc
/// (a rational quadratic's conic tends to a fixed point as the parameter grows).
pub fn eval_face(face: &crate::model::Face, u: f64, v: f64) -> SurfaceDerivs {
    let d = face.domain;
    if matches!(face.surface, Surface::ElementarySurface(_))
        || (d.u_period.is_none() && d.v_period.is_none())
    {
        return eval_surface(&face.surface, u, v);
    }
    let (ru, rv) = parameter_range(&face.surface);
    eval_surface(
        &face.surface,
        wrap_closed(u, d.u_period, ru),
        wrap_closed(v, d.v_period, rv),
    )
}

/// `x` moved by whole periods into `range` when it lies outside and the range is one period
/// long (a surface that closes on itself); otherwise `x`.
fn wrap_closed(x: f64, period: Option<f64>, range: truck_geometry::prelude::ParameterRange) -> f64 {
    use std::ops::Bound::{Excluded, Included};
    let (Included(a) | Excluded(a), Included(b) | Excluded(b)) = range else {
        return x;
    };
    match period {
        Some(p)
            if p > 0.0
                && (x < a || x > b)
                && ((b - a) - p).abs() <= CLOSED_RANGE_REL_PERIOD * p =>
        {
            a + (x - a).rem_euclid(p)
        }
        _ => x,
    }
}

/// How near a closed surface's parameter range must be to its period, relative to it, to
/// wrap parameters by the period (both come from the same knots; rounding only).
const CLOSED_RANGE_REL_PERIOD: f64 = 1e-9;

/// The kind of a surface, as the report names it: `plane`, `cylinder`, `cone`, `sphere`,
/// `torus`, `bspline`, `nurbs`, `extrusion`, `revolution`.
pub fn surface_kind(surface: &Surface) -> &'static str {
    use truck_stepio::r#in::alias::{ElementarySurface as E, SweptCurve as S};
    match surface {
        Surface::ElementarySurface(e) => match e.as_ref() {
            E::Plane(_) => "plane",
            E::CylindricalSurface(_) => "cylinder",
            E::ConicalSurface(_) => "cone",
            E::Sphere(_) => "sphere",
            E::ToroidalSurface(_) => "torus",
        },
        Surface::SweptCurve(s) => match s.as_ref() {
            S::ExtrudedCurve(_) => "extrusion",
            S::RevolutedCurve(_) => "revolution",
        },
        Surface::BSplineSurface(_) => "bspline",
        Surface::NurbsSurface(_) => "nurbs",
    }
}

/// Points at which the two opposite borders of a B-spline or NURBS patch are compared to tell
/// whether it closes on itself ([`surface_periods`]).
const CLOSED_SAMPLES: usize = 9;

/// How near the two opposite borders of a patch must be, relative to the patch's size, for
/// it to close on itself (rounding of control points written to ~13 digits).
const CLOSED_TOL_REL_SIZE: f64 = 1e-9;

/// Periods of a surface's parametrisation in u and v.
///
/// truck's periods for the analytic surfaces, plus what truck does not report: a B-spline,
/// NURBS or swept surface that closes on itself (`S(u₀, v) = S(u₁, v)` for all v, e.g. the NURBS
/// version of a cylinder, or an extrusion of a closed B-spline profile) is treated as periodic with period `u₁ − u₀` for unwrapping its
/// loops, although evaluation outside `[u₀, u₁]` is extrapolation (loops are kept inside).
pub fn surface_periods(surface: &Surface) -> (Option<f64>, Option<f64>) {
    use truck_geometry::prelude::ParametricSurface;
    let truck = (surface.u_period(), surface.v_period());
    if matches!(surface, Surface::ElementarySurface(_)) {
        return truck;
    }
    let (ur, vr) = parameter_range(surface);
    let ends = |r: (std::ops::Bound<f64>, std::ops::Bound<f64>)| match r {
        (
            std::ops::Bound::Included(a) | std::ops::Bound::Excluded(a),
            std::ops::Bound::Included(b) | std::ops::Bound::Excluded(b),
        ) if a.is_finite() && b.is_finite() && b > a => Some((a, b)),
        _ => None,
    };
    // A swept surface is unbounded along its sweep (an extrusion's v): its profile's closure
    // is tested across [0, 1] there.
    let (bu, bv) = (ends(ur), ends(vr));
    if bu.is_none() && bv.is_none() {
        return truck;
    }
    let ((u0, u1), (v0, v1)) = (bu.unwrap_or((0.0, 1.0)), bv.unwrap_or((0.0, 1.0)));
    // Closed when the two border curves coincide at CLOSED_SAMPLES points, to
    // CLOSED_TOL_REL_SIZE of the patch's size.
    let at = |u: f64, v: f64| surface_point(surface, u, v);
    let size = at(u0, v0)
        .distance(at(u1, v1))
        .max(at(u0, v1).distance(at(u1, v0)));
    let size = size
        .max(at(0.5 * (u0 + u1), 0.5 * (v0 + v1)).distance(at(u0, v0)))
        .max(1e-300);
    let closed = |f: &dyn Fn(f64) -> (glam::DVec3, glam::DVec3)| {
        (0..CLOSED_SAMPLES).all(|k| {
            let s = k as f64 / (CLOSED_SAMPLES - 1) as f64;
            let (a, b) = f(s);
            a.distance(b) <= CLOSED_TOL_REL_SIZE * size
        })
    };
    let u_closed = closed(&|s| {
        let v = v0 + (v1 - v0) * s;
        (at(u0, v), at(u1, v))
    });
    let v_closed = closed(&|s| {
        let u = u0 + (u1 - u0) * s;
        (at(u, v0), at(u, v1))
    });
    (
        truck.0.or((bu.is_some() && u_closed).then_some(u1 - u0)),
        truck.1.or((bv.is_some() && v_closed).then_some(v1 - v0)),
    )
}

/// A surface's parameter range, as truck's `parameter_range()` but right for B-splines: an
/// unclamped (periodic-style) knot vector is valid only between its p-th and (m−p)-th knots,
/// where truck reports the whole knot vector (the NURBS cylinder FreeCAD writes has knots
/// `−2.09 … 8.38` over a valid `0 … 2π`).
pub fn parameter_range(
    surface: &Surface,
) -> (
    truck_geometry::prelude::ParameterRange,
    truck_geometry::prelude::ParameterRange,
) {
    use std::ops::Bound::Included;
    use truck_geometry::prelude::ParametricSurface;
    let valid = |k: &truck_geometry::prelude::KnotVec, p: usize| {
        let m = k.len();
        (m > 2 * p + 1).then(|| (Included(k[p]), Included(k[m - p - 1])))
    };
    let knots = match surface {
        Surface::BSplineSurface(b) => Some((b.knot_vecs(), b.udegree(), b.vdegree())),
        Surface::NurbsSurface(n) => {
            let b = n.non_rationalized();
            Some((b.knot_vecs(), b.udegree(), b.vdegree()))
        }
        _ => None,
    };
    let truck = surface.parameter_range();
    match knots {
        Some(((ku, kv), pu, pv)) => (
            valid(ku, pu).unwrap_or(truck.0),
            valid(kv, pv).unwrap_or(truck.1),
        ),
        None => truck,
    }
}

/// The knot vectors along u and along v of a B-spline or NURBS surface; `None` for other
/// surfaces.
pub fn knot_vectors(
    surface: &Surface,
) -> Option<&(
    truck_geometry::prelude::KnotVec,
    truck_geometry::prelude::KnotVec,
)> {
    match surface {
        Surface::BSplineSurface(b) => Some(b.knot_vecs()),
        Surface::NurbsSurface(n) => Some(n.knot_vecs()),
        _ => None,
    }
}

/// The number of non-empty knot spans of a B-spline or NURBS surface along u and along v;
/// `None` for other surfaces.
pub fn knot_spans(surface: &Surface) -> Option<(usize, usize)> {
    let count =
        |k: &truck_geometry::prelude::KnotVec| k.windows(2).filter(|w| w[1] > w[0]).count().max(1);
    knot_vectors(surface).map(|(u, v)| (count(u), count(v)))
}

/// Directions in which a B-spline/NURBS or swept surface is closed although truck does not call
/// it periodic (a cylinder or sphere converted to NURBS, an extrusion of a closed B-spline
/// profile): `S(u₀, v) = S(u₁, v)` at a few `v` (and likewise in `v`), to 1e-9
/// (`CLOSED_TOL_REL_SIZE`) of the surface's size ([`surface_periods`]). Projections clamp at such
/// a seam; the face continues across it.
pub fn closed_periods(surface: &Surface) -> (bool, bool) {
    use truck_geometry::prelude::ParametricSurface;
    if matches!(surface, Surface::ElementarySurface(_)) {
        return (false, false);
    }
    let (u, v) = surface_periods(surface);
    (
        surface.u_period().is_none() && u.is_some(),
        surface.v_period().is_none() && v.is_some(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// The regression plate written as NURBS (`samples/trace/nurbs_hole_plate.step`): its
    /// hole's wall is a closed rational surface over one turn. Past the end of its range,
    /// `eval_face` goes round by the period (the point stays on the wall, radius 5 about the
    /// axis x = y = 20, with the same derivatives as one period back), where `eval_surface`
    /// extrapolates the end piece to another place.
    #[test]
    fn eval_face_goes_round_a_closed_nurbs_surface() {
        let path = crate::testing::root().join("samples/trace/nurbs_hole_plate.step");
        let m = crate::ingest::read_model(&path).unwrap_or_else(|e| panic!("{e}"));
        let face = m
            .faces
            .iter()
            .find(|f| {
                f.domain.u_period.is_some() && !matches!(f.surface, Surface::ElementarySurface(_))
            })
            .expect("the hole's wall is closed in u");
        let p = face.domain.u_period.unwrap();
        let radius = |q: DVec3| ((q.x - 20.0).powi(2) + (q.y - 20.0).powi(2)).sqrt();
        for (u, v) in [
            (face.domain.u.0 - 0.2 * p, 3.0),
            (face.domain.u.1 + 1.7 * p, 6.0),
        ] {
            let wrapped = face.domain.u.0 + (u - face.domain.u.0).rem_euclid(p);
            let a = eval_face(face, u, v);
            let b = eval_surface(&face.surface, wrapped, v);
            assert!((radius(a.p) - 5.0).abs() < 1e-9, "{u}: {:?}", a.p);
            for (x, y) in [(a.p, b.p), (a.su, b.su), (a.sv, b.sv), (a.suu, b.suu)] {
                assert!((x - y).length() < 1e-9, "{u}: {x:?} vs {y:?}");
            }
            // Extrapolated, a rational quadratic arc runs on along its conic (the circle),
            // but not by the period: another place, tending to a fixed point.
            let off = eval_surface(&face.surface, u, v);
            assert!(
                (off.p - b.p).length() > 1e-3,
                "{u}: extrapolation went round"
            );
        }
    }
}
