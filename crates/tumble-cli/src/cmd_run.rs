//! `tumble run`: simulates a scene file and writes an animated glTF and a
//! trajectory table. Outputs are written atomically after the simulation, so
//! a failed run never leaves half a file behind; Ctrl-C or SIGTERM stops the
//! run between two steps and the outputs are written for the steps done
//! (exit status 130). While the run goes the trajectory is streamed to
//! `FILE.part` (CSV, flushed in chunks), so a killed process leaves every
//! finished chunk; `--checkpoint-every` writes world snapshots that
//! `--resume` continues from, bit for bit.

use crate::{interrupt, CliError};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tumble::collide::{DVec3, HalfSpace};
use tumble::export::{write_glb, write_trajectory_csv, write_trajectory_npz, CsvStream, WorldRecorder};
use tumble::joint::urdf::{load_urdf, UrdfOptions};
use tumble::scene::load_scene;
use tumble::scenes::Scene;
use tumble::world::{BodyDesc, Snapshot, World, WorldSettings};

/// Arguments of `tumble run`.
#[derive(Args)]
#[command(after_long_help = RUN_EXAMPLES)]
pub struct RunArgs {
    /// Scene file (.toml or .json; see docs/scenes.md), or a URDF robot
    /// (.urdf), run standing on a ground plane at z = 0 (its lowest point
    /// on the plane, unless --base-position places it).
    #[arg(value_name = "SCENE")]
    scene: PathBuf,
    /// URDF: weld the robot's root link to the world.
    #[arg(long)]
    fixed_base: bool,
    /// URDF: let the robot's links touch each other (off by default, as in
    /// PyBullet: links of files written for other engines overlap beyond
    /// their joints).
    #[arg(long)]
    self_collision: bool,
    /// URDF: replace an inertia no body could have by the isotropic one of
    /// the same trace (as MuJoCo's balanceinertia), instead of refusing it.
    #[arg(long)]
    balance_inertia: bool,
    /// URDF: give each mesh link shape as its convex hull, as PyBullet and
    /// MuJoCo read them (fewer contacts between concave links such as
    /// hands and fingers, their hollows filled), instead of the exact mesh.
    #[arg(long)]
    convex_meshes: bool,
    /// URDF: where the root link's frame goes, "x,y,z" in metres (default: x = y = 0,
    /// z such that the robot's lowest point rests on the ground).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    base_position: Option<String>,
    /// Number of steps (default: the scene's `steps` or `duration`, else 10 s).
    #[arg(long, value_name = "N", conflicts_with = "duration")]
    steps: Option<u64>,
    /// Simulated time in seconds (steps = round(S / dt)).
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Time step in seconds, replacing the scene's `settings.dt`. Without
    /// --steps or --duration the scene's simulated time is kept.
    #[arg(long, value_name = "DT", allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Write the animation as binary glTF 2.0 (open with `tumble view FILE.glb`,
    /// Blender or any glTF viewer).
    #[arg(long, value_name = "FILE.glb")]
    out: Option<PathBuf>,
    /// Write the trajectory: .csv (t, body, x, y, z, qx, qy, qz, qw per row) or
    /// .npz (NumPy arrays time, position, orientation, names).
    #[arg(long, value_name = "FILE.csv|FILE.npz")]
    trajectory: Option<PathBuf>,
    /// Worker threads of the simulation, replacing the scene's
    /// `settings.threads` (0: every core, 1: serial). The trajectory is the
    /// same bits for any count.
    #[arg(long, value_name = "N")]
    threads: Option<u32>,
    /// Record every K-th step in the outputs (the first and last are always kept).
    #[arg(long, value_name = "K", default_value_t = 1)]
    every: u64,
    /// Write a snapshot of the world every N steps (and when the run is
    /// interrupted), to --checkpoint; `--resume` continues from it.
    #[arg(long, value_name = "N")]
    checkpoint_every: Option<u64>,
    /// Where --checkpoint-every writes (default: SCENE's stem + .snapshot in
    /// the current directory; .json for a readable snapshot).
    #[arg(long, value_name = "FILE", requires = "checkpoint_every")]
    checkpoint: Option<PathBuf>,
    /// Continue from a snapshot of this scene (from --checkpoint-every or
    /// World.save) up to the run's last step; the steps after it are those
    /// of an uninterrupted run, bit for bit. The outputs hold the resumed
    /// part, from the snapshot's time on.
    #[arg(long, value_name = "SNAPSHOT", conflicts_with = "dt")]
    resume: Option<PathBuf>,
    /// No progress bar and no summary.
    #[arg(long, short)]
    quiet: bool,
}

const RUN_EXAMPLES: &str = "\
Examples:
  tumble run examples/scenes/tori_pass.toml --out out/tori_pass.glb
  tumble run examples/scenes/chain.toml --steps 120 --trajectory out/chain.npz
  tumble run examples/scenes/cradle.toml --dt 0.001 --out cradle.glb --trajectory cradle.csv
  tumble run examples/robots/quadruped.urdf --base-position 0,0,0.4 --out dog.glb

  tumble run examples/scenes/chain.toml --duration 300 --trajectory x.csv --checkpoint-every 6000
  tumble run examples/scenes/chain.toml --duration 300 --trajectory y.csv --resume chain.snapshot

The summary at the end gives steps, wall time, steps per second, the deepest
penetration seen and the change of total energy (kinetic + potential) from the
first to the last step.

Ctrl-C (or SIGTERM) stops the run between two steps: the outputs are written
for the steps done, with a line saying so, and the exit status is 130 (a
second Ctrl-C ends the process at once). The trajectory is streamed to
FILE.part (CSV rows, flushed at least once a second) while the run goes and
removed when FILE is written, so even a killed run leaves its finished rows.

Exit status: 0 success, 2 bad input (scene file, argument, output path),
1 internal failure, 130 interrupted.";

/// Recorded frames between two flushes of the streamed trajectory (it is
/// flushed at least every STREAM_PERIOD too).
const STREAM_FRAMES: usize = 256;
/// Longest wall time between two flushes of the streamed trajectory.
const STREAM_PERIOD: std::time::Duration = std::time::Duration::from_secs(1);

/// What the trajectory file is.
enum TrajectoryKind {
    Csv,
    Npz,
}

fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

fn check_outputs(args: &RunArgs) -> Result<Option<TrajectoryKind>, CliError> {
    if let Some(out) = &args.out {
        if extension(out) != "glb" {
            return Err(CliError::Input(format!(
                "--out {}: the animation is written as binary glTF; give a .glb file",
                out.display()
            )));
        }
    }
    let kind = match &args.trajectory {
        None => None,
        Some(p) => match extension(p).as_str() {
            "csv" => Some(TrajectoryKind::Csv),
            "npz" => Some(TrajectoryKind::Npz),
            _ => {
                return Err(CliError::Input(format!(
                    "--trajectory {}: give a .csv or .npz file",
                    p.display()
                )))
            }
        },
    };
    for p in args.out.iter().chain(&args.trajectory) {
        if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| CliError::Input(format!("{}: cannot create directory: {e}", dir.display())))?;
        }
    }
    Ok(kind)
}

/// Applies --dt, --steps and --duration to the loaded scene.
fn apply_overrides(args: &RunArgs, scene: &mut Scene) -> Result<(), CliError> {
    let file_dt = scene.settings.dt;
    if let Some(dt) = args.dt {
        if !(dt.is_finite() && dt > 0.0 && dt <= 1.0) {
            return Err(CliError::Input(format!(
                "--dt must be finite, > 0 and at most 1 s, got {dt}"
            )));
        }
        scene.settings.dt = dt;
        // Keep the scene's simulated time.
        scene.steps = ((scene.steps as f64 * file_dt / dt).round() as usize).max(1);
    }
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(CliError::Input(format!(
                "--duration must be finite and > 0 s, got {d}"
            )));
        }
        scene.steps = ((d / scene.settings.dt).round() as usize).max(1);
    }
    if let Some(n) = args.steps {
        if n == 0 {
            return Err(CliError::Input("--steps must be >= 1".into()));
        }
        scene.steps = usize::try_from(n).map_err(|_| CliError::Input(format!("--steps too large: {n}")))?;
    }
    if args.every == 0 {
        return Err(CliError::Input("--every must be >= 1".into()));
    }
    if let Some(n) = args.threads {
        scene.settings.threads = n;
    }
    Ok(())
}

/// A URDF robot on a ground plane (default settings, 10 s), with the
/// overrides of the command line.
fn urdf_world(args: &RunArgs) -> Result<(World, String, usize), CliError> {
    let position = match &args.base_position {
        None => None,
        Some(text) => Some({
            let v: Vec<f64> = text
                .split(',')
                .map(|t| t.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| CliError::Input(format!("--base-position: expected x,y,z, got {text:?}")))?;
            match v.as_slice() {
                [x, y, z] if v.iter().all(|c| c.is_finite()) => DVec3::new(*x, *y, *z),
                _ => {
                    return Err(CliError::Input(format!(
                        "--base-position: expected x,y,z, got {text:?}"
                    )))
                }
            }
        }),
    };
    let settings = WorldSettings::default();
    let mut scene = Scene {
        name: args
            .scene
            .file_stem()
            .map_or("robot".into(), |s| s.to_string_lossy().into_owned()),
        steps: (tumble::scene::DEFAULT_DURATION / settings.dt).round() as usize,
        settings,
        bodies: Vec::new(),
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    };
    apply_overrides(args, &mut scene)?;
    let mut world = World::new(scene.settings.clone()).map_err(|e| CliError::Input(e.to_string()))?;
    let ground = HalfSpace::new(DVec3::Z, 0.0).map_err(|e| CliError::Internal(e.to_string()))?;
    world
        .add_body(&BodyDesc::fixed(ground).named("ground"))
        .map_err(|e| CliError::Internal(e.to_string()))?;
    let mut options = UrdfOptions {
        position: position.unwrap_or(DVec3::ZERO),
        fixed_base: args.fixed_base,
        self_collision: args.self_collision,
        balance_inertia: args.balance_inertia,
        convex_meshes: args.convex_meshes,
        ..UrdfOptions::default()
    };
    if position.is_none() {
        // Standing on the ground: the robot's lowest point at z = 0 (its
        // file's zero configuration may put it anywhere about its root).
        let mut probe = world.clone();
        let robot =
            load_urdf(&mut probe, &args.scene, options).map_err(|e| CliError::Input(e.to_string()))?;
        let lowest = robot
            .bodies
            .iter()
            .flat_map(|&id| {
                let pose = probe.body(id).expect("just added").pose();
                let colliders = probe.colliders(id).expect("just added");
                colliders
                    .iter()
                    .map(move |c| c.shape.aabb(&pose.mul_pose(&c.local)).min.z)
            })
            .fold(f64::INFINITY, f64::min);
        if lowest.is_finite() {
            options.position.z = -lowest;
        }
    }
    let robot = load_urdf(&mut world, &args.scene, options).map_err(|e| CliError::Input(e.to_string()))?;
    if !args.quiet {
        for w in &robot.warnings {
            println!("warning: {w}");
        }
        if !robot.no_contact.is_empty() {
            println!(
                "self-collision: links that overlap in the file's pose never touch (pairs kept apart: {})",
                robot.no_contact.len()
            );
        }
    }
    // A robot without a name (some exported files) goes by its file's.
    let name = match robot.name.is_empty() {
        true => Path::new(&args.scene)
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
        false => robot.name,
    };
    Ok((world, name, scene.steps))
}

/// The partial file written while the work goes: `FILE.part` (a run's
/// streamed trajectory, a sweep's journal).
pub fn part_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".part");
    PathBuf::from(name)
}

/// Where `--checkpoint-every` writes.
fn checkpoint_path(args: &RunArgs) -> PathBuf {
    args.checkpoint.clone().unwrap_or_else(|| {
        let stem = args
            .scene
            .file_stem()
            .map_or("tumble".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.snapshot"))
    })
}

/// The world of `--resume`: the snapshot, checked against the scene's world
/// (same bodies, by name, in the same order) and before the run's end.
fn resumed_world(args: &RunArgs, scene_world: &World, steps: usize, path: &Path) -> Result<World, CliError> {
    let bad = |m: String| CliError::Input(format!("--resume {}: {m}", path.display()));
    let snapshot = Snapshot::load(path).map_err(|e| bad(e.to_string()))?;
    let mut world = World::from_snapshot(&snapshot).map_err(|e| bad(e.to_string()))?;
    let names = |w: &World| -> Vec<String> {
        w.body_ids()
            .into_iter()
            .map(|id| w.name(id).unwrap_or_default().to_string())
            .collect()
    };
    if names(&world) != names(scene_world) {
        return Err(bad(format!(
            "not a snapshot of {}: it has {} bodies, the scene {} (or their names differ)",
            args.scene.display(),
            world.body_count(),
            scene_world.body_count()
        )));
    }
    if world.step_count() >= steps as u64 {
        return Err(bad(format!(
            "the snapshot is at step {}, the run ends at step {steps}: nothing to resume (give --steps or --duration)",
            world.step_count()
        )));
    }
    if let Some(n) = args.threads {
        let mut settings = world.settings().clone();
        settings.threads = n;
        world
            .set_settings(settings)
            .map_err(|e| CliError::Input(e.to_string()))?;
    }
    Ok(world)
}

/// Runs the verb.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let trajectory_kind = check_outputs(args)?;
    if args.checkpoint_every == Some(0) {
        return Err(CliError::Input("--checkpoint-every must be >= 1".into()));
    }
    let (mut world, name, steps) = if extension(&args.scene) == "urdf" {
        urdf_world(args)?
    } else {
        let mut loaded = load_scene(&args.scene).map_err(|e| CliError::Input(e.to_string()))?;
        apply_overrides(args, &mut loaded.scene)?;
        let (world, _ids) = loaded.build().map_err(|e| CliError::Input(e.to_string()))?;
        (world, loaded.scene.name.clone(), loaded.scene.steps)
    };
    if let Some(path) = &args.resume {
        world = resumed_world(args, &world, steps, path)?;
    }
    let first_step = world.step_count() as usize + 1;
    let checkpoint = args.checkpoint_every.map(|n| (n, checkpoint_path(args)));
    let recording = args.out.is_some() || args.trajectory.is_some();
    let mut recorder = if recording {
        Some(WorldRecorder::new(&world).map_err(|e| CliError::Internal(e.to_string()))?)
    } else {
        None
    };
    let write_err = |e: tumble::export::ExportError| CliError::Input(e.to_string());
    let mut stream = match (&args.trajectory, &recorder) {
        (Some(p), Some(r)) => Some(CsvStream::create(part_path(p), r.recording()).map_err(write_err)?),
        _ => None,
    };
    interrupt::install();

    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(steps as u64), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} steps, {elapsed} (eta {eta})")
                .expect("static template"),
        );
        bar.set_message(name.clone());
        bar.set_position(first_step as u64 - 1);
        bar
    };
    let energy = |w: &tumble::world::World| w.kinetic_energy() + w.potential_energy();
    let e0 = energy(&world);
    let mut max_penetration: f64 = 0.0;
    // Largest joint error over the run: linear (m) and angular (rad).
    let mut joint_error = (0.0f64, 0.0f64);
    let mut warnings: Vec<String> = Vec::new();
    let mut quarantined = 0usize;
    let started = Instant::now();
    let mut flushed = Instant::now();
    let mut last_step = first_step - 1;
    for step in first_step..=steps {
        if interrupt::requested() {
            break;
        }
        let report = world.step();
        last_step = step;
        max_penetration = max_penetration.max(report.max_penetration);
        if world.joint_count() > 0 {
            let (l, a) = world.max_joint_error();
            joint_error = (joint_error.0.max(l), joint_error.1.max(a));
        }
        quarantined += report.quarantined.len();
        for w in report.warnings {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
        if let Some(r) = recorder.as_mut() {
            if (step as u64).is_multiple_of(args.every) || step == steps {
                r.record(&world);
            }
            if let Some(s) = stream.as_mut() {
                let pending = r.frames() - s.frames_written();
                if pending >= STREAM_FRAMES || (pending > 0 && flushed.elapsed() >= STREAM_PERIOD) {
                    s.append(r.recording()).map_err(write_err)?;
                    flushed = Instant::now();
                }
            }
        }
        if let Some((every, path)) = &checkpoint {
            if (step as u64).is_multiple_of(*every) {
                save_checkpoint(&world, path)?;
            }
        }
        bar.inc(1);
    }
    let interrupted = last_step < steps;
    let done = last_step + 1 - first_step;
    let wall = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let e1 = energy(&world);
    if interrupted {
        // The last state simulated is a frame of the outputs and a checkpoint.
        if let Some(r) = recorder.as_mut() {
            if r.recording().frame_times.last() != Some(&world.time()) {
                r.record(&world);
            }
        }
        if let Some((_, path)) = &checkpoint {
            save_checkpoint(&world, path)?;
        }
    }

    let mut written = Vec::new();
    if let Some(r) = recorder {
        let rec = r.finish();
        if let Some(out) = &args.out {
            write_glb(&rec, out).map_err(write_err)?;
            written.push(out.display().to_string());
        }
        if let (Some(p), Some(kind)) = (&args.trajectory, trajectory_kind) {
            match kind {
                TrajectoryKind::Csv => write_trajectory_csv(&rec, p),
                TrajectoryKind::Npz => write_trajectory_npz(&rec, p),
            }
            .map_err(write_err)?;
            written.push(p.display().to_string());
        }
    }
    if let Some(s) = stream {
        // The whole file is in place: the partial one has served.
        let _ = std::fs::remove_file(s.path());
    }
    if let Some((_, path)) = &checkpoint {
        written.push(format!(
            "{} (snapshot at step {})",
            path.display(),
            world.step_count()
        ));
    }
    if !args.quiet {
        let dt = world.settings().dt;
        let resumed = if first_step > 1 {
            format!(", resumed at step {}", first_step - 1)
        } else {
            String::new()
        };
        println!(
            "{}: {done} steps of {dt:.6} s ({:.3} s simulated{resumed}), {} bodies",
            name,
            done as f64 * dt,
            world.body_count()
        );
        println!(
            "wall time {wall:.3} s, {:.1} steps/s ({:.3} ms/step)",
            done as f64 / wall.max(1e-12),
            1000.0 * wall / done.max(1) as f64
        );
        println!("max penetration {:.3} mm", max_penetration * 1000.0);
        if world.joint_count() > 0 {
            println!(
                "largest joint error {:.3} mm, {:.4} rad ({} joints)",
                joint_error.0 * 1000.0,
                joint_error.1,
                world.joint_count()
            );
        }
        let rel = if e0.abs() > 1e-12 {
            format!(" ({:+.3}% of the start)", 100.0 * (e1 - e0) / e0.abs())
        } else {
            String::new()
        };
        println!(
            "energy drift (kinetic + potential, end - start): {:+.6e} J{rel}",
            e1 - e0
        );
        if quarantined > 0 {
            println!("warning: {quarantined} body-steps quarantined (non-finite state rolled back)");
        }
        for w in &warnings {
            println!("warning: {w}");
        }
        if !written.is_empty() {
            println!("wrote {}", written.join(", "));
        }
    }
    if interrupted {
        return Err(CliError::Interrupted(format!(
            "interrupted at step {last_step} of {steps} (t = {:.6} s); the outputs hold the steps done",
            world.time()
        )));
    }
    Ok(())
}

fn save_checkpoint(world: &World, path: &Path) -> Result<(), CliError> {
    world
        .snapshot()
        .save(path)
        .map_err(|e| CliError::Input(format!("--checkpoint {}: {e}", path.display())))
}
