//! Surface evaluation with first and second derivatives: ours (`eval_surface`, one pass) vs
//! truck's six separate calls (`subs`, `uder`, `vder`, `uuder`, `uvder`, `vvder`; the last
//! two wrong for degree ≥ 3, timed anyway as the baseline), on a bicubic B-spline with
//! 10 × 10 control points, the same net as a NURBS, and two analytic surfaces.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use matrace::geom::eval_surface;
use matrace::model::Surface;
use truck_geometry::prelude::*;
use truck_stepio::r#in::alias::{ElementarySurface, Sphere as StepSphere};

fn knots(p: usize, n_cp: usize) -> KnotVec {
    let spans = n_cp - p;
    let mut k = vec![0.0; p + 1];
    k.extend((1..spans).map(|i| i as f64 / spans as f64 + 0.013 * (i as f64).sin()));
    k.extend(std::iter::repeat_n(1.0, p + 1));
    KnotVec::from(k)
}

fn net(n: usize) -> Vec<Vec<Point3>> {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    Point3::new(x, y, 0.5 * (1.3 * x + 0.7 * y).sin())
                })
                .collect()
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let n = 10;
    let bsp = BSplineSurface::new((knots(3, n), knots(3, n)), net(n));
    let nurbs = NurbsSurface::new(BSplineSurface::new(
        (knots(3, n), knots(3, n)),
        net(n)
            .into_iter()
            .enumerate()
            .map(|(i, row)| {
                row.into_iter()
                    .enumerate()
                    .map(|(j, p)| {
                        let w = 1.0 + 0.4 * ((i + 2 * j) as f64).sin();
                        Vector4::new(p.x * w, p.y * w, p.z * w, w)
                    })
                    .collect()
            })
            .collect(),
    ));
    let sphere = Processor::new(StepSphere(Sphere::new(Point3::new(1.0, 2.0, 3.0), 2.0)))
        .transformed(Matrix4::from_angle_x(Rad(0.3)));
    let torus = Processor::new(Torus::new(Point3::origin(), 3.0, 1.0))
        .transformed(Matrix4::from_angle_y(Rad(0.4)));
    let surfaces = [
        ("bicubic B-spline", Surface::BSplineSurface(Box::new(bsp))),
        ("bicubic NURBS", Surface::NurbsSurface(Box::new(nurbs))),
        (
            "sphere",
            Surface::ElementarySurface(Box::new(ElementarySurface::Sphere(sphere))),
        ),
        (
            "torus",
            Surface::ElementarySurface(Box::new(ElementarySurface::ToroidalSurface(torus))),
        ),
    ];
    // 64 parameter points per iteration, spread over the domain.
    let params: Vec<(f64, f64)> = (0..64)
        .map(|k| {
            let t = k as f64 / 64.0;
            ((0.618 * k as f64).fract(), 0.03 + 0.94 * t)
        })
        .collect();
    let mut g = c.benchmark_group("eval_surface ×64");
    for (name, s) in &surfaces {
        g.bench_function(format!("{name}: matrace eval_surface"), |b| {
            b.iter(|| {
                for &(u, v) in &params {
                    black_box(eval_surface(black_box(s), u, v));
                }
            })
        });
        g.bench_function(format!("{name}: truck subs+5 derivatives"), |b| {
            b.iter(|| {
                for &(u, v) in &params {
                    let s = black_box(s);
                    black_box((
                        s.subs(u, v),
                        s.uder(u, v),
                        s.vder(u, v),
                        s.uuder(u, v),
                        s.uvder(u, v),
                        s.vvder(u, v),
                    ));
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
