//! IGES surfaces into truck surfaces, in model space (mm).
//!
//! The types are those the STEP reader produces: 108 and 190 planes, 192 cylinders, 194
//! cones, 196 spheres, 198 tori, 120 surfaces of revolution, 122 tabulated cylinders and 128
//! rational B-spline surfaces.
//!
//! Surfaces of revolution (120) whose generatrix is a line or a circular arc are recognised
//! as the analytic surface they are (cylinder, cone, sphere, torus), as FreeCAD writes its
//! cylinders and spheres that way; other 120s stay truck revolutions.

use super::ctx::Ctx;
use super::curve::{check_knots, SAME_WEIGHT_REL_FIRST};
use super::format::DirEntry;
use super::placement::{p3, v3};
use crate::error::Result;
use crate::ingest::transform::{apply, mat_mul, placed, to_matrix4, Mat4, IDENTITY};
use glam::DVec3;
use std::f64::consts::PI;
use truck_geometry::prelude::{
    BSplineSurface, KnotVec, Line, Matrix4, NurbsSurface, Plane, Point3, Processor, RevolutedCurve,
    Torus, Transformed, Vector3, Vector4,
};
use truck_stepio::r#in::alias::{
    Curve3D, ElementarySurface, Sphere, SphericalSurface, Surface, SweptCurve,
};

/// The frame matrix with columns x, y = z × x, z, origin (x made orthogonal to z).
fn frame(origin: DVec3, z: DVec3, x: Option<DVec3>) -> Option<Mat4> {
    let z = z.try_normalize()?;
    let x = x
        .map(|x| x - z * x.dot(z))
        .and_then(|x| x.try_normalize())
        .unwrap_or_else(|| z.any_orthonormal_vector());
    let y = z.cross(x);
    Some([
        [x.x, y.x, z.x, origin.x],
        [x.y, y.y, z.y, origin.y],
        [x.z, y.z, z.z, origin.z],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

impl Ctx<'_> {
    /// The surface of entity `de` in model space (mm); `outer` as for [`Ctx::curve`].
    pub fn surface(&self, de: usize, from: usize, outer: &Mat4) -> Result<Surface> {
        let e = self.entry(de, from)?;
        let m = self.place(outer, e)?;
        // Entities the surface refers to live in its definition space.
        let inner = mat_mul(outer, &self.transform_chain(e)?);
        let mm = self.mm;
        let elementary = |s: ElementarySurface| Surface::ElementarySurface(Box::new(s));
        match e.entity_type {
            108 => {
                let r = self.reals(e, 0, 4, "coefficients A, B, C, D")?;
                let n = DVec3::new(r[0], r[1], r[2]);
                let len2 = n.length_squared();
                if len2 <= 0.0 || len2.is_nan() {
                    return Err(self.err(de, "plane normal (A, B, C) is zero"));
                }
                let o = n * (r[3] / len2);
                let f = frame(o, n, None).ok_or_else(|| self.err(de, "bad normal"))?;
                Ok(elementary(ElementarySurface::Plane(plane_from(&mat_mul(&m, &f)))))
            }
            190 => {
                let o = self.point116(self.ptr(e, 0, "location")?, de)?;
                let n = self.direction123(self.ptr(e, 1, "normal")?, de)?;
                let x = self.opt_direction(e, 2, e.form == 1)?;
                let f = frame(o, n, x).ok_or_else(|| self.err(de, "bad normal"))?;
                Ok(elementary(ElementarySurface::Plane(plane_from(&mat_mul(&m, &f)))))
            }
            192 | 194 => {
                let o = self.point116(self.ptr(e, 0, "location")?, de)?;
                let z = self.direction123(self.ptr(e, 1, "axis")?, de)?;
                let radius = self.real(e, 2, "radius")?;
                let (angle, refk) = if e.entity_type == 194 {
                    (self.real(e, 3, "semi-angle")?.to_radians(), 4)
                } else {
                    (0.0, 3)
                };
                let x = self.opt_direction(e, refk, e.form == 1)?;
                if radius.is_nan() || radius < 0.0 || (e.entity_type == 192 && radius <= 0.0) {
                    return Err(self.err(de, format!("radius {radius}")));
                }
                if !(0.0..PI / 2.0).contains(&angle) {
                    return Err(self.err(de, format!("semi-angle {} degrees", angle.to_degrees())));
                }
                let f = frame(o, z, x).ok_or_else(|| self.err(de, "bad axis"))?;
                let f = mat_mul(&m, &f);
                Ok(elementary(if e.entity_type == 192 {
                    ElementarySurface::CylindricalSurface(cylinder(&f, radius * mm))
                } else {
                    ElementarySurface::ConicalSurface(cone(&f, radius * mm, angle))
                }))
            }
            196 => {
                let c = self.point116(self.ptr(e, 0, "centre")?, de)?;
                let radius = self.real(e, 1, "radius")?;
                let z = match e.form {
                    1 => Some(self.direction123(self.ptr(e, 2, "axis")?, de)?),
                    _ => None,
                };
                let x = self.opt_direction(e, 3, e.form == 1)?;
                if radius.is_nan() || radius <= 0.0 {
                    return Err(self.err(de, format!("radius {radius}")));
                }
                let f = frame(c, z.unwrap_or(DVec3::Z), x).ok_or_else(|| self.err(de, "bad axis"))?;
                Ok(elementary(ElementarySurface::Sphere(sphere(&mat_mul(&m, &f), radius * mm))))
            }
            198 => {
                let c = self.point116(self.ptr(e, 0, "centre")?, de)?;
                let z = self.direction123(self.ptr(e, 1, "axis")?, de)?;
                let big = self.real(e, 2, "major radius")?;
                let small = self.real(e, 3, "minor radius")?;
                let x = self.opt_direction(e, 4, e.form == 1)?;
                if !(big > 0.0 && small > 0.0) {
                    return Err(self.err(de, format!("radii {big} and {small}")));
                }
                let f = frame(c, z, x).ok_or_else(|| self.err(de, "bad axis"))?;
                Ok(elementary(ElementarySurface::ToroidalSurface(torus(&mat_mul(&m, &f), big * mm, small * mm))))
            }
            120 => self.revolution(e, &inner),
            122 => {
                let seg = self.curve(self.ptr(e, 0, "directrix")?, de, &inner)?;
                let r = self.reals(e, 1, 3, "generatrix end point")?;
                let l = apply(&m, DVec3::new(r[0], r[1], r[2]));
                let v = l - seg.start();
                if v.length() <= 0.0 {
                    return Err(self.err(de, "generatrix of zero length"));
                }
                Ok(Surface::SweptCurve(Box::new(SweptCurve::ExtrudedCurve(
                    truck_geometry::prelude::ExtrudedCurve::by_extrusion(seg.curve, v3(v)),
                ))))
            }
            128 => {
                let s = self.bspline_surface(e)?;
                Ok(placed(s, &m))
            }
            t => Err(self.err(de, format!("surface entity type {t} is not supported (supported: 108, 120, 122, 128, 190, 192, 194, 196, 198)"))),
        }
    }

    fn opt_direction(&self, e: &DirEntry, k: usize, wanted: bool) -> Result<Option<DVec3>> {
        if !wanted {
            return Ok(None);
        }
        match e.params.get(k).and_then(|t| t.int()) {
            Some(p) if p > 0 => Ok(Some(self.direction123(p as usize, e.de)?)),
            _ => Ok(None),
        }
    }

    /// Entity 120; `inner` = the transformations of the 120 and what it is used in.
    fn revolution(&self, e: &DirEntry, inner: &Mat4) -> Result<Surface> {
        let de = e.de;
        let axis = self.curve(self.ptr(e, 0, "axis line")?, de, inner)?;
        let gen_de = self.ptr(e, 1, "generatrix")?;
        let gen = self.curve(gen_de, de, inner)?;
        let (a0, a1) = (axis.at(0.0), axis.at(1.0));
        let z = (a1 - a0)
            .try_normalize()
            .ok_or_else(|| self.err(de, "axis of zero length"))?;
        let sa = self.real(e, 2, "start angle")?;
        let ta = self.real(e, 3, "terminate angle")?;
        if ta.is_nan() || sa.is_nan() || ta <= sa {
            return Err(self.err(de, format!("angles [{sa}, {ta}] are empty")));
        }
        let elementary = |s: ElementarySurface| Surface::ElementarySurface(Box::new(s));
        let rel = |p: DVec3| {
            let d = p - a0;
            let h = d.dot(z);
            (h, (d - z * h).length(), d - z * h)
        };
        let size = gen
            .start()
            .distance(gen.end())
            .max(a0.distance(a1))
            .max(1.0);
        let tol = 1e-9 * size;
        match &gen.curve {
            Curve3D::Line(_) => {
                let (h0, r0, x0) = rel(gen.start());
                let (h1, r1, x1) = rel(gen.end());
                // The line must lie in a plane through the axis.
                let coplanar = x0.cross(x1).length() <= tol * (r0 + r1 + 1.0);
                if coplanar && (h1 - h0).abs() > tol {
                    let x = if r0 >= r1 { x0 } else { x1 };
                    if (r1 - r0).abs() <= tol && r0 > tol {
                        let f = frame(a0, z, Some(x)).unwrap_or(IDENTITY);
                        return Ok(elementary(ElementarySurface::CylindricalSurface(cylinder(
                            &f, r0,
                        ))));
                    }
                    if x.length() > tol {
                        // Cone: radius r0 at height h0, growing by (r1 − r0)/(h1 − h0) per unit
                        // height. Keep the frame's z so that the radius grows along it.
                        let slope = (r1 - r0) / (h1 - h0);
                        let (zz, slope) = if slope >= 0.0 {
                            (z, slope)
                        } else {
                            (-z, -slope)
                        };
                        let o = a0 + z * h0;
                        let f = frame(o, zz, Some(x)).unwrap_or(IDENTITY);
                        return Ok(elementary(ElementarySurface::ConicalSurface(cone(
                            &f,
                            r0,
                            slope.atan(),
                        ))));
                    }
                }
            }
            Curve3D::Conic(_) => {
                // A circular arc (100) has its centre in the entity; recover it from three
                // points on the arc.
                let c = circle_centre(
                    gen.at_fraction(0.0),
                    gen.at_fraction(0.5),
                    gen.at_fraction(1.0),
                );
                if let Some((centre, radius, normal)) = c {
                    let (hc, rc, xc) = rel(centre);
                    // The arc's plane contains the axis: its normal is perpendicular to it.
                    if normal.dot(z).abs() <= 1e-9 {
                        if rc <= tol {
                            let f = frame(a0 + z * hc, z, None).unwrap_or(IDENTITY);
                            return Ok(elementary(ElementarySurface::Sphere(sphere(&f, radius))));
                        }
                        if radius < rc {
                            let f = frame(a0 + z * hc, z, Some(xc)).unwrap_or(IDENTITY);
                            return Ok(elementary(ElementarySurface::ToroidalSurface(torus(
                                &f, rc, radius,
                            ))));
                        }
                    }
                }
            }
            _ => {}
        }
        let mut rev = Processor::new(RevolutedCurve::by_revolution(
            gen.curve.clone(),
            p3(a0),
            v3(z),
        ));
        truck_geometry::prelude::Invertible::invert(&mut rev);
        Ok(Surface::SweptCurve(Box::new(SweptCurve::RevolutedCurve(
            rev,
        ))))
    }

    fn bspline_surface(&self, e: &DirEntry) -> Result<Surface> {
        let de = e.de;
        let k1 = self.count(e, 0, "K1")?;
        let k2 = self.count(e, 1, "K2")?;
        let m1 = self.count(e, 2, "M1")?;
        let m2 = self.count(e, 3, "M2")?;
        if m1 == 0 || m2 == 0 {
            return Err(self.err(de, "degree 0"));
        }
        let polynomial = self.int(e, 6, "PROP3")? == 1;
        let (n1, n2) = (k1 + m1 + 2, k2 + m2 + 2);
        let base = 9;
        let s = self.reals(e, base, n1, "u knots")?;
        let t = self.reals(e, base + n1, n2, "v knots")?;
        let np = (k1 + 1) * (k2 + 1);
        let w = self.reals(e, base + n1 + n2, np, "weights")?;
        let x = self.reals(e, base + n1 + n2 + np, 3 * np, "control points")?;
        self.reals(e, base + n1 + n2 + 4 * np, 4, "U0, U1, V0, V1")?;
        check_knots(&s).map_err(|r| self.err(de, format!("u {r}")))?;
        check_knots(&t).map_err(|r| self.err(de, format!("v {r}")))?;
        if w.iter().any(|w| *w <= 0.0) {
            return Err(self.err(de, "weights must be positive"));
        }
        let rational = !polynomial
            && w.iter()
                .any(|x| (x - w[0]).abs() > SAME_WEIGHT_REL_FIRST * w[0]);
        let idx = |i: usize, j: usize| i + j * (k1 + 1);
        let kv = (KnotVec::from(s), KnotVec::from(t));
        let bad = |x: truck_geometry::errors::Error| self.err(de, x.to_string());
        Ok(if rational {
            let cps: Vec<Vec<Vector4>> = (0..=k1)
                .map(|i| {
                    (0..=k2)
                        .map(|j| {
                            let q = idx(i, j);
                            let ww = w[q];
                            Vector4::new(x[3 * q] * ww, x[3 * q + 1] * ww, x[3 * q + 2] * ww, ww)
                        })
                        .collect()
                })
                .collect();
            Surface::NurbsSurface(Box::new(NurbsSurface::new(
                BSplineSurface::try_new(kv, cps).map_err(bad)?,
            )))
        } else {
            let cps: Vec<Vec<Point3>> = (0..=k1)
                .map(|i| {
                    (0..=k2)
                        .map(|j| {
                            let q = idx(i, j);
                            Point3::new(x[3 * q], x[3 * q + 1], x[3 * q + 2])
                        })
                        .collect()
                })
                .collect();
            Surface::BSplineSurface(Box::new(BSplineSurface::try_new(kv, cps).map_err(bad)?))
        })
    }
}

fn col(m: &Mat4, j: usize) -> DVec3 {
    DVec3::new(m[0][j], m[1][j], m[2][j])
}

/// A plane with `Su = x`, `Sv = y` of the frame (normal = its z).
fn plane_from(f: &Mat4) -> Plane {
    let o = col(f, 3);
    Plane::new(p3(o), p3(o + col(f, 0)), p3(o + col(f, 1)))
}

/// A cylinder of radius `r` about the frame's z axis, built as the STEP reader builds
/// `CYLINDRICAL_SURFACE`.
fn cylinder(f: &Mat4, r: f64) -> truck_stepio::r#in::alias::CylindricalSurface {
    let (x, z, c) = (col(f, 0).normalize(), col(f, 2).normalize(), col(f, 3));
    let p = c + x * r;
    let mut s = Processor::new(RevolutedCurve::by_revolution(
        Line(p3(p), p3(p + z)),
        p3(c),
        v3(z),
    ));
    truck_geometry::prelude::Invertible::invert(&mut s);
    s
}

/// A cone of radius `r` at the frame's origin and semi-angle `angle`, opening along z, built
/// as the STEP reader builds `CONICAL_SURFACE`.
fn cone(f: &Mat4, r: f64, angle: f64) -> truck_stepio::r#in::alias::ConicalSurface {
    let p = Point3::new(r, 0.0, 0.0);
    let v = Vector3::new(angle.tan(), 0.0, 1.0);
    let rev = RevolutedCurve::by_revolution(
        Line(p, p + v),
        Point3::new(0.0, 0.0, 0.0),
        Vector3::unit_z(),
    );
    let mut s = Processor::new(rev);
    s.transform_by(to_matrix4(&orthonormal(f)));
    truck_geometry::prelude::Invertible::invert(&mut s);
    s
}

fn sphere(f: &Mat4, r: f64) -> SphericalSurface {
    let s = Sphere(truck_geometry::prelude::Sphere::new(
        Point3::new(0.0, 0.0, 0.0),
        r,
    ));
    placed(Processor::new(s), &orthonormal(f))
}

fn torus(f: &Mat4, big: f64, small: f64) -> Processor<Torus, Matrix4> {
    let t = Torus::new(Point3::new(0.0, 0.0, 0.0), big, small);
    placed(Processor::new(t), &orthonormal(f))
}

/// `f` with unit axes (the frame's scale goes into the radii, which are already in mm).
fn orthonormal(f: &Mat4) -> Mat4 {
    let mut r = *f;
    for j in 0..3 {
        let l = col(f, j).length();
        if l > 0.0 {
            for row in r.iter_mut().take(3) {
                row[j] /= l;
            }
        }
    }
    r
}

/// Centre, radius and unit normal of the circle through three points.
fn circle_centre(a: DVec3, b: DVec3, c: DVec3) -> Option<(DVec3, f64, DVec3)> {
    let (u, v) = (b - a, c - a);
    let n = u.cross(v);
    let n2 = n.length_squared();
    if n2 <= 1e-24 * u.length_squared() * v.length_squared() {
        // Start = end (a full circle): use the midpoint as the antipode of the start.
        return None;
    }
    let centre = a + (v * u.length_squared() - u * v.length_squared()).cross(n) / (2.0 * n2);
    Some((centre, centre.distance(a), n / n2.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::eval_surface;
    use crate::ingest::iges::ctx::with_ctx;
    use crate::testing::IgesEntity;

    const TOL: f64 = 1e-9;

    /// Samples `surface` on a grid over `u` × `v` and returns the worst |g(point)|.
    fn worst(surface: &Surface, u: (f64, f64), v: (f64, f64), g: impl Fn(DVec3) -> f64) -> f64 {
        let mut w: f64 = 0.0;
        for i in 0..=6 {
            for j in 0..=6 {
                let a = u.0 + (u.1 - u.0) * i as f64 / 6.0;
                let b = v.0 + (v.1 - v.0) * j as f64 / 6.0;
                w = w.max(g(eval_surface(surface, a, b).p).abs());
            }
        }
        w
    }

    /// The surface's parameter ranges, unbounded ends replaced by 0 / 1.
    fn finite_ranges(s: &Surface) -> ((f64, f64), (f64, f64)) {
        use std::ops::Bound;
        let end = |b: Bound<f64>, d: f64| match b {
            Bound::Included(x) | Bound::Excluded(x) if x.is_finite() => x,
            _ => d,
        };
        let (u, v) = crate::geom::parameter_range(s);
        (
            (end(u.0, 0.0), end(u.1, 1.0)),
            (end(v.0, 0.0), end(v.1, 1.0)),
        )
    }

    #[test]
    fn rational_bspline_surface_quarter_cylinder() {
        // u: the quarter circle above (K1 = 2, M1 = 2); v: a line along z (K2 = 1, M2 = 1) of
        // length 3. Points indexed with u fastest.
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let ring = |z: f64| format!("1.,0.,{z},1.,1.,{z},0.,1.,{z}");
        let params = format!(
            "2,1,2,1,0,0,0,0,0,0.,0.,0.,1.,1.,1.,0.,0.,1.,1.,1.,{w},1.,1.,{w},1.,{},{},0.,1.,0.,1.",
            ring(0.0),
            ring(3.0)
        );
        let e = [(128, 0, 0, params.as_str())];
        with_ctx(&e, 2, |ctx| {
            let s = ctx.surface(1, 1, &IDENTITY).unwrap();
            assert!(matches!(s, Surface::NurbsSurface(_)));
            let g = worst(&s, (0.0, 1.0), (0.0, 1.0), |p| p.x.hypot(p.y) - 1.0);
            assert!(g < TOL, "{g}");
            let top = eval_surface(&s, 0.5, 1.0).p;
            assert!((top.z - 3.0).abs() < TOL);
        });
    }

    #[test]
    fn analytic_surfaces() {
        // 116 points and 123 directions shared by the surfaces.
        let base: Vec<IgesEntity> = vec![
            (116, 0, 0, "0.,0.,1.,0"),                // DE 1: location (0, 0, 1)
            (123, 0, 0, "0.,0.,1."),                  // DE 3: axis z
            (123, 0, 0, "1.,0.,0."),                  // DE 5: reference x
            (192, 1, 0, "1,3,2.,5"),                  // DE 7: cylinder radius 2
            (194, 1, 0, "1,3,2.,30.,5"),              // DE 9: cone radius 2 at z = 1, 30°
            (196, 1, 0, "1,2.5,3,5"),                 // DE 11: sphere radius 2.5
            (198, 1, 0, "1,3,5.,1.5,5"),              // DE 13: torus 5 / 1.5
            (190, 1, 0, "1,3,5"),                     // DE 15: plane z = 1
            (108, 0, 0, "0.,0.,2.,4.,0,0.,0.,0.,0."), // DE 17: plane 2z = 4
        ];
        with_ctx(&base, 2, |ctx| {
            let s = |de: usize| ctx.surface(de, de, &IDENTITY).unwrap();
            let kind = |de: usize| crate::geom::surface_kind(&s(de));
            assert_eq!(
                [7, 9, 11, 13, 15, 17].map(kind),
                ["cylinder", "cone", "sphere", "torus", "plane", "plane"]
            );
            let r = |p: DVec3| p.x.hypot(p.y);
            let full = (0.0, std::f64::consts::TAU);
            assert!(worst(&s(7), full, (0.0, 3.0), |p| r(p) - 2.0) < TOL);
            let tan = 30f64.to_radians().tan();
            assert!(
                worst(&s(9), full, (0.0, 3.0), |p| r(p)
                    - (2.0 + (p.z - 1.0) * tan))
                    < TOL
            );
            let half = (-1.5, 1.5);
            assert!(worst(&s(11), full, half, |p| (p - DVec3::Z).length() - 2.5) < TOL);
            assert!(worst(&s(13), full, full, |p| (r(p) - 5.0).hypot(p.z - 1.0) - 1.5) < TOL);
            assert!(worst(&s(15), (-3.0, 3.0), (-3.0, 3.0), |p| p.z - 1.0) < TOL);
            assert!(worst(&s(17), (-3.0, 3.0), (-3.0, 3.0), |p| p.z - 2.0) < TOL);
            // Plane normals as given: +z.
            for de in [15, 17] {
                let d = eval_surface(&s(de), 0.3, 0.7);
                assert!(d.su.cross(d.sv).normalize().distance(DVec3::Z) < TOL);
            }
        });
    }

    #[test]
    fn surfaces_of_revolution_and_tabulated_cylinder() {
        let e: Vec<IgesEntity> = vec![
            (110, 0, 0, "0.,0.,0.,0.,0.,1."),                    // DE 1: axis z
            (110, 0, 0, "2.,0.,0.,2.,0.,5."),                    // DE 3: parallel line at 2
            (110, 0, 0, "1.,0.,0.,3.,0.,2."), // DE 5: slanted line in the xz plane
            (110, 0, 0, "1.,0.,0.,1.,1.,1."), // DE 7: skew line (hyperboloid)
            (100, 0, 11, "0.,0.,0.,3.,0.,-3.,0."), // DE 9: half circle r 3 about the origin
            (124, 0, 0, "1.,0.,0.,0.,0.,0.,-1.,0.,0.,1.,0.,0."), // DE 11: its plane → xz plane
            (100, 0, 11, "0.,6.,0.,7.,0.,7.,0."), // DE 13: circle r 1 at (6, 0, 0) in xz
            (120, 0, 0, "1,3,0.,6.283185307"), // DE 15: cylinder
            (120, 0, 0, "1,5,0.,6.283185307"), // DE 17: cone
            (120, 0, 0, "1,7,0.,6.283185307"), // DE 19: hyperboloid (generic)
            (120, 0, 0, "1,9,0.,6.283185307"), // DE 21: sphere
            (120, 0, 0, "1,13,0.,6.283185307"), // DE 23: torus
            (122, 0, 0, "3,2.,4.,0."),        // DE 25: line DE 3 swept by (0, 4, 0)
        ];
        with_ctx(&e, 2, |ctx| {
            let s = |de: usize| ctx.surface(de, de, &IDENTITY).unwrap();
            let kind = |de: usize| crate::geom::surface_kind(&s(de));
            assert_eq!(
                [15, 17, 19, 21, 23, 25].map(kind),
                [
                    "cylinder",
                    "cone",
                    "revolution",
                    "sphere",
                    "torus",
                    "extrusion"
                ]
            );
            let r = |p: DVec3| p.x.hypot(p.y);
            let full = (0.0, std::f64::consts::TAU);
            assert!(worst(&s(15), full, (0.0, 5.0), |p| r(p) - 2.0) < TOL);
            assert!(worst(&s(17), full, (0.0, 2.0), |p| r(p) - (1.0 + p.z)) < TOL);
            // Revolving (1, t, t): x² + y² = 1 + z². Its parameters: truck's revolution.
            let (ur, vr) = finite_ranges(&s(19));
            assert!(worst(&s(19), ur, vr, |p| r(p).powi(2) - 1.0 - p.z * p.z) < 1e-8);
            assert!(worst(&s(21), full, (-1.5, 1.5), |p| p.length() - 3.0) < TOL);
            assert!(worst(&s(23), full, full, |p| (r(p) - 6.0).hypot(p.z) - 1.0) < TOL);
            assert!(worst(&s(25), (0.0, 1.0), (0.0, 1.0), |p| p.x - 2.0) < TOL);
            let far = eval_surface(&s(25), 1.0, 1.0).p;
            assert!(far.distance(DVec3::new(2.0, 4.0, 5.0)) < TOL, "{far}");
        });
    }
}
