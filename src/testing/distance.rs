//! Fixtures of the distance tests (compiled in test builds only): deterministic random
//! numbers, dense brute-force samples of a trimmed face with their cover radius, query points
//! in and around a part, and the check that a hit lies on its face.

use crate::geom::eval::eval_curve;
use crate::geom::{trim, FaceHit};
use crate::model::Element;
use crate::model::Model;
use glam::{DVec2, DVec3};

/// Deterministic uniform numbers in [0, 1) (a 64-bit LCG, high bits).
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn in_box(&mut self, lo: DVec3, hi: DVec3) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * (hi - lo) + lo
    }
}

/// Dense samples of a trimmed face: a UV grid filtered by the trim and every edge of its
/// loops, with a bound on how far any point of the face is from the nearest sample, and
/// how far the trim's UV polygons stray from the exact edges (the trim test accepts the
/// slivers between a polygon's chords and the exact boundary, up to `trim_dev` away).
pub struct Brute {
    pub points: Vec<DVec3>,
    pub cover: f64,
    pub trim_dev: f64,
}

/// [`Brute`] samples of face `fi`: an `(n + 1)²` grid over its domain and 4001 points of each
/// edge of its loops.
pub fn brute_samples(model: &Model, fi: usize, n: usize) -> Brute {
    let face = &model.faces[fi];
    let d = &face.domain;
    let (du, dv) = ((d.u.1 - d.u.0) / n as f64, (d.v.1 - d.v.0) / n as f64);
    let mut points = Vec::new();
    let mut grid = vec![DVec3::NAN; (n + 1) * (n + 1)];
    for j in 0..=n {
        for i in 0..=n {
            let uv = DVec2::new(d.u.0 + du * i as f64, d.v.0 + dv * j as f64);
            let x = crate::geom::surface_point(&face.surface, uv.x, uv.y);
            grid[j * (n + 1) + i] = x;
            if trim::contains(face, uv) {
                points.push(x);
            }
        }
    }
    let grid_count = points.len();
    // Largest cell diagonal (the curvature within a cell this small adds < 1 %).
    let mut cover: f64 = 0.0;
    for j in 0..n {
        for i in 0..n {
            let a = grid[j * (n + 1) + i];
            let b = grid[(j + 1) * (n + 1) + i + 1];
            let c = grid[j * (n + 1) + i + 1];
            let e = grid[(j + 1) * (n + 1) + i];
            cover = cover.max(a.distance(b)).max(c.distance(e));
        }
    }
    for l in &face.loops {
        for oe in &l.edges {
            let e = &model.edges[oe.edge];
            let m = 4000;
            let mut prev: Option<DVec3> = None;
            for k in 0..=m {
                let t = e.range.0 + (e.range.1 - e.range.0) * k as f64 / m as f64;
                let x = eval_curve(&e.curve, t).p;
                if let Some(q) = prev {
                    cover = cover.max(q.distance(x));
                }
                prev = Some(x);
                points.push(x);
            }
        }
    }
    // Chordal deviation of the loop polygons: the image of each segment's midpoint versus
    // the exact edges.
    let edge_points = &points[grid_count..];
    let mut trim_dev: f64 = 0.0;
    let periods = (d.u_period, d.v_period);
    for l in face.loops.iter().filter(|l| l.vertex.is_none()) {
        let n = l.uv.len();
        let wraps = {
            let gap = l.uv[0] - l.uv[n - 1];
            periods.0.is_some_and(|p| gap.x.abs() > 0.5 * p)
                || periods.1.is_some_and(|p| gap.y.abs() > 0.5 * p)
        };
        for k in 0..n {
            if k + 1 == n && wraps {
                continue;
            }
            let mid = (l.uv[k] + l.uv[(k + 1) % n]) * 0.5;
            let x = crate::geom::surface_point(&face.surface, mid.x, mid.y);
            let dev = edge_points
                .iter()
                .map(|q| q.distance(x))
                .fold(f64::INFINITY, f64::min);
            trim_dev = trim_dev.max(dev);
        }
    }
    Brute {
        points,
        cover: 1.01 * cover,
        trim_dev: 1.01 * trim_dev,
    }
}

/// The hit lies on the face: on its surface at `uv` and inside its trim, or on one of its
/// edges; and `distance` is the distance to it.
pub fn assert_hit_on_face(
    model: &Model,
    scale: f64,
    fi: usize,
    p: DVec3,
    hit: &FaceHit,
    what: &str,
) {
    let face = &model.faces[fi];
    assert!(
        (hit.distance - hit.point.distance(p)).abs() <= 1e-12 * scale,
        "{what}: distance"
    );
    let s = crate::geom::surface_point(&face.surface, hit.uv.0, hit.uv.1);
    // Edge points are on the surface only to the file's precision (≤ 1e-6 of the size
    // in the samples); interior points to rounding.
    match hit.on {
        Element::Face(f) => {
            assert_eq!(f, fi, "{what}");
            assert!(
                s.distance(hit.point) <= 1e-12 * scale,
                "{what}: interior point off surface"
            );
            assert!(
                trim::contains(face, DVec2::new(hit.uv.0, hit.uv.1)),
                "{what}: outside trim"
            );
        }
        Element::Edge(e) => {
            let (edge, t) = (
                &model.edges[e],
                hit.t.expect("an edge hit has its parameter"),
            );
            assert!(
                face.loops
                    .iter()
                    .any(|l| l.edges.iter().any(|oe| oe.edge == e)),
                "{what}"
            );
            assert!(
                t >= edge.range.0.min(edge.range.1) && t <= edge.range.0.max(edge.range.1),
                "{what}: t out of range"
            );
            assert!(
                eval_curve(&edge.curve, t).p.distance(hit.point) <= 1e-12 * scale,
                "{what}"
            );
            assert!(
                s.distance(hit.point) <= 1e-6 * scale,
                "{what}: edge point off surface"
            );
        }
        Element::Vertex(v) => {
            assert!(
                model.vertices[v].point.distance(hit.point) <= 1e-6 * scale,
                "{what}: vertex"
            );
            assert!(
                s.distance(hit.point) <= 1e-6 * scale,
                "{what}: vertex off surface"
            );
        }
    }
}

/// Points in the part's box grown by 20 % on each side, and points near the face (a
/// sample of it moved by up to 10 % of the diagonal).
pub fn query_points(model: &Model, brute: &Brute, rng: &mut Lcg, n: usize) -> Vec<DVec3> {
    let (lo, hi) = model.bounding_box();
    let pad = (hi - lo) * 0.2;
    let mut out: Vec<DVec3> = (0..n).map(|_| rng.in_box(lo - pad, hi + pad)).collect();
    for _ in 0..n / 2 {
        let k = (rng.next() * brute.points.len() as f64) as usize;
        let off = rng.in_box(DVec3::splat(-1.0), DVec3::splat(1.0)) * 0.1 * (hi - lo).length();
        out.push(brute.points[k.min(brute.points.len() - 1)] + off);
    }
    out
}
