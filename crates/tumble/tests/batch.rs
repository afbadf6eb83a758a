//! A batch of worlds (tumble::batch) gives each world the trajectory it has
//! stepped alone, bit for bit, for any thread count of the batch and
//! whatever the other worlds are.

use tumble::batch::{for_each_world, step_worlds};
use tumble::scenes;
use tumble::world::World;

/// Different worlds: a domino row, a pile, a torus chain, a ragdoll pile
/// piece, restitution sweeps of a ball drop, each with its own thread count.
fn mixed_worlds() -> Vec<World> {
    let mut worlds = Vec::new();
    for (k, scene) in [
        scenes::domino(),
        scenes::pile(2),
        scenes::chain(),
        scenes::ball_drop(1.0, 0.3),
        scenes::ball_drop(2.0, 0.9),
        scenes::incline(0.2),
        scenes::cradle(),
    ]
    .into_iter()
    .enumerate()
    {
        let mut scene = scene;
        scene.settings.threads = 1 + (k as u32 % 3);
        worlds.push(scene.build().expect("standard scene").0);
    }
    worlds
}

#[test]
fn each_world_of_a_batch_is_the_world_stepped_alone_for_any_thread_count() {
    const STEPS: usize = 40;
    let alone: Vec<u64> = mixed_worlds()
        .into_iter()
        .map(|mut w| {
            for _ in 0..STEPS {
                w.step();
            }
            w.state_hash()
        })
        .collect();
    for threads in [1, 2, 3, 8] {
        let mut worlds = mixed_worlds();
        let reports = step_worlds(&mut worlds, STEPS, threads);
        assert!(reports.iter().all(Option::is_some));
        let hashes: Vec<u64> = worlds.iter().map(World::state_hash).collect();
        assert_eq!(hashes, alone, "{threads} threads");
        // Each world keeps its own thread setting.
        for (k, w) in worlds.iter().enumerate() {
            assert_eq!(w.settings().threads, 1 + (k as u32 % 3));
        }
    }
    // The chain moved: the test compares trajectories, not worlds at rest.
    let mut start = mixed_worlds();
    assert_ne!(start[2].state_hash(), alone[2]);
    assert_eq!(step_worlds(&mut start, 0, 2), vec![None; 7]);
}

#[test]
fn copies_of_one_world_given_different_pushes_diverge_and_repeat() {
    // Eight copies of the domino row, the first domino pushed with eight
    // different impulses: eight different outcomes, the same on 1 and 8 threads.
    let run = |threads: u32| {
        let (base, ids) = scenes::domino().build().unwrap();
        let mut worlds = vec![base; 8];
        let mut pushes: Vec<f64> = (0..8).map(|k| 0.02 + 0.01 * k as f64).collect();
        let first = ids[1];
        for_each_world(&mut worlds, &mut pushes, threads, |_, world, push| {
            let p = world.center_of_mass(first).unwrap();
            world
                .apply_impulse_at_point(first, tumble::collide::DVec3::new(*push, 0.0, 0.0), p)
                .unwrap();
            for _ in 0..60 {
                world.step();
            }
        });
        worlds.iter().map(World::state_hash).collect::<Vec<_>>()
    };
    let serial = run(1);
    assert_eq!(serial, run(8));
    let mut distinct = serial.clone();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), 8, "different pushes give different worlds");
}
