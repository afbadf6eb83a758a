//! One step of the world as named stages (see [`Stage`] and
//! docs/pipeline.md): forces, broad, narrow, islands, solve, integrate,
//! continuous, events. Each stage is a method over the step's [`StepFrame`]; `step()`
//! runs [`Stage::ALL`] in order and times each into the [`StepReport`].
//!
//! Determinism: bodies are visited in slot order, broad-phase pairs in sorted
//! order, contacts in the order the narrow phase produces them, constraint
//! colours in a fixed order; work spread over threads is merged in index
//! order and nothing iterates a hash map. The same world stepped twice, on
//! any number of threads, gives the same bits.

mod broad;
mod continuous;
mod end_overlap;
mod events;
mod frame;
mod margins;
mod narrow;
mod quarantine;
mod solve;
mod thread_choice;
mod writeback;

pub(crate) use broad::new_broad_phase;
pub use continuous::FAST_FRACTION;
pub use end_overlap::{END_OVERLAP_SLACK, STRUCK_MARGINS};
pub(crate) use frame::{StepFrame, StepScratch};
pub(crate) use margins::{body_aabb, bounding_radius, core_radius, thickness, velocities};
pub use quarantine::RUNAWAY_SPEED;
pub(crate) use thread_choice::ThreadChoice;

use super::report::{Stage, StepReport};
use super::World;
use crate::pool::WorkerPool;
use std::time::Instant;

impl World {
    /// Advances the world by `settings.dt` and reports what happened.
    pub fn step(&mut self) -> StepReport {
        // The whole step runs on a worker of the pool, the other workers
        // held as its crew (`pool::crew`): each parallel section inside
        // starts within a microsecond. (Entered from outside the pool for
        // each parallel section instead, the other workers of a 2-core VM
        // took about a millisecond to join; left to sleep between sections,
        // about 9 us each time.)
        // A small step stays on this thread: the hand-over to the pool
        // costs more than its parallel parts would save. Where the work is
        // done never changes the result.
        // And while the threads are measured to be slower than one thread
        // (`thread_choice`), the step stays here too.
        let meshes = self.bodies.iter().any(|(_, e)| margins::has_mesh(e));
        let worth = self.worth_threads(meshes);
        let adaptive = worth && self.settings.adaptive_threads;
        let pool = if worth && (!adaptive || self.scratch.thread_choice.next_threaded()) {
            self.pool.clone()
        } else {
            WorkerPool::serial()
        };
        let start = Instant::now();
        let report = pool.run(|crewed| self.run_stages(crewed.clone(), meshes));
        if adaptive {
            // The step's work: its bodies, candidate pairs and contacts.
            let work = report.awake_bodies + report.broad_pairs + 2 * report.contacts;
            self.scratch
                .thread_choice
                .record(start.elapsed().as_secs_f64(), work);
        }
        report
    }

    /// Whether this step has work enough for the threads, judged from the
    /// last step: many bodies, many contact patches, or mesh bodies (each
    /// mesh pair costs as much as hundreds of box pairs). Measured with
    /// `profile_stages` on this project's 2-core VM (last third of 600
    /// steps), with the step's crew: the 210-box pyramid (420 patches) is
    /// 1.3x faster on two threads than on one (0.53-0.58 against 0.72 ms),
    /// the pile of 100 and the 21-link heavy chain as fast (0.22 and 0.09
    /// ms). Before the crew, when each parallel section woke a sleeping
    /// worker, the pyramid was slower on two threads (1.04 against 0.97 ms)
    /// and these limits were 256 bodies or 1,024 patches.
    fn worth_threads(&self, meshes: bool) -> bool {
        const BODIES: usize = 160;
        const PATCHES: usize = 320;
        self.pool.threads() > 1
            && (self.bodies.len() >= BODIES || self.patch_cache.len() >= PATCHES || meshes)
    }

    fn run_stages(&mut self, pool: WorkerPool, meshes: bool) -> StepReport {
        let buffers = std::mem::take(&mut self.scratch.frame);
        let mut frame = StepFrame::new(self.settings.clone(), self.bodies.slot_count(), pool, buffers);
        frame.meshes = meshes;
        frame.report.threads = frame.pool.threads();
        for stage in Stage::ALL {
            let start = Instant::now();
            match stage {
                Stage::Forces => self.forces_stage(&mut frame),
                Stage::Broad => self.broad_stage(&mut frame),
                Stage::Narrow => self.narrow_stage(&mut frame),
                Stage::Islands => self.islands_stage(&mut frame),
                Stage::Solve => self.solve_stage(&mut frame),
                Stage::Integrate => self.integrate_stage(&mut frame),
                Stage::Continuous => self.continuous_stage(&mut frame),
                Stage::Events => self.events_stage(&mut frame),
            }
            frame.report.stage_time[stage as usize] += start.elapsed();
        }
        // The gears count their hinges' turns across the wrap (from poses
        // the step has settled, quarantine included).
        self.follow_gear_coordinates();
        self.scratch.frame = frame.recycle();
        frame.report
    }

    /// [`Stage::Forces`]: the state before the step is kept, so that a body
    /// quarantined later in the step can be restored to it. (Forces and
    /// gravity themselves are read by the solve stage.)
    fn forces_stage(&mut self, f: &mut StepFrame) {
        f.before = (0..f.n_slots as u32)
            .map(|i| self.bodies.at(i).map(|e| *e.body.state()))
            .collect();
    }

    /// [`Stage::Islands`]: contacts and joints link dynamic bodies into
    /// islands (the unit of sleeping).
    fn islands_stage(&mut self, f: &mut StepFrame) {
        use crate::body::BodyKind;
        // One link per patch (its points share it); an island's label is
        // its smallest slot, whatever the links' order or repeats.
        let mut links: Vec<(u32, u32)> = f.patches.iter().map(|p| (p.key.0, p.key.1)).collect();
        links.dedup();
        links.extend(self.joint_links());
        let dynamic_awake: Vec<bool> = (0..f.n_slots as u32)
            .map(|i| {
                self.bodies
                    .at(i)
                    .is_some_and(|e| e.body.kind() == BodyKind::Dynamic && !e.sleeping)
            })
            .collect();
        f.labels = super::islands::label_islands(&dynamic_awake, &links);
        let mut roots: Vec<u32> = f.labels.iter().copied().filter(|&l| l != u32::MAX).collect();
        roots.sort_unstable();
        roots.dedup();
        f.report.islands = roots.len();
    }
}
