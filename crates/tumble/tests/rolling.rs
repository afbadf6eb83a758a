//! Rolling on curved meshes (issue 15): a ball swinging in a tessellated
//! spherical bowl and a capsule rocking in a tessellated half-pipe, both at
//! dt 1/240 s with friction 0.8, against the period of rolling without
//! slipping and the amplitude a smooth surface keeps; and a ball rolling on
//! flat ground, which must neither sink nor hop.
//!
//! A body of radius r rolling without slipping on the inside of a surface of
//! radius R (sphere or cylinder) moves its centre on a circle of radius
//! R - r with `(1 + k) (R - r) phi'' = -g sin phi`, `k = I / (m r^2)` about
//! its rolling axis: a pendulum of length `(1 + k) (R - r)`, whose period at
//! any amplitude is `4 sqrt(L / g) K(sin^2(phi0 / 2))` (complete elliptic
//! integral of the first kind). Sliding without friction, k = 0.

use tumble::analytic::rolling_period;
use tumble::scenes::{bowl_swing, swing_angle, SwingMeter};
use tumble::world::{BodyDesc, BodyId, World, WorldSettings};
use tumble_collide::mesh::{bowl_mesh, half_pipe_mesh};
use tumble_collide::shape::{Capsule, HalfSpace, MeshShape, Shape, Sphere};
use tumble_collide::{DQuat, DVec3, Pose};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 240.0;

/// The crease angle of the meshes' smooth surfaces: 30 degrees blends the
/// 3.75 degree facets and keeps the rims sharp.
fn smooth(m: MeshShape) -> MeshShape {
    m.with_smooth_surface(30f64.to_radians()).unwrap()
}

/// What a swing measured: the period from the first to the fifth crossing
/// of the bottom, the amplitude at the start and at the fourth turning
/// point after it (two oscillations), the largest rise of the total energy
/// at a turning point over its value at the first (J; the first steps lift
/// the body by the gap the solver keeps from a mesh, half a millimetre),
/// and the largest penetration.
#[derive(Debug)]
struct Swing {
    period: f64,
    start: f64,
    after_two: f64,
    energy_rise: f64,
    deepest: f64,
}

/// Steps `world` until the body has swung through two oscillations
/// (`scenes::SwingMeter`, angle in the plane normal to x for `about_x`,
/// else to y), and reports the swing.
fn swing(world: &mut World, id: BodyId, about_x: bool, start: f64) -> Swing {
    let angle = |w: &World| swing_angle(w.center_of_mass(id).unwrap(), about_x);
    let energy = |w: &World| w.kinetic_energy() + w.potential_energy();
    let mut meter = SwingMeter::new(DT, angle(world));
    let (mut first_turn, mut deepest, mut rise) = (None, 0.0f64, 0.0f64);
    let mut t = 0.0;
    while !meter.done() && t < 30.0 {
        world.step();
        t += DT;
        for c in world.contacts() {
            deepest = deepest.max(-c.contact.distance);
        }
        if meter.observe(angle(world)) {
            let e = energy(world);
            rise = rise.max(e - *first_turn.get_or_insert(e));
        }
    }
    let (Some(period), Some(after_two)) = (meter.period(), meter.amplitude_after_two()) else {
        panic!("did not swing: {meter:?}");
    };
    Swing {
        period,
        start,
        after_two,
        energy_rise: rise,
        deepest,
    }
}

fn world_without_sleep() -> World {
    World::new(WorldSettings {
        sleeping: false,
        dt: DT,
        ..WorldSettings::default()
    })
    .unwrap()
}

/// The swing's figures against the smooth surface's: the period within 1 %,
/// at least 95 % of the amplitude after two oscillations and no more than
/// the start's plus 0.5 % (contact adds no energy), the energy never more than 0.05 % of the swing's
/// above the first turn's, no penetration beyond the allowance.
fn check(s: &Swing, want_period: f64, swing_energy: f64) {
    let kept = s.after_two / s.start;
    assert!(
        (s.period / want_period - 1.0).abs() < 0.01,
        "period {} s, rolling period {want_period} s ({s:?})",
        s.period
    );
    assert!(
        (0.95..=1.005).contains(&kept),
        "kept {kept} of the amplitude ({s:?})"
    );
    assert!(
        s.energy_rise < 0.0005 * swing_energy,
        "energy rose {} J of a {swing_energy} J swing ({s:?})",
        s.energy_rise
    );
    assert!(s.deepest < 0.001, "{s:?}");
}

/// The standard bowl scene (`scenes::bowl_swing`: a 0.5 m bowl of 96 x 48
/// facets with a smooth surface, a 5 cm ball let go 25 degrees up its
/// side), both bodies at friction `mu`.
fn ball_in_bowl(mu: f64) -> (World, BodyId) {
    let mut scene = bowl_swing(true);
    for body in &mut scene.bodies {
        *body = body.clone().with_material(mu, 0.0);
    }
    let (world, ids) = scene.build().unwrap();
    (world, ids[1])
}

#[test]
fn ball_in_a_tessellated_bowl_swings_with_the_rolling_period_and_keeps_its_amplitude() {
    let (path, phi0) = (0.45, 25f64.to_radians());
    let swing_energy = G * path * (1.0 - phi0.cos());
    let (mut world, ball) = ball_in_bowl(0.8);
    let s = swing(&mut world, ball, false, phi0);
    check(&s, rolling_period(path, 0.4, phi0, G), swing_energy);
    // Without friction it slides: a plain pendulum of length R - r.
    let (mut world, ball) = ball_in_bowl(0.0);
    let s = swing(&mut world, ball, false, phi0);
    check(&s, rolling_period(path, 0.0, phi0, G), swing_energy);
    // Normal impulses act through its centre: it does not spin (rolling at
    // the bottom it would turn at 18 rad/s; with contacts kept on material
    // points it spun up to 3.6 rad/s).
    let spin = world.angular_velocity(ball).unwrap().length();
    assert!(spin < 0.01, "a frictionless ball does not spin: {spin} rad/s");
}

#[test]
fn capsule_in_a_tessellated_half_pipe_rolls_with_the_rolling_period_and_keeps_its_amplitude() {
    // A 0.5 m half-pipe of 64 facets across, a capsule (r 5 cm, core 0.2 m)
    // lying along it, let go 25 degrees up its side.
    let (big_r, r, half, phi0) = (0.5, 0.05, 0.1, 25f64.to_radians());
    let mut world = world_without_sleep();
    let pipe = smooth(MeshShape::new(half_pipe_mesh(big_r, 0.05, 1.0, 64).unwrap()).unwrap());
    world
        .add_body(&BodyDesc::fixed(Shape::Mesh(pipe)).with_material(0.8, 0.0))
        .unwrap();
    let path = big_r - r;
    let id = world
        .add_body(
            &BodyDesc::dynamic(Shape::Capsule(Capsule::new(r, half).unwrap()))
                .with_pose(
                    Pose::new(
                        DVec3::new(0.0, path * phi0.sin(), -path * phi0.cos()),
                        DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2),
                    )
                    .unwrap(),
                )
                .with_mass(1.0)
                .with_material(0.8, 0.0),
        )
        .unwrap();
    // k about the core axis: the cylinder's m r^2 / 2 and the two caps'
    // (a ball's) 2 m r^2 / 5, by their volume shares.
    let (cyl, caps) = (2.0 * half * r * r, 4.0 / 3.0 * r * r * r);
    let k = (0.5 * cyl + 0.4 * caps) / (cyl + caps);
    let s = swing(&mut world, id, true, phi0);
    check(
        &s,
        rolling_period(path, k, phi0, G),
        G * path * (1.0 - phi0.cos()),
    );
}

#[test]
fn a_ball_rolling_on_flat_ground_neither_sinks_nor_hops_and_keeps_its_speed() {
    // A ball let go rolling (v = w r) at 3 m/s rolls on at 3 m/s with its
    // centre at its radius: the contact rolls with the ball, so it never
    // sees a gap open under it as its material turns away from the ground.
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())).with_material(0.8, 0.0))
        .unwrap();
    let r = 0.25;
    let ball = world
        .add_body(
            &BodyDesc::dynamic(Shape::Sphere(Sphere::new(r).unwrap()))
                .at(DVec3::new(0.0, 0.0, r))
                .with_mass(20.0)
                .with_material(0.8, 0.0)
                .with_velocity(DVec3::new(0.0, 3.0, 0.0), DVec3::new(-3.0 / r, 0.0, 0.0)),
        )
        .unwrap();
    for _ in 0..120 {
        world.step();
        let (z, v) = (
            world.center_of_mass(ball).unwrap().z,
            world.linear_velocity(ball).unwrap(),
        );
        assert!((z - r).abs() < 1e-6, "centre at {z}");
        assert!(v.z.abs() < 1e-6 && (v.y - 3.0).abs() < 1e-6, "velocity {v:?}");
    }
}

#[test]
fn a_smooth_mesh_survives_a_snapshot_and_continues_bit_for_bit() {
    // The smooth surface is part of the shape: a world restored from a
    // snapshot (through JSON, as a file would) rolls the ball on the same
    // surface, and a second bowl made from the same mesh without a smooth
    // surface stays flat.
    let (mut world, ball) = ball_in_bowl(0.8);
    let flat = MeshShape::new(bowl_mesh(0.5, 0.05, 96, 48).unwrap()).unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::Mesh(flat)).at(DVec3::new(3.0, 0.0, 0.0)))
        .unwrap();
    for _ in 0..60 {
        world.step();
    }
    let json = serde_json::to_string(&world.snapshot()).unwrap();
    let mut restored = World::from_snapshot(&serde_json::from_str(&json).unwrap()).unwrap();
    let smooth_count = |w: &World| {
        w.body_ids()
            .iter()
            .flat_map(|&id| w.colliders(id).unwrap().iter())
            .filter(|c| matches!(&c.shape, Shape::Mesh(m) if m.crease_angle().is_some()))
            .count()
    };
    assert_eq!(smooth_count(&restored), 1);
    for _ in 0..60 {
        world.step();
        restored.step();
    }
    assert_eq!(world.state_hash(), restored.state_hash());
    assert!(world.linear_velocity(ball).unwrap().length() > 0.1);
}

#[test]
fn the_swing_is_the_same_whichever_body_comes_first() {
    // The ball added before the bowl: the pair's bodies change sides, the
    // mesh is A and its contacts' normals point the other way; the swing
    // must not notice.
    let mut scene = bowl_swing(true);
    scene.bodies.swap(0, 1);
    let (mut world, ids) = scene.build().unwrap();
    let (path, phi0) = (0.45, 25f64.to_radians());
    let s = swing(&mut world, ids[0], false, phi0);
    check(
        &s,
        rolling_period(path, 0.4, phi0, G),
        G * path * (1.0 - phi0.cos()),
    );
}
