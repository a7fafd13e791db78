//! The tracer on the reference samples: seams, junctions and ends where the analytic medial
//! axis has them, every point verified.

use super::options::MAX_TURN_RAD;
use super::*;
use crate::geom::{project_point, Boundary};
use crate::medial::axis::{DegenerateKind, Junction, MedialAxis, Seam, SeamEnd};
use crate::model::{Element, Model};
use glam::DVec3;

fn traced(name: &str) -> (Model, MedialAxis) {
    let (m, _, mat) = crate::testing::traced(name);
    (m, mat)
}

/// The worst error of [`crate::medial::verify`] over every ball.
fn verify(m: &Model, mat: &MedialAxis) -> f64 {
    let class = crate::classify::classify(m, &Default::default());
    let accuracy = TraceOptions::for_model(m).accuracy;
    crate::medial::verify(m, &Boundary::new(m), &class, mat, accuracy).worst()
}

/// Box [0,60]×[0,40]×[0,20] (c < b < a): 12 seams, 4 junctions at
/// (a/2 ± (a−c)/2, b/2 ± (b−c)/2, c/2) = (10|50, 10|30, 10), radius c/2 = 10 (the analytic
/// medial axis of a box).
#[test]
fn box_has_twelve_seams_and_four_junctions() {
    for file in ["box.step", "box_nurbs.step"] {
        let (m, mat) = traced(file);
        assert_eq!(mat.junctions.len(), 4, "{file}");
        assert_eq!(mat.seams.len(), 12, "{file}");
        let diag = m.diagonal();
        for j in &mat.junctions {
            let p = DVec3::from_array(j.point);
            let want = [10.0, 50.0]
                .iter()
                .flat_map(|&x| [10.0, 30.0].map(|y| DVec3::new(x, y, 10.0)))
                .map(|q| q.distance(p))
                .fold(f64::INFINITY, f64::min);
            // Junctions within 1e-9 × diagonal of the analytic position: the junction solve
            // is far tighter than the accuracy.
            assert!(want <= 1e-9 * diag, "{file}: junction {p} off by {want:e}");
            assert!(
                (j.radius - 10.0).abs() <= 1e-9 * diag,
                "{file}: radius {}",
                j.radius
            );
        }
        for s in &mat.seams {
            assert!(
                s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
                "{file}: seam {:?} ends {:?}",
                s.segments,
                s.ends
            );
        }
        // 8 corner seams (vertex → junction) and 4 inner seams (junction → junction).
        let corner = mat
            .seams
            .iter()
            .filter(|s| matches!(s.ends[0], SeamEnd::Vertex(_)))
            .count();
        assert_eq!(corner, 8, "{file}");
        let worst = verify(&m, &mat);
        assert!(
            worst <= 1e-6 * diag,
            "{file}: worst verified error {worst:e}"
        );
    }
}

/// Checks a traced convex part: seam and junction counts, every seam closed (no open
/// end), junctions at the expected points and radii (to 1e-9 × diagonal), every point
/// verified maximal to 1e-6 × diagonal (the default accuracy).
fn check(file: &str, seams: usize, junctions: &[([f64; 3], f64)]) {
    let (m, mat) = traced(file);
    let diag = m.diagonal();
    assert_eq!(
        mat.seams.len(),
        seams,
        "{file}: seams {:#?}",
        mat.seams
            .iter()
            .map(|s| (&s.segments, &s.ends))
            .collect::<Vec<_>>()
    );
    assert_eq!(mat.junctions.len(), junctions.len(), "{file}");
    for (p, r) in junctions {
        assert_junction_at(file, &m, &mat, *p, *r);
    }
    for s in &mat.seams {
        assert!(
            s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
            "{file}: {:?} {:?}",
            s.segments,
            s.ends
        );
    }
    let worst = verify(&m, &mat);
    assert!(
        worst <= 1e-6 * diag,
        "{file}: worst verified error {worst:e}"
    );
}

/// Tetrahedron (0,0,0), (36,0,0), (0,28,0), (0,0,24): four seams meet at the incentre
/// (6, 6, 6) with the inradius 6 (manifest, from Σ Aᵢ·Vᵢ / Σ Aᵢ and 3V / Σ Aᵢ).
#[test]
fn tetrahedron_seams_meet_at_the_incentre() {
    check("tetrahedron.step", 4, &[([6.0, 6.0, 6.0], 6.0)]);
}

/// Cube of side 30: a non-generic junction at the centre touching all six faces; the
/// eight corner seams end there and nothing else leaves it.
#[test]
fn cube_seams_meet_at_the_centre() {
    check("cube.step", 8, &[([15.0, 15.0, 15.0], 15.0)]);
}

/// Wedge (a triangular prism, manifest): junctions (10,10,10) and (10,10,50), radius 10;
/// six corner seams and one seam between the junctions.
#[test]
fn wedge() {
    check(
        "wedge.step",
        7,
        &[([10.0, 10.0, 10.0], 10.0), ([10.0, 10.0, 50.0], 10.0)],
    );
}

/// Square pyramid: the apex, where four faces meet, starts one seam down the axis; it
/// and the four base-corner seams meet at (15, 15, 7.5), radius 7.5, a junction touching
/// all five faces.
#[test]
fn pyramid_apex_is_a_non_generic_start() {
    check("pyramid.step", 5, &[([15.0, 15.0, 7.5], 7.5)]);
}

/// The box with a bicubic B-spline top: 12 seams and 4 junctions like the box (the bump
/// moves them), symmetric about x = 30 and y = 20 as the part is, all points verified.
#[test]
fn box_with_bspline_top() {
    let (m, mat) = traced("box_bspline_top.step");
    assert_eq!(mat.seams.len(), 12);
    assert_eq!(mat.junctions.len(), 4);
    let diag = m.diagonal();
    let r0 = mat.junctions[0].radius;
    for j in &mat.junctions {
        assert!(
            (j.radius - r0).abs() <= 1e-9 * diag,
            "radii {} vs {r0}",
            j.radius
        );
        let p = DVec3::from_array(j.point);
        let mirrored = DVec3::new(60.0 - p.x, 40.0 - p.y, p.z);
        let e = mat
            .junctions
            .iter()
            .map(|k| DVec3::from_array(k.point).distance(mirrored))
            .fold(f64::INFINITY, f64::min);
        assert!(e <= 1e-9 * diag, "no mirror image of {p}: {e:e}");
    }
    assert!(verify(&m, &mat) <= 1e-6 * diag);
}

/// Distance from (x, 0) to the ellipse x²/a² + y²/b² = 1 (a > b, |x| < a − b²/a): the
/// two nearest points are at the parameter with cos t = a·x / (a² − b²).
fn ellipse_distance(a: f64, b: f64, x: f64) -> f64 {
    let c = a * x / (a * a - b * b);
    ((a * c - x).powi(2) + b * b * (1.0 - c * c)).sqrt()
}

/// Elliptic cylinder (semi-axes 30 and 15, height 40; manifest): the seam where the ball
/// touches the lateral face twice and the top, traced from a seed at x = 0 both ways.
/// Every point is (x, 0, 40 − r) with r the distance from (x, 0) to the ellipse, the two
/// lateral touch points mirror each other in y = 0, and both ends are where the ball
/// osculates the lateral face: the centres of curvature of the ellipse's vertices,
/// x = ±(a − b²/a) = ±22.5, r = b²/a = 7.5. The lateral face is an extrusion in one
/// file and a rational B-spline in the other (two touch points on one free-form face).
#[test]
fn seam_touching_one_face_twice_from_a_seed() {
    let (a, b, h) = (30.0, 15.0, 40.0);
    for file in ["elliptic_cylinder.step", "elliptic_cylinder_nurbs.step"] {
        let m = crate::testing::sample(file);
        let class = crate::classify(&m, &Default::default());
        // The lateral face owns the seam edge (the same face on both sides); the top is
        // the other face with the higher middle.
        let lat = m
            .edges
            .iter()
            .find(|e| e.faces[0] == e.faces[1])
            .unwrap()
            .faces[0];
        let middle_z = |f: usize| {
            let d = m.faces[f].domain;
            let (u, v) = (0.5 * (d.u.0 + d.u.1), 0.5 * (d.v.0 + d.v.1));
            crate::geom::surface_point(&m.faces[f].surface, u, v).z
        };
        let top = (0..m.faces.len())
            .filter(|&f| f != lat)
            .max_by(|&f, &g| middle_z(f).total_cmp(&middle_z(g)))
            .unwrap();
        let foot = |f: usize, q: DVec3| project_point(&m.faces[f].surface, q, None).unwrap();
        let seed = Seed::new(
            [Element::Face(lat), Element::Face(lat), Element::Face(top)],
            DVec3::new(0.0, 0.0, h - b),
            b,
            [
                foot(lat, DVec3::new(0.0, b, h - b)),
                foot(lat, DVec3::new(0.0, -b, h - b)),
                foot(top, DVec3::new(0.0, 0.0, h)),
            ],
        );
        let boundary = Boundary::new(&m);
        let opts = TraceOptions::for_model(&m);
        let mat = trace_with_seeds(&m, &boundary, &class, &opts, &[seed]);
        // The seed's seam comes first; sampling then finds the bottom one.
        assert_eq!(mat.seams.len(), 2, "{file}");
        let seam = &mat.seams[0];
        let diag = m.diagonal();
        for e in &seam.ends {
            assert_eq!(
                *e,
                SeamEnd::CurvatureLimit {
                    segment: Element::Face(lat)
                },
                "{file}"
            );
        }
        let xs: Vec<f64> = seam.points.iter().map(|q| q.point[0]).collect();
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &x| {
                (l.min(x), u.max(x))
            });
        let x_end = a - b * b / a;
        // The ends within 20× the accuracy: the bisection stops within the accuracy, but
        // where the two touch points nearly meet the system is ill-conditioned (the
        // centre moves along a near-null direction of the Jacobian), so a converged
        // residual places the centre only to about the accuracy itself.
        let end_tol = 2e-5 * diag;
        assert!(
            (lo + x_end).abs() <= end_tol && (hi - x_end).abs() <= end_tol,
            "{file}: ends at x = {lo}, {hi}"
        );
        for q in &seam.points {
            let [x, y, z, r] = q.point;
            let want = ellipse_distance(a, b, x.clamp(-x_end, x_end));
            assert!(y.abs() <= 1e-9 * diag, "{file}: y = {y}");
            assert!(
                (z - (h - r)).abs() <= 1e-9 * diag,
                "{file}: z = {z}, r = {r}"
            );
            // (An end point's x may lie past the exact end by the end tolerance.)
            let past = (x.abs() - x_end).max(0.0);
            assert!(
                (r - want).abs() <= 1e-6 * diag + 2.0 * past,
                "{file}: r({x}) = {r}, not {want}"
            );
            let (t0, t1) = (DVec3::from_array(q.touch[0]), DVec3::from_array(q.touch[1]));
            assert!((t0 - DVec3::new(t1.x, -t1.y, t1.z)).length() <= 1e-6 * diag);
        }
        // Points are spaced by the step control: the direction turns at most MAX_TURN_RAD.
        for w in seam.points.windows(3) {
            let d0 = DVec3::from_slice(&w[1].point[..3]) - DVec3::from_slice(&w[0].point[..3]);
            let d1 = DVec3::from_slice(&w[2].point[..3]) - DVec3::from_slice(&w[1].point[..3]);
            assert!(d0.angle_between(d1) <= 2.0 * MAX_TURN_RAD, "{file}");
        }
        assert!(verify(&m, &mat) <= 1e-6 * diag, "{file}");
    }
}

/// No seam of `mat` has an open end, the seam–junction graph is consistent, and every
/// ball verifies to the default accuracy.
fn complete_and_verified(file: &str, m: &Model, mat: &MedialAxis) {
    for s in &mat.seams {
        assert!(
            s.ends.iter().all(|e| !matches!(e, SeamEnd::Open(_))),
            "{file}: seam {} {:?} ends {:?}",
            s.id,
            s.segments,
            s.ends
        );
    }
    let class = crate::classify(m, &Default::default());
    let sheets = crate::medial::sheets(m, &class, mat);
    let topo = crate::medial::verify::check_topology(mat, &sheets);
    assert!(
        topo.inconsistencies.is_empty(),
        "{file}: {:?}",
        topo.inconsistencies
    );
    // Where the sheets are complete, the medial axis is homotopy-equivalent to the solid.
    for e in &topo.euler {
        if let Some(chi) = e.mat_euler {
            assert_eq!(chi, e.solid_euler, "{file}: Euler characteristics {e:?}");
        }
    }
    let worst = verify(m, mat);
    assert!(
        worst <= 1e-6 * m.diagonal(),
        "{file}: worst verified error {worst:e}"
    );
}

/// Asserts a junction of `mat` at `p` with radius `r`, both to 1e-9 × the diagonal (the
/// junction accuracy the tracer aims for), and returns it.
fn assert_junction_at<'m>(
    file: &str,
    m: &Model,
    mat: &'m MedialAxis,
    p: [f64; 3],
    r: f64,
) -> &'m Junction {
    let diag = m.diagonal();
    let (j, e) = junction_near(mat, DVec3::from_array(p));
    assert!(e <= 1e-9 * diag, "{file}: junction near {p:?} off by {e:e}");
    assert!(
        (j.radius - r).abs() <= 1e-9 * diag,
        "{file}: radius {} vs {r}",
        j.radius
    );
    j
}

/// The junction of `mat` nearest `p`, and its distance from `p`.
fn junction_near(mat: &MedialAxis, p: DVec3) -> (&Junction, f64) {
    mat.junctions
        .iter()
        .map(|j| (j, DVec3::from_array(j.point).distance(p)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
}

/// L-bracket (profile [0,60]×[0,10] ∪ [0,10]×[0,40] in xz, 30 deep in y; one reflex
/// edge E8 along x = 10, z = 10). Ten convex corners start ten seams. The four box-like
/// junctions are at the ends of the two legs, radius 5 (half the thickness):
/// (55, 5|25, 5) and (5, 5|25, 35). At the inner corner, the ball touching the bottom
/// z = 0, the back x = 0, a side y = 0|30 and the reflex edge has centre (c, c|30−c, c)
/// with √2·(10 − c) = c: c = 10·(2 − √2) = 5.858, radius c. Seams: 10 corner seams, one
/// along each leg between its two end junctions, one between the two inner-corner
/// junctions (bottom, back, edge), and four from the leg junctions to the inner ones,
/// each handing its touch point from the leg's inner face onto the reflex edge: 17.
#[test]
fn l_bracket_with_a_reflex_edge() {
    for file in ["l_bracket.step", "l_bracket_nurbs.step"] {
        let (m, mat) = traced(file);
        assert_eq!(mat.seams.len(), 17, "{file}");
        assert_eq!(mat.junctions.len(), 6, "{file}");
        let c = 10.0 * (2.0 - 2f64.sqrt());
        let want = [
            ([55.0, 5.0, 5.0], 5.0),
            ([55.0, 25.0, 5.0], 5.0),
            ([5.0, 5.0, 35.0], 5.0),
            ([5.0, 25.0, 35.0], 5.0),
            ([c, c, c], c),
            ([c, 30.0 - c, c], c),
        ];
        for (p, r) in want {
            let j = assert_junction_at(file, &m, &mat, p, r);
            if r == c {
                assert!(
                    j.segments.iter().any(|s| matches!(s, Element::Edge(_))),
                    "{file}: {:?}",
                    j.segments
                );
            }
        }
        let handed = mat.seams.iter().filter(|s| !s.handovers.is_empty()).count();
        assert_eq!(handed, 4, "{file}");
        complete_and_verified(file, &m, &mat);
    }
}

/// U-channel (base [0,60]×[0,10], uprights x ∈ [0,10] and [50,60] up to z = 40, 30 deep;
/// two reflex edges): the L-bracket's inner-corner junctions at both inner corners,
/// (c | 60 − c, c | 30 − c, c) with c = 10·(2 − √2), and the box-like junctions at the
/// tops of the uprights, (5 | 55, 5 | 25, 35), radius 5. 12 corner seams, 2 up the
/// uprights' tops, 2 between the inner junctions across y, 2 along the base between
/// the inner corners (handing over from edge to the base's top face and onto the other
/// edge), 4 from the upright tops down to the inner corners: 22.
#[test]
fn u_channel_with_two_reflex_edges() {
    let (m, mat) = traced("u_channel.step");
    assert_eq!(mat.seams.len(), 22);
    assert_eq!(mat.junctions.len(), 8);
    let c = 10.0 * (2.0 - 2f64.sqrt());
    for x in [c, 60.0 - c] {
        for y in [c, 30.0 - c] {
            assert_junction_at("u_channel.step", &m, &mat, [x, y, c], c);
        }
    }
    for x in [5.0, 55.0] {
        for y in [5.0, 25.0] {
            assert_junction_at("u_channel.step", &m, &mat, [x, y, 35.0], 5.0);
        }
    }
    complete_and_verified("u_channel.step", &m, &mat);
}

/// Plate [0,80]×[0,50]×[0,10] with through holes r = 5, 8, 5 at x = 15, 40, 65 (y = 25):
/// the box's 12 seams and 4 junctions (radius 5, half the thickness), plus around each
/// hole a closed seam (top, bottom, hole wall) no corner reaches — found by seeding:
/// the circle z = 5 at distance r_hole + 5 from the hole's axis, ball radius 5.
#[test]
fn plate_with_holes_has_a_closed_seam_around_each_hole() {
    let (m, mat) = traced("plate_with_holes.step");
    assert_eq!(mat.junctions.len(), 4);
    assert_eq!(mat.seams.len(), 15);
    let diag = m.diagonal();
    let loops: Vec<&Seam> = mat
        .seams
        .iter()
        .filter(|s| s.ends[0] == SeamEnd::Closed)
        .collect();
    assert_eq!(loops.len(), 3);
    for s in loops {
        let p0 = s.points[0].point;
        let (cx, rh) = [(15.0, 5.0), (40.0, 8.0), (65.0, 5.0)]
            .into_iter()
            .min_by(|a, b| (a.0 - p0[0]).abs().total_cmp(&(b.0 - p0[0]).abs()))
            .unwrap();
        for q in &s.points {
            let [x, y, z, r] = q.point;
            let rho = ((x - cx).powi(2) + (y - 25.0).powi(2)).sqrt();
            assert!(
                (rho - (rh + 5.0)).abs() <= 1e-6 * diag,
                "hole at {cx}: ρ = {rho}"
            );
            assert!((z - 5.0).abs() <= 1e-6 * diag && (r - 5.0).abs() <= 1e-6 * diag);
        }
    }
    complete_and_verified("plate_with_holes.step", &m, &mat);
}

/// Solids without a convex corner. The elliptic cylinder's two seams (the ball touching
/// the lateral face twice and one cap) are found by seeding and end at the centres of
/// curvature x = ±22.5, r = 7.5 (see the seed test). The washer from OpenSCAD (inner
/// radius 15, outer 25, height 8) has two closed seams, the circles of radius 19 and 21
/// at z = 4, ball radius 4 (manifest). Cylinder, sphere and torus have degenerate medial
/// axes, reported as such: the cylinder's axis (x = y = 0, r = 10), the sphere's centre
/// (r = 15), the torus's core circle (x² + y² = 20², z = 0, r = 5).
#[test]
fn solids_without_convex_corners() {
    for file in ["elliptic_cylinder.step", "elliptic_cylinder_nurbs.step"] {
        let (m, mat) = traced(file);
        assert_eq!(mat.seams.len(), 2, "{file}");
        for s in &mat.seams {
            assert!(
                s.ends
                    .iter()
                    .all(|e| matches!(e, SeamEnd::CurvatureLimit { .. })),
                "{file}: {:?}",
                s.ends
            );
            let ends = [s.points[0].point, s.points[s.points.len() - 1].point];
            assert!(
                ends.iter()
                    .all(|p| (p[0].abs() - 22.5).abs() <= 2e-5 * m.diagonal()),
                "{file}: {ends:?}"
            );
        }
        complete_and_verified(file, &m, &mat);
    }
    let (m, mat) = traced("scad_rotate_extrude.step");
    assert_eq!(mat.seams.len(), 2);
    let mut radii: Vec<f64> = mat
        .seams
        .iter()
        .map(|s| {
            assert_eq!(s.ends, [SeamEnd::Closed, SeamEnd::Closed]);
            let [x, y, z, r] = s.points[0].point;
            assert!(
                (z - 4.0).abs() <= 1e-6 * m.diagonal() && (r - 4.0).abs() <= 1e-6 * m.diagonal()
            );
            (x * x + y * y).sqrt()
        })
        .collect();
    radii.sort_by(f64::total_cmp);
    assert!(
        (radii[0] - 19.0).abs() <= 1e-6 * m.diagonal()
            && (radii[1] - 21.0).abs() <= 1e-6 * m.diagonal(),
        "{radii:?}"
    );
    complete_and_verified("scad_rotate_extrude.step", &m, &mat);
    type Check = fn([f64; 4]) -> f64;
    let cases: [(&str, &str, Check); 5] = [
        ("cylinder.step", "curve", |b| {
            b[0].hypot(b[1]) + (b[3] - 10.0).abs()
        }),
        ("cylinder_nurbs.step", "curve", |b| {
            b[0].hypot(b[1]) + (b[3] - 10.0).abs()
        }),
        ("sphere.step", "point", |b| {
            DVec3::new(b[0], b[1], b[2]).length() + (b[3] - 15.0).abs()
        }),
        ("sphere_nurbs.step", "point", |b| {
            DVec3::new(b[0], b[1], b[2]).length() + (b[3] - 15.0).abs()
        }),
        ("torus.step", "curve", |b| {
            (b[0].hypot(b[1]) - 20.0).abs() + b[2].abs() + (b[3] - 5.0).abs()
        }),
    ];
    for (file, kind, err) in cases {
        let (m, mat) = traced(file);
        assert!(mat.seams.is_empty(), "{file}");
        assert!(!mat.degenerate.is_empty(), "{file}");
        for d in &mat.degenerate {
            assert_eq!(d.kind.as_str(), kind, "{file}");
            for b in &d.balls {
                assert!(err(*b) <= 1e-6 * m.diagonal(), "{file}: {b:?}");
            }
        }
        assert!(verify(&m, &mat) <= 1e-6 * m.diagonal(), "{file}");
    }
}

/// Degenerate curves are traced between located ends. The cylinder (radius 10, z from 0 to
/// 30): its axis from z = 10 to z = 20, where the ball (r = 10) touches each cap at its
/// centre, the apex of the cone of balls touching the cap and the lateral face; it touches
/// all round, and the Euler characteristic counts it (1 = 2 cone discs + the segment − 2
/// apexes). The torus (core radius 20, tube 5): its core circle, closed. The filleted box
/// (60×40×20, fillets and corner blends of radius 4): the 12 fillets' axes, each from
/// corner to corner (centres at 4 or 56, 4 or 36, 4 or 16), ending where the ball
/// osculates the corner's blend, touching along an arc only. The boss near a plate's edge
/// (plate 6 mm thick, boss radius 5 on it, top at z = 14): its axis from z = 9 (touching the
/// top) down the boss's side to its foot circle (z = 6), handed over onto that circle (a
/// reflex edge) and on, the ball growing as it touches the circle from below, to where it
/// meets the plate's bottom: `z = r = 61/12` (`z² = 25 + (6 − z)²`); χ = 1. The pin with
/// a hemispherical tip (radius 3, flat end at z = 0, tip's centre at z = 10): its axis from
/// z = 3 (meeting the flat end) to z = 10, where the ball is the tip's sphere (meeting it,
/// osculating).
#[test]
fn degenerate_curves_are_traced_between_located_ends() {
    use crate::medial::axis::DegenerateEnd;
    let near = |m: &Model, a: f64, b: f64| (a - b).abs() <= 1e-5 * m.diagonal();

    let (m, mat) = traced("cylinder.step");
    let [d] = &mat.degenerate[..] else {
        panic!("{:?}", mat.degenerate)
    };
    assert!(d.around && d.kind == DegenerateKind::Curve);
    assert!(d
        .balls
        .iter()
        .all(|b| b[0].hypot(b[1]) <= 1e-6 * m.diagonal() && near(&m, b[3], 10.0)));
    let zs = [d.balls[0][2], d.balls[d.balls.len() - 1][2]];
    assert!(
        (near(&m, zs[0], 10.0) && near(&m, zs[1], 20.0))
            || (near(&m, zs[0], 20.0) && near(&m, zs[1], 10.0)),
        "{zs:?}"
    );
    for (end, z) in d.ends.iter().zip(zs) {
        let DegenerateEnd::Meets {
            touch,
            osculates: false,
            ..
        } = end
        else {
            panic!("{end:?}")
        };
        assert!(touch[0].hypot(touch[1]) <= 1e-6 * m.diagonal(), "{touch:?}");
        assert!(
            near(&m, (touch[2] - z).abs(), 10.0),
            "{touch:?} from z = {z}"
        );
    }
    complete_and_verified("cylinder.step", &m, &mat);
    assert_eq!(axis_euler(&m, &mat), Some(1));

    let (m, mat) = traced("torus.step");
    let [d] = &mat.degenerate[..] else {
        panic!("{:?}", mat.degenerate)
    };
    assert_eq!(d.ends, [DegenerateEnd::Closed]);
    assert!(d.around);
    let mut angles: Vec<f64> = d.balls.iter().map(|b| b[1].atan2(b[0])).collect();
    angles.sort_by(f64::total_cmp);
    let widest = angles
        .windows(2)
        .map(|w| w[1] - w[0])
        .chain([angles[0] + std::f64::consts::TAU - angles[angles.len() - 1]])
        .fold(0.0, f64::max);
    assert!(widest < 0.5, "the core circle has a gap of {widest} rad");
    complete_and_verified("torus.step", &m, &mat);

    let (m, mat) = traced("filleted_box.step");
    let curves = curves_of(&mat);
    assert_eq!(curves.len(), 12);
    for d in curves {
        assert!(!d.around);
        for b in [d.balls[0], d.balls[d.balls.len() - 1]] {
            let corner = [[4.0, 56.0], [4.0, 36.0], [4.0, 16.0]];
            assert!(
                (0..3).all(|k| corner[k].iter().any(|&c| near(&m, b[k], c))),
                "{:?} ends at {b:?}",
                d.segments
            );
        }
        all_meet(d, true);
    }
    complete_and_verified("filleted_box.step", &m, &mat);

    let (m, mat) = traced("trace/boss_near_edge.step");
    let [d] = &mat.degenerate[..] else {
        panic!("{:?}", mat.degenerate)
    };
    // Listed from either end (which way is first depends on the sampled ball).
    let mut pairs = d.segments.clone();
    if matches!(pairs[0], Element::Edge(_)) {
        pairs.reverse();
    }
    assert!(
        matches!(pairs[..], [Element::Face(f), Element::Face(g), Element::Edge(e), Element::Edge(k)] if f == g && e == k),
        "{:?}",
        d.segments
    );
    let (mut top, mut bottom) = (d.balls[0], d.balls[d.balls.len() - 1]);
    if top[2] < bottom[2] {
        (top, bottom) = (bottom, top);
    }
    assert!(near(&m, top[2], 9.0) && near(&m, top[3], 5.0), "{top:?}");
    let z = 61.0 / 12.0;
    assert!(
        near(&m, bottom[2], z) && near(&m, bottom[3], z),
        "{bottom:?}"
    );
    all_meet(d, false);
    complete_and_verified("trace/boss_near_edge.step", &m, &mat);
    assert_eq!(axis_euler(&m, &mat), Some(1));

    let (m, mat) = traced("trace/rounded_pin.step");
    let curves = curves_of(&mat);
    let [d] = &curves[..] else {
        panic!("{:?}", mat.degenerate)
    };
    assert!(d.around && d.segments.iter().all(|s| *s == d.segments[0]));
    let mut zs = [d.balls[0][2], d.balls[d.balls.len() - 1][2]];
    zs.sort_by(f64::total_cmp);
    assert!(near(&m, zs[0], 3.0) && near(&m, zs[1], 10.0), "{zs:?}");
    let osculating: Vec<bool> = d
        .ends
        .iter()
        .map(|e| match e {
            DegenerateEnd::Meets { osculates, .. } => *osculates,
            e => panic!("{e:?}"),
        })
        .collect();
    assert!(osculating.contains(&true) && osculating.contains(&false));
    complete_and_verified("trace/rounded_pin.step", &m, &mat);
}

/// The degenerate curves of `mat` (not its points).
fn curves_of(mat: &MedialAxis) -> Vec<&crate::medial::Degenerate> {
    mat.degenerate
        .iter()
        .filter(|d| d.kind == DegenerateKind::Curve)
        .collect()
}

/// Asserts that both ends of degenerate curve `d` meet an element, osculating it or not.
fn all_meet(d: &crate::medial::Degenerate, osculating: bool) {
    use crate::medial::axis::DegenerateEnd;
    assert!(
        d.ends.len() == 2
            && d.ends.iter().all(
                |e| matches!(e, DegenerateEnd::Meets { osculates, .. } if *osculates == osculating)
            ),
        "{:?}",
        d.ends
    );
}

/// The Euler characteristic of solid 0's medial axis, where counted.
fn axis_euler(m: &Model, mat: &MedialAxis) -> Option<i64> {
    let class = crate::classify(m, &Default::default());
    let sheets = crate::medial::sheets(m, &class, mat);
    crate::medial::verify::check_topology(mat, &sheets).euler[0].mat_euler
}

/// Two solids in one file: the box [0,30]×[0,20]×[0,10] gets the box's MAT (junctions
/// (5|25, 5|15, 5), radius 5) computed against its own faces only; the cylinder beside it
/// (radius 5) gets its degenerate axis, as solid 1.
#[test]
fn each_solid_gets_its_own_medial_axis() {
    let (m, mat) = traced("two_solids.step");
    assert_eq!(mat.seams.len(), 12);
    assert!(mat.seams.iter().all(|s| s.solid == 0));
    for x in [5.0, 25.0] {
        for y in [5.0, 15.0] {
            let j = assert_junction_at("two_solids.step", &m, &mat, [x, y, 5.0], 5.0);
            assert_eq!(j.solid, 0);
        }
    }
    assert!(mat
        .degenerate
        .iter()
        .any(|d| d.solid == 1 && d.kind == DegenerateKind::Curve));
    complete_and_verified("two_solids.step", &m, &mat);
}

/// Box [0,60]×[0,40]×[0,30] with a spherical void (radius 8 at the centre (30,20,15)):
/// the void is part of the boundary. The part is symmetric in x = 30 and y = 20, and so
/// is its traced MAT: every junction has its mirror images, at the same radius.
#[test]
fn box_with_a_void() {
    let (m, mat) = traced("box_with_void.step");
    let diag = m.diagonal();
    assert!(mat.junctions.len() >= 8);
    for j in &mat.junctions {
        let p = DVec3::from_array(j.point);
        for q in [
            DVec3::new(60.0 - p.x, p.y, p.z),
            DVec3::new(p.x, 40.0 - p.y, p.z),
        ] {
            let (k, e) = junction_near(&mat, q);
            assert!(
                e <= 1e-6 * diag && (k.radius - j.radius).abs() <= 1e-6 * diag,
                "no mirror of {p}"
            );
        }
    }
    assert!(
        mat.junctions.iter().any(|j| j
            .touch
            .iter()
            .any(
                |t| (DVec3::from_array(*t) - DVec3::new(30.0, 20.0, 15.0)).length() <= 8.0 + 1e-6
            )),
        "no junction touches the void"
    );
    complete_and_verified("box_with_void.step", &m, &mat);
}

/// Box [0,60]×[0,40]×[0,20] with every edge filleted at radius 4: the inner box
/// [4,56]×[4,36]×[4,16] offset by 4, so its medial axis is the box's with radii + 4
/// (manifest): the same 4 junctions, (10|50, 10|30, 10) with radius 10, and 12 seams,
/// the 8 corner seams now ending at the corner patches' centres (4|56, 4|36, 4|16),
/// radius 4, where the ball osculates the fillets (a curvature-limit end).
#[test]
fn filleted_box_seams_end_at_the_corner_patch_centres() {
    let (m, mat) = traced("filleted_box.step");
    let diag = m.diagonal();
    assert_eq!(mat.seams.len(), 12);
    assert_eq!(mat.junctions.len(), 4);
    for x in [10.0, 50.0] {
        for y in [10.0, 30.0] {
            assert_junction_at("filleted_box.step", &m, &mat, [x, y, 10.0], 10.0);
        }
    }
    let corner_ends: Vec<[f64; 4]> = mat
        .seams
        .iter()
        .flat_map(|s| {
            let pts = [s.points[0].point, s.points[s.points.len() - 1].point];
            s.ends
                .iter()
                .zip(pts)
                .filter(|(e, _)| matches!(e, SeamEnd::CurvatureLimit { .. }))
                .map(|(_, p)| p)
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(corner_ends.len(), 8);
    for p in corner_ends {
        let near = |v: f64, a: f64, b: f64| (v - a).abs().min((v - b).abs());
        let e = near(p[0], 4.0, 56.0) + near(p[1], 4.0, 36.0) + near(p[2], 4.0, 16.0);
        assert!(
            e <= 1e-5 * diag && (p[3] - 4.0).abs() <= 1e-5 * diag,
            "{p:?}"
        );
    }
    complete_and_verified("filleted_box.step", &m, &mat);
}

/// The L-bracket with its reflex edge replaced by a concave fillet of radius 5 (axis
/// x = 15, z = 15): the leg-end junctions stay at (55, 5|25, 5) and (5, 5|25, 35),
/// radius 5. The inner-corner junctions touch bottom, back, a side and the fillet from
/// outside its cylinder: centre (c, c|30 − c, c) with √2·(15 − c) = c + 5, so
/// c = (15√2 − 5)/(1 + √2) = 6.7157, radius c. 17 seams as for the sharp bracket.
#[test]
fn l_bracket_with_a_concave_fillet() {
    let (m, mat) = traced("l_bracket_concave_fillet.step");
    assert_eq!(mat.seams.len(), 17);
    assert_eq!(mat.junctions.len(), 6);
    let c = (15.0 * 2f64.sqrt() - 5.0) / (1.0 + 2f64.sqrt());
    let want = [
        ([55.0, 5.0, 5.0], 5.0),
        ([55.0, 25.0, 5.0], 5.0),
        ([5.0, 5.0, 35.0], 5.0),
        ([5.0, 25.0, 35.0], 5.0),
        ([c, c, c], c),
        ([c, 30.0 - c, c], c),
    ];
    for (p, r) in want {
        assert_junction_at("l_bracket_concave_fillet.step", &m, &mat, p, r);
    }
    complete_and_verified("l_bracket_concave_fillet.step", &m, &mat);
}

/// Plate [0,80]×[0,60]×[0,10] with a boss (radius 12, z from 10 to 30) at (40, 30): the
/// plate's box-like junctions at (5|75, 5|55, 5), radius 5, far from the boss; and the
/// boss's axis x = 40, y = 30 as a degenerate curve of balls of radius 12 touching its
/// whole wall.
#[test]
fn boss_on_a_plate() {
    let (m, mat) = traced("boss_on_plate.step");
    let diag = m.diagonal();
    for x in [5.0, 75.0] {
        for y in [5.0, 55.0] {
            assert_junction_at("boss_on_plate.step", &m, &mat, [x, y, 5.0], 5.0);
        }
    }
    let axis: Vec<&[f64; 4]> = curves_of(&mat).into_iter().flat_map(|d| &d.balls).collect();
    assert!(!axis.is_empty());
    for b in axis {
        let e = (b[0] - 40.0).hypot(b[1] - 30.0) + (b[3] - 12.0).abs();
        assert!(e <= 1e-6 * diag, "{b:?}");
    }
    complete_and_verified("boss_on_plate.step", &m, &mat);
}

/// Past a sphere's pole the parametrisation folds over (`cos v < 0`) and the face's normal
/// `Su × Sv` flips: there the medial equations have the mirror ball, radius `−r` on the other
/// side of the boundary, and a long step's corrector can land on it (a CATIA half shell's seam
/// ended open that way, its touch points handed on and back across the lune's edge). On the
/// half spherical shell's seam (r = 0.5, passing 0.5 from both poles), steps of every length up
/// to 3 mm from the points near a pole give balls of positive radius only (without the test
/// for it in `step`, one of 1.1 mm lands on the mirror ball, r = −0.5).
#[test]
fn steps_past_a_spheres_pole_never_land_on_the_mirror_ball() {
    use crate::medial::equations::MedialSystem;
    let (m, class, mat) = crate::testing::traced("trace/half_spherical_shell.step");
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let mut tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    let poles = m
        .vertices
        .iter()
        .map(|v| v.point)
        .filter(|p| p.x.abs() < 1e-9 && p.y.abs() < 1e-9)
        .collect::<Vec<_>>();
    assert!(!poles.is_empty(), "the shell's poles on the z axis");
    let mut steps = 0;
    for s in &mat.seams {
        let sys = MedialSystem::new(s.segments.clone());
        for w in s.points.windows(2).filter(|w| {
            let c = DVec3::from_slice(&w[0].point[..3]);
            poles.iter().any(|p| p.distance(c) < 2.0)
        }) {
            let p = &w[0];
            if s.segments
                .iter()
                .zip(&p.touch)
                .any(|(seg, _)| !matches!(seg, Element::Face(_)))
            {
                continue;
            }
            let mut x = nalgebra::DVector::zeros(10);
            for c in 0..4 {
                x[c] = p.point[c];
            }
            for (k, seg) in s.segments.iter().enumerate() {
                let Element::Face(f) = *seg else { continue };
                let uv = project_point(&m.faces[f].surface, DVec3::from_array(p.touch[k]), None)
                    .expect("touch point projects");
                x[4 + 2 * k] = uv.0;
                x[5 + 2 * k] = uv.1;
            }
            let mut dir = nalgebra::DVector::zeros(10);
            for c in 0..3 {
                dir[c] = w[1].point[c] - p.point[c];
            }
            let Some(t) = tracer.tangent(&sys, &x, &dir) else {
                continue;
            };
            for k in 1..=60 {
                let h = 0.05 * k as f64;
                if let Some((y, _, _)) = tracer.step(&sys, &x, &t, h) {
                    steps += 1;
                    assert!(y[3] > 0.0, "step {h} from {:?}: radius {}", p.point, y[3]);
                }
            }
        }
    }
    assert!(steps > 100, "{steps} steps near a pole");
}

/// The curvature limit solved for (`osculating_near`, where a step underflows next to it, and
/// to polish the end that `curvature_end` bisects): on the elliptic cylinder (semi-axes 30 and
/// 15), whose seams end where the ball osculates the elliptic wall at its vertices, every such
/// end is the vertex's centre of curvature (x = ±22.5, r = 7.5) to 1e-6 (the bisection alone
/// left it up to 12 accuracies short); from unknowns a little short of an end (its ball shrunk
/// and moved back by 0.1–0.5 % of `r`, `r·κ` within 1 % of 1) the solve lands there too, with
/// `r·κ = 1` to 1e-9; from seam points with `r·κ` farther from 1 there is none.
#[test]
fn a_nearly_osculating_ball_leads_to_the_exact_curvature_limit() {
    use crate::medial::equations::MedialSystem;
    use crate::medial::maximal::bending;
    let (m, class, mat) = crate::testing::traced("elliptic_cylinder.step");
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let mut tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    let is_limit = |y: &[f64]| (y[3] - 7.5).abs() < 1e-6 && (y[0].abs() - 22.5).abs() < 1e-6;
    let (mut ends, mut near, mut far) = (0, 0, 0);
    for s in &mat.seams {
        let sys = MedialSystem::new(s.segments.clone());
        let unknowns = |p: &crate::medial::axis::SeamPoint| {
            let mut x = nalgebra::DVector::zeros(10);
            for c in 0..4 {
                x[c] = p.point[c];
            }
            for (k, seg) in s.segments.iter().enumerate() {
                let Element::Face(f) = *seg else {
                    return None;
                };
                let uv = project_point(&m.faces[f].surface, DVec3::from_array(p.touch[k]), None)?;
                x[4 + 2 * k] = uv.0;
                x[5 + 2 * k] = uv.1;
            }
            Some(x)
        };
        let n = s.points.len();
        for (end, last, before) in [(0, 0, 1), (1, n - 1, n - 2)] {
            let SeamEnd::CurvatureLimit { segment } = s.ends[end] else {
                continue;
            };
            ends += 1;
            let tip = &s.points[last].point;
            assert!(is_limit(tip), "seam {} ends at {tip:?}", s.id);
            let i = s.segments.iter().position(|&e| e == segment).unwrap();
            let rk = |x: &nalgebra::DVector<f64>| {
                x[3] * bending(&m, segment, [x[4 + 2 * i], x[5 + 2 * i]]).unwrap()
            };
            let (a, b) = (
                unknowns(&s.points[before]).unwrap(),
                unknowns(&s.points[last]).unwrap(),
            );
            for w in [1e-3, 3e-3, 5e-3] {
                // The end's ball, shrunk by the fraction w and moved back towards the point
                // before by as much.
                let mut x = b.clone();
                x[3] *= 1.0 - w;
                let back = (unknowns::v3(&a) - unknowns::v3(&b)).normalize() * w * b[3];
                for c in 0..3 {
                    x[c] += back[c];
                }
                assert!((0.99..1.0).contains(&rk(&x)), "r·κ {}", rk(&x));
                near += 1;
                let (k, y) = tracer
                    .osculating_near(&sys, s.solid, &x)
                    .unwrap_or_else(|| panic!("r·κ {}: the limit near", rk(&x)));
                assert_eq!(s.segments[k], segment);
                let ky = y[3] * bending(&m, segment, [y[4 + 2 * k], y[5 + 2 * k]]).unwrap();
                assert!((ky - 1.0).abs() < 1e-9, "r·κ {ky} at the limit");
                assert!(is_limit(y.as_slice()), "{y}");
            }
            for p in &s.points {
                let x = unknowns(p).unwrap();
                if rk(&x) < 0.99 {
                    far += 1;
                    assert!(tracer.osculating_near(&sys, s.solid, &x).is_none());
                }
            }
        }
    }
    assert!(
        ends == 4 && near > 0 && far > 0,
        "{ends} ends, {near} near, {far} far"
    );
}

/// At a fold of 360° (a crack's bottom) the faces' normals are opposite, and every normal
/// square to the edge lies between them by angles: the edge's arc is the half its faces leave
/// towards (the crack's opening), not the half into the material. Before, a touch point on
/// the bottom of `crack_folded_to_its_bottom` stayed on the edge past both faces' normals,
/// and the walls came in as junctions whose touch points on the wall and the edge were one
/// place (and on MSOP-10's leads).
#[test]
fn a_cracks_bottom_owns_the_half_of_its_normals_towards_the_opening() {
    use crate::medial::equations::edge_angle;
    let (m, class) = crate::testing::classified("trace/crack_folded_to_its_bottom.step");
    let e = (0..m.edges.len())
        .find(|&e| class.edges[e].angle_range_deg.0 > 359.99)
        .expect("the crack's bottom");
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    let (lo, hi) = m.edges[e].range;
    let t = 0.5 * (lo + hi);
    let open = crate::geom::fold::into_first_face(&m, e, t, None).expect("a direction");
    let fan = tracer.edge_fan(e, t).expect("the faces' normals");
    let in_arc = |n: DVec3| {
        tracer
            .edge_status(e, [t, edge_angle(&m, e, t, n).unwrap()])
            .1
    };
    assert!(in_arc(open), "the opening's direction");
    assert!(in_arc(fan[0]) && in_arc(fan[1]), "the arc's ends");
    assert!(in_arc((open + 0.5 * fan[0]).normalize()));
    assert!(!in_arc(-open), "into the material");
    assert!(!in_arc((-open + 0.5 * fan[1]).normalize()));
}

/// A seam that ends at a convex vertex ends on it: the ball of radius 0 there is the vertex,
/// each touch point at it. (The system held at `r = 0` is singular where two of the elements
/// are tangent along a line through the vertex, as the faces of a fin folded to its tip are:
/// its solution stopped 2.9e-5 mm past the tip of each lead's fin on the IDF library's
/// MSOP-10, five times the accuracy; here on the samples' fin, a box corner and a pyramid's
/// base.)
#[test]
fn a_seam_ending_at_a_vertex_ends_on_it() {
    for file in [
        "trace/fin_folded_to_its_tip.step",
        "box.step",
        "pyramid.step",
    ] {
        let (m, _, mat) = crate::testing::traced(file);
        let mut ends = 0;
        for s in &mat.seams {
            for (k, end) in s.ends.iter().enumerate() {
                let SeamEnd::Vertex(v) = *end else { continue };
                let p = if k == 0 {
                    &s.points[0]
                } else {
                    s.points.last().unwrap()
                };
                let at = m.vertices[v].point;
                assert_eq!(p.point[3], 0.0, "{file}: seam {} end {k}", s.id);
                assert!(
                    DVec3::from_slice(&p.point[..3]).distance(at) <= 1e-12 * m.diagonal(),
                    "{file}: seam {} end {k} at {:?}, vertex V{v} at {at}",
                    s.id,
                    p.point
                );
                for q in &p.touch {
                    assert!(DVec3::from_array(*q).distance(at) <= 1e-9 * m.diagonal());
                }
                ends += 1;
            }
        }
        assert!(ends > 0, "{file}: no seam ends at a vertex");
    }
}

/// A seam that runs through a junction is dropped where the seams leaving the junction cover
/// it, also where it hands its touch point from one edge to the next through their shared
/// vertex just past the junction: the ball there touches the first edge at its end, that
/// vertex, which the seam leaving the junction along the next edge names through that edge.
/// (On 0603_SMD's lettering two kinked outlines face each other; the seam kept gave a
/// junction five seam ends, on 0603, 1206, 2225 and VC0603.) Here on the box's vertex V0
/// (edges `e1`, `e2` there): seam A runs from J0 to J1 through J2 (at 1.5), handing `e1` →
/// V0 at its point 2 and V0 → `e2` at 3; B runs J0–J2 on `e1`, C J2–J1 on `e2`.
#[test]
fn a_seam_through_a_junction_is_dropped_past_a_vertex_hand_over() {
    use crate::medial::axis::{Handover, SeamPoint};
    let (m, class) = crate::testing::classified("box.step");
    let v = 0;
    let at = m.vertices[v].point.to_array();
    let mut edges = (0..m.edges.len()).filter(|&e| m.edges[e].vertices.contains(&v));
    let (e1, e2) = (edges.next().unwrap(), edges.next().unwrap());
    let (fa, fb) = (Element::Face(4), Element::Face(5));
    let (e1, e2, vv) = (Element::Edge(e1), Element::Edge(e2), Element::Vertex(v));
    let seam = |id: usize, s: std::ops::RangeInclusive<f64>, ends: [usize; 2], on: Element| {
        let steps = ((s.end() - s.start()) * 2.0).round() as usize;
        Seam {
            id,
            solid: 0,
            segments: vec![fa, fb, on],
            ends: ends.map(SeamEnd::Junction),
            end_segments: vec![fa, fb, on],
            points: (0..=steps)
                .map(|k| SeamPoint {
                    point: [s.start() + 0.5 * k as f64, 10.0, 10.0, 5.0],
                    touch: vec![[0.0; 3], [1.0; 3], at],
                })
                .collect(),
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        }
    };
    // A: points every 0.5 from 0 to 4 with its hand-overs at 2 and 3 (its points 4 and 6).
    let mut a = seam(0, 0.0..=4.0, [0, 1], e1);
    a.handovers = vec![
        Handover {
            point: 4,
            from: e1,
            to: vv,
        },
        Handover {
            point: 6,
            from: vv,
            to: e2,
        },
    ];
    a.end_segments = vec![fa, fb, e2];
    let b = seam(1, 0.0..=1.5, [0, 2], e1);
    let c = seam(2, 1.5..=4.0, [2, 1], e2);
    let junction = |id: usize, x: f64| Junction {
        id,
        solid: 0,
        point: [x, 10.0, 10.0],
        radius: 5.0,
        segments: vec![fa, fb, e1, e2],
        touch: vec![[0.0; 3]; 4],
        unresolved: false,
    };
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let mut tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    tracer.seams = vec![a, b, c];
    tracer.junctions = vec![junction(0, 0.0), junction(1, 4.0), junction(2, 1.5)];
    assert_eq!(tracer.drop_seams_through_junctions(), 1);
    assert_eq!(tracer.seams.len(), 2);
    assert!(
        tracer.seams.iter().all(|s| s.points.len() < 9),
        "A is the one dropped"
    );
}

/// Of two seams on one curve of balls, the one reaching a junction at both ends is kept over
/// one that stopped at a curvature limit a step past a junction. (On the Voron Revo mount a
/// seam from junction J1 stopped 7e-4 mm past junction J0 at a curvature limit; the seam
/// traced from J0 to J1 was dropped as its repeat, and J0 kept three seam ends.) Here A runs
/// from J1 to a curvature limit at x = 0 and B from J0 (at 0) to J1 (at 2); A was traced
/// first.
#[test]
fn a_seam_reaching_a_junction_is_kept_over_its_repeat_ending_at_a_curvature_limit() {
    use crate::medial::axis::SeamPoint;
    let (m, class) = crate::testing::classified("box.step");
    let segments = vec![Element::Face(0), Element::Face(1), Element::Face(2)];
    let seam = |id: usize, ends: [SeamEnd; 2], forward: bool| {
        let mut points: Vec<SeamPoint> = (0..=4)
            .map(|k| SeamPoint {
                point: [0.5 * k as f64, 10.0, 10.0, 5.0],
                touch: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            })
            .collect();
        if !forward {
            points.reverse();
        }
        Seam {
            id,
            solid: 0,
            segments: segments.clone(),
            ends,
            end_segments: segments.clone(),
            points,
            handovers: vec![],
            unresolved: vec![],
            trace_seconds: 0.0,
        }
    };
    let limit = SeamEnd::CurvatureLimit {
        segment: Element::Face(0),
    };
    let a = seam(0, [SeamEnd::Junction(1), limit], false);
    let b = seam(1, [SeamEnd::Junction(0), SeamEnd::Junction(1)], true);
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let mut tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    tracer.seams = vec![a, b];
    assert_eq!(tracer.drop_repeated_seams(), 1);
    assert_eq!(
        tracer.seams[0].ends,
        [SeamEnd::Junction(0), SeamEnd::Junction(1)],
        "B is kept"
    );
}

/// A seam that leaves a junction and comes back to it within the separation is dropped
/// though no junction was merged: it is no curve of the medial axis. (On TSM-103's pins an
/// unresolved junction, its touch points at one place named by several elements, had a
/// two-point seam back to itself and counted six seam ends.) A seam from the junction back
/// to it round a loop is kept.
#[test]
fn a_seam_back_to_its_junction_within_the_separation_is_dropped() {
    use crate::medial::axis::SeamPoint;
    let (m, class) = crate::testing::classified("box.step");
    let segments = vec![Element::Face(0), Element::Face(1), Element::Face(2)];
    let seam = |id: usize, far: f64| Seam {
        id,
        solid: 0,
        segments: segments.clone(),
        ends: [SeamEnd::Junction(0), SeamEnd::Junction(0)],
        end_segments: segments.clone(),
        points: [0.0, far, 0.0]
            .iter()
            .map(|&y| SeamPoint {
                point: [10.0, 10.0 + y, 10.0, 5.0],
                touch: vec![[0.0; 3]; 3],
            })
            .collect(),
        handovers: vec![],
        unresolved: vec![],
        trace_seconds: 0.0,
    };
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let mut tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    tracer.seams = vec![seam(0, 1e-9), seam(1, 3.0)];
    tracer.junctions = vec![Junction {
        id: 0,
        solid: 0,
        point: [10.0, 10.0, 10.0],
        radius: 5.0,
        segments: vec![
            Element::Face(0),
            Element::Face(1),
            Element::Face(2),
            Element::Face(3),
        ],
        touch: vec![[0.0; 3]; 4],
        unresolved: true,
    }];
    tracer.arrivals = vec![vec![]];
    assert_eq!(tracer.merge_junctions_found_twice(), 0);
    assert_eq!(tracer.seams.len(), 1);
    assert_eq!(tracer.seams[0].points[1].point[1], 13.0, "the loop is kept");
}

/// At a seam's end an element touching every interior ball may have handed its touch point
/// on to a neighbour: the end ball's touch point is then the neighbour's. (On SOT23's leads a
/// seam between two edges 0.13 mm apart ended at a pinch 3.4 µm past them; its touch points
/// at the upper edge, the fourth contact, lay 9e-5 mm outside the last ball, which the face
/// beyond that edge touched.) Here on the box [0,60]×[0,40]×[0,20]: the edge along x at
/// y = z = 0 and a ball of r = 3 over the bottom face at (30, 5, 3).
#[test]
fn a_fourth_contact_at_a_seams_end_is_on_the_neighbour_touching_the_ball() {
    let (m, class) = crate::testing::classified("box.step");
    let boundary = Boundary::new(&m);
    let opts = TraceOptions::for_model(&m);
    let tracer = tracer::Tracer::new(&m, &boundary, &class, &opts);
    let on_x_axis = |p: DVec3| p.y.abs() < 1e-9 && p.z.abs() < 1e-9;
    let e = (0..m.edges.len())
        .find(|&e| {
            let [a, b] = m.edges[e].vertices;
            on_x_axis(m.vertices[a].point) && on_x_axis(m.vertices[b].point)
        })
        .unwrap();
    let (seg, q) = tracer
        .touching_at_end(Element::Edge(e), DVec3::new(30.0, 5.0, 3.0), 3.0)
        .unwrap();
    assert!(q.distance(DVec3::new(30.0, 5.0, 0.0)) < 1e-9, "{q}");
    let Element::Face(f) = seg else {
        panic!("{seg:?}")
    };
    assert!(m.edges[e].faces.contains(&f));
    // Where the edge itself is at r it keeps the touch point.
    let c = DVec3::new(30.0, 3.0, 4.0);
    let (seg, q) = tracer.touching_at_end(Element::Edge(e), c, 5.0).unwrap();
    assert_eq!(seg, Element::Edge(e));
    assert!(q.distance(DVec3::new(30.0, 0.0, 0.0)) < 1e-9, "{q}");
}
