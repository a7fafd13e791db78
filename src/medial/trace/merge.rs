//! Junctions found twice.
//!
//! A junction is located exactly on the four elements the arriving seam met; where more
//! elements touch the same ball to the accuracy, they are added (a non-generic junction). Two
//! seams arriving at such a ball on different quadruples of its elements locate it on each:
//! where the elements are nearly in a non-generic position (a faceted arc of short reflex
//! edges, symmetric faces), the exact solutions of the two quadruples lie apart by far more
//! than the accuracy though each ball touches all the elements of the other to it. Found
//! again so, the same ball is two junctions close together, each with some of its seams: the
//! seams between them are one ball long, others run out of both along one curve, and the
//! sheets between them do not close.
//!
//! After tracing, a junction is merged into another of the same solid when every element it
//! touches is one the other touches, every touch point of it is within the separation
//! (`√(8·r·a)`, where verify counts one place) of one of the other's, and the two centres and
//! radii are within that too: the other's ball touches every element of it to the accuracy,
//! at the same places. Junctions touching more elements keep; the seams that ended at the one
//! merged end at the one kept, their end ball moved onto it (its touch points on their
//! elements); a seam left with both ends there, no ball of it farther than the separation,
//! was the step between the two and goes. Junctions of small features close together stay
//! distinct: one of them touches a place the other does not.

use super::queue::keep_where;
use super::tracer::Tracer;
use crate::medial::axis::{Junction, SeamEnd, SeamPoint};
use crate::medial::verify::separation;
use glam::DVec3;

impl Tracer<'_> {
    /// Merges every junction found twice (above) into the one kept; drops the seams left
    /// between them, renumbers the junctions and seams, and returns how many junctions were
    /// merged.
    pub(super) fn merge_junctions_found_twice(&mut self) -> usize {
        let n = self.junctions.len();
        let acc = self.opts.accuracy;
        // The junctions by x, to find each one's neighbours within the largest separation.
        let x = |j: usize| self.junctions[j].point[0];
        let mut by_x: Vec<usize> = (0..n).collect();
        by_x.sort_by(|&a, &b| x(a).total_cmp(&x(b)));
        let largest = self.junctions.iter().map(|j| j.radius).fold(0.0, f64::max);
        let reach = separation(largest, acc);
        let near = |a: usize| {
            let lo = by_x.partition_point(|&j| x(j) < x(a) - reach);
            let hi = by_x.partition_point(|&j| x(j) <= x(a) + reach);
            by_x[lo..hi].to_vec()
        };
        // Those touching more elements first: they keep.
        let rank = |j: usize| (std::cmp::Reverse(self.junctions[j].segments.len()), j);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&j| rank(j));
        let mut into: Vec<usize> = (0..n).collect();
        for &a in &order {
            if into[a] != a {
                continue;
            }
            for b in near(a) {
                if rank(b) > rank(a)
                    && into[b] == b
                    && found_twice(&self.junctions[a], &self.junctions[b], acc)
                {
                    into[b] = a;
                }
            }
        }
        let merged = (0..n).filter(|&j| into[j] != j).count();
        if merged == 0 {
            self.drop_steps_in_place();
            return 0;
        }
        // The seams that ended at a merged junction end at the one kept, on its ball.
        for s in &mut self.seams {
            for end in 0..2 {
                let SeamEnd::Junction(j) = s.ends[end] else {
                    continue;
                };
                if into[j] == j {
                    continue;
                }
                let kept = &self.junctions[into[j]];
                s.ends[end] = SeamEnd::Junction(into[j]);
                let elements = if end == 0 {
                    &s.segments
                } else {
                    &s.end_segments
                };
                let k = if end == 0 {
                    0
                } else {
                    s.points.len().saturating_sub(1)
                };
                if let Some(p) = s.points.get(k) {
                    s.points[k] = onto_junction(kept, elements, p);
                }
            }
        }
        self.drop_steps_in_place();
        // Renumber the junctions kept.
        let mut new_id = vec![usize::MAX; n];
        let mut next = 0;
        for j in 0..n {
            if into[j] == j {
                new_id[j] = next;
                next += 1;
            }
        }
        let keep: Vec<bool> = (0..n).map(|j| into[j] == j).collect();
        keep_where(&mut self.junctions, &keep);
        keep_where(&mut self.arrivals, &keep);
        for (id, j) in self.junctions.iter_mut().enumerate() {
            j.id = id;
        }
        for s in &mut self.seams {
            for e in &mut s.ends {
                if let SeamEnd::Junction(j) = e {
                    *j = new_id[*j];
                }
            }
        }
        merged
    }

    /// Drops each seam from a junction back to it whose balls all lie within the separation
    /// of the junction's centre: the step between a junction found twice and the one it was
    /// merged into, or a seam that left a junction and came back to it at once (on an
    /// unresolved junction, whose touch points at one place are named by several elements).
    /// It is no curve of the medial axis.
    fn drop_steps_in_place(&mut self) {
        let drop: Vec<bool> = self
            .seams
            .iter()
            .map(|s| match s.ends {
                [SeamEnd::Junction(a), SeamEnd::Junction(b)] if a == b => {
                    let j = &self.junctions[a];
                    let c = DVec3::from_array(j.point);
                    let sep = separation(j.radius, self.opts.accuracy);
                    s.points
                        .iter()
                        .all(|p| DVec3::new(p.point[0], p.point[1], p.point[2]).distance(c) <= sep)
                }
                _ => false,
            })
            .collect();
        self.stats.duplicate_seams += self.remove_seams(&drop);
    }
}

/// True when junction `b` is junction `a` found again (above): the same solid, every element
/// of `b` one of `a`'s, every touch point of `b` within the separation of one of `a`'s, and
/// the centres and radii within it.
fn found_twice(a: &Junction, b: &Junction, accuracy: f64) -> bool {
    let sep = separation(a.radius.max(b.radius), accuracy);
    let near =
        |p: &[f64; 3], q: &[f64; 3]| DVec3::from_array(*p).distance(DVec3::from_array(*q)) <= sep;
    a.solid == b.solid
        && near(&a.point, &b.point)
        && (a.radius - b.radius).abs() <= sep
        && b.segments.iter().all(|e| a.segments.contains(e))
        && b.touch.iter().all(|t| a.touch.iter().any(|q| near(q, t)))
}

/// The seam point `p`, touching `elements` (slot by slot), moved onto junction `j`'s ball:
/// each slot's touch point is `j`'s on that element nearest the old one (an element `j`
/// touches twice has two), or the old one where `j` does not name the element.
fn onto_junction(j: &Junction, elements: &[crate::model::Element], p: &SeamPoint) -> SeamPoint {
    let touch = elements
        .iter()
        .zip(&p.touch)
        .map(|(e, t)| {
            let old = DVec3::from_array(*t);
            j.segments
                .iter()
                .zip(&j.touch)
                .filter(|(f, _)| *f == e)
                .map(|(_, q)| DVec3::from_array(*q))
                .min_by(|a, b| a.distance(old).total_cmp(&b.distance(old)))
                .map_or(*t, |q| q.to_array())
        })
        .collect();
    SeamPoint {
        point: [j.point[0], j.point[1], j.point[2], j.radius],
        touch,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Element;

    fn junction(segments: &[usize], touch: &[[f64; 3]], point: [f64; 3]) -> Junction {
        Junction {
            id: 0,
            solid: 0,
            point,
            radius: 1.0,
            segments: segments.iter().map(|&f| Element::Face(f)).collect(),
            touch: touch.to_vec(),
            unresolved: false,
        }
    }

    const TOUCH: [[f64; 3]; 5] = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
    ];

    /// A junction touching four of a non-generic junction's five elements at its places, its
    /// centre 20 accuracies away, is that junction found again; one touching an element the
    /// other does not, or a place of its own, or farther than the separation, is not.
    #[test]
    fn a_junction_is_merged_only_into_one_touching_all_its_places() {
        let a = junction(&[0, 1, 2, 3, 4], &TOUCH, [0.0; 3]);
        let acc = 1e-4;
        let sep = separation(1.0, acc);
        let moved = [20.0 * acc, 0.0, 0.0];
        let b = junction(&[0, 1, 2, 3], &TOUCH[..4], moved);
        assert!(found_twice(&a, &b, acc));
        assert!(!found_twice(&b, &a, acc));
        let other = junction(&[0, 1, 2, 5], &TOUCH[..4], moved);
        assert!(!found_twice(&a, &other, acc));
        let mut touch = TOUCH;
        touch[3] = [0.0, -1.0, 0.0];
        let elsewhere = junction(&[0, 1, 2, 3], &touch[..4], moved);
        assert!(!found_twice(&a, &elsewhere, acc));
        let far = junction(&[0, 1, 2, 3], &TOUCH[..4], [1.5 * sep, 0.0, 0.0]);
        assert!(!found_twice(&a, &far, acc));
    }

    /// A seam's end ball moved onto a junction takes the junction's centre, radius and its
    /// touch points on the seam's elements; an element touched twice gives the nearer one.
    #[test]
    fn a_seam_end_moved_onto_a_junction_touches_its_places() {
        let j = junction(&[0, 1, 2, 2], &TOUCH[..4], [0.0; 3]);
        let p = SeamPoint {
            point: [1e-3, 0.0, 0.0, 1.001],
            touch: vec![[1.0, 1e-3, 0.0], [0.0, 0.0, -0.99], [7.0, 7.0, 7.0]],
        };
        let elements = [Element::Face(0), Element::Face(2), Element::Face(9)];
        let q = onto_junction(&j, &elements, &p);
        assert_eq!(q.point, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(q.touch, vec![TOUCH[0], TOUCH[3], [7.0, 7.0, 7.0]]);
    }
}
