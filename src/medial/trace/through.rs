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
//! it, with the junction's radius, and every interior ball of it lies on other seams that
//! name every element it names. The longest such seams go first, each checked again
//! against the seams left.

use super::options::MAX_TURN_RAD;
use super::queue::named;
use super::tracer::Tracer;
use super::unknowns::along_chord;
use crate::medial::axis::{Seam, SeamEnd};
use glam::DVec3;

/// How far, in accuracies, a point may be from a seam's polyline besides the polyline's own
/// sag (`chord·MAX_TURN_RAD/8`) and still lie on the seam.
const ON_SEAM_REL_ACCURACY: f64 = 10.0;

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
    /// another seam not `dropped` that names every element seam `k` names.
    fn covered_by_others(&self, k: usize, dropped: &[bool], slack: f64) -> bool {
        let s = &self.seams[k];
        let names = named(s);
        let others: Vec<&Seam> = self
            .seams
            .iter()
            .enumerate()
            .filter(|&(m, t)| {
                m != k && !dropped[m] && t.solid == s.solid && {
                    let theirs = named(t);
                    names.iter().all(|e| theirs.contains(e))
                }
            })
            .map(|(_, t)| t)
            .collect();
        let n = s.points.len();
        let inner = if n > 2 {
            &s.points[1..n - 1]
        } else {
            &s.points[..]
        };
        !others.is_empty()
            && inner.iter().all(|p| {
                let c = DVec3::new(p.point[0], p.point[1], p.point[2]);
                others.iter().any(|t| ball_on(t, c, p.point[3], slack))
            })
    }
}

/// True when the ball `(c, r)` lies on seam `s`'s polyline of balls: within the chord's sag
/// (at [`MAX_TURN_RAD`] per step) plus `slack` of a chord, with the radius interpolated there
/// within the same.
fn ball_on(s: &Seam, c: DVec3, r: f64, slack: f64) -> bool {
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
    use crate::medial::axis::SeamPoint;
    use crate::model::Element;

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
}
