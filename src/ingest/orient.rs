//! Orientation from geometry: a face's sense agrees with its loops, an outer shell's normals
//! point away from what it encloses, a void's into the void, whatever the file's flags say.
//!
//! **Faces** ([`orient_faces`]): a face's loops run with the face on their left seen from its
//! normal (the surface's normal, turned where the face's sense is false). At the middle of
//! each edge of its loops the face's UV polygon says which side is the face: a point just to
//! the left must be inside the trim and one just to the right outside. (Faces are screened
//! first by the signed area of their loops in UV, where every loop closes there.) A face whose
//! edges mostly say the opposite has a sense that disagrees with its loops. When every one of its
//! edges is used the other way by the face across it (the loops agree with the shell), the
//! sense is what is wrong: it is turned, with a warning. (A face whose loops are what is
//! wrong keeps its normal.)
//!
//! **Shells** ([`orient_shells`]):
//! A closed surface's outward side is decided without any normal the file gives: at the
//! point of the shell farthest along a direction `e`, the side away from what the shell
//! encloses is `+e`. So at that point the outward normal of an outer shell has `n·e > 0`,
//! and a void's (pointing out of the material, into the void) `n·e < 0`. Each shell is
//! tested along ±x, ±y and ±z, at the farthest of the points sampled on its edges and on a
//! grid inside the faces that can bulge beyond their edges; a shell that most directions say
//! is inside out has every face's sign turned, with a
//! warning. (Files disagree on how `ORIENTED_CLOSED_SHELL(.F.)` in `BREP_WITH_VOIDS` is meant:
//! the geometry decides.)

use crate::geom::distance::face_normal;
use crate::geom::eval::curve_point;
use crate::geom::trim::contains;
use crate::geom::trim::edge_samples;
use crate::geom::{surface_kind, surface_point};
use crate::model::{Model, Warnings};
use glam::{DVec2, DVec3};

/// Grid points per direction of a face's domain where the shell's extremes are looked for.
pub const ORIENT_GRID: usize = 5;

/// The boundary is looked at in every this-many of the loops' UV samples (4 on a curved edge
/// the reader did not refine).
pub const BOUNDARY_STRIDE: usize = 8;

/// A direction votes only where its extreme point's normal leans this much along it
/// (cosine): at a sharp edge or a sampled point beside the true extreme the normal is
/// oblique, but still on the right side.
pub const ORIENT_MIN_COS: f64 = 0.05;

/// How many of a face's edges say its sense agrees with its loops (`right`) and disagrees
/// (`wrong`); edges whose middle is ambiguous (a seam, a point on another loop) do not vote.
pub fn face_votes(model: &Model, fi: usize) -> Votes {
    edge_votes(model, fi, usize::MAX)
}

/// [`face_votes`] over at most `limit` edges.
fn edge_votes(model: &Model, fi: usize, limit: usize) -> Votes {
    let face = &model.faces[fi];
    let d = &face.domain;
    let size = (d.u.1 - d.u.0).abs().min((d.v.1 - d.v.0).abs());
    if !(size.is_finite() && size > 0.0) {
        return Votes::default();
    }
    let mut votes = Votes::default();
    for lp in &face.loops {
        if lp.edges.is_empty() || !lp.uv_counts_match() {
            continue;
        }
        let total = lp.uv.len();
        let counts = lp
            .edges
            .iter()
            .zip(&lp.uv_counts)
            .map(|(oe, &n)| (edge_samples(model, fi, oe).0, n));
        let mut start = 0;
        for (seam, n) in counts {
            let mid = start + n / 2;
            start += n;
            if seam {
                continue;
            }
            let at = lp.uv[mid];
            let tangent = lp.uv[(mid + 1) % total] - lp.uv[(mid + total - 1) % total];
            let len = tangent.length();
            if !(len.is_finite() && len > 0.0) {
                continue;
            }
            // Left of the loop in UV, for a face whose normal is +Su×Sv.
            let mut left = DVec2::new(-tangent.y, tangent.x) / len;
            if !face.same_sense {
                left = -left;
            }
            let step = (0.05 * len).min(0.01 * size);
            let inside = contains(face, at + step * left);
            let outside = contains(face, at - step * left);
            match (inside, outside) {
                (true, false) => votes.right += 1,
                (false, true) => votes.wrong += 1,
                _ => {}
            }
            if votes.right + votes.wrong >= limit {
                return votes;
            }
        }
    }
    votes
}

/// The signed area in UV of all of a face's loops (the outer counter-clockwise and the holes
/// clockwise give the face's area, positive, when its loops run with it on their left seen
/// from +Su×Sv); `None` when a loop does not close in UV (it runs round a period) or the area
/// is too small to tell.
fn loops_area(face: &crate::model::Face) -> Option<f64> {
    let mut area = 0.0;
    let mut scale: f64 = 0.0;
    for lp in &face.loops {
        let uv = &lp.uv;
        if lp.vertex.is_some() || uv.len() < 3 {
            return None;
        }
        let mut longest: f64 = 0.0;
        for w in uv.windows(2) {
            longest = longest.max(w[0].distance(w[1]));
            area += w[0].perp_dot(w[1]);
        }
        let (first, last) = (uv[0], uv[uv.len() - 1]);
        if last.distance(first) > 2.0 * longest {
            return None;
        }
        area += last.perp_dot(first);
        scale = scale.max(longest);
    }
    let d = &face.domain;
    let size = (d.u.1 - d.u.0).abs() * (d.v.1 - d.v.0).abs();
    (area.is_finite() && area.abs() > 1e-9 * size && scale > 0.0).then_some(0.5 * area)
}

/// True when every edge of face `fi` that it shares with one other face is used the other
/// way by that face (the loops agree with the shell), counting each face's turn by the file
/// (`ORIENTED_FACE`, the shell's orientation).
fn loops_agree_with_neighbours(model: &Model, fi: usize) -> bool {
    // The direction a face's loops run in the shell: turned when its sign, apart from its
    // sense, is negative.
    let turned = |f: usize| {
        let face = &model.faces[f];
        let sense = if face.same_sense { 1.0 } else { -1.0 };
        face.sign * sense < 0.0
    };
    let uses = |f: usize, e: usize| -> Vec<bool> {
        model.faces[f]
            .loops
            .iter()
            .flat_map(|l| &l.edges)
            .filter(|oe| oe.edge == e)
            .map(|oe| oe.forward != turned(f))
            .collect()
    };
    for oe in model.faces[fi].loops.iter().flat_map(|l| &l.edges) {
        let edge = &model.edges[oe.edge];
        let [a, b] = edge.faces[..] else { continue };
        if a == b {
            continue;
        }
        let other = if a == fi { b } else { a };
        let (mine, theirs) = (uses(fi, oe.edge), uses(other, oe.edge));
        if mine.len() != 1 || theirs.len() != 1 || mine[0] == theirs[0] {
            return false;
        }
    }
    true
}

/// Turns the sense of every face whose loops say it is wrong while they agree with the
/// shell (see the module docs), with a warning naming it. Returns the faces turned.
pub fn orient_faces(model: &mut Model, warnings: &mut Warnings) -> Vec<usize> {
    let mut turned = Vec::new();
    for fi in 0..model.faces.len() {
        // Screened first, cheaply: the signed area of loops that close in UV, else one edge.
        let sound = match loops_area(&model.faces[fi]) {
            Some(area) => (area > 0.0) == model.faces[fi].same_sense,
            None => edge_votes(model, fi, 1).wrong == 0,
        };
        if sound {
            continue;
        }
        let votes = face_votes(model, fi);
        if votes.wrong >= 2
            && votes.wrong >= 3 * votes.right
            && loops_agree_with_neighbours(model, fi)
        {
            warnings.add(
                "orientation",
                format!("#{} face", model.faces[fi].source_id),
                "face whose sense flag disagrees with its loops (and the shell)",
                "its sense turned",
            );
            let f = &mut model.faces[fi];
            f.sign = -f.sign;
            f.same_sense = !f.same_sense;
            turned.push(fi);
        }
    }
    turned
}

/// What [`orient_shells`] found for one shell: how many directions said outward and inward.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Votes {
    pub right: usize,
    pub wrong: usize,
}

/// The votes of the six directions on shell `s`'s orientation (see the module docs).
///
/// The extremes are looked for where they can be: on the faces' boundaries (the loops' UV
/// samples, at their points on the edges), and inside the faces that can bulge beyond their
/// edges (any but planes, cylinders, cones and extrusions: along a ruling a coordinate is
/// linear, so a ruled face's extremes are on its boundary).
pub fn shell_votes(model: &Model, s: usize) -> Votes {
    let shell = &model.shells[s];
    let dirs = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    // Per direction: the farthest height so far, and the (face, uv) samples at it.
    let mut best: [(f64, Vec<(usize, DVec2)>); 6] = Default::default();
    for b in &mut best {
        b.0 = f64::NEG_INFINITY;
    }
    let offer = |best: &mut [(f64, Vec<(usize, DVec2)>); 6], p: DVec3, fi: usize, uv: DVec2| {
        let tol = 1e-9 * (1.0 + p.abs().max_element());
        // The heights along ±x, ±y, ±z.
        let hs = [p.x, -p.x, p.y, -p.y, p.z, -p.z];
        for (b, h) in best.iter_mut().zip(hs) {
            if h > b.0 + tol {
                b.0 = h;
                b.1.clear();
                b.1.push((fi, uv));
            } else if h >= b.0 - tol {
                b.1.push((fi, uv));
            }
        }
    };
    for &fi in &shell.faces {
        let face = &model.faces[fi];
        for lp in &face.loops {
            if let Some(v) = lp.vertex {
                if let Some(&uv) = lp.uv.first() {
                    offer(&mut best, model.vertices[v].point, fi, uv);
                }
                continue;
            }
            if !lp.uv_counts_match() {
                continue;
            }
            let mut idx = 0;
            for (oe, &n) in lp.edges.iter().zip(&lp.uv_counts) {
                let edge = &model.edges[oe.edge];
                let (t0, t1) = if oe.forward {
                    edge.range
                } else {
                    (edge.range.1, edge.range.0)
                };
                // Every BOUNDARY_STRIDE-th sample: the extremes need not be found exactly,
                // only a point near them whose normal leans the same way.
                for k in (0..n).step_by(BOUNDARY_STRIDE) {
                    let t = t0 + (t1 - t0) * k as f64 / n as f64;
                    offer(&mut best, curve_point(&edge.curve, t), fi, lp.uv[idx + k]);
                }
                idx += n;
            }
        }
    }
    // Inside the faces that can bulge, after every boundary: a grid point is tested against
    // the face's trim only when it would reach an extreme so far (most do not).
    for &fi in &shell.faces {
        let face = &model.faces[fi];
        if matches!(
            surface_kind(&face.surface),
            "plane" | "cylinder" | "cone" | "extrusion"
        ) {
            continue;
        }
        let d = &face.domain;
        if !(d.u.0.is_finite() && d.u.1.is_finite() && d.v.0.is_finite() && d.v.1.is_finite()) {
            continue;
        }
        let n = ORIENT_GRID;
        for i in 0..n {
            for j in 0..n {
                // Cell centres, so no sample lies on the domain's edge.
                let uv = DVec2::new(
                    d.u.0 + (d.u.1 - d.u.0) * (i as f64 + 0.5) / n as f64,
                    d.v.0 + (d.v.1 - d.v.0) * (j as f64 + 0.5) / n as f64,
                );
                let p = surface_point(&face.surface, uv.x, uv.y);
                let reaches = dirs
                    .iter()
                    .enumerate()
                    .any(|(k, e)| p.dot(*e) >= best[k].0 - 1e-9 * (1.0 + p.abs().max_element()));
                if reaches && contains(face, uv) {
                    offer(&mut best, p, fi, uv);
                }
            }
        }
    }
    let void = shell.is_void;
    let mut votes = Votes::default();
    for (k, e) in dirs.iter().enumerate() {
        // Of the faces at the extreme point, the one whose normal leans most along the
        // direction (the others there are tangent to it, or are faces of the edge beside).
        let mut at = best[k].1.clone();
        // One sample per face: a face at the extreme is tangent there or leans one way.
        at.sort_by_key(|s| s.0);
        at.dedup_by_key(|s| s.0);
        let lean = at
            .iter()
            .filter_map(|&(fi, uv)| face_normal(&model.faces[fi], (uv.x, uv.y)))
            .map(|n| n.dot(*e))
            .max_by(|a, b| a.abs().total_cmp(&b.abs()));
        let Some(c) = lean else { continue };
        if c.abs() < ORIENT_MIN_COS {
            continue;
        }
        if (c > 0.0) != void {
            votes.right += 1;
        } else {
            votes.wrong += 1;
        }
    }
    votes
}

/// Turns every shell that the geometry says is inside out (more wrong votes than right, and
/// at least two), with a warning naming it. Returns the shells turned.
pub fn orient_shells(model: &mut Model, warnings: &mut Warnings) -> Vec<usize> {
    let mut turned = Vec::new();
    for s in 0..model.shells.len() {
        let votes = shell_votes(model, s);
        if votes.wrong >= 2 && votes.wrong > votes.right {
            let shell = &model.shells[s];
            let what = if shell.is_void { "void" } else { "outer" };
            warnings.add(
                "orientation",
                format!("#{} shell", shell.source_id),
                &format!(
                    "{what} shell whose faces, as the file orients them, point into the material \
                     (by the shell's extreme points)"
                ),
                "every face of the shell turned",
            );
            for &f in &model.shells[s].faces.clone() {
                model.faces[f].sign = -model.faces[f].sign;
            }
            turned.push(s);
        }
    }
    turned
}
