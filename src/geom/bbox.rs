//! Axis-aligned bounding boxes.

use crate::brep::Model;
use glam::DVec3;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (grows from nothing).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// Grows the box to contain `p`.
    pub fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
}

/// Bounding box of a model (see [`Model::bounding_box`]).
pub fn model_bounding_box(model: &Model) -> (DVec3, DVec3) {
    let mut b = Aabb::EMPTY;
    for v in &model.vertices {
        b.add(v.point);
    }
    (b.min, b.max)
}
