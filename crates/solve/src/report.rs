//! Options in, report out, and the convergence monitor every iterative
//! solver shares.

use std::time::Instant;

use crate::error::{LastIterate, SolveError, StopReason};
use crate::kernels::{all_finite, Row};
use crate::tolerances::{DEFAULT_MAX_ITER, DEFAULT_TOL, DIVERGENCE_FACTOR, STAGNATION_FACTOR, STAGNATION_WINDOW};

/// Stopping rule and start of a solve.
///
/// A solve stops when max_i ‖P_i − (A·X)_i‖₂ / `scale` ≤ `tol` ([the stopping rule]:
/// the quantity the papers use; `scale` is the caller's bounding-box
/// diagonal d), or after `max_iter` iterations.
///
/// `#[non_exhaustive]`: build it with [`Default`] and the `with_*` setters
/// (one per field); the fields stay public for reading. Adding a field is
/// then not a breaking change.
///
/// ```
/// use subdiv_solve::{SolveOptions, DEFAULT_MAX_ITER};
/// let opts = SolveOptions::default().with_tol(1e-9).with_scale(2.5).with_history(false);
/// assert_eq!((opts.tol, opts.scale, opts.max_iter, opts.history), (1e-9, 2.5, DEFAULT_MAX_ITER, false));
/// ```
///
/// A struct literal does not compile outside the crate:
///
/// ```compile_fail,E0639
/// let opts = subdiv_solve::SolveOptions { tol: 1e-9, ..Default::default() };
/// ```
///
/// [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SolveOptions {
    /// Relative tolerance on the max row residual.
    pub tol: f64,
    /// Length the residual is measured against (the input's bbox diagonal).
    pub scale: f64,
    /// Iteration cap of the iterative solvers (direct solvers ignore it).
    pub max_iter: usize,
    /// Record the residual of every iterate in [`Solution::history`].
    pub history: bool,
    /// Start X₀ of the iterative solvers (default: X₀ = P, the natural start
    /// since every limit matrix is close to the identity).
    pub initial: Option<Vec<[f64; 3]>>,
    /// Told the relative residual of every iterate (progress bars).
    pub observer: IterationObserver,
}

/// A callback told `(iteration, relative residual)` after every iterate of an
/// iterative solver (a progress bar); none by default. Observers never change
/// a result: they compare equal to each other.
#[derive(Clone, Default)]
pub struct IterationObserver(Option<std::sync::Arc<dyn Fn(usize, f64) + Send + Sync>>);

impl IterationObserver {
    /// An observer calling `f(iteration, relative residual)`.
    pub fn new(f: impl Fn(usize, f64) + Send + Sync + 'static) -> Self {
        Self(Some(std::sync::Arc::new(f)))
    }

    /// Tells the observer, if any.
    pub fn notify(&self, iteration: usize, relative_residual: f64) {
        if let Some(f) = &self.0 {
            f(iteration, relative_residual);
        }
    }
}

impl std::fmt::Debug for IterationObserver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() { "IterationObserver(set)" } else { "IterationObserver(none)" })
    }
}

impl PartialEq for IterationObserver {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Default for SolveOptions {
    /// Tolerance [`DEFAULT_TOL`](crate::DEFAULT_TOL), scale 1, at most
    /// [`DEFAULT_MAX_ITER`](crate::DEFAULT_MAX_ITER) iterations, history
    /// recorded, X₀ = P, no observer.
    fn default() -> Self {
        SolveOptions {
            tol: DEFAULT_TOL,
            scale: 1.0,
            max_iter: DEFAULT_MAX_ITER,
            history: true,
            initial: None,
            observer: IterationObserver::default(),
        }
    }
}

impl SolveOptions {
    /// With relative tolerance `tol` on the max row residual.
    pub fn with_tol(self, tol: f64) -> Self {
        Self { tol, ..self }
    }

    /// With the length `scale` the residual is measured against.
    pub fn with_scale(self, scale: f64) -> Self {
        Self { scale, ..self }
    }

    /// With the iteration cap `max_iter` of the iterative solvers.
    pub fn with_max_iter(self, max_iter: usize) -> Self {
        Self { max_iter, ..self }
    }

    /// Recording the residual of every iterate (`true`) or not.
    pub fn with_history(self, history: bool) -> Self {
        Self { history, ..self }
    }

    /// With start X₀ = `initial` of the iterative solvers (`None`: X₀ = P).
    pub fn with_initial(self, initial: Option<Vec<[f64; 3]>>) -> Self {
        Self { initial, ..self }
    }

    /// With `observer` told the relative residual of every iterate.
    pub fn with_observer(self, observer: IterationObserver) -> Self {
        Self { observer, ..self }
    }
}

/// A converged solve. `#[non_exhaustive]`: made by the solvers, read
/// through its public fields (a new field is not a breaking change).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Solution {
    /// The unknowns X (n × 3), finite.
    pub x: Vec<[f64; 3]>,
    /// Updates applied to X₀ (iterative solvers), or 1 + refinement steps (direct).
    pub iterations: usize,
    /// Always `true` in an `Ok` (non-convergence is an error); kept so that
    /// reports can copy it.
    pub converged: bool,
    /// Final max_i ‖P_i − (A·X)_i‖₂ / scale, recomputed from X with A.
    pub residual: f64,
    /// Relative residual of X₀, X₁, … (`iterations + 1` values; empty when
    /// `history` was off). CG records its recursive residual here (see `cg.rs`).
    pub history: Vec<f64>,
    /// Sparse products with A or S (three columns count once), including
    /// eigenvalue estimation and residual checks; a Gauss-Seidel sweep counts as one.
    pub matvecs: usize,
    /// Wall time of the whole call (estimation, factorisation and solve).
    pub seconds: f64,
    /// Solver name (`Solver::name`).
    pub solver: &'static str,
    /// LDLᵀ only: number of negative pivots of S (the number of negative
    /// eigenvalues of A, by Sylvester's law of inertia). `Some(k > 0)` means A
    /// is indefinite but nonsingular: the solution is valid, but PIA, CG and
    /// Chebyshev cannot reach it.
    pub negative_pivots: Option<usize>,
}

/// What the monitor decided about the latest iterate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    Continue,
    Converged,
    Diverged,
    Stop(StopReason),
}

/// History, divergence, stagnation and iteration-cap bookkeeping shared by
/// the iterative solvers.
pub(crate) struct Monitor {
    pub solver: &'static str,
    /// Absolute threshold tol · scale.
    pub threshold: f64,
    scale: f64,
    record: bool,
    max_iter: usize,
    pub history: Vec<f64>,
    initial: Option<f64>,
    best: f64,
    window_ref: f64,
    window_start: usize,
    pub matvecs: usize,
    start: Instant,
    observer: IterationObserver,
}

impl Monitor {
    pub fn new(solver: &'static str, opts: &crate::SolveOptions, start: Instant) -> Self {
        Monitor {
            solver,
            threshold: opts.tol * opts.scale,
            scale: opts.scale,
            record: opts.history,
            max_iter: opts.max_iter,
            history: Vec::new(),
            initial: None,
            best: f64::INFINITY,
            window_ref: f64::INFINITY,
            window_start: 0,
            matvecs: 0,
            start,
            observer: opts.observer.clone(),
        }
    }

    /// Records the absolute residual `res` of iterate `k` and decides.
    pub fn observe(&mut self, k: usize, res: f64) -> Verdict {
        self.observer.notify(k, res / self.scale);
        if self.record {
            self.history.push(res / self.scale);
        }
        let initial = *self.initial.get_or_insert(res);
        if !res.is_finite() || res > DIVERGENCE_FACTOR * initial.max(self.threshold) {
            return Verdict::Diverged;
        }
        if res <= self.threshold {
            return Verdict::Converged;
        }
        if k >= self.max_iter {
            return Verdict::Stop(StopReason::MaxIterations);
        }
        self.best = self.best.min(res);
        if k == 0 {
            self.window_ref = res;
        } else if k - self.window_start >= STAGNATION_WINDOW {
            if self.best > STAGNATION_FACTOR * self.window_ref {
                // No progress for a whole window while worse than the start:
                // the iteration is diverging (slowly), not stagnating.
                if res > initial {
                    return Verdict::Diverged;
                }
                return Verdict::Stop(StopReason::Stagnated);
            }
            self.window_start = k;
            self.window_ref = self.best;
        }
        Verdict::Continue
    }

    /// The `Ok` report (or `Diverged` if X is not finite).
    pub fn solution(self, x: Vec<Row>, iterations: usize, res: f64) -> Result<crate::Solution, SolveError> {
        if !all_finite(&x) || !res.is_finite() {
            return Err(self.diverged(iterations, res));
        }
        Ok(crate::Solution {
            x,
            iterations,
            converged: true,
            residual: res / self.scale,
            history: self.history,
            matvecs: self.matvecs,
            seconds: self.start.elapsed().as_secs_f64(),
            solver: self.solver,
            negative_pivots: None,
        })
    }

    pub fn diverged(self, iterations: usize, res: f64) -> SolveError {
        SolveError::Diverged { solver: self.solver, iterations, residual: res / self.scale, history: self.history }
    }

    pub fn not_converged(self, reason: StopReason, x: Vec<Row>, iterations: usize, res: f64) -> SolveError {
        if !all_finite(&x) {
            return self.diverged(iterations, res);
        }
        SolveError::NotConverged {
            solver: self.solver,
            iterations,
            residual: res / self.scale,
            history: self.history,
            reason,
            x: LastIterate(x),
        }
    }

    /// Turns a verdict other than `Continue` into the result.
    pub fn finish(self, v: Verdict, x: Vec<Row>, iterations: usize, res: f64) -> Result<crate::Solution, SolveError> {
        match v {
            Verdict::Converged => self.solution(x, iterations, res),
            Verdict::Diverged => Err(self.diverged(iterations, res)),
            Verdict::Stop(reason) => Err(self.not_converged(reason, x, iterations, res)),
            Verdict::Continue => unreachable!("finish called on Continue"),
        }
    }
}

/// X₀: the caller's initial guess or P.
pub(crate) fn initial_guess(p: &[Row], opts: &crate::SolveOptions) -> Vec<Row> {
    match &opts.initial {
        Some(x0) => x0.clone(),
        None => p.to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_observer_hears_every_iterate_relative_to_scale() {
        let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let log = seen.clone();
        let opts = crate::SolveOptions {
            scale: 2.0,
            observer: IterationObserver::new(move |k, r| log.lock().unwrap().push((k, r))),
            ..Default::default()
        };
        let mut mon = Monitor::new("test", &opts, Instant::now());
        for (k, res) in [1.0, 0.5, 0.25].into_iter().enumerate() {
            mon.observe(k, res);
        }
        assert_eq!(*seen.lock().unwrap(), [(0, 0.5), (1, 0.25), (2, 0.125)]);
        assert_eq!(
            opts,
            crate::SolveOptions { scale: 2.0, ..Default::default() },
            "observers never make options differ"
        );
    }

    #[test]
    fn monitor_detects_divergence_stagnation_and_cap() {
        let opts = crate::SolveOptions { max_iter: 1000, ..Default::default() };
        let mut m = Monitor::new("t", &opts, Instant::now());
        assert_eq!(m.observe(0, 1.0), Verdict::Continue);
        assert_eq!(m.observe(1, 2e6), Verdict::Diverged);

        let mut m = Monitor::new("t", &opts, Instant::now());
        let mut v = Verdict::Continue;
        let mut k = 0;
        while v == Verdict::Continue {
            v = m.observe(k, 0.5);
            k += 1;
        }
        assert_eq!(v, Verdict::Stop(StopReason::Stagnated));
        assert_eq!(k - 1, STAGNATION_WINDOW);

        let opts = crate::SolveOptions { max_iter: 3, ..Default::default() };
        let mut m = Monitor::new("t", &opts, Instant::now());
        let verdicts: Vec<_> = (0..4).map(|k| m.observe(k, 0.5f64.powi(k as i32))).collect();
        assert_eq!(verdicts[3], Verdict::Stop(StopReason::MaxIterations));
        assert_eq!(m.history.len(), 4);

        let mut m = Monitor::new("t", &crate::SolveOptions::default(), Instant::now());
        assert_eq!(m.observe(0, f64::NAN), Verdict::Diverged);
        assert_eq!(m.observe(1, 1e-7), Verdict::Converged);
    }
}
