//! The STEP file as the reader's later stages see it.
//!
//! [`Source`] holds its path, its records, truck's table and what truck could not decode;
//! it makes errors naming an entity and reads a record's parameters with checks.

use super::error::entity_err;
use super::records::Records;
use crate::error::{Error, Result};
use crate::model::{ReadWarning, Warnings};
use rustc_hash::FxHashMap as HashMap;
use std::path::Path;
use std::sync::Mutex;
use truck_stepio::r#in::ruststep::ast::Parameter;
use truck_stepio::r#in::Table;

/// The parsed file, indexed, and truck's table of it.
pub struct Source<'a> {
    /// The file, for messages.
    pub path: &'a Path,
    pub recs: &'a Records<'a>,
    pub table: &'a Table,
    /// Why truck could not read an entity, by id.
    pub undecodable: &'a HashMap<u64, String>,
    /// The largest distance uncertainty the file declares, in mm.
    pub uncertainty_mm: Option<f64>,
    /// What the reader repaired or ignored so far.
    pub warnings: Mutex<Warnings>,
}

impl Source<'_> {
    /// Records a repair or an omission concerning entity `id`.
    pub fn warn(&self, kind: &'static str, id: u64, problem: &str, action: &str) {
        self.warn_gap(kind, id, problem, action, None);
    }

    /// As [`Self::warn`], for a gap of `gap_mm` that was accepted.
    pub fn warn_gap(
        &self,
        kind: &'static str,
        id: u64,
        problem: &str,
        action: &str,
        gap_mm: Option<f64>,
    ) {
        let entity = format!("#{id} {}", self.recs.name(id));
        self.warnings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .add_gap(kind, entity, problem, action, gap_mm);
    }

    /// As [`Self::warn`], for `n` entities at once, the first being `id`.
    pub fn warn_many(&self, kind: &'static str, id: u64, n: usize, problem: &str, action: &str) {
        let entity = format!("#{id} {}", self.recs.name(id));
        self.warnings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .add_many(kind, entity, n, problem, action);
    }

    /// The warnings recorded, in the order first met.
    pub fn take_warnings(&self) -> Vec<ReadWarning> {
        std::mem::take(&mut *self.warnings.lock().unwrap_or_else(|e| e.into_inner())).into_vec()
    }

    /// An error naming entity `id`.
    pub fn err(&self, id: u64, reason: impl Into<String>) -> Error {
        entity_err(self.path, id, self.recs.name(id), reason)
    }

    /// Parameter `k` of entity `id`'s record, read by `read`; `what` names it in the error.
    pub fn param<T>(
        &self,
        id: u64,
        params: &[Parameter],
        k: usize,
        read: impl Fn(&Parameter) -> Option<T>,
        what: &str,
    ) -> Result<T> {
        params
            .get(k)
            .and_then(read)
            .ok_or_else(|| self.err(id, what.to_string()))
    }
}
