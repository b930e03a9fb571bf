//! Failures with their exit codes ([error behaviour], README "Exit codes and guarantees").
//!
//! [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes

use std::process::ExitCode;

/// Exit code of a command killed by a signal it handled (128 + the signal),
/// after its temporary files were removed.
pub fn signal_exit_code(signal: i32) -> i32 {
    128 + signal
}

/// The exit code after `signal`, once [`subdiv_io::stop_commits`] returned `commits` (the
/// completed commits of outputs; none can start any more): a single command commits its outputs
/// once, at its end, so one commit means every output is in place and the command succeeded
/// (exit 0: the signal came after its point of no return); none means nothing was written
/// (128 + the signal). A batch commits per input and always reports the signal.
pub fn exit_code_after_signal(signal: i32, commits: u64, batch: bool) -> i32 {
    if commits > 0 && !batch {
        0
    } else {
        signal_exit_code(signal)
    }
}

/// Why a command failed, which fixes its exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input or usage, refused before anything is written: exit 2.
    BadInput(anyhow::Error),
    /// No acceptable result: the solver did not reach its tolerance, the
    /// measured error exceeds `--tol`, or a result is not finite. Exit 3,
    /// nothing written.
    NotConverged(anyhow::Error),
    /// An output could not be written (disk full, permission, a directory
    /// that does not exist or is not writable): exit 4, no output changed.
    WriteFailed(anyhow::Error),
    /// Anything else (a bug): exit 1.
    Other(anyhow::Error),
}

impl Failure {
    /// The exit code.
    pub fn code(&self) -> u8 {
        match self {
            Failure::BadInput(_) => 2,
            Failure::NotConverged(_) => 3,
            Failure::WriteFailed(_) => 4,
            Failure::Other(_) => 1,
        }
    }

    /// Prints the error on one line and returns the exit code.
    pub fn report(self) -> ExitCode {
        let code = self.code();
        let (Failure::BadInput(e) | Failure::NotConverged(e) | Failure::WriteFailed(e) | Failure::Other(e)) = self;
        eprintln!("subdiv: error: {}", in_cli_terms(&one_line(&e)));
        ExitCode::from(code)
    }
}

/// The error and its causes on one line, each cause once: a cause whose text
/// the message already ends with (an OS error that the file's error quoted)
/// is not repeated.
pub fn one_line(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if line.is_empty() {
            line = text;
        } else if !line.ends_with(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line.replace(['\n', '\r'], " ")
}

/// The library's remedies in the command line's terms: the library names a
/// solver by its type (`Solver::Minres`), the command line by its flag
/// (`--solver minres`, the value [`subdiv_solve::Solver::name`] parses from). Applied to
/// every error line the CLI prints.
pub fn in_cli_terms(message: &str) -> String {
    // One translation for the command line and the batch records.
    subdiv::batch::in_option_terms(message)
}

impl From<subdiv::job::JobError> for Failure {
    /// The job's kind decides the exit code; its message is already one line in option terms.
    fn from(e: subdiv::job::JobError) -> Self {
        use subdiv::job::ErrorKind;
        let kind = e.kind;
        let error = anyhow::Error::msg(e.message);
        match kind {
            ErrorKind::BadInput => Failure::BadInput(error),
            ErrorKind::NotConverged => Failure::NotConverged(error),
            ErrorKind::WriteFailed => Failure::WriteFailed(error),
            _ => Failure::Other(error),
        }
    }
}

/// Marks an error as bad input (exit 2).
pub fn bad_input(e: impl Into<anyhow::Error>) -> Failure {
    Failure::BadInput(e.into())
}

/// A size refused by the memory budget (exit 2), with the command line's remedy when the
/// budget is the memory available.
pub fn over_budget(e: subdiv::budget::BudgetError) -> Failure {
    let hint = match &e {
        subdiv::budget::BudgetError::TooManyItems { .. } | subdiv::budget::BudgetError::OverBudget { .. } => {
            " or set --max-memory"
        }
        _ => "",
    };
    Failure::BadInput(anyhow::anyhow!("{e}{hint}"))
}

/// The memory budget of a command: `--max-memory` when given, else ¾ of the memory available.
pub fn budget(max_memory: Option<u64>) -> subdiv::budget::MemoryBudget {
    subdiv::budget::MemoryBudget::given_or_available(max_memory, "--max-memory")
}

/// Marks an error as a failed write (exit 4).
pub fn write_failed(e: impl Into<anyhow::Error>) -> Failure {
    Failure::WriteFailed(e.into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_os_text_appears_once() {
        let os = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory (os error 2)");
        let e = subdiv_io::IoError::Io { path: "m.obj".into(), source: os };
        let line = one_line(&anyhow::Error::new(e));
        assert_eq!(line, "m.obj: No such file or directory (os error 2)");
        let chained = anyhow::Error::msg("inner cause").context("outer");
        assert_eq!(one_line(&chained), "outer: inner cause");
        assert_eq!(one_line(&anyhow::Error::msg("two\nlines")), "two lines");
    }

    #[test]
    fn library_remedies_become_flags() {
        let indefinite = subdiv_solve::SolveError::Indefinite { solver: "cg", detail: "p·Ap = -1".into() };
        let line = in_cli_terms(&indefinite.to_string());
        assert_eq!(
            line,
            "cg: the matrix is indefinite: p·Ap = -1; use --solver minres, --solver ldl or --solver dense"
        );
        let not_symmetric = subdiv_solve::SolveError::NotSymmetric { solver: "cg", detail: "s_01 ≠ s_10".into() };
        let line = in_cli_terms(&not_symmetric.to_string());
        assert!(line
            .ends_with("use --solver gmres, --solver pia, --solver jacobi, --solver gauss-seidel or --solver dense"));
        assert!(!line.contains("Solver::"), "{line}");
        let cheng = "the automatic solver choice, which takes MINRES here (Solver::Minres solves symmetric indefinite \
                     systems), a direct solver (Solver::Ldl or Solver::Dense)";
        assert_eq!(
            in_cli_terms(cheng),
            "the automatic solver choice (--solver auto), which takes MINRES here (--solver minres solves symmetric \
             indefinite systems), a direct solver (--solver ldl or --solver dense)"
        );
        // Every solver name the translation writes is one `--solver` parses.
        for name in
            ["weighted-pia", "gauss-seidel", "chebyshev", "jacobi", "minres", "gmres", "dense", "pia", "ldl", "cg"]
        {
            assert!(name.parse::<subdiv_solve::Solver>().is_ok(), "{name}");
        }
    }
}
