//! Zheng & Cai 2005: Doo-Sabin interpolation that always works, by a few
//! sweeps of a diagonally dominant iteration and a local perturbation of the
//! first refined mesh (Zheng & Cai 2005, §3-§4, ZC05 in [references]).
//!
//! The output control mesh is the **perturbed first refined mesh M¹**; its
//! plain Doo-Sabin limit surface passes through every interpolated vertex I:
//! interior I is the centroid of its V-face in M¹ (a Doo-Sabin limit point at
//! every level, [how the error is measured]), boundary I the midpoint of its two Chaikin points
//! (the quadratic B-spline boundary's point). The error is round-off whatever
//! the iteration count, even with no iteration at all: the perturbation
//! (step 4) makes it exact, the iteration only keeps the perturbation small.
//!
//! # Algorithm (§3.4, with its equations)
//! 1. M⁰ = I, the input positions (step 1).
//! 2. Auxiliary mesh (step 2): sweep Eq. 7 over the interpolated vertices SI,
//!    in storage order (Gauss-Seidel, the paper's choice) or all at once
//!    (Jacobi, §3.2), at most ITE_MAX times; stop after the first sweep in
//!    which no vertex moved by more than EPS·d. Eq. 7 is row v of
//!    Z·M⁰ = I solved for V, where Z = Eq. 6 / 2m
//!    ([`crate::matrices::limit_matrix_zheng_cai`]); the other vertices stay
//!    at V_j = I_j (§2).
//! 3. First refined mesh (step 3): one step of Eq. 4, V'ᵢ = (Vᵢ + A)/2, with
//!    the Chaikin points on boundary edges
//!    ([`subdiv_stencil::doo_sabin::first_step`] with
//!    [`CornerRule::Uniform`]`(0.5)`; M¹'s connectivity, needed from step 4 on,
//!    is built beside steps 1-3 on the other core).
//! 4. Perturbation (step 4): for every interpolated interior vertex with
//!    V-face W₁…W_m, n = the Newell normal of the W's (Eq. 10) or the
//!    user's normal (§4.1), W_c = their mean, and
//!    ε_k = [(W_c − W_k)·n]n + (I − W_c) (Eq. 17, final line); W_c and n are
//!    read off v's face centroids (the V-face is λV + (1 − λ)× their polygon,
//!    step 3), which keeps memory access local. Afterwards the
//!    V-face is planar, ⟂ n, with centroid I: the limit surface passes
//!    through I with tangent plane ⟂ n. V-faces of distinct vertices share no
//!    vertex, so the order does not matter.
//! 5. Shape handles (§4.2, Brunet): W'_k = I + S_k(W_k − I), a homothety
//!    about the centroid, which keeps the centroid and the plane.
//! 6. Output M¹ with [`LimitAssociation::DualSites`]. In the
//!    [`SolveSummary`], `history` is the **max update / d of every sweep**
//!    (the paper's stopping quantity), `residual` the final
//!    max |I − Z·M⁰| / d over SI (what the perturbation had to correct), and
//!    `converged` says whether the EPS rule was met within ITE_MAX sweeps —
//!    the surface interpolates either way.
//!
//! # Deviations from the paper
//! - Eq. 17 is used in its final form with D ≡ I ([corrections Z1-Z3]: its second
//!   line has a sign error, D is never defined, and §3.4 prints V for I),
//!   rearranged as W_k + ε_k = I + P_n(W_k − W_c) (P_n the projection onto
//!   the plane ⟂ n) so that round-off stays relative to the face size.
//!   Eq. 10 is Newell's normal with cyclic indices ([correction Z5]); a V-face with
//!   zero vector area gets only the translation I − W_c (Eq. 9's solution).
//! - Stopping rule: the paper's (every update ≤ EPS·d, or ITE_MAX sweeps),
//!   coded here as a small sweep over the rows of Z, since the solve crate
//!   stops on the residual ([the stopping rule]). Reaching ITE_MAX is the paper's design,
//!   not an error. Any other solver of [`SolverChoice::Use`] (CG, LDLᵀ, …)
//!   is run on the restricted system Z·M⁰ = I with its own residual rule,
//!   tol = EPS and at most ITE_MAX iterations, keeping its last iterate; on
//!   open meshes the boundary block is solved before the interior (as in
//!   `system.rs`). `CommonOptions::max_iter` is not used and `tol` does not
//!   stop the iteration: EPS and ITE_MAX are this method's names for them;
//!   `tol` bounds the error measured at the end (the numeric rule, [`crate`]
//!   docs), which is round-off unless shape handles are extreme.
//! - Open meshes (beyond the paper, which treats closed meshes, §5):
//!   Z's boundary rows are the quadratic B-spline point (B₋ + 6V + B₊)/8,
//!   which is the midpoint of V's two Chaikin points in M¹; step 4 moves
//!   both Chaikin points by ε = I − midpoint (each Chaikin point belongs to
//!   one boundary vertex only). Prescribed normals at boundary vertices are
//!   refused ([`InterpError::InvalidParameter`]): the tangent plane there is
//!   not set by the V-face alone. Shape handles at boundary vertices scale
//!   the whole boundary V-face about I, which keeps the midpoint at I.
//! - Vertices not interpolated keep M⁰ = I and are not perturbed (the
//!   paper's choice); a shape handle at such a vertex scales its V-face about
//!   its own limit point, which therefore does not move. A prescribed normal
//!   at such a vertex is refused.
//! - Interior vertices of valence 2 (beyond the paper): their V-face would
//!   be a digon, which the Doo-Sabin refinement leaves out; their limit point
//!   is the centroid of the second-level E-face of the edge v₀v₁ between
//!   their two images, L = ⅜(v₀ + v₁) + 1/16·(a₀ + a₁ + b₀ + b₁) in M¹
//!   (`subdiv_rules::doo_sabin`, "Interior vertices of valence 2"), which is
//!   also their row of Z. Step 4 moves v₀ and v₁ by ε = (4/3)(I − L) (L moves
//!   by ¾ε), after the V-faces and the shape handles: v₀ and v₁ belong to no
//!   V-face, so the other
//!   vertices' limit points stay, except those of adjacent valence-2
//!   vertices (a₀ may be a neighbour's image), which are corrected together
//!   by a few Gauss-Seidel sweeps of this rule (each sweep contracts the
//!   coupling by ≥ 3) until the error is round-off. A prescribed normal at
//!   such a vertex is refused: its tangent plane is not the plane of a face
//!   that v₀ and v₁ can make planar (the second-level E-face's corners weigh
//!   v₀ and v₁ alike on both sides). A shape handle S scales v₀ and v₁ about
//!   their midpoint, which keeps L (v₀ + v₁ is unchanged).
//!   Isolated vertices lie on no surface: they are left out of SI with a
//!   warning.
//!
//! ```
//! use subdiv_interp::{zheng_cai, ZhengCaiOptions};
//! use subdiv_mesh::shapes;
//! // A genus-1 polygon mix: quads, triangles and 5- to 8-gons.
//! let mesh = shapes::polygon_mix(&shapes::torus(12, 8), 9, 0.2, 0.2, 0.1);
//! assert!(mesh.topology().face_ids().any(|f| mesh.topology().face_size(f) > 4));
//! let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
//! let all = vec![true; mesh.topology().vertex_count()];
//! let err = result.error(mesh.positions(), &all, mesh.bbox_diagonal());
//! assert!(err.max_rel <= 1e-12);
//! // The control mesh is the first refined mesh: one vertex per corner.
//! assert_eq!(result.control.topology().vertex_count(), mesh.topology().half_edge_count());
//! ```
//!
//! [corrections Z1-Z3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z1
//! [correction Z5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z5
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
//! [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use crate::first_step::CornerRule;
use crate::numeric::{max_nan, unit_direction};
use crate::{
    seconds_since, CommonOptions, InterpError, Interpolant, LimitAssociation, Method, Parameter, SolveSummary,
    SolverChoice,
};
use glam::DVec3;
use subdiv_mesh::refine::DualFace;
use subdiv_mesh::{newell_normal, Mesh, Topology, VertexId};
use subdiv_solve::{SolveError, SolveOptions, Solver, SweepOrder};
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{doo_sabin_limit_sites, limit_matrix_doo_sabin_sharp, DualLimitSite, LimitMatrix};

const METHOD: &str = "zheng-cai";

/// ITE_MAX of the paper's implementation (§3.4: "it is chosen to be 5").
pub const DEFAULT_ITE_MAX: usize = 5;
/// EPS of the paper's examples, relative to d (§3.5: "an iterative
/// termination threshold of 0.3%").
pub const DEFAULT_EPS: f64 = 0.003;

/// Options of [`interpolate`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ZhengCaiOptions {
    /// Subset and solver. `solver`: `Auto` (or `Use` of Gauss-Seidel in
    /// storage order) = Eq. 7 as the paper sweeps it; `Use(Solver::Jacobi)` =
    /// the Jacobi form of §3.2; any other solver runs on the Z system with
    /// its residual rule.
    /// `max_iter` is not used and `tol` only bounds the measured error of the
    /// result (the iteration stops by [`Self::eps`] and [`Self::ite_max`]).
    pub common: CommonOptions,
    /// ITE_MAX: the most sweeps of Eq. 7 (0 = the auxiliary mesh is the input).
    pub ite_max: usize,
    /// EPS relative to d: stop after a sweep whose largest update is ≤ EPS·d.
    pub eps: f64,
    /// Per input vertex, the normal the surface must have there (§4.1); it
    /// replaces Eq. 10's average normal. Only at interpolated interior
    /// vertices; the sign does not matter.
    pub normals: Option<Vec<Option<DVec3>>>,
    /// Per input vertex, Brunet's shape handle S_k > 0 (§4.2); 1 = none,
    /// < 1 sharper, > 1 flatter around the vertex.
    pub handles: Option<Vec<f64>>,
}

crate::options::common_setters!(ZhengCaiOptions);

impl ZhengCaiOptions {
    /// Sets ITE_MAX, the most sweeps of Eq. 7.
    pub fn with_ite_max(mut self, ite_max: usize) -> Self {
        self.ite_max = ite_max;
        self
    }

    /// Sets EPS (relative to d).
    pub fn with_eps(mut self, eps: f64) -> Self {
        self.eps = eps;
        self
    }

    /// Sets the prescribed normals (one entry per input vertex; `None`: Eq. 10 everywhere).
    pub fn with_normals(mut self, normals: impl Into<Option<Vec<Option<DVec3>>>>) -> Self {
        self.normals = normals.into();
        self
    }

    /// Sets Brunet's shape handles (one per input vertex; `None`: none).
    pub fn with_handles(mut self, handles: impl Into<Option<Vec<f64>>>) -> Self {
        self.handles = handles.into();
        self
    }
}

impl Default for ZhengCaiOptions {
    fn default() -> Self {
        Self {
            common: CommonOptions::default(),
            ite_max: DEFAULT_ITE_MAX,
            eps: DEFAULT_EPS,
            normals: None,
            handles: None,
        }
    }
}

/// The auxiliary mesh M⁰ of steps 1-2 and how the iteration went.
#[derive(Clone, Debug)]
pub struct AuxiliaryMesh {
    /// M⁰: the input topology with the iterated positions.
    pub mesh: Mesh,
    /// Sweeps, the EPS verdict, max update / d per sweep (`history`) and the
    /// final max |I − Z·M⁰| / d over the interpolated vertices (`residual`).
    pub summary: SolveSummary,
    /// Per input vertex: interpolated (in SI)?
    pub interpolated: Vec<bool>,
    /// Things the user should know (isolated vertices left out).
    pub warnings: Vec<String>,
}

/// How M⁰ is iterated.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Iteration {
    /// Eq. 7 with the paper's update rule: in storage order, or Jacobi.
    Paper { jacobi: bool },
    /// A solver of the solve crate, with its residual rule.
    Other(Solver),
}

impl Iteration {
    fn of(choice: SolverChoice) -> Self {
        match choice {
            SolverChoice::Auto | SolverChoice::Use(Solver::GaussSeidel(SweepOrder::Storage)) => {
                Iteration::Paper { jacobi: false }
            }
            SolverChoice::Use(Solver::Jacobi) => Iteration::Paper { jacobi: true },
            SolverChoice::Use(s) => Iteration::Other(s),
        }
    }
    fn name(self) -> &'static str {
        match self {
            Iteration::Paper { jacobi: false } => Solver::GaussSeidel(SweepOrder::Storage).name(),
            Iteration::Paper { jacobi: true } => Solver::Jacobi.name(),
            Iteration::Other(s) => s.name(),
        }
    }
    /// What `SolveSummary::history` holds.
    fn history_quantity(self) -> &'static str {
        match self {
            Iteration::Paper { .. } => "max update / d per sweep",
            Iteration::Other(_) => "max residual |I - Z M0| / d per iteration",
        }
    }
}

/// Steps 1-2: the auxiliary mesh M⁰ (input topology) whose Eq. 4 step has
/// V-face centroids close to the data. Computed on the data scaled by a
/// power of two and mapped back, as every method ([`crate`] docs, "The
/// numeric rule"); isolated vertices are left out of SI with a warning.
///
/// # Errors
/// [`InterpError::InvalidParameter`] for a bad subset or EPS;
/// [`InterpError::CoincidentVertices`] and [`InterpError::NotRepresentable`]
/// for data without a finite, non-zero d; [`InterpError::Solve`] when a
/// solver other than the paper's fails for a reason other than its
/// iteration cap.
pub fn auxiliary_mesh(mesh: &Mesh, opts: &ZhengCaiOptions) -> Result<AuxiliaryMesh, InterpError> {
    check_eps(opts)?;
    let prepared = crate::numeric::prepare(Method::ZhengCai, mesh, Some(&opts.common))?;
    let z = limit_matrix_doo_sabin_sharp(mesh.topology(), &CornerRule::Uniform(EQ4_LAMBDA), mesh.tags())?;
    let mut aux = auxiliary_from(&prepared.mesh, opts, &z, prepared.interpolated.clone())?;
    prepared.map_back("the auxiliary mesh", aux.mesh.positions_mut())?;
    aux.warnings = prepared.warnings;
    Ok(aux)
}

/// EPS must be finite and ≥ 0.
fn check_eps(opts: &ZhengCaiOptions) -> Result<(), InterpError> {
    if opts.eps.is_finite() && opts.eps >= 0.0 {
        Ok(())
    } else {
        Err(InterpError::invalid(Parameter::Eps, format!("EPS = {} must be finite and ≥ 0", opts.eps)))
    }
}

fn auxiliary_from(
    mesh: &Mesh,
    opts: &ZhengCaiOptions,
    z: &LimitMatrix,
    interpolated: Vec<bool>,
) -> Result<AuxiliaryMesh, InterpError> {
    let d = mesh.bbox_diagonal();
    let iteration = Iteration::of(opts.common.solver);
    let (positions, summary) = match iteration {
        Iteration::Paper { jacobi } => paper_sweeps(z, mesh.positions(), &interpolated, jacobi, opts, d),
        Iteration::Other(solver) => solver_iterations(solver, z, mesh.positions(), &interpolated, opts, d)?,
    };
    Ok(AuxiliaryMesh { mesh: mesh.with_positions(positions), summary, interpolated, warnings: Vec::new() })
}

/// λ of Eq. 4, V' = λV + (1 − λ)A with λ = ½.
const EQ4_LAMBDA: f64 = 0.5;

/// Step 2 as printed: sweeps of Eq. 7 over SI until no update exceeds
/// EPS·d or ITE_MAX sweeps are done. Returns M⁰ and the summary.
#[allow(non_snake_case)]
fn paper_sweeps(
    z: &LimitMatrix,
    I: &[DVec3],
    interpolated: &[bool],
    jacobi: bool,
    opts: &ZhengCaiOptions,
    d: f64,
) -> (Vec<DVec3>, SolveSummary) {
    // Z = D·S, Eq. (6) / 2m: row v is V's V-face centroid after Eq. (4).
    let (indptr, indices, values) = (z.s.indptr(), z.s.indices(), z.s.data());
    let indptr = indptr.raw_storage();
    let SI: Vec<usize> = (0..I.len()).filter(|&v| interpolated[v]).collect();
    let threshold = opts.eps * d;
    let mut V = I.to_vec(); // step 1: M⁰ = I
    let mut fresh = vec![DVec3::ZERO; if jacobi { SI.len() } else { 0 }]; // Jacobi: this sweep's values
    let mut summary = SolveSummary::default();
    for _ in 0..opts.ite_max {
        let mut max_update = 0.0_f64;
        for (k, &v) in SI.iter().enumerate() {
            let (mut diagonal, mut others) = (0.0, DVec3::ZERO);
            for q in indptr[v] as usize..indptr[v + 1] as usize {
                let j = indices[q] as usize;
                if j == v {
                    diagonal = values[q];
                } else {
                    others += values[q] * V[j];
                }
            }
            // Eq. (7): V = 2mC·I − C Σ (1/mᵢ + 1/mᵢ₋₁) Eᵢ − C Σ (1/mᵢ) Σⱼ Vⱼⁱ, with
            // 1/z_vv = 2mC; on the boundary V = (8I − B₋ − B₊)/6.
            let updated = (I[v] - z.d[v] * others) / (z.d[v] * diagonal);
            max_update = max_nan(max_update, updated.distance(V[v]));
            if jacobi {
                fresh[k] = updated;
            } else {
                V[v] = updated; // Gauss-Seidel: used at once (§3.2)
            }
        }
        if jacobi {
            SI.iter().zip(&fresh).for_each(|(&v, &x)| V[v] = x);
        }
        summary.iterations += 1;
        summary.matvecs += 1;
        summary.history.push(max_update / d);
        if max_update <= threshold {
            summary.converged = true; // step 2: PASS == TRUE
            break;
        }
    }
    let ZV = z.apply(&V);
    summary.matvecs += 1;
    summary.residual = SI.iter().map(|&v| I[v].distance(ZV[v])).fold(0.0, max_nan) / d;
    summary.solver = if jacobi { Solver::Jacobi } else { Solver::GaussSeidel(SweepOrder::Storage) }.name().into();
    (V, summary)
}

/// Another solver on Z·M⁰ = I restricted to SI (boundary block first on open
/// meshes), tol = EPS, at most ITE_MAX iterations, keeping the last iterate.
#[allow(non_snake_case)]
fn solver_iterations(
    solver: Solver,
    z: &LimitMatrix,
    I: &[DVec3],
    interpolated: &[bool],
    opts: &ZhengCaiOptions,
    d: f64,
) -> Result<(Vec<DVec3>, SolveSummary), InterpError> {
    let n = z.size();
    let mut V = I.to_vec();
    let mut summary = SolveSummary { solver: solver.name().into(), converged: true, ..SolveSummary::default() };
    for unknowns in crate::system::stages(z, interpolated).iter().filter(|u| !u.is_empty()) {
        if opts.ite_max == 0 {
            summary.converged = false;
            break;
        }
        let (sub, rhs) = crate::system::restrict(z, unknowns, &V, I);
        let solve_opts = SolveOptions::default()
            .with_tol(opts.eps)
            .with_scale(d)
            .with_max_iter(opts.ite_max)
            .with_history(true)
            .with_observer(opts.common.observer.clone())
            .with_initial(Some(unknowns.iter().map(|&v| I[v].to_array()).collect()));
        let (x, iterations, matvecs, history) = match solver.solve(&sub, &rhs, &solve_opts) {
            Ok(sol) => (sol.x, sol.iterations, sol.matvecs, sol.history),
            // ITE_MAX is the paper's budget, not a failure: keep the last iterate.
            Err(SolveError::NotConverged { x, iterations, history, .. }) => {
                summary.converged = false;
                (x.0, iterations, iterations, history)
            }
            Err(source) => return Err(InterpError::Solve { method: METHOD, source: Box::new(source) }),
        };
        for (k, &v) in unknowns.iter().enumerate() {
            V[v] = DVec3::from_array(x[k]);
        }
        summary.iterations += iterations;
        summary.matvecs += matvecs;
        summary.history.extend(history);
    }
    let ZV = z.apply(&V);
    summary.residual = (0..n).filter(|&v| interpolated[v]).map(|v| I[v].distance(ZV[v])).fold(0.0, max_nan) / d;
    Ok((V, summary))
}

/// Checks normals and handles against the mesh and the subset.
fn validate(
    t: &Topology,
    opts: &ZhengCaiOptions,
    interpolated: &[bool],
    sites: &[DualLimitSite],
) -> Result<(), InterpError> {
    let nv = t.vertex_count();
    let bad = |parameter, msg: String| Err(InterpError::invalid(parameter, msg));
    if let Some(normals) = &opts.normals {
        let bad = |msg| bad(Parameter::Normals, msg);
        if normals.len() != nv {
            return bad(format!("{} normals for {nv} vertices", normals.len()));
        }
        for (v, n) in normals.iter().enumerate().filter_map(|(v, n)| n.map(|n| (v, n))) {
            if unit_direction(n).is_none() {
                return bad(format!("the normal of vertex {v} is zero or not finite: {n}"));
            }
            if !interpolated[v] {
                return bad(format!("vertex {v} has a normal but is not interpolated"));
            }
            match sites[v] {
                DualLimitSite::SharpMidpoint(..) if t.is_boundary_vertex(VertexId(v as u32)) => {
                    return bad(format!(
                        "vertex {v} is on the boundary: zheng-cai prescribes normals at interior vertices only"
                    ))
                }
                DualLimitSite::SharpMidpoint(..) => {
                    return bad(format!(
                        "vertex {v} is on a crease: its limit point lies on the sharp curve, where the surface has \
                         one tangent plane per side, so zheng-cai cannot prescribe one normal there (leave it out, or \
                         prescribe the normals of smooth vertices and darts next to it)"
                    ))
                }
                DualLimitSite::Corner(_) => {
                    return bad(format!(
                        "vertex {v} is a corner: the surface has no tangent plane there, so zheng-cai cannot \
                         prescribe its normal"
                    ))
                }
                _ => {}
            }
            if doo_sabin::valence_two_corners(t, VertexId(v as u32)).is_some() {
                return bad(format!(
                    "vertex {v} has valence 2: it has no V-face whose plane could carry the normal, so zheng-cai \
                     cannot prescribe its normal (leave it out of the normals)"
                ));
            }
        }
    }
    if let Some(handles) = &opts.handles {
        let bad = |msg| bad(Parameter::Handles, msg);
        if handles.len() != nv {
            return bad(format!("{} shape handles for {nv} vertices", handles.len()));
        }
        if let Some((v, s)) = handles.iter().enumerate().find(|(_, s)| !(s.is_finite() && **s > 0.0)) {
            return bad(format!("the shape handle of vertex {v} is {s}; it must be finite and > 0"));
        }
    }
    Ok(())
}

/// Interpolates the flagged vertices of `mesh` (default all) with a
/// Doo-Sabin limit surface of the perturbed first refined mesh M¹.
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule": extreme shape
/// handles fail the measured-error check); [`InterpError::InvalidParameter`]
/// for a bad subset, EPS, normal or handle (naming the vertex);
/// [`InterpError::Solve`] when a non-paper solver fails for a reason other
/// than its iteration cap.
pub fn interpolate(mesh: &Mesh, opts: &ZhengCaiOptions) -> Result<Interpolant, InterpError> {
    check_eps(opts)?;
    crate::numeric::run(Method::ZhengCai, mesh, Some(&opts.common), |mesh, interpolated| {
        interpolate_prepared(mesh, interpolated, opts)
    })
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set SI.
#[allow(non_snake_case)]
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    si: Vec<bool>,
    opts: &ZhengCaiOptions,
) -> Result<Interpolant, InterpError> {
    let t = mesh.topology();
    let tags = mesh.tags();
    // The connectivity of M¹ (with the creases and corners of the tags) is
    // needed only from step 4 on: it is built on one core while the other
    // builds Z and runs steps 1-3 (step 3 evaluated directly, without
    // building the Eq. (4) stencil).
    let start = std::time::Instant::now();
    let (refined, steps) = rayon::join(
        || (subdiv_mesh::refine::dual_split_tagged(t, tags), seconds_since(start)),
        || -> Result<_, InterpError> {
            let z = limit_matrix_doo_sabin_sharp(t, &CornerRule::Uniform(EQ4_LAMBDA), tags)?;
            let operators_seconds = seconds_since(start);
            let solve_start = std::time::Instant::now();
            // Steps 1-2, then step 3: M¹ = Eq. (4) step of M⁰.
            let aux = auxiliary_from(mesh, opts, &z, si.clone())?;
            let W = doo_sabin::first_step_tagged(t, tags, &CornerRule::Uniform(EQ4_LAMBDA), aux.mesh.positions())?;
            Ok((aux, W, operators_seconds, seconds_since(solve_start)))
        },
    );
    // Where each input vertex's limit point sits in M¹; the normals and
    // handles are checked against it (a normal at a crease or corner is refused).
    let ((t1, dual, tags1), topology_seconds) = refined;
    let sites = doo_sabin_limit_sites(t, tags, &dual)?;
    validate(t, opts, &si, &sites)?;
    let (aux, mut W, operators_seconds, steps_seconds) = steps?;
    // Setup: Z and M¹'s connectivity (side by side, so the longer of the two
    // branches); solve: steps 1-3 above and steps 4-5 below.
    let setup_seconds = operators_seconds.max(topology_seconds);
    let solve_start = std::time::Instant::now();
    let SI = &aux.interpolated;
    let mut warnings = Vec::new();
    let I = mesh.positions();
    // Step 4 at interior vertices needs each V-face's centroid W_c and normal.
    // Its corners are W_k = λV + (1 − λ)c_f over v's faces f (step 3), so
    // W_c = λV + (1 − λ)·mean(c_f), and the V-face is a scaled copy of the
    // polygon of v's face centroids c_f (fan order): same Newell normal
    // direction (Eq. 10). Reading the face centroids (one per face) instead
    // of the V-face corners (scattered over M¹) keeps memory access local;
    // the corners are then moved in storage order.
    let V = aux.mesh.positions();
    let centroids = aux.mesh.face_centroids();
    let mut frame: Vec<Option<(DVec3, DVec3)>> = vec![None; t.vertex_count()];
    let mut darts = Vec::new(); // (vertex, V-face) of darts: their V-face has a sharp point
    let corner_images = t.half_edge_count();
    let mut ring = Vec::new(); // v's face centroids in fan order
    for v in t.vertices().filter(|v| SI[v.index()]) {
        let i = v.index();
        match sites[i] {
            DualLimitSite::SharpMidpoint(a, b) => {
                // Boundaries and creases: the limit point is the midpoint of the two sharp
                // points (Chaikin's, or a clamped one next to a corner), which belong to v
                // alone; Eq. (9)'s minimal perturbation of that pair: both move by I − midpoint.
                let eps = I[i] - (W[a.index()] + W[b.index()]) / 2.0;
                W[a.index()] += eps;
                W[b.index()] += eps;
                continue;
            }
            // A corner keeps its point: it is the data.
            DualLimitSite::Corner(c) => {
                W[c.index()] = I[i];
                continue;
            }
            DualLimitSite::FaceCentroid(f) if t1.face(f).iter().any(|&k| k as usize >= corner_images) => {
                darts.push((i, f));
                continue;
            }
            DualLimitSite::FaceCentroid(_) => {}
            // Valence 2 (below) and isolated vertices have no V-face.
            DualLimitSite::ValenceTwoEdge(..) | DualLimitSite::Isolated => continue,
        }
        ring.clear();
        ring.extend(t.vertex_fan(v).iter().map(|&h| centroids[t.he_face(h).index()]));
        let W_c = EQ4_LAMBDA * V[i] + (1.0 - EQ4_LAMBDA) * (ring.iter().sum::<DVec3>() / ring.len() as f64);
        let given = opts.normals.as_ref().and_then(|n| n[i]);
        // §4.1: the required normal replaces Eq. (10)'s Newell normal (cyclic, correction Z5, docs/REFERENCES.md).
        // Normalised by a power of two first: a given normal of 1e-200 keeps its direction.
        let n = unit_direction(given.unwrap_or_else(|| newell_normal(ring.iter().copied()))).unwrap_or(DVec3::ZERO);
        frame[i] = Some((W_c, n));
    }
    // M¹ vertex k < H is corner k of M⁰, in the V-face of the corner's vertex.
    for (k, &v) in t.faces().indices().iter().enumerate() {
        if let Some((W_c, n)) = frame[v as usize] {
            let w = W[k] - W_c;
            // Eq. (17), final line with D ≡ I (corrections Z1-Z3, docs/REFERENCES.md):
            // W_k + ε_k = W_k + [(W_c − W_k)·n]n + (I − W_c) = I + (w − (w·n)n), w = W_k − W_c.
            W[k] = I[v as usize] + (w - w.dot(n) * n);
        }
    }
    // Darts: the same perturbation on the V-face itself (its corner images and
    // the crease's point next to the dart, which no other V-face has).
    for &(i, f) in &darts {
        let face = t1.face(f);
        let W_c = face.iter().map(|&k| W[k as usize]).sum::<DVec3>() / face.len() as f64;
        let given = opts.normals.as_ref().and_then(|n| n[i]);
        let n = unit_direction(given.unwrap_or_else(|| newell_normal(face.iter().map(|&k| W[k as usize]))))
            .unwrap_or(DVec3::ZERO);
        for &k in face {
            let w = W[k as usize] - W_c;
            W[k as usize] = I[i] + (w - w.dot(n) * n); // Eq. (17), as above
        }
    }
    let mut handles_applied = 0;
    if let Some(handles) = &opts.handles {
        // The V-faces of every vertex: one per sector (two on a crease).
        let mut v_faces: Vec<Vec<u32>> = vec![Vec::new(); t.vertex_count()];
        for (f, origin) in dual.face_origin.iter().enumerate() {
            if let DualFace::V(v) = origin {
                v_faces[v.index()].push(f as u32);
            }
        }
        let mut points = Vec::new();
        for v in t.vertices().filter(|v| handles[v.index()] != 1.0) {
            let i = v.index();
            if v_faces[i].is_empty() {
                if let Some(c) = doo_sabin::valence_two_corners(t, v) {
                    // Valence 2: scale the two images about their midpoint (keeps L).
                    let (a, b) = (c[0].0.index(), c[1].0.index());
                    let mid = (W[a] + W[b]) / 2.0;
                    W[a] = mid + handles[i] * (W[a] - mid);
                    W[b] = mid + handles[i] * (W[b] - mid);
                    handles_applied += 1;
                } else {
                    warnings.push(format!("vertex {v} has no V-face (isolated): its shape handle has no effect"));
                }
                continue;
            }
            // The homothety's centre: the vertex's limit point, I after step 4.
            let centre = if SI[i] { I[i] } else { sites[i].point(&t1, &W).expect("a vertex with a V-face") };
            // Every point of its V-faces once (two sectors share the crease's points).
            points.clear();
            v_faces[i].iter().for_each(|&f| points.extend_from_slice(t1.face(subdiv_mesh::FaceId(f))));
            points.sort_unstable();
            points.dedup();
            for &k in &points {
                W[k as usize] = centre + handles[i] * (W[k as usize] - centre); // §4.2: W' = D + S(W − D)
            }
            handles_applied += 1;
        }
    }
    // Valence 2: no V-face; move both images so that the second-level E-face
    // centroid of the edge between them is I. Last, because the images next
    // to them are corners of V-faces that step 4 and the handles move.
    let valence_two: Vec<(usize, [(subdiv_mesh::HalfEdgeId, f64); 6])> = t
        .vertices()
        .filter(|v| SI[v.index()])
        .filter_map(|v| doo_sabin::valence_two_corners(t, v).map(|c| (v.index(), c)))
        .collect();
    correct_valence_two(&valence_two, I, &mut W, mesh.bbox_diagonal());
    let solve_seconds = steps_seconds + seconds_since(solve_start);

    let iteration = Iteration::of(opts.common.solver);
    let normals_given = opts.normals.as_ref().map_or(0, |n| n.iter().flatten().count());
    let handles = opts.handles.as_ref().map(|h| {
        let range = crate::report::Range::of(h);
        crate::report::HandlesSummary { count: handles_applied, min: range.min, max: range.max }
    });
    let parameters = crate::Parameters {
        solver: Some(iteration.name().to_string()),
        ite_max: Some(opts.ite_max),
        eps: Some(opts.eps),
        history: Some(iteration.history_quantity().to_string()),
        normals: Some(normals_given),
        handles: Some(handles),
        ..Default::default()
    };
    let sharp = opts.common.surface.sharpness(tags);
    let uvs = crate::interpolant::carry_uvs(
        mesh,
        &sharp,
        &t1,
        subdiv_stencil::Scheme::DooSabin,
        opts.common.surface.fvar,
        &mut warnings,
    );
    let control = Mesh::from_topology(t1, W)
        .with_tags(tags1)
        .with_uvs(uvs)
        .expect("the refined channel has one value per corner of M¹");
    Ok(Interpolant {
        surface_options: opts.common.surface,
        method: Method::ZhengCai,
        control,
        scheme: subdiv_stencil::Scheme::DooSabin,
        interpolated: aux.interpolated,
        association: LimitAssociation::DualSites(sites),
        solve: Some(aux.summary),
        setup_seconds,
        solve_seconds,
        warnings,
        parameters,
        measured_error: None,
    })
}

/// Step 4 at interior valence-2 vertices: for each `(i, corners)`
/// ([`doo_sabin::valence_two_corners`] of input vertex i), L = Σ w·W[corner]
/// is the vertex's limit point; moving its own two images by ε moves L by
/// 2·⅜·ε = ¾ε, so ε = (4/3)(I − L) makes it exact. Adjacent valence-2
/// vertices see each other's images with weight 1/16 (two of them: a
/// correction ε changes a neighbour's L by ⅛ε = ⅙(I − L)), so Gauss-Seidel
/// sweeps contract the remaining error by at least 3 each; they run until it
/// is below 1e-15·d or stops decreasing.
#[allow(non_snake_case)]
fn correct_valence_two(
    vertices: &[(usize, [(subdiv_mesh::HalfEdgeId, f64); 6])],
    I: &[DVec3],
    W: &mut [DVec3],
    d: f64,
) {
    let limit =
        |W: &[DVec3], c: &[(subdiv_mesh::HalfEdgeId, f64); 6]| c.iter().map(|&(h, w)| w * W[h.index()]).sum::<DVec3>();
    let own = subdiv_rules::doo_sabin::VALENCE_TWO_LIMIT.own;
    let mut previous = f64::INFINITY;
    for _ in 0..64 {
        let mut worst = 0.0_f64;
        for (i, c) in vertices {
            let gap = I[*i] - limit(W, c);
            worst = max_nan(worst, gap.length());
            let eps = gap / (2.0 * own); // ε = (4/3)(I − L)
            W[c[0].0.index()] += eps;
            W[c[1].0.index()] += eps;
        }
        // Stop at round-off, when the error stops decreasing, or on NaN.
        if worst.is_nan() || worst <= 1e-15 * d || worst >= previous {
            break;
        }
        previous = worst;
    }
}
