//! Raw access to a parsed STEP exchange structure: records by id, parameters, and the
//! pre-processing truck needs before it sees the data.
//!
//! truck-stepio's `Table` converts geometry well, but it drops or misreads several things
//! (DESIGN.md, "The truck toolkit"). Here we work on the parsed records directly:
//! - [`patch_for_truck`] rewrites `SURFACE_CURVE`/`SEAM_CURVE` master representations to
//!   `.CURVE_3D.` (truck otherwise uses the 2D pcurve and drops the exact 3D curve) and drops
//!   their pcurves (truck would convert each with its surface, for nothing), and makes
//!   `EDGE_CURVE`s that point at a `TRIMMED_CURVE` point at its basis curve (the edge's
//!   vertices trim it anyway; truck does not read `TRIMMED_CURVE`);
//! - [`check_knots`] rejects unsorted knot vectors, on which truck panics;
//! - [`check_acyclic`] rejects reference cycles, on which any recursive reader overflows;
//! - [`length_units`] and [`placements`] recover units and assembly transforms, and
//!   [`plane_angle_factor`] the angle unit (truck reads cones' semi-angles as radians).

use super::p21::{CompactPoint, Item, PointKind, Section};
use glam::DVec3;
use rustc_hash::FxHashMap;
use ruststep::ast::{EntityInstance, Name, Parameter, Record};
use std::collections::HashMap;
use truck_geometry::prelude::{Matrix4, Transformed};
use truck_stepio::r#in::ruststep;

/// Index of the records of a data section by STEP id.
pub struct Records<'a> {
    /// Each id's position in the file and instance.
    by_id: ById<'a>,
    /// Every id, in file order.
    order: Vec<u64>,
    /// Every instance by its position in the file, repeated ids included.
    by_position: Vec<&'a Item>,
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

pub use super::transform::{apply, mat_mul, placed, rigid_inverse, to_matrix4, Mat4, IDENTITY};

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
        for (i, item) in items().enumerate() {
            let id = item.id();
            // A repeated id: the last definition wins, as in the index.
            if by_id.insert(id, (i, item)) {
                order.push(id);
            }
        }
        Records {
            by_id,
            order,
            by_position,
        }
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

/// Radians per unit of the file's plane-angle unit (`CONVERSION_BASED_UNIT('DEGREE', …)`
/// gives π/180); 1 when the file uses radians or says nothing.
pub fn plane_angle_factor(records: &Records) -> f64 {
    for id in records.ids_in_order() {
        if !records.is(id, "PLANE_ANGLE_UNIT") {
            continue;
        }
        let Some(conv) = records.complex_part(id, "CONVERSION_BASED_UNIT") else {
            continue;
        };
        let Some(measure) = params(conv).get(1).and_then(as_ref) else {
            continue;
        };
        let rec = records
            .simple(measure)
            .or_else(|| records.complex_part(measure, "MEASURE_WITH_UNIT"));
        if let Some(v) = rec.and_then(|r| params(r).first()).and_then(as_real) {
            if v.is_finite() && v > 0.0 {
                return v;
            }
        }
    }
    1.0
}

/// Rewrites what truck misreads (see the module docs). Returns the number of records changed.
pub fn patch_for_truck(sections: &mut [Section]) -> usize {
    // One pass for what the rewriting needs to know: the largest id, the basis curve of every
    // TRIMMED_CURVE, and whether some placement leaves its x axis out.
    let mut max_id = 0;
    let mut trimmed_basis: HashMap<u64, u64> = HashMap::new();
    let mut implicit_x = false;
    for item in sections.iter().flat_map(|s| &s.entities) {
        max_id = max_id.max(item.id());
        if let Item::Instance(EntityInstance::Simple { id, record }) = item {
            match record.name.as_str() {
                "TRIMMED_CURVE" => {
                    if let Some(basis) = params(record).get(1).and_then(as_ref) {
                        trimmed_basis.insert(*id, basis);
                    }
                }
                "AXIS2_PLACEMENT_3D" => {
                    implicit_x |= matches!(params(record).get(3), Some(Parameter::NotProvided));
                }
                _ => {}
            }
        }
    }
    // Directions, to repair placements whose implicit x axis is degenerate (only collected
    // when some placement leaves its x axis out).
    let mut directions: HashMap<u64, [f64; 3]> = HashMap::new();
    if implicit_x {
        let records = Records::new(sections);
        for id in records.ids_in_order() {
            if let Some(c) = records.coordinates(id, PointKind::Direction) {
                if c.len() == 3 {
                    directions.insert(id, [c[0], c[1], c[2]]);
                }
            }
        }
    }
    let mut new_directions: Vec<(u64, [f64; 3])> = Vec::new();
    let mut changed = 0;
    for item in sections.iter_mut().flat_map(|s| &mut s.entities) {
        let Item::Instance(EntityInstance::Simple { record, .. }) = item else {
            continue;
        };
        let Parameter::List(list) = &mut record.parameter else {
            continue;
        };
        // truck reads every entity's name as a string; some writers (Rhino) put `$` there.
        if let Some(first @ Parameter::NotProvided) = list.first_mut() {
            if truck_reads(&record.name) {
                *first = Parameter::String(String::new());
                changed += 1;
            }
        }
        match record.name.as_str() {
            // ISO 10303-42 takes x = (1,0,0) when ref_direction is omitted, which is
            // degenerate when the axis is ±x; truck then builds NaN frames. Give such
            // placements OCCT's choice of x axis explicitly.
            "AXIS2_PLACEMENT_3D" if matches!(list.get(3), Some(Parameter::NotProvided)) => {
                let z = list
                    .get(2)
                    .and_then(as_ref)
                    .and_then(|d| directions.get(&d));
                if let Some(z) = z {
                    let n = (z[0] * z[0] + z[1] * z[1] + z[2] * z[2]).sqrt();
                    if n > 0.0 && (z[0] / n).abs() > 1.0 - 1e-9 {
                        max_id += 1;
                        let x = [-z[2] / n, 0.0, z[0] / n];
                        let x = if x[0].abs() + x[2].abs() > 0.5 {
                            x
                        } else {
                            [0.0, 1.0, 0.0]
                        };
                        new_directions.push((max_id, x));
                        list[3] = Parameter::Ref(Name::Entity(max_id));
                        changed += 1;
                    }
                }
            }
            "SURFACE_CURVE" | "SEAM_CURVE" => {
                if let Some(Parameter::Enumeration(e)) = list.last_mut() {
                    if e != "CURVE_3D" {
                        *e = "CURVE_3D".into();
                        changed += 1;
                    }
                }
                // With the 3D curve as the master, truck has no use for the pcurves, but it
                // would still convert each one with its whole surface (a degree-13 patch
                // per pcurve: 10 % of reading the M6 screw).
                if let Some(Parameter::List(associated)) = list.get_mut(2) {
                    if !associated.is_empty() {
                        associated.clear();
                        changed += 1;
                    }
                }
            }
            "EDGE_CURVE" => {
                if let Some(p) = list.get_mut(3) {
                    // Follow chains of trimmed curves down to the basis curve.
                    let mut hops = 0;
                    while let Some(basis) = as_ref(p).and_then(|id| trimmed_basis.get(&id)) {
                        *p = Parameter::Ref(Name::Entity(*basis));
                        changed += 1;
                        hops += 1;
                        if hops > 16 {
                            break;
                        }
                    }
                }
            }
            _ => {}
        }
    }
    if let Some(section) = sections.first_mut() {
        for (id, x) in new_directions {
            section.entities.push(Item::Point(CompactPoint::new(
                id,
                PointKind::Direction,
                String::new(),
                &x,
            )));
        }
    }
    changed
}

/// Finds a knot vector that is not non-decreasing, or a non-finite real anywhere in a
/// B-spline record. Returns `(id, entity, reason)` for the first offender.
pub fn check_knots(records: &Records) -> Option<(u64, String, String)> {
    for id in records.ids_in_order() {
        let Some(inst) = records.get(id) else {
            continue;
        };
        for rec in parts_of(inst) {
            if !rec.name.contains("WITH_KNOTS") {
                continue;
            }
            for p in params(rec) {
                let Parameter::List(list) = p else { continue };
                if list.is_empty() || !list.iter().all(|x| matches!(x, Parameter::Real(_))) {
                    continue;
                }
                let knots: Vec<f64> = list.iter().filter_map(as_real).collect();
                if knots.iter().any(|k| !k.is_finite()) {
                    return Some((id, rec.name.clone(), "knot is not a finite number".into()));
                }
                if knots.windows(2).any(|w| w[1] < w[0]) {
                    return Some((id, rec.name.clone(), "knots not sorted".into()));
                }
            }
        }
    }
    None
}

/// Highest B-spline degree accepted (OpenCASCADE's limit is 25).
pub const MAX_BSPLINE_DEGREE: i64 = 25;

/// One parametric direction of a B-spline: declared degree, number of control points, and the
/// sum and smallest of the knot multiplicities (each `None` where the record does not say).
/// The sum is i128 so that no list of i64 multiplicities can wrap around to a plausible total.
type BsplineDirection = (Option<i64>, Option<usize>, Option<(i128, i64)>);

/// Finds a B-spline curve or surface whose declared degree is absurd or does not match its
/// control points and knot multiplicities (`Σ multiplicities = control points + degree + 1`
/// in each direction). truck derives the degree from the knots and would silently use another
/// curve than the file states. Simple and complex (rational) instances. Returns
/// `(id, entity, reason)`.
pub fn check_bspline_degrees(records: &Records) -> Option<(u64, String, String)> {
    let int = |p: &Parameter| match p {
        Parameter::Integer(i) => Some(*i),
        _ => None,
    };
    let list_len = |p: &Parameter| match p {
        Parameter::List(l) => Some(l.len()),
        _ => None,
    };
    let inner_len = |p: &Parameter| match p {
        Parameter::List(l) => l.first().and_then(list_len),
        _ => None,
    };
    let sum = |p: &Parameter| match p {
        Parameter::List(l) => l.iter().try_fold((0i128, i64::MAX), |(s, lo), q| {
            int(q).map(|m| (s + i128::from(m), lo.min(m)))
        }),
        _ => None,
    };
    for id in records.ids_in_order() {
        let Some(inst) = records.get(id) else {
            continue;
        };
        if !parts_of(inst)
            .iter()
            .any(|r| r.name.starts_with("B_SPLINE_"))
        {
            continue;
        }
        // (name, parameters without the label) of each part.
        let parts: Vec<(&str, &[Parameter])> = match inst {
            EntityInstance::Simple { record, .. } => {
                let ps = params(record);
                vec![(record.name.as_str(), ps.get(1..).unwrap_or(&[]))]
            }
            EntityInstance::Complex { subsuper, .. } => subsuper
                .0
                .iter()
                .map(|r| (r.name.as_str(), params(r)))
                .collect(),
        };
        let find = |n: &str| parts.iter().find(|(name, _)| *name == n).map(|(_, p)| *p);
        // Per direction: (degree, control points, sum of knot multiplicities).
        let (name, dirs): (&str, Vec<BsplineDirection>) =
            if let Some(p) = find("B_SPLINE_CURVE_WITH_KNOTS").filter(|p| p.len() >= 7) {
                // Simple: degree, points, form, closed, self-intersect, mults, knots, spec.
                (
                    "B_SPLINE_CURVE_WITH_KNOTS",
                    vec![(int(&p[0]), list_len(&p[1]), sum(&p[5]))],
                )
            } else if let (Some(c), Some(k)) =
                (find("B_SPLINE_CURVE"), find("B_SPLINE_CURVE_WITH_KNOTS"))
            {
                if c.len() < 2 || k.is_empty() {
                    continue;
                }
                (
                    "B_SPLINE_CURVE",
                    vec![(int(&c[0]), list_len(&c[1]), sum(&k[0]))],
                )
            } else if let Some(p) = find("B_SPLINE_SURFACE_WITH_KNOTS").filter(|p| p.len() >= 10) {
                // Simple: u and v degree, points, form, u/v closed, self-intersect, u and v
                // mults, u and v knots, spec.
                (
                    "B_SPLINE_SURFACE_WITH_KNOTS",
                    vec![
                        (int(&p[0]), list_len(&p[2]), sum(&p[7])),
                        (int(&p[1]), inner_len(&p[2]), sum(&p[8])),
                    ],
                )
            } else if let (Some(c), Some(k)) = (
                find("B_SPLINE_SURFACE"),
                find("B_SPLINE_SURFACE_WITH_KNOTS"),
            ) {
                if c.len() < 3 || k.len() < 2 {
                    continue;
                }
                (
                    "B_SPLINE_SURFACE",
                    vec![
                        (int(&c[0]), list_len(&c[2]), sum(&k[0])),
                        (int(&c[1]), inner_len(&c[2]), sum(&k[1])),
                    ],
                )
            } else {
                continue;
            };
        for dir in dirs {
            let (Some(d), Some(n), Some((m, lowest))) = dir else {
                continue;
            };
            if lowest < 1 {
                return Some((
                    id,
                    name.into(),
                    format!("knot multiplicity {lowest} (must be at least 1)"),
                ));
            }
            if !(1..=MAX_BSPLINE_DEGREE).contains(&d) {
                return Some((
                    id,
                    name.into(),
                    format!("degree {d} (1 to {MAX_BSPLINE_DEGREE} supported)"),
                ));
            }
            if m != n as i128 + i128::from(d) + 1 {
                return Some((
                    id,
                    name.into(),
                    format!(
                        "degree {d} with {n} control points needs knot multiplicities summing to {}, not {m}",
                        n as i64 + d + 1
                    ),
                ));
            }
        }
    }
    None
}

/// Finds a reference to an id that does not exist, or a reference cycle. Returns
/// `(id, entity, reason)`.
pub fn check_acyclic(records: &Records) -> Option<(u64, String, String)> {
    /// Pushes the entity references of `inst`; the first reference to something else (a
    /// constant `#NAME` or a value instance `@3`, on which truck panics) is returned.
    fn refs_of(item: &Item, out: &mut Vec<u64>) -> Option<String> {
        fn walk(p: &Parameter, out: &mut Vec<u64>, other: &mut Option<String>) {
            match p {
                Parameter::Ref(Name::Entity(id)) => out.push(*id),
                Parameter::Ref(name) => {
                    other.get_or_insert_with(|| match name {
                        Name::Value(v) => format!("@{v}"),
                        Name::ConstantEntity(c) => format!("#{c}"),
                        Name::ConstantValue(c) => format!("@{c}"),
                        Name::Entity(id) => format!("#{id}"),
                    });
                }
                Parameter::List(l) => l.iter().for_each(|q| walk(q, out, other)),
                Parameter::Typed { parameter, .. } => walk(parameter, out, other),
                _ => {}
            }
        }
        let mut other = None;
        if let Item::Instance(inst) = item {
            for r in parts_of(inst) {
                walk(&r.parameter, out, &mut other);
            }
        }
        other
    }
    let unsupported = |id: u64, name: String| {
        Some((
            id,
            records.name(id),
            format!("refers to {name}: constant and value-instance names are not supported"),
        ))
    };
    // Every instance's references, gathered in file order (the parsed records lie in memory
    // about in that order; the search below would visit them out of order): `refs[k]` for
    // the instance at position `k` is `flat[first[k]..first[k + 1]]`.
    let n = records.positions();
    let mut first = Vec::with_capacity(n + 1);
    let mut flat: Vec<u64> = Vec::with_capacity(4 * n);
    let mut other: rustc_hash::FxHashMap<usize, String> = Default::default();
    first.push(0);
    for (pos, item) in records.by_position.iter().enumerate() {
        if let Some(name) = refs_of(item, &mut flat) {
            other.insert(pos, name);
        }
        first.push(flat.len());
    }
    let refs = |pos: usize| &flat[first[pos]..first[pos + 1]];
    // Iterative three-colour depth-first search. Colours are kept by file position (dense);
    // the children still to visit of every node on the path share one stack.
    let mut state = vec![0u8; n]; // 0 = new, 1 = on the path, 2 = done
    let mut path: Vec<(u64, usize, usize)> = Vec::new(); // (id, position, children start)
    let mut pending: Vec<u64> = Vec::new();
    for root in records.ids_in_order() {
        let (pos, _) = records.get_indexed(root)?;
        if state[pos] != 0 {
            continue;
        }
        state[pos] = 1;
        if let Some(name) = other.get(&pos) {
            return unsupported(root, name.clone());
        }
        path.push((root, pos, pending.len()));
        pending.extend_from_slice(refs(pos));
        while let Some(&(id, pos, start)) = path.last() {
            if pending.len() == start {
                state[pos] = 2;
                path.pop();
                continue;
            }
            let child = pending.pop().expect("a pending child");
            let Some((cpos, _)) = records.get_indexed(child) else {
                return Some((
                    id,
                    records.name(id),
                    format!("refers to #{child}, which the file does not define"),
                ));
            };
            match state[cpos] {
                2 => {}
                1 => {
                    return Some((
                        child,
                        records.name(child),
                        format!("reference cycle through #{id}"),
                    ))
                }
                _ => {
                    state[cpos] = 1;
                    if let Some(name) = other.get(&cpos) {
                        return unsupported(child, name.clone());
                    }
                    path.push((child, cpos, pending.len()));
                    pending.extend_from_slice(refs(cpos));
                }
            }
        }
    }
    None
}

/// The simple entities truck-stepio 0.3's `Table::push_instance` reads into its tables are
/// these and [`WALKED_TOPOLOGY`] (see [`truck_reads`]); it keeps every other simple entity as
/// a `Dummy` holding the record's `Debug` text. Each one's first attribute is a label truck
/// insists on reading as a string. These are the ones the reader has truck convert (the
/// geometry, with the vertices and edge curves that trim it, and the 2D curves' contexts).
pub const TRUCK_CONVERTED: [&str; 34] = [
    "CARTESIAN_POINT",
    "DIRECTION",
    "VECTOR",
    "PLACEMENT",
    "AXIS1_PLACEMENT",
    "AXIS2_PLACEMENT_2D",
    "AXIS2_PLACEMENT_3D",
    "LINE",
    "POLYLINE",
    "B_SPLINE_CURVE_WITH_KNOTS",
    "BEZIER_CURVE",
    "QUASI_UNIFORM_CURVE",
    "UNIFORM_CURVE",
    "CIRCLE",
    "ELLIPSE",
    "HYPERBOLA",
    "PARABOLA",
    "PCURVE",
    "SURFACE_CURVE",
    "SEAM_CURVE",
    "PLANE",
    "SPHERICAL_SURFACE",
    "CYLINDRICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "CONICAL_SURFACE",
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
    "BEZIER_SURFACE",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "SURFACE_OF_REVOLUTION",
    "VERTEX_POINT",
    "EDGE_CURVE",
    "DEFINITIONAL_REPRESENTATION",
];

/// The topology truck reads but the reader never asks it for: [`super::step`] walks faces,
/// loops and shells itself and converts only surfaces and edge curves (with their vertices)
/// through truck, so these are not pushed into truck's table (pushing them was 3 % of
/// reading the NIST parts).
pub const WALKED_TOPOLOGY: [&str; 11] = [
    "ORIENTED_EDGE",
    "EDGE_LOOP",
    "FACE_BOUND",
    "FACE_OUTER_BOUND",
    "FACE_SURFACE",
    "ADVANCED_FACE",
    "ORIENTED_FACE",
    "OPEN_SHELL",
    "CLOSED_SHELL",
    "ORIENTED_OPEN_SHELL",
    "ORIENTED_CLOSED_SHELL",
];

/// True for the simple entities truck reads: [`TRUCK_CONVERTED`] and [`WALKED_TOPOLOGY`].
pub fn truck_reads(name: &str) -> bool {
    static READS: std::sync::LazyLock<rustc_hash::FxHashSet<&'static str>> =
        std::sync::LazyLock::new(|| TRUCK_CONVERTED.into_iter().chain(WALKED_TOPOLOGY).collect());
    READS.contains(name)
}

/// True for the simple entities the reader has truck convert ([`TRUCK_CONVERTED`]).
pub fn truck_converts(name: &str) -> bool {
    static CONVERTS: std::sync::LazyLock<rustc_hash::FxHashSet<&'static str>> =
        std::sync::LazyLock::new(|| TRUCK_CONVERTED.into_iter().collect());
    CONVERTS.contains(name)
}

/// The entities a `DEFINITIONAL_REPRESENTATION` names as its context: truck resolves them
/// among its `Dummy` records.
pub fn definitional_contexts(records: &Records) -> rustc_hash::FxHashSet<u64> {
    records
        .ids_in_order()
        .filter_map(|id| records.simple(id))
        .filter(|r| r.name == "DEFINITIONAL_REPRESENTATION")
        .filter_map(|r| params(r).get(2).and_then(as_ref))
        .collect()
}

/// A length unit: its name as the file gives it, and millimetres per unit.
#[derive(Clone, Debug, PartialEq)]
pub struct LengthUnit {
    pub name: String,
    pub mm: f64,
}

impl LengthUnit {
    /// Millimetres.
    pub fn mm() -> Self {
        LengthUnit {
            name: "mm".into(),
            mm: 1.0,
        }
    }
}

/// The length unit of the instance `id` (a complex `(LENGTH_UNIT NAMED_UNIT SI_UNIT)` or
/// `(CONVERSION_BASED_UNIT LENGTH_UNIT NAMED_UNIT)`), if it is one.
pub fn length_unit(records: &Records, id: u64, depth: usize) -> Option<Result<LengthUnit, String>> {
    if !records.is(id, "LENGTH_UNIT") || depth > 8 {
        return None;
    }
    if let Some(si) = records.complex_part(id, "SI_UNIT") {
        let p = params(si);
        let prefix = match p.first() {
            Some(Parameter::Enumeration(e)) => Some(e.as_str()),
            _ => None,
        };
        let name = match p.get(1) {
            Some(Parameter::Enumeration(e)) => e.as_str(),
            _ => "",
        };
        if name != "METRE" {
            return Some(Err(format!("length unit .{name}. is not a metre")));
        }
        let (factor, short) = match prefix {
            None => (1000.0, "m"),
            Some("MILLI") => (1.0, "mm"),
            Some("CENTI") => (10.0, "cm"),
            Some("DECI") => (100.0, "dm"),
            Some("KILO") => (1.0e6, "km"),
            Some("MICRO") => (1.0e-3, "um"),
            Some("NANO") => (1.0e-6, "nm"),
            Some("DECA") => (1.0e4, "dam"),
            Some("HECTO") => (1.0e5, "hm"),
            Some(other) => return Some(Err(format!("unsupported SI prefix .{other}."))),
        };
        return Some(Ok(LengthUnit {
            name: short.into(),
            mm: factor,
        }));
    }
    if let Some(conv) = records.complex_part(id, "CONVERSION_BASED_UNIT") {
        let p = params(conv);
        let name = p.first().map(as_string).unwrap_or_default();
        let Some(measure) = p.get(1).and_then(as_ref) else {
            return Some(Err("conversion-based unit without a measure".into()));
        };
        // LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4), #unit), simple or complex.
        let rec = records
            .simple(measure)
            .or_else(|| records.complex_part(measure, "MEASURE_WITH_UNIT"));
        let Some(rec) = rec else {
            return Some(Err(format!("#{measure} is not a measure with unit")));
        };
        let mp = params(rec);
        let (Some(value), Some(base)) = (mp.first().and_then(as_real), mp.get(1).and_then(as_ref))
        else {
            return Some(Err(format!("#{measure}: unreadable measure with unit")));
        };
        let base = match length_unit(records, base, depth + 1) {
            Some(Ok(u)) => u,
            Some(Err(e)) => return Some(Err(e)),
            None => return Some(Err(format!("#{base} is not a length unit"))),
        };
        let mm = value * base.mm;
        if !(mm.is_finite() && mm > 0.0) {
            return Some(Err(format!("conversion factor {value} is not positive")));
        }
        let short = match name.to_ascii_uppercase().as_str() {
            "INCH" => "inch".to_string(),
            "FOOT" => "foot".to_string(),
            _ => name.to_lowercase(),
        };
        return Some(Ok(LengthUnit { name: short, mm }));
    }
    Some(Err("length unit is neither SI nor conversion-based".into()))
}

/// The length unit of a representation context (`GLOBAL_UNIT_ASSIGNED_CONTEXT`).
pub fn context_length_unit(records: &Records, context: u64) -> Option<Result<LengthUnit, String>> {
    let gua = records.complex_part(context, "GLOBAL_UNIT_ASSIGNED_CONTEXT")?;
    let units = params(gua).first().and_then(as_refs)?;
    units.into_iter().find_map(|u| length_unit(records, u, 0))
}

/// Every length unit in the file (used when no context names one).
pub fn all_length_units(records: &Records) -> Vec<Result<LengthUnit, String>> {
    records
        .ids_in_order()
        .filter(|id| records.complex_part(*id, "NAMED_UNIT").is_some())
        .filter_map(|id| length_unit(records, id, 0))
        .collect()
}

/// An `AXIS2_PLACEMENT_3D` as a matrix from local to parent coordinates.
pub fn axis2_placement(records: &Records, id: u64) -> Result<Mat4, String> {
    let rec = records
        .simple(id)
        .filter(|r| r.name == "AXIS2_PLACEMENT_3D")
        .ok_or_else(|| format!("#{id} is not an AXIS2_PLACEMENT_3D"))?;
    let p = params(rec);
    let point = |id: u64, kind: PointKind| -> Result<[f64; 3], String> {
        let c = records
            .coordinates(id, kind)
            .ok_or_else(|| format!("#{id} is not a {}", kind.name()))?;
        if c.len() != 3 || c.iter().any(|x| !x.is_finite()) {
            return Err(format!(
                "#{id} {}: needs three finite coordinates",
                kind.name()
            ));
        }
        Ok([c[0], c[1], c[2]])
    };
    let loc = point(
        p.get(1)
            .and_then(as_ref)
            .ok_or("placement without location")?,
        PointKind::CartesianPoint,
    )?;
    let z = match p.get(2).and_then(as_ref) {
        Some(d) => normalize(point(d, PointKind::Direction)?).ok_or("zero axis direction")?,
        None => [0.0, 0.0, 1.0],
    };
    let xref = match p.get(3).and_then(as_ref) {
        Some(d) => point(d, PointKind::Direction)?,
        None => [1.0, 0.0, 0.0],
    };
    // x = ref_direction made orthogonal to z (ISO 10303-42 first_proj_axis).
    let d = dot(xref, z);
    let x = normalize([xref[0] - d * z[0], xref[1] - d * z[1], xref[2] - d * z[2]])
        .ok_or("ref_direction parallel to axis")?;
    let y = cross(z, x);
    Ok([
        [x[0], y[0], z[0], loc[0]],
        [x[1], y[1], z[1], loc[1]],
        [x[2], y[2], z[2], loc[2]],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = dot(a, a).sqrt();
    (n > 1e-300 && n.is_finite()).then(|| [a[0] / n, a[1] / n, a[2] / n])
}

/// A representation (`SHAPE_REPRESENTATION`, `ADVANCED_BREP_SHAPE_REPRESENTATION`, …):
/// its items and its context.
pub struct Representation {
    pub id: u64,
    pub items: Vec<u64>,
    pub context: Option<u64>,
}

/// Every representation in the file: an instance whose record (or complex part) is named
/// `*REPRESENTATION` and has (name, items, context) parameters.
pub fn representations(records: &Records) -> Vec<Representation> {
    let mut out = Vec::new();
    for id in records.ids_in_order() {
        let rec = match records.get(id) {
            Some(EntityInstance::Simple { record, .. }) => Some(record),
            Some(EntityInstance::Complex { subsuper, .. }) => subsuper
                .0
                .iter()
                .find(|r| r.name == "REPRESENTATION")
                .or_else(|| {
                    subsuper
                        .0
                        .iter()
                        .find(|r| r.name.ends_with("_REPRESENTATION") && params(r).len() == 3)
                }),
            None => None,
        };
        let Some(rec) = rec else { continue };
        if !rec.name.ends_with("REPRESENTATION") || rec.name == "DEFINITIONAL_REPRESENTATION" {
            continue;
        }
        let p = params(rec);
        if p.len() != 3 {
            continue;
        }
        let Some(items) = as_refs(&p[1]) else {
            continue;
        };
        out.push(Representation {
            id,
            items,
            context: as_ref(&p[2]),
        });
    }
    out
}

/// `(child representation, parent representation, child→parent transform)`.
pub type Link = (u64, u64, Mat4);

/// Links between representations: `(child, parent, child→parent transform)`.
///
/// `SHAPE_REPRESENTATION_RELATIONSHIP(name, desc, rep_1, rep_2)` without a transformation
/// links two views of one shape (identity; we treat `rep_1`… either way round, so both
/// directions are recorded as identity links, and the search below avoids cycles).
/// `REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION` places `rep_1` (the component) in
/// `rep_2` (the assembly) by an `ITEM_DEFINED_TRANSFORMATION(name, desc, item_1, item_2)`:
/// a point `x` of `rep_1` is `P(item_2) · P(item_1)⁻¹ · x` in `rep_2`.
pub fn representation_links(records: &Records) -> Result<Vec<Link>, (u64, String)> {
    let mut links = Vec::new();
    for id in records.ids_in_order() {
        let Some(rel) = records.complex_part(id, "REPRESENTATION_RELATIONSHIP") else {
            continue;
        };
        let p = params(rel);
        let (Some(r1), Some(r2)) = (p.get(2).and_then(as_ref), p.get(3).and_then(as_ref)) else {
            continue;
        };
        match records.complex_part(id, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION") {
            Some(with) => {
                let Some(t) = params(with).first().and_then(as_ref) else {
                    return Err((id, "transformation missing".into()));
                };
                let idt = records
                    .simple(t)
                    .filter(|r| r.name == "ITEM_DEFINED_TRANSFORMATION")
                    .ok_or((
                        t,
                        "only ITEM_DEFINED_TRANSFORMATION is supported".to_string(),
                    ))?;
                let q = params(idt);
                let (Some(i1), Some(i2)) = (q.get(2).and_then(as_ref), q.get(3).and_then(as_ref))
                else {
                    return Err((t, "transformation items missing".into()));
                };
                let p1 = axis2_placement(records, i1).map_err(|e| (t, e))?;
                let p2 = axis2_placement(records, i2).map_err(|e| (t, e))?;
                links.push((r1, r2, mat_mul(&p2, &rigid_inverse(&p1))));
            }
            None => {
                links.push((r1, r2, IDENTITY));
                links.push((r2, r1, IDENTITY));
            }
        }
    }
    Ok(links)
}

/// All placements of the representation `rep` in world coordinates: the products of the
/// transforms along every path to a root (a representation that is not placed in another by
/// a transformation). A representation that is placed nowhere has one identity placement.
pub fn placements(rep: u64, links: &[(u64, u64, Mat4)]) -> Vec<Mat4> {
    fn walk(
        rep: u64,
        acc: Mat4,
        links: &[(u64, u64, Mat4)],
        seen: &mut Vec<u64>,
        out: &mut Vec<Mat4>,
    ) {
        let ups: Vec<&(u64, u64, Mat4)> = links
            .iter()
            .filter(|(c, p, _)| *c == rep && !seen.contains(p))
            .collect();
        // Only transformed links make a new placement; identity links just move to the
        // other view of the same shape.
        let mut placed = false;
        for (_, parent, t) in ups {
            seen.push(*parent);
            let before = out.len();
            walk(*parent, mat_mul(t, &acc), links, seen, out);
            placed |= out.len() > before;
            seen.pop();
        }
        if !placed {
            out.push(acc);
        }
        if seen.len() > 64 {
            // Absurd nesting: stop rather than explode.
        }
    }
    let mut out = Vec::new();
    let mut seen = vec![rep];
    walk(rep, IDENTITY, links, &mut seen, &mut out);
    // Deduplicate placements reached along equivalent identity paths.
    let mut unique: Vec<Mat4> = Vec::new();
    for m in out {
        let same = |a: &Mat4| {
            a.iter()
                .flatten()
                .zip(m.iter().flatten())
                .all(|(x, y)| (x - y).abs() < 1e-12 * (1.0 + x.abs()))
        };
        if !unique.iter().any(same) {
            unique.push(m);
        }
    }
    unique
}

#[cfg(test)]
mod tests {
    use super::*;
    use truck_stepio::r#in::ruststep::ast::{EntityInstance, Parameter, Record};
    use truck_stepio::r#in::Table;

    fn simple(id: u64, name: &str) -> EntityInstance {
        EntityInstance::Simple {
            id,
            record: Record {
                name: name.into(),
                parameter: Parameter::List(vec![]),
            },
        }
    }

    /// The list is truck's: every name on it is read into one of truck's tables (or refused
    /// for its missing parameters), never kept as a `Dummy`; a name truck does not know is.
    /// The reader skips the names not on the list, so a name truck reads and the list lacks
    /// would lose geometry: the list was taken from `push_instance`'s match arms, and the
    /// sample and real-world tests read every kind of entity the corpus has.
    #[test]
    fn truck_simple_entities_are_the_ones_truck_does_not_keep_as_dummies() {
        for (k, name) in TRUCK_CONVERTED.iter().chain(&WALKED_TOPOLOGY).enumerate() {
            let mut table = Table::default();
            let _ = table.push_instance(&simple(k as u64 + 1, name));
            assert!(table.dummy.is_empty(), "truck keeps {name} as a dummy");
        }
        assert_eq!(
            TRUCK_CONVERTED.len() + WALKED_TOPOLOGY.len(),
            45,
            "truck reads 45 kinds"
        );
        for name in WALKED_TOPOLOGY {
            assert!(truck_reads(name) && !truck_converts(name), "{name}");
            assert!(!TRUCK_CONVERTED.contains(&name), "{name} on both lists");
        }
        for name in TRUCK_CONVERTED {
            assert!(truck_reads(name) && truck_converts(name), "{name}");
        }
        for name in [
            "STYLED_ITEM",
            "COLOUR_RGB",
            "PRODUCT",
            "SHAPE_REPRESENTATION",
        ] {
            assert!(!truck_reads(name) && !truck_converts(name));
            let mut table = Table::default();
            table.push_instance(&simple(1, name)).expect("a dummy");
            assert_eq!(table.dummy.len(), 1, "{name}");
        }
    }

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
                    .map(|&id| Item::Instance(simple(id, "CARTESIAN_POINT")))
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

    /// A placement whose axis is ±x and whose x axis is left out gets an explicit x axis, a
    /// new DIRECTION after the largest id (ISO's default x would be degenerate); one along
    /// z keeps the default.
    #[test]
    fn placements_along_x_get_an_explicit_x_axis() {
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=CARTESIAN_POINT('',(0.,0.,0.));
            #2=DIRECTION('',(-2.,0.,0.));
            #3=DIRECTION('',(0.,0.,1.));
            #9=AXIS2_PLACEMENT_3D('',#1,#2,$);
            #5=AXIS2_PLACEMENT_3D('',#1,#3,$);
            ENDSEC;END-ISO-10303-21;";
        let mut exchange = crate::ingest::p21::parse(text, 16).expect("parses");
        assert_eq!(patch_for_truck(&mut exchange.data), 1);
        let records = Records::new(&exchange.data);
        let x = |id: u64| params(records.simple(id).expect("a placement"))[3].clone();
        assert_eq!(x(9), Parameter::Ref(Name::Entity(10)));
        assert_eq!(x(5), Parameter::NotProvided);
        let c = records.coordinates(10, PointKind::Direction);
        assert_eq!(c, Some(vec![0.0, 0.0, -1.0]), "the new direction");
    }

    /// A surface curve's pcurves are dropped and its 3D curve made the master: truck then
    /// converts the exact line, where it would have taken the pcurve (here a dangling
    /// reference, which it could not have converted at all).
    #[test]
    fn surface_curves_keep_their_3d_curve_and_lose_their_pcurves() {
        use truck_stepio::r#in::alias::Curve3D;
        use truck_stepio::r#in::ruststep::ast::Name;
        use truck_stepio::r#in::ruststep::tables::{IntoOwned, PlaceHolder};
        use truck_stepio::r#in::CurveAnyHolder;
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=CARTESIAN_POINT('',(0.,0.,0.));
            #2=DIRECTION('',(1.,0.,0.));
            #3=VECTOR('',#2,2.);
            #4=LINE('',#1,#3);
            #5=SURFACE_CURVE('',#4,(#98,#99),.PCURVE_S1.);
            #6=SEAM_CURVE('',#4,(#98,#99),.PCURVE_S2.);
            ENDSEC;END-ISO-10303-21;";
        let mut exchange = crate::ingest::p21::parse(text, 16).expect("parses");
        assert_eq!(patch_for_truck(&mut exchange.data), 4);
        let mut table = Table::default();
        for item in &exchange.data[0].entities {
            table
                .push_instance(&item.to_instance())
                .expect("truck reads it");
        }
        for id in [5, 6] {
            let records = Records::new(&exchange.data);
            let p = params(records.simple(id).expect("simple"));
            assert_eq!(p[2], Parameter::List(vec![]));
            assert_eq!(p[3], Parameter::Enumeration("CURVE_3D".into()));
            let any = PlaceHolder::<CurveAnyHolder>::Ref(Name::Entity(id))
                .into_owned(&table)
                .expect("no pcurve to follow");
            let curve = Curve3D::try_from(&any).expect("converts");
            assert!(matches!(curve, Curve3D::Line(_)), "#{id}: {curve:?}");
        }
    }
}
