//! `subdiv`: glue between the command line and the subdiv library crates.
//!
//! `main` turns every failure into one line on stderr and an exit code
//! (SPEC §6): 0 success, 2 bad input or usage, 3 a solver did not reach its
//! tolerance, 1 anything else. Nothing here panics on user data.

mod failure;
mod info;
mod interpolate;
mod load;
mod params;
mod subdivide;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Interpolating subdivision surfaces: smooth surfaces through a mesh's vertices.
#[derive(Parser, Debug)]
#[command(name = "subdiv", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print a mesh's statistics: counts, histograms, boundary, genus, validity.
    Info(info::InfoArgs),
    /// Subdivide a mesh N levels with Doo-Sabin, Catmull-Clark, Loop or Deng-Ma.
    Subdivide(subdivide::SubdivideArgs),
    /// Find a control mesh whose subdivision surface passes through the mesh's vertices.
    Interpolate(Box<interpolate::InterpolateArgs>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Subdivide(args) => subdivide::run(&args),
        Command::Interpolate(args) => interpolate::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => failure.report(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
