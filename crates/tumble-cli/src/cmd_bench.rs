//! `tumble bench`: runs one standard scene (shared/scenes.md) and prints one
//! JSON line with the timing and quality figures that the side-by-side
//! harness (`bench/run.py`, docs/benchmarks.md) compares with peer engines.

use crate::CliError;
use clap::Args;
use serde_json::{json, Value};
use std::time::Instant;
use tumble::scenes::{self, Scene};
use tumble::world::{BodyId, World};

/// Arguments of `tumble bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Scene: pyramid, large_pyramid, pile (with --n), chain,
    /// chain_decomposed, cradle, bowl, heavy_chain, ragdoll_pile, concave_pile
    /// or tori.
    #[arg(long)]
    scene: String,
    /// Steps to run (default: the scene's own, 600 or 240).
    #[arg(long)]
    steps: Option<usize>,
    /// Bodies in the pile: 100, 1000 or 10000 (a multiple of 100).
    #[arg(long, default_value_t = 1000)]
    n: usize,
    /// Worker threads of the world (0: every core). Default 1, so that
    /// figures compare with single-threaded peers unless asked otherwise.
    #[arg(long, default_value_t = 1)]
    threads: u32,
    /// With --threads T > 1: time one thread and T threads on the same run,
    /// in alternating blocks of steps (1, T, T, 1, 1, T, ...; adaptive
    /// threads off), so that a machine whose speed drifts over minutes
    /// slows both alike. The trajectory is the one any thread count gives
    /// (bit-identical). `step_time` is then the T-thread steps', beside
    /// `one_thread_step_time` and `paired_speedup` (the one-thread steps'
    /// total time over the T-thread steps').
    #[arg(long)]
    paired: bool,
    /// Tori poses: P poses spread evenly over the 200 (default all).
    #[arg(long)]
    poses: Option<usize>,
    /// Instead of running the scene, write it as plain data (JSON: bodies in
    /// their body frames with tumble's masses and inertias, shapes, meshes,
    /// joints; for tori the torus and the --poses poses) to FILE, or to
    /// standard output for `-`: what the benchmark's Python peers build
    /// their worlds from.
    #[arg(long, value_name = "FILE")]
    export_scene: Option<std::path::PathBuf>,
}

pub(crate) fn peak_rss_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map(|kb| kb * 1024)
        .unwrap_or(0)
}

/// Steps of one block of `--paired`: long enough that a switch of thread
/// count (the data moving to another core's cache) is a small part of it.
const PAIRED_BLOCK: usize = 10;

/// The step times of a run (s), and with `--paired` the thread count of
/// each block.
struct Timer {
    /// `Some(T)` with `--paired`: blocks alternate between 1 and T threads.
    paired: Option<u32>,
    /// With `--paired`, each step's time by the thread count of its block.
    one_thread: Vec<f64>,
    threaded: Vec<f64>,
    /// Steps that ran on more than one thread.
    on_threads: usize,
}

impl Timer {
    /// Threads of step `i` with `--paired`: blocks in the order 1, T, T, 1,
    /// 1, T, ..., so that a steady trend in the step's cost (a pile coming
    /// to rest) favours neither.
    fn threads_of(&self, i: usize) -> Option<u32> {
        self.paired.map(|t| {
            let block = i / PAIRED_BLOCK;
            if matches!(block % 4, 1 | 2) {
                t
            } else {
                1
            }
        })
    }
}

/// Steps the world, timing each step call (s); `each` sees the world after
/// every step. With `--paired`, sets the thread count of each block first.
fn run_timed(
    world: &mut World,
    steps: usize,
    timer: &mut Timer,
    mut each: impl FnMut(usize, &World, f64),
) -> Result<Vec<f64>, CliError> {
    let mut times = Vec::with_capacity(steps);
    for i in 0..steps {
        if let Some(threads) = timer.threads_of(i) {
            if world.settings().threads != threads {
                let mut settings = world.settings().clone();
                settings.threads = threads;
                world
                    .set_settings(settings)
                    .map_err(|e| CliError::Internal(e.to_string()))?;
            }
        }
        let t = Instant::now();
        let report = world.step();
        let t = t.elapsed().as_secs_f64();
        times.push(t);
        timer.on_threads += usize::from(report.threads > 1);
        // By the count the block asked for: a step too small for the
        // threads runs on one thread either way (`World::step`).
        match timer.threads_of(i) {
            Some(threads) if threads > 1 => timer.threaded.push(t),
            Some(_) => timer.one_thread.push(t),
            None => {}
        }
        each(i, world, report.max_penetration);
    }
    Ok(times)
}

fn centre(world: &World, id: BodyId) -> tumble_collide::DVec3 {
    world.center_of_mass(id).unwrap_or(tumble_collide::DVec3::NAN)
}

/// Writes `scene` as plain JSON to `path` (`-`: standard output).
fn export_scene(scene: &Scene, path: &std::path::Path) -> Result<(), CliError> {
    let json = scene
        .to_plain_json()
        .map_err(|e| CliError::Input(format!("{}: {e}", scene.name)))?;
    write_json(&json, path)
}

/// Writes `json` on one line to `path` (`-`: standard output).
fn write_json(json: &Value, path: &std::path::Path) -> Result<(), CliError> {
    let text = json.to_string();
    if path.as_os_str() == "-" {
        println!("{text}");
        Ok(())
    } else {
        std::fs::write(path, text + "\n")
            .map_err(|e| CliError::Input(format!("{}: cannot write: {e}", path.display())))
    }
}

/// Runs the verb.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let (name, mut scene): (String, Scene) = match args.scene.as_str() {
        "pyramid" => ("pyramid".into(), scenes::pyramid()),
        "large_pyramid" => ("large_pyramid".into(), scenes::large_pyramid()),
        "chain" => ("chain".into(), scenes::chain()),
        "chain_decomposed" => ("chain_decomposed".into(), scenes::chain_decomposed()),
        "cradle" => ("cradle".into(), scenes::cradle()),
        "bowl" => ("bowl".into(), scenes::bowl_swing(true)),
        "heavy_chain" => ("heavy_chain".into(), scenes::heavy_chain()),
        "ragdoll_pile" => ("ragdoll_pile".into(), scenes::ragdoll_pile()),
        "concave_pile" => (
            "concave_pile".into(),
            scenes::concave_pile(scenes::CONCAVE_PILE_BODIES),
        ),
        s if s.starts_with("pile") => {
            let n = s.trim_start_matches("pile").parse::<usize>().unwrap_or(args.n);
            if n == 0 || n % 100 != 0 || n > 100_000 {
                return Err(CliError::Input(format!(
                    "--n must be a positive multiple of 100 (at most 100000), got {n}"
                )));
            }
            (format!("pile{n}"), scenes::pile(n / 100))
        }
        "tori" => {
            let poses = args.poses.unwrap_or(crate::bench_tori::TORI_POSES);
            if poses == 0 {
                return Err(CliError::Input("--poses must be at least 1".into()));
            }
            if let Some(path) = &args.export_scene {
                let json = scenes::tori_plain_json(poses).map_err(|e| CliError::Internal(e.to_string()))?;
                return write_json(&json, path);
            }
            let (settings, figures) = crate::bench_tori::run(poses)?;
            let out = json!({
                "engine": "tumble",
                "version": env!("CARGO_PKG_VERSION"),
                "scene": "tori",
                "status": "ok",
                "settings": settings,
                "figures": figures,
                "peak_rss_bytes": peak_rss_bytes(),
            });
            println!("{out}");
            return Ok(());
        }
        other => {
            return Err(CliError::Input(format!(
                "unknown scene '{other}' (expected pyramid, large_pyramid, pile, chain, chain_decomposed, cradle, bowl, heavy_chain, ragdoll_pile, concave_pile, tori)"
            )))
        }
    };
    if let Some(path) = &args.export_scene {
        return export_scene(&scene, path);
    }
    let steps = args.steps.unwrap_or(scene.steps);
    scene.settings.threads = args.threads;
    if args.paired {
        if args.threads == 1 {
            return Err(CliError::Input(
                "--paired compares one thread with --threads T: give T > 1 (or 0, every core)".into(),
            ));
        }
        if steps < 2 * PAIRED_BLOCK {
            return Err(CliError::Input(format!(
                "--paired times blocks of {PAIRED_BLOCK} steps on each thread count: give --steps {} or more, got {steps}",
                2 * PAIRED_BLOCK
            )));
        }
        scene.settings.adaptive_threads = false;
    }
    let (mut world, ids) = scene.build().map_err(|e| CliError::Input(e.to_string()))?;
    let settings = world.settings().clone();
    let start: Vec<_> = ids.iter().map(|&id| centre(&world, id)).collect();
    let mut deepest: f64 = 0.0;
    let mut figures = serde_json::Map::new();
    let mut timer = Timer {
        paired: args.paired.then(|| world.threads() as u32),
        one_thread: Vec::new(),
        threaded: Vec::new(),
        on_threads: 0,
    };
    let times = match name.as_str() {
        "pyramid" | "large_pyramid" => {
            let t = run_timed(&mut world, steps, &mut timer, |_, _, p| deepest = deepest.max(p))?;
            let moved: Vec<f64> = ids
                .iter()
                .zip(&start)
                .map(|(&id, s)| (centre(&world, id) - *s).length())
                .collect();
            figures.insert("top_box_displacement_m".into(), json!(moved[moved.len() - 1]));
            figures.insert(
                "largest_displacement_m".into(),
                json!(moved.iter().skip(1).fold(0.0f64, |m, &x| m.max(x))),
            );
            t
        }
        "concave_pile" => {
            // Escapes, the kinetic energy left, and how many contact points
            // the mesh pairs make (the cost the contact reduction
            // is about), besides the deepest overlap of every step.
            let (mut most_points, mut points) = (0usize, 0usize);
            // The goal is "at rest within 5 s": the energy then.
            let five_seconds = (5.0 / settings.dt).round() as usize;
            let mut at_five = None;
            let t = run_timed(&mut world, steps, &mut timer, |i, w, p| {
                deepest = deepest.max(p);
                if i + 1 == five_seconds {
                    at_five = Some(w.kinetic_energy());
                }
                if i % 10 == 9 || i + 1 == steps {
                    let mut per_pair = std::collections::BTreeMap::new();
                    for c in w.contacts() {
                        *per_pair.entry((c.body_a, c.body_b)).or_insert(0usize) += 1;
                    }
                    most_points = most_points.max(per_pair.values().copied().max().unwrap_or(0));
                    points = points.max(w.contacts().len());
                }
            })?;
            let centres: Vec<_> = ids.iter().skip(1).map(|&id| centre(&world, id)).collect();
            figures.insert(
                "bodies_escaped".into(),
                json!(scenes::concave_pile_escaped(&centres)),
            );
            figures.insert("final_kinetic_energy_j".into(), json!(world.kinetic_energy()));
            figures.insert("kinetic_energy_at_5s_j".into(), json!(at_five));
            figures.insert("most_contact_points".into(), json!(points));
            figures.insert("most_points_in_one_pair".into(), json!(most_points));
            t
        }
        "chain" | "chain_decomposed" => {
            let reach = scenes::CHAIN_MAX_CENTRE_DISTANCE;
            let mut widest: f64 = 0.0;
            let t = run_timed(&mut world, steps, &mut timer, |i, w, p| {
                deepest = deepest.max(p);
                if i % 10 == 0 {
                    for pair in ids.windows(2) {
                        widest = widest.max((centre(w, pair[0]) - centre(w, pair[1])).length());
                    }
                }
            })?;
            let broken = ids
                .windows(2)
                .filter(|p| (centre(&world, p[0]) - centre(&world, p[1])).length() > reach)
                .count();
            figures.insert(
                "interlock_held".into(),
                json!(if widest <= reach { "yes" } else { "no" }),
            );
            figures.insert("max_adjacent_centre_distance_m".into(), json!(widest));
            figures.insert("broken_links".into(), json!(broken));
            t
        }
        "heavy_chain" | "ragdoll_pile" => {
            // The largest joint gap (m) and misalignment (rad), every 10 steps.
            let mut worst = (0.0f64, 0.0f64);
            let t = run_timed(&mut world, steps, &mut timer, |i, w, p| {
                deepest = deepest.max(p);
                if i % 10 == 9 || i + 1 == steps {
                    let (l, a) = w.max_joint_error();
                    worst = (worst.0.max(l), worst.1.max(a));
                }
            })?;
            figures.insert("largest_joint_error_m".into(), json!(worst.0));
            figures.insert("largest_joint_angle_error_rad".into(), json!(worst.1));
            figures.insert("final_joint_error_m".into(), json!(world.max_joint_error().0));
            if name == "heavy_chain" {
                // The weight's distance from the pivot: 2.1 m when nothing stretches.
                let weight = centre(&world, ids[ids.len() - 1]);
                figures.insert(
                    "weight_distance_m".into(),
                    json!((weight - tumble_collide::DVec3::new(0.0, 0.0, 2.0)).length()),
                );
            } else {
                let fallen = ids
                    .iter()
                    .skip(1)
                    .filter(|&&id| centre(&world, id).z < 0.0 || !centre(&world, id).is_finite())
                    .count();
                figures.insert("bodies_below_ground".into(), json!(fallen));
            }
            t
        }
        "bowl" => {
            // The swing's period and the amplitude it keeps after two
            // oscillations, on the smooth surface (timed) and on the bare
            // facets (a second, untimed run of the same scene without it).
            let swing = |w: &World| scenes::swing_angle(centre(w, ids[1]), false);
            let mut meter = scenes::SwingMeter::new(settings.dt, swing(&world));
            let t = run_timed(&mut world, steps, &mut timer, |_, w, p| {
                deepest = deepest.max(p);
                meter.observe(swing(w));
            })?;
            let phi0 = scenes::BOWL_START_DEG.to_radians();
            let want = tumble::analytic::rolling_period(
                scenes::BOWL_RADIUS - scenes::BOWL_BALL_RADIUS,
                0.4,
                phi0,
                settings.gravity.length(),
            );
            let (mut facets, facet_ids) = scenes::bowl_swing(false)
                .build()
                .map_err(|e| CliError::Internal(e.to_string()))?;
            let mut facet_meter = scenes::SwingMeter::new(settings.dt, phi0);
            for _ in 0..steps {
                facets.step();
                facet_meter.observe(scenes::swing_angle(centre(&facets, facet_ids[1]), false));
            }
            figures.insert("period_s".into(), json!(meter.period()));
            figures.insert("rolling_period_s".into(), json!(want));
            figures.insert(
                "period_error".into(),
                json!(meter.period().map(|p| p / want - 1.0)),
            );
            figures.insert(
                "amplitude_kept".into(),
                json!(meter.amplitude_after_two().map(|a| a / phi0)),
            );
            figures.insert(
                "amplitude_kept_facets".into(),
                json!(facet_meter.amplitude_after_two().map(|a| a / phi0)),
            );
            t
        }
        "cradle" => {
            let mass = |w: &World, id| w.body(id).map(|b| b.mass()).unwrap_or(0.0);
            let p0: f64 = ids
                .iter()
                .map(|&id| mass(&world, id) * world.linear_velocity(id).unwrap_or_default().x)
                .sum();
            let e0 = world.kinetic_energy();
            let t = run_timed(&mut world, steps, &mut timer, |_, _, p| deepest = deepest.max(p))?;
            let vx: Vec<f64> = ids
                .iter()
                .map(|&id| world.linear_velocity(id).unwrap_or_default().x)
                .collect();
            let p1: f64 = ids
                .iter()
                .map(|&id| mass(&world, id) * world.linear_velocity(id).unwrap_or_default().x)
                .sum();
            figures.insert("final_velocities_x".into(), json!(vx));
            figures.insert("last_sphere_vx".into(), json!(vx[4]));
            figures.insert("momentum_error".into(), json!((p1 - p0).abs()));
            figures.insert(
                "energy_error".into(),
                json!((world.kinetic_energy() - e0).abs() / e0),
            );
            t
        }
        _ => {
            let t = run_timed(&mut world, steps, &mut timer, |_, _, p| deepest = deepest.max(p))?;
            let dynamic: Vec<_> = ids.iter().skip(5).map(|&id| centre(&world, id)).collect();
            figures.insert("bodies_outside".into(), json!(scenes::pile_outside(&dynamic)));
            figures.insert(
                "mean_final_height_m".into(),
                json!(dynamic.iter().map(|c| c.z).sum::<f64>() / dynamic.len() as f64),
            );
            figures.insert("contact_points".into(), json!(world.contacts().len()));
            // Whether the pile has come to rest (a pile can keep its
            // overlaps small by boiling): translational and rotational.
            figures.insert("final_kinetic_energy_j".into(), json!(world.kinetic_energy()));
            t
        }
    };
    figures.insert("deepest_penetration_m".into(), json!(deepest));
    if timer.paired.is_some() {
        // The same run's steps on one thread and on the threads (adaptive
        // threads off, so every step ran on the count its block asked for).
        figures.insert(
            "step_time".into(),
            json!(scenes::TimingStats::ms(&timer.threaded)),
        );
        figures.insert(
            "one_thread_step_time".into(),
            json!(scenes::TimingStats::ms(&timer.one_thread)),
        );
        let total = |t: &[f64]| t.iter().sum::<f64>();
        figures.insert(
            "paired_speedup".into(),
            json!(total(&timer.one_thread) / total(&timer.threaded)),
        );
    } else {
        figures.insert("step_time".into(), json!(scenes::TimingStats::ms(&times)));
    }
    // With `adaptive_threads` a step runs on one thread while the threads
    // are measured slower: how many ran on the threads.
    figures.insert("steps_on_threads".into(), json!(timer.on_threads));
    // A paired run ends on whichever count its last block had: it ran
    // for the T of `--threads`.
    let threads = timer.paired.map_or(world.threads(), |t| t as usize);
    let out = json!({
        "engine": "tumble",
        "version": env!("CARGO_PKG_VERSION"),
        "scene": name,
        "status": "ok",
        "settings": {"dt": settings.dt, "steps": steps, "n": ids.len(), "substeps": settings.substeps,
                     "iterations": settings.iterations, "threads": threads,
                     "adaptive_threads": settings.adaptive_threads, "paired": args.paired},
        "figures": figures,
        "peak_rss_bytes": peak_rss_bytes(),
    });
    println!("{out}");
    Ok(())
}
