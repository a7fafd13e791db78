//! Filling truck's table with the STEP records truck converts.
//!
//! Compact points and the most common records go in as the holders truck's reader would make
//! of them ([`push_point`], [`push_direct`]), the rest through truck's reader, whose failures
//! are kept by id (the topology walk reports them when it needs the entity).

use super::error::{first_line, guarded};
use super::p21::{self, Item, PointKind, Section};
use super::records::{as_bool, as_ref, instance_id, params, Records};
use super::truck::{definitional_contexts, truck_converts};
use rustc_hash::FxHashMap as HashMap;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Name, Parameter, Record};
use truck_stepio::r#in::ruststep::tables::PlaceHolder;
use truck_stepio::r#in::{
    Axis2Placement3dHolder, CartesianPointHolder, CircleHolder, CylindricalSurfaceHolder,
    DirectionHolder, EdgeCurveHolder, LineHolder, PlaneHolder, Table, VectorHolder,
    VertexPointHolder,
};

/// truck's table of the records of `sections` it converts, and why it could not read the
/// others (by id).
pub fn fill_table(sections: &[Section], recs: &Records) -> (Table, HashMap<u64, String>) {
    let mut table = Table::default();
    let mut undecodable: HashMap<u64, String> = HashMap::default();
    let contexts = definitional_contexts(recs);
    // What truck does not read it keeps as text, formatted with `Debug` (8 % of reading the
    // NIST parts, whose styling entities are a large part of the file), and the topology is
    // walked here: both are skipped, but for the contexts of definitional representations,
    // which truck looks up among its text records.
    let to_push: Vec<&Item> = sections
        .iter()
        .flat_map(|s| &s.entities)
        .filter(|item| match item {
            Item::Instance(EntityInstance::Simple { id, record }) => {
                truck_converts(&record.name) || contexts.contains(id)
            }
            Item::Instance(EntityInstance::Complex { .. }) | Item::Point(_) => true,
        })
        .collect();
    reserve_table(&mut table, &to_push);
    for item in to_push {
        let inst = match item {
            Item::Point(p) => {
                push_point(&mut table, p);
                continue;
            }
            Item::Instance(EntityInstance::Simple { id, record })
                if push_direct(&mut table, *id, record) =>
            {
                continue;
            }
            Item::Instance(inst) => inst,
        };
        match guarded(|| table.push_instance(inst)) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                undecodable.insert(instance_id(inst), first_line(&e.to_string()));
            }
            Err(p) => {
                undecodable.insert(instance_id(inst), format!("reader panicked: {p}"));
            }
        }
    }
    (table, undecodable)
}

/// Puts a compact point or direction into truck's table: the holder truck's reader makes of
/// its record (`push_instance`), without the record or the deserializer.
fn push_point(table: &mut Table, p: &p21::CompactPoint) {
    let (label, coords) = (p.label.clone(), p.coords().to_vec());
    match p.kind {
        PointKind::CartesianPoint => {
            let holder = CartesianPointHolder {
                label,
                coordinates: coords,
            };
            table.cartesian_point.insert(p.id, holder);
        }
        PointKind::Direction => {
            let holder = DirectionHolder {
                label,
                direction_ratios: coords,
            };
            table.direction.insert(p.id, holder);
        }
    }
}

/// Puts the most common geometry and vertex records into truck's table when they are in
/// their usual form (a string label, `#id` references, reals, `.T.`/`.F.`): the holder
/// truck's reader makes of the record (`push_instance`, through serde), built directly.
/// False for any other record or form, which goes through truck's reader.
fn push_direct(table: &mut Table, id: u64, record: &Record) -> bool {
    match (record.name.as_str(), params(record)) {
        ("VECTOR", [l, o, m]) => {
            let holder = || {
                Some(VectorHolder {
                    label: label(l)?,
                    orientation: r(o)?,
                    magnitude: real(m)?,
                })
            };
            put(&mut table.vector, id, holder())
        }
        ("AXIS2_PLACEMENT_3D", [l, loc, axis, x]) => {
            let holder = || {
                Some(Axis2Placement3dHolder {
                    label: label(l)?,
                    location: r(loc)?,
                    axis: opt_r(axis)?,
                    ref_direction: opt_r(x)?,
                })
            };
            put(&mut table.axis2_placement_3d, id, holder())
        }
        ("LINE", [l, pnt, dir]) => {
            let holder = || {
                Some(LineHolder {
                    label: label(l)?,
                    pnt: r(pnt)?,
                    dir: r(dir)?,
                })
            };
            put(&mut table.line, id, holder())
        }
        ("CIRCLE", [l, position, radius]) => {
            let holder = || {
                Some(CircleHolder {
                    label: label(l)?,
                    position: r(position)?,
                    radius: real(radius)?,
                })
            };
            put(&mut table.circle, id, holder())
        }
        ("PLANE", [l, position]) => {
            let holder = || {
                Some(PlaneHolder {
                    label: label(l)?,
                    position: r(position)?,
                })
            };
            put(&mut table.plane, id, holder())
        }
        ("CYLINDRICAL_SURFACE", [l, position, radius]) => {
            let holder = || {
                Some(CylindricalSurfaceHolder {
                    label: label(l)?,
                    position: r(position)?,
                    radius: real(radius)?,
                })
            };
            put(&mut table.cylindrical_surface, id, holder())
        }
        ("VERTEX_POINT", [l, point]) => {
            let holder = || {
                Some(VertexPointHolder {
                    label: label(l)?,
                    vertex_geometry: r(point)?,
                })
            };
            put(&mut table.vertex_point, id, holder())
        }
        ("EDGE_CURVE", [l, start, end, geometry, sense]) => {
            let holder = || {
                Some(EdgeCurveHolder {
                    label: label(l)?,
                    edge_start: r(start)?,
                    edge_end: r(end)?,
                    edge_geometry: r(geometry)?,
                    same_sense: as_bool(sense)?,
                })
            };
            put(&mut table.edge_curve, id, holder())
        }
        _ => false,
    }
}

/// A string label.
fn label(q: &Parameter) -> Option<String> {
    match q {
        Parameter::String(s) => Some(s.clone()),
        _ => None,
    }
}

/// A `#id` reference as truck's placeholder.
fn r<T>(q: &Parameter) -> Option<PlaceHolder<T>> {
    as_ref(q).map(|id| PlaceHolder::Ref(Name::Entity(id)))
}

/// An optional `#id` reference (`$`: none) as truck's placeholder.
fn opt_r<T>(q: &Parameter) -> Option<Option<PlaceHolder<T>>> {
    match q {
        Parameter::NotProvided => Some(None),
        _ => r(q).map(Some),
    }
}

/// A real written as one (not an integer, not typed).
fn real(q: &Parameter) -> Option<f64> {
    match q {
        Parameter::Real(x) => Some(*x),
        _ => None,
    }
}

/// Puts the holder, if the record gave one, under `id`.
fn put<H>(map: &mut std::collections::HashMap<u64, H>, id: u64, holder: Option<H>) -> bool {
    holder.map(|h| map.insert(id, h)).is_some()
}

/// Sizes truck's tables for the entities most files are made of, which would otherwise grow
/// by rehashing (truck's maps hash with SipHash).
fn reserve_table(table: &mut Table, items: &[&Item]) {
    let mut n = [0usize; 9];
    for item in items {
        let k = match item {
            Item::Point(p) => match p.kind {
                PointKind::CartesianPoint => 0,
                PointKind::Direction => 1,
            },
            Item::Instance(EntityInstance::Simple { record, .. }) => match record.name.as_str() {
                "CARTESIAN_POINT" => 0,
                "DIRECTION" => 1,
                "VECTOR" => 2,
                "AXIS2_PLACEMENT_3D" => 3,
                "LINE" => 4,
                "CIRCLE" => 5,
                "B_SPLINE_CURVE_WITH_KNOTS" => 6,
                "VERTEX_POINT" => 7,
                "EDGE_CURVE" => 8,
                _ => continue,
            },
            Item::Instance(EntityInstance::Complex { .. }) => continue,
        };
        n[k] += 1;
    }
    table.cartesian_point.reserve(n[0]);
    table.direction.reserve(n[1]);
    table.vector.reserve(n[2]);
    table.axis2_placement_3d.reserve(n[3]);
    table.line.reserve(n[4]);
    table.circle.reserve(n[5]);
    table.b_spline_curve_with_knots.reserve(n[6]);
    table.vertex_point.reserve(n[7]);
    table.edge_curve.reserve(n[8]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ingest::step::truck::patch_for_truck;
    use crate::ingest::step::MAX_NESTING;

    /// A compact point or direction gives truck's table the holder truck's own reader makes
    /// of the full record, for every form the parser keeps compact.
    #[test]
    fn compact_points_make_truck_s_holders() {
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=CARTESIAN_POINT('',(1.,-2.5,3.E1));
            #2=CARTESIAN_POINT('a''b',(0.5,-0.));
            #3=CARTESIAN_POINT('x',(7.));
            #4=DIRECTION('',(0.,0.,1.));
            #5=DIRECTION('d',(1.E-300,-1.));
            ENDSEC;END-ISO-10303-21;";
        let parsed = p21::parse(text, 8).expect("parses");
        let (mut ours, mut truck) = (Table::default(), Table::default());
        for item in &parsed.data[0].entities {
            let Item::Point(p) = item else {
                panic!("{item:?} is not compact")
            };
            push_point(&mut ours, p);
            truck
                .push_instance(&item.to_instance())
                .expect("truck reads it");
        }
        assert_eq!(ours.cartesian_point.len(), 3);
        assert_eq!(ours.direction.len(), 2);
        assert_eq!(ours.cartesian_point, truck.cartesian_point);
        assert_eq!(ours.direction, truck.direction);
    }

    /// Every record `push_direct` takes, in every sample and real-world file, gives the
    /// holder truck's reader makes of it; it takes nearly all records of its kinds.
    #[test]
    fn direct_holders_are_truck_s_on_every_file() {
        let (mut direct, mut kinds) = (0, 0);
        let files = crate::testing::corpus_step_files();
        // The samples hold about 2,600 records of these kinds; with the corpus, over 5,000.
        let with_corpus = files
            .iter()
            .any(|f| !f.starts_with(crate::testing::root().join("samples")));
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            let mut parsed = p21::parse(&text, MAX_NESTING).unwrap();
            patch_for_truck(&mut parsed.data);
            let (mut ours, mut truck) = (Table::default(), Table::default());
            for item in &parsed.data[0].entities {
                let Item::Instance(inst @ EntityInstance::Simple { id, record }) = item else {
                    continue;
                };
                let kind = [
                    "VECTOR",
                    "AXIS2_PLACEMENT_3D",
                    "LINE",
                    "CIRCLE",
                    "PLANE",
                    "CYLINDRICAL_SURFACE",
                    "VERTEX_POINT",
                    "EDGE_CURVE",
                ]
                .contains(&record.name.as_str());
                kinds += usize::from(kind);
                if push_direct(&mut ours, *id, record) {
                    assert!(kind, "{f:?} #{id}");
                    direct += 1;
                    truck
                        .push_instance(inst)
                        .unwrap_or_else(|e| panic!("{f:?} #{id}: {e}"));
                }
            }
            assert_eq!(ours.vector, truck.vector, "{f:?}");
            assert_eq!(ours.axis2_placement_3d, truck.axis2_placement_3d, "{f:?}");
            assert_eq!(ours.line, truck.line, "{f:?}");
            assert_eq!(ours.circle, truck.circle, "{f:?}");
            assert_eq!(ours.plane, truck.plane, "{f:?}");
            assert_eq!(ours.cylindrical_surface, truck.cylindrical_surface, "{f:?}");
            assert_eq!(ours.vertex_point, truck.vertex_point, "{f:?}");
            assert_eq!(ours.edge_curve, truck.edge_curve, "{f:?}");
        }
        assert!(kinds > if with_corpus { 5000 } else { 2000 }, "{kinds}");
        assert!(direct * 100 >= kinds * 95, "{direct} of {kinds}");
    }

    /// Other forms go through truck's reader: an integer where a real is expected, an
    /// unknown enumeration, a typed value where a reference is expected, a parameter too
    /// many, a label left out.
    #[test]
    fn unusual_forms_are_left_to_truck() {
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=VECTOR('',#2,2);
            #3=EDGE_CURVE('',#4,#5,#6,.U.);
            #7=LINE('',#8,LENGTH_MEASURE(1.));
            #9=PLANE('',#10,#11);
            #12=VERTEX_POINT($,#13);
            ENDSEC;END-ISO-10303-21;";
        let parsed = p21::parse(text, 8).expect("parses");
        let mut table = Table::default();
        for item in &parsed.data[0].entities {
            let Item::Instance(EntityInstance::Simple { id, record }) = item else {
                panic!("{item:?}")
            };
            assert!(!push_direct(&mut table, *id, record), "#{id}");
        }
    }
}
