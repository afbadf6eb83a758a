//! `peer-rapier`: the pyramid, large pyramid, pile, chain and cradle scenes of scenes.md in Rapier
//! (rapier3d, f32, built with its `parallel` feature; each scene runs inside a rayon pool of
//! `--threads` threads, 1 by default). Prints one JSON record (see `record.rs`).
//!
//! Settings mirror the other peers: dt 1/60 s, gravity -9.81 z, friction 0.5 on every
//! collider (Rapier's default combine rule, Average, yields 0.5), restitution 0, sleeping
//! off (`can_sleep(false)`), Rapier's default solver iterations and substeps.
//!
//! The chain uses the plain 768-triangle link mesh (`TriMesh`, default flags) with the
//! solid torus mass properties: no convex decomposition.
//!
//! The jointed scenes (heavy_chain, ragdoll_pile) are built from `tumble::scenes` (see
//! `rapier_scenes::jointed`); `heavy_chain-multibody` runs the chain on Rapier's multibody joints.
//!
//! Usage: `peer-rapier --scene pyramid|large_pyramid|pile|chain|cradle|heavy_chain|heavy_chain-multibody|ragdoll_pile [--steps K] [--n N] [--threads T]`

use std::time::Instant;

use rapier3d::prelude::*;
use serde_json::json;
use tumble_bench::rapier_scenes::{self as rs, v, world, FRICTION};
use tumble_bench::scenes;
use tumble_bench::{Args, Record, Stats};

/// Steps `steps` times, timing the step call only; samples the deepest penetration every 10 steps.
fn run(w: &mut PhysicsWorld, steps: usize) -> (Vec<f64>, f64) {
    let mut times = Vec::with_capacity(steps);
    let mut deepest = 0.0f64;
    for s in 0..steps {
        let t0 = Instant::now();
        w.step();
        times.push(t0.elapsed().as_secs_f64());
        if s % 10 == 9 || s + 1 == steps {
            deepest = deepest.max(contacts(w).1);
        }
    }
    (times, deepest)
}

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

fn position(w: &PhysicsWorld, h: RigidBodyHandle) -> [f64; 3] {
    match w.bodies.get(h) {
        Some(b) => {
            let t = b.translation();
            [t.x as f64, t.y as f64, t.z as f64]
        }
        None => [f64::NAN; 3],
    }
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
        "friction_per_collider": FRICTION,
        "friction_combine": "average",
        "sleeping": "disabled",
    })
}

fn pyramid(steps: usize, large: bool) {
    let (mut w, ids, starts) = if large { rs::large_pyramid() } else { rs::pyramid() };
    let (times, deepest) = run(&mut w, steps);
    let disp: Vec<f64> = ids
        .iter()
        .zip(&starts)
        .map(|(&id, &s)| dist(position(&w, id), s))
        .collect();
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: if large { "large_pyramid" } else { "pyramid" }.into(),
        status: "ok",
        settings: settings(&w, steps),
        figures: json!({
            "step_time": Stats::ms(&times),
            "top_box_displacement_m": disp.last(),
            "largest_displacement_m": disp.iter().cloned().fold(0.0, f64::max),
            "deepest_penetration_m": deepest,
        }),
        peak_rss_bytes: None,
    }
    .emit();
}

fn pile(steps: usize, n: usize) -> Result<(), String> {
    let (mut w, ids) =
        rs::pile(n).ok_or_else(|| format!("pile: --n must be a positive multiple of 100, got {n}"))?;
    let (times, _) = run(&mut w, steps);
    let ends: Vec<[f64; 3]> = ids.iter().map(|&id| position(&w, id)).collect();
    let (points, deepest) = contacts(&w);
    let mut set = settings(&w, steps);
    set["n"] = json!(n);
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: format!("pile{n}"),
        status: "ok",
        settings: set,
        figures: json!({
            "step_time": Stats::ms(&times),
            "bodies_outside": scenes::pile_outside(&ends),
            "mean_final_height_m": ends.iter().map(|p| p[2]).sum::<f64>() / ends.len() as f64,
            "contact_points": points,
            "deepest_penetration_m": deepest,
        }),
        peak_rss_bytes: None,
    }
    .emit();
    Ok(())
}

fn chain(steps: usize) -> Result<(), String> {
    let mut w = world();
    let (big_r, r) = scenes::CHAIN_RADII;
    let (verts, tris) = scenes::torus_mesh(big_r, r, 32, 12);
    let verts: Vec<Vector> = verts.into_iter().map(v).collect();
    let inertia = scenes::chain_inertia();
    let mut ids = Vec::with_capacity(21);
    for (k, (c, q)) in scenes::chain_links().into_iter().enumerate() {
        let pose = Pose::from_parts(
            v(c),
            Rotation::from_xyzw(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32),
        );
        let body = if k == 0 {
            RigidBodyBuilder::fixed()
        } else {
            RigidBodyBuilder::dynamic().can_sleep(false)
        };
        let col = ColliderBuilder::trimesh(verts.clone(), tris.clone())
            .map_err(|e| format!("link mesh rejected by rapier: {e:?}"))?
            .friction(FRICTION)
            .restitution(0.0)
            .mass_properties(MassProperties::new(
                Vector::ZERO,
                scenes::CHAIN_MASS as f32,
                v(inertia),
            ));
        ids.push(w.insert(body.pose(pose), col).0);
    }
    let mut times = Vec::with_capacity(steps);
    let (mut max_gap, mut deepest) = (0.0f64, 0.0f64);
    for s in 0..steps {
        let t0 = Instant::now();
        w.step();
        times.push(t0.elapsed().as_secs_f64());
        if s % 10 == 9 || s + 1 == steps {
            let p: Vec<[f64; 3]> = ids.iter().map(|&id| position(&w, id)).collect();
            for pair in p.windows(2) {
                max_gap = max_gap.max(dist(pair[0], pair[1]));
            }
            deepest = deepest.max(contacts(&w).1);
        }
    }
    let ends: Vec<[f64; 3]> = ids.iter().map(|&id| position(&w, id)).collect();
    let broken = ends
        .windows(2)
        .filter(|p| dist(p[0], p[1]) > scenes::CHAIN_MAX_GAP)
        .count();
    let mut set = settings(&w, steps);
    set["collision"] = json!("plain concave TriMesh, 768 triangles, default flags");
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: "chain".into(),
        status: "ok",
        settings: set,
        figures: json!({
            "step_time": Stats::ms(&times),
            "interlock_held": max_gap <= scenes::CHAIN_MAX_GAP,
            "max_adjacent_centre_distance_m": max_gap,
            "broken_links": broken,
            "deepest_penetration_m": deepest,
        }),
        peak_rss_bytes: None,
    }
    .emit();
    Ok(())
}

fn cradle(steps: usize) {
    let (mut w, ids) = rs::cradle();
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t0 = Instant::now();
        w.step();
        times.push(t0.elapsed().as_secs_f64());
    }
    let vel: Vec<[f64; 3]> = ids
        .iter()
        .map(|&id| {
            let v = w
                .bodies
                .get(id)
                .map(|b| b.linvel())
                .unwrap_or(Vector::splat(f32::NAN));
            [v.x as f64, v.y as f64, v.z as f64]
        })
        .collect();
    // Initial state: the 1 kg striker at 1 m/s (p0 = 1 kg m/s, E0 = 0.5 J).
    let p: [f64; 3] = std::array::from_fn(|a| vel.iter().map(|v| v[a]).sum());
    let energy: f64 = vel
        .iter()
        .map(|v| 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
        .sum();
    let mut set = settings(&w, steps);
    set["friction_per_collider"] = json!(0.0);
    set["restitution_per_collider"] = json!(1.0);
    set["gravity"] = json!([0.0, 0.0, 0.0]);
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: "cradle".into(),
        status: "ok",
        settings: set,
        figures: json!({
            "step_time": Stats::ms(&times),
            "final_velocities_x": vel.iter().map(|v| v[0]).collect::<Vec<_>>(),
            "last_sphere_vx": vel[4][0],
            "momentum_error": ((p[0] - 1.0).powi(2) + p[1] * p[1] + p[2] * p[2]).sqrt(),
            "energy_error": (energy - 0.5) / 0.5,
        }),
        peak_rss_bytes: None,
    }
    .emit();
}

/// heavy_chain or ragdoll_pile of `tumble::scenes`, with impulse joints or
/// (`multibody`) Rapier's multibody joints: ms/step and the largest joint
/// error (anchor gap), sampled every 10 steps as tumble does.
fn jointed(steps: usize, name: &str, multibody: bool) -> Result<(), String> {
    let scene = match name {
        "heavy_chain" => tumble::scenes::heavy_chain(),
        _ => tumble::scenes::ragdoll_pile(),
    };
    let mut jw = rs::jointed(&scene, multibody)?;
    let mut times = Vec::with_capacity(steps);
    let mut worst = 0.0f64;
    let mut deepest = 0.0f64;
    for s in 0..steps {
        let t0 = Instant::now();
        jw.world.step();
        times.push(t0.elapsed().as_secs_f64());
        if s % 10 == 9 || s + 1 == steps {
            worst = worst.max(jw.largest_joint_error());
            deepest = deepest.max(contacts(&jw.world).1);
        }
    }
    let mut figures = json!({
        "step_time": Stats::ms(&times),
        "largest_joint_error_m": worst,
        "final_joint_error_m": jw.largest_joint_error(),
        "deepest_penetration_m": deepest,
    });
    if name == "heavy_chain" {
        let weight = position(&jw.world, jw.bodies[jw.bodies.len() - 1]);
        figures["weight_distance_m"] = json!(dist(weight, [0.0, 0.0, 2.0]));
    }
    let mut set = settings(&jw.world, steps);
    set["joints"] = json!(if multibody { "multibody" } else { "impulse" });
    Record {
        engine: "rapier3d",
        version: env!("PEER_RAPIER3D_VERSION"),
        scene: if multibody {
            format!("{name}-multibody")
        } else {
            name.to_string()
        },
        status: "ok",
        settings: set,
        figures,
        peak_rss_bytes: None,
    }
    .emit();
    Ok(())
}

fn main() {
    let args = match Args::parse(std::env::args().skip(1)) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("peer-rapier: {e}");
            std::process::exit(2);
        }
    };
    let full = if args.scene.as_deref() == Some("cradle") {
        scenes::CRADLE_STEPS
    } else {
        scenes::FULL_STEPS
    };
    let steps = args.steps.unwrap_or(full);
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
    let result = pool.install(|| match args.scene.as_deref() {
        Some("pyramid") => {
            pyramid(steps, false);
            Ok(())
        }
        Some("large_pyramid") => {
            pyramid(steps, true);
            Ok(())
        }
        Some("pile") => pile(steps, args.n.unwrap_or(1000)),
        Some("chain") => chain(steps),
        Some("cradle") => {
            cradle(steps);
            Ok(())
        }
        Some(s @ ("heavy_chain" | "ragdoll_pile")) => jointed(steps, s, false),
        Some("heavy_chain-multibody") => jointed(steps, "heavy_chain", true),
        other => Err(format!(
            "--scene must be pyramid, large_pyramid, pile, chain, cradle, heavy_chain, \
             heavy_chain-multibody or ragdoll_pile, got {other:?}"
        )),
    });
    if let Err(e) = result {
        eprintln!("peer-rapier: {e}");
        std::process::exit(2);
    }
}
