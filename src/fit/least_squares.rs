//! The least-squares solve of one fitting round: control points (with radii) minimising the
//! squared distances to the points at their parameters, both ends fixed.
//!
//! The normal equations `NᵀN P = Nᵀ Q` are banded (half-bandwidth `p`), so they are solved by
//! a banded Cholesky factorisation ([`Band`]) in `O(m p²)` instead of a dense `O(m³)` (seams
//! have up to 20 000 points). A tiny ridge term pulls each control point towards the traced
//! point at its Greville abscissa, which keeps the system positive definite when a knot span
//! holds no point; its bias is ~[`RIDGE_REL_MAX_DIAGONAL_ENTRY`] × the part size.

// Index loops over control points, basis functions and coordinates read like the textbook
// algorithms they transcribe (The NURBS Book A2.1–A2.3).
#![allow(clippy::needless_range_loop)]

use super::basis::{basis_ders, find_span};

/// Weight of the regularising ridge, relative to the largest diagonal entry of `NᵀN`.
pub(super) const RIDGE_REL_MAX_DIAGONAL_ENTRY: f64 = 1e-12;

/// Control points and radii minimising `Σ ‖C(tᵢ) − Qᵢ‖²` (all four coordinates) with the
/// end control points at the end points. `params` (sorted) place the ridge's anchors.
pub(super) fn solve_least_squares(
    q: &[[f64; 4]],
    t: &[f64],
    params: &[f64],
    knots: &[f64],
    p: usize,
    ridge: f64,
) -> (Vec<[f64; 3]>, Vec<f64>) {
    let n = q.len();
    let m = knots.len() - p - 1;
    let (q0, q1) = (q[0], q[n - 1]);
    let mut ctrl = vec![q0; m];
    ctrl[m - 1] = q1;
    if m > 2 {
        let u = m - 2;
        let mut a = Band::new(u, p);
        let mut b = vec![[0.0; 4]; u];
        for (ti, qi) in t.iter().zip(q) {
            let span = find_span(knots, p, m, *ti);
            let nb = basis_ders(knots, p, span, *ti)[0];
            let mut rhs = *qi;
            for (j, nj) in nb.iter().enumerate().take(p + 1) {
                let k = span - p + j;
                if k == 0 || k == m - 1 {
                    let end = if k == 0 { q0 } else { q1 };
                    for c in 0..4 {
                        rhs[c] -= nj * end[c];
                    }
                }
            }
            for j in 0..=p {
                let kj = span - p + j;
                if kj == 0 || kj == m - 1 {
                    continue;
                }
                for c in 0..4 {
                    b[kj - 1][c] += nb[j] * rhs[c];
                }
                for l in 0..=j {
                    let kl = span - p + l;
                    if kl == 0 || kl == m - 1 {
                        continue;
                    }
                    *a.at(kj - 1, kl - 1) += nb[j] * nb[l];
                }
            }
        }
        let max_diag = (0..u).map(|i| *a.at(i, i)).fold(0.0, f64::max).max(1.0);
        let mut ridge = ridge * max_diag;
        loop {
            let mut ar = a.clone();
            let mut br = b.clone();
            for (i, bi) in br.iter_mut().enumerate() {
                let k = i + 1;
                let greville = knots[k + 1..=k + p].iter().sum::<f64>() / p as f64;
                let anchor = interpolate(params, q, greville);
                *ar.at(i, i) += ridge;
                for c in 0..4 {
                    bi[c] += ridge * anchor[c];
                }
            }
            if ar.cholesky() {
                ar.solve(&mut br);
                ctrl[1..=u].copy_from_slice(&br);
                break;
            }
            ridge = (ridge * 1e3).max(RIDGE_REL_MAX_DIAGONAL_ENTRY * max_diag);
        }
    }
    (
        ctrl.iter().map(|c| [c[0], c[1], c[2]]).collect(),
        ctrl.iter().map(|c| c[3]).collect(),
    )
}

/// The polyline through `q` at parameters `params` (sorted), evaluated at `t`.
fn interpolate(params: &[f64], q: &[[f64; 4]], t: f64) -> [f64; 4] {
    let i = params
        .partition_point(|&x| x <= t)
        .clamp(1, params.len() - 1);
    let (a, b) = (params[i - 1], params[i]);
    let s = if b > a {
        ((t - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    std::array::from_fn(|c| q[i - 1][c] + s * (q[i][c] - q[i - 1][c]))
}

/// A symmetric banded matrix (lower band stored), factorised in place by Cholesky.
#[derive(Clone)]
struct Band {
    n: usize,
    w: usize,
    /// Row `i` holds entries `(i, i − w) … (i, i)`.
    a: Vec<f64>,
}

impl Band {
    fn new(n: usize, w: usize) -> Band {
        Band {
            n,
            w,
            a: vec![0.0; n * (w + 1)],
        }
    }

    /// Entry `(i, j)`, `j ≤ i ≤ j + w`.
    fn at(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.a[i * (self.w + 1) + (self.w + j - i)]
    }

    fn get(&self, i: usize, j: usize) -> f64 {
        self.a[i * (self.w + 1) + (self.w + j - i)]
    }

    /// `A = L Lᵀ` in place; false when `A` is not (numerically) positive definite.
    fn cholesky(&mut self) -> bool {
        for i in 0..self.n {
            for j in i.saturating_sub(self.w)..=i {
                let mut s = self.get(i, j);
                for k in i.saturating_sub(self.w)..j {
                    s -= self.get(i, k) * self.get(j, k);
                }
                if i == j {
                    if !(s > 0.0 && s.is_finite()) {
                        return false;
                    }
                    *self.at(i, i) = s.sqrt();
                } else {
                    *self.at(i, j) = s / self.get(j, j);
                }
            }
        }
        true
    }

    /// Solves `L Lᵀ x = b` in place, after [`Band::cholesky`].
    fn solve(&self, b: &mut [[f64; 4]]) {
        for i in 0..self.n {
            for k in i.saturating_sub(self.w)..i {
                let l = self.get(i, k);
                for c in 0..4 {
                    b[i][c] -= l * b[k][c];
                }
            }
            let d = self.get(i, i);
            for c in 0..4 {
                b[i][c] /= d;
            }
        }
        for i in (0..self.n).rev() {
            for k in i + 1..(i + self.w + 1).min(self.n) {
                let l = self.get(k, i);
                for c in 0..4 {
                    b[i][c] -= l * b[k][c];
                }
            }
            let d = self.get(i, i);
            for c in 0..4 {
                b[i][c] /= d;
            }
        }
    }
}
