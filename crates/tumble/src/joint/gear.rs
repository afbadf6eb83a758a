//! Gears: a hinge or slider (the follower) whose coordinate is held at a
//! ratio of another's (the leader): `q_follower = ratio q_leader + offset`,
//! both measured from their joints' creation. Two hinges make a gear pair
//! (`ratio` the tooth ratio, negative where the wheels turn opposite
//! ways), a hinge and a slider a rack and pinion (`ratio` in m/rad, the
//! pinion's pitch radius), two sliders a lever or pulley. URDF's
//! `<mimic joint multiplier offset>` is this (`joint::urdf`).
//!
//! The constraint couples four bodies (each joint's two), one scalar row
//! `J = J_follower - ratio J_leader` over the joints' rate Jacobians
//! (`solver::contact_solver::gear`), as Jolt's gear and rack-and-pinion
//! constraints and PhysX's gear joint do. It does no work: an impulse
//! `lambda` on the follower's coordinate comes with `-ratio lambda` on the
//! leader's (a 2:1 follower carries half the leader's torque, the other
//! way), against rates in the ratio `ratio`. A hinge's coordinate is its
//! angle followed across its wrap (by up to pi a sub-step), not the wrapped
//! angle `JointState::position` reads.

use crate::world::{JointId, WorldError};
use serde::{Deserialize, Serialize};

/// A joint's coordinate held at a ratio of another joint's (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gear {
    /// The joint the follower follows (a hinge or a slider).
    pub leader: JointId,
    /// Follower coordinate per unit of the leader's (rad/rad, m/rad, rad/m
    /// or m/m as the two joints are hinges or sliders; any finite value,
    /// 0 holds the follower at `offset`).
    pub ratio: f64,
    /// The follower's coordinate where the leader's is 0 (rad or m).
    #[serde(default)]
    pub offset: f64,
}

impl Gear {
    /// A gear of `ratio` to `leader` with no offset.
    pub fn new(leader: JointId, ratio: f64) -> Gear {
        Gear {
            leader,
            ratio,
            offset: 0.0,
        }
    }

    /// The same with `offset`.
    pub fn with_offset(self, offset: f64) -> Gear {
        Gear { offset, ..self }
    }

    /// Checks the numbers (the joints are the world's to check).
    pub fn validate(&self) -> Result<(), WorldError> {
        for (field, value) in [("gear.ratio", self.ratio), ("gear.offset", self.offset)] {
            if !value.is_finite() {
                return Err(WorldError::BadValue {
                    field,
                    message: format!("must be finite, got {value}"),
                });
            }
        }
        Ok(())
    }

    /// How far `follower` is from where the gear holds it, given both
    /// joints' coordinates (rad or m).
    pub fn error(&self, leader: f64, follower: f64) -> f64 {
        follower - self.ratio * leader - self.offset
    }
}
