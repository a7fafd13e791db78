//! Outputs of a traced MAT: B-spline fits of the seams ([`fit`]) and the STEP wireframe
//! file ([`step`]).

pub mod fit;
pub mod step;
