//! Weighted PIA: X ← X + ω(P − A·X) with the optimal ω = 2/(λ_min + λ_max).
//!
//! # What
//! Richardson's iteration with the step that balances the slowest and the
//! fastest error modes. Same cost per iteration as PIA; the contraction
//! improves from 1 − λ_min to (κ − 1)/(κ + 1), κ = λ_max/λ_min.
//!
//! # Reference
//! L. F. Richardson (1911); Y. Saad, *Iterative Methods for Sparse Linear
//! Systems*, 2nd ed., §4.2.1 (optimal ω for SPD matrices); the weighted
//! progressive-iteration literature (Lu 2010, *Weighted progressive
//! iteration approximation and convergence analysis*, CAGD 27) applies it to
//! PIA. Cheng's PIA (`pia.rs`) is the ω = 1 case.
//!
//! # Algorithm
//! 1. Estimate [λ_min, λ_max] of A with Lanczos on D^{1/2}SD^{1/2}
//!    ([`extreme_eigenvalues`](crate::extreme_eigenvalues),
//!    16 steps, `LANCZOS_STEPS`; the products count in `matvecs`).
//! 2. ω = 2/(λ_min + λ_max) ([`Spectrum::optimal_omega`]).
//! 3. Iterate X_{k+1} = X_k + ω(P − A X_k) from X₀ = P with the fused sweep
//!    of `richardson.rs`, stopping on the max row residual.
//!
//! # Deviations from the textbook
//! - The interval is an estimate widened by 2 % (`spectrum.rs`): the
//!   iteration converges for any ω < 2/λ_max, so a slightly wide interval
//!   costs a few iterations, never convergence.
//! - A spectrum estimate with λ_min ≤ 0 is reported as
//!   [`SolveError::Indefinite`] (or `Singular` when ≈ 0) before iterating.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{pia, weighted_pia, FactoredMatrix, SolveOptions};
//! // Cheng's A of a 16 × 16 quad torus (the bicubic limit mask): spec(A) = [1/9, 1].
//! let m = subdiv_stencil::limit_matrix_catmull_clark(shapes::torus(16, 16).topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [(i % 7) as f64, (i % 3) as f64, 1.0]).collect();
//! let fast = weighted_pia(&a, &p, &SolveOptions::default()).unwrap();
//! let slow = pia(&a, &p, &SolveOptions::default()).unwrap();
//! assert!(fast.iterations < slow.iterations);
//! ```

use std::time::Instant;

use crate::error::SolveError;
use crate::matrix::FactoredMatrix;
use crate::richardson::{self, Step};
use crate::spectrum::{lanczos, Spectrum};
use crate::tolerances::{LANCZOS_STEPS, SINGULAR_SPECTRUM_RTOL};
use crate::{Solution, SolveOptions};

/// Solves A·X = P by weighted PIA with ω from a Lanczos estimate.
///
/// A is n × n with S symmetric; P and X are n × 3.
///
/// # Errors
/// [`SolveError::NotSymmetric`] (Lanczos needs S symmetric),
/// [`SolveError::Indefinite`] / [`SolveError::Singular`] when the estimated
/// λ_min ≤ 0, and the errors of [`pia`](crate::pia()).
pub fn weighted_pia(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    let start = Instant::now();
    crate::matrix::validate(a, p, opts)?;
    if a.n() == 0 {
        return richardson::run("weighted-pia", a, p, opts, Step::Scalar(1.0), 0, start);
    }
    let spec = lanczos(a, LANCZOS_STEPS, false)?;
    check_positive("weighted-pia", &spec)?;
    richardson::run("weighted-pia", a, p, opts, Step::Scalar(spec.optimal_omega()), spec.matvecs, start)
}

/// Weighted PIA with a caller-supplied interval (no Lanczos run): ω =
/// 2/(spectrum.min + spectrum.max).
///
/// # Errors
/// As [`weighted_pia()`], except `NotSymmetric` (no estimate is computed).
pub fn weighted_pia_with(
    a: &FactoredMatrix,
    p: &[[f64; 3]],
    opts: &SolveOptions,
    spectrum: &Spectrum,
) -> Result<Solution, SolveError> {
    check_positive("weighted-pia", spectrum)?;
    richardson::run("weighted-pia", a, p, opts, Step::Scalar(spectrum.optimal_omega()), 0, Instant::now())
}

/// `Err` unless the bracket is (numerically) positive.
pub(crate) fn check_positive(solver: &'static str, s: &Spectrum) -> Result<(), SolveError> {
    if s.ritz_min < -SINGULAR_SPECTRUM_RTOL * s.ritz_max.abs() {
        return Err(SolveError::Indefinite {
            solver,
            detail: format!("Lanczos found the eigenvalue estimate {:.6} < 0", s.ritz_min),
        });
    }
    if s.ritz_min <= SINGULAR_SPECTRUM_RTOL * s.ritz_max.abs() || s.min <= 0.0 || s.max <= s.min || s.max.is_nan() {
        return Err(SolveError::Singular {
            solver,
            detail: format!("the eigenvalue estimates [{:.3e}, {:.3e}] reach 0", s.ritz_min, s.ritz_max),
        });
    }
    Ok(())
}
