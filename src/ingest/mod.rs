//! Reading STEP and IGES files into the B-rep [`Model`].
//!
//! [`read_model`] picks the reader by the file's extension (or, for text in memory, by its
//! first record): [`step`] for STEP (ISO 10303-21), [`iges`] for IGES 5.3. Both build the same
//! [`Model`], with geometry in millimetres, and share the UV loops and face domains
//! ([`domain`]), the 4×4 transforms ([`transform`]) and the tolerances on where a file puts
//! an edge's vertices ([`tolerance`]). Every model read must then pass [`plausible`]'s checks.

mod domain;
pub mod iges;
pub mod orient;
mod plausible;
mod step;
mod tolerance;
mod transform;

pub use plausible::MAX_PART_SIZE_MM;
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
    // A FIFO would block, and a device (/dev/zero) reports no size and never ends.
    if !meta.is_file() {
        return Err(Error::Model {
            path: path.into(),
            reason: format!("is not a regular file (a device, FIFO or socket), not {what} file"),
        });
    }
    let too_big = || Error::Model {
        path: path.into(),
        reason: format!(
            "file is more than the {} MB limit",
            MAX_FILE_BYTES / (1 << 20)
        ),
    };
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_big());
    }
    // The limit applies while reading too: the file may grow between the two.
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| {
            use std::io::Read;
            f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)
        })
        .map_err(|source| Error::Io {
            path: path.into(),
            source,
        })?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_big());
    }
    read_model_from_bytes(path, &bytes)
}

/// Reads STEP or IGES text already in memory: IGES when `path` has an IGES extension or the
/// text has IGES's `S` in column 73 of its first record, STEP otherwise.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    let mut model = if is_iges_path(path) || iges::looks_like_iges(bytes) {
        iges::read_model_from_bytes(path, bytes)
    } else {
        step::read_model_from_bytes(path, bytes)
    }?;
    domain::outline_poles(&mut model);
    plausible::check_finite(path, model)
}
