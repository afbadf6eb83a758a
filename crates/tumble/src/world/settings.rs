//! World settings: every field has a unit, an effect and a default
//! (in the manner of Jolt's `PhysicsSettings` and Box2D's `b2DefaultWorldDef`).

use crate::integrate::Integrator;
use serde::{Deserialize, Serialize};
use tumble_collide::DVec3;

/// Which contact solver the `solve` stage uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// Sub-stepped, warm-started projected Gauss-Seidel / sequential impulses
    /// with split-impulse push-out. Fast, the default.
    #[default]
    Pgs,
    /// Direct pivoting LCP solve (Lemke) of the normal impulses of every
    /// sub-step, then friction by PGS with the normal impulses fixed. Exact
    /// complementarity; cost grows as n^3 with the contact count: for small
    /// systems (at most 256 contact points, else PGS runs and the step
    /// report says so) and as a reference for the iterative solver.
    Lemke,
}

/// How the `solve` and `integrate` stages advance the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct WorldSettings {
    /// Gravitational acceleration (m/s^2). Default (0, 0, -9.81): z is up.
    #[schemars(with = "[f64; 3]")]
    pub gravity: DVec3,
    /// Time step of one `World::step` (s), from 1e-9 (`MIN_DT`) to 1.
    /// Default 1/60. Smaller is more accurate and costs proportionally more.
    pub dt: f64,
    /// Solver sub-steps per step. Each sub-step integrates velocities, solves
    /// the contacts once and integrates positions, reusing the contact points
    /// of the step. More sub-steps stiffen stacks and chains far more cheaply
    /// than more iterations. Default 8.
    #[schemars(range(min = 1, max = 64))]
    pub substeps: u32,
    /// ODE integrator for free motion. Default semi-implicit Euler, the only
    /// one that is sub-stepped with the contact solver; the explicit methods
    /// are for free bodies and accuracy studies.
    pub integrator: Integrator,
    /// Contact solver. Default [`SolverKind::Pgs`].
    pub solver: SolverKind,
    /// Velocity Gauss-Seidel iterations per sub-step. Default 2 (with 8
    /// sub-steps). More converge stacks further each sub-step. A step whose
    /// deepest overlap at its start is 5 mm or more gets one more per whole
    /// 5 mm, at most 2 more (load where it is deep).
    #[schemars(range(min = 1, max = 1000))]
    pub iterations: u32,
    /// Push-out (position correction) iterations per sub-step. Default 1. A
    /// step whose deepest overlap at its start is 5 mm or more gets one
    /// more per whole 5 mm, at most 3 more (load where it is deep: a pass
    /// carries a correction one contact layer further); 0 turns push-out off.
    #[schemars(range(max = 1000))]
    pub push_out_iterations: u32,
    /// Speculative contact margin (m): feature pairs closer than this, plus
    /// the bodies' motion over the step, become contacts whose gap may close
    /// but not go negative. Larger catches faster bodies and costs more
    /// contacts. The bodies' own motion is always added, so the margin only
    /// needs to cover what that bound misses (velocity changed by impulses
    /// within the step): a few millimetres. On triangle meshes every
    /// millimetre adds triangle pairs to test (two meshes use
    /// `mesh_contact_margin` instead). Default 0.005.
    pub contact_margin: f64,
    /// Speculative contact margin of two triangle meshes (m): their feature
    /// pairs closer than this, plus each feature's own travel over the
    /// look-ahead (two steps of the pair's motion) and an estimate of how
    /// much a neighbour's blow changes either body's velocity in the step,
    /// become contacts. Smaller than `contact_margin` because a mesh pair's
    /// look-ahead already follows each feature's own motion; every
    /// millimetre adds triangle pairs to test (a settled pile of concave
    /// bodies tests about twice as many at 5 mm as at 2 mm, with the same
    /// depths over an ensemble of starts). Default 0.002.
    pub mesh_contact_margin: f64,
    /// Resting mesh contacts (m): a triangle mesh against a mesh or a
    /// half-space whose colliders have moved against each other less than
    /// this since their contacts were last searched for, counting how far
    /// they can move within the look-ahead and an estimate of a blow from a
    /// neighbour (its approach speed), takes the points it kept last step,
    /// re-evaluated exactly at the new poses, instead of searching its trees
    /// again: a resting pair then costs what its few kept points do, not
    /// what its tessellation does. A feature pair it does not hold can have
    /// come at most this much closer than at the search. At most half the
    /// pair's contact margin (`mesh_contact_margin` for two meshes) is used;
    /// 0 searches every step. Default 5e-7 (half a micron): only pairs that
    /// are really still keep their points. Each time a kept pair searches
    /// again its contact set changes a little and the load shifts; allowed
    /// 1e-5, the pairs of a settling concave pile went back and forth
    /// between the two every few steps and the pile never came to rest
    /// (docs/pipeline.md, "Resting mesh pairs").
    pub resting_motion: f64,
    /// Penetration left uncorrected (m): resting contacts within it are held
    /// rigidly where they are (no push-out, so no jitter); deeper overlap is
    /// pushed back to it. Stacks sink by at most this per contact layer.
    /// Contacts with a triangle mesh are offset by twice this, so that meshes
    /// rest this far *apart* rather than inside each other: resting mesh
    /// contact then stays exact vertex/face and edge/edge contact instead of
    /// intersecting triangles, whose push-out contacts are coarser.
    /// Default 0.0005.
    pub allowed_penetration: f64,
    /// Fraction of the overlap beyond `allowed_penetration` removed per
    /// sub-step by the push-out pass (dimensionless, in (0, 1]). Larger
    /// corrects faster and is stiffer. Default 0.2.
    pub push_out_fraction: f64,
    /// Largest speed at which overlap is pushed out (m/s). Bounds the energy
    /// that spawning bodies overlapping can inject. Default 3.
    pub max_push_out_speed: f64,
    /// Approach speed below which restitution is ignored (m/s), so resting
    /// contacts do not bounce forever. Default 0.5.
    pub restitution_threshold: f64,
    /// Continuous collision: a body moving more than half its thickness in
    /// one step (or with `ccd` set) is swept over the step and put back at
    /// the first surface in its path, so that nothing passes through a thin
    /// wall; mesh pairs that moved against each other by more than the
    /// contact margin are collided again at the step's end and pushed out of
    /// overlaps their speculative contacts missed (see docs/pipeline.md,
    /// stage `continuous`). Default true.
    pub continuous: bool,
    /// Let resting islands fall asleep (skipped until woken). Default true.
    pub sleeping: bool,
    /// Linear speed below which a body counts as resting (m/s). Default 0.05.
    pub sleep_linear_speed: f64,
    /// Angular speed below which a body counts as resting (rad/s). Default 0.05.
    pub sleep_angular_speed: f64,
    /// Time an island must rest before it sleeps (s). Default 0.5.
    pub time_to_sleep: f64,
    /// Worker threads of the step: the narrow phase runs over pairs and the
    /// solver over colour batches on this many threads. 0 means every core
    /// of the machine, 1 runs serially. The result does not depend on it:
    /// trajectories are bit-identical for any thread count. Default 0.
    #[schemars(range(max = 1024))] // pool::MAX_THREADS
    pub threads: u32,
    /// With more than one thread: a step that has work for the threads
    /// runs on one thread instead while the threads are measured to be
    /// slower (on a busy or shared machine every hand-over between cores
    /// can turn slow for minutes). Each step's report says how many threads
    /// it ran on; the result is the same either way. `false` always uses
    /// the threads. Default true.
    pub adaptive_threads: bool,
}

impl Default for WorldSettings {
    fn default() -> Self {
        WorldSettings {
            gravity: DVec3::new(0.0, 0.0, -9.81),
            dt: 1.0 / 60.0,
            substeps: 8,
            integrator: Integrator::default(),
            solver: SolverKind::default(),
            iterations: 2,
            push_out_iterations: 1,
            contact_margin: 0.005,
            mesh_contact_margin: 0.002,
            resting_motion: 5e-7,
            allowed_penetration: 0.0005,
            push_out_fraction: 0.2,
            max_push_out_speed: 3.0,
            restitution_threshold: 0.5,
            continuous: true,
            sleeping: true,
            sleep_linear_speed: 0.05,
            sleep_angular_speed: 0.05,
            time_to_sleep: 0.5,
            threads: 0,
            adaptive_threads: true,
        }
    }
}
