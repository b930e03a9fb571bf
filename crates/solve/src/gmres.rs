//! Restarted GMRES(m) with right Jacobi preconditioning: the Krylov solver
//! for limit matrices whose S is **not** symmetric.
//!
//! # What
//! The Doo-Sabin limit matrices of meshes with interior valence-2 vertices
//! have rows that break the symmetry of S (the digon's V-face), so CG,
//! MINRES, LDLᵀ and Lanczos do not apply; their spectra stay near [¼, 1],
//! which is what GMRES likes. Each iteration adds one Arnoldi vector and
//! picks the iterate that minimises ‖P − A·X‖₂ over the Krylov space
//! x₀ + M⁻¹·K_k(A·M⁻¹, r₀). The three columns x, y, z are three independent
//! Arnoldi processes **interleaved**: one sparse product per iteration serves
//! all three (each column has its own Hessenberg matrix and rotations), so
//! the matrix is streamed once for three columns.
//!
//! # Reference
//! Y. Saad, M. H. Schultz, *GMRES: a generalized minimal residual algorithm
//! for solving nonsymmetric linear systems*, SIAM J. Sci. Stat. Comput.
//! 7(3):856-869, 1986; Y. Saad, *Iterative Methods for Sparse Linear
//! Systems*, 2nd ed., Algorithm 6.10 (GMRES with modified Gram-Schmidt and
//! Givens rotations) and Algorithm 9.5 (right preconditioning); H. A. van
//! der Vorst, Q. Ye, *Residual replacement strategies for Krylov subspace
//! iterative methods*, SIAM J. Sci. Comput. 22(3), 2000.
//!
//! # Algorithm (Saad Alg. 6.10 + 9.5, per column)
//! 1. M = diag(A) (right Jacobi; a row whose |a_ii| ≤ 10⁻⁶·Σ_j |a_ij| is
//!    scaled by its 1-norm instead); r₀ = P − A·X₀,
//!    β = ‖r₀‖₂, v₁ = r₀/β, g = β·e₁.
//! 2. For j = 1 … m: w = A·M⁻¹v_j; modified Gram-Schmidt: for i ≤ j,
//!    h_ij = wᵀv_i, w −= h_ij·v_i; h_{j+1,j} = ‖w‖, v_{j+1} = w/h_{j+1,j}.
//! 3. Apply the previous Givens rotations to column j of H, compute the one
//!    that zeroes h_{j+1,j}, and rotate g: |g_{j+1}| = ‖r_j‖₂.
//! 4. At convergence or after m steps: y = R⁻¹g, X += M⁻¹·V·y; restart from
//!    the true residual.
//!
//! Passes at step j: the product fused with h_1j; j fused
//! "subtract h_ij·v_i, then dot with v_{i+1}" passes (modified Gram-Schmidt
//! with one pass per basis vector; the last one also gives ‖w‖²); one pass
//! that normalises v_{j+1}, writes M⁻¹v_{j+1} for the next product and
//! updates the residual. **Memory**: the basis holds at most m + 1 vectors
//! of n × 3 (all three columns interleaved, 24 bytes per row each),
//! allocated as a cycle grows and reused by the next, so a solve that
//! converges in k < m steps stores k + 1; plus X, the residual and M⁻¹v.
//! With the default m = 30 (`GMRES_RESTART`) that is at most 31·24·n bytes.
//!
//! # Deviations from the textbook
//! - **Stopping on the true max-row A-residual.** Right preconditioning keeps
//!   the Arnoldi residual equal to P − A·X; GMRES's |g_{j+1}| is its 2-norm,
//!   but the project's rule is the max row norm ([the stopping rule]). The residual
//!   *vector* is carried by r_j = s_j²·r_{j−1} − (g_j·c_j/ρ_j)·w (the GMRES
//!   residual is g_{j+1}·V_{j+1}Q_jᵀe_{j+1}, and Q_jᵀe_{j+1} =
//!   −s_j·Q_{j−1}ᵀe_j + c_j·e_{j+1}; w is the unnormalised v_{j+1}) in the
//!   pass that normalises v_{j+1}: no extra product. When its max-row norm
//!   reaches tol·scale, X is formed and the true residual must confirm it;
//!   otherwise GMRES restarts from the true residual (at most
//!   8 times, `KRYLOV_MAX_RESIDUAL_REPLACEMENTS`). The reported `residual` and
//!   the last `history` entry are the true ones.
//! - **Lucky breakdown** (h_{j+1,j} ≤ 10⁻¹²·‖A·M⁻¹v_j‖, `GMRES_BREAKDOWN_RTOL`):
//!   the column's Krylov space is invariant, its least-squares problem is
//!   exact, and the column stops for the cycle.
//! - **Singular A.** If moreover the rotated diagonal ρ_j vanishes
//!   (|ρ_j| ≤ 10⁻¹²·max_i |ρ_i|, `GMRES_SINGULAR_RTOL`), the column is at a least-squares solution of
//!   a singular system; it stops for good, and if its own max-row residual
//!   (a lower bound of the 3-column one) is above tol·scale the solve ends
//!   with [`SolveError::NotConverged`], reason [`StopReason::LeastSquares`].
//!   Larger singular inconsistent systems (no invariant space within a
//!   cycle) stagnate and stop through the shared monitor
//!   ([`StopReason::Stagnated`]); their last iterate is a least-squares
//!   solution plus a null-space component that each restart may enlarge
//!   (the null vector enters through r₀, and the residual does not see it:
//!   3·10⁵ after 200 iterations on the singular 192-row torus of the
//!   tests, residual reported exactly). Never NaN.
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{gmres, FactoredMatrix, SolveOptions};
//! // Nasri's C of an open 40 × 50 quad grid: the boundary rows are the
//! // boundary curve's (1, 6, 1)/8, which no interior row mirrors, so S is
//! // not symmetric.
//! let m = subdiv_stencil::limit_matrix_doo_sabin(shapes::quad_grid(40, 50).topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! assert!(!a.symmetric());
//! let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [(i % 13) as f64, 1.0, (i as f64).cos()]).collect();
//! let sol = gmres(&a, &p, &SolveOptions::default().with_tol(1e-10)).unwrap();
//! assert!(sol.iterations < 30 && a.max_residual(&sol.x, &p) <= 1e-10);
//! ```
//!
//! [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use std::time::Instant;

use crate::error::{SolveError, StopReason};
use crate::kernels::{self, fold_sum3, map_chunks, map_chunks2, map_chunks3, max_nan, norm2, Csr, Row};
use crate::matrix::{validate, FactoredMatrix};
use crate::report::{initial_guess, Monitor, Verdict};
use crate::tolerances::{GMRES_BREAKDOWN_RTOL, GMRES_RESTART, GMRES_SINGULAR_RTOL, KRYLOV_MAX_RESIDUAL_REPLACEMENTS};
use crate::{Solution, SolveOptions};

const NAME: &str = "gmres";

/// Solves A·X = P (A = D·S, S general) by GMRES(30) with
/// right Jacobi preconditioning.
///
/// A is n × n; P and X are n × 3.
///
/// # Errors
/// As [`gmres_restarted`].
pub fn gmres(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    gmres_restarted(a, p, opts, GMRES_RESTART)
}

/// GMRES(`restart`): as [`gmres`] with a chosen restart length m (the basis
/// holds at most m + 1 vectors of n × 3).
///
/// # Errors
/// [`SolveError::InvalidInput`] (also for `restart == 0`);
/// [`SolveError::NotConverged`] at `max_iter`, on stagnation, at the
/// accuracy limit, or at a least-squares solution of a singular system
/// ([`StopReason::LeastSquares`]); [`SolveError::Diverged`] (non-finite values).
pub fn gmres_restarted(
    a: &FactoredMatrix,
    p: &[[f64; 3]],
    opts: &SolveOptions,
    restart: usize,
) -> Result<Solution, SolveError> {
    let start = Instant::now();
    validate(a, p, opts)?;
    if restart == 0 {
        return Err(SolveError::InvalidInput("the GMRES restart length must be ≥ 1".to_owned()));
    }
    let n = a.n();
    let mut mon = Monitor::new(NAME, opts, start);
    if n == 0 {
        return mon.solution(Vec::new(), 0, 0.0);
    }
    let s = a.csr();
    let d = a.d();
    // Right Jacobi: M = diag(A) = D·diag(S), with the fallback of JACOBI_FALLBACK_RTOL.
    let minv: Vec<f64> = a.jacobi_diagonal(true).iter().zip(d).map(|(sii, di)| 1.0 / (di * sii)).collect();

    let chunks = kernels::n_chunks(n);
    let mut p3 = vec![[0.0; 3]; chunks];
    let mut p33 = vec![([0.0; 3], [0.0; 3]); chunks];
    let mut pres = vec![Residual::default(); chunks];
    let mut unit = vec![(); chunks];

    let mut x = initial_guess(p, opts);
    // The residual P − A X: true at the start of a cycle, then recursive.
    let mut r = vec![[0.0; 3]; n];
    // M⁻¹ v_j, the operand of the next product.
    let mut z = vec![[0.0; 3]; n];
    // The Arnoldi basis v_1 … v_{j+1}, grown on demand (at most m + 1).
    let mut basis: Vec<Vec<Row>> = Vec::new();

    let mut rs = true_residual(s, d, p, &x, &mut r, &mut pres);
    mon.matvecs += 1;
    match mon.observe(0, rs.max) {
        Verdict::Continue => {}
        verdict => return mon.finish(verdict, x, 0, rs.max),
    }
    let mut k = 0;
    let mut least_squares = [false; 3];
    let mut replacements = 0;
    loop {
        // One cycle from the residual in r.
        let mut cyc = Cycle::new(restart);
        for c in 0..3 {
            if !least_squares[c] && rs.sum[c] > 0.0 {
                cyc.active[c] = true;
                cyc.g[0][c] = rs.sum[c].sqrt();
            }
        }
        if basis.is_empty() {
            basis.push(vec![[0.0; 3]; n]);
        }
        {
            let inv: [f64; 3] = std::array::from_fn(|c| if cyc.active[c] { 1.0 / cyc.g[0][c] } else { 0.0 });
            let (r, minv) = (&r, &minv);
            map_chunks2(&mut basis[0], &mut z, &mut unit, |lo, vs, zs| {
                for t in 0..vs.len() {
                    let i = lo + t;
                    for c in 0..3 {
                        vs[t][c] = inv[c] * r[i][c];
                        zs[t][c] = minv[i] * vs[t][c];
                    }
                }
            });
        }
        let mut new_least_squares = false;
        let mut verdict = Verdict::Continue;
        let mut j = 0;
        while j < restart {
            if !cyc.active.iter().any(|&on| on) {
                // Every column's Krylov space is invariant: the true residual decides.
                verdict = Verdict::Converged;
                break;
            }
            if basis.len() < j + 2 {
                basis.push(vec![[0.0; 3]; n]);
            }
            let (head, tail) = basis.split_at_mut(j + 1);
            let w = &mut tail[0];
            // w = A z fused with h_1j = wᵀv_1 and ‖w‖² (the breakdown scale).
            {
                let (z, v0) = (&z, &head[0]);
                map_chunks(w, &mut p33, |lo, out| {
                    let (mut h, mut ww) = ([0.0; 3], [0.0; 3]);
                    for (t, o) in out.iter_mut().enumerate() {
                        let i = lo + t;
                        let sz = s.row_times(i, z);
                        for c in 0..3 {
                            o[c] = d[i] * sz[c];
                            h[c] += o[c] * v0[i][c];
                            ww[c] += o[c] * o[c];
                        }
                    }
                    (h, ww)
                });
            }
            mon.matvecs += 1;
            let mut hj = vec![[0.0; 3]; j + 2];
            hj[0] = fold_sum3(p33.iter().map(|t| t.0));
            let w_norm: [f64; 3] = fold_sum3(p33.iter().map(|t| t.1)).map(f64::sqrt);
            // Modified Gram-Schmidt: w −= h_ij v_i, then the dot with v_{i+1} (‖w‖² after the last).
            for i in 0..=j {
                let hi: [f64; 3] = std::array::from_fn(|c| if cyc.active[c] { hj[i][c] } else { 0.0 });
                let vi = &head[i];
                let vnext = if i < j { Some(&head[i + 1]) } else { None };
                map_chunks(w, &mut p3, |lo, out| {
                    let mut acc = [0.0; 3];
                    for (t, o) in out.iter_mut().enumerate() {
                        let q = lo + t;
                        for c in 0..3 {
                            o[c] -= hi[c] * vi[q][c];
                        }
                        let other = match vnext {
                            Some(v) => v[q],
                            None => *o,
                        };
                        for c in 0..3 {
                            acc[c] += o[c] * other[c];
                        }
                    }
                    acc
                });
                hj[i + 1] = fold_sum3(p3.iter().copied());
            }
            // hj[j + 1] is ‖w‖²; the rotations and the pass coefficients per column.
            let mut up = [Update::STOPPED; 3];
            for c in 0..3 {
                if !cyc.active[c] {
                    continue;
                }
                let hnext = hj[j + 1][c].max(0.0).sqrt();
                let mut col: Vec<f64> = (0..=j).map(|i| hj[i][c]).collect();
                for i in 0..j {
                    let (cs, sn) = (cyc.cs[i][c], cyc.sn[i][c]);
                    let (a0, a1) = (col[i], col[i + 1]);
                    col[i] = cs * a0 + sn * a1;
                    col[i + 1] = -sn * a0 + cs * a1;
                }
                cyc.scale[c] = cyc.scale[c].max(w_norm[c]);
                let rho = col[j].hypot(hnext);
                let invariant = hnext <= GMRES_BREAKDOWN_RTOL * w_norm[c];
                if invariant && rho <= GMRES_SINGULAR_RTOL * cyc.scale[c] {
                    // Singular on an invariant space: the current iterate is a least-squares solution.
                    cyc.active[c] = false;
                    least_squares[c] = true;
                    new_least_squares = true;
                    continue;
                }
                let (cs, sn) = (col[j] / rho, hnext / rho);
                col[j] = rho;
                let g = cyc.g[j][c];
                cyc.g[j][c] = cs * g;
                cyc.g[j + 1][c] = -sn * g;
                cyc.cs[j][c] = cs;
                cyc.sn[j][c] = sn;
                for (i, &v) in col.iter().enumerate() {
                    cyc.h[j][i][c] = v;
                }
                cyc.len[c] = j + 1;
                if invariant {
                    cyc.active[c] = false;
                }
                up[c] = Update { sn2: sn * sn, wcoef: -g * cs / rho, vcoef: if invariant { 0.0 } else { 1.0 / hnext } };
            }
            // v_{j+1} = w / h_{j+1,j}, z = M⁻¹ v_{j+1}, r = s² r − (g c/ρ) w; max-row of r.
            map_chunks3(w, &mut z, &mut r, &mut pres, |lo, ws, zs, rs| {
                let mut acc = Residual::default();
                for t in 0..ws.len() {
                    let i = lo + t;
                    for c in 0..3 {
                        let u = &up[c];
                        rs[t][c] = u.sn2 * rs[t][c] + u.wcoef * ws[t][c];
                        ws[t][c] *= u.vcoef;
                        zs[t][c] = minv[i] * ws[t][c];
                        acc.col_max[c] = max_nan(acc.col_max[c], rs[t][c].abs());
                    }
                    acc.max = max_nan(acc.max, norm2(rs[t]));
                }
                acc
            });
            j += 1;
            k += 1;
            let res_max = pres.iter().fold(0.0, |m, t| max_nan(m, t.max)).sqrt();
            verdict = mon.observe(k, res_max);
            if verdict != Verdict::Continue || new_least_squares {
                break;
            }
        }
        // X += M⁻¹ V y with R y = g per column.
        let y = cyc.solve_triangular();
        {
            let (basis, minv) = (&basis, &minv);
            map_chunks(&mut x, &mut unit, |lo, xs| {
                for (t, xi) in xs.iter_mut().enumerate() {
                    let i = lo + t;
                    let mut acc = [0.0; 3];
                    for (yj, vj) in y.iter().zip(basis) {
                        for c in 0..3 {
                            acc[c] += yj[c] * vj[i][c];
                        }
                    }
                    for c in 0..3 {
                        xi[c] += minv[i] * acc[c];
                    }
                }
            });
        }
        rs = true_residual(s, d, p, &x, &mut r, &mut pres);
        mon.matvecs += 1;
        match verdict {
            Verdict::Continue | Verdict::Converged => {
                if rs.max <= mon.threshold {
                    if let Some(last) = mon.history.last_mut() {
                        *last = rs.max / opts.scale;
                    }
                    return mon.solution(x, k, rs.max);
                }
                // A column stopped at a least-squares solution bounds the max-row
                // residual from below by its own; with nothing left to iterate, tol is out of reach.
                if (0..3).any(|c| least_squares[c] && rs.col_max[c] > mon.threshold)
                    || (0..3).all(|c| least_squares[c] || rs.sum[c] == 0.0)
                {
                    return Err(mon.not_converged(StopReason::LeastSquares, x, k, rs.max));
                }
                if verdict == Verdict::Converged && !new_least_squares {
                    replacements += 1;
                    if replacements > KRYLOV_MAX_RESIDUAL_REPLACEMENTS {
                        return Err(mon.not_converged(StopReason::AccuracyLimit, x, k, rs.max));
                    }
                }
            }
            verdict => return mon.finish(verdict, x, k, rs.max),
        }
    }
}

/// The scalars of one GMRES cycle, per column: the rotated Hessenberg
/// columns (R), rotations, the rotated right-hand side g, and how many basis
/// vectors enter each column's least-squares solution.
struct Cycle {
    active: [bool; 3],
    /// h[j][i]: entry (i, j) of R (after rotation), i ≤ j.
    h: Vec<Vec<[f64; 3]>>,
    cs: Vec<[f64; 3]>,
    sn: Vec<[f64; 3]>,
    g: Vec<[f64; 3]>,
    len: [usize; 3],
    /// max_j ‖A·M⁻¹v_j‖: the scale of the singularity test.
    scale: [f64; 3],
}

impl Cycle {
    fn new(m: usize) -> Self {
        Cycle {
            active: [false; 3],
            h: (0..m).map(|j| vec![[0.0; 3]; j + 1]).collect(),
            cs: vec![[0.0; 3]; m],
            sn: vec![[0.0; 3]; m],
            g: vec![[0.0; 3]; m + 1],
            len: [0; 3],
            scale: [0.0; 3],
        }
    }

    /// y = R⁻¹g per column (back substitution over that column's `len`); 0 beyond it.
    fn solve_triangular(&self) -> Vec<[f64; 3]> {
        let m = self.len.iter().copied().max().unwrap_or(0);
        let mut y = vec![[0.0; 3]; m];
        for c in 0..3 {
            for j in (0..self.len[c]).rev() {
                let mut v = self.g[j][c];
                for (q, yq) in y.iter().enumerate().take(self.len[c]).skip(j + 1) {
                    v -= self.h[q][j][c] * yq[c];
                }
                y[j][c] = v / self.h[j][j][c];
            }
        }
        y
    }
}

/// Coefficients of the normalisation pass for one column.
#[derive(Clone, Copy, Debug)]
struct Update {
    /// r ← sn2·r + wcoef·w.
    sn2: f64,
    wcoef: f64,
    /// v_{j+1} = vcoef·w (0 once the column stops).
    vcoef: f64,
}

impl Update {
    /// A stopped column: residual unchanged, v = 0.
    const STOPPED: Update = Update { sn2: 1.0, wcoef: 0.0, vcoef: 0.0 };
}

/// A residual evaluation of P − A X; `sum` is ‖r_c‖₂² per column.
type Residual = kernels::ResidualStats;

/// r = P − A x, with its max row norm, per-column max and squared norms.
fn true_residual(s: Csr<'_>, d: &[f64], p: &[Row], x: &[Row], r: &mut [Row], partials: &mut [Residual]) -> Residual {
    map_chunks(r, partials, |lo, out| {
        let mut acc = Residual::default();
        for (t, o) in out.iter_mut().enumerate() {
            let i = lo + t;
            let v = s.row_times(i, x);
            *o = [p[i][0] - d[i] * v[0], p[i][1] - d[i] * v[1], p[i][2] - d[i] * v[2]];
            for c in 0..3 {
                acc.col_max[c] = max_nan(acc.col_max[c], o[c].abs());
                acc.sum[c] += o[c] * o[c];
            }
            acc.max = max_nan(acc.max, norm2(*o));
        }
        acc
    });
    Residual::merge(partials)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::internals::model_problems;

    /// The recursive residual tracks the true one (checks the sign and the
    /// coefficients of the recurrence in the module docs), across restarts.
    #[test]
    fn recursive_residual_matches_the_true_one() {
        let a = model_problems::random_nonsymmetric(300, 6, 3);
        let p: Vec<Row> = (0..300).map(|i| [(i % 7) as f64, (i % 3) as f64 - 1.0, (i as f64).sin()]).collect();
        for max_iter in 1..12 {
            let opts = SolveOptions { tol: 1e-14, max_iter, ..Default::default() };
            match gmres_restarted(&a, &p, &opts, 4) {
                Err(SolveError::NotConverged { iterations, history, x, residual, .. }) => {
                    assert_eq!(iterations, max_iter);
                    let truth = a.max_residual(&x.0, &p);
                    assert!(
                        (history[max_iter] - truth).abs() <= 1e-12 * (1.0 + truth),
                        "{max_iter}: {history:?} vs {truth}"
                    );
                    assert!((residual - truth).abs() <= 1e-15 * (1.0 + truth));
                }
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn restart_zero_is_invalid() {
        let a = model_problems::random_nonsymmetric(10, 2, 1);
        let p = vec![[1.0; 3]; 10];
        assert!(matches!(gmres_restarted(&a, &p, &SolveOptions::default(), 0), Err(SolveError::InvalidInput(_))));
    }
}
