//! Seam tracing speed at the default accuracy (1e-6 × diagonal) for parts the first tracer
//! covers, with the boundary BVH built once outside the loop (its build time is in the
//! distance bench); divide by the seam count for time per seam.
//!
//! `cargo bench --bench trace`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples");
    let mut g = c.benchmark_group("trace");
    g.sample_size(20);
    for name in [
        "box",
        "tetrahedron",
        "pyramid",
        "box_nurbs",
        "box_bspline_top",
    ] {
        let m = matrace::read_model(&root.join(format!("{name}.step"))).unwrap();
        let class = matrace::classify(&m, &Default::default());
        let opts = matrace::medial::TraceOptions::for_model(&m);
        let boundary = matrace::geom::Boundary::new(&m);
        let run = || matrace::medial::trace_with_boundary(&m, &boundary, &class, &opts);
        let seams = run().seams.len();
        g.bench_function(format!("{name} ({seams} seams)"), |b| b.iter(run));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
