//! What follows the STEP topology walk: checks, numbering, UV domains.
//!
//! Every face, edge and vertex the file defines must be part of a solid; the model is
//! numbered in file order; and each face's loops are projected into UV and its domain
//! computed (see `crate::ingest::domain`).

use super::records::Records;
use super::source::Source;
use crate::error::Result;
use crate::ingest::domain::{align_loops, face_domain, loop_polygon_tolerance, loop_uv_and_gap};
use crate::ingest::tolerance::VERTEX_ON_CURVE_REL_COORD;
use crate::model::*;
use rayon::prelude::*;
use rustc_hash::{FxHashMap as HashMap, FxHashSet};

/// Finishes the walked `model`: the checks, the numbering and the UV domains (module docs),
/// then its bounding box.
pub fn finish(src: &Source, model: &mut Model) -> Result<()> {
    check_everything_used(src, model)?;
    renumber_in_file_order(model, src.recs);
    compute_domains(src, model)?;
    {
        let mut warnings = src.warnings.lock().unwrap_or_else(|e| e.into_inner());
        crate::ingest::orient::orient_faces(model, &mut warnings);
        crate::ingest::orient::orient_shells(model, &mut warnings);
    }
    model.bbox = crate::geom::model_bounding_box(model);
    Ok(())
}

/// Compares what the file defines with what the model holds: an `ADVANCED_FACE`,
/// `EDGE_CURVE` or `VERTEX_POINT` that belongs to no solid read (stray edges some exporters
/// write, the surface model of a hybrid file, a shape no assembly uses) is ignored with a
/// warning. Nothing a solid references can be missing: the walk converts all of it or fails.
fn check_everything_used(src: &Source, model: &Model) -> Result<()> {
    let used_faces: FxHashSet<u64> = model.faces.iter().map(|f| f.source_id).collect();
    let used_edges: FxHashSet<u64> = model.edges.iter().map(|e| e.source_id).collect();
    let used_vertices: FxHashSet<u64> = model.vertices.iter().map(|v| v.source_id).collect();
    for id in src.recs.ids_in_order() {
        let Some(rec) = src.recs.simple(id) else {
            continue;
        };
        let lost = match rec.name.as_str() {
            "ADVANCED_FACE" | "FACE_SURFACE" => !used_faces.contains(&id),
            "EDGE_CURVE" => !used_edges.contains(&id),
            "VERTEX_POINT" => !used_vertices.contains(&id),
            _ => false,
        };
        if lost {
            let problem = format!(
                "{} defined in the file but not part of any solid read",
                rec.name
            );
            src.warn("unused", id, &problem, "ignored");
        }
    }
    Ok(())
}

/// Faces, edges and vertices numbered in the order the file defines them (then by
/// placement instance).
fn renumber_in_file_order(model: &mut Model, recs: &Records) {
    let m = model;
    // Instance of an entity = order of first creation among copies with the same id.
    let key_f: Vec<(usize, usize)> = order_keys(m.faces.iter().map(|f| f.source_id), recs);
    let key_e: Vec<(usize, usize)> = order_keys(m.edges.iter().map(|e| e.source_id), recs);
    let key_v: Vec<(usize, usize)> = order_keys(m.vertices.iter().map(|v| v.source_id), recs);
    let perm_f = permutation(&key_f);
    let perm_e = permutation(&key_e);
    let perm_v = permutation(&key_v);
    // new_of[old] = new index
    let inv = |perm: &[usize]| {
        let mut inv = vec![0; perm.len()];
        for (new, &old) in perm.iter().enumerate() {
            inv[old] = new;
        }
        inv
    };
    let (nf, ne, nv) = (inv(&perm_f), inv(&perm_e), inv(&perm_v));
    m.faces = perm_f.iter().map(|&o| m.faces[o].clone()).collect();
    m.edges = perm_e.iter().map(|&o| m.edges[o].clone()).collect();
    m.vertices = perm_v.iter().map(|&o| m.vertices[o]).collect();
    for s in &mut m.shells {
        for f in &mut s.faces {
            *f = nf[*f];
        }
    }
    for f in &mut m.faces {
        for l in &mut f.loops {
            for oe in &mut l.edges {
                oe.edge = ne[oe.edge];
            }
            if let Some(v) = &mut l.vertex {
                *v = nv[*v];
            }
        }
    }
    for e in &mut m.edges {
        for v in &mut e.vertices {
            *v = nv[*v];
        }
        for f in &mut e.faces {
            *f = nf[*f];
        }
    }
}

/// Each face's loops in UV, aligned, and its domain (and outer loop, when the file does not
/// say which it is).
fn compute_domains(src: &Source, model: &mut Model) -> Result<()> {
    // Faces are independent: their loops are projected in parallel (results are the same
    // whatever the thread count), then the first error in face order is reported.
    let m = &*model;
    let tol = loop_polygon_tolerance(m);
    let uvs: Vec<LoopsUv> = (0..m.faces.len())
        .into_par_iter()
        .map(|fi| {
            m.faces[fi]
                .loops
                .iter()
                .map(|l| loop_uv_and_gap(m, fi, l, tol).map_err(|reason| (l.source_id, reason)))
                .collect()
        })
        .collect();
    for (fi, uv) in uvs.into_iter().enumerate() {
        let uv = uv.map_err(|(id, reason)| src.err(id, reason))?;
        let m = &mut *model;
        for (l, (poly, gap)) in m.faces[fi].loops.iter_mut().zip(uv) {
            l.uv = poly.uv;
            l.uv_counts = poly.counts;
            l.gap_mm = gap.largest_mm;
            if poly.worst_mm > tol {
                src.warn_gap(
                    "coarse_trim",
                    l.source_id,
                    crate::ingest::domain::COARSE_TRIM_PROBLEM,
                    crate::ingest::domain::COARSE_TRIM_ACTION,
                    Some(poly.worst_mm),
                );
            }
            // Edges off their face's surface by more than rounding, and less than the
            // projection accepts (`ON_SURFACE_REL_COORD`): read, and said.
            if gap.rel > VERTEX_ON_CURVE_REL_COORD {
                src.warn_gap(
                    "gap",
                    l.source_id,
                    "loop's edges off its face's surface by more than 1e-4 of the coordinates' size",
                    "accepted (up to 1e-3 of the coordinates' size)",
                    Some(gap.mm),
                );
            }
        }
        align_loops(&mut m.faces[fi]);
        let (domain, outer) = face_domain(m, &m.faces[fi]);
        m.faces[fi].domain = domain;
        if m.faces[fi].outer.is_none() {
            m.faces[fi].outer = outer;
        }
    }
    Ok(())
}

/// One face's loops in UV, or the failing loop's id and the reason.
type LoopsUv = std::result::Result<
    Vec<(
        crate::ingest::domain::LoopPolygon,
        crate::ingest::domain::SurfaceGap,
    )>,
    (u64, String),
>;

fn order_keys(ids: impl Iterator<Item = u64>, recs: &Records) -> Vec<(usize, usize)> {
    let mut seen: HashMap<u64, usize> = HashMap::default();
    ids.map(|id| {
        let k = seen.entry(id).or_insert(0);
        let inst = *k;
        *k += 1;
        (inst, recs.position(id))
    })
    .collect()
}

fn permutation(keys: &[(usize, usize)]) -> Vec<usize> {
    let mut perm: Vec<usize> = (0..keys.len()).collect();
    perm.sort_by_key(|&i| keys[i]);
    perm
}
