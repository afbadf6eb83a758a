//! [`Stage::Broad`](crate::world::Stage::Broad): every active body's box,
//! swept over the step, goes to sweep-and-prune; the overlapping pairs (and
//! every body against each unbounded one) become the step's candidate
//! pairs, sorted; sleeping islands that an active body comes close to wake.

use super::margins::{body_aabb, is_active, velocities};
use super::StepFrame;
use crate::body::BodyKind;
use crate::world::World;
use tumble_collide::broad::SweepAndPrune;

/// Body slots per task of the swept boxes on the pool (a box costs about
/// 50 ns: fewer would cost more to hand over than to compute).
const SWEPT_BOXES_PER_TASK: usize = 512;

/// How much the broad phase enlarges a body's box in its sorted lists, as a
/// fraction of the box's largest side ([`SweepAndPrune::with_enlargement`]).
/// A body that rests, or moves by less than that since its box was last
/// listed, costs the sorts nothing. The pairs are those of the boxes
/// themselves either way, so this changes no pair and no trajectory, only
/// how often the lists are sorted. Without it the large pyramid's and the
/// ragdoll pile's lists were rebuilt at every step (their layers' equal
/// values, reordered by any jitter, made the insertion sorts fail). At a
/// tenth, the extra pairs of the enlarged boxes, filtered out at every
/// update, cost the pile of 1,000 what its sorts saved.
const BOX_ENLARGEMENT: f64 = 0.1;

/// The world's broad phase, empty (the one place that configures it).
pub(crate) fn new_broad_phase() -> SweepAndPrune {
    SweepAndPrune::new().with_enlargement(BOX_ENLARGEMENT)
}

impl World {
    pub(super) fn broad_stage(&mut self, f: &mut StepFrame) {
        let (n_slots, dt) = (f.n_slots, f.settings.dt);
        let mut events = Vec::new();
        // Wide enough for either kind of pair's margin.
        let margin = f.settings.contact_margin.max(f.settings.mesh_contact_margin);
        // Swept boxes: where each bounded body can be during the step
        // (`None` for unbounded shapes, which are everywhere), computed on
        // the pool a run of slots at a time (a box depends on its body alone).
        let world: &World = self;
        f.swept = f.pool.map_indices(n_slots, SWEPT_BOXES_PER_TASK, |i| {
            let e = world.bodies.at(i)?;
            e.proxy?;
            let (v, w) = velocities(e);
            let fatten = margin + (v.length() + w.length() * e.radius) * dt;
            Some(body_aabb(e, fatten))
        });
        for i in 0..n_slots as u32 {
            let (Some(e), Some(aabb)) = (self.bodies.at(i), f.swept[i as usize]) else {
                continue;
            };
            let Some(proxy) = e.proxy else { continue };
            if !is_active(e) {
                continue;
            }
            if let Err(err) = self.broad.set_aabb(proxy, aabb) {
                f.report
                    .warnings
                    .push(format!("body slot {i}: broad phase: {err}"));
            }
        }
        // Its axes sorted side by side on the threads (the same pairs).
        self.broad.update_on(&mut events, &f.pool);
        let mut pairs = Vec::new();
        self.broad.user_pairs(&mut pairs);
        for &u in &self.unbounded {
            for i in 0..n_slots as u32 {
                if i != u
                    && self
                        .bodies
                        .at(i)
                        .is_some_and(|e| e.body.kind() != BodyKind::Static)
                {
                    pairs.push((u.min(i), u.max(i)));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        // Jointed bodies, bodies of one non-colliding group and excluded
        // pairs do not touch.
        self.filter_contact_pairs(&mut pairs);
        f.report.broad_pairs = pairs.len();
        // Nothing to wake when no body sleeps (a landing pile of 10,000
        // skips a pass over its 100,000 pairs).
        if (0..n_slots as u32).any(|i| self.bodies.at(i).is_some_and(|e| e.sleeping)) {
            self.wake_near_active(&pairs);
        }
        f.pairs = pairs;
    }

    /// Wakes the sleeping islands that an active body has come close to
    /// (a candidate pair of `pairs`) or is jointed to, until none is left.
    fn wake_near_active(&mut self, pairs: &[(u32, u32)]) {
        let links = self.joint_links();
        loop {
            let mut woke = false;
            for &(a, b) in pairs.iter().chain(&links) {
                let (ea, eb) = (self.bodies.at(a).expect("live"), self.bodies.at(b).expect("live"));
                let group = match (is_active(ea), is_active(eb)) {
                    (true, false) if eb.sleeping => Some(b),
                    (false, true) if ea.sleeping => Some(a),
                    _ => None,
                };
                if let Some(slot) = group {
                    self.wake_island_of(slot);
                    woke = true;
                }
            }
            if !woke {
                break;
            }
        }
    }

    /// Wakes every body of the sleeping island that contains `slot`.
    pub(super) fn wake_island_of(&mut self, slot: u32) {
        let group = self.bodies.at(slot).map(|e| e.sleep_group).unwrap_or(u32::MAX);
        for i in 0..self.bodies.slot_count() as u32 {
            if let Some(e) = self.bodies.at_mut(i) {
                if e.sleeping && (i == slot || (group != u32::MAX && e.sleep_group == group)) {
                    e.sleeping = false;
                    e.rest_time = 0.0;
                }
            }
        }
    }
}
