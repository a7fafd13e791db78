//! Where a boundary point lies on a face, and the outward normal of the boundary there: the
//! parameters of an edge or vertex point on an adjacent face's surface (a projection, retried
//! without its hint when that lands off the point), the face normal at a parameter point
//! (moved off a pole or apex), and the angle-weighted pseudo-normals at the vertices that
//! point-in-solid reads.

use crate::geom::eval::{eval_curve, eval_surface};
use crate::geom::project::project_plane;
use crate::geom::trim::covered_domain;
use crate::geom::{project_point, unit_normal};
use crate::model::{Edge, Face, Model, Surface};
use glam::{DVec2, DVec3};

/// How far (relative to the coordinates' size) a boundary point may be from a face's surface
/// before its projection is retried: real files carry gaps of 1e-6..1e-4 of their size.
pub const EDGE_ON_SURFACE_REL_COORD: f64 = 1e-4;

/// Normals averaged around a pole or apex for its pseudo-normal.
pub const POLE_NORMAL_SAMPLES: usize = 8;

/// Parameters of a boundary point `x` on a face's surface: the projection from `hint`, retried
/// without a hint when that lands farther than [`EDGE_ON_SURFACE_REL_COORD`] (relative to the
/// coordinates' size) from `x` (a hint across a seam or a pole can lead to another foot). NaN when
/// no projection is found.
pub(super) fn surface_params(surface: &Surface, x: DVec3, hint: Option<(f64, f64)>) -> (f64, f64) {
    let off = |uv: (f64, f64)| crate::geom::surface_point(surface, uv.0, uv.1).distance(x);
    let tol = EDGE_ON_SURFACE_REL_COORD * (1.0 + x.abs().max_element());
    let first = project_point(surface, x, hint);
    if let Some(uv) = first {
        if off(uv) <= tol {
            return uv;
        }
    }
    let second = hint.and_then(|_| project_point(surface, x, None));
    match (first, second) {
        (Some(a), Some(b)) => {
            if off(b) < off(a) {
                b
            } else {
                a
            }
        }
        (a, b) => a.or(b).unwrap_or((f64::NAN, f64::NAN)),
    }
}

/// Unit outward normal of `face` at `uv`; at a singular point (a pole, an apex) the normal
/// of a point moved slightly towards the domain's centre.
pub fn face_normal(face: &Face, uv: (f64, f64)) -> Option<DVec3> {
    if let Some(n) = unit_normal(&eval_surface(&face.surface, uv.0, uv.1), face.sign) {
        return Some(n);
    }
    let d = &face.domain;
    let centre = DVec2::new(0.5 * (d.u.0 + d.u.1), 0.5 * (d.v.0 + d.v.1));
    let at = DVec2::new(uv.0, uv.1);
    [1e-7, 1e-5, 1e-3].iter().find_map(|&s| {
        let q = at + (centre - at) * s;
        unit_normal(&eval_surface(&face.surface, q.x, q.y), face.sign)
    })
}

/// Unit outward normal of `face` at its point nearest `x`: the plane's exact foot (`plane` is
/// its frame), else the projection hinted by `hint` ([`surface_params`]).
pub(super) fn normal_near(
    face: &Face,
    plane: Option<(DVec3, DVec3, DVec3)>,
    x: DVec3,
    hint: Option<(f64, f64)>,
) -> Option<DVec3> {
    let uv = match plane {
        Some(frame) => project_plane(frame, x),
        None => surface_params(&face.surface, x, hint),
    };
    face_normal(face, uv)
}

/// Angle-weighted pseudo-normals at the vertices (see the module docs of `inside.rs`), not
/// normalised: `normal_at(face, fi, x, hint)` is the unit outward normal of face `fi` at its
/// point nearest `x`, and `loop_points` are [`loop_points`] of every face.
pub(super) fn vertex_normals(
    model: &Model,
    loop_points: &[Vec<(DVec2, DVec3)>],
    normal_at: impl Fn(&Face, usize, DVec3, Option<(f64, f64)>) -> Option<DVec3>,
) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; model.vertices.len()];
    for (fi, face) in model.faces.iter().enumerate() {
        let orient = if face.same_sense { 1.0 } else { -1.0 };
        for l in &face.loops {
            if let (Some(v), Some(&pole)) = (l.vertex, l.uv.first()) {
                // A pole or apex: the face surrounds it (a full turn); its normals around
                // it average to the axis (a sphere's pole normal, a cone's axis).
                normals[v] += around_pole(face, pole) * std::f64::consts::TAU;
            }
            let n = l.edges.len();
            for k in 0..n {
                let a = l.edges[k];
                let b = l.edges[(k + 1) % n];
                let ea = &model.edges[a.edge];
                let eb = &model.edges[b.edge];
                let v = if a.forward {
                    ea.vertices[1]
                } else {
                    ea.vertices[0]
                };
                let x = model.vertices[v].point;
                let hint = nearest_loop_point(&loop_points[fi], x);
                // The loop runs up a seam edge to the vertex and straight back down it: the
                // vertex is a pole or apex the face surrounds (a drill point's tip written
                // with its seam edge), a full turn like a vertex loop's. Its corner angle as
                // two edges would be zero, and the normal there is undefined.
                if a.edge == b.edge && a.forward != b.forward {
                    if let Some(pole) = hint {
                        normals[v] +=
                            around_pole(face, DVec2::new(pole.0, pole.1)) * std::f64::consts::TAU;
                    }
                    continue;
                }
                let Some(normal) = normal_at(face, fi, x, hint) else {
                    continue;
                };
                // Loops turn counter-clockwise about this normal.
                let loop_normal = normal * (face.sign * orient);
                let d_in = end_tangent(ea, a.forward, true);
                let d_out = end_tangent(eb, b.forward, false);
                let flat = |d: DVec3| (d - loop_normal * d.dot(loop_normal)).normalize_or_zero();
                let (d_in, d_out) = (flat(d_in), flat(d_out));
                let angle = if d_in == DVec3::ZERO || d_out == DVec3::ZERO {
                    std::f64::consts::PI
                } else {
                    let turn = d_in.cross(d_out).dot(loop_normal).atan2(d_in.dot(d_out));
                    std::f64::consts::PI - turn
                };
                normals[v] += normal * angle;
            }
        }
    }
    normals
}

/// The unit mean of face `face`'s normals on a small circle about its pole or apex at `pole`
/// (parameters): the normal of the point the face surrounds (a sphere's pole, a cone's
/// axis direction).
fn around_pole(face: &Face, pole: DVec2) -> DVec3 {
    let (uc, vc) = covered_domain(face);
    let centre = DVec2::new(0.5 * (uc.0 + uc.1), 0.5 * (vc.0 + vc.1));
    let mut sum = DVec3::ZERO;
    for k in 0..POLE_NORMAL_SAMPLES {
        let a = k as f64 / POLE_NORMAL_SAMPLES as f64;
        let mut q = pole + (centre - pole) * 1e-6;
        match (face.domain.u_period, face.domain.v_period) {
            (Some(p), _) => q.x = uc.0 + a * p,
            (None, Some(p)) => q.y = vc.0 + a * p,
            (None, None) => {}
        }
        sum += face_normal(face, (q.x, q.y)).unwrap_or(DVec3::ZERO);
    }
    sum.normalize_or_zero()
}

/// Tangent of an oriented edge at its end (`at_end`) or start, in the direction of travel.
fn end_tangent(e: &Edge, forward: bool, at_end: bool) -> DVec3 {
    // Travel end = range.1 when forward.
    let t = if forward == at_end {
        e.range.1
    } else {
        e.range.0
    };
    let sense = if e.range.1 >= e.range.0 { 1.0 } else { -1.0 };
    let d = eval_curve(&e.curve, t).d1 * sense;
    if forward {
        d
    } else {
        -d
    }
}

/// The 3D points of a face's loop polygons with their UV (to seed projections).
pub(super) fn loop_points(face: &Face) -> Vec<(DVec2, DVec3)> {
    face.loops
        .iter()
        .flat_map(|l| l.uv.iter())
        .map(|&uv| (uv, crate::geom::surface_point(&face.surface, uv.x, uv.y)))
        .collect()
}

/// The parameters of the loop point nearest `x` ([`loop_points`]), to seed a projection.
pub(super) fn nearest_loop_point(points: &[(DVec2, DVec3)], x: DVec3) -> Option<(f64, f64)> {
    points
        .iter()
        .filter(|(_, q)| q.is_finite())
        .min_by(|a, b| a.1.distance_squared(x).total_cmp(&b.1.distance_squared(x)))
        .map(|(uv, _)| (uv.x, uv.y))
}
