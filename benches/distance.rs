//! Distance queries on the exact boundary: `Boundary::nearest` (and `within`,
//! `contains_point`) for random points inside a part, per file, with the boundary built once.
//!
//! `cargo bench --bench distance`. Each iteration runs `BATCH` queries over fixed random points
//! inside the part (rejection-sampled in the bounding box with `contains_point`), so the
//! time per query is the reported time divided by `BATCH` (criterion's throughput line gives
//! queries per second directly).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;
use matrace::geom::Boundary;
use std::path::PathBuf;

/// Queries per iteration.
const BATCH: usize = 200;

fn files() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<PathBuf> = ["box_bspline_top.step", "filleted_box.step"]
        .iter()
        .map(|f| root.join("samples").join(f))
        .collect();
    let rw = root.join("../shared/realworld/stepswift_nist_ftc_06_asme1_rd.stp");
    if rw.exists() {
        v.push(rw);
    }
    v
}

/// Deterministic points inside the part.
fn inside_points(model: &matrace::Model, boundary: &Boundary, n: usize) -> Vec<DVec3> {
    let (lo, hi) = model.bounding_box();
    let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut rnd = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut out = Vec::with_capacity(n);
    for _ in 0..1_000_000 {
        if out.len() == n {
            break;
        }
        let p = lo + DVec3::new(rnd(), rnd(), rnd()) * (hi - lo);
        if boundary.contains_point(model, p) {
            out.push(p);
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let models: Vec<(String, matrace::Model)> = files()
        .iter()
        .map(|f| {
            let name = f.file_name().unwrap().to_string_lossy().to_string();
            (name, matrace::read_model(f).expect("reads"))
        })
        .collect();
    let mut g = c.benchmark_group("distance/build");
    g.sample_size(20);
    for (name, model) in &models {
        g.bench_function(format!("Boundary::new/{name}"), |b| {
            b.iter(|| Boundary::new(black_box(model)))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("distance");
    g.sample_size(20);
    g.throughput(Throughput::Elements(BATCH as u64));
    for (name, model) in &models {
        let model = model.clone();
        let boundary = Boundary::new(&model);
        let points = inside_points(&model, &boundary, BATCH);
        assert_eq!(points.len(), BATCH, "{name}: not enough points inside");
        g.bench_function(format!("nearest/{name}"), |b| {
            b.iter(|| {
                for p in &points {
                    black_box(boundary.nearest(&model, black_box(*p)));
                }
            })
        });
        let radii: Vec<f64> = points
            .iter()
            .map(|p| 1.5 * boundary.nearest(&model, *p).distance)
            .collect();
        let mut buf = Vec::new();
        g.bench_function(format!("within(1.5 d)/{name}"), |b| {
            b.iter(|| {
                for (p, r) in points.iter().zip(&radii) {
                    boundary.within_into(&model, black_box(*p), *r, &mut buf);
                    black_box(&buf);
                }
            })
        });
        g.bench_function(format!("contains_point/{name}"), |b| {
            b.iter(|| {
                for p in &points {
                    black_box(boundary.contains_point(&model, black_box(*p)));
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
