//! The balls of a medial axis checked against the definition, one by one (see the parent
//! module for the checks).

use super::outcome::{nan_max, Verification};
use crate::geom::Boundary;
use crate::medial::axis::{MedialAxis, SeamEnd};
use crate::model::Model;
use glam::DVec3;

/// Places a seam point's ball touches (three nearest elements).
pub const SEAM_PLACES: usize = 3;
/// Places a seam point's ball touches where the seam ends at a curvature limit: there two
/// touch points on one face have merged as the ball osculates it.
pub const CURVATURE_END_PLACES: usize = 2;
/// Places a seam point's ball touches where the seam ends at a pinch: there two touch points
/// on different elements have met at a vertex.
pub const PINCH_END_PLACES: usize = 2;
/// Places a junction's ball touches (at least; a non-generic junction touches more).
pub const JUNCTION_PLACES: usize = 4;
/// Places a degenerate ball touches (at least: it touches a continuum).
pub const DEGENERATE_PLACES: usize = 2;

/// Two touch points of a ball of radius `r` are separate places when farther apart than
/// this (mm): `√(8·r·a)`, the chord of the ball over which a surface tangent to it stays
/// within the accuracy `a` of it.
pub fn separation(r: f64, accuracy: f64) -> f64 {
    (8.0 * r * accuracy).sqrt()
}

/// How many separate places `touch` holds, at separation `s`: each point farther than `s`
/// from every place counted so far is a new place.
pub fn places(touch: &[DVec3], s: f64) -> usize {
    let mut found: Vec<DVec3> = vec![];
    for t in touch {
        if found.iter().all(|q| q.distance(*t) > s) {
            found.push(*t);
        }
    }
    found.len()
}

/// One ball to check.
struct Ball<'a> {
    /// Where it is, for messages (`seam 3 point 12`).
    at: &'a dyn Fn() -> String,
    solid: usize,
    centre: [f64; 3],
    r: f64,
    touch: &'a [[f64; 3]],
    /// Separate places the touch points must make.
    places: usize,
}

/// Checks every seam point, junction and degenerate ball of `axis`.
pub(super) fn check_balls(
    model: &Model,
    boundary: &Boundary,
    axis: &MedialAxis,
    accuracy: f64,
    v: &mut Verification,
) {
    let checker = Checker {
        model,
        boundary,
        accuracy,
    };
    for s in &axis.seams {
        let last = s.points.len().saturating_sub(1);
        for (k, p) in s.points.iter().enumerate() {
            let end = match k {
                0 => Some(&s.ends[0]),
                _ if k == last => Some(&s.ends[1]),
                _ => None,
            };
            let places = match end {
                Some(SeamEnd::CurvatureLimit { .. }) => CURVATURE_END_PLACES,
                Some(SeamEnd::Pinch { .. }) => PINCH_END_PLACES,
                _ => SEAM_PLACES,
            };
            let at = || format!("seam {} point {k}", s.id);
            let ball = Ball {
                at: &at,
                solid: s.solid,
                centre: [p.point[0], p.point[1], p.point[2]],
                r: p.point[3],
                touch: &p.touch,
                places,
            };
            checker.check(&ball, v);
        }
    }
    for j in &axis.junctions {
        let at = || format!("junction {}", j.id);
        let ball = Ball {
            at: &at,
            solid: j.solid,
            centre: j.point,
            r: j.radius,
            touch: &j.touch,
            places: JUNCTION_PLACES,
        };
        checker.check(&ball, v);
    }
    for (i, d) in axis.degenerate.iter().enumerate() {
        for (k, b) in d.balls.iter().enumerate() {
            let at = || format!("degenerate {i} ball {k}");
            let touch: &[[f64; 3]] = d.touch.get(k).map_or(&[], |t| &t[..]);
            let ball = Ball {
                at: &at,
                solid: d.solid,
                centre: [b[0], b[1], b[2]],
                r: b[3],
                touch,
                places: DEGENERATE_PLACES,
            };
            checker.check(&ball, v);
        }
    }
}

struct Checker<'a> {
    model: &'a Model,
    boundary: &'a Boundary,
    accuracy: f64,
}

impl Checker<'_> {
    /// The distance from `p` to the boundary of `solid`.
    fn distance(&self, solid: usize, p: DVec3) -> f64 {
        self.boundary
            .nearest_face_where(self.model, p, |f| self.model.solid_of_face(f) == solid)
            .map_or(f64::INFINITY, |(_, h)| h.distance)
    }

    fn check(&self, ball: &Ball, v: &mut Verification) {
        let a = self.accuracy;
        let at = ball.at;
        v.balls += 1;
        let before = v.worst();
        let finite = ball.centre.iter().all(|x| x.is_finite())
            && ball.r.is_finite()
            && ball.touch.iter().flatten().all(|x| x.is_finite());
        v.record("finite", finite, || {
            format!("{}: a number is not finite", at())
        });
        if !finite {
            v.worst_distance_error = f64::NAN;
            v.worst_at = Some(at());
            return;
        }
        let b = DVec3::from_array(ball.centre);
        let r = ball.r;
        let point_ball = r <= a;
        if !point_ball {
            let inside = self
                .boundary
                .contains_point_where(self.model, b, |f| self.model.solid_of_face(f) == ball.solid);
            v.record("inside", inside, || {
                format!("{}: centre {b} is not inside solid {}", at(), ball.solid)
            });
        }
        let d = self.distance(ball.solid, b);
        let e = (d - r).abs();
        v.worst_distance_error = nan_max(v.worst_distance_error, e);
        v.record("distance", e <= a, || {
            format!("{}: nearest boundary at {d:.9e}, r = {r:.9e}", at())
        });
        let touch: Vec<DVec3> = ball.touch.iter().map(|t| DVec3::from_array(*t)).collect();
        for t in &touch {
            let off = self.distance(ball.solid, *t);
            v.worst_touch_off_boundary = nan_max(v.worst_touch_off_boundary, off);
            v.record("touch_on_boundary", off <= a, || {
                format!("{}: touch point {t} is {off:.3e} mm off the boundary", at())
            });
            let e = (t.distance(b) - r).abs();
            v.worst_touch_error = nan_max(v.worst_touch_error, e);
            v.record("touch_at_radius", e <= a, || {
                format!(
                    "{}: touch point {t} at {:.9e} from the centre, r = {r:.9e}",
                    at(),
                    t.distance(b)
                )
            });
        }
        if !point_ball {
            let s = separation(r, a);
            let n = places(&touch, s);
            v.record("separated", n >= ball.places, || {
                format!(
                    "{}: touches {n} separate places (farther apart than {s:.3e} mm), needs {}",
                    at(),
                    ball.places
                )
            });
        }
        let after = v.worst();
        if after > before || (after.is_nan() && !before.is_nan()) {
            v.worst_at = Some(at());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_are_counted_at_the_separation() {
        let p = |x: f64| DVec3::new(x, 0.0, 0.0);
        assert_eq!(places(&[], 1.0), 0);
        assert_eq!(places(&[p(0.0), p(0.5), p(0.9)], 1.0), 1);
        assert_eq!(places(&[p(0.0), p(1.5), p(3.0)], 1.0), 3);
        assert_eq!(places(&[p(0.0), p(0.0), p(2.0), p(2.1)], 1.0), 2);
        // √(8·r·a): r = 10 mm, a = 1e-4 mm → 0.0894 mm.
        assert!((separation(10.0, 1e-4) - 0.08944271909999159).abs() < 1e-15);
    }

    #[test]
    fn nan_is_never_dropped() {
        assert!(nan_max(1.0, f64::NAN).is_nan());
        assert!(nan_max(f64::NAN, 1.0).is_nan());
        assert_eq!(nan_max(1.0, 2.0), 2.0);
    }
}
