//! The nearest point of an edge ([`nearest_on_edge`]): the best of a few samples (ends
//! included), then safeguarded Newton on `f(t) = ½‖C(t) − p‖²` (`f′ = C′·(C − p)`,
//! `f″ = C″·(C − p) + ‖C′‖²`, Gauss–Newton where `f″ ≤ 0`, step halving until `f` decreases),
//! clamped to the edge's range (wrapped around for a closed edge). Lines are solved in closed
//! form.
//!
//! The descent budgets ([`MAX_DESCENT_ITER`], [`MAX_DESCENT_HALVINGS`]) are shared with the
//! descent on a face's surface.

use crate::geom::eval::eval_curve;
use crate::model::{Curve3D, Edge, Element, Model};
use glam::DVec3;

/// Newton iterations for the nearest point of an edge or a surface.
pub const MAX_DESCENT_ITER: usize = 50;

/// Step halvings per Newton iteration before giving up.
pub const MAX_DESCENT_HALVINGS: usize = 40;

/// Samples of a curved edge per quarter turn of a conic's angle parameter (so a full circle
/// gets 32 intervals, each 11.25°).
pub const SAMPLES_PER_QUARTER_TURN: usize = 8;

/// Samples per knot span of a B-spline edge per degree + 1.
pub const SAMPLES_PER_SPAN: usize = 2;

/// Fewest samples of a curved edge.
pub const MIN_EDGE_SAMPLES: usize = 8;

/// Most samples of a curved edge.
pub const MAX_EDGE_SAMPLES: usize = 256;

/// The nearest point of edge `edge` to `p`: `(t, point, distance)` with `t` in the edge's
/// range. `hint_t` (a previous answer) is tried as an extra Newton start.
pub fn nearest_on_edge(
    model: &Model,
    edge: usize,
    p: DVec3,
    hint_t: Option<f64>,
) -> (f64, DVec3, f64) {
    let e = &model.edges[edge];
    let (t, x, d2) = edge_nearest(e, p, hint_t, None, wraps_around(e));
    (t, x, d2.sqrt())
}

/// A lower bound on the distance from `p` to the whole of edge `e`'s curve, where one is
/// known in closed form: an ellipse (a circle) lies in its plane between the circles of its
/// two semi-axes, so it is at least as far as that annulus (exact for a circle). `None` for
/// other curves, and for an ellipse whose axes are not perpendicular.
pub(super) fn curve_distance_below(e: &Edge, p: DVec3) -> Option<f64> {
    let (c, u, v) = crate::geom::eval::ellipse_axes(&e.curve)?;
    let (a, b) = (u.length(), v.length());
    if u.dot(v).abs() > PERPENDICULAR_AXES * a * b {
        return None;
    }
    let n = u.cross(v).normalize_or_zero();
    if n == DVec3::ZERO {
        return None;
    }
    let w = p - c;
    let z = w.dot(n);
    let rho = (w - n * z).length();
    let radial = (a.min(b) - rho).max(rho - a.max(b)).max(0.0);
    let below = (z * z + radial * radial).sqrt();
    below.is_finite().then_some(below)
}

/// An ellipse's two axes are perpendicular when the cosine of their angle is below this.
const PERPENDICULAR_AXES: f64 = 1e-12;

/// `(lo, hi)` of the edge's range.
#[inline]
fn edge_span(e: &Edge) -> (f64, f64) {
    (e.range.0.min(e.range.1), e.range.0.max(e.range.1))
}

/// Number of samples (ends included) of an edge.
pub(super) fn edge_sample_count(e: &Edge) -> usize {
    let (lo, hi) = edge_span(e);
    let n = match &e.curve {
        Curve3D::Line(_) => 2,
        Curve3D::Conic(_) => {
            let quarter = std::f64::consts::FRAC_PI_2;
            ((hi - lo) / quarter * SAMPLES_PER_QUARTER_TURN as f64).ceil() as usize + 1
        }
        Curve3D::BSplineCurve(c) => {
            spans_in(c.knot_vec(), lo, hi) * SAMPLES_PER_SPAN * (c.degree() + 1) + 1
        }
        Curve3D::NurbsCurve(c) => {
            spans_in(c.knot_vec(), lo, hi) * SAMPLES_PER_SPAN * (c.non_rationalized().degree() + 1)
                + 1
        }
        Curve3D::Polyline(pl) => 2 * pl.0.len() + 1,
        Curve3D::PCurve(_) => 4 * SAMPLES_PER_QUARTER_TURN + 1,
    };
    if matches!(e.curve, Curve3D::Line(_)) {
        2
    } else {
        n.clamp(MIN_EDGE_SAMPLES, MAX_EDGE_SAMPLES)
    }
}

/// Number of non-empty knot spans meeting `[lo, hi]`.
fn spans_in(knots: &truck_geometry::prelude::KnotVec, lo: f64, hi: f64) -> usize {
    let mut n = 0;
    for w in knots.windows(2) {
        if w[1] > w[0] && w[1] > lo && w[0] < hi {
            n += 1;
        }
    }
    n.max(1)
}

/// Parameter of sample `k` of `n` (uniform in `t`, ends exact).
#[inline]
pub(super) fn edge_sample_t(e: &Edge, k: usize, n: usize) -> f64 {
    let (lo, hi) = edge_span(e);
    if k + 1 == n {
        hi
    } else {
        lo + (hi - lo) * k as f64 / (n - 1) as f64
    }
}

/// How near its ends must be, relative to the coordinates' size, for a closed edge to wrap
/// around ([`wraps_around`]).
const CLOSED_TOL_REL_COORD: f64 = 1e-9;

/// True when the edge is a closed curve traversed once (a full circle): its parameter wraps.
#[inline]
pub(super) fn wraps_around(e: &Edge) -> bool {
    e.is_closed() && {
        let (lo, hi) = edge_span(e);
        let a = eval_curve(&e.curve, lo).p;
        let b = eval_curve(&e.curve, hi).p;
        a.distance(b) <= CLOSED_TOL_REL_COORD * (1.0 + a.abs().max_element())
    }
}

/// Nearest point of an edge: `(t, point, distance²)`. `samples`, when given, are the edge's
/// cached samples `(t, point)`; otherwise the edge is sampled on the fly.
pub(super) fn edge_nearest(
    e: &Edge,
    p: DVec3,
    hint_t: Option<f64>,
    samples: Option<(&[f64], &[DVec3])>,
    wrap: bool,
) -> (f64, DVec3, f64) {
    let (lo, hi) = edge_span(e);
    if let Curve3D::Line(_) = e.curve {
        let d = eval_curve(&e.curve, lo);
        let len2 = d.d1.length_squared();
        let t = if len2 > 0.0 {
            (lo + (p - d.p).dot(d.d1) / len2).clamp(lo, hi)
        } else {
            lo
        };
        let x = d.p + d.d1 * (t - lo);
        return (t, x, x.distance_squared(p));
    }
    // Best sample (ends included).
    let mut best = (lo, DVec3::NAN, f64::INFINITY);
    match samples {
        Some((ts, ps)) => {
            for (t, x) in ts.iter().zip(ps) {
                let d2 = x.distance_squared(p);
                if d2 < best.2 {
                    best = (*t, *x, d2);
                }
            }
        }
        None => {
            let n = edge_sample_count(e);
            for k in 0..n {
                let t = edge_sample_t(e, k, n);
                let x = eval_curve(&e.curve, t).p;
                let d2 = x.distance_squared(p);
                if d2 < best.2 {
                    best = (t, x, d2);
                }
            }
        }
    }
    let mut out = curve_newton(e, p, best.0, wrap);
    if best.2 < out.2 {
        out = best;
    }
    if let Some(h) = hint_t {
        let r = curve_newton(e, p, h, wrap);
        if r.2 < out.2 {
            out = r;
        }
    }
    out
}

/// Safeguarded Newton on `½‖C(t) − p‖²` from `t0` (see the module docs). Never returns a
/// point farther than the start's.
fn curve_newton(e: &Edge, p: DVec3, t0: f64, wrap: bool) -> (f64, DVec3, f64) {
    let (lo, hi) = edge_span(e);
    let fix = |t: f64| {
        if wrap && hi > lo {
            lo + (t - lo).rem_euclid(hi - lo)
        } else {
            t.clamp(lo, hi)
        }
    };
    let mut t = fix(t0);
    let mut d = eval_curve(&e.curve, t);
    let mut f = d.p.distance_squared(p);
    if !f.is_finite() {
        return (t, d.p, f64::INFINITY);
    }
    for _ in 0..MAX_DESCENT_ITER {
        let r = d.p - p;
        let g = d.d1.dot(r);
        let mut h = d.d2.dot(r) + d.d1.length_squared();
        if h.is_nan() || h <= 0.0 {
            h = d.d1.length_squared();
        }
        if h.is_nan() || h <= 0.0 || g == 0.0 {
            break;
        }
        let mut step = -g / h;
        let mut moved = false;
        for _ in 0..MAX_DESCENT_HALVINGS {
            let tn = fix(t + step);
            if tn == t {
                break;
            }
            let dn = eval_curve(&e.curve, tn);
            let fnew = dn.p.distance_squared(p);
            if fnew <= f {
                let small = (tn - t).abs() <= 1e-15 * (1.0 + t.abs()) + 1e-14 * (hi - lo);
                t = tn;
                d = dn;
                f = fnew;
                moved = !small;
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    (t, d.p, f)
}

/// The element an edge point at parameter `t` lies on, with its curve parameter when that
/// is the edge: the edge, or a vertex at an end of an open edge.
pub(super) fn edge_feature(e: &Edge, edge: usize, t: f64, wrap: bool) -> (Element, Option<f64>) {
    if !wrap {
        if t == e.range.0 {
            return (Element::Vertex(e.vertices[0]), None);
        }
        if t == e.range.1 {
            return (Element::Vertex(e.vertices[1]), None);
        }
    }
    (Element::Edge(edge), Some(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::distance::Lcg;
    use crate::testing::sample;

    /// The closed-form bound on the distance to an edge's whole curve is never more than the
    /// distance to any point of it (dense samples round the whole ellipse or circle, not only
    /// the edge's range), and is the distance itself for a circle at points off its plane,
    /// inside it and outside it; other curves have none.
    #[test]
    fn a_curve_bound_is_below_every_point_of_the_curve() {
        let mut rng = Lcg(11);
        let mut conics = 0;
        for file in [
            "plate_with_holes.step",
            "cylinder.step",
            "elliptic_cylinder.step",
            "boss_on_plate.step",
            "box.step",
            "cylinder_nurbs.step",
        ] {
            let model = sample(file);
            let (lo, hi) = model.bounding_box();
            let margin = 0.3 * (hi - lo);
            for e in &model.edges {
                let Some(_) = curve_distance_below(e, DVec3::ZERO) else {
                    assert!(!matches!(e.curve, Curve3D::Conic(_)), "{file}: {e:?}");
                    continue;
                };
                conics += 1;
                let m = 4000;
                let pts: Vec<DVec3> = (0..m)
                    .map(|k| eval_curve(&e.curve, std::f64::consts::TAU * k as f64 / m as f64).p)
                    .collect();
                let radii: Vec<f64> = pts.windows(2).map(|w| w[0].distance(w[1])).collect();
                let step = radii.iter().cloned().fold(0.0, f64::max);
                let circle = {
                    let c = pts.iter().copied().sum::<DVec3>() / m as f64;
                    let r: Vec<f64> = pts.iter().map(|q| q.distance(c)).collect();
                    let (a, b) = r
                        .iter()
                        .fold((f64::INFINITY, 0.0_f64), |(a, b), &x| (a.min(x), b.max(x)));
                    b - a < 1e-9 * b
                };
                for _ in 0..200 {
                    let p = rng.in_box(lo - margin, hi + margin);
                    let below = curve_distance_below(e, p).unwrap();
                    let sampled = pts
                        .iter()
                        .map(|q| q.distance(p))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        below <= sampled * (1.0 + 1e-12),
                        "{file} {p}: {below} > {sampled}"
                    );
                    if circle {
                        assert!(sampled - below <= step, "{file} {p}: {below} < {sampled}");
                    }
                }
            }
        }
        assert!(conics >= 8, "{conics} conic edges");
    }

    #[test]
    fn edge_distance_matches_dense_sampling() {
        for file in [
            "filleted_box.step",
            "cylinder_nurbs.step",
            "box_bspline_top.step",
            "plate_with_holes.step",
        ] {
            let model = sample(file);
            let (lo, hi) = model.bounding_box();
            let scale = (hi - lo).length();
            let mut rng = Lcg(5);
            for (ei, e) in model.edges.iter().enumerate() {
                let m = 20000;
                let pts: Vec<DVec3> = (0..=m)
                    .map(|k| {
                        eval_curve(
                            &e.curve,
                            e.range.0 + (e.range.1 - e.range.0) * k as f64 / m as f64,
                        )
                        .p
                    })
                    .collect();
                for _ in 0..10 {
                    let p = rng.in_box(lo - (hi - lo) * 0.2, hi + (hi - lo) * 0.2);
                    let (t, x, d) = nearest_on_edge(&model, ei, p, None);
                    let b = pts
                        .iter()
                        .map(|q| q.distance(p))
                        .fold(f64::INFINITY, f64::min);
                    assert!(eval_curve(&e.curve, t).p.distance(x) < 1e-12 * scale);
                    assert!((x.distance(p) - d).abs() < 1e-12 * scale);
                    assert!(d <= b + 1e-9 * scale, "{file} edge {ei}: {d} > {b}");
                }
            }
        }
    }
}
