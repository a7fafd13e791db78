//! The outlines of curved faces in a view (silhouettes: where the surface normal is
//! perpendicular to the view direction), so that a cylinder, sphere or torus looks like one.
//!
//! Each non-planar face is sampled once on a [`SILHOUETTE_GRID`]² grid over its UV domain
//! ([`face_grids`]); per view, marching squares on `n · toward` find the outlines, placed on
//! the exact surface. An outline point lies on the surface, but where along the surface it
//! sits comes from linear interpolation on the grid: close enough to see, not a tolerance,
//! and an outline loop smaller than a grid cell may be missed.

use super::layout::View;
use crate::geom::{eval_surface, surface_kind};
use crate::model::Model;
use glam::{DVec2, DVec3};

/// Grid size (per parameter direction) of the silhouette search on a curved face.
pub const SILHOUETTE_GRID: usize = 48;

/// A curved face sampled on a grid over its UV domain, for silhouettes.
pub(super) struct FaceGrid {
    face: usize,
    u: (f64, f64),
    v: (f64, f64),
    /// Unit normals (orientation irrelevant) at the `(n + 1)²` nodes, row by row in v.
    normals: Vec<DVec3>,
}

/// Grids of every non-planar face (a plane has no silhouette).
pub(super) fn face_grids(model: &Model) -> Vec<FaceGrid> {
    let n = SILHOUETTE_GRID;
    model
        .faces
        .iter()
        .enumerate()
        .filter(|(_, f)| surface_kind(&f.surface) != "plane")
        .map(|(i, f)| {
            let (u, v) = (f.domain.u, f.domain.v);
            let mut normals = Vec::with_capacity((n + 1) * (n + 1));
            for j in 0..=n {
                for k in 0..=n {
                    let (a, b) = (grid_at(u, k, n), grid_at(v, j, n));
                    let d = eval_surface(&f.surface, a, b);
                    normals.push(d.su.cross(d.sv).normalize_or_zero());
                }
            }
            FaceGrid {
                face: i,
                u,
                v,
                normals,
            }
        })
        .collect()
}

/// How far (relative to the range) a crossing on the domain's border is moved inside it.
const NUDGE_REL_RANGE: f64 = 1e-9;
/// A face is seen edge-on when `|n · toward|` stays below this at every grid node.
const MAX_EDGE_ON_COS: f64 = 1e-6;
/// The tilt of the view direction (about 1e-7 rad), see [`silhouettes`].
const VIEW_TILT: DVec3 = DVec3::new(3.1e-8, 7.3e-8, 5.9e-8);

/// `x` moved at most [`NUDGE_REL_RANGE`] of the range into `range`.
fn nudge_inside(x: f64, range: (f64, f64)) -> f64 {
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    let e = NUDGE_REL_RANGE * (hi - lo);
    x.clamp(lo + e, hi - e)
}

fn grid_at(range: (f64, f64), k: usize, n: usize) -> f64 {
    range.0 + (range.1 - range.0) * k as f64 / n as f64
}

/// The silhouettes (contour generators: where the surface normal is perpendicular to the
/// view direction) of the curved faces in `view`, as 3D polylines on the exact surfaces.
///
/// Marching squares on `n · toward` over each face's grid: a crossing is placed on a grid
/// edge by linear interpolation, evaluated on the surface, and kept when it lies in the
/// trimmed face; crossings are chained through the cells into polylines. A face seen
/// exactly edge-on (a cylinder along its axis) has `n · toward = 0` everywhere and no
/// silhouette apart from its boundary edges.
pub(super) fn silhouettes(model: &Model, grids: &[FaceGrid], view: &View) -> Vec<Vec<DVec3>> {
    let n = SILHOUETTE_GRID;
    let node = |k: usize, j: usize| j * (n + 1) + k;
    // The view direction tilted by ~1e-7 rad, so that no grid node lies exactly on a
    // silhouette (where `n · toward = 0` the sign test cannot tell on which side of a node
    // the silhouette passes: a sphere's meridian u = 0 in the front view was lost).
    let toward = (view.toward + VIEW_TILT).normalize();
    let mut out = vec![];
    for grid in grids {
        let face = &model.faces[grid.face];
        let g: Vec<f64> = grid.normals.iter().map(|q| q.dot(toward)).collect();
        if g.iter().all(|x| x.abs() < MAX_EDGE_ON_COS) {
            continue;
        }
        // Crossing on the grid edge `key`: 2·node for the edge to the next u, 2·node + 1
        // for the edge to the next v.
        let mut crossing: Vec<Option<DVec3>> = vec![None; 2 * (n + 1) * (n + 1)];
        for j in 0..=n {
            for k in 0..=n {
                let a = node(k, j);
                for (dir, (k2, j2)) in [(0, (k + 1, j)), (1, (k, j + 1))] {
                    if k2 > n || j2 > n {
                        continue;
                    }
                    let b = node(k2, j2);
                    if (g[a] > 0.0) == (g[b] > 0.0) {
                        continue;
                    }
                    let t = g[a] / (g[a] - g[b]);
                    let uv = DVec2::new(
                        grid_at(grid.u, k, n)
                            + t * (grid_at(grid.u, k2, n) - grid_at(grid.u, k, n)),
                        grid_at(grid.v, j, n)
                            + t * (grid_at(grid.v, j2, n) - grid_at(grid.v, j, n)),
                    );
                    // A crossing on the domain's border (a sphere's meridian u = 0) is
                    // tested a hair inside it: the trimming test may leave the border out.
                    let inner = DVec2::new(nudge_inside(uv.x, grid.u), nudge_inside(uv.y, grid.v));
                    if crate::geom::trim::contains(face, inner) {
                        crossing[2 * a + dir] =
                            Some(crate::geom::surface_point(&face.surface, uv.x, uv.y));
                    }
                }
            }
        }
        // Segments through the cells, as pairs of edge keys.
        let mut links: Vec<Vec<usize>> = vec![vec![]; crossing.len()];
        for j in 0..n {
            for k in 0..n {
                let sides = [
                    2 * node(k, j),
                    2 * node(k, j) + 1,
                    2 * node(k, j + 1),
                    2 * node(k + 1, j) + 1,
                ];
                let hit: Vec<usize> = sides
                    .into_iter()
                    .filter(|&e| crossing[e].is_some())
                    .collect();
                for pair in hit.chunks_exact(2) {
                    links[pair[0]].push(pair[1]);
                    links[pair[1]].push(pair[0]);
                }
            }
        }
        // Chains: from the ends first, then what is left (closed loops).
        let mut used = vec![false; crossing.len()];
        let starts = (0..links.len())
            .filter(|&e| links[e].len() == 1)
            .chain(0..links.len());
        for start in starts {
            if used[start] || links[start].is_empty() {
                continue;
            }
            let mut chain = vec![];
            let mut at = start;
            loop {
                used[at] = true;
                chain.push(crossing[at].unwrap());
                match links[at].iter().find(|&&e| !used[e]) {
                    Some(&next) => at = next,
                    None => {
                        if links[at].contains(&start) && chain.len() > 2 {
                            chain.push(crossing[start].unwrap());
                        }
                        break;
                    }
                }
            }
            if chain.len() >= 2 {
                out.push(chain);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::layout::{isometric, FRONT, RIGHT, TOP};
    use super::*;

    #[test]
    fn a_cylinder_has_two_straight_outlines_from_the_side_and_none_along_its_axis() {
        let m = crate::testing::sample("cylinder.step");
        let (lo, hi) = m.bbox;
        let r = 0.5 * (hi.x - lo.x);
        let grids = face_grids(&m);
        assert_eq!(grids.len(), 1, "one curved face");
        // Seen along its axis (z) the side face is edge-on: no outline.
        assert!(silhouettes(&m, &grids, &TOP).is_empty());
        // From the front: the generators at x = ±r, y = 0, over the whole height.
        let lines = silhouettes(&m, &grids, &FRONT);
        assert_eq!(lines.len(), 2, "{lines:?}");
        let mut xs = vec![];
        for line in &lines {
            for q in line {
                assert!((q.x.abs() - r).abs() < 1e-3 * r, "{q}");
                assert!(q.y.abs() < 1e-3 * r, "{q}");
            }
            let (zlo, zhi) = line
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                    (a.min(q.z), b.max(q.z))
                });
            assert!((zlo - lo.z).abs() < 1e-6 && (zhi - hi.z).abs() < 1e-6);
            xs.push(line[0].x.signum());
        }
        xs.sort_by(f64::total_cmp);
        assert_eq!(xs, [-1.0, 1.0]);
    }

    #[test]
    fn a_sphere_has_a_closed_outline_in_every_view() {
        let m = crate::testing::sample("sphere.step");
        let (lo, hi) = m.bbox;
        let (c, r) = (0.5 * (lo + hi), 0.5 * (hi.x - lo.x));
        let grids = face_grids(&m);
        for view in [FRONT, TOP, RIGHT, isometric()] {
            let lines = silhouettes(&m, &grids, &view);
            // The great circle perpendicular to the view, in one or two pieces (a meridian
            // outline is cut at the poles), all on the sphere and in its plane.
            let n: usize = lines.iter().map(|l| l.len()).sum();
            assert!(n > SILHOUETTE_GRID, "{} {n}", view.name);
            for q in lines.iter().flatten() {
                assert!(((*q - c).length() - r).abs() < 1e-6 * r, "{q}");
                assert!(
                    (*q - c).dot(view.toward).abs() < 2e-3 * r,
                    "{} {q}",
                    view.name
                );
            }
            // It goes all around: points in every quadrant of the view.
            let quadrants: std::collections::BTreeSet<(bool, bool)> = lines
                .iter()
                .flatten()
                .map(|q| ((*q - c).dot(view.u) > 0.0, (*q - c).dot(view.v) > 0.0))
                .collect();
            assert_eq!(quadrants.len(), 4, "{}", view.name);
        }
    }
}
