//! The queue of seams to trace, and recording what was traced: a seam is not traced twice
//! from the same node on the same elements, and a seam between two nodes that repeats one
//! already traced is dropped.

use super::options::{MAX_SEAMS, SAME_BRANCH};
use super::tracer::Tracer;
use super::unknowns::sorted;
use crate::medial::axis::{Handover, Node, Seam, SeamEnd, SeamPoint};
use crate::medial::verify::unresolved_points;
use crate::model::Element;
use std::collections::HashSet;

impl Tracer<'_> {
    /// Traces queued seams until the queue is empty.
    pub(super) fn run_queue(&mut self) {
        while let Some(start) = self.queue.pop_front() {
            if self.seams.len() >= MAX_SEAMS {
                break;
            }
            // At a junction touching one element in two places, two branches leave on the
            // same elements (a, b and either touch of the element): there the branch is named
            // by its direction, not its elements.
            let twice = match start.from {
                Node::Junction(j) => {
                    let segs = &self.junctions[j].segments;
                    segs.iter().enumerate().any(|(k, s)| segs[..k].contains(s))
                }
                _ => false,
            };
            let key = (sorted(start.triplet), start.from);
            if !twice && !self.visited.insert(key) {
                continue;
            }
            if let Node::Junction(j) = start.from {
                let same = if twice { SAME_BRANCH } else { 1e-6 };
                if self.arrivals[j]
                    .iter()
                    .any(|a| a.distance(start.dir) < same)
                {
                    continue;
                }
            }
            let run = self.march(start.triplet, start.x, start.dir, None);
            self.push_seam(
                start.triplet,
                run.triplet,
                [start.from.into(), run.end],
                run.points,
                run.handovers,
                run.seconds,
            );
        }
    }

    /// Drops each seam that leaves a junction and ends open when another seam arrives at that
    /// junction on the same segments: the same curve, traced completely from its other end
    /// (the open one stopped at a hand-over the other side did not need). Renumbers the rest.
    pub(super) fn drop_open_halves(&mut self) {
        let key = |segs: &[Element]| {
            let mut k = segs.to_vec();
            k.sort();
            k
        };
        let arrived: HashSet<(usize, Vec<Element>)> = self
            .seams
            .iter()
            .filter(|s| !s.is_open())
            .flat_map(|s| {
                let a = match s.ends[0] {
                    SeamEnd::Junction(j) => Some((j, key(&s.segments))),
                    _ => None,
                };
                let b = match s.ends[1] {
                    SeamEnd::Junction(j) => Some((j, key(&s.end_segments))),
                    _ => None,
                };
                a.into_iter().chain(b)
            })
            .collect();
        let before = self.seams.len();
        self.seams.retain(|s| {
            !matches!((&s.ends[0], &s.ends[1]), (SeamEnd::Junction(j), SeamEnd::Open(_))
                if arrived.contains(&(*j, key(&s.segments))))
        });
        self.stats.duplicate_seams += before - self.seams.len();
        for (id, s) in self.seams.iter_mut().enumerate() {
            s.id = id;
        }
        self.stats.points = self.seams.iter().map(|s| s.points.len()).sum();
    }

    /// Records a seam; `triplet` holds the segments at its first point, `last` at its last.
    /// A seam between two proper ends (vertices, junctions) that repeats one already traced
    /// — the same ends on the same segments, reached from the other end after the branch
    /// there was traced — is dropped.
    pub(super) fn push_seam(
        &mut self,
        triplet: [Element; 3],
        last: [Element; 3],
        ends: [SeamEnd; 2],
        points: Vec<SeamPoint>,
        handovers: Vec<Handover>,
        seconds: f64,
    ) {
        let id = self.seams.len();
        if let (Some(a), Some(b)) = (ends[0].node(), ends[1].node()) {
            let mut key = [(a, sorted(triplet)), (b, sorted(last))];
            key.sort();
            let same = self.traced_between.entry(key).or_default();
            // Between the same two ends on the same elements there may be two seams (the
            // offset curve of a face touched twice, running both ways round): it repeats one
            // only if it runs along it.
            if same
                .iter()
                .any(|&k| runs_along(&points, &self.seams[k].points))
            {
                self.stats.duplicate_seams += 1;
                return;
            }
            same.push(id);
        }
        self.stats.points += points.len();
        let mut seam = Seam {
            id,
            solid: self.solid_of(triplet[0]),
            segments: triplet.to_vec(),
            ends,
            end_segments: last.to_vec(),
            points,
            handovers,
            unresolved: vec![],
            trace_seconds: seconds,
        };
        seam.unresolved = unresolved_points(&seam, self.opts.accuracy);
        self.seams.push(seam);
    }
}

impl Tracer<'_> {
    /// Removes the seams marked in `drop` (by index), renumbers the rest and recounts the
    /// points; returns how many were removed.
    pub(super) fn remove_seams(&mut self, drop: &[bool]) -> usize {
        let n = drop.iter().filter(|&&d| d).count();
        if n > 0 {
            let keep: Vec<bool> = drop.iter().map(|d| !d).collect();
            keep_where(&mut self.seams, &keep);
            for (id, s) in self.seams.iter_mut().enumerate() {
                s.id = id;
            }
            self.stats.points = self.seams.iter().map(|s| s.points.len()).sum();
        }
        n
    }
}

/// Keeps the items of `v` whose flag in `keep` (one per item, in order) is set.
pub(super) fn keep_where<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut flags = keep.iter();
    v.retain(|_| flags.next().copied().unwrap_or(true));
}

/// Every element seam `s` names (its slots at both ends and along its hand-overs), sorted,
/// each once.
pub(super) fn named(s: &Seam) -> Vec<Element> {
    let mut v: Vec<Element> = s.segments.clone();
    v.extend(&s.end_segments);
    v.extend(s.handovers.iter().flat_map(|h| [h.from, h.to]));
    v.sort();
    v.dedup();
    v
}

/// True when the seam `new` runs along the seam `old`: its middle point is no farther from a
/// point of `old` than `old`'s longest step.
pub(super) fn runs_along(new: &[SeamPoint], old: &[SeamPoint]) -> bool {
    let c = |p: &SeamPoint| glam::DVec3::new(p.point[0], p.point[1], p.point[2]);
    let Some(mid) = new.get(new.len() / 2).map(c) else {
        return true;
    };
    let step = old
        .windows(2)
        .map(|w| c(&w[0]).distance(c(&w[1])))
        .fold(0.0, f64::max);
    old.iter().any(|p| c(p).distance(mid) <= step)
}
