//! Seam tracing speed at the default accuracy (1e-6 × diagonal) on the samples and two parts
//! of the real-world corpus, with the boundary BVH built once outside the loop (its build
//! time is in the distance bench); divide by the seam count for time per seam. Parts
//! without convex corners include the seeding by sampled maximal balls.
//!
//! `cargo bench --bench trace`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut g = c.benchmark_group("trace");
    g.sample_size(20);
    for path in [
        "samples/box.step",
        "samples/tetrahedron.step",
        "samples/pyramid.step",
        "samples/box_nurbs.step",
        "samples/box_bspline_top.step",
        "samples/l_bracket.step",
        "samples/u_channel.step",
        "samples/plate_with_holes.step",
        "samples/elliptic_cylinder.step",
        "samples/filleted_box.step",
        "samples/box_with_void.step",
        "../shared/realworld/stepswift_nist_ftc_09_asme1_rd.stp",
        "../shared/realworld/stepswift_nist_ctc_01_asme1_rd.stp",
    ] {
        let Ok(m) = matrace::read_model(&root.join(path)) else {
            eprintln!("{path}: not found, skipped");
            continue;
        };
        let name = std::path::Path::new(path)
            .file_stem()
            .unwrap()
            .to_string_lossy();
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
