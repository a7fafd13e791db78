//! IGES curves into truck curves, in model space (mm).
//!
//! The types are those the STEP reader produces: 110 lines, 100 circular arcs, 104 conic
//! arcs, 126 rational B-splines and 102 composites of them.
//!
//! A curve comes with its parameter interval from its start to its end as the entity defines
//! them (110 line: [0, 1]; 100 arc and 104 ellipse: an angle interval from the start point
//! counter-clockwise to the end point; 126: [V0, V1]), in model space (mm).

use super::ctx::Ctx;
use super::format::DirEntry;
use super::placement::{p3, scaled};
use super::segment::Segment;
use crate::error::Result;
use crate::ingest::transform::{apply, mat_mul, placed, Mat4};
use glam::DVec3;
use std::f64::consts::PI;
use truck_geometry::prelude::{
    BSplineCurve, KnotVec, Line, Matrix4, NurbsCurve, Point3, Processor, TrimmedCurve, UnitCircle,
    Vector4,
};
use truck_stepio::r#in::alias::{Conic3D, Curve3D};

impl Ctx<'_> {
    /// The curve of entity `de` as one segment, in model space (mm); `outer` are the
    /// transformations of the entities it is used in (see [`Ctx::place`]). A 102 composite of
    /// more than one piece is refused (see [`Ctx::segments`]).
    pub fn curve(&self, de: usize, from: usize, outer: &Mat4) -> Result<Segment> {
        let e = self.entry(de, from)?;
        let m = self.place(outer, e)?;
        match e.entity_type {
            110 => {
                let r = self.reals(e, 0, 6, "end points")?;
                let a = apply(&m, DVec3::new(r[0], r[1], r[2]));
                let b = apply(&m, DVec3::new(r[3], r[4], r[5]));
                if a.distance(b) <= 0.0 {
                    return Err(self.err(de, "line of zero length"));
                }
                Ok(Segment {
                    de,
                    curve: Curve3D::Line(Line(p3(a), p3(b))),
                    range: (0.0, 1.0),
                })
            }
            100 => {
                let r = self.reals(e, 0, 7, "ZT, centre, start and end")?;
                let (zt, c, s, t) = (r[0], (r[1], r[2]), (r[3], r[4]), (r[5], r[6]));
                let rs = (s.0 - c.0).hypot(s.1 - c.1);
                let re = (t.0 - c.0).hypot(t.1 - c.1);
                if rs <= 0.0 || (rs - re).abs() > 1e-6 * rs.max(re) + 1e-9 {
                    return Err(self.err(
                        de,
                        format!("start and end are at different distances from the centre ({rs} and {re})"),
                    ));
                }
                let a0 = (s.1 - c.1).atan2(s.0 - c.0);
                let a1 = (t.1 - c.1).atan2(t.0 - c.0);
                let sweep = counter_clockwise_sweep(a0, a1);
                let local = mat_mul(
                    &[
                        [1.0, 0.0, 0.0, c.0],
                        [0.0, 1.0, 0.0, c.1],
                        [0.0, 0.0, 1.0, zt],
                        [0.0, 0.0, 0.0, 1.0],
                    ],
                    &scaled(&rot_z(a0), rs, rs, rs),
                );
                Ok(Segment {
                    de,
                    curve: unit_circle(&mat_mul(&m, &local)),
                    range: (0.0, sweep),
                })
            }
            104 => {
                let r = self.reals(e, 0, 11, "coefficients, ZT, start and end")?;
                let (curve, range) = conic(&r, e.form).map_err(|why| self.err(de, why))?;
                Ok(Segment {
                    de,
                    curve: placed(curve, &m),
                    range,
                })
            }
            126 => {
                let (curve, range) = self.bspline_curve(e)?;
                Ok(Segment {
                    de,
                    curve: placed(curve, &m),
                    range,
                })
            }
            102 => {
                let mut segs = self.segments(de, from, outer)?;
                if segs.len() == 1 {
                    Ok(segs.remove(0))
                } else {
                    Err(self.err(
                        de,
                        format!(
                            "composite curve of {} pieces where one edge curve is expected",
                            segs.len()
                        ),
                    ))
                }
            }
            t => Err(self.err(
                de,
                format!(
                    "curve entity type {t} is not supported (supported: 100, 102, 104, 110, 126)"
                ),
            )),
        }
    }

    /// A curve split into its pieces: a 102 composite gives its members (recursively, in
    /// order), anything else itself.
    pub fn segments(&self, de: usize, from: usize, outer: &Mat4) -> Result<Vec<Segment>> {
        self.segments_at_depth(de, from, outer, 0)
    }

    fn segments_at_depth(
        &self,
        de: usize,
        from: usize,
        outer: &Mat4,
        depth: usize,
    ) -> Result<Vec<Segment>> {
        /// Composites nested deeper than this are taken for a cycle.
        const MAX_COMPOSITE_NESTING: usize = 16;
        let e = self.entry(de, from)?;
        if e.entity_type != 102 {
            return Ok(vec![self.curve(de, from, outer)?]);
        }
        if depth > MAX_COMPOSITE_NESTING {
            return Err(self.err(de, "composite curves nested too deep (a cycle?)"));
        }
        let n = self.count(e, 0, "number of curves")?;
        let m = mat_mul(outer, &self.transform_chain(e)?);
        let mut out = Vec::new();
        for k in 0..n {
            let c = self.ptr(e, 1 + k, "member curve")?;
            out.extend(self.segments_at_depth(c, de, &m, depth + 1)?);
        }
        Ok(out)
    }

    fn bspline_curve(&self, e: &DirEntry) -> Result<(Curve3D, (f64, f64))> {
        let de = e.de;
        let k = self.count(e, 0, "K (upper index)")?;
        let deg = self.count(e, 1, "M (degree)")?;
        if deg == 0 {
            return Err(self.err(de, "degree 0"));
        }
        let polynomial = self.int(e, 4, "PROP3")? == 1;
        let nk = k + deg + 2;
        let base = 6;
        let knots = self.reals(e, base, nk, "knots")?;
        let weights = self.reals(e, base + nk, k + 1, "weights")?;
        let pts = self.reals(e, base + nk + k + 1, 3 * (k + 1), "control points")?;
        let v = self.reals(e, base + nk + 4 * (k + 1), 2, "V0, V1")?;
        check_knots(&knots).map_err(|r| self.err(de, r))?;
        if weights.iter().any(|w| *w <= 0.0) {
            return Err(self.err(de, "weights must be positive"));
        }
        let mut v = [v[0], v[1]];
        if v[0] == v[1] {
            // An empty range ([0, 0] from some writers): the curve's own, between the
            // degree-th knot from each end.
            v = [knots[deg], knots[nk - 1 - deg]];
            self.warn(
                "range",
                de,
                "126 curve with an empty parameter range (V0 = V1)",
                "the knots' range used",
            );
        }
        if v[0] >= v[1]
            || v[0].is_nan()
            || v[1].is_nan()
            || v[0] < knots[0] - 1e-12
            || v[1] > knots[nk - 1] + 1e-12
        {
            return Err(self.err(
                de,
                format!("parameter range [{}, {}] outside the knots", v[0], v[1]),
            ));
        }
        let kv = KnotVec::from(knots);
        let rational = !polynomial
            && weights
                .iter()
                .any(|w| (w - weights[0]).abs() > SAME_WEIGHT_REL_FIRST * weights[0]);
        let curve = if rational {
            let cps: Vec<Vector4> = (0..=k)
                .map(|i| {
                    let w = weights[i];
                    Vector4::new(pts[3 * i] * w, pts[3 * i + 1] * w, pts[3 * i + 2] * w, w)
                })
                .collect();
            Curve3D::NurbsCurve(NurbsCurve::new(
                BSplineCurve::try_new(kv, cps).map_err(|x| self.err(de, x.to_string()))?,
            ))
        } else {
            let cps: Vec<Point3> = (0..=k)
                .map(|i| Point3::new(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]))
                .collect();
            Curve3D::BSplineCurve(
                BSplineCurve::try_new(kv, cps).map_err(|x| self.err(de, x.to_string()))?,
            )
        };
        Ok((curve, (v[0], v[1])))
    }
}

/// An angle sweep within this of nothing or of a full turn is a full turn: start = end up to
/// rounding.
const FULL_TURN_SLACK_RAD: f64 = 1e-9;

/// The angle from `a0` counter-clockwise to `a1`, in (0, 2π]: a full turn when they are the
/// same angle (up to [`FULL_TURN_SLACK_RAD`]).
fn counter_clockwise_sweep(a0: f64, a1: f64) -> f64 {
    let sweep = (a1 - a0).rem_euclid(2.0 * PI);
    if !(FULL_TURN_SLACK_RAD..=2.0 * PI - FULL_TURN_SLACK_RAD).contains(&sweep) {
        2.0 * PI
    } else {
        sweep
    }
}

/// Weights differing from the first by at most this, relative to the first, are all the
/// same: the B-spline is polynomial, not rational.
pub const SAME_WEIGHT_REL_FIRST: f64 = 1e-14;

/// An error when the knots are not sorted or span nothing.
pub fn check_knots(k: &[f64]) -> std::result::Result<(), String> {
    if k.windows(2).any(|w| w[1] < w[0]) {
        return Err("knots are not in non-decreasing order".into());
    }
    if k.first() == k.last() {
        return Err("knot vector has zero length".into());
    }
    Ok(())
}

/// A 104 conic arc in standard position (`A x² + C y² + F = 0`, or `A x² + E y = 0` /
/// `C y² + D x = 0` for a parabola) at height ZT, from its start to its end point, as a
/// truck curve in its definition space with its parameter interval (increasing). Ellipses run
/// counter-clockwise from start to end (a full ellipse when they coincide); hyperbola and
/// parabola arcs run from start to end along the branch.
fn conic(r: &[f64], form: i64) -> std::result::Result<(Curve3D, (f64, f64)), String> {
    let (a, b, c, d, e, f, zt) = (r[0], r[1], r[2], r[3], r[4], r[5], r[6]);
    let (x1, y1, x2, y2) = (r[7], r[8], r[9], r[10]);
    let big = [a, b, c, d, e, f]
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let zero = |x: f64| x.abs() <= 1e-9 * big;
    if big == 0.0 || !zero(b) {
        return Err("conic not in standard position (B must be 0)".into());
    }
    // Local 2D matrix applied to truck's unit curve, then the curve's parameters at the ends.
    let frame2 = |l: [[f64; 2]; 2]| -> Mat4 {
        [
            [l[0][0], l[0][1], 0.0, 0.0],
            [l[1][0], l[1][1], 0.0, 0.0],
            [0.0, 0.0, 1.0, zt],
            [0.0, 0.0, 0.0, 1.0],
        ]
    };
    // Reversed parameter for the odd unit coordinate: negate the second column, t → −t.
    let increasing = |mut l: [[f64; 2]; 2], t0: f64, t1: f64| {
        if t1 >= t0 {
            (l, (t0, t1))
        } else {
            l[0][1] = -l[0][1];
            l[1][1] = -l[1][1];
            (l, (-t0, -t1))
        }
    };
    match form {
        1 => {
            if !(zero(d) && zero(e)) {
                return Err("ellipse not in standard position (B, D, E must be 0)".into());
            }
            if !(a * f < 0.0 && c * f < 0.0) {
                return Err("coefficients do not describe a real ellipse".into());
            }
            let (sa, sb) = ((-f / a).sqrt(), (-f / c).sqrt());
            let t0 = (y1 / sb).atan2(x1 / sa);
            let t1 = (y2 / sb).atan2(x2 / sa);
            let sweep = counter_clockwise_sweep(t0, t1);
            let local = mat_mul(
                &scaled(&frame2([[1.0, 0.0], [0.0, 1.0]]), sa, sb, sa.min(sb)),
                &rot_z(t0),
            );
            Ok((unit_circle(&local), (0.0, sweep)))
        }
        2 => {
            if !(zero(d) && zero(e)) || zero(a) || zero(c) || zero(f) || a * c >= 0.0 {
                return Err("hyperbola not in standard position (A x² + C y² + F = 0)".into());
            }
            let (l, t0, t1) = if a * f < 0.0 {
                // Transverse axis x: (±p cosh t, q sinh t).
                let (p, q) = ((-f / a).sqrt(), (f / c).sqrt());
                let sx = if x1 < 0.0 { -1.0 } else { 1.0 };
                (
                    [[sx * p, 0.0], [0.0, q]],
                    (y1 / q).asinh(),
                    (y2 / q).asinh(),
                )
            } else {
                // Transverse axis y: (p sinh t, ±q cosh t).
                let (p, q) = ((f / a).sqrt(), (-f / c).sqrt());
                let sy = if y1 < 0.0 { -1.0 } else { 1.0 };
                (
                    [[0.0, p], [sy * q, 0.0]],
                    (x1 / p).asinh(),
                    (x2 / p).asinh(),
                )
            };
            let (l, range) = increasing(l, t0, t1);
            let h: truck_stepio::r#in::alias::Hyperbola<Point3, Matrix4> = Processor::new(
                TrimmedCurve::new(truck_geometry::prelude::UnitHyperbola::new(), range),
            );
            Ok((
                Curve3D::Conic(Conic3D::Hyperbola(placed(h, &frame2(l)))),
                range,
            ))
        }
        3 => {
            // Unit parabola (t², 2t).
            let (l, t0, t1) = if zero(c) && zero(d) && zero(f) && !zero(a) && !zero(e) {
                // y = k x²: (2t, 4k t²), t = x / 2.
                let k = -a / e;
                ([[0.0, 1.0], [4.0 * k, 0.0]], x1 / 2.0, x2 / 2.0)
            } else if zero(a) && zero(e) && zero(f) && !zero(c) && !zero(d) {
                // x = k y²: (4k t², 2t), t = y / 2.
                let k = -c / d;
                ([[4.0 * k, 0.0], [0.0, 1.0]], y1 / 2.0, y2 / 2.0)
            } else {
                return Err(
                    "parabola not in standard position (A x² + E y = 0 or C y² + D x = 0)".into(),
                );
            };
            let (l, range) = increasing(l, t0, t1);
            let q: truck_stepio::r#in::alias::Parabola<Point3, Matrix4> = Processor::new(
                TrimmedCurve::new(truck_geometry::prelude::UnitParabola::new(), range),
            );
            Ok((
                Curve3D::Conic(Conic3D::Parabola(placed(q, &frame2(l)))),
                range,
            ))
        }
        f => Err(format!(
            "conic form {f} (1 ellipse, 2 hyperbola, 3 parabola)"
        )),
    }
}

fn rot_z(a: f64) -> Mat4 {
    let (s, c) = a.sin_cos();
    [
        [c, -s, 0.0, 0.0],
        [s, c, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// truck's unit circle `(cos t, sin t, 0)` moved by `m`.
fn unit_circle(m: &Mat4) -> Curve3D {
    let c: Processor<TrimmedCurve<UnitCircle<Point3>>, Matrix4> =
        Processor::new(TrimmedCurve::new(UnitCircle::new(), (0.0, 2.0 * PI)));
    Curve3D::Conic(Conic3D::Ellipse(placed(c, m)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ingest::iges::ctx::with_ctx;
    use crate::ingest::transform::IDENTITY;
    use glam::DVec3;
    use truck_geometry::prelude::ParametricCurve;

    const TOL: f64 = 1e-9;

    fn point(c: &Curve3D, t: f64) -> DVec3 {
        let p = c.subs(t);
        DVec3::new(p.x, p.y, p.z)
    }

    #[test]
    fn arc_with_chained_transforms() {
        // DE 1: arc in its XY plane at ZT = 2, centre (1, 0), from (3, 0) to (1, 2) (a quarter,
        // counter-clockwise), radius 2; DE 3: rotate 90° about x; DE 5: translate by (0, 0, 10),
        // applied after DE 3.
        let e = [
            (100, 0, 3, "2.,1.,0.,3.,0.,1.,2."),
            (124, 0, 5, "1.,0.,0.,0.,0.,0.,-1.,0.,0.,1.,0.,0."),
            (124, 0, 0, "1.,0.,0.,0.,0.,1.,0.,0.,0.,0.,1.,10."),
        ];
        with_ctx(&e, 2, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            // (x, y, z) → rotation about x: (x, −z, y), then + (0, 0, 10).
            let map = |p: DVec3| DVec3::new(p.x, -p.z, p.y + 10.0);
            assert!(s.start().distance(map(DVec3::new(3.0, 0.0, 2.0))) < TOL);
            assert!(s.end().distance(map(DVec3::new(1.0, 2.0, 2.0))) < TOL);
            let mid = s.at_fraction(0.5);
            let want = map(DVec3::new(1.0 + 2.0_f64.sqrt(), 2.0_f64.sqrt(), 2.0));
            assert!(mid.distance(want) < TOL, "{mid} vs {want}");
            assert!((s.range.1 - s.range.0 - std::f64::consts::FRAC_PI_2).abs() < TOL);
        });
        // Start = end: a full circle.
        with_ctx(&[(100, 0, 0, "0.,0.,0.,1.,0.,1.,0.")], 2, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            assert!((s.range.1 - s.range.0 - std::f64::consts::TAU).abs() < TOL);
            assert!(s.at_fraction(0.5).distance(DVec3::new(-1.0, 0.0, 0.0)) < TOL);
        });
    }

    #[test]
    fn conic_arcs() {
        // x²/16 + y²/4 − 1 = 0 at ZT = 1, from (4, 0) counter-clockwise to (0, 2).
        let e = [(104, 1, 0, "0.0625,0.,0.25,0.,0.,-1.,1.,4.,0.,0.,2.")];
        with_ctx(&e, 2, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            assert!(s.start().distance(DVec3::new(4.0, 0.0, 1.0)) < TOL);
            assert!(s.end().distance(DVec3::new(0.0, 2.0, 1.0)) < TOL);
            for k in 0..=8 {
                let p = s.at_fraction(k as f64 / 8.0);
                let g = p.x * p.x / 16.0 + p.y * p.y / 4.0 - 1.0;
                assert!(g.abs() < TOL && (p.z - 1.0).abs() < TOL && p.x >= -TOL && p.y >= -TOL);
            }
        });
        // Hyperbola x² − y² = 1 (A = 1, C = −1, F = −1) from (cosh 0.5, −sinh 0.5) to
        // (cosh 1, sinh 1); and the left branch run downwards.
        let (c05, s05, c1, s1) = (0.5f64.cosh(), 0.5f64.sinh(), 1f64.cosh(), 1f64.sinh());
        for (x1, y1, x2, y2) in [(c05, -s05, c1, s1), (-c1, s1, -c05, -s05)] {
            let params = format!("1.,0.,-1.,0.,0.,-1.,0.,{x1},{y1},{x2},{y2}");
            let e = [(104, 2, 0, params.as_str())];
            with_ctx(&e, 2, |ctx| {
                let s = ctx.curve(1, 1, &IDENTITY).unwrap();
                assert!(
                    s.start().distance(DVec3::new(x1, y1, 0.0)) < TOL,
                    "{}",
                    s.start()
                );
                assert!(
                    s.end().distance(DVec3::new(x2, y2, 0.0)) < TOL,
                    "{}",
                    s.end()
                );
                for k in 0..=8 {
                    let p = s.at_fraction(k as f64 / 8.0);
                    assert!(
                        (p.x * p.x - p.y * p.y - 1.0).abs() < TOL && p.x * x1 > 0.0,
                        "{p}"
                    );
                }
            });
        }
        // Parabola y = x²/4 (A = 1, E = −4) from x = 2 to x = −1 at ZT = 3.
        let e = [(104, 3, 0, "1.,0.,0.,0.,-4.,0.,3.,2.,1.,-1.,0.25")];
        with_ctx(&e, 2, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            assert!(
                s.start().distance(DVec3::new(2.0, 1.0, 3.0)) < TOL,
                "{}",
                s.start()
            );
            assert!(
                s.end().distance(DVec3::new(-1.0, 0.25, 3.0)) < TOL,
                "{}",
                s.end()
            );
            let p = s.at_fraction(0.5);
            assert!(
                (p.y - p.x * p.x / 4.0).abs() < TOL && (p.z - 3.0).abs() < TOL,
                "{p}"
            );
        });
        // Out of standard position: refused with a message naming the entity.
        let e = [(104, 2, 0, "1.,0.5,-1.,0.,0.,-1.,0.,1.,0.,2.,1.732")];
        with_ctx(&e, 2, |ctx| {
            let msg = ctx.curve(1, 1, &IDENTITY).unwrap_err().to_string();
            assert!(msg.contains("DE 1 (entity 104, conic arc)"), "{msg}");
            assert!(msg.contains("standard position"), "{msg}");
        });
    }

    #[test]
    fn rational_bspline_curve_quarter_circle() {
        // Degree 2, three control points (1,0,0) (1,1,0) (0,1,0), weights 1, √½, 1: exactly a
        // quarter of the unit circle.
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let params = format!(
            "2,2,1,0,0,0,0.,0.,0.,1.,1.,1.,1.,{w},1.,1.,0.,0.,1.,1.,0.,0.,1.,0.,0.,1.,0.,0.,1."
        );
        let e = [(126, 0, 0, params.as_str())];
        with_ctx(&e, 10, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            assert!(matches!(s.curve, Curve3D::NurbsCurve(_)));
            for k in 0..=10 {
                // Unit flag 10: centimetres, so the radius is 10 mm.
                let p = point(&s.curve, k as f64 / 10.0);
                assert!((p.length() - 10.0).abs() < TOL, "{p}");
            }
        });
    }
}
