//! The world's worker threads: a rayon pool per thread count, made once per
//! process and shared by every world that asks for that count (a test suite
//! or a batch of worlds does not spawn threads per world).
//!
//! Two ways to use the threads: `map_chunks` / `for_each_mut` (fork-join
//! over chunks: the narrow phase, the step's smaller shared stages) and
//! `team` (every worker runs the same loop, meeting at spin barriers: the
//! solver's sub-steps, whose hundreds of small colour batches per step
//! would each cost a wake-up of the sleeping workers under fork-join; Box2D
//! v3's solver works the same way). Inside `run` (a world's step) both go
//! to the run's crew (`crew`): the other workers, held on a spin loop for
//! the run, so that no section waits for a sleeping worker to wake.
//!
//! Determinism is the callers' part and rests on two rules: work is split
//! by index, and every result is merged in index order (`map_chunks`
//! collects in order; the solver's colour batches touch disjoint bodies).
//! One thread never enters rayon at all, so `threads = 1` is the plain
//! serial code.

mod crew;

use crew::Crew;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Largest accepted `WorldSettings::threads`.
pub(crate) const MAX_THREADS: u32 = 1024;

/// Cores of this machine (as the process may use them), asked once.
fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Worker threads of one world.
#[derive(Clone)]
pub(crate) struct WorkerPool {
    threads: usize,
    pool: Option<Arc<SharedPool>>,
    /// Inside [`WorkerPool::run`]: the other workers, held for the run
    /// (`crew`); the parallel sections go to them instead of to rayon.
    crew: Option<Arc<Crew>>,
}

/// A rayon pool and the lock that lets one team at a time use it (worlds
/// of the same thread count share a pool; two teams interleaved on it could
/// each wait at a barrier for a thread the other holds).
struct SharedPool {
    pool: rayon::ThreadPool,
    team: Mutex<()>,
}

impl std::fmt::Debug for WorkerPool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "WorkerPool({} threads)", self.threads)
    }
}

/// The pools made so far, by thread count.
type Registry = Mutex<Vec<(usize, Arc<SharedPool>)>>;

fn registry() -> &'static Registry {
    static POOLS: OnceLock<Registry> = OnceLock::new();
    POOLS.get_or_init(|| Mutex::new(Vec::new()))
}

/// The broad phase's jobs (its axes' sorts, the parts of a rebuild's
/// sweep) on the world's threads.
impl tumble_collide::broad::BroadJobs for WorkerPool {
    fn width(&self) -> usize {
        self.threads
    }

    fn each<T: Send>(&self, items: &mut [T], job: impl Fn(usize, &mut T) + Sync + Send) {
        self.for_each_mut(items, job);
    }
}

impl WorkerPool {
    /// The pool for `requested` threads (0: every core). If the threads
    /// cannot be started, the world runs serially (with the same results).
    pub fn new(requested: u32) -> WorkerPool {
        let threads = match requested {
            0 => cores(),
            n => n as usize,
        };
        if threads <= 1 {
            return WorkerPool::serial();
        }
        let mut pools = registry().lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, pool)) = pools.iter().find(|(n, _)| *n == threads) {
            return WorkerPool {
                threads,
                pool: Some(pool.clone()),
                crew: None,
            };
        }
        match rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("tumble-worker-{i}"))
            .build()
        {
            Ok(pool) => {
                let pool = Arc::new(SharedPool {
                    pool,
                    team: Mutex::new(()),
                });
                pools.push((threads, pool.clone()));
                WorkerPool {
                    threads,
                    pool: Some(pool),
                    crew: None,
                }
            }
            Err(_) => WorkerPool::serial(),
        }
    }

    /// One thread: everything runs on the caller's thread.
    pub fn serial() -> WorkerPool {
        WorkerPool {
            threads: 1,
            pool: None,
            crew: None,
        }
    }

    /// Threads the world runs on.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// `f` over consecutive chunks of `items` (its arguments: the index of
    /// the chunk's first item, and the chunk), results in chunk order. On
    /// one thread `f` sees all items at once; on more, chunks of `chunk`
    /// items are spread over the threads (in a run, each thread first takes
    /// its own run of chunks: [`take_runs`]). Callers write results that do
    /// not depend on where the chunks are cut.
    pub fn map_chunks<T: Sync, R: Send>(
        &self,
        items: &[T],
        chunk: usize,
        f: impl Fn(usize, &[T]) -> R + Sync + Send,
    ) -> Vec<R> {
        let chunk = chunk.max(1);
        if let Some(crew) = &self.crew {
            if items.len() <= chunk {
                return vec![f(0, items)];
            }
            // Chunks taken by runs ([`take_runs`]); each result kept in its
            // chunk's place.
            let n = items.len().div_ceil(chunk);
            let results: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
            let runs = runs_of(n, (1 + crew.joined()).min(self.threads));
            crew.run_job(usize::MAX, &|me| {
                take_runs(&runs, me, |k| {
                    let start = k * chunk;
                    let r = f(start, &items[start..(start + chunk).min(items.len())]);
                    *results[k].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
                })
            });
            return results
                .into_iter()
                .map(|r| {
                    r.into_inner()
                        .unwrap_or_else(|e| e.into_inner())
                        .expect("every chunk ran (a chunk left empty is a task that panicked)")
                })
                .collect();
        }
        match &self.pool {
            Some(shared) if items.len() > chunk => shared.pool.install(|| {
                items
                    .par_chunks(chunk)
                    .enumerate()
                    .map(|(k, c)| f(k * chunk, c))
                    .collect()
            }),
            _ => vec![f(0, items)],
        }
    }

    /// [`WorkerPool::map_chunks`] for chunks that each make a list: the
    /// lists joined in chunk order (one chunk's list is returned as it is,
    /// so that one thread pays no copy).
    pub fn flat_map_chunks<T: Sync, R: Send>(
        &self,
        items: &[T],
        chunk: usize,
        f: impl Fn(usize, &[T]) -> Vec<R> + Sync + Send,
    ) -> Vec<R> {
        let mut lists = self.map_chunks(items, chunk, f);
        if lists.len() == 1 {
            return lists.pop().unwrap_or_default();
        }
        let mut joined = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        for list in lists {
            joined.extend(list);
        }
        joined
    }

    /// `f` of every index below `n` (a body slot, say), in order, runs of
    /// `chunk` indices a task.
    pub fn map_indices<R: Send>(&self, n: usize, chunk: usize, f: impl Fn(u32) -> R + Sync + Send) -> Vec<R> {
        let indices: Vec<u32> = (0..n as u32).collect();
        self.flat_map_chunks(&indices, chunk, |_, run| run.iter().map(|&i| f(i)).collect())
    }

    /// The indices below `n` for which `keep` holds, in order, runs of
    /// `chunk` indices a task.
    pub fn filter_indices(
        &self,
        n: usize,
        chunk: usize,
        keep: impl Fn(u32) -> bool + Sync + Send,
    ) -> Vec<u32> {
        let indices: Vec<u32> = (0..n as u32).collect();
        self.flat_map_chunks(&indices, chunk, |_, run| {
            run.iter().copied().filter(|&i| keep(i)).collect()
        })
    }

    /// `f` on every item, each item on one thread (items are independent,
    /// so where each runs never changes a result); on one thread in order.
    pub fn for_each_mut<T: Send>(&self, items: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
        if let Some(crew) = &self.crew {
            if items.len() > 1 {
                let items: Vec<Mutex<&mut T>> = items.iter_mut().map(Mutex::new).collect();
                let runs = runs_of(items.len(), (1 + crew.joined()).min(self.threads));
                crew.run_job(usize::MAX, &|me| {
                    take_runs(&runs, me, |k| {
                        f(k, &mut items[k].lock().unwrap_or_else(|e| e.into_inner()))
                    })
                });
                return;
            }
        }
        match &self.pool {
            Some(shared) if items.len() > 1 => shared.pool.install(|| {
                items
                    .par_iter_mut()
                    .with_max_len(1)
                    .enumerate()
                    .for_each(|(k, item)| f(k, item))
            }),
            _ => items.iter_mut().enumerate().for_each(|(k, item)| f(k, item)),
        }
    }

    /// Runs `f` on a worker of the pool (or here, serially), with the
    /// pool's other workers held as its crew until `f` returns (see
    /// `crew`): `f` gets this pool with the crew, whose parallel sections
    /// start within a microsecond. A step runs whole inside one `run`, so
    /// the hand-over to the pool is paid once per step.
    pub fn run<R: Send>(&self, f: impl FnOnce(&WorkerPool) -> R + Send) -> R {
        let Some(shared) = &self.pool else {
            return f(self);
        };
        if self.crew.is_some() {
            return f(self);
        }
        shared.pool.install(|| {
            let crew = Arc::new(Crew::new());
            let crewed = WorkerPool {
                threads: self.threads,
                pool: self.pool.clone(),
                crew: Some(crew.clone()),
            };
            /// Dismisses the crew when `f` returns or unwinds.
            struct Dismiss(Arc<Crew>);
            impl Drop for Dismiss {
                fn drop(&mut self) {
                    self.0.dismiss();
                }
            }
            rayon::in_place_scope(|scope| {
                // No more helpers than the machine has other cores: a
                // helper without a core of its own spins on one that
                // another member needs, and every barrier waits for the
                // scheduler (eight threads on two cores: 42 ms a step for
                // the pile of 1,000, against 2.1 on two). The work is cut
                // the same whoever does it, so the result is the same.
                for _ in 1..self.threads.min(cores()) {
                    let crew = crew.clone();
                    scope.spawn(move |_| crew.serve());
                }
                let _dismiss = Dismiss(crew);
                f(&crewed)
            })
        })
    }

    /// Runs `f` on every thread of the pool at once, each with a [`Team`]
    /// handle (its index, the team size, barriers), and returns thread 0's
    /// result. With one thread, or while another team holds the pool, `f`
    /// runs here alone as a team of one: callers split work by
    /// [`Team::block_run`] and the like, so the result is the same.
    pub fn team<R: Send>(&self, f: impl Fn(&Team) -> R + Sync) -> R {
        if let Some(crew) = &self.crew {
            // The helpers that have joined by now (all, unless a worker
            // was busy elsewhere when the run began).
            let size = (1 + crew.joined()).min(self.threads);
            if size == 1 {
                return f(&Team::alone());
            }
            let sync = Arc::new(BarrierState::new(size));
            let lead = Mutex::new(None);
            crew.run_job(size, &|index| {
                let me = Team {
                    size,
                    index,
                    sync: sync.clone(),
                };
                let _poison = PoisonOnUnwind(&me.sync);
                let r = f(&me);
                if index == 0 {
                    *lead.lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
                }
            });
            return lead
                .into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("the leader ran its part");
        }
        let Some(shared) = &self.pool else {
            return f(&Team::alone());
        };
        let Ok(_held) = shared.team.try_lock() else {
            return f(&Team::alone());
        };
        let team = Team {
            size: self.threads,
            index: 0,
            sync: Arc::new(BarrierState::new(self.threads)),
        };
        let mut results = shared.pool.broadcast(|ctx| {
            let me = Team {
                index: ctx.index(),
                ..team.clone()
            };
            let _poison = PoisonOnUnwind(&me.sync);
            Some(f(&me))
        });
        results.swap_remove(0).expect("thread 0 ran")
    }
}

/// Items `0..n` cut in `members` runs of near-equal length (as
/// [`Team::share`] cuts them), each packed as [`take_runs`] reads it.
fn runs_of(n: usize, members: usize) -> Vec<AtomicU64> {
    assert!(n < 1 << 32, "at most 2^32 items");
    let members = members.max(1);
    (0..members)
        .map(|m| AtomicU64::new((((n * m / members) as u64) << 32) | (n * (m + 1) / members) as u64))
        .collect()
}

/// Runs `work` on items of `runs` (each `front << 32 | back`: its items
/// `front..back` not yet taken) as member `me`: its own run from the front,
/// then what is left of the others' from their back ends, one item at a
/// time, until none is left (a member without a run of its own only takes
/// from the others'). Each item is taken once, by whoever gets it first.
///
/// Why runs: neighbouring items touch neighbouring data (pairs and patches
/// in body order, body slots), so a thread that takes the same run in
/// every stage of a step finds what it wrote in the last one in its own
/// core's cache, and the solver's flows give it the same run of bodies
/// (`WideBatches::body_run`): the narrow stage's contacts of its pairs are
/// what it fills its bundles from. Taken from one shared counter, the
/// chunks alternated between the threads; the pile of 1,000 took 3.44-3.56
/// ms a step on two threads so, 3.27-3.36 by runs (its narrow stage
/// 0.68-0.75 -> 0.62-0.67 ms, its solve 2.11-2.25 -> 1.99-2.11;
/// `PIN_THREADS=1 profile_stages pile1000 300 2`, five alternated rounds).
/// Threads left to the operating system, which moves them and so their
/// caches between the cores now and then, gain less: 1-2 %.
fn take_runs(runs: &[AtomicU64], me: usize, mut work: impl FnMut(usize)) {
    if let Some(mine) = runs.get(me) {
        while let Some(k) = take_one(mine, true) {
            work(k);
        }
    }
    for k in 1..=runs.len() {
        let other = (me + k) % runs.len();
        if other != me {
            while let Some(k) = take_one(&runs[other], false) {
                work(k);
            }
        }
    }
}

/// Takes one item of a run packed as [`take_runs`] reads it, from its
/// `front` or its back; `None` when the run is empty.
fn take_one(run: &AtomicU64, front: bool) -> Option<usize> {
    let mut v = run.load(Ordering::Acquire);
    loop {
        let (first, end) = ((v >> 32) as usize, (v & 0xffff_ffff) as usize);
        if first >= end {
            return None;
        }
        let (next, item) = if front {
            (v + (1 << 32), first)
        } else {
            (v - 1, end - 1)
        };
        match run.compare_exchange_weak(v, next, Ordering::AcqRel, Ordering::Acquire) {
            Ok(_) => return Some(item),
            Err(now) => v = now,
        }
    }
}

/// Arrivals and generation of a spin barrier, and each member's run of
/// slices ([`Team::slices`]).
#[derive(Default)]
struct BarrierState {
    arrived: AtomicUsize,
    generation: AtomicUsize,
    /// Per member, the slices of its run not yet taken: `front << 32 |
    /// back` (`front..back`).
    runs: Box<[AtomicU64]>,
    /// Per member, how many times it has called [`Team::signal`], each
    /// on a cache line of its own (written by its member, read by the
    /// others).
    signals: Box<[Padded]>,
    /// A member panicked: the others leave their barriers by panicking
    /// too, instead of waiting for it forever.
    poisoned: std::sync::atomic::AtomicBool,
}

impl BarrierState {
    fn new(size: usize) -> BarrierState {
        BarrierState {
            runs: (0..size).map(|_| AtomicU64::new(0)).collect(),
            signals: (0..size).map(|_| Padded::default()).collect(),
            ..BarrierState::default()
        }
    }
}

/// A counter alone on its cache line (128 bytes: adjacent-line prefetch
/// pulls lines in pairs on x86).
#[derive(Default)]
#[repr(align(128))]
struct Padded(AtomicUsize);

/// Poisons a team's barriers when the member holding it unwinds.
struct PoisonOnUnwind<'a>(&'a BarrierState);

impl Drop for PoisonOnUnwind<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::Release);
        }
    }
}

/// One thread's handle on a team (see [`WorkerPool::team`]).
#[derive(Clone)]
pub(crate) struct Team {
    size: usize,
    index: usize,
    sync: Arc<BarrierState>,
}

/// Spins before a waiting thread starts yielding its core (more threads
/// than cores, or a core taken by another process).
const SPINS_BEFORE_YIELD: u32 = 2000;

impl Team {
    fn alone() -> Team {
        Team {
            size: 1,
            index: 0,
            sync: Arc::new(BarrierState::new(1)),
        }
    }

    /// This thread's index in the team (0 leads: it does the serial parts).
    pub fn index(&self) -> usize {
        self.index
    }

    /// Number of threads in the team.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Waits until every thread of the team has arrived. What each thread
    /// wrote before is seen by every thread after.
    pub fn barrier(&self) {
        if self.size == 1 {
            return;
        }
        let s = &self.sync;
        let generation = s.generation.load(Ordering::Acquire);
        if s.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.size {
            s.arrived.store(0, Ordering::Relaxed);
            s.generation.store(generation.wrapping_add(1), Ordering::Release);
            return;
        }
        self.spin_until(|| s.generation.load(Ordering::Acquire) != generation);
    }

    /// Spins until `done`, then yields between the tests; panics when
    /// another member has panicked (it will never arrive).
    fn spin_until(&self, done: impl Fn() -> bool) {
        let mut spins = 0u32;
        while !done() {
            if self.sync.poisoned.load(Ordering::Acquire) {
                panic!("another member of the thread team panicked");
            }
            if spins < SPINS_BEFORE_YIELD {
                std::hint::spin_loop();
                spins += 1;
            } else {
                std::thread::yield_now();
            }
        }
    }

    /// Tells the other members that this thread has done one more step of
    /// a sequence every member walks alike (see [`Team::await_peers`]).
    /// What it wrote before is seen by a member that waited for it.
    pub fn signal(&self) {
        if self.size > 1 {
            self.sync.signals[self.index].0.fetch_add(1, Ordering::Release);
        }
    }

    /// Whether every other member has signalled at least as often as this
    /// thread has ([`Team::await_peers`] without the wait).
    pub fn peers_ready(&self) -> bool {
        if self.size == 1 {
            return true;
        }
        let s = &self.sync;
        let mine = s.signals[self.index].0.load(Ordering::Relaxed);
        s.signals
            .iter()
            .enumerate()
            .all(|(k, peer)| k == self.index || peer.0.load(Ordering::Acquire) >= mine)
    }

    /// Waits until every other member has signalled at least as often as
    /// this thread has ([`Team::signal`]): a point-to-point wait, where a
    /// barrier would also hold back the members that are ahead.
    pub fn await_peers(&self) {
        self.spin_until(|| self.peers_ready());
    }

    /// This thread's share of `n` items as one contiguous run: the items cut
    /// in `size` runs of near-equal length, run `index` for thread `index`
    /// (below `min` items, thread 0 takes all). Where neighbouring items
    /// touch neighbouring data (patches in body order), a thread keeps
    /// working on the same data pass after pass instead of pulling cache
    /// lines the other threads just wrote.
    pub fn share(&self, n: usize, min: usize) -> std::ops::Range<usize> {
        if self.size == 1 || n < min.max(self.size) {
            return if self.index == 0 { 0..n } else { n..n };
        }
        let cut = |i: usize| n * i / self.size;
        cut(self.index)..cut(self.index + 1)
    }

    /// Runs `work` once for every slice below `n`, the slices spread over
    /// the team as they are done: each thread begins on its own run (the
    /// runs of [`Team::share`]) from the front, then takes what is left of
    /// the others' runs from their back ends, one slice at a time, until no
    /// slice is left. Every thread must call it (with the same `n`) before
    /// the next barrier, and no thread returns while its own run has a slice
    /// left; the caller's barrier follows.
    ///
    /// Why: the solver's joint islands cost unequally (by their rows and
    /// the contact points they own, which change step by step); dealt
    /// round-robin, the ragdoll pile's left one thread waiting 0.7 ms a step
    /// at their barriers (docs/pipeline.md, "Threads"). Taking from the back
    /// of another's run keeps each thread on its own stretch of the items,
    /// and so of their bodies' cache lines, pass after pass, moving only the
    /// meeting point. Which thread does a slice never changes what it
    /// computes, so the result is the same bits.
    pub fn slices(&self, n: usize, work: impl FnMut(usize)) {
        if self.size == 1 {
            (0..n).for_each(work);
            return;
        }
        assert!(n < 1 << 32, "at most 2^32 slices");
        let runs = &self.sync.runs;
        let own = self.share(n, 1);
        // A run left by the last call is empty (its owner took or saw taken
        // every slice before the barrier since), so another thread that
        // reads it before this reset finds nothing to take, which is right.
        runs[self.index].store(((own.start as u64) << 32) | own.end as u64, Ordering::Release);
        take_runs(runs, self.index, work);
    }

    /// This thread's share of `n` items to be worked in blocks of `block`
    /// ([`Team::blocks_of`]): the blocks cut in `size` contiguous runs of
    /// near-equal length, run `index` for thread `index` (a fixed
    /// assignment: no atomics, and the work of a block never depends on
    /// who does it). Below two blocks' worth, thread 0 takes all.
    ///
    /// Why runs and not blocks dealt round-robin: a thread that works on a
    /// contiguous run of bodies in every part of a sub-step keeps their
    /// lines in its core's cache between the passes and the integrations
    /// (the solver deals its patches by such runs, `ThreadFlow`).
    pub fn block_run(&self, n: usize, block: usize) -> std::ops::Range<usize> {
        let block = block.max(1);
        if self.size == 1 || n < 2 * block {
            if self.index == 0 {
                0..n
            } else {
                n..n
            }
        } else {
            let blocks = n.div_ceil(block);
            let cut = |i: usize| (blocks * i / self.size * block).min(n);
            cut(self.index)..cut(self.index + 1)
        }
    }

    /// `run` in blocks of `block` from its start.
    pub fn blocks_of(
        run: std::ops::Range<usize>,
        block: usize,
    ) -> impl Iterator<Item = std::ops::Range<usize>> {
        let (block, to) = (block.max(1), run.end);
        run.step_by(block).map(move |s| s..(s + block).min(to))
    }
}

#[cfg(test)]
mod tests;
