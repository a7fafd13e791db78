//! Seam halves that stop at one place, joined.
//!
//! Where a file's faces do not quite meet (an edge written along one surface and off the
//! other by the file's gap, a face tilted against its neighbour within the tangent
//! tolerance), a seam whose touch point passes from one element to the next can be traced
//! up to that crossing from both sides, and from neither side past it: the ball solved on
//! the next element's system lands off the crossing by about the gap plus `r` times the
//! tilt, and the hand-over is refused (or the touch point turns back at a smooth edge and
//! oscillates). The two halves then end open, facing each other, one crossing apart. Both are
//! exact up to their ends; the curve between them is the crossing itself.
//!
//! After tracing, two open ends of different seams are joined into one seam when they are the
//! same ball touching the same places to the file's precision: the same elements in every slot
//! but at most one (the element handed from and the one handed to); centres, radii and touch
//! points, slot by slot, within `4·a + 2·g` (`a` the accuracy, `g` the largest gap of the file
//! about the elements touched: of a face and its neighbours); and the seams running on
//! through the joint (the direction in which the first arrives is the one in which the second
//! leaves). Both ends are exact medial balls of their own elements, so the balls between them
//! are within half that distance of one. In a file without gaps, where faces meet as written,
//! the two ends must be the same ball to the accuracy.

use super::tracer::Tracer;
use crate::medial::axis::{Handover, Seam, SeamEnd, SeamPoint};
use crate::medial::verify::unresolved_points;
use crate::model::Element;
use glam::DVec3;

/// An open end met at the joint: seam `seam`, its first (`end` 0) or last point.
#[derive(Clone, Copy, Debug, PartialEq)]
struct OpenEnd {
    seam: usize,
    end: usize,
}

/// How two open ends are joined: `b`'s slots reordered by `perm` (slot `i` of the joint is
/// `b`'s slot `perm[i]`), and the centres' distance (the closest pair is joined first).
struct Joint {
    a: OpenEnd,
    b: OpenEnd,
    perm: [usize; 3],
    distance: f64,
}

impl Tracer<'_> {
    /// Joins the seams whose open ends are one crossing apart (see the module's note);
    /// returns how many joints were made.
    pub(super) fn join_open_halves(&mut self) -> usize {
        let mut joined = 0;
        while let Some(j) = self.best_joint() {
            self.join(&j);
            joined += 1;
        }
        if joined > 0 {
            for (id, s) in self.seams.iter_mut().enumerate() {
                s.id = id;
            }
            self.stats.points = self.seams.iter().map(|s| s.points.len()).sum();
        }
        joined
    }

    /// The closest pair of open ends that may be joined.
    fn best_joint(&self) -> Option<Joint> {
        let ends: Vec<OpenEnd> = self
            .seams
            .iter()
            .enumerate()
            .flat_map(|(k, s)| {
                (0..2)
                    .filter(move |&e| matches!(s.ends[e], SeamEnd::Open(_)))
                    .map(move |end| OpenEnd { seam: k, end })
            })
            .collect();
        let mut best: Option<Joint> = None;
        for (i, &a) in ends.iter().enumerate() {
            for &b in &ends[i + 1..] {
                if a.seam == b.seam {
                    continue;
                }
                if let Some(j) = self.joint(a, b) {
                    if best.as_ref().is_none_or(|x| j.distance < x.distance) {
                        best = Some(j);
                    }
                }
            }
        }
        best
    }

    /// How open ends `a` and `b` join, if they are one crossing apart.
    fn joint(&self, a: OpenEnd, b: OpenEnd) -> Option<Joint> {
        let (sa, sb) = (&self.seams[a.seam], &self.seams[b.seam]);
        if sa.solid != sb.solid {
            return None;
        }
        let (Some(pa), ea) = sa.at_end(a.end) else {
            return None;
        };
        let (Some(pb), eb) = sb.at_end(b.end) else {
            return None;
        };
        if ea.len() != 3 || eb.len() != 3 || pa.touch.len() != 3 || pb.touch.len() != 3 {
            return None;
        }
        let ball = |p: &SeamPoint| (DVec3::new(p.point[0], p.point[1], p.point[2]), p.point[3]);
        let ((ca, ra), (cb, rb)) = (ball(pa), ball(pb));
        let touch = |p: &SeamPoint, k: usize| DVec3::from_array(p.touch[k]);
        let gap = ea
            .iter()
            .chain(eb)
            .map(|&e| match e {
                Element::Face(f) => self.gap_about(f),
                _ => self.element_gap(e),
            })
            .fold(0.0, f64::max);
        let acc = self.opts.accuracy;
        // The slot order that matches the elements (all but one) and brings the touch points
        // closest.
        let perm = PERMUTATIONS
            .iter()
            .filter(|p| (0..3).filter(|&i| ea[i] != eb[p[i]]).count() <= 1)
            .min_by(|p, q| {
                let d = |p: &[usize; 3]| -> f64 {
                    (0..3).map(|i| touch(pa, i).distance(touch(pb, p[i]))).sum()
                };
                d(p).total_cmp(&d(q))
            })
            .copied()?;
        let tol = 4.0 * acc + 2.0 * gap;
        let distance = ca.distance(cb);
        let same_places = (0..3).all(|i| touch(pa, i).distance(touch(pb, perm[i])) <= tol);
        if distance > tol || (ra - rb).abs() > tol || !same_places {
            return None;
        }
        // Running on through the joint: `a` arrives in the direction `b` leaves in.
        let (arrive, leave) = (heading(sa, a.end), heading(sb, b.end));
        if arrive.dot(-leave) <= 0.0 {
            return None;
        }
        Some(Joint {
            a,
            b,
            perm,
            distance,
        })
    }

    /// Makes joint `j`: the seam of `j.a`, oriented to end there, runs on into the seam of
    /// `j.b`, oriented to start there with its slots in `j.a`'s order; the second seam goes.
    fn join(&mut self, j: &Joint) {
        let mut second = self.seams[j.b.seam].clone();
        if j.b.end == 1 {
            reverse(&mut second);
        }
        permute(&mut second, &j.perm);
        let first = &mut self.seams[j.a.seam];
        if j.a.end == 0 {
            reverse(first);
        }
        let n = first.points.len();
        // The one slot whose element differs: handed over at the joint.
        if let Some(k) = (0..3).find(|&k| first.end_segments[k] != second.segments[k]) {
            first.handovers.push(Handover {
                point: n,
                from: first.end_segments[k],
                to: second.segments[k],
            });
        }
        first
            .handovers
            .extend(second.handovers.into_iter().map(|h| Handover {
                point: h.point + n,
                ..h
            }));
        first.points.extend(second.points);
        first.ends[1] = second.ends[1].clone();
        first.end_segments = second.end_segments;
        first.trace_seconds += second.trace_seconds;
        first.unresolved = unresolved_points(first, self.opts.accuracy);
        self.seams.remove(j.b.seam);
    }
}

/// The six orders of three slots.
const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The unit direction in which seam `s`'s centre moves out through end `end` (0: backwards
/// from its first point, else on from its last); zero for a seam of one point.
fn heading(s: &Seam, end: usize) -> DVec3 {
    let c = |p: &SeamPoint| DVec3::new(p.point[0], p.point[1], p.point[2]);
    let n = s.points.len();
    if n < 2 {
        return DVec3::ZERO;
    }
    let (inner, outer) = if end == 0 {
        (&s.points[1], &s.points[0])
    } else {
        (&s.points[n - 2], &s.points[n - 1])
    };
    (c(outer) - c(inner)).normalize_or_zero()
}

/// Seam `s` run backwards: its points, ends and elements reversed, its hand-overs reversed in
/// order and sense (a hand-over at point `p` is at point `n − 1 − p`, as a seed's backward
/// run is reversed).
pub(super) fn reverse(s: &mut Seam) {
    let n = s.points.len();
    s.points.reverse();
    s.ends.swap(0, 1);
    std::mem::swap(&mut s.segments, &mut s.end_segments);
    s.handovers = reversed_handovers(&s.handovers, n);
    s.unresolved = s.unresolved.iter().rev().map(|&k| n - 1 - k).collect();
}

/// The hand-overs of a run of `n` points, for the run reversed: in reverse order, each from
/// the element it was to, at point `n − 1 − p` (the ball on both elements stays the same).
pub(super) fn reversed_handovers(handovers: &[Handover], n: usize) -> Vec<Handover> {
    handovers
        .iter()
        .rev()
        .map(|h| Handover {
            point: n - 1 - h.point,
            from: h.to,
            to: h.from,
        })
        .collect()
}

/// Seam `s` with its slots reordered: slot `i` becomes what was slot `perm[i]`.
fn permute(s: &mut Seam, perm: &[usize; 3]) {
    let order = |v: &[Element]| -> Vec<Element> { perm.iter().map(|&k| v[k]).collect() };
    s.segments = order(&s.segments);
    s.end_segments = order(&s.end_segments);
    for p in &mut s.points {
        if p.touch.len() == 3 {
            p.touch = perm.iter().map(|&k| p.touch[k]).collect();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Boundary;
    use crate::medial::axis::OpenReason;
    use crate::medial::solver::SolveStatus;
    use crate::medial::TraceOptions;

    /// What a join test starts from: the L-bracket traced, one of its seams with a hand-over
    /// split there into the two halves that would be traced towards it from both ends (each
    /// ending open at the crossing, the second traced from its far end, its slots in another
    /// order), and what the seam was.
    struct Split {
        halves: [Seam; 2],
        whole: Seam,
        accuracy: f64,
    }

    fn split() -> (crate::model::Model, crate::classify::Classification, Split) {
        let (m, class, mat) = crate::testing::traced("l_bracket.step");
        let accuracy = TraceOptions::for_model(&m).accuracy;
        let whole = mat
            .seams
            .iter()
            .find(|s| {
                s.handovers.len() == 1
                    && (3..s.points.len() - 3).contains(&s.handovers[0].point)
                    && !s.is_open()
            })
            .expect("a seam of the L-bracket hands a touch point over")
            .clone();
        let h = whole.handovers[0].clone();
        let open = SeamEnd::Open(OpenReason::NoSeamPointAfterHandover {
            from: h.from,
            to: h.to,
            status: SolveStatus::MaxIter,
            moved: 0.0,
        });
        let first = Seam {
            ends: [whole.ends[0].clone(), open.clone()],
            end_segments: whole.segments.clone(),
            points: whole.points[..=h.point].to_vec(),
            handovers: vec![],
            ..whole.clone()
        };
        let mut second = Seam {
            ends: [open, whole.ends[1].clone()],
            segments: whole.end_segments.clone(),
            points: whole.points[h.point..].to_vec(),
            handovers: vec![],
            ..whole.clone()
        };
        reverse(&mut second);
        permute(&mut second, &[1, 2, 0]);
        let split = Split {
            halves: [first, second],
            whole,
            accuracy,
        };
        (m, class, split)
    }

    /// Moves the centre of the ball at the open end (the first point) of the second half by
    /// `by` along x.
    fn shift_second(s: &mut Split, by: f64) {
        let p = s.halves[1].points.last_mut().expect("points");
        p.point[0] += by;
    }

    /// Joins the halves in a tracer of the L-bracket; returns the joints made and the seams.
    fn join_halves(
        m: &crate::model::Model,
        class: &crate::classify::Classification,
        s: &Split,
    ) -> (usize, Vec<Seam>) {
        let boundary = Boundary::new(m);
        let opts = TraceOptions::for_model(m);
        let mut t = Tracer::new(m, &boundary, class, &opts);
        t.seams = s.halves.to_vec();
        let n = t.join_open_halves();
        (n, t.seams)
    }

    /// Two halves of a seam, stopped one accuracy apart at the crossing where a touch point
    /// is handed over, are joined back into the seam: its ends, its elements at both ends
    /// in its slot order, its hand-over, and every ball with its touch points in their slots.
    #[test]
    fn two_halves_that_stop_at_one_place_are_joined_into_the_seam() {
        let (m, class, mut s) = split();
        let a = s.accuracy;
        shift_second(&mut s, a);
        let (n, seams) = join_halves(&m, &class, &s);
        assert_eq!((n, seams.len()), (1, 1), "joined");
        let (joined, whole) = (&seams[0], &s.whole);
        assert_eq!(joined.ends, whole.ends);
        assert_eq!(joined.segments, whole.segments);
        assert_eq!(joined.end_segments, whole.end_segments);
        let h = whole.handovers[0].clone();
        let at = |k: usize| joined.handovers.iter().find(|x| x.point == k);
        let handed = at(h.point + 1).expect("hand-over at the joint");
        assert_eq!((handed.from, handed.to), (h.from, h.to));
        // The crossing's ball is in both halves: once before the joint, once after it.
        assert_eq!(joined.points.len(), whole.points.len() + 1);
        for (k, p) in whole.points.iter().enumerate() {
            let q = &joined.points[if k <= h.point { k } else { k + 1 }];
            for (a, b) in p.touch.iter().zip(&q.touch) {
                assert!(
                    DVec3::from_array(*a).distance(DVec3::from_array(*b)) < 1e-12,
                    "point {k}: touch {a:?} in the seam, {b:?} joined"
                );
            }
        }
    }

    /// The join is refused where the halves do not stop at one place: ends twenty
    /// accuracies apart in a file without gaps; a second half on other elements in two of
    /// its slots; a second half that runs back the way the first came.
    #[test]
    fn halves_apart_on_other_elements_or_doubling_back_are_not_joined() {
        let (m, class, mut s) = split();
        let a = s.accuracy;
        shift_second(&mut s, 20.0 * a);
        assert_eq!(join_halves(&m, &class, &s).0, 0, "20 accuracies apart");

        let (m, class, mut s) = split();
        let last = s.halves[1].end_segments.len() - 1;
        let other = (0..m.faces.len())
            .map(Element::Face)
            .filter(|e| !s.whole.segments.contains(e) && !s.whole.end_segments.contains(e))
            .take(2)
            .collect::<Vec<_>>();
        s.halves[1].end_segments[last] = other[0];
        s.halves[1].end_segments[last - 1] = other[1];
        assert_eq!(join_halves(&m, &class, &s).0, 0, "two slots on other faces");

        let (m, class, mut s) = split();
        let first = s.halves[0].clone();
        let n = first.points.len();
        s.halves[1].points = first.points[n - 3..].to_vec();
        s.halves[1].end_segments = first.end_segments.clone();
        s.halves[1].segments = first.end_segments.clone();
        s.halves[1].ends = [s.whole.ends[1].clone(), first.ends[1].clone()];
        assert_eq!(join_halves(&m, &class, &s).0, 0, "doubling back");
    }
}
