//! `tumble demo`: two demo simulations that write their outputs.
//!
//! 1. The domino run of shared/scenes.md through the full world pipeline
//!    (contacts, friction, sub-stepped solver), written as an animated glTF
//!    (`domino.glb`, for `viewer/` or Blender) and a trajectory table.
//! 2. The Dzhanibekov effect of a T-handle in zero gravity (free rigid body).
//!
//! Both are defined in the library (`tumble::scenes::domino`,
//! `tumble::scenes::t_handle` and `run_flips`, with the analytic flip period
//! of `tumble::analytic`); this verb runs them and writes and prints what
//! they give.

use crate::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::PathBuf;
use tumble::export::{write_glb, write_trajectory_csv, WorldRecorder};
use tumble::scenes;
use tumble_collide::DVec3;

/// Arguments of `tumble demo`.
#[derive(Args)]
pub struct DemoArgs {
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Simulated time (s).
    #[arg(long, default_value_t = 20.0)]
    duration: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 1e-3)]
    dt: f64,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Simulates the domino run for 10 s and writes `domino.glb` and `domino.csv`.
fn domino(args: &DemoArgs) -> Result<(), CliError> {
    let internal = |e: &dyn std::fmt::Display| CliError::Internal(e.to_string());
    let scene = scenes::domino();
    let (mut world, ids) = scene.build().map_err(|e| internal(&e))?;
    let mut recorder = WorldRecorder::new(&world).map_err(|e| internal(&e))?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(scene.steps as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("domino {bar:40} {pos}/{len} steps {elapsed}").expect("static template"),
    );
    let started = std::time::Instant::now();
    let mut max_penetration: f64 = 0.0;
    for _ in 0..scene.steps {
        max_penetration = max_penetration.max(world.step().max_penetration);
        recorder.record(&world);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    let recording = recorder.finish();
    let glb = args.out.join("domino.glb");
    let csv = args.out.join("domino.csv");
    write_glb(&recording, &glb).map_err(|e| CliError::Input(e.to_string()))?;
    write_trajectory_csv(&recording, &csv).map_err(|e| CliError::Input(e.to_string()))?;
    // A domino has fallen when its tall axis is closer to horizontal than vertical.
    let fallen = ids[1..]
        .iter()
        .filter(|&&id| {
            let up = world.orientation(id).map(|q| q * DVec3::Z).unwrap_or(DVec3::Z);
            up.z.abs() < 0.7
        })
        .count();
    println!(
        "domino: {} steps of {:.4} s in {wall:.2} s ({:.0} steps/s), {fallen} of {} dominoes fell, deepest penetration {:.2} mm",
        scene.steps,
        world.settings().dt,
        scene.steps as f64 / wall,
        ids.len() - 1,
        max_penetration * 1000.0
    );
    println!("wrote {} and {}", glb.display(), csv.display());
    Ok(())
}

/// Runs the demo.
pub fn run(args: &DemoArgs) -> Result<(), CliError> {
    if !(args.dt.is_finite() && args.dt > 0.0 && args.duration.is_finite() && args.duration > 0.0) {
        return Err(CliError::Input(format!(
            "--dt and --duration must be finite and > 0, got {} and {}",
            args.dt, args.duration
        )));
    }
    let internal = |e: &dyn std::fmt::Display| CliError::Internal(e.to_string());
    let handle = scenes::t_handle();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| CliError::Input(format!("{}: cannot create directory: {e}", args.out.display())))?;
    domino(args)?;
    let path = args.out.join("dzhanibekov.csv");
    let tmp = args.out.join(".dzhanibekov.csv.tmp");
    let file = std::fs::File::create(&tmp)
        .map_err(|e| CliError::Input(format!("{}: cannot write: {e}", tmp.display())))?;
    let mut csv = std::io::BufWriter::new(file);
    let io = |e: std::io::Error| CliError::Internal(e.to_string());
    writeln!(
        csv,
        "t,x,y,z,qx,qy,qz,qw,wx,wy,wz,w1_body,w2_body,w3_body,kinetic_energy,angular_momentum"
    )
    .map_err(io)?;

    let steps = (args.duration / args.dt).round() as usize;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(steps as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed}").expect("static template"),
    );
    let mut write_error = None;
    let run = scenes::run_flips(&handle, args.duration, args.dt, |step, t, b, wb| {
        if step % 10 == 0 && write_error.is_none() {
            let (x, q, w) = (b.position(), b.orientation(), b.angular_velocity());
            let row = writeln!(
                csv,
                "{t:.6},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                x.x,
                x.y,
                x.z,
                q.x,
                q.y,
                q.z,
                q.w,
                w.x,
                w.y,
                w.z,
                wb.x,
                wb.y,
                wb.z,
                b.kinetic_energy(),
                b.angular_momentum().length()
            );
            write_error = row.err();
        }
        bar.inc(1);
    })
    .map_err(|e| internal(&e))?;
    if let Some(e) = write_error {
        return Err(io(e));
    }
    bar.finish_and_clear();
    csv.flush().map_err(io)?;
    drop(csv);
    std::fs::rename(&tmp, &path).map_err(io)?;

    let m = handle.moments;
    println!(
        "Dzhanibekov T-handle: mass {:.4} kg, principal moments {:.4e} {:.4e} {:.4e} kg m^2",
        handle.body.mass(),
        m.x,
        m.y,
        m.z
    );
    println!(
        "simulated {:.1} s in {} RK4 steps of {} s",
        args.duration, run.steps, args.dt
    );
    let expected = handle.period;
    match run.measured_period {
        Some(measured) => println!(
            "flip period: measured {measured:.4} s, analytic {expected:.4} s (error {:.3}%), {} flips",
            100.0 * (measured - expected).abs() / expected,
            run.flips
        ),
        None => println!("flip period: analytic {expected:.4} s (simulate longer to measure it)"),
    }
    println!(
        "energy drift {:.2e}, |L| drift {:.2e} (relative)",
        run.energy_drift, run.momentum_drift
    );
    println!("wrote {}", path.display());
    Ok(())
}
