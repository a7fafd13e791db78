//! Position and first and second derivatives of every surface and curve kind truck yields.
//!
//! The medial equations need `S`, `Su`, `Sv` (touch conditions, normals) and `Suu`, `Suv`, `Svv`
//! (analytic Jacobians, curvatures) at millions of parameter points, so every kind is evaluated
//! here in one pass that returns all six vectors at once.
//!
//! **B-splines and NURBS are evaluated by our own code** (`bspline.rs`), because truck 0.5
//! gets them wrong: `BSplineSurface::uuder`/`vvder` multiply by `p` where the second
//! derivative needs `p·(p − 1)`, so they are short by the factor `p − 1` for degree `p ≥ 3`
//! (and `NurbsSurface` inherits the error through the quotient rule); `uvder` is right. The
//! test `truck_uuder_is_wrong_for_cubic_and_ours_is_right` measures it. NURBS are homogeneous
//! B-splines followed by the quotient rule (`rational.rs`).
//!
//! **Analytic surfaces** (plane, sphere, cylinder, cone, torus) and the surface of revolution
//! are evaluated from closed forms in one pass (`analytic.rs`), exactly in truck's
//! parametrisation. Swept surfaces evaluate their profile with [`eval_curve`] (here, with the
//! dispatch: a profile may be a pcurve, which evaluates a surface again), so a B-spline
//! profile of degree ≥ 3 gets correct second derivatives too.
//!
//! Curves: lines, polylines and conics use truck's derivatives (they are right, and tested
//! against finite differences; `curves.rs`); B-spline and NURBS curves use the B-spline code;
//! a `PCurve` composes the 2D curve with the surface by the chain rule.
//!
//! Out-of-range parameters never panic: B-splines extrapolate the end polynomial piece,
//! polylines the end segment, analytic kinds are defined everywhere. A B-spline with fewer
//! than `p + 1` control points (which truck's checked constructors accept) evaluates to NaN.

mod analytic;
mod bspline;
mod curves;
mod derivs;
mod rational;

pub use bspline::{
    eval_bspline_curve, eval_bspline_surface, eval_nurbs_curve, eval_nurbs_surface, STACK_ORDER,
};
pub use derivs::{CurveDerivs, SurfaceDerivs};

use crate::model::{Curve3D, Surface};
use analytic::{eval_elementary, processed, revolve};
use bspline::{bspline_surface_point, tensor_grid};
use curves::{eval_curve2d, eval_line, eval_polyline};
use derivs::{point3, vec3, NAN_SURFACE};
use glam::DVec3;
use truck_geometry::prelude::{ParametricCurve, Point3, Vector4};
use truck_stepio::r#in::alias::SweptCurve;

/// Evaluates `surface` and its derivatives at `(u, v)`.
pub fn eval_surface(surface: &Surface, u: f64, v: f64) -> SurfaceDerivs {
    match surface {
        Surface::ElementarySurface(e) => eval_elementary(e, u, v),
        Surface::SweptCurve(s) => eval_swept(s, u, v),
        Surface::BSplineSurface(s) => eval_bspline_surface(s, u, v),
        Surface::NurbsSurface(s) => eval_nurbs_surface(s, u, v),
    }
}

/// Evaluates `curve` and its derivatives at `t`.
pub fn eval_curve(curve: &Curve3D, t: f64) -> CurveDerivs {
    match curve {
        Curve3D::Line(l) => eval_line(l, t),
        Curve3D::Polyline(pl) => eval_polyline(pl, t),
        Curve3D::Conic(c) => CurveDerivs {
            p: point3(c.subs(t)),
            d1: vec3(c.der(t)),
            d2: vec3(c.der2(t)),
        },
        Curve3D::BSplineCurve(c) => eval_bspline_curve(c, t),
        Curve3D::NurbsCurve(c) => eval_nurbs_curve(c, t),
        Curve3D::PCurve(pc) => {
            let (uv, duv, dduv) = eval_curve2d(pc.curve(), t);
            let s = eval_surface(pc.surface(), uv.x, uv.y);
            CurveDerivs {
                p: s.p,
                d1: s.su * duv.x + s.sv * duv.y,
                d2: s.suu * (duv.x * duv.x)
                    + s.suv * (2.0 * duv.x * duv.y)
                    + s.svv * (duv.y * duv.y)
                    + s.su * dduv.x
                    + s.sv * dduv.y,
            }
        }
    }
}

/// The swept surfaces: an extrusion `C(u) + v·d`, and a revolution of `C` about an axis
/// (`analytic.rs`'s `revolve`). They stay with the dispatch because their profile goes through
/// [`eval_curve`], where a pcurve evaluates a surface again.
fn eval_swept(s: &SweptCurve, u: f64, v: f64) -> SurfaceDerivs {
    match s {
        SweptCurve::ExtrudedCurve(ex) => {
            let c = eval_curve(ex.entity_curve(), u);
            let d = vec3(ex.extruding_vector());
            SurfaceDerivs {
                p: c.p + d * v,
                su: c.d1,
                sv: d,
                suu: c.d2,
                suv: DVec3::ZERO,
                svv: DVec3::ZERO,
            }
        }
        SweptCurve::RevolutedCurve(pr) => {
            let rev = pr.entity();
            let (o, a) = (point3(rev.origin()), vec3(rev.axis()));
            let curve = rev.entity_curve();
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                revolve(o, a, eval_curve(curve, u), v)
            })
        }
    }
}

/// The point of `curve` at `t` alone: B-spline and NURBS curves by our evaluator (truck's
/// allocates per call), the other kinds by truck's `subs` (one evaluation where
/// [`eval_curve`] makes three for a conic).
pub fn curve_point(curve: &Curve3D, t: f64) -> DVec3 {
    match curve {
        Curve3D::BSplineCurve(_) | Curve3D::NurbsCurve(_) | Curve3D::PCurve(_) => {
            eval_curve(curve, t).p
        }
        _ => point3(curve.subs(t)),
    }
}

/// An ellipse's (or circle's) centre and the vectors of its two semi-axes, `t = 0` and
/// `t = π/2` from the centre, read off its placement: `None` for other curves and where the
/// placement is not affine (only placements and unit scaling are expected).
pub(crate) fn ellipse_axes(curve: &Curve3D) -> Option<(DVec3, DVec3, DVec3)> {
    use truck_stepio::r#in::alias::Conic3D;
    let Curve3D::Conic(Conic3D::Ellipse(e)) = curve else {
        return None;
    };
    let m = e.transform();
    if m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0 {
        return None;
    }
    Some((
        DVec3::new(m[3][0], m[3][1], m[3][2]),
        DVec3::new(m[0][0], m[0][1], m[0][2]),
        DVec3::new(m[1][0], m[1][1], m[1][2]),
    ))
}

/// The point of `surface` at `(u, v)` alone: B-spline and NURBS patches without their
/// derivatives (several times cheaper at high degree), bit for bit [`eval_surface`]'s point;
/// other kinds through [`eval_surface`].
pub fn surface_point(surface: &Surface, u: f64, v: f64) -> DVec3 {
    let xyz = |a: [f64; 4]| DVec3::new(a[0], a[1], a[2]);
    match surface {
        Surface::BSplineSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Point3| [p.x, p.y, p.z, 0.0];
            bspline_surface_point(uk, vk, s.control_points(), coords, u, v)
                .map_or(NAN_SURFACE.p, xyz)
        }
        Surface::NurbsSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Vector4| [p.x, p.y, p.z, p.w];
            match bspline_surface_point(uk, vk, s.control_points(), coords, u, v) {
                // As `rational_surface` divides.
                Some(h) => xyz(h) * (1.0 / h[3]),
                None => NAN_SURFACE.p,
            }
        }
        _ => eval_surface(surface, u, v).p,
    }
}

/// [`surface_point`] over the grid `us × vs`, calling `f(i, j, point)`: a B-spline or NURBS
/// patch's basis functions are computed once per row and column, not once per point (the
/// same points, bit for bit).
pub fn surface_grid(
    surface: &Surface,
    us: &[f64],
    vs: &[f64],
    mut f: impl FnMut(usize, usize, DVec3),
) {
    let xyz = |a: [f64; 4]| DVec3::new(a[0], a[1], a[2]);
    match surface {
        Surface::BSplineSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Point3| [p.x, p.y, p.z, 0.0];
            tensor_grid((uk, vk), s.control_points(), coords, us, vs, |i, j, h| {
                f(i, j, h.map_or(NAN_SURFACE.p, xyz))
            });
        }
        Surface::NurbsSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Vector4| [p.x, p.y, p.z, p.w];
            tensor_grid((uk, vk), s.control_points(), coords, us, vs, |i, j, h| {
                f(i, j, h.map_or(NAN_SURFACE.p, |h| xyz(h) * (1.0 / h[3])))
            });
        }
        _ => {
            for (i, &u) in us.iter().enumerate() {
                for (j, &v) in vs.iter().enumerate() {
                    f(i, j, eval_surface(surface, u, v).p);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::geometry::{
        assert_surface_fd, bspline_curve, bspline_surface, grid, nurbs_curve, nurbs_surface, p3,
        placement, rel, u_knots, DEGREE_PAIRS,
    };
    use truck_geometry::prelude::{
        ExtrudedCurve, Invertible, ParametricSurface, Processor, RevolutedCurve, Transformed,
        Vector3,
    };

    fn extrusion(profile: Curve3D) -> Surface {
        let ex = ExtrudedCurve::by_extrusion(profile, Vector3::new(0.3, -0.4, 2.0));
        Surface::SweptCurve(Box::new(SweptCurve::ExtrudedCurve(ex)))
    }

    /// Revolution of `profile` about an axis through (0.5, −1, 0) along (0.2, 0.3, 1), placed
    /// by [`placement`], optionally with the orientation flag flipped.
    fn revolution(profile: Curve3D, inverted: bool) -> Surface {
        let rev = RevolutedCurve::by_revolution(
            profile,
            Point3::new(0.5, -1.0, 0.0),
            Vector3::new(0.2, 0.3, 1.0),
        );
        let mut pr = Processor::new(rev).transformed(placement());
        if inverted {
            pr.invert();
        }
        Surface::SweptCurve(Box::new(SweptCurve::RevolutedCurve(pr)))
    }

    /// `surface_point` and `surface_grid` are bit for bit `eval_surface`'s point, for
    /// B-splines and NURBS of
    /// every degree pair (the high ones beyond the stack buffers), at knots, inside and
    /// beyond the range.
    #[test]
    fn surface_points_are_the_evaluation_s_bit_for_bit() {
        let mut ts: Vec<(f64, f64)> = grid((-1.0, 2.5), (0.0, 1.0), 9, &[], &[]);
        ts.extend(u_knots(3).iter().map(|&u| (u, 0.5)));
        let mut pairs = DEGREE_PAIRS.to_vec();
        pairs.push((STACK_ORDER, 2));
        pairs.push((1, STACK_ORDER + 2));
        for (p, q) in pairs {
            let b = Surface::BSplineSurface(Box::new(bspline_surface(p, q)));
            let n = Surface::NurbsSurface(Box::new(nurbs_surface(p, q)));
            let bits = |x: DVec3| x.to_array().map(f64::to_bits);
            for s in [b, n] {
                for &(u, v) in &ts {
                    let (ours, full) = (surface_point(&s, u, v), eval_surface(&s, u, v).p);
                    assert!(
                        bits(ours) == bits(full),
                        "{p}×{q} at ({u}, {v}): {ours} vs {full}"
                    );
                }
                let us: Vec<f64> = ts.iter().map(|t| t.0).collect();
                let vs: Vec<f64> = ts.iter().map(|t| t.1).collect();
                let mut seen = 0;
                surface_grid(&s, &us, &vs, |i, j, x| {
                    assert!(
                        bits(x) == bits(eval_surface(&s, us[i], vs[j]).p),
                        "{p}×{q} grid"
                    );
                    seen += 1;
                });
                assert_eq!(seen, us.len() * vs.len());
            }
        }
    }

    #[test]
    fn swept_surfaces_match_finite_differences() {
        let k3 = u_knots(3);
        let cases = [
            (
                "extruded cubic B-spline",
                extrusion(Curve3D::BSplineCurve(bspline_curve(3))),
            ),
            (
                "extruded cubic NURBS",
                extrusion(Curve3D::NurbsCurve(nurbs_curve(3))),
            ),
            (
                "revolved cubic B-spline",
                revolution(Curve3D::BSplineCurve(bspline_curve(3)), false),
            ),
            (
                "revolved cubic NURBS",
                revolution(Curve3D::NurbsCurve(nurbs_curve(3)), false),
            ),
            (
                "revolved quartic B-spline, inverted",
                revolution(Curve3D::BSplineCurve(bspline_curve(4)), true),
            ),
        ];
        for (name, s) in cases {
            // After inversion u ↔ v, so the knots may sit on either parameter.
            let params = grid((-1.0, 2.5), (-1.0, 2.5), 10, &k3, &k3);
            let params: Vec<_> = params
                .into_iter()
                .filter(|(u, v)| {
                    u_knots(4)
                        .iter()
                        .all(|k| (u - k).abs() > 1e-3 && (v - k).abs() > 1e-3)
                })
                .collect();
            assert_surface_fd(name, &s, &params);
            // Values equal truck's.
            for &(u, v) in &params {
                let theirs = p3(s.subs(u, v));
                assert!(
                    rel(eval_surface(&s, u, v).p, theirs, theirs.length()) < 1e-12,
                    "{name}"
                );
            }
        }
    }
}
