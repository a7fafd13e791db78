//! The arcs of sheet boundaries (`docs/design.md`, sheets, step 1): three per seam (one per
//! pair of its touch slots; a non-generic seam's, one per pair of neighbouring slots), one per rim (a convex edge between two faces), one per skeletal
//! edge, each with the places its ends are at and the segment pairs along it.

use crate::classify::{Classification, EdgeKind};
use crate::medial::axis::{MedialAxis, Node, Seam, SeamEnd, SeamPoint};
use crate::medial::segments::SegmentGroups;
use crate::model::{Element, Model};
use glam::DVec3;
use serde::Serialize;
use std::collections::{BTreeSet, HashMap};

/// Where arcs end: a node of the graph, or the ball where seams end at a skeletal edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Place {
    Node(Node),
    /// The ball where skeletal edge `k` starts (the seams ending there end at it).
    Skeletal(usize),
}

/// One element of a sheet's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryRef {
    /// A seam (by id).
    Seam(usize),
    /// A convex edge of the model: the sheet's rim.
    Edge(usize),
    /// A skeletal edge (by id): the sheet's free edge.
    Skeletal(usize),
}

/// An arc: one side of a seam, a rim, or a skeletal edge.
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
        }
    }
}

/// The groups of `a` and `b`, smaller first: the sheet's name up to which loops bound it.
fn group_pair(groups: &SegmentGroups, a: Element, b: Element) -> [usize; 2] {
    let (g, h) = (groups.of(a), groups.of(b));
    [g.min(h), g.max(h)]
}

/// The ball each seam end a skeletal edge starts from is: `[seam, end]` → place. (Other
/// pinches are not nodes yet: where two seams end at one, on segments of different groups,
/// the sheets round it are not paired there; the count is withheld.)
pub(super) fn end_balls(mat: &MedialAxis) -> HashMap<[usize; 2], Place> {
    let mut out = HashMap::new();
    for k in &mat.skeletal_edges {
        for start in &k.starts {
            out.insert(*start, Place::Skeletal(k.id));
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

/// Adds the skeletal edges to `arcs`: each runs from its ball to its vertex, on its pair.
/// A free edge that starts on degenerate curves (where a rim's sheet ends, up to the rounds'
/// axes: `meets`) has no node there: degenerate curves are not in the graph yet.
pub(super) fn add_skeletal(mat: &MedialAxis, groups: &SegmentGroups, arcs: &mut Vec<Arc>) {
    for k in &mat.skeletal_edges {
        let mut arc = Arc::between(
            BoundaryRef::Skeletal(k.id),
            k.solid,
            [Place::Skeletal(k.id), Place::Node(Node::Vertex(k.vertex))],
            k.segments,
            groups,
        );
        if k.starts.is_empty() && !k.meets.is_empty() {
            arc.ends[0] = None;
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
