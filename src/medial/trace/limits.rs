//! Curvature limits of a march: where the ball osculates a touched segment (its curvature
//! criterion fails at a touch point, or two touch points on one element meet), located on the
//! step that passed it, and the osculating ball itself solved for where the system is too
//! near singular for the steps to reach it.

use super::march::March;
use super::options::MERGED_TOUCH_REL_RADIUS;
use super::tracer::Tracer;
use super::unknowns::{slot, v3};
use crate::medial::axis::{OpenReason, SeamEnd};
use crate::medial::equations::MedialSystem;
use crate::medial::maximal::{bending, curvature_allows};
use crate::medial::solver::{solve, SolveStatus};
use crate::model::Element;
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// A seam whose step underflows next to a ball with `r·κ` this close to 1 on a touched
/// segment ends at that segment's curvature limit, solved for, when it lies within this
/// times `r` of the last point (see `osculating_near`).
const NEAR_OSCULATION: f64 = 1e-2;

/// The relative step of the central differences of `r·κ` in `osculating_near`.
const OSCULATION_DIFF_STEP: f64 = 1e-6;

/// The knot values of a surface's parameters, in u and in v: a B-spline or NURBS surface's
/// knot vectors; an extrusion's or revolution's of a B-spline or NURBS profile, the profile's
/// in u (none in v). `None` for a surface with no knots.
fn knot_lines(surface: &crate::model::Surface) -> Option<(Vec<f64>, Vec<f64>)> {
    use truck_stepio::r#in::alias::{Curve3D, SweptCurve};
    if let Some((u, v)) = crate::geom::knot_vectors(surface) {
        return Some((u.iter().copied().collect(), v.iter().copied().collect()));
    }
    let crate::model::Surface::SweptCurve(s) = surface else {
        return None;
    };
    let curve = match s.as_ref() {
        SweptCurve::ExtrudedCurve(e) => e.entity_curve(),
        SweptCurve::RevolutedCurve(r) => r.entity().entity_curve(),
    };
    let k = match curve {
        Curve3D::BSplineCurve(c) => c.knot_vec(),
        Curve3D::NurbsCurve(c) => c.knot_vec(),
        _ => return None,
    };
    Some((k.iter().copied().collect(), vec![]))
}

impl Tracer<'_> {
    /// True when the ball of seam point `x` osculates its `i`-th segment to the accuracy:
    /// the segment's radius of curvature towards the ball at the touch point (see
    /// [`bending`]) is at most `r` plus the accuracy.
    pub(super) fn osculates(&self, triplet: &[Element; 3], i: usize, x: &DVector<f64>) -> bool {
        bending(self.model, triplet[i], slot(x, i))
            .is_some_and(|k| k > 0.0 && k.is_finite() && 1.0 / k <= x[3] + self.opts.accuracy)
    }

    /// The ball near the seam point `x` of `sys` (in solid `solid`) that osculates one of its
    /// touched segments `i` exactly (`r·κ = 1`, `κ` the segment's bending towards the ball,
    /// [`bending`]), when the ball at `x` already nearly does (`r·κ` within
    /// [`NEAR_OSCULATION`] of 1): the seam's system with the osculation equation as its last
    /// row, solved by Newton from `x`. It must lie within [`NEAR_OSCULATION`]·`r` of `x`,
    /// touch every segment on it, and be empty. (Near that ball the system is singular — the touch point on `i` moves like the
    /// square root of the centre's travel — and steps towards it fail short of it by more
    /// than the accuracy: a reflex B-spline edge on the extruder motor plate stopped at
    /// `r·κ = 0.99994`, 1.25 accuracies short.)
    pub(super) fn osculating_near(
        &mut self,
        sys: &MedialSystem,
        solid: usize,
        x: &DVector<f64>,
    ) -> Option<(usize, DVector<f64>)> {
        let model = self.model;
        let rk = |y: &DVector<f64>, i: usize| {
            bending(model, sys.segments[i], slot(y, i)).map(|k| y[3] * k)
        };
        let i = (0..3)
            .filter_map(|i| rk(x, i).map(|v| (i, v)))
            .filter(|&(_, v)| (v - 1.0).abs() <= NEAR_OSCULATION)
            .max_by(|a, b| a.1.total_cmp(&b.1))?
            .0;
        let eval = |y: &DVector<f64>| {
            let (f, j) = sys.eval(model, y)?;
            let n = y.len();
            let mut fa = DVector::zeros(n);
            fa.rows_mut(0, n - 1).copy_from(&f);
            fa[n - 1] = rk(y, i)? - 1.0;
            let mut ja = DMatrix::zeros(n, n);
            ja.rows_mut(0, n - 1).copy_from(&j);
            // r·κ depends on r and on the touch point's own parameters only: central
            // differences there.
            for k in [3, 4 + 2 * i, 5 + 2 * i] {
                let d = OSCULATION_DIFF_STEP * y[k].abs().max(1.0);
                let (mut a, mut b) = (y.clone(), y.clone());
                a[k] += d;
                b[k] -= d;
                ja[(n - 1, k)] = (rk(&a, i)? - rk(&b, i)?) / (2.0 * d);
            }
            Some((fa, ja))
        };
        let sol = solve(eval, x.clone(), &self.solve_opts());
        self.stats.newton_iterations += sol.iterations;
        let y = sol.x;
        let ok = sol.status == SolveStatus::Converged
            && y[3] > 0.0
            && v3(&y).distance(v3(x)) <= NEAR_OSCULATION * x[3]
            && (0..3).all(|k| self.on_segment(sys.segments[k], slot(&y, k)))
            && self.ball_is_empty(solid, &y);
        ok.then_some((i, y))
    }

    /// The ball where two touch points of seam point `x` on one B-spline face, closing in on
    /// a knot line between them along which the face's curvature towards the ball peaks,
    /// meet: the knot line is then the ridge (a cubic's curvature is continuous across a
    /// knot, its derivative not, so the ridge is no zero of a derivative for Newton to find)
    /// and the ball osculates the face on it. Solved for with the third segment: the centre,
    /// `r`, the parameter along the knot line and the third touch point, from the face's and
    /// the third segment's contact equations and `r·κ = 1` on the knot line. The ball must
    /// lie within a tenth of `r` of `x`, touch both segments on them, and be empty; returned
    /// as a point of `sys` (both touch points on the face at the meeting), with the face's
    /// first slot.
    pub(super) fn merged_at_knot(
        &mut self,
        sys: &MedialSystem,
        solid: usize,
        x: &DVector<f64>,
    ) -> Option<(usize, DVector<f64>)> {
        let model = self.model;
        let (i, k) = [(0, 1), (0, 2), (1, 2)].into_iter().find(|&(i, k)| {
            sys.segments[i] == sys.segments[k] && matches!(sys.segments[i], Element::Face(_))
        })?;
        let Element::Face(f) = sys.segments[i] else {
            return None;
        };
        let j = 3 - i - k;
        let face = &model.faces[f];
        let (ku, kv) = knot_lines(&face.surface)?;
        let (ku, kv) = (&ku, &kv);
        let (a, b) = (slot(x, i), slot(x, k));
        let seg = sys.segments[i];
        let kappa = |s: [f64; 2]| bending(model, seg, s).filter(|v| v.is_finite());
        let (ka, kb) = (kappa(a)?, kappa(b)?);
        // The knot lines strictly between the two touch points, in u (d = 0) and in v (d = 1),
        // each with the curvature where the segment between the two crosses it.
        let mut best: Option<(usize, f64, f64, f64)> = None;
        for (d, knots) in [(0, ku), (1, kv)] {
            let (lo, hi) = (a[d].min(b[d]), a[d].max(b[d]));
            let mut last = f64::NAN;
            for &t in knots.iter() {
                if t <= lo || t >= hi || t == last {
                    continue;
                }
                last = t;
                let w = (t - a[d]) / (b[d] - a[d]);
                let o = a[1 - d] + w * (b[1 - d] - a[1 - d]);
                let mut s = [0.0; 2];
                s[d] = t;
                s[1 - d] = o;
                let Some(kt) = kappa(s) else { continue };
                if kt > ka.max(kb) && best.is_none_or(|bb| kt > bb.3) {
                    best = Some((d, t, o, kt));
                }
            }
        }
        let (d, t, o, _) = best?;
        // Unknowns: centre, r, the parameter along the knot line, the third touch point.
        let pair = MedialSystem::new(vec![seg, sys.segments[j]]);
        let full = |y: &DVector<f64>| {
            let mut z = DVector::zeros(8);
            z.rows_mut(0, 4).copy_from(&y.rows(0, 4));
            z[4 + d] = t;
            z[5 - d] = y[4];
            z[6] = y[5];
            z[7] = y[6];
            z
        };
        let eval = |y: &DVector<f64>| {
            let z = full(y);
            let (f6, j8) = pair.eval(model, &z)?;
            let mut fa = DVector::zeros(7);
            fa.rows_mut(0, 6).copy_from(&f6);
            let rk = |z: &DVector<f64>| kappa([z[4], z[5]]).map(|v| z[3] * v);
            fa[6] = rk(&z)? - 1.0;
            let mut ja = DMatrix::zeros(7, 7);
            for row in 0..6 {
                for (col, from) in [(0, 0), (1, 1), (2, 2), (3, 3), (4, 5 - d), (5, 6), (6, 7)] {
                    ja[(row, col)] = j8[(row, from)];
                }
            }
            for (col, from) in [(3, 3), (4, 5 - d)] {
                let h = OSCULATION_DIFF_STEP * z[from].abs().max(1.0);
                let (mut p, mut m) = (z.clone(), z.clone());
                p[from] += h;
                m[from] -= h;
                ja[(6, col)] = (rk(&p)? - rk(&m)?) / (2.0 * h);
            }
            Some((fa, ja))
        };
        let mut y0 = DVector::zeros(7);
        y0.rows_mut(0, 4).copy_from(&x.rows(0, 4));
        y0[4] = o;
        y0[5] = x[4 + 2 * j];
        y0[6] = x[5 + 2 * j];
        let sol = solve(eval, y0, &self.solve_opts());
        self.stats.newton_iterations += sol.iterations;
        let z = full(&sol.x);
        let mut out = x.clone();
        out.rows_mut(0, 4).copy_from(&z.rows(0, 4));
        for slot_k in [i, k] {
            out[4 + 2 * slot_k] = z[4];
            out[5 + 2 * slot_k] = z[5];
        }
        out[4 + 2 * j] = z[6];
        out[5 + 2 * j] = z[7];
        let ok = sol.status == SolveStatus::Converged
            && out[3] > 0.0
            && v3(&out).distance(v3(x)) <= 0.1 * x[3]
            && self.on_segment(seg, slot(&out, i))
            && self.on_segment(sys.segments[j], slot(&out, j))
            && self.ball_is_empty(solid, &out);
        ok.then_some((i, out))
    }

    /// The seam's end at the curvature limit of an element touched twice, when the two touch
    /// points had met or passed through each other between the last point and the hand-over's
    /// crossing `xc`: the limit comes first, located as after an ordinary step.
    pub(super) fn limit_before_crossing(
        &mut self,
        m: &mut March,
        xc: &DVector<f64>,
    ) -> Option<SeamEnd> {
        let before = self.touches(&m.triplet, &m.x);
        (0..3)
            .any(|k| self.merged_with(&m.triplet, &before, xc, k).is_some())
            .then(|| self.curvature_end(m, xc))
            .flatten()
    }

    /// The curvature limit of a segment that the ball of the crossing `xc`, on the march's
    /// step, pokes through (its radius of curvature towards the ball there below `r`): the
    /// limit came first, within the step (see `poked_end`).
    pub(super) fn limit_within_step(
        &mut self,
        m: &mut March,
        xc: &DVector<f64>,
    ) -> Option<SeamEnd> {
        let i =
            (0..3).find(|&i| !curvature_allows(self.model, m.triplet[i], slot(xc, i), xc[3]))?;
        let before = self.touches(&m.triplet, &m.x);
        // Up to the crossing only: past it the old system's balls touch the segment left
        // beyond its border, where the criterion says nothing.
        let reach = m.t.rows(0, 3).dot(&(xc - &m.x).rows(0, 3));
        Some(self.poked_end(m, &before, i, reach))
    }

    /// True when the march's step to `xn` is too long to locate the curvature limit it
    /// passes: its ball pokes through a touched segment (or two touch points on one have met
    /// or passed through each other), the step is longer than twice the accuracy, and the
    /// last ball before the poke along it (see `poked_end`) is not near osculating that
    /// segment (`r·κ` at every touch point on it more than [`NEAR_OSCULATION`] below 1). A
    /// shorter step then follows the seam on towards the limit. (Where two touch points on one
    /// face close in on the ridge between them, they move like the square root of the
    /// centre's travel, and a long step's corrector lands on balls tangent at one point twice
    /// over instead: on the Revo hotend mount, a step from r 0.332 landed on such a ball, the
    /// balls along it did from r 0.312 on, and the seam ended there, 0.05 short of the
    /// ridge's centre of curvature, r 0.264.) Where the limit is a jump of the curvature (at a
    /// B-spline's knot, or a joint of two edges) no ball short of it nearly osculates: the
    /// steps shrink to the accuracy, and the limit is located from there.
    pub(super) fn step_past_limit_too_long(&mut self, m: &March, xn: &DVector<f64>) -> bool {
        if 0.5 * m.h < self.opts.accuracy || self.coincident(&m.triplet, xn, false) {
            return false;
        }
        let before = self.touches(&m.triplet, &m.x);
        let Some(i) = self.poked(&m.triplet, &before, xn) else {
            return false;
        };
        let model = self.model;
        let near = |y: &DVector<f64>| {
            (0..3).filter(|&k| m.triplet[k] == m.triplet[i]).any(|k| {
                bending(model, m.triplet[k], slot(y, k))
                    .is_some_and(|b| b * y[3] >= 1.0 - NEAR_OSCULATION)
            })
        };
        if near(&m.x) {
            return false;
        }
        let last = self.last_on_step(m, m.h, |t, xm| t.poked(&m.triplet, &before, xm).is_none());
        !last.is_some_and(|xm| near(&xm))
    }

    /// The curvature criterion at `xn`: the ball must not poke through a touched face. Where
    /// the ball touches a face twice, the two touch points must not meet (or pass through
    /// each other): where they meet the ball osculates the face, `r·κmax = 1`, and the seam
    /// ends at that centre of curvature, located by bisection to the accuracy. Before that,
    /// two different elements touched at one place (where a face meets its edge) end the
    /// march open: the ball touches fewer than three places there.
    pub(super) fn curvature_end(&mut self, m: &mut March, xn: &DVector<f64>) -> Option<SeamEnd> {
        let before = self.touches(&m.triplet, &m.x);
        if self.coincident(&m.triplet, xn, false) {
            if let Some(end) = self.end_in_pinch(m, xn) {
                return Some(end);
            }
            // Two touch points on elements of one tangent-continuous group (B-spline edges
            // running on from each other at a vertex, as on OCCT's sample sink) meet: the
            // ball osculates that group's curve or surface there, its curvature limit, as
            // where two touch points on one element meet (see `merged_end`).
            let at = self.touches(&m.triplet, xn);
            let merged = [(0, 1), (0, 2), (1, 2)].into_iter().find(|&(i, k)| {
                m.triplet[i] != m.triplet[k]
                    && self.groups.of(m.triplet[i]) == self.groups.of(m.triplet[k])
                    && matches!((at[i], at[k]), (Some(a), Some(b))
                        if a.distance(b) <= MERGED_TOUCH_REL_RADIUS * xn[3])
            });
            if let Some((i, k)) = merged {
                // The step may have passed the meeting: past it the corrector converges to
                // balls tangent at one point twice over (any ball tangent at the meeting
                // point satisfies both rows there), which are no seam points. On OCCT's
                // sample sink it lands there; on an elliptic boss in halves, a step from
                // r 2.76 landed at r 2.36 on the split line, 0.2 mm short of the centre of
                // curvature (r 2.5) where the seam ends. The meeting, bisected on the step
                // to the accuracy, as `poked`'s is below, and solved for where it is
                // nearly osculating.
                let end = self.merge_before(m, xn);
                m.points.push(self.seam_point(&m.sys, &end));
                // The curve or surface that curves: not a vertex joining two edges.
                let segment = match m.triplet[i] {
                    Element::Vertex(_) => m.triplet[k],
                    e => e,
                };
                return Some(SeamEnd::CurvatureLimit { segment });
            }
            return Some(SeamEnd::Open(OpenReason::TouchPointsCoincide));
        }
        let i = self.poked(&m.triplet, &before, xn)?;
        let h = m.h;
        Some(self.poked_end(m, &before, i, h))
    }

    /// The march's end at the curvature limit of its `i`-th segment, poked (or met twice)
    /// within the first `reach` of its step: the last ball there that is not, located as
    /// `curvature_end` says, pushed as the march's last point.
    fn poked_end(
        &mut self,
        m: &mut March,
        before: &[Option<DVec3>; 3],
        i: usize,
        reach: f64,
    ) -> SeamEnd {
        // Bisect the arclength from x to where the ball osculates, to the accuracy. The ball
        // must also be empty there: where a face's curvature peaks beside the touch point
        // (a B-spline's ridge), the ball passes through the face near the touch point
        // before the curvature at the touch point reaches 1/r.
        let last = self.last_on_step(m, reach, |t, xm| t.poked(&m.triplet, before, xm).is_none());
        // The bisection on the centre's travel leaves the end short of the osculating ball by
        // up to ten accuracies there (the ball's contact changes like the square root of the
        // travel): the osculating ball itself, where it is solved for from there.
        let last = last.map(|xm| match self.osculating_near(&m.sys, m.solid, &xm) {
            Some((k, y)) if m.triplet[k] == m.triplet[i] => y,
            _ => match self.merged_at_knot(&m.sys, m.solid, &xm) {
                Some((k, y)) if m.triplet[k] == m.triplet[i] => y,
                _ => xm,
            },
        });
        // No ball on the step short of the poke (the system too near singular past the march's
        // point): two touch points closing in on a knot line where the curvature peaks may
        // still meet beyond it.
        let last = last.or_else(|| {
            let x = m.x.clone();
            self.merged_at_knot(&m.sys, m.solid, &x)
                .filter(|&(k, _)| m.triplet[k] == m.triplet[i])
                .map(|(_, y)| y)
        });
        if let Some(xm) = last {
            m.points.push(self.seam_point(&m.sys, &xm));
        }
        SeamEnd::CurvatureLimit {
            segment: m.triplet[i],
        }
    }

    /// Where the step from the march's point to `xn`, whose touch points on two elements of
    /// one group have met, first has them met: the last ball with them apart, by bisection
    /// of the step to the accuracy (each ball empty), then the osculating ball near it where
    /// there is one; `xn` where no shorter step has them apart.
    fn merge_before(&mut self, m: &March, xn: &DVector<f64>) -> DVector<f64> {
        let last = self.last_on_step(m, m.h, |t, xm| !t.coincident(&m.triplet, xm, false));
        // Where no shorter step has them apart (the march's point was within a step of the
        // meeting), the osculating ball is solved for from the step's end.
        let from = last.unwrap_or_else(|| xn.clone());
        match self.osculating_near(&m.sys, m.solid, &from) {
            Some((_, y)) => y,
            None => from,
        }
    }

    /// The farthest ball along the march's step (from its point, up to `reach` of centre
    /// travel) that is `still` so and empty, by bisection of the step to the accuracy; `None`
    /// where no shorter step gives one.
    fn last_on_step(
        &mut self,
        m: &March,
        reach: f64,
        still: impl Fn(&Self, &DVector<f64>) -> bool,
    ) -> Option<DVector<f64>> {
        let (mut lo, mut hi) = (0.0, reach);
        let mut last = None;
        while hi - lo > self.opts.accuracy {
            let mid = 0.5 * (lo + hi);
            match self.centre_step(&m.sys, &m.x, &m.t, mid) {
                Some(xm) if still(self, &xm) && self.ball_is_empty(m.solid, &xm) => {
                    lo = mid;
                    last = Some(xm);
                }
                _ => hi = mid,
            }
        }
        last
    }

    /// The first touch point of `y` where the ball pokes through its face, or where two
    /// touch points on one face (at `before` on the last point) have met or passed through
    /// each other.
    fn poked(
        &self,
        triplet: &[Element; 3],
        before: &[Option<DVec3>; 3],
        y: &DVector<f64>,
    ) -> Option<usize> {
        (0..3).find(|&i| {
            !curvature_allows(self.model, triplet[i], slot(y, i), y[3])
                || self.merged_with(triplet, before, y, i).is_some()
        })
    }
}
