//! The B-spline basis of the fit: the knot span of a parameter and the basis functions that
//! are non-zero there with their first and second derivatives (The NURBS Book, A2.1 and A2.3),
//! for degrees up to 3.

// NOTE(restructure): geom's B-spline evaluation (`find_span`/`basis_ders` in `geom::eval`)
// computes the same basis with other loops and buffers; merging the two could change fitted
// curves in the last digit, so the fit keeps its own.

// Index loops over control points, basis functions and coordinates read like the textbook
// algorithms they transcribe (The NURBS Book A2.1–A2.3).
#![allow(clippy::needless_range_loop)]

/// The knot span `k` with `knots[k] ≤ t < knots[k + 1]`, `p ≤ k < m` (`m` control points;
/// `t` at or beyond the end falls in the last span). The NURBS Book, A2.1.
pub(super) fn find_span(knots: &[f64], p: usize, m: usize, t: f64) -> usize {
    if t >= knots[m] {
        return m - 1;
    }
    if t <= knots[p] {
        return p;
    }
    let (mut lo, mut hi) = (p, m);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if t < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// The `p + 1` basis functions that are non-zero in `span`, and their first and second
/// derivatives, at `t` (The NURBS Book, A2.3; `p ≤ 3`).
pub(super) fn basis_ders(knots: &[f64], p: usize, span: usize, t: f64) -> [[f64; 4]; 3] {
    let mut ndu = [[0.0; 4]; 4];
    let mut left = [0.0; 4];
    let mut right = [0.0; 4];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0; 4]; 3];
    for (j, row) in ndu.iter().enumerate().take(p + 1) {
        ders[0][j] = row[p];
    }
    let nd = p.min(2);
    let p_i = p as isize;
    for r in 0..=p_i {
        let mut a = [[0.0; 4]; 2];
        let (mut s1, mut s2) = (0, 1);
        a[0][0] = 1.0;
        for k in 1..=nd as isize {
            let mut d = 0.0;
            let rk = r - k;
            let pk = p_i - k;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[(pk + 1) as usize][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk as usize];
            }
            let j1 = if rk >= -1 { 1 } else { -rk };
            let j2 = if r - 1 <= pk { k - 1 } else { p_i - r };
            for j in j1..=j2 {
                let (ju, rkj) = (j as usize, (rk + j) as usize);
                a[s2][ju] = (a[s1][ju] - a[s1][ju - 1]) / ndu[(pk + 1) as usize][rkj];
                d += a[s2][ju] * ndu[rkj][pk as usize];
            }
            if r <= pk {
                let ku = k as usize;
                a[s2][ku] = -a[s1][ku - 1] / ndu[(pk + 1) as usize][r as usize];
                d += a[s2][ku] * ndu[r as usize][pk as usize];
            }
            ders[k as usize][r as usize] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=nd {
        for d in ders[k].iter_mut().take(p + 1) {
            *d *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}
