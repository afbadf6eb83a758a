//! Where an update of the broad phase runs its independent jobs: the three
//! axes' sorts and the parts of a rebuild's sweep. A job depends on its own
//! item alone and every result is merged in item order (or sorted), so the
//! pairs and events are the same whichever threads run the jobs.

/// Runs a batch of independent jobs, one after another ([`InOrder`]) or side
/// by side on the caller's threads (the world's pool implements this).
pub trait BroadJobs {
    /// How many jobs can run at once (1 for one thread); a hint for how
    /// finely to cut a job that can be cut (the sweep), never a result.
    fn width(&self) -> usize;

    /// `job(k, item)` for every item, each item on one thread.
    fn each<T: Send>(&self, items: &mut [T], job: impl Fn(usize, &mut T) + Sync + Send);
}

/// Every job on the calling thread, in order.
#[derive(Debug, Clone, Copy, Default)]
pub struct InOrder;

impl BroadJobs for InOrder {
    fn width(&self) -> usize {
        1
    }

    fn each<T: Send>(&self, items: &mut [T], job: impl Fn(usize, &mut T) + Sync + Send) {
        for (k, item) in items.iter_mut().enumerate() {
            job(k, item);
        }
    }
}
