//! How a job fails: one line, in the command line's terms, and its kind (which fixes the exit
//! code of `subdiv`, the record of a batch and the Python exception).

use serde::{Deserialize, Serialize};

/// Why one input failed, as the command line would say it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum ErrorKind {
    /// Bad input or usage: the file, the mesh, or a method that refuses it
    /// (the command line's exit 2).
    BadInput,
    /// No acceptable result: the tolerance was not reached, or a result is
    /// not finite (exit 3).
    NotConverged,
    /// An output could not be written (exit 4).
    WriteFailed,
    /// A bug: the job panicked (exit 1).
    Panic,
}

impl ErrorKind {
    /// The exit code of the single command failing this way.
    pub fn exit_code(self) -> u8 {
        match self {
            ErrorKind::BadInput => 2,
            ErrorKind::NotConverged => 3,
            ErrorKind::WriteFailed => 4,
            ErrorKind::Panic => 1,
        }
    }

    /// True when the same input and command fail the same way again, so a
    /// resumed batch need not retry it.
    pub fn is_deterministic(self) -> bool {
        matches!(self, ErrorKind::BadInput | ErrorKind::NotConverged)
    }
}

/// A failed job: its kind and the line `subdiv` prints after `subdiv: error: ` (also a batch
/// record's message and a Python exception's text).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
#[non_exhaustive]
pub struct JobError {
    /// Why.
    pub kind: ErrorKind,
    /// One line, library remedies in option terms ([`in_option_terms`]).
    pub message: String,
    /// A solver that stopped early: its iterations (the Python exception carries them).
    pub iterations: Option<usize>,
    /// A solver that stopped early, or a tolerance not met: the residual or error reached.
    pub residual: Option<f64>,
}

impl JobError {
    /// An error of `kind` (the message is put in option terms).
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        let message = in_option_terms(&message.into().replace(['\n', '\r'], " "));
        Self { kind, message, iterations: None, residual: None }
    }

    /// Bad input or usage (exit 2).
    pub fn bad_input(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::BadInput, message)
    }

    /// No acceptable result (exit 3).
    pub fn not_converged(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::NotConverged, message)
    }

    /// An output could not be written (exit 4).
    pub fn write_failed(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::WriteFailed, message)
    }

    /// A library error on one line ([`one_line`]) as `kind`.
    pub fn from_error(kind: ErrorKind, error: &(dyn std::error::Error + 'static)) -> Self {
        Self::new(kind, one_line(error))
    }

    /// The exit code of `subdiv` failing this way.
    pub fn exit_code(&self) -> u8 {
        self.kind.exit_code()
    }
}

/// The error and its causes on one line, each once (a cause the message already ends with is
/// not repeated).
pub fn one_line(error: &(dyn std::error::Error + 'static)) -> String {
    let mut line = error.to_string();
    let mut cause = error.source();
    while let Some(c) = cause {
        let text = c.to_string();
        if !line.ends_with(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
        cause = c.source();
    }
    line.replace(['\n', '\r'], " ")
}

/// The library's remedies in option terms: the library names a solver by
/// its type (`Solver::Minres`), the command line and the options by name
/// (`--solver minres`). Applied to every message of a record, and by the
/// command line to every error it prints.
pub fn in_option_terms(message: &str) -> String {
    use subdiv_solve::{Solver, SweepOrder};
    let solvers = [
        ("Solver::WeightedPia", Solver::WeightedPia),
        ("Solver::GaussSeidel", Solver::GaussSeidel(SweepOrder::Storage)),
        ("Solver::Chebyshev", Solver::Chebyshev),
        ("Solver::Jacobi", Solver::Jacobi),
        ("Solver::Minres", Solver::Minres),
        ("Solver::Gmres", Solver::Gmres),
        ("Solver::Dense", Solver::Dense),
        ("Solver::Pia", Solver::Pia),
        ("Solver::Ldl", Solver::Ldl),
        ("Solver::Cg", Solver::Cg { jacobi: false }),
    ];
    if !message.contains("Solver::") && !message.contains("the automatic solver choice") {
        return message.to_string();
    }
    let mut line = message.replace("the automatic solver choice", "the automatic solver choice (--solver auto)");
    for (library, solver) in solvers {
        line = line.replace(library, &format!("--solver {}", solver.name()));
    }
    line
}
