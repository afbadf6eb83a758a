//! Triangle-mesh bodies in the world (issue: concave mesh dynamics), first
//! cases: a mesh body behaves like the primitive it tessellates, and a torus
//! (concave) comes to rest on the ground.

mod common;

use common::ground_world;
use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::{box_mesh, torus_mesh};
use tumble_collide::shape::{Cuboid, HalfSpace, MeshShape, Shape};
use tumble_collide::DVec3;

fn settle(desc: BodyDesc, steps: usize) -> (World, tumble::world::BodyId) {
    let mut world = ground_world();
    let id = world.add_body(&desc).unwrap();
    for _ in 0..steps {
        world.step();
    }
    (world, id)
}

#[test]
fn mesh_cube_rests_where_the_primitive_cube_rests() {
    let start = DVec3::new(0.0, 0.0, 1.0);
    let mesh = Shape::Mesh(MeshShape::new(box_mesh(DVec3::splat(0.25)).unwrap()).unwrap());
    let prim = Shape::Cuboid(Cuboid::new(DVec3::splat(0.25)).unwrap());
    let (wm, m) = settle(BodyDesc::dynamic(mesh).at(start).with_mass(1.0), 120);
    let (wp, p) = settle(BodyDesc::dynamic(prim).at(start).with_mass(1.0), 120);
    let (zm, zp) = (wm.center_of_mass(m).unwrap().z, wp.center_of_mass(p).unwrap().z);
    let margin = wm.settings().contact_margin;
    assert!((zm - zp).abs() < margin, "mesh cube at {zm}, primitive at {zp}");
    assert!((zm - 0.25).abs() < 0.002, "rests on its face: {zm}");
    assert!(wm.linear_velocity(m).unwrap().length() < 1e-3);
    // Same mass properties from the polyhedral integrals as from the formula.
    let (bm, bp) = (wm.body(m).unwrap(), wp.body(p).unwrap());
    assert!((bm.mass() - bp.mass()).abs() < 1e-12);
    assert!((bm.principal_inertia() - bp.principal_inertia()).length() < 1e-12);
}

#[test]
fn torus_dropped_on_the_ground_comes_to_rest_lying_flat() {
    // A concave body: only its ring touches the ground.
    let torus = Shape::Mesh(MeshShape::new(torus_mesh(0.5, 0.1, 24, 12).unwrap()).unwrap());
    let (world, id) = settle(
        BodyDesc::dynamic(torus)
            .at(DVec3::new(0.0, 0.0, 0.5))
            .with_density(500.0),
        240,
    );
    let z = world.center_of_mass(id).unwrap().z;
    // With 12 segments around the tube, a ring of vertices lies exactly r
    // below the centre plane (v = 3 pi / 2): the torus rests on it.
    let lowest = 0.1;
    assert!(
        (z - lowest).abs() < 0.003,
        "torus centre at {z}, expected {lowest}"
    );
    let v = world.linear_velocity(id).unwrap();
    let w = world.angular_velocity(id).unwrap();
    assert!(
        v.length() < 1e-2 && w.length() < 1e-1,
        "still moving: v {v:?}, w {w:?}"
    );
    let axis = world.orientation(id).unwrap() * DVec3::Z;
    assert!(axis.z.abs() > 0.999, "lies flat: axis {axis:?}");
}

#[test]
fn torus_chain_keeps_its_links_interlocked_while_it_drops() {
    // shared/scenes.md chain, first second (the full 10 s run is the
    // `chain` example): links are concave meshes against concave meshes, no
    // convex decomposition. Adjacent centres never part by more than
    // 2R - 2r + 0.2 = 1.8 m, or the tubes would have passed through each other.
    let scene = tumble::scenes::chain();
    let (mut world, ids) = scene.build().unwrap();
    let z0 = world.center_of_mass(*ids.last().unwrap()).unwrap().z;
    for _ in 0..60 {
        world.step();
        for w in ids.windows(2) {
            let d = (world.center_of_mass(w[0]).unwrap() - world.center_of_mass(w[1]).unwrap()).length();
            assert!(d <= 1.8, "links {:?} and {:?} came apart: {d} m", w[0], w[1]);
        }
    }
    // The chain did move: it swings down towards the vertical, so its free end drops.
    let z1 = world.center_of_mass(*ids.last().unwrap()).unwrap().z;
    assert!(z1 < z0 - 0.5, "free end went from z = {z0} to {z1}");
}

fn mesh(m: tumble_collide::TriMesh) -> Shape {
    Shape::Mesh(MeshShape::new(m).unwrap())
}

/// Deepest penetration among the contacts between two given bodies (m).
fn penetration_between(world: &World, a: tumble::world::BodyId, b: tumble::world::BodyId) -> f64 {
    world
        .contacts()
        .iter()
        .filter(|c| (c.body_a, c.body_b) == (a, b) || (c.body_a, c.body_b) == (b, a))
        .map(|c| -c.contact.distance)
        .fold(0.0, f64::max)
}

#[test]
fn torus_chain_swings_for_ten_seconds_without_links_sinking_or_parting() {
    // shared/scenes.md chain at dt 1/240 (4 sub-steps): concave link meshes
    // against each other, no convex decomposition. Over 10 s of swinging the
    // tubes never sink into each other by more than 1% of the tube radius
    // (0.2 m), and adjacent centres never part beyond 2R - 2r + 0.2 = 1.8 m.
    let mut scene = tumble::scenes::chain();
    scene.settings.dt = 1.0 / 240.0;
    scene.settings.substeps = 4;
    let (mut world, ids) = scene.build().unwrap();
    let mut deepest: f64 = 0.0;
    let mut widest: f64 = 0.0;
    for _ in 0..2400 {
        world.step();
        for w in ids.windows(2) {
            deepest = deepest.max(penetration_between(&world, w[0], w[1]));
            let d = (world.center_of_mass(w[0]).unwrap() - world.center_of_mass(w[1]).unwrap()).length();
            widest = widest.max(d);
        }
    }
    assert!(deepest < 0.002, "links sank {deepest} m into each other");
    assert!(widest <= 1.8, "adjacent links {widest} m apart: the chain broke");
    // It did swing: the links passed the vertical below the anchor.
    let end = world.center_of_mass(*ids.last().unwrap()).unwrap();
    assert!(end.z < -15.0, "free end at {end:?}");
}

#[test]
fn torus_dropped_over_a_peg_settles_around_it() {
    // A ring (R 0.5, r 0.1: hole radius 0.4) falls over a vertical peg of
    // radius 0.15, off-centre by 0.1 m and tilted: it must slide down around
    // the peg to the ground. A convex-hull collider would fill the hole and
    // leave the ring sitting on top of the peg.
    let mut world = ground_world();
    let peg = tumble_collide::mesh::cylinder_mesh(0.15, 0.6, 24).unwrap();
    let peg = world
        .add_body(&BodyDesc::fixed(mesh(peg)).at(DVec3::new(0.0, 0.0, 0.6)))
        .unwrap();
    let ring = world
        .add_body(
            &BodyDesc::dynamic(mesh(torus_mesh(0.5, 0.1, 32, 12).unwrap()))
                .with_pose(tumble_collide::Pose {
                    position: DVec3::new(0.1, 0.0, 1.6),
                    rotation: tumble_collide::DQuat::from_rotation_x(0.2),
                })
                .with_density(500.0),
        )
        .unwrap();
    let mut deepest: f64 = 0.0;
    for _ in 0..300 {
        world.step();
        deepest = deepest.max(penetration_between(&world, ring, peg));
    }
    let c = world.center_of_mass(ring).unwrap();
    // Down at the foot of the peg (resting on the ground, perhaps leaning on
    // the peg: its centre is then at most R sin(tilt) + r above the ground).
    assert!(c.z < 0.35, "ring centre at {c:?}: it did not go down the peg");
    // The peg passes through the hole: the ring's centre is within the hole
    // radius minus the peg radius of the peg axis (plus faceting).
    let off_axis = (c.x * c.x + c.y * c.y).sqrt();
    assert!(
        off_axis < 0.4 - 0.15 + 0.01,
        "ring centre {off_axis} m off the peg axis"
    );
    assert!(deepest < 0.005, "ring sank {deepest} m into the peg");
}

#[test]
fn mesh_sphere_rolls_down_the_incline_at_five_sevenths_g_sin_theta() {
    // shared/scenes.md incline (30 degrees, mu 0.7) with a faceted sphere
    // (icosphere, 1280 triangles) instead of the cube: rolling without
    // slipping, a solid sphere accelerates at 5/7 g sin(theta) = 3.50 m/s^2.
    // The facets make it rock from face to face, slowing it slightly.
    let mut scene = tumble::scenes::incline(0.7);
    let theta = 30f64.to_radians();
    let normal = DVec3::new(theta.sin(), 0.0, theta.cos());
    let r = 0.25;
    scene.bodies[1] = BodyDesc::dynamic(mesh(tumble_collide::mesh::icosphere_mesh(r, 3).unwrap()))
        .at(normal * (0.5 + r))
        .with_mass(1.0)
        .with_material(0.7, 0.0);
    let (mut world, ids) = scene.build().unwrap();
    let ball = ids[1];
    let start = world.center_of_mass(ball).unwrap();
    let t = 1.0;
    for _ in 0..(t / scene.settings.dt).round() as usize {
        world.step();
    }
    let down_slope = DVec3::new(theta.cos(), 0.0, -theta.sin());
    let travelled = (world.center_of_mass(ball).unwrap() - start).dot(down_slope);
    let a = 2.0 * travelled / (t * t);
    let ideal = 5.0 / 7.0 * 9.81 * theta.sin();
    assert!(
        a > 0.9 * ideal && a < 1.02 * ideal,
        "rolled at {a} m/s^2, ideal {ideal}"
    );
    // Rolling, not sliding: the contact point is at rest, so v = w r.
    let v = world.linear_velocity(ball).unwrap().length();
    let w = world.angular_velocity(ball).unwrap().length();
    assert!((v - w * r).abs() < 0.05 * v, "v {v} vs w r {}", w * r);
}

#[test]
fn mesh_box_on_a_mesh_slope_sticks_or_slides_as_coulomb_says() {
    // shared/scenes.md incline (30 degrees) with both the slab and the cube
    // as triangle meshes. With mu 0.7 > tan 30 the cube holds still (its
    // patch holds an anchor, and from 0.5 s on it stays within a micron);
    // with mu 0.2 the anchor lets go and the cube slides at
    // g (sin - mu cos).
    let theta = 30f64.to_radians();
    let downhill = DVec3::new(theta.cos(), 0.0, -theta.sin());
    for mu in [0.7, 0.2] {
        let mut scene = tumble::scenes::incline(mu);
        let (slab, cube) = (scene.bodies[0].pose, scene.bodies[1].pose);
        scene.bodies[0] = BodyDesc::fixed(mesh(box_mesh(DVec3::new(10.0, 10.0, 0.5)).unwrap()))
            .with_pose(slab)
            .with_material(mu, 0.0);
        scene.bodies[1] = BodyDesc::dynamic(mesh(box_mesh(DVec3::splat(0.25)).unwrap()))
            .with_pose(cube)
            .with_mass(1.0)
            .with_material(mu, 0.0);
        let (mut world, ids) = scene.build().unwrap();
        let start = world.center_of_mass(ids[1]).unwrap();
        let mut settled = start;
        let steps = (5.0 / scene.settings.dt).round() as usize;
        for k in 1..=steps {
            world.step();
            if k == steps / 10 {
                settled = world.center_of_mass(ids[1]).unwrap();
            }
            if mu < 0.5 && k == steps / 5 {
                // 1 s in: d = a t^2 / 2.
                let a = 9.81 * (theta.sin() - mu * theta.cos());
                let d = (world.center_of_mass(ids[1]).unwrap() - start).dot(downhill);
                assert!(
                    (d - 0.5 * a).abs() < 0.02 * 0.5 * a,
                    "slid {d} m in 1 s, expected {}",
                    0.5 * a
                );
                break;
            }
        }
        if mu > 0.5 {
            let crept = (world.center_of_mass(ids[1]).unwrap() - settled).length();
            assert!(crept < 1e-6, "the cube crept {crept} m from 0.5 s to 5 s");
            assert!(
                (settled - start).length() < 1e-3,
                "moved {} m settling",
                (settled - start).length()
            );
        }
    }
}

#[test]
fn box_slides_straight_and_smoothly_across_a_ground_of_small_triangles() {
    // A cube slides at 3 m/s across a static sheet of 0.25 m cells (3200
    // triangles, diagonals in a checkerboard). The internal edges must not
    // catch it: no vertical velocity spikes, no change of direction, and
    // the deceleration is Coulomb's mu g.
    let mut world = World::new(WorldSettings {
        sleeping: false,
        dt: 1.0 / 120.0,
        ..WorldSettings::default()
    })
    .unwrap();
    let sheet = tumble_collide::mesh::grid_mesh(10.0, 10.0, 40, 40).unwrap();
    world
        .add_body(&BodyDesc::fixed(mesh(sheet)).with_material(0.3, 0.0))
        .unwrap();
    let dir = DVec3::new(1.0, 0.3, 0.0).normalize();
    let cube = world
        .add_body(
            &BodyDesc::dynamic(Shape::Cuboid(Cuboid::new(DVec3::splat(0.2)).unwrap()))
                .at(DVec3::new(-6.0, -2.0, 0.2))
                .with_mass(1.0)
                .with_material(0.3, 0.0)
                .with_velocity(dir * 3.0, DVec3::ZERO),
        )
        .unwrap();
    let start = world.center_of_mass(cube).unwrap();
    let mut max_vz: f64 = 0.0;
    let mut max_w: f64 = 0.0;
    let t = 0.8;
    for _ in 0..(t / 0.008333333333333333_f64).round() as usize {
        world.step();
        max_vz = max_vz.max(world.linear_velocity(cube).unwrap().z.abs());
        max_w = max_w.max(world.angular_velocity(cube).unwrap().length());
    }
    let p = world.center_of_mass(cube).unwrap();
    let moved = p - start;
    assert!(max_vz < 0.02, "vertical velocity spike {max_vz} m/s");
    // Patch friction leaves nothing to turn the cube: no yaw, no tumbling.
    assert!(max_w < 0.01, "the cube turned at {max_w} rad/s");
    let sideways = (moved - dir * moved.dot(dir)).length();
    assert!(
        sideways < 0.001 * moved.length(),
        "left its straight path by {sideways} m over {} m",
        moved.length()
    );
    // Coulomb: v = 3 - mu g t, distance = 3 t - mu g t^2 / 2.
    let expected = 3.0 * t - 0.5 * 0.3 * 9.81 * t * t;
    assert!(
        (moved.dot(dir) - expected).abs() < 0.02 * expected,
        "slid {} m, expected {expected}",
        moved.dot(dir)
    );
}

#[test]
fn interpenetrating_tori_separate_without_gaining_energy() {
    // Two tori spawned overlapping (B is A lifted by half the tube
    // thickness: their tubes overlap all around), in zero gravity. The
    // push-out must separate them along z within a bounded time, and since
    // the correction moves bodies without giving them velocity, they must
    // not fly apart with kinetic energy of their own. The world is built
    // here, as in contact_physics.rs's tunnelling test, with the settings
    // this case relies on (no gravity, no sleeping) in view.
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    let torus = mesh(torus_mesh(1.0, 0.3, 32, 16).unwrap());
    let a = world.add_body(&BodyDesc::dynamic(torus.clone())).unwrap();
    let b = world
        .add_body(&BodyDesc::dynamic(torus).at(DVec3::new(0.0, 0.0, 0.3)))
        .unwrap();
    let allowed = world.settings().allowed_penetration;
    let mut separated_at = None;
    for step in 0..120 {
        let r = world.step();
        if r.max_penetration <= allowed + 1e-6 {
            separated_at.get_or_insert(step);
        } else {
            separated_at = None;
        }
    }
    let step = separated_at.expect("still overlapping after 2 s");
    assert!(step < 60, "took {step} steps to separate");
    // Stacked along z, tube on tube (2r apart, less the allowed overlap),
    // not slid sideways or tilted.
    let (pa, pb) = (world.center_of_mass(a).unwrap(), world.center_of_mass(b).unwrap());
    let d = pb - pa;
    assert!(d.z >= 0.6 - 2.0 * allowed - 1e-3, "centres {pa:?} {pb:?}");
    assert!(d.x.abs() < 1e-3 && d.y.abs() < 1e-3, "slid sideways: {d:?}");
    let tilt = (world.orientation(b).unwrap() * DVec3::Z).z;
    assert!(tilt > 0.9999, "B tilted: axis z {tilt}");
    let ke = world.kinetic_energy();
    let m = world.body(a).unwrap().mass();
    // The split impulse leaves the velocities alone: no energy gained.
    assert!(ke < 1e-6 * m, "kinetic energy {ke} J after separating");
}

#[test]
fn mesh_slab_on_a_fine_sheet_rests_level_on_a_reduced_patch_that_carries_its_weight() {
    // A mesh slab (0.4 x 0.4 x 0.1 m) lying on a sheet of 5 cm cells: 81
    // sheet vertices under its face, the slab's corners and the crossings
    // of their edges make one patch of over a hundred points, which the
    // world reduces (tumble_collide::narrow::reduce_patch). The kept points
    // must still hold the slab level and carry its whole weight.
    let dt = 1.0 / 60.0;
    let mut world = World::new(WorldSettings {
        sleeping: false,
        dt,
        ..WorldSettings::default()
    })
    .unwrap();
    let sheet = tumble_collide::mesh::grid_mesh(1.0, 1.0, 40, 40).unwrap();
    let ground = world.add_body(&BodyDesc::fixed(mesh(sheet))).unwrap();
    let half = DVec3::new(0.2, 0.2, 0.05);
    let slab = world
        .add_body(
            &BodyDesc::dynamic(mesh(box_mesh(half).unwrap()))
                .at(DVec3::new(0.013, -0.021, half.z + 0.002))
                .with_mass(2.0),
        )
        .unwrap();
    for _ in 0..120 {
        world.step();
    }
    // The narrow phase's own points for the pair, before reduction.
    let shape = |id| world.colliders(id).unwrap()[0].shape.clone();
    let mut raw = Vec::new();
    tumble_collide::narrow::contact_shapes(
        &shape(slab),
        &world.pose(slab).unwrap(),
        &shape(ground),
        &world.pose(ground).unwrap(),
        world.settings().contact_margin,
        &mut raw,
    )
    .unwrap();
    assert!(
        raw.len() > 50,
        "only {} raw points: the patch is not large",
        raw.len()
    );
    let kept: Vec<_> = world
        .contacts()
        .iter()
        .filter(|c| c.body_a == slab || c.body_b == slab)
        .collect();
    assert!(
        (3..=tumble_collide::narrow::PATCH_MAX_POINTS).contains(&kept.len()),
        "{} points kept of {}",
        kept.len(),
        raw.len()
    );
    // Level, at rest, at its height, and the kept points carry the weight.
    let p = world.center_of_mass(slab).unwrap();
    assert!((p.z - half.z).abs() < 2e-3, "rests at z = {}", p.z);
    let up = (world.orientation(slab).unwrap() * DVec3::Z).z;
    assert!(up > 1.0 - 1e-6, "tilted: axis z {up}");
    let v = world.linear_velocity(slab).unwrap().length() + world.angular_velocity(slab).unwrap().length();
    assert!(v < 1e-3, "still moving: {v}");
    let carried: f64 = kept.iter().map(|c| c.normal_impulse).sum();
    let weight = 2.0 * 9.81 * dt;
    assert!(
        (carried - weight).abs() < 0.01 * weight,
        "carried {carried} N s of {weight}"
    );
}

/// A torus of 10,000 triangles flat on the ground and a second across it
/// (their tubes cross twice), in a world without sleeping.
fn stacked_fine_tori(settings: WorldSettings) -> (World, [tumble::world::BodyId; 3]) {
    let shape = mesh(torus_mesh(0.4, 0.1, 100, 50).unwrap());
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..settings
    })
    .unwrap();
    let ground = world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .unwrap();
    let lower = world
        .add_body(
            &BodyDesc::dynamic(shape.clone())
                .at(DVec3::new(0.0, 0.0, 0.1))
                .with_density(1000.0),
        )
        .unwrap();
    let across = tumble_collide::Pose::new(
        DVec3::new(0.4, 0.0, 0.301),
        tumble_collide::DQuat::from_rotation_z(0.3),
    )
    .unwrap();
    let upper = world
        .add_body(&BodyDesc::dynamic(shape).with_pose(across).with_density(1000.0))
        .unwrap();
    (world, [ground, lower, upper])
}

#[test]
fn two_fine_tori_stacked_on_the_ground_come_to_rest_on_points_they_keep() {
    // The lower torus rests on a ring of ~100 vertices and the crossings
    // touch at many triangle pairs, so every patch is reduced to a few
    // points. A choice made afresh each step flips between neighbouring
    // vertices as the bodies rock by microns; the points then lose their
    // warm-started impulses and the stack rocks for ever (kinetic energy
    // swinging between 1e-4 and 5e-2 J, step after step). Kept points
    // (reduce_patch's prior) let it come to rest.
    let (mut world, [ground, lower, upper]) = stacked_fine_tori(WorldSettings::default());
    let dt = world.settings().dt;
    let weight = (world.body(lower).unwrap().mass() + world.body(upper).unwrap().mass()) * 9.81;
    for step in 0..180 {
        let report = world.step();
        if step < 150 {
            continue;
        }
        assert_eq!(
            report.warm_started, report.contacts,
            "step {step}: points not kept from the step before"
        );
        let energy = world.kinetic_energy();
        assert!(energy < 1e-9, "step {step}: still moving, {energy} J");
        // The ground carries both tori.
        let carried: f64 = world
            .contacts()
            .iter()
            .filter(|c| c.body_a == ground || c.body_b == ground)
            .map(|c| c.normal_impulse)
            .sum();
        assert!(
            (carried - weight * dt).abs() < 1e-3 * weight * dt,
            "step {step}: the ground carries {} N of {weight}",
            carried / dt
        );
    }
}

/// The contacts of a collider pair of the last step, as the world reports them.
fn contacts_of(
    world: &World,
    a: tumble::world::BodyId,
    b: tumble::world::BodyId,
) -> Vec<tumble_collide::Contact> {
    world
        .contacts()
        .iter()
        .filter(|c| (c.body_a, c.body_b) == (a, b))
        .map(|c| c.contact)
        .collect()
}

#[test]
fn resting_mesh_pairs_re_evaluate_their_kept_points_and_miss_nothing_a_search_finds() {
    // Once the stacked tori rest, their three mesh pairs re-evaluate the
    // points they kept instead of searching their trees. Every point they
    // report is one a full search at the same poses finds, and a full
    // search finds nothing deeper than the deepest of them by more than
    // the reduction's depth slack plus the resting motion. With
    // resting_motion = 0 every step searches, and the stack rests in the
    // same place.
    let settings = WorldSettings::default();
    let (mut world, [_, lower, upper]) = stacked_fine_tori(settings.clone());
    let (mut searched, _) = stacked_fine_tori(WorldSettings {
        resting_motion: 0.0,
        ..settings
    });
    let margin = world.settings().contact_margin;
    let slack = tumble_collide::narrow::KEEP_DEPTH_SLACK + world.settings().resting_motion;
    let shape = |world: &World, id| world.colliders(id).unwrap()[0].shape.clone();
    for step in 0..200 {
        let report = world.step();
        assert_eq!(searched.step().revalidated_mesh_pairs, 0, "step {step}");
        if step < 150 {
            continue;
        }
        assert_eq!(report.revalidated_mesh_pairs, 3, "step {step}");
        let kept = contacts_of(&world, lower, upper);
        assert!(!kept.is_empty(), "step {step}: the tori do not touch");
        let mut found = Vec::new();
        tumble_collide::narrow::contact_shapes(
            &shape(&world, lower),
            &world.pose(lower).unwrap(),
            &shape(&world, upper),
            &world.pose(upper).unwrap(),
            margin + 1e-4,
            &mut found,
        )
        .unwrap();
        for c in &kept {
            assert!(
                found.iter().any(
                    |d| (d.point - c.point).length() <= 1e-12 && (d.distance - c.distance).abs() <= 1e-12
                ),
                "step {step}: {c:?} is not a point of the search"
            );
        }
        let deepest =
            |cs: &[tumble_collide::Contact]| cs.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
        assert!(
            deepest(&found) >= deepest(&kept) - slack,
            "step {step}: search {} m, kept {} m",
            deepest(&found),
            deepest(&kept)
        );
    }
    for id in [lower, upper] {
        let (p, q) = (
            world.center_of_mass(id).unwrap(),
            searched.center_of_mass(id).unwrap(),
        );
        assert!(
            (p - q).length() < 1e-4,
            "{id:?}: {p:?} against {q:?} when searched every step"
        );
    }
}

#[test]
fn resting_mesh_pairs_give_the_same_bits_after_a_snapshot_and_on_any_thread_count() {
    // Where each pair was last searched is state: a snapshot taken while
    // the tori rest (re-evaluating) continues as the original does, and so
    // does a world switched to another thread count.
    let (mut world, _) = stacked_fine_tori(WorldSettings {
        threads: 1,
        ..WorldSettings::default()
    });
    let (mut threaded, _) = stacked_fine_tori(WorldSettings {
        threads: 3,
        adaptive_threads: false,
        ..WorldSettings::default()
    });
    for _ in 0..160 {
        world.step();
        threaded.step();
    }
    assert_eq!(world.state_hash(), threaded.state_hash());
    let mut copy = World::from_snapshot(&world.snapshot()).unwrap();
    for step in 0..30 {
        let report = world.step();
        assert_eq!(report.revalidated_mesh_pairs, 3, "step {step}");
        assert_eq!(copy.step().revalidated_mesh_pairs, 3, "step {step}");
        threaded.step();
        assert_eq!(world.state_hash(), copy.state_hash(), "step {step}");
        assert_eq!(world.state_hash(), threaded.state_hash(), "step {step}");
    }
    // Another thread count alone (`tumble bench --paired` switches every
    // ten steps) keeps that memory: the pairs go on re-evaluating, with the
    // same bits. A new margin makes every pair search again.
    let settings = copy.settings().clone();
    copy.set_settings(WorldSettings {
        threads: 2,
        adaptive_threads: false,
        ..settings.clone()
    })
    .unwrap();
    assert_eq!(copy.step().revalidated_mesh_pairs, 3);
    world.step();
    assert_eq!(world.state_hash(), copy.state_hash());
    copy.set_settings(WorldSettings {
        mesh_contact_margin: settings.mesh_contact_margin * 1.5,
        ..copy.settings().clone()
    })
    .unwrap();
    assert_eq!(copy.step().revalidated_mesh_pairs, 0);
}

#[test]
fn a_resting_stack_struck_from_above_searches_again_and_holds() {
    // A third torus dropped onto the resting pair. Its approach announces
    // the blow (`resting_motion` counts how far a neighbour's approach can
    // push a body within the look-ahead), so the pairs of the torus it
    // strikes (with the lower torus and with the ground) search again in
    // the step it arrives, while the lower torus on the ground, which
    // nothing approaches, still re-evaluates (all three would, were the
    // approach not counted); and nothing sinks in deeper than when every
    // step searches.
    let run = |resting_motion: f64| {
        let (mut world, [_, lower, upper]) = stacked_fine_tori(WorldSettings {
            resting_motion,
            ..WorldSettings::default()
        });
        for _ in 0..150 {
            world.step();
        }
        let falling = world
            .add_body(
                &BodyDesc::dynamic(mesh(torus_mesh(0.4, 0.1, 100, 50).unwrap()))
                    .at(world.center_of_mass(upper).unwrap() + DVec3::new(-0.2, 0.05, 0.4))
                    .with_density(1000.0),
            )
            .unwrap();
        let (mut deepest, mut revalidated_at_impact) = (0.0f64, None);
        for _ in 0..90 {
            let report = world.step();
            if revalidated_at_impact.is_none() && !contacts_of(&world, upper, falling).is_empty() {
                revalidated_at_impact = Some(report.revalidated_mesh_pairs);
            }
            for (a, b) in [(lower, upper), (upper, falling), (lower, falling)] {
                deepest = deepest.max(penetration_between(&world, a, b));
            }
        }
        (
            deepest,
            revalidated_at_impact.expect("the falling torus never arrived"),
        )
    };
    let (resting, revalidated) = run(1e-5);
    let (always, _) = run(0.0);
    assert_eq!(revalidated, 1, "pairs re-evaluated in the step of the impact");
    assert!(
        resting <= always + 5e-4,
        "deepest overlap {resting} m re-evaluating, {always} m searching every step"
    );
}

#[test]
fn two_meshes_meet_within_the_mesh_margin_and_other_pairs_within_the_contact_margin() {
    // A mesh cube held 3 mm above a static mesh slab and a primitive cube 3
    // mm above a primitive slab, nothing moving: the mesh pair's contacts
    // come from `mesh_contact_margin` alone, the primitive pair's from
    // `contact_margin` alone, each whatever the other setting says.
    let gap = 0.003;
    let contacts = |as_meshes: bool, contact_margin: f64, mesh_contact_margin: f64| {
        let mut world = World::new(WorldSettings {
            gravity: DVec3::ZERO,
            sleeping: false,
            contact_margin,
            mesh_contact_margin,
            ..WorldSettings::default()
        })
        .unwrap();
        let shape = |half: DVec3| {
            if as_meshes {
                mesh(box_mesh(half).unwrap())
            } else {
                Shape::Cuboid(Cuboid::new(half).unwrap())
            }
        };
        world
            .add_body(&BodyDesc::fixed(shape(DVec3::new(1.0, 1.0, 0.05))))
            .unwrap();
        world
            .add_body(
                &BodyDesc::dynamic(shape(DVec3::splat(0.1)))
                    .at(DVec3::new(0.0, 0.0, 0.05 + gap + 0.1))
                    .with_mass(1.0),
            )
            .unwrap();
        world.step().contacts
    };
    assert!(
        contacts(true, 0.001, 0.005) > 0,
        "mesh pair within its 5 mm margin"
    );
    assert_eq!(contacts(true, 0.01, 0.002), 0, "mesh pair beyond its 2 mm margin");
    assert!(
        contacts(false, 0.005, 0.001) > 0,
        "primitive pair within its 5 mm margin"
    );
    assert_eq!(
        contacts(false, 0.002, 0.01),
        0,
        "primitive pair beyond its 2 mm margin"
    );
}

#[test]
fn torus_chain_links_whipping_past_each_other_stay_within_one_percent() {
    // shared/scenes.md chain at its standard step (dt 1/60, 8 x 2), its
    // first 200 steps: the free end whips past the vertical at 20-30 m/s and
    // the last links slide over each other by 10-12 cm a step along the
    // inside of a ring curved at 1 / 0.8 m, where the surface rises 6-9 mm
    // out of a step-start contact plane. The chain is chaotic, so eight
    // starts that differ by 1e-5 m (examples/ensemble_depth): the median of
    // their deepest overlaps stays under 1 % of the tube radius, 2 mm
    // (2.35 mm when sliding pairs were not collided again at the step's
    // end, `end_overlap::SLIDING_SLACK`; 1.5 mm with).
    let mut worst = Vec::new();
    for k in 0..8 {
        let mut scene = tumble::scenes::chain();
        for (i, body) in scene.bodies.iter_mut().enumerate() {
            body.pose.position.x += 1e-5 * k as f64 * ((i % 3) as f64 - 1.0);
        }
        let (mut world, _) = scene.build().unwrap();
        let mut deepest: f64 = 0.0;
        for _ in 0..200 {
            deepest = deepest.max(world.step().max_penetration);
        }
        worst.push(deepest);
    }
    worst.sort_by(f64::total_cmp);
    let median = 0.5 * (worst[3] + worst[4]);
    assert!(
        median < 0.002,
        "median of the runs' deepest overlaps {median} m: {worst:?}"
    );
}
