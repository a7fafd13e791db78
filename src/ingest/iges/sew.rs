//! A soup of IGES trimmed surfaces sewn into closed shells.
//!
//! The trimmed surfaces are 144 entities, bounded by 142 curves on surfaces.
//!
//! Each 144 gives a face: its surface and, per boundary (outer, then inner), the model-space
//! curve of the 142 split into pieces (a 102 composite's members). Pieces of zero length (the
//! image of a pole) are dropped, and pieces written against the boundary's direction are
//! turned round, so that each boundary is a chain running end to start.
//!
//! Sewing: piece ends closer than the merge tolerance are one vertex (a spatial hash with
//! cells of that size, so the cost is linear in the number of pieces). Two pieces with the
//! same pair of end vertices are one edge when their interior points (a quarter, half and
//! three quarters along one) lie on the other within the match tolerance; the edge keeps the
//! first piece's curve and is shared by both faces (or used twice by one face: a seam). A
//! piece that matches nothing means the soup is open: that is an error naming the face and the
//! curve. Faces joined by edges form a shell; each shell is one solid (voids in a soup are not
//! told apart from separate solids).
//!
//! Tolerances: merge `tol` = max(10 × the Global section's minimum resolution, 1e-7 × the
//! diagonal of the pieces (sampled at quarters)), at most 1e-4 × that diagonal; match tolerance 10 ×
//! `tol`. The soups written by FreeCAD carry 10 significant digits, so coincident ends differ
//! by about 1e-9 of the coordinates: far inside these.

use super::brep::{edge_entry, loop_entries, vertex_point, EdgeEntry};
use super::ctx::{model_err, Ctx};
use super::segment::{edge_range, nearest_param, Segment};
use crate::error::Result;
use crate::ingest::domain::EMPTY_DOMAIN;
use crate::ingest::transform::{mat_mul, IDENTITY};
use crate::model::*;
use glam::DVec3;
use std::collections::HashMap;

/// The merge tolerance's floor, relative to the diagonal of the soup's pieces.
const MIN_MERGE_REL_DIAGONAL: f64 = 1e-7;
/// The merge tolerance's ceiling, relative to the diagonal of the soup's pieces.
const MAX_MERGE_REL_DIAGONAL: f64 = 1e-4;
/// The merge tolerance relative to the Global section's minimum resolution (in mm).
const MERGE_REL_RESOLUTION: f64 = 10.0;
/// The match tolerance relative to the merge tolerance.
const MATCH_REL_MERGE: f64 = 10.0;

/// A piece of a boundary: (face, loop, piece) indices.
type PieceUse = (usize, usize, usize);

struct SoupLoop {
    de: usize,
    /// The pieces in boundary order, each with whether it is run along its curve.
    pieces: Vec<(Segment, bool)>,
}

struct SoupFace {
    de: usize,
    surface: Surface,
    loops: Vec<SoupLoop>,
}

fn ends(p: &(Segment, bool)) -> (DVec3, DVec3) {
    if p.1 {
        (p.0.start(), p.0.end())
    } else {
        (p.0.end(), p.0.start())
    }
}

/// Sews the trimmed surfaces (144) at `soup` into closed shells, each a solid of `model`.
pub fn build_soup(ctx: &Ctx, model: &mut Model, soup: &[usize]) -> Result<()> {
    let mut faces = Vec::with_capacity(soup.len());
    for &de in soup {
        faces.push(read_face(ctx, de)?);
    }
    sew(ctx, model, faces)
}

/// Sews faces that no shell lists (510 B-rep faces, 143 bounded surfaces) into closed shells
/// as a soup is sewn: each loop's edges (a 510's) or boundary curves (a 143's) become its
/// pieces, and the pieces are matched by geometry, whether or not the faces share edge lists.
pub fn build_loose_faces(ctx: &Ctx, model: &mut Model, loose: &[usize]) -> Result<()> {
    let mut faces = Vec::with_capacity(loose.len());
    for &de in loose {
        faces.push(match ctx.typed(de, de, &[510, 143])?.entity_type {
            510 => read_brep_face(ctx, de)?,
            _ => read_bounded_surface(ctx, de)?,
        });
    }
    sew(ctx, model, faces)
}

/// Sews `faces` (see the module docs).
fn sew(ctx: &Ctx, model: &mut Model, mut faces: Vec<SoupFace>) -> Result<()> {
    let tol = merge_tolerance(ctx, &faces)?;
    for f in &mut faces {
        for l in &mut f.loops {
            chain(ctx, l, tol)?;
        }
    }
    let piece_vertices = merge_vertices(model, &faces, tol);
    let assigned = pair_pieces(ctx, model, &faces, &piece_vertices, tol)?;
    let first_face = model.faces.len();
    push_faces(model, faces, &assigned);
    shells_from_components(model, first_face);
    Ok(())
}

/// The merge tolerance, from the size of the whole soup (see the module docs).
fn merge_tolerance(ctx: &Ctx, faces: &[SoupFace]) -> Result<f64> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for f in faces {
        for l in &f.loops {
            for p in &l.pieces {
                for q in [0.0, 0.25, 0.5, 0.75, 1.0].map(|t| p.0.at_fraction(t)) {
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
            }
        }
    }
    let diag = (hi - lo).length();
    if !diag.is_finite() || diag <= 0.0 {
        return Err(model_err(ctx.path, "the trimmed surfaces have no extent"));
    }
    let resolution = ctx.file.global.resolution.abs() * ctx.mm;
    Ok((MERGE_REL_RESOLUTION * resolution)
        .max(MIN_MERGE_REL_DIAGONAL * diag)
        .min(MAX_MERGE_REL_DIAGONAL * diag))
}

/// The vertices of the pieces' ends, ends closer than `tol` merged: per (face, loop, piece),
/// its (start vertex, end vertex) in boundary order.
fn merge_vertices(
    model: &mut Model,
    faces: &[SoupFace],
    tol: f64,
) -> Vec<Vec<Vec<(usize, usize)>>> {
    let mut grid = Grid {
        cell: tol,
        cells: HashMap::new(),
    };
    let mut piece_vertices: Vec<Vec<Vec<(usize, usize)>>> = Vec::new();
    for f in faces {
        let mut fv = Vec::new();
        for l in &f.loops {
            let mut lv = Vec::new();
            for p in &l.pieces {
                let (a, b) = ends(p);
                let va = grid.vertex(model, a);
                let vb = grid.vertex(model, b);
                lv.push((va, vb));
            }
            fv.push(lv);
        }
        piece_vertices.push(fv);
    }
    piece_vertices
}

/// Pairs the pieces into edges (pushed into `model`): pieces with the same pair of end
/// vertices whose curves match. Returns each piece use's (edge, forward); a piece that
/// matches nothing is an error (the soup is open).
fn pair_pieces(
    ctx: &Ctx,
    model: &mut Model,
    faces: &[SoupFace],
    piece_vertices: &[Vec<Vec<(usize, usize)>>],
    tol: f64,
) -> Result<HashMap<PieceUse, (usize, bool)>> {
    // Group piece uses by their vertex pair, then pair them geometrically.
    let mut groups: HashMap<(usize, usize), Vec<PieceUse>> = HashMap::new();
    let mut order = Vec::new();
    for (fi, fv) in piece_vertices.iter().enumerate() {
        for (li, lv) in fv.iter().enumerate() {
            for (pi, &(a, b)) in lv.iter().enumerate() {
                groups
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((fi, li, pi));
                order.push((fi, li, pi));
            }
        }
    }
    let piece = |u: PieceUse| &faces[u.0].loops[u.1].pieces[u.2];
    // use → (edge, forward)
    let mut assigned: HashMap<PieceUse, (usize, bool)> = HashMap::new();
    for &u in &order {
        if assigned.contains_key(&u) {
            continue;
        }
        let (a, b) = piece_vertices[u.0][u.1][u.2];
        let group = &groups[&(a.min(b), a.max(b))];
        let partner = group.iter().copied().find(|&w| {
            w != u
                && !assigned.contains_key(&w)
                && same_curve(piece(u), piece(w), MATCH_REL_MERGE * tol)
        });
        let Some(w) = partner else {
            let (p, q) = ends(piece(u));
            return Err(ctx.err(
                faces[u.0].de,
                format!(
                    "boundary curve DE {} from ({:.6}, {:.6}, {:.6}) to ({:.6}, {:.6}, {:.6}) is not shared with any other trimmed surface: the surfaces do not close into a shell (open soup)",
                    piece(u).0.de, p.x, p.y, p.z, q.x, q.y, q.z
                ),
            ));
        };
        let (seg, fwd) = piece(u);
        let edge = model.edges.len();
        let vertices = if *fwd { [a, b] } else { [b, a] };
        model.edges.push(Edge {
            source_id: seg.de as u64,
            curve: seg.curve.clone(),
            range: seg.range,
            vertices,
            faces: vec![],
        });
        assigned.insert(u, (edge, *fwd));
        let (wa, _) = piece_vertices[w.0][w.1][w.2];
        let w_forward = if a != b {
            wa == vertices[0]
        } else {
            // A closed edge: the partner runs along the edge when its first quarter lies in
            // the edge's first half.
            let (ws, wf) = piece(w);
            let q = ws.at_fraction(if *wf { 0.25 } else { 0.75 });
            let (t, _) = nearest_param(seg, q);
            ((t - seg.range.0) / (seg.range.1 - seg.range.0) < 0.5) == *fwd
        };
        assigned.insert(w, (edge, w_forward));
    }
    Ok(assigned)
}

/// Pushes the faces with their loops of the paired edges (`assigned`), in no shell yet.
fn push_faces(
    model: &mut Model,
    faces: Vec<SoupFace>,
    assigned: &HashMap<PieceUse, (usize, bool)>,
) {
    let first_face = model.faces.len();
    for (fi, f) in faces.into_iter().enumerate() {
        let face = first_face + fi;
        let mut loops = Vec::new();
        for (li, l) in f.loops.iter().enumerate() {
            let mut edges = Vec::new();
            for pi in 0..l.pieces.len() {
                let (edge, forward) = assigned[&(fi, li, pi)];
                model.edges[edge].faces.push(face);
                edges.push(OrientedEdge { edge, forward });
            }
            loops.push(Loop {
                source_id: l.de as u64,
                edges,
                vertex: None,
                uv: vec![],
                uv_counts: vec![],
                outline: vec![],
                gap_mm: 0.0,
            });
        }
        model.faces.push(Face {
            source_id: f.de as u64,
            shell: usize::MAX,
            surface: f.surface,
            sign: 1.0,
            same_sense: true,
            loops,
            outer: None,
            domain: EMPTY_DOMAIN,
        });
    }
}

/// The faces from `first_face` on, joined by their edges into connected components: each a
/// shell and the solid it bounds.
fn shells_from_components(model: &mut Model, first_face: usize) {
    for seed in first_face..model.faces.len() {
        if model.faces[seed].shell != usize::MAX {
            continue;
        }
        let shell = model.shells.len();
        let solid = model.solids.len();
        model.solids.push(Solid {
            instance: None,
            source_id: model.faces[seed].source_id,
            name: String::new(),
            shells: vec![shell],
        });
        model.shells.push(Shell {
            source_id: model.faces[seed].source_id,
            solid,
            is_void: false,
            faces: vec![],
        });
        let mut stack = vec![seed];
        model.faces[seed].shell = shell;
        while let Some(f) = stack.pop() {
            model.shells[shell].faces.push(f);
            let next: Vec<usize> = model.faces[f]
                .loops
                .iter()
                .flat_map(|l| &l.edges)
                .flat_map(|oe| model.edges[oe.edge].faces.iter().copied())
                .collect();
            for g in next {
                if model.faces[g].shell == usize::MAX {
                    model.faces[g].shell = shell;
                    stack.push(g);
                }
            }
        }
        model.shells[shell].faces.sort_unstable();
    }
}

/// A 510 face as a soup face: its surface, and per 508 loop the model-space curves of its
/// edges (504) cut to the edge's vertices (502); degenerate edges given as a vertex are
/// dropped, as chaining drops zero-length pieces.
fn read_brep_face(ctx: &Ctx, de: usize) -> Result<SoupFace> {
    let e = ctx.typed(de, de, &[510])?;
    let surf = ctx.ptr(e, 0, "surface")?;
    let n = ctx.count(e, 1, "number of loops")?;
    if n == 0 {
        return Err(ctx.err(de, "face has no loops"));
    }
    let surface = ctx.surface(surf, de, &IDENTITY)?;
    let mut loops = Vec::with_capacity(n);
    for k in 0..n {
        let l = ctx.ptr(e, 3 + k, "loop")?;
        let le = ctx.typed(l, de, &[508])?;
        let mut pieces = Vec::new();
        for entry in loop_entries(ctx, le)?.into_iter().filter(|x| x.kind == 0) {
            pieces.push((edge_piece(ctx, entry.list, entry.index, l)?, true));
        }
        if !pieces.is_empty() {
            loops.push(SoupLoop { de: l, pieces });
        }
    }
    Ok(SoupFace { de, surface, loops })
}

/// Edge `index` of the 504 edge list `list`: its curve between its two vertices.
fn edge_piece(ctx: &Ctx, list: usize, index: usize, from: usize) -> Result<Segment> {
    let (e, EdgeEntry { curve, start, end }) = edge_entry(ctx, list, index, from)?;
    let pa = vertex_point(ctx, start.0, start.1, list)?;
    let pb = vertex_point(ctx, end.0, end.1, list)?;
    let seg = ctx.curve(curve, list, &ctx.transform_chain(e)?)?;
    let (range, _) = edge_range(&seg, pa, pb).map_err(|r| ctx.err(curve, r))?;
    Ok(Segment { range, ..seg })
}

/// A 143 bounded surface as a soup face: its surface, and per 141 boundary the model-space
/// curves it lists.
fn read_bounded_surface(ctx: &Ctx, de: usize) -> Result<SoupFace> {
    let e = ctx.typed(de, de, &[143])?;
    let surf = ctx.ptr(e, 1, "surface")?;
    let n = ctx.count(e, 2, "number of boundaries")?;
    let outer_t = ctx.transform_chain(e)?;
    let surface = ctx.surface(surf, de, &outer_t)?;
    let mut loops = Vec::with_capacity(n);
    for k in 0..n {
        let b = ctx.ptr(e, 3 + k, "boundary")?;
        let be = ctx.typed(b, de, &[141])?;
        let m = ctx.count(be, 3, "number of curves")?;
        let t = mat_mul(&outer_t, &ctx.transform_chain(be)?);
        let mut pieces = Vec::new();
        let mut at = 4;
        for _ in 0..m {
            let c = ctx.ptr(be, at, "model-space curve")?;
            let pcurves = ctx.count(be, at + 2, "number of parameter-space curves")?;
            at += 3 + pcurves;
            pieces.extend(ctx.segments(c, b, &t)?.into_iter().map(|s| (s, true)));
        }
        loops.push(SoupLoop { de: b, pieces });
    }
    if loops.is_empty() {
        return Err(ctx.err(de, "bounded surface has no boundary"));
    }
    Ok(SoupFace { de, surface, loops })
}

fn read_face(ctx: &Ctx, de: usize) -> Result<SoupFace> {
    let e = ctx.typed(de, de, &[144])?;
    let surf = ctx.ptr(e, 0, "surface")?;
    let n1 = ctx.int(e, 1, "outer boundary flag")?;
    let n2 = ctx.count(e, 2, "number of inner boundaries")?;
    let outer_t = ctx.transform_chain(e)?;
    let surface = ctx.surface(surf, de, &outer_t)?;
    if n1 == 0 {
        return Err(ctx.err(
            de,
            "outer boundary is the surface's own boundary (N1 = 0): not supported",
        ));
    }
    let mut bounds = vec![ctx.ptr(e, 3, "outer boundary")?];
    for k in 0..n2 {
        bounds.push(ctx.ptr(e, 4 + k, "inner boundary")?);
    }
    let mut loops = Vec::new();
    for b in bounds {
        let c = ctx.typed(b, de, &[142])?;
        let cptr = ctx.int(c, 3, "model-space curve")?;
        if cptr <= 0 {
            return Err(ctx.err(
                b,
                "no model-space curve (only the parameter-space one): not supported",
            ));
        }
        let t = mat_mul(&outer_t, &ctx.transform_chain(c)?);
        let segs = ctx.segments(ctx.ptr(c, 3, "model-space curve")?, b, &t)?;
        loops.push(SoupLoop {
            de: b,
            pieces: segs.into_iter().map(|s| (s, true)).collect(),
        });
    }
    Ok(SoupFace { de, surface, loops })
}

/// Drops zero-length pieces and turns pieces round so that the boundary runs end to start.
fn chain(ctx: &Ctx, l: &mut SoupLoop, tol: f64) -> Result<()> {
    l.pieces.retain(|(s, _)| {
        let (a, b, m) = (s.start(), s.end(), s.at_fraction(0.5));
        a.distance(b) > tol || a.distance(m) > tol
    });
    let n = l.pieces.len();
    if n == 0 {
        return Err(ctx.err(l.de, "boundary has no curve of non-zero length"));
    }
    if n >= 2 {
        let (s0, e0) = (l.pieces[0].0.start(), l.pieces[0].0.end());
        let (s1, e1) = (l.pieces[1].0.start(), l.pieces[1].0.end());
        let joins = |p: DVec3| p.distance(s1) <= tol || p.distance(e1) <= tol;
        if !joins(e0) && joins(s0) {
            l.pieces[0].1 = false;
        }
    }
    for k in 1..n {
        let (_, end) = ends(&l.pieces[k - 1]);
        let (s, e) = (l.pieces[k].0.start(), l.pieces[k].0.end());
        if s.distance(end) <= tol {
            l.pieces[k].1 = true;
        } else if e.distance(end) <= tol {
            l.pieces[k].1 = false;
        } else {
            return Err(ctx.err(
                l.de,
                format!(
                    "boundary pieces DE {} and DE {} do not connect (gap of {:.3e} mm)",
                    l.pieces[k - 1].0.de,
                    l.pieces[k].0.de,
                    s.distance(end).min(e.distance(end))
                ),
            ));
        }
    }
    let (first, _) = ends(&l.pieces[0]);
    let (_, last) = ends(&l.pieces[n - 1]);
    if first.distance(last) > tol {
        return Err(ctx.err(
            l.de,
            format!(
                "boundary does not close (gap of {:.3e} mm)",
                first.distance(last)
            ),
        ));
    }
    Ok(())
}

/// True when the interior of `a` lies on `b` within `tol`.
fn same_curve(a: &(Segment, bool), b: &(Segment, bool), tol: f64) -> bool {
    [0.25, 0.5, 0.75].iter().all(|&s| {
        let p = a.0.at_fraction(s);
        nearest_param(&b.0, p).1 <= tol
    })
}

/// Points merged into vertices by a hash of cells of size `cell`.
struct Grid {
    cell: f64,
    cells: HashMap<(i64, i64, i64), Vec<usize>>,
}

impl Grid {
    fn key(&self, p: DVec3) -> (i64, i64, i64) {
        let k = |x: f64| (x / self.cell).floor() as i64;
        (k(p.x), k(p.y), k(p.z))
    }

    /// The vertex within `cell` of `p`, or a new one.
    fn vertex(&mut self, model: &mut Model, p: DVec3) -> usize {
        let (i, j, k) = self.key(p);
        let mut best: Option<(usize, f64)> = None;
        for di in -1..=1 {
            for dj in -1..=1 {
                for dk in -1..=1 {
                    if let Some(list) = self.cells.get(&(i + di, j + dj, k + dk)) {
                        for &v in list {
                            let d = model.vertices[v].point.distance(p);
                            if d <= self.cell && best.is_none_or(|b| d < b.1) {
                                best = Some((v, d));
                            }
                        }
                    }
                }
            }
        }
        if let Some((v, _)) = best {
            return v;
        }
        let v = model.vertices.len();
        model.vertices.push(Vertex {
            source_id: 0,
            point: p,
        });
        self.cells.entry((i, j, k)).or_default().push(v);
        v
    }
}
