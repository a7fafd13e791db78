//! Degenerate curves traced. Where the maximal ball touches a face along a continuum (a
//! cylinder's or cone's lateral face all round, a torus's tube, the two halves of a split
//! cylinder), the sheet of balls touching it twice has collapsed: its centres form a curve
//! (the axis, the core circle), along which the ball's two touch points can turn freely.
//! Sampling finds one ball of such a curve ([`Tracer::collapsed`]); from it the curve is
//! traced both ways by continuation, like a seam but on the 2-segment system: the predictor
//! moves the centre along the one direction it can move in (the centre part of the
//! Jacobian's null space), the corrector solves the six equations and the plane across that
//! direction through the predicted centre (seven equations in eight unknowns: the
//! minimum-norm Newton step leaves the touch points' turn free).
//!
//! A curve ends where
//! - the ball stops being empty: another element comes as close as `r` (located by
//!   bisection): the ball touches it there ([`DegenerateEnd::Meets`]), at the apex of the
//!   sheet of balls touching that element and the continuum (a cylinder's cap) or, where the
//!   ball touches that element along a continuum too (a capsule's cap), freely;
//! - `r` shrinks to nothing at a vertex (a cone's apex: [`DegenerateEnd::Vanishes`]);
//! - the arc its balls touch their face along shrinks to a point (a round cut off
//!   obliquely: [`DegenerateEnd::Shrinks`], located in `shrink.rs`);
//! - it comes back to its first ball ([`DegenerateEnd::Closed`]);
//! - (not an end) a touch point leaves its element where the continuum runs on onto another
//!   (a boss's side onto its foot circle, a fillet split in two): the curve is handed over
//!   and continues touching that element twice;
//! - or, open, where none of these is found (a touch point left its face, the corrector
//!   failed down to the smallest step): [`DegenerateEnd::Open`] with the reason, which
//!   verification reports.

use super::options::{
    DISTINCT_TOUCH_REL_RADIUS, FIRST_STEP_REL_DIAGONAL, MAX_CORRECTOR_ITER, MAX_STEP_REL_DIAGONAL,
    MAX_TURN_RAD, MIN_STEP_REL_DIAGONAL, OSCULATING_REL_RADIUS, STEP_GROWTH,
};
use super::tracer::Tracer;
use super::unknowns::{slot, sys_point, to_chord, v3};
use crate::geom::eval::eval_curve;
use crate::medial::axis::{Degenerate, DegenerateEnd, DegenerateKind, DegenerateOpen};
use crate::medial::equations::{edge_angle, MedialSystem};
use crate::medial::maximal::curvature_allows;
use crate::medial::solver::{solve, SolveOptions, SolveStatus};
use crate::model::{Element, Model};
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// Most balls of one traced degenerate curve.
pub const MAX_DEGENERATE_BALLS: usize = 2_000;

/// Singular values of the 2-segment Jacobian below this fraction of the largest span its
/// null space.
const NULL_REL_SINGULAR: f64 = 1e-6;

/// The centre parts of two null vectors span no area beyond this: the centre moves along a
/// line at most (unit null vectors).
const NULL_CENTRE_AREA: f64 = 1e-6;

/// A null vector's centre part shorter than this is no motion of the centre (unit vectors).
const NULL_CENTRE_LENGTH: f64 = 1e-6;

/// The end of a degenerate curve is located to this fraction of the accuracy, in centre
/// travel.
const LOCATE_REL_ACCURACY: f64 = 0.25;

/// A degenerate curve's first step from a ball, relative to the ball's radius (then grown
/// or halved as a seam's).
const DEGENERATE_FIRST_STEP_REL_RADIUS: f64 = 0.5;

/// The touch points chosen on a continuum are at least this many times the separation
/// verification requires of two places (`√(8·r·a)`) apart.
const SEPARATED_MARGIN: f64 = 2.0;

/// Along a curve, the touch points stay this many times that separation apart (the OCCT
/// cross-check separates places at the accuracy plus its own 1e-7 mm).
const SEPARATED_STEP_MARGIN: f64 = 1.1;

/// Points of the circle a degenerate ball touches along, tested for [`Degenerate::around`].
const AROUND_SAMPLES: usize = 16;

/// How near its segments' faces each of those points must be, in accuracies.
const AROUND_REL_ACCURACY: f64 = 10.0;

/// How the centre of a ball touching two segments can move while the touch points stay on
/// them (the null space of the 2-segment system's Jacobian, 6 × 8).
#[derive(Clone, Copy, Debug)]
pub(super) enum CentreMotion {
    /// Not at all: the ball touches all round (a sphere's centre).
    Still,
    /// Along one direction (unit): the sheet has collapsed to a curve.
    Along(DVec3),
}

/// The centre's motion at `x` (unknowns `[B, r, s_a, s_b]`) when the sheet of `sys` (two
/// segments) has collapsed there: its null space is more than two-dimensional and moves the
/// centre along a line at most. `None` at a sheet point (the centre moves in a plane) or
/// where the system is undefined.
pub(super) fn centre_motion(
    model: &Model,
    sys: &MedialSystem,
    x: &DVector<f64>,
) -> Option<CentreMotion> {
    let (_, j) = sys.eval(model, x)?;
    let n = x.len();
    let mut m = DMatrix::zeros(n, n);
    m.view_mut((0, 0), (j.nrows(), n)).copy_from(&j);
    let svd = m.svd(false, true);
    let vt = svd.v_t?;
    let smax = svd.singular_values.max();
    // The null space: right singular vectors of (near-)zero singular values.
    let null: Vec<DVec3> = (0..n)
        .filter(|&i| svd.singular_values[i] <= NULL_REL_SINGULAR * smax)
        .map(|i| DVec3::new(vt[(i, 0)], vt[(i, 1)], vt[(i, 2)]))
        .collect();
    if null.len() < 2 {
        return None;
    }
    let area = (0..null.len())
        .flat_map(|i| (i + 1..null.len()).map(move |k| (i, k)))
        .map(|(i, k)| null[i].cross(null[k]).length())
        .fold(0.0, f64::max);
    if area > NULL_CENTRE_AREA {
        return None;
    }
    let longest = null
        .iter()
        .copied()
        .max_by(|a, b| a.length().total_cmp(&b.length()))?;
    Some(if longest.length() > NULL_CENTRE_LENGTH {
        CentreMotion::Along(longest.normalize())
    } else {
        CentreMotion::Still
    })
}

/// The `k`-th of `n` points spaced evenly round the circle of contact of a ball centred `c`
/// with radius `r` whose centre moves along `dir`: the circle across `dir` that lies `axial`
/// along it from the centre (0 on a cylinder's axis, off the centre's plane on a cone's).
fn circle_of_contact(
    c: DVec3,
    r: f64,
    dir: DVec3,
    axial: f64,
    n: usize,
) -> impl Fn(usize) -> DVec3 {
    let (u, v) = dir.any_orthonormal_pair();
    let hub = c + dir.normalize() * axial;
    let rho = (r * r - axial * axial).max(0.0).sqrt();
    move |k| {
        let phi = std::f64::consts::TAU * k as f64 / n as f64;
        hub + (u * phi.cos() + v * phi.sin()) * rho
    }
}

/// Most hand-overs of one degenerate curve from one element to the next, each way.
pub const MAX_DEGENERATE_HANDOVERS: usize = 8;

/// A degenerate curve followed one way from a ball (see [`Tracer::follow`]).
struct Followed {
    /// The balls after the first, with the segments each touches.
    balls: Vec<([Element; 2], DVector<f64>)>,
    end: DegenerateEnd,
    /// The segment pairs it was handed to, in order.
    stretches: Vec<[Element; 2]>,
}

/// Why one step along a degenerate curve failed, with the corrected ball where there is one.
enum StepFail {
    /// Another element is nearer the new centre than `r`: the face of the nearest.
    NotEmpty { ball: DVector<f64>, face: usize },
    /// `r` fell to the accuracy.
    Vanished { ball: DVector<f64> },
    /// The touch point in slot `which` left its segment `seg`.
    Left {
        seg: Element,
        which: usize,
        ball: DVector<f64>,
    },
    /// Anything else (the step may be too long): of what kind, and why.
    Other(DegenerateOpen, String),
}

/// What [`Tracer::margin`] measures along the step that failed: how far a ball is from the
/// event the step ran into, positive before it, falling through 0 at it about linearly.
enum Margin {
    /// `r` less the accuracy.
    Radius,
    /// The distance to this face less `r` (and the accuracy).
    Face(usize),
    /// How far the touch point in slot `which` is short of `at` (the point of its segment
    /// nearest where it went past), along `along` (its motion over the step).
    Past {
        which: usize,
        at: DVec3,
        along: DVec3,
    },
}

impl Tracer<'_> {
    /// Traces every degenerate curve sampling found, both ways from each sampled ball not on
    /// a curve traced already (see the module's documentation); points stay as sampled.
    pub(super) fn trace_degenerates(&mut self) {
        let pieces = std::mem::take(&mut self.degenerate);
        let xs = std::mem::take(&mut self.degenerate_x);
        let tol = self.opts.accuracy.max(1e-6 * self.model.diagonal());
        for (d, xs) in pieces.into_iter().zip(xs) {
            if d.kind != DegenerateKind::Curve {
                self.degenerate.push(d);
                continue;
            }
            let mut traced: Vec<Degenerate> = vec![];
            for x in &xs {
                let c = v3(x);
                let on_traced = traced.iter().any(|t| {
                    t.balls.windows(2).any(|w| {
                        let [p, q] = [w[0], w[1]].map(|b| DVec3::new(b[0], b[1], b[2]));
                        to_chord(c, p, q) <= tol
                    })
                });
                if !on_traced {
                    traced.push(self.trace_degenerate(&d, x));
                }
            }
            self.degenerate.extend(traced);
        }
        self.drop_covered_curves(tol);
    }

    /// The degenerate curve of `d`'s segments through its sampled ball `x0`.
    fn trace_degenerate(&self, d: &Degenerate, x0: &DVector<f64>) -> Degenerate {
        let first = [d.segments[0], d.segments[1]];
        let sys = MedialSystem::new(first.to_vec());
        let mut piece = Degenerate {
            solid: d.solid,
            kind: DegenerateKind::Curve,
            segments: first.to_vec(),
            balls: vec![],
            touch: vec![],
            ends: vec![],
            around: false,
        };
        let Some(CentreMotion::Along(dir)) = centre_motion(self.model, &sys, x0) else {
            piece.push(self.model, first, x0);
            let open = DegenerateEnd::open(
                DegenerateOpen::NoDirection,
                "the centre's direction is undefined at the sampled ball",
            );
            piece.ends = vec![open.clone(), open];
            return piece;
        };
        piece.around = self.touches_around(&d.segments, x0, dir);
        // Sampling may have put a touch point at the border of an arc (a fillet's edge),
        // where the first correction slips it off the face: start from the arc's inside.
        let recentred = self.recentred(&sys, x0, dir, true, 0.0);
        // Where recentring moved both touch points onto one face, the sampled ball stays
        // too (same centre), with its touch point on the other (a plane tangent to a fillet:
        // that face is touched there).
        let sampled = (recentred.as_ref().is_some_and(|(pair, _)| *pair != first))
            .then(|| (first, x0.clone()));
        let (first, x0) = recentred
            .as_ref()
            .map_or((first, x0), |(pair, y)| (*pair, y));
        let fwd = self.follow(first, d.solid, x0, dir);
        // A closed curve came back to `x0`: nothing to follow the other way.
        let closed = fwd.end == DegenerateEnd::Closed;
        let back = if closed {
            Followed {
                balls: vec![],
                end: DegenerateEnd::Closed,
                stretches: vec![],
            }
        } else {
            self.follow(first, d.solid, x0, -dir)
        };
        for (segs, x) in back.balls.iter().rev() {
            piece.push(self.model, *segs, x);
        }
        if let Some((pair, x)) = &sampled {
            piece.push(self.model, *pair, x);
        }
        piece.push(self.model, first, x0);
        for (segs, x) in &fwd.balls {
            piece.push(self.model, *segs, x);
        }
        piece.segments = back
            .stretches
            .iter()
            .rev()
            .chain(sampled.as_ref().map(|(pair, _)| pair))
            .chain([&first])
            .chain(&fwd.stretches)
            .flatten()
            .copied()
            .collect();
        if closed {
            piece.ends = vec![DegenerateEnd::Closed];
            return piece;
        }
        // A vanishing end's last ball is the vertex itself.
        for (end, first) in [(&back.end, true), (&fwd.end, false)] {
            if let DegenerateEnd::Vanishes { vertex } = *end {
                let p = self.model.vertices[vertex].point.to_array();
                let ball = [p[0], p[1], p[2], 0.0];
                if first {
                    piece.balls.insert(0, ball);
                    piece.touch.insert(0, [p, p]);
                } else {
                    piece.balls.push(ball);
                    piece.touch.push([p, p]);
                }
            }
        }
        piece.ends = vec![back.end, fwd.end];
        piece
    }

    /// Follows the curve from `x0` (touching `segments`) along `dir`, handing it over where
    /// its continuum runs off its element onto one the ball touches along a continuum there
    /// too (a boss's side onto its foot circle, a reflex edge): the balls after `x0` with the
    /// segments each touches, how it ends, and the segment pairs it was handed to.
    fn follow(
        &self,
        segments: [Element; 2],
        solid: usize,
        x0: &DVector<f64>,
        dir: DVec3,
    ) -> Followed {
        let mut segs = segments;
        let (mut x, mut d) = (x0.clone(), dir);
        let mut out = Followed {
            balls: vec![],
            end: DegenerateEnd::Closed,
            stretches: vec![],
        };
        let mut visited = vec![segments[0], segments[1]];
        // The located end the last hand-over went past (an element met, osculating).
        let mut handed_past: Option<DegenerateEnd> = None;
        let (mut handovers, mut respreads) = (0, 0);
        // Set by a spread, until the march from it has taken a step.
        let mut just_spread = false;
        while handovers <= MAX_DEGENERATE_HANDOVERS && respreads <= MAX_DEGENERATE_BALLS {
            let sys = MedialSystem::new(segs.to_vec());
            let (balls, end, left_seg) = self.march_degenerate(&sys, solid, &x, d);
            let left = left_seg.is_some();
            if balls.is_empty() && matches!(end, DegenerateEnd::Open { .. }) {
                if let Some(met) = handed_past.take() {
                    // Not one step on the element handed to (a sphere the ball has become,
                    // touching it all over): the curve ends where it met it.
                    out.stretches.pop();
                    out.end = met;
                    return out;
                }
            }
            let balls_taken = balls.len();
            out.balls.extend(balls.into_iter().map(|b| (segs, b)));
            let last = out.balls.last().map_or(&x, |(_, b)| b).clone();
            // Where a touch point left its element and nothing else stops the ball there, the
            // continuum may run on: onto the element the ball osculates there, or a face
            // beside it across a smooth edge (a fillet split in two).
            // So may it where the ball, still on its elements, meets a face it osculates: the
            // face it touches along a continuum there too runs on from it (a cylinder's axis
            // onto a coaxial cone's past the convex circle between them; a capsule's cap,
            // whose centre cannot move, stops it there).
            let carry_on = (left
                && matches!(
                    end,
                    DegenerateEnd::Meets {
                        osculates: true,
                        ..
                    } | DegenerateEnd::Open { .. }
                ))
                || matches!(
                    end,
                    DegenerateEnd::Meets {
                        element: Element::Face(_),
                        osculates: true,
                        ..
                    }
                );
            // A touch point that left its segment off the end of the arc the ball touches it
            // along, where the arc runs on on the same segments (a thread's root, a helical
            // strip whose arc turns round the axis as the centre moves): the touch points are
            // spread along the arc again and the curve goes on.
            let progressed = !(just_spread && balls_taken == 0);
            just_spread = false;
            if left && progressed && matches!(end, DegenerateEnd::Open { .. }) {
                if let Some(y) = self.spread(&sys, &last, d) {
                    let moved = (0..2).any(|i| {
                        let p = |z: &DVector<f64>| sys_point(self.model, segs[i], slot(z, i));
                        p(&y)
                            .zip(p(&last))
                            .is_some_and(|(a, b)| a.distance(b) > self.opts.accuracy)
                    });
                    if moved {
                        x = y;
                        respreads += 1;
                        just_spread = true;
                        continue;
                    }
                }
            }
            let next = carry_on
                .then(|| {
                    // Two elements touched, one left: the continuum may run on on the other
                    // alone (a plane tangent to a round, ending at a corner).
                    let stayed = (segs[0] != segs[1])
                        .then(|| segs.into_iter().find(|&s| Some(s) != left_seg))
                        .flatten();
                    self.degenerate_hand_over(solid, &last, d, (segs, &end), &visited, stayed)
                })
                .flatten();
            match next {
                Some((pair, y, v)) => {
                    handovers += 1;
                    handed_past = matches!(end, DegenerateEnd::Meets { .. }).then_some(end);
                    segs = pair;
                    visited.extend(pair);
                    out.stretches.push(pair);
                    (x, d) = (y, v);
                }
                None => {
                    // The arc of contact may instead shrink to a point of its face ahead (a
                    // vertex, or a point of an edge): `shrink.rs`.
                    let shrunk = (left && matches!(end, DegenerateEnd::Open { .. }))
                        .then(|| self.shrinks(solid, segs, &last, d))
                        .flatten();
                    out.end = match shrunk {
                        Some((pair, y, shrunk)) => {
                            out.balls.push((pair, y));
                            shrunk
                        }
                        None => end,
                    };
                    return out;
                }
            }
        }
        out.end = DegenerateEnd::open(
            DegenerateOpen::HandoverBudget,
            format!("handed over {MAX_DEGENERATE_HANDOVERS} times and no end"),
        );
        out
    }

    /// Marches from `x0` along direction `dir` of the centre: the balls after `x0`, how the
    /// curve ends, and the element a touch point left where it ends so (where
    /// [`Tracer::follow`] may hand it over).
    fn march_degenerate(
        &self,
        sys: &MedialSystem,
        solid: usize,
        x0: &DVector<f64>,
        dir: DVec3,
    ) -> (Vec<DVector<f64>>, DegenerateEnd, Option<Element>) {
        let diag = self.model.diagonal();
        let locate = LOCATE_REL_ACCURACY * self.opts.accuracy;
        // Steps shorter than the end's location would locate nothing more.
        let h_min = (MIN_STEP_REL_DIAGONAL * diag).max(locate);
        let h_max = MAX_STEP_REL_DIAGONAL * diag;
        let start = v3(x0);
        // The curve bends on the scale of its radius (a torus's core, a fillet's axis round
        // a corner): start at half of it, not at a seam's cautious first step.
        let mut h =
            (DEGENERATE_FIRST_STEP_REL_RADIUS * x0[3]).clamp(FIRST_STEP_REL_DIAGONAL * diag, h_max);
        let (mut x, mut d) = (x0.clone(), dir);
        let mut travelled = 0.0;
        let mut out = vec![];
        let open = DegenerateEnd::open;
        let mut respread = false;
        loop {
            if out.len() >= MAX_DEGENERATE_BALLS {
                return (
                    out,
                    open(
                        DegenerateOpen::BallBudget,
                        format!("{MAX_DEGENERATE_BALLS} balls and no end"),
                    ),
                    None,
                );
            }
            match self.degenerate_step(sys, solid, &x, d, h) {
                Ok((xn, dn)) if dn.angle_between(d) > MAX_TURN_RAD => {
                    h *= 0.5;
                    if h < h_min {
                        let why = "the curve turns at every step";
                        return (out, open(DegenerateOpen::TurnsEveryStep, why.into()), None);
                    }
                    let _ = xn;
                }
                Ok((xn, dn)) => {
                    let (c, cn) = (v3(&x), v3(&xn));
                    travelled += c.distance(cn);
                    if travelled > 3.0 * h && to_chord(start, c, cn) <= 0.5 * h {
                        return (out, DegenerateEnd::Closed, None);
                    }
                    out.push(xn.clone());
                    (x, d) = (xn, dn);
                    respread = false;
                    h = (h * STEP_GROWTH).min(h_max);
                }
                Err(StepFail::Other(DegenerateOpen::TouchPointsMeet, _)) if !respread => {
                    // The touch points drifted together round the circle of contact (a
                    // circular edge touched all round, where they are free to): spread them
                    // along the arc again and retry, once per step.
                    respread = true;
                    match self.spread(sys, &x, d) {
                        Some(y) => x = y,
                        None => h *= 0.5,
                    }
                }
                Err(StepFail::Other(cause, why)) => {
                    h *= 0.5;
                    if h < h_min {
                        return (out, open(cause, why), None);
                    }
                }
                Err(fail) => {
                    let (end, lo, last) = self.locate_end(sys, solid, &x, d, h, fail, locate);
                    let end = end.unwrap_or_else(|| x.clone());
                    if lo > 0.0 {
                        out.push(end.clone());
                    }
                    let left = match last {
                        StepFail::Left { seg, .. } => Some(seg),
                        _ => None,
                    };
                    let how = match last {
                        StepFail::NotEmpty { face, .. } => {
                            self.meets(sys, solid, &end, d, Some(face))
                        }
                        StepFail::Vanished { .. } => self.vanishes(sys, &end),
                        // Where the continuum reaches its face's border, the curve ends if
                        // the ball touches something else there (a fillet's axis at the
                        // corner blend it runs into), or osculates the face it leaves onto
                        // (`osculated_past`); carrying on onto the next face is not done yet.
                        StepFail::Left { seg, .. } => match self.meets(sys, solid, &end, d, None) {
                            DegenerateEnd::Open { .. } => {
                                let why = format!(
                                    "a touch point left {seg}, and the curve is not carried on \
                                     onto the next face"
                                );
                                self.osculated_past(seg, &end)
                                    .unwrap_or_else(|| open(DegenerateOpen::LeftFace, why))
                            }
                            met => met,
                        },
                        StepFail::Other(cause, why) => open(cause, why),
                    };
                    return (out, how, left);
                }
            }
        }
    }

    /// Locates where the step of length `h` from `x` along `d` first fails (`fail`, the
    /// step's own failure): the last ball that passes (`None`: none past `x`), how far along
    /// it is, and the failure just past it, `locate` apart. By false position on the
    /// [`Margin`] of the failure (Illinois' rule, with the probe put a little to the side of
    /// the estimate it should land on, so that a linear margin is bracketed in two probes);
    /// by bisection where the margin is unknown or another failure comes first.
    #[allow(clippy::too_many_arguments)]
    fn locate_end(
        &self,
        sys: &MedialSystem,
        solid: usize,
        x: &DVector<f64>,
        d: DVec3,
        h: f64,
        fail: StepFail,
        locate: f64,
    ) -> (Option<DVector<f64>>, f64, StepFail) {
        let margin = self.margin_of(sys, x, &fail);
        let value = |ball: &DVector<f64>| {
            margin
                .as_ref()
                .and_then(|m| self.margin(sys, m, ball))
                .filter(|g| g.is_finite())
        };
        let (mut lo, mut hi) = (0.0, h);
        let mut g_lo = value(x).filter(|&g| g > 0.0);
        let mut g_hi = fail_ball(&fail).and_then(value).filter(|&g| g <= 0.0);
        let mut last = fail;
        let mut end = None;
        // +1 after lo moved, −1 after hi moved.
        let mut moved = -1;
        let mut same_side = 0;
        while hi - lo > locate {
            let mid = match (g_lo, g_hi) {
                (Some(a), Some(b)) if same_side < 2 && a > b => {
                    let s = lo + (hi - lo) * a / (a - b);
                    // Land just short of the event after hi moved, just past it after lo
                    // did.
                    let s = s + (0.4 * locate).copysign(f64::from(moved));
                    s.clamp(lo + 0.25 * locate, hi - 0.25 * locate)
                }
                _ => 0.5 * (lo + hi),
            };
            match self.degenerate_step(sys, solid, x, d, mid) {
                Ok((xm, _)) => {
                    lo = mid;
                    g_lo = g_lo.and(value(&xm)).filter(|&g| g > 0.0);
                    end = Some(xm);
                    same_side = if moved == 1 { same_side + 1 } else { 0 };
                    if moved == 1 {
                        // Illinois: halve the stale end's value.
                        g_hi = g_hi.map(|g| 0.5 * g);
                    }
                    moved = 1;
                }
                Err(f) => {
                    hi = mid;
                    g_hi = if same_failure(&f, &last) {
                        g_hi.and(fail_ball(&f).and_then(value))
                            .filter(|&g| g <= 0.0)
                    } else {
                        None
                    };
                    same_side = if moved == -1 { same_side + 1 } else { 0 };
                    if moved == -1 {
                        g_lo = g_lo.map(|g| 0.5 * g);
                    }
                    moved = -1;
                    last = f;
                }
            }
        }
        (end, lo, last)
    }

    /// What measures the distance to the event behind `fail` from ball `x` (see [`Margin`]).
    fn margin_of(&self, sys: &MedialSystem, x: &DVector<f64>, fail: &StepFail) -> Option<Margin> {
        match fail {
            StepFail::Vanished { .. } => Some(Margin::Radius),
            StepFail::NotEmpty { face, .. } => Some(Margin::Face(*face)),
            StepFail::Left { seg, which, ball } => {
                let from = sys_point(self.model, sys.segments[*which], slot(x, *which))?;
                let to = sys_point(self.model, *seg, slot(ball, *which))?;
                let along = (to - from).try_normalize()?;
                let at = match *seg {
                    Element::Face(f) => {
                        self.boundary
                            .nearest_on_face(self.model, f, to, None, f64::INFINITY)?
                            .point
                    }
                    Element::Edge(e) => self.model.edges[e]
                        .vertices
                        .iter()
                        .map(|&v| self.model.vertices[v].point)
                        .min_by(|a, b| a.distance(to).total_cmp(&b.distance(to)))?,
                    Element::Vertex(_) => return None,
                };
                Some(Margin::Past {
                    which: *which,
                    at,
                    along,
                })
            }
            StepFail::Other(..) => None,
        }
    }

    /// The [`Margin`] `m` of ball `ball`.
    fn margin(&self, sys: &MedialSystem, m: &Margin, ball: &DVector<f64>) -> Option<f64> {
        let a = self.opts.accuracy;
        match *m {
            Margin::Radius => Some(ball[3] - a),
            Margin::Face(f) => self
                .boundary
                .nearest_on_face(self.model, f, v3(ball), None, f64::INFINITY)
                .map(|hit| hit.distance - ball[3] + a),
            Margin::Past { which, at, along } => {
                sys_point(self.model, sys.segments[which], slot(ball, which))
                    .map(|p| (at - p).dot(along))
            }
        }
    }

    /// The corrector of a degenerate curve: the ball near `start` that solves `sys` with its
    /// centre in the plane through `pred` across `d` (seven equations in eight unknowns: the
    /// minimum-norm Newton step leaves the touch points' turn free).
    pub(super) fn correct_across(
        &self,
        sys: &MedialSystem,
        start: DVector<f64>,
        pred: DVec3,
        d: DVec3,
    ) -> crate::medial::solver::Solution {
        let m = sys.equations();
        let eval = |y: &DVector<f64>| {
            let (f, j) = sys.eval(self.model, y)?;
            let mut fa = DVector::zeros(m + 1);
            fa.rows_mut(0, m).copy_from(&f);
            fa[m] = d.dot(v3(y) - pred);
            let mut ja = DMatrix::zeros(m + 1, y.len());
            ja.view_mut((0, 0), (m, y.len())).copy_from(&j);
            for k in 0..3 {
                ja[(m, k)] = d[k];
            }
            Some((fa, ja))
        };
        solve(
            eval,
            start,
            &SolveOptions {
                tol: self.opts.solver_tol,
                max_iter: MAX_CORRECTOR_ITER,
            },
        )
    }

    /// One step of length `h` from `x` along `d`: the corrected ball and the centre's
    /// direction there (oriented with `d`).
    fn degenerate_step(
        &self,
        sys: &MedialSystem,
        solid: usize,
        x: &DVector<f64>,
        d: DVec3,
        h: f64,
    ) -> Result<(DVector<f64>, DVec3), StepFail> {
        let pred = v3(x) + d * h;
        let mut x1 = x.clone();
        x1[0] = pred.x;
        x1[1] = pred.y;
        x1[2] = pred.z;
        let sol = self.correct_across(sys, x1, pred, d);
        if sol.status != SolveStatus::Converged {
            return Err(StepFail::Other(
                DegenerateOpen::CorrectorFailed,
                format!("the corrector did not converge ({:?})", sol.status),
            ));
        }
        let xn = sol.x;
        let r = xn[3];
        if r <= self.opts.accuracy {
            return Err(StepFail::Vanished { ball: xn });
        }
        for (i, &seg) in sys.segments.iter().enumerate() {
            if !self.on_segment(seg, slot(&xn, i)) {
                return Err(StepFail::Left {
                    seg,
                    which: i,
                    ball: xn,
                });
            }
        }
        let [ta, tb] = [0, 1].map(|i| sys_point(self.model, sys.segments[i], slot(&xn, i)));
        // Verification holds a degenerate ball to two separate places.
        let one_place = (8.0 * r * self.opts.accuracy).sqrt();
        if let (Some(ta), Some(tb)) = (ta, tb) {
            if ta.distance(tb)
                <= (DISTINCT_TOUCH_REL_RADIUS * r).max(SEPARATED_STEP_MARGIN * one_place)
            {
                return Err(StepFail::Other(
                    DegenerateOpen::TouchPointsMeet,
                    "its two touch points come within one place of each other (the continuum \
                     is too short for the accuracy)"
                        .into(),
                ));
            }
        }
        let dn = match centre_motion(self.model, sys, &xn) {
            Some(CentreMotion::Along(v)) => {
                if v.dot(d) < 0.0 {
                    -v
                } else {
                    v
                }
            }
            _ => {
                return Err(StepFail::Other(
                    DegenerateOpen::SheetOpens,
                    "the sheet opens again (not degenerate)".into(),
                ))
            }
        };
        match self.nearest_in(solid, v3(&xn)) {
            Some((face, hit)) if hit.distance < r - self.opts.accuracy => {
                return Err(StepFail::NotEmpty { ball: xn, face })
            }
            Some(_) => {}
            None => {
                return Err(StepFail::Other(
                    DegenerateOpen::NoBoundary,
                    "no boundary near the ball".into(),
                ))
            }
        }
        Ok((xn, dn))
    }

    /// Ball `x` (centre moving along `dir`) with its touch points moved round its circle of
    /// contact (the one `axial` along `dir` from its centre: 0 on a cylinder's axis) to
    /// the inside of the arcs it touches its faces along: a quarter and three quarters
    /// along the arc where both segments are one face, the middle of each face's arc where
    /// they are two (the halves of a split cylinder), on the arc of one where the other holds
    /// only a sliver of the circle (with the segments then touched). `None` when a segment is a vertex, an
    /// arc is too short to choose from or to hold two separate places, or the moved ball does
    /// not solve. Where not `strict`
    /// (a ball handed over onto the element its continuum runs onto, exactly at that
    /// element's border), touch points on an edge need only lie within its range (their
    /// normals may be a rounding outside its arc), and are left for the next step to
    /// correct.
    pub(super) fn recentred(
        &self,
        sys: &MedialSystem,
        x: &DVector<f64>,
        dir: DVec3,
        strict: bool,
        axial: f64,
    ) -> Option<([Element; 2], DVector<f64>)> {
        const N: usize = 2 * AROUND_SAMPLES;
        let (c, r) = (v3(x), x[3]);
        let tol = AROUND_REL_ACCURACY * self.opts.accuracy;
        let at = circle_of_contact(c, r, dir, axial, N);
        // Per segment: the parameters of each circle point on its face, where it is.
        let mut on = vec![];
        for (i, &seg) in sys.segments.iter().enumerate() {
            // Each projection starts from the last one's parameters (neighbours on the
            // circle): a search from nothing costs a B-spline face a global sampling.
            let mut hint = strict.then(|| slot(x, i));
            let mut flags = Vec::with_capacity(N);
            for k in 0..N {
                let p = at(k);
                let s = self.params_on(seg, p, c, hint);
                if s.is_some() {
                    hint = s;
                }
                let on = s.filter(|&s| {
                    let close = sys_point(self.model, seg, s).is_some_and(|q| q.distance(p) <= tol);
                    close
                        && match seg {
                            // Handed onto an edge exactly at its face's border, the normal
                            // may be a rounding outside the edge's arc: the range decides.
                            Element::Edge(e) if !strict => self.edge_status(e, s).0,
                            _ => self.on_segment(seg, s),
                        }
                });
                flags.push(on);
            }
            on.push(flags);
        }
        // The longest circular run of circle points on a face: (first, length).
        let run = |flags: &[Option<[f64; 2]>]| {
            if flags.iter().all(Option::is_some) {
                return Some((0, N));
            }
            let start = flags.iter().position(Option::is_none)?;
            let (mut best, mut cur) = ((0, 0), (0, 0));
            for j in 1..=N {
                let k = (start + j) % N;
                if flags[k].is_some() {
                    cur = if cur.1 == 0 {
                        (k, 1)
                    } else {
                        (cur.0, cur.1 + 1)
                    };
                    if cur.1 > best.1 {
                        best = cur;
                    }
                } else {
                    cur = (0, 0);
                }
            }
            (best.1 > 0).then_some(best)
        };
        // Where one of two faces holds only a sliver of the circle (a plane tangent to a
        // fillet, touched on its edge), both touch points go on the other's arc.
        let (ra, rb) = (run(&on[0]), run(&on[1]));
        let long = |r: Option<(usize, usize)>| r.is_some_and(|(_, len)| len >= 3);
        let (pair, picks, from) = if sys.segments[0] == sys.segments[1] || long(ra) != long(rb) {
            let i = usize::from(!long(ra));
            let (k0, len) = [ra, rb][i]?;
            if len < 3 {
                return None;
            }
            let seg = sys.segments[i];
            (
                [seg, seg],
                [(k0 + len / 4) % N, (k0 + 3 * len / 4) % N],
                [i, i],
            )
        } else {
            let ((a0, la), (b0, lb)) = (ra?, rb?);
            (
                [sys.segments[0], sys.segments[1]],
                [(a0 + la / 2) % N, (b0 + lb / 2) % N],
                [0, 1],
            )
        };
        let mut y = x.clone();
        for (i, &k) in picks.iter().enumerate() {
            let s = on[from[i]][k]?;
            y[4 + 2 * i] = s[0];
            y[5 + 2 * i] = s[1];
        }
        // Two touch points closer than verification separates places would be one contact.
        let one_place = (8.0 * r * self.opts.accuracy).sqrt();
        let [ta, tb] = [0, 1].map(|i| sys_point(self.model, pair[i], slot(&y, i)));
        if ta?.distance(tb?) <= SEPARATED_MARGIN * one_place {
            return None;
        }
        if !strict {
            return Some((pair, y));
        }
        // Polished on the plane across `dir` through the centre.
        let sys = MedialSystem::new(pair.to_vec());
        let sol = self.degenerate_step(&sys, self.solid_of(pair[0]), &y, dir, 0.0);
        sol.ok().map(|(y, _)| (pair, y))
    }

    /// Ball `x` with its touch points spread along the arc it touches its segments along
    /// ([`Self::spread_on_edge`] on an edge touched twice, else [`Self::recentred`] on the
    /// same segments), or `None`.
    fn spread(&self, sys: &MedialSystem, x: &DVector<f64>, d: DVec3) -> Option<DVector<f64>> {
        match sys.segments[..] {
            [Element::Edge(e), Element::Edge(f)] if e == f => self.spread_on_edge(e, x),
            _ => self
                .recentred(sys, x, d, true, 0.0)
                .filter(|(pair, _)| pair[..] == sys.segments[..])
                .map(|(_, y)| y),
        }
    }

    /// Ball `x`, touching edge `e` twice along an arc of it (a circular edge round the
    /// centre's line of motion: a slot's round end, a boss's foot), with its touch points
    /// moved to a quarter and three quarters along the longest run of the edge's samples at
    /// distance `r` from the centre and on the edge's arc of normals. `None` when the run is
    /// too short to hold two separate places.
    fn spread_on_edge(&self, e: usize, x: &DVector<f64>) -> Option<DVector<f64>> {
        const N: usize = 2 * AROUND_SAMPLES;
        let (c, r) = (v3(x), x[3]);
        let tol = AROUND_REL_ACCURACY * self.opts.accuracy;
        let (t0, t1) = self.model.edges[e].range;
        let flags: Vec<Option<[f64; 2]>> = (0..=N)
            .map(|k| {
                let t = t0 + (t1 - t0) * k as f64 / N as f64;
                let p = eval_curve(&self.model.edges[e].curve, t).p;
                let n = (p - c).try_normalize()?;
                let th = edge_angle(self.model, e, t, n)?;
                ((p.distance(c) - r).abs() <= tol && self.on_segment(Element::Edge(e), [t, th]))
                    .then_some([t, th])
            })
            .collect();
        let (mut best, mut cur) = ((0, 0), (0, 0));
        for (k, f) in flags.iter().enumerate() {
            cur = match (f, cur.1) {
                (None, _) => (0, 0),
                (Some(_), 0) => (k, 1),
                (Some(_), len) => (cur.0, len + 1),
            };
            if cur.1 > best.1 {
                best = cur;
            }
        }
        let (k0, len) = best;
        if len < 3 {
            return None;
        }
        let mut y = x.clone();
        for (i, k) in [k0 + len / 4, k0 + 3 * len / 4].into_iter().enumerate() {
            let s = flags[k]?;
            y[4 + 2 * i] = s[0];
            y[5 + 2 * i] = s[1];
        }
        let one_place = (8.0 * r * self.opts.accuracy).sqrt();
        let [ta, tb] = [0, 1].map(|i| sys_point(self.model, Element::Edge(e), slot(&y, i)));
        (ta?.distance(tb?) > SEPARATED_MARGIN * one_place).then_some(y)
    }

    /// The parameters of point `p` on segment `seg` touched from centre `c`: a face's
    /// `(u, v)` (searched from `hint`, or from the face's nearest point), a reflex edge's
    /// `(t, θ)`; `None` on a vertex.
    pub(super) fn params_on(
        &self,
        seg: Element,
        p: DVec3,
        c: DVec3,
        hint: Option<[f64; 2]>,
    ) -> Option<[f64; 2]> {
        match seg {
            Element::Face(f) => {
                let surface = &self.model.faces[f].surface;
                // Without a hint, the distance structure's cached samples give one.
                let hint = hint.map(|h| (h[0], h[1])).or_else(|| {
                    self.boundary
                        .nearest_on_face(self.model, f, p, None, f64::INFINITY)
                        .map(|h| h.uv)
                });
                crate::geom::project_point(surface, p, hint).map(|uv| [uv.0, uv.1])
            }
            Element::Edge(e) => {
                let (t, q, _) = crate::geom::nearest_on_edge(self.model, e, p, None);
                let n = (q - c).normalize_or_zero();
                crate::medial::equations::edge_angle(self.model, e, t, n).map(|th| [t, th])
            }
            Element::Vertex(_) => None,
        }
    }

    /// True when ball `x`, whose centre moves along `dir`, touches `segments` all round: its
    /// circle of contact across `dir` through its first touch point (in the centre's plane on
    /// a cylinder, off it on a cone) lies on their faces at [`AROUND_SAMPLES`] points (to
    /// [`AROUND_REL_ACCURACY`] × the accuracy).
    fn touches_around(&self, segments: &[Element], x: &DVector<f64>, dir: DVec3) -> bool {
        let faces: Vec<usize> = segments.iter().flat_map(|&s| s.faces(self.model)).collect();
        let (c, r) = (v3(x), x[3]);
        let tol = AROUND_REL_ACCURACY * self.opts.accuracy;
        // The circle of contact through the first touch point: off the centre's plane on a
        // cone (its balls touch it along a circle ahead of or behind their centre).
        let axial = sys_point(self.model, segments[0], slot(x, 0))
            .map_or(0.0, |p| (p - c).dot(dir.normalize()))
            .clamp(-r, r);
        let at = circle_of_contact(c, r, dir, axial, AROUND_SAMPLES);
        let mut near = vec![];
        (0..AROUND_SAMPLES).all(|k| {
            let p = at(k);
            self.boundary.within_into(self.model, p, tol, &mut near);
            near.iter().any(|f| faces.contains(f))
        })
    }

    /// How a curve whose ball stops being empty past `x` (centre moving along `dir`) ends:
    /// the nearest element its ball touches there off its own continuum. A face touching
    /// the ball on the circle of its continuum (a plane tangent to a fillet along its edge)
    /// is not met there; a face the ball osculates (a corner's spherical blend) is met
    /// wherever, and so is `intruder`, the face that came closer than `r` just past `x`
    /// (a pocket's wall tangent to a boss, met where the boss's foot circle touches it).
    fn meets(
        &self,
        sys: &MedialSystem,
        solid: usize,
        x: &DVector<f64>,
        dir: DVec3,
        intruder: Option<usize>,
    ) -> DegenerateEnd {
        let own: Vec<usize> = sys
            .segments
            .iter()
            .flat_map(|&s| s.faces(self.model))
            .collect();
        let (c, r) = (v3(x), x[3]);
        let a = self.opts.accuracy;
        // Two contacts closer than this are one place (as verification separates them).
        let one_place = (8.0 * r * a).sqrt();
        let on_circle = |p: DVec3| {
            let w = p - c;
            let axial = w.dot(dir);
            let radial = (w - dir * axial).length();
            axial.hypot(radial - r) <= one_place
        };
        let mut best: Option<(f64, Element, DVec3, bool)> = None;
        for g in self.boundary.within(self.model, c, r + a) {
            if self.face_solid[g] != solid || own.contains(&g) {
                continue;
            }
            let Some(hit) = self
                .boundary
                .nearest_on_face(self.model, g, c, None, r + 2.0 * a)
            else {
                continue;
            };
            let Some((element, s)) = self.hit_segment(g, &hit, c) else {
                continue;
            };
            let osculates =
                !curvature_allows(self.model, element, s, r * (1.0 + OSCULATING_REL_RADIUS));
            if (osculates || intruder == Some(g) || !on_circle(hit.point))
                && best.as_ref().is_none_or(|b| hit.distance < b.0)
            {
                best = Some((hit.distance, element, hit.point, osculates));
            }
        }
        match best {
            Some((_, element, touch, osculates)) => DegenerateEnd::Meets {
                element,
                touch: touch.to_array(),
                osculates,
            },
            None => DegenerateEnd::open(
                DegenerateOpen::NoToucher,
                "its ball stops being empty, but no other element touches it",
            ),
        }
    }

    /// Where a touch point left edge `seg` at the end of its arc onto a face of the edge that
    /// the ball `x` osculates there (its radius of curvature towards the ball is `r`: a
    /// circle's axis reaching the centre of a sphere through the circle, the ball now that
    /// sphere), the curve ends meeting that face. `None` otherwise.
    fn osculated_past(&self, seg: Element, x: &DVector<f64>) -> Option<DegenerateEnd> {
        let Element::Edge(e) = seg else {
            return None;
        };
        let (c, r) = (v3(x), x[3]);
        self.model.edges[e].faces.iter().find_map(|&g| {
            let hit = self.boundary.nearest_on_face(
                self.model,
                g,
                c,
                None,
                r + 2.0 * self.opts.accuracy,
            )?;
            let element = Element::Face(g);
            let s = [hit.uv.0, hit.uv.1];
            (!curvature_allows(self.model, element, s, r * (1.0 + OSCULATING_REL_RADIUS))).then(
                || DegenerateEnd::Meets {
                    element,
                    touch: hit.point.to_array(),
                    osculates: true,
                },
            )
        })
    }

    /// How a curve whose ball shrinks to nothing past `x` ends: at the vertex of its
    /// segments' faces nearest the centre, within reach of the ball.
    fn vanishes(&self, sys: &MedialSystem, x: &DVector<f64>) -> DegenerateEnd {
        let c = v3(x);
        let reach = x[3] + 2.0 * self.opts.accuracy;
        let nearest = sys
            .segments
            .iter()
            .flat_map(|&s| s.faces(self.model))
            .flat_map(|f| Element::Face(f).vertices(self.model))
            .map(|v| (v, self.model.vertices[v].point.distance(c)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((vertex, dist)) if dist <= reach => DegenerateEnd::Vanishes { vertex },
            _ => DegenerateEnd::open(
                DegenerateOpen::ZeroRadiusAwayFromVertex,
                "r reached 0 with no vertex within reach",
            ),
        }
    }
}

impl Degenerate {
    /// Appends ball `x` (unknowns `[B, r, s_a, s_b]` touching `segments`) with its two touch
    /// points.
    fn push(&mut self, model: &Model, segments: [Element; 2], x: &DVector<f64>) {
        self.balls.push([x[0], x[1], x[2], x[3]]);
        let at = |i: usize| {
            sys_point(model, segments[i], slot(x, i)).map_or([f64::NAN; 3], |p| p.to_array())
        };
        self.touch.push([at(0), at(1)]);
    }
}

/// The corrected ball of a failed step, where it has one.
fn fail_ball(f: &StepFail) -> Option<&DVector<f64>> {
    match f {
        StepFail::NotEmpty { ball, .. }
        | StepFail::Vanished { ball }
        | StepFail::Left { ball, .. } => Some(ball),
        StepFail::Other(..) => None,
    }
}

/// Whether two failed steps ran into the same event (the same face, the same segment left).
fn same_failure(a: &StepFail, b: &StepFail) -> bool {
    match (a, b) {
        (StepFail::NotEmpty { face: f, .. }, StepFail::NotEmpty { face: g, .. }) => f == g,
        (StepFail::Vanished { .. }, StepFail::Vanished { .. }) => true,
        (
            StepFail::Left {
                seg: s, which: i, ..
            },
            StepFail::Left {
                seg: t, which: j, ..
            },
        ) => s == t && i == j,
        _ => false,
    }
}
