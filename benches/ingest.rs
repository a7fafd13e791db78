//! Ingestion speed: `read_model` (parse, convert, walk, UV domains) and `classify`, per file,
//! for a few reference samples and the largest real-world files.
//!
//! `cargo bench --bench ingest`; figures are recorded in `docs/performance.md`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;

/// The binary's allocator (`src/main.rs`), so that the figures are the command line's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn files() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<PathBuf> = [
        "box.step",
        "filleted_box.step",
        "box_bspline_top.step",
        "plate_with_holes.step",
    ]
    .iter()
    .map(|f| root.join("samples").join(f))
    .collect();
    let rw = root.join("../shared/realworld");
    for f in [
        "b3d_M6-1x12-countersunk-screw.step",
        "stepswift_nist_ftc_09_asme1_rd.stp",
        "stepswift_nist_ctc_01_asme1_rd.stp",
    ] {
        if rw.join(f).exists() {
            v.push(rw.join(f));
        }
    }
    v
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("ingest");
    g.sample_size(10);
    for f in files() {
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        g.bench_function(format!("read_model/{name}"), |b| {
            b.iter(|| matrace::read_model(&f).expect("reads"))
        });
        let m = matrace::read_model(&f).unwrap();
        g.bench_function(format!("classify/{name}"), |b| {
            b.iter(|| matrace::classify(&m, &Default::default()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
