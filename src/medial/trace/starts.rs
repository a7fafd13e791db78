//! Seams leaving convex vertices, where the ball shrinks to nothing.

use super::options::{SAME_DIRECTION, UNIT_ROUNDING};
use super::tracer::{Start, Tracer};
use super::unknowns::seam_x;
use crate::geom::project_point;
use crate::medial::axis::Node;
use crate::medial::equations::NormalField;
use crate::model::Element;
use glam::DVec3;

impl Tracer<'_> {
    /// The faces around vertex `v`.
    pub(super) fn vertex_faces(&self, v: usize) -> Vec<usize> {
        let mut faces: Vec<usize> = self
            .model
            .edges
            .iter()
            .filter(|e| e.vertices.contains(&v))
            .flat_map(|e| e.faces.iter().copied())
            .collect();
        faces.sort_unstable();
        faces.dedup();
        faces
    }

    /// Queues the seams leaving convex vertex `v`. Near the vertex the boundary is the cone of
    /// its faces' tangent planes; a seam leaves along each direction `d` that moves equally
    /// fast from three planes (`nᵢ·d = −1`) and no slower from every other (`nₘ·d ≤ −1`): one
    /// seam for three faces, `k − 2` for `k` faces in general, fewer when directions coincide
    /// (a square pyramid's apex gives one, its axis).
    pub(super) fn start_at_vertex(&mut self, v: usize) {
        let faces = self.vertex_faces(v);
        let p = self.model.vertices[v].point;
        let mut params = Vec::with_capacity(faces.len());
        let mut normals = Vec::with_capacity(faces.len());
        for f in &faces {
            let Some(uv) = project_point(&self.model.faces[*f].surface, p, None) else {
                self.stats.skipped_vertices.push(v);
                return;
            };
            let Some(e) = Element::Face(*f).eval(self.model, [uv.0, uv.1]) else {
                self.stats.skipped_vertices.push(v);
                return;
            };
            params.push(uv);
            normals.push(e.n);
        }
        let mut dirs: Vec<DVec3> = vec![];
        let k = faces.len();
        for a in 0..k {
            for b in a + 1..k {
                for c in b + 1..k {
                    let m = glam::DMat3::from_cols(normals[a], normals[b], normals[c]).transpose();
                    if m.determinant().abs() < UNIT_ROUNDING {
                        continue;
                    }
                    let d = m.inverse() * DVec3::splat(-1.0);
                    // Every other plane at least as far: −nₘ·d ≥ 1 (to rounding).
                    if (0..k).any(|q| normals[q].dot(d) > -1.0 + UNIT_ROUNDING * d.length()) {
                        continue;
                    }
                    let u = d.normalize();
                    if dirs.iter().any(|e| e.distance(u) < SAME_DIRECTION) {
                        continue;
                    }
                    dirs.push(u);
                    let x = seam_x(p, 0.0, [a, b, c].map(|i| params[i]));
                    self.queue.push_back(Start {
                        triplet: [faces[a], faces[b], faces[c]].map(Element::Face),
                        x,
                        dir: u,
                        from: Node::Vertex(v),
                    });
                }
            }
        }
        if dirs.is_empty() {
            self.stats.skipped_vertices.push(v);
        }
    }
}
