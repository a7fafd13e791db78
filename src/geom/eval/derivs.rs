//! The evaluators' results: a surface point with its first and second partial derivatives,
//! a curve point with its first two derivatives, the all-NaN results of a patch that cannot be
//! evaluated, and the conversions from truck's point and vector types.

use glam::DVec3;
use truck_geometry::prelude::{Point3, Vector3};

/// A surface point with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    pub p: DVec3,
    pub su: DVec3,
    pub sv: DVec3,
    pub suu: DVec3,
    pub suv: DVec3,
    pub svv: DVec3,
}

/// A curve point with its first and second derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveDerivs {
    pub p: DVec3,
    pub d1: DVec3,
    pub d2: DVec3,
}

pub(super) const NAN_SURFACE: SurfaceDerivs = SurfaceDerivs {
    p: DVec3::NAN,
    su: DVec3::NAN,
    sv: DVec3::NAN,
    suu: DVec3::NAN,
    suv: DVec3::NAN,
    svv: DVec3::NAN,
};

pub(super) const NAN_CURVE: CurveDerivs = CurveDerivs {
    p: DVec3::NAN,
    d1: DVec3::NAN,
    d2: DVec3::NAN,
};

#[inline]
pub(super) fn point3(p: Point3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

#[inline]
pub(super) fn vec3(v: Vector3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}
