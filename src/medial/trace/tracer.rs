//! The tracer's state, and what it asks of the model: which solid an element bounds, whether
//! a touch point is on its element, the nearest boundary point within a solid.

use super::options::{TraceOptions, MAX_CORRECTOR_ITER, SAME_PLACE_REL_ACCURACY, UNIT_ROUNDING};
use super::unknowns::{slot, sys_point, v3};
use crate::classify::{Classification, EdgeKind, VertexKind};
use crate::geom::{project_point, Boundary, FaceHit};
use crate::medial::axis::{
    Degenerate, Junction, MedialAxis, Node, Seam, SeamPoint, SkeletalEdge, TraceStats,
};
use crate::medial::equations::{vertex_angles, MedialSystem, NormalField};
use crate::medial::segments::SegmentGroups;
use crate::medial::solver::{solve, SolveOptions, SolveStatus};
use crate::model::{Element, Model};
use glam::DVec3;
use nalgebra::DVector;
use std::collections::{HashMap, HashSet, VecDeque};

/// How near (radians) to π the span of a reflex edge's arc of normals must be for the edge to
/// be a fold, whose arc its faces' normals do not decide.
const FOLD_SPAN_RAD: f64 = 1e-3;

/// Points along a step's UV path at which [`Tracer::grazes_edge_run_along`] looks.
const GRAZE_SAMPLES: usize = 16;

/// Where a seam starts.
pub(super) struct Start {
    pub(super) triplet: [Element; 3],
    pub(super) x: DVector<f64>,
    /// Direction of the centre at the start.
    pub(super) dir: DVec3,
    pub(super) from: Node,
}

/// The state of one trace.
pub(super) struct Tracer<'a> {
    pub(super) model: &'a Model,
    pub(super) boundary: &'a Boundary,
    pub(super) class: &'a Classification,
    pub(super) opts: &'a TraceOptions,
    /// The solid of each face.
    pub(super) face_solid: Vec<usize>,
    /// The edges at each vertex, with `true` where the vertex is the edge's end.
    pub(super) vertex_edges: Vec<Vec<(usize, bool)>>,
    /// Faces joined by smooth and reflex edges (with those edges and reflex vertices).
    pub(super) groups: SegmentGroups,
    /// Each face's loops in runs with bounding boxes, for [`Tracer::stays_on`].
    pub(super) loop_chunks: Vec<crate::geom::trim::LoopChunks>,
    pub(super) junctions: Vec<Junction>,
    pub(super) degenerate: Vec<Degenerate>,
    /// The unknowns `[B, r, s_a, s_b]` of each of `degenerate`'s sampled balls.
    pub(super) degenerate_x: Vec<Vec<DVector<f64>>>,
    /// Faces some output seam point touches.
    pub(super) touched: Vec<bool>,
    /// Edges some output seam point touches.
    pub(super) touched_edges: Vec<bool>,
    /// Per junction: unit directions (leaving the junction) of the seams that arrived there,
    /// so a branch along an arrived seam (same curve, another triplet of a non-generic
    /// junction) is not traced again.
    pub(super) arrivals: Vec<Vec<DVec3>>,
    pub(super) seams: Vec<Seam>,
    /// The two ends (and the elements there) of every seam between proper ends, with the
    /// seams (indices) between them.
    pub(super) traced_between: HashMap<[(Node, [Element; 3]); 2], Vec<usize>>,
    /// (sorted triplet, the node where it starts or ends) already traced.
    pub(super) visited: HashSet<([Element; 3], Node)>,
    pub(super) queue: VecDeque<Start>,
    pub(super) stats: TraceStats,
    /// In the current march: the faces and edges of theirs along which touch points run, a
    /// smooth edge or a reflex edge they graze (see [`Tracer::stays_on`]), each with how far
    /// past the edge beyond the accuracy and the face's gap a point still counts as on the
    /// face.
    pub(super) along: Vec<(usize, usize, f64)>,
    /// In the current march: no ordinary step taken yet (the march is at its first ball).
    pub(super) at_start: bool,
    /// Each face's gap ([`crate::model::Face::gap_mm`]) where it is more than the accuracy,
    /// else 0 (see [`Tracer::on_boundary_within_gap`]).
    pub(super) face_gap: Vec<f64>,
    /// Some face has a gap beyond the accuracy.
    pub(super) any_gap: bool,
    /// The cone apexes at vertices (drill points' tips).
    pub(super) apexes: Vec<super::apex::Apex>,
}

impl<'a> Tracer<'a> {
    /// A tracer with nothing traced yet.
    pub(super) fn new(
        model: &'a Model,
        boundary: &'a Boundary,
        class: &'a Classification,
        opts: &'a TraceOptions,
    ) -> Tracer<'a> {
        let face_gap: Vec<f64> = model
            .faces
            .iter()
            .map(|f| f.gap_mm())
            .map(|g| if g > opts.accuracy { g } else { 0.0 })
            .collect();
        let any_gap = face_gap.iter().any(|&g| g > 0.0);
        Tracer {
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
            degenerate_x: vec![],
            touched: vec![false; model.faces.len()],
            touched_edges: vec![false; model.edges.len()],
            arrivals: vec![],
            seams: vec![],
            visited: HashSet::new(),
            traced_between: HashMap::new(),
            queue: VecDeque::new(),
            stats: TraceStats::default(),
            along: Vec::new(),
            at_start: false,
            face_gap,
            any_gap,
            apexes: super::apex::apexes(model, SAME_PLACE_REL_ACCURACY * opts.accuracy),
        }
    }

    /// The medial axis traced, with its skeletal edges.
    pub(super) fn into_axis(self, skeletal_edges: Vec<SkeletalEdge>) -> MedialAxis {
        MedialAxis {
            seams: self.seams,
            junctions: self.junctions,
            degenerate: self.degenerate,
            skeletal_edges,
            stats: self.stats,
        }
    }
    pub(super) fn solve_opts(&self) -> SolveOptions {
        SolveOptions {
            tol: self.opts.solver_tol,
            max_iter: MAX_CORRECTOR_ITER,
        }
    }

    /// The point of `sys` near `x0` with unknown `k` held at `value` (an edge's parameter at
    /// its end, a normal's angle at its arc's end, `r = 0`): the seam's system made square by
    /// that one equation and solved by Newton from `x0`; `None` unless it converges.
    pub(super) fn solve_holding(
        &self,
        sys: &MedialSystem,
        x0: &DVector<f64>,
        k: usize,
        value: f64,
    ) -> Option<DVector<f64>> {
        let mut row = DVector::zeros(x0.len());
        row[k] = 1.0;
        let sol = solve(
            |z| sys.eval_with_row(self.model, z, &row, value),
            x0.clone(),
            &self.solve_opts(),
        );
        (sol.status == SolveStatus::Converged).then_some(sol.x)
    }

    pub(super) fn solid_of(&self, seg: Element) -> usize {
        match seg {
            Element::Face(f) => self.face_solid[f],
            Element::Edge(e) => self.face_solid[self.model.edges[e].faces[0]],
            Element::Vertex(v) => match (self.vertex_edges[v].first(), self.apexes_at(v).next()) {
                (Some(&(e, _)), _) => self.face_solid[self.model.edges[e].faces[0]],
                (None, Some(a)) => self.face_solid[a.face],
                (None, None) => 0,
            },
        }
    }

    /// The cone apexes at vertex `v`.
    pub(super) fn apexes_at(&self, v: usize) -> impl Iterator<Item = &super::apex::Apex> {
        self.apexes.iter().filter(move |a| a.vertex == v)
    }

    /// The unit tangents of vertex `v`'s edges, pointing away from it, with the edges.
    pub(super) fn vertex_tangents(&self, v: usize) -> Vec<(usize, DVec3)> {
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
    pub(super) fn nearest_in(&self, solid: usize, p: DVec3) -> Option<(usize, FaceHit)> {
        self.boundary
            .nearest_face_where(self.model, p, |g| self.face_solid[g] == solid)
    }

    /// [`Self::nearest_in`] when it is nearer than `bound`.
    pub(super) fn nearest_in_within(
        &self,
        solid: usize,
        p: DVec3,
        bound: f64,
    ) -> Option<(usize, FaceHit)> {
        self.boundary
            .nearest_face_within(self.model, p, bound, |g| self.face_solid[g] == solid)
    }

    /// True when nothing of solid `solid`'s boundary is nearer the centre of ball `x`
    /// (unknowns `[B, r, …]`) than `r`, to the accuracy `verify` holds every ball to: plus
    /// the file's gap about the face found nearest (see [`Self::gap_about`]), as there.
    pub(super) fn ball_is_empty(&self, solid: usize, x: &DVector<f64>) -> bool {
        self.nearest_in(solid, v3(x))
            .is_some_and(|(f, h)| h.distance >= x[3] - self.opts.accuracy - self.gap_about(f))
    }

    pub(super) fn is_reflex(&self, e: usize) -> bool {
        self.class.edges[e].kind == EdgeKind::Reflex
    }

    /// The outward normals of edge `e`'s two faces at curve parameter `t`, in the plane
    /// normal to the edge there: the ends of the arc of normals the edge owns as a boundary
    /// segment. (A touch point's normal on the edge lies in that plane; a face's normal at
    /// the edge is perpendicular to it only to the file's precision: the arc test between
    /// the unprojected normals failed in the middle of the arc by the square of that tilt,
    /// on the spline edges of the Prusa LCD knob and adapter, and handed touch points off
    /// the edge there.)
    pub(super) fn edge_fan(&self, e: usize, t: f64) -> Option<[DVec3; 2]> {
        let edge = &self.model.edges[e];
        let p = crate::geom::eval_curve(&edge.curve, t).p;
        let frame = crate::medial::equations::edge_frame(self.model, e, t);
        let normal = |f: usize| {
            let n = self.edge_face_normal(e, f, t, p).map(|(_, n)| n)?;
            let Some(fr) = &frame else { return Some(n) };
            let m = n.dot(fr.a) * fr.a + n.dot(fr.b) * fr.b;
            Some(if m.length() > 0.5 { m.normalize() } else { n })
        };
        Some([normal(edge.faces[0])?, normal(edge.faces[1])?])
    }

    /// The parameters on face `f` of the point `p` of its edge `e` at curve parameter `t`,
    /// and the face's outward normal there: projected from the edge's samples on the face
    /// (a few Newton steps where a projection from nothing searches the whole surface, most
    /// of the trace's time on a screw's thread faces).
    pub(super) fn edge_face_normal(
        &self,
        e: usize,
        f: usize,
        t: f64,
        p: DVec3,
    ) -> Option<([f64; 2], DVec3)> {
        let surface = &self.model.faces[f].surface;
        // Newton from the samples' parameters lands on the exact foot (the point is on the
        // face, up to the file's gaps); truck's search from a hint stops within its 1e-6,
        // enough to turn the normal by more than the arc test's rounding on a small fillet.
        let periodic = {
            use truck_geometry::prelude::ParametricSurface;
            surface.u_period().is_some() || surface.v_period().is_some()
        };
        let hint = self.boundary.edge_uv_hint(self.model, e, f, t);
        let along = |h| crate::geom::project::project_point_along(surface, p, h, periodic);
        let mut uv = match hint {
            Some(h) => along(h)?,
            None => project_point(surface, p, None)?,
        };
        // A B-spline patch that closes on itself (a cylinder written as NURBS) has its
        // parameter clamped to its knots: where the edge crosses the patch's closing border
        // the foot sticks to that border from a hint on the other side. Start from the hint a
        // period round instead, and keep the nearer foot.
        let d = self.model.faces[f].domain;
        if let (Some(h), false) = (hint, periodic) {
            let off = |uv: (f64, f64)| {
                crate::geom::eval_face(&self.model.faces[f], uv.0, uv.1)
                    .p
                    .distance(p)
            };
            if off(uv) > self.opts.accuracy {
                let shifted = [
                    d.u_period.map(|per| (h.0 - per, h.1)),
                    d.u_period.map(|per| (h.0 + per, h.1)),
                    d.v_period.map(|per| (h.0, h.1 - per)),
                    d.v_period.map(|per| (h.0, h.1 + per)),
                ];
                for h2 in shifted.into_iter().flatten() {
                    if let Some(uv2) = along(h2).filter(|&uv2| off(uv2) < off(uv)) {
                        uv = uv2;
                    }
                }
            }
        }
        // The point is on the face (up to the file's gap there): a foot farther than that
        // came from a hint in another basin (a cone's samples at its seam, half a turn
        // round: Newton went to the other nappe, 2 mm away, on the Prusa adapter), and the
        // whole surface is searched instead.
        let off = |uv: (f64, f64)| {
            crate::geom::eval_face(&self.model.faces[f], uv.0, uv.1)
                .p
                .distance(p)
        };
        if off(uv) > SAME_PLACE_REL_ACCURACY * self.opts.accuracy + self.face_gap[f] {
            if let Some(found) = project_point(surface, p, None).filter(|&g| off(g) < off(uv)) {
                uv = found;
            }
        }
        let n = Element::Face(f).eval(self.model, [uv.0, uv.1])?.n;
        Some(([uv.0, uv.1], n))
    }

    /// Where a touch point with parameters `s` on reflex edge `e` is: within the edge's
    /// range, and with its normal inside the arc between the edge's faces' normals.
    pub(super) fn edge_status(&self, e: usize, s: [f64; 2]) -> (bool, bool) {
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
                // At a fold of 360° the faces' normals are opposite and every normal square
                // to the edge is between them: the arc is the half towards which both faces
                // leave the edge (a crack's opening), not the half into the material.
                let half = span < std::f64::consts::PI - FOLD_SPAN_RAD || {
                    let f = self.model.edges[e].faces[0];
                    let hint = self.boundary.edge_uv_hint(self.model, e, f, s[0]);
                    crate::geom::fold::into_first_face(self.model, e, s[0], hint)
                        .is_none_or(|m| ev.n.dot(m) >= -UNIT_ROUNDING)
                };
                half && ev.n.angle_between(fan[0]) + ev.n.angle_between(fan[1])
                    <= span + UNIT_ROUNDING
            }
            _ => false,
        };
        (in_range, in_arc)
    }

    /// The edges of face `f` along which a touch point on it runs in the current march.
    pub(super) fn edges_run_along(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        self.along
            .iter()
            .filter(move |&&(g, _, _)| g == f)
            .map(|&(_, e, _)| e)
    }

    /// True when a touch point moving from parameters `from` to `to` stays on segment `seg`:
    /// `to` is on it, and on a face the path between did not cross a trimming loop (a step
    /// over a hole lands on the face again).
    pub(super) fn stays_on(&self, seg: Element, from: [f64; 2], to: [f64; 2]) -> bool {
        let on = self.on_segment(seg, to);
        match seg {
            Element::Face(f) if !on => {
                // Off the face's trim: still on it next to an edge it runs along (to the
                // accuracy plus the face's gap), or, from a march's first ball (a junction at
                // the face's corner), running along its border (on its edges at both ends of
                // the step, see `on_face_border`).
                if self.edges_run_along(f).next().is_some() {
                    return self.by_edge_run_along(f, to);
                }
                self.at_start && self.on_face_border(seg, from) && self.on_face_border(seg, to)
            }
            Element::Face(f) => {
                !crate::geom::trim::path_crosses_loops(
                    &self.model.faces[f],
                    &self.loop_chunks[f],
                    glam::DVec2::from(from),
                    glam::DVec2::from(to),
                ) || self.grazes_edge_run_along(f, from, to)
            }
            _ => on,
        }
    }

    /// True when a touch point's step on segment `seg` ends at `to` on the face, next to an
    /// edge the touch point runs along: a step that then left the face crossed its loops
    /// twice, which may be its chord dipping across that edge's arc.
    pub(super) fn grazing_step(&self, seg: Element, to: [f64; 2]) -> bool {
        match seg {
            Element::Face(f) => {
                self.edges_run_along(f).next().is_some() && self.on_segment(seg, to)
            }
            _ => false,
        }
    }

    /// True when the UV path from `from` to `to` on face `f`, which crosses its loops twice,
    /// only grazes an edge the touch point runs along (handed onto it and straight back): at
    /// each of [`GRAZE_SAMPLES`] points along it the face's point is inside the trim or
    /// within the accuracy plus the face's gap of such an edge. A touch point's path that
    /// touches a curved reflex edge from the outside of its curve (a wall 2 thick, stepped
    /// down by 1 at a face whose foot is an arc: the mid-surface's balls touch the step at
    /// that arc, once, tangentially) is a chord that dips inside the arc by its sagitta, and
    /// crosses the arc's polygon twice without leaving the face.
    fn grazes_edge_run_along(&self, f: usize, from: [f64; 2], to: [f64; 2]) -> bool {
        if self.edges_run_along(f).next().is_none() {
            return false;
        }
        (1..GRAZE_SAMPLES).all(|k| {
            let t = k as f64 / GRAZE_SAMPLES as f64;
            let s = [
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ];
            self.on_segment(Element::Face(f), s) || self.by_edge_run_along(f, s)
        })
    }

    /// True when face `f`'s point at parameters `s` is within the accuracy plus the face's
    /// gap (plus the entry's own margin) of an edge a touch point runs along on it
    /// ([`Self::edges_run_along`]).
    fn by_edge_run_along(&self, f: usize, s: [f64; 2]) -> bool {
        let tol = self.opts.accuracy + self.face_gap[f];
        sys_point(self.model, Element::Face(f), s).is_some_and(|p| {
            self.along
                .iter()
                .filter(|a| a.0 == f)
                .any(|&(_, e, margin)| {
                    crate::geom::nearest_on_edge(self.model, e, p, None).2 <= tol + margin
                })
        })
    }

    /// True when a touch point on face `f` runs along its edge `e` in the current march.
    pub(super) fn runs_along(&self, f: usize, e: usize) -> bool {
        self.along.iter().any(|a| a.0 == f && a.1 == e)
    }

    /// The angle by which edge `g` turns away from edge `e` at their shared vertex `v`:
    /// between arriving at `v` along `e` (leaving it along −e) and leaving along `g`; `None`
    /// where either has no tangent there.
    pub(super) fn turn_at(&self, v: usize, e: usize, g: usize) -> Option<f64> {
        let tangents = self.vertex_tangents(v);
        let leaving = |k: usize| tangents.iter().find(|(h, _)| *h == k).map(|(_, d)| *d);
        Some((-leaving(e)?).angle_between(leaving(g)?))
    }

    /// The smooth edge between faces `f` and `g`, if any.
    pub(super) fn smooth_edge_between(&self, f: usize, g: usize) -> Option<usize> {
        self.smooth_edges_between(f, g).next()
    }

    /// The smooth edges between faces `f` and `g` (two halves of a split cylinder share
    /// two).
    fn smooth_edges_between(&self, f: usize, g: usize) -> impl Iterator<Item = usize> + '_ {
        self.model.faces[f]
            .loops
            .iter()
            .flat_map(|l| l.edges.iter())
            .map(|oe| oe.edge)
            .filter(move |&e| {
                f != g
                    && self.model.edges[e].faces.contains(&g)
                    && self.class.edges[e].kind == EdgeKind::Smooth
            })
    }

    /// The smooth edge between faces `f` and `g` nearest to `p`, if any.
    pub(super) fn smooth_edge_between_near(&self, f: usize, g: usize, p: DVec3) -> Option<usize> {
        self.smooth_edges_between(f, g).min_by(|&a, &b| {
            let d = |e: usize| crate::geom::nearest_on_edge(self.model, e, p, None).2;
            d(a).total_cmp(&d(b))
        })
    }

    /// True when parameters `s` lie on segment `seg`: inside a face's trim, or on a reflex
    /// edge within its range with the normal inside the arc between its faces' normals.
    pub(super) fn on_segment(&self, seg: Element, s: [f64; 2]) -> bool {
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
            // edges: N·d ≥ 0 for every edge direction d leaving it, and for every generator
            // of a cone whose apex it is.
            Element::Vertex(v) => {
                let Some(ev) = seg.eval(self.model, s) else {
                    return false;
                };
                self.vertex_tangents(v)
                    .iter()
                    .all(|(_, d)| ev.n.dot(*d) >= -UNIT_ROUNDING)
                    && self.apexes_at(v).all(|a| a.admits(ev.n, UNIT_ROUNDING))
            }
        }
    }

    /// True when the point `p` of face `f`'s surface, outside the face's trim, is on the
    /// solid's boundary to the accuracy plus the file's gap there: on `f` or a face next to
    /// it (sharing an edge), within the gap about `f` ([`Self::gap_about`]). Where an
    /// exporter wrote a face's edges along its neighbour's surface, the corner of the two
    /// surfaces lies off the trim by the gap over the sine of the angle between them, and a
    /// seam reaching that corner touches the surface there: either surface, past its own
    /// trim, which may be the nearer boundary (the unmoved one of two roof planes meeting
    /// at 4 degrees, the other moved off their ridge, where the ball is moved by the gap
    /// over twice the sine of 2 degrees).
    fn on_boundary_within_gap(&self, f: usize, p: DVec3) -> bool {
        let Some((g, hit)) = self.nearest_in(self.face_solid[f], p) else {
            return false;
        };
        let gap = self.gap_about(f);
        let next_to = g == f
            || self.model.faces[f]
                .loops
                .iter()
                .flat_map(|l| &l.edges)
                .any(|oe| self.model.edges[oe.edge].faces.contains(&g));
        gap > 0.0 && next_to && hit.distance <= self.opts.accuracy + gap
    }

    /// The file's gap about face `f`: the largest of its own and its neighbours' (faces
    /// sharing an edge with it). Where an exporter wrote one face's edges along its
    /// neighbour's surface, the two surfaces cross near the edge by up to that gap, and a
    /// ball touching one of them may reach into the other by as much.
    pub(super) fn gap_about(&self, f: usize) -> f64 {
        if !self.any_gap {
            return 0.0;
        }
        self.model.faces[f]
            .loops
            .iter()
            .flat_map(|l| &l.edges)
            .flat_map(|oe| &self.model.edges[oe.edge].faces)
            .map(|&g| self.face_gap[g])
            .fold(self.face_gap[f], f64::max)
    }

    /// The file's gap at element `e` (see [`Self::face_gap`]): a face's, or the largest of
    /// the faces an edge or vertex bounds.
    pub(super) fn element_gap(&self, e: Element) -> f64 {
        match e {
            Element::Face(f) => self.face_gap[f],
            Element::Edge(g) => self.model.edges[g]
                .faces
                .iter()
                .map(|&f| self.face_gap[f])
                .fold(0.0, f64::max),
            Element::Vertex(v) => self.vertex_edges[v]
                .iter()
                .flat_map(|&(g, _)| &self.model.edges[g].faces)
                .map(|&f| self.face_gap[f])
                .fold(0.0, f64::max),
        }
    }

    /// True when the point at `s` of face `seg` is on one of the face's edges to a tenth of
    /// the accuracy (on the border of the closed face, whichever side of its trim test; well
    /// within the accuracy `verify` holds a touch point to the boundary).
    pub(super) fn on_face_border(&self, seg: Element, s: [f64; 2]) -> bool {
        let Element::Face(f) = seg else {
            return false;
        };
        sys_point(self.model, seg, s).is_some_and(|p| {
            self.nearest_edge_of_face(f, p).is_some_and(|(e, te)| {
                crate::geom::eval_curve(&self.model.edges[e].curve, te)
                    .p
                    .distance(p)
                    <= 0.1 * self.opts.accuracy
            })
        })
    }

    /// True when the point at `s` of face `seg`, outside its trim, is past a convex edge of it
    /// (which no touch point crosses) but on the boundary within the file's gap there
    /// ([`Self::on_boundary_within_gap`]): the touch point stays on the face's surface.
    pub(super) fn beyond_convex_edge_within_gap(&self, seg: Element, s: [f64; 2]) -> bool {
        let Element::Face(f) = seg else {
            return false;
        };
        if !self.any_gap {
            return false;
        }
        let Some(p) = sys_point(self.model, seg, s) else {
            return false;
        };
        if !self.on_boundary_within_gap(f, p) {
            return false;
        }
        self.nearest_edge_of_face(f, p).is_some_and(|(e, te)| {
            let kind = match self.class.edges[e].kind {
                EdgeKind::Mixed => {
                    crate::classify::edge_kind_at(self.model, e, te, self.opts.tangent_angle_rad).0
                }
                kind => kind,
            };
            kind == EdgeKind::Convex
        })
    }

    pub(super) fn seam_point(&mut self, sys: &MedialSystem, x: &DVector<f64>) -> SeamPoint {
        for seg in &sys.segments {
            match *seg {
                Element::Face(f) => self.touched[f] = true,
                Element::Edge(e) => self.touched_edges[e] = true,
                Element::Vertex(_) => {}
            }
        }
        if let Some(f) = sys.residual(self.model, x) {
            self.stats.worst_residual = self.stats.worst_residual.max(f.amax());
        }
        let touch = (0..sys.segments.len())
            .map(|i| {
                sys_point(self.model, sys.segments[i], slot(x, i))
                    .map_or([f64::NAN; 3], |p| p.to_array())
            })
            .collect();
        SeamPoint {
            point: [x[0], x[1], x[2], x[3]],
            touch,
        }
    }

    /// The edge of face `f` nearest to `p`, with the curve parameter of the nearest point.
    pub(super) fn nearest_edge_of_face(&self, f: usize, p: DVec3) -> Option<(usize, f64)> {
        self.nearest_edge_of_face_where(f, p, |_| true)
    }

    /// [`Self::nearest_edge_of_face`] among the face's edges other than `except`.
    pub(super) fn nearest_edge_of_face_except(
        &self,
        f: usize,
        p: DVec3,
        except: usize,
    ) -> Option<(usize, f64)> {
        self.nearest_edge_of_face_where(f, p, |e| e != except)
    }

    fn nearest_edge_of_face_where(
        &self,
        f: usize,
        p: DVec3,
        keep: impl Fn(usize) -> bool,
    ) -> Option<(usize, f64)> {
        self.model.faces[f]
            .loops
            .iter()
            .flat_map(|l| l.edges.iter())
            .filter(|oe| keep(oe.edge))
            .map(|oe| {
                let (te, _, d) = crate::geom::nearest_on_edge(self.model, oe.edge, p, None);
                (oe.edge, te, d)
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(e, te, _)| (e, te))
    }

    /// The segment a boundary hit of face `f` (from centre `b`) lies on, with its
    /// parameters: the face itself, the reflex edge or the reflex (or mixed) vertex the hit is
    /// on. `None` for a hit on a reflex edge where its normal frame is undefined.
    pub(super) fn hit_segment(
        &self,
        f: usize,
        hit: &FaceHit,
        b: DVec3,
    ) -> Option<(Element, [f64; 2])> {
        match (hit.on, hit.t) {
            (Element::Edge(e), Some(te)) if self.is_reflex(e) => {
                let n = (hit.point - b).normalize();
                let th = crate::medial::equations::edge_angle(self.model, e, te, n)?;
                Some((Element::Edge(e), [te, th]))
            }
            (Element::Vertex(v), _)
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
}
