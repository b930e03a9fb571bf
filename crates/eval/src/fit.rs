//! Fitting a control mesh to dense data: move the control points of a coarse
//! mesh (topology and tags kept) so that its limit surface comes close to a
//! target (a triangle mesh, a point cloud, a partial scan).
//!
//! # References
//! Wang, Pottmann & Liu 2006, *Fitting B-spline curves to point clouds by
//! curvature-based squared distance minimization* (ACM TOG 25(2)): the
//! point-to-plane ("tangent distance", TDM) error term, §4-5, and the
//! observation that minimising it with foot points re-projected every round
//! is the Gauss-Newton method for the squared distance; Marinov & Kobbelt
//! 2005 (optimisation methods for subdivision-surface fitting, the same
//! Gauss-Newton view with Levenberg-Marquardt damping); Deng & Lin 2014
//! (LSPIA: point-to-point least squares with foot points re-projected, which
//! converges linearly, kept as [`FitMethod::PointToPoint`]); Holland &
//! Welsch 1977 (IRLS for robust M-estimators; Huber's and Cauchy's weights,
//! σ from the median absolute deviation). See docs/REFERENCES.md.
//!
//! # Algorithm
//! 0. **Normalise** (the numeric rule): the target and the control points are
//!    scaled by exact powers of two and centred so that the target lies in
//!    a box of half-width in [½, 1); everything below runs there, distances
//!    are mapped back to the input's units, and a result that does not map
//!    back to finite coordinates is refused ([`EvalError::InvalidInput`]).
//! 1. **Feet.** Project every target point qⱼ onto the current limit surface:
//!    parameter tⱼ, foot S(tⱼ) = Wⱼ·P (the row of [`LimitSurface::stencil`]),
//!    normal nⱼ and distance dⱼ. Round 0 uses the exact global search
//!    ([`crate::project`]); later rounds re-project each foot by Newton on its
//!    previous domain from its previous parameter
//!    ([`crate::project::project_near`]: a few evaluations of one patch) and
//!    hand only the feet that end on their domain's boundary (or do not
//!    converge) to the global search. They and the surface → target
//!    distances of surface samples are [`FitIteration`] k.
//! 2. **Weights.** ωⱼ = 1 for [`FitLoss::L2`]; for a robust loss the IRLS
//!    weights of Huber (k = 1.345σ) or Cauchy (c = 2.385σ) at dⱼ, with
//!    σ = 1.4826·median dⱼ (Holland & Welsch 1977).
//! 3. **Step.** With the feet fixed, minimise over the step δ (P = Pₖ + δ)
//!    Σⱼ ωⱼ rⱼᵀMⱼrⱼ + β Σₛ ‖S(tₛ) − q̂ₛ‖² + s‖L P‖² + κ Σ_{i∈U} ‖(L P)ᵢ‖²
//!    + φ Σᵢ ‖Tᵢ(L P)ᵢ‖² + μ Σᵢ Dᵢ‖δᵢ‖², rⱼ = Wⱼ P − qⱼ, where
//!    - Mⱼ = nⱼnⱼᵀ + αI for [`FitMethod::GaussNewton`]: the point-to-plane
//!      term, whose minimisation with re-projected feet is the Gauss-Newton
//!      step of Σ dist(qⱼ, S)² (Wang, Pottmann & Liu 2006, §4, Eq. (9) with
//!      the curvature terms dropped: d/(d − ρ) → 0 as d → 0, the TDM), plus
//!      a **tangential anchor** α = [`TANGENT_ANCHOR`]·min(1, RMS/(0.01·d))²:
//!      a point-to-point part quadratic in the residual level, which vanishes
//!      on exact data and holds the feet against sliding along the surface
//!      while noise keeps the residual up.
//!    - Mⱼ = I for [`FitMethod::PointToPoint`] (the fixed point of LSPIA,
//!      Deng & Lin 2014, reached by one direct solve per round), and
//!      Mⱼ = nⱼnⱼᵀ + λI for [`FitMethod::TangentDistance`] (the previous
//!      default, λ shrinking ×[`LAMBDA_DECREASE`] per kept round).
//!    - **Surface → target term** (Gauss-Newton, first round only:
//!      β = [`BACK_WEIGHT`]·m/(samples), ×[`BACK_DECAY`] = 0 after): the
//!      [`FitOptions::samples_per_domain`] samples S(tₛ) of the domains that
//!      hold feet, pulled to their nearest target points q̂ₛ, so that a start
//!      far off does not leave parts of the surface away from the data. It
//!      fades because q̂ₛ lies on a chord of the data, not on the surface.
//!    - **Fading fairing** (Gauss-Newton): φ = [`FAIR_START`]·m/n in round 1,
//!      ×[`FAIR_DECAY`] per kept round, dropped below [`FAIR_OFF`]; Tᵢ =
//!      I − νᵢνᵢᵀ with νᵢ the control mesh's vertex normal at the round's
//!      start: the tangential part of the umbrella Laplacian, which evens
//!      out the parametrisation of a start whose vertices were moved
//!      independently (a tangled control mesh, which point-to-plane steps
//!      barely see) without shrinking the shape. It vanishes, so exact data
//!      are still recovered exactly.
//!    - s = w·m/n with w = [`FitOptions::smoothness`], L the umbrella
//!      Laplacian of the control mesh.
//!    - **Regularisation (never singular).** The data support of control
//!      vertex i is the trace of its 3 × 3 diagonal block of Σ ωⱼ WⱼᵀMⱼWⱼ.
//!      Vertices whose support is below [`SUPPORT_THRESHOLD`] × the median
//!      non-zero support (a partial scan, a region the target does not
//!      reach) form U; κ = [`REGULARISATION`] × that median. They follow
//!      their neighbours smoothly and are reported
//!      ([`FitResult::regularised`]).
//!    - **Damping (Levenberg-Marquardt).** Dᵢ = max(tr Hᵢᵢ / 3, [`PIN`] ×
//!      the median support): an isotropic Marquardt scaling per vertex, so
//!      the matrix is symmetric positive definite whatever the data (a
//!      vertex without any support, tangential motions of a flat region).
//!      μ starts at [`DAMPING_START`], shrinks ×[`DAMPING_DOWN`] after a kept
//!      round (down to [`DAMPING_MIN`]) and grows ×[`DAMPING_UP`] to retry a
//!      rejected one, at most [`MAX_RETRIES`] times in a row (a retry keeps
//!      the assembled data terms and changes μ only).
//!
//!    The 3n × 3n normal equations are assembled per group of feet with the
//!    same stencil support (the 7 distinct moments of each symmetric 3 × 3
//!    block summed per stencil pair, in chunks of fixed size summed in a
//!    fixed order: the result does not depend on the thread count) and
//!    solved by sparse LDLᵀ with nested-dissection ordering (subdiv-solve)
//!    up to [`DIRECT_LIMIT`] unknowns, above it (or when the factorisation
//!    fails) by conjugate gradients preconditioned with the inverse 3 × 3
//!    diagonal blocks, as an **inexact Newton step**: relative residual
//!    min([`CG_TOLERANCE_START`], RMS/d), at least [`CG_TOLERANCE`], at most
//!    [`CG_MAX_ITERATIONS`] iterations ([`FitIteration::solver_iterations`]).
//! 4. **Accept or retry.** The candidate is re-projected (step 1); it is kept
//!    when the objective F (the data terms of steps 2-3 and the penalties)
//!    decreases.
//! 5. **Stop** ([`FitStop`]): RMS target → surface ≤ tolerance·d, or at the
//!    rounding floor ([`RMS_FLOOR`]·d); a kept round that lowers the data
//!    term by less than [`FitOptions::min_improvement`] (relative) while the
//!    fading fairing is below that fraction of it; [`FitOptions::iterations`]
//!    kept rounds; [`FitOptions::max_time`]; the retries spent.
//!
//! # Deviations from the papers
//! Wang, Pottmann & Liu's SDM keeps the curvature terms of the squared
//! distance (stabler far from the target); we drop them (TDM) and stabilise
//! by the Levenberg-Marquardt damping, the tangential anchor and the fading
//! fairing of step 3 instead, which need no second derivatives and keep the
//! Gauss-Newton step's fast local convergence on exact data (all three
//! vanish there). Feet are re-projected locally (a Newton warm start), as
//! fitting codes commonly do, with the global search as the fallback. LSPIA's fixed-step iteration is replaced by
//! the direct solve of the same least-squares problem each round.

use crate::bvh::TargetIndex;
use crate::project::{project_near, projector, BoundLimitSurface, ProjectOptions, Projection};
use crate::sample::sample_per_domain;
use crate::surface::{EvalError, LimitSurface};
use glam::DVec3;
use rayon::prelude::*;
use sprs::{CsMatI, TriMatI};
use std::sync::Arc;
use std::time::Instant;
use subdiv_mesh::{Mesh, PowerOfTwoScale, VertexId};
use subdiv_solve::{FactoredMatrix, LdlFactor};
use subdiv_stencil::Options;

/// μ of the first round, relative to each vertex's data support (step 3).
pub const DAMPING_START: f64 = 1e-2;
/// The smallest μ.
pub const DAMPING_MIN: f64 = 1e-12;
/// μ after a kept round: μ·DAMPING_DOWN.
pub const DAMPING_DOWN: f64 = 0.1;
/// μ before a retry of a rejected round: μ·DAMPING_UP.
pub const DAMPING_UP: f64 = 10.0;
/// β₀ of the surface → target term, relative to the data term's mass (step 3).
pub const BACK_WEIGHT: f64 = 1.0;
/// β shrinks ×BACK_DECAY per kept round (the term fades: the nearest target
/// point of a sample lies on a chord, not on the true surface). 0: the first
/// round only (measured: a slower fade halves the convergence rate).
pub const BACK_DECAY: f64 = 0.0;
/// Weight of the point-to-point part in a Gauss-Newton round at an RMS
/// residual of 1 % of d (quadratic in the residual below, capped above).
pub const TANGENT_ANCHOR: f64 = 0.1;
/// Weight of the fairing of the control points in the first round (relative
/// to the data term's mass, module docs step 3).
pub const FAIR_START: f64 = 0.4;
/// The fairing's weight shrinks ×FAIR_DECAY per kept round…
pub const FAIR_DECAY: f64 = 0.1;
/// …and is dropped below this.
pub const FAIR_OFF: f64 = 1e-12;
/// Damping of the previous methods (point-to-point, tangent distance): fixed.
pub const DAMPING: f64 = 1e-9;
/// Rejected rounds retried with more damping (or, for the tangent distance,
/// a larger λ) before the fit stops.
pub const MAX_RETRIES: usize = 8;
/// A control vertex whose data support is below this fraction of the median
/// non-zero support is regularised (module docs, step 3).
pub const SUPPORT_THRESHOLD: f64 = 1e-3;
/// κ of the regularisation, relative to the median support.
pub const REGULARISATION: f64 = 1e-3;
/// The floor of every vertex's damping scale Dᵢ, relative to the median support.
pub const PIN: f64 = 1e-6;
/// RMS target → surface distance (relative to d) at which rounding dominates: stop.
pub const RMS_FLOOR: f64 = 1e-14;
/// Unknowns (3 × control vertices) up to which the step is solved by LDLᵀ.
pub const DIRECT_LIMIT: usize = 1_500;
/// Relative residual of the conjugate-gradient solve at most (the forcing
/// term of the inexact Newton step is min(RMS/d, [`CG_TOLERANCE_START`]),
/// down to this).
pub const CG_TOLERANCE: f64 = 1e-6;
/// Relative residual of the conjugate-gradient solve far from the target.
pub const CG_TOLERANCE_START: f64 = 1e-3;
/// Conjugate-gradient iterations at most.
pub const CG_MAX_ITERATIONS: usize = 500;
/// [`FitMethod::TangentDistance`]: λ is multiplied by this after an accepted round
/// (and divided by it before a retry of a rejected one).
pub const LAMBDA_DECREASE: f64 = 0.1;
/// The smallest λ of the tangent-distance schedule.
pub const LAMBDA_MIN: f64 = 1e-8;
/// Huber's constant (×σ): 95 % efficiency under Gaussian noise.
pub const HUBER_K: f64 = 1.345;
/// Cauchy's constant (×σ): 95 % efficiency under Gaussian noise.
pub const CAUCHY_C: f64 = 2.385;
/// Feet per parallel assembly chunk (fixed: the sums do not depend on the threads).
const CHUNK: usize = 4096;

/// What the fit is to come close to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FitTarget {
    /// Target points (the mesh's vertices, or the cloud).
    pub points: Vec<DVec3>,
    /// Triangles over `points` (empty for a point cloud).
    pub triangles: Vec<[u32; 3]>,
}

impl FitTarget {
    /// A point cloud.
    pub fn cloud(points: Vec<DVec3>) -> Self {
        Self { points, triangles: Vec::new() }
    }

    /// A mesh target: its vertices, and its faces as triangle fans.
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let mut triangles = Vec::new();
        for f in mesh.topology().faces().iter() {
            for k in 1..f.len() - 1 {
                triangles.push([f[0], f[k], f[k + 1]]);
            }
        }
        Self { points: mesh.positions().to_vec(), triangles }
    }
}

/// The error term and its minimisation (module docs, step 3).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum FitMethod {
    /// Point-to-plane Gauss-Newton with Levenberg-Marquardt damping (the default).
    #[default]
    GaussNewton,
    /// ‖S(tⱼ) − qⱼ‖²: the LSPIA fixed point each round (converges linearly).
    PointToPoint,
    /// (nⱼ·(S(tⱼ) − qⱼ))² + λ‖S(tⱼ) − qⱼ‖² with λ shrinking per kept round.
    TangentDistance {
        /// λ > 0 at the start.
        lambda: f64,
    },
}

/// λ of [`FitMethod::TangentDistance`] when only its name is given.
pub const TANGENT_LAMBDA: f64 = 0.05;

impl FitMethod {
    /// Every method (the tangent distance with λ = [`TANGENT_LAMBDA`]), in
    /// the order the command line and Python list them.
    pub const ALL: [FitMethod; 3] =
        [Self::GaussNewton, Self::PointToPoint, Self::TangentDistance { lambda: TANGENT_LAMBDA }];

    /// The name used on the command line, in reports and in Python (its [`FromStr`](std::str::FromStr) reads it back).
    pub fn name(self) -> &'static str {
        match self {
            Self::GaussNewton => "gauss-newton",
            Self::PointToPoint => "lspia",
            Self::TangentDistance { .. } => "tangent",
        }
    }

    /// One line for help texts.
    pub fn summary(self) -> &'static str {
        match self {
            Self::GaussNewton => {
                "point-to-plane Gauss-Newton with Levenberg-Marquardt damping (quadratic near the target)"
            }
            Self::PointToPoint => "point-to-point least squares per round: the LSPIA fixed point (converges linearly)",
            Self::TangentDistance { .. } => "tangent distance (n·r)² + λ‖r‖², λ shrinking per round",
        }
    }

    /// The same method with λ = `lambda` if it is the tangent distance.
    pub fn with_lambda(self, lambda: f64) -> Self {
        match self {
            Self::TangentDistance { .. } => Self::TangentDistance { lambda },
            other => other,
        }
    }
}

impl std::fmt::Display for FitMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FitMethod {
    type Err = EvalError;

    /// A [`FitMethod::name`] (the tangent distance with λ = [`TANGENT_LAMBDA`]).
    fn from_str(s: &str) -> Result<Self, EvalError> {
        Self::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| EvalError::InvalidInput {
            what: format!("method {s:?} is not one of {}", Self::ALL.map(Self::name).join(", ")),
        })
    }
}

/// The loss applied to the target → surface distances (module docs, step 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FitLoss {
    /// Least squares (optimal for Gaussian noise).
    #[default]
    L2,
    /// Huber: quadratic to 1.345σ, linear beyond (outliers).
    Huber,
    /// Cauchy (Lorentzian): redescending, for heavy outliers.
    Cauchy,
}

impl FitLoss {
    /// Every loss, in the order the command line and Python list them.
    pub const ALL: [FitLoss; 3] = [Self::L2, Self::Huber, Self::Cauchy];

    /// The name used on the command line, in reports and in Python (its [`FromStr`](std::str::FromStr) reads it back).
    pub fn name(self) -> &'static str {
        match self {
            Self::L2 => "l2",
            Self::Huber => "huber",
            Self::Cauchy => "cauchy",
        }
    }

    /// One line for help texts.
    pub fn summary(self) -> &'static str {
        match self {
            Self::L2 => "least squares (Gaussian noise)",
            Self::Huber => "Huber (outliers)",
            Self::Cauchy => "Cauchy (heavy outliers)",
        }
    }

    /// IRLS weight at distance `d` for scale `sigma`.
    fn weight(self, d: f64, sigma: f64) -> f64 {
        match self {
            Self::L2 => 1.0,
            Self::Huber => {
                let k = HUBER_K * sigma;
                if d <= k {
                    1.0
                } else {
                    k / d
                }
            }
            Self::Cauchy => {
                let c = CAUCHY_C * sigma;
                1.0 / (1.0 + (d / c) * (d / c))
            }
        }
    }

    /// ρ(d), scaled so that ρ(d) = d² near 0.
    fn rho(self, d: f64, sigma: f64) -> f64 {
        match self {
            Self::L2 => d * d,
            Self::Huber => {
                let k = HUBER_K * sigma;
                if d <= k {
                    d * d
                } else {
                    2.0 * k * d - k * k
                }
            }
            Self::Cauchy => {
                let c = CAUCHY_C * sigma;
                c * c * (d / c).mul_add(d / c, 1.0).ln()
            }
        }
    }
}

impl std::fmt::Display for FitLoss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FitLoss {
    type Err = EvalError;

    /// A [`FitLoss::name`].
    fn from_str(s: &str) -> Result<Self, EvalError> {
        Self::ALL.into_iter().find(|l| l.name() == s).ok_or_else(|| EvalError::InvalidInput {
            what: format!("loss {s:?} is not one of {}", Self::ALL.map(Self::name).join(", ")),
        })
    }
}

/// Why a fit stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FitStop {
    /// The RMS target → surface distance reached the tolerance.
    Tolerance,
    /// The RMS target → surface distance is at the rounding floor ([`RMS_FLOOR`]·d).
    Exact,
    /// A kept round improved the objective by less than [`FitOptions::min_improvement`].
    Stalled,
    /// [`FitOptions::iterations`] rounds were kept.
    #[default]
    MaxRounds,
    /// [`FitOptions::max_time`] passed.
    MaxTime,
    /// [`MAX_RETRIES`] rejected rounds in a row: no descent found.
    NoDescent,
}

impl FitStop {
    /// The name used in reports and in Python.
    pub fn name(self) -> &'static str {
        match self {
            Self::Tolerance => "tolerance",
            Self::Exact => "exact",
            Self::Stalled => "relative-improvement",
            Self::MaxRounds => "max-rounds",
            Self::MaxTime => "max-time",
            Self::NoDescent => "no-descent",
        }
    }
}

/// Called after every measured round (progress); the round's [`FitIteration`].
#[derive(Clone, Default)]
pub struct FitObserver(Option<Arc<FitCallback>>);

/// What a [`FitObserver`] calls.
type FitCallback = dyn Fn(&FitIteration) + Send + Sync;

impl FitObserver {
    /// An observer calling `f`.
    pub fn new(f: impl Fn(&FitIteration) + Send + Sync + 'static) -> Self {
        Self(Some(Arc::new(f)))
    }

    fn notify(&self, it: &FitIteration) {
        if let Some(f) = &self.0 {
            f(it);
        }
    }
}

impl std::fmt::Debug for FitObserver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() { "FitObserver(Some)" } else { "FitObserver(None)" })
    }
}

impl PartialEq for FitObserver {
    /// Observers do not change the result: all are equal.
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Options of [`fit`].
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The surface (scheme, boundary, creases).
    pub surface: Options,
    /// Kept rounds at most. Default 30.
    pub iterations: usize,
    /// Weight w ≥ 0 of the umbrella-Laplacian smoothness term. Default 0.
    pub smoothness: f64,
    /// Stop when the RMS target → surface distance is at most this times d. Default 0 (never).
    pub tolerance: f64,
    /// Stop when a kept round lowers the objective by less than this fraction. Default 1e-3.
    pub min_improvement: f64,
    /// Stop after this many seconds (checked after every round). Default none.
    pub max_time: Option<f64>,
    /// The error term and its minimisation. Default Gauss-Newton.
    pub method: FitMethod,
    /// The loss on the distances. Default least squares.
    pub loss: FitLoss,
    /// Surface samples per domain side for the surface → target distance. Default 4.
    pub samples_per_domain: usize,
    /// Projection tuning.
    pub project: ProjectOptions,
    /// Called after every round.
    pub observer: FitObserver,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            surface: Options::default(),
            iterations: 30,
            smoothness: 0.0,
            tolerance: 0.0,
            min_improvement: 1e-3,
            max_time: None,
            method: FitMethod::GaussNewton,
            loss: FitLoss::L2,
            samples_per_domain: 4,
            project: ProjectOptions::default(),
            observer: FitObserver::default(),
        }
    }
}

impl FitOptions {
    /// Checks every number.
    ///
    /// # Errors
    /// [`EvalError::InvalidInput`] naming the option.
    pub fn validate(&self) -> Result<(), EvalError> {
        let bad = |what: String| Err(EvalError::InvalidInput { what });
        if !(self.smoothness >= 0.0 && self.smoothness.is_finite()) {
            return bad(format!("fit: smoothness {} is not a finite number ≥ 0", self.smoothness));
        }
        if !(self.tolerance >= 0.0 && self.tolerance.is_finite()) {
            return bad(format!("fit: tolerance {} is not a finite number ≥ 0", self.tolerance));
        }
        if !(self.min_improvement >= 0.0 && self.min_improvement < 1.0) {
            return bad(format!("fit: minimum relative improvement {} is not in [0, 1)", self.min_improvement));
        }
        if let Some(t) = self.max_time {
            if !(t > 0.0 && t.is_finite()) {
                return bad(format!("fit: max time {t} s is not a finite number > 0"));
            }
        }
        if let FitMethod::TangentDistance { lambda } = self.method {
            if !(lambda > 0.0 && lambda.is_finite()) {
                return bad(format!("fit: tangent-distance λ {lambda} is not a finite number > 0"));
            }
        }
        if self.samples_per_domain == 0 {
            return bad("fit: samples per domain must be at least 1".into());
        }
        Ok(())
    }
}

/// Distances at one round, in the input's units and relative to d (the target's bbox diagonal).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FitIteration {
    /// Round (0: the start).
    pub iteration: usize,
    /// RMS distance of the target points to the surface.
    pub rms_target_to_surface: f64,
    /// Largest distance of a target point to the surface.
    pub max_target_to_surface: f64,
    /// RMS distance of surface samples to the target.
    pub rms_surface_to_target: f64,
    /// Largest distance of a surface sample to the target.
    pub max_surface_to_target: f64,
    /// d, the target's bounding-box diagonal (divide by it for relative values).
    pub scale: f64,
    /// The damping μ (Gauss-Newton) or λ (tangent distance) of the kept step; 0 at round 0.
    pub damping: f64,
    /// Rejected tries before this round was kept.
    pub retries: usize,
    /// Control vertices regularised in this round's step (low data support).
    pub regularised: usize,
    /// σ of the robust loss in this round (relative to d; 0 for least squares).
    pub robust_scale: f64,
    /// Seconds since the fit started.
    pub seconds: f64,
    /// The linear solver of this round's step ("ldl", "cg"; "" at round 0).
    pub solver: &'static str,
    /// Conjugate-gradient iterations of this round's kept step (0 for LDLᵀ).
    pub solver_iterations: usize,
}

/// The fitted mesh and the distances round by round.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The control mesh with fitted positions (topology and tags of the input).
    pub mesh: Mesh,
    /// Distances at the start and after every kept round.
    pub iterations: Vec<FitIteration>,
    /// Why it stopped.
    pub stop: FitStop,
    /// Control vertices regularised in some round (low data support), sorted.
    pub regularised: Vec<u32>,
}

/// The affine map of step 0: normalised = 2^e·(2^e₁·p − c), where
/// 2^e₁ brings the target into [-1, 1] and 2^e its centred copy into [½, 1).
#[derive(Clone, Copy, Debug)]
struct Frame {
    first: PowerOfTwoScale,
    centre: DVec3,
    second: PowerOfTwoScale,
}

impl Frame {
    fn of(points: &[DVec3]) -> Self {
        let first = PowerOfTwoScale::normalizing(points.iter().copied());
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &p in points {
            let q = first.apply_point(p);
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let centre = 0.5 * (lo + hi);
        let second = PowerOfTwoScale::normalizing([lo - centre, hi - centre]);
        Self { first, centre, second }
    }

    fn to_unit(self, p: DVec3) -> DVec3 {
        self.second.apply_point(self.first.apply_point(p) - self.centre)
    }

    fn to_input(self, p: DVec3) -> DVec3 {
        self.first.inverse().apply_point(self.second.inverse().apply_point(p) + self.centre)
    }

    fn length_from_unit(self, x: f64) -> f64 {
        self.first.inverse().apply(self.second.inverse().apply(x))
    }
}

/// Distances of the target to the surface of `mesh` and back, with the feet
/// (normalised units).
struct Measured {
    feet: Vec<Projection>,
    /// Surface samples (as projections: parameter, position, normal) and
    /// their nearest target points.
    samples: Vec<(Projection, DVec3)>,
    rms_a: f64,
    max_a: f64,
    rms_b: f64,
    max_b: f64,
}

fn measure(
    surface: &LimitSurface,
    mesh: &Mesh,
    points: &[DVec3],
    index: &TargetIndex,
    options: &FitOptions,
    previous: Option<&[Projection]>,
) -> Result<Measured, EvalError> {
    let bound = BoundLimitSurface::new(surface, mesh.positions())?;
    // Step 1: every foot re-projected from the previous one (a few Newton
    // steps on one patch); the feet that leave their domain, and all feet of
    // round 0, by the exact global search.
    let mut feet: Vec<Option<Projection>> = match previous {
        Some(prev) => points
            .par_iter()
            .zip(prev)
            .with_min_len(256)
            .map(|(&q, p)| project_near(&bound, q, p.param, options.project.max_iterations))
            .collect::<Result<_, _>>()?,
        None => vec![None; points.len()],
    };
    let missing: Vec<usize> = (0..points.len()).filter(|&j| feet[j].is_none()).collect();
    if !missing.is_empty() {
        let projector = projector(surface, mesh, &options.surface, &options.project)?;
        let queries: Vec<DVec3> = missing.iter().map(|&j| points[j]).collect();
        for (j, f) in missing.iter().zip(projector.project_all(&queries)?) {
            feet[*j] = Some(f);
        }
    }
    let feet: Vec<Projection> = feet.into_iter().map(|f| f.expect("every foot found")).collect();
    let (rms_a, max_a) = rms_max(feet.iter().map(|f| f.distance));
    let samples = sample_per_domain(&bound, options.samples_per_domain)?;
    let samples: Vec<(Projection, DVec3)> = samples
        .par_iter()
        .map(|s| {
            let (c, d) = index.nearest(s.position).unwrap_or((s.position, f64::INFINITY));
            (Projection { param: s.param, position: s.position, normal: s.normal, distance: d }, c)
        })
        .collect();
    let (rms_b, max_b) = rms_max(samples.iter().map(|s| s.0.distance));
    Ok(Measured { feet, samples, rms_a, max_a, rms_b, max_b })
}

fn rms_max(d: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    for x in d {
        sum += x * x;
        max = max.max(x);
        n += 1;
    }
    ((sum / n.max(1) as f64).sqrt(), max)
}

/// Median of non-negative values (0 for none).
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let k = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    *m
}

/// Fits `control`'s limit surface to `target` (module docs).
///
/// # Errors
/// [`EvalError::InvalidInput`] for an empty, non-finite, flat-to-a-point or
/// unrepresentable target, bad options, or a result that does not map back
/// to finite coordinates; [`EvalError::Solve`] when a step cannot be solved
/// (not expected: the system is positive definite); what building,
/// evaluating and projecting the surface returns.
pub fn fit(target: &FitTarget, control: &Mesh, options: &FitOptions) -> Result<FitResult, EvalError> {
    let start = Instant::now();
    options.validate()?;
    if target.points.is_empty() {
        return Err(EvalError::InvalidInput { what: "fit: the target has no points".into() });
    }
    if let Some(i) = target.points.iter().position(|p| !p.is_finite()) {
        return Err(EvalError::InvalidInput { what: format!("fit: target point {i} is not finite") });
    }
    if let Some((k, t)) =
        target.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= target.points.len()))
    {
        return Err(EvalError::InvalidInput { what: format!("fit: target triangle {k} {t:?} names a missing point") });
    }
    // Step 0: the unit frame.
    let frame = Frame::of(&target.points);
    let points: Vec<DVec3> = target.points.iter().map(|&p| frame.to_unit(p)).collect();
    let unit_scale = subdiv_mesh::Aabb::of(points.iter().copied()).map_or(0.0, |b| b.diagonal());
    if unit_scale.is_nan() || unit_scale <= 0.0 {
        return Err(EvalError::InvalidInput {
            what: "fit: the target's points all coincide (its bounding box has no extent): nothing to fit".into(),
        });
    }
    let scale = frame.length_from_unit(unit_scale);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(EvalError::InvalidInput {
            what: format!(
                "fit: the target's bounding-box diagonal is not representable as a finite f64 ({scale:e}): scale the data"
            ),
        });
    }
    let start_positions: Vec<DVec3> = control.positions().iter().map(|&p| frame.to_unit(p)).collect();
    if let Some(i) = start_positions.iter().position(|p| !p.is_finite() || p.abs().max_element() > 1e150) {
        return Err(EvalError::InvalidInput {
            what: format!("fit: control vertex {i} is too far from the target to be represented in the target's frame"),
        });
    }
    let surface = LimitSurface::new(control, &options.surface)?;
    let index = TargetIndex::new(points.clone(), target.triangles.clone());
    let laplacian = umbrella(control);
    let pattern = Pattern::new(&surface, control, &laplacian);
    let mut mesh = control.with_positions(start_positions);
    let mut measured = measure(&surface, &mesh, &points, &index, options, None)?;
    let stats = |m: &Measured, iteration: usize| FitIteration {
        iteration,
        rms_target_to_surface: frame.length_from_unit(m.rms_a),
        max_target_to_surface: frame.length_from_unit(m.max_a),
        rms_surface_to_target: frame.length_from_unit(m.rms_b),
        max_surface_to_target: frame.length_from_unit(m.max_b),
        scale,
        seconds: start.elapsed().as_secs_f64(),
        ..FitIteration::default()
    };
    let mut iterations = vec![stats(&measured, 0)];
    options.observer.notify(&iterations[0]);
    let mut regularised_all: Vec<u32> = Vec::new();
    let smooth_weight = options.smoothness * points.len() as f64 / control.positions().len().max(1) as f64;
    let mut mu = DAMPING_START;
    let mut fair = if matches!(options.method, FitMethod::GaussNewton) { FAIR_START } else { 0.0 };
    let per_vertex = points.len() as f64 / control.positions().len().max(1) as f64;
    let mut beta = if matches!(options.method, FitMethod::GaussNewton) { BACK_WEIGHT } else { 0.0 };
    let mut lambda = match options.method {
        FitMethod::TangentDistance { lambda } => lambda,
        _ => 0.0,
    };
    let mut k = 1;
    let mut retries = 0;
    let mut cached: Option<System> = None;
    let stop = loop {
        if measured.rms_a <= options.tolerance * unit_scale {
            break FitStop::Tolerance;
        }
        if measured.rms_a <= RMS_FLOOR * unit_scale {
            break FitStop::Exact;
        }
        if k > options.iterations {
            break FitStop::MaxRounds;
        }
        if options.max_time.is_some_and(|t| start.elapsed().as_secs_f64() >= t) {
            break FitStop::MaxTime;
        }
        // Step 2: weights.
        let sigma = match options.loss {
            FitLoss::L2 => 0.0,
            _ => (1.4826 * median(measured.feet.iter().map(|f| f.distance).collect())).max(1e-12 * unit_scale),
        };
        let weights: Vec<f64> = measured.feet.iter().map(|f| options.loss.weight(f.distance, sigma)).collect();
        // Step 3: the step.
        let (normal_weight, point_weight, damping) = match options.method {
            // A tangential anchor quadratic in the residual level: it
            // vanishes on exact data (no brake near the solution) and holds
            // the feet against sliding when noise keeps the residual up.
            FitMethod::GaussNewton => {
                (1.0, TANGENT_ANCHOR * (measured.rms_a / (0.01 * unit_scale)).min(1.0).powi(2), mu)
            }
            FitMethod::PointToPoint => (0.0, 1.0, DAMPING),
            FitMethod::TangentDistance { .. } => (1.0, lambda, DAMPING),
        };
        // Tangential relaxation (module docs, step 3), quadratic in the residual level.
        let relax = Relax { weight: fair * per_vertex, normals: vertex_normals(&mesh) };
        // A retry changes the damping only: the data terms are kept.
        let system = match cached.take() {
            Some(system) => system,
            None => {
                let system =
                    assemble(&surface, &pattern, &measured.feet, &points, &weights, [normal_weight, point_weight])?;
                // The surface → target term (module docs, step 3): samples of domains
                // that hold feet, pulled to their nearest target points, weight
                // β = BACK_WEIGHT·BACK_DECAY^(kept rounds)·m/(samples), fading out.
                let back = back_term(&measured, &weights, beta, points.len());
                if back.1.is_empty() {
                    system
                } else {
                    let extra = assemble(&surface, &pattern, &back.0, &back.2, &back.1, [0.0, 1.0])?;
                    add_systems(system, extra)
                }
            }
        };
        // Inexact Newton: the forcing term shrinks with the residual level
        // (superlinear convergence without solving early steps to rounding).
        let cg_tolerance = (measured.rms_a / unit_scale).clamp(CG_TOLERANCE, CG_TOLERANCE_START);
        let step = solve_step(&system, &laplacian, mesh.positions(), smooth_weight, damping, cg_tolerance, &relax)?;
        cached = Some(system);
        let candidate_positions: Vec<DVec3> = mesh.positions().iter().zip(&step.delta).map(|(&p, &d)| p + d).collect();
        let candidate = mesh.with_positions(candidate_positions);
        let next = measure(&surface, &candidate, &points, &index, options, Some(&measured.feet))?;
        // F = data + penalties; the data part alone decides the stall below.
        let data_term = |m: &Measured| -> f64 {
            m.feet.iter().map(|f| options.loss.rho(f.distance, sigma)).sum::<f64>() + {
                let (terms, w, _) = back_term(m, &weights, beta, points.len());
                terms.iter().zip(&w).map(|(t, w)| w * t.distance * t.distance).sum::<f64>()
            }
        };
        let penalty = |positions: &[DVec3]| {
            penalties(&laplacian, positions, smooth_weight, &step.unsupported, step.kappa, &relax)
        };
        let (old_data, new_data) = (data_term(&measured), data_term(&next));
        let (old, new) = (old_data + penalty(mesh.positions()), new_data + penalty(candidate.positions()));
        if new < old && next.rms_a.is_finite() {
            regularised_all.extend(&step.unsupported);
            cached = None;
            mesh = candidate;
            measured = next;
            let mut it = stats(&measured, k);
            it.damping = match options.method {
                FitMethod::GaussNewton => mu,
                FitMethod::PointToPoint => 0.0,
                FitMethod::TangentDistance { .. } => lambda,
            };
            it.retries = retries;
            it.regularised = step.unsupported.len();
            it.robust_scale = sigma / unit_scale;
            it.solver = step.solver;
            it.solver_iterations = step.solver_iterations;
            options.observer.notify(&it);
            iterations.push(it);
            k += 1;
            retries = 0;
            mu = (mu * DAMPING_DOWN).max(DAMPING_MIN);
            beta *= BACK_DECAY;
            fair = if fair * FAIR_DECAY < FAIR_OFF { 0.0 } else { fair * FAIR_DECAY };
            lambda = (lambda * LAMBDA_DECREASE).max(LAMBDA_MIN);
            // Stalled: F or the data term no longer improves (a round that
            // trades data for a penalty goes on), and the fading fairing is
            // too small to be what holds it.
            let fading = relax.weight > 0.0
                && penalties(&laplacian, mesh.positions(), 0.0, &[], 0.0, &relax) > options.min_improvement * new_data;
            let data_gain = old_data - new_data;
            let small = old - new < options.min_improvement * old
                || (data_gain >= 0.0 && data_gain < options.min_improvement * old_data);
            if small && !fading {
                break FitStop::Stalled;
            }
            continue;
        }
        // Rejected: more damping (or more of the point-to-point term), or stop.
        let can_retry = !matches!(options.method, FitMethod::PointToPoint) && retries < MAX_RETRIES;
        if !can_retry {
            break FitStop::NoDescent;
        }
        retries += 1;
        mu *= DAMPING_UP;
        lambda /= LAMBDA_DECREASE;
    };
    regularised_all.sort_unstable();
    regularised_all.dedup();
    let positions: Vec<DVec3> = mesh.positions().iter().map(|&p| frame.to_input(p)).collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(EvalError::InvalidInput {
            what: format!("fit: fitted control vertex {i} is not representable as finite f64 coordinates"),
        });
    }
    Ok(FitResult { mesh: control.with_positions(positions), iterations, stop, regularised: regularised_all })
}

/// The surface → target terms of `m`: samples of the domains that hold a
/// foot with a non-zero weight, their weights β·m/(samples) and their
/// nearest target points (empty when β = 0).
fn back_term(m: &Measured, weights: &[f64], beta: f64, data: usize) -> (Vec<Projection>, Vec<f64>, Vec<DVec3>) {
    if beta == 0.0 || m.samples.is_empty() {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let mut held: Vec<(u32, u32)> =
        m.feet.iter().zip(weights).filter(|&(_, &w)| w > 0.0).map(|(f, _)| (f.param.face, f.param.corner)).collect();
    held.sort_unstable();
    held.dedup();
    let kept: Vec<&(Projection, DVec3)> = m
        .samples
        .iter()
        .filter(|(s, _)| s.distance.is_finite() && held.binary_search(&(s.param.face, s.param.corner)).is_ok())
        .collect();
    let w = beta * data as f64 / kept.len().max(1) as f64;
    (kept.iter().map(|s| s.0).collect(), vec![w; kept.len()], kept.iter().map(|s| s.1).collect())
}

/// `a + b` (the same pattern, entries of `b` missing in `a` inserted).
fn add_systems(mut a: System, b: System) -> System {
    for (row, (cols, blocks)) in b.rows.iter().zip(&b.blocks).enumerate() {
        for (&c, block) in cols.iter().zip(blocks) {
            let pos = match a.rows[row].binary_search(&c) {
                Ok(p) => p,
                Err(p) => {
                    a.rows[row].insert(p, c);
                    a.blocks[row].insert(p, [0.0; 9]);
                    p
                }
            };
            for (x, y) in a.blocks[row][pos].iter_mut().zip(block) {
                *x += y;
            }
        }
        a.rhs[row] += b.rhs[row];
    }
    a
}

/// s‖L P‖² + κ Σ_{i∈U} ‖(L P)ᵢ‖².
fn penalties(laplacian: &CsMatI<f64, u32>, p: &[DVec3], s: f64, unsupported: &[u32], kappa: f64, relax: &Relax) -> f64 {
    let lp = |i: usize| -> DVec3 {
        let row = laplacian.outer_view(i).expect("row in range");
        row.iter().fold(DVec3::ZERO, |acc, (j, &w)| acc + w * p[j])
    };
    let relaxation = if relax.weight > 0.0 {
        relax.weight
            * (0..p.len())
                .filter_map(|i| {
                    let (v, nrm) = (lp(i), relax.normals[i]?);
                    Some((v - nrm.dot(v) * nrm).length_squared())
                })
                .sum::<f64>()
    } else {
        0.0
    };
    if s == 0.0 && unsupported.is_empty() {
        return relaxation;
    }
    let lp = |i: usize| -> DVec3 {
        let row = laplacian.outer_view(i).expect("row in range");
        row.iter().fold(DVec3::ZERO, |acc, (j, &w)| acc + w * p[j])
    };
    let mut total = 0.0;
    if s > 0.0 {
        total += s * (0..p.len()).map(|i| lp(i).length_squared()).sum::<f64>();
    }
    total + kappa * unsupported.iter().map(|&i| lp(i as usize).length_squared()).sum::<f64>() + relaxation
}

/// The tangential relaxation term of step 3: weight ρ·m/n and the unit
/// vertex normals nᵢ of the control mesh at the round's start; the penalty
/// is ρ·m/n·Σᵢ ‖(I − nᵢnᵢᵀ)(L P)ᵢ‖².
struct Relax {
    weight: f64,
    normals: Vec<Option<DVec3>>,
}

/// Unit vertex normals of a control mesh: the sum of its faces' (Newell)
/// normals; `None` on the boundary and at tagged vertices (the relaxation
/// leaves them: their umbrella vector is no tangential imbalance) and
/// where the sum vanishes.
fn vertex_normals(mesh: &Mesh) -> Vec<Option<DVec3>> {
    let p = mesh.positions();
    let t = mesh.topology();
    let mut out = vec![DVec3::ZERO; p.len()];
    for f in mesh.topology().faces().iter() {
        let mut nrm = DVec3::ZERO;
        for k in 0..f.len() {
            let (a, b) = (p[f[k] as usize], p[f[(k + 1) % f.len()] as usize]);
            nrm += a.cross(b);
        }
        for &v in f.iter() {
            out[v as usize] += nrm;
        }
    }
    let mut free: Vec<bool> =
        t.vertices().map(|v| !t.is_boundary_vertex(v) && mesh.tags().vertex_sharpness(v) == 0.0).collect();
    for e in t.edges() {
        if mesh.tags().edge_sharpness(e) > 0.0 {
            let (a, b) = t.edge_vertices(e);
            free[a.index()] = false;
            free[b.index()] = false;
        }
    }
    out.iter().zip(free).map(|(v, f)| v.try_normalize().filter(|_| f)).collect()
}

/// The umbrella Laplacian (L P)ᵢ = Pᵢ − mean of the neighbours of i, n × n.
fn umbrella(mesh: &Mesh) -> CsMatI<f64, u32> {
    let t = mesh.topology();
    let n = t.vertex_count();
    let mut tri = TriMatI::<f64, u32>::new((n, n));
    for v in t.vertices() {
        let nb: Vec<VertexId> = t.vertex_neighbors(v).collect();
        if nb.is_empty() {
            continue;
        }
        tri.add_triplet(v.index(), v.index(), 1.0);
        for w in &nb {
            tri.add_triplet(v.index(), w.index(), -1.0 / nb.len() as f64);
        }
    }
    tri.to_csr()
}

/// The block pattern of the normal equations: per control vertex, the
/// sorted vertices it couples with (face rings of the domains, where every
/// stencil lives, and the 2-rings of LᵀL).
struct Pattern {
    rows: Vec<Vec<u32>>,
}

impl Pattern {
    fn new(surface: &LimitSurface, mesh: &Mesh, laplacian: &CsMatI<f64, u32>) -> Self {
        let n = mesh.positions().len();
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); n];
        for f in 0..mesh.topology().face_count() {
            let Some(ring) = surface.face_domains(f as u32).first().and_then(|&d| surface.domain_support(d)) else {
                continue;
            };
            for &a in ring {
                rows[a as usize].extend_from_slice(ring);
            }
            // Deduplicate as we go (bounded memory).
            for &a in ring {
                let r = &mut rows[a as usize];
                if r.len() > 256 {
                    r.sort_unstable();
                    r.dedup();
                }
            }
        }
        let lt: CsMatI<f64, u32> = laplacian.transpose_view().to_csr();
        let ltl: CsMatI<f64, u32> = &lt * laplacian;
        for (a, row) in ltl.outer_iterator().enumerate() {
            rows[a].extend(row.indices().iter().copied());
            rows[a].push(a as u32);
        }
        rows.par_iter_mut().for_each(|r| {
            r.sort_unstable();
            r.dedup();
        });
        Self { rows }
    }
}

/// The assembled data term: H = Σ ωⱼ WⱼᵀMⱼWⱼ (3 × 3 blocks on the pattern,
/// row-major) and g = Σ ωⱼ WⱼᵀMⱼ(qⱼ − S(tⱼ)) (the negative gradient / 2).
struct System {
    blocks: Vec<Vec<[f64; 9]>>,
    rhs: Vec<DVec3>,
    /// Columns added to the pattern for stencils outside it (none expected).
    rows: Vec<Vec<u32>>,
}

/// Feet with the same stencil support, summed: per pair a ≤ b of the k
/// stencil vertices the moments Σ ω·wₐw_b·(nw·n nᵀ, pw) (the 6 entries of
/// the symmetric nnᵀ part and the isotropic part: every 3 × 3 block of
/// WᵀMW is symmetric), and the 3k right-hand side.
struct Group {
    indices: Vec<u32>,
    /// k × k (row-major, entries a ≤ b used) × 7.
    h: Vec<[f64; 7]>,
    g: Vec<DVec3>,
}

fn assemble(
    surface: &LimitSurface,
    pattern: &Pattern,
    feet: &[Projection],
    points: &[DVec3],
    weights: &[f64],
    [normal_weight, point_weight]: [f64; 2],
) -> Result<System, EvalError> {
    let n = pattern.rows.len();
    let mut order: Vec<u32> = (0..feet.len() as u32).filter(|&j| weights[j as usize] != 0.0).collect();
    order.sort_by_key(|&j| (feet[j as usize].param.face, feet[j as usize].param.corner));
    let mut rows = pattern.rows.clone();
    let mut blocks: Vec<Vec<[f64; 9]>> = rows.iter().map(|r| vec![[0.0; 9]; r.len()]).collect();
    let mut rhs = vec![DVec3::ZERO; n];
    // Batches of chunks: bounded memory; chunks fixed by CHUNK, so the sums
    // are the same on any number of threads.
    let chunks: Vec<&[u32]> = order.chunks(CHUNK).collect();
    for batch in chunks.chunks(64) {
        let groups: Vec<Vec<Group>> = batch
            .par_iter()
            .map(|chunk| {
                let mut out: Vec<Group> = Vec::new();
                for &j in *chunk {
                    let j = j as usize;
                    let w = weights[j];
                    let s = surface.stencil(feet[j].param)?;
                    if out.last().is_none_or(|g| g.indices != s.indices) {
                        let k = s.indices.len();
                        out.push(Group {
                            indices: s.indices.clone(),
                            h: vec![[0.0; 7]; k * k],
                            g: vec![DVec3::ZERO; k],
                        });
                    }
                    let group = out.last_mut().expect("pushed");
                    let k = s.indices.len();
                    let nrm = feet[j].normal;
                    let r = points[j] - feet[j].position;
                    let (nw, pw) = (w * normal_weight, w * point_weight);
                    // M = nw·nnᵀ + pw·I: its 6 distinct entries of nnᵀ, and pw.
                    let c = [
                        nw * nrm.x * nrm.x,
                        nw * nrm.x * nrm.y,
                        nw * nrm.x * nrm.z,
                        nw * nrm.y * nrm.y,
                        nw * nrm.y * nrm.z,
                        nw * nrm.z * nrm.z,
                        pw,
                    ];
                    let mr = nw * nrm.dot(r) * nrm + pw * r;
                    for (a, &wa) in s.position.iter().enumerate() {
                        group.g[a] += wa * mr;
                        let row = &mut group.h[a * k..(a + 1) * k];
                        for (b, &wb) in s.position.iter().enumerate().skip(a) {
                            let ww = wa * wb;
                            let m = &mut row[b];
                            for i in 0..7 {
                                m[i] += ww * c[i];
                            }
                        }
                    }
                }
                Ok(out)
            })
            .collect::<Result<_, EvalError>>()?;
        for group in groups.iter().flatten() {
            let k = group.indices.len();
            for (a, &va) in group.indices.iter().enumerate() {
                let va = va as usize;
                rhs[va] += group.g[a];
                // Merge the sorted stencil indices with the sorted row.
                let mut pos = 0;
                for (b, &vb) in group.indices.iter().enumerate() {
                    while pos < rows[va].len() && rows[va][pos] < vb {
                        pos += 1;
                    }
                    if pos == rows[va].len() || rows[va][pos] != vb {
                        rows[va].insert(pos, vb);
                        blocks[va].insert(pos, [0.0; 9]);
                    }
                    let m = if a <= b { group.h[a * k + b] } else { group.h[b * k + a] };
                    let block = &mut blocks[va][pos];
                    let full = [m[0] + m[6], m[1], m[2], m[1], m[3] + m[6], m[4], m[2], m[4], m[5] + m[6]];
                    for (x, y) in block.iter_mut().zip(full) {
                        *x += y;
                    }
                }
            }
        }
    }
    Ok(System { blocks, rhs, rows })
}

/// The solved step and what regularised it.
struct Step {
    delta: Vec<DVec3>,
    unsupported: Vec<u32>,
    kappa: f64,
    solver: &'static str,
    solver_iterations: usize,
}

/// Adds the smoothness, regularisation and damping terms and solves (module docs, step 3).
fn solve_step(
    system: &System,
    laplacian: &CsMatI<f64, u32>,
    positions: &[DVec3],
    smooth_weight: f64,
    damping: f64,
    cg_tolerance: f64,
    relax: &Relax,
) -> Result<Step, EvalError> {
    let n = positions.len();
    let mut rows = system.rows.clone();
    let mut blocks = system.blocks.clone();
    let mut rhs = system.rhs.clone();
    let diag_pos: Vec<usize> = (0..n)
        .map(|a| rows[a].binary_search(&(a as u32)).map_err(|_| EvalError::Internal("fit: no diagonal block".into())))
        .collect::<Result<_, _>>()?;
    let support: Vec<f64> =
        (0..n).map(|a| blocks[a][diag_pos[a]][0] + blocks[a][diag_pos[a]][4] + blocks[a][diag_pos[a]][8]).collect();
    let reference = {
        let nonzero: Vec<f64> = support.iter().copied().filter(|&s| s > 0.0).collect();
        let m = median(nonzero);
        if m > 0.0 {
            m
        } else {
            1.0
        }
    };
    let unsupported: Vec<u32> =
        (0..n as u32).filter(|&a| support[a as usize] < SUPPORT_THRESHOLD * reference).collect();
    let kappa = REGULARISATION * reference;
    // Regularisation and smoothness: R = s LᵀL + κ L_UᵀL_U (on every coordinate), RHS −R P.
    let mut r_tri = TriMatI::<f64, u32>::new((n, n));
    let add_row_products = |tri: &mut TriMatI<f64, u32>, i: usize, w: f64| {
        let row = laplacian.outer_view(i).expect("row in range");
        for (a, &la) in row.iter() {
            for (b, &lb) in row.iter() {
                tri.add_triplet(a, b, w * la * lb);
            }
        }
    };
    if smooth_weight > 0.0 {
        for i in 0..n {
            add_row_products(&mut r_tri, i, smooth_weight);
        }
    }
    for &i in &unsupported {
        add_row_products(&mut r_tri, i as usize, kappa);
    }
    let r: CsMatI<f64, u32> = r_tri.to_csr();
    for (a, row) in r.outer_iterator().enumerate() {
        for (b, &x) in row.iter() {
            let pos = match rows[a].binary_search(&(b as u32)) {
                Ok(p) => p,
                Err(p) => {
                    rows[a].insert(p, b as u32);
                    blocks[a].insert(p, [0.0; 9]);
                    p
                }
            };
            blocks[a][pos][0] += x;
            blocks[a][pos][4] += x;
            blocks[a][pos][8] += x;
            rhs[a] -= x * positions[b];
        }
    }
    // Tangential relaxation: ρ Σᵢ ‖Tᵢ(L P)ᵢ‖², Tᵢ = I − nᵢnᵢᵀ.
    if relax.weight > 0.0 {
        for i in 0..n {
            let Some(nrm) = relax.normals[i] else { continue };
            let t = [
                1.0 - nrm.x * nrm.x,
                -nrm.x * nrm.y,
                -nrm.x * nrm.z,
                -nrm.y * nrm.x,
                1.0 - nrm.y * nrm.y,
                -nrm.y * nrm.z,
                -nrm.z * nrm.x,
                -nrm.z * nrm.y,
                1.0 - nrm.z * nrm.z,
            ];
            let row = laplacian.outer_view(i).expect("row in range");
            let lp = row.iter().fold(DVec3::ZERO, |acc, (j, &w)| acc + w * positions[j]);
            let tlp = lp - nrm.dot(lp) * nrm;
            for (a, &la) in row.iter() {
                rhs[a] -= relax.weight * la * tlp;
                for (b, &lb) in row.iter() {
                    let pos = match rows[a].binary_search(&(b as u32)) {
                        Ok(p) => p,
                        Err(p) => {
                            rows[a].insert(p, b as u32);
                            blocks[a].insert(p, [0.0; 9]);
                            p
                        }
                    };
                    let x = relax.weight * la * lb;
                    for (e, te) in blocks[a][pos].iter_mut().zip(t) {
                        *e += x * te;
                    }
                }
            }
        }
    }
    // Damping μ·Dᵢ·I, Dᵢ = max(tr Hᵢᵢ/3, PIN·reference).
    for a in 0..n {
        let pos = rows[a].binary_search(&(a as u32)).map_err(|_| EvalError::Internal("fit: no diagonal".into()))?;
        let d = damping * (support[a] / 3.0).max(PIN * reference);
        blocks[a][pos][0] += d;
        blocks[a][pos][4] += d;
        blocks[a][pos][8] += d;
    }
    let direct = if 3 * n <= DIRECT_LIMIT { solve_ldl(&rows, &blocks, &rhs) } else { None };
    let (delta, solver, solver_iterations) = match direct {
        Some(x) => (x, "ldl", 0),
        None => {
            let (x, iterations) = solve_cg(&rows, &blocks, &rhs, cg_tolerance)?;
            (x, "cg", iterations)
        }
    };
    Ok(Step { delta, unsupported, kappa, solver, solver_iterations })
}

/// LDLᵀ of the 3n × 3n matrix; `None` when it fails (then CG).
fn solve_ldl(rows: &[Vec<u32>], blocks: &[Vec<[f64; 9]>], rhs: &[DVec3]) -> Option<Vec<DVec3>> {
    let n = rows.len();
    let mut indptr = Vec::with_capacity(3 * n + 1);
    let (mut indices, mut data) = (Vec::new(), Vec::new());
    indptr.push(0u32);
    for a in 0..n {
        for c in 0..3 {
            for (pos, &b) in rows[a].iter().enumerate() {
                for e in 0..3 {
                    indices.push(3 * b + e as u32);
                    data.push(blocks[a][pos][3 * c + e]);
                }
            }
            indptr.push(indices.len() as u32);
        }
    }
    let s = CsMatI::<f64, u32>::new((3 * n, 3 * n), indptr, indices, data);
    let matrix = FactoredMatrix::new(vec![1.0; 3 * n], s).ok()?;
    let factor = LdlFactor::new(&matrix).ok()?;
    if factor.negative_eigenvalues() != 0 || !factor.perturbed_pivots().is_empty() {
        return None;
    }
    let p: Vec<[f64; 3]> = rhs.iter().flat_map(|r| [[r.x, 0.0, 0.0], [r.y, 0.0, 0.0], [r.z, 0.0, 0.0]]).collect();
    let x = factor.solve(&p);
    let out: Vec<DVec3> = (0..n).map(|a| DVec3::new(x[3 * a][0], x[3 * a + 1][0], x[3 * a + 2][0])).collect();
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// y = A x over the blocks (rows in parallel, each row summed in order).
fn block_apply(rows: &[Vec<u32>], blocks: &[Vec<[f64; 9]>], x: &[DVec3], y: &mut [DVec3]) {
    y.par_iter_mut().enumerate().for_each(|(a, out)| {
        let mut acc = DVec3::ZERO;
        for (&b, m) in rows[a].iter().zip(&blocks[a]) {
            let v = x[b as usize];
            acc += DVec3::new(
                m[0] * v.x + m[1] * v.y + m[2] * v.z,
                m[3] * v.x + m[4] * v.y + m[5] * v.z,
                m[6] * v.x + m[7] * v.y + m[8] * v.z,
            );
        }
        *out = acc;
    });
}

/// Σ aᵢ·bᵢ in fixed chunks, summed in order (deterministic on any thread count).
fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    let partial: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(p, q)| p.dot(*q)).sum())
        .collect();
    partial.iter().sum()
}

/// Conjugate gradients with the inverse 3 × 3 diagonal blocks as preconditioner.
fn solve_cg(
    rows: &[Vec<u32>],
    blocks: &[Vec<[f64; 9]>],
    rhs: &[DVec3],
    tolerance: f64,
) -> Result<(Vec<DVec3>, usize), EvalError> {
    let n = rows.len();
    let inverse: Vec<glam::DMat3> = (0..n)
        .map(|a| {
            let pos = rows[a].binary_search(&(a as u32)).map_err(|_| EvalError::Internal("fit: no diagonal".into()))?;
            let m = blocks[a][pos];
            let mat = glam::DMat3::from_cols_array(&m).transpose();
            let inv = mat.inverse();
            if inv.is_finite() {
                Ok(inv)
            } else {
                Ok(glam::DMat3::from_diagonal(DVec3::new(1.0 / m[0], 1.0 / m[4], 1.0 / m[8])))
            }
        })
        .collect::<Result<_, EvalError>>()?;
    let precondition = |r: &[DVec3]| -> Vec<DVec3> { r.par_iter().zip(&inverse).map(|(v, m)| *m * *v).collect() };
    let mut x = vec![DVec3::ZERO; n];
    let mut r = rhs.to_vec();
    let norm_b = dot(rhs, rhs).sqrt();
    if norm_b == 0.0 {
        return Ok((x, 0));
    }
    let mut z = precondition(&r);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut ap = vec![DVec3::ZERO; n];
    let mut iterations = 0;
    for _ in 0..CG_MAX_ITERATIONS {
        iterations += 1;
        block_apply(rows, blocks, &p, &mut ap);
        let pap = dot(&p, &ap);
        if pap.is_nan() || pap <= 0.0 {
            break;
        }
        let alpha = rz / pap;
        x.par_iter_mut().zip(&p).for_each(|(xi, pi)| *xi += alpha * *pi);
        r.par_iter_mut().zip(&ap).for_each(|(ri, api)| *ri -= alpha * *api);
        if dot(&r, &r).sqrt() <= tolerance * norm_b {
            break;
        }
        z = precondition(&r);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        p.par_iter_mut().zip(&z).for_each(|(pi, zi)| *pi = *zi + beta * *pi);
    }
    if x.iter().all(|v| v.is_finite()) {
        Ok((x, iterations))
    } else {
        Err(EvalError::Solve { what: "the conjugate-gradient step is not finite".into() })
    }
}
