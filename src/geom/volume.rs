//! The volume of each solid, by the divergence theorem on its exact faces.
//!
//! The field `(p − o)/3` has divergence 1, so a solid's volume is the flux of that field out
//! through its faces: `V = Σ_faces ∫∫ (S − o)·N dA / 3`, with `N` the normal out of the
//! material (`face.sign · (Su × Sv)`, voids included: their faces point into the void, so they
//! subtract). `o` is the centre of the model's box, which keeps the terms small.
//!
//! Each face's integral is over its trimmed region `D` in UV, `∫∫_D f du dv` with
//! `f = (S − o)·(Su × Sv)`. Green's theorem turns it into a sum over the region's boundary:
//! with `H(x, y) = ∫_{y₀}^{y} f(x, t) dt` along the direction `y` that no loop wraps around,
//! `∫∫_D f = −∮_{∂D} H dx` for a boundary with the region on its left. Both integrals are
//! Gauss–Legendre rules (five points, exact for polynomials of degree 9: a bicubic patch's
//! `f` is of degree 8 in each parameter) on pieces split at the surface's knots and, for
//! curved kinds, at sixteenths of the covered range, so the surface part of the integral is
//! exact to rounding for planes and polynomial patches and to about 1e-10 for the others.
//!
//! The boundary is the loops' UV samples ([`Loop::uv`](crate::model::Loop::uv)), exact points
//! of the trimming curves, even in each edge's parameter
//! ([`Loop::uv_counts`](crate::model::Loop::uv_counts)). Between two of
//! them the path is the cubic through four consecutive samples of the same curved edge, which
//! follows the curve to fourth order in the spacing: a circle sampled 32 times bounds its area
//! to 1e-5 (the chord polygon cut 0.64 % off it, about 0.2 % of a plate's volume per hole of
//! the plate's own area). A line's two samples, and a jump in the samples (at a pole), are
//! joined straight; where one end is at a pole (`Su` or `Sv` vanishing) the path turns the
//! corner along the pole's line, as the region does in UV (the chord cut 0.16 % off a
//! hemispherical shell). The samples agree with their scripts' exact volumes to 2.4e-5, the
//! third-party parts with OCCT's to 0.1 %.

//! Loops follow the STEP convention (the face on their left seen against `Su × Sv` when the
//! face's `same_sense` holds), as the trim test reads them. A loop that wraps around a
//! period (the rim of a cylinder's band, a cone cap's circle) is closed to the copy of its
//! first point next to its last, and bounds the face on one side only; the face then reaches
//! the pole on that side (the covered range of [`covered_domain`]), which adds the whole
//! strip `∫∫ f` over the period when the loops wind once around it with the face beyond.

use super::eval::eval_surface;
use super::trim::{covered_domain, edge_samples, is_edge_loop, wrap_near, wrapping};
use crate::model::{Face, Model, Surface};
use glam::{DVec2, DVec3, Vec2Swizzles};
use rayon::prelude::*;

/// Gauss–Legendre nodes and weights on `[0, 1]`, five points.
const GAUSS: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_094_5),
    (0.230_765_344_947_158_5, 0.239_314_335_249_683_2),
    (0.5, 0.284_444_444_444_444_4),
    (0.769_234_655_052_841_5, 0.239_314_335_249_683_2),
    (0.953_089_922_969_332, 0.118_463_442_528_094_5),
];

/// Pieces of a curved surface's covered range in one direction (a period for an angle).
const PIECES_PER_RANGE: f64 = 16.0;

/// Most pieces one integral is split into (a B-spline with very many knots).
const MAX_PIECES: usize = 4096;

/// The volume of each solid (see the module docs), `None` for a solid with a face whose
/// region this cannot integrate (loops wrapping around both periods of a torus, a face
/// reaching an unbounded end) or whose integral is not finite.
pub fn solid_volumes(model: &Model) -> Vec<Option<f64>> {
    let (lo, hi) = model.bbox;
    let origin = 0.5 * (lo + hi);
    let flux: Vec<Option<f64>> = model
        .faces
        .par_iter()
        .enumerate()
        .map(|(fi, _)| face_flux(model, fi, origin))
        .collect();
    model
        .solids
        .iter()
        .map(|s| {
            let mut v = 0.0;
            for &sh in &s.shells {
                for &f in &model.shells[sh].faces {
                    v += flux[f]?;
                }
            }
            v.is_finite().then_some(v)
        })
        .collect()
}

/// The flux of `(p − origin)/3` out of the material through `face` (see the module docs).
pub fn face_flux(model: &Model, face_index: usize, origin: DVec3) -> Option<f64> {
    let face = &model.faces[face_index];
    let d = &face.domain;
    let periods = (d.u_period, d.v_period);
    let (cu, cv) = covered_domain(face);
    let loops: Vec<&crate::model::Loop> = face.loops.iter().filter(|l| is_edge_loop(l)).collect();
    // A face bounded by nothing but its own seams (a whole torus: a loop of its two seams,
    // each used twice) is the whole domain, as one without edge loops is (a whole sphere).
    let only_seams = loops.iter().all(|l| {
        l.edges
            .iter()
            .all(|oe| model.edges[oe.edge].faces.iter().all(|&f| f == face_index))
    });
    let integral = if only_seams {
        let span = |r: (f64, f64), p: Option<f64>| match p {
            Some(p) => (r.0, r.0 + p),
            None => r,
        };
        let (u, v) = (span(cu, d.u_period), span(cv, d.v_period));
        let g = Integrand::new(face, origin, false, u, v)?;
        g.strip(u.0, u.1, v.0, v.1)
    } else {
        let (mut wrap_u, mut wrap_v) = (false, false);
        for l in &loops {
            let (wu, wv) = wrapping(&l.uv, periods);
            wrap_u |= wu;
            wrap_v |= wv;
        }
        if wrap_u && wrap_v {
            return None; // a torus's band around both periods: not met yet
        }
        // Integrate along the direction no loop wraps around (as the trim test casts its ray).
        let swap = wrap_v && !wrap_u;
        let orient = if face.same_sense { 1.0 } else { -1.0 } * if swap { -1.0 } else { 1.0 };
        let (xr, yr, px) = if swap {
            (cv, cu, periods.1)
        } else {
            (cu, cv, periods.0)
        };
        let g = Integrand::new(face, origin, swap, xr, yr)?;
        let mut sum = 0.0;
        let mut winding = 0.0;
        for l in &loops {
            let path = LoopPath::new(model, face_index, l, periods, swap);
            for i in 0..path.len() {
                for piece in path.pieces(i) {
                    sum -= g.along(&piece);
                }
            }
            if let Some(p) = px {
                winding += (path.offset.x / p).round();
            }
        }
        let mut integral = orient * sum;
        // Loops winding once around the period with the face beyond them: the face reaches
        // the far end of the covered range, the whole strip from y₀ to there.
        let w = orient * winding;
        if w == 1.0 {
            let p = px?;
            let x0 = xr.0;
            integral += g.strip(x0, x0 + p, yr.0, yr.1);
        } else if w != 0.0 && w != -1.0 {
            return None;
        }
        integral
    };
    let flux = face.sign * integral / 3.0;
    flux.is_finite().then_some(flux)
}

/// Where a direction of a surface is split for the quadrature: its knots, and lines `k·step`.
struct Breaks {
    knots: Vec<f64>,
    step: Option<f64>,
}

impl Breaks {
    /// The sorted points of `[lo, hi]` (`lo < hi`) where pieces start and end, ends included.
    fn within(&self, lo: f64, hi: f64) -> Vec<f64> {
        let mut out = vec![lo];
        out.extend(self.knots.iter().copied().filter(|&k| k > lo && k < hi));
        if let Some(step) = self.step {
            let (k0, k1) = (
                (lo / step).floor() as i64 + 1,
                (hi / step).ceil() as i64 - 1,
            );
            if k1 >= k0 && ((k1 - k0) as usize) < MAX_PIECES {
                out.extend(
                    (k0..=k1)
                        .map(|k| k as f64 * step)
                        .filter(|&x| x > lo && x < hi),
                );
            }
        }
        out.push(hi);
        out.sort_by(f64::total_cmp);
        out.dedup();
        if out.len() > MAX_PIECES + 1 {
            let n = MAX_PIECES;
            out = (0..=n)
                .map(|k| lo + (hi - lo) * k as f64 / n as f64)
                .collect();
        }
        out
    }
}

/// `f = (S − o)·(Su × Sv)` of one face, in swapped coordinates `(x, y)` = `(v, u)` when
/// `swap`, with the breaks of each direction.
struct Integrand<'a> {
    surface: &'a Surface,
    origin: DVec3,
    swap: bool,
    bx: Breaks,
    by: Breaks,
    /// The lower end of `H`'s integral.
    y0: f64,
}

impl<'a> Integrand<'a> {
    /// `None` when the covered range along `y` is not finite.
    fn new(
        face: &'a Face,
        origin: DVec3,
        swap: bool,
        xr: (f64, f64),
        yr: (f64, f64),
    ) -> Option<Integrand<'a>> {
        if !(yr.0.is_finite() && yr.1.is_finite()) {
            return None;
        }
        let (ku, kv) = knots(&face.surface);
        let curved = crate::geom::surface_kind(&face.surface) != "plane";
        let step = |r: (f64, f64), p: Option<f64>| {
            let w = p.unwrap_or(r.1 - r.0);
            (curved && w.is_finite() && w > 0.0).then(|| w / PIECES_PER_RANGE)
        };
        let d = &face.domain;
        let (bu, bv) = (
            Breaks {
                knots: ku,
                step: step(if swap { yr } else { xr }, d.u_period),
            },
            Breaks {
                knots: kv,
                step: step(if swap { xr } else { yr }, d.v_period),
            },
        );
        let (bx, by) = if swap { (bv, bu) } else { (bu, bv) };
        Some(Integrand {
            surface: &face.surface,
            origin,
            swap,
            bx,
            by,
            y0: yr.0,
        })
    }

    fn f(&self, x: f64, y: f64) -> f64 {
        let (u, v) = if self.swap { (y, x) } else { (x, y) };
        let d = eval_surface(self.surface, u, v);
        (d.p - self.origin).dot(d.su.cross(d.sv))
    }

    /// `∫_{y0}^{y} f(x, t) dt`.
    fn h(&self, x: f64, y: f64) -> f64 {
        integrate(&self.by, self.y0, y, |t| self.f(x, t))
    }

    /// `∫ H dx` along one piece of a loop's path.
    fn along(&self, piece: &Piece) -> f64 {
        let (a, b) = (piece.at(0.0).0, piece.at(1.0).0);
        // Split where the chord crosses the breaks across x (near where the path does).
        let dx = b.x - a.x;
        let cuts: Vec<f64> = if dx == 0.0 {
            vec![0.0, 1.0]
        } else {
            let (lo, hi) = (a.x.min(b.x), a.x.max(b.x));
            let mut c: Vec<f64> = self
                .bx
                .within(lo, hi)
                .into_iter()
                .map(|x| ((x - a.x) / dx).clamp(0.0, 1.0))
                .collect();
            c.sort_by(f64::total_cmp);
            c
        };
        let mut sum = 0.0;
        for w in cuts.windows(2) {
            let (p, q) = (w[0], w[1]);
            let len = q - p;
            if len <= 0.0 {
                continue;
            }
            for (t, wt) in GAUSS {
                let (pt, d) = piece.at(p + t * len);
                if d.x != 0.0 {
                    sum += wt * len * self.h(pt.x, pt.y) * d.x;
                }
            }
        }
        sum
    }

    /// `∫_{x0}^{x1} ∫_{y0}^{y1} f dy dx` (with `y0` the integrand's own when they differ).
    fn strip(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        integrate(&self.bx, x0, x1, |x| {
            integrate(&self.by, y0, y1, |t| self.f(x, t))
        })
    }
}

/// `∫_lo^hi g` (oriented: negative when `hi < lo`), five-point Gauss on each piece.
fn integrate(breaks: &Breaks, lo: f64, hi: f64, mut g: impl FnMut(f64) -> f64) -> f64 {
    if lo == hi {
        return 0.0;
    }
    let (a, b, sign) = if lo < hi {
        (lo, hi, 1.0)
    } else {
        (hi, lo, -1.0)
    };
    let pts = breaks.within(a, b);
    let mut sum = 0.0;
    for w in pts.windows(2) {
        let (p, q) = (w[0], w[1]);
        let len = q - p;
        for (t, wt) in GAUSS {
            sum += wt * len * g(p + t * len);
        }
    }
    sign * sum
}

/// The distinct inner knots of a B-spline or NURBS surface in u and in v (empty for others).
fn knots(surface: &Surface) -> (Vec<f64>, Vec<f64>) {
    let distinct = |k: &truck_geometry::prelude::KnotVec| {
        let mut out: Vec<f64> = k.iter().copied().collect();
        out.dedup();
        out
    };
    super::surface::knot_vectors(surface).map_or((Vec::new(), Vec::new()), |(u, v)| {
        (distinct(u), distinct(v))
    })
}

/// A loop's UV polygon as a closed path in (swapped) coordinates `(x, y)`: point `i` for any
/// integer `i`, a wrapping loop's copies shifted by the period it winds (`offset`), and how
/// its points fall on the loop's edges ([`Loop::uv_counts`](crate::model::Loop::uv_counts)).
struct LoopPath<'a> {
    surface: &'a Surface,
    poly: Vec<DVec2>,
    swap: bool,
    /// From the point after the last back to the first: zero unless the loop wraps.
    offset: DVec2,
    /// For each point, the index of its edge's first point and the edge's sample count, when
    /// the edge is curved (sampled more than twice) and the counts match the polygon.
    edge_of: Vec<Option<(usize, usize)>>,
}

/// A loop's polygon with each edge's samples thinned to the count the reader starts from
/// ([`edge_samples`]: the reader refines by doubling, so every `n/n₀`-th sample is one of
/// those), and the per-edge counts; the polygon as it is, without counts, when they do not
/// match it. The cubic path through the thinned samples follows the edges to fourth order
/// already (see the module docs); the refined polygon would only multiply the work.
fn decimated(
    model: &Model,
    face_index: usize,
    lp: &crate::model::Loop,
) -> (Vec<DVec2>, Option<Vec<usize>>) {
    let counts = &lp.uv_counts;
    if !lp.uv_counts_match() {
        return (lp.uv.clone(), None);
    }
    let mut poly = Vec::with_capacity(lp.uv.len());
    let mut thinned = Vec::with_capacity(counts.len());
    let mut start = 0;
    for (oe, &n) in lp.edges.iter().zip(counts) {
        let n0 = edge_samples(model, face_index, oe).1;
        let stride = if n0 > 0 && n > n0 && n % n0 == 0 {
            n / n0
        } else {
            1
        };
        poly.extend((0..n).step_by(stride).map(|k| lp.uv[start + k]));
        thinned.push(n.div_ceil(stride));
        start += n;
    }
    (poly, Some(thinned))
}

impl<'a> LoopPath<'a> {
    fn new(
        model: &'a Model,
        face_index: usize,
        lp: &'a crate::model::Loop,
        periods: (Option<f64>, Option<f64>),
        swap: bool,
    ) -> LoopPath<'a> {
        let (poly, counts) = decimated(model, face_index, lp);
        let n = poly.len();
        let (wu, wv) = wrapping(&poly, periods);
        let offset = if wu || wv {
            let (first, last) = (poly[0], poly[n - 1]);
            DVec2::new(
                wrap_near(first.x, last.x, periods.0),
                wrap_near(first.y, last.y, periods.1),
            ) - first
        } else {
            DVec2::ZERO
        };
        let offset = if swap { offset.yx() } else { offset };
        let mut edge_of = vec![None; n];
        if let Some(counts) = counts {
            let mut start = 0;
            for c in counts {
                if c > 2 {
                    for slot in &mut edge_of[start..start + c] {
                        *slot = Some((start, c));
                    }
                }
                start += c;
            }
        }
        LoopPath {
            surface: &model.faces[face_index].surface,
            poly,
            swap,
            offset,
            edge_of,
        }
    }

    fn len(&self) -> usize {
        self.poly.len()
    }

    /// Point `i` (any integer: copies past either end are shifted by `offset`).
    fn point(&self, i: i64) -> DVec2 {
        let n = self.poly.len() as i64;
        let p = self.poly[i.rem_euclid(n) as usize];
        let p = if self.swap { p.yx() } else { p };
        p + self.offset * i.div_euclid(n) as f64
    }

    /// The path from point `i` to point `i + 1`: the cubic through four consecutive samples
    /// of the same curved edge where they are evenly spread (the samples are even in the
    /// edge's parameter, so this follows the trimming curve to fourth order), else the chord
    /// (a line's two samples), turned into two sides of a rectangle where one end is at a
    /// pole (the polygon jumps there along the pole's line: `u` is undefined at a sphere's
    /// pole, so the loop reaches it along its meridian and leaves along the pole's line).
    fn pieces(&self, i: usize) -> Vec<Piece> {
        let (a, b) = (self.point(i as i64), self.point(i as i64 + 1));
        if let Some((start, count)) = self.edge_of[i] {
            // Local index on the edge, and the first of four nodes within the edge's samples
            // `0..=count` (its end is the next edge's first point).
            let k = i - start;
            let j0 = k.saturating_sub(1).min(count - 3);
            let q: [DVec2; 4] = std::array::from_fn(|m| self.point((start + j0 + m) as i64));
            let d = [q[1] - q[0], q[2] - q[1], q[3] - q[2]];
            let even = |x: DVec2, y: DVec2| {
                (y - x).length() <= CUBIC_EVEN_REL * x.length().max(y.length())
            };
            if even(d[0], d[1]) && even(d[1], d[2]) {
                return vec![Piece::Cubic(q, (k - j0) as f64)];
            }
        }
        // In (u, v) for the pole test, back to (x, y) after.
        let unswap = |p: DVec2| if self.swap { p.yx() } else { p };
        let (ua, ub) = (unswap(a), unswap(b));
        let corner = match (self.degenerate(ub), self.degenerate(ua)) {
            ((true, _), _) if ua.x != ub.x => Some(DVec2::new(ua.x, ub.y)),
            ((_, true), _) if ua.y != ub.y => Some(DVec2::new(ub.x, ua.y)),
            (_, (true, _)) if ua.x != ub.x => Some(DVec2::new(ub.x, ua.y)),
            (_, (_, true)) if ua.y != ub.y => Some(DVec2::new(ua.x, ub.y)),
            _ => None,
        };
        match corner {
            Some(c) => {
                let c = unswap(c);
                vec![Piece::Chord(a, c), Piece::Chord(c, b)]
            }
            None => vec![Piece::Chord(a, b)],
        }
    }

    /// Whether `Su` and `Sv` vanish at `uv` (a pole: the other parameter is undefined there).
    fn degenerate(&self, uv: DVec2) -> (bool, bool) {
        let d = eval_surface(self.surface, uv.x, uv.y);
        let (lu, lv) = (d.su.length(), d.sv.length());
        let tiny = POLE_REL_DERIVATIVE * lu.max(lv);
        (lu <= tiny, lv <= tiny)
    }
}

/// A parameter derivative this much shorter than the other is zero: the point is a pole.
const POLE_REL_DERIVATIVE: f64 = 1e-9;

/// Consecutive steps of four samples may differ by at most this fraction of the longer for the
/// cubic through them to stand for the curve (evenly sampled smooth curves differ by far less;
/// a pole's jump by more).
const CUBIC_EVEN_REL: f64 = 0.5;

/// One piece of a loop's path, for `s` in `[0, 1]`.
enum Piece {
    Chord(DVec2, DVec2),
    /// The cubic through four points at nodes 0, 1, 2, 3, between nodes `t0` and `t0 + 1`.
    Cubic([DVec2; 4], f64),
}

impl Piece {
    /// The point at `s` and its derivative in `s`.
    fn at(&self, s: f64) -> (DVec2, DVec2) {
        match self {
            Piece::Chord(a, b) => (*a + (*b - *a) * s, *b - *a),
            Piece::Cubic(q, t0) => {
                let t = t0 + s;
                let (l, dl) = lagrange4(t);
                let mut p = DVec2::ZERO;
                let mut d = DVec2::ZERO;
                for m in 0..4 {
                    p += q[m] * l[m];
                    d += q[m] * dl[m];
                }
                (p, d)
            }
        }
    }
}

/// The Lagrange basis on the nodes 0, 1, 2, 3 at `t`, and its derivatives.
fn lagrange4(t: f64) -> ([f64; 4], [f64; 4]) {
    let (a, b, c, d) = (t, t - 1.0, t - 2.0, t - 3.0);
    let l = [
        -b * c * d / 6.0,
        a * c * d / 2.0,
        -a * b * d / 2.0,
        a * b * c / 6.0,
    ];
    let dl = [
        -(c * d + b * d + b * c) / 6.0,
        (c * d + a * d + a * c) / 2.0,
        -(b * d + a * d + a * b) / 2.0,
        (b * c + a * c + a * b) / 6.0,
    ];
    (l, dl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::sample_path;

    fn read(name: &str) -> Model {
        crate::read_model(&sample_path(name)).expect("sample reads")
    }

    fn total(m: &Model) -> f64 {
        solid_volumes(m)
            .into_iter()
            .map(|v| v.expect("volume"))
            .sum()
    }

    /// Planes, a void, a whole sphere and torus (seams and poles only), a cylinder's band,
    /// holes in a plate (the loops' cubic paths), a NURBS patch: the exact volumes of the
    /// samples' scripts.
    #[test]
    fn sample_volumes_are_exact_to_the_loops_order() {
        for (name, want, tol) in [
            ("box.step", 48000.0, 1e-12),
            ("box_with_void.step", 69855.339415, 1e-9),
            ("sphere.step", 14137.166941, 1e-9),
            ("torus.step", 9869.604401, 1e-9),
            ("cylinder.step", 9424.777961, 2e-5),
            ("plate_with_holes.step", 36418.584375, 2e-5),
            ("box_bspline_top.step", 51900.0, 1e-9),
        ] {
            let got = total(&read(name));
            assert!(
                (got - want).abs() <= tol * want,
                "{name}: {got} mm³, exact {want}"
            );
        }
    }

    /// The check a reader's orientation must pass: one face taken the wrong way changes the
    /// volume by twice that face's flux, and a solid turned inside out has a negative one.
    #[test]
    fn a_flipped_face_or_solid_is_seen() {
        let mut m = read("box.step");
        m.faces[0].sign = -m.faces[0].sign;
        let v = total(&m);
        assert!((v - 48000.0).abs() > 1000.0, "{v}");
        for f in &mut m.faces {
            f.sign = -f.sign;
        }
        m.faces[0].sign = -m.faces[0].sign;
        assert!((total(&m) + 48000.0).abs() < 1e-6, "{}", total(&m));
    }

    /// Two solids each get their own volume, overlap or not (OCCT adds them the same way).
    #[test]
    fn each_solid_has_its_own_volume() {
        let v = solid_volumes(&read("two_solids.step"));
        assert_eq!(v.len(), 2);
        assert!((v[0].unwrap() - 6000.0).abs() < 1e-6, "{v:?}");
    }

    /// The Lagrange basis reproduces cubics and their derivatives.
    #[test]
    fn lagrange_basis_reproduces_cubics() {
        let c = |t: f64| 1.0 - 2.0 * t + 0.5 * t * t * t;
        let dc = |t: f64| -2.0 + 1.5 * t * t;
        for t in [0.0, 0.3, 1.0, 1.7, 2.5, 3.0] {
            let (l, dl) = lagrange4(t);
            let p: f64 = (0..4).map(|m| l[m] * c(m as f64)).sum();
            let d: f64 = (0..4).map(|m| dl[m] * c(m as f64)).sum();
            assert!((p - c(t)).abs() < 1e-12 && (d - dc(t)).abs() < 1e-12, "{t}");
        }
    }
}
