//! Which loops of sheet boundaries bound one sheet (`docs/design.md`, sheets, step 3): the
//! pieces (exact segment pairs) along each loop, with those a skeletal edge's start ball
//! witnesses, and nesting on a plane where one side of a group pair is a single plane.

use super::arcs::{order_loop, sorted_pair, Arc, BoundaryRef, Place};
use crate::classify::{Classification, EdgeKind};
use crate::medial::axis::MedialAxis;
use crate::medial::segments::{SegmentGroups, UnionFind};
use crate::model::{Element, Model};
use glam::{DVec2, DVec3};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// Angle (rad) within which a ball's direction from a vertex it touches is taken to lie in
/// the normal cone of a face or edge there (the ball is exact to the accuracy; a face whose
/// normal there is that far off touches no ball of the sheet near it).
const IN_CONE_RAD: f64 = 1e-4;

/// At a ball where a seam ends with two touch points at a vertex (a pinch, a skeletal edge's
/// start), the sheets of the third element and each of the other two are one sheet with the
/// pieces of every element whose normal cone there holds the ball's direction: below a box
/// standing on a plate, the sheet between the plate's bottom and the box's two reflex foot
/// edges passes, round that ball, into the plate's middle sheet (bottom and top), whose
/// touch point on the top reaches the foot edge along a line from there. Adds those pieces
/// to the seam's two arcs on the third element. (Seams' arcs are the first three per seam.)
pub(super) fn add_witnesses(
    model: &Model,
    class: &Classification,
    mat: &MedialAxis,
    balls: &HashMap<[usize; 2], Place>,
    arcs: &mut [Arc],
) {
    for (n, s) in mat.seams.iter().enumerate() {
        for end in 0..2 {
            let vertex = match balls.get(&[n, end]) {
                Some(Place::Skeletal(k)) => mat.skeletal_edges.get(*k).map(|k| k.vertex),
                _ => None,
            };
            let (point, segs) = s.at_end(end);
            let (Some(v), Some(p)) = (vertex, point) else {
                continue;
            };
            let Some(at) = model.vertices.get(v).map(|v| v.point) else {
                continue;
            };
            // The third element: the touch point farthest from the vertex.
            let far = |k: usize| DVec3::from_array(p.touch[k]).distance(at);
            let Some(o) = (0..p.touch.len()).max_by(|&a, &b| far(a).total_cmp(&far(b))) else {
                continue;
            };
            let Some(&third) = segs.get(o) else { continue };
            let centre = DVec3::new(p.point[0], p.point[1], p.point[2]);
            let Some(d) = (centre - at).try_normalize() else {
                continue;
            };
            let witnessed: Vec<[Element; 2]> = in_cone_at(model, class, v, d)
                .into_iter()
                .map(|x| sorted_pair(x, third))
                .collect();
            // Not the sides that go on along a skeletal edge from this ball (of a seam of
            // four contacts meeting in two pairs, the far touch point is one of the other
            // pair's, whose side ends along its own edge).
            let along: Vec<[Element; 2]> = mat
                .skeletal_edges
                .iter()
                .filter(|k| k.starts.contains(&[n, end]))
                .map(|k| sorted_pair(k.segments[0], k.segments[1]))
                .collect();
            let sides = arcs.iter_mut().filter(|a| {
                matches!(a.slots, Some((m, [i, j])) if m == n && (i == o || j == o))
                    && !along.contains(&sorted_pair(a.pair[0], a.pair[1]))
            });
            for arc in sides {
                for w in &witnessed {
                    if !arc.pieces.contains(w) {
                        arc.pieces.push(*w);
                    }
                }
            }
        }
    }
}

/// The segments at vertex `v` whose normal cone there holds the unit direction `d` (into the
/// solid): the vertex, its reflex edges whose arc of normals holds `d`, its faces whose inward
/// normal is `d` (each to [`IN_CONE_RAD`]).
fn in_cone_at(model: &Model, class: &Classification, v: usize, d: DVec3) -> Vec<Element> {
    let at = model.vertices[v].point;
    let inward = |f: usize| -> Option<DVec3> {
        let face = model.faces.get(f)?;
        let uv = crate::geom::project_point(&face.surface, at, None)?;
        crate::geom::distance::face_normal(face, uv).map(|n| -n)
    };
    let mut out = vec![Element::Vertex(v)];
    let mut faces = vec![];
    for (e, edge) in model.edges.iter().enumerate() {
        if !edge.vertices.contains(&v) {
            continue;
        }
        for &f in &edge.faces {
            if !faces.contains(&f) {
                faces.push(f);
            }
        }
        if class.edges.get(e).map(|c| c.kind) != Some(EdgeKind::Reflex) {
            continue;
        }
        let t = if edge.vertices[0] == v {
            edge.range.0
        } else {
            edge.range.1
        };
        let tangent = crate::geom::eval_curve(&edge.curve, t)
            .d1
            .normalize_or_zero();
        let fan: Vec<DVec3> = edge.faces.iter().filter_map(|&f| inward(f)).collect();
        let in_fan = match fan[..] {
            [a, b] => a.angle_between(d) + d.angle_between(b) <= a.angle_between(b) + IN_CONE_RAD,
            _ => false,
        };
        if in_fan && tangent.dot(d).abs() <= IN_CONE_RAD {
            out.push(Element::Edge(e));
        }
    }
    for f in faces {
        if inward(f).is_some_and(|n| n.angle_between(d) <= IN_CONE_RAD) {
            out.push(Element::Face(f));
        }
    }
    out
}

/// Loops (components of paired arcs, complete when every end is paired) by sheet, and the
/// solids with incomplete loops. The arcs of one loop bound one sheet, so the segment pairs
/// ("pieces") along them are pieces of that sheet; loops that share a piece bound the same
/// sheet (a plate's outline and the closed seam round a hole through it, both on the top
/// and the bottom). Loops of one pair of segment groups with no piece in common are
/// different sheets (round a box standing on a plate, the four sheets between its top and
/// each wall).
pub(super) type LoopsBySheet = BTreeMap<(usize, usize), Vec<Vec<usize>>>;
pub(super) fn loops_by_sheet(
    arcs: &[Arc],
    uf: &mut UnionFind,
    paired: &[[bool; 2]],
    feet: &Feet,
) -> (LoopsBySheet, BTreeSet<usize>) {
    let mut components: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for k in 0..arcs.len() {
        components.entry(uf.find(k)).or_default().push(k);
    }
    let mut incomplete_solids = BTreeSet::new();
    let mut loops: Vec<Vec<usize>> = vec![];
    for (_, members) in components {
        let complete = members
            .iter()
            .all(|&k| arcs[k].closed || (paired[k][0] && paired[k][1]));
        if complete {
            loops.push(members);
        } else {
            incomplete_solids.insert(arcs[members[0]].solid);
        }
    }
    // Where nesting on a plane decides, the outer loop of each loop's sheet.
    let outer = feet.outer_loops(arcs, &loops);
    // Pieces, per solid, joined when one loop has both (for the other loops).
    let mut index: BTreeMap<(usize, [Element; 2]), usize> = BTreeMap::new();
    let mut pieces = UnionFind::new(0);
    let mut first_of_loop = vec![];
    for (members, outer) in loops.iter().zip(&outer) {
        if outer.is_some() {
            first_of_loop.push(None);
            continue;
        }
        let solid = arcs[members[0]].solid;
        let mut first = None;
        for &k in members {
            for &p in &arcs[k].pieces {
                let id = *index.entry((solid, p)).or_insert_with(|| pieces.add());
                match first {
                    None => first = Some(id),
                    Some(f) => pieces.union(f, id),
                }
            }
        }
        first_of_loop.push(first);
    }
    let n_pieces = index.len();
    let mut by_sheet: LoopsBySheet = BTreeMap::new();
    for (k, (members, first)) in loops.iter().zip(first_of_loop).enumerate() {
        let solid = arcs[members[0]].solid;
        // An arc always has a piece (its own pair); a loop without one is its own sheet.
        let sheet = match (outer[k], first) {
            (Some(o), _) => n_pieces + o,
            (None, Some(f)) => pieces.find(f),
            (None, None) => n_pieces + k,
        };
        by_sheet
            .entry((solid, sheet))
            .or_default()
            .push(order_loop(arcs, members));
    }

    (by_sheet, incomplete_solids)
}

/// The foot points of sheet boundaries on a plane that is a segment group by itself, for
/// telling which loops of one group pair bound one sheet.
pub(super) struct Feet<'a> {
    pub(super) model: &'a Model,
    pub(super) mat: &'a MedialAxis,
    pub(super) groups: &'a SegmentGroups,
}

/// Rim arcs are followed on the plane at this many points.
const RIM_FOOT_POINTS: usize = 17;

impl Feet<'_> {
    /// For each loop (index into `loops`), the outer loop of its sheet where nesting on a
    /// plane decides it: where one side of a group pair is a single plane, every ball of a
    /// sheet of that pair touches it, and the sheet's loops are closed curves of touch points
    /// there that bound the region its balls touch. Where those curves are apart, a loop
    /// inside an even number of the others bounds a sheet of its own (its outer loop), and a
    /// loop inside an odd number is a hole of the smallest of them. So round a shallow
    /// pocket the sheet of the plate's top and the pocket's walls and floor rim is an
    /// annulus (the rims at the pocket's edge inside the seam that closes round it), and a
    /// block's middle sheet between its top and bottom, cut in two by the ring of seams
    /// round a hole through it, is two sheets with the same two faces.
    fn outer_loops(&self, arcs: &[Arc], loops: &[Vec<usize>]) -> Vec<Option<usize>> {
        let mut out = vec![None; loops.len()];
        let mut by_pair: BTreeMap<(usize, [usize; 2]), Vec<usize>> = BTreeMap::new();
        for (k, members) in loops.iter().enumerate() {
            let a = &arcs[members[0]];
            by_pair.entry((a.solid, a.groups)).or_default().push(k);
        }
        for ((_, groups), list) in by_pair {
            if list.len() < 2 {
                continue;
            }
            let Some((face, frame)) = groups.iter().find_map(|&g| self.single_plane(g)) else {
                continue;
            };
            let curves: Vec<Vec<DVec2>> = list
                .iter()
                .map(|&k| self.curve(arcs, &loops[k], face, frame))
                .collect();
            if curves.iter().any(|c| c.len() < 3) {
                continue;
            }
            let tol = ON_CURVE_REL_DIAGONAL * self.model.diagonal();
            let n = list.len();
            let boxes: Vec<(DVec2, DVec2)> = curves.iter().map(|c| bounds(c, tol)).collect();
            let overlap = |a: usize, b: usize| {
                let ((lo_a, hi_a), (lo_b, hi_b)) = (boxes[a], boxes[b]);
                lo_a.cmple(hi_b).all() && lo_b.cmple(hi_a).all()
            };
            // Two loops on one curve (the two sides of a seam, each bounding a sheet of this
            // pair) have their sheets on either side of it: nesting does not tell them
            // apart, and the pieces decide.
            let touching = (0..n).any(|a| {
                (a + 1..n).any(|b| {
                    overlap(a, b) && curves[a].iter().any(|&p| on_polyline(p, &curves[b], tol))
                })
            });
            if touching {
                continue;
            }
            let inside: Vec<Vec<bool>> = (0..n)
                .map(|a| {
                    (0..n)
                        .map(|b| a != b && overlap(a, b) && contained(&curves[a], &curves[b], tol))
                        .collect()
                })
                .collect();
            let depth: Vec<usize> = (0..n)
                .map(|a| (0..n).filter(|&b| inside[a][b]).count())
                .collect();
            let parent = |a: usize| (0..n).find(|&b| inside[a][b] && depth[b] + 1 == depth[a]);
            // Every hole inside an outer loop, or nesting is not consistent: the pieces decide.
            if (0..n).any(|a| !depth[a].is_multiple_of(2) && parent(a).is_none()) {
                continue;
            }
            for a in 0..n {
                let o = if depth[a].is_multiple_of(2) {
                    a
                } else {
                    parent(a).unwrap_or(a)
                };
                out[list[a]] = Some(list[o]);
            }
        }
        out
    }

    /// The face of group `g` when it is the group's only face and a plane, with the plane's
    /// frame.
    fn single_plane(&self, g: usize) -> Option<(usize, (DVec3, DVec3, DVec3))> {
        let mut faces =
            (0..self.model.faces.len()).filter(|&f| self.groups.of(Element::Face(f)) == g);
        let f = faces.next()?;
        if faces.next().is_some() {
            return None;
        }
        crate::geom::project::plane_frame(&self.model.faces[f].surface).map(|frame| (f, frame))
    }

    /// The loop's touch points on the plane (face `face`), in loop order, in the plane's
    /// coordinates.
    fn curve(
        &self,
        arcs: &[Arc],
        members: &[usize],
        face: usize,
        frame: (DVec3, DVec3, DVec3),
    ) -> Vec<DVec2> {
        let order = order_loop(arcs, members);
        let g = self.groups.of(Element::Face(face));
        let mut out: Vec<DVec3> = vec![];
        let mut at: Option<Place> = None;
        for (n, &k) in order.iter().enumerate() {
            let arc = &arcs[k];
            let place = |end: usize| arc.ends[end].map(|(p, _)| p);
            // Forward when it starts where the last one ended (the first: when it ends
            // where the next one starts or ends).
            let forward = match at {
                Some(p) => place(0) == Some(p),
                None => order.get(n + 1).is_none_or(|&next| {
                    let other = &arcs[next];
                    other
                        .ends
                        .iter()
                        .flatten()
                        .any(|(p, _)| Some(*p) == place(1))
                }),
            };
            let mut points = self.arc_points(arc, g);
            if !forward {
                points.reverse();
            }
            out.extend(points);
            at = if forward { place(1) } else { place(0) };
        }
        let (o, a, b) = frame;
        out.iter()
            .map(|p| {
                let (u, v) = crate::geom::project::project_plane((o, a, b), *p);
                DVec2::new(u, v)
            })
            .collect()
    }

    /// An arc's touch points on group `g`'s side, from its start to its end.
    fn arc_points(&self, arc: &Arc, g: usize) -> Vec<DVec3> {
        match (arc.element, arc.slots) {
            (BoundaryRef::Seam(_), Some((n, [i, j]))) => {
                let Some(s) = self.mat.seams.get(n) else {
                    return vec![];
                };
                let slot = match s.segments.get(i) {
                    Some(e) if self.groups.of(*e) == g => i,
                    _ => j,
                };
                s.points
                    .iter()
                    .filter_map(|p| p.touch.get(slot).map(|t| DVec3::from_array(*t)))
                    .collect()
            }
            (BoundaryRef::Edge(e), _) => {
                let Some(edge) = self.model.edges.get(e) else {
                    return vec![];
                };
                let m = RIM_FOOT_POINTS - 1;
                (0..=m)
                    .map(|k| {
                        let t = edge.range.0 + (edge.range.1 - edge.range.0) * k as f64 / m as f64;
                        crate::geom::eval_curve(&edge.curve, t).p
                    })
                    .collect()
            }
            (BoundaryRef::Skeletal(k), _) => self
                .mat
                .skeletal_edges
                .get(k)
                .and_then(|k| self.model.vertices.get(k.vertex))
                .map(|v| vec![v.point])
                .unwrap_or_default(),
            _ => vec![],
        }
    }
}

/// A point closer than this to a curve (over the diagonal) is on it, for [`contained`]: two
/// loops that share a seam share its touch points exactly.
const ON_CURVE_REL_DIAGONAL: f64 = 1e-7;

/// True when closed curve `a` lies inside closed curve `b`: each point of `a` not on `b` (to
/// `tol`) inside it by the even–odd rule, and at least one such point.
fn contained(a: &[DVec2], b: &[DVec2], tol: f64) -> bool {
    if b.len() < 3 {
        return false;
    }
    let mut tested = 0;
    for &p in a {
        if on_polyline(p, b, tol) {
            continue;
        }
        if !inside_polygon(p, b) {
            return false;
        }
        tested += 1;
    }
    tested > 0
}

/// The bounding box of `points`, grown by `tol`.
fn bounds(points: &[DVec2], tol: f64) -> (DVec2, DVec2) {
    let lo = points
        .iter()
        .fold(DVec2::splat(f64::INFINITY), |a, p| a.min(*p));
    let hi = points
        .iter()
        .fold(DVec2::splat(f64::NEG_INFINITY), |a, p| a.max(*p));
    (lo - tol, hi + tol)
}

fn on_polyline(p: DVec2, poly: &[DVec2], tol: f64) -> bool {
    (0..poly.len()).any(|k| {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + ab * t).distance(p) <= tol
    })
}

/// Even–odd rule.
fn inside_polygon(p: DVec2, poly: &[DVec2]) -> bool {
    let mut inside = false;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > p.x {
                inside = !inside;
            }
        }
    }
    inside
}
