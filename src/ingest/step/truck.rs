//! What truck-stepio reads, and the records rewritten where it would misread them.
//!
//! truck-stepio's `Table` converts geometry well, but it drops or misreads several things, so
//! the parsed records are prepared first ([`patch_for_truck`]):
//! - `SURFACE_CURVE`/`SEAM_CURVE` master representations become `.CURVE_3D.` (truck otherwise
//!   uses the 2D pcurve and drops the exact 3D curve), and their pcurves are dropped (truck
//!   would convert each with its surface, for nothing);
//! - `EDGE_CURVE`s that point at a `TRIMMED_CURVE` point at its basis curve (the edge's
//!   vertices trim it anyway; truck does not read `TRIMMED_CURVE`);
//! - a placement whose axis is ±x and whose x axis is left out gets OCCT's x axis explicitly
//!   (ISO's default would be degenerate and truck would build NaN frames);
//! - a `$` label truck would refuse becomes an empty string.
//!
//! After truck has read the table, cones' semi-angles are converted to radians
//! ([`cone_angles_in_radians`]): truck takes them as radians whatever the file's unit.

use super::p21::{CompactPoint, Item, PointKind, Section};
use super::records::{as_ref, params, Records};
use super::units::plane_angle_factor;
use std::collections::HashMap;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Name, Parameter};
use truck_stepio::r#in::Table;

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

/// The topology truck reads but the reader never asks it for: the reader walks faces,
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

/// Rewrites what truck misreads (see the module docs). Returns the number of records changed.
pub fn patch_for_truck(sections: &mut [Section]) -> usize {
    let Survey {
        mut max_id,
        trimmed_basis,
        implicit_x,
    } = survey(sections);
    // Directions, to repair placements whose implicit x axis is degenerate (only collected
    // when some placement leaves its x axis out).
    let directions = if implicit_x {
        directions_by_id(sections)
    } else {
        HashMap::new()
    };
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
        changed += match record.name.as_str() {
            "AXIS2_PLACEMENT_3D" if matches!(list.get(3), Some(Parameter::NotProvided)) => {
                explicit_x_axis(list, &directions, &mut max_id, &mut new_directions)
            }
            "SURFACE_CURVE" | "SEAM_CURVE" => curve_3d_master(list),
            "EDGE_CURVE" => basis_of_trimmed(list, &trimmed_basis),
            _ => 0,
        };
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

/// What the rewriting needs to know of the whole file.
struct Survey {
    /// The largest id (new directions are numbered after it).
    max_id: u64,
    /// The basis curve of every `TRIMMED_CURVE`.
    trimmed_basis: HashMap<u64, u64>,
    /// Whether some placement leaves its x axis out.
    implicit_x: bool,
}

/// One pass over the file for the [`Survey`].
fn survey(sections: &[Section]) -> Survey {
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
    Survey {
        max_id,
        trimmed_basis,
        implicit_x,
    }
}

/// Every direction of the file with three coordinates, by id.
fn directions_by_id(sections: &[Section]) -> HashMap<u64, [f64; 3]> {
    let mut directions: HashMap<u64, [f64; 3]> = HashMap::new();
    let records = Records::new(sections);
    for id in records.ids_in_order() {
        if let Some(c) = records.coordinates(id, PointKind::Direction) {
            if c.len() == 3 {
                directions.insert(id, [c[0], c[1], c[2]]);
            }
        }
    }
    directions
}

/// ISO 10303-42 takes x = (1,0,0) when ref_direction is omitted, which is degenerate when the
/// axis is ±x; truck then builds NaN frames. Gives such a placement (its parameters `list`)
/// OCCT's choice of x axis explicitly: a new direction, numbered after `max_id` and added to
/// `new_directions`. Returns the number of records changed.
fn explicit_x_axis(
    list: &mut [Parameter],
    directions: &HashMap<u64, [f64; 3]>,
    max_id: &mut u64,
    new_directions: &mut Vec<(u64, [f64; 3])>,
) -> usize {
    let z = list
        .get(2)
        .and_then(as_ref)
        .and_then(|d| directions.get(&d));
    if let Some(z) = z {
        let n = (z[0] * z[0] + z[1] * z[1] + z[2] * z[2]).sqrt();
        if n > 0.0 && (z[0] / n).abs() > 1.0 - 1e-9 {
            *max_id += 1;
            let x = [-z[2] / n, 0.0, z[0] / n];
            let x = if x[0].abs() + x[2].abs() > 0.5 {
                x
            } else {
                [0.0, 1.0, 0.0]
            };
            new_directions.push((*max_id, x));
            list[3] = Parameter::Ref(Name::Entity(*max_id));
            return 1;
        }
    }
    0
}

/// Makes a surface curve's (its parameters `list`) 3D curve the master representation and
/// drops its pcurves. Returns the number of records changed.
fn curve_3d_master(list: &mut [Parameter]) -> usize {
    let mut changed = 0;
    if let Some(Parameter::Enumeration(e)) = list.last_mut() {
        if e != "CURVE_3D" {
            *e = "CURVE_3D".into();
            changed += 1;
        }
    }
    // With the 3D curve as the master, truck has no use for the pcurves, but it would still
    // convert each one with its whole surface (a degree-13 patch per pcurve: 10 % of reading
    // the M6 screw).
    if let Some(Parameter::List(associated)) = list.get_mut(2) {
        if !associated.is_empty() {
            associated.clear();
            changed += 1;
        }
    }
    changed
}

/// Points an edge curve (its parameters `list`) at the basis of the trimmed curve it points
/// at, following chains of trimmed curves. Returns the number of references changed.
fn basis_of_trimmed(list: &mut [Parameter], trimmed_basis: &HashMap<u64, u64>) -> usize {
    let mut changed = 0;
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
    changed
}

/// truck takes a cone's semi-angle in radians whatever the file's plane-angle unit: the
/// angles in its table are converted.
pub fn cone_angles_in_radians(table: &mut Table, recs: &Records) {
    let angle = plane_angle_factor(recs);
    if angle != 1.0 {
        for cone in table.conical_surface.values_mut() {
            cone.semi_angle *= angle;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::simple_instance;

    /// The list is truck's: every name on it is read into one of truck's tables (or refused
    /// for its missing parameters), never kept as a `Dummy`; a name truck does not know is.
    /// The reader skips the names not on the list, so a name truck reads and the list lacks
    /// would lose geometry: the list was taken from `push_instance`'s match arms, and the
    /// sample and real-world tests read every kind of entity the corpus has.
    #[test]
    fn truck_simple_entities_are_the_ones_truck_does_not_keep_as_dummies() {
        for (k, name) in TRUCK_CONVERTED.iter().chain(&WALKED_TOPOLOGY).enumerate() {
            let mut table = Table::default();
            let _ = table.push_instance(&simple_instance(k as u64 + 1, name));
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
            table
                .push_instance(&simple_instance(1, name))
                .expect("a dummy");
            assert_eq!(table.dummy.len(), 1, "{name}");
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
        let mut exchange = crate::ingest::step::p21::parse(text, 16).expect("parses");
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
        let mut exchange = crate::ingest::step::p21::parse(text, 16).expect("parses");
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

    /// A cone's semi-angle in degrees reaches truck in radians; in a file in radians it is
    /// left as it is.
    #[test]
    fn cone_angles_reach_truck_in_radians() {
        let cone = "#1=CARTESIAN_POINT('',(0.,0.,0.));
            #2=DIRECTION('',(0.,0.,1.));
            #3=DIRECTION('',(1.,0.,0.));
            #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
            #5=CONICAL_SURFACE('',#4,2.,30.);
            #8=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));";
        let degree = "#6=(CONVERSION_BASED_UNIT('DEGREE',#7)NAMED_UNIT(*)PLANE_ANGLE_UNIT());
            #7=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925),#8);";
        for (units, expected) in [("", 30.0), (degree, 30.0 * 0.0174532925)] {
            let text =
                format!("ISO-10303-21;HEADER;ENDSEC;DATA;{cone}{units}ENDSEC;END-ISO-10303-21;");
            let parsed = super::super::p21::parse(&text, 8).expect("parses");
            let recs = Records::new(&parsed.data);
            let mut table = Table::default();
            for item in &parsed.data[0].entities {
                table
                    .push_instance(&item.to_instance())
                    .expect("truck reads it");
            }
            cone_angles_in_radians(&mut table, &recs);
            assert_eq!(table.conical_surface[&5].semi_angle, expected, "{units}");
        }
    }
}
