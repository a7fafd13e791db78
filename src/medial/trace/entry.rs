//! The tracer's entry points: seams from every convex vertex, then from the given seeds,
//! then from seeds found by sampling faces no seam touches.

use super::options::{TraceOptions, MAX_SEAMS};
use super::seeds::Seed;
use super::tracer::Tracer;
use crate::classify::{Classification, VertexKind};
use crate::geom::Boundary;
use crate::medial::axis::MedialAxis;
use crate::model::Model;

/// Traces the seams and junctions of `model` that start from its convex vertices.
pub fn trace(model: &Model, class: &Classification, opts: &TraceOptions) -> MedialAxis {
    trace_with_boundary(model, &Boundary::new(model), class, opts)
}

/// [`trace`] with a boundary BVH the caller already built (and may reuse, e.g. to verify).
pub fn trace_with_boundary(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    opts: &TraceOptions,
) -> MedialAxis {
    trace_with_seeds(model, boundary, class, opts, &[])
}

/// [`trace_with_boundary`], then from each seed in `seeds` not on a seam already traced:
/// the seam through it in both directions and everything its junctions lead to. Each solid's
/// seams see only that solid's faces.
pub fn trace_with_seeds(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    opts: &TraceOptions,
    seeds: &[Seed],
) -> MedialAxis {
    let mut t = Tracer::new(model, boundary, class, opts);
    for (v, kind) in class.vertices.iter().enumerate() {
        if *kind == VertexKind::Convex {
            t.start_at_vertex(v);
        }
    }
    t.run_queue();
    for seed in seeds {
        if t.seams.len() >= MAX_SEAMS {
            break;
        }
        t.trace_seed(seed);
        t.run_queue();
    }
    t.seed_by_sampling();
    t.seed_by_arcs();
    t.drop_open_halves();
    t.stats.joined_seams = t.join_open_halves();
    t.add_more_contacts();
    t.merge_junctions_found_twice();
    t.stats.duplicate_seams += t.drop_repeated_seams();
    t.stats.duplicate_seams += t.drop_seams_through_junctions();
    t.stats.non_generic_seams = t.seams.iter().filter(|s| s.segments.len() > 3).count();
    // The rim ends where free edges start: their faces sampled for rounds' axes before the
    // degenerate curves are traced, the free edges added after.
    let free = t.free_edge_starts();
    t.sample_rounds_at_free_edges(&free);
    t.trace_degenerates();
    let skeletal_edges = t.skeletal_at_vertices(&free);
    t.into_axis(skeletal_edges)
}
