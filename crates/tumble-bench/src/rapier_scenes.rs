//! The pyramid, pile and cradle of `shared/scenes.md` built in Rapier (rapier3d, f32,
//! one thread), shared by the `peer-rapier` binary and the in-process
//! criterion bench `dynamics_vs_rapier`.
//!
//! Settings mirror the other peers: dt 1/60 s, gravity -9.81 z, friction 0.5 on
//! every collider (Rapier's default combine rule, Average, yields 0.5),
//! restitution 0, sleeping off (`can_sleep(false)`), Rapier's default solver
//! iterations and substeps.

use crate::scenes::{self, PileShape};
use rapier3d::prelude::*;

/// Friction coefficient of every collider.
pub const FRICTION: f32 = 0.5;

/// A point or vector of the scene data as Rapier's f32 vector.
pub fn v(p: [f64; 3]) -> Vector {
    Vector::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

/// An empty world with the scenes' gravity and time step.
pub fn world() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    w.gravity = Vector::new(0.0, 0.0, -9.81);
    w.integration_parameters.dt = scenes::DT as f32;
    w
}

/// Adds a fixed box with half extents `half` centred at `centre`.
pub fn add_static_box(w: &mut PhysicsWorld, half: [f64; 3], centre: [f64; 3]) {
    w.insert(
        RigidBodyBuilder::fixed().translation(v(centre)),
        ColliderBuilder::cuboid(half[0] as f32, half[1] as f32, half[2] as f32)
            .friction(FRICTION)
            .restitution(0.0),
    );
}

/// Adds a dynamic body of density 1 with `collider`, at rest at `centre`.
pub fn add_dynamic(w: &mut PhysicsWorld, collider: ColliderBuilder, centre: [f64; 3]) -> RigidBodyHandle {
    w.insert(
        RigidBodyBuilder::dynamic()
            .translation(v(centre))
            .can_sleep(false),
        collider.friction(FRICTION).restitution(0.0).density(1.0),
    )
    .0
}

/// The 20-row pyramid: the world, its boxes' handles and start centres (top
/// box last).
pub fn pyramid() -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    pyramid_with_base(20, scenes::PYRAMID_GROUND)
}

/// The 100-row large pyramid (5,050 boxes), as [`pyramid`].
pub fn large_pyramid() -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    pyramid_with_base(100, scenes::LARGE_PYRAMID_GROUND)
}

fn pyramid_with_base(
    base: usize,
    ground: ([f64; 3], [f64; 3]),
) -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    let mut w = world();
    add_static_box(&mut w, ground.0, ground.1);
    let starts = scenes::pyramid_boxes_with_base(base);
    let h = scenes::PYRAMID_HALF as f32;
    let ids = starts
        .iter()
        .map(|&c| add_dynamic(&mut w, ColliderBuilder::cuboid(h, h, h), c))
        .collect();
    (w, ids, starts)
}

/// The pile of `n` bodies (a positive multiple of 100) in its container, or
/// `None` for another `n`.
pub fn pile(n: usize) -> Option<(PhysicsWorld, Vec<RigidBodyHandle>)> {
    let bodies = scenes::pile_bodies(n)?;
    let mut w = world();
    for (half, centre) in scenes::pile_container(n) {
        add_static_box(&mut w, half, centre);
    }
    let s = scenes::PILE_SIZE as f32;
    let ids = bodies
        .iter()
        .map(|&(shape, c)| {
            let col = match shape {
                PileShape::Sphere => ColliderBuilder::ball(s),
                PileShape::Cube => ColliderBuilder::cuboid(s, s, s),
            };
            add_dynamic(&mut w, col, c)
        })
        .collect();
    Some((w, ids))
}

/// Newton's cradle: zero gravity, dt 1/240 s, six spheres of 1 kg with
/// restitution 1 and friction 0 (Rapier's default combine rules, Average,
/// keep both), the striker last.
pub fn cradle() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut w = world();
    w.gravity = Vector::ZERO;
    w.integration_parameters.dt = scenes::CRADLE_DT as f32;
    let ids = scenes::cradle_spheres()
        .into_iter()
        .map(|(c, vel)| {
            w.insert(
                RigidBodyBuilder::dynamic()
                    .translation(v(c))
                    .linvel(v(vel))
                    .can_sleep(false),
                ColliderBuilder::ball(scenes::CRADLE_R as f32)
                    .mass(1.0)
                    .friction(0.0)
                    .restitution(1.0),
            )
            .0
        })
        .collect();
    (w, ids)
}
