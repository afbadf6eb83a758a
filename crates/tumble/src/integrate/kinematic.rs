//! Kinematic bodies: the pose advances exactly along the prescribed constant screw
//! motion, `x(t+h) = x + h v`, `q(t+h) = exp(h omega / 2) q` (rotation by angle
//! `h |omega|` about `omega`, world frame). Momenta stay zero.

use crate::body::{BodyState, RigidBody};
use tumble_collide::math::DQuat;

#[inline(always)]
pub(crate) fn advance(body: &RigidBody, h: f64) -> BodyState {
    let (v, omega) = body.kinematic_velocity();
    let s = body.state();
    BodyState {
        position: s.position + v * h,
        orientation: (DQuat::from_scaled_axis(omega * h) * s.orientation).normalize(),
        linear_momentum: s.linear_momentum,
        angular_momentum: s.angular_momentum,
    }
}
