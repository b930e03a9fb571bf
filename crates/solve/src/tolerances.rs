//! Every tolerance, threshold and tuning constant of the crate, in one place
//! (pmp-library's `tolerances.h`).
//!
//! Solvers read these; none hard-codes a number of its own. Each constant
//! says what it guards and why it has its value.

/// Default relative stopping tolerance: max over rows of |P − AX| / scale.
/// [The stopping rule] (the papers stop on the same max-norm quantity).
///
/// [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
pub const DEFAULT_TOL: f64 = 1e-6;

/// Default iteration cap of the iterative solvers.
pub const DEFAULT_MAX_ITER: usize = 10_000;

/// Relative tolerance of [`FactoredMatrix`](crate::FactoredMatrix)'s symmetry check:
/// |s_ij − s_ji| ≤ `SYMMETRY_RTOL` · max |s_kl|. Limit matrices assembled
/// from one set of face contributions agree to a few ulps; 1e-10 leaves room
/// for different summation orders and nothing for a wrong coefficient.
pub const SYMMETRY_RTOL: f64 = 1e-10;

/// An iteration whose residual exceeds `DIVERGENCE_FACTOR` × the initial
/// residual has diverged (plain PIA on an indefinite matrix grows like
/// |1 − λ_min|^k; waiting longer only burns time).
pub const DIVERGENCE_FACTOR: f64 = 1e6;

/// Stagnation window: an iterative solver whose best residual has not
/// improved by the factor [`STAGNATION_FACTOR`] within this many iterations
/// stops with `NotConverged { reason: Stagnated }`. Catches singular,
/// inconsistent systems (the Catmull-Clark checkerboard) long before
/// `max_iter`.
pub const STAGNATION_WINDOW: usize = 200;

/// Required improvement of the best residual per [`STAGNATION_WINDOW`]
/// iterations (0.1 %). A convergent stationary iteration with contraction
/// ρ improves by ρ^200 per window, so only ρ > 0.999995 (λ_min ≲ 5e-6 for
/// PIA) is cut short — and such a run would hit `max_iter` anyway.
pub const STAGNATION_FACTOR: f64 = 0.999;

/// Rows per chunk of every parallel loop and every reduction. Fixed, so sums
/// are formed in the same order whatever the thread count (bitwise
/// determinism); large enough (≈ 100-400 KiB of matrix per chunk) that the
/// rayon task overhead is negligible.
pub const CHUNK_ROWS: usize = 4096;

/// Below this many rows every loop runs on the calling thread (same chunks,
/// same bits): thread hand-off costs more than it saves on small systems.
pub const PARALLEL_MIN_ROWS: usize = 50_000;

/// Lanczos steps spent by the solvers that need an interval (weighted PIA,
/// Chebyshev). Measured on the 10⁶-row bicubic torus and Loop grid: 10, 15,
/// 20, 30 and 50 steps all give the same Chebyshev and weighted-PIA
/// iteration counts (20 and 50; 13 and 23) as the exact intervals, although
/// 10 steps leave θ_min 10 % above λ_min — the methods are insensitive to
/// an interval that is slightly too short at the lower end (`chebyshev.rs`).
/// 16 steps keep a margin; each costs about one product.
pub const LANCZOS_STEPS: usize = 16;

/// Full reorthogonalisation of the Lanczos basis is used while
/// n · steps ≤ this many stored numbers (8 bytes each: 64 MiB); beyond it
/// the plain three-term recurrence runs in O(n) memory. Loss of
/// orthogonality only duplicates converged Ritz values ("ghosts"), it does
/// not move the extreme ones.
pub const LANCZOS_REORTH_MAX_STORE: usize = 8_000_000;

/// Lanczos stops early when β_j ≤ `LANCZOS_BREAKDOWN_RTOL` · |T|: the
/// Krylov space is invariant and its Ritz values are exact eigenvalues.
pub const LANCZOS_BREAKDOWN_RTOL: f64 = 1e-12;

/// Relative safety margin applied to the extreme Ritz values to form the
/// bracket of [`Spectrum`](crate::Spectrum): λ_min ≥ θ_min − m·|θ_min|,
/// λ_max ≤ θ_max + m·|θ_max| (m = 2 %). Chebyshev and weighted PIA stay
/// convergent for moderate errors in either direction (see `chebyshev.rs`);
/// the margin keeps the interval on the safe side of the usual Ritz error.
pub const SPECTRUM_MARGIN: f64 = 0.02;

/// A spectrum whose lower estimate is ≤ `SINGULAR_SPECTRUM_RTOL` · λ_max is
/// treated as singular by the solvers that need λ_min > 0.
pub const SINGULAR_SPECTRUM_RTOL: f64 = 1e-10;

/// CG breakdown: |pᵀSp| ≤ `CG_BREAKDOWN_RTOL` · |p|² · ‖S‖_∞ means the
/// search direction lies in the numerical null space of S (singular system).
/// A clearly negative pᵀSp is indefiniteness instead.
pub const CG_BREAKDOWN_RTOL: f64 = 1e-13;

/// CG replaces its recursive residual by the true one at most this many
/// times (when the recursive residual claims convergence that the true
/// A-residual does not confirm) before it reports `NotConverged`.
pub const CG_MAX_RESIDUAL_REPLACEMENTS: usize = 8;

/// MINRES and GMRES replace their recursive residual by the true one at
/// most this many times (when the recursion claims convergence that the true
/// A-residual does not confirm, or every column's Krylov space became
/// invariant) before they report `NotConverged` with
/// [`StopReason::AccuracyLimit`](crate::StopReason::AccuracyLimit). Each
/// replacement restarts the Krylov process from the true residual.
pub const KRYLOV_MAX_RESIDUAL_REPLACEMENTS: usize = 8;

/// MINRES: a Lanczos coefficient β_{k+1} ≤ `MINRES_BREAKDOWN_RTOL` · ‖T_k‖_F
/// means the Krylov space of that column is invariant: the column is solved
/// in it (or is at a least-squares solution) and stops iterating. As
/// [`LANCZOS_BREAKDOWN_RTOL`].
pub const MINRES_BREAKDOWN_RTOL: f64 = 1e-12;

/// MINRES least-squares test (Paige & Saunders 1975; SciPy's `istop = 2`):
/// ‖H·r‖ ≤ `MINRES_LSQ_RTOL` · ‖T_k‖_F · ‖r‖ (H the preconditioned matrix,
/// both norms from the recurrences) means the residual is orthogonal to the
/// range of H: the iterate is a least-squares solution of a singular,
/// inconsistent system and cannot improve. For a nonsingular H,
/// ‖H·r‖ ≥ σ_min‖r‖ and ‖T_k‖_F ≤ √(3k)·‖H‖, so the test cannot fire while
/// κ(H)·√(3k) < 10⁸ (limit matrices have κ ≲ 10³). It must not be much
/// tighter: in floating point the ratio levels off near ε·κ·√k (5e-10 on a
/// singular 192-row torus with κ⁺ ≈ 120, reached after 48 iterations), and
/// once the least-squares floor is reached the Lanczos vectors lose
/// orthogonality and the iterates grow without bound (10¹³ after 70
/// iterations on that torus); 1e-8 stops it at iteration 44.
pub const MINRES_LSQ_RTOL: f64 = 1e-8;

/// GMRES restart length m: the Arnoldi basis holds at most m + 1 vectors of
/// n × 3. The Doo-Sabin limit matrices (spectrum near [¼, 1]) converge to
/// 1e-6 in about 10-15 products, well within one cycle; the basis is
/// allocated as the cycle grows, so an early convergence stores only what it used.
pub const GMRES_RESTART: usize = 30;

/// GMRES "lucky breakdown": h_{j+1,j} ≤ `GMRES_BREAKDOWN_RTOL` · ‖A·z_j‖
/// (the new Arnoldi vector before orthogonalisation) means the Krylov space
/// of that column is invariant, and the column stops for the cycle.
pub const GMRES_BREAKDOWN_RTOL: f64 = 1e-12;

/// GMRES: a diagonal entry of the triangular factor of the Hessenberg matrix
/// with |r_jj| ≤ `GMRES_SINGULAR_RTOL` · max_i |r_ii| on an invariant
/// Krylov space means A is singular there: the column is at a least-squares
/// solution and cannot improve.
pub const GMRES_SINGULAR_RTOL: f64 = 1e-12;

/// The Jacobi scalings of MINRES (|s_ii|) and GMRES (a_ii) use the diagonal
/// entry unless |s_ii| ≤ `JACOBI_FALLBACK_RTOL` · Σ_j |s_ij|; such a row (no
/// usable diagonal, e.g. a structurally missing one) is scaled by its 1-norm
/// instead (1 for an empty row). Any positive diagonal is a valid MINRES
/// preconditioner and any nonsingular one a valid right preconditioner for
/// GMRES; this only keeps the scaling bounded. Limit matrices never need
/// it (their diagonals are the largest entries of their rows).
pub const JACOBI_FALLBACK_RTOL: f64 = 1e-6;

/// LDLᵀ pivot test: |d_k| ≤ `LDL_PIVOT_RTOL` · max_i |s_ii| is a zero pivot
/// (perturbed, then judged by the Woodbury capacitance with the same
/// relative threshold). The checkerboard cube gives |d_k| ≈ 1e-16 · max;
/// genuinely nonsingular limit matrices have κ(S) ≤ 10³ or so.
pub const LDL_PIVOT_RTOL: f64 = 1e-10;

/// LDLᵀ perturbs at most this many zero pivots (each costs one
/// refactorisation) before declaring S singular.
pub const LDL_MAX_PERTURBATIONS: usize = 8;

/// Dense LU pivot test, as [`LDL_PIVOT_RTOL`]: |u_kk| ≤ `DENSE_PIVOT_RTOL` ·
/// max_j |u_jj| means A is numerically singular.
pub const DENSE_PIVOT_RTOL: f64 = 1e-12;

/// Iterative refinement steps after a direct solve whose residual misses
/// the tolerance (each costs one product and one pair of triangular solves).
pub const REFINEMENT_STEPS: usize = 3;

/// Nested dissection ([`nested_dissection`](crate::nested_dissection)):
/// vertex subsets at most this large are not dissected further (numbered in
/// breadth-first order).
pub const ND_LEAF_SIZE: usize = 64;

/// Default size cap of the dense solver: n² · 8 bytes ≤ 2 GiB (n = 16,384).
/// The LU is O(n³); callers that want bigger systems pass their own cap to
/// [`dense_lu_capped`](crate::dense::dense_lu_capped).
pub const DENSE_MAX_N: usize = 16_384;
