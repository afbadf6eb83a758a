//! The ODE state of one body and the kind of motion it has.

use serde::{Deserialize, Serialize};
use tumble_collide::math::{DQuat, DVec3};
use tumble_collide::Pose;

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum BodyKind {
    /// Finite mass; moved by forces, torques, impulses and gravity.
    #[default]
    Dynamic,
    /// Infinite mass, never moves.
    Static,
    /// Infinite mass, moves with a prescribed linear and angular velocity; never pushed.
    Kinematic,
}

/// The integrated state of a rigid body (thesis 3.2): `y = (x, q, P, L)`.
///
/// All in the world frame. The body frame is the centre of mass with the principal axes
/// of inertia, so `q` maps principal-frame vectors to the world.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    /// Position of the centre of mass `x` (m).
    pub position: DVec3,
    /// Orientation `q` of the principal frame, unit quaternion (x, y, z, w).
    pub orientation: DQuat,
    /// Linear momentum `P = M v` (kg m/s).
    pub linear_momentum: DVec3,
    /// Angular momentum about the centre of mass `L = I(t) omega` (kg m^2/s).
    pub angular_momentum: DVec3,
}

impl BodyState {
    /// A state at rest with the given pose.
    pub fn at_rest(pose: Pose) -> BodyState {
        BodyState {
            position: pose.position,
            orientation: pose.rotation,
            linear_momentum: DVec3::ZERO,
            angular_momentum: DVec3::ZERO,
        }
    }

    /// The pose `(x, q)` of the body frame.
    pub fn pose(&self) -> Pose {
        Pose {
            position: self.position,
            rotation: self.orientation,
        }
    }

    /// `true` when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.linear_momentum.is_finite()
            && self.angular_momentum.is_finite()
    }
}
