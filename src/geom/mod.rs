//! Geometry on the exact model: evaluation with derivatives, normals and curvatures,
//! trimming (inside/outside a face's loops), bounding boxes.
//!
//! Everything here works in model units (millimetres) on the truck geometry that
//! [`crate::brep`] carries, correcting truck where it is wrong (B-spline second derivatives).

mod bbox;
pub mod bvh;
pub mod curvature;
pub mod distance;
pub mod eval;
pub mod project;
pub mod trim;

pub use bbox::{model_bounding_box, Aabb};
pub use bvh::Bvh;
pub use curvature::{principal_curvatures, unit_normal, Curvature};
pub use distance::{nearest_on_edge, nearest_on_face, Boundary, FaceHit, Feature};
pub use eval::{eval_curve, eval_surface, CurveDerivs, SurfaceDerivs};
pub use project::project_point;

use crate::brep::model::Surface;

/// The kind of a surface, as the report names it: `plane`, `cylinder`, `cone`, `sphere`,
/// `torus`, `bspline`, `nurbs`, `extrusion`, `revolution`.
pub fn surface_kind(surface: &Surface) -> &'static str {
    use truck_stepio::r#in::alias::{ElementarySurface as E, SweptCurve as S};
    match surface {
        Surface::ElementarySurface(e) => match e.as_ref() {
            E::Plane(_) => "plane",
            E::CylindricalSurface(_) => "cylinder",
            E::ConicalSurface(_) => "cone",
            E::Sphere(_) => "sphere",
            E::ToroidalSurface(_) => "torus",
        },
        Surface::SweptCurve(s) => match s.as_ref() {
            S::ExtrudedCurve(_) => "extrusion",
            S::RevolutedCurve(_) => "revolution",
        },
        Surface::BSplineSurface(_) => "bspline",
        Surface::NurbsSurface(_) => "nurbs",
    }
}
