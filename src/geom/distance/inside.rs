//! Point in solid, from the nearest boundary point and the outward pseudo-normal there.
//!
//! [`Boundary::contains_point`] takes the nearest boundary point `q` and the outward
//! *pseudo-normal* there (Bærentzen & Aanæs, *Signed distance computation using the angle
//! weighted pseudonormal*, IEEE TVCG 11(3), 2005): the face normal on a face, the sum of the
//! adjacent faces' normals at `q` on an edge, the sum of the incident faces' normals weighted by
//! each face's corner angle at a vertex (a full turn of averaged normals at a pole or apex). `p`
//! is inside iff `(p − q)·n < 0`. The sign is right for every `p` whose nearest point is `q` on a
//! closed, oriented, manifold boundary (the theorem of the paper, which carries over to curved
//! faces because only the tangent cones at `q` matter). Voids need nothing special: a void
//! shell's faces have their outward normals pointing into the void ([`crate::model::Face::sign`]).
//! The pseudo-normals of the vertices are computed once, with the [`Boundary`].
//!
//! Points within [`ON_BOUNDARY_REL_DIAGONAL`](super::ON_BOUNDARY_REL_DIAGONAL) × the model's
//! diagonal of the boundary are inside (the solid is closed). A knife edge (two faces meeting
//! at 180° with opposite normals, a fold) has a zero pseudo-normal: past it is inside where the
//! fold is a cusp (interior angle 360°) and outside where it is a fin (0°), by the faces'
//! second-order separation ([`crate::geom::fold`]); non-manifold
//! edges and solids that touch each other are outside the theorem's assumptions.

use super::hit::FaceHit;
use super::index::Boundary;
use super::normal::face_normal;
use crate::model::{Element, Model};
use glam::DVec3;

/// Below this length the pseudo-normal of an edge (the sum of its faces' unit normals) is
/// rounding: the faces fold back onto each other there.
const FOLD_PSEUDO_NORMAL: f64 = 1e-6;

/// A fold edge as near as a face's nearest point, relative to the distance, is the nearest
/// point's edge.
const FOLD_TIE_REL: f64 = 1e-9;

impl Boundary {
    /// True when `p` is inside the material (see the module docs for the method and its
    /// limits). Points on the boundary count as inside.
    pub fn contains_point(&self, model: &Model, p: DVec3) -> bool {
        self.contains_point_where(model, p, |_| true)
    }

    /// [`Boundary::contains_point`] for the solid bounded by the faces for which `keep` holds
    /// (one solid of several, say).
    pub fn contains_point_where(
        &self,
        model: &Model,
        p: DVec3,
        keep: impl Fn(usize) -> bool,
    ) -> bool {
        let Some((fi, hit)) = self.nearest_face_where(model, p, keep) else {
            return false;
        };
        if hit.distance <= self.on_boundary {
            return true;
        }
        let n = self.pseudo_normal(model, fi, &hit);
        // At an edge whose faces fold back onto each other the pseudo-normal vanishes: past
        // the bottom of a cusp (interior angle 360°, a crack of no width) is material, past
        // the tip of a fin (0°) is not.
        if let (Element::Edge(e), Some(t)) = (hit.on, hit.t) {
            if n.length() < FOLD_PSEUDO_NORMAL {
                if let Some(inside) = self.past_fold_is_inside(model, e, t) {
                    return inside;
                }
            }
        }
        // A nearest point on a face that is on a fold edge of it (both faces there at the
        // same distance, the search taking either) is that edge's: the face's normal is the
        // wrong way for the points past the edge on the other face's side.
        if let Element::Face(f) = hit.on {
            for &e in self
                .folds
                .iter()
                .filter(|&&e| model.edges[e].faces.contains(&f))
            {
                let (t, _, d) = super::nearest_on_edge(model, e, p, None);
                if d <= hit.distance + self.on_boundary.max(FOLD_TIE_REL * hit.distance) {
                    if let Some(inside) = self.past_fold_is_inside(model, e, t) {
                        return inside;
                    }
                }
            }
        }
        (p - hit.point).dot(n) < 0.0
    }

    /// Whether the points past fold edge `e` at its parameter `t`, whose nearest boundary
    /// point is there, are material ([`super::super::fold::past_fold_is_material`]); `None`
    /// where that cannot tell.
    fn past_fold_is_inside(&self, model: &Model, e: usize, t: f64) -> Option<bool> {
        let faces = &model.edges[e].faces;
        let hints = [
            self.edge_uv_hint(model, e, faces[0], t),
            self.edge_uv_hint(model, e, faces[1], t),
        ];
        crate::geom::fold::past_fold_is_material(model, e, t, hints)
    }

    /// Outward (pseudo-)normal of the boundary at a hit (not normalised).
    pub fn pseudo_normal(&self, model: &Model, face: usize, hit: &FaceHit) -> DVec3 {
        match (hit.on, hit.t) {
            (Element::Face(f), _) => face_normal(&model.faces[f], hit.uv)
                .or_else(|| self.normal_at(&model.faces[f], f, hit.point, Some(hit.uv)))
                .unwrap_or(DVec3::ZERO),
            (Element::Edge(ei), Some(t)) => {
                let e = &model.edges[ei];
                let mut n = DVec3::ZERO;
                for &f in &e.faces {
                    let hint = if f == face && hit.uv.0.is_finite() {
                        Some(hit.uv)
                    } else {
                        self.edge_uv_hint(model, ei, f, t)
                    };
                    if let Some(nf) = self.normal_at(&model.faces[f], f, hit.point, hint) {
                        n += nf;
                    }
                }
                n
            }
            (Element::Vertex(v), _) => self.vertex_normals[v],
            // (An edge hit always has its parameter.)
            (Element::Edge(_), None) => DVec3::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::distance::Lcg;
    use crate::testing::sample;

    fn assert_inside(file: &str, inside: &[[f64; 3]], outside: &[[f64; 3]]) {
        let model = sample(file);
        let b = Boundary::new(&model);
        for p in inside {
            assert!(
                b.contains_point(&model, DVec3::from_array(*p)),
                "{file}: {p:?} should be inside"
            );
        }
        for p in outside {
            assert!(
                !b.contains_point(&model, DVec3::from_array(*p)),
                "{file}: {p:?} should be outside"
            );
        }
    }

    #[test]
    fn point_in_solid() {
        // Box [0,60]×[0,40]×[0,20]; the outside points have their nearest point on a face,
        // an edge and a vertex.
        assert_inside(
            "box.step",
            &[
                [30.0, 20.0, 10.0],
                [1.0, 1.0, 1.0],
                [59.0, 39.0, 19.0],
                [30.0, 0.5, 10.0],
            ],
            &[
                [-1.0, 20.0, 10.0],
                [30.0, 20.0, 21.0],
                [61.0, 41.0, 21.0],
                [70.0, 20.0, 10.0],
                [30.0, 45.0, 25.0],
            ],
        );
        for file in ["sphere.step", "sphere_nurbs.step"] {
            // Radius 15 at the origin; (0, 0, ±14.9) are next to the poles.
            assert_inside(
                file,
                &[
                    [0.0, 0.0, 0.0],
                    [10.0, 0.0, 0.0],
                    [0.0, 0.0, 14.9],
                    [0.0, 0.0, -14.9],
                    [8.0, 8.0, 8.0],
                ],
                &[
                    [0.0, 0.0, 15.1],
                    [20.0, 0.0, 0.0],
                    [10.0, 10.0, 10.0],
                    [0.0, 0.0, -15.1],
                ],
            );
        }
        // Round bar r = 8 (z 0 to 40) with a blind hole r = 3 drilled into its top, ending
        // in a drill point whose apex (0, 0, 26.197) is reached by the cone's seam edge, up
        // and straight back down: the points on the axis below the apex have it as their
        // nearest point (it read as outside while its pseudo-normal summed to zero); those
        // above it are in the hole.
        assert_inside(
            "trace/bar_with_a_drilled_end.step",
            &[[0.0, 0.0, 18.2], [0.0, 0.0, 22.0], [0.0, 0.0, 26.0]],
            &[[0.0, 0.0, 26.4], [0.0, 0.0, 30.0], [0.0, 0.0, 41.0]],
        );
        // Box [0,60]×[0,40]×[0,30] with a spherical void r = 8 at (30, 20, 15).
        assert_inside(
            "box_with_void.step",
            &[
                [5.0, 5.0, 5.0],
                [30.0, 20.0, 24.0],
                [30.0, 20.0, 6.5],
                [39.0, 20.0, 15.0],
            ],
            &[
                [30.0, 20.0, 15.0],
                [30.0, 20.0, 22.9],
                [36.0, 24.0, 15.0],
                [-1.0, 0.0, 0.0],
            ],
        );
        // Plate [0,80]×[0,50]×[0,10] with holes r = 5, 8, 5 at (15|40|65, 25).
        assert_inside(
            "plate_with_holes.step",
            &[
                [5.0, 5.0, 5.0],
                [40.0, 35.0, 5.0],
                [27.5, 25.0, 5.0],
                [40.0, 33.5, 9.5],
            ],
            &[
                [15.0, 25.0, 5.0],
                [40.0, 25.0, 5.0],
                [65.0, 25.0, 5.0],
                [40.0, 25.0, 11.0],
                [40.0, 32.5, 5.0],
            ],
        );
        // L: [0,60]×[0,30]×[0,10] ∪ [0,10]×[0,30]×[0,40]; reflex edge x = 10, z = 10. (9, 15, 9)
        // has its nearest point on the reflex edge.
        for file in ["l_bracket.step", "l_bracket_nurbs.step"] {
            assert_inside(
                file,
                &[
                    [5.0, 15.0, 30.0],
                    [30.0, 15.0, 5.0],
                    [9.0, 15.0, 9.0],
                    [9.5, 1.0, 39.0],
                ],
                &[
                    [30.0, 15.0, 25.0],
                    [11.0, 15.0, 11.0],
                    [10.5, 15.0, 10.2],
                    [60.5, 15.0, 10.5],
                ],
            );
        }
        // Two disjoint solids: box [0,30]×[0,20]×[0,10], cylinder r = 5, z ∈ [0, 20] on x = 60, y = 10.
        assert_inside(
            "two_solids.step",
            &[[15.0, 10.0, 5.0], [60.0, 10.0, 10.0], [64.0, 10.0, 19.0]],
            &[
                [45.0, 10.0, 5.0],
                [60.0, 10.0, 21.0],
                [65.5, 10.0, 10.0],
                [60.0, 16.0, 10.0],
            ],
        );
    }

    /// Volume of the solid by stratified sampling: one random point in each of `n³` cells of
    /// the bounding box, tested with `contains_point`.
    fn volume_estimate(model: &Model, n: usize) -> f64 {
        let b = Boundary::new(model);
        let (lo, hi) = model.bounding_box();
        let h = (hi - lo) / n as f64;
        let mut rng = Lcg(11);
        let mut inside = 0usize;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let jitter = DVec3::new(rng.next(), rng.next(), rng.next());
                    let p = lo + h * (DVec3::new(i as f64, j as f64, k as f64) + jitter);
                    inside += b.contains_point(model, p) as usize;
                }
            }
        }
        inside as f64 * h.x * h.y * h.z
    }

    /// Past the bottom of a crack of no width (a fold of 360°) is material; past the tip of
    /// a fin of no thickness (0°) is not: the pseudo-normal there is zero, and the edge's
    /// kind decides. The points past the edge are 0.01 from it along the profile's -x, in the
    /// samples' frame (turned 37° about z).
    #[test]
    fn past_a_folds_edge_is_inside_a_crack_and_outside_a_fin() {
        let d = 0.01;
        let (s, c) = 37f64.to_radians().sin_cos();
        // Also level with the crack's bottom, 2.5 to each side: its nearest point is on both
        // of the fold's faces, and the cylinder's normal there is the wrong way for the
        // plane's side (the search took the cylinder, and the point was outside).
        let turned = |x: f64, y: f64, z: f64| [x * c - y * s, x * s + y * c, z];
        assert_inside(
            "trace/crack_folded_to_its_bottom.step",
            &[
                turned(-d, 0.0, 2.5),
                turned(-d, 0.0, 0.5),
                turned(0.0, -2.5, 2.5),
                turned(0.0, 2.5, 2.5),
            ],
            &[],
        );
        assert_inside(
            "trace/fin_folded_to_its_tip.step",
            &[turned(5.0, 0.1, 2.5)],
            &[turned(-d, 0.0, 2.5), turned(-d, 0.0, 0.5)],
        );
    }

    /// The same on the real-world corpus (when it is beside the project), against the
    /// volumes OCCT reports in its MANIFEST.md (4–5 significant digits).
    #[test]
    fn point_in_solid_integrates_to_the_volume_on_real_parts() {
        let Some(dir) = crate::testing::realworld_dir() else {
            return;
        };
        let volumes = [
            ("axom_tet.step", 2666.7),
            ("axom_sliced_cylinder.step", 1.773e6),
            ("axom_revolved_sphere.step", 523.6),
            ("stepswift_nist_ctc_01_asme1_rd.stp", 1.4643e7),
            ("stepswift_nist_ftc_06_asme1_rd.stp", 3.324e6),
            ("stepswift_nist_ftc_09_asme1_rd.stp", 1.364e5),
            ("stepswift_nist_ftc_11_asme1_rb.stp", 5129.0),
            ("trimesh_featuretype.STEP", 1.904e5),
            ("b3d_M6-1x12-countersunk-screw.step", 336.7),
        ];
        let mut failures = Vec::new();
        for (file, volume) in volumes {
            let Ok(model) = crate::ingest::read_model(&dir.join(file)) else {
                failures.push(format!("{file}: unreadable"));
                continue;
            };
            // Stratified sampling at 32³ cells (a thin part like FTC 9, a 3 mm plate, gets
            // 32 cells across its thickness too): the errors measured are ≤ 0.5 %; 1.5 %
            // leaves room for the sampling noise, while one face whose side is misjudged
            // (a cap outside its box: 6 % on FTC 6 before that was fixed) is caught.
            let estimate = volume_estimate(&model, 32);
            if (estimate - volume).abs() > 0.015 * volume {
                failures.push(format!("{file}: {estimate}, OCCT {volume}"));
            }
        }
        assert!(failures.is_empty(), "{failures:#?}");
    }

    /// Point-in-solid integrates to the manifest's exact volume: the fraction of a grid of
    /// cell centres inside, times the box's volume, on every sample whose volume is known.
    ///
    /// Known-bad files go in `KNOWN_BAD` (none now: `cylinder_nurbs.step` was until its
    /// closed-NURBS period was detected); the test fails loudly once one passes.
    #[test]
    fn point_in_solid_integrates_to_the_volume() {
        const KNOWN_BAD: &[&str] = &[];
        let mut failures = Vec::new();
        let text = std::fs::read_to_string(crate::testing::sample_path("manifest.json")).unwrap();
        let manifest: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut checked = 0;
        for s in manifest["samples"].as_array().unwrap() {
            let file = s["file"].as_str().unwrap();
            let (Some(volume), Ok(model)) = (
                s["volume"].as_f64(),
                crate::ingest::read_model(&crate::testing::sample_path(file)),
            ) else {
                continue;
            };
            let estimate = volume_estimate(&model, 28);
            // Stratified sampling errs only in the cells the boundary cuts, each by at most one
            // cell's volume with variance ≤ 1/4 of its square: for these parts (≤ 3000 cut
            // cells of 28³) the standard deviation is ≤ 0.7 % of the volume, so 2.5 % is a
            // margin of 3.5 σ, while a sign error on a feature (the void of box_with_void is
            // 3 % of its volume) or a whole face is larger.
            let ok = (estimate - volume).abs() <= 0.025 * volume;
            if ok == KNOWN_BAD.contains(&file) {
                failures.push(format!(
                    "{file}: {estimate}, exact {volume}{}",
                    if ok {
                        " (known bad, passes now: remove it from the list)"
                    } else {
                        ""
                    }
                ));
            }
            checked += 1;
        }
        assert!(failures.is_empty(), "{failures:#?}");
        assert!(checked >= 20, "checked {checked}");
    }

    /// Points inside the L-bracket written as B-spline patches, below its reflex edge in the
    /// plane of one of the two faces there (x = 10 or z = 10): the nearest point is on the
    /// edge, where that face's patch ends. The descent on the face stops against the patch's
    /// border there, a foot at which `p − x` is tangent to the face: taken as the face's
    /// interior point, its normal left the sign of `(p − x)·n` to rounding, and a ball
    /// centred there could read as outside (the Prusa motor plate's skeletal edges did). The
    /// hit must be on the edge (or on the other face, to which `p − x` is normal), and
    /// inside.
    #[test]
    fn a_foot_at_a_patch_border_is_on_the_edge_there() {
        let model = sample("l_bracket_nurbs.step");
        let b = Boundary::new(&model);
        for p in [
            [10.0, 15.0, 7.0],
            [7.0, 15.0, 10.0],
            [10.0, 5.0, 8.5],
            [8.0, 25.0, 10.0],
            [10.0, 29.0, 9.0],
        ] {
            let p = DVec3::from_array(p);
            let (f, hit) = b.nearest_face_where(&model, p, |_| true).unwrap();
            let on_edge = (p - DVec3::new(10.0, p.y, 10.0)).length();
            assert!(
                (hit.distance - on_edge).abs() < 1e-9,
                "{p}: {hit:?} on F{f}, the edge at {on_edge}"
            );
            // The sign is decided, not left to rounding: the pseudo-normal there (the edge's,
            // or the normal of the face to which `p − x` is normal) points away from `p`.
            let n = b.pseudo_normal(&model, f, &hit);
            let w = p - hit.point;
            assert!(
                w.dot(n) <= -0.5 * w.length() * n.length(),
                "{p}: {hit:?} on F{f}, pseudo-normal {n}"
            );
            assert!(b.contains_point(&model, p), "{p}: {hit:?} on F{f}");
        }
    }
}
