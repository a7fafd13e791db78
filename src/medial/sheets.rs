//! Sheets: the 2-dimensional pieces of the medial axis, found from their boundaries
//! (`docs/design.md`, sheets).
//!
//! A seam with touch triplet {a, b, c} bounds the three sheets {a, b}, {b, c}, {a, c}; a convex
//! edge between faces a and b is the *rim* of sheet {a, b} (balls of radius → 0 there). So the
//! boundary of every sheet is a set of closed loops made of seam *sides* and rims, joined at
//! junctions and convex vertices. This module walks them:
//!
//! 1. every seam gives three *arcs* (one per pair of its touch slots; a closed seam's arcs are
//!    loops on their own), every convex edge one;
//! 2. at each node (a junction, or a vertex where seams end or rims meet) the arc ends are
//!    paired by the sheet they bound, named by the two *segment groups* touched: faces joined
//!    by smooth or reflex edges (with those edges and the reflex vertices between them) form
//!    one group, because a touch point moves across such an edge without the sheet ending
//!    (a fillet, a split face, the inner corner of an L). Where a group pair is ambiguous at
//!    a node (more than two arc ends), the exact segment pair decides;
//! 3. paired arcs form loops, and the loops with the same group pair form one sheet.
//!
//! Counting then gives the medial axis's Euler characteristic `V − E + Σ χ(sheet)`, with
//! `χ = 2 − loops` for a sheet (a disc with holes). That assumes each sheet has genus 0 and
//! that loops of one group pair are one sheet; both hold for the reference parts (tests), and
//! the count is withheld, with the reason, wherever the boundary is incomplete: open seam
//! ends, curvature-limit ends (the skeletal edges from there are not traced), degenerate
//! pieces (a cylinder's axis) or mixed edges.

use crate::classify::{Classification, EdgeKind};
use crate::medial::axis::{MedialAxis, Node, SeamEnd, SeamPoint};
use crate::medial::segments::{SegmentGroups, UnionFind};
use crate::model::{Element, Model};
use glam::DVec3;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

/// Touch points of two arcs at a junction are the same contact when they lie this close, over
/// the model's bounding-box diagonal (both come from the junction's one solution).
const SAME_TOUCH_REL_DIAGONAL: f64 = 1e-7;

/// One element of a sheet's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryRef {
    /// A seam (by id).
    Seam(usize),
    /// A convex edge of the model: the sheet's rim.
    Edge(usize),
}

/// A sheet, named by two of the segments it touches, with its boundary.
#[derive(Clone, Debug, Serialize)]
pub struct Sheet {
    pub id: usize,
    pub solid: usize,
    /// Two segments whose touch points the sheet's balls have (where its first boundary arc
    /// starts; along the sheet the touch points may move onto neighbouring segments of the
    /// same group).
    pub segments: [Element; 2],
    /// Every seam and rim on the boundary, in loop order.
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
    /// Nodes (junctions and the vertices seams and rims end at), arcs (seams and rims) and
    /// sheets counted.
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
}

/// An arc: one side of a seam, or a rim.
struct Arc {
    element: BoundaryRef,
    solid: usize,
    /// The segment pair at each end (exact elements) and the group pair.
    ends: [Option<(Node, [Element; 2])>; 2],
    groups: [usize; 2],
    /// A closed seam's side: a loop by itself.
    closed: bool,
    /// The segment pair where the arc starts (a closed seam's side has no node to name it).
    pair: [Element; 2],
    /// A seam's side: its two touch points at each end (which contacts of a junction it
    /// runs between, where one element is touched there twice).
    touch: [Option<[DVec3; 2]>; 2],
}

/// Finds the sheets of `mat` and the Euler characteristics of each solid and its medial axis.
pub fn sheets(model: &Model, class: &Classification, mat: &MedialAxis) -> Sheets {
    let groups = SegmentGroups::new(model, class);
    let mut arcs = seam_arcs(mat, &groups);
    let mixed = add_rims(model, class, &groups, &mut arcs);
    // Elements a junction touches in two places.
    let twice: BTreeSet<(Node, Element)> = mat
        .junctions
        .iter()
        .flat_map(|j| {
            let segs = &j.segments;
            (0..segs.len())
                .filter(move |&k| segs[..k].contains(&segs[k]))
                .map(move |k| (Node::Junction(j.id), segs[k]))
        })
        .collect();
    let tol = SAME_TOUCH_REL_DIAGONAL * model.diagonal();
    let (mut uf, paired, unpaired) = pair_ends(&arcs, &twice, tol);
    let (by_sheet, incomplete) = loops_by_sheet(&arcs, &mut uf, &paired);
    let mut out = Sheets {
        unpaired,
        ..Default::default()
    };
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

    out.solids = (0..model.solids.len())
        .map(|solid| {
            solid_and_axis_euler(model, mat, &arcs, &out.sheets, solid, &mixed, &incomplete)
        })
        .collect();
    out
}

/// The three arcs of every seam (one per pair of its touch slots).
fn seam_arcs(mat: &MedialAxis, groups: &SegmentGroups) -> Vec<Arc> {
    let mut arcs: Vec<Arc> = vec![];
    for s in &mat.seams {
        let closed = s.ends.iter().all(|e| matches!(e, SeamEnd::Closed));
        for (i, j) in [(0, 1), (1, 2), (0, 2)] {
            let pair = |segs: &[Element]| match (segs.get(i), segs.get(j)) {
                (Some(a), Some(b)) => Some(sorted_pair(*a, *b)),
                _ => None,
            };
            let start = s.ends[0].node().zip(pair(&s.segments));
            let end = s.ends[1].node().zip(pair(&s.end_segments));
            let g = [groups.of(s.segments[i]), groups.of(s.segments[j])];
            let touch = |p: Option<&SeamPoint>| {
                p.map(|p| [DVec3::from_array(p.touch[i]), DVec3::from_array(p.touch[j])])
            };
            arcs.push(Arc {
                element: BoundaryRef::Seam(s.id),
                solid: s.solid,
                ends: [start, end],
                groups: [g[0].min(g[1]), g[0].max(g[1])],
                closed,
                pair: sorted_pair(s.segments[i], s.segments[j]),
                touch: [touch(s.points.first()), touch(s.points.last())],
            });
        }
    }
    arcs
}

/// Adds the rims (convex edges between two faces) to `arcs`; returns the solids with mixed
/// edges.
fn add_rims(
    model: &Model,
    class: &Classification,
    groups: &SegmentGroups,
    arcs: &mut Vec<Arc>,
) -> BTreeSet<usize> {
    let mut mixed = BTreeSet::new();
    for (e, edge) in model.edges.iter().enumerate() {
        match class.edges[e].kind {
            EdgeKind::Convex if edge.faces.len() == 2 && edge.faces[0] != edge.faces[1] => {
                let (a, b) = (Element::Face(edge.faces[0]), Element::Face(edge.faces[1]));
                let pair = sorted_pair(a, b);
                let g = [groups.of(a), groups.of(b)];
                arcs.push(Arc {
                    element: BoundaryRef::Edge(e),
                    solid: model.solid_of_face(edge.faces[0]),
                    ends: [
                        Some((Node::Vertex(edge.vertices[0]), pair)),
                        Some((Node::Vertex(edge.vertices[1]), pair)),
                    ],
                    groups: [g[0].min(g[1]), g[0].max(g[1])],
                    closed: false,
                    pair,
                    touch: [None, None],
                });
            }
            EdgeKind::Mixed => {
                mixed.insert(model.solid_of_face(edge.faces[0]));
            }
            _ => {}
        }
    }

    mixed
}

/// Pairs the arc ends at each node by group pair, then (where that is ambiguous) by segment
/// pair, then (where one element is touched twice there, so that two sheets share a segment
/// pair) by the touch points the arcs run between, equal to `tol`: the union of paired arcs,
/// which ends are paired, and the ends that could not be.
fn pair_ends(
    arcs: &[Arc],
    twice: &BTreeSet<(Node, Element)>,
    tol: f64,
) -> (UnionFind, Vec<[bool; 2]>, Vec<String>) {
    let mut at: BTreeMap<Node, Vec<(usize, usize)>> = BTreeMap::new();
    for (k, arc) in arcs.iter().enumerate() {
        for (end, e) in arc.ends.iter().enumerate() {
            if let Some((node, _)) = e {
                at.entry(*node).or_default().push((k, end));
            }
        }
    }
    let mut uf = UnionFind::new(arcs.len());
    let mut paired = vec![[false; 2]; arcs.len()];
    let mut unpaired = vec![];
    for (node, ends) in &at {
        let mut by_group: BTreeMap<[usize; 2], Vec<(usize, usize)>> = BTreeMap::new();
        for &(k, end) in ends {
            by_group.entry(arcs[k].groups).or_default().push((k, end));
        }
        for (_, list) in by_group {
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
                        if pair.iter().any(|e| twice.contains(&(*node, *e))) {
                            by_touch(arcs, list, tol)
                        } else {
                            vec![list]
                        }
                    })
                    .collect();
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
                    unpaired.push(format!(
                        "{}: {} arc end(s) of one sheet: {}",
                        node_name(*node),
                        list.len(),
                        names.join(", ")
                    ));
                }
            }
        }
    }

    (uf, paired, unpaired)
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

/// Loops (components of paired arcs, complete when every end is paired) by sheet: (solid,
/// group pair) → loops, and the solids with incomplete loops.
type LoopsBySheet = BTreeMap<(usize, [usize; 2]), Vec<Vec<usize>>>;
fn loops_by_sheet(
    arcs: &[Arc],
    uf: &mut UnionFind,
    paired: &[[bool; 2]],
) -> (LoopsBySheet, BTreeSet<usize>) {
    let mut components: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for k in 0..arcs.len() {
        components.entry(uf.find(k)).or_default().push(k);
    }
    let mut incomplete_solids = BTreeSet::new();
    let mut by_sheet: BTreeMap<(usize, [usize; 2]), Vec<Vec<usize>>> = BTreeMap::new();
    for (_, members) in components {
        let complete = members
            .iter()
            .all(|&k| arcs[k].closed || (paired[k][0] && paired[k][1]));
        let first = &arcs[members[0]];
        if !complete {
            incomplete_solids.insert(first.solid);
            continue;
        }
        by_sheet
            .entry((first.solid, first.groups))
            .or_default()
            .push(order_loop(arcs, &members));
    }

    (by_sheet, incomplete_solids)
}

/// The Euler characteristics of `solid` and of its medial axis (`V − E + Σ χ(sheet)`, or why
/// that is withheld).
fn solid_and_axis_euler(
    model: &Model,
    mat: &MedialAxis,
    arcs: &[Arc],
    sheets: &[Sheet],
    solid: usize,
    mixed: &BTreeSet<usize>,
    incomplete: &BTreeSet<usize>,
) -> SolidEuler {
    let solid_euler = solid_euler(model, solid);
    let mine: Vec<&Arc> = arcs.iter().filter(|a| a.solid == solid).collect();
    let nodes: BTreeSet<Node> = mine
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
    let reason = withheld(mat, solid, mixed, incomplete);
    // A closed seam is a loop with one node of its own: it adds 1 − 1 = 0.
    let chi_sheets: i64 = sheets.iter().map(|s| 2 - s.loops.len() as i64).sum();
    SolidEuler {
        solid,
        solid_euler,
        mat_euler: reason
            .is_none()
            .then(|| nodes.len() as i64 - elements.len() as i64 + chi_sheets),
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

/// Why the medial axis's Euler characteristic of `solid` is not counted, if it is not.
fn withheld(
    mat: &MedialAxis,
    solid: usize,
    mixed: &BTreeSet<usize>,
    incomplete: &BTreeSet<usize>,
) -> Option<String> {
    let seams_of_solid = mat.seams.iter().filter(|s| s.solid == solid);
    if mixed.contains(&solid) {
        Some("the solid has mixed edges (convex along part, reflex along the rest)".into())
    } else if mat.degenerate.iter().any(|d| d.solid == solid) {
        Some("the medial axis has degenerate pieces (sampled, not yet in the cell count)".into())
    } else if seams_of_solid.clone().any(|s| {
        s.ends
            .iter()
            .any(|e| matches!(e, SeamEnd::CurvatureLimit { .. }))
    }) {
        Some("seams end at curvature limits, where untraced skeletal edges begin".into())
    } else if seams_of_solid
        .clone()
        .any(|s| s.ends.iter().any(|e| matches!(e, SeamEnd::Pinch { .. })))
    {
        Some("seams end at pinches, which are not nodes of the graph yet".into())
    } else if seams_of_solid
        .clone()
        .any(|s| s.ends.iter().any(|e| matches!(e, SeamEnd::Open(_))))
    {
        Some("seams end open".into())
    } else if incomplete.contains(&solid) {
        Some("some sheet boundaries do not close (see `unpaired`)".into())
    } else {
        None
    }
}

/// Orders a loop's arcs so consecutive arcs share a node (for the report; the count does not
/// depend on it).
fn order_loop(arcs: &[Arc], members: &[usize]) -> Vec<usize> {
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
fn sorted_pair(a: Element, b: Element) -> [Element; 2] {
    if a.to_string() <= b.to_string() {
        [a, b]
    } else {
        [b, a]
    }
}

fn name(e: BoundaryRef) -> String {
    match e {
        BoundaryRef::Seam(s) => format!("seam {s}"),
        BoundaryRef::Edge(e) => format!("rim E{e}"),
    }
}

fn node_name(n: Node) -> String {
    match n {
        Node::Junction(j) => format!("junction {j}"),
        Node::Vertex(v) => format!("vertex V{v}"),
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
        let j = Node::Junction(0);
        let (f0, f1) = (Element::Face(0), Element::Face(1));
        let (a, b, bottom) = (
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::Z,
        );
        let arc = |id: usize, t: [DVec3; 2]| Arc {
            element: BoundaryRef::Seam(id),
            solid: 0,
            ends: [Some((j, [f0, f1])), Some((Node::Vertex(id), [f0, f1]))],
            groups: [0, 1],
            closed: false,
            pair: [f0, f1],
            touch: [Some(t), None],
        };
        let twice = BTreeSet::from([(j, f0)]);
        let arcs = vec![
            arc(0, [a, bottom]),
            arc(1, [b, bottom]),
            arc(2, [bottom, a]),
            arc(3, [b, bottom]),
        ];
        let (mut uf, paired, unpaired) = pair_ends(&arcs, &twice, 1e-9);
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
        let (_, paired, unpaired) = pair_ends(&wrong, &twice, 1e-9);
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
        let (_, _, unpaired) = pair_ends(&wrong, &BTreeSet::new(), 1e-9);
        assert!(
            unpaired
                .iter()
                .any(|u| u.starts_with("junction 0: 4 arc end(s)")),
            "{unpaired:?}"
        );
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
    /// the cylinder's medial axis is its axis (degenerate), the elliptic cylinder's seams end
    /// at curvature limits.
    #[test]
    fn euler_withheld_where_sheets_are_incomplete() {
        let (_, s) = sheets_of("cylinder.step");
        assert_eq!(s.solids[0].mat_euler, None);
        assert!(s.solids[0]
            .unknown
            .as_deref()
            .unwrap()
            .contains("degenerate"));
        let (_, s) = sheets_of("elliptic_cylinder.step");
        assert_eq!(s.solids[0].mat_euler, None);
        assert!(s.solids[0]
            .unknown
            .as_deref()
            .unwrap()
            .contains("curvature"));
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
