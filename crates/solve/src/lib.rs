//! Solvers for the interpolation systems A·X = P of subdiv.
//!
//! Every interpolating method of the project ends in a square sparse system
//! whose matrix maps control points X to limit points A·X, with data points
//! P as right-hand side (n × 3: x, y, z solved together). Every limit matrix
//! has the factored form **A = D·S**, D diagonal positive, S symmetric
//! ([limit matrices]), carried by [`FactoredMatrix`]. This crate solves such systems;
//! it never sees a mesh.
//!
//! | solver | file | needs | cost per iteration |
//! |---|---|---|---|
//! | [`pia()`] (Cheng's progressive iteration) | [`pia.rs`](mod@pia) | spec(A) ⊂ (0, 2) | 1 product |
//! | [`weighted_pia()`] (ω = 2/(λ_min+λ_max)) | [`weighted_pia.rs`](mod@weighted_pia) | S symmetric, spec(A) > 0 | 1 product (+ Lanczos) |
//! | [`jacobi()`] | [`jacobi.rs`](mod@jacobi) | diagonal dominance (Zheng-Cai) | 1 product |
//! | [`gauss_seidel()`] (storage, symmetric, multicolour order) | [`gauss_seidel.rs`](mod@gauss_seidel) | S SPD or diagonal dominance | 1 sweep + 1 product |
//! | [`chebyshev()`] semi-iteration | [`chebyshev.rs`](mod@chebyshev) | S symmetric, spec(A) > 0 | 1 product (+ Lanczos) |
//! | [`cg()`] on S·X = D⁻¹P, optional Jacobi preconditioner | [`cg.rs`](mod@cg) | S SPD | 1 product + 2 streams |
//! | [`minres()`] on S·X = D⁻¹P, preconditioned by \|diag S\| | [`minres.rs`](mod@minres) | S symmetric (indefinite, singular consistent fine) | 1 product + 2 streams |
//! | [`gmres()`] GMRES(m), right Jacobi preconditioner | [`gmres.rs`](mod@gmres) | any nonsingular A (S need not be symmetric) | 1 product + j + 2 streams at step j |
//! | [`ldl()`] sparse LDLᵀ (Nasri's direct baseline) | [`ldl.rs`](mod@ldl) | S symmetric nonsingular (indefinite is fine) | factorisation |
//! | [`dense_lu`] Gaussian elimination, partial pivoting | [`dense.rs`](mod@dense) | n ≤ cap | O(n³) |
//!
//! plus [`extreme_eigenvalues`] (Lanczos) and [`power_iteration`] for the
//! spectrum, and [`Solver`] to pick one by name.
//!
//! **What it does not do**: build matrices from meshes (`subdiv-stencil`),
//! print, or guess a scale: every tolerance is relative to the caller's
//! `scale` (the data's bounding-box diagonal, [how the error is measured]).
//!
//! **Stopping rule** (all solvers): max_i ‖P_i − (A·X)_i‖₂ / scale ≤ tol, the
//! quantity the papers use ([the stopping rule]), always evaluated on the true
//! A-residual before `Ok` is returned. A solve that does not get there is an
//! error carrying its diagnostics ([`SolveError::NotConverged`] with the
//! iterations, residual history and last iterate), never a silent wrong
//! answer; singular and indefinite matrices are named as such.
//!
//! **Determinism**: results are bitwise identical for any rayon thread count
//! (fixed row chunks, in-order reductions; `kernels.rs`). Every tolerance
//! and tuning constant lives in one file, `tolerances.rs` (the names in code
//! font next to a value in these docs, such as `LANCZOS_STEPS`); the
//! defaults of [`SolveOptions`] are [`DEFAULT_TOL`] and [`DEFAULT_MAX_ITER`].
//!
//! **Options** ([`SolveOptions`]) are `#[non_exhaustive]`: build them from
//! `Default` with the `with_*` setters, so that a new option is not a
//! breaking change; results ([`Solution`], [`Spectrum`]) are
//! `#[non_exhaustive]` too, read through their public fields.
//!
//! The matrices come from `subdiv-stencil` (its limit matrices are A = D·S
//! with the same D and S):
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{FactoredMatrix, SolveOptions, Solver};
//! use subdiv_stencil::limit_matrix_catmull_clark;
//!
//! // Cheng's A of a 24 × 24 quad torus, every vertex regular: the bicubic
//! // limit mask, spec(A) = [1/9, 1].
//! let cheng = |mesh: subdiv_mesh::Mesh| {
//!     let m = limit_matrix_catmull_clark(mesh.topology());
//!     FactoredMatrix::new(m.d, m.s).unwrap()
//! };
//! let a = cheng(shapes::torus(24, 24));
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [(i % 24) as f64, (i / 24) as f64, ((i * 7) % 5) as f64]).collect();
//! let opts = SolveOptions::default().with_tol(1e-8).with_scale(24.0 * 2f64.sqrt());
//!
//! let by_pia = Solver::Pia.solve(&a, &p, &opts).unwrap();
//! let by_cg = Solver::Cg { jacobi: true }.solve(&a, &p, &opts).unwrap();
//! let by_ldl = Solver::Ldl.solve(&a, &p, &opts).unwrap();
//! assert!(by_cg.iterations < by_pia.iterations / 3);
//! // The stopping quantity is the true residual, and all three agree.
//! for sol in [&by_pia, &by_cg, &by_ldl] {
//!     assert!(a.max_residual(&sol.x, &p) / opts.scale <= 1e-8);
//!     let gap = sol.x.iter().zip(&by_ldl.x).map(|(u, v)| (u[0] - v[0]).abs()).fold(0.0, f64::max);
//!     assert!(gap < 1e-6);
//! }
//!
//! // Cheng's A of the pillow (two quads glued along their boundary, every
//! // vertex of valence 2) is indefinite: PIA diverges, CG says why, LDLᵀ solves it.
//! let pillow = cheng(shapes::pillow());
//! let q = vec![[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0], [1.0, 1.0, 1.0]];
//! assert!(matches!(Solver::Pia.solve(&pillow, &q, &opts), Err(subdiv_solve::SolveError::Diverged { .. })));
//! assert!(matches!(Solver::Cg { jacobi: false }.solve(&pillow, &q, &opts), Err(subdiv_solve::SolveError::Indefinite { .. })));
//! assert_eq!(Solver::Ldl.solve(&pillow, &q, &opts).unwrap().negative_pivots, Some(1));
//! // MINRES needs only the symmetry, GMRES not even that: both solve it too.
//! for s in [Solver::Minres, Solver::Gmres] {
//!     assert!(pillow.max_residual(&s.solve(&pillow, &q, &opts).unwrap().x, &q) / opts.scale <= 1e-8);
//! }
//! ```
//!
//! [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
//! [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
#![warn(missing_docs)]

pub mod cg;
pub mod chebyshev;
pub mod dense;
mod error;
pub mod gauss_seidel;
pub mod gmres;
#[doc(hidden)]
pub mod internals;
pub mod jacobi;
mod kernels;
pub mod ldl;
mod matrix;
pub mod minres;
pub mod ordering;
pub mod pia;
mod report;
mod richardson;
pub mod spectrum;
mod tolerances;
pub mod weighted_pia;

use std::fmt;
use std::str::FromStr;

pub use cg::{cg, cg_start, RowSource, RowVisitor};
pub use chebyshev::{chebyshev, chebyshev_with};
pub use dense::{dense_lu, dense_lu_capped};
pub use error::{LastIterate, SolveError, StopReason};
pub use gauss_seidel::{gauss_seidel, SweepOrder};
pub use gmres::{gmres, gmres_restarted};
pub use jacobi::jacobi;
pub use ldl::{ldl, LdlFactor};
pub use matrix::{is_symmetric, FactoredMatrix, SparseMatrix};
pub use minres::minres;
pub use ordering::{nested_dissection, Ordering};
pub use pia::pia;
pub use report::{IterationObserver, Solution, SolveOptions};
pub use spectrum::{extreme_eigenvalues, power_iteration, Spectrum};
pub use tolerances::{DEFAULT_MAX_ITER, DEFAULT_TOL, DENSE_MAX_N};
pub use weighted_pia::{weighted_pia, weighted_pia_with};

/// A solver, selectable by name (`"pia"`, `"weighted-pia"`, `"jacobi"`,
/// `"gauss-seidel"`, `"gauss-seidel-symmetric"`, `"gauss-seidel-multicolor"`,
/// `"chebyshev"`, `"cg"`, `"cg-jacobi"`, `"minres"`, `"gmres"`, `"ldl"`, `"dense"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Solver {
    /// Progressive iteration, ω = 1 ([`pia()`]).
    Pia,
    /// Richardson with ω = 2/(λ_min + λ_max) ([`weighted_pia()`]).
    WeightedPia,
    /// Jacobi ([`jacobi()`]).
    Jacobi,
    /// Gauss-Seidel in the given order ([`gauss_seidel()`]).
    GaussSeidel(SweepOrder),
    /// Chebyshev semi-iteration ([`chebyshev()`]).
    Chebyshev,
    /// Conjugate gradients on S·X = D⁻¹P ([`cg()`]); `jacobi` = diagonal preconditioner.
    Cg {
        /// Precondition with diag(S).
        jacobi: bool,
    },
    /// MINRES on S·X = D⁻¹P ([`minres()`]): S symmetric, possibly indefinite.
    Minres,
    /// Restarted GMRES with right Jacobi preconditioning ([`gmres()`]): any A.
    Gmres,
    /// Sparse LDLᵀ of S ([`ldl()`]).
    Ldl,
    /// Dense LU with partial pivoting ([`dense_lu`]), default size cap.
    Dense,
}

impl Solver {
    /// Every solver, in the order of the crate table.
    pub const ALL: [Solver; 13] = [
        Solver::Pia,
        Solver::WeightedPia,
        Solver::Jacobi,
        Solver::GaussSeidel(SweepOrder::Storage),
        Solver::GaussSeidel(SweepOrder::Symmetric),
        Solver::GaussSeidel(SweepOrder::Multicolor),
        Solver::Chebyshev,
        Solver::Cg { jacobi: false },
        Solver::Cg { jacobi: true },
        Solver::Minres,
        Solver::Gmres,
        Solver::Ldl,
        Solver::Dense,
    ];

    /// The name used in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Pia => "pia",
            Solver::WeightedPia => "weighted-pia",
            Solver::Jacobi => "jacobi",
            Solver::GaussSeidel(order) => order.solver_name(),
            Solver::Chebyshev => "chebyshev",
            Solver::Cg { jacobi: false } => "cg",
            Solver::Cg { jacobi: true } => "cg-jacobi",
            Solver::Minres => "minres",
            Solver::Gmres => "gmres",
            Solver::Ldl => "ldl",
            Solver::Dense => "dense",
        }
    }

    /// Whether the solver needs S symmetric (else `NotSymmetric`).
    pub fn needs_symmetric(self) -> bool {
        matches!(self, Solver::WeightedPia | Solver::Chebyshev | Solver::Cg { .. } | Solver::Minres | Solver::Ldl)
    }

    /// Whether the solver needs A positive definite (spec(A) > 0): it
    /// diverges, stalls or reports `Indefinite` on an indefinite A (Cheng's
    /// matrix with valence-2 vertices). MINRES, GMRES, LDLᵀ and dense LU do
    /// not; Jacobi and Gauss-Seidel are counted here too (no convergence
    /// theory for indefinite A).
    pub fn needs_definite(self) -> bool {
        !matches!(self, Solver::Minres | Solver::Gmres | Solver::Ldl | Solver::Dense)
    }

    /// Solves A·X = P (A n × n, P n × 3) with this solver.
    ///
    /// # Errors
    /// The solver's errors; see [`SolveError`].
    pub fn solve(self, a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
        match self {
            Solver::Pia => pia(a, p, opts),
            Solver::WeightedPia => weighted_pia(a, p, opts),
            Solver::Jacobi => jacobi(a, p, opts),
            Solver::GaussSeidel(order) => gauss_seidel(a, p, opts, order),
            Solver::Chebyshev => chebyshev(a, p, opts),
            Solver::Cg { jacobi } => cg(a, p, opts, jacobi),
            Solver::Minres => minres(a, p, opts),
            Solver::Gmres => gmres(a, p, opts),
            Solver::Ldl => ldl(a, p, opts),
            Solver::Dense => dense_lu(a, p, opts),
        }
    }
}

impl fmt::Display for Solver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Solver {
    type Err = SolveError;

    /// Parses a [`Solver::name`]; `"gauss-seidel"` is the storage order
    /// (Zheng-Cai Eq. 7).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Solver::ALL.into_iter().find(|v| v.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Solver::ALL.iter().map(|v| v.name()).collect();
            SolveError::InvalidInput(format!("unknown solver {s:?}; expected one of {}", names.join(", ")))
        })
    }
}

/// Solves A·X = P with `solver` (same as [`Solver::solve`]).
///
/// # Errors
/// The solver's errors; see [`SolveError`].
pub fn solve(solver: Solver, a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    solver.solve(a, p, opts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for s in Solver::ALL {
            assert_eq!(s.name().parse::<Solver>().unwrap(), s);
            assert_eq!(s.to_string(), s.name());
        }
        assert!(matches!("sor".parse::<Solver>(), Err(SolveError::InvalidInput(_))));
    }
}
