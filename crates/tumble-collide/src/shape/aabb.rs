//! Axis-aligned bounding boxes in world coordinates (Ericson 4.2).

use crate::math::DVec3;

/// An axis-aligned box `min <= p <= max` (m, world frame). Components may be
/// infinite for unbounded shapes (half-spaces); they are never NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner (m).
    pub min: DVec3,
    /// Upper corner (m).
    pub max: DVec3,
}

impl Aabb {
    /// The box around a centre with the given (non-negative) half extents.
    pub fn from_center_half_extents(center: DVec3, half: DVec3) -> Aabb {
        Aabb {
            min: center - half,
            max: center + half,
        }
    }

    /// `true` when the boxes share at least one point.
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// `true` when `p` is inside or on the boundary.
    pub fn contains_point(&self, p: DVec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// The box grown by `margin` (m) on every side.
    pub fn expanded(&self, margin: f64) -> Aabb {
        Aabb {
            min: self.min - DVec3::splat(margin),
            max: self.max + DVec3::splat(margin),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
}
