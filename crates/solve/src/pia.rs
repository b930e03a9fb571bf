//! Progressive iterative approximation (PIA): X ← X + (P − A·X).
//!
//! # What
//! The interpolation iteration of Cheng et al.: move every control point by
//! its current interpolation error. Started at X₀ = P it is Richardson's
//! iteration with ω = 1 on A·X = P.
//!
//! # Reference
//! F. Cheng, F. Fan, S. Lai, C. Huang, J. Wang, J. Yong, *Loop subdivision
//! surface based progressive interpolation* / the Catmull-Clark variant
//! (Cheng et al., *Interpolating meshes of arbitrary topology*, §2, Eq. 1-3;
//! CFL in [references]).
//! Their "M_{i+1} = M_i − L(M_i), control mesh = Σ M_i" is this iteration
//! ([correction C6]). Fan-Cheng-Lai use the same iteration for Doo-Sabin (Eq. 3).
//!
//! # Algorithm
//! 1. X₀ = P (or the caller's start).
//! 2. For k = 0, 1, …: R_k = P − A·X_k; stop if max_i ‖R_{k,i}‖ ≤ tol·scale;
//!    X_{k+1} = X_k + R_k. Steps 2's product, the residual norm and the update
//!    are one fused pass (`richardson.rs`).
//!
//! # Convergence
//! The error contracts by ρ(I − A) = max |1 − λ| per iteration: PIA
//! converges iff spec(A) ⊂ (0, 2). Every limit matrix with spectrum in
//! (0, 1] qualifies ([correction F6]: ρ ≤ 1 − λ_min for Fan's B(λ); [correction Z8]: λ_min ≥ ¼
//! for Nasri's C). Catmull-Clark with a valence-2 vertex has λ_min < 0 and
//! PIA diverges ([`SolveError::Diverged`]); the all-valence-3 bipartite case
//! has λ = 0 and PIA stalls ([`SolveError::NotConverged`], reason
//! `Stagnated`).
//!
//! # Deviations from the paper
//! - The papers stop on the max vertex error; so do we, but relative to the
//!   caller's `scale` and with divergence and stagnation detection.
//! - The iteration is run on all three coordinates at once.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{pia, FactoredMatrix, SolveOptions};
//! // Nasri's C (Doo-Sabin) of a 12 × 12 quad torus: spec(C) ⊂ [¼, 1].
//! let m = subdiv_stencil::limit_matrix_doo_sabin(shapes::torus(12, 12).topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [i as f64, 1.0, (i % 5) as f64]).collect();
//! let sol = pia(&a, &p, &SolveOptions::default()).unwrap();
//! // λ_min ≥ ¼, so the error shrinks by ¾ per step: log(1e-6·…)/log(¾) steps.
//! assert!(sol.iterations < 70 && sol.residual <= 1e-6);
//! assert!(a.max_residual(&sol.x, &p) <= 1e-6);
//! ```
//!
//! [correction C6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c6
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
//! [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use std::time::Instant;

use crate::error::SolveError;
use crate::matrix::FactoredMatrix;
use crate::richardson::{self, Step};
use crate::{Solution, SolveOptions};

/// Solves A·X = P by progressive iteration (Richardson, ω = 1), from X₀ = P.
///
/// A is n × n, P and X are n × 3.
///
/// # Errors
/// [`SolveError::InvalidInput`] for bad data; [`SolveError::Diverged`] when
/// spec(A) ⊄ (0, 2); [`SolveError::NotConverged`] at `max_iter` or on stagnation.
pub fn pia(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    richardson::run("pia", a, p, opts, Step::Scalar(1.0), 0, Instant::now())
}
