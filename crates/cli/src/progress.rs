//! Progress bars on stderr (when it is a terminal), warnings, and `--quiet`.
//!
//! Long operations — reading a large file, each refinement level, solving,
//! writing — show a bar with rate and ETA (a spinner with the elapsed time
//! where the amount of work is not known in advance). Nothing is drawn when
//! stderr is not a terminal; `--quiet` silences bars, warnings and the
//! summary line, leaving errors only.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static QUIET: AtomicBool = AtomicBool::new(false);

/// Silences everything but errors from now on.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// True under `--quiet`.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Prints a warning (one line) unless `--quiet`.
pub fn warn(message: impl std::fmt::Display) {
    if !quiet() {
        eprintln!("subdiv: warning: {message}");
    }
}

/// Prints the command's summary line on stdout unless `--quiet`.
pub fn summary(message: impl std::fmt::Display) {
    if !quiet() {
        crate::stdout::line(&message.to_string());
    }
}

fn target() -> ProgressDrawTarget {
    if quiet() || !std::io::stderr().is_terminal() {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    }
}

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar())
}

/// A bar over `total` bytes (reading, writing), with rate and ETA.
pub fn bytes(message: impl Into<String>, total: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total), target());
    bar.set_style(style("{msg} [{bar:30}] {bytes}/{total_bytes} {binary_bytes_per_sec} ETA {eta}"));
    bar.set_message(message.into());
    bar
}

/// A bar over `total` steps (refinement levels).
pub fn steps(message: impl Into<String>, total: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total), target());
    bar.set_style(style("{msg} [{bar:30}] {pos}/{len} {elapsed} ETA {eta}"));
    bar.set_message(message.into());
    bar
}

/// A spinner for work of unknown length (solving), with the elapsed time.
pub fn spinner(message: impl Into<String>) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(None, target());
    bar.set_style(style("{spinner} {msg} {elapsed}"));
    bar.set_message(message.into());
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// A bar over a solve and the observer that drives it: iterations and their
/// rate, the residual against the tolerance, and an ETA from the convergence
/// so far (the log of the residual falls about linearly with the iterations,
/// so the iterations left are log(r/tol) over the mean decrease per iteration).
pub fn solver(message: impl Into<String>, tol: f64) -> (ProgressBar, subdiv_solve::IterationObserver) {
    let message = message.into();
    let bar = ProgressBar::with_draw_target(None, target());
    bar.set_style(style("{spinner} {msg} [{bar:20}] {pos} it {per_sec} ETA {eta}"));
    bar.set_message(message.clone());
    bar.enable_steady_tick(Duration::from_millis(120));
    let shown = bar.clone();
    let first = std::sync::Mutex::new(None::<f64>);
    let observer = subdiv_solve::IterationObserver::new(move |k, residual| {
        let r0 = *first.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(residual);
        let per_iteration = if k > 0 && residual > 0.0 { (r0 / residual).ln() / k as f64 } else { 0.0 };
        let left = if per_iteration > 0.0 && residual > tol { (residual / tol).ln() / per_iteration } else { 0.0 };
        shown.set_length(k as u64 + left.min(1e9).ceil() as u64);
        shown.set_position(k as u64);
        shown.set_message(format!("{message}: residual {residual:.2e} → {tol:.0e}"));
    });
    (bar, observer)
}

/// The job's progress on the terminal: a bar per phase (bytes read and written, levels refined,
/// a spinner while validating), the solver's bar, warnings on stderr.
#[derive(Default)]
pub struct Terminal {
    bar: Option<ProgressBar>,
    solver: Option<ProgressBar>,
}

impl subdiv::job::Progress for Terminal {
    fn begin(&mut self, phase: subdiv::job::Phase, label: &str, total: u64) {
        use subdiv::job::Phase;
        self.end();
        self.bar = Some(match phase {
            Phase::Read | Phase::Write => bytes(label, total),
            Phase::Refine => steps(label, total),
            _ => spinner(label),
        });
    }

    fn set_total(&mut self, total: u64) {
        if let Some(bar) = &self.bar {
            bar.set_length(total);
        }
    }

    fn advance(&mut self, done: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(done);
        }
    }

    fn end(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    fn warn(&mut self, message: &str) {
        warn(message);
    }

    fn solver(&mut self, label: &str, tol: f64) -> subdiv_solve::IterationObserver {
        let (bar, observer) = solver(label, tol);
        self.solver = Some(bar);
        observer
    }

    fn solver_end(&mut self) {
        if let Some(bar) = self.solver.take() {
            bar.finish_and_clear();
        }
    }
}
