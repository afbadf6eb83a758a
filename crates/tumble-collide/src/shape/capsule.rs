//! Capsule: the points within `radius` of a segment on the body z axis.

use super::{check_non_negative, check_positive, Aabb, ShapeError};
use crate::math::DVec3;
use crate::pose::Pose;

/// A capsule: all points within `radius` (m) of the segment from
/// `(0, 0, -half_height)` to `(0, 0, +half_height)` (m).
// The shapes' common serde header (see sphere.rs), routed through
// `CapsuleParts` so a stored negative half height is refused as `new` does.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(
    try_from = "super::serde_parts::CapsuleParts",
    into = "super::serde_parts::CapsuleParts"
)]
pub struct Capsule {
    radius: f64,
    half_height: f64,
}

impl Capsule {
    /// A capsule; `radius` must be finite and > 0, `half_height` finite and
    /// >= 0 (zero gives a sphere), both at most [`super::MAX_DIMENSION`] (m).
    pub fn new(radius: f64, half_height: f64) -> Result<Capsule, ShapeError> {
        check_positive("capsule", "radius", radius)?;
        // `mass::solid_capsule` keeps its own `>= 0` test (it reports a
        // MassError) and must accept what this accepts.
        check_non_negative("capsule", "half_height", half_height)?;
        Ok(Capsule { radius, half_height })
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Half the length of the core segment (m).
    pub fn half_height(&self) -> f64 {
        self.half_height
    }

    /// The core segment's end points in the body frame: `-h` then `+h` on z.
    pub fn segment(&self) -> [DVec3; 2] {
        [
            DVec3::new(0.0, 0.0, -self.half_height),
            DVec3::new(0.0, 0.0, self.half_height),
        ]
    }

    /// The core segment's end points in the world frame.
    pub fn world_segment(&self, pose: &Pose) -> [DVec3; 2] {
        let [p, q] = self.segment();
        [pose.transform_point(p), pose.transform_point(q)]
    }

    /// Farthest point along `dir` (body frame).
    pub fn support(&self, dir: DVec3) -> DVec3 {
        let z = if dir.z >= 0.0 {
            self.half_height
        } else {
            -self.half_height
        };
        DVec3::new(0.0, 0.0, z) + dir.normalize_or_zero() * self.radius
    }

    /// World bounding box at `pose`.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let [p, q] = self.world_segment(pose);
        Aabb {
            min: p.min(q) - DVec3::splat(self.radius),
            max: p.max(q) + DVec3::splat(self.radius),
        }
    }
}
