//! Index of a parsed STEP data section by id, and reading its records' parameters.
//!
//! [`Records`] finds an instance by id; the functions read `#id` references, reals, booleans
//! and strings from parameters.

use super::p21::{Item, PointKind, Section};
use rustc_hash::FxHashMap;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Name, Parameter, Record};

/// Index of the records of a data section by STEP id.
pub struct Records<'a> {
    /// Each id's position in the file and instance.
    by_id: ById<'a>,
    /// Every id, in file order.
    order: Vec<u64>,
    /// Every instance by its position in the file, repeated ids included.
    by_position: Vec<&'a Item>,
    /// The first id the file defines twice, if any.
    repeated: Option<u64>,
}

/// Ids are usually dense integers from 1: then a table indexed by id, which every lookup of
/// the reader (a few per reference) finds without hashing; a hash map otherwise.
enum ById<'a> {
    Dense(Vec<Option<(usize, &'a Item)>>),
    Sparse(FxHashMap<u64, (usize, &'a Item)>),
}

impl<'a> ById<'a> {
    fn get(&self, id: u64) -> Option<(usize, &'a Item)> {
        match self {
            ById::Dense(v) => usize::try_from(id)
                .ok()
                .and_then(|k| v.get(k).copied().flatten()),
            ById::Sparse(m) => m.get(&id).copied(),
        }
    }

    /// Sets `id`'s entry; true when `id` had none.
    fn insert(&mut self, id: u64, entry: (usize, &'a Item)) -> bool {
        match self {
            ById::Dense(v) => v[id as usize].replace(entry).is_none(),
            ById::Sparse(m) => m.insert(id, entry).is_none(),
        }
    }
}

/// A table indexed by id is used when the largest id is below this many times the number of
/// instances (plus a little): at most a few empty entries per instance.
const DENSE_IDS_PER_INSTANCE: usize = 4;

impl<'a> Records<'a> {
    /// Indexes every instance of `sections`.
    pub fn new(sections: &'a [Section]) -> Self {
        let n = sections.iter().map(|s| s.entities.len()).sum();
        let items = || sections.iter().flat_map(|s| &s.entities);
        let max_id = items().map(Item::id).max().unwrap_or(0);
        let mut by_id = if max_id < (DENSE_IDS_PER_INSTANCE * n + 1024) as u64 {
            ById::Dense(vec![None; max_id as usize + 1])
        } else {
            ById::Sparse(FxHashMap::with_capacity_and_hasher(n, Default::default()))
        };
        let mut order = Vec::with_capacity(n);
        let by_position: Vec<&Item> = items().collect();
        let mut repeated = None;
        for (i, item) in items().enumerate() {
            let id = item.id();
            // A repeated id: the last definition wins in the index, and the reader refuses
            // the file (see [`Self::repeated`]).
            if by_id.insert(id, (i, item)) {
                order.push(id);
            } else {
                repeated.get_or_insert(id);
            }
        }
        Records {
            by_id,
            order,
            by_position,
            repeated,
        }
    }

    /// The first id the file defines more than once: which definition a reference means
    /// cannot be known.
    pub fn repeated(&self) -> Option<u64> {
        self.repeated
    }

    /// All instance ids, in file order.
    pub fn ids_in_order(&self) -> impl Iterator<Item = u64> + '_ {
        self.order.iter().copied()
    }

    /// Position of an instance in the file (0-based), for numbering in file order.
    pub fn position(&self, id: u64) -> usize {
        self.by_id.get(id).map_or(usize::MAX, |(i, _)| i)
    }

    /// The number of instances in the file, repeated ids included (positions are below it).
    pub fn positions(&self) -> usize {
        self.by_position.len()
    }

    /// Every instance by its position in the file, repeated ids included.
    pub fn items_by_position(&self) -> &[&'a Item] {
        &self.by_position
    }

    /// The position and instance of this id.
    pub fn get_indexed(&self, id: u64) -> Option<(usize, &'a Item)> {
        self.by_id.get(id)
    }

    /// The instance with this id, unless it is a compact point (see [`Self::coordinates`]).
    pub fn get(&self, id: u64) -> Option<&'a EntityInstance> {
        match self.by_id.get(id)?.1 {
            Item::Instance(inst) => Some(inst),
            Item::Point(_) => None,
        }
    }

    /// The coordinates of the point (or direction, as `kind` says) with this id, compact or
    /// not; `None` when `id` is not one. Coordinates that are not numbers are left out.
    pub fn coordinates(&self, id: u64, kind: PointKind) -> Option<Vec<f64>> {
        match self.by_id.get(id)?.1 {
            Item::Point(p) => (p.kind == kind).then(|| p.coords().to_vec()),
            Item::Instance(EntityInstance::Simple { record, .. }) if record.name == kind.name() => {
                match params(record).get(1) {
                    Some(Parameter::List(l)) => Some(l.iter().filter_map(as_real).collect()),
                    _ => Some(vec![]),
                }
            }
            Item::Instance(_) => None,
        }
    }

    /// The record of a simple instance.
    pub fn simple(&self, id: u64) -> Option<&'a Record> {
        match self.get(id)? {
            EntityInstance::Simple { record, .. } => Some(record),
            EntityInstance::Complex { .. } => None,
        }
    }

    /// The entity name of an instance (`"ADVANCED_FACE"`; a complex instance gives its parts
    /// joined, `"(BOUNDED_SURFACE B_SPLINE_SURFACE ...)"`), or `"<missing>"`.
    pub fn name(&self, id: u64) -> String {
        match self.by_id.get(id).map(|(_, item)| item) {
            Some(Item::Instance(EntityInstance::Simple { record, .. })) => record.name.clone(),
            Some(Item::Instance(EntityInstance::Complex { subsuper, .. })) => {
                let parts: Vec<&str> = subsuper.0.iter().map(|r| r.name.as_str()).collect();
                format!("({})", parts.join(" "))
            }
            Some(Item::Point(p)) => p.kind.name().into(),
            None => "<missing>".into(),
        }
    }

    /// The part named `part` of a complex instance.
    pub fn complex_part(&self, id: u64, part: &str) -> Option<&'a Record> {
        match self.get(id)? {
            EntityInstance::Complex { subsuper, .. } => subsuper.0.iter().find(|r| r.name == part),
            EntityInstance::Simple { record, .. } => (record.name == part).then_some(record),
        }
    }

    /// True when the instance is (or, if complex, contains) an entity named `name`.
    pub fn is(&self, id: u64, name: &str) -> bool {
        self.complex_part(id, name).is_some()
    }
}

/// The records of an instance: one for a simple instance, its parts for a complex one.
pub fn parts_of(inst: &EntityInstance) -> &[Record] {
    match inst {
        EntityInstance::Simple { record, .. } => std::slice::from_ref(record),
        EntityInstance::Complex { subsuper, .. } => &subsuper.0,
    }
}

/// The id of an instance.
pub fn instance_id(inst: &EntityInstance) -> u64 {
    match inst {
        EntityInstance::Simple { id, .. } | EntityInstance::Complex { id, .. } => *id,
    }
}

/// The parameters of a record.
pub fn params(record: &Record) -> &[Parameter] {
    match &record.parameter {
        Parameter::List(list) => list,
        _ => &[],
    }
}

/// `#id` reference in a parameter.
pub fn as_ref(p: &Parameter) -> Option<u64> {
    match p {
        Parameter::Ref(Name::Entity(id)) => Some(*id),
        _ => None,
    }
}

/// A list of `#id` references.
pub fn as_refs(p: &Parameter) -> Option<Vec<u64>> {
    match p {
        Parameter::List(list) => list.iter().map(as_ref).collect(),
        _ => None,
    }
}

/// `.T.` / `.F.`.
pub fn as_bool(p: &Parameter) -> Option<bool> {
    match p {
        Parameter::Enumeration(e) if e == "T" => Some(true),
        Parameter::Enumeration(e) if e == "F" => Some(false),
        _ => None,
    }
}

/// A real (integers accepted), or a typed real such as `LENGTH_MEASURE(25.4)`.
pub fn as_real(p: &Parameter) -> Option<f64> {
    match p {
        Parameter::Real(x) => Some(*x),
        Parameter::Integer(i) => Some(*i as f64),
        Parameter::Typed { parameter, .. } => as_real(parameter),
        _ => None,
    }
}

/// A string parameter (empty for `$`).
pub fn as_string(p: &Parameter) -> String {
    match p {
        Parameter::String(s) => s.clone(),
        _ => String::new(),
    }
}

/// The `REPRESENTATION_RELATIONSHIP` part of an instance: a simple
/// `SHAPE_REPRESENTATION_RELATIONSHIP` (or `REPRESENTATION_RELATIONSHIP`), or that part of a
/// complex instance.
pub fn relationship<'a>(records: &Records<'a>, id: u64) -> Option<&'a Record> {
    match records.simple(id) {
        Some(r) => r.name.ends_with("REPRESENTATION_RELATIONSHIP").then_some(r),
        None => records.complex_part(id, "REPRESENTATION_RELATIONSHIP"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::simple_instance;

    /// Dense and sparse ids index alike: every id is found with its file position, a
    /// repeated id gives its last definition (listed once, where first defined), and an id
    /// never defined is not found.
    #[test]
    fn records_index_dense_and_sparse_ids() {
        for ids in [vec![3, 1, 2, 3], vec![7, 1_000_000_000_000, 5, 7]] {
            let section = Section {
                meta: vec![],
                entities: ids
                    .iter()
                    .map(|&id| Item::Instance(simple_instance(id, "CARTESIAN_POINT")))
                    .collect(),
            };
            let sections = [section];
            let records = Records::new(&sections);
            let dense = matches!(records.by_id, ById::Dense(_));
            assert_eq!(dense, ids[1] < 1000, "{ids:?}");
            assert_eq!(
                records.ids_in_order().collect::<Vec<_>>(),
                ids[..3].to_vec()
            );
            assert_eq!(records.position(ids[0]), 3, "the last definition");
            assert_eq!(records.position(ids[1]), 1);
            assert_eq!(records.position(ids[2]), 2);
            assert!(records.get(4).is_none() && records.get(u64::MAX).is_none());
            assert_eq!(records.positions(), 4);
        }
    }
}
