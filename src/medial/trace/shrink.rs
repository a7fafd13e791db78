//! Degenerate curves that end where the arc of contact shrinks to a point. A round cut off
//! obliquely by a wall narrows the arc its axis's balls touch it along, down to the vertex
//! where the cut meets one of the round's tangent lines, or to the point of the cut's
//! (elliptic) edge that reaches farthest along the axis. The curve ends there freely: its
//! last ball osculates the face at that point ([`osculating_ball`]) and touches it there
//! only ([`DegenerateEnd::Shrinks`]). Tried where a touch point left its face and nothing
//! else ends or carries the curve on (from `Tracer::follow`, `degenerate.rs`).

use super::tracer::Tracer;
use super::unknowns::v3;
use crate::geom::eval::eval_curve;
use crate::medial::axis::DegenerateEnd;
use crate::medial::maximal::osculating_ball;
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

/// Samples of an edge's range searched for points where it runs across a degenerate curve
/// ([`Tracer::across`]).
const ACROSS_SAMPLES: usize = 32;

impl Tracer<'_> {
    /// Where a touch point left its face `x` on (centre moving along `dir`) and the curve goes
    /// no further: the arc the ball touches the face along may be shrinking to a point ahead
    /// (a round cut off obliquely): a vertex of the face, or a point of one of its edges
    /// where the edge runs across `dir` (the farthest reach of an oblique cut's ellipse along
    /// the curve). The end ball then osculates the face there ([`osculating_ball`]); it is
    /// taken when it is ahead of `x`, within `x`'s radius of it, its radius differs from
    /// `x`'s by no more than the centres are apart (the radius along the medial axis is
    /// 1-Lipschitz), the circle of contact through the point leaves the segments' faces on
    /// both sides of it ([`Tracer::arc_is_point`]), and the ball is empty. The nearest such
    /// ball, as unknowns touching that face twice at the point (the pair: the other segment
    /// may be a plane tangent to the face that does not reach it), and the end.
    pub(super) fn shrinks(
        &self,
        solid: usize,
        segs: [Element; 2],
        x: &DVector<f64>,
        dir: DVec3,
    ) -> Option<([Element; 2], DVector<f64>, DegenerateEnd)> {
        let (c, r) = (v3(x), x[3]);
        let a = self.opts.accuracy;
        let mut faces: Vec<usize> = segs.iter().flat_map(|s| s.faces(self.model)).collect();
        faces.sort_unstable();
        faces.dedup();
        let mut best: Option<(f64, DVector<f64>, usize, Element, DVec3)> = None;
        for &f in &faces {
            let candidates = Element::Face(f)
                .vertices(self.model)
                .into_iter()
                .map(|v| (Element::Vertex(v), self.model.vertices[v].point))
                .chain(self.across(f, dir, c, r));
            for (element, p) in candidates {
                let Some((cv, rv, uv)) = osculating_ball(self.model, f, p) else {
                    continue;
                };
                let apart = cv.distance(c);
                let ahead = (cv - c).dot(dir) >= -a;
                if !ahead || apart > r || (rv - r).abs() > apart + a {
                    continue;
                }
                if best.as_ref().is_some_and(|b| b.0 <= apart) {
                    continue;
                }
                let mut y = DVector::zeros(8);
                y.rows_mut(0, 3).copy_from_slice(&cv.to_array());
                y[3] = rv;
                for i in 0..2 {
                    y[4 + 2 * i] = uv[0];
                    y[5 + 2 * i] = uv[1];
                }
                if self.arc_is_point(&faces, cv, rv, dir, p) && self.ball_is_empty(solid, &y) {
                    best = Some((apart, y, f, element, p));
                }
            }
        }
        best.map(|(_, y, f, element, p)| {
            let end = DegenerateEnd::Shrinks {
                element,
                touch: p.to_array(),
            };
            ([Element::Face(f); 2], y, end)
        })
    }

    /// The points of face `f`'s edges within `2r` of `c` where the edge runs across `dir`
    /// (its tangent perpendicular to it): where [`ACROSS_SAMPLES`] samples of the edge's
    /// range change sign in `C'·dir`, refined by bisection to the parameter's rounding.
    fn across(&self, f: usize, dir: DVec3, c: DVec3, r: f64) -> Vec<(Element, DVec3)> {
        let mut out = vec![];
        let mut edges: Vec<usize> = self.model.faces[f]
            .loops
            .iter()
            .flat_map(|l| l.edges.iter().map(|oe| oe.edge))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        for e in edges {
            let edge = &self.model.edges[e];
            if crate::geom::nearest_on_edge(self.model, e, c, None).2 > 2.0 * r {
                continue;
            }
            let (t0, t1) = edge.range;
            let g = |t: f64| eval_curve(&edge.curve, t).d1.dot(dir);
            let at = |k: usize| t0 + (t1 - t0) * k as f64 / ACROSS_SAMPLES as f64;
            for k in 0..ACROSS_SAMPLES {
                let (mut lo, mut hi) = (at(k), at(k + 1));
                let (mut glo, ghi) = (g(lo), g(hi));
                if !(glo.is_finite() && ghi.is_finite()) || glo * ghi > 0.0 || glo == 0.0 {
                    continue;
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    let gm = g(mid);
                    if gm * glo > 0.0 {
                        (lo, glo) = (mid, gm);
                    } else {
                        hi = mid;
                    }
                }
                let t = 0.5 * (lo + hi);
                // Not at its ends: those are the vertices.
                if t > t0.min(t1) && t < t0.max(t1) {
                    out.push((Element::Edge(e), eval_curve(&edge.curve, t).p));
                }
            }
        }
        out
    }

    /// True when the ball of centre `c` and radius `r` (centre moving along `dir`) touches
    /// `faces` at `p` only: the circle of contact through `p` across `dir` leaves them on
    /// both sides of `p`, at one, two and four times the separation of places (the ball at
    /// a vertex where the arc runs on from it is no end).
    fn arc_is_point(&self, faces: &[usize], c: DVec3, r: f64, dir: DVec3, p: DVec3) -> bool {
        let a = self.opts.accuracy;
        let radial = p - c - dir * (p - c).dot(dir);
        let Some(u) = radial.try_normalize() else {
            return false;
        };
        let w = dir.normalize().cross(u);
        let one_place = (8.0 * r * a).sqrt();
        let mut near = vec![];
        [1.0, 2.0, 4.0].iter().all(|&m| {
            let phi = m * one_place / r;
            [phi, -phi].iter().all(|&phi| {
                let q = c + (u * phi.cos() + w * phi.sin()) * r;
                self.boundary.within_into(self.model, q, a, &mut near);
                !near.iter().any(|f| faces.contains(f))
            })
        })
    }
}
