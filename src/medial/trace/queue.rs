//! The queue of seams to trace, and recording what was traced: a seam is not traced twice
//! from the same node on the same elements, and a seam between two nodes that repeats one
//! already traced is dropped.

use super::options::MAX_SEAMS;
use super::tracer::Tracer;
use super::unknowns::sorted;
use crate::medial::axis::{Handover, Node, Seam, SeamEnd, SeamPoint};
use crate::model::Element;
use std::collections::HashSet;

impl Tracer<'_> {
    /// Traces queued seams until the queue is empty.
    pub(super) fn run_queue(&mut self) {
        while let Some(start) = self.queue.pop_front() {
            if self.seams.len() >= MAX_SEAMS {
                break;
            }
            let key = (sorted(start.triplet), start.from);
            if !self.visited.insert(key) {
                continue;
            }
            if let Node::Junction(j) = start.from {
                if self.arrivals[j]
                    .iter()
                    .any(|a| a.distance(start.dir) < 1e-6)
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
    ) {
        if let (Some(a), Some(b)) = (ends[0].node(), ends[1].node()) {
            let mut key = [(a, sorted(triplet)), (b, sorted(last))];
            key.sort();
            if !self.traced_between.insert(key) {
                self.stats.duplicate_seams += 1;
                return;
            }
        }
        self.stats.points += points.len();
        let id = self.seams.len();
        self.seams.push(Seam {
            id,
            solid: self.solid_of(triplet[0]),
            segments: triplet.to_vec(),
            ends,
            end_segments: last.to_vec(),
            points,
            handovers,
        });
    }
}
