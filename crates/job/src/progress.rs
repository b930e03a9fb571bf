//! What a job tells its front-end while it runs: phases with their amount of work, warnings,
//! the solver's iterations. The command line draws bars, a batch collects the warnings into its
//! records, Python turns them into `UserWarning`s; [`Silent`] ignores everything.

use subdiv_solve::IterationObserver;

/// A phase of a job, with the unit its amounts count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Phase {
    /// Reading the input (bytes).
    Read,
    /// Validating the mesh (no amount).
    Validate,
    /// Refining (levels).
    Refine,
    /// Writing an output (bytes).
    Write,
}

/// The front-end's side of a job. Every method has a do-nothing default.
///
/// A job calls `begin`, then `advance` any number of times, then `end`, for one phase at a
/// time, from the thread that runs the job.
pub trait Progress {
    /// A phase begins: `label` says what it does, `total` its amount (0: unknown).
    fn begin(&mut self, _phase: Phase, _label: &str, _total: u64) {}
    /// The amount of the current phase is now known to be `total`.
    fn set_total(&mut self, _total: u64) {}
    /// `done` of the current phase's amount is done.
    fn advance(&mut self, _done: u64) {}
    /// The current phase ended.
    fn end(&mut self) {}
    /// A warning (one line: what a reader skipped, a mesh defect, a method's note).
    fn warn(&mut self, _message: &str) {}
    /// The observer of the solver's iterations for a solve labelled `label` with tolerance
    /// `tol` (a progress bar); the default observes nothing.
    fn solver(&mut self, _label: &str, _tol: f64) -> IterationObserver {
        IterationObserver::default()
    }
    /// The solve ended.
    fn solver_end(&mut self) {}
}

/// A [`Progress`] that shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}

/// A [`Progress`] that shows nothing and keeps the warnings (a batch record's `warnings`).
#[derive(Clone, Debug, Default)]
pub struct Warnings(pub Vec<String>);

impl Progress for Warnings {
    fn warn(&mut self, message: &str) {
        self.0.push(message.to_string());
    }
}
