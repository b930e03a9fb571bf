//! Fitting a control mesh to dense data: move the control points of a coarse
//! mesh (topology and tags kept) so that its limit surface comes close to a
//! target (a triangle mesh or a point cloud).
//!
//! # References
//! Deng & Lin 2014, progressive-iterative approximation for least-squares
//! fitting (LSPIA) with foot-point re-projection each round; Marinov &
//! Kobbelt 2005 (optimisation methods for subdivision-surface fitting);
//! Wang, Pottmann & Liu 2006 (squared-distance minimisation: point-to-plane
//! and tangent-distance error terms). See docs/REFERENCES.md.
//!
//! # Algorithm
//! For rounds k = 0, 1, …:
//! 1. Project every target point qⱼ onto the current limit surface
//!    ([`crate::project`]): foot parameter tⱼ, normal nⱼ. Record the
//!    distances (target → surface) and those of samples of the surface to the
//!    target (surface → target: point-to-triangle through a BVH, or nearest
//!    cloud point) as [`FitIteration`] k.
//! 2. With the foot parameters fixed, the limit point at tⱼ is linear in the
//!    control points, S(tⱼ) = Wⱼ·P (the rows of [`LimitSurface::stencil`]).
//!    Minimise
//!    Σⱼ rⱼᵀ Mⱼ rⱼ + w·(m/n)·‖L P‖² + μ‖P − Pₖ‖², rⱼ = Wⱼ P − qⱼ,
//!    with Mⱼ = I (point-to-point, [`FitDistance::PointToPoint`]: the
//!    fixed point of LSPIA, reached in one direct solve) or
//!    Mⱼ = nⱼnⱼᵀ + λI (tangent distance, [`FitDistance::TangentDistance`]:
//!    the point-to-plane term lets the surface slide along itself, which is
//!    what makes point-to-point re-projection slow), L the umbrella
//!    Laplacian of the control mesh (weight w = [`FitOptions::smoothness`])
//!    and μ a tiny damping ([`DAMPING`] · mean diagonal) that keeps the
//!    system definite and vanishes at a fixed point. The 3n × 3n normal
//!    equations Σ (Wⱼᵀ ⊗ I₃) Mⱼ (Wⱼ ⊗ I₃) + … are assembled from six sparse
//!    products Wᵀ·diag(Mⱼ,cd)·W and solved by sparse LDLᵀ (subdiv-solve).
//! 3. A round is kept when it lowers the RMS target → surface distance.
//!    The tangential term λ anchors every foot to its current parameter and
//!    so brakes the sliding that the exact solution needs (with exact data,
//!    λ = 0.05 stalls near 1e-4·d, λ = 1e-7 reaches 1e-13·d in ten rounds)
//!    while it keeps the first rounds, far from the target, stable: λ starts
//!    at the given value, shrinks ×[`LAMBDA_DECREASE`] after every kept round
//!    (to [`LAMBDA_MIN`]) and grows ÷[`LAMBDA_DECREASE`] to retry a rejected
//!    one, at most [`MAX_RETRIES`] times in a row (Levenberg-Marquardt style;
//!    [`FitOptions::adaptive_lambda`]). With λ → 0 the round is the
//!    Gauss-Newton step of the joint problem in (P, t): eliminating the foot
//!    parameters from its normal equations leaves exactly the point-to-plane
//!    term nⱼnⱼᵀ.
//! 4. Stop after [`FitOptions::iterations`] kept rounds, or as soon as the RMS
//!    target → surface distance is at most [`FitOptions::tolerance`]·d, or
//!    when a kept round improves it by less than a relative [`STALL`], or
//!    when the retries are spent.
//!
//! # Deviations from the papers
//! LSPIA's fixed-step iteration is replaced by the direct solve of the
//! same least-squares problem each round (same fixed point, no step size to
//! pick); the default error term is the tangent distance, with the adaptive
//! λ of step 3 (ours).

use crate::bvh::TargetIndex;
use crate::project::{projector, ProjectOptions};
use crate::sample::sample_per_domain;
use crate::surface::{EvalError, LimitSurface};
use glam::DVec3;
use rayon::prelude::*;
use sprs::{CsMatI, TriMatI};
use subdiv_mesh::{Aabb, Mesh, VertexId};
use subdiv_solve::{FactoredMatrix, SolveOptions};
use subdiv_stencil::Options;

/// μ of the damping term, relative to the mean diagonal of the data term.
pub const DAMPING: f64 = 1e-9;
/// A round that improves the RMS distance by less than this fraction stops the fit.
pub const STALL: f64 = 1e-4;
/// [`FitOptions::adaptive_lambda`]: λ is multiplied by this after an accepted round
/// (and divided by it before a retry of a rejected one).
pub const LAMBDA_DECREASE: f64 = 0.1;
/// The smallest λ the adaptive schedule reaches.
pub const LAMBDA_MIN: f64 = 1e-8;
/// Rejected rounds retried with a larger λ before the fit stops.
pub const MAX_RETRIES: usize = 3;

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

/// The error term of the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FitDistance {
    /// ‖S(tⱼ) − qⱼ‖².
    PointToPoint,
    /// (nⱼ·(S(tⱼ) − qⱼ))² + λ‖S(tⱼ) − qⱼ‖².
    TangentDistance {
        /// λ > 0: the weight of the tangential part.
        lambda: f64,
    },
}

/// Options of [`fit`].
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The surface (scheme, boundary, creases).
    pub surface: Options,
    /// Rounds at most. Default 30.
    pub iterations: usize,
    /// Weight w of the umbrella-Laplacian smoothness term. Default 0.
    pub smoothness: f64,
    /// Stop when the RMS target → surface distance is at most this times d. Default 0 (never).
    pub tolerance: f64,
    /// The error term. Default tangent distance, λ = 0.05 at the start.
    pub distance: FitDistance,
    /// Tangent distance: λ shrinks ×[`LAMBDA_DECREASE`] after every accepted
    /// round down to [`LAMBDA_MIN`] and grows again for a rejected one
    /// (module docs, step 3). Default true.
    pub adaptive_lambda: bool,
    /// Surface samples per domain side for the surface → target distance. Default 4.
    pub samples_per_domain: usize,
    /// Projection tuning.
    pub project: ProjectOptions,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            surface: Options::default(),
            iterations: 30,
            smoothness: 0.0,
            tolerance: 0.0,
            distance: FitDistance::TangentDistance { lambda: 0.05 },
            adaptive_lambda: true,
            samples_per_domain: 4,
            project: ProjectOptions::default(),
        }
    }
}

/// Distances at one round, absolute and relative to d (the target's bbox diagonal).
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
}

/// The fitted mesh and the distances round by round.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The control mesh with fitted positions (topology and tags of the input).
    pub mesh: Mesh,
    /// Distances at the start and after every round.
    pub iterations: Vec<FitIteration>,
}

/// Distances of the target to the surface of `mesh` and back, with the feet.
struct Measured {
    stats: FitIteration,
    feet: Vec<crate::project::Projection>,
}

fn measure(
    surface: &LimitSurface,
    mesh: &Mesh,
    target: &FitTarget,
    index: &TargetIndex,
    options: &FitOptions,
    iteration: usize,
    scale: f64,
) -> Result<Measured, EvalError> {
    let projector = projector(surface, mesh, &options.surface, &options.project)?;
    let feet = projector.project_all(&target.points)?;
    let (rms_a, max_a) = rms_max(feet.iter().map(|f| f.distance));
    let samples = sample_per_domain(projector.evaluator(), options.samples_per_domain.max(1))?;
    let back: Vec<f64> =
        samples.par_iter().map(|s| index.nearest(s.position).map_or(f64::INFINITY, |(_, d)| d)).collect();
    let (rms_b, max_b) = rms_max(back.into_iter());
    let stats = FitIteration {
        iteration,
        rms_target_to_surface: rms_a,
        max_target_to_surface: max_a,
        rms_surface_to_target: rms_b,
        max_surface_to_target: max_b,
        scale,
    };
    Ok(Measured { stats, feet })
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

/// Fits `control`'s limit surface to `target` (module docs).
///
/// # Errors
/// [`EvalError::InvalidInput`] for an empty or non-finite target or bad
/// options; [`EvalError::Solve`] when a least-squares system cannot be
/// solved; what building, evaluating and projecting the surface returns.
pub fn fit(target: &FitTarget, control: &Mesh, options: &FitOptions) -> Result<FitResult, EvalError> {
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
    if !(options.smoothness >= 0.0 && options.smoothness.is_finite()) {
        return Err(EvalError::InvalidInput { what: format!("fit: smoothness {} is not ≥ 0", options.smoothness) });
    }
    if let FitDistance::TangentDistance { lambda } = options.distance {
        if !(lambda > 0.0 && lambda.is_finite()) {
            return Err(EvalError::InvalidInput { what: format!("fit: tangent-distance λ {lambda} is not > 0") });
        }
    }
    let scale = Aabb::of(target.points.iter().copied()).map_or(0.0, |b| b.diagonal());
    let surface = LimitSurface::new(control, &options.surface)?;
    let index = TargetIndex::new(target.points.clone(), target.triangles.clone());
    let laplacian = (options.smoothness > 0.0).then(|| umbrella(control));
    let mut mesh = control.clone();
    let mut iterations = Vec::new();
    let mut measured = measure(&surface, &mesh, target, &index, options, 0, scale)?;
    iterations.push(measured.stats);
    let mut lambda = match options.distance {
        FitDistance::TangentDistance { lambda } => Some(lambda),
        FitDistance::PointToPoint => None,
    };
    let (mut k, mut retries) = (1, 0);
    while k <= options.iterations && measured.stats.rms_target_to_surface > options.tolerance * scale {
        let distance = lambda.map_or(FitDistance::PointToPoint, |lambda| FitDistance::TangentDistance { lambda });
        let positions = solve_round(&surface, &mesh, target, &measured.feet, distance, options, laplacian.as_ref())?;
        let candidate = mesh.with_positions(positions);
        let next = measure(&surface, &candidate, target, &index, options, k, scale)?;
        let (old, new) = (measured.stats.rms_target_to_surface, next.stats.rms_target_to_surface);
        if new < old * (1.0 - STALL) {
            mesh = candidate;
            iterations.push(next.stats);
            measured = next;
            k += 1;
            retries = 0;
            if options.adaptive_lambda {
                lambda = lambda.map(|l| (l * LAMBDA_DECREASE).max(LAMBDA_MIN));
            }
            continue;
        }
        if new < old {
            // Accepted, but too small a gain to go on.
            mesh = candidate;
            iterations.push(next.stats);
            break;
        }
        // Rejected: more of the point-to-point term (Levenberg-Marquardt style), or stop.
        match lambda {
            Some(l) if options.adaptive_lambda && retries < MAX_RETRIES => {
                lambda = Some(l / LAMBDA_DECREASE);
                retries += 1;
            }
            _ => break,
        }
    }
    Ok(FitResult { mesh, iterations })
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

/// One least-squares solve with the feet fixed (module docs, step 2).
fn solve_round(
    surface: &LimitSurface,
    mesh: &Mesh,
    target: &FitTarget,
    feet: &[crate::project::Projection],
    distance: FitDistance,
    options: &FitOptions,
    laplacian: Option<&CsMatI<f64, u32>>,
) -> Result<Vec<DVec3>, EvalError> {
    let n = mesh.positions().len();
    let m = feet.len();
    // W: m × n, one stencil row per foot.
    let rows: Vec<(Vec<u32>, Vec<f64>)> = feet
        .par_iter()
        .map(|f| {
            let s = surface.stencil(f.param)?;
            let mut row: Vec<(u32, f64)> = s.indices.iter().copied().zip(s.position.iter().copied()).collect();
            row.sort_unstable_by_key(|e| e.0);
            Ok(row.into_iter().unzip())
        })
        .collect::<Result<_, EvalError>>()?;
    let mut indptr = Vec::with_capacity(m + 1);
    indptr.push(0u32);
    let (mut indices, mut data) = (Vec::new(), Vec::new());
    for (i, w) in &rows {
        indices.extend_from_slice(i);
        data.extend_from_slice(w);
        indptr.push(indices.len() as u32);
    }
    let w = CsMatI::<f64, u32>::new((m, n), indptr, indices, data);
    let wt: CsMatI<f64, u32> = w.transpose_view().to_csr();
    // Mⱼ entries (c, d), c ≤ d.
    let weight = |j: usize, c: usize, d: usize| -> f64 {
        let delta = if c == d { 1.0 } else { 0.0 };
        match distance {
            FitDistance::PointToPoint => delta,
            FitDistance::TangentDistance { lambda } => {
                let nj = feet[j].normal.to_array();
                nj[c] * nj[d] + lambda * delta
            }
        }
    };
    let q: Vec<[f64; 3]> = target.points.iter().map(|p| p.to_array()).collect();
    let mut tri = TriMatI::<f64, u32>::new((3 * n, 3 * n));
    let mut rhs = vec![0.0; 3 * n];
    let mut diagonal_sum = 0.0;
    for c in 0..3 {
        for d in c..3 {
            if matches!(distance, FitDistance::PointToPoint) && c != d {
                continue;
            }
            let mut scaled = w.data().to_vec();
            for j in 0..m {
                let s = weight(j, c, d);
                let range = w.indptr().outer_inds_sz(j);
                scaled[range].iter_mut().for_each(|x| *x *= s);
            }
            let wd = CsMatI::<f64, u32>::new((m, n), w.indptr().raw_storage().to_vec(), w.indices().to_vec(), scaled);
            let block: CsMatI<f64, u32> = &wt * &wd;
            for (a, row) in block.outer_iterator().enumerate() {
                for (b, &x) in row.iter() {
                    tri.add_triplet(3 * a + c, 3 * b + d, x);
                    if c != d {
                        tri.add_triplet(3 * a + d, 3 * b + c, x);
                    }
                    if a == b && c == d {
                        diagonal_sum += x;
                    }
                }
            }
            // rhs_c += Wᵀ diag(M_cd) q_d (and rhs_d += … q_c).
            for (j, row) in wd.outer_iterator().enumerate() {
                for (a, &x) in row.iter() {
                    rhs[3 * a + c] += x * q[j][d];
                    if c != d {
                        rhs[3 * a + d] += x * q[j][c];
                    }
                }
            }
        }
    }
    let mu = DAMPING * diagonal_sum / (3 * n).max(1) as f64;
    let current = mesh.positions();
    for a in 0..n {
        for c in 0..3 {
            tri.add_triplet(3 * a + c, 3 * a + c, mu);
            rhs[3 * a + c] += mu * current[a][c];
        }
    }
    if let (Some(l), true) = (laplacian, options.smoothness > 0.0) {
        let lt: CsMatI<f64, u32> = l.transpose_view().to_csr();
        let ltl: CsMatI<f64, u32> = &lt * l;
        let s = options.smoothness * m as f64 / n.max(1) as f64;
        for (a, row) in ltl.outer_iterator().enumerate() {
            for (b, &x) in row.iter() {
                for c in 0..3 {
                    tri.add_triplet(3 * a + c, 3 * b + c, s * x);
                }
            }
        }
    }
    let a: CsMatI<f64, u32> = tri.to_csr();
    let matrix = FactoredMatrix::new(vec![1.0; 3 * n], a).map_err(|e| EvalError::Solve { what: e.to_string() })?;
    let p: Vec<[f64; 3]> = rhs.iter().map(|&x| [x, 0.0, 0.0]).collect();
    let rhs_scale = rhs.iter().fold(0.0f64, |a, &x| a.max(x.abs())).max(f64::MIN_POSITIVE);
    let opts = SolveOptions::default().with_scale(rhs_scale).with_tol(1e-10);
    let solution = subdiv_solve::ldl(&matrix, &p, &opts).map_err(|e| EvalError::Solve { what: e.to_string() })?;
    Ok((0..n).map(|a| DVec3::new(solution.x[3 * a][0], solution.x[3 * a + 1][0], solution.x[3 * a + 2][0])).collect())
}
