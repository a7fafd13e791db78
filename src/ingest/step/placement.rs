//! STEP assembly placements.
//!
//! `AXIS2_PLACEMENT_3D` as matrices, the representations holding the solids, the transforms
//! linking them (`REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION`), and every placement of a
//! representation in world coordinates.

use super::p21::PointKind;
use super::records::{as_ref, as_refs, params, relationship, Records};
use crate::ingest::transform::{mat_mul, rigid_inverse, Mat4, IDENTITY};
use truck_stepio::r#in::ruststep::ast::EntityInstance;

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

/// When `item` is a `MAPPED_ITEM(name, REPRESENTATION_MAP(origin, mapped), target)`: the
/// representation it maps in and the transform from that representation's coordinates to its
/// own, `P(target) · P(origin)⁻¹`.
pub fn mapped_item(records: &Records, item: u64) -> Result<Option<(u64, Mat4)>, (u64, String)> {
    let Some(m) = records.simple(item).filter(|r| r.name == "MAPPED_ITEM") else {
        return Ok(None);
    };
    let p = params(m);
    let (Some(map), Some(target)) = (p.get(1).and_then(as_ref), p.get(2).and_then(as_ref)) else {
        return Err((item, "mapping source or target missing".into()));
    };
    let mp = records
        .simple(map)
        .filter(|r| r.name == "REPRESENTATION_MAP")
        .map(params)
        .ok_or((map, "expected REPRESENTATION_MAP".to_string()))?;
    let (Some(origin), Some(mapped)) = (mp.first().and_then(as_ref), mp.get(1).and_then(as_ref))
    else {
        return Err((map, "mapping origin or representation missing".into()));
    };
    let o = axis2_placement(records, origin).map_err(|e| (map, e))?;
    let t = axis2_placement(records, target).map_err(|e| (item, e))?;
    Ok(Some((mapped, mat_mul(&t, &rigid_inverse(&o)))))
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
/// A `MAPPED_ITEM(name, REPRESENTATION_MAP(origin, mapped), target)` among the items of a
/// representation `R` places `mapped` in `R` the same way: `P(target) · P(origin)⁻¹` (looked
/// for only when `mapped_items`: the file has some).
pub fn representation_links(
    records: &Records,
    reps: &[Representation],
    mapped_items: bool,
) -> Result<Vec<Link>, (u64, String)> {
    let mut links = Vec::new();
    for id in records.ids_in_order() {
        let Some(rel) = relationship(records, id) else {
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
    if mapped_items {
        for rep in reps {
            for &item in &rep.items {
                if let Some((mapped, t)) = mapped_item(records, item)? {
                    links.push((mapped, rep.id, t));
                }
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
