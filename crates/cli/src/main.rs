//! `subdiv`: glue between the command line and the subdiv library crates.
//!
//! `main` turns every failure into one line on stderr and an exit code
//! ([error behaviour], README "Exit codes and guarantees"): 0 success, 2 bad input or
//! usage, 3 no acceptable result (tolerance not reached, result not finite),
//! 4 an output could not be written, 5 some inputs of a batch failed (their
//! records say why), 1 anything else; a handled signal
//! removes the temporaries and exits with 128 + its number — or 0 when it
//! came after the outputs were committed (the exit code matches what is on
//! disk). Nothing here panics on user data.
//!
//! [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes

mod batch;
mod evaluate;
mod failure;
mod fit;
mod info;
mod interpolate;
mod load;
mod options;
mod outputs;
mod progress;
mod project;
mod sample;
mod stdout;
mod subdivide;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Interpolating subdivision surfaces: smooth surfaces through a mesh's vertices.
#[derive(Parser, Debug)]
#[command(name = "subdiv", version, about, long_about = None, after_help = EXIT_CODES)]
struct Cli {
    /// Print nothing but errors (no progress bars, warnings or summary line).
    #[arg(long, short, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

/// The exit codes, in `--help`.
const EXIT_CODES: &str = "Exit codes: 0 success; 2 bad input or usage (nothing written); \
3 no acceptable result: the tolerance was not reached or a result is not finite (nothing written); \
4 an output could not be written (no output changed); 5 batch: some inputs failed (see their records); 1 anything else; 128+N killed by signal N \
(temporary files removed). Outputs are all-or-nothing: every requested file is complete, or none changed.";

/// When SIGINT, SIGTERM or SIGHUP arrives: waits for a commit of outputs under way to finish,
/// keeps any later one from starting, removes the temporaries, and exits with a code that says
/// what is on disk ([`failure::exit_code_after_signal`]): 0 once a single command's outputs are
/// in place (the commit is its point of no return), else 128 + the signal with nothing written.
/// `batch` commits each input's outputs and record on its own, so it always exits 128 + N: the
/// inputs done have their records, a second run resumes with the others.
fn install_signal_cleanup(batch: bool) {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else { return };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let commits = subdiv_io::stop_commits();
            std::process::exit(failure::exit_code_after_signal(signal, commits, batch));
        }
    });
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print a mesh's statistics: counts, histograms, boundary, genus, validity.
    Info(info::InfoArgs),
    /// Subdivide a mesh N levels with Doo-Sabin, Catmull-Clark, Loop or Deng-Ma.
    Subdivide(Box<subdivide::SubdivideArgs>),
    /// Evaluate the limit surface (position, normal, derivatives) at given (face, u, v).
    Evaluate(Box<evaluate::EvaluateArgs>),
    /// Find a control mesh whose subdivision surface passes through the mesh's vertices.
    Interpolate(Box<interpolate::InterpolateArgs>),
    /// Run info, interpolate or subdivide over many meshes (files, directories, globs) in
    /// parallel: one JSON record per input on stdout, resumable; exit 5 when some failed.
    Batch(Box<batch::BatchArgs>),
    /// Sample points with normals on the limit surface (per domain or by area).
    Sample(Box<sample::SampleArgs>),
    /// Closest points on the limit surface to query points: `FACE U V x y z distance` per line.
    Project(Box<project::ProjectArgs>),
    /// Move a control mesh's points so that its limit surface fits a target mesh or point cloud.
    Fit(Box<fit::FitArgs>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    progress::set_quiet(cli.quiet);
    install_signal_cleanup(matches!(cli.command, Command::Batch(_)));
    let result = match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Subdivide(args) => subdivide::run(&args),
        Command::Evaluate(args) => evaluate::run(&args),
        Command::Interpolate(args) => interpolate::run(&args),
        Command::Sample(args) => sample::run(&args),
        Command::Project(args) => project::run(&args),
        Command::Fit(args) => fit::run(&args),
        Command::Batch(args) => match batch::run(&args) {
            Ok(code) => return code,
            Err(failure) => Err(failure),
        },
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
