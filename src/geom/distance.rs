//! Distance queries on the exact boundary: nearest point of a trimmed face, of an edge, of the
//! whole boundary (through a bounding-volume hierarchy), faces within a radius, and
//! point-in-solid.
//!
//! **Nearest point of a trimmed face.** The nearest point of a face is an interior stationary
//! point of `‖S(u,v) − p‖` (a foot point inside the trim), a point of one of the face's edges,
//! or the vertex of a vertex loop (a pole, a cone's apex: the face comes to a point there and
//! the distance has no stationary point). [`nearest_on_face`] finds a foot point from a hint —
//! [`crate::geom::project_point`] on analytic surfaces, our own damped Newton [`descend`] on
//! B-spline and NURBS patches (4–30× faster than truck's search there, measured, and it never
//! climbs) — keeps it if [`trim::contains`] accepts it, and compares it with the nearest
//! point of every edge of the face's loops and with the vertex-loop vertices. It checks the
//! edges even when the foot is inside, because a foot point is only a *local* minimum (a
//! torus, a B-spline); when the foot is outside the trim the answer is on the boundary
//! anyway. Safeguards: where the projection converged to a stationary point farther than its
//! own seed (truck's Newton can), a descent from the seed replaces it; where a descent stops
//! against the border of a patch the face goes beyond (a closed NURBS surface, a patch
//! bounded only by vertex loops), descents from the [`EXTRA_SEEDS`] best local minima of a
//! grid over the face are tried too.
//!
//! **Nearest point of an edge.** [`nearest_on_edge`]: the best of a few samples (ends
//! included), then safeguarded Newton on `f(t) = ½‖C(t) − p‖²` (`f′ = C′·(C − p)`,
//! `f″ = C″·(C − p) + ‖C′‖²`, Gauss–Newton where `f″ ≤ 0`, step halving until `f` decreases),
//! clamped to the edge's range (wrapped around for a closed edge). Lines are solved in closed
//! form.
//!
//! **The boundary: [`Boundary`].** Built once per model (about 20 ms for a 150-face part);
//! it holds, for every curved face, a grid of *cells* over the UV rectangle the face covers
//! (its domain, reaching to any pole beyond a wrapping loop: [`trim::covered_domain`]) with a
//! box per cell that contains the surface over the cell; for every face a finer grid that
//! answers most trim tests without the polygon test, and its loops prepared for the rest
//! ([`trim::Trim`]); for every edge, samples with a *cover radius*; for every vertex its
//! pseudo-normal; and a [`Bvh`] over the faces' boxes. A query visits faces by branch and
//! bound: a face is evaluated only if its box, then the nearest of its cells' boxes, is
//! closer than the best distance so far, and the nearest cell's centre seeds the projection.
//! An edge is evaluated only if its box, then its nearest sample minus its cover radius, is
//! closer than the best so far. Queries do not allocate.
//!
//! *Cell boxes and the safety margin.* Over a UV cell `[u₀,u₁]×[v₀,v₁]` with sides `Δu, Δv`,
//! the surface deviates from the bilinear interpolant of its four corners by at most
//! `e = (Δu²·max‖Suu‖ + Δv²·max‖Svv‖)/8` (the tensor-product linear interpolation error
//! bound), and the bilinear interpolant lies in the convex hull of the corners. So the box of
//! the corners grown by `e` contains the surface over the cell. The maxima of `‖Suu‖`,
//! `‖Svv‖` over the cell are estimated as [`CURVATURE_SAFETY`] times their largest value at
//! the corners: this is the one non-rigorous step (a B-spline with a sharp bump inside one
//! cell could exceed it), which is why the factor is generous. Which cells cover the face:
//! every cell that is not provably outside the trim — a cell a loop polygon passes through
//! (walked in steps of a quarter cell) or neighbours, or a cell in a loop-free region whose
//! test point is inside. Planar faces need no cells: a planar region lies in the convex hull
//! of its boundary, so the union of its edges' boxes bounds it.
//!
//! *Edge cover radius.* Between consecutive samples the arc length is estimated by four
//! sub-chords times [`ARC_SAFETY`]; every point of the arc is within half of that of one of
//! the two samples, so `dist(p, edge) ≥ min_i ‖p − C(tᵢ)‖ − max_i Lᵢ/2`.
//!
//! **Point in solid.** [`Boundary::contains_point`] takes the nearest boundary point `q` and
//! the outward *pseudo-normal* there (Bærentzen & Aanæs, *Signed distance computation using
//! the angle weighted pseudonormal*, IEEE TVCG 11(3), 2005): the face normal on a face, the sum
//! of the adjacent faces' normals at `q` on an edge, the sum of the incident faces' normals
//! weighted by each face's corner angle at a vertex (a full turn of averaged normals at a
//! pole or apex). `p` is inside iff `(p − q)·n < 0`. The sign is right for every `p` whose
//! nearest point is `q` on a closed, oriented, manifold boundary (the theorem of the paper,
//! which carries over to curved faces because only the tangent cones at `q` matter). Voids
//! need nothing special: a void shell's faces have their outward normals pointing into the
//! void ([`crate::model::Face::sign`]).
//!
//! **Limits.**
//! - The trim is the loops' UV polygons (`brep::domain`, 32 samples per curved edge): a foot
//!   point in the sliver between a polygon chord and the exact edge is accepted although it
//!   is just outside the face (by at most the chord's sagitta, 0.5 % of a circle's radius),
//!   and one in the opposite sliver rejected (the edge then gives a point at most that much
//!   farther).
//! - The nearest point is only as global as the seeds: a face's foot point comes from the
//!   nearest cell centre (or the caller's hint), so a second, nearer basin of the distance
//!   inside the same face that no cell centre is closest to is missed. Tested against dense
//!   brute force on every face of every sample and of the real-world corpus.
//! - Points within [`ON_BOUNDARY`] × diagonal of the boundary are reported inside (the solid
//!   is closed); a knife edge (two faces meeting at 180° with opposite normals) has a zero
//!   pseudo-normal and reads as outside; non-manifold edges and solids that touch each other
//!   are outside the theorem's assumptions.
//!
//! All distances are in model units (millimetres).

use super::bbox::Aabb;
use super::bvh::{box_distance_squared, union, Bvh};
use super::eval::{eval_curve, eval_surface};
use super::project::clamp_ranges;
use super::project::{plane_frame, project_plane};
use super::surface::closed_periods;
use super::trim::{covered_domain, TrimGrid};
use super::{project_point, trim, unit_normal};
use crate::model::{Curve3D, Edge, Face, Model, Surface};
use glam::{DVec2, DVec3};
use std::ops::Range;

/// Which feature of the boundary a nearest point lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feature {
    /// Inside face `0` (an interior foot point).
    Face(usize),
    /// On edge `0` at curve parameter `1` (not at its ends).
    Edge(usize, f64),
    /// At vertex `0` (an end of an open edge).
    Vertex(usize),
}

/// The nearest point of a face (or of the boundary) to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHit {
    /// The nearest point (on the face's surface, inside its trim or on one of its edges).
    pub point: DVec3,
    /// `‖p − point‖`, model units.
    pub distance: f64,
    /// Parameters of `point` on the face's surface: the hint for the next nearby query.
    pub uv: (f64, f64),
    /// The feature the point lies on.
    pub on: Feature,
}

/// Newton iterations for the nearest point of an edge or a surface.
pub const MAX_ITER: usize = 50;

/// Step halvings per Newton iteration before giving up.
pub const MAX_HALVINGS: usize = 40;

/// Samples of a curved edge per quarter turn of a conic's angle parameter (so a full circle
/// gets 32 intervals, each 11.25°).
pub const SAMPLES_PER_QUARTER_TURN: usize = 8;

/// Samples per knot span of a B-spline edge per degree + 1.
pub const SAMPLES_PER_SPAN: usize = 2;

/// Fewest samples of a curved edge.
pub const MIN_EDGE_SAMPLES: usize = 8;

/// Most samples of a curved edge.
pub const MAX_EDGE_SAMPLES: usize = 256;

/// Cells of a curved face's grid along its longer side in 3D (proportionally fewer along the
/// shorter). 8 measured faster than 16 on the benchmark parts (a smaller scan per face
/// outweighs the looser bounds).
pub const MAX_FACE_GRID: usize = 8;

/// Fewest cells per direction of a face's grids.
pub const MIN_FACE_GRID: usize = 2;

/// Cells per direction, along the longer side, of the grid that answers most trim tests
/// without the polygon test (a grid of cells classified inside, outside or near a loop).
pub const TRIM_GRID: usize = 64;

/// Factor on the largest second derivative at a cell's corners to bound it over the cell.
pub const CURVATURE_SAFETY: f64 = 2.0;

/// Factor on the sum of four sub-chords to bound the arc length between two edge samples.
pub const ARC_SAFETY: f64 = 1.05;

/// Points closer to the boundary than this fraction of the model's diagonal are on it
/// ([`Boundary::contains_point`] says inside).
pub const ON_BOUNDARY: f64 = 1e-9;

/// Normals averaged around a pole or apex for its pseudo-normal.
pub const POLE_NORMAL_SAMPLES: usize = 8;

/// Seeds per direction of the grid that finds a hint when [`nearest_on_face`] gets none.
pub const SEED_GRID: usize = 8;

// ---------------------------------------------------------------------------------------------
// Edges
// ---------------------------------------------------------------------------------------------

/// The nearest point of edge `edge` to `p`: `(t, point, distance)` with `t` in the edge's
/// range. `hint_t` (a previous answer) is tried as an extra Newton start.
pub fn nearest_on_edge(
    model: &Model,
    edge: usize,
    p: DVec3,
    hint_t: Option<f64>,
) -> (f64, DVec3, f64) {
    let e = &model.edges[edge];
    let (t, x, d2) = edge_nearest(e, p, hint_t, None, wraps_around(e));
    (t, x, d2.sqrt())
}

/// `(lo, hi)` of the edge's range.
#[inline]
fn edge_span(e: &Edge) -> (f64, f64) {
    (e.range.0.min(e.range.1), e.range.0.max(e.range.1))
}

/// Number of samples (ends included) of an edge.
fn edge_sample_count(e: &Edge) -> usize {
    let (lo, hi) = edge_span(e);
    let n = match &e.curve {
        Curve3D::Line(_) => 2,
        Curve3D::Conic(_) => {
            let quarter = std::f64::consts::FRAC_PI_2;
            ((hi - lo) / quarter * SAMPLES_PER_QUARTER_TURN as f64).ceil() as usize + 1
        }
        Curve3D::BSplineCurve(c) => {
            spans_in(c.knot_vec(), lo, hi) * SAMPLES_PER_SPAN * (c.degree() + 1) + 1
        }
        Curve3D::NurbsCurve(c) => {
            spans_in(c.knot_vec(), lo, hi) * SAMPLES_PER_SPAN * (c.non_rationalized().degree() + 1)
                + 1
        }
        Curve3D::Polyline(pl) => 2 * pl.0.len() + 1,
        Curve3D::PCurve(_) => 4 * SAMPLES_PER_QUARTER_TURN + 1,
    };
    if matches!(e.curve, Curve3D::Line(_)) {
        2
    } else {
        n.clamp(MIN_EDGE_SAMPLES, MAX_EDGE_SAMPLES)
    }
}

/// Number of non-empty knot spans meeting `[lo, hi]`.
fn spans_in(knots: &truck_geometry::prelude::KnotVec, lo: f64, hi: f64) -> usize {
    let mut n = 0;
    for w in knots.windows(2) {
        if w[1] > w[0] && w[1] > lo && w[0] < hi {
            n += 1;
        }
    }
    n.max(1)
}

/// Parameter of sample `k` of `n` (uniform in `t`, ends exact).
#[inline]
fn edge_sample_t(e: &Edge, k: usize, n: usize) -> f64 {
    let (lo, hi) = edge_span(e);
    if k + 1 == n {
        hi
    } else {
        lo + (hi - lo) * k as f64 / (n - 1) as f64
    }
}

/// True when the edge is a closed curve traversed once (a full circle): its parameter wraps.
#[inline]
fn wraps_around(e: &Edge) -> bool {
    e.is_closed() && {
        let (lo, hi) = edge_span(e);
        let a = eval_curve(&e.curve, lo).p;
        let b = eval_curve(&e.curve, hi).p;
        a.distance(b) <= 1e-9 * (1.0 + a.abs().max_element())
    }
}

/// Nearest point of an edge: `(t, point, distance²)`. `samples`, when given, are the edge's
/// cached samples `(t, point)`; otherwise the edge is sampled on the fly.
fn edge_nearest(
    e: &Edge,
    p: DVec3,
    hint_t: Option<f64>,
    samples: Option<(&[f64], &[DVec3])>,
    wrap: bool,
) -> (f64, DVec3, f64) {
    let (lo, hi) = edge_span(e);
    if let Curve3D::Line(_) = e.curve {
        let d = eval_curve(&e.curve, lo);
        let len2 = d.d1.length_squared();
        let t = if len2 > 0.0 {
            (lo + (p - d.p).dot(d.d1) / len2).clamp(lo, hi)
        } else {
            lo
        };
        let x = d.p + d.d1 * (t - lo);
        return (t, x, x.distance_squared(p));
    }
    // Best sample (ends included).
    let mut best = (lo, DVec3::NAN, f64::INFINITY);
    match samples {
        Some((ts, ps)) => {
            for (t, x) in ts.iter().zip(ps) {
                let d2 = x.distance_squared(p);
                if d2 < best.2 {
                    best = (*t, *x, d2);
                }
            }
        }
        None => {
            let n = edge_sample_count(e);
            for k in 0..n {
                let t = edge_sample_t(e, k, n);
                let x = eval_curve(&e.curve, t).p;
                let d2 = x.distance_squared(p);
                if d2 < best.2 {
                    best = (t, x, d2);
                }
            }
        }
    }
    let mut out = curve_newton(e, p, best.0, wrap);
    if best.2 < out.2 {
        out = best;
    }
    if let Some(h) = hint_t {
        let r = curve_newton(e, p, h, wrap);
        if r.2 < out.2 {
            out = r;
        }
    }
    out
}

/// Safeguarded Newton on `½‖C(t) − p‖²` from `t0` (see the module docs). Never returns a
/// point farther than the start's.
fn curve_newton(e: &Edge, p: DVec3, t0: f64, wrap: bool) -> (f64, DVec3, f64) {
    let (lo, hi) = edge_span(e);
    let fix = |t: f64| {
        if wrap && hi > lo {
            lo + (t - lo).rem_euclid(hi - lo)
        } else {
            t.clamp(lo, hi)
        }
    };
    let mut t = fix(t0);
    let mut d = eval_curve(&e.curve, t);
    let mut f = d.p.distance_squared(p);
    if !f.is_finite() {
        return (t, d.p, f64::INFINITY);
    }
    for _ in 0..MAX_ITER {
        let r = d.p - p;
        let g = d.d1.dot(r);
        let mut h = d.d2.dot(r) + d.d1.length_squared();
        if h.is_nan() || h <= 0.0 {
            h = d.d1.length_squared();
        }
        if h.is_nan() || h <= 0.0 || g == 0.0 {
            break;
        }
        let mut step = -g / h;
        let mut moved = false;
        for _ in 0..MAX_HALVINGS {
            let tn = fix(t + step);
            if tn == t {
                break;
            }
            let dn = eval_curve(&e.curve, tn);
            let fnew = dn.p.distance_squared(p);
            if fnew <= f {
                let small = (tn - t).abs() <= 1e-15 * (1.0 + t.abs()) + 1e-14 * (hi - lo);
                t = tn;
                d = dn;
                f = fnew;
                moved = !small;
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    (t, d.p, f)
}

/// The feature of an edge point at parameter `t`: a vertex at an end of an open edge.
fn edge_feature(e: &Edge, edge: usize, t: f64, wrap: bool) -> Feature {
    if !wrap {
        if t == e.range.0 {
            return Feature::Vertex(e.vertices[0]);
        }
        if t == e.range.1 {
            return Feature::Vertex(e.vertices[1]);
        }
    }
    Feature::Edge(edge, t)
}

// ---------------------------------------------------------------------------------------------
// Faces
// ---------------------------------------------------------------------------------------------

/// Damped Newton (Levenberg–Marquardt) descent of `½‖S(u,v) − p‖²` from `start`: every
/// accepted step decreases the distance, so the result is never farther than the start.
/// Used where [`project_point`] lands on a stationary point farther than its seed, and to
/// continue across the seam of a closed B-spline surface. Iterates are clamped to a
/// B-spline's parameter range, except in a direction where the surface is closed
/// ([`closed_periods`]): there they wrap around.
pub fn descend(surface: &Surface, p: DVec3, start: (f64, f64)) -> (f64, f64) {
    descend_wrapped(surface, p, start, closed_periods(surface))
}

fn descend_wrapped(
    surface: &Surface,
    p: DVec3,
    start: (f64, f64),
    closed: (bool, bool),
) -> (f64, f64) {
    let (ur, vr) = clamp_ranges(surface);
    let fix = |x: f64, r: (f64, f64), wrap: bool| {
        if wrap && r.1 > r.0 && r.1.is_finite() && r.0.is_finite() {
            r.0 + (x - r.0).rem_euclid(r.1 - r.0)
        } else {
            x.clamp(r.0, r.1)
        }
    };
    let (mut u, mut v) = (fix(start.0, ur, closed.0), fix(start.1, vr, closed.1));
    let mut d = eval_surface(surface, u, v);
    let mut f = 0.5 * d.p.distance_squared(p);
    if !f.is_finite() {
        return (u, v);
    }
    let scale = 1.0 + p.abs().max_element();
    let mut lambda = 0.0;
    for _ in 0..MAX_ITER {
        let r = d.p - p;
        let mut g = (d.su.dot(r), d.sv.dot(r));
        // A gradient component pushing out of a clamped border does not count.
        let pinned = |x: f64, gx: f64, rr: (f64, f64), wrap: bool| {
            !wrap && ((x <= rr.0 && gx > 0.0) || (x >= rr.1 && gx < 0.0))
        };
        let pin_u = pinned(u, g.0, ur, closed.0);
        let pin_v = pinned(v, g.1, vr, closed.1);
        if pin_u {
            g.0 = 0.0;
        }
        if pin_v {
            g.1 = 0.0;
        }
        // Converged: the residual is normal to the surface (tangential part ≤ 1e-13 · size).
        let tangential = (g.0.abs() / d.su.length().max(f64::MIN_POSITIVE))
            .max(g.1.abs() / d.sv.length().max(f64::MIN_POSITIVE));
        if tangential <= 1e-13 * scale {
            break;
        }
        // Newton's Hessian where it is positive definite, Gauss–Newton's JᵀJ otherwise.
        let gn = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let full = (
            gn.0 + d.suu.dot(r),
            gn.1 + d.suv.dot(r),
            gn.2 + d.svv.dot(r),
        );
        let h = if full.0 > 0.0 && full.0 * full.2 - full.1 * full.1 > 0.0 {
            full
        } else {
            gn
        };
        let mut accepted = false;
        for _ in 0..MAX_HALVINGS {
            let damp = (h.0.abs() + h.2.abs()).max(f64::MIN_POSITIVE) * lambda;
            // A pinned variable stays on its border: Newton in the other one alone.
            let (a, b, c) = (
                h.0 + damp,
                if pin_u || pin_v { 0.0 } else { h.1 },
                h.2 + damp,
            );
            let det = a * c - b * b;
            if det.is_nan() || det <= 0.0 || a.is_nan() || a <= 0.0 {
                lambda = (lambda * 10.0).max(1e-9);
                continue;
            }
            let du = -(c * g.0 - b * g.1) / det;
            let dv = -(a * g.1 - b * g.0) / det;
            let (nu, nv) = (fix(u + du, ur, closed.0), fix(v + dv, vr, closed.1));
            if nu == u && nv == v {
                break;
            }
            let nd = eval_surface(surface, nu, nv);
            let nf = 0.5 * nd.p.distance_squared(p);
            if nf <= f {
                let small = (nu - u).abs() + (nv - v).abs() <= 1e-14 * (1.0 + u.abs() + v.abs());
                u = nu;
                v = nv;
                d = nd;
                f = nf;
                lambda *= 0.1;
                accepted = !small;
                break;
            }
            lambda = (lambda * 10.0).max(1e-9);
        }
        if !accepted {
            break;
        }
    }
    (u, v)
}

/// True when `uv` sits on the clamped border of a closed direction.
fn on_closed_border(surface: &Surface, uv: (f64, f64), closed: (bool, bool)) -> bool {
    let (ur, vr) = clamp_ranges(surface);
    let at = |x: f64, r: (f64, f64)| {
        let tol = 1e-12 * (r.1 - r.0).abs().max(1.0);
        (x - r.0).abs() <= tol || (x - r.1).abs() <= tol
    };
    (closed.0 && at(uv.0, ur)) || (closed.1 && at(uv.1, vr))
}

/// Per-face data that [`Boundary`] caches; [`nearest_on_face`] works without it.
struct Cached<'a> {
    boundary: &'a Boundary,
}

/// The nearest point of face `fi` closer than `bound` (the hit, or `None` when nothing on
/// the face is closer). `need_uv`: compute the surface parameters of an edge hit.
fn face_nearest(
    model: &Model,
    fi: usize,
    p: DVec3,
    hint: Option<(f64, f64)>,
    bound: f64,
    cache: Option<Cached<'_>>,
    need_uv: bool,
) -> Option<FaceHit> {
    let face = &model.faces[fi];
    let (plane, closed) = match &cache {
        Some(c) => (c.boundary.faces[fi].plane, c.boundary.faces[fi].closed),
        None => (plane_frame(&face.surface), closed_periods(&face.surface)),
    };
    // Seed: the nearest cell's centre (cached) or the nearest node of a coarse grid.
    let mut seed: Option<(DVec2, f64)> = None;
    if plane.is_none() {
        match &cache {
            Some(c) => match c.boundary.cell_seed(fi, p, bound) {
                Some(s) => seed = s,
                None => return None,
            },
            None if hint.is_none() => seed = grid_seed(face, p),
            None => {}
        }
    }
    let start = hint.or(seed.map(|s| (s.0.x, s.0.y)));
    let mut best_d = bound;
    let mut best: Option<FaceHit> = None;
    // Interior candidate.
    let from = start.unwrap_or((face.domain.u.0, face.domain.v.0));
    let foot = match plane {
        Some(frame) => Some(project_plane(frame, p)),
        // Our descent is 4–30× faster than truck's search on B-splines (measured), and
        // never climbs; analytic surfaces keep the shared projection (under 1 µs).
        None if is_spline(&face.surface) => Some(descend_wrapped(&face.surface, p, from, closed)),
        None => project_point(&face.surface, p, Some(from)),
    };
    let mut interior: Option<((f64, f64), DVec3, f64)> = foot.map(|uv| {
        let x = crate::geom::surface_point(&face.surface, uv.0, uv.1);
        (uv, x, x.distance(p))
    });
    let better = |cand: (f64, f64), cur: &mut Option<((f64, f64), DVec3, f64)>| {
        let x = crate::geom::surface_point(&face.surface, cand.0, cand.1);
        let d = x.distance(p);
        if cur.is_none_or(|c| d < c.2) {
            *cur = Some((cand, x, d));
        }
    };
    if plane.is_none() {
        if let (Some((s, ds)), Some((_, _, d))) = (seed, interior) {
            if d.is_nan() || d > ds * (1.0 + 1e-12) {
                // The projection climbed to a farther stationary point: descend instead.
                better(
                    descend_wrapped(&face.surface, p, (s.x, s.y), closed),
                    &mut interior,
                );
            }
        }
        if let Some((uv, _, _)) = interior {
            if on_closed_border(&face.surface, uv, closed) {
                // Stuck at the seam of a closed B-spline: continue on the other side.
                better(descend_wrapped(&face.surface, p, uv, closed), &mut interior);
            }
        }
        let no_edges = face.loops.iter().all(|l| l.edges.is_empty());
        let suspicious = |uv: (f64, f64)| {
            on_range_border(&face.surface, uv) && (no_edges || closed.0 || closed.1)
        };
        if interior.is_none_or(|(uv, _, _)| suspicious(uv)) {
            // Stopped against the border of a patch that the face goes beyond (no edge
            // bounds it there: a closed NURBS sphere), or failed: the distance may have
            // other basins. Descend from the best local minima of a coarse grid too.
            for s in local_minima_seeds(face, p).into_iter().flatten() {
                better(
                    descend_wrapped(&face.surface, p, (s.x, s.y), closed),
                    &mut interior,
                );
            }
        }
    }
    let interior_uv = interior.map(|i| i.0);
    if let Some((uv, x, d)) = interior {
        let uv2 = DVec2::new(uv.0, uv.1);
        let inside = || match &cache {
            Some(c) => c.boundary.contains_uv(face, fi, uv2),
            None => trim::contains(face, uv2),
        };
        if d < best_d && inside() {
            best_d = d;
            best = Some(FaceHit {
                point: x,
                distance: d,
                uv,
                on: Feature::Face(fi),
            });
        }
    }
    // Boundary candidates.
    let mut edge_best: Option<(usize, f64, DVec3, f64)> = None;
    let mut consider = |ei: usize, best_d: &mut f64| {
        let e = &model.edges[ei];
        let (t, x, d2) = match &cache {
            Some(c) => {
                let ec = &c.boundary.edges[ei];
                if box_distance_squared(&ec.bbox, p) >= *best_d * *best_d {
                    return;
                }
                let ts = &c.boundary.edge_t[range(&ec.samples)];
                let ps = &c.boundary.edge_p[range(&ec.samples)];
                if !matches!(e.curve, Curve3D::Line(_)) {
                    // Skip the edge when its nearest sample, less the cover radius, is not
                    // nearer than `best_d`. The same test on each sample, stopping at the
                    // first that passes, decides alike (sqrt and subtraction are monotone,
                    // so the nearest sample passes if any does); the squared prefilter is
                    // wider than the test by far more than rounding.
                    let reach = (*best_d + ec.cover) * (1.0 + 1e-9);
                    let near_enough = ps.iter().any(|x| {
                        let d2 = x.distance_squared(p);
                        d2 <= reach * reach && d2.sqrt() - ec.cover < *best_d
                    });
                    if !near_enough {
                        return;
                    }
                }
                edge_nearest(e, p, None, Some((ts, ps)), ec.wrap)
            }
            None => edge_nearest(e, p, None, None, wraps_around(e)),
        };
        let d = d2.sqrt();
        if d < *best_d {
            *best_d = d;
            edge_best = Some((ei, t, x, d));
        }
    };
    match &cache {
        Some(c) => {
            for &ei in &c.boundary.face_edges[range(&c.boundary.faces[fi].edges)] {
                consider(ei as usize, &mut best_d);
            }
        }
        None => {
            for (k, l) in face.loops.iter().enumerate() {
                for (j, oe) in l.edges.iter().enumerate() {
                    // Each edge once (a seam appears twice in its loop).
                    let seen = face.loops[..k]
                        .iter()
                        .flat_map(|l| l.edges.iter())
                        .chain(l.edges[..j].iter())
                        .any(|o| o.edge == oe.edge);
                    if !seen {
                        consider(oe.edge, &mut best_d);
                    }
                }
            }
        }
    }
    // The vertices of vertex loops (a pole, a cone's apex) belong to the face too, and the
    // distance has no stationary point there where the face comes to a point.
    let mut pole_best = None;
    for l in &face.loops {
        if let (Some(v), Some(uv)) = (l.vertex, l.uv.first()) {
            let x = model.vertices[v].point;
            let d = x.distance(p);
            if d < best_d {
                best_d = d;
                pole_best = Some(FaceHit {
                    point: x,
                    distance: d,
                    uv: (uv.x, uv.y),
                    on: Feature::Vertex(v),
                });
            }
        }
    }
    if pole_best.is_some() {
        return pole_best;
    }
    if let Some((ei, t, x, d)) = edge_best {
        let uv = if need_uv {
            let hint = match &cache {
                Some(c) => c.boundary.edge_uv_hint(model, ei, fi, t),
                None => None,
            }
            .or(interior_uv)
            .or(start);
            match plane {
                Some(frame) => project_plane(frame, x),
                None => surface_params(&face.surface, x, hint),
            }
        } else {
            (f64::NAN, f64::NAN)
        };
        best = Some(FaceHit {
            point: x,
            distance: d,
            uv,
            on: edge_feature(
                &model.edges[ei],
                ei,
                t,
                match &cache {
                    Some(c) => c.boundary.edges[ei].wrap,
                    None => wraps_around(&model.edges[ei]),
                },
            ),
        });
    }
    best
}

#[inline]
fn range(r: &Range<u32>) -> Range<usize> {
    r.start as usize..r.end as usize
}

/// The nearest node of a `SEED_GRID` grid over the face's domain, preferring nodes inside the
/// trim: `(uv, distance)`.
fn grid_seed(face: &Face, p: DVec3) -> Option<(DVec2, f64)> {
    let (u, v) = covered_domain(face);
    let d = &crate::model::UvDomain {
        u,
        v,
        ..face.domain
    };
    let mut best_in: Option<(DVec2, f64)> = None;
    let mut best_any: Option<(DVec2, f64)> = None;
    for i in 0..=SEED_GRID {
        for j in 0..=SEED_GRID {
            let uv = DVec2::new(
                d.u.0 + (d.u.1 - d.u.0) * i as f64 / SEED_GRID as f64,
                d.v.0 + (d.v.1 - d.v.0) * j as f64 / SEED_GRID as f64,
            );
            let dist = crate::geom::surface_point(&face.surface, uv.x, uv.y).distance(p);
            if !dist.is_finite() {
                continue;
            }
            if best_any.is_none_or(|b| dist < b.1) {
                best_any = Some((uv, dist));
            }
            if best_in.is_none_or(|b| dist < b.1) && trim::contains(face, uv) {
                best_in = Some((uv, dist));
            }
        }
    }
    best_in.or(best_any)
}

/// Seeds beyond the first when a projection ends on a patch border: the best
/// [`EXTRA_SEEDS`] local minima of the distance over a [`EXTRA_SEED_GRID`]² grid on the face's
/// domain (distinct points only: a pole is one point whatever its `u`).
pub const EXTRA_SEEDS: usize = 4;

/// Cells per direction of the grid that finds the extra seeds (it must resolve the basin of
/// the true nearest point: 24 does on the samples' closed NURBS surfaces, 8 did not).
pub const EXTRA_SEED_GRID: usize = 24;

fn local_minima_seeds(face: &Face, p: DVec3) -> [Option<DVec2>; EXTRA_SEEDS] {
    const N: usize = EXTRA_SEED_GRID + 1;
    let (u, v) = covered_domain(face);
    let d = &crate::model::UvDomain {
        u,
        v,
        ..face.domain
    };
    let mut dist = [[f64::INFINITY; N]; N];
    let mut point = [[DVec3::NAN; N]; N];
    let uv_at = |i: usize, j: usize| {
        DVec2::new(
            d.u.0 + (d.u.1 - d.u.0) * i as f64 / EXTRA_SEED_GRID as f64,
            d.v.0 + (d.v.1 - d.v.0) * j as f64 / EXTRA_SEED_GRID as f64,
        )
    };
    let mut size: f64 = 0.0;
    for i in 0..N {
        for j in 0..N {
            let uv = uv_at(i, j);
            let x = crate::geom::surface_point(&face.surface, uv.x, uv.y);
            let q = x.distance(p);
            if q.is_finite() {
                dist[i][j] = q;
                point[i][j] = x;
                size = size.max(x.abs().max_element());
            }
        }
    }
    let same = 1e-9 * size.max(f64::MIN_POSITIVE);
    let mut out: [Option<(DVec2, f64, DVec3)>; EXTRA_SEEDS] = [None; EXTRA_SEEDS];
    for i in 0..N {
        for j in 0..N {
            let here = dist[i][j];
            if !here.is_finite() {
                continue;
            }
            let mut minimum = true;
            for (di, dj) in [
                (-1i64, -1i64),
                (-1, 0),
                (-1, 1),
                (0, -1),
                (0, 1),
                (1, -1),
                (1, 0),
                (1, 1),
            ] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if a >= 0
                    && b >= 0
                    && (a as usize) < N
                    && (b as usize) < N
                    && dist[a as usize][b as usize] < here
                {
                    minimum = false;
                }
            }
            let x = point[i][j];
            if !minimum || out.iter().flatten().any(|s| s.2.distance(x) <= same) {
                continue;
            }
            // Insert into the sorted top list.
            let mut item = Some((uv_at(i, j), here, x));
            for slot in out.iter_mut() {
                match (*slot, item) {
                    (None, _) => {
                        *slot = item;
                        break;
                    }
                    (Some(s), Some(it)) if it.1 < s.1 => {
                        *slot = Some(it);
                        item = Some(s);
                    }
                    _ => {}
                }
            }
        }
    }
    out.map(|o| o.map(|(uv, _, _)| uv))
}

/// True for B-spline and NURBS surfaces.
fn is_spline(s: &Surface) -> bool {
    matches!(s, Surface::BSplineSurface(_) | Surface::NurbsSurface(_))
}

/// True when `uv` is on the border of a B-spline patch's parameter range.
fn on_range_border(surface: &Surface, uv: (f64, f64)) -> bool {
    let (ur, vr) = clamp_ranges(surface);
    let at = |x: f64, r: (f64, f64)| {
        let tol = 1e-12 * (r.1 - r.0).abs().max(1.0);
        (x - r.0).abs() <= tol || (x - r.1).abs() <= tol
    };
    at(uv.0, ur) || at(uv.1, vr)
}

/// The nearest point of the trimmed face `face` to `p` (see the module docs), or `None` when
/// the projection fails and the face has no edges. `hint`: the `uv` of a previous hit on this
/// face; with it the interior candidate is the foot point nearest the hint (the usual case
/// when following a curve), without it a coarse grid over the face picks the start.
///
/// This works on the model alone; [`Boundary::nearest_on_face`] does the same with cached
/// samples (faster, and prunes by a bound).
pub fn nearest_on_face(
    model: &Model,
    face: usize,
    p: DVec3,
    hint: Option<(f64, f64)>,
) -> Option<FaceHit> {
    face_nearest(model, face, p, hint, f64::INFINITY, None, true)
}

// ---------------------------------------------------------------------------------------------
// The boundary
// ---------------------------------------------------------------------------------------------

/// A UV cell of a curved face: a box containing the surface over the cell, and its centre.
#[derive(Clone, Copy, Debug)]
struct Cell {
    bbox: Aabb,
    rep: DVec3,
    uv: DVec2,
}

/// Up to [`CELL_BLOCK`] consecutive cells of one face, with a box around their centres and
/// one around their boxes: a query skips a block that can hold neither a nearer centre nor a
/// box within its bound (the distance to a box is at most that to anything in it, rounding
/// included: subtraction, squaring and the sum are monotone).
#[derive(Clone, Debug)]
struct CellBlock {
    reps: Aabb,
    boxes: Aabb,
    cells: Range<u32>,
}

/// Cells per [`CellBlock`] (a row of the finest face grid).
const CELL_BLOCK: usize = MAX_FACE_GRID;

#[derive(Clone, Debug)]
struct FaceCache {
    /// `(origin, Su, Sv)` of a planar face.
    plane: Option<(DVec3, DVec3, DVec3)>,
    /// [`closed_periods`] of the surface.
    closed: (bool, bool),
    cells: Range<u32>,
    /// The cells in blocks, into `Boundary::blocks`.
    blocks: Range<u32>,
    /// Fast inside/outside lookup for the trim ([`TRIM_GRID`] cells along the longer side).
    trim: Option<TrimGrid>,
    /// The loops prepared for the exact test where the grid cannot tell.
    loops: trim::Trim,
    /// Distinct edges of the face's loops, into `Boundary::face_edges`.
    edges: Range<u32>,
    bbox: Aabb,
}

#[derive(Clone, Debug)]
struct EdgeCache {
    samples: Range<u32>,
    /// [`wraps_around`]: a closed curve whose parameter wraps.
    wrap: bool,
    cover: f64,
    bbox: Aabb,
    /// Start of this edge's `uv` table in `Boundary::edge_uv`: for each entry of
    /// `edge.faces`, the parameters of every sample on that face.
    uv_start: u32,
}

/// The model's boundary prepared for distance queries (see the module docs): built once per
/// model with [`Boundary::new`], then queried with the same model.
#[derive(Clone, Debug)]
pub struct Boundary {
    bvh: Bvh,
    faces: Vec<FaceCache>,
    cells: Vec<Cell>,
    blocks: Vec<CellBlock>,
    face_edges: Vec<u32>,
    edges: Vec<EdgeCache>,
    edge_t: Vec<f64>,
    edge_p: Vec<DVec3>,
    edge_uv: Vec<DVec2>,
    /// Angle-weighted pseudo-normal of each vertex (not normalised).
    vertex_normals: Vec<DVec3>,
    /// Distance under which a point is on the boundary.
    on_boundary: f64,
}

impl Boundary {
    /// Samples the model's faces and edges and builds the hierarchy.
    pub fn new(model: &Model) -> Boundary {
        let mut b = Boundary {
            bvh: Bvh::new(&[]),
            faces: Vec::with_capacity(model.faces.len()),
            cells: Vec::new(),
            blocks: Vec::new(),
            face_edges: Vec::new(),
            edges: Vec::with_capacity(model.edges.len()),
            edge_t: Vec::new(),
            edge_p: Vec::new(),
            edge_uv: Vec::new(),
            vertex_normals: vec![DVec3::ZERO; model.vertices.len()],
            on_boundary: 0.0,
        };
        let loop_points: Vec<Vec<(DVec2, DVec3)>> = model.faces.iter().map(loop_points).collect();
        for e in &model.edges {
            b.add_edge(model, e, &loop_points);
        }
        for (fi, face) in model.faces.iter().enumerate() {
            b.add_face(fi, face);
        }
        b.add_vertex_normals(model, &loop_points);
        let boxes: Vec<Aabb> = b.faces.iter().map(|f| f.bbox).collect();
        // The scale from the faces' boxes (a slight over-estimate of the model's box, and much
        // cheaper than `Model::diagonal`, which samples every face again).
        let all = boxes.iter().fold(
            Aabb::EMPTY,
            |a, f| if f.is_empty() { a } else { union(&a, f) },
        );
        b.on_boundary = if all.is_empty() {
            0.0
        } else {
            ON_BOUNDARY * (all.max - all.min).length()
        };
        b.bvh = Bvh::new(&boxes);
        b
    }

    fn add_edge(&mut self, model: &Model, e: &Edge, loop_points: &[Vec<(DVec2, DVec3)>]) {
        let n = edge_sample_count(e);
        let start = self.edge_t.len() as u32;
        let mut bbox = Aabb::EMPTY;
        let mut cover: f64 = 0.0;
        let mut grow: f64 = 0.0;
        let mut prev: Option<(f64, DVec3)> = None;
        for k in 0..n {
            let t = edge_sample_t(e, k, n);
            let x = eval_curve(&e.curve, t).p;
            bbox.add(x);
            if let Some((t0, x0)) = prev {
                // Arc length between samples from four sub-chords.
                let mut len = 0.0;
                let mut a = x0;
                for s in 1..=4 {
                    let b = if s == 4 {
                        x
                    } else {
                        eval_curve(&e.curve, t0 + (t - t0) * s as f64 / 4.0).p
                    };
                    bbox.add(b);
                    let chord = a.distance(b);
                    grow = grow.max(0.5 * ARC_SAFETY * chord);
                    len += chord;
                    a = b;
                }
                cover = cover.max(0.5 * ARC_SAFETY * len);
            }
            self.edge_t.push(t);
            self.edge_p.push(x);
            prev = Some((t, x));
        }
        if matches!(e.curve, Curve3D::Line(_)) {
            grow = 0.0;
        }
        bbox.min -= DVec3::splat(grow);
        bbox.max += DVec3::splat(grow);
        // Parameters of the samples on each adjacent face, following the edge with hints.
        let uv_start = self.edge_uv.len() as u32;
        for &f in &e.faces {
            let face = &model.faces[f];
            let plane = plane_frame(&face.surface);
            let mut hint = None;
            for k in 0..n {
                let x = self.edge_p[start as usize + k];
                let uv = match plane {
                    Some(frame) => Some(project_plane(frame, x)),
                    None => {
                        let h = hint.or_else(|| nearest_loop_point(&loop_points[f], x));
                        project_point(&face.surface, x, h)
                    }
                };
                let uv = uv.unwrap_or((f64::NAN, f64::NAN));
                if uv.0.is_finite() {
                    hint = Some(uv);
                }
                self.edge_uv.push(DVec2::new(uv.0, uv.1));
            }
        }
        self.edges.push(EdgeCache {
            samples: start..self.edge_t.len() as u32,
            wrap: wraps_around(e),
            cover: if matches!(e.curve, Curve3D::Line(_)) {
                0.0
            } else {
                cover
            },
            bbox,
            uv_start,
        });
    }

    fn add_face(&mut self, fi: usize, face: &Face) {
        let plane = plane_frame(&face.surface);
        // Distinct edges.
        let edges_start = self.face_edges.len() as u32;
        let mut bbox = Aabb::EMPTY;
        for l in &face.loops {
            for oe in &l.edges {
                if !self.face_edges[edges_start as usize..].contains(&(oe.edge as u32)) {
                    self.face_edges.push(oe.edge as u32);
                    bbox = union(&bbox, &self.edges[oe.edge].bbox);
                }
            }
        }
        let edges = edges_start..self.face_edges.len() as u32;
        let cells_start = self.cells.len() as u32;
        // Cell counts along u and v in proportion to the face's extent (UV is metric on a
        // plane), `max` along the longer side.
        let (len_u, len_v) = match plane {
            Some(_) => (
                face.domain.u.1 - face.domain.u.0,
                face.domain.v.1 - face.domain.v.0,
            ),
            None => extents(face),
        };
        let counts = |max: usize| {
            let long = len_u.max(len_v);
            let count = |x: f64| {
                if long > 0.0 {
                    ((max as f64 * x / long).ceil() as usize).clamp(MIN_FACE_GRID, max)
                } else {
                    MIN_FACE_GRID
                }
            };
            (count(len_u), count(len_v))
        };
        let (tu, tv) = counts(TRIM_GRID);
        let trim = TrimGrid::new(face, tu, tv);
        if plane.is_none() {
            let (nu, nv) = counts(MAX_FACE_GRID);
            if let Some(grid) = TrimGrid::new(face, nu, nv) {
                for cell in face_cells(face, &grid) {
                    bbox = union(&bbox, &cell.bbox);
                    self.cells.push(cell);
                }
            }
            if self.cells.len() == cells_start as usize {
                // No cell bounds the face (a degenerate domain this module cannot widen): an
                // unbounded box keeps it in every query rather than losing it.
                bbox = Aabb::UNBOUNDED;
            }
        }
        let blocks_start = self.blocks.len() as u32;
        let cells_end = self.cells.len() as u32;
        for start in (cells_start..cells_end).step_by(CELL_BLOCK) {
            let cells = start..cells_end.min(start + CELL_BLOCK as u32);
            let (mut reps, mut boxes) = (Aabb::EMPTY, Aabb::EMPTY);
            let mut finite = true;
            for cell in &self.cells[range(&cells)] {
                reps.add(cell.rep);
                boxes = union(&boxes, &cell.bbox);
                finite &= [cell.rep, cell.bbox.min, cell.bbox.max]
                    .iter()
                    .all(|v| v.is_finite());
            }
            if !finite {
                // A NaN would be left out of the boxes (min and max skip it) but not out of
                // the cell's own distance: a block with any non-finite coordinate is never
                // skipped.
                (reps, boxes) = (Aabb::UNBOUNDED, Aabb::UNBOUNDED);
            }
            self.blocks.push(CellBlock { reps, boxes, cells });
        }
        self.faces.push(FaceCache {
            plane,
            trim,
            loops: trim::Trim::new(face),
            closed: closed_periods(&face.surface),
            cells: cells_start..cells_end,
            blocks: blocks_start..self.blocks.len() as u32,
            edges,
            bbox,
        });
        debug_assert_eq!(self.faces.len(), fi + 1);
    }

    /// Face `fi`'s cell centre nearest to `p` (its UV and distance; the first of equals in
    /// cell order), or `None` when the face has cells and none of their boxes is within
    /// `bound` of `p` (the face holds no point nearer than `bound`). Blocks that can change
    /// neither answer are skipped (see [`CellBlock`]); the answer is the linear scan's.
    fn cell_seed(&self, fi: usize, p: DVec3, bound: f64) -> Option<Option<(DVec2, f64)>> {
        let fc = &self.faces[fi];
        let bound2 = bound * bound;
        let mut within = false;
        let mut best = f64::INFINITY;
        let mut seed = None;
        for block in &self.blocks[range(&fc.blocks)] {
            let nearer = box_distance_squared(&block.reps, p) < best;
            if !nearer && (within || box_distance_squared(&block.boxes, p) >= bound2) {
                continue;
            }
            for cell in &self.cells[range(&block.cells)] {
                within |= box_distance_squared(&cell.bbox, p) < bound2;
                let d2 = cell.rep.distance_squared(p);
                if d2 < best {
                    best = d2;
                    seed = Some((cell.uv, d2.sqrt()));
                }
            }
        }
        // As `min over the cells of their box distance >= bound²` decided it.
        if fc.cells.end > fc.cells.start && !within && !bound2.is_nan() {
            return None;
        }
        Some(seed)
    }

    /// Angle-weighted pseudo-normals at the vertices (see the module docs).
    fn add_vertex_normals(&mut self, model: &Model, loop_points: &[Vec<(DVec2, DVec3)>]) {
        for (fi, face) in model.faces.iter().enumerate() {
            let orient = if face.same_sense { 1.0 } else { -1.0 };
            for l in &face.loops {
                if let (Some(v), Some(&pole)) = (l.vertex, l.uv.first()) {
                    // A pole or apex: the face surrounds it (a full turn); its normals around
                    // it average to the axis (a sphere's pole normal, a cone's axis).
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
                    self.vertex_normals[v] += sum.normalize_or_zero() * std::f64::consts::TAU;
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
                    let Some(normal) =
                        self.normal_at(face, fi, x, nearest_loop_point(&loop_points[fi], x))
                    else {
                        continue;
                    };
                    // Loops turn counter-clockwise about this normal.
                    let loop_normal = normal * (face.sign * orient);
                    let d_in = end_tangent(ea, a.forward, true);
                    let d_out = end_tangent(eb, b.forward, false);
                    let flat =
                        |d: DVec3| (d - loop_normal * d.dot(loop_normal)).normalize_or_zero();
                    let (d_in, d_out) = (flat(d_in), flat(d_out));
                    let angle = if d_in == DVec3::ZERO || d_out == DVec3::ZERO {
                        std::f64::consts::PI
                    } else {
                        let turn = d_in.cross(d_out).dot(loop_normal).atan2(d_in.dot(d_out));
                        std::f64::consts::PI - turn
                    };
                    self.vertex_normals[v] += normal * angle;
                }
            }
        }
    }

    /// Unit outward normal of `face` at its point nearest `x`.
    fn normal_at(
        &self,
        face: &Face,
        fi: usize,
        x: DVec3,
        hint: Option<(f64, f64)>,
    ) -> Option<DVec3> {
        let uv = match self
            .faces
            .get(fi)
            .and_then(|f| f.plane)
            .or_else(|| plane_frame(&face.surface))
        {
            Some(frame) => project_plane(frame, x),
            None => surface_params(&face.surface, x, hint),
        };
        face_normal(face, uv)
    }

    /// [`trim::contains`] for face `fi` (`face` is `model.faces[fi]`), from the cached grid and
    /// prepared loops.
    pub fn contains_uv(&self, face: &Face, fi: usize, uv: DVec2) -> bool {
        let fc = &self.faces[fi];
        match &fc.trim {
            Some(grid) => grid.contains(face, &fc.loops, uv),
            None => fc.loops.contains(face, uv),
        }
    }

    /// Parameters on face `fi` of the point of edge `ei` at `t`, interpolated from the samples.
    fn edge_uv_hint(&self, model: &Model, ei: usize, fi: usize, t: f64) -> Option<(f64, f64)> {
        let e = &model.edges[ei];
        let slot = e.faces.iter().position(|&f| f == fi)?;
        let ec = &self.edges[ei];
        let n = (ec.samples.end - ec.samples.start) as usize;
        let ts = &self.edge_t[range(&ec.samples)];
        let uvs =
            &self.edge_uv[ec.uv_start as usize + slot * n..ec.uv_start as usize + (slot + 1) * n];
        let k = ts.partition_point(|&s| s <= t).clamp(1, n.max(2) - 1);
        let (t0, t1) = (ts[k - 1], ts[k.min(n - 1)]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        let uv = uvs[k - 1] + (uvs[k.min(n - 1)] - uvs[k - 1]) * w;
        // Interpolating across a seam would land mid-period: take the nearer sample then.
        let uv = if (uvs[k.min(n - 1)] - uvs[k - 1]).abs().max_element()
            > 0.25 * face_period_min(&model.faces[fi])
        {
            if w < 0.5 {
                uvs[k - 1]
            } else {
                uvs[k.min(n - 1)]
            }
        } else {
            uv
        };
        uv.is_finite().then_some((uv.x, uv.y))
    }

    /// The nearest point of the whole boundary to `p`. For a model without faces the distance
    /// is infinite and the point NaN.
    pub fn nearest(&self, model: &Model, p: DVec3) -> FaceHit {
        self.nearest_face(model, p).map_or(
            FaceHit {
                point: DVec3::NAN,
                distance: f64::INFINITY,
                uv: (f64::NAN, f64::NAN),
                on: Feature::Face(usize::MAX),
            },
            |h| h.1,
        )
    }

    /// Like [`Boundary::nearest`], with the face the hit was found on (an edge or vertex hit
    /// belongs to several faces; this is the one whose `uv` the hit carries).
    pub fn nearest_face(&self, model: &Model, p: DVec3) -> Option<(usize, FaceHit)> {
        self.nearest_face_where(model, p, |_| true)
    }

    /// [`Boundary::nearest_face`] over the faces for which `keep` holds (one solid of several,
    /// say).
    pub fn nearest_face_where(
        &self,
        model: &Model,
        p: DVec3,
        keep: impl Fn(usize) -> bool,
    ) -> Option<(usize, FaceHit)> {
        debug_assert_eq!(
            model.faces.len(),
            self.faces.len(),
            "Boundary built for another model"
        );
        let mut best: Option<(usize, FaceHit)> = None;
        let mut best_d = f64::INFINITY;
        self.bvh.branch_and_bound(p, f64::INFINITY, |fi, _| {
            if !keep(fi) {
                return best_d * best_d;
            }
            let cached = Some(Cached { boundary: self });
            if let Some(hit) = face_nearest(model, fi, p, None, best_d, cached, false) {
                if hit.distance < best_d {
                    best_d = hit.distance;
                    best = Some((fi, hit));
                }
            }
            best_d * best_d
        });
        // The surface parameters of an edge hit, computed once for the winner.
        if let Some((fi, hit)) = &mut best {
            if !hit.uv.0.is_finite() {
                let face = &model.faces[*fi];
                let hint = match hit.on {
                    Feature::Edge(ei, t) => self.edge_uv_hint(model, ei, *fi, t),
                    Feature::Vertex(v) => model.faces[*fi]
                        .loops
                        .iter()
                        .flat_map(|l| l.edges.iter())
                        .find_map(|oe| {
                            let e = &model.edges[oe.edge];
                            let t = if e.vertices[0] == v {
                                Some(e.range.0)
                            } else if e.vertices[1] == v {
                                Some(e.range.1)
                            } else {
                                None
                            };
                            t.and_then(|t| self.edge_uv_hint(model, oe.edge, *fi, t))
                        }),
                    Feature::Face(_) => None,
                };
                hit.uv = match self.faces[*fi].plane {
                    Some(frame) => project_plane(frame, hit.point),
                    None => surface_params(&face.surface, hit.point, hint),
                };
            }
        }
        best
    }

    /// The nearest point of face `face` closer than `bound` (use `f64::INFINITY` for no
    /// bound), with the cached samples: like [`nearest_on_face`] but faster. `None` when
    /// nothing on the face is closer than `bound`.
    pub fn nearest_on_face(
        &self,
        model: &Model,
        face: usize,
        p: DVec3,
        hint: Option<(f64, f64)>,
        bound: f64,
    ) -> Option<FaceHit> {
        face_nearest(
            model,
            face,
            p,
            hint,
            bound,
            Some(Cached { boundary: self }),
            true,
        )
    }

    /// The faces with a point closer than `r` to `p`, in increasing order.
    pub fn within(&self, model: &Model, p: DVec3, r: f64) -> Vec<usize> {
        let mut out = Vec::new();
        self.within_into(model, p, r, &mut out);
        out
    }

    /// [`Boundary::within`] into a caller's buffer (cleared first), to avoid allocating.
    pub fn within_into(&self, model: &Model, p: DVec3, r: f64, out: &mut Vec<usize>) {
        out.clear();
        if r.is_nan() || r <= 0.0 {
            return;
        }
        let r2 = r * r;
        self.bvh.branch_and_bound(p, r2, |fi, _| {
            if self.face_within(model, fi, p, r) {
                out.push(fi);
            }
            r2
        });
        out.sort_unstable();
    }

    fn face_within(&self, model: &Model, fi: usize, p: DVec3, r: f64) -> bool {
        let r2 = r * r;
        // Quick accept: a sampled point of an edge of the face is a point of the face.
        for &ei in &self.face_edges[range(&self.faces[fi].edges)] {
            let ec = &self.edges[ei as usize];
            if box_distance_squared(&ec.bbox, p) < r2
                && self.edge_p[range(&ec.samples)]
                    .iter()
                    .any(|x| x.distance_squared(p) < r2)
            {
                return true;
            }
        }
        face_nearest(
            model,
            fi,
            p,
            None,
            r,
            Some(Cached { boundary: self }),
            false,
        )
        .is_some()
    }

    /// True when `p` is inside the material (see the module docs for the method and its
    /// limits). Points on the boundary count as inside.
    pub fn contains_point(&self, model: &Model, p: DVec3) -> bool {
        let Some((fi, hit)) = self.nearest_face(model, p) else {
            return false;
        };
        if hit.distance <= self.on_boundary {
            return true;
        }
        let n = self.pseudo_normal(model, fi, &hit);
        (p - hit.point).dot(n) < 0.0
    }

    /// Outward (pseudo-)normal of the boundary at a hit (not normalised).
    pub fn pseudo_normal(&self, model: &Model, face: usize, hit: &FaceHit) -> DVec3 {
        match hit.on {
            Feature::Face(f) => face_normal(&model.faces[f], hit.uv)
                .or_else(|| self.normal_at(&model.faces[f], f, hit.point, Some(hit.uv)))
                .unwrap_or(DVec3::ZERO),
            Feature::Edge(ei, t) => {
                let e = &model.edges[ei];
                let mut n = DVec3::ZERO;
                for &f in &e.faces {
                    let hint = if f == face && hit.uv.0.is_finite() {
                        Some(hit.uv)
                    } else {
                        self.edge_uv_hint(model, ei, f, t)
                    };
                    if let Some(nf) = self.normal_at(&model.faces[f], f, hit.point, hint) {
                        n += nf;
                    }
                }
                n
            }
            Feature::Vertex(v) => self.vertex_normals[v],
        }
    }
}

/// Parameters of a boundary point `x` on a face's surface: the projection from `hint`,
/// retried without a hint when that lands farther than [`ON_SURFACE`] (relative to the
/// coordinates' size) from `x` (a hint across a seam or a pole can lead to another foot).
/// NaN when no projection is found.
fn surface_params(surface: &Surface, x: DVec3, hint: Option<(f64, f64)>) -> (f64, f64) {
    let off = |uv: (f64, f64)| crate::geom::surface_point(surface, uv.0, uv.1).distance(x);
    let tol = ON_SURFACE * (1.0 + x.abs().max_element());
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

/// How far (relative to the coordinates' size) a boundary point may be from a face's surface
/// before its projection is retried: real files carry gaps of 1e-6..1e-4 of their size.
pub const ON_SURFACE: f64 = 1e-4;

/// Smallest period of a face (∞ when it has none).
fn face_period_min(face: &Face) -> f64 {
    face.domain
        .u_period
        .unwrap_or(f64::INFINITY)
        .min(face.domain.v_period.unwrap_or(f64::INFINITY))
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
fn loop_points(face: &Face) -> Vec<(DVec2, DVec3)> {
    face.loops
        .iter()
        .flat_map(|l| l.uv.iter())
        .map(|&uv| (uv, crate::geom::surface_point(&face.surface, uv.x, uv.y)))
        .collect()
}

fn nearest_loop_point(points: &[(DVec2, DVec3)], x: DVec3) -> Option<(f64, f64)> {
    points
        .iter()
        .filter(|(_, q)| q.is_finite())
        .min_by(|a, b| a.1.distance_squared(x).total_cmp(&b.1.distance_squared(x)))
        .map(|(uv, _)| (uv.x, uv.y))
}

/// Lengths in 3D of the face's domain along u and along v (the longest of a few parameter
/// lines each, as polylines of four chords).
fn extents(face: &Face) -> (f64, f64) {
    let ((u0, u1), (v0, v1)) = covered_domain(face);
    let probe = 4;
    let at = |i: usize, j: usize| {
        eval_surface(
            &face.surface,
            u0 + (u1 - u0) * i as f64 / probe as f64,
            v0 + (v1 - v0) * j as f64 / probe as f64,
        )
        .p
    };
    let mut len_u: f64 = 0.0;
    let mut len_v: f64 = 0.0;
    for j in 0..=probe {
        let mut lu = 0.0;
        let mut lv = 0.0;
        for i in 0..probe {
            lu += at(i, j).distance(at(i + 1, j));
            lv += at(j, i).distance(at(j, i + 1));
        }
        len_u = len_u.max(lu);
        len_v = len_v.max(lv);
    }
    (len_u, len_v)
}

/// The cells covering a curved face (see the module docs): those of the trim grid that are
/// not outside, each with a box that contains the surface over it.
fn face_cells(face: &Face, grid: &TrimGrid) -> Vec<Cell> {
    let (nu, nv) = grid.counts();
    let (du, dv) = grid.cell_size();
    let mut nodes = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        for i in 0..=nu {
            let uv = grid.node(i, j);
            let s = eval_surface(&face.surface, uv.x, uv.y);
            nodes.push((s.p, s.suu.length(), s.svv.length()));
        }
    }
    let node = |i: usize, j: usize| &nodes[j * (nu + 1) + i];
    let mut cells = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            if grid.is_outside(i, j) {
                continue;
            }
            let corners = [
                node(i, j),
                node(i + 1, j),
                node(i, j + 1),
                node(i + 1, j + 1),
            ];
            let mut bbox = Aabb::EMPTY;
            let mut muu: f64 = 0.0;
            let mut mvv: f64 = 0.0;
            for c in corners {
                bbox.add(c.0);
                muu = muu.max(c.1);
                mvv = mvv.max(c.2);
            }
            let e = (du * du * CURVATURE_SAFETY * muu + dv * dv * CURVATURE_SAFETY * mvv) / 8.0;
            if !(e.is_finite() && bbox.min.is_finite() && bbox.max.is_finite()) {
                continue;
            }
            bbox.min -= DVec3::splat(e);
            bbox.max += DVec3::splat(e);
            let uv = grid.node(i, j) + DVec2::new(0.5 * du, 0.5 * dv);
            let rep = crate::geom::surface_point(&face.surface, uv.x, uv.y);
            cells.push(Cell { bbox, rep, uv });
        }
    }
    cells
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geom::surface_kind;

    fn sample(name: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("samples")
            .join(name);
        crate::ingest::read_model(&path).expect("sample reads")
    }

    /// The blocked cell scan answers as the linear scan over every cell did: the same seed,
    /// bit for bit, and the same rejection, for points in and around curved parts and
    /// bounds from zero to infinity.
    #[test]
    fn blocked_cell_scan_is_the_linear_scan() {
        let linear = |b: &Boundary, fi: usize, p: DVec3, bound: f64| {
            let fc = &b.faces[fi];
            let (mut lb, mut best, mut seed) = (f64::INFINITY, f64::INFINITY, None);
            for cell in &b.cells[range(&fc.cells)] {
                lb = lb.min(box_distance_squared(&cell.bbox, p));
                let d2 = cell.rep.distance_squared(p);
                if d2 < best {
                    best = d2;
                    seed = Some((cell.uv, d2.sqrt()));
                }
            }
            if fc.cells.end > fc.cells.start && lb >= bound * bound {
                return None;
            }
            Some(seed)
        };
        let mut rng = Lcg(7);
        let mut rejected = 0;
        for name in [
            "filleted_box.step",
            "sphere.step",
            "torus.step",
            "box_bspline_top.step",
        ] {
            let model = sample(name);
            let b = Boundary::new(&model);
            let (lo, hi) = model.bbox;
            let size = (hi - lo).length();
            for _ in 0..4000 {
                let t = DVec3::new(rng.next(), rng.next(), rng.next()) * 1.4 - 0.2;
                let p = lo + (hi - lo) * t;
                let bound = match rng.next() {
                    x if x < 0.1 => f64::INFINITY,
                    x => x * x * size,
                };
                for fi in 0..model.faces.len() {
                    let (ours, theirs) = (b.cell_seed(fi, p, bound), linear(&b, fi, p, bound));
                    let bits = |s: Option<Option<(DVec2, f64)>>| {
                        s.map(|s| s.map(|(uv, d)| (uv.x.to_bits(), uv.y.to_bits(), d.to_bits())))
                    };
                    assert_eq!(
                        bits(ours),
                        bits(theirs),
                        "{name} face {fi} at {p} within {bound}"
                    );
                    rejected += usize::from(ours.is_none());
                }
            }
        }
        assert!(rejected > 1000, "{rejected}");
    }

    /// Deterministic uniform numbers in [0, 1) (a 64-bit LCG, high bits).
    pub(crate) struct Lcg(pub(crate) u64);
    impl Lcg {
        pub(crate) fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(crate) fn in_box(&mut self, lo: DVec3, hi: DVec3) -> DVec3 {
            DVec3::new(self.next(), self.next(), self.next()) * (hi - lo) + lo
        }
    }

    /// Dense samples of a trimmed face: a UV grid filtered by the trim and every edge of its
    /// loops, with a bound on how far any point of the face is from the nearest sample, and
    /// how far the trim's UV polygons stray from the exact edges (the trim test accepts the
    /// slivers between a polygon's chords and the exact boundary, up to `trim_dev` away).
    pub(crate) struct Brute {
        pub(crate) points: Vec<DVec3>,
        pub(crate) cover: f64,
        pub(crate) trim_dev: f64,
    }

    pub(crate) fn brute_samples(model: &Model, fi: usize, n: usize) -> Brute {
        let face = &model.faces[fi];
        let d = &face.domain;
        let (du, dv) = ((d.u.1 - d.u.0) / n as f64, (d.v.1 - d.v.0) / n as f64);
        let mut points = Vec::new();
        let mut grid = vec![DVec3::NAN; (n + 1) * (n + 1)];
        for j in 0..=n {
            for i in 0..=n {
                let uv = DVec2::new(d.u.0 + du * i as f64, d.v.0 + dv * j as f64);
                let x = crate::geom::surface_point(&face.surface, uv.x, uv.y);
                grid[j * (n + 1) + i] = x;
                if trim::contains(face, uv) {
                    points.push(x);
                }
            }
        }
        let grid_count = points.len();
        // Largest cell diagonal (the curvature within a cell this small adds < 1 %).
        let mut cover: f64 = 0.0;
        for j in 0..n {
            for i in 0..n {
                let a = grid[j * (n + 1) + i];
                let b = grid[(j + 1) * (n + 1) + i + 1];
                let c = grid[j * (n + 1) + i + 1];
                let e = grid[(j + 1) * (n + 1) + i];
                cover = cover.max(a.distance(b)).max(c.distance(e));
            }
        }
        for l in &face.loops {
            for oe in &l.edges {
                let e = &model.edges[oe.edge];
                let m = 4000;
                let mut prev: Option<DVec3> = None;
                for k in 0..=m {
                    let t = e.range.0 + (e.range.1 - e.range.0) * k as f64 / m as f64;
                    let x = eval_curve(&e.curve, t).p;
                    if let Some(q) = prev {
                        cover = cover.max(q.distance(x));
                    }
                    prev = Some(x);
                    points.push(x);
                }
            }
        }
        // Chordal deviation of the loop polygons: the image of each segment's midpoint versus
        // the exact edges.
        let edge_points = &points[grid_count..];
        let mut trim_dev: f64 = 0.0;
        let periods = (d.u_period, d.v_period);
        for l in face.loops.iter().filter(|l| l.vertex.is_none()) {
            let n = l.uv.len();
            let wraps = {
                let gap = l.uv[0] - l.uv[n - 1];
                periods.0.is_some_and(|p| gap.x.abs() > 0.5 * p)
                    || periods.1.is_some_and(|p| gap.y.abs() > 0.5 * p)
            };
            for k in 0..n {
                if k + 1 == n && wraps {
                    continue;
                }
                let mid = (l.uv[k] + l.uv[(k + 1) % n]) * 0.5;
                let x = crate::geom::surface_point(&face.surface, mid.x, mid.y);
                let dev = edge_points
                    .iter()
                    .map(|q| q.distance(x))
                    .fold(f64::INFINITY, f64::min);
                trim_dev = trim_dev.max(dev);
            }
        }
        Brute {
            points,
            cover: 1.01 * cover,
            trim_dev: 1.01 * trim_dev,
        }
    }

    /// The hit lies on the face: on its surface at `uv` and inside its trim, or on one of its
    /// edges; and `distance` is the distance to it.
    fn assert_hit_on_face(
        model: &Model,
        scale: f64,
        fi: usize,
        p: DVec3,
        hit: &FaceHit,
        what: &str,
    ) {
        let face = &model.faces[fi];
        assert!(
            (hit.distance - hit.point.distance(p)).abs() <= 1e-12 * scale,
            "{what}: distance"
        );
        let s = crate::geom::surface_point(&face.surface, hit.uv.0, hit.uv.1);
        // Edge points are on the surface only to the file's precision (≤ 1e-6 of the size
        // in the samples); interior points to rounding.
        match hit.on {
            Feature::Face(f) => {
                assert_eq!(f, fi, "{what}");
                assert!(
                    s.distance(hit.point) <= 1e-12 * scale,
                    "{what}: interior point off surface"
                );
                assert!(
                    trim::contains(face, DVec2::new(hit.uv.0, hit.uv.1)),
                    "{what}: outside trim"
                );
            }
            Feature::Edge(e, t) => {
                let edge = &model.edges[e];
                assert!(
                    face.loops
                        .iter()
                        .any(|l| l.edges.iter().any(|oe| oe.edge == e)),
                    "{what}"
                );
                assert!(
                    t >= edge_span(edge).0 && t <= edge_span(edge).1,
                    "{what}: t out of range"
                );
                assert!(
                    eval_curve(&edge.curve, t).p.distance(hit.point) <= 1e-12 * scale,
                    "{what}"
                );
                assert!(
                    s.distance(hit.point) <= 1e-6 * scale,
                    "{what}: edge point off surface"
                );
            }
            Feature::Vertex(v) => {
                assert!(
                    model.vertices[v].point.distance(hit.point) <= 1e-6 * scale,
                    "{what}: vertex"
                );
                assert!(
                    s.distance(hit.point) <= 1e-6 * scale,
                    "{what}: vertex off surface"
                );
            }
        }
    }

    /// Points in the part's box grown by 20 % on each side, and points near the face (a
    /// sample of it moved by up to 10 % of the diagonal).
    pub(crate) fn query_points(
        model: &Model,
        brute: &Brute,
        rng: &mut Lcg,
        n: usize,
    ) -> Vec<DVec3> {
        let (lo, hi) = model.bounding_box();
        let pad = (hi - lo) * 0.2;
        let mut out: Vec<DVec3> = (0..n).map(|_| rng.in_box(lo - pad, hi + pad)).collect();
        for _ in 0..n / 2 {
            let k = (rng.next() * brute.points.len() as f64) as usize;
            let off = rng.in_box(DVec3::splat(-1.0), DVec3::splat(1.0)) * 0.1 * (hi - lo).length();
            out.push(brute.points[k.min(brute.points.len() - 1)] + off);
        }
        out
    }

    fn check_faces(file: &str, faces: &[usize], kinds: &[&str]) {
        let model = sample(file);
        let boundary = Boundary::new(&model);
        let scale = model.diagonal();
        let mut rng = Lcg(file.len() as u64 * 7919);
        for &fi in faces {
            let kind = surface_kind(&model.faces[fi].surface);
            assert!(kinds.contains(&kind), "{file} face {fi} is a {kind}");
            let brute = brute_samples(&model, fi, 240);
            assert!(!brute.points.is_empty());
            for (k, p) in query_points(&model, &brute, &mut rng, 24)
                .into_iter()
                .enumerate()
            {
                let what = format!("{file} face {fi} ({kind}) point {k} {p}");
                let b = brute
                    .points
                    .iter()
                    .map(|x| x.distance(p))
                    .fold(f64::INFINITY, f64::min);
                for (how, hit) in [
                    ("standalone", nearest_on_face(&model, fi, p, None)),
                    (
                        "cached",
                        boundary.nearest_on_face(&model, fi, p, None, f64::INFINITY),
                    ),
                ] {
                    let hit = hit.unwrap_or_else(|| panic!("{what}: {how}: no hit"));
                    assert_hit_on_face(&model, scale, fi, p, &hit, &format!("{what} {how}"));
                    // Brute force only over-estimates (except in the trim polygons' slivers):
                    // we must not be farther (beyond rounding), and cannot be nearer than the
                    // samples' cover radius allows.
                    assert!(
                        hit.distance <= b + brute.trim_dev + 1e-9 * scale,
                        "{what} {how}: {} > brute force {b} ({:?})",
                        hit.distance,
                        hit.on
                    );
                    assert!(
                        hit.distance >= b - brute.cover,
                        "{what} {how}: {} < {b} − {}",
                        hit.distance,
                        brute.cover
                    );
                    // The hit is a hint that finds itself again.
                    let again = nearest_on_face(&model, fi, p, Some(hit.uv)).unwrap();
                    assert!(
                        (again.distance - hit.distance).abs() <= 1e-9 * scale,
                        "{what} {how}: hinted"
                    );
                }
            }
        }
    }

    #[test]
    fn face_distance_plate_with_holes() {
        let m = sample("plate_with_holes.step");
        let holed = (0..m.faces.len())
            .filter(|&f| m.faces[f].loops.len() == 4)
            .collect::<Vec<_>>();
        let cyl = (0..m.faces.len())
            .filter(|&f| surface_kind(&m.faces[f].surface) == "cylinder")
            .take(2);
        let faces: Vec<usize> = holed.into_iter().chain(cyl).collect();
        assert_eq!(faces.len(), 4);
        check_faces("plate_with_holes.step", &faces, &["plane", "cylinder"]);
    }

    #[test]
    fn face_distance_cylinder_sphere_torus() {
        check_faces("cylinder.step", &[0, 1, 2], &["plane", "cylinder"]);
        check_faces("sphere.step", &[0], &["sphere"]);
        check_faces("torus.step", &[0], &["torus"]);
    }

    #[test]
    fn face_distance_bspline_and_nurbs() {
        check_faces("box_bspline_top.step", &[0, 1, 5], &["bspline", "plane"]);
        check_faces("sphere_nurbs.step", &[0], &["nurbs"]);
        // cylinder_nurbs face 0 is left out: its loop polygon is mixed up by brep::domain
        // (see trim's known-bad list), so its trim is not the face.
        check_faces("cylinder_nurbs.step", &[1, 2], &["bspline"]);
        check_faces("box_nurbs.step", &[0, 3], &["bspline"]);
    }

    #[test]
    fn face_distance_fillets() {
        let m = sample("filleted_box.step");
        let curved: Vec<usize> = (0..m.faces.len())
            .filter(|&f| surface_kind(&m.faces[f].surface) != "plane")
            .step_by(3)
            .collect();
        assert!(curved.len() >= 6);
        check_faces("filleted_box.step", &curved, &["cylinder", "sphere"]);
    }

    /// `Boundary::nearest` equals the minimum of `nearest_on_face` over all faces, and
    /// `within` lists exactly the faces closer than r.
    #[test]
    fn boundary_nearest_and_within_match_all_faces() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut files: Vec<std::path::PathBuf> = [
            "box.step",
            "filleted_box.step",
            "box_bspline_top.step",
            "plate_with_holes.step",
            "box_with_void.step",
            "torus.step",
            "l_bracket_nurbs.step",
        ]
        .iter()
        .map(|f| root.join("samples").join(f))
        .collect();
        // Real parts with many faces, when the corpus is beside the project.
        for f in [
            "stepswift_nist_ftc_06_asme1_rd.stp",
            "b3d_M6-1x12-countersunk-screw.step",
        ] {
            let path = root.join("../shared/realworld").join(f);
            if path.exists() {
                files.push(path);
            }
        }
        for path in &files {
            let file = path.file_name().unwrap().to_string_lossy();
            let model = crate::ingest::read_model(path).expect("reads");
            let boundary = Boundary::new(&model);
            let (lo, hi) = model.bounding_box();
            let pad = (hi - lo) * 0.2;
            let scale = (hi - lo).length();
            let mut rng = Lcg(99);
            for k in 0..60 {
                let p = rng.in_box(lo - pad, hi + pad);
                let all: Vec<f64> = (0..model.faces.len())
                    .map(|f| {
                        nearest_on_face(&model, f, p, None).map_or(f64::INFINITY, |h| h.distance)
                    })
                    .collect();
                let brute = all.iter().copied().fold(f64::INFINITY, f64::min);
                let (fi, hit) = boundary.nearest_face(&model, p).unwrap();
                assert!(
                    (hit.distance - brute).abs() <= 1e-9 * scale,
                    "{file} point {k} {p}: BVH {} on face {fi}, all faces {brute}",
                    hit.distance
                );
                assert_hit_on_face(&model, scale, fi, p, &hit, &format!("{file} point {k}"));
                assert_eq!(boundary.nearest(&model, p), hit);
                let r = brute * (0.5 + 1.5 * rng.next()) + 1e-3 * scale;
                let got = boundary.within(&model, p, r);
                let expect: Vec<usize> = (0..all.len()).filter(|&f| all[f] < r).collect();
                let borderline = |f: &usize| (all[*f] - r).abs() <= 1e-9 * scale;
                let g: Vec<usize> = got.iter().copied().filter(|f| !borderline(f)).collect();
                let e: Vec<usize> = expect.iter().copied().filter(|f| !borderline(f)).collect();
                assert_eq!(g, e, "{file} point {k} {p} r {r}");
            }
        }
    }

    /// The boundary is shared by the tracer's threads.
    #[test]
    fn boundary_is_send_and_sync() {
        fn shareable<T: Send + Sync>() {}
        shareable::<Boundary>();
    }

    fn assert_inside(file: &str, inside: &[[f64; 3]], outside: &[[f64; 3]]) {
        let model = sample(file);
        let b = Boundary::new(&model);
        for p in inside {
            assert!(
                b.contains_point(&model, DVec3::from_array(*p)),
                "{file}: {p:?} should be inside"
            );
        }
        for p in outside {
            assert!(
                !b.contains_point(&model, DVec3::from_array(*p)),
                "{file}: {p:?} should be outside"
            );
        }
    }

    #[test]
    fn point_in_solid() {
        // Box [0,60]×[0,40]×[0,20]; the outside points have their nearest point on a face,
        // an edge and a vertex.
        assert_inside(
            "box.step",
            &[
                [30.0, 20.0, 10.0],
                [1.0, 1.0, 1.0],
                [59.0, 39.0, 19.0],
                [30.0, 0.5, 10.0],
            ],
            &[
                [-1.0, 20.0, 10.0],
                [30.0, 20.0, 21.0],
                [61.0, 41.0, 21.0],
                [70.0, 20.0, 10.0],
                [30.0, 45.0, 25.0],
            ],
        );
        for file in ["sphere.step", "sphere_nurbs.step"] {
            // Radius 15 at the origin; (0, 0, ±14.9) are next to the poles.
            assert_inside(
                file,
                &[
                    [0.0, 0.0, 0.0],
                    [10.0, 0.0, 0.0],
                    [0.0, 0.0, 14.9],
                    [0.0, 0.0, -14.9],
                    [8.0, 8.0, 8.0],
                ],
                &[
                    [0.0, 0.0, 15.1],
                    [20.0, 0.0, 0.0],
                    [10.0, 10.0, 10.0],
                    [0.0, 0.0, -15.1],
                ],
            );
        }
        // Box [0,60]×[0,40]×[0,30] with a spherical void r = 8 at (30, 20, 15).
        assert_inside(
            "box_with_void.step",
            &[
                [5.0, 5.0, 5.0],
                [30.0, 20.0, 24.0],
                [30.0, 20.0, 6.5],
                [39.0, 20.0, 15.0],
            ],
            &[
                [30.0, 20.0, 15.0],
                [30.0, 20.0, 22.9],
                [36.0, 24.0, 15.0],
                [-1.0, 0.0, 0.0],
            ],
        );
        // Plate [0,80]×[0,50]×[0,10] with holes r = 5, 8, 5 at (15|40|65, 25).
        assert_inside(
            "plate_with_holes.step",
            &[
                [5.0, 5.0, 5.0],
                [40.0, 35.0, 5.0],
                [27.5, 25.0, 5.0],
                [40.0, 33.5, 9.5],
            ],
            &[
                [15.0, 25.0, 5.0],
                [40.0, 25.0, 5.0],
                [65.0, 25.0, 5.0],
                [40.0, 25.0, 11.0],
                [40.0, 32.5, 5.0],
            ],
        );
        // L: [0,60]×[0,30]×[0,10] ∪ [0,10]×[0,30]×[0,40]; reflex edge x = 10, z = 10. (9, 15, 9)
        // has its nearest point on the reflex edge.
        for file in ["l_bracket.step", "l_bracket_nurbs.step"] {
            assert_inside(
                file,
                &[
                    [5.0, 15.0, 30.0],
                    [30.0, 15.0, 5.0],
                    [9.0, 15.0, 9.0],
                    [9.5, 1.0, 39.0],
                ],
                &[
                    [30.0, 15.0, 25.0],
                    [11.0, 15.0, 11.0],
                    [10.5, 15.0, 10.2],
                    [60.5, 15.0, 10.5],
                ],
            );
        }
        // Two disjoint solids: box [0,30]×[0,20]×[0,10], cylinder r = 5, z ∈ [0, 20] on x = 60, y = 10.
        assert_inside(
            "two_solids.step",
            &[[15.0, 10.0, 5.0], [60.0, 10.0, 10.0], [64.0, 10.0, 19.0]],
            &[
                [45.0, 10.0, 5.0],
                [60.0, 10.0, 21.0],
                [65.5, 10.0, 10.0],
                [60.0, 16.0, 10.0],
            ],
        );
    }

    /// The trim grid answers exactly like `trim::contains` (it only skips the polygon test
    /// where a cell is provably on one side).
    #[test]
    fn trim_grid_agrees_with_contains() {
        for file in [
            "plate_with_holes.step",
            "filleted_box.step",
            "box_bspline_top.step",
            "scad_rotate_extrude.step",
            "torus.step",
            "sphere.step",
            "tetrahedron.step",
        ] {
            let model = sample(file);
            let b = Boundary::new(&model);
            let mut rng = Lcg(3);
            for (fi, face) in model.faces.iter().enumerate() {
                let grid = b.faces[fi]
                    .trim
                    .as_ref()
                    .expect("every sample face has a grid");
                let exact = &b.faces[fi].loops;
                let d = &face.domain;
                let (w, h) = (d.u.1 - d.u.0, d.v.1 - d.v.0);
                for _ in 0..3000 {
                    // Over the domain and a margin, with periodic shifts.
                    let k = (rng.next() * 3.0).floor() - 1.0;
                    let uv = DVec2::new(
                        d.u.0 - 0.1 * w + 1.2 * w * rng.next() + k * d.u_period.unwrap_or(0.0),
                        d.v.0 - 0.1 * h + 1.2 * h * rng.next(),
                    );
                    assert_eq!(
                        grid.contains(face, exact, uv),
                        trim::contains(face, uv),
                        "{file} face {fi} at {uv}"
                    );
                }
            }
        }
    }

    /// Volume of the solid by stratified sampling: one random point in each of `n³` cells of
    /// the bounding box, tested with `contains_point`.
    fn volume_estimate(model: &Model, n: usize) -> f64 {
        let b = Boundary::new(model);
        let (lo, hi) = model.bounding_box();
        let h = (hi - lo) / n as f64;
        let mut rng = Lcg(11);
        let mut inside = 0usize;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let jitter = DVec3::new(rng.next(), rng.next(), rng.next());
                    let p = lo + h * (DVec3::new(i as f64, j as f64, k as f64) + jitter);
                    inside += b.contains_point(model, p) as usize;
                }
            }
        }
        inside as f64 * h.x * h.y * h.z
    }

    /// The same on the real-world corpus (when it is beside the project), against the
    /// volumes OCCT reports in its MANIFEST.md (4–5 significant digits).
    #[test]
    fn point_in_solid_integrates_to_the_volume_on_real_parts() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/realworld");
        if !dir.is_dir() {
            return;
        }
        let volumes = [
            ("axom_tet.step", 2666.7),
            ("axom_sliced_cylinder.step", 1.773e6),
            ("axom_revolved_sphere.step", 523.6),
            ("stepswift_nist_ctc_01_asme1_rd.stp", 1.4643e7),
            ("stepswift_nist_ftc_06_asme1_rd.stp", 3.324e6),
            ("stepswift_nist_ftc_09_asme1_rd.stp", 1.364e5),
            ("stepswift_nist_ftc_11_asme1_rb.stp", 5129.0),
            ("trimesh_featuretype.STEP", 1.904e5),
            ("b3d_M6-1x12-countersunk-screw.step", 336.7),
        ];
        let mut failures = Vec::new();
        for (file, volume) in volumes {
            let Ok(model) = crate::ingest::read_model(&dir.join(file)) else {
                failures.push(format!("{file}: unreadable"));
                continue;
            };
            // Stratified sampling at 32³ cells (a thin part like FTC 9, a 3 mm plate, gets
            // 32 cells across its thickness too): the errors measured are ≤ 0.5 %; 1.5 %
            // leaves room for the sampling noise, while one face whose side is misjudged
            // (a cap outside its box: 6 % on FTC 6 before that was fixed) is caught.
            let estimate = volume_estimate(&model, 32);
            if (estimate - volume).abs() > 0.015 * volume {
                failures.push(format!("{file}: {estimate}, OCCT {volume}"));
            }
        }
        assert!(failures.is_empty(), "{failures:#?}");
    }

    /// Point-in-solid integrates to the manifest's exact volume: the fraction of a grid of
    /// cell centres inside, times the box's volume, on every sample whose volume is known.
    ///
    /// Known-bad files go in `KNOWN_BAD` (none now: `cylinder_nurbs.step` was until its
    /// closed-NURBS period was detected); the test fails loudly once one passes.
    #[test]
    fn point_in_solid_integrates_to_the_volume() {
        const KNOWN_BAD: &[&str] = &[];
        let mut failures = Vec::new();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(root.join("samples/manifest.json")).unwrap();
        let manifest: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut checked = 0;
        for s in manifest["samples"].as_array().unwrap() {
            let file = s["file"].as_str().unwrap();
            let (Some(volume), Ok(model)) = (
                s["volume"].as_f64(),
                crate::ingest::read_model(&root.join("samples").join(file)),
            ) else {
                continue;
            };
            let estimate = volume_estimate(&model, 28);
            // Stratified sampling errs only in the cells the boundary cuts, each by at most one
            // cell's volume with variance ≤ 1/4 of its square: for these parts (≤ 3000 cut
            // cells of 28³) the standard deviation is ≤ 0.7 % of the volume, so 2.5 % is a
            // margin of 3.5 σ, while a sign error on a feature (the void of box_with_void is
            // 3 % of its volume) or a whole face is larger.
            let ok = (estimate - volume).abs() <= 0.025 * volume;
            if ok == KNOWN_BAD.contains(&file) {
                failures.push(format!(
                    "{file}: {estimate}, exact {volume}{}",
                    if ok {
                        " (known bad, passes now: remove it from the list)"
                    } else {
                        ""
                    }
                ));
            }
            checked += 1;
        }
        assert!(failures.is_empty(), "{failures:#?}");
        assert!(checked >= 20, "checked {checked}");
    }

    #[test]
    fn edge_distance_matches_dense_sampling() {
        for file in [
            "filleted_box.step",
            "cylinder_nurbs.step",
            "box_bspline_top.step",
            "plate_with_holes.step",
        ] {
            let model = sample(file);
            let (lo, hi) = model.bounding_box();
            let scale = (hi - lo).length();
            let mut rng = Lcg(5);
            for (ei, e) in model.edges.iter().enumerate() {
                let m = 20000;
                let pts: Vec<DVec3> = (0..=m)
                    .map(|k| {
                        eval_curve(
                            &e.curve,
                            e.range.0 + (e.range.1 - e.range.0) * k as f64 / m as f64,
                        )
                        .p
                    })
                    .collect();
                for _ in 0..10 {
                    let p = rng.in_box(lo - (hi - lo) * 0.2, hi + (hi - lo) * 0.2);
                    let (t, x, d) = nearest_on_edge(&model, ei, p, None);
                    let b = pts
                        .iter()
                        .map(|q| q.distance(p))
                        .fold(f64::INFINITY, f64::min);
                    assert!(eval_curve(&e.curve, t).p.distance(x) < 1e-12 * scale);
                    assert!((x.distance(p) - d).abs() < 1e-12 * scale);
                    assert!(d <= b + 1e-9 * scale, "{file} edge {ei}: {d} > {b}");
                }
            }
        }
    }
}
#[cfg(test)]
mod stress_tests {
    use super::tests::*;
    use super::*;

    /// Long randomized comparison with brute force on every face of every sample (or of the
    /// STEP files in `STRESS_DIR`), `STRESS_N` points per face (default 16):
    /// `cargo test --release --lib stress_all_faces -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn stress_all_faces() {
        let n: usize = std::env::var("STRESS_N")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(16);
        let dir = std::env::var("STRESS_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples"));
        let mut files: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e != "json" && e != "md"))
            .collect();
        files.sort();
        let mut fails = 0;
        for path in files {
            let Ok(model) = crate::ingest::read_model(&path) else {
                println!("{} unreadable", path.display());
                continue;
            };
            let t0 = std::time::Instant::now();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let (lo, hi) = model.bounding_box();
            let scale = (hi - lo).length();
            let boundary = Boundary::new(&model);
            println!(
                "{name}: {} faces, boundary built in {:?}",
                model.faces.len(),
                t0.elapsed()
            );
            let mut rng = Lcg(17);
            for fi in 0..model.faces.len() {
                if name == "cylinder_nurbs.step" && fi == 0 {
                    continue;
                }
                let brute = brute_samples(&model, fi, 160);
                if brute.points.is_empty() {
                    println!("{name} F{fi}: no brute samples");
                    continue;
                }
                for p in query_points(&model, &brute, &mut rng, n) {
                    let b = brute
                        .points
                        .iter()
                        .map(|x| x.distance(p))
                        .fold(f64::INFINITY, f64::min);
                    for (how, hit) in [
                        ("standalone", nearest_on_face(&model, fi, p, None)),
                        (
                            "cached",
                            boundary.nearest_on_face(&model, fi, p, None, f64::INFINITY),
                        ),
                    ] {
                        match hit {
                            None => {
                                fails += 1;
                                println!("{name} F{fi} {how} {p}: none");
                            }
                            Some(h) => {
                                if h.distance > b + brute.trim_dev + 1e-9 * scale {
                                    fails += 1;
                                    println!(
                                        "{name} F{fi} {} {how} {p}: {} > {b} {:?}",
                                        crate::geom::surface_kind(&model.faces[fi].surface),
                                        h.distance,
                                        h.on
                                    );
                                }
                                let s = crate::geom::surface_point(
                                    &model.faces[fi].surface,
                                    h.uv.0,
                                    h.uv.1,
                                );
                                if s.distance(h.point).is_nan()
                                    || s.distance(h.point) > 1e-5 * scale
                                {
                                    fails += 1;
                                    println!(
                                        "{name} F{fi} {how} {p}: uv off {:?} {}",
                                        h.on,
                                        s.distance(h.point)
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(fails, 0);
    }
}
