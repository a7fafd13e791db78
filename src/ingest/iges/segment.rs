//! A piece of model-space curve with its parameter interval, and where points lie on it.
//!
//! [`Segment`]s are what the curve readers produce; [`nearest_param`] finds the parameter
//! nearest to a point and [`edge_range`] the interval an edge's vertices cut out.

use crate::ingest::tolerance::{VERTEX_AT_END_REL_COORD, VERTEX_ON_CURVE_REL_COORD};
use crate::model::Curve3D;
use glam::DVec3;
use truck_geometry::prelude::{Point3, SearchNearestParameter};

/// A 3D curve with its parameter interval, from the entity's start to its end.
#[derive(Clone, Debug)]
pub struct Segment {
    /// The entity the curve came from.
    pub de: usize,
    pub curve: Curve3D,
    pub range: (f64, f64),
}

impl Segment {
    pub fn at(&self, t: f64) -> DVec3 {
        use truck_geometry::prelude::ParametricCurve;
        let p = self.curve.subs(t);
        DVec3::new(p.x, p.y, p.z)
    }
    pub fn start(&self) -> DVec3 {
        self.at(self.range.0)
    }
    pub fn end(&self) -> DVec3 {
        self.at(self.range.1)
    }
    /// The point at fraction `s` of the parameter interval.
    pub fn at_fraction(&self, s: f64) -> DVec3 {
        self.at(self.range.0 + s * (self.range.1 - self.range.0))
    }
}

/// The parameter interval of `seg` from `pa` to `pb`, and whether the curve runs from `pb` to
/// `pa` instead (then the interval is from `pb` to `pa`).
pub fn edge_range(
    seg: &Segment,
    pa: DVec3,
    pb: DVec3,
) -> std::result::Result<((f64, f64), bool), String> {
    let scale = 1.0 + pa.abs().max_element().max(pb.abs().max_element());
    let tol = VERTEX_AT_END_REL_COORD * scale;
    let (s, e) = (seg.start(), seg.end());
    if s.distance(pa) <= tol && e.distance(pb) <= tol {
        return Ok((seg.range, false));
    }
    if s.distance(pb) <= tol && e.distance(pa) <= tol {
        return Ok((seg.range, true));
    }
    let (ta, da) = nearest_param(seg, pa);
    let (tb, db) = nearest_param(seg, pb);
    if da > VERTEX_ON_CURVE_REL_COORD * scale || db > VERTEX_ON_CURVE_REL_COORD * scale {
        return Err(format!(
            "the edge's vertices are not on its curve (distance {da:.3e} mm and {db:.3e} mm)"
        ));
    }
    if (tb - ta).abs() <= 1e-12 * (1.0 + ta.abs()) {
        return Ok((seg.range, false));
    }
    Ok(if ta < tb {
        ((ta, tb), false)
    } else {
        ((tb, ta), true)
    })
}

/// The parameter of the point of `seg` (within its range) nearest to `p`, and the distance.
pub fn nearest_param(seg: &Segment, p: DVec3) -> (f64, f64) {
    const COARSE: usize = 32;
    let (t0, t1) = seg.range;
    let (lo, hi) = (t0.min(t1), t0.max(t1));
    let mut best = (t0, f64::INFINITY);
    for k in 0..=COARSE {
        let t = t0 + (t1 - t0) * k as f64 / COARSE as f64;
        let d = seg.at(t).distance(p);
        if d < best.1 {
            best = (t, d);
        }
    }
    let refined = crate::panic_guard::catch(|| {
        seg.curve
            .search_nearest_parameter(Point3::new(p.x, p.y, p.z), Some(best.0), 100)
    })
    .ok()
    .flatten()
    .filter(|t| t.is_finite() && *t >= lo - 1e-9 * (hi - lo) && *t <= hi + 1e-9 * (hi - lo));
    if let Some(t) = refined {
        let t = t.clamp(lo, hi);
        let d = seg.at(t).distance(p);
        if d < best.1 {
            best = (t, d);
        }
    }
    best
}
