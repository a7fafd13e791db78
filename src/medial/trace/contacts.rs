//! Non-generic seams: a fourth (fifth …) element touching every ball of a seam.
//!
//! A seam is traced on three segments, but by symmetry more may touch each of its balls: the
//! seam from a square pyramid's apex is touched by all four side faces, the axis of a square
//! pocket's end by its four walls. Their touch points lie on one circle round the seam (every
//! contact normal makes the same angle with the centre's motion), and the sheets along the
//! seam lie between neighbours round that circle: the sides of the polygon of touch points,
//! not its diagonals (which are no sheet at all: the pyramid's two opposite faces are
//! equidistant only on the seam itself). Left as a triplet, the seam named one diagonal
//! sheet and missed two sides, and those sheets' boundaries stayed open at both its ends.
//!
//! After tracing, each seam's middle ball is searched for other elements touching it (the
//! search a non-generic junction makes, [`Tracer::more_contacts`]); an element found there
//! that touches every interior ball of the seam is added to it, with its touch point at every
//! ball, and the seam's slots are put in their order round the circle. The same seam traced
//! from two triplets of its contacts is then seen to be one, and traced once.

use super::options::SAME_PLACE_REL_ACCURACY;
use super::queue::{named, runs_along};
use super::through::{ball_on, ON_SEAM_REL_ACCURACY};
use super::tracer::Start;
use super::tracer::Tracer;
use super::unknowns::seam_x;
use crate::geom::distance::nearest_on_edge;
use crate::medial::axis::{Handover, Junction, Node, Seam, SeamEnd, SeamPoint};
use crate::medial::verify::{junction_unresolved, separation, unresolved_points};
use crate::model::Element;
use glam::DVec3;
use std::collections::HashMap;

impl Tracer<'_> {
    /// Adds to every seam the elements that touch each of its balls besides its own, slots
    /// ordered round the seam. Where an element added so touches every interior ball but not
    /// the ball at one end (nor does a neighbour it hands its touch point to), and the seam
    /// hands a touch point over at the ball before that end, the hand-over has broken the
    /// symmetry that made the seam non-generic: the seam is split there, at a junction (see
    /// [`Self::split_at`]). Elsewhere the end's touch point is left off the ball, for
    /// `touch_at_radius` to report.
    pub(super) fn add_more_contacts(&mut self) {
        let mut n = 0;
        while n < self.seams.len() {
            if let Some(extra) = self.contacts_along(&self.seams[n]) {
                let off: Vec<usize> = (0..2)
                    .filter(|&end| extra.iter().any(|x| !x.touches_end[end]))
                    .collect();
                let original = self.seams[n].clone();
                let points = original.points.len();
                // Split only where a hand-over at that ball is the event located exactly.
                let split = match off[..] {
                    [end] if points >= 3 => Some(if end == 0 { 1 } else { points - 2 }),
                    _ => None,
                }
                .filter(|&k| original.handovers.iter().any(|h| h.point == k));
                let accuracy = self.opts.accuracy;
                let s = &mut self.seams[n];
                for x in &extra {
                    s.segments.push(x.ends[0]);
                    s.end_segments.push(x.ends[1]);
                    for (p, t) in s.points.iter_mut().zip(&x.touch) {
                        p.touch.push(t.to_array());
                    }
                }
                put_slots_in_order(s);
                s.unresolved = unresolved_points(s, accuracy);
                if let Some(k) = split {
                    self.split_at(n, original, k, &extra);
                }
            }
            n += 1;
            if !self.queue.is_empty() {
                self.run_queue();
            }
        }
        self.stats.points = self.seams.iter().map(|s| s.points.len()).sum();
    }

    /// Splits seam `n` (whose further contacts `extra` were just added; `original` is it
    /// without them) at its ball `k` (its second or last but one): the piece from that ball
    /// to the end where the contacts do not all touch keeps only the seam's own three, and
    /// ends at a junction at ball `k`, which touches all of them. The sheets round that
    /// junction (between neighbours round the non-generic piece, and all three of the other
    /// piece's) that only one piece bounds are closed by one more seam, when they are the
    /// three sheets of one triplet: it is queued from the junction, leaving along the plane
    /// of its touch points on the side where the element it omits recedes (along the other
    /// piece where the contacts round a circle leave that side unresolved).
    fn split_at(&mut self, n: usize, original: Seam, k: usize, extra: &[Extra]) {
        let accuracy = self.opts.accuracy;
        let last = k + 1 == original.points.len() - 1;
        let own_at_k = super::through::touched_at(&original)[k][1].clone();
        let ball = original.points[k].clone();
        let centre = |p: &SeamPoint| DVec3::new(p.point[0], p.point[1], p.point[2]);
        let c = centre(&ball);
        let r = ball.point[3];
        let id = self.junctions.len();
        let mut segments = own_at_k.clone();
        segments.extend(extra.iter().map(|x| x.element));
        let mut touch = ball.touch.clone();
        touch.extend(extra.iter().map(|x| x.touch[k].to_array()));
        let mut junction = Junction {
            id,
            solid: original.solid,
            point: c.to_array(),
            radius: r,
            segments: segments.clone(),
            touch: touch.clone(),
            unresolved: false,
        };
        junction.unresolved = junction_unresolved(&junction, accuracy);
        // The piece of three contacts, and the non-generic piece cut short at ball `k`.
        let mut rest = original.clone();
        rest.id = self.seams.len();
        let along_rest;
        let s = &mut self.seams[n];
        if last {
            rest.points = original.points[k..].to_vec();
            rest.segments = own_at_k;
            rest.ends[0] = SeamEnd::Junction(id);
            rest.handovers = shifted(&original.handovers, k);
            s.points.truncate(k + 1);
            s.ends[1] = SeamEnd::Junction(id);
            s.end_segments = ordered(&segments, &s.points[k].touch, &touch);
            s.handovers.retain(|h| h.point <= k);
            along_rest = centre(&rest.points[1]) - c;
        } else {
            rest.points = original.points[..=k].to_vec();
            rest.end_segments = own_at_k;
            rest.ends[1] = SeamEnd::Junction(id);
            rest.handovers.retain(|h| h.point < k);
            s.points.drain(..k);
            s.ends[0] = SeamEnd::Junction(id);
            s.segments = ordered(&segments, &s.points[0].touch, &touch);
            s.handovers = shifted(&s.handovers, k);
            along_rest = centre(&rest.points[k - 1]) - c;
        }
        s.unresolved = unresolved_points(s, accuracy);
        rest.unresolved = unresolved_points(&rest, accuracy);
        // The sheets round the junction that one piece alone bounds.
        let mut once: HashMap<[Element; 2], usize> = HashMap::new();
        let mut count = |a: Element, b: Element| {
            *once.entry(if a < b { [a, b] } else { [b, a] }).or_default() += 1;
        };
        let round = if last { &s.end_segments } else { &s.segments };
        for i in 0..round.len() {
            count(round[i], round[(i + 1) % round.len()]);
        }
        let own = if last {
            &rest.segments
        } else {
            &rest.end_segments
        };
        for (i, j) in [(0, 1), (1, 2), (0, 2)] {
            count(own[i], own[j]);
        }
        let unpaired: Vec<[Element; 2]> = once
            .into_iter()
            .filter(|&(_, n)| n == 1)
            .map(|(p, _)| p)
            .collect();
        let mut open = unpaired.concat();
        open.sort();
        open.dedup();
        let arrived = centre(&s.points[if last { k - 1 } else { 1 }]) - c;
        self.junctions.push(junction);
        self.arrivals.push(
            [arrived, along_rest]
                .iter()
                .filter_map(|d| d.try_normalize())
                .collect(),
        );
        self.seams.push(rest);
        if unpaired.len() != 3 || open.len() != 3 {
            return;
        }
        let slots: Vec<usize> = open
            .iter()
            .filter_map(|e| segments.iter().position(|f| f == e))
            .collect();
        let Some(omitted) = (0..segments.len()).find(|i| !slots.contains(i)) else {
            return;
        };
        let t = |i: usize| DVec3::from_array(touch[i]);
        let Some(mut dir) = (t(slots[1]) - t(slots[0]))
            .cross(t(slots[2]) - t(slots[0]))
            .try_normalize()
        else {
            return;
        };
        let recede = dir.dot(t(slots[0]) - t(omitted));
        if recede.abs() <= SAME_PLACE_REL_ACCURACY * accuracy {
            if dir.dot(along_rest) < 0.0 {
                dir = -dir;
            }
        } else if recede < 0.0 {
            dir = -dir;
        }
        let Some(params) = slots
            .iter()
            .map(|&i| self.start_params(segments[i], c, [f64::NAN; 2]))
            .collect::<Option<Vec<_>>>()
        else {
            return;
        };
        self.queue.push_back(Start {
            triplet: [segments[slots[0]], segments[slots[1]], segments[slots[2]]],
            x: seam_x(c, r, [params[0], params[1], params[2]]),
            dir,
            from: Node::Junction(id),
        });
    }

    /// Drops each seam that repeats another from the same node: between the same two nodes,
    /// running along it, every element it names named by the other too (the same
    /// non-generic seam traced from different triplets, told apart only once their other
    /// contacts are added); or, wherever it ends, every ball of each on the other and
    /// touching the same places (the same curve of balls from a non-generic junction found
    /// twice, or on triplets that differ only in which of two contacts at one place they
    /// name). Closed seams, which meet no node, are compared with each other the second way.
    /// The one naming more, or else the one without an open end, or else the one ending at
    /// more nodes, or else the first, is kept.
    /// Renumbers the rest; returns how many were dropped.
    pub(super) fn drop_repeated_seams(&mut self) -> usize {
        let mut at_node: HashMap<Node, Vec<usize>> = HashMap::new();
        for (k, s) in self.seams.iter().enumerate() {
            let mut nodes: Vec<Node> = s.ends.iter().filter_map(|e| e.node()).collect();
            nodes.dedup();
            for n in nodes {
                at_node.entry(n).or_default().push(k);
            }
        }
        let names: Vec<Vec<Element>> = self.seams.iter().map(named).collect();
        let slack = ON_SEAM_REL_ACCURACY * self.opts.accuracy;
        let on = |s: &Seam, t: &Seam| {
            s.points.iter().all(|p| {
                let c = DVec3::new(p.point[0], p.point[1], p.point[2]);
                ball_on(t, c, p.point[3], slack)
            })
        };
        let ends = |s: &Seam| {
            let mut e: Vec<Option<Node>> = s.ends.iter().map(|e| e.node()).collect();
            e.sort();
            e
        };
        // Whether seam `a` is kept over seam `b` when they repeat each other. Of two seams
        // otherwise alike, the one that reaches a node where the other stops (at a curvature
        // limit found a step past a junction) keeps: it ends where the medial axis goes on.
        let rank = |k: usize| {
            let s = &self.seams[k];
            let nodes = s.ends.iter().filter(|e| e.node().is_some()).count();
            (s.segments.len(), !s.is_open(), nodes, std::cmp::Reverse(k))
        };
        let keeps = |a: usize, b: usize| rank(a) > rank(b);
        let repeats = |a: usize, b: usize| {
            let (sa, sb) = (&self.seams[a], &self.seams[b]);
            let named_again = ends(sa) == ends(sb)
                && sa.ends.iter().all(|e| e.node().is_some())
                && names[b].iter().all(|e| names[a].contains(e))
                && runs_along(&sb.points, &sa.points)
                && runs_along(&sa.points, &sb.points);
            // A seam naming more contacts than another along the same balls is that one
            // with a contact it missed (a symmetric ball of four contacts traced once on
            // three of them: the Prusa y-rod holder): `b`'s places need only be `a`'s.
            let within = sa.segments.len() > sb.segments.len();
            let places = same_places(sa, sb, self.opts.accuracy, within);
            named_again || (on(sa, sb) && on(sb, sa) && places)
        };
        let mut drop = vec![false; self.seams.len()];
        let mut groups: Vec<Vec<usize>> = at_node.into_values().filter(|g| g.len() > 1).collect();
        // Closed seams meet no node: they are compared with each other (a seam seeded on a
        // face at its reflex edge, handed onto that edge at once, is the edge's seam traced
        // from the seed of another of its sheets).
        let closed: Vec<usize> = (0..self.seams.len())
            .filter(|&k| {
                self.seams[k]
                    .ends
                    .iter()
                    .all(|e| matches!(e, SeamEnd::Closed))
            })
            .collect();
        if closed.len() > 1 {
            groups.push(closed);
        }
        groups.sort();
        for group in &groups {
            for &b in group {
                if drop[b] {
                    continue;
                }
                drop[b] = group
                    .iter()
                    .any(|&a| a != b && !drop[a] && keeps(a, b) && repeats(a, b));
            }
        }
        self.remove_seams(&drop)
    }

    /// The elements other than `s`'s own that touch every interior ball of `s` (to the
    /// output accuracy, at a place of their own), each with the elements touching the first
    /// and last balls (it or, below, a neighbour) and its touch point at every ball; `None`
    /// when there are none.
    fn contacts_along(&self, s: &Seam) -> Option<Vec<Extra>> {
        let n = s.points.len();
        if n < 3 {
            return None;
        }
        // Every element the seam names (its slots change at hand-overs).
        let own = named(s);
        let ball = |k: usize| {
            let p = &s.points[k];
            let c = DVec3::new(p.point[0], p.point[1], p.point[2]);
            let touch: Vec<DVec3> = p.touch.iter().map(|t| DVec3::from_array(*t)).collect();
            (c, p.point[3], touch)
        };
        let found_at = |k: usize| {
            let (c, r, touch) = ball(k);
            self.more_contacts(s.solid, c, r, &own, &touch)
        };
        let mut extra: Vec<(Element, Vec<Option<DVec3>>)> = found_at(n / 2)
            .into_iter()
            .map(|(seg, _, _)| (seg, vec![None; n]))
            .collect();
        if extra.is_empty() {
            return None;
        }
        for k in 1..n - 1 {
            let found = found_at(k);
            extra.retain_mut(|(seg, at)| {
                let hit = found.iter().find(|f| f.0 == *seg);
                at[k] = hit.map(|f| f.2);
                hit.is_some()
            });
            if extra.is_empty() {
                return None;
            }
        }
        // At the two ends the touch point may meet another (a vertex, where r is 0) or the
        // ball touch more (a junction): the element's nearest point to the centre, or a
        // neighbour's where the touch point has just left the element (at a pinch past an
        // edge touched along the seam, the face beyond it touches the last ball).
        let mut out = vec![];
        for (seg, mut at) in extra {
            let mut ends = [seg; 2];
            let mut touches_end = [true; 2];
            for (end, k) in [0, n - 1].into_iter().enumerate() {
                let (c, r, _) = ball(k);
                let (e, q) = self.touching_at_end(seg, c, r)?;
                ends[end] = e;
                touches_end[end] = (q.distance(c) - r).abs() <= self.opts.accuracy;
                at[k] = Some(q);
            }
            out.push(Extra {
                element: seg,
                ends,
                touch: at.into_iter().collect::<Option<Vec<DVec3>>>()?,
                touches_end,
            });
        }
        Some(out)
    }

    /// The element touching the ball (`c`, `r`) at the end of a seam along which `seg`
    /// touches every ball, and its touch point: `seg`'s nearest point when it is at `r` to
    /// the accuracy; otherwise the nearest of `seg`'s and its neighbours' (an edge's faces, a
    /// vertex's edges and their faces), which the touch point has moved onto.
    pub(super) fn touching_at_end(
        &self,
        seg: Element,
        c: DVec3,
        r: f64,
    ) -> Option<(Element, DVec3)> {
        let own = self.nearest_on_segment(seg, c)?;
        if (own.distance(c) - r).abs() <= self.opts.accuracy {
            return Some((seg, own));
        }
        let faces_of = |e: usize| self.model.edges[e].faces.clone();
        let neighbours: Vec<Element> = match seg {
            Element::Face(_) => vec![],
            Element::Edge(e) => faces_of(e).into_iter().map(Element::Face).collect(),
            Element::Vertex(v) => self.vertex_edges[v]
                .iter()
                .flat_map(|&(e, _)| {
                    std::iter::once(Element::Edge(e))
                        .chain(faces_of(e).into_iter().map(Element::Face))
                })
                .collect(),
        };
        neighbours
            .into_iter()
            .filter_map(|e| Some((e, self.nearest_on_segment(e, c)?)))
            .chain(std::iter::once((seg, own)))
            .min_by(|a, b| a.1.distance(c).total_cmp(&b.1.distance(c)))
    }

    /// The nearest point of segment `seg` to `p`.
    fn nearest_on_segment(&self, seg: Element, p: DVec3) -> Option<DVec3> {
        match seg {
            Element::Face(f) => self
                .boundary
                .nearest_on_face(self.model, f, p, None, f64::INFINITY)
                .map(|h| h.point),
            Element::Edge(e) => Some(nearest_on_edge(self.model, e, p, None).1),
            Element::Vertex(v) => self.model.vertices.get(v).map(|v| v.point),
        }
    }
}

/// An element touching every interior ball of a seam besides its own.
struct Extra {
    element: Element,
    /// The elements touching the first and last balls in its place (it, or a neighbour its
    /// touch point has moved onto).
    ends: [Element; 2],
    /// Its touch point at every ball.
    touch: Vec<DVec3>,
    /// Whether it (or that neighbour) touches the first and last balls at `r` to the
    /// accuracy.
    touches_end: [bool; 2],
}

/// The hand-overs of `h` after point `k`, renumbered from `k`: those of a seam's piece that
/// starts at its point `k` on the elements it touches there after any hand-over at `k`.
fn shifted(h: &[Handover], k: usize) -> Vec<Handover> {
    h.iter()
        .filter(|x| x.point > k)
        .map(|x| Handover {
            point: x.point - k,
            ..x.clone()
        })
        .collect()
}

/// `segments` (with their touch points `touch`, slot by slot) in the order of the touch points
/// `order` (each the nearest of `touch`).
fn ordered(segments: &[Element], order: &[[f64; 3]], touch: &[[f64; 3]]) -> Vec<Element> {
    let d = |a: &[f64; 3], b: &[f64; 3]| DVec3::from_array(*a).distance(DVec3::from_array(*b));
    order
        .iter()
        .map(|q| {
            let i = (0..touch.len())
                .min_by(|&i, &j| d(&touch[i], q).total_cmp(&d(&touch[j], q)))
                .unwrap_or(0);
            segments[i]
        })
        .collect()
}

/// Puts the slots of `s` (its segments, end segments and every point's touch points) in their
/// order round the seam at its middle ball: by the angle of each contact round the centre's
/// motion there. Only a seam with more than three slots is reordered (three are all
/// neighbours).
fn put_slots_in_order(s: &mut Seam) {
    let n = s.points.len();
    if s.segments.len() <= 3 || n < 3 {
        return;
    }
    let centre = |k: usize| {
        let p = s.points[k].point;
        DVec3::new(p[0], p[1], p[2])
    };
    let m = n / 2;
    let touch: Vec<DVec3> = s.points[m]
        .touch
        .iter()
        .map(|t| DVec3::from_array(*t))
        .collect();
    let order = order_round(centre(m), centre(m + 1) - centre(m - 1), &touch);
    let permute = |v: &mut Vec<Element>| *v = order.iter().map(|&i| v[i]).collect();
    permute(&mut s.segments);
    permute(&mut s.end_segments);
    for p in &mut s.points {
        p.touch = order.iter().map(|&i| p.touch[i]).collect();
    }
}

/// The indices of `touch` in their order round the axis through `centre` along `along` (by
/// angle, from the first).
pub(super) fn order_round(centre: DVec3, along: DVec3, touch: &[DVec3]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..touch.len()).collect();
    let Some(t) = along.try_normalize() else {
        return order;
    };
    let flat = |q: DVec3| {
        let d = q - centre;
        d - t * d.dot(t)
    };
    let Some(u) = touch.first().and_then(|&q| flat(q).try_normalize()) else {
        return order;
    };
    let v = t.cross(u);
    let angle = |i: usize| {
        let d = flat(touch[i]);
        let a = d.dot(v).atan2(d.dot(u));
        if a < 0.0 {
            a + std::f64::consts::TAU
        } else {
            a
        }
    };
    order.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    order
}

/// True when the middle ball of seam `b` touches the same places as the nearest ball of seam
/// `a`: each of its touch points within the separation (`√(8·r·a)`), widened by twice `a`'s
/// longest step (the two balls are that far apart along the curve at most), of one of
/// `a`'s. Seams of near-symmetric faces run within the accuracy of each other for a while
/// yet touch places a millimetre apart. With `within`, only `b`'s places need be `a`'s (`a`
/// may touch more).
fn same_places(a: &Seam, b: &Seam, accuracy: f64, within: bool) -> bool {
    let centre = |p: &SeamPoint| DVec3::new(p.point[0], p.point[1], p.point[2]);
    let Some(pb) = b.points.get(b.points.len() / 2) else {
        return false;
    };
    let Some(pa) = a.points.iter().min_by(|x, y| {
        centre(x)
            .distance(centre(pb))
            .total_cmp(&centre(y).distance(centre(pb)))
    }) else {
        return false;
    };
    let step = a
        .points
        .windows(2)
        .map(|w| centre(&w[0]).distance(centre(&w[1])))
        .fold(0.0, f64::max);
    let tol = separation(pb.point[3], accuracy) + 2.0 * step;
    let near =
        |t: &[f64; 3], q: &[f64; 3]| DVec3::from_array(*t).distance(DVec3::from_array(*q)) <= tol;
    pb.touch.iter().all(|t| pa.touch.iter().any(|q| near(t, q)))
        && (within || pa.touch.iter().all(|q| pb.touch.iter().any(|t| near(t, q))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::axis::SeamEnd;

    #[test]
    fn touch_points_are_ordered_round_the_seam() {
        // Four contacts round the z axis, listed with a diagonal between neighbours.
        let c = DVec3::new(1.0, 2.0, 3.0);
        let at = |deg: f64| {
            let a = deg.to_radians();
            c + DVec3::new(a.cos(), a.sin(), -0.5)
        };
        let touch = [at(10.0), at(190.0), at(100.0), at(280.0)];
        let order = order_round(c, DVec3::Z, &touch);
        assert_eq!(order, vec![0, 2, 1, 3]);
        // Looking the other way round, the same neighbours.
        let back = order_round(c, -DVec3::Z, &touch);
        assert_eq!(back, vec![0, 3, 1, 2]);
    }

    /// A seam along the x axis with touch points at `touch` (moved with the centre).
    fn seam(touch: &[[f64; 3]]) -> Seam {
        Seam {
            id: 0,
            solid: 0,
            segments: (0..touch.len()).map(Element::Face).collect(),
            ends: [SeamEnd::Closed, SeamEnd::Closed],
            end_segments: (0..touch.len()).map(Element::Face).collect(),
            points: (0..5)
                .map(|k| {
                    let x = 0.05 * k as f64;
                    SeamPoint {
                        point: [x, 0.0, 0.0, 1.0],
                        touch: touch.iter().map(|t| [t[0] + x, t[1], t[2]]).collect(),
                    }
                })
                .collect(),
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        }
    }

    /// Two seams of the same balls touching the same places (one naming a face where the
    /// other names another face at the same place) are one; seams of the same balls whose
    /// touch points are a millimetre apart (near-symmetric faces) are not. A seam touching
    /// three of another's four places is that one with a contact missed (`within`), and not
    /// the other way round.
    #[test]
    fn seams_of_the_same_balls_repeat_only_where_they_touch_the_same_places() {
        let acc = 1e-4;
        let a = seam(&[[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]);
        let b = seam(&[[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.002, 0.999]]);
        assert!(same_places(&a, &b, acc, false));
        assert!(same_places(&b, &a, acc, false));
        let c = seam(&[[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        assert!(!same_places(&a, &c, acc, false));
        assert!(!same_places(&a, &c, acc, true));
        let d = seam(&[
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ]);
        assert!(!same_places(&a, &d, acc, false));
        assert!(same_places(&d, &a, acc, true), "a's places are d's");
        assert!(!same_places(&a, &d, acc, true), "d's are not all a's");
    }
}
