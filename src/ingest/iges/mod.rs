//! IGES 5.3 ingestion into our [`Model`].
//!
//! Three layers:
//! - [`format`]: the fixed 80-column file (sections, Global section, Directory Entries,
//!   Parameter Data with Hollerith strings), with errors naming the line or the DE;
//! - [`geometry`]: curves (100, 102, 104, 110, 126) and surfaces (108, 120, 122, 128,
//!   190–198) into truck geometry, with 124 transformations and the unit scale to mm;
//! - topology, two routes into the same [`Model`] the STEP reader builds:
//!   [`brep`] for manifold solid B-rep objects (186 → 514 shell → 510 face → 508 loop →
//!   504 edge list / 502 vertex list, as OpenCASCADE writes in B-rep mode; 514 shells that no
//!   186 uses are solids of their own), and [`sew`] for
//!   a "soup" of trimmed surfaces (144 with 142 boundaries, as FreeCAD writes), which are
//!   sewn into closed shells by matching their boundary curves.
//!
//! Both routes then go through [`finish`]: degenerate edges and seam-only loops (a full
//! sphere) become what the STEP reader makes of them, faces are oriented consistently across
//! shared edges and outward by the sign of the enclosed volume, and the UV loops and domains
//! are computed by the same code as for STEP (`super::domain`).
//!
//! Ids: a face's, loop's and shell's `source_id` is the DE sequence number of its 510/144, 508
//! /142 and 514 entity; an edge's is the DE of its model-space curve; a vertex's the DE of its
//! 502 vertex list (soup vertices have none: 0).

mod brep;
mod finish;
pub mod format;
mod geometry;
mod sew;
#[cfg(test)]
mod tests;

use crate::error::{Error, Result};
use crate::model::*;
use format::{DirEntry, IgesFile, Token};
use glam::DVec3;
use std::path::Path;

/// Entity names for messages.
fn entity_name(t: i64) -> &'static str {
    match t {
        100 => "circular arc",
        102 => "composite curve",
        104 => "conic arc",
        108 => "plane",
        110 => "line",
        116 => "point",
        118 => "ruled surface",
        120 => "surface of revolution",
        122 => "tabulated cylinder",
        123 => "direction",
        124 => "transformation matrix",
        126 => "rational B-spline curve",
        128 => "rational B-spline surface",
        140 => "offset surface",
        141 => "boundary",
        142 => "curve on a parametric surface",
        143 => "bounded surface",
        144 => "trimmed surface",
        186 => "manifold solid B-rep object",
        190 => "plane surface",
        192 => "right circular cylindrical surface",
        194 => "right circular conical surface",
        196 => "spherical surface",
        198 => "toroidal surface",
        402 => "associativity",
        502 => "vertex list",
        504 => "edge list",
        508 => "loop",
        510 => "face",
        514 => "shell",
        _ => "entity",
    }
}

/// True when `bytes` look like fixed-format IGES: the first record has `S` in column 73.
pub fn looks_like_iges(bytes: &[u8]) -> bool {
    let first = bytes.split(|b| *b == b'\n').next().unwrap_or(&[]);
    first.len() >= 73 && first[72] == b'S' && !bytes.starts_with(b"ISO-10303-21")
}

/// Reads IGES text already in memory; `path` is used in messages and the report.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(model_err(path, "file is empty"));
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        model_err(
            path,
            format!(
                "not a readable IGES file: not text (invalid UTF-8 at byte {})",
                e.valid_up_to()
            ),
        )
    })?;
    let file = format::parse(text)
        .map_err(|reason| model_err(path, format!("not a readable IGES file: {reason}")))?;
    let (mm, unit) = file.global.unit().map_err(|r| model_err(path, r))?;
    // truck can panic on geometry no check here foresaw; that is an error, not a crash.
    crate::panic_guard::catch(|| build(path, &file, mm, unit)).unwrap_or_else(|p| {
        Err(model_err(
            path,
            format!("IGES reader panicked (please report): {p}"),
        ))
    })
}

/// The model from a parsed file (see the module docs).
fn build(path: &Path, file: &IgesFile, mm: f64, unit: String) -> Result<Model> {
    let ctx = Ctx { file, path, mm };
    let mut model = Model {
        source: SourceInfo {
            path: path.display().to_string(),
            format: "iges".into(),
            file_unit: unit,
            mm_per_unit: mm,
        },
        solids: vec![],
        shells: vec![],
        faces: vec![],
        edges: vec![],
        vertices: vec![],
        bbox: (DVec3::ZERO, DVec3::ZERO),
    };
    let solids: Vec<usize> = file
        .entries
        .iter()
        .filter(|e| e.entity_type == 186)
        .map(|e| e.de)
        .collect();
    let soup: Vec<usize> = file
        .entries
        .iter()
        .filter(|e| e.entity_type == 144)
        .map(|e| e.de)
        .collect();
    let shells: Vec<usize> = file
        .entries
        .iter()
        .filter(|e| e.entity_type == 514)
        .map(|e| e.de)
        .collect();
    let from_soup = solids.is_empty() && shells.is_empty();
    if !solids.is_empty() {
        for de in solids {
            brep::build_solid(&ctx, &mut model, de)?;
        }
    } else if !shells.is_empty() {
        // Shells without a 186: each closed shell is a solid.
        for de in shells {
            brep::build_shell_solid(&ctx, &mut model, de)?;
        }
    } else if !soup.is_empty() {
        sew::build_soup(&ctx, &mut model, &soup)?;
    } else {
        let faces = file
            .entries
            .iter()
            .filter(|e| matches!(e.entity_type, 143 | 510))
            .count();
        let what = if faces > 0 {
            format!("no solid (186), shell (514) or trimmed surface (144); {faces} face(s) (143 / 510) not part of a shell")
        } else {
            "no solid (186), shell (514) or trimmed surface (144): nothing to build a closed shell from"
                .to_string()
        };
        return Err(model_err(path, what));
    }
    finish::finish(&ctx, &mut model, from_soup)?;
    Ok(model)
}

fn model_err(path: &Path, reason: impl Into<String>) -> Error {
    Error::Model {
        path: path.into(),
        reason: reason.into(),
    }
}

/// What the entity readers share: the parsed file, its path for messages, and the unit.
pub(crate) struct Ctx<'a> {
    pub file: &'a IgesFile,
    pub path: &'a Path,
    /// Millimetres per model-space unit.
    pub mm: f64,
}

impl Ctx<'_> {
    /// An error about entity `de`: `DE 17 (entity 144, trimmed surface): reason`.
    pub fn err(&self, de: usize, reason: impl Into<String>) -> Error {
        let t = self.file.get(de).map_or(0, |e| e.entity_type);
        model_err(
            self.path,
            format!(
                "DE {de} (entity {t}, {}): {}",
                entity_name(t),
                reason.into()
            ),
        )
    }

    /// The entity at `de`, referred to by entity `from`.
    pub fn entry(&self, de: usize, from: usize) -> Result<&DirEntry> {
        match self.file.get(de) {
            Some(e) if e.entity_type != 0 => Ok(e),
            _ => Err(self.err(
                from,
                format!(
                    "points to DE {de}, which is not the start of an entity in this file ({} DE records; dangling pointer)",
                    2 * self.file.entries.len()
                ),
            )),
        }
    }

    /// The entity at `de`, which must be one of `types`.
    pub fn typed(&self, de: usize, from: usize, types: &[i64]) -> Result<&DirEntry> {
        let e = self.entry(de, from)?;
        if types.contains(&e.entity_type) {
            Ok(e)
        } else {
            Err(self.err(
                from,
                format!(
                    "points to DE {de}, entity {} ({}), where entity {} is expected",
                    e.entity_type,
                    entity_name(e.entity_type),
                    types
                        .iter()
                        .map(|t| t.to_string())
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            ))
        }
    }

    fn param<'e>(&self, e: &'e DirEntry, k: usize, what: &str) -> Result<&'e Token> {
        e.params.get(k).ok_or_else(|| {
            self.err(
                e.de,
                format!("parameter {} ({what}) missing (record too short)", k + 1),
            )
        })
    }

    pub fn real(&self, e: &DirEntry, k: usize, what: &str) -> Result<f64> {
        let t = self.param(e, k, what)?;
        match t {
            Token::Default => Ok(0.0),
            _ => t.real().ok_or_else(|| {
                self.err(
                    e.de,
                    format!("parameter {} ({what}) is {t:?}, not a number", k + 1),
                )
            }),
        }
    }

    pub fn reals(&self, e: &DirEntry, k: usize, n: usize, what: &str) -> Result<Vec<f64>> {
        if e.params.len() < k + n {
            return Err(self.err(
                e.de,
                format!(
                    "{what}: needs parameters {}–{}, the record has {} (record too short)",
                    k + 1,
                    k + n,
                    e.params.len()
                ),
            ));
        }
        (k..k + n).map(|i| self.real(e, i, what)).collect()
    }

    pub fn int(&self, e: &DirEntry, k: usize, what: &str) -> Result<i64> {
        let t = self.param(e, k, what)?;
        match t {
            Token::Default => Ok(0),
            _ => t.int().ok_or_else(|| {
                self.err(
                    e.de,
                    format!("parameter {} ({what}) is {t:?}, not an integer", k + 1),
                )
            }),
        }
    }

    /// A count or index: a non-negative integer no larger than the number of parameters
    /// could justify (guards allocations against garbage).
    pub fn count(&self, e: &DirEntry, k: usize, what: &str) -> Result<usize> {
        let n = self.int(e, k, what)?;
        if n < 0 || n as usize > 4 * e.params.len() + 16 {
            return Err(self.err(
                e.de,
                format!("parameter {} ({what}) = {n} is out of range", k + 1),
            ));
        }
        Ok(n as usize)
    }

    /// An index into another entity's list (1-based; checked against that list by the caller).
    pub fn index(&self, e: &DirEntry, k: usize, what: &str) -> Result<usize> {
        let n = self.int(e, k, what)?;
        if n < 1 {
            return Err(self.err(
                e.de,
                format!("parameter {} ({what}) = {n}, not an index (from 1)", k + 1),
            ));
        }
        usize::try_from(n).map_err(|_| self.err(e.de, format!("{what} {n} too large")))
    }

    /// A pointer to another entity (checked to exist).
    pub fn ptr(&self, e: &DirEntry, k: usize, what: &str) -> Result<usize> {
        let p = self.int(e, k, what)?;
        if p <= 0 {
            return Err(self.err(
                e.de,
                format!(
                    "parameter {} ({what}) is {p}, not a pointer to an entity",
                    k + 1
                ),
            ));
        }
        self.entry(p as usize, e.de)?;
        Ok(p as usize)
    }
}
