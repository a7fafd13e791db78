//! Maximality of a ball beyond the medial equations: the curvature criterion.
//!
//! A solution of the medial equations is only a bisector point; it is on the medial axis
//! when, besides nothing of the boundary being closer than `r` (a distance query, done by
//! the tracer), the ball does not poke through a face or a curved edge it touches.

use crate::medial::equations::NormalField;
use crate::model::{Element, Model};

/// Rounding allowance of the criterion `r·κmax ≤ 1`, relative (balls that osculate exactly,
/// a sphere's centre).
pub const CURVATURE_ROUNDING_REL: f64 = 1e-9;

/// The curvature criterion at a touch point: a ball of radius `r` tangent to the face from
/// inside stays inside near the touch point only if `r·κmax ≤ 1`, with `κmax` the larger
/// principal curvature (positive where the face bends towards the ball, as a convex solid's
/// boundary does). Where the normal is undefined (a pole) the criterion cannot fail.
///
/// On a reflex edge touched at `s = (t, θ)` the same holds along the edge: a curved edge
/// whose curvature vector points towards the centre (a hole's rim seen from inside the
/// hole) enters the ball near the touch point unless `r·κn ≤ 1`, `κn` the normal curvature
/// of the edge in the direction of the centre, `−C''·N/|C'|²` (`N` ⊥ `C'`). A vertex is a
/// point: the criterion cannot fail there.
pub fn curvature_allows(model: &Model, seg: Element, s: [f64; 2], r: f64) -> bool {
    bending(model, seg, s).is_none_or(|k| r * k <= 1.0 + CURVATURE_ROUNDING_REL)
}

/// How strongly the segment bends towards a ball touching it at `s` (1/mm): the larger
/// principal curvature of a face, the normal curvature `−C''·N/|C'|²` of a reflex edge in
/// the direction of the centre, 0 at a vertex (see [`curvature_allows`]). Negative where it
/// bends away; `None` where it is undefined (a pole, a vanishing tangent).
pub fn bending(model: &Model, seg: Element, s: [f64; 2]) -> Option<f64> {
    match seg {
        Element::Face(f) => {
            let face = &model.faces[f];
            let d = crate::geom::eval_face(face, s[0], s[1]);
            crate::geom::principal_curvatures(&d, face.sign).map(|k| k.k1)
        }
        Element::Edge(e) => {
            let ev = seg.eval(model, s)?;
            let d = crate::geom::eval_curve(&model.edges[e].curve, s[0]);
            let speed2 = d.d1.length_squared();
            (speed2 > 0.0 && speed2.is_finite()).then(|| -d.d2.dot(ev.n) / speed2)
        }
        Element::Vertex(_) => Some(0.0),
    }
}

/// The ball that osculates face `f` at its point nearest `p` (`p` on the face: a vertex of
/// it): centre `P − n/κ1`, radius `1/κ1`, with `n` the outward normal and `κ1` the larger
/// principal curvature there, and the point's `(u, v)`. `None` where the face does not bend
/// towards the material there (`κ1 ≤ 0`), or its normal is undefined.
pub fn osculating_ball(
    model: &Model,
    f: usize,
    p: glam::DVec3,
) -> Option<(glam::DVec3, f64, [f64; 2])> {
    let face = &model.faces[f];
    let (u, v) = crate::geom::project_point(&face.surface, p, None)?;
    let d = crate::geom::eval_face(face, u, v);
    let n = crate::geom::unit_normal(&d, face.sign)?;
    let k = crate::geom::principal_curvatures(&d, face.sign)?;
    (k.k1 > 0.0 && k.k1.is_finite()).then(|| (d.p - n / k.k1, 1.0 / k.k1, [u, v]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sphere sample (radius 15, outward normals): a ball of radius 14 fits against its
    /// wall, one of radius 16 pokes through; a plane never fails.
    #[test]
    fn curvature_criterion_on_a_sphere() {
        let m = crate::testing::sample("sphere.step");
        let s = [1.0, 0.3];
        assert!(curvature_allows(&m, Element::Face(0), s, 14.0));
        assert!(curvature_allows(&m, Element::Face(0), s, 15.0));
        assert!(!curvature_allows(&m, Element::Face(0), s, 16.0));
        let b = crate::testing::sample("box.step");
        assert!(curvature_allows(&b, Element::Face(0), [1.0, 1.0], 1e6));
    }

    /// How a segment bends towards its ball: the sphere (radius 15) by 1/15 anywhere, the
    /// cylinder sample's lateral face (radius 10) by 1/10, a plane and a vertex not at all.
    #[test]
    fn bending_towards_the_ball() {
        let m = crate::testing::sample("sphere.step");
        let k = bending(&m, Element::Face(0), [1.0, 0.3]).unwrap();
        assert!((k - 1.0 / 15.0).abs() < 1e-9, "{k}");
        assert_eq!(bending(&m, Element::Vertex(0), [0.0, 0.0]), Some(0.0));
        let c = crate::testing::sample("cylinder.step");
        let ks: Vec<f64> = (0..c.faces.len())
            .filter_map(|f| bending(&c, Element::Face(f), [0.4, 0.4]))
            .collect();
        assert!(ks.iter().any(|k| (k - 0.1).abs() < 1e-9), "{ks:?}");
        assert!(
            ks.iter().all(|k| k.abs() < 1e-9 || (k - 0.1).abs() < 1e-9),
            "{ks:?}"
        );
        let b = crate::testing::sample("box.step");
        assert!(bending(&b, Element::Face(0), [1.0, 1.0]).unwrap().abs() < 1e-12);
    }

    /// The osculating ball at a vertex: on the sphere (radius 15) its centre and radius at
    /// any point, on the cylinder sample (radius 10) the axis point level with a rim vertex
    /// and r = 10; a plane bends nowhere (none).
    #[test]
    fn osculating_balls_at_vertices() {
        let m = crate::testing::sample("sphere.step");
        let p = glam::DVec3::new(9.0, 12.0, 0.0);
        let (c, r, _) = osculating_ball(&m, 0, p).unwrap();
        assert!(c.length() < 1e-9 && (r - 15.0).abs() < 1e-9, "{c} {r}");
        let m = crate::testing::sample("cylinder.step");
        // The end caps are planes: only the lateral face has balls.
        let balls: Vec<_> = (0..m.faces.len())
            .flat_map(|f| {
                Element::Face(f)
                    .vertices(&m)
                    .into_iter()
                    .map(move |v| (f, v))
            })
            .filter_map(|(f, v)| {
                let p = m.vertices[v].point;
                osculating_ball(&m, f, p).map(|b| (p, b))
            })
            .collect();
        assert!(!balls.is_empty());
        for (p, (c, r, _)) in balls {
            assert!((r - 10.0).abs() < 1e-9, "{r}");
            assert!(
                c.x.hypot(c.y) < 1e-9 && (c.z - p.z).abs() < 1e-9,
                "{c} for {p}"
            );
        }
        let b = crate::testing::sample("box.step");
        assert!(osculating_ball(&b, 0, b.vertices[0].point).is_none());
    }

    /// The boss on the plate (radius 12): the boss's base circle is a reflex edge. A ball
    /// whose centre lies towards the boss's axis from the rim fits against it only up to the
    /// rim's radius, 12; one on the far side is never stopped by the rim's curvature; a
    /// straight reflex edge never stops a ball.
    #[test]
    fn curvature_criterion_on_a_curved_reflex_edge() {
        use crate::geom::eval_curve;
        let m = crate::testing::sample("boss_on_plate.step");
        let class = crate::classify::classify(&m, &Default::default());
        let reflex = |e: &usize| class.edges[*e].kind == crate::classify::EdgeKind::Reflex;
        let straight = |e: &usize| matches!(m.edges[*e].curve, crate::model::Curve3D::Line(_));
        let rim = (0..m.edges.len())
            .filter(reflex)
            .find(|e| !straight(e))
            .expect("the boss's base circle is a curved reflex edge");
        let (lo, hi) = m.edges[rim].range;
        let t = 0.5 * (lo + hi);
        let d = eval_curve(&m.edges[rim].curve, t);
        let towards_axis = (d.d2 - d.d1 * (d.d2.dot(d.d1) / d.d1.length_squared())).normalize();
        // The angles whose normal puts the centre (at p − r·n) straight towards the axis,
        // and straight away from it.
        let angle_where = |share: f64| {
            (0..360)
                .map(|k| (k as f64).to_radians())
                .min_by_key(|&th| {
                    let n = Element::Edge(rim).eval(&m, [t, th]).unwrap().n;
                    ((n.dot(towards_axis) + share).abs() * 1e9) as i64
                })
                .unwrap()
        };
        let inner = [t, angle_where(1.0)];
        assert!(curvature_allows(&m, Element::Edge(rim), inner, 11.9));
        assert!(!curvature_allows(&m, Element::Edge(rim), inner, 12.1));
        let outer = [t, angle_where(-1.0)];
        assert!(curvature_allows(&m, Element::Edge(rim), outer, 1e6));
        let line = (0..m.edges.len()).filter(reflex).find(straight);
        if let Some(e) = line {
            let (lo, hi) = m.edges[e].range;
            assert!(curvature_allows(
                &m,
                Element::Edge(e),
                [0.5 * (lo + hi), 0.3],
                1e6
            ));
        }
    }
}
