//! Lines, polylines and the 2D parameter curves (pcurves) of a `PCurve`, with their first two
//! derivatives. Lines and polylines are straight (zero second derivative); a polyline is
//! parametrised by vertex index and extrapolates its end segments; a 2D B-spline or NURBS
//! curve goes through our B-spline code ([`super::bspline`]).

use super::bspline::bspline_curve_ders;
use super::derivs::{point3, CurveDerivs, NAN_CURVE};
use super::rational::rational_curve;
use glam::{DVec2, DVec3};
use truck_geometry::prelude::{Line, ParametricCurve, Point2, Point3, Vector2};
use truck_stepio::r#in::alias::{Curve2D, PolylineCurve};

#[inline]
pub(super) fn eval_line(l: &Line<Point3>, t: f64) -> CurveDerivs {
    let (a, b) = (point3(l.0), point3(l.1));
    CurveDerivs {
        p: a + (b - a) * t,
        d1: b - a,
        d2: DVec3::ZERO,
    }
}

/// A polyline parametrised by vertex index (truck's convention), extrapolating the end
/// segments outside `[0, n − 1]`. truck's own `der` panics on a one-point polyline.
pub(super) fn eval_polyline(pl: &PolylineCurve<Point3>, t: f64) -> CurveDerivs {
    let pts = &pl.0;
    match pts.len() {
        0 => NAN_CURVE,
        1 => CurveDerivs {
            p: point3(pts[0]),
            d1: DVec3::ZERO,
            d2: DVec3::ZERO,
        },
        n => {
            // `as usize` saturates (NaN → 0), so this cannot index out of range.
            let i = (t.max(0.0).floor() as usize).min(n - 2);
            let (a, b) = (point3(pts[i]), point3(pts[i + 1]));
            CurveDerivs {
                p: a + (b - a) * (t - i as f64),
                d1: b - a,
                d2: DVec3::ZERO,
            }
        }
    }
}

/// A 2D parameter curve (pcurve) with its first two derivatives.
pub(super) fn eval_curve2d(c: &Curve2D, t: f64) -> (DVec2, DVec2, DVec2) {
    let p2 = |p: Point2| DVec2::new(p.x, p.y);
    let v2 = |v: Vector2| DVec2::new(v.x, v.y);
    match c {
        Curve2D::Line(l) => {
            let (a, b) = (p2(l.0), p2(l.1));
            (a + (b - a) * t, b - a, DVec2::ZERO)
        }
        Curve2D::Polyline(pl) => {
            let pts = &pl.0;
            match pts.len() {
                0 => (DVec2::NAN, DVec2::NAN, DVec2::NAN),
                1 => (p2(pts[0]), DVec2::ZERO, DVec2::ZERO),
                n => {
                    let i = (t.max(0.0).floor() as usize).min(n - 2);
                    let (a, b) = (p2(pts[i]), p2(pts[i + 1]));
                    (a + (b - a) * (t - i as f64), b - a, DVec2::ZERO)
                }
            }
        }
        Curve2D::Conic(c) => (p2(c.subs(t)), v2(c.der(t)), v2(c.der2(t))),
        Curve2D::BSplineCurve(c) => {
            match bspline_curve_ders(c.knot_vec(), c.control_points(), |p| [p.x, p.y], t) {
                Some(h) => (
                    DVec2::from_array(h[0]),
                    DVec2::from_array(h[1]),
                    DVec2::from_array(h[2]),
                ),
                None => (DVec2::NAN, DVec2::NAN, DVec2::NAN),
            }
        }
        Curve2D::NurbsCurve(c) => {
            match bspline_curve_ders(c.knot_vec(), c.control_points(), |p| [p.x, p.y, p.z], t) {
                Some(h) => {
                    let a = h.map(DVec3::from_array);
                    rational_curve(
                        [a[0].truncate(), a[1].truncate(), a[2].truncate()],
                        [a[0].z, a[1].z, a[2].z],
                    )
                }
                None => (DVec2::NAN, DVec2::NAN, DVec2::NAN),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::eval::eval_curve;
    use crate::model::{Curve3D, Surface};
    use crate::testing::geometry::{
        assert_curve_fd, bspline_curve, bspline_surface, curve_params, knots, nurbs_curve,
        nurbs_surface, p3, placement, rel, u_knots, v_knots,
    };
    use std::f64::consts::PI;
    use truck_geometry::prelude::{
        BSplineCurve, Invertible, Matrix4, NurbsCurve, PCurve, Processor, Transformed,
        TrimmedCurve, UnitCircle, UnitHyperbola, UnitParabola,
    };
    use truck_stepio::r#in::alias::Conic3D;

    fn conics() -> Vec<(&'static str, Curve3D)> {
        let m = placement() * Matrix4::from_nonuniform_scale(3.0, 1.5, 1.0);
        let ellipse = Processor::new(TrimmedCurve::new(
            UnitCircle::<Point3>::new(),
            (0.0, 2.0 * PI),
        ))
        .transformed(m);
        let hyperbola = Processor::new(TrimmedCurve::new(
            UnitHyperbola::<Point3>::new(),
            (-1.0, 1.0),
        ))
        .transformed(m);
        let parabola = Processor::new(TrimmedCurve::new(
            UnitParabola::<Point3>::new(),
            (-1.0, 1.0),
        ))
        .transformed(m);
        vec![
            ("ellipse", Curve3D::Conic(Conic3D::Ellipse(ellipse))),
            (
                "ellipse inverted",
                Curve3D::Conic(Conic3D::Ellipse(ellipse.inverse())),
            ),
            ("hyperbola", Curve3D::Conic(Conic3D::Hyperbola(hyperbola))),
            ("parabola", Curve3D::Conic(Conic3D::Parabola(parabola))),
        ]
    }

    #[test]
    fn curves_match_finite_differences() {
        let line = Curve3D::Line(truck_geometry::prelude::Line(
            Point3::new(1.0, 2.0, 3.0),
            Point3::new(-0.5, 4.0, 2.0),
        ));
        assert_curve_fd("line", &line, &curve_params((-0.5, 1.5), 11, &[]));
        let poly = Curve3D::Polyline(PolylineCurve(vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.5, 0.0),
            Point3::new(1.5, 2.0, 1.0),
        ]));
        assert_curve_fd(
            "polyline",
            &poly,
            &curve_params((-0.5, 2.5), 13, &[0.0, 1.0, 2.0]),
        );
        for (name, c) in conics() {
            assert_curve_fd(name, &c, &curve_params((-0.9, 0.9), 17, &[]));
        }
        for p in 1..=4 {
            let c = Curve3D::BSplineCurve(bspline_curve(p));
            assert_curve_fd(
                &format!("B-spline curve degree {p}"),
                &c,
                &curve_params((-1.3, 2.8), 41, &u_knots(p)),
            );
        }
        for p in [2, 3] {
            let c = Curve3D::NurbsCurve(nurbs_curve(p));
            assert_curve_fd(
                &format!("NURBS curve degree {p}"),
                &c,
                &curve_params((-1.3, 2.8), 41, &u_knots(p)),
            );
        }
    }

    #[test]
    fn pcurves_match_finite_differences() {
        let c2 = BSplineCurve::new(
            knots(3, 0.0, 1.0, &[0.4]),
            vec![
                Point2::new(-0.9, 0.1),
                Point2::new(0.0, 0.8),
                Point2::new(0.9, 0.3),
                Point2::new(1.7, 0.9),
                Point2::new(2.3, 0.2),
            ],
        );
        let n2 = NurbsCurve::new(BSplineCurve::new(
            knots(2, 0.0, 1.0, &[]),
            vec![
                truck_geometry::prelude::Vector3::new(-0.5, 0.2, 1.0),
                truck_geometry::prelude::Vector3::new(0.8 * 0.7, 0.9 * 0.7, 0.7),
                truck_geometry::prelude::Vector3::new(2.0, 0.3, 1.0),
            ],
        ));
        let surfaces = [
            Surface::BSplineSurface(Box::new(bspline_surface(3, 3))),
            Surface::NurbsSurface(Box::new(nurbs_surface(3, 2))),
        ];
        let knot_list: Vec<f64> = u_knots(3)
            .iter()
            .chain(v_knots(3).iter())
            .chain(v_knots(2).iter())
            .copied()
            .collect();
        for s in &surfaces {
            for (name, c) in [
                ("cubic", Curve2D::BSplineCurve(c2.clone())),
                ("conic", Curve2D::NurbsCurve(n2.clone())),
                (
                    "line",
                    Curve2D::Line(Line(Point2::new(-0.7, 0.15), Point2::new(2.2, 0.85))),
                ),
            ] {
                let pc = Curve3D::PCurve(PCurve::new(Box::new(c.clone()), Box::new(s.clone())));
                // Avoid parameters whose image crosses a surface knot line.
                let ts: Vec<f64> = curve_params((0.0, 1.0), 41, &[0.4])
                    .into_iter()
                    .filter(|&t| {
                        let (uv, _, _) = eval_curve2d(&c, t);
                        knot_list
                            .iter()
                            .all(|k| (uv.x - k).abs() > 2e-3 && (uv.y - k).abs() > 2e-3)
                    })
                    .collect();
                assert_curve_fd(&format!("pcurve {name}"), &pc, &ts);
                for &t in &ts {
                    let theirs = p3(pc.subs(t));
                    assert!(rel(eval_curve(&pc, t).p, theirs, theirs.length()) < 1e-12);
                }
            }
        }
    }
}
