//! Geometry on the exact model: evaluation with derivatives, normals and curvatures,
//! projection onto a surface, trimming (inside/outside a face's loops), bounding boxes, and
//! distance queries on the whole boundary (nearest point, faces within a radius, point in
//! solid).
//!
//! Everything here works in model units (millimetres) on the truck geometry that
//! [`crate::model`] carries, correcting truck where it is wrong (B-spline second derivatives).
//! The modules, lowest first: [`eval`]; `surface` (kind, periods, parameter range),
//! [`curvature`], `bbox`, [`bvh`]; [`project`]; [`fold`]; [`trim`]; [`distance`].

mod bbox;
pub mod bvh;
pub mod curvature;
pub mod distance;
pub mod eval;
pub mod fold;
pub mod project;
mod surface;
pub mod trim;
pub mod volume;

pub use bbox::{edges_bounding_box, model_bounding_box, Aabb};
pub use bvh::Bvh;
pub use curvature::{principal_curvatures, unit_normal, Curvature};
pub use distance::{nearest_on_edge, nearest_on_face, Boundary, FaceHit};
pub use eval::{eval_curve, eval_surface, surface_point, CurveDerivs, SurfaceDerivs};
pub use project::{nearest_sample_between, project_point};
pub use surface::{
    closed_periods, eval_face, knot_vectors, parameter_range, surface_kind, surface_periods,
};
pub use volume::solid_volumes;
