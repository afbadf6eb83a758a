//! The `tumble` command line: thin translation from arguments to the library.
//!
//! Exit status: 0 success, 2 bad input (file, argument, mesh), 1 internal failure.

mod bench_tori;
mod cmd_bench;
mod cmd_collide;
mod cmd_demo;
mod cmd_mass;
mod cmd_run;
mod cmd_sweep;
mod cmd_view;
mod interrupt;
mod live_session;
mod mesh_spec;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// tumble: rigid body dynamics with exact triangle-mesh contact.
#[derive(Parser)]
#[command(
    name = "tumble",
    version,
    about,
    long_about = LONG_ABOUT,
    after_long_help = AFTER_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

const LONG_ABOUT: &str = "\
tumble simulates rigid bodies described by triangle meshes or primitives
(spheres, boxes, capsules, convex hulls, half-spaces), with exact mesh-mesh
contact, Coulomb friction and restitution. Scenes are TOML or JSON files
(docs/scenes.md, examples in examples/scenes/); results are animated glTF
files, trajectory tables (CSV, NumPy .npz) and a web viewer.

Conventions: SI units (m, kg, s), z up, gravity (0, 0, -9.81) by default,
quaternions (x, y, z, w), angular velocity in the world frame.";

const AFTER_HELP: &str = "\
Examples:
  tumble run examples/scenes/tori_pass.toml --out out/tori_pass.glb --trajectory out/tori_pass.npz
  tumble view out/tori_pass.glb
  tumble view examples/scenes/domino.toml
  tumble mass torus:R=1,r=0.3,n=50 --density 1000
  tumble bench --scene pyramid --steps 60
  tumble sweep examples/scenes/first.toml --param materials.rubber.restitution=0.2,0.5,0.8 --metric ball.rebound_z --out bounce.csv

Exit status:
  0  success
  2  bad input: a scene file, mesh, argument or output path (one line on
     stderr naming the file, line, column and field where there is one)
  1  internal failure
  130 interrupted (Ctrl-C or SIGTERM; `tumble run` writes its outputs first)

`tumble help VERB` (or `tumble VERB --help`) prints the manual of a verb.";

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene file; write an animated glTF (.glb) and a trajectory (.csv, .npz).
    #[command(long_about = "\
Simulate a scene file (.toml or .json) and report steps, wall time, steps per
second, the deepest penetration and the energy drift. With --out the motion is
written as an animated binary glTF (one node per body, a translation and a
rotation channel per moving body, one key per recorded step; z up is turned to
glTF's y up by the root node). With --trajectory the poses are written as a
table: CSV rows (t, body, x, y, z, qx, qy, qz, qw) or a NumPy .npz archive
(time[F], position[F, N, 3], orientation[F, N, 4] as x y z w, names[N]).
Files are written when the simulation has finished, atomically: an error never
leaves a partial file. Ctrl-C stops between two steps and writes the outputs for
the steps done (exit status 130); the trajectory is streamed to FILE.part while
the run goes; --checkpoint-every and --resume continue a run bit for bit.
A progress bar is drawn when stderr is a terminal.")]
    Run(cmd_run::RunArgs),
    /// Watch a recording (.glb) or a live simulation of a scene in the browser.
    #[command(long_about = "\
Serve the web viewer on 127.0.0.1 and print its URL. Given a .glb (from
`tumble run --out`), the page plays the recording: timeline, speed, orbit
camera, contact points and normals, energy and contact plots. Given a scene
file, every page load starts the simulation and streams each step to the page
over a WebSocket (/live), so the scene is watched while it is computed; a
click in the 3D view throws a ball into the running simulation.")]
    View(cmd_view::ViewArgs),
    /// Mass properties of a closed triangle mesh: volume, mass, centre of mass,
    /// inertia tensor about the centre of mass, principal moments and axes.
    Mass(cmd_mass::MassArgs),
    /// Collision queries between two meshes: intersection, triangle pairs,
    /// contacts, distance and tolerance.
    Collide(cmd_collide::CollideArgs),
    /// Run the built-in demo simulations and write their outputs.
    Demo(cmd_demo::DemoArgs),
    /// Run one standard scene and print its timing and quality figures as one
    /// JSON line (the format of the benchmark harness, docs/benchmarks.md).
    Bench(cmd_bench::BenchArgs),
    /// Run a scene once per combination of parameter values (on every core,
    /// or on a Ray cluster) into a results table (.parquet, .csv, .json).
    Sweep(cmd_sweep::SweepArgs),
}

/// An error the user can fix (exit status 2), an internal failure (1), or
/// an interrupted run (130).
pub enum CliError {
    /// Bad input: one line, exit status 2.
    Input(String),
    /// Something failed that is not the user's input (exit status 1).
    Internal(String),
    /// Stopped by Ctrl-C or SIGTERM after writing what it had (exit status 130).
    Interrupted(String),
}

/// Help and version go out as clap prints them; a usage error becomes the
/// one-line `tumble: error: ...` of every other bad input (exit status 2).
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            ExitCode::from(if e.use_stderr() { 2 } else { 0 })
        }
        _ => {
            // clap's message up to its usage block, without tips, on one line.
            let text = e.to_string();
            let parts: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .filter(|l| !l.is_empty() && !l.starts_with("tip:"))
                .collect();
            eprintln!("tumble: error: {}", parts.join(" ").trim_start_matches("error: "));
            ExitCode::from(2)
        }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let result = match cli.command {
        Command::Run(args) => cmd_run::run(&args),
        Command::View(args) => cmd_view::run(&args),
        Command::Mass(args) => cmd_mass::run(&args),
        Command::Collide(args) => cmd_collide::run(&args),
        Command::Demo(args) => cmd_demo::run(&args),
        Command::Bench(args) => cmd_bench::run(&args),
        Command::Sweep(args) => cmd_sweep::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError::Input(msg)) => {
            eprintln!("tumble: error: {msg}");
            ExitCode::from(2)
        }
        Err(CliError::Internal(msg)) => {
            eprintln!("tumble: internal error: {msg}");
            ExitCode::from(1)
        }
        Err(CliError::Interrupted(msg)) => {
            eprintln!("tumble: {msg}");
            ExitCode::from(interrupt::EXIT_INTERRUPTED)
        }
    }
}
