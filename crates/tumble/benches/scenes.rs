//! Time per step of the standard scenes (shared/scenes.md) in the world:
//! `cargo bench -p tumble --bench scenes` (pyramid, piles, domino, torus
//! chain, tori pass). Each benchmark first runs the
//! scene for a while so that the measured steps are typical (a settled
//! pyramid, a pile in motion), then times single steps.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tumble::scenes::{self, Scene};

fn bench_scene(c: &mut Criterion, name: &str, scene: Scene, warm_steps: usize) {
    let (mut world, _ids) = scene.build().expect("scene builds");
    for _ in 0..warm_steps {
        world.step();
    }
    let contacts = world.step().contacts;
    c.bench_function(&format!("{name} ({contacts} contacts)"), |b| {
        b.iter(|| black_box(world.step().contacts));
    });
}

fn scenes_bench(c: &mut Criterion) {
    bench_scene(c, "pyramid", scenes::pyramid(), 120);
    bench_scene(c, "pile 1000", scenes::pile(10), 120);
    bench_scene(c, "pile 100", scenes::pile(1), 120);
    bench_scene(c, "domino", scenes::domino(), 60);
    // Concave meshes against concave meshes (issue: mesh dynamics): the
    // torus chain at the standard dt 1/60 (8 sub-steps) and at dt 1/240 (4
    // sub-steps: real time needs a step under 4.17 ms), and the tori pass.
    bench_scene(c, "chain dt 1/60", scenes::chain(), 120);
    let mut fine = scenes::chain();
    fine.settings.dt = 1.0 / 240.0;
    fine.settings.substeps = 4;
    bench_scene(c, "chain dt 1/240", fine, 480);
    bench_scene(c, "tori pass", scenes::tori_pass(), 180);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(3));
    targets = scenes_bench
}
criterion_main!(benches);
