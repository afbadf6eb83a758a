//! Rigid poses (position + unit quaternion) as used at every API boundary.
//!
//! A pose maps body-frame points to world-frame points: `p_world = R p_body + x`.
//! Constructors validate: finite components and a quaternion of unit length
//! (within [`Pose::UNIT_TOLERANCE`]); a non-unit quaternion is an error rather than
//! silently renormalised, because a user passing (1, 1, 1, 1) has most likely made a
//! mistake (use [`Pose::new_normalized`] to opt into normalisation).

use crate::math::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// Why a pose was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// A position component is NaN or infinite.
    #[error("pose position must be finite, got {0:?}")]
    NonFinitePosition(DVec3),
    /// A quaternion component is NaN or infinite.
    #[error("pose orientation must be finite, got {0:?}")]
    NonFiniteRotation(DQuat),
    /// The quaternion's length is not 1 within tolerance (or is zero).
    #[error("pose orientation must be a unit quaternion (x, y, z, w), got length {length}")]
    NonUnitRotation {
        /// The length that was found.
        length: f64,
    },
}

/// Position and orientation of a rigid frame in the world.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Origin of the frame in world coordinates (m).
    pub position: DVec3,
    /// Orientation, unit quaternion (x, y, z, w).
    pub rotation: DQuat,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity pose.
    pub const IDENTITY: Pose = Pose {
        position: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
    };

    /// How far `|q|` may be from 1 before a quaternion is rejected.
    pub const UNIT_TOLERANCE: f64 = 1e-6;

    /// A validated pose; the quaternion is renormalised exactly if it is within
    /// [`Self::UNIT_TOLERANCE`] of unit length, rejected otherwise.
    pub fn new(position: DVec3, rotation: DQuat) -> Result<Pose, PoseError> {
        if !position.is_finite() {
            return Err(PoseError::NonFinitePosition(position));
        }
        if !rotation.is_finite() {
            return Err(PoseError::NonFiniteRotation(rotation));
        }
        let length = rotation.length();
        if (length - 1.0).abs() > Self::UNIT_TOLERANCE {
            return Err(PoseError::NonUnitRotation { length });
        }
        Ok(Pose {
            position,
            rotation: rotation / length,
        })
    }

    /// Like [`Pose::new`] but any non-zero finite quaternion is normalised.
    pub fn new_normalized(position: DVec3, rotation: DQuat) -> Result<Pose, PoseError> {
        let length = rotation.length();
        if length.is_nan() || length <= 1e-12 || !length.is_finite() {
            if !rotation.is_finite() {
                return Err(PoseError::NonFiniteRotation(rotation));
            }
            return Err(PoseError::NonUnitRotation { length });
        }
        Self::new(position, rotation / length)
    }

    /// A pure translation.
    pub fn from_translation(position: DVec3) -> Pose {
        Pose {
            position,
            rotation: DQuat::IDENTITY,
        }
    }

    /// Maps a body-frame point to the world frame.
    #[inline]
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.position
    }

    /// Rotates a body-frame direction into the world frame.
    #[inline]
    pub fn transform_vector(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }

    /// Maps a world-frame point into this frame.
    #[inline]
    pub fn inverse_transform_point(&self, p: DVec3) -> DVec3 {
        self.rotation.inverse() * (p - self.position)
    }

    /// The inverse pose.
    pub fn inverse(&self) -> Pose {
        let r = self.rotation.inverse();
        Pose {
            position: -(r * self.position),
            rotation: r,
        }
    }

    /// `self * other`: applies `other` first, then `self`.
    pub fn mul_pose(&self, other: &Pose) -> Pose {
        Pose {
            position: self.transform_point(other.position),
            rotation: (self.rotation * other.rotation).normalize(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input() {
        assert!(matches!(
            Pose::new(DVec3::new(f64::NAN, 0.0, 0.0), DQuat::IDENTITY),
            Err(PoseError::NonFinitePosition(_))
        ));
        assert!(matches!(
            Pose::new(DVec3::ZERO, DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0)),
            Err(PoseError::NonUnitRotation { .. })
        ));
        assert!(matches!(
            Pose::new_normalized(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)),
            Err(PoseError::NonUnitRotation { .. })
        ));
        assert!(Pose::new_normalized(DVec3::ZERO, DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0)).is_ok());
    }

    #[test]
    fn inverse_round_trips() {
        let p = Pose::new(
            DVec3::new(1.0, -2.0, 0.5),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.2, 0.3, -0.4),
        )
        .unwrap();
        let x = DVec3::new(0.3, 0.7, -1.1);
        let back = p.inverse().transform_point(p.transform_point(x));
        assert!((back - x).length() < 1e-14);
        assert!((p.inverse_transform_point(p.transform_point(x)) - x).length() < 1e-14);
        let id = p.mul_pose(&p.inverse());
        assert!(id.position.length() < 1e-14);
    }
}
