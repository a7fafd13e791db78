//! What the IGES entity readers share: the parsed file, errors, typed parameters.
//!
//! [`Ctx`] holds the parsed file with its path and unit; its errors name the Directory Entry
//! at fault, and its accessors give an entity's parameters by type.
//!
//! Every accessor checks what it reads (a missing parameter, a number where a pointer is
//! expected, a count too large for the record, a pointer to no entity) and says so in an
//! error of the form `DE 17 (entity 144, trimmed surface): reason`.

use super::format::{DirEntry, IgesFile, Token};
use crate::error::{Error, Result};
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

/// An error about the whole file (no entity to blame).
pub fn model_err(path: &Path, reason: impl Into<String>) -> Error {
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
    /// What the reader repaired or ignored so far.
    pub warnings: std::sync::Mutex<crate::model::Warnings>,
}

impl Ctx<'_> {
    /// Records a repair concerning entity `de`.
    pub fn warn(&self, kind: &'static str, de: usize, problem: &str, action: &str) {
        let t = self.file.get(de).map_or(0, |e| e.entity_type);
        self.warnings.lock().unwrap_or_else(|e| e.into_inner()).add(
            kind,
            format!("DE {de} ({t})"),
            problem,
            action,
        );
    }

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

/// Runs `f` with the context of a small IGES file holding `entities`, with unit flag `unit`
/// (see [`crate::testing::iges_file`]).
#[cfg(test)]
pub fn with_ctx<T>(
    entities: &[crate::testing::IgesEntity],
    unit: i64,
    f: impl FnOnce(&Ctx) -> T,
) -> T {
    let text = crate::testing::iges_file(entities, unit);
    let parsed = super::format::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let (mm, _) = parsed.global.unit().unwrap();
    let ctx = Ctx {
        file: &parsed,
        path: Path::new("test.igs"),
        mm,
        warnings: Default::default(),
    };
    f(&ctx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ingest::iges::segment::Segment;
    use crate::ingest::transform::IDENTITY;
    use crate::testing::IgesEntity;

    #[test]
    fn bad_entities_name_themselves() {
        // Unsorted knots, a pointer to nowhere, a wrong entity type, a short record.
        let e: Vec<IgesEntity> = vec![
            (
                126,
                0,
                0,
                "1,1,0,0,1,0,1.,0.,0.,0.,1.,1.,0.,0.,0.,1.,1.,1.,0.,1.",
            ), // DE 1
            (120, 0, 0, "99,3,0.,1."),        // DE 3
            (120, 0, 0, "5,1,0.,1."),         // DE 5
            (116, 0, 0, "0.,0."),             // DE 7
            (110, 0, 0, "0.,0.,0.,1.,1.,1."), // DE 9
            (192, 0, 0, "7,9,1."),            // DE 11
        ];
        with_ctx(&e, 2, |ctx| {
            let msg = |r: crate::Result<_>| r.map(|_: Segment| ()).unwrap_err().to_string();
            assert!(
                msg(ctx.curve(1, 1, &IDENTITY)).contains("knots are not in non-decreasing order")
            );
            let m = ctx
                .surface(3, 3, &IDENTITY)
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(
                m.contains("DE 3 (entity 120, surface of revolution): points to DE 99"),
                "{m}"
            );
            let m = ctx
                .surface(5, 5, &IDENTITY)
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(
                m.contains("surface entity type 120") || m.contains("curve entity type 120"),
                "{m}"
            );
            let m = ctx
                .surface(11, 11, &IDENTITY)
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(
                m.contains("DE 7 (entity 116, point)") && m.contains("record too short"),
                "{m}"
            );
        });
    }
}
