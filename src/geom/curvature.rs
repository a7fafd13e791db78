//! Unit normals, principal curvatures and principal directions of a surface point.
//!
//! Sign convention, the crate's throughout: curvatures are measured so that a **convex solid
//! has positive curvature** — the ball of radius R bounded by a sphere has `k1 = k2 = +1/R`,
//! the wall of a spherical void `−1/R`, a shaft's wall `(+1/R, 0)`, a hole's wall
//! `(0, −1/R)` sorted as `k1 = 0, k2 = −1/R`. Equivalently `k` is the normal curvature towards
//! the *inward* normal `−n`: `k(t) = II(t, t)/I(t, t)` with `II = ⟨S_xy, −n⟩`.
//!
//! The outward normal is `n = sign·(Su × Sv)/‖Su × Sv‖`, `sign = ±1` telling whether `Su × Sv`
//! points out of the material (the face's orientation, [`crate::model`]).
//!
//! Method (do Carmo, *Differential Geometry of Curves and Surfaces*, §3.3): build the
//! orthonormal tangent frame `e1 = Su/‖Su‖`, `e2 = n × e1`, express the second fundamental form
//! in it (a symmetric 2×2 matrix `[[a, b], [b, c]]`, i.e. the shape operator in an orthonormal
//! basis), and diagonalise it in closed form: `k1,2 = (a + c)/2 ± √(((a − c)/2)² + b²)`, first
//! principal direction at angle `θ = ½·atan2(2b, a − c)` from `e1`. This is well conditioned
//! everywhere, including at umbilics (any direction is principal there; we return `e1`), and
//! gives exactly orthogonal unit directions with `(d1, d2, n)` right-handed.

use super::eval::SurfaceDerivs;
use glam::DVec3;

/// Below this value of `‖Su × Sv‖ / (‖Su‖‖Sv‖)` (the sine of the angle between the
/// parameter directions) the parametrisation is treated as singular (a pole, an apex, a
/// degenerate edge) and no normal or curvature is returned. At `sin = 1e-10` the normal
/// computed from the cross product has lost about 6 of its 16 digits.
pub const SINGULAR_SIN: f64 = 1e-10;

/// Principal curvatures and directions at a surface point (convex solid ⇒ positive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// Larger principal curvature (1/length, model units).
    pub k1: f64,
    /// Smaller principal curvature, `k2 ≤ k1`.
    pub k2: f64,
    /// Unit principal direction of `k1` (tangent to the surface).
    pub d1: DVec3,
    /// Unit principal direction of `k2`, `d2 = n × d1` with `n` the outward normal.
    pub d2: DVec3,
    /// Mean curvature `H = (k1 + k2)/2`.
    pub mean: f64,
    /// Gaussian curvature `K = k1·k2`.
    pub gauss: f64,
}

/// The unit normal pointing out of the material, `sign·(Su × Sv)/‖Su × Sv‖`, or `None` where
/// the parametrisation is singular (see [`SINGULAR_SIN`]) or not finite.
pub fn unit_normal(d: &SurfaceDerivs, sign: f64) -> Option<DVec3> {
    let cross = d.su.cross(d.sv);
    let len = cross.length();
    let scale = d.su.length() * d.sv.length();
    if !(len.is_finite() && scale > 0.0 && len > SINGULAR_SIN * scale) {
        return None;
    }
    Some(cross * (sign.signum() / len))
}

/// Principal curvatures at a surface point, signed so that a convex solid is positive.
/// `sign` is `+1` when `Su × Sv` points out of the material, `−1` otherwise. `None` where
/// the parametrisation is singular ([`unit_normal`] is `None`).
pub fn principal_curvatures(d: &SurfaceDerivs, sign: f64) -> Option<Curvature> {
    let n = unit_normal(d, sign)?;
    let inward = -n;
    // Second fundamental form w.r.t. the inward normal.
    let l = d.suu.dot(inward);
    let m = d.suv.dot(inward);
    let nn = d.svv.dot(inward);

    // Orthonormal frame e1 = Su/‖Su‖, e2 = n × e1, and the parameter-space coordinates of
    // e1 = α·(Su, Sv), e2 = β·(Su, Sv): Sv = j12·e1 + j22·e2 with j12 = Sv·e1, j22 = Sv·e2.
    let j11 = d.su.length();
    let e1 = d.su / j11;
    let e2 = n.cross(e1);
    let j12 = d.sv.dot(e1);
    let j22 = d.sv.dot(e2);
    let (a0, b0, b1) = (1.0 / j11, -j12 / (j11 * j22), 1.0 / j22);
    // II in the orthonormal frame: [[a, b], [b, c]].
    let a = l * a0 * a0;
    let b = a0 * (l * b0 + m * b1);
    let c = l * b0 * b0 + 2.0 * m * b0 * b1 + nn * b1 * b1;

    let mean = 0.5 * (a + c);
    let half_diff = 0.5 * (a - c);
    let radius = half_diff.hypot(b);
    let (k1, k2) = (mean + radius, mean - radius);
    let theta = 0.5 * (2.0 * b).atan2(a - c);
    let (s, co) = theta.sin_cos();
    let d1 = e1 * co + e2 * s;
    let d2 = n.cross(d1);
    if !(k1.is_finite() && k2.is_finite()) {
        return None;
    }
    Some(Curvature {
        k1,
        k2,
        d1,
        d2,
        mean,
        gauss: a * c - b * b,
    })
}

#[cfg(test)]
mod tests {
    //! Closed forms. Tolerances: the quantities are computed from exact derivatives with a
    //! handful of products and one square root, so the error is a few ulps of the curvature
    //! scale; 1e-12 relative leaves ~10³ ulps of margin.

    use super::*;
    use crate::geom::eval::eval_surface;
    use crate::model::Surface;
    use crate::testing::geometry::{cylinder, plane, sphere, torus};
    use std::f64::consts::PI;
    use truck_geometry::prelude::{BSplineSurface, KnotVec, NurbsSurface, Point3, Vector4};

    const TOL: f64 = 1e-12;

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= TOL * scale
    }

    /// Normal curvature (convex ⇒ positive) of the surface in the 3D tangent direction `t`,
    /// from the fundamental forms: κ = II(α, α)/I(α, α) with `t = α₀Su + α₁Sv`.
    fn normal_curvature(d: &SurfaceDerivs, sign: f64, t: DVec3) -> f64 {
        let n = unit_normal(d, sign).unwrap();
        let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let (bu, bv) = (t.dot(d.su), t.dot(d.sv));
        let det = e * g - f * f;
        let (a0, a1) = ((g * bu - f * bv) / det, (e * bv - f * bu) / det);
        let (l, m, nn) = (-d.suu.dot(n), -d.suv.dot(n), -d.svv.dot(n));
        (a0 * a0 * l + 2.0 * a0 * a1 * m + a1 * a1 * nn)
            / (a0 * a0 * e + 2.0 * a0 * a1 * f + a1 * a1 * g)
    }

    /// Invariants every answer must satisfy: unit, orthogonal, tangent directions with
    /// (d1, d2, n) right-handed, normal curvatures k1 and k2 along them, k1 ≥ k2, H and K
    /// consistent, and Euler's theorem for a few other directions.
    fn check_invariants(d: &SurfaceDerivs, sign: f64, c: &Curvature) {
        let n = unit_normal(d, sign).unwrap();
        let scale = c.k1.abs().max(c.k2.abs()).max(1e-3);
        assert!(c.k1 >= c.k2);
        assert!((c.d1.length() - 1.0).abs() < TOL && (c.d2.length() - 1.0).abs() < TOL);
        assert!(c.d1.dot(c.d2).abs() < TOL && c.d1.dot(n).abs() < TOL && c.d2.dot(n).abs() < TOL);
        assert!((c.d1.cross(c.d2) - n).length() < TOL);
        assert!(
            close(normal_curvature(d, sign, c.d1), c.k1, scale),
            "k1 direction"
        );
        assert!(
            close(normal_curvature(d, sign, c.d2), c.k2, scale),
            "k2 direction"
        );
        assert!(close(c.mean, 0.5 * (c.k1 + c.k2), scale));
        assert!(close(c.gauss, c.k1 * c.k2, scale * scale));
        for phi in [0.3f64, 1.1, 2.0] {
            let t = c.d1 * phi.cos() + c.d2 * phi.sin();
            let euler = c.k1 * phi.cos().powi(2) + c.k2 * phi.sin().powi(2);
            assert!(close(normal_curvature(d, sign, t), euler, scale), "Euler");
        }
    }

    /// `sign` that makes the normal point along `outward`.
    fn sign_towards(d: &SurfaceDerivs, outward: DVec3) -> f64 {
        d.su.cross(d.sv).dot(outward).signum()
    }

    fn params() -> Vec<(f64, f64)> {
        let mut v = Vec::new();
        for i in 0..6 {
            for j in 0..5 {
                v.push((0.1 + 1.07 * i as f64, -1.3 + 0.61 * j as f64));
            }
        }
        v
    }

    #[test]
    fn sphere_ball_and_void() {
        let r = 2.5;
        let s = sphere(r);
        let centre = {
            // The centre is where the inward normal line of every point meets: p + r·(−n).
            let d = eval_surface(&s, 0.3, 0.2);
            let n = d.su.cross(d.sv).normalize();
            let c1 = d.p + r * n;
            let c2 = d.p - r * n;
            let d2 = eval_surface(&s, 2.0, -0.7);
            if (d2.p - c1).length() < (d2.p - c2).length() + 1e-9
                && ((d2.p - c1).length() - r).abs() < 1e-9
            {
                c1
            } else {
                c2
            }
        };
        for (u, v) in params() {
            let d = eval_surface(&s, u, v);
            assert!(((d.p - centre).length() - r).abs() < 1e-12 * r);
            let ball = sign_towards(&d, d.p - centre);
            let c = principal_curvatures(&d, ball).unwrap();
            assert!(
                close(c.k1, 1.0 / r, 1.0 / r) && close(c.k2, 1.0 / r, 1.0 / r),
                "{c:?}"
            );
            let n = unit_normal(&d, ball).unwrap();
            assert!((n - (d.p - centre) / r).length() < 1e-12);
            check_invariants(&d, ball, &c);
            let c = principal_curvatures(&d, -ball).unwrap();
            assert!(
                close(c.k1, -1.0 / r, 1.0 / r) && close(c.k2, -1.0 / r, 1.0 / r),
                "{c:?}"
            );
            check_invariants(&d, -ball, &c);
        }
    }

    /// Outer wall of a shaft (+1/R, 0) and wall of a hole (0, −1/R); the directions are
    /// circumferential and axial.
    #[test]
    fn cylinder_shaft_and_hole() {
        let r = 1.5;
        let s = cylinder(r);
        // The axis direction is the ruling: the direction along which the surface is straight.
        for (u, v) in params() {
            let d = eval_surface(&s, u, v);
            let axis = if d.suu.length() < 1e-12 { d.su } else { d.sv }.normalize();
            let radial = -(if d.suu.length() < 1e-12 { d.svv } else { d.suu }).normalize();
            let shaft = sign_towards(&d, radial);
            let c = principal_curvatures(&d, shaft).unwrap();
            assert!(
                close(c.k1, 1.0 / r, 1.0 / r) && close(c.k2, 0.0, 1.0 / r),
                "{c:?}"
            );
            assert!(c.d1.dot(axis).abs() < 1e-12 && c.d2.cross(axis).length() < 1e-12);
            check_invariants(&d, shaft, &c);
            let c = principal_curvatures(&d, -shaft).unwrap();
            assert!(
                close(c.k1, 0.0, 1.0 / r) && close(c.k2, -1.0 / r, 1.0 / r),
                "{c:?}"
            );
            assert!(c.d1.cross(axis).length() < 1e-12);
            check_invariants(&d, -shaft, &c);
        }
    }

    /// Solid torus (ring): outer equator k1 = 1/r, k2 = 1/(R + r); inner equator
    /// k1 = 1/r, k2 = −1/(R − r). truck's torus has the tube angle as the second parameter
    /// (in the local frame; the STEP placement keeps it), v = 0 on the outer equator.
    #[test]
    fn torus_equators() {
        let (big, small) = (3.0, 1.0);
        let s = torus(big, small);
        for u in [0.0, 0.7, 2.5, 4.0] {
            for (v, k2) in [(0.0, 1.0 / (big + small)), (PI, -1.0 / (big - small))] {
                let d = eval_surface(&s, u, v);
                // Outward = away from the tube's centre circle = −Svv direction (Svv = −r·n).
                let sign = sign_towards(&d, -d.svv);
                let c = principal_curvatures(&d, sign).unwrap();
                assert!(
                    close(c.k1, 1.0 / small, 1.0) && close(c.k2, k2, 1.0),
                    "v = {v}: {c:?}"
                );
                assert!(
                    c.d1.cross(d.sv).length() < 1e-12 * d.sv.length(),
                    "k1 along the tube"
                );
                check_invariants(&d, sign, &c);
            }
        }
        // Everywhere: K = cos v / (r (R + r cos v)), H from the closed form.
        for (u, v) in params() {
            let d = eval_surface(&s, u, v);
            let c = principal_curvatures(&d, sign_towards(&d, -d.svv)).unwrap();
            let k_tube = 1.0 / small;
            let k_ring = v.cos() / (big + small * v.cos());
            assert!(
                close(c.gauss, k_tube * k_ring, 1.0) && close(c.mean, 0.5 * (k_tube + k_ring), 1.0)
            );
        }
    }

    #[test]
    fn plane_is_flat() {
        let s = plane();
        for (u, v) in params() {
            let d = eval_surface(&s, u, v);
            for sign in [1.0, -1.0] {
                let c = principal_curvatures(&d, sign).unwrap();
                assert_eq!((c.k1, c.k2, c.mean, c.gauss), (0.0, 0.0, 0.0, 0.0));
                check_invariants(&d, sign, &c);
            }
        }
    }

    /// The saddle z = xy as a bilinear B-spline, material below (outward +z):
    /// H = xy/W³, K = −1/W⁴ with W² = 1 + x² + y² (graph formulas, sign flipped to our
    /// convex-positive convention).
    #[test]
    fn saddle_z_equals_xy() {
        let b = BSplineSurface::new(
            (KnotVec::bezier_knot(1), KnotVec::bezier_knot(1)),
            vec![
                vec![Point3::new(0.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)],
                vec![Point3::new(1.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0)],
            ],
        );
        let s = Surface::BSplineSurface(Box::new(b));
        for (x, y) in [(0.0, 0.0), (0.3, 0.6), (0.9, 0.2), (0.5, 0.5), (0.1, 0.95)] {
            let d = eval_surface(&s, x, y);
            assert!((d.p - DVec3::new(x, y, x * y)).length() < 1e-15);
            let c = principal_curvatures(&d, sign_towards(&d, DVec3::Z)).unwrap();
            let w2: f64 = 1.0 + x * x + y * y;
            let (h, k) = (x * y / w2.powf(1.5), -1.0 / (w2 * w2));
            assert!(
                close(c.mean, h, 1.0) && close(c.gauss, k, 1.0),
                "({x}, {y}): {c:?}"
            );
            assert!(c.k1 > 0.0 && c.k2 < 0.0);
            check_invariants(&d, 1.0, &c);
        }
        // At the origin: k = ±1 along the diagonals; along x = y the surface (z = t²) bends
        // away from the material below it, so that is the concave direction k2 = −1.
        let c = principal_curvatures(&eval_surface(&s, 0.0, 0.0), 1.0).unwrap();
        assert!(close(c.k1, 1.0, 1.0) && close(c.k2, -1.0, 1.0));
        let diag = DVec3::new(1.0, -1.0, 0.0).normalize();
        assert!(c.d1.cross(diag).length() < 1e-12);
    }

    /// A rational (NURBS) quarter cylinder: exact circle of radius R, so k = (1/R, 0) at
    /// every point — exercises the quotient rule's second derivatives.
    #[test]
    fn nurbs_cylinder_has_exact_curvature() {
        let r = 2.0;
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let arc = [(r, 0.0, 1.0), (r, r, w), (0.0, r, 1.0)];
        let cps = arc
            .iter()
            .map(|&(x, y, wt)| {
                [0.0, 3.0]
                    .iter()
                    .map(|&z| Vector4::new(x * wt, y * wt, z * wt, wt))
                    .collect()
            })
            .collect();
        let n = NurbsSurface::new(BSplineSurface::new(
            (KnotVec::bezier_knot(2), KnotVec::bezier_knot(1)),
            cps,
        ));
        let s = Surface::NurbsSurface(Box::new(n));
        for i in 0..=10 {
            let d = eval_surface(&s, i as f64 / 10.0, 0.37);
            let radial = DVec3::new(d.p.x, d.p.y, 0.0);
            assert!((radial.length() - r).abs() < 1e-14);
            let c = principal_curvatures(&d, sign_towards(&d, radial)).unwrap();
            assert!(close(c.k1, 1.0 / r, 1.0) && close(c.k2, 0.0, 1.0), "{c:?}");
            check_invariants(&d, sign_towards(&d, radial), &c);
        }
    }

    /// A B-spline with a collapsed boundary (all control points of the first row equal):
    /// Su = 0 there, so no normal and no curvature; one step inside, both exist.
    #[test]
    fn singular_points_give_none() {
        let apex = Point3::new(0.0, 0.0, 1.0);
        let b = BSplineSurface::new(
            (KnotVec::bezier_knot(1), KnotVec::bezier_knot(1)),
            vec![
                vec![apex, apex],
                vec![Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)],
            ],
        );
        let s = Surface::BSplineSurface(Box::new(b));
        let d = eval_surface(&s, 0.0, 0.5);
        assert!(d.sv.length() == 0.0);
        assert!(unit_normal(&d, 1.0).is_none() && principal_curvatures(&d, 1.0).is_none());
        let d = eval_surface(&s, 0.25, 0.5);
        assert!(unit_normal(&d, 1.0).is_some() && principal_curvatures(&d, 1.0).is_some());
        // Parallel derivatives (a folded parametrisation) are singular too.
        let folded = SurfaceDerivs {
            p: DVec3::ZERO,
            su: DVec3::X,
            sv: DVec3::new(2.0, 1e-13, 0.0),
            suu: DVec3::ZERO,
            suv: DVec3::ZERO,
            svv: DVec3::Y,
        };
        assert!(principal_curvatures(&folded, 1.0).is_none());
        let nan = SurfaceDerivs {
            su: DVec3::NAN,
            ..folded
        };
        assert!(unit_normal(&nan, 1.0).is_none());
    }
}
