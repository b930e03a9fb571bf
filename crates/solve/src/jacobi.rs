//! Jacobi iteration: x_i ← x_i + (p_i − (A·X)_i)/a_ii, all rows at once.
//!
//! # What
//! Richardson's iteration preconditioned by the diagonal of A. For
//! A = D·S, a_ii = d_i·s_ii and the update is (b_i − (S·X)_i)/s_ii with
//! b = D⁻¹P: Jacobi on A and on S coincide, so D does not matter.
//!
//! # Reference
//! Zheng & Cai 2005, §3.2 and Eq. 7 (the Jacobi form of their iteration;
//! ZC05 in [references]); Saad, *Iterative
//! Methods for Sparse Linear Systems*, §4.1.
//!
//! # Algorithm
//! 1. w_i = 1/a_ii (error `Singular` if a diagonal entry is 0).
//! 2. X₀ = P; X_{k+1} = X_k + W(P − A X_k), fused with the residual norm
//!    (`richardson.rs`), until max_i ‖r_i‖ ≤ tol·scale.
//!
//! # Convergence
//! Converges when A is strictly diagonally dominant — Zheng-Cai's matrix is
//! ([correction Z7]: diagonal m + Σ1/m_i against off-diagonal sum m − Σ1/m_i) —
//! or, for symmetric positive definite S, iff 2·diag(S) − S is positive
//! definite. Many limit matrices are **not** in that class: the regular
//! bicubic mask (S = 16 | 4 | 1) has λ_max(S) = 36 > 2·16, so Jacobi
//! diverges ([`SolveError::Diverged`]); the regular Loop mask (S = 6 | 1) has
//! λ_max(S) = 12 = 2·6: the constant mode has factor −1, and Jacobi converges
//! only because the start X₀ = P leaves no constant component in the
//! residual (the rows of A sum to 1); from other starts it stalls
//! ([`SolveError::NotConverged`]). Use Gauss-Seidel (always convergent for
//! SPD S), PIA or CG there.
//!
//! # Deviations from the paper
//! Zheng & Cai stop after ITE_MAX = 5 iterations or at EPS; callers get
//! that with `max_iter = 5` and take the last iterate from
//! [`SolveError::NotConverged`]'s `x`.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{jacobi, FactoredMatrix, SolveOptions};
//! // Doo-Sabin's C of a 20 × 25 quad torus: strictly diagonally dominant (9/16 on the diagonal).
//! let m = subdiv_stencil::limit_matrix_doo_sabin(shapes::torus(20, 25).topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [i as f64, 1.0, -(i as f64)]).collect();
//! let sol = jacobi(&a, &p, &SolveOptions::default()).unwrap();
//! assert!(a.max_residual(&sol.x, &p) <= 1e-6);
//! ```
//!
//! [correction Z7]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z7
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use std::time::Instant;

use crate::error::SolveError;
use crate::matrix::FactoredMatrix;
use crate::richardson::{self, Step};
use crate::{Solution, SolveOptions};

/// Solves A·X = P by Jacobi iteration from X₀ = P.
///
/// A is n × n (any A = D·S, symmetric or not); P and X are n × 3.
///
/// # Errors
/// [`SolveError::Singular`] when a diagonal entry of A is zero, and the
/// errors of [`pia`](crate::pia()).
pub fn jacobi(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    let start = Instant::now();
    crate::matrix::validate(a, p, opts)?;
    let w = inverse_diagonal("jacobi", a)?;
    richardson::run("jacobi", a, p, opts, Step::PerRow(&w), 0, start)
}

/// 1/a_ii = 1/(d_i s_ii), or `Singular` naming the first zero diagonal.
pub(crate) fn inverse_diagonal(solver: &'static str, a: &FactoredMatrix) -> Result<Vec<f64>, SolveError> {
    let sd = a.s_diagonal();
    if let Some(i) = sd.iter().position(|&v| v == 0.0) {
        return Err(SolveError::Singular { solver, detail: format!("diagonal entry a[{i},{i}] is zero") });
    }
    Ok(sd.iter().zip(a.d()).map(|(s, d)| 1.0 / (s * d)).collect())
}
