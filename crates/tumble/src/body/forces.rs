//! Force, torque and impulse accumulators (Baraff & Witkin, "Rigid Body Dynamics",
//! section 2.9; thesis 2.2): a force `F` at world point `p` adds `F` to the total force
//! and `(p - x) x F` to the torque about the centre of mass `x`.
//!
//! Static and kinematic bodies accept the calls (after validation) and ignore them: they
//! are never pushed.

use super::error::BodyError;
use super::rigid_body::RigidBody;
use super::state::BodyKind;
use super::validate::finite_vec;
use tumble_collide::math::DVec3;

impl RigidBody {
    #[inline]
    fn pushable(&self) -> bool {
        self.kind == BodyKind::Dynamic
    }

    /// Adds a force `force` (N) through the centre of mass.
    pub fn apply_force(&mut self, force: DVec3) -> Result<(), BodyError> {
        let force = finite_vec("force", force)?;
        if self.pushable() {
            self.force = finite_vec("accumulated force", self.force + force)?;
        }
        Ok(())
    }

    /// Adds a force `force` (N) acting at world point `point` (m): the force plus the
    /// torque `(point - x) x force` (N m).
    pub fn apply_force_at_point(&mut self, force: DVec3, point: DVec3) -> Result<(), BodyError> {
        let force = finite_vec("force", force)?;
        let point = finite_vec("application point", point)?;
        if self.pushable() {
            let torque = (point - self.state.position).cross(force);
            let new_force = finite_vec("accumulated force", self.force + force)?;
            let new_torque = finite_vec("accumulated torque", self.torque + torque)?;
            self.force = new_force;
            self.torque = new_torque;
        }
        Ok(())
    }

    /// Adds a torque `torque` (N m, world frame) about the centre of mass.
    pub fn apply_torque(&mut self, torque: DVec3) -> Result<(), BodyError> {
        let torque = finite_vec("torque", torque)?;
        if self.pushable() {
            self.torque = finite_vec("accumulated torque", self.torque + torque)?;
        }
        Ok(())
    }

    // The pattern of `apply_force_at_point`, on the momenta instead of the
    // accumulators: both sums are checked before either is written, so a
    // non-finite result leaves the body unchanged.
    /// Applies an impulse `impulse` (N s) at world point `point` (m), changing the momenta
    /// at once: `P += J`, `L += (point - x) x J`.
    pub fn apply_impulse_at_point(&mut self, impulse: DVec3, point: DVec3) -> Result<(), BodyError> {
        let impulse = finite_vec("impulse", impulse)?;
        let point = finite_vec("application point", point)?;
        if self.pushable() {
            let dl = (point - self.state.position).cross(impulse);
            let p = finite_vec("linear momentum", self.state.linear_momentum + impulse)?;
            let l = finite_vec("angular momentum", self.state.angular_momentum + dl)?;
            self.state.linear_momentum = p;
            self.state.angular_momentum = l;
        }
        Ok(())
    }

    /// Applies an impulse `impulse` (N s) through the centre of mass: `P += J`.
    pub fn apply_central_impulse(&mut self, impulse: DVec3) -> Result<(), BodyError> {
        let impulse = finite_vec("impulse", impulse)?;
        if self.pushable() {
            self.state.linear_momentum = finite_vec("linear momentum", self.state.linear_momentum + impulse)?;
        }
        Ok(())
    }

    /// Applies an angular impulse `impulse` (N m s, world frame): `L += impulse`.
    pub fn apply_angular_impulse(&mut self, impulse: DVec3) -> Result<(), BodyError> {
        let impulse = finite_vec("angular impulse", impulse)?;
        if self.pushable() {
            self.state.angular_momentum =
                finite_vec("angular momentum", self.state.angular_momentum + impulse)?;
        }
        Ok(())
    }

    /// Zeroes the force and torque accumulators. The integrators do not clear them: the
    /// world calls this after each step.
    pub fn clear_forces(&mut self) {
        self.force = DVec3::ZERO;
        self.torque = DVec3::ZERO;
    }
}
