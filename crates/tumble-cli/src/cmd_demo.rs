//! `tumble demo`: two demo simulations that write their outputs.
//!
//! 1. The domino run of shared/scenes.md through the full world pipeline
//!    (contacts, friction, sub-stepped solver), written as an animated glTF
//!    (`domino.glb`, for `viewer/` or Blender) and a trajectory table.
//! 2. The Dzhanibekov effect of a T-handle in zero gravity (free rigid body).
//!
//! The T-handle is a composite of two boxes; its mass properties come from the
//! composite rule, its body frame from the principal axes. It spins about the
//! intermediate axis with a 1% perturbation and is integrated with RK4. The
//! measured flip period is compared with the analytic period of Euler's
//! equations (Landau & Lifshitz, Mechanics, section 37).

use crate::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::PathBuf;
use tumble::body::RigidBody;
use tumble::export::{write_glb, write_trajectory_csv, WorldRecorder};
use tumble::integrate::{integrate, Integrator};
use tumble::scenes;
use tumble_collide::mass::{solid_box, MassProperties, MassSpec};
use tumble_collide::{DMat3, DVec3, Pose};

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

/// Complete elliptic integral of the first kind K(m), m = k^2, by the
/// arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(1 - m))).
fn elliptic_k(m: f64) -> f64 {
    let (mut a, mut g) = (1.0f64, (1.0 - m).sqrt());
    while (a - g).abs() > 1e-15 * a {
        (a, g) = (0.5 * (a + g), (a * g).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Period of the body-frame angular velocity of a torque-free rigid body
/// (moments `i` ascending, body-frame angular velocity `w`), Landau & Lifshitz 37:
/// T = 4 K(k^2) sqrt(I1 I2 I3 / ((I3 - I2)(L^2 - 2 E I1))) with
/// k^2 = (I2 - I1)(2 E I3 - L^2) / ((I3 - I2)(L^2 - 2 E I1)) when L^2 > 2 E I2,
/// and I1, I3 exchanged otherwise.
fn analytic_period(i: DVec3, w: DVec3) -> f64 {
    let two_e = i.x * w.x * w.x + i.y * w.y * w.y + i.z * w.z * w.z;
    let l2 = (i * w).length_squared();
    let (i1, i2, i3) = if l2 > two_e * i.y {
        (i.x, i.y, i.z)
    } else {
        (i.z, i.y, i.x)
    };
    let lam2 = (i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3);
    let k2 = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1));
    4.0 * elliptic_k(k2) / lam2.sqrt()
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
    // Shaft along z and a cross bar along x on top: a T-handle of steel-like density.
    let density = MassSpec::Density(7800.0);
    let shaft = solid_box(DVec3::new(0.01, 0.01, 0.05), density).map_err(|e| internal(&e))?;
    let bar = solid_box(DVec3::new(0.04, 0.01, 0.01), density)
        .map_err(|e| internal(&e))?
        .translated(DVec3::new(0.0, 0.0, 0.06));
    let handle = MassProperties::combine(&[shaft, bar]).map_err(|e| internal(&e))?;
    let frame = handle.principal();
    let axes = DMat3::from_quat(frame.rotation);
    let mid_axis = axes.y_axis; // moments ascending: column 1 is the intermediate axis
    let omega0 = 3.0 * mid_axis + 0.03 * axes.z_axis;

    let pose = Pose::new(frame.com, frame.rotation).map_err(|e| internal(&e))?;
    let mut body = RigidBody::new_dynamic(frame.mass, frame.moments, pose).map_err(|e| internal(&e))?;
    body.set_angular_velocity(omega0).map_err(|e| internal(&e))?;
    let expected = analytic_period(frame.moments, axes.transpose() * omega0);

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
    let mut bodies = [body];
    let mut crossings = Vec::new();
    let mut last_w2 = 0.0f64;
    let (e0, l0) = (bodies[0].kinetic_energy(), bodies[0].angular_momentum().length());
    for step in 0..=steps {
        let b = &bodies[0];
        let t = step as f64 * args.dt;
        let w = b.angular_velocity();
        let wb = b.orientation().inverse() * w;
        if step > 0 && last_w2 > 0.0 && wb.y <= 0.0 {
            // Linear interpolation of the downward zero crossing of the body-frame
            // intermediate component: one per period.
            crossings.push(t - args.dt * wb.y / (wb.y - last_w2));
        }
        last_w2 = wb.y;
        if step % 10 == 0 {
            let (x, q) = (b.position(), b.orientation());
            writeln!(
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
            )
            .map_err(io)?;
        }
        if step < steps {
            integrate(&mut bodies, DVec3::ZERO, args.dt, Integrator::Rk4).map_err(|e| internal(&e))?;
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    csv.flush().map_err(io)?;
    drop(csv);
    std::fs::rename(&tmp, &path).map_err(io)?;

    let b = &bodies[0];
    println!(
        "Dzhanibekov T-handle: mass {:.4} kg, principal moments {:.4e} {:.4e} {:.4e} kg m^2",
        frame.mass, frame.moments.x, frame.moments.y, frame.moments.z
    );
    println!(
        "simulated {:.1} s in {steps} RK4 steps of {} s",
        args.duration, args.dt
    );
    if crossings.len() >= 2 {
        let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        println!(
            "flip period: measured {measured:.4} s, analytic {expected:.4} s (error {:.3}%), {} flips",
            100.0 * (measured - expected).abs() / expected,
            2 * crossings.len()
        );
    } else {
        println!("flip period: analytic {expected:.4} s (simulate longer to measure it)");
    }
    println!(
        "energy drift {:.2e}, |L| drift {:.2e} (relative)",
        (b.kinetic_energy() - e0).abs() / e0,
        (b.angular_momentum().length() - l0).abs() / l0
    );
    println!("wrote {}", path.display());
    Ok(())
}
