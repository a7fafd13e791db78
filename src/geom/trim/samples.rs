//! How many samples a face's loop polygon ([`Loop::uv`](crate::model::Loop::uv)) starts with
//! on each of its edges: the reader (`ingest::domain`) doubles an edge's count until the
//! polygon follows the edge to its tolerance, and records the counts it ends with
//! ([`Loop::uv_counts`](crate::model::Loop::uv_counts)), by which whatever reads a polygon edge
//! by edge (the orientation screen, the volume) finds the edges.

use crate::model::{Model, OrientedEdge};

/// Samples per curved edge a loop's UV polygon starts with (32 keep the chordal deviation of a
/// full circle below 0.5 % of its radius; the reader refines from there).
pub const SAMPLES_PER_CURVED_EDGE: usize = 32;

/// Whether an oriented edge of a face's loop is a seam of that face, and how many samples the
/// loop's UV polygon starts with on it (two on a line that is not a seam): sample `k` of `n`
/// is at `t0 + (t1 − t0)·k/n` in the loop's direction.
pub fn edge_samples(model: &Model, face_index: usize, oe: &OrientedEdge) -> (bool, usize) {
    let edge = &model.edges[oe.edge];
    let seam = edge.faces.iter().filter(|&&f| f == face_index).count() >= 2;
    let straight = matches!(edge.curve, crate::model::Curve3D::Line(_));
    let n = if straight && !seam {
        2
    } else {
        SAMPLES_PER_CURVED_EDGE
    };
    (seam, n)
}
