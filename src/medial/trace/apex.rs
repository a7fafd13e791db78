//! Cone apexes at vertices: the point of a drill's tip (a blind hole's conical end) or of a
//! conical spike, where the face's normal is undefined. Exporters write it as a vertex of the
//! face alone (a `VERTEX_LOOP`, or the end of the cone's seam edge). A ball touches the apex
//! of a hole's tip while its normal turns about the axis, as at a reflex vertex; the cone's
//! generators leaving the apex bound the normals it may have there.

use crate::geom::eval_face;
use crate::model::{Model, Surface};
use glam::DVec3;

/// The apex of face `face`'s cone at vertex `vertex`: the unit direction `axis` about which
/// the face's generators leave the apex, and the sine of their half-angle to it. A ball touching
/// the apex with outward normal `n` keeps every generator at least `r` from its centre when
/// `n · d ≥ 0` for each generator direction `d`, that is when the angle between `n` and
/// `axis` is at most 90° less the half-angle: `n · axis ≥ sin_half_angle`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Apex {
    pub(super) vertex: usize,
    pub(super) face: usize,
    pub(super) point: DVec3,
    pub(super) axis: DVec3,
    pub(super) sin_half_angle: f64,
}

impl Apex {
    /// True when a ball touching the apex with outward normal `n` does not cross the face.
    pub(super) fn admits(&self, n: DVec3, rounding: f64) -> bool {
        self.margin(n) >= -rounding
    }

    /// How far the normal `n` is inside the normals the apex admits (negative outside).
    pub(super) fn margin(&self, n: DVec3) -> f64 {
        n.dot(self.axis) - self.sin_half_angle
    }

    /// The direction of the generator along which the cone's normal is `n`, for a normal
    /// `n` on the border of (or just past) the apex's normals: where the touch point leaves
    /// the apex onto the face. `None` when `n` is along the axis (every generator).
    pub(super) fn generator_for(&self, n: DVec3) -> Option<DVec3> {
        let across = n - n.dot(self.axis) * self.axis;
        let e = across.try_normalize()?;
        let sin = self.sin_half_angle;
        let cos = (1.0 - sin * sin).max(0.0).sqrt();
        Some(cos * self.axis - sin * e)
    }
}

/// The cone apexes at vertices of `model` (few: a part's drill points): for every face on a
/// conical surface, its vertices (of its edges and vertex loops) within `tol` of the cone's
/// apex.
pub(super) fn apexes(model: &Model, tol: f64) -> Vec<Apex> {
    let mut at = vec![];
    for (f, face) in model.faces.iter().enumerate() {
        let Some((point, axis, sin_half_angle)) = cone_apex(model, f) else {
            continue;
        };
        let vertices = face.loops.iter().flat_map(|l| {
            l.vertex.into_iter().chain(
                l.edges
                    .iter()
                    .flat_map(|oe| model.edges[oe.edge].vertices.into_iter()),
            )
        });
        let mut seen = vec![];
        for v in vertices {
            if !seen.contains(&v) && model.vertices[v].point.distance(point) <= tol {
                seen.push(v);
                at.push(Apex {
                    vertex: v,
                    face: f,
                    point,
                    axis,
                    sin_half_angle,
                });
            }
        }
    }
    at
}

/// Face `f`'s cone apex, axis and the sine of the half-angle, from four generators at quarter turns over the
/// face's parameter range (exact for a circular cone: the generators' directions from the
/// apex sum to the axis); `None` for a face on any other surface.
fn cone_apex(model: &Model, f: usize) -> Option<(DVec3, DVec3, f64)> {
    use truck_stepio::r#in::alias::ElementarySurface as E;
    let face = &model.faces[f];
    let Surface::ElementarySurface(e) = &face.surface else {
        return None;
    };
    if !matches!(e.as_ref(), E::ConicalSurface(_)) {
        return None;
    }
    let d = face.domain;
    // The angle is the periodic parameter; the other runs along the generators.
    let (turn_in_u, along) = match (d.u_period, d.v_period) {
        (Some(_), None) => (true, d.v),
        (None, Some(_)) => (false, d.u),
        _ => return None,
    };
    let at = |angle: f64, s: f64| {
        let (u, v) = if turn_in_u { (angle, s) } else { (s, angle) };
        eval_face(face, u, v).p
    };
    let a0 = if turn_in_u { d.u.0 } else { d.v.0 };
    let quarter = std::f64::consts::FRAC_PI_2;
    let (s0, s1) = along;
    // Two generators, a quarter turn apart, meet at the apex.
    let (p0, q0) = (at(a0, s0), at(a0, s1));
    let (p1, q1) = (at(a0 + quarter, s0), at(a0 + quarter, s1));
    let point = closest_of_lines(p0, q0 - p0, p1, q1 - p1)?;
    // The face's side of the apex: its middle generator point.
    let mid = 0.5 * (s0 + s1);
    let dirs: Vec<DVec3> = (0..4)
        .map(|k| (at(a0 + quarter * k as f64, mid) - point).try_normalize())
        .collect::<Option<_>>()?;
    let axis = dirs.iter().copied().sum::<DVec3>().try_normalize()?;
    let sin_half_angle = (dirs[0] - dirs[0].dot(axis) * axis).length();
    Some((point, axis, sin_half_angle))
}

/// The point midway between the nearest points of lines `p + s·a` and `q + t·b`; `None` for
/// parallel lines.
fn closest_of_lines(p: DVec3, a: DVec3, q: DVec3, b: DVec3) -> Option<DVec3> {
    let w = p - q;
    let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
    let (aw, bw) = (a.dot(w), b.dot(w));
    let den = aa * bb - ab * ab;
    if den <= 1e-12 * aa * bb {
        return None;
    }
    let s = (ab * bw - bb * aw) / den;
    let t = (aa * bw - ab * aw) / den;
    Some(0.5 * ((p + s * a) + (q + t * b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The drilled blind hole's drill point, written with a seam edge to the apex and with the
    /// apex a vertex loop: one apex, at the vertex there, on the cone; its generators leave
    /// it about −y (towards the hole's mouth) at 59°. A ball touching the apex may have the
    /// cone's normal at the apex's border and any normal within it, not one beyond.
    #[test]
    fn a_drill_points_apex_is_found_with_its_axis_and_half_angle() {
        let tip = 2.0 / 59f64.to_radians().tan();
        let point = DVec3::new(20.0, 14.0 + tip, 5.0);
        for name in [
            "trace/drilled_blind_hole.step",
            "trace/drilled_blind_hole_vertex_loop.step",
        ] {
            let model = crate::testing::sample(name);
            let found = apexes(&model, 1e-6);
            assert_eq!(found.len(), 1, "{name}: {found:?}");
            let a = found[0];
            assert!(
                model.vertices[a.vertex].point.distance(point) < 1e-9,
                "{name}"
            );
            assert!(a.point.distance(point) < 1e-9, "{name}: {:?}", a.point);
            assert!(
                a.axis.distance(DVec3::NEG_Y) < 1e-12,
                "{name}: {:?}",
                a.axis
            );
            let sin = 59f64.to_radians().sin();
            assert!((a.sin_half_angle - sin).abs() < 1e-12, "{name}");
            // The cone's outward normal along the generator in direction +x from the axis
            // (into the hole, towards the mouth): at the border.
            let cos = 59f64.to_radians().cos();
            let border = DVec3::new(-cos, -sin, 0.0);
            assert!(a.admits(border, 1e-12) && a.margin(border).abs() < 1e-12);
            let d = a.generator_for(border).unwrap();
            assert!(d.dot(border).abs() < 1e-12, "{d:?}");
            assert!(d.dot(DVec3::NEG_Y) > 0.0 && d.x > 0.0, "{d:?}");
            assert!(a.admits(DVec3::NEG_Y, 0.0));
            let past = DVec3::new(-cos - 0.01, -sin + 0.01, 0.0).normalize();
            assert!(
                !a.admits(past, 1e-9),
                "{name}: a normal past the border is admitted"
            );
        }
    }
}
