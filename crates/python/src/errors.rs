//! Rust errors as Python exceptions.
//!
//! The exception classes live in Python (`subdiv/_errors.py`), where a class
//! can have two bases: `subdiv.InputError` is a `subdiv.SubdivError` *and* a
//! `ValueError`, `subdiv.NotConvergedError` a `SubdivError` and a
//! `RuntimeError`. The messages are the library's `Display` texts, which the
//! command line prints after the file or flag they concern.

use pyo3::exceptions::{PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError, PyValueError};
use pyo3::prelude::*;
use subdiv::interp::InterpError;
use subdiv::solve::SolveError;
use subdiv::{IoError, MeshError, StencilError};

/// An error of the bindings before it meets the interpreter: built without
/// the GIL (inside `Python::detach`), raised with it.
#[derive(Debug)]
pub enum Error {
    /// Bad input: `subdiv.InputError` (a `ValueError`).
    Input(String),
    /// A solver that stopped short, or a result beyond the tolerance:
    /// `subdiv.NotConvergedError` with its iterations and residual when known.
    NotConverged {
        /// The message.
        message: String,
        /// Iterations performed (`None` when no iterative solver ran).
        iterations: Option<usize>,
        /// The residual or measured error reached, relative to d.
        residual: Option<f64>,
    },
    /// The operating system refused a file: `OSError` or its subclass for the kind.
    Os {
        /// The message (naming the file).
        message: String,
        /// What the system said.
        kind: std::io::ErrorKind,
    },
    /// Anything else (a bug of the library): `subdiv.SubdivError`.
    Other(String),
}

impl Error {
    /// The Python exception.
    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let class = |name: &str| -> PyResult<Bound<'_, PyAny>> { py.import("subdiv._errors")?.getattr(name) };
        let raised = match self {
            Error::Input(message) => class("InputError").and_then(|c| c.call1((message,))),
            Error::NotConverged { message, iterations, residual } => {
                class("NotConvergedError").and_then(|c| c.call1((message, iterations, residual)))
            }
            Error::Other(message) => class("SubdivError").and_then(|c| c.call1((message,))),
            Error::Os { message, kind } => {
                return match kind {
                    std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
                    std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
                    std::io::ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
                    _ => PyOSError::new_err(message),
                }
            }
        };
        match raised {
            Ok(exception) => PyErr::from_value(exception),
            // The package is broken (subdiv._errors missing): say so, as a ValueError at least.
            Err(e) => PyValueError::new_err(format!("subdiv: cannot build the exception: {e}")),
        }
    }
}

impl From<MeshError> for Error {
    fn from(e: MeshError) -> Self {
        Error::Input(e.to_string())
    }
}

impl From<IoError> for Error {
    fn from(e: IoError) -> Self {
        match &e {
            IoError::Io { source, .. } => Error::Os { message: e.to_string(), kind: source.kind() },
            IoError::NotAFile { kind, .. } if kind.contains("directory") => {
                Error::Os { message: e.to_string(), kind: std::io::ErrorKind::IsADirectory }
            }
            IoError::NotAFile { .. } => Error::Os { message: e.to_string(), kind: std::io::ErrorKind::Other },
            // Unknown extension, malformed or invalid file: bad input (the command line's exit 2).
            _ => Error::Input(e.to_string()),
        }
    }
}

impl From<subdiv::budget::BudgetError> for Error {
    fn from(e: subdiv::budget::BudgetError) -> Self {
        Error::Input(e.to_string())
    }
}

impl From<StencilError> for Error {
    fn from(e: StencilError) -> Self {
        Error::Input(e.to_string())
    }
}

/// Iterations and residual of a solver's error, when it has them.
fn solver_state(e: &SolveError) -> (Option<usize>, Option<f64>) {
    match e {
        SolveError::NotConverged { iterations, residual, .. } | SolveError::Diverged { iterations, residual, .. } => {
            (Some(*iterations), Some(*residual))
        }
        _ => (None, None),
    }
}

impl From<InterpError> for Error {
    fn from(e: InterpError) -> Self {
        if !e.is_not_converged() {
            // Everything else is about the input: the command line's exit 2.
            return Error::Input(e.to_string());
        }
        let (iterations, residual) = match &e {
            InterpError::Solve { source, .. } | InterpError::Unsolvable { source, .. } => solver_state(source),
            InterpError::ToleranceNotMet { max_rel, .. } => (None, Some(*max_rel)),
            _ => (None, None),
        };
        Error::NotConverged { message: e.to_string(), iterations, residual }
    }
}

impl From<subdiv::job::JobError> for Error {
    /// The job's kind decides the exception; its message is the command line's.
    fn from(e: subdiv::job::JobError) -> Self {
        use subdiv::job::ErrorKind;
        match e.kind {
            ErrorKind::BadInput => Error::Input(e.message),
            ErrorKind::NotConverged => {
                Error::NotConverged { message: e.message, iterations: e.iterations, residual: e.residual }
            }
            ErrorKind::WriteFailed => Error::Os { message: e.message, kind: std::io::ErrorKind::Other },
            _ => Error::Other(e.message),
        }
    }
}

impl From<subdiv::Error> for Error {
    fn from(e: subdiv::Error) -> Self {
        match e {
            subdiv::Error::Io(e) => e.into(),
            subdiv::Error::Mesh(e) => e.into(),
            subdiv::Error::Stencil(e) => e.into(),
            subdiv::Error::Interp(e) => e.into(),
            e if e.is_not_converged() => {
                Error::NotConverged { message: e.to_string(), iterations: None, residual: None }
            }
            e => Error::Input(e.to_string()),
        }
    }
}

/// `Result` of the bindings' Rust side.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Runs `f` without the GIL (other Python threads run meanwhile), turning a
/// panic — a library bug — into `subdiv.SubdivError` instead of letting it
/// reach the interpreter as a `PanicException`.
pub fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T> + Send) -> PyResult<T> {
    let outcome = py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
    match outcome {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(e)) => Err(e.into_pyerr(py)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(Error::Other(format!("internal error (please report it): {what}")).into_pyerr(py))
        }
    }
}

/// A bad-input error with this message.
pub fn input(message: impl Into<String>) -> Error {
    Error::Input(message.into())
}

/// Raises [`Error`] in Python.
pub trait RaiseExt<T> {
    /// The Python exception of the error.
    fn raise(self, py: Python<'_>) -> PyResult<T>;
}

impl<T, E: Into<Error>> RaiseExt<T> for std::result::Result<T, E> {
    fn raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| e.into().into_pyerr(py))
    }
}
