//! Checks of the STEP records before truck sees them.
//!
//! They refuse what truck would panic on, overflow its stack on, or silently misread:
//! unsorted or non-finite knots, multiplicities that are not one per knot, B-spline degrees that do not match the control points and
//! knots, references to nothing, and reference cycles.

use super::error::entity_err;
use super::p21::Item;
use super::records::{as_real, params, parts_of, Records};
use crate::error::Result;
use std::path::Path;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Name, Parameter};

/// Runs every check (reference cycles first, then B-spline degrees, then knots): the first
/// offender is an error naming its entity. Returns the reference cycles that nothing reads
/// through (see [`check_acyclic`]), by one entity of each, for a warning.
pub fn check_records(path: &Path, recs: &Records) -> Result<Vec<u64>> {
    let (found, unread_cycles) = check_acyclic(recs);
    if let Some((id, entity, reason)) = found {
        return Err(entity_err(path, id, entity, reason));
    }
    if let Some((id, entity, reason)) = check_bspline_degrees(recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    if let Some((id, entity, reason)) = check_knots(recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    if let Some((id, entity, reason)) = check_radii(recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    Ok(unread_cycles)
}

/// The radii and semi-axes of the analytic curves and surfaces, by entity: (name, parameter
/// indices, label included, and whether zero is allowed).
const RADII: [(&str, &[usize], bool); 6] = [
    ("CIRCLE", &[2], false),
    ("ELLIPSE", &[2, 3], false),
    ("CYLINDRICAL_SURFACE", &[2], false),
    ("SPHERICAL_SURFACE", &[2], false),
    ("TOROIDAL_SURFACE", &[2, 3], false),
    // A cone's radius is at its placement, which may be its apex.
    ("CONICAL_SURFACE", &[2], true),
];

/// Finds a negative (or, where it makes no sense, zero) radius or semi-axis, or one that is
/// not a finite number. truck would build the curve or surface with it: a circle of radius
/// −5 is a circle of radius 5 run the other way, which is not what the file says. Returns
/// `(id, entity, reason)` for the first.
pub fn check_radii(records: &Records) -> Option<(u64, String, String)> {
    for id in records.ids_in_order() {
        let Some(rec) = records.simple(id) else {
            continue;
        };
        let Some((name, at, zero_ok)) = RADII.iter().find(|(n, _, _)| rec.name == *n) else {
            continue;
        };
        let p = params(rec);
        for &k in *at {
            let Some(r) = p.get(k).and_then(as_real) else {
                continue;
            };
            let bad = !r.is_finite() || r < 0.0 || (r == 0.0 && !zero_ok);
            if bad {
                return Some((
                    id,
                    (*name).to_string(),
                    format!("radius {r} (must be a positive number)"),
                ));
            }
        }
    }
    None
}

/// Finds a knot vector that is not non-decreasing, a non-finite knot, or knot multiplicities
/// that are not one per knot, in a B-spline record. Returns `(id, entity, reason)` for the first offender.
pub fn check_knots(records: &Records) -> Option<(u64, String, String)> {
    for id in records.ids_in_order() {
        let Some(inst) = records.get(id) else {
            continue;
        };
        for rec in parts_of(inst) {
            if !rec.name.contains("WITH_KNOTS") {
                continue;
            }
            // Multiplicity lists (integers) and knot lists (reals), in order: one of each
            // per parametric direction.
            let (mut mults, mut knot_lists) = (vec![], vec![]);
            for p in params(rec) {
                let Parameter::List(list) = p else { continue };
                if !list.is_empty() && list.iter().all(|x| matches!(x, Parameter::Integer(_))) {
                    mults.push(list.len());
                }
                if list.is_empty() || !list.iter().all(|x| matches!(x, Parameter::Real(_))) {
                    continue;
                }
                knot_lists.push(list.len());
                let knots: Vec<f64> = list.iter().filter_map(as_real).collect();
                if knots.iter().any(|k| !k.is_finite()) {
                    return Some((id, rec.name.clone(), "knot is not a finite number".into()));
                }
                if knots.windows(2).any(|w| w[1] < w[0]) {
                    return Some((id, rec.name.clone(), "knots not sorted".into()));
                }
            }
            // truck indexes the multiplicities by the knots' positions.
            if mults != knot_lists {
                return Some((
                    id,
                    rec.name.clone(),
                    format!(
                        "knot multiplicities ({mults:?} per direction) do not match the knots \
                         ({knot_lists:?})"
                    ),
                ));
            }
        }
    }
    None
}

/// Most control points of one B-spline surface: projecting onto a net costs time in
/// proportion to its size (a 1000 × 1000 net kept the reader busy for 329 s), and CAD
/// exporters' faces stay far below this (the corpus's largest is a few hundred).
pub const MAX_SURFACE_CONTROL_POINTS: usize = 40_000;

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
        let Some((name, dirs)) = bspline_directions(inst) else {
            continue;
        };
        if let [(_, Some(nu), _), (_, Some(nv), _)] = dirs[..] {
            if nu.saturating_mul(nv) > MAX_SURFACE_CONTROL_POINTS {
                return Some((
                    id,
                    name.into(),
                    format!(
                        "control net of {nu} × {nv} points, more than the {MAX_SURFACE_CONTROL_POINTS} \
                         supported (finding points on it would take minutes)"
                    ),
                ));
            }
        }
        for dir in dirs {
            if let Some(reason) = direction_error(dir) {
                return Some((id, name.into(), reason));
            }
        }
    }
    None
}

/// The entity name a B-spline instance is reported by, and its parametric directions; `None`
/// when the instance is not a B-spline with knots in a form the check reads.
fn bspline_directions(inst: &EntityInstance) -> Option<(&'static str, Vec<BsplineDirection>)> {
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
    if let Some(p) = find("B_SPLINE_CURVE_WITH_KNOTS").filter(|p| p.len() >= 7) {
        // Simple: degree, points, form, closed, self-intersect, mults, knots, spec.
        Some((
            "B_SPLINE_CURVE_WITH_KNOTS",
            vec![(int(&p[0]), list_len(&p[1]), multiplicities(&p[5]))],
        ))
    } else if let (Some(c), Some(k)) = (find("B_SPLINE_CURVE"), find("B_SPLINE_CURVE_WITH_KNOTS")) {
        if c.len() < 2 || k.is_empty() {
            return None;
        }
        Some((
            "B_SPLINE_CURVE",
            vec![(int(&c[0]), list_len(&c[1]), multiplicities(&k[0]))],
        ))
    } else if let Some(p) = find("B_SPLINE_SURFACE_WITH_KNOTS").filter(|p| p.len() >= 10) {
        // Simple: u and v degree, points, form, u/v closed, self-intersect, u and v mults, u
        // and v knots, spec.
        Some((
            "B_SPLINE_SURFACE_WITH_KNOTS",
            vec![
                (int(&p[0]), list_len(&p[2]), multiplicities(&p[7])),
                (int(&p[1]), inner_len(&p[2]), multiplicities(&p[8])),
            ],
        ))
    } else if let (Some(c), Some(k)) = (
        find("B_SPLINE_SURFACE"),
        find("B_SPLINE_SURFACE_WITH_KNOTS"),
    ) {
        if c.len() < 3 || k.len() < 2 {
            return None;
        }
        Some((
            "B_SPLINE_SURFACE",
            vec![
                (int(&c[0]), list_len(&c[2]), multiplicities(&k[0])),
                (int(&c[1]), inner_len(&c[2]), multiplicities(&k[1])),
            ],
        ))
    } else {
        None
    }
}

/// What is wrong with one direction of a B-spline, if anything the record says is: a
/// multiplicity below 1, a degree out of range, or multiplicities that do not sum to control
/// points + degree + 1.
fn direction_error(dir: BsplineDirection) -> Option<String> {
    let (Some(d), Some(n), Some((m, lowest))) = dir else {
        return None;
    };
    if lowest < 1 {
        return Some(format!("knot multiplicity {lowest} (must be at least 1)"));
    }
    if !(1..=MAX_BSPLINE_DEGREE).contains(&d) {
        return Some(format!("degree {d} (1 to {MAX_BSPLINE_DEGREE} supported)"));
    }
    if m != n as i128 + i128::from(d) + 1 {
        return Some(format!(
            "degree {d} with {n} control points needs knot multiplicities summing to {}, not {m}",
            n as i64 + d + 1
        ));
    }
    None
}

/// An integer parameter.
fn int(p: &Parameter) -> Option<i64> {
    match p {
        Parameter::Integer(i) => Some(*i),
        _ => None,
    }
}

/// The length of a list parameter.
fn list_len(p: &Parameter) -> Option<usize> {
    match p {
        Parameter::List(l) => Some(l.len()),
        _ => None,
    }
}

/// The length of the first list in a list of lists (a surface's control points in v).
fn inner_len(p: &Parameter) -> Option<usize> {
    match p {
        Parameter::List(l) => l.first().and_then(list_len),
        _ => None,
    }
}

/// The sum and the smallest of a list of knot multiplicities.
fn multiplicities(p: &Parameter) -> Option<(i128, i64)> {
    match p {
        Parameter::List(l) => l.iter().try_fold((0i128, i64::MAX), |(s, lo), q| {
            int(q).map(|m| (s + i128::from(m), lo.min(m)))
        }),
        _ => None,
    }
}

/// Finds a reference to an id that does not exist, or a reference cycle that a reader would
/// follow round: `(id, entity, reason)`, with the entities (one of each) of the cycles that
/// nothing follows.
///
/// A cycle is an error when each of its entities is one truck reads (whose conversion
/// recurses through references: it would overflow its stack), a complex instance or a point
/// (truck reads them all), or a definitional representation's context. A cycle through
/// anything else is never followed round — the reader's own walks of the topology, the
/// assembly and the placements go a fixed depth or are bounded — and is harmless: a
/// Datakit/Open CASCADE file of the CAx-IF (`dm1-oc-214`) has `#3381 =
/// REPRESENTATION('density',(#3381),#1454)`, a material property whose items hold itself,
/// and was refused for it.
pub fn check_acyclic(records: &Records) -> (Option<(u64, String, String)>, Vec<u64>) {
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
    for (pos, item) in records.items_by_position().iter().enumerate() {
        if let Some(name) = refs_of(item, &mut flat) {
            other.insert(pos, name);
        }
        first.push(flat.len());
    }
    let refs = |pos: usize| &flat[first[pos]..first[pos + 1]];
    let contexts = super::truck::definitional_contexts(records);
    let followed: Vec<bool> = records
        .items_by_position()
        .iter()
        .map(|item| match item {
            Item::Instance(EntityInstance::Simple { id, record }) => {
                super::truck::truck_reads(&record.name) || contexts.contains(id)
            }
            Item::Instance(EntityInstance::Complex { .. }) | Item::Point(_) => true,
        })
        .collect();
    let mut unread_cycles = Vec::new();
    // Iterative three-colour depth-first search. Colours are kept by file position (dense);
    // the children still to visit of every node on the path share one stack.
    let mut state = vec![0u8; n]; // 0 = new, 1 = on the path, 2 = done
    let mut path: Vec<(u64, usize, usize)> = Vec::new(); // (id, position, children start)
    let mut pending: Vec<u64> = Vec::new();
    for root in records.ids_in_order() {
        let Some((pos, _)) = records.get_indexed(root) else {
            return (None, unread_cycles);
        };
        if state[pos] != 0 {
            continue;
        }
        state[pos] = 1;
        if let Some(name) = other.get(&pos) {
            return (unsupported(root, name.clone()), unread_cycles);
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
                let why = format!("refers to #{child}, which the file does not define");
                return (Some((id, records.name(id), why)), unread_cycles);
            };
            match state[cpos] {
                2 => {}
                1 => {
                    // The cycle: the path from `child` to here.
                    let from = path
                        .iter()
                        .rposition(|&(_, p, _)| p == cpos)
                        .expect("a node on the path");
                    if path[from..].iter().all(|&(_, p, _)| followed[p]) {
                        let why = format!("reference cycle through #{id}");
                        return (Some((child, records.name(child), why)), unread_cycles);
                    }
                    unread_cycles.push(child);
                }
                _ => {
                    state[cpos] = 1;
                    if let Some(name) = other.get(&cpos) {
                        return (unsupported(child, name.clone()), unread_cycles);
                    }
                    path.push((child, cpos, pending.len()));
                    pending.extend_from_slice(refs(cpos));
                }
            }
        }
    }
    (None, unread_cycles)
}
