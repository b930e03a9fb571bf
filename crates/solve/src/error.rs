//! The crate's one error type.

use std::fmt;

/// Why an iterative solver stopped without reaching the tolerance.
/// `#[non_exhaustive]`: a new solver may stop for a new reason.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// `max_iter` iterations were spent.
    MaxIterations,
    /// The best residual did not improve by 0.1 % within a window of 200
    /// iterations (typical of a singular, inconsistent system).
    Stagnated,
    /// CG's, MINRES's or GMRES's recursive residual kept claiming convergence
    /// that the true A-residual did not confirm (accuracy limit of the
    /// floating-point system).
    AccuracyLimit,
    /// A least-squares solution was reached with the residual above the
    /// tolerance: the residual is (numerically) orthogonal to the range of the
    /// matrix, which is therefore singular, and the data lie outside its range
    /// (MINRES's ‖S·r‖ test, GMRES's invariant Krylov space with a singular
    /// Hessenberg matrix). The last iterate is a least-squares solution.
    LeastSquares,
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StopReason::MaxIterations => "the iteration limit was reached",
            StopReason::Stagnated => "the residual stagnated (singular or inconsistent system?)",
            StopReason::AccuracyLimit => "the attainable accuracy was reached",
            StopReason::LeastSquares => {
                "a least-squares solution was reached (the matrix is singular and the data are outside its range)"
            }
        })
    }
}

/// The last iterate of a solver that did not converge: what the iteration
/// produced, for callers that accept a fixed iteration budget (Zheng-Cai's
/// ITE_MAX = 5). Its `Debug` prints only the length.
#[derive(Clone, PartialEq, Default)]
pub struct LastIterate(pub Vec<[f64; 3]>);

impl fmt::Debug for LastIterate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "LastIterate(<{} rows>)", self.0.len())
    }
}

/// Everything that can go wrong in a solve. Contract violations by the
/// caller (mismatched lengths passed to [`FactoredMatrix::apply`](crate::FactoredMatrix::apply))
/// panic instead; everything about user data is one of these.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// The iteration did not reach `tol`; the diagnostics say how far it got.
    #[error(
        "{solver} did not converge: {reason} after {iterations} iterations, \
         max row residual {residual:.3e} (relative to scale)"
    )]
    NotConverged {
        /// Solver name (`Solver::name`).
        solver: &'static str,
        /// Iterations performed.
        iterations: usize,
        /// Relative max-row residual of the returned iterate.
        residual: f64,
        /// Relative residual per iteration (empty when history was off).
        history: Vec<f64>,
        /// Why it stopped.
        reason: StopReason,
        /// The last finite iterate.
        x: LastIterate,
    },
    /// The residual grew to more than 10⁶ times the initial one, or became
    /// non-finite: the iteration matrix has spectral radius > 1 (plain PIA on
    /// an indefinite A, e.g. Catmull-Clark with valence-2 vertices).
    #[error(
        "{solver} diverged after {iterations} iterations (residual {residual:.3e}); \
         the matrix is probably indefinite or has eigenvalues ≥ 2 — use Solver::Minres, Solver::Ldl or \
         Solver::Dense"
    )]
    Diverged {
        /// Solver name.
        solver: &'static str,
        /// Iterations performed.
        iterations: usize,
        /// Relative residual when the divergence was detected (may be inf/NaN).
        residual: f64,
        /// Relative residual per iteration.
        history: Vec<f64>,
    },
    /// The matrix is (numerically) singular: no unique solution exists.
    #[error("{solver}: the matrix is singular: {detail}")]
    Singular {
        /// Solver name.
        solver: &'static str,
        /// Which pivot, row or direction showed it.
        detail: String,
    },
    /// The matrix has a negative eigenvalue (or a non-positive diagonal), so
    /// a method that needs a positive definite S cannot be used.
    #[error("{solver}: the matrix is indefinite: {detail}; use Solver::Minres, Solver::Ldl or Solver::Dense")]
    Indefinite {
        /// Solver name.
        solver: &'static str,
        /// The curvature, pivot or eigenvalue that showed it.
        detail: String,
    },
    /// A solver that needs a symmetric S got a matrix without that structure.
    #[error(
        "{solver} needs A = D·S with S symmetric: {detail}; \
         use Solver::Gmres, Solver::Pia, Solver::Jacobi, Solver::GaussSeidel or Solver::Dense"
    )]
    NotSymmetric {
        /// Solver name.
        solver: &'static str,
        /// The offending entry, or "built with from_general".
        detail: String,
    },
    /// The dense solver refuses systems above its size cap.
    #[error(
        "dense: n = {n} exceeds the cap of {cap} rows (n² doubles of memory, n³ work); use Solver::Ldl or \
         Solver::Cg"
    )]
    TooLarge {
        /// Rows of the system.
        n: usize,
        /// The cap in force.
        cap: usize,
    },
    /// Bad user data: non-finite values, d ≤ 0, a dimension mismatch.
    #[error("invalid input: {0}")]
    InvalidInput(String),
}
