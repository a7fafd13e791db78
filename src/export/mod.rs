//! Writers of the outputs: the JSON report's schema ([`report`]), the STEP file of the seams
//! and junctions ([`step`]), the OBJ mesh of the sheets ([`obj`]), the picture ([`svg`]),
//! each written atomically ([`write_atomic`]); and a report read back ([`read`]).

mod atomic;
pub mod obj;
pub mod read;
pub mod report;
pub mod step;
pub mod svg;

pub use atomic::write_atomic;
