//! Fitting one seam ([`fit_bspline`]): the rounds of least squares, knot placement and
//! parameter correction described in the module docs of [`crate::fit`], with the straight line
//! tried first and interpolation, or the polyline itself, as the last resort.

use super::curve::{dist3, SeamFit};
use super::knots::{
    averaged_knots, chord_params, insert_knots, keep_points_in_every_span, redistribute_knots,
};
use super::least_squares::{solve_least_squares, RIDGE_REL_MAX_DIAGONAL_ENTRY};

/// Highest degree used (cubic).
pub const MAX_DEGREE: usize = 3;
/// Budget of knot-insertion rounds before falling back to interpolation.
pub const MAX_ROUNDS: usize = 100;
/// Parameter correction starts when the worst distance is within this many tolerances.
const CORRECTION_START_REL_TOL: f64 = 10.0;
/// An interpolating cubic longer than this many times the polyline swings between points.
const MAX_LENGTH_REL_POLYLINE: f64 = 1.05;
/// Consecutive points whose coordinates all differ by at most this, relative to the largest
/// coordinate (taken as at least 1), are repeats.
const REPEAT_REL_MAX_COORD: f64 = 1e-14;

/// Fits `points` (`[x, y, z, r]`, in order along the seam) within `tol` (see the module
/// docs). `None` when `points` is empty.
pub fn fit_bspline(points: &[[f64; 4]], tol: f64) -> Option<SeamFit> {
    let q = distinct_points(points)?;
    let n = q.len();
    let params = chord_params(&q);
    let p = MAX_DEGREE.min(n - 1);
    let (lo, hi) = (params[0], params[n - 1]);
    let mut knots: Vec<f64> = [vec![lo; p + 1], vec![hi; p + 1]].concat();
    if p > 1 {
        // A straight seam (a box's) is a line: degree 1, two control points, when that fits.
        let line = [vec![lo; 2], vec![hi; 2]].concat();
        let (fit, _, _) = solve_round(&q, &params, &params, line, 1, 0.0);
        if fit.max_error <= tol && fit.max_radius_error <= tol {
            return Some(fit);
        }
    }
    let mut t = params.clone();
    let mut rounds = 0;
    // Knots are first redistributed by the error estimate (few rounds, near-minimal count);
    // once a redistribution makes the fit worse, the last good knots are refined by insertion
    // only, which cannot make the least-squares residual worse.
    let mut equidistribute = true;
    let mut accepted: Option<Attempt> = None;
    let mut interpolating = knots.len() - p > n;
    loop {
        // Interpolation is well posed (Schoenberg–Whitney holds for averaged knots): no ridge,
        // whose bias could be felt when control points are far from the polyline.
        let ridge = if interpolating {
            0.0
        } else {
            RIDGE_REL_MAX_DIAGONAL_ENTRY
        };
        let (fit, mut projected, mut errors) =
            solve_round(&q, &t, &params, knots.clone(), p, ridge);
        if (fit.max_error <= tol && fit.max_radius_error <= tol) || interpolating {
            if !swings(&fit, &q) {
                return Some(fit);
            }
            if interpolating {
                // Cubic interpolation of very unevenly spaced points can overshoot between
                // them: take the polyline itself (degree 1), which cannot.
                return fit_polyline(&q, &params);
            }
            // Close to the points but swinging between them (as many knots as points, badly
            // placed): interpolate instead.
            knots = averaged_knots(&params, p);
            t = params.clone();
            interpolating = true;
            continue;
        }
        rounds += 1;
        let worst = fit.max_error.max(fit.max_radius_error) / tol;
        match &accepted {
            Some(prev) if equidistribute && worst > prev.worst => {
                equidistribute = false;
                knots = prev.knots.clone();
                t = prev.t.clone();
                projected = prev.projected.clone();
                errors = prev.errors.clone();
            }
            _ => {
                accepted = Some(Attempt {
                    knots: knots.clone(),
                    t: t.clone(),
                    projected: projected.clone(),
                    errors: errors.clone(),
                    worst,
                })
            }
        }
        let mut new_knots = vec![];
        if equidistribute {
            new_knots =
                keep_points_in_every_span(redistribute_knots(&knots, p, &t, &errors, tol), p, &t);
        }
        if new_knots.len() <= knots.len() {
            // Redistribution off, or it could not add a span that holds points.
            equidistribute = false;
            new_knots = keep_points_in_every_span(insert_knots(&knots, p, &t, &errors, tol), p, &t);
        }
        if rounds > MAX_ROUNDS || new_knots.len() <= knots.len() || new_knots.len() - p > n {
            // Interpolate every point, on the chord-length parameters.
            knots = averaged_knots(&params, p);
            t = params.clone();
            interpolating = true;
            continue;
        }
        knots = new_knots;
        // Parameter correction, once the curve follows the points in order: projecting
        // onto a poor curve would scramble the parameters.
        let err_of_t = accepted.as_ref().map_or(worst, |a| a.worst) * tol;
        if err_of_t <= CORRECTION_START_REL_TOL * tol && projected.windows(2).all(|w| w[0] < w[1]) {
            t = projected;
        }
    }
}

/// `points` without exact repeats (they carry no information and would make interpolation
/// singular), and at least two of them (a single point is doubled). `None` when `points` is
/// empty.
fn distinct_points(points: &[[f64; 4]]) -> Option<Vec<[f64; 4]>> {
    let first = *points.first()?;
    let scale = points
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1.0);
    let mut q: Vec<[f64; 4]> = vec![first];
    for p in &points[1..] {
        let last = q[q.len() - 1];
        if (0..4).any(|a| (p[a] - last[a]).abs() > REPEAT_REL_MAX_COORD * scale) {
            q.push(*p);
        }
    }
    if q.len() == 1 {
        q.push(first);
    }
    Some(q)
}

/// One round: the least-squares curve of degree `p` on `knots` through `q` at parameters `t`
/// (see [`solve_least_squares`]), its errors measured; with each point's projected parameter
/// and errors.
fn solve_round(
    q: &[[f64; 4]],
    t: &[f64],
    params: &[f64],
    knots: Vec<f64>,
    p: usize,
    ridge: f64,
) -> (SeamFit, Vec<f64>, Vec<(f64, f64)>) {
    let (ctrl, radii) = solve_least_squares(q, t, params, &knots, p, ridge);
    let mut fit = SeamFit {
        degree: p,
        knots,
        control_points: ctrl,
        radii,
        max_error: 0.0,
        max_radius_error: 0.0,
    };
    let (projected, errors) = measure(&fit, q, t);
    fit.max_error = errors.iter().map(|e| e.0).fold(0.0, f64::max);
    fit.max_radius_error = errors.iter().map(|e| e.1).fold(0.0, f64::max);
    (fit, projected, errors)
}

/// True when the curve is clearly longer than the polyline through `q` (it swings between
/// the points; a faithful curve is about as long as its chords).
fn swings(fit: &SeamFit, q: &[[f64; 4]]) -> bool {
    let polyline: f64 = q
        .windows(2)
        .map(|w| dist3(w[0], [w[1][0], w[1][1], w[1][2]]))
        .sum();
    // A polygon through N samples of the curve is shorter than the curve by O(1/N²): the
    // lengths through 4 and 8 samples per point extrapolate (Richardson) to the curve's
    // length, so that a fit at the limit is not passed for its polygon's shortfall.
    let coarse = sampled_length(fit, 4 * q.len());
    let fine = sampled_length(fit, 8 * q.len());
    fine + (fine - coarse) / 3.0 > MAX_LENGTH_REL_POLYLINE * polyline
}

/// The length of the polygon through `samples + 1` points of `fit` evenly spaced in its
/// parameter.
fn sampled_length(fit: &SeamFit, samples: usize) -> f64 {
    let (lo, hi) = fit.range();
    let mut length = 0.0;
    let mut prev = fit.subs(lo);
    for i in 1..=samples {
        let c = fit.subs(lo + (hi - lo) * i as f64 / samples as f64);
        length += dist3(prev, [c[0], c[1], c[2]]);
        prev = c;
    }
    length
}

/// The polyline through `q` as a degree-1 B-spline (knots at the chord parameters).
fn fit_polyline(q: &[[f64; 4]], params: &[f64]) -> Option<SeamFit> {
    let n = q.len();
    let knots = [vec![params[0]], params.to_vec(), vec![params[n - 1]]].concat();
    Some(SeamFit {
        degree: 1,
        knots,
        control_points: q.iter().map(|c| [c[0], c[1], c[2]]).collect(),
        radii: q.iter().map(|c| c[3]).collect(),
        max_error: 0.0,
        max_radius_error: 0.0,
    })
}

/// One least-squares round: its knots, parameters, projected parameters, errors, and worst
/// error relative to the tolerance.
struct Attempt {
    knots: Vec<f64>,
    t: Vec<f64>,
    projected: Vec<f64>,
    errors: Vec<(f64, f64)>,
    worst: f64,
}

/// Each point's error, after projection: `(distance, radius error)`, and its projected
/// parameter. The end points keep their parameters (the curve interpolates them).
fn measure(fit: &SeamFit, q: &[[f64; 4]], t: &[f64]) -> (Vec<f64>, Vec<(f64, f64)>) {
    let n = q.len();
    let mut projected = t.to_vec();
    let mut errors = Vec::with_capacity(n);
    for i in 0..n {
        let qi = [q[i][0], q[i][1], q[i][2]];
        let (ti, d) = if i == 0 || i == n - 1 {
            (t[i], dist3(fit.subs(t[i]), qi))
        } else {
            fit.search_nearest_parameter(qi, t[i])
        };
        projected[i] = ti;
        errors.push((d, (fit.subs(ti)[3] - q[i][3]).abs()));
    }
    (projected, errors)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::truck_errors;
    use super::*;
    use proptest::prelude::*;

    fn arc(n: usize, radius: f64, angle: f64) -> Vec<[f64; 4]> {
        (0..n)
            .map(|i| {
                let a = angle * i as f64 / (n - 1) as f64;
                [radius * a.cos(), radius * a.sin(), 0.5 * a, 1.0 + 0.1 * a]
            })
            .collect()
    }

    #[test]
    fn densely_sampled_arc_fits_to_1e_6_with_few_control_points() {
        let points = arc(400, 10.0, 2.0);
        for tol in [1e-2, 1e-4, 1e-6] {
            let fit = fit_bspline(&points, tol).unwrap();
            assert_eq!(fit.degree, 3);
            assert!(
                fit.max_error <= tol && fit.max_radius_error <= tol,
                "{fit:?}"
            );
            let (d, dr) = truck_errors(&fit, &points);
            // Our Newton projection and truck's may stop a rounding error apart.
            assert!(
                d <= tol * (1.0 + 1e-6) && dr <= tol * (1.0 + 1e-6),
                "{d} {dr}"
            );
            // With chord-length parameters a cubic least-squares fit converges as h⁴:
            // measured ≈ 1.5e-3·r·θ⁴ on spans of θ rad, so 2 rad of radius 10 at 1e-6 needs
            // about 22 spans; 32 control points leave room, 400 would be interpolation.
            assert!(fit.control_points.len() <= 32, "{tol}: {fit:?}");
            assert_eq!(fit.control_points[0], [10.0, 0.0, 0.0]);
            let last = points[points.len() - 1];
            assert_eq!(
                *fit.control_points.last().unwrap(),
                [last[0], last[1], last[2]]
            );
        }
    }

    #[test]
    fn two_points_give_a_line_of_degree_1() {
        let fit = fit_bspline(&[[0.0, 0.0, 0.0, 0.0], [3.0, 4.0, 0.0, 2.0]], 1e-9).unwrap();
        assert_eq!(fit.degree, 1);
        assert_eq!(fit.control_points, vec![[0.0, 0.0, 0.0], [3.0, 4.0, 0.0]]);
        assert_eq!(fit.radii, vec![0.0, 2.0]);
        assert_eq!(fit.knots, vec![0.0, 0.0, 5.0, 5.0]);
        assert_eq!(fit.subs(2.5), [1.5, 2.0, 0.0, 1.0]);
    }

    #[test]
    fn three_points_give_a_quadratic_through_them() {
        let pts = [
            [0.0, 0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0, 1.0],
            [2.0, 0.0, 0.0, 0.0],
        ];
        let fit = fit_bspline(&pts, 1e-9).unwrap();
        assert_eq!(fit.degree, 2);
        assert_eq!(fit.control_points.len(), 3);
        assert!(
            fit.max_error < 1e-12 && fit.max_radius_error < 1e-12,
            "{fit:?}"
        );
    }

    #[test]
    fn points_on_a_line_give_a_line() {
        let pts: Vec<[f64; 4]> = (0..50)
            .map(|i| {
                // Uneven spacing, as the tracer's steps are.
                let s = (i as f64 / 49.0).powi(2) * 10.0;
                [1.0 + s, 2.0 - 0.5 * s, 3.0 + 0.25 * s, 0.1 * s]
            })
            .collect();
        let fit = fit_bspline(&pts, 1e-9).unwrap();
        assert_eq!(fit.degree, 1);
        assert_eq!(fit.control_points.len(), 2);
        assert!(
            fit.max_error < 1e-9 && fit.max_radius_error < 1e-9,
            "{fit:?}"
        );
    }

    #[test]
    fn points_nearly_on_a_line_give_a_line_within_the_tolerance_only() {
        let pts: Vec<[f64; 4]> = (0..30)
            .map(|i| {
                let s = i as f64 / 29.0;
                [10.0 * s, 1e-4 * (s * std::f64::consts::PI).sin(), 0.0, 1.0]
            })
            .collect();
        let line = fit_bspline(&pts, 2e-4).unwrap();
        assert_eq!((line.degree, line.control_points.len()), (1, 2));
        assert!(line.max_error <= 2e-4 && line.max_error > 5e-5, "{line:?}");
        let cubic = fit_bspline(&pts, 1e-6).unwrap();
        assert_eq!(cubic.degree, 3);
        assert!(cubic.max_error <= 1e-6, "{cubic:?}");
    }

    #[test]
    fn closed_seam_ends_coincide() {
        let points = arc(300, 5.0, std::f64::consts::TAU)
            .into_iter()
            .map(|p| [p[0], p[1], 0.0, 2.0])
            .collect::<Vec<_>>();
        let mut points = points;
        let n = points.len();
        points[n - 1] = points[0];
        let fit = fit_bspline(&points, 1e-5).unwrap();
        assert_eq!(fit.control_points[0], *fit.control_points.last().unwrap());
        assert!(fit.max_error <= 1e-5, "{fit:?}");
        let (d, dr) = truck_errors(&fit, &points);
        assert!(
            d <= 1e-5 * (1.0 + 1e-6) && dr <= 1e-5 * (1.0 + 1e-6),
            "{d} {dr}"
        );
    }

    #[test]
    fn repeated_and_single_points_do_not_break_the_fit() {
        let p = [1.0, 2.0, 3.0, 0.5];
        let fit = fit_bspline(&[p], 1e-6).unwrap();
        assert_eq!(fit.degree, 1);
        assert_eq!(fit.subs(0.0), p);
        let fit = fit_bspline(&[p, p, [2.0, 2.0, 3.0, 0.5], [2.0, 2.0, 3.0, 0.5]], 1e-6).unwrap();
        assert_eq!(fit.degree, 1);
        assert!(fit.max_error == 0.0, "{fit:?}");
        assert!(fit_bspline(&[], 1e-6).is_none());
    }

    #[test]
    fn twenty_thousand_points_fit_quickly_and_within_tolerance() {
        // A helix traced with steps dense where it bends hard (the tracer's MAX_TURN rule).
        let points: Vec<[f64; 4]> = (0..20_000)
            .map(|i| {
                let s = i as f64 / 19_999.0;
                let a = 12.0 * s + 3.0 * (s * 7.0).sin();
                [
                    20.0 * a.cos(),
                    20.0 * a.sin(),
                    30.0 * s,
                    5.0 + (3.0 * a).sin(),
                ]
            })
            .collect();
        let started = std::time::Instant::now();
        let fit = fit_bspline(&points, 1e-3).unwrap();
        let seconds = started.elapsed().as_secs_f64();
        assert!(
            fit.max_error <= 1e-3 && fit.max_radius_error <= 1e-3,
            "{fit:?}"
        );
        assert!(
            fit.control_points.len() < 300,
            "{}",
            fit.control_points.len()
        );
        // Generous: ~50 ms on this machine in the dev profile; a sign of a quadratic blow-up.
        assert!(seconds < 5.0, "{seconds} s");
    }

    /// Regression: NIST CTC-01 seam 67 (24 points, between two junctions, two hand-overs) at
    /// the part's default tolerance (1e-4 × its 930 mm diagonal). Knot redistribution could
    /// not add a span holding points, which fell straight to interpolating all 24 points;
    /// knot insertion from there needs 11 control points.
    #[test]
    fn stalled_redistribution_falls_back_to_insertion_not_interpolation() {
        let points: &[[f64; 4]] = &[
            [153.30127018922167, -100.0, -25.0, 25.0],
            [154.23132395110858, -100.0, -25.0, 25.0],
            [155.62640459393896, -100.0, -25.0, 25.0],
            [157.7190255581845, -100.0, -25.0, 25.0],
            [160.85795700455284, -100.0, -25.0, 25.0],
            [165.56635417410536, -100.0, -25.0, 25.0],
            [172.6289499284341, -100.0, -25.0, 25.0],
            [183.22284355992724, -100.0, -25.0, 25.0],
            [199.11368400716694, -100.0, -25.0, 25.0],
            [217.71475924490522, -100.0, -25.0, 25.0],
            [224.99996277677545, -100.0, -25.0, 25.0],
            [229.65023085029173, -100.21671567359023, -25.0, 25.0],
            [236.54992247557988, -101.35229408483792, -25.0, 25.0],
            [241.5765856609392, -102.82779526222834, -25.0, 25.0],
            [245.22722417423827, -104.27408373244003, -25.0, 25.0],
            [250.46899764729048, -106.9729136607844, -25.0, 25.0],
            [254.16808950144687, -109.38937838526928, -25.0, 25.0],
            [259.2890175791166, -113.60957167799431, -25.0, 25.0],
            [
                260.7071358985698,
                -114.99999362970169,
                -24.999999999998494,
                24.999999999998494,
            ],
            [
                264.09529733093166,
                -118.67561430307433,
                -25.09650100232569,
                25.09650100232569,
            ],
            [
                268.77927644750326,
                -124.53081936564368,
                -25.648832251388214,
                25.648832251388214,
            ],
            [
                274.9607193451019,
                -133.79476797479052,
                -27.523166424786275,
                27.523166424786275,
            ],
            [
                278.98779426922954,
                -140.82142325151003,
                -29.762470676764423,
                29.762470676764423,
            ],
            [
                282.69702918395006,
                -147.90737299690798,
                -32.7349656828752,
                32.7349656828752,
            ],
        ];
        let tol = 0.09300537618869137;
        let fit = fit_bspline(points, tol).unwrap();
        assert!(
            fit.max_error <= tol && fit.max_radius_error <= tol,
            "{fit:?}"
        );
        assert!(
            fit.control_points.len() <= 12,
            "{}",
            fit.control_points.len()
        );
    }

    /// A smooth random space curve with a radius, sampled unevenly: the spacing grows along
    /// the curve up to `s^2`, i.e. neighbouring steps differ by up to 3× (the tracer's step
    /// control changes its step more gently), and as densely as a trace (the tracer turns at
    /// most 0.15 rad a step): short samples get gentle curves.
    fn random_curve() -> impl Strategy<Value = (Vec<[f64; 4]>, f64)> {
        (
            prop::collection::vec((-5.0f64..5.0, 0.2f64..4.0, 0.0f64..6.3), 12),
            2usize..400,
            0.0f64..1.0,
            2i32..7,
        )
            .prop_map(|(waves, n, skew, k)| {
                // As dense as a trace: fewer points, gentler curve.
                let wiggle = 3.0 * (n as f64 / 100.0).min(1.0);
                let points = (0..n)
                    .map(|i| {
                        let s = (i as f64 / (n - 1).max(1) as f64).powf(1.0 + skew);
                        std::array::from_fn(|c| {
                            (0..3)
                                .map(|w| {
                                    let (amp, freq, phase) = waves[3 * c + w];
                                    amp * (freq * s * wiggle + phase).sin()
                                })
                                .sum::<f64>()
                                + if c == 3 { 20.0 } else { 10.0 * s }
                        })
                    })
                    .collect();
                (points, 10f64.powi(-k))
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn the_tolerance_is_always_honoured((points, tol) in random_curve()) {
            let fit = fit_bspline(&points, tol).unwrap();
            prop_assert!(fit.max_error <= tol && fit.max_radius_error <= tol,
                "reported {} {} > {tol}", fit.max_error, fit.max_radius_error);
            let (d, dr) = truck_errors(&fit, &points);
            prop_assert!(d <= tol * (1.0 + 1e-6) + 1e-12 && dr <= tol * (1.0 + 1e-6) + 1e-12,
                "measured {d} {dr} > {tol}");
            prop_assert!(fit.control_points.len() <= points.len().max(2));
            // No swings between the points: the curve is hardly longer than the polyline
            // (a smooth curve sampled this densely is at most ~1 % longer than its chords).
            let polyline: f64 = points.windows(2).map(|w| dist3(w[0], [w[1][0], w[1][1], w[1][2]])).sum();
            let (lo, hi) = fit.range();
            let curve: f64 = (0..4000).map(|i| {
                let (a, b) = (lo + (hi - lo) * i as f64 / 4000.0, lo + (hi - lo) * (i + 1) as f64 / 4000.0);
                let pb = fit.subs(b);
                dist3(fit.subs(a), [pb[0], pb[1], pb[2]])
            }).sum();
            prop_assert!(curve <= 1.05 * polyline + 1e-9, "curve {curve} vs polyline {polyline}");
        }
    }
}
