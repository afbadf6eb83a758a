//! tumble against Rapier on the pyramid and the piles of 100 and 1,000 bodies
//! (shared/scenes.md) in one criterion run, so that the ratio of the two
//! comes from the same machine state: both built from `tumble::scenes`
//! (Rapier through `rapier_scenes::build`: same bodies, masses and materials), sleeping off, each engine at its default iterations
//! and sub-steps, one thread.
//!
//! Each engine first steps its scene for one simulated second (the pile
//! lands, every contact exists and is warm), then criterion times single
//! steps of the running simulation. Before the timings, the pyramid's top
//! box drift over that second is printed for both, so a fast step that lets
//! the stack move cannot pass unnoticed.
//!
//! Run: `nice -n 10 cargo bench -p tumble-bench --bench dynamics_vs_rapier`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;
use tumble::scenes as tscenes;
use tumble::world::World;
use tumble_bench::rapier_scenes as rs;

const SETTLE_STEPS: usize = 60;

fn tumble_world(mut scene: tscenes::Scene) -> (World, Vec<tumble::world::BodyId>) {
    // One thread each: tumble serial, Rapier (built with `parallel`) on a
    // global rayon pool of one thread.
    let _ = rayon::ThreadPoolBuilder::new().num_threads(1).build_global();
    scene.settings.threads = 1;
    let (mut world, ids) = scene.build().expect("standard scene builds");
    for _ in 0..SETTLE_STEPS {
        world.step();
    }
    (world, ids)
}

fn settle_rapier(w: &mut rapier3d::prelude::PhysicsWorld) {
    for _ in 0..SETTLE_STEPS {
        w.step();
    }
}

fn pyramid(c: &mut Criterion) {
    let scene = tscenes::pyramid();
    let mut rw = rs::build(&scene, false).expect("the pyramid builds in Rapier");
    let (mut tw, tids) = tumble_world(scene);
    let top_index = tids.len() - 1;
    let top = rw.centre(top_index);
    settle_rapier(&mut rw.world);
    let t_top = tw.center_of_mass(tids[top_index]).expect("live");
    println!(
        "pyramid top box drift after {SETTLE_STEPS} steps: tumble {:.2e} m, rapier3d {:.2e} m",
        (t_top - tumble::collide::DVec3::from_array(top)).length(),
        (tumble::collide::DVec3::from_array(rw.centre(top_index)) - tumble::collide::DVec3::from_array(top))
            .length()
    );
    let mut g = c.benchmark_group("pyramid");
    g.bench_function("tumble", |b| b.iter(|| tw.step()));
    g.bench_function("rapier3d", |b| b.iter(|| rw.world.step()));
    g.finish();
}

fn pile(c: &mut Criterion, layers: usize) {
    let n = layers * 100;
    let scene = tscenes::pile(layers);
    let mut rw = rs::build(&scene, false).expect("the pile builds in Rapier").world;
    let (mut tw, _) = tumble_world(scene);
    settle_rapier(&mut rw);
    let mut g = c.benchmark_group(format!("pile{n}"));
    if n >= 1000 {
        g.sample_size(20).measurement_time(Duration::from_secs(8));
    }
    g.bench_function("tumble", |b| b.iter(|| tw.step()));
    g.bench_function("rapier3d", |b| b.iter(|| rw.step()));
    g.finish();
}

fn piles(c: &mut Criterion) {
    pile(c, 1);
    pile(c, 10);
}

criterion_group!(benches, pyramid, piles);
criterion_main!(benches);
