//! Many worlds at once: a batch of independent worlds (rollouts, parameter
//! sweeps, data generation) spread over the threads of one pool, one world
//! per thread at a time, each stepped serially on its thread.
//!
//! Why one world per thread rather than each world's own threads: the
//! worlds share nothing, so running them side by side needs no barrier and
//! no merge, and a batch of B >= threads worlds keeps every core busy where
//! a single world's parallel stages would not. A world's result never
//! depends on where or beside what it ran: each world's trajectory is the
//! one it has stepped alone, bit for bit, for any thread count of the batch
//! (the step is deterministic for any thread count, see [`crate::world`]).

use crate::pool::WorkerPool;
use crate::world::{StepReport, World};

/// Runs `job` once for each world (with its index and its own item of
/// `scratch`, for its inputs and outputs) on up to `threads` threads (0:
/// every core). Inside `job`, `world.step()` runs serially on the calling
/// thread; each world gets its own pool back afterwards.
///
/// # Panics
/// If `scratch` and `worlds` differ in length.
pub fn for_each_world<S: Send>(
    worlds: &mut [World],
    scratch: &mut [S],
    threads: u32,
    job: impl Fn(usize, &mut World, &mut S) + Sync + Send,
) {
    assert_eq!(worlds.len(), scratch.len(), "one scratch item per world");
    let mut pairs: Vec<(&mut World, &mut S)> = worlds.iter_mut().zip(scratch.iter_mut()).collect();
    for_each_item(&mut pairs, threads, |(w, _)| w, |k, (w, s)| job(k, w, s));
}

/// [`for_each_world`] for items that hold their world (`world_of` finds
/// it): `job` gets the item, whose world steps serially on the thread.
pub fn for_each_item<T: Send>(
    items: &mut [T],
    threads: u32,
    world_of: impl Fn(&mut T) -> &mut World + Sync + Send,
    job: impl Fn(usize, &mut T) + Sync + Send,
) {
    WorkerPool::new(threads).for_each_mut(items, |k, item| {
        let own = world_of(item).swap_pool(WorkerPool::serial());
        job(k, item);
        world_of(item).swap_pool(own);
    });
}

/// Steps every world `steps` times on up to `threads` threads (0: every
/// core) and returns each world's report of its last step (`None` where
/// `steps` is 0).
///
/// ```
/// use tumble::collide::{DVec3, HalfSpace, Sphere};
/// use tumble::world::{BodyDesc, World, WorldSettings};
///
/// // Eight balls dropped from eight heights, one world each.
/// let mut worlds: Vec<World> = (0..8)
///     .map(|k| {
///         let mut w = World::new(WorldSettings::default())?;
///         w.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0)?))?;
///         w.add_body(&BodyDesc::dynamic(Sphere::new(0.1)?).at(DVec3::new(0.0, 0.0, 1.0 + k as f64)))?;
///         Ok(w)
///     })
///     .collect::<Result<_, Box<dyn std::error::Error>>>()?;
/// let mut alone = worlds[3].clone();
/// tumble::batch::step_worlds(&mut worlds, 30, 0);
/// for _ in 0..30 {
///     alone.step();
/// }
/// assert_eq!(worlds[3].state_hash(), alone.state_hash());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn step_worlds(worlds: &mut [World], steps: usize, threads: u32) -> Vec<Option<StepReport>> {
    let mut reports: Vec<Option<StepReport>> = vec![None; worlds.len()];
    for_each_world(worlds, &mut reports, threads, |_, world, last| {
        for _ in 0..steps {
            *last = Some(world.step());
        }
    });
    reports
}
