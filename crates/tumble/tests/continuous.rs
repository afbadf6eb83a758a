//! Nothing passes through a wall (issue 16): projectiles of every shape
//! fired at thin slabs, a spinning rod beside a slab, a mesh dropped from
//! 100 m onto a thin floor, overlaps pushed out without launching anything.
//! Each asserts no tunnelling, no energy gain and no panic; the matrix also
//! asserts that no body is held in place while it still moves (continuous
//! collision puts bodies back along their path, which must never become a
//! trap). Release mode: `cargo test --release -p tumble --test continuous`.

mod common;

use common::leaning_bar::assert_spun_bar_is_pushed_back_out;
use tumble::scenes::{self, Fault, Projectile};
use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::box_mesh;
use tumble_collide::shape::{Capsule, Cuboid, MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

/// A 2 m x 2 m slab `thick` m thick, a box primitive or a closed mesh.
fn slab(thick: f64, mesh: bool) -> Shape {
    let half = DVec3::new(1.0, 1.0, thick / 2.0);
    if mesh {
        Shape::Mesh(MeshShape::new(box_mesh(half).unwrap()).unwrap())
    } else {
        Shape::Cuboid(Cuboid::new(half).unwrap())
    }
}

fn weightless(continuous: bool) -> World {
    World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        continuous,
        ..WorldSettings::default()
    })
    .unwrap()
}

#[test]
fn no_projectile_passes_a_slab_gains_energy_or_gets_stuck() {
    // The matrix of tumble::scenes::projectile_cases (720 cases: box,
    // sphere, capsule, hull and mesh projectiles; box and mesh slabs 1 mm
    // to 10 cm thick, 0 to 60 degrees; 10 to 1,000 m/s), judged by Flight.
    let cases = scenes::projectile_cases();
    assert_eq!(cases.len(), 720);
    let failures: Vec<String> = cases
        .iter()
        .filter_map(|case| {
            scenes::fire_projectile(case, true)
                .err()
                .map(|(_, why)| format!("{}: {why}", case.label()))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases fail:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn without_continuous_collision_fast_bodies_do_pass_through() {
    // The matrix above is not vacuous: without the continuous stage boxes,
    // hulls and meshes pass through in 284 of its 720 cases, among them
    // these. (Spheres and capsules no longer do: their speculative contacts
    // roll with them, so a gap the step can close is closed.)
    let picks = [
        (Projectile::Hull, false, 30.0, 120.0),
        (Projectile::Box, false, 30.0, 600.0),
        (Projectile::Box, true, 30.0, 250.0),
        (Projectile::Mesh, true, 0.0, 600.0),
    ];
    for (projectile, mesh_slab, degrees, speed) in picks {
        let case = scenes::ProjectileCase {
            projectile,
            mesh_slab,
            thickness: 0.01,
            degrees,
            speed,
        };
        assert!(scenes::fire_projectile(&case, true).is_ok(), "{}", case.label());
        let without = scenes::fire_projectile(&case, false);
        assert!(
            matches!(without, Err((Fault::PassedThrough, _))),
            "{} held without continuous collision: {without:?}",
            case.label()
        );
    }
}

#[test]
fn a_rod_spinning_beside_a_thin_slab_never_reaches_through_it() {
    // A 1.04 m rod turning at 50 rad/s about its centre, 0.3 m from a 1 mm
    // slab: its tips sweep 0.43 m per step and would reach 0.22 m past the
    // slab's face. No point of the rod may ever be beyond the slab.
    for mesh in [false, true] {
        let mut world = weightless(true);
        world
            .add_body(
                &BodyDesc::fixed(slab(0.001, mesh)).with_pose(
                    Pose::new(
                        DVec3::new(0.3, 0.0, 0.0),
                        DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2),
                    )
                    .unwrap(),
                ),
            )
            .unwrap();
        let rod = world
            .add_body(
                &BodyDesc::dynamic(Shape::Capsule(Capsule::new(0.02, 0.5).unwrap()))
                    .with_velocity(DVec3::ZERO, DVec3::new(0.0, 50.0, 0.0)),
            )
            .unwrap();
        let e0 = world.kinetic_energy();
        for step in 0..120 {
            world.step();
            let pose = world.pose(rod).unwrap();
            for end in [-0.52, 0.52] {
                let tip = pose.transform_point(DVec3::new(0.0, 0.0, end));
                assert!(
                    tip.x < 0.3 + 0.0005 + 0.005,
                    "mesh {mesh}, step {step}: tip at {tip:.3} beyond the slab"
                );
            }
            assert!(
                world.kinetic_energy() <= e0 * (1.0 + 1e-9),
                "mesh {mesh}, step {step}: energy gained"
            );
        }
    }
}

#[test]
fn a_mesh_dropped_from_100_m_onto_a_thin_mesh_floor_comes_to_rest_on_it() {
    // 44 m/s at the floor, 0.74 m per step, onto 1 cm of triangles.
    let mut world = World::new(WorldSettings::default()).unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::Mesh(
            MeshShape::new(box_mesh(DVec3::new(3.0, 3.0, 0.005)).unwrap()).unwrap(),
        )))
        .unwrap();
    let ball = world
        .add_body(&BodyDesc::dynamic(Projectile::Mesh.shape()).at(DVec3::new(0.0, 0.0, 100.0)))
        .unwrap();
    let mut peak_after_landing = 0.0f64;
    let mut landed = false;
    for step in 0..(60 * 8) {
        world.step();
        let z = world.center_of_mass(ball).unwrap().z;
        assert!(z > 0.005, "step {step}: the ball is through the floor at z = {z}");
        if z < 0.2 {
            landed = true;
        }
        if landed {
            peak_after_landing = peak_after_landing.max(z);
        }
    }
    assert!(landed, "the ball never reached the floor");
    let z = world.center_of_mass(ball).unwrap().z;
    // Resting on the floor (radius 5 cm, floor top at 5 mm; meshes rest a
    // hair apart), after at most a small hop (restitution 0).
    assert!((z - 0.055).abs() < 0.01, "ball rests at z = {z}");
    assert!(
        peak_after_landing < 1.0,
        "bounced up to {peak_after_landing} m with restitution 0"
    );
    assert!(world.linear_velocity(ball).unwrap().length() < 0.1);
}

#[test]
fn overlaps_are_pushed_out_without_launching_anything() {
    // A box spawned half inside a slab, and one nearly through a thin one:
    // the push-out moves them out by pseudo-velocities, never by speed.
    for (thick, depth) in [(0.2, 0.05), (0.01, 0.04)] {
        let mut world = weightless(true);
        world.add_body(&BodyDesc::fixed(slab(thick, false))).unwrap();
        let top = thick / 2.0;
        let body = world
            .add_body(&BodyDesc::dynamic(Projectile::Box.shape()).at(DVec3::new(
                0.0,
                0.0,
                top + 0.05 - depth,
            )))
            .unwrap();
        for step in 0..120 {
            world.step();
            assert!(
                world.kinetic_energy() < 1e-12,
                "slab {thick}, step {step}: the box was given speed"
            );
        }
        let z = world.center_of_mass(body).unwrap().z;
        assert!(
            z > top + 0.05 - 0.001,
            "slab {thick}: still {} m inside",
            top + 0.05 - z
        );
    }
}

#[test]
fn swept_bodies_survive_a_snapshot_bit_for_bit() {
    let mut world = weightless(true);
    world.add_body(&BodyDesc::fixed(slab(0.01, true))).unwrap();
    world
        .add_body(
            &BodyDesc::dynamic(Projectile::Box.shape())
                .at(DVec3::new(0.0, 0.0, 3.0))
                .with_velocity(DVec3::new(0.0, 0.0, -250.0), DVec3::new(3.0, 0.0, 0.0))
                .with_ccd(true),
        )
        .unwrap();
    world.step();
    let mut copy = World::from_snapshot(&world.snapshot()).unwrap();
    for _ in 0..20 {
        world.step();
        copy.step();
        assert_eq!(world.state_hash(), copy.state_hash());
    }
}

/// A 10 cm box fired at 400 m/s at a free 100 kg plate 1 cm thick, turned
/// 30 degrees, in empty space: whether the box's centre crossed the
/// plate's plane inside its square, the largest total kinetic energy seen
/// over the start's, and how often continuous collision put it back.
fn bullet_at_free_plate(ccd: bool) -> (bool, f64, usize) {
    let mut world = weightless(true);
    let turn = DQuat::from_rotation_y(30f64.to_radians());
    let plate = world
        .add_body(
            &BodyDesc::dynamic(slab(0.01, false))
                .with_pose(Pose::new(DVec3::ZERO, turn).unwrap())
                .with_mass(100.0),
        )
        .unwrap();
    let bullet = world
        .add_body(
            &BodyDesc::dynamic(Projectile::Box.shape())
                .at(DVec3::new(0.0, 0.0, 3.0))
                .with_velocity(DVec3::new(0.0, 0.0, -400.0), DVec3::ZERO)
                .with_ccd(ccd),
        )
        .unwrap();
    let e0 = world.kinetic_energy();
    let mut worst = 1.0f64;
    let side = |w: &World| {
        let pose = w.pose(plate).unwrap();
        let local = pose.inverse_transform_point(w.center_of_mass(bullet).unwrap());
        (local.z, local.x.abs() < 1.0 && local.y.abs() < 1.0)
    };
    let (mut last, _) = side(&world);
    let mut put_back = 0;
    for _ in 0..40 {
        put_back += world.step().continuous;
        worst = worst.max(world.kinetic_energy() / e0);
        let (h, inside) = side(&world);
        if last >= 0.0 && h < 0.0 && inside {
            return (true, worst, put_back);
        }
        last = h;
    }
    (false, worst, put_back)
}

#[test]
fn a_bullet_flagged_ccd_stops_at_a_free_plate_and_pushes_it() {
    // Fast bodies are swept against static and kinematic bodies; with
    // `ccd` set, against dynamic ones too (Box2D's bullets).
    let (through, worst, put_back) = bullet_at_free_plate(true);
    assert!(!through, "the bullet passed through the plate");
    assert!(worst <= 1.0 + 1e-9, "energy rose to {worst} times the start");
    assert!(
        put_back >= 1,
        "the flagged bullet was never swept against the plate"
    );
    let (_, _, unflagged) = bullet_at_free_plate(false);
    assert_eq!(
        unflagged, 0,
        "an unflagged body is not swept against a dynamic one"
    );
}

#[test]
fn a_box_squeezed_into_a_thick_wall_as_it_slides_down_keeps_falling() {
    // A box falls at 16 m/s down the face of a thick frictionless wall
    // while a kinematic plate presses it 3 cm into the wall (nothing can
    // hold it out: the plate cannot move). Fast, it is swept against both;
    // it began each step touching them and ends deeper than the contact
    // margin. Such an overlap with a thick partner is the push-out's
    // business: put back where it began the step, it would hang on the wall
    // (the 10,000-body pile's boxes squeezed into its walls by the landing
    // layers were, and the layer above crashed into them).
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    let slab = || Shape::Cuboid(Cuboid::new(DVec3::new(0.25, 2.0, 50.0)).unwrap());
    world
        .add_body(
            &BodyDesc::fixed(slab())
                .at(DVec3::new(0.25, 0.0, 50.0))
                .with_material(0.0, 0.0),
        )
        .unwrap();
    let plate = world
        .add_body(
            &BodyDesc::kinematic(slab())
                .at(DVec3::new(-0.75, 0.0, 50.0))
                .with_material(0.0, 0.0)
                .with_velocity(DVec3::new(0.6, 0.0, 0.0), DVec3::ZERO),
        )
        .unwrap();
    let (z0, v0) = (80.0, 16.0);
    let body = world
        .add_body(
            &BodyDesc::dynamic(Shape::Cuboid(Cuboid::new(DVec3::splat(0.25)).unwrap()))
                .at(DVec3::new(-0.25, 0.0, z0))
                .with_material(0.0, 0.0)
                .with_velocity(DVec3::new(0.0, 0.0, -v0), DVec3::ZERO),
        )
        .unwrap();
    let steps = 30;
    for step in 0..steps {
        if step == 3 {
            world.set_velocity(plate, DVec3::ZERO, DVec3::ZERO).unwrap();
        }
        world.step();
    }
    // Frictionless: the fall of a free body, z0 - v0 t - g t^2 / 2.
    let t = steps as f64 / 60.0;
    let expected = z0 - v0 * t - 0.5 * 9.81 * t * t;
    let z = world.center_of_mass(body).unwrap().z;
    assert!(
        (z - expected).abs() < 0.05,
        "the box is at z = {z} m after {t} s; a free fall puts it at {expected} m"
    );
}

#[test]
fn a_box_spun_round_within_the_step_into_a_neighbour_is_pushed_back_out() {
    // The leaning bar of `common::leaning_bar` and its slab as box
    // primitives: the bar spun round within one step swings its far end
    // into the slab, which its speculative contacts, found with the
    // velocities the step starts with (zero), did not hold. A pair without
    // a mesh takes part in the end-overlap stage when one of its bodies was
    // struck (its velocities changed by STRUCK_MARGINS margins'
    // worth in the step), as a cube of the 10,000-body pile spun by its
    // corner's landing is; without the stage the bar ends centimetres inside
    // (about 19 mm at 36 rad/s).
    assert_spun_bar_is_pushed_back_out(&|half| Shape::Cuboid(Cuboid::new(half).unwrap()));
}
