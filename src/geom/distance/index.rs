//! The boundary prepared for distance queries ([`Boundary`]): built once per model (about 20 ms for
//! a 150-face part); it holds, for every curved face, a grid of *cells* over the UV rectangle the
//! face covers (its domain, reaching to any pole beyond a wrapping loop:
//! [`covered_domain`](crate::geom::trim::covered_domain)) with a box per cell that contains the
//! surface over the cell; for every face a finer grid that answers most trim tests without the
//! polygon test, and its loops prepared for the rest ([`Trim`](crate::geom::trim::Trim)); for every
//! edge, samples with a *cover radius*; for every vertex its pseudo-normal; and a
//! [`Bvh`](crate::geom::Bvh) over the faces' boxes. A query (see `query.rs`) visits faces by branch
//! and bound: a face is evaluated only if its box, then the nearest of its cells' boxes, is closer
//! than the best distance so far, and the nearest cell's centre seeds the projection. An edge is
//! evaluated only if its box, then its nearest sample minus its cover radius, is closer than the
//! best so far. Queries do not allocate.
//!
//! *Cell boxes and the safety margin.* Over a UV cell `[u₀,u₁]×[v₀,v₁]` with sides `Δu, Δv`, the
//! surface deviates from the bilinear interpolant of its four corners by at most
//! `e = (Δu²·max‖Suu‖ + Δv²·max‖Svv‖)/8` (the tensor-product linear interpolation error bound),
//! and the bilinear interpolant lies in the convex hull of the corners. So the box of the corners
//! grown by `e` contains the surface over the cell. The maxima of `‖Suu‖`, `‖Svv‖` over the cell
//! are estimated as [`CELL_CURVATURE_REL_CORNERS`] times their largest value at the corners: this
//! is the one non-rigorous step (a B-spline with a sharp bump inside one cell could exceed it),
//! which is why the factor is generous. Which cells cover the face: every cell that is not
//! provably outside the trim — a cell a loop polygon passes through (walked in steps of a quarter
//! cell) or neighbours, or a cell in a loop-free region whose test point is inside. Planar faces
//! need no cells: a planar region lies in the convex hull of its boundary, so the union of its
//! edges' boxes bounds it.
//!
//! *Edge cover radius.* Between consecutive samples the arc length is estimated by four sub-chords
//! times [`ARC_LENGTH_REL_CHORDS`]; every point of the arc is within half of that of one of the two
//! samples, so `dist(p, edge) ≥ min_i ‖p − C(tᵢ)‖ − max_i Lᵢ/2`.

use super::edge::{edge_sample_count, edge_sample_t, wraps_around};
use super::normal::{loop_points, nearest_loop_point, normal_near, vertex_normals};
use super::revolution::Profile;
use crate::geom::bbox::Aabb;
use crate::geom::bvh::{box_distance_squared, union, Bvh};
use crate::geom::eval::{eval_curve, eval_surface};
use crate::geom::project::{plane_frame, project_plane, ClosedForm};
use crate::geom::project_point;
use crate::geom::surface::closed_periods;
use crate::geom::trim::{self, covered_domain, TrimGrid};
use crate::model::{Curve3D, Edge, Face, Model};
use glam::{DVec2, DVec3};
use std::ops::Range;

/// Cells of a curved face's grid along its longer side in 3D (proportionally fewer along the
/// shorter). 8 measured faster than 16 on the benchmark parts (a smaller scan per face
/// outweighs the looser bounds).
pub const MAX_FACE_GRID: usize = 8;

/// The most a curved face (its normal or its parameter lines) turns across one cell of its
/// grid (radians, as [`turning`] estimates it).
pub const MAX_CELL_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// Most cells per direction that [`MAX_CELL_TURN`] asks for (a 12-turn thread face needs 96).
pub const MAX_TURNING_GRID: usize = 256;

/// Samples per knot span along a parameter line when a face's turning is measured.
pub const TURNING_SAMPLES_PER_SPAN: usize = 4;

/// Fewest samples along a parameter line when a face's turning is measured (all of them on a
/// surface without knots).
pub const MIN_TURNING_SAMPLES: usize = 64;

/// Most samples along a parameter line when a face's turning is measured.
pub const MAX_TURNING_SAMPLES: usize = 4096;

/// Fewest cells per direction of a face's grids.
pub const MIN_FACE_GRID: usize = 2;

/// Cells per direction, along the longer side, of the grid that answers most trim tests
/// without the polygon test (a grid of cells classified inside, outside or near a loop).
pub const MAX_TRIM_GRID: usize = 64;

/// Factor on the largest second derivative at a cell's corners to bound it over the cell.
pub const CELL_CURVATURE_REL_CORNERS: f64 = 2.0;

/// Factor on the sum of four sub-chords to bound the arc length between two edge samples.
pub const ARC_LENGTH_REL_CHORDS: f64 = 1.05;

/// Points closer to the boundary than this fraction of the model's diagonal are on it
/// ([`Boundary::contains_point`] says inside).
pub const ON_BOUNDARY_REL_DIAGONAL: f64 = 1e-9;

/// A UV cell of a curved face: a box containing the surface over the cell, and its centre.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cell {
    pub(super) bbox: Aabb,
    pub(super) rep: DVec3,
    pub(super) uv: DVec2,
}

/// Up to [`CELL_BLOCK`] consecutive cells of one face, with a box around their centres and
/// one around their boxes: a query skips a block that can hold neither a nearer centre nor a
/// box within its bound (the distance to a box is at most that to anything in it, rounding
/// included: subtraction, squaring and the sum are monotone).
#[derive(Clone, Debug)]
pub(super) struct CellBlock {
    pub(super) reps: Aabb,
    pub(super) boxes: Aabb,
    pub(super) cells: Range<u32>,
}

/// Cells per [`CellBlock`] (a row of the finest face grid).
const CELL_BLOCK: usize = MAX_FACE_GRID;

#[derive(Clone, Debug)]
pub(super) struct FaceCache {
    /// `(origin, Su, Sv)` of a planar face.
    pub(super) plane: Option<(DVec3, DVec3, DVec3)>,
    /// [`closed_periods`] of the surface.
    pub(super) closed: (bool, bool),
    /// The foot in closed form of a cylinder, cone or sphere (`None` for other surfaces).
    pub(super) closed_form: Option<ClosedForm>,
    /// A surface of revolution's axis and profile samples (`None` for other surfaces).
    pub(super) profile: Option<Profile>,
    pub(super) cells: Range<u32>,
    /// The cells in blocks, into `Boundary::blocks`.
    pub(super) blocks: Range<u32>,
    /// Fast inside/outside lookup for the trim ([`MAX_TRIM_GRID`] cells along the longer side).
    pub(super) trim: Option<TrimGrid>,
    /// The loops prepared for the exact test where the grid cannot tell.
    pub(super) loops: trim::Trim,
    /// Distinct edges of the face's loops, into `Boundary::face_edges`.
    pub(super) edges: Range<u32>,
    pub(super) bbox: Aabb,
}

#[derive(Clone, Debug)]
pub(super) struct EdgeCache {
    pub(super) samples: Range<u32>,
    /// [`wraps_around`]: a closed curve whose parameter wraps.
    pub(super) wrap: bool,
    pub(super) cover: f64,
    pub(super) bbox: Aabb,
    /// Start of this edge's `uv` table in `Boundary::edge_uv`: for each entry of
    /// `edge.faces`, the parameters of every sample on that face.
    pub(super) uv_start: u32,
}

/// The cosine above which the angle between two faces' normals at their edge makes the edge a
/// fold (0.1°).
const FOLD_COS: f64 = 0.999_998_5;

/// The model's boundary prepared for distance queries (see the module docs): built once per
/// model with [`Boundary::new`], then queried with the same model.
#[derive(Clone, Debug)]
pub struct Boundary {
    pub(super) bvh: Bvh,
    pub(super) faces: Vec<FaceCache>,
    pub(super) cells: Vec<Cell>,
    pub(super) blocks: Vec<CellBlock>,
    pub(super) face_edges: Vec<u32>,
    pub(super) edges: Vec<EdgeCache>,
    pub(super) edge_t: Vec<f64>,
    pub(super) edge_p: Vec<DVec3>,
    pub(super) edge_uv: Vec<DVec2>,
    /// Angle-weighted pseudo-normal of each vertex (not normalised).
    pub(super) vertex_normals: Vec<DVec3>,
    /// Distance under which a point is on the boundary.
    pub(super) on_boundary: f64,
    /// The edges whose two faces fold back onto each other (opposite normals at the edge's
    /// middle): where a face's nearest point is on such an edge, the point-in-solid test
    /// reads the edge's kind, not the face's normal.
    pub(super) folds: Vec<usize>,
}

impl Boundary {
    /// Samples the model's faces and edges and builds the hierarchy.
    pub fn new(model: &Model) -> Boundary {
        let mut b = Boundary {
            bvh: Bvh::new(&[]),
            faces: Vec::with_capacity(model.faces.len()),
            cells: Vec::new(),
            blocks: Vec::new(),
            face_edges: Vec::new(),
            edges: Vec::with_capacity(model.edges.len()),
            edge_t: Vec::new(),
            edge_p: Vec::new(),
            edge_uv: Vec::new(),
            vertex_normals: Vec::new(),
            on_boundary: 0.0,
            folds: Vec::new(),
        };
        let loop_points: Vec<Vec<(DVec2, DVec3)>> = model.faces.iter().map(loop_points).collect();
        for e in &model.edges {
            b.add_edge(model, e, &loop_points);
        }
        for (fi, face) in model.faces.iter().enumerate() {
            b.add_face(fi, face);
        }
        b.vertex_normals = vertex_normals(model, &loop_points, |face, fi, x, hint| {
            b.normal_at(face, fi, x, hint)
        });
        let boxes: Vec<Aabb> = b.faces.iter().map(|f| f.bbox).collect();
        // The scale from the faces' boxes (a slight over-estimate of the model's box, and much
        // cheaper than `Model::diagonal`, which samples every face again).
        let all = boxes.iter().fold(
            Aabb::EMPTY,
            |a, f| if f.is_empty() { a } else { union(&a, f) },
        );
        b.on_boundary = if all.is_empty() {
            0.0
        } else {
            ON_BOUNDARY_REL_DIAGONAL * (all.max - all.min).length()
        };
        b.bvh = Bvh::new(&boxes);
        b.folds = (0..model.edges.len())
            .filter(|&e| b.is_fold(model, e))
            .collect();
        b
    }

    /// True when edge `e`'s faces have opposite normals (to [`FOLD_COS`]) at its middle.
    fn is_fold(&self, model: &Model, e: usize) -> bool {
        let edge = &model.edges[e];
        let (f, g) = match edge.faces[..] {
            [f, g] => (f, g),
            _ => return false,
        };
        if f == g {
            return false;
        }
        let t = 0.5 * (edge.range.0 + edge.range.1);
        let x = eval_curve(&edge.curve, t).p;
        let normal = |fi: usize| {
            let hint = self.edge_uv_hint(model, e, fi, t);
            self.normal_at(&model.faces[fi], fi, x, hint)
        };
        normal(f)
            .zip(normal(g))
            .is_some_and(|(a, b)| a.dot(b) < -FOLD_COS)
    }

    fn add_edge(&mut self, model: &Model, e: &Edge, loop_points: &[Vec<(DVec2, DVec3)>]) {
        let n = edge_sample_count(e);
        let start = self.edge_t.len() as u32;
        let mut bbox = Aabb::EMPTY;
        let mut cover: f64 = 0.0;
        let mut grow: f64 = 0.0;
        let mut prev: Option<(f64, DVec3)> = None;
        for k in 0..n {
            let t = edge_sample_t(e, k, n);
            let x = eval_curve(&e.curve, t).p;
            bbox.add(x);
            if let Some((t0, x0)) = prev {
                // Arc length between samples from four sub-chords.
                let mut len = 0.0;
                let mut a = x0;
                for s in 1..=4 {
                    let b = if s == 4 {
                        x
                    } else {
                        eval_curve(&e.curve, t0 + (t - t0) * s as f64 / 4.0).p
                    };
                    bbox.add(b);
                    let chord = a.distance(b);
                    grow = grow.max(0.5 * ARC_LENGTH_REL_CHORDS * chord);
                    len += chord;
                    a = b;
                }
                cover = cover.max(0.5 * ARC_LENGTH_REL_CHORDS * len);
            }
            self.edge_t.push(t);
            self.edge_p.push(x);
            prev = Some((t, x));
        }
        if matches!(e.curve, Curve3D::Line(_)) {
            grow = 0.0;
        }
        bbox.min -= DVec3::splat(grow);
        bbox.max += DVec3::splat(grow);
        // Parameters of the samples on each adjacent face, following the edge with hints.
        let uv_start = self.edge_uv.len() as u32;
        for &f in &e.faces {
            let face = &model.faces[f];
            let plane = plane_frame(&face.surface);
            let mut hint = None;
            for k in 0..n {
                let x = self.edge_p[start as usize + k];
                let uv = match plane {
                    Some(frame) => Some(project_plane(frame, x)),
                    None => {
                        let h = hint.or_else(|| nearest_loop_point(&loop_points[f], x));
                        project_point(&face.surface, x, h)
                    }
                };
                let uv = uv.unwrap_or((f64::NAN, f64::NAN));
                if uv.0.is_finite() {
                    hint = Some(uv);
                }
                self.edge_uv.push(DVec2::new(uv.0, uv.1));
            }
        }
        self.edges.push(EdgeCache {
            samples: start..self.edge_t.len() as u32,
            wrap: wraps_around(e),
            cover: if matches!(e.curve, Curve3D::Line(_)) {
                0.0
            } else {
                cover
            },
            bbox,
            uv_start,
        });
    }

    fn add_face(&mut self, fi: usize, face: &Face) {
        let plane = plane_frame(&face.surface);
        // Distinct edges.
        let edges_start = self.face_edges.len() as u32;
        let mut bbox = Aabb::EMPTY;
        for l in &face.loops {
            for oe in &l.edges {
                if !self.face_edges[edges_start as usize..].contains(&(oe.edge as u32)) {
                    self.face_edges.push(oe.edge as u32);
                    bbox = union(&bbox, &self.edges[oe.edge].bbox);
                }
            }
        }
        let edges = edges_start..self.face_edges.len() as u32;
        let cells_start = self.cells.len() as u32;
        // Cell counts along u and v in proportion to the face's extent (UV is metric on a
        // plane), `max` along the longer side.
        let (len_u, len_v) = match plane {
            Some(_) => (
                face.domain.u.1 - face.domain.u.0,
                face.domain.v.1 - face.domain.v.0,
            ),
            None => extents(face),
        };
        let counts = |max: usize| {
            let long = len_u.max(len_v);
            let count = |x: f64| {
                if long > 0.0 {
                    ((max as f64 * x / long).ceil() as usize).clamp(MIN_FACE_GRID, max)
                } else {
                    MIN_FACE_GRID
                }
            };
            (count(len_u), count(len_v))
        };
        let (tu, tv) = counts(MAX_TRIM_GRID);
        let trim = TrimGrid::new(face, tu, tv);
        if plane.is_none() {
            let (nu, nv) = counts(MAX_FACE_GRID);
            let (nu, nv) = finer_where_it_winds(face, nu, nv);
            if let Some(grid) = TrimGrid::new(face, nu, nv) {
                for cell in face_cells(face, &grid) {
                    bbox = union(&bbox, &cell.bbox);
                    self.cells.push(cell);
                }
            }
            if self.cells.len() == cells_start as usize {
                // No cell bounds the face (a degenerate domain this module cannot widen): an
                // unbounded box keeps it in every query rather than losing it.
                bbox = Aabb::UNBOUNDED;
            }
        }
        let blocks_start = self.blocks.len() as u32;
        let cells_end = self.cells.len() as u32;
        for start in (cells_start..cells_end).step_by(CELL_BLOCK) {
            let cells = start..cells_end.min(start + CELL_BLOCK as u32);
            let (mut reps, mut boxes) = (Aabb::EMPTY, Aabb::EMPTY);
            let mut finite = true;
            for cell in &self.cells[range(&cells)] {
                reps.add(cell.rep);
                boxes = union(&boxes, &cell.bbox);
                finite &= [cell.rep, cell.bbox.min, cell.bbox.max]
                    .iter()
                    .all(|v| v.is_finite());
            }
            if !finite {
                // A NaN would be left out of the boxes (min and max skip it) but not out of
                // the cell's own distance: a block with any non-finite coordinate is never
                // skipped.
                (reps, boxes) = (Aabb::UNBOUNDED, Aabb::UNBOUNDED);
            }
            self.blocks.push(CellBlock { reps, boxes, cells });
        }
        self.faces.push(FaceCache {
            plane,
            trim,
            loops: trim::Trim::new(face),
            closed: closed_periods(&face.surface),
            closed_form: match ClosedForm::new(&face.surface) {
                c @ (ClosedForm::RevolvedLine { .. } | ClosedForm::Sphere { .. }) => Some(c),
                ClosedForm::Plane { .. } | ClosedForm::None => None,
            },
            profile: Profile::new(face),
            cells: cells_start..cells_end,
            blocks: blocks_start..self.blocks.len() as u32,
            edges,
            bbox,
        });
        debug_assert_eq!(self.faces.len(), fi + 1);
    }

    /// Face `fi`'s cell centre nearest to `p` (its UV and distance; the first of equals in
    /// cell order), or `None` when the face has cells and none of their boxes is within
    /// `bound` of `p` (the face holds no point nearer than `bound`). Blocks that can change
    /// neither answer are skipped (see [`CellBlock`]); the answer is the linear scan's.
    pub(super) fn cell_seed(
        &self,
        fi: usize,
        p: DVec3,
        bound: f64,
    ) -> Option<Option<(DVec2, f64)>> {
        let fc = &self.faces[fi];
        let bound2 = bound * bound;
        let mut within = false;
        let mut best = f64::INFINITY;
        let mut seed = None;
        for block in &self.blocks[range(&fc.blocks)] {
            let nearer = box_distance_squared(&block.reps, p) < best;
            if !nearer && (within || box_distance_squared(&block.boxes, p) >= bound2) {
                continue;
            }
            for cell in &self.cells[range(&block.cells)] {
                within |= box_distance_squared(&cell.bbox, p) < bound2;
                let d2 = cell.rep.distance_squared(p);
                if d2 < best {
                    best = d2;
                    seed = Some((cell.uv, d2.sqrt()));
                }
            }
        }
        // As `min over the cells of their box distance >= bound²` decided it.
        if fc.cells.end > fc.cells.start && !within && !bound2.is_nan() {
            return None;
        }
        Some(seed)
    }

    /// The cell of face `fi` whose representative point is nearest `p` among those whose
    /// box is farther than `apart` from `away` (another basin of the distance than the foot
    /// at `away`), with the distance to its box (nothing in it is nearer).
    pub(super) fn cell_seed_away(
        &self,
        fi: usize,
        p: DVec3,
        away: DVec3,
        apart: f64,
    ) -> Option<(DVec2, f64)> {
        let fc = &self.faces[fi];
        let apart2 = apart * apart;
        let mut best = f64::INFINITY;
        let mut seed = None;
        for block in &self.blocks[range(&fc.blocks)] {
            if box_distance_squared(&block.reps, p) >= best {
                continue;
            }
            for cell in &self.cells[range(&block.cells)] {
                let d2 = cell.rep.distance_squared(p);
                if d2 < best && box_distance_squared(&cell.bbox, away) > apart2 {
                    best = d2;
                    seed = Some((cell.uv, box_distance_squared(&cell.bbox, p).sqrt()));
                }
            }
        }
        seed
    }

    /// Unit outward normal of `face` at its point nearest `x` (see [`normal_near`]).
    pub(super) fn normal_at(
        &self,
        face: &Face,
        fi: usize,
        x: DVec3,
        hint: Option<(f64, f64)>,
    ) -> Option<DVec3> {
        let plane = self
            .faces
            .get(fi)
            .and_then(|f| f.plane)
            .or_else(|| plane_frame(&face.surface));
        normal_near(face, plane, x, hint)
    }

    /// [`trim::contains`] for face `fi` (`face` is `model.faces[fi]`), from the cached grid and
    /// prepared loops.
    pub fn contains_uv(&self, face: &Face, fi: usize, uv: DVec2) -> bool {
        let fc = &self.faces[fi];
        match &fc.trim {
            Some(grid) => grid.contains(face, &fc.loops, uv),
            None => fc.loops.contains(face, uv),
        }
    }

    /// Parameters on face `fi` of the point of edge `ei` at `t`, interpolated from the samples
    /// (a start for projecting the point onto the face; `None` when `fi` is not the edge's).
    pub fn edge_uv_hint(&self, model: &Model, ei: usize, fi: usize, t: f64) -> Option<(f64, f64)> {
        let e = &model.edges[ei];
        let slot = e.faces.iter().position(|&f| f == fi)?;
        let ec = &self.edges[ei];
        let n = (ec.samples.end - ec.samples.start) as usize;
        let ts = &self.edge_t[range(&ec.samples)];
        let uvs =
            &self.edge_uv[ec.uv_start as usize + slot * n..ec.uv_start as usize + (slot + 1) * n];
        let k = ts.partition_point(|&s| s <= t).clamp(1, n.max(2) - 1);
        let (t0, t1) = (ts[k - 1], ts[k.min(n - 1)]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        let uv = uvs[k - 1] + (uvs[k.min(n - 1)] - uvs[k - 1]) * w;
        // Interpolating across a seam would land mid-period: take the nearer sample then.
        let uv = if (uvs[k.min(n - 1)] - uvs[k - 1]).abs().max_element()
            > 0.25 * face_period_min(&model.faces[fi])
        {
            if w < 0.5 {
                uvs[k - 1]
            } else {
                uvs[k.min(n - 1)]
            }
        } else {
            uv
        };
        uv.is_finite().then_some((uv.x, uv.y))
    }
}

#[inline]
pub(super) fn range(r: &Range<u32>) -> Range<usize> {
    r.start as usize..r.end as usize
}

/// Smallest period of a face (∞ when it has none).
fn face_period_min(face: &Face) -> f64 {
    face.domain
        .u_period
        .unwrap_or(f64::INFINITY)
        .min(face.domain.v_period.unwrap_or(f64::INFINITY))
}

/// The cell counts `(nu, nv)` of a curved face's grid raised where it turns (its normal or
/// its parameter lines, see [`turning`]): no cell wider than a turn of [`MAX_CELL_TURN`], and
/// square cells (in 3D, [`MIN_FACE_GRID`] across the narrower direction) on a face that winds
/// round more than once (a thread's flank, a spiral): there the face comes back near itself a
/// turn later, and a cell as long as that turn holds both places, so the nearest cell's centre
/// seeds the descent into the wrong turn. At most [`MAX_TURNING_GRID`] per direction.
pub(super) fn finer_where_it_winds(face: &Face, nu: usize, nv: usize) -> (usize, usize) {
    let w = turning(face);
    let raise = |n: usize, want: f64| {
        if want.is_finite() && want > n as f64 {
            (want.ceil() as usize).min(MAX_TURNING_GRID).max(n)
        } else {
            n
        }
    };
    let (mut nu, mut nv) = (
        raise(nu, w.turn_u / MAX_CELL_TURN),
        raise(nv, w.turn_v / MAX_CELL_TURN),
    );
    let narrow = w.len_u.min(w.len_v);
    if w.turn_u.max(w.turn_v) > std::f64::consts::TAU && narrow > 0.0 {
        let side = narrow / MIN_FACE_GRID as f64;
        nu = raise(nu, w.len_u / side);
        nv = raise(nv, w.len_v / side);
    }
    (nu, nv)
}

/// How far a curved face turns along its parameter lines, and how long they are.
#[derive(Clone, Copy, Debug, Default)]
struct Winding {
    /// Radians (the normal's turning or the line's, whichever is more), the most of three
    /// parameter lines along u, and along v.
    turn_u: f64,
    turn_v: f64,
    /// Lengths in 3D (polylines through the samples), the most of the same lines.
    len_u: f64,
    len_v: f64,
}

/// How far the normal of a curved face, or its parameter lines' direction, turns along u and
/// along v over its covered domain, and how long its parameter lines are: the most of three
/// parameter lines each, sampled [`TURNING_SAMPLES_PER_SPAN`] times per knot span of a
/// B-spline, at least [`MIN_TURNING_SAMPLES`] times, at most [`MAX_TURNING_SAMPLES`].
fn turning(face: &Face) -> Winding {
    let ((u0, u1), (v0, v1)) = covered_domain(face);
    if !(u0.is_finite() && u1.is_finite() && v0.is_finite() && v1.is_finite()) {
        return Winding::default();
    }
    let spans = crate::geom::surface::knot_spans(&face.surface);
    let samples = |spans: Option<usize>| {
        spans.map_or(MIN_TURNING_SAMPLES, |s| {
            (s * TURNING_SAMPLES_PER_SPAN).clamp(MIN_TURNING_SAMPLES, MAX_TURNING_SAMPLES)
        })
    };
    let (nu, nv) = (samples(spans.map(|s| s.0)), samples(spans.map(|s| s.1)));
    let angle = |a: DVec3, b: DVec3| a.dot(b).clamp(-1.0, 1.0).acos();
    // Total turning (of the normal, and of the line's own direction: a helicoid's flat
    // flank winds round with a normal that hardly turns) and length along the line
    // `at(k/n)`, k = 0..=n.
    let along = |n: usize, at: &dyn Fn(f64) -> (f64, f64)| {
        let (mut normal_turn, mut line_turn, mut len) = (0.0, 0.0, 0.0);
        let mut prev: Option<(DVec3, DVec3)> = None;
        let mut prev_chord: Option<DVec3> = None;
        for k in 0..=n {
            let (u, v) = at(k as f64 / n as f64);
            let d = eval_surface(&face.surface, u, v);
            let normal = d.su.cross(d.sv).normalize_or_zero();
            if normal == DVec3::ZERO || !normal.is_finite() || !d.p.is_finite() {
                continue;
            }
            if let Some((p, m)) = prev {
                normal_turn += angle(m, normal);
                len += p.distance(d.p);
                let chord = (d.p - p).normalize_or_zero();
                if chord != DVec3::ZERO {
                    if let Some(c) = prev_chord {
                        line_turn += angle(c, chord);
                    }
                    prev_chord = Some(chord);
                }
            }
            prev = Some((d.p, normal));
        }
        (f64::max(normal_turn, line_turn), len)
    };
    let mut w = Winding::default();
    for s in [1.0 / 6.0, 0.5, 5.0 / 6.0] {
        let (v, u) = (v0 + (v1 - v0) * s, u0 + (u1 - u0) * s);
        let (tu, lu) = along(nu, &|x| (u0 + (u1 - u0) * x, v));
        let (tv, lv) = along(nv, &|x| (u, v0 + (v1 - v0) * x));
        w.turn_u = w.turn_u.max(tu);
        w.len_u = w.len_u.max(lu);
        w.turn_v = w.turn_v.max(tv);
        w.len_v = w.len_v.max(lv);
    }
    w
}

/// Lengths in 3D of the face's domain along u and along v (the longest of a few parameter
/// lines each, as polylines of four chords).
fn extents(face: &Face) -> (f64, f64) {
    let ((u0, u1), (v0, v1)) = covered_domain(face);
    let probe = 4;
    let at = |i: usize, j: usize| {
        eval_surface(
            &face.surface,
            u0 + (u1 - u0) * i as f64 / probe as f64,
            v0 + (v1 - v0) * j as f64 / probe as f64,
        )
        .p
    };
    let mut len_u: f64 = 0.0;
    let mut len_v: f64 = 0.0;
    for j in 0..=probe {
        let mut lu = 0.0;
        let mut lv = 0.0;
        for i in 0..probe {
            lu += at(i, j).distance(at(i + 1, j));
            lv += at(j, i).distance(at(j, i + 1));
        }
        len_u = len_u.max(lu);
        len_v = len_v.max(lv);
    }
    (len_u, len_v)
}

/// The cells covering a curved face (see the module docs): those of the trim grid that are
/// not outside, each with a box that contains the surface over it.
fn face_cells(face: &Face, grid: &TrimGrid) -> Vec<Cell> {
    let (nu, nv) = grid.counts();
    let (du, dv) = grid.cell_size();
    let mut nodes = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        for i in 0..=nu {
            let uv = grid.node(i, j);
            let s = eval_surface(&face.surface, uv.x, uv.y);
            nodes.push((s.p, s.suu.length(), s.svv.length()));
        }
    }
    let node = |i: usize, j: usize| &nodes[j * (nu + 1) + i];
    let mut cells = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            if grid.is_outside(i, j) {
                continue;
            }
            let corners = [
                node(i, j),
                node(i + 1, j),
                node(i, j + 1),
                node(i + 1, j + 1),
            ];
            let mut bbox = Aabb::EMPTY;
            let mut muu: f64 = 0.0;
            let mut mvv: f64 = 0.0;
            for c in corners {
                bbox.add(c.0);
                muu = muu.max(c.1);
                mvv = mvv.max(c.2);
            }
            let e = (du * du * CELL_CURVATURE_REL_CORNERS * muu
                + dv * dv * CELL_CURVATURE_REL_CORNERS * mvv)
                / 8.0;
            if !(e.is_finite() && bbox.min.is_finite() && bbox.max.is_finite()) {
                continue;
            }
            bbox.min -= DVec3::splat(e);
            bbox.max += DVec3::splat(e);
            let uv = grid.node(i, j) + DVec2::new(0.5 * du, 0.5 * dv);
            let rep = crate::geom::surface_point(&face.surface, uv.x, uv.y);
            cells.push(Cell { bbox, rep, uv });
        }
    }
    cells
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::distance::Lcg;
    use crate::testing::sample;

    /// The blocked cell scan answers as the linear scan over every cell did: the same seed,
    /// bit for bit, and the same rejection, for points in and around curved parts and
    /// bounds from zero to infinity.
    #[test]
    fn blocked_cell_scan_is_the_linear_scan() {
        let linear = |b: &Boundary, fi: usize, p: DVec3, bound: f64| {
            let fc = &b.faces[fi];
            let (mut lb, mut best, mut seed) = (f64::INFINITY, f64::INFINITY, None);
            for cell in &b.cells[range(&fc.cells)] {
                lb = lb.min(box_distance_squared(&cell.bbox, p));
                let d2 = cell.rep.distance_squared(p);
                if d2 < best {
                    best = d2;
                    seed = Some((cell.uv, d2.sqrt()));
                }
            }
            if fc.cells.end > fc.cells.start && lb >= bound * bound {
                return None;
            }
            Some(seed)
        };
        let mut rng = Lcg(7);
        let mut rejected = 0;
        for name in [
            "filleted_box.step",
            "sphere.step",
            "torus.step",
            "box_bspline_top.step",
        ] {
            let model = sample(name);
            let b = Boundary::new(&model);
            let (lo, hi) = model.bbox;
            let size = (hi - lo).length();
            for _ in 0..4000 {
                let t = DVec3::new(rng.next(), rng.next(), rng.next()) * 1.4 - 0.2;
                let p = lo + (hi - lo) * t;
                let bound = match rng.next() {
                    x if x < 0.1 => f64::INFINITY,
                    x => x * x * size,
                };
                for fi in 0..model.faces.len() {
                    let (ours, theirs) = (b.cell_seed(fi, p, bound), linear(&b, fi, p, bound));
                    let bits = |s: Option<Option<(DVec2, f64)>>| {
                        s.map(|s| s.map(|(uv, d)| (uv.x.to_bits(), uv.y.to_bits(), d.to_bits())))
                    };
                    assert_eq!(
                        bits(ours),
                        bits(theirs),
                        "{name} face {fi} at {p} within {bound}"
                    );
                    rejected += usize::from(ours.is_none());
                }
            }
        }
        assert!(rejected > 1000, "{rejected}");
    }

    /// The trim grid answers exactly like `trim::contains` (it only skips the polygon test
    /// where a cell is provably on one side).
    #[test]
    fn trim_grid_agrees_with_contains() {
        for file in [
            "plate_with_holes.step",
            "filleted_box.step",
            "box_bspline_top.step",
            "scad_rotate_extrude.step",
            "torus.step",
            "sphere.step",
            "tetrahedron.step",
        ] {
            let model = sample(file);
            let b = Boundary::new(&model);
            let mut rng = Lcg(3);
            for (fi, face) in model.faces.iter().enumerate() {
                let grid = b.faces[fi]
                    .trim
                    .as_ref()
                    .expect("every sample face has a grid");
                let exact = &b.faces[fi].loops;
                let d = &face.domain;
                let (w, h) = (d.u.1 - d.u.0, d.v.1 - d.v.0);
                for _ in 0..3000 {
                    // Over the domain and a margin, with periodic shifts.
                    let k = (rng.next() * 3.0).floor() - 1.0;
                    let uv = DVec2::new(
                        d.u.0 - 0.1 * w + 1.2 * w * rng.next() + k * d.u_period.unwrap_or(0.0),
                        d.v.0 - 0.1 * h + 1.2 * h * rng.next(),
                    );
                    assert_eq!(
                        grid.contains(face, exact, uv),
                        trim::contains(face, uv),
                        "{file} face {fi} at {uv}"
                    );
                }
            }
        }
    }

    /// The boundary is shared by the tracer's threads.
    #[test]
    fn boundary_is_send_and_sync() {
        fn shareable<T: Send + Sync>() {}
        shareable::<Boundary>();
    }
}
