//! Marching along a seam: pseudo-arclength predictor–corrector steps with step control, and
//! the events that end a march or change its elements.

use super::handover::HandOverError;
use super::junctions::Meeting;
use super::options::{
    FAST_CONVERGENCE_ITER, FIRST_STEP_REL_DIAGONAL, MAX_CENTRE_STEP_ITER, MAX_HANDOVERS_IN_PLACE,
    MAX_POINTS, MAX_STEP_REL_DIAGONAL, MAX_TOUCH_TURN_RAD, MAX_TURN_RAD, MERGED_TOUCH_REL_RADIUS,
    MIN_STEP_REL_DIAGONAL, REACH_REL_ACCURACY, SAME_PLACE_REL_ACCURACY, STEP_GROWTH, STEP_SHRINK,
    TIP_AHEAD_RAD, TIP_REL_ACCURACY,
};
use super::tracer::Tracer;
use super::unknowns::{
    along_chord, new_triplet, slot, sys_point, to_chord, touches_meet, v3, Pairs,
};
use crate::classify::VertexKind;
use crate::geom::project_point;
use crate::medial::axis::{Handover, OpenReason, SeamEnd, SeamPoint};
use crate::medial::equations::MedialSystem;
use crate::medial::solver::{solve, solve_keeping_jacobian, SolveOptions, SolveStatus};
use crate::model::Element;
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// The points of one march along a seam and how it ended.
pub(super) struct Run {
    pub(super) points: Vec<SeamPoint>,
    pub(super) end: SeamEnd,
    /// The elements at the end (after any hand-over).
    pub(super) triplet: [Element; 3],
    pub(super) handovers: Vec<Handover>,
    /// How long the march took (s).
    pub(super) seconds: f64,
}

/// The state of one march.
#[derive(Clone)]
pub(super) struct March<'c> {
    /// The elements touched now, and at the start.
    pub(super) triplet: [Element; 3],
    pub(super) first: [Element; 3],
    pub(super) sys: MedialSystem,
    pub(super) solid: usize,
    /// Where a march from a seed closes.
    pub(super) close_at: Option<&'c DVector<f64>>,
    /// The last seam point, the unit tangent there, the next step's length (mm of centre
    /// travel) and the travel so far.
    pub(super) x: DVector<f64>,
    pub(super) t: DVector<f64>,
    pub(super) h: f64,
    pub(super) travel: f64,
    pub(super) points: Vec<SeamPoint>,
    pub(super) handovers: Vec<Handover>,
    /// Hand-overs since the last ordinary step.
    pub(super) in_place: usize,
}

/// What one step of a march leads to.
enum Flow {
    /// The next step.
    Next,
    /// The end of the march.
    End(SeamEnd),
}

/// True when handing touch point `i` to `to` undoes the hand-over made at the last point.
fn handed_back(m: &March, i: usize, to: Element) -> bool {
    m.handovers
        .last()
        .is_some_and(|h| h.point + 1 >= m.points.len() && h.to == m.triplet[i] && h.from == to)
}

/// The centre of a seam point.
fn centre_of(p: &SeamPoint) -> DVec3 {
    DVec3::new(p.point[0], p.point[1], p.point[2])
}

/// Two touch points closing in on each other at a hand-over's crossing are taken to meet
/// there when within this many of `verify`'s separations (the seam's end then within about
/// 4 accuracies of their meeting; the new system is too near singular to go on).
const MERGING_SEPARATIONS: f64 = 2.0;

impl Tracer<'_> {
    /// Marches along the seam of `triplet` from the seam point `x0`, leaving along `dir0`,
    /// until it ends (see [`SeamEnd`]). With `close_at`, a march that comes back to that
    /// point ends [`SeamEnd::Closed`].
    pub(super) fn march(
        &mut self,
        triplet: [Element; 3],
        x0: DVector<f64>,
        dir0: DVec3,
        close_at: Option<&DVector<f64>>,
    ) -> Run {
        let started = std::time::Instant::now();
        let sys = MedialSystem::new(triplet.to_vec());
        let points = vec![self.seam_point(&sys, &x0)];
        // The first tangent is oriented by the centre's direction alone (no weight on r).
        let mut dir = DVector::zeros(10);
        dir[0] = dir0.x;
        dir[1] = dir0.y;
        dir[2] = dir0.z;
        let Some(t) = self.tangent(&sys, &x0, &dir) else {
            return Run {
                points,
                end: SeamEnd::Open(OpenReason::SingularTangent),
                triplet,
                handovers: vec![],
                seconds: started.elapsed().as_secs_f64(),
            };
        };
        let mut m = March {
            triplet,
            first: triplet,
            sys,
            solid: self.solid_of(triplet[0]),
            close_at,
            x: x0,
            t,
            h: FIRST_STEP_REL_DIAGONAL * self.model.diagonal(),
            travel: 0.0,
            points,
            handovers: vec![],
            in_place: 0,
        };
        self.along.clear();
        self.at_start = true;
        let end = loop {
            if let Flow::End(end) = self.march_step(&mut m) {
                break end;
            }
        };
        self.along.clear();
        Run {
            points: m.points,
            end,
            triplet: m.triplet,
            handovers: m.handovers,
            seconds: started.elapsed().as_secs_f64(),
        }
    }

    /// One step of a march: the next seam point, or the event that ends the march or hands a
    /// touch point over, in this order: the point budget, the corrector (halving the step
    /// when it fails), a convex vertex, the seed (a closed seam), a touch point leaving its
    /// element, a junction, the curvature limit.
    fn march_step(&mut self, m: &mut March) -> Flow {
        let diag = self.model.diagonal();
        if m.points.len() >= MAX_POINTS {
            return Flow::End(SeamEnd::Open(OpenReason::PointBudgetExhausted));
        }
        let Some((xn, tn, iterations)) = self.step(&m.sys, &m.x, &m.t, m.h) else {
            self.stats.corrector_failures += 1;
            m.h *= 0.5;
            if m.h < MIN_STEP_REL_DIAGONAL * diag {
                // The step keeps failing where the ball osculates a touched face or curved
                // edge to the accuracy (its radius of curvature towards the ball within the
                // accuracy of r: a hole's rim whose osculating circle lies on the ball's
                // sphere): the system is singular there, and that is the seam's curvature
                // limit, as `curvature_end` finds where a step passes it.
                if let Some(i) = (0..3).find(|&i| self.osculates(&m.triplet, i, &m.x)) {
                    return Flow::End(SeamEnd::CurvatureLimit {
                        segment: m.triplet[i],
                    });
                }
                // Nearly so, where the system is too near singular for the step to get
                // within the accuracy: the osculating ball itself, solved for.
                if let Some((i, y)) = self.osculating_near(&m.sys, m.solid, &m.x) {
                    m.points.push(self.seam_point(&m.sys, &y));
                    return Flow::End(SeamEnd::CurvatureLimit {
                        segment: m.triplet[i],
                    });
                }
                // Two touch points closing in on a vertex both their elements reach (a rib's
                // two feet running into its tip: OCCT's sample bottle's thread): the system
                // turns singular as they meet, and the steps may shrink to nothing before
                // it; they meet at a pinch.
                let x = m.x.clone();
                if let Some(end) = self.end_in_pinch(m, &x) {
                    return Flow::End(end);
                }
                return Flow::End(SeamEnd::Open(OpenReason::StepSizeUnderflow));
            }
            return Flow::Next;
        };
        if let Some(end) = self.end_at_vertex(m, &xn) {
            return Flow::End(end);
        }
        if let Some(end) = self.close_at_seed(m, &xn) {
            return Flow::End(end);
        }
        // A touch point that leaves its element is handed over to the next one across the
        // edge it crossed (xn itself, off the element, is not output).
        if let Some(i) = (0..3).find(|&i| {
            !self.stays_on(m.triplet[i], slot(&m.x, i), slot(&xn, i))
                && !self.beyond_convex_edge_within_gap(m.triplet[i], slot(&xn, i))
        }) {
            // A touch point on a face grazing an edge it runs along, whose step ends on the
            // face but whose chord crosses the edge's arc (see `grazes_edge_run_along`): the
            // step is too long to tell a graze from a jump; shorter, the chord dips less.
            if self.grazing_step(m.triplet[i], slot(&xn, i))
                && 0.5 * m.h >= MIN_STEP_REL_DIAGONAL * diag
            {
                m.h *= 0.5;
                return Flow::Next;
            }
            return self.cross_over(m, i);
        }
        // Another part of the boundary closer than r: a junction between x and xn.
        if let Some(flow) = self.junction_end(m, &xn) {
            return flow;
        }
        if self.step_past_limit_too_long(m, &xn) {
            m.h *= 0.5;
            return Flow::Next;
        }
        if let Some(end) = self.curvature_end(m, &xn) {
            return Flow::End(end);
        }
        m.points.push(self.seam_point(&m.sys, &xn));
        self.at_start = false;
        m.in_place = 0;
        m.travel += v3(&xn).distance(v3(&m.x));
        m.x = xn;
        m.t = tn;
        m.h = if iterations <= FAST_CONVERGENCE_ITER {
            (m.h * STEP_GROWTH).min(MAX_STEP_REL_DIAGONAL * diag)
        } else {
            m.h * STEP_SHRINK
        };
        Flow::Next
    }

    /// The pinch at the seam point `x` of the march ([`Self::pinch`]), when there is one:
    /// its ball is the march's last point, and the end is returned.
    pub(super) fn end_in_pinch(&mut self, m: &mut March, x: &DVector<f64>) -> Option<SeamEnd> {
        let (end, y) = self.pinch(&m.sys, &m.triplet, x)?;
        m.points.push(self.seam_point(&m.sys, &y));
        Some(end)
    }

    /// Back to a convex vertex: `r` returns to zero at `xn`. (Away from a vertex with a touch
    /// point off its element, the step overshot a hand-over or a junction: that is left to
    /// those.)
    fn end_at_vertex(&mut self, m: &mut March, xn: &DVector<f64>) -> Option<SeamEnd> {
        if !(xn[3] <= self.opts.accuracy && m.points.len() > 1) {
            return None;
        }
        let (xe, v) = self.land_at_vertex(&m.sys, xn.clone());
        let off = (0..3).any(|i| !self.on_segment(m.triplet[i], slot(xn, i)));
        if v.is_none() && off {
            return None;
        }
        m.points.push(self.seam_point(&m.sys, &xe));
        Some(v.map_or_else(
            || SeamEnd::Open(OpenReason::ZeroRadiusAwayFromVertex),
            SeamEnd::Vertex,
        ))
    }

    /// Back at the seed: a closed seam. The ball decides (its centre and radius), not the
    /// elements: a seed next to an edge may hand its touch point onto that edge at once and
    /// never back (a reflex circle's seam round a Motor-c part's boss went round 680 times,
    /// to the point budget, on the circle and not the face it started on). The seed's ball is
    /// the last point, on the elements touched now.
    fn close_at_seed(&mut self, m: &mut March, xn: &DVector<f64>) -> Option<SeamEnd> {
        let acc = self.opts.accuracy;
        let xs = m.close_at?;
        let step = v3(xn).distance(v3(&m.x));
        // The radius is compared where the chord passes the seed's centre: r may change along
        // the seam as fast as the centre moves, and the seed lies anywhere on the step (a seam
        // round a hub under a slot passed its seed 0.9 mm of radius from the step's end, 1e-3
        // mm from its chord, and went round 99 times to the point budget).
        let along = along_chord(v3(xs), v3(&m.x), v3(xn));
        let r_there = m.x[3] + along * (xn[3] - m.x[3]);
        let back = m.travel > 3.0 * step
            && to_chord(v3(xs), v3(&m.x), v3(xn)) <= 0.05 * step + SAME_PLACE_REL_ACCURACY * acc
            && (xs[3] - r_there).abs() <= 0.05 * step + SAME_PLACE_REL_ACCURACY * acc;
        if !back {
            return None;
        }
        // The seed's ball, on the elements touched now (their parameters at its touch
        // points), so the seam's last point is its first (where a parameter is not found, the
        // seam closes from its last point).
        let mut y = Some(xs.clone());
        for k in (0..3).filter(|&k| m.triplet[k] != m.first[k]) {
            let s = self.start_params(m.triplet[k], v3(xs), slot(&m.x, k));
            if let (Some(y), Some(s)) = (y.as_mut(), s) {
                y[4 + 2 * k] = s.0;
                y[5 + 2 * k] = s.1;
            } else {
                y = None;
            }
        }
        if let Some(y) = y {
            m.points.push(self.seam_point(&m.sys, &y));
        }
        Some(SeamEnd::Closed)
    }

    /// Touch point `i` left its element between `m.x` and the next point: hands it over, or
    /// ends the march where it cannot be.
    fn cross_over(&mut self, m: &mut March, mut i: usize) -> Flow {
        match self.hand_over(&m.triplet, &mut i, &m.x, &m.t, m.h) {
            Ok((to, xc, xnew)) if handed_back(m, i, to) => self.stay_on_vertex(m, i, to, &xc, xnew),
            Ok((to, crossing, xnew)) => self.continue_on(m, i, to, &crossing, xnew),
            // The step left the face away from its edges: no crossing was there to find (the
            // corrector jumped to another stretch of the seam, whose tangent happened to pass
            // the turn check, while the steps towards it turn too fast): the step is too long.
            Err((HandOverError::Stop(OpenReason::LeftFaceAwayFromEdges { .. }), _))
                if 0.5 * m.h >= MIN_STEP_REL_DIAGONAL * self.model.diagonal() =>
            {
                m.h *= 0.5;
                Flow::Next
            }
            // Likewise where no probe of the step saw the touch point leave, the ones past
            // the last point on it failing (their tangent turning too far: the step's end
            // jumped along a seam that curves round a glyph's stroke, on the lettering of a
            // KiCad resistor), and no hand-over was found at that last point.
            // (Unless the march ends properly there all the same: at a junction, a pinch, a
            // curvature limit found at that last point.)
            Err((HandOverError::Unbracketed(why), xc)) => {
                let mut ended = m.clone();
                let flow = self.end_at_crossing(&mut ended, HandOverError::Stop(why), &xc);
                if matches!(flow, Flow::End(SeamEnd::Open(_)))
                    && 0.5 * m.h >= MIN_STEP_REL_DIAGONAL * self.model.diagonal()
                {
                    m.h *= 0.5;
                    return Flow::Next;
                }
                *m = ended;
                flow
            }
            Err((e, xc)) => self.end_at_crossing(m, e, &xc),
        }
    }

    /// The touch point sits at a vertex while the normal turns (it was just handed the other
    /// way): it is on the vertex (a corner of two reflex edges, or of faceted faces meeting
    /// at small angles), not on either neighbour; or, handed from a face onto one of its
    /// edges and back, its path grazes that edge and it runs on along the face.
    fn stay_on_vertex(
        &mut self,
        m: &mut March,
        i: usize,
        to: Element,
        xc: &DVector<f64>,
        xnew: DVector<f64>,
    ) -> Flow {
        let from = m.triplet[i];
        match self.onto_vertex(&m.triplet, i, xc, &m.t) {
            Some((v, xv)) => {
                m.handovers.push(Handover {
                    point: m.points.len(),
                    from,
                    to: v,
                });
                self.switch_to(m, i, v, xv)
            }
            None => {
                // Two faces across a smooth edge: the touch point runs along the edge (the
                // one it is at: the halves of a split cylinder share two). Stay on this face,
                // counting points within the accuracy (plus the face's gap) past that edge as
                // on it; where it leaves the face, it leaves across another edge
                // (`next_from_face`). Where the file's gap there lets the faces meet at a
                // slight convex crease (for the ball), the same ball's touch point on either
                // face lies on the other's side, as far as the two touch points are apart:
                // that far too.
                if let (Element::Face(f), Element::Face(g)) = (from, to) {
                    let at = self.touches(&m.triplet, xc)[i];
                    let e = at.and_then(|p| self.smooth_edge_between_near(f, g, p));
                    if let Some(e) = e.filter(|&e| !self.runs_along(f, e)) {
                        let margin =
                            self.crease_margin(f, g, at, self.touches(&m.triplet, &xnew)[i], xc[3]);
                        self.along.push((f, e, margin));
                        return Flow::Next;
                    }
                }
                // Handed from a face onto a reflex edge of it and straight back: the touch
                // point's path on the face grazes the edge (a boss's foot circle tangent to
                // it). Back on the face, points within the accuracy of that edge count as on
                // the face.
                if let (Element::Edge(e), Element::Face(f)) = (from, to) {
                    if self.model.edges[e].faces.contains(&f) && !self.runs_along(f, e) {
                        self.along.push((f, e, 0.0));
                        m.handovers.push(Handover {
                            point: m.points.len(),
                            from,
                            to,
                        });
                        return self.switch_to(m, i, to, xnew);
                    }
                }
                // Two touch points meeting at the vertex the touch point is handed about at
                // (a reflex edge and another element ending there): a pinch.
                if let Some(end) = self.end_in_pinch(m, xc) {
                    return Flow::End(end);
                }
                Flow::End(SeamEnd::Open(OpenReason::Oscillates { from, to }))
            }
        }
    }

    /// How far past the smooth edge between faces `f` and `g` a touch point on `f` that was
    /// just handed to `g` and back still counts as on `f`: as far as the ball's touch points
    /// on the two, `a` and `b`, are apart, where the file's gap there tilts one face against
    /// the other (a ball tilted by δ off one face's normal sinks `r·(1 − cos δ)` into the
    /// other, admitted up to the gap `g₀`: at most `√(2·g₀·r)`); else nothing.
    fn crease_margin(&self, f: usize, g: usize, a: Option<DVec3>, b: Option<DVec3>, r: f64) -> f64 {
        let gap = self.face_gap[f].max(self.face_gap[g]);
        match (a, b) {
            (Some(a), Some(b)) if gap > 0.0 => a.distance(b).min((2.0 * gap * r).sqrt()),
            _ => 0.0,
        }
    }

    /// A hand-over of touch point `i` to `to` at `crossing` (`xnew`: the same ball on the new
    /// triplet): unless a junction comes first or two touch points meet there, the march
    /// goes on from `xnew`.
    fn continue_on(
        &mut self,
        m: &mut March,
        i: usize,
        to: Element,
        crossing: &DVector<f64>,
        xnew: DVector<f64>,
    ) -> Flow {
        // The crossing point must itself be medial: a junction may come first, or the
        // curvature limit of a touched segment.
        if let Some(flow) = self.junction_end(m, crossing) {
            return flow;
        }
        if let Some(end) = self.limit_within_step(m, crossing) {
            return Flow::End(end);
        }
        // Onto a vertex that another touch point is reaching too (two reflex edges running
        // into it): the two meet there, a pinch, before the touch point can stay on it.
        if let Element::Vertex(v) = to {
            let at = self.touches(&m.triplet, crossing);
            let others_reach = (0..3).any(|k| {
                k != i
                    && at[k].is_some_and(|p| {
                        p.distance(self.model.vertices[v].point)
                            <= REACH_REL_ACCURACY * self.opts.accuracy
                    })
            });
            if others_reach {
                if let Some(end) = self.end_in_pinch(m, crossing) {
                    return Flow::End(end);
                }
            }
        }
        let nt = new_triplet(&m.triplet, i, to);
        if self.coincident(&nt, &xnew, true) {
            return Flow::End(self.merged_end(m, i, to, crossing, &xnew));
        }
        m.handovers.push(Handover {
            point: m.points.len(),
            from: m.triplet[i],
            to,
        });
        self.switch_to(m, i, to, xnew)
    }

    /// Two touch points coincide after handing touch point `i` to `to`. When they are on one
    /// part of the boundary (faces and the reflex edges and vertices joining them, across
    /// which a touch point moves on), the ball osculates it there, like a face touched twice
    /// at its curvature limit, and the seam ends at the crossing; otherwise it ends open.
    fn merged_end(
        &mut self,
        m: &mut March,
        i: usize,
        to: Element,
        crossing: &DVector<f64>,
        xc: &DVector<f64>,
    ) -> SeamEnd {
        let nt = new_triplet(&m.triplet, i, to);
        let at = |k: usize| sys_point(self.model, nt[k], slot(xc, k));
        let merged = (0..3).find(|&k| {
            k != i
                && self.groups.of(nt[k]) == self.groups.of(to)
                && matches!((at(k), at(i)), (Some(a), Some(b)) if a.distance(b) <= MERGED_TOUCH_REL_RADIUS * xc[3])
        });
        match merged {
            // Where they meet at a vertex both reach (a floor and the reflex edge at the foot
            // of a wall's end face, where a fillet along the wall runs into that end), the
            // meeting is located exactly there: a pinch, where the sheet's skeletal edge to
            // the vertex starts. The crossing is only as near as the hand-over's step.
            // But where two touch points on one element had already met on the way (a
            // reflex edge touched twice, its two touch points meeting where its curvature
            // peaks, a step before both reach the end of its arc of normals together: the
            // Voron Dragon mount's), that element's curvature limit comes first; the balls
            // past it, both touches at one point, are no seam points.
            Some(_) => match self.end_in_pinch(m, crossing) {
                Some(end) => end,
                None => match self.limit_before_crossing(m, crossing) {
                    Some(end) => end,
                    None => {
                        m.points.push(self.seam_point(&m.sys, crossing));
                        SeamEnd::CurvatureLimit { segment: to }
                    }
                },
            },
            // Elsewhere they meet at the vertex the touch point was handed over at: a pinch.
            // Or two touch points on one element had already met on the way to the crossing
            // (a pin's tip cut by a plane, its hyperbola edge touched twice while the third
            // touch point runs to the plane's edge: FreeCAD's TSM headers): the seam reaches
            // that element's curvature limit before the crossing, located as after a step.
            None => match self.end_in_pinch(m, crossing) {
                Some(end) => end,
                None => self
                    .limit_before_crossing(m, crossing)
                    .unwrap_or(SeamEnd::Open(OpenReason::CoincideAfterHandover {
                        from: m.triplet[i],
                        to,
                    })),
            },
        }
    }

    /// Moves touch point `i` onto `to` and goes on from `xnew` (the ball on the new triplet),
    /// along the tangent there oriented like the last one.
    fn switch_to(&mut self, m: &mut March, i: usize, to: Element, xnew: DVector<f64>) -> Flow {
        // A touch point handed on and on without the seam moving (between a vertex and its
        // edges, each hand-over undoing another) is stuck there: end rather than loop.
        m.in_place += 1;
        if m.in_place > MAX_HANDOVERS_IN_PLACE {
            return Flow::End(SeamEnd::Open(OpenReason::Oscillates {
                from: m.triplet[i],
                to,
            }));
        }
        let from = m.triplet[i];
        m.triplet[i] = to;
        m.sys = MedialSystem::new(m.triplet.to_vec());
        m.points.push(self.seam_point(&m.sys, &xnew));
        let mut d = DVector::zeros(10);
        d.rows_mut(0, 3).copy_from(&m.t.rows(0, 3));
        let Some(tc) = self.tangent(&m.sys, &xnew, &d) else {
            // Where the ball has shrunk to nothing the seam is at a convex vertex (a touch
            // point crossed a smooth edge into it, onto the face another one is on). The seam
            // ends on the elements it ran along: the ball there (r = 0, every touch point at
            // the vertex) is on both, and the hand-over into the vertex is no part of it (it
            // would name the face another touch point is on twice).
            if xnew[3] <= self.opts.accuracy {
                if let Some(v) = self.vertex_reached(&m.sys.segments, v3(&xnew)) {
                    m.handovers.pop();
                    m.triplet[i] = from;
                    m.sys = MedialSystem::new(m.triplet.to_vec());
                    return Flow::End(SeamEnd::Vertex(v));
                }
            }
            return Flow::End(SeamEnd::Open(OpenReason::SingularTangentAfterHandover));
        };
        m.travel += v3(&xnew).distance(v3(&m.x));
        m.x = xnew;
        m.t = tc;
        Flow::Next
    }

    /// A hand-over failed at the crossing point `xc`: the march ends at a junction before it
    /// (the step that left the element may have passed one), or at the crossing.
    fn end_at_crossing(&mut self, m: &mut March, e: HandOverError, xc: &DVector<f64>) -> Flow {
        if let Some(flow) = self.junction_end(m, xc) {
            return flow;
        }
        // Where two touch points meet at a vertex, the seam ends at that pinch.
        // So too where the next face bends into the ball too tightly to take the touch
        // point (`Osculates`) at a vertex where two touch points meet: a blend tapering to a
        // point between two faces tangent there, which the touch points on them reach
        // together (the Voron Manta mount's: its radius of curvature 0.26 at the tip, the
        // ball's 0.75); the ball is not that face's centre of curvature.
        if let HandOverError::Stop(_) | HandOverError::Osculates(_) = e {
            if let Some(end) = self.end_in_pinch(m, xc) {
                return Flow::End(end);
            }
        }
        // Two touch points on one element that met before the crossing: the curvature limit
        // (the hand-over past it cannot find the ball: its two touch points have swapped).
        if let HandOverError::Stop(OpenReason::NoSeamPointAfterHandover { .. }) = e {
            if let Some(end) = self.limit_before_crossing(m, xc) {
                return Flow::End(end);
            }
        }
        // The ball at the crossing already pokes through a segment it touches (its radius of
        // curvature there below `r`), where the next segment is too tight to take the touch
        // point: that segment's curvature limit came first, within the step, as where the
        // hand-over is made (`continue_on`).
        if let HandOverError::Osculates(_) = e {
            if let Some(end) = self.limit_within_step(m, xc) {
                return Flow::End(end);
            }
        }
        // The element handed to may come closer than `r` before the crossing by less than
        // the accuracy (the intrusion test cannot see it), next to a vertex where it meets
        // the element left at a kink: the crossing then stands for the junction with it,
        // which the new system cannot reach (its ball is another one).
        if let HandOverError::Stop(OpenReason::NoSeamPointAfterHandover { from, to, .. }) = e {
            if let Some(flow) = self.junction_with_next(m, from, to, xc) {
                return flow;
            }
        }
        // Handed onto the part of the boundary another touch point is on, where the two are
        // already one place by `verify`'s separation: they meet there, the ball osculating
        // that part of the boundary (the new system is singular, its solve fails) — the
        // seam's curvature limit, as `merged_end` finds where the solve still converges.
        // The touch point handed on is at the crossing, on `from`'s border (within the trim
        // test's tolerance, or just past it): only the others are held to their elements.
        // Handed on from a vertex, the touch point is at that vertex, and the two meet there:
        // the vertex is the segment named (on the Prusa adapter a touch point at a vertex
        // and one on the straight edge ending there, 0.013 mm apart where the edge's curve
        // ends 5.9e-4 mm off the vertex, were named that edge's curvature limit, which
        // neither checker found).
        if let HandOverError::Stop(OpenReason::NoSeamPointAfterHandover { from, to, .. }) = e {
            let others_on = (0..3)
                .filter(|&k| m.triplet[k] != from)
                .all(|k| self.on_segment(m.triplet[k], slot(xc, k)));
            if self.merges_at_crossing(&m.triplet, from, to, &m.x, xc)
                && others_on
                && self.ball_is_empty(m.solid, xc)
            {
                m.points.push(self.seam_point(&m.sys, xc));
                let segment = match from {
                    Element::Vertex(_) => from,
                    _ => to,
                };
                return Flow::End(SeamEnd::CurvatureLimit { segment });
            }
        }
        // A crossing where the ball has shrunk to nothing: back at a convex vertex whose
        // faces meet there at a small angle (r has its minimum, about 0, at the vertex, and the
        // step passed it).
        if xc[3] <= self.opts.accuracy {
            if let (xe, Some(v)) = self.land_at_vertex(&m.sys, xc.clone()) {
                m.points.push(self.seam_point(&m.sys, &xe));
                return Flow::End(SeamEnd::Vertex(v));
            }
        }
        // A crossing within a few accuracies of nothing, by the trim test's tolerance: where a
        // fin is folded to its tip (interior angle 0), the ball's radius falls as the square
        // of the distance to the tip's vertex, and every touch point stands within `r` of an
        // edge of its face long before the seam is within reach of the vertex. The seam ends
        // at the convex vertex ahead that its elements meet, the rest of it within `r/4` of
        // the chord there.
        // (A curvature limit there stays one.)
        let osculates = matches!(e, HandOverError::Osculates(_));
        if xc[3] <= TIP_REL_ACCURACY * self.opts.accuracy && !osculates {
            if let Some(v) = self.vertex_ahead(&m.sys.segments, xc, &m.t) {
                m.points.push(self.seam_point(&m.sys, xc));
                let xv = self.on_vertex(&m.sys, xc.clone(), v);
                m.points.push(self.seam_point(&m.sys, &xv));
                return Flow::End(SeamEnd::Vertex(v));
            }
        }
        // The crossing point itself is a seam point when it is medial.
        if self.is_medial(&m.triplet, xc) {
            m.points.push(self.seam_point(&m.sys, xc));
        }
        Flow::End(match e {
            HandOverError::Osculates(seg) => SeamEnd::CurvatureLimit { segment: seg },
            HandOverError::Unbracketed(why) => SeamEnd::Open(why),
            HandOverError::Stop(why) => SeamEnd::Open(why),
        })
    }

    /// The junction of the seam with `to`, the element its touch point on `from` was handed
    /// to at the crossing `xc` without a seam point: the 4-segment system with `to` solved
    /// from there — from the element the touch point was on just before, when `from` is a
    /// vertex it was handed to at the last point (where two reflex edges meet at a kink
    /// towards the ball, both touch the balls near the vertex: the junction is where they
    /// are at one distance, and the seam ran past it to the vertex). The march ends at that
    /// junction, or passes on where `to` continues the element (see `tangent_across`);
    /// points past the junction are dropped.
    fn junction_with_next(
        &mut self,
        m: &mut March,
        from: Element,
        to: Element,
        xc: &DVector<f64>,
    ) -> Option<Flow> {
        let i = m.triplet.iter().position(|&s| s == from)?;
        if m.triplet.contains(&to) {
            return None;
        }
        let b = v3(xc);
        let (triplet, x, undo) = match (from, m.handovers.last()) {
            (Element::Vertex(_), Some(h)) if h.to == from && h.point + 1 >= m.points.len() => {
                let prev = h.from;
                if prev == to || m.triplet.contains(&prev) {
                    return None;
                }
                let s = self.start_params(prev, b, [f64::NAN; 2])?;
                let mut x = xc.clone();
                x[4 + 2 * i] = s.0;
                x[5 + 2 * i] = s.1;
                (new_triplet(&m.triplet, i, prev), x, true)
            }
            (Element::Vertex(_), _) => return None,
            _ => (m.triplet, xc.clone(), false),
        };
        let (triplet, jx, kept) = self.junction_before_handovers(m, triplet, &x, to, i, true)?;
        if undo {
            m.handovers.pop();
        }
        self.back_to(m, triplet, &jx, kept);
        let meeting = self.meeting_at(&triplet, to, jx, &m.t);
        Some(self.go_on_from(m, meeting))
    }

    /// The junction with `to` of the seam on `triplet` (its ball `x`: the march's last point
    /// or the crossing past it): first on `triplet` (where `as_is`), then with hand-overs of
    /// its other touch points than `i` made at the last two points undone. Two events that
    /// close together (a touch point handed from a vertex onto its edge, then the junction
    /// with the next edge of a kinked outline across the stroke) may have been located in
    /// the wrong order: the junction touches the element handed from, and must precede that
    /// hand-over along the seam. Returns the junction's triplet, the 4-segment solution and
    /// how many of the march's points precede it.
    fn junction_before_handovers(
        &mut self,
        m: &March,
        triplet: [Element; 3],
        x: &DVector<f64>,
        to: Element,
        i: usize,
        as_is: bool,
    ) -> Option<([Element; 3], DVector<f64>, usize)> {
        let b = v3(x);
        let s4 = self.start_params(to, b, [f64::NAN; 2])?;
        let recent: Vec<(usize, Element, usize)> = (0..3)
            .filter(|&k| k != i)
            .filter_map(|k| {
                let h = m.handovers.iter().rev().find(|h| h.to == triplet[k])?;
                (h.point + 2 >= m.points.len() && h.from != to && !triplet.contains(&h.from))
                    .then_some((k, h.from, h.point))
            })
            .collect();
        let first = if as_is { 0 } else { 1 };
        let mut variants = (first..1usize << recent.len()).filter_map(|mask| {
            let (mut t3, mut y) = (triplet, x.clone());
            let mut before = usize::MAX;
            for (bit, &(k, prev, at)) in recent.iter().enumerate() {
                if mask & (1 << bit) != 0 {
                    let s = self.start_params(prev, b, [f64::NAN; 2])?;
                    t3[k] = prev;
                    y[4 + 2 * k] = s.0;
                    y[5 + 2 * k] = s.1;
                    before = before.min(at);
                }
            }
            Some((t3, y, before))
        });
        variants.find_map(|(t3, y, before)| {
            let jx = self
                .locate_junction(&t3, &y, to, [s4.0, s4.1])
                .filter(|jx| self.ball_is_empty(m.solid, jx))?;
            // The points past the junction (along the seam) are dropped.
            let (j, dir) = (v3(&jx), v3(&m.t));
            let kept = m.points.len()
                - m.points
                    .iter()
                    .skip(1)
                    .rev()
                    .take_while(|p| (centre_of(p) - j).dot(dir) > 0.0)
                    .count();
            (kept <= before).then_some((t3, jx, kept))
        })
    }

    /// True when, at the crossing `xc`, a touch point on `from` (the one being handed on) and
    /// another on `to` or on its part of the boundary are one place by `verify`'s separation
    /// or, closing in on each other since the last point `x`, within
    /// [`MERGING_SEPARATIONS`] of it: the centre is then within about the square of that
    /// many accuracies of where they meet (the separation `√(8·r·a)` is the distance of two
    /// touch points whose ball is `a` from its curvature limit). In a file with gaps `a` is
    /// the accuracy plus the gap about `from` and `to`: an edge or vertex written off its
    /// neighbours by the gap puts a kink of about that size between them.
    fn merges_at_crossing(
        &self,
        triplet: &[Element; 3],
        from: Element,
        to: Element,
        x: &DVector<f64>,
        xc: &DVector<f64>,
    ) -> bool {
        let (before, now) = (self.touches(triplet, x), self.touches(triplet, xc));
        let gap = self.element_gap(from).max(self.element_gap(to));
        let sep = crate::medial::verify::separation(xc[3], self.opts.accuracy + gap);
        let apart = |at: &[Option<DVec3>; 3], i: usize, k: usize| match (at[i], at[k]) {
            (Some(a), Some(b)) => a.distance(b),
            _ => f64::NAN,
        };
        (0..3).any(|i| {
            triplet[i] == from
                && (0..3).any(|k| {
                    let d = apart(&now, i, k);
                    k != i
                        && self.groups.of(triplet[k]) == self.groups.of(to)
                        && (d <= sep
                            || (d <= MERGING_SEPARATIONS * sep && apart(&before, i, k) > d))
                })
        })
    }

    /// The junction between `m.x` and `to`, if another part of the boundary comes closer than
    /// `r` there: its point ends the march. Where that part is the smooth continuation of a
    /// touched face or edge, the touch point passes onto it there instead, and the march
    /// goes on.
    fn junction_end(&mut self, m: &mut March, to: &DVector<f64>) -> Option<Flow> {
        let meeting = self.junction_between(&m.triplet, m.solid, &m.x, to, &m.t)?;
        // No junction on the triplet as it is: perhaps on the one before a hand-over made
        // just before (see `junction_before_handovers`).
        if let Meeting::End(SeamEnd::Open(OpenReason::NoJunction { element }), _) = meeting {
            let x = m.x.clone();
            if let Some((triplet, jx, kept)) =
                self.junction_before_handovers(m, m.triplet, &x, element, usize::MAX, false)
            {
                self.back_to(m, triplet, &jx, kept);
                let meeting = self.meeting_at(&triplet, element, jx, &m.t);
                return Some(self.go_on_from(m, meeting));
            }
        }
        Some(self.go_on_from(m, meeting))
    }

    /// The march back at the junction `jx` on `triplet`, of which its first `kept` points
    /// are before: the rest, and hand-overs made there, are dropped.
    fn back_to(&self, m: &mut March, triplet: [Element; 3], jx: &DVector<f64>, kept: usize) {
        m.points.truncate(kept);
        m.handovers.retain(|h| h.point < kept);
        m.triplet = triplet;
        m.sys = MedialSystem::new(triplet.to_vec());
        m.x = jx.rows(0, 10).into_owned();
    }

    /// The march at what it met: its end (at the junction's point, when located), or on,
    /// with the touch point passed onto the segment that continues a touched one.
    fn go_on_from(&mut self, m: &mut March, meeting: Meeting) -> Flow {
        let (i, to, x) = match meeting {
            Meeting::End(end, jx) => {
                if let Some(jx) = jx {
                    m.points
                        .push(self.seam_point(&m.sys, &jx.rows(0, 10).into_owned()));
                }
                return Flow::End(end);
            }
            Meeting::Across { i, to, x } => (i, to, x),
        };
        // As at a hand-over, the ball is output once, on the new triplet.
        let mut xnew = x.rows(0, 10).into_owned();
        xnew[4 + 2 * i] = x[10];
        xnew[5 + 2 * i] = x[11];
        m.handovers.push(Handover {
            point: m.points.len(),
            from: m.triplet[i],
            to,
        });
        self.switch_to(m, i, to, xnew)
    }

    /// The touch points of `y` on `triplet`.
    pub(super) fn touches(&self, triplet: &[Element; 3], y: &DVector<f64>) -> [Option<DVec3>; 3] {
        std::array::from_fn(|i| sys_point(self.model, triplet[i], slot(y, i)))
    }

    /// The ordered pairs of slots `(i, k)`, `i ≠ k`, whose touch points of `y` on `triplet`
    /// are one place by `verify`'s separation `√(8·r·a)` (both defined).
    pub(super) fn one_place_pairs(
        &self,
        triplet: &[Element; 3],
        y: &DVector<f64>,
    ) -> impl Iterator<Item = (usize, usize)> {
        let at = self.touches(triplet, y);
        let sep = crate::medial::verify::separation(y[3], self.opts.accuracy);
        (0..3)
            .flat_map(|i| (0..3).map(move |k| (i, k)))
            .filter(move |&(i, k)| {
                i != k && matches!((at[i], at[k]), (Some(a), Some(b)) if a.distance(b) <= sep)
            })
    }

    /// The slot `j < i` touching the same element as slot `i` whose touch point and slot
    /// `i`'s, at `before` on the last point, have met or passed through each other at `y`.
    pub(super) fn merged_with(
        &self,
        triplet: &[Element; 3],
        before: &[Option<DVec3>; 3],
        y: &DVector<f64>,
        i: usize,
    ) -> Option<usize> {
        let now = self.touches(triplet, y);
        (0..i).find(|&j| {
            triplet[j] == triplet[i]
                && match (before[i], before[j], now[i], now[j]) {
                    (Some(a), Some(b), Some(c), Some(d)) => {
                        (c - d).dot(a - b) <= 0.0 || c.distance(d) <= MERGED_TOUCH_REL_RADIUS * y[3]
                    }
                    _ => true,
                }
        })
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
        touches_meet(
            self.model,
            triplet,
            x,
            MERGED_TOUCH_REL_RADIUS * x[3],
            pairs,
        )
    }

    /// One predictor–corrector step of length `h` from `x` along the unit tangent `t`: the new
    /// point, its tangent (oriented along `t`) and the corrector's iterations. `None` when the
    /// corrector fails, the radius goes negative from a point that already had r ≤ 0, or the
    /// seam turns by more than [`MAX_TURN_RAD`] (step control by seam curvature), or a touch
    /// point on an edge runs round it by more than [`MAX_TOUCH_TURN_RAD`] (the corrector
    /// jumped to another foot of the ball on that edge).
    pub(super) fn step(
        &mut self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> Option<(DVector<f64>, DVector<f64>, usize)> {
        let pred = x + t * h;
        let pred_r = pred[3];
        // Corrector: F = 0 and t_B·(B − B_pred) = 0, the hyperplane across the centre's
        // direction (t is scaled so that t_B is a unit vector): the step is `h` of centre
        // travel. (Across the whole tangent, where a touch point's parameters turn fast, as
        // past a sphere's pole, the hyperplane would measure the parameters instead, and
        // the corrector jump between the places the seam crosses it.)
        let mut row = DVector::zeros(t.len());
        row.rows_mut(0, 3).copy_from(&t.rows(0, 3));
        let c = row.dot(&pred);
        let (sol, jacobian) = solve_keeping_jacobian(
            |y| sys.eval_with_row(self.model, y, &row, c),
            pred,
            &self.solve_opts(),
        );
        self.stats.newton_iterations += sol.iterations;
        // A negative radius is an overshoot past a convex vertex (landed on r = 0 there)
        // only where the predictor heads below zero too; from a ball that predicts r > 0 it
        // is the mirror ball on the other side of the boundary (where a surface's normal
        // flips, past a sphere's pole), not the seam.
        let mirror = sol.x[3] < -self.opts.accuracy && (x[3] <= 0.0 || pred_r > 0.0);
        // A predictor heading below r = 0 from a ball of r > 0 whose corrector lands on a
        // bigger ball has jumped: past a convex vertex the ball shrinks to nothing, and
        // where the seam only dips towards r = 0 (passing a convex edge close by, a face
        // nearly meeting it), the corrector lands on some other stretch of it beyond the dip.
        let jumped = pred_r < 0.0 && x[3] > 0.0 && sol.x[3] > x[3];
        if sol.status != SolveStatus::Converged || mirror || jumped {
            return None;
        }
        if self.touch_runs_round_an_edge(sys, x, &sol.x) {
            return None;
        }
        // The system's rows of the corrector's last Jacobian are the ones at the landed
        // point: the tangent there needs no new evaluation.
        let tn = match jacobian {
            Some(j) => tangent_from(j, t)?,
            None => self.tangent(sys, &sol.x, t)?,
        };
        let turn = v3(t).angle_between(v3(&tn));
        (turn <= MAX_TURN_RAD).then_some((sol.x, tn, sol.iterations))
    }

    /// True when, from seam point `x` to `y`, a touch point on an edge moved along it so far
    /// that the edge's tangent turned by more than [`MAX_TOUCH_TURN_RAD`].
    fn touch_runs_round_an_edge(
        &self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        y: &DVector<f64>,
    ) -> bool {
        sys.segments.iter().enumerate().any(|(k, seg)| {
            let Element::Edge(e) = *seg else {
                return false;
            };
            let curve = &self.model.edges[e].curve;
            let a = crate::geom::eval_curve(curve, slot(x, k)[0]).d1;
            let b = crate::geom::eval_curve(curve, slot(y, k)[0]).d1;
            a.length() > 0.0 && b.length() > 0.0 && a.angle_between(b) > MAX_TOUCH_TURN_RAD
        })
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
                tol: self.opts.solver_tol,
                max_iter: MAX_CENTRE_STEP_ITER,
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
        tangent_from(a, dir)
    }

    /// Lands a seam point that reached `r ≈ 0` exactly on `r = 0` (the corrector may have
    /// overshot to a negative radius) by replacing the arclength equation with `r = 0`, and
    /// finds the vertex there. The ball of radius 0 is that vertex: the point returned is
    /// put on it, each touch point there. (Where two of the elements are tangent along a
    /// line through the vertex — a fold's fin, its faces a plane and a cylinder lying on it —
    /// the system held at `r = 0` is singular along that line, and its solution stopped
    /// 2.9e-5 mm past the fin's tip on MSOP-10's leads, five times the accuracy.)
    pub(super) fn land_at_vertex(
        &mut self,
        sys: &MedialSystem,
        xn: DVector<f64>,
    ) -> (DVector<f64>, Option<usize>) {
        let xe = self.solve_holding(sys, &xn, 3, 0.0).unwrap_or(xn);
        let v = self.vertex_reached(&sys.segments, v3(&xe));
        let xe = match v {
            Some(v) => self.on_vertex(sys, xe, v),
            None => xe,
        };
        (xe, v)
    }

    /// The seam point `x` of `sys` moved onto vertex `v` with radius 0, each touch point's
    /// parameters those of the vertex on its element (from `x`'s).
    /// (`x` as it is where a face's parameters there are not found.)
    fn on_vertex(&self, sys: &MedialSystem, x: DVector<f64>, v: usize) -> DVector<f64> {
        let p = self.model.vertices[v].point;
        let mut y = x.clone();
        for (i, seg) in sys.segments.iter().enumerate() {
            let k = 4 + 2 * i;
            match *seg {
                Element::Face(f) => {
                    let surface = &self.model.faces[f].surface;
                    match project_point(surface, p, Some((x[k], x[k + 1]))) {
                        Some(uv) => (y[k], y[k + 1]) = uv,
                        None => return x,
                    }
                }
                Element::Edge(e) => {
                    y[k] = crate::geom::nearest_on_edge(self.model, e, p, Some(x[k])).0;
                }
                Element::Vertex(_) => {}
            }
        }
        y[0] = p.x;
        y[1] = p.y;
        y[2] = p.z;
        y[3] = 0.0;
        y
    }

    /// The convex vertex that every one of `segments` reaches, ahead of the seam point `x`
    /// along its tangent `t` (within [`TIP_AHEAD_RAD`] of it), nearest `x`.
    fn vertex_ahead(
        &self,
        segments: &[Element],
        x: &DVector<f64>,
        t: &DVector<f64>,
    ) -> Option<usize> {
        let (b, dir) = (v3(x), v3(t).normalize_or_zero());
        (0..self.model.vertices.len())
            .filter(|&v| self.class.vertices[v] == VertexKind::Convex)
            .filter(|&v| {
                let to = self.model.vertices[v].point - b;
                to.length() > 0.0 && to.angle_between(dir) <= TIP_AHEAD_RAD
            })
            .filter(|&v| segments.iter().all(|&e| self.reaches(e, v)))
            .min_by(|&a, &c| {
                let da = self.model.vertices[a].point.distance(b);
                da.total_cmp(&self.model.vertices[c].point.distance(b))
            })
    }

    /// The vertex at `b` (within [`REACH_REL_ACCURACY`] × the accuracy) that every one of
    /// `segments` reaches: where `r` returns to 0 elsewhere (the elements' surfaces meeting
    /// past their trims, a corner buried in the material) the seam has left its elements,
    /// which the hand-over after this finds.
    fn vertex_reached(&self, segments: &[Element], b: DVec3) -> Option<usize> {
        let reach = REACH_REL_ACCURACY * self.opts.accuracy;
        (0..self.model.vertices.len())
            .filter(|&v| self.model.vertices[v].point.distance(b) <= reach)
            .filter(|&v| segments.iter().all(|&e| self.reaches(e, v)))
            .min_by(|&a, &c| {
                let va = self.model.vertices[a].point.distance(b);
                va.total_cmp(&self.model.vertices[c].point.distance(b))
            })
    }
}

/// The seam's unit tangent (centre part of unit length) from the Jacobian `a` of a seam
/// system with an added row (its last), that row replaced by `dir`: the null direction of
/// the system's rows, oriented along `dir`.
fn tangent_from(mut a: DMatrix<f64>, dir: &DVector<f64>) -> Option<DVector<f64>> {
    let n = a.nrows();
    if n == 0 || a.ncols() != n || dir.len() != n {
        return None;
    }
    a.row_mut(n - 1).copy_from(&dir.transpose());
    let mut rhs = DVector::zeros(n);
    rhs[n - 1] = 1.0;
    let z = a.lu().solve(&rhs)?;
    let zb = DVec3::new(z[0], z[1], z[2]).length();
    (zb.is_finite() && zb > 0.0).then(|| z / zb)
}
