//! Seeds for seams that no convex vertex leads to and no face sample finds: the closed loop of
//! seams round a pocket's floor or a boss's foot, whose balls touch the two faces of a plate
//! and the feature's reflex rim. Maximal balls are grown from points of each reflex edge no
//! seam touches, over the arc of normals the edge owns (its sheet, parametrised by the point
//! along the edge and the normal across the arc). Where the element such a ball touches
//! besides the edge changes between neighbouring samples, a seam touching the edge lies
//! between them: bisected, the ball touches the edge and both elements in distinct places, a
//! seam point to trace from.

use super::options::{DISTINCT_TOUCH_REL_RADIUS, MAX_SEAMS, SAME_PLACE_REL_ACCURACY};
use super::seeds::Seed;
use super::tracer::Tracer;
use crate::geom::eval_curve;
use crate::medial::axis::SeamEnd;
use crate::model::{Curve3D, Element};
use glam::DVec3;

/// Samples along each edge, and across its arc of normals.
const ALONG: usize = 4;
const ACROSS: usize = 6;
/// Most bisection steps between two samples touching different elements.
const BISECTIONS: usize = 40;
/// Most bisection steps looking for a ball that touches an edge along a curve between two
/// samples: each step keeps the stretch of such balls between the two ends, so after these
/// it has been hit unless it spans less than 2^-12 of the samples' spacing (a 90-degree arc
/// of normals sampled 6 times: 0.004 degrees; about 3e-4 mm of axis under a boss r = 5).
const COLLAPSE_BISECTIONS: usize = 12;
/// Bisection stops with the centres this close (× r): Newton refines the seed from there.
const SEED_REL_RADIUS: f64 = 1e-4;
/// Bisection gives up with the touch points this close (× r): one element passing into its
/// neighbour (a face into its reflex edge, an edge into its vertex), not a seam.
const MEETING_REL_RADIUS: f64 = 1e-2;

/// Balls reaching less than this far towards an edge's centre of curvature (see
/// [`Tracer::reach`]) are not bisected between for a ball touching the edge all round: on a
/// circle the reach is 1 on its axis and falls off smoothly away from it (0.83 for the
/// ball 8 degrees below the axis's end under a boss r = 5 on a 10 mm plate).
const REACH: f64 = 0.5;

/// The curvature vector of a curve with derivatives `d1`, `d2` (towards its centre of
/// curvature, length 1/radius); `None` where it has no tangent.
fn bend(d1: DVec3, d2: DVec3) -> Option<DVec3> {
    let speed2 = d1.length_squared();
    if speed2 <= 0.0 {
        return None;
    }
    let tangent = d1 / speed2.sqrt();
    Some((d2 - tangent * d2.dot(tangent)) / speed2)
}

/// The maximal ball grown from a point of an edge: where it touches besides the edge.
#[derive(Clone, Copy, Debug)]
struct Contact {
    /// The element touched and its parameters there.
    seg: Element,
    s: [f64; 2],
    /// Where it is touched.
    touch: DVec3,
    /// The edge's parameters `[t, θ]` at the ball's touch point on it.
    edge_s: [f64; 2],
    centre: DVec3,
    r: f64,
}

/// A place on edge `e`'s sheet: the curve parameter and the fraction of the way across the
/// arc of normals.
type Place = [f64; 2];

fn lerp(a: Place, b: Place, w: f64) -> Place {
    [a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w]
}

impl Tracer<'_> {
    /// Seeds from the sheets of reflex edges that no seam touches (see the module's doc).
    pub(super) fn seed_by_arcs(&mut self) {
        // An edge a seam ends on, osculating it, is touched there.
        for s in &self.seams {
            for end in &s.ends {
                if let SeamEnd::CurvatureLimit {
                    segment: Element::Edge(e),
                } = *end
                {
                    self.touched_edges[e] = true;
                }
            }
        }
        for e in 0..self.model.edges.len() {
            if self.seams.len() >= MAX_SEAMS {
                break;
            }
            if !self.is_reflex(e) {
                continue;
            }
            if !self.touched_edges[e] {
                self.seed_on_edge(e);
            } else if !matches!(self.model.edges[e].curve, Curve3D::Line(_)) {
                // A seam touching an edge does not say its sheet has no collapsed piece: a
                // boss wider than it is high has, under its foot circle, a stretch of axis
                // whose balls touch the circle all round, which no face sample finds.
                self.collapse_on_edge(e);
            }
        }
    }

    /// Looks for a ball touching curved reflex edge `e` along a curve (a degenerate curve of
    /// the edge) across its sheet at the middle of the edge: a ball touching a circle all
    /// round touches every point of it, so it is grown from any one of them (the edges that
    /// bound such balls are circles and circular arcs, exactly or as splines). Of the
    /// `ACROSS` directions there only those towards the edge's centre of curvature (where
    /// its balls can reach round it: a boss's foot circle, not a hole's floor circle): a
    /// sampled ball touching the edge a second time, or one bisected between two neighbours
    /// touching different elements, is recorded, and the whole curve traced from it with the
    /// others.
    fn collapse_on_edge(&mut self, e: usize) {
        let (lo, hi) = self.model.edges[e].range;
        let t = 0.5 * (lo + hi);
        let line: Vec<(Place, Option<Contact>)> = (0..ACROSS)
            .map(|j| [t, (j as f64 + 0.5) / ACROSS as f64])
            .map(|place| {
                let c = self
                    .bends_towards(e, place)
                    .then(|| self.edge_contact(e, place))
                    .flatten();
                (place, c)
            })
            .collect();
        for &(_, c) in &line {
            if let Some(c) = c.filter(|c| c.seg == Element::Edge(e)) {
                if self.collapsed(Element::Edge(e), c.edge_s, c.seg, c.s, c.centre, c.r) {
                    return;
                }
            }
        }
        for pair in line.windows(2) {
            let [(pa, Some(ca)), (pb, Some(cb))] = [pair[0], pair[1]] else {
                continue;
            };
            // Between two balls that reach towards the centre of curvature less than half
            // way, no ball reaches round the edge.
            if ca.seg == cb.seg || self.reach(e, pa, &ca).max(self.reach(e, pb, &cb)) < REACH {
                continue;
            }
            let mut again = None;
            let _ = self.bisect_contacts(e, (pa, ca), (pb, cb), &mut again, COLLAPSE_BISECTIONS);
            if let Some(c) = again {
                if self.collapsed(Element::Edge(e), c.edge_s, c.seg, c.s, c.centre, c.r) {
                    return;
                }
            }
        }
    }

    /// How far ball `c`, grown at `place` on reflex edge `e`'s sheet, reaches towards the
    /// edge's centre of curvature: its centre's distance along the principal normal over the
    /// radius of curvature (at most 1 on a circle, where the ball touches the circle all
    /// round exactly when it is 1).
    fn reach(&self, e: usize, place: Place, c: &Contact) -> f64 {
        let d = eval_curve(&self.model.edges[e].curve, place[0]);
        let Some(bend) = bend(d.d1, d.d2) else {
            return 0.0;
        };
        (c.centre - d.p).dot(bend)
    }

    /// Whether the inward direction at `place` on reflex edge `e`'s sheet points towards the
    /// edge's centre of curvature there.
    fn bends_towards(&self, e: usize, place: Place) -> bool {
        let edge = &self.model.edges[e];
        let d = eval_curve(&edge.curve, place[0]);
        let (Some(n), Some(bend)) = (self.fan_normal(e, place), bend(d.d1, d.d2)) else {
            return false;
        };
        -n.dot(bend) > 0.0
    }

    /// The outward normal at `place` on reflex edge `e`'s arc of normals.
    fn fan_normal(&self, e: usize, place: Place) -> Option<DVec3> {
        let [na, nb] = self.edge_fan(e, place[0])?;
        let span = na.angle_between(nb);
        if span.is_nan() || span <= 1e-6 {
            return None;
        }
        let w = place[1];
        Some(((na * ((1.0 - w) * span).sin() + nb * (w * span).sin()) / span.sin()).normalize())
    }

    /// Samples edge `e`'s sheet on a grid, bisects between neighbours touching different
    /// elements, and traces from each seam point found.
    fn seed_on_edge(&mut self, e: usize) {
        let (lo, hi) = self.model.edges[e].range;
        let place = |i: usize| -> Place {
            let (k, j) = (i / ACROSS, i % ACROSS);
            [
                lo + (hi - lo) * (k as f64 + 0.5) / ALONG as f64,
                (j as f64 + 0.5) / ACROSS as f64,
            ]
        };
        let grid: Vec<Option<Contact>> = (0..ALONG * ACROSS)
            .map(|i| self.edge_contact(e, place(i)))
            .collect();
        let mut pairs = vec![];
        for i in 0..ALONG * ACROSS {
            if i % ACROSS + 1 < ACROSS {
                pairs.push((i, i + 1));
            }
            if i + ACROSS < ALONG * ACROSS {
                pairs.push((i, i + ACROSS));
            }
        }
        for (a, b) in pairs {
            let (Some(ca), Some(cb)) = (grid[a], grid[b]) else {
                continue;
            };
            if ca.seg == cb.seg || self.seams.len() >= MAX_SEAMS {
                continue;
            }
            // Between a ball touching one element and one touching another, the ball may
            // touch the edge itself a second time: where it touches the edge along a curve (a
            // boss's foot circle, touched all round by the balls on its axis), that is a
            // degenerate curve of the edge, recorded (and traced with the others) instead of a
            // seam touching the edge twice.
            let mut again = None;
            let seed =
                self.bisect_contacts(e, (place(a), ca), (place(b), cb), &mut again, BISECTIONS);
            if let Some(c) = again {
                if self.collapsed(Element::Edge(e), c.edge_s, c.seg, c.s, c.centre, c.r) {
                    continue;
                }
            }
            if let Some(seed) = seed {
                self.trace_seed(&seed);
                self.run_queue();
            }
        }
    }

    /// The maximal ball at `place` on reflex edge `e`'s sheet and what it touches besides
    /// the edge; `None` where the ball is nothing (a degenerate arc) or touches only the
    /// edge near the point it grew from.
    fn edge_contact(&self, e: usize, place: Place) -> Option<Contact> {
        let edge = &self.model.edges[e];
        let t = place[0];
        let n = self.fan_normal(e, place)?;
        let p = eval_curve(&edge.curve, t).p;
        let solid = self.face_solid[edge.faces[0]];
        let (r, centre, g, hit) = self.maximal_along(solid, p, n)?;
        if r <= SAME_PLACE_REL_ACCURACY * self.opts.accuracy
            || hit.point.distance(p) <= DISTINCT_TOUCH_REL_RADIUS * r
        {
            return None;
        }
        let (seg, s) = self.hit_segment(g, &hit, centre)?;
        let theta = crate::medial::equations::edge_angle(self.model, e, t, n)?;
        Some(Contact {
            seg,
            s,
            touch: hit.point,
            edge_s: [t, theta],
            centre,
            r,
        })
    }

    /// Bisects between two places on edge `e`'s sheet whose balls touch different elements
    /// to the ball touching both (to the accuracy): a seed on the edge and the two elements,
    /// when their touch points are distinct there (not one element passing into its
    /// neighbour, as a face into its reflex edge). `again` is set to the first ball on the
    /// way that touches the edge itself a second time (see [`Self::seed_on_edge`]).
    fn bisect_contacts(
        &self,
        e: usize,
        (mut pa, mut ca): (Place, Contact),
        (mut pb, mut cb): (Place, Contact),
        again: &mut Option<Contact>,
        steps: usize,
    ) -> Option<Seed> {
        for _ in 0..steps {
            // Close enough for Newton (the seed is refined onto its seam); or one element
            // passing into its neighbour, where the touch points meet.
            let r = ca.r.min(cb.r);
            if ca.centre.distance(cb.centre) <= self.opts.accuracy.max(SEED_REL_RADIUS * r) {
                break;
            }
            if ca.touch.distance(cb.touch) <= MEETING_REL_RADIUS * r {
                return None;
            }
            let pm = lerp(pa, pb, 0.5);
            let cm = self.edge_contact(e, pm)?;
            if cm.seg == Element::Edge(e) && again.is_none() {
                *again = Some(cm);
            }
            if cm.seg == ca.seg {
                (pa, ca) = (pm, cm);
            } else {
                // The same element as at b, or a third one between: bisect towards a.
                (pb, cb) = (pm, cm);
            }
        }
        let r = 0.5 * (ca.r + cb.r);
        if ca.touch.distance(cb.touch) <= DISTINCT_TOUCH_REL_RADIUS * r {
            return None;
        }
        Some(Seed::new(
            [Element::Edge(e), ca.seg, cb.seg],
            0.5 * (ca.centre + cb.centre),
            r,
            [
                (0.5 * (ca.edge_s[0] + cb.edge_s[0]), ca.edge_s[1]),
                (ca.s[0], ca.s[1]),
                (cb.s[0], cb.s[1]),
            ],
        ))
    }
}
