//! MINRES on the symmetric form S·X = D⁻¹·P, preconditioned by |diag S|: the
//! Krylov solver for symmetric **indefinite** limit matrices.
//!
//! # What
//! Cheng's Catmull-Clark matrix A = D·S is indefinite as soon as the mesh
//! has an interior vertex of valence 2 (Cheng et al., appendix proof,
//! corrected in [correction C3]: the quadratic form's term n(n − 3)/4·x² is
//! negative for n = 2). CG then meets pᵀSp < 0 and PIA diverges; MINRES only
//! needs S symmetric. Each iteration extends the Krylov space by one product
//! and picks the iterate that **minimises the residual norm** over it, so the
//! residual never grows, whatever the signs of the eigenvalues. The three
//! columns x, y, z are three independent Lanczos processes sharing one
//! sparse product per iteration (each has its own scalars).
//!
//! # Reference
//! C. C. Paige, M. A. Saunders, *Solution of sparse indefinite systems of
//! linear equations*, SIAM J. Numer. Anal. 12(4):617-629, 1975 (MINRES, §6-7);
//! S.-C. T. Choi, C. C. Paige, M. A. Saunders, *MINRES-QLP*, SIAM J. Sci.
//! Comput. 33(4), 2011, Table 2.1 (preconditioned MINRES, the ‖A·r‖
//! estimate φ̄·‖(γ̄, δ̄)‖); the recurrences are those of SciPy's
//! `scipy.sparse.linalg.minres` (a port of Saunders' `minres.m`); H. A. van
//! der Vorst, Q. Ye, *Residual replacement strategies for Krylov subspace
//! iterative methods*, SIAM J. Sci. Comput. 22(3), 2000.
//!
//! # Which symmetric system, which preconditioner
//! A·X = P ⇔ S·X = b with b = D⁻¹P. MINRES runs on S with the diagonal
//! preconditioner M = |diag S| (Jacobi scaling by absolute values: MINRES
//! needs a positive definite preconditioner, which plain Jacobi on an
//! indefinite diagonal is not; rows without a usable diagonal fall back to
//! their 1-norm: |s_ii| ≤ 10⁻⁶·Σ_j |s_ij|).
//! Preconditioned MINRES on (S, M) is plain MINRES on H = M^{-1/2}·S·M^{-1/2};
//! its iterates lie in X₀ + K_k(J·A, J·R₀) with J = |diag A|⁻¹ and minimise
//! ‖b − S·X‖_{M⁻¹} = ‖W·(P − A·X)‖₂, W = diag(1/(d_i·√|s_ii|)): the true
//! A-residual with row weights that vary only with the valence.
//! The alternative M = D⁻¹ (MINRES on D^{1/2}·S·D^{1/2}, which is similar
//! to A and needs no fallback) was measured on the 524,288-row valence-2
//! tori of `benches/indefinite.rs` (data jittered by 0.2 edge lengths, tol
//! 1e-6): 13 and 19 iterations (4 single valence-2 vertices; 2 single and 2
//! adjacent pairs) against 9 and 17 with |diag S|, which also matches CG's
//! default Jacobi preconditioner (10 iterations on the clean torus).
//!
//! # Algorithm (per column; SciPy's `minres` with the preconditioner diagonal)
//! 1. r₀ = b − S·X₀, β₁ = ‖r₀‖_{M⁻¹}, v₁ = M⁻¹r₀/β₁; φ̄ = β₁, c = −1, s = 0.
//! 2. Lanczos: y = S·v_k − (β_k/β_{k−1})·r_{k−1}; α_k = v_kᵀy;
//!    y −= (α_k/β_k)·r_k; β_{k+1} = ‖y‖_{M⁻¹}; r_{k+1} = y.
//! 3. Previous rotation: δ_k = c·δ̄ + s·α, γ̄ = s·δ̄ − c·α, ε_{k+1} = s·β_{k+1},
//!    δ̄ = −c·β_{k+1}; new rotation: γ = ‖(γ̄, β_{k+1})‖, c = γ̄/γ, s = β_{k+1}/γ;
//!    φ = c·φ̄, φ̄ ← s·φ̄ (= ‖r_k‖_{M⁻¹}, monotone non-increasing).
//! 4. w_k = (v_k − ε_k·w_{k−2} − δ_k·w_{k−1})/γ; X += φ·w_k.
//!
//! Three passes per iteration, as CG: (1) y = S·v − (β/β_old)·r_{k−1}
//! fused with α = vᵀy; (2) y −= (α/β)·r_k fused with yᵀM⁻¹y; (3) the w, X,
//! residual and next-v updates fused with the stopping test. The
//! Lanczos vectors live in two buffers that swap roles (y overwrites
//! r_{k−1} in place), the w's in a pair indexed by the parity of k.
//!
//! # Deviations from the textbook
//! - **Stopping on the true max-row A-residual.** MINRES's estimate φ̄ is a
//!   2-norm; the project's rule is max_i ‖P_i − (A·X)_i‖ ≤ tol·scale
//!   ([the stopping rule]), which no scalar recurrence gives. The residual *vector* is
//!   carried instead, by the recurrence r_k = s_k²·r_{k−1} − (φ̄_{k−1}·c_k/γ_k)·y
//!   (the MINRES residual is φ̄_k·V_{k+1}Q_kᵀe_{k+1}, and Q_kᵀe_{k+1} =
//!   s_k·Q_{k−1}ᵀe_k − c_k·e_{k+1}): one fused stream in pass 3, no product.
//!   When its max-row norm reaches tol·scale the true residual is computed
//!   (one product) and must confirm it; otherwise the Lanczos process
//!   restarts from the true residual (residual replacement, van der
//!   Vorst-Ye), at most 8 times (`KRYLOV_MAX_RESIDUAL_REPLACEMENTS`). The
//!   reported `residual` and the last `history` entry are the true ones;
//!   the other `history` entries are the recursive ones.
//! - **Invariant Krylov spaces** (β_{k+1} ≤ 10⁻¹²·‖T_k‖ (`MINRES_BREAKDOWN_RTOL`),
//!   e.g. n ≤ 3, or a right-hand side column that is an eigenvector): that
//!   column is solved in its space and stops; when every column has stopped
//!   the true residual decides (converged, or a restart).
//! - **Singular systems.** On consistent data the residual stays in the range
//!   of S and MINRES converges (the checkerboard cube with data A·X). On
//!   inconsistent data it reaches a least-squares solution: the estimate
//!   ‖S·r‖/(‖T‖·‖r‖) = ‖(γ̄, δ̄)‖/‖T_k‖_F falls below 10⁻⁸ (`MINRES_LSQ_RTOL`)
//!   *before* the next update would divide by γ ≈ 0. That column stops for
//!   good; if its own max-row residual (a lower bound of the 3-column one)
//!   is above tol·scale the solve ends with [`SolveError::NotConverged`],
//!   reason [`StopReason::LeastSquares`], carrying the least-squares
//!   iterate. Never NaN.
//! - `max_iter`, stagnation and divergence are the shared monitor's
//!   ([`SolveError::NotConverged`] with the true residual and the last
//!   iterate).
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_solve::{minres, FactoredMatrix, Solver, SolveError, SolveOptions};
//! // Cheng's A of the pillow (two quads, valence 2): spectrum {1, 1/7, 1/7, −1/7}.
//! let m = subdiv_stencil::limit_matrix_catmull_clark(shapes::pillow().topology());
//! let a = FactoredMatrix::new(m.d, m.s).unwrap();
//! let p = vec![[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0], [1.0, 1.0, 1.0]];
//! let opts = SolveOptions::default().with_tol(1e-10);
//! assert!(matches!(Solver::Cg { jacobi: true }.solve(&a, &p, &opts), Err(SolveError::Indefinite { .. })));
//! let sol = minres(&a, &p, &opts).unwrap();
//! assert!(sol.iterations <= 4 && a.max_residual(&sol.x, &p) <= 1e-10);
//! ```
//!
//! [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
//! [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use std::time::Instant;

use crate::error::{SolveError, StopReason};
use crate::kernels::{self, fold_sum3, map_chunks, map_chunks2, map_chunks3, max_nan, norm2, Csr, Row};
use crate::matrix::{validate, FactoredMatrix};
use crate::report::{initial_guess, Monitor, Verdict};
use crate::tolerances::{KRYLOV_MAX_RESIDUAL_REPLACEMENTS, MINRES_BREAKDOWN_RTOL, MINRES_LSQ_RTOL};
use crate::{Solution, SolveOptions};

const NAME: &str = "minres";

/// Solves A·X = P (A = D·S, S symmetric, possibly indefinite or singular) by
/// MINRES on S·X = D⁻¹P preconditioned by |diag S|.
///
/// A is n × n; P and X are n × 3.
///
/// # Errors
/// [`SolveError::NotSymmetric`]; [`SolveError::NotConverged`] at `max_iter`,
/// on stagnation, at the accuracy limit, or at a least-squares solution of a
/// singular inconsistent system ([`StopReason::LeastSquares`]);
/// [`SolveError::Diverged`] (non-finite values); [`SolveError::InvalidInput`].
pub fn minres(a: &FactoredMatrix, p: &[[f64; 3]], opts: &SolveOptions) -> Result<Solution, SolveError> {
    let start = Instant::now();
    a.require_symmetric(NAME)?;
    validate(a, p, opts)?;
    let n = a.n();
    let mut mon = Monitor::new(NAME, opts, start);
    if n == 0 {
        return mon.solution(Vec::new(), 0, 0.0);
    }
    let s = a.csr();
    let d = a.d();
    // M = |diag S| (module docs), with the fallback of JACOBI_FALLBACK_RTOL.
    let minv: Vec<f64> = a.jacobi_diagonal(false).iter().map(|m| 1.0 / m).collect();
    let minv = &minv[..];
    let b: Vec<Row> = p.iter().zip(d).map(|(pi, di)| [pi[0] / di, pi[1] / di, pi[2] / di]).collect();

    let chunks = kernels::n_chunks(n);
    let mut p3 = vec![[0.0; 3]; chunks];
    let mut pres = vec![Residual::default(); chunks];
    let mut pmax = vec![(0.0, [0.0; 3]); chunks];
    let mut unit = vec![(); chunks];

    let mut x = initial_guess(p, opts);
    // Lanczos vectors r_{k−1}, r_k (unnormalised, in the space of b); y overwrites r_{k−1}.
    let mut r1 = vec![[0.0; 3]; n];
    let mut r2 = vec![[0.0; 3]; n];
    // v_k = M⁻¹ r_k / β_k, the operand of the product.
    let mut v = vec![[0.0; 3]; n];
    // Per row: [recursive residual b − S X, w of even k, w of odd k].
    let mut aux = vec![[[0.0; 3]; 3]; n];

    let mut rs = true_residual(s, d, minv, &b, &x, &mut r2, &mut pres);
    mon.matvecs += 1;
    match mon.observe(0, rs.max) {
        Verdict::Continue => {}
        verdict => return mon.finish(verdict, x, 0, rs.max),
    }
    let mut k = 0;
    // Columns at a least-squares solution stay stopped across restarts.
    let mut least_squares = [false; 3];
    let mut replacements = 0;

    'restart: loop {
        // Start (or restart) every column from the true residual now in r2.
        let mut cols = [Column::stopped(); 3];
        let mut inv_beta = [0.0; 3];
        for c in 0..3 {
            if !least_squares[c] && rs.sum[c] > 0.0 {
                cols[c] = Column::start(rs.sum[c].sqrt());
                inv_beta[c] = 1.0 / cols[c].beta;
            }
        }
        {
            let r0 = &r2;
            map_chunks2(&mut v, &mut aux, &mut unit, |lo, vs, auxs| {
                for t in 0..vs.len() {
                    let i = lo + t;
                    for c in 0..3 {
                        vs[t][c] = inv_beta[c] * minv[i] * r0[i][c];
                    }
                    auxs[t] = [r0[i], [0.0; 3], [0.0; 3]];
                }
            });
        }
        let mut it = 0usize;
        loop {
            let mut new_least_squares = false;
            let verdict = if cols.iter().all(|c| !c.active) {
                // Every Krylov space is invariant: the true residual decides.
                Verdict::Converged
            } else {
                it += 1;
                // Pass 1: y = S v − (β_k/β_{k−1}) r_{k−1}, in place of r_{k−1}; α = vᵀy.
                let c1: [f64; 3] = std::array::from_fn(|c| {
                    if cols[c].active && cols[c].oldb > 0.0 {
                        cols[c].beta / cols[c].oldb
                    } else {
                        0.0
                    }
                });
                {
                    let v = &v;
                    map_chunks(&mut r1, &mut p3, |lo, out| {
                        let mut acc = [0.0; 3];
                        for (t, o) in out.iter_mut().enumerate() {
                            let i = lo + t;
                            let sv = s.row_times(i, v);
                            for c in 0..3 {
                                o[c] = sv[c] - c1[c] * o[c];
                                acc[c] += v[i][c] * o[c];
                            }
                        }
                        acc
                    });
                }
                mon.matvecs += 1;
                let alpha = fold_sum3(p3.iter().copied());
                // Pass 2: y −= (α/β_k) r_k, with yᵀM⁻¹y.
                let c2: [f64; 3] = std::array::from_fn(|c| if cols[c].active { alpha[c] / cols[c].beta } else { 0.0 });
                {
                    let r2 = &r2;
                    map_chunks(&mut r1, &mut p3, |lo, out| {
                        let mut acc = [0.0; 3];
                        for (t, o) in out.iter_mut().enumerate() {
                            let i = lo + t;
                            for c in 0..3 {
                                o[c] -= c2[c] * r2[i][c];
                                acc[c] += o[c] * o[c] * minv[i];
                            }
                        }
                        acc
                    });
                }
                let ymy = fold_sum3(p3.iter().copied());
                // r_{k+1} = y; r_k moves to the other buffer.
                std::mem::swap(&mut r1, &mut r2);
                let mut up = [Update::STOPPED; 3];
                for c in 0..3 {
                    if cols[c].active {
                        match cols[c].step(alpha[c], ymy[c]) {
                            Step::Update(u) => up[c] = u,
                            Step::LeastSquares => {
                                least_squares[c] = true;
                                new_least_squares = true;
                            }
                        }
                    }
                }
                // Pass 3: w_k, X += φ w_k, the recursive residual, v_{k+1}; max-row residual.
                let slot = 1 + it % 2;
                {
                    let y = &r2;
                    map_chunks3(&mut x, &mut v, &mut aux, &mut pmax, |lo, xs, vs, auxs| {
                        let mut m = 0.0f64;
                        let mut col_max = [0.0f64; 3];
                        for t in 0..xs.len() {
                            let i = lo + t;
                            let [res, w_even, w_odd] = &mut auxs[t];
                            let (w_old2, w_old1) = if slot == 1 { (w_even, &*w_odd) } else { (w_odd, &*w_even) };
                            for c in 0..3 {
                                let u = &up[c];
                                let w = (vs[t][c] - u.oldeps * w_old2[c] - u.delta * w_old1[c]) * u.inv_gamma;
                                w_old2[c] = w;
                                xs[t][c] += u.phi * w;
                                res[c] = u.sn2 * res[c] - u.rcoef * y[i][c];
                                vs[t][c] = u.vcoef * minv[i] * y[i][c];
                                col_max[c] = max_nan(col_max[c], d[i] * res[c].abs());
                            }
                            m = max_nan(m, d[i] * d[i] * norm2(*res));
                        }
                        (m, col_max)
                    });
                }
                k += 1;
                let res_max = pmax.iter().fold(0.0, |m, t| max_nan(m, t.0)).sqrt();
                mon.observe(k, res_max)
            };
            match verdict {
                Verdict::Continue if !new_least_squares => continue,
                Verdict::Continue | Verdict::Converged => {
                    rs = true_residual(s, d, minv, &b, &x, &mut r2, &mut pres);
                    mon.matvecs += 1;
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
                    if !new_least_squares {
                        replacements += 1;
                        if replacements > KRYLOV_MAX_RESIDUAL_REPLACEMENTS {
                            return Err(mon.not_converged(StopReason::AccuracyLimit, x, k, rs.max));
                        }
                    }
                    continue 'restart;
                }
                verdict => {
                    let rs = true_residual(s, d, minv, &b, &x, &mut r2, &mut pres);
                    mon.matvecs += 1;
                    return mon.finish(verdict, x, k, rs.max);
                }
            }
        }
    }
}

/// One column's Lanczos scalars and the running QR factorisation of its
/// tridiagonal T_k (Paige-Saunders; names as in SciPy's `minres`).
#[derive(Clone, Copy, Debug)]
struct Column {
    /// Still iterating (else: zero residual, invariant Krylov space, or a
    /// least-squares solution).
    active: bool,
    /// β_k = ‖r_k‖_{M⁻¹} of the current (unnormalised) Lanczos vector.
    beta: f64,
    /// β_{k−1} (0 before the second step).
    oldb: f64,
    /// δ̄: the rotated super-diagonal carried to the next step.
    dbar: f64,
    /// ε: the second super-diagonal of R carried to the next step.
    epsln: f64,
    /// φ̄ = ‖r_k‖_{M⁻¹} of the current iterate.
    phibar: f64,
    /// ‖T_k‖_F², the estimate of ‖H‖² used by the relative tests.
    tnorm2: f64,
    /// The last rotation (c, s).
    cs: f64,
    sn: f64,
}

/// What one step of a column's recurrences asks pass 3 to do.
enum Step {
    /// Apply these coefficients.
    Update(Update),
    /// The current iterate is a least-squares solution: stop the column
    /// before dividing by γ ≈ 0.
    LeastSquares,
}

/// Coefficients of pass 3 for one column.
#[derive(Clone, Copy, Debug)]
struct Update {
    /// w_k = (v_k − oldeps·w_{k−2} − delta·w_{k−1})·inv_gamma.
    oldeps: f64,
    delta: f64,
    inv_gamma: f64,
    /// X += phi·w_k.
    phi: f64,
    /// residual ← sn2·residual − rcoef·r_{k+1}.
    sn2: f64,
    rcoef: f64,
    /// v_{k+1} = vcoef·M⁻¹·r_{k+1} (0 once the column stops).
    vcoef: f64,
}

impl Update {
    /// A stopped column: X and its residual unchanged, v = 0 (so the product
    /// and the inner products of the column are 0).
    const STOPPED: Update =
        Update { oldeps: 0.0, delta: 0.0, inv_gamma: 0.0, phi: 0.0, sn2: 1.0, rcoef: 0.0, vcoef: 0.0 };
}

impl Column {
    fn stopped() -> Self {
        Column {
            active: false,
            beta: 0.0,
            oldb: 0.0,
            dbar: 0.0,
            epsln: 0.0,
            phibar: 0.0,
            tnorm2: 0.0,
            cs: -1.0,
            sn: 0.0,
        }
    }

    fn start(beta1: f64) -> Self {
        Column { active: true, beta: beta1, phibar: beta1, ..Column::stopped() }
    }

    /// Steps 2-4 of the module docs for one column, given α_k and
    /// ‖y‖²_{M⁻¹} = β_{k+1}².
    fn step(&mut self, alpha: f64, beta_next_sq: f64) -> Step {
        self.oldb = self.beta;
        self.beta = beta_next_sq.max(0.0).sqrt();
        self.tnorm2 += alpha * alpha + self.oldb * self.oldb + self.beta * self.beta;
        // Previous rotation applied to the new column of T.
        let oldeps = self.epsln;
        let delta = self.cs * self.dbar + self.sn * alpha;
        let gbar = self.sn * self.dbar - self.cs * alpha;
        self.epsln = self.sn * self.beta;
        self.dbar = -self.cs * self.beta;
        let t_norm = self.tnorm2.sqrt();
        // ‖S r_{k−1}‖ / ‖r_{k−1}‖ = ‖(γ̄, δ̄)‖ (Choi-Paige-Saunders Table 2.1).
        if gbar.hypot(self.dbar) <= MINRES_LSQ_RTOL * t_norm {
            self.active = false;
            return Step::LeastSquares;
        }
        // New rotation.
        let gamma = gbar.hypot(self.beta);
        let (cs, sn) = (gbar / gamma, self.beta / gamma);
        let phi = cs * self.phibar;
        let rcoef = self.phibar * cs / gamma;
        self.phibar *= sn;
        self.cs = cs;
        self.sn = sn;
        let invariant = self.beta <= MINRES_BREAKDOWN_RTOL * t_norm;
        if invariant {
            self.active = false;
        }
        Step::Update(Update {
            oldeps,
            delta,
            inv_gamma: 1.0 / gamma,
            phi,
            sn2: sn * sn,
            rcoef,
            vcoef: if invariant { 0.0 } else { 1.0 / self.beta },
        })
    }
}

/// A residual evaluation: max row norm of the A-residual
/// (max_i d_i ‖r_i‖₂ = max_i ‖P_i − (A X)_i‖₂), the same per column, and
/// `sum` = Σ_i r_ic² · M⁻¹_i = rᵀM⁻¹r per column (β₁²).
type Residual = kernels::ResidualStats;

/// r = b − S x; the A-residual's max row norm (P − A X = D r), per column,
/// and rᵀM⁻¹r.
fn true_residual(
    s: Csr<'_>,
    d: &[f64],
    minv: &[f64],
    b: &[Row],
    x: &[Row],
    r: &mut [Row],
    partials: &mut [Residual],
) -> Residual {
    map_chunks(r, partials, |lo, out| {
        let mut acc = Residual::default();
        for (t, o) in out.iter_mut().enumerate() {
            let i = lo + t;
            let v = s.row_times(i, x);
            *o = [b[i][0] - v[0], b[i][1] - v[1], b[i][2] - v[2]];
            for c in 0..3 {
                acc.col_max[c] = max_nan(acc.col_max[c], d[i] * o[c].abs());
                acc.sum[c] += o[c] * o[c] * minv[i];
            }
            acc.max = max_nan(acc.max, d[i] * d[i] * norm2(*o));
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
    /// coefficients of the recurrence in the module docs).
    #[test]
    fn recursive_residual_matches_the_true_one() {
        let a = model_problems::random_spd(300, 6, 3);
        let p: Vec<Row> = (0..300).map(|i| [(i % 7) as f64, (i % 3) as f64 - 1.0, (i as f64).sin()]).collect();
        for max_iter in 1..12 {
            let opts = SolveOptions { tol: 1e-14, max_iter, ..Default::default() };
            match minres(&a, &p, &opts) {
                Err(SolveError::NotConverged { iterations, history, x, residual, .. }) => {
                    assert_eq!(iterations, max_iter);
                    let truth = a.max_residual(&x.0, &p);
                    // history[k] is the recursive estimate of iterate k.
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
}
