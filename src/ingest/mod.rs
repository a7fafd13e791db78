//! Reading STEP and IGES files into the B-rep [`Model`].

mod domain;
pub mod iges;
mod step;
mod tolerance;
mod transform;

pub use step::{p21, MAX_FILE_BYTES};

use crate::model::Model;

use crate::error::{Error, Result};
use std::path::Path;

/// True when `path` names an IGES file (`.igs` / `.iges`, any case).
pub fn is_iges_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("igs") || e.eq_ignore_ascii_case("iges"))
}

/// Reads a STEP or IGES file into a [`Model`]: IGES for the `.igs` / `.iges` extensions,
/// STEP otherwise.
///
/// Errors name the file and, where one is to blame, the entity. Nothing the file defines as
/// part of a solid is dropped: a face, edge or vertex that cannot be converted is an error.
pub fn read_model(path: &Path) -> Result<Model> {
    let meta = std::fs::metadata(path).map_err(|source| Error::Io {
        path: path.into(),
        source,
    })?;
    let what = if is_iges_path(path) {
        "an IGES"
    } else {
        "a STEP"
    };
    if meta.is_dir() {
        return Err(Error::Model {
            path: path.into(),
            reason: format!("is a directory, not {what} file"),
        });
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(Error::Model {
            path: path.into(),
            reason: format!(
                "file is {} MB, more than the {} MB limit",
                meta.len() / (1 << 20),
                MAX_FILE_BYTES / (1 << 20)
            ),
        });
    }
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.into(),
        source,
    })?;
    read_model_from_bytes(path, &bytes)
}

/// Refuses a model with a non-finite coordinate (a real like `1.E400` overflows to infinity):
/// every vertex, and the bounding box, which samples every edge and face.
fn check_finite(path: &Path, model: Model) -> Result<Model> {
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

/// Reads STEP or IGES text already in memory: IGES when `path` has an IGES extension or the
/// text has IGES's `S` in column 73 of its first record, STEP otherwise.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    let model = if is_iges_path(path) || iges::looks_like_iges(bytes) {
        iges::read_model_from_bytes(path, bytes)
    } else {
        step::read_model_from_bytes(path, bytes)
    }?;
    check_finite(path, model)
}
