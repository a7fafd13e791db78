//! Position and first and second derivatives of every surface and curve kind truck yields.
//!
//! The medial equations need `S`, `Su`, `Sv` (touch conditions, normals) and `Suu`, `Suv`, `Svv`
//! (analytic Jacobians, curvatures) at millions of parameter points, so every kind is evaluated
//! here in one pass that returns all six vectors at once.
//!
//! **B-splines and NURBS are evaluated by our own code**, because truck 0.5 gets them wrong:
//! `BSplineSurface::uuder`/`vvder` multiply by `p` where the second derivative needs
//! `p·(p − 1)`, so they are short by the factor `p − 1` for degree `p ≥ 3` (and `NurbsSurface`
//! inherits the error through the quotient rule); `uvder` is right. The test
//! `truck_uuder_is_wrong_for_cubic_and_ours_is_right` measures it. The algorithms are those of
//! Piegl & Tiller, *The NURBS Book*, 2nd ed., Springer 1997:
//! - span search (A2.1), clamped so that parameters outside the knot range extrapolate the first
//!   or last polynomial piece instead of failing;
//! - the non-zero basis functions and their first two derivatives (A2.2 + A2.3, eq. 2.9/2.10:
//!   `N′ᵢ,ₚ = p·(Nᵢ,ₚ₋₁/(uᵢ₊ₚ − uᵢ) − Nᵢ₊₁,ₚ₋₁/(uᵢ₊ₚ₊₁ − uᵢ₊₁))`, applied twice), keeping
//!   only the degree `p − 1` and `p − 2` rows of the triangular table instead of all of `ndu`;
//! - surface derivatives up to order 2 (A3.6): contract the control net with the `v` basis
//!   first (three sums per row), then with the `u` basis (six sums);
//! - the rational quotient rule for NURBS (A4.2 for curves, A4.4 for surfaces) on the
//!   homogeneous derivatives `A = w·S`:
//!   `S = A/w`, `Su = (Au − wu·S)/w`, `Suv = (Auv − wuv·S − wu·Sv − wv·Su)/w`, …
//!
//! Degrees up to [`STACK_ORDER`]` − 1` use stack buffers; higher degrees allocate.
//!
//! **Analytic surfaces** (plane, sphere, cylinder, cone, torus) and the swept surfaces are
//! evaluated from closed forms in one pass (one `sin_cos` per angle), reading truck's own
//! parameters (`origin()`, `axis()`, `radius()`, …) so that the parametrisation is exactly
//! truck's; truck's transform (`Processor`) and orientation flag (which swaps `u` and `v`)
//! are applied afterwards. Swept surfaces evaluate their profile with [`eval_curve`], so a
//! B-spline profile of degree ≥ 3 gets correct second derivatives too.
//!
//! Curves: lines, polylines and conics use truck's derivatives (they are right, and tested
//! here against finite differences); B-spline and NURBS curves use the code above; a `PCurve`
//! composes the 2D curve with the surface by the chain rule.
//!
//! Out-of-range parameters never panic: B-splines extrapolate the end polynomial piece,
//! polylines the end segment, analytic kinds are defined everywhere. A B-spline with fewer
//! than `p + 1` control points (which truck's checked constructors accept) evaluates to NaN.

use crate::model::{Curve3D, Surface};
use glam::{DMat4, DVec2, DVec3, DVec4};
use truck_geometry::prelude::{
    BSplineCurve, BSplineSurface, Line, Matrix4, NurbsCurve, NurbsSurface, ParametricCurve, Point2,
    Point3, Vector2, Vector3, Vector4,
};
use truck_stepio::r#in::alias::{Curve2D, ElementarySurface, PolylineCurve, SweptCurve};

/// A surface point with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    pub p: DVec3,
    pub su: DVec3,
    pub sv: DVec3,
    pub suu: DVec3,
    pub suv: DVec3,
    pub svv: DVec3,
}

/// A curve point with its first and second derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveDerivs {
    pub p: DVec3,
    pub d1: DVec3,
    pub d2: DVec3,
}

/// Largest B-spline order (degree + 1) whose basis functions are computed in stack buffers;
/// higher degrees allocate one small `Vec` per evaluation.
pub const STACK_ORDER: usize = 11;

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
    fn bases(knots: &[f64], n_cp: usize, ts: &[f64]) -> Option<Vec<(usize, usize, Vec<f64>)>> {
        ts.iter()
            .map(|&t| with_values(knots, n_cp, t, |p, span, n| (p, span, n.to_vec())))
            .collect()
    }
    fn grid<P, const D: usize>(
        (uk, vk): (&[f64], &[f64]),
        cps: &[Vec<P>],
        coords: impl Fn(&P) -> [f64; D],
        us: &[f64],
        vs: &[f64],
        mut f: impl FnMut(usize, usize, Option<[f64; D]>),
    ) {
        let n_v = cps.first().map_or(0, |r| r.len());
        let (Some(bu), Some(bv)) = (bases(uk, cps.len(), us), bases(vk, n_v, vs)) else {
            for i in 0..us.len() {
                for j in 0..vs.len() {
                    f(i, j, None);
                }
            }
            return;
        };
        for (i, (p, uspan, nu)) in bu.iter().enumerate() {
            let rows = &cps[uspan - p..uspan + 1];
            for (j, (q, vspan, nv)) in bv.iter().enumerate() {
                f(
                    i,
                    j,
                    Some(tensor_point(rows, nu, (*q, *vspan, nv), &coords)),
                );
            }
        }
    }
    let xyz = |a: [f64; 4]| DVec3::new(a[0], a[1], a[2]);
    match surface {
        Surface::BSplineSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Point3| [p.x, p.y, p.z, 0.0];
            grid((uk, vk), s.control_points(), coords, us, vs, |i, j, h| {
                f(i, j, h.map_or(NAN_SURFACE.p, xyz))
            });
        }
        Surface::NurbsSurface(s) => {
            let (uk, vk) = s.knot_vecs();
            let coords = |p: &Vector4| [p.x, p.y, p.z, p.w];
            grid((uk, vk), s.control_points(), coords, us, vs, |i, j, h| {
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

/// Evaluates a B-spline surface (our code, not truck's `uuder`/`vvder`).
pub fn eval_bspline_surface(s: &BSplineSurface<Point3>, u: f64, v: f64) -> SurfaceDerivs {
    let (uk, vk) = s.knot_vecs();
    // Padded to four lanes: the accumulation then vectorises two lanes at a time (SSE2).
    let coords = |p: &Point3| [p.x, p.y, p.z, 0.0];
    let h = bspline_surface_ders(uk, vk, s.control_points(), coords, u, v);
    let xyz = |a: [f64; 4]| DVec3::new(a[0], a[1], a[2]);
    match h {
        Some(h) => SurfaceDerivs {
            p: xyz(h[0]),
            su: xyz(h[1]),
            sv: xyz(h[2]),
            suu: xyz(h[3]),
            suv: xyz(h[4]),
            svv: xyz(h[5]),
        },
        None => NAN_SURFACE,
    }
}

/// Evaluates a NURBS surface (homogeneous B-spline + quotient rule).
pub fn eval_nurbs_surface(s: &NurbsSurface<Vector4>, u: f64, v: f64) -> SurfaceDerivs {
    let (uk, vk) = s.knot_vecs();
    let h = bspline_surface_ders(
        uk,
        vk,
        s.control_points(),
        |p: &Vector4| [p.x, p.y, p.z, p.w],
        u,
        v,
    );
    match h {
        Some(h) => rational_surface(&h.map(DVec4::from_array)),
        None => NAN_SURFACE,
    }
}

/// Evaluates a B-spline curve (our code).
pub fn eval_bspline_curve(c: &BSplineCurve<Point3>, t: f64) -> CurveDerivs {
    match bspline_curve_ders(c.knot_vec(), c.control_points(), |p| [p.x, p.y, p.z], t) {
        Some(h) => CurveDerivs {
            p: DVec3::from_array(h[0]),
            d1: DVec3::from_array(h[1]),
            d2: DVec3::from_array(h[2]),
        },
        None => NAN_CURVE,
    }
}

/// Evaluates a NURBS curve (homogeneous B-spline + quotient rule).
pub fn eval_nurbs_curve(c: &NurbsCurve<Vector4>, t: f64) -> CurveDerivs {
    match bspline_curve_ders(
        c.knot_vec(),
        c.control_points(),
        |p| [p.x, p.y, p.z, p.w],
        t,
    ) {
        Some(h) => {
            let a = h.map(DVec4::from_array);
            let (p, d1, d2) = rational_curve(
                [a[0].truncate(), a[1].truncate(), a[2].truncate()],
                [a[0].w, a[1].w, a[2].w],
            );
            CurveDerivs { p, d1, d2 }
        }
        None => NAN_CURVE,
    }
}

const NAN_SURFACE: SurfaceDerivs = SurfaceDerivs {
    p: DVec3::NAN,
    su: DVec3::NAN,
    sv: DVec3::NAN,
    suu: DVec3::NAN,
    suv: DVec3::NAN,
    svv: DVec3::NAN,
};

const NAN_CURVE: CurveDerivs = CurveDerivs {
    p: DVec3::NAN,
    d1: DVec3::NAN,
    d2: DVec3::NAN,
};

#[inline]
fn point3(p: Point3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

#[inline]
fn vec3(v: Vector3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

// ---------------------------------------------------------------------------------------------
// Analytic and swept surfaces
// ---------------------------------------------------------------------------------------------

fn eval_elementary(e: &ElementarySurface, u: f64, v: f64) -> SurfaceDerivs {
    match e {
        ElementarySurface::Plane(pl) => {
            let (o, a, b) = (point3(pl.origin()), vec3(pl.u_axis()), vec3(pl.v_axis()));
            SurfaceDerivs {
                p: o + a * u + b * v,
                su: a,
                sv: b,
                suu: DVec3::ZERO,
                suv: DVec3::ZERO,
                svv: DVec3::ZERO,
            }
        }
        ElementarySurface::Sphere(pr) => {
            let sphere = pr.entity().0;
            let (c, r) = (point3(sphere.center()), sphere.radius());
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                local_sphere(c, r, u, v)
            })
        }
        ElementarySurface::ToroidalSurface(pr) => {
            let torus = pr.entity();
            let c = point3(torus.center());
            let (big, small) = (torus.large_radius(), torus.small_radius());
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                local_torus(c, big, small, u, v)
            })
        }
        ElementarySurface::CylindricalSurface(pr) | ElementarySurface::ConicalSurface(pr) => {
            let rev = pr.entity();
            let (o, a) = (point3(rev.origin()), vec3(rev.axis()));
            let line = rev.entity_curve();
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                revolve(o, a, eval_line(line, u), v)
            })
        }
    }
}

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

/// Applies a truck `Processor<_, Matrix4>`: orientation `false` swaps the parameters
/// (`S(u, v) = E(v, u)`), then the transform maps points and vectors.
#[inline]
fn processed(
    m: &Matrix4,
    orientation: bool,
    u: f64,
    v: f64,
    local: impl FnOnce(f64, f64) -> SurfaceDerivs,
) -> SurfaceDerivs {
    let d = if orientation {
        local(u, v)
    } else {
        let d = local(v, u);
        SurfaceDerivs {
            p: d.p,
            su: d.sv,
            sv: d.su,
            suu: d.svv,
            suv: d.suv,
            svv: d.suu,
        }
    };
    transform_derivs(m, d)
}

/// Maps surface derivatives through a 4×4 homogeneous matrix. Affine matrices (what STEP
/// placements and unit scaling produce) map points and vectors directly; a projective matrix
/// is handled exactly by the quotient rule.
fn transform_derivs(m: &Matrix4, d: SurfaceDerivs) -> SurfaceDerivs {
    let m = DMat4::from_cols_array_2d(&(*m).into());
    let affine = m.x_axis.w == 0.0 && m.y_axis.w == 0.0 && m.z_axis.w == 0.0 && m.w_axis.w == 1.0;
    if affine {
        if m == DMat4::IDENTITY {
            return d;
        }
        SurfaceDerivs {
            p: m.transform_point3(d.p),
            su: m.transform_vector3(d.su),
            sv: m.transform_vector3(d.sv),
            suu: m.transform_vector3(d.suu),
            suv: m.transform_vector3(d.suv),
            svv: m.transform_vector3(d.svv),
        }
    } else {
        rational_surface(&[
            m * d.p.extend(1.0),
            m * d.su.extend(0.0),
            m * d.sv.extend(0.0),
            m * d.suu.extend(0.0),
            m * d.suv.extend(0.0),
            m * d.svv.extend(0.0),
        ])
    }
}

/// truck's `alias::Sphere` before its transform: `S(u, v) = c + r·(cos v cos u, cos v sin u,
/// sin v)` (longitude `u`, latitude `v`).
#[inline]
fn local_sphere(c: DVec3, r: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let radial = DVec3::new(cv * cu, cv * su, 0.0);
    SurfaceDerivs {
        p: c + r * DVec3::new(cv * cu, cv * su, sv),
        su: r * DVec3::new(-cv * su, cv * cu, 0.0),
        sv: r * DVec3::new(-sv * cu, -sv * su, cv),
        suu: -r * radial,
        suv: r * DVec3::new(sv * su, -sv * cu, 0.0),
        svv: -r * DVec3::new(cv * cu, cv * su, sv),
    }
}

/// truck's `Torus`: `S(u, v) = c + ((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`.
#[inline]
fn local_torus(c: DVec3, big: f64, small: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let rho = big + small * cv;
    let e_r = DVec3::new(cu, su, 0.0);
    let e_t = DVec3::new(-su, cu, 0.0);
    SurfaceDerivs {
        p: c + rho * e_r + DVec3::new(0.0, 0.0, small * sv),
        su: rho * e_t,
        sv: small * DVec3::new(-sv * cu, -sv * su, cv),
        suu: -rho * e_r,
        suv: -small * sv * e_t,
        svv: -small * DVec3::new(cv * cu, cv * su, sv),
    }
}

/// truck's `RevolutedCurve`: `S(u, v) = o + R(a, v)·(C(u) − o)` with `R(a, v)` the right-handed
/// rotation by `v` about the unit axis `a`. `∂R/∂v·w = R·(a × w)`, so
/// `Sv = R(a × w)`, `Suv = R(a × C′)`, `Svv = R(a × (a × w))` with `w = C − o`.
#[inline]
fn revolve(o: DVec3, a: DVec3, c: CurveDerivs, v: f64) -> SurfaceDerivs {
    let (s, co) = v.sin_cos();
    // Rodrigues: R·w = w cos v + (a × w) sin v + a (a·w)(1 − cos v).
    let rot = |w: DVec3| w * co + a.cross(w) * s + a * (a.dot(w) * (1.0 - co));
    let w = c.p - o;
    let aw = a.cross(w);
    SurfaceDerivs {
        p: o + rot(w),
        su: rot(c.d1),
        sv: rot(aw),
        suu: rot(c.d2),
        suv: rot(a.cross(c.d1)),
        svv: rot(a.cross(aw)),
    }
}

// ---------------------------------------------------------------------------------------------
// Curves
// ---------------------------------------------------------------------------------------------

#[inline]
fn eval_line(l: &Line<Point3>, t: f64) -> CurveDerivs {
    let (a, b) = (point3(l.0), point3(l.1));
    CurveDerivs {
        p: a + (b - a) * t,
        d1: b - a,
        d2: DVec3::ZERO,
    }
}

/// A polyline parametrised by vertex index (truck's convention), extrapolating the end
/// segments outside `[0, n − 1]`. truck's own `der` panics on a one-point polyline.
fn eval_polyline(pl: &PolylineCurve<Point3>, t: f64) -> CurveDerivs {
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
fn eval_curve2d(c: &Curve2D, t: f64) -> (DVec2, DVec2, DVec2) {
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

// ---------------------------------------------------------------------------------------------
// Rational quotient rule
// ---------------------------------------------------------------------------------------------

/// Piegl & Tiller A4.2 up to order 2: from `A = w·C` and `w` with their derivatives, returns
/// `C`, `C′ = (A′ − w′C)/w`, `C″ = (A″ − 2w′C′ − w″C)/w`.
#[inline]
fn rational_curve<V>(a: [V; 3], w: [f64; 3]) -> (V, V, V)
where
    V: Copy + std::ops::Sub<Output = V> + std::ops::Mul<f64, Output = V>,
{
    let inv = 1.0 / w[0];
    let c = a[0] * inv;
    let c1 = (a[1] - c * w[1]) * inv;
    let c2 = (a[2] - c1 * (2.0 * w[1]) - c * w[2]) * inv;
    (c, c1, c2)
}

/// Piegl & Tiller A4.4 up to order 2. `h` holds the homogeneous `[A, Au, Av, Auu, Auv, Avv]`
/// with the weight in `w`.
#[inline]
fn rational_surface(h: &[DVec4; 6]) -> SurfaceDerivs {
    let a = |k: usize| h[k].truncate();
    let w = |k: usize| h[k].w;
    let inv = 1.0 / w(0);
    let p = a(0) * inv;
    let su = (a(1) - p * w(1)) * inv;
    let sv = (a(2) - p * w(2)) * inv;
    let suu = (a(3) - su * (2.0 * w(1)) - p * w(3)) * inv;
    let suv = (a(4) - su * w(2) - sv * w(1) - p * w(4)) * inv;
    let svv = (a(5) - sv * (2.0 * w(2)) - p * w(5)) * inv;
    SurfaceDerivs {
        p,
        su,
        sv,
        suu,
        suv,
        svv,
    }
}

// ---------------------------------------------------------------------------------------------
// B-spline basis functions and non-rational evaluation
// ---------------------------------------------------------------------------------------------

/// Piegl & Tiller A2.1 with a clamped end convention: the knot span index `s` (`p ≤ s ≤ n`,
/// `uₛ < uₛ₊₁`) whose polynomial piece is used at `t`. Parameters below the range use the
/// first non-empty span, parameters at or above the end the last one (so `t = u_max` belongs
/// to the last span and evaluation extrapolates outside the range). NaN maps to the first
/// span. `None` when the knot vector has no valid span (fewer than `p + 1` control points).
#[inline]
fn find_span(knots: &[f64], p: usize, n_cp: usize, t: f64) -> Option<usize> {
    if n_cp < p + 1 || knots.len() != n_cp + p + 1 {
        return None;
    }
    let n = n_cp - 1;
    if t >= knots[n + 1] {
        let mut s = n;
        while s > p && knots[s] >= knots[s + 1] {
            s -= 1;
        }
        return Some(s);
    }
    if t < knots[p] || t.is_nan() {
        let mut s = p;
        while s < n && knots[s] >= knots[s + 1] {
            s += 1;
        }
        return Some(s);
    }
    // knots[p] ≤ t < knots[n + 1]: the largest s in [p, n] with knots[s] ≤ t.
    let (mut lo, mut hi) = (p, n + 1);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if knots[mid] <= t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

/// The `p + 1` basis functions non-zero on span `span`, `N[r] = N_{span−p+r, p}(t)`, with
/// their first and second derivatives.
struct Basis<'a> {
    span: usize,
    n: &'a [f64],
    d1: &'a [f64],
    d2: &'a [f64],
}

#[inline]
fn inv_or_zero(x: f64) -> f64 {
    if x != 0.0 {
        1.0 / x
    } else {
        0.0
    }
}

/// A2.2 (Cox–de Boor triangle) keeping the degree `p − 1` and `p − 2` rows, then A2.3's
/// derivative recurrence for orders 1 and 2. `buf` needs [`BUF_PER_ORDER`]`·(p + 1)` entries.
fn basis_ders<'a>(knots: &[f64], p: usize, span: usize, t: f64, buf: &'a mut [f64]) -> Basis<'a> {
    let m = p + 1;
    let (n, rest) = buf.split_at_mut(m);
    let (d1, rest) = rest.split_at_mut(m);
    let (d2, rest) = rest.split_at_mut(m);
    let (left, rest) = rest.split_at_mut(m);
    let (right, rest) = rest.split_at_mut(m);
    let (n1, rest) = rest.split_at_mut(m);
    let n2 = &mut rest[..m];
    n[0] = 1.0;
    d1[0] = 0.0;
    d2[0] = 0.0;
    if p == 0 {
        return Basis { span, n, d1, d2 };
    }
    // The knots that matter: w[i] = u_{span+1−p+i}, i = 0..2p.
    let w = &knots[span + 1 - p..span + 1 + p];
    // Degree-0 row saved when it is the p−1 or p−2 row.
    n1[0] = 1.0;
    n2[0] = 1.0;
    for j in 1..m {
        left[j] = t - w[p - j];
        right[j] = w[p - 1 + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            // right[r+1] + left[j−r] is a knot difference, independent of t.
            let temp = n[r] * inv_or_zero(right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
        if j + 2 == p {
            n2[..j + 1].copy_from_slice(&n[..j + 1]);
        } else if j + 1 == p {
            n1[..j + 1].copy_from_slice(&n[..j + 1]);
        }
    }

    let pf = p as f64;
    // Degree p−1 functions N_{span−p+1+j, p−1}, j = 0..p, divided by their knot spans
    // u_{span+1+j} − u_{span−p+1+j} = w[p+j] − w[j]; N′_{span−p+r, p} = p·(q[r−1] − q[r]).
    let q = &mut left[..];
    for j in 0..p {
        q[j] = n1[j] * inv_or_zero(w[p + j] - w[j]);
    }
    d1[0] = -pf * q[0];
    for r in 1..p {
        d1[r] = pf * (q[r - 1] - q[r]);
    }
    d1[p] = pf * q[p - 1];
    for x in d2.iter_mut() {
        *x = 0.0;
    }
    if p >= 2 {
        // Degree p−2 functions scaled by their spans w[p+j] − w[j+1] give
        // e[j] = N′_{span−p+1+j, p−1}/(w[p+j] − w[j]) (into n1), and then
        // N″_{span−p+r, p} = p·(e[r−1] − e[r]).
        for j in 0..p - 1 {
            q[j] = n2[j] * inv_or_zero(w[p + j] - w[j + 1]);
        }
        let pm = (p - 1) as f64;
        n1[0] = -pm * q[0] * inv_or_zero(w[p] - w[0]);
        for j in 1..p - 1 {
            n1[j] = pm * (q[j - 1] - q[j]) * inv_or_zero(w[p + j] - w[j]);
        }
        n1[p - 1] = pm * q[p - 2] * inv_or_zero(w[2 * p - 1] - w[p - 1]);
        d2[0] = -pf * n1[0];
        for r in 1..p {
            d2[r] = pf * (n1[r - 1] - n1[r]);
        }
        d2[p] = pf * n1[p - 1];
    }
    Basis { span, n, d1, d2 }
}

/// Scratch entries per basis function order used by [`basis_ders`].
const BUF_PER_ORDER: usize = 7;

/// Runs `f` on the basis functions at `t`, in stack buffers for degree < [`STACK_ORDER`].
#[inline]
fn with_basis<R>(
    knots: &[f64],
    n_cp: usize,
    t: f64,
    f: impl FnOnce(usize, Basis<'_>) -> R,
) -> Option<R> {
    let p = knots.len().checked_sub(n_cp + 1)?;
    let span = find_span(knots, p, n_cp, t)?;
    // Two stack tiers so that the common low degrees zero a small buffer.
    if p < 4 {
        let mut buf = [0.0; BUF_PER_ORDER * 4];
        Some(f(p, basis_ders(knots, p, span, t, &mut buf)))
    } else if p < STACK_ORDER {
        let mut buf = [0.0; BUF_PER_ORDER * STACK_ORDER];
        Some(f(p, basis_ders(knots, p, span, t, &mut buf)))
    } else {
        let mut buf = vec![0.0; BUF_PER_ORDER * (p + 1)];
        Some(f(p, basis_ders(knots, p, span, t, &mut buf)))
    }
}

#[inline(always)]
fn axpy<const D: usize>(acc: &mut [f64; D], a: f64, x: &[f64; D]) {
    for k in 0..D {
        acc[k] += a * x[k];
    }
}

/// `[C, C′, C″]` of a (homogeneous) B-spline curve with control points mapped by `coords`.
fn bspline_curve_ders<P, const D: usize>(
    knots: &[f64],
    cps: &[P],
    coords: impl Fn(&P) -> [f64; D],
    t: f64,
) -> Option<[[f64; D]; 3]> {
    with_basis(knots, cps.len(), t, |p, b| {
        let mut out = [[0.0; D]; 3];
        let active = &cps[b.span - p..b.span + 1];
        for (cp, ((&b0, &b1), &b2)) in active.iter().zip(b.n.iter().zip(b.d1).zip(b.d2)) {
            let c = coords(cp);
            axpy(&mut out[0], b0, &c);
            axpy(&mut out[1], b1, &c);
            axpy(&mut out[2], b2, &c);
        }
        out
    })
}

/// `[S, Su, Sv, Suu, Suv, Svv]` of a (homogeneous) tensor-product B-spline surface, control
/// points `cps[i][j]` (`i` along `u`) mapped by `coords` (Piegl & Tiller A3.6, order 2).
fn bspline_surface_ders<P, const D: usize>(
    uknots: &[f64],
    vknots: &[f64],
    cps: &[Vec<P>],
    coords: impl Fn(&P) -> [f64; D],
    u: f64,
    v: f64,
) -> Option<[[f64; D]; 6]> {
    let n_v = cps.first()?.len();
    with_basis(uknots, cps.len(), u, |p, bu| {
        with_basis(vknots, n_v, v, |q, bv| {
            let mut s = [[0.0; D]; 6];
            let rows = &cps[bu.span - p..bu.span + 1];
            let ubasis = bu.n.iter().zip(bu.d1).zip(bu.d2);
            for (row, ((&n, &n1), &n2)) in rows.iter().zip(ubasis) {
                let row = &row[bv.span - q..bv.span + 1];
                let (mut t0, mut t1, mut t2) = ([0.0; D], [0.0; D], [0.0; D]);
                for (cp, ((&m, &m1), &m2)) in row.iter().zip(bv.n.iter().zip(bv.d1).zip(bv.d2)) {
                    let c = coords(cp);
                    axpy(&mut t0, m, &c);
                    axpy(&mut t1, m1, &c);
                    axpy(&mut t2, m2, &c);
                }
                axpy(&mut s[0], n, &t0);
                axpy(&mut s[1], n1, &t0);
                axpy(&mut s[2], n, &t1);
                axpy(&mut s[3], n2, &t0);
                axpy(&mut s[4], n1, &t1);
                axpy(&mut s[5], n, &t2);
            }
            s
        })
    })
    .flatten()
}

/// The `p + 1` basis functions non-zero on span `span` without derivatives: A2.2 alone, the
/// same arithmetic as [`basis_ders`]' `n`. `buf` needs `3·(p + 1)` entries.
fn basis_values<'a>(knots: &[f64], p: usize, span: usize, t: f64, buf: &'a mut [f64]) -> &'a [f64] {
    let m = p + 1;
    let (n, rest) = buf.split_at_mut(m);
    let (left, right) = rest.split_at_mut(m);
    n[0] = 1.0;
    if p == 0 {
        return n;
    }
    let w = &knots[span + 1 - p..span + 1 + p];
    for j in 1..m {
        left[j] = t - w[p - j];
        right[j] = w[p - 1 + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = n[r] * inv_or_zero(right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

/// [`with_basis`] for [`basis_values`].
#[inline]
fn with_values<R>(
    knots: &[f64],
    n_cp: usize,
    t: f64,
    f: impl FnOnce(usize, usize, &[f64]) -> R,
) -> Option<R> {
    let p = knots.len().checked_sub(n_cp + 1)?;
    let span = find_span(knots, p, n_cp, t)?;
    if p < STACK_ORDER {
        let mut buf = [0.0; 3 * STACK_ORDER];
        Some(f(p, span, basis_values(knots, p, span, t, &mut buf)))
    } else {
        let mut buf = vec![0.0; 3 * (p + 1)];
        Some(f(p, span, basis_values(knots, p, span, t, &mut buf)))
    }
}

/// `S` of a (homogeneous) tensor-product B-spline surface: [`bspline_surface_ders`]' first
/// row, summed in the same order.
fn bspline_surface_point<P, const D: usize>(
    uknots: &[f64],
    vknots: &[f64],
    cps: &[Vec<P>],
    coords: impl Fn(&P) -> [f64; D],
    u: f64,
    v: f64,
) -> Option<[f64; D]> {
    let n_v = cps.first()?.len();
    with_values(uknots, cps.len(), u, |p, uspan, nu| {
        with_values(vknots, n_v, v, |q, vspan, nv| {
            tensor_point(&cps[uspan - p..uspan + 1], nu, (q, vspan, nv), &coords)
        })
    })
    .flatten()
}

/// `Σᵢ nu[i] · Σⱼ nv[j] · coords(rows[i][vspan − q + j])`, in [`bspline_surface_ders`]' order.
#[inline]
fn tensor_point<P, const D: usize>(
    rows: &[Vec<P>],
    nu: &[f64],
    (q, vspan, nv): (usize, usize, &[f64]),
    coords: impl Fn(&P) -> [f64; D],
) -> [f64; D] {
    let mut s = [0.0; D];
    for (row, &n) in rows.iter().zip(nu) {
        let mut t0 = [0.0; D];
        for (cp, &m) in row[vspan - q..vspan + 1].iter().zip(nv) {
            axpy(&mut t0, m, &coords(cp));
        }
        axpy(&mut s, n, &t0);
    }
    s
}

#[cfg(test)]
pub(crate) mod tests {
    //! Every surface and curve kind against central finite differences, our B-spline values
    //! against truck's `subs`, and the truck bug that makes us hand-write B-splines.
    //!
    //! Finite-difference tolerance. With step `h` the central difference has truncation error
    //! `h²/6·‖f‴‖` and rounding error `≈ ε‖f‖/h` (`ε = 2.2e-16`). The test geometry has
    //! coordinates of a few units and knot spans ≥ 0.1 in parameter ranges of a few units, so
    //! `‖f‖` and `‖f‴‖` are within ~10³ of the derivative scale `σ = ‖Su‖ + ‖Sv‖ + ‖Suu‖ +
    //! ‖Suv‖ + ‖Svv‖`; with `h = 1e-5` both error terms are ≲ 1e-8·σ. We require
    //! `‖analytic − FD‖ ≤ 1e-6·σ`: ×100 margin, while a wrong factor such as truck's
    //! (`Suu` short by ½ for cubics) is an error of order 0.1·σ — five orders above the bar.
    //! Sample points keep ≥ 1e-3 away from knots, where the derivatives of a spline of low
    //! continuity jump and a difference quotient straddling the knot would be meaningless.

    use super::*;
    use std::f64::consts::PI;
    use std::str::FromStr;
    use truck_geometry::prelude::ExtrudedCurve;
    use truck_geometry::prelude::{
        BSplineCurve, BSplineSurface, Invertible, KnotVec, Matrix4, NurbsCurve, NurbsSurface,
        PCurve, ParametricCurve, ParametricSurface, Point2, Point3, Processor, Rad, RevolutedCurve,
        Transformed, TrimmedCurve, UnitCircle, UnitHyperbola, UnitParabola, Vector3, Vector4,
    };
    use truck_stepio::r#in::alias::{Conic3D, Curve2D, SweptCurve};

    pub(crate) const FD_H: f64 = 1e-5;
    pub(crate) const FD_TOL: f64 = 1e-6;

    // ------------------------------------------------------------------ test geometry

    /// A surface read from a one-entity STEP DATA section, through truck-stepio's own
    /// conversion (so the parametrisation and `Processor` flags are exactly what ingest sees).
    /// The placement is a rotated, translated frame.
    pub(crate) fn step_surface(entity: &str) -> Surface {
        use truck_stepio::r#in::ruststep::{ast::DataSection, tables::EntityTable};
        use truck_stepio::r#in::{SurfaceAnyHolder, Table};
        let text = format!(
            "DATA;\n#1 = {entity};\n\
             #2 = AXIS2_PLACEMENT_3D('', #3, #4, #5);\n\
             #3 = CARTESIAN_POINT('', (1.0, -2.0, 0.5));\n\
             #4 = DIRECTION('', (0.36, 0.48, 0.8));\n\
             #5 = DIRECTION('', (0.8, -0.6, 0.0));\n\
             ENDSEC;"
        );
        let ds = DataSection::from_str(&text).expect("STEP snippet parses");
        let table = Table::from_data_section(&ds);
        let any = EntityTable::<SurfaceAnyHolder>::get_owned(&table, 1).expect("entity #1");
        Surface::try_from(&any).expect("converts to a truck surface")
    }

    pub(crate) fn plane() -> Surface {
        step_surface("PLANE('', #2)")
    }
    pub(crate) fn sphere(r: f64) -> Surface {
        step_surface(&format!("SPHERICAL_SURFACE('', #2, {r:?})"))
    }
    pub(crate) fn cylinder(r: f64) -> Surface {
        step_surface(&format!("CYLINDRICAL_SURFACE('', #2, {r:?})"))
    }
    pub(crate) fn torus(big: f64, small: f64) -> Surface {
        step_surface(&format!("TOROIDAL_SURFACE('', #2, {big:?}, {small:?})"))
    }
    pub(crate) fn cone(r: f64, semi_angle: f64) -> Surface {
        step_surface(&format!("CONICAL_SURFACE('', #2, {r:?}, {semi_angle:?})"))
    }

    /// A rigid motion plus uniform scale, as ingest applies for placements and units.
    fn placement() -> Matrix4 {
        Matrix4::from_translation(Vector3::new(0.3, -1.2, 2.0))
            * Matrix4::from_axis_angle(Vector3::new(1.0, 2.0, 2.0) / 3.0, Rad(0.7))
            * Matrix4::from_scale(1.5)
    }

    /// Clamped knot vector on `[a, b]` with the given interior knots.
    pub(crate) fn knots(p: usize, a: f64, b: f64, interior: &[f64]) -> KnotVec {
        let mut k = vec![a; p + 1];
        k.extend_from_slice(interior);
        k.extend(std::iter::repeat_n(b, p + 1));
        KnotVec::from(k)
    }

    /// Non-uniform interior knots on `[-1, 2.5]` (u) and `[0, 1]` (v), with multiplicities up
    /// to `p` (C⁰ at most for degree ≥ 2: double knots for p = 2, 3, triple for p = 4).
    pub(crate) fn u_knots(p: usize) -> KnotVec {
        let interior: &[f64] = match p {
            1 => &[-0.2, 0.6, 1.7],
            2 => &[-0.2, 0.6, 0.6, 1.7],
            3 => &[-0.55, 0.1, 0.6, 0.6, 1.2, 1.7, 1.7],
            _ => &[0.3, 0.9, 0.9, 0.9, 1.9],
        };
        knots(p, -1.0, 2.5, interior)
    }
    pub(crate) fn v_knots(p: usize) -> KnotVec {
        let interior: &[f64] = match p {
            1 => &[0.3, 0.55],
            2 => &[0.25, 0.25, 0.7],
            3 => &[0.2, 0.5, 0.5, 0.8],
            _ => &[0.1, 0.45, 0.45, 0.45, 0.8],
        };
        knots(p, 0.0, 1.0, interior)
    }

    fn n_cp(k: &KnotVec, p: usize) -> usize {
        k.len() - p - 1
    }

    /// A wavy control net of a few units with an offset, deterministic.
    pub(crate) fn net(nu: usize, nv: usize) -> Vec<Vec<Point3>> {
        (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| {
                        let (x, y) = (i as f64, j as f64);
                        Point3::new(
                            1.0 + 0.9 * x + 0.2 * (1.7 * x + 0.3 * y).sin(),
                            -2.0 + 0.8 * y + 0.2 * (0.9 * x + 2.1 * y).cos(),
                            0.5 + 0.6 * (1.3 * x + 0.7 * y).sin() + 0.3 * (2.3 * y - x).cos(),
                        )
                    })
                    .collect()
            })
            .collect()
    }

    pub(crate) fn weight(i: usize, j: usize) -> f64 {
        0.6 + 1.2 * (0.5 + 0.5 * (1.1 * i as f64 + 0.8 * j as f64 + 0.3).sin())
    }

    pub(crate) fn bspline_surface(p: usize, q: usize) -> BSplineSurface<Point3> {
        let (ku, kv) = (u_knots(p), v_knots(q));
        let cps = net(n_cp(&ku, p), n_cp(&kv, q));
        BSplineSurface::new((ku, kv), cps)
    }

    pub(crate) fn nurbs_surface(p: usize, q: usize) -> NurbsSurface<Vector4> {
        let (ku, kv) = (u_knots(p), v_knots(q));
        let cps = net(n_cp(&ku, p), n_cp(&kv, q))
            .into_iter()
            .enumerate()
            .map(|(i, row)| {
                row.into_iter()
                    .enumerate()
                    .map(|(j, c)| {
                        let w = weight(i, j);
                        Vector4::new(c.x * w, c.y * w, c.z * w, w)
                    })
                    .collect()
            })
            .collect();
        NurbsSurface::new(BSplineSurface::new((ku, kv), cps))
    }

    pub(crate) fn bspline_curve(p: usize) -> BSplineCurve<Point3> {
        let k = u_knots(p);
        let cps = net(n_cp(&k, p), 2).into_iter().map(|row| row[1]).collect();
        BSplineCurve::new(k, cps)
    }

    pub(crate) fn nurbs_curve(p: usize) -> NurbsCurve<Vector4> {
        let k = u_knots(p);
        let cps = net(n_cp(&k, p), 2)
            .into_iter()
            .enumerate()
            .map(|(i, row)| {
                let (c, w) = (row[1], weight(i, 3));
                Vector4::new(c.x * w, c.y * w, c.z * w, w)
            })
            .collect();
        NurbsCurve::new(BSplineCurve::new(k, cps))
    }

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

    // ------------------------------------------------------------------ checkers

    /// Sample points on an `n × n` grid over `[u0, u1] × [v0, v1]`, offset so they avoid
    /// the ends, and dropped when within 1e-3 of a listed knot.
    pub(crate) fn grid(
        (u0, u1): (f64, f64),
        (v0, v1): (f64, f64),
        n: usize,
        uknots: &[f64],
        vknots: &[f64],
    ) -> Vec<(f64, f64)> {
        let far = |t: f64, ks: &[f64]| ks.iter().all(|k| (t - k).abs() > 1e-3);
        let mut pts = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let u = u0 + (u1 - u0) * (i as f64 + 0.37) / n as f64;
                let v = v0 + (v1 - v0) * (j as f64 + 0.61) / n as f64;
                if far(u, uknots) && far(v, vknots) {
                    pts.push((u, v));
                }
            }
        }
        pts
    }

    /// Largest FD error of each of `[Su, Sv, Suu, Suv (from Su), Suv (from Sv), Svv]`,
    /// relative to the derivative scale σ, over `params`.
    pub(crate) fn surface_fd_errors(
        params: &[(f64, f64)],
        eval: impl Fn(f64, f64) -> SurfaceDerivs,
    ) -> [f64; 6] {
        let h = FD_H;
        let mut worst = [0.0f64; 6];
        for &(u, v) in params {
            let d = eval(u, v);
            let (up, um, vp, vm) = (
                eval(u + h, v),
                eval(u - h, v),
                eval(u, v + h),
                eval(u, v - h),
            );
            let sigma =
                d.su.length() + d.sv.length() + d.suu.length() + d.suv.length() + d.svv.length();
            let fd = [
                (up.p - um.p) / (2.0 * h),
                (vp.p - vm.p) / (2.0 * h),
                (up.su - um.su) / (2.0 * h),
                (vp.su - vm.su) / (2.0 * h),
                (up.sv - um.sv) / (2.0 * h),
                (vp.sv - vm.sv) / (2.0 * h),
            ];
            let an = [d.su, d.sv, d.suu, d.suv, d.suv, d.svv];
            for k in 0..6 {
                let e = (fd[k] - an[k]).length() / sigma;
                assert!(e.is_finite(), "non-finite derivative at ({u}, {v})");
                worst[k] = worst[k].max(e);
            }
        }
        worst
    }

    /// Asserts [`surface_fd_errors`] ≤ [`FD_TOL`] for `eval_surface(s)` on `params`.
    pub(crate) fn assert_surface_fd(name: &str, s: &Surface, params: &[(f64, f64)]) {
        assert!(
            params.len() >= 16,
            "{name}: only {} sample points",
            params.len()
        );
        let worst = surface_fd_errors(params, |u, v| eval_surface(s, u, v));
        let names = ["su", "sv", "suu", "suv(u)", "suv(v)", "svv"];
        for k in 0..6 {
            assert!(
                worst[k] <= FD_TOL,
                "{name}: {} differs from finite differences by {:.3e}·σ (all: {worst:?})",
                names[k],
                worst[k]
            );
        }
    }

    pub(crate) fn assert_curve_fd(name: &str, c: &Curve3D, params: &[f64]) {
        assert!(
            params.len() >= 10,
            "{name}: only {} sample points",
            params.len()
        );
        let h = FD_H;
        for &t in params {
            let d = eval_curve(c, t);
            let (a, b) = (eval_curve(c, t + h), eval_curve(c, t - h));
            let sigma = d.d1.length() + d.d2.length();
            let e1 = ((a.p - b.p) / (2.0 * h) - d.d1).length() / sigma;
            let e2 = ((a.d1 - b.d1) / (2.0 * h) - d.d2).length() / sigma;
            assert!(
                e1 <= FD_TOL && e2 <= FD_TOL,
                "{name} at t = {t}: d1 error {e1:.3e}·σ, d2 error {e2:.3e}·σ"
            );
        }
    }

    fn curve_params((t0, t1): (f64, f64), n: usize, knots: &[f64]) -> Vec<f64> {
        (0..n)
            .map(|i| t0 + (t1 - t0) * (i as f64 + 0.37) / n as f64)
            .filter(|t| knots.iter().all(|k| (t - k).abs() > 1e-3))
            .collect()
    }

    fn rel(a: DVec3, b: DVec3, scale: f64) -> f64 {
        (a - b).length() / scale
    }

    fn p3(p: Point3) -> DVec3 {
        DVec3::new(p.x, p.y, p.z)
    }
    fn v3(v: Vector3) -> DVec3 {
        DVec3::new(v.x, v.y, v.z)
    }

    // ------------------------------------------------------------------ analytic surfaces

    fn analytic_surfaces() -> Vec<(String, Surface)> {
        let base = [
            ("plane", plane()),
            ("sphere", sphere(2.5)),
            ("cylinder", cylinder(1.5)),
            ("torus", torus(3.0, 1.0)),
            ("cone", cone(1.5, 0.3)),
        ];
        // Each also with the orientation flag flipped (u and v swap) and scaled as a unit
        // conversion would.
        base.into_iter()
            .flat_map(|(name, s)| {
                let flipped = s.inverse().transformed(Matrix4::from_scale(25.4));
                [
                    (name.to_string(), s),
                    (format!("{name} inverted+scaled"), flipped),
                ]
            })
            .collect()
    }

    #[test]
    fn analytic_surfaces_match_finite_differences() {
        for (name, s) in analytic_surfaces() {
            let params = grid((-0.4, 2.0 * PI), (-1.2, 1.2), 9, &[], &[]);
            assert_surface_fd(&name, &s, &params);
        }
    }

    /// Our closed forms reproduce truck's parametrisation (the values), and truck's analytic
    /// derivatives, which are right for these kinds.
    #[test]
    fn analytic_surfaces_agree_with_truck() {
        for (name, s) in analytic_surfaces() {
            for (u, v) in grid((-0.4, 2.0 * PI), (-1.2, 1.2), 7, &[], &[]) {
                let d = eval_surface(&s, u, v);
                let scale = p3(s.subs(u, v)).length().max(1.0);
                let truck = [
                    (d.p, p3(s.subs(u, v))),
                    (d.su, v3(s.uder(u, v))),
                    (d.sv, v3(s.vder(u, v))),
                    (d.suu, v3(s.uuder(u, v))),
                    (d.suv, v3(s.uvder(u, v))),
                    (d.svv, v3(s.vvder(u, v))),
                ];
                for (k, (ours, theirs)) in truck.into_iter().enumerate() {
                    assert!(
                        rel(ours, theirs, scale) < 1e-12,
                        "{name} output {k} at ({u}, {v}): ours {ours:?}, truck {theirs:?}"
                    );
                }
            }
        }
    }

    /// A projective placement matrix (no STEP entity produces one, but `Matrix4` allows it)
    /// goes through the quotient rule: values equal truck's `subs`, derivatives pass the
    /// finite-difference check.
    #[test]
    fn projective_transform_uses_quotient_rule() {
        #[rustfmt::skip]
        let m = Matrix4::new(
            1.0, 0.2, 0.0, 0.05,
            0.0, 1.1, 0.3, 0.02,
            0.1, 0.0, 0.9, 0.01,
            0.5, -0.3, 0.2, 1.0,
        );
        let s = sphere(2.5).transformed(m);
        let params = grid((-0.4, 2.0 * PI), (-1.2, 1.2), 9, &[], &[]);
        assert_surface_fd("projected sphere", &s, &params);
        for (u, v) in params {
            let theirs = p3(s.subs(u, v));
            assert!(rel(eval_surface(&s, u, v).p, theirs, theirs.length()) < 1e-12);
        }
    }

    // ------------------------------------------------------------------ B-splines and NURBS

    const DEGREE_PAIRS: [(usize, usize); 7] =
        [(1, 1), (2, 1), (1, 3), (2, 2), (3, 3), (4, 3), (4, 4)];

    #[test]
    fn bspline_surfaces_match_finite_differences() {
        for (p, q) in DEGREE_PAIRS {
            let b = bspline_surface(p, q);
            let params = grid((-1.0, 2.5), (0.0, 1.0), 12, b.uknot_vec(), b.vknot_vec());
            let s = Surface::BSplineSurface(Box::new(b));
            assert_surface_fd(&format!("B-spline {p}×{q}"), &s, &params);
        }
    }

    #[test]
    fn nurbs_surfaces_match_finite_differences() {
        for (p, q) in [(2, 2), (3, 3), (2, 3), (4, 2)] {
            let n = nurbs_surface(p, q);
            let params = grid((-1.0, 2.5), (0.0, 1.0), 12, n.uknot_vec(), n.vknot_vec());
            let s = Surface::NurbsSurface(Box::new(n));
            assert_surface_fd(&format!("NURBS {p}×{q}"), &s, &params);
        }
    }

    /// Values equal truck's `subs` (which is right) to 1e-12, everywhere including the knots
    /// and both ends of the range; first derivatives and `uvder`, which truck gets right,
    /// agree to 1e-10 of the derivative scale.
    #[test]
    fn bspline_and_nurbs_values_equal_truck_subs() {
        let mut ts: Vec<(f64, f64)> = grid((-1.0, 2.5), (0.0, 1.0), 9, &[], &[]);
        for uk in u_knots(3).iter().chain(u_knots(4).iter()) {
            for vk in v_knots(3).iter().chain(v_knots(2).iter()) {
                ts.push((*uk, *vk));
            }
        }
        for (p, q) in DEGREE_PAIRS {
            let b = bspline_surface(p, q);
            let n = nurbs_surface(p, q);
            for &(u, v) in &ts {
                let ours = eval_bspline_surface(&b, u, v);
                let theirs = p3(b.subs(u, v));
                assert!(
                    rel(ours.p, theirs, theirs.length()) < 1e-12,
                    "B-spline {p}×{q} at ({u}, {v}): {:?} vs {theirs:?}",
                    ours.p
                );
                let ours = eval_nurbs_surface(&n, u, v);
                let theirs = p3(n.subs(u, v));
                assert!(
                    rel(ours.p, theirs, theirs.length()) < 1e-12,
                    "NURBS {p}×{q} at ({u}, {v}): {:?} vs {theirs:?}",
                    ours.p
                );
            }
            // Away from knots (where truck's one-sided convention may pick the other piece).
            for (u, v) in grid((-1.0, 2.5), (0.0, 1.0), 9, b.uknot_vec(), b.vknot_vec()) {
                let d = eval_bspline_surface(&b, u, v);
                let sigma = d.su.length() + d.sv.length() + d.suv.length();
                for (k, (ours, theirs)) in [
                    (d.su, v3(b.uder(u, v))),
                    (d.sv, v3(b.vder(u, v))),
                    (d.suv, v3(b.uvder(u, v))),
                ]
                .into_iter()
                .enumerate()
                {
                    assert!(
                        rel(ours, theirs, sigma) < 1e-10,
                        "B-spline {p}×{q} derivative {k} at ({u}, {v}): {ours:?} vs {theirs:?}"
                    );
                }
            }
        }
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

    /// DESIGN.md fact 4: truck's `uuder`/`vvder` are short by the factor `p − 1`. Measured on
    /// a cubic and a quartic B-spline and a cubic NURBS against finite differences of truck's
    /// own (correct) `uder`/`vder`; ours passes the same check.
    #[test]
    fn truck_uuder_is_wrong_for_cubic_and_ours_is_right() {
        for p in [3usize, 4] {
            let b = bspline_surface(p, p);
            let params = grid((-1.0, 2.5), (0.0, 1.0), 8, b.uknot_vec(), b.vknot_vec());
            let h = FD_H;
            let (mut ratio_uu, mut ratio_vv) = (0.0f64, 0.0f64);
            for &(u, v) in &params {
                let fd_uu = (v3(b.uder(u + h, v)) - v3(b.uder(u - h, v))) / (2.0 * h);
                let fd_vv = (v3(b.vder(u, v + h)) - v3(b.vder(u, v - h))) / (2.0 * h);
                // truck's value is exactly fd/(p − 1): measure the ratio.
                ratio_uu = ratio_uu.max(v3(b.uuder(u, v)).length() / fd_uu.length());
                ratio_vv = ratio_vv.max(v3(b.vvder(u, v)).length() / fd_vv.length());
                let ours = eval_bspline_surface(&b, u, v);
                let sigma = ours.suu.length() + ours.svv.length() + ours.su.length();
                assert!(rel(ours.suu, fd_uu, sigma) < FD_TOL);
                assert!(rel(ours.svv, fd_vv, sigma) < FD_TOL);
            }
            let expected = 1.0 / (p - 1) as f64;
            eprintln!(
                "degree {p}: truck |uuder|/|FD| = {ratio_uu:.6}, |vvder|/|FD| = {ratio_vv:.6} \
                 (1/(p−1) = {expected:.6})"
            );
            assert!(
                (ratio_uu - expected).abs() < 1e-6,
                "truck uuder ratio {ratio_uu}"
            );
            assert!(
                (ratio_vv - expected).abs() < 1e-6,
                "truck vvder ratio {ratio_vv}"
            );
        }
        // NURBS inherit it through the quotient rule.
        let n = nurbs_surface(3, 3);
        let params = grid((-1.0, 2.5), (0.0, 1.0), 8, n.uknot_vec(), n.vknot_vec());
        let truck_err = surface_fd_errors(&params, |u, v| SurfaceDerivs {
            p: p3(n.subs(u, v)),
            su: v3(n.uder(u, v)),
            sv: v3(n.vder(u, v)),
            suu: v3(n.uuder(u, v)),
            suv: v3(n.uvder(u, v)),
            svv: v3(n.vvder(u, v)),
        });
        let ours = surface_fd_errors(&params, |u, v| eval_nurbs_surface(&n, u, v));
        eprintln!("cubic NURBS, worst FD error/σ [su sv suu suv suv svv]: truck {truck_err:?}, ours {ours:?}");
        assert!(
            truck_err[2] > 1e-2 && truck_err[5] > 1e-2,
            "truck NURBS uuder/vvder now right?"
        );
        assert!(ours.iter().all(|e| *e < FD_TOL));
    }

    /// Parameters outside the knot range extrapolate the end polynomial pieces: no panic,
    /// finite, and still consistent with finite differences.
    #[test]
    fn out_of_range_parameters_extrapolate() {
        let b = Surface::BSplineSurface(Box::new(bspline_surface(3, 4)));
        let n = Surface::NurbsSurface(Box::new(nurbs_surface(3, 2)));
        // A tenth of a span or so outside: far out, an extrapolated weight function may come
        // near zero and the rational surface is ill-conditioned (which is no bug).
        let outside = [
            (-1.1, 0.4),
            (2.6, 0.4),
            (0.4, -0.08),
            (0.4, 1.08),
            (-1.05, 1.05),
            (2.6, -0.05),
        ];
        let mut params = Vec::new();
        for (u, v) in outside {
            for k in 0..4 {
                params.push((u + 0.01 * k as f64, v - 0.007 * k as f64));
            }
        }
        assert_surface_fd("B-spline outside", &b, &params);
        assert_surface_fd("NURBS outside", &n, &params);
        // Non-finite input: no panic.
        let d = eval_surface(&b, f64::NAN, 0.5);
        assert!(d.p.is_nan());
        let d = eval_surface(&b, f64::INFINITY, f64::NEG_INFINITY);
        assert!(!d.p.is_finite());
    }

    /// Degree ≥ STACK_ORDER takes the allocating path; same answers.
    #[test]
    fn high_degree_uses_heap_path_correctly() {
        let p = STACK_ORDER + 1;
        let k = knots(p, 0.0, 2.0, &[0.7, 1.3]);
        let cps: Vec<Point3> = net(k.len() - p - 1, 2).into_iter().map(|r| r[0]).collect();
        let c = BSplineCurve::new(k.clone(), cps);
        for i in 0..=20 {
            let t = 2.0 * i as f64 / 20.0;
            let theirs = p3(c.subs(t));
            assert!(rel(eval_bspline_curve(&c, t).p, theirs, theirs.length()) < 1e-12);
        }
        let c = Curve3D::BSplineCurve(c);
        assert_curve_fd("degree-12 curve", &c, &curve_params((0.0, 2.0), 23, &k));
    }

    // ------------------------------------------------------------------ swept surfaces

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

    // ------------------------------------------------------------------ curves

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
    fn curve_values_equal_truck_and_truck_der2_is_right_for_curves() {
        for p in 1..=4 {
            let b = bspline_curve(p);
            let n = nurbs_curve(p);
            let k = u_knots(p);
            for t in curve_params((-1.0, 2.5), 37, &k)
                .into_iter()
                .chain(k.iter().copied())
            {
                let theirs = p3(b.subs(t));
                assert!(rel(eval_bspline_curve(&b, t).p, theirs, theirs.length()) < 1e-12);
                let theirs = p3(n.subs(t));
                assert!(rel(eval_nurbs_curve(&n, t).p, theirs, theirs.length()) < 1e-12);
            }
            // Measured: truck's curve der/der2 are right (unlike its surfaces).
            for t in curve_params((-1.0, 2.5), 37, &k) {
                let d = eval_bspline_curve(&b, t);
                let s = d.d1.length() + d.d2.length();
                assert!(rel(d.d1, v3(b.der(t)), s) < 1e-10 && rel(d.d2, v3(b.der2(t)), s) < 1e-10);
                let d = eval_nurbs_curve(&n, t);
                let s = d.d1.length() + d.d2.length();
                assert!(rel(d.d1, v3(n.der(t)), s) < 1e-10 && rel(d.d2, v3(n.der2(t)), s) < 1e-10);
            }
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
