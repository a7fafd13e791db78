//! IGES curves and surfaces into truck geometry (the same types the STEP reader produces).
//!
//! Every entity is read in its definition space and moved by its transformation matrix
//! (entity 124, chained when a 124 points at another one) and then by the unit scale, so the
//! result is in millimetres in model space. A curve comes with its parameter interval from
//! its start to its end as the entity defines them (110 line: [0, 1]; 100 arc and 104 ellipse:
//! an angle interval from the start point counter-clockwise to the end point; 126: [V0, V1]).
//!
//! Surfaces of revolution (120) whose generatrix is a line or a circular arc are recognised
//! as the analytic surface they are (cylinder, cone, sphere, torus), as FreeCAD writes its
//! cylinders and spheres that way; other 120s stay truck revolutions.

use super::format::DirEntry;
use super::Ctx;
use crate::error::Result;
use glam::DVec3;
use std::f64::consts::PI;
use truck_geometry::prelude::{
    BSplineCurve, BSplineSurface, KnotVec, Line, Matrix4, NurbsCurve, NurbsSurface, Plane, Point3,
    Processor, RevolutedCurve, Torus, Transformed, TrimmedCurve, UnitCircle, Vector3, Vector4,
};
use truck_stepio::r#in::alias::{
    Conic3D, Curve3D, ElementarySurface, Sphere, SphericalSurface, Surface, SweptCurve,
};

pub use crate::ingest::records::{apply, mat_mul, placed, to_matrix4, Mat4, IDENTITY};

fn apply_dir(m: &Mat4, d: DVec3) -> DVec3 {
    let r = |i: usize| m[i][0] * d.x + m[i][1] * d.y + m[i][2] * d.z;
    DVec3::new(r(0), r(1), r(2))
}

fn p3(p: DVec3) -> Point3 {
    Point3::new(p.x, p.y, p.z)
}

fn v3(p: DVec3) -> Vector3 {
    Vector3::new(p.x, p.y, p.z)
}

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

/// Scales the first three columns (not the translation) of `m` by `sx, sy, sz`.
fn scaled(m: &Mat4, sx: f64, sy: f64, sz: f64) -> Mat4 {
    let mut r = *m;
    for row in r.iter_mut().take(3) {
        row[0] *= sx;
        row[1] *= sy;
        row[2] *= sz;
    }
    r
}

/// A 3D curve with its parameter interval, from the entity's start to its end.
#[derive(Clone, Debug)]
pub struct Segment {
    /// The entity the curve came from.
    pub de: usize,
    pub curve: Curve3D,
    pub range: (f64, f64),
}

impl Segment {
    pub fn at(&self, t: f64) -> DVec3 {
        use truck_geometry::prelude::ParametricCurve;
        let p = self.curve.subs(t);
        DVec3::new(p.x, p.y, p.z)
    }
    pub fn start(&self) -> DVec3 {
        self.at(self.range.0)
    }
    pub fn end(&self) -> DVec3 {
        self.at(self.range.1)
    }
    /// The point at fraction `s` of the parameter interval.
    pub fn at_fraction(&self, s: f64) -> DVec3 {
        self.at(self.range.0 + s * (self.range.1 - self.range.0))
    }
}

impl Ctx<'_> {
    /// The full placement of entity `e` used inside a parent whose own transformations are
    /// `outer` (definition space of the parent → model space): `S · outer · T(e)` with `S` the
    /// unit scale to mm.
    pub fn place(&self, outer: &Mat4, e: &DirEntry) -> Result<Mat4> {
        let t = self.transform_chain(e)?;
        let s = self.mm;
        Ok(mat_mul(&scaled(&IDENTITY, s, s, s), &mat_mul(outer, &t)))
    }

    /// The entity's own transformation (no units): its 124, composed with what that one
    /// points at in turn.
    pub fn transform_chain(&self, e: &DirEntry) -> Result<Mat4> {
        let mut m = IDENTITY;
        let mut next = e.transform;
        let mut from = e.de;
        let mut hops = 0;
        while next != 0 {
            hops += 1;
            if hops > 32 {
                return Err(self.err(
                    e.de,
                    "transformation matrices point at each other in a cycle",
                ));
            }
            let t = self.entry(next, from)?;
            if t.entity_type != 124 {
                return Err(self.err(
                    from,
                    format!(
                        "transformation matrix pointer to DE {next}, which is entity {}, not 124",
                        t.entity_type
                    ),
                ));
            }
            let r = self.reals(t, 0, 12, "matrix")?;
            let mine = [
                [r[0], r[1], r[2], r[3]],
                [r[4], r[5], r[6], r[7]],
                [r[8], r[9], r[10], r[11]],
                [0.0, 0.0, 0.0, 1.0],
            ];
            // The matrix a 124 points at is applied after it.
            m = mat_mul(&mine, &m);
            from = next;
            next = t.transform;
        }
        Ok(m)
    }

    /// A point entity (116) in the definition space of the entity that uses it (only its
    /// own transformation applied, no units).
    pub fn point116(&self, de: usize, from: usize) -> Result<DVec3> {
        let e = self.typed(de, from, &[116])?;
        let r = self.reals(e, 0, 3, "coordinates")?;
        Ok(apply(
            &self.transform_chain(e)?,
            DVec3::new(r[0], r[1], r[2]),
        ))
    }

    /// A direction entity (123) in the definition space of the entity that uses it (unit
    /// length).
    pub fn direction123(&self, de: usize, from: usize) -> Result<DVec3> {
        let e = self.typed(de, from, &[123])?;
        let r = self.reals(e, 0, 3, "components")?;
        apply_dir(&self.transform_chain(e)?, DVec3::new(r[0], r[1], r[2]))
            .try_normalize()
            .ok_or_else(|| self.err(de, "zero direction"))
    }

    /// The curve of entity `de` as one segment, in model space (mm); `outer` are the
    /// transformations of the entities it is used in (see [`Ctx::place`]). A 102 composite of
    /// more than one piece is refused (see [`Ctx::segments`]).
    pub fn curve(&self, de: usize, from: usize, outer: &Mat4) -> Result<Segment> {
        let e = self.entry(de, from)?;
        let m = self.place(outer, e)?;
        match e.entity_type {
            110 => {
                let r = self.reals(e, 0, 6, "end points")?;
                let a = apply(&m, DVec3::new(r[0], r[1], r[2]));
                let b = apply(&m, DVec3::new(r[3], r[4], r[5]));
                if a.distance(b) <= 0.0 {
                    return Err(self.err(de, "line of zero length"));
                }
                Ok(Segment {
                    de,
                    curve: Curve3D::Line(Line(p3(a), p3(b))),
                    range: (0.0, 1.0),
                })
            }
            100 => {
                let r = self.reals(e, 0, 7, "ZT, centre, start and end")?;
                let (zt, c, s, t) = (r[0], (r[1], r[2]), (r[3], r[4]), (r[5], r[6]));
                let rs = (s.0 - c.0).hypot(s.1 - c.1);
                let re = (t.0 - c.0).hypot(t.1 - c.1);
                if rs <= 0.0 || (rs - re).abs() > 1e-6 * rs.max(re) + 1e-9 {
                    return Err(self.err(
                        de,
                        format!("start and end are at different distances from the centre ({rs} and {re})"),
                    ));
                }
                let a0 = (s.1 - c.1).atan2(s.0 - c.0);
                let a1 = (t.1 - c.1).atan2(t.0 - c.0);
                let mut sweep = (a1 - a0).rem_euclid(2.0 * PI);
                // Start = end: a full circle (rounding can leave a hair of an angle either way).
                if !(1e-9..=2.0 * PI - 1e-9).contains(&sweep) {
                    sweep = 2.0 * PI;
                }
                let local = mat_mul(
                    &[
                        [1.0, 0.0, 0.0, c.0],
                        [0.0, 1.0, 0.0, c.1],
                        [0.0, 0.0, 1.0, zt],
                        [0.0, 0.0, 0.0, 1.0],
                    ],
                    &scaled(&rot_z(a0), rs, rs, rs),
                );
                Ok(Segment {
                    de,
                    curve: unit_circle(&mat_mul(&m, &local)),
                    range: (0.0, sweep),
                })
            }
            104 => {
                let r = self.reals(e, 0, 11, "coefficients, ZT, start and end")?;
                let (curve, range) = conic(&r, e.form).map_err(|why| self.err(de, why))?;
                Ok(Segment {
                    de,
                    curve: placed(curve, &m),
                    range,
                })
            }
            126 => {
                let (curve, range) = self.bspline_curve(e)?;
                Ok(Segment {
                    de,
                    curve: placed(curve, &m),
                    range,
                })
            }
            102 => {
                let mut segs = self.segments(de, from, outer)?;
                if segs.len() == 1 {
                    Ok(segs.remove(0))
                } else {
                    Err(self.err(
                        de,
                        format!(
                            "composite curve of {} pieces where one edge curve is expected",
                            segs.len()
                        ),
                    ))
                }
            }
            t => Err(self.err(
                de,
                format!(
                    "curve entity type {t} is not supported (supported: 100, 102, 104, 110, 126)"
                ),
            )),
        }
    }

    /// A curve split into its pieces: a 102 composite gives its members (recursively, in
    /// order), anything else itself.
    pub fn segments(&self, de: usize, from: usize, outer: &Mat4) -> Result<Vec<Segment>> {
        self.segments_at_depth(de, from, outer, 0)
    }

    fn segments_at_depth(
        &self,
        de: usize,
        from: usize,
        outer: &Mat4,
        depth: usize,
    ) -> Result<Vec<Segment>> {
        /// Composites nested deeper than this are taken for a cycle.
        const MAX_NESTING: usize = 16;
        let e = self.entry(de, from)?;
        if e.entity_type != 102 {
            return Ok(vec![self.curve(de, from, outer)?]);
        }
        if depth > MAX_NESTING {
            return Err(self.err(de, "composite curves nested too deep (a cycle?)"));
        }
        let n = self.count(e, 0, "number of curves")?;
        let m = mat_mul(outer, &self.transform_chain(e)?);
        let mut out = Vec::new();
        for k in 0..n {
            let c = self.ptr(e, 1 + k, "member curve")?;
            out.extend(self.segments_at_depth(c, de, &m, depth + 1)?);
        }
        Ok(out)
    }

    fn bspline_curve(&self, e: &DirEntry) -> Result<(Curve3D, (f64, f64))> {
        let de = e.de;
        let k = self.count(e, 0, "K (upper index)")?;
        let deg = self.count(e, 1, "M (degree)")?;
        if deg == 0 {
            return Err(self.err(de, "degree 0"));
        }
        let polynomial = self.int(e, 4, "PROP3")? == 1;
        let nk = k + deg + 2;
        let base = 6;
        let knots = self.reals(e, base, nk, "knots")?;
        let weights = self.reals(e, base + nk, k + 1, "weights")?;
        let pts = self.reals(e, base + nk + k + 1, 3 * (k + 1), "control points")?;
        let v = self.reals(e, base + nk + 4 * (k + 1), 2, "V0, V1")?;
        check_knots(&knots).map_err(|r| self.err(de, r))?;
        if weights.iter().any(|w| *w <= 0.0) {
            return Err(self.err(de, "weights must be positive"));
        }
        if v[0] >= v[1]
            || v[0].is_nan()
            || v[1].is_nan()
            || v[0] < knots[0] - 1e-12
            || v[1] > knots[nk - 1] + 1e-12
        {
            return Err(self.err(
                de,
                format!("parameter range [{}, {}] outside the knots", v[0], v[1]),
            ));
        }
        let kv = KnotVec::from(knots);
        let rational = !polynomial
            && weights
                .iter()
                .any(|w| (w - weights[0]).abs() > 1e-14 * weights[0]);
        let curve = if rational {
            let cps: Vec<Vector4> = (0..=k)
                .map(|i| {
                    let w = weights[i];
                    Vector4::new(pts[3 * i] * w, pts[3 * i + 1] * w, pts[3 * i + 2] * w, w)
                })
                .collect();
            Curve3D::NurbsCurve(NurbsCurve::new(
                BSplineCurve::try_new(kv, cps).map_err(|x| self.err(de, x.to_string()))?,
            ))
        } else {
            let cps: Vec<Point3> = (0..=k)
                .map(|i| Point3::new(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]))
                .collect();
            Curve3D::BSplineCurve(
                BSplineCurve::try_new(kv, cps).map_err(|x| self.err(de, x.to_string()))?,
            )
        };
        Ok((curve, (v[0], v[1])))
    }

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
        let rational = !polynomial && w.iter().any(|x| (x - w[0]).abs() > 1e-14 * w[0]);
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

fn check_knots(k: &[f64]) -> std::result::Result<(), String> {
    if k.windows(2).any(|w| w[1] < w[0]) {
        return Err("knots are not in non-decreasing order".into());
    }
    if k.first() == k.last() {
        return Err("knot vector has zero length".into());
    }
    Ok(())
}

/// A 104 conic arc in standard position (`A x² + C y² + F = 0`, or `A x² + E y = 0` /
/// `C y² + D x = 0` for a parabola) at height ZT, from its start to its end point, as a
/// truck curve in its definition space with its parameter interval (increasing). Ellipses run
/// counter-clockwise from start to end (a full ellipse when they coincide); hyperbola and
/// parabola arcs run from start to end along the branch.
fn conic(r: &[f64], form: i64) -> std::result::Result<(Curve3D, (f64, f64)), String> {
    let (a, b, c, d, e, f, zt) = (r[0], r[1], r[2], r[3], r[4], r[5], r[6]);
    let (x1, y1, x2, y2) = (r[7], r[8], r[9], r[10]);
    let big = [a, b, c, d, e, f]
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let zero = |x: f64| x.abs() <= 1e-9 * big;
    if big == 0.0 || !zero(b) {
        return Err("conic not in standard position (B must be 0)".into());
    }
    // Local 2D matrix applied to truck's unit curve, then the curve's parameters at the ends.
    let frame2 = |l: [[f64; 2]; 2]| -> Mat4 {
        [
            [l[0][0], l[0][1], 0.0, 0.0],
            [l[1][0], l[1][1], 0.0, 0.0],
            [0.0, 0.0, 1.0, zt],
            [0.0, 0.0, 0.0, 1.0],
        ]
    };
    // Reversed parameter for the odd unit coordinate: negate the second column, t → −t.
    let increasing = |mut l: [[f64; 2]; 2], t0: f64, t1: f64| {
        if t1 >= t0 {
            (l, (t0, t1))
        } else {
            l[0][1] = -l[0][1];
            l[1][1] = -l[1][1];
            (l, (-t0, -t1))
        }
    };
    match form {
        1 => {
            if !(zero(d) && zero(e)) {
                return Err("ellipse not in standard position (B, D, E must be 0)".into());
            }
            if !(a * f < 0.0 && c * f < 0.0) {
                return Err("coefficients do not describe a real ellipse".into());
            }
            let (sa, sb) = ((-f / a).sqrt(), (-f / c).sqrt());
            let t0 = (y1 / sb).atan2(x1 / sa);
            let t1 = (y2 / sb).atan2(x2 / sa);
            let mut sweep = (t1 - t0).rem_euclid(2.0 * PI);
            if !(1e-9..=2.0 * PI - 1e-9).contains(&sweep) {
                sweep = 2.0 * PI;
            }
            let local = mat_mul(
                &scaled(&frame2([[1.0, 0.0], [0.0, 1.0]]), sa, sb, sa.min(sb)),
                &rot_z(t0),
            );
            Ok((unit_circle(&local), (0.0, sweep)))
        }
        2 => {
            if !(zero(d) && zero(e)) || zero(a) || zero(c) || zero(f) || a * c >= 0.0 {
                return Err("hyperbola not in standard position (A x² + C y² + F = 0)".into());
            }
            let (l, t0, t1) = if a * f < 0.0 {
                // Transverse axis x: (±p cosh t, q sinh t).
                let (p, q) = ((-f / a).sqrt(), (f / c).sqrt());
                let sx = if x1 < 0.0 { -1.0 } else { 1.0 };
                (
                    [[sx * p, 0.0], [0.0, q]],
                    (y1 / q).asinh(),
                    (y2 / q).asinh(),
                )
            } else {
                // Transverse axis y: (p sinh t, ±q cosh t).
                let (p, q) = ((f / a).sqrt(), (-f / c).sqrt());
                let sy = if y1 < 0.0 { -1.0 } else { 1.0 };
                (
                    [[0.0, p], [sy * q, 0.0]],
                    (x1 / p).asinh(),
                    (x2 / p).asinh(),
                )
            };
            let (l, range) = increasing(l, t0, t1);
            let h: truck_stepio::r#in::alias::Hyperbola<Point3, Matrix4> = Processor::new(
                TrimmedCurve::new(truck_geometry::prelude::UnitHyperbola::new(), range),
            );
            Ok((
                Curve3D::Conic(Conic3D::Hyperbola(placed(h, &frame2(l)))),
                range,
            ))
        }
        3 => {
            // Unit parabola (t², 2t).
            let (l, t0, t1) = if zero(c) && zero(d) && zero(f) && !zero(a) && !zero(e) {
                // y = k x²: (2t, 4k t²), t = x / 2.
                let k = -a / e;
                ([[0.0, 1.0], [4.0 * k, 0.0]], x1 / 2.0, x2 / 2.0)
            } else if zero(a) && zero(e) && zero(f) && !zero(c) && !zero(d) {
                // x = k y²: (4k t², 2t), t = y / 2.
                let k = -c / d;
                ([[4.0 * k, 0.0], [0.0, 1.0]], y1 / 2.0, y2 / 2.0)
            } else {
                return Err(
                    "parabola not in standard position (A x² + E y = 0 or C y² + D x = 0)".into(),
                );
            };
            let (l, range) = increasing(l, t0, t1);
            let q: truck_stepio::r#in::alias::Parabola<Point3, Matrix4> = Processor::new(
                TrimmedCurve::new(truck_geometry::prelude::UnitParabola::new(), range),
            );
            Ok((
                Curve3D::Conic(Conic3D::Parabola(placed(q, &frame2(l)))),
                range,
            ))
        }
        f => Err(format!(
            "conic form {f} (1 ellipse, 2 hyperbola, 3 parabola)"
        )),
    }
}

fn rot_z(a: f64) -> Mat4 {
    let (s, c) = a.sin_cos();
    [
        [c, -s, 0.0, 0.0],
        [s, c, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// truck's unit circle `(cos t, sin t, 0)` moved by `m`.
fn unit_circle(m: &Mat4) -> Curve3D {
    let c: Processor<TrimmedCurve<UnitCircle<Point3>>, Matrix4> =
        Processor::new(TrimmedCurve::new(UnitCircle::new(), (0.0, 2.0 * PI)));
    Curve3D::Conic(Conic3D::Ellipse(placed(c, m)))
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
