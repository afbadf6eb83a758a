//! Two tori resting on each other on the ground, at chosen tessellations
//! (issue 15: "the cost follows the tessellation, not the contact"):
//! `resting_tori TRIANGLES[,TRIANGLES...] STEPS [THREADS]` drops a torus of
//! about TRIANGLES triangles flat on the ground and a second one across it,
//! once with the default settings and once searching every step
//! (`resting_motion = 0`), and prints a markdown table: the cost per step
//! over the last third of the steps (both at rest by then), the mesh pairs
//! that re-evaluated their kept points and that recalled their walks (per
//! step), the contact points, the deepest overlap and the energy left. All
//! rows come from one run.
//!
//! The tori: major radius 0.4 m, tube 0.1 m, density 1,000 kg/m^3, both
//! flat, the upper one 1 mm above the lower and shifted by the major
//! radius (turned 0.3 rad about z), so that their tubes cross twice.
use std::time::Instant;
use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::torus_mesh;
use tumble_collide::shape::{HalfSpace, MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

/// What one run measured.
struct Run {
    triangles: usize,
    ms_per_step: f64,
    revalidated: f64,
    recalled: f64,
    contacts: usize,
    deepest: f64,
    energy: f64,
}

fn run(shape: &Shape, triangles: usize, steps: usize, threads: u32, resting_motion: f64) -> Run {
    let mut world = World::new(WorldSettings {
        sleeping: false,
        threads,
        resting_motion,
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
        .add_body(
            &BodyDesc::dynamic(shape.clone())
                .with_pose(above)
                .with_density(1000.0),
        )
        .expect("upper torus");
    let late_steps = (steps / 3).max(1);
    let (mut late, mut deepest, mut contacts, mut recalled, mut revalidated) = (0.0, 0.0f64, 0, 0, 0);
    for step in 0..steps {
        let started = Instant::now();
        let report = world.step();
        let took = started.elapsed().as_secs_f64();
        deepest = deepest.max(report.max_penetration);
        if step >= steps - late_steps {
            late += took;
            contacts = contacts.max(report.contacts);
            recalled += report.recalled_mesh_pairs;
            revalidated += report.revalidated_mesh_pairs;
        }
    }
    Run {
        triangles,
        ms_per_step: late / late_steps as f64 * 1e3,
        revalidated: revalidated as f64 / late_steps as f64,
        recalled: recalled as f64 / late_steps as f64,
        contacts,
        deepest,
        energy: world.kinetic_energy(),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let sizes: Vec<usize> = args
        .get(1)
        .map_or("10000", String::as_str)
        .split(',')
        .map(|s| s.trim().parse().expect("triangle counts, comma-separated"))
        .collect();
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(180);
    let threads: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    println!(
        "Two resting tori, {steps} steps at 1/60 s on {threads} thread(s), cost over the last {} steps:\n",
        (steps / 3).max(1)
    );
    println!(
        "| triangles per torus | contact search | ms/step | pairs re-evaluated per step | pairs recalled per step | contact points | deepest overlap (m) | kinetic energy at the end (J) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for &triangles in &sizes {
        // 2 n_major n_minor triangles with n_major = 2 n_minor.
        let n_minor = ((triangles as f64 / 4.0).sqrt().round() as usize).max(3);
        let mesh = torus_mesh(0.4, 0.1, 2 * n_minor, n_minor).expect("torus");
        let count = mesh.triangles().len();
        let shape = Shape::Mesh(MeshShape::new(mesh).expect("mesh shape"));
        let default = WorldSettings::default().resting_motion;
        for (mode, resting_motion) in [("resting pairs re-evaluate", default), ("every step", 0.0)] {
            let r = run(&shape, count, steps, threads, resting_motion);
            println!(
                "| {} | {mode} | {:.3} | {:.1} | {:.1} | {} | {:.4} | {:.1e} |",
                r.triangles, r.ms_per_step, r.revalidated, r.recalled, r.contacts, r.deepest, r.energy
            );
        }
    }
}
