//! Joints: descriptions ([`JointDesc`]: fixed, ball, hinge, slider,
//! distance, with limits, motors, springs and friction), the joint frames and the
//! coordinates measured through them ([`JointPose`]), and the state the
//! world reports ([`JointState`]), gears between two joints' coordinates
//! ([`Gear`]), and robots from URDF files ([`urdf`]).
//! The rows the solver relaxes live with the contact rows in
//! `solver::contact_solver::joint`.

mod desc;
mod frame;
mod gear;
pub mod urdf;

pub use crate::world::JointId;
pub use desc::{JointDesc, JointKind, Motor, Spring};
pub use frame::{frame_rotation, unwrap_coordinate, wrap_angle, JointPose};
pub use gear::{Gear, MAX_GEAR_NUMBER};

use tumble_collide::DVec3;

/// A joint as it is now (after the last step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointState {
    /// The joint coordinate: hinge angle or ball twist (rad), slider offset
    /// (m), distance between the anchors (m); 0 for a weld.
    pub position: f64,
    /// Its rate (rad/s or m/s).
    pub rate: f64,
    /// How far the anchors are from where the joint wants them (m): apart
    /// (fixed, ball, hinge), off the axis (slider), off the rod's length or
    /// outside the limits (distance).
    pub linear_error: f64,
    /// How far the frames are turned from what the joint allows (rad): the
    /// whole relative rotation (fixed, slider), the axes' misalignment
    /// (hinge), beyond the swing cone (ball).
    pub angular_error: f64,
    /// Force the joint applied to body A over the last step (N, world).
    pub force: DVec3,
    /// Torque the joint applied to body A about A's anchor (N m, world).
    pub torque: DVec3,
    /// A's anchor (m, world).
    pub anchor_a: DVec3,
    /// B's anchor (m, world).
    pub anchor_b: DVec3,
    /// The joint axis as body B carries it (world, unit).
    pub axis: DVec3,
    /// The rotation of A relative to B since the joint was made, as a
    /// rotation vector (axis times angle, rad, the short way round) in the
    /// world's axes at creation carried with B: what a ball joint's
    /// orientation motor drives to its target (`Motor::Orientation`); on a
    /// hinge its angle about its axis.
    pub rotation: DVec3,
}
