//! Failures with their exit codes ([error behaviour], README "Exit codes and guarantees").
//!
//! [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes

use std::process::ExitCode;

/// Exit code of a command killed by a signal it handled (128 + the signal),
/// after its temporary files were removed.
pub fn signal_exit_code(signal: i32) -> i32 {
    128 + signal
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
        eprintln!("subdiv: error: {}", one_line(&e));
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

/// Marks an error as bad input (exit 2).
pub fn bad_input(e: impl Into<anyhow::Error>) -> Failure {
    Failure::BadInput(e.into())
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
}
