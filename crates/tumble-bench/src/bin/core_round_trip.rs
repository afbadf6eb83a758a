//! `core-round-trip`: how long one cache line takes to go from one thread to
//! another and back (two threads handing a counter to each other through an
//! atomic), where the OS places them, as every engine's threads are placed.
//! Prints one JSON line: the median round trip in ns over a few rounds, and
//! each round's.
//!
//! Why the benchmark harness records it: a solver on two threads hands its
//! bodies and barriers from core to core hundreds of times a step, so its
//! step time follows this number. On this project's 2-core VM it was 55-140
//! ns for some hours and 340-510 ns for others (the host placing the two
//! virtual cores near each other or not; one thread's time does not move),
//! and tumble's pile of 1,000 took 3.2-3.3 ms a step on two threads in the
//! first case and 7.1-7.4 ms (slower than one thread's 4.7) in the second
//! (docs/benchmarks.md, "Reading the ratios"). A two-thread row is read
//! against the round trips measured next to it.
//!
//! Usage: `core-round-trip [--rounds R] [--trips N]`

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// The mean round trip over one round of `trips` hand-overs, in ns.
fn round(trips: u64) -> f64 {
    let ball = Arc::new(AtomicU64::new(0));
    let other = ball.clone();
    // The other thread answers each odd value with the next even one.
    let echo = std::thread::spawn(move || {
        for i in 0..trips {
            while other.load(Ordering::Acquire) != 2 * i + 1 {
                std::hint::spin_loop();
            }
            other.store(2 * i + 2, Ordering::Release);
        }
    });
    let start = Instant::now();
    for i in 0..trips {
        ball.store(2 * i + 1, Ordering::Release);
        while ball.load(Ordering::Acquire) != 2 * i + 2 {
            std::hint::spin_loop();
        }
    }
    let ns = start.elapsed().as_nanos() as f64 / trips as f64;
    // The echo has answered every trip by now; a thread that cannot be
    // joined (it panicked) leaves the figure as it is.
    let _ = echo.join();
    ns
}

/// The value after `flag` in `args`, parsed, or `default`.
fn option(args: &[String], flag: &str, default: u64) -> Result<u64, String> {
    match args.iter().position(|a| a == flag) {
        None => Ok(default),
        Some(k) => args
            .get(k + 1)
            .and_then(|v| v.parse().ok())
            .filter(|&v| v > 0)
            .ok_or_else(|| format!("{flag} needs a positive whole number")),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parsed = option(&args, "--rounds", 5).and_then(|r| Ok((r, option(&args, "--trips", 100_000)?)));
    let (rounds, trips) = match parsed {
        Ok(p) => p,
        Err(e) => {
            eprintln!("core-round-trip: {e}\nusage: core-round-trip [--rounds R] [--trips N]");
            std::process::exit(2);
        }
    };
    let mut each: Vec<f64> = (0..rounds).map(|_| round(trips)).collect();
    let rounds_ns = each.clone();
    each.sort_by(f64::total_cmp);
    let median = each[each.len() / 2];
    println!(
        "{}",
        serde_json::json!({ "core_round_trip_ns": median, "rounds_ns": rounds_ns, "trips": trips })
    );
}
