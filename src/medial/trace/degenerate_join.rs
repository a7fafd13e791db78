//! Where one degenerate curve runs on into the next: the hand-over of a curve whose
//! continuum runs off its element onto another it touches along a continuum there too (a
//! boss's side onto its foot circle, a cylinder's axis onto a coaxial cone's), and the curves
//! such a run covers, traced again from their own sampled balls, dropped.

use super::degenerate::{centre_motion, CentreMotion};
use super::options::OSCULATING_REL_RADIUS;
use super::tracer::Tracer;
use super::unknowns::{to_chord, v3};
use crate::medial::axis::{DegenerateEnd, DegenerateKind};
use crate::medial::equations::MedialSystem;
use crate::medial::solver::SolveStatus;
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

impl Tracer<'_> {
    /// Drops each degenerate curve whose balls all lie on another curve (within `tol`): a
    /// curve handed over onto the elements of a neighbour (a fillet's axis onto a coaxial
    /// cylinder's, and on onto a cone's) runs along the curve traced from that neighbour's
    /// own sampled ball. Of two that cover each other, the first is kept.
    pub(super) fn drop_covered_curves(&mut self, tol: f64) {
        let centres: Vec<Vec<DVec3>> = self
            .degenerate
            .iter()
            .map(|d| {
                d.balls
                    .iter()
                    .map(|b| DVec3::new(b[0], b[1], b[2]))
                    .collect()
            })
            .collect();
        let curve = |k: usize| self.degenerate[k].kind == DegenerateKind::Curve;
        let covers = |b: usize, a: usize| {
            self.degenerate[a].solid == self.degenerate[b].solid
                && centres[b].len() >= 2
                && centres[a].iter().all(|&c| {
                    centres[b]
                        .windows(2)
                        .any(|w| to_chord(c, w[0], w[1]) <= tol)
                })
        };
        let n = self.degenerate.len();
        let mut keep = vec![true; n];
        for a in 0..n {
            if !curve(a) {
                continue;
            }
            keep[a] = !(0..n)
                .any(|b| b != a && keep[b] && curve(b) && covers(b, a) && (b < a || !covers(a, b)));
        }
        let mut k = 0;
        self.degenerate.retain(|_| {
            k += 1;
            keep[k - 1]
        });
    }

    /// Where a curve touching `segs` that stopped at ball `x` (centre moving along `d`) —
    /// a touch point left its element, or the ball met a face it osculates — carries on:
    /// the element `end` names, or else a reflex edge of its
    /// faces or a face across an edge from them within reach of the ball (none `visited`),
    /// or, first, the segment that `stayed` touched where the other was left, on which the
    /// ball touches along a continuum and its centre moves along a line; the pair touched,
    /// the ball with touch points on it, and the direction.
    pub(super) fn degenerate_hand_over(
        &self,
        solid: usize,
        x: &DVector<f64>,
        d: DVec3,
        (segs, end): ([Element; 2], &DegenerateEnd),
        visited: &[Element],
        stayed: Option<Element>,
    ) -> Option<([Element; 2], DVector<f64>, DVec3)> {
        let named = match end {
            DegenerateEnd::Meets { element, .. } if !matches!(element, Element::Vertex(_)) => {
                Some(*element)
            }
            _ => None,
        };
        let (c, reach) = (v3(x), x[3] + self.opts.accuracy);
        let mut edges: Vec<usize> = segs
            .iter()
            .flat_map(|s| s.faces(self.model))
            .flat_map(|f| &self.model.faces[f].loops)
            .flat_map(|l| l.edges.iter().map(|oe| oe.edge))
            .filter(|&e| {
                self.is_reflex(e) && crate::geom::nearest_on_edge(self.model, e, c, None).2 <= reach
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        // Faces across an edge from the segments' faces, within reach.
        let own: Vec<usize> = segs.iter().flat_map(|s| s.faces(self.model)).collect();
        let beside = |g: usize| {
            self.model.faces[g]
                .loops
                .iter()
                .flat_map(|l| &l.edges)
                .any(|oe| {
                    self.model.edges[oe.edge]
                        .faces
                        .iter()
                        .any(|f| own.contains(f))
                })
        };
        let near = self
            .boundary
            .within(self.model, c, reach)
            .into_iter()
            .filter(|&g| self.face_solid[g] == solid && beside(g))
            .map(Element::Face);
        let unvisited = named
            .into_iter()
            .chain(edges.into_iter().map(Element::Edge))
            .chain(near)
            .filter(|e| !visited.contains(e));
        stayed.into_iter().chain(unvisited).find_map(|e| {
            let sys = MedialSystem::new(vec![e, e]);
            let mut y = DVector::zeros(8);
            y.rows_mut(0, 4).copy_from(&x.rows(0, 4));
            // The circle of contact through the point where the ball met `e` (off the
            // centre's plane on a cone: the balls of its axis touch it along a circle
            // ahead of or behind their centre).
            let axial = match end {
                DegenerateEnd::Meets { touch, .. } if Some(e) == named => {
                    // A face the ball touches all over there (a corner's sphere of radius
                    // r, where three fillets' axes end) holds its centre still: there is
                    // nothing to run on.
                    let p = DVec3::from_array(*touch);
                    if let (Element::Face(f), Some(s)) = (e, self.params_on(e, p, v3(x), None)) {
                        let face = &self.model.faces[f];
                        let k = crate::geom::principal_curvatures(
                            &crate::geom::eval_face(face, s[0], s[1]),
                            face.sign,
                        );
                        if k.is_some_and(|k| x[3] * k.k2 >= 1.0 - OSCULATING_REL_RADIUS) {
                            return None;
                        }
                    }
                    (p - v3(x)).dot(d.normalize())
                }
                _ => 0.0,
            };
            let (pair, y) = self.recentred(&sys, &y, d, false, axial)?;
            if pair == segs {
                return None;
            }
            let sys = MedialSystem::new(pair.to_vec());
            // Recentred touch points on a face's circle of contact are where that circle
            // crosses it, to the accuracy: solve the ball there, in the plane across `d`
            // (the Jacobian's null space is the curve's only at a solution). It must be the
            // same ball.
            let y = match e {
                Element::Face(_) => {
                    let sol = self.correct_across(&sys, y.clone(), v3(&y), d);
                    (sol.status == SolveStatus::Converged
                        && v3(&sol.x).distance(v3(&y)) <= self.opts.accuracy
                        && (sol.x[3] - y[3]).abs() <= self.opts.accuracy)
                        .then_some(sol.x)?
                }
                _ => y,
            };
            match centre_motion(self.model, &sys, &y)? {
                CentreMotion::Along(v) => Some((pair, y, if v.dot(d) < 0.0 { -v } else { v })),
                CentreMotion::Still => None,
            }
        })
    }
}
