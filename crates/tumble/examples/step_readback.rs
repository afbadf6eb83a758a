//! The Rust side of `bench/python_overhead.py`: times `step()` plus one
//! readback of every body's pose per step, for the two 1,000-body scenes
//! that the Python side builds through the bindings, and prints one JSON
//! line per scene with the time and a hash of the final poses (so the two
//! sides are checked to have done the same work):
//!
//! ```text
//! cargo run --release -p tumble --example step_readback -- [repeats]
//! ```
//!
//! Scenes (the Python script builds the same ones, body for body):
//! - `grid_fall`: 1,000 boxes (half extent 0.1 m, density 1000) in a
//!   10 x 10 x 10 grid, 0.25 m apart, the lowest layer 0.5 m above a
//!   half-space ground; default settings (dt 1/60, 8 sub-steps); 240 steps.
//!   Contact-heavy: the steps are expensive, the readback relatively cheap.
//! - `free_float`: 1,000 spheres (radius 0.1 m) 0.5 m apart in zero gravity,
//!   each with its own small velocity, no contacts; 240 steps. Cheap steps:
//!   the worst case for the binding overhead.

use std::time::Instant;

use tumble::world::{BodyDesc, BodyId, World, WorldSettings};
use tumble_collide::shape::{Cuboid, HalfSpace, Shape, Sphere};
use tumble_collide::DVec3;

const STEPS: usize = 240;

fn grid(i: usize) -> DVec3 {
    DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64)
}

fn grid_fall() -> (World, Vec<BodyId>) {
    let mut world = World::new(WorldSettings::default()).expect("default settings are valid");
    let mut ids = vec![world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .expect("ground")];
    let cube = Cuboid::new(DVec3::splat(0.1)).expect("valid box");
    for i in 0..1000 {
        let p = grid(i) * 0.25 + DVec3::new(0.0, 0.0, 0.5);
        ids.push(world.add_body(&BodyDesc::dynamic(cube).at(p)).expect("box"));
    }
    (world, ids)
}

fn free_float() -> (World, Vec<BodyId>) {
    let settings = WorldSettings {
        gravity: DVec3::ZERO,
        ..WorldSettings::default()
    };
    let mut world = World::new(settings).expect("valid settings");
    let ball = Sphere::new(0.1).expect("valid sphere");
    let ids = (0..1000)
        .map(|i| {
            let g = grid(i);
            let v = DVec3::new(g.y - 4.5, g.z - 4.5, g.x - 4.5) * 0.01;
            world
                .add_body(&BodyDesc::dynamic(ball).at(g * 0.5).with_velocity(v, DVec3::ZERO))
                .expect("ball")
        })
        .collect();
    (world, ids)
}

/// FNV-1a over the little-endian bytes of the values (same as the Python side).
fn fnv1a(values: &[f64]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in values {
        for b in v.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// Seconds for `STEPS` x (step + pose readback), the seconds of the readbacks
/// alone, and the hash of the last readback.
fn run(build: fn() -> (World, Vec<BodyId>)) -> (f64, f64, u64) {
    let (mut world, ids) = build();
    let mut poses = Vec::new();
    let mut readback = 0.0;
    let start = Instant::now();
    for _ in 0..STEPS {
        world.step();
        // The readback the bindings do for `World.poses()`: a fresh (N, 7) buffer.
        let t = Instant::now();
        poses = Vec::with_capacity(ids.len() * 7);
        for &id in &ids {
            let p = world.pose(id).expect("live body");
            poses.extend_from_slice(&p.position.to_array());
            poses.extend_from_slice(&p.rotation.to_array());
        }
        readback += t.elapsed().as_secs_f64();
    }
    (start.elapsed().as_secs_f64(), readback, fnv1a(&poses))
}

fn main() {
    let repeats: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    for (name, build) in [("grid_fall", grid_fall as fn() -> _), ("free_float", free_float)] {
        let (mut best, mut best_readback) = (f64::INFINITY, f64::INFINITY);
        let mut hash = 0;
        for _ in 0..repeats.max(1) {
            let (t, r, h) = run(build);
            best = best.min(t);
            best_readback = best_readback.min(r);
            hash = h;
        }
        println!(
            "{{\"scene\": \"{name}\", \"steps\": {STEPS}, \"seconds\": {best}, \
             \"readback_seconds\": {best_readback}, \"hash\": \"{hash:016x}\"}}"
        );
    }
}
