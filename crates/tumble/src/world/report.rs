//! What `World::step` reports: per-stage timings, counters, warnings and
//! quarantined bodies; and the contact events of the step.

use super::handles::BodyId;
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// The stages of one step, in order (see docs/pipeline.md). The same names
/// are used by the step's functions and by the profile in [`StepReport`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Stage {
    /// Gravity, user forces and torques, damping.
    Forces,
    /// World bounding boxes (fattened by margin and motion) and sweep-and-prune pairs.
    Broad,
    /// Shape-pair contact generation within the margin; manifolds matched to
    /// the previous step's for warm starting.
    Narrow,
    /// Islands of bodies linked by contacts; sleeping and waking.
    Islands,
    /// Contact constraints: sub-stepped PGS with patch friction and
    /// split-impulse push-out (or the direct LCP).
    Solve,
    /// Poses and momenta written back; free bodies advanced by the chosen integrator.
    Integrate,
    /// Contact begin/end events; non-finite states quarantined.
    Events,
}

impl Stage {
    /// All stages in pipeline order.
    pub const ALL: [Stage; 7] = [
        Stage::Forces,
        Stage::Broad,
        Stage::Narrow,
        Stage::Islands,
        Stage::Solve,
        Stage::Integrate,
        Stage::Events,
    ];
}

/// A contact starting or ending between two bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum ContactEvent {
    /// The bodies touch (have contact points) this step and did not last step.
    Begin(BodyId, BodyId),
    /// The bodies touched last step and do not now.
    End(BodyId, BodyId),
}

/// A body whose state became non-finite during the step: it was restored to
/// its state before the step and stopped, instead of spreading NaN.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quarantined {
    /// Which body.
    pub body: BodyId,
}

/// Returned by every step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepReport {
    /// Wall time per stage, in [`Stage::ALL`] order.
    pub stage_time: [Duration; 7],
    /// Bodies that were simulated (awake, dynamic or kinematic).
    pub awake_bodies: usize,
    /// Bodies asleep after the step.
    pub sleeping_bodies: usize,
    /// Overlapping bounding-box pairs from the broad phase.
    pub broad_pairs: usize,
    /// Contact points handed to the solver.
    pub contacts: usize,
    /// Contact points that matched one of the previous step (warm started).
    pub warm_started: usize,
    /// Islands of awake bodies.
    pub islands: usize,
    /// Sub-steps run.
    pub substeps: u32,
    /// Velocity iterations per sub-step.
    pub iterations: u32,
    /// What the solver left unsolved (m/s): the largest violation of a
    /// non-penetration row, `max(0, -(v_n + s/h))`, after the last sub-step's
    /// velocity iterations (before the push-out and the position update).
    /// Zero for an exact solve; PGS approaches it as iterations rise.
    pub solver_residual: f64,
    /// Deepest penetration among the contacts at the start of the step (m, >= 0).
    pub max_penetration: f64,
    /// Human-readable warnings (e.g. a shape pair without a handler).
    pub warnings: Vec<String>,
    /// Bodies stopped because their state became non-finite.
    pub quarantined: Vec<Quarantined>,
    /// Contact begin/end events, sorted.
    pub events: Vec<ContactEvent>,
}

impl StepReport {
    /// Time spent in one stage.
    pub fn time(&self, stage: Stage) -> Duration {
        self.stage_time[stage as usize]
    }

    /// Total wall time of the step.
    pub fn total_time(&self) -> Duration {
        self.stage_time.iter().sum()
    }
}
