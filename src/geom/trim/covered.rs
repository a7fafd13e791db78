//! The parameter rectangle a face covers: its UV domain, widened across loops that wrap around
//! a period to the pole beyond them that no vertex loop records (a spherical cap bounded by
//! one circle, a cone cap without its apex vertex).

use crate::geom::eval::eval_surface;
use crate::geom::project::clamp_ranges;
use crate::model::Face;
use glam::DVec2;

/// The parameter rectangle the face covers: its UV domain, except across loops that wrap around a
/// period, where the face may reach beyond its loops to a pole that no vertex loop records (a
/// spherical cap bounded by one circle: its domain is that circle's latitude alone). There the
/// rectangle takes the surface's whole bounded range (a sphere's latitudes, a B-spline's range),
/// or, in an unbounded direction (a cone), reaches to the pole beyond the loop on the face's side
/// (found by secant steps on `‖Su‖`); the trim test then tells which part is the face. Also bounds
/// [`contains`](super::contains) for faces with wrapping loops.
pub fn covered_domain(face: &Face) -> ((f64, f64), (f64, f64)) {
    let d = &face.domain;
    let (mut u, mut v) = (d.u, d.v);
    let mut wraps = [0usize; 2];
    let mut example: [Option<&[DVec2]>; 2] = [None, None];
    for l in face
        .loops
        .iter()
        .filter(|l| l.vertex.is_none() && l.uv.len() >= 2)
    {
        let poly = l.outline();
        let gap = poly[0] - poly[poly.len() - 1];
        if d.u_period.is_some_and(|p| gap.x.abs() > 0.5 * p) {
            wraps[0] += 1;
            example[0] = Some(poly);
        }
        if d.v_period.is_some_and(|p| gap.y.abs() > 0.5 * p) {
            wraps[1] += 1;
            example[1] = Some(poly);
        }
    }
    let (ur, vr) = clamp_ranges(&face.surface);
    let bounded = |r: (f64, f64)| r.0.is_finite() && r.1.is_finite();
    if wraps[0] > 0 {
        if bounded(vr) {
            v = (v.0.min(vr.0), v.1.max(vr.1));
        } else if wraps[0] % 2 == 1 {
            if let Some(pole) = example[0].and_then(|poly| pole_beyond(face, poly, false)) {
                v = (v.0.min(pole), v.1.max(pole));
            }
        }
    }
    if wraps[1] > 0 {
        if bounded(ur) {
            u = (u.0.min(ur.0), u.1.max(ur.1));
        } else if wraps[1] % 2 == 1 {
            if let Some(pole) = example[1].and_then(|poly| pole_beyond(face, poly, true)) {
                u = (u.0.min(pole), u.1.max(pole));
            }
        }
    }
    (u, v)
}

/// For a loop wrapping around the period of u (of v when `swap`): the parameter across it of
/// the pole on the face's side, where the circles of the periodic direction shrink to a
/// point (`‖Su‖ = 0`; a cone's apex). Found by secant steps on `‖Su‖` (exact for a cone, where
/// it is linear). `None` when the circles do not shrink that way.
fn pole_beyond(face: &Face, poly: &[DVec2], swap: bool) -> Option<f64> {
    let get = |p: DVec2| if swap { DVec2::new(p.y, p.x) } else { p };
    // Side of the face: left of travel (seen against the normal the loops turn about).
    let (a, b) = (get(poly[0]), get(poly[1]));
    let orient = if face.same_sense { 1.0 } else { -1.0 } * if swap { -1.0 } else { 1.0 };
    let up = (b.x - a.x) * orient > 0.0;
    let across = poly.iter().map(|&p| get(p).y);
    let start = if up {
        across.fold(f64::NEG_INFINITY, f64::max)
    } else {
        across.fold(f64::INFINITY, f64::min)
    };
    let along = a.x;
    let size = |y: f64| {
        let (u, v) = if swap { (y, along) } else { (along, y) };
        let s = eval_surface(&face.surface, u, v);
        if swap {
            s.sv.length()
        } else {
            s.su.length()
        }
    };
    let s0 = size(start);
    let step = if up { 1.0 } else { -1.0 } * 1e-3 * (1.0 + start.abs());
    let (mut y0, mut f0, mut y1, mut f1) = (start, s0, start + step, size(start + step));
    if f1.is_nan() || f0.is_nan() || f1 >= f0 {
        return None;
    }
    for _ in 0..20 {
        let y2 = y1 - f1 * (y1 - y0) / (f1 - f0);
        if !y2.is_finite() {
            return None;
        }
        let f2 = size(y2);
        (y0, f0, y1, f1) = (y1, f1, y2, f2);
        if f1 <= 1e-9 * s0 {
            return Some(y1);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::surface_kind;

    /// A cone cap whose apex no vertex loop records still covers the apex: the real NIST
    /// part's cone caps (which do have a vertex loop) with the vertex loop removed.
    #[test]
    fn cone_cap_reaches_its_apex_without_a_vertex_loop() {
        let Some(dir) = crate::testing::realworld_dir() else {
            return;
        };
        let model = crate::ingest::read_model(&dir.join("stepswift_nist_ftc_06_asme1_rd.stp"))
            .unwrap_or_else(|e| panic!("{e}"));
        let mut checked = 0;
        for face in &model.faces {
            let Some(apex) = face.loops.iter().find_map(|l| l.vertex) else {
                continue;
            };
            if surface_kind(&face.surface) != "cone" {
                continue;
            }
            let mut cap = face.clone();
            cap.loops.retain(|l| l.vertex.is_none());
            let ((u0, u1), (v0, v1)) = covered_domain(&cap);
            let apex = model.vertices[apex].point;
            // The apex is on the covered rectangle's border in the direction across the loop.
            let corners = [
                (u0, v0),
                (u0, v1),
                (u1, v0),
                (u1, v1),
                (0.5 * (u0 + u1), v0),
                (0.5 * (u0 + u1), v1),
            ];
            let nearest = corners
                .iter()
                .map(|&(u, v)| crate::geom::surface_point(&cap.surface, u, v).distance(apex))
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest < 1e-6 * (1.0 + apex.length()),
                "apex {apex} not reached: {nearest}"
            );
            checked += 1;
        }
        assert!(checked > 0);
    }
}
