//! The motion of a shape over an interval, as continuous collision sees it:
//! from a start pose to an end pose, the rotation centre moving on a
//! straight line and the orientation turning at a constant rate about one
//! axis (slerp), the screw-free motion of a body that keeps its velocities
//! through the interval (Box2D's `b2Sweep` has the same form).

use super::error::QueryError;
use super::input::checked_pose;
use crate::math::DVec3;
use crate::pose::Pose;

/// A shape's motion over the normalised interval `t` in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Pose of the shape frame at `t = 0`.
    pub start: Pose,
    /// Pose of the shape frame at `t = 1`.
    pub end: Pose,
    /// The point the shape turns about, in the shape frame (m): a body's
    /// centre of mass, which moves on a straight line while the body turns.
    pub center: DVec3,
}

impl Motion {
    /// A shape that does not move.
    pub fn fixed(pose: Pose) -> Motion {
        Motion {
            start: pose,
            end: pose,
            center: DVec3::ZERO,
        }
    }

    /// A shape moving from `start` to `end`, turning about `center` (shape frame, m).
    pub fn new(start: Pose, end: Pose, center: DVec3) -> Motion {
        Motion { start, end, center }
    }

    /// A shape moving from `start` to `end` about its own origin.
    pub fn between(start: Pose, end: Pose) -> Motion {
        Motion::new(start, end, DVec3::ZERO)
    }

    /// The pose at `t` in `[0, 1]`: the centre interpolated linearly, the
    /// orientation by slerp (the shorter way round).
    pub fn pose_at(&self, t: f64) -> Pose {
        if t <= 0.0 {
            return self.start;
        }
        if t >= 1.0 {
            return self.end;
        }
        let (c0, c1) = (self.center_start(), self.center_end());
        let rotation = self.start.rotation.slerp(self.end.rotation, t).normalize();
        let center = c0 + (c1 - c0) * t;
        Pose {
            position: center - rotation * self.center,
            rotation,
        }
    }

    /// The centre's displacement over the interval (m).
    pub fn travel(&self) -> DVec3 {
        self.center_end() - self.center_start()
    }

    /// The angle turned over the interval (rad, in `[0, pi]`).
    pub fn turn(&self) -> f64 {
        let dq = self.end.rotation * self.start.rotation.conjugate();
        2.0 * dq.w.abs().min(1.0).acos()
    }

    fn center_start(&self) -> DVec3 {
        self.start.transform_point(self.center)
    }

    fn center_end(&self) -> DVec3 {
        self.end.transform_point(self.center)
    }

    pub(crate) fn checked(&self, which: &'static str) -> Result<Motion, QueryError> {
        if !self.center.is_finite() {
            return Err(QueryError::BadOption {
                option: "Motion::center",
                expected: "finite",
                value: self
                    .center
                    .to_array()
                    .into_iter()
                    .find(|x| !x.is_finite())
                    .unwrap_or(f64::NAN),
            });
        }
        Ok(Motion {
            start: checked_pose(which, &self.start)?,
            end: checked_pose(which, &self.end)?,
            center: self.center,
        })
    }
}
