//! The fitted curve of one seam ([`SeamFit`]): a clamped B-spline of the centres with the
//! radius as a fourth coordinate on the same knots; its evaluation with derivatives, and the
//! search for the parameter nearest a point (Newton's method on `(C(t) − Q)·C′(t) = 0`).

// Index loops over control points, basis functions and coordinates read like the textbook
// algorithms they transcribe (The NURBS Book A2.1–A2.3).
#![allow(clippy::needless_range_loop)]

use super::basis::{basis_ders, find_span};

/// Newton steps of each point projection at most (started at the point's own parameter, which
/// is already close: quadratic convergence makes 4 more than enough).
pub const MAX_NEWTON_STEPS: usize = 4;
/// The projection stops when a Newton step moves the parameter by less than this, relative
/// to the parameter range.
const NEWTON_STOP_REL_RANGE: f64 = 1e-15;

/// A clamped B-spline fit of one seam: centre curve `C(t)` and radius `r(t)` on the same
/// knots, `t ∈ [knots[0], knots[last]]` (millimetres of chord length).
#[derive(Clone, Debug, PartialEq)]
pub struct SeamFit {
    pub degree: usize,
    /// The full knot vector, each knot repeated by its multiplicity (`p + 1` at both ends).
    pub knots: Vec<f64>,
    /// Control points of the centre curve (mm).
    pub control_points: Vec<[f64; 3]>,
    /// Control values of the radius (mm), one per control point.
    pub radii: Vec<f64>,
    /// Largest distance from a traced point to the curve (mm).
    pub max_error: f64,
    /// Largest `|r(t) − rᵢ|` at the parameter nearest each traced point (mm).
    pub max_radius_error: f64,
}

impl SeamFit {
    /// The parameter range `[t0, t1]`.
    pub fn range(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// Distinct knots and their multiplicities (what STEP's `B_SPLINE_CURVE_WITH_KNOTS`
    /// lists).
    pub fn knots_with_multiplicities(&self) -> (Vec<f64>, Vec<usize>) {
        let mut knots: Vec<f64> = vec![];
        let mut mults: Vec<usize> = vec![];
        for &k in &self.knots {
            if knots.last() == Some(&k) {
                *mults.last_mut().unwrap() += 1;
            } else {
                knots.push(k);
                mults.push(1);
            }
        }
        (knots, mults)
    }

    /// `[x, y, z, r]` at `t`.
    pub fn subs(&self, t: f64) -> [f64; 4] {
        self.eval(t).0
    }

    /// Position (with radius), first and second derivative of the centre curve at `t`.
    pub fn eval(&self, t: f64) -> ([f64; 4], [f64; 3], [f64; 3]) {
        let p = self.degree;
        let span = find_span(&self.knots, p, self.control_points.len(), t);
        let ders = basis_ders(&self.knots, p, span, t);
        let mut c = [0.0; 4];
        let mut d1 = [0.0; 3];
        let mut d2 = [0.0; 3];
        for j in 0..=p {
            let k = span - p + j;
            let cp = self.control_points[k];
            for a in 0..3 {
                c[a] += ders[0][j] * cp[a];
                d1[a] += ders[1][j] * cp[a];
                d2[a] += ders[2][j] * cp[a];
            }
            c[3] += ders[0][j] * self.radii[k];
        }
        (c, d1, d2)
    }

    /// The parameter of the curve point nearest `q`, by Newton's method from `hint` (a local
    /// search: `hint` must be near the answer), with the distance there.
    pub fn search_nearest_parameter(&self, q: [f64; 3], hint: f64) -> (f64, f64) {
        let (lo, hi) = self.range();
        let mut t = hint.clamp(lo, hi);
        let mut best = (t, dist3(self.subs(t), q));
        for _ in 0..MAX_NEWTON_STEPS {
            let (c, d1, d2) = self.eval(t);
            let diff = [c[0] - q[0], c[1] - q[1], c[2] - q[2]];
            let f = dot(d1, diff);
            let fp = dot(d2, diff) + dot(d1, d1);
            if !(fp > 0.0 && f.is_finite()) {
                break;
            }
            let next = (t - f / fp).clamp(lo, hi);
            let d = dist3(self.subs(next), q);
            if d < best.1 {
                best = (next, d);
            }
            if (next - t).abs() <= NEWTON_STOP_REL_RANGE * (hi - lo) {
                break;
            }
            t = next;
        }
        best
    }
}

/// The dot product of two vectors.
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The distance from the centre of `c` (`[x, y, z, r]`) to `q`.
pub(super) fn dist3(c: [f64; 4], q: [f64; 3]) -> f64 {
    ((c[0] - q[0]).powi(2) + (c[1] - q[1]).powi(2) + (c[2] - q[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::super::test_support::truck_curves;
    use super::*;
    use truck_geometry::prelude::*;

    #[test]
    fn basis_and_derivatives_agree_with_truck() {
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.7, 1.5, 1.5, 3.0, 3.0, 3.0, 3.0];
        let fit = SeamFit {
            degree: 3,
            knots: knots.clone(),
            control_points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 2.0, 0.5],
                [2.0, -1.0, 1.0],
                [3.0, 0.5, -2.0],
                [4.0, 4.0, 0.0],
                [5.0, 1.0, 1.0],
                [6.0, 0.0, 3.0],
            ],
            radii: vec![0.0, 1.0, 2.0, 0.5, 0.3, 0.2, 0.0],
            max_error: 0.0,
            max_radius_error: 0.0,
        };
        let (c, r) = truck_curves(&fit);
        for i in 0..=60 {
            let t = 3.0 * i as f64 / 60.0;
            let (p, d1, d2) = fit.eval(t);
            let (tp, td1, td2) = (c.subs(t), c.der(t), c.der2(t));
            for a in 0..3 {
                assert!((p[a] - tp[a]).abs() < 1e-12, "C({t})");
                assert!((d1[a] - td1[a]).abs() < 1e-10, "C'({t})");
                assert!((d2[a] - td2[a]).abs() < 1e-9, "C''({t})");
            }
            assert!((p[3] - r.subs(t).x).abs() < 1e-12, "r({t})");
        }
    }
}
