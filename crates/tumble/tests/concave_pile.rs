//! The concave pile (issue 15's standard scene): its meshes are what
//! docs/scenes.md says (closed, concave, the blob's triangle count), the
//! bin holds, and a small version of the pile settles in it.

mod common;

use common::leaning_bar::{assert_spun_bar_is_pushed_back_out, bar_depth, leaning_bar};
use common::weightless_world;
use std::f64::consts::FRAC_PI_2;
use tumble::scenes::{self, concave_pile_escaped, CONCAVE_KINDS};
use tumble::world::{BodyDesc, BodyId, World, WorldSettings};
use tumble::world::{END_OVERLAP_SLACK, STRUCK_MARGINS};
use tumble_collide::mesh::box_mesh;
use tumble_collide::mesh::torus_mesh;
use tumble_collide::narrow::contact_shapes;
use tumble_collide::shape::ConvexHull;
use tumble_collide::shape::Sphere;
use tumble_collide::shape::{MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

#[test]
fn every_kind_is_a_closed_concave_solid_of_the_stated_size() {
    let meshes = scenes::concave_kind_meshes();
    assert_eq!(meshes.len(), CONCAVE_KINDS.len());
    for (kind, mesh) in CONCAVE_KINDS.iter().zip(&meshes) {
        // Closed and outward: a positive volume; concave: clearly less
        // than its convex hull's (a convex body would fill its hull).
        let volume = mesh.signed_volume();
        let hull = ConvexHull::from_points(mesh.vertices())
            .unwrap()
            .surface_mesh()
            .unwrap()
            .signed_volume();
        assert!(volume > 0.0, "{kind}: volume {volume}");
        assert!(
            volume < 0.9 * hull,
            "{kind}: volume {volume} of a hull of {hull}: not concave"
        );
        // Fits the 0.3 m drop grid whatever its turn: two neighbours, each
        // within 0.15 m of its grid point, cannot overlap.
        let reach = mesh.vertices().iter().map(|v| v.length()).fold(0.0, f64::max);
        assert!(
            reach <= 0.15 + 1e-12,
            "{kind}: reaches {reach} m from its frame's origin"
        );
    }
    let blob = &meshes[4];
    assert!(
        (2000..=5000).contains(&blob.triangles().len()),
        "blob: {} triangles",
        blob.triangles().len()
    );
    // The cup: a 0.09 m x 0.18 m cylinder less its 0.078 m x 0.168 m hollow.
    let cup = meshes[1].signed_volume();
    let pi = std::f64::consts::PI;
    let ring = |r: f64| r * (pi / 24.0).sin() * 24.0 * r * (pi / 24.0).cos(); // area of the 24-gon
    let exact = ring(0.09) * 0.18 - ring(0.078) * 0.168;
    assert!(
        (cup - exact).abs() < 1e-12,
        "cup volume {cup}, 24-gon prism difference {exact}"
    );
}

#[test]
fn the_bin_is_a_closed_box_with_a_cavity() {
    let bin = scenes::concave_bin();
    let (w, h) = (
        scenes::CONCAVE_BIN_INNER_HALF_WIDTH,
        scenes::CONCAVE_BIN_WALL_HEIGHT,
    );
    let outer = 2.0 * (w + 0.1);
    let exact = outer * outer * (h + 0.1) - (2.0 * w) * (2.0 * w) * h;
    assert!(
        (bin.signed_volume() - exact).abs() < 1e-9,
        "bin volume {}",
        bin.signed_volume()
    );
    assert_eq!(bin.triangles().len(), 28);
}

#[test]
fn a_small_concave_pile_settles_inside_the_bin() {
    // Ten bodies (two of each kind) for 2 s: none escapes, none sinks into
    // another by more than 2 cm, and they come down to rest on the floor.
    let scene = scenes::concave_pile(10);
    let (mut world, ids) = scene.build().unwrap();
    let mut deepest: f64 = 0.0;
    for _ in 0..120 {
        deepest = deepest.max(world.step().max_penetration);
    }
    let centres: Vec<DVec3> = ids[1..]
        .iter()
        .map(|&id| world.center_of_mass(id).unwrap())
        .collect();
    assert_eq!(concave_pile_escaped(&centres), 0, "{centres:?}");
    assert!(deepest < 0.02, "deepest overlap {deepest} m");
    assert!(centres.iter().all(|c| c.z < 0.3), "not down: {centres:?}");
    let ke = world.kinetic_energy();
    let mass: f64 = ids[1..].iter().map(|&id| world.body(id).unwrap().mass()).sum();
    assert!(ke < 0.01 * mass, "still moving: {ke} J for {mass} kg");
}

#[test]
fn a_layer_of_concave_bodies_comes_to_rest_and_stays_still() {
    // 25 bodies (five of each kind) dropped onto the bin's floor: by 5 s
    // they lie still, and over the next second none creeps by more than a
    // micron. Static friction is held at the position level (patch
    // anchors): without it, what the velocity passes left unsolved kept a
    // few bodies rocking and creeping, 1.4e-5 J still moving at 5 s and
    // 6.4e-6 J at 6 s.
    let scene = scenes::concave_pile(25);
    let (mut world, ids) = scene.build().unwrap();
    let mut deepest: f64 = 0.0;
    let centres =
        |w: &World| -> Vec<DVec3> { ids[1..].iter().map(|&id| w.center_of_mass(id).unwrap()).collect() };
    for _ in 0..300 {
        deepest = deepest.max(world.step().max_penetration);
    }
    let at_rest = centres(&world);
    let ke_5s = world.kinetic_energy();
    for _ in 0..60 {
        deepest = deepest.max(world.step().max_penetration);
    }
    let now = centres(&world);
    assert_eq!(concave_pile_escaped(&now), 0, "{now:?}");
    assert!(deepest < 0.002, "deepest overlap {deepest} m");
    assert!(ke_5s < 1e-7, "still moving at 5 s: {ke_5s} J");
    let crept = now
        .iter()
        .zip(&at_rest)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    assert!(crept < 1e-6, "a body crept {crept} m from 5 s to 6 s");
    assert!(
        world.kinetic_energy() < 1e-8,
        "still moving at 6 s: {} J",
        world.kinetic_energy()
    );
}

/// The pile of `concave_pile(100)`, every body's start moved by up to 2
/// mm along each axis (`seed`; 0: not moved), stepped for 5 s and then
/// through the sixth second with `resting_motion` (m): how many bodies
/// moved faster than 1 mm/s in that second, how many mesh pairs
/// re-evaluated their kept points in it, and how many bodies escaped.
fn pile_in_its_sixth_second(seed: u64, resting_motion: f64) -> (usize, usize, usize) {
    use tumble_testkit::RandomSource;
    let mut scene = scenes::concave_pile(100);
    scene.settings.resting_motion = resting_motion;
    let mut rng = tumble_testkit::SplitMix64(seed);
    if seed != 0 {
        for body in scene.bodies.iter_mut().skip(1) {
            body.pose.position +=
                DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.002;
        }
    }
    let (mut world, ids) = scene.build().unwrap();
    for _ in 0..300 {
        world.step();
    }
    let mut fastest = vec![0.0f64; ids.len() - 1];
    let mut revalidated = 0;
    for _ in 0..60 {
        revalidated += world.step().revalidated_mesh_pairs;
        for (most, &id) in fastest.iter_mut().zip(&ids[1..]) {
            *most = most.max(world.linear_velocity(id).unwrap().length());
        }
    }
    let centres: Vec<DVec3> = ids[1..]
        .iter()
        .map(|&id| world.center_of_mass(id).unwrap())
        .collect();
    let moving = fastest.iter().filter(|&&v| v > 1e-3).count();
    (moving, revalidated, concave_pile_escaped(&centres))
}

#[test]
fn four_layers_of_concave_bodies_come_to_rest_and_stay_still() {
    // 100 bodies, four layers of the spawn grid, stacked on each other in
    // the bin: still by 5 s and through the next second. A mesh pair
    // that has moved less than `resting_motion` since its last search
    // re-evaluates the points it kept instead of searching; each time
    // such a pair searches again its contact set changes a little and the
    // load shifts. With 10 um of motion allowed the pile kept shifting
    // like that; with the half micron of the default only pairs that are
    // really still keep their points.
    //
    // Which way a pile of 100 tumbling bodies comes down is chaotic, and
    // one start alone says little about how still such piles lie (the
    // pile's own start had 5e-7 J in its sixth second, and 4.7e-5 and
    // 1.6e-4 J with two versions of the corner contacts, each time one
    // body twitching once at a few mm/s). So
    // the test counts the bodies still moving faster than 1 mm/s in the
    // sixth second over 21 starts, the pile's own and 20 moved by up to
    // 2 mm, and takes the median. When the test was written, over its
    // first seven starts: 0, 0, 0, 1, 11, 12 and 31 bodies with the
    // default, and 5, 10, 12, 12, 12, 20 and 35 with 10 um allowed. The
    // starts with many are those where a bracket lying across another's
    // edges rocks on them at a few cm/s and does not soon stop
    // (docs/pipeline.md, "Measured and not kept", 2026-12-05, third
    // session), shaking its neighbours.
    //
    // Why 21 starts (2026-12-06): the median of seven did not separate
    // a solver that leaves piles restless from one that does not. On 21
    // starts main had a median of 1 (seven starts with none, six with
    // one, the most nine); three or four velocity passes a sub-step
    // instead of two gave 2; the warm-start remedies of docs/pipeline.md,
    // "Warm starts that add energy", measured on 21 starts gave 5 to 8;
    // another had a median of 3 over the first seven, which the old
    // bound of 4 let through.
    let mut moving = Vec::new();
    for seed in 0..21 {
        let (count, revalidated, escaped) =
            pile_in_its_sixth_second(seed, WorldSettings::default().resting_motion);
        assert_eq!(escaped, 0, "start {seed}: {escaped} bodies left the bin");
        // The still pairs did keep their points (else every pair searched).
        assert!(
            revalidated > 0,
            "start {seed}: no pair re-evaluated its kept points"
        );
        moving.push(count);
    }
    let mut sorted = moving.clone();
    sorted.sort_unstable();
    let median = sorted[sorted.len() / 2];
    assert!(
        median <= 3,
        "a median of {median} bodies moving faster than 1 mm/s between 5 s and 6 s ({moving:?} by start)"
    );
}

#[test]
fn resting_mesh_pairs_recall_their_walks_and_step_to_the_same_bits_as_without() {
    // The same small pile twice: one world keeps its mesh pairs' walks from
    // step to step; the other is cloned before every step, and a clone
    // starts with no memory, so each of its steps walks every pair anew.
    // A remembered walk may change the cost only: same bits at every step.
    let scene = scenes::concave_pile(10);
    let (mut kept, _) = scene.build().unwrap();
    let mut fresh = kept.clone();
    let mut recalled = 0;
    for step in 0..180 {
        let report = kept.step();
        fresh = fresh.clone();
        let fresh_report = fresh.step();
        assert_eq!(fresh_report.recalled_mesh_pairs, 0);
        assert_eq!(kept.state_hash(), fresh.state_hash(), "step {step}");
        if step >= 120 {
            recalled += report.recalled_mesh_pairs;
        }
    }
    // The settling pile's pairs did recall their walks (else this compared
    // two runs of the same code path).
    assert!(recalled >= 60, "{recalled} recalled pairs over the last 60 steps");
}

#[test]
fn a_small_concave_pile_with_remembered_walks_is_the_same_bits_on_1_2_3_and_8_threads() {
    // The memories are kept per pair and rebuilt in pair order at the join
    // of the threads' chunks: no thread count may change a bit.
    let mut hashes = Vec::new();
    for threads in [1, 2, 3, 8] {
        let mut scene = scenes::concave_pile(10);
        scene.settings.threads = threads;
        scene.settings.adaptive_threads = false;
        let (mut world, _) = scene.build().unwrap();
        let mut recalled = 0;
        for _ in 0..180 {
            recalled += world.step().recalled_mesh_pairs;
        }
        assert!(recalled > 0, "{threads} threads: no pair recalled its walk");
        hashes.push((threads, world.state_hash()));
    }
    assert!(hashes.iter().all(|h| h.1 == hashes[0].1), "{hashes:?}");
}

#[test]
fn landing_bodies_are_pushed_out_of_what_their_speculative_contacts_missed() {
    // Fifty bodies in two layers of 25, the second landing on the first:
    // tumbling jacks and cups meet each other with features that were not
    // the closest ones at the step's start (a corner swinging in sideways).
    // Collided again at the end of each step and pushed apart, no two
    // bodies ever overlap by more than the contact margin at a step's start;
    // with the continuous stage off (its sweeps too, which never sweep one
    // dynamic body against another) the same landing sinks bodies deeper
    // than the margin into each other (centimetres before corners were
    // seen against edges and corners, `triangle::tri_vertex_edge`; 9.5 mm
    // since), which shows the bound is the stage's doing and not the
    // scene's. (Overlaps with the static bin, which the
    // stage also takes out for slow bodies, are left out of the count.)
    let deepest = |continuous: bool| {
        let mut scene = scenes::concave_pile(50);
        scene.settings.continuous = continuous;
        let margin = scene.settings.contact_margin;
        let (mut world, ids) = scene.build().unwrap();
        let bin = ids[0];
        let mut deepest: f64 = 0.0;
        for _ in 0..150 {
            world.step();
            for c in world.contacts() {
                if c.body_a != bin && c.body_b != bin {
                    deepest = deepest.max(-c.contact.distance);
                }
            }
        }
        (deepest, margin)
    };
    let (with, margin) = deepest(true);
    let (without, _) = deepest(false);
    assert!(
        with <= margin,
        "deepest overlap {with} m with the end-overlap stage"
    );
    assert!(
        without > margin,
        "deepest overlap {without} m without it: the scene no longer tests the stage"
    );
}

#[test]
fn a_mesh_knocked_into_another_by_a_third_within_the_step_is_pushed_back_out() {
    // Three mesh cubes (0.2 m) in a row without gravity: A and B at rest 4 mm
    // apart (a broad-phase pair), C coming at B at 6 m/s from 1 cm away.
    // Within the first step C strikes B, and B crosses the gap to A at about
    // 3 m/s: A and B had no contact (B was at rest, 4 mm is beyond the mesh
    // margin), so nothing stops B until the step ends. Their closing over the step, not their
    // velocities at its start, is what tells the end-overlap stage to
    // collide them again and push them apart; without that B ended the step
    // 4.2 cm inside A.
    let (mut world, _, [a, b]) = knocked_row(false);
    world.step();
    let (xa, xb) = (
        world.center_of_mass(a).unwrap().x,
        world.center_of_mass(b).unwrap().x,
    );
    assert!(
        world.linear_velocity(b).unwrap().x < -1.0,
        "B was not knocked towards A: the test no longer tests the stage"
    );
    let overlap = 2.0 * KNOCKED_HALF - (xb - xa);
    let margin = world.settings().contact_margin;
    assert!(overlap <= margin, "B ended the step {overlap} m inside A");
}

#[test]
fn a_body_knocked_against_a_wall_is_pushed_out_of_both_its_neighbours() {
    // The knock of the test above with a static wall W behind A: A rests
    // against W, B 4 mm from A, C comes at B at 6 m/s from 1 cm away, all
    // mesh cubes (0.2 m) without gravity. Within the first step B crosses
    // the gap and ends it centimetres inside A. Pushing A and B apart
    // pushes A into W, and pushing A out of W pushes it back into B: a
    // body squeezed between two others went back and forth, pass after
    // pass (B ended 16 mm inside A), unless the other pairs of the bodies
    // being pushed apart hold them where they are meanwhile (A against W,
    // B against C, whose points are within the contact margin), so that
    // the push moves B and C instead. With guards that only held pairs
    // already touching, A ended 4.7 mm inside the wall.
    let (mut world, wall, [a, b]) = knocked_row(true);
    let wall = wall.unwrap();
    let allowed = world.settings().allowed_penetration;
    // Their closest contact at the world's poses (m).
    let gap = |world: &World, p: BodyId, q: BodyId| {
        let mut out = Vec::new();
        let shape = |id: BodyId| (&world.colliders(id).unwrap()[0].shape, world.pose(id).unwrap());
        let ((sp, pp), (sq, pq)) = (shape(p), shape(q));
        contact_shapes(sp, &pp, sq, &pq, 0.1, &mut out).unwrap();
        out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min)
    };
    world.step();
    assert!(
        world.linear_velocity(b).unwrap().x < -1.0,
        "B was not knocked towards A: the test no longer tests the stage"
    );
    for (name, p, q) in [("A in the wall", wall, a), ("B in A", a, b)] {
        let overlap = -gap(&world, p, q);
        assert!(
            overlap <= (1.0 + END_OVERLAP_SLACK) * allowed,
            "{name}: {overlap} m after the step"
        );
    }
}

#[test]
fn a_ring_jerked_into_a_ring_it_was_not_touching_is_pushed_back_out() {
    // Two interlocked rings as two links of the torus chain, without
    // gravity: A above, its lower tube through B's hole, 4 mm above B's
    // upper tube (beyond the mesh margin, so the pair has no speculative
    // contact). Two kinematic balls under A's lower flanks lift it at
    // 0.9 m/s from the first sub-step on, which the velocities at the
    // step's start (all zero but the balls') do not announce: A's tube
    // rises about 15 mm into B's within the step. The centres move apart
    // (no landing along their line) and the pair had no contact at all;
    // what tells the end-overlap stage to collide it again is that A's
    // velocity changed by 3 contact margins a step, more than the
    // STRUCK_MARGINS that make a body "struck".
    let ring = Shape::Mesh(MeshShape::new(torus_mesh(1.0, 0.2, 32, 12).unwrap()).unwrap());
    let ring_a = Pose::new(DVec3::ZERO, DQuat::from_rotation_x(FRAC_PI_2)).unwrap();
    let ring_b_at = |z: f64| Pose::new(DVec3::new(0.0, 0.0, z), DQuat::from_rotation_y(FRAC_PI_2)).unwrap();
    // The meshes' gap with B's centre at z (m): their closest contact.
    let gap = |pose_a: &Pose, pose_b: &Pose| {
        let mut out = Vec::new();
        contact_shapes(&ring, pose_a, &ring, pose_b, 0.1, &mut out).unwrap();
        out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min)
    };
    // Tube centre lines 0.4 m apart touch; B placed so the meshes are 4 mm apart.
    let z0 = -1.6;
    let z = z0 + (0.004 - gap(&ring_a, &ring_b_at(z0)));
    let start_gap = gap(&ring_a, &ring_b_at(z));
    assert!((start_gap - 0.004).abs() < 1e-4, "start gap {start_gap}");
    // One step of the scene, with the continuous stage (and the
    // end-overlap stage in it) on or off: A's lift over the step at its
    // end velocity (m), and how deep A ends in B (m).
    let step = |continuous: bool| {
        let mut world = weightless_world(continuous);
        let ring_desc = |pose: Pose| {
            BodyDesc::dynamic(ring.clone())
                .with_pose(pose)
                .with_mass(1.0)
                .with_material(0.0, 0.0)
        };
        let a = world.add_body(&ring_desc(ring_a)).unwrap();
        let b = world.add_body(&ring_desc(ring_b_at(z))).unwrap();
        // Each ball touches A's outer surface below its flank at 45 degrees.
        for side in [-1.0, 1.0] {
            let flank = DVec3::new(side, 0.0, -1.0).normalize();
            let ball = BodyDesc::kinematic(Shape::Sphere(Sphere::new(0.1).unwrap()))
                .at(flank * (1.2 + 0.1))
                .with_material(0.0, 0.0)
                .with_velocity(DVec3::new(0.0, 0.0, 0.9), DVec3::ZERO);
            world.add_body(&ball).unwrap();
        }
        assert!(
            start_gap > world.settings().mesh_contact_margin,
            "the rings start within the mesh margin: the test no longer tests an unseen pair"
        );
        world.step();
        let lift = world.linear_velocity(a).unwrap().z * world.settings().dt;
        let (pose_a, pose_b) = (world.pose(a).unwrap(), world.pose(b).unwrap());
        (lift, -gap(&pose_a, &pose_b))
    };
    let settings = WorldSettings::default();
    let (margin, allowed) = (settings.contact_margin, settings.allowed_penetration);
    let bound = (1.0 + END_OVERLAP_SLACK) * allowed;
    // The jerk as the solver gives it (the end-overlap stage's plastic
    // impulse would slow A), and the overlap it leaves without the stage.
    let (lift, unchecked) = step(false);
    assert!(
        lift > STRUCK_MARGINS * margin && lift < 2.0 * STRUCK_MARGINS * margin,
        "A was lifted {lift} m a step: the test no longer tests a jerk of a few margins"
    );
    assert!(
        unchecked > 2.0 * bound,
        "A ended {unchecked} m inside B without the stage: the test no longer tests it"
    );
    let (_, overlap) = step(true);
    assert!(overlap <= bound, "A ended the step {overlap} m inside B");
}

#[test]
fn a_mesh_knocked_a_few_mesh_margins_into_a_wall_is_pushed_back_out() {
    // A mesh cube A at rest 2.2 mm from a static mesh wall (beyond the mesh
    // margin: no speculative contact), a second cube C touching A's far
    // side and coming at it at 0.55 m/s, no gravity. Within the step C
    // pushes A about 4.6 mm towards the wall, more than the mesh margin
    // that A's contacts with the wall are found with but less than the
    // contact margin: A ends 2.4 mm in the wall without the end-overlap
    // stage. A mesh pair's thresholds (moved, closed in) count in its own
    // margin; when they counted in the contact margin (5 mm, not 2),
    // the stage left this pair alone, and in the concave pile a torus
    // rocking on another, which found one of its two contact regions each
    // step, swung the other 4.8 mm deep.
    let step = |continuous: bool| {
        let mut world = weightless_world(continuous);
        let half = KNOCKED_HALF;
        let gap = 0.0022;
        let wall = BodyDesc::fixed(box_shape(DVec3::new(0.2, 0.5, 0.5))).at(DVec3::new(-0.2, 0.0, 0.0));
        world.add_body(&wall).unwrap();
        let a = world.add_body(&row_cube(half + gap, 0.0)).unwrap();
        world
            .add_body(&row_cube(3.0 * half + gap + 0.0005, -0.55))
            .unwrap();
        let settings = world.settings().clone();
        assert!(
            gap > settings.mesh_contact_margin,
            "A starts within the mesh margin of the wall"
        );
        world.step();
        let x = world.center_of_mass(a).unwrap().x;
        // How far A moved, and how deep it ends in the wall (m).
        (half + gap - x, half - x, settings)
    };
    let (travel, unchecked, settings) = step(false);
    let bound = (1.0 + END_OVERLAP_SLACK) * settings.allowed_penetration;
    assert!(
        travel > settings.mesh_contact_margin && travel < settings.contact_margin,
        "A moved {travel} m in the step: the test no longer tests a move of a few mesh margins"
    );
    assert!(
        unchecked > bound,
        "A ended {unchecked} m in the wall without the stage: the test no longer tests it"
    );
    let (_, overlap, _) = step(true);
    assert!(overlap <= bound, "A ended the step {overlap} m in the wall");
}

/// Half the edge of [`knocked_row`]'s cubes (m).
const KNOCKED_HALF: f64 = 0.1;

/// A frictionless mesh cube of edge `2 KNOCKED_HALF` (1000 kg/m^3) centred
/// at `x` on the x axis, moving along it at `v` (m/s).
fn row_cube(x: f64, v: f64) -> BodyDesc {
    BodyDesc::dynamic(box_shape(DVec3::splat(KNOCKED_HALF)))
        .at(DVec3::new(x, 0.0, 0.0))
        .with_density(1000.0)
        .with_material(0.0, 0.0)
        .with_velocity(DVec3::new(v, 0.0, 0.0), DVec3::ZERO)
}

/// Three mesh cubes in a row along x without gravity: A at the origin and
/// B 4 mm from it at rest, C coming at B at 6 m/s from 1 cm away; with
/// `wall`, a static mesh slab touching A's far side. The wall, A and B.
fn knocked_row(wall: bool) -> (World, Option<BodyId>, [BodyId; 2]) {
    let mut world = weightless_world(true);
    let half = KNOCKED_HALF;
    let slab = BodyDesc::fixed(box_shape(DVec3::new(0.2, 0.5, 0.5))).at(DVec3::new(-half - 0.2, 0.0, 0.0));
    let wall = wall.then(|| world.add_body(&slab).unwrap());
    let a = world.add_body(&row_cube(0.0, 0.0)).unwrap();
    let b = world.add_body(&row_cube(2.0 * half + 0.004, 0.0)).unwrap();
    world.add_body(&row_cube(4.0 * half + 0.014, -6.0)).unwrap();
    (world, wall, [a, b])
}

/// A closed triangle-mesh box of half extents `half` (m).
fn box_shape(half: DVec3) -> Shape {
    Shape::Mesh(MeshShape::new(box_mesh(half).unwrap()).unwrap())
}

/// The bar of [`leaning_bar`] against a thick static wall, its far end
/// struck towards the wall by a mesh cube at `speed`, mostly across the
/// line of the two centres (which is how the narrow phase's margins read a
/// coming blow): the far end swings into the wall within the step, where
/// the bar's speculative contacts with the wall were only at its near end.
/// Gives the bar's deepest corner behind the wall's face over three steps
/// (m), its spin about z after the first (rad/s) and the contact margin (m).
fn bar_swung_into_a_wall(speed: f64, continuous: bool) -> (f64, f64, f64) {
    let wall = BodyDesc::fixed(box_shape(DVec3::new(0.1, 1.0, 1.0))).at(DVec3::new(-0.1, 0.0, 0.0));
    let (mut world, bar, _, far_end_x) = leaning_bar(&wall, &box_shape, continuous);
    world
        .add_body(
            &BodyDesc::dynamic(box_shape(DVec3::splat(0.05)))
                .at(DVec3::new(far_end_x + 0.055, 0.26, 0.0))
                .with_density(1000.0)
                .with_material(0.0, 0.0)
                .with_velocity(DVec3::new(-speed, 0.0, 0.0), DVec3::ZERO),
        )
        .unwrap();
    let mut deepest = f64::NEG_INFINITY;
    let mut spin = 0.0;
    for step in 0..3 {
        world.step();
        deepest = deepest.max(bar_depth(&world, bar));
        if step == 0 {
            spin = world.angular_velocity(bar).unwrap().z;
        }
    }
    (deepest, spin, world.settings().contact_margin)
}

#[test]
fn a_mesh_spun_against_a_wall_it_touches_is_pushed_back_out() {
    // The bar is fast (it moves more than half its thickness in a step),
    // and the sweeps leave an overlap shallower than half a thick wall to
    // the push-out; it began the step touching the wall, so the end-overlap
    // stage takes it out (before it did so, the bar ended 27-30 mm inside).
    for speed in [12.0, 15.0, 20.0] {
        let (with, _, margin) = bar_swung_into_a_wall(speed, true);
        let (without, spin, _) = bar_swung_into_a_wall(speed, false);
        assert!(
            spin > 1.0,
            "{speed} m/s: the bar was not swung towards the wall ({spin} rad/s about z)"
        );
        assert!(
            without > margin,
            "{speed} m/s: {without} m deep without the continuous stage: the test no longer tests it"
        );
        assert!(
            with <= margin,
            "{speed} m/s: the bar ended {with} m inside the wall"
        );
    }
}

#[test]
fn a_mesh_spun_round_within_the_step_into_a_body_whose_centre_it_does_not_close_in_on_is_pushed_back_out() {
    // The bar of `leaning_bar` as a mesh, spun round into a mesh slab within
    // one step. Its velocities changed by far more than four contact
    // margins' worth over the step, so the end-overlap stage collides the
    // pair again and takes the overlap out (before, it left the pair alone:
    // 20-70 mm deep at these spins, as without the stage).
    assert_spun_bar_is_pushed_back_out(&box_shape);
}
