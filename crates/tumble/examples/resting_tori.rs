//! Two tori resting on each other on the ground, at a chosen tessellation
//! (issue 15: "the cost follows the tessellation, not the contact"):
//! `resting_tori TRIANGLES STEPS [THREADS]` drops a torus of about
//! TRIANGLES triangles flat on the ground and a second one across it, and
//! prints the cost per step over the last third of the steps (both at
//! rest by then), the contact points, the triangle pairs that remembered
//! their walks, the deepest overlap and the energy left.
//!
//! The tori: major radius 0.4 m, tube 0.1 m, density 1,000 kg/m^3, both
//! flat, the upper one 1 mm above the lower and shifted by the major
//! radius (turned 0.3 rad about z), so that their tubes cross twice.
use std::time::Instant;
use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::torus_mesh;
use tumble_collide::shape::{HalfSpace, MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let triangles: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10_000);
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(180);
    let threads: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    // 2 n_major n_minor triangles with n_major = 2 n_minor.
    let n_minor = ((triangles as f64 / 4.0).sqrt().round() as usize).max(3);
    let mesh = torus_mesh(0.4, 0.1, 2 * n_minor, n_minor).expect("torus");
    let count = mesh.triangles().len();
    let shape = Shape::Mesh(MeshShape::new(mesh).expect("mesh shape"));
    let mut world = World::new(WorldSettings {
        sleeping: false,
        threads,
        ..WorldSettings::default()
    })
    .expect("settings");
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .expect("ground");
    world
        .add_body(
            &BodyDesc::dynamic(shape.clone())
                .at(DVec3::new(0.0, 0.0, 0.1))
                .with_density(1000.0),
        )
        .expect("lower torus");
    // Flat on top, shifted by the major radius: the tubes cross twice.
    let above = Pose::new(DVec3::new(0.4, 0.0, 0.301), DQuat::from_rotation_z(0.3)).expect("pose");
    world
        .add_body(&BodyDesc::dynamic(shape).with_pose(above).with_density(1000.0))
        .expect("upper torus");
    let (mut late, mut deepest, mut contacts, mut recalled) = (0.0, 0.0f64, 0, 0);
    for step in 0..steps {
        let started = Instant::now();
        let report = world.step();
        let took = started.elapsed().as_secs_f64();
        deepest = deepest.max(report.max_penetration);
        if step >= steps - steps / 3 {
            late += took;
            contacts = contacts.max(report.contacts);
            recalled += report.recalled_mesh_pairs;
        }
    }
    println!(
        "tori of {count} triangles: {:.3} ms/step over the last {} steps on {threads} thread(s); \
         up to {contacts} contact points; {recalled} mesh pairs recalled their walk; \
         deepest {:.4} m; energy left {:.2e} J",
        late / (steps / 3).max(1) as f64 * 1e3,
        steps / 3,
        deepest,
        world.kinetic_energy()
    );
}
