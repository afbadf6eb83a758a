//! `tumble run`: simulates a scene file and writes an animated glTF and a
//! trajectory table. Outputs are written atomically after the simulation, so
//! a failed or interrupted run never leaves half a file behind.

use crate::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tumble::collide::{DVec3, HalfSpace};
use tumble::export::{write_glb, write_trajectory_csv, write_trajectory_npz, WorldRecorder};
use tumble::joint::urdf::{load_urdf, UrdfOptions};
use tumble::scene::load_scene;
use tumble::scenes::Scene;
use tumble::world::{BodyDesc, World, WorldSettings};

/// Arguments of `tumble run`.
#[derive(Args)]
#[command(after_long_help = RUN_EXAMPLES)]
pub struct RunArgs {
    /// Scene file (.toml or .json; see docs/scenes.md), or a URDF robot
    /// (.urdf), run standing on a ground plane at z = 0.
    #[arg(value_name = "SCENE")]
    scene: PathBuf,
    /// URDF: weld the robot's root link to the world.
    #[arg(long)]
    fixed_base: bool,
    /// URDF: where the root link's frame goes, "x,y,z" in metres (default 0,0,0).
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

The summary at the end gives steps, wall time, steps per second, the deepest
penetration seen and the change of total energy (kinetic + potential) from the
first to the last step. Exit status: 0 success, 2 bad input (scene file,
argument, output path), 1 internal failure.";

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
        None => DVec3::ZERO,
        Some(text) => {
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
        }
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
    };
    apply_overrides(args, &mut scene)?;
    let mut world = World::new(scene.settings.clone()).map_err(|e| CliError::Input(e.to_string()))?;
    let ground = HalfSpace::new(DVec3::Z, 0.0).map_err(|e| CliError::Internal(e.to_string()))?;
    world
        .add_body(&BodyDesc::fixed(ground).named("ground"))
        .map_err(|e| CliError::Internal(e.to_string()))?;
    let options = UrdfOptions {
        position,
        fixed_base: args.fixed_base,
        ..UrdfOptions::default()
    };
    let robot = load_urdf(&mut world, &args.scene, options).map_err(|e| CliError::Input(e.to_string()))?;
    if !args.quiet {
        for w in &robot.warnings {
            println!("warning: {w}");
        }
    }
    Ok((world, robot.name, scene.steps))
}

/// Runs the verb.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let trajectory_kind = check_outputs(args)?;
    let (mut world, name, steps) = if extension(&args.scene) == "urdf" {
        urdf_world(args)?
    } else {
        let mut loaded = load_scene(&args.scene).map_err(|e| CliError::Input(e.to_string()))?;
        apply_overrides(args, &mut loaded.scene)?;
        let (world, _ids) = loaded.build().map_err(|e| CliError::Input(e.to_string()))?;
        (world, loaded.scene.name.clone(), loaded.scene.steps)
    };
    let recording = args.out.is_some() || args.trajectory.is_some();
    let mut recorder = if recording {
        Some(WorldRecorder::new(&world).map_err(|e| CliError::Internal(e.to_string()))?)
    } else {
        None
    };

    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(steps as u64), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} steps, {elapsed} (eta {eta})")
                .expect("static template"),
        );
        bar.set_message(name.clone());
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
    for step in 1..=steps {
        let report = world.step();
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
        }
        bar.inc(1);
    }
    let wall = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let e1 = energy(&world);

    let mut written = Vec::new();
    if let Some(r) = recorder {
        let rec = r.finish();
        let write_err = |e: tumble::export::ExportError| CliError::Input(e.to_string());
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
    if !args.quiet {
        let dt = world.settings().dt;
        println!(
            "{}: {steps} steps of {dt:.6} s ({:.3} s simulated), {} bodies",
            name,
            steps as f64 * dt,
            world.body_count()
        );
        println!(
            "wall time {wall:.3} s, {:.1} steps/s ({:.3} ms/step)",
            steps as f64 / wall.max(1e-12),
            1000.0 * wall / steps as f64
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
    Ok(())
}
