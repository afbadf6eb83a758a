//! Quarantine, in one place: a body whose state, forces or velocities are
//! not finite, or that would run away (faster than [`RUNAWAY_SPEED`]), is
//! frozen for the step (immovable in the solver, so NaN cannot travel
//! through contacts to its neighbours), then restored to its state before
//! the step, stopped and reported in `StepReport::quarantined`; its
//! joints' and contacts' impulses of the step are forgotten with it. Three
//! checks feed it: before the solve (forces and velocities), at the write
//! back (the solver's result), and after the step (bodies moved by an
//! explicit integrator, and the backstop for everything else).

use super::StepFrame;
use crate::world::report::Quarantined;
use crate::world::World;
use tumble_collide::DVec3;

/// Speed (m/s) beyond which a body counts as a runaway: a third of the speed
/// of light, which no rigid-body simulation means. A body whose centre or
/// surface would move faster (after a force of 1e308 N, say) is treated like
/// one whose state is not finite: frozen for the step, restored to its state
/// before it, stopped and reported in
/// [`StepReport::quarantined`](crate::world::StepReport::quarantined). Finite
/// but absurd speeds would otherwise grow the broad-phase boxes and contact
/// margins over the whole world and overflow a few steps later.
pub const RUNAWAY_SPEED: f64 = 1e8;

/// `true` when a body with velocity `v`, angular velocity `w` and bounding
/// radius `radius` moves some point faster than [`RUNAWAY_SPEED`] (or its
/// velocities are not finite).
pub(crate) fn runaway(v: DVec3, w: DVec3, radius: f64) -> bool {
    let speed = v.length() + w.length() * radius;
    // NaN compares false: a NaN speed is a runaway too.
    speed.is_nan() || speed > RUNAWAY_SPEED
}

/// Before the solve: whether a body with velocities `v`, `w`, linear
/// acceleration `accel`, angular acceleration `alpha` and bounding radius
/// `radius` must be frozen for a step of `dt`.
pub(crate) fn must_freeze(v: DVec3, w: DVec3, accel: DVec3, alpha: DVec3, radius: f64, dt: f64) -> bool {
    let finite = v.is_finite() && w.is_finite() && accel.is_finite() && alpha.is_finite();
    !finite || runaway(v + accel * dt, w + alpha * dt, radius)
}

impl World {
    /// Restores body slot `slot` to its state before the step, stopped,
    /// clears its forces and reports it.
    pub(super) fn quarantine(&mut self, f: &mut StepFrame, slot: u32) {
        let restored = f.stopped_state_before(slot as usize);
        let Some(e) = self.bodies.at_mut(slot) else { return };
        if let Some(restored) = restored {
            // A state that was valid before the step is accepted again;
            // should it not be, the body at least stops where it is.
            if e.body.set_state(restored).is_err() {
                e.body.stop();
            }
        }
        e.body.clear_forces();
        // What the step's contacts and joints did to it is undone with its
        // state: none of it is warm started from or reported as a
        // reaction (a runaway solve leaves impulses of 1e308 or NaN;
        // libFuzzer's `joints` target).
        self.reset_joints_of(slot);
        self.cache.retain(|c| c.key.0 != slot && c.key.1 != slot);
        self.patch_cache.retain(|c| c.key.0 != slot && c.key.1 != slot);
        if let Some(body) = self.bodies.id_at(slot) {
            f.report.quarantined.push(Quarantined { body });
        }
    }
}
