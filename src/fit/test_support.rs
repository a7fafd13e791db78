//! Helpers of the fit's unit tests: the fitted curve evaluated by truck, an evaluator that
//! shares no code with ours, and the errors of a fit measured with it.

use super::SeamFit;
use truck_geometry::prelude::*;

/// The fit as a truck curve (centres) and a truck curve of `[r, 0, 0]`: an evaluator that
/// shares no code with ours.
pub(super) fn truck_curves(fit: &SeamFit) -> (BSplineCurve<Point3>, BSplineCurve<Point3>) {
    let knots = KnotVec::from(fit.knots.clone());
    let centres = fit
        .control_points
        .iter()
        .map(|c| Point3::new(c[0], c[1], c[2]))
        .collect();
    let radii = fit
        .radii
        .iter()
        .map(|r| Point3::new(*r, 0.0, 0.0))
        .collect();
    (
        BSplineCurve::new(knots.clone(), centres),
        BSplineCurve::new(knots, radii),
    )
}

/// Worst distance from `points` to the fitted curve, measured with truck (the nearest 8 of
/// 4000 samples, each refined by four rounds of 64 samples between its neighbours and
/// truck's own Newton search), and the worst radius error, truck's
/// `r(t)` at the parameter our projection finds from there (the radius error depends on
/// which nearby parameter is taken, and ours is the one the fit reports).
pub(super) fn truck_errors(fit: &SeamFit, points: &[[f64; 4]]) -> (f64, f64) {
    let (c, r) = truck_curves(fit);
    let (lo, hi) = fit.range();
    let samples: Vec<(f64, Point3)> = (0..=4000)
        .map(|i| {
            let t = lo + (hi - lo) * i as f64 / 4000.0;
            (t, c.subs(t))
        })
        .collect();
    let mut worst = (0.0f64, 0.0f64);
    for p in points {
        let q = Point3::new(p[0], p[1], p[2]);
        // The nearest samples (the curve may pass near `q` more than once): a ternary
        // search between each one's neighbours, then truck's Newton; the best wins.
        let mut order: Vec<usize> = (0..samples.len()).collect();
        order.select_nth_unstable_by(8, |a, b| {
            samples[*a]
                .1
                .distance2(q)
                .total_cmp(&samples[*b].1.distance2(q))
        });
        let mut t = samples[order[0]].0;
        for &k in &order[..8] {
            let (mut a, mut b) = (
                samples[k.saturating_sub(1)].0,
                samples[(k + 1).min(samples.len() - 1)].0,
            );
            // Not a ternary search: where the centre curve stalls it can fold within one
            // sample spacing, and the distance has two minima there (seed `28537a4e…`
            // had feet at 1.1e-4 and 1.8e-5 a quarter of a spacing apart).
            for _ in 0..4 {
                let step = (b - a) / 64.0;
                let best = (0..=64)
                    .map(|j| a + step * j as f64)
                    .min_by(|x, y| c.subs(*x).distance2(q).total_cmp(&c.subs(*y).distance2(q)))
                    .unwrap();
                (a, b) = ((best - step).max(lo), (best + step).min(hi));
            }
            let hint = 0.5 * (a + b);
            for cand in [Some(hint), c.search_nearest_parameter(q, Some(hint), 100)] {
                match cand {
                    Some(u) if c.subs(u).distance(q) < c.subs(t).distance(q) => t = u,
                    _ => {}
                }
            }
        }
        worst.0 = worst.0.max(c.subs(t).distance(q));
        let (ours, _) = fit.search_nearest_parameter([p[0], p[1], p[2]], t);
        worst.1 = worst.1.max((r.subs(ours).x - p[3]).abs());
    }
    worst
}
