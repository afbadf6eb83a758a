//! The cost of handing work to a rayon pool's threads that the step's
//! threads pay: how long a parallel section takes after a serial stretch of
//! each length (the wake-up of a worker that went to sleep while there was
//! no work, which `pool/crew.rs` avoids by holding the workers for a step).
//! `cargo run --release -p tumble --example pool_wake`. On this project's
//! 2-core VM: a section 2.7 us after 0-5 us of serial work, 11-12 us after
//! 20 us or more. What every barrier of the solver's team pays at least,
//! the round trip of a cache line between two cores, is measured by
//! `core-round-trip` (`cargo run --release -p tumble-bench --bin
//! core-round-trip`), which the benchmark harness records beside every
//! multi-thread run.
use rayon::prelude::*;
use std::time::Instant;

/// Keeps this thread busy for `us` microseconds.
fn busy(us: f64) {
    let t = Instant::now();
    while t.elapsed().as_secs_f64() * 1e6 < us {
        std::hint::spin_loop();
    }
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool of two threads");
    let items: Vec<u64> = (0..2).collect();
    pool.install(|| {
        for gap in [0.0, 5.0, 20.0, 50.0, 100.0, 200.0, 500.0] {
            let rounds = 400;
            let mut total = 0.0;
            for _ in 0..rounds {
                busy(gap);
                let t = Instant::now();
                let sum: u64 = items
                    .par_iter()
                    .with_max_len(1)
                    .map(|&x| {
                        busy(2.0);
                        x
                    })
                    .sum();
                std::hint::black_box(sum);
                total += t.elapsed().as_secs_f64();
            }
            println!(
                "after {gap:>5} us of serial work: a section of two 2 us tasks took {:.1} us",
                total / rounds as f64 * 1e6
            );
        }
    });
}
