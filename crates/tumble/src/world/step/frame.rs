//! The step's scratch: what one stage hands to the next. Built fresh by
//! `World::step` (sized from the last step's contacts, so a steady scene
//! does not grow it) and dropped at the end of the step.

use crate::body::BodyState;
use crate::pool::WorkerPool;
use crate::solver::contact_solver::{
    BundleKind, Coloring, GearConstraint, JointConstraint, JointIsland, ManifoldConstraint, PointConstraint,
    SolverBody, ThreadFlow, WideBatches,
};
use crate::world::patches::{ContactPoints, PatchExtras, PreparedPatch};
use crate::world::report::StepReport;
use crate::world::WorldSettings;
use tumble_collide::broad::Aabb;
use tumble_collide::narrow::MeshPairMemory;

/// What the stages of one step share (see `World::step`).
pub(crate) struct StepFrame {
    /// The world's settings, as they were when the step began.
    pub settings: WorldSettings,
    /// The threads this step runs on (the world's pool, or one thread for
    /// a small step).
    pub pool: WorkerPool,
    /// What the step reports; each stage fills its part.
    pub report: StepReport,
    /// Body slots of the world (live or free).
    pub n_slots: usize,
    /// Some body has a triangle-mesh collider (mesh pairs cost far more).
    pub meshes: bool,
    /// Forces: every live body's state before the step (quarantine restores it).
    pub before: Vec<Option<crate::body::BodyState>>,
    /// Broad: where each bounded body can be during the step (`None` for
    /// unbounded shapes and free slots).
    pub swept: Vec<Option<Aabb>>,
    /// Broad: body slot pairs whose boxes overlap, sorted, `a < b`.
    pub pairs: Vec<(u32, u32)>,
    /// Narrow: every contact point, one record from the narrow phase to the
    /// events (geometry, warm-start impulse, cache key), grouped by patch,
    /// in one run per chunk of pairs.
    pub points: ContactPoints,
    /// Narrow: the contact patches, each a slice of a run of `points`.
    pub patches: Vec<PreparedPatch>,
    /// Narrow: what only some patches carry (`PreparedPatch::extras`).
    pub patch_extras: Vec<PatchExtras>,
    /// Islands: island label per body slot (`u32::MAX`: not in an island).
    pub labels: Vec<u32>,
    /// Solve: the solver's arrays.
    pub solver: SolverFrame,
}

/// The solve stage's arrays, kept in the frame for the write-back.
#[derive(Default)]
pub(crate) struct SolverFrame {
    /// Solver body index per body slot (0: the shared immovable body).
    pub slot_to_solver: Vec<u32>,
    /// Body slot per solver body (`u32::MAX` for entry 0).
    pub slots: Vec<u32>,
    /// Solver bodies; entry 0 is static.
    pub bodies: Vec<SolverBody>,
    /// Per body slot: the body has a contact patch or a joint this step
    /// (it is moved by the solver, not by an explicit integrator).
    pub has_contact: Vec<bool>,
    /// Per solver body: quarantined before the solve (restored afterwards).
    pub frozen: Vec<bool>,
    /// Normal rows, one per contact point: each patch record's points after
    /// the last one's, so in the order of `manifolds`.
    pub points: Vec<PointConstraint>,
    /// Patch rows, one per contact patch, sorted by colour.
    pub manifolds: Vec<ManifoldConstraint>,
    /// Per patch row: the bundles it goes to, written with the rows, so
    /// that the bundles are planned from this list alone.
    pub bundle_kinds: Vec<BundleKind>,
    /// Per contact patch (`StepFrame::patches` order): its index in `manifolds`.
    pub position: Vec<u32>,
    /// Joint rows, one record per joint with a movable body, sorted by colour.
    pub joints: Vec<JointConstraint>,
    /// Joint arena slot of each record of `joints`.
    pub joint_slots: Vec<u32>,
    /// Gears between two records of `joints`, in joint slot order of their
    /// followers.
    pub gears: Vec<GearConstraint>,
    /// Joint arena slot of each gear's follower.
    pub gear_slots: Vec<u32>,
    /// The joints' colours (the order of `joints`).
    pub joint_coloring: Coloring,
    /// Islands of joints whose equality rows are solved directly (kept
    /// from step to step while their shapes hold).
    pub joint_islands: Vec<JointIsland>,
    /// What `joint_islands`' shapes were found from
    /// (`contact_solver::keep_joint_islands`).
    pub joint_island_key: Vec<u64>,
    /// Per solver body: rotational inertia added by joint geometric
    /// stiffness (kg m^2; 0 for most bodies).
    pub geometric: Vec<f64>,
}

impl StepFrame {
    /// An empty frame for a world with `n_slots` body slots, its largest
    /// arrays taken (empty) from `buffers`.
    pub fn new(
        settings: WorldSettings,
        n_slots: usize,
        pool: WorkerPool,
        buffers: FrameBuffers,
    ) -> StepFrame {
        let mut frame = StepFrame {
            settings,
            pool,
            report: StepReport::default(),
            n_slots,
            meshes: false,
            before: Vec::new(),
            swept: Vec::new(),
            pairs: Vec::new(),
            points: ContactPoints::default(),
            patches: Vec::new(),
            patch_extras: Vec::new(),
            labels: Vec::new(),
            solver: SolverFrame::default(),
        };
        frame.points = buffers.points;
        frame.patches = buffers.patches;
        frame.patch_extras = buffers.patch_extras;
        frame.solver.points = buffers.solver_points;
        frame.solver.manifolds = buffers.manifolds;
        frame.solver.bodies = buffers.bodies;
        frame.solver.joints = buffers.joints;
        frame.solver.joint_islands = buffers.joint_islands;
        frame.solver.joint_island_key = buffers.joint_island_key;
        frame
    }

    /// The frame's largest arrays for the next step's frame: emptied, but
    /// for the joint islands (kept while their shapes hold) and the
    /// solver's point, patch and joint records, which keep their length
    /// (`World::prepare_solver` cuts or grows them to the step's and
    /// overwrites every record before one is read, so that it writes each
    /// record once instead of clearing and pushing; a joint record is
    /// renewed, `JointConstraint::renew`).
    pub fn recycle(&mut self) -> FrameBuffers {
        let mut take = FrameBuffers {
            points: std::mem::take(&mut self.points),
            patches: std::mem::take(&mut self.patches),
            patch_extras: std::mem::take(&mut self.patch_extras),
            solver_points: std::mem::take(&mut self.solver.points),
            manifolds: std::mem::take(&mut self.solver.manifolds),
            bodies: std::mem::take(&mut self.solver.bodies),
            joints: std::mem::take(&mut self.solver.joints),
            joint_islands: std::mem::take(&mut self.solver.joint_islands),
            joint_island_key: std::mem::take(&mut self.solver.joint_island_key),
        };
        take.points.clear();
        take.patches.clear();
        take.patch_extras.clear();
        take.bodies.clear();
        take
    }

    /// The state of body slot `i` before the step, stopped: what quarantine restores.
    pub fn stopped_state_before(&self, i: usize) -> Option<BodyState> {
        self.before[i].map(|mut s| {
            s.linear_momentum = tumble_collide::DVec3::ZERO;
            s.angular_momentum = tumble_collide::DVec3::ZERO;
            s
        })
    }
}

/// Buffers a world keeps from step to step, so that a steady scene does not
/// allocate its largest arrays anew every step (fresh ones cost the
/// allocation and, once the allocator has handed the memory back to the
/// system, a page fault per 4 KiB touched: 80,000 over 300 steps of the
/// pyramid). Not state: a copy of the world starts with none, and no result
/// depends on them.
#[derive(Default)]
pub(crate) struct StepScratch {
    /// The colour batches in bundles of four patches.
    pub wide: WideBatches,
    /// Each solver thread's order of the heavy colours' items.
    pub flows: Vec<ThreadFlow>,
    /// The solver's records compacted for the write-back
    /// (`World::store_impulses`) and the events: written and read within
    /// each step.
    pub solved: crate::solver::contact_solver::SolvedPatches,
    /// The last step's frame arrays, emptied (see [`StepFrame::recycle`]).
    pub frame: FrameBuffers,
    /// The walks that mesh pairs remember (`narrow::MeshPairMemory`: a
    /// resting pair's triangle pairs, a moving pair's walk front), by
    /// collider pair, in the step's pair order. They change the cost of the
    /// narrow phase and of the end-of-step overlaps, never their contacts.
    pub mesh_memory: Vec<(MeshPairKey, Option<MeshPairMemory>)>,
    /// Where the end-of-step overlap walks of mesh pairs ended last step
    /// (`bvh::front`), by collider pair in key order: their next walks
    /// begin there. They change those walks' cost, never their contacts.
    pub end_fronts: Vec<(MeshPairKey, MeshPairMemory)>,
    /// The narrow phase's per-chunk buffers on several threads (patches and
    /// patch extras of chunk k at entry k; its points are run k of the
    /// frame's `ContactPoints`), emptied: what each chunk wrote last step,
    /// reused.
    pub narrow_chunks: Vec<NarrowBuffers>,
    /// Whether steps run on the threads or on one (`thread_choice`): where
    /// the work is done, never what it gives.
    pub thread_choice: super::ThreadChoice,
}

/// One narrow-phase chunk's patches and patch extras.
pub(crate) type NarrowBuffers = (Vec<PreparedPatch>, Vec<PatchExtras>);

/// A collider pair: body slots and collider indices `(a, b, ia, ib)`.
pub(crate) type MeshPairKey = (u32, u32, u16, u16);

/// The frame's largest arrays, kept between steps (empty, or of stale
/// records that are overwritten: see [`StepFrame::recycle`]).
#[derive(Default)]
pub(crate) struct FrameBuffers {
    points: ContactPoints,
    patches: Vec<PreparedPatch>,
    patch_extras: Vec<PatchExtras>,
    solver_points: Vec<PointConstraint>,
    manifolds: Vec<ManifoldConstraint>,
    bodies: Vec<SolverBody>,
    joints: Vec<JointConstraint>,
    /// The joint islands and what their shapes were found from: kept
    /// whole while the shapes hold (`contact_solver::keep_joint_islands`).
    joint_islands: Vec<JointIsland>,
    joint_island_key: Vec<u64>,
}

impl Clone for StepScratch {
    fn clone(&self) -> StepScratch {
        StepScratch::default()
    }
}

impl std::fmt::Debug for StepScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StepScratch")
    }
}
