//! The `tumble` command line: thin translation from arguments to the library.
//!
//! Exit status: 0 success, 2 bad input (file, argument, mesh), 1 internal failure.

mod bench_tori;
mod cmd_bench;
mod cmd_collide;
mod cmd_demo;
mod cmd_mass;
mod mesh_spec;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// tumble: rigid body dynamics with exact triangle-mesh contact.
#[derive(Parser)]
#[command(name = "tumble", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
}

/// An error the user can fix (exit status 2) or an internal failure (1).
pub enum CliError {
    /// Bad input: one line, exit status 2.
    Input(String),
    /// Something failed that is not the user's input (exit status 1).
    Internal(String),
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
        Command::Mass(args) => cmd_mass::run(&args),
        Command::Collide(args) => cmd_collide::run(&args),
        Command::Demo(args) => cmd_demo::run(&args),
        Command::Bench(args) => cmd_bench::run(&args),
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
    }
}
