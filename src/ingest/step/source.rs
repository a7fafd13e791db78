//! The STEP file as the reader's later stages see it.
//!
//! [`Source`] holds its path, its records, truck's table and what truck could not decode;
//! it makes errors naming an entity and reads a record's parameters with checks.

use super::error::entity_err;
use super::records::Records;
use crate::error::{Error, Result};
use rustc_hash::FxHashMap as HashMap;
use std::path::Path;
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
}

impl Source<'_> {
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
