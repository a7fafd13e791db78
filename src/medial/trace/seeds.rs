//! Seeds beyond the paper: on faces no seam touches, maximal balls sampled from the
//! boundary (shrunk from the inward normal until they touch elsewhere) give points to trace
//! from; balls whose sheet has collapsed are degenerate pieces (a cylinder's axis, a
//! sphere's centre).

use super::degenerate::{centre_motion, CentreMotion};
use super::options::{
    DISTINCT_TOUCH_REL_RADIUS, MAX_REFINE_ITER, MAX_SAMPLE_GRID, MAX_SEAMS, MIN_FACE_SAMPLES,
    OSCULATING_REL_RADIUS, SAME_PLACE_REL_ACCURACY, SHRINK_STEPS, UNIT_ROUNDING, WALK_STEPS,
};
use super::tracer::Tracer;
use super::unknowns::{seam_x, slot, sys_point, to_chord, touches_meet, v3, Pairs};
use crate::geom::{project_point, FaceHit};
use crate::medial::axis::{Degenerate, DegenerateKind, Handover, SeamEnd, SeamPoint};
use crate::medial::equations::{MedialSystem, NormalField};
use crate::medial::maximal::curvature_allows;
use crate::medial::solver::{solve, SolveOptions, SolveStatus};
use crate::medial::verify::separation;
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

/// A point near a seam to trace from in both directions: a ball found by sampling (solids
/// without convex corners, sheets no corner reaches), or given by the caller.
#[derive(Clone, Debug)]
pub struct Seed {
    /// The three elements; a face may appear twice (two touch points on it).
    pub triplet: [Element; 3],
    /// Unknowns `[B, r, s₁, s₂, s₃]` near the seam; refined before tracing.
    pub x: DVector<f64>,
}

impl Seed {
    /// A seed from a centre, a radius and the three elements' parameters.
    pub fn new(triplet: [Element; 3], centre: DVec3, r: f64, params: [(f64, f64); 3]) -> Seed {
        Seed {
            triplet,
            x: seam_x(centre, r, params),
        }
    }
}

/// A maximal ball grown from a face ([`Tracer::sheet_ball`]): its centre, radius, and the
/// other segment it touches with the parameters of the touch.
#[derive(Clone, Debug)]
struct SheetBall {
    /// The point of the face it is grown from.
    foot: DVec3,
    centre: DVec3,
    r: f64,
    seg: (Element, [f64; 2]),
    /// Where it touches `seg`.
    touch: DVec3,
}

impl Tracer<'_> {
    /// Completes the trace beyond the paper (`docs/design.md`, seeds by sampling): on
    /// every face no seam touches yet, samples boundary points, grows the maximal ball at
    /// each (shrinking from the inward normal until it touches elsewhere), and from the two
    /// touches and the nearest third segment solves for a seam point to trace from. Balls
    /// whose sheet has collapsed (a cylinder's axis, a sphere's centre) are reported as
    /// [`Degenerate`] instead.
    pub(super) fn seed_by_sampling(&mut self) {
        for f in 0..self.model.faces.len() {
            if self.touched[f] {
                continue;
            }
            for s in self.sample_points(f) {
                if self.touched[f] || self.seams.len() >= MAX_SEAMS {
                    break;
                }
                let seeds = self.sample_seeds(f, s);
                self.try_seeds(seeds);
            }
        }
        // Surfaces (faces joined across smooth edges) that no ball touches yet, their
        // sampled balls touching one other face each and the seam that bounds that sheet out
        // of reach of the seeds above (the wall of a hole between a floor and a ceiling
        // sampled away from them): walk the sheet from a few samples.
        let surface = self.class.smooth_surfaces(self.model);
        for f in 0..self.model.faces.len() {
            if self.surface_reached(&surface, surface[f]) {
                continue;
            }
            let samples = self.sample_points(f);
            let every = samples.len().div_ceil(MIN_FACE_SAMPLES).max(1);
            for s in samples.into_iter().step_by(every) {
                for dir in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
                    if self.surface_reached(&surface, surface[f]) || self.seams.len() >= MAX_SEAMS {
                        break;
                    }
                    let seeds = self.walk_seeds(f, s, dir);
                    self.try_seeds(seeds);
                }
            }
        }
    }

    /// True when a seam touches a face of smooth surface `root` (`surface` from
    /// [`crate::classify::Classification::smooth_surfaces`]) or one of its faces' edges.
    fn surface_reached(&self, surface: &[usize], root: usize) -> bool {
        (0..self.model.faces.len())
            .filter(|&f| surface[f] == root)
            .any(|f| {
                self.touched[f]
                    || self.model.faces[f]
                        .loops
                        .iter()
                        .flat_map(|l| &l.edges)
                        .any(|oe| self.touched_edges[oe.edge])
            })
    }

    /// Traces from the first of `seeds` that gives a new seam.
    fn try_seeds(&mut self, seeds: Vec<Seed>) {
        for seed in seeds {
            let before = self.seams.len();
            self.trace_seed(&seed);
            self.run_queue();
            if self.seams.len() > before {
                break;
            }
        }
    }

    /// Seeds where the sheet of the maximal balls touching face `f` changes what else they
    /// touch, met walking from `s` along `dir` in the face's parameters to the end of its
    /// domain or its trim: each change is bracketed to the solver's tolerance, and the ball
    /// there, touching `f` and the segments on either side of it, seeds a seam (a change
    /// between faces of one smooth surface seeds nothing: its refinement fails).
    fn walk_seeds(&mut self, f: usize, s: [f64; 2], dir: [f64; 2]) -> Vec<Seed> {
        let d = self.model.faces[f].domain;
        let span = [d.u.1 - d.u.0, d.v.1 - d.v.0];
        let at = |t: f64| [s[0] + dir[0] * span[0] * t, s[1] + dir[1] * span[1] * t];
        let inside = |p: [f64; 2]| p[0] >= d.u.0 && p[0] <= d.u.1 && p[1] >= d.v.0 && p[1] <= d.v.1;
        let mut seeds = vec![];
        let Some(mut prev) = self.sheet_ball(f, s) else {
            return seeds;
        };
        let mut t0 = 0.0;
        for k in 1..=WALK_STEPS {
            let t1 = k as f64 / WALK_STEPS as f64;
            let p = at(t1);
            if !inside(p) || !self.on_segment(Element::Face(f), p) {
                break;
            }
            let Some(next) = self.sheet_ball(f, p) else {
                break;
            };
            if next.seg.0 != prev.seg.0 {
                // Bracket the change.
                let (mut lo, mut hi) = ((t0, prev.clone()), (t1, next.clone()));
                for _ in 0..MAX_REFINE_ITER {
                    let mid = 0.5 * (lo.0 + hi.0);
                    let Some(ball) = self.sheet_ball(f, at(mid)) else {
                        break;
                    };
                    if ball.seg.0 == lo.1.seg.0 {
                        lo = (mid, ball);
                    } else {
                        hi = (mid, ball);
                    }
                    if (hi.0 - lo.0) * span[0].hypot(span[1]) <= self.opts.solver_tol {
                        break;
                    }
                }
                let sf = at(lo.0);
                let (a, b) = (&lo.1, &hi.1);
                seeds.push(Seed::new(
                    [Element::Face(f), a.seg.0, b.seg.0],
                    a.centre,
                    a.r,
                    [
                        (sf[0], sf[1]),
                        (a.seg.1[0], a.seg.1[1]),
                        (b.seg.1[0], b.seg.1[1]),
                    ],
                ));
            }
            (t0, prev) = (t1, next);
        }
        seeds
    }

    /// The maximal ball touching face `f` at `s` and the segment it touches besides, or None
    /// at a convex edge (`r` within the accuracy), where it osculates the face (its second
    /// touch at the first), or where it cannot be grown.
    fn sheet_ball(&self, f: usize, s: [f64; 2]) -> Option<SheetBall> {
        let solid = self.face_solid[f];
        let ev = Element::Face(f).eval(self.model, s)?;
        let (r, centre, g, hit) = self.maximal_along(solid, ev.p, ev.n)?;
        if r <= SAME_PLACE_REL_ACCURACY * self.opts.accuracy
            || hit.point.distance(ev.p) <= DISTINCT_TOUCH_REL_RADIUS * r
        {
            return None;
        }
        let seg = self.hit_segment(g, &hit, centre)?;
        Some(SheetBall {
            foot: ev.p,
            centre,
            r,
            seg,
            touch: hit.point,
        })
    }

    /// Records the maximal ball touching face `f` at `s` as a degenerate ball when it is one
    /// (see [`Self::collapsed`]); seeds nothing else.
    pub(super) fn sample_for_degenerate(&mut self, f: usize, s: [f64; 2]) -> bool {
        let Some(ball) = self.sheet_ball(f, s) else {
            return false;
        };
        let (seg, s2) = ball.seg;
        self.collapsed(Element::Face(f), s, seg, s2, ball.centre, ball.r)
    }

    /// Points of face `f` to sample from: the centres of a grid of cells over its domain that
    /// are on the face, the grid made finer (up to [`MAX_SAMPLE_GRID`] cells a side) while
    /// fewer than [`MIN_FACE_SAMPLES`] are (a thin face: a tube's annular end, a narrow
    /// chamfer or land, whose trim covers little of its domain).
    pub(super) fn sample_points(&self, f: usize) -> Vec<[f64; 2]> {
        let d = self.model.faces[f].domain;
        let mut grid = 4;
        loop {
            let points: Vec<[f64; 2]> = (0..grid * grid)
                .map(|k| {
                    let at = |i: usize| (i as f64 + 0.5) / grid as f64;
                    [
                        d.u.0 + (d.u.1 - d.u.0) * at(k % grid),
                        d.v.0 + (d.v.1 - d.v.0) * at(k / grid),
                    ]
                })
                .filter(|&s| self.on_segment(Element::Face(f), s))
                .collect();
            if points.len() >= MIN_FACE_SAMPLES || grid >= MAX_SAMPLE_GRID {
                return points;
            }
            grid *= 2;
        }
    }

    /// The maximal ball touching face `f` at `s` and seeds from it (see
    /// [`Self::seed_by_sampling`]): with the nearest third segment, or with one of the two
    /// touched faces touched again (the foot on it nearest the point opposite the touch
    /// across the ball). None when the ball is degenerate (then recorded).
    pub(super) fn sample_seeds(&mut self, f: usize, s: [f64; 2]) -> Vec<Seed> {
        self.sample_ball(f, s).unwrap_or_default()
    }

    pub(super) fn sample_ball(&mut self, f: usize, s: [f64; 2]) -> Option<Vec<Seed>> {
        let solid = self.face_solid[f];
        let ball = self.sheet_ball(f, s)?;
        let (b, r, (seg2, s2)) = (ball.centre, ball.r, ball.seg);
        let first = Element::Face(f);
        if self.collapsed(first, s, seg2, s2, b, r) {
            return None;
        }
        let mut thirds = vec![];
        if let Some((k, hit3)) = self.boundary.nearest_face_where(self.model, b, |h| {
            self.face_solid[h] == solid && h != f && Element::Face(h) != seg2
        }) {
            thirds.extend(self.hit_segment(k, &hit3, b));
        }
        // Where the ball reaches a face of `f`'s own edge as it reaches another face (a
        // pocket half as deep as its plate is thick: the ball between the plate's faces
        // touches the wall at its foot edge, where it meets the floor), the third nearest
        // past `f`'s neighbours too: the seam runs with its touch point on `f`'s edge.
        let neighbours = self.model.faces_next_to(f);
        if let Some((k, hit3)) = self.boundary.nearest_face_where(self.model, b, |h| {
            self.face_solid[h] == solid && !neighbours.contains(&h) && Element::Face(h) != seg2
        }) {
            // The same seed again where it is the nearest third anyway.
            let known: Vec<Element> = thirds.iter().map(|t| t.0).collect();
            thirds.extend(
                self.hit_segment(k, &hit3, b)
                    .filter(|(seg, _)| !known.contains(seg)),
            );
        }
        for (seg, touch) in [(first, ball.foot), (seg2, ball.touch)] {
            if let Element::Face(h) = seg {
                let opposite = b * 2.0 - touch;
                if let Some(uv) = project_point(&self.model.faces[h].surface, opposite, None) {
                    thirds.push((seg, [uv.0, uv.1]));
                }
            }
        }
        Some(
            thirds
                .into_iter()
                .map(|(seg3, s3)| {
                    Seed::new(
                        [first, seg2, seg3],
                        b,
                        r,
                        [(s[0], s[1]), (s2[0], s2[1]), (s3[0], s3[1])],
                    )
                })
                .collect(),
        )
    }

    /// The maximal ball touching the boundary of solid `solid` at `p` with outward normal
    /// `n` (largest `r` with nothing closer than `r` to `p − r·n`, to the solver tolerance): its radius
    /// and centre, and the face and point nearest to the centre of a ball just past it (the
    /// other place it touches).
    pub(super) fn maximal_along(
        &self,
        solid: usize,
        p: DVec3,
        n: DVec3,
    ) -> Option<(f64, DVec3, usize, FaceHit)> {
        let nearest = |b: DVec3| self.nearest_in(solid, b);
        let fits = |r: f64| {
            nearest(p - n * r).is_some_and(|(_, h)| h.distance >= r * (1.0 - UNIT_ROUNDING))
        };
        // The shrinking ball: the ball through p and the nearest point q to its centre, with
        // its centre on the normal, until nothing is nearer than r (a few steps where the
        // bisection below takes dozens); its radius brackets the bisection.
        let diag = self.model.diagonal();
        let mut shrunk = diag;
        for _ in 0..SHRINK_STEPS {
            let Some((_, h)) = nearest(p - n * shrunk) else {
                break;
            };
            let d = h.point - p;
            let along = -d.dot(n);
            if h.distance >= shrunk * (1.0 - UNIT_ROUNDING) || along.is_nan() || along <= 0.0 {
                break;
            }
            let r = 0.5 * d.length_squared() / along;
            if r.is_nan() || r >= shrunk {
                break;
            }
            shrunk = r;
        }
        let (mut lo, mut hi) = (0.0, diag);
        let slack = 1e-9 * shrunk + self.opts.solver_tol;
        if shrunk > slack && fits(shrunk - slack) && !fits(shrunk + slack) {
            (lo, hi) = (shrunk - slack, shrunk + slack);
        }
        for _ in 0..48 {
            let mid = 0.5 * (lo + hi);
            if fits(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
            // Bisected as far as the solver's residuals go.
            if hi - lo <= self.opts.solver_tol {
                break;
            }
        }
        let (g, hit) = nearest(p - n * hi)?;
        Some((lo, p - n * lo, g, hit))
    }

    /// True (and recorded as [`Degenerate`]) when the sheet of balls touching `a` at `sa` and
    /// `b` at `sb` has collapsed at centre `c`, radius `r`: the directions in which the two
    /// touch points can move together (the null space of the 2-segment Jacobian, 6 × 8) move
    /// the centre along fewer than two dimensions.
    pub(super) fn collapsed(
        &mut self,
        a: Element,
        sa: [f64; 2],
        b: Element,
        sb: [f64; 2],
        c: DVec3,
        r: f64,
    ) -> bool {
        let sys = MedialSystem::new(vec![a, b]);
        let mut x = DVector::zeros(8);
        x[0] = c.x;
        x[1] = c.y;
        x[2] = c.z;
        x[3] = r;
        x[4] = sa[0];
        x[5] = sa[1];
        x[6] = sb[0];
        x[7] = sb[1];
        let rank = match centre_motion(self.model, &sys, &x) {
            Some(CentreMotion::Still) => 0,
            Some(CentreMotion::Along(_)) => 1,
            None => return false,
        };
        let kind = if rank == 0 {
            DegenerateKind::Point
        } else {
            DegenerateKind::Curve
        };
        let segments = vec![a, b];
        let solid = self.solid_of(a);
        let ball = [c.x, c.y, c.z, r];
        let at = |seg: Element, s: [f64; 2]| {
            sys_point(self.model, seg, s).map_or([f64::NAN; 3], |p| p.to_array())
        };
        let touch = [at(a, sa), at(b, sb)];
        match self
            .degenerate
            .iter_mut()
            .enumerate()
            .find(|(_, d)| d.solid == solid && d.kind == kind && d.segments == segments)
        {
            Some((k, d)) => {
                d.balls.push(ball);
                d.touch.push(touch);
                self.degenerate_x[k].push(x);
            }
            None => {
                self.degenerate.push(Degenerate {
                    solid,
                    kind,
                    segments,
                    balls: vec![ball],
                    touch: vec![touch],
                    ends: vec![],
                    around: false,
                });
                self.degenerate_x.push(vec![x]);
            }
        }
        if let Element::Face(f) = a {
            self.touched[f] = true;
        }
        true
    }

    /// Refines `seed` onto its seam and, unless it is not a medial point or lies on a seam
    /// already traced, traces that seam both ways (queueing what its junctions lead to).
    pub(super) fn trace_seed(&mut self, seed: &Seed) {
        let sys = MedialSystem::new(seed.triplet.to_vec());
        let sol = solve(
            |y| sys.eval(self.model, y),
            seed.x.clone(),
            &SolveOptions {
                tol: self.opts.solver_tol,
                max_iter: MAX_REFINE_ITER,
            },
        );
        let x = sol.x;
        let r = x[3];
        // A ball that osculates one of its faces or edges (a fillet's axis: radius = the
        // fillet's, touching it along a whole arc; the axis of a rounded corner's foot circle)
        // is a degenerate piece, not a seam point, although the three-segment system is
        // solvable there.
        let osculates = (0..3).any(|i| {
            !curvature_allows(
                self.model,
                seed.triplet[i],
                slot(&x, i),
                r * (1.0 + OSCULATING_REL_RADIUS),
            )
        });
        let valid = sol.status == SolveStatus::Converged
            && r > self.opts.accuracy
            && !osculates
            && self.is_medial(&seed.triplet, &x)
            // Three places, not two (a sheet's ball where it crosses a smooth edge touches
            // the faces on either side at one point, and the system is solvable there).
            && !touches_meet(
                self.model,
                &seed.triplet,
                &x,
                DISTINCT_TOUCH_REL_RADIUS * r,
                Pairs::All,
            )
            && !self.across_a_tangent_joint(&seed.triplet, &x)
            && !self.on_traced_seam(&seed.triplet, &x)
            && !self.touches_along(&seed.triplet, &x);
        let dir = valid.then(|| self.null_direction(&sys, &x)).flatten();
        let Some(dir) = dir else {
            self.stats.skipped_seeds += 1;
            return;
        };
        let fwd = self.march(seed.triplet, x.clone(), dir, Some(&x));
        if fwd.end == SeamEnd::Closed {
            let ends = [SeamEnd::Closed, SeamEnd::Closed];
            self.push_seam(
                seed.triplet,
                fwd.triplet,
                ends,
                fwd.points,
                fwd.handovers,
                fwd.seconds,
            );
            return;
        }
        let back = self.march(seed.triplet, x, -dir, None);
        // The backward run reversed, then the forward run after the seed point; the
        // backward run's hand-overs reversed in order and sense.
        let nb = back.points.len();
        let mut handovers = super::join::reversed_handovers(&back.handovers, nb);
        handovers.extend(fwd.handovers.into_iter().map(|h| Handover {
            point: h.point + nb - 1,
            ..h
        }));
        let mut points: Vec<SeamPoint> = back.points.into_iter().rev().collect();
        points.extend(fwd.points.into_iter().skip(1));
        self.push_seam(
            back.triplet,
            fwd.triplet,
            [back.end, fwd.end],
            points,
            handovers,
            back.seconds + fwd.seconds,
        );
    }

    /// True when the seam point `x` is medial: its touch points lie on their faces, nothing
    /// of the solid is closer than `r`, and no touched face curves through the ball.
    pub(super) fn is_medial(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        let r = x[3];
        let solid = self.solid_of(triplet[0]);
        let on_faces = (0..3).all(|i| self.on_segment(triplet[i], slot(x, i)));
        // A segment touched twice must be touched in two places, not once counted twice
        // (that is a sheet point, where Newton also converges).
        let distinct = !touches_meet(
            self.model,
            triplet,
            x,
            DISTINCT_TOUCH_REL_RADIUS * r,
            Pairs::SameSegment,
        );
        on_faces
            && distinct
            && self.ball_is_empty(solid, x)
            && (0..3).all(|i| curvature_allows(self.model, triplet[i], slot(x, i), r))
    }

    /// True when `x` lies on a seam traced already that touches the same segments there (at
    /// its start, its end, or between hand-overs).
    pub(super) fn on_traced_seam(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        let b = v3(x);
        let tol = 1e-3 * self.model.diagonal();
        self.seams.iter().any(|s| {
            let touches = |e: &Element| {
                s.segments.contains(e)
                    || s.end_segments.contains(e)
                    || s.handovers.iter().any(|h| h.from == *e || h.to == *e)
            };
            triplet.iter().all(touches)
                && s.points.windows(2).any(|w| {
                    let a = DVec3::new(w[0].point[0], w[0].point[1], w[0].point[2]);
                    let c = DVec3::new(w[1].point[0], w[1].point[1], w[1].point[2]);
                    to_chord(b, a, c) <= tol
                })
        })
    }

    /// The seam's direction at `x` without a preferred orientation: the null vector of the
    /// Jacobian (smallest singular value of `J` padded to a square).
    pub(super) fn null_direction(&self, sys: &MedialSystem, x: &DVector<f64>) -> Option<DVec3> {
        let (_, j) = sys.eval(self.model, x)?;
        let n = x.len();
        let mut a = nalgebra::DMatrix::zeros(n, n);
        a.view_mut((0, 0), (n - 1, n)).copy_from(&j);
        let svd = a.svd(false, true);
        let vt = svd.v_t?;
        let k = svd.singular_values.imin();
        let d = DVec3::new(vt[(k, 0)], vt[(k, 1)], vt[(k, 2)]);
        (d.length() > UNIT_ROUNDING).then(|| d.normalize())
    }
}

impl Tracer<'_> {
    /// True when the ball of seam point `x` (on `triplet`) touches the boundary all along
    /// the way between two of its touch points: the point of its sphere midway between them
    /// (on the great circle) is on the boundary too, to the accuracy. It is then a ball of a
    /// degenerate piece (a full round's axis: the ball of the fillet's radius touches the
    /// fillet along an arc and the faces on either side at its ends), traced as such, not a
    /// seam point; a seam's ball touches its three places only.
    fn touches_along(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        let Some(touch) = self
            .touches(triplet, x)
            .into_iter()
            .collect::<Option<Vec<DVec3>>>()
        else {
            return false;
        };
        let (c, r) = (v3(x), x[3]);
        // Touch points closer than twice the separation are one place or next to it: a
        // surface through them stays within the accuracy of the sphere between them anyway.
        let apart = 2.0 * separation(r, self.opts.accuracy);
        (0..3).any(|i| {
            (i + 1..3).any(|j| {
                let mid = 0.5 * (touch[i] + touch[j]) - c;
                // Opposite touch points have no one midway.
                touch[i].distance(touch[j]) > apart && mid.length() > 0.1 * r && {
                    let q = c + mid.normalize() * r;
                    // On a face there that the ball osculates (its curvature that of the
                    // ball: a full round's fillet), not merely passing near it.
                    self.boundary
                        .nearest_face(self.model, q)
                        .is_some_and(|(f, hit)| {
                            hit.distance <= self.opts.accuracy
                                && hit.on == Element::Face(f)
                                && !curvature_allows(
                                    self.model,
                                    Element::Face(f),
                                    [hit.uv.0, hit.uv.1],
                                    r * (1.0 + OSCULATING_REL_RADIUS),
                                )
                        })
                }
            })
        })
    }
}
