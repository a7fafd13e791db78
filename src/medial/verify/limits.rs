//! Seam ends at curvature limits, checked (`curvature_limits`): the ball there osculates the
//! boundary.
//!
//! A seam ends at a curvature limit where its ball stops being maximal because the boundary
//! bends round it as fast as its sphere does: somewhere it touches, the boundary's radius of
//! curvature towards the centre is `r` (`r·κ = 1`). Where exactly is not well defined to the
//! accuracy: near that place the boundary and the sphere agree to second order, so the touch
//! point can lie anywhere along the stretch where they stay within the accuracy of each
//! other, and the tracer puts it where its step ended. So the check looks along that
//! stretch: from each touch point (and from the boundary points nearest the centre, which
//! are touch points too), in eight directions across each face within reach of it and both
//! ways along each edge, a 1024th of a place at a time over the first 64th (touch points met
//! at a B-spline's knot, its curvature's peak between them), a 64th of a place at a time over
//! the first place (two touch points about to meet may lie closer than a quarter place, and a
//! B-spline's curvature peak between them) and a quarter place at a time beyond, out to 17
//! places, while the boundary stays within [`OSCULATION_NEAR_ACCURACIES`] (plus the file's
//! gap there) of the sphere. The radii of curvature of the faces there (`1/κ1`, the larger
//! principal curvature where it bends towards the ball), or of the edges (`1/(K·u)`, `K` the
//! curvature vector and `u` the unit vector to the centre), must come within
//! [`CURVATURE_LIMIT_ACCURACIES`] (plus the gap) of `r`, or lie on both sides of it: where a
//! B-spline's curvature jumps at a knot, or two edges or faces joined there bend differently,
//! the limit is where `r` passes from one side's radius to the other's. At a vertex's limit
//! (two touch points that met at a vertex, where a skeletal edge starts; `skeletal_edges`
//! checks that edge) the ball touches a vertex of the part.
//!
//! A ball tangent to the boundary with a smaller radius than it bends with anywhere near lies
//! on a sheet, not at the end of a seam: the check fails an end that stopped short, or that
//! names a limit its ball does not reach (a plane's, or a face's whose radius is three times
//! the ball's). `scripts/ocp/crosscheck_mat.py` checks the same with OpenCASCADE's curvatures.

use super::outcome::Verification;
use crate::geom::{
    eval_curve, eval_face, nearest_on_edge, principal_curvatures, unit_normal, Boundary,
};
use crate::medial::axis::{MedialAxis, SeamEnd};
use crate::model::{Element, Model};
use glam::DVec3;

/// How far from the ball's radius (in accuracies, plus the file's gap there) a radius of
/// curvature near its touch points may be: the end is located to the accuracy, where the
/// curvature is taken: four accuracies, and as many again for a margin.
const CURVATURE_LIMIT_ACCURACIES: f64 = 8.0;

/// How close to the ball's sphere (in accuracies, plus the file's gap there) the boundary
/// must stay for its radius of curvature there to count.
const OSCULATION_NEAR_ACCURACIES: f64 = 2.0;

/// The steps along the boundary from a touch point, in places (`√(8·r·a)`): finest steps
/// over the first 64th of a place (two touch points that have met at a B-spline's knot lie a
/// few accuracies apart, its curvature's peak between them: on the Revo hotend mount, 1.8e-4
/// mm apart on an edge, its radius of curvature 1.73315 at the touch point and 1.73295 1.5e-4
/// mm along, where the fine steps are 3.7e-4 mm), fine steps over the first place (where
/// two touch points about to meet lie less than a quarter place apart, a B-spline's curvature
/// can peak between them), coarse ones beyond, out to 17 places.
const OSCULATION_FINEST_STEP_PLACES: f64 = 1.0 / 1024.0;
const OSCULATION_FINEST_STEPS: usize = 16;
const OSCULATION_FINE_STEP_PLACES: f64 = 1.0 / 64.0;
const OSCULATION_COARSE_STEP_PLACES: f64 = 0.25;
const OSCULATION_STEPS: usize = 64;

/// The distances along the boundary from a touch point at which its curvature is taken, in
/// places: 0, then [`OSCULATION_FINEST_STEPS`] finest steps (to the first fine step), the
/// fine steps on to the [`OSCULATION_STEPS`]th, and as many coarse ones.
fn osculation_offsets() -> impl Iterator<Item = f64> {
    let finest = (0..=OSCULATION_FINEST_STEPS).map(|m| m as f64 * OSCULATION_FINEST_STEP_PLACES);
    let fine = (2..=OSCULATION_STEPS).map(|m| m as f64 * OSCULATION_FINE_STEP_PLACES);
    let start = OSCULATION_STEPS as f64 * OSCULATION_FINE_STEP_PLACES;
    let coarse =
        (1..=OSCULATION_STEPS).map(move |m| start + m as f64 * OSCULATION_COARSE_STEP_PLACES);
    finest.chain(fine).chain(coarse)
}

/// Every seam end at a curvature limit: its ball osculates the boundary near one of its
/// touch points (see the module docs).
pub(super) fn check_curvature_limits(
    model: &Model,
    boundary: &Boundary,
    axis: &MedialAxis,
    v: &mut Verification,
) {
    let a = v.accuracy;
    let largest_gap = model.faces.iter().map(|f| f.gap_mm()).fold(0.0, f64::max);
    for s in &axis.seams {
        for end in 0..2 {
            let SeamEnd::CurvatureLimit { segment } = s.ends[end] else {
                continue;
            };
            let (Some(p), _) = s.at_end(end) else {
                continue;
            };
            let ball = Ball {
                centre: DVec3::new(p.point[0], p.point[1], p.point[2]),
                r: p.point[3],
            };
            let mut touch: Vec<DVec3> = p.touch.iter().map(|t| DVec3::from_array(*t)).collect();
            // The boundary's points nearest the centre are touch points too (the ball may
            // osculate the face it was handed towards away from the touch points listed).
            if ball.centre.is_finite() {
                let hit = boundary.nearest(model, ball.centre);
                if (hit.distance - ball.r).abs() <= a + largest_gap {
                    touch.push(hit.point);
                }
            }
            let found = osculation(model, boundary, segment, &ball, &touch, a, largest_gap);
            v.record("curvature_limits", found.is_ok(), || {
                let why = found.as_ref().err().cloned().unwrap_or_default();
                format!(
                    "seam {} end {end} at {segment}'s curvature limit: {why}",
                    s.id
                )
            });
        }
    }
}

/// A ball: centre and radius.
struct Ball {
    centre: DVec3,
    r: f64,
}

/// `Ok` when the ball osculates the boundary near one of `touch` as the end at `segment`'s
/// curvature limit says (see the module docs), or why not.
fn osculation(
    model: &Model,
    boundary: &Boundary,
    segment: Element,
    ball: &Ball,
    touch: &[DVec3],
    a: f64,
    largest_gap: f64,
) -> Result<(), String> {
    if !(ball.centre.is_finite() && ball.r.is_finite() && ball.r > 0.0) {
        return Err("its ball is not a ball".into());
    }
    let place = super::balls::separation(ball.r, a);
    // The radii nearest r where none brackets it: (distance from r, lowest, highest).
    let mut nearest: Option<(f64, f64, f64)> = None;
    for &t in touch.iter().filter(|t| t.is_finite()) {
        let faces: Vec<(usize, crate::geom::FaceHit)> = boundary
            .within(model, t, a + largest_gap)
            .into_iter()
            .filter_map(|f| {
                let hit = boundary.nearest_on_face(model, f, t, None, a + largest_gap)?;
                Some((f, hit))
            })
            .collect();
        let gap = faces
            .iter()
            .map(|(f, _)| model.faces[*f].gap_mm())
            .fold(0.0, f64::max);
        let reach = a + gap;
        if let Element::Vertex(_) = segment {
            let touched = model.vertices.iter().any(|v| {
                v.point.distance(t) <= reach
                    && (v.point.distance(ball.centre) - ball.r).abs() <= reach
            });
            if touched {
                return Ok(());
            }
            continue;
        }
        let near = OSCULATION_NEAR_ACCURACIES * a + gap;
        let allowed = CURVATURE_LIMIT_ACCURACIES * a + gap;
        let faces: Vec<_> = faces
            .into_iter()
            .filter(|(_, h)| h.distance <= reach)
            .collect();
        let on_faces: Vec<f64> = faces
            .iter()
            .flat_map(|(f, h)| face_radii_near(model, *f, h.uv, ball, near, place))
            .collect();
        let on_edges: Vec<f64> = (0..model.edges.len())
            .filter(|&e| {
                model.edges[e]
                    .faces
                    .iter()
                    .any(|g| faces.iter().any(|(f, _)| f == g))
            })
            .filter_map(|e| {
                let (s0, _, d) = nearest_on_edge(model, e, t, None);
                (d <= reach).then(|| edge_radii_near(model, e, s0, ball, near, place))
            })
            .flatten()
            .collect();
        for radii in [on_faces, on_edges] {
            if radii.is_empty() {
                continue;
            }
            let lo = radii.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = radii.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if lo - allowed <= ball.r && ball.r <= hi + allowed {
                return Ok(());
            }
            let off = (lo - ball.r).abs().min((hi - ball.r).abs());
            if nearest.is_none_or(|(o, _, _)| off < o) {
                nearest = Some((off, lo, hi));
            }
        }
    }
    Err(match (segment, nearest) {
        (Element::Vertex(_), _) => "its ball touches no vertex of the part".into(),
        (_, None) => "no face or edge there bends towards its ball".into(),
        (_, Some((_, lo, hi))) => format!(
            "its radius {:.6} is no radius of curvature there (the nearest: {lo:.6} to {hi:.6})",
            ball.r
        ),
    })
}

/// The radii of curvature of face `f` towards the ball's centre (`1/κ1` where its larger
/// principal curvature bends towards it) at `uv` and along rays from there in eight
/// directions (at [`osculation_offsets`]), while the face stays within `near` of the ball's
/// sphere.
fn face_radii_near(
    model: &Model,
    f: usize,
    (u0, v0): (f64, f64),
    ball: &Ball,
    near: f64,
    place: f64,
) -> Vec<f64> {
    let face = &model.faces[f];
    let d0 = eval_face(face, u0, v0);
    let (su, sv) = (d0.su.length(), d0.sv.length());
    if !(su > 0.0 && sv > 0.0 && su.is_finite() && sv.is_finite()) {
        return vec![];
    }
    let ((ulo, uhi), (vlo, vhi)) = crate::geom::project::clamp_ranges(&face.surface);
    let mut out = vec![];
    for j in 0..8 {
        let (sin, cos) = (j as f64 * std::f64::consts::FRAC_PI_4).sin_cos();
        for offset in osculation_offsets().skip(usize::from(j > 0)) {
            let step = offset * place;
            let (u, v) = (u0 + cos * step / su, v0 + sin * step / sv);
            if !(ulo <= u && u <= uhi && vlo <= v && v <= vhi) {
                break;
            }
            let d = eval_face(face, u, v);
            let out_of_ball = d.p - ball.centre;
            if (out_of_ball.length() - ball.r).abs() > near {
                break;
            }
            // Touched there: the face tangent to the sphere (its outward normal along the way
            // from the centre, to the angle over which a place stays within `near` of it).
            let tangent = unit_normal(&d, face.sign).is_some_and(|n| {
                n.dot(out_of_ball.normalize_or_zero()) >= max_tilt(near, place).cos()
            });
            if !tangent {
                continue;
            }
            let k = principal_curvatures(&d, face.sign).map(|k| k.k1);
            if let Some(k) = k.filter(|k| *k > 0.0 && k.is_finite()) {
                out.push(1.0 / k);
            }
        }
    }
    out
}

/// The radii of curvature of edge `e` towards the ball's centre (`1/(K·u)` where positive,
/// `K` its curvature vector, `u` the unit vector to the centre) at `s0` and both ways along
/// it (at [`osculation_offsets`]), while it stays within `near` of the ball's sphere.
fn edge_radii_near(
    model: &Model,
    e: usize,
    s0: f64,
    ball: &Ball,
    near: f64,
    place: f64,
) -> Vec<f64> {
    let edge = &model.edges[e];
    let (lo, hi) = (
        edge.range.0.min(edge.range.1),
        edge.range.0.max(edge.range.1),
    );
    let speed = eval_curve(&edge.curve, s0).d1.length();
    if !(speed > 0.0 && speed.is_finite()) {
        return vec![];
    }
    let mut out = vec![];
    for sign in [-1.0, 1.0] {
        for offset in osculation_offsets().skip(usize::from(sign > 0.0)) {
            let s = s0 + sign * offset * place / speed;
            if !(lo <= s && s <= hi) {
                break;
            }
            let c = eval_curve(&edge.curve, s);
            let to_centre = ball.centre - c.p;
            let dist = to_centre.length();
            if (dist - ball.r).abs() > near {
                break;
            }
            let speed2 = c.d1.length_squared();
            if !(speed2 > 0.0 && dist > 0.0) {
                continue;
            }
            // Touched there: square to the way to the centre (to the angle over which a place
            // stays within `near` of the sphere).
            if c.d1.normalize().dot(to_centre / dist).abs() > max_tilt(near, place).sin() {
                continue;
            }
            let bend_vector = (c.d2 - c.d1 * (c.d2.dot(c.d1) / speed2)) / speed2;
            let bend = bend_vector.dot(to_centre / dist);
            if bend > 0.0 && bend.is_finite() {
                out.push(1.0 / bend);
            }
        }
    }
    out
}

/// The most a face or edge may turn from square to the way to the ball's centre where it is
/// taken to touch the ball: over a place it then stays within `near` of the sphere (at most
/// half a radian).
fn max_tilt(near: f64, place: f64) -> f64 {
    (near / place).min(0.5)
}
