//! The costs of handing work between threads that the step's threads pay:
//! how long a parallel section of a rayon pool takes after a serial
//! stretch of each length (the wake-up of a worker that went to sleep while
//! there was no work, which `pool/crew.rs` avoids by holding the workers
//! for a step), and the round trip of a value between two spinning threads
//! (what every barrier of the solver's team pays at least).
//! `cargo run --release -p tumble --example pool_wake`. On this project's
//! 2-core VM: a section 2.7 us after 0-5 us of serial work, 11-12 us after
//! 20 us or more; a round trip 0.04-0.14 us, but 0.5 us in spells of a few
//! minutes in which the pile of 1,000 takes 4.3-4.8 ms a step on two
//! threads instead of 2.1-2.4 (and 3.5 on one): the two cores then share
//! their cache lines far more slowly.
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Keeps this thread busy for `us` microseconds.
fn busy(us: f64) {
    let t = Instant::now();
    while t.elapsed().as_secs_f64() * 1e6 < us {
        std::hint::spin_loop();
    }
}

/// Mean round trip (us) of a counter bounced `n` times between this
/// thread and another, both spinning.
fn round_trip(n: u64) -> f64 {
    let flag = Arc::new(AtomicU64::new(0));
    let other = flag.clone();
    let echo = std::thread::spawn(move || {
        for i in 0..n {
            while other.load(Ordering::Acquire) != 2 * i + 1 {
                std::hint::spin_loop();
            }
            other.store(2 * i + 2, Ordering::Release);
        }
    });
    let start = Instant::now();
    for i in 0..n {
        flag.store(2 * i + 1, Ordering::Release);
        while flag.load(Ordering::Acquire) != 2 * i + 2 {
            std::hint::spin_loop();
        }
    }
    let mean = start.elapsed().as_secs_f64() / n as f64 * 1e6;
    echo.join().expect("the echo thread ends");
    mean
}

fn main() {
    println!(
        "round trip between two spinning threads: {:.3} us",
        round_trip(200_000)
    );
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
