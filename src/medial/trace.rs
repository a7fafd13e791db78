//! Seam tracing by pseudo-arclength continuation (Ramanathan & Gurumoorthy 2005, §4; Allgower
//! & Georg's predictor–corrector, the paper's ref. \[1\]).
//!
//! A seam is a curve of the 3-segment medial system (9 equations, 10 unknowns). From a known
//! point `x` with unit tangent `t` (the null vector of the Jacobian, scaled so that its centre
//! part `t_B` has unit length), the predictor is `x + h·t` and the corrector solves the square
//! system `[F(x); t·(x − x_pred)] = 0`. The step `h` (millimetres of centre travel) grows when
//! the corrector converges in few iterations, shrinks when it needs many, and halves when it
//! fails or the seam turns by more than [`MAX_TURN`].
//!
//! Segments are faces, reflex edges and reflex (or mixed) vertices ([`Element`]). Seams start
//! at convex vertices (`r = 0`), leaving along each direction that moves equally away from
//! three tangent planes and no slower from the others; then from seeds: maximal balls sampled
//! on faces no seam touches (holes, solids without corners). A seam ends
//! - at a junction, when another part of the solid comes closer than `r` (located by
//!   bisection, then exactly by the 4-segment system); the other triplets leave along the
//!   normal of the plane through their touch points, in the sense in which the omitted
//!   segment moves away;
//! - at a convex vertex, when `r` returns to 0;
//! - at a curvature limit, where the ball osculates a face (two touch points on one face
//!   meet, or the curvature criterion fails): a skeletal edge starts there;
//! - closed, back at its seed;
//! - or open, with the reason, where none of these is reached.
//!
//! A touch point that leaves its segment is handed over: across a smooth edge to the next
//! face, onto and off reflex edges, from a reflex edge into the next one or onto its vertex.

use super::axis::{
    Degenerate, DegenerateKind, Handover, Junction, MedialAxis, Node, OpenReason, Seam, SeamEnd,
    SeamPoint, TraceStats,
};
use super::equations::{vertex_angles, MedialSystem, NormalField};
use super::maximal::curvature_allows;
use super::segments::SegmentGroups;
use super::solver::{solve, SolveOptions, SolveStatus};
use crate::classify::{Classification, EdgeKind, VertexKind};
use crate::geom::{project_point, Boundary, FaceHit, Feature};
use crate::model::{Element, Model};
use glam::DVec3;
use nalgebra::DVector;
use std::collections::{HashSet, VecDeque};

/// Default accuracy, relative to the bounding-box diagonal (DESIGN.md).
pub const DEFAULT_ACCURACY: f64 = 1e-6;
/// Largest centre step, relative to the diagonal.
pub const MAX_STEP: f64 = 0.02;
/// Smallest centre step before a seam is abandoned, relative to the diagonal.
pub const MIN_STEP: f64 = 1e-9;
/// Largest turn of the seam's direction over one step (radians): the step control by seam
/// curvature. A step that turns more is retried at half the length, so consecutive points are
/// never more than this apart in direction and the chord between them stays within
/// `h·MAX_TURN/8` of the curve.
pub const MAX_TURN: f64 = 0.15;
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

/// A point near a seam to trace from in both directions: a ball found by sampling (solids
/// without convex corners, sheets no corner reaches), or given by the caller.
#[derive(Clone, Debug)]
pub struct Seed {
    /// The three segments; a face may appear twice (two touch points on it).
    pub triplet: [Element; 3],
    /// Unknowns `[B, r, s₁, s₂, s₃]` near the seam; refined before tracing.
    pub x: DVector<f64>,
}

impl Seed {
    /// A seed from a centre, a radius and the three segments' parameters.
    pub fn new(triplet: [Element; 3], centre: DVec3, r: f64, params: [(f64, f64); 3]) -> Seed {
        Seed {
            triplet,
            x: seam_x(centre, r, params),
        }
    }
}

/// Where a seam starts.
struct Start {
    triplet: [Element; 3],
    x: DVector<f64>,
    /// Direction of the centre at the start.
    dir: DVec3,
    from: Node,
}

/// A hand-over: the new segment, the crossing point (old triplet) and the same point on the
/// new triplet; or why not, with the crossing point.
type HandOverResult = Result<(Element, DVector<f64>, DVector<f64>), (HandOverError, DVector<f64>)>;

/// Why a touch point could not be handed over.
enum HandOverError {
    /// The ball osculates the next element (touches it along a curve).
    Osculates(Element),
    /// The seam ends open there.
    Stop(OpenReason),
}

impl From<OpenReason> for HandOverError {
    fn from(why: OpenReason) -> Self {
        HandOverError::Stop(why)
    }
}

/// The points of one march along a seam and how it ended.
struct Run {
    points: Vec<SeamPoint>,
    end: SeamEnd,
    /// The segments at the end (after any hand-over).
    triplet: [Element; 3],
    handovers: Vec<Handover>,
}

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
    let mut t = Tracer {
        model,
        boundary,
        class,
        opts,
        face_solid: (0..model.faces.len())
            .map(|f| model.solid_of_face(f))
            .collect(),
        vertex_edges: {
            let mut ve = vec![vec![]; model.vertices.len()];
            for (e, edge) in model.edges.iter().enumerate() {
                ve[edge.vertices[0]].push((e, false));
                ve[edge.vertices[1]].push((e, true));
            }
            ve
        },
        groups: SegmentGroups::new(model, class),
        loop_chunks: model
            .faces
            .iter()
            .map(crate::geom::trim::LoopChunks::new)
            .collect(),
        junctions: vec![],
        degenerate: vec![],
        touched: vec![false; model.faces.len()],
        arrivals: vec![],
        seams: vec![],
        visited: HashSet::new(),
        traced_between: HashSet::new(),
        queue: VecDeque::new(),
        stats: TraceStats::default(),
    };
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
    t.drop_open_halves();
    MedialAxis {
        seams: t.seams,
        junctions: t.junctions,
        degenerate: t.degenerate,
        stats: t.stats,
    }
}

fn sorted(mut s: [Element; 3]) -> [Element; 3] {
    s.sort();
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

/// The segment parameters of slot `i` of a seam or junction unknown vector.
fn slot(x: &DVector<f64>, i: usize) -> [f64; 2] {
    [x[4 + 2 * i], x[5 + 2 * i]]
}

/// Distance from `p` to the segment `[a, b]`.
fn to_chord(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + d * t)
}

struct Tracer<'a> {
    model: &'a Model,
    boundary: &'a Boundary,
    class: &'a Classification,
    opts: &'a TraceOptions,
    /// The solid of each face.
    face_solid: Vec<usize>,
    /// The edges at each vertex, with `true` where the vertex is the edge's end.
    vertex_edges: Vec<Vec<(usize, bool)>>,
    /// Faces joined by smooth and reflex edges (with those edges and reflex vertices).
    groups: SegmentGroups,
    /// Each face's loops in runs with bounding boxes, for [`Tracer::stays_on`].
    loop_chunks: Vec<crate::geom::trim::LoopChunks>,
    junctions: Vec<Junction>,
    degenerate: Vec<Degenerate>,
    /// Faces some output seam point touches.
    touched: Vec<bool>,
    /// Per junction: unit directions (leaving the junction) of the seams that arrived there,
    /// so a branch along an arrived seam (same curve, another triplet of a non-generic
    /// junction) is not traced again.
    arrivals: Vec<Vec<DVec3>>,
    seams: Vec<Seam>,
    /// The two ends (and the elements there) of every seam between proper ends.
    traced_between: HashSet<[(Node, [Element; 3]); 2]>,
    /// (sorted triplet, the node where it starts or ends) already traced.
    visited: HashSet<([Element; 3], Node)>,
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

    fn solid_of(&self, seg: Element) -> usize {
        match seg {
            Element::Face(f) => self.face_solid[f],
            Element::Edge(e) => self.face_solid[self.model.edges[e].faces[0]],
            Element::Vertex(v) => self.vertex_edges[v]
                .first()
                .map_or(0, |&(e, _)| self.face_solid[self.model.edges[e].faces[0]]),
        }
    }

    /// The unit tangents of vertex `v`'s edges, pointing away from it, with the edges.
    fn vertex_tangents(&self, v: usize) -> Vec<(usize, DVec3)> {
        self.vertex_edges[v]
            .iter()
            .filter_map(|&(e, at_end)| {
                let edge = &self.model.edges[e];
                let t = if at_end { edge.range.1 } else { edge.range.0 };
                let d = crate::geom::eval_curve(&edge.curve, t).d1;
                let d = if at_end { -d } else { d };
                (d.length() > 0.0).then(|| (e, d.normalize()))
            })
            .collect()
    }

    /// The nearest point of solid `solid`'s boundary to `p`, with the face it is on.
    fn nearest_in(&self, solid: usize, p: DVec3) -> Option<(usize, FaceHit)> {
        self.boundary
            .nearest_face_where(self.model, p, |g| self.face_solid[g] == solid)
    }

    fn is_reflex(&self, e: usize) -> bool {
        self.class.edges[e].kind == EdgeKind::Reflex
    }

    /// The outward normals of edge `e`'s two faces at curve parameter `t`: the ends of the
    /// arc of normals the edge owns as a boundary segment.
    fn edge_fan(&self, e: usize, t: f64) -> Option<[DVec3; 2]> {
        let edge = &self.model.edges[e];
        let p = crate::geom::eval_curve(&edge.curve, t).p;
        let normal = |f: usize| {
            let uv = project_point(&self.model.faces[f].surface, p, None)?;
            Element::Face(f).eval(self.model, [uv.0, uv.1]).map(|e| e.n)
        };
        Some([normal(edge.faces[0])?, normal(edge.faces[1])?])
    }

    /// Where a touch point with parameters `s` on reflex edge `e` is: within the edge's
    /// range, and with its normal inside the arc between the edge's faces' normals.
    fn edge_status(&self, e: usize, s: [f64; 2]) -> (bool, bool) {
        // A touch point that the corrector leaves a hair past an end (the accuracy, in
        // length along the curve) is still on the edge: where the edge runs on into another
        // (a circle split at a seam vertex) and the touch point sits at that vertex while
        // the normal turns, an exact range test would hand it back and forth between the two.
        let (lo, hi) = self.model.edges[e].range;
        let end = s[0].clamp(lo, hi);
        let in_range = end == s[0]
            || (s[0] - end).abs()
                * crate::geom::eval_curve(&self.model.edges[e].curve, end)
                    .d1
                    .length()
                <= self.opts.accuracy;
        let in_arc = match (self.edge_fan(e, s[0]), Element::Edge(e).eval(self.model, s)) {
            (Some(fan), Some(ev)) => {
                let span = fan[0].angle_between(fan[1]);
                ev.n.angle_between(fan[0]) + ev.n.angle_between(fan[1]) <= span + 1e-9
            }
            _ => false,
        };
        (in_range, in_arc)
    }

    /// True when a touch point moving from parameters `from` to `to` stays on segment `seg`:
    /// `to` is on it, and on a face the path between did not cross a trimming loop (a step
    /// over a hole lands on the face again).
    fn stays_on(&self, seg: Element, from: [f64; 2], to: [f64; 2]) -> bool {
        self.on_segment(seg, to)
            && match seg {
                Element::Face(f) => !crate::geom::trim::path_crosses_loops(
                    &self.model.faces[f],
                    &self.loop_chunks[f],
                    glam::DVec2::from(from),
                    glam::DVec2::from(to),
                ),
                _ => true,
            }
    }

    /// True when parameters `s` lie on segment `seg`: inside a face's trim, or on a reflex
    /// edge within its range with the normal inside the arc between its faces' normals.
    fn on_segment(&self, seg: Element, s: [f64; 2]) -> bool {
        match seg {
            Element::Face(f) => {
                self.boundary
                    .contains_uv(&self.model.faces[f], f, glam::DVec2::new(s[0], s[1]))
            }
            Element::Edge(e) => {
                let (in_range, in_arc) = self.edge_status(e, s);
                in_range && in_arc
            }
            // Touching at a vertex only, the boundary must not come closer along any of its
            // edges: N·d ≥ 0 for every edge direction d leaving it.
            Element::Vertex(v) => {
                let Some(ev) = seg.eval(self.model, s) else {
                    return false;
                };
                self.vertex_tangents(v)
                    .iter()
                    .all(|(_, d)| ev.n.dot(*d) >= -1e-9)
            }
        }
    }

    /// Traces queued seams until the queue is empty.
    fn run_queue(&mut self) {
        while let Some(start) = self.queue.pop_front() {
            if self.seams.len() >= MAX_SEAMS {
                break;
            }
            let key = (sorted(start.triplet), start.from);
            if !self.visited.insert(key) {
                continue;
            }
            if let Node::Junction(j) = start.from {
                if self.arrivals[j]
                    .iter()
                    .any(|a| a.distance(start.dir) < 1e-6)
                {
                    continue;
                }
            }
            let run = self.march(start.triplet, start.x, start.dir, None);
            self.push_seam(
                start.triplet,
                run.triplet,
                [start.from.into(), run.end],
                run.points,
                run.handovers,
            );
        }
    }

    /// Drops each seam that leaves a junction and ends open when another seam arrives at that
    /// junction on the same segments: the same curve, traced completely from its other end
    /// (the open one stopped at a hand-over the other side did not need). Renumbers the rest.
    fn drop_open_halves(&mut self) {
        let key = |segs: &[Element]| {
            let mut k = segs.to_vec();
            k.sort();
            k
        };
        let arrived: HashSet<(usize, Vec<Element>)> = self
            .seams
            .iter()
            .filter(|s| !s.is_open())
            .flat_map(|s| {
                let a = match s.ends[0] {
                    SeamEnd::Junction(j) => Some((j, key(&s.segments))),
                    _ => None,
                };
                let b = match s.ends[1] {
                    SeamEnd::Junction(j) => Some((j, key(&s.end_segments))),
                    _ => None,
                };
                a.into_iter().chain(b)
            })
            .collect();
        let before = self.seams.len();
        self.seams.retain(|s| {
            !matches!((&s.ends[0], &s.ends[1]), (SeamEnd::Junction(j), SeamEnd::Open(_))
                if arrived.contains(&(*j, key(&s.segments))))
        });
        self.stats.duplicate_seams += before - self.seams.len();
        for (id, s) in self.seams.iter_mut().enumerate() {
            s.id = id;
        }
        self.stats.points = self.seams.iter().map(|s| s.points.len()).sum();
    }

    /// Records a seam; `triplet` holds the segments at its first point, `last` at its last.
    /// A seam between two proper ends (vertices, junctions) that repeats one already traced
    /// — the same ends on the same segments, reached from the other end after the branch
    /// there was traced — is dropped.
    fn push_seam(
        &mut self,
        triplet: [Element; 3],
        last: [Element; 3],
        ends: [SeamEnd; 2],
        points: Vec<SeamPoint>,
        handovers: Vec<Handover>,
    ) {
        if let (Some(a), Some(b)) = (ends[0].node(), ends[1].node()) {
            let mut key = [(a, sorted(triplet)), (b, sorted(last))];
            key.sort();
            if !self.traced_between.insert(key) {
                self.stats.duplicate_seams += 1;
                return;
            }
        }
        self.stats.points += points.len();
        let id = self.seams.len();
        self.seams.push(Seam {
            id,
            solid: self.solid_of(triplet[0]),
            segments: triplet.to_vec(),
            ends,
            end_segments: last.to_vec(),
            points,
            handovers,
        });
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
            let Some(e) = Element::Face(*f).eval(self.model, [uv.0, uv.1]) else {
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
                        triplet: [faces[a], faces[b], faces[c]].map(Element::Face),
                        x,
                        dir: u,
                        from: Node::Vertex(v),
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

    /// The seam's direction at `x` without a preferred orientation: the null vector of the
    /// Jacobian (smallest singular value of `J` padded to a square).
    fn null_direction(&self, sys: &MedialSystem, x: &DVector<f64>) -> Option<DVec3> {
        let (_, j) = sys.eval(self.model, x)?;
        let n = x.len();
        let mut a = nalgebra::DMatrix::zeros(n, n);
        a.view_mut((0, 0), (n - 1, n)).copy_from(&j);
        let svd = a.svd(false, true);
        let vt = svd.v_t?;
        let k = svd.singular_values.imin();
        let d = DVec3::new(vt[(k, 0)], vt[(k, 1)], vt[(k, 2)]);
        (d.length() > 1e-9).then(|| d.normalize())
    }

    /// Completes the trace beyond the paper (DESIGN.md, "Termination and completeness"): on
    /// every face no seam touches yet, samples boundary points, grows the maximal ball at
    /// each (shrinking from the inward normal until it touches elsewhere), and from the two
    /// touches and the nearest third segment solves for a seam point to trace from. Balls
    /// whose sheet has collapsed (a cylinder's axis, a sphere's centre) are reported as
    /// [`Degenerate`] instead.
    fn seed_by_sampling(&mut self) {
        const GRID: usize = 4;
        for f in 0..self.model.faces.len() {
            let d = self.model.faces[f].domain;
            for k in 0..GRID * GRID {
                if self.touched[f] || self.seams.len() >= MAX_SEAMS {
                    break;
                }
                let u = d.u.0 + (d.u.1 - d.u.0) * ((k % GRID) as f64 + 0.5) / GRID as f64;
                let v = d.v.0 + (d.v.1 - d.v.0) * ((k / GRID) as f64 + 0.5) / GRID as f64;
                if !self.on_segment(Element::Face(f), [u, v]) {
                    continue;
                }
                for seed in self.sample_seeds(f, [u, v]) {
                    let before = self.seams.len();
                    self.trace_seed(&seed);
                    self.run_queue();
                    if self.seams.len() > before {
                        break;
                    }
                }
            }
        }
    }

    /// The maximal ball touching face `f` at `s` and seeds from it (see
    /// [`Self::seed_by_sampling`]): with the nearest third segment, or with one of the two
    /// touched faces touched again (the foot on it nearest the point opposite the touch
    /// across the ball). None when the ball is degenerate (then recorded).
    fn sample_seeds(&mut self, f: usize, s: [f64; 2]) -> Vec<Seed> {
        self.sample_ball(f, s).unwrap_or_default()
    }

    fn sample_ball(&mut self, f: usize, s: [f64; 2]) -> Option<Vec<Seed>> {
        let solid = self.face_solid[f];
        let diag = self.model.diagonal();
        let ev = Element::Face(f).eval(self.model, s)?;
        let nearest = |b: DVec3| self.nearest_in(solid, b);
        // Largest r with nothing closer than r to p − r·n: bisection.
        let fits =
            |r: f64| nearest(ev.p - ev.n * r).is_some_and(|(_, h)| h.distance >= r * (1.0 - 1e-9));
        let (mut lo, mut hi) = (0.0, diag);
        for _ in 0..48 {
            let mid = 0.5 * (lo + hi);
            if fits(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-3 * self.opts.accuracy {
                break;
            }
        }
        let r = lo;
        let b = ev.p - ev.n * r;
        // The other touch: the nearest point just past the maximal ball, away from p.
        let (g, hit) = nearest(ev.p - ev.n * hi)?;
        if r <= 10.0 * self.opts.accuracy || hit.point.distance(ev.p) <= 1e-3 * r {
            return None; // at a convex edge, or where the ball osculates the face
        }
        let (seg2, s2) = self.hit_segment(g, &hit, b)?;
        let first = Element::Face(f);
        if self.collapsed(first, s, seg2, s2, b, r) {
            return None;
        }
        let mut thirds = vec![];
        if let Some((k, hit3)) = self.boundary.nearest_face_where(self.model, b, |h| {
            self.face_solid[h] == solid && h != f && Element::Face(h) != seg2
        }) {
            thirds.extend(self.hit_segment(k, &hit3, b));
        }
        for (seg, touch) in [(first, ev.p), (seg2, hit.point)] {
            if let Element::Face(h) = seg {
                let opposite = b * 2.0 - touch;
                if let Some(uv) = project_point(&self.model.faces[h].surface, opposite, None) {
                    thirds.push((seg, [uv.0, uv.1]));
                }
            }
        }
        Some(
            thirds
                .into_iter()
                .map(|(seg3, s3)| {
                    Seed::new(
                        [first, seg2, seg3],
                        b,
                        r,
                        [(s[0], s[1]), (s2[0], s2[1]), (s3[0], s3[1])],
                    )
                })
                .collect(),
        )
    }

    /// True (and recorded as [`Degenerate`]) when the sheet of balls touching `a` at `sa` and
    /// `b` at `sb` has collapsed at centre `c`, radius `r`: the directions in which the two
    /// touch points can move together (the null space of the 2-segment Jacobian, 6 × 8) move
    /// the centre along fewer than two dimensions.
    fn collapsed(
        &mut self,
        a: Element,
        sa: [f64; 2],
        b: Element,
        sb: [f64; 2],
        c: DVec3,
        r: f64,
    ) -> bool {
        let sys = MedialSystem::new(vec![a, b]);
        let mut x = DVector::zeros(8);
        x[0] = c.x;
        x[1] = c.y;
        x[2] = c.z;
        x[3] = r;
        x[4] = sa[0];
        x[5] = sa[1];
        x[6] = sb[0];
        x[7] = sb[1];
        let Some((_, j)) = sys.eval(self.model, &x) else {
            return false;
        };
        let mut m = nalgebra::DMatrix::zeros(8, 8);
        m.view_mut((0, 0), (6, 8)).copy_from(&j);
        let svd = m.svd(false, true);
        let Some(vt) = svd.v_t else {
            return false;
        };
        let smax = svd.singular_values.max();
        // The null space: right singular vectors of (near-)zero singular values.
        let null: Vec<DVec3> = (0..8)
            .filter(|&i| svd.singular_values[i] <= 1e-6 * smax)
            .map(|i| DVec3::new(vt[(i, 0)], vt[(i, 1)], vt[(i, 2)]))
            .collect();
        let rank = match null.len() {
            0 | 1 => return false,
            _ => {
                let big = null.iter().map(|v| v.length()).fold(0.0, f64::max);
                let area = (0..null.len())
                    .flat_map(|i| (i + 1..null.len()).map(move |k| (i, k)))
                    .map(|(i, k)| null[i].cross(null[k]).length())
                    .fold(0.0, f64::max);
                if area > 1e-6 {
                    return false;
                }
                usize::from(big > 1e-6)
            }
        };
        let kind = if rank == 0 {
            DegenerateKind::Point
        } else {
            DegenerateKind::Curve
        };
        let segments = vec![a, b];
        let solid = self.solid_of(a);
        let ball = [c.x, c.y, c.z, r];
        match self
            .degenerate
            .iter_mut()
            .find(|d| d.solid == solid && d.kind == kind && d.segments == segments)
        {
            Some(d) => d.balls.push(ball),
            None => self.degenerate.push(Degenerate {
                solid,
                kind,
                segments,
                balls: vec![ball],
            }),
        }
        if let Element::Face(f) = a {
            self.touched[f] = true;
        }
        true
    }

    /// Refines `seed` onto its seam and, unless it is not a medial point or lies on a seam
    /// already traced, traces that seam both ways (queueing what its junctions lead to).
    fn trace_seed(&mut self, seed: &Seed) {
        let sys = MedialSystem::new(seed.triplet.to_vec());
        let sol = solve(
            |y| sys.eval(self.model, y),
            seed.x.clone(),
            &SolveOptions {
                tol: 1e-3 * self.opts.accuracy,
                max_iter: 30,
            },
        );
        let x = sol.x;
        let r = x[3];
        // A ball that osculates one of its faces (a fillet's axis: radius = the fillet's,
        // touching it along a whole arc) is a degenerate piece, not a seam point, although
        // the three-segment system is solvable there.
        let osculates = (0..3).any(|i| {
            matches!(seed.triplet[i], Element::Face(_))
                && !curvature_allows(self.model, seed.triplet[i], slot(&x, i), r * (1.0 + 1e-6))
        });
        let valid = sol.status == SolveStatus::Converged
            && r > self.opts.accuracy
            && !osculates
            && self.is_medial(&seed.triplet, &x)
            && !self.on_traced_seam(&seed.triplet, &x);
        let dir = valid.then(|| self.null_direction(&sys, &x)).flatten();
        let Some(dir) = dir else {
            self.stats.skipped_seeds += 1;
            return;
        };
        let fwd = self.march(seed.triplet, x.clone(), dir, Some(&x));
        if fwd.end == SeamEnd::Closed {
            let ends = [SeamEnd::Closed, SeamEnd::Closed];
            self.push_seam(seed.triplet, fwd.triplet, ends, fwd.points, fwd.handovers);
            return;
        }
        let back = self.march(seed.triplet, x, -dir, None);
        // The backward run reversed, then the forward run after the seed point; the
        // backward run's hand-overs reversed in order and sense.
        let nb = back.points.len();
        let mut handovers: Vec<Handover> = back
            .handovers
            .into_iter()
            .rev()
            .map(|h| Handover {
                point: nb - 1 - h.point,
                from: h.to,
                to: h.from,
            })
            .collect();
        handovers.extend(fwd.handovers.into_iter().map(|h| Handover {
            point: h.point + nb - 1,
            ..h
        }));
        let mut points: Vec<SeamPoint> = back.points.into_iter().rev().collect();
        points.extend(fwd.points.into_iter().skip(1));
        self.push_seam(
            back.triplet,
            fwd.triplet,
            [back.end, fwd.end],
            points,
            handovers,
        );
    }

    /// True when the seam point `x` is medial: its touch points lie on their faces, nothing
    /// of the solid is closer than `r`, and no touched face curves through the ball.
    fn is_medial(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        let r = x[3];
        let solid = self.solid_of(triplet[0]);
        let on_faces = (0..3).all(|i| self.on_segment(triplet[i], slot(x, i)));
        // A segment touched twice must be touched in two places, not once counted twice
        // (that is a sheet point, where Newton also converges).
        let distinct = !touches_meet(self.model, triplet, x, 1e-3 * r, Pairs::SameSegment);
        let nearest = self.nearest_in(solid, v3(x));
        on_faces
            && distinct
            && nearest.is_some_and(|(_, h)| h.distance >= r - self.opts.accuracy)
            && (0..3).all(|i| curvature_allows(self.model, triplet[i], slot(x, i), r))
    }

    /// True when `x` lies on a seam of the same segments traced already.
    fn on_traced_seam(&self, triplet: &[Element; 3], x: &DVector<f64>) -> bool {
        let b = v3(x);
        let tol = 1e-3 * self.model.diagonal();
        let ids: Vec<Element> = sorted(*triplet).to_vec();
        self.seams.iter().any(|s| {
            let mut same = s.segments.clone();
            same.sort();
            let mut want = ids.clone();
            want.sort();
            same == want
                && s.points.windows(2).any(|w| {
                    let a = DVec3::new(w[0].point[0], w[0].point[1], w[0].point[2]);
                    let c = DVec3::new(w[1].point[0], w[1].point[1], w[1].point[2]);
                    to_chord(b, a, c) <= tol
                })
        })
    }

    /// Marches along the seam of `triplet` from the seam point `x0`, leaving along `dir0`,
    /// until it ends (see [`SeamEnd`]). With `close_at`, a march that comes back to that
    /// point ends [`SeamEnd::Closed`].
    fn march(
        &mut self,
        mut triplet: [Element; 3],
        x0: DVector<f64>,
        dir0: DVec3,
        close_at: Option<&DVector<f64>>,
    ) -> Run {
        let mut sys = MedialSystem::new(triplet.to_vec());
        let mut handovers = vec![];
        let first = triplet;
        let solid = self.solid_of(triplet[0]);
        let diag = self.model.diagonal();
        let acc = self.opts.accuracy;
        let mut x = x0;
        let mut points = vec![self.seam_point(&sys, &x)];
        // The first tangent is oriented by the centre's direction alone (no weight on r).
        let mut dir = DVector::zeros(10);
        dir[0] = dir0.x;
        dir[1] = dir0.y;
        dir[2] = dir0.z;
        let Some(mut t) = self.tangent(&sys, &x, &dir) else {
            let end = SeamEnd::Open(OpenReason::SingularTangent);
            return Run {
                points,
                end,
                triplet,
                handovers,
            };
        };
        let mut h = 1e-3 * diag;
        let mut travel = 0.0;
        let end: SeamEnd;
        loop {
            if points.len() >= MAX_POINTS {
                end = SeamEnd::Open(OpenReason::PointBudgetExhausted);
                break;
            }
            let Some((xn, tn, iterations)) = self.step(&sys, &x, &t, h) else {
                self.stats.corrector_failures += 1;
                h *= 0.5;
                if h < MIN_STEP * diag {
                    end = SeamEnd::Open(OpenReason::StepSizeUnderflow);
                    break;
                }
                continue;
            };
            let r = xn[3];
            // Back to a convex vertex: r returns to zero.
            // (Away from a vertex with a touch point off its segment, the step overshot a
            // hand-over or a junction: that is handled below.)
            if r <= acc && points.len() > 1 {
                let (xe, v) = self.land_at_vertex(&sys, xn.clone());
                let off = (0..3).any(|i| !self.on_segment(triplet[i], slot(&xn, i)));
                if v.is_some() || !off {
                    points.push(self.seam_point(&sys, &xe));
                    end = v.map_or_else(
                        || SeamEnd::Open(OpenReason::ZeroRadiusAwayFromVertex),
                        SeamEnd::Vertex,
                    );
                    break;
                }
            }
            // Back at the seed: a closed seam.
            // (Only on the segments it started with: the seed's parameters are theirs.)
            if let Some(xs) = close_at.filter(|_| triplet == first) {
                let step = v3(&xn).distance(v3(&x));
                if travel > 3.0 * step
                    && to_chord(v3(xs), v3(&x), v3(&xn)) <= 0.05 * step + 10.0 * acc
                    && (xs[3] - r).abs() <= 0.05 * step + 10.0 * acc
                {
                    points.push(self.seam_point(&sys, xs));
                    end = SeamEnd::Closed;
                    break;
                }
            }
            // A touch point that leaves its segment is handed over to the next one across
            // the edge it crossed (xn itself, off the segment, is not output).
            if let Some(mut i) =
                (0..3).find(|&i| !self.stays_on(triplet[i], slot(&x, i), slot(&xn, i)))
            {
                match self.hand_over(&triplet, &mut i, &x, &t, h) {
                    Ok((to, xc, _))
                        if handovers.last().is_some_and(|h: &Handover| {
                            h.point + 1 >= points.len() && h.to == triplet[i] && h.from == to
                        }) =>
                    {
                        // The touch point sits at a vertex while the normal turns: it is
                        // on the vertex (a corner of two reflex edges, or of faceted faces
                        // meeting at small angles), not on either neighbour.
                        let from = triplet[i];
                        match self.onto_vertex(&triplet, i, &xc, &t) {
                            Some((v, xv)) => {
                                handovers.push(Handover {
                                    point: points.len(),
                                    from,
                                    to: v,
                                });
                                triplet[i] = v;
                                sys = MedialSystem::new(triplet.to_vec());
                                points.push(self.seam_point(&sys, &xv));
                                let mut d = DVector::zeros(10);
                                d.rows_mut(0, 3).copy_from(&t.rows(0, 3));
                                let Some(tc) = self.tangent(&sys, &xv, &d) else {
                                    end = SeamEnd::Open(OpenReason::SingularTangentAfterHandover);
                                    break;
                                };
                                travel += v3(&xv).distance(v3(&x));
                                x = xv;
                                t = tc;
                                continue;
                            }
                            None => {
                                end = SeamEnd::Open(OpenReason::Oscillates { from, to });
                                break;
                            }
                        }
                    }
                    Ok((to, crossing, xnew)) => {
                        // The crossing point must itself be medial: a junction may come first.
                        if let Some((e, jx)) =
                            self.junction_between(&triplet, solid, &x, &crossing, &t)
                        {
                            if let Some(jx) = jx {
                                points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                            }
                            end = e;
                            break;
                        }
                        let xc = xnew;
                        let nt = new_triplet(&triplet, i, to);
                        if self.coincident(&nt, &xc, true) {
                            // Two touch points on one part of the boundary (faces and the
                            // reflex edges and vertices joining them, across which a touch
                            // point moves on) have met: the ball osculates it there, like a
                            // face touched twice at its curvature limit, and the seam ends.
                            let at = |k: usize| sys_point(self.model, nt[k], slot(&xc, k));
                            let merged = (0..3).find(|&k| {
                                k != i
                                    && self.groups.of(nt[k]) == self.groups.of(to)
                                    && matches!((at(k), at(i)), (Some(a), Some(b)) if a.distance(b) <= 1e-4 * xc[3])
                            });
                            end = match merged {
                                Some(_) => {
                                    points.push(self.seam_point(&sys, &crossing));
                                    SeamEnd::CurvatureLimit { segment: to }
                                }
                                None => SeamEnd::Open(OpenReason::CoincideAfterHandover {
                                    from: triplet[i],
                                    to,
                                }),
                            };
                            break;
                        }
                        handovers.push(Handover {
                            point: points.len(),
                            from: triplet[i],
                            to,
                        });
                        triplet[i] = to;
                        sys = MedialSystem::new(triplet.to_vec());
                        points.push(self.seam_point(&sys, &xc));
                        let mut d = DVector::zeros(10);
                        d.rows_mut(0, 3).copy_from(&t.rows(0, 3));
                        let Some(tc) = self.tangent(&sys, &xc, &d) else {
                            end = SeamEnd::Open(OpenReason::SingularTangentAfterHandover);
                            break;
                        };
                        travel += v3(&xc).distance(v3(&x));
                        x = xc;
                        t = tc;
                        continue;
                    }
                    Err((e, xc)) => {
                        // A junction before the crossing ends the seam there instead (the
                        // step that left the segment may have passed it).
                        if let Some((e, jx)) = self.junction_between(&triplet, solid, &x, &xc, &t) {
                            if let Some(jx) = jx {
                                points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                            }
                            end = e;
                            break;
                        }
                        // The crossing point itself is a seam point when it is medial.
                        if self.is_medial(&triplet, &xc) {
                            points.push(self.seam_point(&sys, &xc));
                        }
                        end = match e {
                            HandOverError::Osculates(seg) => {
                                SeamEnd::CurvatureLimit { segment: seg }
                            }
                            HandOverError::Stop(why) => SeamEnd::Open(why),
                        };
                        break;
                    }
                }
            }
            // Another part of the boundary closer than r: a junction between x and xn.
            if let Some((e, jx)) = self.junction_between(&triplet, solid, &x, &xn, &t) {
                if let Some(jx) = jx {
                    points.push(self.seam_point(&sys, &jx.rows(0, 10).into_owned()));
                }
                end = e;
                break;
            }
            // The curvature criterion: the ball must not poke through a touched face. Where
            // the ball touches a face twice, the two touch points must not meet (or pass
            // through each other): where they meet the ball osculates the face, r·κmax = 1,
            // and the seam ends at that centre of curvature.
            let touches = |y: &DVector<f64>| -> [Option<DVec3>; 3] {
                std::array::from_fn(|i| sys_point(self.model, triplet[i], slot(y, i)))
            };
            let before = touches(&x);
            let poked = |y: &DVector<f64>| {
                let now = touches(y);
                (0..3).find(|&i| {
                    !curvature_allows(self.model, triplet[i], slot(y, i), y[3])
                        || (0..i).any(|j| {
                            triplet[j] == triplet[i]
                                && match (before[i], before[j], now[i], now[j]) {
                                    // Separated by less than 1e-4·r, the centre is within
                                    // ~(1e-4·r)²/ρ of the end: far below the accuracy.
                                    (Some(a), Some(b), Some(c), Some(d)) => {
                                        (c - d).dot(a - b) <= 0.0 || c.distance(d) <= 1e-4 * y[3]
                                    }
                                    _ => true,
                                }
                        })
                })
            };
            // Two different segments touched at one place (where a face meets its edge): the
            // ball touches fewer than three places, so the point is no seam point.
            if self.coincident(&triplet, &xn, false) {
                end = SeamEnd::Open(OpenReason::TouchPointsCoincide);
                break;
            }
            if let Some(i) = poked(&xn) {
                // Bisect the arclength from x to where the ball osculates, to the accuracy.
                let (mut lo, mut hi) = (0.0, h);
                let mut last = None;
                while hi - lo > acc {
                    let mid = 0.5 * (lo + hi);
                    match self.centre_step(&sys, &x, &t, mid) {
                        Some(xm) if poked(&xm).is_none() => {
                            lo = mid;
                            last = Some(xm);
                        }
                        _ => hi = mid,
                    }
                }
                if let Some(xm) = last {
                    points.push(self.seam_point(&sys, &xm));
                }
                end = SeamEnd::CurvatureLimit {
                    segment: triplet[i],
                };
                break;
            }
            points.push(self.seam_point(&sys, &xn));
            travel += v3(&xn).distance(v3(&x));
            x = xn;
            t = tn;
            h = if iterations <= 3 {
                (h * 1.5).min(MAX_STEP * diag)
            } else {
                h * 0.7
            };
        }
        Run {
            points,
            end,
            triplet,
            handovers,
        }
    }

    /// True when two touch points of the seam point `x` are one place (closer than 1e-4·r):
    /// for different segments always, for a segment touched twice only with `same` (a
    /// merging pair on one face is otherwise the curvature limit's business).
    fn coincident(&self, triplet: &[Element; 3], x: &DVector<f64>, same: bool) -> bool {
        let pairs = if same {
            Pairs::All
        } else {
            Pairs::DifferentSegments
        };
        touches_meet(self.model, triplet, x, 1e-4 * x[3], pairs)
    }

    /// Hands touch point `i` over to the next segment: finds (by bisecting the step `h` from
    /// `x` along `t`) the last seam point with the touch point still on its segment, which is
    /// then on the segment's boundary, and continues it on the neighbour there: across a
    /// smooth edge the next face; onto a reflex edge the edge (the normal is that face's
    /// normal, an end of the edge's arc); off a reflex edge's arc the face at that end.
    /// Returns the new segment, the crossing point (on the old triplet) and the same point
    /// solved for the new triplet, or why the touch point cannot continue (a convex edge, an
    /// edge's end).
    fn hand_over(
        &mut self,
        triplet: &[Element; 3],
        i: &mut usize,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> HandOverResult {
        let acc = self.opts.accuracy;
        let sys = MedialSystem::new(triplet.to_vec());
        let (mut lo, mut hi) = (0.0, h);
        let mut xc = x.clone();
        // The nearest point past the crossing: which touch point left first (two may leave
        // within one step, at a rounded corner), and which of an edge's bounds it broke.
        let mut off: Option<DVector<f64>> = None;
        let on_all = |me: &Self, y: &DVector<f64>| {
            (0..3).all(|k| me.stays_on(triplet[k], slot(x, k), slot(y, k)))
        };
        while hi - lo > 0.1 * acc {
            let mid = 0.5 * (lo + hi);
            match self.step(&sys, x, t, mid) {
                Some((xm, _, _)) if on_all(self, &xm) => {
                    lo = mid;
                    xc = xm;
                }
                Some((xm, _, _)) => {
                    hi = mid;
                    off = Some(xm);
                }
                None => hi = mid,
            }
        }
        if let Some(k) = off
            .as_ref()
            .and_then(|y| (0..3).find(|&k| !self.stays_on(triplet[k], slot(x, k), slot(y, k))))
        {
            *i = k;
        }
        let i = *i;
        let off = off.map(|y| slot(&y, i));
        let exit = match (triplet[i], off) {
            (Element::Edge(e), Some(s)) => Some(self.edge_status(e, s)),
            _ => None,
        };
        // Off an edge's end: the crossing is where the touch point is exactly at the end
        // (the bisection on the centre's travel leaves it up to the accuracy short of or
        // past it), so the next segment takes over the same ball at the shared vertex.
        if let (Element::Edge(e), Some((false, true))) = (triplet[i], exit) {
            let (lo, hi) = self.model.edges[e].range;
            let te = slot(&xc, i)[0];
            let end = if te - lo < hi - te { lo } else { hi };
            let mut row = DVector::zeros(10);
            row[4 + 2 * i] = 1.0;
            let sol = solve(
                |z| sys.eval_with_row(self.model, z, &row, end),
                xc.clone(),
                &self.solve_opts(),
            );
            if sol.status == SolveStatus::Converged && v3(&sol.x).distance(v3(&xc)) <= 10.0 * acc {
                xc = sol.x;
            }
        }
        match self.hand_over_at(triplet, i, &xc, t, exit) {
            Ok((to, xnew)) => Ok((to, xc, xnew)),
            Err(e) => Err((e, xc)),
        }
    }

    /// [`Self::hand_over`] at the crossing point `xc`. For a touch point on an edge, `exit`
    /// says which bounds the point just past the crossing kept (range, arc), when known.
    fn hand_over_at(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
        exit: Option<(bool, bool)>,
    ) -> Result<(Element, DVector<f64>), HandOverError> {
        let acc = self.opts.accuracy;
        let xc = xc.clone();
        let seg = triplet[i];
        let ev = seg
            .eval(self.model, slot(&xc, i))
            .ok_or(OpenReason::UndefinedNormal { element: seg })?;
        let (to, params) = match seg {
            Element::Face(f) => {
                let (e, te) = self
                    .nearest_edge_of_face(f, ev.p)
                    .filter(|&(e, te)| {
                        let q = crate::geom::eval_curve(&self.model.edges[e].curve, te).p;
                        q.distance(ev.p) <= 1e3 * acc
                    })
                    .ok_or(OpenReason::LeftFaceAwayFromEdges { face: seg })?;
                let edge = &self.model.edges[e];
                match self.class.edges[e].kind {
                    EdgeKind::Reflex => {
                        let th = crate::medial::equations::edge_angle(self.model, e, te, ev.n)
                            .ok_or(OpenReason::NoNormalFrame { edge: e })?;
                        (Element::Edge(e), [te, th])
                    }
                    EdgeKind::Smooth => {
                        let g = if edge.faces[0] == f {
                            edge.faces[1]
                        } else {
                            edge.faces[0]
                        };
                        let uv = project_point(&self.model.faces[g].surface, ev.p, None)
                            .ok_or(OpenReason::NotFoundOnFace { face: g })?;
                        (Element::Face(g), [uv.0, uv.1])
                    }
                    kind => {
                        return Err(HandOverError::Stop(OpenReason::ReachedEdge {
                            element: seg,
                            kind,
                            edge: e,
                        }))
                    }
                }
            }
            Element::Edge(e) => {
                let edge = &self.model.edges[e];
                let te = slot(&xc, i)[0];
                let (lo, hi) = edge.range;
                // Off the edge's end or off its arc? The crossing is bisected on the centre's
                // travel, so the touch point may stop short of the end by more than a
                // relative 1e-6: an end within 10× the accuracy, or a normal well inside
                // the arc, means the end.
                let at_end = match exit {
                    Some((in_range, in_arc)) => !in_range && in_arc,
                    None => {
                        let near_end = self.model.vertices[edge.vertices[0]]
                            .point
                            .distance(ev.p)
                            .min(self.model.vertices[edge.vertices[1]].point.distance(ev.p))
                            <= 10.0 * acc;
                        (te - lo).min(hi - te) <= 1e-6 * (hi - lo)
                            || (near_end
                                && self.edge_fan(e, te).is_some_and(|fan| {
                                    ev.n.angle_between(fan[0]).min(ev.n.angle_between(fan[1]))
                                        > 1e-4
                                }))
                    }
                };
                if at_end {
                    // On to the vertex at that end, with the same normal.
                    let v = if te - lo < hi - te {
                        edge.vertices[0]
                    } else {
                        edge.vertices[1]
                    };
                    // A reflex edge continued by another (a circle split at a seam vertex, a
                    // line running into an arc, a closed edge into its own start): the touch
                    // point goes on along it.
                    let next: Vec<(usize, f64)> = self.vertex_edges[v]
                        .iter()
                        .filter(|&&(g, at_end)| {
                            self.is_reflex(g) && !(g == e && at_end == (te - lo >= hi - te))
                        })
                        .map(|&(g, at_end)| {
                            let r = self.model.edges[g].range;
                            (g, if at_end { r.1 } else { r.0 })
                        })
                        .collect();
                    // (Only where the two run on tangentially. At a corner of two reflex
                    // edges the touch point stays on the vertex while the normal turns.)
                    if let [(g, tg)] = next[..] {
                        let tangents = self.vertex_tangents(v);
                        let leaving =
                            |k: usize| tangents.iter().find(|(h, _)| *h == k).map(|(_, d)| *d);
                        let tangential = match (leaving(e), leaving(g)) {
                            // Leaving v along e is arriving along −e; g goes on from there.
                            (Some(de), Some(dg)) if e != g => {
                                (-de).angle_between(dg)
                                    <= crate::classify::DEFAULT_ANGLE_TOL_DEG.to_radians()
                            }
                            _ => true,
                        };
                        if let Some(th) = tangential
                            .then(|| crate::medial::equations::edge_angle(self.model, g, tg, ev.n))
                            .flatten()
                        {
                            let to = Element::Edge(g);
                            return self.polish_hand_over(triplet, i, &xc, t, to, [tg, th], ev.p);
                        }
                    }
                    if !matches!(
                        self.class.vertices[v],
                        VertexKind::Reflex | VertexKind::Mixed
                    ) {
                        return Err(HandOverError::Stop(OpenReason::ReachedEdgeEnd {
                            edge: e,
                            vertex_kind: self.class.vertices[v],
                        }));
                    }
                    let to = Element::Vertex(v);
                    return self.polish_hand_over(
                        triplet,
                        i,
                        &xc,
                        t,
                        to,
                        vertex_angles(ev.n),
                        ev.p,
                    );
                }
                let fan = self
                    .edge_fan(e, te)
                    .ok_or(OpenReason::NoFaceNormals { edge: e })?;
                let k = if ev.n.angle_between(fan[0]) <= ev.n.angle_between(fan[1]) {
                    0
                } else {
                    1
                };
                let g = edge.faces[k];
                let uv = project_point(&self.model.faces[g].surface, ev.p, None)
                    .ok_or(OpenReason::NotFoundOnFace { face: g })?;
                (Element::Face(g), [uv.0, uv.1])
            }
            Element::Vertex(v) => {
                // Off the vertex over the edge whose direction the normal turned away from.
                let (e, _) = self
                    .vertex_tangents(v)
                    .into_iter()
                    .min_by(|a, b| ev.n.dot(a.1).total_cmp(&ev.n.dot(b.1)))
                    .ok_or(OpenReason::VertexWithoutEdges { vertex: v })?;
                if !self.is_reflex(e) {
                    return Err(HandOverError::Stop(OpenReason::ReachedEdge {
                        element: Element::Vertex(v),
                        kind: self.class.edges[e].kind,
                        edge: e,
                    }));
                }
                let edge = &self.model.edges[e];
                let te = if edge.vertices[0] == v {
                    edge.range.0
                } else {
                    edge.range.1
                };
                let th = crate::medial::equations::edge_angle(self.model, e, te, ev.n)
                    .ok_or(OpenReason::NoNormalFrame { edge: e })?;
                (Element::Edge(e), [te, th])
            }
        };
        self.polish_hand_over(triplet, i, &xc, t, to, params, ev.p)
    }

    /// Moves touch point `i` of the seam point `xc` onto the vertex it sits at (within 10×
    /// the accuracy), keeping its normal, when the ball may touch that vertex there (the
    /// normal inside the vertex's cone) and the re-solved point is the same ball.
    fn onto_vertex(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
    ) -> Option<(Element, DVector<f64>)> {
        let ev = triplet[i].eval(self.model, slot(xc, i))?;
        let v = (0..self.model.vertices.len())
            .filter(|&v| self.model.vertices[v].point.distance(ev.p) <= 10.0 * self.opts.accuracy)
            .min_by(|&a, &b| {
                let da = self.model.vertices[a].point.distance(ev.p);
                da.total_cmp(&self.model.vertices[b].point.distance(ev.p))
            })?;
        let to = Element::Vertex(v);
        let params = vertex_angles(ev.n);
        if !self.on_segment(to, params) {
            return None;
        }
        let (to, xv) = self
            .polish_hand_over(triplet, i, xc, t, to, params, ev.p)
            .ok()?;
        (!self.coincident(&new_triplet(triplet, i, to), &xv, true)).then_some((to, xv))
    }

    /// The end of a hand-over: the seam point `xc` with slot `i` moved to segment `to` at
    /// `params`, polished on the new system, which must be the same ball touching `to` at
    /// the old touch point `p`.
    #[allow(clippy::too_many_arguments)]
    fn polish_hand_over(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
        to: Element,
        params: [f64; 2],
        p: DVec3,
    ) -> Result<(Element, DVector<f64>), HandOverError> {
        let acc = self.opts.accuracy;
        let seg = triplet[i];
        let xc = xc.clone();
        // The ball osculates the next face (a fillet or a corner patch of its own radius):
        // it touches it along a curve, and the seam ends there, at that centre of curvature.
        if !curvature_allows(self.model, to, params, xc[3] * (1.0 + 1e-6)) {
            return Err(HandOverError::Osculates(to));
        }
        let mut new = *triplet;
        new[i] = to;
        let sys = MedialSystem::new(new.to_vec());
        let mut y = xc.clone();
        y[4 + 2 * i] = params[0];
        y[5 + 2 * i] = params[1];
        // Polish on the new system with the centre held in the plane normal to the seam.
        let mut row = DVector::zeros(10);
        row.rows_mut(0, 3).copy_from(&t.rows(0, 3));
        let c = row.dot(&y);
        let sol = solve(
            |z| sys.eval_with_row(self.model, z, &row, c),
            y,
            &self.solve_opts(),
        );
        // The same ball, touching the new segment where the old one left off: to 2× the
        // accuracy, plus the gap between where the touch point left its segment and where
        // the new one starts (a face's trim is a sampled polygon; its crossing is off the
        // exact edge by up to the polygon's sag). The new point is solved exactly anyway.
        let gap = sys_point(self.model, to, params).map_or(0.0, |q| q.distance(p));
        let same = sol.status == SolveStatus::Converged
            && v3(&sol.x).distance(v3(&xc)) <= 2.0 * acc + 10.0 * gap
            && sys_point(self.model, to, slot(&sol.x, i))
                .is_some_and(|q| q.distance(p) <= 2.0 * acc + 2.0 * gap);
        if !same {
            return Err(HandOverError::Stop(OpenReason::NoSeamPointAfterHandover {
                from: seg,
                to,
                status: sol.status,
                moved: v3(&sol.x).distance(v3(&xc)),
            }));
        }
        Ok((to, sol.x))
    }

    /// The edge of face `f` nearest to `p`, with the curve parameter of the nearest point.
    fn nearest_edge_of_face(&self, f: usize, p: DVec3) -> Option<(usize, f64)> {
        self.model.faces[f]
            .loops
            .iter()
            .flat_map(|l| l.edges.iter())
            .map(|oe| {
                let (te, _, d) = crate::geom::nearest_on_edge(self.model, oe.edge, p, None);
                (oe.edge, te, d)
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(e, te, _)| (e, te))
    }

    /// One predictor–corrector step of length `h` from `x` along the unit tangent `t`: the new
    /// point, its tangent (oriented along `t`) and the corrector's iterations. `None` when the
    /// corrector fails, the radius goes negative from a point that already had r ≤ 0, or the
    /// seam turns by more than [`MAX_TURN`] (step control by seam curvature).
    fn step(
        &mut self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> Option<(DVector<f64>, DVector<f64>, usize)> {
        let pred = x + t * h;
        // Corrector: F = 0 and t·(y − pred) = 0.
        let c = t.dot(&pred);
        let sol = solve(
            |y| sys.eval_with_row(self.model, y, t, c),
            pred,
            &self.solve_opts(),
        );
        self.stats.newton_iterations += sol.iterations;
        if sol.status != SolveStatus::Converged || sol.x[3] < -self.opts.accuracy && x[3] <= 0.0 {
            return None;
        }
        let tn = self.tangent(sys, &sol.x, t)?;
        let turn = v3(t).angle_between(v3(&tn));
        (turn <= MAX_TURN).then_some((sol.x, tn, sol.iterations))
    }

    /// The seam point whose centre lies in the plane `t_B·(B − B(x)) = h` (normal to the
    /// centre's direction `t_B`, `h` ahead), from a start with `x`'s segment parameters. Near
    /// an end where two touch points on one face meet, the parameters move like the square
    /// root of the centre's travel, so the arclength predictor along `t` overshoots them;
    /// fixing only the centre's advance keeps Newton within reach (used to locate ends).
    fn centre_step(
        &mut self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        t: &DVector<f64>,
        h: f64,
    ) -> Option<DVector<f64>> {
        let tb = v3(t).normalize();
        let mut row = DVector::zeros(x.len());
        row[0] = tb.x;
        row[1] = tb.y;
        row[2] = tb.z;
        let mut start = x.clone();
        for k in 0..4 {
            start[k] += h * t[k] / v3(t).length();
        }
        let c = row.dot(x) + h;
        let sol = solve(
            |y| sys.eval_with_row(self.model, y, &row, c),
            start,
            &SolveOptions {
                tol: 1e-3 * self.opts.accuracy,
                max_iter: 40,
            },
        );
        self.stats.newton_iterations += sol.iterations;
        (sol.status == SolveStatus::Converged).then_some(sol.x)
    }

    /// Lands a seam point that reached `r ≈ 0` exactly on `r = 0` (the corrector may have
    /// overshot to a negative radius) by replacing the arclength equation with `r = 0`, and
    /// finds the vertex there.
    fn land_at_vertex(
        &mut self,
        sys: &MedialSystem,
        xn: DVector<f64>,
    ) -> (DVector<f64>, Option<usize>) {
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
        let v = (0..self.model.vertices.len())
            .min_by(|&a, &c| {
                let va = self.model.vertices[a].point.distance(b);
                va.total_cmp(&self.model.vertices[c].point.distance(b))
            })
            .filter(|&v| self.model.vertices[v].point.distance(b) <= 1e3 * self.opts.accuracy);
        (xe, v)
    }

    /// Checks the new seam point `xn` (reached from `x` along `t`) for a part of the solid's
    /// boundary closer than `r`: another face, or a touched face far from its touch point
    /// (the ball meets it a second time; a face close to its own touch point is the
    /// curvature criterion's business). Then the seam ends at the junction located between
    /// `x` and `xn`, or — when the 4-segment system has no solution on the faces — open.
    fn junction_between(
        &mut self,
        triplet: &[Element; 3],
        solid: usize,
        x: &DVector<f64>,
        xn: &DVector<f64>,
        t: &DVector<f64>,
    ) -> Option<(SeamEnd, Option<DVector<f64>>)> {
        let (mut f, mut hit) = self.intrusion(triplet, solid, xn)?;
        // The first intrusion between x and xn (another feature may come closer than r
        // before the one seen at xn): bisect the step.
        let sys = MedialSystem::new(triplet.to_vec());
        let h = t.dot(&(xn - x)) / t.dot(t);
        let (mut lo, mut hi) = (0.0, h);
        let mut x_lo = x.clone();
        let mut x_hi = xn.clone();
        for _ in 0..12 {
            let mid = 0.5 * (lo + hi);
            let Some((xm, _, _)) = self.step(&sys, x, t, mid) else {
                break;
            };
            match self.intrusion(triplet, solid, &xm) {
                Some((g, hg)) => {
                    (f, hit) = (g, hg);
                    hi = mid;
                    x_hi = xm;
                }
                None => {
                    lo = mid;
                    x_lo = xm;
                }
            }
        }
        let x = &x_lo;
        let Some((fourth, s4)) = self.hit_segment(f, &hit, v3(&x_hi)) else {
            let (on, t) = match hit.on {
                Feature::Face(g) => (Element::Face(g), None),
                Feature::Edge(e, t) => (Element::Edge(e), Some(t)),
                Feature::Vertex(v) => (Element::Vertex(v), None),
            };
            let why = OpenReason::CloserThanR { on, t };
            return Some((SeamEnd::Open(why), None));
        };
        // A hit reported inside a face but next to one of its reflex edges (the trim test
        // and the nearest-point search agree only to their tolerances) may be a touch of
        // the edge: try it when the face has no junction.
        let located = self
            .locate_junction(triplet, x, fourth, s4)
            .map(|jx| (fourth, jx))
            .or_else(|| {
                let Element::Face(f) = fourth else {
                    return None;
                };
                let (e, te) = self.nearest_edge_of_face(f, hit.point)?;
                let edge = Element::Edge(e);
                (self.is_reflex(e) && !triplet.contains(&edge))
                    .then(|| self.locate_junction(triplet, x, edge, [te, 0.0]))
                    .flatten()
                    .map(|jx| (edge, jx))
            });
        // The junction itself must be medial (nothing closer than its radius).
        let located = located.filter(|(_, jx)| {
            self.nearest_in(solid, v3(jx))
                .is_some_and(|(_, h)| h.distance >= jx[3] - 10.0 * self.opts.accuracy)
        });
        let Some((fourth, jx)) = located else {
            let why = OpenReason::NoJunction { element: fourth };
            return Some((SeamEnd::Open(why), None));
        };
        let id = self.add_junction(triplet, fourth, &jx);
        if let Some(a) = self.arrivals.get_mut(id) {
            a.push(-v3(t).normalize());
        }
        self.visited.insert((sorted(*triplet), Node::Junction(id)));
        Some((SeamEnd::Junction(id), Some(jx)))
    }

    /// The nearest boundary point of the solid to the seam point `y` when it is closer than
    /// `r` and not next to a touch point on the same face (that is the curvature
    /// criterion's business): the face it was found on and the hit.
    fn intrusion(
        &self,
        triplet: &[Element; 3],
        solid: usize,
        y: &DVector<f64>,
    ) -> Option<(usize, FaceHit)> {
        let r = y[3];
        let (f, hit) = self.nearest_in(solid, v3(y))?;
        if hit.distance >= r - self.opts.accuracy {
            return None;
        }
        let far = (0..3).all(|i| {
            triplet[i] != Element::Face(f)
                || sys_point(self.model, triplet[i], slot(y, i))
                    .is_none_or(|p| p.distance(hit.point) > 0.05 * r)
        });
        far.then_some((f, hit))
    }

    /// The segment a boundary hit of face `f` (from centre `b`) lies on, with its
    /// parameters: the face itself, or the reflex edge the hit is on. `None` for a hit at a
    /// vertex that is not convex (a vertex segment).
    fn hit_segment(&self, f: usize, hit: &FaceHit, b: DVec3) -> Option<(Element, [f64; 2])> {
        match hit.on {
            Feature::Edge(e, te) if self.is_reflex(e) => {
                let n = (hit.point - b).normalize();
                let th = crate::medial::equations::edge_angle(self.model, e, te, n)?;
                Some((Element::Edge(e), [te, th]))
            }
            Feature::Vertex(v)
                if matches!(
                    self.class.vertices[v],
                    VertexKind::Reflex | VertexKind::Mixed
                ) =>
            {
                let n = (hit.point - b).normalize();
                Some((Element::Vertex(v), vertex_angles(n)))
            }
            _ => Some((Element::Face(f), [hit.uv.0, hit.uv.1])),
        }
    }

    fn seam_point(&mut self, sys: &MedialSystem, x: &DVector<f64>) -> SeamPoint {
        for seg in &sys.segments {
            if let Element::Face(f) = *seg {
                self.touched[f] = true;
            }
        }
        if let Some(f) = sys.residual(self.model, x) {
            self.stats.worst_residual = self.stats.worst_residual.max(f.amax());
        }
        let touch = std::array::from_fn(|i| {
            sys_point(self.model, sys.segments[i], slot(x, i))
                .map_or([f64::NAN; 3], |p| p.to_array())
        });
        SeamPoint {
            point: [x[0], x[1], x[2], x[3]],
            touch,
        }
    }

    /// Solves the 4-segment system from the seam point `x` (before the crossing), starting
    /// the fourth segment at the foot of `x` near `s4` (where the crossing was seen).
    fn locate_junction(
        &self,
        triplet: &[Element; 3],
        x: &DVector<f64>,
        fourth: Element,
        s4: [f64; 2],
    ) -> Option<DVector<f64>> {
        let b = v3(x);
        let uv = match fourth {
            Element::Face(f) => {
                let hint = s4[0].is_finite().then_some((s4[0], s4[1]));
                project_point(&self.model.faces[f].surface, b, hint).or(hint)?
            }
            Element::Edge(e) => {
                let (te, q, d) = crate::geom::nearest_on_edge(self.model, e, b, Some(s4[0]));
                let th = crate::medial::equations::edge_angle(self.model, e, te, (q - b) / d)?;
                (te, th)
            }
            Element::Vertex(v) => {
                let a = vertex_angles((self.model.vertices[v].point - b).normalize());
                (a[0], a[1])
            }
        };
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
        let on_faces = (0..4).all(|i| self.on_segment(sys.segments[i], slot(&sol.x, i)));
        // Two touch points on one face must be two places, not the same one found twice.
        let r = sol.x[3];
        let distinct = !touches_meet(
            self.model,
            &sys.segments,
            &sol.x,
            1e-3 * r,
            Pairs::SameSegment,
        );
        (on_faces && distinct).then_some(sol.x)
    }

    /// Records a junction (or finds the same one already found) and queues the seams that
    /// leave it. All faces at distance `r` from the centre touch it (more than four at a
    /// non-generic junction, such as a cube's centre). A seam leaves along the normal `n` of the
    /// plane through three touch points, in the sense in which every other touched segment
    /// moves away (`n·(t₀ − tₖ) ≥ 0`, so its distance grows faster than `r`); for a generic
    /// junction that is the paper's rule, one seam per omitted segment.
    fn add_junction(
        &mut self,
        arriving: &[Element; 3],
        fourth: Element,
        jx: &DVector<f64>,
    ) -> usize {
        let p = v3(jx);
        let r = jx[3];
        let solid = self.solid_of(fourth);
        let tol = 10.0 * self.opts.accuracy;
        if let Some(id) = self
            .junctions
            .iter()
            .position(|j| j.solid == solid && DVec3::from_array(j.point).distance(p) <= tol)
        {
            return id;
        }
        let mut segs = arriving.to_vec();
        segs.push(fourth);
        let mut params: Vec<(f64, f64)> = (0..4).map(|i| (jx[4 + 2 * i], jx[5 + 2 * i])).collect();
        // Other faces touching the same ball (non-generic junctions).
        for f in self.boundary.within(self.model, p, r + tol) {
            if self.face_solid[f] != solid {
                continue;
            }
            let hit = self
                .boundary
                .nearest_on_face(self.model, f, p, None, f64::INFINITY);
            // Touching to the output accuracy (the junction itself is solved far tighter),
            // so every touch point reported is within it; a hit on a face's convex edge is
            // not a touch of that face.
            let Some(hit) = hit.filter(|h| (h.distance - r).abs() <= self.opts.accuracy) else {
                continue;
            };
            let seg = match hit.on {
                Feature::Face(_) => Some((Element::Face(f), (hit.uv.0, hit.uv.1))),
                Feature::Edge(..) => self
                    .hit_segment(f, &hit, p)
                    .filter(|(s, _)| matches!(s, Element::Edge(_)))
                    .map(|(s, q)| (s, (q[0], q[1]))),
                Feature::Vertex(_) => self
                    .hit_segment(f, &hit, p)
                    .filter(|(s, _)| matches!(s, Element::Vertex(_)))
                    .map(|(s, q)| (s, (q[0], q[1]))),
            };
            // The segment must touch this very ball there: P − r·N = centre.
            let fits = |seg: Element, uv: (f64, f64)| {
                seg.eval(self.model, [uv.0, uv.1])
                    .is_some_and(|e| (e.p - e.n * r - p).length() <= self.opts.accuracy)
            };
            if let Some((seg, uv)) = seg {
                if !segs.contains(&seg) && uv.0.is_finite() && fits(seg, uv) {
                    segs.push(seg);
                    params.push(uv);
                }
            }
        }
        let touch: Vec<DVec3> = segs
            .iter()
            .zip(&params)
            .filter_map(|(s, uv)| sys_point(self.model, *s, [uv.0, uv.1]))
            .collect();
        if touch.len() != segs.len() {
            return usize::MAX;
        }
        let id = self.junctions.len();
        self.junctions.push(Junction {
            id,
            solid,
            point: p.to_array(),
            radius: r,
            segments: segs.clone(),
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
                        from: Node::Junction(id),
                    });
                }
            }
        }
        id
    }
}

/// Which pairs of touch points [`touches_meet`] compares.
#[derive(Clone, Copy, PartialEq)]
enum Pairs {
    /// Two slots of one segment (a face touched twice).
    SameSegment,
    /// Slots of different segments.
    DifferentSegments,
    All,
}

/// True when two touch points of `x` (unknowns over `segs`), among `pairs`, are within `tol`
/// of each other — or one of them is undefined (a pole).
fn touches_meet(model: &Model, segs: &[Element], x: &DVector<f64>, tol: f64, pairs: Pairs) -> bool {
    let p: Vec<Option<DVec3>> = (0..segs.len())
        .map(|i| sys_point(model, segs[i], slot(x, i)))
        .collect();
    (0..segs.len()).any(|i| {
        (0..i).any(|j| {
            let same = segs[i] == segs[j];
            let compared = match pairs {
                Pairs::SameSegment => same,
                Pairs::DifferentSegments => !same,
                Pairs::All => true,
            };
            compared
                && match (p[i], p[j]) {
                    (Some(a), Some(b)) => a.distance(b) <= tol,
                    _ => true,
                }
        })
    })
}

/// `triplet` with slot `i` replaced by `to`.
fn new_triplet(triplet: &[Element; 3], i: usize, to: Element) -> [Element; 3] {
    let mut t = *triplet;
    t[i] = to;
    t
}

/// The point of segment `seg` at parameters `s`.
fn sys_point(model: &Model, seg: Element, s: [f64; 2]) -> Option<DVec3> {
    seg.eval(model, s).map(|e| e.p)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn traced(name: &str) -> (Model, MedialAxis) {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("samples")
            .join(name);
        let m = crate::ingest::read_model(&p).unwrap();
        let c = crate::classify(&m, &Default::default());
        let mat = trace(&m, &c, &TraceOptions::for_model(&m));
        (m, mat)
    }

    /// The worst error of [`crate::medial::verify`] over every seam point and junction.
    fn verify(m: &Model, mat: &MedialAxis) -> f64 {
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
            assert_junction_at(file, &m, &mat, *p, *r);
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
        let m = crate::ingest::read_model(&p).unwrap();
        let s = [1.0, 0.3];
        assert!(curvature_allows(&m, Element::Face(0), s, 14.0));
        assert!(curvature_allows(&m, Element::Face(0), s, 15.0));
        assert!(!curvature_allows(&m, Element::Face(0), s, 16.0));
        let (b, _) = traced("box.step");
        assert!(curvature_allows(&b, Element::Face(0), [1.0, 1.0], 1e6));
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

    /// Distance from (x, 0) to the ellipse x²/a² + y²/b² = 1 (a > b, |x| < a − b²/a): the
    /// two nearest points are at the parameter with cos t = a·x / (a² − b²).
    fn ellipse_distance(a: f64, b: f64, x: f64) -> f64 {
        let c = a * x / (a * a - b * b);
        ((a * c - x).powi(2) + b * b * (1.0 - c * c)).sqrt()
    }

    /// Elliptic cylinder (semi-axes 30 and 15, height 40; manifest): the seam where the ball
    /// touches the lateral face twice and the top, traced from a seed at x = 0 both ways.
    /// Every point is (x, 0, 40 − r) with r the distance from (x, 0) to the ellipse, the two
    /// lateral touch points mirror each other in y = 0, and both ends are where the ball
    /// osculates the lateral face: the centres of curvature of the ellipse's vertices,
    /// x = ±(a − b²/a) = ±22.5, r = b²/a = 7.5. The lateral face is an extrusion in one
    /// file and a rational B-spline in the other (two touch points on one free-form face).
    #[test]
    fn seam_touching_one_face_twice_from_a_seed() {
        let (a, b, h) = (30.0, 15.0, 40.0);
        for file in ["elliptic_cylinder.step", "elliptic_cylinder_nurbs.step"] {
            let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("samples")
                .join(file);
            let m = crate::ingest::read_model(&p).unwrap();
            let class = crate::classify(&m, &Default::default());
            // The lateral face owns the seam edge (the same face on both sides); the top is
            // the other face with the higher middle.
            let lat = m
                .edges
                .iter()
                .find(|e| e.faces[0] == e.faces[1])
                .unwrap()
                .faces[0];
            let middle_z = |f: usize| {
                let d = m.faces[f].domain;
                let (u, v) = (0.5 * (d.u.0 + d.u.1), 0.5 * (d.v.0 + d.v.1));
                crate::geom::surface_point(&m.faces[f].surface, u, v).z
            };
            let top = (0..m.faces.len())
                .filter(|&f| f != lat)
                .max_by(|&f, &g| middle_z(f).total_cmp(&middle_z(g)))
                .unwrap();
            let foot = |f: usize, q: DVec3| project_point(&m.faces[f].surface, q, None).unwrap();
            let seed = Seed::new(
                [Element::Face(lat), Element::Face(lat), Element::Face(top)],
                DVec3::new(0.0, 0.0, h - b),
                b,
                [
                    foot(lat, DVec3::new(0.0, b, h - b)),
                    foot(lat, DVec3::new(0.0, -b, h - b)),
                    foot(top, DVec3::new(0.0, 0.0, h)),
                ],
            );
            let boundary = Boundary::new(&m);
            let opts = TraceOptions::for_model(&m);
            let mat = trace_with_seeds(&m, &boundary, &class, &opts, &[seed]);
            // The seed's seam comes first; sampling then finds the bottom one.
            assert_eq!(mat.seams.len(), 2, "{file}");
            let seam = &mat.seams[0];
            let diag = m.diagonal();
            for e in &seam.ends {
                assert_eq!(
                    *e,
                    SeamEnd::CurvatureLimit {
                        segment: Element::Face(lat)
                    },
                    "{file}"
                );
            }
            let xs: Vec<f64> = seam.points.iter().map(|q| q.point[0]).collect();
            let (lo, hi) = xs
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &x| {
                    (l.min(x), u.max(x))
                });
            let x_end = a - b * b / a;
            // The ends within 20× the accuracy: the bisection stops within the accuracy, but
            // where the two touch points nearly meet the system is ill-conditioned (the
            // centre moves along a near-null direction of the Jacobian), so a converged
            // residual places the centre only to about the accuracy itself.
            let end_tol = 2e-5 * diag;
            assert!(
                (lo + x_end).abs() <= end_tol && (hi - x_end).abs() <= end_tol,
                "{file}: ends at x = {lo}, {hi}"
            );
            for q in &seam.points {
                let [x, y, z, r] = q.point;
                let want = ellipse_distance(a, b, x.clamp(-x_end, x_end));
                assert!(y.abs() <= 1e-9 * diag, "{file}: y = {y}");
                assert!(
                    (z - (h - r)).abs() <= 1e-9 * diag,
                    "{file}: z = {z}, r = {r}"
                );
                // (An end point's x may lie past the exact end by the end tolerance.)
                let past = (x.abs() - x_end).max(0.0);
                assert!(
                    (r - want).abs() <= 1e-6 * diag + 2.0 * past,
                    "{file}: r({x}) = {r}, not {want}"
                );
                let (t0, t1) = (DVec3::from_array(q.touch[0]), DVec3::from_array(q.touch[1]));
                assert!((t0 - DVec3::new(t1.x, -t1.y, t1.z)).length() <= 1e-6 * diag);
            }
            // Points are spaced by the step control: the direction turns at most MAX_TURN.
            for w in seam.points.windows(3) {
                let d0 = DVec3::from_slice(&w[1].point[..3]) - DVec3::from_slice(&w[0].point[..3]);
                let d1 = DVec3::from_slice(&w[2].point[..3]) - DVec3::from_slice(&w[1].point[..3]);
                assert!(d0.angle_between(d1) <= 2.0 * MAX_TURN, "{file}");
            }
            assert!(verify(&m, &mat) <= 1e-6 * diag, "{file}");
        }
    }

    /// No seam of `mat` has an open end, the seam–junction graph is consistent, and every
    /// ball verifies to the default accuracy.
    fn complete_and_verified(file: &str, m: &Model, mat: &MedialAxis) {
        for s in &mat.seams {
            assert!(
                s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
                "{file}: seam {} {:?} ends {:?}",
                s.id,
                s.segments,
                s.ends
            );
        }
        let class = crate::classify(m, &Default::default());
        let sheets = crate::medial::sheets(m, &class, mat);
        let topo = crate::medial::verify::check_topology(mat, &sheets);
        assert!(
            topo.inconsistencies.is_empty(),
            "{file}: {:?}",
            topo.inconsistencies
        );
        // Where the sheets are complete, the medial axis is homotopy-equivalent to the solid.
        for e in &topo.euler {
            if let Some(chi) = e.mat_euler {
                assert_eq!(chi, e.solid_euler, "{file}: Euler characteristics {e:?}");
            }
        }
        let worst = verify(m, mat);
        assert!(
            worst <= 1e-6 * m.diagonal(),
            "{file}: worst verified error {worst:e}"
        );
    }

    /// Asserts a junction of `mat` at `p` with radius `r`, both to 1e-9 × the diagonal (the
    /// junction accuracy DESIGN.md asks for), and returns it.
    fn assert_junction_at<'m>(
        file: &str,
        m: &Model,
        mat: &'m MedialAxis,
        p: [f64; 3],
        r: f64,
    ) -> &'m Junction {
        let diag = m.diagonal();
        let (j, e) = junction_near(mat, DVec3::from_array(p));
        assert!(e <= 1e-9 * diag, "{file}: junction near {p:?} off by {e:e}");
        assert!(
            (j.radius - r).abs() <= 1e-9 * diag,
            "{file}: radius {} vs {r}",
            j.radius
        );
        j
    }

    /// The junction of `mat` nearest `p`, and its distance from `p`.
    fn junction_near(mat: &MedialAxis, p: DVec3) -> (&Junction, f64) {
        mat.junctions
            .iter()
            .map(|j| (j, DVec3::from_array(j.point).distance(p)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap()
    }

    /// L-bracket (profile [0,60]×[0,10] ∪ [0,10]×[0,40] in xz, 30 deep in y; one reflex
    /// edge E8 along x = 10, z = 10). Ten convex corners start ten seams. The four box-like
    /// junctions are at the ends of the two legs, radius 5 (half the thickness):
    /// (55, 5|25, 5) and (5, 5|25, 35). At the inner corner, the ball touching the bottom
    /// z = 0, the back x = 0, a side y = 0|30 and the reflex edge has centre (c, c|30−c, c)
    /// with √2·(10 − c) = c: c = 10·(2 − √2) = 5.858, radius c. Seams: 10 corner seams, one
    /// along each leg between its two end junctions, one between the two inner-corner
    /// junctions (bottom, back, edge), and four from the leg junctions to the inner ones,
    /// each handing its touch point from the leg's inner face onto the reflex edge: 17.
    #[test]
    fn l_bracket_with_a_reflex_edge() {
        for file in ["l_bracket.step", "l_bracket_nurbs.step"] {
            let (m, mat) = traced(file);
            assert_eq!(mat.seams.len(), 17, "{file}");
            assert_eq!(mat.junctions.len(), 6, "{file}");
            let c = 10.0 * (2.0 - 2f64.sqrt());
            let want = [
                ([55.0, 5.0, 5.0], 5.0),
                ([55.0, 25.0, 5.0], 5.0),
                ([5.0, 5.0, 35.0], 5.0),
                ([5.0, 25.0, 35.0], 5.0),
                ([c, c, c], c),
                ([c, 30.0 - c, c], c),
            ];
            for (p, r) in want {
                let j = assert_junction_at(file, &m, &mat, p, r);
                if r == c {
                    assert!(
                        j.segments.iter().any(|s| matches!(s, Element::Edge(_))),
                        "{file}: {:?}",
                        j.segments
                    );
                }
            }
            let handed = mat.seams.iter().filter(|s| !s.handovers.is_empty()).count();
            assert_eq!(handed, 4, "{file}");
            complete_and_verified(file, &m, &mat);
        }
    }

    /// U-channel (base [0,60]×[0,10], uprights x ∈ [0,10] and [50,60] up to z = 40, 30 deep;
    /// two reflex edges): the L-bracket's inner-corner junctions at both inner corners,
    /// (c | 60 − c, c | 30 − c, c) with c = 10·(2 − √2), and the box-like junctions at the
    /// tops of the uprights, (5 | 55, 5 | 25, 35), radius 5. 12 corner seams, 2 up the
    /// uprights' tops, 2 between the inner junctions across y, 2 along the base between
    /// the inner corners (handing over from edge to the base's top face and onto the other
    /// edge), 4 from the upright tops down to the inner corners: 22.
    #[test]
    fn u_channel_with_two_reflex_edges() {
        let (m, mat) = traced("u_channel.step");
        assert_eq!(mat.seams.len(), 22);
        assert_eq!(mat.junctions.len(), 8);
        let c = 10.0 * (2.0 - 2f64.sqrt());
        for x in [c, 60.0 - c] {
            for y in [c, 30.0 - c] {
                assert_junction_at("u_channel.step", &m, &mat, [x, y, c], c);
            }
        }
        for x in [5.0, 55.0] {
            for y in [5.0, 25.0] {
                assert_junction_at("u_channel.step", &m, &mat, [x, y, 35.0], 5.0);
            }
        }
        complete_and_verified("u_channel.step", &m, &mat);
    }

    /// Plate [0,80]×[0,50]×[0,10] with through holes r = 5, 8, 5 at x = 15, 40, 65 (y = 25):
    /// the box's 12 seams and 4 junctions (radius 5, half the thickness), plus around each
    /// hole a closed seam (top, bottom, hole wall) no corner reaches — found by seeding:
    /// the circle z = 5 at distance r_hole + 5 from the hole's axis, ball radius 5.
    #[test]
    fn plate_with_holes_has_a_closed_seam_around_each_hole() {
        let (m, mat) = traced("plate_with_holes.step");
        assert_eq!(mat.junctions.len(), 4);
        assert_eq!(mat.seams.len(), 15);
        let diag = m.diagonal();
        let loops: Vec<&Seam> = mat
            .seams
            .iter()
            .filter(|s| s.ends[0] == SeamEnd::Closed)
            .collect();
        assert_eq!(loops.len(), 3);
        for s in loops {
            let p0 = s.points[0].point;
            let (cx, rh) = [(15.0, 5.0), (40.0, 8.0), (65.0, 5.0)]
                .into_iter()
                .min_by(|a, b| (a.0 - p0[0]).abs().total_cmp(&(b.0 - p0[0]).abs()))
                .unwrap();
            for q in &s.points {
                let [x, y, z, r] = q.point;
                let rho = ((x - cx).powi(2) + (y - 25.0).powi(2)).sqrt();
                assert!(
                    (rho - (rh + 5.0)).abs() <= 1e-6 * diag,
                    "hole at {cx}: ρ = {rho}"
                );
                assert!((z - 5.0).abs() <= 1e-6 * diag && (r - 5.0).abs() <= 1e-6 * diag);
            }
        }
        complete_and_verified("plate_with_holes.step", &m, &mat);
    }

    /// Solids without a convex corner. The elliptic cylinder's two seams (the ball touching
    /// the lateral face twice and one cap) are found by seeding and end at the centres of
    /// curvature x = ±22.5, r = 7.5 (see the seed test). The washer from OpenSCAD (inner
    /// radius 15, outer 25, height 8) has two closed seams, the circles of radius 19 and 21
    /// at z = 4, ball radius 4 (manifest). Cylinder, sphere and torus have degenerate medial
    /// axes, reported as such: the cylinder's axis (x = y = 0, r = 10), the sphere's centre
    /// (r = 15), the torus's core circle (x² + y² = 20², z = 0, r = 5).
    #[test]
    fn solids_without_convex_corners() {
        for file in ["elliptic_cylinder.step", "elliptic_cylinder_nurbs.step"] {
            let (m, mat) = traced(file);
            assert_eq!(mat.seams.len(), 2, "{file}");
            for s in &mat.seams {
                assert!(
                    s.ends
                        .iter()
                        .all(|e| matches!(e, SeamEnd::CurvatureLimit { .. })),
                    "{file}: {:?}",
                    s.ends
                );
                let ends = [s.points[0].point, s.points[s.points.len() - 1].point];
                assert!(
                    ends.iter()
                        .all(|p| (p[0].abs() - 22.5).abs() <= 2e-5 * m.diagonal()),
                    "{file}: {ends:?}"
                );
            }
            complete_and_verified(file, &m, &mat);
        }
        let (m, mat) = traced("scad_rotate_extrude.step");
        assert_eq!(mat.seams.len(), 2);
        let mut radii: Vec<f64> = mat
            .seams
            .iter()
            .map(|s| {
                assert_eq!(s.ends, [SeamEnd::Closed, SeamEnd::Closed]);
                let [x, y, z, r] = s.points[0].point;
                assert!(
                    (z - 4.0).abs() <= 1e-6 * m.diagonal()
                        && (r - 4.0).abs() <= 1e-6 * m.diagonal()
                );
                (x * x + y * y).sqrt()
            })
            .collect();
        radii.sort_by(f64::total_cmp);
        assert!(
            (radii[0] - 19.0).abs() <= 1e-6 * m.diagonal()
                && (radii[1] - 21.0).abs() <= 1e-6 * m.diagonal(),
            "{radii:?}"
        );
        complete_and_verified("scad_rotate_extrude.step", &m, &mat);
        type Check = fn([f64; 4]) -> f64;
        let cases: [(&str, &str, Check); 5] = [
            ("cylinder.step", "curve", |b| {
                b[0].hypot(b[1]) + (b[3] - 10.0).abs()
            }),
            ("cylinder_nurbs.step", "curve", |b| {
                b[0].hypot(b[1]) + (b[3] - 10.0).abs()
            }),
            ("sphere.step", "point", |b| {
                DVec3::new(b[0], b[1], b[2]).length() + (b[3] - 15.0).abs()
            }),
            ("sphere_nurbs.step", "point", |b| {
                DVec3::new(b[0], b[1], b[2]).length() + (b[3] - 15.0).abs()
            }),
            ("torus.step", "curve", |b| {
                (b[0].hypot(b[1]) - 20.0).abs() + b[2].abs() + (b[3] - 5.0).abs()
            }),
        ];
        for (file, kind, err) in cases {
            let (m, mat) = traced(file);
            assert!(mat.seams.is_empty(), "{file}");
            assert!(!mat.degenerate.is_empty(), "{file}");
            for d in &mat.degenerate {
                assert_eq!(d.kind.as_str(), kind, "{file}");
                for b in &d.balls {
                    assert!(err(*b) <= 1e-6 * m.diagonal(), "{file}: {b:?}");
                }
            }
            assert!(verify(&m, &mat) <= 1e-6 * m.diagonal(), "{file}");
        }
    }

    /// Two solids in one file: the box [0,30]×[0,20]×[0,10] gets the box's MAT (junctions
    /// (5|25, 5|15, 5), radius 5) computed against its own faces only; the cylinder beside it
    /// (radius 5) gets its degenerate axis, as solid 1.
    #[test]
    fn each_solid_gets_its_own_medial_axis() {
        let (m, mat) = traced("two_solids.step");
        assert_eq!(mat.seams.len(), 12);
        assert!(mat.seams.iter().all(|s| s.solid == 0));
        for x in [5.0, 25.0] {
            for y in [5.0, 15.0] {
                let j = assert_junction_at("two_solids.step", &m, &mat, [x, y, 5.0], 5.0);
                assert_eq!(j.solid, 0);
            }
        }
        assert!(mat
            .degenerate
            .iter()
            .any(|d| d.solid == 1 && d.kind == DegenerateKind::Curve));
        complete_and_verified("two_solids.step", &m, &mat);
    }

    /// Box [0,60]×[0,40]×[0,30] with a spherical void (radius 8 at the centre (30,20,15)):
    /// the void is part of the boundary. The part is symmetric in x = 30 and y = 20, and so
    /// is its traced MAT: every junction has its mirror images, at the same radius.
    #[test]
    fn box_with_a_void() {
        let (m, mat) = traced("box_with_void.step");
        let diag = m.diagonal();
        assert!(mat.junctions.len() >= 8);
        for j in &mat.junctions {
            let p = DVec3::from_array(j.point);
            for q in [
                DVec3::new(60.0 - p.x, p.y, p.z),
                DVec3::new(p.x, 40.0 - p.y, p.z),
            ] {
                let (k, e) = junction_near(&mat, q);
                assert!(
                    e <= 1e-6 * diag && (k.radius - j.radius).abs() <= 1e-6 * diag,
                    "no mirror of {p}"
                );
            }
        }
        assert!(
            mat.junctions
                .iter()
                .any(|j| j.touch.iter().any(|t| (DVec3::from_array(*t)
                    - DVec3::new(30.0, 20.0, 15.0))
                .length()
                    <= 8.0 + 1e-6)),
            "no junction touches the void"
        );
        complete_and_verified("box_with_void.step", &m, &mat);
    }

    /// Box [0,60]×[0,40]×[0,20] with every edge filleted at radius 4: the inner box
    /// [4,56]×[4,36]×[4,16] offset by 4, so its medial axis is the box's with radii + 4
    /// (manifest): the same 4 junctions, (10|50, 10|30, 10) with radius 10, and 12 seams,
    /// the 8 corner seams now ending at the corner patches' centres (4|56, 4|36, 4|16),
    /// radius 4, where the ball osculates the fillets (a curvature-limit end).
    #[test]
    fn filleted_box_seams_end_at_the_corner_patch_centres() {
        let (m, mat) = traced("filleted_box.step");
        let diag = m.diagonal();
        assert_eq!(mat.seams.len(), 12);
        assert_eq!(mat.junctions.len(), 4);
        for x in [10.0, 50.0] {
            for y in [10.0, 30.0] {
                assert_junction_at("filleted_box.step", &m, &mat, [x, y, 10.0], 10.0);
            }
        }
        let corner_ends: Vec<[f64; 4]> = mat
            .seams
            .iter()
            .flat_map(|s| {
                let pts = [s.points[0].point, s.points[s.points.len() - 1].point];
                s.ends
                    .iter()
                    .zip(pts)
                    .filter(|(e, _)| matches!(e, SeamEnd::CurvatureLimit { .. }))
                    .map(|(_, p)| p)
                    .collect::<Vec<_>>()
            })
            .collect();
        assert_eq!(corner_ends.len(), 8);
        for p in corner_ends {
            let near = |v: f64, a: f64, b: f64| (v - a).abs().min((v - b).abs());
            let e = near(p[0], 4.0, 56.0) + near(p[1], 4.0, 36.0) + near(p[2], 4.0, 16.0);
            assert!(
                e <= 1e-5 * diag && (p[3] - 4.0).abs() <= 1e-5 * diag,
                "{p:?}"
            );
        }
        complete_and_verified("filleted_box.step", &m, &mat);
    }

    /// The L-bracket with its reflex edge replaced by a concave fillet of radius 5 (axis
    /// x = 15, z = 15): the leg-end junctions stay at (55, 5|25, 5) and (5, 5|25, 35),
    /// radius 5. The inner-corner junctions touch bottom, back, a side and the fillet from
    /// outside its cylinder: centre (c, c|30 − c, c) with √2·(15 − c) = c + 5, so
    /// c = (15√2 − 5)/(1 + √2) = 6.7157, radius c. 17 seams as for the sharp bracket.
    #[test]
    fn l_bracket_with_a_concave_fillet() {
        let (m, mat) = traced("l_bracket_concave_fillet.step");
        assert_eq!(mat.seams.len(), 17);
        assert_eq!(mat.junctions.len(), 6);
        let c = (15.0 * 2f64.sqrt() - 5.0) / (1.0 + 2f64.sqrt());
        let want = [
            ([55.0, 5.0, 5.0], 5.0),
            ([55.0, 25.0, 5.0], 5.0),
            ([5.0, 5.0, 35.0], 5.0),
            ([5.0, 25.0, 35.0], 5.0),
            ([c, c, c], c),
            ([c, 30.0 - c, c], c),
        ];
        for (p, r) in want {
            assert_junction_at("l_bracket_concave_fillet.step", &m, &mat, p, r);
        }
        complete_and_verified("l_bracket_concave_fillet.step", &m, &mat);
    }

    /// Plate [0,80]×[0,60]×[0,10] with a boss (radius 12, z from 10 to 30) at (40, 30): the
    /// plate's box-like junctions at (5|75, 5|55, 5), radius 5, far from the boss; and the
    /// boss's axis x = 40, y = 30 as a degenerate curve of balls of radius 12 touching its
    /// whole wall.
    #[test]
    fn boss_on_a_plate() {
        let (m, mat) = traced("boss_on_plate.step");
        let diag = m.diagonal();
        for x in [5.0, 75.0] {
            for y in [5.0, 55.0] {
                assert_junction_at("boss_on_plate.step", &m, &mat, [x, y, 5.0], 5.0);
            }
        }
        let axis: Vec<&[f64; 4]> = mat
            .degenerate
            .iter()
            .filter(|d| d.kind == DegenerateKind::Curve)
            .flat_map(|d| &d.balls)
            .collect();
        assert!(!axis.is_empty());
        for b in axis {
            let e = (b[0] - 40.0).hypot(b[1] - 30.0) + (b[3] - 12.0).abs();
            assert!(e <= 1e-6 * diag, "{b:?}");
        }
        complete_and_verified("boss_on_plate.step", &m, &mat);
    }
}
