//! The analytic surfaces (plane, sphere, cylinder, cone, torus) and the surface of revolution
//! in closed form, with their first and second derivatives in one pass (one `sin_cos` per
//! angle).
//!
//! They read truck's own parameters (`origin()`, `axis()`, `radius()`, …) so that the
//! parametrisation is exactly truck's; truck's transform (`Processor`) and orientation flag
//! (which swaps `u` and `v`) are applied afterwards ([`processed`]). An affine transform maps
//! points and vectors; a projective one goes through the quotient rule.

use super::curves::eval_line;
use super::derivs::{point3, vec3, CurveDerivs, SurfaceDerivs};
use super::rational::rational_surface;
use glam::{DMat4, DVec3};
use truck_geometry::prelude::Matrix4;
use truck_stepio::r#in::alias::ElementarySurface;

pub(super) fn eval_elementary(e: &ElementarySurface, u: f64, v: f64) -> SurfaceDerivs {
    match e {
        ElementarySurface::Plane(pl) => {
            let (o, a, b) = (point3(pl.origin()), vec3(pl.u_axis()), vec3(pl.v_axis()));
            SurfaceDerivs {
                p: o + a * u + b * v,
                su: a,
                sv: b,
                suu: DVec3::ZERO,
                suv: DVec3::ZERO,
                svv: DVec3::ZERO,
            }
        }
        ElementarySurface::Sphere(pr) => {
            let sphere = pr.entity().0;
            let (c, r) = (point3(sphere.center()), sphere.radius());
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                local_sphere(c, r, u, v)
            })
        }
        ElementarySurface::ToroidalSurface(pr) => {
            let torus = pr.entity();
            let c = point3(torus.center());
            let (big, small) = (torus.large_radius(), torus.small_radius());
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                local_torus(c, big, small, u, v)
            })
        }
        ElementarySurface::CylindricalSurface(pr) | ElementarySurface::ConicalSurface(pr) => {
            let rev = pr.entity();
            let (o, a) = (point3(rev.origin()), vec3(rev.axis()));
            let line = rev.entity_curve();
            processed(pr.transform(), pr.orientation(), u, v, |u, v| {
                revolve(o, a, eval_line(line, u), v)
            })
        }
    }
}

/// Applies a truck `Processor<_, Matrix4>`: orientation `false` swaps the parameters
/// (`S(u, v) = E(v, u)`), then the transform maps points and vectors.
#[inline]
pub(super) fn processed(
    m: &Matrix4,
    orientation: bool,
    u: f64,
    v: f64,
    local: impl FnOnce(f64, f64) -> SurfaceDerivs,
) -> SurfaceDerivs {
    let d = if orientation {
        local(u, v)
    } else {
        let d = local(v, u);
        SurfaceDerivs {
            p: d.p,
            su: d.sv,
            sv: d.su,
            suu: d.svv,
            suv: d.suv,
            svv: d.suu,
        }
    };
    transform_derivs(m, d)
}

/// Maps surface derivatives through a 4×4 homogeneous matrix. Affine matrices (what STEP
/// placements and unit scaling produce) map points and vectors directly; a projective matrix
/// is handled exactly by the quotient rule.
fn transform_derivs(m: &Matrix4, d: SurfaceDerivs) -> SurfaceDerivs {
    let m = DMat4::from_cols_array_2d(&(*m).into());
    let affine = m.x_axis.w == 0.0 && m.y_axis.w == 0.0 && m.z_axis.w == 0.0 && m.w_axis.w == 1.0;
    if affine {
        if m == DMat4::IDENTITY {
            return d;
        }
        SurfaceDerivs {
            p: m.transform_point3(d.p),
            su: m.transform_vector3(d.su),
            sv: m.transform_vector3(d.sv),
            suu: m.transform_vector3(d.suu),
            suv: m.transform_vector3(d.suv),
            svv: m.transform_vector3(d.svv),
        }
    } else {
        rational_surface(&[
            m * d.p.extend(1.0),
            m * d.su.extend(0.0),
            m * d.sv.extend(0.0),
            m * d.suu.extend(0.0),
            m * d.suv.extend(0.0),
            m * d.svv.extend(0.0),
        ])
    }
}

/// truck's `alias::Sphere` before its transform: `S(u, v) = c + r·(cos v cos u, cos v sin u,
/// sin v)` (longitude `u`, latitude `v`).
#[inline]
fn local_sphere(c: DVec3, r: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let radial = DVec3::new(cv * cu, cv * su, 0.0);
    SurfaceDerivs {
        p: c + r * DVec3::new(cv * cu, cv * su, sv),
        su: r * DVec3::new(-cv * su, cv * cu, 0.0),
        sv: r * DVec3::new(-sv * cu, -sv * su, cv),
        suu: -r * radial,
        suv: r * DVec3::new(sv * su, -sv * cu, 0.0),
        svv: -r * DVec3::new(cv * cu, cv * su, sv),
    }
}

/// truck's `Torus`: `S(u, v) = c + ((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`.
#[inline]
fn local_torus(c: DVec3, big: f64, small: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let rho = big + small * cv;
    let e_r = DVec3::new(cu, su, 0.0);
    let e_t = DVec3::new(-su, cu, 0.0);
    SurfaceDerivs {
        p: c + rho * e_r + DVec3::new(0.0, 0.0, small * sv),
        su: rho * e_t,
        sv: small * DVec3::new(-sv * cu, -sv * su, cv),
        suu: -rho * e_r,
        suv: -small * sv * e_t,
        svv: -small * DVec3::new(cv * cu, cv * su, sv),
    }
}

/// truck's `RevolutedCurve`: `S(u, v) = o + R(a, v)·(C(u) − o)` with `R(a, v)` the right-handed
/// rotation by `v` about the unit axis `a`. `∂R/∂v·w = R·(a × w)`, so
/// `Sv = R(a × w)`, `Suv = R(a × C′)`, `Svv = R(a × (a × w))` with `w = C − o`.
#[inline]
pub(super) fn revolve(o: DVec3, a: DVec3, c: CurveDerivs, v: f64) -> SurfaceDerivs {
    let (s, co) = v.sin_cos();
    // Rodrigues: R·w = w cos v + (a × w) sin v + a (a·w)(1 − cos v).
    let rot = |w: DVec3| w * co + a.cross(w) * s + a * (a.dot(w) * (1.0 - co));
    let w = c.p - o;
    let aw = a.cross(w);
    SurfaceDerivs {
        p: o + rot(w),
        su: rot(c.d1),
        sv: rot(aw),
        suu: rot(c.d2),
        suv: rot(a.cross(c.d1)),
        svv: rot(a.cross(aw)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::eval::eval_surface;
    use crate::model::Surface;
    use crate::testing::geometry::{
        assert_surface_fd, cone, cylinder, grid, p3, plane, rel, sphere, torus, v3,
    };
    use std::f64::consts::PI;
    use truck_geometry::prelude::{Invertible, ParametricSurface, Transformed};

    fn analytic_surfaces() -> Vec<(String, Surface)> {
        let base = [
            ("plane", plane()),
            ("sphere", sphere(2.5)),
            ("cylinder", cylinder(1.5)),
            ("torus", torus(3.0, 1.0)),
            ("cone", cone(1.5, 0.3)),
        ];
        // Each also with the orientation flag flipped (u and v swap) and scaled as a unit
        // conversion would.
        base.into_iter()
            .flat_map(|(name, s)| {
                let flipped = s.inverse().transformed(Matrix4::from_scale(25.4));
                [
                    (name.to_string(), s),
                    (format!("{name} inverted+scaled"), flipped),
                ]
            })
            .collect()
    }

    #[test]
    fn analytic_surfaces_match_finite_differences() {
        for (name, s) in analytic_surfaces() {
            let params = grid((-0.4, 2.0 * PI), (-1.2, 1.2), 9, &[], &[]);
            assert_surface_fd(&name, &s, &params);
        }
    }

    /// Our closed forms reproduce truck's parametrisation (the values), and truck's analytic
    /// derivatives, which are right for these kinds.
    #[test]
    fn analytic_surfaces_agree_with_truck() {
        for (name, s) in analytic_surfaces() {
            for (u, v) in grid((-0.4, 2.0 * PI), (-1.2, 1.2), 7, &[], &[]) {
                let d = eval_surface(&s, u, v);
                let scale = p3(s.subs(u, v)).length().max(1.0);
                let truck = [
                    (d.p, p3(s.subs(u, v))),
                    (d.su, v3(s.uder(u, v))),
                    (d.sv, v3(s.vder(u, v))),
                    (d.suu, v3(s.uuder(u, v))),
                    (d.suv, v3(s.uvder(u, v))),
                    (d.svv, v3(s.vvder(u, v))),
                ];
                for (k, (ours, theirs)) in truck.into_iter().enumerate() {
                    assert!(
                        rel(ours, theirs, scale) < 1e-12,
                        "{name} output {k} at ({u}, {v}): ours {ours:?}, truck {theirs:?}"
                    );
                }
            }
        }
    }

    /// A projective placement matrix (no STEP entity produces one, but `Matrix4` allows it)
    /// goes through the quotient rule: values equal truck's `subs`, derivatives pass the
    /// finite-difference check.
    #[test]
    fn projective_transform_uses_quotient_rule() {
        #[rustfmt::skip]
        let m = Matrix4::new(
            1.0, 0.2, 0.0, 0.05,
            0.0, 1.1, 0.3, 0.02,
            0.1, 0.0, 0.9, 0.01,
            0.5, -0.3, 0.2, 1.0,
        );
        let s = sphere(2.5).transformed(m);
        let params = grid((-0.4, 2.0 * PI), (-1.2, 1.2), 9, &[], &[]);
        assert_surface_fd("projected sphere", &s, &params);
        for (u, v) in params {
            let theirs = p3(s.subs(u, v));
            assert!(rel(eval_surface(&s, u, v).p, theirs, theirs.length()) < 1e-12);
        }
    }
}
