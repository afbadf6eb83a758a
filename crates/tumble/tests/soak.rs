//! Long runs: the pile(100) and the chain stepped for many steps at
//! dt = 1/240 s with every step checked: no non-finite state and no
//! quarantined body, no body outside its container (the pile's walls; for
//! the chain, every link still interlocked with the next), total energy never
//! above its start (both scenes are passive: gravity, contacts and friction
//! can only take energy out, up to the push-out's bounded correction), and
//! memory flat (resident set size sampled along the run).
//!
//! The short versions run in the test suite; the long ones (100,000 steps
//! each) with `make soak`, which runs the ignored tests of this file and
//! prints a summary.

use tumble::scenes::{self, Scene};
use tumble::world::{BodyId, World};

const DT: f64 = 1.0 / 240.0;

/// Resident set size of this process (bytes), from /proc (0 elsewhere).
fn rss_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .map_or(0, |kb| kb * 1024)
}

fn total_energy(world: &World) -> f64 {
    world.kinetic_energy() + world.potential_energy()
}

/// What must hold of the bodies at every step, besides finiteness.
type Containment = fn(&World, &[BodyId]) -> Result<(), String>;

/// The pile's container: inner floor 6 m x 6 m (|x|, |y| <= 3 m, with the
/// body's own size allowed through the wall's slop) and above the floor.
fn inside_pile_container(world: &World, ids: &[BodyId]) -> Result<(), String> {
    for &id in &ids[5..] {
        let p = world.center_of_mass(id).map_err(|e| e.to_string())?;
        if p.x.abs() > 3.01 || p.y.abs() > 3.01 || p.z < 0.0 {
            return Err(format!("body {id:?} left the container: {p:?}"));
        }
    }
    Ok(())
}

/// The chain's links stay interlocked: two rings (R = 1, r = 0.2) threaded
/// through each other cannot have centres more than 2 R apart; a link that
/// tunnelled out would drift beyond.
fn chain_linked(world: &World, ids: &[BodyId]) -> Result<(), String> {
    for pair in ids.windows(2) {
        let a = world.center_of_mass(pair[0]).map_err(|e| e.to_string())?;
        let b = world.center_of_mass(pair[1]).map_err(|e| e.to_string())?;
        let d = (a - b).length();
        if d > 2.0 + 0.02 {
            return Err(format!(
                "links {:?} and {:?} are {d} m apart: unlinked",
                pair[0], pair[1]
            ));
        }
    }
    Ok(())
}

struct SoakSummary {
    energy_start: f64,
    energy_max: f64,
    energy_end: f64,
    kinetic_end: f64,
    rss_after_warmup: u64,
    rss_end: u64,
}

fn soak(name: &str, scene: Scene, steps: usize, contained: Containment) -> SoakSummary {
    let mut scene = scene;
    scene.settings.dt = DT;
    let (mut world, ids) = scene.build().unwrap();
    let energy_start = total_energy(&world);
    let mut energy_max = energy_start;
    let warmup = steps / 5;
    let mut rss_after_warmup = 0;
    let mut rss_samples = Vec::new();
    for k in 1..=steps {
        let report = world.step();
        assert!(
            report.quarantined.is_empty(),
            "{name} step {k}: quarantined {:?}",
            report.quarantined
        );
        for &id in &ids {
            let s = world.body(id).unwrap().state();
            assert!(s.is_finite(), "{name} step {k}: {id:?} is not finite: {s:?}");
        }
        if let Err(e) = contained(&world, &ids) {
            panic!("{name} step {k}: {e}");
        }
        let e = total_energy(&world);
        energy_max = energy_max.max(e);
        if k == warmup {
            rss_after_warmup = rss_bytes();
        }
        if k % (steps / 10).max(1) == 0 {
            rss_samples.push(rss_bytes());
        }
    }
    let summary = SoakSummary {
        energy_start,
        energy_max,
        energy_end: total_energy(&world),
        kinetic_end: world.kinetic_energy(),
        rss_after_warmup,
        rss_end: rss_bytes(),
    };
    println!(
        "soak {name}: {steps} steps of {DT:.6} s ({:.0} s simulated), {} bodies: no NaN, no quarantine, \
         contained; energy start {:.4} J, max {:.4} J, end {:.4} J (kinetic {:.3e} J); RSS after warm-up \
         {:.1} MiB, end {:.1} MiB, samples {:?} MiB",
        steps as f64 * DT,
        ids.len(),
        summary.energy_start,
        summary.energy_max,
        summary.energy_end,
        summary.kinetic_end,
        summary.rss_after_warmup as f64 / 1048576.0,
        summary.rss_end as f64 / 1048576.0,
        rss_samples
            .iter()
            .map(|&b| (b as f64 / 1048576.0 * 10.0).round() / 10.0)
            .collect::<Vec<_>>()
    );
    summary
}

/// Energy may rise above its start only by round-off and the push-out's
/// bounded correction: a tiny fraction of the potential energy in play.
fn check_energy(name: &str, s: &SoakSummary, scale: f64) {
    assert!(
        s.energy_max <= s.energy_start + 1e-3 * scale,
        "{name}: energy rose from {} to {} J (scale {scale} J)",
        s.energy_start,
        s.energy_max
    );
    assert!(s.energy_end <= s.energy_start, "{name}: energy grew");
}

/// Memory is flat once the contact buffers have grown: at most 8 MiB more
/// after the first fifth of the run (a leak of even a few bytes per contact
/// per step would show far more over a long run).
fn check_memory(name: &str, s: &SoakSummary) {
    if s.rss_after_warmup > 0 {
        assert!(
            s.rss_end <= s.rss_after_warmup + 8 * 1048576,
            "{name}: RSS grew from {} to {} bytes",
            s.rss_after_warmup,
            s.rss_end
        );
    }
}

/// |m g| summed over the dynamic bodies times the height they can fall (J).
fn energy_scale(scene: &Scene, height: f64) -> f64 {
    let (world, _) = scene.build().unwrap();
    let weight: f64 = world
        .body_ids()
        .into_iter()
        .filter_map(|id| world.body(id).ok())
        .filter(|b| b.inv_mass() > 0.0)
        .map(|b| b.mass() * 9.81)
        .sum();
    weight * height
}

fn soak_pile(steps: usize) {
    let scene = scenes::pile(1);
    let scale = energy_scale(&scene, 1.0);
    let s = soak("pile(100)", scene, steps, inside_pile_container);
    check_energy("pile", &s, scale);
    check_memory("pile", &s);
    // After the first seconds the pile rests.
    if steps >= 2000 {
        assert!(
            s.kinetic_end < 1e-3 * scale,
            "pile still moving: {} J",
            s.kinetic_end
        );
    }
}

fn soak_chain(steps: usize) {
    let scene = scenes::chain();
    let scale = energy_scale(&scene, 30.0);
    let s = soak("chain", scene, steps, chain_linked);
    check_energy("chain", &s, scale);
    check_memory("chain", &s);
}

#[test]
fn pile_2000_steps_stay_finite_contained_and_dissipative() {
    soak_pile(2000);
}

#[test]
fn chain_1000_steps_stay_finite_linked_and_dissipative() {
    soak_chain(1000);
}

/// `make soak`: 100,000 steps (417 s simulated).
#[test]
#[ignore]
fn soak_pile_100k_steps() {
    soak_pile(100_000);
}

/// `make soak`: 100,000 steps (417 s simulated).
#[test]
#[ignore]
fn soak_chain_100k_steps() {
    soak_chain(100_000);
}

#[test]
fn rss_is_readable_here() {
    // The memory check needs /proc; on Linux (CI) it must be there.
    if cfg!(target_os = "linux") {
        assert!(rss_bytes() > 0);
    }
}
