//! Sheets: the 2-dimensional pieces of the medial axis, found from their boundaries
//! (`docs/design.md`, sheets).
//!
//! A seam with touch triplet {a, b, c} bounds the three sheets {a, b}, {b, c}, {a, c}; a convex
//! edge between faces a and b is the *rim* of sheet {a, b} (balls of radius → 0 there); a
//! skeletal edge is a sheet's free edge, where the two touch points of its balls meet. So the
//! boundary of every sheet is a set of closed loops made of seam *sides*, rims and skeletal
//! edges, joined at junctions, vertices, and the balls where seams end at a pinch or at a
//! skeletal edge. This module walks them:
//!
//! 1. every seam gives three *arcs* (one per pair of its touch slots; a non-generic seam one
//!    per pair of neighbouring slots round it; a closed seam's arcs are loops on their own),
//!    every convex edge one, every skeletal edge one, every round's axis (a degenerate curve
//!    touching a round along an arc: where the sheet of the faces either side of the round
//!    ends) one;
//! 2. at each node (a junction, a vertex where seams end or rims meet, a seam's end ball, the
//!    ball where rounds' axes end) the
//!    arc ends are
//!    paired by the sheet they bound, named by the two *segment groups* touched: faces joined
//!    by smooth or reflex edges (with those edges and the reflex vertices between them) form
//!    one group, because a touch point moves across such an edge without the sheet ending
//!    (a fillet, a split face, the inner corner of an L). Where a group pair is ambiguous at
//!    a node (more than two arc ends), what is known there decides: at a vertex, the groups
//!    joined across the edges that end there only; at a junction, the two of its contacts
//!    an arc runs between; then the exact segment pair;
//! 3. paired arcs form loops, and the loops with the same group pair form one sheet.
//!
//! Counting then gives the medial axis's Euler characteristic `V − E + Σ χ(sheet)`, with
//! `χ = 2 − loops` for a sheet (a disc with holes). That assumes each sheet has genus 0 and
//! that loops of one group pair are one sheet; both hold for the reference parts (tests), and
//! the count is withheld, with the reason, wherever the boundary is incomplete: open seam
//! ends, curvature-limit ends whose skeletal edges are not traced (all but those at
//! vertices), degenerate pieces not in the graph, sheets round a ball where rounds' axes end
//! not told apart, or mixed edges. Curves that touch all round (a cylinder's axis) and
//! degenerate points are added by inclusion–exclusion.

mod arcs;
mod which;

use crate::classify::Classification;
use crate::medial::axis::{MedialAxis, Node, SeamEnd};
use crate::medial::segments::{SegmentGroups, UnionFind};
use crate::model::{Element, Model};
pub use arcs::BoundaryRef;
use arcs::{
    add_degenerate, add_rims, add_skeletal, ball_places, convex_kinks, end_balls, seam_arcs, Arc,
    BallPlaces, Place,
};
use glam::DVec3;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use which::{add_witnesses, loops_by_sheet, Feet};

/// Touch points of two arcs at a junction are the same contact when they lie this close, over
/// the model's bounding-box diagonal (both come from the junction's one solution).
const SAME_TOUCH_REL_DIAGONAL: f64 = 1e-7;

/// A sheet, named by two of the segments it touches, with its boundary.
#[derive(Clone, Debug, Serialize)]
pub struct Sheet {
    pub id: usize,
    pub solid: usize,
    /// Two segments whose touch points the sheet's balls have (where its first boundary arc
    /// starts; along the sheet the touch points may move onto neighbouring segments of the
    /// same group).
    pub segments: [Element; 2],
    /// Every seam, rim and skeletal edge on the boundary, in loop order.
    pub boundary: Vec<BoundaryRef>,
    /// The boundary as closed loops (a sheet with holes has several).
    pub loops: Vec<Vec<BoundaryRef>>,
}

/// Euler characteristics of one solid and of its medial axis.
#[derive(Clone, Debug, Serialize)]
pub struct SolidEuler {
    pub solid: usize,
    /// The solid's Euler characteristic: half its boundary's, `V − E + Σ(2 − loops)` over
    /// its faces (Euler–Poincaré). 1 for a ball, 1 − g for a solid with g through-holes.
    pub solid_euler: i64,
    /// `V − E + Σ χ(sheet)` of the medial axis, when its sheets are complete.
    pub mat_euler: Option<i64>,
    /// Nodes (junctions, the vertices seams, rims and skeletal edges end at, the balls where
    /// seams end at a pinch or a skeletal edge, and those where rounds' axes end), arcs
    /// (seams, rims, skeletal edges, rounds' axes) and sheets counted.
    pub nodes: usize,
    pub arcs: usize,
    pub sheets: usize,
    /// Why `mat_euler` is withheld.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unknown: Option<String>,
}

/// The sheets of a medial axis, the per-solid Euler characteristics, and arc ends that could
/// not be paired (with why).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Sheets {
    pub sheets: Vec<Sheet>,
    pub solids: Vec<SolidEuler>,
    pub unpaired: Vec<String>,
    /// Arc ends at a ball where rounds' axes end that could not be paired there by the
    /// segments they name: one sheet may be named by a round on one side and by the face
    /// beside it on the other (the ball touches both along one contact), so this is not a
    /// piece missing, but the sheets round that ball not told apart; the count is withheld.
    pub untold: Vec<String>,
}

/// Finds the sheets of `mat` and the Euler characteristics of each solid and its medial axis.
pub fn sheets(model: &Model, class: &Classification, mat: &MedialAxis) -> Sheets {
    let groups = SegmentGroups::new(model, class);
    let mut balls = end_balls(mat);
    let places = ball_places(model, mat, &balls);
    balls.extend(places.seam_ends.iter().map(|(k, p)| (*k, *p)));
    let mut arcs = seam_arcs(mat, &groups, &balls);
    let kinks = convex_kinks(model, class, mat);
    let mixed = add_rims(model, class, &groups, &kinks, &mut arcs);
    add_skeletal(mat, &groups, &balls, &places.skeletal_starts, &mut arcs);
    let fillets = add_degenerate(model, class, mat, &groups, &places.curve_ends, &mut arcs);
    add_witnesses(model, class, mat, &balls, &mut arcs);
    // Elements a junction touches in two places.
    let twice: BTreeSet<(Place, Element)> = mat
        .junctions
        .iter()
        .flat_map(|j| {
            let segs = &j.segments;
            (0..segs.len())
                .filter(move |&k| segs[..k].contains(&segs[k]))
                .map(move |k| (Place::Node(Node::Junction(j.id)), segs[k]))
        })
        .collect();
    let tol = SAME_TOUCH_REL_DIAGONAL * model.diagonal();
    let mut edges_at = vec![vec![]; model.vertices.len()];
    for (e, edge) in model.edges.iter().enumerate() {
        for &v in &edge.vertices {
            edges_at[v].push(e);
        }
    }
    let near = |v: usize| Some(groups_at_vertex(model, class, v, &edges_at[v]));
    let contacts: BTreeMap<Place, Vec<DVec3>> = mat
        .junctions
        .iter()
        .map(|j| {
            let touch = j.touch.iter().map(|t| DVec3::from_array(*t)).collect();
            (Place::Node(Node::Junction(j.id)), touch)
        })
        .collect();
    let (mut uf, paired, unpaired, untold) = pair_ends(&arcs, &twice, tol, &near, &contacts);
    let feet = Feet {
        model,
        mat,
        groups: &groups,
    };
    let (by_sheet, incomplete) = loops_by_sheet(&arcs, &mut uf, &paired, &feet);
    let mut out = Sheets {
        unpaired,
        untold: untold.iter().map(|(_, u)| u.clone()).collect(),
        ..Default::default()
    };
    let untold_solids: BTreeSet<usize> = untold.iter().map(|(s, _)| *s).collect();
    for ((solid, _), loops) in by_sheet {
        let first = &arcs[loops[0][0]];
        let segments = first.pair;
        let loops: Vec<Vec<BoundaryRef>> = loops
            .iter()
            .map(|l| l.iter().map(|&k| arcs[k].element).collect())
            .collect();
        out.sheets.push(Sheet {
            id: out.sheets.len(),
            solid,
            segments,
            boundary: loops.concat(),
            loops,
        });
    }

    let graph = Graph {
        arcs: &arcs,
        sheets: &out.sheets,
        mixed: &mixed,
        incomplete: &incomplete,
        places: &places,
        fillets: &fillets,
        untold: &untold_solids,
    };
    let solids = (0..model.solids.len())
        .map(|solid| solid_and_axis_euler(model, mat, &graph, solid))
        .collect();
    out.solids = solids;
    out
}

/// Pairs the arc ends at each node by group pair, then (where that is ambiguous) at a vertex
/// by the groups there (`near`), at a junction by the two of its `contacts` the arcs' touch
/// points are at (equal to `tol`), then by segment pair, then (where one element is touched
/// twice there, so that two sheets share a segment pair) by the touch points the arcs run
/// between: the union of paired arcs, which ends are paired, and the ends that could not be
/// (at a ball where rounds' axes end, apart, with their solid: see [`Sheets::untold`]).
fn pair_ends(
    arcs: &[Arc],
    twice: &BTreeSet<(Place, Element)>,
    tol: f64,
    near: &dyn Fn(usize) -> Option<LocalGroups>,
    contacts: &BTreeMap<Place, Vec<DVec3>>,
) -> PairedEnds {
    let mut at: BTreeMap<Place, Vec<(usize, usize)>> = BTreeMap::new();
    for (k, arc) in arcs.iter().enumerate() {
        for (end, e) in arc.ends.iter().enumerate() {
            if let Some((node, _)) = e {
                at.entry(*node).or_default().push((k, end));
            }
        }
    }
    let mut out = Pairing {
        uf: UnionFind::new(arcs.len()),
        paired: vec![[false; 2]; arcs.len()],
        unpaired: vec![],
        untold: vec![],
    };
    for (node, ends) in &at {
        if let Some(pairs) = at_skeletal_ball(arcs, *node, ends) {
            for [(k1, e1), (k2, e2)] in pairs {
                out.uf.union(k1, k2);
                out.paired[k1][e1] = true;
                out.paired[k2][e2] = true;
            }
            continue;
        }
        let mut by_group: BTreeMap<[usize; 2], Vec<(usize, usize)>> = BTreeMap::new();
        for &(k, end) in ends {
            by_group.entry(arcs[k].groups).or_default().push((k, end));
        }
        // Ambiguous by groups: first by what tells sheets apart at this node. At a vertex,
        // the groups as they are there (a touch point moves on across the smooth and reflex
        // edges that end there only); at a junction, the two of its contacts an arc's touch
        // points are at (one sheet lies between each two; an element named differently by
        // two seams, a face and its edge where the ball touches the face at that edge, is
        // one contact).
        // (The vertex's groups are built only where some list is ambiguous.)
        let ambiguous = by_group.values().any(|list| list.len() > 2);
        let local = match node {
            Place::Node(Node::Vertex(v)) if ambiguous => near(*v),
            _ => None,
        };
        let at_junction = match node {
            Place::Node(Node::Junction(_)) => contacts.get(node),
            _ => None,
        };
        let key = |k: usize, end: usize| -> Option<[usize; 2]> {
            let mut key = if let Some(g) = &local {
                arcs[k].ends[end].as_ref()?.1.map(g)
            } else {
                let contacts = at_junction?;
                let slot = |t: DVec3| contacts.iter().position(|c| c.distance(t) <= tol);
                let [a, b] = arcs[k].touch[end]?;
                [slot(a)?, slot(b)?]
            };
            key.sort_unstable();
            Some(key)
        };
        for (_, list) in by_group {
            let keys: Option<Vec<[usize; 2]>> = if list.len() > 2 {
                list.iter().map(|&(k, end)| key(k, end)).collect()
            } else {
                None
            };
            let lists = match keys {
                Some(keys) => {
                    let mut by_key: BTreeMap<[usize; 2], Vec<(usize, usize)>> = BTreeMap::new();
                    for (e, key) in list.into_iter().zip(keys) {
                        by_key.entry(key).or_default().push(e);
                    }
                    by_key.into_values().collect()
                }
                _ => vec![list],
            };
            for list in lists {
                pair_list(arcs, twice, tol, *node, list, &mut out);
            }
        }
    }

    (out.uf, out.paired, out.unpaired, out.untold)
}

/// What [`pair_ends`] finds: the union of paired arcs, which ends are paired, the ends that
/// could not be, and those at balls where rounds' axes end (with their solid).
type PairedEnds = (UnionFind, Vec<[bool; 2]>, Vec<String>, Vec<(usize, String)>);

/// The group of each element as the groups are at one vertex (see [`groups_at_vertex`]).
type LocalGroups = Box<dyn Fn(Element) -> usize>;

/// The segment groups as they are near vertex `v` (whose edges are `edges`): faces joined
/// only across the smooth and reflex edges that end at `v`, with those reflex edges and `v`.
/// Two elements of one group far apart may be in different groups here (the top face and a
/// nut pocket's walls, joined elsewhere, meet at `v` only across the reflex edge between the
/// walls); elements that do not reach `v` are each a group of their own.
fn groups_at_vertex(
    model: &Model,
    class: &Classification,
    v: usize,
    edges: &[usize],
) -> LocalGroups {
    use crate::classify::EdgeKind;
    let mut members: Vec<Element> = vec![];
    let mut joins: Vec<(Element, Element)> = vec![];
    for &e in edges {
        let kind = class.edges[e].kind;
        if !matches!(kind, EdgeKind::Smooth | EdgeKind::Reflex) {
            continue;
        }
        for &f in &model.edges[e].faces {
            joins.push((Element::Face(f), Element::Edge(e)));
        }
        if kind == EdgeKind::Reflex {
            joins.push((Element::Edge(e), Element::Vertex(v)));
        }
    }
    let index = |e: Element, members: &mut Vec<Element>| match members.iter().position(|m| *m == e)
    {
        Some(k) => k,
        None => {
            members.push(e);
            members.len() - 1
        }
    };
    let pairs: Vec<(usize, usize)> = joins
        .iter()
        .map(|&(a, b)| (index(a, &mut members), index(b, &mut members)))
        .collect();
    let mut uf = UnionFind::new(members.len());
    for (a, b) in pairs {
        uf.union(a, b);
    }
    let root: Vec<usize> = (0..members.len()).map(|k| uf.find(k)).collect();
    // Elements not joined at the vertex: a key of their own, past the members' indices.
    let n = members.len();
    Box::new(move |e| match members.iter().position(|m| *m == e) {
        Some(k) => root[k],
        None => {
            n + match e {
                Element::Face(f) => 3 * f,
                Element::Edge(g) => 3 * g + 1,
                Element::Vertex(w) => 3 * w + 2,
            }
        }
    })
}

/// Arc ends paired so far: the union of paired arcs, which ends are paired, and the ends
/// that could not be (with why).
struct Pairing {
    uf: UnionFind,
    paired: Vec<[bool; 2]>,
    unpaired: Vec<String>,
    untold: Vec<(usize, String)>,
}

/// Pairs the arc ends `list` at `node`, all of one group pair: two are one sheet's; more are
/// split by segment pair (and, where an element is touched twice there, by touch points);
/// an end left alone, or more than two that cannot be told apart, go to `unpaired`.
fn pair_list(
    arcs: &[Arc],
    twice: &BTreeSet<(Place, Element)>,
    tol: f64,
    node: Place,
    list: Vec<(usize, usize)>,
    out: &mut Pairing,
) {
    let Pairing {
        uf,
        paired,
        unpaired,
        untold,
    } = out;
    // The rounds whose axes end here, with their sides.
    let rounds: Vec<(Vec<Element>, [Element; 2])> = list
        .iter()
        .filter(|&&(k, _)| !arcs[k].round.is_empty())
        .map(|&(k, _)| (arcs[k].round.clone(), arcs[k].pair))
        .collect();
    let mut tries = vec![list];
    if tries[0].len() > 2 {
        // Keyed by the pair's names: the order in which `unpaired` lists them.
        let mut by_pair: BTreeMap<[String; 2], Vec<(usize, usize)>> = BTreeMap::new();
        for &(k, end) in &tries[0] {
            let pair = arcs[k].ends[end].as_ref().unwrap().1;
            by_pair
                .entry(pair.map(|e| e.to_string()))
                .or_default()
                .push((k, end));
        }
        tries = by_pair
            .into_values()
            .flat_map(|list| {
                let (k, end) = list[0];
                let pair = arcs[k].ends[end].as_ref().unwrap().1;
                if pair.iter().any(|e| twice.contains(&(node, *e))) {
                    by_touch(arcs, list, tol)
                } else {
                    vec![list]
                }
            })
            .collect();
    }
    // At a ball where rounds' axes end, one sheet may be named by a round on one side and by
    // the face beside it (a side of that round's) on the other: the two arc ends left alone
    // whose pairs name the same two contacts that way, and no other, are one sheet's (below
    // a mitred corner, the sheet of the top and the front runs on as the sheet of the two
    // rounds beside them, along the mitre's free edge).
    if let Place::Ball(_) = node {
        tries = pair_across_rounds(arcs, &rounds, tries);
    }
    for list in tries {
        if let [(k1, e1), (k2, e2)] = list[..] {
            uf.union(k1, k2);
            paired[k1][e1] = true;
            paired[k2][e2] = true;
        } else {
            let names: Vec<String> = list
                .iter()
                .map(|&(k, end)| {
                    let pair = &arcs[k].ends[end].as_ref().unwrap().1;
                    format!("{} {{{},{}}}", name(arcs[k].element), pair[0], pair[1])
                })
                .collect();
            let text = format!(
                "{}: {} arc end(s) of one sheet: {}",
                node_name(node),
                list.len(),
                names.join(", ")
            );
            match node {
                Place::Ball(_) => untold.push((arcs[list[0].0].solid, text)),
                _ => unpaired.push(text),
            }
        }
    }
}

/// `tries` with the arc ends left alone (lists of one) paired where two of them name one
/// sheet across the rounds whose axes end at the ball (`rounds`: each round's faces and its
/// two sides): each element of one pair is the other's, or a round and one of its sides,
/// and neither end has another such partner.
fn pair_across_rounds(
    arcs: &[Arc],
    rounds: &[(Vec<Element>, [Element; 2])],
    tries: Vec<Vec<(usize, usize)>>,
) -> Vec<Vec<(usize, usize)>> {
    if rounds.is_empty() {
        return tries;
    }
    let one = |a: Element, b: Element| {
        a == b
            || rounds.iter().any(|(round, sides)| {
                (round.contains(&a) && sides.contains(&b))
                    || (round.contains(&b) && sides.contains(&a))
            })
    };
    let pair_of = |(k, end): (usize, usize)| arcs[k].ends[end].map(|(_, p)| p);
    let same = |x: (usize, usize), y: (usize, usize)| match (pair_of(x), pair_of(y)) {
        (Some([a, b]), Some([c, d])) => (one(a, c) && one(b, d)) || (one(a, d) && one(b, c)),
        _ => false,
    };
    let (alone, mut out): (Vec<_>, Vec<_>) = tries.into_iter().partition(|l| l.len() == 1);
    let alone: Vec<(usize, usize)> = alone.into_iter().map(|l| l[0]).collect();
    let partners = |i: usize| -> Vec<usize> {
        (0..alone.len())
            .filter(|&j| j != i && same(alone[i], alone[j]))
            .collect()
    };
    let mut used = vec![false; alone.len()];
    for i in 0..alone.len() {
        if used[i] {
            continue;
        }
        if let [j] = partners(i)[..] {
            if !used[j] && partners(j) == [i] {
                used[i] = true;
                used[j] = true;
                out.push(vec![alone[i], alone[j]]);
            }
        }
    }
    out.extend(
        (0..alone.len())
            .filter(|&i| !used[i])
            .map(|i| vec![alone[i]]),
    );
    out
}

/// At the ball where one seam ends and skeletal edges start: the seam's side on the two
/// segments that meet at each edge's vertex goes on along that edge, and the two sides left
/// are one sheet round the ball (of a generic seam, its two sides on the third segment: the
/// plate's middle sheet round the ball below a box's corner; of a seam of four contacts
/// meeting in two pairs, the two sides between the pairs: the plate's middle sheet round a
/// hub's corner, the hub's bisector ending above and below it). Told by the segments, not
/// the groups, which may all be one (three reflex edges of one part of the boundary).
/// `None` elsewhere, and where more seams end there.
fn at_skeletal_ball(
    arcs: &[Arc],
    node: Place,
    ends: &[(usize, usize)],
) -> Option<Vec<[(usize, usize); 2]>> {
    let Place::Skeletal(_) = node else {
        return None;
    };
    let is_edge = |&(k, _): &(usize, usize)| matches!(arcs[k].element, BoundaryRef::Skeletal(_));
    let (edges, mut sides): (Vec<_>, Vec<_>) = ends.iter().copied().partition(is_edge);
    let seam = |(k, _): (usize, usize)| arcs[k].slots.map(|(n, _)| n);
    let first = seam(*sides.first()?);
    if edges.is_empty() || first.is_none() || sides.iter().any(|&e| seam(e) != first) {
        return None;
    }
    let pair = |(k, end): (usize, usize)| arcs[k].ends[end].map(|(_, p)| p);
    let mut out = vec![];
    for edge in edges {
        let on_edge = pair(edge)?;
        let along: Vec<usize> = (0..sides.len())
            .filter(|&i| pair(sides[i]) == Some(on_edge))
            .collect();
        let [i] = along[..] else { return None };
        out.push([edge, sides.remove(i)]);
    }
    let [y, z] = sides[..] else { return None };
    out.push([y, z]);
    Some(out)
}

/// Splits arc ends at one node that have one segment pair into the pairs that run between the
/// same two touch points (to `tol`); an end left unmatched is a list by itself (reported
/// unpaired). A list of two, or with an end that has no touch points, is kept as it is.
fn by_touch(arcs: &[Arc], list: Vec<(usize, usize)>, tol: f64) -> Vec<Vec<(usize, usize)>> {
    let touch = |&(k, end): &(usize, usize)| arcs[k].touch[end];
    if list.len() <= 2 || list.iter().any(|e| touch(e).is_none()) {
        return vec![list];
    }
    let same = |a: [DVec3; 2], b: [DVec3; 2]| {
        (a[0].distance(b[0]) <= tol && a[1].distance(b[1]) <= tol)
            || (a[0].distance(b[1]) <= tol && a[1].distance(b[0]) <= tol)
    };
    let mut rest = list;
    let mut out = vec![];
    while let Some(first) = rest.pop() {
        let t = touch(&first).unwrap();
        match rest.iter().position(|e| same(t, touch(e).unwrap())) {
            Some(k) => out.push(vec![first, rest.remove(k)]),
            None => out.push(vec![first]),
        }
    }
    out
}

/// What the count of one solid's Euler characteristic is made from.
struct Graph<'a> {
    arcs: &'a [Arc],
    sheets: &'a [Sheet],
    /// Solids with mixed edges.
    mixed: &'a BTreeSet<usize>,
    /// Solids with sheet boundaries that do not close.
    incomplete: &'a BTreeSet<usize>,
    /// The balls where rounds' axes end, with the seam ends and points there.
    places: &'a BallPlaces,
    /// The degenerate curves that are arcs of the graph (rounds' axes).
    fillets: &'a BTreeSet<usize>,
    /// Solids with arc ends not told apart at a ball where rounds' axes end.
    untold: &'a BTreeSet<usize>,
}

impl Graph<'_> {
    /// The degenerate pieces of `solid` that are not in the graph itself (as rounds' axes, or
    /// as points at the balls where they meet): those counted by inclusion–exclusion.
    fn pieces_apart<'m>(
        &self,
        mat: &'m MedialAxis,
        solid: usize,
    ) -> impl Iterator<Item = &'m crate::medial::Degenerate> + use<'_, 'm> {
        mat.degenerate
            .iter()
            .enumerate()
            .filter(move |(k, d)| {
                d.solid == solid && !self.fillets.contains(k) && !self.places.points.contains(k)
            })
            .map(|(_, d)| d)
    }
}

/// The Euler characteristics of `solid` and of its medial axis (`V − E + Σ χ(sheet)`, or why
/// that is withheld).
fn solid_and_axis_euler(model: &Model, mat: &MedialAxis, g: &Graph, solid: usize) -> SolidEuler {
    let (arcs, sheets) = (g.arcs, g.sheets);
    let solid_euler = solid_euler(model, solid);
    let mine: Vec<&Arc> = arcs.iter().filter(|a| a.solid == solid).collect();
    let nodes: BTreeSet<Place> = mine
        .iter()
        .flat_map(|a| a.ends.iter().flatten().map(|(n, _)| *n))
        .collect();
    let mut elements: BTreeSet<BoundaryRef> = BTreeSet::new();
    let mut closed_seams = BTreeSet::new();
    for a in &mine {
        if a.closed {
            closed_seams.insert(a.element);
        } else {
            elements.insert(a.element);
        }
    }
    let sheets: Vec<&Sheet> = sheets.iter().filter(|s| s.solid == solid).collect();
    let reason = withheld(mat, solid, g, !mine.is_empty());
    // A closed seam is a loop with one node of its own: it adds 1 − 1 = 0.
    let chi_sheets: i64 = sheets.iter().map(|s| 2 - s.loops.len() as i64).sum();
    // Rounds' axes are arcs, and the points where they meet are nodes, counted above.
    let chi_degenerate: i64 = g
        .pieces_apart(mat, solid)
        .map(|d| degenerate_euler(d) - sheets_ending_inside(d, &sheets))
        .sum();
    SolidEuler {
        solid,
        solid_euler,
        mat_euler: reason
            .is_none()
            .then(|| nodes.len() as i64 - elements.len() as i64 + chi_sheets + chi_degenerate),
        nodes: nodes.len() + closed_seams.len(),
        arcs: elements.len() + closed_seams.len(),
        sheets: sheets.len(),
        unknown: reason,
    }
}

/// The Euler characteristic of `solid`: half its boundary's.
fn solid_euler(model: &Model, solid: usize) -> i64 {
    let faces: Vec<usize> = (0..model.faces.len())
        .filter(|&f| model.solid_of_face(f) == solid)
        .collect();
    let mut edges = BTreeSet::new();
    let mut vertices = BTreeSet::new();
    for &f in &faces {
        for l in &model.faces[f].loops {
            vertices.extend(l.vertex);
            for oe in &l.edges {
                edges.insert(oe.edge);
                vertices.extend(model.edges[oe.edge].vertices);
            }
        }
    }
    // χ of the boundary surface by Euler–Poincaré (a face with k loops is a disc with
    // k − 1 holes; a face with no loop at all is a closed surface: a torus, or else a
    // sphere), and the solid's χ is half of it.
    let boundary_euler: i64 = vertices.len() as i64 - edges.len() as i64
        + faces
            .iter()
            .map(|&f| match model.faces[f].loops.len() {
                0 if crate::geom::surface_kind(&model.faces[f].surface) == "torus" => 0,
                0 => 2,
                k => 2 - k as i64,
            })
            .sum::<i64>();
    boundary_euler / 2
}

/// What a degenerate piece adds to the medial axis's Euler characteristic, by
/// inclusion–exclusion (χ(A ∪ B) = χ(A) + χ(B) − χ(A ∩ B)): a curve is 1 (0 when it closes),
/// less 1 for each end where it meets the rest of the medial axis at one point (its ball
/// touches another element once: the apex of a sheet of balls touching that element and the
/// continuum); a free end (`r = 0` at a vertex, or a ball that osculates the element it meets,
/// a capsule's cap) takes nothing away. A point is 1 (the only piece of its solid: see
/// [`degenerate_withheld`]).
fn degenerate_euler(d: &crate::medial::Degenerate) -> i64 {
    use crate::medial::axis::DegenerateEnd;
    match d.kind {
        crate::medial::DegenerateKind::Point => 1,
        crate::medial::DegenerateKind::Curve => {
            if d.ends == [DegenerateEnd::Closed] {
                return 0;
            }
            let meets = d
                .ends
                .iter()
                .filter(|e| {
                    matches!(
                        e,
                        DegenerateEnd::Meets {
                            osculates: false,
                            ..
                        }
                    )
                })
                .count();
            1 - meets as i64
        }
    }
}

/// How many sheets end at a point inside degenerate curve `d`, where it was handed over from
/// one continuum to the next across a convex edge (a cylinder's axis onto a coaxial cone's):
/// the rim sheet of balls touching both faces grows from that edge to the ball of the
/// hand-over and ends there, a disc joined to the curve at one point (each takes 1 away, like
/// an end that meets the rest at one point). A hand-over between faces no sheet joins (a
/// boss's side onto its foot circle, one group) takes nothing away.
fn sheets_ending_inside(d: &crate::medial::Degenerate, sheets: &[&Sheet]) -> i64 {
    let stretches: Vec<&[Element]> = d.segments.chunks(2).collect();
    stretches
        .windows(2)
        .filter(|w| {
            sheets.iter().any(|s| {
                let [a, b] = s.segments;
                a != b
                    && ((w[0].contains(&a) && w[1].contains(&b))
                        || (w[0].contains(&b) && w[1].contains(&a)))
            })
        })
        .count() as i64
}

/// Why the degenerate pieces of `solid` keep its medial axis's Euler characteristic from
/// being counted, if they do: a curve not traced to located ends, or a point beside other
/// pieces (where it joins them is not known). `has_arcs`: the solid's medial axis has seams,
/// rims or skeletal edges.
fn degenerate_withheld(
    mat: &MedialAxis,
    solid: usize,
    g: &Graph,
    has_arcs: bool,
) -> Option<String> {
    use crate::medial::axis::DegenerateEnd;
    let mine: Vec<_> = g.pieces_apart(mat, solid).collect();
    let open = mine.iter().any(|d| {
        d.kind == crate::medial::DegenerateKind::Curve
            && (d.ends.is_empty()
                || d.ends
                    .iter()
                    .any(|e| matches!(e, DegenerateEnd::Open { .. })))
    });
    let arc = mine
        .iter()
        .any(|d| d.kind == crate::medial::DegenerateKind::Curve && !d.around);
    let others = has_arcs || mine.len() > 1;
    let point_among_others = others
        && mine
            .iter()
            .any(|d| d.kind == crate::medial::DegenerateKind::Point);
    if open {
        Some("a degenerate curve is not traced to located ends".into())
    } else if arc {
        Some("a degenerate curve's balls touch along an arc, not all round (a fillet's axis), and where it ends or which two faces' sheet it bounds is not known".into())
    } else if point_among_others {
        Some("a degenerate point lies among other pieces (where it joins them is not known)".into())
    } else {
        None
    }
}

/// Why the medial axis's Euler characteristic of `solid` is not counted, if it is not.
fn withheld(mat: &MedialAxis, solid: usize, g: &Graph, has_arcs: bool) -> Option<String> {
    let seams_of_solid = mat.seams.iter().filter(|s| s.solid == solid);
    // Seam ends that are places of the graph: a skeletal edge's start, a round's axis's end.
    let skeletal_starts: BTreeSet<[usize; 2]> = mat
        .skeletal_edges
        .iter()
        .flat_map(|k| k.starts.iter().copied())
        .chain(g.places.seam_ends.keys().copied())
        .collect();
    if g.mixed.contains(&solid) {
        Some("the solid has mixed edges (convex along part, reflex along the rest)".into())
    } else if let Some(why) = degenerate_withheld(mat, solid, g, has_arcs) {
        Some(why)
    } else if mat.skeletal_edges.iter().any(|k| {
        k.solid == solid && !k.meets.is_empty() && !g.places.skeletal_starts.contains_key(&k.id)
    }) {
        Some("skeletal edges end at degenerate curves, which are not in the cell count yet".into())
    } else if mat.seams.iter().enumerate().any(|(i, s)| {
        s.solid == solid
            && (0..2).any(|end| {
                matches!(s.ends[end], SeamEnd::CurvatureLimit { .. })
                    && !skeletal_starts.contains(&[i, end])
            })
    }) {
        Some("seams end at curvature limits, where untraced skeletal edges begin".into())
    } else if mat.seams.iter().enumerate().any(|(i, s)| {
        s.solid == solid
            && (0..2).any(|end| {
                matches!(s.ends[end], SeamEnd::Pinch { .. }) && !skeletal_starts.contains(&[i, end])
            })
    }) {
        Some("seams end at pinches between two groups of segments, which are not nodes of the graph yet".into())
    } else if seams_of_solid
        .clone()
        .any(|s| s.ends.iter().any(|e| matches!(e, SeamEnd::Open(_))))
    {
        Some("seams end open".into())
    } else if g.untold.contains(&solid) {
        Some(
            "the sheets round a ball where rounds' axes end are not told apart (see `untold`)"
                .into(),
        )
    } else if g.incomplete.contains(&solid) {
        Some("some sheet boundaries do not close (see `unpaired`)".into())
    } else {
        None
    }
}

fn name(e: BoundaryRef) -> String {
    match e {
        BoundaryRef::Seam(s) => format!("seam {s}"),
        BoundaryRef::Edge(e) => format!("rim E{e}"),
        BoundaryRef::Skeletal(k) => format!("skeletal edge {k}"),
        BoundaryRef::Degenerate(k) => format!("degenerate curve {k}"),
    }
}

fn node_name(n: Place) -> String {
    match n {
        Place::Node(Node::Junction(j)) => format!("junction {j}"),
        Place::Node(Node::Vertex(v)) => format!("vertex V{v}"),
        Place::Skeletal(k) => format!("the ball skeletal edge {k} starts at"),
        Place::Ball(k) => format!("the ball {k} where rounds' axes end"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheets_of(name: &str) -> (MedialAxis, Sheets) {
        let (m, c, mat) = crate::testing::traced(name);
        let s = sheets(&m, &c, &mat);
        (mat, s)
    }

    /// Four arc ends at a junction that touches face 0 twice, all on the segment pair
    /// (face 0, face 1): two sheets, told apart by the touch points their arcs run between.
    /// Paired by those; and when one arc's touch points are not the junction's, it is
    /// reported, not paired with the wrong sheet.
    #[test]
    fn a_face_touched_twice_pairs_arcs_by_their_touch_points() {
        let j = Place::Node(Node::Junction(0));
        let (f0, f1) = (Element::Face(0), Element::Face(1));
        let (a, b, bottom) = (
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::Z,
        );
        let arc = |id: usize, t: [DVec3; 2]| Arc {
            element: BoundaryRef::Seam(id),
            solid: 0,
            ends: [
                Some((j, [f0, f1])),
                Some((Place::Node(Node::Vertex(id)), [f0, f1])),
            ],
            groups: [0, 1],
            closed: false,
            pair: [f0, f1],
            touch: [Some(t), None],
            pieces: vec![[f0, f1]],
            slots: None,
            round: vec![],
        };
        let twice = BTreeSet::from([(j, f0)]);
        let arcs = vec![
            arc(0, [a, bottom]),
            arc(1, [b, bottom]),
            arc(2, [bottom, a]),
            arc(3, [b, bottom]),
        ];
        let (mut uf, paired, unpaired, _) =
            pair_ends(&arcs, &twice, 1e-9, &|_| None, &BTreeMap::new());
        assert!(paired.iter().all(|p| p[0]), "{paired:?}");
        assert!(
            unpaired.iter().all(|u| !u.contains("junction")),
            "{unpaired:?}"
        );
        assert_eq!(uf.find(0), uf.find(2));
        assert_eq!(uf.find(1), uf.find(3));
        assert_ne!(uf.find(0), uf.find(1));
        // Arc 3 off by more than the tolerance: arcs 1 and 3 are not one sheet's.
        let mut wrong = arcs;
        wrong[3] = arc(3, [b + DVec3::X * 1e-6, bottom]);
        let (_, paired, unpaired, _) = pair_ends(&wrong, &twice, 1e-9, &|_| None, &BTreeMap::new());
        assert!(!paired[1][0] && !paired[3][0], "{paired:?}");
        assert_eq!(
            unpaired
                .iter()
                .filter(|u| u.starts_with("junction 0: 1 arc end(s)"))
                .count(),
            2,
            "{unpaired:?}"
        );
        // Without the face touched twice the four are one ambiguous set, as before.
        let (_, _, unpaired, _) =
            pair_ends(&wrong, &BTreeSet::new(), 1e-9, &|_| None, &BTreeMap::new());
        assert!(
            unpaired
                .iter()
                .any(|u| u.starts_with("junction 0: 4 arc end(s)")),
            "{unpaired:?}"
        );
    }

    /// An arc of solid 0 between `places`, its segments all of one group, its one piece its
    /// pair.
    fn one_group_arc(
        element: BoundaryRef,
        pair: [Element; 2],
        places: [Place; 2],
        slots: Option<(usize, [usize; 2])>,
    ) -> Arc {
        Arc {
            element,
            solid: 0,
            ends: places.map(|p| Some((p, pair))),
            groups: [0, 0],
            closed: false,
            pair,
            touch: [None, None],
            pieces: vec![pair],
            slots,
            round: vec![],
        }
    }

    /// At the ball where a seam ends and a skeletal edge starts, with all three segments in
    /// one group (three reflex edges of one part of the boundary, as on the Prusa LCD knob):
    /// the group pairs cannot tell the four arc ends apart, the segments do. The seam's side
    /// on the two segments that meet goes on along the skeletal edge; its two sides on the
    /// third are one sheet round the ball.
    #[test]
    fn arcs_at_a_skeletal_edges_ball_pair_by_their_segments() {
        let ball = Place::Skeletal(0);
        let v = Place::Node(Node::Vertex(9));
        let (a, b, c) = (Element::Edge(1), Element::Edge(8), Element::Edge(152));
        let arc = |element: BoundaryRef, pair: [Element; 2], slots| {
            one_group_arc(element, pair, [v, ball], slots)
        };
        let mut arcs = vec![
            arc(BoundaryRef::Seam(0), [a, b], Some((0, [0, 1]))),
            arc(BoundaryRef::Seam(0), [b, c], Some((0, [1, 2]))),
            arc(BoundaryRef::Seam(0), [a, c], Some((0, [0, 2]))),
        ];
        let mut edge = arc(BoundaryRef::Skeletal(0), [a, b], None);
        edge.ends = [Some((ball, [a, b])), Some((v, [a, b]))];
        arcs.push(edge);
        let (mut uf, paired, unpaired, _) =
            pair_ends(&arcs, &BTreeSet::new(), 1e-9, &|_| None, &BTreeMap::new());
        assert!(
            paired[0][1] && paired[1][1] && paired[2][1] && paired[3][0],
            "{paired:?}"
        );
        assert!(
            unpaired.iter().all(|u| !u.starts_with("the ball")),
            "{unpaired:?}"
        );
        assert_eq!(uf.find(0), uf.find(3), "along the skeletal edge");
        assert_eq!(uf.find(1), uf.find(2), "round the ball");
        assert_ne!(uf.find(0), uf.find(1));
    }

    /// A plate through a hub's corner (samples/trace/plate_through_a_split_hub): the seam of
    /// the plate's four reflex edges at the hub (two on top, two below) ends at the ball
    /// touching the two vertices where each pair meets. Each pair's side goes on along the
    /// skeletal edge to its vertex (the hub's bisector ends there, above and below); the two
    /// sides between the pairs are the plate's middle sheet, one round the ball. A third
    /// skeletal edge naming no side leaves the ends unpaired.
    #[test]
    fn a_ball_of_four_contacts_pairs_each_skeletal_edge_and_the_two_sides_left() {
        let ball = Place::Skeletal(4);
        let (lo, hi) = (Place::Node(Node::Vertex(14)), Place::Node(Node::Vertex(21)));
        let (a, b, c, d) = (
            Element::Edge(16),
            Element::Edge(15),
            Element::Edge(24),
            Element::Edge(25),
        );
        let j = Place::Node(Node::Junction(6));
        let side = |pair: [Element; 2], s: [usize; 2]| {
            one_group_arc(BoundaryRef::Seam(19), pair, [j, ball], Some((19, s)))
        };
        let edge = |k: usize, pair: [Element; 2], v: Place| {
            one_group_arc(BoundaryRef::Skeletal(k), pair, [ball, v], None)
        };
        let mut arcs = vec![
            side([a, b], [0, 1]),
            side([b, c], [1, 2]),
            side([c, d], [2, 3]),
            side([d, a], [3, 0]),
            edge(4, [a, b], lo),
            edge(7, [c, d], hi),
        ];
        let (mut uf, paired, _, _) =
            pair_ends(&arcs, &BTreeSet::new(), 1e-9, &|_| None, &BTreeMap::new());
        assert!((0..4).all(|k| paired[k][1]) && paired[4][0] && paired[5][0]);
        assert_eq!(uf.find(0), uf.find(4), "down the lower edge");
        assert_eq!(uf.find(2), uf.find(5), "up the upper edge");
        assert_eq!(uf.find(1), uf.find(3), "round the ball");
        assert_ne!(uf.find(0), uf.find(1));
        assert_ne!(uf.find(2), uf.find(1));
        // An edge naming a pair no side has: nothing is paired at the ball by the segments.
        arcs.push(edge(8, [a, c], hi));
        let (_, paired, _, _) =
            pair_ends(&arcs, &BTreeSet::new(), 1e-9, &|_| None, &BTreeMap::new());
        assert!(!paired[6][0], "{paired:?}");
    }

    /// The Prusa extruder idler's vertex V64, where the corner of a hexagonal nut pocket (two
    /// walls joined by a reflex edge) reaches the top face exactly on a groove's edge: two
    /// seams end there at `r = 0`, one touching the top, the groove's half on one side and
    /// one pocket wall, the other the top, the other half and the other wall; four rims end
    /// there too. Everything is one group across the part. The seams' sides on the top and
    /// a wall are one sheet, its touch point crossing the reflex edge at the vertex: paired
    /// by the groups as they are at the vertex; by the segments alone they are two ends left
    /// open (as before), and with the local groups taken away again they are not paired.
    #[test]
    fn arcs_at_a_vertex_pair_across_a_reflex_edge_that_ends_there() {
        let v = Place::Node(Node::Vertex(64));
        let [top, half1, half2, wall1, wall2] = [12, 25, 69, 39, 68].map(Element::Face);
        let arc = |element: BoundaryRef, pair: [Element; 2]| Arc {
            element,
            solid: 0,
            ends: [Some((v, pair)), None],
            groups: [0, 0],
            closed: false,
            pair,
            touch: [None, None],
            pieces: vec![pair],
            slots: None,
            round: vec![],
        };
        let arcs = vec![
            arc(BoundaryRef::Seam(128), [top, half1]),
            arc(BoundaryRef::Seam(128), [half1, wall1]),
            arc(BoundaryRef::Seam(128), [top, wall1]),
            arc(BoundaryRef::Seam(147), [wall2, half2]),
            arc(BoundaryRef::Seam(147), [top, wall2]),
            arc(BoundaryRef::Seam(147), [top, half2]),
            arc(BoundaryRef::Edge(76), [top, half1]),
            arc(BoundaryRef::Edge(115), [half1, wall1]),
            arc(BoundaryRef::Edge(75), [top, half2]),
            arc(BoundaryRef::Edge(215), [wall2, half2]),
        ];
        // Each pair in the order of its elements, as the arcs of a report have them. At V64
        // only the reflex edge between the walls joins anything.
        let local = |_: usize| -> Option<LocalGroups> {
            Some(Box::new(move |e| match e {
                Element::Face(39) | Element::Face(68) => 39,
                Element::Face(f) => f,
                _ => usize::MAX,
            }))
        };
        let (mut uf, paired, unpaired, _) =
            pair_ends(&arcs, &BTreeSet::new(), 1e-9, &local, &BTreeMap::new());
        assert!(unpaired.is_empty(), "{unpaired:?}");
        assert!(paired.iter().all(|p| p[0]), "{paired:?}");
        assert_eq!(uf.find(2), uf.find(4), "top and the walls: one sheet");
        assert_eq!(uf.find(0), uf.find(6));
        assert_ne!(uf.find(2), uf.find(0));
        let (_, _, unpaired, _) =
            pair_ends(&arcs, &BTreeSet::new(), 1e-9, &|_| None, &BTreeMap::new());
        assert_eq!(
            unpaired,
            [
                "vertex V64: 1 arc end(s) of one sheet: seam 128 {F12,F39}",
                "vertex V64: 1 arc end(s) of one sheet: seam 147 {F12,F68}",
            ]
        );
    }

    /// `faceted_boss`'s junction 7: its ball (between the boss's top and the plate's bottom,
    /// centred on the plate's top) touches a boss wall exactly at its foot edge. The junction
    /// names that contact by the edge; one seam ending there names it by the wall. Walls,
    /// foot edges and the plate's top are one group, so the four arc ends between that group
    /// and the boss's top are ambiguous, and by segments two are left alone. The junction's
    /// contacts tell them apart: the arcs between the same two contacts are one sheet's. An
    /// arc whose touch point is at none of the contacts is not paired by them.
    #[test]
    fn arcs_at_a_junction_pair_by_the_contacts_they_run_between() {
        let j = Place::Node(Node::Junction(7));
        let (e11, e10, f10, top) = (
            Element::Edge(11),
            Element::Edge(10),
            Element::Face(10),
            Element::Face(12),
        );
        let contacts = [
            DVec3::new(16.02, 19.98, 4.0),
            DVec3::new(12.0, 15.98, 4.0),
            DVec3::new(16.0, 15.98, 8.0),
            DVec3::new(16.0, 15.98, 0.0),
        ];
        let arc = |seam: usize, pair: [Element; 2], slots: [usize; 2]| Arc {
            element: BoundaryRef::Seam(seam),
            solid: 0,
            ends: [Some((j, pair)), None],
            groups: [0, 1],
            closed: false,
            pair,
            touch: [Some(slots.map(|s| contacts[s])), None],
            pieces: vec![pair],
            slots: None,
            round: vec![],
        };
        let arcs = vec![
            arc(11, [e10, top], [1, 2]),
            arc(11, [e11, top], [0, 2]),
            arc(18, [e10, top], [1, 2]),
            arc(22, [f10, top], [0, 2]),
        ];
        let at = BTreeMap::from([(j, contacts.to_vec())]);
        let none = BTreeSet::new();
        let (mut uf, paired, unpaired, _) = pair_ends(&arcs, &none, 1e-9, &|_| None, &at);
        assert!(unpaired.is_empty(), "{unpaired:?}");
        assert!(paired.iter().all(|p| p[0]), "{paired:?}");
        assert_eq!(
            uf.find(1),
            uf.find(3),
            "the wall and its foot edge: one contact"
        );
        assert_eq!(uf.find(0), uf.find(2));
        let (_, _, unpaired, _) = pair_ends(&arcs, &none, 1e-9, &|_| None, &BTreeMap::new());
        assert_eq!(unpaired.len(), 2, "{unpaired:?}");
        let mut off = arcs;
        off[3].touch[0] = Some([contacts[0] + DVec3::Z * 1e-6, contacts[2]]);
        let (_, _, unpaired, _) = pair_ends(&off, &none, 1e-9, &|_| None, &at);
        assert_eq!(unpaired.len(), 2, "{unpaired:?}");
    }

    /// `kinked_walls`: a long wall written as two planes meeting at a 0.5° convex kink,
    /// classified smooth. A seam that ends at the kink's top vertex (`r = 0`) touching both
    /// planes (as the Voron Dragon mount's 0.36° kink between two B-spline faces has) makes
    /// that smooth edge the rim of the sheet between them; a seam ending there touching one
    /// of them only, or ending elsewhere, does not; nor does the traced part, which has none.
    #[test]
    fn a_smooth_edge_is_a_rim_where_a_seam_ends_at_its_vertex_touching_both_faces() {
        use crate::medial::axis::{Seam, SeamEnd};
        let (model, class, mut mat) = crate::testing::traced("trace/kinked_walls.step");
        assert!(convex_kinks(&model, &class, &mat).is_empty());
        let kink = (0..model.edges.len())
            .find(|&e| {
                class.edges[e].kind == crate::classify::EdgeKind::Smooth
                    && model.edges[e]
                        .vertices
                        .iter()
                        .all(|&v| model.vertices[v].point.y.abs() < 1e-9)
            })
            .unwrap();
        let edge = &model.edges[kink];
        let top = *edge
            .vertices
            .iter()
            .find(|&&v| model.vertices[v].point.z > 2.0)
            .unwrap();
        let [a, b] = [edge.faces[0], edge.faces[1]].map(Element::Face);
        let roof = (0..model.faces.len())
            .find(|&f| {
                let at_top = |v: usize| (model.vertices[v].point.z - 4.0).abs() < 1e-9;
                model
                    .edges
                    .iter()
                    .filter(|e| e.faces.contains(&f))
                    .all(|e| e.vertices.iter().all(|&v| at_top(v)))
            })
            .map(Element::Face)
            .unwrap();
        let seam = |end_segments: Vec<Element>, end: SeamEnd| Seam {
            id: 0,
            solid: 0,
            segments: end_segments.clone(),
            ends: [SeamEnd::Junction(0), end],
            end_segments,
            points: vec![],
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        };
        mat.seams.push(seam(vec![a, roof, a], SeamEnd::Vertex(top)));
        assert!(
            convex_kinks(&model, &class, &mat).is_empty(),
            "one face only"
        );
        mat.seams.push(seam(vec![a, roof, b], SeamEnd::Junction(1)));
        assert!(
            convex_kinks(&model, &class, &mat).is_empty(),
            "not at the vertex"
        );
        mat.seams.push(seam(vec![a, roof, b], SeamEnd::Vertex(top)));
        assert_eq!(convex_kinks(&model, &class, &mat), BTreeSet::from([kink]));
    }

    fn loop_sizes(s: &Sheets) -> Vec<usize> {
        let mut v: Vec<usize> = s.sheets.iter().map(|s| s.loops.len()).collect();
        v.sort();
        v
    }

    /// Box [0,60]×[0,40]×[0,20] (three different side lengths): one sheet along each of its
    /// 12 edges (bounded by that edge's rim and seams), and one in the middle between top and
    /// bottom bounded by the 4 inner seams: 13 sheets, each a disc. Nodes: 4 junctions and
    /// 8 corners; arcs: 12 seams and 12 rims. V − E + F = 12 − 24 + 13 = 1, the solid's.
    #[test]
    fn box_has_thirteen_sheets() {
        for file in ["box.step", "box_nurbs.step"] {
            let (mat, s) = sheets_of(file);
            assert_eq!(s.sheets.len(), 13, "{file}");
            assert!(s.unpaired.is_empty(), "{file}: {:?}", s.unpaired);
            assert_eq!(loop_sizes(&s), vec![1; 13], "{file}");
            let e = &s.solids[0];
            assert_eq!((e.nodes, e.arcs, e.sheets), (12, 24, 13), "{file}");
            assert_eq!((e.solid_euler, e.mat_euler), (1, Some(1)), "{file}");
            // The middle sheet: the one without a rim, bounded by the four seams that join
            // the junctions (both ends at junctions).
            let inner: Vec<&Sheet> = s
                .sheets
                .iter()
                .filter(|sh| {
                    sh.boundary
                        .iter()
                        .all(|b| matches!(b, BoundaryRef::Seam(_)))
                })
                .collect();
            assert_eq!(inner.len(), 1, "{file}");
            assert_eq!(inner[0].boundary.len(), 4, "{file}");
            for b in &inner[0].boundary {
                let BoundaryRef::Seam(k) = b else {
                    unreachable!()
                };
                assert!(
                    mat.seams[*k]
                        .ends
                        .iter()
                        .all(|e| matches!(e, SeamEnd::Junction(_))),
                    "{file}: seam {k}"
                );
            }
            // Every rim bounds exactly one sheet, every seam three.
            let mut uses: BTreeMap<BoundaryRef, usize> = BTreeMap::new();
            for sh in &s.sheets {
                for b in &sh.boundary {
                    *uses.entry(*b).or_default() += 1;
                }
            }
            for (b, n) in uses {
                let want = if matches!(b, BoundaryRef::Seam(_)) {
                    3
                } else {
                    1
                };
                assert_eq!(n, want, "{file}: {b:?}");
            }
        }
    }

    /// L-bracket (8 planar faces, 17 convex edges, 1 reflex edge between the inner faces F2
    /// and F3). Nodes: 6 junctions and 12 vertices = 18; arcs: 17 seams and 17 rims = 34.
    /// Sheets: each convex edge's rim starts a sheet, but on each end face the two rims
    /// beside the reflex edge (F2|F6 and F3|F6; F2|F7 and F3|F7) bound one sheet, because its
    /// balls' touch point moves from F2 over the reflex edge onto F3: 17 − 2 = 15 sheets with
    /// rims; and each leg has a mid-sheet between its two parallel faces, bounded by seams
    /// only: 15 + 2 = 17 discs. V − E + F = 18 − 34 + 17 = 1, the solid's.
    #[test]
    fn l_bracket_has_seventeen_sheets() {
        for file in ["l_bracket.step", "l_bracket_nurbs.step"] {
            let (_, s) = sheets_of(file);
            assert!(s.unpaired.is_empty(), "{file}: {:?}", s.unpaired);
            assert_eq!(loop_sizes(&s), vec![1; 17], "{file}");
            let e = &s.solids[0];
            assert_eq!((e.nodes, e.arcs, e.sheets), (18, 34, 17), "{file}");
            assert_eq!((e.solid_euler, e.mat_euler), (1, Some(1)), "{file}");
            let two_rims = s
                .sheets
                .iter()
                .filter(|sh| {
                    sh.boundary
                        .iter()
                        .filter(|b| matches!(b, BoundaryRef::Edge(_)))
                        .count()
                        == 2
                })
                .count();
            let no_rim = s
                .sheets
                .iter()
                .filter(|sh| {
                    sh.boundary
                        .iter()
                        .all(|b| matches!(b, BoundaryRef::Seam(_)))
                })
                .count();
            assert_eq!((two_rims, no_rim), (2, 2), "{file}");
        }
    }

    /// Plate with three cylindrical through-holes (a curved part; χ = 1 − 3 = −2). The box
    /// part gives 4 junctions, 8 corners, 12 seams, 12 rims and 12 edge sheets. Each hole adds
    /// a closed seam (top, bottom, hole wall) — a loop with a node of its own — and two circle
    /// rims with one vertex each; the sheets {top, hole} and {bottom, hole} are annuli (the
    /// closed seam and a rim: χ = 0), and the mid-sheet {top, bottom} is a disc with three
    /// holes (χ = 2 − 4 = −2). V = 12 + 3 + 6 = 21, E = 24 + 3 + 6 = 33, Σχ = 12 − 2 + 0:
    /// V − E + Σχ = 21 − 33 + 10 = −2, the solid's.
    #[test]
    fn plate_with_holes_has_annuli_and_a_mid_sheet_with_three_holes() {
        let (_, s) = sheets_of("plate_with_holes.step");
        assert!(s.unpaired.is_empty(), "{:?}", s.unpaired);
        let mut want = vec![1; 12];
        want.extend([2; 6]);
        want.push(4);
        assert_eq!(loop_sizes(&s), want);
        let e = &s.solids[0];
        assert_eq!((e.nodes, e.arcs, e.sheets), (21, 33, 19));
        assert_eq!((e.solid_euler, e.mat_euler), (-2, Some(-2)));
    }

    /// Where the boundary is incomplete the count is withheld with a reason, never guessed:
    /// the elliptic cylinder's seams end at curvature limits whose skeletal edges are not
    /// traced; the filleted box's rounds' axes, when one of them is not known to end (its end
    /// made open), keep its count from being made. The cylinder's axis, touching all round,
    /// is counted (see `degenerate_curves_are_traced_between_located_ends`).
    #[test]
    fn euler_withheld_where_sheets_are_incomplete() {
        let (m, c, mut mat) = crate::testing::traced("filleted_box.step");
        let k = mat.degenerate.iter().position(|d| !d.around).unwrap();
        mat.degenerate[k].ends[1] = crate::medial::axis::DegenerateEnd::open(
            crate::medial::axis::DegenerateOpen::BallBudget,
            "made open by the test",
        );
        let s = sheets(&m, &c, &mat);
        assert_eq!(s.solids[0].mat_euler, None);
        assert!(s.solids[0]
            .unknown
            .as_deref()
            .unwrap()
            .contains("not traced"));
        let (_, s) = sheets_of("cylinder.step");
        assert_eq!(s.solids[0].mat_euler, Some(1));
        let (_, s) = sheets_of("elliptic_cylinder.step");
        assert_eq!(s.solids[0].mat_euler, None);
        assert!(s.solids[0]
            .unknown
            .as_deref()
            .unwrap()
            .contains("curvature"));
    }

    /// The filleted box (60×40×20, every edge rounded with radius 4) has the medial axis of
    /// the inner box 52×32×12 grown by 4: its rounds' axes are that box's rims, its corner
    /// spheres' centres its vertices, where the corner seams end at a curvature limit and
    /// three axes meet. 12 nodes (4 junctions, 8 corner balls), 24 arcs (12 seams, 12 axes),
    /// 13 sheets: χ = 1, as the box's. Each axis bounds the sheet of the two faces its round
    /// joins.
    #[test]
    fn filleted_box_counts_its_rounds_axes_as_rims() {
        let (mat, s) = sheets_of("filleted_box.step");
        assert!(s.unpaired.is_empty(), "{:?}", s.unpaired);
        let e = &s.solids[0];
        assert_eq!(
            (e.nodes, e.arcs, e.sheets, e.solid_euler, e.mat_euler),
            (12, 24, 13, 1, Some(1)),
            "{:?}",
            e.unknown
        );
        let axes: Vec<usize> = (0..mat.degenerate.len())
            .filter(|&k| !mat.degenerate[k].around && mat.degenerate[k].balls.len() > 1)
            .collect();
        assert_eq!(axes.len(), 12);
        for k in axes {
            let sheet = s
                .sheets
                .iter()
                .find(|sh| sh.boundary.contains(&BoundaryRef::Degenerate(k)))
                .unwrap_or_else(|| panic!("axis {k} bounds no sheet"));
            // Two planes, neither of them the round.
            assert!(
                !sheet
                    .segments
                    .iter()
                    .any(|e| mat.degenerate[k].segments.contains(e))
                    || mat.degenerate[k].segments.len() > 2,
                "{:?} {:?}",
                sheet.segments,
                mat.degenerate[k].segments
            );
        }
    }

    /// A box's corner with two rounds meeting in a mitre (`samples/trace`): at the ball where
    /// the two rounds' axes end, the seam of the side, the top and the front ends, and the
    /// mitre's free edge starts. The sheet of the top and the front (the seam's side there)
    /// runs on past that ball as the sheet of the two rounds beside them, along the free
    /// edge: named by the rounds on one side of the ball and by their sides on the other, it
    /// is paired across them. χ = 1, every end paired.
    #[test]
    fn a_mitred_corner_pairs_the_sheet_named_by_its_rounds_and_their_sides() {
        let (mat, s) = sheets_of("trace/box_with_a_mitred_corner.step");
        assert!(s.unpaired.is_empty(), "{:?}", s.unpaired);
        assert!(s.untold.is_empty(), "{:?}", s.untold);
        assert_eq!(
            (s.solids[0].solid_euler, s.solids[0].mat_euler),
            (1, Some(1)),
            "{:?}",
            s.solids[0].unknown
        );
        let free = BoundaryRef::Skeletal(mat.skeletal_edges[0].id);
        let sheet = s
            .sheets
            .iter()
            .find(|sh| sh.boundary.contains(&free))
            .unwrap();
        assert!(
            sheet
                .boundary
                .iter()
                .any(|b| matches!(b, BoundaryRef::Seam(_))),
            "the free edge's sheet is bounded by the seam too: {:?}",
            sheet.boundary
        );
    }

    /// A square pyramid: the seam from its apex is touched by the four side faces, so its
    /// sheets are the four between neighbouring sides (not the two diagonals) and the four
    /// between the base and a side: eight, every boundary closed, χ = 1 as the solid's.
    #[test]
    fn square_pyramid_has_eight_sheets_round_its_non_generic_seam() {
        let (mat, s) = sheets_of("pyramid.step");
        let apex: Vec<&crate::medial::axis::Seam> =
            mat.seams.iter().filter(|s| s.segments.len() == 4).collect();
        assert_eq!(apex.len(), 1, "one seam touched by four faces");
        assert!(s.unpaired.is_empty(), "{:?}", s.unpaired);
        assert_eq!(s.sheets.len(), 8);
        assert_eq!(
            (s.solids[0].solid_euler, s.solids[0].mat_euler),
            (1, Some(1))
        );
        // No sheet between the two faces across the seam from each other.
        let across =
            [0, 1].map(|i| arcs::sorted_pair(apex[0].segments[i], apex[0].segments[i + 2]));
        assert!(s.sheets.iter().all(|sh| !across.contains(&sh.segments)));
    }

    /// A box with a void is homotopy-equivalent to a sphere (χ = 2); so is its medial axis.
    #[test]
    fn box_with_void_has_euler_two() {
        let (_, s) = sheets_of("box_with_void.step");
        assert!(s.unpaired.is_empty(), "{:?}", s.unpaired);
        assert_eq!(
            (s.solids[0].solid_euler, s.solids[0].mat_euler),
            (2, Some(2))
        );
    }
}
