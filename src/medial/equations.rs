//! Boundary segments as normal fields, and the medial system `Pᵢ(sᵢ) − r·Nᵢ(sᵢ) − B = 0`.
//!
//! Unknowns are ordered `x = [B (3), r, s₁ (2), …, s_k (2)]`; residuals `[F₁ (3), …, F_k (3)]`.
//! The Jacobian is analytic: `∂Fᵢ/∂B = −I`, `∂Fᵢ/∂r = −Nᵢ`, `∂Fᵢ/∂sᵢ = ∂Pᵢ − r·∂Nᵢ`, where
//! for a face `N = m/‖m‖`, `m = σ·(Su × Sv)` and
//! `∂N = (∂m − N·(N·∂m)) / ‖m‖`, `∂m/∂u = σ·(Suu × Sv + Su × Suv)`,
//! `∂m/∂v = σ·(Suv × Sv + Su × Svv)` (σ = the face's `sign`). Reflex edges (`(t, θ)` in the
//! frame of [`edge_frame`]) and reflex vertices (`(φ, ψ)` in [`vertex_frame`]) are segments
//! with the same two-parameter interface ([`NormalField`]).

use crate::geom::{eval_curve, eval_face};
use crate::model::{Element, Model};
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

/// The fixed frame of vertex normals `[e₁, e₂, e₃]`: `e₃` is a direction no CAD part favours,
/// so a vertex's normal cone meets the frame's poles (where `φ` is undefined) only by accident.
pub fn vertex_frame() -> [DVec3; 3] {
    let e3 = DVec3::new(0.5, 0.7, 0.51).normalize();
    let e1 = e3.cross(DVec3::Z).normalize();
    [e1, e3.cross(e1), e3]
}

/// The parameters `(φ, ψ)` of a unit normal `n` of a vertex segment.
pub fn vertex_angles(n: DVec3) -> [f64; 2] {
    let [e1, e2, e3] = vertex_frame();
    [
        n.dot(e2).atan2(n.dot(e1)),
        n.dot(e3).clamp(-1.0, 1.0).asin(),
    ]
}

/// A normal field evaluated at one parameter: point, outward unit normal, and their
/// derivatives with respect to the two parameters.
#[derive(Clone, Copy, Debug)]
pub struct FieldEval {
    pub p: DVec3,
    pub n: DVec3,
    pub dp: [DVec3; 2],
    pub dn: [DVec3; 2],
}

/// A boundary element as a normal field `s ↦ (P(s), N(s))` over two parameters:
/// - a face, by its surface's `(u, v)`;
/// - a reflex edge, by `(t, θ)`: the curve parameter and the angle of the normal in the
///   edge's normal plane, `N = cos θ·a(t) + sin θ·b(t)` with the frame of [`edge_frame`] (the
///   paper's "cylinder of zero radius");
/// - a reflex (or mixed) vertex, by `(φ, ψ)`: the normal's longitude and latitude in a fixed
///   frame, `N = cos ψ·(cos φ·e₁ + sin φ·e₂) + sin ψ·e₃` (see [`vertex_frame`]).
pub trait NormalField {
    /// Evaluates the normal field at `s`. `None` where the normal is undefined (a pole, a
    /// point where an edge's tangent vanishes).
    fn eval(&self, model: &Model, s: [f64; 2]) -> Option<FieldEval>;
}

impl NormalField for Element {
    fn eval(&self, model: &Model, s: [f64; 2]) -> Option<FieldEval> {
        match *self {
            Element::Vertex(v) => {
                let [e1, e2, e3] = vertex_frame();
                let (sp, cp) = s[0].sin_cos();
                let (sq, cq) = s[1].sin_cos();
                let h = e1 * cp + e2 * sp;
                Some(FieldEval {
                    p: model.vertices[v].point,
                    n: h * cq + e3 * sq,
                    dp: [DVec3::ZERO, DVec3::ZERO],
                    dn: [(e2 * cp - e1 * sp) * cq, e3 * cq - h * sq],
                })
            }
            Element::Edge(e) => {
                let edge = &model.edges[e];
                let c = eval_curve(&edge.curve, s[0]);
                let w = edge_axis(edge);
                let fr = frame_with_derivatives(c.d1, c.d2, w)?;
                let (sn, cs) = s[1].sin_cos();
                let n = fr.a * cs + fr.b * sn;
                let dn_dt = fr.da * cs + fr.db * sn;
                let dn_dth = fr.b * cs - fr.a * sn;
                Some(FieldEval {
                    p: c.p,
                    n,
                    dp: [c.d1, DVec3::ZERO],
                    dn: [dn_dt, dn_dth],
                })
            }
            Element::Face(f) => {
                let face = &model.faces[f];
                let d = eval_face(face, s[0], s[1]);
                let m = (d.su.cross(d.sv)) * face.sign;
                let len = m.length();
                if !(len.is_finite() && len > 1e-12 * (d.su.length() * d.sv.length())) {
                    return None;
                }
                let n = m / len;
                let dm = [
                    (d.suu.cross(d.sv) + d.su.cross(d.suv)) * face.sign,
                    (d.suv.cross(d.sv) + d.su.cross(d.svv)) * face.sign,
                ];
                let dn = dm.map(|dmk| (dmk - n * n.dot(dmk)) / len);
                Some(FieldEval {
                    p: d.p,
                    n,
                    dp: [d.su, d.sv],
                    dn,
                })
            }
        }
    }
}

/// The orthonormal frame `(a, b)` of an edge's normal plane at a point with curve derivatives
/// `d1`, `d2`, and the frame's derivatives along the curve parameter.
#[derive(Clone, Copy, Debug)]
pub struct EdgeFrame {
    pub a: DVec3,
    pub b: DVec3,
    pub da: DVec3,
    pub db: DVec3,
}

/// `T = d1/‖d1‖`, `a = (T × w)/‖T × w‖`, `b = T × a` with a fixed axis `w` per edge (see
/// [`edge_axis`]); `None` where `d1` vanishes or `T ∥ w`.
fn frame_with_derivatives(d1: DVec3, d2: DVec3, w: DVec3) -> Option<EdgeFrame> {
    let len = d1.length();
    if !(len.is_finite() && len > 0.0) {
        return None;
    }
    let t = d1 / len;
    let dt = (d2 - t * t.dot(d2)) / len;
    let u = t.cross(w);
    let ul = u.length();
    if ul < 1e-6 {
        return None;
    }
    let a = u / ul;
    let du = dt.cross(w);
    let da = (du - a * a.dot(du)) / ul;
    let b = t.cross(a);
    let db = dt.cross(a) + t.cross(da);
    Some(EdgeFrame { a, b, da, db })
}

/// The frame of edge `e`'s normal plane at curve parameter `t` (see [`Element::Edge`]).
pub fn edge_frame(model: &Model, e: usize, t: f64) -> Option<EdgeFrame> {
    let edge = &model.edges[e];
    let c = eval_curve(&edge.curve, t);
    frame_with_derivatives(c.d1, c.d2, edge_axis(edge))
}

/// A fixed axis `w` for an edge's normal frame, as far from every tangent as cheaply known:
/// for a line, the coordinate axis least aligned with it; for a curve, the normal of the
/// plane of its tangents at the start, middle and end (exact for planar curves: circles,
/// ellipses, planar splines), falling back to the coordinate axis least aligned with the
/// middle tangent.
pub fn edge_axis(edge: &crate::model::Edge) -> DVec3 {
    let least_aligned = |t: DVec3| {
        let t = t.abs();
        if t.x <= t.y && t.x <= t.z {
            DVec3::X
        } else if t.y <= t.z {
            DVec3::Y
        } else {
            DVec3::Z
        }
    };
    let (lo, hi) = edge.range;
    let mid = eval_curve(&edge.curve, 0.5 * (lo + hi)).d1;
    if matches!(edge.curve, crate::model::Curve3D::Line(_)) {
        return least_aligned(mid);
    }
    let t0 = eval_curve(&edge.curve, lo).d1.normalize_or_zero();
    let t2 = eval_curve(&edge.curve, hi).d1.normalize_or_zero();
    let t1 = mid.normalize_or_zero();
    let n = t0.cross(t1) + t1.cross(t2);
    if n.length() > 1e-3 {
        n.normalize()
    } else {
        least_aligned(mid)
    }
}

/// The angle `θ` of a unit normal `n` in edge `e`'s frame at `t`.
pub fn edge_angle(model: &Model, e: usize, t: f64, n: DVec3) -> Option<f64> {
    let f = edge_frame(model, e, t)?;
    Some(n.dot(f.b).atan2(n.dot(f.a)))
}

/// The medial system for `k` segments: `3k` equations in `4 + 2k` unknowns.
#[derive(Clone, Debug)]
pub struct MedialSystem {
    pub segments: Vec<Element>,
}

impl MedialSystem {
    /// A system touching `segments`.
    pub fn new(segments: Vec<Element>) -> Self {
        MedialSystem { segments }
    }

    /// Number of unknowns, `4 + 2k`.
    pub fn unknowns(&self) -> usize {
        4 + 2 * self.segments.len()
    }

    /// Number of equations, `3k`.
    pub fn equations(&self) -> usize {
        3 * self.segments.len()
    }

    /// Residual and analytic Jacobian at `x`; `None` where a normal field is undefined.
    pub fn eval(&self, model: &Model, x: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let b = DVec3::new(x[0], x[1], x[2]);
        let r = x[3];
        let mut f = DVector::zeros(self.equations());
        let mut j = DMatrix::zeros(self.equations(), self.unknowns());
        for (i, seg) in self.segments.iter().enumerate() {
            let s = [x[4 + 2 * i], x[5 + 2 * i]];
            let e = seg.eval(model, s)?;
            let res = e.p - e.n * r - b;
            for c in 0..3 {
                let row = 3 * i + c;
                f[row] = res[c];
                j[(row, c)] = -1.0;
                j[(row, 3)] = -e.n[c];
                for k in 0..2 {
                    j[(row, 4 + 2 * i + k)] = e.dp[k][c] - r * e.dn[k][c];
                }
            }
        }
        Some((f, j))
    }

    /// The system made square by one linear equation `row·x = c` (a continuation equation:
    /// `t_B·(B − B_pred) = 0` across the centre's direction, or `r = 0`): residual `[F; row·x − c]`,
    /// Jacobian `[J; rowᵀ]`. Only for one equation fewer than unknowns (a seam).
    pub fn eval_with_row(
        &self,
        model: &Model,
        x: &DVector<f64>,
        row: &DVector<f64>,
        c: f64,
    ) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let (f, j) = self.eval(model, x)?;
        let n = x.len();
        let mut fa = DVector::zeros(n);
        fa.rows_mut(0, n - 1).copy_from(&f);
        fa[n - 1] = row.dot(x) - c;
        let mut ja = DMatrix::zeros(n, n);
        ja.view_mut((0, 0), (n - 1, n)).copy_from(&j);
        ja.row_mut(n - 1).copy_from(&row.transpose());
        Some((fa, ja))
    }

    /// Residual only.
    pub fn residual(&self, model: &Model, x: &DVector<f64>) -> Option<DVector<f64>> {
        self.eval(model, x).map(|(f, _)| f)
    }

    /// Central finite-difference Jacobian: the test oracle for [`Self::eval`]. `h` is the
    /// step in every unknown.
    pub fn jacobian_fd(&self, model: &Model, x: &DVector<f64>, h: f64) -> Option<DMatrix<f64>> {
        let mut j = DMatrix::zeros(self.equations(), self.unknowns());
        for c in 0..self.unknowns() {
            let mut xp = x.clone();
            let mut xm = x.clone();
            xp[c] += h;
            xm[c] -= h;
            let d = (self.residual(model, &xp)? - self.residual(model, &xm)?) / (2.0 * h);
            j.set_column(c, &d);
        }
        Some(j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::testing::sample;

    /// Analytic Jacobian against central differences on curved faces (sphere, torus,
    /// B-spline top, NURBS cylinder, fillets), at interior parameters of each face.
    ///
    /// Threshold: with h = 1e-6 the central-difference error is O(h²·‖F'''‖) ≈ 1e-12 plus
    /// rounding O(ε·‖F‖/h) ≈ 1e-10·size; 1e-6 relative to the largest entry leaves room
    /// while a wrong term (a missing r·∂N, a sign) is O(1) relative.
    #[test]
    fn analytic_jacobian_matches_finite_differences() {
        let mut checked = 0;
        for file in [
            "sphere.step",
            "torus.step",
            "box_bspline_top.step",
            "cylinder_nurbs.step",
            "filleted_box.step",
            "scad_rotate_extrude.step",
        ] {
            let m = sample(file);
            let faces: Vec<usize> = (0..m.faces.len()).collect();
            for chunk in faces.chunks(3) {
                let segs: Vec<Element> = chunk.iter().map(|&f| Element::Face(f)).collect();
                let sys = MedialSystem::new(segs.clone());
                let mut x = DVector::zeros(sys.unknowns());
                let (lo, hi) = m.bounding_box();
                let c = (lo + hi) * 0.5;
                x[0] = c.x + 0.3;
                x[1] = c.y - 0.2;
                x[2] = c.z + 0.1;
                x[3] = 0.17 * (hi - lo).length();
                for (i, &f) in chunk.iter().enumerate() {
                    let d = m.faces[f].domain;
                    x[4 + 2 * i] = d.u.0 + 0.37 * (d.u.1 - d.u.0);
                    x[5 + 2 * i] = d.v.0 + 0.61 * (d.v.1 - d.v.0);
                }
                let Some((_, ja)) = sys.eval(&m, &x) else {
                    continue;
                };
                let jf = sys.jacobian_fd(&m, &x, 1e-6).unwrap();
                let scale = ja.amax().max(1.0);
                let err = (&ja - &jf).amax();
                assert!(
                    err <= 1e-6 * scale,
                    "{file} faces {chunk:?}: |J − J_fd| = {err:e} (scale {scale})"
                );
                checked += 1;
            }
        }
        assert!(checked >= 8, "only {checked} systems checked");
    }

    /// The same check for reflex-edge and vertex segments: the boss's reflex foot circle
    /// (a curved edge, so ∂N/∂t involves the curve's second derivative), the L-bracket's
    /// straight reflex edge, and vertex normals at several angles; each with two faces.
    #[test]
    fn edge_and_vertex_jacobians_match_finite_differences() {
        let mut checked = 0;
        for file in ["boss_on_plate.step", "l_bracket.step"] {
            let m = sample(file);
            let class = crate::classify(&m, &Default::default());
            let reflex: Vec<usize> = (0..m.edges.len())
                .filter(|&e| class.edges[e].kind == crate::classify::EdgeKind::Reflex)
                .collect();
            assert!(!reflex.is_empty(), "{file}");
            let (lo, hi) = m.bounding_box();
            let c = (lo + hi) * 0.5;
            for (k, seg) in reflex
                .iter()
                .map(|&e| Element::Edge(e))
                .chain([Element::Vertex(0), Element::Vertex(m.vertices.len() - 1)])
                .enumerate()
            {
                let sys = MedialSystem::new(vec![seg, Element::Face(0), Element::Face(1)]);
                let mut x = DVector::zeros(sys.unknowns());
                x[0] = c.x + 0.3;
                x[1] = c.y - 0.2;
                x[2] = c.z + 0.1;
                x[3] = 7.3;
                x[4] = match seg {
                    Element::Edge(e) => {
                        let r = m.edges[e].range;
                        r.0 + 0.37 * (r.1 - r.0)
                    }
                    _ => 0.4 + 0.9 * k as f64,
                };
                x[5] = 0.3 + 0.7 * k as f64;
                for (i, f) in [0usize, 1].into_iter().enumerate() {
                    let d = m.faces[f].domain;
                    x[6 + 2 * i] = d.u.0 + 0.41 * (d.u.1 - d.u.0);
                    x[7 + 2 * i] = d.v.0 + 0.59 * (d.v.1 - d.v.0);
                }
                let (_, ja) = sys.eval(&m, &x).unwrap();
                let jf = sys.jacobian_fd(&m, &x, 1e-6).unwrap();
                let err = (&ja - &jf).amax();
                let scale = ja.amax().max(1.0);
                assert!(err <= 1e-6 * scale, "{file} {seg:?}: |J − J_fd| = {err:e}");
                checked += 1;
            }
        }
        assert!(checked >= 5, "only {checked} systems checked");
    }
}
