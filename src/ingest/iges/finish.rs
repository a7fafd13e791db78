//! What both IGES routes need after topology is built.
//!
//! Full closed surfaces, consistent and outward orientation, UV loops and domains, the
//! bounding box.
//!
//! **Orientation.** IGES does not say reliably on which side of a loop its face lies (a 144
//! soup carries no orientation at all, and writers differ on 510/514 flags), so it is
//! derived from geometry, writer-independently:
//! 1. the faces of a closed shell are made consistent: an edge shared by two faces must be
//!    used in opposite directions by their loops; faces are flipped (loops reversed) by a
//!    breadth-first walk over shared edges, and a conflict means the shell is not orientable;
//! 2. each face's `same_sense` (the side of `Su × Sv` against which its loops have the face
//!    on their left, see [`Face::same_sense`]) is read from its outer loop's UV polygon:
//!    counter-clockwise means `same_sense`; for faces whose UV polygon depends on it (seam
//!    edges are placed by it) both values are tried and the one that agrees is kept;
//! 3. the loops' side is then the same for every face of the shell, so their outward normal is
//!    either all `same_sense · (Su × Sv)` or all the opposite: the sign of the volume the shell
//!    encloses, `V = ⅓ ∮ (P − c)·n dA` (divergence theorem, sampled on a grid of each face's
//!    trimmed domain), decides (positive for an outer shell, negative for a void).
//!
//! **Full closed surfaces.** A loop made of one seam edge run there and back (OpenCASCADE's
//! full sphere, with its pole edges given as vertices; FreeCAD's full sphere, whose meridian
//! is written twice) bounds nothing: it becomes a vertex loop at the seam's start, as the STEP
//! reader's `VERTEX_LOOP` does, and the seam edge is dropped.

use super::ctx::Ctx;
use crate::error::Result;
use crate::ingest::domain::{
    align_loops, face_domain, loop_polygon_tolerance, loop_uv_and_gap, signed_area,
};
use crate::model::*;
use glam::DVec3;
use std::collections::VecDeque;

/// Grid of samples per face direction for the enclosed-volume sign.
const VOLUME_GRID: usize = 32;

/// `nest_shells`: the shells were found as connected components of a soup, each its own
/// solid so far; a shell inside another is then made a void of it (see [`nest_voids`]).
pub fn finish(ctx: &Ctx, model: &mut Model, nest_shells: bool) -> Result<()> {
    close_full_surfaces(model);
    compact(model);
    let uses = edge_uses(model);
    for (e, u) in uses.iter().enumerate() {
        if u.len() != 2 {
            return Err(ctx.err(
                model.edges[e].source_id as usize,
                format!(
                    "edge used by {} face loop(s); a closed shell uses each edge twice (open shell?)",
                    u.len()
                ),
            ));
        }
    }
    orient_consistently(ctx, model, &uses)?;
    compute_domains(ctx, model)?;
    if nest_shells && model.shells.len() > 1 {
        nest_voids(model);
    }
    orient_outward(ctx, model)?;
    model.bbox = crate::geom::model_bounding_box(model);
    Ok(())
}

/// Loops made of one seam run there and back become vertex loops (module docs).
fn close_full_surfaces(model: &mut Model) {
    for f in 0..model.faces.len() {
        for l in 0..model.faces[f].loops.len() {
            let lp = &model.faces[f].loops[l];
            if lp.edges.len() != 2 || lp.edges[0].edge != lp.edges[1].edge {
                continue;
            }
            let e = lp.edges[0].edge;
            if lp.edges[0].forward == lp.edges[1].forward {
                continue;
            }
            let start = model.edges[e].vertices[0];
            let lp = &mut model.faces[f].loops[l];
            lp.edges.clear();
            lp.vertex = Some(start);
            model.edges[e].faces.clear();
        }
    }
}

/// Drops edges no loop uses and vertices nothing uses, renumbering the rest in order.
fn compact(model: &mut Model) {
    let mut edge_used = vec![false; model.edges.len()];
    let mut vertex_used = vec![false; model.vertices.len()];
    for f in &model.faces {
        for l in &f.loops {
            for oe in &l.edges {
                edge_used[oe.edge] = true;
            }
            if let Some(v) = l.vertex {
                vertex_used[v] = true;
            }
        }
    }
    for (e, edge) in model.edges.iter().enumerate() {
        if edge_used[e] {
            for &v in &edge.vertices {
                vertex_used[v] = true;
            }
        }
    }
    let renumber = |used: &[bool]| {
        let mut next = 0;
        used.iter()
            .map(|&u| {
                let n = next;
                if u {
                    next += 1;
                }
                n
            })
            .collect::<Vec<usize>>()
    };
    let new_e = renumber(&edge_used);
    let new_v = renumber(&vertex_used);
    let mut k = 0;
    model.edges.retain(|_| {
        k += 1;
        edge_used[k - 1]
    });
    let mut k = 0;
    model.vertices.retain(|_| {
        k += 1;
        vertex_used[k - 1]
    });
    for edge in &mut model.edges {
        for v in &mut edge.vertices {
            *v = new_v[*v];
        }
    }
    for f in &mut model.faces {
        for l in &mut f.loops {
            for oe in &mut l.edges {
                oe.edge = new_e[oe.edge];
            }
            if let Some(v) = &mut l.vertex {
                *v = new_v[*v];
            }
        }
    }
}

/// For each edge, its uses: (face, forward).
fn edge_uses(model: &Model) -> Vec<Vec<(usize, bool)>> {
    let mut uses = vec![Vec::new(); model.edges.len()];
    for (f, face) in model.faces.iter().enumerate() {
        for l in &face.loops {
            for oe in &l.edges {
                uses[oe.edge].push((f, oe.forward));
            }
        }
    }
    uses
}

/// Step 1 of the module docs.
fn orient_consistently(ctx: &Ctx, model: &mut Model, uses: &[Vec<(usize, bool)>]) -> Result<()> {
    let nf = model.faces.len();
    let mut face_edges: Vec<Vec<usize>> = vec![Vec::new(); nf];
    for (e, u) in uses.iter().enumerate() {
        for &(f, _) in u {
            face_edges[f].push(e);
        }
    }
    let mut flip: Vec<Option<bool>> = vec![None; nf];
    for seed in 0..nf {
        if flip[seed].is_some() {
            continue;
        }
        flip[seed] = Some(false);
        let mut queue = VecDeque::from([seed]);
        while let Some(f) = queue.pop_front() {
            for &e in &face_edges[f] {
                let (a, b) = (uses[e][0], uses[e][1]);
                if a.0 == b.0 {
                    // A seam: the face meets itself; consistent when run both ways.
                    if a.1 == b.1 {
                        return Err(ctx.err(
                            model.faces[a.0].source_id as usize,
                            "the face's loops run along its seam twice in the same direction",
                        ));
                    }
                    continue;
                }
                let (this, other) = if a.0 == f { (a, b) } else { (b, a) };
                let fl = flip[f].unwrap_or(false);
                // Directions after flips must differ.
                let want_other_flip = (this.1 != fl) == other.1;
                match flip[other.0] {
                    None => {
                        flip[other.0] = Some(want_other_flip);
                        queue.push_back(other.0);
                    }
                    Some(x) if x != want_other_flip => {
                        return Err(ctx.err(
                            model.edges[e].source_id as usize,
                            "faces around this edge cannot be oriented consistently (non-orientable or inconsistent shell)",
                        ));
                    }
                    Some(_) => {}
                }
            }
        }
    }
    for (f, fl) in flip.iter().enumerate() {
        if *fl == Some(true) {
            for l in &mut model.faces[f].loops {
                l.edges.reverse();
                for oe in &mut l.edges {
                    oe.forward = !oe.forward;
                }
            }
        }
    }
    Ok(())
}

/// UV loops, domain and outer loop of one face, for a given `same_sense`.
fn face_loops(
    ctx: &Ctx,
    model: &mut Model,
    f: usize,
    same_sense: bool,
    tol: f64,
) -> Result<Option<f64>> {
    model.faces[f].same_sense = same_sense;
    let mut loops = std::mem::take(&mut model.faces[f].loops);
    let mut failed = None;
    for l in &mut loops {
        match loop_uv_and_gap(model, f, l, tol) {
            Ok((poly, gap)) => {
                if poly.worst_mm > tol {
                    ctx.warn(
                        "coarse_trim",
                        l.source_id as usize,
                        &format!(
                            "{} (by {:.3e} mm)",
                            crate::ingest::domain::COARSE_TRIM_PROBLEM,
                            poly.worst_mm
                        ),
                        crate::ingest::domain::COARSE_TRIM_ACTION,
                    );
                }
                l.uv = poly.uv;
                l.uv_counts = poly.counts;
                l.gap_mm = gap.largest_mm;
            }
            Err(reason) => {
                failed = Some((l.source_id, reason));
                break;
            }
        }
    }
    model.faces[f].loops = loops;
    if let Some((id, reason)) = failed {
        return Err(ctx.err(id as usize, reason));
    }
    align_loops(&mut model.faces[f]);
    let (domain, outer) = face_domain(model, &model.faces[f]);
    model.faces[f].domain = domain;
    model.faces[f].outer = outer;
    Ok(outer.map(|o| signed_area(&model.faces[f].loops[o].uv)))
}

/// True when the face's loops span at most one period in each periodic direction, as any
/// face of a periodic surface does: a seam placed on the wrong side of the period by a wrong
/// `same_sense` makes the loop run on into the next period copy. (A jump between consecutive
/// UV samples is no criterion: at a pole `u` legitimately jumps.)
fn within_one_period(face: &Face) -> bool {
    let d = face.domain;
    let fits = |r: (f64, f64), p: Option<f64>| p.is_none_or(|p| r.1 - r.0 <= p * (1.0 + 1e-9));
    fits(d.u, d.u_period) && fits(d.v, d.v_period)
}

/// Step 2 of the module docs.
fn compute_domains(ctx: &Ctx, model: &mut Model) -> Result<()> {
    let tol = loop_polygon_tolerance(model);
    for f in 0..model.faces.len() {
        let has_seam = model.faces[f]
            .loops
            .iter()
            .flat_map(|l| &l.edges)
            .any(|oe| {
                model.edges[oe.edge]
                    .faces
                    .iter()
                    .filter(|&&g| g == f)
                    .count()
                    >= 2
            });
        let area = face_loops(ctx, model, f, true, tol)?;
        if !has_seam {
            // The UV polygons do not depend on `same_sense`: a clockwise outer loop says it.
            // (No outer loop — only wrapping or vertex loops — leaves nothing to tell by.)
            model.faces[f].same_sense = area.is_none_or(|a| a > 0.0);
            continue;
        }
        // Seam edges are placed by `same_sense`: the right value gives loops within one
        // period whose outer one turns the matching way.
        if within_one_period(&model.faces[f]) && area.is_some_and(|a| a > 0.0) {
            continue;
        }
        let other = face_loops(ctx, model, f, false, tol)?;
        if within_one_period(&model.faces[f]) && other.is_some_and(|a| a < 0.0) {
            continue;
        }
        // Neither fits (a face whose loops only wrap around a period): keep the default.
        face_loops(ctx, model, f, true, tol)?;
    }
    Ok(())
}

/// Step 3 of the module docs. Where the loops turn the other way (the face on their left
/// seen from inside the material), they are reversed, so that every face follows the STEP
/// convention the rest of the crate expects: loops have the face on their left seen from
/// outside, i.e. `sign` equals the `same_sense` orientation.
fn orient_outward(ctx: &Ctx, model: &mut Model) -> Result<()> {
    let centre = {
        let (lo, hi) = crate::geom::model_bounding_box(model);
        (lo + hi) * 0.5
    };
    for s in 0..model.shells.len() {
        let mut volume = 0.0;
        for &f in &model.shells[s].faces {
            let face = &model.faces[f];
            let orient = if face.same_sense { 1.0 } else { -1.0 };
            volume += orient * flux(face, centre) / 3.0;
        }
        if volume == 0.0 || !volume.is_finite() {
            return Err(ctx.err(
                model.shells[s].source_id as usize,
                "the shell encloses no volume: cannot tell inside from outside",
            ));
        }
        let outward = if model.shells[s].is_void {
            volume < 0.0
        } else {
            volume > 0.0
        };
        let faces = model.shells[s].faces.clone();
        for f in faces {
            if !outward {
                for l in &mut model.faces[f].loops {
                    l.edges.reverse();
                    for oe in &mut l.edges {
                        oe.forward = !oe.forward;
                    }
                    // The polygon backwards, each edge's samples from its new start: the
                    // reversed edge starts where the loop's next edge started.
                    l.uv.reverse();
                    if !l.uv.is_empty() {
                        l.uv.rotate_right(1);
                    }
                    l.uv_counts.reverse();
                }
                model.faces[f].same_sense = !model.faces[f].same_sense;
            }
            let face = &mut model.faces[f];
            face.sign = if face.same_sense { 1.0 } else { -1.0 };
        }
    }
    Ok(())
}

/// Makes every shell that lies inside another (by the winding number of the other's
/// surface around a point of it: `w = (1/4π) ∮ (S − p)·n / ‖S − p‖³ dA`, 1 inside, 0
/// outside) a void of the innermost shell containing it, when that one is at even depth (an
/// outer boundary); shells at even depth stay solids of their own.
fn nest_voids(model: &mut Model) {
    let ns = model.shells.len();
    // A point on each shell: the centre of its first face's domain if it is in the face,
    // else a vertex.
    let probe: Vec<DVec3> = (0..ns)
        .map(|s| {
            let f = model.shells[s].faces[0];
            let face = &model.faces[f];
            let d = face.domain;
            let (u, v) = (0.5 * (d.u.0 + d.u.1), 0.5 * (d.v.0 + d.v.1));
            if crate::geom::trim::contains(face, glam::DVec2::new(u, v)) {
                crate::geom::surface_point(&face.surface, u, v)
            } else {
                face.loops
                    .iter()
                    .find_map(|l| {
                        l.edges
                            .first()
                            .map(|oe| model.edges[oe.edge].vertices[0])
                            .or(l.vertex)
                    })
                    .map_or(DVec3::ZERO, |v| model.vertices[v].point)
            }
        })
        .collect();
    let inside = |a: usize, b: usize| -> bool {
        let w: f64 = model.shells[b]
            .faces
            .iter()
            .map(|&f| {
                let face = &model.faces[f];
                let orient = if face.same_sense { 1.0 } else { -1.0 };
                orient * solid_angle(face, probe[a])
            })
            .sum::<f64>()
            / (4.0 * std::f64::consts::PI);
        w.abs() > 0.5
    };
    let contains: Vec<Vec<usize>> = (0..ns)
        .map(|a| (0..ns).filter(|&b| b != a && inside(a, b)).collect())
        .collect();
    let depth: Vec<usize> = contains.iter().map(|c| c.len()).collect();
    let mut solids: Vec<Solid> = Vec::new();
    let mut solid_of = vec![usize::MAX; ns];
    for s in 0..ns {
        if depth[s].is_multiple_of(2) {
            solid_of[s] = solids.len();
            solids.push(Solid {
                instance: None,
                source_id: model.shells[s].source_id,
                name: String::new(),
                shells: vec![s],
            });
            model.shells[s].is_void = false;
        }
    }
    for s in 0..ns {
        if depth[s] % 2 == 1 {
            // The innermost container: the one of greatest depth.
            let parent = contains[s]
                .iter()
                .copied()
                .max_by_key(|&b| depth[b])
                .expect("odd depth has a container");
            let solid = solid_of[parent];
            solids[solid].shells.push(s);
            solid_of[s] = solid;
            model.shells[s].is_void = true;
        }
    }
    for (shell, &solid) in model.shells.iter_mut().zip(&solid_of) {
        shell.solid = solid;
    }
    model.solids = solids;
}

/// `∫∫ (S − p)·(Su × Sv) / ‖S − p‖³ du dv` over the face's trimmed domain (midpoint rule): the
/// solid angle the face subtends at `p`, signed by `Su × Sv`.
fn solid_angle(face: &Face, p: DVec3) -> f64 {
    integrate(face, |s| {
        let r = s.p - p;
        let l = r.length();
        if l == 0.0 {
            0.0
        } else {
            r.dot(s.su.cross(s.sv)) / (l * l * l)
        }
    })
}

/// `∫∫ (S − c)·(Su × Sv) du dv` over the face's trimmed domain (midpoint rule).
fn flux(face: &Face, c: DVec3) -> f64 {
    integrate(face, |s| (s.p - c).dot(s.su.cross(s.sv)))
}

/// `∫∫ g(S(u, v)) du dv` over the face's trimmed domain, midpoint rule on a
/// `VOLUME_GRID × VOLUME_GRID` grid of the domain.
fn integrate(face: &Face, g: impl Fn(&crate::geom::SurfaceDerivs) -> f64) -> f64 {
    let d = face.domain;
    let (du, dv) = (
        (d.u.1 - d.u.0) / VOLUME_GRID as f64,
        (d.v.1 - d.v.0) / VOLUME_GRID as f64,
    );
    if !(du.is_finite() && dv.is_finite()) || du == 0.0 || dv == 0.0 {
        return 0.0;
    }
    let trim = crate::geom::trim::Trim::new(face);
    let mut sum = 0.0;
    for i in 0..VOLUME_GRID {
        for j in 0..VOLUME_GRID {
            let u = d.u.0 + (i as f64 + 0.5) * du;
            let v = d.v.0 + (j as f64 + 0.5) * dv;
            if !trim.contains(face, glam::DVec2::new(u, v)) {
                continue;
            }
            let s = crate::geom::eval_surface(&face.surface, u, v);
            sum += g(&s) * du * dv;
        }
    }
    sum
}
