//! Seam tracing by pseudo-arclength continuation (Ramanathan & Gurumoorthy 2005, §4; Allgower
//! & Georg's predictor–corrector, the paper's ref. [1]).
//!
//! A seam is a curve of the 3-segment medial system (9 equations, 10 unknowns). From a known
//! point `x` with unit tangent `t` (the null vector of the Jacobian, scaled so that its centre
//! part `t_B` has unit length), the predictor is `x + h·t` and the corrector solves the square
//! system `[F(x); t·(x − x_pred)] = 0`. The step `h` (millimetres of centre travel) grows when
//! the corrector converges in few iterations and halves when it fails.
//!
//! Seams start at convex vertices where exactly three faces meet (`r = 0`), leaving along the
//! direction that moves equally away from the three tangent planes. A seam ends when another
//! face comes closer than `r` (a junction, located exactly by the 4-segment system), when `r`
//! returns to 0 (a convex vertex), or — left for the next issue — when a touch point leaves its
//! face. From a new junction the three other triplets leave along the normal of the plane
//! through their touch points, in the sense in which the omitted segment moves away.
//!
//! This is the first part of the tracer: faces only, generic junctions (four segments).

use super::equations::{MedialSystem, Segment};
use super::solver::{solve, SolveOptions, SolveStatus};
use crate::brep::Model;
use crate::classify::{Classification, VertexKind};
use crate::geom::{project_point, Boundary};
use glam::DVec3;
use nalgebra::DVector;
use std::collections::{HashSet, VecDeque};

/// Default accuracy, relative to the bounding-box diagonal (DESIGN.md).
pub const DEFAULT_ACCURACY: f64 = 1e-6;
/// Largest centre step, relative to the diagonal.
pub const MAX_STEP: f64 = 0.02;
/// Smallest centre step before a seam is abandoned, relative to the diagonal.
pub const MIN_STEP: f64 = 1e-9;
/// Budget of points per seam.
pub const MAX_POINTS: usize = 20_000;
/// Budget of seams per part (guards against a tracer loop on unexpected geometry).
pub const MAX_SEAMS: usize = 10_000;

/// Options of [`trace`].
#[derive(Clone, Debug)]
pub struct TraceOptions {
    /// Output accuracy in model units (mm): residuals of every point, and junction location.
    pub accuracy: f64,
}

impl TraceOptions {
    /// Defaults for a model: accuracy `1e-6 ×` its bounding-box diagonal.
    pub fn for_model(model: &Model) -> Self {
        TraceOptions {
            accuracy: DEFAULT_ACCURACY * model.diagonal(),
        }
    }
}

/// One point of a seam.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SeamPoint {
    /// `[x, y, z, r]`.
    pub point: [f64; 4],
    /// The touch points on the three segments.
    pub touch: [[f64; 3]; 3],
}

/// How a seam ends.
#[derive(Clone, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SeamEnd {
    Vertex(usize),
    Junction(usize),
    /// The tracer stopped without a proper end; the reason says why.
    Open(String),
}

/// A seam: a curve of ball centres touching three segments.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Seam {
    pub id: usize,
    pub segments: Vec<String>,
    pub ends: [SeamEnd; 2],
    pub points: Vec<SeamPoint>,
}

/// A junction: a ball touching four segments.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Junction {
    pub id: usize,
    pub point: [f64; 3],
    pub radius: f64,
    pub segments: Vec<String>,
    pub touch: Vec<[f64; 3]>,
}

/// Counters of the run.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct TraceStats {
    pub points: usize,
    pub newton_iterations: usize,
    pub corrector_failures: usize,
    /// Largest `‖F‖∞` over the output points (mm).
    pub worst_residual: f64,
    /// Vertices where more than three faces meet, not started from (non-generic starts).
    pub skipped_vertices: Vec<usize>,
}

/// The traced medial axis.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Mat {
    pub seams: Vec<Seam>,
    pub junctions: Vec<Junction>,
    pub stats: TraceStats,
}

/// Where a seam starts.
struct Start {
    triplet: [Segment; 3],
    x: DVector<f64>,
    /// Direction of the centre at the start.
    dir: DVec3,
    from: SeamEnd,
}

/// Traces the seams and junctions of `model` that start from its convex vertices.
pub fn trace(model: &Model, class: &Classification, opts: &TraceOptions) -> Mat {
    trace_with_boundary(model, &Boundary::new(model), class, opts)
}

/// [`trace`] with a boundary BVH the caller already built (and may reuse, e.g. to verify).
pub fn trace_with_boundary(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    opts: &TraceOptions,
) -> Mat {
    let mut t = Tracer {
        model,
        boundary,
        opts,
        junctions: vec![],
        arrivals: vec![],
        seams: vec![],
        visited: HashSet::new(),
        queue: VecDeque::new(),
        stats: TraceStats::default(),
    };
    for (v, kind) in class.vertices.iter().enumerate() {
        if *kind == VertexKind::Convex {
            t.start_at_vertex(v);
        }
    }
    while let Some(start) = t.queue.pop_front() {
        if t.seams.len() >= MAX_SEAMS {
            break;
        }
        let key = (sorted(start.triplet), start.from.clone());
        if !t.visited.insert(key) {
            continue;
        }
        if let SeamEnd::Junction(j) = start.from {
            if t.arrivals[j].iter().any(|a| a.distance(start.dir) < 1e-6) {
                continue;
            }
        }
        t.trace_seam(start);
    }
    Mat {
        seams: t.seams,
        junctions: t.junctions,
        stats: t.stats,
    }
}

/// The curvature criterion at a touch point (DESIGN.md, "Maximality is not automatic"): a ball
/// of radius `r` tangent to the face from inside stays inside near the touch point only if
/// `r·κmax ≤ 1`, with `κmax` the larger principal curvature (positive where the face bends
/// towards the ball, as a convex solid's boundary does). A tolerance of 1e-9 relative absorbs
/// rounding at balls that osculate exactly (a sphere's centre). Where the normal is undefined
/// (a pole) the criterion cannot fail.
pub fn curvature_allows(model: &Model, seg: Segment, s: [f64; 2], r: f64) -> bool {
    match seg {
        Segment::Face(f) => {
            let face = &model.faces[f];
            let d = crate::geom::eval_surface(&face.surface, s[0], s[1]);
            match crate::geom::principal_curvatures(&d, face.sign) {
                Some(k) => r * k.k1 <= 1.0 + 1e-9,
                None => true,
            }
        }
    }
}

fn sorted(mut s: [Segment; 3]) -> [Segment; 3] {
    s.sort_by_key(|x| match x {
        Segment::Face(f) => *f,
    });
    s
}

/// The unknowns `[B, r, s₁, s₂, s₃]` of a seam point.
fn seam_x(b: DVec3, r: f64, params: [(f64, f64); 3]) -> DVector<f64> {
    let mut x = DVector::zeros(10);
    x[0] = b.x;
    x[1] = b.y;
    x[2] = b.z;
    x[3] = r;
    for (slot, (u, v)) in params.into_iter().enumerate() {
        x[4 + 2 * slot] = u;
        x[5 + 2 * slot] = v;
    }
    x
}

fn v3(x: &DVector<f64>) -> DVec3 {
    DVec3::new(x[0], x[1], x[2])
}

struct Tracer<'a> {
    model: &'a Model,
    boundary: &'a Boundary,
    opts: &'a TraceOptions,
    junctions: Vec<Junction>,
    /// Per junction: unit directions (leaving the junction) of the seams that arrived there,
    /// so a branch along an arrived seam (same curve, another triplet of a non-generic
    /// junction) is not traced again.
    arrivals: Vec<Vec<DVec3>>,
    seams: Vec<Seam>,
    /// (sorted triplet, where it starts or ends) already traced.
    visited: HashSet<([Segment; 3], SeamEnd)>,
    queue: VecDeque<Start>,
    stats: TraceStats,
}

impl Tracer<'_> {
    fn solve_opts(&self) -> SolveOptions {
        SolveOptions {
            // Residuals well inside the output accuracy.
            tol: 1e-3 * self.opts.accuracy,
            max_iter: 12,
        }
    }

    /// The faces around vertex `v`.
    fn vertex_faces(&self, v: usize) -> Vec<usize> {
        let mut faces: Vec<usize> = self
            .model
            .edges
            .iter()
            .filter(|e| e.vertices.contains(&v))
            .flat_map(|e| e.faces.iter().copied())
            .collect();
        faces.sort_unstable();
        faces.dedup();
        faces
    }

    /// Queues the seams leaving convex vertex `v`. Near the vertex the boundary is the cone of
    /// its faces' tangent planes; a seam leaves along each direction `d` that moves equally
    /// fast from three planes (`nᵢ·d = −1`) and no slower from every other (`nₘ·d ≤ −1`): one
    /// seam for three faces, `k − 2` for `k` faces in general, fewer when directions coincide
    /// (a square pyramid's apex gives one, its axis).
    fn start_at_vertex(&mut self, v: usize) {
        let faces = self.vertex_faces(v);
        let p = self.model.vertices[v].point;
        let mut params = Vec::with_capacity(faces.len());
        let mut normals = Vec::with_capacity(faces.len());
        for f in &faces {
            let Some(uv) = project_point(&self.model.faces[*f].surface, p, None) else {
                self.stats.skipped_vertices.push(v);
                return;
            };
            let Some(e) = Segment::Face(*f).eval(self.model, [uv.0, uv.1]) else {
                self.stats.skipped_vertices.push(v);
                return;
            };
            params.push(uv);
            normals.push(e.n);
        }
        let mut dirs: Vec<DVec3> = vec![];
        let k = faces.len();
        for a in 0..k {
            for b in a + 1..k {
                for c in b + 1..k {
                    let m = glam::DMat3::from_cols(normals[a], normals[b], normals[c]).transpose();
                    if m.determinant().abs() < 1e-9 {
                        continue;
                    }
                    let d = m.inverse() * DVec3::splat(-1.0);
                    // Every other plane at least as far: −nₘ·d ≥ 1 (to rounding).
                    if (0..k).any(|q| normals[q].dot(d) > -1.0 + 1e-9 * d.length()) {
                        continue;
                    }
                    let u = d.normalize();
                    if dirs.iter().any(|e| e.distance(u) < 1e-9) {
                        continue;
                    }
                    dirs.push(u);
                    let x = seam_x(p, 0.0, [a, b, c].map(|i| params[i]));
                    self.queue.push_back(Start {
                        triplet: [faces[a], faces[b], faces[c]].map(Segment::Face),
                        x,
                        dir: u,
                        from: SeamEnd::Vertex(v),
                    });
                }
            }
        }
        if dirs.is_empty() {
            self.stats.skipped_vertices.push(v);
        }
    }

    /// Unit tangent of the seam at `x` (centre part of unit length), oriented along `dir`.
    fn tangent(
        &self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        dir: &DVector<f64>,
    ) -> Option<DVector<f64>> {
        let (_, a) = sys.eval_with_row(self.model, x, dir, 0.0)?;
        let mut rhs = DVector::zeros(x.len());
        rhs[x.len() - 1] = 1.0;
        let z = a.lu().solve(&rhs)?;
        let zb = DVec3::new(z[0], z[1], z[2]).length();
        (zb.is_finite() && zb > 0.0).then(|| z / zb)
    }

    fn trace_seam(&mut self, start: Start) {
        let sys = MedialSystem::new(start.triplet.to_vec());
        let diag = self.model.diagonal();
        let mut x = start.x.clone();
        let mut dir = DVector::zeros(10);
        dir[0] = start.dir.x;
        dir[1] = start.dir.y;
        dir[2] = start.dir.z;
        // The first tangent is oriented by the centre's direction alone (no weight on r).
        let mut points = vec![self.seam_point(&sys, &x)];
        let mut h = 1e-3 * diag;
        let end: SeamEnd;
        loop {
            if points.len() >= MAX_POINTS {
                end = SeamEnd::Open("point budget exhausted".into());
                break;
            }
            let Some(t) = self.tangent(&sys, &x, &dir) else {
                end = SeamEnd::Open("singular tangent".into());
                break;
            };
            let pred = &x + &t * h;
            // Corrector: F = 0 and t·(y − pred) = 0.
            let c = t.dot(&pred);
            let sol = solve(
                |y| sys.eval_with_row(self.model, y, &t, c),
                pred,
                &self.solve_opts(),
            );
            self.stats.newton_iterations += sol.iterations;
            if sol.status != SolveStatus::Converged || sol.x[3] < -self.opts.accuracy && x[3] <= 0.0
            {
                self.stats.corrector_failures += 1;
                h *= 0.5;
                if h < MIN_STEP * diag {
                    end = SeamEnd::Open("step size underflow".into());
                    break;
                }
                continue;
            }
            let xn = sol.x;
            let r = xn[3];
            // Back to a convex vertex: r returns to zero. Land exactly on r = 0 (the corrector
            // may have overshot to a negative radius) by replacing the arclength equation with
            // r = 0.
            if r <= self.opts.accuracy && points.len() > 1 {
                let mut r_row = DVector::zeros(xn.len());
                r_row[3] = 1.0;
                let xe = solve(
                    |y| sys.eval_with_row(self.model, y, &r_row, 0.0),
                    xn.clone(),
                    &self.solve_opts(),
                );
                let xe = if xe.status == SolveStatus::Converged {
                    xe.x
                } else {
                    xn
                };
                let b = v3(&xe);
                let v = (0..self.model.vertices.len()).min_by(|&a, &c| {
                    self.model.vertices[a]
                        .point
                        .distance(b)
                        .total_cmp(&self.model.vertices[c].point.distance(b))
                });
                points.push(self.seam_point(&sys, &xe));
                end = match v {
                    Some(v)
                        if self.model.vertices[v].point.distance(b) <= 1e3 * self.opts.accuracy =>
                    {
                        SeamEnd::Vertex(v)
                    }
                    _ => SeamEnd::Open("radius reached zero away from a vertex".into()),
                };
                break;
            }
            // Another face closer than r: a junction between x and xn.
            let b = v3(&xn);
            if let Some((f, hit)) = self.boundary.nearest_face(self.model, b) {
                let in_triplet = start.triplet.contains(&Segment::Face(f));
                if !in_triplet && hit.distance < r - self.opts.accuracy {
                    match self.locate_junction(&start.triplet, &x, Segment::Face(f)) {
                        Some(jx) => {
                            let id = self.add_junction(&start.triplet, Segment::Face(f), &jx);
                            if let Some(a) = self.arrivals.get_mut(id) {
                                a.push(-DVec3::new(dir[0], dir[1], dir[2]).normalize());
                            }
                            points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                            self.visited
                                .insert((sorted(start.triplet), SeamEnd::Junction(id)));
                            end = SeamEnd::Junction(id);
                        }
                        None => {
                            end = SeamEnd::Open(format!(
                                "F{f} comes closer than r, but no junction with it on the faces (an edge or vertex segment is needed)"
                            ));
                        }
                    }
                    break;
                }
            }
            // Touch points must stay on their faces (crossing edges is the next issue).
            let left = (0..3).find(|&i| {
                let Segment::Face(f) = start.triplet[i];
                let uv = glam::DVec2::new(xn[4 + 2 * i], xn[5 + 2 * i]);
                !crate::geom::trim::contains(&self.model.faces[f], uv)
            });
            if let Some(i) = left {
                // xn is not a medial point (its touch point is off the face): not output.
                end = SeamEnd::Open(format!("touch point left {}", start.triplet[i].id()));
                break;
            }
            // The curvature criterion: the ball must not poke through a touched face.
            let poked = (0..3).find(|&i| {
                !curvature_allows(
                    self.model,
                    start.triplet[i],
                    [xn[4 + 2 * i], xn[5 + 2 * i]],
                    r,
                )
            });
            if let Some(i) = poked {
                end = SeamEnd::Open(format!(
                    "curvature criterion fails on {} (a skeletal edge starts here)",
                    start.triplet[i].id()
                ));
                break;
            }
            points.push(self.seam_point(&sys, &xn));
            dir = t;
            x = xn;
            h = if sol.iterations <= 3 {
                (h * 1.5).min(MAX_STEP * diag)
            } else {
                h * 0.7
            };
        }
        self.stats.points += points.len();
        let id = self.seams.len();
        self.seams.push(Seam {
            id,
            segments: start.triplet.iter().map(|s| s.id()).collect(),
            ends: [start.from, end],
            points,
        });
    }

    fn seam_point(&mut self, sys: &MedialSystem, x: &DVector<f64>) -> SeamPoint {
        if let Some(f) = sys.residual(self.model, x) {
            self.stats.worst_residual = self.stats.worst_residual.max(f.amax());
        }
        let touch = std::array::from_fn(|i| {
            let e = sys.segments[i].eval(self.model, [x[4 + 2 * i], x[5 + 2 * i]]);
            e.map_or([f64::NAN; 3], |e| e.p.to_array())
        });
        SeamPoint {
            point: [x[0], x[1], x[2], x[3]],
            touch,
        }
    }

    /// Solves the 4-segment system from the seam point `x` (before the crossing).
    fn locate_junction(
        &self,
        triplet: &[Segment; 3],
        x: &DVector<f64>,
        fourth: Segment,
    ) -> Option<DVector<f64>> {
        let Segment::Face(f) = fourth;
        let b = v3(x);
        let uv = project_point(&self.model.faces[f].surface, b, None)?;
        let mut segs = triplet.to_vec();
        segs.push(fourth);
        let sys = MedialSystem::new(segs);
        let mut x0 = DVector::zeros(12);
        x0.rows_mut(0, 10).copy_from(x);
        x0[10] = uv.0;
        x0[11] = uv.1;
        let sol = solve(
            |y| sys.eval(self.model, y),
            x0,
            &SolveOptions {
                tol: 1e-3 * self.opts.accuracy,
                max_iter: 30,
            },
        );
        if !(sol.status == SolveStatus::Converged && sol.x[3] > 0.0) {
            return None;
        }
        // Every touch point must lie on its face: a ball touching a face's extension beyond
        // its edges is not a junction (the event there involves an edge or a vertex).
        let on_faces = sys.segments.iter().enumerate().all(|(i, seg)| {
            let Segment::Face(f) = *seg;
            let uv = glam::DVec2::new(sol.x[4 + 2 * i], sol.x[5 + 2 * i]);
            crate::geom::trim::contains(&self.model.faces[f], uv)
        });
        on_faces.then_some(sol.x)
    }

    /// Records a junction (or finds the same one already found) and queues the seams that
    /// leave it. All faces at distance `r` from the centre touch it (more than four at a
    /// non-generic junction, such as a cube's centre). A seam leaves along the normal `n` of the
    /// plane through three touch points, in the sense in which every other touched segment
    /// moves away (`n·(t₀ − tₖ) ≥ 0`, so its distance grows faster than `r`); for a generic
    /// junction that is the paper's rule, one seam per omitted segment.
    fn add_junction(
        &mut self,
        arriving: &[Segment; 3],
        fourth: Segment,
        jx: &DVector<f64>,
    ) -> usize {
        let p = v3(jx);
        let r = jx[3];
        let tol = 1e3 * self.opts.accuracy;
        if let Some(id) = self
            .junctions
            .iter()
            .position(|j| DVec3::from_array(j.point).distance(p) <= tol)
        {
            return id;
        }
        let mut segs = arriving.to_vec();
        segs.push(fourth);
        let mut params: Vec<(f64, f64)> = (0..4).map(|i| (jx[4 + 2 * i], jx[5 + 2 * i])).collect();
        // Other faces touching the same ball (non-generic junctions).
        for f in self.boundary.within(self.model, p, r + tol) {
            if segs.contains(&Segment::Face(f)) {
                continue;
            }
            let hit = self
                .boundary
                .nearest_on_face(self.model, f, p, None, f64::INFINITY);
            if let Some(hit) = hit {
                if (hit.distance - r).abs() <= tol {
                    segs.push(Segment::Face(f));
                    params.push(hit.uv);
                }
            }
        }
        let touch: Vec<DVec3> = segs
            .iter()
            .zip(&params)
            .filter_map(|(s, uv)| s.eval(self.model, [uv.0, uv.1]))
            .map(|e| e.p)
            .collect();
        if touch.len() != segs.len() {
            return usize::MAX;
        }
        let id = self.junctions.len();
        self.junctions.push(Junction {
            id,
            point: p.to_array(),
            radius: r,
            segments: segs.iter().map(|s| s.id()).collect(),
            touch: touch.iter().map(|t| t.to_array()).collect(),
        });
        self.arrivals.push(vec![]);
        let k = segs.len();
        let mut dirs: Vec<DVec3> = vec![];
        for a in 0..k {
            for b in a + 1..k {
                for c in b + 1..k {
                    let (t0, t1, t2) = (touch[a], touch[b], touch[c]);
                    let n = (t1 - t0).cross(t2 - t0);
                    if n.length() < 1e-12 * r * r {
                        continue;
                    }
                    let mut n = n.normalize();
                    let others = (0..k).filter(|&q| q != a && q != b && q != c);
                    let first = others.clone().next().unwrap_or(a);
                    if n.dot(t0 - touch[first]) < 0.0 {
                        n = -n;
                    }
                    let eps = 1e-9 * r;
                    if others.into_iter().any(|q| n.dot(t0 - touch[q]) < -eps) {
                        continue;
                    }
                    if dirs.iter().any(|e| e.distance(n) < 1e-9) {
                        continue;
                    }
                    dirs.push(n);
                    let x = seam_x(p, r, [a, b, c].map(|q| params[q]));
                    self.queue.push_back(Start {
                        triplet: [segs[a], segs[b], segs[c]],
                        x,
                        dir: n,
                        from: SeamEnd::Junction(id),
                    });
                }
            }
        }
        id
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn traced(name: &str) -> (Model, Mat) {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("samples")
            .join(name);
        let m = crate::read_model(&p).unwrap();
        let c = crate::classify(&m, &Default::default());
        let mat = trace(&m, &c, &TraceOptions::for_model(&m));
        (m, mat)
    }

    /// The worst error of [`crate::medial::verify`] over every seam point and junction.
    fn verify(m: &Model, mat: &Mat) -> f64 {
        crate::medial::verify(m, &Boundary::new(m), mat).worst()
    }

    /// Box [0,60]×[0,40]×[0,20] (c < b < a): 12 seams, 4 junctions at
    /// (a/2 ± (a−c)/2, b/2 ± (b−c)/2, c/2) = (10|50, 10|30, 10), radius c/2 = 10 (DESIGN.md).
    #[test]
    fn box_has_twelve_seams_and_four_junctions() {
        for file in ["box.step", "box_nurbs.step"] {
            let (m, mat) = traced(file);
            assert_eq!(mat.junctions.len(), 4, "{file}");
            assert_eq!(mat.seams.len(), 12, "{file}");
            let diag = m.diagonal();
            for j in &mat.junctions {
                let p = DVec3::from_array(j.point);
                let want = [10.0, 50.0]
                    .iter()
                    .flat_map(|&x| [10.0, 30.0].map(|y| DVec3::new(x, y, 10.0)))
                    .map(|q| q.distance(p))
                    .fold(f64::INFINITY, f64::min);
                // DESIGN.md: junctions within 1e-9 × diagonal of the analytic position.
                assert!(want <= 1e-9 * diag, "{file}: junction {p} off by {want:e}");
                assert!(
                    (j.radius - 10.0).abs() <= 1e-9 * diag,
                    "{file}: radius {}",
                    j.radius
                );
            }
            for s in &mat.seams {
                assert!(
                    s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
                    "{file}: seam {:?} ends {:?}",
                    s.segments,
                    s.ends
                );
            }
            // 8 corner seams (vertex → junction) and 4 inner seams (junction → junction).
            let corner = mat
                .seams
                .iter()
                .filter(|s| matches!(s.ends[0], SeamEnd::Vertex(_)))
                .count();
            assert_eq!(corner, 8, "{file}");
            let worst = verify(&m, &mat);
            assert!(
                worst <= 1e-6 * diag,
                "{file}: worst verified error {worst:e}"
            );
        }
    }

    /// Checks a traced convex part: seam and junction counts, every seam closed (no open
    /// end), junctions at the expected points and radii (to 1e-9 × diagonal), every point
    /// verified maximal to 1e-6 × diagonal (the default accuracy).
    fn check(file: &str, seams: usize, junctions: &[([f64; 3], f64)]) {
        let (m, mat) = traced(file);
        let diag = m.diagonal();
        assert_eq!(
            mat.seams.len(),
            seams,
            "{file}: seams {:#?}",
            mat.seams
                .iter()
                .map(|s| (&s.segments, &s.ends))
                .collect::<Vec<_>>()
        );
        assert_eq!(mat.junctions.len(), junctions.len(), "{file}");
        for (p, r) in junctions {
            let p = DVec3::from_array(*p);
            let j = mat
                .junctions
                .iter()
                .min_by(|a, b| {
                    DVec3::from_array(a.point)
                        .distance(p)
                        .total_cmp(&DVec3::from_array(b.point).distance(p))
                })
                .unwrap();
            let e = DVec3::from_array(j.point).distance(p);
            assert!(e <= 1e-9 * diag, "{file}: junction near {p} off by {e:e}");
            assert!(
                (j.radius - r).abs() <= 1e-9 * diag,
                "{file}: radius {} vs {r}",
                j.radius
            );
        }
        for s in &mat.seams {
            assert!(
                s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
                "{file}: {:?} {:?}",
                s.segments,
                s.ends
            );
        }
        let worst = verify(&m, &mat);
        assert!(
            worst <= 1e-6 * diag,
            "{file}: worst verified error {worst:e}"
        );
    }

    /// The sphere sample (radius 15, outward normals): a ball of radius 14 fits against its
    /// wall, one of radius 16 pokes through; a plane never fails.
    #[test]
    fn curvature_criterion_on_a_sphere() {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/sphere.step");
        let m = crate::read_model(&p).unwrap();
        let s = [1.0, 0.3];
        assert!(curvature_allows(&m, Segment::Face(0), s, 14.0));
        assert!(curvature_allows(&m, Segment::Face(0), s, 15.0));
        assert!(!curvature_allows(&m, Segment::Face(0), s, 16.0));
        let (b, _) = traced("box.step");
        assert!(curvature_allows(&b, Segment::Face(0), [1.0, 1.0], 1e6));
    }

    /// Tetrahedron (0,0,0), (36,0,0), (0,28,0), (0,0,24): four seams meet at the incentre
    /// (6, 6, 6) with the inradius 6 (manifest, from Σ Aᵢ·Vᵢ / Σ Aᵢ and 3V / Σ Aᵢ).
    #[test]
    fn tetrahedron_seams_meet_at_the_incentre() {
        check("tetrahedron.step", 4, &[([6.0, 6.0, 6.0], 6.0)]);
    }

    /// Cube of side 30: a non-generic junction at the centre touching all six faces; the
    /// eight corner seams end there and nothing else leaves it.
    #[test]
    fn cube_seams_meet_at_the_centre() {
        check("cube.step", 8, &[([15.0, 15.0, 15.0], 15.0)]);
    }

    /// Wedge (a triangular prism, manifest): junctions (10,10,10) and (10,10,50), radius 10;
    /// six corner seams and one seam between the junctions.
    #[test]
    fn wedge() {
        check(
            "wedge.step",
            7,
            &[([10.0, 10.0, 10.0], 10.0), ([10.0, 10.0, 50.0], 10.0)],
        );
    }

    /// Square pyramid: the apex, where four faces meet, starts one seam down the axis; it
    /// and the four base-corner seams meet at (15, 15, 7.5), radius 7.5, a junction touching
    /// all five faces.
    #[test]
    fn pyramid_apex_is_a_non_generic_start() {
        check("pyramid.step", 5, &[([15.0, 15.0, 7.5], 7.5)]);
    }

    /// The box with a bicubic B-spline top: 12 seams and 4 junctions like the box (the bump
    /// moves them), symmetric about x = 30 and y = 20 as the part is, all points verified.
    #[test]
    fn box_with_bspline_top() {
        let (m, mat) = traced("box_bspline_top.step");
        assert_eq!(mat.seams.len(), 12);
        assert_eq!(mat.junctions.len(), 4);
        let diag = m.diagonal();
        let r0 = mat.junctions[0].radius;
        for j in &mat.junctions {
            assert!(
                (j.radius - r0).abs() <= 1e-9 * diag,
                "radii {} vs {r0}",
                j.radius
            );
            let p = DVec3::from_array(j.point);
            let mirrored = DVec3::new(60.0 - p.x, 40.0 - p.y, p.z);
            let e = mat
                .junctions
                .iter()
                .map(|k| DVec3::from_array(k.point).distance(mirrored))
                .fold(f64::INFINITY, f64::min);
            assert!(e <= 1e-9 * diag, "no mirror image of {p}: {e:e}");
        }
        assert!(verify(&m, &mat) <= 1e-6 * diag);
    }
}
