//! Pinches: two touch points of a seam that meet at a vertex of the boundary both their
//! elements reach — a hole's wall and a slot's edge where the hole is tangent to the slot, a
//! face and an edge that runs into it there. The sheet between those two elements pinches off
//! at that ball (`r > 0`, the ball touches two places) and the seam ends; the seam on the
//! elements past the vertex ends at the same ball ([`SeamEnd::Pinch`]).

use super::options::{REACH_REL_ACCURACY, UNIT_ROUNDING};
use super::tracer::Tracer;
use super::unknowns::{slot, v3};
use crate::geom::project_point;
use crate::medial::axis::SeamEnd;
use crate::medial::equations::{edge_angle, vertex_angles, MedialSystem, NormalField};
use crate::medial::maximal::curvature_allows;
use crate::medial::solver::{solve, SolveStatus};
use crate::model::Element;
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

impl Tracer<'_> {
    /// Where two touch points of the seam point `x` (of `sys` on `triplet`) are about to meet
    /// at a vertex that both their elements reach (each within [`REACH_REL_ACCURACY`] × the
    /// accuracy of it), the seam point where they meet there, when it is medial: the seam
    /// ends there, at a pinch.
    pub(super) fn pinch(
        &self,
        sys: &MedialSystem,
        triplet: &[Element; 3],
        x: &DVector<f64>,
    ) -> Option<(SeamEnd, DVector<f64>)> {
        let near = REACH_REL_ACCURACY * self.opts.accuracy;
        let at = self.touches(triplet, x);
        for (i, k) in [(0, 1), (0, 2), (1, 2)] {
            let (Some(a), Some(b)) = (at[i], at[k]) else {
                continue;
            };
            if triplet[i] == triplet[k] {
                continue;
            }
            let candidates = (0..self.model.vertices.len()).filter(|&v| {
                let p = self.model.vertices[v].point;
                p.distance(a) <= near
                    && p.distance(b) <= near
                    && self.reaches(triplet[i], v)
                    && self.reaches(triplet[k], v)
            });
            for v in candidates {
                let y = self
                    .pinch_on_normal(sys, triplet, x, [i, k], v)
                    .or_else(|| self.pinch_held(sys, triplet, x, [i, k], v));
                if let Some(y) = y.filter(|y| self.pinch_is_medial(triplet, y, 3 - i - k, v)) {
                    let end = SeamEnd::Pinch {
                        segments: [triplet[i], triplet[k]],
                        vertex: v,
                    };
                    return Some((end, y));
                }
            }
        }
        None
    }

    /// True when element `e` reaches vertex `v` (is it, ends there, or is bounded by an edge
    /// that does).
    pub(super) fn reaches(&self, e: Element, v: usize) -> bool {
        match e {
            Element::Vertex(w) => w == v,
            Element::Edge(g) => self.model.edges[g].vertices.contains(&v),
            Element::Face(f) => self.vertex_edges[v]
                .iter()
                .any(|&(g, _)| self.model.edges[g].faces.contains(&f)),
        }
    }

    /// The pinch exactly, where the two elements `pair` fix the ball's normal at the vertex
    /// (see [`Self::pinch_normal`]): its centre is then on the normal line `V − r·n` and only
    /// its radius and the third element's touch point are unknown (the two-element system of
    /// the vertex and the third element, with the vertex's normal held). The seam point is
    /// that ball when both elements of the pair take it at the vertex (the system of `triplet`
    /// holds there to a tenth of the accuracy: a file's vertex may lie a little off its
    /// edges' ends), as where they meet tangentially; otherwise `None`.
    fn pinch_on_normal(
        &self,
        sys: &MedialSystem,
        triplet: &[Element; 3],
        x: &DVector<f64>,
        pair: [usize; 2],
        v: usize,
    ) -> Option<DVector<f64>> {
        let acc = self.opts.accuracy;
        let third = 3 - pair[0] - pair[1];
        let n = self.pinch_normal(triplet, x, pair, v)?;
        let held = vertex_angles(n);
        let two = MedialSystem::new(vec![Element::Vertex(v), triplet[third]]);
        let mut z0 = DVector::zeros(8);
        z0.rows_mut(0, 4).copy_from(&x.rows(0, 4));
        z0[4] = held[0];
        z0[5] = held[1];
        z0[6] = slot(x, third)[0];
        z0[7] = slot(x, third)[1];
        let sol = solve(
            |z| {
                let (f, j) = two.eval(self.model, z)?;
                let mut fa = DVector::zeros(8);
                let mut ja = DMatrix::zeros(8, 8);
                fa.rows_mut(0, 6).copy_from(&f);
                ja.view_mut((0, 0), (6, 8)).copy_from(&j);
                for (row, c) in [(6, 4), (7, 5)] {
                    fa[row] = z[c] - held[c - 4];
                    ja[(row, c)] = 1.0;
                }
                Some((fa, ja))
            },
            z0,
            &self.solve_opts(),
        );
        if sol.status != SolveStatus::Converged
            || v3(&sol.x).distance(v3(x)) > REACH_REL_ACCURACY * acc
        {
            return None;
        }
        let mut y = x.clone();
        y.rows_mut(0, 4).copy_from(&sol.x.rows(0, 4));
        y[4 + 2 * third] = sol.x[6];
        y[5 + 2 * third] = sol.x[7];
        for s in pair {
            let [a, b] = self.params_at_vertex(triplet[s], v, n, slot(x, s))?;
            y[4 + 2 * s] = a;
            y[5 + 2 * s] = b;
        }
        let residual = sys.residual(self.model, &y)?.amax();
        (residual <= 0.1 * acc).then_some(y)
    }

    /// The outward normal of a ball that touches both elements of `pair` at vertex `v`, where
    /// they fix it: a face's normal there; for two edges that meet at an angle, the normal of
    /// the plane of their tangents there (on the side of the touch point's normal at `x`).
    fn pinch_normal(
        &self,
        triplet: &[Element; 3],
        x: &DVector<f64>,
        pair: [usize; 2],
        v: usize,
    ) -> Option<DVec3> {
        let p = self.model.vertices[v].point;
        // A face collapsed to a point at the vertex (a blend tapering to a tip) has no one
        // normal there: the other face's fixes the ball's.
        let faces: Vec<usize> = pair
            .iter()
            .filter_map(|&s| match triplet[s] {
                Element::Face(f) => Some(f),
                _ => None,
            })
            .collect();
        if !faces.is_empty() {
            return faces.into_iter().find_map(|f| {
                let uv = project_point(&self.model.faces[f].surface, p, None)?;
                if collapsed_side(&self.model.faces[f], uv).is_some() {
                    return None;
                }
                Some(Element::Face(f).eval(self.model, [uv.0, uv.1])?.n)
            });
        }
        let tangent = |s: usize| match triplet[s] {
            Element::Edge(g) => {
                let t = self.edge_end_at(g, v, slot(x, s)[0])?;
                Some(crate::geom::eval_curve(&self.model.edges[g].curve, t).d1)
            }
            _ => None,
        };
        let (a, b) = (
            tangent(pair[0])?.try_normalize()?,
            tangent(pair[1])?.try_normalize()?,
        );
        // Edges that run on in one line leave the plane undefined.
        if a.dot(b).abs() > 1.0 - 1e-6 {
            return None;
        }
        let n = a.cross(b).normalize();
        let now = triplet[pair[0]].eval(self.model, slot(x, pair[0]))?.n;
        Some(if n.dot(now) < 0.0 { -n } else { n })
    }

    /// The parameters of element `e` at vertex `v` with the normal `n`, on the branch of the
    /// angles nearest `now` (the element's parameters at the seam point).
    fn params_at_vertex(&self, e: Element, v: usize, n: DVec3, now: [f64; 2]) -> Option<[f64; 2]> {
        let tau = std::f64::consts::TAU;
        let branch = |a: f64, near: f64| a + tau * ((near - a) / tau).round();
        let p = self.model.vertices[v].point;
        match e {
            Element::Face(f) => {
                let uv = project_point(&self.model.faces[f].surface, p, Some((now[0], now[1])))?;
                let face = &self.model.faces[f];
                match collapsed_side(face, uv) {
                    Some(side) => params_on_collapsed_side(face, uv, side, n, self.opts.accuracy),
                    None => Some([uv.0, uv.1]),
                }
            }
            Element::Edge(g) => {
                let t = self.edge_end_at(g, v, now[0])?;
                let th = edge_angle(self.model, g, t, n)?;
                Some([t, branch(th, now[1])])
            }
            Element::Vertex(_) => {
                let [a, b] = vertex_angles(n);
                Some([branch(a, now[0]), b])
            }
        }
    }

    /// The parameter of edge `g`'s end at vertex `v` (of the two, on a closed edge, the one
    /// nearer `t`).
    fn edge_end_at(&self, g: usize, v: usize, t: f64) -> Option<f64> {
        let edge = &self.model.edges[g];
        [
            (edge.vertices[0], edge.range.0),
            (edge.vertices[1], edge.range.1),
        ]
        .into_iter()
        .filter(|&(w, _)| w == v)
        .map(|(_, te)| te)
        .min_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs()))
    }

    /// The pinch where the elements of `pair` do not fix the ball's normal at the vertex (a
    /// vertex and an edge that ends there, edges that run on in one line): the seam point with
    /// the touch point on an edge that ends at the vertex held at that end, when the other
    /// touch point is at the vertex too (to the accuracy).
    fn pinch_held(
        &self,
        sys: &MedialSystem,
        triplet: &[Element; 3],
        x: &DVector<f64>,
        pair: [usize; 2],
        v: usize,
    ) -> Option<DVector<f64>> {
        let acc = self.opts.accuracy;
        let (s, e) = pair.into_iter().find_map(|s| match triplet[s] {
            Element::Edge(e) if self.model.edges[e].vertices.contains(&v) => Some((s, e)),
            _ => None,
        })?;
        let end = self.edge_end_at(e, v, slot(x, s)[0])?;
        let y = self
            .solve_holding(sys, x, 4 + 2 * s, end)
            .filter(|y| v3(y).distance(v3(x)) <= REACH_REL_ACCURACY * acc)?;
        let p = self.model.vertices[v].point;
        let t = self.touches(triplet, &y);
        pair.iter()
            .all(|&k| t[k].is_some_and(|q| q.distance(p) <= acc))
            .then_some(y)
    }

    /// True when the pinch `y` at vertex `v` is medial: the third touch point on its element,
    /// nothing of the boundary closer than `r`, and no touched face curving into the ball.
    /// (The two touch points at the vertex are on their elements there: rounding may put one
    /// a hair past a face's boundary, which `is_medial` would refuse. A face collapsed to a
    /// point at the vertex — a blend tapering to a tip, the Voron Manta mount's — bends as
    /// tightly as its width there allows, which says nothing of the ball: that the ball is
    /// empty does.)
    fn pinch_is_medial(
        &self,
        triplet: &[Element; 3],
        y: &DVector<f64>,
        third: usize,
        v: usize,
    ) -> bool {
        let r = y[3];
        let p = self.model.vertices[v].point;
        let tip = |s: usize| match triplet[s] {
            Element::Face(f) if s != third => project_point(
                &self.model.faces[f].surface,
                p,
                Some((slot(y, s)[0], slot(y, s)[1])),
            )
            .is_some_and(|uv| collapsed_side(&self.model.faces[f], uv).is_some()),
            _ => false,
        };
        r > UNIT_ROUNDING
            && self.on_segment(triplet[third], slot(y, third))
            && self.ball_is_empty(self.solid_of(triplet[third]), y)
            && (0..3).all(|s| tip(s) || curvature_allows(self.model, triplet[s], slot(y, s), r))
    }
}

/// Which parameter of a face's surface moves the point no more along a side of its domain
/// collapsed to a point: `AlongV` where `Sv` vanishes (the side is `u` = constant), `AlongU`
/// where `Su` does.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Collapsed {
    AlongU,
    AlongV,
}

/// Whether `face`'s surface is collapsed to a point at `uv` (one of its first derivatives
/// below a millionth of the other: a blend written as a B-spline tapering to a tip, a cone's
/// apex, a sphere's pole), and along which parameter.
fn collapsed_side(face: &crate::model::Face, uv: (f64, f64)) -> Option<Collapsed> {
    let d = crate::geom::eval_face(face, uv.0, uv.1);
    let (lu, lv) = (d.su.length(), d.sv.length());
    if lv <= 1e-6 * lu {
        Some(Collapsed::AlongV)
    } else if lu <= 1e-6 * lv {
        Some(Collapsed::AlongU)
    } else {
        None
    }
}

/// The parameters of `face` at `uv`, on a side of its domain that `side` says is collapsed
/// to a point ([`collapsed_side`]), where its outward normal is `n`: along that side a hair
/// inside the domain (the point moves by a thousandth of `accuracy`; on the side itself the
/// normal is undefined), the normal nearest `n` by sampling and then golden section. `None`
/// when none along the side is within a milliradian of `n`.
fn params_on_collapsed_side(
    face: &crate::model::Face,
    uv: (f64, f64),
    side: Collapsed,
    n: DVec3,
    accuracy: f64,
) -> Option<[f64; 2]> {
    let d = crate::geom::eval_face(face, uv.0, uv.1);
    // `fixed`: the parameter constant along the side; `free`: the one along it.
    let (fixed, range, free, speed) = match side {
        Collapsed::AlongV => (uv.0, face.domain.u, face.domain.v, d.su.length()),
        Collapsed::AlongU => (uv.1, face.domain.v, face.domain.u, d.sv.length()),
    };
    if !speed.is_finite() || speed <= 0.0 {
        return None;
    }
    let inward = if fixed - range.0 <= range.1 - fixed {
        1.0
    } else {
        -1.0
    };
    let fixed = fixed + inward * 1e-3 * accuracy / speed;
    let at = |t: f64| match side {
        Collapsed::AlongV => [fixed, t],
        Collapsed::AlongU => [t, fixed],
    };
    let fit = |t: f64| {
        let [u, v] = at(t);
        crate::geom::unit_normal(&crate::geom::eval_face(face, u, v), face.sign)
            .map_or(f64::NEG_INFINITY, |m| m.dot(n))
    };
    const SAMPLES: usize = 64;
    let step = (free.1 - free.0) / SAMPLES as f64;
    let best = (0..=SAMPLES)
        .map(|k| free.0 + k as f64 * step)
        .max_by(|a, b| fit(*a).total_cmp(&fit(*b)))?;
    let (mut lo, mut hi) = ((best - step).max(free.0), (best + step).min(free.1));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if fit(a) >= fit(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let t = 0.5 * (lo + hi);
    (fit(t) >= (1e-3f64).cos()).then_some(at(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Face, Surface, UvDomain};
    use truck_geometry::prelude::{BSplineSurface, KnotVec, Point3};

    /// A B-spline patch collapsed to its apex along its side u = 0 (every pole of that row at
    /// the apex: a blend tapering to a tip, as exporters write one), its side u = 1 a
    /// quadratic arc in the plane z = 0: its normal at the apex turns with v, as a cone's.
    fn tip_patch() -> Face {
        let apex = Point3::new(0.0, 0.0, 1.0);
        let poles = vec![
            vec![apex; 3],
            vec![
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(1.0, 1.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
        ];
        let surface =
            BSplineSurface::new((KnotVec::bezier_knot(1), KnotVec::bezier_knot(2)), poles);
        Face {
            source_id: 0,
            shell: 0,
            surface: Surface::BSplineSurface(Box::new(surface)),
            sign: 1.0,
            same_sense: true,
            loops: vec![],
            outer: None,
            domain: UvDomain {
                u: (0.0, 1.0),
                v: (0.0, 1.0),
                u_period: None,
                v_period: None,
            },
        }
    }

    /// The touch point at a collapsed tip is put where the face's normal is the ball's (the
    /// Voron Manta mount's blend F164 at its tip V291, a pinch with the plane F172: projecting
    /// the tip gave a normal 60 degrees off, and the pinch was not found), for normals all
    /// along the side; a regular point is not collapsed.
    #[test]
    fn a_patch_collapsed_to_a_tip_takes_the_touch_point_with_the_balls_normal() {
        let face = tip_patch();
        let accuracy = 1e-6;
        let normal = |u: f64, v: f64| {
            crate::geom::unit_normal(&crate::geom::eval_face(&face, u, v), face.sign)
                .expect("a regular point")
        };
        assert_eq!(collapsed_side(&face, (0.0, 0.3)), Some(Collapsed::AlongV));
        assert_eq!(collapsed_side(&face, (0.5, 0.3)), None);
        let tip = crate::geom::eval_face(&face, 0.0, 0.0).p;
        let mut seen = vec![];
        for v in [0.1, 0.5, 0.9] {
            let n = normal(1e-3, v);
            // Projecting the tip lands anywhere along the side: start at its other end.
            let found =
                params_on_collapsed_side(&face, (0.0, 1.0 - v), Collapsed::AlongV, n, accuracy)
                    .unwrap_or_else(|| panic!("v {v}: no parameters with the normal {n}"));
            let p = crate::geom::eval_face(&face, found[0], found[1]).p;
            assert!(
                p.distance(tip) <= accuracy,
                "v {v}: {} off the tip",
                p.distance(tip)
            );
            let m = normal(found[0], found[1]);
            assert!(
                m.angle_between(n) < 1e-3,
                "v {v}: the normal {} rad off",
                m.angle_between(n)
            );
            seen.push(n);
        }
        assert!(seen[0].angle_between(seen[2]) > 0.5, "{seen:?}");
        // A normal the tip does not have.
        assert_eq!(
            params_on_collapsed_side(&face, (0.0, 0.5), Collapsed::AlongV, DVec3::Z, accuracy),
            None
        );
    }
}
