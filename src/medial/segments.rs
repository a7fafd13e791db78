//! Segment groups: the parts of the boundary a touch point moves across freely.
//!
//! Faces joined by smooth or reflex edges, with those reflex edges and the reflex vertices
//! between them, form one group: a touch point moves across such an edge without the sheet
//! it feeds ending (a fillet, a split face, the inner corner of an L). Sheets are named by
//! the pair of groups their balls touch; the tracer ends a seam where two touch points in
//! one group meet.

use crate::classify::{Classification, EdgeKind};
use crate::model::{Element, Model};

/// Faces joined across smooth and reflex edges, with those reflex edges and the reflex
/// vertices on them: the touch point of a sheet's ball moves within a group.
#[derive(Clone, Debug)]
pub struct SegmentGroups {
    faces: usize,
    edges: usize,
    group: Vec<usize>,
}

impl SegmentGroups {
    pub fn new(model: &Model, class: &Classification) -> SegmentGroups {
        let (nf, ne) = (model.faces.len(), model.edges.len());
        let mut uf = UnionFind::new(nf + ne + model.vertices.len());
        for (e, edge) in model.edges.iter().enumerate() {
            if matches!(class.edges[e].kind, EdgeKind::Smooth | EdgeKind::Reflex) {
                for &f in &edge.faces {
                    uf.union(f, nf + e);
                }
                if class.edges[e].kind == EdgeKind::Reflex {
                    for &v in &edge.vertices {
                        uf.union(nf + e, nf + ne + v);
                    }
                }
            }
        }
        let group = (0..uf.parent.len()).map(|i| uf.find(i)).collect();
        SegmentGroups {
            faces: nf,
            edges: ne,
            group,
        }
    }

    /// The group of an element.
    pub fn of(&self, element: Element) -> usize {
        self.group[match element {
            Element::Face(f) => f,
            Element::Edge(e) => self.faces + e,
            Element::Vertex(v) => self.faces + self.edges + v,
        }]
    }
}

/// Disjoint sets over `0..n`; the representative of a set is its smallest member.
pub(crate) struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    pub(crate) fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    /// A new set of its own; its index.
    pub(crate) fn add(&mut self) -> usize {
        self.parent.push(self.parent.len());
        self.parent.len() - 1
    }

    pub(crate) fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
}
