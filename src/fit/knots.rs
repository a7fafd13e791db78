//! The parameters and knots of the fit: chord-length parameters, the averaged knots of
//! interpolation, and the two ways of adding knots between rounds (redistribution by the
//! error, insertion in the spans over the tolerance), with the spans left without points
//! dropped.

use super::basis::find_span;
use super::curve::dist3;

/// Knot redistribution asks for this many times the spans the error estimate says are
/// needed (the estimate is asymptotic; a little margin saves a round).
const SPANS_REL_ESTIMATE: f64 = 1.1;
/// Error floor (relative to the tolerance) of a span in the redistribution, so spans far
/// within the tolerance still keep some knots (1e-4 ⇒ a cubic span up to 10× as long).
const MIN_SPAN_ERROR_REL_TOL: f64 = 1e-4;
/// Shortest knot span, relative to the parameter range: readers treat closer knots as one
/// (truck merges knots within 1e-6, OCCT within its parametric resolution).
const MIN_KNOT_GAP_REL_RANGE: f64 = 1e-6;
/// A knot placed by insertion or redistribution closer than this (relative to the parameter
/// range) to its neighbour or to the end is not placed.
const MIN_NEW_KNOT_GAP_REL_RANGE: f64 = 1e-12;
/// Smallest step between chord-length parameters, relative to the polyline length.
const MIN_PARAM_STEP_REL_LENGTH: f64 = 1e-9;

/// Cumulative chord length of the centres (index when all centres coincide).
pub(super) fn chord_params(q: &[[f64; 4]]) -> Vec<f64> {
    let mut t = vec![0.0];
    for w in q.windows(2) {
        let d = dist3(w[1], [w[0][0], w[0][1], w[0][2]]);
        t.push(t[t.len() - 1] + d);
    }
    let total = t[t.len() - 1];
    // Repeated centres (points differing only in r) would share a parameter; spread them a
    // little so interpolation stays well posed.
    let min_step = MIN_PARAM_STEP_REL_LENGTH * total.max(f64::MIN_POSITIVE);
    if total == 0.0 {
        return (0..q.len()).map(|i| i as f64).collect();
    }
    for i in 1..t.len() {
        if t[i] - t[i - 1] < min_step {
            t[i] = t[i - 1] + min_step;
        }
    }
    t
}

/// The knot vector of global interpolation with averaged knots (The NURBS Book, eq. 9.8).
pub(super) fn averaged_knots(params: &[f64], p: usize) -> Vec<f64> {
    let n = params.len();
    let mut knots = vec![params[0]; p + 1];
    for j in 1..n - p {
        knots.push(params[j..j + p].iter().sum::<f64>() / p as f64);
    }
    knots.extend(vec![params[n - 1]; p + 1]);
    knots
}

/// Drops interior knots so that every knot span holds at least one parameter (`t` sorted)
/// and is at least [`MIN_KNOT_GAP_REL_RANGE`] of the range long:
/// a span without points leaves the curve free to swing between them (the
/// Schoenberg–Whitney condition of least squares, The NURBS Book §9.4.1).
pub(super) fn keep_points_in_every_span(knots: Vec<f64>, p: usize, t: &[f64]) -> Vec<f64> {
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let interior = &knots[p + 1..knots.len() - p - 1];
    let min_gap = MIN_KNOT_GAP_REL_RANGE * (hi - lo);
    let inside = |a: f64, b: f64| {
        let i = t.partition_point(|&x| x <= a);
        i < t.len() && t[i] < b
    };
    let mut kept: Vec<f64> = vec![];
    for &k in interior {
        let prev = kept.last().copied().unwrap_or(lo);
        if inside(prev, k) && k - prev > min_gap && hi - k > min_gap {
            kept.push(k);
        }
    }
    while let Some(&last) = kept.last() {
        if inside(last, hi) {
            break;
        }
        kept.pop();
    }
    [vec![lo; p + 1], kept, vec![hi; p + 1]].concat()
}

/// The knot vector with one knot more in each span whose worst error exceeds the tolerance,
/// at the median parameter of the points in it: the spline space only grows, so the
/// least-squares residual cannot (The NURBS Book §9.4.4).
pub(super) fn insert_knots(
    knots: &[f64],
    p: usize,
    t: &[f64],
    errors: &[(f64, f64)],
    tol: f64,
) -> Vec<f64> {
    let m = knots.len() - p - 1;
    let mut span_err = vec![0.0f64; m];
    let mut span_params: Vec<Vec<f64>> = vec![vec![]; m];
    for (ti, e) in t.iter().zip(errors) {
        let s = find_span(knots, p, m, *ti);
        span_err[s] = span_err[s].max(e.0.max(e.1) / tol);
        span_params[s].push(*ti);
    }
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let mut out = knots.to_vec();
    for s in p..m {
        if span_err[s] <= 1.0 {
            continue;
        }
        let (a, b) = (knots[s], knots[s + 1]);
        let ps = &mut span_params[s];
        ps.retain(|&x| x > a && x < b);
        ps.sort_by(f64::total_cmp);
        let k = if ps.len() >= 2 {
            0.5 * (ps[ps.len() / 2 - 1] + ps[ps.len() / 2])
        } else {
            0.5 * (a + b)
        };
        if k - a > MIN_NEW_KNOT_GAP_REL_RANGE * (hi - lo)
            && b - k > MIN_NEW_KNOT_GAP_REL_RANGE * (hi - lo)
        {
            out.push(k);
        }
    }
    out.sort_by(f64::total_cmp);
    out
}

/// A new knot vector with more spans, placed to equidistribute the error: a span of length
/// `h` with worst error `e` needs about `(e / tol)^(1/(p+1))` spans of its own (the error of
/// a degree-`p` fit falls as `h^(p+1)`), so interior knots go at equal steps of the
/// cumulative `Σ (e / tol)^(1/(p+1))` (de Boor's equidistribution, *A Practical Guide to
/// Splines*, ch. XII). At least one span more than before.
pub(super) fn redistribute_knots(
    knots: &[f64],
    p: usize,
    t: &[f64],
    errors: &[(f64, f64)],
    tol: f64,
) -> Vec<f64> {
    let m = knots.len() - p - 1;
    let mut span_err = vec![0.0f64; m];
    for (ti, e) in t.iter().zip(errors) {
        let s = find_span(knots, p, m, *ti);
        span_err[s] = span_err[s].max(e.0.max(e.1) / tol);
    }
    let exponent = 1.0 / (p + 1) as f64;
    // Spans: knots[s]..knots[s + 1] for s in p..m, each with its share of the error mass.
    let mass: Vec<f64> = (p..m)
        .map(|s| span_err[s].max(MIN_SPAN_ERROR_REL_TOL).powf(exponent))
        .collect();
    let total: f64 = mass.iter().sum();
    let spans = (m - p + 1).max((SPANS_REL_ESTIMATE * total).ceil() as usize);
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let mut out = vec![lo; p + 1];
    let mut acc = 0.0;
    let mut s = 0;
    for k in 1..spans {
        let target = total * k as f64 / spans as f64;
        while s + 1 < mass.len() && acc + mass[s] < target {
            acc += mass[s];
            s += 1;
        }
        let (a, b) = (knots[p + s], knots[p + s + 1]);
        let f = ((target - acc) / mass[s]).clamp(0.0, 1.0);
        let u = a + f * (b - a);
        if u - out[out.len() - 1] > MIN_NEW_KNOT_GAP_REL_RANGE * (hi - lo)
            && hi - u > MIN_NEW_KNOT_GAP_REL_RANGE * (hi - lo)
        {
            out.push(u);
        }
    }
    out.extend(vec![hi; p + 1]);
    out
}
