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

use super::queue::{named, runs_along};
use super::tracer::Tracer;
use crate::geom::distance::nearest_on_edge;
use crate::medial::axis::{Node, Seam};
use crate::medial::verify::unresolved_points;
use crate::model::Element;
use glam::DVec3;
use std::collections::HashMap;

impl Tracer<'_> {
    /// Adds to every seam the elements that touch each of its balls besides its own, slots
    /// ordered round the seam.
    pub(super) fn add_more_contacts(&mut self) {
        for n in 0..self.seams.len() {
            let Some(extra) = self.contacts_along(&self.seams[n]) else {
                continue;
            };
            let accuracy = self.opts.accuracy;
            let s = &mut self.seams[n];
            for (seg, touch) in extra {
                s.segments.push(seg);
                s.end_segments.push(seg);
                for (p, t) in s.points.iter_mut().zip(touch) {
                    p.touch.push(t.to_array());
                }
            }
            put_slots_in_order(s);
            s.unresolved = unresolved_points(s, accuracy);
        }
    }

    /// Drops each seam that repeats another between the same two nodes: it runs along it,
    /// and every element it names the other names too (the same non-generic seam traced
    /// from different triplets, told apart only once their other contacts are added). The
    /// one naming more, or else the first, is kept. Renumbers the rest; returns how many
    /// were dropped.
    pub(super) fn drop_repeated_seams(&mut self) -> usize {
        let nodes = |s: &Seam| {
            let (a, b) = (s.ends[0].node()?, s.ends[1].node()?);
            Some([a.min(b), a.max(b)])
        };
        let mut by_nodes: HashMap<[Node; 2], Vec<usize>> = HashMap::new();
        for (k, s) in self.seams.iter().enumerate() {
            if let Some(key) = nodes(s) {
                by_nodes.entry(key).or_default().push(k);
            }
        }
        let mut drop = vec![false; self.seams.len()];
        for group in by_nodes.values().filter(|g| g.len() > 1) {
            let names: Vec<Vec<Element>> = group.iter().map(|&k| named(&self.seams[k])).collect();
            for (m, &b) in group.iter().enumerate() {
                let sb = &self.seams[b];
                let repeats = group.iter().enumerate().any(|(l, &a)| {
                    let sa = &self.seams[a];
                    let keeps_a = sa.segments.len() > sb.segments.len()
                        || (sa.segments.len() == sb.segments.len() && a < b);
                    a != b
                        && !drop[a]
                        && keeps_a
                        && names[m].iter().all(|e| names[l].contains(e))
                        && runs_along(&sb.points, &sa.points)
                        && runs_along(&sa.points, &sb.points)
                });
                drop[b] = repeats;
            }
        }
        self.remove_seams(&drop)
    }

    /// The elements other than `s`'s own that touch every interior ball of `s` (to the
    /// output accuracy, at a place of their own), each with its touch point at every ball;
    /// `None` when there are none.
    fn contacts_along(&self, s: &Seam) -> Option<Vec<(Element, Vec<DVec3>)>> {
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
        // ball touch more (a junction): the element's nearest point to the centre.
        let mut out = vec![];
        for (seg, mut at) in extra {
            for k in [0, n - 1] {
                let (c, _, _) = ball(k);
                at[k] = self.nearest_on_segment(seg, c);
            }
            out.push((seg, at.into_iter().collect::<Option<Vec<DVec3>>>()?));
        }
        Some(out)
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
