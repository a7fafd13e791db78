//! The STEP file's length and plane-angle units.
//!
//! Length units (SI with a prefix, or conversion-based such as the inch) as millimetres per
//! unit; the plane-angle unit as radians per unit.

use super::records::{as_real, as_ref, as_refs, as_string, params, Records};
use truck_stepio::r#in::ruststep::ast::Parameter;

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

/// The largest distance uncertainty the file declares (`UNCERTAINTY_MEASURE_WITH_UNIT` of a
/// length unit), in millimetres; `None` when it declares none that can be read.
pub fn length_uncertainty_mm(records: &Records) -> Option<f64> {
    records
        .ids_in_order()
        .filter_map(|id| records.simple(id))
        .filter(|r| r.name == "UNCERTAINTY_MEASURE_WITH_UNIT")
        .filter_map(|r| {
            let p = params(r);
            let value = p.first().and_then(as_real)?;
            let unit = length_unit(records, p.get(1).and_then(as_ref)?, 0)?.ok()?;
            let mm = value * unit.mm;
            (mm.is_finite() && mm > 0.0).then_some(mm)
        })
        .fold(None, |acc: Option<f64>, x| {
            Some(acc.map_or(x, |a| a.max(x)))
        })
}
