//! Gears against physics: a pair of wheels turns in its ratio through
//! many revolutions, a free pair shares its spin as the reduced inertia
//! says and then keeps its energy, a rack falls on its pinion with the
//! acceleration of the reduced mass, the same bits through snapshots and
//! thread counts; bad gears refused with the world unchanged, and a gear
//! goes with either of its joints.

mod common;

use common::{joint_world, G};
use tumble::collide::{Cuboid, DQuat, DVec3, Sphere};
use tumble::joint::{Gear, JointDesc, Motor};
use tumble::world::{BodyDesc, BodyId, JointId, Snapshot, World, WorldError, WorldSettings};

/// A uniform sphere of `mass` kg and radius 0.1 m at `at` (moment of inertia
/// `2/5 m r^2` about any axis), spinning at `spin` about z.
fn wheel(w: &mut World, at: DVec3, mass: f64, spin: f64) -> BodyId {
    w.add_body(
        &BodyDesc::dynamic(Sphere::new(0.1).unwrap())
            .at(at)
            .with_mass(mass)
            .with_velocity(DVec3::ZERO, DVec3::Z * spin),
    )
    .unwrap()
}

fn inertia(mass: f64) -> f64 {
    0.4 * mass * 0.1 * 0.1
}

/// Two wheels on hinges to the world about z, 0.3 m apart; the second
/// follows the first at `ratio`. Returns the world, the bodies and the
/// joints (leader, follower).
fn gear_pair(
    masses: [f64; 2],
    spins: [f64; 2],
    ratio: f64,
    threads: u32,
) -> (World, [BodyId; 2], [JointId; 2]) {
    let mut w = joint_world(false, threads);
    let centres = [DVec3::ZERO, DVec3::new(0.3, 0.0, 0.0)];
    let bodies = [0, 1].map(|k| wheel(&mut w, centres[k], masses[k], spins[k]));
    let joints = [0, 1].map(|k| {
        w.add_joint(&JointDesc::hinge(bodies[k], None, centres[k], DVec3::Z))
            .unwrap()
    });
    w.set_joint_gear(joints[1], Some(Gear::new(joints[0], ratio)))
        .unwrap();
    (w, bodies, joints)
}

/// The angle about z that takes the identity to `q` (rad, in (-pi, pi]).
fn angle_about_z(q: DQuat) -> f64 {
    2.0 * q.z.atan2(q.w)
}

fn wrap(a: f64) -> f64 {
    tumble::joint::wrap_angle(a)
}

#[test]
fn a_driven_gear_pair_turns_in_its_ratio_through_many_revolutions() {
    // The leader driven at 10 rad/s for 2 s: 20 rad, more than three turns,
    // the follower at -1/2 of it, turning back across its own wrap.
    let (mut w, bodies, joints) = gear_pair([1.0, 1.0], [0.0, 0.0], -0.5, 1);
    w.set_joint_motor(
        joints[0],
        Some(Motor::Velocity {
            target: 10.0,
            max_force: 1e3,
        }),
    )
    .unwrap();
    let mut leader_turn = 0.0;
    let mut last = 0.0;
    for step in 0..120 {
        w.step();
        let a = angle_about_z(w.orientation(bodies[0]).unwrap());
        leader_turn += wrap(a - last);
        last = a;
        if step >= 10 {
            let rates = [0, 1].map(|k| w.angular_velocity(bodies[k]).unwrap().z);
            assert!((rates[0] - 10.0).abs() < 1e-6, "leader at {} rad/s", rates[0]);
            assert!((rates[1] + 5.0).abs() < 1e-6, "follower at {} rad/s", rates[1]);
        }
        // Where the follower is: turned back by half the leader's turn, to
        // within the push-out's tolerance, however many times either wrapped.
        let follower = angle_about_z(w.orientation(bodies[1]).unwrap());
        let off = wrap(follower + 0.5 * leader_turn);
        assert!(off.abs() < 1e-6, "step {step}: follower {off} rad off its gear");
        let error = w.gear_error(joints[1]).unwrap();
        assert!(error.abs() < 1e-5, "step {step}: gear error {error} rad");
    }
    assert!(leader_turn > 19.0, "the leader turned {leader_turn} rad");
    assert_eq!(w.joint_gear(joints[1]).unwrap(), Some(Gear::new(joints[0], -0.5)));
    assert_eq!(w.joint_gear(joints[0]).unwrap(), None);
}

#[test]
fn a_free_gear_pair_shares_its_spin_as_the_reduced_inertia_says_and_keeps_its_energy() {
    // The leader spinning alone at w0 meets its follower: one plastic
    // impulse along the gear makes the rates agree, the leader then at
    // w0 I1 / (I1 + r^2 I2) (its angular momentum about the gear's
    // reduced coordinate kept); from there the pair keeps its energy.
    for (masses, ratio) in [([1.0, 1.0], 2.0), ([3.0, 0.5], -0.75), ([0.2, 5.0], 1.5)] {
        let w0 = 4.0;
        let (mut w, bodies, joints) = gear_pair(masses, [w0, 0.0], ratio, 1);
        let (i1, i2) = (inertia(masses[0]), inertia(masses[1]));
        let leader = w0 * i1 / (i1 + ratio * ratio * i2);
        w.step();
        let energy = |w: &World| w.kinetic_energy();
        let e1 = energy(&w);
        let expected = 0.5 * (i1 + ratio * ratio * i2) * leader * leader;
        assert!(
            (e1 - expected).abs() < 1e-9 * expected,
            "{masses:?} {ratio}: {e1} J against {expected}"
        );
        for _ in 0..600 {
            w.step();
            let rates = [0, 1].map(|k| w.angular_velocity(bodies[k]).unwrap().z);
            assert!(
                (rates[0] - leader).abs() < 1e-9 * w0,
                "{masses:?} {ratio}: leader {} rad/s",
                rates[0]
            );
            assert!(
                (rates[1] - ratio * leader).abs() < 1e-9 * w0,
                "follower {}",
                rates[1]
            );
            assert!((energy(&w) - e1).abs() < 1e-9 * e1);
        }
        assert!(w.gear_error(joints[1]).unwrap() < 1e-6);
    }
}

/// A pinion (a hinge about y at the origin) and a rack (a box on a
/// vertical slider), the rack's height held at `ratio` times the pinion's
/// angle. Returns the world, the rack and the pinion's joint.
fn rack_and_pinion(ratio: f64, rack_mass: f64, pinion_mass: f64, threads: u32) -> (World, BodyId, BodyId) {
    let mut w = joint_world(true, threads);
    let pinion = w
        .add_body(
            &BodyDesc::dynamic(Sphere::new(0.1).unwrap())
                .at(DVec3::ZERO)
                .with_mass(pinion_mass),
        )
        .unwrap();
    let rack_at = DVec3::new(0.2, 0.0, 0.0);
    let rack = w
        .add_body(
            &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.02, 0.05, 0.3)).unwrap())
                .at(rack_at)
                .with_mass(rack_mass),
        )
        .unwrap();
    let turn = w
        .add_joint(&JointDesc::hinge(pinion, None, DVec3::ZERO, DVec3::Y))
        .unwrap();
    let slide = w
        .add_joint(&JointDesc::slider(rack, None, rack_at, DVec3::Z))
        .unwrap();
    w.set_joint_gear(slide, Some(Gear::new(turn, ratio))).unwrap();
    (w, rack, pinion)
}

#[test]
fn a_rack_falls_on_its_pinion_with_the_acceleration_of_the_reduced_mass() {
    // x = r theta: the rack's weight m g drives the reduced mass m + I / r^2,
    // so it falls at a = m g / (m + I / r^2), the pinion turning at x' / r.
    for (ratio, m, mp) in [(0.1, 2.0, 1.0), (-0.05, 0.5, 4.0), (0.3, 1.0, 10.0)] {
        let (mut w, rack, pinion) = rack_and_pinion(ratio, m, mp, 1);
        let i = inertia(mp);
        let a = m * G / (m + i / (ratio * ratio));
        let z0 = w.center_of_mass(rack).unwrap().z;
        for _ in 0..60 {
            w.step();
        }
        let t = w.time();
        let fall = z0 - w.center_of_mass(rack).unwrap().z;
        let speed = -w.linear_velocity(rack).unwrap().z;
        assert!(
            (speed - a * t).abs() < 1e-6 * a * t,
            "r {ratio}: falls at {speed} m/s, {} expected",
            a * t
        );
        // Positions by the semi-implicit step: within one step's speed of the analytic.
        assert!(
            (fall - 0.5 * a * t * t).abs() < a * t * w.settings().dt,
            "fell {fall} m"
        );
        let spin = w.angular_velocity(pinion).unwrap().y;
        assert!(
            (spin * ratio + speed).abs() < 1e-6 * speed,
            "pinion at {spin} rad/s"
        );
    }
}

#[test]
fn a_geared_world_continues_bit_for_bit_through_snapshots_and_on_1_2_3_and_8_threads() {
    let run = |threads: u32, through: Option<bool>| {
        let (mut w, _, _) = rack_and_pinion(0.1, 2.0, 1.0, threads);
        // Every step on the threads (never moved to one thread for speed),
        // with enough bodies to share out, far from the gear.
        let settings = WorldSettings {
            adaptive_threads: false,
            ..w.settings().clone()
        };
        w.set_settings(settings).unwrap();
        for k in 0..200 {
            w.add_body(&BodyDesc::dynamic(Sphere::new(0.05).unwrap()).at(DVec3::new(
                10.0 + 0.2 * k as f64,
                0.0,
                0.0,
            )))
            .unwrap();
        }
        let mut threaded = (0..30).filter(|_| w.step().threads > 1).count();
        if let Some(json) = through {
            let snap = w.snapshot();
            let snap = if json {
                Snapshot::from_json(&snap.to_json()).unwrap()
            } else {
                Snapshot::from_bytes(&snap.to_bytes()).unwrap()
            };
            w = World::from_snapshot(&snap).unwrap();
        }
        let mut hashes = Vec::new();
        for _ in 0..30 {
            threaded += usize::from(w.step().threads > 1);
            hashes.push(w.state_hash());
        }
        // Every step on the threads, those after a snapshot too (the
        // setting travels with it).
        assert_eq!(
            threaded,
            if threads > 1 { 60 } else { 0 },
            "{threads} threads, snapshot {through:?}: steps on the threads"
        );
        hashes
    };
    let reference = run(1, None);
    for (threads, through) in [
        (2, None),
        (3, None),
        (8, None),
        (1, Some(false)),
        (1, Some(true)),
        (2, Some(false)),
    ] {
        assert_eq!(
            run(threads, through),
            reference,
            "threads {threads}, snapshot {through:?}"
        );
    }
}

#[test]
fn bad_gears_are_refused_at_their_field_with_the_world_unchanged() {
    let (mut w, bodies, joints) = gear_pair([1.0, 1.0], [1.0, 0.0], 2.0, 1);
    let ball = w
        .add_joint(&JointDesc::ball(
            bodies[0],
            Some(bodies[1]),
            DVec3::new(0.15, 0.0, 0.0),
        ))
        .unwrap();
    let before = w.snapshot().to_bytes();
    let field = |e: WorldError| match e {
        WorldError::BadValue { field, .. } => field.to_string(),
        WorldError::StaleJoint(_) => "stale".to_string(),
        other => format!("{other:?}"),
    };
    // (Ratios and offsets beyond 1e6: at f64::MAX the error overflowed to
    // infinity, found by the fuzzer.)
    let cases: [(JointId, Gear, &str); 8] = [
        (joints[1], Gear::new(joints[1], 1.0), "gear.leader"),
        (joints[1], Gear::new(ball, 1.0), "gear.leader"),
        (ball, Gear::new(joints[0], 1.0), "gear.follower"),
        (joints[1], Gear::new(joints[0], f64::NAN), "gear.ratio"),
        (joints[1], Gear::new(joints[0], -2e6), "gear.ratio"),
        (
            joints[1],
            Gear::new(joints[0], 1.0).with_offset(f64::INFINITY),
            "gear.offset",
        ),
        (
            joints[1],
            Gear::new(joints[0], 1.0).with_offset(1.5e6),
            "gear.offset",
        ),
        (
            joints[1],
            Gear::new(joints[0], f64::MAX).with_offset(f64::MAX),
            "gear.ratio",
        ),
    ];
    for (follower, gear, expected) in cases {
        let e = w.set_joint_gear(follower, Some(gear)).unwrap_err();
        assert_eq!(field(e), expected, "{gear:?} on {follower:?}");
        assert_eq!(w.snapshot().to_bytes(), before, "{gear:?} changed the world");
    }
    // A removed joint, as leader or follower.
    let gone = w
        .add_joint(&JointDesc::hinge(bodies[0], None, DVec3::ZERO, DVec3::X))
        .unwrap();
    w.remove_joint(gone).unwrap();
    let before = w.snapshot().to_bytes();
    assert!(
        matches!(w.set_joint_gear(joints[1], Some(Gear::new(gone, 1.0))), Err(WorldError::StaleJoint(j)) if j == gone)
    );
    assert!(matches!(
        w.set_joint_gear(gone, None),
        Err(WorldError::StaleJoint(_))
    ));
    assert_eq!(w.snapshot().to_bytes(), before);
}

#[test]
fn a_gear_goes_with_either_of_its_joints_and_can_be_let_go() {
    // Let go: the follower keeps the rate it had and the leader its own.
    let (mut w, bodies, joints) = gear_pair([1.0, 1.0], [2.0, 0.0], 1.0, 1);
    w.step();
    w.set_joint_gear(joints[1], None).unwrap();
    w.set_joint_motor(
        joints[0],
        Some(Motor::Velocity {
            target: 5.0,
            max_force: 1e3,
        }),
    )
    .unwrap();
    let follower = w.angular_velocity(bodies[1]).unwrap().z;
    for _ in 0..30 {
        w.step();
    }
    assert!((w.angular_velocity(bodies[1]).unwrap().z - follower).abs() < 1e-12);
    // The leader removed: the follower has no gear any more.
    let (mut w, _, joints) = gear_pair([1.0, 1.0], [2.0, 0.0], 1.0, 1);
    w.remove_joint(joints[0]).unwrap();
    assert_eq!(w.joint_gear(joints[1]).unwrap(), None);
    w.step();
    // The leader's body removed (its joints with it): the same.
    let (mut w, bodies, joints) = gear_pair([1.0, 1.0], [2.0, 0.0], 1.0, 1);
    w.remove_body(bodies[0]).unwrap();
    assert_eq!(w.joint_gear(joints[1]).unwrap(), None);
    w.step();
}

/// A tumbling frame carrying a wheel (a hinge about the frame's z) and a
/// block (a slider along its x), the block's offset geared to the wheel's
/// angle at 0.05 m/rad unless `geared` is false. Returns the world, the
/// frame, wheel and block, and the two joints.
fn flying_rack(geared: bool) -> (World, [BodyId; 3], [JointId; 2]) {
    let mut w = joint_world(false, 1);
    let frame = w
        .add_body(
            &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.3, 0.1, 0.05)).unwrap())
                .at(DVec3::ZERO)
                .with_mass(3.0),
        )
        .unwrap();
    let (wheel_at, block_at) = (DVec3::new(-0.2, 0.0, 0.1), DVec3::new(0.2, 0.0, 0.1));
    let wheel = wheel(&mut w, wheel_at, 0.5, 0.0);
    let block = w
        .add_body(
            &BodyDesc::dynamic(Cuboid::new(DVec3::splat(0.03)).unwrap())
                .at(block_at)
                .with_mass(0.7),
        )
        .unwrap();
    let turn = w
        .add_joint(&JointDesc::hinge(wheel, Some(frame), wheel_at, DVec3::Z))
        .unwrap();
    let slide = w
        .add_joint(&JointDesc::slider(block, Some(frame), block_at, DVec3::X))
        .unwrap();
    if geared {
        w.set_joint_gear(slide, Some(Gear::new(turn, 0.05))).unwrap();
    }
    // The whole tumbling, the wheel spinning against it.
    let spin = DVec3::new(0.7, -1.1, 2.3);
    for (id, extra) in [
        (frame, DVec3::ZERO),
        (wheel, DVec3::Z * 6.0),
        (block, DVec3::ZERO),
    ] {
        let x = w.center_of_mass(id).unwrap();
        w.set_velocity(id, DVec3::new(0.2, 0.1, -0.3) + spin.cross(x), spin + extra)
            .unwrap();
    }
    (w, [frame, wheel, block], [turn, slide])
}

#[test]
fn a_free_floating_geared_mechanism_keeps_its_momentum_and_its_ratio() {
    // The gear is internal (its row's parts sum to no force and no torque
    // about any point), so the mechanism's linear momentum stays what it
    // was, to round-off; its angular momentum moves only as much as the
    // same mechanism's without the gear does (the push-out moves bodies,
    // which turns `x x p`). The rates read through the moving frames keep
    // the ratio to within the sub-step's turn (the row is built at each
    // sub-step's start).
    let momentum = |w: &World, bodies: &[BodyId; 3]| {
        let (mut p, mut l) = (DVec3::ZERO, DVec3::ZERO);
        for &id in bodies {
            let body = w.body(id).unwrap();
            p += body.linear_momentum();
            l += body.angular_momentum() + body.position().cross(body.linear_momentum());
        }
        (p, l)
    };
    let mut drift = [0.0f64; 2];
    for geared in [false, true] {
        let (mut w, bodies, [turn, slide]) = flying_rack(geared);
        let (p0, l0) = momentum(&w, &bodies);
        let h = w.settings().dt / w.settings().substeps as f64;
        for step in 0..240 {
            w.step();
            let (p, l) = momentum(&w, &bodies);
            assert!((p - p0).length() < 1e-9, "step {step}: {p} from {p0}");
            drift[geared as usize] = drift[geared as usize].max((l - l0).length());
            if geared && step >= 10 {
                let (leader, follower) = (w.joint_state(turn).unwrap(), w.joint_state(slide).unwrap());
                assert!(
                    w.gear_error(slide).unwrap() < 1e-5,
                    "step {step}: {}",
                    w.gear_error(slide).unwrap()
                );
                assert!(follower.linear_error < 1e-4, "{follower:?}");
                let lag = 2.0 * h * w.angular_velocity(bodies[1]).unwrap().length();
                assert!(
                    (follower.rate - 0.05 * leader.rate).abs() < lag * follower.rate.abs(),
                    "step {step}: slider at {} m/s, wheel at {} rad/s",
                    follower.rate,
                    leader.rate
                );
            }
        }
    }
    assert!(
        drift[1] < 3.0 * drift[0] + 1e-9,
        "angular momentum moved {} with the gear, {} without",
        drift[1],
        drift[0]
    );
    // Made with an offset the coordinates do not have, the gear closes it.
    let (mut w, _, [turn, slide]) = flying_rack(false);
    w.set_joint_gear(slide, Some(Gear::new(turn, 0.05).with_offset(0.01)))
        .unwrap();
    assert!((w.gear_error(slide).unwrap() - 0.01).abs() < 1e-12);
    for _ in 0..30 {
        w.step();
    }
    assert!(
        w.gear_error(slide).unwrap() < 1e-5,
        "{}",
        w.gear_error(slide).unwrap()
    );
}

#[test]
fn a_gear_holds_under_the_exact_contact_solver_too() {
    // `SolverKind::Lemke` runs its sub-steps on one thread, gears included:
    // the rack falls on its pinion as with the passes.
    let (mut w, rack, _) = rack_and_pinion(0.1, 2.0, 1.0, 1);
    // (The exact path runs where there are contacts: a box resting on a
    // floor well away from the rack.)
    w.add_body(&BodyDesc::fixed(
        tumble::collide::HalfSpace::new(DVec3::Z, -10.0).unwrap(),
    ))
    .unwrap();
    w.add_body(
        &BodyDesc::dynamic(Cuboid::new(DVec3::splat(0.1)).unwrap())
            .at(DVec3::new(5.0, 0.0, -9.9))
            .with_mass(1.0),
    )
    .unwrap();
    let mut settings = w.settings().clone();
    settings.solver = tumble::world::SolverKind::Lemke;
    w.set_settings(settings).unwrap();
    let a = 2.0 * G / (2.0 + inertia(1.0) / 0.01);
    for _ in 0..60 {
        w.step();
    }
    let speed = -w.linear_velocity(rack).unwrap().z;
    assert!(
        (speed - a * w.time()).abs() < 1e-6 * speed,
        "falls at {speed} m/s"
    );
    assert!(w.step().contacts > 0, "the exact path ran");
}

#[test]
fn a_gear_counts_the_turns_of_a_wheel_faster_than_half_a_turn_a_step() {
    // 250 rad/s is 4.2 rad a step at 60 Hz, more than pi: counted step to
    // step the leader's turn would come out 2 pi short every step and the
    // follower at -1/2 of it pi off. Counted sub-step to sub-step (0.52
    // rad each) it is right: the follower stays at -1/2 of the leader's
    // turn (the turn summed from the leader's speed, which its motor holds).
    // The gear holds to a few microradians: the pair is one joint island
    // whose system holds the gear, and the leader's motor, relaxed after
    // that system in each pass, has the last word.
    let (mut w, bodies, joints) = gear_pair([1.0, 1.0], [0.0, 0.0], -0.5, 1);
    w.set_joint_motor(
        joints[0],
        Some(Motor::Velocity {
            target: 250.0,
            max_force: 1e6,
        }),
    )
    .unwrap();
    let dt = w.settings().dt;
    let mut turn = 0.0;
    for step in 0..60 {
        w.step();
        turn += w.angular_velocity(bodies[0]).unwrap().z * dt;
        let follower = angle_about_z(w.orientation(bodies[1]).unwrap());
        let off = wrap(follower + 0.5 * turn);
        assert!(
            off.abs() < 1e-2,
            "step {step}: follower {off} rad off half the leader's turn"
        );
        let error = w.gear_error(joints[1]).unwrap();
        assert!(error.abs() < 1e-5, "step {step}: gear error {error} rad");
    }
    assert!(turn > 240.0, "{turn}");
}

#[test]
fn a_scene_with_a_gear_builds_it_and_resolves_to_plain_data() {
    use tumble::scenes::{Scene, SceneGear};
    let wheel = |x: f64| {
        BodyDesc::dynamic(Sphere::new(0.1).unwrap())
            .at(DVec3::new(x, 0.0, 0.0))
            .with_mass(1.0)
    };
    let scene = Scene {
        name: "gears".into(),
        settings: WorldSettings::default(),
        bodies: vec![wheel(0.0), wheel(0.3)],
        steps: 10,
        joints: vec![
            JointDesc::hinge(0, None, DVec3::ZERO, DVec3::Z),
            JointDesc::hinge(1, None, DVec3::new(0.3, 0.0, 0.0), DVec3::Z),
        ],
        no_contact: Vec::new(),
        gears: vec![SceneGear {
            follower: 1,
            leader: 0,
            ratio: 3.0,
            offset: 0.0,
        }],
    };
    let (w, _) = scene.build().unwrap();
    let ids = w.joint_ids();
    assert_eq!(w.joint_gear(ids[1]).unwrap(), Some(Gear::new(ids[0], 3.0)));
    // The bodies' plain data (for the other engines) leaves joints, and so gears, out.
    assert_eq!(scene.plain().unwrap().bodies.len(), 2);
    // A gear naming a joint the scene does not have is refused, not a panic.
    let bad = Scene {
        gears: vec![SceneGear {
            follower: 1,
            leader: 5,
            ratio: 1.0,
            offset: 0.0,
        }],
        ..scene
    };
    assert!(matches!(
        bad.build(),
        Err(WorldError::BadValue {
            field: "scene.gears",
            ..
        })
    ));
}

#[test]
fn a_light_follower_stopped_by_a_contact_stops_its_heavy_leader() {
    // A 1 kg wheel on a 10 kg frame drives, through a gear of ratio 1, a
    // 1 g flap hinged to the same frame (a robot's finger on its hand),
    // and the flap swings into a stop welded to the frame. Nothing can
    // pass: the flap stops at the stop, the gear stops the wheel with it,
    // and the frame takes the wheel's spin (no gravity, nothing outside:
    // momentum is kept). Relaxed beside the contact (before 2026-12-02),
    // the gear let the wheel spin on while the contact turned the flap
    // back, and the flap went 4 mm into the stop; now the gear and the
    // contact are rows of one system (the frame's joint island).
    for threads in [1, 2] {
        let mut w = joint_world(false, threads);
        let frame = w
            .add_body(
                &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.3, 0.3, 0.05)).unwrap())
                    .at(DVec3::ZERO)
                    .with_mass(10.0),
            )
            .unwrap();
        let (wheel_at, hinge_at) = (DVec3::new(-0.2, 0.0, 0.2), DVec3::new(0.2, 0.0, 0.2));
        let spin = 3.0;
        let wheel = wheel(&mut w, wheel_at, 1.0, spin);
        let flap = w
            .add_body(
                &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.1, 0.01, 0.02)).unwrap())
                    .at(hinge_at + DVec3::X * 0.1)
                    .with_mass(1e-3)
                    .with_velocity(DVec3::Y * 0.1 * spin, DVec3::Z * spin),
            )
            .unwrap();
        let stop_at = DVec3::new(0.3, 0.08, 0.2);
        let stop = w
            .add_body(
                &BodyDesc::dynamic(Cuboid::new(DVec3::splat(0.02)).unwrap())
                    .at(stop_at)
                    .with_mass(0.5),
            )
            .unwrap();
        let turn = w
            .add_joint(&JointDesc::hinge(wheel, Some(frame), wheel_at, DVec3::Z))
            .unwrap();
        let swing = w
            .add_joint(&JointDesc::hinge(flap, Some(frame), hinge_at, DVec3::Z))
            .unwrap();
        w.add_joint(&JointDesc::fixed(stop, Some(frame), stop_at))
            .unwrap();
        w.set_joint_gear(swing, Some(Gear::new(turn, 1.0))).unwrap();
        let bodies = [frame, wheel, flap, stop];
        let angular_momentum = |w: &World| {
            bodies
                .iter()
                .map(|&id| {
                    let body = w.body(id).unwrap();
                    body.angular_momentum() + body.position().cross(body.linear_momentum())
                })
                .sum::<DVec3>()
        };
        let l0 = angular_momentum(&w);
        let mut met = false;
        for step in 0..120 {
            let report = w.step();
            met |= report.contacts > 0;
            let error = w.gear_error(swing).unwrap();
            assert!(
                error.abs() < 1e-3,
                "threads {threads}, step {step}: gear error {error} rad"
            );
            assert!(
                report.max_penetration < 2e-3,
                "threads {threads}, step {step}: the flap {} m into the stop",
                report.max_penetration
            );
        }
        assert!(met, "the flap reached the stop");
        // Stopped at the stop: the wheel turns no more against the frame.
        let rate = w.joint_state(turn).unwrap().rate;
        assert!(
            rate.abs() < 0.05 * spin,
            "threads {threads}: the wheel still turns at {rate} rad/s"
        );
        // (To the push-out's share: it moves bodies, which turns x x p.)
        let l = angular_momentum(&w);
        assert!((l - l0).length() < 1e-4 * l0.length(), "{l} from {l0}");
    }
}

#[test]
fn a_gear_measures_its_leader_against_a_turning_kinematic_base() {
    // The leader wheel is hinged to a kinematic turntable spinning at 2
    // rad/s, the follower to the world, ratio 1: the follower turns at the
    // leader's rate against the turntable, not against the world (before
    // 2026-12-02 the gear's row left the turntable's velocity out: the
    // leader turned at -2 rad/s against it while the follower stood).
    let mut w = joint_world(false, 1);
    let table = w
        .add_body(
            &BodyDesc::kinematic(Cuboid::new(DVec3::new(0.3, 0.3, 0.05)).unwrap())
                .at(DVec3::ZERO)
                .with_velocity(DVec3::ZERO, DVec3::Z * 2.0),
        )
        .unwrap();
    let (leader_at, follower_at) = (DVec3::new(0.0, 0.0, 0.3), DVec3::new(1.0, 0.0, 0.0));
    let leader_wheel = wheel(&mut w, leader_at, 1.0, 0.0);
    let follower_wheel = wheel(&mut w, follower_at, 1.0, 0.0);
    let leader = w
        .add_joint(&JointDesc::hinge(leader_wheel, Some(table), leader_at, DVec3::Z))
        .unwrap();
    let follower = w
        .add_joint(&JointDesc::hinge(follower_wheel, None, follower_at, DVec3::Z))
        .unwrap();
    w.set_joint_gear(follower, Some(Gear::new(leader, 1.0))).unwrap();
    for step in 0..60 {
        w.step();
        let (l, f) = (
            w.joint_state(leader).unwrap().rate,
            w.joint_state(follower).unwrap().rate,
        );
        assert!(
            (f - l).abs() < 1e-6 * (1.0 + l.abs()),
            "step {step}: follower at {f}, leader at {l} rad/s"
        );
        let error = w.gear_error(follower).unwrap();
        assert!(error.abs() < 1e-6, "step {step}: gear error {error} rad");
    }
    // Equal wheels, ratio 1, nothing else turning them: the gear's impulse
    // gives the leader +w and the follower -w, with the follower at the
    // leader's rate against the table, -w = w - 2: both joints at -1 rad/s.
    for joint in [leader, follower] {
        let rate = w.joint_state(joint).unwrap().rate;
        assert!((rate + 1.0).abs() < 1e-6, "{rate} rad/s");
    }
}
