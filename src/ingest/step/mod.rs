//! STEP (ISO 10303-21) ingestion into our [`Model`].
//!
//! The stages, in order:
//! - [`p21`] parses the file into ruststep's AST (points and directions kept compact);
//!   [`records`] indexes it by id;
//! - [`truck`] patches the records where truck misreads them, and [`checks`] refuses what
//!   truck would panic on or misread (reference cycles, B-spline degrees, knots);
//! - [`table`] puts the records truck converts into truck's table (the common ones as
//!   holders built directly, the rest through truck's reader);
//! - [`topology`] walks the solids by hand: `MANIFOLD_SOLID_BREP` / `BREP_WITH_VOIDS` →
//!   `CLOSED_SHELL` / `ORIENTED_CLOSED_SHELL` → `ADVANCED_FACE` (or `ORIENTED_FACE`) →
//!   `FACE_BOUND` → `EDGE_LOOP` / `VERTEX_LOOP` → `ORIENTED_EDGE` → `EDGE_CURVE` →
//!   `VERTEX_POINT`, in the [`units`] and at the assembly [`placement`]s of each solid. Only
//!   the geometry (surfaces, edge curves) is converted by truck ([`convert`]), one entity at a
//!   time, so a conversion that fails is an error naming that entity instead of a face that
//!   silently disappears;
//! - [`finish`] checks that every entity is used, numbers the model in file order and
//!   computes the UV loops and domains.
//!
//! The later stages share the file as a [`source::Source`]; errors are made in [`error`].

mod assembly;
mod checks;
mod convert;
mod error;
mod finish;
pub mod p21;
mod placement;
mod records;
mod repair;
mod source;
mod table;
mod topology;
mod truck;
mod units;

use crate::error::{Error, Result};
use crate::model::Model;
use error::model_err;
use records::Records;
use source::Source;
use std::path::Path;

/// Files larger than this are refused before parsing (the parser keeps the whole structure in
/// memory, several times the file size).
pub const MAX_FILE_BYTES: u64 = 512 * 1024 * 1024;

/// Deepest list nesting accepted. AP203/AP214 need at most 4 or 5 (a rational B-spline
/// surface's weights: a list of lists inside a complex instance).
pub const MAX_NESTING: usize = 64;

/// Reads STEP text already in memory; `path` is used in messages and the report.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    let (mut exchange, latin1_at) = parse(path, bytes)?;
    let directions = repair::normalise_directions(&mut exchange.data)
        .map_err(|(id, reason)| error::entity_err(path, id, "DIRECTION", reason))?;
    truck::patch_for_truck(&mut exchange.data);
    let recs = Records::new(&exchange.data);
    if let Some(id) = recs.repeated() {
        return Err(error::entity_err(
            path,
            id,
            recs.name(id),
            "the file defines this id more than once: which definition a reference means is \
             unknown",
        ));
    }
    let unread_cycles = checks::check_records(path, &recs)?;
    let (mut table, undecodable) = table::fill_table(&exchange.data, &recs);
    truck::cone_angles_in_radians(&mut table, &recs);
    let src = Source {
        path,
        recs: &recs,
        table: &table,
        undecodable: &undecodable,
        uncertainty_mm: units::length_uncertainty_mm(&recs),
        warnings: Default::default(),
    };
    if let Some(at) = latin1_at {
        src.warnings.lock().unwrap_or_else(|e| e.into_inner()).add(
            "text",
            format!("byte {at}"),
            "not UTF-8: strings with bytes outside ASCII",
            "strings decoded as Latin-1",
        );
    }
    if let Some(&id) = unread_cycles.first() {
        src.warn_many(
            "cycle",
            id,
            unread_cycles.len(),
            "reference cycle through entities the reader does not use",
            "ignored",
        );
    }
    if let Some((id, length)) = directions.first {
        src.warn_many(
            "direction",
            id,
            directions.count,
            &format!("DIRECTION not of length one (e.g. {length:.6})"),
            "scaled to length one",
        );
    }
    let mut model = topology::build_solids(&src)?;
    finish::finish(&src, &mut model)?;
    model.source.warnings = src.take_warnings();
    Ok(model)
}

/// The file parsed, after the checks that it is STEP text with a data section.
fn parse(path: &Path, bytes: &[u8]) -> Result<(p21::Parsed, Option<usize>)> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(model_err(path, "file is empty"));
    }
    let text = decode(bytes).map_err(|reason| Error::Syntax {
        path: path.into(),
        reason,
    })?;
    let head = text.trim_start_matches('\u{feff}').trim_start();
    if !head.starts_with("ISO-10303-21") {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "does not start with ISO-10303-21; (not a STEP file)".into(),
        });
    }
    if !text.contains("END-ISO-10303-21") {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "no END-ISO-10303-21; (file truncated?)".into(),
        });
    }
    let latin1_at = match &text {
        std::borrow::Cow::Owned(_) => bytes.iter().position(|b| !b.is_ascii()),
        std::borrow::Cow::Borrowed(_) => None,
    };
    let exchange = p21::parse(&text, MAX_NESTING).map_err(|e| Error::Syntax {
        path: path.into(),
        reason: e.to_string(),
    })?;
    if exchange.data.is_empty() {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "no DATA section".into(),
        });
    }
    Ok((exchange, latin1_at))
}

/// The file as text: UTF-8, or, where it is not, a file whose strings hold single bytes
/// outside ASCII (Windows-1252 or Latin-1 names, common from European CAD users) decoded as
/// Latin-1. Outside strings and comments the file must be ASCII: an error there names the
/// byte.
fn decode(bytes: &[u8]) -> std::result::Result<std::borrow::Cow<'_, str>, String> {
    let utf8_err = match std::str::from_utf8(bytes) {
        Ok(text) => return Ok(text.into()),
        Err(e) => e,
    };
    let (mut in_string, mut in_comment) = (false, false);
    for (k, &b) in bytes.iter().enumerate() {
        match b {
            b'\'' if !in_comment => in_string = !in_string,
            b'/' if !in_string && !in_comment && bytes.get(k + 1) == Some(&b'*') => {
                in_comment = true
            }
            b'/' if in_comment && k > 0 && bytes[k - 1] == b'*' => in_comment = false,
            _ if !b.is_ascii() && !in_string && !in_comment => {
                return Err(format!(
                    "not text (invalid UTF-8 at byte {}, and byte {k} outside ASCII is not in a \
                     string)",
                    utf8_err.valid_up_to()
                ))
            }
            _ => {}
        }
    }
    Ok(bytes
        .iter()
        .map(|&b| char::from(b))
        .collect::<String>()
        .into())
}
