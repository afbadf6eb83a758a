//! [`Stage::Integrate`](crate::world::Stage::Integrate): the solver's
//! velocities and poses written back into the bodies' momentum state
//! (quarantined bodies restored to their state before the step, stopped);
//! with an explicit integrator, bodies without contacts are advanced by it
//! over the whole step instead.

use super::StepFrame;
use crate::body::{BodyKind, BodyState};
use crate::integrate::{integrate, Integrator};
use crate::solver::contact_solver::SolverBody;
use crate::world::World;
use tumble_collide::Pose;

impl World {
    pub(super) fn integrate_stage(&mut self, f: &mut StepFrame) {
        for k in 1..f.solver.slots.len() {
            let (slot, sb) = (f.solver.slots[k], f.solver.bodies[k]);
            let finite = sb.v.is_finite() && sb.w.is_finite() && sb.dp.is_finite() && sb.q.is_finite();
            if f.solver.frozen[k] || !finite {
                self.quarantine(f, slot);
                continue;
            }
            let e = self.bodies.at_mut(slot).expect("live");
            if sb.dynamic {
                // The momentum of the body's own inertia (the solver's may
                // carry geometric stiffness, see `add_geometric_stiffness`).
                let inv_inertia = if f.solver.geometric.get(k).is_some_and(|&g| g > 0.0) {
                    SolverBody::world_inverse_inertia(sb.q, e.body.inv_principal_inertia())
                } else {
                    sb.inv_inertia
                };
                let state = BodyState {
                    position: e.body.position() + sb.dp,
                    orientation: sb.q,
                    linear_momentum: sb.v * e.body.mass(),
                    angular_momentum: inv_inertia.inverse() * sb.w,
                };
                if e.body.set_state(state).is_err() {
                    // Finite velocities can still give a non-finite momentum
                    // (a huge mass or a near-singular inertia): quarantined
                    // like a non-finite solve.
                    self.quarantine(f, slot);
                    continue;
                }
            } else {
                let pose = e.body.pose();
                e.body.set_pose(Pose {
                    position: pose.position + sb.dp,
                    rotation: sb.q,
                });
            }
            e.body.clear_forces();
        }
        // The integrator story: every integrator but the default advances the
        // awake dynamic bodies that have no contact patch and no joint (free
        // flight) over the whole step, on their momentum state; every other
        // body is advanced by the solver's semi-implicit sub-steps, the only
        // integration the contact and joint rows are built around.
        if f.settings.integrator != Integrator::SemiImplicitEuler {
            for i in 0..f.n_slots as u32 {
                let Some(e) = self.bodies.at_mut(i) else { continue };
                if e.body.kind() == BodyKind::Dynamic && !e.sleeping && !f.solver.has_contact[i as usize] {
                    let advanced = integrate(
                        std::slice::from_mut(&mut e.body),
                        f.settings.gravity,
                        f.settings.dt,
                        f.settings.integrator,
                    );
                    e.body.clear_forces();
                    // A refused step (a state that would become non-finite)
                    // is quarantined like a non-finite solve.
                    if advanced.is_err() {
                        self.quarantine(f, i);
                    }
                }
            }
        }
    }
}
