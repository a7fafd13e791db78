//! STEP assemblies: which solids the product structure places, and where.
//!
//! A file with `NEXT_ASSEMBLY_USAGE_OCCURRENCE`s (NAUO) is an assembly. Its solids are found
//! by walking the product structure from each root product (one no NAUO uses as a component):
//! - a product definition's shape is the representation a `SHAPE_DEFINITION_REPRESENTATION`
//!   gives it, with every representation linked to that one by a
//!   `SHAPE_REPRESENTATION_RELATIONSHIP` without a transformation (other views of one shape),
//!   and the representations its `MAPPED_ITEM`s map in (placed by the map's origin and target);
//! - each NAUO places its component in its assembly by the `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION`
//!   naming it: a `REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION` whose
//!   `ITEM_DEFINED_TRANSFORMATION` maps an item of the component's representation onto one of
//!   the assembly's. Which of `rep_1`/`rep_2` is the component is decided by the product
//!   structure, not by the order (ISO puts the component first; SolidWorks writes the
//!   assembly first).
//!
//! Every path from a root to a solid is one placed solid, in world coordinates: a shape used
//! twice comes out twice. Solids the product structure does not reach are not read (with a
//! warning).

use super::placement::{axis2_placement, mapped_item};
use super::records::{as_ref, as_refs, as_string, params, relationship, Records};
use crate::ingest::transform::{mat_mul, rigid_inverse, Mat4, IDENTITY};
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use truck_stepio::r#in::ruststep::ast::Record;

/// Deepest assembly nesting followed (a deeper path is a cycle or absurd).
pub const MAX_ASSEMBLY_DEPTH: usize = 32;

/// Most placed solids an assembly may expand to.
pub const MAX_PLACED_SOLIDS: usize = 100_000;

/// One solid the product structure places.
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// The `MANIFOLD_SOLID_BREP` / `BREP_WITH_VOIDS`.
    pub brep: u64,
    /// The representation whose items hold it (its context gives the unit).
    pub rep: u64,
    /// File coordinates of the solid → world coordinates (file units).
    pub placement: Mat4,
    /// The products from the root down, `/`-separated, each with the NAUO's id where it is a
    /// component: `box_sides/gusset (#10519)`.
    pub path: String,
    /// A NAUO on the path that no `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` places: its
    /// component was taken in the assembly's coordinates (as OpenCASCADE takes it).
    pub unplaced: Option<u64>,
}

/// `(id, relating (the assembly), related (the component))` of a
/// `NEXT_ASSEMBLY_USAGE_OCCURRENCE` record.
pub fn nauo(id: u64, r: &Record) -> Option<(u64, u64, u64)> {
    let p = params(r);
    Some((id, p.get(3).and_then(as_ref)?, p.get(4).and_then(as_ref)?))
}

/// The product structure's solids, or `None` when the file is not an assembly (no NAUO:
/// `nauos` are the file's, by [`nauo`], in file order). `Err((id, reason))` names the entity
/// that makes the structure unreadable.
pub fn placed_solids(
    records: &Records,
    is_brep: &dyn Fn(u64) -> bool,
    nauos: Vec<(u64, u64, u64)>,
) -> Result<Option<Vec<Placed>>, (u64, String)> {
    if nauos.is_empty() {
        return Ok(None);
    }
    let s = Structure::new(records, is_brep);
    let children: HashSet<u64> = nauos.iter().map(|n| n.2).collect();
    let mut roots: Vec<u64> = Vec::new();
    for &(_, parent, _) in &nauos {
        if !children.contains(&parent) && !roots.contains(&parent) {
            roots.push(parent);
        }
    }
    // A product with a shape that is no one's component is a root too (a part beside the
    // assembly).
    for &pd in s.shape_of.keys() {
        if !children.contains(&pd) && !roots.contains(&pd) {
            roots.push(pd);
        }
    }
    roots.sort_by_key(|pd| records.position(*pd));
    let mut out = Vec::new();
    for root in roots {
        let name = s.product_name(root);
        s.visit(root, IDENTITY, name, None, &nauos, 0, &mut out)?;
    }
    Ok(Some(out))
}

/// The product structure, indexed.
struct Structure<'a> {
    records: &'a Records<'a>,
    is_brep: &'a dyn Fn(u64) -> bool,
    /// Product definition → the representations of its shape.
    shape_of: HashMap<u64, Vec<u64>>,
    /// NAUO → the representation relationship placing it.
    placing: HashMap<u64, u64>,
    /// Representation → the representations linked to it without a transformation.
    views: HashMap<u64, Vec<u64>>,
}

impl<'a> Structure<'a> {
    fn new(records: &'a Records<'a>, is_brep: &'a dyn Fn(u64) -> bool) -> Self {
        let mut s = Structure {
            records,
            is_brep,
            shape_of: HashMap::default(),
            placing: HashMap::default(),
            views: HashMap::default(),
        };
        // PRODUCT_DEFINITION_SHAPE → what it defines the shape of.
        let definition_of = |pds: u64| -> Option<u64> {
            let r = records.complex_part(pds, "PRODUCT_DEFINITION_SHAPE")?;
            params(r).get(2).and_then(as_ref)
        };
        for id in records.ids_in_order() {
            if let Some(r) = records.simple(id) {
                let p = params(r);
                match r.name.as_str() {
                    "SHAPE_DEFINITION_REPRESENTATION" => {
                        if let (Some(def), Some(rep)) = (
                            p.first().and_then(as_ref).and_then(definition_of),
                            p.get(1).and_then(as_ref),
                        ) {
                            s.shape_of.entry(def).or_default().push(rep);
                        }
                    }
                    "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION" => {
                        if let (Some(rr), Some(nauo)) = (
                            p.first().and_then(as_ref),
                            p.get(1).and_then(as_ref).and_then(definition_of),
                        ) {
                            s.placing.insert(nauo, rr);
                        }
                    }
                    _ => {}
                }
            }
            if let Some(rel) = relationship(records, id) {
                if records
                    .complex_part(id, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")
                    .is_none()
                {
                    let p = params(rel);
                    if let (Some(a), Some(b)) =
                        (p.get(2).and_then(as_ref), p.get(3).and_then(as_ref))
                    {
                        s.views.entry(a).or_default().push(b);
                        s.views.entry(b).or_default().push(a);
                    }
                }
            }
        }
        s
    }

    /// The product's name (`PRODUCT.name`, else its id), for instance paths.
    fn product_name(&self, pd: u64) -> String {
        let recs = self.records;
        let product = recs
            .simple(pd)
            .and_then(|r| params(r).get(2).and_then(as_ref))
            .and_then(|form| recs.simple(form))
            .and_then(|r| params(r).get(2).and_then(as_ref))
            .and_then(|p| recs.simple(p))
            .filter(|r| r.name == "PRODUCT");
        match product {
            Some(r) => {
                let p = params(r);
                let name = p.get(1).map(as_string).unwrap_or_default();
                if name.trim().is_empty() {
                    p.first().map(as_string).unwrap_or_default()
                } else {
                    name
                }
            }
            None => format!("#{pd}"),
        }
    }

    /// Every representation of the product definition's shape: its own and their views.
    fn reps_of(&self, pd: u64) -> Vec<u64> {
        let mut out: Vec<u64> = self.shape_of.get(&pd).cloned().unwrap_or_default();
        let mut k = 0;
        while k < out.len() {
            for &v in self.views.get(&out[k]).into_iter().flatten() {
                if !out.contains(&v) {
                    out.push(v);
                }
            }
            k += 1;
        }
        out
    }

    /// The solids among the items of `rep` (and of the representations its mapped items map
    /// in), each with its placement in `rep`'s coordinates.
    fn solids_in(
        &self,
        rep: u64,
        acc: Mat4,
        depth: usize,
        out: &mut Vec<(u64, u64, Mat4)>,
    ) -> Result<(), (u64, String)> {
        if depth > MAX_ASSEMBLY_DEPTH {
            return Err((rep, "mapped items nested too deep (a cycle?)".into()));
        }
        let recs = self.records;
        let Some(items) = recs
            .simple(rep)
            .or_else(|| recs.complex_part(rep, "REPRESENTATION"))
            .and_then(|r| params(r).get(1).and_then(as_refs))
        else {
            return Ok(());
        };
        for item in items {
            if (self.is_brep)(item) {
                out.push((item, rep, acc));
            } else if let Some((mapped, t)) = mapped_item(recs, item)? {
                let m = mat_mul(&acc, &t);
                self.solids_in(mapped, m, depth + 1, out)?;
                for &v in self.views.get(&mapped).into_iter().flatten() {
                    self.solids_in(v, m, depth + 1, out)?;
                }
            }
        }
        Ok(())
    }

    /// The transform from the component's coordinates to the assembly's for one NAUO; `None`
    /// when no `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` places it.
    fn component_transform(&self, nauo: u64, child: u64) -> Result<Option<Mat4>, (u64, String)> {
        let recs = self.records;
        let Some(&rr) = self.placing.get(&nauo) else {
            return Ok(None);
        };
        let rel = relationship(recs, rr)
            .ok_or((rr, "expected a REPRESENTATION_RELATIONSHIP".to_string()))?;
        let p = params(rel);
        let (Some(r1), Some(r2)) = (p.get(2).and_then(as_ref), p.get(3).and_then(as_ref)) else {
            return Err((rr, "representations missing".into()));
        };
        let Some(with) = recs.complex_part(rr, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")
        else {
            // Same coordinates.
            return Ok(Some(IDENTITY));
        };
        let t = params(with)
            .first()
            .and_then(as_ref)
            .ok_or((rr, "transformation missing".to_string()))?;
        let q = recs
            .simple(t)
            .filter(|r| r.name == "ITEM_DEFINED_TRANSFORMATION")
            .map(params)
            .ok_or((
                t,
                "only ITEM_DEFINED_TRANSFORMATION is supported".to_string(),
            ))?;
        let (Some(i1), Some(i2)) = (q.get(2).and_then(as_ref), q.get(3).and_then(as_ref)) else {
            return Err((t, "transformation items missing".into()));
        };
        let p1 = axis2_placement(recs, i1).map_err(|e| (t, e))?;
        let p2 = axis2_placement(recs, i2).map_err(|e| (t, e))?;
        let child_reps = self.reps_of(child);
        if child_reps.contains(&r1) && !child_reps.contains(&r2) {
            // ISO's order: rep_1 (and item_1) the component's.
            Ok(Some(mat_mul(&p2, &rigid_inverse(&p1))))
        } else if child_reps.contains(&r2) && !child_reps.contains(&r1) {
            // The assembly first (SolidWorks).
            Ok(Some(mat_mul(&p1, &rigid_inverse(&p2))))
        } else {
            Err((
                rr,
                format!(
                    "neither #{r1} nor #{r2} (alone) is the shape of the component #{child} of \
                     #{nauo}"
                ),
            ))
        }
    }

    /// Places the solids of `pd`'s shape by `acc`, then visits its components. `unplaced`
    /// is the first NAUO on the path that nothing places.
    #[allow(clippy::too_many_arguments)]
    fn visit(
        &self,
        pd: u64,
        acc: Mat4,
        path: String,
        unplaced: Option<u64>,
        nauos: &[(u64, u64, u64)],
        depth: usize,
        out: &mut Vec<Placed>,
    ) -> Result<(), (u64, String)> {
        if depth > MAX_ASSEMBLY_DEPTH {
            return Err((pd, "assembly nested too deep (a cycle?)".into()));
        }
        let mut found = Vec::new();
        for rep in self.reps_of(pd) {
            self.solids_in(rep, IDENTITY, 0, &mut found)?;
        }
        let mut seen = HashSet::default();
        for (brep, rep, m) in found {
            // The same solid reached through two views of one shape is one solid.
            if seen.insert((
                brep,
                m.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>(),
            )) {
                out.push(Placed {
                    brep,
                    rep,
                    placement: mat_mul(&acc, &m),
                    path: path.clone(),
                    unplaced,
                });
            }
        }
        if out.len() > MAX_PLACED_SOLIDS {
            return Err((
                pd,
                format!("the assembly places more than {MAX_PLACED_SOLIDS} solids"),
            ));
        }
        for &(nauo, parent, child) in nauos {
            if parent != pd {
                continue;
            }
            let t = self.component_transform(nauo, child)?;
            let name = format!("{path}/{} (#{nauo})", self.product_name(child));
            let unplaced = unplaced.or(t.is_none().then_some(nauo));
            let acc = mat_mul(&acc, &t.unwrap_or(IDENTITY));
            self.visit(child, acc, name, unplaced, nauos, depth + 1, out)?;
        }
        Ok(())
    }
}
