//! Conjugate gradients on the symmetric form S·X = D⁻¹·P, optionally
//! preconditioned by diag(S) (Jacobi).
//!
//! # What
//! A = D·S is not symmetric, but A·X = P ⇔ S·X = b with b = D⁻¹P, and S is
//! symmetric positive definite whenever A's spectrum is positive (A and
//! D^{1/2}SD^{1/2} are similar, and S is congruent to the latter). CG on
//! S converges in O(√κ) iterations with no spectrum estimate. The three
//! columns x, y, z run together (one sparse product per iteration) with
//! independent scalars α, β per column.
//!
//! # Reference
//! M. R. Hestenes, E. Stiefel, *Methods of conjugate gradients for solving
//! linear systems*, J. Res. NBS 49 (1952); Y. Saad, *Iterative Methods for
//! Sparse Linear Systems*, 2nd ed., Algorithm 6.18 (CG) and 9.1
//! (preconditioned CG); H. A. van der Vorst, Q. Ye, *Residual replacement
//! strategies for Krylov subspace iterative methods*, SISC 22 (2000).
//!
//! # Algorithm (Saad Alg. 9.1, per column c)
//! 1. b = D⁻¹P, M = diag(S) or I; r₀ = b − S X₀, z₀ = M⁻¹r₀, p₀ = z₀.
//! 2. For k = 0, 1, …:
//!    q = S p_k; α_c = (r_c·z_c)/(p_c·q_c);
//!    X_c += α_c p_c; r_c −= α_c q_c; z = M⁻¹r;
//!    β_c = (r_c·z_c)_new/(r_c·z_c)_old; p_c = z_c + β_c p_c.
//!
//! One product and three streaming passes per iteration: (1) q = S·p fused
//! with the dot products pᵀq and pᵀp; (2) the X and r updates fused with
//! rᵀM⁻¹r and the stopping estimate; (3) the p update (z is never stored).
//!
//! # Deviations from the textbook
//! - **Stopping on the true A-residual.** CG's r is the residual of the
//!   symmetric form, b − S X; the A-residual is P − A X = D(b − S X). Each
//!   iteration evaluates the max row norm of D·r (free, in pass 2); when it
//!   reaches tol·scale the true residual P − A X is computed from scratch
//!   (one extra product) and must confirm it. If it does not (rounding drift
//!   of the recursive r), r is replaced by the true residual and CG restarts
//!   from p = z (van der Vorst-Ye), at most
//!   8 times (`CG_MAX_RESIDUAL_REPLACEMENTS`). The reported `residual` is always the
//!   true one; `history` holds the per-iteration estimates.
//! - **Indefiniteness.** pᵀSp < 0 for a search direction proves S (hence A)
//!   indefinite: [`SolveError::Indefinite`] with the Rayleigh quotient. With
//!   a generic right-hand side the Krylov space eventually contains the
//!   negative direction, so CG detects the pillow (λ_min = −1/7).
//!   A non-positive diagonal of S also proves it (when preconditioning).
//! - **Breakdown.** |pᵀSp| ≤ 10⁻¹³·|p|²·‖S‖_∞ (`CG_BREAKDOWN_RTOL`): the direction lies in
//!   the numerical null space (the checkerboard kernel): [`SolveError::Singular`].
//! - **Stagnation** (no 0.1 % progress in 200 iterations, typical of a
//!   singular inconsistent system) and `max_iter` give
//!   [`SolveError::NotConverged`] with the true residual.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{cg, FactoredMatrix, SolveOptions};
//! // Cheng's A of a 32 × 32 quad torus (the bicubic limit mask): spec(A) = [1/9, 1].
//! let m = subdiv_stencil::limit_matrix_catmull_clark(shapes::torus(32, 32).topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [(i % 32) as f64, (i / 32) as f64, 0.5]).collect();
//! let sol = cg(&a, &p, &SolveOptions::default(), true).unwrap();
//! assert!(sol.iterations < 40);
//! assert!(a.max_residual(&sol.x, &p) <= 1e-6);
//! ```

use std::time::Instant;

use crate::error::{SolveError, StopReason};
use crate::kernels::{self, fold_sum3, map_chunks, map_chunks2, max_nan, norm2, Csr, Row};
use crate::matrix::{validate, FactoredMatrix};
use crate::report::{initial_guess, Monitor, Verdict};
use crate::tolerances::{CG_BREAKDOWN_RTOL, CG_MAX_RESIDUAL_REPLACEMENTS};
use crate::{Solution, SolveOptions};

/// Solves A·X = P (A = D·S, S symmetric positive definite) by conjugate
/// gradients on S·X = D⁻¹P; `jacobi` preconditions with diag(S).
///
/// A is n × n; P and X are n × 3.
///
/// # Errors
/// [`SolveError::NotSymmetric`], [`SolveError::Indefinite`],
/// [`SolveError::Singular`] (breakdown), [`SolveError::NotConverged`],
/// [`SolveError::Diverged`], [`SolveError::InvalidInput`].
pub fn cg(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions, jacobi: bool) -> Result<Solution, SolveError> {
    let start = Instant::now();
    let name = if jacobi { "cg-jacobi" } else { "cg" };
    a.require_symmetric(name)?;
    validate(a, p, opts)?;
    let n = a.n();
    let mut mon = Monitor::new(name, opts, start);
    if n == 0 {
        return mon.solution(Vec::new(), 0, 0.0);
    }
    let s = a.csr();
    let d = a.d();
    let minv: Vec<f64> = if jacobi {
        let diag = a.s_diagonal();
        if let Some(i) = diag.iter().position(|&v| v <= 0.0) {
            return Err(SolveError::Indefinite {
                solver: name,
                detail: format!("diagonal entry s[{i},{i}] = {} is not positive", diag[i]),
            });
        }
        diag.iter().map(|v| 1.0 / v).collect()
    } else {
        vec![1.0; n]
    };
    let s_norm = (0..n)
        .map(|i| s.data[s.indptr[i] as usize..s.indptr[i + 1] as usize].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0f64, f64::max);
    let b: Vec<Row> = p.iter().zip(d).map(|(pi, di)| [pi[0] / di, pi[1] / di, pi[2] / di]).collect();

    let chunks = kernels::n_chunks(n);
    let mut pmax = vec![0.0; chunks];
    let mut p3 = vec![[0.0; 3]; chunks];
    let mut p33 = vec![([0.0; 3], [0.0; 3]); chunks];
    let mut p3m = vec![([0.0; 3], 0.0); chunks];

    let mut x = initial_guess(p, opts);
    let mut r = vec![[0.0; 3]; n];

    let mut res = true_residual(s, d, &b, &x, &mut r, &mut pmax);
    mon.matvecs += 1;
    let mut k = 0;
    match mon.observe(0, res) {
        Verdict::Continue => {}
        v => return mon.finish(v, x, 0, res),
    }
    // Allocated once X₀ is known not to do (an interpolated fine mesh stops above).
    let mut dir = vec![[0.0; 3]; n];
    let mut q = vec![[0.0; 3]; n];
    let mut rz = restart_direction(&r, &minv, &mut dir, &mut p3);
    let mut replacements = 0;

    loop {
        // Pass 1: q = S p, with pᵀq and pᵀp per column.
        {
            let dir = &dir;
            map_chunks(&mut q, &mut p33, |lo, out| {
                let mut pq = [0.0; 3];
                let mut pp = [0.0; 3];
                for (t, o) in out.iter_mut().enumerate() {
                    let i = lo + t;
                    *o = s.row_times(i, dir);
                    for c in 0..3 {
                        pq[c] += dir[i][c] * o[c];
                        pp[c] += dir[i][c] * dir[i][c];
                    }
                }
                (pq, pp)
            });
        }
        mon.matvecs += 1;
        let pq = fold_sum3(p33.iter().map(|t| t.0));
        let pp = fold_sum3(p33.iter().map(|t| t.1));
        let mut alpha = [0.0; 3];
        for c in 0..3 {
            if rz[c] == 0.0 || pp[c] == 0.0 {
                continue;
            }
            let rayleigh = pq[c] / pp[c];
            if rayleigh < -CG_BREAKDOWN_RTOL * s_norm {
                return Err(SolveError::Indefinite {
                    solver: name,
                    detail: format!(
                        "iteration {k}, column {c}: search direction with pᵀSp/pᵀp = {rayleigh:.4e} < 0 \
                         (A has a negative eigenvalue)"
                    ),
                });
            }
            if rayleigh <= CG_BREAKDOWN_RTOL * s_norm {
                return Err(SolveError::Singular {
                    solver: name,
                    detail: format!(
                        "iteration {k}, column {c}: pᵀSp/pᵀp = {rayleigh:.3e} ≈ 0, the search direction lies \
                         in the null space (residual {:.3e})",
                        res / opts.scale
                    ),
                });
            }
            alpha[c] = rz[c] / pq[c];
        }
        // Pass 2: X += α p, r −= α q, with rᵀM⁻¹r and max_i d_i‖r_i‖.
        {
            let (dir, q, minv) = (&dir, &q, &minv);
            map_chunks2(&mut x, &mut r, &mut p3m, |lo, xs, rs| {
                let mut rz = [0.0; 3];
                let mut m = 0.0f64;
                for t in 0..xs.len() {
                    let i = lo + t;
                    for c in 0..3 {
                        xs[t][c] += alpha[c] * dir[i][c];
                        rs[t][c] -= alpha[c] * q[i][c];
                        rz[c] += rs[t][c] * rs[t][c] * minv[i];
                    }
                    m = max_nan(m, d[i] * d[i] * norm2(rs[t]));
                }
                (rz, m)
            });
        }
        k += 1;
        let rz_new = fold_sum3(p3m.iter().map(|t| t.0));
        res = p3m.iter().fold(0.0, |m, t| max_nan(m, t.1)).sqrt();
        match mon.observe(k, res) {
            Verdict::Continue => {}
            Verdict::Converged => {
                res = true_residual(s, d, &b, &x, &mut r, &mut pmax);
                mon.matvecs += 1;
                if res <= mon.threshold {
                    return mon.solution(x, k, res);
                }
                replacements += 1;
                if replacements > CG_MAX_RESIDUAL_REPLACEMENTS {
                    return Err(mon.not_converged(StopReason::AccuracyLimit, x, k, res));
                }
                rz = restart_direction(&r, &minv, &mut dir, &mut p3);
                continue;
            }
            v => {
                let res = true_residual(s, d, &b, &x, &mut r, &mut pmax);
                mon.matvecs += 1;
                return mon.finish(v, x, k, res);
            }
        }
        // Pass 3: p = M⁻¹r + β p.
        let mut beta = [0.0; 3];
        for c in 0..3 {
            if rz[c] > 0.0 {
                beta[c] = rz_new[c] / rz[c];
            }
        }
        rz = rz_new;
        {
            let (r, minv) = (&r, &minv);
            map_chunks(&mut dir, &mut pmax, |lo, ps| {
                for (t, pv) in ps.iter_mut().enumerate() {
                    let i = lo + t;
                    for c in 0..3 {
                        pv[c] = r[i][c] * minv[i] + beta[c] * pv[c];
                    }
                }
                0.0
            });
        }
    }
}

/// r = b − S x; returns max_i d_i ‖r_i‖ (= the A-residual max norm).
fn true_residual(s: Csr<'_>, d: &[f64], b: &[Row], x: &[Row], r: &mut [Row], partials: &mut [f64]) -> f64 {
    map_chunks(r, partials, |lo, out| {
        let mut m = 0.0f64;
        for (t, o) in out.iter_mut().enumerate() {
            let i = lo + t;
            let v = s.row_times(i, x);
            *o = [b[i][0] - v[0], b[i][1] - v[1], b[i][2] - v[2]];
            m = max_nan(m, d[i] * d[i] * norm2(*o));
        }
        m
    });
    kernels::fold_max(partials).sqrt()
}

/// The rows of a sparse matrix S made on demand instead of stored (a
/// matrix-free S), as [`cg_start`] reads them.
pub trait RowSource: Sync {
    /// Number of rows (= columns).
    fn rows(&self) -> usize;
    /// Calls `f(i, columns, values)` for every row i of `range`, in order,
    /// the columns ascending and distinct (as a CSR row stores them).
    fn for_each_row(&self, range: std::ops::Range<usize>, f: &mut RowVisitor<'_>);
}

/// What [`RowSource::for_each_row`] calls with each row: (row, columns, values).
pub type RowVisitor<'f> = dyn FnMut(usize, &[u32], &[f64]) + 'f;

/// CG's first test without S stored: when the initial guess X₀ already
/// meets the stopping rule, the [`Solution`] [`cg`] returns for
/// `FactoredMatrix::new(d, S)` — the same X₀, residual, history and product
/// count, bit for bit (the residual is computed row by row with CG's own
/// arithmetic), the observer told iterate 0 —, else `None` and nothing is
/// told: CG must iterate (or refuse), and the caller stores S and calls [`cg`].
///
/// For a solve of millions of unknowns whose data are already interpolated
/// to the tolerance (a finely subdivided mesh): one pass over the rows, no
/// n × n storage, no workspace.
///
/// The caller guarantees that S is symmetric (what `FactoredMatrix::new`
/// would find; [`cg`] refuses a nonsymmetric one). `None` too for anything
/// [`cg`] would refuse: mismatched sizes, a non-finite entry, d not
/// positive, a nonpositive diagonal with `jacobi`, invalid options.
pub fn cg_start(s: &dyn RowSource, d: &[f64], p: &[[f64; 3]], opts: &SolveOptions, jacobi: bool) -> Option<Solution> {
    let start = Instant::now();
    let name = if jacobi { "cg-jacobi" } else { "cg" };
    let n = d.len();
    let usable = n > 0
        && s.rows() == n
        && crate::matrix::validate_parts(n, p, opts).is_ok()
        && d.iter().all(|v| v.is_finite() && *v > 0.0);
    if !usable {
        return None;
    }
    let x = initial_guess(p, opts);
    // Per chunk: max_i d_i² ‖b_i − (S x)_i‖², and whether every row was usable.
    let mut partials = vec![(0.0f64, true); kernels::n_chunks(n)];
    kernels::reduce_chunks(n, &mut partials, |rows| {
        let (mut m, mut ok) = (0.0f64, true);
        s.for_each_row(rows, &mut |i, columns, values| {
            let diagonal = columns.binary_search(&(i as u32)).map_or(0.0, |k| values[k]);
            ok &= values.iter().all(|v| v.is_finite()) && (!jacobi || diagonal > 0.0);
            // As `true_residual`, with b = D⁻¹P computed in place.
            let v = kernels::row_dot(columns, values, &x);
            let (pi, di) = (p[i], d[i]);
            let b = [pi[0] / di, pi[1] / di, pi[2] / di];
            let r = [b[0] - v[0], b[1] - v[1], b[2] - v[2]];
            m = max_nan(m, di * di * norm2(r));
        });
        (m, ok)
    });
    if !partials.iter().all(|t| t.1) {
        return None;
    }
    let res = partials.iter().fold(0.0, |m, t| max_nan(m, t.0)).sqrt();
    let mut mon = Monitor::new(name, opts, start);
    if !(res.is_finite() && res <= mon.threshold) {
        return None;
    }
    mon.matvecs += 1;
    match mon.observe(0, res) {
        Verdict::Converged => mon.solution(x, 0, res).ok(),
        _ => None,
    }
}

/// p = M⁻¹ r; returns rᵀM⁻¹r per column.
fn restart_direction(r: &[Row], minv: &[f64], dir: &mut [Row], partials: &mut [Row]) -> Row {
    map_chunks(dir, partials, |lo, out| {
        let mut rz = [0.0; 3];
        for (t, o) in out.iter_mut().enumerate() {
            let i = lo + t;
            for c in 0..3 {
                o[c] = r[i][c] * minv[i];
                rz[c] += r[i][c] * o[c];
            }
        }
        rz
    });
    fold_sum3(partials.iter().copied())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SparseMatrix;
    use sprs::TriMatI;

    /// A stored matrix read row by row, as a matrix-free source would give it.
    struct Stored<'a>(&'a SparseMatrix);

    impl RowSource for Stored<'_> {
        fn rows(&self) -> usize {
            self.0.rows()
        }
        fn for_each_row(&self, range: std::ops::Range<usize>, f: &mut RowVisitor<'_>) {
            for i in range {
                let row = self.0.outer_view(i).unwrap();
                f(i, row.indices(), row.data());
            }
        }
    }

    /// S = tridiagonal (1, 6, 1) on a cycle of n (symmetric positive
    /// definite), D = 1/8: A = D·S is close to the identity, so data close to
    /// A·P meet a loose tolerance at X₀ = P and a tight one does not.
    fn cycle(n: usize) -> (Vec<f64>, SparseMatrix) {
        let mut t = TriMatI::<f64, u32>::new((n, n));
        for i in 0..n {
            t.add_triplet(i, i, 6.0);
            t.add_triplet(i, (i + 1) % n, 1.0);
            t.add_triplet(i, (i + n - 1) % n, 1.0);
        }
        (vec![0.125; n], t.to_csr())
    }

    #[test]
    fn cg_start_is_cg_when_the_initial_guess_does_and_none_otherwise() {
        // Enough rows for the parallel chunks.
        let n = 20_000;
        let (d, s) = cycle(n);
        let p: Vec<[f64; 3]> = (0..n)
            .map(|i| std::f64::consts::TAU * i as f64 / n as f64)
            .map(|t| [t.sin(), (2.0 * t).cos(), 1.0 + 1e-3 * t.sin()])
            .collect();
        let a = FactoredMatrix::new(d.clone(), s.clone()).unwrap();
        for jacobi in [true, false] {
            for (tol, converges) in [(1e-2, true), (1e-12, false)] {
                let opts = SolveOptions::default().with_tol(tol).with_scale(1.0).with_history(true);
                let started = cg_start(&Stored(&s), &d, &p, &opts, jacobi);
                let full = cg(&a, &p, &opts, jacobi).unwrap();
                assert_eq!(full.iterations == 0, converges, "the test's premise (tol {tol})");
                match started {
                    Some(sol) => {
                        assert!(converges);
                        assert_eq!(sol.x, full.x);
                        assert_eq!(sol.residual.to_bits(), full.residual.to_bits());
                        assert_eq!(sol.history, full.history);
                        assert_eq!((sol.iterations, sol.matvecs, sol.solver), (0, full.matvecs, full.solver));
                    }
                    None => assert!(!converges, "tol {tol}: CG stops at X₀ but cg_start did not"),
                }
            }
        }
        // What CG refuses, cg_start leaves to it.
        let opts = SolveOptions::default().with_tol(1e-2).with_scale(1.0);
        assert!(cg_start(&Stored(&s), &d[1..], &p, &opts, true).is_none());
        let mut bad = p.clone();
        bad[3][1] = f64::NAN;
        assert!(cg_start(&Stored(&s), &d, &bad, &opts, true).is_none());
    }
}
