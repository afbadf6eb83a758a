//! Contact physics of the world against analytic results and conservation
//! laws (issue: world and contact solver). Release mode: `cargo test --release`.

mod common;

use common::falling_pile::{allowed_gain, falling_pile};
use common::ground_world;
use tumble::scenes;
use tumble::world::{BodyDesc, ContactEvent, World, WorldSettings};
use tumble_collide::shape::{Cuboid, HalfSpace, Shape, Sphere};
use tumble_collide::DVec3;

/// Apex heights (of the lowest point above the ground) after each bounce.
fn bounce_apexes(e: f64, bounces: usize) -> (f64, Vec<f64>) {
    let scene = scenes::ball_drop(1.0, e);
    let (mut world, ids) = scene.build().unwrap();
    let ball = ids[1];
    let r = 0.1;
    let mut apexes = Vec::new();
    let mut last_vz = 0.0;
    for _ in 0..(240 * 6) {
        world.step();
        let vz = world.linear_velocity(ball).unwrap().z;
        if last_vz > 0.0 && vz <= 0.0 {
            apexes.push(world.center_of_mass(ball).unwrap().z - r);
            if apexes.len() == bounces {
                break;
            }
        }
        last_vz = vz;
    }
    (1.0 - r, apexes)
}

#[test]
fn bounce_heights_follow_e_squared() {
    let e = 0.8;
    let (h0, apexes) = bounce_apexes(e, 3);
    assert_eq!(apexes.len(), 3, "three bounces within 6 s");
    for (k, &h) in apexes.iter().enumerate() {
        let expected = h0 * e.powi(2 * (k as i32 + 1));
        assert!(
            (h - expected).abs() < 0.02 * expected,
            "bounce {k}: apex {h:.4} m, e^2k law {expected:.4} m"
        );
    }
}

/// Each bounce is a touch: a Begin event on the step of the impact and an
/// End event when the ball leaves, as many of each as there are impacts
/// (counted independently from the sign changes of the velocity).
#[test]
fn bounces_begin_and_end_contacts() {
    let (mut world, ids) = scenes::ball_drop(1.0, 0.8).build().unwrap();
    let (ground, ball) = (ids[0], ids[1]);
    let (mut begins, mut ends, mut impacts) = (0, 0, 0);
    let mut last_vz = 0.0;
    for _ in 0..240 * 2 {
        let report = world.step();
        let vz = world.linear_velocity(ball).unwrap().z;
        if last_vz < 0.0 && vz > 0.0 {
            impacts += 1;
        }
        last_vz = vz;
        for e in report.events {
            match e {
                ContactEvent::Begin(a, b) => {
                    assert!((a, b) == (ground, ball) || (a, b) == (ball, ground));
                    assert_eq!(begins, ends, "a second Begin before the End");
                    begins += 1;
                }
                ContactEvent::End(..) => {
                    ends += 1;
                    assert_eq!(begins, ends, "an End without a Begin");
                }
            }
        }
    }
    assert!(impacts >= 3, "only {impacts} impacts in 2 s");
    assert_eq!(begins, impacts);
    assert_eq!(ends, impacts);
}

#[test]
fn elastic_ball_keeps_its_energy_over_five_bounces() {
    let (h0, apexes) = bounce_apexes(1.0, 5);
    assert_eq!(apexes.len(), 5);
    for &h in &apexes {
        assert!((h - h0).abs() < 0.01 * h0, "apex {h} vs drop height {h0}");
    }
}

#[test]
fn inelastic_ball_comes_to_rest_without_jitter() {
    let (mut world, ids) = scenes::ball_drop(1.0, 0.0).build().unwrap();
    let ball = ids[1];
    for _ in 0..480 {
        world.step();
    }
    let mut max_speed: f64 = 0.0;
    let mut z = Vec::new();
    for _ in 0..240 {
        world.step();
        max_speed = max_speed.max(world.linear_velocity(ball).unwrap().length());
        z.push(world.center_of_mass(ball).unwrap().z);
    }
    assert!(max_speed < 1e-3, "resting ball moves at {max_speed} m/s");
    let (lo, hi) = z.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
        (l.min(v), h.max(v))
    });
    assert!(hi - lo < 1e-4, "height jitters by {} m", hi - lo);
    let allowed = world.settings().allowed_penetration;
    assert!(
        lo <= 0.1 + 1e-9 && lo >= 0.1 - allowed - 1e-4,
        "rests at z = {lo}: touching, within the allowance"
    );
}

/// Displacement and velocity of the cube after 1 s on the 30 degree slope.
fn incline_after_one_second(mu: f64) -> (DVec3, DVec3) {
    let scene = scenes::incline(mu);
    let (mut world, ids) = scene.build().unwrap();
    let cube = ids[1];
    let start = world.center_of_mass(cube).unwrap();
    for _ in 0..scene.steps {
        world.step();
    }
    (
        world.center_of_mass(cube).unwrap() - start,
        world.linear_velocity(cube).unwrap(),
    )
}

#[test]
fn incline_sticks_with_high_friction() {
    let (d, v) = incline_after_one_second(0.7);
    assert!(d.length() < 1e-3, "moved {d:?}");
    assert!(v.length() < 1e-4, "still moving at {v:?}");
}

#[test]
fn incline_slides_with_coulomb_acceleration() {
    let theta = 30f64.to_radians();
    let g = 9.81;
    let a = g * (theta.sin() - 0.2 * theta.cos());
    let (d, v) = incline_after_one_second(0.2);
    // The slope normal is Ry(theta) z = (sin, 0, cos); gravity's tangential
    // part points downhill along (cos theta, 0, -sin theta).
    let downhill = DVec3::new(theta.cos(), 0.0, -theta.sin());
    let speed = v.dot(downhill);
    assert!(
        (speed - a).abs() < 0.02 * a,
        "speed after 1 s {speed}, expected {a}"
    );
    assert!((d.dot(downhill) - 0.5 * a).abs() < 0.02 * 0.5 * a);
}

#[test]
fn cradle_transfers_momentum_to_the_last_ball() {
    let scene = scenes::cradle();
    let (mut world, ids) = scene.build().unwrap();
    let momentum = |w: &World| {
        ids.iter()
            .map(|&id| w.linear_velocity(id).unwrap())
            .sum::<DVec3>()
    };
    let p0 = momentum(&world);
    let e0 = world.kinetic_energy();
    for _ in 0..scene.steps {
        world.step();
    }
    let last = world.linear_velocity(ids[4]).unwrap();
    assert!((last.x - 1.0).abs() < 0.05, "last ball leaves at {last:?}");
    for &id in &ids[..4] {
        assert!(world.linear_velocity(id).unwrap().length() < 0.05);
    }
    assert!(
        world.linear_velocity(ids[5]).unwrap().length() < 0.05,
        "striker stops"
    );
    assert!((momentum(&world) - p0).length() < 1e-9, "momentum conserved");
    assert!(
        (world.kinetic_energy() - e0).abs() < 0.01 * e0,
        "energy conserved"
    );
}

#[test]
fn pyramid_of_twenty_rows_stands() {
    let scene = scenes::pyramid();
    let (mut world, ids) = scene.build().unwrap();
    let starts: Vec<DVec3> = ids.iter().map(|&id| world.pose(id).unwrap().position).collect();
    let mut deepest: f64 = 0.0;
    for _ in 0..scene.steps {
        deepest = deepest.max(world.step().max_penetration);
    }
    let top = (world.pose(*ids.last().unwrap()).unwrap().position - starts[ids.len() - 1]).length();
    assert!(top < 0.01, "top box moved {top} m in 10 s");
    let worst = ids
        .iter()
        .zip(&starts)
        .map(|(&id, s)| (world.pose(id).unwrap().position - *s).length())
        .fold(0.0, f64::max);
    assert!(worst < 0.02, "a box moved {worst} m");
    assert!(deepest < world.settings().contact_margin, "penetration {deepest}");
}

#[test]
fn tower_of_ten_stands() {
    let scene = scenes::tower(10);
    let (mut world, ids) = scene.build().unwrap();
    let top = *ids.last().unwrap();
    let start = world.center_of_mass(top).unwrap();
    let mut deepest: f64 = 0.0;
    for _ in 0..600 {
        let r = world.step();
        deepest = deepest.max(r.max_penetration);
    }
    let drift = (world.center_of_mass(top).unwrap() - start).length();
    assert!(drift < 0.01, "top box moved {drift} m");
    assert!(deepest < world.settings().contact_margin, "penetration {deepest}");
}

/// A column of 50 unit cubes stands straight for 10 s, at the default 8
/// sub-steps x 2 iterations and at 4 x 4: the push-out removes overlap
/// without turning the boxes (pushed one point of a face after another, it
/// turned each box a little at every sub-step, and columns of 40 and more
/// leaned over and fell; at 4 x 4 one of 100 was thrown 120 m up). The top
/// box stays above where it began within a millimetre, no box turns by a
/// milliradian, and the column sinks by at most the allowed penetration and
/// half a millimetre per interface.
#[test]
fn a_column_of_fifty_boxes_stands_straight() {
    for (substeps, iterations) in [(8, 2), (4, 4)] {
        let mut scene = scenes::tower(50);
        scene.settings.substeps = substeps;
        scene.settings.iterations = iterations;
        let (mut world, ids) = scene.build().unwrap();
        let top = *ids.last().unwrap();
        let start = world.center_of_mass(top).unwrap();
        for _ in 0..600 {
            world.step();
        }
        let at = world.center_of_mass(top).unwrap();
        let across = (at - start).truncate().length();
        let sink = start.z - at.z;
        let allowed = 50.0 * (world.settings().allowed_penetration + 0.0005);
        assert!(
            across < 1e-3,
            "{substeps} x {iterations}: the top box moved {across} m across"
        );
        assert!(
            (0.0..allowed).contains(&sink),
            "{substeps} x {iterations}: the top box sank {sink} m (at most {allowed})"
        );
        for &id in &ids[1..] {
            let turned = world.orientation(id).unwrap().to_scaled_axis().length();
            assert!(
                turned < 1e-3,
                "{substeps} x {iterations}: a box turned {turned} rad"
            );
        }
    }
}

#[test]
fn no_tunnelling_of_a_fast_small_sphere() {
    // Zero gravity and no sleeping, spelt out here as in mesh_dynamics.rs
    // (interpenetrating tori): each test states the settings it relies on.
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::Cuboid(
            Cuboid::new(DVec3::new(1.0, 1.0, 0.005)).unwrap(),
        )))
        .unwrap();
    let ball = world
        .add_body(
            // 1 cm across at 100 m/s: 1.7 m per step against a 1 cm plate.
            &BodyDesc::dynamic(Shape::Sphere(Sphere::new(0.005).unwrap()))
                .at(DVec3::new(0.0, 0.0, 0.5))
                .with_velocity(DVec3::new(0.0, 0.0, -100.0), DVec3::ZERO),
        )
        .unwrap();
    for _ in 0..60 {
        world.step();
        assert!(
            world.center_of_mass(ball).unwrap().z > 0.0,
            "tunnelled through the plate"
        );
    }
}

#[test]
fn falling_column_lands_without_sinking_into_itself() {
    // 30 bodies (spheres and cubes, 0.5 m across) 0.1 m apart fall together
    // from up to 18 m. Each pair closes its gap only when the body below
    // lands, then at up to 19 m/s: 0.31 m in one step of 1/60 s. Its
    // margin must have seen that coming (the neighbour's closing speed),
    // or the upper body sinks into the lower one by most of a step's fall.
    // The no-sleep world of mesh_dynamics.rs `torus_dropped_over_a_peg_settles_around_it`,
    // but on a box plate: each test file builds the ground its case needs.
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    world
        .add_body(
            &BodyDesc::fixed(Shape::Cuboid(Cuboid::new(DVec3::new(3.0, 3.0, 0.5)).unwrap()))
                .at(DVec3::new(0.0, 0.0, -0.5)),
        )
        .unwrap();
    let layers = 30;
    let mut ids = Vec::new();
    for k in 0..layers {
        let shape = if k % 2 == 0 {
            Shape::Sphere(Sphere::new(0.25).unwrap())
        } else {
            Shape::Cuboid(Cuboid::new(DVec3::splat(0.25)).unwrap())
        };
        let desc = BodyDesc::dynamic(shape)
            .at(DVec3::new(0.0, 0.0, 1.0 + 0.6 * k as f64))
            .with_density(1.0);
        ids.push(world.add_body(&desc).unwrap());
    }
    let mut deepest: f64 = 0.0;
    for _ in 0..600 {
        deepest = deepest.max(world.step().max_penetration);
    }
    assert!(deepest < 0.05, "a body sank {deepest} m into its neighbour");
    // At rest the column is 30 bodies of 0.5 m, stacked straight.
    let top = world.center_of_mass(*ids.last().unwrap()).unwrap();
    let rest = 0.25 + 0.5 * (layers - 1) as f64;
    assert!(
        (top.z - rest).abs() < 0.05 && top.truncate().length() < 0.01,
        "top at {top}, rest height {rest}"
    );
}

/// Two boxes colliding off-centre with restitution `e`: returns the
/// kinetic energy before and after (momentum and energy checked per step).
fn off_centre_collision(e: f64) -> (f64, f64) {
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    let cube = || Shape::Cuboid(Cuboid::new(DVec3::new(0.3, 0.2, 0.1)).unwrap());
    let a = world
        .add_body(
            &BodyDesc::dynamic(cube())
                .at(DVec3::new(-1.0, 0.15, 0.05))
                .with_mass(2.0)
                .with_material(0.3, e)
                .with_velocity(DVec3::new(3.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 1.0)),
        )
        .unwrap();
    let b = world
        .add_body(
            &BodyDesc::dynamic(cube())
                .at(DVec3::new(1.0, 0.0, 0.0))
                .with_mass(1.0)
                .with_material(0.3, e),
        )
        .unwrap();
    let momentum = |w: &World| {
        let (ma, mb) = (w.body(a).unwrap().mass(), w.body(b).unwrap().mass());
        let p = w.linear_velocity(a).unwrap() * ma + w.linear_velocity(b).unwrap() * mb;
        let l = w
            .center_of_mass(a)
            .unwrap()
            .cross(w.linear_velocity(a).unwrap() * ma)
            + w.body(a).unwrap().angular_momentum()
            + w.center_of_mass(b)
                .unwrap()
                .cross(w.linear_velocity(b).unwrap() * mb)
            + w.body(b).unwrap().angular_momentum();
        (p, l)
    };
    let (p0, l0) = momentum(&world);
    let e0 = world.kinetic_energy();
    let mut e_prev = e0;
    let mut l_prev = l0;
    let mut touched = false;
    let allowed = world.settings().allowed_penetration;
    for _ in 0..120 {
        let r = world.step();
        touched |= r.contacts > 0;
        let (p, l) = momentum(&world);
        assert!((p - p0).length() < 1e-9 * p0.length().max(1.0), "linear momentum");
        // Every impulse acts on both bodies along one line, so impulses keep
        // angular momentum to round-off. Only the position correction (when
        // an overlap beyond the allowance is pushed out, moving the bodies
        // without changing their momenta) shifts it, by the correction times
        // the relative velocity: steps that needed none must conserve it.
        if r.max_penetration <= allowed {
            assert!(
                (l - l_prev).length() < 1e-12 * l0.length().max(1.0),
                "angular momentum {l:?} vs {l_prev:?}"
            );
        }
        assert!(
            (l - l0).length() < 1e-3 * l0.length(),
            "angular momentum drifted: {l:?} vs {l0:?}"
        );
        l_prev = l;
        // Impulses never add energy; the free tumbling between them is
        // integrated by a symplectic splitting whose energy error is bounded
        // (O(h^2), no drift): allow that, far below what a bad impulse adds.
        let e = world.kinetic_energy();
        assert!(e <= e_prev * (1.0 + 1e-6), "energy grew {e_prev} -> {e}");
        assert!(e <= e0 * (1.0 + 1e-6), "energy above the initial {e0}: {e}");
        e_prev = e;
    }
    assert!(touched, "the boxes collided");
    (e0, e_prev)
}

/// A pile of 60 boxes and rocks (convex hulls) dropped in three columns onto
/// the ground, over six seeds: contact only takes energy out, so the
/// total (kinetic plus potential) never rises from one step to the next by
/// more than the integrator's rounding (a millionth). The Rust twin of
/// `examples/python/falling_pile.py`'s check, which caught an exact solve
/// of the face blocks adding 11 J in one step (docs/pipeline.md, "Measured
/// and not kept"); that solve gained in 2 of these 6 seeds.
///
/// Known limit (2026-12-06): the claim holds for these six seeds, not for
/// every seed. Over seeds 1-120, 20 gain energy in some step: 26 steps, up
/// to 18.6 J at an impact (seed 84, step 62), 2-40 mJ later on. In each of
/// the 26, the same step taken from the same state without the warm start
/// loses energy, and 24 of them still gain with the push-out off: the
/// gains come from the warm start, which re-applies an impact's stopping
/// impulses that two velocity passes a sub-step cannot take back through a
/// stack. A change that only moves the trajectories can fail this test on
/// a seed of its own. docs/pipeline.md, "Warm starts that add energy", has the
/// cases and the remedies measured (none kept: each cost a stack or pile
/// figure); `examples/warm_start_energy.rs` runs the scene
/// (`common/falling_pile.rs`) over any range of seeds and retakes each
/// gaining step without the warm start and without the push-out. After a
/// fix this test should run many seeds.
#[test]
fn a_falling_pile_of_boxes_and_rocks_never_gains_energy() {
    for seed in 1..=6 {
        let (mut world, _) = falling_pile(seed, WorldSettings::default());
        let total = |w: &World| w.kinetic_energy() + w.potential_energy();
        let start = total(&world);
        let mut last = start;
        for step in 1..=360 {
            world.step();
            let now = total(&world);
            assert!(
                now - last <= allowed_gain(start),
                "seed {seed}, step {step}: the pile gained {} J",
                now - last
            );
            last = now;
        }
    }
}

#[test]
fn off_centre_collisions_conserve_momentum_and_never_gain_energy() {
    // e = 0 and e = 0.5 dissipate; e = 1 keeps the energy (the boxes separate
    // after one impact, up to the bounded integration error).
    let (e0, e1) = off_centre_collision(0.0);
    assert!(e1 < 0.9 * e0, "e = 0 dissipated: {e0} -> {e1}");
    let (e0, e1) = off_centre_collision(0.5);
    assert!(e1 < 0.95 * e0, "e = 0.5 dissipated: {e0} -> {e1}");
    let (e0, e1) = off_centre_collision(1.0);
    assert!(e1 > 0.99 * e0, "e = 1 kept its energy: {e0} -> {e1}");
}

#[test]
fn sleeping_stack_stays_bit_still_and_wakes_when_hit() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .unwrap();
    let cube = || Shape::Cuboid(Cuboid::new(DVec3::splat(0.5)).unwrap());
    let boxes: Vec<_> = (0..3)
        .map(|i| {
            world
                .add_body(&BodyDesc::dynamic(cube()).at(DVec3::new(0.0, 0.0, 0.5 + i as f64)))
                .unwrap()
        })
        .collect();
    for _ in 0..240 {
        world.step();
    }
    assert!(
        boxes.iter().all(|&b| world.is_sleeping(b).unwrap()),
        "stack fell asleep"
    );
    let poses: Vec<_> = boxes.iter().map(|&b| world.pose(b).unwrap()).collect();
    for _ in 0..60 {
        world.step();
    }
    for (&b, p) in boxes.iter().zip(&poses) {
        assert_eq!(world.pose(b).unwrap(), *p, "sleeping body moved");
    }
    let ball = world
        .add_body(
            &BodyDesc::dynamic(Shape::Sphere(Sphere::new(0.2).unwrap()))
                .at(DVec3::new(-3.0, 0.0, 2.5))
                .with_velocity(DVec3::new(10.0, 0.0, 0.0), DVec3::ZERO),
        )
        .unwrap();
    for _ in 0..30 {
        world.step();
    }
    assert!(!world.is_sleeping(boxes[2]).unwrap(), "top box woke");
    let _ = ball;
}

#[test]
fn bad_descriptions_leave_the_world_unchanged() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let sphere = || Shape::Sphere(Sphere::new(0.5).unwrap());
    let good = world.add_body(&BodyDesc::dynamic(sphere())).unwrap();
    let bad = [
        BodyDesc::dynamic(sphere()).with_mass(-1.0),
        BodyDesc::dynamic(sphere()).with_density(f64::NAN),
        BodyDesc::dynamic(sphere()).at(DVec3::new(f64::INFINITY, 0.0, 0.0)),
        BodyDesc::dynamic(sphere()).with_velocity(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ZERO),
        BodyDesc::dynamic(sphere()).with_material(-0.5, 0.0),
        BodyDesc::dynamic(sphere()).with_material(0.5, 1.5),
        BodyDesc::dynamic(Shape::HalfSpace(HalfSpace::ground())),
        BodyDesc {
            shapes: vec![],
            ..BodyDesc::default()
        },
    ];
    for desc in &bad {
        assert!(world.add_body(desc).is_err(), "accepted {desc:?}");
        assert_eq!(world.body_count(), 1);
    }
    world.remove_body(good).unwrap();
    assert!(world.remove_body(good).is_err(), "removing twice");
    assert!(world.pose(good).is_err(), "stale handle");
    assert!(World::new(WorldSettings {
        dt: -1.0,
        ..WorldSettings::default()
    })
    .is_err());
}

#[test]
fn non_finite_state_is_quarantined_not_spread() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let sphere = || Shape::Sphere(Sphere::new(0.5).unwrap());
    // A light body and a finite but absurd force: F/m overflows to infinity.
    let a = world
        .add_body(
            &BodyDesc::dynamic(sphere())
                .at(DVec3::new(0.0, 0.0, 5.0))
                .with_mass(1e-6),
        )
        .unwrap();
    let b = world
        .add_body(&BodyDesc::dynamic(sphere()).at(DVec3::new(0.9, 0.0, 5.0)))
        .unwrap();
    world.apply_force(a, DVec3::new(1e308, 0.0, 0.0)).unwrap();
    let before = world.pose(a).unwrap();
    let report = world.step();
    assert_eq!(report.quarantined.len(), 1, "{report:?}");
    assert_eq!(report.quarantined[0].body, a);
    assert_eq!(
        world.pose(a).unwrap(),
        before,
        "restored to its state before the step"
    );
    assert_eq!(world.linear_velocity(a).unwrap(), DVec3::ZERO, "and stopped");
    for _ in 0..10 {
        world.step();
    }
    for id in [a, b] {
        assert!(world.center_of_mass(id).unwrap().is_finite());
        assert!(world.linear_velocity(id).unwrap().is_finite());
    }
}

#[test]
fn same_scene_gives_identical_bits() {
    let run = || {
        let (mut world, ids) = scenes::pile(1).build().unwrap();
        for _ in 0..120 {
            world.step();
        }
        ids.iter()
            .flat_map(|&id| {
                let p = world.pose(id).unwrap();
                [
                    p.position.x,
                    p.position.y,
                    p.position.z,
                    p.rotation.x,
                    p.rotation.y,
                    p.rotation.z,
                    p.rotation.w,
                ]
            })
            .map(f64::to_bits)
            .collect::<Vec<u64>>()
    };
    assert_eq!(run(), run());
}

#[test]
fn exact_and_iterative_solvers_agree_on_a_resting_stack() {
    use tumble::world::SolverKind;
    let run = |solver: SolverKind| {
        let mut scene = scenes::tower(3);
        scene.settings.solver = solver;
        let (mut world, ids) = scene.build().unwrap();
        for _ in 0..120 {
            let report = world.step();
            assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        }
        // Impulse carried by each contact layer over one step.
        let mut per_layer = [0.0f64; 3];
        for c in world.contacts() {
            let layer = c.body_a.index.min(c.body_b.index) as usize;
            per_layer[layer] += c.normal_impulse;
        }
        let poses: Vec<_> = ids.iter().map(|&id| world.pose(id).unwrap().position).collect();
        (per_layer, poses)
    };
    let (exact, exact_poses) = run(SolverKind::Lemke);
    let (iterative, iterative_poses) = run(SolverKind::Pgs);
    let dt = WorldSettings::default().dt;
    for layer in 0..3 {
        // Layer k carries the 3 - k boxes above it (1 kg each): m g dt.
        let weight = (3 - layer) as f64 * 9.81 * dt;
        assert!(
            (exact[layer] - weight).abs() < 0.01 * weight,
            "exact layer {layer}: {} vs {weight}",
            exact[layer]
        );
        assert!(
            (iterative[layer] - exact[layer]).abs() < 0.02 * weight,
            "layer {layer}: PGS {} vs Lemke {}",
            iterative[layer],
            exact[layer]
        );
    }
    for (a, b) in exact_poses.iter().zip(&iterative_poses) {
        assert!((*a - *b).length() < 1e-3, "poses differ: {a:?} vs {b:?}");
    }
}

/// Overlap is pushed out in proportion to its depth: a column of twelve
/// boxes spawned 2 cm into each other (and the lowest 2 cm into the ground)
/// is within 5 mm everywhere after 40 steps (2/3 s) and within the
/// allowance plus 0.5 mm after 4 s, still standing. With one
/// push-out pass per sub-step whatever the depth, each pass carries a
/// correction one contact further up the column while the column's weight
/// presses it together: the overlap first grew to 27 mm and was still
/// 13 mm after 40 steps. A step whose deepest overlap is a multiple of
/// 5 mm now gets as many more passes (solve stage, `deep_load`).
#[test]
fn a_deeply_overlapping_column_is_pushed_apart_in_proportion_to_its_depth() {
    let mut world = ground_world();
    let cube = || Shape::Cuboid(Cuboid::new(DVec3::splat(0.25)).unwrap());
    let overlap = 0.02;
    let boxes: Vec<_> = (0..12)
        .map(|i| {
            let z = 0.25 - overlap + i as f64 * (0.5 - overlap);
            world
                .add_body(&BodyDesc::dynamic(cube()).at(DVec3::new(0.0, 0.0, z)))
                .unwrap()
        })
        .collect();
    let allowed = world.settings().allowed_penetration;
    // The report's deepest is that of the step's start: the state the
    // steps before left.
    let mut deepest = Vec::new();
    for _ in 0..241 {
        deepest.push(world.step().max_penetration);
    }
    assert!(
        deepest[40] <= 0.005,
        "deepest overlap after 40 steps: {} m",
        deepest[40]
    );
    assert!(
        deepest[240] <= allowed + 5e-4,
        "deepest overlap after 4 s: {} m",
        deepest[240]
    );
    for (i, &b) in boxes.iter().enumerate() {
        let x = world.center_of_mass(b).unwrap();
        // Pushed apart at four corners each, the boxes slide a little (1-2
        // cm, with one pass or with more): the column stands.
        assert!(x.truncate().length() < 0.025, "box {i} left the column: {x:?}");
        // The column sways a little after the push (a few cm/s at the top,
        // with one pass or with more); it does not fall.
        let v = world.linear_velocity(b).unwrap();
        assert!(v.length() < 0.05, "box {i} moves at {v:?}");
    }
}

/// Layers of boxes and spheres landing on each other sink in no deeper than
/// 6 cm: a shaft of 3 x 3 bodies (spheres and cubes of 0.25 m alternating,
/// density 1, as in the standard piles) and 100 layers 0.6 m apart falls
/// onto the floor, each layer landing on the ones below at up to 9 m/s
/// while its boxes tumble. Two causes were found and fixed: a box touching
/// another at an edge kept one contact point for the step while its
/// turning brought a corner 10 cm into the other (narrow phase: corners
/// within the margin are held too, `hold_near_vertices`; spheres alone
/// sank 1 cm); and the landing load reached the layers below one contact
/// per pass (solve stage, `deep_load`: more iterations where it is deep).
/// Before both, the deepest overlap was 11 cm; after, 4 cm.
#[test]
fn layers_of_boxes_and_spheres_landing_on_each_other_sink_in_no_deeper_than_6_cm() {
    let mut world = ground_world();
    let (n, layers) = (3, 100);
    let half = 0.3 * n as f64;
    let wall_half_height = 0.3 * layers as f64 + 1.0;
    let wall = |half: DVec3, x: f64, y: f64| {
        BodyDesc::fixed(Shape::Cuboid(Cuboid::new(half).unwrap())).at(DVec3::new(x, y, wall_half_height))
    };
    for sign in [-1.0, 1.0] {
        let across = DVec3::new(0.25, half + 0.5, wall_half_height);
        let along = DVec3::new(half, 0.25, wall_half_height);
        world.add_body(&wall(across, sign * (half + 0.25), 0.0)).unwrap();
        world.add_body(&wall(along, 0.0, sign * (half + 0.25))).unwrap();
    }
    for k in 0..layers {
        for j in 0..n {
            for i in 0..n {
                let shape = if (i + j + k) % 2 == 0 {
                    Shape::Sphere(Sphere::new(0.25).unwrap())
                } else {
                    Shape::Cuboid(Cuboid::new(DVec3::splat(0.25)).unwrap())
                };
                let at = DVec3::new(
                    -half + 0.3 + 0.6 * i as f64,
                    -half + 0.3 + 0.6 * j as f64,
                    0.3 + 0.6 * k as f64,
                );
                world
                    .add_body(&BodyDesc::dynamic(shape).at(at).with_density(1.0))
                    .unwrap();
            }
        }
    }
    let start_energy = world.potential_energy();
    let mut deepest = 0.0f64;
    for _ in 0..240 {
        deepest = deepest.max(world.step().max_penetration);
    }
    assert!(
        deepest <= 0.06,
        "deepest overlap while the layers landed: {deepest} m"
    );
    // Landed: nothing left the shaft, and of the energy the fall released
    // (kJ) under a thousandth still moves (a sphere on top may roll on).
    for id in world.body_ids().into_iter().skip(5) {
        let x = world.center_of_mass(id).unwrap();
        assert!(
            x.x.abs() < half && x.y.abs() < half && x.z > 0.0,
            "body left the shaft: {x:?}"
        );
    }
    let released = start_energy - world.potential_energy();
    assert!(released > 1e3, "the fall released {released} J");
    assert!(
        world.kinetic_energy() < 1e-3 * released,
        "still moving after 4 s: {} J of {released} J",
        world.kinetic_energy()
    );
}

#[test]
fn bodies_of_one_non_colliding_group_pass_through_each_other_and_touch_the_rest() {
    // A ball dropped onto a box: of one group, it falls through the box
    // onto the ground (its free fall, g t^2 / 2, unchanged by the box);
    // of another group, or none, it comes to rest on the box.
    let rest_height = |ball_group: u32| {
        let mut world = ground_world();
        let slab = BodyDesc {
            non_colliding_group: 3,
            ..BodyDesc::fixed(Cuboid::new(DVec3::new(1.0, 1.0, 0.1)).unwrap()).at(DVec3::new(0.0, 0.0, 1.0))
        };
        world.add_body(&slab).unwrap();
        let ball = world
            .add_body(&BodyDesc {
                non_colliding_group: ball_group,
                ..BodyDesc::dynamic(Sphere::new(0.1).unwrap()).at(DVec3::new(0.0, 0.0, 1.5))
            })
            .unwrap();
        for _ in 0..240 {
            world.step();
        }
        world.center_of_mass(ball).unwrap().z
    };
    assert!(
        (rest_height(3) - 0.1).abs() < 2e-3,
        "through the slab onto the ground"
    );
    for group in [0, 4] {
        let z = rest_height(group);
        assert!((z - 1.2).abs() < 2e-3, "group {group}: on the slab, at {z} m");
    }
}

#[test]
fn an_excluded_pair_passes_through_itself_and_touches_the_rest() {
    use tumble::world::WorldError;
    // Two balls dropped onto a slab, their pair excluded: the upper one
    // falls through the lower one (its free fall unchanged by it) and both
    // come to rest on the slab, which they still touch.
    let mut world = ground_world();
    let slab = world
        .add_body(
            &BodyDesc::fixed(Cuboid::new(DVec3::new(1.0, 1.0, 0.1)).unwrap()).at(DVec3::new(0.0, 0.0, 1.0)),
        )
        .unwrap();
    let ball = |z: f64| BodyDesc::dynamic(Sphere::new(0.1).unwrap()).at(DVec3::new(0.0, 0.0, z));
    let lower = world.add_body(&ball(1.2)).unwrap();
    let upper = world.add_body(&ball(1.6)).unwrap();
    assert!(world.contacts_allowed(lower, upper).unwrap());
    world.set_contacts_between(upper, lower, false).unwrap();
    assert!(!world.contacts_allowed(lower, upper).unwrap());
    assert_eq!(world.excluded_contact_pairs(), &[(lower, upper)]);
    assert!(world.contacts_allowed(lower, slab).unwrap());
    // A refused call leaves the world as it was.
    let before = world.snapshot();
    assert!(matches!(
        world.set_contacts_between(lower, lower, false),
        Err(WorldError::BadValue { field: "body_b", .. })
    ));
    assert!(world.snapshot() == before, "a refused call changed the world");
    // Until the upper ball reaches the slab (0.4 m of free fall, 17 steps), it falls
    // as it falls with no lower ball at all, to the bit.
    let mut alone = ground_world();
    alone
        .add_body(
            &BodyDesc::fixed(Cuboid::new(DVec3::new(1.0, 1.0, 0.1)).unwrap()).at(DVec3::new(0.0, 0.0, 1.0)),
        )
        .unwrap();
    let single = alone.add_body(&ball(1.6)).unwrap();
    for _ in 0..14 {
        world.step();
        alone.step();
        assert!(world.contacts().iter().all(|c| {
            let pair = [c.body_a, c.body_b];
            !(pair.contains(&lower) && pair.contains(&upper))
        }));
        assert_eq!(
            world.center_of_mass(upper).unwrap(),
            alone.center_of_mass(single).unwrap()
        );
    }
    // (Resting on the lower ball, its centre would be at 1.4 m.)
    let z = world.center_of_mass(upper).unwrap().z;
    assert!(z < 1.36, "at {z} m: not through the lower ball");
    for _ in 0..240 {
        world.step();
    }
    for id in [lower, upper] {
        let z = world.center_of_mass(id).unwrap().z;
        assert!((z - 1.2).abs() < 2e-3, "{id:?} at {z} m, not on the slab");
    }
    // Stale handles are refused, the world unchanged; removing a body
    // drops its exclusions.
    world.remove_body(upper).unwrap();
    assert!(world.excluded_contact_pairs().is_empty());
    let after_removal = world.snapshot();
    assert!(matches!(
        world.set_contacts_between(lower, upper, false),
        Err(WorldError::StaleBody(_))
    ));
    assert!(matches!(
        world.contacts_allowed(upper, lower),
        Err(WorldError::StaleBody(_))
    ));
    assert!(
        world.snapshot() == after_removal,
        "a refused call changed the world"
    );
    // A snapshot keeps the exclusion.
    world.restore(&before).unwrap();
    assert_eq!(world.excluded_contact_pairs(), &[(lower, upper)]);
}

#[test]
fn a_body_without_shapes_falls_freely_touches_nothing_and_carries_a_joint() {
    use tumble::collide::mass::MassProperties;
    use tumble::collide::DMat3;
    use tumble::joint::{JointDesc, JointKind};
    use tumble::world::MassDesc;
    // A point-like mass given by its mass properties alone (a robot link
    // with an <inertial> and no geometry): it falls through the ground
    // as a free particle, g t^2 / 2, since it has nothing to touch.
    let mut world = ground_world();
    let inertial = MassProperties::new(2.0, DVec3::ZERO, DMat3::from_diagonal(DVec3::splat(0.01))).unwrap();
    let ghost = BodyDesc {
        shapes: Vec::new(),
        mass: MassDesc::Inertial(inertial),
        ..BodyDesc::default()
    };
    let falling = world
        .add_body(&ghost.clone().at(DVec3::new(0.0, 0.0, 0.5)))
        .unwrap();
    // The same hanging from a static box by a 1 m hinge, released
    // horizontal: it swings down (energy conserved to within the
    // integrator's error), held at 1 m from the pivot.
    let pivot = DVec3::new(3.0, 0.0, 2.0);
    let post = world
        .add_body(&BodyDesc::fixed(Cuboid::new(DVec3::splat(0.1)).unwrap()).at(pivot))
        .unwrap();
    let bob = world.add_body(&ghost.at(pivot + DVec3::X)).unwrap();
    let hinge = world
        .add_joint(&JointDesc::new(
            JointKind::Hinge,
            bob,
            Some(post),
            pivot,
            DVec3::Y,
        ))
        .unwrap();
    let steps = 60;
    let mut lowest = f64::INFINITY;
    for _ in 0..steps {
        world.step();
        lowest = lowest.min(world.center_of_mass(bob).unwrap().z);
    }
    // Semi-implicit Euler over N sub-steps of h: z0 - g h^2 N (N + 1) / 2.
    let n = (steps * world.settings().substeps as usize) as f64;
    let h = world.settings().dt / world.settings().substeps as f64;
    let z = world.center_of_mass(falling).unwrap().z;
    let expected = 0.5 - 9.81 * h * h * n * (n + 1.0) / 2.0;
    assert!(
        (z - expected).abs() < 1e-9,
        "free fall through the ground: {z} against {expected}"
    );
    assert!(world.contacts().is_empty());
    let reach = (world.center_of_mass(bob).unwrap() - pivot).length();
    assert!((reach - 1.0).abs() < 1e-3, "held by its hinge: {reach} m");
    assert!(
        (lowest - (pivot.z - 1.0)).abs() < 0.02,
        "swung down to {lowest} m"
    );
    assert!(world.joint_state(hinge).unwrap().linear_error < 1e-3);
}
