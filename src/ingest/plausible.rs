//! The checks every model read passes, whatever its format.
//!
//! Every coordinate must be finite (a real like `1.E400` overflows to infinity) and the part
//! no larger than a machined part can be ([`MAX_PART_SIZE_MM`]).

use crate::error::{Error, Result};
use crate::model::Model;
use std::path::Path;

/// Refuses a model with a non-finite coordinate (a real like `1.E400` overflows to infinity):
/// every vertex, and the bounding box, which samples every edge and face.
pub fn check_finite(path: &Path, model: Model) -> Result<Model> {
    let bad = model
        .vertices
        .iter()
        .position(|v| !v.point.is_finite())
        .map(|v| format!("vertex {} (#{})", v, model.vertices[v].source_id))
        .or_else(|| {
            model.edges.iter().enumerate().find_map(|(e, edge)| {
                let t = 0.5 * (edge.range.0 + edge.range.1);
                let c = crate::geom::eval_curve(&edge.curve, t);
                (!(t.is_finite() && c.p.is_finite() && c.d1.is_finite()))
                    .then(|| format!("edge {e} (#{})", edge.source_id))
            })
        })
        .or_else(|| {
            model.faces.iter().enumerate().find_map(|(f, face)| {
                let (u, v) = (
                    0.5 * (face.domain.u.0 + face.domain.u.1),
                    0.5 * (face.domain.v.0 + face.domain.v.1),
                );
                let d = crate::geom::eval_surface(&face.surface, u, v);
                (!(u.is_finite() && v.is_finite() && d.p.is_finite() && d.su.is_finite()))
                    .then(|| format!("face {f} (#{})", face.source_id))
            })
        })
        .or_else(|| {
            (!(model.bbox.0.is_finite() && model.bbox.1.is_finite()))
                .then(|| "the bounding box".to_string())
        });
    if let Some(what) = bad {
        return Err(Error::Model {
            path: path.into(),
            reason: format!("non-finite coordinate in {what}: a number overflows"),
        });
    }
    let size = model.bbox.0.distance(model.bbox.1);
    if size > MAX_PART_SIZE_MM {
        return Err(Error::Model {
            path: path.into(),
            reason: format!(
                "the part is {size:.3e} mm across, more than {MAX_PART_SIZE_MM:.0e} mm (a unit or scale error?)"
            ),
        });
    }
    Ok(model)
}

/// The largest bounding-box diagonal accepted: 10 km. Beyond it squared distances lose the
/// precision the tolerances assume, and no machined part is that large.
pub const MAX_PART_SIZE_MM: f64 = 1e7;
