//! Inside or outside a face's trimming loops: the ray-crossing test and the prepared loops.
//!
//! A face is its surface restricted to the region its edge loops enclose in the face's
//! (unwrapped) UV space, [`Loop::uv`](crate::model::Loop::uv). [`contains`] decides
//! whether a parameter point lies in that region by casting a ray along one parameter
//! direction and looking at the loop segments it crosses (the crossing-number test, Shimrat,
//! *Algorithm 112: Position of point relative to polygon*, CACM 5(8), 1962; Haines, *Point in
//! Polygon Strategies*, Graphics Gems IV, 1994). Vertex loops (poles) bound nothing and are
//! ignored; a face with only vertex loops (a full sphere) is its whole UV domain.
//!
//! **Periodic directions.** A periodic direction is a circle: the ray is cast *across* it
//! (along the other direction), and the loop segments are tested against every copy
//! `x + k·P` of the ray's line, so the query point needs no shifting and a loop may sit
//! anywhere in the period. Copy `k` is computed as `x + k·P` for every segment alike, so a
//! loop vertex on a copy is counted once (half-open rule) even across rounding.
//!
//! **Loops that wrap around a period** (a circle bounding a cylinder's side without a seam
//! edge: the side face of a cylinder is the band between two such loops) do not enclose
//! anything on their own, so parity alone cannot tell which side is the face: a ray from a
//! point of the band crosses one circle, a ray from a point of a cone cap (one circle and
//! a vertex loop at the apex) may cross none. For such faces the decision uses the loops'
//! orientation instead: by the STEP convention a loop has the face on its left seen against
//! the face normal (`Su × Sv` when the face's `same_sense` is true, `−(Su × Sv)` otherwise),
//! i.e. counter-clockwise outer loops in UV when `same_sense` holds (checked on every sample
//! and real-world face). The first segment the ray meets tells on which side of it the query
//! lies, hence whether it is in the face. This works whatever the number of loops and also
//! when the ray's own direction is periodic (a band on a torus), where "below" has no end.
//! A side that no loop closes ends at a pole: beyond it ([`covered_domain`]; past a cone's
//! apex the surface goes on as another sheet) nothing is in the face. Faces without wrapping
//! loops use the plain even–odd rule, which does not depend on orientation at all.
//!
//! Wrapping is told as in `ingest::domain`'s loop unwrapping: the closing step from a loop's last
//! UV point back to its first is longer than half a period. The closing segment of a wrapping loop
//! is then taken to the copy of the first point nearest the last one.
//!
//! [`Trim`] prepares a face's loops for many tests (the segments bucketed by columns across
//! the ray), with the same answers as [`contains`].

use super::covered::covered_domain;
use crate::model::{Face, Loop};
use glam::{DVec2, Vec2Swizzles};

/// Relative tolerance on the UV domain in a bounded, non-periodic direction of a face with
/// only vertex loops: a parameter beyond the domain by more than this fraction of its width
/// is not on the face.
pub const DOMAIN_TOL_REL_WIDTH: f64 = 1e-9;

/// True when `uv` is inside the trimmed face (see the module docs). Allocation-free; for
/// many tests on one face, [`Trim`] does the same faster.
pub fn contains(face: &Face, uv: DVec2) -> bool {
    let Some(setup) = Setup::new(face) else {
        return in_domain(face, uv);
    };
    setup.decide(uv, segments(face, setup.swap), || {
        covered_along(face, setup.swap)
    })
}

/// The covered range ([`covered_domain`]) along the ray's direction.
fn covered_along(face: &Face, swap: bool) -> (f64, f64) {
    let (u, v) = covered_domain(face);
    if swap {
        u
    } else {
        v
    }
}

/// How a face's loops are tested (see the module docs).
#[derive(Clone, Copy, Debug)]
struct Setup {
    /// Cast the ray along u (lines `v = const`) instead of along v: only v wraps.
    swap: bool,
    /// Some loop wraps around a period: decide by orientation instead of parity.
    wraps: bool,
    /// +1 when the face is on the left of its loops in the (swapped) coordinates.
    orient: f64,
    /// Periods across the ray (`px`) and along it (`py`), in swapped coordinates.
    px: Option<f64>,
    py: Option<f64>,
    /// The domain along the ray.
    y_start: f64,
    y_end: f64,
    /// Crossings closer than this along the ray are at the same place.
    tie: f64,
}

impl Setup {
    /// `None` for a face without edge loops (the whole domain).
    fn new(face: &Face) -> Option<Setup> {
        let d = &face.domain;
        let periods = (d.u_period, d.v_period);
        let mut any = false;
        let mut wrap_u = false;
        let mut wrap_v = false;
        for l in face.loops.iter().filter(|l| is_edge_loop(l)) {
            any = true;
            let (wu, wv) = wrapping(l.outline(), periods);
            wrap_u |= wu;
            wrap_v |= wv;
        }
        if !any {
            return None;
        }
        // Cast the ray across the wrapped direction: along v unless only v wraps.
        let swap = wrap_v && !wrap_u;
        let (px, py) = if swap {
            (periods.1, periods.0)
        } else {
            (periods.0, periods.1)
        };
        // Swapping the coordinates mirrors the plane.
        let orient = if face.same_sense { 1.0 } else { -1.0 } * if swap { -1.0 } else { 1.0 };
        let (y_start, y_end) = if swap { d.u } else { d.v };
        let extent = y_end - y_start;
        Some(Setup {
            swap,
            wraps: wrap_u || wrap_v,
            orient,
            px,
            py,
            y_start,
            y_end,
            tie: SEAM_TOL_REL_PERIOD * py.unwrap_or(extent).abs().max(f64::MIN_POSITIVE),
        })
    }

    /// The decision for `uv` from the segments that may cross its ray (in swapped
    /// coordinates; any superset of the crossing ones will do). `covered` gives the range
    /// along the ray the face can reach (asked only for a point beyond its domain).
    ///
    /// Loops that wrap bound the face only on one side each: the other side reaches to a
    /// pole. Beyond the pole (past a cone's apex) the surface goes on as another sheet
    /// that is not the face, so there the orientation rule's answer is cut at the covered
    /// range.
    #[inline]
    fn decide(
        &self,
        uv: DVec2,
        segs: impl Iterator<Item = (DVec2, DVec2)>,
        covered: impl FnOnce() -> (f64, f64),
    ) -> bool {
        let q = if self.swap { uv.yx() } else { uv };
        if !self.wraps {
            return self.even_odd(q, segs);
        }
        if !self.nearest_crossing_side(q, segs) {
            return false;
        }
        if self.py.is_some() {
            return true;
        }
        let tol = DOMAIN_TOL_REL_WIDTH * (self.y_end - self.y_start).abs().max(1.0);
        if q.y >= self.y_start - tol && q.y <= self.y_end + tol {
            return true;
        }
        let (lo, hi) = covered();
        let tol = DOMAIN_TOL_REL_WIDTH * (hi - lo).abs().max(1.0);
        q.y >= lo - tol && q.y <= hi + tol
    }

    /// Even–odd rule with a ray from `q` towards decreasing `y`.
    fn even_odd(&self, q: DVec2, segs: impl Iterator<Item = (DVec2, DVec2)>) -> bool {
        // Move q into the period of the loops in the ray's direction (loops are closed there).
        let qy = match self.py {
            Some(p) => self.y_start + (q.y - self.y_start).rem_euclid(p),
            None => q.y,
        };
        let mut inside = false;
        for (a, b) in segs {
            for_each_crossing(a, b, q.x, self.px, |y, _| {
                if y < qy {
                    inside = !inside;
                }
            });
        }
        inside
    }

    /// Orientation rule for faces with wrapping loops: the nearest crossing below `q` (the
    /// first one met going down, cyclically when `y` is periodic) has the face above it iff
    /// `q` is in the face; when nothing is below, the nearest crossing above decides the
    /// other way round. Two crossings at the same place with opposite orientations are a
    /// seam (the face on both sides; a torus's loop is made of seams only): `q` is then
    /// inside.
    fn nearest_crossing_side(&self, q: DVec2, segs: impl Iterator<Item = (DVec2, DVec2)>) -> bool {
        let mut below = Nearest::default();
        let mut above = Nearest::default();
        for (a, b) in segs {
            for_each_crossing(a, b, q.x, self.px, |y, dx| {
                let face_above = dx * self.orient > 0.0;
                let (down, up) = match self.py {
                    Some(p) => {
                        let down = (q.y - y).rem_euclid(p);
                        (down, p - down)
                    }
                    None => (q.y - y, y - q.y),
                };
                if down >= 0.0 {
                    below.offer(down, face_above, self.tie);
                }
                if up > 0.0 {
                    above.offer(up, face_above, self.tie);
                }
            });
        }
        match (below.sides(), above.sides()) {
            (Some((true, true)), _) => true,
            (Some((face_above, _)), _) => face_above,
            (None, Some((true, true))) => true,
            (None, Some((face_above, _))) => !face_above,
            (None, None) => self.py.is_some(),
        }
    }
}

/// The segments of a face's edge loops, in swapped coordinates when `swap`; the closing step
/// of a wrapping loop goes to the copy of its first point next to its last.
fn segments(face: &Face, swap: bool) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
    let periods = (face.domain.u_period, face.domain.v_period);
    face.loops
        .iter()
        .filter(|l| is_edge_loop(l))
        .flat_map(move |l| {
            let poly = l.outline();
            let n = poly.len();
            let (wu, wv) = wrapping(poly, periods);
            (0..n).map(move |i| {
                let a = poly[i];
                let mut b = poly[(i + 1) % n];
                if i + 1 == n && (wu || wv) {
                    b = DVec2::new(
                        wrap_near(b.x, a.x, periods.0),
                        wrap_near(b.y, a.y, periods.1),
                    );
                }
                if swap {
                    (a.yx(), b.yx())
                } else {
                    (a, b)
                }
            })
        })
}

/// A face's trim prepared for many inside tests: the same answers as [`contains`], with the
/// loop segments bucketed by columns across the ray so that a test reads only the segments
/// that can cross its ray.
#[derive(Clone, Debug)]
pub struct Trim {
    setup: Option<Setup>,
    /// [`covered_domain`] along the ray.
    covered: (f64, f64),
    segs: Vec<(DVec2, DVec2)>,
    /// Columns `[x0 + j·w, x0 + (j + 1)·w)` across the ray (`x` reduced to one period when
    /// periodic).
    x0: f64,
    w: f64,
    cols: usize,
    col_start: Vec<u32>,
    col_items: Vec<u32>,
}

/// Segments per column of a [`Trim`], about.
pub const SEGMENTS_PER_COLUMN: usize = 2;

/// Most columns of a [`Trim`].
pub const MAX_COLUMNS: usize = 512;

impl Trim {
    /// Prepares `face`'s loops.
    pub fn new(face: &Face) -> Trim {
        let Some(setup) = Setup::new(face) else {
            return Trim {
                setup: None,
                covered: (f64::NEG_INFINITY, f64::INFINITY),
                segs: Vec::new(),
                x0: 0.0,
                w: 1.0,
                cols: 0,
                col_start: vec![0],
                col_items: Vec::new(),
            };
        };
        let segs: Vec<(DVec2, DVec2)> = segments(face, setup.swap).collect();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (a, b) in &segs {
            lo = lo.min(a.x.min(b.x));
            hi = hi.max(a.x.max(b.x));
        }
        let (x0, span) = match setup.px {
            Some(p) => (lo, p),
            None => (lo, hi - lo),
        };
        let cols = (segs.len() / SEGMENTS_PER_COLUMN).clamp(1, MAX_COLUMNS);
        let w = if span > 0.0 && span.is_finite() {
            span / cols as f64
        } else {
            1.0
        };
        let col = |x: f64| ((x - x0) / w).floor();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); cols];
        for (k, (a, b)) in segs.iter().enumerate() {
            let (sa, sb) = (a.x.min(b.x), a.x.max(b.x));
            if sa.is_nan() || sb.is_nan() || sb <= sa {
                continue; // never crosses a line across the ray
            }
            let periodic = setup.px.is_some();
            let mut add = |from: f64, to: f64| {
                // Padded by one column at both ends against rounding; around the period when
                // periodic (a query reduced to the period's end reads the first column's
                // neighbour).
                let (j0, j1) = (col(from) as i64 - 1, col(to) as i64 + 1);
                for j in j0..=j1 {
                    let j = if periodic {
                        j.rem_euclid(cols as i64)
                    } else {
                        j.clamp(0, cols as i64 - 1)
                    } as usize;
                    if lists[j].last() != Some(&(k as u32)) {
                        lists[j].push(k as u32);
                    }
                }
            };
            match setup.px {
                Some(p) if sb - sa >= p => add(x0, x0 + p),
                Some(p) => {
                    let from = x0 + (sa - x0).rem_euclid(p);
                    let to = from + (sb - sa);
                    add(from, to.min(x0 + p));
                    if to > x0 + p {
                        add(x0, to - p);
                    }
                }
                None => add(sa, sb),
            }
        }
        let mut col_start = Vec::with_capacity(cols + 1);
        let mut col_items = Vec::new();
        col_start.push(0);
        for list in lists {
            col_items.extend(list);
            col_start.push(col_items.len() as u32);
        }
        Trim {
            setup: Some(setup),
            covered: covered_along(face, setup.swap),
            segs,
            x0,
            w,
            cols,
            col_start,
            col_items,
        }
    }

    /// True when `uv` is inside the trimmed face: the answer of [`contains`]`(face, uv)`.
    /// `face` must be the face this was built from.
    #[inline]
    pub fn contains(&self, face: &Face, uv: DVec2) -> bool {
        let Some(setup) = &self.setup else {
            return in_domain(face, uv);
        };
        let x = if setup.swap { uv.y } else { uv.x };
        let x = match setup.px {
            Some(p) => self.x0 + (x - self.x0).rem_euclid(p),
            None => x,
        };
        // Columns are padded by one on each side, so a query a rounding error beyond the
        // first or last column reads that column.
        let j = ((x - self.x0) / self.w).floor();
        let items: &[u32] = if j >= -1.0 && j <= self.cols as f64 {
            let j = (j.max(0.0) as usize).min(self.cols - 1);
            &self.col_items[self.col_start[j] as usize..self.col_start[j + 1] as usize]
        } else {
            &[]
        };
        setup.decide(uv, items.iter().map(|&k| self.segs[k as usize]), || {
            self.covered
        })
    }
}

/// True for a loop that bounds a region (not a vertex loop, at least a segment).
pub(crate) fn is_edge_loop(l: &Loop) -> bool {
    l.vertex.is_none() && l.uv.len() >= 2
}

/// Whether a loop's polygon wraps around the u and v periods (mirrors `domain::wraps`).
pub(crate) fn wrapping(poly: &[DVec2], periods: (Option<f64>, Option<f64>)) -> (bool, bool) {
    if poly.len() < 2 {
        return (false, false);
    }
    let gap = poly[0] - poly[poly.len() - 1];
    let big = |g: f64, p: Option<f64>| p.is_some_and(|p| g.abs() > 0.5 * p);
    (big(gap.x, periods.0), big(gap.y, periods.1))
}

/// A face bounded only by vertex loops covers its domain; periodic directions always match.
fn in_domain(face: &Face, uv: DVec2) -> bool {
    let d = &face.domain;
    let inside = |x: f64, r: (f64, f64), p: Option<f64>| {
        p.is_some() || {
            let tol = DOMAIN_TOL_REL_WIDTH * (r.1 - r.0).abs().max(1.0);
            x >= r.0 - tol && x <= r.1 + tol
        }
    };
    inside(uv.x, d.u, d.u_period) && inside(uv.y, d.v, d.v_period)
}

/// `x` moved by a multiple of `period` to the copy nearest `reference`.
#[inline]
pub(crate) fn wrap_near(x: f64, reference: f64, period: Option<f64>) -> f64 {
    match period {
        Some(p) => x + ((reference - x) / p).round() * p,
        None => x,
    }
}

/// Calls `visit(y, dx)` for every crossing of the segment `a → b` with the lines
/// `x = c + k·P` (all `k` when `x` is periodic, `k = 0` otherwise), with `y` the crossing's
/// coordinate along the line and `dx` the segment's extent across it (its sign is the
/// direction of travel). Coordinates are already swapped so that `x` is across the ray.
/// Half-open rule: the segment crosses `x = c` when `min(a.x, b.x) ≤ c < max(a.x, b.x)`, so a
/// vertex on the line counts once.
#[inline]
fn for_each_crossing(a: DVec2, b: DVec2, c: f64, px: Option<f64>, mut visit: impl FnMut(f64, f64)) {
    let (lo, hi) = if a.x <= b.x { (a.x, b.x) } else { (b.x, a.x) };
    if lo >= hi {
        return;
    }
    let dx = b.x - a.x;
    match px {
        None => {
            if lo <= c && c < hi {
                visit(a.y + (b.y - a.y) / dx * (c - a.x), dx);
            }
        }
        Some(p) => {
            // Copy k of the line is at `c + k·p`, computed the same way for every segment, so
            // that two segments sharing a vertex on a copy see the same number and the
            // half-open rule counts the vertex once. Start one copy early against rounding.
            let mut k = ((lo - c) / p).ceil() - 1.0;
            loop {
                let ck = c + k * p;
                if ck >= hi {
                    break;
                }
                if ck >= lo {
                    visit(a.y + (b.y - a.y) / dx * (ck - a.x), dx);
                }
                k += 1.0;
            }
        }
    }
}

/// Two crossings closer than this fraction of the period (or of the domain's extent) along
/// the ray are at the same place (a seam traversed both ways).
pub const SEAM_TOL_REL_PERIOD: f64 = 1e-9;

/// The nearest crossing(s) in one direction along the ray.
#[derive(Default)]
struct Nearest {
    dist: Option<f64>,
    face_above: bool,
    face_below: bool,
}

impl Nearest {
    fn offer(&mut self, d: f64, face_above: bool, tie: f64) {
        match self.dist {
            Some(best) if d > best + tie => {}
            Some(best) if d >= best - tie => {
                self.dist = Some(best.min(d));
                self.face_above |= face_above;
                self.face_below |= !face_above;
            }
            _ => {
                self.dist = Some(d);
                self.face_above = face_above;
                self.face_below = !face_above;
            }
        }
    }

    /// `(face above, face below)` of the nearest crossing(s): `(true, true)` for a seam;
    /// for a single crossing the first flag is its side.
    fn sides(&self) -> Option<(bool, bool)> {
        self.dist.map(|_| {
            if self.face_above && self.face_below {
                (true, true)
            } else {
                (self.face_above, false)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Loop;
    use crate::testing::geometry::{face_where, uv_of};
    use crate::testing::sample;
    use glam::DVec3;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn plate_with_holes_top_face() {
        let m = sample("plate_with_holes.step");
        let top = face_where(&m, |p| (p.z - 10.0).abs() < 1e-9);
        let face = &m.faces[top];
        assert_eq!(face.loops.len(), 4, "outer loop and three holes");
        let inside = |x: f64, y: f64| contains(face, uv_of(face, DVec3::new(x, y, 10.0)));
        // Holes r = 5 at (15, 25), r = 8 at (40, 25), r = 5 at (65, 25).
        for (x, y) in [
            (15.0, 25.0),
            (40.0, 25.0),
            (65.0, 25.0),
            (19.9, 25.0),
            (40.0, 32.9),
        ] {
            assert!(!inside(x, y), "({x}, {y}) is in a hole");
        }
        for (x, y) in [
            (1.0, 1.0),
            (79.0, 49.0),
            (40.0, 33.1),
            (20.1, 25.0),
            (27.5, 25.0),
            (40.0, 5.0),
        ] {
            assert!(inside(x, y), "({x}, {y}) is on the plate");
        }
        for (x, y) in [(-1.0, 25.0), (81.0, 25.0), (40.0, -0.1), (40.0, 50.1)] {
            assert!(!inside(x, y), "({x}, {y}) is beyond the plate");
        }
    }

    #[test]
    fn cylinder_side_face_any_period() {
        let m = sample("cylinder.step");
        let side = (0..m.faces.len())
            .find(|&f| crate::geom::surface_kind(&m.faces[f].surface) == "cylinder")
            .unwrap();
        let face = &m.faces[side];
        for k in -3..=3 {
            for a in [0.0, 0.3, 1.0, PI, 5.0, TAU - 1e-6] {
                let p = DVec3::new(10.0 * a.cos(), 10.0 * a.sin(), 15.0);
                let uv = uv_of(face, p) + DVec2::new(k as f64 * TAU, 0.0);
                assert!(contains(face, uv), "angle {a} shifted {k} periods");
                for z in [-0.5, 30.5] {
                    let uv = uv_of(face, DVec3::new(p.x, p.y, z)) + DVec2::new(k as f64 * TAU, 0.0);
                    assert!(
                        !contains(face, uv),
                        "angle {a}, z = {z} is off the side face"
                    );
                }
            }
        }
    }

    /// A loop whose polygon is `n` points of `f(t)`, `t ∈ [0, 1)`.
    fn synthetic_loop(n: usize, f: impl Fn(f64) -> DVec2) -> Loop {
        Loop {
            source_id: 0,
            edges: vec![],
            vertex: None,
            uv: (0..n).map(|k| f(k as f64 / n as f64)).collect(),
            uv_counts: vec![],
            outline: vec![],
            gap_mm: 0.0,
        }
    }

    #[test]
    fn band_between_two_wrapping_circles() {
        // The cylinder's side face re-bounded like a face without a seam edge: two circle
        // loops at v = 0 (travelling +u: face above, to its left) and v = 30 (travelling −u),
        // slightly wavy so that crossings are not all at one height.
        let m = sample("cylinder.step");
        let mut face = m
            .faces
            .iter()
            .find(|f| crate::geom::surface_kind(&f.surface) == "cylinder")
            .unwrap()
            .clone();
        assert!(face.same_sense);
        let wave = |t: f64| 0.5 * (TAU * 3.0 * t).sin();
        face.loops = vec![
            synthetic_loop(40, |t| DVec2::new(1.0 + TAU * t, wave(t))),
            synthetic_loop(40, |t| DVec2::new(1.0 - TAU * t, 30.0 + wave(-t))),
        ];
        // The domain ingest::domain would give these loops: a whole period, their v extent.
        face.domain.u = (1.0, 1.0 + TAU);
        face.domain.v = (-0.5, 30.5);
        assert!(face
            .loops
            .iter()
            .all(|l| wrapping(&l.uv, (Some(TAU), None)).0));
        for k in -2..=2 {
            for u in [0.0, 0.7, 1.0, 2.5, 4.0, 6.2] {
                let u = u + k as f64 * TAU;
                let w = wave((u - 1.0) / TAU);
                // 0.05 exceeds the polygon's chordal deviation from the wave (0.014).
                assert!(
                    contains(&face, DVec2::new(u, w + 0.05)),
                    "u {u} just above the bottom"
                );
                assert!(contains(&face, DVec2::new(u, 15.0)), "u {u} mid-band");
                assert!(
                    !contains(&face, DVec2::new(u, w - 0.05)),
                    "u {u} below the band"
                );
                assert!(
                    !contains(&face, DVec2::new(u, 31.0)),
                    "u {u} above the band"
                );
            }
        }
        // A cone cap: the bottom circle alone (with a vertex loop at an apex above it).
        face.loops.truncate(1);
        face.loops.push(Loop {
            source_id: 0,
            edges: vec![],
            vertex: Some(0),
            uv: vec![DVec2::new(0.0, 40.0)],
            uv_counts: vec![],
            outline: vec![],
            gap_mm: 0.0,
        });
        face.domain.v = (-0.5, 40.0);
        assert!(contains(&face, DVec2::new(3.0, 20.0)));
        assert!(contains(&face, DVec2::new(3.0, 39.0)));
        assert!(!contains(&face, DVec2::new(3.0, -1.0)));
        // The same circle travelled the other way: the face is below it (to an apex at −40).
        face.loops[0].uv.reverse();
        face.loops[1].uv = vec![DVec2::new(0.0, -40.0)];
        face.domain.v = (-40.0, 0.5);
        assert!(!contains(&face, DVec2::new(3.0, 20.0)));
        assert!(contains(&face, DVec2::new(3.0, -1.0)));
        assert!(contains(&face, DVec2::new(3.0, -39.0)));
    }

    #[test]
    fn torus_band_and_full_torus() {
        let m = sample("torus.step");
        let full = &m.faces[0];
        for u in [-7.0, 0.0, 1.0, 3.0, 6.0, 12.0] {
            for v in [-7.0, -0.1, 0.0, 1.0, 3.0, 6.2, 9.0] {
                assert!(contains(full, DVec2::new(u, v)), "full torus at ({u}, {v})");
            }
        }
        // Band a < v < b on the torus (both directions periodic, the ray's direction too).
        let mut face = full.clone();
        let (a, b) = (2.0, 4.0);
        let o = if face.same_sense { 1.0 } else { -1.0 };
        face.loops = vec![
            synthetic_loop(24, |t| DVec2::new(o * TAU * t, a)),
            synthetic_loop(24, |t| DVec2::new(-o * TAU * t, b)),
        ];
        for k in -2..=2 {
            let shift = k as f64 * TAU;
            for u in [0.1, 2.0, 5.0] {
                assert!(contains(&face, DVec2::new(u + shift, 3.0 + shift)));
                assert!(!contains(&face, DVec2::new(u - shift, 1.0 + shift)));
                assert!(!contains(&face, DVec2::new(u, 5.0 + shift)));
                assert!(!contains(&face, DVec2::new(u, 0.0 + shift)));
            }
        }
    }

    #[test]
    fn sphere_with_only_a_vertex_loop_is_all_inside() {
        let m = sample("sphere.step");
        let face = &m.faces[0];
        assert!(face.loops.iter().all(|l| l.vertex.is_some()));
        for u in [-10.0, 0.0, 1.0, 6.0, 20.0] {
            for v in [-PI / 2.0, -1.0, 0.0, 1.5, PI / 2.0] {
                assert!(contains(face, DVec2::new(u, v)));
            }
        }
        assert!(!contains(face, DVec2::new(0.0, 2.0)), "beyond the pole");
    }

    #[test]
    fn triangle_face_of_the_tetrahedron() {
        let m = sample("tetrahedron.step");
        // The slanted face through (36,0,0), (0,28,0), (0,0,24): x/36 + y/28 + z/24 = 1.
        let (a, b, c) = (
            DVec3::new(36.0, 0.0, 0.0),
            DVec3::new(0.0, 28.0, 0.0),
            DVec3::new(0.0, 0.0, 24.0),
        );
        let on = |p: DVec3| (p.x / 36.0 + p.y / 28.0 + p.z / 24.0 - 1.0).abs() < 1e-9;
        let face = &m.faces[face_where(&m, on)];
        let at = |wa: f64, wb: f64| uv_of(face, a * wa + b * wb + c * (1.0 - wa - wb));
        assert!(contains(face, at(1.0 / 3.0, 1.0 / 3.0)), "centroid");
        assert!(contains(face, at(0.98, 0.01)), "near a corner");
        assert!(contains(face, at(0.5, 0.49)), "near an edge");
        assert!(!contains(face, at(0.5, 0.51)), "beyond an edge");
        assert!(!contains(face, at(-0.01, 0.5)), "beyond another edge");
        assert!(!contains(face, at(1.2, 0.3)), "far outside");
    }

    /// The prepared [`Trim`] answers exactly like [`contains`] on every sample face and on
    /// the synthetic wrapping faces, over the domain, beyond it and shifted by periods.
    #[test]
    fn prepared_trim_agrees_with_contains() {
        let mut faces: Vec<Face> = Vec::new();
        // The samples, and the real-world corpus when it is beside the project (its NIST
        // parts have many seamless cylinder bands and cone caps).
        for path in crate::testing::corpus_step_files() {
            let m = crate::ingest::read_model(&path).unwrap_or_else(|e| panic!("{e}"));
            faces.extend(m.faces);
        }
        let m = sample("cylinder.step");
        let mut band = m
            .faces
            .iter()
            .find(|f| crate::geom::surface_kind(&f.surface) == "cylinder")
            .unwrap()
            .clone();
        band.loops = vec![
            synthetic_loop(40, |t| {
                DVec2::new(1.0 + TAU * t, 0.5 * (TAU * 3.0 * t).sin())
            }),
            synthetic_loop(40, |t| DVec2::new(1.0 - TAU * t, 30.0)),
        ];
        faces.push(band);
        let mut rng = crate::testing::distance::Lcg(7);
        let mut rnd = move || rng.next();
        let mut checked = 0;
        for face in &faces {
            let trim = Trim::new(face);
            let d = &face.domain;
            let (w, h) = (d.u.1 - d.u.0, d.v.1 - d.v.0);
            for _ in 0..300 {
                let k = (rnd() * 3.0).floor() - 1.0;
                let uv = DVec2::new(
                    d.u.0 - 0.1 * w + 1.2 * w * rnd() + k * d.u_period.unwrap_or(0.0),
                    d.v.0 - 0.1 * h + 1.2 * h * rnd() + k * d.v_period.unwrap_or(0.0),
                );
                assert_eq!(trim.contains(face, uv), contains(face, uv), "at {uv}");
                checked += 1;
            }
            // Exactly on loop points too (the half-open rule must pick the same side).
            for l in &face.loops {
                for &p in l.outline() {
                    if trim.contains(face, p) != contains(face, p) {
                        let st = Setup::new(face).unwrap();
                        let x = if st.swap { p.y } else { p.x };
                        let all: Vec<_> = segments(face, st.swap)
                            .filter(|(a, b)| a.x.min(b.x) <= x + 1e-9 && x - 1e-9 <= a.x.max(b.x))
                            .collect();
                        panic!("at loop point {p}: setup {st:?} x0 {} w {} cols {} segs near {all:?} domain {:?}", trim.x0, trim.w, trim.cols, face.domain);
                    }
                }
            }
        }
        assert!(checked > 10_000);
    }

    /// A cone cap (one circle and the apex) does not continue past its apex onto the cone's
    /// other sheet, which the orientation rule alone would accept: the real NIST part's
    /// cone F75 (when the corpus is present), and the same cap without its vertex loop.
    #[test]
    fn cone_cap_stops_at_its_apex() {
        let Some(dir) = crate::testing::realworld_dir() else {
            return;
        };
        let m = crate::ingest::read_model(&dir.join("stepswift_nist_ctc_01_asme1_rd.stp"))
            .unwrap_or_else(|e| panic!("{e}"));
        let face = &m.faces[75];
        assert_eq!(crate::geom::surface_kind(&face.surface), "cone");
        let mut bare = face.clone();
        bare.loops.retain(|l| l.vertex.is_none());
        let (v0, v1) = face.domain.v;
        for f in [face, &bare] {
            let trim = Trim::new(f);
            for u in [3.5, 5.0, 9.0] {
                let inside = DVec2::new(u, 0.5 * (v0 + v1));
                let beyond = DVec2::new(u, v0 - 0.5 * (v1 - v0));
                assert!(contains(f, inside) && trim.contains(f, inside), "{inside}");
                assert!(
                    !contains(f, beyond) && !trim.contains(f, beyond),
                    "{beyond}"
                );
            }
        }
    }

    /// A ray through a loop vertex on a periodic face counts the vertex once even when the
    /// vertex's u differs from the ray's by a rounding error across a period copy: the
    /// two-segment polyline below crosses the line u = 0.49087385212340584 exactly once.
    #[test]
    fn ray_through_a_vertex_counts_once_on_a_periodic_face() {
        let c = 0.49087385212340584;
        let p = Some(TAU);
        let v = DVec2::new(0.4908738521234061, 180.0);
        let mut n = 0;
        for (a, b) in [
            (DVec2::new(0.5399612373357465, 180.0), v),
            (v, DVec2::new(0.44178646691106516, 180.0)),
        ] {
            for_each_crossing(a, b, c, p, |_, _| n += 1);
        }
        assert_eq!(n, 1);
        // Across copies: the same polyline shifted by whole periods.
        for k in [-3.0, -1.0, 1.0, 7.0] {
            let s = DVec2::new(k * TAU, 0.0);
            let mut n = 0;
            for (a, b) in [
                (DVec2::new(0.5399612373357465, 180.0) + s, v + s),
                (v + s, DVec2::new(0.44178646691106516, 180.0) + s),
            ] {
                for_each_crossing(a, b, c, p, |_, _| n += 1);
            }
            assert_eq!(n, 1, "shifted by {k} periods");
        }
    }

    fn signed_area(poly: &[DVec2]) -> f64 {
        let n = poly.len();
        (0..n)
            .map(|i| poly[i].perp_dot(poly[(i + 1) % n]))
            .sum::<f64>()
            * 0.5
    }

    /// On every sample face without wrapping loops, the fraction of a UV grid inside the face
    /// times the domain's area equals the oriented area of the loops (outer loops count +,
    /// holes −, by the STEP orientation rule), up to the grid's resolution.
    ///
    /// Known-bad faces go in `KNOWN_BAD` (none now: the closed NURBS cylinder was until
    /// `geom::surface_periods` detected its period); the test fails loudly when one passes.
    #[test]
    fn grid_area_matches_loop_area_on_all_samples() {
        const KNOWN_BAD: &[(&str, usize)] = &[];
        let mut checked = 0;
        for path in crate::testing::sample_files() {
            let m = crate::ingest::read_model(&path).unwrap_or_else(|e| panic!("{e}"));
            for (i, face) in m.faces.iter().enumerate() {
                let periods = (face.domain.u_period, face.domain.v_period);
                let edge_loops: Vec<&Loop> =
                    face.loops.iter().filter(|l| is_edge_loop(l)).collect();
                if edge_loops.is_empty()
                    || edge_loops.iter().any(|l| {
                        let w = wrapping(l.outline(), periods);
                        w.0 || w.1
                    })
                {
                    continue;
                }
                let o = if face.same_sense { 1.0 } else { -1.0 };
                let loops_area: f64 = edge_loops
                    .iter()
                    .map(|l| o * signed_area(l.outline()))
                    .sum();
                let d = face.domain;
                let n = 200;
                let (du, dv) = ((d.u.1 - d.u.0) / n as f64, (d.v.1 - d.v.0) / n as f64);
                let hits = (0..n * n)
                    .filter(|k| {
                        let uv = DVec2::new(
                            d.u.0 + (k % n) as f64 * du + 0.5 * du,
                            d.v.0 + (k / n) as f64 * dv + 0.5 * dv,
                        );
                        contains(face, uv)
                    })
                    .count();
                let grid_area = hits as f64 * du * dv;
                let total = (d.u.1 - d.u.0) * (d.v.1 - d.v.0);
                // Cells cut by a loop are counted or not by their centre: the error is at most
                // the loops' length times a cell's diagonal; 2 % of the domain covers it.
                let ok = (grid_area - loops_area).abs() <= 0.02 * total;
                let name = path.file_name().unwrap().to_string_lossy();
                let known_bad = KNOWN_BAD.contains(&(name.as_ref(), i));
                assert!(
                    ok != known_bad,
                    "{name} face {i}: grid {grid_area}, loops {loops_area}, domain {total}{}",
                    if known_bad {
                        " (listed as known bad but passes now: remove it)"
                    } else {
                        ""
                    }
                );
                checked += 1;
            }
        }
        assert!(checked > 100, "checked {checked} faces");
    }
}
