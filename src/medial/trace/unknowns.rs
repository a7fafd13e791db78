//! The layout of the tracer's unknowns, `x = [B (3), r, s₁ (2), s₂ (2), s₃ (2)]` (a fourth
//! element's parameters after those at a junction), and small helpers on them.

use crate::medial::equations::NormalField;
use crate::model::{Element, Model};
use glam::DVec3;
use nalgebra::DVector;

pub(super) fn sorted(mut s: [Element; 3]) -> [Element; 3] {
    s.sort();
    s
}

/// The unknowns `[B, r, s₁, s₂, s₃]` of a seam point.
pub(super) fn seam_x(b: DVec3, r: f64, params: [(f64, f64); 3]) -> DVector<f64> {
    let mut x = DVector::zeros(10);
    x[0] = b.x;
    x[1] = b.y;
    x[2] = b.z;
    x[3] = r;
    for (slot, (u, v)) in params.into_iter().enumerate() {
        x[4 + 2 * slot] = u;
        x[5 + 2 * slot] = v;
    }
    x
}

pub(super) fn v3(x: &DVector<f64>) -> DVec3 {
    DVec3::new(x[0], x[1], x[2])
}

/// The segment parameters of slot `i` of a seam or junction unknown vector.
pub(super) fn slot(x: &DVector<f64>, i: usize) -> [f64; 2] {
    [x[4 + 2 * i], x[5 + 2 * i]]
}

/// Distance from `p` to the segment `[a, b]`.
pub(super) fn to_chord(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    p.distance(a.lerp(b, along_chord(p, a, b)))
}

pub(super) use crate::medial::axis::along_chord;

/// Which pairs of touch points [`touches_meet`] compares.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Pairs {
    /// Two slots of one segment (a face touched twice).
    SameSegment,
    /// Slots of different segments.
    DifferentSegments,
    All,
}

/// True when two touch points of `x` (unknowns over `segs`), among `pairs`, are within `tol`
/// of each other — or one of them is undefined (a pole).
pub(super) fn touches_meet(
    model: &Model,
    segs: &[Element],
    x: &DVector<f64>,
    tol: f64,
    pairs: Pairs,
) -> bool {
    let p: Vec<Option<DVec3>> = (0..segs.len())
        .map(|i| sys_point(model, segs[i], slot(x, i)))
        .collect();
    (0..segs.len()).any(|i| {
        (0..i).any(|j| {
            let same = segs[i] == segs[j];
            let compared = match pairs {
                Pairs::SameSegment => same,
                Pairs::DifferentSegments => !same,
                Pairs::All => true,
            };
            compared
                && match (p[i], p[j]) {
                    (Some(a), Some(b)) => a.distance(b) <= tol,
                    _ => true,
                }
        })
    })
}

/// `triplet` with slot `i` replaced by `to`.
pub(super) fn new_triplet(triplet: &[Element; 3], i: usize, to: Element) -> [Element; 3] {
    let mut t = *triplet;
    t[i] = to;
    t
}

/// The point of segment `seg` at parameters `s`.
pub(super) fn sys_point(model: &Model, seg: Element, s: [f64; 2]) -> Option<DVec3> {
    seg.eval(model, s).map(|e| e.p)
}
