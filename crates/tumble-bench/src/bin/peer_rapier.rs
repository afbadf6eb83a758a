//! `peer-rapier`: the pyramid, large pyramid, pile, chain, cradle and jointed scenes of
//! scenes.md in Rapier (rapier3d, f32, built with its `parallel` feature; each scene runs
//! inside a rayon pool of `--threads` threads, 1 by default). Prints one JSON record (see
//! `record.rs`).
//!
//! Every scene is built from its one definition in `tumble::scenes` by
//! `rapier_scenes::build`: the same bodies, poses, velocities, masses and inertias (tumble's),
//! materials combined as tumble combines them (friction: geometric mean; restitution:
//! maximum), sleeping off, Rapier's default solver iterations and sub-steps. The chain's links
//! are the plain 768-triangle mesh (`TriMesh`, default flags): no convex decomposition.
//! `heavy_chain-multibody` and `ragdoll_pile-multibody` run the heavy chain and the ragdoll
//! pile on Rapier's multibody (reduced-coordinate) joints;
//! `concave_pile-vhacd` the concave pile with each body's mesh as Rapier's own convex
//! decomposition (`concave_pile`: plain `TriMesh`es).
//! A scene name with `-passes` appended (`pyramid-passes`, `pile-passes`, ...) runs the scene
//! with tumble's passes instead of Rapier's defaults: as many solver sub-steps as tumble's
//! `substeps`, as many PGS iterations in each as tumble's `iterations` and as many
//! stabilization iterations as tumble's `push_out_iterations` (8, 2 and 1 by default, against
//! Rapier's 4, 1 and 1), so that the two engines' times compare the same solver work.
//!
//! Usage: `peer-rapier --scene pyramid|large_pyramid|pile|chain|cradle|bowl|bowl-facets|heavy_chain|heavy_chain-multibody|ragdoll_pile|ragdoll_pile-multibody|concave_pile|concave_pile-vhacd[-passes] [--steps K] [--n N] [--threads T]`

use std::time::Instant;

use rapier3d::prelude::*;
use serde_json::json;
use tumble::collide::DVec3;
use tumble::scenes::TimingStats;
use tumble::scenes::{self, Scene};
use tumble_bench::rapier_scenes as rs;
use tumble_bench::{Args, Record};

/// (contact points in all manifolds, deepest penetration in m).
fn contacts(w: &PhysicsWorld) -> (usize, f64) {
    let mut n = 0;
    let mut deepest = 0.0f64;
    for pair in w.narrow_phase.contact_pairs() {
        for m in pair.manifolds() {
            n += m.points.len();
            for p in &m.points {
                deepest = deepest.max(-(p.dist as f64));
            }
        }
    }
    (n, deepest)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn settings(w: &PhysicsWorld, steps: usize) -> serde_json::Value {
    let p = &w.integration_parameters;
    json!({
        "dt": p.dt,
        "steps": steps,
        "threads": rayon::current_num_threads(),
        "precision": "f32",
        "solver_iterations": p.num_solver_iterations,
        "internal_pgs_iterations": p.num_internal_pgs_iterations,
        "internal_stabilization_iterations": p.num_internal_stabilization_iterations,
        "materials": "tumble's per body",
        "friction_combine": "geometric mean",
        "restitution_combine": "max",
        "sleeping": "disabled",
    })
}

/// The scene of `tumble::scenes` that `name` runs (`pile`: of `n` bodies).
fn scene(name: &str, n: usize) -> Result<Scene, String> {
    Ok(match name {
        "pyramid" => scenes::pyramid(),
        "large_pyramid" => scenes::large_pyramid(),
        "pile" if n > 0 && n.is_multiple_of(100) => scenes::pile(n / 100),
        "pile" => return Err(format!("pile: --n must be a positive multiple of 100, got {n}")),
        "chain" => scenes::chain(),
        "cradle" => scenes::cradle(),
        "bowl" => scenes::bowl_swing(true),
        "bowl-facets" => scenes::bowl_swing(false),
        "heavy_chain" | "heavy_chain-multibody" => scenes::heavy_chain(),
        "ragdoll_pile" | "ragdoll_pile-multibody" => scenes::ragdoll_pile(),
        "concave_pile" | "concave_pile-vhacd" => scenes::concave_pile(scenes::CONCAVE_PILE_BODIES),
        other => {
            return Err(format!(
            "--scene must be pyramid, large_pyramid, pile, chain, cradle, bowl, bowl-facets, heavy_chain, \
                 heavy_chain-multibody, ragdoll_pile, ragdoll_pile-multibody, concave_pile or concave_pile-vhacd, got {other:?}"
        ))
        }
    })
}

/// Runs `name` for `steps` steps (default: the scene's own), timing the
/// step call only, and prints the record with the figures of scenes.md;
/// deepest penetration and joint error are sampled every 10 steps.
fn run(full_name: &str, steps: Option<usize>, n: usize) -> Result<(), String> {
    let passes = full_name.ends_with("-passes");
    let name = full_name.strip_suffix("-passes").unwrap_or(full_name);
    let scene = scene(name, n)?;
    let multibody = name.ends_with("-multibody");
    let decomposed = name.ends_with("-vhacd");
    let mut sw = rs::build_with(&scene, multibody, decomposed)?;
    if passes {
        let p = &mut sw.world.integration_parameters;
        let s = &scene.settings;
        if s.substeps == 0 {
            return Err(format!("{name}: tumble's settings have no sub-steps"));
        }
        p.num_solver_iterations = s.substeps as usize;
        p.num_internal_pgs_iterations = s.iterations as usize;
        p.num_internal_stabilization_iterations = s.push_out_iterations as usize;
    }
    let steps = steps.unwrap_or(scene.steps);
    let dynamic: Vec<usize> = (0..scene.bodies.len())
        .filter(|&i| scene.bodies[i].kind == tumble::BodyKind::Dynamic)
        .collect();
    let starts: Vec<[f64; 3]> = (0..scene.bodies.len()).map(|i| sw.centre(i)).collect();
    // Rapier computes its mass properties in the first step: the start's
    // energy comes from the scene's own masses and velocities.
    let energy_start: f64 = sw
        .plain
        .bodies
        .iter()
        .map(|b| {
            0.5 * b.mass * b.linear_velocity.length_squared()
                + 0.5 * b.principal_inertia.dot(b.angular_velocity * b.angular_velocity)
        })
        .sum();
    let mut times = Vec::with_capacity(steps);
    let (mut deepest, mut widest, mut worst_joint) = (0.0f64, 0.0f64, 0.0f64);
    // The kinetic energy 5 s in (the concave pile's "at rest within 5 s").
    let five_seconds = (5.0 / scene.settings.dt).round() as usize;
    let mut energy_at_five = None;
    // The bowl's swing, read every step (the ball is body 1).
    let swing = |sw: &rs::SceneWorld| scenes::swing_angle(DVec3::from_array(sw.centre(1)), false);
    let mut meter = name
        .starts_with("bowl")
        .then(|| scenes::SwingMeter::new(scene.settings.dt, swing(&sw)));
    for s in 0..steps {
        let t0 = Instant::now();
        sw.world.step();
        times.push(t0.elapsed().as_secs_f64());
        if let Some(m) = meter.as_mut() {
            m.observe(swing(&sw));
        }
        if s + 1 == five_seconds {
            energy_at_five = Some(kinetic_energy(&sw));
        }
        if s % 10 == 9 || s + 1 == steps {
            deepest = deepest.max(contacts(&sw.world).1);
            worst_joint = worst_joint.max(sw.largest_joint_error());
            if name == "chain" {
                widest = widest.max(largest_gap(&sw));
            }
        }
    }
    let ends: Vec<[f64; 3]> = (0..scene.bodies.len()).map(|i| sw.centre(i)).collect();
    let mut figures = json!({ "step_time": TimingStats::ms(&times), "deepest_penetration_m": deepest });
    let mut set = settings(&sw.world, steps);
    match name {
        "pyramid" | "large_pyramid" => {
            let moved: Vec<f64> = dynamic.iter().map(|&i| dist(ends[i], starts[i])).collect();
            figures["top_box_displacement_m"] = json!(moved.last());
            figures["largest_displacement_m"] = json!(moved.iter().cloned().fold(0.0, f64::max));
        }
        "pile" => {
            let centres: Vec<DVec3> = dynamic.iter().map(|&i| DVec3::from_array(ends[i])).collect();
            figures["bodies_outside"] = json!(scenes::pile_outside(&centres));
            figures["mean_final_height_m"] =
                json!(centres.iter().map(|c| c.z).sum::<f64>() / centres.len() as f64);
            figures["contact_points"] = json!(contacts(&sw.world).0);
            figures["final_kinetic_energy_j"] = json!(kinetic_energy(&sw));
            set["n"] = json!(n);
        }
        "concave_pile" | "concave_pile-vhacd" => {
            let centres: Vec<DVec3> = dynamic.iter().map(|&i| DVec3::from_array(ends[i])).collect();
            figures["bodies_escaped"] = json!(scenes::concave_pile_escaped(&centres));
            figures["final_kinetic_energy_j"] = json!(kinetic_energy(&sw));
            figures["kinetic_energy_at_5s_j"] = json!(energy_at_five);
            figures["contact_points"] = json!(contacts(&sw.world).0);
            set["collision"] = json!(if decomposed {
                "Rapier's own convex decomposition of each body's mesh (V-HACD, default parameters); \
                 the bin a TriMesh"
            } else {
                "plain TriMesh colliders, default flags"
            });
        }
        "chain" => {
            let reach = scenes::CHAIN_MAX_CENTRE_DISTANCE;
            figures["interlock_held"] = json!(widest <= reach);
            figures["max_adjacent_centre_distance_m"] = json!(widest);
            figures["broken_links"] = json!(ends.windows(2).filter(|p| dist(p[0], p[1]) > reach).count());
            set["collision"] = json!("plain concave TriMesh, 768 triangles, default flags");
        }
        "bowl" | "bowl-facets" => {
            let meter = meter.as_ref().ok_or("the bowl's swing was not read")?;
            let phi0 = scenes::BOWL_START_DEG.to_radians();
            let want = tumble::analytic::rolling_period(
                scenes::BOWL_RADIUS - scenes::BOWL_BALL_RADIUS,
                0.4,
                phi0,
                scene.settings.gravity.length(),
            );
            figures["period_s"] = json!(meter.period());
            figures["rolling_period_s"] = json!(want);
            figures["period_error"] = json!(meter.period().map(|p| p / want - 1.0));
            figures["amplitude_kept"] = json!(meter.amplitude_after_two().map(|a| a / phi0));
            set["collision"] = json!(if name == "bowl" {
                "TriMesh with FIX_INTERNAL_EDGES (96 x 48 facets)"
            } else {
                "TriMesh, default flags (96 x 48 facets)"
            });
        }
        "cradle" => {
            let vel: Vec<[f64; 3]> = sw
                .bodies
                .iter()
                .map(|&h| {
                    sw.world
                        .bodies
                        .get(h)
                        .map(|b| b.linvel())
                        .unwrap_or(Vector::splat(f32::NAN))
                })
                .map(|v| [v.x as f64, v.y as f64, v.z as f64])
                .collect();
            let mass: Vec<f64> = sw.plain.bodies.iter().map(|b| b.mass).collect();
            let p: [f64; 3] = std::array::from_fn(|a| vel.iter().zip(&mass).map(|(v, m)| m * v[a]).sum());
            // The striker alone moves at the start: p0 = m v along x.
            let p0 = mass[5] * 1.0;
            figures["final_velocities_x"] = json!(vel.iter().map(|v| v[0]).collect::<Vec<_>>());
            figures["last_sphere_vx"] = json!(vel[4][0]);
            figures["momentum_error"] = json!(((p[0] - p0).powi(2) + p[1] * p[1] + p[2] * p[2]).sqrt());
            figures["energy_error"] = json!((kinetic_energy(&sw) - energy_start) / energy_start);
            set["restitution_per_collider"] = json!(1.0);
            set["gravity"] = json!([0.0, 0.0, 0.0]);
        }
        _ => {
            figures["largest_joint_error_m"] = json!(worst_joint);
            figures["final_joint_error_m"] = json!(sw.largest_joint_error());
            if scene.name == "heavy_chain" {
                let weight = ends[ends.len() - 1];
                figures["weight_distance_m"] = json!(dist(weight, [0.0, 0.0, 2.0]));
            }
            set["joints"] = json!(if multibody { "multibody" } else { "impulse" });
        }
    }
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: match name {
            "pile" => format!("pile{n}"),
            other => other.to_string(),
        } + if passes { "-passes" } else { "" },
        status: "ok",
        settings: set,
        figures,
        peak_rss_bytes: None,
    }
    .emit();
    Ok(())
}

/// Largest distance between adjacent link centres of the chain (m).
fn largest_gap(sw: &rs::SceneWorld) -> f64 {
    let c: Vec<[f64; 3]> = (0..sw.bodies.len()).map(|i| sw.centre(i)).collect();
    c.windows(2).map(|p| dist(p[0], p[1])).fold(0.0, f64::max)
}

/// Kinetic energy of every body (J).
fn kinetic_energy(sw: &rs::SceneWorld) -> f64 {
    sw.bodies
        .iter()
        .filter_map(|&h| sw.world.bodies.get(h))
        .map(|b| b.kinetic_energy() as f64)
        .sum()
}

fn main() {
    let args = Args::from_env_or_exit("peer-rapier");
    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(1))
        .build()
    {
        Ok(p) => p,
        Err(e) => {
            eprintln!("peer-rapier: cannot start threads: {e}");
            std::process::exit(1);
        }
    };
    let name = args.scene.clone().unwrap_or_default();
    let result = pool.install(|| run(&name, args.steps, args.n.unwrap_or(1000)));
    if let Err(e) = result {
        eprintln!("peer-rapier: {e}");
        std::process::exit(2);
    }
}
