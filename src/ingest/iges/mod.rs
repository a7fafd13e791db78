//! IGES 5.3 ingestion into our [`Model`].
//!
//! Three layers:
//! - [`format`]: the fixed 80-column file (sections, Global section, Directory Entries,
//!   Parameter Data with Hollerith strings), with errors naming the line or the DE;
//! - geometry: [`curve`]s (100, 102, 104, 110, 126) and [`surface`]s (108, 120, 122, 128,
//!   190–198) into truck geometry, [`placement`] by 124 transformations and the unit scale
//!   to mm; all entity readers share [`ctx`], the parsed file with typed parameter access and
//!   errors naming the DE;
//! - topology, two routes into the same [`Model`] the STEP reader builds:
//!   [`brep`] for manifold solid B-rep objects (186 → 514 shell → 510 face → 508 loop →
//!   504 edge list / 502 vertex list, as OpenCASCADE writes in B-rep mode; 514 shells that no
//!   186 uses are solids of their own), and [`sew`] for
//!   a "soup" of trimmed surfaces (144 with 142 boundaries, as FreeCAD writes), which are
//!   sewn into closed shells by matching their boundary curves. Both place an edge's
//!   vertices on its curve with [`segment`].
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
mod ctx;
mod curve;
mod finish;
pub mod format;
mod placement;
mod segment;
mod sew;
mod surface;

use crate::error::Result;
use crate::model::*;
use ctx::{model_err, Ctx};
use format::IgesFile;
use glam::DVec3;
use std::path::Path;

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
    // IGES's columns and Hollerith counts are in bytes. Names written in UTF-8 or Latin-1
    // (Inventor's `8HSólido1`) have bytes outside ASCII: each becomes a `?`, which keeps every
    // column and count; anywhere but inside a string it is then a syntax error as before.
    let first_non_ascii = bytes.iter().position(|b| !b.is_ascii());
    let ascii: std::borrow::Cow<[u8]> = match first_non_ascii {
        None => bytes.into(),
        Some(_) => bytes
            .iter()
            .map(|&b| if b.is_ascii() { b } else { b'?' })
            .collect::<Vec<u8>>()
            .into(),
    };
    let text = std::str::from_utf8(&ascii).expect("ASCII is UTF-8");
    let file = format::parse(text)
        .map_err(|reason| model_err(path, format!("not a readable IGES file: {reason}")))?;
    let (mm, unit) = file.global.unit().map_err(|r| model_err(path, r))?;
    // truck can panic on geometry no check here foresaw; that is an error, not a crash.
    let mut model =
        crate::panic_guard::catch(|| build(path, &file, mm, unit)).unwrap_or_else(|p| {
            Err(model_err(
                path,
                format!("IGES reader panicked (please report): {p}"),
            ))
        })?;
    if let Some(at) = first_non_ascii {
        let line = bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        let n = bytes.iter().filter(|b| !b.is_ascii()).count();
        let mut w = Warnings::default();
        w.add_many(
            "text",
            format!("line {line}"),
            n,
            "bytes outside ASCII (UTF-8 or Latin-1 in a name)",
            "each read as '?' (names only: the file's structure is ASCII)",
        );
        model.source.warnings.extend(w.into_vec());
    }
    Ok(model)
}

/// The model from a parsed file (see the module docs).
fn build(path: &Path, file: &IgesFile, mm: f64, unit: String) -> Result<Model> {
    let ctx = Ctx {
        file,
        path,
        mm,
        warnings: Default::default(),
    };
    let mut model = Model {
        source: SourceInfo {
            path: path.display().to_string(),
            format: "iges".into(),
            file_unit: unit,
            mm_per_unit: mm,
            warnings: vec![],
        },
        solids: vec![],
        shells: vec![],
        faces: vec![],
        edges: vec![],
        vertices: vec![],
        bbox: (DVec3::ZERO, DVec3::ZERO),
    };
    let of_type = |t: i64| -> Vec<usize> {
        file.entries
            .iter()
            .filter(|e| e.entity_type == t)
            .map(|e| e.de)
            .collect()
    };
    let (solids, soup, shells) = (of_type(186), of_type(144), of_type(514));
    let (faces, bounded) = (of_type(510), of_type(143));
    // Shells found without a solid (186) to say which is a void: nested by geometry.
    let nest_shells = solids.is_empty();
    let from_shells = !solids.is_empty() || !shells.is_empty();
    if !solids.is_empty() {
        for de in solids {
            brep::build_solid(&ctx, &mut model, de)?;
        }
    } else if !shells.is_empty() {
        // Shells without a 186 (a surface model): each closed shell is a solid, or a void of
        // the one it lies in.
        for de in shells {
            ctx.warn(
                "surface_model",
                de,
                "shell (514) that no solid (186) lists",
                "read as a solid if closed (a void of the shell it lies in)",
            );
            brep::build_shell_solid(&ctx, &mut model, de)?;
        }
    } else if !soup.is_empty() {
        sew::build_soup(&ctx, &mut model, &soup)?;
    } else if !faces.is_empty() || !bounded.is_empty() {
        // Faces that no shell lists: sewn by geometry as a soup is.
        let loose: Vec<usize> = faces.iter().chain(&bounded).copied().collect();
        for &de in &loose {
            ctx.warn(
                "sewn",
                de,
                "face (510) or bounded surface (143) that no shell (514) lists",
                "sewn with the others into closed shells by its edges' geometry, as trimmed \
                 surfaces (144) are",
            );
        }
        sew::build_loose_faces(&ctx, &mut model, &loose)?;
    } else {
        return Err(model_err(
            path,
            "no solid (186), shell (514), trimmed surface (144), face (510) or bounded surface \
             (143): nothing to build a closed shell from",
        ));
    }
    if from_shells {
        // Faces the solids and shells read do not use.
        let used: std::collections::HashSet<u64> =
            model.faces.iter().map(|f| f.source_id).collect();
        for &de in faces.iter().filter(|&&de| !used.contains(&(de as u64))) {
            ctx.warn(
                "unused",
                de,
                "face (510) that no solid or shell read uses",
                "ignored",
            );
        }
    }
    finish::finish(&ctx, &mut model, nest_shells)?;
    model.source.warnings = ctx
        .warnings
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_vec();
    Ok(model)
}
