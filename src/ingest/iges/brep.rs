//! IGES manifold solid B-rep objects (186) into the model.
//!
//! The walk: 186 → 514 shells → 510 faces → 508 loops → edges of 504 edge lists between
//! vertices of 502 vertex lists.
//!
//! A 508 loop lists, per edge, whether it is an edge or a vertex (`TYPE` 1: OpenCASCADE
//! writes the degenerate edge at a sphere's pole this way; it is dropped), the edge list and
//! index, the orientation flag (1 = along the model-space curve) and parameter-space curves,
//! which are ignored: the UV loops are computed from the 3D edges as for STEP. Face and shell
//! orientation flags are not needed either: [`super::finish`] orients every face from the
//! loops and the enclosed volume.

use super::ctx::Ctx;
use super::format::DirEntry;
use super::segment::{edge_range, Segment};
use crate::error::Result;
use crate::ingest::domain::EMPTY_DOMAIN;
use crate::ingest::transform::{apply, IDENTITY};
use crate::model::*;
use glam::DVec3;
use std::collections::HashMap;

#[derive(Default)]
struct Maps {
    /// (502 DE, index) → vertex.
    vertices: HashMap<(usize, usize), usize>,
    /// (504 DE, index) → (edge, whether the model curve runs against the list's start→end).
    edges: HashMap<(usize, usize), (usize, bool)>,
}

/// Builds the solid of the 186 entity at `de` (outer shell and voids).
pub fn build_solid(ctx: &Ctx, model: &mut Model, de: usize) -> Result<()> {
    let e = ctx.typed(de, de, &[186])?;
    let shell = ctx.ptr(e, 0, "shell")?;
    let voids = ctx.count(e, 2, "number of void shells").unwrap_or(0);
    let solid = model.solids.len();
    model.solids.push(Solid {
        instance: None,
        source_id: de as u64,
        name: String::new(),
        shells: vec![],
    });
    let mut maps = Maps::default();
    let mut shells = vec![(shell, false)];
    for k in 0..voids {
        shells.push((ctx.ptr(e, 3 + 2 * k, "void shell")?, true));
    }
    for (s, is_void) in shells {
        let idx = build_shell(ctx, model, &mut maps, s, de, solid, is_void)?;
        model.solids[solid].shells.push(idx);
    }
    Ok(())
}

/// Builds a solid from a shell (514) that no 186 refers to (some writers stop at shells).
pub fn build_shell_solid(ctx: &Ctx, model: &mut Model, de: usize) -> Result<()> {
    let solid = model.solids.len();
    model.solids.push(Solid {
        instance: None,
        source_id: de as u64,
        name: String::new(),
        shells: vec![],
    });
    let mut maps = Maps::default();
    let idx = build_shell(ctx, model, &mut maps, de, de, solid, false)?;
    model.solids[solid].shells.push(idx);
    Ok(())
}

fn build_shell(
    ctx: &Ctx,
    model: &mut Model,
    maps: &mut Maps,
    de: usize,
    from: usize,
    solid: usize,
    is_void: bool,
) -> Result<usize> {
    let e = ctx.typed(de, from, &[514])?;
    let n = ctx.count(e, 0, "number of faces")?;
    if n == 0 {
        return Err(ctx.err(de, "shell has no faces"));
    }
    let shell = model.shells.len();
    model.shells.push(Shell {
        source_id: de as u64,
        solid,
        is_void,
        faces: vec![],
    });
    for k in 0..n {
        let f = ctx.ptr(e, 1 + 2 * k, "face")?;
        let fi = build_face(ctx, model, maps, f, de, shell)?;
        model.shells[shell].faces.push(fi);
    }
    Ok(shell)
}

fn build_face(
    ctx: &Ctx,
    model: &mut Model,
    maps: &mut Maps,
    de: usize,
    from: usize,
    shell: usize,
) -> Result<usize> {
    let e = ctx.typed(de, from, &[510])?;
    let surf = ctx.ptr(e, 0, "surface")?;
    let n = ctx.count(e, 1, "number of loops")?;
    if n == 0 {
        return Err(ctx.err(de, "face has no loops"));
    }
    let surface = ctx.surface(surf, de, &IDENTITY)?;
    let fi = model.faces.len();
    let mut loops = Vec::with_capacity(n);
    for k in 0..n {
        let l = ctx.ptr(e, 3 + k, "loop")?;
        loops.push(build_loop(ctx, model, maps, l, de, fi)?);
    }
    model.faces.push(Face {
        source_id: de as u64,
        shell,
        surface,
        sign: 1.0,
        same_sense: true,
        loops,
        outer: None,
        domain: EMPTY_DOMAIN,
    });
    Ok(fi)
}

fn build_loop(
    ctx: &Ctx,
    model: &mut Model,
    maps: &mut Maps,
    de: usize,
    from: usize,
    face: usize,
) -> Result<Loop> {
    let e = ctx.typed(de, from, &[508])?;
    let mut edges = Vec::new();
    let mut lone_vertex = None;
    for entry in loop_entries(ctx, e)? {
        match entry.kind {
            0 => {
                let (edge, reversed) = edge(ctx, model, maps, entry.list, entry.index, de)?;
                model.edges[edge].faces.push(face);
                edges.push(OrientedEdge {
                    edge,
                    forward: entry.along != reversed,
                });
            }
            1 => {
                // A degenerate edge, given as its vertex: nothing to trace along it.
                lone_vertex = Some(vertex(ctx, model, maps, entry.list, entry.index, de)?);
            }
            t => return Err(ctx.err(de, format!("edge type {t} (0 = edge, 1 = vertex)"))),
        }
    }
    if edges.is_empty() {
        return match lone_vertex {
            Some(v) => Ok(Loop {
                source_id: de as u64,
                edges: vec![],
                vertex: Some(v),
                uv: vec![],
                uv_counts: vec![],
                outline: vec![],
                gap_mm: 0.0,
            }),
            None => Err(ctx.err(de, "empty loop")),
        };
    }
    // The loop must be connected end to start.
    for i in 0..edges.len() {
        let a = edges[i];
        let b = edges[(i + 1) % edges.len()];
        let end = model.edges[a.edge].vertices[usize::from(a.forward)];
        let start = model.edges[b.edge].vertices[usize::from(!b.forward)];
        if end != start {
            return Err(ctx.err(de, "edges of the loop do not connect end to start"));
        }
    }
    Ok(Loop {
        source_id: de as u64,
        edges,
        vertex: None,
        uv: vec![],
        uv_counts: vec![],
        outline: vec![],
        gap_mm: 0.0,
    })
}

fn vertex(
    ctx: &Ctx,
    model: &mut Model,
    maps: &mut Maps,
    list: usize,
    index: usize,
    from: usize,
) -> Result<usize> {
    if let Some(&v) = maps.vertices.get(&(list, index)) {
        return Ok(v);
    }
    let point = vertex_point(ctx, list, index, from)?;
    let v = model.vertices.len();
    model.vertices.push(Vertex {
        source_id: list as u64,
        point,
    });
    maps.vertices.insert((list, index), v);
    Ok(v)
}

fn edge(
    ctx: &Ctx,
    model: &mut Model,
    maps: &mut Maps,
    list: usize,
    index: usize,
    from: usize,
) -> Result<(usize, bool)> {
    if let Some(&x) = maps.edges.get(&(list, index)) {
        return Ok(x);
    }
    let (e, EdgeEntry { curve, start, end }) = edge_entry(ctx, list, index, from)?;
    let a = vertex(ctx, model, maps, start.0, start.1, list)?;
    let b = vertex(ctx, model, maps, end.0, end.1, list)?;
    let seg = ctx.curve(curve, list, &ctx.transform_chain(e)?)?;
    let (pa, pb) = (model.vertices[a].point, model.vertices[b].point);
    let (range, reversed) = edge_range(&seg, pa, pb).map_err(|r| ctx.err(curve, r))?;
    let vertices = if reversed { [b, a] } else { [a, b] };
    let idx = model.edges.len();
    let Segment { curve: c, .. } = seg;
    model.edges.push(Edge {
        source_id: curve as u64,
        curve: c,
        range,
        vertices,
        faces: vec![],
    });
    maps.edges.insert((list, index), (idx, reversed));
    Ok((idx, reversed))
}

/// One entry of a 508 loop: `kind` 0 for an edge, 1 for a vertex; the edge (or vertex) list
/// and the index in it; whether the loop runs along the model-space curve. Parameter-space
/// curves are skipped.
pub(super) struct LoopEntry {
    pub kind: i64,
    pub list: usize,
    pub index: usize,
    pub along: bool,
}

/// The entries of the 508 loop `e`, in order.
pub(super) fn loop_entries(ctx: &Ctx, e: &DirEntry) -> Result<Vec<LoopEntry>> {
    let n = ctx.count(e, 0, "number of edges")?;
    let mut k = 1;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let kind = ctx.int(e, k, "edge or vertex type")?;
        let list = ctx.ptr(e, k + 1, "edge list")?;
        let index = ctx.index(e, k + 2, "index in the list")?;
        let along = ctx.int(e, k + 3, "orientation flag")? != 0;
        let pcurves = ctx.count(e, k + 4, "number of parameter-space curves")?;
        k += 5 + 2 * pcurves;
        out.push(LoopEntry {
            kind,
            list,
            index,
            along,
        });
    }
    Ok(out)
}

/// Edge `index` of a 504 edge list: its model-space curve's DE, and its start and end
/// vertices as (502 list, index).
pub(super) struct EdgeEntry {
    pub curve: usize,
    pub start: (usize, usize),
    pub end: (usize, usize),
}

/// Entry `index` of the 504 edge list `list` (referred to from `from`), with the list's own
/// directory entry.
pub(super) fn edge_entry<'a>(
    ctx: &'a Ctx,
    list: usize,
    index: usize,
    from: usize,
) -> Result<(&'a DirEntry, EdgeEntry)> {
    let e = list_with(ctx, list, index, from, (504, "edge", "number of edges"))?;
    let k = 1 + 5 * (index - 1);
    let entry = EdgeEntry {
        curve: ctx.ptr(e, k, "model-space curve")?,
        start: (
            ctx.ptr(e, k + 1, "start vertex list")?,
            ctx.index(e, k + 2, "start vertex index")?,
        ),
        end: (
            ctx.ptr(e, k + 3, "end vertex list")?,
            ctx.index(e, k + 4, "end vertex index")?,
        ),
    };
    Ok((e, entry))
}

/// The list `list` (referred to from `from`) of `kind`: its entity type (504 edges, 502
/// vertices), what an item is called and what its count parameter is; it must hold an item
/// `index` (1-based).
fn list_with<'a>(
    ctx: &'a Ctx,
    list: usize,
    index: usize,
    from: usize,
    kind: (i64, &str, &str),
) -> Result<&'a DirEntry> {
    let (ty, item, count) = kind;
    let e = ctx.typed(list, from, &[ty])?;
    let n = ctx.count(e, 0, count)?;
    if index < 1 || index > n {
        return Err(ctx.err(
            from,
            format!("{item} {index} of the {item} list DE {list}, which has {n}"),
        ));
    }
    Ok(e)
}

/// Vertex `index` of the 502 vertex list `list` (referred to from `from`), placed.
pub(super) fn vertex_point(ctx: &Ctx, list: usize, index: usize, from: usize) -> Result<DVec3> {
    let e = list_with(
        ctx,
        list,
        index,
        from,
        (502, "vertex", "number of vertices"),
    )?;
    let r = ctx.reals(e, 1 + 3 * (index - 1), 3, "vertex coordinates")?;
    let m = ctx.place(&IDENTITY, e)?;
    Ok(apply(&m, DVec3::new(r[0], r[1], r[2])))
}
