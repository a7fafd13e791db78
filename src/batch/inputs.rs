//! The batch's inputs: folders searched recursively for part files, files as given,
//! deduplicated and sorted, each with its output location, names kept apart.

use super::error::BatchError;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// File extensions (lower case) a folder is searched for.
pub const EXTENSIONS: [&str; 4] = ["step", "stp", "igs", "iges"];

/// One part to trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The file, as found (a folder argument joined with the path below it, or a file
    /// argument as given).
    pub path: PathBuf,
    /// Where its outputs go, relative to the output folder, without the output suffixes:
    /// `sub/part` for `DIR/sub/part.step`, `part` for a file argument `x/part.step`. When two
    /// inputs would get the same location (compared without regard to case, as some file
    /// systems do), each of them gets `-` and 8 hex digits of the FNV-1a hash of its path
    /// appended (`part-1f0c33ab`): the same input list always gives the same names.
    pub out_rel: PathBuf,
}

impl Input {
    /// The output file stem (`out_rel`'s last component).
    pub fn stem(&self) -> String {
        self.out_rel
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "part".into())
    }

    /// The folder of the outputs inside `out_dir`.
    pub fn out_dir(&self, out_dir: &Path) -> PathBuf {
        match self.out_rel.parent() {
            Some(p) => out_dir.join(p),
            None => out_dir.to_path_buf(),
        }
    }
}

/// True when `path`'s extension is one we read.
pub fn is_part_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// The inputs named by `args` (files, or folders searched recursively), deduplicated (by
/// canonical path) and sorted by output location, then path. A file argument is taken
/// whatever its extension; an argument that does not exist is an error, as is finding nothing.
/// The folder `out_dir` is not searched (an output folder inside an input folder holds
/// `.mat.step` files, which are not parts).
pub fn collect_inputs(args: &[PathBuf], out_dir: &Path) -> Result<Vec<Input>, BatchError> {
    let skip = std::fs::canonicalize(out_dir).ok();
    let mut found: Vec<(PathBuf, PathBuf)> = vec![]; // (path, out_rel before disambiguation)
    for arg in args {
        let meta = std::fs::metadata(arg).map_err(|_| BatchError::Missing(arg.clone()))?;
        if meta.is_dir() {
            let mut files = vec![];
            walk(arg, skip.as_deref(), &mut files)?;
            for f in files {
                let rel = f.strip_prefix(arg).unwrap_or(&f).with_extension("");
                found.push((f, rel));
            }
        } else {
            let name = arg.file_stem().map(PathBuf::from).unwrap_or("part".into());
            found.push((arg.clone(), name));
        }
    }
    if found.is_empty() {
        let names: Vec<String> = args.iter().map(|a| a.display().to_string()).collect();
        return Err(BatchError::NoInputs(names.join(", ")));
    }
    found.sort();
    let mut seen = BTreeSet::new();
    found.retain(|(p, _)| seen.insert(std::fs::canonicalize(p).unwrap_or_else(|_| p.clone())));
    let mut by_key: BTreeMap<String, usize> = BTreeMap::new();
    for (_, rel) in &found {
        *by_key.entry(collision_key(rel)).or_default() += 1;
    }
    let mut inputs: Vec<Input> = found
        .into_iter()
        .map(|(path, rel)| {
            let out_rel = if by_key[&collision_key(&rel)] > 1 {
                let name = rel.file_name().unwrap_or_default().to_string_lossy();
                let hash = fnv1a(path.to_string_lossy().as_bytes());
                rel.with_file_name(format!("{name}-{:08x}", hash as u32))
            } else {
                rel
            };
            Input { path, out_rel }
        })
        .collect();
    inputs.sort_by(|a, b| (&a.out_rel, &a.path).cmp(&(&b.out_rel, &b.path)));
    Ok(inputs)
}

/// Output locations that the file system might take for the same.
fn collision_key(rel: &Path) -> String {
    rel.to_string_lossy().to_lowercase()
}

/// 64-bit FNV-1a.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Appends the part files below `dir` (recursively, symlinked folders not followed, the
/// folder `skip` (canonical) left out).
fn walk(dir: &Path, skip: Option<&Path>, out: &mut Vec<PathBuf>) -> Result<(), BatchError> {
    if skip.is_some_and(|s| std::fs::canonicalize(dir).is_ok_and(|d| d == s)) {
        return Ok(());
    }
    let entries = std::fs::read_dir(dir).map_err(|source| BatchError::ReadDir {
        path: dir.into(),
        source,
    })?;
    let mut entries: Vec<_> = entries.filter_map(|e| e.ok()).collect();
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let path = e.path();
        let Ok(kind) = e.file_type() else { continue };
        if kind.is_dir() {
            walk(&path, skip, out)?;
        } else if is_part_file(&path) && std::fs::metadata(&path).is_ok_and(|m| m.is_file()) {
            out.push(path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_are_found_sorted_and_kept_apart() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in [
            "b/part.step",
            "a/part.STEP",
            "a/part.stp",
            "z.iges",
            "a/notes.txt",
        ] {
            let p = d.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, "x").unwrap();
        }
        let extra = d.join("b/part.step");
        let none = d.join("no-output-folder");
        let inputs = collect_inputs(&[d.to_path_buf(), extra], &none).unwrap();
        let rels: Vec<String> = inputs
            .iter()
            .map(|i| i.out_rel.display().to_string())
            .collect();
        // a/part.STEP and a/part.stp collide (hashed), b/part.step is found once, notes.txt
        // is not a part.
        assert_eq!(rels.len(), 4, "{rels:?}");
        assert!(rels[0].starts_with("a/part-") && rels[1].starts_with("a/part-"));
        assert_ne!(rels[0], rels[1]);
        assert_eq!(&rels[2..], ["b/part", "z"]);
        assert_eq!(inputs, collect_inputs(&[d.to_path_buf()], &none).unwrap());
        // An output folder inside the input folder is not searched.
        let with_b: Vec<Input> = collect_inputs(&[d.to_path_buf()], &d.join("b/.")).unwrap();
        assert_eq!(with_b.len(), 3);
        assert!(with_b.iter().all(|i| !i.out_rel.starts_with("b")));
        assert!(matches!(
            collect_inputs(&[d.join("a/notes.txt").with_extension("none")], &none),
            Err(BatchError::Missing(_))
        ));
        let empty = tempfile::tempdir().unwrap();
        assert!(matches!(
            collect_inputs(&[empty.path().to_path_buf()], &none),
            Err(BatchError::NoInputs(_))
        ));
    }
}
