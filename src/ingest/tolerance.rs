//! The tolerances both readers apply to an edge's vertices.
//!
//! They are relative to the size of the coordinates (`1 + |p|∞` of the vertices): files carry
//! small gaps between a vertex and its curve, which are accepted up to these.

/// How far (relative to the coordinates' size) an edge's vertex may be from its curve's end
/// before the vertex is projected onto the curve instead.
pub const VERTEX_AT_END_REL_COORD: f64 = 1e-6;

/// How far (relative to the coordinates' size) a vertex may be from its edge's curve at all.
pub const VERTEX_ON_CURVE_REL_COORD: f64 = 1e-4;

/// The most a vertex may be off its curve (relative to the coordinates' size) when the file
/// declares a larger uncertainty: the file's own tolerance is accepted up to this ceiling.
pub const MAX_GAP_REL_COORD: f64 = 1e-3;

/// How far a vertex may be from its edge's curve: [`VERTEX_ON_CURVE_REL_COORD`] of the
/// coordinates' size `scale`, or the file's declared uncertainty `file_mm` where that is
/// larger, up to [`MAX_GAP_REL_COORD`] of `scale`.
pub fn vertex_gap_allowed(scale: f64, file_mm: Option<f64>) -> f64 {
    let floor = VERTEX_ON_CURVE_REL_COORD * scale;
    file_mm.map_or(floor, |u| floor.max(u.min(MAX_GAP_REL_COORD * scale)))
}
