//! Seams that run through a junction.
//!
//! A seam ends where a fourth element comes as close as `r`: at a junction. A step longer
//! than the distance between two junctions close together can carry a seam across the
//! second without seeing it (a touch point on a faceted face converging to the face's other
//! place, where the ball touches that face twice): the seam then runs on, over the junction,
//! along the curve that the seams leaving that junction trace too. Its balls are medial (the
//! other seams have the same ones), but it is one curve twice, and the junction it crossed
//! and the one it left from each count a seam end too many.
//!
//! After tracing, a seam is dropped when a junction's centre (not at one of its ends) lies on
//! it, with the junction's radius, and every interior ball of it lies on another seam that
//! names every element the ball touches (the seam's elements at that ball, after the
//! hand-overs before it). The balls may be covered by different seams: a seam that passes a
//! junction where a touch point is handed from one reflex edge to the next at their shared
//! vertex (a faceted profile's crease, where a third seam arrives along the crease) runs along
//! one seam leaving the junction before the hand-over and another after it. A vertex touched
//! (or an edge touched at its end vertex, where a touch point is handed from one edge to the
//! next through it) is named by a seam naming an edge at that vertex: where two kinked
//! outlines face each other, the hand-over comes just past the junction, along the seam
//! leaving it on the next edge. The longest such seams go first, each checked again against
//! the seams left.

use super::options::MAX_TURN_RAD;
use super::queue::named;
use super::tracer::Tracer;
use super::unknowns::along_chord;
use crate::medial::axis::{Seam, SeamEnd};
use crate::model::Element;
use glam::DVec3;

/// How far, in accuracies, a point may be from a seam's polyline besides the polyline's own
/// sag (`chord·MAX_TURN_RAD/8`) and still lie on the seam.
pub(super) const ON_SEAM_REL_ACCURACY: f64 = 10.0;

impl Tracer<'_> {
    /// Drops every seam that runs through a junction along other seams (above); renumbers
    /// the rest and returns how many were dropped.
    pub(super) fn drop_seams_through_junctions(&mut self) -> usize {
        let slack = ON_SEAM_REL_ACCURACY * self.opts.accuracy;
        let mut candidates: Vec<usize> = (0..self.seams.len())
            .filter(|&k| self.through_junction(&self.seams[k], slack))
            .collect();
        if candidates.is_empty() {
            return 0;
        }
        candidates.sort_by_key(|&k| std::cmp::Reverse((self.seams[k].points.len(), k)));
        let mut dropped = vec![false; self.seams.len()];
        for k in candidates {
            if self.covered_by_others(k, &dropped, slack) {
                dropped[k] = true;
            }
        }
        self.remove_seams(&dropped)
    }

    /// True when the centre of a junction of `s`'s solid other than its end junctions lies on
    /// `s`'s polyline with the radius `s` has there.
    fn through_junction(&self, s: &Seam, slack: f64) -> bool {
        let ends: Vec<usize> = s
            .ends
            .iter()
            .filter_map(|e| match e {
                SeamEnd::Junction(j) => Some(*j),
                _ => None,
            })
            .collect();
        // The box of its centres, widened by the most any chord's sag allows: a junction
        // outside it is not on the seam (the test stays linear in the junctions).
        let centre = |k: usize| {
            let p = s.points[k].point;
            DVec3::new(p[0], p[1], p[2])
        };
        let Some(first) = s.points.first().map(|_| centre(0)) else {
            return false;
        };
        let (mut lo, mut hi, mut chord) = (first, first, 0.0f64);
        for k in 1..s.points.len() {
            let c = centre(k);
            (lo, hi) = (lo.min(c), hi.max(c));
            chord = chord.max(c.distance(centre(k - 1)));
        }
        let reach = chord * MAX_TURN_RAD / 8.0 + slack;
        let (lo, hi) = (lo - DVec3::splat(reach), hi + DVec3::splat(reach));
        self.junctions.iter().any(|j| {
            let at = DVec3::from_array(j.point);
            j.solid == s.solid
                && at.cmpge(lo).all()
                && at.cmple(hi).all()
                && !ends.contains(&j.id)
                && ball_on(s, at, j.radius, slack)
        })
    }

    /// True when every interior ball of seam `k` (both balls of a two-point seam) lies on
    /// another seam not `dropped` that names every element seam `k` touches at that ball.
    fn covered_by_others(&self, k: usize, dropped: &[bool], slack: f64) -> bool {
        let s = &self.seams[k];
        let others: Vec<(&Seam, Vec<Element>)> = self
            .seams
            .iter()
            .enumerate()
            .filter(|&(m, t)| m != k && !dropped[m] && t.solid == s.solid)
            .map(|(_, t)| (t, named(t)))
            .collect();
        let touched = touched_at(s);
        let n = s.points.len();
        let inner = if n > 2 { 1..n - 1 } else { 0..n };
        inner.into_iter().all(|i| {
            let p = s.points[i].point;
            let c = DVec3::new(p[0], p[1], p[2]);
            let touch = &s.points[i].touch;
            others.iter().any(|(t, theirs)| {
                touched[i].iter().any(|set| {
                    set.iter().all(|&e| {
                        theirs.contains(&e) || self.named_at_vertex(e, theirs, touch, slack)
                    })
                }) && ball_on(t, c, p[3], slack)
            })
        })
    }

    /// True when element `e` (a vertex, or an edge), touched at one of the points `touch`
    /// within `slack` of a vertex of it, is named by `theirs` through that vertex: the vertex
    /// itself or an edge ending there. A seam handed from one edge to the next through their
    /// shared vertex (a kinked outline) touches the vertex and the edge's end there; the seam
    /// leaving the junction just past it names the next edge (0603_SMD's lettering).
    fn named_at_vertex(
        &self,
        e: Element,
        theirs: &[Element],
        touch: &[[f64; 3]],
        slack: f64,
    ) -> bool {
        let vertices: &[usize] = match e {
            Element::Vertex(ref v) => std::slice::from_ref(v),
            Element::Edge(g) => &self.model.edges[g].vertices,
            Element::Face(_) => return false,
        };
        vertices.iter().any(|&v| {
            let at = self.model.vertices[v].point;
            touch
                .iter()
                .any(|q| DVec3::from_array(*q).distance(at) <= slack)
                && theirs.iter().any(|x| match *x {
                    Element::Vertex(w) => w == v,
                    Element::Edge(h) => self.model.edges[h].vertices.contains(&v),
                    Element::Face(_) => false,
                })
        })
    }
}

/// The elements seam `s` touches at each of its points: its first elements with the
/// hand-overs before the point made; at a hand-over's point (which is on both elements) also
/// with that hand-over made.
pub(super) fn touched_at(s: &Seam) -> Vec<[Vec<Element>; 2]> {
    let mut now = s.segments.clone();
    let hand = |now: &mut Vec<Element>, from: Element, to: Element| {
        if let Some(slot) = now.iter_mut().find(|e| **e == from) {
            *slot = to;
        }
    };
    let mut out = Vec::with_capacity(s.points.len());
    let mut h = 0;
    for i in 0..s.points.len() {
        let before = now.clone();
        while let Some(ho) = s.handovers.get(h).filter(|ho| ho.point <= i) {
            hand(&mut now, ho.from, ho.to);
            h += 1;
        }
        out.push([before, now.clone()]);
    }
    out
}

/// True when the ball `(c, r)` lies on seam `s`'s polyline of balls: within the chord's sag
/// (at [`MAX_TURN_RAD`] per step) plus `slack` of a chord, with the radius interpolated there
/// within the same.
pub(super) fn ball_on(s: &Seam, c: DVec3, r: f64, slack: f64) -> bool {
    s.points.windows(2).any(|w| {
        let (a, b) = (w[0].point, w[1].point);
        let (pa, pb) = (DVec3::new(a[0], a[1], a[2]), DVec3::new(b[0], b[1], b[2]));
        let t = along_chord(c, pa, pb);
        let tol = pa.distance(pb) * MAX_TURN_RAD / 8.0 + slack;
        pa.lerp(pb, t).distance(c) <= tol && (a[3] + (b[3] - a[3]) * t - r).abs() <= tol
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::axis::{Handover, SeamPoint};

    fn seam(points: &[[f64; 4]]) -> Seam {
        Seam {
            id: 0,
            solid: 0,
            segments: vec![Element::Face(0), Element::Face(1), Element::Face(2)],
            ends: [SeamEnd::Closed, SeamEnd::Closed],
            end_segments: vec![Element::Face(0), Element::Face(1), Element::Face(2)],
            points: points
                .iter()
                .map(|&point| SeamPoint {
                    point,
                    touch: vec![[0.0; 3]; 3],
                })
                .collect(),
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        }
    }

    /// A ball on a chord, with the radius interpolated there, is on the seam; one beside it,
    /// or with another radius, is not.
    #[test]
    fn a_ball_is_on_a_seam_within_its_chords_sag() {
        let s = seam(&[[0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 2.0]]);
        let slack = 1e-6;
        assert!(ball_on(&s, DVec3::new(0.5, 0.0, 0.0), 1.5, slack));
        // The sag allowed on a chord of 1 is 0.15 / 8.
        assert!(ball_on(&s, DVec3::new(0.5, 0.018, 0.0), 1.5, slack));
        assert!(!ball_on(&s, DVec3::new(0.5, 0.02, 0.0), 1.5, slack));
        assert!(!ball_on(&s, DVec3::new(0.5, 0.0, 0.0), 1.6, slack));
        assert!(!ball_on(&s, DVec3::new(1.5, 0.0, 0.0), 2.0, slack));
    }

    /// The elements at each point follow the hand-overs: at a hand-over's point both sets.
    #[test]
    fn the_elements_at_each_point_follow_the_hand_overs() {
        let mut s = seam(&[[0.0; 4]; 4]);
        s.handovers = vec![
            Handover {
                point: 1,
                from: Element::Face(1),
                to: Element::Edge(7),
            },
            Handover {
                point: 2,
                from: Element::Edge(7),
                to: Element::Edge(8),
            },
        ];
        let (f, e) = (Element::Face, Element::Edge);
        let at = touched_at(&s);
        assert_eq!(at[0][0], vec![f(0), f(1), f(2)]);
        assert_eq!(at[0][1], vec![f(0), f(1), f(2)]);
        assert_eq!(at[1], [vec![f(0), f(1), f(2)], vec![f(0), e(7), f(2)]]);
        assert_eq!(at[2], [vec![f(0), e(7), f(2)], vec![f(0), e(8), f(2)]]);
        assert_eq!(at[3], [vec![f(0), e(8), f(2)], vec![f(0), e(8), f(2)]]);
    }
}
