//! Sheet geometry as a triangle mesh (`docs/design.md`, the sheet mesh).
//!
//! Every point `p` of a face, with inward normal `m`, is the foot point of exactly one
//! maximal ball: the largest ball tangent to the face at `p` inside the solid. Its centre is
//! a medial point, on the sheet of the face and whatever the ball touches second. So a grid
//! over each face's trimmed parameter domain, each grid point mapped to its maximal ball,
//! gives the sheets as height fields over the faces; grid cells whose corners belong to one
//! sheet become two triangles.
//!
//! The maximal ball is found by *shrinking*: start with a ball too large, take the nearest
//! boundary point `q` to its centre, and shrink to the ball tangent at `p` through `q`,
//! `r = ‖q − p‖² / (2 m·(q − p))`, until nothing is nearer than `r` (each step one exact
//! nearest-point query; a few steps suffice). Mesh vertices are therefore exact medial points
//! (to the accuracy); only the triangles between them are linear.
//!
//! A sheet is meshed from the faces of one side only (its lower-numbered segment group), so
//! it is not covered twice; a sheet between two touches of one group (a face touching the ball
//! twice) is meshed from both foot regions, which cover it twice. Cells are cut at the sheet
//! boundaries, not fitted to them: the mesh stops up to one cell short of a seam or rim.

use crate::classify::Classification;
use crate::geom::Boundary;
use crate::medial::segments::SegmentGroups;
use crate::medial::sheets::Sheets;
use crate::medial::NormalField;
use crate::model::Element;
use crate::model::Model;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// How densely the faces are sampled.
#[derive(Clone, Copy, Debug)]
pub struct MeshOptions {
    /// About this many grid points over the whole part, shared among faces by area.
    pub samples: usize,
    /// Grid points per face side, at least and at most.
    pub min_side: usize,
    pub max_side: usize,
    /// The accuracy of the ball radii (mm).
    pub accuracy: f64,
}

/// Default sampling budget: ~3000 grid points (refined near sheet boundaries), enough to see every sheet of the
/// reference parts and about a second on a 200-face part.
pub const DEFAULT_SAMPLES: usize = 3000;

impl MeshOptions {
    /// Defaults for `model` at the trace accuracy `accuracy`.
    pub fn new(accuracy: f64) -> MeshOptions {
        MeshOptions {
            samples: DEFAULT_SAMPLES,
            min_side: 4,
            max_side: 48,
            accuracy,
        }
    }
}

/// Triangles of the medial sheets: vertices `[x, y, z, r]`, triangles (indices into
/// `vertices`) grouped by sheet.
#[derive(Clone, Debug, Default)]
pub struct SheetMesh {
    pub vertices: Vec<[f64; 4]>,
    /// Per sheet: its id in [`Sheets::sheets`] (None where the sheet's boundary did not close,
    /// so it has no entry) and its triangles.
    pub parts: Vec<MeshPart>,
}

/// The triangles of one sheet.
#[derive(Clone, Debug)]
pub struct MeshPart {
    pub sheet: Option<usize>,
    /// The sheet's two segment groups (faces joined by smooth and reflex edges, numbered
    /// internally), as a name for parts that have no sheet entry (`G3|G7`).
    pub name: String,
    pub triangles: Vec<[u32; 3]>,
}

impl SheetMesh {
    /// Number of triangles over all parts.
    pub fn triangles(&self) -> usize {
        self.parts.iter().map(|p| p.triangles.len()).sum()
    }
}

/// The vertices (`[x, y, z, r]`) and triangles (tagged with their sheet's two groups) meshed
/// from one face.
type FacePiece = (Vec<[f64; 4]>, Vec<(usize, usize, [u32; 3])>);

/// One sampled ball: centre, radius, and the group of what it touches second.
#[derive(Clone, Copy, Debug)]
struct Ball {
    c: DVec3,
    r: f64,
    partner: usize,
}

/// Meshes the sheets of a traced part. `sheets` names them (see [`crate::medial::sheets()`]).
pub fn sheet_mesh(
    model: &Model,
    boundary: &Boundary,
    class: &Classification,
    sheets: &Sheets,
    opts: &MeshOptions,
) -> SheetMesh {
    let groups = SegmentGroups::new(model, class);
    let group_of_face = |f: usize| groups.of(Element::Face(f));
    // Sheets by (solid, group pair).
    let mut sheet_of: BTreeMap<(usize, usize, usize), usize> = BTreeMap::new();
    for s in &sheets.sheets {
        let (a, b) = (groups.of(s.segments[0]), groups.of(s.segments[1]));
        sheet_of.insert((s.solid, a.min(b), a.max(b)), s.id);
    }
    // Grid cells of about one size over the whole part (the budget shared by area), so a
    // long thin face gets long thin rows of square-ish cells.
    let extents: Vec<(f64, f64)> = (0..model.faces.len())
        .map(|f| approx_extent(model, f))
        .collect();
    let total: f64 = extents.iter().map(|(a, b)| a * b).sum::<f64>();
    let h = (total / opts.samples as f64).sqrt().max(f64::MIN_POSITIVE);
    let per_face: Vec<FacePiece> = (0..model.faces.len())
        .into_par_iter()
        .map(|f| {
            let side = |len: f64| ((len / h).round() as usize).clamp(opts.min_side, opts.max_side);
            let (nu, nv) = (side(extents[f].0), side(extents[f].1));
            face_mesh(model, boundary, f, (nu, nv), opts, &group_of_face)
        })
        .collect();
    let mut mesh = SheetMesh::default();
    let mut part_index: BTreeMap<(usize, usize, usize), usize> = BTreeMap::new();
    for (f, (verts, tris)) in per_face.into_iter().enumerate() {
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(verts);
        let solid = model.solid_of_face(f);
        for (ga, gb, t) in tris {
            let key = (solid, ga.min(gb), ga.max(gb));
            let k = *part_index.entry(key).or_insert_with(|| {
                mesh.parts.push(MeshPart {
                    sheet: sheet_of.get(&key).copied(),
                    name: format!("G{}|G{}", key.1, key.2),
                    triangles: vec![],
                });
                mesh.parts.len() - 1
            });
            mesh.parts[k]
                .triangles
                .push([t[0] + base, t[1] + base, t[2] + base]);
        }
    }
    mesh.parts
        .sort_by_key(|p| (p.sheet.is_none(), p.sheet, p.name.clone()));
    mesh
}

/// Times a grid cell is split in four where its corners do not lie on one sheet, so the mesh
/// reaches to 1/2³ of a cell from the sheet boundaries.
const REFINE: u32 = 3;

/// The mesh from face `f`'s foot points: local vertices and triangles tagged with the two
/// groups of their sheet.
fn face_mesh(
    model: &Model,
    boundary: &Boundary,
    f: usize,
    (nu, nv): (usize, usize),
    opts: &MeshOptions,
    group_of_face: &(dyn Fn(usize) -> usize + Sync),
) -> FacePiece {
    let face = &model.faces[f];
    let (u0, u1) = face.domain.u;
    let (v0, v1) = face.domain.v;
    let me = group_of_face(f);
    // Balls on a lattice 2^REFINE times finer than the grid, computed on demand.
    let k = 1usize << REFINE;
    let (lu, lv) = (nu * k, nv * k);
    let mut balls: std::collections::HashMap<(usize, usize), Option<Ball>> = Default::default();
    // The last ball's radius: cells are visited neighbour after neighbour, so it is a close
    // first guess for the next one.
    let mut last_r: Option<f64> = None;
    let mut ball = |i: usize, j: usize| -> Option<Ball> {
        *balls.entry((i, j)).or_insert_with(|| {
            let uv = DVec2::new(
                u0 + (u1 - u0) * (i as f64 + 0.5 * k as f64) / lu as f64,
                v0 + (v1 - v0) * (j as f64 + 0.5 * k as f64) / lv as f64,
            );
            if !boundary.contains_uv(face, f, uv) {
                return None;
            }
            let b = maximal_ball(model, boundary, f, uv, opts.accuracy, last_r, group_of_face);
            last_r = b.map(|b| b.r).or(last_r);
            b
        })
    };
    let mut verts = vec![];
    let mut index: std::collections::HashMap<(usize, usize), u32> = Default::default();
    let mut tris = vec![];
    // Cells to visit: (lattice corner, size); coarse cells first.
    let mut stack: Vec<(usize, usize, usize)> = vec![];
    for j in 0..nv.saturating_sub(1) {
        for i in 0..nu.saturating_sub(1) {
            stack.push((i * k, j * k, k));
        }
    }
    while let Some((i, j, size)) = stack.pop() {
        let corners = [(i, j), (i + size, j), (i + size, j + size), (i, j + size)];
        let cell: Vec<Option<Ball>> = corners.iter().map(|&(a, b)| ball(a, b)).collect();
        let uniform = cell.iter().all(|b| b.is_some()) && {
            let p = cell[0].unwrap().partner;
            cell.iter().all(|b| b.unwrap().partner == p)
        };
        // A cell of one sheet whose centres do not jump (a jump means a seam runs through
        // it: the sheet folds or another sheet takes over).
        let smooth = uniform && {
            let c: Vec<Ball> = cell.iter().map(|b| b.unwrap()).collect();
            let diagonal = c[0].c.distance(c[2].c).max(c[1].c.distance(c[3].c));
            let sides = (0..4)
                .map(|q| c[q].c.distance(c[(q + 1) % 4].c))
                .fold(0.0, f64::max);
            diagonal <= 2.0 * sides + opts.accuracy
        };
        if smooth {
            let partner = cell[0].unwrap().partner;
            // One sheet, meshed from its lower group's side (both when a group touches
            // itself).
            if partner < me {
                continue;
            }
            let mut local = [0u32; 4];
            for (q, &(a, b)) in corners.iter().enumerate() {
                local[q] = *index.entry((a, b)).or_insert_with(|| {
                    let c = cell[q].unwrap();
                    verts.push([c.c.x, c.c.y, c.c.z, c.r]);
                    (verts.len() - 1) as u32
                });
            }
            tris.push((me, partner, [local[0], local[1], local[2]]));
            tris.push((me, partner, [local[0], local[2], local[3]]));
        } else if size > 1 && cell.iter().any(|b| b.is_some()) {
            let h = size / 2;
            stack.extend([(i, j, h), (i + h, j, h), (i + h, j + h, h), (i, j + h, h)]);
        }
    }
    (verts, tris)
}

/// The maximal ball tangent to face `f` at `uv`, by shrinking (module docs). None at a pole,
/// where the ball is degenerate (r ≈ 0, at a convex edge), or if shrinking does not settle.
fn maximal_ball(
    model: &Model,
    boundary: &Boundary,
    f: usize,
    uv: DVec2,
    acc: f64,
    near_r: Option<f64>,
    group_of_face: &(dyn Fn(usize) -> usize + Sync),
) -> Option<Ball> {
    let ev = Element::Face(f).eval(model, [uv.x, uv.y])?;
    let (p, m) = (ev.p, -ev.n);
    let solid = model.solid_of_face(f);
    // Start from the largest ball tangent at p that fits in the part's bounding box (a
    // maximal ball is inside the solid, so inside its box): a far tighter first guess than
    // the diagonal, and a first nearest-point query from inside the part.
    let (lo, hi) = model.bbox;
    let mut r = model.diagonal();
    for k in 0..3 {
        let slack = 1e-9 * model.diagonal();
        if m[k] < 1.0 {
            r = r.min((p[k] - lo[k] + slack).max(0.0) / (1.0 - m[k]));
        }
        if m[k] > -1.0 {
            r = r.min((hi[k] - p[k] + slack).max(0.0) / (1.0 + m[k]));
        }
    }
    r *= 1.01;
    // A neighbour's radius, with a margin: shrinking converges from above to the same
    // maximal ball from any start, in fewer queries from a close one; a start below it
    // finds the ball empty and grows.
    if let Some(near) = near_r {
        r = r.min(1.5 * near + 10.0 * acc);
    }
    // The box of a curved part is a close inner estimate (`Model::bounding_box`), so a
    // ball that is empty at the first guess is grown until a query shrinks it: only a
    // shrunk ball is known to be maximal.
    // The point the ball last shrank to: its second contact once it settles.
    let mut second: Option<DVec3> = None;
    let nearest =
        |c: DVec3| boundary.nearest_face_where(model, c, |g| model.solid_of_face(g) == solid);
    for _ in 0..64 {
        let c = p + m * r;
        let (g, hit) = nearest(c)?;
        if hit.distance >= r - acc && second.is_none() && r < model.diagonal() {
            r = (2.0 * r).min(model.diagonal());
            continue;
        }
        if hit.distance >= r - acc {
            // Settled. A nearest point inside the ball by less than the accuracy: the ball
            // through it (one more exact shrink, no query), so that both contacts are at r.
            // Unless that shrinks the ball by more than the accuracy: where the ball nearly
            // osculates the face it touches at `q`, a point inside by less than the accuracy
            // shrank it 6.7e-4 mm, and something else came nearer (on the Prusa adapter's
            // 0.2 mm round, another point of the same face by 6e-5 mm): query again.
            let through_hit = through(p, m, hit.point).filter(|&t| t < r);
            if let Some(t) = through_hit.filter(|&t| hit.distance < r && r - t > acc) {
                r = t;
                second = Some(hit.point);
                continue;
            }
            let (r, c, q) = match through_hit {
                Some(t) if hit.distance < r => (t, p + m * t, hit.point),
                _ => (r, c, second?),
            };
            if r <= 100.0 * acc || !apart(p, q, r, acc) {
                return None;
            }
            // The ball's partner: what the ball touches just beyond it.
            let (g2, _) = nearest(p + m * (r + 10.0 * acc)).unwrap_or((g, hit));
            return Some(Ball {
                c,
                r,
                partner: group_of_face(g2),
            });
        }
        let next = through(p, m, hit.point)?;
        if next >= r {
            return None;
        }
        r = next;
        second = Some(hit.point);
    }
    None
}

/// The radius of the ball tangent at `p` (inward normal `m`) through `q`:
/// `‖q − p‖² / (2 m·(q − p))`; None when `q` is not on the ball's side of the tangent plane.
fn through(p: DVec3, m: DVec3, q: DVec3) -> Option<f64> {
    let d = q - p;
    let along = m.dot(d);
    let r = d.length_squared() / (2.0 * along);
    (along > 0.0 && r.is_finite()).then_some(r)
}

/// True when a ball of radius `r` touching at `p` and `q` has them apart by more than
/// `verify`'s separation at accuracy `acc` ([`crate::medial::verify::separation`]). Nearer
/// together, its two contacts are one place to the accuracy (next to a skeletal edge, where a
/// sheet ends as its contacts meet; along a round of about the ball's radius): the ball is
/// not known to be maximal, and the mesh leaves it out, as the tracer lists such balls
/// unresolved. The mesh then stops that short of the sheet's boundary.
fn apart(p: DVec3, q: DVec3, r: f64, acc: f64) -> bool {
    p.distance(q) > crate::medial::verify::separation(r, acc)
}

/// Rough lengths of face `f` along u and v (for sharing the sampling budget): |Su|·Δu and
/// |Sv|·Δv at the middle of its domain.
fn approx_extent(model: &Model, f: usize) -> (f64, f64) {
    let face = &model.faces[f];
    let (u0, u1) = face.domain.u;
    let (v0, v1) = face.domain.v;
    Element::Face(f)
        .eval(model, [0.5 * (u0 + u1), 0.5 * (v0 + v1)])
        .map_or((0.0, 0.0), |e| {
            (e.dp[0].length() * (u1 - u0), e.dp[1].length() * (v1 - v0))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::BoundaryRef;

    fn meshed(name: &str) -> (Model, Sheets, SheetMesh) {
        let (m, c, mat) = crate::testing::traced(name);
        let b = Boundary::new(&m);
        let s = crate::medial::sheets(&m, &c, &mat);
        let accuracy = crate::medial::TraceOptions::for_model(&m).accuracy;
        let mesh = sheet_mesh(&m, &b, &c, &s, &MeshOptions::new(accuracy));
        (m, s, mesh)
    }

    /// Box [0,60]×[0,40]×[0,20]: every one of its 13 sheets gets triangles; every vertex is
    /// the centre of a ball whose nearest boundary point is at r (to the accuracy); the middle
    /// sheet (no rim) lies in z = 10 with r = 10.
    #[test]
    fn box_sheets_are_meshed_with_medial_vertices() {
        let (m, s, mesh) = meshed("box.step");
        let acc = 1e-6 * m.diagonal();
        let ids: Vec<Option<usize>> = mesh.parts.iter().map(|p| p.sheet).collect();
        assert_eq!(ids, (0..13).map(Some).collect::<Vec<_>>());
        assert!(mesh.parts.iter().all(|p| !p.triangles.is_empty()));
        let b = Boundary::new(&m);
        for v in &mesh.vertices {
            let (_, hit) = b.nearest_face(&m, DVec3::new(v[0], v[1], v[2])).unwrap();
            // The shrinking stops within the accuracy of the radius.
            assert!(
                (hit.distance - v[3]).abs() <= 2.0 * acc,
                "{v:?}: {}",
                hit.distance
            );
        }
        let middle = s
            .sheets
            .iter()
            .find(|sh| {
                sh.boundary
                    .iter()
                    .all(|e| matches!(e, BoundaryRef::Seam(_)))
            })
            .unwrap()
            .id;
        let part = mesh.parts.iter().find(|p| p.sheet == Some(middle)).unwrap();
        for t in &part.triangles {
            for &k in t {
                let v = mesh.vertices[k as usize];
                assert!((v[2] - 10.0).abs() <= 2.0 * acc && (v[3] - 10.0).abs() <= 2.0 * acc);
            }
        }
    }

    /// Plate with holes: all 19 sheets (annuli around the holes included) get triangles.
    #[test]
    fn plate_with_holes_every_sheet_is_meshed() {
        let (_, s, mesh) = meshed("plate_with_holes.step");
        assert_eq!(s.sheets.len(), 19);
        let mut ids: Vec<usize> = mesh.parts.iter().filter_map(|p| p.sheet).collect();
        ids.sort();
        assert_eq!(ids, (0..19).collect::<Vec<_>>());
    }
}
