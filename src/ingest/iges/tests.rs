//! Entity conversions against closed forms, on small files written here: the entity types
//! and variants the samples do not contain (104 ellipse, 194 cone, 198 torus, rational 126 /
//! 128, a generic 120, 122 over a line, 124 chains, units).

use super::format;
use super::geometry::IDENTITY;
use super::Ctx;
use crate::geom::eval_surface;
use crate::model::{Curve3D, Surface};
use glam::DVec3;
use std::path::Path;
use truck_geometry::prelude::ParametricCurve;

/// One entity: type, form, DE of its transformation matrix (0: none), parameters (without
/// the type number and the record delimiter).
type Spec<'a> = (i64, i64, usize, &'a str);

/// A fixed-format IGES file holding `entities` (DE numbers 1, 3, 5, … in order), with unit
/// flag `unit`.
fn file(entities: &[Spec], unit: i64) -> String {
    let mut d = vec![];
    let mut p: Vec<String> = vec![];
    for (k, (ty, form, tr, params)) in entities.iter().enumerate() {
        let de = 2 * k + 1;
        let first = p.len() + 1;
        // Split the record at delimiters into lines of at most 64 columns.
        let text = format!("{ty},{params};");
        let mut line = String::new();
        for piece in text.split_inclusive(',') {
            if line.len() + piece.len() > 64 {
                p.push(format!("{line:<64}{de:>8}P{:>7}", p.len() + 1));
                line.clear();
            }
            line.push_str(piece);
        }
        p.push(format!("{line:<64}{de:>8}P{:>7}", p.len() + 1));
        let count = p.len() + 1 - first;
        d.push(format!(
            "{ty:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{tr:>8}{:>8}{:>8}D{de:>7}",
            0, 0, 0, 0, 0, "00010000"
        ));
        d.push(format!(
            "{ty:>8}{:>8}{:>8}{count:>8}{form:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            0,
            0,
            "",
            "",
            "",
            0,
            de + 1
        ));
    }
    let g = format!(",,4Htest,,,,,,,,,,1.,{unit},,,,,1E-07,;");
    let mut out = vec![format!("{:<72}S{:>7}", "unit test", 1)];
    out.push(format!("{g:<72}G{:>7}", 1));
    out.extend(d.iter().cloned());
    out.extend(p.iter().cloned());
    out.push(format!(
        "{:<72}T{:>7}",
        format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, 1, d.len(), p.len()),
        1
    ));
    out.join("\n") + "\n"
}

fn with_ctx<T>(entities: &[Spec], unit: i64, f: impl FnOnce(&Ctx) -> T) -> T {
    let text = file(entities, unit);
    let parsed = format::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let (mm, _) = parsed.global.unit().unwrap();
    let ctx = Ctx {
        file: &parsed,
        path: Path::new("test.igs"),
        mm,
    };
    f(&ctx)
}

fn point(c: &Curve3D, t: f64) -> DVec3 {
    let p = c.subs(t);
    DVec3::new(p.x, p.y, p.z)
}

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

const TOL: f64 = 1e-9;

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
fn arc_with_chained_transforms() {
    // DE 1: arc in its XY plane at ZT = 2, centre (1, 0), from (3, 0) to (1, 2) (a quarter,
    // counter-clockwise), radius 2; DE 3: rotate 90° about x; DE 5: translate by (0, 0, 10),
    // applied after DE 3.
    let e = [
        (100, 0, 3, "2.,1.,0.,3.,0.,1.,2."),
        (124, 0, 5, "1.,0.,0.,0.,0.,0.,-1.,0.,0.,1.,0.,0."),
        (124, 0, 0, "1.,0.,0.,0.,0.,1.,0.,0.,0.,0.,1.,10."),
    ];
    with_ctx(&e, 2, |ctx| {
        let s = ctx.curve(1, 1, &IDENTITY).unwrap();
        // (x, y, z) → rotation about x: (x, −z, y), then + (0, 0, 10).
        let map = |p: DVec3| DVec3::new(p.x, -p.z, p.y + 10.0);
        assert!(s.start().distance(map(DVec3::new(3.0, 0.0, 2.0))) < TOL);
        assert!(s.end().distance(map(DVec3::new(1.0, 2.0, 2.0))) < TOL);
        let mid = s.at_fraction(0.5);
        let want = map(DVec3::new(1.0 + 2.0_f64.sqrt(), 2.0_f64.sqrt(), 2.0));
        assert!(mid.distance(want) < TOL, "{mid} vs {want}");
        assert!((s.range.1 - s.range.0 - std::f64::consts::FRAC_PI_2).abs() < TOL);
    });
    // Start = end: a full circle.
    with_ctx(&[(100, 0, 0, "0.,0.,0.,1.,0.,1.,0.")], 2, |ctx| {
        let s = ctx.curve(1, 1, &IDENTITY).unwrap();
        assert!((s.range.1 - s.range.0 - std::f64::consts::TAU).abs() < TOL);
        assert!(s.at_fraction(0.5).distance(DVec3::new(-1.0, 0.0, 0.0)) < TOL);
    });
}

#[test]
fn conic_arcs() {
    // x²/16 + y²/4 − 1 = 0 at ZT = 1, from (4, 0) counter-clockwise to (0, 2).
    let e = [(104, 1, 0, "0.0625,0.,0.25,0.,0.,-1.,1.,4.,0.,0.,2.")];
    with_ctx(&e, 2, |ctx| {
        let s = ctx.curve(1, 1, &IDENTITY).unwrap();
        assert!(s.start().distance(DVec3::new(4.0, 0.0, 1.0)) < TOL);
        assert!(s.end().distance(DVec3::new(0.0, 2.0, 1.0)) < TOL);
        for k in 0..=8 {
            let p = s.at_fraction(k as f64 / 8.0);
            let g = p.x * p.x / 16.0 + p.y * p.y / 4.0 - 1.0;
            assert!(g.abs() < TOL && (p.z - 1.0).abs() < TOL && p.x >= -TOL && p.y >= -TOL);
        }
    });
    // Hyperbola x² − y² = 1 (A = 1, C = −1, F = −1) from (cosh 0.5, −sinh 0.5) to
    // (cosh 1, sinh 1); and the left branch run downwards.
    let (c05, s05, c1, s1) = (0.5f64.cosh(), 0.5f64.sinh(), 1f64.cosh(), 1f64.sinh());
    for (x1, y1, x2, y2) in [(c05, -s05, c1, s1), (-c1, s1, -c05, -s05)] {
        let params = format!("1.,0.,-1.,0.,0.,-1.,0.,{x1},{y1},{x2},{y2}");
        let e = [(104, 2, 0, params.as_str())];
        with_ctx(&e, 2, |ctx| {
            let s = ctx.curve(1, 1, &IDENTITY).unwrap();
            assert!(
                s.start().distance(DVec3::new(x1, y1, 0.0)) < TOL,
                "{}",
                s.start()
            );
            assert!(
                s.end().distance(DVec3::new(x2, y2, 0.0)) < TOL,
                "{}",
                s.end()
            );
            for k in 0..=8 {
                let p = s.at_fraction(k as f64 / 8.0);
                assert!(
                    (p.x * p.x - p.y * p.y - 1.0).abs() < TOL && p.x * x1 > 0.0,
                    "{p}"
                );
            }
        });
    }
    // Parabola y = x²/4 (A = 1, E = −4) from x = 2 to x = −1 at ZT = 3.
    let e = [(104, 3, 0, "1.,0.,0.,0.,-4.,0.,3.,2.,1.,-1.,0.25")];
    with_ctx(&e, 2, |ctx| {
        let s = ctx.curve(1, 1, &IDENTITY).unwrap();
        assert!(
            s.start().distance(DVec3::new(2.0, 1.0, 3.0)) < TOL,
            "{}",
            s.start()
        );
        assert!(
            s.end().distance(DVec3::new(-1.0, 0.25, 3.0)) < TOL,
            "{}",
            s.end()
        );
        let p = s.at_fraction(0.5);
        assert!(
            (p.y - p.x * p.x / 4.0).abs() < TOL && (p.z - 3.0).abs() < TOL,
            "{p}"
        );
    });
    // Out of standard position: refused with a message naming the entity.
    let e = [(104, 2, 0, "1.,0.5,-1.,0.,0.,-1.,0.,1.,0.,2.,1.732")];
    with_ctx(&e, 2, |ctx| {
        let msg = ctx.curve(1, 1, &IDENTITY).unwrap_err().to_string();
        assert!(msg.contains("DE 1 (entity 104, conic arc)"), "{msg}");
        assert!(msg.contains("standard position"), "{msg}");
    });
}

#[test]
fn rational_bspline_curve_quarter_circle() {
    // Degree 2, three control points (1,0,0) (1,1,0) (0,1,0), weights 1, √½, 1: exactly a
    // quarter of the unit circle.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let params = format!(
        "2,2,1,0,0,0,0.,0.,0.,1.,1.,1.,1.,{w},1.,1.,0.,0.,1.,1.,0.,0.,1.,0.,0.,1.,0.,0.,1."
    );
    let e = [(126, 0, 0, params.as_str())];
    with_ctx(&e, 10, |ctx| {
        let s = ctx.curve(1, 1, &IDENTITY).unwrap();
        assert!(matches!(s.curve, Curve3D::NurbsCurve(_)));
        for k in 0..=10 {
            // Unit flag 10: centimetres, so the radius is 10 mm.
            let p = point(&s.curve, k as f64 / 10.0);
            assert!((p.length() - 10.0).abs() < TOL, "{p}");
        }
    });
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
    let base: Vec<Spec> = vec![
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
    let e: Vec<Spec> = vec![
        (110, 0, 0, "0.,0.,0.,0.,0.,1."),                    // DE 1: axis z
        (110, 0, 0, "2.,0.,0.,2.,0.,5."),                    // DE 3: parallel line at 2
        (110, 0, 0, "1.,0.,0.,3.,0.,2."),                    // DE 5: slanted line in the xz plane
        (110, 0, 0, "1.,0.,0.,1.,1.,1."),                    // DE 7: skew line (hyperboloid)
        (100, 0, 11, "0.,0.,0.,3.,0.,-3.,0."), // DE 9: half circle r 3 about the origin
        (124, 0, 0, "1.,0.,0.,0.,0.,0.,-1.,0.,0.,1.,0.,0."), // DE 11: its plane → xz plane
        (100, 0, 11, "0.,6.,0.,7.,0.,7.,0."),  // DE 13: circle r 1 at (6, 0, 0) in xz
        (120, 0, 0, "1,3,0.,6.283185307"),     // DE 15: cylinder
        (120, 0, 0, "1,5,0.,6.283185307"),     // DE 17: cone
        (120, 0, 0, "1,7,0.,6.283185307"),     // DE 19: hyperboloid (generic)
        (120, 0, 0, "1,9,0.,6.283185307"),     // DE 21: sphere
        (120, 0, 0, "1,13,0.,6.283185307"),    // DE 23: torus
        (122, 0, 0, "3,2.,4.,0."),             // DE 25: line DE 3 swept by (0, 4, 0)
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

#[test]
fn bad_entities_name_themselves() {
    // Unsorted knots, a pointer to nowhere, a wrong entity type, a short record.
    let e: Vec<Spec> = vec![
        (
            126,
            0,
            0,
            "1,1,0,0,1,0,1.,0.,0.,0.,1.,1.,0.,0.,0.,1.,1.,1.,0.,1.",
        ), // DE 1
        (120, 0, 0, "99,3,0.,1."),        // DE 3
        (120, 0, 0, "5,1,0.,1."),         // DE 5
        (116, 0, 0, "0.,0."),             // DE 7
        (110, 0, 0, "0.,0.,0.,1.,1.,1."), // DE 9
        (192, 0, 0, "7,9,1."),            // DE 11
    ];
    with_ctx(&e, 2, |ctx| {
        let msg = |r: crate::Result<_>| {
            r.map(|_: super::geometry::Segment| ())
                .unwrap_err()
                .to_string()
        };
        assert!(msg(ctx.curve(1, 1, &IDENTITY)).contains("knots are not in non-decreasing order"));
        let m = ctx
            .surface(3, 3, &IDENTITY)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("DE 3 (entity 120, surface of revolution): points to DE 99"),
            "{m}"
        );
        let m = ctx
            .surface(5, 5, &IDENTITY)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("surface entity type 120") || m.contains("curve entity type 120"),
            "{m}"
        );
        let m = ctx
            .surface(11, 11, &IDENTITY)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("DE 7 (entity 116, point)") && m.contains("record too short"),
            "{m}"
        );
    });
}
