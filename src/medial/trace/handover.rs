//! Hand-overs: a touch point that leaves its element continues on the next one — across a
//! smooth edge onto the next face, onto a reflex edge and off it, from a reflex edge into the
//! next one or onto its vertex — as the same ball, re-solved on the new triplet.

use super::options::{OSCULATING_REL_RADIUS, REACH_REL_ACCURACY, SAME_PLACE_REL_ACCURACY};
use super::tracer::Tracer;
use super::unknowns::{new_triplet, slot, sys_point, v3};
use crate::classify::{EdgeKind, VertexKind};
use crate::geom::project_point;
use crate::medial::axis::OpenReason;
use crate::medial::equations::{vertex_angles, FieldEval, MedialSystem, NormalField};
use crate::medial::maximal::curvature_allows;
use crate::medial::solver::{solve, SolveStatus};
use crate::model::Element;
use glam::DVec3;
use nalgebra::DVector;

/// A hand-over: the new element, the crossing point (old triplet) and the same point on the
/// new triplet; or why not, with the crossing point.
pub(super) type HandOverResult =
    Result<(Element, DVector<f64>, DVector<f64>), (HandOverError, DVector<f64>)>;

/// Why a touch point could not be handed over.
pub(super) enum HandOverError {
    /// The ball osculates the next element (touches it along a curve).
    Osculates(Element),
    /// The seam ends open there.
    Stop(OpenReason),
    /// The step's crossing was not bracketed — no probe between the last seam point and the
    /// step's end saw the touch point off its segment; the probes past the last one on it
    /// failed (the step's end had jumped to another stretch of the seam) — and the hand-over
    /// at the last point on it failed, for the reason given: the step is to be shortened.
    Unbracketed(OpenReason),
}

impl From<OpenReason> for HandOverError {
    fn from(why: OpenReason) -> Self {
        HandOverError::Stop(why)
    }
}

impl Tracer<'_> {
    /// Hands touch point `i` over to the next segment: finds (by bisecting the step `h` from
    /// `x` along `t`) the last seam point with the touch point still on its segment, which is
    /// then on the segment's boundary, and continues it on the neighbour there: across a
    /// smooth edge the next face; onto a reflex edge the edge (the normal is that face's
    /// normal, an end of the edge's arc); off a reflex edge's arc the face at that end.
    /// Returns the new segment, the crossing point (on the old triplet) and the same point
    /// solved for the new triplet, or why the touch point cannot continue (a convex edge, an
    /// edge's end).
    pub(super) fn hand_over(
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
        let mut failed = false;
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
                None => {
                    hi = mid;
                    failed = true;
                }
            }
        }
        let unbracketed = off.is_none() && failed;
        if let Some(k) = off
            .as_ref()
            .and_then(|y| (0..3).find(|&k| !self.stays_on(triplet[k], slot(x, k), slot(y, k))))
        {
            *i = k;
        }
        let i = *i;
        let off = off.map(|y| slot(&y, i));
        let mut exit = match (triplet[i], off) {
            (Element::Edge(e), Some(s)) => Some(self.edge_status(e, s)),
            _ => None,
        };
        // Off an edge's arc: the crossing is where the normal is exactly the face's at that
        // end of the arc (the fan's ends move with the parameter along a curved edge: a few
        // rounds). Where no such point is near, while the touch point sits at an end of the
        // edge, the step went past that end too (its normal then turns fast about the
        // vertex, out of the arc): the range's end is the crossing.
        if let (Element::Edge(e), Some((_, false))) = (triplet[i], exit) {
            match self.at_arc_end(&sys, e, i, &xc) {
                Some(x_arc) => xc = x_arc,
                None if self.at_edge_end(e, slot(&xc, i)[0]) => exit = Some((false, true)),
                None => {}
            }
        }
        // Off an edge's end: the crossing is where the touch point is exactly at the end
        // (the bisection on the centre's travel leaves it up to the accuracy short of or
        // past it), so the next segment takes over the same ball at the shared vertex.
        if let (Element::Edge(e), Some((false, true))) = (triplet[i], exit) {
            let (lo, hi) = self.model.edges[e].range;
            let te = slot(&xc, i)[0];
            let end = if te - lo < hi - te { lo } else { hi };
            if let Some(y) = self
                .solve_holding(&sys, &xc, 4 + 2 * i, end)
                .filter(|y| v3(y).distance(v3(&xc)) <= SAME_PLACE_REL_ACCURACY * acc)
            {
                xc = y;
            }
        }
        match self.hand_over_at(triplet, i, &xc, t, exit) {
            Ok((to, xnew)) => Ok((to, xc, xnew)),
            Err(HandOverError::Stop(why)) if unbracketed => {
                Err((HandOverError::Unbracketed(why), xc))
            }
            Err(e) => Err((e, xc)),
        }
    }

    /// True when the point at parameter `te` of edge `e` is within
    /// [`SAME_PLACE_REL_ACCURACY`] × the accuracy of one of its end vertices.
    fn at_edge_end(&self, e: usize, te: f64) -> bool {
        let p = crate::geom::eval_curve(&self.model.edges[e].curve, te).p;
        self.model.edges[e].vertices.iter().any(|&v| {
            self.model.vertices[v].point.distance(p) <= SAME_PLACE_REL_ACCURACY * self.opts.accuracy
        })
    }

    /// The seam point near `xc` of the system `sys` whose touch point `i`, on reflex edge
    /// `e`, has the normal of the face at the nearer end of the edge's arc; `None` when the
    /// corrector fails or lands farther than [`SAME_PLACE_REL_ACCURACY`] × the accuracy away.
    fn at_arc_end(
        &self,
        sys: &MedialSystem,
        e: usize,
        i: usize,
        xc: &DVector<f64>,
    ) -> Option<DVector<f64>> {
        let acc = self.opts.accuracy;
        let mut y = xc.clone();
        for _ in 0..4 {
            let s = slot(&y, i);
            let n = Element::Edge(e).eval(self.model, s)?.n;
            let fan = self.edge_fan(e, s[0])?;
            let k = nearer_end(&fan, n);
            let end = crate::medial::equations::edge_angle(self.model, e, s[0], fan[k])?;
            // The same branch of the angle as the touch point's.
            let tau = std::f64::consts::TAU;
            let end = end + tau * ((s[1] - end) / tau).round();
            if (end - s[1]).abs() <= 1e-12 {
                break;
            }
            y = self.solve_holding(sys, &y, 5 + 2 * i, end)?;
        }
        (v3(&y).distance(v3(xc)) <= SAME_PLACE_REL_ACCURACY * acc).then_some(y)
    }

    /// [`Self::hand_over`] at the crossing point `xc`. For a touch point on an edge, `exit`
    /// says which bounds the point just past the crossing kept (range, arc), when known.
    pub(super) fn hand_over_at(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
        exit: Option<(bool, bool)>,
    ) -> Result<(Element, DVector<f64>), HandOverError> {
        let xc = xc.clone();
        let seg = triplet[i];
        let ev = seg
            .eval(self.model, slot(&xc, i))
            .ok_or(OpenReason::UndefinedNormal { element: seg })?;
        let (to, params) = match seg {
            Element::Face(f) => self.next_from_face(f, &ev)?,
            Element::Edge(e) => self.next_from_edge(e, slot(&xc, i)[0], exit, &ev)?,
            Element::Vertex(v) => self.next_from_vertex(v, &ev)?,
        };
        // Off a cone's apex, the exact crossing touches the cone at the apex, where its normal
        // is undefined: the ball moves on with its touch point along the generator, to where
        // `next_from_vertex` put it.
        let xc = match (seg, to) {
            (Element::Vertex(v), Element::Face(f)) if self.apexes_at(v).any(|a| a.face == f) => {
                let mut y = xc;
                if let Some(q) = sys_point(self.model, to, params) {
                    let moved = v3(&y) + (q - ev.p);
                    y.rows_mut(0, 3).copy_from_slice(&moved.to_array());
                }
                y
            }
            _ => xc,
        };
        let mut handed = self.polish_hand_over(triplet, i, &xc, t, to, params, ev.p);
        // Across a smooth edge where the next face bends slightly towards the ball (a
        // reflex kink within the tangent tolerance), the same ball's touch point on it lies
        // behind the edge, off the face: the ball touches the edge itself while its normal
        // turns from one face's to the other's, as at a reflex edge.
        // (`polish_hand_over` refuses a touch point that slid off the next face.)
        if let (Element::Face(f), Element::Face(_), Err(HandOverError::Stop(_))) =
            (seg, to, &handed)
        {
            if let Some(ok) = self.onto_smooth_edge(triplet, i, f, &xc, t, &ev) {
                handed = Ok(ok);
            }
        }
        // From a reflex edge into the next one at a vertex where they meet at a slight
        // angle that turns away from the ball, the same ball's nearest point on the next
        // edge lies behind the vertex: the touch point stays on the vertex while the normal
        // turns (see `next_from_vertex` for where it leaves), as when it is handed back and
        // forth there.
        if let (Err(HandOverError::Stop(_)), Element::Edge(_), Element::Edge(_)) =
            (&handed, seg, to)
        {
            if let Some(ok) = self.onto_vertex(triplet, i, &xc, t) {
                return Ok(ok);
            }
        }
        handed
    }

    /// Touch point `i` at `ev`, which left face `f` across a smooth edge, onto that edge
    /// (with the face's normal, an end of the edge's arc), when it is the same ball there.
    fn onto_smooth_edge(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        f: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
        ev: &FieldEval,
    ) -> Option<(Element, DVector<f64>)> {
        let (e, te) = self.nearest_edge_of_face(f, ev.p)?;
        if self.class.edges[e].kind != EdgeKind::Smooth {
            return None;
        }
        let mut th = crate::medial::equations::edge_angle(self.model, e, te, ev.n)?;
        let to = Element::Edge(e);
        // The face's normal where the touch point left it is the end of the edge's arc up to
        // how far that point is from the edge's (the polygon's crossing is off the exact
        // edge): an angle whose effect on the centre, r·angle, is within the accuracy is
        // that end.
        if !self.on_segment(to, [te, th]) {
            let fan = self.edge_fan(e, te)?;
            let k = nearer_end(&fan, ev.n);
            if ev.n.angle_between(fan[k]) * xc[3] > self.opts.accuracy {
                return None;
            }
            let end = crate::medial::equations::edge_angle(self.model, e, te, fan[k])?;
            let tau = std::f64::consts::TAU;
            th = end + tau * ((th - end) / tau).round();
            if !self.on_segment(to, [te, th]) {
                return None;
            }
        }
        self.polish_hand_over(triplet, i, xc, t, to, [te, th], ev.p)
            .ok()
    }

    /// Where a touch point at `ev` that left face `f` goes on: the reflex edge it reached,
    /// or across a smooth edge the next face (with its parameters there).
    fn next_from_face(
        &self,
        f: usize,
        ev: &FieldEval,
    ) -> Result<(Element, [f64; 2]), HandOverError> {
        let acc = self.opts.accuracy;
        let seg = Element::Face(f);
        // At a cone's apex (a drill point's tip) the touch point passes onto the apex, which
        // the ball touches while its normal turns about the cone's axis.
        if let Some(v) = self.apex_reached(f, ev.p) {
            return Ok((Element::Vertex(v), vertex_angles(ev.n)));
        }
        // The distance from the touch point to edge `e`'s point at `te` (its nearest there).
        let away = |&(e, te): &(usize, f64)| {
            crate::geom::eval_curve(&self.model.edges[e].curve, te)
                .p
                .distance(ev.p)
        };
        let reaches = |hit: &(usize, f64)| away(hit) <= REACH_REL_ACCURACY * acc;
        // A touch point running along an edge of this face (`along`: a smooth edge it was
        // handed back and forth across, or a reflex edge it grazed) leaves where it reaches
        // another edge at the edge's end: at that vertex the edge it runs along is as near,
        // and is not crossed. An edge farther than that one (by more than the same-place
        // distance) is not where it leaves: it leaves across the edge it runs along.
        let running_along = self.edges_run_along(f).last();
        let (e, te) = running_along
            .and_then(|e| {
                let along = crate::geom::nearest_on_edge(self.model, e, ev.p, None).2;
                self.nearest_edge_of_face_except(f, ev.p, e)
                    .filter(|hit| away(hit) <= along + SAME_PLACE_REL_ACCURACY * acc)
            })
            .filter(reaches)
            .or_else(|| self.nearest_edge_of_face(f, ev.p).filter(reaches))
            .ok_or(OpenReason::LeftFaceAwayFromEdges { face: seg })?;
        let edge = &self.model.edges[e];
        // A mixed edge (convex along part of it, reflex or smooth along the rest) is what it
        // is where the touch point reaches it.
        let kind = match self.class.edges[e].kind {
            EdgeKind::Mixed => {
                crate::classify::edge_kind_at(self.model, e, te, self.opts.tangent_angle_rad).0
            }
            kind => kind,
        };
        match kind {
            EdgeKind::Reflex => {
                let th = crate::medial::equations::edge_angle(self.model, e, te, ev.n)
                    .ok_or(OpenReason::NoNormalFrame { edge: e })?;
                Ok((Element::Edge(e), [te, th]))
            }
            EdgeKind::Smooth => {
                let g = if edge.faces[0] == f {
                    edge.faces[1]
                } else {
                    edge.faces[0]
                };
                // From the edge's samples on the next face: a projection from nothing
                // searches the whole surface (most of the trace's time on a NURBS part).
                let uv = self
                    .edge_face_normal(e, g, te, ev.p)
                    .map(|(uv, _)| (uv[0], uv[1]))
                    .or_else(|| project_point(&self.model.faces[g].surface, ev.p, None))
                    .ok_or(OpenReason::NotFoundOnFace { face: g })?;
                Ok((Element::Face(g), [uv.0, uv.1]))
            }
            kind => Err(HandOverError::Stop(OpenReason::ReachedEdge {
                element: seg,
                kind,
                edge: e,
            })),
        }
    }

    /// Where a touch point at `ev`, parameter `te` on reflex edge `e`, goes on: past the
    /// edge's end (see [`Self::next_at_edge_end`]), or off its arc onto the face at that end
    /// of the arc.
    fn next_from_edge(
        &self,
        e: usize,
        te: f64,
        exit: Option<(bool, bool)>,
        ev: &FieldEval,
    ) -> Result<(Element, [f64; 2]), HandOverError> {
        let edge = &self.model.edges[e];
        let (lo, hi) = edge.range;
        // Off the edge's end or off its arc? The crossing is bisected on the centre's
        // travel, so the touch point may stop short of the end by more than a relative 1e-6:
        // an end within SAME_PLACE_REL_ACCURACY × the accuracy, or a normal well inside the
        // arc, means the end.
        let at_end = match exit {
            Some((in_range, in_arc)) => !in_range && in_arc,
            None => {
                (te - lo).min(hi - te) <= 1e-6 * (hi - lo)
                    || (self.at_edge_end(e, te)
                        && self.edge_fan(e, te).is_some_and(|fan| {
                            ev.n.angle_between(fan[0]).min(ev.n.angle_between(fan[1])) > 1e-4
                        }))
            }
        };
        if at_end {
            return self.next_at_edge_end(e, te, ev);
        }
        let fan = self
            .edge_fan(e, te)
            .ok_or(OpenReason::NoFaceNormals { edge: e })?;
        let g = edge.faces[nearer_end(&fan, ev.n)];
        let (uv, _) = self
            .edge_face_normal(e, g, te, ev.p)
            .ok_or(OpenReason::NotFoundOnFace { face: g })?;
        Ok((Element::Face(g), uv))
    }

    /// Past the end of reflex edge `e` (at parameter `te`), with the same normal: along the
    /// reflex edge that continues it tangentially (a circle split at a seam vertex, a line
    /// running into an arc, a closed edge into its own start), or onto the vertex there when
    /// it is reflex or mixed. At a corner of two reflex edges the touch point stays on the
    /// vertex while the normal turns.
    fn next_at_edge_end(
        &self,
        e: usize,
        te: f64,
        ev: &FieldEval,
    ) -> Result<(Element, [f64; 2]), HandOverError> {
        let edge = &self.model.edges[e];
        let (lo, hi) = edge.range;
        let v = if te - lo < hi - te {
            edge.vertices[0]
        } else {
            edge.vertices[1]
        };
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
        if let [(g, tg)] = next[..] {
            let tangential = e == g
                || self
                    .turn_at(v, e, g)
                    .is_none_or(|a| a <= self.opts.tangent_angle_rad);
            if let Some(th) = tangential
                .then(|| crate::medial::equations::edge_angle(self.model, g, tg, ev.n))
                .flatten()
            {
                return Ok((Element::Edge(g), [tg, th]));
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
        Ok((Element::Vertex(v), vertex_angles(ev.n)))
    }

    /// The apex of face `f`'s cone within [`SAME_PLACE_REL_ACCURACY`] × the accuracy of `p`.
    fn apex_reached(&self, f: usize, p: DVec3) -> Option<usize> {
        let near = SAME_PLACE_REL_ACCURACY * self.opts.accuracy;
        self.apexes
            .iter()
            .find(|a| a.face == f && a.point.distance(p) <= near)
            .map(|a| a.vertex)
    }

    /// Where a touch point at `ev` leaves vertex `v`: onto the cone whose apex it is, when
    /// the normal left the normals the apex admits (along the generator where the cone's
    /// normal is the ball's, a rounding from the apex, where the face's normal is defined);
    /// otherwise onto the reflex edge whose direction the normal turned away from.
    fn next_from_vertex(
        &self,
        v: usize,
        ev: &FieldEval,
    ) -> Result<(Element, [f64; 2]), HandOverError> {
        // The bound the normal is nearest to breaking (the crossing is the last point that
        // keeps them all): a cone's generators, or an edge's direction.
        let edge_margin = self
            .vertex_tangents(v)
            .iter()
            .map(|(_, d)| ev.n.dot(*d))
            .fold(f64::INFINITY, f64::min);
        if let Some(a) = self
            .apexes_at(v)
            .min_by(|a, b| a.margin(ev.n).total_cmp(&b.margin(ev.n)))
            .filter(|a| a.margin(ev.n) <= edge_margin)
        {
            let d = a.generator_for(ev.n).ok_or(OpenReason::UndefinedNormal {
                element: Element::Vertex(v),
            })?;
            let off = a.point + SAME_PLACE_REL_ACCURACY * self.opts.accuracy * d;
            let uv = project_point(&self.model.faces[a.face].surface, off, None)
                .ok_or(OpenReason::NotFoundOnFace { face: a.face })?;
            return Ok((Element::Face(a.face), [uv.0, uv.1]));
        }
        let (e, _) = self
            .vertex_tangents(v)
            .into_iter()
            .min_by(|a, b| ev.n.dot(a.1).total_cmp(&ev.n.dot(b.1)))
            .ok_or(OpenReason::VertexWithoutEdges { vertex: v })?;
        // Along a smooth edge (faces meeting tangentially to the angle tolerance: a faceted
        // profile's walls), the touch point leaves the vertex onto the face whose normal
        // the ball's is.
        if self.class.edges[e].kind == EdgeKind::Smooth {
            let p = self.model.vertices[v].point;
            let edge = &self.model.edges[e];
            let t = if edge.vertices[0] == v {
                edge.range.0
            } else {
                edge.range.1
            };
            if let Some((f, uv, _)) = edge
                .faces
                .iter()
                .filter_map(|&f| {
                    let (uv, n) = self.edge_face_normal(e, f, t, p)?;
                    Some((f, uv, n.angle_between(ev.n)))
                })
                .min_by(|a, b| a.2.total_cmp(&b.2))
            {
                return Ok((Element::Face(f), uv));
            }
        }
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
        Ok((Element::Edge(e), [te, th]))
    }

    /// Moves touch point `i` of the seam point `xc` onto the vertex it sits at (within 10×
    /// the accuracy), keeping its normal, when the ball may touch that vertex there (the
    /// normal inside the vertex's cone) and the re-solved point is the same ball.
    pub(super) fn onto_vertex(
        &mut self,
        triplet: &[Element; 3],
        i: usize,
        xc: &DVector<f64>,
        t: &DVector<f64>,
    ) -> Option<(Element, DVector<f64>)> {
        let ev = triplet[i].eval(self.model, slot(xc, i))?;
        let v = (0..self.model.vertices.len())
            .filter(|&v| {
                self.model.vertices[v].point.distance(ev.p)
                    <= SAME_PLACE_REL_ACCURACY * self.opts.accuracy
            })
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
    pub(super) fn polish_hand_over(
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
        // The ball osculates the next face or curved edge (a fillet or a corner patch of its
        // own radius, a hole's rim): it touches it along a curve, and the seam ends there, at
        // that centre of curvature. To the accuracy, as the curvature limit is located: a
        // ball bigger by the accuracy would poke through (the system is singular there, and
        // its corrector lands anywhere).
        if !curvature_allows(
            self.model,
            to,
            params,
            xc[3] * (1.0 + OSCULATING_REL_RADIUS) + acc,
        ) {
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
        // Onto a face whose normal differs from the old segment's at the crossing by an
        // angle δ within the tangent tolerance (faces that meet at a smooth edge are tangent
        // only to that tolerance; a reflex edge's arc end is the face's normal only to the
        // crossing's accuracy), the same ball touches it r·sin δ away, its centre moves
        // r·(1 − cos δ); likewise onto a reflex edge running on from one at a slight angle.
        // It must then still be on the new segment: where it slid off (behind a smooth
        // edge or a vertex, the next one bending towards the ball), the ball touches that
        // edge or vertex instead while its normal turns (see `hand_over_at`).
        let kink = match (
            seg.eval(self.model, slot(&xc, i)),
            to.eval(self.model, params),
        ) {
            (Some(a), Some(b)) if !matches!(to, Element::Vertex(_)) => a.n.angle_between(b.n),
            _ => 0.0,
        };
        // Where the file has a gap `g` there, the faces may cross at a steeper angle than the
        // tangent tolerance: a ball tilted by `δ` off one face's normal sinks `r·(1 − cos δ)`
        // into the other, which the gap's tolerance admits up to `g`.
        let file_gap = self.element_gap(seg).max(self.element_gap(to));
        let gap_tilt = (1.0 - file_gap / xc[3]).clamp(-1.0, 1.0).acos();
        let kink = if kink <= self.opts.tangent_angle_rad + gap_tilt {
            kink
        } else {
            0.0
        };
        // To first order; where the new segment bends towards the ball (curvature κ) its
        // foot point runs 1/(1 − r·κ) times as far (the foot of a fixed centre on a curve
        // through p: (c − γ(s))·γ'(s) = 0 gives s = r·sin δ / (1 − r·κ)), κ the most it
        // bends between the two touch points (a spline blend's curvature may rise from 0).
        let bend = [params, slot(&sol.x, i)]
            .into_iter()
            .filter_map(|s| crate::medial::maximal::bending(self.model, to, s))
            .filter(|k| k.is_finite())
            .fold(0.0_f64, f64::max);
        let bend = 1.0 / (1.0 - xc[3] * bend).max(MIN_OSCULATION_GAP);
        let (slide, sink) = (xc[3] * kink.sin() * bend, xc[3] * (1.0 - kink.cos()));
        // Where the file's edge between the two follows one surface and not the other, the
        // ball moves by up to that gap as it passes from one to the other, and its foot on
        // the new segment by as much again times the same factor; where the ball is held by
        // faces meeting at a slight angle (touched on either side of a convex crease of a few
        // degrees), many times as far: by as much as offsetting the new segment by the gap
        // moves the solution.
        let (centre_by_gap, touch_by_gap) =
            self.moved_by_offset(&sys, &sol.x, &row, c, i, file_gap);
        let same = sol.status == SolveStatus::Converged
            && v3(&sol.x).distance(v3(&xc)) <= 2.0 * acc + 10.0 * gap + sink + centre_by_gap
            && sys_point(self.model, to, slot(&sol.x, i)).is_some_and(|q| {
                let d = q.distance(p);
                let off = 2.0 * acc + 2.0 * gap + (file_gap * bend).max(touch_by_gap);
                d <= off || (d <= off + slide && self.on_segment(to, slot(&sol.x, i)))
            });
        if !same {
            // The ball osculates the new segment to within a few accuracies (its radius of
            // curvature at the crossing within NEARLY_OSCULATING_ACCURACIES of `r`): the foot
            // of the centre on it is then indeterminate along the arc where the two nearly
            // coincide (it runs 1/(1 − r·κ) times as far as on a flat face), and the solve
            // lands off the segment; the seam is at that segment's curvature limit, to the
            // accuracy the limit is located to (a B-spline blend of nominal radius 0.9 whose
            // radius falls to the ball's 0.8726 where it tapers to a point).
            if !curvature_allows(
                self.model,
                to,
                params,
                xc[3] + NEARLY_OSCULATING_ACCURACIES * acc,
            ) {
                return Err(HandOverError::Osculates(to));
            }
            return Err(HandOverError::Stop(OpenReason::NoSeamPointAfterHandover {
                from: seg,
                to,
                status: sol.status,
                moved: v3(&sol.x).distance(v3(&xc)),
            }));
        }
        Ok((to, sol.x))
    }

    /// How far the ball `x` on `sys` (held to `row·x = c`) moves when its `i`-th segment is
    /// offset towards it by `g`, to first order: its centre's move and the `i`-th touch
    /// point's, each at least `g` and at most [`MAX_GAP_AMPLIFICATION`] times `g` (`g` where
    /// the system is singular). Where the ball's touch points on two faces are close on
    /// either side of a slight crease, the centre moves `g` over twice the sine of half the
    /// crease's angle; where it nearly osculates a face, its touch point there runs
    /// `1/(1 − r·κ)` times as far as the centre.
    fn moved_by_offset(
        &self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        row: &DVector<f64>,
        c: f64,
        i: usize,
        g: f64,
    ) -> (f64, f64) {
        if g <= 0.0 {
            return (0.0, 0.0);
        }
        let (Some((_, j)), Some(e)) = (
            sys.eval_with_row(self.model, x, row, c),
            sys.segments[i].eval(self.model, slot(x, i)),
        ) else {
            return (g, g);
        };
        let mut rhs = DVector::zeros(x.len());
        for k in 0..3 {
            rhs[3 * i + k] = g * e.n[k];
        }
        let bound = |d: f64| {
            if d.is_finite() {
                d.clamp(g, MAX_GAP_AMPLIFICATION * g)
            } else {
                g
            }
        };
        j.lu().solve(&rhs).map_or((g, g), |d| {
            let touch = e.dp[0] * d[4 + 2 * i] + e.dp[1] * d[5 + 2 * i];
            (bound(v3(&d).length()), bound(touch.length()))
        })
    }
}

/// The most a file's gap is taken to move a ball by (see `moved_by_offset`): a crease of
/// 1.15 degrees between the two faces it touches.
const MAX_GAP_AMPLIFICATION: f64 = 50.0;

/// The least `1 − r·κ` the factor `1/(1 − r·κ)` by which a foot on a segment bending
/// towards the ball runs farther than on a flat one is taken at (a hand-over's slide
/// tolerance; below it the ball nearly osculates the segment, see
/// [`NEARLY_OSCULATING_ACCURACIES`]). A foot on a blend of radius 1.5 tapering to a point ran
/// 280 times as far (`r·κ` 0.9964): with the factor capped at 10 the hand-over onto it was
/// refused, though its ball was the same to 1e-6 mm.
const MIN_OSCULATION_GAP: f64 = 1e-3;

/// How many accuracies a new segment's radius of curvature at a hand-over's crossing may
/// exceed the ball's for the ball to count as osculating it, where the hand-over's solve
/// finds no seam point (half the margin `verify` allows a curvature limit).
const NEARLY_OSCULATING_ACCURACIES: f64 = 4.0;

/// Which end of an edge's arc of normals `fan` the normal `n` is nearer (the first on a tie).
fn nearer_end(fan: &[DVec3; 2], n: DVec3) -> usize {
    usize::from(n.angle_between(fan[1]) < n.angle_between(fan[0]))
}
