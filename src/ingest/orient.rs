//! Shell orientation from geometry: an outer shell's normals point away from what it
//! encloses, a void's into the void, whatever the file's orientation flags say.
//!
//! A closed surface's outward side is decided without any normal the file gives: at the
//! point of the shell farthest along a direction `e`, the side away from what the shell
//! encloses is `+e`. So at that point the outward normal of an outer shell has `n·e > 0`,
//! and a void's (pointing out of the material, into the void) `n·e < 0`. Each shell is
//! tested along ±x, ±y and ±z, at the farthest of a grid of points inside its faces' trims;
//! a shell that most directions say is inside out has every face's sign turned, with a
//! warning. (Files disagree on how `ORIENTED_CLOSED_SHELL(.F.)` in `BREP_WITH_VOIDS` is meant:
//! the geometry decides.)

use crate::geom::distance::face_normal;
use crate::geom::surface_point;
use crate::geom::trim::Trim;
use crate::model::{Model, Warnings};
use glam::{DVec2, DVec3};

/// Grid points per direction of a face's domain where the shell's extremes are looked for.
pub const ORIENT_GRID: usize = 7;

/// A direction votes only where its extreme point's normal leans this much along it
/// (cosine): at a sharp edge or a sampled point beside the true extreme the normal is
/// oblique, but still on the right side.
pub const ORIENT_MIN_COS: f64 = 0.05;

/// What [`orient_shells`] found for one shell: how many directions said outward and inward.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Votes {
    pub right: usize,
    pub wrong: usize,
}

/// The votes of the six directions on shell `s`'s orientation (see the module docs).
pub fn shell_votes(model: &Model, s: usize) -> Votes {
    let shell = &model.shells[s];
    // Per direction: the farthest point so far and the normal there.
    let dirs = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let mut best: [Option<(f64, DVec3)>; 6] = [None; 6];
    for &fi in &shell.faces {
        let face = &model.faces[fi];
        let d = &face.domain;
        if !(d.u.0.is_finite() && d.u.1.is_finite() && d.v.0.is_finite() && d.v.1.is_finite()) {
            continue;
        }
        let trim = Trim::new(face);
        let n = ORIENT_GRID;
        for i in 0..n {
            for j in 0..n {
                // Cell centres, so no sample lies on the domain's edge.
                let u = d.u.0 + (d.u.1 - d.u.0) * (i as f64 + 0.5) / n as f64;
                let v = d.v.0 + (d.v.1 - d.v.0) * (j as f64 + 0.5) / n as f64;
                if !trim.contains(face, DVec2::new(u, v)) {
                    continue;
                }
                let p = surface_point(&face.surface, u, v);
                let Some(normal) = face_normal(face, (u, v)) else {
                    continue;
                };
                if !p.is_finite() {
                    continue;
                }
                for (k, e) in dirs.iter().enumerate() {
                    let h = p.dot(*e);
                    if best[k].is_none_or(|(b, _)| h > b) {
                        best[k] = Some((h, normal));
                    }
                }
            }
        }
    }
    let void = shell.is_void;
    let mut votes = Votes::default();
    for (k, e) in dirs.iter().enumerate() {
        let Some((_, n)) = best[k] else { continue };
        let c = n.dot(*e);
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
