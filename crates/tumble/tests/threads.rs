//! Threads change the speed of a step, never its result: the pile (also
//! with bouncing bodies), the ragdoll pile, the torus chain and a volley of swept projectiles stepped
//! on 1, 2, 3 and 8 threads follow bit-identical trajectories (hashes
//! compared every few steps, so a divergence is caught where it starts, with
//! the report's solver residual, a maximum met across the threads), and the
//! report says how many threads ran; with `adaptive_threads` (steps moved
//! to one thread while the threads are slower) the trajectory is the same.

use tumble::scenes::{self, Scene};
use tumble::world::{World, WorldSettings};

/// The state hash and the bits of the solver's residual every `every`
/// steps over `steps` steps on `threads` threads.
fn trajectory(scene: &Scene, threads: u32, steps: usize, every: usize) -> Vec<(u64, u64)> {
    let mut scene = scene.clone();
    scene.settings.threads = threads;
    // The threads always, never one thread because they seemed slower.
    scene.settings.adaptive_threads = false;
    let (mut world, _) = scene.build().unwrap();
    let mut hashes = Vec::new();
    assert_eq!(world.threads(), threads as usize);
    let mut threaded = 0;
    for k in 0..steps {
        let report = world.step();
        // A step small enough runs on one thread; none runs on more than asked.
        assert!(report.threads == threads as usize || report.threads == 1);
        threaded += usize::from(report.threads > 1);
        assert!(report.quarantined.is_empty());
        assert!(
            report.solver_residual >= 0.0 && report.solver_residual.is_sign_positive(),
            "residual {:e}",
            report.solver_residual
        );
        if k % every == every - 1 {
            hashes.push((world.state_hash(), report.solver_residual.to_bits()));
        }
    }
    assert!(
        threads == 1 || threaded > 0,
        "{}: no step ran on the threads",
        scene.name
    );
    hashes
}

fn same_for_every_thread_count(scene: Scene, steps: usize, every: usize) {
    let serial = trajectory(&scene, 1, steps, every);
    for threads in [2, 3, 8] {
        let parallel = trajectory(&scene, threads, steps, every);
        let first = serial.iter().zip(&parallel).position(|(a, b)| a != b);
        assert!(
            first.is_none(),
            "{}: {threads} threads leave the serial trajectory at step {}",
            scene.name,
            first.map_or(0, |i| (i + 1) * every)
        );
    }
}

#[test]
fn pile_is_bit_identical_on_1_2_3_and_8_threads() {
    // 1,000 bodies falling into the bin, long enough to pile up and touch
    // in large islands (many colours, many pairs per thread).
    same_for_every_thread_count(scenes::pile(10), 90, 10);
}

#[test]
fn bouncing_pile_is_bit_identical_on_1_2_3_and_8_threads() {
    // Restitution reads every record with a bouncing patch before the
    // sub-steps, and bundles mix lanes that bounce (filled from their
    // records, after restitution) with lanes that do not (filled from
    // records written afresh, theirs left empty in the arrays): a third
    // of the pile's bodies bounce, a third slightly.
    let mut scene = scenes::pile(3);
    for (k, body) in scene.bodies.iter_mut().enumerate() {
        body.material.restitution = [0.0, 0.3, 0.8][k % 3];
    }
    same_for_every_thread_count(scene, 90, 10);
}

#[test]
fn several_push_out_passes_end_together_on_every_thread_count() {
    // With more than one push-out pass per sub-step, the threads decide
    // together after each pass whether another is needed; a decision that
    // differed between them left the team waiting forever. Run on a thread
    // of its own so that a hang fails the test instead of stalling the run.
    let mut scene = scenes::pile(10);
    scene.settings.push_out_iterations = 3;
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        same_for_every_thread_count(scene, 60, 10);
        done.send(()).ok();
    });
    finished
        .recv_timeout(std::time::Duration::from_secs(120))
        .expect("the threads did not finish their push-out passes together (or a trajectory differed)");
}

#[test]
fn ragdoll_pile_is_bit_identical_on_1_2_3_and_8_threads() {
    // Joint islands four to a unit of SIMD lanes, the contacts they own
    // (limbs on their own chests) and the colour batches around them, on
    // the pool: 100 ragdolls toppling onto each other.
    same_for_every_thread_count(scenes::ragdoll_pile(), 60, 10);
}

#[test]
fn chain_is_bit_identical_on_1_2_3_and_8_threads() {
    same_for_every_thread_count(scenes::chain(), 120, 10);
}

#[test]
fn volley_of_swept_projectiles_is_bit_identical_on_1_2_3_and_8_threads() {
    // Continuous collision sweeps fast bodies on the pool and puts them back
    // in slot order: 12 projectiles of every kind (mesh balls among them,
    // so the step runs on the threads), half of them bullets, fired at a
    // turned mesh slab and through each other's paths.
    let base = scenes::ProjectileCase {
        projectile: scenes::Projectile::Mesh,
        mesh_slab: true,
        thickness: 0.01,
        degrees: 30.0,
        speed: 300.0,
    };
    let mut scene = base.scene(true);
    for k in 0..12 {
        let projectile = scenes::Projectile::ALL[k % 5];
        let x = -0.6 + 0.1 * k as f64;
        let body = tumble::world::BodyDesc::dynamic(projectile.shape())
            .at(base.start() + tumble::collide::DVec3::new(x, 0.1 * (k % 3) as f64, 0.2 * k as f64))
            .with_velocity(
                tumble::collide::DVec3::new(-x * 20.0, 0.0, -100.0 - 40.0 * k as f64),
                tumble::collide::DVec3::new(0.0, 5.0 * k as f64, 0.0),
            )
            .with_ccd(k % 2 == 0);
        scene.bodies.push(body);
    }
    let (mut world, _) = scene.build().unwrap();
    let swept: usize = (0..40).map(|_| world.step().continuous).sum();
    assert!(swept > 0, "the volley never needed continuous collision");
    same_for_every_thread_count(scene, 40, 4);
}

#[test]
fn adaptive_threads_give_the_bits_of_one_thread_whatever_they_choose() {
    // With `adaptive_threads` a step runs on the threads or on one thread,
    // whichever was measured faster lately: the trajectory is the serial
    // one either way, and each report says where its step ran.
    let scene = scenes::pile(10);
    let serial = trajectory(&scene, 1, 60, 10);
    let mut adaptive = scene.clone();
    adaptive.settings.threads = 2;
    assert!(adaptive.settings.adaptive_threads, "on by default");
    let (mut world, _) = adaptive.build().unwrap();
    let mut hashes = Vec::new();
    for k in 0..60 {
        let report = world.step();
        assert!(report.threads == 2 || report.threads == 1);
        if k % 10 == 9 {
            hashes.push((world.state_hash(), report.solver_residual.to_bits()));
        }
    }
    assert_eq!(hashes, serial);
}

#[test]
fn bad_thread_counts_are_refused_and_zero_means_every_core() {
    let too_many = WorldSettings {
        threads: 100_000,
        ..WorldSettings::default()
    };
    let err = World::new(too_many).unwrap_err().to_string();
    assert!(err.contains("settings.threads"), "{err}");
    let mut world = World::new(WorldSettings::default()).unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(world.threads(), cores);
    assert_eq!(world.step().threads, 1, "an empty world steps on one thread");
    let before = world.settings().clone();
    assert!(world
        .set_settings(WorldSettings {
            threads: 5000,
            ..before.clone()
        })
        .is_err());
    assert_eq!(world.settings(), &before, "a refused setting changes nothing");
    world
        .set_settings(WorldSettings { threads: 3, ..before })
        .unwrap();
    assert_eq!(world.threads(), 3);
}
