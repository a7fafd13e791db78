//! Damped Newton for the medial equations, with a backtracking line search (the paper's
//! solver, Ramanathan & Gurumoorthy 2005, §4.2), reporting how it ended as data.
//!
//! Square systems (`n` equations, `n` unknowns) take the Newton step `J·Δ = −F`; systems
//! with more unknowns than equations (a seam or sheet point before the tracer adds its
//! continuation equation) take the minimum-norm step `Δ = −J⁺·F`, which converges to a
//! nearby point of the solution curve or surface. The step is halved until `‖F‖` decreases
//! (at most [`MAX_HALVINGS`] times).

use nalgebra::{DMatrix, DVector};

/// Most halvings of one Newton step before the line search gives up.
pub const MAX_HALVINGS: usize = 30;

/// Default iteration budget.
pub const DEFAULT_MAX_ITER: usize = 50;

/// How a solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolveStatus {
    /// `‖F‖∞ ≤ tol`.
    Converged,
    /// The iteration budget ran out first; the best point so far is returned.
    MaxIter,
    /// The Jacobian was singular, the line search found no decrease, or the system could not
    /// be evaluated (a segment's normal undefined).
    Singular,
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct SolveOptions {
    /// Convergence threshold on `‖F‖∞` (model units).
    pub tol: f64,
    pub max_iter: usize,
}

/// The outcome of [`solve`].
#[derive(Clone, Debug)]
pub struct Solution {
    pub x: DVector<f64>,
    pub status: SolveStatus,
    pub iterations: usize,
    /// `‖F(x)‖∞` at the returned point.
    pub residual: f64,
}

/// Solves `F(x) = 0` from `x0`. `eval` returns the residual and Jacobian, or `None` where the
/// system is undefined.
pub fn solve(
    eval: impl Fn(&DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)>,
    x0: DVector<f64>,
    opts: &SolveOptions,
) -> Solution {
    solve_keeping_jacobian(eval, x0, opts).0
}

/// [`solve`], with the Jacobian `eval` gave at the returned point (`None` where it could not
/// evaluate there): a caller that needs it there (the seam's tangent at a converged point)
/// need not evaluate the system again.
pub fn solve_keeping_jacobian(
    eval: impl Fn(&DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)>,
    x0: DVector<f64>,
    opts: &SolveOptions,
) -> (Solution, Option<DMatrix<f64>>) {
    let mut x = x0;
    let Some((mut f, mut j)) = eval(&x) else {
        let sol = Solution {
            residual: f64::INFINITY,
            x,
            status: SolveStatus::Singular,
            iterations: 0,
        };
        return (sol, None);
    };
    let norm = |f: &DVector<f64>| f.amax();
    for it in 0..opts.max_iter {
        let r = norm(&f);
        if r <= opts.tol {
            let sol = Solution {
                x,
                status: SolveStatus::Converged,
                iterations: it,
                residual: r,
            };
            return (sol, Some(j));
        }
        let Some(step) = newton_step(&j, &f) else {
            let sol = Solution {
                x,
                status: SolveStatus::Singular,
                iterations: it,
                residual: r,
            };
            return (sol, Some(j));
        };
        let mut t = 1.0;
        let mut accepted = false;
        for _ in 0..=MAX_HALVINGS {
            let xn = &x + &step * t;
            if let Some((fn_, jn)) = eval(&xn) {
                if norm(&fn_) < r {
                    x = xn;
                    f = fn_;
                    j = jn;
                    accepted = true;
                    break;
                }
            }
            t *= 0.5;
        }
        if !accepted {
            let sol = Solution {
                x,
                status: SolveStatus::Singular,
                iterations: it,
                residual: r,
            };
            return (sol, Some(j));
        }
    }
    let r = norm(&f);
    let sol = Solution {
        x,
        status: if r <= opts.tol {
            SolveStatus::Converged
        } else {
            SolveStatus::MaxIter
        },
        iterations: opts.max_iter,
        residual: r,
    };
    (sol, Some(j))
}

/// The Newton step: `J⁻¹·(−F)` for square `J`, the minimum-norm `−J⁺·F` otherwise.
fn newton_step(j: &DMatrix<f64>, f: &DVector<f64>) -> Option<DVector<f64>> {
    let step = if j.is_square() {
        j.clone().lu().solve(&(-f))?
    } else {
        // Rank-revealing SVD; singular values below 1e-12 of the largest are dropped.
        let svd = j.clone().svd(true, true);
        let smax = svd.singular_values.max();
        if !(smax.is_finite() && smax > 0.0) {
            return None;
        }
        svd.solve(&(-f), 1e-12 * smax).ok()?
    };
    step.iter().all(|v| v.is_finite()).then_some(step)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::{MedialSystem, NormalField};
    use crate::model::Element;
    use proptest::prelude::*;

    use crate::testing::sample;

    /// Unknowns `[B, r, s…]` with each touch parameter at fraction `frac(i)` of segment i's
    /// face domain.
    fn start(
        m: &crate::model::Model,
        sys: &MedialSystem,
        b: [f64; 3],
        r: f64,
        frac: impl Fn(usize) -> (f64, f64),
    ) -> DVector<f64> {
        let mut x = DVector::zeros(sys.unknowns());
        x.rows_mut(0, 3).copy_from_slice(&b);
        x[3] = r;
        for (i, seg) in sys.segments.iter().enumerate() {
            let Element::Face(f) = *seg else {
                panic!("test starts are built on faces");
            };
            let d = m.faces[f].domain;
            let (a, c) = frac(i);
            x[4 + 2 * i] = d.u.0 + a * (d.u.1 - d.u.0);
            x[5 + 2 * i] = d.v.0 + c * (d.v.1 - d.v.0);
        }
        x
    }

    /// Solves to 1e-12 mm in at most 30 iterations.
    fn solve_tight(m: &crate::model::Model, sys: &MedialSystem, x: DVector<f64>) -> Solution {
        solve(
            |x| sys.eval(m, x),
            x,
            &SolveOptions {
                tol: 1e-12,
                max_iter: 30,
            },
        )
    }

    /// The face of `m` whose outward normal at its domain centre is `n` (±1e-9).
    fn face_with_normal(m: &crate::model::Model, n: glam::DVec3) -> usize {
        (0..m.faces.len())
            .find(|&f| {
                let d = m.faces[f].domain;
                let e = Element::Face(f)
                    .eval(m, [0.5 * (d.u.0 + d.u.1), 0.5 * (d.v.0 + d.v.1)])
                    .unwrap();
                e.n.distance(n) < 1e-9
            })
            .expect("face with that normal")
    }

    /// The box [0,60]×[0,40]×[0,20]: the junction touching bottom, top, x = 0 and y = 0 is
    /// (10, 10, 10) with radius 10 (the analytic formula for a box). A square 12×12 system.
    fn box_junction_system(m: &crate::model::Model) -> MedialSystem {
        MedialSystem::new(
            [
                glam::DVec3::NEG_Z,
                glam::DVec3::Z,
                glam::DVec3::NEG_X,
                glam::DVec3::NEG_Y,
            ]
            .map(|n| Element::Face(face_with_normal(m, n)))
            .to_vec(),
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Known root from perturbed starts: the box junction, with B and r perturbed by up
        /// to 4 mm and the touch parameters started at arbitrary points of their faces.
        #[test]
        fn box_junction_from_perturbed_starts(
            db in proptest::array::uniform3(-4.0f64..4.0),
            dr in -4.0f64..4.0,
            s in proptest::array::uniform8(0.05f64..0.95),
        ) {
            let m = sample("box.step");
            let sys = box_junction_system(&m);
            let x = start(&m, &sys, [10.0 + db[0], 10.0 + db[1], 10.0 + db[2]], 10.0 + dr, |i| (s[2 * i], s[2 * i + 1]));
            let sol = solve_tight(&m, &sys, x);
            prop_assert_eq!(sol.status, SolveStatus::Converged);
            // Planes make the system linear: Newton lands in one step, to rounding.
            let err = (sol.x[0] - 10.0).abs().max((sol.x[1] - 10.0).abs()).max((sol.x[2] - 10.0).abs()).max((sol.x[3] - 10.0).abs());
            prop_assert!(err < 1e-9, "junction off by {}", err);
        }
    }

    /// A seam point (3 faces, 9 equations, 10 unknowns) from a perturbed start converges to
    /// a point equidistant from bottom, x = 0 and y = 0 of the box: B = (t, t, t), r = t.
    #[test]
    fn underdetermined_seam_point_lands_on_the_seam() {
        let m = sample("box.step");
        let segs = [glam::DVec3::NEG_Z, glam::DVec3::NEG_X, glam::DVec3::NEG_Y]
            .map(|n| Element::Face(face_with_normal(&m, n)))
            .to_vec();
        let sys = MedialSystem::new(segs);
        let x = start(&m, &sys, [5.0, 6.5, 4.2], 4.0, |_| (0.5, 0.5));
        let sol = solve_tight(&m, &sys, x);
        assert_eq!(sol.status, SolveStatus::Converged);
        let t = sol.x[3];
        for k in 0..3 {
            assert!(
                (sol.x[k] - t).abs() < 1e-9,
                "B = {:?}, r = {t}",
                &sol.x.as_slice()[..3]
            );
        }
    }

    /// The sheet system of the cylinder's curved wall (of `cylinder.step` or its NURBS twin)
    /// and its bottom, started at B = (3, 2, 5), r = 4, off the solution.
    fn wall_and_bottom(m: &crate::model::Model) -> (MedialSystem, DVector<f64>) {
        let bottom = face_with_normal(m, glam::DVec3::NEG_Z);
        let wall = (0..m.faces.len())
            .find(|&f| {
                !matches!(
                    crate::geom::surface_kind(&m.faces[f].surface),
                    "plane" | "bspline"
                )
            })
            .expect("curved wall");
        let sys = MedialSystem::new(vec![Element::Face(wall), Element::Face(bottom)]);
        let x = start(m, &sys, [3.0, 2.0, 5.0], 4.0, |i| {
            if i == 0 {
                (0.3, 0.2)
            } else {
                (0.5, 0.5)
            }
        });
        (sys, x)
    }

    /// The Jacobian kept is the one at the point returned, equal to the bit to evaluating
    /// there again (the tracer takes the seam's tangent from it), on a cylinder where it
    /// changes from one iterate to the next; and there is none where the system cannot be
    /// evaluated at the start.
    #[test]
    fn the_jacobian_kept_is_the_one_at_the_returned_point() {
        let m = sample("cylinder.step");
        let (sys, x) = wall_and_bottom(&m);
        let opts = SolveOptions {
            tol: 1e-12,
            max_iter: 30,
        };
        let (sol, j) = solve_keeping_jacobian(|y| sys.eval(&m, y), x.clone(), &opts);
        assert_eq!(sol.status, SolveStatus::Converged, "{sol:?}");
        assert!(sol.iterations > 1, "{sol:?}");
        let (_, again) = sys.eval(&m, &sol.x).unwrap();
        assert_eq!(j.unwrap(), again);
        let (_, at_start) = sys.eval(&m, &x).unwrap();
        assert_ne!(at_start, again, "the Jacobian changes along the way");
        let (none, j) = solve_keeping_jacobian(|_| None, x, &opts);
        assert_eq!(none.status, SolveStatus::Singular);
        assert!(j.is_none());
    }

    /// A sheet point on a curved face (2 segments, 6 equations, 8 unknowns): the cylinder
    /// (radius 10, height 30, axis z) and its NURBS twin. Any ball touching the side wall and
    /// the bottom has its centre at z = r and at distance 10 − r from the axis.
    #[test]
    fn sheet_point_between_cylinder_wall_and_bottom() {
        for file in ["cylinder.step", "cylinder_nurbs.step"] {
            let m = sample(file);
            let (sys, x) = wall_and_bottom(&m);
            let sol = solve_tight(&m, &sys, x);
            assert_eq!(sol.status, SolveStatus::Converged, "{file}: {sol:?}");
            let (bx, by, bz, r) = (sol.x[0], sol.x[1], sol.x[2], sol.x[3]);
            assert!(r > 0.0 && r < 10.0, "{file}: r = {r}");
            assert!((bz - r).abs() < 1e-9, "{file}: z = {bz}, r = {r}");
            assert!(
                ((bx * bx + by * by).sqrt() - (10.0 - r)).abs() < 1e-9,
                "{file}: B = ({bx}, {by}, {bz}), r = {r}"
            );
        }
    }

    /// A curved junction: the tetrahedron's incentre (6, 6, 6), inradius 6, touching its four
    /// planar faces; and a system with no solution reports it instead of claiming one.
    #[test]
    fn tetrahedron_incentre_and_reported_failure() {
        let m = sample("tetrahedron.step");
        let sys = MedialSystem::new((0..4).map(Element::Face).collect());
        let x = start(&m, &sys, [5.0, 7.0, 6.5], 4.0, |_| (0.5, 0.5));
        let sol = solve_tight(&m, &sys, x);
        assert_eq!(sol.status, SolveStatus::Converged);
        for (k, want) in [6.0, 6.0, 6.0, 6.0].iter().enumerate() {
            assert!((sol.x[k] - want).abs() < 1e-9, "x[{k}] = {}", sol.x[k]);
        }
        // The box's bottom, top (20 apart) and its x = 0, x = 60 sides (60 apart): no ball
        // touches all four, so the solver must end without claiming convergence.
        let b = sample("box.step");
        let sys = MedialSystem::new(
            [
                glam::DVec3::NEG_Z,
                glam::DVec3::Z,
                glam::DVec3::NEG_X,
                glam::DVec3::X,
            ]
            .map(|n| Element::Face(face_with_normal(&b, n)))
            .to_vec(),
        );
        let x = start(&b, &sys, [30.0, 20.0, 10.0], 10.0, |_| (0.5, 0.5));
        let sol = solve_tight(&b, &sys, x);
        assert_ne!(sol.status, SolveStatus::Converged, "{sol:?}");
    }
}
