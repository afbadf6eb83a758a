//! [`Stage::Integrate`](crate::world::Stage::Integrate): the solver's
//! velocities and poses written back into the bodies' momentum state
//! (quarantined bodies restored to their state before the step, stopped);
//! with an explicit integrator, bodies without contacts are advanced by it
//! over the whole step instead.

use super::StepFrame;
use crate::body::{BodyKind, BodyState};
use crate::integrate::{integrate, Integrator};
use crate::solver::contact_solver::SolverBody;
use crate::world::handles::SlotRun;
use crate::world::{BodyEntry, World};
use tumble_collide::Pose;

impl World {
    pub(super) fn integrate_stage(&mut self, f: &mut StepFrame) {
        // Run by run of body slots on the pool (a body's write-back reads
        // its solver body alone); the bodies to quarantine are collected and
        // quarantined afterwards, in slot order.
        let solver = &f.solver;
        let mut runs: Vec<(u32, SlotRun<'_, BodyEntry>, Vec<u32>)> = self
            .bodies
            .runs_mut(WRITEBACK_SLOTS_PER_TASK)
            .into_iter()
            .map(|(first, run)| (first, run, Vec::new()))
            .collect();
        f.pool.for_each_mut(&mut runs, |_, (first, run, refused)| {
            for k in 0..run.len() {
                let slot = *first + k as u32;
                let Some(&si) = solver.slot_to_solver.get(slot as usize) else {
                    break;
                };
                if si == 0 {
                    continue;
                }
                let si = si as usize;
                let sb = &solver.bodies[si];
                let finite = sb.v.is_finite() && sb.w.is_finite() && sb.dp.is_finite() && sb.q.is_finite();
                let Some(e) = run.at_mut(k).filter(|_| !solver.frozen[si] && finite) else {
                    refused.push(slot);
                    continue;
                };
                if !write_back(e, sb, solver.geometric.get(si).copied()) {
                    refused.push(slot);
                }
            }
        });
        let refused: Vec<u32> = runs.into_iter().flat_map(|(_, _, refused)| refused).collect();
        for slot in refused {
            self.quarantine(f, slot);
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

/// Body slots per task of the write-back (a body takes about 20 ns).
const WRITEBACK_SLOTS_PER_TASK: usize = 256;

/// Writes solver body `sb` back into the body of `e` (`geometric`: the
/// geometric stiffness the solver added to its inertia, if any); `false`
/// when the body refused the state (to be quarantined).
fn write_back(e: &mut BodyEntry, sb: &SolverBody, geometric: Option<f64>) -> bool {
    if sb.dynamic {
        // The momentum of the body's own inertia (the solver's may
        // carry geometric stiffness, see `add_geometric_stiffness`).
        let inv_inertia = if geometric.is_some_and(|g| g > 0.0) {
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
            // Finite velocities can still give a non-finite momentum (a
            // huge mass or a near-singular inertia): quarantined like a
            // non-finite solve.
            return false;
        }
    } else {
        let pose = e.body.pose();
        e.body.set_pose(Pose {
            position: pose.position + sb.dp,
            rotation: sb.q,
        });
    }
    e.body.clear_forces();
    true
}
