//! Marching along a seam: pseudo-arclength predictor–corrector steps with step control, and
//! the events that end a march or change its elements.

use super::handover::HandOverError;
use super::options::{MAX_POINTS, MAX_STEP_REL_DIAGONAL, MAX_TURN_RAD, MIN_STEP_REL_DIAGONAL};
use super::tracer::Tracer;
use super::unknowns::{new_triplet, slot, sys_point, to_chord, touches_meet, v3, Pairs};
use crate::medial::axis::{Handover, OpenReason, SeamEnd, SeamPoint};
use crate::medial::equations::MedialSystem;
use crate::medial::maximal::curvature_allows;
use crate::medial::solver::{solve, SolveOptions, SolveStatus};
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

/// The points of one march along a seam and how it ended.
pub(super) struct Run {
    pub(super) points: Vec<SeamPoint>,
    pub(super) end: SeamEnd,
    /// The elements at the end (after any hand-over).
    pub(super) triplet: [Element; 3],
    pub(super) handovers: Vec<Handover>,
}

impl Tracer<'_> {
    /// Marches along the seam of `triplet` from the seam point `x0`, leaving along `dir0`,
    /// until it ends (see [`SeamEnd`]). With `close_at`, a march that comes back to that
    /// point ends [`SeamEnd::Closed`].
    pub(super) fn march(
        &mut self,
        mut triplet: [Element; 3],
        x0: DVector<f64>,
        dir0: DVec3,
        close_at: Option<&DVector<f64>>,
    ) -> Run {
        let mut sys = MedialSystem::new(triplet.to_vec());
        let mut handovers = vec![];
        let first = triplet;
        let solid = self.solid_of(triplet[0]);
        let diag = self.model.diagonal();
        let acc = self.opts.accuracy;
        let mut x = x0;
        let mut points = vec![self.seam_point(&sys, &x)];
        // The first tangent is oriented by the centre's direction alone (no weight on r).
        let mut dir = DVector::zeros(10);
        dir[0] = dir0.x;
        dir[1] = dir0.y;
        dir[2] = dir0.z;
        let Some(mut t) = self.tangent(&sys, &x, &dir) else {
            let end = SeamEnd::Open(OpenReason::SingularTangent);
            return Run {
                points,
                end,
                triplet,
                handovers,
            };
        };
        let mut h = 1e-3 * diag;
        let mut travel = 0.0;
        let end: SeamEnd;
        loop {
            if points.len() >= MAX_POINTS {
                end = SeamEnd::Open(OpenReason::PointBudgetExhausted);
                break;
            }
            let Some((xn, tn, iterations)) = self.step(&sys, &x, &t, h) else {
                self.stats.corrector_failures += 1;
                h *= 0.5;
                if h < MIN_STEP_REL_DIAGONAL * diag {
                    end = SeamEnd::Open(OpenReason::StepSizeUnderflow);
                    break;
                }
                continue;
            };
            let r = xn[3];
            // Back to a convex vertex: r returns to zero.
            // (Away from a vertex with a touch point off its segment, the step overshot a
            // hand-over or a junction: that is handled below.)
            if r <= acc && points.len() > 1 {
                let (xe, v) = self.land_at_vertex(&sys, xn.clone());
                let off = (0..3).any(|i| !self.on_segment(triplet[i], slot(&xn, i)));
                if v.is_some() || !off {
                    points.push(self.seam_point(&sys, &xe));
                    end = v.map_or_else(
                        || SeamEnd::Open(OpenReason::ZeroRadiusAwayFromVertex),
                        SeamEnd::Vertex,
                    );
                    break;
                }
            }
            // Back at the seed: a closed seam.
            // (Only on the segments it started with: the seed's parameters are theirs.)
            if let Some(xs) = close_at.filter(|_| triplet == first) {
                let step = v3(&xn).distance(v3(&x));
                if travel > 3.0 * step
                    && to_chord(v3(xs), v3(&x), v3(&xn)) <= 0.05 * step + 10.0 * acc
                    && (xs[3] - r).abs() <= 0.05 * step + 10.0 * acc
                {
                    points.push(self.seam_point(&sys, xs));
                    end = SeamEnd::Closed;
                    break;
                }
            }
            // A touch point that leaves its segment is handed over to the next one across
            // the edge it crossed (xn itself, off the segment, is not output).
            if let Some(mut i) =
                (0..3).find(|&i| !self.stays_on(triplet[i], slot(&x, i), slot(&xn, i)))
            {
                match self.hand_over(&triplet, &mut i, &x, &t, h) {
                    Ok((to, xc, _))
                        if handovers.last().is_some_and(|h: &Handover| {
                            h.point + 1 >= points.len() && h.to == triplet[i] && h.from == to
                        }) =>
                    {
                        // The touch point sits at a vertex while the normal turns: it is
                        // on the vertex (a corner of two reflex edges, or of faceted faces
                        // meeting at small angles), not on either neighbour.
                        let from = triplet[i];
                        match self.onto_vertex(&triplet, i, &xc, &t) {
                            Some((v, xv)) => {
                                handovers.push(Handover {
                                    point: points.len(),
                                    from,
                                    to: v,
                                });
                                triplet[i] = v;
                                sys = MedialSystem::new(triplet.to_vec());
                                points.push(self.seam_point(&sys, &xv));
                                let mut d = DVector::zeros(10);
                                d.rows_mut(0, 3).copy_from(&t.rows(0, 3));
                                let Some(tc) = self.tangent(&sys, &xv, &d) else {
                                    end = SeamEnd::Open(OpenReason::SingularTangentAfterHandover);
                                    break;
                                };
                                travel += v3(&xv).distance(v3(&x));
                                x = xv;
                                t = tc;
                                continue;
                            }
                            None => {
                                end = SeamEnd::Open(OpenReason::Oscillates { from, to });
                                break;
                            }
                        }
                    }
                    Ok((to, crossing, xnew)) => {
                        // The crossing point must itself be medial: a junction may come first.
                        if let Some((e, jx)) =
                            self.junction_between(&triplet, solid, &x, &crossing, &t)
                        {
                            if let Some(jx) = jx {
                                points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                            }
                            end = e;
                            break;
                        }
                        let xc = xnew;
                        let nt = new_triplet(&triplet, i, to);
                        if self.coincident(&nt, &xc, true) {
                            // Two touch points on one part of the boundary (faces and the
                            // reflex edges and vertices joining them, across which a touch
                            // point moves on) have met: the ball osculates it there, like a
                            // face touched twice at its curvature limit, and the seam ends.
                            let at = |k: usize| sys_point(self.model, nt[k], slot(&xc, k));
                            let merged = (0..3).find(|&k| {
                                k != i
                                    && self.groups.of(nt[k]) == self.groups.of(to)
                                    && matches!((at(k), at(i)), (Some(a), Some(b)) if a.distance(b) <= 1e-4 * xc[3])
                            });
                            end = match merged {
                                Some(_) => {
                                    points.push(self.seam_point(&sys, &crossing));
                                    SeamEnd::CurvatureLimit { segment: to }
                                }
                                None => SeamEnd::Open(OpenReason::CoincideAfterHandover {
                                    from: triplet[i],
                                    to,
                                }),
                            };
                            break;
                        }
                        handovers.push(Handover {
                            point: points.len(),
                            from: triplet[i],
                            to,
                        });
                        triplet[i] = to;
                        sys = MedialSystem::new(triplet.to_vec());
                        points.push(self.seam_point(&sys, &xc));
                        let mut d = DVector::zeros(10);
                        d.rows_mut(0, 3).copy_from(&t.rows(0, 3));
                        let Some(tc) = self.tangent(&sys, &xc, &d) else {
                            end = SeamEnd::Open(OpenReason::SingularTangentAfterHandover);
                            break;
                        };
                        travel += v3(&xc).distance(v3(&x));
                        x = xc;
                        t = tc;
                        continue;
                    }
                    Err((e, xc)) => {
                        // A junction before the crossing ends the seam there instead (the
                        // step that left the segment may have passed it).
                        if let Some((e, jx)) = self.junction_between(&triplet, solid, &x, &xc, &t) {
                            if let Some(jx) = jx {
                                points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                            }
                            end = e;
                            break;
                        }
                        // The crossing point itself is a seam point when it is medial.
                        if self.is_medial(&triplet, &xc) {
                            points.push(self.seam_point(&sys, &xc));
                        }
                        end = match e {
                            HandOverError::Osculates(seg) => {
                                SeamEnd::CurvatureLimit { segment: seg }
                            }
                            HandOverError::Stop(why) => SeamEnd::Open(why),
                        };
                        break;
                    }
                }
            }
            // Another part of the boundary closer than r: a junction between x and xn.
            if let Some((e, jx)) = self.junction_between(&triplet, solid, &x, &xn, &t) {
                if let Some(jx) = jx {
                    points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                }
                end = e;
                break;
            }
            // The curvature criterion: the ball must not poke through a touched face. Where
            // the ball touches a face twice, the two touch points must not meet (or pass
            // through each other): where they meet the ball osculates the face, r·κmax = 1,
            // and the seam ends at that centre of curvature.
            let touches = |y: &DVector<f64>| -> [Option<DVec3>; 3] {
                std::array::from_fn(|i| sys_point(self.model, triplet[i], slot(y, i)))
            };
            let before = touches(&x);
            let poked = |y: &DVector<f64>| {
                let now = touches(y);
                (0..3).find(|&i| {
                    !curvature_allows(self.model, triplet[i], slot(y, i), y[3])
                        || (0..i).any(|j| {
                            triplet[j] == triplet[i]
                                && match (before[i], before[j], now[i], now[j]) {
                                    // Separated by less than 1e-4·r, the centre is within
                                    // ~(1e-4·r)²/ρ of the end: far below the accuracy.
                                    (Some(a), Some(b), Some(c), Some(d)) => {
                                        (c - d).dot(a - b) <= 0.0 || c.distance(d) <= 1e-4 * y[3]
                                    }
                                    _ => true,
                                }
                        })
                })
            };
            // Two different segments touched at one place (where a face meets its edge): the
            // ball touches fewer than three places, so the point is no seam point.
            if self.coincident(&triplet, &xn, false) {
                end = SeamEnd::Open(OpenReason::TouchPointsCoincide);
                break;
            }
            if let Some(i) = poked(&xn) {
                // Bisect the arclength from x to where the ball osculates, to the accuracy.
                let (mut lo, mut hi) = (0.0, h);
                let mut last = None;
                while hi - lo > acc {
                    let mid = 0.5 * (lo + hi);
                    match self.centre_step(&sys, &x, &t, mid) {
                        Some(xm) if poked(&xm).is_none() => {
                            lo = mid;
                            last = Some(xm);
                        }
                        _ => hi = mid,
                    }
                }
                if let Some(xm) = last {
                    points.push(self.seam_point(&sys, &xm));
                }
                end = SeamEnd::CurvatureLimit {
                    segment: triplet[i],
                };
                break;
            }
            points.push(self.seam_point(&sys, &xn));
            travel += v3(&xn).distance(v3(&x));
            x = xn;
            t = tn;
            h = if iterations <= 3 {
                (h * 1.5).min(MAX_STEP_REL_DIAGONAL * diag)
            } else {
                h * 0.7
            };
        }
        Run {
            points,
            end,
            triplet,
            handovers,
        }
    }

    /// True when two touch points of the seam point `x` are one place (closer than 1e-4·r):
    /// for different segments always, for a segment touched twice only with `same` (a
    /// merging pair on one face is otherwise the curvature limit's business).
    pub(super) fn coincident(&self, triplet: &[Element; 3], x: &DVector<f64>, same: bool) -> bool {
        let pairs = if same {
            Pairs::All
        } else {
            Pairs::DifferentSegments
        };
        touches_meet(self.model, triplet, x, 1e-4 * x[3], pairs)
    }

    /// One predictor–corrector step of length `h` from `x` along the unit tangent `t`: the new
    /// point, its tangent (oriented along `t`) and the corrector's iterations. `None` when the
    /// corrector fails, the radius goes negative from a point that already had r ≤ 0, or the
    /// seam turns by more than [`MAX_TURN_RAD`] (step control by seam curvature).
    pub(super) fn step(
        &mut self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> Option<(DVector<f64>, DVector<f64>, usize)> {
        let pred = x + t * h;
        // Corrector: F = 0 and t·(y − pred) = 0.
        let c = t.dot(&pred);
        let sol = solve(
            |y| sys.eval_with_row(self.model, y, t, c),
            pred,
            &self.solve_opts(),
        );
        self.stats.newton_iterations += sol.iterations;
        if sol.status != SolveStatus::Converged || sol.x[3] < -self.opts.accuracy && x[3] <= 0.0 {
            return None;
        }
        let tn = self.tangent(sys, &sol.x, t)?;
        let turn = v3(t).angle_between(v3(&tn));
        (turn <= MAX_TURN_RAD).then_some((sol.x, tn, sol.iterations))
    }

    /// The seam point whose centre lies in the plane `t_B·(B − B(x)) = h` (normal to the
    /// centre's direction `t_B`, `h` ahead), from a start with `x`'s segment parameters. Near
    /// an end where two touch points on one face meet, the parameters move like the square
    /// root of the centre's travel, so the arclength predictor along `t` overshoots them;
    /// fixing only the centre's advance keeps Newton within reach (used to locate ends).
    pub(super) fn centre_step(
        &mut self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> Option<DVector<f64>> {
        let tb = v3(t).normalize();
        let mut row = DVector::zeros(x.len());
        row[0] = tb.x;
        row[1] = tb.y;
        row[2] = tb.z;
        let mut start = x.clone();
        for k in 0..4 {
            start[k] += h * t[k] / v3(t).length();
        }
        let c = row.dot(x) + h;
        let sol = solve(
            |y| sys.eval_with_row(self.model, y, &row, c),
            start,
            &SolveOptions {
                tol: 1e-3 * self.opts.accuracy,
                max_iter: 40,
            },
        );
        self.stats.newton_iterations += sol.iterations;
        (sol.status == SolveStatus::Converged).then_some(sol.x)
    }

    /// Unit tangent of the seam at `x` (centre part of unit length), oriented along `dir`.
    pub(super) fn tangent(
        &self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        dir: &DVector<f64>,
    ) -> Option<DVector<f64>> {
        let (_, a) = sys.eval_with_row(self.model, x, dir, 0.0)?;
        let mut rhs = DVector::zeros(x.len());
        rhs[x.len() - 1] = 1.0;
        let z = a.lu().solve(&rhs)?;
        let zb = DVec3::new(z[0], z[1], z[2]).length();
        (zb.is_finite() && zb > 0.0).then(|| z / zb)
    }

    /// Lands a seam point that reached `r ≈ 0` exactly on `r = 0` (the corrector may have
    /// overshot to a negative radius) by replacing the arclength equation with `r = 0`, and
    /// finds the vertex there.
    pub(super) fn land_at_vertex(
        &mut self,
        sys: &MedialSystem,
        xn: DVector<f64>,
    ) -> (DVector<f64>, Option<usize>) {
        let mut r_row = DVector::zeros(xn.len());
        r_row[3] = 1.0;
        let xe = solve(
            |y| sys.eval_with_row(self.model, y, &r_row, 0.0),
            xn.clone(),
            &self.solve_opts(),
        );
        let xe = if xe.status == SolveStatus::Converged {
            xe.x
        } else {
            xn
        };
        let b = v3(&xe);
        let v = (0..self.model.vertices.len())
            .min_by(|&a, &c| {
                let va = self.model.vertices[a].point.distance(b);
                va.total_cmp(&self.model.vertices[c].point.distance(b))
            })
            .filter(|&v| self.model.vertices[v].point.distance(b) <= 1e3 * self.opts.accuracy);
        (xe, v)
    }
}
