//! Folds: edges whose two faces are tangent with opposite normals, folded back onto each
//! other — a fin of no thickness (interior angle 0°) or a crack of no width (360°). Which of
//! the two an edge is, the faces' normals cannot say (`b1·n2`, the sine by which face 2 leaves
//! face 1's tangent plane, is rounding there); the faces' second-order separation does: a
//! point a short way into face 1 is projected onto both surfaces, and the feet compared along
//! face 1's normal ([`fold_is_fin`]). The classifier decides a fold's kind so, the
//! point-in-solid test reads it where an edge's pseudo-normal vanishes
//! ([`past_fold_is_material`]), and the tracer takes a crack's arc of normals to be the half
//! its faces leave towards ([`into_first_face`]).

use super::eval::{eval_surface, surface_point};
use super::project::project_point;
use crate::model::Model;
use glam::DVec3;
use truck_geometry::prelude::ParametricCurve;

/// The distance, relative to the edge's chord, at which [`fold_is_fin`] compares the faces.
const FOLD_PROBE_REL: f64 = 1e-2;

/// Where face `face` uses edge `edge`: the direction of its loop along the edge (`true` =
/// along the curve), for each use (a seam is used twice).
pub fn loop_directions(model: &Model, face: usize, edge: usize) -> Vec<bool> {
    model.faces[face]
        .loops
        .iter()
        .flat_map(|l| &l.edges)
        .filter(|oe| oe.edge == edge)
        .map(|oe| oe.forward)
        .collect()
}

/// The point and unit tangent of edge `e` at curve parameter `t`.
pub fn edge_point(model: &Model, e: usize, t: f64) -> (DVec3, DVec3) {
    let curve = &model.edges[e].curve;
    let (c, d) = (curve.subs(t), curve.der(t));
    (
        DVec3::new(c.x, c.y, c.z),
        DVec3::new(d.x, d.y, d.z).normalize_or_zero(),
    )
}

/// Face `f`'s normals at parameters `uv`: the outward one, and the one its loops run
/// anticlockwise about (the surface's, turned by the face's `same_sense`).
pub fn face_normals(model: &Model, f: usize, uv: (f64, f64)) -> (DVec3, DVec3) {
    let face = &model.faces[f];
    let s = eval_surface(&face.surface, uv.0, uv.1);
    let raw = s.su.cross(s.sv).normalize_or_zero();
    (raw * face.sign, if face.same_sense { raw } else { -raw })
}

/// The direction into face `f` square to its edge `e` at the point `p` of it (`tangent`, the
/// edge's direction there; `uv`, `p`'s parameters on the face): the face lies to the left of
/// its loop's direction along the edge, seen against its anticlockwise normal.
fn into_face(model: &Model, e: usize, f: usize, tangent: DVec3, uv: (f64, f64)) -> Option<DVec3> {
    let dir = loop_directions(model, f, e).first().copied()?;
    let travel = if dir { tangent } else { -tangent };
    let b = face_normals(model, f, uv)
        .1
        .cross(travel)
        .normalize_or_zero();
    (b != DVec3::ZERO).then_some(b)
}

/// The direction into edge `e`'s first face from its point at curve parameter `t`, square to
/// the edge in the face's tangent plane (`hint`: a start for the point's parameters on the
/// face). At a fold of 360° both faces leave the edge that way: it is the middle of the
/// edge's arc of normals, which the faces' opposite normals leave undecided.
pub fn into_first_face(model: &Model, e: usize, t: f64, hint: Option<(f64, f64)>) -> Option<DVec3> {
    let f = model.edges[e].faces[0];
    let (p, tangent) = edge_point(model, e, t);
    let uv = project_point(&model.faces[f].surface, p, hint)?;
    into_face(model, e, f, tangent, uv)
}

/// At the point `p` of edge `e` (`tangent`, its direction there), where its two faces are
/// tangent with opposite normals (`n1`, face 1's outward normal; `b1`, the direction into
/// face 1 across the edge; `hints`, `p`'s parameters on the two faces), whether face 2
/// leaves behind face 1 — on the material's side of it, a fin of no thickness — or in front
/// of it, a crack of no width. `None` where the faces do not leave the edge the same way (a
/// surface continued with its normal flipped) or coincide to the second order.
pub fn fold_is_fin(
    model: &Model,
    e: usize,
    p: DVec3,
    tangent: DVec3,
    n1: DVec3,
    b1: DVec3,
    hints: &[Option<(f64, f64)>; 2],
) -> Option<bool> {
    let edge = &model.edges[e];
    let (f1, f2) = (edge.faces[0], edge.faces[1]);
    let b2 = into_face(model, e, f2, tangent, hints[1]?)?;
    if b1.dot(b2) < 0.5 {
        return None;
    }
    let at = |t: f64| edge_point(model, e, t).0;
    let (c0, cm, c1) = (
        at(edge.range.0),
        at(0.5 * (edge.range.0 + edge.range.1)),
        at(edge.range.1),
    );
    let chord = c0.distance(cm) + cm.distance(c1);
    let m = p + b1 * (FOLD_PROBE_REL * chord);
    let foot = |f: usize, hint: Option<(f64, f64)>| {
        let s = &model.faces[f].surface;
        project_point(s, m, hint).map(|uv| surface_point(s, uv.0, uv.1))
    };
    let d = (foot(f2, hints[1])? - foot(f1, hints[0])?).dot(n1);
    let noise = 1e-9 * (1.0 + p.abs().max_element());
    (d.abs() > noise).then_some(d < 0.0)
}

/// Whether the points past fold edge `e` at its parameter `t` (whose nearest boundary point
/// is there) are material: past a crack's bottom they are, past a fin's tip they are not
/// (`hints`: starts for the point's parameters on the edge's two faces). `None` where
/// [`fold_is_fin`] cannot tell.
pub fn past_fold_is_material(
    model: &Model,
    e: usize,
    t: f64,
    hints: [Option<(f64, f64)>; 2],
) -> Option<bool> {
    let edge = &model.edges[e];
    let (p, tangent) = edge_point(model, e, t);
    let uv1 = project_point(&model.faces[edge.faces[0]].surface, p, hints[0])?;
    let uv2 = project_point(&model.faces[edge.faces[1]].surface, p, hints[1])?;
    let n1 = face_normals(model, edge.faces[0], uv1).0;
    let b1 = into_face(model, e, edge.faces[0], tangent, uv1)?;
    fold_is_fin(model, e, p, tangent, n1, b1, &[Some(uv1), Some(uv2)]).map(|fin| !fin)
}
