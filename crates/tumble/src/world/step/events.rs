//! [`Stage::Events`](crate::world::Stage::Events): contact begin and end
//! events (pairs touching now against the last step), the backstop of
//! quarantine (any state that is not finite or runs away after the step is
//! restored and stopped), sleep, and the clock.

use super::quarantine::runaway;
use super::StepFrame;
use crate::body::BodyKind;
use crate::world::report::ContactEvent;
use crate::world::{BodyId, World};

/// Contact patches per task of the touching pairs on the pool.
const PATCHES_PER_TASK: usize = 1024;

/// Body slots per task of quarantine's last check on the pool.
const SLOTS_PER_TASK: usize = 512;

impl World {
    pub(super) fn events_stage(&mut self, f: &mut StepFrame) {
        // The pairs touching now, found on the pool a run of patches at a
        // time and joined in patch order, from what the solve stage kept of
        // its records (`SolvedPatches`: compact, where the records
        // themselves, read in patch order, are misses from memory).
        let sf = &f.solver;
        let solved = &self.scratch.solved;
        let mut touching: Vec<(BodyId, BodyId)> =
            f.pool
                .flat_map_chunks(&sf.position, PATCHES_PER_TASK, |first, run| {
                    let mut found = Vec::with_capacity(run.len());
                    for (patch, &k) in f.patches[first..first + run.len()].iter().zip(run) {
                        let s = solved.patch(k);
                        // A patch's points share its bodies: one pair a patch.
                        let touches = f
                            .points
                            .of(patch)
                            .iter()
                            .zip(solved.points_of(s, patch.count))
                            .any(|(p, c)| c.pressed || p.contact.distance <= 0.0);
                        if touches {
                            found.push(patch.ids);
                        }
                    }
                    found
                });
        touching.sort_unstable();
        touching.dedup();
        let report = &mut f.report;
        let (mut i, mut j) = (0, 0);
        while i < touching.len() || j < self.touching.len() {
            match (touching.get(i), self.touching.get(j)) {
                (Some(a), Some(b)) if a == b => {
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a < b => {
                    report.events.push(ContactEvent::Begin(a.0, a.1));
                    i += 1;
                }
                (Some(a), None) => {
                    report.events.push(ContactEvent::Begin(a.0, a.1));
                    i += 1;
                }
                (_, Some(b)) => {
                    report.events.push(ContactEvent::End(b.0, b.1));
                    j += 1;
                }
                (None, None) => break,
            }
        }
        report.events.sort_unstable();
        self.touching = touching;

        // Quarantine's last check: bodies advanced by an explicit integrator
        // (which refuses non-finite states already), and the backstop for
        // runaways that solver impulses made. The bodies to restore are
        // found on the pool a run of slots at a time.
        let world: &World = self;
        let restore = f.pool.filter_indices(f.n_slots, SLOTS_PER_TASK, |i| {
            world.bodies.at(i).is_some_and(|e| {
                let dynamic = e.body.kind() == BodyKind::Dynamic;
                !e.body.state().is_finite()
                    || (dynamic && runaway(e.body.velocity(), e.body.angular_velocity(), e.radius))
            })
        });
        for i in restore {
            self.quarantine(f, i);
        }
        if f.settings.sleeping {
            self.update_sleep(&f.labels, f.settings.dt);
        }
        f.report.sleeping_bodies = self.bodies.iter().filter(|(_, e)| e.sleeping).count();
        self.time += f.settings.dt;
        self.step_count += 1;
    }

    /// Accumulates rest time per body and puts islands to sleep whose every
    /// body has rested long enough.
    fn update_sleep(&mut self, labels: &[u32], dt: f64) {
        let s = &self.settings;
        let n = self.bodies.slot_count();
        let mut island_min_rest = vec![f64::INFINITY; n];
        for i in 0..n as u32 {
            let Some(e) = self.bodies.at_mut(i) else { continue };
            if e.body.kind() != BodyKind::Dynamic || e.sleeping {
                continue;
            }
            let slow = e.body.velocity().length() < s.sleep_linear_speed
                && e.body.angular_velocity().length() < s.sleep_angular_speed;
            e.rest_time = if slow { e.rest_time + dt } else { 0.0 };
            let l = labels[i as usize];
            if l != u32::MAX {
                island_min_rest[l as usize] = island_min_rest[l as usize].min(e.rest_time);
            }
        }
        for i in 0..n as u32 {
            let l = labels.get(i as usize).copied().unwrap_or(u32::MAX);
            if l == u32::MAX || island_min_rest[l as usize] < s.time_to_sleep {
                continue;
            }
            let Some(e) = self.bodies.at_mut(i) else { continue };
            e.sleeping = true;
            e.sleep_group = l;
            e.body.stop();
        }
    }
}
