//! Runs the torus chain of shared/scenes.md and reports the interlock figures:
//! `cargo run --release -p tumble --example chain`.
use tumble::scenes;
fn main() {
    let scene = scenes::chain();
    let (mut world, ids) = scene.build().expect("chain builds");
    let started = std::time::Instant::now();
    let (mut worst_gap, mut deepest, mut contacts) = (0.0f64, 0.0f64, 0usize);
    for step in 0..scene.steps {
        let r = world.step();
        deepest = deepest.max(r.max_penetration);
        contacts = contacts.max(r.contacts);
        if step % 10 == 0 {
            for w in ids.windows(2) {
                let d = (world.center_of_mass(w[0]).unwrap() - world.center_of_mass(w[1]).unwrap()).length();
                worst_gap = worst_gap.max(d);
            }
        }
    }
    let ms = started.elapsed().as_secs_f64() * 1000.0 / scene.steps as f64;
    let broken = ids
        .windows(2)
        .filter(|w| {
            (world.center_of_mass(w[0]).unwrap() - world.center_of_mass(w[1]).unwrap()).length() > 1.8
        })
        .count();
    println!(
        "chain: {ms:.2} ms/step, largest adjacent centre distance {worst_gap:.3} m (interlock bound 1.8), broken links {broken}, deepest penetration {:.4} m, most contacts {contacts}",
        deepest
    );
}
