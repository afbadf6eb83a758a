//! A square net of ball joints dropped onto a box on the ground
//! (`tumble::scenes::net_drop`), the case that sizes
//! `MAX_OWNED_SUBSTITUTION` (docs/pipeline.md, 2026-12-04, night):
//! `cargo run --release -p tumble --example net_on_box -- [size [steps [threads]]]`
//! (default 30 x 30, 300 steps, one thread). Prints
//! the mean time per step, the largest gain of total energy in one step
//! against the energy the net holds above the ground, the largest joint
//! opening after any step, and the state hash (the same for any thread
//! count).

use std::time::Instant;
use tumble::scenes::net_drop;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: usize| -> Result<usize, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let (n, steps, threads) = (arg(1, 30)?.max(2), arg(2, 300)?.max(1), arg(3, 1)?);
    let mut scene = net_drop(n, true);
    scene.settings.threads = u32::try_from(threads)?;
    let (mut w, _) = scene.build()?;
    let energy = |w: &tumble::world::World| w.kinetic_energy() + w.potential_energy();
    let held = (n * n) as f64 * 0.1 * -scene.settings.gravity.z * 0.8;
    let (mut before, mut gain, mut apart) = (energy(&w), 0.0f64, 0.0f64);
    let clock = Instant::now();
    for _ in 0..steps {
        w.step();
        let e = energy(&w);
        gain = gain.max(e - before);
        before = e;
        apart = apart.max(w.max_joint_error().0);
    }
    let ms = clock.elapsed().as_secs_f64() * 1e3 / steps as f64;
    println!(
        "net {n} x {n}, {steps} steps on {threads} threads: {ms:.2} ms/step; largest gain in a step \
         {gain:.3e} J (the net holds {held:.1} J); joints apart {:.3} mm; state hash {:016x}",
        apart * 1e3,
        w.state_hash()
    );
    Ok(())
}
