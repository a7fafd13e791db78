//! Junctions: where another part of the boundary comes closer than `r`, the seam ends at the
//! ball touching four elements, located exactly; the other triplets of that ball leave it as
//! new seams.

use super::options::{
    DISTINCT_TOUCH_REL_RADIUS, MAX_REFINE_ITER, SAME_DIRECTION, SAME_PLACE_REL_ACCURACY,
    UNIT_ROUNDING,
};
use super::tracer::{Start, Tracer};
use super::unknowns::{seam_x, slot, sorted, sys_point, touches_meet, v3, Pairs};
use crate::geom::{nearest_sample_between, project_point, FaceHit};
use crate::medial::axis::{Junction, Node, OpenReason, SeamEnd};
use crate::medial::equations::{vertex_angles, MedialSystem, NormalField};
use crate::medial::solver::{solve, SolveOptions, SolveStatus};
use crate::medial::verify::{junction_unresolved, separation};
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

/// What a seam meets where another part of the boundary comes closer than `r`.
pub(super) enum Meeting {
    /// It ends there: at the junction located at the point given (the 4-segment system's
    /// solution), or open.
    End(SeamEnd, Option<DVector<f64>>),
    /// The part coming closer, `to`, continues touched segment `i` to the angle tolerance
    /// (a face across a smooth edge, a reflex edge running on at a slight kink: an
    /// exporter's facets): the touch point passes from one to the other at the ball `x`
    /// touching both (the 4-segment system's solution, `to` last), which is no junction.
    Across {
        i: usize,
        to: Element,
        x: DVector<f64>,
    },
}

impl Tracer<'_> {
    /// Checks the new seam point `xn` (reached from `x` along `t`) for a part of the solid's
    /// boundary closer than `r`: another face, or a touched face far from its touch point
    /// (the ball meets it a second time; a face close to its own touch point is the
    /// curvature criterion's business). Then the seam ends at the junction located between
    /// `x` and `xn`, or — when the 4-segment system has no solution on the faces — open; or,
    /// where the fourth segment continues a touched one ([`Meeting::Across`]), goes on.
    pub(super) fn junction_between(
        &mut self,
        triplet: &[Element; 3],
        solid: usize,
        x: &DVector<f64>,
        xn: &DVector<f64>,
        t: &DVector<f64>,
    ) -> Option<Meeting> {
        let (mut f, mut hit) = self.intrusion(triplet, solid, xn)?;
        let before = self.touches(triplet, x);
        // The first intrusion between x and xn (another feature may come closer than r
        // before the one seen at xn): bisect the step.
        let sys = MedialSystem::new(triplet.to_vec());
        let h = t.dot(&(xn - x)) / t.dot(t);
        let (mut lo, mut hi) = (0.0, h);
        let mut x_lo = x.clone();
        let mut t_lo = t.clone();
        let mut x_hi = xn.clone();
        // Each probe steps from the last point without an intrusion, along its tangent: the
        // predictor lands within the square of the bracket of the seam. (The hand-over's
        // bisection still steps from the seam point: see docs/design.md, Junctions.)
        for _ in 0..12 {
            let mid = 0.5 * (lo + hi);
            let Some((xm, tm, _)) = self.step(&sys, &x_lo, &t_lo, mid - lo) else {
                break;
            };
            match self.intrusion(triplet, solid, &xm) {
                Some((g, hg)) => {
                    (f, hit) = (g, hg);
                    hi = mid;
                    x_hi = xm;
                }
                None => {
                    lo = mid;
                    x_lo = xm;
                    t_lo = tm;
                }
            }
        }
        let x = &x_lo;
        let Some((fourth, s4)) = self.hit_segment(f, &hit, v3(&x_hi)) else {
            let why = OpenReason::CloserThanR {
                on: hit.on,
                t: hit.edge().map(|(_, t)| t),
            };
            return Some(Meeting::End(SeamEnd::Open(why), None));
        };
        // A hit reported inside a face but next to one of its reflex edges (the trim test
        // and the nearest-point search agree only to their tolerances) may be a touch of
        // the edge: try it when the face has no junction.
        let located = self
            .locate_junction(triplet, x, fourth, s4)
            .map(|jx| (fourth, jx))
            .or_else(|| match fourth {
                Element::Face(f) => {
                    let (e, te) = self.nearest_edge_of_face(f, hit.point)?;
                    let edge = Element::Edge(e);
                    (self.is_reflex(e) && !triplet.contains(&edge))
                        .then(|| self.locate_junction(triplet, x, edge, [te, 0.0]))
                        .flatten()
                        .map(|jx| (edge, jx))
                }
                // A hit on a reflex edge whose junction has the ball's normal outside the
                // edge's arc: the ball touches one of the edge's faces next to it.
                Element::Edge(e) => self.model.edges[e]
                    .faces
                    .iter()
                    .map(|&g| Element::Face(g))
                    .filter(|face| !triplet.contains(face))
                    .find_map(|face| {
                        self.locate_junction(triplet, x, face, [f64::NAN, f64::NAN])
                            .map(|jx| (face, jx))
                    }),
                Element::Vertex(_) => None,
            });
        // The junction itself must be medial: nothing closer than its radius, to the
        // accuracy `verify` holds every ball to.
        let located = located.filter(|(_, jx)| self.ball_is_empty(solid, jx));
        let Some((fourth, jx)) = located else {
            // A touched element (a face, a curved reflex edge) met again, with no junction:
            // where the ball pokes through it by its curvature at its touch point, that is
            // its own curvature limit coming (the nearest point runs away from the touch
            // point as the ball nears osculating it), which the curvature check after this
            // one locates.
            let osculating = (0..3).any(|i| {
                triplet[i] == fourth
                    && !crate::medial::maximal::curvature_allows(
                        self.model,
                        fourth,
                        slot(xn, i),
                        xn[3],
                    )
            });
            if osculating {
                return None;
            }
            // Two touch points on one element (a curved reflex edge touched twice) that have
            // met or passed through each other by `xn`: the seam reaches that element's
            // curvature limit first, where they meet (the 4-segment system is solved there
            // with the two coinciding, on the Voron Manta mount's B-spline rims), which the
            // curvature check after this one locates (on empty balls only).
            if (0..3).any(|i| self.merged_with(triplet, &before, xn, i).is_some()) {
                return None;
            }
            // Where the file has a gap about the face met (edges written off the surfaces),
            // the boundary there is defined only to that gap: a ball reaching into it by no
            // more, with no junction on the segments, has met the file's gap, not a part of
            // the boundary, and goes on (a part truly met comes closer still further on).
            if self.within_gap(solid, xn) {
                return None;
            }
            // Two touch points at a vertex both their elements reach, where the part met
            // comes in: the seam reaches a pinch there (a rib's tip on a wall half as thick
            // as the ball is wide, where the wall's face beyond the tip comes in exactly as
            // the touch points on the rib's feet meet at it: OCCT's sample bottle's thread).
            if let Some((end, y)) = self.pinch(&sys, triplet, x) {
                return Some(Meeting::End(end, Some(y)));
            }
            let why = OpenReason::NoJunction { element: fourth };
            return Some(Meeting::End(SeamEnd::Open(why), None));
        };
        Some(self.meeting_at(triplet, fourth, jx, t))
    }

    /// What a seam on `triplet` arriving along `t` meets at `jx`, the 4-segment system's
    /// solution with `fourth`: the touch point passes onto `fourth` where that continues a
    /// touched segment ([`Self::tangent_across`]); otherwise the junction, recorded (with the
    /// direction the seam arrived from, and the seam's triplet there as traced).
    pub(super) fn meeting_at(
        &mut self,
        triplet: &[Element; 3],
        fourth: Element,
        jx: DVector<f64>,
        t: &DVector<f64>,
    ) -> Meeting {
        if let Some(i) = self.tangent_across(triplet, fourth, &jx) {
            return Meeting::Across {
                i,
                to: fourth,
                x: jx,
            };
        }
        let id = self.add_junction(triplet, fourth, &jx);
        if let Some(a) = self.arrivals.get_mut(id) {
            a.push(-v3(t).normalize());
        }
        self.visited.insert((sorted(*triplet), Node::Junction(id)));
        Meeting::End(SeamEnd::Junction(id), Some(jx))
    }

    /// Which touched segment of `triplet` the fourth segment of the junction point `jx` is
    /// the smooth continuation of: a face joined to a touched face by a smooth edge, or a
    /// reflex edge running on from a touched one at a vertex within the angle tolerance,
    /// its normal at its touch point within twice that tolerance of the touched one's, or
    /// the two touch points one place by `verify`'s separation at the accuracy plus the
    /// file's gap there (an exporter's edge off its faces' surfaces puts a kink of that size
    /// between them). By the tolerance the two are one tangent surface or curve, whose kink
    /// sheet is not part of the medial axis.
    fn tangent_across(
        &self,
        triplet: &[Element; 3],
        fourth: Element,
        jx: &DVector<f64>,
    ) -> Option<usize> {
        let n4 = fourth.eval(self.model, slot(jx, 3))?.n;
        let p4 = sys_point(self.model, fourth, slot(jx, 3));
        (0..3).find(|&i| {
            let one_place = || {
                let gap = self.element_gap(triplet[i]).max(self.element_gap(fourth));
                gap > 0.0
                    && p4
                        .zip(sys_point(self.model, triplet[i], slot(jx, i)))
                        .is_some_and(|(a, b)| {
                            a.distance(b) <= separation(jx[3], self.opts.accuracy + gap)
                        })
            };
            self.one_tangent(triplet[i], fourth)
                && (one_place()
                    || triplet[i].eval(self.model, slot(jx, i)).is_some_and(|ev| {
                        ev.n.angle_between(n4) <= 2.0 * self.opts.tangent_angle_rad
                    }))
        })
    }

    /// True when elements `a` and `b` are one tangent surface or curve by the angle
    /// tolerance: faces joined by a smooth edge, or reflex edges that run on from each other.
    fn one_tangent(&self, a: Element, b: Element) -> bool {
        match (a, b) {
            (Element::Face(f), Element::Face(g)) => self.smooth_edge_between(f, g).is_some(),
            (Element::Edge(e), Element::Edge(g)) => e != g && self.edges_run_on(e, g),
            _ => false,
        }
    }

    /// True when edges `e` and `g` meet at a vertex where one runs on from the other within
    /// the angle tolerance.
    fn edges_run_on(&self, e: usize, g: usize) -> bool {
        let ends = |k: usize| self.model.edges[k].vertices;
        ends(e).iter().filter(|v| ends(g).contains(v)).any(|&v| {
            self.turn_at(v, e, g)
                .is_some_and(|a| a <= self.opts.tangent_angle_rad)
        })
    }

    /// True when two touch points of the ball `x` are one place by `verify`'s separation on
    /// two elements that are one tangent surface or curve by the angle tolerance (faces
    /// joined by a smooth edge, reflex edges running on from each other): a ball of the kink
    /// between them, whose sheet and seams are not part of the medial axis.
    pub(super) fn across_a_tangent_joint(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        self.one_place_pairs(triplet, x)
            .any(|(i, k)| self.one_tangent(triplet[i], triplet[k]))
    }

    /// The nearest boundary point of the solid to the seam point `y` when it is closer than
    /// `r` and not next to a touch point on the same face (that is the curvature
    /// criterion's business): the face it was found on and the hit. Where the nearest is
    /// not, a face touched twice may still bulge into the ball between its two touch points
    /// (see [`Self::bulge_between_touches`]).
    pub(super) fn intrusion(
        &self,
        triplet: &[Element; 3],
        solid: usize,
        y: &DVector<f64>,
    ) -> Option<(usize, FaceHit)> {
        let r = y[3];
        let bound = r - self.opts.accuracy;
        let far = |f: usize, hit: &FaceHit| {
            (0..3).all(|i| {
                triplet[i] != Element::Face(f)
                    || sys_point(self.model, triplet[i], slot(y, i))
                        .is_none_or(|p| p.distance(hit.point) > 0.05 * r)
            })
        };
        if let Some((f, hit)) = self.nearest_in_within(solid, v3(y), bound) {
            if far(f, &hit) {
                return Some((f, hit));
            }
        }
        self.bulge_between_touches(triplet, y, bound)
            .filter(|(f, hit)| far(*f, hit))
    }

    /// The point of a face touched twice by the ball of `y` that is nearer its centre than
    /// `bound` between the two touch points, when there is one: descended from the nearest
    /// of the points on the straight line between their parameters
    /// ([`nearest_sample_between`]). Where a face's curvature wanders, the distance from the
    /// centre has several basins about as deep (two touch points are two of them), and the
    /// nearest-point search may settle in a touched one while a third, between them, is
    /// nearer: on a B-spline round taken from the Voron Revo mount, a seam of balls touching
    /// it twice ran on past the junction where the round came 5e-4 mm nearer than `r`
    /// between its touch points (`samples/trace/long_block_with_a_wavy_round.step`).
    fn bulge_between_touches(
        &self,
        triplet: &[Element; 3],
        y: &DVector<f64>,
        bound: f64,
    ) -> Option<(usize, FaceHit)> {
        let c = v3(y);
        [(0, 1), (0, 2), (1, 2)].into_iter().find_map(|(i, k)| {
            let Element::Face(f) = triplet[i] else {
                return None;
            };
            if triplet[k] != triplet[i] {
                return None;
            }
            let (a, b) = (slot(y, i), slot(y, k));
            let surface = &self.model.faces[f].surface;
            let start = nearest_sample_between(surface, c, (a[0], a[1]), (b[0], b[1]))?;
            let hit = self
                .boundary
                .nearest_on_face(self.model, f, c, Some(start), bound)?;
            Some((f, hit))
        })
    }

    /// True when the nearest boundary point of solid `solid` to the seam point `y` is
    /// closer than `r` by no more than the accuracy plus the file's gap about its face
    /// ([`Self::gap_about`]; `verify` holds balls there to the same).
    fn within_gap(&self, solid: usize, y: &DVector<f64>) -> bool {
        self.nearest_in(solid, v3(y)).is_some_and(|(f, hit)| {
            let gap = self.gap_about(f);
            gap > 0.0 && hit.distance >= y[3] - self.opts.accuracy - gap
        })
    }

    /// The parameters of segment `seg` at the foot of the centre `b` (near `hint` where
    /// finite): a start for the systems that add `seg` to a seam's triplet.
    pub(super) fn start_params(
        &self,
        seg: Element,
        b: DVec3,
        hint: [f64; 2],
    ) -> Option<(f64, f64)> {
        Some(match seg {
            Element::Face(f) => {
                let hint = hint[0].is_finite().then_some((hint[0], hint[1]));
                let projected = project_point(&self.model.faces[f].surface, b, hint).or(hint)?;
                // The projection onto the whole surface may land in another basin, off the
                // face (a cone's other nappe): then start from the hint, the face's nearest
                // point a step away.
                match hint {
                    Some(h) if !self.model.faces[f].domain.contains(projected) => h,
                    _ => projected,
                }
            }
            Element::Edge(e) => {
                let hint = hint[0].is_finite().then_some(hint[0]);
                let (te, q, d) = crate::geom::nearest_on_edge(self.model, e, b, hint);
                let th = crate::medial::equations::edge_angle(self.model, e, te, (q - b) / d)?;
                (te, th)
            }
            Element::Vertex(v) => {
                let a = vertex_angles((self.model.vertices[v].point - b).normalize());
                (a[0], a[1])
            }
        })
    }

    /// Solves the 4-segment system from the seam point `x` (before the crossing), starting
    /// the fourth segment at the foot of `x` near `s4` (where the crossing was seen).
    pub(super) fn locate_junction(
        &self,
        triplet: &[Element; 3],
        x: &DVector<f64>,
        fourth: Element,
        s4: [f64; 2],
    ) -> Option<DVector<f64>> {
        let uv = self.start_params(fourth, v3(x), s4)?;
        let mut segs = triplet.to_vec();
        segs.push(fourth);
        let sys = MedialSystem::new(segs);
        let mut x0 = DVector::zeros(12);
        x0.rows_mut(0, 10).copy_from(x);
        x0[10] = uv.0;
        x0[11] = uv.1;
        let sol = solve(
            |y| sys.eval(self.model, y),
            x0,
            &SolveOptions {
                tol: self.opts.solver_tol,
                max_iter: MAX_REFINE_ITER,
            },
        );
        if !(sol.status == SolveStatus::Converged && sol.x[3] > 0.0) {
            return None;
        }
        // Every touch point must lie on its face: a ball touching a face's extension beyond
        // its edges is not a junction (the event there involves an edge or a vertex).
        // On its border (to a tenth of the accuracy) counts as on it: a junction at a face's
        // corner (a shelf as thick as twice its walls: the ball touches the shelf's two faces
        // at their corners, the walls' faces inside) is on the closed face, whatever side of
        // the trim polygon the corner falls on. Not where another touch point is there too
        // (the face's edge or a face across it, touched at that place: one contact, not two).
        let r = sol.x[3];
        let at: Vec<Option<DVec3>> = (0..4)
            .map(|i| sys_point(self.model, sys.segments[i], slot(&sol.x, i)))
            .collect();
        let alone = |i: usize| {
            let sep = separation(r, self.opts.accuracy);
            at[i].is_some_and(|p| {
                (0..4).all(|k| k == i || at[k].is_none_or(|q| q.distance(p) > sep))
            })
        };
        let on_faces = (0..4).all(|i| {
            let (seg, s) = (sys.segments[i], slot(&sol.x, i));
            self.on_segment(seg, s) || (self.on_face_border(seg, s) && alone(i))
        });
        // Two touch points on one face must be two places, not the same one found twice.
        let distinct = !touches_meet(
            self.model,
            &sys.segments,
            &sol.x,
            DISTINCT_TOUCH_REL_RADIUS * r,
            Pairs::SameSegment,
        );
        (on_faces && distinct).then_some(sol.x)
    }

    /// The segments of solid `solid` that touch the ball `(p, r)` to the output accuracy at a
    /// place other than the contacts already known (`touch`, on `segs`): a face whose inside
    /// the ball touches, or the reflex edge or vertex of a face it touches there. Each with its
    /// parameters and touch point, in the order found: the fifth and further elements of a
    /// non-generic junction, the fourth of a non-generic seam.
    pub(super) fn more_contacts(
        &self,
        solid: usize,
        p: DVec3,
        r: f64,
        segs: &[Element],
        touch: &[DVec3],
    ) -> Vec<(Element, (f64, f64), DVec3)> {
        let tol = SAME_PLACE_REL_ACCURACY * self.opts.accuracy;
        let mut out: Vec<(Element, (f64, f64), DVec3)> = vec![];
        for f in self.boundary.within(self.model, p, r + tol) {
            if self.face_solid[f] != solid {
                continue;
            }
            let hit = self
                .boundary
                .nearest_on_face(self.model, f, p, None, f64::INFINITY);
            // Touching to the output accuracy (a junction itself is solved far tighter), so
            // every touch point reported is within it; a hit on a face's convex edge is not a
            // touch of that face.
            let Some(hit) = hit.filter(|h| (h.distance - r).abs() <= self.opts.accuracy) else {
                continue;
            };
            let seg = match hit.on {
                Element::Face(_) => Some((Element::Face(f), (hit.uv.0, hit.uv.1))),
                Element::Edge(_) => self
                    .hit_segment(f, &hit, p)
                    .filter(|(s, _)| matches!(s, Element::Edge(_)))
                    .map(|(s, q)| (s, (q[0], q[1]))),
                Element::Vertex(_) => self
                    .hit_segment(f, &hit, p)
                    .filter(|(s, _)| matches!(s, Element::Vertex(_)))
                    .map(|(s, q)| (s, (q[0], q[1]))),
            };
            let Some((seg, uv)) = seg else { continue };
            // The segment must touch this very ball there: P − r·N = centre.
            let fits = seg
                .eval(self.model, [uv.0, uv.1])
                .is_some_and(|e| (e.p - e.n * r - p).length() <= self.opts.accuracy);
            if segs.contains(&seg) || out.iter().any(|o| o.0 == seg) || !uv.0.is_finite() || !fits {
                continue;
            }
            // A segment touching next to a touch point already counted (a face's reflex edge
            // just past where the ball touches the face) is the same contact, not another
            // place (verify counts places at the same separation): triplets with both would
            // be one contact twice.
            let sep = separation(r, self.opts.accuracy);
            let Some(q) = sys_point(self.model, seg, [uv.0, uv.1]) else {
                continue;
            };
            if touch
                .iter()
                .chain(out.iter().map(|o| &o.2))
                .all(|t| t.distance(q) > sep)
            {
                out.push((seg, uv, q));
            }
        }
        out
    }

    /// Records a junction (or finds the same one already found) and queues the seams that
    /// leave it. All faces at distance `r` from the centre touch it (more than four at a
    /// non-generic junction, such as a cube's centre). A seam leaves along the normal `n` of the
    /// plane through three touch points, in the sense in which every other touched segment
    /// moves away (`n·(t₀ − tₖ) ≥ 0`, so its distance grows faster than `r`); for a generic
    /// junction that is the paper's rule, one seam per omitted segment.
    pub(super) fn add_junction(
        &mut self,
        arriving: &[Element; 3],
        fourth: Element,
        jx: &DVector<f64>,
    ) -> usize {
        let p = v3(jx);
        let r = jx[3];
        let solid = self.solid_of(fourth);
        let tol = SAME_PLACE_REL_ACCURACY * self.opts.accuracy;
        let mut segs = arriving.to_vec();
        segs.push(fourth);
        let mut params: Vec<(f64, f64)> = (0..4).map(|i| (jx[4 + 2 * i], jx[5 + 2 * i])).collect();
        // The touch points, one per segment (kept alongside `segs` and `params`).
        let Some(mut touch) = (0..4)
            .map(|i| sys_point(self.model, segs[i], slot(jx, i)))
            .collect::<Option<Vec<DVec3>>>()
        else {
            return usize::MAX;
        };
        // The same place to the accuracy, as verify counts places; never finer than the
        // centres are compared (a touch point moves with the centre).
        let sep = separation(r, self.opts.accuracy).max(tol);
        if let Some(id) = self
            .junctions
            .iter()
            .position(|j| j.solid == solid && same_junction(j, p, &touch, tol, sep))
        {
            return id;
        }
        // Other elements touching the same ball (non-generic junctions).
        for (seg, uv, q) in self.more_contacts(solid, p, r, &segs, &touch) {
            segs.push(seg);
            params.push(uv);
            touch.push(q);
        }
        let id = self.junctions.len();
        let mut junction = Junction {
            id,
            solid,
            point: p.to_array(),
            radius: r,
            segments: segs.clone(),
            touch: touch.iter().map(|t| t.to_array()).collect(),
            unresolved: false,
        };
        junction.unresolved = junction_unresolved(&junction, self.opts.accuracy);
        self.junctions.push(junction);
        self.arrivals.push(vec![]);
        let k = segs.len();
        let mut dirs: Vec<DVec3> = vec![];
        for a in 0..k {
            for b in a + 1..k {
                for c in b + 1..k {
                    let (t0, t1, t2) = (touch[a], touch[b], touch[c]);
                    let n = (t1 - t0).cross(t2 - t0);
                    if n.length() < 1e-12 * r * r {
                        continue;
                    }
                    let mut n = n.normalize();
                    let others = (0..k).filter(|&q| q != a && q != b && q != c);
                    let first = others.clone().next().unwrap_or(a);
                    if n.dot(t0 - touch[first]) < 0.0 {
                        n = -n;
                    }
                    let eps = UNIT_ROUNDING * r;
                    if others.into_iter().any(|q| n.dot(t0 - touch[q]) < -eps) {
                        continue;
                    }
                    if dirs.iter().any(|e| e.distance(n) < SAME_DIRECTION) {
                        continue;
                    }
                    dirs.push(n);
                    let x = seam_x(p, r, [a, b, c].map(|q| params[q]));
                    self.queue.push_back(Start {
                        triplet: [segs[a], segs[b], segs[c]],
                        x,
                        dir: n,
                        from: Node::Junction(id),
                    });
                }
            }
        }
        id
    }
}

/// True when a junction found at `p`, touching the boundary at `touch`, is junction `j` found
/// again: its centre within `tol` of `j`'s, and each of its touch points within `sep` of one of
/// `j`'s (the same contact, though an arrival may name a face where another names its edge).
/// Junctions of small features close together are distinct however near their centres: one
/// of them touches a place the other does not.
pub(super) fn same_junction(j: &Junction, p: DVec3, touch: &[DVec3], tol: f64, sep: f64) -> bool {
    DVec3::from_array(j.point).distance(p) <= tol
        && touch.iter().all(|t| {
            j.touch
                .iter()
                .any(|q| DVec3::from_array(*q).distance(*t) <= sep)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A junction at the origin, radius 1, touching the four places given.
    fn junction(touch: [[f64; 3]; 4]) -> Junction {
        Junction {
            id: 0,
            solid: 0,
            point: [0.0; 3],
            radius: 1.0,
            segments: (0..4).map(Element::Face).collect(),
            touch: touch.to_vec(),
            unresolved: false,
        }
    }

    const TOUCH: [[f64; 3]; 4] = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];

    fn places(touch: [[f64; 3]; 4]) -> Vec<DVec3> {
        touch.iter().map(|t| DVec3::from_array(*t)).collect()
    }

    /// Found again (from another seam, its centre a rounding away, one touch named by an edge
    /// of its face: the same place) it is the same junction; a junction as near whose fourth
    /// touch point is another place (a small feature next to the first) is another one, and
    /// so is one whose centre is farther than the tolerance.
    #[test]
    fn close_junctions_of_different_places_stay_distinct() {
        let j = junction(TOUCH);
        let (tol, sep) = (1e-3, 1e-2);
        let near = DVec3::new(2e-4, 0.0, 0.0);
        let mut again = TOUCH;
        again[3] = [0.0, 0.003, -1.0];
        assert!(same_junction(&j, near, &places(again), tol, sep));
        let mut other = TOUCH;
        other[3] = [0.0, -1.0, 0.0];
        assert!(!same_junction(&j, near, &places(other), tol, sep));
        assert!(!same_junction(
            &j,
            DVec3::new(2e-3, 0.0, 0.0),
            &places(TOUCH),
            tol,
            sep
        ));
    }
}
