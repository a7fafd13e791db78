//! The medial axis as a graph: its seam–junction graph checked, and the Euler characteristics
//! of each solid and of its medial axis set side by side.

use super::outcome::Verification;
use crate::classify::{Classification, VertexKind};
use crate::geom::Boundary;
use crate::medial::axis::{DegenerateEnd, DegenerateKind, MedialAxis, Seam, SeamEnd};
use crate::medial::maximal::osculating_ball;
use crate::medial::sheets::{Sheets, SolidEuler};
use crate::model::{Element, Model};
use glam::DVec3;

/// Consistency of the seam–junction graph, and the Euler characteristic of each solid next to
/// its medial axis's (which must be equal: the medial axis is a deformation retract of the
/// solid).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Topology {
    /// Junctions plus convex vertices where seams end.
    pub graph_nodes: usize,
    /// Seams (a closed seam counts as one edge with one node of its own).
    pub graph_edges: usize,
    /// Seam ends that are not a vertex, a junction, a closed loop, a curvature limit or a
    /// pinch.
    pub open_ends: usize,
    /// Generic junctions (4 segments, every seam ending there on 3) that do not have exactly
    /// 4 seam ends, and seam ends naming a junction that does not exist: both would be
    /// tracer bugs.
    pub inconsistencies: Vec<String>,
    /// Per solid: `V − E + F` of the B-rep and `V − E + Σ χ(sheet)` of its medial axis.
    pub euler: Vec<SolidEuler>,
    /// Sheet-boundary arc ends that could not be paired at a node (tracer gaps).
    pub unpaired: Vec<String>,
    /// Arc ends at a ball where rounds' axes end that the segments they name do not pair
    /// (the count is withheld there; see `Sheets::untold`).
    pub untold: Vec<String>,
}

/// Checks the seam–junction graph of `mat`, and takes the Euler characteristics and the
/// unpaired sheet-boundary ends from its `sheets`.
pub fn check_topology(mat: &MedialAxis, sheets: &Sheets) -> Topology {
    let mut ends_at = vec![0usize; mat.junctions.len()];
    // Junctions where a non-generic seam (four or more contacts round it) ends: there it
    // may split into two seams of three (a package body's corner seam at a lead's edge),
    // and the sheets round it, not a count of seams, say whether the junction is complete.
    let mut non_generic_end = vec![false; mat.junctions.len()];
    let mut vertices = std::collections::BTreeSet::new();
    let mut inconsistencies = vec![];
    let mut open_ends = 0;
    let mut closed = 0;
    for s in &mat.seams {
        for (k, e) in s.ends.iter().enumerate() {
            let segments = if k == 0 { &s.segments } else { &s.end_segments };
            match e {
                SeamEnd::Junction(j) if *j < ends_at.len() => {
                    ends_at[*j] += 1;
                    non_generic_end[*j] |= segments.len() > 3;
                }
                SeamEnd::Junction(j) => {
                    inconsistencies.push(format!("seam {} ends at missing junction {j}", s.id))
                }
                SeamEnd::Vertex(v) => {
                    vertices.insert(*v);
                }
                SeamEnd::Open(_) => open_ends += 1,
                SeamEnd::Closed => closed += 1,
                SeamEnd::CurvatureLimit { .. } | SeamEnd::Pinch { .. } => {}
            }
        }
    }
    for (j, n) in ends_at.iter().enumerate() {
        if mat.junctions[j].segments.len() == 4 && !non_generic_end[j] && *n != 4 {
            inconsistencies.push(format!("junction {j} (4 segments) has {n} seam ends"));
        }
    }
    Topology {
        graph_nodes: mat.junctions.len() + vertices.len() + closed / 2,
        graph_edges: mat.seams.len(),
        open_ends,
        inconsistencies,
        euler: sheets.solids.clone(),
        unpaired: sheets.unpaired.clone(),
        untold: sheets.untold.clone(),
    }
}

/// True when every element, vertex and solid `axis` names exists in `model` (a report read
/// back may name anything); each one that does not is a failure.
pub(super) fn check_elements(model: &Model, axis: &MedialAxis, v: &mut Verification) -> bool {
    let exists = |e: &Element| match *e {
        Element::Face(i) => i < model.faces.len(),
        Element::Edge(i) => i < model.edges.len(),
        Element::Vertex(i) => i < model.vertices.len(),
    };
    let mut all = true;
    let mut check = |v: &mut Verification, ok: bool, what: &dyn Fn() -> String| {
        all &= ok;
        v.record("elements", ok, what);
    };
    for s in &axis.seams {
        let named = s
            .segments
            .iter()
            .chain(&s.end_segments)
            .chain(s.handovers.iter().flat_map(|h| [&h.from, &h.to]))
            .chain(s.ends.iter().flat_map(|e| match e {
                SeamEnd::CurvatureLimit { segment } => std::slice::from_ref(segment),
                SeamEnd::Pinch { segments, .. } => &segments[..],
                _ => &[],
            }));
        for e in named {
            check(v, exists(e), &|| {
                format!("seam {} names {e}, which the part lacks", s.id)
            });
        }
        for e in &s.ends {
            if let SeamEnd::Vertex(k) | SeamEnd::Pinch { vertex: k, .. } = e {
                let ok = *k < model.vertices.len();
                check(v, ok, &|| {
                    format!("seam {} ends at vertex V{k}, which the part lacks", s.id)
                });
            }
        }
        // Three elements, or more at a non-generic seam: as many at its end and at every
        // point as at its start.
        let k = s.segments.len();
        let slots =
            k >= 3 && s.end_segments.len() == k && s.points.iter().all(|p| p.touch.len() == k);
        check(v, slots, &|| {
            format!(
                "seam {} does not name three or more elements, as many at each point",
                s.id
            )
        });
        check(v, s.solid < model.solids.len(), &|| {
            format!(
                "seam {} is in solid {}, which the part lacks",
                s.id, s.solid
            )
        });
    }
    for j in &axis.junctions {
        for e in &j.segments {
            check(v, exists(e), &|| {
                format!("junction {} names {e}, which the part lacks", j.id)
            });
        }
        check(v, j.solid < model.solids.len(), &|| {
            format!(
                "junction {} is in solid {}, which the part lacks",
                j.id, j.solid
            )
        });
    }
    for (i, k) in axis.skeletal_edges.iter().enumerate() {
        for e in &k.segments {
            check(v, exists(e), &|| {
                format!("skeletal edge {i} names {e}, which the part lacks")
            });
        }
        let ok = k.id == i
            && k.vertex < model.vertices.len()
            && k.solid < model.solids.len()
            && k.starts
                .iter()
                .all(|&[s, end]| s < axis.seams.len() && end < 2);
        check(v, ok, &|| {
            format!(
                "skeletal edge {i} (id {}) names a vertex, solid or seam end the part or the \
                 report lacks",
                k.id
            )
        });
    }
    for (i, d) in axis.degenerate.iter().enumerate() {
        for e in &d.segments {
            check(v, exists(e), &|| {
                format!("degenerate {i} names {e}, which the part lacks")
            });
        }
        check(v, d.solid < model.solids.len(), &|| {
            format!(
                "degenerate {i} is in solid {}, which the part lacks",
                d.solid
            )
        });
        for end in &d.ends {
            let ok = match end {
                DegenerateEnd::Meets { element, .. } => exists(element),
                DegenerateEnd::Vanishes { vertex } => *vertex < model.vertices.len(),
                DegenerateEnd::Shrinks { element, .. } => exists(element),
                _ => true,
            };
            check(v, ok, &|| {
                format!("degenerate {i} ends at an element the part lacks")
            });
        }
    }
    all
}

/// True when end `k` of seam `s`, a pinch of `segments` at vertex `vertex`, has the touch
/// points on those two elements at the vertex, to the accuracy. An element may hold two of
/// the end's touch points (a seam of an edge and a face touched twice, pinched where the edge
/// meets the face): any touch point on each will do.
fn pinch_at_vertex(
    model: &Model,
    s: &Seam,
    k: usize,
    segments: &[Element; 2],
    vertex: usize,
    accuracy: f64,
) -> bool {
    let (point, elements) = s.at_end(k);
    let (Some(point), Some(at)) = (point, model.vertices.get(vertex)) else {
        return false;
    };
    let there = |i: usize| {
        point
            .touch
            .get(i)
            .is_some_and(|t| DVec3::from_array(*t).distance(at.point) <= accuracy)
    };
    let slots = |e: Element| (0..elements.len()).filter(move |&i| elements[i] == e);
    slots(segments[0]).any(|a| there(a) && slots(segments[1]).any(|b| b != a && there(b)))
}

/// Checks the graph of `axis` into `v`: proper seam ends, junctions with their seams, the
/// Euler characteristics where they are counted (the sheets found afresh), every face of every
/// solid touched by some ball, every convex vertex the end of a seam.
pub(super) fn check_graph(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    axis: &MedialAxis,
    v: &mut Verification,
) {
    for s in &axis.seams {
        for (k, e) in s.ends.iter().enumerate() {
            let proper = match e {
                SeamEnd::Open(_) => false,
                SeamEnd::Pinch { segments, vertex } => {
                    pinch_at_vertex(model, s, k, segments, *vertex, v.accuracy)
                }
                _ => true,
            };
            v.record("seam_ends", proper, || match e {
                SeamEnd::Open(why) => format!("seam {} end {k} is open: {why}", s.id),
                SeamEnd::Pinch { segments, vertex } => format!(
                    "seam {} end {k}: a pinch of {} and {} at V{vertex}, but their touch \
                     points are not there",
                    s.id, segments[0], segments[1]
                ),
                _ => String::new(),
            });
        }
    }
    let sheets = crate::medial::sheets::sheets(model, class, axis);
    let topology = check_topology(axis, &sheets);
    let graph_checks = axis.junctions.len() + axis.seams.len();
    for i in 0..graph_checks.max(topology.inconsistencies.len()) {
        let bad = topology.inconsistencies.get(i);
        v.record("junction_seams", bad.is_none(), || {
            bad.cloned().unwrap_or_default()
        });
    }
    // A sheet's boundary that does not close (an arc end no other pairs at its node) is a
    // piece of the medial axis not found (an untraced skeletal edge, a seam not traced).
    for u in &topology.unpaired {
        v.record("sheets_closed", false, || {
            format!("sheet boundary open at {u}")
        });
    }
    if topology.unpaired.is_empty() {
        v.record("sheets_closed", true, String::new);
    }
    for e in &topology.euler {
        match e.mat_euler {
            Some(chi) => v.record("euler", chi == e.solid_euler, || {
                format!(
                    "solid {}: the medial axis has Euler characteristic {chi}, the solid {}",
                    e.solid, e.solid_euler
                )
            }),
            None => v.euler_withheld.push(format!(
                "solid {}: {}",
                e.solid,
                e.unknown.as_deref().unwrap_or("not counted")
            )),
        }
    }
    check_skeletal_edges(model, axis, v);
    super::limits::check_curvature_limits(model, boundary, axis, v);
    check_degenerate_ends(model, boundary, axis, v);
    check_faces_touched(model, class, boundary, axis, v);
    check_convex_vertices(model, class, axis, v);
}

/// Every skeletal edge at a vertex starts where its seams end (at a curvature limit or a
/// pinch, on its first ball, with the two touch points of its segments at its vertex) and
/// runs straight to the vertex (its last ball there, `r = 0`), all to the accuracy.
fn check_skeletal_edges(model: &Model, axis: &MedialAxis, v: &mut Verification) {
    let a = v.accuracy;
    for k in &axis.skeletal_edges {
        let at = model.vertices[k.vertex].point;
        let ball = |b: &[f64; 4]| (DVec3::new(b[0], b[1], b[2]), b[3]);
        let (Some(first), Some(last)) = (k.balls.first(), k.balls.last()) else {
            v.record("skeletal_edges", false, || {
                format!("skeletal edge {} has no balls", k.id)
            });
            continue;
        };
        let (c0, r0) = ball(first);
        let (c1, r1) = ball(last);
        let reaches = c1.distance(at) <= a && r1.abs() <= a;
        // Straight: every centre on the line from the first to the vertex.
        let along = (at - c0).normalize_or_zero();
        let straight = k.balls.iter().all(|b| {
            let (c, _) = ball(b);
            let off = (c - c0) - along * (c - c0).dot(along);
            off.length() <= a
        });
        v.record("skeletal_edges", reaches && straight, || {
            format!(
                "skeletal edge {}: does not run straight to V{} (last ball {c1} r {r1:e})",
                k.id, k.vertex
            )
        });
        // A free edge where a rim's sheet ends starts on the degenerate curves it names, at
        // ball `i` of each or between its balls `i` and `i + 1` (the emptiness search finds
        // that ball to a fraction of the accuracy, the curve's balls are found to it: they
        // agree to four accuracies).
        for &[d, i] in &k.meets {
            let on = axis.degenerate.get(d).is_some_and(|g| {
                let piece = g.balls.get(i..(i + 2).min(g.balls.len())).unwrap_or(&[]);
                g.kind == DegenerateKind::Curve
                    && crate::medial::axis::ball_on_polyline(piece, c0, r0, 4.0 * a).is_some()
            });
            v.record("skeletal_edges", on, || {
                format!(
                    "skeletal edge {}: its first ball is not on degenerate {d} at its ball {i}",
                    k.id
                )
            });
        }
        for &[s, end] in &k.starts {
            let seam = &axis.seams[s];
            let (point, segs) = seam.at_end(end);
            let kind_ok = matches!(
                seam.ends[end],
                SeamEnd::CurvatureLimit { .. } | SeamEnd::Pinch { .. }
            );
            let met = point.is_some_and(|p| {
                let (c, r) = ball(&p.point);
                let at_v = |i: usize, e: Element| {
                    segs.get(i) == Some(&e)
                        && p.touch
                            .get(i)
                            .is_some_and(|t| DVec3::from_array(*t).distance(at) <= a)
                };
                let [e0, e1] = k.segments;
                let both = (0..segs.len())
                    .any(|i| at_v(i, e0) && (0..segs.len()).any(|j| j != i && at_v(j, e1)));
                c.distance(c0) <= a && (r - r0).abs() <= a && both
            });
            v.record("skeletal_edges", kind_ok && met, || {
                format!(
                    "skeletal edge {}: seam {s} end {end} is not a curvature limit or pinch \
                     at its first ball with touch points on {} and {} at V{}",
                    k.id, k.segments[0], k.segments[1], k.vertex
                )
            });
        }
    }
}

/// Every degenerate curve is traced to its ends, and each end is located: its ball touches
/// the element it meets at its touch point (`r` from the centre, on that element), or
/// shrinks to `r = 0` at its vertex, or the curve closes (its last ball a step from its
/// first); all to the accuracy. An open end, or a curve only sampled, fails
/// `degenerate_ends`.
fn check_degenerate_ends(
    model: &Model,
    boundary: &Boundary,
    axis: &MedialAxis,
    v: &mut Verification,
) {
    let a = v.accuracy;
    let mut near = vec![];
    for (i, d) in axis.degenerate.iter().enumerate() {
        if d.kind != DegenerateKind::Curve {
            continue;
        }
        let ball = |b: &[f64; 4]| (DVec3::new(b[0], b[1], b[2]), b[3]);
        let shape = matches!(d.ends.as_slice(), [DegenerateEnd::Closed])
            || (d.ends.len() == 2 && !d.ends.contains(&DegenerateEnd::Closed));
        v.record("degenerate_ends", shape && !d.balls.is_empty(), || {
            format!("degenerate {i} is not traced to two ends or round a loop (sampled only)")
        });
        if !shape || d.balls.is_empty() {
            continue;
        }
        for (k, end) in d.ends.iter().enumerate() {
            let (c, r) = ball(if k == 0 {
                &d.balls[0]
            } else {
                &d.balls[d.balls.len() - 1]
            });
            let (ok, what) = match end {
                DegenerateEnd::Meets { element, touch, .. } => {
                    let t = DVec3::from_array(*touch);
                    boundary.within_into(model, t, a, &mut near);
                    let faces = element.faces(model);
                    let on = near.iter().any(|f| faces.contains(f));
                    (
                        on && (c.distance(t) - r).abs() <= a,
                        format!("its ball does not touch {element} at {t}"),
                    )
                }
                DegenerateEnd::Vanishes { vertex } => {
                    let at = model.vertices.get(*vertex).map(|p| p.point);
                    (
                        at.is_some_and(|p| c.distance(p) <= a) && r.abs() <= a,
                        format!("its ball (r {r:e}) is not V{vertex}"),
                    )
                }
                DegenerateEnd::Shrinks { element, touch } => {
                    // The ball osculating one of the curve's faces at the point, which is on
                    // the element named (a vertex or an edge of that face).
                    let t = DVec3::from_array(*touch);
                    let on = match *element {
                        Element::Vertex(v) => model.vertices[v].point.distance(t) <= a,
                        Element::Edge(e) => crate::geom::nearest_on_edge(model, e, t, None).2 <= a,
                        Element::Face(_) => false,
                    };
                    let faces = element.faces(model);
                    let osculates = on
                        && d.segments
                            .iter()
                            .flat_map(|s| s.faces(model))
                            .filter(|f| faces.contains(f))
                            .any(|f| {
                                osculating_ball(model, f, t).is_some_and(|(cv, rv, _)| {
                                    c.distance(cv) <= a && (r - rv).abs() <= a
                                })
                            });
                    (
                        osculates,
                        format!(
                            "its ball (centre {c}, r {r:e}) does not osculate its face at {t} \
                             on {element}"
                        ),
                    )
                }
                DegenerateEnd::Closed => {
                    let (first, _) = ball(&d.balls[0]);
                    let step = d
                        .balls
                        .windows(2)
                        .map(|w| ball(&w[0]).0.distance(ball(&w[1]).0))
                        .fold(0.0, f64::max);
                    (
                        d.balls.len() > 2 && c.distance(first) <= 1.5 * step + a,
                        "it does not come back to its first ball".into(),
                    )
                }
                DegenerateEnd::Open { reason, .. } => (false, format!("open: {reason}")),
            };
            v.record("degenerate_ends", ok, || {
                format!("degenerate {i} end {k}: {what}")
            });
        }
    }
}

/// Every face of every solid is touched by some ball: a face no touch point is on (to the
/// accuracy), and no ball reaches (within `r + a` of its centre), is a part of the boundary
/// the medial axis has not reached. Faces joined across smooth edges count as one surface
/// (the medial axis does not see a smooth edge): a hemispherical end blending into a tube's
/// wall is touched only by the balls of the wall's sheet, which no seam or junction need
/// reach, and passes when the wall is touched.
fn check_faces_touched(
    model: &Model,
    class: &Classification,
    boundary: &Boundary,
    axis: &MedialAxis,
    v: &mut Verification,
) {
    let a = v.accuracy;
    let mut touched = vec![false; model.faces.len()];
    let points = axis
        .seams
        .iter()
        .flat_map(|s| s.points.iter().flat_map(|p| p.touch.iter()))
        .chain(axis.junctions.iter().flat_map(|j| j.touch.iter()))
        .chain(
            axis.degenerate
                .iter()
                .flat_map(|d| d.touch.iter().flatten()),
        )
        .chain(axis.degenerate.iter().flat_map(|d| {
            d.ends.iter().filter_map(|e| match e {
                DegenerateEnd::Meets { touch, .. } | DegenerateEnd::Shrinks { touch, .. } => {
                    Some(touch)
                }
                _ => None,
            })
        }));
    let mut near = vec![];
    for t in points {
        let t = DVec3::from_array(*t);
        if !t.is_finite() {
            continue;
        }
        boundary.within_into(model, t, a, &mut near);
        for &f in &near {
            touched[f] = true;
        }
    }
    let surface = class.smooth_surfaces(model);
    let mut surface_touched = vec![false; model.faces.len()];
    for (f, &hit) in touched.iter().enumerate() {
        surface_touched[surface[f]] |= hit;
    }
    // A face no touch point is on may still be touched by a ball at a place the report does
    // not list (a bead's fillet axis whose balls reach the flat bottom under it: the ball
    // touches the bottom at one point besides its arc on the torus): the face within r + a
    // of a ball's centre, in the ball's solid, is touched (the balls are checked empty).
    if (0..model.faces.len()).any(|f| !surface_touched[surface[f]]) {
        let balls = axis
            .seams
            .iter()
            .flat_map(|s| s.points.iter().map(|p| (s.solid, p.point)))
            .chain(
                axis.junctions
                    .iter()
                    .map(|j| (j.solid, [j.point[0], j.point[1], j.point[2], j.radius])),
            )
            .chain(
                axis.degenerate
                    .iter()
                    .flat_map(|d| d.balls.iter().map(|b| (d.solid, *b))),
            );
        for (solid, b) in balls {
            let (c, r) = (DVec3::new(b[0], b[1], b[2]), b[3]);
            if !(c.is_finite() && r.is_finite()) {
                continue;
            }
            boundary.within_into(model, c, r + a, &mut near);
            for &f in &near {
                if model.solid_of_face(f) == solid {
                    surface_touched[surface[f]] = true;
                }
            }
        }
    }
    if (0..model.faces.len()).any(|f| !surface_touched[surface[f]]) {
        reach_across_reflex_edges(
            model,
            class,
            boundary,
            axis,
            a,
            &surface,
            &mut surface_touched,
        );
    }
    for f in 0..model.faces.len() {
        v.record("faces_touched", surface_touched[surface[f]], || {
            format!(
                "face F{f} (solid {}) is touched by no ball (nor is any face joined to it \
                 across smooth edges, nor does its sheet run on across its reflex edges to \
                 balls that are)",
                model.solid_of_face(f)
            )
        });
    }
}

/// Marks in `surface_touched` the smooth surfaces (`surface`, by least face) no ball touches
/// whose sheet runs on across reflex edges to balls that are listed. A face whose every
/// neighbour across its edges is reached through a reflex edge (a pocket's floor, the
/// plate under it thinner than the pocket's walls are far apart) may be touched by sheet
/// balls only: the ball touching the floor and the plate's bottom moves on, as it passes the
/// floor's edge, to touching that edge and then the pocket's wall, with the bottom all along,
/// and the seams bounding that sheet touch the walls, not the floor. So for a face `f` no
/// ball touches: at points of it (a grid over its domain, up to 8×8 on the face), the largest
/// ball inside the solid touching it there (centre on the inward normal) touches the boundary
/// at one other place `q`; the face is reached when a listed ball touches both a face within
/// the accuracy of `q` and a face of `f`'s reflex group (faces joined to it across reflex and
/// smooth edges), other than those: the sheet between them is the one `f`'s balls are on.
fn reach_across_reflex_edges(
    model: &Model,
    class: &Classification,
    boundary: &Boundary,
    axis: &MedialAxis,
    a: f64,
    surface: &[usize],
    surface_touched: &mut [bool],
) {
    use crate::classify::EdgeKind;
    use crate::medial::equations::NormalField;
    let group = class.faces_joined_by(model, &[EdgeKind::Smooth, EdgeKind::Reflex]);
    // The faces each listed ball touches (within the accuracy of a touch point).
    let mut near = vec![];
    let balls: Vec<Vec<usize>> = axis
        .seams
        .iter()
        .flat_map(|s| s.points.iter().map(|p| &p.touch))
        .chain(axis.junctions.iter().map(|j| &j.touch))
        .map(|touch| {
            let mut faces = vec![];
            for t in touch.iter().map(|t| DVec3::from_array(*t)) {
                if t.is_finite() {
                    boundary.within_into(model, t, a, &mut near);
                    faces.extend(&near);
                }
            }
            faces.sort_unstable();
            faces.dedup();
            faces
        })
        .collect();
    let diagonal = model.diagonal();
    for f in 0..model.faces.len() {
        if surface_touched[surface[f]] {
            continue;
        }
        let solid = model.solid_of_face(f);
        let face = &model.faces[f];
        let d = face.domain;
        let n = SHEET_SAMPLE_GRID;
        let reached = (0..n * n).any(|k| {
            let at = |i: usize| (i as f64 + 0.5) / n as f64;
            let uv = [
                d.u.0 + (d.u.1 - d.u.0) * at(k % n),
                d.v.0 + (d.v.1 - d.v.0) * at(k / n),
            ];
            if !crate::geom::trim::contains(face, glam::DVec2::from_array(uv)) {
                return false;
            }
            let Some(ev) = Element::Face(f).eval(model, uv) else {
                return false;
            };
            let Some(q) = other_contact(model, boundary, solid, ev.p, ev.n, diagonal, a) else {
                return false;
            };
            boundary.within_into(model, q, a, &mut near);
            let across: Vec<usize> = near
                .iter()
                .copied()
                .filter(|&g| model.solid_of_face(g) == solid && group[g] != group[f])
                .collect();
            !across.is_empty()
                && balls.iter().any(|b| {
                    b.iter().any(|g| across.contains(g)) && b.iter().any(|&g| group[g] == group[f])
                })
        });
        if reached {
            surface_touched[surface[f]] = true;
        }
    }
}

/// Cells a side of the grid over a face's domain at whose centres on the face
/// [`reach_across_reflex_edges`] grows balls.
const SHEET_SAMPLE_GRID: usize = 8;

/// The place other than `p` where the largest ball inside solid `solid` touching its boundary
/// at `p` (outward normal `n`, centre `p − r·n`) touches it: the nearest boundary point to the
/// centre of a ball just bigger (by bisection on `r` to 1e-12 of the diagonal). `None` where
/// that point is within `√(8·r·a)` of `p` (the ball osculates the face there: no second place).
fn other_contact(
    model: &Model,
    boundary: &Boundary,
    solid: usize,
    p: DVec3,
    n: DVec3,
    diagonal: f64,
    a: f64,
) -> Option<DVec3> {
    let nearest = |c: DVec3| {
        boundary
            .nearest_face_where(model, c, |g| model.solid_of_face(g) == solid)
            .map(|(_, h)| h)
    };
    let fits = |r: f64| nearest(p - n * r).is_some_and(|h| h.distance >= r * (1.0 - 1e-9));
    let (mut lo, mut hi) = (0.0, diagonal);
    while hi - lo > 1e-12 * diagonal {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let q = nearest(p - n * hi)?.point;
    (q.distance(p) > crate::medial::verify::separation(lo, a)).then_some(q)
}

/// Every convex vertex ends a seam (the ball shrinks to nothing there).
fn check_convex_vertices(
    model: &Model,
    class: &Classification,
    axis: &MedialAxis,
    v: &mut Verification,
) {
    let mut ends = vec![false; model.vertices.len()];
    for s in &axis.seams {
        for e in &s.ends {
            if let SeamEnd::Vertex(k) | SeamEnd::Pinch { vertex: k, .. } = e {
                if let Some(x) = ends.get_mut(*k) {
                    *x = true;
                }
            }
        }
    }
    for (k, kind) in class.vertices.iter().enumerate() {
        if *kind == VertexKind::Convex {
            v.record("convex_vertices", ends[k], || {
                format!("convex vertex V{k} ends no seam")
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::axis::{Junction, SeamPoint};
    use crate::testing::sample;

    /// A seam ending in a pinch at vertex 0 of the box, its last touch points `touch` on the
    /// elements `at_end`.
    fn pinched(at_end: Vec<Element>, touch: Vec<[f64; 3]>, segments: [Element; 2]) -> Seam {
        Seam {
            id: 0,
            solid: 0,
            segments: at_end.clone(),
            ends: [
                SeamEnd::Closed,
                SeamEnd::Pinch {
                    segments,
                    vertex: 0,
                },
            ],
            end_segments: at_end,
            points: vec![SeamPoint {
                point: [1.0, 1.0, 1.0, 1.0],
                touch,
            }],
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        }
    }

    /// A junction of four segments where three seams of three end is missing one; where a
    /// seam of four contacts (round a pocket's chamfered corner) ends and splits into two
    /// seams of three, three seam ends are all there are.
    #[test]
    fn a_junction_where_a_non_generic_seam_splits_has_three_seam_ends() {
        let (e, f, g, h) = (
            Element::Edge(0),
            Element::Face(1),
            Element::Face(2),
            Element::Face(3),
        );
        let seam = |segments: Vec<Element>, end: usize| Seam {
            id: 0,
            solid: 0,
            segments: segments.clone(),
            ends: [SeamEnd::Junction(0), SeamEnd::Vertex(end)],
            end_segments: segments.clone(),
            points: vec![],
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        };
        let axis = |seams: Vec<Seam>| MedialAxis {
            seams,
            junctions: vec![Junction {
                id: 0,
                solid: 0,
                point: [0.0; 3],
                radius: 1.0,
                segments: vec![e, f, g, h],
                touch: vec![[0.0; 3]; 4],
                unresolved: false,
            }],
            degenerate: vec![],
            skeletal_edges: vec![],
            stats: Default::default(),
        };
        let sheets = Sheets::default();
        let generic = axis(vec![
            seam(vec![e, f, g], 0),
            seam(vec![e, f, h], 1),
            seam(vec![f, g, h], 2),
        ]);
        assert_eq!(
            check_topology(&generic, &sheets).inconsistencies,
            ["junction 0 (4 segments) has 3 seam ends"]
        );
        let split = axis(vec![
            seam(vec![e, f, g, h], 0),
            seam(vec![e, f, h], 1),
            seam(vec![f, g, h], 2),
        ]);
        assert!(check_topology(&split, &sheets).inconsistencies.is_empty());
    }

    /// The pinch's two elements may each hold more than one touch point: the one at the
    /// vertex counts, whichever slot it is in; a pinch whose touch points on one of its
    /// elements are all away from the vertex is refused.
    #[test]
    fn a_pinch_is_at_its_vertex_whichever_slot_holds_the_touch_point_there() {
        let model = sample("box.step");
        let v = model.vertices[0].point.to_array();
        let away = [v[0] + 1.0, v[1] + 1.0, v[2] + 1.0];
        let (e, f) = (Element::Edge(0), Element::Face(0));
        let check = |s: &Seam| pinch_at_vertex(&model, s, 1, &[e, f], 0, 1e-6);
        // The face twice, its first slot away from the vertex (as a seam of an edge and a
        // face touched twice, where the edge meets that face).
        assert!(check(&pinched(vec![e, f, f], vec![v, away, v], [e, f])));
        assert!(check(&pinched(vec![e, f, f], vec![v, v, away], [e, f])));
        assert!(check(&pinched(vec![f, e, f], vec![away, v, v], [e, f])));
        // Neither of the face's touch points at the vertex, or the edge's not.
        assert!(!check(&pinched(vec![e, f, f], vec![v, away, away], [e, f])));
        assert!(!check(&pinched(vec![e, f, f], vec![away, v, v], [e, f])));
        // One touch point cannot stand for both elements.
        assert!(!check(&pinched(
            vec![e, f, Element::Face(1)],
            vec![v, away, v],
            [e, f]
        )));
    }
}
