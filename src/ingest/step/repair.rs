//! Repairs of the parsed STEP records, before anything reads them.
//!
//! - [`normalise_directions`]: a `DIRECTION` is a direction whatever its length, but truck
//!   uses its ratios as a vector (a circle's radius scales with its placement's axes). CATIA
//!   V5 writes every direction of an inch file with length 1/25.4: each is scaled to length
//!   one, with a warning. A zero or non-finite direction cannot be repaired: an error.

use super::p21::{Item, PointKind, Section};
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Parameter};

/// A direction whose length differs from one by more than this (relative) is normalised and
/// counted; nearer ones are left exactly as written.
pub const UNIT_DIRECTION_REL: f64 = 1e-6;

/// Directions normalised: the first one's id and length, and how many.
#[derive(Debug, Default, PartialEq)]
pub struct Normalised {
    pub first: Option<(u64, f64)>,
    pub count: usize,
}

/// Scales every `DIRECTION` (compact or not) whose length is not one to length one. A
/// direction of length zero (or not finite) is `Err((id, reason))`.
pub fn normalise_directions(sections: &mut [Section]) -> Result<Normalised, (u64, String)> {
    let mut done = Normalised::default();
    for item in sections.iter_mut().flat_map(|s| &mut s.entities) {
        let id = item.id();
        match item {
            Item::Point(p) if p.kind == PointKind::Direction => {
                let mut c = p.coords().to_vec();
                if let Some(n) = unit(id, &mut c)? {
                    p.set_coords(&c);
                    done.count += 1;
                    done.first.get_or_insert((id, n));
                }
            }
            Item::Instance(EntityInstance::Simple { record, .. }) if record.name == "DIRECTION" => {
                let Parameter::List(list) = &mut record.parameter else {
                    continue;
                };
                let Some(Parameter::List(ratios)) = list.get_mut(1) else {
                    continue;
                };
                let mut c: Vec<f64> = ratios
                    .iter()
                    .map(|r| match r {
                        Parameter::Real(x) => *x,
                        Parameter::Integer(i) => *i as f64,
                        _ => f64::NAN,
                    })
                    .collect();
                if let Some(n) = unit(id, &mut c)? {
                    *ratios = c.into_iter().map(Parameter::Real).collect();
                    done.count += 1;
                    done.first.get_or_insert((id, n));
                }
            }
            _ => {}
        }
    }
    Ok(done)
}

/// Scales `c` to length one when it is not; returns its length then, `None` when it was
/// already a unit vector.
fn unit(id: u64, c: &mut [f64]) -> Result<Option<f64>, (u64, String)> {
    let n = c.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(n.is_finite() && n > 1e-300) {
        return Err((
            id,
            format!("direction {c:?} has no length: it gives no direction"),
        ));
    }
    if (n - 1.0).abs() <= UNIT_DIRECTION_REL {
        return Ok(None);
    }
    c.iter_mut().for_each(|x| *x /= n);
    Ok(Some(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ingest::step::p21;

    fn parse(data: &str) -> Vec<Section> {
        let text =
            format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n");
        p21::parse(&text, 8).expect("parses").data
    }

    #[test]
    fn directions_of_any_length_become_unit_vectors_and_are_counted() {
        let mut s = parse(
            "#1=DIRECTION('',(0.,0.,0.03937007874));\n#2=DIRECTION('',(1.,0.,0.));\n\
             #3=DIRECTION($,(0.,3.,4.));",
        );
        let done = normalise_directions(&mut s).unwrap();
        assert_eq!(done.count, 2);
        assert_eq!(done.first.unwrap().0, 1);
        assert!((done.first.unwrap().1 - 1.0 / 25.4).abs() < 1e-9);
        let recs = crate::ingest::step::records::Records::new(&s);
        assert_eq!(
            recs.coordinates(1, PointKind::Direction).unwrap(),
            vec![0.0, 0.0, 1.0]
        );
        assert_eq!(
            recs.coordinates(2, PointKind::Direction).unwrap(),
            vec![1.0, 0.0, 0.0]
        );
        let c = recs.coordinates(3, PointKind::Direction).unwrap();
        assert!(
            (c[1] - 0.6).abs() < 1e-15 && (c[2] - 0.8).abs() < 1e-15,
            "{c:?}"
        );
    }

    #[test]
    fn a_direction_of_no_length_is_an_error_naming_it() {
        let mut s = parse("#1=DIRECTION('',(1.,0.,0.));\n#7=DIRECTION('',(0.,0.,0.));");
        let (id, reason) = normalise_directions(&mut s).unwrap_err();
        assert_eq!(id, 7);
        assert!(reason.contains("no length"), "{reason}");
    }
}
