//! The falling pile's energy over many seeds (`warm_start_energy [FIRST
//! LAST]`, seeds 1-120 by default): the scene of
//! `contact_physics::a_falling_pile_of_boxes_and_rocks_never_gains_energy`
//! (`tests/common/falling_pile.rs`), 360 steps a seed. Every step whose
//! total energy (kinetic plus potential) rises by more than the test allows
//! (a millionth of the start) is taken again from a copy of the world made
//! before it, twice: with the contact cache cleared (no warm start from the
//! last step) and with the push-out off. docs/pipeline.md, "Warm starts that
//! add energy", reads what it prints. `ITERATIONS=n` and `SUBSTEPS=n` set
//! those `WorldSettings` fields for every seed.
#[path = "../tests/common/falling_pile.rs"]
mod falling_pile;

use falling_pile::{allowed_gain, falling_pile};
use tumble::world::{World, WorldSettings};

/// The pile's total energy (J).
fn total(world: &World) -> f64 {
    world.kinetic_energy() + world.potential_energy()
}

/// How much `world` gains in one step taken from a copy of it with `change`
/// made first.
fn retaken(world: &World, change: impl FnOnce(&mut World)) -> f64 {
    let mut copy = world.clone();
    change(&mut copy);
    copy.step();
    total(&copy) - total(world)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let first: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let last: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(120);
    if first > last {
        eprintln!("usage: warm_start_energy [FIRST LAST] (seeds FIRST..=LAST, FIRST <= LAST)");
        std::process::exit(2);
    }
    let mut settings = WorldSettings::default();
    if let Some(n) = std::env::var("ITERATIONS").ok().and_then(|v| v.parse().ok()) {
        settings.iterations = n;
    }
    if let Some(n) = std::env::var("SUBSTEPS").ok().and_then(|v| v.parse().ok()) {
        settings.substeps = n;
    }
    let (mut seeds, mut steps, mut cold_loses, mut still_without_push) = (0, 0, 0, 0);
    let mut largest = (0.0f64, 0u64, 0usize);
    for seed in first..=last {
        let (mut world, _) = falling_pile(seed, settings.clone());
        let allowed = allowed_gain(total(&world));
        let mut gained_here = false;
        for step in 1..=360 {
            let before = world.clone();
            world.step();
            let gain = total(&world) - total(&before);
            if gain <= allowed {
                continue;
            }
            let cold = retaken(&before, World::clear_contact_cache);
            let no_push = retaken(&before, |w| {
                let s = WorldSettings {
                    push_out_iterations: 0,
                    ..w.settings().clone()
                };
                w.set_settings(s).unwrap();
            });
            println!("seed {seed:3} step {step:3}: gained {gain:.5} J; retaken without the warm start {cold:+.5} J, without the push-out {no_push:+.5} J");
            gained_here = true;
            steps += 1;
            cold_loses += usize::from(cold <= 0.0);
            still_without_push += usize::from(no_push > allowed);
            if gain > largest.0 {
                largest = (gain, seed, step);
            }
        }
        seeds += usize::from(gained_here);
    }
    println!(
        "{seeds} of {} seeds gained energy, in {steps} steps; largest {:.4} J (seed {}, step {}); \
         without the warm start {cold_loses} of those steps lose energy, without the push-out {still_without_push} still gain",
        last + 1 - first,
        largest.0,
        largest.1,
        largest.2
    );
}
