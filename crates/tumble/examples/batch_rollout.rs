//! The Rust side of `bench/rollout_overhead.py`: B copies of a scene stepped
//! T steps by `tumble::batch`, every body's position recorded after every
//! step (the work of `tumble.rollout(..., record=["positions"])`), timed on
//! each thread count given; one JSON line per thread count with the best
//! time of `repeats` and a hash of the final positions, so that the Python
//! side is checked to have done the same work:
//!
//! ```text
//! cargo run --release -p tumble --example batch_rollout -- SCENE B T REPEATS THREADS...
//! ```

use std::time::Instant;

use tumble::batch::for_each_world;
use tumble::scene::load_scene;
use tumble::world::World;

/// FNV-1a over the bytes of the final positions, world by world, body by body.
fn hash(positions: &[Vec<f64>], n: usize) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in positions {
        for x in &p[p.len() - 3 * n..] {
            for b in x.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    h
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 6 {
        return Err("usage: batch_rollout SCENE B T REPEATS THREADS...".into());
    }
    let (base, ids) = load_scene(&args[1])?.build()?;
    let (b, t, repeats): (usize, usize, usize) = (args[2].parse()?, args[3].parse()?, args[4].parse()?);
    let n = ids.len();
    for threads in &args[5..] {
        let threads: u32 = threads.parse()?;
        let mut best = f64::INFINITY;
        let mut digest = 0;
        for _ in 0..repeats {
            let mut worlds: Vec<World> = vec![base.clone(); b];
            let mut positions: Vec<Vec<f64>> = vec![Vec::with_capacity(t * n * 3); b];
            let start = Instant::now();
            for_each_world(&mut worlds, &mut positions, threads, |_, world, out| {
                for _ in 0..t {
                    world.step();
                    for &id in &ids {
                        out.extend(world.pose(id).map_or([f64::NAN; 3], |p| p.position.to_array()));
                    }
                }
            });
            best = best.min(start.elapsed().as_secs_f64());
            digest = hash(&positions, n);
        }
        println!(r#"{{"threads": {threads}, "seconds": {best}, "hash": "{digest:016x}"}}"#);
    }
    Ok(())
}
