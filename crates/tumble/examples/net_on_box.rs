//! A square net of ball joints dropped onto a box on the ground, the case
//! that sizes `MAX_OWNED_SUBSTITUTION` (docs/pipeline.md, 2026-12-04, night):
//! `cargo run --release -p tumble --example net_on_box -- [size [steps [threads]]]`
//! (default 30 x 30, 300 steps, one thread). Spheres of 0.1 kg and radius
//! 0.04 m, 0.1 m apart, dropped from 0.8 m onto a 0.6 m cube; one island of
//! `2 size (size - 1)` ball joints whose loops are closed beside it. Prints
//! the mean time per step, the largest gain of total energy in one step
//! against the energy the net holds above the ground, the largest joint
//! opening after any step, and the state hash (the same for any thread
//! count).

use std::time::Instant;
use tumble::collide::{Cuboid, DVec3, HalfSpace, Sphere};
use tumble::joint::JointDesc;
use tumble::world::{BodyDesc, World, WorldSettings};

const G: f64 = 9.81;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: usize| -> Result<usize, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let (n, steps, threads) = (arg(1, 30)?.max(2), arg(2, 300)?.max(1), arg(3, 1)?);
    let mut w = World::new(WorldSettings {
        gravity: DVec3::new(0.0, 0.0, -G),
        sleeping: false,
        threads: u32::try_from(threads)?,
        ..WorldSettings::default()
    })?;
    w.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0)?))?;
    w.add_body(&BodyDesc::fixed(Cuboid::new(DVec3::splat(0.3))?).at(DVec3::new(0.0, 0.0, 0.3)))?;
    let gap = 0.1;
    let half = (n - 1) as f64 * gap / 2.0;
    let mut ids = Vec::with_capacity(n * n);
    for i in 0..n {
        for k in 0..n {
            let at = DVec3::new(i as f64 * gap - half, k as f64 * gap - half, 0.8);
            ids.push(w.add_body(&BodyDesc::dynamic(Sphere::new(0.04)?).at(at).with_mass(0.1))?);
        }
    }
    for i in 0..n {
        for k in 0..n {
            let a = ids[i * n + k];
            let at = w.center_of_mass(a)?;
            if i + 1 < n {
                w.add_joint(&JointDesc::ball(
                    a,
                    Some(ids[(i + 1) * n + k]),
                    at + DVec3::X * gap / 2.0,
                ))?;
            }
            if k + 1 < n {
                w.add_joint(&JointDesc::ball(
                    a,
                    Some(ids[i * n + k + 1]),
                    at + DVec3::Y * gap / 2.0,
                ))?;
            }
        }
    }
    let energy = |w: &World| w.kinetic_energy() + w.potential_energy();
    let held = (n * n) as f64 * 0.1 * G * 0.8;
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
