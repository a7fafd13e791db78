//! B-spline and NURBS curves and surfaces with their first and second derivatives, by our own
//! code (Piegl & Tiller, *The NURBS Book*, 2nd ed., Springer 1997), because truck 0.5's
//! `BSplineSurface::uuder`/`vvder` are short by the factor `p − 1` for degree `p ≥ 3` (see the
//! module docs of [`super`]):
//! - span search (A2.1), clamped so that parameters outside the knot range extrapolate the
//!   first or last polynomial piece instead of failing;
//! - the non-zero basis functions and their first two derivatives (A2.2 + A2.3, eq. 2.9/2.10:
//!   `N′ᵢ,ₚ = p·(Nᵢ,ₚ₋₁/(uᵢ₊ₚ − uᵢ) − Nᵢ₊₁,ₚ₋₁/(uᵢ₊ₚ₊₁ − uᵢ₊₁))`, applied twice), keeping
//!   only the degree `p − 1` and `p − 2` rows of the triangular table instead of all of `ndu`;
//! - surface derivatives up to order 2 (A3.6): contract the control net with the `v` basis
//!   first (three sums per row), then with the `u` basis (six sums);
//! - NURBS as homogeneous B-splines followed by the quotient rule ([`super::rational`]);
//! - the point alone (no derivatives), summed in the same order as the derivatives' first
//!   row, so that it is bit for bit the evaluation's point.
//!
//! Degrees up to [`STACK_ORDER`]` − 1` use stack buffers; higher degrees allocate. A B-spline
//! with fewer than `p + 1` control points (which truck's checked constructors accept)
//! evaluates to NaN.

use super::derivs::{CurveDerivs, SurfaceDerivs, NAN_CURVE, NAN_SURFACE};
use super::rational::{rational_curve, rational_surface};
use glam::{DVec3, DVec4};
use truck_geometry::prelude::{
    BSplineCurve, BSplineSurface, NurbsCurve, NurbsSurface, Point3, Vector4,
};

/// Largest B-spline order (degree + 1) whose basis functions are computed in stack buffers;
/// higher degrees allocate one small `Vec` per evaluation.
pub const STACK_ORDER: usize = 11;

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
pub(super) fn bspline_curve_ders<P, const D: usize>(
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
pub(super) fn bspline_surface_point<P, const D: usize>(
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

/// The basis functions at each of `ts`: `(degree, span, values)`, `None` when the knot vector
/// has no valid span.
fn bases(knots: &[f64], n_cp: usize, ts: &[f64]) -> Option<Vec<(usize, usize, Vec<f64>)>> {
    ts.iter()
        .map(|&t| with_values(knots, n_cp, t, |p, span, n| (p, span, n.to_vec())))
        .collect()
}

/// `f(i, j, S(us[i], vs[j]))` over a grid of a (homogeneous) tensor-product B-spline surface,
/// with the basis functions computed once per row and column: [`tensor_point`] at each node,
/// `None` everywhere when a knot vector has no valid span.
pub(super) fn tensor_grid<P, const D: usize>(
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
mod tests {
    use super::*;
    use crate::geom::eval::eval_surface;
    use crate::model::{Curve3D, Surface};
    use crate::testing::geometry::{
        assert_curve_fd, assert_surface_fd, bspline_curve, bspline_surface, curve_params, grid,
        knots, net, nurbs_curve, nurbs_surface, p3, rel, surface_fd_errors, u_knots, v3, v_knots,
        DEGREE_PAIRS, FD_H, FD_TOL,
    };
    use truck_geometry::prelude::{ParametricCurve, ParametricSurface};

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

    /// truck's `uuder`/`vvder` are short by the factor `p − 1`. Measured on a cubic and a
    /// quartic B-spline and a cubic NURBS against finite differences of truck's own (correct)
    /// `uder`/`vder`; ours passes the same check.
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
}
