//! Projecting a point onto an untrimmed surface: the foot point `(u, v)` minimising
//! `‖S(u, v) − p‖`.
//!
//! [`project_point`], in order: a plane in closed form; truck's `search_nearest_parameter`;
//! with a hint, damped Newton (Levenberg–Marquardt on `½‖S − p‖²` with the exact second
//! derivatives of [`super::eval`]) from it; last, Newton from a grid of seeds over the
//! parameter range (knot spans for B-splines; unbounded directions seeded at 0 and around the
//! hint). truck alone fails outright on some inputs (cones, high-degree B-splines, poles of
//! spheres, measured on the real-world corpus). [`project_point_along`], for trim-loop
//! samples only, tries Newton from the hint before truck on non-periodic surfaces.
//!
//! For the trim loops only, [`ClosedForm`] answers planes, cylinders, cones and spheres
//! exactly in truck's parameters and angle ranges (truck's own `acos` formulas lose half the
//! digits next to the seam and the poles; these use `atan2`), and [`greville_hint`] gives a
//! B-spline patch a start from its control net. Edge classification and the tracer keep
//! [`project_point`] unchanged (see [`project_point_along`] for why).

use super::eval::eval_surface;
use crate::model::Surface;
use glam::DVec3;
use std::ops::Bound;
use truck_geometry::prelude::{ParametricSurface, Point3, SearchNearestParameter};
use truck_stepio::r#in::alias::ElementarySurface;

/// Newton iterations per seed.
pub const MAX_NEWTON_ITER: usize = 50;

/// Seeds per bounded direction of the fallback grid.
pub const FALLBACK_SEED_GRID: usize = 12;

/// How far beyond a bounded parameter range truck's answer may be and still count as inside,
/// relative to the size of the range's end.
const RANGE_TOL_REL_END: f64 = 1e-12;

/// Points on the straight line between two parameter pairs, both ends included, of which
/// [`nearest_sample_between`] takes the inner ones.
pub const BETWEEN_SAMPLES: usize = 8;

/// Of the points strictly between parameters `a` and `b` of `surface` on the straight line
/// between them (at `1/BETWEEN_SAMPLES` steps), the one nearest `p`: a start for a descent
/// into a basin of the distance that lies between two touch points on one face (a face whose
/// curvature wanders can bulge into a ball there while the nearest-point search settles in
/// a touched basin).
pub fn nearest_sample_between(
    surface: &Surface,
    p: DVec3,
    a: (f64, f64),
    b: (f64, f64),
) -> Option<(f64, f64)> {
    let at = |uv: &(f64, f64)| super::eval::surface_point(surface, uv.0, uv.1).distance(p);
    (1..BETWEEN_SAMPLES)
        .map(|k| {
            let t = k as f64 / BETWEEN_SAMPLES as f64;
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        })
        .min_by(|x, y| at(x).total_cmp(&at(y)))
}

/// The foot point of `p` on `surface`, or `None` when no seed converges. `hint` is a nearby
/// parameter (the previous foot point along a curve) and makes the common case a few Newton
/// steps. The result is a local minimum of the distance; with a hint, the one nearest the
/// hint; without one, the best over the seed grid.
pub fn project_point(surface: &Surface, p: DVec3, hint: Option<(f64, f64)>) -> Option<(f64, f64)> {
    if let Some(frame) = plane_frame(surface) {
        return Some(project_plane(frame, p));
    }
    let q = Point3::new(p.x, p.y, p.z);
    let truck = crate::panic_guard::catch(|| surface.search_nearest_parameter(q, hint, 100))
        .ok()
        .flatten()
        .filter(|uv| is_foot(surface, p, *uv))
        .filter(|uv| {
            // Outside a bounded direction (past a sphere's pole) the parametrisation folds
            // back and the normal flips: not an answer.
            let (ur, vr) = clamp_ranges(surface);
            let inside = |x: f64, r: (f64, f64)| {
                x >= r.0 - RANGE_TOL_REL_END * (1.0 + r.0.abs())
                    && x <= r.1 + RANGE_TOL_REL_END * (1.0 + r.1.abs())
            };
            inside(uv.0, ur) && inside(uv.1, vr)
        });
    if let Some(h) = hint {
        if truck.is_some() {
            return truck;
        }
        if let Some(uv) = newton(surface, p, h) {
            return Some(uv);
        }
    }
    seeded(surface, p, hint, truck)
}

/// [`project_point`] for the samples along a trim loop, each next to the previous one's
/// foot `hint`: our damped Newton from the hint first, several times cheaper than truck's
/// search. Not on periodic surfaces, whose angles truck answers in its canonical range (the
/// loop unwrapping in `ingest::domain` relies on that).
///
/// The loops use it, and the tracer for an edge's points on its faces (their arc of
/// normals, from the edge's samples there). Edge classification and the tracer's other
/// projections keep [`project_point`]: there a different foot changed results (measured on
/// the trimesh part: skipping truck's search for B-splines without a hint in classification
/// gave 249 seams with 30 open ends instead of 268 with 22). The loops' feet are exact to
/// 1e-12 instead of truck's 1e-6; even that moves a few open seam ends on the two real parts
/// that have them in degenerate spots (trimesh 22 → 20, M6 screw 7 → 8).
///
/// `periodic` is whether the surface has an angle parameter (truck's `u_period` or
/// `v_period`: spheres, tori, cylinders, cones, revolutions), where our Newton would leave
/// truck's canonical range. A B-spline patch that closes on itself is not periodic here:
/// Newton's iterates are clamped to its knot range, and a foot stuck at the closing border
/// fails `is_foot` and goes to truck. The caller decides once per loop.
pub fn project_point_along(
    surface: &Surface,
    p: DVec3,
    hint: (f64, f64),
    periodic: bool,
) -> Option<(f64, f64)> {
    if let Some(frame) = plane_frame(surface) {
        return Some(project_plane(frame, p));
    }
    if !periodic {
        // A loop sample lies on the surface up to the file's gaps (1e-8 on the screw), where
        // rounding leaves `is_foot`'s angle test (1e-6 rad) out of reach: a foot within
        // `FOOT_ON_SURFACE_REL_COORD` of the point is taken as it is.
        let scale = 1.0 + p.abs().max_element();
        let on = |uv: &(f64, f64)| {
            super::surface_point(surface, uv.0, uv.1).distance(p)
                <= FOOT_ON_SURFACE_REL_COORD * scale
        };
        if let Some(uv) = newton(surface, p, hint).filter(|uv| on(uv) || is_foot(surface, p, *uv)) {
            return Some(uv);
        }
    }
    project_point(surface, p, Some(hint))
}

/// A start for Newton on a B-spline or NURBS patch near `p`: the Greville abscissae
/// (`(t_{i+1} + … + t_{i+p}) / p` in each direction) of the control point nearest `p`. A
/// patch follows its control net, so this is near the foot of a point on the patch; `None`
/// for other surfaces and for degree 0.
pub fn greville_hint(surface: &Surface, p: DVec3) -> Option<(f64, f64)> {
    use truck_geometry::prelude::KnotVec;
    let nearest = |rows: &mut dyn Iterator<Item = (usize, usize, DVec3)>| {
        rows.filter(|(_, _, c)| c.is_finite())
            .min_by(|a, b| a.2.distance_squared(p).total_cmp(&b.2.distance_squared(p)))
            .map(|(i, j, _)| (i, j))
    };
    let (ku, kv, pu, pv, (i, j)): (&KnotVec, &KnotVec, usize, usize, (usize, usize)) = match surface
    {
        Surface::BSplineSurface(b) => {
            let ij = nearest(
                &mut b.control_points().iter().enumerate().flat_map(|(i, r)| {
                    r.iter()
                        .enumerate()
                        .map(move |(j, c)| (i, j, DVec3::new(c.x, c.y, c.z)))
                }),
            )?;
            (
                &b.knot_vecs().0,
                &b.knot_vecs().1,
                b.udegree(),
                b.vdegree(),
                ij,
            )
        }
        Surface::NurbsSurface(n) => {
            let ij = nearest(
                &mut n.control_points().iter().enumerate().flat_map(|(i, r)| {
                    r.iter()
                        .enumerate()
                        .map(move |(j, c)| (i, j, DVec3::new(c.x, c.y, c.z) / c.w))
                }),
            )?;
            (
                &n.knot_vecs().0,
                &n.knot_vecs().1,
                n.udegree(),
                n.vdegree(),
                ij,
            )
        }
        _ => return None,
    };
    let greville = |k: &KnotVec, deg: usize, i: usize| -> Option<f64> {
        (deg > 0 && i + deg < k.len())
            .then(|| (1..=deg).map(|d| k[i + d]).sum::<f64>() / deg as f64)
    };
    Some((greville(ku, pu, i)?, greville(kv, pv, j)?))
}

/// How far a matrix's columns may be from orthogonal and of equal length, relative to the
/// square of their length, for [`similarity_inverse`] to call it a similarity.
const SIMILARITY_TOL_REL_SCALE_SQ: f64 = 1e-12;

/// The inverse of a truck `Processor`'s matrix when it is a similarity (a rotation, a
/// uniform scale and a shift map feet to feet); `None` for any other matrix.
fn similarity_inverse(m: &truck_geometry::prelude::Matrix4) -> Option<(glam::DMat4, f64)> {
    let m = glam::DMat4::from_cols_array_2d(&(*m).into());
    let (c0, c1, c2) = (
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    );
    let s2 = c0.length_squared();
    let similar = m.x_axis.w == 0.0
        && m.y_axis.w == 0.0
        && m.z_axis.w == 0.0
        && m.w_axis.w == 1.0
        && s2 > 0.0
        && (c1.length_squared() - s2).abs() <= SIMILARITY_TOL_REL_SCALE_SQ * s2
        && (c2.length_squared() - s2).abs() <= SIMILARITY_TOL_REL_SCALE_SQ * s2
        && c0.dot(c1).abs() <= SIMILARITY_TOL_REL_SCALE_SQ * s2
        && c0.dot(c2).abs() <= SIMILARITY_TOL_REL_SCALE_SQ * s2
        && c1.dot(c2).abs() <= SIMILARITY_TOL_REL_SCALE_SQ * s2;
    similar.then(|| (m.inverse(), s2.sqrt()))
}

/// The exact foot of `p` on a sphere, in truck's parameters and ranges (longitude in
/// `[0, 2π]`, `2π` on the seam's lower side as truck's mirrored `acos` gives it; latitude),
/// without the Newton polish truck's `Processor` adds after its `acos` formulas, which is
/// most of its cost. `None` at the centre and at the poles (every longitude is a
/// foot there), and for a transform that is not a similarity.
pub fn project_sphere(surface: &Surface, p: DVec3) -> Option<(f64, f64)> {
    match ClosedForm::new(surface) {
        c @ ClosedForm::Sphere { .. } => c.project(p),
        _ => None,
    }
}

/// The exact foot of `p` on a cylinder or cone (truck's `Processor<RevolutedCurve<Line>,
/// Matrix4>`), in truck's parameters: the line parameter, and the angle in `[0, 2π]` as
/// truck's own search gives it (`acos` of the radial directions, mirrored by the side of the
/// axis). Both nappes of a cone count; the nearer wins.
///
/// `None` (the caller searches instead) for other surfaces, a transform that is not a
/// similarity (it would not map feet to feet), a line out of the axis's plane, and a point
/// on the axis (every angle is a foot).
pub fn project_revolved_line(surface: &Surface, p: DVec3) -> Option<(f64, f64)> {
    match ClosedForm::new(surface) {
        c @ ClosedForm::RevolvedLine { .. } => c.project(p),
        _ => None,
    }
}

/// How far from a meridian half-plane a cylinder's or cone's line may stray, relative to the
/// farther of its ends' distances from the revolution's origin, for [`ClosedForm`] to answer
/// in closed form.
const MERIDIAN_TOL_REL_SIZE: f64 = 1e-12;

/// A parameter derivative shorter than this (model units per unit of the parameter) makes a
/// closed-form foot a pole of the parametrisation ([`ClosedFoot::pole`]).
const POLE_DERIVATIVE_LENGTH: f64 = 1e-12;

/// The foot of a point in closed form where there is one, and what that needs of the
/// surface, computed once: a trim loop projects dozens of points onto the same face.
/// Planes as `project_plane`, cylinders and cones as [`project_revolved_line`], spheres as
/// [`project_sphere`], bit for bit, in truck's parameters.
#[derive(Clone, Debug)]
pub enum ClosedForm {
    /// A cylinder or cone: its matrix's inverse, and the line's (axial, radial) ends in the
    /// meridian half-plane of `e`.
    RevolvedLine {
        inverse: glam::DMat4,
        scale: f64,
        orientation: bool,
        o: DVec3,
        a: DVec3,
        e: DVec3,
        size: f64,
        za: f64,
        ra: f64,
        dz: f64,
        dr: f64,
        dd: f64,
    },
    /// A plane `o + u·a + v·b`.
    Plane { frame: (DVec3, DVec3, DVec3) },
    /// A sphere: its matrix's inverse and its centre.
    Sphere {
        inverse: glam::DMat4,
        scale: f64,
        orientation: bool,
        c: DVec3,
        radius: f64,
    },
    /// Any other surface, or a matrix that is not a similarity, or a degenerate line.
    None,
}

impl ClosedForm {
    pub fn new(surface: &Surface) -> Self {
        if let Some(frame) = plane_frame(surface) {
            return ClosedForm::Plane { frame };
        }
        let Surface::ElementarySurface(e) = surface else {
            return ClosedForm::None;
        };
        match e.as_ref() {
            ElementarySurface::CylindricalSurface(pr) | ElementarySurface::ConicalSurface(pr) => {
                let Some((inverse, scale)) = similarity_inverse(pr.transform()) else {
                    return ClosedForm::None;
                };
                let rev = pr.entity();
                let o = DVec3::new(rev.origin().x, rev.origin().y, rev.origin().z);
                let a = DVec3::new(rev.axis().x, rev.axis().y, rev.axis().z);
                let line = rev.entity_curve();
                let (la, lb) = (
                    DVec3::new(line.0.x, line.0.y, line.0.z),
                    DVec3::new(line.1.x, line.1.y, line.1.z),
                );
                // (axial, radial) coordinates in the meridian half-plane of `e`, the line's
                // side.
                let ((za, ha), (zb, hb)) = (split(o, a, la), split(o, a, lb));
                let size = (la - o).length().max((lb - o).length()).max(1e-300);
                let e = if ha.length() >= hb.length() { ha } else { hb }.normalize_or_zero();
                if e == DVec3::ZERO
                    || ha.cross(e).length() > MERIDIAN_TOL_REL_SIZE * size
                    || hb.cross(e).length() > MERIDIAN_TOL_REL_SIZE * size
                {
                    return ClosedForm::None;
                }
                let (ra, rb) = (ha.dot(e), hb.dot(e));
                let (dz, dr) = (zb - za, rb - ra);
                let dd = dz * dz + dr * dr;
                if dd <= 0.0 {
                    return ClosedForm::None;
                }
                ClosedForm::RevolvedLine {
                    inverse,
                    scale,
                    orientation: pr.orientation(),
                    o,
                    a,
                    e,
                    size,
                    za,
                    ra,
                    dz,
                    dr,
                    dd,
                }
            }
            ElementarySurface::Sphere(pr) => {
                let Some((inverse, scale)) = similarity_inverse(pr.transform()) else {
                    return ClosedForm::None;
                };
                let sphere = pr.entity().0;
                ClosedForm::Sphere {
                    inverse,
                    scale,
                    orientation: pr.orientation(),
                    c: DVec3::new(sphere.center().x, sphere.center().y, sphere.center().z),
                    radius: sphere.radius(),
                }
            }
            _ => ClosedForm::None,
        }
    }

    /// The foot of `p` (see [`project_revolved_line`] and [`project_sphere`]).
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        self.foot(p).map(|f| f.uv)
    }

    /// [`ClosedForm::project`], and where every angle is a foot (`p` on a cylinder's or
    /// cone's axis, at a sphere's centre or above its pole) the foot at `hint`'s angle: a
    /// degenerate medial ball's centre is there, and the search there is slow and arbitrary.
    pub fn project_near(&self, p: DVec3, hint: (f64, f64)) -> Option<(f64, f64)> {
        if let Some(uv) = self.project(p) {
            return Some(uv);
        }
        match *self {
            ClosedForm::RevolvedLine {
                inverse,
                orientation,
                o,
                a,
                za,
                ra,
                dz,
                dr,
                dd,
                ..
            } => {
                let (zq, _) = split(o, a, inverse.transform_point3(p));
                let t = ((zq - za) * dz - ra * dr) / dd;
                if ra + t * dr <= 0.0 {
                    return None;
                }
                Some(if orientation {
                    (t, hint.1)
                } else {
                    (hint.0, t)
                })
            }
            ClosedForm::Sphere {
                inverse,
                orientation,
                c,
                ..
            } => {
                use std::f64::consts::FRAC_PI_2;
                let d = (inverse.transform_point3(p) - c).normalize_or_zero();
                let (longitude, latitude) = if orientation { hint } else { (hint.1, hint.0) };
                let latitude = if d == DVec3::ZERO {
                    latitude
                } else {
                    FRAC_PI_2.copysign(d.z)
                };
                Some(if orientation {
                    (longitude, latitude)
                } else {
                    (latitude, longitude)
                })
            }
            ClosedForm::Plane { .. } | ClosedForm::None => None,
        }
    }

    /// The foot of `p`, with its distance from `p` and whether the parametrisation is
    /// singular there (a cone's apex), without evaluating the surface.
    pub fn foot(&self, p: DVec3) -> Option<ClosedFoot> {
        use std::f64::consts::PI;
        match *self {
            ClosedForm::Plane { frame } => {
                let (o, a, b) = frame;
                let (u, v) = project_plane(frame, p);
                Some(ClosedFoot {
                    uv: (u, v),
                    // The plane's point as `eval_surface` computes it.
                    distance: (o + a * u + b * v).distance(p),
                    pole: a.cross(b).length() <= 1e-9 * (a.length() * b.length()).max(1e-300)
                        || a.length() < POLE_DERIVATIVE_LENGTH
                        || b.length() < POLE_DERIVATIVE_LENGTH,
                })
            }
            ClosedForm::RevolvedLine {
                inverse,
                scale,
                orientation,
                o,
                a,
                e,
                size,
                za,
                ra,
                dz,
                dr,
                dd,
            } => {
                let q = inverse.transform_point3(p);
                let (zq, hq) = split(o, a, q);
                let rq = hq.length();
                if rq <= 1e-12 * (size + (q - o).length()) {
                    return None;
                }
                // truck's angle from `e` to `hq`, in [0, 2π]: its `acos`, mirrored when the
                // turn is negative, computed by `atan2`, which stays exact near 0 and π where
                // `acos` loses half the digits (truck polishes that with Newton).
                let hqn = hq / rq;
                let angle = |from: DVec3| {
                    let (sin, cos) = (from.cross(hqn).dot(a), from.dot(hqn));
                    if sin < 0.0 {
                        2.0 * PI + sin.atan2(cos)
                    } else {
                        sin.abs().atan2(cos)
                    }
                };
                // The nearest point of the line in the half-plane of `q` (radius > 0 there)
                // and in the opposite one (radius < 0: the other nappe, reached by turning
                // half a turn more).
                // (Squared distances: `hypot` was a fifth of this function's time.)
                let foot = |rq: f64| {
                    let t = ((zq - za) * dz + (rq - ra) * dr) / dd;
                    let (z, r) = (za + t * dz, ra + t * dr);
                    (t, r, (z - zq) * (z - zq) + (r - rq) * (r - rq))
                };
                let (t1, r1, d1) = foot(rq);
                let (t2, r2, d2) = foot(-rq);
                let (t, theta, r, d) = match (r1 > 0.0, r2 < 0.0) {
                    (true, false) => (t1, angle(e), r1, d1),
                    (false, true) => (t2, angle(-e), r2, d2),
                    (true, true) if d1 <= d2 => (t1, angle(e), r1, d1),
                    (true, true) => (t2, angle(-e), r2, d2),
                    (false, false) => return None,
                };
                // The angle's derivative is the radius times the axis (times the scale):
                // singular where it vanishes, as `domain`'s test of `Su × Sv` has it.
                let along = scale * dd.sqrt();
                let around = scale * r.abs() * a.length();
                Some(ClosedFoot {
                    uv: if orientation { (t, theta) } else { (theta, t) },
                    distance: scale * d.sqrt(),
                    pole: around < POLE_DERIVATIVE_LENGTH || along < POLE_DERIVATIVE_LENGTH,
                })
            }
            ClosedForm::Sphere {
                inverse,
                scale,
                orientation,
                c,
                radius,
            } => {
                let q = inverse.transform_point3(p);
                let d = (q - c).normalize_or_zero();
                let sinu = (1.0 - d.z * d.z).sqrt();
                if d == DVec3::ZERO || sinu <= 1e-12 {
                    return None;
                }
                // truck's `acos` formulas, computed by `atan2` (exact near the poles and the
                // seam).
                let latitude = d.z.atan2(d.x.hypot(d.y));
                let longitude = if d.y > 0.0 {
                    d.y.atan2(d.x)
                } else {
                    // |y|, not −y: at y = +0 on the negative x axis, −y = −0 would give
                    // atan2 = −π.
                    2.0 * PI - d.y.abs().atan2(d.x)
                };
                let (u, v) = (longitude, latitude);
                // The longitude's derivative is the radius times cos(latitude).
                Some(ClosedFoot {
                    uv: if orientation { (u, v) } else { (v, u) },
                    distance: scale * ((q - c).length() - radius.abs()).abs(),
                    pole: scale * radius.abs() * latitude.cos() < POLE_DERIVATIVE_LENGTH
                        || scale * radius.abs() < POLE_DERIVATIVE_LENGTH,
                })
            }
            ClosedForm::None => None,
        }
    }
}

/// A foot found by [`ClosedForm::foot`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedFoot {
    /// The foot's parameters, in truck's ranges.
    pub uv: (f64, f64),
    /// The distance from the projected point to the foot.
    pub distance: f64,
    /// Whether the parametrisation is singular at the foot (a cone's apex, a sphere's pole).
    pub pole: bool,
}

/// `x`'s (axial, radial) coordinates about the axis through `o` along `a`.
fn split(o: DVec3, a: DVec3, x: DVec3) -> (f64, DVec3) {
    let r = x - o;
    let z = r.dot(a);
    (z, r - a * z)
}

/// Distance, relative to the size of the coordinates, within which [`project_point_along`]
/// takes Newton's point as the foot of a point on the surface without testing that it is a
/// stationary point (truck's search is accurate to about this).
pub const FOOT_ON_SURFACE_REL_COORD: f64 = 1e-6;

/// The best foot from a grid of seeds (knot spans for B-splines) and Newton from the few
/// nearest, with `truck`'s answer as one more candidate when there was no hint.
fn seeded(
    surface: &Surface,
    p: DVec3,
    hint: Option<(f64, f64)>,
    truck: Option<(f64, f64)>,
) -> Option<(f64, f64)> {
    let (ur, vr) = crate::geom::parameter_range(surface);
    let seeds = |r: (Bound<f64>, Bound<f64>), h: Option<f64>| -> Vec<f64> {
        match (r.0, r.1) {
            (Bound::Included(a) | Bound::Excluded(a), Bound::Included(b) | Bound::Excluded(b))
                if a.is_finite() && b.is_finite() =>
            {
                (0..FALLBACK_SEED_GRID)
                    .map(|k| a + (b - a) * (k as f64 + 0.5) / FALLBACK_SEED_GRID as f64)
                    .collect()
            }
            _ => {
                let mut s = vec![0.0, 1.0, -1.0];
                s.extend(h);
                s
            }
        }
    };
    // B-splines can wind many times over their range (a helical thread): seed every knot
    // span, not just a fixed grid.
    let (us, vs) = match knot_seeds(surface) {
        Some(kv) => kv,
        None => (seeds(ur, hint.map(|h| h.0)), seeds(vr, hint.map(|h| h.1))),
    };
    // Best seed by distance, then Newton from the few best.
    let mut scored: Vec<(f64, (f64, f64))> = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .map(|(u, v)| {
            (
                super::surface_point(surface, u, v).distance_squared(p),
                (u, v),
            )
        })
        .filter(|(d, _)| d.is_finite())
        .collect();
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Without a hint, truck's answer is only one candidate: it can stop at a local minimum.
    let mut best: Option<(f64, (f64, f64))> = truck
        .filter(|_| hint.is_none())
        .map(|uv| (super::surface_point(surface, uv.0, uv.1).distance(p), uv));
    for (_, seed) in scored.into_iter().take(MAX_NEWTON_SEEDS) {
        if let Some(uv) = newton(surface, p, seed) {
            let d = super::surface_point(surface, uv.0, uv.1).distance(p);
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, uv));
            }
        }
    }
    best.map(|b| b.1)
}

/// Seeds of a B-spline/NURBS surface: `degree + 1` (at least three) per knot span in each direction
/// (at most `MAX_SPAN_SEEDS` per direction).
fn knot_seeds(surface: &Surface) -> Option<(Vec<f64>, Vec<f64>)> {
    let (ku, kv, pu, pv) = match surface {
        Surface::BSplineSurface(b) => (
            b.knot_vecs().0.clone(),
            b.knot_vecs().1.clone(),
            b.udegree(),
            b.vdegree(),
        ),
        Surface::NurbsSurface(n) => {
            let b = n.non_rationalized();
            (
                b.knot_vecs().0.clone(),
                b.knot_vecs().1.clone(),
                b.udegree(),
                b.vdegree(),
            )
        }
        _ => return None,
    };
    let spans = |k: &truck_geometry::prelude::KnotVec, p: usize| -> Vec<f64> {
        let m = k.len();
        if m < 2 * p + 2 {
            return vec![];
        }
        let (a, b) = (k[p], k[m - p - 1]);
        let mut distinct: Vec<f64> = (p..m - p)
            .map(|i| k[i])
            .filter(|x| *x >= a && *x <= b)
            .collect();
        distinct.dedup_by(|x, y| (*x - *y).abs() <= 1e-14 * (1.0 + y.abs()));
        // A span of degree p can turn about p/2 times: seed it p + 1 times (at least 3).
        let per = (p + 1).max(3);
        let mut out = Vec::new();
        for w in distinct.windows(2) {
            for j in 0..per {
                out.push(w[0] + (w[1] - w[0]) * (j as f64 + 0.5) / per as f64);
            }
        }
        if out.len() > MAX_SPAN_SEEDS {
            let step = out.len() as f64 / MAX_SPAN_SEEDS as f64;
            out = (0..MAX_SPAN_SEEDS)
                .map(|i| out[(i as f64 * step) as usize])
                .collect();
        }
        out
    };
    let (us, vs) = (spans(&ku, pu), spans(&kv, pv));
    (!us.is_empty() && !vs.is_empty()).then_some((us, vs))
}

/// Newton runs from this many of the best seeds.
pub const MAX_NEWTON_SEEDS: usize = 8;

/// Cap on seeds per direction from knot spans.
pub const MAX_SPAN_SEEDS: usize = 400;

/// `(origin, Su, Sv)` of a plane.
pub(crate) fn plane_frame(s: &Surface) -> Option<(DVec3, DVec3, DVec3)> {
    match s {
        Surface::ElementarySurface(e) if matches!(e.as_ref(), ElementarySurface::Plane(_)) => {
            let d = eval_surface(s, 0.0, 0.0);
            Some((d.p, d.su, d.sv))
        }
        _ => None,
    }
}

/// Exact foot point on a plane `o + u·a + v·b`.
#[inline]
pub(crate) fn project_plane(frame: (DVec3, DVec3, DVec3), p: DVec3) -> (f64, f64) {
    let (o, a, b) = frame;
    let r = p - o;
    let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
    let (ra, rb) = (r.dot(a), r.dot(b));
    let det = aa * bb - ab * ab;
    if det.abs() <= f64::MIN_POSITIVE {
        return (0.0, 0.0);
    }
    ((ra * bb - rb * ab) / det, (rb * aa - ra * ab) / det)
}

/// How far below zero [`is_foot`] lets the Hessian's diagonal (and, squared, its determinant)
/// be, relative to the larger of `‖Su‖²` and `‖Sv‖²`: rounding, not a maximum or a saddle.
const HESSIAN_TOL_REL_METRIC: f64 = 1e-9;

/// True when `uv` is a foot point of `p`: `S(uv) − p` is normal to the surface (or `p` is on
/// it), to a relative tolerance, and the distance is a local minimum there, not a maximum or
/// saddle (the far side of a sphere is a stationary point too; truck's search can land on it).
fn is_foot(surface: &Surface, p: DVec3, uv: (f64, f64)) -> bool {
    let d = eval_surface(surface, uv.0, uv.1);
    let r = d.p - p;
    // Hessian of ½‖S − p‖²: positive semi-definite at a minimum (up to rounding).
    let h00 = d.su.dot(d.su) + d.suu.dot(r);
    let h01 = d.su.dot(d.sv) + d.suv.dot(r);
    let h11 = d.sv.dot(d.sv) + d.svv.dot(r);
    let scale2 = d.su.length_squared().max(d.sv.length_squared()).max(1e-300);
    if h00 < -HESSIAN_TOL_REL_METRIC * scale2
        || h11 < -HESSIAN_TOL_REL_METRIC * scale2
        || h00 * h11 - h01 * h01 < -HESSIAN_TOL_REL_METRIC * scale2 * scale2
    {
        return false;
    }
    let scale = 1.0 + p.abs().max_element();
    if r.length() <= 1e-9 * scale {
        return true;
    }
    let g = (d.su.dot(r).abs() / (d.su.length() * r.length()).max(1e-300))
        .max(d.sv.dot(r).abs() / (d.sv.length() * r.length()).max(1e-300));
    g < 1e-6
}

/// True for surfaces whose parameter range ([`crate::geom::parameter_range`]) is their real
/// extent: B-spline/NURBS patches and spheres (latitude ±π/2). truck reports [0, 1] for a
/// plane and unbounded or arbitrary ranges for the other analytic and swept surfaces.
pub fn range_is_extent(surface: &Surface) -> bool {
    match surface {
        Surface::BSplineSurface(_) | Surface::NurbsSurface(_) => true,
        Surface::ElementarySurface(e) => matches!(e.as_ref(), ElementarySurface::Sphere(_)),
        Surface::SweptCurve(_) => false,
    }
}

/// The ranges iterates are clamped to: the parameter range in each direction that is bounded
/// and not periodic (a B-spline patch; a sphere's latitude), unbounded otherwise.
///
/// Only B-spline/NURBS patches and spheres are trusted: truck reports [0, 1] for a plane,
/// which is not a bound at all.
pub fn clamp_ranges(surface: &Surface) -> ((f64, f64), (f64, f64)) {
    if let Some(u) = extruded_spline_range(surface) {
        // The directrix of an extrusion ends where its knots end: beyond, truck extrapolates
        // the polynomial (an IGES tabulated cylinder over a closed 126 B-spline).
        return (u, (f64::NEG_INFINITY, f64::INFINITY));
    }
    if !range_is_extent(surface) {
        return (
            (f64::NEG_INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::INFINITY),
        );
    }
    let (ur, vr) = crate::geom::parameter_range(surface);
    let finite = |r: (Bound<f64>, Bound<f64>), periodic: bool| match r {
        (Bound::Included(a) | Bound::Excluded(a), Bound::Included(b) | Bound::Excluded(b))
            if a.is_finite() && b.is_finite() && !periodic =>
        {
            (a, b)
        }
        _ => (f64::NEG_INFINITY, f64::INFINITY),
    };
    (
        finite(ur, surface.u_period().is_some()),
        finite(vr, surface.v_period().is_some()),
    )
}

/// The valid knot range of an extrusion's directrix when it is a B-spline or NURBS curve.
fn extruded_spline_range(surface: &Surface) -> Option<(f64, f64)> {
    use truck_stepio::r#in::alias::{Curve3D, SweptCurve};
    let Surface::SweptCurve(s) = surface else {
        return None;
    };
    let SweptCurve::ExtrudedCurve(e) = s.as_ref() else {
        return None;
    };
    let (k, p) = match e.entity_curve() {
        Curve3D::BSplineCurve(c) => (c.knot_vec(), c.degree()),
        Curve3D::NurbsCurve(c) => (c.knot_vec(), c.degree()),
        _ => return None,
    };
    let m = k.len();
    (m > 2 * p + 1).then(|| (k[p], k[m - p - 1]))
}

/// [`newton`] has converged when the point is on the surface, or the gradient's part along
/// the parameter directions has vanished, to this fraction of the coordinates' size.
const CONVERGED_REL_COORD: f64 = 1e-12;

/// Levenberg–Marquardt on `½‖S(u,v) − p‖²` from `start`.
///
/// Iterates are clamped to the parameter range where it is finite (a B-spline patch), so a
/// point beyond the patch's border gets its nearest point on the border, not on the
/// polynomial's extrapolation.
fn newton(surface: &Surface, p: DVec3, start: (f64, f64)) -> Option<(f64, f64)> {
    let (ur, vr) = clamp_ranges(surface);
    let (mut u, mut v) = start;
    let mut lambda = 1e-3;
    let scale = 1.0 + p.abs().max_element();
    let mut d = eval_surface(surface, u, v);
    let mut f = 0.5 * (d.p - p).length_squared();
    for _ in 0..MAX_NEWTON_ITER {
        let r: DVec3 = d.p - p;
        let g = [d.su.dot(r), d.sv.dot(r)];
        let h = [
            [d.su.dot(d.su) + d.suu.dot(r), d.su.dot(d.sv) + d.suv.dot(r)],
            [d.su.dot(d.sv) + d.suv.dot(r), d.sv.dot(d.sv) + d.svv.dot(r)],
        ];
        // Gradient components pushing out of a clamped border do not count.
        let free =
            |x: f64, gx: f64, r: (f64, f64)| !((x <= r.0 && gx > 0.0) || (x >= r.1 && gx < 0.0));
        let g0 = if free(u, g[0], ur) { g[0] } else { 0.0 };
        let g1 = if free(v, g[1], vr) { g[1] } else { 0.0 };
        let gn = (g0.abs() / d.su.length().max(1e-300)).max(g1.abs() / d.sv.length().max(1e-300));
        if r.length() <= CONVERGED_REL_COORD * scale || gn <= CONVERGED_REL_COORD * scale {
            return Some((u, v));
        }
        let mut accepted = false;
        for _ in 0..20 {
            let diag = (h[0][0].abs() + h[1][1].abs()).max(1e-300) * lambda;
            let a = h[0][0] + diag;
            let b = h[0][1];
            let c = h[1][1] + diag;
            let det = a * c - b * b;
            if det.abs() < 1e-300 || !det.is_finite() {
                lambda *= 10.0;
                continue;
            }
            let du = -(c * g[0] - b * g[1]) / det;
            let dv = -(a * g[1] - b * g[0]) / det;
            let (nu, nv) = ((u + du).clamp(ur.0, ur.1), (v + dv).clamp(vr.0, vr.1));
            let (du, dv) = (nu - u, nv - v);
            let nd = eval_surface(surface, nu, nv);
            let nf = 0.5 * (nd.p - p).length_squared();
            if nf.is_finite() && nf <= f {
                let small = du.abs() + dv.abs() <= 1e-15 * (1.0 + u.abs() + v.abs());
                u = nu;
                v = nv;
                d = nd;
                f = nf;
                lambda = (lambda * 0.3).max(1e-12);
                accepted = true;
                if small {
                    return Some((u, v));
                }
                break;
            }
            lambda *= 10.0;
        }
        if !accepted {
            // No descent possible: a (possibly degenerate) minimum.
            return is_foot(surface, p, (u, v))
                .then_some((u, v))
                .or(Some((u, v)));
        }
    }
    Some((u, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};
    use truck_geometry::prelude::*;
    use truck_stepio::r#in::alias::ElementarySurface;

    /// Test angles: 400 spread by the golden ratio, then 8 next to the seam and half a turn
    /// away, where `acos` loses digits.
    const ANGLES: usize = 408;

    fn angle(k: usize) -> f64 {
        let near = [
            1e-10,
            TAU - 1e-10,
            PI - 1e-10,
            PI + 1e-10,
            1e-6,
            TAU - 1e-6,
            0.0,
            PI,
        ];
        if k < 400 {
            TAU * ((k as f64 * 0.618034) % 1.0)
        } else {
            near[k - 400]
        }
    }

    /// A cylinder (`apex_shift` 0) or cone about `axis`, placed by a rotation, a uniform scale
    /// and a shift, in both orientations: what truck-stepio makes of STEP's cylinders and
    /// cones, placed and scaled to mm.
    fn revolved(apex_shift: f64, inverted: bool, turn: f64, scale: f64) -> Surface {
        let (c, z) = (
            Point3::new(1.0, -2.0, 0.5),
            Vector3::new(0.3, 0.4, 1.0).normalize(),
        );
        let x = Vector3::new(1.0, 0.0, -0.3).normalize();
        let x = (x - z * x.dot(z)).normalize();
        let p = c + x * 2.0;
        let line = Line(p, p + z + x * apex_shift);
        let mut s = Processor::<_, Matrix4>::new(RevolutedCurve::by_revolution(line, c, z));
        if inverted {
            s.invert();
        }
        let m = Matrix4::from_translation(Vector3::new(5.0, 0.0, -3.0))
            * Matrix4::from_axis_angle(Vector3::new(1.0, 1.0, 0.0).normalize(), Rad(turn))
            * Matrix4::from_scale(scale);
        s.transform_by(m);
        let e = if apex_shift == 0.0 {
            ElementarySurface::CylindricalSurface(s)
        } else {
            ElementarySurface::ConicalSurface(s)
        };
        Surface::ElementarySurface(Box::new(e))
    }

    /// [`ClosedForm::foot`]'s distance and pole flag are what evaluating the surface at its
    /// parameters gives: the distance to 1e-12 of the size, and a regular point.
    fn assert_foot_is_the_surface_s(s: &Surface, p: DVec3, size: f64) {
        let foot = ClosedForm::new(s).foot(p).expect("closed form");
        let d = eval_surface(s, foot.uv.0, foot.uv.1);
        assert!(
            (foot.distance - d.p.distance(p)).abs() <= 1e-12 * size,
            "distance {} vs {}",
            foot.distance,
            d.p.distance(p)
        );
        let regular = d.su.cross(d.sv).length() > 1e-9 * d.su.length() * d.sv.length();
        assert_eq!(foot.pole, !regular);
    }

    /// The closed form gives truck's own answer (its search without a hint, which for a
    /// revolved line solves along the line and then takes the angle) for points on and near
    /// cylinders and cones, seam included: a foot at least as near and the same to 1e-7,
    /// the same parameters (the angle to truck's accuracy, 1e-7), the angle in truck's
    /// `[0, 2π]` (`2π − ε` rounds to 2π) and differing by a whole turn only at the seam.
    #[test]
    fn revolved_line_feet_are_truck_s() {
        let mut compared = 0;
        for (apex_shift, inverted, turn, scale) in [
            (0.0, true, 0.0, 1.0),
            (0.0, false, 0.7, 25.4),
            (0.4, true, 2.0, 1.0),
            (-0.25, false, -1.1, 0.001),
        ] {
            let s = revolved(apex_shift, inverted, turn, scale);
            for k in 0..ANGLES {
                let (a, h, off) = (
                    angle(k),
                    -1.5 + 3.0 * ((k as f64 * 0.414214) % 1.0),
                    0.2 * ((k as f64 * 0.732051) % 1.0) - 0.1,
                );
                let (u, v) = if inverted { (a, h) } else { (h, a) };
                let d = eval_surface(&s, u, v);
                let n = d.su.cross(d.sv).normalize();
                let p = d.p + n * off * scale;
                let ours = project_revolved_line(&s, p).expect("closed form");
                let q = Point3::new(p.x, p.y, p.z);
                let truck = s.search_nearest_parameter(q, None, 100).expect("truck");
                let foot = |uv: (f64, f64)| eval_surface(&s, uv.0, uv.1).p;
                let size = scale * 4.0;
                assert_foot_is_the_surface_s(&s, p, size);
                // Ours is at least as near as truck's (whose angle is off by up to 1.5e-8
                // rad next to the seam, where `acos` loses digits), and the same point.
                assert!(
                    foot(ours).distance(p) <= foot(truck).distance(p) + 1e-12 * size
                        && foot(ours).distance(foot(truck)) <= 1e-7 * size,
                    "{apex_shift} {inverted}: {ours:?} vs truck {truck:?}"
                );
                // The same parameters, the angle up to a whole turn only at the seam.
                let (ai, hi) = if inverted { (0, 1) } else { (1, 0) };
                let pick = |uv: (f64, f64), i: usize| if i == 0 { uv.0 } else { uv.1 };
                assert!((pick(ours, hi) - pick(truck, hi)).abs() <= 1e-9 * (1.0 + size));
                let (ao, at) = (pick(ours, ai), pick(truck, ai));
                assert!((0.0..=TAU).contains(&ao), "angle {ao} outside [0, 2π]");
                let da = (ao - at).abs();
                assert!(
                    da <= 1e-7 || ((da - TAU).abs() <= 1e-7 && ao.min(TAU - ao) <= 1e-7),
                    "angle {ao} vs truck {at}"
                );
                compared += 1;
            }
        }
        assert_eq!(compared, 1632);
    }

    /// The sphere's closed form gives the exact foot (on the ray from the centre, to 1e-12)
    /// for points on and near placed, scaled, mirrored spheres in both orientations, seam
    /// included, and truck's parameters to truck's accuracy (1e-7: its `acos` loses digits
    /// next to the seam and its Newton polish does not always recover them) wherever truck
    /// answers at all.
    #[test]
    fn sphere_feet_are_truck_s() {
        use truck_stepio::r#in::alias::Sphere as StepSphere;
        let mut compared = 0;
        for (inverted, mirrored, scale) in [
            (false, false, 1.0),
            (true, false, 2.5),
            (false, true, 0.3),
            (true, true, 25.4),
        ] {
            let mut s = Processor::<_, Matrix4>::new(StepSphere(
                truck_geometry::prelude::Sphere::new(Point3::origin(), 3.0),
            ));
            if inverted {
                s.invert();
            }
            let flip = if mirrored {
                Matrix4::from_nonuniform_scale(1.0, 1.0, -1.0)
            } else {
                Matrix4::from_scale(1.0)
            };
            s.transform_by(
                Matrix4::from_translation(Vector3::new(1.0, -2.0, 4.0))
                    * Matrix4::from_axis_angle(Vector3::new(0.2, 1.0, 0.4).normalize(), Rad(1.3))
                    * Matrix4::from_scale(scale)
                    * flip,
            );
            let s = Surface::ElementarySurface(Box::new(ElementarySurface::Sphere(s)));
            for k in 0..ANGLES {
                let lon = angle(k);
                let lat = 3.0 * ((k as f64 * 0.414214) % 1.0) - 1.5;
                let off = 0.2 * ((k as f64 * 0.732051) % 1.0) - 0.1;
                let (u, v) = if inverted { (lat, lon) } else { (lon, lat) };
                let d = eval_surface(&s, u, v);
                let n = d.su.cross(d.sv).normalize();
                let p = d.p + n * off * scale;
                let ours = project_sphere(&s, p).expect("closed form");
                let foot = |uv: (f64, f64)| eval_surface(&s, uv.0, uv.1).p;
                assert_foot_is_the_surface_s(&s, p, 3.0 * scale);
                // The nearest point of a sphere is along the ray from its centre.
                let centre = DVec3::new(1.0, -2.0, 4.0);
                let nearest = centre + (p - centre).normalize() * 3.0 * scale;
                assert!(foot(ours).distance(nearest) <= 1e-12 * 10.0 * scale, "{inverted} {mirrored} {scale}: uv {u} {v} ours {ours:?} foot {} nearest {nearest} p {p}", foot(ours));
                // truck's Newton polish sometimes fails (returns None): compare where it
                // answers.
                let q = Point3::new(p.x, p.y, p.z);
                let Some(truck) = s.search_nearest_parameter(q, None, 100) else {
                    continue;
                };
                assert!(
                    foot(ours).distance(foot(truck)) <= 1e-7 * 3.0 * scale,
                    "{inverted} {mirrored}: {ours:?} vs truck {truck:?}"
                );
                let d_ang = |a: f64, b: f64| ((a - b).abs()).min(((a - b).abs() - TAU).abs());
                // Longitude errors count as far as they move the point (near a pole, little).
                let (lon_o, lat_o, lon_t, lat_t) = if inverted {
                    (ours.1, ours.0, truck.1, truck.0)
                } else {
                    (ours.0, ours.1, truck.0, truck.1)
                };
                assert!(
                    d_ang(lon_o, lon_t) * lat_o.cos() <= 1e-7 && d_ang(lat_o, lat_t) <= 1e-7,
                    "{inverted} {mirrored}: {ours:?} vs truck {truck:?}"
                );
                compared += 1;
            }
        }
        assert!(compared >= 1200, "truck answered {compared} of 1600");
    }

    /// A plane's closed form is `project_point`'s foot, bit for bit, with the distance and
    /// pole flag of evaluating it.
    #[test]
    fn plane_feet_are_project_point_s() {
        let plane = Surface::ElementarySurface(Box::new(ElementarySurface::Plane(Plane::new(
            Point3::new(1.0, 2.0, -3.0),
            Point3::new(4.0, 2.5, -3.0),
            Point3::new(1.0, 2.0, 5.0),
        ))));
        assert!(matches!(ClosedForm::new(&plane), ClosedForm::Plane { .. }));
        for k in 0..ANGLES {
            let p = DVec3::new(
                10.0 * ((k as f64 * 0.618034) % 1.0) - 5.0,
                10.0 * ((k as f64 * 0.414214) % 1.0) - 5.0,
                10.0 * ((k as f64 * 0.732051) % 1.0) - 5.0,
            );
            let foot = ClosedForm::new(&plane).foot(p).expect("a foot");
            assert_eq!(Some(foot.uv), project_point(&plane, p, None));
            assert_foot_is_the_surface_s(&plane, p, 10.0);
        }
    }

    /// A point on the axis has every angle as a foot, and a shear is not a similarity: both
    /// are left to the search.
    #[test]
    fn revolved_line_declines_the_axis_and_non_similar_transforms() {
        let s = revolved(0.0, true, 0.0, 1.0);
        let axis_point = eval_surface(&s, 0.0, 0.5).p; // on the surface ...
        assert!(project_revolved_line(&s, axis_point).is_some());
        let Surface::ElementarySurface(e) = &s else {
            unreachable!()
        };
        let ElementarySurface::CylindricalSurface(pr) = e.as_ref() else {
            unreachable!()
        };
        // ... the axis itself: centre (1, −2, 0.5) placed by the shift.
        let c = DVec3::new(6.0, -2.0, -2.5);
        assert!(project_revolved_line(&s, c).is_none());
        let mut sheared = *pr;
        sheared.transform_by(Matrix4::new(
            1.0, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ));
        let sheared =
            Surface::ElementarySurface(Box::new(ElementarySurface::CylindricalSurface(sheared)));
        assert!(project_revolved_line(&sheared, axis_point).is_none());
        let plane = Surface::ElementarySurface(Box::new(ElementarySurface::Plane(Plane::new(
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ))));
        assert!(project_revolved_line(&plane, DVec3::ONE).is_none());
    }

    /// On a cylinder's or cone's axis, at a sphere's centre and above its pole every angle is
    /// a foot: [`ClosedForm::project_near`] answers with the hint's angle, and the point it
    /// gives is a foot (the offset normal to both derivatives) at the right distance.
    #[test]
    fn on_the_axis_the_foot_keeps_the_hint_s_angle() {
        let is_foot_at = |s: &Surface, p: DVec3, uv: (f64, f64), dist: f64, size: f64| {
            let d = eval_surface(s, uv.0, uv.1);
            let w = p - d.p;
            assert!(
                (w.length() - dist).abs() <= 1e-9 * size,
                "{} vs {dist}",
                w.length()
            );
            assert!(w.dot(d.su.normalize_or_zero()).abs() <= 1e-9 * size);
            assert!(w.dot(d.sv.normalize_or_zero()).abs() <= 1e-9 * size);
        };
        for (apex_shift, inverted, turn, scale) in [
            (0.0, true, 0.0, 1.0),
            (0.0, false, 0.7, 25.4),
            (0.4, true, 2.0, 1.0),
            (-0.25, false, -1.1, 0.001),
        ] {
            let s = revolved(apex_shift, inverted, turn, scale);
            let c = ClosedForm::new(&s);
            for (a, h) in [(0.3, 0.5), (2.0, -0.7), (5.9, 1.2)] {
                let uv = |a: f64| if inverted { (a, h) } else { (h, a) };
                let (p0, p1) = (eval_surface(&s, uv(a).0, uv(a).1).p, {
                    let b = uv(a + PI);
                    eval_surface(&s, b.0, b.1).p
                });
                let axis = 0.5 * (p0 + p1);
                assert!(c.project(axis).is_none(), "every angle is a foot");
                let hint = uv(1.25);
                let got = c.project_near(axis, hint).expect("a foot on the axis");
                let angle = if inverted { got.0 } else { got.1 };
                assert_eq!(angle, 1.25);
                let dist = (0..64)
                    .map(|k| {
                        let t = if inverted {
                            (0.1 * k as f64, h)
                        } else {
                            (h, 0.1 * k as f64)
                        };
                        let g = c.project_near(axis, t).unwrap();
                        eval_surface(&s, g.0, g.1).p.distance(axis)
                    })
                    .fold(f64::INFINITY, f64::min);
                is_foot_at(&s, axis, got, dist, 4.0 * scale);
            }
        }
        use truck_stepio::r#in::alias::Sphere as StepSphere;
        for inverted in [false, true] {
            let mut s = Processor::<_, Matrix4>::new(StepSphere(
                truck_geometry::prelude::Sphere::new(Point3::origin(), 3.0),
            ));
            if inverted {
                s.invert();
            }
            s.transform_by(Matrix4::from_translation(Vector3::new(1.0, -2.0, 4.0)));
            let s = Surface::ElementarySurface(Box::new(ElementarySurface::Sphere(s)));
            let c = ClosedForm::new(&s);
            let centre = DVec3::new(1.0, -2.0, 4.0);
            let hint = if inverted { (0.4, 2.0) } else { (2.0, 0.4) };
            assert!(c.project(centre).is_none());
            assert_eq!(c.project_near(centre, hint), Some(hint));
            is_foot_at(&s, centre, hint, 3.0, 3.0);
            for (z, lat) in [(1.0, PI / 2.0), (-5.0, -PI / 2.0)] {
                let above = centre + DVec3::Z * z;
                let got = c.project_near(above, hint).expect("the pole");
                let (lon, la) = if inverted { (got.1, got.0) } else { got };
                assert_eq!((lon, la), (2.0, lat));
                is_foot_at(&s, above, got, (3.0 - z.abs()).abs(), 3.0);
            }
        }
    }
}
