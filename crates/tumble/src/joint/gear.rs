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

/// Largest ratio and offset a gear takes, either way: a million turns of
/// the follower per turn of the leader (real gear trains reach thousands),
/// a million rad or m of offset. Beyond, `ratio q_leader + offset` leaves
/// the numbers a coordinate can be told apart in (at `f64::MAX` the error
/// itself overflowed).
pub const MAX_GEAR_NUMBER: f64 = 1e6;

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

    /// Checks the numbers (the joints are the world's to check): finite
    /// and within [`MAX_GEAR_NUMBER`] either way.
    pub fn validate(&self) -> Result<(), WorldError> {
        Gear::check_numbers(self.ratio, self.offset)
    }

    /// [`Gear::validate`]'s check of a ratio and an offset, before a gear
    /// is made of them (a URDF `<mimic>`'s, checked at its element).
    pub fn check_numbers(ratio: f64, offset: f64) -> Result<(), WorldError> {
        for (field, value) in [("gear.ratio", ratio), ("gear.offset", offset)] {
            if !value.is_finite() || value.abs() > MAX_GEAR_NUMBER {
                return Err(WorldError::BadValue {
                    field,
                    message: format!("must be finite and within +-{MAX_GEAR_NUMBER:e}, got {value}"),
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
