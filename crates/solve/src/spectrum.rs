//! Extreme eigenvalue estimates of A = D·S: Lanczos and power iteration.
//!
//! # What
//! Weighted PIA needs ω = 2/(λ_min + λ_max) and Chebyshev needs an interval
//! [λ_min, λ_max] containing spec(A). Both come from a few Lanczos steps.
//! Tests and reports use the same estimates to state the eigenvalue range
//! of a limit matrix (the Cheng table of [paper reproduction]).
//!
//! # Reference
//! C. Lanczos (1950); G. H. Golub, C. F. Van Loan, *Matrix Computations*,
//! 4th ed., §10.1-10.3 (Lanczos, Kaniel-Paige theory, reorthogonalisation);
//! B. N. Parlett, *The Symmetric Eigenvalue Problem*, ch. 13 (loss of
//! orthogonality produces copies of converged Ritz values, not wrong ones).
//!
//! # Algorithm
//! A = D·S is similar to the symmetric H = D^{1/2}·S·D^{1/2}
//! (A = D^{1/2}·H·D^{-1/2}), so spec(A) = spec(H) is real and Lanczos on H
//! applies.
//! 1. v₁ = a fixed pseudo-random unit vector (SplitMix64; a constant start
//!    would be an exact eigenvector of every regular torus matrix).
//! 2. For j = 1..k: w = H·v_j − β_{j−1}·v_{j−1}; α_j = wᵀv_j; w −= α_j·v_j;
//!    with full reorthogonalisation, w −= Σ_i (wᵀv_i)·v_i twice (modified
//!    Gram-Schmidt); β_j = ‖w‖; stop early if β_j ≈ 0 (invariant subspace:
//!    the Ritz values are exact); v_{j+1} = w/β_j.
//! 3. Eigen-decompose the k × k tridiagonal T_k = tridiag(β, α, β) (nalgebra):
//!    the extreme Ritz values θ_min ≥ λ_min and θ_max ≤ λ_max (Cauchy
//!    interlacing), with residual bounds |β_k·y_k| (an eigenvalue of A lies
//!    within that distance of θ).
//! 4. Widen to the bracket [`Spectrum::min`, `Spectrum::max`]: θ_min by
//!    2 % (`SPECTRUM_MARGIN`); θ_max by the larger of 2 % and its residual
//!    bound, capped at ‖A‖_∞ (a rigorous bound of ρ(A), equal to 1 for
//!    every limit matrix: rows of non-negative weights summing to 1). The
//!    upper end matters most: Chebyshev and weighted PIA diverge on an
//!    eigenvalue above min + max, while an eigenvalue below min only slows
//!    them.
//!
//! # Deviations from the textbook
//! - Full reorthogonalisation (in [`extreme_eigenvalues`]) only while
//!   n·k ≤ 8·10⁶ numbers (`LANCZOS_REORTH_MAX_STORE`); above it (the 10⁶-row
//!   systems) the plain three-term recurrence runs in O(n) memory. The
//!   solvers (weighted PIA, Chebyshev) always use the plain recurrence: only
//!   extreme Ritz values are needed, loss of orthogonality duplicates them
//!   rather than moving them (Parlett), and reorthogonalising k vectors
//!   costs O(k²n) — more than the solve it serves.
//! - The bracket's margin is heuristic, not a rigorous bound; the solvers
//!   that use it tolerate moderate errors (see `chebyshev.rs`).
//! - Every dot product is a fixed-chunk reduction: same bits for any thread count.
//!
//! [paper reproduction]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-paper-reproduction

use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::SolveError;
use crate::kernels::{self, map_chunks, reduce_chunks, splitmix_unit};
use crate::matrix::FactoredMatrix;
use crate::tolerances::{LANCZOS_BREAKDOWN_RTOL, LANCZOS_REORTH_MAX_STORE, SPECTRUM_MARGIN};

/// Estimated extreme eigenvalues of A.
///
/// `#[non_exhaustive]`: made by [`extreme_eigenvalues`], or from a known
/// bracket by [`Spectrum::bracket`] (for [`chebyshev_with`](crate::chebyshev_with)
/// and [`weighted_pia_with`](crate::weighted_pia_with)); read through its
/// public fields.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Spectrum {
    /// Lower end of the bracket: θ_min − margin (intended ≤ λ_min).
    pub min: f64,
    /// Upper end of the bracket: θ_max + margin (intended ≥ λ_max).
    pub max: f64,
    /// Smallest Ritz value θ_min (≥ λ_min).
    pub ritz_min: f64,
    /// Largest Ritz value θ_max (≤ λ_max).
    pub ritz_max: f64,
    /// Residual bound of θ_min: some eigenvalue lies within it.
    pub residual_min: f64,
    /// Residual bound of θ_max.
    pub residual_max: f64,
    /// Lanczos steps taken (fewer than asked on breakdown or when n is small).
    pub steps: usize,
    /// Sparse products spent.
    pub matvecs: usize,
}

impl Spectrum {
    /// A known bracket [`min`, `max`] of spec(A), without Lanczos data: the
    /// Ritz values are the ends, the residual bounds 0, no step or product
    /// spent. Weighted PIA refuses a bracket that reaches 0; Chebyshev trusts
    /// it (it converges for moderate errors in either end).
    ///
    /// ```
    /// // The regular bicubic limit mask has spec(A) = [1/9, 1].
    /// let s = subdiv_solve::Spectrum::bracket(1.0 / 9.0, 1.0);
    /// assert!((s.condition() - 9.0).abs() < 1e-12 && s.matvecs == 0);
    /// ```
    pub fn bracket(min: f64, max: f64) -> Self {
        Self { min, max, ritz_min: min, ritz_max: max, residual_min: 0.0, residual_max: 0.0, steps: 0, matvecs: 0 }
    }

    /// This estimate with the bracket [`min`, `max`] instead (e.g. widened by
    /// a safety margin); the Lanczos data are kept.
    pub fn with_bracket(self, min: f64, max: f64) -> Self {
        Self { min, max, ..self }
    }

    /// The step length of weighted PIA, ω = 2/(min + max): it minimises
    /// max |1 − ωλ| over the bracket.
    pub fn optimal_omega(&self) -> f64 {
        2.0 / (self.min + self.max)
    }

    /// Bracket condition number max/min (∞ when min ≤ 0).
    pub fn condition(&self) -> f64 {
        if self.min > 0.0 {
            self.max / self.min
        } else {
            f64::INFINITY
        }
    }
}

/// y = H·v with H = D^{1/2}·S·D^{1/2}; `u` is scratch (u = D^{1/2} v).
fn apply_h(a: &FactoredMatrix, sq: &[f64], v: &[f64], u: &mut [f64], y: &mut [f64], unit: &mut [()]) {
    map_chunks(u, unit, |lo, out| {
        for (q, o) in out.iter_mut().enumerate() {
            *o = sq[lo + q] * v[lo + q];
        }
    });
    let s = a.csr();
    let u: &[f64] = u;
    map_chunks(y, unit, |lo, out| {
        for (q, o) in out.iter_mut().enumerate() {
            let i = lo + q;
            *o = sq[i] * s.row_times_1(i, u);
        }
    });
}

/// ‖A‖_∞ = max_i d_i Σ_j |s_ij|, an upper bound of every |λ(A)|.
fn norm_inf(a: &FactoredMatrix) -> f64 {
    let s = a.csr();
    (0..a.n())
        .map(|i| a.d()[i] * s.data[s.indptr[i] as usize..s.indptr[i + 1] as usize].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Fixed-chunk dot product.
fn dot(a: &[f64], b: &[f64], partials: &mut [f64]) -> f64 {
    reduce_chunks(a.len(), partials, |rows| rows.map(|i| a[i] * b[i]).sum::<f64>());
    partials.iter().sum()
}

/// y += alpha·x over fixed chunks.
fn axpy(alpha: f64, x: &[f64], y: &mut [f64], unit: &mut [()]) {
    map_chunks(y, unit, |lo, out| {
        for (q, o) in out.iter_mut().enumerate() {
            *o += alpha * x[lo + q];
        }
    });
}

/// Lanczos estimate of the extreme eigenvalues of A = D·S (`steps` ≈ 30-60).
///
/// # Errors
/// [`SolveError::NotSymmetric`] when S is not symmetric (the similarity to a
/// symmetric matrix needs it); [`SolveError::InvalidInput`] for an empty
/// matrix or `steps == 0`.
pub fn extreme_eigenvalues(a: &FactoredMatrix, steps: usize) -> Result<Spectrum, SolveError> {
    lanczos(a, steps, true)
}

/// Lanczos with full reorthogonalisation when `allow_reorth` and the basis
/// fits [`LANCZOS_REORTH_MAX_STORE`]; the solvers pass `false` (extreme
/// Ritz values need no reorthogonalisation, and it would cost more than the
/// solve itself).
pub(crate) fn lanczos(a: &FactoredMatrix, steps: usize, allow_reorth: bool) -> Result<Spectrum, SolveError> {
    a.require_symmetric("lanczos")?;
    let n = a.n();
    if n == 0 || steps == 0 {
        return Err(SolveError::InvalidInput(format!("Lanczos needs n ≥ 1 and steps ≥ 1 (n = {n}, steps = {steps})")));
    }
    let k_max = steps.min(n);
    let reorth = allow_reorth && n.saturating_mul(k_max) <= LANCZOS_REORTH_MAX_STORE;
    let sq: Vec<f64> = a.d().iter().map(|d| d.sqrt()).collect();
    let chunks = kernels::n_chunks(n);
    let mut unit = vec![(); chunks];
    let mut partials = vec![0.0; chunks];

    let mut v: Vec<f64> = (0..n).map(|i| splitmix_unit(0x5EED_1A4C_2025, i as u64)).collect();
    let nv = dot(&v, &v, &mut partials).sqrt();
    v.iter_mut().for_each(|x| *x /= nv);
    let mut v_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut alpha = Vec::with_capacity(k_max);
    let mut beta: Vec<f64> = Vec::with_capacity(k_max);
    let mut matvecs = 0;
    let mut t_norm = 0.0f64;

    let s = a.csr();
    for j in 0..k_max {
        // Pass 1: w = H v − β_{j−1} v_{j−1}, fused with α_j = wᵀv.
        let b_prev = if j > 0 { beta[j - 1] } else { 0.0 };
        {
            let (v, vp, sq) = (&v, &v_prev, &sq);
            map_chunks(&mut w, &mut partials, |lo, out| {
                let mut acc = 0.0;
                for (q, o) in out.iter_mut().enumerate() {
                    let i = lo + q;
                    let mut h = 0.0;
                    for k in s.indptr[i] as usize..s.indptr[i + 1] as usize {
                        let c = s.indices[k] as usize;
                        h += s.data[k] * sq[c] * v[c];
                    }
                    *o = sq[i] * h - b_prev * vp[i];
                    acc += *o * v[i];
                }
                acc
            });
        }
        matvecs += 1;
        let aj: f64 = partials.iter().sum();
        // Pass 2: w −= α_j v, fused with ‖w‖².
        {
            let v = &v;
            map_chunks(&mut w, &mut partials, |lo, out| {
                let mut acc = 0.0;
                for (q, o) in out.iter_mut().enumerate() {
                    *o -= aj * v[lo + q];
                    acc += *o * *o;
                }
                acc
            });
        }
        let mut bj = partials.iter().sum::<f64>().sqrt();
        if reorth {
            basis.push(v.clone());
            for _ in 0..2 {
                for q in &basis {
                    let c = dot(&w, q, &mut partials);
                    axpy(-c, q, &mut w, &mut unit);
                }
            }
            bj = dot(&w, &w, &mut partials).sqrt();
        }
        alpha.push(aj);
        t_norm = t_norm.max(aj.abs() + bj + b_prev);
        beta.push(bj);
        if !bj.is_finite() || !aj.is_finite() {
            return Err(SolveError::InvalidInput("Lanczos produced a non-finite value".to_owned()));
        }
        if bj <= LANCZOS_BREAKDOWN_RTOL * t_norm || j + 1 == k_max {
            break;
        }
        // Pass 3: v_{j+1} = w/β_j.
        std::mem::swap(&mut v_prev, &mut v);
        map_chunks(&mut v, &mut unit, |lo, out| {
            for (q, o) in out.iter_mut().enumerate() {
                *o = w[lo + q] / bj;
            }
        });
    }

    let k = alpha.len();
    let t = DMatrix::from_fn(k, k, |i, j| {
        if i == j {
            alpha[i]
        } else if i + 1 == j {
            beta[i]
        } else if j + 1 == i {
            beta[j]
        } else {
            0.0
        }
    });
    let eig = SymmetricEigen::new(t);
    let (mut imin, mut imax) = (0, 0);
    for i in 0..k {
        if eig.eigenvalues[i] < eig.eigenvalues[imin] {
            imin = i;
        }
        if eig.eigenvalues[i] > eig.eigenvalues[imax] {
            imax = i;
        }
    }
    let b_last = if k == n { 0.0 } else { beta[k - 1] };
    let ritz_min = eig.eigenvalues[imin];
    let ritz_max = eig.eigenvalues[imax];
    let residual_max = (b_last * eig.eigenvectors[(k - 1, imax)]).abs();
    // Upper end: widened by the margin or the residual bound, whichever is
    // larger, but never above ‖A‖_∞ ≥ ρ(A) (rigorous; = 1 for limit matrices).
    let max = (ritz_max + (SPECTRUM_MARGIN * ritz_max.abs()).max(residual_max)).min(norm_inf(a)).max(ritz_max);
    Ok(Spectrum {
        min: ritz_min - SPECTRUM_MARGIN * ritz_min.abs(),
        max,
        ritz_min,
        ritz_max,
        residual_min: (b_last * eig.eigenvectors[(k - 1, imin)]).abs(),
        residual_max,
        steps: k,
        matvecs,
    })
}

/// Power-iteration estimate of the dominant eigenvalue magnitude |λ|_max of A
/// (`steps` products). For a symmetric S it iterates on D^{1/2}·S·D^{1/2} and
/// returns the Rayleigh quotient (a lower bound of λ_max when λ_max is
/// dominant); otherwise it iterates on A and returns ‖A·v‖/‖v‖. Slower to
/// converge than Lanczos; kept as the textbook cross-check.
///
/// # Errors
/// [`SolveError::InvalidInput`] for an empty matrix or `steps == 0`.
pub fn power_iteration(a: &FactoredMatrix, steps: usize) -> Result<f64, SolveError> {
    let n = a.n();
    if n == 0 || steps == 0 {
        return Err(SolveError::InvalidInput(format!("power iteration needs n ≥ 1 and steps ≥ 1 (n = {n})")));
    }
    let sym = a.symmetric();
    let sq: Vec<f64> = if sym { a.d().iter().map(|d| d.sqrt()).collect() } else { vec![1.0; n] };
    let d_general: Vec<f64> = if sym { Vec::new() } else { a.d().to_vec() };
    let chunks = kernels::n_chunks(n);
    let mut unit = vec![(); chunks];
    let mut partials = vec![0.0; chunks];
    let mut v: Vec<f64> = (0..n).map(|i| splitmix_unit(0xB0_0B5, i as u64)).collect();
    let mut w = vec![0.0; n];
    let mut u = vec![0.0; n];
    let mut estimate = 0.0;
    for _ in 0..steps {
        let nv = dot(&v, &v, &mut partials).sqrt();
        if nv == 0.0 || !nv.is_finite() {
            return Ok(estimate);
        }
        v.iter_mut().for_each(|x| *x /= nv);
        apply_h(a, &sq, &v, &mut u, &mut w, &mut unit);
        if !sym {
            w.iter_mut().zip(&d_general).for_each(|(x, d)| *x *= d);
        }
        estimate = if sym { dot(&w, &v, &mut partials).abs() } else { dot(&w, &w, &mut partials).sqrt() };
        std::mem::swap(&mut v, &mut w);
    }
    Ok(estimate)
}
