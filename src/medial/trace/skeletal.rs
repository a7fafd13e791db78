//! Skeletal edges at vertices: where a seam ends because two of its touch points, on one part
//! of the boundary (faces and the reflex edges joining them), have met at a vertex of it.
//!
//! The commonest case is a box standing on a plate: each of its vertical (convex) edges ends
//! at the plate's top in a vertex with two reflex edges. Below that vertex the balls touching
//! the two reflex edges form a sheet whose two touch points come together at the vertex: the
//! sheet ends there along the straight line of balls touching the vertex alone, centres `V +
//! s·d` and radius `s` for `s` from 0 up to the ball where the seam of those two edges and a
//! third element ends. Each of those balls lies inside that last one (they are internally
//! tangent at V), so each is empty: the line is the sheet's free edge, its *skeletal edge*,
//! and it joins the seam's end to the vertex, where the convex edge's rim meets it.

use super::tracer::Tracer;
use crate::classify::EdgeKind;
use crate::medial::axis::{DegenerateKind, SeamEnd, SkeletalEdge};
use crate::model::Element;
use glam::DVec3;

/// A rim end where a free edge starts (see [`Tracer::flat_rim_ends`]).
pub(super) struct FreeEdgeStart {
    vertex: usize,
    /// The rim's two faces.
    pair: [Element; 2],
    /// The outward normal at the vertex the free edge runs against (`V − s·n`).
    normal: DVec3,
    /// The faces tangent to the plane of that normal at the vertex: where a round's axis
    /// the free edge runs to is looked for.
    tangent: Vec<usize>,
}

/// Balls written along a skeletal edge at a vertex (it is straight, `r` linear along it).
const VERTEX_LINE_BALLS: usize = 9;

/// A free edge where a rim flattens out is looked for only when the ball of this many
/// accuracies tangent at the vertex is empty (a shorter one is a vertex's rounding).
const FREE_EDGE_MIN_ACCURACIES: f64 = 16.0;

/// A free edge's largest ball is on a degenerate curve when its centre and radius are this
/// many accuracies from the curve's polyline of balls (the edge's ball is found to an eighth
/// of the accuracy by emptiness, which grows only linearly past it; the curve's balls to the
/// accuracy).
const FREE_EDGE_MEETS_ACCURACIES: f64 = 4.0;

impl Tracer<'_> {
    /// The skeletal edges at vertices of the seams traced: for every seam end at a curvature
    /// limit or a pinch whose ball has two touch points on one group of segments at a vertex
    /// both reach (to the accuracy, as verification holds them), the straight line from that
    /// ball to the vertex. A curvature-limit end there is renamed for the vertex (the ball
    /// "osculates" it: the element it was being handed to is another face at that vertex).
    /// Seam ends at one ball share one edge.
    pub(super) fn skeletal_at_vertices(&mut self, free: &[FreeEdgeStart]) -> Vec<SkeletalEdge> {
        let near = self.opts.accuracy;
        let mut out: Vec<SkeletalEdge> = vec![];
        for s in 0..self.seams.len() {
            for end in 0..2 {
                let seam = &self.seams[s];
                if !matches!(
                    seam.ends[end],
                    SeamEnd::CurvatureLimit { .. } | SeamEnd::Pinch { .. }
                ) {
                    continue;
                }
                let (point, segs) = seam.at_end(end);
                let Some(point) = point else { continue };
                let met = self.met_at_vertices(segs, &point.touch, near);
                let Some(&(_, first)) = met.first() else {
                    continue;
                };
                let ball = point.point;
                let solid = seam.solid;
                if let SeamEnd::CurvatureLimit { segment } = &mut self.seams[s].ends[end] {
                    *segment = Element::Vertex(first);
                }
                let at = DVec3::new(ball[0], ball[1], ball[2]);
                // A non-generic seam's ball may have two pairs meeting, each at its own
                // vertex (a plate through a hub's corner: the touch points on the plate's two
                // reflex edges at the top meet at one vertex, those at the bottom at another):
                // a free edge runs to each.
                for (pair, v) in met {
                    let same = out.iter_mut().find(|k| {
                        let b = k.balls[0];
                        k.vertex == v
                            && DVec3::new(b[0], b[1], b[2]).distance(at) <= near
                            && (b[3] - ball[3]).abs() <= near
                    });
                    match same {
                        Some(k) => k.starts.push([s, end]),
                        None => out.push(SkeletalEdge {
                            id: out.len(),
                            solid,
                            starts: vec![[s, end]],
                            segments: pair,
                            vertex: v,
                            balls: self.vertex_line(ball, v),
                            meets: vec![],
                        }),
                    }
                }
            }
        }
        self.flat_rim_ends(free, &mut out);
        out
    }

    /// The free edges where a rim's sheet ends at its vertex with its two touch points
    /// together: at each end `V` of a convex edge between faces `A` and `B`,
    /// - where the edge flattens out (smooth at `V` by the classification's angle tolerance:
    ///   two rounds of one radius meeting in a mitre, both tangent to the side face at the
    ///   mitre's end), along the faces' common normal `n` there;
    /// - where `V`'s other edges are a smooth one joining `A` to a face `C` and a reflex one
    ///   joining `B` to `C` (a round ending against a wall: `A` the top the round is tangent
    ///   to, `B` the wall above the round, which narrows to nothing at `V`), along `A`'s
    ///   normal `n` there: the sheet of `A` and `B` goes on past the wall's foot as the sheet
    ///   of `A` and that reflex edge, whose two touch points meet at `V`;
    /// - where `V`'s other edges are two reflex ones joining `A` and `B` to one face `W` (a
    ///   boss's top rim ending against a taller boss's wall), along `W`'s normal `n` there:
    ///   the balls tangent to `W` at `V` are where the sheet of those two reflex edges ends,
    ///   its two touch points meeting at `V`, and the rim's sheet ends on them;
    ///
    /// the line of balls tangent to the boundary at `V`, centres `V − s·n` and radius `s`, from
    /// the largest of them that is empty down to the vertex (each lies inside the next, so
    /// emptiness decides one radius). Where a degenerate curve passes through that largest
    /// ball (the rounds' axes), the edge meets it; otherwise nothing known ends there and the
    /// sheet's boundary stays open (verification says so). Not where a skeletal edge already
    /// ends at the vertex (one a seam's end found).
    fn flat_rim_ends(&self, free: &[FreeEdgeStart], out: &mut Vec<SkeletalEdge>) {
        for start in free {
            // A skeletal edge a seam started at this vertex is that free edge already.
            if out.iter().any(|k| k.vertex == start.vertex) {
                continue;
            }
            let &FreeEdgeStart {
                vertex: v,
                pair,
                normal: n,
                ..
            } = start;
            let p = self.model.vertices[v].point;
            let solid = self.solid_of(pair[0]);
            let Some(largest) = self.largest_tangent_ball(solid, p, n) else {
                continue;
            };
            // A line no longer than the file's gap about the vertex is that gap's noise (the
            // boundary there is defined only to it; the two checkers put such balls on
            // either side of it).
            if largest <= self.element_gap(Element::Vertex(v)) {
                continue;
            }
            // Where a degenerate curve crosses the line below the largest empty ball (a
            // round's axis whose arc of contact narrows to the vertex there: past its ball
            // the line's balls are empty but touch the vertex alone), the free edge starts
            // on it.
            let r = self
                .degenerate_on_line(solid, p, n, largest)
                .unwrap_or(largest);
            let c = p - r * n;
            let ball = [c.x, c.y, c.z, r];
            out.push(SkeletalEdge {
                id: out.len(),
                solid,
                starts: vec![],
                segments: pair,
                vertex: v,
                balls: self.vertex_line(ball, v),
                meets: self.degenerate_balls_at(solid, c, r),
            });
        }
    }

    /// The rim ends where a free edge starts (see [`Self::flat_rim_ends`]), with the normal
    /// it runs along and the faces tangent to that normal's plane at the vertex.
    pub(super) fn free_edge_starts(&self) -> Vec<FreeEdgeStart> {
        let tol = crate::classify::DEFAULT_ANGLE_TOL_DEG.to_radians();
        let mut out = vec![];
        for (e, edge) in self.model.edges.iter().enumerate() {
            if self.class.edges[e].kind != EdgeKind::Convex {
                continue;
            }
            let Some([fa, fb]) = self.two_faces(e) else {
                continue;
            };
            for (end, &v) in edge.vertices.iter().enumerate() {
                let t = if end == 0 { edge.range.0 } else { edge.range.1 };
                let p = self.model.vertices[v].point;
                let normal = |f| self.edge_face_normal(e, f, t, p).map(|(_, n)| n);
                // Told by the edges at the vertex first (a mitre's end has two smooth ones
                // besides), the dihedral angle measured only there.
                let flat = self.others_smooth(e, v)
                    && crate::classify::edge_kind_at(self.model, e, t, tol).0 == EdgeKind::Smooth;
                let (n, tangent) = if flat {
                    let (Some(na), Some(nb)) = (normal(fa), normal(fb)) else {
                        continue;
                    };
                    ((na + nb).normalize_or_zero(), vec![fa, fb])
                } else if let Some((x, c)) = self.round_against_a_wall(e, v, [fa, fb]) {
                    let Some(n) = normal(x) else { continue };
                    (n, vec![x, c])
                } else if let Some((w, g, tg)) = self.rim_end_at_a_wall(e, v, [fa, fb]) {
                    let Some((_, n)) = self.edge_face_normal(g, w, tg, p) else {
                        continue;
                    };
                    (n, vec![w])
                } else {
                    continue;
                };
                if n != DVec3::ZERO {
                    out.push(FreeEdgeStart {
                        vertex: v,
                        pair: [Element::Face(fa), Element::Face(fb)],
                        normal: n,
                        tangent,
                    });
                }
            }
        }
        out
    }

    /// Samples the faces tangent at each rim end where a free edge starts, near its vertex,
    /// for degenerate curves (recorded like any sampled ball's, and traced with them): a
    /// round's axis the free edge runs to is often found by no other sample (the round's
    /// balls elsewhere blocked by what stands next to it, or the round touched by seams
    /// already, so not sampled at all). Points at 1/64, 1/16 and 1/4 of the face's domain
    /// from the vertex's parameters along each direction, those on the face.
    pub(super) fn sample_rounds_at_free_edges(&mut self, free: &[FreeEdgeStart]) {
        for start in free {
            let p = self.model.vertices[start.vertex].point;
            for &f in &start.tangent {
                let face = &self.model.faces[f];
                let Some((u, v)) = crate::geom::project_point(&face.surface, p, None) else {
                    continue;
                };
                let d = face.domain;
                let (du, dv) = (d.u.1 - d.u.0, d.v.1 - d.v.0);
                for frac in [1.0 / 64.0, 1.0 / 16.0, 0.25] {
                    for [su, sv] in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
                        let s = [u + su * frac * du, v + sv * frac * dv];
                        if !self.on_segment(Element::Face(f), s) {
                            continue;
                        }
                        self.sample_for_degenerate(f, s);
                    }
                }
            }
        }
    }

    /// The edges at vertex `v` besides `e`, each with `true` where `v` is its end.
    fn other_edges_at(&self, e: usize, v: usize) -> Vec<(usize, bool)> {
        self.vertex_edges[v]
            .iter()
            .copied()
            .filter(|&(g, _)| g != e)
            .collect()
    }

    /// Edge `g`'s two faces, when they are two.
    fn two_faces(&self, g: usize) -> Option<[usize; 2]> {
        match self.model.edges[g].faces[..] {
            [a, b] if a != b => Some([a, b]),
            _ => None,
        }
    }

    /// True when vertex `v` has two edges besides `e`, both smooth (where two rounds meet
    /// `e`'s end in a mitre, each tangent to the face between them).
    fn others_smooth(&self, e: usize, v: usize) -> bool {
        let others = self.other_edges_at(e, v);
        others.len() == 2
            && others
                .iter()
                .all(|&(g, _)| self.class.edges[g].kind == EdgeKind::Smooth)
    }

    /// At vertex `v` of convex edge `e` between faces `faces`: where `v`'s other edges are
    /// exactly a smooth one joining one of the faces to a third face `C` and a reflex one
    /// joining the other to `C`, the face joined smoothly (whose normal at `v` is `C`'s) and
    /// `C`.
    fn round_against_a_wall(
        &self,
        e: usize,
        v: usize,
        faces: [usize; 2],
    ) -> Option<(usize, usize)> {
        let [(g, _), (h, _)] = self.other_edges_at(e, v)[..] else {
            return None;
        };
        let kind = |g: usize| self.class.edges[g].kind;
        let (smooth, reflex) = match (kind(g), kind(h)) {
            (EdgeKind::Smooth, EdgeKind::Reflex) => (g, h),
            (EdgeKind::Reflex, EdgeKind::Smooth) => (h, g),
            _ => return None,
        };
        let (s, r) = (self.two_faces(smooth)?, self.two_faces(reflex)?);
        faces.into_iter().find_map(|x| {
            let y = faces[0] + faces[1] - x;
            let c = s
                .into_iter()
                .find(|&c| c != x && !faces.contains(&c) && r.contains(&c))?;
            (s.contains(&x) && r.contains(&y)).then_some((x, c))
        })
    }

    /// At vertex `v` of convex edge `e` between faces `faces`: where `v`'s other edges are
    /// exactly two reflex ones joining each of the faces to one third face `W` (a boss's top
    /// rim ending against a taller boss's wall, a block's top edge against a wall), `W`, one
    /// of those edges and its parameter at `v`.
    fn rim_end_at_a_wall(
        &self,
        e: usize,
        v: usize,
        faces: [usize; 2],
    ) -> Option<(usize, usize, f64)> {
        let [(g, g_end), (h, _)] = self.other_edges_at(e, v)[..] else {
            return None;
        };
        let reflex = |g: usize| self.class.edges[g].kind == EdgeKind::Reflex;
        if !reflex(g) || !reflex(h) {
            return None;
        }
        let (eg, eh) = (self.two_faces(g)?, self.two_faces(h)?);
        // The face the two share that is neither of the rim's; each joins one of them.
        let w = eg
            .into_iter()
            .find(|&w| eh.contains(&w) && !faces.contains(&w))?;
        let other = |pair: [usize; 2]| pair[0] + pair[1] - w;
        let (x, y) = (other(eg), other(eh));
        if x == y || !faces.contains(&x) || !faces.contains(&y) {
            return None;
        }
        let edge = &self.model.edges[g];
        let t = if g_end { edge.range.1 } else { edge.range.0 };
        Some((w, g, t))
    }

    /// The radius of the largest empty ball tangent to the boundary at `p` with outward
    /// normal `n` (centre `p − s·n`), to an eighth of the accuracy; `None` when even a ball
    /// of [`FREE_EDGE_MIN_ACCURACIES`] accuracies is not empty (the boundary curves in
    /// tighter there, or `n` is not its normal).
    fn largest_tangent_ball(&self, solid: usize, p: DVec3, n: DVec3) -> Option<f64> {
        let a = self.opts.accuracy;
        // Held to a quarter of the accuracy: the ball's distance check then passes by a margin.
        let empty = |s: f64| {
            self.nearest_in(solid, p - s * n)
                .is_some_and(|(_, h)| h.distance >= s - 0.25 * a)
        };
        let mut lo = FREE_EDGE_MIN_ACCURACIES * a;
        if n == DVec3::ZERO || !empty(lo) {
            return None;
        }
        let mut hi = 2.0 * lo;
        while empty(hi) {
            if hi > self.model.diagonal() {
                return None;
            }
            (lo, hi) = (hi, 2.0 * hi);
        }
        while hi - lo > 0.125 * a {
            let mid = 0.5 * (lo + hi);
            if empty(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(lo)
    }

    /// The largest `s` up to `largest` (and a quarter of the accuracy past it) at which the
    /// line of balls `(p − s·n, s)` passes within [`FREE_EDGE_MEETS_ACCURACIES`] accuracies of the
    /// polyline of a degenerate curve of `solid` (nearest approach of each segment, in centre
    /// and radius, to the line).
    fn degenerate_on_line(&self, solid: usize, p: DVec3, n: DVec3, largest: f64) -> Option<f64> {
        let near = FREE_EDGE_MEETS_ACCURACIES * self.opts.accuracy;
        // Past the largest empty ball only by what its search leaves open (a ball further
        // out would not pass the distance check; a curve that close is met there anyway).
        let slack = 0.25 * self.opts.accuracy;
        let mut best: Option<f64> = None;
        for d in &self.degenerate {
            if d.solid != solid || d.kind != DegenerateKind::Curve {
                continue;
            }
            let at = |b: &[f64; 4]| (DVec3::new(b[0], b[1], b[2]), b[3]);
            let pieces: Vec<[(DVec3, f64); 2]> = match d.balls.len() {
                0 => vec![],
                1 => vec![[at(&d.balls[0]), at(&d.balls[0])]],
                _ => d.balls.windows(2).map(|w| [at(&w[0]), at(&w[1])]).collect(),
            };
            for [(a, ra), (b, rb)] in pieces {
                let Some((s, gap)) = line_meets_segment(p, n, (a, ra), (b, rb)) else {
                    continue;
                };
                if gap <= near && s > 0.0 && s <= largest + slack && best.is_none_or(|m| s > m) {
                    best = Some(s);
                }
            }
        }
        best
    }

    /// The degenerate curves of `solid` that pass through the ball at `c` of radius `r` (to
    /// [`FREE_EDGE_MEETS_ACCURACIES`] accuracies, between two of their consecutive balls, or
    /// at a curve's one ball): `[degenerate index, k]`, the ball at or after which it does.
    fn degenerate_balls_at(&self, solid: usize, c: DVec3, r: f64) -> Vec<[usize; 2]> {
        let near = FREE_EDGE_MEETS_ACCURACIES * self.opts.accuracy;
        let mut out = vec![];
        for (i, d) in self.degenerate.iter().enumerate() {
            if d.solid != solid || d.kind != DegenerateKind::Curve {
                continue;
            }
            if let Some(k) = crate::medial::axis::ball_on_polyline(&d.balls, c, r, near) {
                out.push([i, k]);
            }
        }
        out
    }

    /// The pairs of `touch` (on `segs`) on one group of segments that meet at a vertex both
    /// reach where the line of balls to it is medial ([`Self::line_to_vertex_is_medial`]),
    /// each with its vertex: of a generic seam's three, the first pair that does; of a
    /// non-generic seam's, every slot in one such pair, each at its own vertex (a plate
    /// through a hub's corner: the touch points on the plate's two reflex edges at the top
    /// meet at one vertex, those at the bottom at another), or else the first pair of any
    /// two slots that does (where the sheets round the ball are not yet told apart; a
    /// package's corner whose seam of four contacts names the two reflex edges meeting at
    /// the corner's vertex first and last).
    fn met_at_vertices(
        &self,
        segs: &[Element],
        touch: &[[f64; 3]],
        near: f64,
    ) -> Vec<([Element; 2], usize)> {
        let n = segs.len().min(touch.len());
        let met = |i: usize, k: usize| -> Option<([Element; 2], usize)> {
            let (a, b) = (segs[i], segs[k]);
            if self.groups.of(a) != self.groups.of(b) {
                return None;
            }
            let (ta, tb) = (DVec3::from_array(touch[i]), DVec3::from_array(touch[k]));
            (0..self.model.vertices.len())
                .find(|&v| {
                    let p = self.model.vertices[v].point;
                    p.distance(ta) <= near
                        && p.distance(tb) <= near
                        && self.reaches(a, v)
                        && self.reaches(b, v)
                        && self.line_to_vertex_is_medial(a, b, v)
                })
                .map(|v| ([a, b], v))
        };
        // The pairs that meet, in order of their slots, no slot in two of them and no vertex
        // twice: the first is the first of any two slots that meets.
        let mut pairs: Vec<([Element; 2], usize)> = vec![];
        let mut used = vec![false; n];
        for i in 0..n {
            for k in i + 1..n {
                if used[i] || used[k] {
                    continue;
                }
                if let Some((pair, v)) = met(i, k) {
                    if pairs.iter().all(|&(_, w)| w != v) {
                        pairs.push((pair, v));
                        (used[i], used[k]) = (true, true);
                    }
                }
            }
        }
        // Every slot of a non-generic seam paired: an edge from each pair; otherwise the
        // first pair's alone.
        if !(n > 3 && used.iter().all(|&u| u)) {
            pairs.truncate(1);
        }
        pairs
    }

    /// True when the balls touching vertex `v` alone, on the line from a ball where touch
    /// points on `a` and `b` met there down to `v`, are medial (a skeletal edge): where a
    /// reflex edge ends at `v` (by its classification's sample there), the boundary sharp
    /// towards the material; where `a` and `b` are faces joined at `v` by an edge (a convex
    /// one flattening out there: their sheet from that edge ends on the line, as
    /// [`Self::flat_rim_ends`] has it); where either is not a face. Not where two faces that
    /// share no edge at `v`, or only a smooth one, are tangent there and no reflex edge ends:
    /// a ball touching `v` alone then has one contact, and the touch points that met there
    /// (on a plane and a torus, a blend tapering to a point between them, on the Voron Manta
    /// mount; on that blend and the plane it runs into smoothly) close their sheet at that
    /// ball, as at a curvature limit.
    fn line_to_vertex_is_medial(&self, a: Element, b: Element, v: usize) -> bool {
        let (Element::Face(fa), Element::Face(fb)) = (a, b) else {
            return true;
        };
        self.vertex_edges[v].iter().any(|&(e, at_end)| {
            let faces = &self.model.edges[e].faces;
            (faces.contains(&fa)
                && faces.contains(&fb)
                && self.class.edges[e].kind != EdgeKind::Smooth)
                || self.class.edges[e].kind_at(at_end) == Some(EdgeKind::Reflex)
        })
    }

    /// The balls from `ball` to vertex `v` along the straight line through their centres.
    fn vertex_line(&self, ball: [f64; 4], v: usize) -> Vec<[f64; 4]> {
        let p = self.model.vertices[v].point;
        let c = DVec3::new(ball[0], ball[1], ball[2]);
        let n = VERTEX_LINE_BALLS - 1;
        (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                let q = c.lerp(p, t);
                // The seam's ball as it is; the others at their exact distance from the vertex.
                let r = if k == 0 { ball[3] } else { q.distance(p) };
                [q.x, q.y, q.z, r]
            })
            .collect()
    }
}

/// The nearest approach, in centre and radius (`[x, y, z, r]` as a point of 4-space), of the
/// line of balls `(p − s·n, s)` (`n` a unit vector) to the segment of balls from `(a, ra)` to
/// `(b, rb)`: the line's `s` there and the distance; `None` when they are parallel.
fn line_meets_segment(
    p: DVec3,
    n: DVec3,
    (a, ra): (DVec3, f64),
    (b, rb): (DVec3, f64),
) -> Option<(f64, f64)> {
    use nalgebra::{Matrix2, Vector2, Vector4};
    let four = |c: DVec3, r: f64| Vector4::new(c.x, c.y, c.z, r);
    // Line: L(s) = P + s·U; segment: A + t·D, t in [0, 1].
    let (big_p, u) = (four(p, 0.0), four(-n, 1.0));
    let (big_a, big_d) = (four(a, ra), four(b - a, rb - ra));
    let at = |s: f64, t: f64| ((big_p + u * s) - (big_a + big_d * t)).norm();
    let s_for = |t: f64| (big_a + big_d * t - big_p).dot(&u) / u.dot(&u);
    if big_d.norm() == 0.0 {
        let s = s_for(0.0);
        return Some((s, at(s, 0.0)));
    }
    // Normal equations of min |P + s·U − A − t·D|².
    let m = Matrix2::new(u.dot(&u), -u.dot(&big_d), -u.dot(&big_d), big_d.dot(&big_d));
    let w = big_a - big_p;
    let rhs = Vector2::new(u.dot(&w), -big_d.dot(&w));
    let st = m.lu().solve(&rhs)?;
    let t = st[1].clamp(0.0, 1.0);
    let s = s_for(t);
    Some((s, at(s, t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line of balls tangent at the origin under the plane z = 0 (centres (0, 0, −s),
    /// radius s) meets a round's axis along x at depth 3 (balls of radius 3) where it crosses
    /// it, at s = 3, exactly; an axis 0.5 off to the side passes at a distance of 0.5; balls
    /// of the wrong radius on the crossing axis are as far off as their radius is.
    #[test]
    fn a_line_of_tangent_balls_meets_an_axis_where_it_crosses_it() {
        let n = DVec3::Z;
        let axis = |y: f64, r: f64| {
            (
                (DVec3::new(-5.0, y, -3.0), r),
                (DVec3::new(5.0, y, -3.0), r),
            )
        };
        let ((a, ra), (b, rb)) = axis(0.0, 3.0);
        let (s, gap) = line_meets_segment(DVec3::ZERO, n, (a, ra), (b, rb)).unwrap();
        assert!((s - 3.0).abs() < 1e-12 && gap < 1e-12, "{s} {gap}");
        let ((a, ra), (b, rb)) = axis(0.5, 3.0);
        let (s, gap) = line_meets_segment(DVec3::ZERO, n, (a, ra), (b, rb)).unwrap();
        assert!(
            (s - 3.0).abs() < 1e-12 && (gap - 0.5).abs() < 1e-12,
            "{s} {gap}"
        );
        let ((a, ra), (b, rb)) = axis(0.0, 2.0);
        let (_, gap) = line_meets_segment(DVec3::ZERO, n, (a, ra), (b, rb)).unwrap();
        assert!((gap - 0.5f64.sqrt()).abs() < 1e-12, "{gap}");
        // A segment that stops short of the line: its end is the nearest approach.
        let (s, gap) = line_meets_segment(
            DVec3::ZERO,
            n,
            (DVec3::new(-5.0, 0.0, -3.0), 3.0),
            (DVec3::new(-1.0, 0.0, -3.0), 3.0),
        )
        .unwrap();
        assert!(
            (s - 3.0).abs() < 1e-12 && (gap - 1.0).abs() < 1e-12,
            "{s} {gap}"
        );
    }

    /// A ball on a polyline of balls is found on the segment it lies on (between balls 1
    /// and 2 here), or at a ball it is; one off by more than `near` in centre or radius is
    /// not.
    #[test]
    fn a_ball_is_on_a_polyline_of_balls_between_two_of_them_or_at_one() {
        use crate::medial::axis::ball_on_polyline;
        let balls = [
            [0.0, 0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0, 1.0],
            [2.0, 0.0, 0.0, 2.0],
        ];
        let on = |x: f64, y: f64, r: f64| ball_on_polyline(&balls, DVec3::new(x, y, 0.0), r, 1e-6);
        assert_eq!(on(1.5, 0.0, 1.5), Some(1));
        assert_eq!(on(2.0, 0.0, 2.0), Some(2));
        assert_eq!(on(0.5, 0.0, 1.0), Some(0));
        assert_eq!(on(1.5, 1e-3, 1.5), None);
        assert_eq!(on(1.5, 0.0, 1.6), None);
        assert_eq!(on(2.5, 0.0, 2.5), None);
    }
}
