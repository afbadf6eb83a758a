//! What `World::step` reports: per-stage timings, counters, warnings and
//! quarantined bodies; and the contact events of the step.

use super::handles::BodyId;
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// The stages of one step, in order (see docs/pipeline.md). Each is one
/// function over the step's `StepFrame` (`World::step`
/// runs [`Stage::ALL`] and times each); the same names are used by those
/// functions, the profile in [`StepReport`] and the docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Stage {
    /// The state before the step is kept (for quarantine); forces are read in solve.
    Forces,
    /// World bounding boxes (fattened by margin and motion) and sweep-and-prune pairs.
    Broad,
    /// Shape-pair contact generation within the margin, over pairs on the
    /// thread pool; contacts matched to the previous step's for warm starting.
    Narrow,
    /// Islands of bodies linked by contacts; sleeping and waking.
    Islands,
    /// Contact constraints: sub-stepped PGS with patch friction and
    /// split-impulse push-out (or the direct LCP); timed by [`SolveStage`].
    Solve,
    /// Poses and momenta written back; free bodies advanced by the chosen integrator.
    Integrate,
    /// Fast bodies swept from their pose before the step to the one after
    /// it and put back at their first time of impact (continuous collision).
    Continuous,
    /// Contact begin/end events; non-finite states quarantined; sleep.
    Events,
}

impl Stage {
    /// All stages in pipeline order.
    pub const ALL: [Stage; 8] = [
        Stage::Forces,
        Stage::Broad,
        Stage::Narrow,
        Stage::Islands,
        Stage::Solve,
        Stage::Integrate,
        Stage::Continuous,
        Stage::Events,
    ];

    /// The stage's name in profiles, Python and the docs (snake case).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Forces => "forces",
            Stage::Broad => "broad",
            Stage::Narrow => "narrow",
            Stage::Islands => "islands",
            Stage::Solve => "solve",
            Stage::Integrate => "integrate",
            Stage::Continuous => "continuous",
            Stage::Events => "events",
        }
    }
}

/// The timed parts of [`Stage::Solve`], in the order they first run (the
/// sub-step parts repeat every sub-step; their times add up). Box2D v3's
/// solver stages are the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum SolveStage {
    /// Solver bodies, constraint rows, effective masses, colouring, quarantine.
    Prepare,
    /// Newton's restitution law on colliding contacts (before the sub-steps).
    Restitution,
    /// Gravity, forces and damping into the velocities (every sub-step).
    IntegrateVelocities,
    /// Separations refreshed, accumulated impulses applied (every sub-step;
    /// a joint island's in its first velocity pass, timed in `Iterate`).
    WarmStart,
    /// Velocity iterations over the coloured rows (every sub-step).
    Iterate,
    /// Position correction by split-impulse push-out (every sub-step; its
    /// first pass is made with the last velocity pass, timed in
    /// `Iterate`).
    Relax,
    /// Orientations and displacements advanced (every sub-step).
    IntegratePositions,
    /// Impulses stored for warm starting and reported with the contacts.
    StoreImpulses,
}

impl SolveStage {
    /// All solve sub-stages in order.
    pub const ALL: [SolveStage; 8] = [
        SolveStage::Prepare,
        SolveStage::Restitution,
        SolveStage::IntegrateVelocities,
        SolveStage::WarmStart,
        SolveStage::Iterate,
        SolveStage::Relax,
        SolveStage::IntegratePositions,
        SolveStage::StoreImpulses,
    ];

    /// The sub-stage's name in profiles, Python and the docs (snake case).
    pub fn name(self) -> &'static str {
        match self {
            SolveStage::Prepare => "prepare",
            SolveStage::Restitution => "restitution",
            SolveStage::IntegrateVelocities => "integrate_velocities",
            SolveStage::WarmStart => "warm_start",
            SolveStage::Iterate => "iterate",
            SolveStage::Relax => "relax",
            SolveStage::IntegratePositions => "integrate_positions",
            SolveStage::StoreImpulses => "store_impulses",
        }
    }
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
    pub stage_time: [Duration; 8],
    /// Wall time per part of the solve stage, in [`SolveStage::ALL`] order
    /// (included in the solve stage's time).
    pub solve_time: [Duration; 8],
    /// Threads the step ran on (the world's pool).
    pub threads: usize,
    /// Colours of the constraint graph: batches of rows that share no
    /// dynamic body and are solved in parallel (in a problem of fewer than
    /// 128 patches, the levels of its patch order, solved on one thread;
    /// 1 where it is one serial batch).
    pub colors: usize,
    /// Joints in the solver this step (those with a body it moves).
    pub joints: usize,
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
    /// Mesh pairs whose triangle pairs came from a walk of their trees that
    /// they remembered from an earlier step (resting pairs; the contacts are
    /// the same bits as from a new walk, only cheaper).
    pub recalled_mesh_pairs: usize,
    /// Collider pairs of a triangle mesh against a mesh or a half-space
    /// that had barely moved since their last search and took their kept
    /// points again, re-evaluated at the new poses
    /// (`WorldSettings::resting_motion`).
    pub revalidated_mesh_pairs: usize,
    /// Islands of awake bodies.
    pub islands: usize,
    /// Sub-steps run.
    pub substeps: u32,
    /// Velocity iterations per sub-step run: the settings' plus those a
    /// deep overlap at the step's start added.
    pub iterations: u32,
    /// What the solver left unsolved (m/s): the largest violation of a
    /// non-penetration row, `max(0, -(v_n + s/h))`, after the last sub-step's
    /// velocity iterations (before the push-out and the position update).
    /// Zero for an exact solve; PGS approaches it as iterations rise.
    pub solver_residual: f64,
    /// Fast bodies put back at their first time of impact by continuous
    /// collision ([`Stage::Continuous`]).
    pub continuous: usize,
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

    /// Time spent in one part of the solve stage.
    pub fn solve_time(&self, part: SolveStage) -> Duration {
        self.solve_time[part as usize]
    }

    /// Total wall time of the step.
    pub fn total_time(&self) -> Duration {
        self.stage_time.iter().sum()
    }
}
