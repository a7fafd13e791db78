//! How tracing time grows with the number of seams: comb prisms with 1 to 32 teeth, built
//! with truck-modeling and written to STEP by truck-stepio, then read by matrace like any
//! file. Every tooth adds two reflex edges and about a dozen seams; near-linear growth means
//! a flat time per seam across the family (`docs/performance.md`).
//!
//! `cargo bench --bench growth`.

use criterion::{criterion_group, criterion_main, Criterion};
use truck_modeling::*;

/// A comb: a base `6 mm` high with `teeth` teeth 4 mm wide, 10 mm high and 4 mm apart,
/// extruded 8 mm; as STEP text.
fn comb_step(teeth: usize) -> String {
    let (w, gap, h, b) = (4.0, 4.0, 10.0, 6.0);
    let len = teeth as f64 * (w + gap) - gap;
    let mut pts = vec![(0.0, 0.0), (len, 0.0)];
    for i in (0..teeth).rev() {
        let x0 = i as f64 * (w + gap);
        pts.push((x0 + w, b + h));
        pts.push((x0, b + h));
        if i > 0 {
            pts.push((x0, b));
            pts.push((x0 - gap, b));
        }
    }
    let vs: Vec<Vertex> = pts
        .iter()
        .map(|&(x, y)| builder::vertex(Point3::new(x, y, 0.0)))
        .collect();
    let edges: Vec<Edge> = (0..vs.len())
        .map(|i| builder::line(&vs[i], &vs[(i + 1) % vs.len()]))
        .collect();
    let wire: Wire = edges.into_iter().collect();
    let face = builder::try_attach_plane(&[wire]).expect("planar profile");
    let solid: Solid = builder::tsweep(&face, Vector3::new(0.0, 0.0, 8.0));
    let compressed = solid.compress();
    truck_stepio::out::CompleteStepDisplay::new(
        truck_stepio::out::StepModel::from(&compressed),
        Default::default(),
    )
    .to_string()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("growth");
    g.sample_size(10);
    for teeth in [1, 2, 4, 8, 16, 32] {
        let text = comb_step(teeth);
        let name = format!("comb_{teeth}.step");
        let m =
            matrace::ingest::read_model_from_bytes(std::path::Path::new(&name), text.as_bytes())
                .expect("truck's STEP reads");
        let class = matrace::classify(&m, &Default::default());
        let opts = matrace::medial::TraceOptions::for_model(&m);
        let boundary = matrace::geom::Boundary::new(&m);
        let run = || matrace::medial::trace_with_boundary(&m, &boundary, &class, &opts);
        let mat = run();
        let open = mat.seams.iter().filter(|s| s.is_open()).count();
        g.bench_function(
            format!(
                "comb {teeth} teeth ({} seams, {open} open)",
                mat.seams.len()
            ),
            |b| b.iter(run),
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
