//! The arcs of sheet boundaries (`docs/design.md`, sheets, step 1): three per seam (one per
//! pair of its touch slots; a non-generic seam's, one per pair of neighbouring slots), one
//! per rim (a convex edge between two faces), one per skeletal edge, one per round's axis (a
//! degenerate curve touching a round along an arc), each with the places its ends are at and
//! the segment pairs along it.

use crate::classify::{Classification, EdgeKind};
use crate::medial::axis::{MedialAxis, Node, Seam, SeamEnd, SeamPoint};
use crate::medial::segments::SegmentGroups;
use crate::model::{Element, Model};
use glam::DVec3;
use serde::Serialize;
use std::collections::{BTreeSet, HashMap};

/// Where arcs end: a node of the graph, the ball where seams end at a skeletal edge, or a
/// ball where degenerate curves touching along an arc end (see [`ball_places`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Place {
    Node(Node),
    /// The ball where skeletal edge `k` starts (the seams ending there end at it).
    Skeletal(usize),
    /// The `k`-th ball where a degenerate curve touching along an arc ends (a fillet's axis
    /// where it meets the next round or the corner sphere of a filleted box), with the seams
    /// that end at a curvature limit or a pinch at that ball.
    Ball(usize),
}

/// One element of a sheet's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryRef {
    /// A seam (by id).
    Seam(usize),
    /// A convex edge of the model: the sheet's rim.
    Edge(usize),
    /// A skeletal edge (by id): the sheet's free edge.
    Skeletal(usize),
    /// A degenerate curve (by its index in `mat.degenerate`) whose balls touch a round along
    /// an arc: the axis along which the sheet of the faces either side of the round ends.
    Degenerate(usize),
}

/// An arc: one side of a seam, a rim, a skeletal edge, or a round's axis.
pub(super) struct Arc {
    pub(super) element: BoundaryRef,
    pub(super) solid: usize,
    /// The segment pair at each end (exact elements) and the group pair.
    pub(super) ends: [Option<(Place, [Element; 2])>; 2],
    pub(super) groups: [usize; 2],
    /// A closed seam's side: a loop by itself.
    pub(super) closed: bool,
    /// The segment pair where the arc starts (a closed seam's side has no node to name it).
    pub(super) pair: [Element; 2],
    /// A seam's side: its two touch points at each end (which contacts of a junction it
    /// runs between, where one element is touched there twice).
    pub(super) touch: [Option<[DVec3; 2]>; 2],
    /// Every segment pair of the sheet next to it along the arc (a touch point handed over
    /// changes it), and at its end balls (see `which::add_witnesses`): pieces of one sheet.
    pub(super) pieces: Vec<[Element; 2]>,
    /// A seam's side: the seam's index and the two touch slots.
    pub(super) slots: Option<(usize, [usize; 2])>,
    /// A round's axis: the round (the faces its balls osculate), whose sides are `pair`.
    pub(super) round: Vec<Element>,
}

impl Arc {
    /// A rim or a skeletal edge: one segment pair from end to end, no touch points.
    fn between(
        element: BoundaryRef,
        solid: usize,
        ends: [Place; 2],
        [a, b]: [Element; 2],
        groups: &SegmentGroups,
    ) -> Arc {
        let pair = sorted_pair(a, b);
        Arc {
            element,
            solid,
            ends: ends.map(|p| Some((p, pair))),
            groups: group_pair(groups, a, b),
            closed: false,
            pair,
            touch: [None, None],
            pieces: vec![pair],
            slots: None,
            round: vec![],
        }
    }
}

/// The groups of `a` and `b`, smaller first: the sheet's name up to which loops bound it.
fn group_pair(groups: &SegmentGroups, a: Element, b: Element) -> [usize; 2] {
    let (g, h) = (groups.of(a), groups.of(b));
    [g.min(h), g.max(h)]
}

/// The ball each seam end a skeletal edge starts from is: `[seam, end]` → place, named by the
/// first skeletal edge starting there (two start at a ball of four contacts whose touch
/// points meet in two pairs, each at its vertex). (Other
/// pinches are not nodes yet: where two seams end at one, on segments of different groups,
/// the sheets round it are not paired there; the count is withheld.)
pub(super) fn end_balls(mat: &MedialAxis) -> HashMap<[usize; 2], Place> {
    let mut out = HashMap::new();
    for k in &mat.skeletal_edges {
        for start in &k.starts {
            out.entry(*start).or_insert(Place::Skeletal(k.id));
        }
    }
    out
}

/// The pairs of touch slots of a seam with `k` slots that a sheet lies between: all three
/// pairs of a generic seam; where more elements touch each ball (`k > 3`, a non-generic seam:
/// the touch points lie on one circle round the seam, its slots in their order round it), the
/// neighbours round that circle — the sides of the polygon of touch points, not its
/// diagonals.
fn slot_pairs(k: usize) -> Vec<(usize, usize)> {
    match k {
        0..=2 => vec![],
        3 => vec![(0, 1), (1, 2), (0, 2)],
        _ => (0..k).map(|i| (i, (i + 1) % k)).collect(),
    }
}

/// The arcs of every seam (one per pair of its touch slots that a sheet lies between:
/// [`slot_pairs`]).
pub(super) fn seam_arcs(
    mat: &MedialAxis,
    groups: &SegmentGroups,
    balls: &HashMap<[usize; 2], Place>,
) -> Vec<Arc> {
    let mut arcs: Vec<Arc> = vec![];
    for (n, s) in mat.seams.iter().enumerate() {
        let closed = s.ends.iter().all(|e| matches!(e, SeamEnd::Closed));
        let place = |end: usize| {
            s.ends[end]
                .node()
                .map(Place::Node)
                .or_else(|| balls.get(&[n, end]).copied())
        };
        for (i, j) in slot_pairs(s.segments.len()) {
            let pair = |segs: &[Element]| match (segs.get(i), segs.get(j)) {
                (Some(a), Some(b)) => Some(sorted_pair(*a, *b)),
                _ => None,
            };
            let start = place(0).zip(pair(&s.segments));
            let end = place(1).zip(pair(&s.end_segments));
            let touch = |p: Option<&SeamPoint>| {
                p.map(|p| [DVec3::from_array(p.touch[i]), DVec3::from_array(p.touch[j])])
            };
            arcs.push(Arc {
                element: BoundaryRef::Seam(s.id),
                solid: s.solid,
                ends: [start, end],
                groups: group_pair(groups, s.segments[i], s.segments[j]),
                closed,
                pair: sorted_pair(s.segments[i], s.segments[j]),
                touch: [touch(s.points.first()), touch(s.points.last())],
                pieces: pairs_along(s, i, j),
                slots: Some((n, [i, j])),
                round: vec![],
            });
        }
    }
    arcs
}

/// The segment pairs of slots `i` and `j` along seam `s`, from its first point through each
/// hand-over to its last.
pub(super) fn pairs_along(s: &Seam, i: usize, j: usize) -> Vec<[Element; 2]> {
    let mut slots = s.segments.clone();
    let mut out = vec![];
    let mut push = |slots: &[Element]| {
        if let (Some(a), Some(b)) = (slots.get(i), slots.get(j)) {
            let p = sorted_pair(*a, *b);
            if !out.contains(&p) {
                out.push(p);
            }
        }
    };
    push(&slots);
    for h in &s.handovers {
        if let Some(k) = slots.iter().position(|e| *e == h.from) {
            slots[k] = h.to;
            push(&slots);
        }
    }
    push(&s.end_segments);
    out
}

/// Adds the rims (convex edges between two faces, and the smooth edges in `kinks`) to
/// `arcs`; returns the solids with mixed edges.
pub(super) fn add_rims(
    model: &Model,
    class: &Classification,
    groups: &SegmentGroups,
    kinks: &BTreeSet<usize>,
    arcs: &mut Vec<Arc>,
) -> BTreeSet<usize> {
    let mut mixed = BTreeSet::new();
    for (e, edge) in model.edges.iter().enumerate() {
        let rim = class.edges[e].kind == EdgeKind::Convex || kinks.contains(&e);
        match class.edges[e].kind {
            _ if rim && edge.faces.len() == 2 && edge.faces[0] != edge.faces[1] => {
                let pair = [Element::Face(edge.faces[0]), Element::Face(edge.faces[1])];
                arcs.push(Arc::between(
                    BoundaryRef::Edge(e),
                    model.solid_of_face(edge.faces[0]),
                    edge.vertices.map(|v| Place::Node(Node::Vertex(v))),
                    pair,
                    groups,
                ));
            }
            EdgeKind::Mixed => {
                mixed.insert(model.solid_of_face(edge.faces[0]));
            }
            _ => {}
        }
    }

    mixed
}

/// The smooth edges that are a sheet's rim all the same: faces meeting at a convex angle
/// below the angle tolerance (a wall written as two B-splines with a 0.4° kink between them)
/// are one smooth surface to the classification, but exact tracing finds the sheet between
/// them where a seam ends at the edge's vertex (`r = 0`) touching both. The edges at whose
/// vertices that happens.
pub(super) fn convex_kinks(
    model: &Model,
    class: &Classification,
    mat: &MedialAxis,
) -> BTreeSet<usize> {
    // The smooth edges between two faces at each vertex.
    let mut smooth_at: HashMap<usize, Vec<usize>> = HashMap::new();
    for (e, edge) in model.edges.iter().enumerate() {
        if class.edges[e].kind == EdgeKind::Smooth
            && edge.faces.len() == 2
            && edge.faces[0] != edge.faces[1]
        {
            for &v in &edge.vertices {
                smooth_at.entry(v).or_default().push(e);
            }
        }
    }
    let mut kinks = BTreeSet::new();
    for s in &mat.seams {
        for (end, how) in s.ends.iter().enumerate() {
            let SeamEnd::Vertex(v) = how else { continue };
            let (_, segs) = s.at_end(end);
            for &e in smooth_at.get(v).into_iter().flatten() {
                let faces = &model.edges[e].faces;
                if faces.iter().all(|&f| segs.contains(&Element::Face(f))) {
                    kinks.insert(e);
                }
            }
        }
    }
    kinks
}

/// Balls closer than this, over the diagonal, are one place of the graph: the ends of
/// degenerate curves and the seam ends at curvature limits there are each located to the
/// accuracy (1e-6 of the diagonal by default; on the filleted box they agree to 1.5e-7).
const SAME_BALL_REL_DIAGONAL: f64 = 1e-5;

/// The places of the balls where degenerate curves touching along an arc end, and of what
/// meets them there (see [`ball_places`]).
#[derive(Default)]
pub(super) struct BallPlaces {
    /// Seam ends at a curvature limit or a pinch at one of those balls: `[seam, end]` → place.
    pub(super) seam_ends: HashMap<[usize; 2], Place>,
    /// Each degenerate piece's two end places (`None` where not a place of the graph, and for
    /// curves that touch all round, which do not bound a sheet).
    pub(super) curve_ends: Vec<[Option<Place>; 2]>,
    /// Skeletal edges that start where a rim's sheet ends on rounds' axes, at one of those
    /// balls (a mitred corner of two rounds, where their axes meet): id → place.
    pub(super) skeletal_starts: HashMap<usize, Place>,
    /// The degenerate points at one of those balls (a filleted box's corner sphere's centre,
    /// where three rounds' axes and a seam end): a node, not a piece of its own.
    pub(super) points: BTreeSet<usize>,
}

/// The places where degenerate curves touching along an arc (fillets' axes) end: a junction
/// whose ball is theirs, a vertex where the ball vanishes, or a [`Place::Ball`] shared by the
/// curves ending at one ball; with the seam ends at a curvature limit or a pinch at such a
/// ball (not already at a skeletal edge's start: `skeletal`), and the degenerate points there.
/// An inner box's medial axis grown by the rounds' radius is a filleted box's: the rounds'
/// axes are the inner box's rims, the corner spheres' centres its vertices, where its seams
/// end.
pub(super) fn ball_places(
    model: &Model,
    mat: &MedialAxis,
    skeletal: &HashMap<[usize; 2], Place>,
) -> BallPlaces {
    use crate::medial::axis::DegenerateEnd;
    use crate::medial::DegenerateKind;
    let tol = SAME_BALL_REL_DIAGONAL * model.diagonal();
    let centre = |b: &[f64; 4]| DVec3::new(b[0], b[1], b[2]);
    let mut balls: Vec<DVec3> = vec![];
    // A curve's end: the junction there, or the ball of the curves ending there. What ends
    // at a curvature limit, or starts, at such a ball: that ball (a seam ending beside a
    // junction at its own curvature limit does not end at the junction).
    let mut place_of = |c: DVec3, curve_end: bool| -> Option<Place> {
        if let Some(j) = mat
            .junctions
            .iter()
            .find(|j| curve_end && DVec3::from_array(j.point).distance(c) <= tol)
        {
            return Some(Place::Node(Node::Junction(j.id)));
        }
        if let Some(k) = balls.iter().position(|b| b.distance(c) <= tol) {
            return Some(Place::Ball(k));
        }
        curve_end.then(|| {
            balls.push(c);
            Place::Ball(balls.len() - 1)
        })
    };
    let mut out = BallPlaces::default();
    for d in &mat.degenerate {
        let mut ends = [None, None];
        if d.kind == DegenerateKind::Curve && !d.around && d.ends.len() == 2 {
            for (i, end) in d.ends.iter().enumerate() {
                let ball = if i == 0 {
                    d.balls.first()
                } else {
                    d.balls.last()
                };
                ends[i] = match (end, ball) {
                    (DegenerateEnd::Vanishes { vertex }, _) => {
                        Some(Place::Node(Node::Vertex(*vertex)))
                    }
                    (DegenerateEnd::Meets { .. } | DegenerateEnd::Shrinks { .. }, Some(b)) => {
                        place_of(centre(b), true)
                    }
                    _ => None,
                };
            }
        }
        out.curve_ends.push(ends);
    }
    for (n, s) in mat.seams.iter().enumerate() {
        for end in 0..2 {
            if skeletal.contains_key(&[n, end])
                || !matches!(
                    s.ends[end],
                    SeamEnd::CurvatureLimit { .. } | SeamEnd::Pinch { .. }
                )
            {
                continue;
            }
            let (Some(p), _) = s.at_end(end) else {
                continue;
            };
            if let Some(place) = place_of(centre(&p.point), false) {
                out.seam_ends.insert([n, end], place);
            }
        }
    }
    for k in &mat.skeletal_edges {
        if !k.starts.is_empty() || k.meets.is_empty() {
            continue;
        }
        if let Some(place) = k.balls.first().and_then(|b| place_of(centre(b), false)) {
            out.skeletal_starts.insert(k.id, place);
        }
    }
    for (k, d) in mat.degenerate.iter().enumerate() {
        if d.kind == DegenerateKind::Point
            && d.balls
                .first()
                .is_some_and(|b| place_of(centre(b), false).is_some())
        {
            out.points.insert(k);
        }
    }
    out
}

/// Adds the degenerate curves that touch along an arc (a fillet's axis) to `arcs`, each a
/// free edge of the sheet of the two faces its round joins (the faces either side of the
/// arc of contact, tangent to the balls there), from its place at one end to the other
/// (`ends`, from [`ball_places`]). Returns the curves added. A curve whose ends are not
/// both places, or whose two sides are not found, is left out (and the count withheld).
pub(super) fn add_degenerate(
    model: &Model,
    class: &Classification,
    mat: &MedialAxis,
    groups: &SegmentGroups,
    ends: &[[Option<Place>; 2]],
    arcs: &mut Vec<Arc>,
) -> BTreeSet<usize> {
    use crate::medial::DegenerateKind;
    let mut added = BTreeSet::new();
    for (k, d) in mat.degenerate.iter().enumerate() {
        if d.kind != DegenerateKind::Curve || d.around {
            continue;
        }
        // (A closed one, a ring's beaded rim, is a loop by itself with no node to tell which
        // sheet it bounds: its sheet's other loops are named by other segments, and the
        // pieces would count them as sheets of their own. Left out.)
        let Some([Some(a), Some(b)]) = ends.get(k) else {
            continue;
        };
        let Some((round, pair)) = round_sides(model, class, d) else {
            continue;
        };
        let mut arc = Arc::between(BoundaryRef::Degenerate(k), d.solid, [*a, *b], pair, groups);
        arc.round = round;
        arcs.push(arc);
        added.insert(k);
    }
    added
}

/// A round's curvature across is `1/r` to this, relative, at its axis's balls.
const ROUND_CURVATURE_REL: f64 = 1e-3;

/// The two sides of a round, either side of the arc its degenerate curve `d`'s balls touch
/// it along: the faces across its smooth edges whose surfaces the curve's middle ball is
/// tangent to, and its reflex edges the ball touches (each at the distance `r` from its
/// centre, to [`SAME_BALL_REL_DIAGONAL`] of the diagonal). The round is the faces of the
/// curve's segments the ball osculates (curvature across `1/r`). The round's faces and the
/// two sides; `None` unless there are exactly two sides.
fn round_sides(
    model: &Model,
    class: &Classification,
    d: &crate::medial::Degenerate,
) -> Option<(Vec<Element>, [Element; 2])> {
    let b = d.balls.get(d.balls.len() / 2)?;
    let (c, r) = (DVec3::new(b[0], b[1], b[2]), b[3]);
    let tol = SAME_BALL_REL_DIAGONAL * model.diagonal();
    // The foot of the centre on face `f`'s surface: its distance, and the surface there.
    let foot = |f: usize| {
        let (u, v) = crate::geom::project::project_point(&model.faces[f].surface, c, None)?;
        let at = crate::geom::eval_face(&model.faces[f], u, v);
        Some((at.p.distance(c), at))
    };
    // The round: the faces of its segments the middle ball osculates (a face the curve's
    // touch point was handed to at the arc's end, the plane beside the round, is a side).
    let faces = || {
        d.segments.iter().filter_map(|e| match e {
            Element::Face(f) => Some(*f),
            _ => None,
        })
    };
    let osculated = |f: usize| {
        foot(f).is_some_and(|(dist, at)| {
            (dist - r).abs() <= tol
                && crate::geom::principal_curvatures(&at, model.faces[f].sign)
                    .is_some_and(|k| (k.k1 * r - 1.0).abs() <= ROUND_CURVATURE_REL)
        })
    };
    let mut on: BTreeSet<usize> = faces().filter(|&f| osculated(f)).collect();
    if on.is_empty() {
        on = faces().collect();
    }
    let mut sides: Vec<Element> = vec![];
    for (e, edge) in model.edges.iter().enumerate() {
        if edge.faces.len() != 2 || !edge.faces.iter().any(|f| on.contains(f)) {
            continue;
        }
        match class.edges[e].kind {
            // The arc of contact ends where the round meets a face tangent to it.
            EdgeKind::Smooth => {
                for &x in &edge.faces {
                    let side = Element::Face(x);
                    if !on.contains(&x)
                        && !sides.contains(&side)
                        && foot(x).is_some_and(|(dist, _)| (dist - r).abs() <= tol)
                    {
                        sides.push(side);
                    }
                }
            }
            // Or at a reflex edge of the round's that the ball touches (a bead on a ring's
            // rim, its arc of contact ending in the groove at its foot).
            EdgeKind::Reflex => {
                let (_, _, dist) = crate::geom::distance::nearest_on_edge(model, e, c, None);
                if (dist - r).abs() <= tol && !sides.contains(&Element::Edge(e)) {
                    sides.push(Element::Edge(e));
                }
            }
            _ => {}
        }
    }
    match sides[..] {
        [x, y] => Some((
            on.iter().map(|&f| Element::Face(f)).collect(),
            sorted_pair(x, y),
        )),
        _ => None,
    }
}

/// Adds the skeletal edges to `arcs`: each runs from its ball to its vertex, on its pair.
/// A free edge that starts on degenerate curves (where a rim's sheet ends, up to the rounds'
/// axes: `meets`) starts at the place where those curves end (`starts`, from
/// [`ball_places`]); inside a curve it has no node (the curve is not split there yet).
pub(super) fn add_skeletal(
    mat: &MedialAxis,
    groups: &SegmentGroups,
    balls: &HashMap<[usize; 2], Place>,
    starts: &HashMap<usize, Place>,
    arcs: &mut Vec<Arc>,
) {
    for k in &mat.skeletal_edges {
        let mut arc = Arc::between(
            BoundaryRef::Skeletal(k.id),
            k.solid,
            [Place::Skeletal(k.id), Place::Node(Node::Vertex(k.vertex))],
            k.segments,
            groups,
        );
        if let Some(start) = k.starts.first() {
            // The place of the seam end it starts at (where two start, the first's).
            if let Some(place) = balls.get(start) {
                arc.ends[0] = Some((*place, arc.pair));
            }
        } else if !k.meets.is_empty() {
            arc.ends[0] = starts.get(&k.id).map(|p| (*p, arc.pair));
        }
        arcs.push(arc);
    }
}

/// Orders a loop's arcs so consecutive arcs share a node (for the report; the count does not
/// depend on it).
pub(super) fn order_loop(arcs: &[Arc], members: &[usize]) -> Vec<usize> {
    if members.len() <= 2 {
        return members.to_vec();
    }
    let mut left: Vec<usize> = members.to_vec();
    let mut out = vec![left.remove(0)];
    let mut at = arcs[out[0]].ends[1].as_ref().map(|(n, _)| *n);
    while !left.is_empty() {
        let next = left
            .iter()
            .position(|&k| arcs[k].ends.iter().flatten().any(|(n, _)| Some(*n) == at));
        let Some(p) = next else {
            out.append(&mut left);
            break;
        };
        let k = left.remove(p);
        at = arcs[k]
            .ends
            .iter()
            .flatten()
            .map(|(n, _)| *n)
            .find(|n| Some(*n) != at)
            .or(at);
        out.push(k);
    }
    out
}

/// `[a, b]` in the order of their names (`F10` before `F2`), as reports have always listed a
/// sheet's pair.
pub(super) fn sorted_pair(a: Element, b: Element) -> [Element; 2] {
    if a.to_string() <= b.to_string() {
        [a, b]
    } else {
        [b, a]
    }
}
