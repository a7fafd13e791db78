//! Where an IGES entity is: transformation matrices, unit scale, points and directions.
//!
//! An entity's transformation matrix (entity 124) is chained when a 124 points at another
//! one; the unit scale is to millimetres; points (116) and directions (123) define frames.
//!
//! Every entity is read in its definition space and moved by its own transformation and then
//! by those of the entities it is used in ([`Ctx::place`]), so the result is in millimetres
//! in model space.

use super::ctx::Ctx;
use super::format::DirEntry;
use crate::error::Result;
use crate::ingest::transform::{apply, mat_mul, Mat4, IDENTITY};
use glam::DVec3;
use truck_geometry::prelude::{Point3, Vector3};

fn apply_dir(m: &Mat4, d: DVec3) -> DVec3 {
    let r = |i: usize| m[i][0] * d.x + m[i][1] * d.y + m[i][2] * d.z;
    DVec3::new(r(0), r(1), r(2))
}

/// `p` as a truck point.
pub fn p3(p: DVec3) -> Point3 {
    Point3::new(p.x, p.y, p.z)
}

/// `p` as a truck vector.
pub fn v3(p: DVec3) -> Vector3 {
    Vector3::new(p.x, p.y, p.z)
}

/// Scales the first three columns (not the translation) of `m` by `sx, sy, sz`.
pub fn scaled(m: &Mat4, sx: f64, sy: f64, sz: f64) -> Mat4 {
    let mut r = *m;
    for row in r.iter_mut().take(3) {
        row[0] *= sx;
        row[1] *= sy;
        row[2] *= sz;
    }
    r
}

impl Ctx<'_> {
    /// The full placement of entity `e` used inside a parent whose own transformations are
    /// `outer` (definition space of the parent → model space): `S · outer · T(e)` with `S` the
    /// unit scale to mm.
    pub fn place(&self, outer: &Mat4, e: &DirEntry) -> Result<Mat4> {
        let t = self.transform_chain(e)?;
        let s = self.mm;
        Ok(mat_mul(&scaled(&IDENTITY, s, s, s), &mat_mul(outer, &t)))
    }

    /// The entity's own transformation (no units): its 124, composed with what that one
    /// points at in turn.
    pub fn transform_chain(&self, e: &DirEntry) -> Result<Mat4> {
        let mut m = IDENTITY;
        let mut next = e.transform;
        let mut from = e.de;
        let mut hops = 0;
        while next != 0 {
            hops += 1;
            if hops > 32 {
                return Err(self.err(
                    e.de,
                    "transformation matrices point at each other in a cycle",
                ));
            }
            let t = self.entry(next, from)?;
            if t.entity_type != 124 {
                return Err(self.err(
                    from,
                    format!(
                        "transformation matrix pointer to DE {next}, which is entity {}, not 124",
                        t.entity_type
                    ),
                ));
            }
            let r = self.reals(t, 0, 12, "matrix")?;
            let mine = [
                [r[0], r[1], r[2], r[3]],
                [r[4], r[5], r[6], r[7]],
                [r[8], r[9], r[10], r[11]],
                [0.0, 0.0, 0.0, 1.0],
            ];
            // The matrix a 124 points at is applied after it.
            m = mat_mul(&mine, &m);
            from = next;
            next = t.transform;
        }
        Ok(m)
    }

    /// A point entity (116) in the definition space of the entity that uses it (only its
    /// own transformation applied, no units).
    pub fn point116(&self, de: usize, from: usize) -> Result<DVec3> {
        let e = self.typed(de, from, &[116])?;
        let r = self.reals(e, 0, 3, "coordinates")?;
        Ok(apply(
            &self.transform_chain(e)?,
            DVec3::new(r[0], r[1], r[2]),
        ))
    }

    /// A direction entity (123) in the definition space of the entity that uses it (unit
    /// length).
    pub fn direction123(&self, de: usize, from: usize) -> Result<DVec3> {
        let e = self.typed(de, from, &[123])?;
        let r = self.reals(e, 0, 3, "components")?;
        apply_dir(&self.transform_chain(e)?, DVec3::new(r[0], r[1], r[2]))
            .try_normalize()
            .ok_or_else(|| self.err(de, "zero direction"))
    }
}
