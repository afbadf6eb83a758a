//! Triangle-mesh bodies in the world (issue: concave mesh dynamics), first
//! cases: a mesh body behaves like the primitive it tessellates, and a torus
//! (concave) comes to rest on the ground.

use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::{box_mesh, torus_mesh};
use tumble_collide::shape::{Cuboid, HalfSpace, MeshShape, Shape};
use tumble_collide::DVec3;

fn settle(desc: BodyDesc, steps: usize) -> (World, tumble::world::BodyId) {
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .unwrap();
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
