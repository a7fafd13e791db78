//! Skeletal edges at vertices: where a seam ends because two of its touch points, on one part
//! of the boundary (faces and the reflex edges joining them), have met at a vertex of it.
//!
//! The commonest case is a box standing on a plate: each of its vertical (convex) edges ends
//! at the plate's top in a vertex with two reflex edges. Below that vertex the balls touching
//! the two reflex edges form a sheet whose two touch points come together at the vertex: the
//! sheet ends there along the straight line of balls touching the vertex alone, centres `V +
//! s·d` and radius `s` for `s` from 0 up to the ball where the seam of those two edges and a
//! third element ends. Each of those balls lies inside that last one (they are internally
//! tangent at V), so each is empty: the line is the sheet's free edge, its *skeletal edge*,
//! and it joins the seam's end to the vertex, where the convex edge's rim meets it.

use super::tracer::Tracer;
use crate::classify::EdgeKind;
use crate::medial::axis::{DegenerateKind, SeamEnd, SkeletalEdge};
use crate::model::Element;
use glam::DVec3;

/// Balls written along a skeletal edge at a vertex (it is straight, `r` linear along it).
const VERTEX_LINE_BALLS: usize = 9;

/// A free edge where a rim flattens out is looked for only when the ball of this many
/// accuracies tangent at the vertex is empty (a shorter one is a vertex's rounding).
const FREE_EDGE_MIN_ACCURACIES: f64 = 16.0;

/// A free edge's largest ball is a degenerate curve's end ball when centres and radii agree
/// to this many accuracies (the edge's ball is found to an eighth of the accuracy by
/// emptiness, which grows only linearly past it; the curve's end to the accuracy).
const FREE_EDGE_MEETS_ACCURACIES: f64 = 4.0;

impl Tracer<'_> {
    /// The skeletal edges at vertices of the seams traced: for every seam end at a curvature
    /// limit or a pinch whose ball has two touch points on one group of segments at a vertex
    /// both reach (to the accuracy, as verification holds them), the straight line from that
    /// ball to the vertex. A curvature-limit end there is renamed for the vertex (the ball
    /// "osculates" it: the element it was being handed to is another face at that vertex).
    /// Seam ends at one ball share one edge.
    pub(super) fn skeletal_at_vertices(&mut self) -> Vec<SkeletalEdge> {
        let near = self.opts.accuracy;
        let mut out: Vec<SkeletalEdge> = vec![];
        for s in 0..self.seams.len() {
            for end in 0..2 {
                let seam = &self.seams[s];
                if !matches!(
                    seam.ends[end],
                    SeamEnd::CurvatureLimit { .. } | SeamEnd::Pinch { .. }
                ) {
                    continue;
                }
                let (point, segs) = seam.at_end(end);
                let Some(point) = point else { continue };
                let Some((pair, v)) = self.met_at_vertex(segs, &point.touch, near) else {
                    continue;
                };
                let ball = point.point;
                let solid = seam.solid;
                if let SeamEnd::CurvatureLimit { segment } = &mut self.seams[s].ends[end] {
                    *segment = Element::Vertex(v);
                }
                let at = DVec3::new(ball[0], ball[1], ball[2]);
                let same = out.iter_mut().find(|k| {
                    let b = k.balls[0];
                    k.vertex == v
                        && DVec3::new(b[0], b[1], b[2]).distance(at) <= near
                        && (b[3] - ball[3]).abs() <= near
                });
                match same {
                    Some(k) => k.starts.push([s, end]),
                    None => out.push(SkeletalEdge {
                        id: out.len(),
                        solid,
                        starts: vec![[s, end]],
                        segments: pair,
                        vertex: v,
                        balls: self.vertex_line(ball, v),
                        meets: vec![],
                    }),
                }
            }
        }
        self.flat_rim_ends(&mut out);
        out
    }

    /// The free edges where a rim flattens out: at each end of a convex edge where its two
    /// faces are tangent (smooth to the classification's angle tolerance: two fillets of one
    /// radius meeting in a mitre, both tangent to the side face at the mitre's end), the
    /// sheet between the faces ends along the line of balls tangent to both there, centres
    /// `V − s·n` and radius `s`, from the largest of them that is empty down to the vertex
    /// (each lies inside the next, so emptiness decides one radius). Where a degenerate curve
    /// ends at that largest ball (the fillets' axes meeting), the edge meets it; otherwise
    /// nothing known ends there and the sheet's boundary stays open (verification says so).
    /// Not where a skeletal edge of the same two faces already ends at the vertex.
    fn flat_rim_ends(&self, out: &mut Vec<SkeletalEdge>) {
        let tol = crate::classify::DEFAULT_ANGLE_TOL_DEG.to_radians();
        for (e, edge) in self.model.edges.iter().enumerate() {
            if self.class.edges[e].kind != EdgeKind::Convex {
                continue;
            }
            let [fa, fb] = match edge.faces[..] {
                [a, b] if a != b => [a, b],
                _ => continue,
            };
            let pair = [Element::Face(fa), Element::Face(fb)];
            for (end, &v) in edge.vertices.iter().enumerate() {
                let t = if end == 0 { edge.range.0 } else { edge.range.1 };
                if crate::classify::edge_kind_at(self.model, e, t, tol).0 != EdgeKind::Smooth {
                    continue;
                }
                let done = out.iter().any(|k| {
                    k.vertex == v && (k.segments == pair || k.segments == [pair[1], pair[0]])
                });
                if done {
                    continue;
                }
                let p = self.model.vertices[v].point;
                let normal = |f| self.edge_face_normal(e, f, t, p).map(|(_, n)| n);
                let (Some(na), Some(nb)) = (normal(fa), normal(fb)) else {
                    continue;
                };
                let n = (na + nb).normalize_or_zero();
                let solid = self.face_solid[fa];
                let Some(r) = self.largest_tangent_ball(solid, p, n) else {
                    continue;
                };
                let c = p - r * n;
                let ball = [c.x, c.y, c.z, r];
                out.push(SkeletalEdge {
                    id: out.len(),
                    solid,
                    starts: vec![],
                    segments: pair,
                    vertex: v,
                    balls: self.vertex_line(ball, v),
                    meets: self.degenerate_ends_at(solid, c, r),
                });
            }
        }
    }

    /// The radius of the largest empty ball tangent to the boundary at `p` with outward
    /// normal `n` (centre `p − s·n`), to an eighth of the accuracy; `None` when even a ball
    /// of [`FREE_EDGE_MIN_ACCURACIES`] accuracies is not empty (the boundary curves in
    /// tighter there, or `n` is not its normal).
    fn largest_tangent_ball(&self, solid: usize, p: DVec3, n: DVec3) -> Option<f64> {
        let a = self.opts.accuracy;
        // Held to a quarter of the accuracy: the ball's distance check then passes by a margin.
        let empty = |s: f64| {
            self.nearest_in(solid, p - s * n)
                .is_some_and(|(_, h)| h.distance >= s - 0.25 * a)
        };
        let mut lo = FREE_EDGE_MIN_ACCURACIES * a;
        if n == DVec3::ZERO || !empty(lo) {
            return None;
        }
        let mut hi = 2.0 * lo;
        while empty(hi) {
            if hi > self.model.diagonal() {
                return None;
            }
            (lo, hi) = (hi, 2.0 * hi);
        }
        while hi - lo > 0.125 * a {
            let mid = 0.5 * (lo + hi);
            if empty(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(lo)
    }

    /// The ends of degenerate curves of `solid` whose ball is the ball at `c` of radius `r`
    /// (to [`FREE_EDGE_MEETS_ACCURACIES`] accuracies): `[degenerate index, end]`.
    fn degenerate_ends_at(&self, solid: usize, c: DVec3, r: f64) -> Vec<[usize; 2]> {
        let near = FREE_EDGE_MEETS_ACCURACIES * self.opts.accuracy;
        let mut out = vec![];
        for (i, d) in self.degenerate.iter().enumerate() {
            if d.solid != solid || d.kind != DegenerateKind::Curve || d.balls.is_empty() {
                continue;
            }
            for (end, b) in [(0, d.balls[0]), (1, d.balls[d.balls.len() - 1])] {
                let at = DVec3::new(b[0], b[1], b[2]);
                if at.distance(c) <= near && (b[3] - r).abs() <= near {
                    out.push([i, end]);
                }
            }
        }
        out
    }

    /// Two of `touch` (on `segs`) on one group of segments, at a vertex both reach: the two
    /// segments and the vertex.
    fn met_at_vertex(
        &self,
        segs: &[Element],
        touch: &[[f64; 3]],
        near: f64,
    ) -> Option<([Element; 2], usize)> {
        for (i, k) in [(0, 1), (0, 2), (1, 2)] {
            let (Some(&a), Some(&b)) = (segs.get(i), segs.get(k)) else {
                continue;
            };
            if self.groups.of(a) != self.groups.of(b) {
                continue;
            }
            let (Some(&ta), Some(&tb)) = (touch.get(i), touch.get(k)) else {
                continue;
            };
            let (ta, tb) = (DVec3::from_array(ta), DVec3::from_array(tb));
            let v = (0..self.model.vertices.len()).find(|&v| {
                let p = self.model.vertices[v].point;
                p.distance(ta) <= near
                    && p.distance(tb) <= near
                    && self.reaches(a, v)
                    && self.reaches(b, v)
            });
            if let Some(v) = v {
                return Some(([a, b], v));
            }
        }
        None
    }

    /// The balls from `ball` to vertex `v` along the straight line through their centres.
    fn vertex_line(&self, ball: [f64; 4], v: usize) -> Vec<[f64; 4]> {
        let p = self.model.vertices[v].point;
        let c = DVec3::new(ball[0], ball[1], ball[2]);
        let n = VERTEX_LINE_BALLS - 1;
        (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                let q = c.lerp(p, t);
                // The seam's ball as it is; the others at their exact distance from the vertex.
                let r = if k == 0 { ball[3] } else { q.distance(p) };
                [q.x, q.y, q.z, r]
            })
            .collect()
    }
}
