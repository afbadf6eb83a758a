//! The falling pile of `contact_physics::a_falling_pile_of_boxes_and_rocks_never_gains_energy`:
//! 60 bodies (flat boxes, rocks as convex hulls of 24 random points, cubes)
//! in three columns, dropped onto the ground at dt = 1/120 s. One home for
//! the test and the example that measures its energy over many seeds
//! (`examples/warm_start_energy.rs`, docs/pipeline.md, "Warm starts that
//! add energy").

use tumble::world::{BodyDesc, BodyId, World, WorldSettings};
use tumble_collide::shape::{ConvexHull, Cuboid, HalfSpace, Shape};
use tumble_collide::{DQuat, DVec3, Pose};
use tumble_testkit::{RandomSource, SplitMix64};

/// Bodies in the pile (the ground not counted).
pub const FALLING_PILE_BODIES: usize = 60;

/// The most a step may add to the pile's total energy (J), given its total
/// at the start `start`: the integrator's rounding, a millionth of it.
pub fn allowed_gain(start: f64) -> f64 {
    1e-6 * start.abs() + 1e-9
}

/// A standard normal deviate (Box-Muller).
fn normal(rng: &mut SplitMix64) -> f64 {
    let (u, v) = (rng.next_f64().max(1e-300), rng.next_f64());
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// The pile of `seed` with `settings` (whose `dt` is set to 1/120 s): the
/// world and the pile's bodies in insertion order (the ground is the first
/// body of the world, not in the list).
pub fn falling_pile(seed: u64, settings: WorldSettings) -> (World, Vec<BodyId>) {
    let mut rng = SplitMix64(seed);
    let mut world = World::new(WorldSettings {
        dt: 1.0 / 120.0,
        ..settings
    })
    .unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())).with_material(0.6, 0.0))
        .unwrap();
    let corners: Vec<DVec3> = (0..24)
        .map(|_| {
            DVec3::new(
                normal(&mut rng) * 0.07,
                normal(&mut rng) * 0.06,
                normal(&mut rng) * 0.05,
            )
        })
        .collect();
    let shapes = [
        Shape::Cuboid(Cuboid::new(DVec3::new(0.12, 0.08, 0.05)).unwrap()),
        Shape::ConvexHull(ConvexHull::from_points(&corners).unwrap()),
        Shape::Cuboid(Cuboid::new(DVec3::splat(0.06)).unwrap()),
    ];
    let mut ids = Vec::with_capacity(FALLING_PILE_BODIES);
    for i in 0..FALLING_PILE_BODIES {
        let position = DVec3::new(
            0.3 * (i % 3) as f64 - 0.3,
            0.05 * normal(&mut rng),
            0.3 + 0.2 * (i / 3) as f64,
        );
        let angle = rng.next_f64() * std::f64::consts::PI;
        let axis = DVec3::new(normal(&mut rng), normal(&mut rng), normal(&mut rng)).normalize();
        let pose = Pose::new(position, DQuat::from_axis_angle(axis, angle)).unwrap();
        ids.push(
            world
                .add_body(
                    &BodyDesc::dynamic(shapes[i % 3].clone())
                        .with_pose(pose)
                        .with_density(600.0)
                        .with_material(0.6, 0.0),
                )
                .unwrap(),
        );
    }
    (world, ids)
}
