//! A small rigid displacement of one body relative to another, to first
//! order: what a step of a dynamics engine moves the bodies by, given to
//! the queries that look ahead over it (`bvh::collide_moving`,
//! `narrow::contact_shapes_moving`). The point at `origin` moves by
//! `translation` and the point at `x` by `translation + rotation x (x -
//! origin)`, where `rotation` is the rotation vector (rad; angular velocity
//! times duration). Geometry only: no velocities or times here.

use crate::math::DVec3;
use crate::pose::Pose;

/// A first-order rigid displacement (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// The point about which `rotation` acts (m).
    pub origin: DVec3,
    /// How far the point at `origin` moves (m).
    pub translation: DVec3,
    /// Rotation vector (rad): axis times angle.
    pub rotation: DVec3,
}

impl Drift {
    /// No motion at all.
    pub const NONE: Drift = Drift {
        origin: DVec3::ZERO,
        translation: DVec3::ZERO,
        rotation: DVec3::ZERO,
    };

    /// `true` when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.origin.is_finite() && self.translation.is_finite() && self.rotation.is_finite()
    }

    /// `true` for [`Drift::NONE`]-like drifts that move nothing.
    pub fn is_none(&self) -> bool {
        self.translation == DVec3::ZERO && self.rotation == DVec3::ZERO
    }

    /// How far the point at `x` moves (m).
    #[inline]
    pub fn displacement(&self, x: DVec3) -> DVec3 {
        self.translation + self.rotation.cross(x - self.origin)
    }

    /// A bound on how far any point within `radius` of `center` moves (m):
    /// the centre's displacement plus the rotation's reach over the radius.
    #[inline]
    pub fn reach(&self, center: DVec3, radius: f64) -> f64 {
        self.displacement(center).length() + self.rotation.length() * radius
    }

    /// The same drift in the local coordinates of `pose` (a frame the
    /// drift's points are expressed in after `pose.inverse_transform_point`).
    pub fn in_frame_of(&self, pose: &Pose) -> Drift {
        let to_local = pose.rotation.conjugate();
        Drift {
            origin: pose.inverse_transform_point(self.origin),
            translation: to_local * self.translation,
            rotation: to_local * self.rotation,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;

    #[test]
    fn a_small_turn_moves_points_as_the_first_order_rotation_and_reach_bounds_them() {
        // A turn of 0.01 rad about z through (1, 0, 0) plus a shift along x:
        // the point (2, 0, 0) moves by the shift plus 0.01 along y.
        let d = Drift {
            origin: DVec3::X,
            translation: DVec3::new(0.1, 0.0, 0.0),
            rotation: DVec3::new(0.0, 0.0, 0.01),
        };
        let moved = d.displacement(DVec3::new(2.0, 0.0, 0.0));
        assert!((moved - DVec3::new(0.1, 0.01, 0.0)).length() < 1e-15);
        // Every point of a ball moves no farther than its reach.
        let (c, r) = (DVec3::new(1.5, 0.5, -0.3), 0.4);
        let reach = d.reach(c, r);
        for k in 0..50 {
            let t = k as f64 * 0.7;
            let p = c + DVec3::new(t.sin() * t.cos(), t.sin() * t.sin(), t.cos()) * r;
            assert!(d.displacement(p).length() <= reach + 1e-15);
        }
        // The drift seen from a turned and shifted frame moves the same
        // material points by the same (rotated) amounts.
        let pose = Pose::new(DVec3::new(3.0, -1.0, 2.0), DQuat::from_rotation_y(0.7)).unwrap();
        let local = d.in_frame_of(&pose);
        let x = DVec3::new(0.2, 0.9, -1.1);
        let world_move = d.displacement(x);
        let local_move = local.displacement(pose.inverse_transform_point(x));
        assert!((pose.rotation * local_move - world_move).length() < 1e-14);
    }
}
