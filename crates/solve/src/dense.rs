//! Dense Gaussian elimination with partial pivoting on the materialised A.
//!
//! # What
//! The method Zheng & Cai 2005 (§3.5) timed for Nasri's system: form A as a
//! dense n × n matrix and solve by LU with row pivoting. O(n²) memory and
//! O(n³) work — kept to reproduce that comparison and as the reference
//! answer of the tests, not for production sizes.
//!
//! # Reference
//! Zheng & Cai 2005, §3.5 (ZC05 in [references]);
//! G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., §3.4
//! (Gaussian elimination with partial pivoting); nalgebra's `LU`.
//!
//! # Algorithm
//! 1. Refuse n > cap ([`SolveError::TooLarge`]; default [`DENSE_MAX_N`],
//!    2 GiB of matrix).
//! 2. Materialise A = D·S densely; P A = L U by nalgebra's partial-pivoting LU.
//! 3. |u_kk| ≤ 10⁻¹²·max|u_jj| (`DENSE_PIVOT_RTOL`) → [`SolveError::Singular`].
//! 4. Solve the three columns at once; check the true residual; iterative
//!    refinement as in `ldl.rs`.
//!
//! # Deviations from the textbook
//! Works on any A (symmetric or not, from [`FactoredMatrix::from_general`]
//! too); the size cap is the caller's to raise.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{dense_lu, FactoredMatrix, SolveOptions};
//! use subdiv_stencil::{limit_matrix_loop, LoopBeta};
//! // Loop's limit matrix of the icosahedron (12 vertices of valence 5).
//! let m = limit_matrix_loop(shapes::icosahedron().topology(), LoopBeta::Warren).unwrap();
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [i as f64, 1.0, 2.0]).collect();
//! let sol = dense_lu(&a, &p, &SolveOptions::default()).unwrap();
//! assert!(a.max_residual(&sol.x, &p) <= 1e-12);
//! ```
//!
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use std::time::Instant;

use nalgebra::DMatrix;

use crate::error::SolveError;
use crate::ldl::refine;
use crate::matrix::{validate, FactoredMatrix};
use crate::tolerances::{DENSE_MAX_N, DENSE_PIVOT_RTOL};
use crate::{Solution, SolveOptions};

const NAME: &str = "dense";

/// Solves A·X = P by dense LU with partial pivoting, refusing n > [`DENSE_MAX_N`].
///
/// A is n × n (any A); P and X are n × 3.
///
/// # Errors
/// [`SolveError::TooLarge`], [`SolveError::Singular`],
/// [`SolveError::NotConverged`] (residual above tol after refinement),
/// [`SolveError::InvalidInput`].
pub fn dense_lu(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    dense_lu_capped(a, p, opts, DENSE_MAX_N)
}

/// [`dense_lu`] with the caller's size cap.
///
/// # Errors
/// As [`dense_lu`].
pub fn dense_lu_capped(
    a: &FactoredMatrix,
    p: &[[f64; 3]],
    opts: &SolveOptions,
    cap: usize,
) -> Result<Solution, SolveError> {
    let start = Instant::now();
    validate(a, p, opts)?;
    let n = a.n();
    if n > cap {
        return Err(SolveError::TooLarge { n, cap });
    }
    if n == 0 {
        return refine(NAME, a, p, opts, Vec::new(), |_| Vec::new(), start);
    }
    let mut m = DMatrix::<f64>::zeros(n, n);
    let s = a.csr();
    for i in 0..n {
        for k in s.indptr[i] as usize..s.indptr[i + 1] as usize {
            m[(i, s.indices[k] as usize)] = a.d()[i] * s.data[k];
        }
    }
    let lu = m.lu();
    let u = lu.u();
    let max = (0..n).fold(0.0f64, |acc, k| acc.max(u[(k, k)].abs()));
    if let Some(k) = (0..n).find(|&k| u[(k, k)].is_nan() || u[(k, k)].abs() <= DENSE_PIVOT_RTOL * max) {
        return Err(SolveError::Singular {
            solver: NAME,
            detail: format!("LU pivot {k} of {n} is {:.3e}, {:.1e} × the largest", u[(k, k)], u[(k, k)].abs() / max),
        });
    }
    drop(u);
    let solve = |rhs: &[[f64; 3]]| -> Vec<[f64; 3]> {
        let b = DMatrix::from_fn(n, 3, |i, c| rhs[i][c]);
        match lu.solve(&b) {
            Some(xm) => (0..n).map(|i| [xm[(i, 0)], xm[(i, 1)], xm[(i, 2)]]).collect(),
            None => vec![[f64::NAN; 3]; n],
        }
    };
    let x = solve(p);
    refine(NAME, a, p, opts, x, solve, start)
}
