//! The balls of a medial axis checked against the definition, one by one (see the parent
//! module for the checks).

use super::outcome::{nan_max, Verification};
use crate::geom::{Boundary, FaceHit};
use crate::medial::axis::{DegenerateEnd, Junction, MedialAxis, Seam, SeamEnd};
use crate::model::{Element, Model};
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

/// How many separate places `touch` holds, at separation `s`: the most touch points that
/// are pairwise farther apart than `s`. Counting in the order given undercounts: with three
/// touch points in a row 0.9·s apart, the middle one is within `s` of both others, and
/// those two are separate places.
pub fn places(touch: &[DVec3], s: f64) -> usize {
    places_where(touch.len(), &|i, j| touch[i].distance(touch[j]) > s)
}

/// The most of `n` touch points that are pairwise separate places by `separate(i, j)`
/// (`i < j`). A search over subsets, bounded by [`PLACES_SEARCH_STEPS`]: past it, the
/// largest set found so far (never more places than there are).
fn places_where(n: usize, separate: &dyn Fn(usize, usize) -> bool) -> usize {
    fn grow(
        n: usize,
        separate: &dyn Fn(usize, usize) -> bool,
        chosen: &mut Vec<usize>,
        from: usize,
        best: &mut usize,
        steps: &mut usize,
    ) {
        *best = (*best).max(chosen.len());
        for i in from..n {
            // Not even every point left would make more than the best.
            if chosen.len() + (n - i) <= *best || *steps == 0 {
                return;
            }
            *steps -= 1;
            if chosen.iter().all(|&j| separate(j, i)) {
                chosen.push(i);
                grow(n, separate, chosen, i + 1, best, steps);
                chosen.pop();
            }
        }
    }
    let mut best = 0;
    let mut steps = PLACES_SEARCH_STEPS;
    grow(n, separate, &mut vec![], 0, &mut best, &mut steps);
    best
}

/// The finest error a ball's separation is taken at (mm), however exact the ball: the
/// checkers' own distances vouch for no less (OpenCASCADE's extrema are exact to 1e-7 mm).
pub const FINEST_SEPARATION_ACCURACY: f64 = 1e-7;
/// The same relative to the part's diagonal: double precision over a large part.
pub const FINEST_SEPARATION_REL_DIAGONAL: f64 = 1e-9;

/// Samples of an edge between two touch points at which [`Checker::curls_round`] looks for
/// the edge bending round the ball.
const CURL_SAMPLES: usize = 8;

/// Most subsets [`places`] tries: far more than the few touch points of a ball need.
const PLACES_SEARCH_STEPS: usize = 100_000;

/// Places seam point `k` of `s` must touch: [`SEAM_PLACES`], or 2 at an end at a curvature
/// limit or a pinch.
pub fn seam_places(s: &Seam, k: usize) -> usize {
    let end = match k {
        0 => s.ends.first(),
        _ if k + 1 == s.points.len() => s.ends.last(),
        _ => None,
    };
    match end {
        Some(SeamEnd::CurvatureLimit { .. }) => CURVATURE_END_PLACES,
        Some(SeamEnd::Pinch { .. }) => PINCH_END_PLACES,
        _ => SEAM_PLACES,
    }
}

/// How much coarser than the accuracy the tracer takes it when it marks balls unresolved, so
/// that a checker whose tolerance is a little coarser (OpenCASCADE's adds 1e-7 mm) counts no
/// fewer places than it: a ball marked unresolved may still make enough places, and then
/// passes as any other.
const UNRESOLVED_MARGIN: f64 = 1.1;

/// The points of seam `s` whose touch points make fewer separate places than a seam point
/// needs at the accuracy (`r > a`; with [`UNRESOLVED_MARGIN`]): the accuracy cannot resolve
/// their third contact. Where two faces meet at a shallow crease, or a sliver face lies
/// between two edges, the touch points on them near the crease come closer than `√(8·r·a)`;
/// towards a curvature limit or a pinch two touch points do.
pub fn unresolved_points(s: &Seam, accuracy: f64) -> Vec<usize> {
    let coarser = UNRESOLVED_MARGIN * accuracy;
    s.points
        .iter()
        .enumerate()
        .filter(|(k, p)| {
            let r = p.point[3];
            let touch: Vec<DVec3> = p.touch.iter().map(|t| DVec3::from_array(*t)).collect();
            r > accuracy && places(&touch, separation(r, coarser)) < seam_places(s, *k)
        })
        .map(|(k, _)| k)
        .collect()
}

/// True when every two touch points closer than `sep` lie on two different faces that meet
/// (share a vertex: a shallow crease, a sliver face between two edges) and not on the same
/// faces (not both on one edge), or on one face where `same_ok` allows it (a face of the
/// element at which the seam ends at its curvature limit or a pinch): the geometry explains
/// why the accuracy cannot resolve them. `faces[i]`: the faces within the accuracy of touch
/// point `i` (found from the geometry, not from the elements a report names).
fn shortfall_explained(
    model: &Model,
    touch: &[DVec3],
    faces: &[Vec<usize>],
    sep: f64,
    same_ok: &dyn Fn(usize) -> bool,
) -> bool {
    let meet = |f: usize, g: usize| {
        let vf = Element::Face(f).vertices(model);
        f != g
            && Element::Face(g)
                .vertices(model)
                .iter()
                .any(|v| vf.contains(v))
    };
    // Not on the same faces (two touch points on one edge are one place there), and on two
    // faces that meet.
    let across = |i: usize, j: usize| {
        let same =
            faces[i].len() == faces[j].len() && faces[i].iter().all(|f| faces[j].contains(f));
        !same
            && faces[i]
                .iter()
                .any(|&f| faces[j].iter().any(|&g| meet(f, g)))
    };
    (0..touch.len()).all(|i| {
        (i + 1..touch.len()).all(|j| {
            touch[i].distance(touch[j]) > sep
                || across(i, j)
                || faces[i].iter().any(|f| faces[j].contains(f) && same_ok(*f))
        })
    })
}

/// True when each touch point can be given a face of its own among those it lies on
/// (`faces[i]`) for which `allowed` holds, no face given twice.
fn distinct_faces(faces: &[Vec<usize>], allowed: &dyn Fn(usize) -> bool) -> bool {
    fn assign(
        faces: &[Vec<usize>],
        used: &mut Vec<usize>,
        allowed: &dyn Fn(usize) -> bool,
    ) -> bool {
        let Some((first, rest)) = faces.split_first() else {
            return true;
        };
        first.iter().any(|&f| {
            if used.contains(&f) || !allowed(f) {
                return false;
            }
            used.push(f);
            let ok = assign(rest, used, allowed);
            used.pop();
            ok
        })
    }
    assign(faces, &mut Vec::with_capacity(faces.len()), allowed)
}

/// True when junction `j`'s touch points make fewer than [`JUNCTION_PLACES`] separate places
/// at the accuracy (`r > a`; with [`UNRESOLVED_MARGIN`]).
pub fn junction_unresolved(j: &Junction, accuracy: f64) -> bool {
    let touch: Vec<DVec3> = j.touch.iter().map(|t| DVec3::from_array(*t)).collect();
    let coarser = UNRESOLVED_MARGIN * accuracy;
    j.radius > accuracy && places(&touch, separation(j.radius, coarser)) < JUNCTION_PLACES
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
    /// For a ball marked unresolved: the places it needs then (one fewer than `places`), and
    /// the faces on which one face may hold two touch points closer than the separation.
    unresolved: Option<(usize, &'a dyn Fn(usize) -> bool)>,
    /// The convex vertices the seam of a seam point ends at: in such a vertex's corner (every
    /// touch point on a face of it) a ball marked unresolved may make one place.
    corners: &'a [usize],
}

/// Checks every seam point, junction, skeletal-edge ball and degenerate ball of `axis`.
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
        largest_gap: model.faces.iter().map(|f| f.gap_mm()).fold(0.0, f64::max),
    };
    for s in &axis.seams {
        // Two touch points on the same faces only where the seam ends at a curvature limit or
        // a pinch there (on that element, or a face it bounds): they merge towards that end.
        let at_limit = |f: usize| {
            let on = |e: &Element| match *e {
                Element::Face(g) => g == f,
                Element::Edge(g) => model.edges.get(g).is_some_and(|e| e.faces.contains(&f)),
                Element::Vertex(v) => Element::Face(f).vertices(model).contains(&v),
            };
            s.ends.iter().any(|end| match end {
                SeamEnd::CurvatureLimit { segment } => on(segment),
                SeamEnd::Pinch { segments, vertex } => {
                    segments.iter().any(on) || on(&Element::Vertex(*vertex))
                }
                _ => false,
            })
        };
        let corners: Vec<usize> = s
            .ends
            .iter()
            .filter_map(|e| match e {
                SeamEnd::Vertex(c) => Some(*c),
                _ => None,
            })
            .collect();
        for (k, p) in s.points.iter().enumerate() {
            let at = || format!("seam {} point {k}", s.id);
            let ball = Ball {
                at: &at,
                solid: s.solid,
                centre: [p.point[0], p.point[1], p.point[2]],
                r: p.point[3],
                touch: &p.touch,
                places: seam_places(s, k),
                unresolved: s
                    .unresolved
                    .contains(&k)
                    .then_some((CURVATURE_END_PLACES, &at_limit as &dyn Fn(usize) -> bool)),
                corners: &corners,
            };
            checker.check(&ball, v);
        }
    }
    for j in &axis.junctions {
        let at = || format!("junction {}", j.id);
        let never = |_: usize| false;
        let ball = Ball {
            at: &at,
            solid: j.solid,
            centre: j.point,
            r: j.radius,
            touch: &j.touch,
            places: JUNCTION_PLACES,
            unresolved: j
                .unresolved
                .then_some((JUNCTION_PLACES - 1, &never as &dyn Fn(usize) -> bool)),
            corners: &[],
        };
        checker.check(&ball, v);
    }
    for k in &axis.skeletal_edges {
        let vertex = model.vertices.get(k.vertex).map(|v| v.point.to_array());
        let touch: Vec<[f64; 3]> = vertex.into_iter().collect();
        for (i, b) in k.balls.iter().enumerate() {
            let at = || format!("skeletal edge {} ball {i}", k.id);
            let ball = Ball {
                at: &at,
                solid: k.solid,
                centre: [b[0], b[1], b[2]],
                r: b[3],
                touch: &touch,
                places: SKELETAL_PLACES,
                unresolved: None,
                corners: &[],
            };
            checker.check(&ball, v);
        }
    }
    for (i, d) in axis.degenerate.iter().enumerate() {
        // The ball at an end where the arc of contact shrinks to a vertex touches there only.
        let shrinks = |end: usize| {
            matches!(d.ends.get(end), Some(DegenerateEnd::Shrinks { .. })) && d.ends.len() == 2
        };
        let last = d.balls.len().saturating_sub(1);
        for (k, b) in d.balls.iter().enumerate() {
            let at = || format!("degenerate {i} ball {k}");
            let touch: &[[f64; 3]] = d.touch.get(k).map_or(&[], |t| &t[..]);
            let at_shrunk_end = (k == 0 && shrinks(0)) || (k == last && shrinks(1));
            let ball = Ball {
                at: &at,
                solid: d.solid,
                centre: [b[0], b[1], b[2]],
                r: b[3],
                touch,
                places: if at_shrunk_end {
                    SHRUNK_END_PLACES
                } else {
                    DEGENERATE_PLACES
                },
                unresolved: None,
                corners: &[],
            };
            checker.check(&ball, v);
        }
    }
}

/// Places the ball at a degenerate curve's end where its arc of contact shrinks to a vertex
/// touches: that vertex alone (`degenerate_ends` holds it to the ball osculating the face
/// there).
pub const SHRUNK_END_PLACES: usize = 1;

/// Places a skeletal edge's ball at a vertex touches: that vertex alone (it is the limit of
/// the sheet's balls, whose two touch points meet there; `distance` holds it to the rest).
pub const SKELETAL_PLACES: usize = 1;

struct Checker<'a> {
    model: &'a Model,
    boundary: &'a Boundary,
    accuracy: f64,
    /// The largest [`Face::gap_mm`](crate::model::Face::gap_mm) of the model.
    largest_gap: f64,
}

/// Most faces [`Checker::gap_near`] looks at around one point.
const GAP_FACES_NEAR: usize = 8;

impl Checker<'_> {
    /// The largest gap between the surface and the edges of a face of `solid` within `reach`
    /// plus the model's largest gap and the accuracy of `p` (0 when the file has no gap
    /// beyond the accuracy):
    /// where an exporter wrote edges that follow one face and not the other, the boundary
    /// there is defined only to that gap, and an error within it is the file's, not the
    /// ball's.
    fn gap_near(&self, solid: usize, p: DVec3, reach: f64) -> f64 {
        if self.largest_gap <= self.accuracy {
            return 0.0;
        }
        let reach = reach + self.largest_gap + self.accuracy;
        self.faces_within(solid, p, reach, GAP_FACES_NEAR)
            .into_iter()
            .map(|f| self.model.faces[f].gap_mm())
            .fold(0.0, f64::max)
    }

    /// `error` ≤ the accuracy, or ≤ the accuracy plus the file's gap near `p` (`reach` as
    /// in [`Self::gap_near`]), which is then counted in `v`.
    fn within(&self, error: f64, solid: usize, p: DVec3, reach: f64, v: &mut Verification) -> bool {
        if error <= self.accuracy {
            return true;
        }
        let gap = self.gap_near(solid, p, reach);
        let ok = gap > self.accuracy && error <= self.accuracy + gap;
        if ok {
            v.held_to_gap += 1;
            v.largest_gap_held = v.largest_gap_held.max(error);
        }
        ok
    }

    /// The distance from `p` to the boundary of `solid`.
    fn distance(&self, solid: usize, p: DVec3) -> f64 {
        self.nearest(solid, p)
            .map_or(f64::INFINITY, |(_, h)| h.distance)
    }

    /// The nearest point of `solid`'s boundary to `p`: its face and the hit.
    fn nearest(&self, solid: usize, p: DVec3) -> Option<(usize, FaceHit)> {
        self.boundary
            .nearest_face_where(self.model, p, |f| self.model.solid_of_face(f) == solid)
    }

    /// The faces of `solid` within the accuracy of `p` (at most four: a point on an edge is on
    /// two faces, at a vertex on more); for a point on none within a file's gap, the faces
    /// next to it on whose surfaces it lies.
    fn faces_near(&self, solid: usize, p: DVec3) -> Vec<usize> {
        let mut found = self.faces_within(solid, p, self.accuracy, 4);
        // On none, where the file has a gap there: the faces on whose surface `p` lies, next
        // to a face within the gap. The corner of two surfaces, one of which the edge between
        // them does not follow, is off the other face's trim by the gap over the sine of
        // their angle, and a touch point there is on that face's surface, not on its trim.
        if found.is_empty() {
            let gap = self.gap_near(solid, p, 0.0);
            if gap <= self.accuracy {
                return found;
            }
            for f in self.faces_within(solid, p, self.accuracy + gap, 4) {
                for g in self.model.faces_next_to(f) {
                    if found.len() < 4 && !found.contains(&g) && self.on_surface(g, p) {
                        found.push(g);
                    }
                }
            }
        }
        found
    }

    /// The edges of `solid` within the accuracy of `p` (those of the faces it is on), each
    /// with the parameter of `p`'s foot on it.
    fn edges_near(&self, solid: usize, p: DVec3) -> Vec<(usize, f64)> {
        let mut found: Vec<(usize, f64)> = vec![];
        for f in self.faces_within(solid, p, self.accuracy, 4) {
            for oe in self.model.faces[f].loops.iter().flat_map(|l| &l.edges) {
                if found.iter().any(|&(e, _)| e == oe.edge) {
                    continue;
                }
                let (t, _, d) = crate::geom::nearest_on_edge(self.model, oe.edge, p, None);
                if d <= self.accuracy {
                    found.push((oe.edge, t));
                }
            }
        }
        found
    }

    /// True when edge `e` curls round the ball centred at `c` somewhere between its
    /// parameters `t0` and `t1` (both included): there `½‖c − C(t)‖²`, whose minima along the
    /// edge are its touch points, has second derivative `‖C′‖² − (c − C)·C″` at most what
    /// the accuracy of `c` allows (`a·‖C″‖`): the edge bends round the ball as tightly as the
    /// ball, towards its centre, so that the distance along it has a maximum between two
    /// touch points or is constant. Two touch points on it there are two places however
    /// close; along an edge that bends less (a straight one, or one curving away) one touch
    /// point cannot pass for two. Between the parameters directly, not round a closed edge's
    /// seam.
    fn curls_round(&self, e: usize, t0: f64, t1: f64, c: DVec3) -> bool {
        let curve = &self.model.edges[e].curve;
        (0..=CURL_SAMPLES).any(|k| {
            let t = t0 + (t1 - t0) * k as f64 / CURL_SAMPLES as f64;
            let d = crate::geom::eval_curve(curve, t);
            d.d1.length_squared() - (c - d.p).dot(d.d2) <= self.accuracy * d.d2.length()
        })
    }

    /// True when `p` is within the accuracy of face `f`'s surface (untrimmed).
    fn on_surface(&self, f: usize, p: DVec3) -> bool {
        let surface = &self.model.faces[f].surface;
        crate::geom::project_point(surface, p, None).is_some_and(|(u, v)| {
            crate::geom::eval::surface_point(surface, u, v).distance(p) <= self.accuracy
        })
    }

    /// `d`, or the distance from `b` of a curved face of `solid` that two of the ball's touch
    /// points lie on, where it comes nearer between them: descended from the nearest of the
    /// points on the straight line between their parameters
    /// ([`crate::geom::nearest_sample_between`]), as the tracer looks for a junction there.
    /// Where a face's curvature wanders, the distance from the centre has several basins
    /// about as deep (two touch points are two of them), and the nearest-point search may
    /// settle in a touched one while a third, between them, is nearer: on a B-spline round
    /// taken from the Voron Revo mount, 26 balls of two seams poked into it by up to 5e-4 mm and
    /// passed (`samples/trace/long_block_with_a_wavy_round.step`).
    /// `feet` are the touch points' nearest boundary points ([`Self::nearest`]).
    fn bulge_between(
        &self,
        b: DVec3,
        touch: &[DVec3],
        feet: &[Option<(usize, FaceHit)>],
        d: f64,
    ) -> f64 {
        let model = self.model;
        let mut best = d;
        for (i, (&ti, foot)) in touch.iter().zip(feet).enumerate() {
            let Some((f, hi)) = foot else {
                continue;
            };
            let (f, hi) = (*f, hi);
            let surface = &model.faces[f].surface;
            if hi.distance > self.accuracy
                || hi.on != Element::Face(f)
                || crate::geom::project::plane_frame(surface).is_some()
            {
                continue;
            }
            for &tj in &touch[i + 1..] {
                if tj.distance(ti) <= self.accuracy {
                    continue;
                }
                let Some(hj) =
                    self.boundary
                        .nearest_on_face(model, f, tj, Some(hi.uv), self.accuracy)
                else {
                    continue;
                };
                let start = crate::geom::nearest_sample_between(surface, b, hi.uv, hj.uv);
                if let Some(h) =
                    start.and_then(|s| self.boundary.nearest_on_face(model, f, b, Some(s), best))
                {
                    best = h.distance;
                }
            }
        }
        best
    }

    /// The faces of `solid` within `reach` of `p`, nearest first (at most `most`).
    fn faces_within(&self, solid: usize, p: DVec3, reach: f64, most: usize) -> Vec<usize> {
        let mut found: Vec<usize> = vec![];
        while found.len() < most {
            let next = self.boundary.nearest_face_where(self.model, p, |f| {
                self.model.solid_of_face(f) == solid && !found.contains(&f)
            });
            match next {
                Some((f, h)) if h.distance <= reach => found.push(f),
                _ => break,
            }
        }
        found
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
        let touch: Vec<DVec3> = ball.touch.iter().map(|t| DVec3::from_array(*t)).collect();
        let feet: Vec<_> = touch.iter().map(|t| self.nearest(ball.solid, *t)).collect();
        let d = self.bulge_between(b, &touch, &feet, self.distance(ball.solid, b));
        let e = (d - r).abs();
        // The ball's own error: its distance's and its touch points' (off the ball, off the
        // boundary), for the separation below.
        let mut own_error = e;
        v.worst_distance_error = nan_max(v.worst_distance_error, e);
        let ok = self.within(e, ball.solid, b, r, v);
        v.record("distance", ok, || {
            format!("{}: nearest boundary at {d:.9e}, r = {r:.9e}", at())
        });
        for (t, foot) in touch.iter().zip(&feet) {
            let off = foot.as_ref().map_or(f64::INFINITY, |(_, h)| h.distance);
            own_error = nan_max(own_error, off);
            v.worst_touch_off_boundary = nan_max(v.worst_touch_off_boundary, off);
            let ok = self.within(off, ball.solid, *t, 0.0, v);
            v.record("touch_on_boundary", ok, || {
                format!("{}: touch point {t} is {off:.3e} mm off the boundary", at())
            });
            let e = (t.distance(b) - r).abs();
            own_error = nan_max(own_error, e);
            v.worst_touch_error = nan_max(v.worst_touch_error, e);
            let ok = self.within(e, ball.solid, *t, 0.0, v);
            v.record("touch_at_radius", ok, || {
                format!(
                    "{}: touch point {t} at {:.9e} from the centre, r = {r:.9e}",
                    at(),
                    t.distance(b)
                )
            });
        }
        if !point_ball {
            // The chord at the ball's own error where that is finer than the accuracy: a
            // touch point as close to another on one smooth contact would be farther off the
            // ball than that error (by at least chord²/(8·r), short of osculation).
            let finest = FINEST_SEPARATION_ACCURACY
                .max(FINEST_SEPARATION_REL_DIAGONAL * self.model.diagonal());
            let s = separation(r, own_error.clamp(finest, a.max(finest)));
            let mut n = places(&touch, s);
            if n < ball.places {
                // Closer than the separation but on one edge that curls round the ball between
                // them: two places the chord cannot tell apart, and the curve's second
                // derivative can.
                let edges: Vec<Vec<(usize, f64)>> = touch
                    .iter()
                    .map(|t| self.edges_near(ball.solid, *t))
                    .collect();
                n = places_where(touch.len(), &|i, j| {
                    touch[i].distance(touch[j]) > s
                        || edges[i].iter().any(|&(e, ti)| {
                            edges[j]
                                .iter()
                                .any(|&(g, tj)| g == e && self.curls_round(e, ti, tj, b))
                        })
                });
            }
            // A ball marked unresolved may touch one place fewer, where its touch points
            // closer than the separation are on elements that meet (or on a face at the
            // seam's curvature limit). In the corner of the convex vertex its seam ends at,
            // each touch point on a face of that vertex and no two on the same one, it may
            // touch one place: there the touch points converge on the vertex, as the radius
            // does on 0, faster than the separation `√(8·r·a)` does where the faces meet at
            // shallow angles (the ball of r = 0 at the vertex is exempt for the same reason).
            let ok = n >= ball.places
                || ball.unresolved.is_some_and(|(fewer, same_ok)| {
                    let faces: Vec<Vec<usize>> = touch
                        .iter()
                        .map(|t| self.faces_near(ball.solid, *t))
                        .collect();
                    let in_corner = ball.corners.iter().any(|&c| {
                        distinct_faces(&faces, &|f| {
                            Element::Face(f).vertices(self.model).contains(&c)
                        })
                    });
                    in_corner
                        || (n >= fewer
                            && shortfall_explained(self.model, &touch, &faces, s, same_ok))
                });
            v.record("separated", ok, || {
                let why = match ball.unresolved {
                    Some((fewer, _)) if n < fewer => "",
                    Some(_) => {
                        ": marked unresolved, but the touch points closer than that are on \
                         elements that do not meet"
                    }
                    None => "",
                };
                format!(
                    "{}: touches {n} separate places (farther apart than {s:.3e} mm), needs \
                     {}{why}",
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
        // The middle one within the separation of both ends, which are not: two places, in
        // any order.
        assert_eq!(places(&[p(0.9), p(0.0), p(1.8)], 1.0), 2);
        assert_eq!(places(&[p(0.0), p(0.9), p(1.8)], 1.0), 2);
        // Many points one place apart along a line: every other one.
        let row: Vec<DVec3> = (0..40).map(|i| p(0.6 * i as f64)).collect();
        assert_eq!(places(&row, 1.0), 20);
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
