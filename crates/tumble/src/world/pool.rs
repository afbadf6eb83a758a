//! The world's worker threads: a rayon pool per thread count, made once per
//! process and shared by every world that asks for that count (a test suite
//! or a batch of worlds does not spawn threads per world).
//!
//! Determinism is the callers' part and rests on two rules: work is split
//! by index, and every result is merged in index order (`map` collects in
//! order; the solver's colour batches touch disjoint bodies). One thread
//! never enters rayon at all, so `threads = 1` is the plain serial code.

use rayon::prelude::*;
use std::sync::{Arc, Mutex, OnceLock};

/// Largest accepted `WorldSettings::threads`.
pub(crate) const MAX_THREADS: u32 = 1024;

/// Worker threads of one world.
#[derive(Clone)]
pub(crate) struct WorkerPool {
    threads: usize,
    pool: Option<Arc<rayon::ThreadPool>>,
}

impl std::fmt::Debug for WorkerPool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "WorkerPool({} threads)", self.threads)
    }
}

/// The pools made so far, by thread count.
type Registry = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;

fn registry() -> &'static Registry {
    static POOLS: OnceLock<Registry> = OnceLock::new();
    POOLS.get_or_init(|| Mutex::new(Vec::new()))
}

impl WorkerPool {
    /// The pool for `requested` threads (0: every core). If the threads
    /// cannot be started, the world runs serially (with the same results).
    pub fn new(requested: u32) -> WorkerPool {
        let threads = match requested {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n as usize,
        };
        if threads <= 1 {
            return WorkerPool {
                threads: 1,
                pool: None,
            };
        }
        let mut pools = registry().lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, pool)) = pools.iter().find(|(n, _)| *n == threads) {
            return WorkerPool {
                threads,
                pool: Some(pool.clone()),
            };
        }
        match rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("tumble-worker-{i}"))
            .build()
        {
            Ok(pool) => {
                let pool = Arc::new(pool);
                pools.push((threads, pool.clone()));
                WorkerPool {
                    threads,
                    pool: Some(pool),
                }
            }
            Err(_) => WorkerPool {
                threads: 1,
                pool: None,
            },
        }
    }

    /// Threads the world runs on.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// `f` over consecutive chunks of `items` (its arguments: the index of
    /// the chunk's first item, and the chunk), results in chunk order. On
    /// one thread `f` sees all items at once; on more, chunks of `chunk`
    /// items are spread over the threads. Callers write results that do
    /// not depend on where the chunks are cut.
    pub fn map_chunks<T: Sync, R: Send>(
        &self,
        items: &[T],
        chunk: usize,
        f: impl Fn(usize, &[T]) -> R + Sync + Send,
    ) -> Vec<R> {
        let chunk = chunk.max(1);
        match &self.pool {
            Some(pool) if items.len() > chunk => pool.install(|| {
                items
                    .par_chunks(chunk)
                    .enumerate()
                    .map(|(k, c)| f(k * chunk, c))
                    .collect()
            }),
            _ => vec![f(0, items)],
        }
    }

    /// Runs `f` on a worker of the pool (or here, serially). A step runs
    /// whole inside one `run`, so the hand-over to the pool is paid once
    /// per step and the parallel sections inside start from a worker.
    pub fn run<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.pool {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }
}
