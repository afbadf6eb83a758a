//! Where a joint is: each body carries a joint frame (an anchor point and a
//! rotation whose x axis is the joint axis), fixed in the body; placed in
//! the world with the bodies' poses they give the joint's coordinates
//! (hinge angle, slider offset, distance, swing and twist) and errors. The
//! solver and the state the world reports both measure through here.

use super::JointKind;
use tumble_collide::{DQuat, DVec3, Pose};

/// Both joint frames placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointPose {
    /// Anchor of A's frame (m, world).
    pub pa: DVec3,
    /// Anchor of B's frame (m, world).
    pub pb: DVec3,
    /// Lever arm from A's centre of mass to its anchor (m, world).
    pub ra: DVec3,
    /// Lever arm from B's centre of mass (the world origin for the world) to its anchor.
    pub rb: DVec3,
    /// Rotation of A's joint frame (x: the joint axis as A carries it).
    pub fa: DQuat,
    /// Rotation of B's joint frame.
    pub fb: DQuat,
}

impl JointPose {
    /// The frames `local_a`, `local_b` (in the body frames) placed by the
    /// body poses: centre of mass `x` and orientation `q` of each side.
    pub fn new(xa: DVec3, qa: DQuat, local_a: &Pose, xb: DVec3, qb: DQuat, local_b: &Pose) -> JointPose {
        let ra = qa * local_a.position;
        let rb = qb * local_b.position;
        JointPose {
            pa: xa + ra,
            pb: xb + rb,
            ra,
            rb,
            fa: qa * local_a.rotation,
            fb: qb * local_b.rotation,
        }
    }

    /// Axis `i` (0 = x, the joint axis) of A's frame, world.
    pub fn axis_a(&self, i: usize) -> DVec3 {
        self.fa * DVec3::AXES[i]
    }

    /// Axis `i` of B's frame, world.
    pub fn axis_b(&self, i: usize) -> DVec3 {
        self.fb * DVec3::AXES[i]
    }

    /// A's frame relative to B's, in B's frame, with a non-negative scalar part.
    fn relative(&self) -> DQuat {
        let q = self.fb.conjugate() * self.fa;
        if q.w < 0.0 {
            -q
        } else {
            q
        }
    }

    /// A's frame relative to B's as a rotation vector in B's frame (rad,
    /// the short way round).
    pub fn relative_rotation(&self) -> DVec3 {
        self.relative().to_scaled_axis()
    }

    /// Twist of A's frame relative to B's about the joint axis (rad, in
    /// [-pi, pi]): the hinge angle, the ball joint's twist. The twist part of
    /// the swing-twist split of the relative rotation, so a swing (axes not
    /// aligned) does not change it.
    pub fn twist(&self) -> f64 {
        let q = self.relative();
        2.0 * q.x.atan2(q.w)
    }

    /// Angle between the two frames' axes (rad, in [0, pi]).
    pub fn swing(&self) -> f64 {
        self.axis_a(0).dot(self.axis_b(0)).clamp(-1.0, 1.0).acos()
    }

    /// Offset of A's anchor from B's along B's axis (m): the slider coordinate.
    pub fn offset(&self) -> f64 {
        self.axis_b(0).dot(self.pa - self.pb)
    }

    /// Distance between the anchors (m).
    pub fn distance(&self) -> f64 {
        (self.pa - self.pb).length()
    }

    /// The coordinate a gear reads (`joint::Gear`): a hinge's angle (rad,
    /// [`Self::twist`]) or a slider's offset (m, [`Self::offset`]); 0 for
    /// other kinds.
    pub fn coordinate(&self, kind: JointKind) -> f64 {
        match kind {
            JointKind::Hinge => self.twist(),
            JointKind::Slider => self.offset(),
            _ => 0.0,
        }
    }

    /// The rate of [`Self::coordinate`] as a row over the two bodies'
    /// velocities: `(linear, angular)` for A and for B, so that the rate is
    /// `lin_a . vA + ang_a . wA + lin_b . vB + ang_b . wB`. A hinge turns
    /// about B's axis `n`: `n . (wA - wB)`. A slider's offset `n . d` (`d`
    /// from B's anchor to A's, `n` fixed in B) changes at `n . (vA + wA x
    /// rA - vB - wB x rB) + (wB x n) . d`.
    pub fn coordinate_rows(&self, kind: JointKind) -> [(DVec3, DVec3); 2] {
        let n = self.axis_b(0);
        match kind {
            JointKind::Hinge => [(DVec3::ZERO, n), (DVec3::ZERO, -n)],
            JointKind::Slider => {
                let d = self.pa - self.pb;
                [(n, self.ra.cross(n)), (-n, n.cross(d) - self.rb.cross(n))]
            }
            _ => [(DVec3::ZERO, DVec3::ZERO); 2],
        }
    }

    /// The rotation taking B's frame onto A's, as a world rotation vector
    /// (axis times angle, rad): zero when the frames agree.
    pub fn rotation_error(&self) -> DVec3 {
        let mut q = self.fa * self.fb.conjugate();
        if q.w < 0.0 {
            q = -q;
        }
        q.to_scaled_axis()
    }

    /// The rotation taking the frame `target` (B's frame turned by it, in
    /// B's frame: where a ball motor wants A's frame) onto A's, as a world
    /// rotation vector, the short way round: zero when A's frame is there.
    pub fn rotation_error_from(&self, target: DQuat) -> DVec3 {
        let mut q = self.fa * (self.fb * target).conjugate();
        if q.w < 0.0 {
            q = -q;
        }
        q.to_scaled_axis()
    }
}

/// A joint coordinate followed across a hinge's wrap: `raw` (as
/// [`JointPose::coordinate`] reads it, a hinge's in [-pi, pi]) taken as
/// the value nearest `last` (rad or m; a slider's is `raw` itself), so that
/// a wheel that has turned three times reads 6 pi.
pub fn unwrap_coordinate(kind: JointKind, last: f64, raw: f64) -> f64 {
    match kind {
        JointKind::Hinge => last + wrap_angle(raw - last),
        _ => raw,
    }
}

/// `angle` wrapped into (-pi, pi] (differences of hinge angles).
pub fn wrap_angle(angle: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let a = angle.rem_euclid(TAU);
    if a > PI {
        a - TAU
    } else {
        a
    }
}

/// A joint frame whose x axis is `axis` (unit), fixed up to a rotation
/// about it in a deterministic way.
pub fn frame_rotation(axis: DVec3) -> DQuat {
    DQuat::from_rotation_arc(DVec3::X, axis)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(q: DQuat) -> JointPose {
        JointPose::new(
            DVec3::ZERO,
            q,
            &Pose::IDENTITY,
            DVec3::ZERO,
            DQuat::IDENTITY,
            &Pose::IDENTITY,
        )
    }

    #[test]
    fn twist_is_the_angle_about_the_axis_and_ignores_swing() {
        for angle in [-3.0, -1.0, 0.0, 0.5, 2.9] {
            let p = pose(DQuat::from_rotation_x(angle));
            assert!((p.twist() - angle).abs() < 1e-12, "{angle}: {}", p.twist());
            assert!(p.swing() < 1e-7);
            // A swing of 0.3 rad about y, applied after the twist, leaves it.
            let p = pose(DQuat::from_rotation_y(0.3) * DQuat::from_rotation_x(angle));
            assert!((p.swing() - 0.3).abs() < 1e-12);
        }
    }

    #[test]
    fn rotation_error_is_the_relative_rotation_vector() {
        let v = DVec3::new(0.1, -0.2, 0.3);
        let p = pose(DQuat::from_scaled_axis(v));
        assert!((p.rotation_error() - v).length() < 1e-12);
    }

    #[test]
    fn wrap_angle_stays_in_range() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
        assert!((wrap_angle(-3.0 * PI / 2.0) - PI / 2.0).abs() < 1e-12);
        assert!((wrap_angle(0.25) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn frame_rotation_carries_x_onto_the_axis() {
        for axis in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            assert!((frame_rotation(axis) * DVec3::X - axis).length() < 1e-12);
        }
    }
}
