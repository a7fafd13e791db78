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
use crate::medial::axis::{SeamEnd, SkeletalEdge};
use crate::model::Element;
use glam::DVec3;

/// Balls written along a skeletal edge at a vertex (it is straight, `r` linear along it).
const VERTEX_LINE_BALLS: usize = 9;

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
                    }),
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
