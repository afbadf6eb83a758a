//! Sphere centred on the body origin.

use super::{check_positive, Aabb, ShapeError};
use crate::math::DVec3;
use crate::pose::Pose;

/// A ball of `radius` (m) around the body origin.
// The derive and serde header every shape file repeats (cuboid.rs, capsule.rs,
// halfspace.rs, convex_hull.rs): the attribute must name the type's own Parts
// form, here so that a read radius goes through `Sphere::new`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(
    try_from = "super::serde_parts::SphereParts",
    into = "super::serde_parts::SphereParts"
)]
pub struct Sphere {
    radius: f64,
}

impl Sphere {
    /// A sphere; `radius` must be finite, > 0 and at most
    /// [`super::MAX_DIMENSION`] (m).
    pub fn new(radius: f64) -> Result<Sphere, ShapeError> {
        check_positive("sphere", "radius", radius)?;
        Ok(Sphere { radius })
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Farthest point along `dir` (body frame); the centre for a zero `dir`.
    pub fn support(&self, dir: DVec3) -> DVec3 {
        dir.normalize_or_zero() * self.radius
    }

    /// World bounding box at `pose`.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        Aabb::from_center_half_extents(pose.position, DVec3::splat(self.radius))
    }
}
