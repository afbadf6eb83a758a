//! Determinism and snapshots: the same scene stepped twice gives the same
//! bits; a snapshot restored (in memory, through the binary form, through a
//! file, through JSON) continues to the very bits the original reaches; a
//! snapshot of another format version is refused, not misread.

use tumble::collide::mass::MassProperties;
use tumble::collide::mesh::box_mesh;
use tumble::collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use tumble::collide::{DMat3, DQuat, DVec3, Pose};
use tumble::scenes;
use tumble::world::{
    BodyDesc, BodyId, MassDesc, ShapeDesc, Snapshot, SnapshotError, World, WorldSettings,
    SNAPSHOT_FORMAT_VERSION, SNAPSHOT_MAGIC,
};

/// Every number of the dynamic state of every live body, in slot order:
/// x, q, P, L (13 f64) as raw bits.
fn state_bits(world: &World) -> Vec<u64> {
    let mut out = Vec::new();
    for id in world.body_ids() {
        let s = *world.body(id).unwrap().state();
        for v in [s.position, s.linear_momentum, s.angular_momentum] {
            out.extend(v.to_array().map(f64::to_bits));
        }
        out.extend(s.orientation.to_array().map(f64::to_bits));
    }
    out
}

fn run(world: &mut World, steps: usize) {
    for _ in 0..steps {
        let report = world.step();
        assert!(report.quarantined.is_empty(), "{:?}", report.quarantined);
    }
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-snapshots-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The state bits of the pile(100) after this many steps at the scene's dt
/// (1/60 s), hashed by `World::state_hash`. It changes whenever the physics does
/// (solver, contacts, integration, scene): then check that the change is
/// intended and update it. Determinism itself is checked by two runs below,
/// independently of this constant.
const GOLDEN_PILE_STEPS: usize = 240;
const GOLDEN_PILE_HASH: u64 = 0xbe56af350e91ff53;

#[test]
fn same_scene_twice_gives_identical_bits_and_the_golden_hash() {
    let scene = scenes::pile(1);
    let hashes: Vec<u64> = (0..2)
        .map(|_| {
            let (mut world, _) = scene.build().unwrap();
            run(&mut world, GOLDEN_PILE_STEPS);
            world.state_hash()
        })
        .collect();
    assert_eq!(hashes[0], hashes[1], "two runs of the same scene differ");
    assert_eq!(
        hashes[0], GOLDEN_PILE_HASH,
        "pile(100) after {GOLDEN_PILE_STEPS} steps hashes to {:#018x}: the physics changed; \
         if that is intended, update GOLDEN_PILE_HASH",
        hashes[0]
    );
}

#[test]
fn pile_restored_from_a_snapshot_continues_bit_for_bit() {
    let (mut world, _) = scenes::pile(1).build().unwrap();
    run(&mut world, 90);
    let snap = world.snapshot();
    assert_eq!(snap.format_version, SNAPSHOT_FORMAT_VERSION);
    assert_eq!(snap.body_count(), 105);
    let bytes = snap.to_bytes();
    let dir = temp_dir("pile");
    let (bin_path, json_path) = (dir.join("pile.snap"), dir.join("pile.json"));
    snap.save(&bin_path).unwrap();
    snap.save(&json_path).unwrap();
    assert_eq!(
        std::fs::read(&bin_path).unwrap(),
        bytes,
        "the file holds the binary form"
    );

    run(&mut world, 90);
    let expected = state_bits(&world);
    let expected_snapshot = world.snapshot();

    let copies = [
        ("in memory", snap.clone()),
        ("bytes", Snapshot::from_bytes(&bytes).unwrap()),
        ("binary file", Snapshot::load(&bin_path).unwrap()),
        ("json file", Snapshot::load(&json_path).unwrap()),
    ];
    for (how, copy) in copies {
        assert!(copy == snap, "{how}: the snapshot does not round-trip exactly");
        let mut restored = World::from_snapshot(&copy).unwrap();
        assert_eq!(restored.time(), snap.time());
        assert_eq!(restored.step_count(), 90);
        run(&mut restored, 90);
        assert_eq!(state_bits(&restored), expected, "{how}: trajectories diverge");
        // Everything else that steers the future (contact cache, broad-phase
        // boxes, sleep state) agrees as well.
        assert!(
            restored.snapshot() == expected_snapshot,
            "{how}: full state differs"
        );
    }
    // restore() into a world that has run on.
    let mut w = world.clone();
    w.restore(&snap).unwrap();
    run(&mut w, 90);
    assert_eq!(state_bits(&w), expected);
    std::fs::remove_dir_all(&dir).ok();

    // Compactness: bytes per body against the raw state (13 f64), with and
    // without the warm-start cache (one entry per contact point).
    let per_body = bytes.len() as f64 / snap.body_count() as f64;
    let mut no_cache = World::from_snapshot(&snap).unwrap();
    no_cache.clear_contact_cache();
    let bodies_only = no_cache.snapshot().to_bytes().len() as f64 / snap.body_count() as f64;
    println!(
        "pile(100) snapshot: {} bytes for {} bodies: {per_body:.0} bytes/body, {bodies_only:.0} without the \
         contact cache (raw x, q, P, L: 104 bytes/body); JSON {} bytes",
        bytes.len(),
        snap.body_count(),
        snap.to_json().len()
    );
    assert!(bodies_only < 3.0 * 104.0, "{bodies_only} bytes per body");
}

#[test]
fn chain_snapshot_stores_the_shared_mesh_once_and_continues_exactly() {
    let (mut world, _) = scenes::chain().build().unwrap();
    run(&mut world, 30);
    let snap = world.snapshot();
    let bytes = snap.to_bytes();
    // 21 links share one 384-vertex, 768-triangle mesh: stored once.
    assert_eq!(snap.mesh_count(), 1);
    println!("chain(21 links) snapshot: {} bytes", bytes.len());
    run(&mut world, 30);
    let mut restored = World::from_snapshot(&Snapshot::from_bytes(&bytes).unwrap()).unwrap();
    run(&mut restored, 30);
    assert_eq!(state_bits(&restored), state_bits(&world));
    assert!(restored.snapshot() == world.snapshot(), "full state differs");
}

/// A world with every kind of body and shape, a removed body (free slot,
/// bumped generation), pending forces, a kinematic body and sleeping bodies.
fn assorted_world() -> (World, Vec<BodyId>, BodyId) {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let hull = ConvexHull::from_points(&[
        DVec3::new(0.0, 0.0, 0.3),
        DVec3::new(0.3, 0.0, -0.1),
        DVec3::new(-0.2, 0.25, -0.1),
        DVec3::new(-0.2, -0.25, -0.1),
    ])
    .unwrap();
    let cube_mesh = MeshShape::new(box_mesh(DVec3::splat(0.2)).unwrap()).unwrap();
    let tilt = DQuat::from_rotation_x(0.3) * DQuat::from_rotation_z(0.2);
    let descs = vec![
        BodyDesc::fixed(HalfSpace::ground()).named("ground"),
        BodyDesc::dynamic(Sphere::new(0.2).unwrap()).at(DVec3::new(0.0, 0.0, 0.5)),
        BodyDesc::dynamic(Cuboid::new(DVec3::new(0.3, 0.2, 0.1)).unwrap())
            .with_pose(Pose::new(DVec3::new(1.0, 0.0, 0.4), tilt).unwrap())
            .with_material(0.8, 0.3),
        BodyDesc::dynamic(Capsule::new(0.1, 0.2).unwrap()).at(DVec3::new(-1.0, 0.0, 0.6)),
        BodyDesc::dynamic(hull).at(DVec3::new(0.0, 1.0, 0.5)),
        BodyDesc::dynamic(cube_mesh.clone()).at(DVec3::new(0.0, -1.0, 0.5)),
        BodyDesc::dynamic(cube_mesh).at(DVec3::new(0.0, -1.0, 1.0)),
        BodyDesc {
            shapes: vec![
                ShapeDesc::new(Sphere::new(0.1).unwrap()).at(Pose::from_translation(DVec3::X * 0.2)),
                ShapeDesc::new(Cuboid::new(DVec3::splat(0.1)).unwrap()),
            ],
            linear_damping: 0.1,
            angular_damping: 0.2,
            ..BodyDesc::dynamic(Sphere::new(0.1).unwrap())
        }
        .at(DVec3::new(1.0, 1.0, 0.5))
        .with_velocity(DVec3::new(0.1, 0.0, 0.0), DVec3::new(0.0, 0.0, 1.0)),
        BodyDesc::kinematic(Cuboid::new(DVec3::new(0.5, 0.5, 0.05)).unwrap())
            .at(DVec3::new(3.0, 0.0, 0.2))
            .with_velocity(DVec3::new(0.0, 0.1, 0.0), DVec3::new(0.0, 0.0, 0.2)),
        BodyDesc::dynamic(Sphere::new(0.1).unwrap()).at(DVec3::new(5.0, 5.0, 5.0)),
        // Two overlapping balls of one non-colliding group (index 10, 11).
        BodyDesc {
            non_colliding_group: 7,
            ..BodyDesc::dynamic(Sphere::new(0.2).unwrap()).at(DVec3::new(-2.0, 2.0, 0.5))
        },
        BodyDesc {
            non_colliding_group: 7,
            ..BodyDesc::dynamic(Sphere::new(0.2).unwrap()).at(DVec3::new(-2.0, 2.1, 0.5))
        },
        // A body without shapes, its mass given (index 12): no broad-phase box.
        BodyDesc {
            shapes: Vec::new(),
            mass: MassDesc::Inertial(
                MassProperties::new(1.5, DVec3::ZERO, DMat3::from_diagonal(DVec3::new(0.1, 0.2, 0.3)))
                    .unwrap(),
            ),
            ..BodyDesc::default()
        }
        .at(DVec3::new(2.0, -2.0, 1.0))
        .with_velocity(DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.5, 0.0, 1.0)),
    ];
    let mut ids: Vec<BodyId> = descs.iter().map(|d| world.add_body(d).unwrap()).collect();
    let removed = ids.remove(9);
    world.remove_body(removed).unwrap();
    world.apply_force(ids[1], DVec3::new(1.0, 2.0, 3.0)).unwrap();
    world.apply_torque(ids[2], DVec3::new(0.0, 0.1, 0.0)).unwrap();
    // The two mesh cubes, one above the other, never touch each other.
    world.set_contacts_between(ids[6], ids[5], false).unwrap();
    (world, ids, removed)
}

#[test]
fn every_kind_of_body_survives_a_snapshot() {
    let (mut world, ids, removed) = assorted_world();
    // Run until some bodies sleep, then snapshot mid-flight.
    run(&mut world, 150);
    world.apply_force(ids[3], DVec3::new(0.5, 0.0, 0.0)).unwrap();
    let snap = world.snapshot();
    assert_eq!(snap.body_count(), 12);
    let mut restored = World::from_snapshot(&Snapshot::from_json(&snap.to_json()).unwrap()).unwrap();
    assert!(restored.pose(removed).is_err(), "a removed body stays removed");
    for &id in &ids {
        assert_eq!(
            restored.pose(id).unwrap(),
            world.pose(id).unwrap(),
            "handles stay valid"
        );
        assert_eq!(restored.name(id).unwrap(), world.name(id).unwrap());
        assert_eq!(restored.is_sleeping(id).unwrap(), world.is_sleeping(id).unwrap());
        assert_eq!(
            restored.non_colliding_group(id).unwrap(),
            world.non_colliding_group(id).unwrap()
        );
    }
    assert_eq!(restored.excluded_contact_pairs(), &[(ids[5], ids[6])]);
    assert_eq!(restored.non_colliding_group(ids[10]).unwrap(), 7);
    let new_a = world.add_body(&BodyDesc::dynamic(Sphere::new(0.1).unwrap()).at(DVec3::new(-3.0, 0.0, 1.0)));
    let new_b =
        restored.add_body(&BodyDesc::dynamic(Sphere::new(0.1).unwrap()).at(DVec3::new(-3.0, 0.0, 1.0)));
    assert_eq!(
        new_a.unwrap(),
        new_b.unwrap(),
        "the free list is restored: the same slot is reused"
    );
    assert!(
        restored.pose(removed).is_err(),
        "the reused slot's old handle is still stale"
    );
    let mut events = (Vec::new(), Vec::new());
    for _ in 0..120 {
        events.0.push(world.step().events);
        events.1.push(restored.step().events);
    }
    assert_eq!(state_bits(&restored), state_bits(&world));
    assert_eq!(events.0, events.1, "contact events agree too");
    assert!(restored.snapshot() == world.snapshot(), "full state differs");
}

#[test]
fn snapshots_of_other_versions_are_refused_not_misread() {
    let (world, ..) = assorted_world();
    let snap = world.snapshot();
    let bytes = snap.to_bytes();
    // The version is the first value after the magic (a one-byte varint).
    assert_eq!(bytes[SNAPSHOT_MAGIC.len()], SNAPSHOT_FORMAT_VERSION as u8);
    for other in [0u8, SNAPSHOT_FORMAT_VERSION as u8 + 1, 100] {
        let mut old = bytes.clone();
        old[SNAPSHOT_MAGIC.len()] = other;
        assert_eq!(
            Snapshot::from_bytes(&old),
            Err(SnapshotError::UnsupportedVersion {
                found: other as u32,
                supported: SNAPSHOT_FORMAT_VERSION
            })
        );
    }
    let json = snap.to_json();
    let key = format!("\"format_version\":{SNAPSHOT_FORMAT_VERSION}");
    assert!(json.contains(&key));
    let old = json.replacen(&key, "\"format_version\":0", 1);
    let err = Snapshot::from_json(&old).unwrap_err();
    assert!(matches!(err, SnapshotError::UnsupportedVersion { found: 0, .. }));
    assert!(err.to_string().contains("version 0 is not supported"), "{err}");
    // A snapshot value with another version (made in memory) is refused too.
    let mut other = snap.clone();
    other.format_version = SNAPSHOT_FORMAT_VERSION + 1;
    assert!(matches!(
        World::from_snapshot(&other),
        Err(SnapshotError::UnsupportedVersion { found, .. }) if found == SNAPSHOT_FORMAT_VERSION + 1
    ));
    // Not a snapshot, truncated, trailing garbage.
    assert!(matches!(
        Snapshot::from_bytes(b"PK\x03\x04"),
        Err(SnapshotError::NotASnapshot(_))
    ));
    assert!(matches!(
        Snapshot::from_bytes(&bytes[..bytes.len() / 2]),
        Err(SnapshotError::Decode(_))
    ));
    let mut long = bytes.clone();
    long.push(0);
    assert!(matches!(
        Snapshot::from_bytes(&long),
        Err(SnapshotError::Decode(_))
    ));
    assert!(matches!(Snapshot::from_json("{}"), Err(SnapshotError::Decode(_))));
}

#[test]
fn inconsistent_snapshots_are_refused_and_restore_leaves_the_world_unchanged() {
    let (world, ..) = assorted_world();
    let json = world.snapshot().to_json();
    let mut target = world.clone();
    let before = target.snapshot();
    // Each edit makes the JSON describe an impossible world.
    let edits: [(&str, &str); 6] = [
        ("\"dt\":0.016666666666666666", "\"dt\":-1.0"),
        ("\"free\":[9]", "\"free\":[]"),
        ("\"free\":[9]", "\"free\":[3]"),
        ("\"name\":\"ground\"", "\"name\":\"ground\",\"bogus\":1"),
        ("\"material\":[0.3,0.8]", "\"material\":[-0.3,0.8]"),
        ("\"unbounded\":[0]", "\"unbounded\":[]"),
    ];
    for (from, to) in edits {
        assert!(json.contains(from), "{from} not in the snapshot JSON");
        let bad = json.replacen(from, to, 1);
        let result = Snapshot::from_json(&bad).and_then(|s| target.restore(&s));
        assert!(
            matches!(
                result,
                Err(SnapshotError::Invalid(_)) | Err(SnapshotError::Decode(_))
            ),
            "{to}: {result:?}"
        );
        assert!(target.snapshot() == before, "{to}: the world changed");
    }
    // Excluded pairs: reversed, repeated, or naming a body that is not
    // there (a stale generation, the removed slot).
    let key = "\"contact_exclusions\":";
    let at = json.find(key).expect("contact_exclusions in the JSON") + key.len();
    let end = at + json[at..].find("]]").unwrap() + 2;
    let list = &json[at..end];
    let (first, second) = list[2..list.len() - 2].split_once("},{").unwrap();
    let (first, second) = (format!("{first}}}"), format!("{{{second}"));
    let stale = first.replace("\"generation\":", "\"generation\":7");
    let removed_slot = format!("{{\"index\":9,{}", &second[second.find(',').unwrap() + 1..]);
    for pairs in [
        format!("[[{second},{first}]]"),
        format!("[[{first},{second}],[{first},{second}]]"),
        format!("[[{stale},{second}]]"),
        format!("[[{first},{removed_slot}]]"),
        format!("[[{first},{first}]]"),
    ] {
        let bad = format!("{}{pairs}{}", &json[..at], &json[end..]);
        let result = Snapshot::from_json(&bad).and_then(|s| target.restore(&s));
        match result {
            Err(SnapshotError::Invalid(message)) => {
                assert!(message.contains("contact_exclusions"), "{pairs}: {message}")
            }
            other => panic!("{pairs}: {other:?}"),
        }
        assert!(target.snapshot() == before, "{pairs}: the world changed");
    }
    // A state that is not finite cannot be put in through a snapshot.
    let (world2, ..) = assorted_world();
    let bad = world2.snapshot().to_json().replacen(
        "\"state\":{\"position\":[0.0",
        "\"state\":{\"position\":[1e400",
        1,
    );
    assert!(Snapshot::from_json(&bad).is_err());
    // Nor a body or a shape beyond the coordinate limit that `add_body`
    // and `set_pose` hold every body to (finite, so it decodes).
    let json2 = world2.snapshot().to_json();
    let far = format!("{:e}", 10.0 * tumble::world::MAX_POSITION);
    for prefix in ["\"state\":{\"position\":[", "\"local\":{\"position\":["] {
        // The first coordinate after `prefix` replaced by `far`.
        let at = json2
            .find(prefix)
            .unwrap_or_else(|| panic!("{prefix} not in the snapshot JSON"))
            + prefix.len();
        let comma = at + json2[at..].find(',').unwrap();
        let bad = format!("{}{far}{}", &json2[..at], &json2[comma..]);
        let result = Snapshot::from_json(&bad).and_then(|s| target.restore(&s));
        match result {
            Err(SnapshotError::Invalid(message)) => {
                assert!(message.contains("within"), "{prefix}: {message}")
            }
            other => panic!("{prefix}: {other:?}"),
        }
        assert!(target.snapshot() == before, "{prefix}: the world changed");
    }
}

#[test]
fn file_errors_are_typed() {
    let dir = temp_dir("files");
    assert!(matches!(
        Snapshot::load(dir.join("missing.snap")),
        Err(SnapshotError::Io { .. })
    ));
    std::fs::write(dir.join("empty.snap"), b"").unwrap();
    assert!(matches!(
        Snapshot::load(dir.join("empty.snap")),
        Err(SnapshotError::Io { .. })
    ));
    std::fs::write(dir.join("text.snap"), b"hello").unwrap();
    assert!(matches!(
        Snapshot::load(dir.join("text.snap")),
        Err(SnapshotError::NotASnapshot(_))
    ));
    let (world, ..) = assorted_world();
    assert!(matches!(
        world.snapshot().save(dir.join("no/such/dir/w.snap")),
        Err(SnapshotError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shapes_serialise_exactly_and_reject_bad_values() {
    let h = HalfSpace::new(DVec3::new(1.0, 2.0, 2.0) / 3.0, 0.5).unwrap();
    let back: HalfSpace = serde_json::from_str(&serde_json::to_string(&h).unwrap()).unwrap();
    assert_eq!(
        back.normal().to_array().map(f64::to_bits),
        h.normal().to_array().map(f64::to_bits)
    );
    assert!(serde_json::from_str::<Sphere>("{\"radius\":-1.0}").is_err());
    assert!(serde_json::from_str::<Cuboid>("{\"half_extents\":[1.0,0.0,1.0]}").is_err());
    assert!(serde_json::from_str::<Capsule>("{\"radius\":1.0,\"half_height\":-1.0}").is_err());
    assert!(serde_json::from_str::<HalfSpace>("{\"normal\":[0.0,0.0,2.0],\"offset\":0.0}").is_err());
    let hull = ConvexHull::from_mesh(&box_mesh(DVec3::splat(0.5)).unwrap()).unwrap();
    let text = serde_json::to_string(&hull).unwrap();
    assert_eq!(serde_json::from_str::<ConvexHull>(&text).unwrap(), hull);
    // A corner index past the vertices is refused.
    let bad = text.replacen("\"corners\":[", "\"corners\":[99,", 1);
    assert!(serde_json::from_str::<ConvexHull>(&bad).is_err());
    let _ = Shape::Sphere(Sphere::new(1.0).unwrap());
}
