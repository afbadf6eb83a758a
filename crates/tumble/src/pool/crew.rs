//! A step's crew: the pool's other workers held for the length of one
//! `WorkerPool::run`, waiting between its parallel sections on a spin loop
//! instead of going to sleep. A rayon worker that finds no work sleeps
//! after some 20 us; waking it again costs about 9 us on this project's
//! 2-core VM (a parallel section of two 2 us tasks took 2.7 us after a
//! short serial stretch and 11-12 us after one of 20 us or more:
//! `examples/pool_wake.rs`), and a step of the pile of 1,000 bodies has
//! half a dozen parallel sections between serial stages. Held, a worker
//! starts a section within a microsecond, and stages too small to pay a
//! wake-up can be shared.
//!
//! The protocol (one leader, thread 0 of the run, posts jobs; helpers take
//! part): the leader writes the job, then raises `posted`; a helper that
//! sees a new generation announces itself in `inside`, then checks that
//! the job is still open (`closed` below its generation) before it reads
//! the job. The leader, its own part done, closes the job and waits until
//! `inside` is back to zero before it returns (and before the job's
//! borrowed closure dies). Announce-then-check against close-then-wait,
//! both sequentially consistent, means a helper either sees the job open
//! and is waited for, or sees it closed and never touches it.
//!
//! Two kinds of job: shared (any helper that comes takes chunks, its own
//! run first, `take_runs`: the caller's result never depends on who ran a
//! chunk),
//! and team (exactly the helpers that had joined when the job was posted
//! take part, each with its index, so that the job may meet at barriers).
//! A helper that joins late (its worker was busy elsewhere) only takes the
//! jobs posted after it joined; a run whose helpers never come runs alone.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Spins of a waiting helper before it starts yielding its core between
/// looks (more threads than cores, or a core taken by another process).
const SPINS_BEFORE_YIELD: u32 = 2000;

/// A job as the helpers see it: how many members it takes (team) or
/// `usize::MAX` (shared), and the work, called with the member's index.
#[derive(Clone, Copy)]
struct JobRef {
    members: usize,
    work: *const (dyn Fn(usize) + Sync),
}

/// The shared state of one run's crew (see the module docs).
pub(crate) struct Crew {
    /// Helpers that have joined; helper `k` (1-based) joined `k`-th.
    joined: AtomicUsize,
    /// Generation of the last job posted.
    posted: AtomicUsize,
    /// Generation of the last job closed.
    closed: AtomicUsize,
    /// Helpers inside a job (or checking whether they may enter one).
    inside: AtomicUsize,
    /// The run is over: helpers leave.
    done: AtomicBool,
    /// The open job; written by the leader only while no helper can read
    /// it (between a close that found `inside` at zero and the next post).
    job: UnsafeCell<Option<JobRef>>,
}

// SAFETY: `job` is written by the leader only while no helper reads it
// (module docs: a helper reads it only after announcing itself and seeing
// the job open, and the leader writes it only after closing the last job
// and waiting for `inside` to reach zero); its closure is `Sync`.
unsafe impl Sync for Crew {}
// SAFETY: as above; the pointer in `job` is only followed under that protocol.
unsafe impl Send for Crew {}

impl Crew {
    pub(crate) fn new() -> Crew {
        Crew {
            joined: AtomicUsize::new(0),
            posted: AtomicUsize::new(0),
            closed: AtomicUsize::new(0),
            inside: AtomicUsize::new(0),
            done: AtomicBool::new(false),
            job: UnsafeCell::new(None),
        }
    }

    /// Helpers that have joined so far (they take part in the next team job).
    pub(crate) fn joined(&self) -> usize {
        self.joined.load(Ordering::SeqCst)
    }

    /// A helper's life: join, then take part in every job posted until the
    /// run is over.
    pub(crate) fn serve(&self) {
        let me = self.joined.fetch_add(1, Ordering::SeqCst) + 1;
        // Every generation is new to a helper that just joined: a closed
        // one it skips after the check, an open team job sized without it
        // by the index test, an open shared one it helps with.
        let mut seen = 0;
        loop {
            let mut spins = 0u32;
            let generation = loop {
                if self.done.load(Ordering::Acquire) {
                    return;
                }
                let g = self.posted.load(Ordering::Acquire);
                if g != seen {
                    break g;
                }
                if spins < SPINS_BEFORE_YIELD {
                    std::hint::spin_loop();
                    spins += 1;
                } else {
                    std::thread::yield_now();
                }
            };
            seen = generation;
            self.inside.fetch_add(1, Ordering::SeqCst);
            let _leave = Leave(&self.inside);
            if self.closed.load(Ordering::SeqCst) >= generation {
                continue;
            }
            // SAFETY: announced and seen open: the leader does not write
            // `job` or drop the closure until this helper leaves.
            let Some(job) = (unsafe { *self.job.get() }) else {
                continue;
            };
            if me < job.members {
                // SAFETY: as above, the closure outlives this call.
                unsafe { (*job.work)(me) };
            }
        }
    }

    /// Runs `work` as one job: the leader calls it with index 0, each
    /// helper that takes part with its own; returns when every helper that
    /// entered has left. `members`: `usize::MAX` for a shared job, else
    /// the team's size (the leader and helpers `1..members`, which must all
    /// have joined).
    pub(crate) fn run_job(&self, members: usize, work: &(dyn Fn(usize) + Sync)) {
        let generation = self.posted.load(Ordering::SeqCst) + 1;
        // SAFETY: the lifetime is erased only for the helpers' copy, which
        // they follow only while this call waits for them (below).
        let work: *const (dyn Fn(usize) + Sync + '_) = work;
        let work: *const (dyn Fn(usize) + Sync) = unsafe { std::mem::transmute(work) };
        // SAFETY: no helper reads `job` now: the last job was closed and
        // `inside` seen at zero, and this generation is not posted yet.
        unsafe { *self.job.get() = Some(JobRef { members, work }) };
        self.posted.store(generation, Ordering::SeqCst);
        // Closes the job and waits for the helpers inside it, also when
        // the leader's part unwinds.
        struct Close<'a>(&'a Crew, usize);
        impl Drop for Close<'_> {
            fn drop(&mut self) {
                self.0.closed.store(self.1, Ordering::SeqCst);
                let mut spins = 0u32;
                while self.0.inside.load(Ordering::SeqCst) != 0 {
                    if spins < SPINS_BEFORE_YIELD {
                        std::hint::spin_loop();
                        spins += 1;
                    } else {
                        std::thread::yield_now();
                    }
                }
            }
        }
        let _close = Close(self, generation);
        // SAFETY: `work` is the caller's live closure.
        unsafe { (*work)(0) };
    }

    /// Ends the run: the helpers leave their loops.
    pub(crate) fn dismiss(&self) {
        self.done.store(true, Ordering::Release);
    }
}

/// Leaves a job (or the check for one) on every path out of it.
struct Leave<'a>(&'a AtomicUsize);

impl Drop for Leave<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}
