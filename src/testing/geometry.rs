//! Test geometry shared by the unit tests of `geom` (compiled in test builds only): analytic
//! surfaces read from STEP snippets, B-spline and NURBS curves and surfaces on non-uniform
//! knots, parameter grids that avoid knots, and checks of derivatives against central finite
//! differences.
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

use crate::geom::eval::{eval_curve, eval_surface, SurfaceDerivs};
use crate::model::{Curve3D, Face, Model, Surface};
use glam::{DVec2, DVec3};
use std::str::FromStr;
use truck_geometry::prelude::{
    BSplineCurve, BSplineSurface, KnotVec, Matrix4, NurbsCurve, NurbsSurface, Point3, Rad, Vector3,
    Vector4,
};

/// Central finite-difference step.
pub const FD_H: f64 = 1e-5;

/// Largest finite-difference error allowed, relative to the derivative scale σ.
pub const FD_TOL: f64 = 1e-6;

/// A surface read from a one-entity STEP DATA section, through truck-stepio's own
/// conversion (so the parametrisation and `Processor` flags are exactly what ingest sees).
/// The placement is a rotated, translated frame.
pub fn step_surface(entity: &str) -> Surface {
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

pub fn plane() -> Surface {
    step_surface("PLANE('', #2)")
}

pub fn sphere(r: f64) -> Surface {
    step_surface(&format!("SPHERICAL_SURFACE('', #2, {r:?})"))
}

pub fn cylinder(r: f64) -> Surface {
    step_surface(&format!("CYLINDRICAL_SURFACE('', #2, {r:?})"))
}

pub fn torus(big: f64, small: f64) -> Surface {
    step_surface(&format!("TOROIDAL_SURFACE('', #2, {big:?}, {small:?})"))
}

pub fn cone(r: f64, semi_angle: f64) -> Surface {
    step_surface(&format!("CONICAL_SURFACE('', #2, {r:?}, {semi_angle:?})"))
}

/// A rigid motion plus uniform scale, as ingest applies for placements and units.
pub fn placement() -> Matrix4 {
    Matrix4::from_translation(Vector3::new(0.3, -1.2, 2.0))
        * Matrix4::from_axis_angle(Vector3::new(1.0, 2.0, 2.0) / 3.0, Rad(0.7))
        * Matrix4::from_scale(1.5)
}

/// Clamped knot vector on `[a, b]` with the given interior knots.
pub fn knots(p: usize, a: f64, b: f64, interior: &[f64]) -> KnotVec {
    let mut k = vec![a; p + 1];
    k.extend_from_slice(interior);
    k.extend(std::iter::repeat_n(b, p + 1));
    KnotVec::from(k)
}

/// Non-uniform interior knots on `[-1, 2.5]` (u) and `[0, 1]` (v), with multiplicities up
/// to `p` (C⁰ at most for degree ≥ 2: double knots for p = 2, 3, triple for p = 4).
pub fn u_knots(p: usize) -> KnotVec {
    let interior: &[f64] = match p {
        1 => &[-0.2, 0.6, 1.7],
        2 => &[-0.2, 0.6, 0.6, 1.7],
        3 => &[-0.55, 0.1, 0.6, 0.6, 1.2, 1.7, 1.7],
        _ => &[0.3, 0.9, 0.9, 0.9, 1.9],
    };
    knots(p, -1.0, 2.5, interior)
}

pub fn v_knots(p: usize) -> KnotVec {
    let interior: &[f64] = match p {
        1 => &[0.3, 0.55],
        2 => &[0.25, 0.25, 0.7],
        3 => &[0.2, 0.5, 0.5, 0.8],
        _ => &[0.1, 0.45, 0.45, 0.45, 0.8],
    };
    knots(p, 0.0, 1.0, interior)
}

pub fn n_cp(k: &KnotVec, p: usize) -> usize {
    k.len() - p - 1
}

/// A wavy control net of a few units with an offset, deterministic.
pub fn net(nu: usize, nv: usize) -> Vec<Vec<Point3>> {
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

pub fn weight(i: usize, j: usize) -> f64 {
    0.6 + 1.2 * (0.5 + 0.5 * (1.1 * i as f64 + 0.8 * j as f64 + 0.3).sin())
}

pub fn bspline_surface(p: usize, q: usize) -> BSplineSurface<Point3> {
    let (ku, kv) = (u_knots(p), v_knots(q));
    let cps = net(n_cp(&ku, p), n_cp(&kv, q));
    BSplineSurface::new((ku, kv), cps)
}

pub fn nurbs_surface(p: usize, q: usize) -> NurbsSurface<Vector4> {
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

pub fn bspline_curve(p: usize) -> BSplineCurve<Point3> {
    let k = u_knots(p);
    let cps = net(n_cp(&k, p), 2).into_iter().map(|row| row[1]).collect();
    BSplineCurve::new(k, cps)
}

pub fn nurbs_curve(p: usize) -> NurbsCurve<Vector4> {
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

/// Degree pairs `(p, q)` the B-spline and NURBS surface tests go through.
pub const DEGREE_PAIRS: [(usize, usize); 7] =
    [(1, 1), (2, 1), (1, 3), (2, 2), (3, 3), (4, 3), (4, 4)];

/// Sample points on an `n × n` grid over `[u0, u1] × [v0, v1]`, offset so they avoid
/// the ends, and dropped when within 1e-3 of a listed knot.
pub fn grid(
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
pub fn surface_fd_errors(
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
pub fn assert_surface_fd(name: &str, s: &Surface, params: &[(f64, f64)]) {
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

pub fn assert_curve_fd(name: &str, c: &Curve3D, params: &[f64]) {
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

pub fn curve_params((t0, t1): (f64, f64), n: usize, knots: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| t0 + (t1 - t0) * (i as f64 + 0.37) / n as f64)
        .filter(|t| knots.iter().all(|k| (t - k).abs() > 1e-3))
        .collect()
}

pub fn rel(a: DVec3, b: DVec3, scale: f64) -> f64 {
    (a - b).length() / scale
}

pub fn p3(p: Point3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

pub fn v3(v: Vector3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// UV of a 3D point on `face`'s surface.
pub fn uv_of(face: &Face, p: DVec3) -> DVec2 {
    let uv = crate::geom::project_point(&face.surface, p, None).expect("projects");
    let q = crate::geom::surface_point(&face.surface, uv.0, uv.1);
    assert!(q.distance(p) < 1e-9, "{p} is not on the surface ({q})");
    DVec2::new(uv.0, uv.1)
}

/// The face all of whose loop points satisfy `on`.
pub fn face_where(m: &Model, on: impl Fn(DVec3) -> bool) -> usize {
    (0..m.faces.len())
        .find(|&f| {
            m.faces[f].loops.iter().all(|l| {
                l.edges.iter().all(|oe| {
                    let e = &m.edges[oe.edge];
                    m.vertices[e.vertices[0]].point.is_finite()
                        && on(m.vertices[e.vertices[0]].point)
                        && on(m.vertices[e.vertices[1]].point)
                })
            })
        })
        .expect("face found")
}
