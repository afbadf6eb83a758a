//! NaN containment: a body driven to a non-finite or runaway state (a force
//! of 1e308 N, a torque of 1e308 N m, an absurd velocity) is named in the
//! step report, restored to its state before the step and stopped; its
//! neighbours in a resting stack carry on as if it had simply been held
//! still for one step, and nothing else becomes non-finite.

use tumble::collide::shape::Sphere;
use tumble::collide::DVec3;
use tumble::scenes;
use tumble::world::{BodyId, Quarantined, World, RUNAWAY_SPEED};

/// A settled tower of 5 unit cubes on the ground (ids[0] is the ground):
/// it sways by millimetres for the first seconds and rests after 10.
fn settled_tower() -> (World, Vec<BodyId>) {
    let (mut world, ids) = scenes::tower(5).build().unwrap();
    for _ in 0..600 {
        let r = world.step();
        assert!(r.quarantined.is_empty());
    }
    (world, ids)
}

fn assert_all_finite(world: &World) {
    for id in world.body_ids() {
        let s = world.body(id).unwrap().state();
        assert!(s.is_finite(), "{id:?}: {s:?}");
        assert!(world.linear_velocity(id).unwrap().length() < RUNAWAY_SPEED);
    }
}

/// Applies `poke` to the middle cube of a settled tower and checks the
/// containment against the same tower left alone.
fn check_contained(what: &str, poke: impl Fn(&mut World, BodyId)) {
    let (mut world, ids) = settled_tower();
    let mut reference = world.clone();
    let victim = ids[3];
    let before = world.pose(victim).unwrap();
    poke(&mut world, victim);
    let report = world.step();
    reference.step();
    assert_eq!(
        report.quarantined,
        vec![Quarantined { body: victim }],
        "{what}: the report names the body, and only it"
    );
    assert_eq!(
        world.pose(victim).unwrap(),
        before,
        "{what}: restored to its pose before the step"
    );
    assert_eq!(
        world.linear_velocity(victim).unwrap(),
        DVec3::ZERO,
        "{what}: stopped"
    );
    assert_eq!(
        world.angular_velocity(victim).unwrap(),
        DVec3::ZERO,
        "{what}: stopped"
    );
    assert_all_finite(&world);
    // The force was consumed: the stack goes on resting, each body within
    // the solver's slop of where the untouched tower has it. For one step
    // the victim was held immovable, so the load path changed: heights agree
    // within the allowed penetration (0.5 mm per contact layer, five layers)
    // and sideways within a millimetre.
    const HEIGHT_SLOP: f64 = 5.0 * 0.5e-3;
    const SIDEWAYS_SLOP: f64 = 1e-3;
    for _ in 0..120 {
        let r = world.step();
        assert!(r.quarantined.is_empty(), "{what}: quarantined again: {r:?}");
        reference.step();
    }
    assert_all_finite(&world);
    for &id in &ids {
        let d = world.center_of_mass(id).unwrap() - reference.center_of_mass(id).unwrap();
        assert!(
            d.z.abs() < HEIGHT_SLOP && d.truncate().length() < SIDEWAYS_SLOP,
            "{what}: body {id:?} is {d:?} m from where the untouched tower has it"
        );
        assert!(
            world.linear_velocity(id).unwrap().length() < 0.05,
            "{what}: {id:?} moves"
        );
    }
}

#[test]
fn force_of_1e308_on_a_stacked_cube_is_quarantined_not_spread() {
    check_contained("force 1e308 N", |w, id| {
        w.apply_force(id, DVec3::new(1e308, 0.0, 0.0)).unwrap();
    });
}

#[test]
fn torque_of_1e308_on_a_stacked_cube_is_quarantined_not_spread() {
    check_contained("torque 1e308 N m", |w, id| {
        w.apply_torque(id, DVec3::new(0.0, 1e308, 1e308)).unwrap();
    });
}

#[test]
fn absurd_velocity_on_a_stacked_cube_is_quarantined_not_spread() {
    check_contained("velocity 1e200 m/s", |w, id| {
        w.set_velocity(id, DVec3::new(0.0, 1e200, 0.0), DVec3::ZERO)
            .unwrap();
    });
    check_contained("angular velocity 1e200 rad/s", |w, id| {
        w.set_velocity(id, DVec3::ZERO, DVec3::new(1e200, 0.0, 0.0))
            .unwrap();
    });
    check_contained("force at a far point", |w, id| {
        let far = w.center_of_mass(id).unwrap() + DVec3::new(0.0, 1e100, 0.0);
        w.apply_force_at_point(id, DVec3::new(1e200, 0.0, 0.0), far)
            .unwrap();
    });
}

#[test]
fn a_fast_but_physical_body_is_not_quarantined() {
    // A bullet at 1 km/s is physics, not a runaway.
    let mut world = World::new(Default::default()).unwrap();
    let id = world
        .add_body(
            &tumble::world::BodyDesc::dynamic(Sphere::new(0.01).unwrap())
                .with_velocity(DVec3::new(1000.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 1000.0)),
        )
        .unwrap();
    for _ in 0..10 {
        assert!(world.step().quarantined.is_empty());
    }
    let v = world.linear_velocity(id).unwrap();
    assert!((v.x - 1000.0).abs() < 1e-9, "{v:?}");
}

#[test]
fn a_runaway_in_the_pile_stays_alone() {
    let (mut world, ids) = scenes::pile(1).build().unwrap();
    for _ in 0..60 {
        world.step();
    }
    // The last body of the grid (a cube or sphere among the others).
    let victim = *ids.last().unwrap();
    world
        .apply_force(victim, DVec3::new(-1e308, 1e308, 1e308))
        .unwrap();
    let report = world.step();
    assert_eq!(report.quarantined, vec![Quarantined { body: victim }]);
    for _ in 0..120 {
        assert!(world.step().quarantined.is_empty());
    }
    assert_all_finite(&world);
    for &id in &ids[5..] {
        let p = world.center_of_mass(id).unwrap();
        assert!(
            p.x.abs() < 3.01 && p.y.abs() < 3.01 && p.z > 0.0,
            "{id:?} left the container: {p:?}"
        );
    }
}

#[test]
fn a_quarantined_body_keeps_no_impulse_of_its_step() {
    // A cube resting on the ground, hinged to the world at its centre; its
    // motor asked for 1.8e308 rad/s with an unbounded torque (valid
    // numbers, an absurd request) runs it away in one step. The quarantine
    // restores it, and what the step's joint and contacts did goes with
    // it: the joint reports no reaction, and the next steps, the motor
    // taken off, start from nothing (a warm start from the runaway's
    // impulses of 1e308 or NaN ran the cube away again; libFuzzer's
    // `joints` target).
    use tumble::collide::shape::{Cuboid, HalfSpace};
    use tumble::joint::{JointDesc, Motor};
    use tumble::world::{BodyDesc, WorldSettings};
    let mut world = World::new(WorldSettings::default()).unwrap();
    world
        .add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0).unwrap()))
        .unwrap();
    let centre = DVec3::new(0.0, 0.0, 0.5);
    let cube = world
        .add_body(&BodyDesc::dynamic(Cuboid::new(DVec3::splat(0.5)).unwrap()).at(centre))
        .unwrap();
    let motor = Motor::Velocity {
        target: f64::MAX,
        max_force: f64::MAX,
    };
    let hinge = world
        .add_joint(&JointDesc::hinge(cube, None, centre, DVec3::Z).with_motor(motor))
        .unwrap();
    for _ in 0..3 {
        world.step();
    }
    let report = world.step();
    assert_eq!(report.quarantined, vec![Quarantined { body: cube }]);
    let state = world.joint_state(hinge).unwrap();
    assert_eq!(
        (state.force, state.torque),
        (DVec3::ZERO, DVec3::ZERO),
        "{state:?}"
    );
    world.set_joint_motor(hinge, None).unwrap();
    for _ in 0..60 {
        let report = world.step();
        assert!(report.quarantined.is_empty(), "{:?}", report.quarantined);
        let state = world.joint_state(hinge).unwrap();
        assert!(state.force.is_finite() && state.torque.is_finite(), "{state:?}");
    }
    assert_all_finite(&world);
    // At rest on the ground where it was held.
    assert!(world.linear_velocity(cube).unwrap().length() < 1e-3);
    assert!((world.pose(cube).unwrap().position - centre).length() < 1e-3);
}
