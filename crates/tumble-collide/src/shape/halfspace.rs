//! Half-space: the infinite solid below a plane (ground, walls).

use super::{Aabb, ShapeError};
use crate::math::DVec3;
use crate::pose::Pose;

/// The solid `normal . x <= offset` in the body frame; `normal` is the unit
/// outward normal (pointing out of the solid), `offset` in m.
// Same header as the other shape files (sphere.rs, ...), with its own Parts
// form: `HalfSpaceParts` checks like `new` but keeps the normal bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(
    try_from = "super::serde_parts::HalfSpaceParts",
    into = "super::serde_parts::HalfSpaceParts"
)]
pub struct HalfSpace {
    normal: DVec3,
    offset: f64,
}

impl HalfSpace {
    /// How far `|normal|` may be from 1 before it is rejected.
    pub const UNIT_TOLERANCE: f64 = 1e-6;

    /// A half-space; `normal` must be finite and unit (within
    /// [`Self::UNIT_TOLERANCE`], then renormalised), `offset` finite (m).
    pub fn new(normal: DVec3, offset: f64) -> Result<HalfSpace, ShapeError> {
        let length = normal.length();
        if !normal.is_finite() || (length - 1.0).abs() > Self::UNIT_TOLERANCE {
            return Err(ShapeError::NotUnit {
                shape: "half_space",
                name: "normal",
                value: normal,
                length,
            });
        }
        if !super::within_dimension_limit(offset) {
            return Err(ShapeError::BadDimension {
                shape: "half_space",
                name: "offset",
                expected: "within 1e36 of 0",
                value: offset,
            });
        }
        Ok(HalfSpace {
            normal: normal / length,
            offset,
        })
    }

    /// A half-space from a normal and offset already checked by [`Self::new`]
    /// (kept bit for bit).
    pub(crate) fn from_raw(normal: DVec3, offset: f64) -> HalfSpace {
        HalfSpace { normal, offset }
    }

    /// The ground `z <= 0`.
    pub fn ground() -> HalfSpace {
        HalfSpace {
            normal: DVec3::Z,
            offset: 0.0,
        }
    }

    /// Unit outward normal (body frame).
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// Plane offset along the normal (m, body frame).
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// The plane in world coordinates at `pose`: `(normal, offset)` with the
    /// solid at `normal . x <= offset`.
    pub fn world_plane(&self, pose: &Pose) -> (DVec3, f64) {
        let n = pose.transform_vector(self.normal);
        (n, self.offset + n.dot(pose.position))
    }

    /// World bounding box: infinite except along an axis the plane is
    /// perpendicular to (then bounded above or below by the plane).
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let (n, d) = self.world_plane(pose);
        let mut min = DVec3::splat(f64::NEG_INFINITY);
        let mut max = DVec3::splat(f64::INFINITY);
        for axis in 0..3 {
            let c = n[axis];
            if (c.abs() - 1.0).abs() <= 1e-12 {
                if c > 0.0 {
                    max[axis] = d;
                } else {
                    min[axis] = -d;
                }
            }
        }
        Aabb { min, max }
    }
}
