//! Writers of the outputs besides the JSON report (DESIGN.md, "Outputs").

pub mod svg;
