//! Failures with their exit codes (SPEC §6).

use std::process::ExitCode;

/// Why a command failed, which fixes its exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input or usage: exit 2.
    BadInput(anyhow::Error),
    /// A solver did not reach its tolerance: exit 3 (nothing written).
    NotConverged(anyhow::Error),
    /// Anything else: exit 1.
    Other(anyhow::Error),
}

impl Failure {
    /// Prints the error chain on one line and returns the exit code.
    pub fn report(self) -> ExitCode {
        let (code, error) = match self {
            Failure::BadInput(e) => (2, e),
            Failure::NotConverged(e) => (3, e),
            Failure::Other(e) => (1, e),
        };
        eprintln!("subdiv: error: {error:#}");
        ExitCode::from(code)
    }
}

/// Marks an error as bad input (exit 2).
pub fn bad_input(e: impl Into<anyhow::Error>) -> Failure {
    Failure::BadInput(e.into())
}
