//! The `tumble` command line: thin translation from arguments to the library.
//!
//! Exit status: 0 success, 2 bad input (file, argument, mesh), 1 internal failure.

mod cmd_bench;
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Mass(args) => cmd_mass::run(&args),
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
