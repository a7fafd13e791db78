//! The queries on a [`Boundary`]: the nearest point of the whole boundary (of the faces a
//! filter keeps), the nearest point of one face with the cached samples, and the faces within
//! a radius.
//!
//! The faces are visited by branch and bound on the bounding-volume hierarchy of their boxes:
//! a face is evaluated only if its box is nearer than the best distance so far (or than the
//! radius), and then [`face_nearest`] prunes by its cells and edge samples. Queries do not
//! allocate (but [`Boundary::within`], which returns a new list).

use super::face::{face_nearest, Cached};
use super::hit::FaceHit;
use super::index::{range, Boundary};
use super::normal::surface_params;
use crate::geom::bvh::box_distance_squared;
use crate::geom::project::project_plane;
use crate::model::{Element, Model};
use glam::DVec3;

impl Boundary {
    /// The nearest point of the whole boundary to `p`. For a model without faces the distance
    /// is infinite and the point NaN.
    pub fn nearest(&self, model: &Model, p: DVec3) -> FaceHit {
        self.nearest_face(model, p).map_or(
            FaceHit {
                point: DVec3::NAN,
                distance: f64::INFINITY,
                uv: (f64::NAN, f64::NAN),
                on: Element::Face(usize::MAX),
                t: None,
            },
            |h| h.1,
        )
    }

    /// Like [`Boundary::nearest`], with the face the hit was found on (an edge or vertex hit
    /// belongs to several faces; this is the one whose `uv` the hit carries).
    pub fn nearest_face(&self, model: &Model, p: DVec3) -> Option<(usize, FaceHit)> {
        self.nearest_face_where(model, p, |_| true)
    }

    /// [`Boundary::nearest_face`] over the faces for which `keep` holds (one solid of several,
    /// say).
    pub fn nearest_face_where(
        &self,
        model: &Model,
        p: DVec3,
        keep: impl Fn(usize) -> bool,
    ) -> Option<(usize, FaceHit)> {
        self.nearest_face_within(model, p, f64::INFINITY, keep)
    }

    /// [`Boundary::nearest_face_where`] when it is nearer than `bound`, `None` otherwise: the
    /// same hit, found without evaluating the faces that cannot come that near (the question
    /// "does anything come closer than r" visits only those).
    pub fn nearest_face_within(
        &self,
        model: &Model,
        p: DVec3,
        bound: f64,
        keep: impl Fn(usize) -> bool,
    ) -> Option<(usize, FaceHit)> {
        debug_assert_eq!(
            model.faces.len(),
            self.faces.len(),
            "Boundary built for another model"
        );
        if bound.is_nan() || bound <= 0.0 {
            return None;
        }
        let mut best: Option<(usize, FaceHit)> = None;
        let mut best_d = bound;
        self.bvh.branch_and_bound(p, bound * bound, |fi, _| {
            if !keep(fi) {
                return best_d * best_d;
            }
            let cached = Some(Cached { boundary: self });
            if let Some(hit) = face_nearest(model, fi, p, None, best_d, cached, false) {
                if hit.distance < best_d {
                    best_d = hit.distance;
                    best = Some((fi, hit));
                }
            }
            best_d * best_d
        });
        // The surface parameters of an edge hit, computed once for the winner.
        if let Some((fi, hit)) = &mut best {
            if !hit.uv.0.is_finite() {
                let face = &model.faces[*fi];
                let hint = match (hit.on, hit.t) {
                    (Element::Edge(ei), Some(t)) => self.edge_uv_hint(model, ei, *fi, t),
                    (Element::Vertex(v), _) => model.faces[*fi]
                        .loops
                        .iter()
                        .flat_map(|l| l.edges.iter())
                        .find_map(|oe| {
                            let e = &model.edges[oe.edge];
                            let t = if e.vertices[0] == v {
                                Some(e.range.0)
                            } else if e.vertices[1] == v {
                                Some(e.range.1)
                            } else {
                                None
                            };
                            t.and_then(|t| self.edge_uv_hint(model, oe.edge, *fi, t))
                        }),
                    // (An edge hit always has its parameter.)
                    (Element::Face(_) | Element::Edge(_), _) => None,
                };
                hit.uv = match self.faces[*fi].plane {
                    Some(frame) => project_plane(frame, hit.point),
                    None => surface_params(&face.surface, hit.point, hint),
                };
            }
        }
        best
    }

    /// The nearest point of face `face` closer than `bound` (use `f64::INFINITY` for no bound),
    /// with the cached samples: like [`nearest_on_face`](crate::geom::nearest_on_face) but faster.
    /// `None` when nothing on the face is closer than `bound`.
    pub fn nearest_on_face(
        &self,
        model: &Model,
        face: usize,
        p: DVec3,
        hint: Option<(f64, f64)>,
        bound: f64,
    ) -> Option<FaceHit> {
        face_nearest(
            model,
            face,
            p,
            hint,
            bound,
            Some(Cached { boundary: self }),
            true,
        )
    }

    /// The faces with a point closer than `r` to `p`, in increasing order.
    pub fn within(&self, model: &Model, p: DVec3, r: f64) -> Vec<usize> {
        let mut out = Vec::new();
        self.within_into(model, p, r, &mut out);
        out
    }

    /// [`Boundary::within`] into a caller's buffer (cleared first), to avoid allocating.
    pub fn within_into(&self, model: &Model, p: DVec3, r: f64, out: &mut Vec<usize>) {
        out.clear();
        if r.is_nan() || r <= 0.0 {
            return;
        }
        let r2 = r * r;
        self.bvh.branch_and_bound(p, r2, |fi, _| {
            if self.face_within(model, fi, p, r) {
                out.push(fi);
            }
            r2
        });
        out.sort_unstable();
    }

    fn face_within(&self, model: &Model, fi: usize, p: DVec3, r: f64) -> bool {
        let r2 = r * r;
        // Quick accept: a sampled point of an edge of the face is a point of the face.
        for &ei in &self.face_edges[range(&self.faces[fi].edges)] {
            let ec = &self.edges[ei as usize];
            if box_distance_squared(&ec.bbox, p) < r2
                && self.edge_p[range(&ec.samples)]
                    .iter()
                    .any(|x| x.distance_squared(p) < r2)
            {
                return true;
            }
        }
        face_nearest(
            model,
            fi,
            p,
            None,
            r,
            Some(Cached { boundary: self }),
            false,
        )
        .is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::nearest_on_face;
    use crate::testing::distance::{assert_hit_on_face, Lcg};

    /// The distance from `p` to the ellipse with semi-axes `a` (along x) and `b` (along y)
    /// about the z axis at height `z`, by dense sampling (200,000 points).
    fn ellipse_distance(a: f64, b: f64, z: f64, p: DVec3) -> f64 {
        (0..200_000)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 200_000.0;
                DVec3::new(a * t.cos(), b * t.sin(), z).distance(p)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// A face with two basins of the distance about as near: the elliptic bar's wall (semi-axes
    /// 20 and 10, 16 high) from a point just past the major axis, where the wall's two sides
    /// are at 7.81 (this side, y < 0) and 8.00 (the other). The nearest cell of the face's
    /// coarse grid lies on the farther side, whose foot (8.00) used to be returned: the
    /// tracer's seams ran on past their junction and `verify` passed them (OpenCASCADE did
    /// not). The hit must be on this side, at the exact distance to the ellipse (by dense
    /// sampling).
    #[test]
    fn a_face_seen_twice_gives_its_nearer_side() {
        let model =
            crate::ingest::read_model(&crate::testing::sample_path("trace/elliptic_bar.step"))
                .unwrap();
        let b = Boundary::new(&model);
        let p = DVec3::new(10.606865956887082, -0.10567701088875538, 8.0);
        let hit = b.nearest(&model, p);
        let exact = ellipse_distance(20.0, 10.0, 8.0, p);
        assert!(hit.point.y < 0.0, "{hit:?}");
        assert!(
            (hit.distance - exact).abs() < 1e-6,
            "{} vs {exact}",
            hit.distance
        );
    }

    /// The bounded query gives the unbounded one's hit when that is nearer than the bound,
    /// and nothing otherwise (nor for a bound of zero, negative or NaN), at random points in
    /// and about parts whose faces are B-splines (the elliptic bar), planes, cylinders and
    /// circles (the plate with holes, the boss on a plate), a sphere, a torus, and an
    /// elliptic cylinder with elliptic edges — with bounds far from the distance and within
    /// a millionth of it on both sides (the tracer's intrusion query asks just short of a
    /// ball's radius). The query skips a face whose whole surface, or an edge whose whole
    /// curve, cannot come within the bound: a bound on either that were too large would
    /// show here as nothing found where the unbounded query finds a nearer hit.
    #[test]
    fn a_bounded_query_is_the_nearest_hit_or_nothing() {
        let mut rng = Lcg(7);
        for file in [
            "trace/elliptic_bar.step",
            "plate_with_holes.step",
            "boss_on_plate.step",
            "sphere.step",
            "torus.step",
            "elliptic_cylinder.step",
        ] {
            let model = crate::ingest::read_model(&crate::testing::sample_path(file)).unwrap();
            let b = Boundary::new(&model);
            let (lo, hi) = model.bounding_box();
            let margin = 0.2 * (hi - lo);
            let (mut near, mut far) = (0, 0);
            for k in 0..600 {
                let p = rng.in_box(lo - margin, hi + margin);
                let (f, hit) = b.nearest_face(&model, p).unwrap();
                let bound = match k % 3 {
                    0 => hit.distance * (0.5 + rng.next()),
                    1 => hit.distance * (1.0 - 1e-6),
                    _ => hit.distance * (1.0 + 1e-6),
                };
                match b.nearest_face_within(&model, p, bound, |_| true) {
                    Some((g, h)) => {
                        near += 1;
                        assert!(hit.distance < bound, "{file} {p}: {h:?} beyond {bound}");
                        assert_eq!(g, f, "{file} {p}");
                        assert_eq!(h.distance, hit.distance, "{file} {p}");
                        assert_eq!(h.point, hit.point, "{file} {p}");
                    }
                    None => {
                        far += 1;
                        assert!(hit.distance >= bound, "{file} {p}: {hit:?} within {bound}");
                    }
                }
                for bad in [0.0, -1.0, f64::NAN] {
                    assert!(b.nearest_face_within(&model, p, bad, |_| true).is_none());
                }
            }
            assert!(near > 100 && far > 100, "{file}: {near} near, {far} far");
        }
    }

    /// Points just off an ellipse's major axis, between its two centres of curvature at the
    /// vertices, seen from where the vertex is a maximum of the distance along the wall (the
    /// elliptic cylinder as a NURBS, semi-axes 30 and 15: the centres of curvature at
    /// x = ±22.5). The face's nearest cell there is the vertex's: the descent from it, with
    /// Gauss–Newton's short steps where the distance curves away, stopped 0.11 rad from the
    /// vertex, 0.06 mm farther than the foot, so sheet-mesh balls there were too large and
    /// OpenCASCADE found them touching one side only. Every hit must be at the exact distance
    /// (by dense sampling).
    #[test]
    fn a_point_past_a_centre_of_curvature_finds_its_foot_off_the_vertex() {
        let model =
            crate::ingest::read_model(&crate::testing::sample_path("elliptic_cylinder_nurbs.step"))
                .unwrap();
        let b = Boundary::new(&model);
        for k in 0..=40 {
            let x = -22.4 + 44.8 * k as f64 / 40.0;
            for y in [4e-4, -1e-3, 0.0] {
                let p = DVec3::new(x, y, 8.8);
                let hit = b.nearest(&model, p);
                let exact = ellipse_distance(30.0, 15.0, 8.8, p).min(8.8);
                assert!(
                    (hit.distance - exact).abs() < 1e-6,
                    "{p}: {} vs {exact} ({hit:?})",
                    hit.distance
                );
            }
        }
    }

    /// Every point of every face (on a grid over its domain, inside its trim) is at distance 0
    /// from the boundary, on faces that wind round many times (`samples/distance`: a coil
    /// whose turns are 0.2 mm apart; the M6 screw's thread when the corpus is there) and on a
    /// surface of revolution whose neck passes 0.3 mm from its axis (`necked_vase`). A grid
    /// cell as long as a turn used to seed the descent on the next turn: 13 % of the screw's
    /// points were found up to 0.30 mm away, half of the coil's flanks up to 0.2 mm; a cell
    /// across the vase's axis left 74 of its 576 points found up to 26 mm away.
    #[test]
    fn points_of_winding_faces_are_on_the_boundary() {
        let mut files = vec![
            crate::testing::sample_path("distance/coil.step"),
            crate::testing::sample_path("distance/necked_vase.step"),
        ];
        if let Some(dir) = crate::testing::realworld_dir() {
            files.push(dir.join("b3d_M6-1x12-countersunk-screw.step"));
        }
        for path in &files {
            let file = path.file_name().unwrap().to_string_lossy();
            let model = crate::ingest::read_model(path).expect("reads");
            let boundary = Boundary::new(&model);
            let scale = model.diagonal();
            let n = 24;
            let mut checked = 0;
            for (fi, face) in model.faces.iter().enumerate() {
                let d = &face.domain;
                for i in 0..n {
                    for j in 0..n {
                        let uv = glam::DVec2::new(
                            d.u.0 + (d.u.1 - d.u.0) * (i as f64 + 0.5) / n as f64,
                            d.v.0 + (d.v.1 - d.v.0) * (j as f64 + 0.5) / n as f64,
                        );
                        if !crate::geom::trim::contains(face, uv) {
                            continue;
                        }
                        let p = crate::geom::surface_point(&face.surface, uv.x, uv.y);
                        let hit = boundary.nearest(&model, p);
                        assert!(
                            hit.distance <= 1e-9 * scale,
                            "{file}: face {fi} at {uv}, {p}: nearest boundary {} away on {:?}",
                            hit.distance,
                            hit.on
                        );
                        checked += 1;
                    }
                }
            }
            assert!(
                checked > 100 * model.faces.len(),
                "{file}: {checked} points"
            );
        }
    }

    /// `Boundary::nearest` equals the minimum of `nearest_on_face` over all faces, and
    /// `within` lists exactly the faces closer than r.
    #[test]
    fn boundary_nearest_and_within_match_all_faces() {
        let mut files: Vec<std::path::PathBuf> = [
            "box.step",
            "filleted_box.step",
            "box_bspline_top.step",
            "plate_with_holes.step",
            "box_with_void.step",
            "torus.step",
            "l_bracket_nurbs.step",
        ]
        .iter()
        .map(|f| crate::testing::sample_path(f))
        .collect();
        // Real parts with many faces, when the corpus is beside the project.
        if let Some(dir) = crate::testing::realworld_dir() {
            for f in [
                "stepswift_nist_ftc_06_asme1_rd.stp",
                "b3d_M6-1x12-countersunk-screw.step",
            ] {
                let path = dir.join(f);
                if path.exists() {
                    files.push(path);
                }
            }
        }
        for path in &files {
            let file = path.file_name().unwrap().to_string_lossy();
            let model = crate::ingest::read_model(path).expect("reads");
            let boundary = Boundary::new(&model);
            let (lo, hi) = model.bounding_box();
            let pad = (hi - lo) * 0.2;
            let scale = (hi - lo).length();
            let mut rng = Lcg(99);
            for k in 0..60 {
                let p = rng.in_box(lo - pad, hi + pad);
                let all: Vec<f64> = (0..model.faces.len())
                    .map(|f| {
                        nearest_on_face(&model, f, p, None).map_or(f64::INFINITY, |h| h.distance)
                    })
                    .collect();
                let brute = all.iter().copied().fold(f64::INFINITY, f64::min);
                let (fi, hit) = boundary.nearest_face(&model, p).unwrap();
                assert!(
                    (hit.distance - brute).abs() <= 1e-9 * scale,
                    "{file} point {k} {p}: BVH {} on face {fi}, all faces {brute}",
                    hit.distance
                );
                assert_hit_on_face(&model, scale, fi, p, &hit, &format!("{file} point {k}"));
                assert_eq!(boundary.nearest(&model, p), hit);
                let r = brute * (0.5 + 1.5 * rng.next()) + 1e-3 * scale;
                let got = boundary.within(&model, p, r);
                let expect: Vec<usize> = (0..all.len()).filter(|&f| all[f] < r).collect();
                let borderline = |f: &usize| (all[*f] - r).abs() <= 1e-9 * scale;
                let g: Vec<usize> = got.iter().copied().filter(|f| !borderline(f)).collect();
                let e: Vec<usize> = expect.iter().copied().filter(|f| !borderline(f)).collect();
                assert_eq!(g, e, "{file} point {k} {p} r {r}");
            }
        }
    }
}
