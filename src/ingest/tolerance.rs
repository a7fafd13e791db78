//! The tolerances both readers apply to an edge's vertices.
//!
//! They are relative to the size of the coordinates (`1 + |p|∞` of the vertices): files carry
//! small gaps between a vertex and its curve, which are accepted up to these.

/// How far (relative to the coordinates' size) an edge's vertex may be from its curve's end
/// before the vertex is projected onto the curve instead.
pub const VERTEX_AT_END_REL_COORD: f64 = 1e-6;

/// How far (relative to the coordinates' size) a vertex may be from its edge's curve at all.
pub const VERTEX_ON_CURVE_REL_COORD: f64 = 1e-4;
