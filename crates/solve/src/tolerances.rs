//! Every tolerance, threshold and tuning constant of the crate, in one place
//! (pmp-library's `tolerances.h`).
//!
//! Solvers read these; none hard-codes a number of its own. Each constant
//! says what it guards and why it has its value.

/// Default relative stopping tolerance: max over rows of |P − AX| / scale.
/// SPEC §4 (the papers stop on the same max-norm quantity).
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

/// Default size cap of the dense solver: n² · 8 bytes ≤ 2 GiB (n = 16,384).
/// The LU is O(n³); callers that want bigger systems pass their own cap to
/// [`dense_lu_capped`](crate::dense::dense_lu_capped).
pub const DENSE_MAX_N: usize = 16_384;
