//! Polylines of the picture: part edges sampled from their exact curves, and every
//! polyline thinned per view.
//!
//! Lines are sampled by their ends, polylines by their vertices, other curves by recursive
//! midpoint subdivision until the curve is within a tolerance of its chords. Thinning is
//! Douglas–Peucker (D. Douglas, T. Peucker, "Algorithms for the reduction of the number of
//! points required to represent a digitized line or its caricature", *The Canadian
//! Cartographer* 10(2), 1973) to a tolerance in px.

use crate::geom::eval_curve;
use glam::{DVec2, DVec3};
use truck_stepio::r#in::alias::Curve3D;

/// Largest depth of the midpoint subdivision of a curved edge (2^12 pieces per interval at
/// most).
const MAX_SUBDIVISION_DEPTH: u32 = 12;

/// Samples an edge's exact curve over `range` so that the polyline is within `tol` (mm) of
/// the curve: lines by their ends, polylines by their vertices, others by midpoint
/// subdivision from 16 equal intervals (32 for a closed edge).
pub(super) fn sample_curve(
    curve: &Curve3D,
    range: (f64, f64),
    closed: bool,
    tol: f64,
) -> Vec<DVec3> {
    let at = |t: f64| eval_curve(curve, t).p;
    let (t0, t1) = range;
    match curve {
        Curve3D::Line(_) => vec![at(t0), at(t1)],
        Curve3D::Polyline(_) => {
            let (a, b) = (t0.min(t1), t0.max(t1));
            let mut ts = vec![a];
            let mut k = a.floor() + 1.0;
            while k < b {
                ts.push(k);
                k += 1.0;
            }
            ts.push(b);
            if t0 > t1 {
                ts.reverse();
            }
            ts.into_iter().map(at).collect()
        }
        _ => {
            let n = if closed { 32 } else { 16 };
            let mut out = vec![at(t0)];
            for k in 0..n {
                let a = t0 + (t1 - t0) * k as f64 / n as f64;
                let b = t0 + (t1 - t0) * (k + 1) as f64 / n as f64;
                subdivide(&at, (a, at(a)), (b, at(b)), tol, 0, &mut out);
            }
            out
        }
    }
}

fn subdivide(
    at: &impl Fn(f64) -> DVec3,
    a: (f64, DVec3),
    b: (f64, DVec3),
    tol: f64,
    depth: u32,
    out: &mut Vec<DVec3>,
) {
    let tm = 0.5 * (a.0 + b.0);
    let m = at(tm);
    if depth < MAX_SUBDIVISION_DEPTH && distance_to_segment(m, a.1, b.1) > tol {
        subdivide(at, a, (tm, m), tol, depth + 1, out);
        subdivide(at, (tm, m), b, tol, depth + 1, out);
    } else {
        out.push(b.1);
    }
}

fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * s).distance(p)
}

fn distance_to_segment_2d(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * s).distance(p)
}

/// Douglas–Peucker thinning: the points of `pts` farther than `tol` from the chords of the
/// kept points, with both ends always kept.
pub(super) fn thin(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    if pts.len() <= 2 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    keep[0] = true;
    keep[pts.len() - 1] = true;
    let mut stack = vec![(0, pts.len() - 1)];
    while let Some((i, j)) = stack.pop() {
        let mut worst = (0.0, 0);
        for k in i + 1..j {
            let d = distance_to_segment_2d(pts[k], pts[i], pts[j]);
            if d > worst.0 {
                worst = (d, k);
            }
        }
        if worst.0 > tol {
            keep[worst.1] = true;
            stack.push((i, worst.1));
            stack.push((worst.1, j));
        }
    }
    pts.iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(*p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles_are_sampled_to_the_tolerance_and_lines_by_their_ends() {
        let m = crate::testing::sample("plate_with_holes.step");
        let tol = 0.01;
        let (mut circles, mut lines) = (0, 0);
        for e in &m.edges {
            let pts = sample_curve(&e.curve, e.range, e.is_closed(), tol);
            match e.curve {
                Curve3D::Line(_) => {
                    assert_eq!(pts.len(), 2);
                    lines += 1;
                }
                _ => {
                    circles += 1;
                    assert!(pts.len() >= 17, "{}", pts.len());
                    // Between consecutive samples the curve stays within tol of the chord.
                    let n = pts.len() - 1;
                    let (t0, t1) = e.range;
                    for k in 0..4 * n {
                        let t = t0 + (t1 - t0) * (k as f64 + 0.5) / (4 * n) as f64;
                        let q = eval_curve(&e.curve, t).p;
                        let d = pts
                            .windows(2)
                            .map(|w| distance_to_segment(q, w[0], w[1]))
                            .fold(f64::INFINITY, f64::min);
                        assert!(d <= tol * 1.01, "{d}");
                    }
                }
            }
        }
        assert!(circles > 0 && lines > 0, "{circles} {lines}");
    }

    #[test]
    fn thinning_keeps_the_ends_and_every_point_off_the_chord() {
        let line: Vec<DVec2> = (0..100)
            .map(|k| DVec2::new(k as f64, 2.0 * k as f64))
            .collect();
        assert_eq!(thin(&line, 0.25), vec![line[0], line[99]]);
        let arc: Vec<DVec2> = (0..=200)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 200.0;
                DVec2::new(100.0 * a.cos(), 100.0 * a.sin())
            })
            .collect();
        let kept = thin(&arc, 0.25);
        assert!(kept.len() > 10 && kept.len() < 60, "{}", kept.len());
        assert_eq!((kept[0], *kept.last().unwrap()), (arc[0], arc[200]));
        for p in &arc {
            let d = kept
                .windows(2)
                .map(|w| distance_to_segment_2d(*p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.25 + 1e-12, "{d}");
        }
    }
}
