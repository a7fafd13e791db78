//! Trimming loops in UV space and the UV domain of each face.
//!
//! truck's `parameter_range()` is not a face's domain (a plane reports \[0,1\]); the domain is
//! what the face's boundary loops enclose. Each loop is sampled along its exact edge curves
//! and projected onto the face's surface: planes, cylinders, cones and spheres in closed
//! form, other surfaces by Newton from the linear prediction of the last two feet (or the
//! control net's nearest point for a loop's first sample), with truck's search as the
//! fallback. Periodic parameters are unwrapped continuously along the loop, and a *seam* edge
//! (an edge the face uses twice) is placed on the side of the period where the face lies:
//! by the STEP convention a loop has the face on its left when seen against the face normal
//! (`Su × Sv` when the face's `same_sense` is true), which fixes whether a traversal of the
//! seam is at `u₀` or `u₀ + P`. That also resolves poles, where `u` is undefined and a loop
//! jumps across the period.

use crate::geom::trim::edge_samples;
use crate::geom::{eval_curve, eval_surface, SurfaceDerivs};
use crate::model::{Face, Loop, Model, UvDomain};
use glam::{DVec2, DVec3};

/// The domain of a face before its loops are known (both readers fill it in last).
pub const EMPTY_DOMAIN: UvDomain = UvDomain {
    u: (0.0, 0.0),
    v: (0.0, 0.0),
    u_period: None,
    v_period: None,
};

/// Projects points of a loop onto one face's surface: what the closed forms need of the
/// surface is computed once per loop.
struct Projector<'a> {
    face: &'a Face,
    closed: crate::geom::project::ClosedForm,
    /// Whether the surface has an angle parameter (truck's `u_period`/`v_period`).
    periodic: bool,
}

impl<'a> Projector<'a> {
    fn new(face: &'a Face, periodic: bool) -> Self {
        Projector {
            face,
            closed: crate::geom::project::ClosedForm::new(&face.surface),
            periodic,
        }
    }

    /// The foot of `p`, whether the parametrisation is singular there (a pole), and its
    /// distance from `p`; `None` unless the foot point is within [`ON_SURFACE_REL_COORD`]
    /// (relative to the coordinates' size `1 + |p|∞`) of `p`.
    fn project(&self, p: DVec3, hint: Option<(f64, f64)>) -> Option<((f64, f64), bool, f64)> {
        let (face, periodic) = (self.face, self.periodic);
        let tolerance = ON_SURFACE_REL_COORD * (1.0 + p.abs().max_element());
        // Planes, cylinders, cones and spheres in closed form, in truck's parameters, with
        // the distance and the pole test in closed form too.
        if let Some(foot) = self.closed.foot(p) {
            if foot.distance <= tolerance {
                let pole =
                    foot.pole || is_singular(&eval_surface(&face.surface, foot.uv.0, foot.uv.1));
                return Some((foot.uv, pole, foot.distance));
            }
        }
        let on = |uv: (f64, f64)| {
            let d = eval_surface(&face.surface, uv.0, uv.1);
            let gap = d.p.distance(p);
            (gap <= tolerance).then(|| (uv, is_singular(&d), gap))
        };
        let along = |h: (f64, f64)| {
            crate::geom::project::project_point_along(&face.surface, p, h, periodic).and_then(on)
        };
        // A B-spline patch's own control net gives a hint (the loop's first sample), or
        // another one (when the previous sample's leads astray: at a pole, or across a closed
        // patch's seam): several times cheaper than truck's search without a hint, which
        // starts from a dense grid of surface points (two such searches were 12 % of reading
        // the screw).
        let net = || {
            (!periodic)
                .then(|| crate::geom::project::greville_hint(&face.surface, p))
                .flatten()
        };
        // A hint can lead to a far stationary point (the far side of a sphere): retry
        // without.
        hint.and_then(along)
            .or_else(|| net().filter(|n| Some(*n) != hint).and_then(along))
            .or_else(|| crate::geom::project_point(&face.surface, p, None).and_then(on))
    }
}

/// How far a boundary point `p` may be from its face's surface, relative to the size of the
/// coordinates `1 + |p|∞`. Real files carry gaps of 1e-6..1e-4 of their size; beyond 1e-3 the
/// edge is not on the face.
pub const ON_SURFACE_REL_COORD: f64 = 1e-3;

/// A surface derivative shorter than this (mm per unit of parameter) vanishes: the
/// parametrisation is singular there (a pole).
const VANISHING_DERIVATIVE_MM: f64 = 1e-12;

/// A surface derivative shorter than this fraction of the other one vanishes too: a point
/// that far from a pole is at the pole to the file's precision (a vertex written 1e-12 mm off
/// a sphere's axis), and its `u` there means nothing.
const VANISHING_DERIVATIVE_REL_OTHER: f64 = 1e-9;

/// True where the parametrisation is singular (a pole: `Su × Sv` vanishes); `d` is the
/// surface there.
fn is_singular(d: &SurfaceDerivs) -> bool {
    let (su, sv) = (d.su, d.sv);
    let (lu, lv) = (su.length(), sv.length());
    su.cross(sv).length() <= 1e-9 * (lu * lv).max(1e-300)
        || lu < VANISHING_DERIVATIVE_MM
        || lv < VANISHING_DERIVATIVE_MM
        || lu < VANISHING_DERIVATIVE_REL_OTHER * lv
        || lv < VANISHING_DERIVATIVE_REL_OTHER * lu
}

/// The outline of a loop polygon `uv` of `face` with each pole given two points
/// ([`Loop::outline`]); empty when the polygon has no point at a pole (it is its own
/// outline then).
///
/// A pole is one point of the surface (a sphere's, a cone's apex, a B-spline patch whose
/// border row collapses) and a segment of its UV domain: the coordinate whose derivative
/// vanishes there is free. The loop reaches the pole along one meridian and leaves along
/// another, and the polygon has one point there, its free coordinate borrowed from a
/// neighbour ([`unwrap_loop`]), so one of the chords to it cuts across the face (0.07 mm
/// off at the filleted box's sphere corners; a touch point running into that corner is
/// "off the face"). The outline replaces the pole's point (or run of points) by the two
/// corners: the free coordinate of the sample before it, then of the one after, each with
/// the pole's other coordinate. The samples themselves stay as they are in `uv`, laid out
/// on the edges as [`Loop::uv_counts`] says.
pub fn pole_outline(face: &Face, uv: &[DVec2]) -> Vec<DVec2> {
    if matches!(
        crate::geom::surface_kind(&face.surface),
        "plane" | "cylinder"
    ) || uv.len() < 3
    {
        return Vec::new();
    }
    let n = uv.len();
    // A B-spline patch's poles are rows of its control net collapsed to a point: on the
    // border of its knot rectangle. Only points there are evaluated (the patches are the
    // faces with the most loop points, and their evaluation the dearest).
    let border = crate::geom::knot_vectors(&face.surface).map(|(ku, kv)| {
        let range = |k: &truck_geometry::prelude::KnotVec| {
            let (a, b) = (k[0], k[k.len() - 1]);
            (a, b, 1e-9 * (b - a).abs().max(1.0))
        };
        (range(ku), range(kv))
    });
    let may_be_pole = |p: DVec2| match border {
        None => true,
        Some(((u0, u1, tu), (v0, v1, tv))) => {
            (p.x - u0).abs() <= tu
                || (p.x - u1).abs() <= tu
                || (p.y - v0).abs() <= tv
                || (p.y - v1).abs() <= tv
        }
    };
    let derivs: Vec<Option<SurfaceDerivs>> = uv
        .iter()
        .map(|&p| may_be_pole(p).then(|| eval_surface(&face.surface, p.x, p.y)))
        .collect();
    let singular: Vec<bool> = derivs
        .iter()
        .map(|d| d.as_ref().is_some_and(is_singular))
        .collect();
    // Start after a regular sample, so that no run of pole samples wraps round the end.
    let Some(first) = (0..n).find(|&i| !singular[i]) else {
        return Vec::new();
    };
    if !singular.iter().any(|&s| s) {
        return Vec::new();
    }
    let (up, vp) = (face.domain.u_period, face.domain.v_period);
    let wrapping = wraps(uv, up, vp);
    let mut out = Vec::with_capacity(n + 4);
    // Where the outline's point for `uv[0]` is (its run's first corner at a pole).
    let mut start_at = 0;
    let mut k = 0;
    while k < n {
        let i = (first + k) % n;
        if !singular[i] {
            if i == 0 {
                start_at = out.len();
            }
            out.push(uv[i]);
            k += 1;
            continue;
        }
        // A run of pole samples, between two regular ones.
        let mut len = 0;
        while len < n && singular[(i + len) % n] {
            len += 1;
        }
        let straddles = i == 0 || i + len > n;
        if straddles {
            start_at = out.len();
        }
        let pole = uv[i];
        let after = uv[(i + len) % n];
        // The polygon is unwrapped continuously, so the free coordinates of the samples
        // before and after the pole are where the outline runs along it (a loop passing
        // straight through a pole, half a period round, included) — except across the
        // closing step of a loop that wraps round a period, where it jumps by the period:
        // there the sample before is brought next to the pole's copy.
        let mut before = uv[(i + n - 1) % n];
        if straddles && wrapping {
            before = DVec2::new(
                wrap_near(before.x, pole.x, up),
                wrap_near(before.y, pole.y, vp),
            );
        }
        // (A pole sample was evaluated: `singular` says so.)
        let u_free = derivs[i]
            .as_ref()
            .is_some_and(|d| d.su.length() < d.sv.length());
        let corners = if u_free {
            [DVec2::new(before.x, pole.y), DVec2::new(after.x, pole.y)]
        } else {
            [DVec2::new(pole.x, before.y), DVec2::new(pole.x, after.y)]
        };
        out.push(corners[0]);
        if corners[1] != corners[0] {
            out.push(corners[1]);
        }
        k += len;
    }
    // The outline was built from `first`: turn it so that it starts where `uv` does (a
    // loop that wraps round a period jumps by the period between its last and first points,
    // and the inside tests take that closing step to the copy of the first point).
    out.rotate_left(start_at);
    out
}

/// Gives every loop of `model` whose polygon passes a pole its [`pole_outline`].
pub fn outline_poles(model: &mut Model) {
    use rayon::prelude::*;
    model.faces.par_iter_mut().for_each(|face| {
        let outlines: Vec<Vec<DVec2>> = face
            .loops
            .iter()
            .map(|l| {
                if l.vertex.is_none() {
                    pole_outline(face, &l.uv)
                } else {
                    Vec::new()
                }
            })
            .collect();
        for (l, o) in face.loops.iter_mut().zip(outlines) {
            l.outline = o;
        }
    });
}

fn wrap_near(x: f64, reference: f64, period: Option<f64>) -> f64 {
    match period {
        Some(p) => x + ((reference - x) / p).round() * p,
        None => x,
    }
}

/// A point sampled along a loop, with the 3D direction of travel when it is on a seam edge.
struct Sample {
    p: DVec3,
    seam_dir: Option<DVec3>,
}

/// The largest distance of a loop's points from its face's surface: in mm, and relative to
/// the coordinates' size `1 + |p|∞` there.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceGap {
    pub mm: f64,
    pub rel: f64,
    /// The largest distance in mm (of any point, whatever its coordinates' size).
    pub largest_mm: f64,
}

/// How far a loop's UV polygon may stray from the loop's exact edges (measured on the
/// surface, across the edge), relative to the model's size: a tenth of the default accuracy
/// ([`DEFAULT_ACCURACY_REL_DIAGONAL`](crate::model::tolerances::DEFAULT_ACCURACY_REL_DIAGONAL)),
/// so that the inside tests the tracer and the verifier make with the polygon are exact to
/// within what the medial axis is checked to.
pub const LOOP_POLYGON_TOL_REL_DIAGONAL: f64 = 1e-7;

/// The tolerance of a model's loop polygons: [`LOOP_POLYGON_TOL_REL_DIAGONAL`] of the
/// diagonal of its vertices and edges (a model without edges has no polygons to refine).
pub fn loop_polygon_tolerance(model: &Model) -> f64 {
    let b = crate::geom::edges_bounding_box(model);
    let diagonal = if b.is_empty() {
        0.0
    } else {
        (b.max - b.min).length()
    };
    if diagonal.is_finite() && diagonal > 0.0 {
        LOOP_POLYGON_TOL_REL_DIAGONAL * diagonal
    } else {
        f64::INFINITY
    }
}

/// What a reader warns (kind `coarse_trim`) of a loop whose polygon still strays more than the
/// tolerance from its edges ([`LoopPolygon::worst_mm`]).
pub const COARSE_TRIM_PROBLEM: &str =
    "loop's UV polygon strays from its edges by more than the trim tolerance, and more samples did not help";

/// What is done about it.
pub const COARSE_TRIM_ACTION: &str =
    "accepted; inside tests within that distance of this loop may err";

/// Most samples the polygon has on one edge: the refinement stops there (a polygon this fine
/// that still strays is reported in [`LoopPolygon::worst_mm`]).
pub const MAX_SAMPLES_PER_EDGE: usize = 1 << 14;

/// Most samples the polygon of one loop has (16 MiB of points).
pub const MAX_SAMPLES_PER_LOOP: usize = 1 << 20;

/// An edge whose stray is more than this fraction of the last round's did not converge that
/// round.
const STALLED_REL_BEFORE: f64 = 0.5;

/// Rounds in a row an edge may fail to converge before its refinement stops.
const MAX_STALLED_ROUNDS: usize = 2;

/// A loop's UV polygon: `uv`, with `counts[i]` samples on the loop's edge `i` (sample `k` of
/// `n` at `t0 + (t1 − t0)·k/n` in the loop's direction, edges in the loop's order). Each edge
/// starts with [`edge_samples`]'s count, doubled until the polygon's chords, mapped onto the
/// surface, stray at most the tolerance across the edge at their midpoints, or the edge has
/// [`MAX_SAMPLES_PER_EDGE`], or the loop [`MAX_SAMPLES_PER_LOOP`], or its stray stops
/// converging; `worst_mm` is the largest such distance left.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoopPolygon {
    pub uv: Vec<DVec2>,
    pub counts: Vec<usize>,
    pub worst_mm: f64,
}

/// The UV polygon of one loop of `face` (see the module docs), within `tol_mm` of the
/// loop's edges where the file allows it ([`LoopPolygon`]), and how far the loop's sampled
/// points are from the face's surface. A vertex loop gives one point.
pub fn loop_uv_and_gap(
    model: &Model,
    face_index: usize,
    lp: &Loop,
    tol_mm: f64,
) -> Result<(LoopPolygon, SurfaceGap), String> {
    let face = &model.faces[face_index];
    // Angles: truck's canonical range is what the unwrapping below expects. A B-spline that
    // closes on itself has no angle: every answer is in its knot range, which `align_loops`
    // handles.
    let periodic = {
        use truck_geometry::prelude::ParametricSurface;
        face.surface.u_period().is_some() || face.surface.v_period().is_some()
    };
    if let Some(v) = lp.vertex {
        let p = model.vertices[v].point;
        let (uv, _, mm) = Projector::new(face, false)
            .project(p, None)
            .ok_or("vertex loop's vertex is not on the face's surface")?;
        let rel = mm / (1.0 + p.abs().max_element());
        let poly = LoopPolygon {
            uv: vec![DVec2::new(uv.0, uv.1)],
            counts: Vec::new(),
            worst_mm: 0.0,
        };
        return Ok((
            poly,
            SurfaceGap {
                mm,
                rel,
                largest_mm: mm,
            },
        ));
    }
    let mut counts: Vec<usize> = lp
        .edges
        .iter()
        .map(|oe| edge_samples(model, face_index, oe).1)
        .collect();
    // Each edge's stray after the last round, and how many rounds in a row it did not halve.
    let mut before: Vec<Option<f64>> = vec![None; counts.len()];
    let mut stalled: Vec<usize> = vec![0; counts.len()];
    loop {
        let samples = sample_loop(model, face_index, lp, &counts);
        let (raw, singular, gap) = project_samples(face, periodic, &samples);
        if let Some(k) = raw.iter().position(|x| x.is_none()) {
            return Err(not_on_surface(face, samples[k].p));
        }
        let raw: Vec<(f64, f64)> = raw.into_iter().flatten().collect();
        let uv = unwrap_loop(face, &samples, &raw, &singular);
        let strays = chord_strays(model, face, lp, &counts, &samples, &uv, &singular);
        let worst_mm = strays.iter().copied().fold(0.0, f64::max);
        let mut refined = false;
        let mut total: usize = counts.iter().sum();
        for (e, &stray) in strays.iter().enumerate() {
            // Sampling error falls about fourfold per doubling; what does not even halve twice
            // running is not sampling error (a gap, a kink the tolerance hides): leave it.
            if before[e].is_some_and(|b| stray > STALLED_REL_BEFORE * b) {
                stalled[e] += 1;
            } else {
                stalled[e] = 0;
            }
            before[e] = Some(stray);
            let n = counts[e];
            if stray > tol_mm
                && n < MAX_SAMPLES_PER_EDGE
                && stalled[e] < MAX_STALLED_ROUNDS
                && total + n <= MAX_SAMPLES_PER_LOOP
            {
                counts[e] = (n * 2).min(MAX_SAMPLES_PER_EDGE);
                total += counts[e] - n;
                refined = true;
            }
        }
        if !refined {
            let poly = LoopPolygon {
                uv,
                counts,
                worst_mm,
            };
            return Ok((poly, gap));
        }
    }
}

/// For each edge of a loop, the largest distance across the edge between a chord's
/// midpoint mapped onto the surface and the edge's point at the chord's middle parameter.
/// Only the sideways part counts, not the parts along the edge or the surface normal (an
/// uneven parametrisation moves the point along), and the file's gap between edge and surface
/// is taken out: the edge's offset from its foot at the chord's ends, averaged, is added to
/// the midpoint (and so is half the gap between the edge's end and the next edge's start, on
/// the chord between them). Chords at a pole are not measured (the polygon's point there is a
/// coordinate borrowed from its neighbour).
fn chord_strays(
    model: &Model,
    face: &Face,
    lp: &Loop,
    counts: &[usize],
    samples: &[Sample],
    uv: &[DVec2],
    singular: &[bool],
) -> Vec<f64> {
    let (up, vp) = crate::geom::surface_periods(&face.surface);
    // A closed B-spline is not periodic: a chord's middle goes back into its knot range.
    let (cu, cv) = crate::geom::closed_periods(&face.surface);
    let ((u0, _), (v0, _)) = face_parameter_range(face);
    let into_range = |x: f64, start: f64, closed: bool, period: Option<f64>| match period {
        Some(p) if closed => start + (x - start).rem_euclid(p),
        _ => x,
    };
    let total = uv.len();
    // Each sample's offset from its foot on the surface.
    let offset: Vec<DVec3> = samples
        .iter()
        .zip(uv)
        .map(|(s, q)| {
            let q = DVec2::new(into_range(q.x, u0, cu, up), into_range(q.y, v0, cv, vp));
            s.p - crate::geom::surface_point(&face.surface, q.x, q.y)
        })
        .collect();
    let mut start = 0;
    let mut out = Vec::with_capacity(counts.len());
    for (oe, &n) in lp.edges.iter().zip(counts) {
        let edge = &model.edges[oe.edge];
        let (t0, t1) = if oe.forward {
            edge.range
        } else {
            (edge.range.1, edge.range.0)
        };
        let mut worst: f64 = 0.0;
        for k in 0..n {
            let (i, j) = (start + k, (start + k + 1) % total);
            if singular[i] || singular[j] {
                continue;
            }
            let (a, b) = (uv[i], uv[j]);
            let b = DVec2::new(wrap_near(b.x, a.x, up), wrap_near(b.y, a.y, vp));
            let m = (a + b) * 0.5;
            let m = DVec2::new(into_range(m.x, u0, cu, up), into_range(m.y, v0, cv, vp));
            let s = eval_surface(&face.surface, m.x, m.y);
            let c = eval_curve(&edge.curve, t0 + (t1 - t0) * (k as f64 + 0.5) / n as f64);
            let normal = s.su.cross(s.sv).normalize_or_zero();
            let tangent = (c.d1 - c.d1.dot(normal) * normal).normalize_or_zero();
            // The last chord ends at the next edge's start, which is this edge's end only
            // to the file's gap between them: the chord's middle moves by half that gap.
            let end_gap = if k + 1 == n {
                samples[j].p - crate::geom::eval::curve_point(&edge.curve, t1)
            } else {
                DVec3::ZERO
            };
            let d = s.p + 0.5 * (offset[i] + offset[j]) - (c.p + 0.5 * end_gap);
            let across = d - d.dot(normal) * normal - d.dot(tangent) * tangent;
            let stray = across.length();
            if stray.is_nan() {
                continue;
            }
            worst = worst.max(stray);
        }
        out.push(worst);
        start += n;
    }
    out
}

/// The loop sampled in order, `counts[i]` samples on its edge `i`; samples on a seam edge
/// carry their direction of travel.
fn sample_loop(model: &Model, face_index: usize, lp: &Loop, counts: &[usize]) -> Vec<Sample> {
    let mut samples: Vec<Sample> = Vec::with_capacity(counts.iter().sum());
    for (oe, &n) in lp.edges.iter().zip(counts) {
        let edge = &model.edges[oe.edge];
        let seam = edge_samples(model, face_index, oe).0;
        let (t0, t1) = if oe.forward {
            edge.range
        } else {
            (edge.range.1, edge.range.0)
        };
        for k in 0..n {
            let t = t0 + (t1 - t0) * (k as f64) / (n as f64);
            let p = crate::geom::eval::curve_point(&edge.curve, t);
            let seam_dir = seam.then(|| {
                let d = eval_curve(&edge.curve, t).d1;
                if oe.forward {
                    d
                } else {
                    -d
                }
            });
            samples.push(Sample { p, seam_dir });
        }
    }
    samples
}

/// Each sample's foot on the face's surface (`None` where it is not on it), whether the
/// parametrisation is singular there, and the largest distance of a sample from its foot.
type Projected = (Vec<Option<(f64, f64)>>, Vec<bool>, SurfaceGap);

/// Each sample's foot on the face's surface (see [`Projected`]).
fn project_samples(face: &Face, periodic: bool, samples: &[Sample]) -> Projected {
    let projector = Projector::new(face, periodic);
    let mut gap = SurfaceGap::default();
    let mut raw: Vec<Option<(f64, f64)>> = Vec::with_capacity(samples.len());
    let mut singular: Vec<bool> = Vec::with_capacity(samples.len());
    let mut hint: Option<(f64, f64)> = None;
    let mut before: Option<(f64, f64)> = None;
    for s in samples {
        // Linear prediction from the last two feet (samples are evenly spaced along each
        // edge): Newton starts second-order close instead of first-order.
        let predicted = match (hint, before) {
            (Some(h), Some(b)) if !periodic => Some((2.0 * h.0 - b.0, 2.0 * h.1 - b.1)),
            _ => hint,
        };
        let found = projector.project(s.p, predicted).or_else(|| {
            (predicted != hint)
                .then(|| projector.project(s.p, hint))
                .flatten()
        });
        let pole = found.is_some_and(|(_, pole, _)| pole);
        let uv = found.map(|(uv, _, _)| uv);
        if let Some((_, _, mm)) = found {
            let rel = mm / (1.0 + s.p.abs().max_element());
            if rel > gap.rel {
                gap.mm = mm;
                gap.rel = rel;
            }
            gap.largest_mm = gap.largest_mm.max(mm);
        }
        if let (Some(uv), false) = (uv, pole) {
            before = hint;
            hint = Some(uv);
        } else {
            before = None;
        }
        raw.push(uv);
        singular.push(pole);
    }
    (raw, singular, gap)
}

/// The message for a loop point `p` that is not on the face's surface.
fn not_on_surface(face: &Face, p: DVec3) -> String {
    let near = crate::geom::project_point(&face.surface, p, None)
        .map(|uv| eval_surface(&face.surface, uv.0, uv.1).p.distance(p));
    format!(
        "loop point ({:.6}, {:.6}, {:.6}) is not on the face's {} surface (nearest point found at {})",
        p.x,
        p.y,
        p.z,
        crate::geom::surface_kind(&face.surface),
        near.map_or("none".to_string(), |d| format!("{d:.3e} mm")),
    )
}

/// The feet `raw` unwrapped into one continuous UV polygon: poles take the coordinate that is
/// undefined there from the next regular sample, seam samples are placed on the side of the
/// period where the face lies, and everything else follows continuity.
fn unwrap_loop(
    face: &Face,
    samples: &[Sample],
    raw: &[(f64, f64)],
    singular: &[bool],
) -> Vec<DVec2> {
    let (up, vp) = crate::geom::surface_periods(&face.surface);
    // Start at a seam sample if there is one (its placement is absolute).
    let start = samples
        .iter()
        .position(|s| s.seam_dir.is_some())
        .unwrap_or(0);
    let n = raw.len();
    let mut out = vec![DVec2::ZERO; n];
    let mut prev: Option<DVec2> = None;
    let mut low = (None, None);
    for k in 0..n {
        let i = (start + k) % n;
        let (mut u, mut v) = raw[i];
        if singular[i] {
            // u (or v) is undefined at a pole: take it from the next regular sample.
            if let Some(j) = (1..n).map(|d| (i + d) % n).find(|&j| !singular[j]) {
                let pole_v = v;
                let pole_u = u;
                let (nu, nv) = raw[j];
                // Keep the coordinate that is well defined (the one that does not vary at
                // the pole): the surface evaluates to the same point for any value of the
                // other one.
                let d = eval_surface(&face.surface, pole_u, pole_v);
                if d.su.length() < d.sv.length() {
                    u = nu;
                } else {
                    v = nv;
                }
            }
        }
        let placed_seam = samples[i]
            .seam_dir
            .and_then(|d| seam_placement(face, (u, v), d, (up, vp), &mut low));
        // A placed seam coordinate is absolute; everything else follows continuity.
        let (u2, v2) = match (placed_seam, prev) {
            (Some((su, _, true)), Some(p)) => (su, wrap_near(v, p.y, vp)),
            (Some((_, sv, false)), Some(p)) => (wrap_near(u, p.x, up), sv),
            (Some((su, sv, _)), None) => (su, sv),
            (None, Some(p)) => (wrap_near(u, p.x, up), wrap_near(v, p.y, vp)),
            (None, None) => (u, v),
        };
        out[i] = DVec2::new(u2, v2);
        prev = Some(out[i]);
    }
    out
}

/// Placement of a sample on a seam. The first seam traversal met fixes `low`, the seam copy
/// at the low end of the face's period; every traversal is then put at `low` or `low + P`,
/// whichever has the face on its left (seen against the face normal). Returns `None` when
/// the edge is not along a periodic direction; the flag says whether `u` (true) or `v` was
/// placed.
fn seam_placement(
    face: &Face,
    uv: (f64, f64),
    dir3: DVec3,
    periods: (Option<f64>, Option<f64>),
    low: &mut (Option<f64>, Option<f64>),
) -> Option<(f64, f64, bool)> {
    let d = eval_surface(&face.surface, uv.0, uv.1);
    let (su, sv) = (d.su, d.sv);
    // Direction of travel in UV (least squares in the tangent plane).
    let (a, b, c) = (su.dot(su), su.dot(sv), sv.dot(sv));
    let det = a * c - b * b;
    if det.abs() <= 1e-300 {
        return None;
    }
    let (r1, r2) = (su.dot(dir3), sv.dot(dir3));
    let du = (c * r1 - b * r2) / det;
    let dv = (a * r2 - b * r1) / det;
    // Left of travel in UV is (-dv, du); mirrored when the face normal is -(Su × Sv).
    let orient = if face.same_sense { 1.0 } else { -1.0 };
    let place = |x: f64, left: f64, p: f64, low: &mut Option<f64>| -> f64 {
        // left > 0: the face lies towards larger values, so this copy is the low side.
        let is_low = left > 0.0;
        let l = *low.get_or_insert(if is_low { x } else { x - p });
        let x0 = if is_low { l } else { l + p };
        // Same copy of x as x0 (x may come from the projection as x0 ± P).
        wrap_near(x, x0, Some(p))
    };
    if du.abs() <= dv.abs() {
        let p = periods.0?;
        Some((place(uv.0, -dv * orient, p, &mut low.0), uv.1, true))
    } else {
        let p = periods.1?;
        Some((uv.0, place(uv.1, du * orient, p, &mut low.1), false))
    }
}

/// Moves a face's loops, all by the same whole number of periods, into the surface's
/// parameter range. Only needed for B-spline/NURBS and swept surfaces that close on themselves (see
/// [`crate::geom::surface_periods`]): there the parametrisation is not really periodic, so a
/// loop unwrapped into the neighbouring period copy would be evaluated by extrapolation.
pub fn align_loops(face: &mut Face) {
    let (cu, cv) = crate::geom::closed_periods(&face.surface);
    if !(cu || cv) {
        return;
    }
    let (up, vp) = crate::geom::surface_periods(&face.surface);
    let (up, vp) = (up.filter(|_| cu), vp.filter(|_| cv));
    let ((u0, _), (v0, _)) = face_parameter_range(face);
    let edge_points = || {
        face.loops
            .iter()
            .filter(|l| l.vertex.is_none())
            .flat_map(|l| &l.uv)
    };
    let umin = edge_points().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let vmin = edge_points().map(|p| p.y).fold(f64::INFINITY, f64::min);
    // Tolerance for "at the start of the range": loop points come from projections that are
    // exact to rounding.
    let shift = |min: f64, start: f64, period: Option<f64>| match period {
        Some(p) if min.is_finite() => ((start - min) / p - 1e-9).ceil() * p,
        _ => 0.0,
    };
    let (su, sv) = (shift(umin, u0, up), shift(vmin, v0, vp));
    if su == 0.0 && sv == 0.0 {
        return;
    }
    for l in face.loops.iter_mut().filter(|l| l.vertex.is_none()) {
        for p in &mut l.uv {
            p.x += su;
            p.y += sv;
        }
    }
}

/// Signed area of a closed polygon (positive counter-clockwise).
pub fn signed_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

/// True when a loop's UV polygon does not close: it goes once around a periodic direction
/// (a circle loop on a cylinder without a seam edge).
pub fn wraps(poly: &[DVec2], u_period: Option<f64>, v_period: Option<f64>) -> bool {
    if poly.len() < 2 {
        return false;
    }
    let first = poly[0];
    let last = poly[poly.len() - 1];
    // Closing step from last back to first, before wrapping.
    let gap_u = first.x - last.x;
    let gap_v = first.y - last.y;
    let big = |gap: f64, p: Option<f64>| p.is_some_and(|p| gap.abs() > 0.5 * p);
    big(gap_u, u_period) || big(gap_v, v_period)
}

/// The face's UV domain, and its outer loop when one can be told geometrically (the
/// non-wrapping loop of largest area, when no loop wraps).
pub fn face_domain(_model: &Model, face: &Face) -> (UvDomain, Option<usize>) {
    let (up, vp) = crate::geom::surface_periods(&face.surface);
    let mut b = loop_bounds(face, up, vp);
    extend_past_wrapping_loop(face, (up, vp), &mut b);
    if b.wrap_u {
        if let Some(p) = up {
            b.umax = b.umin + p;
        }
    }
    if b.wrap_v {
        if let Some(p) = vp {
            b.vmax = b.vmin + p;
        }
    }
    let outer = if !b.wrap_u && !b.wrap_v {
        face.loops
            .iter()
            .enumerate()
            .filter(|(_, l)| l.vertex.is_none())
            .max_by(|a, b| {
                signed_area(&a.1.uv)
                    .abs()
                    .total_cmp(&signed_area(&b.1.uv).abs())
            })
            .map(|(i, _)| i)
    } else {
        None
    };
    (
        UvDomain {
            u: (b.umin, b.umax),
            v: (b.vmin, b.vmax),
            u_period: up,
            v_period: vp,
        },
        outer,
    )
}

/// The box of a face's UV loops, and whether some loop wraps around the periodic u or v.
struct LoopBounds {
    umin: f64,
    umax: f64,
    vmin: f64,
    vmax: f64,
    wrap_u: bool,
    wrap_v: bool,
}

/// The box of the face's loops (a vertex loop counts by its defined coordinate only); with
/// only vertex loops, the whole parameter range (a periodic direction one period from its
/// start).
fn loop_bounds(face: &Face, up: Option<f64>, vp: Option<f64>) -> LoopBounds {
    let mut umin = f64::INFINITY;
    let mut umax = f64::NEG_INFINITY;
    let mut vmin = f64::INFINITY;
    let mut vmax = f64::NEG_INFINITY;
    let mut wrap_u = false;
    let mut wrap_v = false;
    let mut edge_loops = 0;
    for l in &face.loops {
        if l.vertex.is_some() {
            // A pole: only the coordinate that is defined there counts.
            for p in &l.uv {
                vmin = vmin.min(p.y);
                vmax = vmax.max(p.y);
            }
            continue;
        }
        edge_loops += 1;
        for p in &l.uv {
            umin = umin.min(p.x);
            umax = umax.max(p.x);
            vmin = vmin.min(p.y);
            vmax = vmax.max(p.y);
        }
        if wraps(&l.uv, up, None) {
            wrap_u = true;
        }
        if wraps(&l.uv, None, vp) {
            wrap_v = true;
        }
    }
    if edge_loops == 0 || !umin.is_finite() {
        // Only vertex loops (a full sphere or torus): the whole parameter range (a periodic
        // direction one period from its start).
        let ((u0, u1), (v0, v1)) = face_parameter_range(face);
        umin = u0;
        umax = up.map_or(u1, |p| u0 + p);
        vmin = v0;
        vmax = vp.map_or(v1, |p| v0 + p);
    }
    LoopBounds {
        umin,
        umax,
        vmin,
        vmax,
        wrap_u,
        wrap_v,
    }
}

/// A face bounded by a single loop that wraps around one periodic direction (a spherical
/// cap bounded by one circle, with no vertex loop at its pole) extends from that loop to
/// the end of the other direction's range on the loop's left (STEP: the face is on the
/// left of its loops, seen against the face normal). Where that range is unbounded (a
/// cone's line parameter) the apex is not found here: the domain stops at the loop.
fn extend_past_wrapping_loop(
    face: &Face,
    (up, vp): (Option<f64>, Option<f64>),
    b: &mut LoopBounds,
) {
    let wrapping: Vec<&Loop> = face
        .loops
        .iter()
        .filter(|l| l.vertex.is_none() && wraps(&l.uv, up, vp))
        .collect();
    let has_vertex_loop = face.loops.iter().any(|l| l.vertex.is_some());
    if wrapping.len() == 1 && !has_vertex_loop {
        let l = wrapping[0];
        let travel = l.uv[l.uv.len() - 1] - l.uv[0];
        let orient = if face.same_sense { 1.0 } else { -1.0 };
        let ((u0, u1), (v0, v1)) = face_parameter_range(face);
        let bounded = |lo: f64, hi: f64| lo.is_finite() && hi.is_finite() && hi > lo;
        if b.wrap_u
            && !b.wrap_v
            && bounded(v0, v1)
            && vp.is_none()
            && crate::geom::project::range_is_extent(&face.surface)
        {
            // Travel along +u has its left towards +v.
            if travel.x * orient > 0.0 {
                b.vmax = v1;
            } else {
                b.vmin = v0;
            }
        } else if b.wrap_v
            && !b.wrap_u
            && bounded(u0, u1)
            && up.is_none()
            && crate::geom::project::range_is_extent(&face.surface)
        {
            // Travel along +v has its left towards −u.
            if travel.y * orient > 0.0 {
                b.umin = u0;
            } else {
                b.umax = u1;
            }
        }
    }
}

fn face_parameter_range(face: &Face) -> ((f64, f64), (f64, f64)) {
    use std::ops::Bound;
    let (ur, vr) = crate::geom::parameter_range(&face.surface);
    let end = |b: Bound<f64>| match b {
        Bound::Included(x) | Bound::Excluded(x) => x,
        Bound::Unbounded => 0.0,
    };
    ((end(ur.0), end(ur.1)), (end(vr.0), end(vr.1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::distance::nearest_on_edge;

    /// True where `uv` is a pole of the face's surface.
    fn at_pole(face: &Face, uv: DVec2) -> bool {
        is_singular(&eval_surface(&face.surface, uv.x, uv.y))
    }

    /// A tolerance no sampling reaches stops the refinement at the caps, and the polygon
    /// says how far it still strays (what the readers warn of as `coarse_trim`).
    #[test]
    fn an_unreachable_tolerance_is_bounded_and_reported() {
        let model =
            crate::ingest::read_model(&crate::testing::sample_path("plate_with_holes.step"))
                .expect("reads");
        let mut checked = 0;
        for (fi, face) in model.faces.iter().enumerate() {
            for lp in face.loops.iter().filter(|l| l.vertex.is_none()) {
                let (poly, _) = loop_uv_and_gap(&model, fi, lp, 1e-300).expect("projects");
                let curved = lp.edges.iter().any(|oe| {
                    !matches!(model.edges[oe.edge].curve, crate::model::Curve3D::Line(_))
                });
                if !curved {
                    continue;
                }
                assert!(poly.worst_mm > 1e-300, "{poly:?}");
                assert_eq!(poly.counts.iter().sum::<usize>(), poly.uv.len());
                assert!(
                    poly.counts.iter().all(|&n| n <= MAX_SAMPLES_PER_EDGE),
                    "{:?}",
                    poly.counts
                );
                assert!(poly.uv.len() <= MAX_SAMPLES_PER_LOOP);
                checked += 1;
            }
        }
        assert!(checked > 3);
    }

    /// A pole is a segment of the UV domain. The loops of the filleted box's sphere corners
    /// and of the NIST part's hemispherical face (bounded by one great circle through both
    /// poles) have outlines that run along each pole between the meridians the loop arrives
    /// and leaves by, so that the face's points just off the pole, all the way between
    /// them, are inside. The one-point polygons (`uv`) cut a triangle off there: the test
    /// fails on them (checked below), as the tracer did ("touch point left F1 away from its
    /// edges" on the CATIA head's spherical shell).
    #[test]
    fn pole_outlines_keep_the_face_at_its_poles() {
        use crate::geom::trim::contains;
        use std::path::PathBuf;
        let mut pole_segments = 0;
        let mut cut_off_without = 0;
        let hemisphere =
            crate::testing::realworld_dir().map(|d| d.join("stepswift_nist_ftc_06_asme1_rd.stp"));
        let parts: Vec<PathBuf> = std::iter::once(crate::testing::sample_path("filleted_box.step"))
            .chain(hemisphere.clone())
            .collect();
        for path in parts {
            let model = crate::ingest::read_model(&path).expect("reads");
            for face in &model.faces {
                let mut bare = face.clone();
                for l in &mut bare.loops {
                    l.outline.clear();
                }
                let (vmid, umid) = (
                    0.5 * (face.domain.v.0 + face.domain.v.1),
                    0.5 * (face.domain.u.0 + face.domain.u.1),
                );
                for l in face.loops.iter().filter(|l| !l.outline.is_empty()) {
                    let o = &l.outline;
                    for k in 0..o.len() {
                        let (a, b) = (o[k], o[(k + 1) % o.len()]);
                        let at_pole =
                            |p: DVec2| is_singular(&eval_surface(&face.surface, p.x, p.y));
                        if a == b || !at_pole(a) || !at_pole(b) {
                            continue;
                        }
                        pole_segments += 1;
                        // Just off the pole, towards the middle of the domain.
                        let off = if a.y == b.y {
                            DVec2::new(0.0, 1e-3 * (vmid - a.y).signum())
                        } else {
                            DVec2::new(1e-3 * (umid - a.x).signum(), 0.0)
                        };
                        for t in [0.05, 0.25, 0.5, 0.75, 0.95] {
                            let q = a + (b - a) * t + off;
                            assert!(
                                contains(face, q),
                                "{}: face {}: {q} next to the pole from {a} to {b} is outside",
                                path.display(),
                                face.source_id
                            );
                            cut_off_without += usize::from(!contains(&bare, q));
                        }
                    }
                }
            }
        }
        // 8 sphere corners of the box; the hemisphere's 2 poles.
        let want = 8 + if hemisphere.is_some() { 2 } else { 0 };
        assert!(pole_segments >= want, "{pole_segments}");
        assert!(cut_off_without >= pole_segments, "{cut_off_without}");
    }

    /// Every chord of every loop polygon, mapped onto its face's surface at its middle, lies
    /// within the polygon tolerance of the chord's edge, measured independently of the
    /// refinement (the exact edge's nearest point): holes in a plate, a filleted box's
    /// cylinders and its sphere corners, a torus, an ellipse. With the 32 samples per curved
    /// edge the polygons used to have, the plate's holes strayed by 0.5 % of their radius (40
    /// times the tolerance).
    ///
    /// Not the chords at a pole: the polygon reaches a pole along one meridian and leaves
    /// along another, with one point there, so one of the two chords is a diagonal (0.07 mm
    /// off at the filleted box's corners). The inside tests walk the loop's outline instead,
    /// which runs along the pole ([`pole_outlines_keep_the_face_at_its_poles`]).
    #[test]
    fn loop_polygons_follow_their_edges() {
        for name in [
            "plate_with_holes.step",
            "filleted_box.step",
            "torus.step",
            "trace/elliptic_bar.step",
            "trace/fillet_meets_hole.step",
        ] {
            let model =
                crate::ingest::read_model(&crate::testing::sample_path(name)).expect("reads");
            let tol = loop_polygon_tolerance(&model);
            let mut worst: f64 = 0.0;
            for face in &model.faces {
                let (up, vp) = crate::geom::surface_periods(&face.surface);
                for lp in face.loops.iter().filter(|l| l.vertex.is_none()) {
                    assert_eq!(lp.uv_counts.len(), lp.edges.len(), "{name}");
                    assert_eq!(lp.uv_counts.iter().sum::<usize>(), lp.uv.len(), "{name}");
                    let total = lp.uv.len();
                    let mut start = 0;
                    for (oe, &n) in lp.edges.iter().zip(&lp.uv_counts) {
                        for k in 0..n {
                            let (a, b) = (lp.uv[start + k], lp.uv[(start + k + 1) % total]);
                            let b = DVec2::new(wrap_near(b.x, a.x, up), wrap_near(b.y, a.y, vp));
                            if [a, b].iter().any(|q| at_pole(face, *q)) {
                                continue;
                            }
                            let m = (a + b) * 0.5;
                            let p = crate::geom::surface_point(&face.surface, m.x, m.y);
                            let (_, _, d) = nearest_on_edge(&model, oe.edge, p, None);
                            worst = worst.max(d);
                        }
                        start += n;
                    }
                }
            }
            assert!(
                worst <= 2.0 * tol,
                "{name}: a chord strays {worst:.3e} mm (tolerance {tol:.3e})"
            );
        }
    }
}
